//! Spatial (6D) algebra, pure math (MuJoCo's `mju_*`): motion and force vectors, rigid
//! transforms, spatial inertias.
//!
//! Conventions (Featherstone 2008, *Rigid Body Dynamics Algorithms*, ch. 2), stated once here:
//! - spatial vectors are **angular first**: a motion vector is `[ω; v]` (rad/s; m/s of the
//!   body-fixed point at the frame origin), a force vector `[n; f]` (N·m about the frame origin; N);
//! - a [`SpatialTransform`] `aXb` is the **pose of frame b in frame a** (Pinocchio's `aMb`):
//!   rotation `rot` (columns are b's axes in a's coordinates) and translation `trans` (b's origin
//!   in a's coordinates, m). `act` maps vectors from b coordinates to a coordinates, `act_inv`
//!   from a to b;
//! - a [`SpatialInertia`] is given in a body frame, about that frame's origin, from mass (kg),
//!   centre of mass `com` (m, body frame) and the rotational inertia about the COM (kg·m², body
//!   axes).

use nalgebra::{Matrix3, Matrix6, Quaternion, UnitQuaternion, Vector3, Vector6};

/// A spatial motion vector `[ω; v]` (angular first).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MotionVec {
    /// Angular velocity (rad/s) or acceleration (rad/s²).
    pub ang: Vector3<f64>,
    /// Linear velocity (m/s) or acceleration (m/s²) of the point at the frame origin.
    pub lin: Vector3<f64>,
}

/// A spatial force vector `[n; f]` (angular first).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct ForceVec {
    /// Moment about the frame origin (N·m).
    pub ang: Vector3<f64>,
    /// Force (N).
    pub lin: Vector3<f64>,
}

impl MotionVec {
    pub const ZERO: MotionVec = MotionVec {
        ang: Vector3::new(0.0, 0.0, 0.0),
        lin: Vector3::new(0.0, 0.0, 0.0),
    };
    pub fn new(ang: Vector3<f64>, lin: Vector3<f64>) -> Self {
        Self { ang, lin }
    }
    pub fn from_vector6(x: &Vector6<f64>) -> Self {
        Self::new(x.fixed_rows::<3>(0).into(), x.fixed_rows::<3>(3).into())
    }
    pub fn to_vector6(&self) -> Vector6<f64> {
        Vector6::new(
            self.ang.x, self.ang.y, self.ang.z, self.lin.x, self.lin.y, self.lin.z,
        )
    }
    /// Motion cross product `self ×ₘ m` (Featherstone eq. 2.31, `crm(self) * m`).
    #[inline]
    pub fn cross_motion(&self, m: &MotionVec) -> MotionVec {
        MotionVec {
            ang: self.ang.cross(&m.ang),
            lin: self.ang.cross(&m.lin) + self.lin.cross(&m.ang),
        }
    }
    /// Force cross product `self ×* f` (Featherstone eq. 2.32, `crf(self) * f`).
    #[inline]
    pub fn cross_force(&self, f: &ForceVec) -> ForceVec {
        ForceVec {
            ang: self.ang.cross(&f.ang) + self.lin.cross(&f.lin),
            lin: self.ang.cross(&f.lin),
        }
    }
    /// `self ×ₘ (w e_k, 0)`: the cross product with a rotation rate `w` about coordinate axis
    /// `k` (the velocity-product term of a revolute joint about x, y or z).
    #[inline]
    pub fn cross_axis(&self, k: usize, w: f64) -> MotionVec {
        let cross = |u: &Vector3<f64>| match k {
            0 => Vector3::new(0.0, u.z * w, -u.y * w),
            1 => Vector3::new(-u.z * w, 0.0, u.x * w),
            _ => Vector3::new(u.y * w, -u.x * w, 0.0),
        };
        MotionVec {
            ang: cross(&self.ang),
            lin: cross(&self.lin),
        }
    }
    /// The scalar product with a force (power, W).
    #[inline]
    pub fn dot(&self, f: &ForceVec) -> f64 {
        self.ang.dot(&f.ang) + self.lin.dot(&f.lin)
    }
}

