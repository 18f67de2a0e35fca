//! The curves of the selected coordinate: its angle (or position) and its torque (or force),
//! each with the running min/max up to the current frame and its value now.
//!
//! Two forms, chosen by the room the terminal gives ([`curves_height`]):
//! - **compact** (up to 35 rows, so at 80×24): two sparklines of 2 rows, one label row each;
//! - **charts** (36 rows and more): braille line charts that share a third of the height, with
//!   a zero line, y ticks at round values in the coordinate's unit, the time axis in s on the
//!   file's clock, the current-frame cursor, and the running min and max marked on the curve.
//!
//! In both, a torque's frames that are not quoted (the take's edge frames, frames whose needed
//! force is beyond what the feet can give: issue 14) are drawn dim (in a chart: grey, or dim
//! without colours) and left out of its min/max.

use super::ui::Ui;
use crate::session::Workbench;
use crate::session::command::Quantity;
use crate::session::engine::Analysis;
use crate::session::units::{self, Kind};
use crate::session::workbench::{
    Overlay, angle_series, mirror_coord, reference_series, simulated_coord, torque_series,
};
use ratatui::Frame;
use ratatui::layout::{Constraint, Layout, Rect};
use ratatui::style::{Color, Modifier, Style};
use ratatui::symbols::Marker;
use ratatui::text::Line;
use ratatui::widgets::{
    Axis, Chart, Dataset, GraphType, LegendPosition, Paragraph, Sparkline, SparklineBar,
};

/// Terminal heights from which the curves are line charts rather than sparklines.
pub const CHARTS_FROM_ROWS: u16 = 36;

/// Rows of the curves' area on a terminal `height` rows tall: 6 (two sparklines with their
/// labels) below [`CHARTS_FROM_ROWS`], a third of the height from there on.
pub fn curves_height(height: u16) -> u16 {
    if height >= CHARTS_FROM_ROWS {
        height / 3
    } else {
        6
    }
}

/// Round tick values covering `[lo, hi]`: a step of 1, 2 or 5 × 10ⁿ, at most `max_ticks`
/// ticks, the first at or below `lo` and the last at or above `hi`; zero is a tick whenever
/// the ticks span it. A flat or empty range gets a unit-wide span around its value.
pub fn nice_ticks(lo: f64, hi: f64, max_ticks: usize) -> Vec<f64> {
    let (lo, hi) = if lo.is_finite() && hi.is_finite() && lo <= hi {
        (lo, hi)
    } else {
        (0.0, 0.0)
    };
    let (lo, hi) = if hi - lo < 1e-9 * hi.abs().max(1.0) {
        (lo - 0.5, hi + 0.5)
    } else {
        (lo, hi)
    };
    let max_ticks = max_ticks.max(2);
    let raw = (hi - lo) / (max_ticks - 1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    for m in [1.0, 2.0, 5.0, 10.0, 20.0] {
        let step = m * mag;
        let first = (lo / step).floor();
        let last = (hi / step).ceil();
        if ((last - first) as usize) < max_ticks {
            // ticks as multiples of the step, so that zero is exactly one of them
            return (first as i64..=last as i64)
                .map(|i| i as f64 * step)
                .collect();
        }
    }
    vec![lo, hi]
}

/// Ticks whose labels sit on the rows their values are drawn at: a chart spaces `n` labels
/// evenly over its `rows`, which matches the curve's scale only when `n − 1` divides
/// `rows − 1`. Steps are added, on the side with the least room around `[lo, hi]`, until it
/// does; where that would need more ticks than rows, only the end ticks are kept (the scale
/// is unchanged).
pub fn fit_ticks(mut ticks: Vec<f64>, (lo, hi): (f64, f64), rows: usize) -> Vec<f64> {
    if ticks.len() < 2 || rows < 2 {
        return ticks;
    }
    let step = ticks[1] - ticks[0];
    while !(rows - 1).is_multiple_of(ticks.len() - 1) && ticks.len() < rows {
        let (first, last) = (ticks[0], ticks[ticks.len() - 1]);
        if lo - first <= last - hi {
            ticks.insert(0, first - step);
        } else {
            ticks.push(last + step);
        }
    }
    if !(rows - 1).is_multiple_of(ticks.len() - 1) {
        ticks = vec![ticks[0], ticks[ticks.len() - 1]];
    }
    ticks
}

/// `min`, `max` over the frames `0..=k` of `x` that `quoted` keeps (issue 14: a torque's
/// running extremes leave out the edge frames and those beyond what the feet can give), and
/// `x[k]`; `None` before the first quoted frame's min and max exist.
pub fn running_stats(
    x: &[f64],
    k: usize,
    quoted: impl Fn(usize) -> bool,
) -> Option<(Option<(f64, f64)>, f64)> {
    let seen = x.get(..=k.min(x.len().checked_sub(1)?))?;
    let kept = seen.iter().enumerate().filter(|&(i, _)| quoted(i));
    let (min, max) = kept.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (_, &v)| {
        (lo.min(v), hi.max(v))
    });
    Some(((min <= max).then_some((min, max)), *seen.last()?))
}

