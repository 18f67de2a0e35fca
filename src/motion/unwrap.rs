//! Continuity of angle trajectories, before any smoothing or differentiation.
//!
//! Captures store each Euler angle in a bounded range (usually ±180°), so an angle that keeps
//! turning jumps by a full turn; and near gimbal lock (middle angle ±90°) the decomposition of a
//! rotation into a triple flips between the two equivalent triples `(a, b, c)` and
//! `(a ± 180°, 180° − b, c ± 180°)`. Both jumps are artefacts: the rotation itself moves
//! smoothly. Differentiating them gives spikes of thousands of degrees per second.
//!
//! [`unwrap_angles`] removes full turns from one angle; [`make_euler_continuous`] re-picks
//! whole triples, which also handles the branch flips. What no re-pick can remove is a true
//! passage near gimbal lock: there the triple itself must turn fast while the rotation moves
//! little, and the euler joint model's velocities, accelerations and torques spike;
//! [`scan_triples`] finds it (the ball joint model has no such coordinates), and also a rotation
//! that jumps more than any joint can turn in one frame: a capture glitch.

use crate::rotation::{
    EulerOrder, euler_to_matrix, matrix_to_euler_near, nearest_branch, round_turns,
};
use nalgebra::Matrix3;

/// The unit of an angle trajectory: the period of a full turn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AngleUnit {
    /// Full turn = 360 (BVH channels).
    Degrees,
    /// Full turn = 2π (q).
    Radians,
}

impl AngleUnit {
    /// A full turn in this unit.
    pub fn full_turn(self) -> f64 {
        match self {
            AngleUnit::Degrees => 360.0,
            AngleUnit::Radians => std::f64::consts::TAU,
        }
    }
}

/// Removes full-turn jumps in place: every frame is shifted by a whole number of turns so that
/// it differs from the (already unwrapped) previous frame by at most half a turn (the classic
/// phase unwrapping, as NumPy's `unwrap`). The first frame is kept. Allocates nothing.
pub fn unwrap_angles(unit: AngleUnit, x: &mut [f64]) {
    let turn = unit.full_turn();
    let step = |x: &mut [f64], k: usize| {
        let d = x[k] - x[k - 1];
        x[k] -= turn * round_turns(d / turn);
    };
    // the common case, every step under half a turn (the Euler triples re-picked before this,
    // most captured channels), in one pass without the loop's chain of divisions from frame
    // to frame: there each frame's shift is `turn · round_turns(d / turn)`, a zero with the
    // sign of the step `d`, which leaves a value as it is, but turns −0 into +0 where the
    // zero is −0 (−0 − (−0) = +0): a zero value whose step from the previous (already
    // unwrapped) value has its sign bit set becomes +0 (no division)
    let mut small = true;
    for k in 1..x.len() {
        small &= (x[k] - x[k - 1]).abs() < 0.49 * turn;
    }
    if small {
        for k in 1..x.len() {
            if x[k] == 0.0 && (x[k] - x[k - 1]).is_sign_negative() {
                x[k] = 0.0;
            }
        }
        return;
    }
    for k in 1..x.len() {
        step(x, k);
    }
}

/// Makes a trajectory of Euler triples (radians, `R = R_c1(a1) R_c2(a2) R_c3(a3)` for
/// `order = c1 c2 c3`) continuous in place: every frame after the first is replaced by the
/// triple of the same rotation nearest to the previous (already continuous) frame
/// ([`repick`]: both Tait–Bryan branches, whole-turn shifts, and at gimbal lock the first
/// angle held). This removes both full-turn jumps and branch flips near
/// the singularity; the rotations themselves are unchanged. Allocates nothing.
pub fn make_euler_continuous(order: EulerOrder, frames: &mut [[f64; 3]]) {
    for k in 1..frames.len() {
        let r = euler_to_matrix(order, frames[k]);
        frames[k] = repick(order, &r, frames[k], frames[k - 1]);
    }
}

/// The triple of rotation `r` (given as the triple `x`) nearest to `previous`. Away from
/// gimbal lock (`|cos a2| ≥` [`LOCK_COS`]) the triples of a rotation are `x` and its other
/// branch, each shifted by whole turns, so this is
/// [`rotation::nearest_branch`](crate::rotation::nearest_branch) of `x`: what
/// `matrix_to_euler_near(order, r, previous)` picks, without the rounding of the trip through
/// the matrix (the two agree to a few ulps, `tests/motion_unwrap.rs`). Near the lock it is
/// `matrix_to_euler_near`, which holds the first angle there.
#[inline]
pub fn repick(order: EulerOrder, r: &Matrix3<f64>, x: [f64; 3], previous: [f64; 3]) -> [f64; 3] {
    let [i, j, _] = order.axes();
    // |cos a2| from row i: r[i][i] = cos a2 cos a3, r[i][j] = −s cos a2 sin a3
    let cos_a2 = (r[(i, i)] * r[(i, i)] + r[(i, j)] * r[(i, j)]).sqrt();
    if cos_a2 >= LOCK_COS {
        nearest_branch(x, previous)
    } else {
        matrix_to_euler_near(order, r, previous)
    }
}