impl ForceVec {
    pub const ZERO: ForceVec = ForceVec {
        ang: Vector3::new(0.0, 0.0, 0.0),
        lin: Vector3::new(0.0, 0.0, 0.0),
    };
    pub fn new(ang: Vector3<f64>, lin: Vector3<f64>) -> Self {
        Self { ang, lin }
    }
    pub fn from_vector6(x: &Vector6<f64>) -> Self {
        Self::new(x.fixed_rows::<3>(0).into(), x.fixed_rows::<3>(3).into())
    }
    pub fn to_vector6(&self) -> Vector6<f64> {
        Vector6::new(
            self.ang.x, self.ang.y, self.ang.z, self.lin.x, self.lin.y, self.lin.z,
        )
    }
}

macro_rules! spatial_ops {
    ($t:ty) => {
        impl std::ops::Add for $t {
            type Output = $t;
            #[inline]
            fn add(self, o: $t) -> $t {
                Self {
                    ang: self.ang + o.ang,
                    lin: self.lin + o.lin,
                }
            }
        }
        impl std::ops::Sub for $t {
            type Output = $t;
            #[inline]
            fn sub(self, o: $t) -> $t {
                Self {
                    ang: self.ang - o.ang,
                    lin: self.lin - o.lin,
                }
            }
        }
        impl std::ops::AddAssign for $t {
            #[inline]
            fn add_assign(&mut self, o: $t) {
                self.ang += o.ang;
                self.lin += o.lin;
            }
        }
        impl std::ops::SubAssign for $t {
            #[inline]
            fn sub_assign(&mut self, o: $t) {
                self.ang -= o.ang;
                self.lin -= o.lin;
            }
        }
        impl std::ops::Mul<f64> for $t {
            type Output = $t;
            #[inline]
            fn mul(self, s: f64) -> $t {
                Self {
                    ang: self.ang * s,
                    lin: self.lin * s,
                }
            }
        }
        impl std::ops::Neg for $t {
            type Output = $t;
            #[inline]
            fn neg(self) -> $t {
                Self {
                    ang: -self.ang,
                    lin: -self.lin,
                }
            }
        }
    };
}
spatial_ops!(MotionVec);
spatial_ops!(ForceVec);

/// A rigid transform: the pose of frame b in frame a (`aXb`, Pinocchio's `aMb`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpatialTransform {
    /// Rotation: b's axes in a's coordinates (a 3×3 rotation matrix).
    pub rot: Matrix3<f64>,
    /// b's origin in a's coordinates (m).
    pub trans: Vector3<f64>,
}

impl Default for SpatialTransform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl SpatialTransform {
    pub const IDENTITY: SpatialTransform = SpatialTransform {
        rot: Matrix3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
        trans: Vector3::new(0.0, 0.0, 0.0),
    };
    pub fn new(rot: Matrix3<f64>, trans: Vector3<f64>) -> Self {
        Self { rot, trans }
    }
    pub fn from_translation(trans: Vector3<f64>) -> Self {
        Self {
            rot: Matrix3::identity(),
            trans,
        }
    }
    pub fn from_rotation(rot: Matrix3<f64>) -> Self {
        Self {
            rot,
            trans: Vector3::zeros(),
        }
    }
    /// `aXc = aXb · bXc`.
    #[inline]
    pub fn compose(&self, b_x_c: &SpatialTransform) -> SpatialTransform {
        SpatialTransform {
            rot: self.rot * b_x_c.rot,
            trans: self.trans + self.rot * b_x_c.trans,
        }
    }
    /// `bXa` from `aXb`.
    #[inline]
    pub fn inverse(&self) -> SpatialTransform {
        let rt = self.rot.transpose();
        SpatialTransform {
            rot: rt,
            trans: -(rt * self.trans),
        }
    }
    /// A point given in b coordinates, in a coordinates.
    #[inline]
    pub fn transform_point(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.rot * p + self.trans
    }
    /// Motion vector from b coordinates to a coordinates.
    #[inline]
    pub fn act_motion(&self, m: &MotionVec) -> MotionVec {
        let ang = self.rot * m.ang;
        MotionVec {
            ang,
            lin: self.rot * m.lin + self.trans.cross(&ang),
        }
    }
    /// Motion vector from a coordinates to b coordinates.
    #[inline]
    pub fn act_inv_motion(&self, m: &MotionVec) -> MotionVec {
        MotionVec {
            ang: self.rot.tr_mul(&m.ang),
            lin: self.rot.tr_mul(&(m.lin - self.trans.cross(&m.ang))),
        }
    }
    /// Force vector from b coordinates to a coordinates.
    #[inline]
    pub fn act_force(&self, f: &ForceVec) -> ForceVec {
        let lin = self.rot * f.lin;
        ForceVec {
            ang: self.rot * f.ang + self.trans.cross(&lin),
            lin,
        }
    }
    /// Force vector from a coordinates to b coordinates.
    #[inline]
    pub fn act_inv_force(&self, f: &ForceVec) -> ForceVec {
        ForceVec {
            ang: self.rot.tr_mul(&(f.ang - self.trans.cross(&f.lin))),
            lin: self.rot.tr_mul(&f.lin),
        }
    }
    /// The 6×6 matrix that maps motion vectors from b to a coordinates (`act_motion`).
    pub fn motion_matrix(&self) -> Matrix6<f64> {
        let mut x = Matrix6::zeros();
        x.fixed_view_mut::<3, 3>(0, 0).copy_from(&self.rot);
        x.fixed_view_mut::<3, 3>(3, 3).copy_from(&self.rot);
        x.fixed_view_mut::<3, 3>(3, 0)
            .copy_from(&(skew(&self.trans) * self.rot));
        x
    }
    /// A congruence transform of a 6×6 spatial inertia-like matrix given in b coordinates to a
    /// coordinates: `Xᵀ⁻¹ I X⁻¹` with `X = act_inv_motion` (Featherstone eq. 2.66).
    pub fn act_inertia_matrix(&self, i_b: &Matrix6<f64>) -> Matrix6<f64> {
        let x = self
            .motion_matrix()
            .try_inverse()
            .unwrap_or_else(Matrix6::identity);
        x.transpose() * i_b * x
    }
}