/// The frames of the running min and max of `x` over `0..=k` among the quoted frames.
fn running_extreme_frames(
    x: &[f64],
    k: usize,
    quoted: impl Fn(usize) -> bool,
) -> Option<(usize, usize)> {
    let seen = x.get(..=k.min(x.len().checked_sub(1)?))?;
    let kept = || seen.iter().enumerate().filter(|&(i, _)| quoted(i));
    let lo = kept().min_by(|a, b| a.1.total_cmp(b.1))?.0;
    let hi = kept().max_by(|a, b| a.1.total_cmp(b.1))?.0;
    Some((lo, hi))
}

/// Sparkline bars: the take squeezed to `width` columns on the scale of the whole take;
/// columns after frame `k` are absent, columns on a frame `quoted` leaves out are `shaded`.
fn bars(
    x: &[f64],
    k: usize,
    width: usize,
    quoted: impl Fn(usize) -> bool,
    shaded: Style,
) -> Vec<SparklineBar> {
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
            let bar = SparklineBar::from(
                (i <= k).then(|| 1 + ((x[i] - lo) / span * 99.0).round() as u64),
            );
            if quoted(i) {
                bar
            } else {
                bar.style(Some(shaded))
            }
        })
        .collect()
}

/// One curve to draw: its name, quantity word, series (SI), kind and colour.
struct Curve {
    name: String,
    what: &'static str,
    x: Option<Vec<f64>>,
    kind: Kind,
    color: Color,
    /// A force: its axis holds zero, and the frames not quoted are shaded and not in its
    /// min/max.
    forces: bool,
    /// Further curves on the same scale (the mirror joint's, the other foot's, the other body
    /// masses'): name, series (SI), colour.
    others: Vec<(String, Vec<f64>, Color)>,
    /// Drawn against this series (an angle, SI, of kind `Kind::Angle`) instead of time.
    against: Option<Vec<f64>>,
    /// Why there is nothing to draw (`run sim first`), when `x` is `None`.
    missing: Option<String>,
}

impl Curve {
    fn new(name: &str, what: &'static str, x: Option<Vec<f64>>, kind: Kind, color: Color) -> Self {
        Self {
            name: name.to_string(),
            what,
            x,
            kind,
            color,
            forces: matches!(what, "torque" | "force" | "moment"),
            others: vec![],
            against: None,
            missing: None,
        }
    }
    fn missing(name: &str, what: &'static str, kind: Kind, why: String) -> Self {
        Self {
            missing: Some(why),
            ..Self::new(name, what, None, kind, Color::Reset)
        }
    }
}

/// The colour of the mirror joint's curve.
const MIRROR: Color = Color::Green;

