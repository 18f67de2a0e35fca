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
use crate::report::caption::{CAPTION_FONT, CAPTION_LINE, encode_png, wrap_caption};
pub use crate::report::caption::{caption, elide_middle};
use crate::report::labels;
pub use crate::report::legend::common_prefix;
use crate::report::legend::{draw_legend, legend_entries};
use plotters::coord::Shift;
use plotters::coord::types::RangedCoordf64;
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
    /// Drawn as dots (marked samples, e.g. frames beyond a motor's envelope), not as a line.
    pub dots: bool,
}

impl Series {
    pub fn new(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self {
            label: label.into(),
            x,
            y,
            dots: false,
        }
    }

    /// Samples drawn as dots.
    pub fn dots(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>) -> Self {
        Self {
            dots: true,
            ..Self::new(label, x, y)
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
    /// Filled bands drawn under the curves (a mean ± SD, a normative range); none: `&[]`.
    pub bands: &'a [Band],
}

/// A filled band between `lo[i]` and `hi[i]` at `x[i]` (same length, finite), drawn under the
/// curves: translucent in the colour of series `color`, or grey (a reference range) for `None`,
/// which also gets a legend entry `label` when it is not empty.
#[derive(Debug, Clone, PartialEq)]
pub struct Band {
    pub label: String,
    pub x: Vec<f64>,
    pub lo: Vec<f64>,
    pub hi: Vec<f64>,
    pub color: Option<usize>,
}

/// The fill of a reference band.
pub(crate) const REFERENCE: RGBColor = RGBColor(0x70, 0x70, 0x70);

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

/// Colour-blind-aware categorical palette, cycled over the series: Okabe & Ito's (2008, "Color
/// Universal Design") seven colours without its yellow (too light on white) plus black, then
/// four of Paul Tol's "muted" scheme (2021, "Colour schemes", SRON/EPS/TN/09-002) that stay
/// apart from them; twelve curves never share a colour. A thirteenth and later series take the
/// colours again, drawn dashed ([`series_style`]).
pub const PALETTE: [RGBColor; 12] = [
    RGBColor(0x00, 0x72, 0xB2), // blue
    RGBColor(0xE6, 0x9F, 0x00), // orange
    RGBColor(0x00, 0x9E, 0x73), // bluish green
    RGBColor(0xD5, 0x5E, 0x00), // vermillion
    RGBColor(0xCC, 0x79, 0xA7), // reddish purple
    RGBColor(0x56, 0xB4, 0xE9), // sky blue
    RGBColor(0x00, 0x00, 0x00), // black
    RGBColor(0x88, 0x22, 0x55), // wine
    RGBColor(0x99, 0x99, 0x33), // olive
    RGBColor(0x33, 0x22, 0x88), // indigo
    RGBColor(0x44, 0xAA, 0x99), // teal
    RGBColor(0xAA, 0x44, 0x99), // purple
];

/// The colour of series `k` and whether it is drawn dashed (past the palette's length).
pub fn series_style(k: usize) -> (RGBColor, bool) {
    (PALETTE[k % PALETTE.len()], k >= PALETTE.len())
}

pub(crate) const FONT: &str = "sans-serif";
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
            bands: &[],
        }],
        None,
    )
}

/// Panels stacked top to bottom, all [`WIDTH`] wide, optionally followed by a text table.
pub fn stacked_svg(panels: &[Panel<'_>], table: Option<&Table>) -> Result<String, Error> {
    let bytes = stacked_chart(panels, table, None, ImageFormat::Svg)?;
    String::from_utf8(bytes).map_err(|e| Error::Invalid(format!("chart: SVG is not UTF-8: {e}")))
}

/// The image formats a chart is written in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    /// Scalable vector graphics (text as `<text>`, the embedded font's family names).
    Svg,
    /// A PNG bitmap of the same layout, one pixel per SVG unit, text drawn with the embedded font.
    Png,
}

/// Each image format and the file extension that selects it.
const FORMATS: [(&str, ImageFormat); 2] = [("svg", ImageFormat::Svg), ("png", ImageFormat::Png)];

impl ImageFormat {
    /// The format a path's extension names (`.svg`, `.png`, any case); `None` for others.
    pub fn of_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?;
        FORMATS
            .iter()
            .find(|(e, _)| e.eq_ignore_ascii_case(ext))
            .map(|&(_, f)| f)
    }

    /// The format named `svg` or `png`.
    pub fn from_name(name: &str) -> Option<Self> {
        FORMATS.iter().find(|(e, _)| *e == name).map(|&(_, f)| f)
    }
}

