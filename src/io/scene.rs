//! Scene files (TOML): what a study needs in one place — the take(s), the body, units and axes,
//! the joint model, what to lock or prune, smoothing, contact and control gains. An example with
//! every field documented is `data/scene_example.toml`.
//!
//! ```toml
//! takes = ["walk.bvh"]            # relative to the scene file
//! mass = 72.0                     # kg
//! sex = "female"
//! segments = "regression"         # or "fractions" (de Leva's fixed fractions of body mass)
//! unit = "cm"                     # or "auto", m, dm, mm, in, cmu, or metres per unit (0.0254)
//! up = "y"                        # or "auto"
//! joints = "euler"                # or "ball"
//! lock = ["LeftHand", "RightHand"]
//! subtree = "RightUpLeg"
//! smooth = "butterworth:6hz"
//! contact = "feet"                # or "none", "auto" (the default)
//! keep_first_frame = false        # true keeps a rest pose stored as frame 0
//! joint_translations = "weld"     # or "keep": position channels below the root as coordinates
//! damping = 0.5                   # N·m·s/rad, every joint coordinate (or a table by joint)
//! [link_mass]
//! LeftUpLeg = 9.5
//! [gains]
//! kp = 400.0                      # 1/s², every coordinate (or a table by joint, "*" the rest)
//! kv = { "*" = 40.0, LeftLeg = 60.0 }
//! ```
//!
//! Values are checked while reading, and a bad one is reported with its line and column (from
//! the TOML spans). Choices that only later stages understand (`smooth`) are kept as written
//! and checked there. This module describes; it does not build anything (`model::bvh` turns a
//! scene into model options).

use crate::error::Error;
use crate::io::bvh::{JointTranslations, LengthUnit, PositionMode, UpAxis, check_given_stature};
use serde::{Deserialize, Deserializer, de::Error as _};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::str::FromStr;

/// Computed-torque gains: `q̈_cmd = q̈_ref + kv (q̇_ref − q̇) + kp (q_ref − q)`, diagonal: each
/// a number for every coordinate or a table by joint or coordinate name (`"*"` for the rest):
///
/// ```toml
/// [gains]
/// kp = 400.0                      # 1/s², every coordinate
/// kv = { "*" = 40.0, LeftLeg = 60.0, "LeftLeg.Xrotation" = 80.0 }
/// ```
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Gains {
    /// Position gains (1/s²), ≥ 0 (0: no position feedback); default 400.
    #[serde(default = "default_kp", deserialize_with = "gain_kp")]
    pub kp: PerJoint,
    /// Velocity gains (1/s), ≥ 0; default 40.
    #[serde(default = "default_kv", deserialize_with = "gain_kv")]
    pub kv: PerJoint,
}

fn default_kp() -> PerJoint {
    PerJoint::all(400.0)
}
fn default_kv() -> PerJoint {
    PerJoint::all(40.0)
}

/// A value for every joint coordinate (`all`) with overrides by BVH joint name (all its
/// coordinates) or coordinate name (`LeftLeg.Xrotation`, `LeftLeg:wx`, `j2`): viscous friction
/// and the computed-torque gains. `pipeline::per_coordinate` matches the names to a model.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PerJoint {
    /// The value of every coordinate without an override.
    pub all: f64,
    /// Overrides by joint or coordinate name.
    pub joints: BTreeMap<String, f64>,
}

impl PerJoint {
    /// `x` on every coordinate, no override.
    pub fn all(x: f64) -> Self {
        PerJoint {
            all: x,
            joints: BTreeMap::new(),
        }
    }
    /// Zero everywhere.
    pub fn is_none(&self) -> bool {
        self.all == 0.0 && self.joints.values().all(|&b| b == 0.0)
    }
}

