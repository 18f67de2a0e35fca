//! Rigid-body dynamics over a [`Model`](crate::model::Model) and a reusable [`Workspace`]:
//! kinematics, inverse dynamics (RNEA), and what builds on them.
//!
//! Every algorithm is a short function `algorithm(model, ws, inputs…)` that writes its outputs
//! into the workspace and allocates nothing.

pub mod kinematics;
pub mod rnea;
pub mod workspace;

pub use kinematics::forward_kinematics;
pub use rnea::rnea;
pub use workspace::Workspace;
