//! C² ramps for blending windows.
//!
//! A blend `θr = θa(1 − λ) + θb λ` inherits the smoothness of λ: with a linear (C⁰) ramp the
//! blended velocity jumps at the window edges and the acceleration has Dirac spikes there, which
//! inverse dynamics turns into torque spikes. The quintic `λ(s) = 6s⁵ − 15s⁴ + 10s³` has zero
//! first and second derivatives at both ends, so the blend stays C² when the inputs are. It is
//! the minimum-jerk profile of Flash & Hogan (1985, *J. Neurosci.* 5(7), eq. 3 with zero end
//! velocity and acceleration), called "smootherstep" by Perlin (2002, *Improving Noise*).

/// The shape of a blending ramp `λ(s)`, `s ∈ [0, 1]` the normalised time in the window.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RampShape {
    /// `λ = s`: C⁰ only (its derivative jumps at the edges). Kept for comparison.
    Linear,
    /// `λ = 6s⁵ − 15s⁴ + 10s³`: C² (see [`smoothstep5`]).
    #[default]
    Quintic,
}

impl RampShape {
    /// `λ(s)`, with `s` clamped to `[0, 1]`.
    pub fn value(self, s: f64) -> f64 {
        match self {
            RampShape::Linear => s.clamp(0.0, 1.0),
            RampShape::Quintic => smoothstep5(s),
        }
    }
    /// `dλ/ds` (zero outside `[0, 1]`).
    pub fn d1(self, s: f64) -> f64 {
        match self {
            RampShape::Linear if (0.0..=1.0).contains(&s) => 1.0,
            RampShape::Linear => 0.0,
            RampShape::Quintic => smoothstep5_d1(s),
        }
    }
}

/// `λ(s) = 6s⁵ − 15s⁴ + 10s³` for `s ∈ [0, 1]`, 0 below and 1 above: λ(0) = 0, λ(1) = 1, and
/// λ', λ'' vanish at both ends (C² everywhere).
#[inline]
pub fn smoothstep5(s: f64) -> f64 {
    let s = s.clamp(0.0, 1.0);
    s * s * s * (s * (6.0 * s - 15.0) + 10.0)
}

/// `dλ/ds = 30s⁴ − 60s³ + 30s² = 30 s² (1 − s)²` (zero outside `[0, 1]`).
#[inline]
pub fn smoothstep5_d1(s: f64) -> f64 {
    if !(0.0..=1.0).contains(&s) {
        return 0.0;
    }
    let u = s * (1.0 - s);
    30.0 * u * u
}

/// `d²λ/ds² = 120s³ − 180s² + 60s = 60 s (1 − s)(1 − 2s)` (zero outside `[0, 1]`).
#[inline]
pub fn smoothstep5_d2(s: f64) -> f64 {
    if !(0.0..=1.0).contains(&s) {
        return 0.0;
    }
    60.0 * s * (1.0 - s) * (1.0 - 2.0 * s)
}

/// `d³λ/ds³ = 360s² − 360s + 60` inside `[0, 1]` (it jumps at the ends: λ is C² but not C³).
#[inline]
pub fn smoothstep5_d3(s: f64) -> f64 {
    if !(0.0..=1.0).contains(&s) {
        return 0.0;
    }
    360.0 * s * s - 360.0 * s + 60.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn end_values_and_derivatives() {
        assert_eq!(smoothstep5(0.0), 0.0);
        assert_eq!(smoothstep5(1.0), 1.0);
        assert_eq!(smoothstep5(0.5), 0.5);
        assert_eq!(smoothstep5(-1.0), 0.0);
        assert_eq!(smoothstep5(2.0), 1.0);
        for s in [0.0, 1.0] {
            assert!(smoothstep5_d1(s).abs() < 1e-15);
            assert!(smoothstep5_d2(s).abs() < 1e-15);
        }
        assert!((smoothstep5_d1(0.5) - 1.875).abs() < 1e-15);
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let h = 1e-6;
        for k in 1..20 {
            let s = k as f64 / 20.0;
            let fd1 = (smoothstep5(s + h) - smoothstep5(s - h)) / (2.0 * h);
            let fd2 = (smoothstep5_d1(s + h) - smoothstep5_d1(s - h)) / (2.0 * h);
            let fd3 = (smoothstep5_d2(s + h) - smoothstep5_d2(s - h)) / (2.0 * h);
            assert!((fd1 - smoothstep5_d1(s)).abs() < 1e-8, "d1 at {s}");
            assert!((fd2 - smoothstep5_d2(s)).abs() < 1e-7, "d2 at {s}");
            assert!((fd3 - smoothstep5_d3(s)).abs() < 1e-6, "d3 at {s}");
        }
    }

    #[test]
    fn monotone() {
        let mut prev = 0.0;
        for k in 1..=100 {
            let v = smoothstep5(k as f64 / 100.0);
            assert!(v > prev);
            prev = v;
        }
    }
}