/// Panels stacked top to bottom, all [`WIDTH`] wide, optionally followed by a text table and by
/// a caption (the context of the figure: take, body, model, settings, version; wrapped at
/// `·`), as the bytes of an SVG or PNG file.
pub fn stacked_chart(
    panels: &[Panel<'_>],
    table: Option<&Table>,
    caption: Option<&str>,
    format: ImageFormat,
) -> Result<Vec<u8>, Error> {
    if panels.is_empty() {
        return Err(Error::Invalid("chart: no panel to draw".into()));
    }
    for p in panels {
        validate(p)?;
    }
    register_fonts()?;
    let caption_lines = caption.map(wrap_caption).unwrap_or_default();
    let table_h = table.map_or(0, |t| {
        (t.rows.len() as u32 + 1) * TABLE_LINE + 2 * TABLE_LINE
    });
    let caption_h = if caption_lines.is_empty() {
        0
    } else {
        caption_lines.len() as u32 * CAPTION_LINE + CAPTION_LINE / 2
    };
    let height = panels.len() as u32 * PANEL_HEIGHT + table_h + caption_h;
    let layout = Layout {
        panels,
        table,
        caption: &caption_lines,
        table_h,
    };
    match format {
        ImageFormat::Svg => {
            let mut svg = String::new();
            {
                let root = SVGBackend::with_string(&mut svg, (WIDTH, height)).into_drawing_area();
                draw_layout(&root, &layout)?;
            }
            Ok(svg.into_bytes())
        }
        ImageFormat::Png => {
            let mut rgb = vec![0u8; (WIDTH * height * 3) as usize];
            {
                let root =
                    BitMapBackend::with_buffer(&mut rgb, (WIDTH, height)).into_drawing_area();
                draw_layout(&root, &layout)?;
            }
            encode_png(&rgb, WIDTH, height)
        }
    }
}

/// What [`stacked_chart`] draws, top to bottom.
struct Layout<'a> {
    panels: &'a [Panel<'a>],
    table: Option<&'a Table>,
    caption: &'a [String],
    table_h: u32,
}

/// Draws the panels, the table and the caption on any plotters backend.
fn draw_layout<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    l: &Layout<'_>,
) -> Result<(), Error>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE).map_err(plot_err)?;
    let (charts, below) = root.split_vertically(l.panels.len() as u32 * PANEL_HEIGHT);
    let areas = charts.split_evenly((l.panels.len(), 1));
    for (p, area) in l.panels.iter().zip(&areas) {
        draw_panel(area, p)?;
    }
    let (table_area, caption_area) = below.split_vertically(l.table_h);
    if let Some(t) = l.table {
        draw_table(&table_area, t)?;
    }
    for (k, line) in l.caption.iter().enumerate() {
        let style = TextStyle::from((FONT, CAPTION_FONT).into_font())
            .color(&RGBColor(0x44, 0x44, 0x44))
            .pos(Pos::new(HPos::Left, VPos::Top));
        caption_area
            .draw(&Text::new(
                line.as_str(),
                (12, 4 + (k as u32 * CAPTION_LINE) as i32),
                style,
            ))
            .map_err(plot_err)?;
    }
    root.present().map_err(plot_err)
}

