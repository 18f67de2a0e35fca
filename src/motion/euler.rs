//! A ball joint written as three hinges (the euler model's BVH joint, `R = R_c1(a1) R_c2(a2)
//! R_c3(a3)`), smoothed and differentiated as the rotation it is, not as three angles.
//!
//! Filtering the angles as scalars is not filtering the rotation: near gimbal lock
//! (`|cos a2|` small) the first and third angles turn fast and in opposite senses while the
//! joint barely moves, and a low-pass of each angle changes the rotation the triple makes;
//! their central differences likewise differ from the joint's angular velocity by terms that
//! grow as `1/cos a2`. Here the triple's rotations are smoothed on SO(3) exactly as a ball
//! joint's quaternions are ([`Smoother::smooth_quaternions`]) and written back as angles on the
//! take's continuous branch ([`repick_fast`]); the rates come from the smoothed rotation itself
//! (not from one rebuilt from the written-back angles): the joint's body
//! angular velocity `ω` by the ball joint's manifold differences, `ω̇` by the same differences
//! of `ω`, then `q̇ = H⁻¹ ω` and `q̈ = H⁻¹ (α − Ḣ q̇)` in the joint's parent frame (`ω_p = R ω`,
//! `α_p = R ω̇`: `d(Rω)/dt = R ω̇ + R [ω]× ω`), `H` the hinges' axes
//! ([`hinge_axes`](crate::rotation::hinge_axes)). The motion of every body then is the ball
//! model's, whatever the take's rotation order.

use crate::lanes::{BLOCK, HingeBlock, atan2_many, sin_cos_many, vectorised};
use crate::motion::smooth::{SmoothSpec, Smoother};
use crate::motion::unwrap::lock_distance;
use crate::motion::unwrap::repick_fast;
use crate::rotation::{
    EulerOrder, euler_half_angles_to_quaternion, matrix_to_euler_fast_args, quat_log,
    quat_log_from, quat_log_parts, with_axes,
};
use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// Within this `|det H| = |cos a2|` of gimbal lock (the middle angle within 0.00001° of ±90°)
/// `H` cannot be inverted with any accuracy: at a frame this close a triple's rates are its
/// angles' scalar differences ([`triple_rates`] leaves those frames to its caller).
pub const LOCK_DET: f64 = 1e-7;

/// Farther than this (rad) from gimbal lock, [`hinge_axes_at`] reads the first angle's sine
/// and cosine from the rotation (dividing by `|cos a2| > sin 0.01`, which costs at most two
/// digits); nearer, it takes them from the angle.
const AXES_FROM_ROTATION: f64 = 0.01;

/// Work buffers of [`triple_rates`] and of a ball joint's smoothing, for up to a take's
/// frames; reused, so the per-frame loops allocate nothing.
#[derive(Debug, Clone, Default)]
pub struct TripleScratch {
    /// Rotation of each frame.
    pub quats: Vec<UnitQuaternion<f64>>,
    /// Body angular velocity `ω` of each frame (rad/s, child frame).
    omega: Vec<Vector3<f64>>,
}

impl TripleScratch {
    /// Buffers for `frames` frames.
    pub fn with_capacity(frames: usize) -> Self {
        Self {
            quats: Vec::with_capacity(frames),
            omega: Vec::with_capacity(frames),
        }
    }
}

