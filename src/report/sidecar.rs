//! The sidecar `NAME.csv.json` beside every CSV articula writes to a file: what each column is and
//! in which unit, what it was computed from and how, and which articula wrote it.
//!
//! Keys (documented in docs/formats.md): `file` (the CSV's file name), `articula_version`,
//! `command` (the articula command or session command that wrote it), `arguments` (its
//! arguments as given), `take` (the take's path, or null for a robot), `settings` (the take's
//! resolved settings: unit, up axis, joint model, smoothing, contact, mass …; text values),
//! `columns` (one `{name, quantity, unit}` per CSV column, in order, units from
//! [`super::columns::KINDS`]), `notes` (what the pipeline assumed, changed or found) and
//! `consistency` (with ground contact: the residual figures against Hicks et al.'s thresholds
//! the columns were computed with, issue 14; null otherwise).
//! Written with the one atomic writer ([`crate::io::write_atomic`]); never for standard output.

use super::columns;
use crate::error::Error;
use crate::model::Model;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// One CSV column: its name, what it holds, its unit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ColumnInfo {
    pub name: String,
    pub quantity: String,
    pub unit: String,
}

/// The sidecar's content.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sidecar {
    pub file: String,
    pub articula_version: String,
    pub command: String,
    pub arguments: Vec<String>,
    pub take: Option<String>,
    pub settings: BTreeMap<String, String>,
    pub columns: Vec<ColumnInfo>,
    pub notes: Vec<String>,
    /// With ground contact, the take's consistency the columns were computed with: the
    /// residual figures before and after reduction against Hicks et al.'s thresholds, as
    /// `anatomy --json` prints them (`pipeline::consistency::Consistency::json`); null
    /// without contact or for a table that is no take's.
    #[serde(default)]
    pub consistency: Option<serde_json::Value>,
}

/// The columns of `header` with their quantities and units for `model` (an error names the
/// first column outside the scheme); `known` gives `(column, unit)` of columns a summary's
/// `peak:<column>` names that neither the scheme nor the model settles (a batch's, from its
/// outputs' sidecars).
pub fn describe(
    header: &[String],
    model: Option<&Model>,
    known: &[(String, String)],
) -> Result<Vec<ColumnInfo>, Error> {
    let known = |c: &str| {
        (known.iter())
            .find(|(n, _)| n == c)
            .and_then(|(_, u)| columns::scheme_unit(u))
    };
    header
        .iter()
        .map(|h| {
            let unit = columns::unit_of_known(h, model, &known)?;
            let quantity = columns::kind_of(h).map_or("", |k| k.quantity);
            Ok(ColumnInfo {
                name: h.clone(),
                quantity: quantity.into(),
                unit: unit.into(),
            })
        })
        .collect()
}

/// Where the sidecar of `csv` goes: the file's whole name with `.json` added (`t.csv.json`
/// beside `t.csv`), so that it never takes the name of another output (`articula info t.bvh
/// --json > t.json`, a batch's `info` and `id` into one folder); `None` for standard output
/// (`-`), for anything that is not a regular file once written (a device, a FIFO), and for an
/// output whose own name ends in `.json`.
pub fn path_for(csv: &Path) -> Option<PathBuf> {
    if csv.as_os_str() == "-" || !csv.is_file() {
        return None;
    }
    if csv
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("json"))
    {
        return None;
    }
    let mut name = csv.as_os_str().to_owned();
    name.push(".json");
    Some(PathBuf::from(name))
}

/// The sidecar of the CSV at `csv` as written: its header line read back, so that the
/// sidecar's columns are the file's. Errors when the header holds a name outside the scheme.
pub fn read_header(csv: &Path) -> Result<Vec<String>, Error> {
    use std::io::BufRead;
    let f = std::fs::File::open(csv).map_err(|e| Error::io(csv, e))?;
    let mut line = String::new();
    std::io::BufReader::new(f)
        .read_line(&mut line)
        .map_err(|e| Error::io(csv, e))?;
    Ok(super::csv::parse_columns(&line, csv)?.0)
}

/// Writes `sidecar` beside `csv` ([`path_for`]) atomically; returns its path, or `None` when
/// `csv` gets no sidecar.
pub fn write(csv: &Path, sidecar: &Sidecar) -> Result<Option<PathBuf>, Error> {
    let Some(p) = path_for(csv) else {
        return Ok(None);
    };
    let text = serde_json::to_string_pretty(sidecar)
        .map_err(|e| Error::Invalid(format!("sidecar {}: {e}", p.display())))?;
    crate::io::write_atomic(&p, format!("{text}\n").as_bytes())?;
    Ok(Some(p))
}
