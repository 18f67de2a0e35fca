//! The named stages that turn a take (or a robot and a states file) and its options into a
//! model and the q, v, a that the dynamics uses; and the jobs the CLI, sessions and TUI run on
//! them. Every front end goes through here, so `articula id`, a session's `run id` and the
//! TUI's torque curves are the same numbers.
//!
//! A take flows through these stages, in order:
//! 1. `read`: parse the BVH (`io::bvh`);
//! 2. `axes and unit`: up axis and length unit detected from the rest pose, or given
//!    (`--up`, `--unit`, `--stature`), stature checked against 1.0–2.3 m;
//! 3. `position semantics`: add / replace / auto per joint; position channels of the joints
//!    below the body's root welded at their mean (`motion::weld`; `--joint-translations keep`
//!    keeps them as coordinates);
//! 4. `model`: euler or ball joints, de Leva masses, locks and subtree (`model::bvh`); a
//!    massless helper root folded into the pelvis (`motion::fold`);
//! 5. `q`: channels → q per frame (`motion::take`), Euler angles unwrapped;
//! 6. `smooth`: the chosen low-pass on q (`motion::smooth`);
//! 7. `v, a`: central differences on the configuration manifold (`Model::difference`), then
//!    of v.

pub mod anatomy;
mod animation;
pub mod commands;
pub mod consistency;
mod contact;
mod edit;
pub mod flags;
pub mod formats;
pub mod measured;
mod mujoco;
pub mod reduce;
mod sim;
pub mod stages;
mod states;
pub mod summary;
pub mod table;

pub use animation::{TO_Y_UP, export_gltf, rig_world_positions, take_rig, to_y_up};
pub use contact::{
    Contact, contact_choice, contact_feet, edge_frames, estimate_take_ground_reactions,
    estimate_take_ground_reactions_with, ground_reactions, ground_reactions_with, resolve_contact,
    resolve_contact_after, same_motion, take_feet,
};
pub use edit::{blend_files, export_smoothed_bvh, export_smoothed_bvh_as};
pub use mujoco::{export_mjcf, floor_level};
pub use sim::{
    Bench, SimSettings, SimSummary, Tradeoff, TradeoffRow, bench, bench_batches,
    passive_energy_drift, reference, simulate, simulate_states, tradeoff, tradeoff_grid,
};
pub use stages::{STAGES, Stage, StageBench, StageSettings, bench_stages};
pub use states::{
    derivatives, make_euler_triples_continuous, take_states, take_states_marked, take_states_with,
    unwrap_and_smooth, unwrap_and_smooth_with,
};

use crate::dynamics::{self, Workspace};
use crate::error::Error;
use crate::io::bvh::{
    self, Bvh, JointTranslations, LengthUnit, PositionMode, ResolvedPosition, UpAxis,
};
pub use crate::io::scene::{Damping, PerJoint};
use crate::model::Model;
use crate::model::anthropometry::{BodyParams, SegmentTable, Sex};
use crate::model::bvh::{BvhMap, BvhModelOptions, JointModel, build_bvh_model};
use crate::motion::smooth::{SmoothSpec, Smoother};
use crate::par;
use crate::report::columns;
use crate::report::csv::{read_columns, write_columns};
use std::borrow::Cow;
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// Everything that decides how a take becomes a model and states.
#[derive(Debug, Clone, PartialEq)]
pub struct TakeOptions {
    /// Length unit; `None`: detected from the rest-pose stature.
    pub unit: Option<LengthUnit>,
    /// Scale the skeleton to this stature (m) instead; wins over `unit`.
    pub stature_m: Option<f64>,
    /// Up axis; `None`: detected.
    pub up: Option<UpAxis>,
    /// Position channel semantics.
    pub positions: PositionMode,
    /// Joint model.
    pub joints: JointModel,
    /// Body mass, sex, segment table and link-mass overrides (`body.height_m` is set from the
    /// take's stature when the model is built).
    pub body: BodyParams,
    /// Low-pass applied to q before differentiation; `None`: the default that fits the take
    /// ([`default_smoothing`]: `butterworth:6hz`, or none on a keyframed or low-rate take).
    pub smooth: Option<SmoothSpec>,
    /// Joints whose DOFs leave the model (held at the rest pose), and at most one
    /// `auto:TOL` (`auto:2%`, `auto:1nm`): then the joints [`reduce::lock_auto`] finds can go
    /// within TOL on this take go too.
    pub lock: Vec<String>,
    /// Keep only the subtree below this joint.
    pub subtree: Option<String>,
    /// Ground contact model.
    pub contact: Contact,
    /// Keep frame 0 even when it is a rest pose before the motion (`motion::trim`); by
    /// default [`load_take`] drops it.
    pub keep_first_frame: bool,
    /// Viscous joint friction `b q̇` set on the model (`Model::damping`); never on the 6 root
    /// coordinates of a floating avatar.
    pub damping: Damping,
    /// Position channels of the joints below the body's root: welded at their mean (the
    /// default) or kept as coordinates (`motion::weld`).
    pub joint_translations: JointTranslations,
}

impl Default for TakeOptions {
    fn default() -> Self {
        Self {
            unit: None,
            stature_m: None,
            up: None,
            positions: PositionMode::Auto,
            joints: JointModel::Euler,
            body: BodyParams::new(75.0, Sex::Male),
            smooth: None,
            lock: vec![],
            subtree: None,
            contact: Contact::Auto,
            keep_first_frame: false,
            damping: Damping::default(),
            joint_translations: JointTranslations::Weld,
        }
    }
}

/// Flags as typed by a user (strings not yet validated); `None` leaves the option unchanged.
#[derive(Debug, Default)]
pub struct Flags<'a> {
    pub unit: Option<&'a str>,
    pub stature_m: Option<f64>,
    pub up: Option<&'a str>,
    pub positions: Option<&'a str>,
    pub joints: Option<&'a str>,
    pub mass_kg: Option<f64>,
    pub sex: Option<&'a str>,
    /// `regression` or `fractions`.
    pub segments: Option<&'a str>,
    pub link_mass: &'a [String],
    pub smooth: Option<&'a str>,
    pub lock: &'a [String],
    pub subtree: Option<&'a str>,
    pub contact: Option<&'a str>,
    /// `--keep-first-frame` (false leaves the option unchanged).
    pub keep_first_frame: bool,
    /// `B` (every joint coordinate) or `JOINT=B` (N·m·s/rad), in order.
    pub damping: &'a [String],
    /// `weld` or `keep`.
    pub joint_translations: Option<&'a str>,
}

/// A smoothing as typed: `auto` (the default that fits the take) or a [`SmoothSpec`].
pub fn parse_smooth(s: &str) -> Result<Option<SmoothSpec>, Error> {
    if s.trim().eq_ignore_ascii_case("auto") {
        return Ok(None);
    }
    parse_flag("smooth", s).map(Some)
}

/// A turn of more than 90° in one frame is a capture glitch only this fast (rad/s): 90° a
/// frame at 20 fps. Slower, it is a keyframed or low-rate take's ordinary step.
const GLITCH_SPEED: f64 = 1800.0 * std::f64::consts::PI / 180.0;

/// An Euler triple whose middle angle is within this of ±90° is near gimbal lock (rad).
const NEAR_LOCK: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// Frame times below this (10 kHz) are noted as likely wrong: motion capture runs at 1 kHz at
/// most.
const MIN_PLAUSIBLE_FRAME_TIME_S: f64 = 1e-4;

/// The default smoothing's cutoff (Hz): the biomechanics standard for gait.
pub const DEFAULT_CUTOFF_HZ: f64 = 6.0;

