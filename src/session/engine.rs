//! The computations the workbench asks for, behind one small trait so that the workbench does
//! not care which stage functions compute them ([`Engine`]), and the built-in engine over the
//! library ([`Builtin`]).
//!
//! Every engine call gets a [`Control`]: it reports progress (0‥1) and polls for
//! cancellation, so that the terminal UI can run it on a worker thread.

use super::command::ExportKind;
use crate::error::Error;
use crate::io::bvh::{Bvh, detect_up};
use crate::model::Model;
use crate::motion::blend::{Align, BlendOptions, TimeMap, WarpWindow};
use crate::pipeline::PerJoint;
use crate::pipeline::stages::Stage;
use crate::pipeline::{self, TakeOptions};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU32, AtomicU64, Ordering};

/// Progress and cancellation shared between a computation and whoever waits for it.
///
/// Progress is reported in 0‥1 of the current *span* ([`set_span`](Self::set_span)), a part
/// of the whole job: a job of several stages (a comparison re-running inverse dynamics at each
/// body mass) gives each stage its span, and the stage reports its own 0‥1 inside it. Every
/// field is an atomic: reporting allocates nothing and takes no lock.
#[derive(Debug)]
pub struct Control {
    cancel: AtomicBool,
    /// Progress of the whole job in parts per million.
    progress: AtomicU32,
    /// The current span: its start (high 32 bits) and end (low 32 bits) in parts per million.
    span: AtomicU64,
    /// How many times each pipeline stage ran (indexed by `Stage as usize`): what a
    /// recompute reran (issue 17 item 4), counted, not timed.
    stage_runs: [AtomicU32; STAGE_COUNT],
}

/// The number of [`Stage`]s.
pub const STAGE_COUNT: usize = pipeline::stages::STAGES.len();

impl Default for Control {
    fn default() -> Self {
        Self {
            cancel: AtomicBool::new(false),
            progress: AtomicU32::new(0),
            span: AtomicU64::new(PPM as u64),
            stage_runs: Default::default(),
        }
    }
}

/// Parts per million in one.
const PPM: u32 = 1_000_000;

fn ppm(f: f64) -> u32 {
    (f.clamp(0.0, 1.0) * f64::from(PPM)).round() as u32
}

impl Control {
    /// Asks the computation to stop at its next check.
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }
    /// True once [`cancel`](Self::cancel) was called.
    pub fn is_cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }
    /// Makes `from‥to` (parts of the whole job, 0‥1) the span that [`set_progress`]
    /// reports into, and moves the progress to `from`.
    ///
    /// [`set_progress`]: Self::set_progress
    pub fn set_span(&self, from: f64, to: f64) {
        let (a, b) = (ppm(from), ppm(to).max(ppm(from)));
        self.span
            .store((u64::from(a) << 32) | u64::from(b), Ordering::Relaxed);
        self.progress.store(a, Ordering::Relaxed);
    }
    /// The current span (0‥1 of the whole job).
    pub fn span(&self) -> (f64, f64) {
        let s = self.span.load(Ordering::Relaxed);
        let p = f64::from(PPM);
        (f64::from((s >> 32) as u32) / p, f64::from(s as u32) / p)
    }
    /// Records progress `f` in 0‥1 of the current span.
    pub fn set_progress(&self, f: f64) {
        let (from, to) = self.span();
        self.progress.store(
            ppm(from + (to - from) * f.clamp(0.0, 1.0)),
            Ordering::Relaxed,
        );
    }
    /// Progress of the whole job in 0‥1.
    pub fn progress(&self) -> f64 {
        f64::from(self.progress.load(Ordering::Relaxed)) / f64::from(PPM)
    }
    /// `Err(Cancelled)` once cancelled; engines call it in their loops.
    pub fn check(&self) -> Result<(), Error> {
        if self.is_cancelled() {
            Err(Error::Cancelled)
        } else {
            Ok(())
        }
    }
    /// Counts one run of stage `s` (the pipeline's `done(Stage)` callback).
    pub fn done(&self, s: Stage) {
        self.stage_runs[s as usize].fetch_add(1, Ordering::Relaxed);
    }
    /// How many times each stage ran so far, indexed by `Stage as usize`.
    pub fn stage_runs(&self) -> [u32; STAGE_COUNT] {
        std::array::from_fn(|i| self.stage_runs[i].load(Ordering::Relaxed))
    }
    /// A progress callback for the library's loops (`keep_going(f) -> bool`): reports `f`
    /// mapped onto `from‥to` of the current span, and returns false once cancelled.
    pub fn stage(&self, from: f64, to: f64) -> impl FnMut(f64) -> bool + '_ {
        move |f| {
            self.set_progress(from + (to - from) * f);
            !self.is_cancelled()
        }
    }
}

// the joint model, sex, contact model and smoothing are the pipeline's own types
pub use crate::model::anthropometry::Sex;
pub use crate::model::bvh::JointModel;
pub use crate::motion::smooth::SmoothSpec;
pub use crate::pipeline::{Contact, States};
pub use crate::report::motor::MotorSpec;

/// Per-joint changes to the drive of [`Params::motor`] (`set motor.<joint>.km …`); what is not
/// given comes from the common drive.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MotorOverride {
    /// Torque constant Km (N·m/A).
    pub km: Option<f64>,
    /// Gear ratio N (motor turns per joint turn).
    pub gear: Option<f64>,
    /// Gearbox efficiency η in (0, 1].
    pub efficiency: Option<f64>,
}

