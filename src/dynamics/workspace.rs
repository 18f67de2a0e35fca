//! Per-evaluation buffers, allocated once per model and reused by every call (Pinocchio's
//! `Data`, MuJoCo's `mjData`). Each field says its shape, frame, unit and which function
//! writes it.

use super::crba::WorldInertia;
use super::inertia6::SymInertia6;
use super::rnea::{JointStep, joint_steps};
use crate::model::Model;
use crate::spatial::{AxisRotation, FastTransform, ForceVec, MotionVec, SpatialTransform};
use nalgebra::{DMatrix, DVector, Matrix6, Vector6};

/// Marks "no parent degree of freedom" in [`Workspace::dof_parent`].
pub const NO_DOF: usize = usize::MAX;

/// Scratch and results of the dynamics algorithms for one model.
#[derive(Debug, Clone)]
pub struct Workspace {
    /// Pose of body i in its parent's frame at the current q (`nbodies`); written by the
    /// energy functions (`forward_kinematics` writes the world poses only).
    pub li_x_i: Vec<SpatialTransform>,
    /// The same pose in the fast form of `Model::parent_transform` (`nbodies`); written by
    /// `rnea` for the joints of [`JointStep::General`] (the others' is `joint_rot`).
    pub x_up: Vec<FastTransform>,
    /// The joint rotation of each joint of [`JointStep::Axis`] (`nbodies`, its placement
    /// being a translation only); written by `rnea`.
    pub joint_rot: Vec<AxisRotation>,
    /// `sin q` and `cos q` of every coordinate of the pass's configuration
    /// ([`crate::lanes::sin_cos_many`]), which the axis joints' rotations read.
    pub sin_q: Vec<f64>,
    pub cos_q: Vec<f64>,
    /// Pose of body i in the world frame (`nbodies`); written by `forward_kinematics` and the
    /// energy functions (and `aba`); `crba` writes it relative to the origin of the first body
    /// with mass (world axes). Entry 0 stays the identity.
    pub o_x_i: Vec<SpatialTransform>,
    /// Motion subspace column of each velocity coordinate in world axes (`nv`; the spatial
    /// velocity of its body at unit rate, at unit rate); written by `crba` (about its reference point)
    /// and `aba` (about the body's origin).
    pub s_world: Vec<MotionVec>,
    /// Spatial velocity of body i, body frame (`nbodies`, rad/s, m/s); written by `rnea` and
    /// the energy functions.
    pub v: Vec<MotionVec>,
    /// Spatial acceleration of body i, body frame, gravity included as a fictitious upward
    /// acceleration of the world (`nbodies`); written by `rnea`.
    pub a: Vec<MotionVec>,
    /// Spatial force transmitted by joint i onto body i, body frame (`nbodies`, N·m, N);
    /// written by `rnea`.
    pub f: Vec<ForceVec>,
    /// Generalized forces (`nv`, N·m or N); written by `rnea` (and the bias-term functions,
    /// which run it).
    pub tau: DVector<f64>,
    /// Composite rigid-body inertia `I^c_i` of the subtree of body i (`nbodies`, kg, kg·m,
    /// kg·m²), world axes, about `crba`'s reference point (the origin of the first body with
    /// mass); written by `crba`.
    pub ycrb: Vec<WorldInertia>,
    /// Articulated-body inertia `I^A_i` of body i, angular first, world axes about the body's
    /// origin (`nbodies`, kg, kg·m, kg·m²); written by `aba`.
    pub oyaba: Vec<SymInertia6>,
    /// Articulated bias force `p^A_i`, world axes about the body's origin (`nbodies`, N·m, N);
    /// written by `aba`.
    pub p_a: Vec<ForceVec>,
    /// Velocity-product acceleration `c_i = v_i ×ₘ S_i q̇_i`, world axes about the body's
    /// origin (`nbodies`); written by `aba`.
    pub c: Vec<MotionVec>,
    /// Spatial velocity of body i, world axes about its origin (`nbodies`); written by `aba`.
    pub ov: Vec<MotionVec>,
    /// Spatial acceleration of body i, world axes about its origin, gravity included as an
    /// upward acceleration of the world (`nbodies`); written by `aba`.
    pub oa: Vec<MotionVec>,
    /// The lever from the parent's origin to body i's, world axes (`nbodies`, m); written by
    /// `aba`.
    pub lever: Vec<nalgebra::Vector3<f64>>,
    /// `U = I^A_i S_k` for each velocity coordinate k of body i, world axes about its origin
    /// (`nv`); written by `aba`.
    pub u_f: Vec<ForceVec>,
    /// `D_i⁻¹ = (S_iᵀ U_i)⁻¹`, its top-left `nv_i × nv_i` block used (`nbodies`); written by
    /// `aba`.
    pub d_inv: Vec<Matrix6<f64>>,
    /// `u_i = τ_i − b_i q̇_i − S_iᵀ p^A_i`, its first `nv_i` entries used (`nbodies`); written by
    /// `aba`.
    pub u_vec: Vec<Vector6<f64>>,
    /// The joint-space inertia (mass) matrix `D(q)` (`nv × nv`, symmetric, kg·m² / kg);
    /// written by `crba`, which writes only the entries of coordinates on one path to the root:
    /// the others are zero from here on and must stay so (nothing else writes this matrix).
    pub mass_matrix: DMatrix<f64>,
    /// Gravity term `c(q)` (`nv`, N·m or N); written by `gravity_terms`.
    pub gravity: DVector<f64>,
    /// Velocity term `h(q, v)`, Coriolis and centripetal (`nv`); written by `coriolis_terms`.
    pub coriolis: DVector<f64>,
    /// `h(q, v) + c(q)` (Pinocchio's `nle`, `nv`); written by `nonlinear_effects` and
    /// `forward_dynamics_cholesky` (which also subtracts the external forces' share).
    pub nle: DVector<f64>,
    /// Joint accelerations `q̈` (`nv`, rad/s² or m/s²); written by `aba` and
    /// `forward_dynamics_cholesky`.
    pub qdd: DVector<f64>,
    /// The `LᵀDL` factors of `D(q)` in place (`nv × nv`, Featherstone 2008 §6.5: `D` on the
    /// diagonal, `L` below it, only ancestor entries meaningful); written by
    /// `forward_dynamics_cholesky`.
    pub ltdl: DMatrix<f64>,
    /// For each velocity coordinate, the previous coordinate on its path to the root (the
    /// expanded parent array λ of Featherstone 2008 §6.5), or [`NO_DOF`] (`nv`); constant, set
    /// by [`Workspace::new`] from the model's topology.
    pub dof_parent: Vec<usize>,
    /// How `rnea` crosses each joint (`nbodies`); constant, set by [`Workspace::new`] from the
    /// model's joints and placements (so a workspace serves the model it was made for).
    pub joint_steps: Vec<JointStep>,
}

