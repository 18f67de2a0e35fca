//! The computations the workbench asks for, behind one small trait so that the workbench does
//! not care which stage functions compute them ([`Engine`]), and the built-in engine over the
//! library ([`Builtin`]).
//!
//! Every engine call gets a [`Control`]: it reports progress (0‥1) and polls for
//! cancellation, so that the terminal UI can run it on a worker thread.

mod analysis;
mod builtin;
mod control;

pub use analysis::{Analysis, LeftOut, Table};
pub use builtin::{Builtin, DEMO_WALK};
pub use control::{Control, STAGE_COUNT};

use super::command::ExportKind;
use crate::error::Error;
use crate::io::bvh::Bvh;
use crate::model::Model;
use crate::pipeline::PerJoint;
use crate::pipeline::{self, TakeOptions};
use std::collections::BTreeMap;
use std::path::Path;
use std::sync::Arc;

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
    /// those of `inverse_dynamics`, bit for bit, but for residual reduction when every mass is
    /// `previous`'s times one factor: then it reuses what `previous`'s found
    /// (`Analysis::reduction`, `dynamics::rra::Seed`), equal to a cold start to 1e-9 of the
    /// peaks. By default, computes everything.
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
    /// A preview of [`inverse_dynamics_after`](Self::inverse_dynamics_after)'s results for a
    /// workbench's first redraw after an edit of the body's masses alone, whose residual
    /// reduction would start cold (tenths of a second on a long take): the reduction
    /// `previous` found, its adjustments evaluated on the new masses, nothing solved
    /// (`dynamics::rra::Warm::Preview`). Not these masses' reduction: the results proper
    /// replace it. `None` when the edit is of anything else, when `previous` has no reduction,
    /// or when the results proper are as quick (masses scaled alike). By default none.
    fn preview_after(
        &self,
        take: &Take,
        params: &Params,
        previous: Option<&Analysis>,
        ctl: &Control,
    ) -> Option<Analysis> {
        let _ = (take, params, previous, ctl);
        None
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
                let c = pipeline::consistency::consistent_job(&mut job, reduce, true, None)?;
                ctl.check()?;
                write_inverse_dynamics_as(&job, path, format, c.as_ref())?;
                if format == TableFormat::Csv {
                    // the sidecar of `articula id`'s CSV: the (adjusted) take and model
                    let p = pipeline::summary::Provenance {
                        command: "export id",
                        arguments: &[],
                        take: job.take.as_ref(),
                        model: Some(&job.model),
                        notes: &[],
                        known_units: &[],
                        consistency: c.as_ref(),
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
                consistency: None,
            };
            wrote.extend(pipeline::summary::write_sidecar(path, &p)?);
        }
        Ok(wrote)
    }
}

/// The pipeline's take of a BVH take under `params` (what the exports write from); a robot
/// model is an error naming `what` was asked.
pub(super) fn pipeline_take(
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

pub(super) fn no_motion(take: &Take) -> Error {
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
