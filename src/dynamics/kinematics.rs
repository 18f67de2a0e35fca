//! Forward kinematics: the world pose of every body.

use super::Workspace;
use crate::model::Model;

/// World pose of every body at configuration `q` (Featherstone 2008, §4.1):
/// `λ(i)X_i = X_tree(i) · X_J(q_i)`, `0X_i = 0X_λ(i) · λ(i)X_i`.
/// Writes `ws.li_x_i` and `ws.o_x_i`.
pub fn forward_kinematics(model: &Model, ws: &mut Workspace, q: &[f64]) {
    for i in 1..model.nbodies() {
        let joint = &model.joints[i];
        let iq = model.idx_q[i];
        ws.li_x_i[i] = model.placement[i].compose(&joint.transform(&q[iq..iq + joint.nq()]));
        ws.o_x_i[i] = ws.o_x_i[model.parent[i]].compose(&ws.li_x_i[i]);
    }
}