impl Workspace {
    /// Buffers sized for `model`.
    pub fn new(model: &Model) -> Self {
        let n = model.nbodies();
        let nv = model.nv;
        Self {
            li_x_i: vec![SpatialTransform::IDENTITY; n],
            o_x_i: vec![SpatialTransform::IDENTITY; n],
            x_up: vec![FastTransform::default(); n],
            joint_rot: vec![AxisRotation::new(0, 0.0); n],
            sin_q: vec![0.0; model.nq],
            cos_q: vec![0.0; model.nq],
            s_world: vec![MotionVec::ZERO; nv],
            v: vec![MotionVec::ZERO; n],
            a: vec![MotionVec::ZERO; n],
            f: vec![ForceVec::ZERO; n],
            tau: DVector::zeros(nv),
            ycrb: vec![WorldInertia::default(); n],
            oyaba: vec![SymInertia6::default(); n],
            p_a: vec![ForceVec::ZERO; n],
            c: vec![MotionVec::ZERO; n],
            ov: vec![MotionVec::ZERO; n],
            oa: vec![MotionVec::ZERO; n],
            lever: vec![nalgebra::Vector3::zeros(); n],
            u_f: vec![ForceVec::ZERO; nv],
            d_inv: vec![Matrix6::zeros(); n],
            u_vec: vec![Vector6::zeros(); n],
            mass_matrix: DMatrix::zeros(nv, nv),
            gravity: DVector::zeros(nv),
            coriolis: DVector::zeros(nv),
            nle: DVector::zeros(nv),
            qdd: DVector::zeros(nv),
            ltdl: DMatrix::zeros(nv, nv),
            dof_parent: dof_parents(model),
            joint_steps: joint_steps(model),
        }
    }
}

/// The expanded parent array λ over velocity coordinates: within a joint, each coordinate's
/// parent is the previous one; a joint's first coordinate hangs from the last coordinate of the
/// nearest ancestor joint that has any.
fn dof_parents(model: &Model) -> Vec<usize> {
    // last coordinate of each body's nearest moving ancestor-or-self
    let mut last = vec![NO_DOF; model.nbodies()];
    let mut out = vec![NO_DOF; model.nv];
    for i in 1..model.nbodies() {
        let inherited = last[model.parent[i]];
        let nv = model.joints[i].nv();
        let iv = model.idx_v[i];
        for k in 0..nv {
            out[iv + k] = if k == 0 { inherited } else { iv + k - 1 };
        }
        last[i] = if nv > 0 { iv + nv - 1 } else { inherited };
    }
    out
}
