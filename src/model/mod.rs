//! The immutable articulated `Model` (Featherstone's model table; Pinocchio's `Model`).
//!
//! Invariants every algorithm relies on:
//! - body 0 is the world (no joint, no mass); for every other body `parent[i] < i`, so a
//!   forward loop `1..n` visits parents before children and a backward loop children first;
//! - joint `i` connects `parent[i]` to body `i`; its coordinates are
//!   `q[idx_q[i]..idx_q[i] + nq_i]` and `v[idx_v[i]..idx_v[i] + nv_i]`;
//! - all quantities are SI (m, kg, s, rad) and expressed in body frames (see `spatial`).
//!
//! A model is built once (by a [`ModelBuilder`]) and never changed by an algorithm.

pub mod anthropometry;
pub mod bvh;
pub mod dh;
pub mod joint;
pub mod simplify;
pub mod skeleton;
pub mod urdf;

pub use joint::JointKind;

use crate::rotation::EulerOrder;
use crate::spatial::{AxisRotation, FastTransform, SpatialInertia, SpatialTransform};
use nalgebra::Vector3;

/// Three hinges of a model that make one ball joint ([`Model::euler_triples`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct EulerTriple {
    /// The first hinge's body (its coordinates are `idx_q[body] .. idx_q[body] + 3`, and the
    /// same in v).
    pub body: usize,
    /// The hinges' axes in chain order.
    pub order: EulerOrder,
}

/// A superquadric used to draw a link: `|x/a|^(2/e2) + |y/b|^(2/e2)` … (Barr 1981), in the
/// body frame.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Superquadric {
    /// Centre in the body frame (m).
    pub center: Vector3<f64>,
    /// Rotation of the shape's axes in the body frame (its local z is the long axis).
    pub rot: nalgebra::Matrix3<f64>,
    /// Semi-axes a, b, c along the shape's local x, y, z (m).
    pub size: Vector3<f64>,
    /// Shape exponents (ε1 north-south, ε2 east-west); 1, 1 is an ellipsoid, → 0 a box.
    pub exponents: [f64; 2],
}

/// The immutable articulated model. Every `Vec` here has one entry per body (`nbodies`),
/// entry 0 being the world, unless said otherwise.
#[derive(Debug, Clone)]
pub struct Model {
    /// A short name for messages (file stem).
    pub name: String,
    /// Body names; `"world"` at 0. For BVH euler models, `<joint>.<channel>` per channel body.
    pub body_names: Vec<String>,
    /// `parent[i] < i` for `i ≥ 1`; `parent[0] = 0`.
    pub parent: Vec<usize>,
    /// The joint between `parent[i]` and `i`; `Fixed` at 0.
    pub joints: Vec<JointKind>,
    /// Pose of joint frame `i` in the frame of body `parent[i]` at q = 0 (Featherstone's
    /// `X_tree`, Pinocchio's `jointPlacements`), m.
    pub placement: Vec<SpatialTransform>,
    /// Spatial inertia of body `i` in its own frame, about its origin (kg, m, kg·m²).
    pub inertia: Vec<SpatialInertia>,
    /// First configuration coordinate of joint `i`.
    pub idx_q: Vec<usize>,
    /// First velocity coordinate of joint `i`.
    pub idx_v: Vec<usize>,
    /// Configuration size.
    pub nq: usize,
    /// Degrees of freedom.
    pub nv: usize,
    /// Gravity acceleration in the world frame (m/s²), e.g. `[0, -9.81, 0]` for a Y-up take.
    pub gravity: Vector3<f64>,
    /// Names of the `nq` configuration coordinates (`<joint>` or `<joint>:<comp>`).
    pub q_names: Vec<String>,
    /// Names of the `nv` velocity coordinates.
    pub v_names: Vec<String>,
    /// Joint name of each body (the name its coordinates carry).
    pub joint_names: Vec<String>,
    /// Viscous friction coefficient per velocity coordinate (`nv` entries; N·m·s/rad or N·s/m),
    /// the paper's `bᵢ`; zero unless set.
    pub damping: Vec<f64>,
    /// Drawing shape of each body, if it has one.
    pub shapes: Vec<Option<Superquadric>>,
}

