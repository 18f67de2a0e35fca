//! The workbench state and the one function that changes it, [`Workbench::apply`].

mod expect;
mod job;
mod prepare;
mod select;
mod series;

use select::{selection_for, selection_on_load};

use job::Output;
pub use job::{Job, JobResult};
use series::{
    anatomical_axis, channel_by_range, image_format, is_csv, joint_of, joint_of_name,
    joint_of_selection,
};
pub use series::{
    angle_series, best_coordinate, coords_of_joint, is_anatomical, mirror_coord, mirror_names,
    reference_series, results_csv, selection_chart, selection_svg, simulated_coord, statistic,
    torque_series,
};

use super::SessionError;
use super::command::{Command, Expectation, Quantity, RunKind, TakeRef};
use super::engine::{Analysis, Builtin, Control, Engine, Params, STAGE_COUNT, Take, TakeData};
use super::units::{self, Bare, Measure};
use crate::model::{JointKind, Model};
use crate::report::motor;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// What the curves pane draws beside the selected coordinate's curves (`set overlay`; a view
/// setting, results do not depend on it).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Overlay {
    /// Nothing.
    #[default]
    None,
    /// The selected coordinate's mirror (`knee_r:flexion` beside `knee_l:flexion`,
    /// `RightLeg.Xrotation` beside `LeftLeg.Xrotation`).
    Mirror,
    /// The moment against the angle (the joint's work loop) under the angle.
    Angle,
    /// Both feet's vertical ground forces under the torque (with ground contact).
    Feet,
    /// The torques of the last `compare weights`, one curve per body mass.
    Weights,
    /// The last `run sim`: the simulated angle with the reference, and the tracking error.
    Sim,
}

impl Overlay {
    /// Every overlay, in the order of [`WORDS`](Self::WORDS).
    pub const ALL: &[Overlay] = &[
        Overlay::Mirror,
        Overlay::Angle,
        Overlay::Feet,
        Overlay::Weights,
        Overlay::Sim,
        Overlay::None,
    ];
    /// The words of `set overlay`.
    pub const WORDS: &[&str] = &["mirror", "angle", "feet", "weights", "sim", "none"];
}

/// The torques of the last `compare weights`, for the curves (`set overlay weights`).
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// The coordinate compared.
    pub coord: String,
    /// The torque's kind (a torque, or a prismatic joint's force).
    pub kind: units::Kind,
    /// Each body mass (kg) and the coordinate's torque per frame (SI).
    pub runs: Vec<(f64, Vec<f64>)>,
}

/// What applying a command did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Outcome {
    /// A one-line message for the status line (also kept in `Workbench::messages`).
    pub message: String,
    /// Files written.
    pub written: Vec<PathBuf>,
    /// The command asks the front end to quit.
    pub quit: bool,
    /// What a passed `expect` found, in the unit it shows it in (`deg`, `N·m`, `kg`; empty for
    /// a count); `None` for any other command.
    pub value: Option<(f64, &'static str)>,
}

/// The sidecar `NAME.csv.json` of a table the session wrote in the column scheme (its units
/// from `model`'s coordinates; docs/formats.md).
fn table_sidecar(
    out: &Path,
    command: &'static str,
    model: Option<&crate::model::Model>,
) -> Result<(), SessionError> {
    let p = crate::pipeline::summary::Provenance {
        command,
        arguments: &[],
        take: None,
        model,
        notes: &[],
        known_units: &[],
        consistency: None,
    };
    crate::pipeline::summary::write_sidecar(out, &p)?;
    Ok(())
}

