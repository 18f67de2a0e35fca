//! A job: a model and the states to run an algorithm on — a take's own, or a robot's (URDF,
//! DH) with a states CSV — and where its model comes from.

use super::stages::Stage;
use super::{
    StateColumns, States, Take, TakeOptions, apply_damping, load_take, load_take_marked,
    read_states_with,
};
use crate::error::Error;
use crate::model::Model;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Where a job's model comes from.
#[derive(Debug, Clone)]
pub enum ModelSource {
    Take(PathBuf),
    /// A URDF and its options (fixed or floating base, gravity).
    Urdf(PathBuf, crate::model::urdf::UrdfOptions),
    Dh(PathBuf),
}

/// A model and states to run an algorithm on (a take, or a robot with a states file).
#[derive(Debug, Clone)]
pub struct Job {
    pub model: Model,
    /// Shared with the take's (`Take::states`), not copied.
    pub states: Arc<States>,
    /// The take, when the source is one (for contact and reports).
    pub take: Option<Take>,
    /// Measured ground reactions (`id --grf`, [`measured::use_measured_grf`]), used instead
    /// of the estimate.
    ///
    /// [`measured::use_measured_grf`]: super::measured::use_measured_grf
    pub measured: Option<crate::dynamics::grf::GroundReactions>,
    /// The ground reactions estimated on `take` as it is, kept by
    /// [`consistency::consistent_job`] (which needs them for its figures) so that
    /// [`job_torques`] does not estimate them a second time.
    ///
    /// [`consistency::consistent_job`]: super::consistency::consistent_job
    /// [`job_torques`]: super::job_torques
    pub estimated: Option<crate::dynamics::grf::GroundReactions>,
}

impl Job {
    /// A take's job: its model and its own states.
    pub fn from_take(take: Take) -> Self {
        Self {
            model: take.model.clone(),
            states: take.states.clone(),
            take: Some(take),
            measured: None,
            estimated: None,
        }
    }
}

/// Loads only the model of a source (for `bench`).
pub fn load_model(src: &ModelSource, opts: &TakeOptions) -> Result<Model, Error> {
    Ok(match src {
        ModelSource::Take(p) => load_take(p, opts)?.model,
        ModelSource::Urdf(..) | ModelSource::Dh(_) => robot_model(src, opts)?,
    })
}

/// A URDF or DH model with the options that apply to robots (damping).
fn robot_model(src: &ModelSource, opts: &TakeOptions) -> Result<Model, Error> {
    let mut model = match src {
        ModelSource::Urdf(p, o) => crate::model::urdf::read_urdf(p, o)?,
        ModelSource::Dh(p) => crate::model::dh::build_dh_model(&crate::io::dh::read(p)?)?,
        ModelSource::Take(p) => return Ok(load_take(p, opts)?.model),
    };
    apply_damping(&mut model, &opts.damping)?;
    Ok(model)
}

/// Loads a model and its states: a take's own states, or a states CSV (required for robots)
/// with every column, accelerations included.
pub fn load_source(
    src: &ModelSource,
    states: Option<&Path>,
    opts: &TakeOptions,
) -> Result<Job, Error> {
    load_source_with(src, states, opts, StateColumns::QVA)
}

/// [`load_source`] for a job that needs only the `columns` of a states CSV.
pub fn load_source_with(
    src: &ModelSource,
    states: Option<&Path>,
    opts: &TakeOptions,
    columns: StateColumns,
) -> Result<Job, Error> {
    load_source_marked(src, states, opts, columns, None, &mut |_| {})
}

/// [`load_source_with`] that calls `done` at the end of each stage ([`load_take_marked`],
/// then [`Stage::Job`]); `text` is the take's content already read, if any.
pub fn load_source_marked(
    src: &ModelSource,
    states: Option<&Path>,
    opts: &TakeOptions,
    columns: StateColumns,
    text: Option<&[u8]>,
    done: &mut dyn FnMut(Stage),
) -> Result<Job, Error> {
    let (model, own, take) = match src {
        ModelSource::Take(p) => {
            let t = load_take_marked(p, text, opts, done)?;
            (t.model.clone(), Some(t.states.clone()), Some(t))
        }
        ModelSource::Urdf(..) | ModelSource::Dh(_) => (robot_model(src, opts)?, None, None),
    };
    let states = match (states, own) {
        (Some(s), _) => Arc::new(read_states_with(&model, s, columns)?),
        (None, Some(own)) => own,
        (None, None) => {
            return Err(Error::Invalid(format!(
                "a robot model needs --states S.csv ({})",
                columns.expected()
            )));
        }
    };
    done(Stage::Job);
    Ok(Job {
        model,
        states,
        take,
        measured: None,
        estimated: None,
    })
}
