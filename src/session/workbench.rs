//! The workbench state and the one function that changes it, [`Workbench::apply`].

use super::SessionError;
use super::command::{Command, Expectation, ExportKind, Quantity, RunKind, Statistic};
use super::engine::{Analysis, Builtin, Control, Engine, Params, SmoothSpec, Take, TakeData};
use crate::model::{JointKind, Model};
use crate::pipeline::TakeOptions;
use crate::report::chart::{Panel, Series, stacked_svg};
use crate::report::knee::{self, MassRun};
use crate::report::motor::{self, JointMotion};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// What applying a command did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Outcome {
    /// A one-line message for the status line (also kept in `Workbench::messages`).
    pub message: String,
    /// Files written.
    pub written: Vec<PathBuf>,
    /// The command asks the front end to quit.
    pub quit: bool,
}

/// A computation prepared from the workbench, runnable on another thread
/// ([`Job::run`]); its [`JobResult`] goes back through [`Workbench::finish`].
#[derive(Clone)]
pub struct Job {
    pub kind: RunKind,
    engine: Arc<dyn Engine>,
    take: Take,
    params: Params,
}

impl std::fmt::Debug for Job {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Job")
            .field("kind", &self.kind)
            .field("take", &self.take.name)
            .finish()
    }
}

/// What a [`Job`] produced, with the parameters it ran under (so a stale result is known).
#[derive(Debug)]
pub struct JobResult {
    pub kind: RunKind,
    pub take: String,
    pub params: Params,
    pub result: Result<Analysis, crate::error::Error>,
}

impl Job {
    /// A short label for progress displays.
    pub fn label(&self) -> String {
        match self.kind {
            RunKind::Id => format!("inverse dynamics of {}", self.take.name),
            RunKind::Sim => format!("simulation of {}", self.take.name),
        }
    }
    /// Runs the computation (any thread).
    pub fn run(&self, ctl: &Control) -> JobResult {
        let result = match self.kind {
            RunKind::Id => self.engine.inverse_dynamics(&self.take, &self.params, ctl),
            RunKind::Sim => self.engine.simulate(&self.take, &self.params, ctl),
        };
        JobResult {
            kind: self.kind,
            take: self.take.name.clone(),
            params: self.params.clone(),
            result,
        }
    }
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

    fn in_path(&self, p: &Path) -> PathBuf {
        if p.is_absolute() || p.to_string_lossy().starts_with("demo:") {
            p.to_path_buf()
        } else {
            self.in_dir.join(p)
        }
    }

    /// The computation a `run` command needs, to run on any thread; `None` for other commands.
    pub fn prepare(&self, cmd: &Command) -> Result<Option<Job>, SessionError> {
        let Command::Run(kind) = cmd else {
            return Ok(None);
        };
        let take = self
            .take()
            .ok_or_else(|| err("no take loaded (load PATH first)"))?;
        Ok(Some(Job {
            kind: *kind,
            engine: self.engine.clone(),
            take: take.clone(),
            params: self.params.clone(),
        }))
    }

