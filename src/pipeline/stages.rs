//! The stages a take goes through on its way from a file to torques, as `articula id` runs
//! them, and `articula bench --stages`: the wall time of each.
//!
//! The stage functions (`load_take_marked`, `load_source_marked`, `job_torques_marked`) call
//! a `done(Stage)` callback at the end of each stage; the plain functions every command uses
//! pass one that does nothing, the bench one that reads the clock. So the bench times the very
//! code `articula id` runs, in the same order, not a copy of it; only writing the CSV is left
//! out (the total is file to torques).

use super::{Contact, ModelSource, StateColumns, TakeOptions};
use crate::error::Error;
use std::path::Path;
use std::time::Instant;

/// A stage of a take's way from the file to torques, in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    Parse,
    Model,
    Coordinates,
    Unwrap,
    Smooth,
    Derivatives,
    Job,
    Contact,
    InverseDynamics,
}

/// A stage's key (in `bench --stages --json`'s `stages_ms`) and what it does.
#[derive(Debug, Clone, Copy)]
pub struct StageInfo {
    pub stage: Stage,
    pub key: &'static str,
    pub what: &'static str,
}

/// Every stage, in the order a take goes through them.
pub const STAGES: &[StageInfo] = &[
    StageInfo {
        stage: Stage::Parse,
        key: "parse",
        what: "BVH text → joints and frames; a rest pose at frame 0 dropped",
    },
    StageInfo {
        stage: Stage::Model,
        key: "model",
        what: "axes, unit, human landmarks, masses, model; helper roots, welds, twists",
    },
    StageInfo {
        stage: Stage::Coordinates,
        key: "coordinates",
        what: "channels → q, column by column",
    },
    StageInfo {
        stage: Stage::Unwrap,
        key: "unwrap",
        what: "Euler triples made continuous, revolute turns unwrapped",
    },
    StageInfo {
        stage: Stage::Smooth,
        key: "smooth",
        what: "the low-pass on every coordinate (quaternions on the sphere); an euler joint's v \
               and a right after its own",
    },
    StageInfo {
        stage: Stage::Derivatives,
        key: "derivatives",
        what: "v and a of the other joints by second-order differences on the manifold; the q, \
               v, a rows",
    },
    StageInfo {
        stage: Stage::Job,
        key: "job",
        what: "the take's model copied into the job, its states shared",
    },
    StageInfo {
        stage: Stage::Contact,
        key: "contact",
        what: "contact choice, consistency figures and ground reactions (when on)",
    },
    StageInfo {
        stage: Stage::InverseDynamics,
        key: "inverse_dynamics",
        what: "RNEA at every frame (with the ground reactions when on)",
    },
];

/// How `bench --stages` runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StageSettings {
    /// Timed runs (at least 1), after one untimed warm-up run.
    pub repeat: usize,
    /// Cycle the take to this many minutes of frames first ([`cycle_take_text`]).
    pub minutes: Option<f64>,
}

/// `bench --stages`: per stage (in [`STAGES`] order) the minimum and median over the runs (ms).
#[derive(Debug, Clone, PartialEq)]
pub struct StageBench {
    pub take: String,
    /// How the take was cycled, if it was.
    pub cycled: Option<String>,
    pub frames: usize,
    pub nv: usize,
    pub threads: usize,
    pub contact: Contact,
    pub repeat: usize,
    pub min_ms: Vec<f64>,
    pub median_ms: Vec<f64>,
    /// File to torques: the sum of the stages, minimum and median over the runs.
    pub total_min_ms: f64,
    pub total_median_ms: f64,
}

