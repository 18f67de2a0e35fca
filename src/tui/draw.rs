//! Drawing: a pure function of the [`Ui`] and the [`Workbench`] (it only records pane
//! rectangles for the mouse).
//!
//! Layout, top to bottom: the joint tree | the avatar | the parameters; the curves of the
//! selected coordinate (its angle and torque: sparklines, or line charts on a tall terminal,
//! see [`super::curves`]); with ground contact, the take's residual figures against Hicks et
//! al.'s thresholds (issue 14: the consistency is read where the moments are); the timeline;
//! the status or command line. At 80×24 the main row keeps 13 rows inside its borders (14
//! without contact); below 60×16 only a notice is drawn.

pub use super::curves::running_stats;
use super::curves::{curves_height, draw_curves};
use super::ui::{Focus, Ui, params_of};
use crate::dynamics::{Workspace, forward_kinematics};
use crate::pipeline::consistency::Consistency;
use crate::report::superquadric::SuperquadricMesh;
use crate::session::Workbench;
use crate::session::engine::Analysis;
use crate::session::units::{self, Kind};
use crate::session::workbench::coords_of_joint;
use crate::spatial::SpatialTransform;
use ratatui::Frame;
use ratatui::buffer::Buffer;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::symbols::Marker;
use ratatui::text::{Line, Span};
use ratatui::widgets::canvas::{Canvas, Line as CLine};
use ratatui::widgets::{Block, Borders, Clear, LineGauge, Paragraph, Wrap};

/// The glyph over the selected link in the avatar when colours are off.
pub const SELECTED_GLYPH: &str = "◆";
/// The timeline's played and unplayed parts.
pub const PLAYED: &str = "━";
pub const UNPLAYED: &str = "─";

/// Smallest size drawn in full.
pub const MIN_SIZE: (u16, u16) = (60, 16);