    /// Stores what a [`Job`] computed. Results for another take than the active one are
    /// dropped.
    pub fn finish(&mut self, done: JobResult) -> Result<Outcome, SessionError> {
        if self.take().map(|t| t.name.as_str()) != Some(done.take.as_str()) {
            return Ok(self.say(format!("dropped results for {}", done.take)));
        }
        let r = Arc::new(done.result?);
        let mut msg = format!(
            "{}: {} frames, nv {}, {:.1} kg",
            match done.kind {
                RunKind::Id => "inverse dynamics",
                RunKind::Sim => "simulation",
            },
            r.time.len(),
            r.model.nv,
            r.model.total_mass()
        );
        if !r.note.is_empty() {
            msg = format!("{msg}, {}", r.note);
        }
        if self
            .selection
            .as_ref()
            .is_none_or(|s| r.model.v_index(s).is_none())
        {
            // the joint of the old selection if it has a coordinate here, else the first
            // rotation
            let joint = self
                .selection
                .as_deref()
                .and_then(|s| joint_of_name(&r.model, s));
            self.selection = joint.and_then(|j| best_coordinate(&r, &j)).or_else(|| {
                (0..r.model.nv)
                    .find(|&k| is_angular(&r.model, k))
                    .map(|k| r.model.v_names[k].clone())
            });
        }
        match done.kind {
            RunKind::Id => self.results = Some((r, done.params)),
            RunKind::Sim => self.sim = Some((r, done.params)),
        }
        Ok(self.say(msg))
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
            Command::Load { path, name } => {
                if is_csv(path) {
                    return self.load_motion(path);
                }
                let mut take = self.engine.load(&self.in_path(path), &self.params)?;
                if let Some(n) = name {
                    take.name = n.clone();
                }
                let msg = match &take.data {
                    TakeData::Bvh(b) => format!(
                        "loaded {} ({} joints, {} frames at {:.0} fps)",
                        take.name,
                        b.joints.len(),
                        b.frames,
                        1.0 / b.frame_time
                    ),
                    TakeData::Robot(r) => format!(
                        "loaded {} ({}: {} joints, nv {}, {:.2} kg); give it a motion: load \
                         STATES.csv or trajectory POSE POSE … over T",
                        take.name,
                        r.kind,
                        take.joint_tree().len(),
                        r.model.nv,
                        r.model.total_mass()
                    ),
                };
                match self.takes.iter().position(|t| t.name == take.name) {
                    Some(i) => {
                        self.takes[i] = take;
                        self.active = Some(i);
                    }
                    None => {
                        self.takes.push(take);
                        self.active = Some(self.takes.len() - 1);
                    }
                }
                self.frame = 0;
                self.results = None;
                self.sim = None;
                Ok(self.say(msg))
            }
            Command::Scene { path } => self.scene(path),
            Command::Trajectory {
                poses,
                duration_s,
                rate_hz,
            } => self.trajectory(poses, *duration_s, *rate_hz),
            Command::Set { key, value } => {
                self.set(key, value)?;
                Ok(self.say(format!("{key} = {value}")))
            }
            Command::Run(_) => {
                let job = self.prepare(cmd)?.ok_or_else(|| err("nothing to run"))?;
                let done = job.run(&Control::default());
                self.finish(done)
            }
            Command::Blend { a, b, window } => {
                let find = |n: &str| {
                    self.takes
                        .iter()
                        .find(|t| t.name == *n)
                        .ok_or_else(|| err(format!("no take called '{n}'")))
                };
                let t = self.engine.blend(find(a)?, find(b)?, *window)?;
                let msg = format!(
                    "blended {a} into {b} over {}:{} s as {} ({} frames)",
                    window.0,
                    window.1,
                    t.name,
                    t.frames()
                );
                match self.takes.iter().position(|x| x.name == t.name) {
                    Some(i) => {
                        self.takes[i] = t;
                        self.active = Some(i);
                    }
                    None => {
                        self.takes.push(t);
                        self.active = Some(self.takes.len() - 1);
                    }
                }
                self.results = None;
                self.frame = self.frame.min(self.frames().saturating_sub(1));
                Ok(self.say(msg))
            }
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
            Command::Export { kind, path } => self.export(*kind, path),
            Command::CompareWeights {
                masses,
                joint,
                path,
            } => self.compare_weights(masses, joint.as_deref(), path),
            Command::ReportMotor { path, curves } => self.report_motor(path, *curves),
            Command::Expect(e) => self.expect(e),
            Command::Screen { .. } | Command::Key(_) => {
                Err(err("screen and key need a front end (the TUI)"))
            }
            Command::Quit => Ok(Outcome {
                quit: true,
                ..Outcome::default()
            }),
        }
    }

    /// Reads a scene (io::scene) exactly as `--scene` does (`TakeOptions::from_scene`): its
    /// unit, stature, up axis, position semantics, joint model, mass, sex, link masses,
    /// smoothing, locks, subtree and contact become the take options, its gains `kp`/`kv`;
    /// its takes are loaded (the first becomes active).
    fn scene(&mut self, path: &Path) -> Result<Outcome, SessionError> {
        let file = self.in_path(path);
        let sc = crate::io::scene::read(&file)?;
        let take =
            TakeOptions::from_scene(&sc).map_err(|e| err(format!("{}: {e}", file.display())))?;
        self.params.take = take;
        if let Some(g) = sc.gains {
            self.params.kp = g.kp;
            self.params.kv = g.kv;
        }
        let first = self.takes.len();
        for t in &sc.takes {
            self.apply(&Command::Load {
                path: t.clone(),
                name: None,
            })?;
        }
        if first < self.takes.len() {
            self.active = Some(first);
        }
        Ok(self.say(format!(
            "scene {}: {} take(s), {} kg",
            file.display(),
            sc.takes.len(),
            sc.mass
        )))
    }

    /// `load S.csv`: a states CSV becomes the active robot's motion.
    fn load_motion(&mut self, path: &Path) -> Result<Outcome, SessionError> {
        let file = self.in_path(path);
        let (i, model) = self.active_robot("load STATES.csv")?;
        let states = self.engine.load_motion(&model, &file)?;
        let n = states.len();
        self.set_motion(i, states, file.display().to_string());
        Ok(self.say(format!(
            "{}: motion from {} ({n} samples)",
            self.takes[i].name,
            file.display()
        )))
    }

    /// `trajectory …`: quintic moves through the poses become the active robot's motion.
    fn trajectory(
        &mut self,
        poses: &[Vec<f64>],
        duration_s: f64,
        rate_hz: f64,
    ) -> Result<Outcome, SessionError> {
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
        let states = super::trajectory::quintic_moves(poses, duration_s, rate_hz)?;
        let n = states.len();
        let source = format!(
            "{} quintic move(s) of {duration_s} s at {rate_hz} Hz",
            poses.len().saturating_sub(1).max(1)
        );
        self.set_motion(i, states, source.clone());
        Ok(self.say(format!("{}: {source} ({n} samples)", self.takes[i].name)))
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

    fn set(&mut self, key: &str, value: &str) -> Result<(), SessionError> {
        let num = |what: &str| -> Result<f64, SessionError> {
            match value.trim_end_matches("kg").parse::<f64>() {
                Ok(x) if x.is_finite() && x >= 0.0 => Ok(x),
                _ => Err(err(format!(
                    "set {key}: expected {what} (a non-negative number), found '{value}'"
                ))),
            }
        };
        // the pipeline's own parsers, so the values mean what the CLI's flags mean
        fn parsed<T: std::str::FromStr>(key: &str, value: &str) -> Result<T, SessionError>
        where
            T::Err: std::fmt::Display,
        {
            value
                .parse::<T>()
                .map_err(|e| err(format!("set {key}: {e}")))
        }
        let auto = matches!(value, "auto" | "none");
        let p = &mut self.params;
        match key {
            "body.mass" => {
                let m = num("a mass in kg")?;
                if m <= 0.0 {
                    return Err(err("set body.mass: the mass must be positive"));
                }
                p.take.body.mass_kg = m;
            }
            "body.sex" => p.take.body.sex = parsed(key, value)?,
            "unit" => {
                p.take.unit = if auto {
                    None
                } else {
                    Some(parsed(key, value)?)
                };
                p.take.stature_m = None;
            }
            "stature" => {
                p.take.stature_m = if auto {
                    None
                } else {
                    let s = num("a stature in m")?;
                    crate::io::bvh::check_stature(s).map_err(|e| err(format!("set {key}: {e}")))?;
                    Some(s)
                }
            }
            "up" => {
                p.take.up = if auto {
                    None
                } else {
                    Some(parsed(key, value)?)
                }
            }
            "positions" => p.take.positions = parsed(key, value)?,
            "subtree" => p.take.subtree = (!auto).then(|| value.to_string()),
            "joints" => p.take.joints = parsed(key, value)?,
            "smooth" => p.take.smooth = parsed::<SmoothSpec>(key, value)?,
            "contact" => p.take.contact = parsed(key, value)?,
            "kp" => p.kp = num("a gain in 1/s²")?,
            "kv" => p.kv = num("a gain in 1/s")?,
            "integrator" => {
                const KNOWN: [&str; 4] = ["euler", "semi-implicit", "rk4", "dopri5"];
                if !KNOWN.contains(&value) {
                    return Err(err(format!(
                        "set integrator: expected one of {}, found '{value}'",
                        KNOWN.join(", ")
                    )));
                }
                p.integrator = value.to_string();
            }
            "dt" => {
                let dt = num("a step in seconds")?;
                if dt <= 0.0 {
                    return Err(err("set dt: the step must be positive"));
                }
                p.dt = dt;
            }
            "lock" => {
                p.take.lock = value
                    .split([',', ' '])
                    .filter(|s| !s.is_empty() && *s != "none")
                    .map(str::to_string)
                    .collect();
            }
            "blend.window" => p.blend_window = num("a window length in seconds")?,
            "motor.catalogue" => {
                // read now, so a bad file fails here and not at the report
                if auto {
                    self.motor_classes = motor::default_catalogue()?;
                    self.params.motor_catalogue = None;
                } else {
                    let file = self.in_path(Path::new(value));
                    self.motor_classes = motor::read_catalogue(&file)?;
                    self.params.motor_catalogue = Some(file);
                }
            }
            _ if key.starts_with("motor.") => {
                let x = num("a positive number")?;
                let (joint, field) = key
                    .strip_prefix("motor.")
                    .and_then(|k| k.rsplit_once('.'))
                    .map_or(("", &key[6..]), |(j, f)| (j, f));
                if x <= 0.0 || (field == "efficiency" && x > 1.0) {
                    return Err(err(format!(
                        "set {key}: {value} is out of range (Km, N > 0; 0 < η ≤ 1)"
                    )));
                }
                if joint.is_empty() {
                    match field {
                        "km" => p.motor.km_nm_per_a = x,
                        "gear" => p.motor.gear_ratio = x,
                        "efficiency" => p.motor.efficiency = Some(x),
                        _ => return Err(err(format!("unknown setting '{key}'"))),
                    }
                } else {
                    // checked against the robot's model, or the latest results of a take
                    let model = match self.take().and_then(|t| t.robot()) {
                        Some(rb) => Some(rb.model.clone()),
                        None => self.latest_results().map(|r| r.model.clone()),
                    };
                    if let Some(m) = model.filter(|m| m.v_index(joint).is_none()) {
                        return Err(err(format!(
                            "set {key}: no coordinate '{joint}' (expected e.g. {})",
                            m.v_names.first().map_or("", String::as_str)
                        )));
                    }
                    let o = self
                        .params
                        .motor_joint
                        .entry(joint.to_string())
                        .or_default();
                    match field {
                        "km" => o.km = Some(x),
                        "gear" => o.gear = Some(x),
                        "efficiency" => o.efficiency = Some(x),
                        _ => return Err(err(format!("unknown setting '{key}'"))),
                    }
                }
            }
            _ => {
                let link = key
                    .strip_prefix("link.")
                    .and_then(|k| k.strip_suffix(".mass"))
                    .ok_or_else(|| err(format!("unknown setting '{key}'")))?;
                if let Some(t) = self.take()
                    && !t.joint_tree().iter().any(|(n, _)| n == link)
                {
                    return Err(err(format!("set {key}: no joint called '{link}'")));
                }
                if self.take().is_some_and(|t| t.robot().is_some()) {
                    return Err(err(format!(
                        "set {key}: a robot's masses are those of its DH table or URDF"
                    )));
                }
                let m = num("a mass in kg")?;
                self.params.take.body.link_mass.insert(link.to_string(), m);
            }
        }
        Ok(())
    }

    /// The coordinates of a joint (a BVH joint, or a robot joint) in the latest results.
    pub fn joint_coords(&self, joint: &str) -> Vec<String> {
        match self.latest_results() {
            Some(r) => coords_of_joint(&r.model, joint),
            None => vec![],
        }
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
        if let Some(r) = self.latest_results()
            && r.model.v_index(name).is_some()
        {
            return Ok(name.to_string());
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
        let Some(r) = self.latest_results() else {
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

    fn export(&mut self, kind: ExportKind, path: &Path) -> Result<Outcome, SessionError> {
        let out = self.out_path(path);
        match kind {
            ExportKind::Csv => {
                let r = self.ensure_results()?;
                let text = results_csv(&r);
                crate::io::write_atomic(&out, text.as_bytes())?;
            }
            ExportKind::Svg => {
                let r = self.ensure_results()?;
                let coord = self
                    .selection
                    .clone()
                    .ok_or_else(|| err("export svg: select a joint first"))?;
                let svg = selection_svg(&r, &coord)?;
                crate::report::chart::write_svg(&out, &svg)?;
            }
            ExportKind::Bvh => {
                // what the user sees: the take (as loaded or blended) smoothed as set
                let take = self
                    .take()
                    .ok_or_else(|| err("no take loaded (load PATH first)"))?;
                self.engine.export_bvh(take, &self.params, None, &out)?;
            }
            ExportKind::BvhSim => {
                let take = self
                    .take()
                    .ok_or_else(|| err("no take loaded (load PATH first)"))?;
                let sim = self
                    .sim
                    .as_ref()
                    .filter(|(_, p)| p.same_results(&self.params))
                    .map(|(r, _)| r.clone())
                    .ok_or_else(|| {
                        err("export bvh sim: no simulation under the current parameters (run sim first)")
                    })?;
                self.engine
                    .export_bvh(take, &self.params, Some(&sim), &out)?;
            }
            ExportKind::Urdf => {
                let r = self.ensure_results()?;
                let urdf = crate::io::urdf_write::model_to_urdf(&r.model)?;
                crate::io::write_atomic(&out, urdf.as_bytes())?;
            }
        }
        let mut o = self.say(format!("wrote {}", out.display()));
        o.written.push(out);
        Ok(o)
    }

    fn compare_weights(
        &mut self,
        masses: &[f64],
        joint: Option<&str>,
        path: &Path,
    ) -> Result<Outcome, SessionError> {
        let coord = match joint {
            Some(j) => self.resolve_coord(j)?,
            None => self
                .selection
                .clone()
                .ok_or_else(|| err("compare weights: select a joint or give joint J"))?,
        };
        let take = self
            .take()
            .ok_or_else(|| err("no take loaded (load PATH first)"))?
            .clone();
        let mut columns = vec![];
        let mut time = vec![];
        for &m in masses {
            let mut params = self.params.clone();
            params.take.body.mass_kg = m;
            let r = self
                .engine
                .inverse_dynamics(&take, &params, &Control::default())?;
            let j = r
                .model
                .v_index(&coord)
                .ok_or_else(|| err(format!("no coordinate '{coord}' in the model")))?;
            columns.push(r.tau.column(j));
            time = r.time.clone();
        }
        let runs: Vec<MassRun> = masses
            .iter()
            .zip(columns)
            .map(|(&mass_kg, tau)| MassRun {
                mass_kg,
                t: time.clone(),
                tau,
            })
            .collect();
        let out = self.out_path(path);
        let text = if is_csv(&out) {
            knee::curves_csv(&runs)?
        } else {
            knee::knee_svg_with_table(&coord, &runs)?
        };
        crate::io::write_atomic(&out, text.as_bytes())?;
        let mut o = self.say(format!(
            "compared {coord} torque at {} kg: wrote {}",
            masses
                .iter()
                .map(|m| m.to_string())
                .collect::<Vec<_>>()
                .join(", "),
            out.display()
        ));
        o.written.push(out);
        Ok(o)
    }

    /// Motor sizing (report::motor) of the revolute coordinates of the selected joint, or of
    /// every revolute coordinate of a robot (or of any model with at most 12 of them). Each
    /// coordinate's drive is [`Params::motor_of`]; the catalogue is `motor.catalogue` or the
    /// bundled `data/motor_classes.toml`.
    fn report_motor(&mut self, path: &Path, curves: bool) -> Result<Outcome, SessionError> {
        let r = self.ensure_results()?;
        let m = &r.model;
        let revolute: Vec<usize> = (0..m.nv)
            .filter(|&k| matches!(m.joints[m.body_of_v(k)], JointKind::Revolute { .. }))
            .collect();
        let robot = self.take().is_some_and(|t| t.robot().is_some());
        let chosen: Vec<usize> = if robot || revolute.len() <= 12 {
            revolute
        } else {
            let sel = self
                .selection
                .as_deref()
                .ok_or_else(|| err("report motor: select a joint first"))?;
            let joint = joint_of_name(m, sel).unwrap_or_else(|| sel.to_string());
            let coords = coords_of_joint(m, &joint);
            revolute
                .into_iter()
                .filter(|&k| coords.contains(&m.v_names[k]))
                .collect()
        };
        if chosen.is_empty() {
            return Err(err(
                "report motor: the selection has no revolute coordinate",
            ));
        }
        let joints: Vec<JointMotion> = chosen
            .iter()
            .map(|&k| JointMotion {
                joint: m.v_names[k].clone(),
                t: r.time.clone(),
                tau: r.tau.column(k),
                qd: r.v.column(k),
            })
            .collect();
        let specs: Vec<_> = joints
            .iter()
            .map(|j| self.params.motor_of(&j.joint))
            .collect();
        if self.motor_classes.is_empty() {
            return Err(err("report motor: the motor catalogue is empty"));
        }
        let loads = motor::size_motors(&joints, &specs, &self.motor_classes)?;
        let out = self.out_path(path);
        let text = match (curves, is_csv(&out)) {
            (true, true) => motor::motor_curves_csv(&joints, &specs)?,
            (true, false) => {
                return Err(err("report motor curves: the curves are written as .csv"));
            }
            (false, true) => motor::motor_table_csv(&loads),
            (false, false) => motor::motor_svg(&joints, &specs, &loads)?,
        };
        crate::io::write_atomic(&out, text.as_bytes())?;
        let classes: Vec<String> = loads
            .iter()
            .map(|l| format!("{} {}", l.joint, motor::class_name(l)))
            .collect();
        let mut o = self.say(format!(
            "motors: {}; wrote {}",
            classes.join(", "),
            out.display()
        ));
        o.written.push(out);
        Ok(o)
    }

    fn expect(&mut self, e: &Expectation) -> Result<Outcome, SessionError> {
        let fail = |m: String| Err(SessionError::Expect(m));
        let within = |x: f64, lo: f64, hi: f64| (lo..=hi).contains(&x);
        let msg = match e {
            Expectation::Nv(n) | Expectation::Nq(n) => {
                let r = self.ensure_results()?;
                let (what, got) = match e {
                    Expectation::Nv(_) => ("nv", r.model.nv),
                    _ => ("nq", r.model.nq),
                };
                if got != *n {
                    return fail(format!("{what} is {got}, expected {n}"));
                }
                format!("{what} = {n}")
            }
            Expectation::Frames(n) => {
                let got = self.frames();
                if got != *n {
                    return fail(format!("the take has {got} frames, expected {n}"));
                }
                format!("frames = {n}")
            }
            Expectation::Frame(n) => {
                if self.frame != *n {
                    return fail(format!("the current frame is {}, expected {n}", self.frame));
                }
                format!("frame = {n}")
            }
            Expectation::Selected(s) => {
                if self.selection.as_deref() != Some(s.as_str()) {
                    return fail(format!(
                        "selected is {}, expected {s}",
                        self.selection.as_deref().unwrap_or("nothing")
                    ));
                }
                format!("selected = {s}")
            }
            Expectation::Mass { lo, hi } => {
                let m = self.ensure_results()?.model.total_mass();
                if !within(m, *lo, *hi) {
                    return fail(format!("total mass {m} kg is outside {lo}‥{hi}"));
                }
                format!("mass {m} kg in {lo}‥{hi}")
            }
            Expectation::Stat {
                stat,
                coord,
                quantity,
                lo,
                hi,
            } => {
                let r = self.ensure_results()?;
                let (table, unit) = match quantity {
                    Quantity::Angle => (&r.v, "rad|m"),
                    Quantity::Velocity => (&r.v, "rad/s|m/s"),
                    Quantity::Acceleration => (&r.a, "rad/s²|m/s²"),
                    Quantity::Torque => (&r.tau, "N·m|N"),
                };
                let j = table.col_index(coord).ok_or_else(|| {
                    err(format!(
                        "no coordinate '{coord}' (expected e.g. {})",
                        table.names.first().map_or("", String::as_str)
                    ))
                })?;
                // angles of ball and free joints: rotation-vector components (angle_series)
                let x = match quantity {
                    Quantity::Angle => angle_series(&r, coord)
                        .ok_or_else(|| err(format!("no angle for '{coord}'")))?,
                    _ => table.column(j),
                };
                let value = match stat {
                    Statistic::Now => x.get(self.frame).copied().unwrap_or(0.0),
                    _ => statistic(*stat, &x),
                };
                let name = format!(
                    "{} {coord} {}",
                    format!("{stat:?}").to_lowercase(),
                    format!("{quantity:?}").to_lowercase()
                );
                if !within(value, *lo, *hi) {
                    return fail(format!("{name} is {value} {unit}, expected {lo}‥{hi}"));
                }
                format!("{name} = {value} in {lo}‥{hi}")
            }
            Expectation::MessageContains(text) => {
                let last = self
                    .messages
                    .iter()
                    .rev()
                    .find(|m| !m.starts_with("ok: "))
                    .map_or("", String::as_str);
                if !last.contains(text.as_str()) {
                    return fail(format!(
                        "the last message is '{last}', expected it to contain '{text}'"
                    ));
                }
                format!("message contains '{text}'")
            }
            Expectation::ScreenContains(_) => {
                return Err(err("expect screen needs a front end (the TUI)"));
            }
        };
        Ok(self.say(format!("ok: {msg}")))
    }
}

/// True for a `.csv` path (anything else is written as SVG).
fn is_csv(p: &Path) -> bool {
    p.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"))
}

/// The paper's figure 4 for one coordinate: its angle (deg) or position (m) and its torque
/// over time, minimum and maximum marked.
pub fn selection_svg(r: &Analysis, coord: &str) -> Result<String, SessionError> {
    let (Some(q), Some(jv)) = (angle_series(r, coord), r.tau.col_index(coord)) else {
        return Err(err(format!("no coordinate '{coord}' in the model")));
    };
    let rotation = is_angular(&r.model, jv);
    let (factor, angle_label, torque_label) = if rotation {
        (180.0 / std::f64::consts::PI, "angle (deg)", "torque (N·m)")
    } else {
        (1.0, "position (m)", "force (N)")
    };
    let angle = [Series::new(
        coord,
        r.time.clone(),
        q.iter().map(|x| x * factor).collect(),
    )];
    let torque = [Series::new(coord, r.time.clone(), r.tau.column(jv))];
    let title_a = format!("{coord} {}", angle_label.split(' ').next().unwrap_or(""));
    let title_t = format!("{coord} {}", torque_label.split(' ').next().unwrap_or(""));
    let panels = [
        Panel {
            title: &title_a,
            x_label: "time (s)",
            y_label: angle_label,
            series: &angle,
            mark_min_max: true,
        },
        Panel {
            title: &title_t,
            x_label: "time (s)",
            y_label: torque_label,
            series: &torque,
            mark_min_max: true,
        },
    ];
    Ok(stacked_svg(&panels, None)?)
}

/// A statistic over a series (0 for an empty one).
pub fn statistic(stat: Statistic, x: &[f64]) -> f64 {
    if x.is_empty() {
        return 0.0;
    }
    let n = x.len() as f64;
    match stat {
        Statistic::Peak => x.iter().fold(0.0, |m, v| m.max(v.abs())),
        Statistic::Min => x.iter().copied().fold(f64::INFINITY, f64::min),
        Statistic::Max => x.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        Statistic::Mean => x.iter().sum::<f64>() / n,
        Statistic::Rms => (x.iter().map(|v| v * v).sum::<f64>() / n).sqrt(),
        Statistic::Now => x[0],
    }
}

/// BVH channel names: the suffix of an euler-model coordinate.
const CHANNELS: [&str; 6] = [
    "Xposition",
    "Yposition",
    "Zposition",
    "Xrotation",
    "Yrotation",
    "Zrotation",
];

/// The BVH (or robot) joint that velocity coordinate `k` belongs to: the joint name of its
/// body, without the `.Xrotation` of an euler-model channel body.
fn joint_of(model: &Model, k: usize) -> &str {
    let name = model.joint_names[model.body_of_v(k)].as_str();
    match name.rsplit_once('.') {
        Some((j, c)) if CHANNELS.contains(&c) => j,
        _ => name,
    }
}

/// The joint of a coordinate name, if the model has that coordinate.
fn joint_of_name(model: &Model, coord: &str) -> Option<String> {
    model.v_index(coord).map(|k| joint_of(model, k).to_string())
}

/// The velocity coordinates of `joint` (a BVH joint or a robot joint), in model order.
pub fn coords_of_joint(model: &Model, joint: &str) -> Vec<String> {
    (0..model.nv)
        .filter(|&k| joint_of(model, k) == joint)
        .map(|k| model.v_names[k].clone())
        .collect()
}

/// True when coordinate `k` is a rotation (rad): revolute joints and the rotation part of ball
/// and free joints.
pub fn is_angular(model: &Model, k: usize) -> bool {
    let b = model.body_of_v(k);
    match model.joints[b] {
        JointKind::Revolute { .. } | JointKind::Spherical => true,
        JointKind::Free => k - model.idx_v[b] >= 3,
        JointKind::Prismatic { .. } | JointKind::Fixed => false,
    }
}

/// The angle (rad) or position (m) of velocity coordinate `coord` over the take: the q column
/// of a 1-DoF joint; for a ball joint (and the rotation of a free joint) the component of the
/// rotation vector `θ·u = log(q)` in the joint frame named by the coordinate (`J:wx` → x), whose
/// derivative is the angular velocity `J:wx` for rotations about a fixed axis; for the
/// translation of a free joint (`J:vx`) its position `J:x` in the parent frame.
pub fn angle_series(r: &Analysis, coord: &str) -> Option<Vec<f64>> {
    if let Some(j) = r.q.col_index(coord) {
        return Some(r.q.column(j));
    }
    let m = &r.model;
    let k = m.v_index(coord)?;
    let b = m.body_of_v(k);
    let (iq, off) = (m.idx_q[b], k - m.idx_v[b]);
    let quat_at = match m.joints[b] {
        JointKind::Spherical => iq,
        JointKind::Free if off < 3 => {
            return Some((0..r.q.rows()).map(|f| r.q.row(f)[iq + off]).collect());
        }
        JointKind::Free => iq + 3,
        _ => return None,
    };
    let c = if matches!(m.joints[b], JointKind::Free) {
        off - 3
    } else {
        off
    };
    Some(
        (0..r.q.rows())
            .map(|f| {
                let q = crate::spatial::quat_from_xyzw(&r.q.row(f)[quat_at..quat_at + 4]);
                q.scaled_axis()[c]
            })
            .collect(),
    )
}

/// The rotation coordinate of `joint` with the largest range of motion (max − min of
/// [`angle_series`]) over the take; `None` when the model has no coordinate of that joint.
pub fn best_coordinate(r: &Analysis, joint: &str) -> Option<String> {
    let coords = coords_of_joint(&r.model, joint);
    let range = |c: &String| {
        angle_series(r, c).map_or(0.0, |x| {
            let hi = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let lo = x.iter().copied().fold(f64::INFINITY, f64::min);
            hi - lo
        })
    };
    let rotations: Vec<&String> = coords
        .iter()
        .filter(|c| r.model.v_index(c).is_some_and(|k| is_angular(&r.model, k)))
        .collect();
    let pool = if rotations.is_empty() {
        coords.iter().collect()
    } else {
        rotations
    };
    // the first of equal ranges wins (deterministic)
    pool.into_iter()
        .fold(None::<(&String, f64)>, |best, c| {
            let x = range(c);
            match best {
                Some((_, b)) if b >= x => best,
                _ => Some((c, x)),
            }
        })
        .map(|(c, _)| c.clone())
}

/// Before any result: `J.CHANNEL` checked against the BVH joint's channels, or for a bare
/// joint its rotation channel with the largest range over the take; named as the joint model
/// names it (`J.Xrotation` euler, `J:wx` ball).
fn channel_by_range(
    bvh: &crate::io::bvh::Bvh,
    name: &str,
    joints: crate::model::bvh::JointModel,
) -> Result<String, SessionError> {
    let (joint, channel) = match bvh.joint_index(name) {
        Some(_) => (name, ""),
        None => name.rsplit_once('.').unwrap_or((name, "")),
    };
    let j = bvh
        .joint_index(joint)
        .ok_or_else(|| err(format!("no joint called '{joint}'")))?;
    let bj = &bvh.joints[j];
    let chans = &bj.channels;
    let range = |i: usize| {
        let col = bj.first_channel + i;
        let x = (0..bvh.frames).map(|f| bvh.frame(f)[col]);
        let hi = x.clone().fold(f64::NEG_INFINITY, f64::max);
        let lo = x.fold(f64::INFINITY, f64::min);
        hi - lo
    };
    let ch = if channel.is_empty() {
        let rot = (0..chans.len()).filter(|&i| chans[i].is_rotation());
        rot.fold(None::<(usize, f64)>, |best, i| match best {
            Some((_, b)) if b >= range(i) => best,
            _ => Some((i, range(i))),
        })
        .map(|(i, _)| i)
        .or((!chans.is_empty()).then_some(0))
    } else {
        chans.iter().position(|c| c.name() == channel)
    };
    let Some(i) = ch else {
        return Err(err(format!(
            "{joint} has no channel '{channel}' (it has {})",
            chans
                .iter()
                .map(|c| c.name())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    };
    let c = chans[i].name();
    Ok(match joints {
        crate::model::bvh::JointModel::Euler => format!("{joint}.{c}"),
        _ => {
            let axis = c[..1].to_ascii_lowercase();
            let kind = if chans[i].is_rotation() { "w" } else { "v" };
            format!("{joint}:{kind}{axis}")
        }
    })
}

/// `time`, then `q:<coord>` (rad, m), `v:` (rad/s, m/s), `a:` (rad/s², m/s²) and `tau:`
/// (N·m, N) per coordinate; shortest round-trip decimal formatting, so replays are
/// byte-identical.
pub fn results_csv(r: &Analysis) -> String {
    let mut text = String::from("time");
    for (prefix, t) in [("q", &r.q), ("v", &r.v), ("a", &r.a), ("tau", &r.tau)] {
        for n in &t.names {
            let _ = write!(text, ",{prefix}:{n}");
        }
    }
    text.push('\n');
    for (k, time) in r.time.iter().enumerate() {
        let _ = write!(text, "{time}");
        for t in [&r.q, &r.v, &r.a, &r.tau] {
            for x in t.row(k) {
                let _ = write!(text, ",{x}");
            }
        }
        text.push('\n');
    }
    text
}