/// The rotation of each frame of a triple's angle columns `cols` into `out` (one per frame):
/// [`euler_to_quaternion`](crate::rotation::euler_to_quaternion) frame by frame, bit for bit,
/// the sines and cosines of a block of frames' half angles at once.
pub fn triple_rotations(order: EulerOrder, cols: [&[f64]; 3], out: &mut [UnitQuaternion<f64>]) {
    fn fill<const I: usize, const J: usize, const K: usize>(
        cols: [&[f64]; 3],
        out: &mut [UnitQuaternion<f64>],
    ) {
        let n = out.len();
        let mut half = [0.0; 3 * BLOCK];
        let (mut s, mut c) = ([0.0; 3 * BLOCK], [0.0; 3 * BLOCK]);
        for k0 in (0..n).step_by(BLOCK) {
            let m = BLOCK.min(n - k0);
            // angle a of the block's frame d at a·m + d
            for (a, col) in cols.iter().enumerate() {
                for (h, x) in half[a * m..(a + 1) * m].iter_mut().zip(&col[k0..k0 + m]) {
                    *h = 0.5 * x;
                }
            }
            sin_cos_many(&half[..3 * m], &mut s, &mut c);
            for (d, r) in out[k0..k0 + m].iter_mut().enumerate() {
                let half = [0, 1, 2].map(|a| (s[a * m + d], c[a * m + d]));
                *r = euler_half_angles_to_quaternion([I, J, K], half);
            }
        }
    }
    with_axes!(order, fill(cols, out));
}

/// Smooths the rotation of one euler joint (its three angle columns, one value per frame,
/// continuous) on SO(3) with `smoother`, and writes the angles back: each frame's triple of
/// the smoothed rotation nearest the previous frame's (the first frame's nearest the given
/// first triple). `rotations` (one per frame) receives the rotations, smoothed: the ones the
/// angles are read from, which [`triple_rates`] takes the rates from. Without smoothing the
/// angles do not change and `rotations` are theirs.
pub fn smooth_triple(
    smoother: &mut Smoother,
    order: EulerOrder,
    cols: [&mut [f64]; 3],
    rotations: &mut [UnitQuaternion<f64>],
) {
    let [c0, c1, c2] = cols;
    if c0.is_empty() {
        return;
    }
    triple_rotations(order, [&c0[..], &c1[..], &c2[..]], rotations);
    if smoother.spec() == SmoothSpec::None {
        return;
    }
    smoother.smooth_quaternions(rotations);
    with_axes!(order, write_back(order, rotations, [c0, c1, c2]));
}

/// The angles of the rotations `quats` on the take's branch (see [`smooth_triple`]).
fn write_back<const I: usize, const J: usize, const K: usize>(
    order: EulerOrder,
    quats: &[UnitQuaternion<f64>],
    cols: [&mut [f64]; 3],
) {
    let [c0, c1, c2] = cols;
    let mut previous = [c0[0], c1[0], c2[0]];
    let mut matrices = [Matrix3::zeros(); BLOCK];
    for k0 in (0..quats.len()).step_by(BLOCK) {
        let block = &quats[k0..quats.len().min(k0 + BLOCK)];
        write_back_block::<I, J, K>(order, block, &mut previous, &mut matrices, |d, q, _| {
            let k = k0 + d;
            (c0[k], c1[k], c2[k]) = (q[0], q[1], q[2]);
        });
    }
}

