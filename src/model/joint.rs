//! Joints: a closed enum with one `transform` match (Featherstone 2008, ch. 4, table 4.1).
//!
//! Generalized coordinates follow Pinocchio, so that its results compare column by column:
//! - `Revolute`/`Prismatic`: `q` = angle (rad) / displacement (m) about/along `axis`;
//!   `v` = its rate.
//! - `Spherical`: `q = [qx, qy, qz, qw]` (unit quaternion, w last), `v = ω` in the child frame.
//! - `Free`: `q = [x, y, z, qx, qy, qz, qw]` (child origin in the parent frame, orientation),
//!   `v = [vx, vy, vz, ωx, ωy, ωz]` in the **child** frame, **linear first** (generalized
//!   coordinate order; spatial vectors stay angular first).
//! - `Fixed`: no coordinates (builders usually merge fixed bodies into their parent).
//!
//! With velocities expressed in the child frame every motion subspace `S` is constant, so the
//! joint bias acceleration `cJ = Ṡ q̇` is zero for all kinds here.

use crate::rotation::quat_log;
use crate::spatial::{ForceVec, MotionVec, SpatialTransform, quat_from_xyzw, quat_to_xyzw};
use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// The kind of a joint and its constant parameters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointKind {
    /// Rotation about a unit `axis` given in the joint frame.
    Revolute { axis: Vector3<f64> },
    /// Translation along a unit `axis` given in the joint frame.
    Prismatic { axis: Vector3<f64> },
    /// A ball joint (quaternion).
    Spherical,
    /// A 6-DOF free joint (translation + quaternion).
    Free,
    /// No motion.
    Fixed,
}

impl JointKind {
    /// Number of configuration coordinates.
    pub fn nq(&self) -> usize {
        match self {
            JointKind::Revolute { .. } | JointKind::Prismatic { .. } => 1,
            JointKind::Spherical => 4,
            JointKind::Free => 7,
            JointKind::Fixed => 0,
        }
    }

    /// Number of velocity coordinates (degrees of freedom).
    pub fn nv(&self) -> usize {
        match self {
            JointKind::Revolute { .. } | JointKind::Prismatic { .. } => 1,
            JointKind::Spherical => 3,
            JointKind::Free => 6,
            JointKind::Fixed => 0,
        }
    }

