//! SVG charts of curves over time, drawn with plotters into a `String`.
//!
//! The layout follows the paper's figure 4 (joint torque and angle over time with the minimum
//! and maximum of each curve marked and labelled), with a legend and axis titles carrying the
//! units. Text is laid out with an embedded font (Hack from `epaint_default_fonts`, registered
//! with plotters under the generic family names `sans-serif` and `monospace`), so no system font
//! is needed and the SVG names a family every viewer has. Hack is monospaced at 0.6 em per glyph,
//! at least as wide as the common sans-serif faces, so boxes sized from its metrics (legend,
//! label areas) still hold the text in whatever face the viewer substitutes.
//!
//! Output is deterministic: plotters' SVG backend writes integer pixel coordinates in drawing
//! order, colours come from a fixed palette, and nothing depends on time or hashing, so the same
//! input gives byte-identical SVG.
//!
//! Bad data is an [`Error::Invalid`], never a panic: no series, a series without points, `x`
//! and `y` of different lengths, or a value that is not finite (NaN, ±∞). Degenerate ranges (a
//! constant curve, a single point) are widened so the chart still has an extent.

use crate::error::Error;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;
use std::sync::OnceLock;

/// One curve: `y[i]` at `x[i]` (same length, finite), shown in the legend as `label`.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend entry (e.g. `"knee (right)"`, `"60 kg"`).
    pub label: String,
    /// Abscissae, usually time (s).
    pub x: Vec<f64>,
    /// Ordinates, in the unit named by the panel's y label.
    pub y: Vec<f64>,
}

impl Series {
    pub fn new(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self {
            label: label.into(),
            x,
            y,
        }
    }
}

/// One chart panel: a titled pair of axes with its curves.
#[derive(Debug, Clone, Copy)]
pub struct Panel<'a> {
    /// Caption above the axes.
    pub title: &'a str,
    /// Horizontal axis title with its unit, e.g. `"time (s)"`.
    pub x_label: &'a str,
    /// Vertical axis title with its unit, e.g. `"torque (N·m)"`.
    pub y_label: &'a str,
    /// The curves, one colour and one legend entry each.
    pub series: &'a [Series],
    /// Mark and label the minimum and maximum of every curve.
    pub mark_min_max: bool,
    /// Spans of the abscissa `[from, to]` drawn shaded and left out of the minimum and maximum
    /// (issue 14: frames whose forces are not quoted), with what the shading means in the
    /// legend; none: `&[]`.
    pub shaded: &'a [(f64, f64)],
    /// The legend entry of the shading (e.g. `"not quoted"`).
    pub shaded_label: &'a str,
}

/// A table drawn as text under the panels: one `<text>` per cell, columns left-aligned.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Table {
    pub header: Vec<String>,
    pub rows: Vec<Vec<String>>,
}

/// Width of every chart (px).
pub const WIDTH: u32 = 960;
/// Height of one panel (px).
pub const PANEL_HEIGHT: u32 = 420;
/// Height of one table line (px).
const TABLE_LINE: u32 = 22;

/// Colour-blind-friendly categorical palette (Tableau 10), cycled over the series.
const PALETTE: [RGBColor; 10] = [
    RGBColor(0x4E, 0x79, 0xA7),
    RGBColor(0xF2, 0x8E, 0x2B),
    RGBColor(0xE1, 0x57, 0x59),
    RGBColor(0x76, 0xB7, 0xB2),
    RGBColor(0x59, 0xA1, 0x4F),
    RGBColor(0xED, 0xC9, 0x48),
    RGBColor(0xB0, 0x7A, 0xA1),
    RGBColor(0xFF, 0x9D, 0xA7),
    RGBColor(0x9C, 0x75, 0x5F),
    RGBColor(0xBA, 0xB0, 0xAC),
];

const FONT: &str = "sans-serif";
const MONO: &str = "monospace";

/// Registers the embedded fonts with plotters once per process.
fn register_fonts() -> Result<(), Error> {
    static OK: OnceLock<bool> = OnceLock::new();
    let ok = *OK.get_or_init(|| {
        let sans = plotters::style::register_font(
            FONT,
            FontStyle::Normal,
            epaint_default_fonts::HACK_REGULAR,
        );
        let mono = plotters::style::register_font(
            MONO,
            FontStyle::Normal,
            epaint_default_fonts::HACK_REGULAR,
        );
        sans.is_ok() && mono.is_ok()
    });
    if ok {
        Ok(())
    } else {
        Err(Error::Invalid(
            "the embedded chart fonts failed to load".into(),
        ))
    }
}