/// Everything the computations depend on besides the take. SI units.
#[derive(Debug, Clone, PartialEq)]
pub struct Params {
    /// How a BVH take becomes a model and states: the pipeline's own options (unit, stature,
    /// up, position semantics, joint model, body mass and sex, link masses, smoothing, locks,
    /// subtree, contact), exactly what the CLI's flags and `--scene` set. Robot models (DH,
    /// URDF) carry their own masses and use none of these.
    pub take: TakeOptions,
    /// Computed-torque gains (1/s², 1/s), diagonal: every coordinate's, and overrides by joint
    /// or coordinate name (`set kp.LeftLeg 800`).
    pub kp: PerJoint,
    pub kv: PerJoint,
    /// Integrator name (`euler`, `semi-implicit`, `rk4`, `dopri5`).
    pub integrator: String,
    /// Simulation step (s).
    pub dt: f64,
    /// Default blend window length (s).
    pub blend_window: f64,
    /// The drive of every joint for `report motor` (`set motor.km|gear|efficiency`).
    pub motor: MotorSpec,
    /// Per-joint drives, by coordinate name (`set motor.<joint>.km|gear|efficiency`).
    pub motor_joint: BTreeMap<String, MotorOverride>,
    /// Motor catalogue (TOML, see `data/motor_classes.toml`); `None`: the bundled one.
    pub motor_catalogue: Option<std::path::PathBuf>,
    /// Residual reduction with ground contact (`set consistent auto|on|off`, the CLI's
    /// `--consistent`): `None` is on with `contact feet`, as `articula anatomy`.
    pub consistent: Option<bool>,
    /// Quote the edge frames' accelerations and torques too (`set edges include`, the CLI's
    /// `anatomy --edges include`); by default they are [`LeftOut::Edge`].
    pub include_edges: bool,
    /// How `export bvh` and `export bvh sim` write the take (`set bvh_style portable|as-read`,
    /// the CLI's `--bvh-style`); nothing computed depends on it.
    pub bvh_style: crate::io::bvh::BvhStyle,
}

impl Default for Params {
    fn default() -> Self {
        Self {
            // the CLI's defaults: 75 kg male, euler joints, butterworth:6hz, contact auto
            take: TakeOptions::default(),
            kp: PerJoint::all(400.0),
            kv: PerJoint::all(40.0),
            integrator: "rk4".into(),
            dt: 0.001,
            blend_window: 0.5,
            motor: MotorSpec {
                km_nm_per_a: 0.1,
                gear_ratio: 100.0,
                efficiency: Some(1.0),
                rotor_inertia_kg_m2: 0.0,
            },
            motor_joint: BTreeMap::new(),
            motor_catalogue: None,
            consistent: None,
            include_edges: false,
            bvh_style: crate::io::bvh::BvhStyle::Portable,
        }
    }
}

impl Params {
    /// True when inverse-dynamics results computed under `other` are valid under `self`: the
    /// take's options, residual reduction and the quoted frames are the same (the gains,
    /// integrator and step are the simulation's; the motor drives and the blend window change
    /// neither; `keep_first_frame` acts when a take is read, on the takes loaded after it).
    pub fn same_inverse_dynamics(&self, other: &Params) -> bool {
        let read_only = |t: &TakeOptions| TakeOptions {
            keep_first_frame: false,
            ..t.clone()
        };
        read_only(&self.take) == read_only(&other.take)
            && self.consistent == other.consistent
            && self.include_edges == other.include_edges
    }

    /// True when a simulation computed under `other` is valid under `self` (the motor drives
    /// and the blend window do not change it).
    pub fn same_results(&self, other: &Params) -> bool {
        self.same_inverse_dynamics(other)
            && self.kp == other.kp
            && self.kv == other.kv
            && self.integrator == other.integrator
            && self.dt == other.dt
    }

    /// The drive of coordinate `joint`: its overrides over the common drive.
    pub fn motor_of(&self, joint: &str) -> MotorSpec {
        let o = self.motor_joint.get(joint).copied().unwrap_or_default();
        MotorSpec {
            km_nm_per_a: o.km.unwrap_or(self.motor.km_nm_per_a),
            gear_ratio: o.gear.unwrap_or(self.motor.gear_ratio),
            efficiency: o.efficiency.or(self.motor.efficiency),
            rotor_inertia_kg_m2: self.motor.rotor_inertia_kg_m2,
        }
    }
}

/// A robot arm (DH table or URDF) and the motion it is analysed over.
#[derive(Debug, Clone)]
pub struct Robot {
    pub model: Arc<Model>,
    /// `DH table` or `URDF`.
    pub kind: &'static str,
    /// Joint-space motion (a states CSV or a generated trajectory); `None` until given.
    pub motion: Option<Arc<States>>,
    /// Where the motion came from, for messages.
    pub motion_source: String,
}

/// What a loaded take holds: a motion-capture take, or a robot model with its motion.
#[derive(Debug, Clone)]
pub enum TakeData {
    Bvh(Arc<Bvh>),
    Robot(Robot),
}

/// A loaded take: a short name, its source and its data.
#[derive(Debug, Clone)]
pub struct Take {
    pub name: String,
    /// Where it came from (a path, or `demo:walk`).
    pub source: String,
    pub data: TakeData,
    /// What the pipeline assumed or changed when the take was loaded (`pipeline::Take::notes`:
    /// a scale, a smoothing, a dropped rest frame, …), for the load message.
    pub notes: Vec<String>,
}