/// The colours of the body masses of `compare weights`, in order (cycled past eleven).
const PALETTE: [Color; 11] = [
    Color::Magenta,
    Color::Cyan,
    Color::Green,
    Color::Yellow,
    Color::Red,
    Color::Blue,
    Color::LightMagenta,
    Color::LightCyan,
    Color::LightGreen,
    Color::LightYellow,
    Color::LightRed,
];

/// The two curves the pane draws for the selection and `set overlay`.
fn curves_of(wb: &Workbench) -> [Curve; 2] {
    let sel = wb.selection.clone();
    let r = wb.latest_results().map(|a| &**a);
    let name = sel.as_deref().unwrap_or("no selection");
    // the angle of the selected coordinate (a rotation-vector component for ball joints) and
    // its torque
    let series = |f: fn(&Analysis, &str) -> Option<Vec<f64>>| {
        r.zip(sel.as_deref()).and_then(|(r, s)| f(r, s))
    };
    let is_angle = match (r, sel.as_deref()) {
        (Some(r), Some(s)) => r.model.v_index(s).is_none_or(|k| r.model.is_angular(k)),
        _ => true,
    };
    let angle = || {
        let what = if is_angle { "angle" } else { "position" };
        let kind = Quantity::Angle.kind(is_angle);
        Curve::new(name, what, series(angle_series), kind, Color::Cyan)
    };
    let torque = || {
        let what = if is_angle { "torque" } else { "force" };
        let kind = Quantity::Torque.kind(is_angle);
        Curve::new(name, what, series(torque_series), kind, Color::Magenta)
    };
    match wb.overlay {
        Overlay::None => [angle(), torque()],
        Overlay::Mirror => {
            let mirror = r
                .zip(sel.as_deref())
                .and_then(|(r, s)| Some((r, mirror_coord(r, s)?)));
            let mut c = [angle(), torque()];
            for (c, f) in c
                .iter_mut()
                .zip([angle_series, torque_series] as [fn(&Analysis, &str) -> Option<Vec<f64>>; 2])
            {
                if let Some((r, m)) = &mirror
                    && let Some(y) = f(r, m)
                {
                    c.others.push((m.clone(), y, MIRROR));
                }
            }
            c
        }
        // the moment against the angle: the joint's work loop
        Overlay::Angle => {
            let mut loop_ = torque();
            loop_.against = series(angle_series);
            [angle(), loop_]
        }
        Overlay::Feet => [torque(), feet(r)],
        Overlay::Weights => [angle(), weights(wb)],
        Overlay::Sim => sim_curves(wb, r, sel.as_deref()),
    }
}

/// Both feet's vertical ground forces (with ground contact).
fn feet(r: Option<&Analysis>) -> Curve {
    let what = "vertical ground force";
    let Some(f) = r.filter(|r| !r.feet.names.is_empty()).map(|r| &r.feet) else {
        let why = "no ground forces: set contact feet".to_string();
        return Curve::missing("feet", what, Kind::Force, why);
    };
    let foot = |j: usize| (format!("{} foot", f.names[j]), f.column(j));
    let (name, x) = foot(0);
    let mut c = Curve::new(&name, what, Some(x), Kind::Force, Color::Cyan);
    c.forces = true;
    c.others = (1..f.names.len())
        .map(|j| {
            let (n, y) = foot(j);
            (n, y, Color::Magenta)
        })
        .collect();
    c
}

/// The torque of the last `compare weights` per body mass.
fn weights(wb: &Workbench) -> Curve {
    let Some(cmp) = &wb.comparison else {
        let why = "no comparison: compare weights 60,80,100 PATH first".to_string();
        return Curve::missing("weights", "torque", Kind::Torque, why);
    };
    let mut runs = cmp.runs.iter().zip(PALETTE.iter().cycle());
    let Some(((m0, x0), &c0)) = runs.next() else {
        return Curve::missing("weights", "torque", Kind::Torque, "no masses".into());
    };
    let name = format!("{} at {m0} kg", cmp.coord);
    let mut c = Curve::new(&name, "torque", Some(x0.clone()), cmp.kind, c0);
    c.others = runs
        .map(|((m, x), &col)| (format!("{m} kg"), x.clone(), col))
        .collect();
    c
}

