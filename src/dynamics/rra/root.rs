//! Moving the whole body by its root, as residual reduction does: a translation `δp(t)` of the
//! root's origin, and a rotation `R_δ(t)` of the whole body about it (RRA's pelvis
//! translations and rotations, Delp et al. 2007), written into the root's coordinates, rates
//! and accelerations for a free joint or for three prismatic then three revolute joints (the
//! euler model's root).
//!
//! Kinematics (world frame, root origin `P` fixed by the rotation): the body's new
//! orientation is `R' = R_δ R`, its angular velocity `ω' = ω_δ + R_δ ω` and acceleration
//! `α' = α_δ + R_δ α + ω_δ × R_δ ω` (Murray, Li & Sastry 1994, *A Mathematical Introduction to
//! Robotic Manipulation*, §2.4: spatial velocities compose by the adjoint). For
//! `R_δ = exp([θ])`, `ω_δ = J_l(θ) θ̇` with `J_l` the left Jacobian of SO(3) (Barfoot 2017,
//! *State Estimation for Robotics*, eq. 7.77), and `α_δ` its time derivative.

use super::super::grf::floating_root;
use super::super::{Workspace, forward_kinematics};
use crate::model::{JointKind, Model};
use crate::rotation::{
    EulerOrder, hinge_axes, hinge_coordinate_rates, hinge_rates, matrix_to_euler_near,
};
use crate::spatial::{quat_from_xyzw, quat_to_xyzw};
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};

/// How the root's translation enters q, v, a: a free joint, or three prismatic joints from the
/// world before any rotation (their world axes).
#[derive(Debug, Clone, Copy)]
pub(super) enum RootTranslation {
    Free {
        placement: Matrix3<f64>,
    },
    Prismatic {
        iq: [usize; 3],
        iv: [usize; 3],
        inverse: Matrix3<f64>,
    },
}

pub(super) fn root_translation(model: &Model) -> Option<RootTranslation> {
    let root = floating_root(model)?;
    if model.joints[1] == JointKind::Free {
        return Some(RootTranslation::Free {
            placement: model.placement[1].rot,
        });
    }
    let mut ws = Workspace::new(model);
    forward_kinematics(model, &mut ws, &model.neutral());
    let (mut iq, mut iv, mut axes) = (vec![], vec![], vec![]);
    for i in 1..=root {
        match model.joints[i] {
            JointKind::Prismatic { axis } => {
                iq.push(model.idx_q[i]);
                iv.push(model.idx_v[i]);
                axes.push(ws.o_x_i[i].rot * axis);
            }
            JointKind::Fixed => {}
            _ => break,
        }
    }
    let [a0, a1, a2] = axes[..] else {
        return None;
    };
    let inverse = Matrix3::from_columns(&[a0, a1, a2]).try_inverse()?;
    Some(RootTranslation::Prismatic {
        iq: iq.try_into().ok()?,
        iv: iv.try_into().ok()?,
        inverse,
    })
}

/// Moves the root of one sample by the world offset `p` with rate `dp` and acceleration
/// `ddp`, the whole body with it. For a free joint (v linear in the body frame,
/// `R` its world rotation): `δv = Rᵀ δṗ`, `δa = Rᵀ δp̈ − ω × Rᵀ δṗ`.
#[allow(clippy::too_many_arguments)]
pub(super) fn shift_root(
    t: &RootTranslation,
    rot: &Matrix3<f64>,
    p: &Vector3<f64>,
    dp: &Vector3<f64>,
    ddp: &Vector3<f64>,
    q: &mut [f64],
    v: &mut [f64],
    a: &mut [f64],
) {
    match t {
        RootTranslation::Free { placement } => {
            let dq = placement.transpose() * p;
            let dv = rot.transpose() * dp;
            let w = Vector3::new(v[3], v[4], v[5]);
            let da = rot.transpose() * ddp - w.cross(&dv);
            for k in 0..3 {
                q[k] += dq[k];
                v[k] += dv[k];
                a[k] += da[k];
            }
        }
        RootTranslation::Prismatic { iq, iv, inverse } => {
            let (dq, dv, da) = (inverse * p, inverse * dp, inverse * ddp);
            for k in 0..3 {
                q[iq[k]] += dq[k];
                v[iv[k]] += dv[k];
                a[iv[k]] += da[k];
            }
        }
    }
}

