//! Rotations about the coordinate axes and Tait–Bryan ("Euler") angles in the six orders BVH
//! files use.
//!
//! Convention (the BVH one, see `io::bvh`): an order `c1 c2 c3` with angles `[a1, a2, a3]` (rad)
//! means `R = R_c1(a1) · R_c2(a2) · R_c3(a3)`, i.e. intrinsic rotations applied in the listed
//! order (equivalently extrinsic ones in the reverse order). `R` maps child-frame coordinates to
//! parent-frame coordinates; each `R_x(a)` is the right-handed (counter-clockwise) rotation.
//!
//! Extraction follows Shoemake (*Euler angle conversion*, Graphics Gems IV, 1994, pp. 222–229)
//! for the axis permutation and parity, with the numerically robust variant used by Eigen's
//! `MatrixBase::eulerAngles`: the first angle is taken from the third column, the matrix is
//! de-rotated by it, and the remaining two angles are read from the de-rotated matrix. Whatever
//! the first angle (even at gimbal lock, where it is arbitrary), the triple reproduces `R` to
//! rounding.

use crate::spatial::{atan2, sin_cos};
use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};
use std::f64::consts::PI;

/// One of the six Tait–Bryan orders (three distinct axes), named by its channel order:
/// `ZXY` is `Zrotation Xrotation Yrotation`, i.e. `R = R_z(a1) · R_x(a2) · R_y(a3)`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EulerOrder {
    XYZ,
    XZY,
    YXZ,
    YZX,
    ZXY,
    ZYX,
}

impl EulerOrder {
    /// All six orders.
    pub const ALL: [EulerOrder; 6] = [
        EulerOrder::XYZ,
        EulerOrder::XZY,
        EulerOrder::YXZ,
        EulerOrder::YZX,
        EulerOrder::ZXY,
        EulerOrder::ZYX,
    ];

    /// Axis indices (0 = X, 1 = Y, 2 = Z) in application order.
    pub fn axes(self) -> [usize; 3] {
        match self {
            EulerOrder::XYZ => [0, 1, 2],
            EulerOrder::XZY => [0, 2, 1],
            EulerOrder::YXZ => [1, 0, 2],
            EulerOrder::YZX => [1, 2, 0],
            EulerOrder::ZXY => [2, 0, 1],
            EulerOrder::ZYX => [2, 1, 0],
        }
    }

    /// The order whose axes are `axes` (e.g. the axes of a joint's rotation channels in file
    /// order); `None` unless they are three distinct axes in `0..3`.
    pub fn from_axes(axes: [usize; 3]) -> Option<EulerOrder> {
        EulerOrder::ALL.into_iter().find(|o| o.axes() == axes)
    }

    /// `XYZ`, `ZXY`, ...
    pub fn name(self) -> &'static str {
        match self {
            EulerOrder::XYZ => "XYZ",
            EulerOrder::XZY => "XZY",
            EulerOrder::YXZ => "YXZ",
            EulerOrder::YZX => "YZX",
            EulerOrder::ZXY => "ZXY",
            EulerOrder::ZYX => "ZYX",
        }
    }

    /// +1 when the axes are an even (cyclic) permutation of X, Y, Z, −1 otherwise.
    fn parity(self) -> f64 {
        match self {
            EulerOrder::XYZ | EulerOrder::YZX | EulerOrder::ZXY => 1.0,
            _ => -1.0,
        }
    }
}

impl std::fmt::Display for EulerOrder {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Right-handed rotation by `angle` (rad) about coordinate axis `axis` (0 = X, 1 = Y, 2 = Z).
///
/// Panics if `axis > 2` (a programming error, not bad input).
pub fn axis_rotation(axis: usize, angle: f64) -> Matrix3<f64> {
    let (s, c) = angle.sin_cos();
    match axis {
        0 => Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c),
        1 => Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c),
        2 => Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0),
        _ => panic!("axis_rotation: axis {axis} is not 0, 1 or 2"),
    }
}

