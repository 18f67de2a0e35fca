//! Uniform cubic B-splines: a smooth (C²) low-frequency correction of a trajectory, given by a
//! few coefficients, whose values, first and second derivatives are linear in them (de Boor
//! 1978, *A Practical Guide to Splines*, ch. IX; the uniform basis in matrix form, Qin 2000,
//! "General matrix representations for B-splines", *The Visual Computer* 16, eq. 3).

/// A uniform cubic B-spline basis over `[t0, t1]` with knots every `spacing` seconds: basis
/// function `i` (of [`len`](Self::len)) is centred at `t0 + (i − 1)·spacing` and is non-zero
/// over four knot intervals, so each coefficient moves the curve over about `4·spacing`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UniformBSpline {
    /// Start of the interval (s).
    pub t0: f64,
    /// Knot spacing (s), > 0.
    pub spacing: f64,
    /// Number of knot intervals covering `[t0, t1]`.
    pub intervals: usize,
}

impl UniformBSpline {
    /// Knots every `spacing` (at most; the spacing shrinks so that they divide the interval
    /// evenly) over `[t0, t1]`; `None` if the interval or the spacing is not positive and finite.
    pub fn new(t0: f64, t1: f64, spacing: f64) -> Option<Self> {
        let span = t1 - t0;
        if !(span > 0.0 && span.is_finite() && spacing > 0.0 && spacing.is_finite()) {
            return None;
        }
        let intervals = (span / spacing).ceil().max(1.0) as usize;
        Some(Self {
            t0,
            spacing: span / intervals as f64,
            intervals,
        })
    }

    /// Number of basis functions (coefficients): intervals + 3.
    pub fn len(&self) -> usize {
        self.intervals + 3
    }

    /// Always false: a spline has at least four basis functions.
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The first of the four basis functions non-zero at `t`, and their values, first and
    /// second derivatives at `t` (per s, per s²): `B(u) = [(1−u)³, 3u³ − 6u² + 4,
    /// −3u³ + 3u² + 3u + 1, u³] / 6` with `u` the position within the knot interval.
    pub fn basis(&self, t: f64) -> (usize, [[f64; 4]; 3]) {
        let x = ((t - self.t0) / self.spacing).clamp(0.0, self.intervals as f64);
        let i = (x.floor() as usize).min(self.intervals - 1);
        let u = x - i as f64;
        let (u2, u3) = (u * u, u * u * u);
        let h = self.spacing;
        let value = [
            (1.0 - u).powi(3) / 6.0,
            (3.0 * u3 - 6.0 * u2 + 4.0) / 6.0,
            (-3.0 * u3 + 3.0 * u2 + 3.0 * u + 1.0) / 6.0,
            u3 / 6.0,
        ];
        let d1 = [
            -(1.0 - u).powi(2) / 2.0 / h,
            (3.0 * u2 - 4.0 * u) / 2.0 / h,
            (-3.0 * u2 + 2.0 * u + 1.0) / 2.0 / h,
            u2 / 2.0 / h,
        ];
        let h2 = h * h;
        let d2 = [
            (1.0 - u) / h2,
            (3.0 * u - 2.0) / h2,
            (-3.0 * u + 1.0) / h2,
            u / h2,
        ];
        (i, [value, d1, d2])
    }

    /// The curve's derivative `order` (0, 1, 2) at `t` for scalar coefficients `c`.
    pub fn eval(&self, c: &[f64], t: f64, order: usize) -> f64 {
        let (i, b) = self.basis(t);
        (0..4).map(|j| b[order][j] * c[i + j]).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_basis_is_a_partition_of_unity_and_its_derivatives_match_differences() {
        let s = UniformBSpline::new(0.3, 2.0, 0.25).unwrap();
        assert_eq!(s.len(), s.intervals + 3);
        let c: Vec<f64> = (0..s.len()).map(|i| (i as f64 * 0.7).sin()).collect();
        for k in 0..=170 {
            let t = 0.3 + 1.7 * k as f64 / 170.0;
            let (_, b) = s.basis(t);
            assert!((b[0].iter().sum::<f64>() - 1.0).abs() < 1e-12);
            assert!(b[1].iter().sum::<f64>().abs() < 1e-9);
            assert!(b[2].iter().sum::<f64>().abs() < 1e-9);
            let h = 1e-5;
            if t - h > 0.3 && t + h < 2.0 {
                let d1 = (s.eval(&c, t + h, 0) - s.eval(&c, t - h, 0)) / (2.0 * h);
                let d2 = (s.eval(&c, t + h, 1) - s.eval(&c, t - h, 1)) / (2.0 * h);
                assert!((d1 - s.eval(&c, t, 1)).abs() < 1e-6, "t {t}");
                assert!((d2 - s.eval(&c, t, 2)).abs() < 1e-5, "t {t}");
            }
        }
        assert!(UniformBSpline::new(1.0, 1.0, 0.25).is_none());
        assert!(UniformBSpline::new(0.0, 1.0, 0.0).is_none());
    }
}