impl Model {
    /// Number of bodies including the world.
    pub fn nbodies(&self) -> usize {
        self.parent.len()
    }
    /// Total mass (kg).
    pub fn total_mass(&self) -> f64 {
        self.inertia.iter().map(|i| i.mass).sum()
    }
    /// The neutral configuration (zero angles, identity quaternions).
    pub fn neutral(&self) -> Vec<f64> {
        let mut q = vec![0.0; self.nq];
        for i in 1..self.nbodies() {
            let j = &self.joints[i];
            j.neutral(&mut q[self.idx_q[i]..self.idx_q[i] + j.nq()]);
        }
        q
    }
    /// Every triple of hinges that together make one ball joint, a BVH joint's three rotation
    /// channels in the euler model: bodies `i`, `i + 1`, `i + 2` each the child of the one
    /// before, revolute about three distinct coordinate axes, no rotation or offset between
    /// them (the joint frame turns by `R_c1(q_i) R_c2(q_i+1) R_c3(q_i+2)`), the first two
    /// massless with no other children (the fictitious links). In body order, disjoint.
    pub fn euler_triples(&self) -> Vec<EulerTriple> {
        let n = self.nbodies();
        let mut children = vec![0usize; n];
        for i in 1..n {
            children[self.parent[i]] += 1;
        }
        let mut out = vec![];
        let mut i = 1;
        while i + 2 < n {
            let axes = [i, i + 1, i + 2].map(|b| self.joints[b].revolute_coordinate_axis());
            let chained = (1..3).all(|m| {
                let b = i + m;
                self.parent[b] == b - 1
                    && self.placement[b] == SpatialTransform::IDENTITY
                    && self.inertia[b - 1].mass == 0.0
                    && children[b - 1] == 1
            });
            let order = match axes {
                [Some(a), Some(b), Some(c)] if chained => EulerOrder::from_axes([a, b, c]),
                _ => None,
            };
            match order {
                Some(order) => {
                    out.push(EulerTriple { body: i, order });
                    i += 3;
                }
                None => i += 1,
            }
        }
        out
    }
    /// Index of the body called `name`.
    pub fn body_index(&self, name: &str) -> Option<usize> {
        self.body_names.iter().position(|n| n == name)
    }
    /// Index of the velocity coordinate called `name`.
    pub fn v_index(&self, name: &str) -> Option<usize> {
        self.v_names.iter().position(|n| n == name)
    }
    /// `λ(i)X_i(q) = X_tree(i) · X_J(q_i)`: the pose of body i in its parent's frame at `q`
    /// (Featherstone 2008, §4.1; Pinocchio's `liMi`), in the fast form when joint i is revolute
    /// about a coordinate axis and its placement has no rotation (every joint of a BVH euler
    /// model), otherwise as a general transform (a coordinate axis under a rotated placement
    /// still costs only the two columns the joint rotation mixes).
    #[inline]
    pub fn parent_transform(&self, i: usize, q: &[f64]) -> FastTransform {
        self.parent_transform_sc(i, q, |iq| crate::spatial::sin_cos(q[iq]))
    }

    /// [`Model::parent_transform`] with a revolute coordinate's sine and cosine read from
    /// `sc(iq)`: for a caller that took every angle's at once (`crate::lanes::sin_cos_many`,
    /// the same bits as [`crate::spatial::sin_cos`]), so the joint does not take them again.
    #[inline]
    pub fn parent_transform_sc(
        &self,
        i: usize,
        q: &[f64],
        sc: impl FnOnce(usize) -> (f64, f64),
    ) -> FastTransform {
        let (joint, placement, iq) = (&self.joints[i], &self.placement[i], self.idx_q[i]);
        match joint.revolute_coordinate_axis() {
            Some(k) => {
                let (sin, cos) = sc(iq);
                let rot = AxisRotation::from_sin_cos(k, sin, cos);
                if placement.rot == nalgebra::Matrix3::identity() {
                    FastTransform::Axis {
                        trans: placement.trans,
                        rot,
                    }
                } else {
                    FastTransform::General(SpatialTransform::new(
                        rot.premul(&placement.rot),
                        placement.trans,
                    ))
                }
            }
            None => {
                FastTransform::General(placement.compose(&joint.transform(&q[iq..iq + joint.nq()])))
            }
        }
    }
    /// `out = q ⊕ v·dt` joint by joint on the configuration manifold.
    pub fn integrate(&self, q: &[f64], v: &[f64], dt: f64, out: &mut [f64]) {
        for i in 1..self.nbodies() {
            let j = &self.joints[i];
            let (iq, iv) = (self.idx_q[i], self.idx_v[i]);
            j.integrate(
                &q[iq..iq + j.nq()],
                &v[iv..iv + j.nv()],
                dt,
                &mut out[iq..iq + j.nq()],
            );
        }
    }
    /// `out = q1 ⊖ q0`, the velocity that takes `q0` to `q1` in unit time.
    pub fn difference(&self, q0: &[f64], q1: &[f64], out: &mut [f64]) {
        for i in 1..self.nbodies() {
            let j = &self.joints[i];
            let (iq, iv) = (self.idx_q[i], self.idx_v[i]);
            j.difference(
                &q0[iq..iq + j.nq()],
                &q1[iq..iq + j.nq()],
                &mut out[iv..iv + j.nv()],
            );
        }
    }
    /// Renormalise every quaternion in `q`.
    pub fn normalize(&self, q: &mut [f64]) {
        for i in 1..self.nbodies() {
            let j = &self.joints[i];
            let iq = self.idx_q[i];
            j.normalize(&mut q[iq..iq + j.nq()]);
        }
    }
    /// The joint (body index) that owns velocity coordinate `k`.
    pub fn body_of_v(&self, k: usize) -> usize {
        (1..self.nbodies())
            .rev()
            .find(|&i| self.idx_v[i] <= k && self.joints[i].nv() > 0)
            .unwrap_or(0)
    }

