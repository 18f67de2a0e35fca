//! Where a chart's value labels go, and which values are worth a label: pure geometry in the
//! backend's pixels (y down), so the chart's drawing code only asks and draws.
//!
//! - A label is a box `[left, top, right, bottom]`. It is placed at the nearest candidate
//!   position beside its marker (away from its curve first) that lies inside the plot and
//!   overlaps no label placed before it, no marker dot and no segment of any curve (each
//!   segment thickened by its stroke). When no candidate is free the label is left out
//!   (thinned): a marker with no label is better than a label over data.
//! - A panel's *resolution* is the smallest value its labels quote as non-zero:
//!   [`RESOLUTION_ABS`] or [`RESOLUTION_REL`] of the panel's largest |y|, whichever is larger.
//!   Below it a value is numerical noise (`-9.872e-21` of a curve that should be 0) and prints
//!   as 0; a curve whose whole range lies below it is *idle* (flat) and gets no min/max labels.

/// Smallest magnitude (in the panel's SI unit: N·m, rad, W, …) a label quotes as non-zero.
pub const RESOLUTION_ABS: f64 = 1e-9;
/// Fraction of the panel's largest |y| below which a value is noise (double precision rounding
/// of sums of terms of that size leaves ~1e-16 of it; 1e-9 leaves room for integration error).
pub const RESOLUTION_REL: f64 = 1e-9;

/// The resolution of a panel whose values are `ys` (see the module documentation).
pub fn resolution<'a>(ys: impl IntoIterator<Item = &'a [f64]>) -> f64 {
    let largest = ys
        .into_iter()
        .flat_map(|y| y.iter())
        .fold(0.0f64, |m, v| m.max(v.abs()));
    RESOLUTION_ABS.max(RESOLUTION_REL * largest)
}

/// `v`, or 0 when it lies below the resolution `res`.
pub fn denoise(v: f64, res: f64) -> f64 {
    if v.abs() < res { 0.0 } else { v }
}

/// Whether a curve with this range is idle (flat within the resolution).
pub fn idle(lo: f64, hi: f64, res: f64) -> bool {
    hi - lo <= res
}

/// True when the boxes `[left, top, right, bottom]` overlap.
/// The width (px) a text takes at `size` px in any face a viewer substitutes: 0.6 em a glyph
/// (Hack's advance, at least as wide as the common sans-serif faces). The label placer's and
/// the table's measure.
pub fn text_width(text: &str, size: f64) -> f64 {
    size * 0.6 * text.chars().count() as f64
}

pub fn overlaps(a: &[f64; 4], b: &[f64; 4]) -> bool {
    a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]
}

/// Whether the segment `p`–`q` meets the box `b` (Liang–Barsky clipping).
pub fn segment_hits_box(p: (f64, f64), q: (f64, f64), b: &[f64; 4]) -> bool {
    let (dx, dy) = (q.0 - p.0, q.1 - p.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (den, num) in [
        (-dx, p.0 - b[0]),
        (dx, b[2] - p.0),
        (-dy, p.1 - b[1]),
        (dy, b[3] - p.1),
    ] {
        if den == 0.0 {
            if num < 0.0 {
                return false;
            }
        } else {
            let t = num / den;
            if den < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
            if t0 > t1 {
                return false;
            }
        }
    }
    true
}

/// Places label boxes in a plot among curves and marker dots.
#[derive(Debug, Default)]
pub struct Placer {
    /// The plot `[left, top, right, bottom]` (px).
    plot: [f64; 4],
    /// Every curve as its drawn polyline (px).
    curves: Vec<Vec<(f64, f64)>>,
    /// Boxes no label may overlap: labels placed so far and the marker dots.
    taken: Vec<[f64; 4]>,
}

/// Clearance (px) kept between a label and a curve's centre line (the stroke is 2 px wide).
const CLEAR: f64 = 2.5;
/// Radius (px) of a marker dot.
pub const DOT: f64 = 4.0;

impl Placer {
    pub fn new(plot: [f64; 4], curves: Vec<Vec<(f64, f64)>>, dots: &[(f64, f64)]) -> Self {
        let taken = dots
            .iter()
            .map(|&(x, y)| [x - DOT, y - DOT, x + DOT, y + DOT])
            .collect();
        Self {
            plot,
            curves,
            taken,
        }
    }

    /// Whether the box `b` is inside the plot and clear of curves, dots and labels.
    fn free(&self, b: &[f64; 4]) -> bool {
        let p = &self.plot;
        if b[0] < p[0] || b[1] < p[1] || b[2] > p[2] || b[3] > p[3] {
            return false;
        }
        if self.taken.iter().any(|t| overlaps(t, b)) {
            return false;
        }
        let wide = [b[0] - CLEAR, b[1] - CLEAR, b[2] + CLEAR, b[3] + CLEAR];
        !self.curves.iter().any(|c| {
            c.windows(2).any(|s| {
                let (lo_x, hi_x) = (s[0].0.min(s[1].0), s[0].0.max(s[1].0));
                hi_x >= wide[0] && lo_x <= wide[2] && segment_hits_box(s[0], s[1], &wide)
            })
        })
    }

    /// A free box `w` × `h` near the marker at `dot`: beside it, above for a maximum (`up`) and
    /// below for a minimum first, then further away, then on the other side; `None` when the
    /// plot has no free place for it. The box returned is taken.
    pub fn place(&mut self, dot: (f64, f64), w: f64, h: f64, up: bool) -> Option<[f64; 4]> {
        let (x, y) = dot;
        let lefts = [x + DOT + 2.0, x - DOT - 2.0 - w, x - w / 2.0];
        let start = if up { y - DOT - 2.0 - h } else { y + DOT + 2.0 };
        let step = if up { -h / 2.0 } else { h / 2.0 };
        let n = ((self.plot[3] - self.plot[1]) / (h / 2.0)) as i32 + 1;
        let tops = (0..n)
            .map(|k| start + step * k as f64)
            .chain((1..2 * n).map(|k| start - step * k as f64));
        for top in tops {
            for left in lefts {
                let b = [left, top, left + w, top + h];
                if self.free(&b) {
                    self.taken.push(b);
                    return Some(b);
                }
            }
        }
        None
    }
}
