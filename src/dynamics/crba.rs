//! The joint-space inertia (mass) matrix by the composite rigid body algorithm.

use super::workspace::NO_DOF;
use super::{Workspace, inertia6};
use crate::model::Model;
use crate::spatial::{FastTransform, SpatialTransform};
use nalgebra::{DMatrix, Matrix6};

/// The mass matrix `D(q)` of the paper's equation 1 (`D q̈ + h + c = τ`), by the composite
/// rigid body algorithm (Featherstone 2008, table 6.2), in world coordinates as Pinocchio's
/// `crba` with `Convention::WORLD` (Carpentier et al. 2019, *The Pinocchio C++ library*, §IV).
///
/// Forward pass: the world pose `0X_i = 0X_λ λX_i` of each body, its inertia `I_i` and its
/// joint's motion subspace `S_i` in world coordinates (world axes, about the origin of the
/// first body with mass rather than the world origin, for precision far from it). Backward pass: the composite inertia of
/// each subtree, `I^c_λ += I^c_i` (all in one frame, so no transform). Then for each
/// coordinate `k` of joint i, `F = I^c_i S_k` is the force that accelerates the whole subtree
/// at unit `q̈_k`, and `D[j, k] = D[k, j] = S_jᵀ F` for k and every coordinate j on its path to
/// the root (`ws.dof_parent`); entries between coordinates of different branches are zero.
///
/// Symmetric; positive definite unless the model has a massless chain or an euler joint model
/// is in gimbal lock. Bodies without mass or inertia (the fictitious links of a BVH euler model)
/// add nothing and are skipped. Writes `ws.x_up`, `ws.o_x_i` (poses relative to that point),
/// `ws.s_world`, `ws.inertia6` (composite inertias, world axes, about that point) and
/// `ws.mass_matrix`, and returns `&ws.mass_matrix`.
pub fn crba<'w>(model: &Model, ws: &'w mut Workspace, q: &[f64]) -> &'w DMatrix<f64> {
    let nv = model.nv;
    let n = model.nbodies();

    // reference point: the origin of the first body with mass (an avatar's pelvis, an arm's
    // base), so that lever arms stay short wherever the take walks to (world-frame sums lose
    // digits as |lever|²)
    let mut r = SpatialTransform::IDENTITY;
    for i in 1..n {
        let p = model.parent[i];
        let op = if p == 0 { r } else { ws.o_x_i[p] };
        let o = then(&op, &model.parent_transform(i, q));
        ws.o_x_i[i] = o;
        if !model.inertia[i].is_zero() {
            r = SpatialTransform::from_translation(-o.trans);
            break;
        }
    }

    // forward pass: poses, inertias and motion subspaces in world axes about that point
    for i in 1..n {
        let x = model.parent_transform(i, q);
        let p = model.parent[i];
        let o = then(if p == 0 { &r } else { &ws.o_x_i[p] }, &x);
        let inertia = &model.inertia[i];
        ws.inertia6[i] = if inertia.is_zero() {
            Matrix6::zeros()
        } else {
            inertia.transformed(&o).to_matrix()
        };
        let joint = &model.joints[i];
        let iv = model.idx_v[i];
        for k in 0..joint.nv() {
            ws.s_world[iv + k] = o.act_motion(&joint.subspace_col(k));
        }
        ws.x_up[i] = x;
        ws.o_x_i[i] = o;
    }

    // backward pass: composite inertias I^c_λ += I^c_i
    for i in (2..n).rev() {
        let p = model.parent[i];
        if p > 0 {
            let ic = ws.inertia6[i];
            ws.inertia6[p] += ic;
        }
    }

    // columns: F = I^c_i S_k, projected on k and on every coordinate above it
    let h = ws.mass_matrix.as_mut_slice();
    h.fill(0.0);
    for i in 1..n {
        let iv = model.idx_v[i];
        for k in iv..iv + model.joints[i].nv() {
            let f = inertia6::mul_motion(&ws.inertia6[i], &ws.s_world[k]);
            let mut j = k;
            while j != NO_DOF {
                // D is stored column-major: D[r, c] at r + c·nv
                let x = ws.s_world[j].dot(&f);
                h[j + k * nv] = x;
                h[k + j * nv] = x;
                j = ws.dof_parent[j];
            }
        }
    }
    &ws.mass_matrix
}

/// `0X_i = 0X_λ · λX_i` with `λX_i` in fast form (a coordinate-axis rotation mixes two columns).
#[inline]
fn then(o_parent: &SpatialTransform, x: &FastTransform) -> SpatialTransform {
    match x {
        FastTransform::Axis { trans, rot } => SpatialTransform::new(
            rot.premul(&o_parent.rot),
            o_parent.trans + o_parent.rot * trans,
        ),
        FastTransform::General(x) => o_parent.compose(x),
    }
}
