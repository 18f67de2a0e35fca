//! `articula bench TAKE --edit SETTING=V1,V2[,…]`: how long a workbench edit takes to show,
//! `set SETTING V` and then `run id`, timed as the terminal UI's status line times it
//! ("recomputed in N ms": from the command to its results), on a take loaded once into a
//! headless [`Workbench`] with the CLI's take options.
//!
//! One untimed `run id` first (the results an edit starts from), then `repeat` timed edits,
//! each setting the next value of the list in turn (so that every timed run is a real edit:
//! two neighbours in the cycle must differ). Before the first run, `--set KEY=VALUE` lines are
//! applied as they are (`consistent=off`, `edges=include`). Besides the times, the stages the
//! edits reran, per edit (`Workbench::stage_runs`): what an edit recomputes, counted.

use super::{Builtin, Command, Control, RunKind, Workbench};
use crate::error::Error;
use crate::pipeline::TakeOptions;
use crate::pipeline::stages::{STAGES, median, min};
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

/// What `bench --edit` times.
#[derive(Debug, Clone)]
pub struct EditSettings {
    /// The workbench setting edited (`body.mass`, `link.LeftLeg.mass`, `smooth`, …).
    pub setting: String,
    /// The values set in turn; two neighbours in the cycle differ.
    pub values: Vec<String>,
    /// Settings applied before the first run, as `set KEY VALUE`.
    pub before: Vec<(String, String)>,
    /// Timed edits (after one untimed run).
    pub repeat: usize,
}

impl EditSettings {
    /// `SETTING=V1,V2[,…]` and the `KEY=VALUE` lines of `--set`.
    pub fn parse(edit: &str, before: &[String], repeat: usize) -> Result<Self, Error> {
        let split = |s: &str, what: &str| -> Result<(String, String), Error> {
            s.split_once('=')
                .map(|(k, v)| (k.trim().to_string(), v.trim().to_string()))
                .filter(|(k, v)| !k.is_empty() && !v.is_empty())
                .ok_or_else(|| Error::Invalid(format!("{what} `{s}`: expected KEY=VALUE")))
        };
        let (setting, list) = split(edit, "--edit")?;
        let values: Vec<String> = list.split(',').map(|v| v.trim().to_string()).collect();
        let cycle_differs = values.len() >= 2
            && (0..values.len()).all(|i| values[i] != values[(i + 1) % values.len()]);
        if !cycle_differs {
            return Err(Error::Invalid(format!(
                "--edit {edit}: give two values or more, each different from the next (e.g. \
                 `{setting}=80,70`): setting the value a setting has is no edit"
            )));
        }
        if repeat == 0 {
            return Err(Error::Invalid("--repeat 0: time at least one edit".into()));
        }
        let before = before
            .iter()
            .map(|s| split(s, "--set"))
            .collect::<Result<_, _>>()?;
        Ok(Self {
            setting,
            values,
            before,
            repeat,
        })
    }
}

/// The times of the edits and what they reran.
#[derive(Debug, Clone)]
pub struct EditBench {
    pub take: String,
    pub frames: usize,
    pub nv: usize,
    pub threads: usize,
    /// The take's contact after `auto` is settled (`feet`, `none`).
    pub contact: String,
    pub settings: EditSettings,
    /// Milliseconds of each timed edit (`set` + `run id`), in order: as the terminal UI's
    /// worker does it, a preview first when the edit has one.
    pub ms: Vec<f64>,
    /// Milliseconds from each timed edit to its preview (`Job::preview`: after an edit of the
    /// masses alone, the last residual reduction at the new masses), the terminal UI's first
    /// redraw; empty when the edits have none.
    pub preview_ms: Vec<f64>,
    /// `(stage key, runs per edit)` for every stage that reran: what an edit recomputes.
    pub reran: Vec<(&'static str, f64)>,
}

fn command(wb: &mut Workbench, cmd: Command) -> Result<String, Error> {
    wb.apply(&cmd)
        .map(|o| o.message)
        .map_err(|e| Error::Invalid(e.to_string()))
}

fn set(wb: &mut Workbench, key: &str, value: &str) -> Result<String, Error> {
    command(
        wb,
        Command::Set {
            key: key.into(),
            value: value.into(),
        },
    )
}

/// Times `settings.repeat` edits of `settings.setting` on the take at `path`, loaded with
/// `opts` (the CLI's take flags).
pub fn bench_edit(
    path: &Path,
    opts: &TakeOptions,
    settings: &EditSettings,
) -> Result<EditBench, Error> {
    // the workbench reads relative to the take's folder: the take is its file name there
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut wb = Workbench::new(Arc::new(Builtin), dir, dir);
    wb.params.take = opts.clone();
    command(
        &mut wb,
        Command::Load {
            path: path.file_name().map_or(path.to_path_buf(), Into::into),
            name: None,
        },
    )?;
    for (k, v) in &settings.before {
        set(&mut wb, k, v)?;
    }
    command(&mut wb, Command::Run(RunKind::Id))?;
    let runs_before = wb.stage_runs;
    let (mut ms, mut preview_ms) = (vec![], vec![]);
    let since = |start: Instant| start.elapsed().as_secs_f64() * 1e3;
    for i in 0..settings.repeat {
        let value = &settings.values[i % settings.values.len()];
        let start = Instant::now();
        set(&mut wb, &settings.setting, value)?;
        // the terminal UI's worker: the recompute's preview, when it has one, then the results
        let job = wb
            .prepare(&Command::Run(RunKind::Id))
            .map_err(|e| Error::Invalid(e.to_string()))?;
        if let Some(job) = job
            && job.preview(&Control::default()).is_some()
        {
            preview_ms.push(since(start));
        }
        command(&mut wb, Command::Run(RunKind::Id))?;
        ms.push(since(start));
    }
    let reran = STAGES
        .iter()
        .map(|s| {
            let n = wb.stage_runs[s.stage as usize] - runs_before[s.stage as usize];
            (s.key, n as f64 / settings.repeat as f64)
        })
        .filter(|(_, n)| *n > 0.0)
        .collect();
    let r = wb
        .fresh_results()
        .ok_or_else(|| Error::Invalid("bench --edit: `run id` left no results".into()))?;
    // the vertical forces of the feet are there when the ground reactions are
    let contact = if r.feet.names.is_empty() {
        "none"
    } else {
        "feet"
    };
    Ok(EditBench {
        take: path.display().to_string(),
        frames: r.time.len(),
        nv: r.model.nv,
        threads: crate::par::slots(),
        contact: contact.into(),
        settings: settings.clone(),
        ms,
        preview_ms,
        reran,
    })
}

impl EditBench {
    /// The fastest edit (ms).
    pub fn min_ms(&self) -> f64 {
        min(&self.ms)
    }

