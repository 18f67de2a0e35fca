//! Models from Denavit–Hartenberg tables ([`crate::io::dh`]), in Corke's conventions.
//!
//! A model body frame must be the joint frame moved by the joint (`X_tree · X_J(q)`), with the
//! joint axis fixed in it. Rotation about z and translation along z commute, so each DH
//! transform splits into a constant placement, the joint motion about/along z, and a constant
//! pose of the DH link frame in the body frame ([`link_frame`]):
//!
//! - standard, `A_i = Rz(θ) Tz(d) Tx(a) Rx(α)`: body i = link frame i−1 · Rz(θ) (R) or
//!   · Rz(θ) Tz(d) (P); placement = `L_{i−1} · Rz(offset)` (R) or `L_{i−1} · Rz(θ) Tz(offset)`
//!   (P); link frame i = body i · `Tz(d) Tx(a) Rx(α)` (R) or `Tx(a) Rx(α)` (P);
//! - modified, `A_i = Rx(α) Tx(a) Rz(θ) Tz(d)`: body i = link frame i; placement =
//!   `Rx(α) Tx(a) Tz(d) Rz(offset)` (R) or `Rx(α) Tx(a) Rz(θ) Tz(offset)` (P).
//!
//! The link's mass, COM `r` and inertia `I` (link frame) are moved into the body frame. Joints
//! are named `j1 … jN`, bodies `link1 … linkN` (as the toolbox fixtures). Joint limits stay in
//! the table (the model has none).

use crate::error::Error;
use crate::io::dh::{DhConvention, DhJointType, DhTable};
use crate::model::joint::axis_angle;
use crate::model::{JointKind, Model, ModelBuilder};
use crate::spatial::{SpatialInertia, SpatialTransform};
use nalgebra::Vector3;

fn rz(t: f64) -> SpatialTransform {
    SpatialTransform::from_rotation(axis_angle(&Vector3::z(), t))
}
fn rx(t: f64) -> SpatialTransform {
    SpatialTransform::from_rotation(axis_angle(&Vector3::x(), t))
}
fn tz(d: f64) -> SpatialTransform {
    SpatialTransform::from_translation(Vector3::new(0.0, 0.0, d))
}
fn tx(a: f64) -> SpatialTransform {
    SpatialTransform::from_translation(Vector3::new(a, 0.0, 0.0))
}

/// Pose of DH link frame `i` (0-based link index) in the frame of model body `i + 1`.
pub fn link_frame(table: &DhTable, i: usize) -> SpatialTransform {
    let l = &table.links[i];
    match (table.convention, l.joint_type) {
        (DhConvention::Standard, DhJointType::R) => tz(l.d).compose(&tx(l.a)).compose(&rx(l.alpha)),
        (DhConvention::Standard, DhJointType::P) => tx(l.a).compose(&rx(l.alpha)),
        (DhConvention::Modified, _) => SpatialTransform::IDENTITY,
    }
}

/// The model of a DH table (see the module doc).
///
/// Errors: none beyond the table's own validation today; the `Result` leaves room for tables
/// the model cannot represent.
pub fn build_dh_model(table: &DhTable) -> Result<Model, Error> {
    let mut b = ModelBuilder::new(table.name.clone(), table.gravity);
    let mut prev_link = SpatialTransform::IDENTITY;
    for (i, l) in table.links.iter().enumerate() {
        let placement = match (table.convention, l.joint_type) {
            (DhConvention::Standard, DhJointType::R) => prev_link.compose(&rz(l.offset)),
            (DhConvention::Standard, DhJointType::P) => {
                prev_link.compose(&rz(l.theta)).compose(&tz(l.offset))
            }
            (DhConvention::Modified, DhJointType::R) => rx(l.alpha)
                .compose(&tx(l.a))
                .compose(&tz(l.d))
                .compose(&rz(l.offset)),
            (DhConvention::Modified, DhJointType::P) => rx(l.alpha)
                .compose(&tx(l.a))
                .compose(&rz(l.theta))
                .compose(&tz(l.offset)),
        };
        let joint = match l.joint_type {
            DhJointType::R => JointKind::Revolute { axis: Vector3::z() },
            DhJointType::P => JointKind::Prismatic { axis: Vector3::z() },
        };
        let lf = link_frame(table, i);
        let inertia = SpatialInertia::new(l.m, l.r, l.inertia).transformed(&lf);
        b.add_body(
            i,
            format!("link{}", i + 1),
            format!("j{}", i + 1),
            joint,
            placement,
            inertia,
        );
        prev_link = lf;
    }
    Ok(b.build())
}
