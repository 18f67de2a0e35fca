//! The workbench state and the one function that changes it, [`Workbench::apply`].

mod expect;
mod job;
mod prepare;
mod series;

use job::Output;
pub use job::{Job, JobResult};
use series::{
    anatomical_axis, channel_by_range, is_csv, joint_of, joint_of_name, joint_of_selection,
};
pub use series::{
    angle_series, best_coordinate, coords_of_joint, is_anatomical, mirror_coord, mirror_names,
    results_csv, selection_svg, statistic, torque_series,
};

use super::SessionError;
use super::command::{Command, Expectation, Quantity, RunKind, TakeRef};
use super::engine::{Analysis, Builtin, Control, Engine, Params, Take, TakeData};
use super::units::{Bare, Measure};
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
}

impl Overlay {
    /// Every overlay, in the order of [`WORDS`](Self::WORDS).
    pub const ALL: &[Overlay] = &[Overlay::Mirror, Overlay::None];
    /// The words of `set overlay`.
    pub const WORDS: &[&str] = &["mirror", "none"];
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

/// The selection once results `r` are stored: `sel` if `r` has that coordinate; otherwise the
/// coordinate with the largest range of motion of the old selection's joint, or the first
/// rotation.
fn selection_for(r: &Analysis, sel: Option<&str>) -> Option<String> {
    if let Some(s) = sel
        && (r.model.v_index(s).is_some() || is_anatomical(r, s))
    {
        return Some(s.to_string());
    }
    // a human take: its left knee's flexion, as a gait lab shows it first
    if sel.is_none()
        && let Some(c) = anatomical_axis(r, "knee_l")
    {
        return Some(c);
    }
    let joint = sel.and_then(|s| joint_of_name(&r.model, s));
    joint.and_then(|j| best_coordinate(r, &j)).or_else(|| {
        (0..r.model.nv)
            .find(|&k| r.model.is_angular(k))
            .map(|k| r.model.v_names[k].clone())
    })
}

/// The selection when `take` becomes active: `sel` if the take has it (a robot's coordinate,
/// or a coordinate of one of a BVH take's joints: `<joint>.<channel>`, `<joint>:<comp>`);
/// otherwise a robot's first rotation, or none for a take (its results choose).
fn selection_on_load(take: &Take, sel: Option<&str>) -> Option<String> {
    match &take.data {
        TakeData::Robot(r) => sel
            .filter(|s| r.model.v_index(s).is_some())
            .map(str::to_string)
            .or_else(|| {
                (0..r.model.nv)
                    .find(|&k| r.model.is_angular(k))
                    .map(|k| r.model.v_names[k].clone())
            }),
        TakeData::Bvh(b) => sel.filter(|s| names_a_joint(b, s)).map(str::to_string),
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
    /// Simulation results of the active take.
    pub sim: Option<(Arc<Analysis>, Params)>,
    /// Every message so far, oldest first.
    pub messages: Vec<String>,
    /// The motor catalogue `report motor` chooses from (`set motor.catalogue`; the bundled
    /// `data/motor_classes.toml` by default).
    pub motor_classes: Vec<motor::MotorClass>,
    /// What the curves draw beside the selection's (`set overlay`).
    pub overlay: Overlay,
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
            sim: None,
            messages: vec![],
            motor_classes: motor::default_catalogue().unwrap_or_default(),
            overlay: Overlay::None,
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
            .filter(|(_, p)| p.same_results(&self.params))
            .map(|(r, _)| r)
    }

    /// The latest results, even if parameters changed since (for drawing while recomputing).
    pub fn latest_results(&self) -> Option<&Arc<Analysis>> {
        self.results.as_ref().map(|(r, _)| r)
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
        self.selection = selection_for(&r, self.selection.as_deref());
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
            self.sim = None;
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
        self.sim = None;
    }

    /// The coordinates of a joint (a BVH joint, or a robot joint) in the latest results.
    /// The anatomical axes of the joint of `sel` when `sel` is one (`knee_l:flexion` →
    /// `knee_l:flexion`, `knee_l:adduction`, `knee_l:rotation`), for ←/→ in the TUI.
    pub fn anatomical_axes(&self, sel: &str) -> Option<Vec<String>> {
        let r = self.latest_results()?;
        if !is_anatomical(r, sel) {
            return None;
        }
        let joint = sel.split(':').next()?;
        Some(
            ["flexion", "adduction", "rotation"]
                .iter()
                .map(|a| format!("{joint}:{a}"))
                .filter(|c| is_anatomical(r, c))
                .collect(),
        )
    }

    /// The joint of the selection, as the joint tree names it: the BVH joint at an
    /// anatomical joint's centre (`knee_l:flexion` → `LeftLeg`), the joint of a coordinate
    /// (`LeftLeg.Xrotation`, `LeftLeg:wx`, a robot's `j2`).
    pub fn selected_joint(&self) -> Option<String> {
        let sel = self.selection.as_deref()?;
        if let Some(r) = self.latest_results()
            && is_anatomical(r, sel)
        {
            return joint_of_selection(r, sel);
        }
        let r = self.latest_results();
        r.and_then(|r| joint_of_name(&r.model, sel)).or_else(|| {
            // before results: the name up to the coordinate's separator
            let tree = self.take()?.joint_tree();
            tree.into_iter()
                .map(|(n, _)| n)
                .filter(|n| {
                    sel == n
                        || sel
                            .strip_prefix(n.as_str())
                            .is_some_and(|r| r.starts_with(['.', ':']))
                })
                .max_by_key(|n| n.len())
        })
    }

    pub fn joint_coords(&self, joint: &str) -> Vec<String> {
        match self.latest_results() {
            Some(r) => coords_of_joint(&r.model, joint),
            None => vec![],
        }
    }

    /// True when the latest results were computed for the model the current parameters
    /// build (same joint model, locks, subtree and joint translations): their coordinates are
    /// those of the next results.
    fn results_model_current(&self) -> bool {
        self.results.as_ref().is_some_and(|(_, p)| {
            let (a, b) = (&p.take, &self.params.take);
            a.joints == b.joints
                && a.lock == b.lock
                && a.subtree == b.subtree
                && a.joint_translations == b.joint_translations
        })
    }

    /// A coordinate name from a coordinate or a joint name. A joint gives its coordinate with
    /// the largest range of motion over the take (the knee's and elbow's flexion axis):
    /// from the latest results, or before any result from the BVH rotation channels (the
    /// channel's axis names the ball model's rotation-vector component, `J:wx` for
    /// `Xrotation`).
    fn resolve_coord(&self, name: &str) -> Result<String, SessionError> {
        let take = self
            .take()
            .ok_or_else(|| err("no take loaded (load PATH first)"))?;
        // results of another model (computed before `set joints`, `lock`, `subtree`, …) name
        // coordinates the next results will not have: then choose from the take's channels
        let current = self
            .latest_results()
            .filter(|_| self.results_model_current());
        if let Some(r) = current
            && r.model.v_index(name).is_some()
        {
            return Ok(name.to_string());
        }
        if let Some(c) = self.latest_results().and_then(|r| anatomical_axis(r, name)) {
            return Ok(c);
        }
        if let Some(rb) = take.robot() {
            // a robot joint is its coordinate (or the first of a multi-DoF joint)
            return coords_of_joint(&rb.model, name)
                .into_iter()
                .next()
                .ok_or_else(|| {
                    err(format!(
                        "no joint called '{name}' in {} (it has {})",
                        take.name,
                        rb.model.v_names.join(", ")
                    ))
                });
        }
        let bvh = take.bvh().ok_or_else(|| err("no take loaded"))?;
        let Some(r) = current else {
            return channel_by_range(bvh, name, self.params.take.joints);
        };
        if let Some(c) = best_coordinate(r, name) {
            return Ok(c);
        }
        // a BVH name the model does not have (locked, or the results are of another model)
        let c = channel_by_range(bvh, name, self.params.take.joints)?;
        match r.model.v_index(&c) {
            Some(_) => Ok(c),
            None if self.fresh_results().is_some() => Err(err(format!(
                "{name} has no coordinate in the model (locked or outside the subtree?)"
            ))),
            None => Ok(c),
        }
    }
}
