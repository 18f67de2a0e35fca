//! A ball joint written as three hinges (the euler model's BVH joint, `R = R_c1(a1) R_c2(a2)
//! R_c3(a3)`), smoothed and differentiated as the rotation it is, not as three angles.
//!
//! Filtering the angles as scalars is not filtering the rotation: near gimbal lock
//! (`|cos a2|` small) the first and third angles turn fast and in opposite senses while the
//! joint barely moves, and a low-pass of each angle changes the rotation the triple makes;
//! their central differences likewise differ from the joint's angular velocity by terms that
//! grow as `1/cos a2`. Here the triple's rotations are smoothed on SO(3) exactly as a ball
//! joint's quaternions are ([`Smoother::smooth_quaternions`]) and written back as angles on the
//! take's continuous branch ([`repick_fast`]); the rates come from the rotation: the joint's body
//! angular velocity `ω` by the ball joint's manifold differences, `ω̇` by the same differences
//! of `ω`, then `q̇ = H⁻¹ ω` and `q̈ = H⁻¹ (α − Ḣ q̇)` in the joint's parent frame (`ω_p = R ω`,
//! `α_p = R ω̇`: `d(Rω)/dt = R ω̇ + R [ω]× ω`), `H` the hinges' axes
//! ([`hinge_axes`](crate::rotation::hinge_axes)). The motion of every body then is the ball
//! model's, whatever the take's rotation order.

use crate::motion::smooth::{SmoothSpec, Smoother};
use crate::motion::unwrap::lock_distance;
use crate::motion::unwrap::repick_fast;
use crate::rotation::{
    EulerOrder, euler_frame_axes, euler_to_quaternion_axes, hinge_coordinate_rates,
    matrix_to_euler_fast_axes, with_axes,
};
use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// Within this `|det H| = |cos a2|` of gimbal lock (the middle angle within 0.00001° of ±90°)
/// `H` cannot be inverted with any accuracy: at a frame this close a triple's rates are its
/// angles' scalar differences ([`triple_rates`] leaves those frames to its caller).
pub const LOCK_DET: f64 = 1e-7;

/// Work buffers of [`smooth_triple`] and [`triple_rates`], for up to a take's frames; reused,
/// so the per-frame loops allocate nothing.
#[derive(Debug, Clone, Default)]
pub struct TripleScratch {
    /// Rotation of each frame.
    pub quats: Vec<UnitQuaternion<f64>>,
    /// Each frame's rotation and hinge axes ([`euler_frame`]).
    frames: Vec<Frame>,
    /// Body angular velocity `ω` of each frame (rad/s, child frame).
    omega: Vec<Vector3<f64>>,
}

/// A frame's rotation (quaternion, matrix) and its hinges' axes in the parent frame.
type Frame = (UnitQuaternion<f64>, Matrix3<f64>, Matrix3<f64>);

impl TripleScratch {
    /// Buffers for `frames` frames.
    pub fn with_capacity(frames: usize) -> Self {
        Self {
            quats: Vec::with_capacity(frames),
            frames: Vec::with_capacity(frames),
            omega: Vec::with_capacity(frames),
        }
    }

    fn fill_quats(&mut self, order: EulerOrder, cols: [&[f64]; 3]) {
        fn fill<const I: usize, const J: usize, const K: usize>(
            quats: &mut Vec<UnitQuaternion<f64>>,
            cols: [&[f64]; 3],
        ) {
            quats.clear();
            quats.extend((0..cols[0].len()).map(|k| {
                euler_to_quaternion_axes([I, J, K], [cols[0][k], cols[1][k], cols[2][k]])
            }));
        }
        with_axes!(order, fill(&mut self.quats, cols));
    }

    fn fill_frames(&mut self, order: EulerOrder, cols: [&[f64]; 3]) {
        fn fill<const I: usize, const J: usize, const K: usize>(
            frames: &mut Vec<Frame>,
            cols: [&[f64]; 3],
        ) {
            frames.clear();
            frames.extend(
                (0..cols[0].len())
                    .map(|k| euler_frame_axes([I, J, K], [cols[0][k], cols[1][k], cols[2][k]])),
            );
        }
        with_axes!(order, fill(&mut self.frames, cols));
    }
}

/// Smooths the rotation of one euler joint (its three angle columns, one value per frame,
/// continuous) on SO(3) with `smoother`, and writes the angles back: each frame's triple of
/// the smoothed rotation nearest the previous frame's (the first frame's nearest the given
/// first triple). Without smoothing nothing changes.
pub fn smooth_triple(
    smoother: &mut Smoother,
    s: &mut TripleScratch,
    order: EulerOrder,
    cols: [&mut [f64]; 3],
) {
    let [c0, c1, c2] = cols;
    let n = c0.len();
    if n == 0 || smoother.spec() == SmoothSpec::None {
        return;
    }
    s.fill_quats(order, [&c0[..], &c1[..], &c2[..]]);
    smoother.smooth_quaternions(&mut s.quats);
    with_axes!(order, write_back(order, &s.quats, [c0, c1, c2]));
}