/// `atan2(y, x)` by the `libm` crate (a port of musl's, itself fdlibm's `e_atan2.c`: error
/// < 1 ulp), for the angles read back from rotations at every frame (the euler model's
/// write-back, the rotation logarithm of the manifold differences). glibc's `atan2` spends
/// more than twice the instructions, on last-bit rounding the angles have no use for
/// (callgrind on the minute take: about 240 a call against 100).
#[inline]
pub fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}

/// `(sin x, cos x)` within about 1 ulp, for the joint angles of the dynamics: Cody-Waite
/// reduction by π/2 (π/2 split in three parts of 33, 33 and 53 bits, so `n·P₁` and `n·P₂` are
/// exact for `|n| < 2¹⁹`) and fdlibm's minimax kernels on `[−π/4, π/4]` (Sun Microsystems,
/// `k_sin.c` and `k_cos.c`, error < 1 ulp; the tail term of the reduced argument is dropped).
/// Arguments beyond `|x| < 2¹⁹·π/2` (≈ 8·10⁵ rad), infinities and NaN go to the standard
/// library's `sin_cos`. About a sixth of the instructions of glibc's `sincos`, whose last-bit
/// accuracy the dynamics has no use for (the Pinocchio fixtures hold at 1e-10; the tests check
/// this function against `f64::sin_cos` to 2.3e-16 absolute). Without a branch on the
/// quadrant (which mispredicted on every other hinge of a capture): it is the kernel
/// [`crate::lanes::sin_cos_many`] runs on many values at once, here on one.
#[inline]
pub fn sin_cos(x: f64) -> (f64, f64) {
    // also NaN and ±∞
    if crate::lanes::beyond_sin_cos(x) {
        return x.sin_cos();
    }
    crate::lanes::sin_cos_lane(x)
}

/// A rotation by an angle about a coordinate axis (x, y or z): the joint rotation of a revolute
/// joint whose axis is a unit coordinate vector — every channel of a BVH euler model and most
/// URDF joints. Applying it costs 4 multiplications instead of a 3×3 product's 9.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisRotation {
    /// 0, 1 or 2 for x, y, z.
    pub axis: usize,
    pub sin: f64,
    pub cos: f64,
}