/// Viscous joint friction `τ = b q̇` (the paper's `bᵢ q̇ᵢ`): `all` for every joint coordinate
/// (N·m·s/rad for angles, N·s/m for translations), `joints` overriding it by BVH joint name
/// (all its coordinates) or coordinate name (`LeftLeg.Xrotation`). The 6 root coordinates of a
/// floating avatar never get damping (they are a residual actuator, not a joint). In a scene:
/// `damping = 0.5`, or a table `[damping]` of `JOINT = B` with an optional `"*" = B` for the rest.
pub type Damping = PerJoint;

/// A number, or a table of numbers by name with `"*"` for the rest (`rest` when absent), each
/// passing `check`.
fn per_joint<'de, D: Deserializer<'de>>(
    d: D,
    rest: f64,
    check: impl Fn(f64) -> Result<f64, String>,
) -> Result<PerJoint, D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Spec {
        All(f64),
        Table(BTreeMap<String, f64>),
    }
    let spec = Spec::deserialize(d)
        .map_err(|_| D::Error::custom("expected a number, or a table of numbers by joint name"))?;
    Ok(match spec {
        Spec::All(x) => PerJoint::all(check(x).map_err(D::Error::custom)?),
        Spec::Table(t) => {
            let mut out = PerJoint::all(rest);
            for (name, x) in t {
                let x = check(x).map_err(D::Error::custom)?;
                if name == "*" {
                    out.all = x;
                } else {
                    out.joints.insert(name, x);
                }
            }
            out
        }
    })
}

fn damping<'de, D: Deserializer<'de>>(d: D) -> Result<Damping, D::Error> {
    per_joint(d, 0.0, |b| {
        if b.is_finite() && b >= 0.0 {
            Ok(b)
        } else {
            Err(format!(
                "damping {b}: a viscous friction coefficient must be ≥ 0 (N·m·s/rad)"
            ))
        }
    })
}

fn gain(x: f64) -> Result<f64, String> {
    if x.is_finite() && x >= 0.0 {
        Ok(x)
    } else {
        Err(format!("expected a gain ≥ 0, found {x}"))
    }
}
fn gain_kp<'de, D: Deserializer<'de>>(d: D) -> Result<PerJoint, D::Error> {
    per_joint(d, default_kp().all, gain)
}
fn gain_kv<'de, D: Deserializer<'de>>(d: D) -> Result<PerJoint, D::Error> {
    per_joint(d, default_kv().all, gain)
}

