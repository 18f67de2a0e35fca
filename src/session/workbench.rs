//! The workbench state and the one function that changes it, [`Workbench::apply`].

use super::SessionError;
use super::command::{Command, Expectation, ExportKind, Quantity, RunKind, Statistic, TakeRef};
use super::engine::{Analysis, Builtin, Control, Engine, Params, Take, TakeData};
use super::units::{self, Bare, Kind, Measure};
use crate::model::{JointKind, Model};
use crate::pipeline::{PerJoint, TakeOptions};
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
    /// What a passed `expect` found, in the unit it shows it in (`deg`, `N·m`, `kg`; empty for
    /// a count); `None` for any other command.
    pub value: Option<(f64, &'static str)>,
}

/// What a [`Job`] computes: the commands whose work can take longer than a frame on a big
/// take (parsing, building the model, smoothing, inverse dynamics, simulation, charts).
#[derive(Debug, Clone)]
enum Task {
    /// `run id`, `run sim`.
    Run(RunKind),
    /// `load PATH [as NAME]` of a take, a DH table or a URDF (the file resolved).
    Load { file: PathBuf, name: Option<String> },
    /// `load STATES.csv`: the motion of robot `index`.
    Motion {
        file: PathBuf,
        index: usize,
        model: Arc<Model>,
    },
    /// `trajectory …`: the motion of robot `index`.
    Trajectory {
        index: usize,
        poses: Vec<Vec<f64>>,
        duration_s: f64,
        rate_hz: f64,
    },
    /// `scene PATH`; its takes are read as `load` reads them (relative to `in_dir`).
    Scene { file: PathBuf, in_dir: PathBuf },
    /// `blend A B T0:T1`.
    Blend {
        a: Box<Take>,
        b: Box<Take>,
        window: (f64, f64),
    },
    /// `export KIND PATH` (the output path resolved).
    Export { kind: ExportKind, out: PathBuf },
    /// `compare weights …` of coordinate `coord`.
    Compare {
        masses: Vec<f64>,
        coord: String,
        out: PathBuf,
    },
    /// `report motor [curves] PATH`.
    ReportMotor { out: PathBuf, curves: bool },
    /// A cheap command that needs fresh inverse-dynamics results (an `expect`): the results
    /// are computed by the job, the command is applied by [`Workbench::finish`].
    Then(Box<Command>),
}

/// A computation prepared from the workbench ([`Workbench::prepare`]), runnable on another
/// thread ([`Job::run`]): it holds a snapshot of what it reads (the take, the parameters, the
/// fresh results, the selection), so the workbench may change meanwhile. Its [`JobResult`]
/// goes back through [`Workbench::finish`], which alone changes the workbench.
#[derive(Clone)]
pub struct Job {
    task: Task,
    label: String,
    engine: Arc<dyn Engine>,
    /// The active take.
    take: Option<Take>,
    params: Params,
    /// Inverse-dynamics results valid under `params`, if the workbench had them.
    fresh: Option<Arc<Analysis>>,
    /// The simulation valid under `params`, if any (`export bvh sim`).
    sim: Option<Arc<Analysis>>,
    selection: Option<String>,
    motor_classes: Vec<motor::MotorClass>,
}

impl std::fmt::Debug for Job {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Job")
            .field("task", &self.label)
            .field("take", &self.take.as_ref().map(|t| &t.name))
            .finish()
    }
}

/// What a [`Job`] produced.
#[derive(Debug)]
enum Output {
    /// Results of `run id` / `run sim`.
    Run(RunKind, Arc<Analysis>),
    /// A loaded (or blended) take, to make active.
    Take {
        take: Box<Take>,
        blended: bool,
        message: String,
    },
    /// The motion of robot `index` (called `take` when the job started).
    Motion {
        index: usize,
        take: String,
        states: crate::pipeline::States,
        source: String,
        message: String,
    },
    /// A scene's options, gains and takes.
    Scene {
        options: Box<TakeOptions>,
        gains: Option<(PerJoint, PerJoint)>,
        takes: Vec<Take>,
        message: String,
    },
    /// A file written (atomically: a cancelled job writes nothing).
    Wrote { path: PathBuf, message: String },
    /// Apply this command now that the results are fresh.
    Then(Box<Command>),
}

/// What a [`Job`] produced, with the take and parameters it ran under (so a stale result is
/// known).
#[derive(Debug)]
pub struct JobResult {
    label: String,
    /// Name of the take that was active when the job was prepared.
    take: Option<String>,
    params: Params,
    /// Inverse-dynamics results the job computed on the way (for an export, a report, an
    /// expect); kept as `run id` keeps its results.
    analysis: Option<Arc<Analysis>>,
    output: Result<Output, SessionError>,
}

impl JobResult {
    /// The job's label.
    pub fn label(&self) -> &str {
        &self.label
    }
    /// True when the job stopped because it was cancelled.
    pub fn is_cancelled(&self) -> bool {
        self.output
            .as_ref()
            .err()
            .is_some_and(SessionError::is_cancelled)
    }
}

impl Job {
    /// A short label for progress displays (`compare weights 60, 80, 100 kg`).
    pub fn label(&self) -> &str {
        &self.label
    }