    /// The median edit (ms).
    pub fn median_ms(&self) -> f64 {
        median(&self.ms)
    }

    /// `--json`: `take`, `frames`, `nv`, `threads`, `contact`, `edit` (the setting), `values`,
    /// `before` (the `--set` lines), `repeat`, `edit_ms` (every timed edit), `median_ms`,
    /// `min_ms`, `preview_ms` (every timed edit's preview; empty without),
    /// `preview_median_ms` and `preview_min_ms` (null without), `reran` (stage key → runs per
    /// edit).
    pub fn json(&self) -> serde_json::Value {
        let before: serde_json::Map<String, serde_json::Value> = self
            .settings
            .before
            .iter()
            .map(|(k, v)| (k.clone(), v.clone().into()))
            .collect();
        let reran: serde_json::Map<String, serde_json::Value> = self
            .reran
            .iter()
            .map(|(k, n)| (k.to_string(), (*n).into()))
            .collect();
        serde_json::json!({
            "take": self.take,
            "frames": self.frames,
            "nv": self.nv,
            "threads": self.threads,
            "contact": self.contact,
            "edit": self.settings.setting,
            "values": self.settings.values,
            "before": before,
            "repeat": self.settings.repeat,
            "edit_ms": self.ms,
            "median_ms": self.median_ms(),
            "min_ms": self.min_ms(),
            "preview_ms": self.preview_ms,
            "preview_median_ms": (!self.preview_ms.is_empty()).then(|| median(&self.preview_ms)),
            "preview_min_ms": (!self.preview_ms.is_empty()).then(|| min(&self.preview_ms)),
            "reran": reran,
        })
    }

    /// For a user: the setting, the take, min and median, and what reran.
    pub fn text(&self) -> String {
        let before: Vec<String> = self
            .settings
            .before
            .iter()
            .map(|(k, v)| format!("{k} {v}"))
            .collect();
        let reran: Vec<String> = self
            .reran
            .iter()
            .map(|(k, n)| format!("{k} ×{n:.0}"))
            .collect();
        format!(
            "{}: {} frames, nv {}, {} thread{}, contact {}{}\n\
             `set {} {}` + `run id`, {} timed edits after one run: min {:.2} ms, median {:.2} ms\n\
             {}reran per edit: {}\n",
            self.take,
            self.frames,
            self.nv,
            self.threads,
            if self.threads == 1 { "" } else { "s" },
            self.contact,
            if before.is_empty() {
                String::new()
            } else {
                format!(", after `set {}`", before.join("`, `set "))
            },
            self.settings.setting,
            self.settings.values.join("|"),
            self.settings.repeat,
            self.min_ms(),
            self.median_ms(),
            if self.preview_ms.is_empty() {
                String::new()
            } else {
                format!(
                    "the preview drawn first (the last residual reduction at the new masses), \
                     {} of them: min {:.2} ms, median {:.2} ms\n",
                    self.preview_ms.len(),
                    min(&self.preview_ms),
                    median(&self.preview_ms)
                )
            },
            if reran.is_empty() {
                "nothing".into()
            } else {
                reran.join(", ")
            },
        )
    }
}
