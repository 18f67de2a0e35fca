//! Every `set` key as one row of a table ([`SETTINGS`]): its name, the value it takes, its
//! help, the values completion offers, how a value is checked and applied, and its row in the
//! parameter panel (shown value, unit, the step of ←/→). The parser ([`find`]), the workbench
//! ([`Workbench::set`]), the panel and completion (the TUI) and `set KEY` without a value (its
//! help) all read this table, so a new setting is one row.

mod rows;

pub use rows::{INTEGRATORS, SETTINGS};

use super::SessionError;
use super::units::{self, Kind};
use super::workbench::Workbench;

/// What a change of a setting makes stale (the stages it reruns, issue 17 item 4).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Recompute {
    /// Nothing: a view setting, or one read by a report only (motor drives, blend window).
    Nothing,
    /// Inverse dynamics over the same smoothed states: the model's masses, the contact,
    /// the quoted frames.
    Dynamics,
    /// Only the simulation (gains, integrator, step): inverse dynamics stays.
    Simulation,
    /// The smoothing and all that follows it.
    Smoothing,
    /// Everything from the take's file: axes, unit, the model's structure, the states.
    Take,
}

/// Where a setting sits in the parameter panel.
#[derive(Debug, Clone, Copy)]
pub struct PanelRow {
    /// Row in a human take's panel, in a robot's.
    pub human: Option<u8>,
    pub robot: Option<u8>,
    /// What the `<…>` of a pattern key stands for in the panel.
    pub subject: Subject,
    /// The unit after the value (` kg`).
    pub unit: &'static str,
    /// The value shown, for the key's subject (a joint, a coordinate, or "").
    pub show: fn(&Workbench, &str) -> Option<String>,
    /// The value one step up (`dir` 1) or down (-1) from `value`; `None`: no step.
    pub step: fn(&Workbench, &str, f64) -> Option<String>,
}

/// What a pattern key's `<…>` is in the panel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Subject {
    /// A plain key.
    None,
    /// The joint under the joint tree's cursor (`link.<name>.mass`).
    Joint,
    /// The selected coordinate (`motor.<joint>.gear`).
    Selection,
}

/// One `set` key.
pub struct Setting {
    /// The key (`body.mass`), or a pattern with one `<…>` part for any joint
    /// (`kp.<joint>`, `link.<name>.mass`).
    pub name: &'static str,
    /// The value it takes, as help and errors write it (`KG`, `auto|on|off`).
    pub value: &'static str,
    /// What it sets.
    pub help: &'static str,
    /// The values completion offers after the key.
    pub values: &'static [&'static str],
    /// What a change recomputes.
    pub recompute: Recompute,
    /// Checks the value and applies it (nothing changes on an error).
    pub apply: fn(&mut Workbench, &Arg) -> Result<(), SessionError>,
    /// Its row in the parameter panel, if any.
    pub panel: Option<PanelRow>,
}

impl std::fmt::Debug for Setting {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Setting").field("name", &self.name).finish()
    }
}

impl Setting {
    /// The `<…>` part of `key` if `key` is this setting (`Some("")` for a plain key).
    pub fn subject_of<'k>(&self, key: &'k str) -> Option<&'k str> {
        match (self.name.find('<'), self.name.find('>')) {
            (Some(a), Some(b)) => {
                let (pre, post) = (&self.name[..a], &self.name[b + 1..]);
                let n = key.len().checked_sub(pre.len() + post.len())?;
                (n > 0 && key.starts_with(pre) && key.ends_with(post))
                    .then(|| &key[pre.len()..pre.len() + n])
            }
            _ => (key == self.name).then_some(""),
        }
    }
    /// The key for subject `s` (`link.<name>.mass` and `LeftLeg` → `link.LeftLeg.mass`).
    pub fn key_for(&self, s: &str) -> String {
        match (self.name.find('<'), self.name.find('>')) {
            (Some(a), Some(b)) => format!("{}{s}{}", &self.name[..a], &self.name[b + 1..]),
            _ => self.name.to_string(),
        }
    }
    /// `set NAME VALUE: help`, for `set NAME` without a value.
    pub fn usage(&self) -> String {
        format!("set {} {}: {}", self.name, self.value, self.help)
    }
}