/// How the root's orientation enters q, v, a: a free joint (quaternion after its placement
/// `placement`), or three revolute joints about distinct coordinate axes, in `order`, after a
/// constant world rotation `before` (the euler model's root).
#[derive(Debug, Clone, Copy)]
pub(super) enum RootRotation {
    Free {
        placement: Matrix3<f64>,
    },
    Hinges {
        before: Matrix3<f64>,
        order: EulerOrder,
        iq: [usize; 3],
        iv: [usize; 3],
    },
}

/// Within this of gimbal lock (|cos| of the middle Euler angle, about 6e-6°), the euler
/// root's rates, `|q̇| ≈ |ω| / |cos|`, lose more than 1e-9 of `ω` to rounding: there (a set of
/// poses a take meets with probability zero) the root does not follow the rotation.
const LOCK_COS: f64 = 1e-7;

/// The root's rotation, by which residual reduction can rotate the body at any pose: a free
/// joint; or three revolute joints about distinct coordinate axes with no rotation between
/// them (BVH's euler root), whose triple follows the rotation on the take's own branch, near
/// gimbal lock too ([`rotate_root`]).
pub(super) fn root_rotation(model: &Model) -> Option<RootRotation> {
    let root = floating_root(model)?;
    if model.joints[1] == JointKind::Free {
        return Some(RootRotation::Free {
            placement: model.placement[1].rot,
        });
    }
    let hinges: Vec<usize> = (1..=root)
        .filter(|&i| matches!(model.joints[i], JointKind::Revolute { .. }))
        .collect();
    let [h0, h1, h2] = hinges[..] else {
        return None;
    };
    if h2 != root || h1 != h0 + 1 || h2 != h1 + 1 {
        return None;
    }
    let mut axes = [0usize; 3];
    for (n, &h) in hinges.iter().enumerate() {
        let JointKind::Revolute { axis } = model.joints[h] else {
            return None;
        };
        axes[n] = axis.iamax();
        let unit = (axis - Vector3::ith(axes[n], 1.0)).norm() < 1e-12;
        let plain = (model.placement[h].rot - Matrix3::identity()).norm() < 1e-12;
        if !unit || (n > 0 && !plain) {
            return None;
        }
    }
    let order = EulerOrder::from_axes(axes)?;
    let mut ws = Workspace::new(model);
    forward_kinematics(model, &mut ws, &model.neutral());
    let before = ws.o_x_i[model.parent[h0]].rot * model.placement[h0].rot;
    let iq = [model.idx_q[h0], model.idx_q[h1], model.idx_q[h2]];
    let iv = [model.idx_v[h0], model.idx_v[h1], model.idx_v[h2]];
    Some(RootRotation::Hinges {
        before,
        order,
        iq,
        iv,
    })
}

/// A rotation of the whole body: `R_δ`, its world angular velocity `ω_δ` and acceleration
/// `α_δ`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct BodyRotation {
    pub rot: Matrix3<f64>,
    pub w: Vector3<f64>,
    pub dw: Vector3<f64>,
}

impl BodyRotation {
    /// `R_δ = exp([θ])` with `θ(t)`'s rates `dθ`, `ddθ`: `ω_δ = J_l(θ) θ̇`,
    /// `α_δ = J_l(θ) θ̈ + (d/dt J_l(θ)) θ̇`, the last by a central difference along `θ̇`.
    pub fn exp(th: &Vector3<f64>, dth: &Vector3<f64>, ddth: &Vector3<f64>) -> Self {
        let jl = left_jacobian(th);
        let speed = dth.norm();
        let djl_dth = if speed > 0.0 {
            let h = 1e-5 / speed;
            (left_jacobian(&(th + dth * h)) - left_jacobian(&(th - dth * h))) / (2.0 * h) * dth
        } else {
            Vector3::zeros()
        };
        Self {
            rot: Rotation3::new(*th).into_inner(),
            w: jl * dth,
            dw: jl * ddth + djl_dth,
        }
    }
}

/// The left Jacobian of SO(3) at `θ` (Barfoot 2017, eq. 7.77), by its series near 0.
fn left_jacobian(th: &Vector3<f64>) -> Matrix3<f64> {
    let phi = th.norm();
    let k = th.cross_matrix();
    let (a, b) = if phi < 1e-4 {
        (0.5 - phi * phi / 24.0, 1.0 / 6.0 - phi * phi / 120.0)
    } else {
        (
            (1.0 - phi.cos()) / (phi * phi),
            (phi - phi.sin()) / (phi * phi * phi),
        )
    };
    Matrix3::identity() + k * a + k * k * b
}