impl AxisRotation {
    /// The rotation by `angle` (rad) about coordinate axis `axis` (0, 1 or 2).
    #[inline]
    pub fn new(axis: usize, angle: f64) -> Self {
        let (sin, cos) = sin_cos(angle);
        Self { axis, sin, cos }
    }
    /// The rotation about coordinate axis `axis` whose angle has sine `sin` and cosine `cos`.
    #[inline]
    pub fn from_sin_cos(axis: usize, sin: f64, cos: f64) -> Self {
        Self { axis, sin, cos }
    }
    /// The two coordinates the rotation mixes, in right-handed order (`e_i → c e_i + s e_j`).
    #[inline]
    fn plane(&self) -> (usize, usize) {
        match self.axis {
            0 => (1, 2),
            1 => (2, 0),
            _ => (0, 1),
        }
    }
    /// `R v`.
    #[inline]
    pub fn rotate(&self, v: &Vector3<f64>) -> Vector3<f64> {
        let (s, c) = (self.sin, self.cos);
        match self.axis {
            0 => Vector3::new(v.x, c * v.y - s * v.z, s * v.y + c * v.z),
            1 => Vector3::new(c * v.x + s * v.z, v.y, c * v.z - s * v.x),
            _ => Vector3::new(c * v.x - s * v.y, s * v.x + c * v.y, v.z),
        }
    }
    /// `Rᵀ v`.
    #[inline]
    pub fn rotate_inv(&self, v: &Vector3<f64>) -> Vector3<f64> {
        let (s, c) = (self.sin, self.cos);
        match self.axis {
            0 => Vector3::new(v.x, c * v.y + s * v.z, c * v.z - s * v.y),
            1 => Vector3::new(c * v.x - s * v.z, v.y, c * v.z + s * v.x),
            _ => Vector3::new(c * v.x + s * v.y, c * v.y - s * v.x, v.z),
        }
    }
    /// `M R` for a 3×3 `m`: two columns mixed.
    #[inline]
    pub fn premul(&self, m: &Matrix3<f64>) -> Matrix3<f64> {
        let (i, j) = self.plane();
        let (s, c) = (self.sin, self.cos);
        let (ci, cj) = (m.column(i).into_owned(), m.column(j).into_owned());
        let mut out = *m;
        out.set_column(i, &(ci * c + cj * s));
        out.set_column(j, &(cj * c - ci * s));
        out
    }
    /// The 3×3 matrix.
    #[inline]
    pub fn matrix(&self) -> Matrix3<f64> {
        self.premul(&Matrix3::identity())
    }
}

/// A rigid transform `aXb` in the cheapest exact form the dynamics can use: a translation
/// followed by a rotation about a coordinate axis (a revolute joint about x, y or z whose
/// placement in its parent has no rotation: every joint of a BVH euler model), or a general
/// [`SpatialTransform`]. The two forms give the same numbers up to rounding.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FastTransform {
    /// Rotation `rot` after translation `trans` (b's origin in a, m): `[R(rot), trans]`.
    Axis {
        trans: Vector3<f64>,
        rot: AxisRotation,
    },
    General(SpatialTransform),
}

impl Default for FastTransform {
    fn default() -> Self {
        FastTransform::General(SpatialTransform::IDENTITY)
    }
}

impl FastTransform {
    /// As a general transform.
    #[inline]
    pub fn to_transform(&self) -> SpatialTransform {
        match self {
            FastTransform::Axis { trans, rot } => SpatialTransform::new(rot.matrix(), *trans),
            FastTransform::General(x) => *x,
        }
    }
    /// The rotation part `R` applied to a vector (b's coordinates → a's).
    #[inline]
    pub fn rotate(&self, v: &Vector3<f64>) -> Vector3<f64> {
        match self {
            FastTransform::Axis { rot, .. } => rot.rotate(v),
            FastTransform::General(x) => x.rot * v,
        }
    }
    /// `Rᵀ v` (a's coordinates → b's).
    #[inline]
    pub fn rotate_inv(&self, v: &Vector3<f64>) -> Vector3<f64> {
        match self {
            FastTransform::Axis { rot, .. } => rot.rotate_inv(v),
            FastTransform::General(x) => x.rot.tr_mul(v),
        }
    }
    /// b's origin in a (m).
    #[inline]
    pub fn trans(&self) -> &Vector3<f64> {
        match self {
            FastTransform::Axis { trans, .. } => trans,
            FastTransform::General(x) => &x.trans,
        }
    }
    /// [`SpatialTransform::act_inv_motion`].
    #[inline(always)]
    pub fn act_inv_motion(&self, m: &MotionVec) -> MotionVec {
        match self {
            FastTransform::Axis { trans, rot } => MotionVec {
                ang: rot.rotate_inv(&m.ang),
                lin: rot.rotate_inv(&(m.lin - trans.cross(&m.ang))),
            },
            FastTransform::General(x) => x.act_inv_motion(m),
        }
    }
    /// [`SpatialTransform::act_force`].
    #[inline(always)]
    pub fn act_force(&self, f: &ForceVec) -> ForceVec {
        match self {
            FastTransform::Axis { trans, rot } => {
                let lin = rot.rotate(&f.lin);
                ForceVec {
                    ang: rot.rotate(&f.ang) + trans.cross(&lin),
                    lin,
                }
            }
            FastTransform::General(x) => x.act_force(f),
        }
    }
    /// [`SpatialTransform::act_motion`].
    #[inline(always)]
    pub fn act_motion(&self, m: &MotionVec) -> MotionVec {
        match self {
            FastTransform::Axis { trans, rot } => {
                let ang = rot.rotate(&m.ang);
                MotionVec {
                    ang,
                    lin: rot.rotate(&m.lin) + trans.cross(&ang),
                }
            }
            FastTransform::General(x) => x.act_motion(m),
        }
    }
}

