//! The named stages that turn a take (or a robot and a states file) and its options into a
//! model and the q, v, a that the dynamics uses; and the jobs the CLI, sessions and TUI run on
//! them. Every front end goes through here, so `articula id`, a session's `run id` and the
//! TUI's torque curves are the same numbers.
//!
//! A take flows through these stages, in order:
//! 1. `read`: parse the BVH (`io::bvh`);
//! 2. `axes and unit`: up axis and length unit detected from the rest pose, or given
//!    (`--up`, `--unit`, `--stature`), stature checked against 1.0–2.3 m;
//! 3. `position semantics`: add / replace / auto per joint; position channels of the joints
//!    below the body's root welded at their mean (`motion::weld`; `--joint-translations keep`
//!    keeps them as coordinates);
//! 4. `model`: euler or ball joints, de Leva masses, locks and subtree (`model::bvh`); a
//!    massless helper root folded into the pelvis (`motion::fold`);
//! 5. `q`: channels → q per frame (`motion::take`), Euler angles unwrapped;
//! 6. `smooth`: the chosen low-pass on q (`motion::smooth`);
//! 7. `v, a`: central differences on the configuration manifold (`Model::difference`), then
//!    of v.
//!
//! Where each part lives: `options.rs` (the take's options, the flags validated, the default
//! smoothing, per-joint settings), `load.rs` (stages 1–4 and the [`Take`]), `states/` (stages
//! 5–7), `job.rs` (a model and states to run an algorithm on, a take's or a robot's),
//! `torques.rs` (inverse and forward dynamics and the mass matrix over a job, and their files),
//! `states_csv.rs` (the states CSV read back), `export.rs` (states, joint positions, URDF, the
//! demo walk), `info.rs` (`articula info`); the [`States`] every stage and job share are here.

pub mod anatomy;
mod animation;
pub mod commands;
pub mod consistency;
mod contact;
mod edit;
mod export;
pub mod flags;
pub mod formats;
mod info;
mod job;
mod load;
pub mod measured;
mod mujoco;
mod options;
pub mod reduce;
mod sim;
pub mod stages;
mod states;
mod states_csv;
pub mod summary;
pub mod table;
mod torques;

pub use animation::{TO_Y_UP, export_gltf, rig_world_positions, take_rig, to_y_up};
pub use contact::{
    Contact, ContactFit, KeptFit, contact_choice, contact_feet, contact_params, edge_frames,
    estimate_take_ground_reactions, estimate_take_ground_reactions_with, ground_reactions,
    ground_reactions_with, resolve_contact, resolve_contact_after, same_motion, take_feet,
};
pub use edit::{blend_files, export_smoothed_bvh, export_smoothed_bvh_as};
pub(crate) use export::as_in_file;
pub use export::{
    JointCentres, export_positions, export_states, export_urdf, generate_walk, joint_centres,
};
pub use info::{Info, info};
pub use job::{Job, ModelSource, load_model, load_source, load_source_marked, load_source_with};
pub(crate) use load::at_file;
pub use load::{
    HeldContact, Take, load_take, load_take_marked, read_take, take_from_bvh, take_from_bvh_marked,
    take_from_bvh_reusing, take_from_bvh_with,
};
pub use mujoco::{export_mjcf, floor_level};
pub(crate) use options::parse_flag;
pub use options::{
    DEFAULT_CUTOFF_HZ, Flags, TakeOptions, apply_damping, default_smoothing, parse_per_joint,
    parse_smooth, per_coordinate,
};
pub use sim::{
    Bench, SimSettings, SimSummary, Tradeoff, TradeoffRow, bench, bench_batches,
    passive_energy_drift, reference, simulate, simulate_states, tradeoff, tradeoff_grid,
};
pub use stages::{STAGES, Stage, StageBench, StageSettings, bench_stages};
pub use states::{
    derivatives, make_euler_triples_continuous, take_states, take_states_marked, take_states_with,
    unwrap_and_smooth, unwrap_and_smooth_with,
};
pub use states_csv::{StateColumns, read_states, read_states_with, states_header};
pub use torques::{
    IdOutcome, PROGRESS_EVERY, Torques, inverse_dynamics, inverse_dynamics_with, job_torques,
    job_torques_marked, write_forward_dynamics, write_inverse_dynamics, write_mass_matrix,
};

pub use crate::io::scene::{Damping, PerJoint};

/// Generalized states over time: `q` (nq per sample), `v` and `a` (nv per sample), SI.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct States {
    /// Sample times (s).
    pub time: Vec<f64>,
    pub q: Vec<Vec<f64>>,
    pub v: Vec<Vec<f64>>,
    pub a: Vec<Vec<f64>>,
}

impl States {
    pub fn len(&self) -> usize {
        self.time.len()
    }
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }
}