/// The smoothing a take gets when the user chose none: `butterworth:6hz` when its cutoff is
/// at most 60 % of the take's Nyquist frequency (20 fps and up) and the filter fits the frame
/// time (`Smoother::new`); otherwise none, with a note saying why. A take keyframed every
/// second or sampled at 12 fps holds no capture noise above 6 Hz to remove, and a 6 Hz filter
/// cannot even be built below 12 fps.
pub fn default_smoothing(frame_time: f64) -> (SmoothSpec, Option<String>) {
    let spec = SmoothSpec::Butterworth {
        cutoff_hz: DEFAULT_CUTOFF_HZ,
        order: 2,
    };
    let fps = 1.0 / frame_time;
    let min_fps = DEFAULT_CUTOFF_HZ / (0.5 * MAX_CUTOFF_OF_NYQUIST);
    if fps < min_fps {
        let note = format!(
            "not smoothed: the take is sampled at {fps:.3} fps, too slowly for the default \
             low-pass `{spec}` (it needs {min_fps} fps or more); a keyframed or low-rate take \
             is used as it is (--smooth chooses a filter)"
        );
        return (SmoothSpec::None, Some(note));
    }
    match Smoother::new(spec, frame_time) {
        Ok(_) => (spec, None),
        Err(e) => (
            SmoothSpec::None,
            Some(format!(
                "not smoothed: the default low-pass cannot apply: {e}"
            )),
        ),
    }
}

/// The default low-pass applies when its cutoff is at most this fraction of the take's
/// Nyquist frequency (6 Hz: 20 fps and up).
const MAX_CUTOFF_OF_NYQUIST: f64 = 0.6;

pub(crate) fn parse_flag<T: FromStr>(flag: &str, value: &str) -> Result<T, Error>
where
    T::Err: std::fmt::Display,
{
    value
        .parse()
        .map_err(|e| Error::Invalid(format!("--{flag} {value}: {e}")))
}

impl TakeOptions {
    /// Options from a scene file (TOML; see `data/scene_example.toml`).
    pub fn from_scene_file(path: &Path) -> Result<Self, Error> {
        Self::from_scene(&crate::io::scene::read(path)?)
    }

    /// Options from a parsed scene (the takes and gains of the scene are used by the caller).
    pub fn from_scene(scene: &crate::io::scene::Scene) -> Result<Self, Error> {
        let mut o = Self {
            unit: scene.unit,
            stature_m: scene.stature,
            up: scene.up,
            positions: scene.position,
            lock: scene.lock.clone(),
            subtree: scene.subtree.clone(),
            ..Self::default()
        };
        o.joints = scene.joints.parse()?;
        o.body = BodyParams {
            mass_kg: scene.mass,
            sex: scene.sex.parse()?,
            segments: scene.segments.parse()?,
            height_m: None,
            link_mass: scene.link_mass.clone(),
        };
        if let Some(sm) = &scene.smooth {
            o.smooth = parse_smooth(sm)?;
        }
        o.contact = scene.contact.parse()?;
        o.keep_first_frame = scene.keep_first_frame;
        o.damping = scene.damping.clone();
        o.joint_translations = scene.joint_translations;
        Ok(o)
    }

    /// Applies user flags over these options.
    pub fn apply_flags(&mut self, f: &Flags) -> Result<(), Error> {
        if let Some(u) = f.unit {
            self.unit = Some(parse_flag("unit", u)?);
            self.stature_m = None;
        }
        if let Some(s) = f.stature_m {
            if !(s.is_finite() && s > 0.0) {
                return Err(Error::Invalid(format!(
                    "--stature {s}: expected a height in metres, e.g. 1.75"
                )));
            }
            self.stature_m = Some(s);
        }
        if let Some(u) = f.up {
            self.up = Some(parse_flag("up", u)?);
        }
        if let Some(p) = f.positions {
            self.positions = parse_flag("positions", p)?;
        }
        if let Some(j) = f.joints {
            self.joints = parse_flag("joints", j)?;
        }
        if let Some(m) = f.mass_kg {
            if !(m.is_finite() && m > 0.0) {
                return Err(Error::Invalid(format!(
                    "--mass {m}: expected a body mass in kg, e.g. 75"
                )));
            }
            self.body.mass_kg = m;
        }
        if let Some(s) = f.sex {
            self.body.sex = parse_flag("sex", s)?;
        }
        if let Some(s) = f.segments {
            self.body.segments = parse_flag("segments", s)?;
        }
        for lm in f.link_mass {
            let (name, kg) = lm.split_once('=').ok_or_else(|| {
                Error::Invalid(format!(
                    "--link-mass {lm}: expected JOINT=KG, e.g. LeftLeg=3.5"
                ))
            })?;
            let kg: f64 = parse_flag("link-mass", kg.trim())?;
            self.body.link_mass.insert(name.trim().to_string(), kg);
        }
        if let Some(s) = f.smooth {
            self.smooth = parse_smooth(s)?;
        }
        if !f.lock.is_empty() {
            self.lock = f.lock.iter().map(|s| s.trim().to_string()).collect();
            reduce::split_lock(&self.lock)?;
        }
        if let Some(s) = f.subtree {
            self.subtree = Some(s.to_string());
        }
        if let Some(c) = f.contact {
            self.contact = parse_flag("contact", c)?;
        }
        if f.keep_first_frame {
            self.keep_first_frame = true;
        }
        if let Some(j) = f.joint_translations {
            self.joint_translations = parse_flag("joint-translations", j)?;
        }
        parse_per_joint(
            "damping",
            f.damping,
            &mut self.damping,
            "N·m·s/rad",
            "0.5 or LeftLeg=2",
        )?;
        Ok(())
    }
}

/// Sets `model.damping` from `d` ([`per_coordinate`]), skipping the root residual coordinates of
/// a floating avatar ([`dynamics::floating_root_nv`]: they are not a joint, so friction there
/// means nothing).
///
/// # Errors
/// An override that names no coordinate, or only root coordinates.
pub fn apply_damping(model: &mut Model, d: &Damping) -> Result<(), Error> {
    let root = dynamics::floating_root_nv(model);
    let b = per_coordinate(model, d, root, "damping")?;
    model.damping = b;
    Ok(())
}