/// Times every stage of `articula id` on the take at `path` with `opts`: its text is read
/// once (and cycled when asked), then each run parses it and goes on to the torques.
pub fn bench_stages(
    path: &Path,
    opts: &TakeOptions,
    settings: StageSettings,
) -> Result<StageBench, Error> {
    let raw = std::fs::read(path).map_err(|e| Error::Io {
        path: path.to_path_buf(),
        source: e,
    })?;
    let (text, cycled) = match settings.minutes {
        Some(m) => {
            let text = String::from_utf8_lossy(&raw);
            let (t, how) = cycle_take_text(&text, m, path)?;
            (t.into_bytes(), Some(how))
        }
        None => (raw, None),
    };
    let repeat = settings.repeat.max(1);
    let warm_up = run_once(path, &text, opts)?;
    let runs = (0..repeat)
        .map(|_| run_once(path, &text, opts))
        .collect::<Result<Vec<_>, _>>()?;
    let StageRun {
        frames,
        nv,
        contact,
        ..
    } = warm_up;
    let column = |s: usize| runs.iter().map(|r| r.ms[s]).collect::<Vec<f64>>();
    let totals: Vec<f64> = runs.iter().map(|r| r.ms.iter().sum()).collect();
    Ok(StageBench {
        take: path.display().to_string(),
        cycled,
        frames,
        nv,
        threads: crate::par::slots(),
        contact,
        repeat,
        min_ms: (0..STAGES.len()).map(|s| min(&column(s))).collect(),
        median_ms: (0..STAGES.len()).map(|s| median(&column(s))).collect(),
        total_min_ms: min(&totals),
        total_median_ms: median(&totals),
    })
}

/// One run of the stages: ms per stage (in [`STAGES`] order), and what the take was.
struct StageRun {
    ms: Vec<f64>,
    frames: usize,
    nv: usize,
    contact: Contact,
}

/// One run of `articula id`'s stages on `text`.
fn run_once(path: &Path, text: &[u8], opts: &TakeOptions) -> Result<StageRun, Error> {
    let mut ms = vec![f64::NAN; STAGES.len()];
    let mut last = Instant::now();
    let mut done = |stage: Stage| {
        let now = Instant::now();
        let s = STAGES
            .iter()
            .position(|i| i.stage == stage)
            .expect("every stage is in the table");
        ms[s] = now.duration_since(last).as_secs_f64() * 1e3;
        last = now;
    };
    // the same calls, in the same order, as `articula id` on a take without --grf
    let src = ModelSource::Take(path.to_path_buf());
    let mut job =
        super::load_source_marked(&src, None, opts, StateColumns::QVA, Some(text), &mut done)?;
    if let Some(t) = job.take.as_mut() {
        super::resolve_contact(t);
    }
    super::consistency::consistent_job(&mut job, false, true, None)?;
    let (tau, _) = super::job_torques_marked(&job, &mut done)?;
    std::hint::black_box(&tau);
    let contact = job
        .take
        .as_ref()
        .map_or(Contact::None, |t| t.options.contact);
    if let Some(s) = ms.iter().position(|x| x.is_nan()) {
        return Err(Error::Invalid(format!(
            "stage `{}` did not report its end",
            STAGES[s].key
        )));
    }
    Ok(StageRun {
        ms,
        frames: job.states.len(),
        nv: job.model.nv,
        contact,
    })
}

/// The smallest of `x` (ms; +∞ for none): the benches' min (`bench --stages`, `--edit`).
pub fn min(x: &[f64]) -> f64 {
    x.iter().copied().fold(f64::INFINITY, f64::min)
}

/// The median of `x` (the mean of the middle two for an even count; NaN for none): the
/// benches' median (`bench --stages`, `--edit`).
pub fn median(x: &[f64]) -> f64 {
    let mut x = x.to_vec();
    x.sort_by(f64::total_cmp);
    let n = x.len();
    if n == 0 {
        return f64::NAN;
    }
    if n % 2 == 1 {
        x[n / 2]
    } else {
        0.5 * (x[n / 2 - 1] + x[n / 2])
    }
}

