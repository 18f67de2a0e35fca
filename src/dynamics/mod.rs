//! Rigid-body dynamics over a [`Model`](crate::model::Model) and a reusable [`Workspace`]:
//! kinematics, inverse dynamics (RNEA), the paper's terms of `D q̈ + h + c = τ` (CRBA and the
//! bias terms), direct dynamics (ABA, or `D`, `h`, `c` and a sparse Cholesky solve), energy
//! and momentum.
//!
//! Every algorithm is a short function `algorithm(model, ws, inputs…)` that writes its outputs
//! into the workspace and allocates nothing.

pub mod aba;
pub mod bias;
pub mod crba;
pub mod energy;
pub mod forward;
pub mod grf;
pub mod inertia6;
pub mod kinematics;
pub mod rnea;
pub mod samples;
pub mod workspace;

pub use aba::aba;
pub use bias::{coriolis_terms, gravity_terms, nonlinear_effects};
pub use crba::crba;
pub use energy::{kinetic_energy, potential_energy, spatial_momentum};
pub use forward::{ForwardMethod, forward_dynamics, forward_dynamics_cholesky};
pub use kinematics::forward_kinematics;
pub use rnea::rnea;
pub use workspace::Workspace;