/// The angles of the rotations `quats` on the take's branch (see [`smooth_triple`]).
fn write_back<const I: usize, const J: usize, const K: usize>(
    order: EulerOrder,
    quats: &[UnitQuaternion<f64>],
    cols: [&mut [f64]; 3],
) {
    let [c0, c1, c2] = cols;
    let mut previous = [c0[0], c1[0], c2[0]];
    for (k, r) in quats.iter().enumerate() {
        let m: Matrix3<f64> = r.to_rotation_matrix().into_inner();
        let x = repick_fast(order, matrix_to_euler_fast_axes([I, J, K], &m), previous);
        (c0[k], c1[k], c2[k]) = (x[0], x[1], x[2]);
        previous = x;
    }
}

/// Whether `|cos a2| < LOCK_DET`, `cos` computed only where [`lock_distance`] leaves doubt:
/// farther than `2·LOCK_DET` from the lock `|cos a2| = sin(distance) > LOCK_DET` by a margin
/// far beyond rounding, so the answer is the same as always computing it.
pub fn at_gimbal_lock(a2: f64) -> bool {
    match lock_distance(a2) {
        Some(d) if d > 2.0 * LOCK_DET => false,
        _ => a2.cos().abs() < LOCK_DET,
    }
}

/// The rates of one euler joint from its rotation (module doc): `v` = q̇ and `a` = q̈ of its
/// three hinges at every frame of the angle columns `q` sampled every `dt` s, with the ball
/// joint's differences (second order at every frame; two frames: the one difference, no
/// acceleration). Frames within [`LOCK_DET`] of gimbal lock, where `H` is singular, are left
/// as they were and counted: the caller gives them the angles' differences (`ω` and `ω̇` are
/// the rotation's there too, so the frames around them keep their rates from the rotation).
/// Returns how many frames were left.
pub fn triple_rates(
    s: &mut TripleScratch,
    order: EulerOrder,
    q: [&[f64]; 3],
    dt: f64,
    v: [&mut [f64]; 3],
    a: [&mut [f64]; 3],
) -> usize {
    let n = q[0].len();
    s.fill_frames(order, q);
    body_angular_velocity(&s.frames, dt, &mut s.omega);
    let [v0, v1, v2] = v;
    let [a0, a1, a2] = a;
    let h2 = 2.0 * dt;
    let mut left = 0;
    for k in 0..n {
        if at_gimbal_lock(q[1][k]) {
            left += 1;
            continue;
        }
        // ω̇ by the scalar formulas of each component (pipeline::states' accelerations)
        let w = &s.omega;
        let dw = match n {
            0..=2 => Vector3::zeros(),
            _ if k == 0 => (-3.0 * w[0] + 4.0 * w[1] - w[2]) / h2,
            _ if k == n - 1 => (3.0 * w[n - 1] - 4.0 * w[n - 2] + w[n - 3]) / h2,
            _ => (w[k + 1] - w[k - 1]) / h2,
        };
        let (_, r, axes) = &s.frames[k];
        let Some((dq, ddq)) = hinge_coordinate_rates(axes, &(r * w[k]), &(r * dw), 0.0) else {
            // a singular H at |cos a2| ≥ LOCK_DET is rounding's, not the take's: hold
            continue;
        };
        (v0[k], v1[k], v2[k]) = (dq[0], dq[1], dq[2]);
        if n > 2 {
            (a0[k], a1[k], a2[k]) = (ddq[0], ddq[1], ddq[2]);
        }
    }
    left
}

/// The body angular velocity of a rotation trajectory by the ball joint's differences
/// (`pipeline::states`' `joint_velocity` with the spherical joint's `difference`,
/// `log(q_i⁻¹ q_j)`): central inside, one-sided second order at the ends, the one difference
/// for two frames.
fn body_angular_velocity(q: &[Frame], dt: f64, out: &mut Vec<Vector3<f64>>) {
    let n = q.len();
    let diff = |i: usize, j: usize| (q[i].0.inverse() * q[j].0).scaled_axis();
    out.clear();
    match n {
        0 => {}
        1 => out.push(Vector3::zeros()),
        2 => {
            let d = diff(0, 1) / dt;
            out.extend([d, d]);
        }
        _ => out.extend((0..n).map(|k| {
            if k == 0 {
                (4.0 * diff(0, 1) - diff(0, 2)) / (2.0 * dt)
            } else if k == n - 1 {
                -(4.0 * diff(n - 1, n - 2) - diff(n - 1, n - 3)) / (2.0 * dt)
            } else {
                diff(k - 1, k + 1) / (2.0 * dt)
            }
        })),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    #[test]
    fn the_lock_test_without_cos_answers_as_cos_does() {
        // around the locks (±π/2 and beyond whole turns), across the threshold and far from it
        for lock in [-5.0, -1.0, 1.0, 3.0, 2001.0].map(|m| m * FRAC_PI_2) {
            for e in 0..4000 {
                let d = (e as f64 - 2000.0) * 1.7e-10 * (1.0 + (e % 7) as f64);
                for a2 in [lock + d, lock + d * 1e3, lock + d * 1e6] {
                    assert_eq!(at_gimbal_lock(a2), a2.cos().abs() < LOCK_DET, "{a2}");
                }
            }
        }
        for a2 in [0.0, -0.3, 1.2, f64::NAN, 1e7, -3e9] {
            assert_eq!(at_gimbal_lock(a2), a2.cos().abs() < LOCK_DET, "{a2}");
        }
    }
}
