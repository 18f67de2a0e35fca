//! Drawing: a pure function of the [`Ui`] and the [`Workbench`] (it only records pane
//! rectangles for the mouse).
//!
//! Layout, top to bottom: the joint tree | the avatar | the parameters; two sparklines
//! (trajectory and torque of the selected coordinate); the timeline; the status or command
//! line. At 80×24 the main row keeps 14 rows; below 60×16 only a notice is drawn.

use super::ui::{Focus, Ui, params_of};
use crate::dynamics::{Workspace, forward_kinematics};
use crate::report::superquadric::SuperquadricMesh;
use crate::session::Workbench;
use crate::session::command::Quantity;
use crate::session::engine::Analysis;
use crate::session::units::{self, Kind};
use crate::session::workbench::{angle_series, is_angular, torque_series};
use crate::spatial::SpatialTransform;
use ratatui::Frame;
use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::canvas::{Canvas, Line as CLine};
use ratatui::widgets::{Block, Borders, Clear, LineGauge, Paragraph, Sparkline, Wrap};

/// Smallest size drawn in full.
pub const MIN_SIZE: (u16, u16) = (60, 16);

impl Ui {
    fn fg(&self, c: Color) -> Style {
        if self.color {
            Style::default().fg(c)
        } else {
            Style::default()
        }
    }
    fn pane(&self, title: String, focus: Focus) -> Block<'static> {
        let b = Block::default().borders(Borders::ALL).title(title);
        if self.focus == focus {
            b.border_style(self.fg(Color::Yellow).add_modifier(Modifier::BOLD))
        } else {
            b
        }
    }
}

/// Draws everything.
pub fn draw(ui: &Ui, wb: &Workbench, f: &mut Frame) {
    let area = f.area();
    if area.width < MIN_SIZE.0 || area.height < MIN_SIZE.1 {
        let msg = format!(
            "articula needs at least {}×{} (now {}×{}); q quits",
            MIN_SIZE.0, MIN_SIZE.1, area.width, area.height
        );
        f.render_widget(Paragraph::new(msg).wrap(Wrap { trim: true }), area);
        return;
    }
    let [main, sparks, timeline, status] = Layout::vertical([
        Constraint::Min(8),
        Constraint::Length(6),
        Constraint::Length(1),
        Constraint::Length(1),
    ])
    .areas(area);
    let side = if area.width >= 100 { 26 } else { 20 };
    let [tree, view, params] = Layout::horizontal([
        Constraint::Length(side),
        Constraint::Min(20),
        Constraint::Length(side + 4),
    ])
    .areas(main);
    draw_tree(ui, wb, f, tree);
    draw_view(ui, wb, f, view);
    draw_params(ui, wb, f, params);
    draw_sparks(ui, wb, f, sparks);
    draw_timeline(ui, wb, f, timeline);
    draw_status(ui, wb, f, status);
    // an error too long for the status line: all of it, wrapped, above the status line
    if let Some(e) = &ui.error
        && ui.cmdline.is_none()
        && !ui.help
        && e.chars().count() + 7 > area.width as usize
    {
        draw_popup(
            ui,
            f,
            area,
            " Error (Esc closes) ",
            &format!("error: {e}"),
            Color::Red,
        );
    }
    if ui.help {
        let last = wb.last_message();
        let text = if last.is_empty() {
            HELP.to_string()
        } else {
            format!("Last message: {last}\n\n{HELP}")
        };
        draw_popup(ui, f, area, " Help ", &text, Color::Yellow);
    }
}

/// The screen as text (one line per row, trailing spaces trimmed) at `width × height`.
pub fn render_text(ui: &Ui, wb: &Workbench, width: u16, height: u16) -> String {
    let backend = ratatui::backend::TestBackend::new(width, height);
    let mut term = match ratatui::Terminal::new(backend) {
        Ok(t) => t,
        Err(e) => return format!("cannot draw: {e}"),
    };
    if let Err(e) = term.draw(|f| draw(ui, wb, f)) {
        return format!("cannot draw: {e}");
    }
    buffer_text(term.backend().buffer())
}

/// A buffer as text, trailing spaces trimmed.
pub fn buffer_text(buf: &Buffer) -> String {
    let mut out = String::new();
    for y in 0..buf.area.height {
        let mut line = String::new();
        for x in 0..buf.area.width {
            line.push_str(buf[(x, y)].symbol());
        }
        out.push_str(line.trim_end());
        out.push('\n');
    }
    out
}

