//! Inverse dynamics by the recursive Newton-Euler algorithm.

use super::Workspace;
use crate::model::Model;
use crate::spatial::{ForceVec, MotionVec};
use nalgebra::{DVector, Vector3};

/// Inverse dynamics, recursive Newton-Euler: the generalized forces `τ` that produce the
/// accelerations `a` at state `(q, v)` (Featherstone 2008, table 5.1; the paper's forward sweep
/// of velocities and accelerations and backward sweep of forces and moments), including the
/// model's viscous joint friction `bᵢ q̇ᵢ` and optional external forces `f_ext` (one per body,
/// body frame, acting on the body).
///
/// `τ = D(q) a + h(q, v) + c(q) + b·v − Σ Jᵢᵀ f_ext,i`. Writes `ws.x_up`, `ws.v`, `ws.a`,
/// `ws.f`, `ws.tau` and returns `&ws.tau`.
///
/// Cost: the joint transforms take the fast form of [`Model::parent_transform`] (4
/// multiplications per rotated vector for a coordinate-axis revolute joint), and bodies without
/// mass or inertia (the fictitious links of a BVH euler model, two in three bodies) skip the
/// inertial terms `I a + v ×* I v`.
pub fn rnea<'w>(
    model: &Model,
    ws: &'w mut Workspace,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    f_ext: Option<&[ForceVec]>,
) -> &'w DVector<f64> {
    rnea_terms(model, ws, q, Some(v), Some(a), f_ext, true);
    &ws.tau
}

/// The recursive Newton-Euler sweeps with any of the terms switched off: `v = None` is
/// `v = 0` (and no friction), `a = None` is `a = 0`, `gravity = false` drops `c(q)`. The
/// bias-term functions ([`super::bias`]) are this with some terms off. Writes `ws.x_up`,
/// `ws.v`, `ws.a`, `ws.f`, `ws.tau`.
pub(crate) fn rnea_terms(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    v: Option<&[f64]>,
    a: Option<&[f64]>,
    f_ext: Option<&[ForceVec]>,
    gravity: bool,
) {
    // the world: at rest, accelerating upward to stand in for gravity
    ws.v[0] = MotionVec::ZERO;
    ws.a[0] = if gravity {
        MotionVec::new(Vector3::zeros(), -model.gravity)
    } else {
        MotionVec::ZERO
    };

    // forward pass: velocities, accelerations and the net force each body needs
    //   v_i = iX_λ v_λ + S_i q̇_i,   a_i = iX_λ a_λ + S_i q̈_i + v_i ×ₘ S_i q̇_i
    //   f_i = I_i a_i + v_i ×* I_i v_i − f_ext,i
    for i in 1..model.nbodies() {
        let (joint, p) = (&model.joints[i], model.parent[i]);
        let iv = model.idx_v[i];
        let x = model.parent_transform(i, q);
        let mut vi = x.act_inv_motion(&ws.v[p]);
        let mut ai = x.act_inv_motion(&ws.a[p]);
        match joint.revolute_coordinate_axis() {
            // S = e_k (angular): the same sums with S q̇ a single component
            Some(k) => {
                let qd = v.map_or(0.0, |v| v[iv]);
                vi.ang[k] += qd;
                ai.ang[k] += a.map_or(0.0, |a| a[iv]);
                ai += vi.cross_axis(k, qd);
            }
            None => {
                let vj = v.map_or(MotionVec::ZERO, |v| joint.motion(&v[iv..iv + joint.nv()]));
                let aj = a.map_or(MotionVec::ZERO, |a| joint.motion(&a[iv..iv + joint.nv()]));
                vi += vj;
                ai += aj + vi.cross_motion(&vj);
            }
        }
        let inertia = &model.inertia[i];
        let mut fi = if inertia.is_zero() {
            ForceVec::ZERO
        } else {
            inertia.mul_motion(&ai) + vi.cross_force(&inertia.mul_motion(&vi))
        };
        if let Some(fx) = f_ext {
            fi -= fx[i];
        }
        ws.x_up[i] = x;
        ws.v[i] = vi;
        ws.a[i] = ai;
        ws.f[i] = fi;
    }

    // backward pass: project each body's force on its joint, pass it on to the parent
    //   τ_i = S_iᵀ f_i + b_i q̇_i,   f_λ += λX_i f_i
    for i in (1..model.nbodies()).rev() {
        let joint = &model.joints[i];
        let iv = model.idx_v[i];
        let nv = joint.nv();
        let tau = &mut ws.tau.as_mut_slice()[iv..iv + nv];
        match joint.revolute_coordinate_axis() {
            Some(k) => tau[0] = ws.f[i].ang[k],
            None => joint.project_force(&ws.f[i], tau),
        }
        if let Some(v) = v {
            for ((t, b), vk) in tau
                .iter_mut()
                .zip(&model.damping[iv..iv + nv])
                .zip(&v[iv..])
            {
                *t += b * vk;
            }
        }
        let p = model.parent[i];
        if p > 0 {
            let fp = ws.x_up[i].act_force(&ws.f[i]);
            ws.f[p] += fp;
        }
    }
}

#[cfg(test)]
mod tests {
    //! A point-mass pendulum (mass m at distance l below a z-axis hinge, gravity −y) obeys
    //! `τ = m l² q̈ + m g l sin q + b q̇` exactly.
    use super::*;
    use crate::model::{JointKind, ModelBuilder};
    use crate::spatial::{SpatialInertia, SpatialTransform};
    use nalgebra::{Matrix3, Vector3};

    #[test]
    fn pendulum_matches_the_analytic_equation_of_motion() {
        let (m, l, g, b) = (2.0, 0.7, 9.81, 0.3);
        let mut mb = ModelBuilder::new("pendulum", Vector3::new(0.0, -g, 0.0));
        mb.add_body(
            0,
            "bob",
            "hinge",
            JointKind::Revolute { axis: Vector3::z() },
            SpatialTransform::IDENTITY,
            SpatialInertia::new(m, Vector3::new(0.0, -l, 0.0), Matrix3::zeros()),
        );
        let mut model = mb.build();
        model.damping[0] = b;
        let mut ws = Workspace::new(&model);
        for (q, v, a) in [(0.0, 0.0, 0.0), (0.4, 1.3, -2.0), (-2.5, -0.2, 5.0)] {
            let tau = rnea(&model, &mut ws, &[q], &[v], &[a], None)[0];
            let expected = m * l * l * a + m * g * l * f64::sin(q) + b * v;
            assert!((tau - expected).abs() < 1e-12, "q={q}: {tau} vs {expected}");
        }
    }
}
