//! The states CSV (`export states` writes it, `id`/`fd --states` read it back): its header,
//! and reading it by column name.

use super::States;
use crate::error::Error;
use crate::model::Model;
use crate::report::columns;
use crate::report::csv::read_columns;
use std::path::Path;

/// Header of a states CSV for `model`: `time`, `q:<coord>`…, `v:<coord>`…, `a:<coord>`….
pub fn states_header(model: &Model) -> Vec<String> {
    let mut h = vec!["time".to_string()];
    h.extend(model.q_names.iter().map(|n| columns::name("q", &[n])));
    h.extend(model.v_names.iter().map(|n| columns::name("v", &[n])));
    h.extend(model.v_names.iter().map(|n| columns::name("a", &[n])));
    h
}

/// The columns a job needs from a states CSV. Forward dynamics computes the accelerations
/// from q, v and τ, so a states file without `a:` columns must do for it; inverse dynamics
/// needs them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StateColumns {
    /// `q:`, `v:` and `a:` for every coordinate.
    QVA,
    /// `q:` and `v:`; `a:` columns are optional (read when present, else zero).
    QV,
}

impl StateColumns {
    /// What a states file must hold, for error messages.
    pub(super) fn expected(self) -> &'static str {
        match self {
            StateColumns::QVA => "`time`, then q:, v:, a: columns",
            StateColumns::QV => "`time`, then q: and v: columns; a: columns optional",
        }
    }
}

/// Reads a states CSV written by `export states` (columns matched by name, any order; extra
/// columns ignored; `time` optional), every column required.
pub fn read_states(model: &Model, path: &Path) -> Result<States, Error> {
    read_states_with(model, path, StateColumns::QVA)
}

/// [`read_states`] needing only `columns`; a missing one is an error naming the first
/// missing column, in the file's order (q:, v:, then a:).
pub fn read_states_with(
    model: &Model,
    path: &Path,
    columns: StateColumns,
) -> Result<States, Error> {
    let (header, cols) = read_columns(path)?;
    let column = |name: &str| header.iter().position(|h| h == name).map(|i| &cols[i]);
    let find = |name: &str| -> Result<&Vec<f64>, Error> {
        column(name).ok_or_else(|| {
            Error::Invalid(format!(
                "{}: no column `{name}` (expected {} for {})",
                path.display(),
                columns.expected(),
                model.name
            ))
        })
    };
    // without a `time` column (e.g. the Pinocchio fixtures) samples are numbered 0, 1, 2 …
    let n = cols.first().map_or(0, |c| c.len());
    let time = match header.iter().position(|h| h == "time") {
        Some(i) => cols[i].clone(),
        None => (0..n).map(|k| k as f64).collect(),
    };
    let mut s = States {
        time,
        q: vec![vec![0.0; model.nq]; n],
        v: vec![vec![0.0; model.nv]; n],
        a: vec![vec![0.0; model.nv]; n],
    };
    for (j, name) in model.q_names.iter().enumerate() {
        let c = find(&columns::name("q", &[name]))?;
        for (row, x) in s.q.iter_mut().zip(c) {
            row[j] = *x;
        }
    }
    for (j, name) in model.v_names.iter().enumerate() {
        let cv = find(&columns::name("v", &[name]))?;
        for (row, x) in s.v.iter_mut().zip(cv) {
            row[j] = *x;
        }
    }
    for (j, name) in model.v_names.iter().enumerate() {
        let a = columns::name("a", &[name]);
        let ca = match columns {
            StateColumns::QVA => find(&a)?,
            StateColumns::QV => match column(&a) {
                Some(c) => c,
                None => continue,
            },
        };
        for (row, x) in s.a.iter_mut().zip(ca) {
            row[j] = *x;
        }
    }
    Ok(s)
}