/// One value per velocity coordinate from `p`: `p.all` on every coordinate from `first` on
/// (0 before it), then the overrides, matched to coordinates by name — a joint name covers
/// `<joint>`, `<joint>.<channel>` and `<joint>:<comp>`, a coordinate name itself. `what` names
/// the setting in errors (`damping`, `kp`, `kv`).
///
/// # Errors
/// An override that names no coordinate from `first` on.
pub fn per_coordinate(
    model: &Model,
    p: &PerJoint,
    first: usize,
    what: &str,
) -> Result<Vec<f64>, Error> {
    let mut out = vec![0.0; model.nv];
    for x in &mut out[first..] {
        *x = p.all;
    }
    for (name, &x) in &p.joints {
        let covers = |v: &str| {
            v == name
                || v.strip_prefix(name.as_str())
                    .is_some_and(|rest| rest.starts_with('.') || rest.starts_with(':'))
        };
        let hits: Vec<usize> = (0..model.nv)
            .filter(|&k| covers(&model.v_names[k]))
            .collect();
        if hits.is_empty() || hits.iter().all(|&k| k < first) {
            let why = if hits.is_empty() {
                "no coordinate of the model is named so"
            } else {
                "those are the floating root's coordinates, which get no damping"
            };
            // examples from the joints, past a floating avatar's root coordinates
            let from = first.max(dynamics::floating_root_nv(model));
            return Err(Error::Invalid(format!(
                "{what} {name}={x}: {why} (joints' coordinates are e.g. {})",
                model.v_names[from.min(model.nv.saturating_sub(1))..]
                    .iter()
                    .take(3)
                    .cloned()
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
        for k in hits.into_iter().filter(|&k| k >= first) {
            out[k] = x;
        }
    }
    Ok(out)
}

/// Parses repeatable `--FLAG X` / `--FLAG JOINT=X` values into `into` (a plain value sets
/// every coordinate's, `JOINT=X` one joint's or coordinate's), each `≥ 0` and finite. `unit`
/// and `example` complete the error message.
pub fn parse_per_joint(
    flag: &str,
    values: &[String],
    into: &mut PerJoint,
    unit: &str,
    example: &str,
) -> Result<(), Error> {
    for d in values {
        let (name, x) = match d.split_once('=') {
            Some((name, x)) => (Some(name.trim()), x),
            None => (None, d.as_str()),
        };
        let bad = || {
            Error::Invalid(format!(
                "--{flag} {d}: expected X or JOINT=X with X ≥ 0 ({unit}), e.g. {example}"
            ))
        };
        let x: f64 = x.trim().parse().map_err(|_| bad())?;
        if !(x.is_finite() && x >= 0.0) {
            return Err(bad());
        }
        match name {
            Some(n) => {
                into.joints.insert(n.to_string(), x);
            }
            None => into.all = x,
        }
    }
    Ok(())
}

/// Generalized states over time: `q` (nq per sample), `v` and `a` (nv per sample), SI.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct States {
    /// Sample times (s).
    pub time: Vec<f64>,
    pub q: Vec<Vec<f64>>,
    pub v: Vec<Vec<f64>>,
    pub a: Vec<Vec<f64>>,
}

impl States {
    pub fn len(&self) -> usize {
        self.time.len()
    }
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }
}

/// A loaded take: the file, what was detected, the model and its states.
#[derive(Debug, Clone)]
pub struct Take {
    pub path: PathBuf,
    pub bvh: Bvh,
    pub options: TakeOptions,
    pub up: UpAxis,
    /// The unit used (detected or given); with `--stature`, the scale is in `scale_to_m`.
    pub unit: String,
    /// Metres per file length unit.
    pub scale_to_m: f64,
    /// Rest-pose stature (m) after scaling.
    pub stature_m: f64,
    /// The table that gave the segment masses (with `stature_m` for the regression); `None`:
    /// no trunk among the joint names, link masses by bone volume.
    pub segments: Option<SegmentTable>,
    pub positions: Vec<ResolvedPosition>,
    pub model: Model,
    pub map: BvhMap,
    /// The smoothing applied: the one given, or the default that fits the take.
    pub smooth: SmoothSpec,
    /// A massless helper root folded into its child (`motion::fold`): `bvh` holds the folded
    /// motion, this the file's root channels, so outputs can give the root motion back.
    pub fold: Option<crate::motion::fold::Fold>,
    /// The position channels held at their mean (`motion::weld`): `bvh` holds them so, as the
    /// model does.
    pub welded: Vec<crate::motion::weld::Welded>,
    /// The joints inside a human's long bones and whether each was folded into the next joint
    /// as a twist helper (`motion::twist`): `bvh` holds the folded motion, as the model does.
    pub twists: Vec<crate::motion::twist::Twist>,
    /// q, v, a after unwrapping, smoothing and differentiation.
    pub states: States,
    /// What stages 5–7 found (passages near gimbal lock, capture glitches), also in `notes`.
    pub passages: Vec<String>,
    /// What the loader changed on its own, for `info` (e.g. a folded helper root).
    pub notes: Vec<String>,
    /// The skeleton's human landmarks (`model::skeleton`), or why it is not a human's.
    pub human: Result<crate::model::skeleton::Human, String>,
}

/// Stages 1–7 of the module doc.
pub fn load_take(path: &Path, opts: &TakeOptions) -> Result<Take, Error> {
    load_take_marked(path, None, opts, &mut |_| {})
}

/// [`load_take`] that calls `done` at the end of each stage ([`Stage`]); `text`, when given,
/// is the file's content already read (the bench's cycled take), else the file is read.
pub fn load_take_marked(
    path: &Path,
    text: Option<&[u8]>,
    opts: &TakeOptions,
    done: &mut dyn FnMut(Stage),
) -> Result<Take, Error> {
    // read; a rest pose stored as frame 0 (CMU conversions) is dropped
    let (bvh, note) = match text {
        Some(bytes) => trim_take(bvh::parse_bytes(bytes, path)?, opts.keep_first_frame),
        None => read_take(path, opts.keep_first_frame)?,
    };
    done(Stage::Parse);
    let mut take = take_from_bvh_marked(path, bvh, opts, &mut |_| true, done)?;
    take.notes.extend(note);
    Ok(take)
}

/// Stage 1: parses a BVH and, unless `keep_first_frame`, drops its frame 0 when that is a rest
/// pose before the motion (`motion::trim`); the note says so, for `info`.
pub fn read_take(path: &Path, keep_first_frame: bool) -> Result<(Bvh, Option<String>), Error> {
    Ok(trim_take(bvh::read(path)?, keep_first_frame))
}

/// The trimming half of [`read_take`].
fn trim_take(mut bvh: Bvh, keep_first_frame: bool) -> (Bvh, Option<String>) {
    if keep_first_frame {
        return (bvh, None);
    }
    let note = crate::motion::trim::trim_rest_first_frame(&mut bvh).map(|r| {
        format!(
            "frame 0 was dropped: a rest pose, not part of the motion (its step to frame 1 is \
             {:.0}× the median frame-to-frame step of the rotations, {:.0}× of the root \
             position); --keep-first-frame keeps it",
            r.rotation_ratio, r.position_ratio
        )
    });
    (bvh, note)
}

/// Stages 2–7 on an already parsed take.
pub fn take_from_bvh(path: &Path, bvh: Bvh, opts: &TakeOptions) -> Result<Take, Error> {
    take_from_bvh_with(path, bvh, opts, &mut |_| true)
}

/// [`take_from_bvh`] that reports its progress (0‥1) to `keep_going` (the smoothing once per
/// coordinate group, [`unwrap_and_smooth_with`]) and stops with [`Error::Cancelled`] when it
/// returns false.
pub fn take_from_bvh_with(
    path: &Path,
    bvh: Bvh,
    opts: &TakeOptions,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<Take, Error> {
    take_from_bvh_marked(path, bvh, opts, keep_going, &mut |_| {})
}

/// [`take_from_bvh_with`] that calls `done` at the end of each stage ([`Stage::Model`], then
/// those of [`take_states_marked`]).
pub fn take_from_bvh_marked(
    path: &Path,
    bvh: Bvh,
    opts: &TakeOptions,
    keep_going: &mut dyn FnMut(f64) -> bool,
    done: &mut dyn FnMut(Stage),
) -> Result<Take, Error> {
    take_from_bvh_reusing(path, bvh, opts, None, keep_going, done)
}

/// [`take_from_bvh_marked`] that takes the states (stages 5–7: q, unwrap, smoothing, v, a)
/// from `previous`, a take of the same file, when they are the ones it would compute: the
/// same motion after the model stage's folds and welds, the same coordinates and joint kinds,
/// the same smoothing. The states read no mass, so an edit of the body mass, the sex, the
/// segment table or a link's mass keeps them: only the model (stages 2–4) is built again, and
/// `done` is called for [`Stage::Model`] alone. The result is the same, bit for bit, as
/// without `previous`.
pub fn take_from_bvh_reusing(
    path: &Path,
    mut bvh: Bvh,
    opts: &TakeOptions,
    previous: Option<&Take>,
    keep_going: &mut dyn FnMut(f64) -> bool,
    done: &mut dyn FnMut(Stage),
) -> Result<Take, Error> {
    // axes and unit
    let mut notes = vec![];
    let named_human =
        crate::model::anthropometry::looks_human(bvh.joints.iter().map(|j| j.name.as_str()));
    let positions = bvh::resolve_position_modes(&bvh, opts.positions);
    // the skeleton's geometry as the model holds it and any BVH written of the take says it:
    // below the body's root, position channels at their mean in the OFFSETs
    // (`motion::weld::held_shape`; with `--joint-translations keep` too, where the channels
    // move about that mean), so that the take written and read back gets the same up axis,
    // unit, stature, landmarks and segments
    let held_shape = crate::motion::weld::held_shape(&bvh, opts.positions);
    let (shape, shape_positions) = match &held_shape {
        Some((b, m)) => (b, m.as_slice()),
        None => (&bvh, positions.as_slice()),
    };
    let up = match opts.up {
        Some(u) => u,
        // hips stand over the feet, however the body bends
        None if named_human => {
            let joints: Vec<(&str, Option<usize>)> = bvh
                .joints
                .iter()
                .map(|j| (j.name.as_str(), j.parent))
                .collect();
            let (hips, feet) = crate::model::anthropometry::hips_and_feet(&joints);
            bvh::detect_up_by_legs(shape, &hips, &feet).unwrap_or_else(|| bvh::detect_up(shape))
        }
        // a quadruped is longer than tall: its feet tell where the floor is
        None => bvh::detect_up_by_feet(shape).unwrap_or_else(|| bvh::detect_up(shape)),
    };
    // a human whose names say nothing (`J1`, `J2`, …) is one by its shape: two legs under an
    // upright trunk (`model::skeleton`); then the hips stand over its ankles
    let mut up = up;
    let mut human = named_human;
    // (about the axis along which its trunk stands most upright)
    let sampled = anatomy::sample_bvh_poses(shape, shape_positions);
    if !named_human {
        let axes = match opts.up {
            Some(u) => vec![u],
            None => vec![UpAxis::X, UpAxis::Y, UpAxis::Z],
        };
        if let Some((axis, h)) = axes
            .into_iter()
            .filter_map(|a| {
                anatomy::human_of_bvh(shape, &sampled, a)
                    .ok()
                    .map(|h| (a, h))
            })
            // about another axis than the detected one, only a body that stands (its trunk
            // within 30° of the vertical in the median frame): an animal on its side does not
            .filter(|(a, h)| *a == up || h.lean < 30f64.to_radians())
            .min_by(|a, b| a.1.lean.total_cmp(&b.1.lean))
        {
            human = true;
            let hips = [h.legs[0].hip, h.legs[1].hip];
            let ankles = [h.legs[0].ankle, h.legs[1].ankle];
            up = match opts.up {
                Some(u) => u,
                None => bvh::detect_up_by_legs(shape, &hips, &ankles).unwrap_or(axis),
            };
        }
    }
    let scale = bvh::choose_scale(shape, up, opts.unit, opts.stature_m, human)
        .map_err(|e| at_file(path, e))?;
    // a human's segments by topology and geometry (names only as hints)
    let in_metres: Vec<_> = sampled.iter().map(|p| p.scaled(scale.scale_to_m)).collect();
    let landmarks = anatomy::human_of_bvh(shape, &in_metres, up);
    let trunk = crate::model::anthropometry::has_trunk(bvh.joints.iter().map(|j| j.name.as_str()));
    if landmarks.is_err() && !trunk {
        notes.push(
            "neither the shape (two legs under an upright trunk) nor a joint name reads as a \
             human's: link masses follow bone volume (de Leva's segment table needs a trunk)"
                .into(),
        );
    } else if landmarks.is_err() {
        // a biped rig's names on an animal (3ds Max `Bip01_Pelvis` on an elephant)
        notes.push(
            "not a human skeleton, but a joint name reads as a trunk: link masses follow the \
             human segment table (--segments: regression on mass and stature, or de Leva's \
             fractions) by the joint names, the missing segments' mass given to the trunk"
                .into(),
        );
    }
    let (unit, scale_to_m, mut stature_m) = (scale.unit, scale.scale_to_m, scale.stature_m);
    // a human's stature from its own dimensions, the same whatever its rest pose, so that the
    // same body written another way gets the same masses; a given stature always wins
    // (one scaled to a stature, given or fitted, keeps it)
    if opts.stature_m.is_none()
        && unit != "stature"
        && let Ok(h) = &landmarks
        && h.standing_height > 0.0
    {
        stature_m = h.standing_height;
    }
    notes.extend(scale.note);
    if bvh.frame_time < MIN_PLAUSIBLE_FRAME_TIME_S {
        notes.push(format!(
            "the frame time, {} s ({:.0} fps), is shorter than any capture system's: check the \
             file's Frame Time (velocities scale with it, accelerations with its square)",
            bvh.frame_time,
            1.0 / bvh.frame_time
        ));
    }
    if bvh.frames < 3 {
        notes.push(format!(
            "the take has {} frame{}: velocities and accelerations need three frames or more \
             (they are {} here), so the torques hold gravity and the pose alone",
            bvh.frames,
            if bvh.frames == 1 { "" } else { "s" },
            if bvh.frames == 1 {
                "zero"
            } else {
                "one difference, and zero"
            }
        ));
    }

    // model
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "take".into());
    // the body at the take's stature (the regression's second variable)
    let body = BodyParams {
        height_m: Some(stature_m),
        ..opts.body.clone()
    };
    let segments = if trunk || landmarks.is_ok() {
        let masses =
            crate::model::anthropometry::segment_masses(&body).map_err(|e| at_file(path, e))?;
        notes.extend(masses.notes);
        let radii =
            crate::model::anthropometry::segment_radii(&body).map_err(|e| at_file(path, e))?;
        notes.extend(radii.notes);
        Some(masses.table)
    } else {
        None
    };
    // `--lock auto:TOL` applies once the take's states are known (below)
    let (auto_lock, named_locks) = reduce::split_lock(&opts.lock)?;
    let mut mopts = BvhModelOptions {
        name,
        joints: opts.joints,
        scale_to_m,
        up,
        positions: positions.clone(),
        body,
        lock: named_locks,
        subtree: opts.subtree.clone(),
        segments: None,
        held_positions: vec![],
        folded: vec![],
        bone_offsets: (held_shape.as_ref())
            .map(|(b, _)| b.joints.iter().map(|j| j.offset).collect())
            .unwrap_or_default(),
    };
    let human = landmarks;
    if let Ok(h) = &human {
        let (segments, props, branches) = anatomy::segments_of(shape, h);
        mopts.segments = Some(segments);
        if !branches.is_empty() {
            notes.push(format!(
                "massless and welded (they branch off a long bone between two joints of a limb: \
                 twist or deformation helpers, no body part; the segment's mass stays on the \
                 limb's own joints): {}",
                branches.join(", ")
            ));
            for b in branches {
                if !mopts.lock.contains(&b) {
                    mopts.lock.push(b);
                }
            }
        }
        if !props.is_empty() {
            notes.push(format!(
                "massless and welded (they reach farther than half a thigh from a hand, foot or \
                 head: a prop or a marker, not a body part; a massless joint would make D(q) \
                 singular): {}",
                props.join(", ")
            ));
            for p in props {
                if !mopts.lock.contains(&p) {
                    mopts.lock.push(p);
                }
            }
        }
    }
    let (mut model, mut map) = build_bvh_model(&bvh, &mopts).map_err(|e| at_file(path, e))?;

    // a massless helper root whose only child has six channels of its own (Bandai's
    // `joint_Root` above `Hips`) duplicates the child's coordinates and makes D(q) singular:
    // fold its motion into the child and weld it (`motion::fold`)
    let mut fold = None;
    let mut pelvis = None; // below a helper root: it carries the body too (`motion::weld`)
    if let Some(c) = crate::motion::fold::redundant_root_child(&bvh) {
        let root_body = map.joints[0].body;
        let root = bvh.joints[0].name.clone();
        let overridden = opts.body.link_mass.contains_key(&root);
        let massless = root_body != 0 && model.inertia[root_body].mass == 0.0;
        if massless || (root_body != 0 && overridden) {
            pelvis = Some(c);
        }
        if massless && !overridden {
            fold = Some(crate::motion::fold::Fold::record(&bvh, c));
            crate::motion::fold::fold_root_into_child(&mut bvh, &positions, c);
            mopts.lock.push(root.clone());
            notes.push(format!(
                "root `{root}` is massless and `{}` has six channels of its own: its motion \
                 was folded into `{}` and it was welded (its coordinates were redundant)",
                bvh.joints[c].name, bvh.joints[c].name
            ));
        }
    }

    // bones do not stretch: the position channels of the joints below the body's root are
    // held at their mean, in the frames and in the model (`motion::weld`)
    let welded = match opts.joint_translations {
        JointTranslations::Weld => {
            crate::motion::weld::weld_at_mean(&mut bvh, &positions, scale_to_m, pelvis)
        }
        JointTranslations::Keep => vec![],
    };
    notes.extend(crate::motion::weld::note(&bvh, &welded));

    // twist helpers inside a long bone (no segment of their own) are folded into the next
    // joint when they only turn the limb about the bone, and made massless (`motion::twist`);
    // a helper whose translation is a coordinate (`--joint-translations keep`) stays
    let twists = match &human {
        Ok(h) => {
            let names: Vec<&str> = bvh.joints.iter().map(|j| j.name.as_str()).collect();
            let parent: Vec<Option<usize>> = bvh.joints.iter().map(|j| j.parent).collect();
            let topo = crate::model::skeleton::Topology {
                names: &names,
                parent: &parent,
            };
            let held =
                |j: usize| !bvh.joints[j].has_position() || welded.iter().any(|w| w.joint == j);
            let inside: Vec<usize> = crate::model::skeleton::inside_long_bones(&topo, h)
                .into_iter()
                .filter(|&j| held(j) && !mopts.lock.contains(&bvh.joints[j].name))
                .collect();
            crate::motion::twist::fold_twists(&mut bvh, &positions, scale_to_m, &inside)
        }
        Err(_) => vec![],
    };
    notes.extend(crate::motion::twist::note(&bvh, &twists));
    mopts.folded = crate::motion::twist::folded(&twists);
    if fold.is_some() || !welded.is_empty() || !mopts.folded.is_empty() {
        mopts.held_positions = crate::motion::weld::held_positions(&welded, bvh.joints.len());
        (model, map) = build_bvh_model(&bvh, &mopts).map_err(|e| at_file(path, e))?;
    }
    apply_damping(&mut model, &opts.damping).map_err(|e| at_file(path, e))?;

    // q, smooth, v, a
    if !keep_going(0.1) {
        return Err(Error::Cancelled);
    }
    let smooth = match opts.smooth {
        Some(s) => s,
        None => {
            let (s, note) = default_smoothing(bvh.frame_time);
            notes.extend(note);
            s
        }
    };
    done(Stage::Model);
    let same_states = |p: &&Take| {
        p.smooth == smooth
            && p.model.q_names == model.q_names
            && p.model.v_names == model.v_names
            && p.model.joints == model.joints
            && p.model.parent == model.parent
            && p.model.idx_q == model.idx_q
            && p.map == map
            && p.bvh == bvh
    };
    let (states, passages) = match previous.filter(same_states) {
        Some(p) => (p.states.clone(), p.passages.clone()),
        None => take_states_marked(
            &bvh,
            &model,
            &map,
            &smooth,
            &mut |f| keep_going(0.1 + 0.9 * f),
            done,
        )?,
    };
    notes.extend(passages.iter().cloned());
    let take = Take {
        path: path.to_path_buf(),
        bvh,
        options: opts.clone(),
        up,
        unit,
        scale_to_m,
        stature_m,
        segments,
        positions,
        model,
        map,
        smooth,
        fold,
        welded,
        twists,
        states,
        passages,
        notes,
        human,
    };
    match auto_lock {
        Some(tol) => reduce::lock_auto(take, tol),
        None => Ok(take),
    }
}

fn at_file(path: &Path, e: Error) -> Error {
    match e {
        Error::Invalid(m) => Error::Invalid(format!("{}: {m}", path.display())),
        other => other,
    }
}

/// Where a job's model comes from.
#[derive(Debug, Clone)]
pub enum ModelSource {
    Take(PathBuf),
    /// A URDF and its options (fixed or floating base, gravity).
    Urdf(PathBuf, crate::model::urdf::UrdfOptions),
    Dh(PathBuf),
}

/// A model and states to run an algorithm on (a take, or a robot with a states file).
#[derive(Debug, Clone)]
pub struct Job {
    pub model: Model,
    pub states: States,
    /// The take, when the source is one (for contact and reports).
    pub take: Option<Take>,
    /// Measured ground reactions (`id --grf`, [`measured::use_measured_grf`]), used instead
    /// of the estimate.
    pub measured: Option<crate::dynamics::grf::GroundReactions>,
    /// The ground reactions estimated on `take` as it is, kept by
    /// [`consistency::consistent_job`] (which needs them for its figures) so that
    /// [`job_torques`] does not estimate them a second time.
    pub estimated: Option<crate::dynamics::grf::GroundReactions>,
}

impl Job {
    /// A take's job: its model and its own states.
    pub fn from_take(take: Take) -> Self {
        Self {
            model: take.model.clone(),
            states: take.states.clone(),
            take: Some(take),
            measured: None,
            estimated: None,
        }
    }
}

/// Loads only the model of a source (for `bench`).
pub fn load_model(src: &ModelSource, opts: &TakeOptions) -> Result<Model, Error> {
    Ok(match src {
        ModelSource::Take(p) => load_take(p, opts)?.model,
        ModelSource::Urdf(..) | ModelSource::Dh(_) => robot_model(src, opts)?,
    })
}

/// A URDF or DH model with the options that apply to robots (damping).
fn robot_model(src: &ModelSource, opts: &TakeOptions) -> Result<Model, Error> {
    let mut model = match src {
        ModelSource::Urdf(p, o) => crate::model::urdf::read_urdf(p, o)?,
        ModelSource::Dh(p) => crate::model::dh::build_dh_model(&crate::io::dh::read(p)?)?,
        ModelSource::Take(p) => return Ok(load_take(p, opts)?.model),
    };
    apply_damping(&mut model, &opts.damping)?;
    Ok(model)
}

/// Loads a model and its states: a take's own states, or a states CSV (required for robots)
/// with every column, accelerations included.
pub fn load_source(
    src: &ModelSource,
    states: Option<&Path>,
    opts: &TakeOptions,
) -> Result<Job, Error> {
    load_source_with(src, states, opts, StateColumns::QVA)
}

/// [`load_source`] for a job that needs only the `columns` of a states CSV.
pub fn load_source_with(
    src: &ModelSource,
    states: Option<&Path>,
    opts: &TakeOptions,
    columns: StateColumns,
) -> Result<Job, Error> {
    load_source_marked(src, states, opts, columns, None, &mut |_| {})
}

/// [`load_source_with`] that calls `done` at the end of each stage ([`load_take_marked`],
/// then [`Stage::Job`]); `text` is the take's content already read, if any.
pub fn load_source_marked(
    src: &ModelSource,
    states: Option<&Path>,
    opts: &TakeOptions,
    columns: StateColumns,
    text: Option<&[u8]>,
    done: &mut dyn FnMut(Stage),
) -> Result<Job, Error> {
    let (model, own, take) = match src {
        ModelSource::Take(p) => {
            let t = load_take_marked(p, text, opts, done)?;
            (t.model.clone(), Some(t.states.clone()), Some(t))
        }
        ModelSource::Urdf(..) | ModelSource::Dh(_) => (robot_model(src, opts)?, None, None),
    };
    let states = match (states, own) {
        (Some(s), _) => read_states_with(&model, s, columns)?,
        (None, Some(own)) => own,
        (None, None) => {
            return Err(Error::Invalid(format!(
                "a robot model needs --states S.csv ({})",
                columns.expected()
            )));
        }
    };
    done(Stage::Job);
    Ok(Job {
        model,
        states,
        take,
        measured: None,
        estimated: None,
    })
}

/// Header of a states CSV for `model`: `time`, `q:<coord>`…, `v:<coord>`…, `a:<coord>`….
pub fn states_header(model: &Model) -> Vec<String> {
    let mut h = vec!["time".to_string()];
    h.extend(model.q_names.iter().map(|n| columns::name("q", &[n])));
    h.extend(model.v_names.iter().map(|n| columns::name("v", &[n])));
    h.extend(model.v_names.iter().map(|n| columns::name("a", &[n])));
    h
}

/// The columns a job needs from a states CSV. Forward dynamics computes the accelerations
/// from q, v and τ, so a states file without `a:` columns must do for it; inverse dynamics
/// needs them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StateColumns {
    /// `q:`, `v:` and `a:` for every coordinate.
    QVA,
    /// `q:` and `v:`; `a:` columns are optional (read when present, else zero).
    QV,
}

impl StateColumns {
    /// What a states file must hold, for error messages.
    fn expected(self) -> &'static str {
        match self {
            StateColumns::QVA => "`time`, then q:, v:, a: columns",
            StateColumns::QV => "`time`, then q: and v: columns; a: columns optional",
        }
    }
}