/// The simulation's angle over the take's and its tracking error (`q_sim − q_ref`) of the
/// selected coordinate (an anatomical axis: its joint's coordinate of largest motion).
fn sim_curves(wb: &Workbench, r: Option<&Analysis>, sel: Option<&str>) -> [Curve; 2] {
    let Some((sim, _)) = &wb.sim else {
        let why = || "no simulation: run sim".to_string();
        return [
            Curve::missing("sim", "angle", Kind::Angle, why()),
            Curve::missing("sim", "tracking error", Kind::Angle, why()),
        ];
    };
    let coord = sel.and_then(|s| simulated_coord(r.unwrap_or(sim), sim, s));
    let Some(c) = coord else {
        let why = || {
            format!(
                "{}: no coordinate of the simulation",
                sel.unwrap_or("no selection")
            )
        };
        return [
            Curve::missing("sim", "angle", Kind::Angle, why()),
            Curve::missing("sim", "tracking error", Kind::Angle, why()),
        ];
    };
    let angular = sim
        .model
        .v_index(&c)
        .is_none_or(|k| sim.model.is_angular(k));
    let kind = Quantity::Angle.kind(angular);
    let (q, q_ref) = (angle_series(sim, &c), reference_series(sim, &c));
    let mut a = Curve::new(&c, "simulated", q.clone(), kind, Color::Cyan);
    if let Some(y) = &q_ref {
        a.others.push(("reference".into(), y.clone(), Color::Green));
    }
    let e = q
        .zip(q_ref)
        .map(|(q, y)| q.iter().zip(&y).map(|(a, b)| a - b).collect());
    let mut err = Curve::new(&c, "tracking error", e, kind, Color::Red);
    err.forces = false;
    [a, err]
}

/// Draws the selected coordinate's two curves in `area` (sparklines or charts by its height),
/// or what `set overlay` puts there.
pub fn draw_curves(ui: &Ui, wb: &Workbench, f: &mut Frame, area: Rect) {
    let r = wb.latest_results();
    let curves = curves_of(wb);
    let charts = area.height >= 2 * 6;
    let halves: [Rect; 2] = if charts {
        // the lower chart also holds the time axis (2 rows)
        let upper = area.height.saturating_sub(2) / 2;
        Layout::vertical([Constraint::Length(upper), Constraint::Min(0)]).areas(area)
    } else {
        Layout::vertical([Constraint::Length(3), Constraint::Length(3)]).areas(area)
    };
    for (i, (c, rect)) in curves.into_iter().zip(halves).enumerate() {
        let Some(x) = &c.x else {
            let why = c.missing.clone().unwrap_or_else(|| "no results".into());
            let p = Paragraph::new(format!("{} {}: {why}", c.name, c.what));
            f.render_widget(p, rect);
            continue;
        };
        // a torque's frames left out (edge, beyond the feet) are shaded and not in its min/max
        let forces = c.forces;
        let quoted = |k: usize| !forces || r.is_none_or(|r| r.quoted(k));
        let [l, s] = Layout::vertical([Constraint::Length(1), Constraint::Min(1)]).areas(rect);
        f.render_widget(
            Paragraph::new(label(&c, x, wb.frame, quoted)).style(ui.fg(c.color)),
            l,
        );
        let shaded = ui.fg(Color::DarkGray).add_modifier(Modifier::DIM);
        if let Some(angle) = &c.against {
            draw_against(ui, wb, f, s, &c, x, angle);
        } else if charts {
            // the time axis once, under the lower chart
            draw_chart(ui, wb, f, s, &c, x, quoted, i == 1);
        } else {
            let spark = Sparkline::default()
                .data(bars(x, wb.frame, s.width as usize, quoted, shaded))
                .max(100)
                .style(ui.fg(c.color));
            f.render_widget(spark, s);
        }
    }
}