    /// Short lowercase name (`revolute`, …).
    pub fn name(&self) -> &'static str {
        match self {
            JointKind::Revolute { .. } => "revolute",
            JointKind::Prismatic { .. } => "prismatic",
            JointKind::Spherical => "spherical",
            JointKind::Free => "free",
            JointKind::Fixed => "fixed",
        }
    }

    /// Component suffixes of the `q` columns of a multi-coordinate joint (empty for 1-DoF).
    pub fn q_components(&self) -> &'static [&'static str] {
        match self {
            JointKind::Spherical => &["qx", "qy", "qz", "qw"],
            JointKind::Free => &["x", "y", "z", "qx", "qy", "qz", "qw"],
            _ => &[],
        }
    }

    /// Component suffixes of the `v` columns of a multi-DoF joint (empty for 1-DoF).
    pub fn v_components(&self) -> &'static [&'static str] {
        match self {
            JointKind::Spherical => &["wx", "wy", "wz"],
            JointKind::Free => &["vx", "vy", "vz", "wx", "wy", "wz"],
            _ => &[],
        }
    }

    /// The joint transform `XJ(q)`: pose of the child frame in the joint frame.
    #[inline]
    pub fn transform(&self, q: &[f64]) -> SpatialTransform {
        match self {
            JointKind::Revolute { axis } => SpatialTransform::from_rotation(axis_angle(axis, q[0])),
            JointKind::Prismatic { axis } => SpatialTransform::from_translation(axis * q[0]),
            JointKind::Spherical => {
                SpatialTransform::from_rotation(quat_from_xyzw(q).to_rotation_matrix().into_inner())
            }
            JointKind::Free => SpatialTransform::new(
                quat_from_xyzw(&q[3..7]).to_rotation_matrix().into_inner(),
                Vector3::new(q[0], q[1], q[2]),
            ),
            JointKind::Fixed => SpatialTransform::IDENTITY,
        }
    }

    /// The coordinate axis (0, 1, 2 for x, y, z) of a revolute joint whose axis is exactly that
    /// unit vector; `None` for any other axis (negative, oblique, not of unit length) and every
    /// other kind. The dynamics' fast paths (`spatial::AxisRotation`) key on it.
    #[inline]
    pub fn revolute_coordinate_axis(&self) -> Option<usize> {
        match self {
            JointKind::Revolute { axis } => match (axis.x, axis.y, axis.z) {
                (1.0, 0.0, 0.0) => Some(0),
                (0.0, 1.0, 0.0) => Some(1),
                (0.0, 0.0, 1.0) => Some(2),
                _ => None,
            },
            _ => None,
        }
    }

    /// Column `k` of the motion subspace `S` (child frame): the spatial motion produced by a
    /// unit rate of velocity coordinate `k`.
    #[inline]
    pub fn subspace_col(&self, k: usize) -> MotionVec {
        let e = |i: usize| Vector3::ith(i, 1.0);
        match self {
            JointKind::Revolute { axis } => MotionVec::new(*axis, Vector3::zeros()),
            JointKind::Prismatic { axis } => MotionVec::new(Vector3::zeros(), *axis),
            JointKind::Spherical => MotionVec::new(e(k), Vector3::zeros()),
            JointKind::Free if k < 3 => MotionVec::new(Vector3::zeros(), e(k)),
            JointKind::Free => MotionVec::new(e(k - 3), Vector3::zeros()),
            JointKind::Fixed => MotionVec::ZERO,
        }
    }

    /// `S · v`: the joint's spatial velocity (or acceleration) in the child frame.
    #[inline]
    pub fn motion(&self, v: &[f64]) -> MotionVec {
        match self {
            JointKind::Revolute { axis } => MotionVec::new(axis * v[0], Vector3::zeros()),
            JointKind::Prismatic { axis } => MotionVec::new(Vector3::zeros(), axis * v[0]),
            JointKind::Spherical => {
                MotionVec::new(Vector3::new(v[0], v[1], v[2]), Vector3::zeros())
            }
            JointKind::Free => MotionVec::new(
                Vector3::new(v[3], v[4], v[5]),
                Vector3::new(v[0], v[1], v[2]),
            ),
            JointKind::Fixed => MotionVec::ZERO,
        }
    }

    /// `Sᵀ · f`: the generalized force a spatial force (child frame) exerts on this joint.
    #[inline]
    pub fn project_force(&self, f: &ForceVec, out: &mut [f64]) {
        match self {
            JointKind::Revolute { axis } => out[0] = axis.dot(&f.ang),
            JointKind::Prismatic { axis } => out[0] = axis.dot(&f.lin),
            JointKind::Spherical => out.copy_from_slice(f.ang.as_slice()),
            JointKind::Free => {
                out[..3].copy_from_slice(f.lin.as_slice());
                out[3..].copy_from_slice(f.ang.as_slice());
            }
            JointKind::Fixed => {}
        }
    }

    /// The neutral configuration (zero angle, identity quaternion).
    pub fn neutral(&self, out: &mut [f64]) {
        out.fill(0.0);
        match self {
            JointKind::Spherical => out[3] = 1.0,
            JointKind::Free => out[6] = 1.0,
            _ => {}
        }
    }

    /// `q ⊕ v·dt`: integrate a constant velocity over `dt` on the joint's manifold
    /// (the exponential map for rotations, Pinocchio's `integrate`).
    #[inline]
    pub fn integrate(&self, q: &[f64], v: &[f64], dt: f64, out: &mut [f64]) {
        match self {
            JointKind::Revolute { .. } | JointKind::Prismatic { .. } => out[0] = q[0] + v[0] * dt,
            JointKind::Spherical => {
                let r = quat_from_xyzw(q);
                let dr = UnitQuaternion::from_scaled_axis(Vector3::new(v[0], v[1], v[2]) * dt);
                quat_to_xyzw(&(r * dr), out);
            }
            JointKind::Free => {
                // se(3) exponential: the child frame moves with the constant body twist (v, ω)
                let r = quat_from_xyzw(&q[3..7]);
                let lin = Vector3::new(v[0], v[1], v[2]) * dt;
                let ang = Vector3::new(v[3], v[4], v[5]) * dt;
                let dp = se3_exp_translation(&ang, &lin);
                let p = Vector3::new(q[0], q[1], q[2]) + r * dp;
                out[..3].copy_from_slice(p.as_slice());
                quat_to_xyzw(&(r * UnitQuaternion::from_scaled_axis(ang)), &mut out[3..7]);
            }
            JointKind::Fixed => {}
        }
    }

    /// `q1 ⊖ q0`: the velocity that `integrate` needs to go from `q0` to `q1` in unit time
    /// (the logarithm map for rotations).
    pub fn difference(&self, q0: &[f64], q1: &[f64], out: &mut [f64]) {
        match self {
            JointKind::Revolute { .. } | JointKind::Prismatic { .. } => out[0] = q1[0] - q0[0],
            JointKind::Spherical => {
                let d = quat_from_xyzw(q0).inverse() * quat_from_xyzw(q1);
                out.copy_from_slice(quat_log(&d).as_slice());
            }
            JointKind::Free => {
                let r0 = quat_from_xyzw(&q0[3..7]);
                let d = r0.inverse() * quat_from_xyzw(&q1[3..7]);
                let ang = quat_log(&d);
                let dp = r0.inverse()
                    * (Vector3::new(q1[0], q1[1], q1[2]) - Vector3::new(q0[0], q0[1], q0[2]));
                let lin = se3_log_translation(&ang, &dp);
                out[..3].copy_from_slice(lin.as_slice());
                out[3..].copy_from_slice(ang.as_slice());
            }
            JointKind::Fixed => {}
        }
    }

    /// Renormalise quaternion coordinates (after a generic vector operation on q).
    pub fn normalize(&self, q: &mut [f64]) {
        let s = match self {
            JointKind::Spherical => &mut q[0..4],
            JointKind::Free => &mut q[3..7],
            _ => return,
        };
        let n = s.iter().map(|x| x * x).sum::<f64>().sqrt();
        if n > 0.0 {
            s.iter_mut().for_each(|x| *x /= n);
        }
    }
}

