//! The workbench state and the one function that changes it, [`Workbench::apply`].

use super::SessionError;
use super::command::{Command, Expectation, ExportKind, Quantity, RunKind, Statistic};
use super::engine::{
    Analysis, Builtin, Contact, Control, Engine, JointModel, Params, Sex, Smooth, Take,
};
use crate::report::chart::{Panel, Series, stacked_svg};
use crate::report::knee::{self, MassRun};
use crate::report::motor::{self, JointMotion, MotorSpec};
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
        }
    }

    /// The active take.
    pub fn take(&self) -> Option<&Take> {
        self.active.map(|i| &self.takes[i])
    }

    /// Number of frames of the active take (0 without one).
    pub fn frames(&self) -> usize {
        self.take().map_or(0, |t| t.bvh.frames)
    }

    /// The current results if they match the current parameters.
    pub fn fresh_results(&self) -> Option<&Arc<Analysis>> {
        self.results
            .as_ref()
            .filter(|(_, p)| *p == self.params)
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
            self.selection = r
                .model
                .v_names
                .iter()
                .find(|n| !n.contains("position"))
                .cloned();
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
                let mut take = self.engine.load(&self.in_path(path))?;
                if let Some(n) = name {
                    take.name = n.clone();
                }
                let msg = format!(
                    "loaded {} ({} joints, {} frames at {:.0} fps)",
                    take.name,
                    take.bvh.joints.len(),
                    take.bvh.frames,
                    1.0 / take.bvh.frame_time
                );
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
                    window.0, window.1, t.name, t.bvh.frames
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
            Command::ReportMotor { path } => self.report_motor(path),
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

    /// Reads a scene (io::scene): its parameters replace the current ones, its takes are
    /// loaded (the first becomes active). `stature`, `up`, `position` and `subtree` are not
    /// parameters of the workbench yet; the message says when a scene sets them.
    fn scene(&mut self, path: &Path) -> Result<Outcome, SessionError> {
        let file = self.in_path(path);
        let sc = crate::io::scene::read(&file)?;
        let smooth = match &sc.smooth {
            Some(s) => s
                .parse::<Smooth>()
                .map_err(|e| err(format!("{}: smooth: {e}", file.display())))?,
            None => self.params.smooth,
        };
        self.params = Params {
            body_mass: sc.mass,
            sex: if sc.sex == "female" {
                Sex::Female
            } else {
                Sex::Male
            },
            unit: sc.unit.map(|u| u.scale_to_m()),
            joints: if sc.joints == "ball" {
                JointModel::Ball
            } else {
                JointModel::Euler
            },
            smooth,
            contact: if sc.contact == "feet" {
                Contact::Feet
            } else {
                Contact::None
            },
            link_mass: sc.link_mass.clone(),
            lock: sc.lock.clone(),
            ..self.params.clone()
        };
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
        let ignored: Vec<&str> = [
            ("stature", sc.stature.is_some()),
            ("up", sc.up.is_some()),
            ("subtree", sc.subtree.is_some()),
        ]
        .into_iter()
        .filter_map(|(n, set)| set.then_some(n))
        .collect();
        let mut msg = format!(
            "scene {}: {} take(s), {} kg",
            file.display(),
            sc.takes.len(),
            sc.mass
        );
        if !ignored.is_empty() {
            msg.push_str(&format!(
                " (not applied by the workbench: {})",
                ignored.join(", ")
            ));
        }
        Ok(self.say(msg))
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
        let p = &mut self.params;
        match key {
            "body.mass" => {
                let m = num("a mass in kg")?;
                if m <= 0.0 {
                    return Err(err("set body.mass: the mass must be positive"));
                }
                p.body_mass = m;
            }
            "body.sex" => {
                p.sex = match value {
                    "male" | "m" => Sex::Male,
                    "female" | "f" => Sex::Female,
                    _ => return Err(err(format!("set body.sex: expected male or female, found '{value}'"))),
                }
            }
            "unit" => {
                p.unit = match value {
                    "auto" => None,
                    "m" => Some(1.0),
                    "dm" => Some(0.1),
                    "cm" => Some(0.01),
                    "mm" => Some(0.001),
                    "in" | "inch" => Some(0.0254),
                    _ => Some(value.parse::<f64>().ok().filter(|x| *x > 0.0).ok_or_else(|| {
                        err(format!(
                            "set unit: expected auto, m, dm, cm, mm, in or metres per unit, found '{value}'"
                        ))
                    })?),
                }
            }
            "joints" => {
                p.joints = match value {
                    "euler" => JointModel::Euler,
                    "ball" => JointModel::Ball,
                    _ => return Err(err(format!("set joints: expected euler or ball, found '{value}'"))),
                }
            }
            "smooth" => {
                p.smooth = value
                    .parse::<Smooth>()
                    .map_err(|e| err(format!("set smooth: {e}")))?
            }
            "contact" => {
                p.contact = match value {
                    "none" => Contact::None,
                    "feet" => Contact::Feet,
                    _ => return Err(err(format!("set contact: expected none or feet, found '{value}'"))),
                }
            }
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
                p.lock = value
                    .split([',', ' '])
                    .filter(|s| !s.is_empty() && *s != "none")
                    .map(str::to_string)
                    .collect();
            }
            "blend.window" => p.blend_window = num("a window length in seconds")?,
            "motor.km" | "motor.gear" | "motor.efficiency" => {
                let x = num("a positive number")?;
                if x <= 0.0 || (key == "motor.efficiency" && x > 1.0) {
                    return Err(err(format!(
                        "set {key}: {value} is out of range (Km, N > 0; 0 < η ≤ 1)"
                    )));
                }
                match key {
                    "motor.km" => p.motor_km = x,
                    "motor.gear" => p.motor_gear = x,
                    _ => p.motor_efficiency = x,
                }
            }
            _ => {
                let link = key
                    .strip_prefix("link.")
                    .and_then(|k| k.strip_suffix(".mass"))
                    .ok_or_else(|| err(format!("unknown setting '{key}'")))?;
                if let Some(t) = self.take()
                    && t.bvh.joint_index(link).is_none()
                {
                    return Err(err(format!("set {key}: no joint called '{link}'")));
                }
                let m = num("a mass in kg")?;
                self.params.link_mass.insert(link.to_string(), m);
            }
        }
        Ok(())
    }

    /// A coordinate name from a coordinate or a joint name (its first rotation coordinate).
    fn resolve_coord(&self, name: &str) -> Result<String, SessionError> {
        let take = self
            .take()
            .ok_or_else(|| err("no take loaded (load PATH first)"))?;
        if let Some(r) = self.latest_results()
            && r.model.v_index(name).is_some()
        {
            return Ok(name.to_string());
        }
        let (joint, channel) = name.split_once('.').unwrap_or((name, ""));
        let j = take
            .bvh
            .joint_index(joint)
            .ok_or_else(|| err(format!("no joint called '{joint}' in {}", take.name)))?;
        let chans = &take.bvh.joints[j].channels;
        let ch = if channel.is_empty() {
            chans.iter().find(|c| c.is_rotation()).or(chans.first())
        } else {
            chans.iter().find(|c| c.name() == channel)
        };
        match ch {
            Some(c) => Ok(format!("{joint}.{}", c.name())),
            None => Err(err(format!(
                "{joint} has no channel '{channel}' (it has {})",
                chans
                    .iter()
                    .map(|c| c.name())
                    .collect::<Vec<_>>()
                    .join(", ")
            ))),
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
                let take = self
                    .take()
                    .ok_or_else(|| err("no take loaded (load PATH first)"))?;
                crate::io::bvh::write(&take.bvh, &out)?;
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
            let params = Params {
                body_mass: m,
                ..self.params.clone()
            };
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
    /// every revolute coordinate when the model has at most 12 (an arm).
    fn report_motor(&mut self, path: &Path) -> Result<Outcome, SessionError> {
        let r = self.ensure_results()?;
        let m = &r.model;
        let revolute: Vec<usize> = (0..m.nv)
            .filter(|&k| m.joints[m.body_of_v(k)].name() == "revolute")
            .collect();
        let chosen: Vec<usize> = if revolute.len() <= 12 {
            revolute
        } else {
            let sel = self
                .selection
                .as_deref()
                .ok_or_else(|| err("report motor: select a joint first"))?;
            let joint = sel.rsplit_once('.').map_or(sel, |(j, _)| j);
            revolute
                .into_iter()
                .filter(|&k| m.v_names[k].rsplit_once('.').map_or("", |(j, _)| j) == joint)
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
        let spec = MotorSpec {
            km_nm_per_a: self.params.motor_km,
            gear_ratio: self.params.motor_gear,
            efficiency: Some(self.params.motor_efficiency),
        };
        let loads = motor::size_motors(&joints, &vec![spec; joints.len()])?;
        let out = self.out_path(path);
        let text = if is_csv(&out) {
            motor::motor_table_csv(&loads)
        } else {
            motor::motor_svg(&joints, &loads)?
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
                    Quantity::Angle => (&r.q, "rad|m"),
                    Quantity::Velocity => (&r.v, "rad/s|m/s"),
                    Quantity::Acceleration => (&r.a, "rad/s²|m/s²"),
                    Quantity::Torque => (&r.tau, "N·m|N"),
                };
                let j = table.col_index(coord).ok_or_else(|| {
                    err(format!(
                        "no coordinate '{coord}' (expected e.g. {})",
                        table.names[0]
                    ))
                })?;
                let x = table.column(j);
                let value = statistic(*stat, &x);
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
    let (jq, jv) = match (r.q.col_index(coord), r.tau.col_index(coord)) {
        (Some(a), Some(b)) => (a, b),
        _ => return Err(err(format!("no coordinate '{coord}' in the model"))),
    };
    let rotation = r.model.joints[r.model.body_of_v(jv)].name() == "revolute";
    let (factor, angle_label, torque_label) = if rotation {
        (180.0 / std::f64::consts::PI, "angle (deg)", "torque (N·m)")
    } else {
        (1.0, "position (m)", "force (N)")
    };
    let angle = [Series::new(
        coord,
        r.time.clone(),
        r.q.column(jq).iter().map(|x| x * factor).collect(),
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
    }
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