/// `knee_l:flexion torque [N·m]  min -56.9  max 57.2  now 40.9  (345 shaded frames not quoted)`
fn label(c: &Curve, x: &[f64], k: usize, quoted: impl Fn(usize) -> bool + Copy) -> String {
    let left_out = (0..x.len()).filter(|&i| !quoted(i)).count();
    // the label in the coordinate's own unit, rounded by its kind
    let unit = units::shown_unit(c.kind);
    let n = |v| units::format_number(c.kind, v);
    let what = match c.against {
        Some(_) => format!("{} against angle", c.what),
        None => c.what.to_string(),
    };
    let name = c.name.as_str();
    let label = match running_stats(x, k, quoted) {
        Some((Some((min, max)), now)) => format!(
            "{name} {what} [{unit}]  min {}  max {}  now {}",
            n(min),
            n(max),
            n(now)
        ),
        Some((None, now)) => format!("{name} {what} [{unit}]  now {}", n(now)),
        None => format!("{name} {what}"),
    };
    // the other curves' values now (the mirror joint, the other foot, the other masses)
    let mut label = label;
    for (m, y, _) in &c.others {
        if let Some(&v) = y.get(k.min(y.len().saturating_sub(1))) {
            label = format!("{label}  │ {m} now {}", n(v));
        }
    }
    if left_out > 0 {
        format!("{label}  ({left_out} shaded frames not quoted)")
    } else {
        label
    }
}