/// Rotates the whole body of one sample by `d` about the root's origin (`rot` the root's world
/// rotation): its position path stays, its orientation, angular velocity and acceleration
/// change as in the module doc, and the free joint's linear terms, being in the body frame,
/// follow. The euler root's new triple is the one nearest its old (the take's own branch,
/// unwrapped), its rates and accelerations those of the composed angular velocity: near gimbal
/// lock they grow as `1 / cos` of the middle angle, and the massless links they move carry no
/// wrench, so every body with mass turns as the rotation says. Returns false, leaving the
/// sample as it was, only within [`LOCK_COS`] of the lock itself.
#[allow(clippy::too_many_arguments)]
pub(super) fn rotate_root(
    r: &RootRotation,
    rot: &Matrix3<f64>,
    d: &BodyRotation,
    q: &mut [f64],
    v: &mut [f64],
    a: &mut [f64],
) -> bool {
    match *r {
        RootRotation::Free { placement } => {
            let new_rot = d.rot * rot;
            let (w, dw) = (
                rot * Vector3::new(v[3], v[4], v[5]),
                rot * Vector3::new(a[3], a[4], a[5]),
            );
            let (lin, dlin) = (
                Vector3::new(v[0], v[1], v[2]),
                Vector3::new(a[0], a[1], a[2]),
            );
            let body_w = Vector3::new(v[3], v[4], v[5]);
            let pd = rot * lin;
            let pdd = rot * (dlin + body_w.cross(&lin));
            let (w2, dw2) = composed_rates(d, &w, &dw);
            let local = placement.transpose() * new_rot;
            let mut quat =
                UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(local));
            if quat.coords.dot(&quat_from_xyzw(&q[3..7]).coords) < 0.0 {
                quat = UnitQuaternion::new_unchecked(-quat.into_inner());
            }
            quat_to_xyzw(&quat, &mut q[3..7]);
            let (bw, bdw) = (new_rot.transpose() * w2, new_rot.transpose() * dw2);
            let blin = new_rot.transpose() * pd;
            let bdlin = new_rot.transpose() * pdd - bw.cross(&blin);
            for k in 0..3 {
                v[k] = blin[k];
                a[k] = bdlin[k];
                v[3 + k] = bw[k];
                a[3 + k] = bdw[k];
            }
            true
        }
        RootRotation::Hinges {
            before,
            order,
            iq,
            iv,
        } => {
            let old = [q[iq[0]], q[iq[1]], q[iq[2]]];
            let (rate, acc) = (
                [v[iv[0]], v[iv[1]], v[iv[2]]],
                [a[iv[0]], a[iv[1]], a[iv[2]]],
            );
            let (w, dw) = hinge_rates(before, order, old, rate, acc);
            let (w2, dw2) = composed_rates(d, &w, &dw);
            let new = matrix_to_euler_near(order, &(before.transpose() * d.rot * rot), old);
            // det of the hinges' axes is ±cos of the middle angle
            let axes = hinge_axes(before, order, new);
            let Some((dq, ddq)) = hinge_coordinate_rates(&axes, &w2, &dw2, LOCK_COS) else {
                return false;
            };
            for k in 0..3 {
                q[iq[k]] = new[k];
                v[iv[k]] = dq[k];
                a[iv[k]] = ddq[k];
            }
            true
        }
    }
}

/// `ω' = ω_δ + R_δ ω`, `α' = α_δ + R_δ α + ω_δ × R_δ ω` (module doc).
fn composed_rates(
    d: &BodyRotation,
    w: &Vector3<f64>,
    dw: &Vector3<f64>,
) -> (Vector3<f64>, Vector3<f64>) {
    let rw = d.rot * w;
    (d.w + rw, d.dw + d.rot * dw + d.w.cross(&rw))
}

#[cfg(test)]
mod tests {
    //! A rotation of the whole body about the root's origin, written into the root's
    //! coordinates, turns every body's pose, velocity and acceleration as a rigid rotation
    //! does, for a free root and for the euler root; and a rigid translation adds exactly
    //! the force `M δp̈` at the centre of mass (the linearization residual reduction uses).
    use super::super::super::grf::{about, root_wrench};
    use super::super::super::residual::centre_of_mass;
    use super::super::super::rnea;
    use super::*;
    use crate::dynamics::samples::{
        SplitMix64, euler_avatar, random_configuration, random_tree, random_vector,
    };
    use crate::rotation::euler_to_matrix;

    fn needed_about_pelvis(model: &Model, q: &[f64], v: &[f64], a: &[f64]) -> [f64; 6] {
        let mut ws = Workspace::new(model);
        forward_kinematics(model, &mut ws, q);
        rnea(model, &mut ws, q, v, a, None);
        let root = floating_root(model).unwrap();
        about(&root_wrench(model, &ws), &ws.o_x_i[root].trans)
    }

