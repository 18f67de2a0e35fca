//! Superquadric surfaces for drawing links (Barr 1981, "Superquadrics and angle-preserving
//! transformations", IEEE CG&A 1(1):11–23).
//!
//! Barr's parametrisation of the superellipsoid with semi-axes `a, b, c` and exponents
//! `ε1` (north–south) and `ε2` (east–west), with the signed power `s^ε = sign(s)·|s|^ε`:
//!
//! ```text
//! x(η, ω) = a · cos^ε1(η) · cos^ε2(ω)      η ∈ [−π/2, π/2]  (latitude)
//! y(η, ω) = b · cos^ε1(η) · sin^ε2(ω)      ω ∈ [−π, π)      (longitude)
//! z(η, ω) = c · sin^ε1(η)
//! ```
//!
//! Every such point satisfies the implicit equation
//! `(|x/a|^(2/ε2) + |y/b|^(2/ε2))^(ε2/ε1) + |z/c|^(2/ε1) = 1`; `ε1 = ε2 = 1` is an ellipsoid and
//! `ε → 0` tends to the box `|x| ≤ a, |y| ≤ b, |z| ≤ c`. Points are returned in the body frame
//! (`center + rot · local`), in metres.

use crate::model::Superquadric;
use crate::spatial::SpatialTransform;
use nalgebra::Vector3;

/// `sign(s) · |s|^e` (Barr's signed power), with `0^e = 0`.
fn signed_pow(s: f64, e: f64) -> f64 {
    if s == 0.0 {
        0.0
    } else {
        s.signum() * s.abs().powf(e)
    }
}

/// Left-hand side of the implicit equation of `sq` at the body-frame point `p`: 1 on the
/// surface, < 1 inside, > 1 outside (Barr 1981, eq. for the inside-outside function).
pub fn inside_outside(sq: &Superquadric, p: &Vector3<f64>) -> f64 {
    let [e1, e2] = sq.exponents;
    let l = sq.rot.transpose() * (p - sq.center);
    let (x, y, z) = (l.x / sq.size.x, l.y / sq.size.y, l.z / sq.size.z);
    let xy = x.abs().powf(2.0 / e2) + y.abs().powf(2.0 / e2);
    xy.powf(e2 / e1) + z.abs().powf(2.0 / e1)
}

/// `n_u × n_v` surface points of `sq` in its body frame (m): row `i` is latitude
/// `η = −π/2 + π·i/(n_u−1)` (both poles included, so the pole rows repeat one point), column
/// `j` is longitude `ω = −π + 2π·j/n_v`. Index `i·n_v + j`. `n_u` is raised to at least 2 and
/// `n_v` to at least 3.
pub fn superquadric_points(sq: &Superquadric, n_u: usize, n_v: usize) -> Vec<Vector3<f64>> {
    let (n_u, n_v) = (n_u.max(2), n_v.max(3));
    let [e1, e2] = sq.exponents;
    let mut out = Vec::with_capacity(n_u * n_v);
    for i in 0..n_u {
        let eta = -std::f64::consts::FRAC_PI_2 + std::f64::consts::PI * i as f64 / (n_u - 1) as f64;
        let (se, ce) = eta.sin_cos();
        // cos η is ≥ 0 on [−π/2, π/2]; clamp the rounding at the poles
        let (ce1, se1) = (signed_pow(ce.max(0.0), e1), signed_pow(se, e1));
        for j in 0..n_v {
            let omega = -std::f64::consts::PI + 2.0 * std::f64::consts::PI * j as f64 / n_v as f64;
            let (so, co) = omega.sin_cos();
            let local = Vector3::new(
                sq.size.x * ce1 * signed_pow(co, e2),
                sq.size.y * ce1 * signed_pow(so, e2),
                sq.size.z * se1,
            );
            out.push(sq.center + sq.rot * local);
        }
    }
    out
}

/// A wireframe of a superquadric: its [`superquadric_points`] and the segments joining them
/// (meridians and parallels), ready to be placed in the world and projected (the TUI draws it in
/// a braille canvas).
#[derive(Debug, Clone, PartialEq)]
pub struct SuperquadricMesh {
    /// Surface points in the body frame (m), `n_u · n_v` of them, index `i·n_v + j`.
    pub points: Vec<Vector3<f64>>,
    /// Pairs of indices into `points`: every meridian segment `(i, j)–(i+1, j)` and every
    /// parallel segment `(i, j)–(i, j+1 mod n_v)` except on the two pole rows (zero length).
    pub edges: Vec<[usize; 2]>,
}

impl SuperquadricMesh {
    /// The wireframe of `sq` with `n_u` parallels (poles included) and `n_v` meridians (raised to
    /// at least 2 and 3).
    pub fn new(sq: &Superquadric, n_u: usize, n_v: usize) -> Self {
        let (n_u, n_v) = (n_u.max(2), n_v.max(3));
        let points = superquadric_points(sq, n_u, n_v);
        let mut edges = Vec::with_capacity(2 * n_u * n_v);
        for i in 0..n_u {
            for j in 0..n_v {
                let k = i * n_v + j;
                // meridian: down to the next parallel
                if i + 1 < n_u {
                    edges.push([k, k + n_v]);
                }
                // parallel: around the ring, skipped on the pole rows
                if i > 0 && i + 1 < n_u {
                    edges.push([k, i * n_v + (j + 1) % n_v]);
                }
            }
        }
        Self { points, edges }
    }

    /// The segments in the frame `x` maps the body frame into (e.g. the world pose of the body
    /// from forward kinematics), without allocating.
    pub fn edges_in<'a>(
        &'a self,
        x: &'a SpatialTransform,
    ) -> impl Iterator<Item = (Vector3<f64>, Vector3<f64>)> + 'a {
        self.edges.iter().map(move |&[a, b]| {
            (
                x.transform_point(&self.points[a]),
                x.transform_point(&self.points[b]),
            )
        })
    }
}
