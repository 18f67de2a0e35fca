//! A chart's caption (the context of the figure: take, body, model, settings, version),
//! wrapped to the chart's width, and the PNG encoding of a drawn bitmap.

use super::chart::WIDTH;
use crate::error::Error;

/// A chart's caption: its context `parts` (`("take", "walk.bvh")`, `("body", "80 kg")`, …)
/// as `take walk.bvh · body 80 kg · … · articula 0.1.0`, so a figure pasted into a report
/// still says what it was computed from and by which version.
pub fn caption(parts: &[(&str, String)]) -> String {
    let mut out: Vec<String> = parts
        .iter()
        .filter(|(_, v)| !v.is_empty())
        .map(|(k, v)| format!("{k} {v}"))
        .collect();
    out.push(format!("articula {}", env!("CARGO_PKG_VERSION")));
    out.join(" · ")
}

/// Height (px) of a caption line and its font size.
pub(crate) const CAPTION_LINE: u32 = 18;
pub(crate) const CAPTION_FONT: u32 = 12;

/// The caption as lines that fit the width (0.6 em a glyph), broken after its ` · ` separators
/// (a part longer than a line is elided in the middle).
pub(crate) fn wrap_caption(caption: &str) -> Vec<String> {
    let max = ((WIDTH as f64 - 24.0) / (0.6 * CAPTION_FONT as f64)) as usize;
    let mut lines: Vec<String> = vec![];
    let mut line = String::new();
    for part in caption.split(" · ").map(|p| elide_middle(p.trim(), max)) {
        let extra = if line.is_empty() { 0 } else { 3 };
        if !line.is_empty() && line.chars().count() + extra + part.chars().count() > max {
            lines.push(std::mem::take(&mut line));
        }
        if !line.is_empty() {
            line.push_str(" · ");
        }
        line.push_str(&part);
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

/// `s` shortened to `max` characters by an ellipsis in its middle (both ends stay readable).
pub fn elide_middle(s: &str, max: usize) -> String {
    let n = s.chars().count();
    if n <= max || max < 3 {
        return s.to_string();
    }
    let head = (max - 1) / 2;
    let tail = max - 1 - head;
    let mut out: String = s.chars().take(head).collect();
    out.push('…');
    out.extend(s.chars().skip(n - tail));
    out
}

/// An RGB buffer as PNG bytes.
pub(crate) fn encode_png(rgb: &[u8], width: u32, height: u32) -> Result<Vec<u8>, Error> {
    let fail = |e: png::EncodingError| Error::Invalid(format!("chart: PNG encoding failed: {e}"));
    let mut out = vec![];
    {
        let mut enc = png::Encoder::new(&mut out, width, height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut w = enc.write_header().map_err(fail)?;
        w.write_image_data(rgb).map_err(fail)?;
        w.finish().map_err(fail)?;
    }
    Ok(out)
}