fn draw_tree(ui: &Ui, wb: &Workbench, f: &mut Frame, area: Rect) {
    let block = ui.pane(" Joints ".into(), Focus::Tree);
    let inner = block.inner(area);
    ui.tree_area.set(inner);
    let tree = Ui::tree(wb);
    let cursor = Ui::tree_cursor(wb);
    let h = inner.height as usize;
    // keep the selected row visible
    let scroll = match cursor {
        Some(c) if c >= h => c + 1 - h,
        _ => 0,
    };
    ui.tree_scroll.set(scroll);
    let lines: Vec<Line> = tree
        .iter()
        .enumerate()
        .skip(scroll)
        .take(h)
        .map(|(i, (name, depth))| {
            let indent = " ".repeat((*depth).min(6));
            let text = format!("{indent}{name}");
            if Some(i) == cursor {
                Line::from(Span::styled(
                    text,
                    ui.fg(Color::Cyan).add_modifier(Modifier::REVERSED),
                ))
            } else {
                Line::from(text)
            }
        })
        .collect();
    let body = if lines.is_empty() {
        Paragraph::new("no take\n:load PATH")
    } else {
        Paragraph::new(lines)
    };
    f.render_widget(body.block(block), area);
}

/// World pose of every body at frame `k` (empty without frames).
fn body_poses(r: &Analysis, k: usize) -> Vec<SpatialTransform> {
    if r.q.rows() == 0 {
        return vec![];
    }
    let mut ws = Workspace::new(&r.model);
    forward_kinematics(&r.model, &mut ws, r.q.row(k.min(r.q.rows() - 1)));
    ws.o_x_i
}

fn draw_view(ui: &Ui, wb: &Workbench, f: &mut Frame, area: Rect) {
    let title = match wb.take() {
        Some(t) => format!(" {} ", t.name),
        None => " Avatar ".into(),
    };
    let block = ui.pane(title, Focus::View);
    let inner = block.inner(area);
    let Some(r) = wb.latest_results() else {
        let msg = if ui.running.is_some() {
            "computing…"
        } else {
            "no results yet (:run id)"
        };
        f.render_widget(Paragraph::new(msg).block(block), area);
        return;
    };
    let poses = body_poses(r, wb.frame);
    let pos: Vec<nalgebra::Vector3<f64>> = poses.iter().map(|x| x.trans).collect();
    if pos.is_empty() {
        f.render_widget(block, area);
        return;
    }
    // follow the root horizontally; project orthographically after yaw then pitch
    let up = -r.model.gravity.normalize();
    let up_axis = (0..3)
        .max_by(|&a, &b| up[a].abs().total_cmp(&up[b].abs()))
        .unwrap_or(1);
    let (h1, h2) = ((up_axis + 1) % 3, (up_axis + 2) % 3);
    // the centroid of the bodies (in the euler model body 1 is only the root's x slider)
    let root = pos.iter().skip(1).sum::<nalgebra::Vector3<f64>>() / (pos.len().max(2) - 1) as f64;
    let (sy, cy) = ui.yaw.sin_cos();
    let (sp, cp) = ui.pitch.sin_cos();
    let project = |p: &nalgebra::Vector3<f64>| -> (f64, f64) {
        let (a, b, u) = (p[h2] - root[h2], p[h1] - root[h1], p[up_axis]);
        let x = cy * a - sy * b;
        let depth = sy * a + cy * b;
        (x, u * cp - depth * sp)
    };
    // bounds: 2.2 m tall, width from the pane's aspect (braille dots are square-ish)
    let height_m = 2.3;
    let aspect = f64::from(inner.width.max(1)) / (2.0 * f64::from(inner.height.max(1)));
    let half_w = height_m * aspect / 2.0;
    // links with a shape: superquadric wireframes (Barr 1981) of 6 parallels × 8 meridians;
    // without shapes (robot models): segments from each body to its parent
    let with_shapes = r.model.shapes.iter().any(Option::is_some);
    let mut segments: Vec<((f64, f64), (f64, f64))> = vec![];
    for i in 1..pos.len() {
        if with_shapes {
            if let Some(sq) = &r.model.shapes[i] {
                let mesh = SuperquadricMesh::new(sq, 6, 8);
                segments.extend(
                    mesh.edges_in(&poses[i])
                        .map(|(a, b)| (project(&a), project(&b))),
                );
            }
        } else if r.model.parent[i] > 0 && (pos[i] - pos[r.model.parent[i]]).norm() > 1e-6 {
            segments.push((project(&pos[r.model.parent[i]]), project(&pos[i])));
        }
    }
    let selected_body = wb
        .selection
        .as_deref()
        .and_then(|s| r.model.body_index(s))
        .map(|b| project(&pos[b]));
    let color = if ui.color { Color::White } else { Color::Reset };
    let accent = if ui.color {
        Color::Yellow
    } else {
        Color::Reset
    };
    let ground = if ui.color {
        Color::DarkGray
    } else {
        Color::Reset
    };
    let canvas = Canvas::default()
        .block(block)
        .marker(Marker::Braille)
        .x_bounds([-half_w, half_w])
        .y_bounds([-0.2, height_m - 0.2])
        .paint(move |ctx| {
            ctx.draw(&CLine::new(-half_w, -0.05, half_w, -0.05, ground));
            for ((x1, y1), (x2, y2)) in &segments {
                ctx.draw(&CLine::new(*x1, *y1, *x2, *y2, color));
            }
            if let Some((x, y)) = selected_body {
                ctx.draw(&CLine::new(x - 0.04, y, x + 0.04, y, accent));
                ctx.draw(&CLine::new(x, y - 0.04, x, y + 0.04, accent));
            }
        });
    f.render_widget(canvas, area);
}

