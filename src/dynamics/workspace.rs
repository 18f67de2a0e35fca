//! Per-evaluation buffers, allocated once per model and reused by every call (Pinocchio's
//! `Data`, MuJoCo's `mjData`). Each field says its shape, frame, unit and which function
//! writes it.

use crate::model::Model;
use crate::spatial::{ForceVec, MotionVec, SpatialTransform};
use nalgebra::DVector;

/// Scratch and results of the dynamics algorithms for one model.
#[derive(Debug, Clone)]
pub struct Workspace {
    /// Pose of body i in its parent's frame at the current q (`nbodies`); written by
    /// `forward_kinematics` and `rnea`.
    pub li_x_i: Vec<SpatialTransform>,
    /// Pose of body i in the world frame (`nbodies`); written by `forward_kinematics`.
    pub o_x_i: Vec<SpatialTransform>,
    /// Spatial velocity of body i, body frame (`nbodies`, rad/s, m/s); written by `rnea`.
    pub v: Vec<MotionVec>,
    /// Spatial acceleration of body i, body frame, gravity included as a fictitious upward
    /// acceleration of the world (`nbodies`); written by `rnea`.
    pub a: Vec<MotionVec>,
    /// Spatial force transmitted by joint i onto body i, body frame (`nbodies`, N·m, N);
    /// written by `rnea`.
    pub f: Vec<ForceVec>,
    /// Generalized forces (`nv`, N·m or N); written by `rnea`.
    pub tau: DVector<f64>,
}

impl Workspace {
    /// Buffers sized for `model`.
    pub fn new(model: &Model) -> Self {
        let n = model.nbodies();
        Self {
            li_x_i: vec![SpatialTransform::IDENTITY; n],
            o_x_i: vec![SpatialTransform::IDENTITY; n],
            v: vec![MotionVec::ZERO; n],
            a: vec![MotionVec::ZERO; n],
            f: vec![ForceVec::ZERO; n],
            tau: DVector::zeros(model.nv),
        }
    }
}
