//! A take command's result as the table its CSV holds: `time` first, then the columns by name,
//! one row per frame (SI). The writers of `id`, `anatomy`, `simulate` and `export states` write
//! these tables, and the Python module hands the same tables out, so that the column names and
//! numbers of both front ends come from one function each.

use super::{Job, States, Torques, job_torques, states_header};
use crate::dynamics::grf::GroundQuality;
use crate::dynamics::grf::GroundReactions;
use crate::error::Error;
use crate::model::Model;
use crate::report::columns;
use crate::report::csv::{write_filled_rows, write_row_table};
use std::path::Path;

/// A result table: `header[0]` is `time`; every row has `header.len()` numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// Column names, `time` first, as the CSV's header.
    pub header: Vec<String>,
    /// One row per frame or recorded sample.
    pub rows: Vec<Vec<f64>>,
}

impl Table {
    /// Writes the table as CSV (`-` is standard output), atomically.
    pub fn write_csv(&self, path: &Path) -> Result<(), Error> {
        write_row_table(path, &self.header, &self.rows)
    }

    /// A table from named columns of equal length.
    pub fn from_columns(header: Vec<String>, columns: &[&[f64]]) -> Self {
        let n = columns.first().map_or(0, |c| c.len());
        let rows = (0..n)
            .map(|k| columns.iter().map(|c| c[k]).collect())
            .collect();
        Self { header, rows }
    }
}

/// `articula id`'s table: `time`, one torque column per coordinate; with ground contact the
/// ground reaction, centre of pressure and residual columns follow
/// ([`GroundReactions::columns`](crate::dynamics::grf::GroundReactions::columns)). Also how far
/// the feet could give the force the motion needs.
pub fn inverse_dynamics_table(job: &Job) -> Result<(Table, Option<GroundQuality>), Error> {
    let (t, grf) = job_torques(job)?;
    let header = inverse_dynamics_header(&t, grf.as_deref());
    let rows = made_rows(header.len(), t.time.len(), |k, r| {
        inverse_dynamics_row(&t, grf.as_deref(), k, r)
    });
    Ok((Table { header, rows }, grf.map(|g| g.quality())))
}

/// Writes [`inverse_dynamics_table`] of the torques `t` (and the ground reactions `grf` they
/// were computed with) as CSV to `path` (`-` is standard output), atomically, without making
/// the table ([`write_filled_rows`]).
pub(crate) fn write_inverse_dynamics_csv(
    t: &Torques,
    grf: Option<&GroundReactions>,
    path: &Path,
) -> Result<(), Error> {
    let fill = |k: usize, r: &mut Vec<f64>| inverse_dynamics_row(t, grf, k, r);
    let header = inverse_dynamics_header(t, grf);
    write_filled_rows(path, &header, t.time.len(), &fill)
}

/// The header of [`inverse_dynamics_table`].
fn inverse_dynamics_header(t: &Torques, grf: Option<&GroundReactions>) -> Vec<String> {
    let mut header = vec!["time".to_string()];
    header.extend(t.names.iter().map(|n| columns::name("tau", &[n])));
    if let Some(g) = grf {
        header.extend(g.columns());
    }
    header
}

/// Row `k` of [`inverse_dynamics_table`], appended to `r`.
fn inverse_dynamics_row(t: &Torques, grf: Option<&GroundReactions>, k: usize, r: &mut Vec<f64>) {
    r.push(t.time[k]);
    r.extend_from_slice(&t.tau[k]);
    if let Some(g) = grf {
        g.row(k, r);
    }
}

/// `n` rows of `width` values, row `k` what `fill(k, row)` appends (each row allocated once).
fn made_rows(width: usize, n: usize, fill: impl Fn(usize, &mut Vec<f64>)) -> Vec<Vec<f64>> {
    (0..n)
        .map(|k| {
            let mut r = Vec::with_capacity(width);
            fill(k, &mut r);
            r
        })
        .collect()
}

/// `articula export states`' table: `time`, `q:<coord>`, `v:<coord>`, `a:<coord>`.
pub fn states_table(model: &Model, s: &States) -> Table {
    let header = states_header(model);
    let rows = made_rows(header.len(), s.len(), |k, r| states_row(s, k, r));
    Table { header, rows }
}

/// Row `k` of [`states_table`], appended to `r`.
fn states_row(s: &States, k: usize, r: &mut Vec<f64>) {
    r.push(s.time[k]);
    r.extend_from_slice(&s.q[k]);
    r.extend_from_slice(&s.v[k]);
    r.extend_from_slice(&s.a[k]);
}

/// Writes [`states_table`] as CSV to `path` (`-` is standard output), atomically, without
/// making the table ([`write_filled_rows`]).
pub fn write_states_csv(model: &Model, s: &States, path: &Path) -> Result<(), Error> {
    let fill = |k: usize, r: &mut Vec<f64>| states_row(s, k, r);
    write_filled_rows(path, &states_header(model), s.len(), &fill)
}

/// `articula simulate -o`'s table: `time`, `q:<coord>`, `v:<coord>`, `tau:<coord>`,
/// `err:<coord>` per recorded row (SI).
pub fn simulation_table(model: &Model, result: &crate::dynamics::simulate::SimResult) -> Table {
    let mut header = vec!["time".to_string()];
    for (kind, names) in [
        ("q", &model.q_names),
        ("v", &model.v_names),
        ("tau", &model.v_names),
        ("err", &model.v_names),
    ] {
        header.extend(names.iter().map(|n| columns::name(kind, &[n])));
    }
    let rows: Vec<Vec<f64>> = (0..result.time.len())
        .map(|k| {
            let mut r = vec![result.time[k]];
            r.extend_from_slice(&result.q[k]);
            r.extend_from_slice(&result.v[k]);
            r.extend_from_slice(&result.tau[k]);
            r.extend_from_slice(&result.error[k]);
            r
        })
        .collect();
    Table { header, rows }
}

/// Peak |x| and root mean square of a column: the figures `articula batch` summarises and
/// the Python module's `Result.peaks()` and `.rms()` give.
pub fn peak_rms(x: &[f64]) -> (f64, f64) {
    let peak = x.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let rms = if x.is_empty() {
        0.0
    } else {
        (x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64).sqrt()
    };
    (peak, rms)
}

impl Table {
    /// [`peak_rms`] of every column after `time`, by name.
    pub fn peak_rms(&self) -> Vec<(String, f64, f64)> {
        (1..self.header.len())
            .map(|c| {
                let col: Vec<f64> = self.rows.iter().map(|r| r[c]).collect();
                let (peak, rms) = peak_rms(&col);
                (self.header[c].clone(), peak, rms)
            })
            .collect()
    }
}