/// The skew-symmetric matrix `[v]×` with `[v]× w = v × w`.
#[inline]
pub fn skew(v: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -v.z, v.y, v.z, 0.0, -v.x, -v.y, v.x, 0.0)
}

/// A rigid-body spatial inertia in a body frame, about its origin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpatialInertia {
    /// Mass (kg), ≥ 0.
    pub mass: f64,
    /// Centre of mass in the body frame (m).
    pub com: Vector3<f64>,
    /// Rotational inertia about the COM, body axes (kg·m²), symmetric positive semi-definite.
    pub inertia_com: Matrix3<f64>,
}

impl Default for SpatialInertia {
    fn default() -> Self {
        Self::ZERO
    }
}

impl SpatialInertia {
    pub const ZERO: SpatialInertia = SpatialInertia {
        mass: 0.0,
        com: Vector3::new(0.0, 0.0, 0.0),
        inertia_com: Matrix3::new(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
    };
    pub fn new(mass: f64, com: Vector3<f64>, inertia_com: Matrix3<f64>) -> Self {
        Self {
            mass,
            com,
            inertia_com,
        }
    }
    /// No mass and no rotational inertia: `I · m = 0` for every `m` (the fictitious links of a
    /// BVH euler model); the dynamics skips such bodies' inertial terms.
    #[inline]
    pub fn is_zero(&self) -> bool {
        self.mass == 0.0 && self.inertia_com == Matrix3::zeros()
    }
    /// `I · m`: the momentum `[n; f]` of a body moving with `m` (Featherstone eq. 2.63):
    /// `f = mass (v − c × ω)`, `n = Ic ω + c × f`.
    #[inline]
    pub fn mul_motion(&self, m: &MotionVec) -> ForceVec {
        let lin = (m.lin - self.com.cross(&m.ang)) * self.mass;
        ForceVec {
            ang: self.inertia_com * m.ang + self.com.cross(&lin),
            lin,
        }
    }
    /// The 6×6 matrix `[Ic + m c×c×ᵀ, m c×; m c×ᵀ, m 1]` (angular first).
    pub fn to_matrix(&self) -> Matrix6<f64> {
        let cx = skew(&self.com);
        let mut i = Matrix6::zeros();
        i.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&(self.inertia_com + cx * cx.transpose() * self.mass));
        i.fixed_view_mut::<3, 3>(0, 3).copy_from(&(cx * self.mass));
        i.fixed_view_mut::<3, 3>(3, 0)
            .copy_from(&(cx.transpose() * self.mass));
        i.fixed_view_mut::<3, 3>(3, 3)
            .copy_from(&(Matrix3::identity() * self.mass));
        i
    }
    /// The sum of two inertias given in the same frame (lumping two rigidly joined bodies).
    pub fn add(&self, o: &SpatialInertia) -> SpatialInertia {
        let mass = self.mass + o.mass;
        if mass <= 0.0 {
            return SpatialInertia::ZERO;
        }
        let com = (self.com * self.mass + o.com * o.mass) / mass;
        // parallel-axis theorem: move each COM inertia to the common COM
        let shift = |i: &SpatialInertia| {
            let d = i.com - com;
            i.inertia_com + (Matrix3::identity() * d.dot(&d) - d * d.transpose()) * i.mass
        };
        SpatialInertia {
            mass,
            com,
            inertia_com: shift(self) + shift(o),
        }
    }
    /// This inertia (given in frame b) expressed in frame a, where `a_x_b` is b's pose in a.
    pub fn transformed(&self, a_x_b: &SpatialTransform) -> SpatialInertia {
        SpatialInertia {
            mass: self.mass,
            com: a_x_b.transform_point(&self.com),
            inertia_com: a_x_b.rot * self.inertia_com * a_x_b.rot.transpose(),
        }
    }
    /// Kinetic energy `½ mᵀ I m` (J).
    pub fn kinetic_energy(&self, m: &MotionVec) -> f64 {
        0.5 * m.dot(&self.mul_motion(m))
    }
}