/// The message of a `load`.
fn loaded_message(take: &Take) -> String {
    match &take.data {
        TakeData::Bvh(b) => {
            let mut m = format!(
                "loaded {} ({} joints, {} frames at {:.0} fps)",
                take.name,
                b.joints.len(),
                b.frames,
                1.0 / b.frame_time
            );
            // what the loader assumed (a scale, a smoothing, a dropped frame): the first,
            // and how many more
            if !take.notes.is_empty() {
                m.push_str("; ");
                m.push_str(&super::engine::summarize_notes(&take.notes));
            }
            m
        }
        TakeData::Robot(r) => format!(
            "loaded {} ({}: {} joints, nv {}, {:.2} kg); give it a motion: load \
             STATES.csv or trajectory POSE POSE … over T",
            take.name,
            r.kind,
            take.joint_tree().len(),
            r.model.nv,
            r.model.total_mass()
        ),
    }
}

/// True when `name` is a joint of the take or one of its coordinates (`<joint>.<channel>`,
/// `<joint>:<comp>`), before any model of it is built.
pub(crate) fn names_a_joint(b: &crate::io::bvh::Bvh, name: &str) -> bool {
    let joint = |n: &str| b.joints.iter().any(|j| j.name == n);
    joint(name)
        || [name.rsplit_once('.'), name.rsplit_once(':')]
            .into_iter()
            .flatten()
            .any(|(j, _)| joint(j))
}

/// Where an input path is read: relative paths under `in_dir` (`demo:` takes as they are).
fn resolve_in(in_dir: &Path, p: &Path) -> PathBuf {
    if p.is_absolute() || p.to_string_lossy().starts_with("demo:") {
        p.to_path_buf()
    } else {
        in_dir.join(p)
    }
}

/// True for an `expect` that reads inverse-dynamics results.
fn needs_results(e: &Expectation) -> bool {
    matches!(
        e,
        Expectation::Nv(_)
            | Expectation::Nq(_)
            | Expectation::Mass { .. }
            | Expectation::Stat { .. }
    )
}

/// The whole state of a study: takes, parameters, selection, current frame, results and
/// messages. Changed only by [`apply`](Self::apply) (and [`finish`](Self::finish), the second
/// half of a `run` that went to another thread).
pub struct Workbench {
    engine: Arc<dyn Engine>,
    /// Base folder of relative output paths.
    out_dir: PathBuf,
    /// Base folder of relative input paths.
    in_dir: PathBuf,
    /// Loaded takes, in load order.
    pub takes: Vec<Take>,
    /// Index of the active take in `takes`.
    pub active: Option<usize>,
    pub params: Params,
    /// The selected coordinate (`<joint>.<channel>`).
    pub selection: Option<String>,
    /// Current frame (0-based).
    pub frame: usize,
    pub playing: bool,
    /// Inverse-dynamics results of the active take, and the parameters they were computed
    /// with.
    pub results: Option<(Arc<Analysis>, Params)>,
    /// A preview of the inverse-dynamics results a recompute is computing (`Job::preview`:
    /// after an edit of the masses alone, the last residual reduction evaluated on the new
    /// masses), drawn until the results proper arrive; never fresh, never exported.
    pub preview: Option<Arc<Analysis>>,
    /// Simulation results of the active take.
    pub sim: Option<(Arc<Analysis>, Params)>,
    /// Every message so far, oldest first.
    pub messages: Vec<String>,
    /// The motor catalogue `report motor` chooses from (`set motor.catalogue`; the bundled
    /// `data/motor_classes.toml` by default).
    pub motor_classes: Vec<motor::MotorClass>,
    /// What the curves draw beside the selection's (`set overlay`).
    pub overlay: Overlay,
    /// The last `compare weights` of the active take.
    pub comparison: Option<Comparison>,
    /// How many times each pipeline stage ran in this workbench's jobs (`Stage as usize`):
    /// what an edit recomputed, counted (issue 17 item 4).
    pub stage_runs: [u64; STAGE_COUNT],
}

impl std::fmt::Debug for Workbench {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Workbench")
            .field("takes", &self.takes.len())
            .field("active", &self.active)
            .field("selection", &self.selection)
            .field("frame", &self.frame)
            .finish()
    }
}

impl Default for Workbench {
    fn default() -> Self {
        Self::new(Arc::new(Builtin), ".", ".")
    }
}

fn err(message: impl Into<String>) -> SessionError {
    SessionError::Command(message.into())
}