fn draw_params(ui: &Ui, wb: &Workbench, f: &mut Frame, area: Rect) {
    let block = ui.pane(" Parameters ".into(), Focus::Params);
    let w = block.inner(area).width as usize;
    let mut lines = vec![];
    for (i, param) in params_of(wb).iter().enumerate() {
        let Some((key, value)) = ui.param_row(wb, i) else {
            lines.push(Line::from("(select a joint)"));
            continue;
        };
        let label = match key.strip_prefix("link.") {
            Some(k) => k.trim_end_matches(".mass").to_string(),
            // `motor.j2.gear` → `j2 gear`
            None => match key.strip_prefix("motor.").and_then(|k| k.rsplit_once('.')) {
                Some((j, f)) => format!("{j} {f}"),
                None => key,
            },
        };
        let unit = match *param {
            "body.mass" | "link.<selected>.mass" => " kg",
            "blend.window" | "dt" => " s",
            "motor.<selected>.km" => " N·m/A",
            _ => "",
        };
        let v = format!("{value}{unit}");
        let pad = w
            .saturating_sub(label.chars().count() + v.chars().count())
            .max(1);
        let text = format!("{label}{}{v}", " ".repeat(pad));
        let style = if ui.focus == Focus::Params && ui.param_cursor == i {
            ui.fg(Color::Yellow).add_modifier(Modifier::REVERSED)
        } else {
            Style::default()
        };
        lines.push(Line::from(Span::styled(text, style)));
    }
    let p = &wb.params;
    // a robot: the current and the motor class the selected joint needs (report::motor)
    if let (Some(_), Some(r), Some(sel)) = (
        wb.take().and_then(|t| t.robot()),
        wb.latest_results(),
        wb.selection.as_deref(),
    ) && let Some(k) = r.tau.col_index(sel)
        && is_angular(&r.model, k)
    {
        let m = crate::report::motor::JointMotion {
            joint: sel.to_string(),
            t: r.time.clone(),
            tau: r.tau.column(k),
            qd: r.v.column(k),
        };
        if let Ok(l) = crate::report::motor::size_motor(&m, &p.motor_of(sel), &wb.motor_classes) {
            lines.push(Line::from(format!(
                "I peak {:.2} A rms {:.2} A",
                l.peak_current_a, l.rms_current_a
            )));
            lines.push(Line::from(format!(
                "→ {}",
                crate::report::motor::class_name(&l)
            )));
        }
    }
    lines.push(Line::from(match wb.take().and_then(|t| t.robot()) {
        Some(rb) => format!("robot ({})", rb.kind),
        None => format!("joints {:?} contact {:?}", p.take.joints, p.take.contact).to_lowercase(),
    }));
    if let Some(r) = wb.latest_results() {
        lines.push(Line::from(format!(
            "nv {}  {}{}",
            r.model.nv,
            units::format_value(Kind::Mass, r.model.total_mass()),
            if wb.fresh_results().is_none() {
                " (stale)"
            } else {
                ""
            }
        )));
    }
    f.render_widget(Paragraph::new(lines).block(block), area);
}

