//! Jobs: the long commands' computations, prepared by [`Workbench::prepare`](super::Workbench::prepare),
//! run on any thread ([`Job::run`]) and stored by [`Workbench::finish`](super::Workbench::finish).

use super::super::SessionError;
use super::super::command::{Command, ExportKind, RunKind};
use super::super::engine::{Analysis, Control, Engine, Params, STAGE_COUNT, Take};
use super::{
    coords_of_joint, err, image_format, is_csv, joint_of, joint_of_selection, loaded_message,
    resolve_in, results_csv, selection_chart, selection_for, torque_series,
};
use crate::model::{JointKind, Model};
use crate::pipeline::consistency::Consistency;
use crate::pipeline::{PerJoint, TakeOptions};
use crate::report::chart::ImageFormat;
use crate::report::knee::{self, MassRun};
use crate::report::motor::{self, JointMotion};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// What a [`Job`] computes: the commands whose work can take longer than a frame on a big
/// take (parsing, building the model, smoothing, inverse dynamics, simulation, charts).
#[derive(Debug, Clone)]
pub(super) enum Task {
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
    /// `report gait PATH`.
    ReportGait { out: PathBuf },
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
    pub(super) task: Task,
    pub(super) label: String,
    pub(super) engine: Arc<dyn Engine>,
    /// The active take.
    pub(super) take: Option<Take>,
    pub(super) params: Params,
    /// Inverse-dynamics results valid under `params`, if the workbench had them.
    pub(super) fresh: Option<Arc<Analysis>>,
    /// The latest inverse-dynamics results of the take, even stale: what an edit keeps of
    /// them is reused ([`Engine::inverse_dynamics_after`]).
    pub(super) previous: Option<Arc<Analysis>>,
    /// The simulation valid under `params`, if any (`export bvh sim`).
    pub(super) sim: Option<Arc<Analysis>>,
    pub(super) selection: Option<String>,
    pub(super) motor_classes: Vec<motor::MotorClass>,
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
pub(super) enum Output {
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
    /// `compare weights`: its file written, and its curves for the workbench.
    Compared {
        comparison: super::Comparison,
        path: PathBuf,
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
    pub(super) label: String,
    /// Name of the take that was active when the job was prepared.
    pub(super) take: Option<String>,
    pub(super) params: Params,
    /// Inverse-dynamics results the job computed on the way (for an export, a report, an
    /// expect); kept as `run id` keeps its results.
    pub(super) analysis: Option<Arc<Analysis>>,
    pub(super) output: Result<Output, SessionError>,
    /// How many times each pipeline stage ran (`Stage as usize`).
    pub(super) stage_runs: [u32; STAGE_COUNT],
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
            stage_runs: ctl.stage_runs(),
        }
    }

    /// For a recompute of inverse dynamics after an edit of the masses alone: a preview of its
    /// results ([`Engine::preview_after`]), shown until [`run`](Self::run)'s replace them
    /// ([`Workbench::show_preview`](super::Workbench::show_preview)). `None` for other jobs
    /// and edits. Its stage runs are not counted.
    pub fn preview(&self, ctl: &Control) -> Option<JobResult> {
        if !self.is_inverse_dynamics() || self.fresh.is_some() {
            return None;
        }
        let take = self.take.as_ref()?;
        // the preview reports no progress: the bar is the results proper's
        ctl.set_span(0.0, 0.0);
        let r = self
            .engine
            .preview_after(take, &self.params, self.previous.as_deref(), ctl);
        ctl.forget_stage_runs();
        ctl.set_span(0.0, 1.0);
        Some(JobResult {
            label: self.label.clone(),
            take: Some(take.name.clone()),
            params: self.params.clone(),
            analysis: None,
            output: Ok(Output::Run(RunKind::Id, Arc::new(r?))),
            stage_runs: [0; STAGE_COUNT],
        })
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
        let r = Arc::new(self.inverse_dynamics(take, &self.params, ctl)?);
        ctl.set_span(upto, 1.0);
        *analysis = Some(r.clone());
        Ok(r)
    }