/// The setting of `key` (plain keys before patterns) and its `<…>` part.
pub fn find(key: &str) -> Option<(&'static Setting, &str)> {
    let plain = SETTINGS.iter().find(|s| s.name == key);
    plain
        .map(|s| (s, ""))
        .or_else(|| SETTINGS.iter().find_map(|s| Some((s, s.subject_of(key)?))))
}

/// Every key name, patterns as written in the table, in table order.
pub fn names() -> impl Iterator<Item = &'static str> {
    SETTINGS.iter().map(|s| s.name)
}

/// The rows of the parameter panel of a human take (`robot` false) or of a robot, in order.
pub fn panel(robot: bool) -> Vec<&'static Setting> {
    let pos = |s: &Setting| s.panel.and_then(|p| if robot { p.robot } else { p.human });
    let mut rows: Vec<_> = SETTINGS.iter().filter(|s| pos(s).is_some()).collect();
    rows.sort_by_key(|s| pos(s));
    rows
}

/// A `set` command's key and value, with the readers of the value every row shares.
#[derive(Debug)]
pub struct Arg<'a> {
    pub key: &'a str,
    pub value: &'a str,
    /// The key's `<…>` part (`LeftLeg` of `kp.LeftLeg`), "" for a plain key.
    pub subject: &'a str,
}

fn err(message: impl Into<String>) -> SessionError {
    SessionError::Command(message.into())
}

impl Arg<'_> {
    /// An error about this setting: `set KEY: message`.
    pub fn error(&self, message: impl std::fmt::Display) -> SessionError {
        err(format!("set {}: {message}", self.key))
    }
    /// `auto` or `none`.
    pub fn auto(&self) -> bool {
        matches!(self.value, "auto" | "none")
    }
    /// A number of `kind` (a unit may be written: `80kg`, `5ms`, `175cm`), or a plain number
    /// for `kind` None (gains, drive ratios).
    pub fn read(&self, kind: Option<Kind>, what: &str) -> Result<f64, SessionError> {
        match kind {
            Some(k) => units::parse_si(self.value, k, what),
            None => units::parse_plain(self.value, what),
        }
        .map_err(|e| match e {
            units::UnitError::NotANumber { .. } => {
                self.error(format!("expected {what}, found '{}'", self.value))
            }
            e => self.error(e),
        })
    }
    /// A non-negative number.
    pub fn num(&self, kind: Option<Kind>, what: &str) -> Result<f64, SessionError> {
        match self.read(kind, what)? {
            x if x >= 0.0 => Ok(x),
            _ => Err(self.error(format!(
                "expected {what} (a non-negative number), found '{}'",
                self.value
            ))),
        }
    }
    /// A positive number.
    pub fn positive(&self, kind: Option<Kind>, what: &str) -> Result<f64, SessionError> {
        match self.read(kind, what)? {
            x if x > 0.0 => Ok(x),
            _ => Err(self.error(format!("expected {what}, found '{}'", self.value))),
        }
    }
    /// The value by the pipeline's own parser, so it means what the CLI's flag means.
    pub fn parsed<T: std::str::FromStr>(&self) -> Result<T, SessionError>
    where
        T::Err: std::fmt::Display,
    {
        self.value.parse::<T>().map_err(|e| self.error(e))
    }
    /// The value parsed, or `None` for `auto`/`none`.
    pub fn parsed_or_auto<T: std::str::FromStr>(&self) -> Result<Option<T>, SessionError>
    where
        T::Err: std::fmt::Display,
    {
        if self.auto() {
            Ok(None)
        } else {
            self.parsed().map(Some)
        }
    }
    /// The index of the value among `words` (`set KEY: expected a, b or c, found 'x'`).
    pub fn one_of(&self, words: &[&str]) -> Result<usize, SessionError> {
        words.iter().position(|w| *w == self.value).ok_or_else(|| {
            let list = match words {
                [a, b] => format!("{a} or {b}"),
                [init @ .., last] => format!("{} or {last}", init.join(", ")),
                [] => String::new(),
            };
            self.error(format!("expected {list}, found '{}'", self.value))
        })
    }
}

impl Workbench {
    /// `set KEY VALUE`: the row of `key` checks the value and applies it.
    pub fn set(&mut self, key: &str, value: &str) -> Result<(), SessionError> {
        let (row, subject) = find(key).ok_or_else(|| err(format!("unknown setting '{key}'")))?;
        (row.apply)(
            self,
            &Arg {
                key,
                value,
                subject,
            },
        )
    }
}
