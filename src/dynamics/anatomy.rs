//! Anatomical joint angles and net internal joint moments in the joint coordinate system of
//! Grood & Suntay (1983), as the ISB recommends it for the hip, knee and ankle (Wu et al. 2002,
//! *J. Biomech.* 35:543–548) and Vicon's Plug-in Gait uses it for the trunk and arms.
//!
//! Every segment has an anatomical frame, a rotation whose columns are its axes in world
//! coordinates: X anterior, Y along the segment towards its proximal end (up), Z to the
//! subject's right, on both sides. The frames are built from the skeleton's geometry (bone
//! directions, the left–right line of the hips or shoulders, the joint's own flexion axis
//! found from the motion), never from the file's channel frames, so an exporter's joint
//! orientations, rotation orders and names do not change them.
//!
//! A joint's angles are the Cardan decomposition `R = R_z(α) R_x(β) R_y(γ)` of the distal
//! frame in the proximal one (`Rₚᵀ R_d`): `α` about the proximal Z (flexion axis `e₁`), `β`
//! about the floating axis `e₂ = e₃ × e₁`, `γ` about the distal Y (`e₃`). Clinical signs, the
//! same on both sides ([`JointKind`]): flexion, adduction and internal rotation positive (the
//! knee's flexion is −α; the ankle's α is dorsiflexion).
//!
//! The relative angular velocity is `α̇ e₁ + β̇ e₂ + γ̇ e₃`, so the net moment `M` that the
//! proximal segment exerts on the distal one (muscles, ligaments and contact together; RNEA's
//! joint force) does work `M·e₁ α̇ + M·e₂ β̇ + M·e₃ γ̇`: its component conjugate to each angle is
//! its projection on that angle's axis. Moments are reported with the sign that opposes the
//! angle (Winter 2009): extensor (ankle: plantarflexor), abductor and external-rotator moments
//! positive.

use nalgebra::{Matrix3, Vector3};

/// An anatomical joint: how its angles are named and signed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointKind {
    /// `hip`, `knee`, …
    pub name: &'static str,
    /// Sign of α in flexion (the knee flexes with −α, the trunk bends forward with −α).
    pub flexion_sign: f64,
}

/// The joints, in output order.
pub const PELVIS: JointKind = JointKind {
    name: "pelvis",
    flexion_sign: -1.0,
};
pub const LUMBAR: JointKind = JointKind {
    name: "lumbar",
    flexion_sign: -1.0,
};
pub const HIP: JointKind = JointKind {
    name: "hip",
    flexion_sign: 1.0,
};
pub const KNEE: JointKind = JointKind {
    name: "knee",
    flexion_sign: -1.0,
};
pub const ANKLE: JointKind = JointKind {
    name: "ankle",
    flexion_sign: 1.0,
};
pub const SHOULDER: JointKind = JointKind {
    name: "shoulder",
    flexion_sign: 1.0,
};
pub const ELBOW: JointKind = JointKind {
    name: "elbow",
    flexion_sign: 1.0,
};

/// The three angle names, in column order.
pub const AXES: [&str; 3] = ["flexion", "adduction", "rotation"];

/// Signs turning `(α, β, γ)` into (flexion, adduction, internal rotation): adduction and
/// internal rotation turn the other way on the left (`right = false`); a joint on the midline
/// uses the right side's (bending and turning to the right positive... see [`JointKind`]).
pub fn signs(kind: JointKind, right: bool) -> [f64; 3] {
    let s = if right { 1.0 } else { -1.0 };
    [kind.flexion_sign, s, s]
}

/// `(α, β, γ)` (rad) of `R = R_z(α) R_x(β) R_y(γ)`.
pub fn zxy_angles(r: &Matrix3<f64>) -> [f64; 3] {
    let alpha = (-r[(0, 1)]).atan2(r[(1, 1)]);
    let beta = r[(2, 1)].clamp(-1.0, 1.0).asin();
    let gamma = (-r[(2, 0)]).atan2(r[(2, 2)]);
    [alpha, beta, gamma]
}

/// The joint coordinate system's axes (world): `e₁` the proximal Z, `e₃` the distal Y, `e₂`
/// the floating axis `e₃ × e₁` (normalised; `e₁` itself at gimbal lock).
pub fn jcs_axes(proximal: &Matrix3<f64>, distal: &Matrix3<f64>) -> [Vector3<f64>; 3] {
    let e1: Vector3<f64> = proximal.column(2).into();
    let e3: Vector3<f64> = distal.column(1).into();
    let e2 = e3.cross(&e1).try_normalize(1e-12).unwrap_or(e1);
    [e1, e2, e3]
}