    /// True for inverse dynamics of the active take (`run id`, or the recompute after a
    /// change): a newer request makes a running one obsolete.
    pub fn is_inverse_dynamics(&self) -> bool {
        matches!(self.task, Task::Run(RunKind::Id))
    }

    /// Runs the computation (any thread), reporting progress to `ctl` and stopping with
    /// `cancelled` soon after `ctl` is cancelled. Files are written last and atomically
    /// (`io::write_atomic`), after the last cancel check.
    pub fn run(&self, ctl: &Control) -> JobResult {
        let mut analysis = None;
        let output = self.compute(ctl, &mut analysis);
        JobResult {
            label: self.label.clone(),
            take: self.take.as_ref().map(|t| t.name.clone()),
            params: self.params.clone(),
            analysis,
            output,
        }
    }

    fn take(&self) -> Result<&Take, SessionError> {
        self.take
            .as_ref()
            .ok_or_else(|| err("no take loaded (load PATH first)"))
    }

    /// Fresh inverse-dynamics results: the workbench's, or computed now over `0‥upto` of the
    /// job's progress (and recorded in `analysis`).
    fn results(
        &self,
        ctl: &Control,
        analysis: &mut Option<Arc<Analysis>>,
        upto: f64,
    ) -> Result<Arc<Analysis>, SessionError> {
        if let Some(r) = &self.fresh {
            return Ok(r.clone());
        }
        let take = self.take()?;
        ctl.set_span(0.0, upto);
        let r = Arc::new(self.engine.inverse_dynamics(take, &self.params, ctl)?);
        ctl.set_span(upto, 1.0);
        *analysis = Some(r.clone());
        Ok(r)
    }

    /// The selection once `analysis` (computed by this job) is stored ([`selection_for`]).
    fn selection(&self, analysis: &Option<Arc<Analysis>>) -> Option<String> {
        match analysis {
            Some(r) => selection_for(r, self.selection.as_deref()),
            None => self.selection.clone(),
        }
    }

    fn compute(
        &self,
        ctl: &Control,
        analysis: &mut Option<Arc<Analysis>>,
    ) -> Result<Output, SessionError> {
        ctl.check()?;
        let (engine, params) = (&self.engine, &self.params);
        match &self.task {
            Task::Run(kind) => {
                let take = self.take()?;
                let r = match kind {
                    RunKind::Id => engine.inverse_dynamics(take, params, ctl)?,
                    RunKind::Sim => engine.simulate(take, params, ctl)?,
                };
                Ok(Output::Run(*kind, Arc::new(r)))
            }
            Task::Load { file, name } => {
                let mut take = engine.load(file, params)?;
                if let Some(n) = name {
                    take.name = n.clone();
                }
                ctl.check()?;
                Ok(Output::Take {
                    message: loaded_message(&take),
                    take: Box::new(take),
                    blended: false,
                })
            }
            Task::Motion { file, index, model } => {
                let states = engine.load_motion(model, file)?;
                ctl.check()?;
                let take = self.take()?.name.clone();
                let message = format!(
                    "{take}: motion from {} ({} samples)",
                    file.display(),
                    states.len()
                );
                Ok(Output::Motion {
                    index: *index,
                    take,
                    states,
                    source: file.display().to_string(),
                    message,
                })
            }
            Task::Trajectory {
                index,
                poses,
                duration_s,
                rate_hz,
            } => {
                let states = super::trajectory::quintic_moves(poses, *duration_s, *rate_hz)?;
                ctl.check()?;
                let source = format!(
                    "{} quintic move(s) of {duration_s} s at {rate_hz} Hz",
                    poses.len().saturating_sub(1).max(1)
                );
                let take = self.take()?.name.clone();
                let message = format!("{take}: {source} ({} samples)", states.len());
                Ok(Output::Motion {
                    index: *index,
                    take,
                    states,
                    source,
                    message,
                })
            }
            Task::Scene { file, in_dir } => {
                let sc = crate::io::scene::read(file)?;
                let options = TakeOptions::from_scene(&sc)
                    .map_err(|e| err(format!("{}: {e}", file.display())))?;
                let mut p = params.clone();
                p.take = options.clone();
                // the takes, as `load` reads them, one span of the progress each
                let n = sc.takes.len().max(1) as f64;
                let mut takes = vec![];
                for (i, t) in sc.takes.iter().enumerate() {
                    ctl.set_span(i as f64 / n, (i + 1) as f64 / n);
                    ctl.check()?;
                    takes.push(engine.load(&resolve_in(in_dir, t), &p)?);
                }
                ctl.check()?;
                Ok(Output::Scene {
                    options: Box::new(options),
                    gains: sc.gains.map(|g| (g.kp, g.kv)),
                    message: format!(
                        "scene {}: {} take(s), {} kg",
                        file.display(),
                        sc.takes.len(),
                        sc.mass
                    ),
                    takes,
                })
            }
            Task::Blend { a, b, window } => {
                let t = engine.blend(a, b, *window)?;
                ctl.check()?;
                let message = format!(
                    "blended {} into {} over {}:{} s as {} ({} frames)",
                    a.name,
                    b.name,
                    window.0,
                    window.1,
                    t.name,
                    t.frames()
                );
                Ok(Output::Take {
                    take: Box::new(t),
                    blended: true,
                    message,
                })
            }
            Task::Export { kind, out } => self.export(ctl, analysis, *kind, out),
            Task::Compare { masses, coord, out } => self.compare(ctl, masses, coord, out),
            Task::ReportMotor { out, curves } => self.report_motor(ctl, analysis, out, *curves),
            Task::Then(cmd) => {
                self.results(ctl, analysis, 1.0)?;
                Ok(Output::Then(cmd.clone()))
            }
        }
    }