impl Ui {
    pub(super) fn fg(&self, c: Color) -> Style {
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
    ui.drawn.set((area.width, area.height));
    if area.width < MIN_SIZE.0 || area.height < MIN_SIZE.1 {
        let msg = format!(
            "articula needs at least {}×{} (now {}×{}); q quits",
            MIN_SIZE.0, MIN_SIZE.1, area.width, area.height
        );
        f.render_widget(Paragraph::new(msg).wrap(Wrap { trim: true }), area);
        return;
    }
    // under the curves, the take's consistency where its moments are read (issue 14), when
    // the results have one and the screen a row to spare
    let residuals = (area.height > MIN_SIZE.1)
        .then(|| wb.latest_results()?.consistency.clone())
        .flatten();
    let [main, sparks, resid, timeline, status] = Layout::vertical([
        Constraint::Min(8),
        Constraint::Length(curves_height(area.height)),
        Constraint::Length(u16::from(residuals.is_some())),
        Constraint::Length(1),
        Constraint::Length(1),
    ])
    .areas(area);
    let side = if area.width >= 100 { 26 } else { 20 };
    let [tree, view, params] = Layout::horizontal([
        Constraint::Length(tree_width(&Ui::tree(wb), side, area.width)),
        Constraint::Min(20),
        Constraint::Length(side + 4),
    ])
    .areas(main);
    draw_tree(ui, wb, f, tree);
    draw_view(ui, wb, f, view);
    draw_params(ui, wb, f, params);
    draw_curves(ui, wb, f, sparks);
    if let Some(c) = residuals {
        draw_residuals(ui, &c, f, resid);
    }
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
    let labels = tree_labels(&tree, inner.width as usize);
    let lines: Vec<Line> = labels
        .into_iter()
        .enumerate()
        .skip(scroll)
        .take(h)
        .map(|(i, text)| {
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

/// Indentation of a tree row at `depth` (one column a level, at most [`MAX_INDENT`]).
fn indent(depth: usize) -> usize {
    depth.min(MAX_INDENT)
}

/// The deepest indentation of the joint tree.
const MAX_INDENT: usize = 6;

/// The share of the screen's width the joint tree may take to show whole names.
const TREE_SHARE: f64 = 0.3;

/// The width of the joint tree's pane: its rows whole (after [`common_prefix`]) and its
/// borders, at least `min` columns and at most [`TREE_SHARE`] of `screen` columns (or `min`).
pub fn tree_width(tree: &[(String, usize)], min: u16, screen: u16) -> u16 {
    let cut = common_prefix(tree);
    let widest = tree
        .iter()
        .map(|(n, d)| indent(*d) + n[cut..].chars().count())
        .max()
        .unwrap_or(0);
    let most = ((f64::from(screen) * TREE_SHARE) as u16).max(min);
    (widest as u16 + 2).clamp(min, most)
}

/// Length (bytes) of the prefix every joint name shares and no row needs (`mixamorig:`,
/// `Bip01 `): the common start up to and including its last separator (`:`, `_`, `|`, `.`,
/// `-`, space), 0 when there is none or for a single joint.
pub fn common_prefix(tree: &[(String, usize)]) -> usize {
    let Some(((first, _), rest)) = tree.split_first() else {
        return 0;
    };
    if rest.is_empty() {
        return 0;
    }
    let mut len = first.len();
    for (n, _) in rest {
        len = first
            .char_indices()
            .zip(n.chars())
            .take_while(|((_, a), b)| a == b)
            .map(|((i, a), _)| i + a.len_utf8())
            .last()
            .unwrap_or(0)
            .min(len);
    }
    // cut after the last separator inside the common start, leaving every name a rest
    first[..len]
        .rfind([':', '_', '|', '.', '-', ' '])
        .map(|i| i + 1)
        .filter(|&cut| tree.iter().all(|(n, _)| n.len() > cut))
        .unwrap_or(0)
}

/// The text of each tree row in `width` columns: indentation by depth, the name without the
/// prefix all names share, elided in the middle (`Right…Index3`) when still too long, so that
/// both ends — side and finger, chain and number — stay readable.
pub fn tree_labels(tree: &[(String, usize)], width: usize) -> Vec<String> {
    let cut = common_prefix(tree);
    tree.iter()
        .map(|(name, depth)| {
            let pad = indent(*depth).min(width.saturating_sub(4));
            let room = width - pad;
            format!("{}{}", " ".repeat(pad), elide_middle(&name[cut..], room))
        })
        .collect()
}

/// `s` in at most `room` characters: whole, or its start and end around `…` (the end given
/// the larger half: it tells siblings apart).
pub fn elide_middle(s: &str, room: usize) -> String {
    let n = s.chars().count();
    if n <= room {
        return s.to_string();
    }
    if room <= 1 {
        return "…".chars().take(room).collect();
    }
    let keep = room - 1;
    let head = keep / 2;
    let tail = keep - head;
    let chars: Vec<char> = s.chars().collect();
    let mut out: String = chars[..head].iter().collect();
    out.push('…');
    out.extend(&chars[n - tail..]);
    out
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
    // with several takes: which one of how many, and the key to the next
    let title = match (wb.take(), wb.active) {
        (Some(t), Some(i)) if wb.takes.len() > 1 => {
            let which = format!(" [{}/{}, t: next] ", i + 1, wb.takes.len());
            let room = (area.width as usize).saturating_sub(which.chars().count() + 3);
            format!(" {}{which}", elide_middle(&t.name, room.max(4)))
        }
        (Some(t), _) => format!(" {} ", t.name),
        _ => " Avatar ".into(),
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
    // the body of the selected coordinate, or the first body of the selected joint (an
    // anatomical joint's: the knee's for `knee_l:flexion`)
    let selected_body = wb
        .selection
        .as_deref()
        .and_then(|s| r.model.body_index(s))
        .or_else(|| {
            let joint = wb.selected_joint()?;
            let coord = coords_of_joint(&r.model, &joint).into_iter().next()?;
            Some(r.model.body_of_v(r.model.v_index(&coord)?))
        })
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
    let color_on = ui.color;
    let marked = Style::default().add_modifier(Modifier::REVERSED | Modifier::BOLD);
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
                // without colours the cross is lost among the links: a glyph in reverse
                if !color_on {
                    ctx.print(x, y, Line::styled(SELECTED_GLYPH, marked));
                }
            }
        });
    f.render_widget(canvas, area);
}

fn draw_params(ui: &Ui, wb: &Workbench, f: &mut Frame, area: Rect) {
    let block = ui.pane(" Parameters ".into(), Focus::Params);
    let w = block.inner(area).width as usize;
    // joint names as the tree shows them (without the prefix all share)
    let tree = Ui::tree(wb);
    let prefix = tree.first().map_or("", |(n, _)| &n[..common_prefix(&tree)]);
    let mut lines = vec![];
    for (i, param) in params_of(wb).iter().enumerate() {
        let Some((key, value)) = ui.param_row(wb, i) else {
            lines.push(Line::from("(select a joint)"));
            continue;
        };
        let label = match key.strip_prefix("link.") {
            Some(k) => {
                let joint = k.trim_end_matches(".mass");
                joint.strip_prefix(prefix).unwrap_or(joint).to_string()
            }
            // `motor.j2.gear` → `j2 gear`
            None => match key.strip_prefix("motor.").and_then(|k| k.rsplit_once('.')) {
                Some((j, f)) => format!("{j} {f}"),
                None => key,
            },
        };
        let unit = param.panel.map_or("", |p| p.unit);
        let v = format!("{value}{unit}");
        // the value whole, the label elided in the middle when both do not fit
        let label = elide_middle(&label, w.saturating_sub(v.chars().count() + 1).max(1));
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
        && r.model.is_angular(k)
    {
        let m = crate::report::motor::JointMotion {
            joint: sel.to_string(),
            t: r.time.clone(),
            tau: r.tau.column(k),
            qd: r.v.column(k),
            qdd: r.a.column(k),
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
    match wb.take().and_then(|t| t.robot()) {
        Some(rb) => lines.push(Line::from(format!("robot ({})", rb.kind))),
        None => {
            lines.push(Line::from(
                format!("joints {:?}", p.take.joints).to_lowercase(),
            ));
            // what `auto` settled on, once a run has settled it
            let settled = wb.latest_results().and_then(|r| r.contact_auto.as_ref());
            lines.push(Line::from(match (p.take.contact, settled) {
                (crate::pipeline::Contact::Auto, Some((c, _))) => format!("contact auto → {c}"),
                (c, _) => format!("contact {c}"),
            }));
        }
    }
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
    // several takes: the list, the active one marked (`take N|NAME`, t and T switch)
    if wb.takes.len() > 1 {
        lines.push(Line::from("takes (t/T):"));
        for (i, name) in wb.take_names().into_iter().enumerate() {
            let active = wb.active == Some(i);
            let text = elide_middle(
                &format!("{}{} {name}", if active { "▸" } else { " " }, i + 1),
                w,
            );
            let style = if active {
                Style::default().add_modifier(Modifier::BOLD)
            } else {
                Style::default()
            };
            lines.push(Line::from(Span::styled(text, style)));
        }
    }
    f.render_widget(Paragraph::new(lines).block(block), area);
}

/// The residual figures against Hicks et al.'s thresholds (before and after reduction when
/// the run reduced) in one row: the longest of the pipeline's forms that fits; bold and light
/// red when beyond them (no curve's colour).
fn draw_residuals(ui: &Ui, c: &Consistency, f: &mut Frame, area: Rect) {
    let text = fit_line(&c.figure_lines(), area.width as usize);
    let style = if c.last().meets() {
        Style::default()
    } else {
        ui.fg(Color::LightRed).add_modifier(Modifier::BOLD)
    };
    f.render_widget(Paragraph::new(text).style(style), area);
}

/// The first of `forms` (longest first) that fits `width` columns, else the last cut to it.
pub fn fit_line(forms: &[String], width: usize) -> String {
    forms
        .iter()
        .find(|l| l.chars().count() <= width)
        .cloned()
        .unwrap_or_else(|| {
            let last = forms.last().map_or("", String::as_str);
            elide_middle(last, width)
        })
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
    // the part played is a thick line, the rest a thin one: the playhead reads without
    // colours (NO_COLOR) too
    let gauge = LineGauge::default()
        .ratio(ratio.clamp(0.0, 1.0))
        .label(label)
        .filled_symbol(PLAYED)
        .unfilled_symbol(UNPLAYED)
        .filled_style(style.add_modifier(Modifier::BOLD));
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
        // a recompute's preview is on screen: say what it is until the results replace it
        let preview = match (r.preview_ms, &wb.preview) {
            (Some(ms), Some(_)) => format!(
                "; drawn: a preview in {ms} ms, the last residual reduction at the new masses"
            ),
            _ => String::new(),
        };
        Line::from(format!(
            "⟳ {} {:.0}%{preview}  (Esc cancels{waiting})",
            r.label,
            r.control.progress() * 100.0
        ))
    } else {
        let msg = wb.last_message();
        let first = msg.lines().next().unwrap_or("");
        // the time of the recompute that said it, as the message's first clause: the one a
        // narrow terminal drops first ([`fit_status`]), before the verdicts that end it
        let timed;
        let first = match ui.recompute_ms {
            Some((ms, preview, n)) if n == wb.messages.len() => {
                timed = match preview {
                    Some(p) => format!("preview in {p} ms, recomputed in {ms} ms; {first}"),
                    None => format!("recomputed in {ms} ms; {first}"),
                };
                timed.as_str()
            }
            _ => first,
        };
        let hint = format!("   [{}]  ? help  : command  q quit", ui.focus.name());
        let (text, hint) = fit_status(first, &hint, area.width as usize);
        Line::from(vec![
            Span::raw(text),
            Span::styled(hint, ui.fg(Color::DarkGray)),
        ])
    };
    f.render_widget(Paragraph::new(line), area);
}

/// A message and the key hint in `width` columns: both whole if they fit; else the short hint
/// (`? help`, which shows the whole message) or none; else the message without its first
/// clauses (`; `-separated, the summary first and the verdicts last), the last ones kept.
pub fn fit_status(msg: &str, hint: &str, width: usize) -> (String, String) {
    let fits = |m: &str, h: &str| m.chars().count() + h.chars().count() <= width;
    let hints = [hint, "  ? help", ""];
    let mut clauses: Vec<&str> = msg.split("; ").collect();
    let mut text = msg.to_string();
    loop {
        if let Some(h) = hints.iter().find(|h| fits(&text, h)) {
            return (text, h.to_string());
        }
        if clauses.len() <= 1 {
            return (text, String::new());
        }
        clauses.remove(0);
        text = format!("…{}", clauses.join("; "));
    }
}

/// The key reference shown by `?`.
pub const HELP: &str = "\
q quit   ? help (any key closes)   : command line (Tab completes names and paths, ↑/↓
              history, Ctrl-U clears, Ctrl-W deletes a word, Esc closes)
Tab / S-Tab   focus the next / previous pane (joints, avatar, parameters, timeline)
joints        ↑/↓ or k/j select a joint, ←/→ or h/l its coordinate, mouse click, wheel
avatar        ←/→ yaw, ↑/↓ pitch (also < and > anywhere), r resets the view
parameters    ↑/↓ choose, ←/→ or -/+ change (results recompute), Enter edits as :set
timeline      ←/→ one frame, ↑/↓ ten frames, click to jump
anywhere      Space play/pause, [ ] one frame, { } ten frames, g/G first/last frame,
              t/T the next/previous loaded take (:take N|NAME), m the mirror joint's
              curves beside the selected one's (:set overlay mirror|none; also
              angle, feet, weights, sim: docs/workbench.md)
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

#[cfg(test)]
mod tests {
    use super::*;

    fn tree(names: &[&str]) -> Vec<(String, usize)> {
        names
            .iter()
            .enumerate()
            .map(|(i, n)| (n.to_string(), i.min(9)))
            .collect()
    }

    #[test]
    fn the_prefix_all_joints_share_is_dropped_up_to_a_separator() {
        let mixamo = tree(&["mixamorig:Hips", "mixamorig:Spine", "mixamorig:RightHand"]);
        assert_eq!(common_prefix(&mixamo), "mixamorig:".len());
        let biped = tree(&["Bip01 Pelvis", "Bip01 L Thigh", "Bip01 R Thigh"]);
        assert_eq!(common_prefix(&biped), "Bip01 ".len());
        // a shared start that is no prefix (`H`), one joint, none at all
        assert_eq!(common_prefix(&tree(&["Hips", "Head"])), 0);
        assert_eq!(common_prefix(&tree(&["mixamorig:Hips"])), 0);
        assert_eq!(common_prefix(&tree(&["joint_Root", "Hips"])), 0);
        assert_eq!(common_prefix(&[]), 0);
        // a name that is all prefix keeps it
        assert_eq!(common_prefix(&tree(&["a:", "a:b"])), 0);
    }

    /// Regression: a Mixamo hand read as identical rows of `mixamorig:RightHan` in 18 columns.
    #[test]
    fn long_names_are_elided_in_the_middle_and_stay_distinct() {
        let names: Vec<String> = (1..=3)
            .flat_map(|k| {
                ["Thumb", "Index", "Middle", "Ring", "Pinky"]
                    .map(|f| format!("mixamorig:RightHand{f}{k}"))
            })
            .collect();
        let t: Vec<(String, usize)> = names.iter().map(|n| (n.clone(), 9)).collect();
        let labels = tree_labels(&t, 18);
        for l in &labels {
            assert!(l.chars().count() <= 18, "{l}");
            assert!(!l.contains("mixamorig"), "{l}");
        }
        let mut distinct = labels.clone();
        distinct.sort();
        distinct.dedup();
        assert_eq!(distinct.len(), labels.len(), "{labels:?}");
        assert_eq!(labels[6].trim_start(), "Right…Index2");
        assert_eq!(elide_middle("RightHandIndex3", 12), "Right…Index3");
        assert_eq!(elide_middle("Hips", 12), "Hips");
    }

    #[test]
    fn a_line_is_the_longest_form_that_fits_else_the_last_elided() {
        let forms = ["a long form".to_string(), "short".into()];
        assert_eq!(fit_line(&forms, 20), "a long form");
        assert_eq!(fit_line(&forms, 10), "short");
        assert_eq!(fit_line(&forms, 4), "s…rt");
        assert_eq!(fit_line(&[], 4), "");
    }

    #[test]
    fn the_tree_widens_to_its_names_within_a_share_of_the_screen() {
        let short = tree(&["Hips", "Spine"]);
        assert_eq!(tree_width(&short, 20, 180), 20);
        let long = vec![
            ("mixamorig:Hips".to_string(), 0),
            ("mixamorig:RightHandIndex3".to_string(), 9),
        ];
        // 6 of indentation, 15 of name, 2 of borders
        assert_eq!(tree_width(&long, 20, 180), 23);
        let longer = vec![
            ("Hips".to_string(), 0),
            (
                "AVeryLongJointNameFromSomeRigExporter_Left_Index_3".to_string(),
                9,
            ),
        ];
        assert_eq!(tree_width(&longer, 26, 180), 54);
        assert_eq!(tree_width(&longer, 20, 80), 24);
    }
}
