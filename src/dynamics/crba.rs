//! The joint-space inertia (mass) matrix by the composite rigid body algorithm.

use super::{Workspace, inertia6};
use crate::model::Model;
use nalgebra::DMatrix;

/// The mass matrix `D(q)` of the paper's equation 1 (`D q̈ + h + c = τ`), by the composite
/// rigid body algorithm (Featherstone 2008, table 6.2; Pinocchio's `crba`).
///
/// Backward pass: the composite inertia of each subtree, `I^c_λ += λX_i* I^c_i iX_λ`. Then for
/// each coordinate `k` of joint i, `F = I^c_i S_k` is the force that accelerates the whole
/// subtree at unit `q̈_k`; its projections on joint i and on every ancestor joint j
/// (`F ← λX_j* F` up the path) are the entries `D[j, k] = D[k, j] = S_jᵀ F`. Entries between
/// coordinates of different branches are zero.
///
/// Symmetric; positive definite unless the model has a massless chain or an euler joint model
/// is in gimbal lock. Writes `ws.li_x_i`, `ws.inertia6` (composite inertias) and
/// `ws.mass_matrix`, and returns `&ws.mass_matrix`.
pub fn crba<'w>(model: &Model, ws: &'w mut Workspace, q: &[f64]) -> &'w DMatrix<f64> {
    let nv = model.nv;
    let n = model.nbodies();

    // joint transforms and each body's own inertia
    for i in 1..n {
        let joint = &model.joints[i];
        let iq = model.idx_q[i];
        ws.li_x_i[i] = model.placement[i].compose(&joint.transform(&q[iq..iq + joint.nq()]));
        ws.inertia6[i] = model.inertia[i].to_matrix();
    }

    // backward pass: composite inertias I^c_λ += λX_i* I^c_i iX_λ
    for i in (2..n).rev() {
        let p = model.parent[i];
        if p > 0 {
            let ic = inertia6::to_parent(&ws.li_x_i[i], &ws.inertia6[i]);
            ws.inertia6[p] += ic;
        }
    }

    // columns: F = I^c_i S_k, projected on joint i and carried up to every ancestor
    let h = ws.mass_matrix.as_mut_slice();
    h.fill(0.0);
    let mut proj = [0.0; 6];
    for i in 1..n {
        let joint = &model.joints[i];
        let iv = model.idx_v[i];
        for k in 0..joint.nv() {
            let col = iv + k;
            let mut f = inertia6::mul_motion(&ws.inertia6[i], &joint.subspace_col(k));
            let mut j = i;
            loop {
                let jj = &model.joints[j];
                let (jv, jn) = (model.idx_v[j], jj.nv());
                jj.project_force(&f, &mut proj[..jn]);
                // D is stored column-major: D[r, c] at r + c·nv
                for (r, &x) in proj[..jn].iter().enumerate() {
                    h[jv + r + col * nv] = x;
                    h[col + (jv + r) * nv] = x;
                }
                let p = model.parent[j];
                if p == 0 {
                    break;
                }
                f = ws.li_x_i[j].act_force(&f);
                j = p;
            }
        }
    }
    &ws.mass_matrix
}