    fn export(
        &self,
        ctl: &Control,
        analysis: &mut Option<Arc<Analysis>>,
        kind: ExportKind,
        out: &Path,
    ) -> Result<Output, SessionError> {
        match kind {
            ExportKind::Csv => {
                let r = self.results(ctl, analysis, 0.8)?;
                let text = results_csv(&r);
                ctl.check()?;
                crate::io::write_atomic(out, text.as_bytes())?;
                // its sidecar NAME.json: the columns' units (docs/formats.md)
                let p = crate::pipeline::summary::Provenance {
                    command: "export csv",
                    arguments: &[],
                    take: None,
                    model: Some(&r.model),
                    notes: &[],
                };
                crate::pipeline::summary::write_sidecar(out, &p)?;
            }
            ExportKind::Svg => {
                let r = self.results(ctl, analysis, 0.8)?;
                let coord = self
                    .selection(analysis)
                    .ok_or_else(|| err("export svg: select a joint first"))?;
                let svg = selection_svg(&r, &coord)?;
                ctl.check()?;
                crate::report::chart::write_svg(out, &svg)?;
            }
            ExportKind::Bvh => {
                // what the user sees: the take (as loaded or blended) smoothed as set
                let take = self.take()?;
                self.engine.export_bvh(take, &self.params, None, out, ctl)?;
            }
            ExportKind::BvhSim => {
                let take = self.take()?;
                let sim = self.sim.as_ref().ok_or_else(|| {
                    err("export bvh sim: no simulation under the current parameters (run sim first)")
                })?;
                self.engine
                    .export_bvh(take, &self.params, Some(sim), out, ctl)?;
            }
            ExportKind::Urdf => {
                let r = self.results(ctl, analysis, 0.9)?;
                let urdf = crate::io::urdf_write::model_to_urdf(&r.model)?;
                ctl.check()?;
                crate::io::write_atomic(out, urdf.as_bytes())?;
            }
            ExportKind::Mjcf => {
                let r = self.results(ctl, analysis, 0.9)?;
                let mjcf = self.mjcf(&r)?;
                ctl.check()?;
                crate::io::write_atomic(out, mjcf.as_bytes())?;
            }
            ExportKind::States | ExportKind::Trc | ExportKind::Grf | ExportKind::Gltf => {
                let take = self.take()?;
                let files = self
                    .engine
                    .export_take_file(take, &self.params, kind, out, ctl)?;
                let names: Vec<String> = files.iter().map(|p| p.display().to_string()).collect();
                return Ok(Output::Wrote {
                    path: out.to_path_buf(),
                    message: format!("wrote {}", names.join(" and ")),
                });
            }
        }
        Ok(Output::Wrote {
            path: out.to_path_buf(),
            message: format!("wrote {}", out.display()),
        })
    }

    /// The results' model as MJCF: every motor's gear the drive's `N·η` (so the control is the
    /// motor shaft's torque), a floor under a BVH take's frames (none under a robot).
    fn mjcf(&self, r: &Analysis) -> Result<String, SessionError> {
        let gear = r
            .model
            .v_names
            .iter()
            .map(|n| {
                let m = self.params.motor_of(n);
                m.gear_ratio * m.eta()
            })
            .collect();
        let floor = self
            .take()?
            .bvh()
            .map(|_| crate::pipeline::floor_level(&r.model, (0..r.q.rows()).map(|k| r.q.row(k))));
        let keyframe = (r.q.rows() > 0).then(|| r.q.row(0).to_vec());
        let opts = crate::io::mjcf_write::MjcfOptions {
            floor,
            keyframe,
            gear,
            gear_source: Some(
                "the workbench's motor drives (gear = N * efficiency: the control is the motor \
                 shaft's torque)"
                    .into(),
            ),
        };
        Ok(crate::io::mjcf_write::model_to_mjcf(&r.model, &opts)?)
    }

    /// Inverse dynamics at each body mass, one span of the progress per mass; the torque of
    /// `coord` per mass as a chart with its peak/RMS table (`.svg`) or the curves (`.csv`).
    fn compare(
        &self,
        ctl: &Control,
        masses: &[f64],
        coord: &str,
        out: &Path,
    ) -> Result<Output, SessionError> {
        let take = self.take()?;
        let n = masses.len().max(1) as f64;
        let mut runs = Vec::with_capacity(masses.len());
        let mut model = None; // the coordinates' model, for the sidecar's units
        let mut kind = "tau"; // a model coordinate's torque, or an anatomical axis's moment
        for (i, &mass_kg) in masses.iter().enumerate() {
            ctl.set_span(i as f64 / n, (i + 1) as f64 / n);
            let mut params = self.params.clone();
            params.take.body.mass_kg = mass_kg;
            let r = self.engine.inverse_dynamics(take, &params, ctl)?;
            let tau = torque_series(&r, coord)
                .ok_or_else(|| err(format!("no coordinate '{coord}' in the model")))?;
            model = Some(r.model.clone());
            if r.tau.col_index(coord).is_none() {
                kind = "moment";
            }
            runs.push(MassRun {
                mass_kg,
                tau,
                quoted: (0..r.time.len()).map(|k| r.quoted(k)).collect(),
                t: r.time,
            });
        }
        let text = if is_csv(out) {
            knee::curves_csv(kind, coord, &runs)?
        } else {
            knee::knee_svg_with_table(coord, &runs)?
        };
        ctl.check()?;
        crate::io::write_atomic(out, text.as_bytes())?;
        if is_csv(out) {
            table_sidecar(out, "compare weights", model.as_deref())?;
        }
        let message = format!(
            "compared {coord} torque at {} kg: wrote {}",
            masses
                .iter()
                .map(|m| m.to_string())
                .collect::<Vec<_>>()
                .join(", "),
            out.display()
        );
        Ok(Output::Wrote {
            path: out.to_path_buf(),
            message,
        })
    }