/// `min`, `max` over frames `0..=k` of `x`, and `x[k]`.
pub fn running_stats(x: &[f64], k: usize) -> Option<(f64, f64, f64)> {
    let seen = x.get(..=k.min(x.len().checked_sub(1)?))?;
    let min = seen.iter().copied().fold(f64::INFINITY, f64::min);
    let max = seen.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Some((min, max, *seen.last()?))
}

/// Sparkline bars: the take squeezed to `width` columns on the scale of the whole take;
/// columns after frame `k` are absent.
fn bars(x: &[f64], k: usize, width: usize) -> Vec<Option<u64>> {
    if x.is_empty() || width == 0 {
        return vec![];
    }
    let lo = x.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let span = (hi - lo).max(1e-12);
    (0..width)
        .map(|c| {
            let i = if width > 1 {
                c * (x.len() - 1) / (width - 1)
            } else {
                0
            };
            (i <= k).then(|| 1 + ((x[i] - lo) / span * 99.0).round() as u64)
        })
        .collect()
}

/// What a sparkline shows: quantity, series (SI), its kind, colour.
type SparkRow<'a> = (&'a str, Option<Vec<f64>>, Kind, Color);

fn draw_sparks(ui: &Ui, wb: &Workbench, f: &mut Frame, area: Rect) {
    let [a, b] = Layout::vertical([Constraint::Length(3), Constraint::Length(3)]).areas(area);
    let sel = wb.selection.clone();
    let r = wb.latest_results();
    // the angle of the selected coordinate (a rotation-vector component for ball joints) and
    // its torque
    let angle = r.zip(sel.as_deref()).and_then(|(r, s)| angle_series(r, s));
    let torque = r.zip(sel.as_deref()).and_then(|(r, s)| torque_series(r, s));
    let is_angle = match (r, sel.as_deref()) {
        (Some(r), Some(s)) => r.model.v_index(s).is_none_or(|k| is_angular(&r.model, k)),
        _ => true,
    };
    let rows: [SparkRow; 2] = [
        (
            if is_angle { "angle" } else { "position" },
            angle,
            Quantity::Angle.kind(is_angle),
            Color::Cyan,
        ),
        (
            if is_angle { "torque" } else { "force" },
            torque,
            Quantity::Torque.kind(is_angle),
            Color::Magenta,
        ),
    ];
    for ((what, x, kind, color), rect) in rows.into_iter().zip([a, b]) {
        let name = sel.as_deref().unwrap_or("no selection");
        let Some(x) = x else {
            let p = Paragraph::new(format!("{name} {what}: no results"));
            f.render_widget(p, rect);
            continue;
        };
        // the label in the coordinate's own unit, rounded by its kind; the bars in SI
        let unit = units::shown_unit(kind);
        let label = match running_stats(&x, wb.frame) {
            Some((min, max, now)) => {
                let n = |v| units::format_number(kind, v);
                format!(
                    "{name} {what} [{unit}]  min {}  max {}  now {}",
                    n(min),
                    n(max),
                    n(now)
                )
            }
            None => format!("{name} {what}"),
        };
        let [l, s] = Layout::vertical([Constraint::Length(1), Constraint::Length(2)]).areas(rect);
        f.render_widget(Paragraph::new(label).style(ui.fg(color)), l);
        let spark = Sparkline::default()
            .data(bars(&x, wb.frame, s.width as usize))
            .max(100)
            .style(ui.fg(color));
        f.render_widget(spark, s);
    }
}

