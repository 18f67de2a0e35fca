//! A chart panel's legend, in a strip of its own right of the plot: one entry per curve (a
//! line of its colour, dashed past the palette), per labelled reference band and for the
//! shading; a prefix all curve names share heads it once.

use super::chart::{
    Band, FONT, LEGEND_FONT, Panel, REFERENCE, SHADE, WIDTH, elide_keeping_tail, plot_err,
    series_style,
};
use crate::error::Error;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// The legend's lines: each series' label without the prefix all of them share (a rig's
/// `mixamorig:`), which heads the legend instead, each at most a quarter of the chart's width
/// (elided in the middle, keeping the end that tells `…UpLeg.Xrotation` from
/// `…UpLeg.Zrotation`), and the shading's entry.
pub(crate) fn legend_entries(p: &Panel<'_>) -> Vec<String> {
    let names: Vec<&str> = p.series.iter().map(|s| s.label.as_str()).collect();
    let prefix = common_prefix(&names);
    let max_chars = ((WIDTH as f64 / 4.0 - 40.0) / (LEGEND_FONT as f64 * 0.6)) as usize;
    let fit = |s: &str| elide_keeping_tail(s, max_chars);
    let mut out: Vec<String> = vec![];
    if !prefix.is_empty() {
        // the shared prefix reads from its start
        let head: String = prefix.chars().take(max_chars.saturating_sub(1)).collect();
        out.push(format!("{head}…"));
    }
    out.extend(names.iter().map(|n| fit(&n[prefix.len()..])));
    out.extend(reference_bands(p).map(|b| fit(&b.label)));
    if !p.shaded.is_empty() {
        out.push(fit(p.shaded_label));
    }
    out
}

/// The bands with a legend entry: reference ranges with a label.
fn reference_bands<'a>(p: &'a Panel<'_>) -> impl Iterator<Item = &'a Band> {
    p.bands
        .iter()
        .filter(|b| b.color.is_none() && !b.label.is_empty())
}

/// The longest prefix shared by all of `names` (two or more) that ends in a separator (`:`,
/// `_`, `.`, `|`, `/`) and leaves every name something to show; "" when there is none.
pub fn common_prefix<'a>(names: &[&'a str]) -> &'a str {
    let [first, rest @ ..] = names else {
        return "";
    };
    if rest.is_empty() {
        return "";
    }
    let mut end = 0;
    for (i, c) in first.char_indices() {
        let len = i + c.len_utf8();
        let shared = rest
            .iter()
            .all(|n| n.len() > len && n.as_bytes()[..len] == first.as_bytes()[..len]);
        if len >= first.len() || !shared {
            break;
        }
        if matches!(c, ':' | '_' | '.' | '|' | '/') {
            end = len;
        }
    }
    &first[..end]
}

/// The legend, in its strip right of the plot: a line of each curve's colour and its entry.
pub(crate) fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    p: &Panel<'_>,
    legend: &[String],
    legend_w: u32,
) -> Result<(), Error>
where
    DB::ErrorType: 'static,
{
    let (area_w, _) = area.dim_in_pixel();
    let lx = (area_w - legend_w) as i32;
    let style = TextStyle::from((FONT, LEGEND_FONT).into_font())
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    let references: Vec<&Band> = reference_bands(p).collect();
    let headed =
        legend.len() > p.series.len() + references.len() + usize::from(!p.shaded.is_empty());
    let mut y = 48;
    let mut lines = legend.iter();
    if headed && let Some(head) = lines.next() {
        area.draw(&Text::new(head.as_str(), (lx, y), style.clone()))
            .map_err(plot_err)?;
        y += 20;
    }
    for (k, line) in lines.enumerate() {
        if k < p.series.len() {
            let (color, dashed) = series_style(k);
            let stroke = color.stroke_width(2);
            if dashed {
                for (a, b) in [(0, 8), (13, 22)] {
                    area.draw(&PathElement::new(vec![(lx + a, y), (lx + b, y)], stroke))
                        .map_err(plot_err)?;
                }
            } else {
                area.draw(&PathElement::new(vec![(lx, y), (lx + 22, y)], stroke))
                    .map_err(plot_err)?;
            }
        } else {
            let fill = if k < p.series.len() + references.len() {
                REFERENCE.mix(0.35).filled()
            } else {
                SHADE.filled()
            };
            area.draw(&Rectangle::new([(lx, y - 6), (lx + 22, y + 6)], fill))
                .map_err(plot_err)?;
        }
        area.draw(&Text::new(line.as_str(), (lx + 30, y), style.clone()))
            .map_err(plot_err)?;
        y += 20;
    }
    Ok(())
}