/// Reads a states CSV written by `export states` (columns matched by name, any order; extra
/// columns ignored; `time` optional), every column required.
pub fn read_states(model: &Model, path: &Path) -> Result<States, Error> {
    read_states_with(model, path, StateColumns::QVA)
}

/// [`read_states`] needing only `columns`; a missing one is an error naming the first
/// missing column, in the file's order (q:, v:, then a:).
pub fn read_states_with(
    model: &Model,
    path: &Path,
    columns: StateColumns,
) -> Result<States, Error> {
    let (header, cols) = read_columns(path)?;
    let column = |name: &str| header.iter().position(|h| h == name).map(|i| &cols[i]);
    let find = |name: &str| -> Result<&Vec<f64>, Error> {
        column(name).ok_or_else(|| {
            Error::Invalid(format!(
                "{}: no column `{name}` (expected {} for {})",
                path.display(),
                columns.expected(),
                model.name
            ))
        })
    };
    // without a `time` column (e.g. the Pinocchio fixtures) samples are numbered 0, 1, 2 …
    let n = cols.first().map_or(0, |c| c.len());
    let time = match header.iter().position(|h| h == "time") {
        Some(i) => cols[i].clone(),
        None => (0..n).map(|k| k as f64).collect(),
    };
    let mut s = States {
        time,
        q: vec![vec![0.0; model.nq]; n],
        v: vec![vec![0.0; model.nv]; n],
        a: vec![vec![0.0; model.nv]; n],
    };
    for (j, name) in model.q_names.iter().enumerate() {
        let c = find(&columns::name("q", &[name]))?;
        for (row, x) in s.q.iter_mut().zip(c) {
            row[j] = *x;
        }
    }
    for (j, name) in model.v_names.iter().enumerate() {
        let cv = find(&columns::name("v", &[name]))?;
        for (row, x) in s.v.iter_mut().zip(cv) {
            row[j] = *x;
        }
    }
    for (j, name) in model.v_names.iter().enumerate() {
        let a = columns::name("a", &[name]);
        let ca = match columns {
            StateColumns::QVA => find(&a)?,
            StateColumns::QV => match column(&a) {
                Some(c) => c,
                None => continue,
            },
        };
        for (row, x) in s.a.iter_mut().zip(ca) {
            row[j] = *x;
        }
    }
    Ok(s)
}

