//! `articula.load(path, **take_options)` → `Take`; its commands → `Result` tables.

use crate::options::{TakeFlags, repeated};
use crate::to_py;
use articula_core::error::Error;
use articula_core::io::scene::Gains;
use articula_core::pipeline::{
    self, Contact, Job, TakeOptions, commands, consistency, flags, formats, table,
};
use numpy::{PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// Loads a take (BVH) as `articula COMMAND TAKE --flag …` does; the keywords are the take
/// flags (`mass=80`, `smooth="none"`, `contact="feet"`, `joints="ball"`, `unit="cm"`, …).
#[pyfunction]
#[pyo3(signature = (path, **take_options))]
pub fn load(
    py: Python<'_>,
    path: PathBuf,
    take_options: Option<&Bound<'_, PyDict>>,
) -> PyResult<Take> {
    let flags = TakeFlags::from_kwargs(take_options)?;
    let (options, gains) = options_of(&flags)?;
    let take = py
        .detach(|| pipeline::load_take(&path, &options))
        .map_err(to_py)?;
    Ok(Take {
        path,
        flags,
        options,
        gains,
        take,
    })
}

/// The take options of a scene (if any) with the flags over them, and the scene's gains.
fn options_of(f: &TakeFlags) -> PyResult<(TakeOptions, Option<Gains>)> {
    flags::options_from(f.scene().as_deref(), &f.flags()).map_err(to_py)
}

/// A loaded take: its model, states and notes; each command method returns a `Result`.
#[pyclass(frozen, module = "articula")]
pub struct Take {
    path: PathBuf,
    flags: TakeFlags,
    options: TakeOptions,
    gains: Option<Gains>,
    take: pipeline::Take,
}

impl Take {
    /// The options for `command` (refusing a take option it would ignore, as the command
    /// line refuses the flag).
    fn options_for(&self, command: &str) -> PyResult<TakeOptions> {
        flags::refuse_unused(command, &self.flags.flags().given()).map_err(to_py)?;
        Ok(self.options.clone())
    }

    /// The take loaded with `options`: this one when they are its own, else read again.
    fn take_with(&self, options: &TakeOptions) -> Result<pipeline::Take, Error> {
        if *options == self.options {
            Ok(self.take.clone())
        } else {
            pipeline::load_take(&self.path, options)
        }
    }
}

#[pymethods]
impl Take {
    /// The take's file.
    #[getter]
    fn path(&self) -> PathBuf {
        self.path.clone()
    }

    /// Frames (after the rest frame, if any, is dropped).
    #[getter]
    fn frames(&self) -> usize {
        self.take.states.len()
    }

    /// Time of each frame (s), 1-D.
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_vec(py, self.take.states.time.clone())
    }

    /// The model's coordinates (names of q).
    #[getter]
    fn coordinates(&self) -> Vec<String> {
        self.take.model.q_names.clone()
    }

    /// What the loader changed or found on its own.
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.take.notes.clone()
    }

    /// `articula info --json` as a dict.
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let options = self.options_for("info")?;
        let text = py
            .detach(|| {
                let mut t = self.take_with(&options)?;
                pipeline::resolve_contact(&mut t);
                Ok::<_, Error>(pipeline::info(&t).json().to_string())
            })
            .map_err(to_py)?;
        py.import("json")?.call_method1("loads", (text,))
    }

    /// `articula id`: torques (and ground reactions with contact) per frame.
    /// `consistent`: "on" or "off" (residual reduction; default off).
    #[pyo3(signature = (*, consistent = None))]
    fn inverse_dynamics(&self, py: Python<'_>, consistent: Option<String>) -> PyResult<Table> {
        let options = self.options_for("id")?;
        py.detach(|| {
            let mut job = Job::from_take(self.take_with(&options)?);
            if let Some(t) = job.take.as_mut() {
                pipeline::resolve_contact(t);
            }
            let contact = job
                .take
                .as_ref()
                .is_some_and(|t| t.options.contact == Contact::Feet);
            let reduce = commands::reduce_residuals(consistent.as_deref(), contact, false)?;
            let c = consistency::consistent_job(&mut job, reduce, true, None)?;
            let (table, quality) = table::inverse_dynamics_table(&job)?;
            let mut notes = job.take.as_ref().map_or(vec![], |t| t.notes.clone());
            notes.extend(quality.map(|q| q.to_string()));
            Ok(Table::new(table, notes, c.map(|c| c.json())))
        })
        .map_err(to_py)
    }

    /// `articula anatomy`: anatomical angles and moments per frame (ball joints unless
    /// `joints` was given). `consistent`: "on" (the default with contact) or "off".
    #[pyo3(signature = (*, consistent = None))]
    fn anatomy(&self, py: Python<'_>, consistent: Option<String>) -> PyResult<Table> {
        let options =
            commands::anatomy_options(self.options_for("anatomy")?, self.flags.joints_chosen());
        py.detach(|| {
            let mut take = self.take_with(&options)?;
            pipeline::resolve_contact(&mut take);
            let contact = take.options.contact == Contact::Feet;
            let reduce = commands::reduce_residuals(consistent.as_deref(), contact, true)?;
            let a = consistency::anatomy_consistent(&take, reduce)?;
            let mut notes = take.notes.clone();
            notes.extend(a.notes.iter().cloned());
            let summary = a.consistency.as_ref().map(|c| c.json());
            Ok(Table::new(
                pipeline::anatomy::anatomy_table(&a),
                notes,
                summary,
            ))
        })
        .map_err(to_py)
    }

    /// `articula simulate`: computed-torque tracking; the table `simulate -o` writes, and
    /// `summary` as `simulate --json`. `kp`, `kv`: a number, `{JOINT: X}` or a list of
    /// `"X"`/`"JOINT=X"`.
    #[pyo3(signature = (*, integrator = "rk4".to_string(), dt = 0.001, kp = None, kv = None, mass_error = 0.0, duration = None))]
    #[allow(clippy::too_many_arguments)]
    fn simulate(
        &self,
        py: Python<'_>,
        integrator: String,
        dt: f64,
        kp: Option<&Bound<'_, PyAny>>,
        kv: Option<&Bound<'_, PyAny>>,
        mass_error: f64,
        duration: Option<f64>,
    ) -> PyResult<Table> {
        let options = self.options_for("simulate")?;
        let kp = kp.map(repeated).transpose()?.unwrap_or_default();
        let kv = kv.map(repeated).transpose()?.unwrap_or_default();
        py.detach(|| {
            let settings = commands::sim_settings(
                &commands::SimFlags {
                    integrator: &integrator,
                    dt,
                    kp: &kp,
                    kv: &kv,
                    mass_error,
                    duration_s: duration,
                },
                self.gains.clone(),
            )?;
            let take = self.take_with(&options)?;
            let s = pipeline::simulate(&take, &settings, None)?;
            let table = table::simulation_table(&take.model, &s.result);
            Ok(Table::new(table, take.notes.clone(), Some(s.json())))
        })
        .map_err(to_py)
    }

    /// `articula export WHAT TAKE -o PATH`: writes the file; returns its table when it is a
    /// CSV table (`positions`, `states`, `grf`), else `None`.
    #[pyo3(signature = (path, what = "states".to_string(), *, format = None, trc_units = None))]
    fn export(
        &self,
        py: Python<'_>,
        path: PathBuf,
        what: String,
        format: Option<String>,
        trc_units: Option<String>,
    ) -> PyResult<Option<Table>> {
        let options = self.options_for(&format!("export {what}"))?;
        py.detach(|| {
            let mut take = self.take_with(&options)?;
            formats::export(
                &mut take,
                &what,
                &path,
                format.as_deref(),
                trc_units.as_deref(),
            )?;
            let is_table = formats::EXPORTS.iter().any(|(w, t)| *w == what && *t);
            let csv = formats::TableFormat::choose(&path, format.as_deref())?
                == formats::TableFormat::Csv;
            if !(is_table && csv) || path.as_os_str() == "-" {
                return Ok(None);
            }
            // the file just written, read back: its numbers are shortest round-trip, exact
            let (header, columns) = articula_core::report::csv::read_columns(&path)?;
            let refs: Vec<&[f64]> = columns.iter().map(Vec::as_slice).collect();
            let table = table::Table::from_columns(header, &refs);
            Ok(Some(Table::new(table, take.notes.clone(), None)))
        })
        .map_err(to_py)
    }

    fn __repr__(&self) -> String {
        format!(
            "<articula.Take {} frames={} coordinates={}>",
            self.path.display(),
            self.take.states.len(),
            self.take.model.nq
        )
    }
}