/// A study: takes and every parameter the pipeline needs. Units are SI.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// BVH takes; [`read`] makes relative paths relative to the scene file. At least one.
    #[serde(deserialize_with = "non_empty_paths")]
    pub takes: Vec<PathBuf>,
    /// Total body mass (kg), > 0. Default 75.
    #[serde(default = "default_mass", deserialize_with = "positive")]
    pub mass: f64,
    /// `"female"` or `"male"` (de Leva's tables). Default male.
    #[serde(default = "default_sex", deserialize_with = "sex")]
    pub sex: String,
    /// Segment masses: `"regression"` (default: Zatsiorsky–Seluyanov, on body mass and the
    /// skeleton's stature) or `"fractions"` (de Leva's fixed fractions of body mass).
    #[serde(default = "default_segments", deserialize_with = "segments")]
    pub segments: String,
    /// Length unit of the takes; `None` (`"auto"` or absent): detected from the stature.
    #[serde(default, deserialize_with = "unit")]
    pub unit: Option<LengthUnit>,
    /// Scale the skeleton to this stature (m, 1.0–2.3) instead of giving a unit.
    #[serde(default, deserialize_with = "stature")]
    pub stature: Option<f64>,
    /// Up axis; `None` (`"auto"` or absent): detected.
    #[serde(default, deserialize_with = "up")]
    pub up: Option<UpAxis>,
    /// Position-channel semantics: `"auto"` (default), `"add"` or `"replace"`.
    #[serde(default, deserialize_with = "from_str")]
    pub position: PositionMode,
    /// `"euler"` (default, the paper's) or `"ball"`.
    #[serde(default = "default_joints", deserialize_with = "joints")]
    pub joints: String,
    /// Smoothing before differentiation, as the `--smooth` option (`none`,
    /// `gaussian:0.02`, `butterworth:6hz`); `None`: the default.
    #[serde(default)]
    pub smooth: Option<String>,
    /// Ground contact: `"auto"` (default: feet when the take stands on a floor, none when it
    /// never touches one), `"feet"` or `"none"` (the avatar hangs from its root).
    #[serde(default = "default_contact", deserialize_with = "contact")]
    pub contact: String,
    /// Keep frame 0 of the takes even when it is a rest pose before the motion (default
    /// false: such a frame is dropped, as `--keep-first-frame` keeps it).
    #[serde(default)]
    pub keep_first_frame: bool,
    /// Position channels of the joints below the body's root: `"weld"` (default: held at
    /// their mean, as `--joint-translations weld`) or `"keep"` (coordinates).
    #[serde(default, deserialize_with = "from_str")]
    pub joint_translations: JointTranslations,
    /// Per-link mass overrides (kg, ≥ 0) by BVH joint name.
    #[serde(default, deserialize_with = "masses")]
    pub link_mass: BTreeMap<String, f64>,
    /// BVH joints (or single coordinates such as `LeftLeg.Yrotation`) locked at rest.
    #[serde(default)]
    pub lock: Vec<String>,
    /// Keep only this BVH joint's subtree (and the chain carrying it).
    #[serde(default)]
    pub subtree: Option<String>,
    /// Computed-torque gains; `None`: the default.
    #[serde(default)]
    pub gains: Option<Gains>,
    /// Viscous joint friction (N·m·s/rad): a number for every joint coordinate, or a table by
    /// joint name (`"*"` for the rest). Default none.
    #[serde(default, deserialize_with = "damping")]
    pub damping: Damping,
}

fn default_mass() -> f64 {
    75.0
}
fn default_sex() -> String {
    "male".into()
}
fn default_segments() -> String {
    "regression".into()
}
fn default_joints() -> String {
    "euler".into()
}
fn default_contact() -> String {
    "auto".into()
}

fn positive<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    let x = f64::deserialize(d)?;
    if x.is_finite() && x > 0.0 {
        Ok(x)
    } else {
        Err(D::Error::custom(format!(
            "expected a positive number, found {x}"
        )))
    }
}

fn non_empty_paths<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<PathBuf>, D::Error> {
    let v = Vec::<PathBuf>::deserialize(d)?;
    if v.is_empty() {
        Err(D::Error::custom("expected at least one take"))
    } else {
        Ok(v)
    }
}

/// A lowercase string that must be one of `allowed`.
fn choice<'de, D: Deserializer<'de>>(
    d: D,
    what: &str,
    allowed: &[(&str, &str)],
) -> Result<String, D::Error> {
    let s = String::deserialize(d)?.trim().to_ascii_lowercase();
    allowed
        .iter()
        .find(|(alias, _)| *alias == s)
        .map(|(_, canonical)| canonical.to_string())
        .ok_or_else(|| {
            let mut names: Vec<&str> = allowed.iter().map(|a| a.1).collect();
            names.dedup();
            D::Error::custom(format!(
                "unknown {what} {s:?}: expected {}",
                names.join(" or ")
            ))
        })
}

fn sex<'de, D: Deserializer<'de>>(d: D) -> Result<String, D::Error> {
    choice(
        d,
        "sex",
        &[
            ("female", "female"),
            ("f", "female"),
            ("male", "male"),
            ("m", "male"),
        ],
    )
}

fn segments<'de, D: Deserializer<'de>>(d: D) -> Result<String, D::Error> {
    choice(
        d,
        "segment table",
        &[("regression", "regression"), ("fractions", "fractions")],
    )
}

fn joints<'de, D: Deserializer<'de>>(d: D) -> Result<String, D::Error> {
    choice(d, "joint model", &[("euler", "euler"), ("ball", "ball")])
}