/// `R = R_c1(a1) · R_c2(a2) · R_c3(a3)` for `order = c1 c2 c3`, angles in radians.
pub fn euler_to_matrix(order: EulerOrder, angles: [f64; 3]) -> Matrix3<f64> {
    let [i, j, k] = order.axes();
    axis_rotation(i, angles[0]) * axis_rotation(j, angles[1]) * axis_rotation(k, angles[2])
}

/// The unit quaternion of `euler_to_matrix(order, angles)`: the product of the three axis
/// quaternions `(cos a/2, sin a/2 · e_axis)`, without the matrix.
pub fn euler_to_quaternion(order: EulerOrder, angles: [f64; 3]) -> UnitQuaternion<f64> {
    euler_to_quaternion_axes(order.axes(), angles)
}

/// [`euler_to_quaternion`] for the axes `ax`, three different ones (inlined, so constant axes
/// fold away: see [`with_axes`]). The product written out for axis quaternions, without the
/// multiplications by their zero components that a general quaternion product makes (a
/// floating-point `0·x` cannot be folded away): `(c₁ + s₁eᵢ)(c₂ + s₂eⱼ) = c₁c₂ + s₁c₂eᵢ +
/// c₁s₂eⱼ + p s₁s₂eₖ` (`eᵢeⱼ = p eₖ`, `p` the order's parity), then times `c₃ + s₃eₖ`.
#[inline(always)]
pub fn euler_to_quaternion_axes(ax: [usize; 3], angles: [f64; 3]) -> UnitQuaternion<f64> {
    euler_half_angles_to_quaternion(ax, angles.map(|a| sin_cos(0.5 * a)))
}

/// [`euler_to_quaternion_axes`] from the sines and cosines of the half angles, `(sin a/2,
/// cos a/2)` for each of the three (computed elsewhere, several frames at once:
/// `motion::euler::triple_rotations`).
#[inline(always)]
pub fn euler_half_angles_to_quaternion(
    ax: [usize; 3],
    half: [(f64, f64); 3],
) -> UnitQuaternion<f64> {
    let [i, j, k] = ax;
    debug_assert!(i != j && j != k && k != i, "a Tait–Bryan order");
    let [(s1, c1), (s2, c2), (s3, c3)] = half;
    let p = if j == (i + 1) % 3 { 1.0 } else { -1.0 };
    let (w, mut v) = (c1 * c2, [0.0; 3]);
    (v[i], v[j], v[k]) = (s1 * c2, c1 * s2, p * s1 * s2);
    // (w + v)(c₃ + s₃eₖ) = w c₃ − s₃vₖ + c₃v + s₃w eₖ + s₃ v × eₖ, with
    // v × eₖ = vⱼ eⱼ × eₖ + vᵢ eᵢ × eₖ = p vⱼ eᵢ − p vᵢ eⱼ
    let mut out = [0.0; 3];
    out[i] = c3 * v[i] + p * s3 * v[j];
    out[j] = c3 * v[j] - p * s3 * v[i];
    out[k] = c3 * v[k] + s3 * w;
    UnitQuaternion::new_unchecked(Quaternion::new(w * c3 - s3 * v[k], out[0], out[1], out[2]))
}

/// The rotation vector `θ·n` of `q` (angle θ ∈ [0, π] about the unit axis n, rad), i.e.
/// `2 · log(q)` for the quaternion logarithm, the SO(3) logarithm: `q = exp(θ n / 2)`. Chooses
/// the shortest arc (`q` and `−q` give the same result). Accurate near the identity (a
/// first-order series below 1e-12 rad).
#[inline]
pub fn quat_log(q: &UnitQuaternion<f64>) -> Vector3<f64> {
    let (v, s, w) = quat_log_parts(q);
    if s < 1e-12 {
        return quat_log_from(v, s, w, 0.0);
    }
    quat_log_from(v, s, w, atan2(s, w))
}

