//! A take command's result as the table its CSV holds: `time` first, then the columns by name,
//! one row per frame (SI). The writers of `id`, `anatomy`, `simulate` and `export states` write
//! these tables, and the Python module hands the same tables out, so that the column names and
//! numbers of both front ends come from one function each.

use super::{Job, States, Take, Torques, job_torques, states_header};
use crate::dynamics::grf::GroundQuality;
use crate::dynamics::grf::GroundReactions;
use crate::error::Error;
use crate::model::Model;
use crate::report::columns;
use crate::report::csv::write_row_table;
use std::borrow::Cow;
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
    let (table, _, grf) = inverse_dynamics_parts(job)?;
    Ok((table, grf.map(|g| g.quality())))
}

/// [`inverse_dynamics_table`] with the torques and ground reactions it was made of (for the
/// `--json` figures).
pub(crate) fn inverse_dynamics_parts(
    job: &Job,
) -> Result<(Table, Torques, Option<Cow<'_, GroundReactions>>), Error> {
    let (t, grf) = job_torques(job)?;
    let mut header = vec!["time".to_string()];
    header.extend(t.names.iter().map(|n| columns::name("tau", &[n])));
    if let Some(g) = &grf {
        header.extend(g.columns());
    }
    let rows: Vec<Vec<f64>> = (0..t.time.len())
        .map(|k| {
            let mut r = vec![t.time[k]];
            r.extend_from_slice(&t.tau[k]);
            if let Some(g) = &grf {
                g.row(k, &mut r);
            }
            r
        })
        .collect();
    Ok((Table { header, rows }, t, grf))
}

/// `articula export states`' table: `time`, `q:<coord>`, `v:<coord>`, `a:<coord>`.
pub fn states_table(model: &Model, s: &States) -> Table {
    let rows: Vec<Vec<f64>> = (0..s.len())
        .map(|k| {
            let mut r = vec![s.time[k]];
            r.extend_from_slice(&s.q[k]);
            r.extend_from_slice(&s.v[k]);
            r.extend_from_slice(&s.a[k]);
            r
        })
        .collect();
    Table {
        header: states_header(model),
        rows,
    }
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

/// `articula export states` of a take.
pub fn take_states_table(take: &Take) -> Table {
    states_table(&take.model, &take.states)
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