/// A chart of `series` over time (the paper's figure 4): one panel with title, axis titles,
/// legend, and with `mark_min_max` the minimum and maximum of each curve marked and labelled
/// `min <value> @ <x>` / `max <value> @ <x>`.
pub fn time_series_svg(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    mark_min_max: bool,
) -> Result<String, Error> {
    stacked_svg(
        &[Panel {
            title,
            x_label,
            y_label,
            series,
            mark_min_max,
            shaded: &[],
            shaded_label: "",
        }],
        None,
    )
}

/// Panels stacked top to bottom, all [`WIDTH`] wide, optionally followed by a text table.
pub fn stacked_svg(panels: &[Panel<'_>], table: Option<&Table>) -> Result<String, Error> {
    if panels.is_empty() {
        return Err(Error::Invalid("chart: no panel to draw".into()));
    }
    for p in panels {
        validate(p)?;
    }
    register_fonts()?;
    let table_h = table.map_or(0, |t| {
        (t.rows.len() as u32 + 1) * TABLE_LINE + 2 * TABLE_LINE
    });
    let height = panels.len() as u32 * PANEL_HEIGHT + table_h;
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (WIDTH, height)).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        let (charts, below) = root.split_vertically(panels.len() as u32 * PANEL_HEIGHT);
        let areas = charts.split_evenly((panels.len(), 1));
        for (p, area) in panels.iter().zip(&areas) {
            draw_panel(area, p)?;
        }
        if let Some(t) = table {
            draw_table(&below, t)?;
        }
        root.present().map_err(plot_err)?;
    }
    Ok(svg)
}

/// Writes an SVG document to `path` atomically.
pub fn write_svg(path: &Path, svg: &str) -> Result<(), Error> {
    crate::io::write_atomic(path, svg.as_bytes())
}

/// `series` as CSV columns: the shared abscissa first (named `x_name`), then one column per
/// series named by its label. All series must share the same `x` (bit for bit).
pub fn series_columns<'a>(
    x_name: &str,
    series: &'a [Series],
) -> Result<(Vec<String>, Vec<&'a [f64]>), Error> {
    let Some(first) = series.first() else {
        return Err(Error::Invalid("CSV export: no series".into()));
    };
    let mut header = vec![x_name.to_string()];
    let mut cols: Vec<&[f64]> = vec![&first.x];
    for s in series {
        let same = s.x.len() == first.x.len()
            && s.x
                .iter()
                .zip(&first.x)
                .all(|(a, b)| a.to_bits() == b.to_bits());
        if !same {
            return Err(Error::Invalid(format!(
                "CSV export: series {:?} is sampled at other abscissae than {:?}; export them \
                 separately",
                s.label, first.label
            )));
        }
        if s.y.len() != s.x.len() {
            return Err(Error::Invalid(format!(
                "CSV export: series {:?} has {} x and {} y values",
                s.label,
                s.x.len(),
                s.y.len()
            )));
        }
        header.push(s.label.clone());
        cols.push(&s.y);
    }
    Ok((header, cols))
}

/// The CSV text of [`series_columns`] (what a chart plots, at full resolution).
pub fn series_csv(x_name: &str, series: &[Series]) -> Result<String, Error> {
    let (header, cols) = series_columns(x_name, series)?;
    crate::report::csv::columns_to_string(&header, &cols)
}

/// A short decimal for labels: four significant digits, no exponent for ordinary magnitudes.
pub fn fmt_value(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{}", if v == 0.0 { 0.0 } else { v });
    }
    let mag = v.abs().log10().floor() as i32;
    if !(-4..=6).contains(&mag) {
        return format!("{v:.3e}");
    }
    let decimals = (3 - mag).clamp(0, 7) as usize;
    let s = format!("{v:.decimals$}");
    // "-0.000" style results of rounding are printed as 0
    if s.trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        "0".into()
    } else {
        s
    }
}