fn contact<'de, D: Deserializer<'de>>(d: D) -> Result<String, D::Error> {
    choice(
        d,
        "contact model",
        &[("auto", "auto"), ("none", "none"), ("feet", "feet")],
    )
}

fn from_str<'de, D: Deserializer<'de>, T: FromStr<Err = Error>>(d: D) -> Result<T, D::Error> {
    let s = String::deserialize(d)?;
    s.parse()
        .map_err(|e: Error| D::Error::custom(e.to_string()))
}

/// `"auto"` → `None`, otherwise `T::from_str`.
fn auto_or<'de, D: Deserializer<'de>, T: FromStr<Err = Error>>(
    d: D,
) -> Result<Option<T>, D::Error> {
    let s = String::deserialize(d)?;
    if s.trim().eq_ignore_ascii_case("auto") {
        return Ok(None);
    }
    s.parse()
        .map(Some)
        .map_err(|e: Error| D::Error::custom(e.to_string()))
}

fn up<'de, D: Deserializer<'de>>(d: D) -> Result<Option<UpAxis>, D::Error> {
    auto_or(d)
}

/// A unit name (`"cm"`, `"auto"`) or a number of metres per unit.
fn unit<'de, D: Deserializer<'de>>(d: D) -> Result<Option<LengthUnit>, D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum NameOrNumber {
        Number(f64),
        Name(String),
    }
    match NameOrNumber::deserialize(d)? {
        NameOrNumber::Number(x) if x.is_finite() && x > 0.0 => Ok(Some(LengthUnit::Custom(x))),
        NameOrNumber::Number(x) => Err(D::Error::custom(format!(
            "unit = {x}: metres per unit must be positive"
        ))),
        NameOrNumber::Name(s) if s.trim().eq_ignore_ascii_case("auto") => Ok(None),
        NameOrNumber::Name(s) => s
            .parse()
            .map(Some)
            .map_err(|e: Error| D::Error::custom(e.to_string())),
    }
}

fn stature<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
    let x = f64::deserialize(d)?;
    check_given_stature(x).map_err(|e| D::Error::custom(format!("stature = {x} m: {e}")))?;
    Ok(Some(x))
}

fn masses<'de, D: Deserializer<'de>>(d: D) -> Result<BTreeMap<String, f64>, D::Error> {
    /// A mass ≥ 0 kg, checked where it is written (so the error points at the value).
    struct Kg(f64);
    impl<'de> Deserialize<'de> for Kg {
        fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Kg, D::Error> {
            let v = f64::deserialize(d)?;
            if v.is_finite() && v >= 0.0 {
                Ok(Kg(v))
            } else {
                Err(D::Error::custom(format!(
                    "link mass {v}: a mass must be ≥ 0 kg"
                )))
            }
        }
    }
    let m = BTreeMap::<String, Kg>::deserialize(d)?;
    Ok(m.into_iter().map(|(k, v)| (k, v.0)).collect())
}

/// Reads a scene file; relative take paths become relative to the file's folder.
pub fn read(path: &Path) -> Result<Scene, Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let mut scene = parse_str(&text, path)?;
    let dir = path.parent().unwrap_or(Path::new(""));
    for t in &mut scene.takes {
        if t.is_relative() {
            *t = dir.join(&*t);
        }
    }
    Ok(scene)
}