/// A braille line chart of `x` (SI) in its display unit against the file's time.
#[allow(clippy::too_many_arguments)]
fn draw_chart(
    ui: &Ui,
    wb: &Workbench,
    f: &mut Frame,
    area: Rect,
    c: &Curve,
    x: &[f64],
    quoted: impl Fn(usize) -> bool + Copy,
    time_axis: bool,
) {
    let dt = wb.take().map_or(0.0, |t| t.frame_time());
    // times on the file's clock, as the timeline and every output write them
    let t0 = wb.take().and_then(|t| t.bvh()).map_or(0.0, |b| b.time(0));
    let t = |k: usize| t0 + k as f64 * dt;
    let shown = |v: f64| units::shown(c.kind, v).0;
    let pts: Vec<(f64, f64)> = x
        .iter()
        .enumerate()
        .map(|(k, &v)| (t(k), shown(v)))
        .collect();
    // the scale serves the numbers a user reads: the quoted frames' range when there are
    // any (a left-out spike runs off the chart, dim), else every frame's
    let range = |keep: &dyn Fn(usize) -> bool| {
        (pts.iter().enumerate().filter(|&(k, _)| keep(k)))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), (_, p)| {
                (lo.min(p.1), hi.max(p.1))
            })
    };
    let (lo, hi) = match range(&quoted) {
        (lo, hi) if lo <= hi => (lo, hi),
        _ => range(&|_| true),
    };
    // the other curves on the same scale (their quoted frames are the take's)
    let others: Vec<Vec<(f64, f64)>> = (c.others.iter())
        .map(|(_, y, _)| {
            y.iter()
                .enumerate()
                .map(|(k, &v)| (t(k), shown(v)))
                .collect()
        })
        .collect();
    let (lo, hi) = (others.iter())
        .flat_map(|o| o.iter().enumerate())
        .filter(|&(k, _)| quoted(k))
        .fold((lo, hi), |(lo, hi), (_, p)| (lo.min(p.1), hi.max(p.1)));
    // a force's sign is what a reader looks for: its axis always holds zero
    let forces = c.forces;
    let (lo, hi) = if forces {
        (lo.min(0.0), hi.max(0.0))
    } else {
        (lo, hi)
    };
    let plot_rows = area.height.saturating_sub(if time_axis { 2 } else { 0 }) as usize;
    // ticks on the chart's rows, or on one row fewer when that needs fewer added steps (the
    // chart then leaves its top row blank)
    let nice = nice_ticks(lo, hi, (plot_rows.div_ceil(2) + 1).clamp(2, 6));
    let (ticks, area) = [0, 1]
        .into_iter()
        .filter(|&less| plot_rows > less + 2)
        .map(|less| {
            let t = fit_ticks(nice.clone(), (lo, hi), plot_rows - less);
            let inner = Rect {
                y: area.y + less as u16,
                height: area.height - less as u16,
                ..area
            };
            (t, inner)
        })
        .min_by_key(|(t, _)| {
            if t.len() == 2 {
                usize::MAX
            } else {
                t.len() - nice.len()
            }
        })
        .unwrap_or((nice.clone(), area));
    let (y0, y1) = (ticks[0], ticks[ticks.len() - 1]);
    let (x0, x1) = (t(0), t(x.len().saturating_sub(1)).max(t(0) + dt.max(1e-9)));
    let runs = runs_of(x.len(), quoted);
    let pieces: Vec<Vec<(f64, f64)>> = runs
        .iter()
        .map(|&(a, b, _)| pts[a..=b.min(pts.len() - 1)].to_vec())
        .collect();
    let zero = [(x0, 0.0), (x1, 0.0)];
    let cursor_t = t(wb.frame.min(x.len().saturating_sub(1)));
    let cursor = [(cursor_t, y0), (cursor_t, y1)];
    let extremes: Vec<(f64, f64)> = running_extreme_frames(x, wb.frame, quoted)
        .map(|(a, b)| vec![pts[a], pts[b]])
        .unwrap_or_default();
    let mut sets = vec![];
    if y0 < 0.0 && y1 > 0.0 {
        sets.push(
            Dataset::default()
                .marker(Marker::Dot)
                .graph_type(GraphType::Line)
                .style(ui.fg(Color::Gray))
                .data(&zero),
        );
    }
    // left-out frames: grey (a chart's cells keep no modifier: without colours the grey is
    // turned into dim below)
    for (piece, &(_, _, kept)) in pieces.iter().zip(&runs) {
        sets.push(
            Dataset::default()
                .marker(Marker::Braille)
                .graph_type(GraphType::Line)
                .style(if kept {
                    ui.fg(c.color)
                } else {
                    Style::default().fg(LEFT_OUT)
                })
                .data(piece),
        );
    }
    // the other curves under the selected one, which is drawn over them
    for (o, (_, _, color)) in others.iter().zip(&c.others).rev() {
        sets.insert(
            usize::from(y0 < 0.0 && y1 > 0.0),
            Dataset::default()
                .marker(Marker::Braille)
                .graph_type(GraphType::Line)
                .style(Style::default().fg(*color))
                .data(o),
        );
    }
    sets.push(
        Dataset::default()
            .marker(Marker::Braille)
            .graph_type(GraphType::Line)
            .style(ui.fg(Color::Yellow))
            .data(&cursor),
    );
    sets.push(
        Dataset::default()
            .marker(Marker::Block)
            .graph_type(GraphType::Scatter)
            .style(ui.fg(Color::White).add_modifier(Modifier::BOLD))
            .data(&extremes),
    );
    let step = (y1 - y0) / (ticks.len() - 1) as f64;
    let fmt = |v: f64| tick_label(v, step.min(y1 - y0));
    // the top tick carries the unit
    let unit = units::shown_unit(c.kind);
    let last = ticks.len() - 1;
    let y_labels: Vec<Line> = (ticks.iter().enumerate())
        .map(|(i, &v)| {
            Line::from(if i == last {
                format!("{} {unit}", fmt(v))
            } else {
                fmt(v)
            })
        })
        .collect();
    let mut x_axis = Axis::default().bounds([x0, x1]);
    if time_axis {
        x_axis = x_axis.labels([
            format!("{x0:.2} s"),
            format!("{:.2}", (x0 + x1) / 2.0),
            format!("{x1:.2} s"),
        ]);
    }
    let chart = Chart::new(sets)
        .x_axis(x_axis)
        .y_axis(
            Axis::default()
                .bounds([y0, y1])
                .labels(y_labels)
                .style(ui.fg(Color::Gray)),
        )
        .legend_position(None::<LegendPosition>);
    f.render_widget(chart, area);
    if !ui.color {
        let buf = f.buffer_mut();
        for y in area.top()..area.bottom() {
            for x in area.left()..area.right() {
                let cell = &mut buf[(x, y)];
                if cell.fg == LEFT_OUT {
                    cell.set_fg(Color::Reset);
                    cell.modifier.insert(Modifier::DIM);
                }
            }
        }
    }
}