    fn sample(model: &Model, rng: &mut SplitMix64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let (mut q, mut v, mut a) = (
            vec![0.0; model.nq],
            vec![0.0; model.nv],
            vec![0.0; model.nv],
        );
        random_configuration(model, rng, &mut q);
        random_vector(rng, 1.0, &mut v);
        random_vector(rng, 1.0, &mut a);
        (q, v, a)
    }

    #[test]
    fn a_rigid_translation_adds_m_times_its_acceleration_at_the_centre_of_mass() {
        let mut rng = SplitMix64(7);
        for model in [random_tree(9, 3, true), euler_avatar()] {
            let t = root_translation(&model).expect("a floating root");
            let root = floating_root(&model).unwrap();
            let (mut q, mut v, mut a) = sample(&model, &mut rng);
            let w0 = needed_about_pelvis(&model, &q, &v, &a);
            let mut ws = Workspace::new(&model);
            forward_kinematics(&model, &mut ws, &q);
            let (pelvis, rot) = (ws.o_x_i[root].trans, ws.o_x_i[root].rot);
            let com = centre_of_mass(&model, &ws);
            let (p, dp, ddp) = (rng.vec3(0.05), rng.vec3(0.3), rng.vec3(2.0));
            shift_root(&t, &rot, &p, &dp, &ddp, &mut q, &mut v, &mut a);
            forward_kinematics(&model, &mut ws, &q);
            assert!((ws.o_x_i[root].trans - pelvis - p).norm() < 1e-12);
            assert!((ws.o_x_i[root].rot - rot).norm() < 1e-12);
            let w1 = needed_about_pelvis(&model, &q, &v, &a);
            let df = ddp * model.total_mass();
            let dn = (com - pelvis).cross(&df);
            for c in 0..3 {
                assert!(
                    (w1[c] - w0[c] - df[c]).abs() < 1e-9,
                    "{}: force",
                    model.name
                );
                assert!(
                    (w1[3 + c] - w0[3 + c] - dn[c]).abs() < 1e-9,
                    "{}: moment",
                    model.name
                );
            }
        }
    }

