//! Link masses, centres of mass, inertias and drawing shapes of a human skeleton from total body
//! mass, stature and sex, after Zatsiorsky & Seluyanov (1983) and de Leva (1996).
//!
//! Sources: P. de Leva, "Adjustments to Zatsiorsky-Seluyanov's segment inertia parameters",
//! *J. Biomechanics* 29(9):1223–1230, 1996, Table 4 (the numbers of
//! `../shared/reference/de_leva_1996.csv`, embedded in [`DE_LEVA_1996`]); V. M. Zatsiorsky &
//! V. N. Seluyanov, "The mass and inertia characteristics of the main segments of the human
//! body", *Biomechanics VIII-B*, 1983, pp. 1152–1159, the regression of segment mass on body
//! mass and stature as Zatsiorsky (2002, *Kinetics of Human Motion*) reproduces it (the numbers
//! of `data/reference/zatsiorsky_seluyanov_1983_mass_regression.csv`, embedded in
//! [`ZATSIORSKY_SELUYANOV`]), and their regression of the segments' principal moments of
//! inertia on the same two variables (Zatsiorsky 2002, Table A2.6:
//! `data/reference/zatsiorsky_seluyanov_1983_inertia_regression.csv`, embedded in
//! [`ZATSIORSKY_SELUYANOV_INERTIA`], the trunk's parts placed along it by
//! `data/reference/de_leva_1996_trunk_parts.csv`, [`TRUNK_PARTS`]);
//! `tools/check_segment_regression.py` checks them all. Segment masses and radii of gyration
//! come from the regressions by default and from de Leva's fixed fractions with
//! [`SegmentTable::Fractions`] ([`segment_masses`], module `masses`; [`segment_radii`], module
//! `inertia`); radii of gyration are fractions of the bone either way, so they scale with the
//! skeleton's own bone lengths, and centres of mass are de Leva's fractions of the bone with
//! either table.
//!
//! How a skeleton gets its masses ([`distribute`]):
//! 1. every joint is classified by name into a de Leva segment and a side ([`classify`]: CMU,
//!    Daz/Poser, Mixamo, Bandai, MakeHuman, Blender and the generated walk's names); a joint whose
//!    name says nothing inherits the class of its parent (fingers → hand, toes → foot, face →
//!    head); joints above every classified joint (`joint_Root`, MakeHuman's `Root`) stay
//!    unclassified and massless;
//! 2. each segment instance (head, trunk, left/right upper arm, forearm, hand, thigh, shank,
//!    foot) gets its mass from [`segment_masses`] (the regression on body mass and stature, or
//!    de Leva's fraction of the body mass); a segment missing from the skeleton gives
//!    its mass to the next segment towards the trunk (hand → forearm → upper arm → trunk);
//! 3. a segment's mass is shared among its joints in proportion to their bone lengths (the bone
//!    of a joint is the mean of its non-zero child offsets, End Sites included), shoulder-girdle
//!    and breast bones counting a quarter of their length in the trunk ([`GIRDLE_WEIGHT`]);
//!    Every joint's share gets 5 % of the mean added, so that bone-less joints (zero-length
//!    leaves) still carry a little mass; a link with mass but no bone is a sphere of segment
//!    density ([`SEGMENT_DENSITY`]);
//! 4. fallback, when no trunk is recognised (an unknown naming scheme): the body mass is shared
//!    by bone volume, each bone a solid cylinder of radius 0.1 × its length (volume ∝ L³);
//! 5. per-link overrides ([`BodyParams::link_mass`]) are applied and every other link is
//!    rescaled so that the masses sum exactly to the body mass.
//!
//! Each link's centre of mass lies on its bone at de Leva's fraction (measured from the joint:
//! de Leva measures the head and trunk from their upper end, so those are mirrored), and its
//! inertia about the COM comes from the segment's radii of gyration ([`segment_radii`]: by
//! regression on body mass and stature, or de Leva's) times the bone length, axisymmetric
//! about the bone (the transverse radius is the mean of the sagittal and transverse ones,
//! because a BVH bone does not say which way is anterior).

use crate::error::Error;
use crate::model::Superquadric;
use nalgebra::{Matrix3, Vector3};
use std::collections::BTreeMap;
use std::str::FromStr;

/// Sex, which selects de Leva's male or female table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Sex {
    Female,
    #[default]
    Male,
}

impl FromStr for Sex {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s.trim().to_ascii_lowercase().as_str() {
            "female" | "f" => Ok(Sex::Female),
            "male" | "m" => Ok(Sex::Male),
            other => Err(Error::Invalid(format!(
                "unknown sex {other:?}: expected \"female\" or \"male\""
            ))),
        }
    }
}

impl std::fmt::Display for Sex {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Sex::Female => "female",
            Sex::Male => "male",
        })
    }
}

/// What the anthropometry needs to know about the body.
#[derive(Debug, Clone, PartialEq)]
pub struct BodyParams {
    /// Total body mass (kg), > 0.
    pub mass_kg: f64,
    /// Selects de Leva's male or female table (and, with the regression, the female ratios).
    pub sex: Sex,
    /// Which table gives the segment masses ([`segment_masses`]).
    pub segments: SegmentTable,
    /// Stature (m), which the regression needs: the skeleton's, set by the pipeline and by
    /// `model::bvh::build_bvh_model` from the scaled rest pose (`--stature` scales the skeleton
    /// to it); `None` until then.
    pub height_m: Option<f64>,
    /// Per-link mass overrides (kg) by BVH joint name; the other links are rescaled so that the
    /// total stays `mass_kg`.
    pub link_mass: BTreeMap<String, f64>,
}