/// Below this `|cos a2|` (the middle angle within about 0.0006° of ±90°) [`repick`] goes
/// through the rotation matrix, which holds the first angle at gimbal lock
/// (`matrix_to_euler_near` does below 1e-9).
pub const LOCK_COS: f64 = 1e-5;

/// A frame step where a continuous Euler triple turns much faster than the rotation it
/// describes: near gimbal lock.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GimbalPassage {
    /// The step from frame `frame` to `frame + 1`.
    pub frame: usize,
    /// The largest change of one of the three angles over that step (rad).
    pub coordinate_step: f64,
    /// The rotation's own change over that step: the angle of `R_kᵀ R_k+1` (rad).
    pub rotation_step: f64,
}

/// What [`scan_triples`] finds in one joint's continuous Euler triples.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TripleScan {
    /// The worst step where one angle changes by more than 30° and more than 5 times the
    /// rotation itself: a passage near gimbal lock, where the euler joint model's derivatives
    /// spike.
    pub passage: Option<GimbalPassage>,
    /// The step where the rotation itself turns most, `(frame, angle in rad)`, when that is
    /// over 90° in one frame: no joint does that (over 2,700°/s at 30 fps), a capture glitch
    /// (a marker or solver swap) does.
    pub jump: Option<(usize, f64)>,
}

/// Scans `frames` (angles in rad, continuous as [`make_euler_continuous`] leaves them) for
/// passages near gimbal lock and implausible jumps of the rotation. Allocates nothing.
pub fn scan_triples(order: EulerOrder, frames: &[[f64; 3]]) -> TripleScan {
    let mut out = TripleScan::default();
    let Some(first) = frames.first() else {
        return out;
    };
    let mut prev = euler_to_matrix(order, *first);
    for k in 1..frames.len() {
        let r = euler_to_matrix(order, frames[k]);
        out.step(k, &prev, &r, frames[k - 1], frames[k]);
        prev = r;
    }
    out
}

/// [`make_euler_continuous`] and [`scan_triples`] in one pass, what the pipeline runs (on
/// columns: [`make_euler_columns_continuous_and_scan`]). Allocates nothing.
pub fn make_euler_continuous_and_scan(order: EulerOrder, frames: &mut [[f64; 3]]) -> TripleScan {
    continuous_and_scan(order, frames)
}

/// [`make_euler_continuous_and_scan`] on a joint's three angle columns (frame `k`'s triple is
/// `[c0[k], c1[k], c2[k]]`, all of one length), as the pipeline stores coordinates: the
/// same triples and the same scan, bit for bit. Allocates nothing.
pub fn make_euler_columns_continuous_and_scan(
    order: EulerOrder,
    cols: [&mut [f64]; 3],
) -> TripleScan {
    let [c0, c1, c2] = cols;
    let n = c0.len().min(c1.len()).min(c2.len());
    let mut columns = [&mut c0[..n], &mut c1[..n], &mut c2[..n]];
    continuous_and_scan(order, &mut columns)
}

/// Frames of Euler triples, however they are stored.
trait Triples {
    fn len(&self) -> usize;
    fn get(&self, k: usize) -> [f64; 3];
    fn set(&mut self, k: usize, x: [f64; 3]);
}

impl Triples for [[f64; 3]] {
    fn len(&self) -> usize {
        <[[f64; 3]]>::len(self)
    }
    #[inline]
    fn get(&self, k: usize) -> [f64; 3] {
        self[k]
    }
    #[inline]
    fn set(&mut self, k: usize, x: [f64; 3]) {
        self[k] = x;
    }
}

impl Triples for [&mut [f64]; 3] {
    fn len(&self) -> usize {
        self[0].len()
    }
    #[inline]
    fn get(&self, k: usize) -> [f64; 3] {
        [self[0][k], self[1][k], self[2][k]]
    }
    #[inline]
    fn set(&mut self, k: usize, x: [f64; 3]) {
        (self[0][k], self[1][k], self[2][k]) = (x[0], x[1], x[2]);
    }
}