impl Take {
    /// The BVH take, if this is one.
    pub fn bvh(&self) -> Option<&Bvh> {
        match &self.data {
            TakeData::Bvh(b) => Some(b),
            TakeData::Robot(_) => None,
        }
    }
    /// The robot, if this is one.
    pub fn robot(&self) -> Option<&Robot> {
        match &self.data {
            TakeData::Robot(r) => Some(r),
            TakeData::Bvh(_) => None,
        }
    }
    /// Number of frames (samples of a robot's motion; 0 without one).
    pub fn frames(&self) -> usize {
        match &self.data {
            TakeData::Bvh(b) => b.frames,
            TakeData::Robot(r) => r.motion.as_ref().map_or(0, |m| m.len()),
        }
    }
    /// Time between frames (s); a robot's first sampling interval (1 without a motion).
    pub fn frame_time(&self) -> f64 {
        match &self.data {
            TakeData::Bvh(b) => b.frame_time,
            TakeData::Robot(r) => r
                .motion
                .as_ref()
                .and_then(|m| Some(m.time.get(1)? - m.time.first()?))
                .filter(|dt| *dt > 0.0)
                .unwrap_or(1.0),
        }
    }
    /// The joints in tree order with their depths: BVH joints, or the robot's joints.
    pub fn joint_tree(&self) -> Vec<(String, usize)> {
        match &self.data {
            TakeData::Bvh(b) => {
                let mut depth = vec![0usize; b.joints.len()];
                b.joints
                    .iter()
                    .enumerate()
                    .map(|(i, j)| {
                        depth[i] = j.parent.map_or(0, |p| depth[p] + 1);
                        (j.name.clone(), depth[i])
                    })
                    .collect()
            }
            TakeData::Robot(r) => {
                // joints that move (fixed URDF joints have no coordinate), depth counted in
                // moving ancestors
                let m = &r.model;
                let mut depth = vec![0usize; m.nbodies()];
                let mut out = vec![];
                for i in 1..m.nbodies() {
                    let p = m.parent[i];
                    let moving = m.joints[i].nv() > 0;
                    let below = if p > 0 && m.joints[p].nv() > 0 {
                        depth[p] + 1
                    } else {
                        depth[p]
                    };
                    depth[i] = below;
                    if moving {
                        out.push((m.joint_names[i].clone(), below));
                    }
                }
                out
            }
        }
    }
}

/// The ground contact's verdicts in a few words: how often the foot gives the force the
/// motion needs in single support (its centre of pressure within `COP_GAP_TOLERANCE` of the
/// foot), and whether the residuals meet Hicks et al.'s thresholds.
fn contact_brief(q: &crate::dynamics::grf::GroundQuality, meets: bool) -> String {
    let feet = if q.single_support_frames == 0 {
        "contact: no single support".to_string()
    } else {
        format!(
            "feet give the force in {:.0} % of single support",
            100.0 * (1.0 - q.outside_share())
        )
    };
    let residuals = if meets { "within" } else { "beyond" };
    format!("{feet}; residuals {residuals} Hicks et al.")
}

/// The anatomical angles (rad) and moments (N·m) of a human take as a table
/// ([`Analysis::anatomy`]); empty for a take that is not a human's, or whose segments have no
/// frame somewhere (the inverse dynamics stands without them).
fn anatomy_table(a: Result<pipeline::anatomy::Anatomy, Error>) -> Table {
    let Ok(a) = a else {
        return Table::zeros(vec![], 0);
    };
    let keep: Vec<(usize, String, f64)> = a
        .names
        .iter()
        .enumerate()
        .filter_map(|(i, n)| {
            if let Some(b) = n.strip_suffix(":angle") {
                Some((i, format!("{b}:angle"), 1f64.to_radians()))
            } else {
                n.strip_suffix(":moment")
                    .map(|b| (i, format!("{b}:moment"), 1.0))
            }
        })
        .collect();
    let frames = a.time.len();
    let mut out = Table::zeros(keep.iter().map(|k| k.1.clone()).collect(), frames);
    for k in 0..frames {
        let row = out.row_mut(k);
        for (c, (i, _, f)) in keep.iter().enumerate() {
            row[c] = a.columns[*i][k] * f;
        }
    }
    out
}

/// A per-frame table: `frames × names.len()` values, row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    pub names: Vec<String>,
    pub data: Vec<f64>,
}

impl Table {
    /// An all-zero table.
    pub fn zeros(names: Vec<String>, frames: usize) -> Self {
        let data = vec![0.0; frames * names.len()];
        Self { names, data }
    }
    /// Number of columns.
    pub fn cols(&self) -> usize {
        self.names.len()
    }
    /// Number of rows (frames).
    pub fn rows(&self) -> usize {
        self.data.len().checked_div(self.cols()).unwrap_or(0)
    }
    /// Row `k`.
    pub fn row(&self, k: usize) -> &[f64] {
        &self.data[k * self.cols()..(k + 1) * self.cols()]
    }
    /// Row `k`, mutable.
    pub fn row_mut(&mut self, k: usize) -> &mut [f64] {
        let c = self.cols();
        &mut self.data[k * c..(k + 1) * c]
    }
    /// Index of the column called `name`.
    pub fn col_index(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }
    /// Column `j` as a vector.
    pub fn column(&self, j: usize) -> Vec<f64> {
        (0..self.rows()).map(|k| self.row(k)[j]).collect()
    }
}

