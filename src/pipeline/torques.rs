//! The algorithms a job runs over its samples and the files they write: inverse dynamics
//! (`articula id`, with the ground reactions when the take has contact), forward dynamics
//! (`articula fd`) and the mass matrix (`articula mass-matrix`).

use super::stages::Stage;
use super::{Job, States, ground_reactions, summary, table};
use crate::dynamics::{self, Workspace};
use crate::error::Error;
use crate::model::Model;
use crate::par;
use crate::report::columns;
use crate::report::csv::read_columns;
use crate::report::csv::{write_filled_rows, write_row_table};
use std::borrow::Cow;
use std::path::Path;

/// Generalized forces per sample (`nv` each), and optional ground reaction columns.
#[derive(Debug, Clone)]
pub struct Torques {
    pub time: Vec<f64>,
    pub names: Vec<String>,
    pub tau: Vec<Vec<f64>>,
}

/// Inverse dynamics over every sample of a job.
pub fn inverse_dynamics(model: &Model, states: &States) -> Torques {
    inverse_dynamics_with(model, states, &mut |_| true)
}

/// Samples between two calls of a progress callback.
pub const PROGRESS_EVERY: usize = 64;

/// [`inverse_dynamics`] that reports its progress (0‥1) to `keep_going` every
/// [`PROGRESS_EVERY`] samples and stops when it returns false: then `tau` holds only the
/// samples computed so far (fewer than `states.len()`). Frames in parallel
/// ([`par::for_each_block_reporting`]), each worker with one [`Workspace`] made once.
pub fn inverse_dynamics_with(
    model: &Model,
    states: &States,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Torques {
    let n = states.len();
    // each row allocated where it is written, from the workspace's torques (no zeroed table
    // filled again: one pass over the memory, on the worker's thread)
    let mut tau = vec![Vec::new(); n];
    let mut workspaces = par::scratch(|| Workspace::new(model));
    let reached = par::for_each_block_reporting(
        &mut tau,
        PROGRESS_EVERY,
        &mut workspaces,
        |ws, first, rows| {
            for (i, row) in rows.iter_mut().enumerate() {
                let k = first + i;
                let t = dynamics::rnea(model, ws, &states.q[k], &states.v[k], &states.a[k], None);
                *row = t.as_slice().to_vec();
            }
        },
        &mut |k| keep_going(k as f64 / n as f64),
    );
    tau.truncate(reached);
    Torques {
        time: states.time.clone(),
        names: model.v_names.clone(),
        tau,
    }
}

/// `articula id`: `time`, `tau:<coord>` per coordinate (N·m or N); with `--contact feet` the torques
/// are those with the ground reactions applied and `grf:<foot>:x|y|z`, `cop:<foot>:x|y|z`,
/// `residual:fx|fy|fz|tx|ty|tz` follow (N, m, N·m; world axes of the take), and the result is
/// how far the feet could give the ground force the motion needs
/// ([`GroundReactions::quality`](crate::dynamics::grf::GroundReactions::quality)).
pub fn write_inverse_dynamics(job: &Job, path: &Path) -> Result<IdOutcome, Error> {
    let (t, grf) = job_torques(job)?;
    table::write_inverse_dynamics_csv(&t, grf.as_deref(), path)?;
    Ok(IdOutcome::new(job, &t, grf.as_deref()))
}

/// What `articula id` found besides its file: the ground reactions' quality (estimated forces)
/// and the `--json` figures.
#[derive(Debug, Clone)]
pub struct IdOutcome {
    pub quality: Option<crate::dynamics::grf::GroundQuality>,
    pub summary: summary::IdSummary,
}

impl IdOutcome {
    pub(crate) fn new(
        job: &Job,
        t: &Torques,
        grf: Option<&crate::dynamics::grf::GroundReactions>,
    ) -> Self {
        Self {
            quality: grf.map(|g| g.quality()),
            summary: summary::id_summary(job, t, grf),
        }
    }
}

/// A job's generalized forces, with the ground reactions applied when the take has contact
/// (then also those reactions: the job's own, borrowed, when it holds measured or estimated
/// ones); an error when a torque is not finite.
pub fn job_torques(
    job: &Job,
) -> Result<
    (
        Torques,
        Option<Cow<'_, crate::dynamics::grf::GroundReactions>>,
    ),
    Error,
> {
    job_torques_marked(job, &mut |_| {})
}

/// [`job_torques`] that calls `done` at the end of [`Stage::Contact`] (the ground reactions,
/// when the take has contact) and of [`Stage::InverseDynamics`].
pub fn job_torques_marked<'j>(
    job: &'j Job,
    done: &mut dyn FnMut(Stage),
) -> Result<
    (
        Torques,
        Option<Cow<'j, crate::dynamics::grf::GroundReactions>>,
    ),
    Error,
