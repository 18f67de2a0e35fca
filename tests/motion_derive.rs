//! Derivatives of sampled trajectories are second order at every frame, ends included: on
//! analytic signals the largest error falls by 4 when the frame time halves. Ball joints are
//! differentiated on the rotation manifold and give the body angular velocity in the model's
//! spherical-joint convention (`v = ω` in the child frame, the velocity `integrate` expects).

use articula::model::JointKind;
use articula::motion::derive::{
    differentiate, differentiate_columns, differentiate_quaternions, differentiate_vectors,
    quat_exp, quat_log, second_derivative,
};
use nalgebra::{UnitQuaternion, Vector3};

fn max_err(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// Largest errors of ẋ and ẍ for x = sin(3t) + 0.5t² on [0, 2] s sampled every `dt`.
fn scalar_errors(dt: f64) -> (f64, f64) {
    let n = (2.0 / dt).round() as usize + 1;
    let t: Vec<f64> = (0..n).map(|k| k as f64 * dt).collect();
    let x: Vec<f64> = t.iter().map(|t| (3.0 * t).sin() + 0.5 * t * t).collect();
    let xd: Vec<f64> = t.iter().map(|t| 3.0 * (3.0 * t).cos() + t).collect();
    let xdd: Vec<f64> = t.iter().map(|t| -9.0 * (3.0 * t).sin() + 1.0).collect();
    let mut d = vec![0.0; n];
    let mut dd = vec![0.0; n];
    differentiate(&x, dt, &mut d);
    second_derivative(&x, dt, &mut dd);
    (max_err(&d, &xd), max_err(&dd, &xdd))
}

#[test]
fn scalar_derivatives_are_second_order_including_the_ends() {
    let (e1, e2) = scalar_errors(0.01);
    let (h1, h2) = scalar_errors(0.005);
    // |error| ≤ C dt² with C from the third / fourth derivative (27, 81)
    assert!(e1 < 27.0 * 0.01f64.powi(2), "ẋ error {e1}");
    assert!(e2 < 2.0 * 81.0 * 0.01f64.powi(2), "ẍ error {e2}");
    for (coarse, fine) in [(e1, h1), (e2, h2)] {
        let ratio = coarse / fine;
        assert!((3.5..4.5).contains(&ratio), "convergence ratio {ratio}");
    }
}

#[test]
fn a_parabola_is_differentiated_exactly() {
    let dt = 0.1;
    let x: Vec<f64> = (0..6)
        .map(|k| 2.0 - 3.0 * (k as f64 * dt) + 4.0 * (k as f64 * dt).powi(2))
        .collect();
    let cols = vec![x.clone()];
    let mut out = vec![vec![0.0; 6]];
    differentiate_columns(&cols, dt, &mut out);
    for (k, v) in out[0].iter().enumerate() {
        assert!((v - (-3.0 + 8.0 * k as f64 * dt)).abs() < 1e-12);
    }
    let mut dd = vec![0.0; 6];
    second_derivative(&x, dt, &mut dd);
    assert!(dd.iter().all(|a| (a - 8.0).abs() < 1e-9), "{dd:?}");
}

/// q(t) = exp(α(t)·a) · exp(β(t)·b) with fixed unit axes a, b: the body angular velocity is
/// ω = exp(β b)⁻¹ (α̇ a) + β̇ b.
fn two_axis(t: f64) -> (UnitQuaternion<f64>, Vector3<f64>) {
    let a = Vector3::new(0.0, 1.0, 0.0);
    let b = Vector3::new(1.0, 0.0, 1.0).normalize();
    let (al, ald) = (2.0 * t + 0.4 * (5.0 * t).sin(), 2.0 + 2.0 * (5.0 * t).cos());
    let (be, bed) = (0.7 * (2.0 * t).sin(), 1.4 * (2.0 * t).cos());
    let qb = quat_exp(&(b * be));
    let q = quat_exp(&(a * al)) * qb;
    let w = qb.inverse() * (a * ald) + b * bed;
    (q, w)
}

fn quaternion_error(dt: f64) -> f64 {
    let n = (3.0 / dt).round() as usize + 1;
    let (q, w): (Vec<_>, Vec<_>) = (0..n).map(|k| two_axis(k as f64 * dt)).unzip();
    let mut out = vec![Vector3::zeros(); n];
    differentiate_quaternions(&q, dt, &mut out);
    out.iter()
        .zip(&w)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max)
}

#[test]
fn angular_velocity_is_second_order_on_the_manifold() {
    let (e, h) = (quaternion_error(0.01), quaternion_error(0.005));
    assert!(e < 0.05, "ω error {e} rad/s");
    let ratio = e / h;
    assert!((3.5..4.5).contains(&ratio), "convergence ratio {ratio}");
}

#[test]
fn angular_velocity_is_the_models_spherical_velocity() {
    // a constant body rate: q_{k+1} = integrate(q_k, ω, dt) exactly, and ω comes back at every
    // frame, whatever the sign of each stored quaternion
    let dt = 1.0 / 30.0;
    let w = Vector3::new(1.5, -0.5, 3.0);
    let mut q = vec![UnitQuaternion::from_scaled_axis(Vector3::new(
        0.3, 0.2, 0.1,
    ))];
    let mut buf = [0.0; 4];
    for _ in 0..40 {
        let last = q.last().unwrap();
        let xyzw = [last.i, last.j, last.k, last.w];
        JointKind::Spherical.integrate(&xyzw, w.as_slice(), dt, &mut buf);
        let next = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
            buf[3], buf[0], buf[1], buf[2],
        ));
        q.push(next);
    }
    for k in (0..q.len()).step_by(5) {
        q[k] = UnitQuaternion::new_unchecked(-q[k].into_inner());
    }
    let mut out = vec![Vector3::zeros(); q.len()];
    differentiate_quaternions(&q, dt, &mut out);
    for o in &out {
        assert!((o - w).norm() < 1e-9, "{o:?}");
    }
    // and its derivative, the joint acceleration, is zero
    let mut acc = vec![Vector3::zeros(); q.len()];
    differentiate_vectors(&out, dt, &mut acc);
    assert!(acc.iter().all(|a| a.norm() < 1e-6));
}

#[test]
fn log_is_the_rotation_vector() {
    let r = Vector3::new(0.0, 0.0, 1.0);
    let q = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 1.0);
    assert!((quat_log(&q) - r).norm() < 1e-15);
    // beyond half a turn the shortest arc is the other way round
    let q = UnitQuaternion::from_axis_angle(&Vector3::z_axis(), 4.0);
    assert!((quat_log(&q) - Vector3::new(0.0, 0.0, 4.0 - std::f64::consts::TAU)).norm() < 1e-12);
}