/// The parts of [`quat_log`] before its `atan2`: `q`'s vector part `v` and scalar part `w`
/// on the hemisphere `w ≥ 0`, and `s = |v|`; the logarithm is [`quat_log_from`]`(v, s, w,
/// atan2(s, w))`. For the logarithms of several frames at once (`motion::euler`).
#[inline(always)]
pub fn quat_log_parts(q: &UnitQuaternion<f64>) -> (Vector3<f64>, f64, f64) {
    let (mut w, mut v) = (q.w, q.imag());
    if w < 0.0 {
        w = -w;
        v = -v;
    }
    (v, v.norm(), w)
}

/// [`quat_log`] from its [`quat_log_parts`] and `half = atan2(s, w)` (half the angle; not
/// read below `s < 1e-12`).
#[inline(always)]
pub fn quat_log_from(v: Vector3<f64>, s: f64, w: f64, half: f64) -> Vector3<f64> {
    if s < 1e-12 {
        // θ ≈ 2s, n = v/s: θ n ≈ 2v/w
        return v * (2.0 / w);
    }
    v * (2.0 * half / s)
}

/// The unit quaternion of the rotation vector `r = θ·n` (inverse of [`quat_log`]).
#[inline]
pub fn quat_exp(r: &Vector3<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::from_scaled_axis(*r)
}

/// Calls `$f::<I, J, K>($args…)` with the axes of `$order` as constants: the per-frame loops
/// of the euler model's rotations ([`euler_to_quaternion_axes`],
/// [`matrix_to_euler_fast_axes`]) compiled once per order, their axis indices folded away
/// (the same floating-point operations in the same order, so the same bits).
macro_rules! with_axes {
    ($order:expr, $f:ident ( $($arg:expr),* $(,)? )) => {
        match $order {
            $crate::rotation::EulerOrder::XYZ => $f::<0, 1, 2>($($arg),*),
            $crate::rotation::EulerOrder::XZY => $f::<0, 2, 1>($($arg),*),
            $crate::rotation::EulerOrder::YXZ => $f::<1, 0, 2>($($arg),*),
            $crate::rotation::EulerOrder::YZX => $f::<1, 2, 0>($($arg),*),
            $crate::rotation::EulerOrder::ZXY => $f::<2, 0, 1>($($arg),*),
            $crate::rotation::EulerOrder::ZYX => $f::<2, 1, 0>($($arg),*),
        }
    };
}
pub(crate) use with_axes;

/// Rotation `angle` about coordinate `axis` given its sine and cosine ([`axis_rotation`]
/// without the trigonometry).
fn axis_rotation_sc(axis: usize, s: f64, c: f64) -> Matrix3<f64> {
    match axis {
        0 => Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c),
        1 => Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c),
        _ => Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0),
    }
}

/// [`matrix_to_euler`] with the first angle's sine and cosine read from the matrix instead
/// of computed from the angle: the same angles to rounding, one `sin_cos` fewer.
pub fn matrix_to_euler_fast(order: EulerOrder, r: &Matrix3<f64>) -> [f64; 3] {
    matrix_to_euler_fast_axes(order.axes(), r)
}

/// [`matrix_to_euler_fast`] for the axes `ax` (inlined, so constant axes fold away: see
/// [`with_axes`]).
#[inline(always)]
pub fn matrix_to_euler_fast_axes(ax: [usize; 3], r: &Matrix3<f64>) -> [f64; 3] {
    let (args, first) = matrix_to_euler_fast_args(ax, r);
    let [a1, a2, a3] = args.map(|(y, x)| atan2(y, x));
    [if first { a1 } else { 0.0 }, a2, a3]
}

