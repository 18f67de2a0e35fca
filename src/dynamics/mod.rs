//! Rigid-body dynamics over a [`Model`](crate::model::Model) and a reusable [`Workspace`]:
//! kinematics, inverse dynamics (RNEA), the paper's terms of `D q̈ + h + c = τ` (CRBA and the
//! bias terms), direct dynamics (ABA, or `D`, `h`, `c` and a sparse Cholesky solve), energy
//! and momentum; integrators, computed-torque control and the tracking simulation.
//!
//! Every algorithm is a short function `algorithm(model, ws, inputs…)` that writes its outputs
//! into the workspace and allocates nothing.

pub mod aba;
pub mod anatomy;
pub mod bench;
pub mod bias;
pub mod control;
pub mod crba;
pub mod diagnose;
pub mod energy;
pub mod forward;
pub mod grf;
pub mod inertia6;
pub mod integrate;
pub mod kinematics;
pub mod residual;
pub mod rnea;
pub mod rra;
pub mod samples;
pub mod simulate;
pub mod workspace;

pub use aba::aba;
pub use bench::{BenchResult, time_algorithms};
pub use bias::{coriolis_terms, gravity_terms, nonlinear_effects};
pub use control::{ComputedTorque, Gains, Reference};
pub use crba::crba;
pub use diagnose::{Consistency, forward_inverse_residual};
pub use energy::{kinetic_energy, potential_energy, spatial_momentum};
pub use forward::{ForwardMethod, forward_dynamics, forward_dynamics_cholesky};
pub use integrate::{ButcherTableau, Integrator, Stepper};
pub use kinematics::{forward_kinematics, forward_kinematics_through, last_root_level_body};
pub use rnea::rnea;
pub use simulate::{SimOptions, SimResult, floating_root_nv, simulate};
pub use workspace::Workspace;