/// The one loop of the re-pick and scan. Per frame, in the common case (middle angle away
/// from gimbal lock, every angle within 45° of the previous frame's, the rotation's step too
/// small to be a passage or a jump) it is a few additions: no rotation matrix, no trig.
/// Otherwise it computes exactly what the trip through the matrices computes:
/// - the re-pick ([`repick_fast`]) goes through the matrix only near the lock, where
///   [`repick`] does;
/// - the scan needs the rotation's own step (`acos` of the relative rotation's trace) only
///   where an angle moved more than 30° (a passage needs that) or the angles moved more than
///   90° in all (a jump needs the rotation to turn that much, and a rotation
///   `R_i(a1)R_j(a2)R_k(a3)` turns at most `|Δa1| + |Δa2| + |Δa3|`: the geodesic distance on
///   SO(3) is invariant and obeys the triangle inequality); the matrices are made from the
///   frames as given, as before.
fn continuous_and_scan<T: Triples + ?Sized>(order: EulerOrder, frames: &mut T) -> TripleScan {
    // margin for the rounding of the trace and acos against the bound (rad)
    const BOUND_MARGIN: f64 = 1e-6;
    let mut out = TripleScan::default();
    if frames.len() == 0 {
        return out;
    }
    // frame k − 1 as given (its matrix is what the scan compares) and as re-picked
    let mut given_prev = frames.get(0);
    let mut prev = given_prev;
    for k in 1..frames.len() {
        let given = frames.get(k);
        let x = repick_fast(order, given, prev);
        frames.set(k, x);
        let d = [
            (x[0] - prev[0]).abs(),
            (x[1] - prev[1]).abs(),
            (x[2] - prev[2]).abs(),
        ];
        let step = d[0].max(d[1]).max(d[2]);
        if step > TripleScan::MIN_STEP || d[0] + d[1] + d[2] > TripleScan::JUMP - BOUND_MARGIN {
            let (r0, r1) = (
                euler_to_matrix(order, given_prev),
                euler_to_matrix(order, given),
            );
            out.step(k, &r0, &r1, prev, x);
        }
        (given_prev, prev) = (given, x);
    }
    out
}

/// [`repick`] of the triple `x` without its rotation matrix where it is not needed: away
/// from gimbal lock ([`lock_distance`] over twice [`LOCK_COS`], where the matrix's
/// `|cos a2|` is surely at least `LOCK_COS`) [`nearest_branch`], and when every angle lies
/// within 45° of `previous` the triple itself, each angle plus a zero signed as
/// `nearest_branch`'s zero turns are (its other branch then lies more than 135° away in two
/// angles): the same bits as [`repick`]. Elsewhere [`repick`] with the matrix.
#[inline]
pub fn repick_fast(order: EulerOrder, x: [f64; 3], previous: [f64; 3]) -> [f64; 3] {
    let far = lock_distance(x[1]).is_some_and(|e| e > 2.0 * LOCK_COS);
    if !far {
        return repick(order, &euler_to_matrix(order, x), x, previous);
    }
    const CLOSE: f64 = std::f64::consts::FRAC_PI_4;
    if (0..3).all(|n| (x[n] - previous[n]).abs() < CLOSE) {
        // nearest_turn: x + round_turns((p − x)/2π)·2π, with round_turns = ±0 here
        return [0, 1, 2].map(|n| x[n] + 0.0f64.copysign(previous[n] - x[n]));
    }
    nearest_branch(x, previous)
}

/// How far (rad) the middle angle `a2` lies from gimbal lock, the nearest odd multiple of
/// π/2: `|cos a2| = sin(distance)`. `None` for `|a2| > 1e6` rad, where the reduction would
/// lose the digits that matter (and for NaN). Agrees with `acos(|cos a2|)` to about
/// `1e-16·|a2|`.
#[inline]
pub fn lock_distance(a2: f64) -> Option<f64> {
    use std::f64::consts::{FRAC_1_PI, FRAC_PI_2, PI};
    if a2.abs() > 1e6 || a2.is_nan() {
        return None;
    }
    let d = a2 - FRAC_PI_2;
    let t = d * FRAC_1_PI;
    // nearest integer (half away from zero; where rounding could pick the other neighbour, t
    // is a half and a2 is π/2 from the lock either way)
    let k = (t + 0.5f64.copysign(t)) as i64 as f64;
    Some((d - k * PI).abs())
}

impl TripleScan {
    /// An angle's step (rad) above which a step may be a passage near gimbal lock.
    const MIN_STEP: f64 = std::f64::consts::PI / 6.0;
    /// The rotation's step (rad) above which a step is a jump.
    const JUMP: f64 = std::f64::consts::FRAC_PI_2;