/// The arguments `(y, x)` of the three `atan2` that give [`matrix_to_euler_fast_axes`]'s
/// angles, and whether the first angle is its `atan2` (else 0: at gimbal lock, where the
/// third column leaves it undetermined). For the angles of several frames at once
/// (`motion::euler`'s write-back).
#[inline(always)]
pub fn matrix_to_euler_fast_args(ax: [usize; 3], r: &Matrix3<f64>) -> ([(f64, f64); 3], bool) {
    let [i, j, k] = ax;
    // the parity: +1 for the cyclic orders XYZ, YZX, ZXY
    let s = if j == (i + 1) % 3 { 1.0 } else { -1.0 };
    // entries of a rotation: no overflow or underflow for `hypot` to guard against
    let h = (r[(j, k)] * r[(j, k)] + r[(k, k)] * r[(k, k)]).sqrt();
    let first = h > 1e-12;
    let (y1, x1) = (-s * r[(j, k)], r[(k, k)]);
    let (s1, c1) = if first { (y1 / h, x1 / h) } else { (0.0, 1.0) };
    let m = axis_rotation_sc(i, s1, c1).transpose() * r;
    let args = [
        (y1, x1),
        (s * m[(i, k)], m[(k, k)]),
        (s * m[(j, i)], m[(j, j)]),
    ];
    (args, first)
}

/// The axes of three hinges `R = before · R_c1(q1) R_c2(q2) R_c3(q3)` (a BVH joint of the euler
/// model, or its root under the rotation `before`), as columns in the frame `before` is
/// expressed in: `w_n = before · R_c1 ⋯ R_c(n−1) e_cn`. The angular velocity of the last hinge's
/// body relative to that frame is `ω = H q̇`; `det H = ±cos q2`, zero at gimbal lock.
pub fn hinge_axes(before: Matrix3<f64>, order: EulerOrder, q: [f64; 3]) -> Matrix3<f64> {
    let ax = order.axes();
    let mut r = before;
    let mut cols = [Vector3::zeros(); 3];
    for n in 0..3 {
        cols[n] = r.column(ax[n]).into_owned();
        r *= axis_rotation(ax[n], q[n]);
    }
    Matrix3::from_columns(&cols)
}

/// The angular velocity and acceleration of the last of three hinges ([`hinge_axes`]):
/// `ω = Σ w_n q̇_n`, `α = Σ w_n q̈_n + Σ ω_(<n) × w_n q̇_n` (each axis turns with the hinges
/// before it, `ẇ_n = ω_(<n) × w_n`).
pub fn hinge_rates(
    before: Matrix3<f64>,
    order: EulerOrder,
    q: [f64; 3],
    dq: [f64; 3],
    ddq: [f64; 3],
) -> (Vector3<f64>, Vector3<f64>) {
    let axes = hinge_axes(before, order, q);
    let (mut w, mut dw) = (Vector3::zeros(), Vector3::zeros());
    for n in 0..3 {
        let axis = axes.column(n).into_owned();
        dw += axis * ddq[n] + w.cross(&axis) * dq[n];
        w += axis * dq[n];
    }
    (w, dw)
}

/// The inverse of [`hinge_rates`] at the hinges' `axes` (`H`): `q̇ = H⁻¹ ω` and
/// `q̈ = H⁻¹ (α − Ḣ q̇)`, with `Ḣ q̇ = Σ ω_(<n) × w_n q̇_n` at the new rates. `None` when
/// `|det H| < min_det` (within that `|cos|` of gimbal lock the rates grow without bound).
pub fn hinge_coordinate_rates(
    axes: &Matrix3<f64>,
    w: &Vector3<f64>,
    dw: &Vector3<f64>,
    min_det: f64,
) -> Option<(Vector3<f64>, Vector3<f64>)> {
    if axes.determinant().abs() < min_det {
        return None;
    }
    let inverse = axes.try_inverse()?;
    let dq = inverse * w;
    let w0 = axes.column(0) * dq[0];
    let bias = w0.cross(&axes.column(1)) * dq[1]
        + (w0 + axes.column(1) * dq[1]).cross(&axes.column(2)) * dq[2];
    Some((dq, inverse * (dw - bias)))
}