/// Indices of the samples worth drawing when `x` (non-decreasing, within `[x0, x1]`) is drawn
/// `columns` pixels wide: in every pixel column the first, lowest, highest and last sample
/// (M4 aggregation, Jugel et al. 2014, "M4: a visualization-oriented time series data
/// aggregation", PVLDB 7(10)), which draws the same line at that resolution. Series with at most
/// `4 · columns` samples, or whose `x` goes back, are kept whole, as is everything when
/// `columns` is 0.
pub fn decimate_m4(x: &[f64], y: &[f64], x0: f64, x1: f64, columns: usize) -> Vec<usize> {
    let n = x.len().min(y.len());
    let sorted = x[..n].windows(2).all(|w| w[0] <= w[1]);
    if columns == 0 || n <= 4 * columns || !sorted || x1 <= x0 {
        return (0..n).collect();
    }
    let column = |v: f64| (((v - x0) / (x1 - x0) * columns as f64) as usize).min(columns - 1);
    let mut keep = Vec::with_capacity(4 * columns);
    let mut start = 0;
    while start < n {
        // one pixel column: samples start..end
        let c = column(x[start]);
        let mut end = start + 1;
        while end < n && column(x[end]) == c {
            end += 1;
        }
        let (mut lo, mut hi) = (start, start);
        for i in start..end {
            if y[i] < y[lo] {
                lo = i;
            }
            if y[i] > y[hi] {
                hi = i;
            }
        }
        let mut four = [start, lo, hi, end - 1];
        four.sort_unstable();
        for i in four {
            if keep.last() != Some(&i) {
                keep.push(i);
            }
        }
        start = end;
    }
    keep
}

/// Rejects panels plotters cannot draw or would draw misleadingly.
fn validate(p: &Panel<'_>) -> Result<(), Error> {
    if p.series.is_empty() {
        return Err(Error::Invalid(format!(
            "chart {:?}: no series to draw",
            p.title
        )));
    }
    for s in p.series {
        if s.x.len() != s.y.len() {
            return Err(Error::Invalid(format!(
                "chart {:?}: series {:?} has {} x values and {} y values",
                p.title,
                s.label,
                s.x.len(),
                s.y.len()
            )));
        }
        if s.x.is_empty() {
            return Err(Error::Invalid(format!(
                "chart {:?}: series {:?} has no points",
                p.title, s.label
            )));
        }
        for (i, (x, y)) in s.x.iter().zip(&s.y).enumerate() {
            if !x.is_finite() || !y.is_finite() {
                return Err(Error::Invalid(format!(
                    "chart {:?}: series {:?} sample {i} is ({x}, {y}); every value must be finite",
                    p.title, s.label
                )));
            }
        }
    }
    Ok(())
}

/// `[lo, hi]` widened by `frac` of its span on both sides; a zero span is widened around the
/// value by 10 % of its magnitude (at least 1).
fn padded(lo: f64, hi: f64, frac: f64) -> Result<(f64, f64), Error> {
    let span = hi - lo;
    let (a, b) = if span > 0.0 {
        (lo - frac * span, hi + frac * span)
    } else {
        let d = (0.1 * lo.abs()).max(1.0);
        (lo - d, hi + d)
    };
    if a.is_finite() && b.is_finite() && b > a {
        Ok((a, b))
    } else {
        Err(Error::Invalid(format!(
            "chart: values spanning [{lo}, {hi}] are too large to plot"
        )))
    }
}

fn plot_err<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> Error {
    Error::Invalid(format!("drawing the chart failed: {e}"))
}

/// Index of the first minimum and of the first maximum of `y` (finite) among the samples
/// `keep` keeps; `None` when it keeps none.
fn arg_min_max(y: &[f64], keep: impl Fn(usize) -> bool) -> Option<(usize, usize)> {
    let mut kept = (0..y.len()).filter(|&i| keep(i));
    let first = kept.next()?;
    let (mut imin, mut imax) = (first, first);
    for i in kept {
        if y[i] < y[imin] {
            imin = i;
        }
        if y[i] > y[imax] {
            imax = i;
        }
    }
    Some((imin, imax))
}

/// Whether `x` lies in one of the `spans` `[from, to]`.
fn in_spans(spans: &[(f64, f64)], x: f64) -> bool {
    spans.iter().any(|&(a, b)| (a..=b).contains(&x))
}