/// A BVH text cycled to `minutes` of frames: the header as it is with `Frames:` changed, frame
/// 0 once, then frames 1…last played forward and backward in turn (so the motion stays
/// continuous: no jump back to the start) until the take lasts `minutes` at its frame time.
/// Frame lines are copied as they are. Returns the text and a sentence saying how.
pub fn cycle_take_text(text: &str, minutes: f64, path: &Path) -> Result<(String, String), Error> {
    let bad = |what: &str| Error::Invalid(format!("{}: {what}", path.display()));
    if !(minutes > 0.0 && minutes.is_finite()) {
        return Err(bad(&format!(
            "--minutes {minutes}: expected a positive number of minutes"
        )));
    }
    let lines: Vec<&str> = text.lines().collect();
    let find = |prefix: &str| {
        lines
            .iter()
            .position(|l| l.trim_start().to_ascii_lowercase().starts_with(prefix))
    };
    let frames_at = find("frames:").ok_or_else(|| bad("no `Frames:` line to cycle"))?;
    let time_at = find("frame time:").ok_or_else(|| bad("no `Frame Time:` line to cycle"))?;
    let frame_time: f64 = lines[time_at]
        .split_once(':')
        .and_then(|(_, t)| t.trim().parse().ok())
        .filter(|t: &f64| *t > 0.0 && t.is_finite())
        .ok_or_else(|| bad("the `Frame Time:` line holds no positive number"))?;
    let rows: Vec<&str> = lines[time_at + 1..]
        .iter()
        .copied()
        .filter(|l| !l.trim().is_empty())
        .collect();
    if rows.is_empty() {
        return Err(bad("no frames to cycle"));
    }
    let target = ((minutes * 60.0 / frame_time).round() as usize).max(1);
    let mut out = String::with_capacity(text.len() * (target / rows.len() + 2));
    for (i, l) in lines[..=time_at].iter().enumerate() {
        if i == frames_at {
            out.push_str(&format!("Frames: {target}"));
        } else {
            out.push_str(l);
        }
        out.push('\n');
    }
    // frame 0, then 1…m−1, m−2…1, 2…m−1, …
    let m = rows.len();
    let (mut k, mut step) = (0usize, 1isize);
    for _ in 0..target {
        out.push_str(rows[k]);
        out.push('\n');
        if m > 2 {
            if (step > 0 && k == m - 1) || (step < 0 && k == 1) {
                step = -step;
            }
            k = (k as isize + step) as usize;
        } else {
            k = (k + 1) % m;
        }
    }
    let how = format!(
        "cycled to {minutes} min: {target} frames at {frame_time} s, frame 0 once then frames \
         1…{} forward and backward in turn (the parse timed on the cycled text)",
        m - 1
    );
    Ok((out, how))
}

impl StageBench {
    /// The keys `frames`, `nv`, `threads`, `contact`, `repeat`, `take`, `cycled`, `stages_ms`
    /// (median per stage key), `stages_min_ms`, `total_ms` (median, file to torques),
    /// `total_min_ms`.
    pub fn json(&self) -> serde_json::Value {
        let by_key = |v: &[f64]| {
            STAGES
                .iter()
                .zip(v)
                .map(|(s, x)| (s.key.to_string(), serde_json::json!(x)))
                .collect::<serde_json::Map<_, _>>()
        };
        serde_json::json!({
            "take": self.take,
            "cycled": self.cycled,
            "frames": self.frames,
            "nv": self.nv,
            "threads": self.threads,
            "contact": self.contact.to_string(),
            "repeat": self.repeat,
            "stages_ms": by_key(&self.median_ms),
            "stages_min_ms": by_key(&self.min_ms),
            "total_ms": self.total_median_ms,
            "total_min_ms": self.total_min_ms,
        })
    }

    /// A table: stage, min and median (ms), what it does.
    pub fn text(&self) -> String {
        let mut s = format!(
            "{}{}\n{} frames, nv {}, {} thread{}, contact {}, {} timed run{} after one warm-up\n\n",
            self.take,
            self.cycled
                .as_ref()
                .map(|c| format!(" {c}"))
                .unwrap_or_default(),
            self.frames,
            self.nv,
            self.threads,
            if self.threads == 1 { "" } else { "s" },
            self.contact,
            self.repeat,
            if self.repeat == 1 { "" } else { "s" },
        );
        s.push_str(&format!(
            "{:<18} {:>9} {:>9}  what\n",
            "stage", "min ms", "median ms"
        ));
        for ((info, lo), med) in STAGES.iter().zip(&self.min_ms).zip(&self.median_ms) {
            s.push_str(&format!(
                "{:<18} {lo:>9.2} {med:>9.2}  {}\n",
                info.key, info.what
            ));
        }
        s.push_str(&format!(
            "{:<18} {:>9.2} {:>9.2}  file to torques\n",
            "total", self.total_min_ms, self.total_median_ms
        ));
        s
    }
}