/// The rotation matrix of `angle` (rad) about the unit `axis`, specialised for the principal
/// axes (the common case of BVH channels); any other axis by Rodrigues' formula
/// `R = c 1 + s [a]× + (1 − c) a aᵀ` (Murray, Li, Sastry 1994, eq. 2.14). Sine and cosine come
/// from [`crate::spatial::sin_cos`] (≤ 1 ulp, a sixth of the standard library's cost).
#[inline]
pub fn axis_angle(axis: &Vector3<f64>, angle: f64) -> Matrix3<f64> {
    let (s, c) = crate::spatial::sin_cos(angle);
    if axis.x == 1.0 {
        Matrix3::new(1.0, 0.0, 0.0, 0.0, c, -s, 0.0, s, c)
    } else if axis.y == 1.0 {
        Matrix3::new(c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c)
    } else if axis.z == 1.0 {
        Matrix3::new(c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
    } else {
        let (x, y, z) = (axis.x, axis.y, axis.z);
        let t = 1.0 - c;
        let (xt, yt, zt) = (x * t, y * t, z * t);
        let (xs, ys, zs) = (x * s, y * s, z * s);
        Matrix3::new(
            c + x * xt,
            x * yt - zs,
            x * zt + ys,
            x * yt + zs,
            c + y * yt,
            y * zt - xs,
            x * zt - ys,
            y * zt + xs,
            c + z * zt,
        )
    }
}

/// `V(ω) · v`: the translation part of the SE(3) exponential of the twist `(v, ω)`
/// (Murray, Li, Sastry 1994, eq. 2.36), with a Taylor expansion for small rotations.
fn se3_exp_translation(w: &Vector3<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    let t2 = w.norm_squared();
    let t = t2.sqrt();
    let (a, b) = if t < 1e-4 {
        (0.5 - t2 / 24.0, 1.0 / 6.0 - t2 / 120.0)
    } else {
        ((1.0 - t.cos()) / t2, (t - t.sin()) / (t2 * t))
    };
    v + w.cross(v) * a + w.cross(&w.cross(v)) * b
}

/// The inverse of [`se3_exp_translation`]: `V(ω)⁻¹ · p`.
fn se3_log_translation(w: &Vector3<f64>, p: &Vector3<f64>) -> Vector3<f64> {
    let t2 = w.norm_squared();
    let t = t2.sqrt();
    let c = if t < 1e-4 {
        1.0 / 12.0 + t2 / 720.0
    } else {
        (1.0 - t * t.sin() / (2.0 * (1.0 - t.cos()))) / t2
    };
    p - w.cross(p) * 0.5 + w.cross(&w.cross(p)) * c
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Rotation3, Unit};

    #[test]
    fn axis_angle_is_nalgebras_rotation_for_every_axis() {
        let axes = [
            Vector3::x(),
            Vector3::y(),
            Vector3::z(),
            Vector3::new(0.0, 0.6, 0.8),
            Vector3::new(-1.0, 2.0, 0.5).normalize(),
        ];
        for axis in axes {
            for angle in [-3.0, -0.4, 0.0, 1e-9, 0.7, 2.9, 40.0] {
                let expected = Rotation3::from_axis_angle(&Unit::new_unchecked(axis), angle);
                let got = axis_angle(&axis, angle);
                assert!((got - expected.matrix()).norm() < 1e-14, "{axis:?} {angle}");
            }
        }
    }

    #[test]
    fn integrate_then_difference_is_identity_for_every_kind() {
        let kinds = [
            JointKind::Revolute { axis: Vector3::y() },
            JointKind::Prismatic {
                axis: Vector3::new(0.6, 0.0, 0.8),
            },
            JointKind::Spherical,
            JointKind::Free,
        ];
        let v = [0.3, -1.2, 0.7, 2.0, -0.4, 1.1];
        for k in kinds {
            let mut q0 = vec![0.0; k.nq()];
            k.neutral(&mut q0);
            // move away from neutral first
            let mut q1 = vec![0.0; k.nq()];
            k.integrate(
                &q0,
                &[0.5, 0.2, -0.3, 0.9, 0.1, -0.6][..k.nv()],
                1.0,
                &mut q1,
            );
            let mut q2 = vec![0.0; k.nq()];
            k.integrate(&q1, &v[..k.nv()], 0.37, &mut q2);
            let mut d = vec![0.0; k.nv()];
            k.difference(&q1, &q2, &mut d);
            for (i, di) in d.iter().enumerate() {
                assert!((di - v[i] * 0.37).abs() < 1e-12, "{}: {d:?}", k.name());
            }
        }
    }

    #[test]
    fn free_joint_integrate_follows_a_constant_body_twist() {
        // a body spinning about its own z with forward speed in its own x traces a circle
        let k = JointKind::Free;
        let q0 = [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];
        let mut q = [0.0; 7];
        let w = std::f64::consts::PI; // half a turn in 1 s
        k.integrate(&q0, &[1.0, 0.0, 0.0, 0.0, 0.0, w], 1.0, &mut q);
        // radius 1/w: after half a turn the origin is at (0, 2/w)
        assert!(
            q[0].abs() < 1e-12 && (q[1] - 2.0 / w).abs() < 1e-12,
            "{q:?}"
        );
    }

    #[test]
    fn principal_axis_rotation_matches_general_formula() {
        for axis in [Vector3::x(), Vector3::y(), Vector3::z()] {
            let a = axis_angle(&axis, 0.7);
            let b = Rotation3::from_axis_angle(&Unit::new_normalize(axis), 0.7).into_inner();
            assert!((a - b).norm() < 1e-15);
        }
    }
}