/// The write-back of one block of frames (`quats`, at most [`BLOCK`]): each frame's matrix
/// (into `matrices`) and [`matrix_to_euler_fast_args`], the block's `atan2` together, then
/// frame by frame the triple [`repick_fast`] nearest `previous` (which it then becomes),
/// given to `each` with the frame's index in the block and its matrix.
#[inline(always)]
fn write_back_block<const I: usize, const J: usize, const K: usize>(
    order: EulerOrder,
    quats: &[UnitQuaternion<f64>],
    previous: &mut [f64; 3],
    matrices: &mut [Matrix3<f64>; BLOCK],
    mut each: impl FnMut(usize, [f64; 3], &Matrix3<f64>),
) {
    let (mut y, mut x, mut angles) = ([0.0; 3 * BLOCK], [0.0; 3 * BLOCK], [0.0; 3 * BLOCK]);
    let mut first = [false; BLOCK];
    let m = quats.len().min(BLOCK);
    for (d, r) in quats[..m].iter().enumerate() {
        let r: Matrix3<f64> = r.to_rotation_matrix().into_inner();
        let (args, a1) = matrix_to_euler_fast_args([I, J, K], &r);
        for (a, (ya, xa)) in args.into_iter().enumerate() {
            (y[3 * d + a], x[3 * d + a]) = (ya, xa);
        }
        first[d] = a1;
        matrices[d] = r;
    }
    atan2_many(&y[..3 * m], &x[..3 * m], &mut angles);
    for d in 0..m {
        let a = &angles[3 * d..3 * d + 3];
        let triple = [if first[d] { a[0] } else { 0.0 }, a[1], a[2]];
        let q = repick_fast(order, triple, *previous);
        *previous = q;
        each(d, q, &matrices[d]);
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
/// acceleration). `rotations` are the frames' rotations as [`smooth_triple`] left them (the
/// angles' own when `None`). Frames within [`LOCK_DET`] of gimbal lock, where `H` is singular,
/// are left as they were and counted: the caller gives them the angles' differences (`ω` and
/// `ω̇` are the rotation's there too, so the frames around them keep their rates from the
/// rotation). Returns how many frames were left.
pub fn triple_rates(
    s: &mut TripleScratch,
    order: EulerOrder,
    q: [&[f64]; 3],
    rotations: Option<&[UnitQuaternion<f64>]>,
    dt: f64,
    v: [&mut [f64]; 3],
    a: [&mut [f64]; 3],
) -> usize {
    let quats = match rotations {
        Some(r) => r,
        None => {
            s.quats.resize(q[0].len(), UnitQuaternion::identity());
            triple_rotations(order, q, &mut s.quats);
            &s.quats
        }
    };
    body_angular_velocity(quats, dt, &mut s.omega);
    with_axes!(order, coordinate_rates(quats, &s.omega, q, dt, v, a))
}

/// [`triple_rates`] from the rotations `quats` and their body angular velocities `w`: per
/// frame `H`, `ω` and `α` in the parent's axes, then `H⁻¹` and the rates a block of frames at
/// a time ([`HingeBlock`], the arithmetic of
/// [`hinge_coordinate_rates`](crate::rotation::hinge_coordinate_rates) on the vector lanes).
fn coordinate_rates<const I: usize, const J: usize, const K: usize>(
    quats: &[UnitQuaternion<f64>],
    w: &[Vector3<f64>],
    q: [&[f64]; 3],
    dt: f64,
    v: [&mut [f64]; 3],
    a: [&mut [f64]; 3],
) -> usize {
    let n = q[0].len();
    let [v0, v1, v2] = v;
    let [a0, a1, a2] = a;
    let h2 = 2.0 * dt;
    let mut left = 0;
    let mut b = HingeBlock::default();
    let mut locked = [false; BLOCK];
    for k0 in (0..n).step_by(BLOCK) {
        let m = BLOCK.min(n - k0);
        for (d, lock) in locked[..m].iter_mut().enumerate() {
            let k = k0 + d;
            let r = quats[k].to_rotation_matrix().into_inner();
            *lock = hinge_inputs::<I, J, K>(&mut b, d, &r, w, k, [q[0][k], q[1][k], q[2][k]], h2);
            left += usize::from(*lock);
        }
        let (v, a) = (
            [&mut *v0, &mut *v1, &mut *v2],
            [&mut *a0, &mut *a1, &mut *a2],
        );
        solve_and_store(&mut b, &locked[..m], k0, n, v, a);
    }
    left
}

/// Frame `k`'s inputs of [`HingeBlock`] at its slot `d`: `H` from the rotation `r` and the
/// triple `x` ([`hinge_axes_at`]), `ω` (`w[k]`) and `ω̇` (by the scalar formulas of each
/// component, `pipeline::states`' accelerations) in the parent's axes. Returns whether the
/// frame is at gimbal lock ([`at_gimbal_lock`]).
#[inline(always)]
fn hinge_inputs<const I: usize, const J: usize, const K: usize>(
    b: &mut HingeBlock,
    d: usize,
    r: &Matrix3<f64>,
    w: &[Vector3<f64>],
    k: usize,
    x: [f64; 3],
    h2: f64,
) -> bool {
    let n = w.len();
    let lock = at_gimbal_lock(x[1]);
    let dw = match n {
        0..=2 => Vector3::zeros(),
        _ if k == 0 => (-3.0 * w[0] + 4.0 * w[1] - w[2]) / h2,
        _ if k == n - 1 => (3.0 * w[n - 1] - 4.0 * w[n - 2] + w[n - 3]) / h2,
        _ => (w[k + 1] - w[k - 1]) / h2,
    };
    let axes = hinge_axes_at::<I, J, K>(r, x);
    let (wp, dwp) = (r * w[k], r * dw);
    for (e, x) in axes.iter().enumerate() {
        b.axes[e][d] = *x;
    }
    for c in 0..3 {
        (b.w[c][d], b.dw[c][d]) = (wp[c], dwp[c]);
    }
    lock
}

/// Solves a block's hinges ([`HingeBlock::solve`], on the vector lanes) and stores the rates
/// of its frames `k0 ..` (`locked` one per frame) into the columns `v` and `a` (`n` frames; `a`
/// only for `n > 2`), except at the frames at gimbal lock (the caller's) and where `H` came out
/// singular at `|cos a2| ≥ LOCK_DET` (rounding's, not the take's: held).
#[inline(always)]
fn solve_and_store(
    b: &mut HingeBlock,
    locked: &[bool],
    k0: usize,
    n: usize,
    v: [&mut [f64]; 3],
    a: [&mut [f64]; 3],
) {
    let m = locked.len();
    vectorised(
        #[inline(always)]
        || b.solve(m),
    );
    let [v0, v1, v2] = v;
    let [a0, a1, a2] = a;
    for (d, &lock) in locked.iter().enumerate() {
        if lock || !b.ok[d] {
            continue;
        }
        let k = k0 + d;
        (v0[k], v1[k], v2[k]) = (b.dq[0][d], b.dq[1][d], b.dq[2][d]);
        if n > 2 {
            (a0[k], a1[k], a2[k]) = (b.ddq[0][d], b.ddq[1][d], b.ddq[2][d]);
        }
    }
}

/// [`smooth_triple`] then [`triple_rates`] of the rotations and angles it leaves, without
/// keeping the rotations for later: the angles written back and the rates made in one pass
/// over the frames after the filter, each frame's rotation matrix made once for both
/// (`write_back` and `coordinate_rates` in one loop; the same operations, so the same bits
/// as the two calls). `s.quats` holds the rotations afterwards. Returns the number of frames
/// at gimbal lock, left to the caller as [`triple_rates`] leaves them.
pub fn smooth_triple_and_rates(
    s: &mut TripleScratch,
    smoother: &mut Smoother,
    order: EulerOrder,
    cols: [&mut [f64]; 3],
    dt: f64,
    v: [&mut [f64]; 3],
    a: [&mut [f64]; 3],
) -> usize {
    let [c0, c1, c2] = cols;
    let n = c0.len();
    if n == 0 {
        return 0;
    }
    s.quats.resize(n, UnitQuaternion::identity());
    triple_rotations(order, [&c0[..], &c1[..], &c2[..]], &mut s.quats);
    if smoother.spec() == SmoothSpec::None {
        body_angular_velocity(&s.quats, dt, &mut s.omega);
        let q = [&c0[..], &c1[..], &c2[..]];
        return with_axes!(order, coordinate_rates(&s.quats, &s.omega, q, dt, v, a));
    }
    smoother.smooth_quaternions(&mut s.quats);
    body_angular_velocity(&s.quats, dt, &mut s.omega);
    let (quats, w) = (&s.quats[..], &s.omega[..]);
    with_axes!(
        order,
        write_back_and_rates(order, quats, w, [c0, c1, c2], dt, v, a)
    )
}

/// `write_back` and `coordinate_rates` in one loop (see [`smooth_triple_and_rates`]): per
/// block of frames, each frame's matrix, the block's `atan2` together, then frame by frame
/// the triple re-picked and written back and the hinges' inputs from the same matrix, then
/// `H⁻¹` and the rates on the lanes.
fn write_back_and_rates<const I: usize, const J: usize, const K: usize>(
    order: EulerOrder,
    quats: &[UnitQuaternion<f64>],
    w: &[Vector3<f64>],
    cols: [&mut [f64]; 3],
    dt: f64,
    v: [&mut [f64]; 3],
    a: [&mut [f64]; 3],
) -> usize {
    let [c0, c1, c2] = cols;
    let [v0, v1, v2] = v;
    let [a0, a1, a2] = a;
    let n = quats.len();
    let h2 = 2.0 * dt;
    let mut previous = [c0[0], c1[0], c2[0]];
    let mut matrices = [Matrix3::zeros(); BLOCK];
    let mut b = HingeBlock::default();
    let mut locked = [false; BLOCK];
    let mut left = 0;
    for k0 in (0..n).step_by(BLOCK) {
        let block = &quats[k0..n.min(k0 + BLOCK)];
        write_back_block::<I, J, K>(order, block, &mut previous, &mut matrices, |d, q, r| {
            let k = k0 + d;
            (c0[k], c1[k], c2[k]) = (q[0], q[1], q[2]);
            locked[d] = hinge_inputs::<I, J, K>(&mut b, d, r, w, k, q, h2);
            left += usize::from(locked[d]);
        });
        let m = block.len();
        let (v, a) = (
            [&mut *v0, &mut *v1, &mut *v2],
            [&mut *a0, &mut *a1, &mut *a2],
        );
        solve_and_store(&mut b, &locked[..m], k0, n, v, a);
    }
    left
}

/// The hinges' axes `H` ([`hinge_axes`](crate::rotation::hinge_axes) under the identity) of
/// the triple `x` (axes `I, J, K`, parity `p`) whose rotation is `r`: `w1 = e_I`,
/// `w2 = R_I(a1) e_J = cos a1 e_J + p sin a1 e_K` and `w3 = r e_K` (the last hinge's axis
/// turns with the first two only). Farther than [`AXES_FROM_ROTATION`] from gimbal lock the
/// first angle's sine and cosine are read from `r`'s third column, `r e_K = p sin a2 e_I +
/// cos a2 (cos a1 e_K − p sin a1 e_J)`, as the write-back took `a1` from it
/// ([`matrix_to_euler_fast_axes`]), with the sign of `cos a2` from `x`'s branch: no
/// trigonometry. Nearer, from `sin_cos(a1)`.
#[inline(always)]
fn hinge_axes_at<const I: usize, const J: usize, const K: usize>(
    r: &Matrix3<f64>,
    x: [f64; 3],
) -> Matrix3<f64> {
    let p = if J == (I + 1) % 3 { 1.0 } else { -1.0 };
    let (s1, c1) = match lock_distance(x[1]) {
        Some(d) if d > AXES_FROM_ROTATION => {
            let (y, z) = (r[(J, K)], r[(K, K)]);
            let inv = cos_sign(x[1]) / (y * y + z * z).sqrt();
            (-p * y * inv, z * inv)
        }
        _ => x[0].sin_cos(),
    };
    let mut axes = Matrix3::zeros();
    axes[(I, 0)] = 1.0;
    axes[(J, 1)] = c1;
    axes[(K, 1)] = p * s1;
    axes.set_column(2, &r.column(K));
    axes
}

/// The sign of `cos a` (+1 or −1) for an angle `a` not within rounding of an odd multiple of
/// π/2: `a` reduced by whole turns to `[−π, π]` lies within π/2 of 0.
fn cos_sign(a: f64) -> f64 {
    use std::f64::consts::{FRAC_PI_2, TAU};
    let t = a / TAU;
    // nearest integer (half away from zero; at a half, a lies π from 0 either way)
    let turns = (t + 0.5f64.copysign(t)) as i64 as f64;
    if (a - turns * TAU).abs() < FRAC_PI_2 {
        1.0
    } else {
        -1.0
    }
}

/// The body angular velocity of a rotation trajectory by the ball joint's differences
/// (`pipeline::states`' `joint_velocity` with the spherical joint's `difference`,
/// `log(q_i⁻¹ q_j)`): central inside, one-sided second order at the ends, the one difference
/// for two frames.
fn body_angular_velocity(q: &[UnitQuaternion<f64>], dt: f64, out: &mut Vec<Vector3<f64>>) {
    let n = q.len();
    let diff = |i: usize, j: usize| quat_log(&(q[i].inverse() * q[j]));
    out.clear();
    match n {
        0 => {}
        1 => out.push(Vector3::zeros()),
        2 => {
            let d = diff(0, 1) / dt;
            out.extend([d, d]);
        }
        _ => {
            out.push((4.0 * diff(0, 1) - diff(0, 2)) / (2.0 * dt));
            // inside, diff(k − 1, k + 1) a block of frames at a time, its atan2 together
            let mut v = [Vector3::zeros(); BLOCK];
            let (mut s, mut w, mut half) = ([0.0; BLOCK], [0.0; BLOCK], [0.0; BLOCK]);
            for k0 in (1..n - 1).step_by(BLOCK) {
                let m = BLOCK.min(n - 1 - k0);
                for d in 0..m {
                    let k = k0 + d;
                    (v[d], s[d], w[d]) = quat_log_parts(&(q[k - 1].inverse() * q[k + 1]));
                }
                atan2_many(&s[..m], &w[..m], &mut half);
                out.extend((0..m).map(|d| quat_log_from(v[d], s[d], w[d], half[d]) / (2.0 * dt)));
            }
            out.push(-(4.0 * diff(n - 1, n - 2) - diff(n - 1, n - 3)) / (2.0 * dt));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::FRAC_PI_2;

    /// The hinges' axes read from the rotation are the axes of the angles on either branch,
    /// whatever the turns added, near the lock and far from it, in every order.
    #[test]
    fn hinge_axes_from_the_rotation_are_the_angles_axes() {
        use crate::rotation::{euler_to_quaternion, hinge_axes};
        use std::f64::consts::PI;
        fn at<const I: usize, const J: usize, const K: usize>(
            r: &Matrix3<f64>,
            x: [f64; 3],
        ) -> Matrix3<f64> {
            hinge_axes_at::<I, J, K>(r, x)
        }
        let mut worst: f64 = 0.0;
        for order in EulerOrder::ALL {
            for a2 in [
                0.0,
                0.4,
                -1.2,
                1.55,
                FRAC_PI_2 - 0.011,
                FRAC_PI_2 - 0.009,
                -FRAC_PI_2 + 2e-4,
            ] {
                for (a1, a3) in [(0.3, -2.1), (-2.9, 0.7), (1.6, 3.0)] {
                    let x = [a1, a2, a3];
                    let r = euler_to_quaternion(order, x)
                        .to_rotation_matrix()
                        .into_inner();
                    // the other branch, and whole turns on every angle
                    let other = [a1 + PI, PI - a2, a3 + PI];
                    let turned = [a1 - 2.0 * PI, a2 + 4.0 * PI, a3 + 2.0 * PI];
                    for y in [x, other, turned] {
                        let want = hinge_axes(Matrix3::identity(), order, y);
                        let got = with_axes!(order, at(&r, y));
                        worst = worst.max((got - want).amax());
                    }
                }
            }
        }
        assert!(worst < 1e-13, "{worst:e}");
    }

    /// The one pass after the filter (angles written back and rates from the same matrices)
    /// gives what smoothing then differentiating give, bit for bit: the angles, v, a and the
    /// frames left at gimbal lock, in every order, with and without smoothing, on a motion
    /// that turns several times, flips branch and passes through the lock.
    #[test]
    fn smoothing_with_rates_is_smoothing_then_rates_bit_for_bit() {
        let n = 300;
        let dt = 1.0 / 120.0;
        let specs = [
            SmoothSpec::None,
            SmoothSpec::Butterworth {
                cutoff_hz: 6.0,
                order: 2,
            },
            SmoothSpec::Gaussian { sigma_s: 0.02 },
        ];
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        let mut left_somewhere = false;
        for order in EulerOrder::ALL {
            for spec in specs {
                let angles: Vec<[f64; 3]> = (0..n)
                    .map(|k| {
                        let t = k as f64 * dt;
                        let a2 = if (140..150).contains(&k) {
                            FRAC_PI_2 // at the lock for ten frames
                        } else {
                            1.2 * (3.0 * t).sin() + 0.3
                        };
                        [9.0 * t - 2.0, a2, -4.0 * (2.0 * t).cos()]
                    })
                    .collect();
                let col = |a: usize| angles.iter().map(|x| x[a]).collect::<Vec<_>>();
                let (mut c0, mut c1, mut c2) = (col(0), col(1), col(2));
                let (mut d0, mut d1, mut d2) = (c0.clone(), c1.clone(), c2.clone());
                // smoothing, then the rates from its rotations
                let mut smoother = Smoother::new(spec, dt).unwrap();
                let mut rotations = vec![UnitQuaternion::identity(); n];
                smooth_triple(
                    &mut smoother,
                    order,
                    [&mut c0, &mut c1, &mut c2],
                    &mut rotations,
                );
                let mut s = TripleScratch::with_capacity(n);
                let (mut v, mut a) = (vec![7.0; 3 * n], vec![7.0; 3 * n]);
                let left = {
                    let (v0, r) = v.split_at_mut(n);
                    let (v1, v2) = r.split_at_mut(n);
                    let (a0, r) = a.split_at_mut(n);
                    let (a1, a2) = r.split_at_mut(n);
                    let q = [&c0[..], &c1[..], &c2[..]];
                    triple_rates(
                        &mut s,
                        order,
                        q,
                        Some(&rotations),
                        dt,
                        [v0, v1, v2],
                        [a0, a1, a2],
                    )
                };
                // the one pass
                let mut smoother = Smoother::new(spec, dt).unwrap();
                let mut s = TripleScratch::with_capacity(n);
                let (mut w, mut b) = (vec![7.0; 3 * n], vec![7.0; 3 * n]);
                let left_too = {
                    let (v0, r) = w.split_at_mut(n);
                    let (v1, v2) = r.split_at_mut(n);
                    let (a0, r) = b.split_at_mut(n);
                    let (a1, a2) = r.split_at_mut(n);
                    let cols = [&mut d0[..], &mut d1[..], &mut d2[..]];
                    smooth_triple_and_rates(
                        &mut s,
                        &mut smoother,
                        order,
                        cols,
                        dt,
                        [v0, v1, v2],
                        [a0, a1, a2],
                    )
                };
                assert_eq!(left, left_too, "{order:?} {spec:?}");
                left_somewhere |= left > 0;
                for (x, y) in [(&c0, &d0), (&c1, &d1), (&c2, &d2), (&v, &w), (&a, &b)] {
                    assert_eq!(bits(x), bits(y), "{order:?} {spec:?}");
                }
            }
        }
        assert!(left_somewhere, "the motion reaches the lock");
    }

    #[test]
    fn cos_sign_is_the_sign_of_cos() {
        for k in -4000..4000 {
            let a = k as f64 * 0.01 + 0.003;
            assert_eq!(cos_sign(a), a.cos().signum(), "{a}");
        }
    }

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