/// Angles `[a1, a2, a3]` (rad) with `euler_to_matrix(order, angles) ≈ r`, for a rotation
/// matrix `r`: `a2 ∈ [−π/2, π/2]`, `a1, a3 ∈ [−π, π]`. At gimbal lock (`|a2| = π/2`) only a
/// combination of `a1` and `a3` is determined; the split returned is the one the third column
/// happens to give (usually `a1 ≈ 0`); use [`matrix_to_euler_near`] for continuity.
pub fn matrix_to_euler(order: EulerOrder, r: &Matrix3<f64>) -> [f64; 3] {
    let [_, j, k] = order.axes();
    let s = order.parity();
    // third column: r e_k = R_i(a1) R_j(a2) e_k; its j and k rows give a1 (up to cos a2 ≥ 0)
    let a1 = if r[(j, k)].hypot(r[(k, k)]) > 1e-12 {
        atan2(-s * r[(j, k)], r[(k, k)])
    } else {
        0.0
    };
    let (a2, a3) = rest_after_first(order, r, a1);
    [a1, a2, a3]
}

/// Given the first angle, the two others from `M = R_i(a1)ᵀ · r = R_j(a2) · R_k(a3)`:
/// `M e_k = e_k cos a2 + s e_i sin a2` and row j of `M` is row j of `R_k(a3)`.
fn rest_after_first(order: EulerOrder, r: &Matrix3<f64>, a1: f64) -> (f64, f64) {
    let [i, j, k] = order.axes();
    let s = order.parity();
    let m = axis_rotation(i, a1).transpose() * r;
    let a2 = atan2(s * m[(i, k)], m[(k, k)]);
    let a3 = atan2(s * m[(j, i)], m[(j, j)]);
    (a2, a3)
}

/// Like [`matrix_to_euler`], but returns the equivalent triple nearest to `previous` (e.g. the
/// angles of the previous frame): among the two Tait–Bryan branches `(a1, a2, a3)` and
/// `(a1 + π, π − a2, a3 + π)`, each angle shifted by whole turns to lie within π of
/// `previous`, the one with the smallest squared distance. At gimbal lock, where a whole
/// family of triples gives `r`, `a1` is held at `previous[0]` and the others follow, so the
/// angles stay continuous through the pole. The result may lie outside ±π (unwrapped).
pub fn matrix_to_euler_near(order: EulerOrder, r: &Matrix3<f64>, previous: [f64; 3]) -> [f64; 3] {
    let [i, j, _] = order.axes();
    // |cos a2| from row i: r[i][i] = cos a2 cos a3, r[i][j] = −s cos a2 sin a3
    let cos_a2 = r[(i, i)].hypot(r[(i, j)]);
    let [a1, a2, a3] = if cos_a2 < 1e-9 {
        let a1 = previous[0];
        let (a2, a3) = rest_after_first(order, r, a1);
        [a1, a2, a3]
    } else {
        matrix_to_euler(order, r)
    };
    nearest_branch([a1, a2, a3], previous)
}

/// Of the triple `a` and its other Tait–Bryan branch `(a1 + π, π − a2, a3 + π)` (the same
/// rotation), each angle shifted by whole turns to lie within π of `previous`, the one with
/// the smallest squared distance to `previous` (the first on a tie). Away from gimbal lock
/// these are all the triples of `a`'s rotation, so this is [`matrix_to_euler_near`] of `a`'s
/// matrix without the trip through the matrix (and without its rounding).
pub fn nearest_branch(a: [f64; 3], previous: [f64; 3]) -> [f64; 3] {
    let [a1, a2, a3] = a;
    let candidates = [[a1, a2, a3], [a1 + PI, PI - a2, a3 + PI]];
    let mut best = [0.0; 3];
    let mut best_d = f64::INFINITY;
    for c in candidates {
        let shifted = [
            nearest_turn(c[0], previous[0]),
            nearest_turn(c[1], previous[1]),
            nearest_turn(c[2], previous[2]),
        ];
        let d: f64 = (0..3).map(|n| (shifted[n] - previous[n]).powi(2)).sum();
        if d < best_d {
            best_d = d;
            best = shifted;
        }
    }
    best
}