/// A unit quaternion from the four numbers `[x, y, z, w]` (Pinocchio's storage order).
#[inline]
pub fn quat_from_xyzw(q: &[f64]) -> UnitQuaternion<f64> {
    UnitQuaternion::new_normalize(Quaternion::new(q[3], q[0], q[1], q[2]))
}

/// Writes a unit quaternion as `[x, y, z, w]`.
#[inline]
pub fn quat_to_xyzw(r: &UnitQuaternion<f64>, out: &mut [f64]) {
    out[0] = r.i;
    out[1] = r.j;
    out[2] = r.k;
    out[3] = r.w;
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_transform() -> SpatialTransform {
        let r = UnitQuaternion::from_euler_angles(0.3, -0.7, 1.1);
        SpatialTransform::new(
            *r.to_rotation_matrix().matrix(),
            Vector3::new(0.2, -0.5, 0.9),
        )
    }

    #[test]
    fn atan2_matches_the_standard_library() {
        // every quadrant, the axes, signed zeros and a wide range of ratios
        let values = [
            -3.0,
            -1.0,
            -0.7,
            -1e-9,
            -0.0,
            0.0,
            1e-300,
            1e-9,
            0.3,
            1.0,
            2.5,
            1e12,
            f64::INFINITY,
        ];
        for &y in &values {
            for &x in &values {
                let (a, b) = (atan2(y, x), y.atan2(x));
                assert!(
                    (a - b).abs() <= 4.5e-16 * b.abs().max(1e-300) && a.signum() == b.signum(),
                    "atan2({y}, {x}) = {a}, std {b}"
                );
            }
        }
        for k in -2000..=2000 {
            let t = k as f64 * 1.7e-3;
            let (y, x) = (t.sin() * 1.3, t.cos() * 0.8 - 0.1);
            assert!((atan2(y, x) - y.atan2(x)).abs() <= 9e-16, "{y} {x}");
        }
    }

    #[test]
    fn sin_cos_matches_the_standard_library() {
        // dense over the joint-angle range, near every multiple of π/4, and large arguments
        let mut worst: f64 = 0.0;
        let mut check = |x: f64| {
            let (s, c) = sin_cos(x);
            let (s0, c0) = x.sin_cos();
            worst = worst.max((s - s0).abs()).max((c - c0).abs());
        };
        for k in -200_000..=200_000 {
            check(k as f64 * 1.0e-4 * std::f64::consts::PI);
        }
        for k in -400..=400 {
            let m = k as f64 * std::f64::consts::FRAC_PI_4;
            for d in [0.0, 1e-300, 1e-16, 1e-12, 1e-8, 1e-4] {
                check(m + d);
                check(m - d);
            }
        }
        for x in [1e3, -1e4 + 0.3, 8.2e5, 8.3e5, 1e7, 1e300] {
            check(x);
        }
        assert!(worst <= 2.3e-16, "worst absolute error {worst:e}");
        assert!(sin_cos(f64::NAN).0.is_nan() && sin_cos(f64::INFINITY).1.is_nan());
        assert_eq!(sin_cos(-0.0).0.to_bits(), (-0.0f64).to_bits());
    }

    #[test]
    fn axis_rotation_matches_its_matrix() {
        let v = Vector3::new(0.3, -1.2, 2.5);
        for axis in 0..3 {
            let r = AxisRotation::new(axis, 0.83);
            let m = crate::model::joint::axis_angle(&Vector3::ith(axis, 1.0), 0.83);
            assert!((r.matrix() - m).norm() < 1e-15);
            assert!((r.rotate(&v) - m * v).norm() < 1e-15);
            assert!((r.rotate_inv(&v) - m.transpose() * v).norm() < 1e-15);
            let a = sample_transform();
            assert!((r.premul(&a.rot) - a.rot * m).norm() < 1e-15);
            // the fast form acts as the general transform it stands for
            let fast = FastTransform::Axis {
                trans: a.trans,
                rot: r,
            };
            let x = fast.to_transform();
            let mv = MotionVec::new(v, Vector3::new(-0.4, 0.9, 0.1));
            let f = ForceVec::new(Vector3::new(1.5, 0.2, -0.7), v);
            let d = |p: Vector6<f64>, q: Vector6<f64>| (p - q).norm();
            assert!(
                d(
                    fast.act_inv_motion(&mv).to_vector6(),
                    x.act_inv_motion(&mv).to_vector6()
                ) < 1e-14
            );
            assert!(
                d(
                    fast.act_motion(&mv).to_vector6(),
                    x.act_motion(&mv).to_vector6()
                ) < 1e-14
            );
            assert!(
                d(
                    fast.act_force(&f).to_vector6(),
                    x.act_force(&f).to_vector6()
                ) < 1e-14
            );
        }
    }

    #[test]
    fn cross_axis_is_the_motion_cross_product() {
        let m = MotionVec::new(Vector3::new(1.0, -2.0, 0.5), Vector3::new(0.3, 0.7, -1.1));
        for k in 0..3 {
            let s = MotionVec::new(Vector3::ith(k, 1.7), Vector3::zeros());
            let d = m.cross_axis(k, 1.7).to_vector6() - m.cross_motion(&s).to_vector6();
            assert!(d.norm() < 1e-15, "axis {k}");
        }
    }

    #[test]
    fn act_and_act_inv_are_inverse() {
        let x = sample_transform();
        let m = MotionVec::new(Vector3::new(1.0, 2.0, 3.0), Vector3::new(-1.0, 0.5, 0.25));
        let back = x.act_inv_motion(&x.act_motion(&m));
        assert!((back.to_vector6() - m.to_vector6()).norm() < 1e-14);
        let f = ForceVec::new(Vector3::new(0.1, 2.0, -3.0), Vector3::new(4.0, 0.5, 0.25));
        let back = x.act_inv_force(&x.act_force(&f));
        assert!((back.to_vector6() - f.to_vector6()).norm() < 1e-14);
    }

    #[test]
    fn power_is_frame_invariant() {
        // m·f is a scalar: the same in every frame
        let x = sample_transform();
        let m = MotionVec::new(Vector3::new(1.0, 2.0, 3.0), Vector3::new(-1.0, 0.5, 0.25));
        let f = ForceVec::new(Vector3::new(0.1, 2.0, -3.0), Vector3::new(4.0, 0.5, 0.25));
        let p_b = m.dot(&f);
        let p_a = x.act_motion(&m).dot(&x.act_force(&f));
        assert!((p_a - p_b).abs() < 1e-12);
    }

    #[test]
    fn inertia_matrix_matches_mul_motion() {
        let i = SpatialInertia::new(
            2.5,
            Vector3::new(0.1, -0.2, 0.3),
            Matrix3::new(0.3, 0.01, 0.0, 0.01, 0.2, 0.02, 0.0, 0.02, 0.1),
        );
        let m = MotionVec::new(Vector3::new(1.0, 2.0, 3.0), Vector3::new(-1.0, 0.5, 0.25));
        let a = i.mul_motion(&m).to_vector6();
        let b = i.to_matrix() * m.to_vector6();
        assert!((a - b).norm() < 1e-12);
    }

    #[test]
    fn transformed_inertia_matches_congruence() {
        let i = SpatialInertia::new(
            2.5,
            Vector3::new(0.1, -0.2, 0.3),
            Matrix3::new(0.3, 0.01, 0.0, 0.01, 0.2, 0.02, 0.0, 0.02, 0.1),
        );
        let x = sample_transform();
        let a = i.transformed(&x).to_matrix();
        let b = x.act_inertia_matrix(&i.to_matrix());
        assert!((a - b).norm() < 1e-12);
    }

    #[test]
    fn lumping_two_point_masses_gives_parallel_axis_inertia() {
        let p = |x: f64| SpatialInertia::new(1.0, Vector3::new(x, 0.0, 0.0), Matrix3::zeros());
        let sum = p(1.0).add(&p(-1.0));
        assert_eq!(sum.mass, 2.0);
        assert!(sum.com.norm() < 1e-15);
        assert!((sum.inertia_com[(1, 1)] - 2.0).abs() < 1e-15);
        assert!(sum.inertia_com[(0, 0)].abs() < 1e-15);
    }
}