/// Writes a chart (SVG or PNG bytes of [`stacked_chart`]) to `path` atomically.
pub fn write_chart(path: &Path, bytes: &[u8]) -> Result<(), Error> {
    crate::io::write_atomic(path, bytes)
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
    for b in p.bands {
        let n = b.x.len();
        let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
        if b.lo.len() != n || b.hi.len() != n || !finite(&b.x) || !finite(&b.lo) || !finite(&b.hi) {
            return Err(Error::Invalid(format!(
                "chart {:?}: band {:?} needs as many finite lower and upper values as abscissae",
                p.title, b.label
            )));
        }
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

pub(crate) fn plot_err<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> Error {
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
    // below the panel's resolution a value is noise: it prints as 0, and a curve whose whole
    // range lies below it is idle (no min / max labels)
    let res = labels::resolution(p.series.iter().map(|s| s.y.as_slice()));
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
    let band_lo = p.bands.iter().flat_map(|b| b.lo.iter().copied());
    let band_hi = p.bands.iter().flat_map(|b| b.hi.iter().copied());
    let (ylo, yhi) = (
        band_lo.fold(fold(|s| &s.y, f64::INFINITY, f64::min), f64::min),
        band_hi.fold(fold(|s| &s.y, f64::NEG_INFINITY, f64::max), f64::max),
    );
    // noise alone spans no axis: a flat panel is drawn around its (denoised) value
    let (ylo, yhi) = if labels::idle(ylo, yhi, res) {
        let v = labels::denoise(0.5 * (ylo + yhi), res);
        (v, v)
    } else {
        (ylo, yhi)
    };
    // room above and below the curves for the min / max labels (one line a curve, up to four)
    let label_pad = 0.08 + 0.05 * p.series.len().min(4) as f64;
    let (y0, y1) = padded(ylo, yhi, if p.mark_min_max { label_pad } else { 0.05 })?;

    let legend = legend_entries(p);
    let glyph = LEGEND_FONT as f64 * 0.6;
    let legend_chars = legend.iter().map(|l| l.chars().count()).max().unwrap_or(0);
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

    // bands: reference ranges grey, a curve's spread in its colour, both translucent
    for b in p.bands {
        let fill = b
            .color
            .map_or(REFERENCE.mix(0.35), |k| series_style(k).0.mix(0.18));
        let outline: Vec<(f64, f64)> =
            b.x.iter()
                .zip(&b.hi)
                .map(|(x, y)| (*x, *y))
                .chain(b.x.iter().zip(&b.lo).rev().map(|(x, y)| (*x, *y)))
                .collect();
        chart
            .draw_series(std::iter::once(Polygon::new(outline, fill.filled())))
            .map_err(plot_err)?;
    }

    // curves, long ones reduced to what the pixels can show
    let columns = chart.plotting_area().dim_in_pixel().0 as usize;
    let mut drawn: Vec<Vec<(f64, f64)>> = Vec::with_capacity(p.series.len());
    for (k, s) in p.series.iter().enumerate() {
        let (color, dashed) = series_style(k);
        let keep = decimate_m4(&s.x, &s.y, x0, x1, columns);
        let points = keep.iter().map(|&i| (s.x[i], s.y[i]));
        if s.dots {
            chart
                .draw_series(points.map(|p| Circle::new(p, 3, color.filled())))
                .map_err(plot_err)?;
        } else if dashed {
            chart
                .draw_series(DashedLineSeries::new(points, 8, 5, color.stroke_width(2)))
                .map_err(plot_err)?;
        } else {
            chart
                .draw_series(LineSeries::new(points, color.stroke_width(2)))
                .map_err(plot_err)?;
        }
        drawn.push(
            keep.iter()
                .map(|&i| {
                    let (u, v) = chart.backend_coord(&(s.x[i], s.y[i]));
                    (u as f64, v as f64)
                })
                .collect(),
        );
    }
    if p.mark_min_max {
        mark_min_max(&chart, p, drawn, res)?;
    }
    draw_legend(area, p, &legend, legend_w)
}

/// The min / max markers of every curve that is not idle: a dot on the sample and its value
/// and abscissa beside it, wherever [`labels::Placer`] finds room clear of every curve, dot and
/// label (a label with no room is left out).
fn mark_min_max<DB: DrawingBackend>(
    chart: &ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    p: &Panel<'_>,
    drawn: Vec<Vec<(f64, f64)>>,
    res: f64,
) -> Result<(), Error>
where
    DB::ErrorType: 'static,
{
    let mut marks = vec![];
    for (k, s) in p.series.iter().enumerate() {
        let Some((imin, imax)) = arg_min_max(&s.y, |i| !in_spans(p.shaded, s.x[i])) else {
            continue;
        };
        if labels::idle(s.y[imin], s.y[imax], res) {
            continue;
        }
        for (what, i, up) in [("max", imax, true), ("min", imin, false)] {
            let text = format!(
                "{what} {} @ {}",
                fmt_value(labels::denoise(s.y[i], res)),
                fmt_value(s.x[i])
            );
            let (u, v) = chart.backend_coord(&(s.x[i], s.y[i]));
            marks.push((k, i, up, text, (u as f64, v as f64)));
        }
    }
    let (xr, yr) = chart.plotting_area().get_pixel_range();
    let plot = [xr.start, yr.start, xr.end, yr.end].map(f64::from);
    let dots: Vec<(f64, f64)> = marks.iter().map(|m| m.4).collect();
    let mut placer = labels::Placer::new(plot, drawn, &dots);
    for (k, i, up, text, dot) in marks {
        let s = &p.series[k];
        let (color, _) = series_style(k);
        chart
            .plotting_area()
            .draw(&Circle::new(
                (s.x[i], s.y[i]),
                labels::DOT as i32,
                color.filled(),
            ))
            .map_err(plot_err)?;
        // a box that holds the text in any face a viewer substitutes: 0.6 em a glyph at the
        // nominal size (the SVG draws it smaller, the substitutes are wider)
        let w = labels::text_width(&text, MARK_FONT as f64);
        let h = MARK_FONT as f64 + 2.0;
        let Some(b) = placer.place(dot, w, h, up) else {
            continue;
        };
        let style = TextStyle::from((FONT, MARK_FONT).into_font())
            .color(&color)
            .pos(Pos::new(HPos::Left, VPos::Top));
        let (dx, dy) = ((b[0] - dot.0).round() as i32, (b[1] - dot.1).round() as i32);
        chart
            .plotting_area()
            .draw(&(EmptyElement::at((s.x[i], s.y[i])) + Text::new(text, (dx, dy), style)))
            .map_err(plot_err)?;
    }
    Ok(())
}

/// The shading of spans left out of the quoted figures.
pub(crate) const SHADE: RGBColor = RGBColor(0xDD, 0xDD, 0xDD);

/// Font sizes (px) of the min / max labels and of the legend.
pub(crate) const MARK_FONT: u32 = 13;
pub(crate) const LEGEND_FONT: u32 = 14;

/// Font size (px) of the table under the panels.
const TABLE_FONT: u32 = 14;

/// The left edge (px) of each of the table's columns, and the characters a cell of each may
/// show: every column as wide as its widest cell ([`labels::text_width`]) plus a gap, so that
/// no cell runs into the next; when they do not fit the chart's width, the widest column
/// loses a character at a time (its cells then elided after their first characters,
/// [`elide_keeping_tail`]).
fn table_columns(t: &Table, left: f64, right: f64) -> (Vec<f64>, Vec<usize>) {
    let lines = || std::iter::once(&t.header).chain(&t.rows);
    let ncols = lines().map(Vec::len).max().unwrap_or(0);
    let mut chars: Vec<usize> = (0..ncols)
        .map(|c| {
            lines()
                .filter_map(|r| r.get(c))
                .map(|s| s.chars().count())
                .max()
                .unwrap_or(0)
        })
        .collect();
    let size = TABLE_FONT as f64;
    let glyph = labels::text_width("m", size);
    let gap = 1.5 * glyph;
    let total = |chars: &[usize]| {
        chars.iter().map(|&n| n as f64 * glyph).sum::<f64>()
            + gap * chars.len().saturating_sub(1) as f64
    };
    const NARROWEST: usize = 5;
    while total(&chars) > right - left {
        let Some((widest, n)) = chars.iter().copied().enumerate().max_by_key(|&(_, n)| n) else {
            break;
        };
        if n <= NARROWEST {
            break;
        }
        chars[widest] = n - 1;
    }
    let mut x = left;
    let starts = chars
        .iter()
        .map(|&n| {
            let at = x;
            x += n as f64 * glyph + gap;
            at
        })
        .collect();
    (starts, chars)
}

/// `s` in at most `room` characters (`room` ≥ 5): whole, or its first four characters, `…` and
/// as much of its end as fits: the end tells a table's rows apart
/// (`mixa…ftUpLeg.Xrotation`, `mixa…ftUpLeg.Yrotation`), a namespace prefix does not.
pub(crate) fn elide_keeping_tail(s: &str, room: usize) -> String {
    let n = s.chars().count();
    if n <= room || room < 5 {
        return s.to_string();
    }
    let head = 4.min((room - 1) / 2);
    let tail = room - 1 - head;
    let mut out: String = s.chars().take(head).collect();
    out.push('…');
    out.extend(s.chars().skip(n - tail));
    out
}

/// Draws `t` as a grid of left-aligned text cells in `area` ([`table_columns`]).
fn draw_table<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, t: &Table) -> Result<(), Error>
where
    DB::ErrorType: 'static,
{
    let (starts, room) = table_columns(t, 48.0, WIDTH as f64 - 20.0);
    let lines = std::iter::once((&t.header, true)).chain(t.rows.iter().map(|r| (r, false)));
    for (row, (cells, is_header)) in lines.enumerate() {
        let y = TABLE_LINE as i32 * (row as i32 + 1);
        let color = if is_header {
            BLACK
        } else {
            RGBColor(0x33, 0x33, 0x33)
        };
        for ((cell, x), &room) in cells.iter().zip(&starts).zip(&room) {
            let style = TextStyle::from((MONO, TABLE_FONT).into_font()).color(&color);
            let text = elide_keeping_tail(cell, room);
            area.draw(&Text::new(text.as_str(), (x.round() as i32, y), style))
                .map_err(plot_err)?;
        }
    }
    Ok(())
}