impl Workbench {
    /// An empty workbench over `engine`; relative input paths are read from `in_dir`, relative
    /// output paths written under `out_dir`.
    pub fn new(
        engine: Arc<dyn Engine>,
        in_dir: impl Into<PathBuf>,
        out_dir: impl Into<PathBuf>,
    ) -> Self {
        Self {
            engine,
            out_dir: out_dir.into(),
            in_dir: in_dir.into(),
            takes: vec![],
            active: None,
            params: Params::default(),
            selection: None,
            frame: 0,
            playing: false,
            results: None,
            preview: None,
            sim: None,
            messages: vec![],
            motor_classes: motor::default_catalogue().unwrap_or_default(),
            overlay: Overlay::None,
            comparison: None,
            stage_runs: [0; STAGE_COUNT],
        }
    }

    /// The active take.
    pub fn take(&self) -> Option<&Take> {
        self.active.map(|i| &self.takes[i])
    }

    /// Number of frames of the active take (0 without one).
    pub fn frames(&self) -> usize {
        self.take().map_or(0, Take::frames)
    }

    /// The current results if they match the current parameters.
    pub fn fresh_results(&self) -> Option<&Arc<Analysis>> {
        self.results
            .as_ref()
            .filter(|(_, p)| p.same_inverse_dynamics(&self.params))
            .map(|(r, _)| r)
    }

    /// How many times pipeline stage `s` ran in this workbench's jobs.
    pub fn stage_runs(&self, s: crate::pipeline::stages::Stage) -> u64 {
        self.stage_runs[s as usize]
    }

    /// The latest results, even if parameters changed since (for drawing while recomputing):
    /// the preview of a recompute when there is one ([`show_preview`](Self::show_preview)).
    pub fn latest_results(&self) -> Option<&Arc<Analysis>> {
        self.preview
            .as_ref()
            .or(self.results.as_ref().map(|(r, _)| r))
    }

    /// Shows `done`, a recompute's preview ([`Job::preview`](job::Job::preview)), until its
    /// results proper are stored (or the take changes, or the recompute is cancelled). A
    /// preview of another take than the active one is dropped.
    pub fn show_preview(&mut self, done: JobResult) {
        if let Ok(Output::Run(RunKind::Id, r)) = done.output
            && done.take.is_some()
            && done.take.as_deref() == self.take().map(|t| t.name.as_str())
        {
            self.preview = Some(r);
        }
    }

    /// The model a per-joint setting is checked against: the active robot's, or that of the
    /// latest results of a take (none before a take's first results).
    pub(crate) fn model_to_check(&self) -> Option<Arc<Model>> {
        match self.take().and_then(|t| t.robot()) {
            Some(rb) => Some(rb.model.clone()),
            None => self.latest_results().map(|r| r.model.clone()),
        }
    }

    /// The last message.
    pub fn last_message(&self) -> &str {
        self.messages.last().map_or("", String::as_str)
    }

    /// Where an output path goes: relative paths under the output folder.
    pub fn out_path(&self, p: &Path) -> PathBuf {
        if p.is_absolute() {
            p.to_path_buf()
        } else {
            self.out_dir.join(p)
        }
    }

    /// Where an input path is read: relative paths under the input folder.
    pub fn in_path(&self, p: &Path) -> PathBuf {
        resolve_in(&self.in_dir, p)
    }