/// Angles (rad, clinical signs) and moments (N·m, signed to oppose the angles) of a joint
/// whose proximal and distal anatomical frames are `p`, `d` and whose net moment on the distal
/// segment is `m` (world axes).
pub fn joint_angles_moments(
    kind: JointKind,
    right: bool,
    p: &Matrix3<f64>,
    d: &Matrix3<f64>,
    m: &Vector3<f64>,
) -> ([f64; 3], [f64; 3]) {
    let (angles, e) = joint_angles_axes(kind, right, p, d);
    (angles, joint_moments(kind, right, &e, m))
}

/// The half of [`joint_angles_moments`] that reads the motion alone: the angles (rad,
/// clinical signs) and the joint coordinate system's axes ([`jcs_axes`], world) the moments
/// are projected on.
pub fn joint_angles_axes(
    kind: JointKind,
    right: bool,
    p: &Matrix3<f64>,
    d: &Matrix3<f64>,
) -> ([f64; 3], [Vector3<f64>; 3]) {
    let s = signs(kind, right);
    let raw = zxy_angles(&(p.transpose() * d));
    let angles = [s[0] * raw[0], s[1] * raw[1], s[2] * raw[2]];
    (angles, jcs_axes(p, d))
}

/// The other half: the net moment `m` (N·m, world axes) on the axes `e` of
/// [`joint_angles_axes`], signed to oppose the angles.
pub fn joint_moments(
    kind: JointKind,
    right: bool,
    e: &[Vector3<f64>; 3],
    m: &Vector3<f64>,
) -> [f64; 3] {
    let s = signs(kind, right);
    [
        -s[0] * m.dot(&e[0]),
        -s[1] * m.dot(&e[1]),
        -s[2] * m.dot(&e[2]),
    ]
}

/// The frame with long axis `y` (exact) and lateral axis `z` made orthogonal to it; `None` if
/// either is zero or they are parallel.
pub fn frame_from_yz(y: &Vector3<f64>, z: &Vector3<f64>) -> Option<Matrix3<f64>> {
    let y = y.try_normalize(1e-12)?;
    let z = (z - y * z.dot(&y)).try_normalize(1e-9)?;
    Some(Matrix3::from_columns(&[y.cross(&z), y, z]))
}

/// The frame with lateral axis `z` (exact) and anterior axis `x` made orthogonal to it.
pub fn frame_from_zx(z: &Vector3<f64>, x: &Vector3<f64>) -> Option<Matrix3<f64>> {
    let z = z.try_normalize(1e-12)?;
    let x = (x - z * x.dot(&z)).try_normalize(1e-9)?;
    Some(Matrix3::from_columns(&[x, z.cross(&x), z]))
}

/// The rotation vector (axis × angle, rad) of a rotation matrix.
fn log_so3(r: &Matrix3<f64>) -> Vector3<f64> {
    nalgebra::Rotation3::from_matrix_unchecked(*r).scaled_axis()
}