/// Draws one validated panel into `area`.
fn draw_panel<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, p: &Panel<'_>) -> Result<(), Error>
where
    DB::ErrorType: 'static,
{
    // extent: all curves, widened so the markers' labels fit inside
    let fold = |f: fn(&Series) -> &Vec<f64>, init: f64, g: fn(f64, f64) -> f64| {
        p.series
            .iter()
            .flat_map(|s| f(s).iter().copied())
            .fold(init, g)
    };
    let (x0, x1) = padded(
        fold(|s| &s.x, f64::INFINITY, f64::min),
        fold(|s| &s.x, f64::NEG_INFINITY, f64::max),
        0.02,
    )?;
    // room above and below the curves for the stacked min / max labels (one line a curve)
    let label_pad = 0.08 + 0.05 * p.series.len().min(4) as f64;
    let (y0, y1) = padded(
        fold(|s| &s.y, f64::INFINITY, f64::min),
        fold(|s| &s.y, f64::NEG_INFINITY, f64::max),
        if p.mark_min_max { label_pad } else { 0.05 },
    )?;

    // the legend has a strip of its own right of the plot, so it never covers a curve or a label
    let legend_chars = p
        .series
        .iter()
        .map(|s| s.label.chars().count())
        .chain((!p.shaded.is_empty()).then(|| p.shaded_label.chars().count()))
        .max()
        .unwrap_or(0);
    // at most a quarter of the width: longer labels are shortened with an ellipsis
    let glyph = LEGEND_FONT as f64 * 0.6;
    let max_chars = ((area.dim_in_pixel().0 as f64 / 4.0 - 40.0) / glyph).max(4.0) as usize;
    let legend_chars = legend_chars.min(max_chars);
    let legend_w = 40 + (glyph * legend_chars as f64).ceil() as u32;

    // axes, grid and axis titles
    let mut chart = ChartBuilder::on(area)
        .caption(p.title, (FONT, 22))
        .margin(12)
        .margin_right(12 + legend_w)
        .x_label_area_size(48)
        .y_label_area_size(80)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(plot_err)?;
    chart
        .configure_mesh()
        .x_desc(p.x_label)
        .y_desc(p.y_label)
        .label_style((FONT, 14))
        .axis_desc_style((FONT, 16))
        .light_line_style(RGBColor(0xEE, 0xEE, 0xEE))
        .draw()
        .map_err(plot_err)?;

    // the spans not quoted, light grey under the curves
    for &(a, b) in p.shaded {
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(a.max(x0), y0), (b.min(x1), y1)],
                SHADE.filled(),
            )))
            .map_err(plot_err)?;
    }

    // curves, long ones reduced to what the pixels can show
    let columns = chart.plotting_area().dim_in_pixel().0 as usize;
    for (k, s) in p.series.iter().enumerate() {
        let color = PALETTE[k % PALETTE.len()];
        let keep = decimate_m4(&s.x, &s.y, x0, x1, columns);
        chart
            .draw_series(LineSeries::new(
                keep.iter().map(|&i| (s.x[i], s.y[i])),
                color.stroke_width(2),
            ))
            .map_err(plot_err)?;
    }

    // min / max markers: a dot on the sample and its value and abscissa beside it, each label
    // at the nearest place inside the plot, away from its curve first (up for a maximum, down
    // for a minimum), where it overlaps no label placed before it
    if p.mark_min_max {
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        let (px, py) = (xr.start as f64, yr.start as f64);
        let (pw, ph) = ((xr.end - xr.start) as f64, (yr.end - yr.start) as f64);
        let mut placed: Vec<[f64; 4]> = vec![];
        for (k, s) in p.series.iter().enumerate() {
            let color = PALETTE[k % PALETTE.len()];
            let Some((imin, imax)) = arg_min_max(&s.y, |i| !in_spans(p.shaded, s.x[i])) else {
                continue;
            };
            for (what, i, up) in [("max", imax, true), ("min", imin, false)] {
                let text = format!("{what} {} @ {}", fmt_value(s.y[i]), fmt_value(s.x[i]));
                let (dot_x, dot_y) = chart.backend_coord(&(s.x[i], s.y[i]));
                let (dot_x, dot_y) = (dot_x as f64, dot_y as f64);
                let style = TextStyle::from((FONT, MARK_FONT).into_font())
                    .color(&color)
                    .pos(Pos::new(HPos::Left, VPos::Top));
                // a box that holds the text in any face a viewer substitutes: 0.6 em a glyph at
                // the nominal size (the SVG draws it smaller, the substitutes are wider)
                let w = MARK_FONT as f64 * 0.6 * text.chars().count() as f64;
                let h = MARK_FONT as f64 + 2.0;
                // beside the dot, extending into the plot (leftwards in its right quarter)
                let left = if dot_x > px + 0.75 * pw {
                    dot_x - 6.0 - w
                } else {
                    dot_x + 6.0
                };
                // candidates: away from the curve first (up for a maximum, down for a
                // minimum), then towards it, every one inside the plot; the first free one
                let start = if up { dot_y - 6.0 - h } else { dot_y + 6.0 };
                let away = if up { -h } else { h };
                let inside = |t: f64| t >= py && t + h <= py + ph;
                let free = |t: f64| {
                    !placed
                        .iter()
                        .any(|q| overlaps(q, &[left, t, left + w, t + h]))
                };
                let n = (ph / h) as i32 + 1;
                let top = (0..n)
                    .map(|k| start + away * k as f64)
                    .chain((1..n).map(|k| start - away * k as f64))
                    .find(|&t| inside(t) && free(t))
                    .unwrap_or_else(|| start.clamp(py, (py + ph - h).max(py)));
                placed.push([left, top, left + w, top + h]);
                let (dx, dy) = ((left - dot_x).round() as i32, (top - dot_y).round() as i32);
                chart
                    .draw_series(std::iter::once(
                        EmptyElement::at((s.x[i], s.y[i]))
                            + Circle::new((0, 0), 4, color.filled())
                            // a light backing, so that curves crossing the label do not hide it
                            + Rectangle::new(
                                [(dx - 1, dy - 1), (dx + w.ceil() as i32 + 1, dy + h as i32)],
                                WHITE.mix(0.75).filled(),
                            )
                            + Text::new(text, (dx, dy), style),
                    ))
                    .map_err(plot_err)?;
            }
        }
    }

    // the legend, in its strip: a line of the curve's colour and its label
    let (area_w, _) = area.dim_in_pixel();
    let lx = (area_w - legend_w) as i32;
    for (k, s) in p.series.iter().enumerate() {
        let color = PALETTE[k % PALETTE.len()];
        let y = 48 + 20 * k as i32;
        area.draw(&PathElement::new(
            vec![(lx, y), (lx + 22, y)],
            color.stroke_width(2),
        ))
        .map_err(plot_err)?;
        let style = TextStyle::from((FONT, LEGEND_FONT).into_font())
            .color(&BLACK)
            .pos(Pos::new(HPos::Left, VPos::Center));
        let label: String = if s.label.chars().count() > legend_chars {
            let mut t: String = s.label.chars().take(legend_chars - 1).collect();
            t.push('…');
            t
        } else {
            s.label.clone()
        };
        area.draw(&Text::new(label, (lx + 30, y), style))
            .map_err(plot_err)?;
    }
    if !p.shaded.is_empty() {
        let y = 48 + 20 * p.series.len() as i32;
        area.draw(&Rectangle::new(
            [(lx, y - 6), (lx + 22, y + 6)],
            SHADE.filled(),
        ))
        .map_err(plot_err)?;
        let style = TextStyle::from((FONT, LEGEND_FONT).into_font())
            .color(&BLACK)
            .pos(Pos::new(HPos::Left, VPos::Center));
        let label: String = p.shaded_label.chars().take(legend_chars).collect();
        area.draw(&Text::new(label, (lx + 30, y), style))
            .map_err(plot_err)?;
    }
    Ok(())
}