/// `angle + 2πn` for the integer `n` that brings it nearest to `target`.
fn nearest_turn(angle: f64, target: f64) -> f64 {
    let turns = round_turns((target - angle) / (2.0 * PI));
    angle + turns * 2.0 * PI
}

/// `x.round()` (half away from zero), bit for bit, without the library call in the common case
/// of angle continuity, `|x| < 0.5`: there it is zero with the sign of `x`, as `round` gives
/// (`round(−0.3) = −0`). NaN goes to `round`.
#[inline]
pub fn round_turns(x: f64) -> f64 {
    if x.abs() < 0.5 {
        0.0f64.copysign(x)
    } else {
        x.round()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn quarter_turns_are_right_handed() {
        let x = Vector3::x();
        let y = Vector3::y();
        let z = Vector3::z();
        let q = PI / 2.0;
        assert!((axis_rotation(2, q) * x - y).norm() < 1e-15);
        assert!((axis_rotation(0, q) * y - z).norm() < 1e-15);
        assert!((axis_rotation(1, q) * z - x).norm() < 1e-15);
    }

    #[test]
    fn order_is_intrinsic_in_listed_order() {
        // ZXY: R = Rz(a) Rx(b) Ry(c); a vector along child y rotated by Ry (no change),
        // then Rx(90°) sends y to z, then Rz(90°) leaves z alone.
        let r = euler_to_matrix(EulerOrder::ZXY, [PI / 2.0, PI / 2.0, 0.3]);
        assert!((r * Vector3::y() - Vector3::z()).norm() < 1e-15);
        for o in EulerOrder::ALL {
            assert_eq!(EulerOrder::from_axes(o.axes()), Some(o));
        }
        assert_eq!(EulerOrder::from_axes([0, 0, 1]), None);
    }

    #[test]
    fn the_quaternion_of_a_triple_is_its_matrix() {
        for o in EulerOrder::ALL {
            let a = [0.3, -1.2, 2.5];
            let q = euler_to_quaternion(o, a);
            assert!((q.to_rotation_matrix().into_inner() - euler_to_matrix(o, a)).norm() < 1e-14);
            // the product of the three axis quaternions
            let axis_q =
                |n: usize| UnitQuaternion::from_axis_angle(&Vector3::ith_axis(o.axes()[n]), a[n]);
            let general = axis_q(0) * axis_q(1) * axis_q(2);
            assert!(
                (q.into_inner() - general.into_inner()).norm() < 1e-15,
                "{o}"
            );
            let r = euler_to_matrix(o, a);
            let fast = matrix_to_euler_fast(o, &r);
            let slow = matrix_to_euler(o, &r);
            assert!(
                (0..3).all(|n| (fast[n] - slow[n]).abs() < 1e-12),
                "{fast:?} {slow:?}"
            );
        }
    }

    #[test]
    fn hinge_coordinate_rates_invert_hinge_rates() {
        let before = euler_to_matrix(EulerOrder::YXZ, [0.4, 0.2, -0.7]);
        for o in EulerOrder::ALL {
            let (q, dq, ddq) = ([0.3, 1.4, -2.0], [1.1, -0.4, 2.2], [-3.0, 0.5, 1.7]);
            let (w, dw) = hinge_rates(before, o, q, dq, ddq);
            let axes = hinge_axes(before, o, q);
            let (v, a) = hinge_coordinate_rates(&axes, &w, &dw, 1e-7).unwrap();
            for n in 0..3 {
                assert!((v[n] - dq[n]).abs() < 1e-12 && (a[n] - ddq[n]).abs() < 1e-11);
            }
            let locked = hinge_axes(before, o, [0.3, std::f64::consts::FRAC_PI_2, -2.0]);
            assert!(hinge_coordinate_rates(&locked, &w, &dw, 1e-7).is_none());
        }
    }
}