/// A braille chart of `y` (a moment, SI) against `angle` (SI): the joint's work loop, the
/// current frame marked, zero lines where the ranges span zero, the ends of both axes
/// labelled with their units.
fn draw_against(
    ui: &Ui,
    wb: &Workbench,
    f: &mut Frame,
    area: Rect,
    c: &Curve,
    y: &[f64],
    angle: &[f64],
) {
    let pts: Vec<(f64, f64)> = angle
        .iter()
        .zip(y)
        .map(|(&a, &m)| (units::shown(Kind::Angle, a).0, units::shown(c.kind, m).0))
        .collect();
    let span = |i: usize| {
        let (lo, hi) = pts
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                let v = if i == 0 { p.0 } else { p.1 };
                (lo.min(v), hi.max(v))
            });
        let ticks = nice_ticks(lo, hi, 6);
        (ticks[0], ticks[ticks.len() - 1])
    };
    let ((x0, x1), (y0, y1)) = (span(0), span(1));
    let now = pts.get(wb.frame.min(pts.len().saturating_sub(1))).copied();
    let now: Vec<(f64, f64)> = now.into_iter().collect();
    let (zx, zy) = ([(x0, 0.0), (x1, 0.0)], [(0.0, y0), (0.0, y1)]);
    let mut sets = vec![];
    if y0 < 0.0 && y1 > 0.0 {
        sets.push(zero_line(ui, &zx));
    }
    if x0 < 0.0 && x1 > 0.0 {
        sets.push(zero_line(ui, &zy));
    }
    sets.push(
        Dataset::default()
            .marker(Marker::Braille)
            .graph_type(GraphType::Line)
            .style(ui.fg(c.color))
            .data(&pts),
    );
    sets.push(
        Dataset::default()
            .marker(Marker::Block)
            .graph_type(GraphType::Scatter)
            .style(ui.fg(Color::Yellow).add_modifier(Modifier::BOLD))
            .data(&now),
    );
    let fmt = |v: f64, lo: f64, hi: f64| tick_label(v, (hi - lo).max(1e-9));
    let (ua, um) = (units::shown_unit(Kind::Angle), units::shown_unit(c.kind));
    let (mut x_axis, mut y_axis) = (
        Axis::default().bounds([x0, x1]),
        Axis::default().bounds([y0, y1]).style(ui.fg(Color::Gray)),
    );
    // the ends of both axes labelled when there is room; the compact form is the loop alone
    // (its label says what it is)
    if area.height >= 6 {
        x_axis = x_axis.labels([fmt(x0, x0, x1), format!("angle [{ua}] {}", fmt(x1, x0, x1))]);
        y_axis = y_axis.labels([fmt(y0, y0, y1), format!("{} {um}", fmt(y1, y0, y1))]);
    }
    let chart = Chart::new(sets)
        .x_axis(x_axis)
        .y_axis(y_axis)
        .legend_position(None::<LegendPosition>);
    f.render_widget(chart, area);
}

/// A dotted grey zero line through `pts`.
fn zero_line<'a>(ui: &Ui, pts: &'a [(f64, f64)]) -> Dataset<'a> {
    Dataset::default()
        .marker(Marker::Dot)
        .graph_type(GraphType::Line)
        .style(ui.fg(Color::Gray))
        .data(pts)
}