/// The shading of spans left out of the quoted figures.
const SHADE: RGBColor = RGBColor(0xDD, 0xDD, 0xDD);

/// True when the boxes `[left, top, right, bottom]` (pixels) overlap.
fn overlaps(a: &[f64; 4], b: &[f64; 4]) -> bool {
    a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]
}

/// Font sizes (px) of the min / max labels and of the legend.
const MARK_FONT: u32 = 13;
const LEGEND_FONT: u32 = 14;

/// Draws `t` as a grid of left-aligned text cells in `area`.
fn draw_table<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, t: &Table) -> Result<(), Error>
where
    DB::ErrorType: 'static,
{
    let ncols = t
        .rows
        .iter()
        .map(Vec::len)
        .chain(std::iter::once(t.header.len()))
        .max()
        .unwrap_or(0)
        .max(1);
    let left = 90;
    let col_w = (WIDTH as i32 - left - 20) / ncols as i32;
    let lines = std::iter::once((&t.header, true)).chain(t.rows.iter().map(|r| (r, false)));
    for (row, (cells, is_header)) in lines.enumerate() {
        let y = TABLE_LINE as i32 * (row as i32 + 1);
        let color = if is_header {
            BLACK
        } else {
            RGBColor(0x33, 0x33, 0x33)
        };
        for (c, cell) in cells.iter().enumerate() {
            let style = TextStyle::from((MONO, 14).into_font()).color(&color);
            area.draw(&Text::new(
                cell.as_str(),
                (left + c as i32 * col_w, y),
                style,
            ))
            .map_err(plot_err)?;
        }
    }
    Ok(())
}
