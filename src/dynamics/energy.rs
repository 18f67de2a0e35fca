//! Energy and momentum of the whole model: the invariants that check an integrator
//! (Featherstone 2008, §2.13 and §2.15; Pinocchio's `computeKineticEnergy`,
//! `computePotentialEnergy`, `computeCentroidalMomentum`).

use super::Workspace;
use crate::model::Model;
use crate::spatial::{ForceVec, MotionVec};

/// World poses and body velocities: `λ(i)X_i`, `0X_i` and `v_i = iX_λ v_λ + S_i q̇_i` (body
/// frames). Writes `ws.li_x_i`, `ws.o_x_i` and `ws.v`.
pub fn kinematics_velocities(model: &Model, ws: &mut Workspace, q: &[f64], v: &[f64]) {
    ws.v[0] = MotionVec::ZERO;
    for i in 1..model.nbodies() {
        let (joint, p) = (&model.joints[i], model.parent[i]);
        let (iq, iv) = (model.idx_q[i], model.idx_v[i]);
        let x = model.placement[i].compose(&joint.transform(&q[iq..iq + joint.nq()]));
        ws.v[i] = x.act_inv_motion(&ws.v[p]) + joint.motion(&v[iv..iv + joint.nv()]);
        ws.o_x_i[i] = ws.o_x_i[p].compose(&x);
        ws.li_x_i[i] = x;
    }
}

/// Kinetic energy `T = Σᵢ ½ v_iᵀ I_i v_i = ½ q̇ᵀ D(q) q̇` (J). Writes as
/// [`kinematics_velocities`].
pub fn kinetic_energy(model: &Model, ws: &mut Workspace, q: &[f64], v: &[f64]) -> f64 {
    kinematics_velocities(model, ws, q, v);
    (1..model.nbodies())
        .map(|i| model.inertia[i].kinetic_energy(&ws.v[i]))
        .sum()
}

/// Potential energy of gravity `V = −Σᵢ mᵢ g · c_i` (J), `c_i` the world position of body i's
/// centre of mass; zero at the world origin. Writes `ws.li_x_i` and `ws.o_x_i`.
pub fn potential_energy(model: &Model, ws: &mut Workspace, q: &[f64]) -> f64 {
    super::forward_kinematics(model, ws, q);
    (1..model.nbodies())
        .map(|i| {
            let inertia = &model.inertia[i];
            -inertia.mass
                * model
                    .gravity
                    .dot(&ws.o_x_i[i].transform_point(&inertia.com))
        })
        .sum()
}

/// Total spatial momentum `Σᵢ 0X_i* I_i v_i` in the world frame, about the world origin:
/// `ang` the angular momentum (kg·m²/s), `lin` the linear momentum (kg·m/s). Constant in time
/// when no external force (gravity included) acts. Writes as [`kinematics_velocities`].
pub fn spatial_momentum(model: &Model, ws: &mut Workspace, q: &[f64], v: &[f64]) -> ForceVec {
    kinematics_velocities(model, ws, q, v);
    let mut h = ForceVec::ZERO;
    for i in 1..model.nbodies() {
        h += ws.o_x_i[i].act_force(&model.inertia[i].mul_motion(&ws.v[i]));
    }
    h
}