pub(crate) fn write_rows(path: &Path, header: Vec<String>, rows: &[Vec<f64>]) -> Result<(), Error> {
    let ncol = header.len();
    let mut cols: Vec<Vec<f64>> = vec![Vec::with_capacity(rows.len()); ncol];
    for r in rows {
        for (c, x) in cols.iter_mut().zip(r) {
            c.push(*x);
        }
    }
    let refs: Vec<&[f64]> = cols.iter().map(|c| c.as_slice()).collect();
    write_columns(path, &header, &refs)
}

/// `articula export states`.
pub fn export_states(take: &Take, path: &Path) -> Result<(), Error> {
    table::take_states_table(take).write_csv(path)
}

/// `articula export positions`: world position of every BVH joint, `pos:<joint>:x|y|z` (m, the
/// take's own axes), straight from the BVH definition (independent of the model).
pub fn export_positions(take: &Take, path: &Path) -> Result<(), Error> {
    let c = joint_centres(take);
    let mut header = vec!["time".to_string()];
    for name in &c.names {
        for a in ["x", "y", "z"] {
            header.push(columns::name("pos", &[name, a]));
        }
    }
    let rows: Vec<Vec<f64>> = (0..c.time.len())
        .map(|k| {
            let mut r = vec![c.time[k]];
            r.extend(c.positions[k].iter().flatten());
            r
        })
        .collect();
    write_rows(path, header, &rows)
}