    /// Inverse dynamics of `take` under `params`, after the workbench's latest results.
    fn inverse_dynamics(
        &self,
        take: &Take,
        params: &Params,
        ctl: &Control,
    ) -> Result<Analysis, SessionError> {
        let previous = self.previous.as_deref();
        Ok(self
            .engine
            .inverse_dynamics_after(take, params, previous, ctl)?)
    }

    /// [`inverse_dynamics`](Self::inverse_dynamics) whose residual reduction starts cold: a
    /// batch over settings (`compare weights`) gives the same results whatever the session
    /// computed before it.
    fn inverse_dynamics_cold_reduction(
        &self,
        take: &Take,
        params: &Params,
        ctl: &Control,
    ) -> Result<Analysis, SessionError> {
        let previous = self.previous.as_deref().map(|p| Analysis {
            reduction: None,
            ..p.clone()
        });
        Ok(self
            .engine
            .inverse_dynamics_after(take, params, previous.as_ref(), ctl)?)
    }

    /// The selection once `analysis` (computed by this job) is stored ([`selection_for`]).
    fn selection(&self, analysis: &Option<Arc<Analysis>>) -> Option<String> {
        match analysis {
            Some(r) => selection_for(r, self.selection.as_deref()),
            None => self.selection.clone(),
        }
    }

    /// The task's computation, one function per kind.
    fn compute(
        &self,
        ctl: &Control,
        analysis: &mut Option<Arc<Analysis>>,
    ) -> Result<Output, SessionError> {
        ctl.check()?;
        match &self.task {
            Task::Run(kind) => {
                let take = self.take()?;
                let r = match kind {
                    RunKind::Id => self.inverse_dynamics(take, &self.params, ctl)?,
                    RunKind::Sim => self.engine.simulate(take, &self.params, ctl)?,
                };
                Ok(Output::Run(*kind, Arc::new(r)))
            }
            Task::Load { file, name } => self.load(ctl, file, name.as_deref()),
            Task::Motion { file, index, model } => self.motion(ctl, file, *index, model),
            Task::Trajectory {
                index,
                poses,
                duration_s,
                rate_hz,
            } => self.trajectory(ctl, *index, poses, *duration_s, *rate_hz),
            Task::Scene { file, in_dir } => self.scene(ctl, file, in_dir),
            Task::Blend { a, b, window } => self.blend(ctl, a, b, *window),
            Task::Export { kind, out } => self.export(ctl, analysis, *kind, out),
            Task::Compare { masses, coord, out } => self.compare(ctl, masses, coord, out),
            Task::ReportMotor { out, curves } => self.report_motor(ctl, analysis, out, *curves),
            Task::ReportGait { out } => self.report_gait(ctl, out),
            Task::Then(cmd) => {
                self.results(ctl, analysis, 1.0)?;
                Ok(Output::Then(cmd.clone()))
            }
        }
    }

    /// `load PATH [as NAME]` of a take, a DH table or a URDF.
    fn load(&self, ctl: &Control, file: &Path, name: Option<&str>) -> Result<Output, SessionError> {
        let mut take = self.engine.load(file, &self.params)?;
        if let Some(n) = name {
            take.name = n.to_string();
        }
        ctl.check()?;
        Ok(Output::Take {
            message: loaded_message(&take),
            take: Box::new(take),
            blended: false,
        })
    }

    /// `load STATES.csv`: the motion of robot `index`.
    fn motion(
        &self,
        ctl: &Control,
        file: &Path,
        index: usize,
        model: &Model,
    ) -> Result<Output, SessionError> {
        let states = self.engine.load_motion(model, file)?;
        ctl.check()?;
        let take = self.take()?.name.clone();
        let message = format!(
            "{take}: motion from {} ({} samples)",
            file.display(),
            states.len()
        );
        Ok(Output::Motion {
            index,
            take,
            states,
            source: file.display().to_string(),
            message,
        })
    }