/// The results of inverse dynamics over a take.
#[derive(Debug, Clone)]
pub struct Analysis {
    pub model: Arc<Model>,
    /// Time of each frame (s).
    pub time: Vec<f64>,
    /// Configuration per frame (`nq` columns, rad / m).
    pub q: Table,
    /// Velocity (`nv` columns, rad/s, m/s).
    pub v: Table,
    /// Acceleration (`nv` columns, rad/s², m/s²).
    pub a: Table,
    /// Generalized forces (`nv` columns, N·m / N).
    pub tau: Table,
    /// Metres per file unit used for the take.
    pub scale: f64,
    /// A one-line summary for messages (a simulation's tracking error), or empty.
    pub note: String,
    /// [`note`](Self::note) in a few words for a status line (`feet give the force in 88 % of
    /// single support; residuals within Hicks et al.`), or empty.
    pub brief: String,
    /// A human take's anatomical series (`pipeline::anatomy`): `<joint>:<axis>:angle` (rad)
    /// and `<joint>:<axis>:moment` (N·m) per frame, `knee_l:flexion:angle`; empty otherwise.
    pub anatomy: Table,
    /// Per frame, why its accelerations and torques are not quoted (issue 14: peaks, minima,
    /// maxima and the charts' markers leave these frames out, the charts shade them); `None`
    /// for a frame that is. Empty: every frame is quoted.
    pub left_out: Vec<Option<LeftOut>>,
    /// A human take's anatomical joints and the BVH joint at each one's centre (`knee_l` →
    /// `LeftLeg`), from the landmarks the take's human was found by; empty otherwise.
    pub anatomy_joints: Vec<(String, String)>,
    /// With ground contact: each foot's vertical ground force per frame (N, up positive),
    /// columns named by foot (`left`, `right`); empty otherwise.
    pub feet: Table,
    /// A simulation's reference: the configurations it tracked (`nq` columns, as `q`); empty
    /// for inverse dynamics.
    pub reference: Table,
    /// The pipeline's take these results were computed from (a BVH take's model and smoothed
    /// states, before contact), so that an edit that keeps its states reuses them
    /// ([`pipeline::take_from_bvh_reusing`]); `None` for a robot or a simulation.
    pub source: Option<Arc<pipeline::Take>>,
    /// A human take's anatomical calibration (segment frames and kept poses: what masses do
    /// not change, `pipeline::anatomy::Calibration`), reused by an edit whose take has the
    /// same kinematics; `None` otherwise.
    pub calibration: Option<Arc<pipeline::anatomy::Calibration>>,
    /// What `contact auto` settled on for [`source`](Self::source) and why
    /// (`pipeline::resolve_contact_after`), reused by an edit of masses alone; `None` when the
    /// contact was not `auto`.
    pub contact_auto: Option<(pipeline::Contact, String)>,
}

/// Why a frame's accelerations and torques are left out of the figures quoted from them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LeftOut {
    /// Within the smoothing's reach of the take's ends, where the smoothed accelerations see
    /// past the take (`pipeline::edge_frames`); quoted with `set edges include`.
    Edge,
    /// The residuals stay beyond Hicks et al.'s thresholds: the motion needs a force the feet
    /// cannot give (`pipeline::consistency`, the CSV column `residual:beyond`).
    Beyond,
}

impl LeftOut {
    /// A short name for messages and legends.
    pub fn name(self) -> &'static str {
        match self {
            LeftOut::Edge => "edge",
            LeftOut::Beyond => "beyond the feet",
        }
    }
}

impl Analysis {
    /// Whether frame `k`'s accelerations and torques are quoted (not [`left_out`](Self::left_out)).
    pub fn quoted(&self, k: usize) -> bool {
        self.left_out.get(k).is_none_or(Option::is_none)
    }

    /// The runs of frames left out, as `(first, last, why)` with `first..=last` one reason.
    pub fn left_out_runs(&self) -> Vec<(usize, usize, LeftOut)> {
        let mut runs: Vec<(usize, usize, LeftOut)> = vec![];
        for (k, w) in self.left_out.iter().enumerate() {
            let Some(w) = *w else { continue };
            match runs.last_mut() {
                Some(r) if r.1 + 1 == k && r.2 == w => r.1 = k,
                _ => runs.push((k, k, w)),
            }
        }
        runs
    }
}