fn draw_timeline(ui: &Ui, wb: &Workbench, f: &mut Frame, area: Rect) {
    let frames = wb.frames();
    let dt = wb.take().map_or(0.0, |t| t.frame_time());
    // times on the file's clock, as every output writes them (a dropped rest frame 0: from dt)
    let t0 = wb.take().and_then(|t| t.bvh()).map_or(0.0, |b| b.time(0));
    let state = if wb.playing { "▶" } else { "⏸" };
    let label = format!(
        "{state} {:.2}/{:.2} s  frame {}/{} ",
        t0 + wb.frame as f64 * dt,
        t0 + frames.saturating_sub(1) as f64 * dt,
        wb.frame,
        frames.saturating_sub(1)
    );
    let ratio = if frames > 1 {
        wb.frame as f64 / (frames - 1) as f64
    } else {
        0.0
    };
    let style = if ui.focus == Focus::Timeline {
        ui.fg(Color::Yellow).add_modifier(Modifier::BOLD)
    } else {
        ui.fg(Color::Green)
    };
    let gauge = LineGauge::default()
        .ratio(ratio.clamp(0.0, 1.0))
        .label(label)
        .filled_style(style);
    let label_w = 34.min(area.width);
    ui.timeline_area.set(Rect {
        x: area.x + label_w,
        width: area.width - label_w,
        ..area
    });
    f.render_widget(gauge, area);
}

fn draw_status(ui: &Ui, wb: &Workbench, f: &mut Frame, area: Rect) {
    let line = if let Some(cmd) = &ui.cmdline {
        let hint = if ui.completions.is_empty() {
            String::new()
        } else {
            format!("   [{}]", ui.completions.join(" "))
        };
        Line::from(vec![
            Span::raw(format!(":{cmd}█")),
            Span::styled(hint, ui.fg(Color::DarkGray)),
        ])
    } else if let Some(e) = &ui.error {
        Line::from(Span::styled(
            format!("error: {e}"),
            ui.fg(Color::Red).add_modifier(Modifier::BOLD),
        ))
    } else if let Some(r) = &ui.running {
        let waiting = match ui.queue.len() {
            0 => String::new(),
            n => format!(", {n} command(s) wait"),
        };
        Line::from(format!(
            "⟳ {} {:.0}%  (Esc cancels{waiting})",
            r.label,
            r.control.progress() * 100.0
        ))
    } else {
        let msg = wb.last_message();
        let first = msg.lines().next().unwrap_or("");
        Line::from(vec![
            Span::raw(first.to_string()),
            Span::styled(
                format!("   [{}]  ? help  : command  q quit", ui.focus.name()),
                ui.fg(Color::DarkGray),
            ),
        ])
    };
    f.render_widget(Paragraph::new(line), area);
}

/// The key reference shown by `?`.
pub const HELP: &str = "\
q quit   ? help (any key closes)   : command line (Tab completes, ↑/↓ history, Esc closes)
Tab / S-Tab   focus the next / previous pane (joints, avatar, parameters, timeline)
joints        ↑/↓ or k/j select a joint, ←/→ or h/l its coordinate, mouse click, wheel
avatar        ←/→ yaw, ↑/↓ pitch (also < and > anywhere), r resets the view
parameters    ↑/↓ choose, ←/→ or -/+ change (results recompute), Enter edits as :set
timeline      ←/→ one frame, ↑/↓ ten frames, click to jump
anywhere      Space play/pause, [ ] one frame, { } ten frames, g/G first/last frame
Esc           cancel the running job (⟳ in the status line) and what waits for it; clear an error
Commands are the session language: load, set, run, select, frame, export, expect, ...";

/// A box of wrapped `text` centred in `area` (the help), or low in it (an error), at most as
/// tall as the area.
fn draw_popup(ui: &Ui, f: &mut Frame, area: Rect, title: &str, text: &str, color: Color) {
    let w = area.width.saturating_sub(4).min(96);
    let inner = w.saturating_sub(2).max(1) as usize;
    // wrapped height: each line takes ⌈chars / inner width⌉ rows (at least one)
    let rows: usize = text
        .lines()
        .map(|l| l.chars().count().div_ceil(inner).max(1))
        .sum();
    let h = (rows as u16 + 2).min(area.height);
    let y = if color == Color::Red {
        area.y + area.height.saturating_sub(h + 1)
    } else {
        area.y + (area.height - h) / 2
    };
    let rect = Rect {
        x: area.x + (area.width - w) / 2,
        y,
        width: w,
        height: h,
    };
    f.render_widget(Clear, rect);
    let p = Paragraph::new(text.to_string())
        .wrap(Wrap { trim: false })
        .block(
            Block::default()
                .borders(Borders::ALL)
                .title(title.to_string())
                .border_style(ui.fg(color)),
        );
    f.render_widget(p, rect);
}