/// A joint's functional axis (Ehrig et al. 2007, *J. Biomech.* 40:2150, as a principal axis of
/// the relative rotation): the direction, in the proximal body's frame, about which the
/// relative rotations `rel[k]` (distal body in proximal body) turn most between samples
/// `stride` apart; `None` when they turn by less than `min_turn` (rad) in all. With
/// `in_distal`, the same axis in the distal body's frame. The sign is arbitrary.
pub fn functional_axis(
    rel: &[Matrix3<f64>],
    stride: usize,
    in_distal: bool,
    min_turn: f64,
) -> Option<Vector3<f64>> {
    let stride = stride.max(1);
    let mut scatter = Matrix3::zeros();
    let mut turned = 0.0_f64;
    for k in 0..rel.len().saturating_sub(stride) {
        let (a, b) = (&rel[k], &rel[k + stride]);
        let w = if in_distal {
            log_so3(&(a.transpose() * b))
        } else {
            log_so3(&(b * a.transpose()))
        };
        turned = turned.max(w.norm());
        scatter += w * w.transpose();
    }
    if turned < min_turn {
        return None;
    }
    let eig = nalgebra::SymmetricEigen::new(scatter);
    let i = eig.eigenvalues.imax();
    Some(eig.eigenvectors.column(i).into())
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Rotation3;

    fn rz(a: f64) -> Matrix3<f64> {
        *Rotation3::from_axis_angle(&Vector3::z_axis(), a).matrix()
    }
    fn rx(a: f64) -> Matrix3<f64> {
        *Rotation3::from_axis_angle(&Vector3::x_axis(), a).matrix()
    }
    fn ry(a: f64) -> Matrix3<f64> {
        *Rotation3::from_axis_angle(&Vector3::y_axis(), a).matrix()
    }

    #[test]
    fn zxy_decomposition_inverts_its_composition() {
        for &(a, b, g) in &[(0.3, -0.2, 0.5), (-2.8, 1.2, 3.0), (1.5, -1.4, -0.1)] {
            let r = rz(a) * rx(b) * ry(g);
            let [x, y, z] = zxy_angles(&r);
            assert!((x - a).abs() < 1e-12 && (y - b).abs() < 1e-12 && (z - g).abs() < 1e-12);
        }
    }

    #[test]
    fn knee_flexion_is_positive_and_an_extensor_moment_is_positive() {
        // thigh upright (identity frame); the shank turned so that the ankle lies behind the
        // knee: its long axis (ankle → knee) leans forward, +X
        let flex = 0.6;
        let shank = rz(-flex);
        let y: Vector3<f64> = shank.column(1).into();
        assert!(y.x > 0.0, "ankle → knee leans forward: {y}");
        // a moment on the shank that would straighten it: about +Z (turns Y back to vertical)
        let m = Vector3::new(0.0, 0.0, 40.0);
        for right in [true, false] {
            let (ang, mom) = joint_angles_moments(KNEE, right, &Matrix3::identity(), &shank, &m);
            assert!((ang[0] - flex).abs() < 1e-12, "{ang:?}");
            assert!((mom[0] - 40.0).abs() < 1e-12, "{mom:?}");
        }
        // the hip flexes with the thigh's knee end forward: Y (knee → hip) leans back, −X
        let thigh = rz(flex);
        let (ang, mom) = joint_angles_moments(
            HIP,
            true,
            &Matrix3::identity(),
            &thigh,
            &Vector3::new(0.0, 0.0, -30.0),
        );
        assert!((ang[0] - flex).abs() < 1e-12 && (mom[0] - 30.0).abs() < 1e-12);
    }

    #[test]
    fn adduction_and_internal_rotation_are_positive_on_both_sides() {
        // right thigh: the knee moves towards the midline (−Z): Y (knee → hip) leans to +Z
        let add = 0.2;
        let right = rx(add);
        let (a, _) =
            joint_angles_moments(HIP, true, &Matrix3::identity(), &right, &Vector3::zeros());
        assert!((a[1] - add).abs() < 1e-12);
        // left thigh: the midline is +Z; the knee moving there leans Y to −Z
        let left = rx(-add);
        let (a, _) =
            joint_angles_moments(HIP, false, &Matrix3::identity(), &left, &Vector3::zeros());
        assert!((a[1] - add).abs() < 1e-12);
        // internal rotation turns the front (X) towards the midline: −Z on the right
        let (a, _) =
            joint_angles_moments(HIP, true, &Matrix3::identity(), &ry(0.3), &Vector3::zeros());
        assert!((a[2] - 0.3).abs() < 1e-12);
        let (a, _) = joint_angles_moments(
            HIP,
            false,
            &Matrix3::identity(),
            &ry(-0.3),
            &Vector3::zeros(),
        );
        assert!((a[2] - 0.3).abs() < 1e-12);
    }

    #[test]
    fn moments_project_on_the_joint_axes_as_the_power_says() {
        // power M·ω equals Σ mᵢ θ̇ᵢ for a random pose and moment (finite differences)
        let (a, b, g) = (0.4, 0.3, -0.5);
        let (da, db, dg) = (0.7, -0.2, 0.9);
        let h = 1e-6;
        let p = *Rotation3::from_euler_angles(0.1, 0.2, 0.3).matrix();
        let d = |t: f64| p * rz(a + da * t) * rx(b + db * t) * ry(g + dg * t);
        let omega_skew = (d(h) - d(-h)) / (2.0 * h) * d(0.0).transpose();
        let omega = Vector3::new(omega_skew[(2, 1)], omega_skew[(0, 2)], omega_skew[(1, 0)]);
        let m = Vector3::new(3.0, -7.0, 11.0);
        let e = jcs_axes(&p, &d(0.0));
        let via_axes = m.dot(&e[0]) * da + m.dot(&e[1]) * db + m.dot(&e[2]) * dg;
        assert!(
            (m.dot(&omega) - via_axes).abs() < 1e-6,
            "{} vs {via_axes}",
            m.dot(&omega)
        );
    }

    #[test]
    fn a_hinge_is_found_from_its_motion_and_a_still_joint_is_not() {
        let axis = Vector3::new(0.2, -0.3, 0.9).normalize();
        let rel: Vec<Matrix3<f64>> = (0..50)
            .map(|k| {
                *Rotation3::from_axis_angle(
                    &nalgebra::Unit::new_normalize(axis),
                    (k as f64 * 0.2).sin(),
                )
                .matrix()
            })
            .collect();
        let found = functional_axis(&rel, 2, false, 0.01).unwrap();
        assert!(found.dot(&axis).abs() > 1.0 - 1e-9, "{found}");
        let still = vec![Matrix3::identity(); 10];
        assert!(functional_axis(&still, 2, false, 0.01).is_none());
    }
}