/// The computations behind the workbench. Implementations must be deterministic.
pub trait Engine: Send + Sync {
    /// Reads a take: a BVH file (`demo:walk` is the generated walk of
    /// [`crate::io::generate`]; frame 0 dropped when it is a rest pose, unless
    /// `params.take.keep_first_frame`), a DH table (`.toml`) or a URDF (`.urdf`, fixed base, z up).
    fn load(&self, path: &Path, params: &Params) -> Result<Take, Error>;
    /// Reads a states CSV (`articula export states` format) for `model`.
    fn load_motion(&self, model: &Model, path: &Path) -> Result<States, Error>;
    /// Model, smoothed q, v, a and inverse-dynamics torques of `take` under `params`.
    fn inverse_dynamics(
        &self,
        take: &Take,
        params: &Params,
        ctl: &Control,
    ) -> Result<Analysis, Error>;
    /// [`inverse_dynamics`](Self::inverse_dynamics) after `previous`, earlier results of the
    /// same take: what the edit since does not change is reused (the built-in engine keeps
    /// the smoothed states of an edit of masses, contact or quoted frames). The results are
    /// those of `inverse_dynamics`, bit for bit. By default, computes everything.
    fn inverse_dynamics_after(
        &self,
        take: &Take,
        params: &Params,
        previous: Option<&Analysis>,
        ctl: &Control,
    ) -> Result<Analysis, Error> {
        let _ = previous;
        self.inverse_dynamics(take, params, ctl)
    }
    /// A computed-torque simulation tracking `take`; the results in the same shape.
    fn simulate(&self, take: &Take, params: &Params, ctl: &Control) -> Result<Analysis, Error>;
    /// Take `b` blended into take `a` over `window` (s).
    fn blend(&self, a: &Take, b: &Take, window: (f64, f64)) -> Result<Take, Error>;
    /// Writes a BVH take's motion as the user sees it: the smoothed q of `params` (the
    /// pipeline's `articula smooth`), or with `motion`, those configurations (a simulation of
    /// the take, one row per frame). Nothing is written once `ctl` is cancelled.
    fn export_bvh(
        &self,
        take: &Take,
        params: &Params,
        motion: Option<&Analysis>,
        path: &Path,
        ctl: &Control,
    ) -> Result<(), Error>;
    /// Writes a BVH take's states, joint centres, ground reactions or glTF animation under
    /// `params` as the CLI's `export states|trc|grf|gltf` does, or its inverse dynamics as
    /// `articula id` does (`kind` one of [`ExportKind::take_file`]; the format by `path`'s
    /// extension: `.sto` / `.mot` for OpenSim, else CSV; `.trc` in mm).
    /// Returns the files written. Nothing is written once `ctl` is cancelled.
    fn export_take_file(
        &self,
        take: &Take,
        params: &Params,
        kind: ExportKind,
        path: &Path,
        ctl: &Control,
    ) -> Result<Vec<std::path::PathBuf>, Error> {
        use crate::pipeline::formats::{
            TableFormat, export_grf, export_states_as, export_trc, write_inverse_dynamics_as,
        };
        let mut t = pipeline_take(take, params, "export", &mut ctl.stage(0.0, 0.7))?;
        pipeline::resolve_contact(&mut t);
        ctl.check()?;
        let mut wrote = vec![path.to_path_buf()];
        if kind == ExportKind::Gltf {
            pipeline::export_gltf(&t, path)?;
            return Ok(wrote);
        }
        let format = TableFormat::choose(path, None)?;
        match kind {
            ExportKind::States => export_states_as(&t, path, format)?,
            ExportKind::Trc => export_trc(&t, path, crate::report::opensim::TrcUnits::Mm)?,
            ExportKind::Id => {
                // `articula id`'s own path: the take made consistent as the session's
                // results are (`set consistent`, on by default with contact feet)
                let feet = t.options.contact == pipeline::Contact::Feet;
                let reduce = feet && params.consistent.unwrap_or(true);
                let mut job = pipeline::Job::from_take(t.clone());
                pipeline::consistency::consistent_job(&mut job, reduce, true, None)?;
                ctl.check()?;
                write_inverse_dynamics_as(&job, path, format)?;
                if format == TableFormat::Csv {
                    // the sidecar of `articula id`'s CSV: the (adjusted) take and model
                    let p = pipeline::summary::Provenance {
                        command: "export id",
                        arguments: &[],
                        take: job.take.as_ref(),
                        model: Some(&job.model),
                        notes: &[],
                        known_units: &[],
                    };
                    wrote.extend(pipeline::summary::write_sidecar(path, &p)?);
                }
                return Ok(wrote);
            }
            ExportKind::Grf => {
                if let crate::pipeline::formats::ExternalLoadsXml::Written(xml) =
                    export_grf(&t, path, format)?
                {
                    wrote.push(xml);
                }
            }
            other => {
                return Err(Error::Invalid(format!(
                    "export {other:?}: not a take file (states, trc, grf, gltf or id)"
                )));
            }
        }
        if kind != ExportKind::Trc && format == TableFormat::Csv {
            let command = match kind {
                ExportKind::States => "export states",
                _ => "export grf",
            };
            let p = pipeline::summary::Provenance {
                command,
                arguments: &[],
                take: Some(&t),
                model: None,
                notes: &[],
                known_units: &[],
            };
            wrote.extend(pipeline::summary::write_sidecar(path, &p)?);
        }
        Ok(wrote)
    }
}

/// The engine over the library's stage functions.
#[derive(Debug, Clone, Copy, Default)]
pub struct Builtin;

/// The built-in demo take (`demo:walk`).
pub const DEMO_WALK: &str = "demo:walk";

/// Rows as one row-major [`Table`].
fn table(names: &[String], rows: &[Vec<f64>]) -> Table {
    Table {
        names: names.to_vec(),
        data: rows.concat(),
    }
}

fn cancelled() -> Error {
    Error::Cancelled
}

