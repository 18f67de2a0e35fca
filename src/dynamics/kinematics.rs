//! Forward kinematics: the world pose of every body.

use super::Workspace;
use super::rnea::JointStep;
use crate::model::Model;
use crate::spatial::{AxisRotation, FastTransform, SpatialTransform};
use nalgebra::Vector3;

/// World pose of every body at configuration `q` (Featherstone 2008, §4.1):
/// `0X_i = 0X_λ(i) · λ(i)X_i`, `λ(i)X_i = X_tree(i) · X_J(q_i)`. Writes `ws.o_x_i`.
///
/// Each joint is crossed as `rnea` crosses it ([`JointStep`], decided once per model): a
/// revolute joint about a coordinate axis under an unrotated placement mixes two columns of the
/// parent's rotation (the axis a constant, no branch on it) and adds the placement's
/// translation only when it has one; any other joint composes [`Model::parent_transform`].
/// CRBA and ABA start from this pass (`crba::world_poses`).
pub fn forward_kinematics(model: &Model, ws: &mut Workspace, q: &[f64]) {
    forward_kinematics_through(model, ws, q, model.nbodies() - 1);
}

/// [`forward_kinematics`] of bodies `1..=last` only (the bodies are numbered parents first,
/// so those are every ancestor of `last` and more): each pose bit for bit what the whole pass
/// writes. What a caller reading a few poses near the root needs, e.g. the root's orientation,
/// or the root-level bodies' poses that [`root_wrench`](super::grf) reads after RNEA (which
/// works in body frames and writes no world pose).
#[inline]
pub fn forward_kinematics_through(model: &Model, ws: &mut Workspace, q: &[f64], last: usize) {
    let n = (last + 1).min(model.nbodies());
    if n < 2 {
        return;
    }
    let parent = &model.parent[..n];
    let (steps, o_x_i) = (&ws.joint_steps[..n], &mut ws.o_x_i[..n]);
    // the sines and cosines of the angles of bodies 1..n at once (coordinates in body order)
    let nq = model.idx_q[n - 1] + model.joints[n - 1].nq();
    let (sin_q, cos_q) = (&mut ws.sin_q[..nq], &mut ws.cos_q[..nq]);
    crate::lanes::sin_cos_many(&q[..nq], sin_q, cos_q);
    let sc = |iq: usize| (sin_q[iq], cos_q[iq]);
    for i in 1..n {
        o_x_i[i] = body_pose(model, steps[i], &o_x_i[parent[i]], i, q, sc);
    }
}

/// [`forward_kinematics`] of the bodies `bodies` only (ascending, each body's parent among them
/// or the world): each pose bit for bit what the whole pass writes (the same sine and cosine,
/// [`crate::spatial::sin_cos`], and the same products). What a caller reading the poses along
/// a few chains needs, e.g. the feet's paths to the root ([`crate::dynamics::grf`]'s ground
/// reactions on the joints), without the arms and the head.
pub fn forward_kinematics_of(model: &Model, ws: &mut Workspace, q: &[f64], bodies: &[usize]) {
    let parent = &model.parent;
    let (steps, o_x_i) = (&ws.joint_steps, &mut ws.o_x_i);
    let sc = |iq: usize| crate::spatial::sin_cos(q[iq]);
    for &i in bodies {
        debug_assert!(parent[i] == 0 || bodies.contains(&parent[i]), "a chain");
        o_x_i[i] = body_pose(model, steps[i], &o_x_i[parent[i]], i, q, sc);
    }
}

/// Body `i`'s world pose `0X_i` from its parent's `op`, by its joint's `step`; `sc(iq)` gives
/// the sine and cosine of coordinate `iq` (an axis joint's angle).
#[inline(always)]
fn body_pose(
    model: &Model,
    step: JointStep,
    op: &SpatialTransform,
    i: usize,
    q: &[f64],
    sc: impl Fn(usize) -> (f64, f64),
) -> SpatialTransform {
    let iq = model.idx_q[i];
    match step {
        JointStep::Axis { k, shifted }
        | JointStep::Triple {
            k: [k, _, _],
            shifted,
        } => axis_pose(k, op, shifted.then_some(&model.placement[i].trans), sc(iq)),
        JointStep::InTriple { k } => axis_pose(k, op, None, sc(iq)),
        JointStep::General => then(op, &model.parent_transform_sc(i, q, sc)),
    }
}

/// `0X_i = 0X_λ λX_i` across a revolute joint about coordinate axis `k` (its angle's sine
/// and cosine `sc`) after the translation `t` (none: zero).
#[inline(always)]
fn axis_pose(
    k: usize,
    op: &SpatialTransform,
    t: Option<&Vector3<f64>>,
    sc: (f64, f64),
) -> SpatialTransform {
    match k {
        0 => axis_pose_k::<0>(op, t, sc),
        1 => axis_pose_k::<1>(op, t, sc),
        _ => axis_pose_k::<2>(op, t, sc),
    }
}

/// [`axis_pose`] with the axis a constant: two columns of the parent's rotation mixed.
#[inline(always)]
fn axis_pose_k<const K: usize>(
    op: &SpatialTransform,
    t: Option<&Vector3<f64>>,
    (sin, cos): (f64, f64),
) -> SpatialTransform {
    let rot = AxisRotation::from_sin_cos(K, sin, cos);
    SpatialTransform::new(
        rot.premul(&op.rot),
        t.map_or(op.trans, |t| op.trans + op.rot * t),
    )
}

/// `0X_i = 0X_λ · λX_i` with `λX_i` in fast form (a coordinate-axis rotation mixes two columns).
#[inline(always)]
fn then(o_parent: &SpatialTransform, x: &FastTransform) -> SpatialTransform {
    match x {
        FastTransform::Axis { trans, rot } => SpatialTransform::new(
            rot.premul(&o_parent.rot),
            o_parent.trans + o_parent.rot * trans,
        ),
        FastTransform::General(x) => o_parent.compose(x),
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