impl BodyParams {
    /// A body of `mass_kg` kg without overrides, segment masses by regression (stature not yet
    /// known).
    pub fn new(mass_kg: f64, sex: Sex) -> Self {
        Self {
            mass_kg,
            sex,
            segments: SegmentTable::default(),
            height_m: None,
            link_mass: BTreeMap::new(),
        }
    }
}

impl Default for BodyParams {
    /// 75 kg, male: the body the fixtures and the paper's examples use.
    fn default() -> Self {
        Self::new(75.0, Sex::Male)
    }
}

/// A de Leva body segment.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Segment {
    /// Head and neck (vertex to C7).
    Head,
    /// Trunk (C7 to mid-hip), with the pelvis and the shoulder girdle.
    Trunk,
    UpperArm,
    Forearm,
    Hand,
    Thigh,
    Shank,
    Foot,
}

impl Segment {
    /// The segment that receives this one's mass when it is missing from a skeleton.
    fn proximal(self) -> Option<Segment> {
        match self {
            Segment::Head | Segment::UpperArm | Segment::Thigh => Some(Segment::Trunk),
            Segment::Forearm => Some(Segment::UpperArm),
            Segment::Hand => Some(Segment::Forearm),
            Segment::Shank => Some(Segment::Thigh),
            Segment::Foot => Some(Segment::Shank),
            Segment::Trunk => None,
        }
    }
    /// Whether the segment comes in a left and a right copy.
    fn is_limb(self) -> bool {
        !matches!(self, Segment::Head | Segment::Trunk)
    }
    /// Lowercase name as in de Leva's table (`upper_arm`, …).
    pub fn name(self) -> &'static str {
        match self {
            Segment::Head => "head",
            Segment::Trunk => "trunk",
            Segment::UpperArm => "upper_arm",
            Segment::Forearm => "forearm",
            Segment::Hand => "hand",
            Segment::Thigh => "thigh",
            Segment::Shank => "shank",
            Segment::Foot => "foot",
        }
    }
}

/// Body side of a joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Side {
    Left,
    Right,
    Center,
}

mod inertia;
mod masses;
mod tables;

/// A body of `mass_kg`, `height_m` and `sex` under the segment table `segments`, for the
/// tables' unit tests.
#[cfg(test)]
fn test_body(mass_kg: f64, height_m: f64, sex: Sex, segments: SegmentTable) -> BodyParams {
    BodyParams {
        segments,
        height_m: Some(height_m),
        ..BodyParams::new(mass_kg, sex)
    }
}

pub use inertia::{SegmentRadii, segment_radii};
pub use masses::{SegmentMasses, SegmentTable, segment_masses};
pub use tables::{
    DE_LEVA_1996, InertiaRegression, MassRegression, SegmentParams, TRUNK_PARTS, TrunkPart,
    ZATSIORSKY_SELUYANOV, ZATSIORSKY_SELUYANOV_INERTIA, de_leva,
};

/// Splits a joint name into side and the rest (lowercase): `LeftUpLeg` → (Left, `upleg`),
/// `lThigh` → (Left, `thigh`), `UpperLeg_L` → (Left, `upperleg`), `thigh.L` → (Left, `thigh`),
/// `mixamorig:RightArm` → (Right, `arm`).
fn split_side(name: &str) -> (Side, String) {
    // namespaces (`mixamorig:`) and helper prefixes (`__UpLeg_L`)
    let name = name.rsplit(':').next().unwrap_or(name);
    let name = name.trim_start_matches('_');
    let lower = name.to_ascii_lowercase();
    for (side, word) in [(Side::Left, "left"), (Side::Right, "right")] {
        if let Some(rest) = lower.strip_prefix(word) {
            return (side, rest.trim_start_matches(['_', '.', '-', ' ']).into());
        }
        for sep in ['_', '.', '-', ' '] {
            if let Some(rest) = lower.strip_suffix(&format!("{sep}{word}")) {
                return (side, rest.into());
            }
        }
    }
    for (side, c) in [(Side::Left, 'l'), (Side::Right, 'r')] {
        for sep in ['_', '.', '-', ' '] {
            if let Some(rest) = lower.strip_suffix(&format!("{sep}{c}")) {
                return (side, rest.into());
            }
        }
    }
    // CMU / Daz short prefixes: `LHipJoint`, `lThigh`, `rShldr`
    let mut chars = name.chars();
    if let (Some(c0), Some(c1)) = (chars.next(), chars.next())
        && c1.is_ascii_uppercase()
    {
        match c0 {
            'l' | 'L' => return (Side::Left, lower[1..].into()),
            'r' | 'R' => return (Side::Right, lower[1..].into()),
            _ => {}
        }
    }
    (Side::Center, lower)
}

/// The side a joint name says (`LeftUpLeg`, `lThigh`, `UpperLeg_L`, `thigh.L`: left), or
/// [`Side::Center`] if it says none.
pub fn name_side(name: &str) -> Side {
    split_side(name).0
}