/// Parses scene text; `path` names the source in error messages. Take paths are kept as
/// written.
pub fn parse_str(text: &str, path: &Path) -> Result<Scene, Error> {
    let scene: Scene =
        toml::from_str(text).map_err(|e| crate::io::dh::toml_error(path, text, &e))?;
    if scene.unit.is_some() && scene.stature.is_some() {
        let pos = text.find("stature").unwrap_or(0);
        let (line, col) = crate::io::dh::line_col(text, pos);
        return Err(Error::parse(
            path,
            line,
            col,
            "give either unit or stature, not both (stature rescales the skeleton)",
        ));
    }
    Ok(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Scene, Error> {
        parse_str(text, Path::new("s.toml"))
    }

    #[test]
    fn defaults_fill_what_is_not_given() {
        let s = parse("takes = [\"a.bvh\"]\n").unwrap();
        assert_eq!(s.mass, 75.0);
        assert_eq!(s.sex, "male");
        assert_eq!(s.segments, "regression");
        assert_eq!(s.joints, "euler");
        assert_eq!(s.contact, "auto");
        assert_eq!(s.position, PositionMode::Auto);
        assert_eq!(s.joint_translations, JointTranslations::Weld);
        assert_eq!((s.unit, s.up, s.stature), (None, None, None));
        let s = parse("takes = [\"a.bvh\"]\njoint_translations = \"keep\"\n").unwrap();
        assert_eq!(s.joint_translations, JointTranslations::Keep);
        let s = parse(
            "takes = [\"a.bvh\"]\nunit = 0.0254\nup = \"Z\"\nsex = \"F\"\nsegments = \"Fractions\"\n",
        )
        .unwrap();
        assert_eq!(s.unit, Some(LengthUnit::Custom(0.0254)));
        assert_eq!(s.up, Some(UpAxis::Z));
        assert_eq!(s.sex, "female");
        assert_eq!(s.segments, "fractions");
    }

    #[test]
    fn damping_is_a_number_or_a_table_by_joint() {
        let s = parse("takes = [\"a.bvh\"]\n").unwrap();
        assert!(s.damping.is_none());
        let s = parse("takes = [\"a.bvh\"]\ndamping = 0.5\n").unwrap();
        assert_eq!((s.damping.all, s.damping.joints.len()), (0.5, 0));
        let s = parse("takes = [\"a.bvh\"]\n[damping]\n\"*\" = 0.2\nLeftLeg = 1.5\n").unwrap();
        assert_eq!(s.damping.all, 0.2);
        assert_eq!(s.damping.joints["LeftLeg"], 1.5);
    }

    #[test]
    fn bad_values_are_reported_at_their_line() {
        let cases = [
            ("takes = []\n", 1),
            ("takes = [\"a.bvh\"]\nmass = -3\n", 2),
            ("takes = [\"a.bvh\"]\n\nsex = \"other\"\n", 3),
            ("takes = [\"a.bvh\"]\nsegments = \"dempster\"\n", 2),
            ("takes = [\"a.bvh\"]\nunit = \"furlong\"\n", 2),
            ("takes = [\"a.bvh\"]\nstature = -3.1\n", 2),
            ("takes = [\"a.bvh\"]\nup = \"w\"\n", 2),
            ("takes = [\"a.bvh\"]\njoints = \"hinge\"\n", 2),
            ("takes = [\"a.bvh\"]\ncontact = \"hands\"\n", 2),
            ("takes = [\"a.bvh\"]\nposition = \"both\"\n", 2),
            ("takes = [\"a.bvh\"]\njoint_translations = \"stretch\"\n", 2),
            ("takes = [\"a.bvh\"]\n[link_mass]\nLeftUpLeg = -1\n", 3),
            ("takes = [\"a.bvh\"]\n[gains]\nkp = -1\nkv = 1\n", 3),
            ("takes = [\"a.bvh\"]\ndamping = -0.5\n", 2),
            ("takes = [\"a.bvh\"]\n\ndamping = \"lots\"\n", 3),
            ("takes = [\"a.bvh\"]\nmas = 70\n", 2),
            ("takes = [\"a.bvh\"]\nunit = \"cm\"\nstature = 1.7\n", 3),
            ("mass = 70\n", 1),
        ];
        for (text, line) in cases {
            match parse(text) {
                Err(Error::Parse { at, message }) => {
                    assert_eq!(at.line, line, "{text:?}: {message}")
                }
                other => panic!("{text:?}: {other:?}"),
            }
        }
    }
}