    /// `trajectory …`: quintic moves between poses, the motion of robot `index`.
    fn trajectory(
        &self,
        ctl: &Control,
        index: usize,
        poses: &[Vec<f64>],
        duration_s: f64,
        rate_hz: f64,
    ) -> Result<Output, SessionError> {
        let states = super::super::trajectory::quintic_moves(poses, duration_s, rate_hz)?;
        ctl.check()?;
        let source = format!(
            "{} quintic move(s) of {duration_s} s at {rate_hz} Hz",
            poses.len().saturating_sub(1).max(1)
        );
        let take = self.take()?.name.clone();
        let message = format!("{take}: {source} ({} samples)", states.len());
        Ok(Output::Motion {
            index,
            take,
            states,
            source,
            message,
        })
    }

    /// `scene PATH`: its options and gains, its takes read as `load` reads them.
    fn scene(&self, ctl: &Control, file: &Path, in_dir: &Path) -> Result<Output, SessionError> {
        let sc = crate::io::scene::read(file)?;
        let options =
            TakeOptions::from_scene(&sc).map_err(|e| err(format!("{}: {e}", file.display())))?;
        let mut p = self.params.clone();
        p.take = options.clone();
        // the takes, as `load` reads them, one span of the progress each
        let n = sc.takes.len().max(1) as f64;
        let mut takes = vec![];
        for (i, t) in sc.takes.iter().enumerate() {
            ctl.set_span(i as f64 / n, (i + 1) as f64 / n);
            ctl.check()?;
            takes.push(self.engine.load(&resolve_in(in_dir, t), &p)?);
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

    /// `blend A B T0:T1`.
    fn blend(
        &self,
        ctl: &Control,
        a: &Take,
        b: &Take,
        window: (f64, f64),
    ) -> Result<Output, SessionError> {
        let t = self.engine.blend(a, b, window)?;
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

    fn export(
        &self,
        ctl: &Control,
        analysis: &mut Option<Arc<Analysis>>,
        kind: ExportKind,
        out: &Path,
    ) -> Result<Output, SessionError> {
        match kind {
            ExportKind::Csv => {
                // an OpenSim name would get CSV text: say what writes OpenSim's tables
                let ext = out.extension().and_then(|e| e.to_str()).unwrap_or("");
                if ["sto", "mot"].iter().any(|x| ext.eq_ignore_ascii_case(x)) {
                    return Err(err(format!(
                        "export csv {}: export csv writes CSV; OpenSim's .{ext} is written by \
                         export states|grf|id PATH.{ext} (id: the torques)",
                        out.display()
                    )));
                }
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
                    known_units: &[],
                    consistency: r.consistency.as_deref(),
                };
                crate::pipeline::summary::write_sidecar(out, &p)?;
            }
            ExportKind::Svg | ExportKind::Png => {
                let r = self.results(ctl, analysis, 0.8)?;
                let coord = self
                    .selection(analysis)
                    .ok_or_else(|| err("export svg|png: select a joint first"))?;
                let format = if kind == ExportKind::Png {
                    ImageFormat::Png
                } else {
                    ImageFormat::Svg
                };
                let bytes = selection_chart(&r, &coord, Some(&self.caption_of(&r)), format)?;
                ctl.check()?;
                crate::report::chart::write_chart(out, &bytes)?;
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
            ExportKind::States
            | ExportKind::Trc
            | ExportKind::Grf
            | ExportKind::Gltf
            | ExportKind::Id => {
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

    /// Which of `joint`'s drive parameters `[gear, Km, η]` are the defaults: set neither for
    /// the joint (`set motor.<joint>.…`) nor for every joint (`set motor.…`).
    fn drive_defaults(&self, joint: &str) -> [bool; 3] {
        let o = self
            .params
            .motor_joint
            .get(joint)
            .copied()
            .unwrap_or_default();
        let (m, d) = (&self.params.motor, Params::default().motor);
        [
            o.gear.is_none() && m.gear_ratio == d.gear_ratio,
            o.km.is_none() && m.km_nm_per_a == d.km_nm_per_a,
            o.efficiency.is_none() && m.efficiency == d.efficiency,
        ]
    }

    /// A chart's caption: the take, the body (mass, the skeleton's height, sex), joint model,
    /// smoothing, contact model and residual reduction as computed, and with contact the
    /// take's residual figures against Hicks et al.'s thresholds (`consistency`, issue 14:
    /// the moments are read with them), or the robot's own model; `scale` the take's length
    /// scale (m per file unit), `masses` the body masses compared (none: the one set).
    fn caption(
        &self,
        scale: f64,
        masses: Option<&[f64]>,
        consistency: Option<&Consistency>,
    ) -> String {
        let t = &self.params.take;
        let mut parts: Vec<(&str, String)> = vec![];
        if let Some(take) = self.take.as_ref() {
            let file = Path::new(&take.source).file_name();
            let name = file.map_or_else(|| take.source.clone(), |f| f.to_string_lossy().into());
            parts.push(("take", name));
            if let Some(bvh) = take.bvh() {
                let up = t.up.unwrap_or_else(|| crate::io::bvh::detect_up(bvh));
                let height = t
                    .stature_m
                    .unwrap_or_else(|| crate::io::bvh::stature(bvh, up) * scale);
                let mass = masses.map_or_else(
                    || t.body.mass_kg.to_string(),
                    |m| m.iter().map(f64::to_string).collect::<Vec<_>>().join(", "),
                );
                parts.push(("body", format!("{mass} kg, {height:.2} m, {}", t.body.sex)));
                parts.push(("joints", t.joints.to_string()));
                let smooth = t.smooth.as_ref().map_or_else(
                    || {
                        format!(
                            "default ({})",
                            crate::pipeline::default_smoothing(bvh.frame_time).0
                        )
                    },
                    |s| s.to_string(),
                );
                parts.push(("smoothing", smooth));
                parts.push(("contact", t.contact.to_string()));
                let consistent = match self.params.consistent {
                    None => "auto",
                    Some(true) => "on",
                    Some(false) => "off",
                };
                parts.push(("residual reduction", consistent.into()));
                parts.extend(
                    consistency
                        .map(Consistency::caption_parts)
                        .unwrap_or_default(),
                );
            } else {
                parts.push(("model", "the robot's own masses and inertias".into()));
            }
        }
        crate::report::chart::caption(&parts)
    }

    /// [`caption`](Self::caption) of results `r`: their take's scale and consistency.
    fn caption_of(&self, r: &Analysis) -> String {
        self.caption(r.scale, None, r.consistency.as_deref())
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
        let mut kind = super::super::units::Kind::Torque;
        let mut scale = 1.0;
        let mut model = None; // the coordinates' model, for the sidecar's units
        let mut column = "tau"; // a model coordinate's torque, or an anatomical axis's moment
        for (i, &mass_kg) in masses.iter().enumerate() {
            ctl.set_span(i as f64 / n, (i + 1) as f64 / n);
            let mut params = self.params.clone();
            params.take.body.mass_kg = mass_kg;
            let r = self.inverse_dynamics_cold_reduction(take, &params, ctl)?;
            scale = r.scale;
            let tau = torque_series(&r, coord)
                .ok_or_else(|| err(format!("no coordinate '{coord}' in the model")))?;
            model = Some(r.model.clone());
            if r.tau.col_index(coord).is_none() {
                column = "moment";
            }
            let angular = r.model.v_index(coord).is_none_or(|k| r.model.is_angular(k));
            kind = super::super::command::Quantity::Torque.kind(angular);
            runs.push(MassRun {
                mass_kg,
                tau,
                quoted: (0..r.time.len()).map(|k| r.quoted(k)).collect(),
                residual_pct: r.consistency.as_ref().map(|c| {
                    let f = c.last();
                    (f.force_pct(), f.moment_pct())
                }),
                t: r.time,
            });
        }
        let bytes = if is_csv(out) {
            knee::curves_csv(column, coord, &runs)?.into_bytes()
        } else {
            let caption = self.caption(scale, Some(masses), None);
            knee::knee_chart(coord, &runs, Some(&caption), image_format(out))?
        };
        ctl.check()?;
        crate::io::write_atomic(out, &bytes)?;
        if is_csv(out) {
            super::table_sidecar(out, "compare weights", model.as_deref())?;
        }
        let message = format!(
            "compared {coord} torque at {} kg: wrote {} (set overlay weights draws them)",
            masses
                .iter()
                .map(|m| m.to_string())
                .collect::<Vec<_>>()
                .join(", "),
            out.display()
        );
        let comparison = super::Comparison {
            coord: coord.to_string(),
            kind,
            runs: runs.into_iter().map(|r| (r.mass_kg, r.tau)).collect(),
        };
        Ok(Output::Compared {
            comparison,
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
                qdd: r.a.column(k),
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
        let bytes = match (curves, is_csv(out)) {
            (true, true) => motor::motor_curves_csv(&joints, &specs)?.into_bytes(),
            (true, false) => {
                return Err(err("report motor curves: the curves are written as .csv"));
            }
            (false, true) => motor::motor_table_csv(&loads)?.into_bytes(),
            (false, false) => {
                let caption = self.caption_of(&r);
                let defaults: Vec<[bool; 3]> = joints
                    .iter()
                    .map(|j| self.drive_defaults(&j.joint))
                    .collect();
                let format = image_format(out);
                motor::motor_chart(&joints, &specs, &loads, &defaults, Some(&caption), format)?
            }
        };
        ctl.check()?;
        crate::io::write_atomic(out, &bytes)?;
        // the tables' sidecar NAME.csv.json (the curves are always a CSV)
        if is_csv(out) {
            let command = if curves {
                "report motor curves"
            } else {
                "report motor"
            };
            super::table_sidecar(out, command, Some(m.as_ref()))?;
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

impl Job {
    /// The clinical gait view (report::gait) of the active take, as `articula anatomy` computes
    /// its moments: the session's take options, with ground contact the take made consistent
    /// unless `consistent off`.
    fn report_gait(&self, ctl: &Control, out: &Path) -> Result<Output, SessionError> {
        use crate::report::gait;
        let take = self.take()?;
        let bvh = take.bvh().ok_or_else(|| {
            err("report gait: the gait view needs a human take (BVH), not a robot")
        })?;
        let mut t = crate::pipeline::take_from_bvh_with(
            Path::new(&take.source),
            bvh.clone(),
            &self.params.take,
            &mut ctl.stage(0.0, 0.3),
        )?;
        crate::pipeline::resolve_contact(&mut t);
        ctl.check()?;
        let reduce = self.params.consistent.unwrap_or(true)
            && t.options.contact == crate::pipeline::Contact::Feet;
        let mut a = crate::pipeline::consistency::anatomy_consistent(&t, reduce)?;
        a.include_edges = self.params.include_edges;
        ctl.check()?;
        let caption = self.caption(t.scale_to_m, None, a.consistency.as_ref());
        let notes = gait::write_gait(&a, &t, Some(&caption), out)?;
        let mut message = format!("gait report: wrote {}", out.display());
        for n in notes {
            message.push_str("; ");
            message.push_str(&n);
        }
        Ok(Output::Wrote {
            path: out.to_path_buf(),
            message,
        })
    }
}
