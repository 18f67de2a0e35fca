//! Forward kinematics: the world pose of every body.

use super::Workspace;
use crate::model::Model;

/// World pose of every body at configuration `q` (Featherstone 2008, §4.1):
/// `λ(i)X_i = X_tree(i) · X_J(q_i)`, `0X_i = 0X_λ(i) · λ(i)X_i`.
/// Writes `ws.li_x_i` and `ws.o_x_i`.
pub fn forward_kinematics(model: &Model, ws: &mut Workspace, q: &[f64]) {
    forward_kinematics_through(model, ws, q, model.nbodies() - 1);
}

/// [`forward_kinematics`] of bodies `1..=last` only (the bodies are numbered parents first,
/// so those are every ancestor of `last` and more): each pose bit for bit what the whole pass
/// writes. What a caller reading a few poses near the root needs, e.g. the root's orientation,
/// or the root-level bodies' poses that [`root_wrench`](super::grf) reads after RNEA (which
/// works in body frames and writes no world pose).
pub fn forward_kinematics_through(model: &Model, ws: &mut Workspace, q: &[f64], last: usize) {
    for i in 1..=last.min(model.nbodies() - 1) {
        let joint = &model.joints[i];
        let iq = model.idx_q[i];
        ws.li_x_i[i] = model.placement[i].compose(&joint.transform(&q[iq..iq + joint.nq()]));
        ws.o_x_i[i] = ws.o_x_i[model.parent[i]].compose(&ws.li_x_i[i]);
    }
}

/// The last body hung from the world (parent 0): [`forward_kinematics_through`] it gives every
/// pose that the root's wrench ([`root_wrench`](super::grf)) reads. 0 for a model of no body.
pub fn last_root_level_body(model: &Model) -> usize {
    (1..model.nbodies())
        .rev()
        .find(|&i| model.parent[i] == 0)
        .unwrap_or(0)
}