/// The world positions of a take's joints (`export positions`, `export trc`).
#[derive(Debug, Clone)]
pub struct JointCentres {
    /// The BVH joints' names, in file order.
    pub names: Vec<String>,
    /// Frame times (s, the file's clock: [`Bvh::time`]).
    pub time: Vec<f64>,
    /// `[frame][joint]`: world position (m, the take's own axes).
    pub positions: Vec<Vec<[f64; 3]>>,
}

/// Every BVH joint's world position per frame, straight from the BVH definition (independent
/// of the model), a folded helper root given its motion back ([`as_in_file`]).
pub fn joint_centres(take: &Take) -> JointCentres {
    let b = &as_in_file(take, take.bvh.clone());
    let positions = (0..b.frames)
        .map(|k| {
            bvh::bvh_world_positions(b, &take.positions, k)
                .iter()
                .map(|x| [x.x, x.y, x.z].map(|c| c * take.scale_to_m))
                .collect()
        })
        .collect();
    JointCentres {
        names: b.joints.iter().map(|j| j.name.clone()).collect(),
        time: (0..b.frames).map(|k| b.time(k)).collect(),
        positions,
    }
}

/// `b` (the take's skeleton, its frames possibly rewritten) with a folded helper root's motion
/// given back to the root, as the file had it ([`Take::fold`]).
pub(crate) fn as_in_file(take: &Take, mut b: Bvh) -> Bvh {
    if let Some(f) = &take.fold {
        crate::motion::fold::unfold_root(&mut b, &take.positions, f);
    }
    b
}

/// `articula export urdf`.
pub fn export_urdf(take: &Take, path: &Path) -> Result<(), Error> {
    let text = crate::io::urdf_write::model_to_urdf(&take.model)?;
    crate::io::write_atomic(path, text.as_bytes())
}

/// Generalized forces per sample (`nv` each), and optional ground reaction columns.
#[derive(Debug, Clone)]
pub struct Torques {
    pub time: Vec<f64>,
    pub names: Vec<String>,
    pub tau: Vec<Vec<f64>>,
}

