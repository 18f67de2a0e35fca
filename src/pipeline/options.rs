//! Stage 0 of a take: the options that decide how it becomes a model and states — from a
//! scene file, from the flags as typed ([`Flags`], validated here), the default smoothing that
//! fits the take, and the per-joint settings (damping, gains) spread over the coordinates.

use super::Contact;
use super::reduce;
use crate::dynamics;
use crate::error::Error;
use crate::io::bvh::{JointTranslations, LengthUnit, PositionMode, UpAxis};
use crate::io::scene::{Damping, PerJoint};
use crate::model::Model;
use crate::model::anthropometry::{BodyParams, Sex};
use crate::model::bvh::JointModel;
use crate::motion::smooth::{SmoothSpec, Smoother};
use std::path::Path;
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
    ///
    /// [`load_take`]: super::load_take
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
