//! Joint-space motion: BVH channels → q (take), continuity (unwrap), smoothing, derivatives,
//! C² ramps and blending/warping of takes, a helper root folded (fold) and bone translations
//! welded (weld), twist helpers inside a long bone folded into the next joint (twist).

pub mod blend;
pub mod contact;
pub mod derive;
pub mod euler;
pub mod fold;
pub mod ramp;
pub mod smooth;
pub mod spline;
pub mod take;
pub mod trim;
pub mod twist;
pub mod unwrap;
pub mod weld;

/// The maximal runs of frames `0..n` where `holds` is true, in order (half-open ranges): the
/// flights, double supports and unloaded stretches the ground reactions look for, and the
/// runs the consistency report names.
pub fn runs(n: usize, holds: impl Fn(usize) -> bool) -> Vec<std::ops::Range<usize>> {
    let mut out = vec![];
    let mut k = 0;
    while k < n {
        if !holds(k) {
            k += 1;
            continue;
        }
        let first = k;
        while k < n && holds(k) {
            k += 1;
        }
        out.push(first..k);
    }
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn runs_are_the_maximal_stretches_where_a_frame_holds() {
        let f = [true, true, false, true, false, false, true];
        assert_eq!(super::runs(f.len(), |k| f[k]), vec![0..2, 3..4, 6..7]);
        assert_eq!(super::runs(3, |_| false), vec![]);
        assert_eq!(super::runs(3, |_| true), vec![0..3]);
        assert_eq!(super::runs(0, |_| true), vec![]);
    }
}