> {
    let grf = match (&job.measured, &job.estimated, &job.take) {
        (Some(m), _, _) => Some(Cow::Borrowed(m)),
        (None, Some(e), _) => Some(Cow::Borrowed(e)),
        (None, None, Some(t)) => ground_reactions(t)?.map(Cow::Owned),
        (None, None, None) => None,
    };
    done(Stage::Contact);
    // with ground reactions, their estimate's torques are the answer (it ran RNEA with them)
    let t = match &grf {
        Some(g) => Torques {
            time: job.states.time.clone(),
            names: job.model.v_names.clone(),
            tau: g.tau.clone(),
        },
        None => inverse_dynamics(&job.model, &job.states),
    };
    check_finite(&t.tau, &t.names, "torque")?;
    done(Stage::InverseDynamics);
    Ok((t, grf))
}

fn check_finite(rows: &[Vec<f64>], names: &[String], what: &str) -> Result<(), Error> {
    // the culprit searched for only in a row that has one
    let bad_rows = rows
        .iter()
        .enumerate()
        .filter(|(_, r)| !crate::lanes::all_finite(r));
    for (k, r) in bad_rows {
        if let Some(j) = r.iter().position(|x| !x.is_finite()) {
            return Err(Error::Numerical(format!(
                "{what} of `{}` is not finite at sample {k}; nothing written",
                names.get(j).map(String::as_str).unwrap_or("?")
            )));
        }
    }
    Ok(())
}

/// `articula fd`: accelerations `a:<coord>` from states and a torques CSV (`tau:<coord>`, as
/// `articula id` writes; a coordinate's bare name, as `id` wrote before 0.x, is read too).
pub fn write_forward_dynamics(job: &Job, torques: &Path, path: &Path) -> Result<(), Error> {
    let m = &job.model;
    let (header, cols) = read_columns(torques)?;
    if header.iter().any(|h| h.starts_with("grf:")) {
        return Err(Error::Invalid(format!(
            "{}: these torques were computed with ground reactions (its `grf:` columns: \
             `articula id` with contact feet, the default on a take that stands); fd has no \
             contact model, so they would not give the motion back; write them with \
             `articula id --contact none`",
            torques.display()
        )));
    }
    let mut idx = Vec::with_capacity(m.nv);
    for n in &m.v_names {
        let tau = columns::name("tau", &[n]);
        let at = |name: &str| header.iter().position(|h| h == name);
        idx.push(at(&tau).or_else(|| at(n)).ok_or_else(|| {
            Error::Invalid(format!(
                "{}: no torque column `{tau}` (write it with `articula id`)",
                torques.display()
            ))
        })?);
    }
    let n = job.states.len();
    if cols.first().map_or(0, |c| c.len()) != n {
        return Err(Error::Invalid(format!(
            "{}: {} rows of torques for {n} states",
            torques.display(),
            cols.first().map_or(0, |c| c.len())
        )));
    }
    let mut ws = Workspace::new(m);
    let mut rows = Vec::with_capacity(n);
    let s = &job.states;
    let tau_rows = (0..n).map(|k| idx.iter().map(|&c| cols[c][k]).collect::<Vec<f64>>());
    for (k, tau) in tau_rows.enumerate() {
        let a = dynamics::aba(m, &mut ws, &s.q[k], &s.v[k], &tau, None)?;
        let mut r = vec![s.time[k]];
        r.extend(a.iter());
        rows.push(r);
    }
    let mut h = vec!["time".to_string()];
    h.extend(m.v_names.iter().map(|n| columns::name("a", &[n])));
    write_row_table(path, &h, &rows)
}

/// `articula mass-matrix`: D(q) row-major per sample, columns `M:<i>:<j>`.
pub fn write_mass_matrix(job: &Job, path: &Path) -> Result<(), Error> {
    let m = &job.model;
    let mut h = vec!["time".to_string()];
    for i in 0..m.nv {
        for j in 0..m.nv {
            h.push(columns::name("M", &[&i.to_string(), &j.to_string()]));
        }
    }
    let s = &job.states;
    // the rows made as they are written (a minute take's would be 7,200 × 9,217 numbers held
    // at once): each worker borrows a workspace from the pool for a row, then gives it back
    let pool = std::sync::Mutex::new(vec![]);
    let fill = |k: usize, r: &mut Vec<f64>| {
        let taken = pool.lock().map(|mut p| p.pop()).unwrap_or(None);
        let mut ws = taken.unwrap_or_else(|| Workspace::new(m));
        let d = dynamics::crba(m, &mut ws, &s.q[k]);
        r.push(s.time[k]);
        // row-major: D is symmetric (CRBA writes each entry and its mirror from one number),
        // so its column-major storage, read in order, is its rows one after the other
        r.extend_from_slice(d.as_slice());
        if let Ok(mut p) = pool.lock() {
            p.push(ws);
        }
    };
    write_filled_rows(path, &h, s.len(), &fill)
}