    /// Whether velocity coordinate `k` is a rotation (rad; a moment in inverse dynamics):
    /// revolute joints and the rotation part of ball and free joints. Otherwise a translation
    /// (m; a force).
    pub fn is_angular(&self, k: usize) -> bool {
        let b = self.body_of_v(k);
        match self.joints[b] {
            JointKind::Revolute { .. } | JointKind::Spherical => true,
            JointKind::Free => k - self.idx_v[b] >= 3,
            JointKind::Prismatic { .. } | JointKind::Fixed => false,
        }
    }
}

/// Builds a [`Model`] body by body, keeping `parent < child` and the coordinate offsets.
#[derive(Debug, Clone)]
pub struct ModelBuilder {
    model: Model,
}

impl ModelBuilder {
    /// A model with only the world body.
    pub fn new(name: impl Into<String>, gravity: Vector3<f64>) -> Self {
        Self {
            model: Model {
                name: name.into(),
                body_names: vec!["world".into()],
                parent: vec![0],
                joints: vec![JointKind::Fixed],
                placement: vec![SpatialTransform::IDENTITY],
                inertia: vec![SpatialInertia::ZERO],
                idx_q: vec![0],
                idx_v: vec![0],
                nq: 0,
                nv: 0,
                gravity,
                q_names: vec![],
                v_names: vec![],
                joint_names: vec!["world".into()],
                damping: vec![],
                shapes: vec![None],
            },
        }
    }

    /// Adds body `name` attached to `parent` by `joint` (whose coordinates are named
    /// `joint_name`), with the joint frame at `placement` in the parent frame. Returns its index.
    pub fn add_body(
        &mut self,
        parent: usize,
        name: impl Into<String>,
        joint_name: impl Into<String>,
        joint: JointKind,
        placement: SpatialTransform,
        inertia: SpatialInertia,
    ) -> usize {
        let m = &mut self.model;
        let i = m.parent.len();
        assert!(parent < i, "parent {parent} must come before body {i}");
        let joint_name = joint_name.into();
        m.body_names.push(name.into());
        m.parent.push(parent);
        m.joints.push(joint);
        m.placement.push(placement);
        m.inertia.push(inertia);
        m.idx_q.push(m.nq);
        m.idx_v.push(m.nv);
        m.nq += joint.nq();
        m.nv += joint.nv();
        // coordinate names: `<joint>` for 1-DoF joints, `<joint>:<comp>` otherwise
        match joint.q_components() {
            [] if joint.nq() == 1 => m.q_names.push(joint_name.clone()),
            comps => m
                .q_names
                .extend(comps.iter().map(|c| format!("{joint_name}:{c}"))),
        }
        match joint.v_components() {
            [] if joint.nv() == 1 => m.v_names.push(joint_name.clone()),
            comps => m
                .v_names
                .extend(comps.iter().map(|c| format!("{joint_name}:{c}"))),
        }
        m.damping.extend(std::iter::repeat_n(0.0, joint.nv()));
        m.joint_names.push(joint_name);
        m.shapes.push(None);
        i
    }

    /// Sets the drawing shape of body `i`.
    pub fn set_shape(&mut self, i: usize, shape: Superquadric) {
        self.model.shapes[i] = Some(shape);
    }

    /// Sets the inertia of body `i`.
    pub fn set_inertia(&mut self, i: usize, inertia: SpatialInertia) {
        self.model.inertia[i] = inertia;
    }

    /// Read access to what has been built so far.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The finished, immutable model.
    pub fn build(self) -> Model {
        self.model
    }
}