    /// Every body's world pose, angular and linear velocity and acceleration after the
    /// rotation, against the rigid motion's about the moving root origin `P`:
    /// `p' = P + R_δ (p − P)`, `ṗ' = Ṗ + ω_δ × r' + R_δ (ṗ − Ṗ)`, `p̈' = P̈ + α_δ × r' +
    /// ω_δ × (ω_δ × r') + 2 ω_δ × R_δ (ṗ − Ṗ) + R_δ (p̈ − P̈)` with `r' = p' − P`; for the
    /// euler root far from gimbal lock, 0.6° and 0.0006° from it (its rates then grow as
    /// `1 / cos` of the middle angle, and the tolerance with them).
    #[test]
    fn a_rotation_about_the_root_turns_every_body_rigidly() {
        let mut rng = SplitMix64(11);
        let lock = std::f64::consts::FRAC_PI_2;
        let cases = [
            (random_tree(9, 5, true), 0.3),
            (euler_avatar(), 0.3),
            (euler_avatar(), lock - 0.01),
            (euler_avatar(), -lock + 1e-5),
        ];
        for (model, middle) in cases {
            let root = floating_root(&model).unwrap();
            let (mut q, mut v, mut a) = sample(&model, &mut rng);
            let r = root_rotation(&model).expect("a rotatable root");
            let d = BodyRotation::exp(&rng.vec3(0.1), &rng.vec3(0.5), &rng.vec3(3.0));
            // the euler root's triple such that the rotated one has the middle angle asked
            if let RootRotation::Hinges {
                before, order, iq, ..
            } = r
            {
                let turned = euler_to_matrix(order, [0.4, middle, -0.7]);
                let old = before.transpose() * d.rot.transpose() * before * turned;
                let triple = matrix_to_euler_near(order, &old, [0.0; 3]);
                for k in 0..3 {
                    q[iq[k]] = triple[k];
                }
            }
            let world = |q: &[f64], v: &[f64], a: &[f64]| {
                let mut ws = Workspace::new(&model);
                forward_kinematics(&model, &mut ws, q);
                rnea(&model, &mut ws, q, v, a, None);
                (1..model.nbodies())
                    .map(|i| {
                        let x = ws.o_x_i[i];
                        (
                            x.rot,
                            x.trans,
                            x.rot * ws.v[i].ang,
                            x.rot * ws.v[i].lin,
                            x.rot * ws.a[i].ang,
                            x.rot * ws.a[i].lin,
                        )
                    })
                    .collect::<Vec<_>>()
            };
            // gravity enters ws.a as a fictitious upward acceleration: take it out
            let g = model.gravity;
            let before = world(&q, &v, &a);
            let mut ws = Workspace::new(&model);
            forward_kinematics(&model, &mut ws, &q);
            let (pelvis, rot) = (ws.o_x_i[root].trans, ws.o_x_i[root].rot);
            assert!(rotate_root(&r, &rot, &d, &mut q, &mut v, &mut a));
            if let RootRotation::Hinges { iq, .. } = r {
                let lock_cos = q[iq[1]].cos().abs();
                assert!((lock_cos - middle.cos().abs()).abs() < 1e-9, "{lock_cos}");
            }
            let after = world(&q, &v, &a);
            // the root's own path: Ṗ, P̈
            let (_, _, wp, vp, _, dvp) = before[root - 1];
            let (pd_root, pdd_root) = (vp, dvp + wp.cross(&vp) + g);
            // the bodies from the root on (the euler root's coordinate bodies before it are
            // massless links of the world)
            for (b, (x0, x1)) in before.iter().zip(&after).enumerate().skip(root - 1) {
                let (r0, p0, w0, v0, dw0, dv0) = *x0;
                let (r1, p1, w1, v1, dw1, dv1) = *x1;
                // body-frame linear terms are of the body origin; to world point rates:
                // ṗ = R v_lin, p̈ = R a_lin + ω × ṗ (spatial → classical), gravity removed
                let pd0 = v0;
                let pdd0 = dv0 + w0.cross(&v0) + g;
                let pd1 = v1;
                let pdd1 = dv1 + w1.cross(&v1) + g;
                let r = p1 - pelvis;
                let tol = 1e-9 / middle.cos().abs().min(1.0);
                let ctx = format!("{} at {middle} body {}", model.name, b + 1);
                assert!((r1 - d.rot * r0).norm() < tol, "{ctx}: rotation");
                assert!(
                    (p1 - pelvis - d.rot * (p0 - pelvis)).norm() < tol,
                    "{ctx}: position"
                );
                assert!((w1 - d.w - d.rot * w0).norm() < tol, "{ctx}: ω");
                assert!(
                    (dw1 - d.dw - d.rot * dw0 - d.w.cross(&(d.rot * w0))).norm() < tol,
                    "{ctx}: α"
                );
                let rel = d.rot * (pd0 - pd_root);
                assert!(
                    (pd1 - pd_root - d.w.cross(&r) - rel).norm() < tol,
                    "{ctx}: ṗ"
                );
                let expect = pdd_root
                    + d.dw.cross(&r)
                    + d.w.cross(&d.w.cross(&r))
                    + 2.0 * d.w.cross(&rel)
                    + d.rot * (pdd0 - pdd_root);
                assert!((pdd1 - expect).norm() < 10.0 * tol, "{ctx}: p̈");
            }
        }
    }

    /// `ω_δ` of `exp([θ(t)])` against central differences of the rotation in time, `α_δ`
    /// against those of `ω_δ`.
    #[test]
    fn the_rates_of_exp_theta_match_differences_in_time() {
        let th = |t: f64| Vector3::new(0.1 * t, -0.05 * t * t, 0.02 + 0.03 * t * t * t);
        let dth = |t: f64| Vector3::new(0.1, -0.1 * t, 0.09 * t * t);
        let ddth = |t: f64| Vector3::new(0.0, -0.1, 0.18 * t);
        let rot = |t: f64| Rotation3::new(th(t));
        let t = 0.7;
        let h = 1e-4;
        let d = BodyRotation::exp(&th(t), &dth(t), &ddth(t));
        let w = |t: f64| (rot(t + h) * rot(t - h).inverse()).scaled_axis() / (2.0 * h);
        assert!((d.w - w(t)).norm() < 1e-7, "{} vs {}", d.w, w(t));
        // α_δ against differences of ω_δ (a rotation's angle from its matrix loses digits
        // near the identity, so not differences of differences of the rotation)
        let hw = 1e-5;
        let at = |t: f64| BodyRotation::exp(&th(t), &dth(t), &ddth(t)).w;
        let dw = (at(t + hw) - at(t - hw)) / (2.0 * hw);
        assert!((d.dw - dw).norm() < 1e-8, "{} vs {}", d.dw, dw);
    }
}