/// The de Leva segment and side a joint name denotes, or `None` if the name says nothing
/// (then [`distribute`] lets the joint inherit its parent's class).
pub fn classify(name: &str) -> Option<(Segment, Side)> {
    let (side, base) = split_side(name);
    let has = |words: &[&str]| words.iter().any(|w| base.contains(w));
    let seg = if has(&[
        "hand",
        "finger",
        "thumb",
        "index",
        "mid",
        "ring",
        "pinky",
        "wrist",
        "metacarpal",
        "palm",
    ]) {
        Segment::Hand
    } else if has(&["foot", "toe", "ankle", "heel", "metatarsal"]) {
        Segment::Foot
    } else if has(&["forearm", "lowerarm", "loarm", "lowarm", "elbow"]) {
        Segment::Forearm
    } else if has(&["upperarm", "uparm", "upper_arm", "shldr", "humerus"]) || base == "arm" {
        Segment::UpperArm
    } else if has(&["upleg", "upperleg", "thigh", "femur"]) {
        Segment::Thigh
    } else if has(&["lowerleg", "loleg", "lowleg", "shin", "calf", "knee", "leg"]) {
        Segment::Shank
    } else if has(&[
        "shoulder", "collar", "clavicle", "scapula", "hipjoint", "buttock", "pelvis", "breast",
    ]) {
        Segment::Trunk
    } else if has(&["head", "neck", "skull", "jaw", "eye", "nose", "tongue"]) {
        Segment::Head
    } else if has(&[
        "hip", "spine", "back", "abdomen", "chest", "torso", "waist", "thorax", "lumbar",
    ]) {
        Segment::Trunk
    } else {
        return None;
    };
    Some((seg, if seg.is_limb() { side } else { Side::Center }))
}

/// The share weight, per metre of bone, of shoulder-girdle (clavicle, collar, scapula, the
/// CMU/Mixamo `LeftShoulder`) and breast bones relative to the spine's within the trunk. A
/// heuristic, not de Leva's: by length alone a CMU clavicle (as long as a spine segment) would
/// take ~7 kg of a 75 kg body, while the clavicle, scapula and the muscles between them and the
/// thorax weigh ~2 kg a side.
pub const GIRDLE_WEIGHT: f64 = 0.25;

/// Whether a trunk joint is a shoulder-girdle or breast bone (see [`GIRDLE_WEIGHT`]).
fn is_appendage(name: &str) -> bool {
    let (_, base) = split_side(name);
    ["shoulder", "collar", "clavicle", "scapula", "breast"]
        .iter()
        .any(|w| base.contains(w))
        && classify(name).is_some_and(|c| c.0 == Segment::Trunk)
}

/// Whether joint names describe a human body as [`classify`] reads them: a trunk, and a thigh,
/// shank or foot on each side. A skeleton without them (an animal, a crab, a robot, or a
/// human whose joints are named `J1`, `J2`, …) gets its link masses by bone volume in
/// [`distribute`] and its length unit from its size, not from a human's height.
pub fn looks_human<'a>(names: impl IntoIterator<Item = &'a str>) -> bool {
    let (mut trunk, mut left, mut right) = (false, false, false);
    for c in names.into_iter().filter_map(classify) {
        match c {
            (Segment::Trunk, _) => trunk = true,
            (Segment::Thigh | Segment::Shank | Segment::Foot, Side::Left) => left = true,
            (Segment::Thigh | Segment::Shank | Segment::Foot, Side::Right) => right = true,
            _ => {}
        }
    }
    trunk && left && right
}

/// The ankles (the first foot joint of each side, by [`classify`]) of a skeleton given as
/// `(name, parent)` per joint, and the hip joints above them: each ankle's parent's parent
/// (ankle → knee → hip, whatever the exporter named them: `LeftFoot` under `LeftLeg` under
/// `LeftUpLeg`, or `RightAnkle` under `RightKnee` under `RightHip`). Both empty unless both
/// sides have an ankle two joints below another.
pub fn hips_and_feet(joints: &[(&str, Option<usize>)]) -> (Vec<usize>, Vec<usize>) {
    let mut feet = [None; 2];
    for (j, (name, _)) in joints.iter().enumerate() {
        let side = match classify(name) {
            Some((Segment::Foot, Side::Left)) => 0,
            Some((Segment::Foot, Side::Right)) => 1,
            _ => continue,
        };
        feet[side].get_or_insert(j);
    }
    let hip = |f: usize| joints[f].1.and_then(|knee| joints[knee].1);
    match feet {
        [Some(l), Some(r)] => match (hip(l), hip(r)) {
            (Some(a), Some(b)) => (vec![a, b], vec![l, r]),
            _ => (vec![], vec![]),
        },
        _ => (vec![], vec![]),
    }
}

/// Whether a joint name reads as the trunk ([`classify`]): then [`distribute`] uses de Leva's
/// segment table, otherwise (an animal, a robot, names no scheme knows) bone volume. A class
/// inherited from a parent is never the trunk unless the parent's name is, so this is the
/// same test as on [`distribute`]'s classes.
pub fn has_trunk<'a>(names: impl IntoIterator<Item = &'a str>) -> bool {
    names
        .into_iter()
        .any(|n| matches!(classify(n), Some((Segment::Trunk, _))))
}