impl Engine for Builtin {
    fn load(&self, path: &Path, params: &Params) -> Result<Take, Error> {
        let source = path.to_string_lossy().into_owned();
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| source.clone())
            .replace("demo:", "");
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        let robot = |model: Model, kind| {
            TakeData::Robot(Robot {
                model: Arc::new(model),
                kind,
                motion: None,
                motion_source: String::new(),
            })
        };
        let mut notes = vec![];
        let data = if source == DEMO_WALK {
            TakeData::Bvh(Arc::new(crate::io::generate::walk(
                &crate::io::generate::WalkParams::default(),
            )))
        } else if ext == "toml" {
            let table = crate::io::dh::read(path)?;
            robot(crate::model::dh::build_dh_model(&table)?, "DH table")
        } else if ext == "urdf" {
            let opts = crate::model::urdf::UrdfOptions::default();
            robot(crate::model::urdf::read_urdf(path, &opts)?, "URDF")
        } else {
            // as `pipeline::load_take`: a rest pose stored as frame 0 is dropped unless kept
            let (bvh, trimmed) = pipeline::read_take(path, params.take.keep_first_frame)?;
            // a take the pipeline cannot turn into a model and states under these settings
            // fails here, and the workbench keeps the take it had (it became the active take
            // and every later command repeated its error)
            let t = pipeline::take_from_bvh(path, bvh.clone(), &params.take)?;
            notes.extend(trimmed);
            notes.extend(t.notes);
            TakeData::Bvh(Arc::new(bvh))
        };
        Ok(Take {
            name,
            source,
            data,
            notes,
        })
    }

    fn load_motion(&self, model: &Model, path: &Path) -> Result<States, Error> {
        let s = pipeline::read_states(model, path)?;
        if s.len() < 2 {
            return Err(Error::Invalid(format!(
                "{}: {} sample(s); a motion needs two or more",
                path.display(),
                s.len()
            )));
        }
        Ok(s)
    }

    fn inverse_dynamics(
        &self,
        take: &Take,
        params: &Params,
        ctl: &Control,
    ) -> Result<Analysis, Error> {
        self.inverse_dynamics_after(take, params, None, ctl)
    }

    fn inverse_dynamics_after(
        &self,
        take: &Take,
        params: &Params,
        previous: Option<&Analysis>,
        ctl: &Control,
    ) -> Result<Analysis, Error> {
        ctl.check()?;
        let mut note = String::new();
        let mut anatomy = Table::zeros(vec![], 0);
        let mut left_out = vec![];
        let mut anatomy_joints = vec![];
        let mut brief = String::new();
        let mut source = None;
        let mut feet = Table::zeros(vec![], 0);
        let mut calibration = None;
        let mut contact_auto = None;
        let (model, states, scale, grf) = match &take.data {
            TakeData::Bvh(bvh) => {
                // the pipeline's stages: axes and unit, model, q, unwrap, smooth, differentiate
                // (progress: the smoothing per coordinate, then the ground reactions or RNEA
                // per frame)
                // stages 2–7; the states of `previous` when the edit keeps them
                let mut t = pipeline::take_from_bvh_reusing(
                    Path::new(&take.source),
                    (**bvh).clone(),
                    &params.take,
                    previous.and_then(|p| p.source.as_deref()),
                    &mut ctl.stage(0.0, 0.2),
                    &mut |s| ctl.done(s),
                )?;
                ctl.set_progress(0.2);
                ctl.check()?;
                source = Some(Arc::new(t.clone()));
                // `contact auto` as the last results settled it when only masses changed
                let settled =
                    previous.and_then(|p| Some((p.source.as_deref()?, p.contact_auto.as_ref()?)));
                contact_auto = pipeline::resolve_contact_after(&mut t, settled);
                let scale = t.scale_to_m;
                // the frames within the smoothing's reach of the ends, unless `edges include`
                left_out = vec![None; t.states.len()];
                if !params.include_edges {
                    let e = pipeline::edge_frames(&t);
                    let n = left_out.len();
                    for k in (0..e.min(n)).chain(n.saturating_sub(e)..n) {
                        left_out[k] = Some(LeftOut::Edge);
                    }
                }
                note = summarize_notes(&t.notes);
                // with `contact feet`: the torques with the estimated ground reactions
                // (and how far the feet could give the ground force the motion needs), of the
                // take made consistent unless `consistent off` (residual reduction)
                // the bodies whose net moments the anatomical series read: the estimate keeps
                // them from its own RNEA with the ground reactions
                let bodies = match &t.human {
                    Ok(_) => pipeline::anatomy::moment_bodies(&t),
                    Err(_) => vec![],
                };
                let (t, g) = if t.options.contact == pipeline::Contact::Feet {
                    let reduce = params.consistent.unwrap_or(true);
                    let (adjusted, g, c) =
                        pipeline::consistency::consistent_take_keeping(&t, reduce, None, &bodies)?;
                    for (k, b) in c.beyond.iter().enumerate() {
                        if *b && k < left_out.len() {
                            left_out[k] = Some(LeftOut::Beyond);
                        }
                    }
                    brief = contact_brief(&g.quality(), c.last().meets());
                    ctl.done(Stage::Contact);
                    feet = vertical_forces(&g);
                    let said = format!("{}; {}", g.quality(), c.headline());
                    note = if note.is_empty() {
                        said
                    } else {
                        format!("{note}; {said}")
                    };
                    ctl.set_progress(0.9);
                    (adjusted.unwrap_or(t), Some(g))
                } else {
                    (t, None)
                };
                ctl.check()?;
                // the anatomical series: the calibration of the last results when this take's
                // kinematics are theirs (a mass edit), the moments from this run's RNEA
                calibration = t.human.is_ok().then(|| {
                    previous
                        .and_then(|p| p.calibration.clone())
                        .filter(|c| c.fits(&t))
                        .or_else(|| pipeline::anatomy::Calibration::new(&t).ok().map(Arc::new))
                });
                let calibration = calibration.as_ref().and_then(Option::as_ref);
                let tau = match (&g, calibration) {
                    (Some(g), Some(cal)) => {
                        let moments = cal.net_moments(&t, Some(g));
                        anatomy = anatomy_table(cal.series(&t, &moments, Some(g)));
                        None
                    }
                    // without contact, one RNEA per frame gives the torques and the moments
                    (None, Some(cal)) => {
                        let (tau, moments) = pipeline::anatomy::inverse_dynamics_and_moments(
                            &t.model,
                            &t.states,
                            cal.bodies(),
                            &mut ctl.stage(0.2, 1.0),
                        )
                        .ok_or_else(cancelled)?;
                        ctl.done(Stage::InverseDynamics);
                        anatomy = anatomy_table(cal.series(&t, &moments, None));
                        Some(tau)
                    }
                    (_, None) => None,
                };
                if !anatomy.names.is_empty()
                    && let Ok(h) = &t.human
                {
                    anatomy_joints = pipeline::anatomy::anatomical_joints(h, &t.bvh);
                }
                ctl.check()?;
                let grf = g.map(|g| g.tau).or(tau);
                (Arc::new(t.model), Arc::new(t.states), scale, grf)
            }
            TakeData::Robot(r) => {
                let m = r.motion.clone().ok_or_else(|| no_motion(take))?;
                (r.model.clone(), m, 1.0, None)
            }
        };
        // inverse dynamics (RNEA) frame by frame, with progress and cancel
        let tau = match grf {
            Some(tau) => tau,
            None => {
                let t = pipeline::inverse_dynamics_with(&model, &states, &mut ctl.stage(0.2, 1.0));
                if t.tau.len() < states.len() {
                    return Err(cancelled());
                }
                ctl.done(Stage::InverseDynamics);
                t.tau
            }
        };
        ctl.set_progress(1.0);
        // a non-finite torque (an absurd mass, a singular pose) is an error here, so that no
        // view, expect or file ever shows one
        for (k, row) in tau.iter().enumerate() {
            if let Some(j) = row.iter().position(|x| !x.is_finite()) {
                return Err(Error::Numerical(format!(
                    "inverse dynamics: the torque on `{}` is not finite at frame {k} ({:.4e} kg \
                     body): check body.mass and the link masses",
                    model.v_names[j], params.take.body.mass_kg
                )));
            }
        }
        Ok(Analysis {
            q: table(&model.q_names, &states.q),
            v: table(&model.v_names, &states.v),
            a: table(&model.v_names, &states.a),
            tau: table(&model.v_names, &tau),
            time: states.time.clone(),
            scale,
            note,
            brief,
            model,
            anatomy,
            left_out,
            anatomy_joints,
            feet,
            source,
            calibration: calibration.flatten(),
            contact_auto,
            reference: Table::zeros(vec![], 0),
        })
    }

    fn simulate(&self, take: &Take, params: &Params, ctl: &Control) -> Result<Analysis, Error> {
        // computed-torque tracking of the take's (smoothed) motion, or of a robot's motion
        ctl.check()?;
        let (model, states, scale) = match &take.data {
            TakeData::Bvh(bvh) => {
                let t = pipeline::take_from_bvh_with(
                    Path::new(&take.source),
                    (**bvh).clone(),
                    &params.take,
                    &mut ctl.stage(0.0, 0.05),
                )?;
                (Arc::new(t.model), Arc::new(t.states), t.scale_to_m)
            }
            TakeData::Robot(r) => {
                let m = r.motion.clone().ok_or_else(|| no_motion(take))?;
                (r.model.clone(), m, 1.0)
            }
        };
        ctl.set_progress(0.05);
        ctl.check()?;
        let settings = pipeline::SimSettings::parse(
            &params.integrator,
            params.dt,
            &params.kp,
            &params.kv,
            0.0,
            None,
        )?;
        let r = pipeline::simulate_states(&model, &states, &settings, &mut ctl.stage(0.05, 1.0))?
            .result;
        ctl.set_progress(1.0);
        // the configurations it tracked
        let reference = table(&model.q_names, &states.q);
        // accelerations are not recorded: differentiate the simulated velocities
        let dt = r.time.get(1).map_or(params.dt, |t1| t1 - r.time[0]);
        let mut a = Table::zeros(model.v_names.clone(), r.time.len());
        let mut da = vec![0.0; r.time.len()];
        let mut vj = vec![0.0; r.time.len()];
        for j in 0..model.nv {
            for (x, row) in vj.iter_mut().zip(&r.v) {
                *x = row[j];
            }
            crate::motion::derive::differentiate(&vj, dt, &mut da);
            for (k, x) in da.iter().enumerate() {
                a.row_mut(k)[j] = *x;
            }
        }
        Ok(Analysis {
            q: table(&model.q_names, &r.q),
            v: table(&model.v_names, &r.v),
            a,
            tau: table(&model.v_names, &r.tau),
            time: r.time.clone(),
            scale,
            note: format!(
                "tracking error RMS {}, max {}",
                super::units::format_value(super::units::Kind::Angle, r.rms_error_rad()),
                super::units::format_value(super::units::Kind::Angle, r.max_error_rad())
            ),
            brief: String::new(),
            model,
            anatomy: Table::zeros(vec![], 0),
            left_out: vec![],
            anatomy_joints: vec![],
            feet: Table::zeros(vec![], 0),
            source: None,
            calibration: None,
            contact_auto: None,
            reference,
        })
    }

    fn blend(&self, a: &Take, b: &Take, window: (f64, f64)) -> Result<Take, Error> {
        let (Some(ba), Some(bb)) = (a.bvh(), b.bvh()) else {
            return Err(Error::Invalid(format!(
                "blend {} {}: only BVH takes blend (a robot's motion is a trajectory)",
                a.name, b.name
            )));
        };
        // motion::blend: C² ramp, shortest-arc slerp per joint, b's root and heading aligned
        // to a's at the window start
        let opts = BlendOptions {
            align: Align::ALL,
            up_axis: detect_up(ba).index(),
            ..BlendOptions::default()
        };
        let w = WarpWindow {
            t0: window.0,
            t1: window.1,
        };
        let bvh = crate::motion::blend::blend(ba, bb, w, TimeMap::IDENTITY, &opts)?;
        Ok(Take {
            name: format!("{}+{}", a.name, b.name),
            source: format!("blend {} {} {}:{}", a.name, b.name, window.0, window.1),
            data: TakeData::Bvh(Arc::new(bvh)),
            notes: vec![],
        })
    }

    fn export_bvh(
        &self,
        take: &Take,
        params: &Params,
        motion: Option<&Analysis>,
        path: &Path,
        ctl: &Control,
    ) -> Result<(), Error> {
        // the pipeline's take under the current options: its q are what the user sees
        let mut t = pipeline_take(take, params, "export bvh", &mut ctl.stage(0.0, 0.9))?;
        if let Some(m) = motion {
            if m.q.rows() != t.states.len() || m.q.names != t.model.q_names {
                return Err(Error::Invalid(format!(
                    "export bvh sim: the simulation has {} rows of {} coordinates, the take {} \
                     frames of {}; run sim again",
                    m.q.rows(),
                    m.q.cols(),
                    t.states.len(),
                    t.model.nq
                )));
            }
            for (k, row) in t.states.q.iter_mut().enumerate() {
                row.copy_from_slice(m.q.row(k));
            }
        }
        ctl.check()?;
        pipeline::export_smoothed_bvh_as(&t, path, params.bvh_style)
    }
}