    /// The step from frame `k − 1` (rotation `prev`, angles `a`) to frame `k` (`r`, `b`).
    fn step(&mut self, k: usize, prev: &Matrix3<f64>, r: &Matrix3<f64>, a: [f64; 3], b: [f64; 3]) {
        const MIN_STEP: f64 = TripleScan::MIN_STEP;
        const MIN_RATIO: f64 = 5.0;
        const JUMP: f64 = TripleScan::JUMP;
        let cos = ((prev.transpose() * r).trace() - 1.0) / 2.0;
        let rotation_step = cos.clamp(-1.0, 1.0).acos();
        let step = (0..3).map(|i| (b[i] - a[i]).abs()).fold(0.0, f64::max);
        if step > MIN_STEP
            && step > MIN_RATIO * rotation_step
            && self
                .passage
                .is_none_or(|w| step / rotation_step > w.coordinate_step / w.rotation_step)
        {
            self.passage = Some(GimbalPassage {
                frame: k - 1,
                coordinate_step: step,
                rotation_step,
            });
        }
        if rotation_step > JUMP && self.jump.is_none_or(|(_, a)| rotation_step > a) {
            self.jump = Some((k - 1, rotation_step));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pass_near_gimbal_lock_is_found_and_a_smooth_turn_is_not() {
        // XYZ at b = 88°: Rx(θ)·Ry(b)·Rz(−θ) barely moves as θ sweeps (at b = 90° it would not
        // move at all), so the outer angles turn 40° a frame while the rotation turns 1.4°
        let order = EulerOrder::XYZ;
        let deg = |a: f64, b: f64, c: f64| [a.to_radians(), b.to_radians(), c.to_radians()];
        let mut frames: Vec<[f64; 3]> = (0..12)
            .map(|k| {
                let t = 40.0 * k as f64;
                deg(t, 88.0, -t)
            })
            .collect();
        make_euler_continuous(order, &mut frames);
        let scan = scan_triples(order, &frames);
        let p = scan.passage.expect("passage near gimbal lock");
        assert!(p.coordinate_step > 5.0 * p.rotation_step, "{p:?}");
        assert_eq!(scan.jump, None);
        // far from the singularity the same motion's coordinates follow the rotation
        let calm: Vec<[f64; 3]> = (0..12).map(|k| deg(40.0 * k as f64, 20.0, 10.0)).collect();
        assert_eq!(scan_triples(order, &calm), TripleScan::default());
        // a three-frame glitch: the rotation jumps 126° and back
        let mut glitch = calm.clone();
        glitch[5] = deg(200.0, 20.0, 10.0 + 126.0);
        glitch[6] = glitch[5];
        let scan = scan_triples(order, &glitch);
        let (frame, angle) = scan.jump.expect("jump");
        assert!(frame == 4 || frame == 6, "{frame}");
        assert!(angle > 90f64.to_radians(), "{angle}");
    }

    #[test]
    fn removes_turns_keeps_small_steps() {
        let mut x = [170.0, 179.0, -172.0, -165.0, 175.0, 10.0];
        unwrap_angles(AngleUnit::Degrees, &mut x);
        assert_eq!(x, [170.0, 179.0, 188.0, 195.0, 175.0, 10.0]);
    }

    /// The one-pass common case gives what the frame-by-frame loop gives, to the bit (signed
    /// zeros included), on walks with small steps through ±0 and with steps near half a turn.
    #[test]
    fn unwrapping_small_steps_is_the_loop_bit_for_bit() {
        fn by_loop(unit: AngleUnit, x: &mut [f64]) {
            let turn = unit.full_turn();
            for k in 1..x.len() {
                let d = x[k] - x[k - 1];
                x[k] -= turn * round_turns(d / turn);
            }
        }
        let walks: [&[f64]; 5] = [
            &[0.0, -0.0, -0.0, 0.1, -0.0, 0.0, -0.2, -0.0],
            &[-0.0, -0.0, 3.0, -3.0, 0.0, -0.0],
            &[1.0, 1.0 + 0.49 * std::f64::consts::TAU, -0.0, 2.0],
            &[179.0, -179.0, -0.0, 0.0, 176.3, -0.0],
            &[f64::NAN, 0.0, -0.0],
        ];
        // and random walks of small steps through signed zeros and tiny values
        let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
        let mut next = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
            seed >> 33
        };
        let picks = [0.0, -0.0, 1e-310, -1e-310, 0.25, -0.25, 1e-17, -1e-17];
        let random: Vec<Vec<f64>> = (0..200)
            .map(|_| {
                (0..40)
                    .map(|_| picks[next() as usize % picks.len()])
                    .collect()
            })
            .collect();
        for unit in [AngleUnit::Radians, AngleUnit::Degrees] {
            for w in walks.iter().copied().chain(random.iter().map(|w| &w[..])) {
                let (mut a, mut b) = (w.to_vec(), w.to_vec());
                unwrap_angles(unit, &mut a);
                by_loop(unit, &mut b);
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&a), bits(&b), "{w:?}");
            }
        }
    }
}