/// What [`distribute`] needs to know about one BVH joint.
#[derive(Debug, Clone, PartialEq)]
pub struct Bone {
    /// Joint name (BVH).
    pub name: String,
    /// Parent joint index (`< self`), `None` for the root.
    pub parent: Option<usize>,
    /// Offsets of the child joints and End Sites, in this joint's frame (m).
    pub ends: Vec<Vector3<f64>>,
}

impl Bone {
    /// Mean of the non-zero child offsets (the bone direction and reach; m) and the mean of
    /// their lengths (the bone length used for shares and radii; m).
    fn geometry(&self) -> (Vector3<f64>, f64) {
        let ends: Vec<&Vector3<f64>> = self.ends.iter().filter(|e| e.norm() > 0.0).collect();
        if ends.is_empty() {
            return (Vector3::zeros(), 0.0);
        }
        let n = ends.len() as f64;
        let b = ends.iter().copied().sum::<Vector3<f64>>() / n;
        let l = ends.iter().map(|e| e.norm()).sum::<f64>() / n;
        (b, l)
    }
}

/// Mass properties of one link (the body that carries a BVH joint's frame).
#[derive(Debug, Clone, PartialEq)]
pub struct LinkMass {
    /// Mass (kg).
    pub mass: f64,
    /// Centre of mass in the joint frame (m).
    pub com: Vector3<f64>,
    /// Inertia about the COM, joint-frame axes (kg·m²).
    pub inertia_com: Matrix3<f64>,
    /// Drawing shape sized from the bone length and radius of gyration (`None` for a joint
    /// without a bone).
    pub shape: Option<Superquadric>,
    /// The segment the joint was assigned to (`None`: unclassified helper or fallback).
    pub segment: Option<(Segment, Side)>,
}

/// Per-unit-mass geometry of a link: COM and inertia about the COM for 1 kg.
struct UnitLink {
    com: Vector3<f64>,
    inertia: Matrix3<f64>,
    shape: Option<Superquadric>,
}

/// Radii of gyration (fractions of the bone length) of the fallback solid cylinder of radius
/// 0.1 L: transverse √((3R² + L²)/12), longitudinal R/√2.
const FALLBACK_R_TRANS: f64 = 0.295_803_989_154_980_8;
const FALLBACK_R_LONG: f64 = 0.070_710_678_118_654_76;

/// Fractions (summing to 1) proportional to `w[j] + ε`, with `ε` 5 % of the mean weight, so
/// that a joint without a bone (a zero-length leaf such as a `Toes` joint whose End Site is at
/// zero) still carries a little mass and never makes a massless leaf (whose joint would be
/// singular in forward dynamics); equal fractions if every weight is zero.
fn shares(w: &[f64]) -> Vec<f64> {
    let n = w.len() as f64;
    let sum: f64 = w.iter().sum();
    if sum <= 0.0 {
        return vec![1.0 / n; w.len()];
    }
    let eps = 0.05 * sum / n;
    w.iter().map(|x| (x + eps) / (sum + n * eps)).collect()
}

/// Density of body segments (kg/m³): 1.04–1.16 g/cm³ in Dempster's data (Winter 2009,
/// *Biomechanics and Motor Control of Human Movement*, 4th ed., Table 4.1).
pub const SEGMENT_DENSITY: f64 = 1100.0;

/// A link with mass but no bone is a uniform sphere of [`SEGMENT_DENSITY`] centred on the
/// joint: its radius (m) and its inertia about the centre (kg·m²).
fn boneless_sphere(mass: f64) -> (f64, Matrix3<f64>) {
    let r = (3.0 * mass / (4.0 * std::f64::consts::PI * SEGMENT_DENSITY)).cbrt();
    (r, Matrix3::identity() * (0.4 * mass * r * r))
}

/// Shape and 1-kg inertia of a bone `b` of mean length `l`, with COM at `com_frac` along `b` and
/// radii of gyration `r_trans`, `r_long` (fractions of `l`).
fn unit_link(b: &Vector3<f64>, l: f64, com_frac: f64, r_trans: f64, r_long: f64) -> UnitLink {
    let (rt, rl) = ((r_trans * l).powi(2), (r_long * l).powi(2));
    let reach = b.norm();
    if l <= 0.0 {
        return UnitLink {
            com: Vector3::zeros(),
            inertia: Matrix3::zeros(),
            shape: None,
        };
    }
    // a cylinder with the same longitudinal radius of gyration has radius √2 r_long L
    let radius = std::f64::consts::SQRT_2 * r_long * l;
    if reach <= 1e-12 * l {
        // a hub (children on opposite sides, e.g. the hips): isotropic, drawn as a sphere
        return UnitLink {
            com: Vector3::zeros(),
            inertia: Matrix3::identity() * rt,
            shape: Some(Superquadric {
                center: Vector3::zeros(),
                rot: Matrix3::identity(),
                size: Vector3::repeat(radius.max(0.5 * r_trans * l)),
                exponents: [1.0, 1.0],
            }),
        };
    }
    let u = b / reach;
    let uu = u * u.transpose();
    UnitLink {
        com: b * com_frac,
        inertia: (Matrix3::identity() - uu) * rt + uu * rl,
        shape: Some(Superquadric {
            center: b * 0.5,
            rot: frame_with_z(&u),
            size: Vector3::new(radius, radius, 0.5 * reach),
            exponents: [0.5, 1.0],
        }),
    }
}