/// Each foot's vertical ground force (N, up positive) per frame, columns named by foot.
fn vertical_forces(g: &crate::dynamics::grf::GroundReactions) -> Table {
    let rows: Vec<Vec<f64>> = g
        .grf
        .iter()
        .map(|f| f.iter().map(|v| v[g.up]).collect())
        .collect();
    table(&g.feet, &rows)
}

/// The pipeline's take of a BVH take under `params` (what the exports write from); a robot
/// model is an error naming `what` was asked.
fn pipeline_take(
    take: &Take,
    params: &Params,
    what: &str,
    progress: &mut dyn FnMut(f64) -> bool,
) -> Result<pipeline::Take, Error> {
    let bvh = take.bvh().ok_or_else(|| {
        Error::Invalid(format!(
            "{what}: {} is a robot model, not a BVH take (export csv writes its motion)",
            take.name
        ))
    })?;
    pipeline::take_from_bvh_with(Path::new(&take.source), bvh.clone(), &params.take, progress)
}

fn no_motion(take: &Take) -> Error {
    Error::Invalid(format!(
        "{} has no motion yet: `load STATES.csv` (articula export states format) or \
         `trajectory POSE POSE … over T` first",
        take.name
    ))
}

/// The take's notes after inverse dynamics (what the loader assumed — a scale, a smoothing —
/// and where torques are not to be trusted — gimbal lock, a capture glitch), as one
/// status-line message: the first and how many more. The load message said them too, but the
/// recompute that follows a load replaced it at once.
pub(crate) fn summarize_notes(notes: &[String]) -> String {
    // where torques are not to be trusted comes first, then what the loader assumed
    let warns = |n: &&String| n.contains("gimbal lock") || n.contains("capture glitch");
    let ordered: Vec<&String> = notes
        .iter()
        .filter(warns)
        .chain(notes.iter().filter(|n| !warns(n)))
        .collect();
    match ordered.as_slice() {
        [] => String::new(),
        [one] => format!("note: {one}"),
        [first, rest @ ..] => format!(
            "note: {first} (+{} more; `articula info` lists every note)",
            rest.len()
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn demo_walk_has_the_paper_euler_model_and_body_mass() {
        let take = Builtin
            .load(Path::new(DEMO_WALK), &Params::default())
            .unwrap();
        let params = Params::default();
        let r = Builtin
            .inverse_dynamics(&take, &params, &Control::default())
            .unwrap();
        // 21 joints × 3 rotations + 3 root translations
        assert_eq!(r.model.nv, 66);
        assert!((r.model.total_mass() - 75.0).abs() < 1e-9);
        assert_eq!(r.scale, 0.01);
        assert!(r.tau.data.iter().all(|x| x.is_finite()));
    }

    #[test]
    fn smoothing_width_changes_the_torques_and_none_keeps_the_raw_angles() {
        let take = Builtin
            .load(Path::new(DEMO_WALK), &Params::default())
            .unwrap();
        let bvh = take.bvh().unwrap();
        let ctl = Control::default();
        let mut raw = Params::default();
        raw.take.smooth = Some(SmoothSpec::None);
        let r0 = Builtin.inverse_dynamics(&take, &raw, &ctl).unwrap();
        // unsmoothed: q is the channel value in radians
        let j = r0.q.col_index("LeftLeg.Xrotation").unwrap();
        let c = bvh.joints[bvh.joint_index("LeftLeg").unwrap()].first_channel + 1;
        for k in [0, 100, 479] {
            assert!((r0.q.row(k)[j] - bvh.frame(k)[c].to_radians()).abs() < 1e-12);
        }
        let mut wide = Params::default();
        wide.take.smooth = Some(SmoothSpec::Gaussian { sigma_s: 0.05 });
        let r1 = Builtin.inverse_dynamics(&take, &wide, &ctl).unwrap();
        assert_ne!(r0.tau, r1.tau);
    }

    #[test]
    fn a_cancelled_control_stops_before_any_result() {
        let take = Builtin
            .load(Path::new(DEMO_WALK), &Params::default())
            .unwrap();
        let ctl = Control::default();
        ctl.cancel();
        let e = Builtin
            .inverse_dynamics(&take, &Params::default(), &ctl)
            .unwrap_err();
        assert!(e.to_string().contains("cancelled"), "{e}");
    }
}