/// The colour of a torque's frames that are not quoted.
const LEFT_OUT: Color = Color::DarkGray;

/// A tick's value with the decimals its step needs: `50` for a step of 50, `0.5` for 0.5.
pub fn tick_label(v: f64, step: f64) -> String {
    let d = (-step.abs().log10().floor()).clamp(0.0, 9.0) as usize;
    units::fixed(v, d)
}

/// Runs of consecutive frames that are all quoted or all left out: `(first, last, quoted)`;
/// each run but the last also holds the next run's first frame, so the pieces join.
fn runs_of(n: usize, quoted: impl Fn(usize) -> bool) -> Vec<(usize, usize, bool)> {
    let mut runs: Vec<(usize, usize, bool)> = vec![];
    for k in 0..n {
        let q = quoted(k);
        match runs.last_mut() {
            Some(r) if r.2 == q => r.1 = k,
            Some(r) => {
                r.1 = k;
                runs.push((k, k, q));
            }
            None => runs.push((k, k, q)),
        }
    }
    runs
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_are_round_cover_the_range_and_hold_zero_when_it_is_spanned() {
        let t = nice_ticks(-56.9, 57.2, 5);
        assert!(t.len() <= 5 && t.len() >= 2, "{t:?}");
        assert!(t[0] <= -56.9 && *t.last().unwrap() >= 57.2, "{t:?}");
        assert!(t.contains(&0.0), "{t:?}");
        let step = t[1] - t[0];
        assert!(t.windows(2).all(|w| ((w[1] - w[0]) - step).abs() < 1e-9));
        assert!([1.0, 2.0, 5.0].iter().any(|m| {
            let e = step / m;
            (e.log10() - e.log10().round()).abs() < 1e-9
        }));
        // a positive range keeps its own ticks; a flat one gets a span
        let t = nice_ticks(3.3, 67.7, 4);
        assert!(
            t[0] <= 3.3 && *t.last().unwrap() >= 67.7 && t.len() <= 4,
            "{t:?}"
        );
        let t = nice_ticks(2.0, 2.0, 4);
        assert!(t[0] < 2.0 && *t.last().unwrap() > 2.0, "{t:?}");
        assert!(nice_ticks(f64::NAN, 1.0, 4).len() >= 2);
    }

    #[test]
    fn runs_join_and_alternate() {
        let q = |k: usize| !(3..5).contains(&k);
        assert_eq!(
            runs_of(8, q),
            vec![(0, 3, true), (3, 5, false), (5, 7, true)]
        );
        assert_eq!(runs_of(3, |_| true), vec![(0, 2, true)]);
        assert!(runs_of(0, |_| true).is_empty());
    }

    #[test]
    fn fitted_ticks_divide_the_rows() {
        for rows in 2..20 {
            for (lo, hi) in [(-56.9, 57.2), (3.3, 67.7), (-130.0, 20.0)] {
                let t = fit_ticks(
                    nice_ticks(lo, hi, (rows / 2 + 1).clamp(2, 6)),
                    (lo, hi),
                    rows,
                );
                assert!((rows - 1).is_multiple_of(t.len() - 1), "{rows} {t:?}");
                assert!(t[0] <= lo && t[t.len() - 1] >= hi);
            }
        }
        // ticks that fit already are kept
        assert_eq!(
            fit_ticks(vec![-100.0, 0.0, 100.0], (-57.0, 57.0), 5).len(),
            3
        );
    }

    #[test]
    fn tick_labels_carry_the_decimals_of_their_step() {
        assert_eq!(tick_label(100.0, 50.0), "100");
        assert_eq!(tick_label(-0.5, 0.5), "-0.5");
        assert_eq!(tick_label(0.25, 0.05), "0.25");
        assert_eq!(tick_label(-0.0, 20.0), "0");
    }
}