/// Inverse dynamics over every sample of a job.
pub fn inverse_dynamics(model: &Model, states: &States) -> Torques {
    inverse_dynamics_with(model, states, &mut |_| true)
}

/// Samples between two calls of a progress callback.
pub const PROGRESS_EVERY: usize = 64;

/// [`inverse_dynamics`] that reports its progress (0‥1) to `keep_going` every
/// [`PROGRESS_EVERY`] samples and stops when it returns false: then `tau` holds only the
/// samples computed so far (fewer than `states.len()`). Frames in parallel ([`par::rounds`]),
/// each worker with one [`Workspace`] made once.
pub fn inverse_dynamics_with(
    model: &Model,
    states: &States,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Torques {
    let n = states.len();
    let mut tau = vec![vec![0.0; model.nv]; n];
    let mut workspaces = par::scratch(|| Workspace::new(model));
    let reached = par::rounds(
        &mut tau,
        PROGRESS_EVERY,
        &mut workspaces,
        |ws, first, rows| {
            for (i, row) in rows.iter_mut().enumerate() {
                let k = first + i;
                let t = dynamics::rnea(model, ws, &states.q[k], &states.v[k], &states.a[k], None);
                row.copy_from_slice(t.as_slice());
            }
        },
        &mut |k| keep_going(k as f64 / n as f64),
    );
    tau.truncate(reached);
    Torques {
        time: states.time.clone(),
        names: model.v_names.clone(),
        tau,
    }
}

/// `articula id`: `time`, `tau:<coord>` per coordinate (N·m or N); with `--contact feet` the torques
/// are those with the ground reactions applied and `grf:<foot>:x|y|z`, `cop:<foot>:x|y|z`,
/// `residual:fx|fy|fz|tx|ty|tz` follow (N, m, N·m; world axes of the take), and the result is
/// how far the feet could give the ground force the motion needs
/// ([`GroundReactions::quality`](crate::dynamics::grf::GroundReactions::quality)).
pub fn write_inverse_dynamics(job: &Job, path: &Path) -> Result<IdOutcome, Error> {
    let (table, t, grf) = table::inverse_dynamics_parts(job)?;
    table.write_csv(path)?;
    Ok(IdOutcome::new(job, &t, grf.as_deref()))
}

/// What `articula id` found besides its file: the ground reactions' quality (estimated forces)
/// and the `--json` figures.
#[derive(Debug, Clone)]
pub struct IdOutcome {
    pub quality: Option<crate::dynamics::grf::GroundQuality>,
    pub summary: summary::IdSummary,
}

impl IdOutcome {
    pub(crate) fn new(
        job: &Job,
        t: &Torques,
        grf: Option<&crate::dynamics::grf::GroundReactions>,
    ) -> Self {
        Self {
            quality: grf.map(|g| g.quality()),
            summary: summary::id_summary(job, t, grf),
        }
    }
}

/// A job's generalized forces, with the ground reactions applied when the take has contact
/// (then also those reactions: the job's own, borrowed, when it holds measured or estimated
/// ones); an error when a torque is not finite.
pub fn job_torques(
    job: &Job,
) -> Result<
    (
        Torques,
        Option<Cow<'_, crate::dynamics::grf::GroundReactions>>,
    ),
    Error,
> {
    job_torques_marked(job, &mut |_| {})
}

/// [`job_torques`] that calls `done` at the end of [`Stage::Contact`] (the ground reactions,
/// when the take has contact) and of [`Stage::InverseDynamics`].
pub fn job_torques_marked<'j>(
    job: &'j Job,
    done: &mut dyn FnMut(Stage),
) -> Result<
    (
        Torques,
        Option<Cow<'j, crate::dynamics::grf::GroundReactions>>,
    ),
    Error,
> {
    let grf = match (&job.measured, &job.estimated, &job.take) {
        (Some(m), _, _) => Some(Cow::Borrowed(m)),
        (None, Some(e), _) => Some(Cow::Borrowed(e)),
        (None, None, Some(t)) => ground_reactions(t)?.map(Cow::Owned),
        (None, None, None) => None,
    };
    done(Stage::Contact);
    // with ground reactions, their estimate's torques are the answer (it ran RNEA with them)
    let t = match &grf {
        Some(g) => Torques {
            time: job.states.time.clone(),
            names: job.model.v_names.clone(),
            tau: g.tau.clone(),
        },
        None => inverse_dynamics(&job.model, &job.states),
    };
    check_finite(&t.tau, &t.names, "torque")?;
    done(Stage::InverseDynamics);
    Ok((t, grf))
}

fn check_finite(rows: &[Vec<f64>], names: &[String], what: &str) -> Result<(), Error> {
    for (k, r) in rows.iter().enumerate() {
        if let Some(j) = r.iter().position(|x| !x.is_finite()) {
            return Err(Error::Numerical(format!(
                "{what} of `{}` is not finite at sample {k}; nothing written",
                names.get(j).map(String::as_str).unwrap_or("?")
            )));
        }
    }
    Ok(())
}

/// `articula fd`: accelerations `a:<coord>` from states and a torques CSV (`tau:<coord>`, as
/// `articula id` writes; a coordinate's bare name, as `id` wrote before 0.x, is read too).
pub fn write_forward_dynamics(job: &Job, torques: &Path, path: &Path) -> Result<(), Error> {
    let m = &job.model;
    let (header, cols) = read_columns(torques)?;
    if header.iter().any(|h| h.starts_with("grf:")) {
        return Err(Error::Invalid(format!(
            "{}: these torques were computed with ground reactions (its `grf:` columns: \
             `articula id` with contact feet, the default on a take that stands); fd has no \
             contact model, so they would not give the motion back; write them with \
             `articula id --contact none`",
            torques.display()
        )));
    }
    let mut idx = Vec::with_capacity(m.nv);
    for n in &m.v_names {
        let tau = columns::name("tau", &[n]);
        let at = |name: &str| header.iter().position(|h| h == name);
        idx.push(at(&tau).or_else(|| at(n)).ok_or_else(|| {
            Error::Invalid(format!(
                "{}: no torque column `{tau}` (write it with `articula id`)",
                torques.display()
            ))
        })?);
    }
    let n = job.states.len();
    if cols.first().map_or(0, |c| c.len()) != n {
        return Err(Error::Invalid(format!(
            "{}: {} rows of torques for {n} states",
            torques.display(),
            cols.first().map_or(0, |c| c.len())
        )));
    }
    let mut ws = Workspace::new(m);
    let mut rows = Vec::with_capacity(n);
    let s = &job.states;
    let tau_rows = (0..n).map(|k| idx.iter().map(|&c| cols[c][k]).collect::<Vec<f64>>());
    for (k, tau) in tau_rows.enumerate() {
        let a = dynamics::aba(m, &mut ws, &s.q[k], &s.v[k], &tau, None)?;
        let mut r = vec![s.time[k]];
        r.extend(a.iter());
        rows.push(r);
    }
    let mut h = vec!["time".to_string()];
    h.extend(m.v_names.iter().map(|n| columns::name("a", &[n])));
    write_rows(path, h, &rows)
}

/// `articula mass-matrix`: D(q) row-major per sample, columns `M:<i>:<j>`.
pub fn write_mass_matrix(job: &Job, path: &Path) -> Result<(), Error> {
    let m = &job.model;
    let mut ws = Workspace::new(m);
    let mut h = vec!["time".to_string()];
    for i in 0..m.nv {
        for j in 0..m.nv {
            h.push(columns::name("M", &[&i.to_string(), &j.to_string()]));
        }
    }
    let s = &job.states;
    let rows: Vec<Vec<f64>> = (0..s.len())
        .map(|k| {
            let d = dynamics::crba(m, &mut ws, &s.q[k]);
            let mut r = vec![s.time[k]];
            for i in 0..m.nv {
                for j in 0..m.nv {
                    r.push(d[(i, j)]);
                }
            }
            r
        })
        .collect();
    write_rows(path, h, &rows)
}