    /// Stores what a [`Job`] computed and says so. A failed or cancelled job changes nothing
    /// and returns its error. Results for another take than the active one are dropped.
    pub fn finish(&mut self, done: JobResult) -> Result<Outcome, SessionError> {
        for (n, k) in self.stage_runs.iter_mut().zip(done.stage_runs) {
            *n += u64::from(k);
        }
        let output = done.output?;
        // results computed on the way are kept as those of `run id`
        let stored = match done.analysis {
            Some(r) => self.store(RunKind::Id, done.take.as_deref(), done.params.clone(), r),
            None => true,
        };
        match output {
            Output::Run(kind, r) => {
                self.store(kind, done.take.as_deref(), done.params, r);
                Ok(Outcome {
                    message: self.last_message().to_string(),
                    ..Outcome::default()
                })
            }
            Output::Take {
                take,
                blended,
                message,
            } => {
                let i = match self.takes.iter().position(|t| t.name == take.name) {
                    Some(i) => {
                        self.takes[i] = *take;
                        i
                    }
                    None => {
                        self.takes.push(*take);
                        self.takes.len() - 1
                    }
                };
                self.active = Some(i);
                self.results = None;
                self.preview = None;
                self.comparison = None;
                self.selection = selection_on_load(&self.takes[i], self.selection.as_deref());
                if blended {
                    self.frame = self.frame.min(self.frames().saturating_sub(1));
                } else {
                    self.frame = 0;
                    self.sim = None;
                }
                Ok(self.say(message))
            }
            Output::Motion {
                index,
                take,
                states,
                source,
                message,
            } => {
                if self.takes.get(index).map(|t| t.name.as_str()) != Some(take.as_str()) {
                    return Ok(self.say(format!("dropped the motion of {take}")));
                }
                self.set_motion(index, states, source);
                Ok(self.say(message))
            }
            Output::Scene {
                options,
                gains,
                takes,
                message,
            } => {
                self.params.take = *options;
                if let Some((kp, kv)) = gains {
                    self.params.kp = kp;
                    self.params.kv = kv;
                }
                let first = self.takes.len();
                for take in takes {
                    let message = loaded_message(&take);
                    self.finish(JobResult {
                        label: String::new(),
                        take: None,
                        params: self.params.clone(),
                        analysis: None,
                        stage_runs: [0; STAGE_COUNT],
                        output: Ok(Output::Take {
                            take: Box::new(take),
                            blended: false,
                            message,
                        }),
                    })?;
                }
                if first < self.takes.len() {
                    self.active = Some(first);
                }
                Ok(self.say(message))
            }
            Output::Compared {
                comparison,
                path,
                message,
            } => {
                if done.take.is_some() && self.take().map(|t| &t.name) == done.take.as_ref() {
                    self.comparison = Some(comparison);
                }
                let mut o = self.say(message);
                o.written.push(path);
                Ok(o)
            }
            Output::Wrote { path, message } => {
                let mut o = self.say(message);
                o.written.push(path);
                Ok(o)
            }
            Output::Then(cmd) => {
                if !stored || self.fresh_results().is_none() {
                    return Err(err(
                        "the take or its parameters changed while computing; try again",
                    ));
                }
                self.apply(&cmd)
            }
        }
    }

    /// Keeps results `r` of `kind` computed for take `take` under `params` (with a message),
    /// and makes the selection a coordinate of their model. False when `take` is no longer
    /// the active take (the results are dropped).
    fn store(
        &mut self,
        kind: RunKind,
        take: Option<&str>,
        params: Params,
        r: Arc<Analysis>,
    ) -> bool {
        self.preview = None;
        if take.is_none() || self.take().map(|t| t.name.as_str()) != take {
            self.say(format!("dropped results for {}", take.unwrap_or("no take")));
            return false;
        }
        let mut msg = format!(
            "{}: {} frames, nv {}, {:.1} kg",
            match kind {
                RunKind::Id => "inverse dynamics",
                RunKind::Sim => "simulation",
            },
            r.time.len(),
            r.model.nv,
            r.model.total_mass()
        );
        // a long note after a short first line (the status line shows the first line,
        // the TUI's help all of it)
        if !r.brief.is_empty() {
            msg = format!("{msg}; {}\n{}", r.brief, r.note);
        } else if !r.note.is_empty() {
            msg = format!("{msg}, {}", r.note);
        }
        // a simulation has no anatomical axes: the selection stays one of the results'
        let basis = match (kind, self.latest_results()) {
            (RunKind::Sim, Some(id)) => id.clone(),
            _ => r.clone(),
        };
        self.selection = selection_for(&basis, self.selection.as_deref());
        match kind {
            RunKind::Id => self.results = Some((r, params)),
            RunKind::Sim => self.sim = Some((r, params)),
        }
        self.say(msg);
        true
    }