    /// Motor sizing (report::motor) of the revolute coordinates of the selected joint, or of
    /// every revolute coordinate of a robot (or of any model with at most 12 of them). Each
    /// coordinate's drive is [`Params::motor_of`]; the catalogue is `motor.catalogue` or the
    /// bundled `data/motor_classes.toml`.
    fn report_motor(
        &self,
        ctl: &Control,
        analysis: &mut Option<Arc<Analysis>>,
        out: &Path,
        curves: bool,
    ) -> Result<Output, SessionError> {
        let r = self.results(ctl, analysis, 0.8)?;
        let m = &r.model;
        let revolute: Vec<usize> = (0..m.nv)
            .filter(|&k| matches!(m.joints[m.body_of_v(k)], JointKind::Revolute { .. }))
            .collect();
        let robot = self.take.as_ref().is_some_and(|t| t.robot().is_some());
        let chosen: Vec<usize> = if robot || revolute.len() <= 12 {
            revolute
        } else {
            let sel = self
                .selection(analysis)
                .ok_or_else(|| err("report motor: select a joint first"))?;
            let joint = joint_of_selection(&r, &sel).unwrap_or_else(|| sel.to_string());
            let coords = coords_of_joint(m, &joint);
            revolute
                .into_iter()
                .filter(|&k| coords.contains(&m.v_names[k]))
                .collect()
        };
        // an avatar's root hangs from the world: its "torques" are the residual forces and
        // moments no joint gives (near zero for a consistent take), so no motor drives them
        if !robot
            && m.nv > 0
            && let Some(&k) = chosen.first()
            && joint_of(m, k) == joint_of(m, 0)
        {
            return Err(err(format!(
                "report motor: {} is the root; its coordinates carry the residual forces and                  moments that no motor gives: select a joint of a limb (select knee_l, select                  LeftLeg)",
                joint_of(m, 0)
            )));
        }
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
        let text = match (curves, is_csv(out)) {
            (true, true) => motor::motor_curves_csv(&joints, &specs)?,
            (true, false) => {
                return Err(err("report motor curves: the curves are written as .csv"));
            }
            (false, true) => motor::motor_table_csv(&loads),
            (false, false) => motor::motor_svg(&joints, &specs, &loads)?,
        };
        ctl.check()?;
        crate::io::write_atomic(out, text.as_bytes())?;
        if curves {
            table_sidecar(out, "report motor curves", Some(m.as_ref()))?;
        }
        let classes: Vec<String> = loads
            .iter()
            .map(|l| format!("{} {}", l.joint, motor::class_name(l)))
            .collect();
        Ok(Output::Wrote {
            path: out.to_path_buf(),
            message: format!("motors: {}; wrote {}", classes.join(", "), out.display()),
        })
    }
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
fn names_a_joint(b: &crate::io::bvh::Bvh, name: &str) -> bool {
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
    /// Whether the curves also draw the selected coordinate's mirror (`set overlay mirror`:
    /// `knee_r:flexion` beside `knee_l:flexion`, `RightLeg.Xrotation` beside
    /// `LeftLeg.Xrotation`); a view setting, results do not depend on it.
    pub overlay_mirror: bool,
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
            overlay_mirror: false,
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
    fn model_to_check(&self) -> Option<Arc<Model>> {
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

    /// The computation a long command needs (`run`, `load`, `scene`, `trajectory`, `blend`,
    /// `export`, `compare weights`, `report motor`, and an `expect` whose results are stale),
    /// to run on any thread; `None` for the commands that apply at once. Errors that need no
    /// computation (no take, an unknown joint) are found here.
    pub fn prepare(&self, cmd: &Command) -> Result<Option<Job>, SessionError> {
        let take_name = || {
            self.take()
                .map(|t| t.name.clone())
                .ok_or_else(|| err("no take loaded (load PATH first)"))
        };
        let (task, label) = match cmd {
            Command::Run(kind) => {
                let name = take_name()?;
                let label = match kind {
                    RunKind::Id => format!("inverse dynamics of {name}"),
                    RunKind::Sim => format!("simulation of {name}"),
                };
                (Task::Run(*kind), label)
            }
            Command::Load { path, .. } if is_csv(path) => {
                let file = self.in_path(path);
                let (index, model) = self.active_robot("load STATES.csv")?;
                let label = format!("loading {}", path.display());
                (Task::Motion { file, index, model }, label)
            }
            Command::Load { path, name } => {
                let file = self.in_path(path);
                let name = name.clone().or_else(|| self.second_name(&file));
                (
                    Task::Load { file, name },
                    format!("loading {}", path.display()),
                )
            }
            Command::Scene { path } => (
                Task::Scene {
                    file: self.in_path(path),
                    in_dir: self.in_dir.clone(),
                },
                format!("scene {}", path.display()),
            ),
            Command::Trajectory {
                poses,
                duration_s,
                rate_hz,
            } => {
                let (index, poses) = self.check_trajectory(poses)?;
                let label = format!("trajectory of {}", self.takes[index].name);
                let task = Task::Trajectory {
                    index,
                    poses,
                    duration_s: *duration_s,
                    rate_hz: *rate_hz,
                };
                (task, label)
            }
            Command::Blend { a, b, window } => {
                let find = |n: &str| {
                    self.takes
                        .iter()
                        .find(|t| t.name == *n)
                        .cloned()
                        .ok_or_else(|| err(format!("no take called '{n}'")))
                };
                let task = Task::Blend {
                    a: Box::new(find(a)?),
                    b: Box::new(find(b)?),
                    window: *window,
                };
                (task, format!("blend {a} {b}"))
            }
            Command::Export { kind, path } => {
                let word = kind.word();
                let task = Task::Export {
                    kind: *kind,
                    out: self.out_path(path),
                };
                (task, format!("export {word} {}", path.display()))
            }
            Command::CompareWeights {
                masses,
                joint,
                path,
            } => {
                let coord = match joint {
                    Some(j) => self.resolve_coord(j)?,
                    None => self
                        .selection
                        .clone()
                        .ok_or_else(|| err("compare weights: select a joint or give joint J"))?,
                };
                take_name()?;
                let label = format!(
                    "compare weights {} kg",
                    masses
                        .iter()
                        .map(|m| m.to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                );
                let task = Task::Compare {
                    masses: masses.clone(),
                    coord,
                    out: self.out_path(path),
                };
                (task, label)
            }
            Command::ReportMotor { path, curves } => (
                Task::ReportMotor {
                    out: self.out_path(path),
                    curves: *curves,
                },
                format!("report motor {}", path.display()),
            ),
            Command::Expect(e)
                if needs_results(e) && self.take().is_some() && self.fresh_results().is_none() =>
            {
                let label = format!("inverse dynamics of {}", take_name()?);
                (Task::Then(Box::new(cmd.clone())), label)
            }
            _ => return Ok(None),
        };
        Ok(Some(Job {
            task,
            label,
            engine: self.engine.clone(),
            take: self.take().cloned(),
            params: self.params.clone(),
            fresh: self.fresh_results().cloned(),
            sim: self
                .sim
                .as_ref()
                .filter(|(_, p)| p.same_results(&self.params))
                .map(|(r, _)| r.clone()),
            selection: self.selection.clone(),
            motor_classes: self.motor_classes.clone(),
        }))
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

    fn set(&mut self, key: &str, value: &str) -> Result<(), SessionError> {
        // a number of `kind` (a unit may be written: `80kg`, `5ms`, `175cm`), or a plain
        // number for `kind` None (gains, drive ratios)
        let read = |kind: Option<Kind>, what: &str| -> Result<f64, SessionError> {
            match kind {
                Some(k) => units::parse_si(value, k, what),
                None => units::parse_plain(value, what),
            }
            .map_err(|e| match e {
                units::UnitError::NotANumber { .. } => {
                    err(format!("set {key}: expected {what}, found '{value}'"))
                }
                e => err(format!("set {key}: {e}")),
            })
        };
        let num = |kind: Option<Kind>, what: &str| -> Result<f64, SessionError> {
            match read(kind, what)? {
                x if x >= 0.0 => Ok(x),
                _ => Err(err(format!(
                    "set {key}: expected {what} (a non-negative number), found '{value}'"
                ))),
            }
        };
        let positive = |kind: Option<Kind>, what: &str| -> Result<f64, SessionError> {
            match read(kind, what)? {
                x if x > 0.0 => Ok(x),
                _ => Err(err(format!("set {key}: expected {what}, found '{value}'"))),
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
        if key == "overlay" {
            self.overlay_mirror = match value {
                "mirror" => true,
                "none" => false,
                _ => {
                    return Err(err(format!(
                        "set overlay: expected mirror or none, found '{value}'"
                    )));
                }
            };
            return Ok(());
        }
        let auto = matches!(value, "auto" | "none");
        let p = &mut self.params;
        match key {
            "body.mass" => {
                p.take.body.mass_kg = positive(Some(Kind::Mass), "a positive mass in kg")?
            }
            "body.sex" => p.take.body.sex = parsed(key, value)?,
            "body.segments" => p.take.body.segments = parsed(key, value)?,
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
                    let s = num(Some(Kind::Length), "a stature in m")?;
                    crate::io::bvh::check_given_stature(s)
                        .map_err(|e| err(format!("set {key}: {e}")))?;
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
            "smooth" => {
                let spec = crate::pipeline::parse_smooth(value)
                    .map_err(|e| err(format!("set {key}: {e}")))?;
                // a filter the active take cannot take is refused now, with nothing changed
                // (it stayed in the panel, marked stale, after the recompute failed)
                let dt = self
                    .active
                    .and_then(|i| self.takes[i].bvh())
                    .map(|b| b.frame_time);
                if let (Some(s), Some(dt)) = (spec, dt) {
                    crate::motion::smooth::Smoother::new(s, dt)
                        .map_err(|e| err(format!("set {key}: {e}")))?;
                }
                self.params.take.smooth = spec;
            }
            "contact" => p.take.contact = parsed(key, value)?,
            "consistent" => {
                p.consistent = match value {
                    "auto" => None,
                    "on" => Some(true),
                    "off" => Some(false),
                    _ => {
                        return Err(err(format!(
                            "set consistent: expected auto, on or off, found '{value}'"
                        )));
                    }
                }
            }
            "edges" => {
                p.include_edges = match value {
                    "exclude" => false,
                    "include" => true,
                    _ => {
                        return Err(err(format!(
                            "set edges: expected exclude or include, found '{value}'"
                        )));
                    }
                }
            }
            "keep_first_frame" => p.take.keep_first_frame = parsed::<bool>(key, value)?,
            "joint_translations" => p.take.joint_translations = parsed(key, value)?,
            "bvh_style" => p.bvh_style = parsed(key, value)?,
            "kp" => p.kp.all = num(None, "a gain in 1/s²")?,
            "kv" => p.kv.all = num(None, "a gain in 1/s")?,
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
            "dt" => p.dt = positive(Some(Kind::Time), "a positive step in seconds")?,
            "lock" => {
                p.take.lock = value
                    .split([',', ' '])
                    .filter(|s| !s.is_empty() && *s != "none")
                    .map(str::to_string)
                    .collect();
            }
            "blend.window" => p.blend_window = num(Some(Kind::Time), "a window length in seconds")?,
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
            _ if key.starts_with("kp.") || key.starts_with("kv.") => {
                // a diagonal gain of one joint or coordinate (`kp.LeftLeg`, `kv.j2`)
                let (which, name) = (&key[..2], &key[3..]);
                let x = num(None, "a gain (1/s² for kp, 1/s for kv)")?;
                if name.is_empty() {
                    return Err(err(format!("set {key}: expected kp.<joint> or kv.<joint>")));
                }
                if let Some(m) = self.model_to_check() {
                    let mut one = PerJoint::default();
                    one.joints.insert(name.to_string(), x);
                    crate::pipeline::per_coordinate(&m, &one, 0, which)
                        .map_err(|e| err(format!("set {key}: {e}")))?;
                } else if let Some(b) = self.take().and_then(|t| t.bvh()) {
                    // no model yet: a joint of the take, or one of its coordinates
                    if !names_a_joint(b, name) {
                        return Err(err(format!(
                            "set {key}: the take has no joint '{name}' (expected e.g. {})",
                            b.joints.get(1).map_or("", |j| j.name.as_str())
                        )));
                    }
                }
                let p = &mut self.params;
                let g = if which == "kp" { &mut p.kp } else { &mut p.kv };
                g.joints.insert(name.to_string(), x);
            }
            _ if key.starts_with("motor.") => {
                let x = num(None, "a positive number")?;
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
                    if let Some(m) = self.model_to_check().filter(|m| m.v_index(joint).is_none()) {
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
                let m = num(Some(Kind::Mass), "a mass in kg")?;
                self.params.take.body.link_mass.insert(link.to_string(), m);
            }
        }
        Ok(())
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

    fn expect(&mut self, e: &Expectation) -> Result<Outcome, SessionError> {
        let fail = |m: String| Err(SessionError::Expect(m));
        let within = |x: f64, lo: f64, hi: f64| (lo..=hi).contains(&x);
        let count = |n: usize| Some((n as f64, ""));
        let (msg, found) = match e {
            Expectation::Nv(n) | Expectation::Nq(n) => {
                let r = self.ensure_results()?;
                let (what, got) = match e {
                    Expectation::Nv(_) => ("nv", r.model.nv),
                    _ => ("nq", r.model.nq),
                };
                if got != *n {
                    return fail(format!("{what} is {got}, expected {n}"));
                }
                (format!("{what} = {n}"), count(got))
            }
            Expectation::Frames(n) => {
                let got = self.frames();
                if got != *n {
                    return fail(format!("the take has {got} frames, expected {n}"));
                }
                (format!("frames = {n}"), count(got))
            }
            Expectation::Frame(n) => {
                if self.frame != *n {
                    return fail(format!("the current frame is {}, expected {n}", self.frame));
                }
                (format!("frame = {n}"), count(self.frame))
            }
            Expectation::Selected(s) => {
                if self.selection.as_deref() != Some(s.as_str()) {
                    return fail(format!(
                        "selected is {}, expected {s}",
                        self.selection.as_deref().unwrap_or("nothing")
                    ));
                }
                (format!("selected = {s}"), None)
            }
            Expectation::Mass { lo, hi } => {
                let m = self.ensure_results()?.model.total_mass();
                let check = units::format_check(Kind::Mass, m, *lo, *hi);
                if !within(m, *lo, *hi) {
                    return fail(format!("total mass {check}"));
                }
                (format!("mass {check}"), Some(units::shown(Kind::Mass, m)))
            }
            Expectation::Stat {
                stat,
                coord,
                quantity,
                lo,
                hi,
            } => {
                let r = self.ensure_results()?;
                let table = match quantity {
                    Quantity::Angle | Quantity::Velocity => &r.v,
                    Quantity::Acceleration => &r.a,
                    Quantity::Torque => &r.tau,
                };
                // an anatomical axis (`knee_l:flexion`) has an angle and a moment
                let anatomical = is_anatomical(&r, coord);
                if anatomical && matches!(quantity, Quantity::Velocity | Quantity::Acceleration) {
                    return Err(err(format!(
                        "{coord} is an anatomical axis: it has an angle and a moment (torque), \
                         not a {}",
                        quantity.name()
                    )));
                }
                let j = if anatomical {
                    0
                } else {
                    table.col_index(coord).ok_or_else(|| {
                        err(format!(
                            "no coordinate '{coord}' (expected e.g. {})",
                            table.names.first().map_or("", String::as_str)
                        ))
                    })?
                };
                // the coordinate's own unit: a rotation's angle in deg, a translation's in m
                let angular = anatomical
                    || r.model
                        .v_index(coord)
                        .is_some_and(|k| r.model.is_angular(k));
                let kind = quantity.kind(angular);
                let what = format!(
                    "the {} of {coord} (a {})",
                    quantity.name(),
                    if angular { "rotation" } else { "translation" }
                );
                let bound = |m: &Measure| {
                    m.to_si(&m.written(), kind, Bare::Shown, &what)
                        .map_err(|e| err(e.to_string()))
                };
                let (lo, hi) = (bound(lo)?, bound(hi)?);
                if hi < lo {
                    return Err(err(format!(
                        "between {} {}: HI is below LO",
                        units::format_value(kind, lo),
                        units::format_value(kind, hi)
                    )));
                }
                // angles of ball and free joints: rotation-vector components (angle_series)
                let x = match quantity {
                    Quantity::Angle => angle_series(&r, coord)
                        .ok_or_else(|| err(format!("no angle for '{coord}'")))?,
                    Quantity::Torque if anatomical => torque_series(&r, coord)
                        .ok_or_else(|| err(format!("no moment for '{coord}'")))?,
                    _ => table.column(j),
                };
                // accelerations and torques: never of the frames left out (issue 14)
                let forces = matches!(quantity, Quantity::Acceleration | Quantity::Torque);
                let quoted: Vec<f64> = x
                    .iter()
                    .enumerate()
                    .filter(|&(k, _)| !forces || r.quoted(k))
                    .map(|(_, v)| *v)
                    .collect();
                let value = match stat {
                    Statistic::Now => x.get(self.frame).copied().unwrap_or(0.0),
                    _ if quoted.is_empty() => {
                        return Err(err(format!(
                            "{coord}: every frame is left out of the quoted figures (edge                              frames or residuals beyond the feet; `set edges include` quotes                              the edges)"
                        )));
                    }
                    _ => statistic(*stat, &quoted),
                };
                let name = format!(
                    "{} {coord} {}",
                    format!("{stat:?}").to_lowercase(),
                    quantity.name()
                );
                let check = units::format_check(kind, value, lo, hi);
                if !within(value, lo, hi) {
                    return fail(format!("{name} {check}"));
                }
                (format!("{name} {check}"), Some(units::shown(kind, value)))
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
                (format!("message contains '{text}'"), None)
            }
            Expectation::ScreenContains(_) => {
                return Err(err("expect screen needs a front end (the TUI)"));
            }
        };
        let mut outcome = self.say(format!("ok: {msg}"));
        outcome.value = found;
        Ok(outcome)
    }
}

/// True for a `.csv` path (anything else is written as SVG).
fn is_csv(p: &Path) -> bool {
    p.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"))
}

/// The paper's figure 4 for one coordinate: its angle (deg) or position (m) and its torque
/// over time, minimum and maximum marked.
pub fn selection_svg(r: &Analysis, coord: &str) -> Result<String, SessionError> {
    let (Some(q), Some(tau)) = (angle_series(r, coord), torque_series(r, coord)) else {
        return Err(err(format!("no coordinate '{coord}' in the model")));
    };
    let rotation = r.model.v_index(coord).is_none_or(|k| r.model.is_angular(k));
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
    let torque = [Series::new(coord, r.time.clone(), tau)];
    // the frames whose forces are not quoted (edge frames, residuals beyond the feet)
    let half = r
        .time
        .get(1)
        .zip(r.time.first())
        .map_or(0.0, |(b, a)| (b - a) / 2.0);
    let shaded: Vec<(f64, f64)> = r
        .left_out_runs()
        .iter()
        .map(|&(a, b, _)| (r.time[a] - half, r.time[b] + half))
        .collect();
    let title_a = format!("{coord} {}", angle_label.split(' ').next().unwrap_or(""));
    let title_t = format!("{coord} {}", torque_label.split(' ').next().unwrap_or(""));
    let panels = [
        Panel {
            title: &title_a,
            x_label: "time (s)",
            y_label: angle_label,
            series: &angle,
            mark_min_max: true,
            shaded: &[],
            shaded_label: "",
        },
        Panel {
            title: &title_t,
            x_label: "time (s)",
            y_label: torque_label,
            series: &torque,
            mark_min_max: true,
            shaded: &shaded,
            shaded_label: "not quoted (edge/feet)",
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

/// The BVH (or robot) joint that velocity coordinate `k` belongs to: the joint name of its
/// body, without the `.Xrotation` of an euler-model channel body.
fn joint_of(model: &Model, k: usize) -> &str {
    let name = model.joint_names[model.body_of_v(k)].as_str();
    match name.rsplit_once('.') {
        Some((j, c)) if crate::io::bvh::Channel::ALL.iter().any(|ch| ch.name() == c) => j,
        _ => name,
    }
}

/// The joint of a selection in results `r`: the BVH joint at an anatomical joint's centre
/// (`knee_l:flexion` → `LeftLeg`), the joint of a coordinate of the model.
fn joint_of_selection(r: &Analysis, sel: &str) -> Option<String> {
    if is_anatomical(r, sel) {
        let joint = sel.split(':').next()?;
        return r
            .anatomy_joints
            .iter()
            .find(|(a, _)| a == joint)
            .map(|(_, j)| j.clone());
    }
    joint_of_name(&r.model, sel)
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

/// The angle (rad) or position (m) of velocity coordinate `coord` over the take: the q column
/// of a 1-DoF joint; for a ball joint (and the rotation of a free joint) the component of the
/// rotation vector `θ·u = log(q)` in the joint frame named by the coordinate (`J:wx` → x), whose
/// derivative is the angular velocity `J:wx` for rotations about a fixed axis; for the
/// translation of a free joint (`J:vx`) its position `J:x` in the parent frame.
pub fn angle_series(r: &Analysis, coord: &str) -> Option<Vec<f64>> {
    if let Some(j) = r.q.col_index(coord) {
        return Some(r.q.column(j));
    }
    if let Some(j) = r.anatomy.col_index(&format!("{coord}:angle")) {
        return Some(r.anatomy.column(j));
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
        .filter(|c| r.model.v_index(c).is_some_and(|k| r.model.is_angular(k)))
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

/// The generalized force of coordinate `coord` (N·m, N), or the net moment about an
/// anatomical axis (`knee_l:flexion`, N·m, signed as `pipeline::anatomy` signs it).
pub fn torque_series(r: &Analysis, coord: &str) -> Option<Vec<f64>> {
    if let Some(j) = r.tau.col_index(coord) {
        return Some(r.tau.column(j));
    }
    let j = r.anatomy.col_index(&format!("{coord}:moment"))?;
    Some(r.anatomy.column(j))
}

/// The selected coordinate's mirror in the results, whose angle is known: the same name with
/// left and right swapped in the joint's name, as exporters write them (`knee_l` / `knee_r`,
/// `LeftLeg` / `RightLeg`, `lThigh` / `rThigh`, `Foot_L` / `Foot_R`, `thigh.L` / `thigh.R`,
/// `mHipLeft` / `mHipRight`, `L_Knee` / `R_Knee`). `None` when no swap names a coordinate.
pub fn mirror_coord(r: &Analysis, coord: &str) -> Option<String> {
    mirror_names(coord)
        .into_iter()
        .find(|m| m != coord && angle_series(r, m).is_some())
}

/// The names `coord` may have on the other side: each way of writing left and right swapped.
pub fn mirror_names(coord: &str) -> Vec<String> {
    // the joint's part: before the coordinate's separator (`.` before a channel, `:` before an
    // anatomical axis); a name's own `.L` / `.R` stays in the joint part
    let (joint, rest) = match coord.rfind([':', '.']) {
        Some(i) if !matches!(&coord[i..], ".L" | ".R" | ".l" | ".r") => coord.split_at(i),
        _ => (coord, ""),
    };
    const PAIRS: [(&str, &str); 12] = [
        ("Left", "Right"),
        ("left", "right"),
        ("LEFT", "RIGHT"),
        ("_l", "_r"),
        ("_L", "_R"),
        (".L", ".R"),
        (".l", ".r"),
        ("L_", "R_"),
        ("l_", "r_"),
        ("Lf", "Rt"),
        ("l", "r"),
        ("L", "R"),
    ];
    let mut out = vec![];
    for (a, b) in PAIRS {
        for (from, to) in [(a, b), (b, a)] {
            // a one-letter side is a prefix (`lThigh`, `LHipJoint`), the others anywhere
            let swapped = if from.len() == 1 {
                joint
                    .strip_prefix(from)
                    .filter(|t| t.starts_with(|c: char| c.is_uppercase()))
                    .map(|t| format!("{to}{t}"))
            } else if joint.contains(from) {
                Some(joint.replacen(from, to, 1))
            } else {
                None
            };
            if let Some(j) = swapped {
                out.push(format!("{j}{rest}"));
            }
        }
    }
    out
}

/// Whether `coord` is an anatomical axis of the results (`knee_l:flexion`).
pub fn is_anatomical(r: &Analysis, coord: &str) -> bool {
    r.anatomy.col_index(&format!("{coord}:angle")).is_some()
}

/// The anatomical axis a name means: `knee_l` → `knee_l:flexion`, `knee_l:adduction` as it is.
fn anatomical_axis(r: &Analysis, name: &str) -> Option<String> {
    [name.to_string(), format!("{name}:flexion")]
        .into_iter()
        .find(|c| is_anatomical(r, c))
}
