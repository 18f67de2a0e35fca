//! Inverse dynamics with given (measured) ground reactions: force plates, or articula's own
//! estimate written out and read back.
//!
//! Each foot's load is a force `f` at a point `p` on the floor plus a free moment `m` about the
//! vertical, as the estimate's ([`super::FootLoad`]); frame by frame the loads are applied to
//! the feet's bodies and taken from RNEA's joint torques without them along the feet's paths
//! (the estimate's own pass 3, [`super::passes`]), and what the root still needs (the
//! residual, OpenSim's "residual forces") is what the loads do not explain: a measured force
//! off in time or size shows there.

use super::passes::take_load;
use super::share::centre_of_pressure;
use super::{GroundReactions, about, check_inputs, floating_root, root_wrench};
use crate::dynamics::{Workspace, forward_kinematics, rnea};
use crate::error::Error;
use crate::model::Model;
use crate::spatial::ForceVec;
use nalgebra::Vector3;

/// Vertical force (N) above which a foot counts as on the floor.
pub const CONTACT_FORCE_N: f64 = 1.0;

/// The loads of the feet over a take's samples: `[frame][foot]` each (N, m, N·m; world axes).
#[derive(Debug, Clone, Default)]
pub struct FootLoads {
    /// Foot names (`left`, `right`), the order of every per-foot vector.
    pub feet: Vec<String>,
    /// The body each foot's load acts on.
    pub bodies: Vec<usize>,
    /// Force of the ground on the foot (N).
    pub force: Vec<Vec<Vector3<f64>>>,
    /// Its point of application on the floor (m).
    pub cop: Vec<Vec<Vector3<f64>>>,
    /// Free moment about the vertical (N·m).
    pub free_moment: Vec<Vec<f64>>,
}

/// Inverse dynamics of `q, v, a` (samples `time`) with the given ground `loads` applied: the
/// torques, the root's residual and the reactions as [`GroundReactions`] (a foot is in contact
/// where its vertical force exceeds [`CONTACT_FORCE_N`]; the floor is the lowest point of
/// application in contact).
#[allow(clippy::too_many_arguments)]
pub fn apply_ground_reactions(
    model: &Model,
    loads: &FootLoads,
    time: &[f64],
    q: &[Vec<f64>],
    v: &[Vec<f64>],
    a: &[Vec<f64>],
    up: usize,
) -> Result<GroundReactions, Error> {
    check_inputs(model, time, q, v, a, up)?;
    let root = floating_root(model).ok_or_else(|| {
        Error::Invalid(format!(
            "model {}: ground reactions act on a floating body (a free joint, or three \
             prismatic and three revolute joints from the world)",
            model.name
        ))
    })?;
    let (n, nf) = (time.len(), loads.feet.len());
    if loads.force.len() != n || loads.cop.len() != n || loads.free_moment.len() != n {
        return Err(Error::Invalid(format!(
            "ground reactions: {} frames of loads for {n} samples",
            loads.force.len()
        )));
    }
    let contact: Vec<Vec<bool>> = loads
        .force
        .iter()
        .map(|fs| fs.iter().map(|f| f[up] > CONTACT_FORCE_N).collect())
        .collect();
    let mut floor = f64::INFINITY;
    for (on, cop) in contact.iter().zip(&loads.cop) {
        for (_, p) in on.iter().zip(cop).filter(|(c, _)| **c) {
            floor = floor.min(p[up]);
        }
    }
    let mut out = GroundReactions {
        feet: loads.feet.clone(),
        bodies: loads.bodies.clone(),
        up,
        floor: if floor.is_finite() { floor } else { 0.0 },
        loaded: contact.clone(),
        contact,
        foot_height: vec![],
        grf: loads.force.clone(),
        cop: loads.cop.clone(),
        free_moment: loads.free_moment.clone(),
        wrench: vec![[0.0; 6]; n],
        residual: vec![[0.0; 6]; n],
        pelvis: vec![Vector3::zeros(); n],
        com: vec![Vector3::zeros(); n],
        cop_gap: vec![0.0; n],
        tau: vec![vec![0.0; model.nv]; n],
        moment_bodies: vec![],
        moments: vec![],
    };
    let mut ws = Workspace::new(model);
    for k in 0..n {
        // the wrench the motion needs, about the pelvis (world axes)
        forward_kinematics(model, &mut ws, &q[k]);
        rnea(model, &mut ws, &q[k], &v[k], &a[k], None);
        let w = root_wrench(model, &ws);
        let pelvis = ws.o_x_i[root].trans;
        out.pelvis[k] = pelvis;
        out.com[k] = crate::dynamics::residual::centre_of_mass(model, &ws);
        out.wrench[k] = about(&w, &pelvis);

        // the loads given, and how far their centre of pressure is from the needed one
        let mut given = ForceVec::ZERO;
        for j in 0..nf {
            given += out.foot_wrench(k, j);
        }
        if let (Some((p, _)), Some((p_feet, _))) = (
            centre_of_pressure(&w, up, out.floor),
            centre_of_pressure(&given, up, out.floor),
        ) {
            out.cop_gap[k] = (p - p_feet).norm();
        }

        // inverse dynamics with them (the loads taken from the torques without them, as the
        // estimate's pass 3 does); what the root still supplies
        out.tau[k].copy_from_slice(ws.tau.as_slice());
        let mut left = w;
        for j in 0..nf {
            let wj = out.foot_wrench(k, j);
            take_load(
                model,
                &ws,
                &wj,
                out.bodies[j],
                Some(&mut out.tau[k]),
                (|_| None, &mut []),
            );
            left -= wj;
        }
        out.residual[k] = about(&left, &pelvis);
    }
    Ok(out)
}
