//! Time derivatives of sampled trajectories: q → q̇ → q̈.
//!
//! Scalar coordinates (revolute angles in rad, prismatic displacements in m) use second-order
//! finite differences (Fornberg 1988, *Math. Comp.* 51(184), table 1): the central difference
//! `ẋₖ = (xₖ₊₁ − xₖ₋₁)/2dt` inside, and the one-sided second-order formulas at the first and
//! last frame, `ẋ₀ = (−3x₀ + 4x₁ − x₂)/2dt`, so the error is O(dt²) at every frame, ends
//! included. Second derivatives: `(xₖ₊₁ − 2xₖ + xₖ₋₁)/dt²` inside and
//! `(2x₀ − 5x₁ + 4x₂ − x₃)/dt²` at the ends (also O(dt²)).
//!
//! Ball joints (unit quaternions) are differentiated on the rotation manifold: around frame
//! `k` the trajectory is written `q(t) = qₖ · exp(φ(t))` with `φ(tₖ) = 0`, so that the body
//! angular velocity is `ω(tₖ) = φ̇(tₖ)` exactly, and `φ` at the neighbours is the logarithm
//! `φ(tⱼ) = log(qₖ⁻¹ qⱼ)` (the model's `difference` of a spherical joint, Pinocchio's
//! `difference`). The scalar formulas are then applied to `φ`. This is the model's convention
//! for a spherical joint: `v = ω` in the child frame, `q̇ = q ⊗ (0, ω/2)`, so the result can be
//! fed to the dynamics directly and its derivative (by [`differentiate_vectors`]) is the
//! joint acceleration `a`.

pub use crate::rotation::{quat_exp, quat_log};
use nalgebra::{UnitQuaternion, Vector3};

/// `out = dx/dt` of a trajectory sampled every `dt` s (second order at every frame, see the
/// module doc). One frame: zero; two frames: the plain difference. `out.len() == x.len()`.
pub fn differentiate(x: &[f64], dt: f64, out: &mut [f64]) {
    let n = x.len();
    assert_eq!(out.len(), n, "derivative buffer length");
    match n {
        0 => {}
        1 => out[0] = 0.0,
        2 => {
            let d = (x[1] - x[0]) / dt;
            out[0] = d;
            out[1] = d;
        }
        _ => {
            let h2 = 2.0 * dt;
            out[0] = (-3.0 * x[0] + 4.0 * x[1] - x[2]) / h2;
            for k in 1..n - 1 {
                out[k] = (x[k + 1] - x[k - 1]) / h2;
            }
            out[n - 1] = (3.0 * x[n - 1] - 4.0 * x[n - 2] + x[n - 3]) / h2;
        }
    }
}

/// `out = d²x/dt²` (second order at every frame when `x` has at least 4 frames; with 3 the
/// single central value is used everywhere, with fewer the result is zero).
pub fn second_derivative(x: &[f64], dt: f64, out: &mut [f64]) {
    let n = x.len();
    assert_eq!(out.len(), n, "derivative buffer length");
    let h2 = dt * dt;
    if n < 3 {
        out.iter_mut().for_each(|o| *o = 0.0);
        return;
    }
    for k in 1..n - 1 {
        out[k] = (x[k + 1] - 2.0 * x[k] + x[k - 1]) / h2;
    }
    if n == 3 {
        out[0] = out[1];
        out[2] = out[1];
    } else {
        out[0] = (2.0 * x[0] - 5.0 * x[1] + 4.0 * x[2] - x[3]) / h2;
        out[n - 1] = (2.0 * x[n - 1] - 5.0 * x[n - 2] + 4.0 * x[n - 3] - x[n - 4]) / h2;
    }
}

/// Differentiates each column: `out[c] = d columns[c] / dt`. `out` must have the same shape.
pub fn differentiate_columns(columns: &[Vec<f64>], dt: f64, out: &mut [Vec<f64>]) {
    assert_eq!(columns.len(), out.len(), "derivative column count");
    for (x, o) in columns.iter().zip(out.iter_mut()) {
        differentiate(x, dt, o);
    }
}

/// Differentiates a sampled 3-vector (e.g. ω → ω̇, the joint acceleration of a ball joint in
/// the model's convention), component by component, with the formulas of [`differentiate`].
pub fn differentiate_vectors(x: &[Vector3<f64>], dt: f64, out: &mut [Vector3<f64>]) {
    let n = x.len();
    assert_eq!(out.len(), n, "derivative buffer length");
    match n {
        0 => {}
        1 => out[0] = Vector3::zeros(),
        2 => {
            let d = (x[1] - x[0]) / dt;
            out[0] = d;
            out[1] = d;
        }
        _ => {
            let h2 = 2.0 * dt;
            out[0] = (-3.0 * x[0] + 4.0 * x[1] - x[2]) / h2;
            for k in 1..n - 1 {
                out[k] = (x[k + 1] - x[k - 1]) / h2;
            }
            out[n - 1] = (3.0 * x[n - 1] - 4.0 * x[n - 2] + x[n - 3]) / h2;
        }
    }
}

/// Body angular velocity `ω` (rad/s, child frame) of a ball-joint trajectory sampled every
/// `dt` s: the model's spherical-joint `v`. Second order at every frame (see the module doc);
/// the sign of each quaternion does not matter.
pub fn differentiate_quaternions(q: &[UnitQuaternion<f64>], dt: f64, omega: &mut [Vector3<f64>]) {
    let n = q.len();
    assert_eq!(omega.len(), n, "derivative buffer length");
    // φ(j) = log(q_k⁻¹ q_j): the neighbours in the chart centred on frame k
    let phi = |k: usize, j: usize| quat_log(&(q[k].inverse() * q[j]));
    match n {
        0 => {}
        1 => omega[0] = Vector3::zeros(),
        2 => {
            let d = phi(0, 1) / dt;
            omega[0] = d;
            // in the chart of frame 1 the step back is −d rotated into frame 1: −φ₁(0)/dt
            omega[1] = -phi(1, 0) / dt;
        }
        _ => {
            let h2 = 2.0 * dt;
            // one-sided: (−3φ(0) + 4φ(1) − φ(2))/2dt with φ(0) = 0
            omega[0] = (4.0 * phi(0, 1) - phi(0, 2)) / h2;
            for (k, w) in omega.iter_mut().enumerate().take(n - 1).skip(1) {
                *w = (phi(k, k + 1) - phi(k, k - 1)) / h2;
            }
            omega[n - 1] = -(4.0 * phi(n - 1, n - 2) - phi(n - 1, n - 3)) / h2;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_inverts_exp_and_ignores_sign() {
        for r in [
            Vector3::new(0.3, -1.2, 0.5),
            Vector3::new(1e-14, 0.0, -2e-14),
            Vector3::new(0.0, 3.1, 0.0),
        ] {
            let q = quat_exp(&r);
            assert!((quat_log(&q) - r).norm() < 1e-12, "{r:?}");
            let minus = UnitQuaternion::new_unchecked(-q.into_inner());
            assert!((quat_log(&minus) - r).norm() < 1e-12);
        }
    }
}