/// A rotation whose third column is the unit vector `u`.
fn frame_with_z(u: &Vector3<f64>) -> Matrix3<f64> {
    let a = if u.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let x = (a - u * a.dot(u)).normalize();
    let y = u.cross(&x);
    Matrix3::from_columns(&[x, y, *u])
}

/// Link masses, centres of mass, inertias and shapes of a skeleton (see the module doc for the
/// rules). Returns one [`LinkMass`] per bone; the masses sum to `body.mass_kg`.
///
/// Errors: a non-positive body mass, a regression ([`SegmentTable::Regression`]) on a human
/// skeleton without a positive `body.height_m`, an override naming no joint, negative
/// overrides, or overrides that exceed the body mass. Notes on the segment masses (a
/// regression row held at its floor) come from [`segment_masses`], which the pipeline calls
/// for them.
pub fn distribute(bones: &[Bone], body: &BodyParams) -> Result<Vec<LinkMass>, Error> {
    distribute_classes(bones, body, &classes_by_name(bones))
}

/// The segment a joint's link belongs to, and whether it is a shoulder-girdle, hip-bone or
/// breast bone of the trunk (weighted by [`GIRDLE_WEIGHT`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SegmentOf {
    pub class: Option<(Segment, Side)>,
    pub girdle: bool,
}

/// Step 1 of [`distribute`]: the classes the joint names say ([`classify`], inherited from the
/// parent when a name says nothing), a humanoid's branching unnamed root as the pelvis.
pub fn classes_by_name(bones: &[Bone]) -> Vec<SegmentOf> {
    let n = bones.len();
    let mut class: Vec<Option<(Segment, Side)>> = Vec::with_capacity(n);
    for b in bones {
        let inherited = b.parent.and_then(|p| class[p]);
        class.push(classify(&b.name).or(inherited));
    }
    // a humanoid's root whose name says nothing but which branches (MakeHuman's `Root` above
    // `Hips` and `Spine1`, both at one point) is the body's hub, the pelvis: trunk. Left
    // massless, its rotation would be undone by its children's and D(q) would be singular; a
    // root with one child is a helper, which the pipeline folds into that child.
    let humanoid = has_trunk(bones.iter().map(|b| b.name.as_str()));
    let branching = |j: usize| bones.iter().filter(|c| c.parent == Some(j)).count() > 1;
    if let Some(r) = (0..n).find(|&j| bones[j].parent.is_none())
        && humanoid
        && class[r].is_none()
        && branching(r)
    {
        class[r] = Some((Segment::Trunk, Side::Center));
    }
    (0..n)
        .map(|j| SegmentOf {
            class: class[j],
            girdle: is_appendage(&bones[j].name),
        })
        .collect()
}