/// `articula generate walk`: the bundled demo take is made this way.
pub fn generate_walk(path: &Path, fps: f64, duration_s: f64, scale: f64) -> Result<(), Error> {
    if !(fps > 0.0 && duration_s > 0.0 && scale > 0.0) {
        return Err(Error::Invalid(
            "generate walk: --fps, --duration and --scale must be positive".into(),
        ));
    }
    let take = crate::io::generate::walk(&crate::io::generate::WalkParams {
        fps,
        duration_s,
        scale,
        ..Default::default()
    });
    let modes = bvh::resolve_position_modes(&take, bvh::PositionMode::Auto);
    bvh::write(&bvh::portable(&take, &modes), path)
}

/// What `articula info` prints.
#[derive(Debug, Clone)]
pub struct Info<'a> {
    take: &'a Take,
}

/// Describes a loaded take.
pub fn info(take: &Take) -> Info<'_> {
    Info { take }
}

impl Info<'_> {
    /// The `--json` summary: the keys joints, frames, frame_time, nq, nv, scale_to_m,
    /// stature_m, up, gravity, mass_kg, unit, smooth (the smoothing applied), segments (the
    /// table of segment masses: `regression`, `fractions`, or `bone_volume` when no trunk is
    /// named), segments_stature_m (the stature the regression used, else null), human
    /// ([`Info::landmarks`]), contact (`feet` or `none`: what `--contact` gives the take,
    /// `auto` settled by [`resolve_contact`]), notes (a list of strings: what the pipeline
    /// assumed, changed or found, as `info` prints them) and skeleton (every joint: name,
    /// parent, channels, rotation_order, offset_m; [`summary::skeleton`]).
    pub fn json(&self) -> serde_json::Value {
        let t = self.take;
        let regression = t.segments == Some(SegmentTable::Regression);
        serde_json::json!({
            "joints": t.bvh.joints.len(),
            "frames": t.bvh.frames,
            "frame_time": t.bvh.frame_time,
            "nq": t.model.nq,
            "nv": t.model.nv,
            "scale_to_m": t.scale_to_m,
            "stature_m": t.stature_m,
            "up": t.up.to_string(),
            "gravity": [t.model.gravity.x, t.model.gravity.y, t.model.gravity.z],
            "mass_kg": t.model.total_mass(),
            "unit": t.unit,
            "smooth": t.smooth.to_string(),
            "segments": t.segments.map_or("bone_volume".into(), |s| s.to_string()),
            "segments_stature_m": regression.then_some(t.stature_m),
            "human": self.landmarks(),
            "contact": t.options.contact.to_string(),
            "notes": t.notes,
            "skeleton": summary::skeleton(t),
        })
    }

    /// The human-readable description.
    /// Which joints the skeleton's shape makes the pelvis, the legs' hip, knee and ankle, the
    /// lumbar joint, thorax and head, and the arms' shoulder, elbow and wrist; or why it is not
    /// a human's.
    pub fn landmarks(&self) -> String {
        let t = self.take;
        let name = |j: usize| t.bvh.joints[j].name.as_str();
        let h = match &t.human {
            Ok(h) => h,
            Err(why) => return format!("no ({why})"),
        };
        let mut s = format!("pelvis {}", name(h.pelvis));
        for (side, l) in ["left", "right"].iter().zip(&h.legs) {
            s += &format!(
                "; {side} leg {} / {} / {}",
                name(l.hip),
                name(l.knee),
                name(l.ankle)
            );
        }
        if let Some(sp) = &h.spine {
            s += &format!(
                "; lumbar {}, thorax {}, head {}",
                name(sp.lumbar),
                name(sp.thorax),
                name(sp.head)
            );
            for (side, a) in ["left", "right"].iter().zip(sp.arms.iter().flatten()) {
                s += &format!(
                    "; {side} arm {} / {} / {}",
                    name(a.shoulder),
                    name(a.elbow),
                    name(a.wrist)
                );
            }
        }
        s += if h.sides_from_names {
            " (sides from the names)"
        } else {
            " (sides from forward × up)"
        };
        s
    }

    pub fn text(&self) -> String {
        use std::fmt::Write;
        let t = self.take;
        let b = &t.bvh;
        let mut s = String::new();
        let end_sites: usize = b.joints.iter().map(|j| j.end_sites.len()).sum();
        let _ = writeln!(s, "take        {}", t.path.display());
        let _ = writeln!(
            s,
            "skeleton    {} joints (root `{}`), {} End Sites, {} channels",
            b.joints.len(),
            b.joints.first().map(|j| j.name.as_str()).unwrap_or("?"),
            end_sites,
            b.channel_count
        );
        let _ = writeln!(
            s,
            "motion      {} frames, frame time {} s ({:.3} fps), {:.3} s",
            b.frames,
            b.frame_time,
            1.0 / b.frame_time,
            b.frames.saturating_sub(1) as f64 * b.frame_time
        );
        let _ = writeln!(
            s,
            "unit        {} (scale_to_m {}), stature {:.3} m, up {}",
            t.unit, t.scale_to_m, t.stature_m, t.up
        );
        let g = t.model.gravity;
        let _ = writeln!(s, "gravity     [{}, {}, {}] m/s²", g.x, g.y, g.z);
        let _ = writeln!(s, "human       {}", self.landmarks());
        let _ = writeln!(
            s,
            "model       {} joints, nq {}, nv {}, mass {:.3} kg, smoothing {}",
            t.options.joints,
            t.model.nq,
            t.model.nv,
            t.model.total_mass(),
            t.smooth
        );
        let _ = writeln!(s, "contact     {}", t.options.contact);
        let _ = match t.segments {
            Some(SegmentTable::Regression) => writeln!(
                s,
                "masses      segments: {} ({} kg, stature {:.3} m), rescaled to the body \
                 mass; radii of gyration: de Leva (1996) changed as the same regression of the \
                 moments of inertia changes them; centres of mass: de Leva (1996)",
                SegmentTable::Regression.source(),
                t.options.body.mass_kg,
                t.stature_m
            ),
            Some(table) => writeln!(
                s,
                "masses      segments: {}; centres of mass and radii of gyration: de Leva \
                 (1996)",
                table.source()
            ),
            None => writeln!(
                s,
                "masses      by bone volume (no joint name reads as a trunk)"
            ),
        };
        let _ = writeln!(
            s,
            "joints      (name: channels [rotation order] position channels)"
        );
        for (i, (j, pos)) in b.joints.iter().zip(&t.positions).enumerate() {
            let chans: Vec<&str> = j.channels.iter().map(|c| c.name()).collect();
            let order = j
                .euler_order()
                .map(|o| format!(" [{o}]"))
                .unwrap_or_default();
            let p = match pos {
                ResolvedPosition::None => String::new(),
                ResolvedPosition::Add => " positions: add".into(),
                ResolvedPosition::Replace => " positions: replace".into(),
            };
            let held = match t.welded.iter().find(|w| w.joint == i) {
                Some(w) => format!(
                    ", welded at their mean (varied up to {})",
                    crate::motion::weld::centimetres(w.variation_m)
                ),
                None => String::new(),
            };
            let _ = writeln!(s, "  {}: {}{order}{p}{held}", j.name, chans.join(" "));
        }
        for n in &t.notes {
            let _ = writeln!(s, "note        {n}");
        }
        s
    }
}