/// A command's result: the table its CSV holds.
#[pyclass(frozen, name = "Result", module = "articula")]
pub struct Table {
    table: table::Table,
    notes: Vec<String>,
    summary: Option<String>,
}

impl Table {
    /// One figure of every column (of name, peak, RMS), by name in column order.
    fn figures<'py>(
        &self,
        py: Python<'py>,
        pick: impl Fn(&str, f64, f64) -> f64,
    ) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (name, peak, rms) in self.table.peak_rms() {
            d.set_item(&name, pick(&name, peak, rms))?;
        }
        Ok(d)
    }

    fn new(table: table::Table, notes: Vec<String>, summary: Option<serde_json::Value>) -> Self {
        Self {
            table,
            notes,
            summary: summary.map(|s| s.to_string()),
        }
    }
}

#[pymethods]
impl Table {
    /// Time of each row (s), 1-D.
    #[getter]
    fn time<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        PyArray1::from_vec(py, self.table.rows.iter().map(|r| r[0]).collect())
    }

    /// The CSV's column names after `time`.
    #[getter]
    fn columns(&self) -> Vec<String> {
        self.table.header[1..].to_vec()
    }

    /// rows × columns (SI), without `time`.
    #[getter]
    fn values<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let rows = self.table.rows.len();
        let cols = self.table.header.len() - 1;
        let flat: Vec<f64> = self
            .table
            .rows
            .iter()
            .flat_map(|r| r[1..].iter().copied())
            .collect();
        Ok(PyArray1::from_vec(py, flat)
            .reshape([rows, cols])?
            .into_any())
    }

    /// What the pipeline noted (the take's notes, the ground estimate's quality, …).
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.notes.clone()
    }

    /// The command's JSON summary as a dict (`id`/`anatomy`: the consistency with contact;
    /// `simulate`: as `--json`), or None.
    #[getter]
    fn summary<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.summary
            .as_ref()
            .map(|s| py.import("json")?.call_method1("loads", (s.as_str(),)))
            .transpose()
    }

    /// Peak |x| of every column, by name in column order (as `articula batch`'s `peak:`
    /// columns).
    fn peaks<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.figures(py, |_, peak, _| peak)
    }

    /// Root mean square of every column, by name in column order (as `articula batch`'s
    /// `rms:` columns).
    fn rms<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.figures(py, |_, _, rms| rms)
    }

    /// A pandas DataFrame indexed by `time`, one column each; needs pandas installed.
    fn to_pandas<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let pandas = py.import("pandas").map_err(|_| {
            pyo3::exceptions::PyImportError::new_err(
                "Result.to_pandas() needs pandas: pip install pandas (or use .time, .columns \
                 and .values)",
            )
        })?;
        let kwargs = PyDict::new(py);
        kwargs.set_item("columns", self.columns())?;
        let index = pandas.call_method1("Index", (self.time(py),))?;
        index.setattr("name", "time")?;
        kwargs.set_item("index", index)?;
        pandas.call_method("DataFrame", (self.values(py)?,), Some(&kwargs))
    }

    fn __repr__(&self) -> String {
        format!(
            "<articula.Result rows={} columns={}>",
            self.table.rows.len(),
            self.table.header.len() - 1
        )
    }
}