    fn say(&mut self, message: String) -> Outcome {
        self.messages.push(message.clone());
        Outcome {
            message,
            ..Outcome::default()
        }
    }

    /// Runs inverse dynamics now if a take is loaded and its results are missing or stale (what
    /// a front end does before showing the screen of a replay).
    pub fn refresh(&mut self) -> Result<(), SessionError> {
        if self.take().is_some() && self.fresh_results().is_none() {
            self.ensure_results()?;
        }
        Ok(())
    }

    /// Runs inverse dynamics now unless fresh results exist.
    fn ensure_results(&mut self) -> Result<Arc<Analysis>, SessionError> {
        if let Some(r) = self.fresh_results() {
            return Ok(r.clone());
        }
        self.apply(&Command::Run(RunKind::Id))?;
        self.fresh_results()
            .cloned()
            .ok_or_else(|| err("inverse dynamics produced no results"))
    }

    /// Applies one command. `screen` and `key` belong to a front end (see
    /// [`Frontend`](super::Frontend)) and are refused here.
    pub fn apply(&mut self, cmd: &Command) -> Result<Outcome, SessionError> {
        match cmd {
            Command::Set { key, value } => {
                self.set(key, value)?;
                Ok(self.say(format!("{key} = {value}")))
            }
            Command::Take(which) => self.switch_take(which),
            Command::Select(name) => {
                let coord = self.resolve_coord(name)?;
                self.selection = Some(coord.clone());
                Ok(self.say(format!("selected {coord}")))
            }
            Command::Frame(n) => {
                let frames = self.frames();
                if frames == 0 {
                    return Err(err("no take loaded (load PATH first)"));
                }
                if *n >= frames {
                    return Err(err(format!(
                        "frame {n}: the take has frames 0‥{}",
                        frames - 1
                    )));
                }
                self.frame = *n;
                Ok(Outcome::default())
            }
            Command::Play => {
                self.playing = true;
                Ok(Outcome::default())
            }
            Command::Pause => {
                self.playing = false;
                Ok(Outcome::default())
            }
            Command::Expect(e) => match self.prepare(cmd)? {
                Some(job) => self.finish(job.run(&Control::default())),
                None => self.expect(e),
            },
            Command::Screen { .. } | Command::Key(_) => {
                Err(err("screen and key need a front end (the TUI)"))
            }
            Command::Quit => Ok(Outcome {
                quit: true,
                ..Outcome::default()
            }),
            // the long commands: the job a front end may run on another thread, run here
            _ => {
                let job = self.prepare(cmd)?.ok_or_else(|| err("nothing to run"))?;
                self.finish(job.run(&Control::default()))
            }
        }
    }

    /// `take`: makes another loaded take active, from its first frame. The results were the
    /// old take's (they go); the selection stays when the take has it.
    fn switch_take(&mut self, which: &TakeRef) -> Result<Outcome, SessionError> {
        let n = self.takes.len();
        if n == 0 {
            return Err(err("no take loaded (load PATH first)"));
        }
        let cur = self.active.unwrap_or(0);
        let i = match which {
            TakeRef::Next => (cur + 1) % n,
            TakeRef::Prev => (cur + n - 1) % n,
            TakeRef::Index(k) if *k <= n => k - 1,
            TakeRef::Index(k) => {
                return Err(err(format!("take {k}: {n} take(s) are loaded")));
            }
            TakeRef::Name(name) => {
                self.takes
                    .iter()
                    .position(|t| t.name == *name)
                    .ok_or_else(|| {
                        err(format!(
                            "no take called '{name}' (loaded: {})",
                            self.take_names().join(", ")
                        ))
                    })?
            }
        };
        if self.active != Some(i) {
            self.active = Some(i);
            self.results = None;
            self.preview = None;
            self.sim = None;
            self.comparison = None;
            self.frame = 0;
            self.selection = selection_on_load(&self.takes[i], self.selection.as_deref());
        }
        let t = &self.takes[i];
        Ok(self.say(format!(
            "take {}/{n}: {} ({} frames)",
            i + 1,
            t.name,
            t.frames()
        )))
    }

