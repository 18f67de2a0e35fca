//! Keyword arguments → the command line's flags as text (`pipeline::Flags`), so that the
//! library parses and validates them exactly as it does `--mass 80` or `--smooth none`.
//! The keywords are the flags' long names with `_` for `-`.

use articula_core::pipeline::Flags;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// How a keyword's value becomes flag text.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    /// One value (`str(value)`).
    Text,
    /// A number (float).
    Number,
    /// Repeatable: a value, a list of values, or a dict `{JOINT: X}` (`JOINT=X` each).
    List,
    /// A switch.
    Switch,
}

/// The take options and how each is given.
const TAKE_OPTIONS: &[(&str, Kind)] = &[
    ("unit", Kind::Text),
    ("stature", Kind::Number),
    ("up", Kind::Text),
    ("positions", Kind::Text),
    ("joints", Kind::Text),
    ("mass", Kind::Number),
    ("sex", Kind::Text),
    ("segments", Kind::Text),
    ("link_mass", Kind::List),
    ("smooth", Kind::Text),
    ("lock", Kind::List),
    ("subtree", Kind::Text),
    ("contact", Kind::Text),
    ("keep_first_frame", Kind::Switch),
    ("joint_translations", Kind::Text),
    ("damping", Kind::List),
    ("scene", Kind::Text),
];

/// The take options given as keywords, owned (a [`Flags`] borrows them).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TakeFlags {
    text: BTreeMap<&'static str, String>,
    numbers: BTreeMap<&'static str, f64>,
    lists: BTreeMap<&'static str, Vec<String>>,
    switches: BTreeMap<&'static str, bool>,
}

const NO_LIST: &[String] = &[];

impl TakeFlags {
    /// From `load`'s keywords; an unknown keyword is a `TypeError` naming the known ones.
    pub fn from_kwargs(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let mut f = Self::default();
        let Some(kwargs) = kwargs else {
            return Ok(f);
        };
        for (key, value) in kwargs.iter() {
            let key: String = key.extract()?;
            let Some(&(name, kind)) = TAKE_OPTIONS.iter().find(|(n, _)| *n == key) else {
                let known: Vec<&str> = TAKE_OPTIONS.iter().map(|(n, _)| *n).collect();
                return Err(PyTypeError::new_err(format!(
                    "load() got an unknown take option `{key}`; the take options are {}",
                    known.join(", ")
                )));
            };
            if value.is_none() {
                continue;
            }
            match kind {
                Kind::Text => {
                    f.text.insert(name, text(&value)?);
                }
                Kind::Number => {
                    f.numbers.insert(name, value.extract()?);
                }
                Kind::List => {
                    let mut items = repeated(&value)?;
                    // `lock` is comma-separated on the command line too
                    if name == "lock" {
                        items = items
                            .iter()
                            .flat_map(|s| s.split(',').map(str::to_string))
                            .collect();
                    }
                    f.lists.insert(name, items);
                }
                Kind::Switch => {
                    f.switches.insert(name, value.extract()?);
                }
            }
        }
        Ok(f)
    }

    fn text(&self, name: &str) -> Option<&str> {
        self.text.get(name).map(String::as_str)
    }

    fn list(&self, name: &str) -> &[String] {
        self.lists.get(name).map_or(NO_LIST, Vec::as_slice)
    }

    /// The scene file, if given.
    pub fn scene(&self) -> Option<PathBuf> {
        self.text("scene").map(PathBuf::from)
    }

    /// Whether `joints` (or a scene, which sets it) was given.
    pub fn joints_chosen(&self) -> bool {
        self.text("joints").is_some() || self.text("scene").is_some()
    }

    /// The flags as the command line hands them to the library.
    pub fn flags(&self) -> Flags<'_> {
        Flags {
            unit: self.text("unit"),
            stature_m: self.numbers.get("stature").copied(),
            up: self.text("up"),
            positions: self.text("positions"),
            joints: self.text("joints"),
            mass_kg: self.numbers.get("mass").copied(),
            sex: self.text("sex"),
            segments: self.text("segments"),
            link_mass: self.list("link_mass"),
            smooth: self.text("smooth"),
            lock: self.list("lock"),
            subtree: self.text("subtree"),
            contact: self.text("contact"),
            keep_first_frame: self
                .switches
                .get("keep_first_frame")
                .copied()
                .unwrap_or(false),
            damping: self.list("damping"),
            joint_translations: self.text("joint_translations"),
        }
    }
}

/// A value as flag text: a string as it is, anything else by `str()` (a float's `str` is its
/// shortest round-trip form, so the library parses the same number back).
pub fn text(value: &Bound<'_, PyAny>) -> PyResult<String> {
    Ok(value.str()?.to_string())
}

/// A repeatable flag's values: one value, a list or tuple of values, or a dict
/// `{NAME: X}` as `NAME=X` each.
pub fn repeated(value: &Bound<'_, PyAny>) -> PyResult<Vec<String>> {
    if let Ok(d) = value.cast::<PyDict>() {
        return d
            .iter()
            .map(|(k, v)| Ok(format!("{}={}", text(&k)?, text(&v)?)))
            .collect();
    }
    if value.cast::<PyList>().is_ok() || value.cast::<PyTuple>().is_ok() {
        return value.try_iter()?.map(|v| text(&v?)).collect();
    }
    Ok(vec![text(value)?])
}