/// [`distribute`] with the joints' segments given (`classes`, one per bone: by name,
/// [`classes_by_name`], or by the skeleton's topology, `model::skeleton`).
pub fn distribute_classes(
    bones: &[Bone],
    body: &BodyParams,
    classes: &[SegmentOf],
) -> Result<Vec<LinkMass>, Error> {
    let total = body.mass_kg;
    if !(total.is_finite() && total > 0.0) {
        return Err(Error::Invalid(format!(
            "body mass {total} kg: give a positive mass (--mass or `mass` in the scene)"
        )));
    }
    let n = bones.len();
    if classes.len() != n {
        return Err(Error::Invalid(format!(
            "{} segment classes for {n} bones",
            classes.len()
        )));
    }
    let geom: Vec<(Vector3<f64>, f64)> = bones.iter().map(Bone::geometry).collect();
    let class: Vec<Option<(Segment, Side)>> = classes.iter().map(|c| c.class).collect();
    let has_trunk = class.iter().any(|c| matches!(c, Some((Segment::Trunk, _))));

    let mut mass = vec![0.0; n];
    let mut unit: Vec<UnitLink> = Vec::with_capacity(n);
    if has_trunk {
        // 2. segment instances and their masses; missing ones go proximal
        let seg_kg = segment_masses(body)?;
        let mut instance_mass: BTreeMap<(Segment, Side), f64> = BTreeMap::new();
        let present: std::collections::BTreeSet<(Segment, Side)> =
            class.iter().flatten().copied().collect();
        let expected = seg_kg.kg.iter().flat_map(|(&seg, &kg)| {
            let sides: &[Side] = if seg.is_limb() {
                &[Side::Left, Side::Right]
            } else {
                &[Side::Center]
            };
            sides.iter().map(move |s| (seg, *s, kg))
        });
        for (seg, side, kg) in expected {
            let mut key = (seg, side);
            while !present.contains(&key) {
                key = match key.0.proximal() {
                    Some(Segment::Trunk) => (Segment::Trunk, Side::Center),
                    Some(p) => (p, side),
                    None => break,
                };
            }
            *instance_mass.entry(key).or_insert(0.0) += kg;
        }
        // unsided limb joints (`thigh` without L/R) get one limb's share
        for key in &present {
            if key.1 == Side::Center && key.0.is_limb() {
                *instance_mass.entry(*key).or_insert(0.0) += seg_kg.kg(key.0);
            }
        }
        // 3. share each instance among its joints by bone length (equally if all are zero);
        //    shoulder-girdle and breast bones count a quarter of their length in the trunk
        let weight = |j: usize| {
            if classes[j].girdle {
                GIRDLE_WEIGHT * geom[j].1
            } else {
                geom[j].1
            }
        };
        for (key, m) in &instance_mass {
            let members: Vec<usize> = (0..n).filter(|&j| class[j] == Some(*key)).collect();
            let w: Vec<f64> = members.iter().map(|&j| weight(j)).collect();
            for (share, &j) in shares(&w).iter().zip(&members) {
                mass[j] += m * share;
            }
        }
        let radii = segment_radii(body)?;
        for j in 0..n {
            let (b, l) = &geom[j];
            unit.push(match class[j] {
                Some((seg, _)) => {
                    let p = de_leva(seg, body.sex);
                    // de Leva measures head and trunk from their upper end; BVH bones point up
                    let com_frac = match seg {
                        Segment::Head | Segment::Trunk => 1.0 - p.com_pct / 100.0,
                        _ => p.com_pct / 100.0,
                    };
                    let [r_sag, r_trans, r_long] = radii.pct(seg);
                    let r_trans = 0.5 * (r_sag + r_trans) / 100.0;
                    unit_link(b, *l, com_frac, r_trans, r_long / 100.0)
                }
                None => unit_link(b, *l, 0.5, FALLBACK_R_TRANS, FALLBACK_R_LONG),
            });
        }
    } else {
        // 4. fallback: by bone volume (cylinders of radius 0.1 L, volume ∝ L³)
        let w: Vec<f64> = geom.iter().map(|g| g.1.powi(3)).collect();
        let share = shares(&w);
        for j in 0..n {
            mass[j] = total * share[j];
            unit.push(unit_link(
                &geom[j].0,
                geom[j].1,
                0.5,
                FALLBACK_R_TRANS,
                FALLBACK_R_LONG,
            ));
        }
    }

    // 5. overrides, then rescale the others so that the sum is exactly the body mass
    let mut fixed = vec![false; n];
    for (name, &m) in &body.link_mass {
        let j = bones.iter().position(|b| &b.name == name).ok_or_else(|| {
            Error::Invalid(format!(
                "link mass override for {name:?}, which is not a joint of this skeleton \
                 (joints: {})",
                bones
                    .iter()
                    .map(|b| b.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })?;
        if !(m.is_finite() && m >= 0.0) {
            return Err(Error::Invalid(format!(
                "link mass override {name:?} = {m} kg: give a mass ≥ 0"
            )));
        }
        mass[j] = m;
        fixed[j] = true;
    }
    let fixed_sum: f64 = (0..n).filter(|&j| fixed[j]).map(|j| mass[j]).sum();
    let free_sum: f64 = (0..n).filter(|&j| !fixed[j]).map(|j| mass[j]).sum();
    let rest = total - fixed_sum;
    if rest < -1e-12 * total {
        return Err(Error::Invalid(format!(
            "link mass overrides sum to {fixed_sum} kg, more than the body mass {total} kg: \
             lower them or raise the body mass"
        )));
    }
    if rest > 1e-12 * total && free_sum <= 0.0 {
        return Err(Error::Invalid(format!(
            "link mass overrides sum to {fixed_sum} kg and no other link carries mass: the \
             remaining {rest} kg of the {total} kg body has nowhere to go; override fewer links"
        )));
    }
    if free_sum > 0.0 {
        let k = rest.max(0.0) / free_sum;
        for j in (0..n).filter(|&j| !fixed[j]) {
            mass[j] *= k;
        }
    }
    // put the rounding residual on the heaviest rescaled link so that the sum is exact and
    // the overrides stay as given
    let residual = total - mass.iter().sum::<f64>();
    let heaviest = (0..n)
        .filter(|&j| !fixed[j] || free_sum <= 0.0)
        .max_by(|&a, &b| mass[a].total_cmp(&mass[b]));
    if let Some(h) = heaviest {
        mass[h] += residual;
    }

    Ok((0..n)
        .map(|j| {
            let (inertia_com, shape) = if geom[j].1 <= 0.0 && mass[j] > 0.0 {
                let (r, i) = boneless_sphere(mass[j]);
                let sphere = Superquadric {
                    center: Vector3::zeros(),
                    rot: Matrix3::identity(),
                    size: Vector3::repeat(r),
                    exponents: [1.0, 1.0],
                };
                (i, Some(sphere))
            } else {
                (unit[j].inertia * mass[j], unit[j].shape)
            };
            LinkMass {
                mass: mass[j],
                com: unit[j].com,
                inertia_com,
                shape,
                segment: if has_trunk { class[j] } else { None },
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A body whose segment masses are de Leva's fixed fractions.
    fn fractions(mass_kg: f64, sex: Sex) -> BodyParams {
        BodyParams {
            segments: SegmentTable::Fractions,
            ..BodyParams::new(mass_kg, sex)
        }
    }

    /// A body whose segment masses come from the regression, 1.75 m tall.
    fn regression(mass_kg: f64, sex: Sex) -> BodyParams {
        BodyParams {
            height_m: Some(1.75),
            ..BodyParams::new(mass_kg, sex)
        }
    }

    #[test]
    fn each_sex_sums_to_the_whole_body() {
        for sex in [Sex::Male, Sex::Female] {
            let s: f64 = DE_LEVA_1996
                .iter()
                .filter(|r| r.sex == sex)
                .map(|r| r.mass_pct * if r.segment.is_limb() { 2.0 } else { 1.0 })
                .sum();
            assert!((s - 100.0).abs() < 0.06, "{sex}: {s}");
        }
    }

    #[test]
    fn naming_schemes_map_to_segments() {
        use Segment::*;
        use Side::*;
        let cases = [
            ("LeftUpLeg", Thigh, Left),
            ("mixamorig:RightUpLeg", Thigh, Right),
            ("RightLeg", Shank, Right),
            ("LHipJoint", Trunk, Center),
            ("LowerBack", Trunk, Center),
            ("Neck1", Head, Center),
            ("LFingers", Hand, Left),
            ("RThumb", Hand, Right),
            ("hip", Trunk, Center),
            ("abdomen", Trunk, Center),
            ("chest", Trunk, Center),
            ("lThigh", Thigh, Left),
            ("lShin", Shank, Left),
            ("lCollar", Trunk, Center),
            ("lShldr", UpperArm, Left),
            ("rForeArm", Forearm, Right),
            ("UpperLeg_L", Thigh, Left),
            ("LowerArm_R", Forearm, Right),
            ("Toes_L", Foot, Left),
            ("upperleg01.L", Thigh, Left),
            ("lowerleg02.R", Shank, Right),
            ("metatarsal3.L", Foot, Left),
            ("wrist.R", Hand, Right),
            ("thigh.L", Thigh, Left),
            ("shin.R", Shank, Right),
            ("upper_arm.L", UpperArm, Left),
            ("forearm.R", Forearm, Right),
            ("LeftArm", UpperArm, Left),
            ("LeftForeArm", Forearm, Left),
            ("LeftToeBase", Foot, Left),
            ("Spine1", Trunk, Center),
            ("UpArm_L", UpperArm, Left),
            ("LoLeg_R", Shank, Right),
            ("__UpLeg_L", Thigh, Left),
            ("LeftHandThumb1", Hand, Left),
        ];
        for (name, seg, side) in cases {
            assert_eq!(classify(name), Some((seg, side)), "{name}");
        }
        assert_eq!(classify("joint_Root"), None);
        assert_eq!(classify("special04"), None);
    }

    fn chain() -> Vec<Bone> {
        // hips → spine; hips → left thigh → left shank; no arms, no head, no right leg
        let v = Vector3::new;
        vec![
            Bone {
                name: "Hips".into(),
                parent: None,
                ends: vec![v(0.0, 0.3, 0.0), v(0.1, -0.05, 0.0)],
            },
            Bone {
                name: "Spine".into(),
                parent: Some(0),
                ends: vec![v(0.0, 0.3, 0.0)],
            },
            Bone {
                name: "LeftUpLeg".into(),
                parent: Some(0),
                ends: vec![v(0.0, -0.4, 0.0)],
            },
            Bone {
                name: "LeftLeg".into(),
                parent: Some(2),
                ends: vec![v(0.0, -0.4, 0.0)],
            },
        ]
    }

    #[test]
    fn masses_sum_to_the_body_and_missing_segments_go_proximal() {
        let links = distribute(&chain(), &fractions(80.0, Sex::Female)).unwrap();
        let sum: f64 = links.iter().map(|l| l.mass).sum();
        assert_eq!(sum, 80.0);
        // the left foot is missing: its mass joins the left shank (the female table sums to
        // 99.99 %, so compare ratios)
        let p = |s| de_leva(s, Sex::Female).mass_pct;
        let ratio = links[3].mass / links[2].mass;
        let expected = (p(Segment::Shank) + p(Segment::Foot)) / p(Segment::Thigh);
        assert!((ratio - expected).abs() < 1e-12, "{ratio} vs {expected}");
        assert!((links[2].mass - p(Segment::Thigh) * 0.8).abs() < 1e-2);
        // the thigh COM lies on the bone at de Leva's fraction from the hip
        let c = links[2].com;
        assert!((c.y + 0.4 * 0.3612).abs() < 1e-12 && c.x == 0.0, "{c}");
        // longitudinal inertia from the longitudinal radius of gyration
        let i_long = links[2].inertia_com[(1, 1)];
        assert!((i_long - links[2].mass * (0.162 * 0.4_f64).powi(2)).abs() < 1e-12);
    }

    #[test]
    fn regression_masses_reach_the_links_and_shift_with_mass_at_one_height() {
        // the left thigh's share of the body: the regression's grows with mass at 1.75 m, de
        // Leva's fractions are the same at every mass
        let share = |body: BodyParams| distribute(&chain(), &body).unwrap()[2].mass / body.mass_kg;
        let (light, heavy) = (
            share(regression(60.0, Sex::Male)),
            share(regression(100.0, Sex::Male)),
        );
        assert!(heavy > light * 1.005, "{light} → {heavy}");
        let (light, heavy) = (
            share(fractions(60.0, Sex::Male)),
            share(fractions(100.0, Sex::Male)),
        );
        assert!((heavy - light).abs() < 1e-15, "{light} → {heavy}");
        // a human skeleton needs a stature for the regression; bone volume needs none
        assert!(distribute(&chain(), &BodyParams::new(70.0, Sex::Male)).is_err());
    }

    #[test]
    fn a_heavier_body_of_the_same_height_gets_larger_radii_of_gyration_not_a_rescale() {
        // the left thigh (0.4 m bone along −y): its radii of gyration as fractions of the bone,
        // across (x) and about it (y), from its link's inertia
        let radii = |body: BodyParams| {
            let l = &distribute(&chain(), &body).unwrap()[2];
            let r = |i: f64| (i / l.mass).sqrt() / 0.4;
            (r(l.inertia_com[(0, 0)]), r(l.inertia_com[(1, 1)]))
        };
        let (light, heavy) = (
            radii(regression(60.0, Sex::Male)),
            radii(regression(100.0, Sex::Male)),
        );
        assert!(heavy.0 > light.0 * 1.02, "across: {light:?} → {heavy:?}");
        assert!(
            heavy.1 > light.1 * 1.1,
            "about the bone: {light:?} → {heavy:?}"
        );
        // de Leva's fractions: his radii exactly, the same at every mass
        let p = de_leva(Segment::Thigh, Sex::Male);
        for m in [60.0, 100.0] {
            let (across, along) = radii(fractions(m, Sex::Male));
            assert!((across - 0.5 * (p.r_sag_pct + p.r_trans_pct) / 100.0).abs() < 1e-12);
            assert!((along - p.r_long_pct / 100.0).abs() < 1e-12);
        }
    }

    #[test]
    fn a_clavicle_weighs_less_than_a_spine_segment_of_the_same_length() {
        let v = Vector3::new;
        let bone = |name: &str, parent, end| Bone {
            name: name.into(),
            parent,
            ends: vec![end],
        };
        let bones = vec![
            bone("Hips", None, v(0.0, 0.2, 0.0)),
            bone("Spine", Some(0), v(0.0, 0.2, 0.0)),
            bone("LeftShoulder", Some(1), v(0.2, 0.0, 0.0)),
        ];
        let links = distribute(&bones, &regression(75.0, Sex::Male)).unwrap();
        let ratio = links[2].mass / links[1].mass;
        assert!(ratio < 2.0 * GIRDLE_WEIGHT, "{ratio}");
        let w = shares(&[0.2, 0.2, GIRDLE_WEIGHT * 0.2]);
        assert!((ratio - w[2] / w[1]).abs() < 1e-12);
    }

    #[test]
    fn a_boneless_leaf_gets_a_little_mass_and_a_sphere_inertia() {
        let mut bones = chain();
        bones.push(Bone {
            name: "LeftFoot".into(),
            parent: Some(3),
            ends: vec![Vector3::zeros()],
        });
        bones.push(Bone {
            name: "LeftToeBase".into(),
            parent: Some(4),
            ends: vec![],
        });
        bones[3].ends = vec![Vector3::new(0.0, -0.4, 0.0)];
        bones[4].ends = vec![Vector3::new(0.0, -0.05, 0.15)];
        let links = distribute(&bones, &regression(75.0, Sex::Male)).unwrap();
        let toe = &links[5];
        assert!(
            toe.mass > 0.0 && toe.mass < 0.1 * links[4].mass,
            "{}",
            toe.mass
        );
        let (r, i) = boneless_sphere(toe.mass);
        assert_eq!(toe.inertia_com, i);
        assert!(r > 0.01 && i[(0, 0)] > 0.0);
    }

    #[test]
    fn overrides_are_kept_and_the_rest_rescaled() {
        let mut body = regression(70.0, Sex::Male);
        body.link_mass.insert("LeftLeg".into(), 10.0);
        let links = distribute(&chain(), &body).unwrap();
        assert_eq!(links[3].mass, 10.0);
        let sum: f64 = links.iter().map(|l| l.mass).sum();
        assert!((sum - 70.0).abs() < 1e-12);
        body.link_mass.insert("Nope".into(), 1.0);
        assert!(distribute(&chain(), &body).is_err());
        body.link_mass.remove("Nope");
        body.link_mass.insert("Spine".into(), 65.0);
        assert!(distribute(&chain(), &body).is_err());
    }

    #[test]
    fn a_humanoids_branching_root_without_a_segment_name_is_the_pelvis() {
        // MakeHuman: `Root` above `Hips` (the legs) and `Spine` at one point
        let mut bones = chain();
        bones[0].name = "Root".into();
        let links = distribute(&bones, &regression(75.0, Sex::Male)).unwrap();
        assert!(links[0].mass > 0.5, "{}", links[0].mass);
        // a helper root with one child stays massless (the pipeline folds it)
        let mut helper = chain();
        helper[0].name = "joint_Root".into();
        helper[0].ends.truncate(1);
        helper[2].parent = Some(1); // the thigh hangs from the spine: the root has one child
        let links = distribute(&helper, &regression(75.0, Sex::Male)).unwrap();
        assert_eq!(links[0].mass, 0.0);
    }

    #[test]
    fn unknown_names_fall_back_to_bone_volume() {
        let mut bones = chain();
        for (i, b) in bones.iter_mut().enumerate() {
            b.name = format!("link{i}");
        }
        // (no stature given: bone volume needs none)
        let links = distribute(&bones, &BodyParams::new(50.0, Sex::Male)).unwrap();
        let sum: f64 = links.iter().map(|l| l.mass).sum();
        assert!((sum - 50.0).abs() < 1e-12);
        // equal 0.4 m bones get equal mass; the 0.3 m spine about (0.3/0.4)³ of that
        assert!((links[2].mass - links[3].mass).abs() < 1e-12);
        let r = links[1].mass / links[2].mass;
        assert!((r - 0.421875).abs() < 0.05, "{r}");
    }
}