    /// A name for the take of `file` when another file already gave its name (`a/walk.bvh`
    /// and `b/walk.bvh` are `walk` and `walk-2`); `None` to keep the file's (a new name, or
    /// the same file loaded again, which replaces its take).
    fn second_name(&self, file: &Path) -> Option<String> {
        let source = file.to_string_lossy();
        let stem = file.file_stem()?.to_string_lossy().replace("demo:", "");
        let taken = |n: &str| self.takes.iter().find(|t| t.name == n);
        match taken(&stem) {
            Some(t) if t.source != source => {}
            _ => return None,
        }
        (2..)
            .map(|k| format!("{stem}-{k}"))
            .find(|n| taken(n).is_none_or(|t| t.source == source))
    }

    /// The names of the loaded takes, in load order.
    pub fn take_names(&self) -> Vec<String> {
        self.takes.iter().map(|t| t.name.clone()).collect()
    }

    /// Checks a `trajectory` for the active take: a robot of revolute and prismatic joints,
    /// poses of one value per coordinate, each an angle on a revolute coordinate and a length
    /// on a prismatic one (bare: rad or m). Its index in `takes` and the poses in SI.
    fn check_trajectory(
        &self,
        poses: &[Vec<Measure>],
    ) -> Result<(usize, Vec<Vec<f64>>), SessionError> {
        let (i, model) = self.active_robot("trajectory")?;
        let simple = (1..model.nbodies()).all(|b| {
            matches!(
                model.joints[b],
                JointKind::Revolute { .. } | JointKind::Prismatic { .. } | JointKind::Fixed
            )
        });
        if !simple {
            return Err(err(format!(
                "trajectory: {} has ball or free joints; give its motion as a states CSV",
                model.name
            )));
        }
        if let Some(p) = poses.iter().find(|p| p.len() != model.nq) {
            return Err(err(format!(
                "trajectory: a pose of {} values for {} coordinates ({})",
                p.len(),
                model.nq,
                model.q_names.join(", ")
            )));
        }
        // revolute and prismatic joints only: q and v coordinates coincide
        let si = poses
            .iter()
            .map(|p| {
                p.iter()
                    .enumerate()
                    .map(|(k, m)| {
                        let angular = model.is_angular(k);
                        let kind = Quantity::Angle.kind(angular);
                        let joint = if angular { "revolute" } else { "prismatic" };
                        let what = format!("{} (a {joint} coordinate)", model.v_names[k]);
                        m.to_si(&m.written(), kind, Bare::Si, &what)
                            .map_err(|e| err(format!("trajectory: {e}")))
                    })
                    .collect::<Result<Vec<f64>, _>>()
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok((i, si))
    }

    /// The active take if it is a robot: its index and model.
    fn active_robot(&self, what: &str) -> Result<(usize, Arc<Model>), SessionError> {
        let i = self
            .active
            .ok_or_else(|| err(format!("{what}: load a DH table or URDF first")))?;
        match &self.takes[i].data {
            TakeData::Robot(r) => Ok((i, r.model.clone())),
            TakeData::Bvh(_) => Err(err(format!(
                "{what}: {} is a BVH take; a motion is given to a robot (load a DH table or \
                 URDF first)",
                self.takes[i].name
            ))),
        }
    }

    fn set_motion(&mut self, i: usize, states: crate::pipeline::States, source: String) {
        if let TakeData::Robot(r) = &mut self.takes[i].data {
            r.motion = Some(Arc::new(states));
            r.motion_source = source;
        }
        self.frame = 0;
        self.results = None;
        self.preview = None;
        self.sim = None;
    }
}
