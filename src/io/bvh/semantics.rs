//! What the numbers of a BVH file mean: position-channel modes, forward kinematics straight
//! from the definition, up axis, length unit and stature.
//!
//! All lengths here are in the file's units unless a name ends in `_m`; angles in the file are
//! degrees. The forward kinematics below is deliberately the plain definition (one matrix
//! product per channel, no model, no caching) so that it can serve as the independent
//! reference for `model`'s kinematics.

use super::{Bvh, BvhJoint};
use crate::error::Error;
use crate::rotation::axis_rotation;
use nalgebra::{Matrix3, Vector3};
use std::str::FromStr;

/// How position channels relate to a joint's OFFSET (a user option; `auto` by default).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PositionMode {
    /// Translation = OFFSET + channel values (most parsers; MakeHuman files).
    Add,
    /// Translation = channel values, the OFFSET only a rest pose (Blender's importer; Bandai
    /// files).
    Replace,
    /// Per joint from the data: see [`resolve_position_modes`].
    #[default]
    Auto,
}

impl FromStr for PositionMode {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s.to_ascii_lowercase().as_str() {
            "add" => Ok(PositionMode::Add),
            "replace" => Ok(PositionMode::Replace),
            "auto" => Ok(PositionMode::Auto),
            _ => Err(Error::Invalid(format!(
                "unknown position mode '{s}': expected add, replace or auto"
            ))),
        }
    }
}

impl std::fmt::Display for PositionMode {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            PositionMode::Add => "add",
            PositionMode::Replace => "replace",
            PositionMode::Auto => "auto",
        })
    }
}

/// What position channels on joints other than the body's root become (a user option, `weld`
/// by default): bones do not stretch, so where a file restates a bone's OFFSET in them or moves
/// it by capture noise they are held at their mean (`motion::weld`); `keep` makes each a
/// prismatic coordinate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum JointTranslations {
    /// Held at their mean over the take: no coordinate.
    #[default]
    Weld,
    /// One prismatic coordinate per channel (euler model), a free joint (ball model).
    Keep,
}

impl FromStr for JointTranslations {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s.trim().to_ascii_lowercase().as_str() {
            "weld" => Ok(JointTranslations::Weld),
            "keep" => Ok(JointTranslations::Keep),
            _ => Err(Error::Invalid(format!(
                "unknown joint translations '{s}': expected weld or keep"
            ))),
        }
    }
}

impl std::fmt::Display for JointTranslations {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            JointTranslations::Weld => "weld",
            JointTranslations::Keep => "keep",
        })
    }
}

/// The mode in force for one joint.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ResolvedPosition {
    /// The joint has no position channels: translation = OFFSET.
    None,
    /// Translation = OFFSET + channel values (per axis present).
    Add,
    /// Translation = channel value on each axis that has a channel, OFFSET on the others.
    Replace,
}

impl std::fmt::Display for ResolvedPosition {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ResolvedPosition::None => "none",
            ResolvedPosition::Add => "add",
            ResolvedPosition::Replace => "replace",
        })
    }
}

/// The position mode of every joint (indexed like `bvh.joints`).
///
/// `Add` and `Replace` apply to every joint with position channels. `Auto` decides per joint
/// from the mean `m` of the joint's position-channel values over the take and its OFFSET `o`,
/// both restricted to the axes that have a channel:
///
/// 1. **clear evidence:** `|m − o| ≤ 5 % |o|` (the values repeat the OFFSET, as in the
///    Bandai files), or a non-zero OFFSET that the first frame's values repeat (a travelling
///    root whose OFFSET is its start, as LaFAN1 writes it) → replace; `|m| ≤ 5 % |o|` (the values are deltas around zero, as in the
///    MakeHuman files) → add;
/// 2. **otherwise** (a travelling root, a zero OFFSET where both modes agree): the file's
///    majority among the joints with clear evidence, since one exporter wrote them all (the
///    Bandai `bye_old` hips have an OFFSET 4.5 m from the capture start, but every other
///    joint repeats its OFFSET, so the hips replace too);
/// 3. **no majority** (typically only the root has position channels): replace when the
///    values sit nearer the OFFSET than the origin, `|m − o| < |m|`, add otherwise. The PyMO
///    sample's root OFFSET `11 35 −54` with values around `−6 35 −163` is replace (adding
///    would float the hips at twice their height); a zero OFFSET gives add.
pub fn resolve_position_modes(bvh: &Bvh, mode: PositionMode) -> Vec<ResolvedPosition> {
    if mode != PositionMode::Auto {
        return bvh
            .joints
            .iter()
            .map(|joint| match (joint.has_position(), mode) {
                (false, _) => ResolvedPosition::None,
                (true, PositionMode::Replace) => ResolvedPosition::Replace,
                (true, _) => ResolvedPosition::Add,
            })
            .collect();
    }
    let evidence: Vec<Evidence> = bvh.joints.iter().map(|j| evidence(bvh, j)).collect();
    let replace = evidence
        .iter()
        .filter(|e| matches!(e, Evidence::Replace))
        .count();
    let add = evidence
        .iter()
        .filter(|e| matches!(e, Evidence::Add))
        .count();
    evidence
        .into_iter()
        .map(|e| match e {
            Evidence::NoChannels => ResolvedPosition::None,
            Evidence::Replace => ResolvedPosition::Replace,
            Evidence::Add => ResolvedPosition::Add,
            Evidence::Unclear { nearer_offset } => {
                if replace > add || (replace == add && nearer_offset) {
                    ResolvedPosition::Replace
                } else {
                    ResolvedPosition::Add
                }
            }
        })
        .collect()
}

/// What one joint's own data says about its position mode (rule 1 of
/// [`resolve_position_modes`]).
enum Evidence {
    NoChannels,
    Replace,
    Add,
    /// Neither; `nearer_offset` is rule 3, `|m − o| < |m|`.
    Unclear {
        nearer_offset: bool,
    },
}

/// Relative tolerance of "the values repeat the OFFSET" / "the values are zero".
const CLEAR: f64 = 0.05;

fn evidence(bvh: &Bvh, joint: &BvhJoint) -> Evidence {
    if !joint.has_position() {
        return Evidence::NoChannels;
    }
    let cols = joint.position_columns();
    let mut mean: Vector3<f64> = Vector3::zeros();
    let mut first: Vector3<f64> = Vector3::zeros();
    let mut offset: Vector3<f64> = Vector3::zeros();
    for axis in 0..3 {
        if let Some(c) = cols[axis] {
            let col = joint.first_channel + c;
            let sum: f64 = (0..bvh.frames).map(|k| bvh.frame(k)[col]).sum();
            mean[axis] = sum / bvh.frames.max(1) as f64;
            first[axis] = bvh.frames.checked_sub(1).map_or(0.0, |_| bvh.frame(0)[col]);
            offset[axis] = joint.offset[axis];
        }
    }
    let (to_offset, to_zero, tol) = ((mean - offset).norm(), mean.norm(), CLEAR * offset.norm());
    // a travelling root whose OFFSET is its first position, as LaFAN1 writes it: the values
    // are positions, not steps from the OFFSET (adding would float the body at twice its
    // height)
    let first_is_offset = (first - offset).norm() <= 1e-6 * offset.norm();
    if tol > 0.0 && (to_offset <= tol || first_is_offset) {
        Evidence::Replace
    } else if tol > 0.0 && to_zero <= tol {
        Evidence::Add
    } else {
        Evidence::Unclear {
            nearer_offset: to_offset < to_zero,
        }
    }
}

/// The translation part of `joint`'s local transform (file units, parent frame) in the frame
/// whose values are `frame_row` (a whole frame, `bvh.frame(k)`).
pub fn joint_translation(
    joint: &BvhJoint,
    mode: ResolvedPosition,
    frame_row: &[f64],
) -> Vector3<f64> {
    let mut t = joint.offset;
    if mode == ResolvedPosition::None {
        return t;
    }
    for (n, c) in joint.channels.iter().enumerate() {
        if !c.is_rotation() {
            let v = frame_row[joint.first_channel + n];
            match mode {
                ResolvedPosition::Add => t[c.axis()] += v,
                _ => t[c.axis()] = v,
            }
        }
    }
    t
}

/// The rotation part of `joint`'s local transform, `R = R_c1(a1) · R_c2(a2) · R_c3(a3)` over
/// its rotation channels in file order (degrees in the file), for the frame `frame_row`.
pub fn joint_rotation(joint: &BvhJoint, frame_row: &[f64]) -> Matrix3<f64> {
    let mut r = Matrix3::identity();
    for (n, c) in joint.channels.iter().enumerate() {
        if c.is_rotation() {
            let a = frame_row[joint.first_channel + n].to_radians();
            r *= axis_rotation(c.axis(), a);
        }
    }
    r
}

/// World position (file units, the file's axes) of every joint at frame `frame`, given one
/// mode per joint (from [`resolve_position_modes`]), from the definition:
/// `p_j = p_parent + R_parent · t_j`, `R_j = R_parent · R(channels of j)`, with `t_j` from
/// [`joint_translation`] and `R(channels of j)` from [`joint_rotation`].
pub fn bvh_world_positions(
    bvh: &Bvh,
    modes: &[ResolvedPosition],
    frame: usize,
) -> Vec<Vector3<f64>> {
    bvh_world_poses(bvh, modes, frame).0
}

/// World position of every End Site at frame `frame`, in joint order and, within a joint, in
/// file order (`p = p_j + R_j · offset`).
pub fn bvh_end_site_positions(
    bvh: &Bvh,
    modes: &[ResolvedPosition],
    frame: usize,
) -> Vec<Vector3<f64>> {
    let (p, r) = bvh_world_poses(bvh, modes, frame);
    bvh.joints
        .iter()
        .enumerate()
        .flat_map(|(j, joint)| joint.end_sites.iter().map(move |s| (j, s)))
        .map(|(j, s)| p[j] + r[j] * s)
        .collect()
}

/// World position and orientation (file units, the file's axes) of every joint at frame
/// `frame`, as [`bvh_world_positions`] computes them.
pub fn bvh_world_poses(
    bvh: &Bvh,
    modes: &[ResolvedPosition],
    frame: usize,
) -> (Vec<Vector3<f64>>, Vec<Matrix3<f64>>) {
    let row = bvh.frame(frame);
    let n = bvh.joints.len();
    let mut p: Vec<Vector3<f64>> = Vec::with_capacity(n);
    let mut r: Vec<Matrix3<f64>> = Vec::with_capacity(n);
    for (j, joint) in bvh.joints.iter().enumerate() {
        let t = joint_translation(joint, modes[j], row);
        let rot = joint_rotation(joint, row);
        match joint.parent {
            Some(q) => {
                p.push(p[q] + r[q] * t);
                r.push(r[q] * rot);
            }
            None => {
                p.push(t);
                r.push(rot);
            }
        }
    }
    (p, r)
}

/// Rest-pose positions (file units): every joint (OFFSETs only, no channel values), then
/// every End Site in the order of [`bvh_end_site_positions`].
pub fn rest_points(bvh: &Bvh) -> Vec<Vector3<f64>> {
    let mut p: Vec<Vector3<f64>> = Vec::with_capacity(bvh.joints.len());
    for joint in &bvh.joints {
        let base = joint.parent.map_or(Vector3::zeros(), |q| p[q]);
        p.push(base + joint.offset);
    }
    let sites: Vec<Vector3<f64>> = bvh
        .joints
        .iter()
        .enumerate()
        .flat_map(|(j, joint)| joint.end_sites.iter().map(move |s| (j, s)))
        .map(|(j, s)| p[j] + s)
        .collect();
    p.extend(sites);
    p
}

/// A coordinate axis of the file taken as "up" (gravity along its negative direction).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UpAxis {
    X,
    Y,
    Z,
}

impl UpAxis {
    /// 0, 1, 2.
    pub fn index(self) -> usize {
        match self {
            UpAxis::X => 0,
            UpAxis::Y => 1,
            UpAxis::Z => 2,
        }
    }
    fn from_index(i: usize) -> UpAxis {
        match i {
            0 => UpAxis::X,
            1 => UpAxis::Y,
            _ => UpAxis::Z,
        }
    }
}

impl FromStr for UpAxis {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s.to_ascii_lowercase().as_str() {
            "x" => Ok(UpAxis::X),
            "y" => Ok(UpAxis::Y),
            "z" => Ok(UpAxis::Z),
            _ => Err(Error::Invalid(format!(
                "unknown up axis '{s}': expected x, y or z"
            ))),
        }
    }
}

impl std::fmt::Display for UpAxis {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            UpAxis::X => "x",
            UpAxis::Y => "y",
            UpAxis::Z => "z",
        })
    }
}

/// The up axis of the file.
///
/// A standing human is longest from feet to head, so the up axis is the axis of largest
/// extent of the body. The extent is measured in the poses of the take itself (the median
/// over up to 64 evenly spaced frames, position channels resolved by `auto`), not only in the
/// rest pose, because some rest poses are not upright: the Bandai files' bones all lie along
/// local X, so their OFFSET-only pose lies on its side while every frame stands along Y.
/// When the two largest extents are within 20 % of each other (a T-pose, where the arm span
/// ≈ the stature), the rest pose decides if its own largest extent is clear; otherwise mirror
/// symmetry does: a body is left–right symmetric but not head–feet symmetric, so the up axis
/// is the one of the two whose mirror image of the first frame (about the middle of the
/// extent) lies farther, on average, from the nearest body point.
///
/// A root joint with a single child and no End Site is a placement node (Bandai's
/// `joint_Root`, which stays on the floor while the hips travel), not a body point: it is
/// left out of these extents.
pub fn detect_up(bvh: &Bvh) -> UpAxis {
    let modes = resolve_position_modes(bvh, PositionMode::Auto);
    let ext = median_extents(bvh, &modes);
    let [first, second, _] = by_extent(ext);
    if ext[second] < TIE * ext[first] {
        return UpAxis::from_index(first);
    }
    let rest = body_points(bvh, &rest_points(bvh));
    let rest_ext = extents(&rest);
    let [r1, r2, _] = by_extent(rest_ext);
    if rest_ext[r2] < TIE * rest_ext[r1] && (r1 == first || r1 == second) {
        return UpAxis::from_index(r1);
    }
    let pts = body_points(bvh, &pose_points(bvh, &modes, 0));
    if mirror_asymmetry(&pts, second) > mirror_asymmetry(&pts, first) {
        UpAxis::from_index(second)
    } else {
        UpAxis::from_index(first)
    }
}

/// The up axis of a human skeleton from its legs: the axis along which, over the take's frames
/// (the median of up to 64), the hip joints (`hips`) stand furthest from the feet (`feet`),
/// when that distance is at least twice the one along either other axis. Hips stand over the
/// feet whether the body is upright, bent over a box or crouching, where the body's largest
/// extent (what [`detect_up`] measures) can lie along the floor: an inertial-suit box lift,
/// bent over most of the take, fell forward. `None` (the caller then uses [`detect_up`]) when
/// the legs lie along no clear axis (lying down, a split).
pub fn detect_up_by_legs(bvh: &Bvh, hips: &[usize], feet: &[usize]) -> Option<UpAxis> {
    if hips.is_empty() || feet.is_empty() {
        return None;
    }
    let modes = resolve_position_modes(bvh, PositionMode::Auto);
    let mean = |p: &[Vector3<f64>], of: &[usize]| {
        of.iter().map(|&j| p[j]).sum::<Vector3<f64>>() / of.len() as f64
    };
    let mut legs: [Vec<f64>; 3] = Default::default();
    for k in sampled_frames(bvh) {
        let p = bvh_world_positions(bvh, &modes, k);
        let d = mean(&p, hips) - mean(&p, feet);
        for (axis, l) in legs.iter_mut().enumerate() {
            l.push(d[axis].abs());
        }
    }
    let m: Vec<f64> = legs
        .iter_mut()
        .map(|l| {
            l.sort_by(f64::total_cmp);
            l[l.len() / 2]
        })
        .collect();
    let [first, second, _] = by_extent([m[0], m[1], m[2]]);
    (m[first] > 0.0 && m[first] >= 2.0 * m[second]).then(|| UpAxis::from_index(first))
}

/// The up axis of a skeleton that is not a human's, from its feet: the axis along which, in the
/// take's frames, the most limb tips (End Sites, or joints without children) lie together at
/// the lowest level, within 5 % of the body's extent of its lowest point. A quadruped's four
/// feet, a crab's eight, a bird's two stand on the floor; along the other axes one tip (a
/// nose, a tail, a claw) is the extreme, except along the lateral axis, where the left (or
/// right) limbs share the extreme: that axis, the one about whose middle the body is most
/// nearly its own mirror image, is left out. The count is the median over up to 64 frames;
/// `None` when neither remaining axis has at least two tips on its floor, more than the other
/// (the caller then uses [`detect_up`]). A body longer than tall, as most quadrupeds are, defeats the largest
/// extent rule of [`detect_up`]: an elephant would fall along its trunk.
pub fn detect_up_by_feet(bvh: &Bvh) -> Option<UpAxis> {
    let modes = resolve_position_modes(bvh, PositionMode::Auto);
    // limb ends: joints without child joints, each with its End Sites (a toe's End Site may
    // point up from a toe joint on the floor)
    let ends: Vec<usize> = (0..bvh.joints.len())
        .filter(|&j| !bvh.joints.iter().any(|c| c.parent == Some(j)))
        .collect();
    let mut counts: [Vec<usize>; 3] = Default::default();
    for k in sampled_frames(bvh) {
        let (p, r) = bvh_world_poses(bvh, &modes, k);
        let body = body_points(bvh, &points_of(bvh, &p, &r));
        let near = 0.05 * extents(&body).iter().copied().fold(0.0, f64::max);
        for (axis, c) in counts.iter_mut().enumerate() {
            let (lo, _) = min_max(&body, axis);
            let lowest = |j: usize| {
                let sites = bvh.joints[j]
                    .end_sites
                    .iter()
                    .map(|s| (p[j] + r[j] * s)[axis]);
                sites.fold(p[j][axis], f64::min)
            };
            c.push(ends.iter().filter(|&&j| lowest(j) - lo <= near).count());
        }
    }
    let median = |c: &mut Vec<usize>| {
        c.sort_unstable();
        c.get(c.len() / 2).copied().unwrap_or(0)
    };
    let m: Vec<usize> = counts.iter_mut().map(median).collect();
    // the left and right limbs share the lateral extremes: the lateral axis is the one about
    // whose middle the body is its own mirror image, and it is never up
    let first = body_points(bvh, &pose_points(bvh, &modes, 0));
    let lateral = (0..3)
        .min_by(|&a, &b| mirror_asymmetry(&first, a).total_cmp(&mirror_asymmetry(&first, b)))?;
    let (a, b) = ((lateral + 1) % 3, (lateral + 2) % 3);
    let best = if m[a] > m[b] { a } else { b };
    (m[best] >= 2 && m[a] != m[b]).then(|| UpAxis::from_index(best))
}

/// Two extents closer than this ratio are a tie.
const TIE: f64 = 0.8;

/// Axis indices sorted by decreasing extent.
fn by_extent(ext: [f64; 3]) -> [usize; 3] {
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| ext[b].total_cmp(&ext[a]));
    order
}

/// Joints then End Sites (the order of [`rest_points`]) at frame `frame`.
fn pose_points(bvh: &Bvh, modes: &[ResolvedPosition], frame: usize) -> Vec<Vector3<f64>> {
    let (p, r) = bvh_world_poses(bvh, modes, frame);
    points_of(bvh, &p, &r)
}

/// Joints then End Sites from world joint positions `p` and orientations `r` (one forward
/// kinematics pass serves both).
fn points_of(bvh: &Bvh, p: &[Vector3<f64>], r: &[Matrix3<f64>]) -> Vec<Vector3<f64>> {
    let sites = bvh
        .joints
        .iter()
        .enumerate()
        .flat_map(|(j, joint)| joint.end_sites.iter().map(move |s| p[j] + r[j] * s));
    p.iter().copied().chain(sites).collect()
}

/// `points` (joints then End Sites) without a placement root: a root joint with exactly one
/// child joint and no End Site.
fn body_points(bvh: &Bvh, points: &[Vector3<f64>]) -> Vec<Vector3<f64>> {
    let placement_root = bvh.joints.first().is_some_and(|root| {
        root.end_sites.is_empty() && bvh.joints.iter().filter(|j| j.parent == Some(0)).count() == 1
    });
    let skip = usize::from(placement_root);
    points.iter().skip(skip).copied().collect()
}

/// Up to 64 evenly spaced frame indices, the first and the last included.
fn sampled_frames(bvh: &Bvh) -> Vec<usize> {
    let n = bvh.frames;
    if n == 0 {
        return Vec::new();
    }
    let k = n.min(64);
    let mut out: Vec<usize> = (0..k)
        .map(|i| if k == 1 { 0 } else { i * (n - 1) / (k - 1) })
        .collect();
    out.dedup();
    out
}

/// Per axis, the median over [`sampled_frames`] of the body's extent along that axis.
fn median_extents(bvh: &Bvh, modes: &[ResolvedPosition]) -> [f64; 3] {
    let per_frame: Vec<[f64; 3]> = sampled_frames(bvh)
        .into_iter()
        .map(|k| extents(&body_points(bvh, &pose_points(bvh, modes, k))))
        .collect();
    let mut out = [0.0; 3];
    for (axis, e) in out.iter_mut().enumerate() {
        let mut v: Vec<f64> = per_frame.iter().map(|x| x[axis]).collect();
        v.sort_by(f64::total_cmp);
        *e = v.get(v.len() / 2).copied().unwrap_or(0.0);
    }
    out
}

/// `max − min` of the points along each axis.
fn extents(pts: &[Vector3<f64>]) -> [f64; 3] {
    let mut out = [0.0; 3];
    for (axis, e) in out.iter_mut().enumerate() {
        let (lo, hi) = min_max(pts, axis);
        *e = hi - lo;
    }
    out
}

fn min_max(pts: &[Vector3<f64>], axis: usize) -> (f64, f64) {
    pts.iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p[axis]), hi.max(p[axis]))
        })
}

/// Mean distance from each point mirrored across the mid-plane normal to `axis` to the
/// nearest point of the set.
fn mirror_asymmetry(pts: &[Vector3<f64>], axis: usize) -> f64 {
    let (lo, hi) = min_max(pts, axis);
    let mid = 0.5 * (lo + hi);
    let total: f64 = pts
        .iter()
        .map(|p| {
            let mut m = *p;
            m[axis] = 2.0 * mid - m[axis];
            pts.iter()
                .map(|q| (q - m).norm_squared())
                .fold(f64::INFINITY, f64::min)
                .sqrt()
        })
        .sum();
    total / pts.len().max(1) as f64
}

/// Rest-pose height in file units: highest minus lowest rest-pose point along `up` (OFFSETs
/// only), End Sites included.
pub fn rest_stature(bvh: &Bvh, up: UpAxis) -> f64 {
    let (lo, hi) = min_max(&rest_points(bvh), up.index());
    if hi >= lo { hi - lo } else { 0.0 }
}

/// The stature (file units) that unit detection and `--stature` scaling use: the
/// [`rest_stature`] when the rest pose is upright along `up` (its body extent along `up` is
/// within 20 % of its largest extent), otherwise (a rest pose on its side, as in the Bandai
/// files) the median over the take's sampled frames of the body's extent along `up`.
pub fn stature(bvh: &Bvh, up: UpAxis) -> f64 {
    let rest_ext = extents(&body_points(bvh, &rest_points(bvh)));
    let largest = rest_ext.iter().copied().fold(0.0, f64::max);
    if rest_ext[up.index()] >= TIE * largest {
        return rest_stature(bvh, up);
    }
    let modes = resolve_position_modes(bvh, PositionMode::Auto);
    median_extents(bvh, &modes)[up.index()]
}

/// A length unit of a BVH file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LengthUnit {
    M,
    Dm,
    Cm,
    Mm,
    In,
    /// The CMU ASF unit of the CMU mocap database's BVH conversions: the ASF files say
    /// `length 0.45` with inches as the base unit, so one unit is `1/0.45` in `= 0.0254/0.45`
    /// m ≈ 0.05644 m.
    Cmu,
    /// Any other unit, given as metres per unit.
    Custom(f64),
}

impl LengthUnit {
    /// The units `detect_unit` chooses among.
    pub const DETECTABLE: [LengthUnit; 6] = [
        LengthUnit::M,
        LengthUnit::Dm,
        LengthUnit::Cm,
        LengthUnit::Mm,
        LengthUnit::In,
        LengthUnit::Cmu,
    ];

    /// Metres per unit.
    pub fn scale_to_m(self) -> f64 {
        match self {
            LengthUnit::M => 1.0,
            LengthUnit::Dm => 0.1,
            LengthUnit::Cm => 0.01,
            LengthUnit::Mm => 0.001,
            LengthUnit::In => 0.0254,
            LengthUnit::Cmu => 0.0254 / 0.45,
            LengthUnit::Custom(s) => s,
        }
    }
}

impl FromStr for LengthUnit {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s.to_ascii_lowercase().as_str() {
            "m" => Ok(LengthUnit::M),
            "dm" => Ok(LengthUnit::Dm),
            "cm" => Ok(LengthUnit::Cm),
            "mm" => Ok(LengthUnit::Mm),
            "in" => Ok(LengthUnit::In),
            "cmu" => Ok(LengthUnit::Cmu),
            other => match other.parse::<f64>() {
                Ok(v) if v.is_finite() && v > 0.0 => Ok(LengthUnit::Custom(v)),
                _ => Err(Error::Invalid(format!(
                    "unknown length unit '{s}': expected m, dm, cm, mm, in, cmu or a positive \
                     number of metres per unit"
                ))),
            },
        }
    }
}

impl std::fmt::Display for LengthUnit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            LengthUnit::M => f.write_str("m"),
            LengthUnit::Dm => f.write_str("dm"),
            LengthUnit::Cm => f.write_str("cm"),
            LengthUnit::Mm => f.write_str("mm"),
            LengthUnit::In => f.write_str("in"),
            LengthUnit::Cmu => f.write_str("cmu"),
            LengthUnit::Custom(s) => write!(f, "{s}"),
        }
    }
}

/// Plausible adult stature (m); outside it `check_stature` asks for `--unit` or `--stature`.
pub const STATURE_RANGE_M: (f64, f64) = (1.0, 2.3);

/// The stature a unit guess aims at (m).
const TYPICAL_STATURE_M: f64 = 1.7;

/// The length unit that makes the rest-pose stature plausible, and that stature (m).
///
/// Among [`LengthUnit::DETECTABLE`], the units that put [`stature`] inside
/// [`STATURE_RANGE_M`] compete; the one nearest 1.7 m (by ratio, `|ln(s / 1.7)|`) wins. When
/// none is plausible, the nearest overall is returned and [`check_stature`] rejects it.
pub fn detect_unit(bvh: &Bvh, up: UpAxis) -> (LengthUnit, f64) {
    let stature = stature(bvh, up);
    let (lo, hi) = STATURE_RANGE_M;
    let score = |u: &LengthUnit| {
        let s = stature * u.scale_to_m();
        let plausible = (lo..=hi).contains(&s);
        (!plausible, (s / TYPICAL_STATURE_M).ln().abs())
    };
    let best = LengthUnit::DETECTABLE
        .into_iter()
        .min_by(|a, b| {
            let (pa, da) = score(a);
            let (pb, db) = score(b);
            pa.cmp(&pb).then(da.total_cmp(&db))
        })
        .unwrap_or(LengthUnit::M);
    (best, stature * best.scale_to_m())
}

/// Accepts a stature (m) within [`STATURE_RANGE_M`]; the error says which option fixes it.
pub fn check_stature(stature_m: f64) -> Result<(), Error> {
    let (lo, hi) = STATURE_RANGE_M;
    if stature_m.is_finite() && (lo..=hi).contains(&stature_m) {
        return Ok(());
    }
    Err(Error::Invalid(format!(
        "the skeleton's stature comes out at {stature_m:.3} m, outside the plausible {lo}–{hi} m: \
         give the file's length unit with --unit (m, dm, cm, mm, in, cmu or metres per unit), \
         or the person's height with --stature (e.g. --stature 1.75), or check the up axis \
         (--up x|y|z)"
    )))
}

/// Accepts a stature the user gave (m): any positive height, since a given stature always wins
/// (a child, a dog, a giant); the error says what to give.
pub fn check_given_stature(stature_m: f64) -> Result<(), Error> {
    if stature_m.is_finite() && stature_m > 0.0 {
        return Ok(());
    }
    Err(Error::Invalid(format!(
        "stature {stature_m}: expected a height in metres, e.g. 1.75"
    )))
}

/// Metres per file unit that give the skeleton a [`stature`] of `stature_m` along `up`.
/// A skeleton with zero rest stature (all points at one height) gives infinity; callers
/// validate the result with [`check_stature`] or reject non-finite scales.
pub fn scale_for_stature(bvh: &Bvh, up: UpAxis, stature_m: f64) -> f64 {
    stature_m / stature(bvh, up)
}

/// A standard adult stature (m): a human skeleton that no length unit puts at a human's
/// height (a game character twice human size) is scaled to it, and a note says so.
pub const STANDARD_STATURE_M: f64 = 1.75;

/// Units tried, in order, for a skeleton that is not a human's: the ones BVH exporters write.
const NON_HUMAN_UNITS: [LengthUnit; 3] = [LengthUnit::Cm, LengthUnit::M, LengthUnit::Mm];

/// Sizes (m) a non-human skeleton is taken to have in its unit: a mouse to a giraffe.
const NON_HUMAN_SIZE_M: (f64, f64) = (0.1, 20.0);

/// How a take's lengths become metres: the unit's name (or `stature` when scaled to one),
/// metres per file unit, the stature (m) along up, and a note when the choice was not the
/// plain detected human unit.
#[derive(Debug, Clone, PartialEq)]
pub struct Scale {
    pub unit: String,
    pub scale_to_m: f64,
    pub stature_m: f64,
    pub note: Option<String>,
}

/// The scale of a take, from what the user gave or from the skeleton (see [`stature`] for
/// the height it measures, which comes from the motion when the rest pose is not upright):
///
/// - `--stature S` always wins: the skeleton is scaled to stand `S` m tall;
/// - `--unit U` is used as given (a note when the height it gives is not a human's);
/// - otherwise, a `human` skeleton (the caller decides: `model::anthropometry::looks_human`
///   reads the joint names) gets the unit of
///   [`detect_unit`]; if no unit puts it at 1.0–2.3 m it is scaled to
///   [`STANDARD_STATURE_M`] with a note; a skeleton that is not a human's gets the first of
///   cm, m, mm that puts it at a human's height (a human with unreadable joint names), else at
///   0.1–20 m, with a note.
///
/// Errors: a skeleton with no height along `up`, or a given stature or unit that is not a
/// positive finite number.
pub fn choose_scale(
    bvh: &Bvh,
    up: UpAxis,
    unit: Option<LengthUnit>,
    stature_m: Option<f64>,
    human: bool,
) -> Result<Scale, Error> {
    let height = stature(bvh, up);
    if !(height.is_finite() && height > 0.0) {
        return Err(Error::Invalid(format!(
            "the skeleton has no height along the up axis {up}: every point of it lies at one \
             height, so neither its unit nor its stature can be found; give the up axis with \
             --up x|y|z"
        )));
    }
    let (lo, hi) = STATURE_RANGE_M;
    let scale = |unit: String, scale_to_m: f64, note: Option<String>| Scale {
        unit,
        scale_to_m,
        stature_m: height * scale_to_m,
        note,
    };
    if let Some(s) = stature_m {
        check_given_stature(s)?;
        return Ok(scale("stature".into(), s / height, None));
    }
    if let Some(u) = unit {
        let s = height * u.scale_to_m();
        let note = (!(lo..=hi).contains(&s)).then(|| {
            format!(
                "in the unit given ({u}) the skeleton stands {s:.3} m tall, outside a human's \
                 {lo}–{hi} m: used as given"
            )
        });
        return Ok(scale(u.to_string(), u.scale_to_m(), note));
    }
    if human {
        let (u, s) = detect_unit(bvh, up);
        if (lo..=hi).contains(&s) {
            return Ok(scale(u.to_string(), u.scale_to_m(), None));
        }
        let k = STANDARD_STATURE_M / height;
        let note = format!(
            "no length unit puts this human skeleton at a human's height ({height:.4} units \
             tall: {s:.3} m in {u}, the nearest): it was scaled to a standard adult stature of \
             {STANDARD_STATURE_M} m ({k:.6} m per unit; --stature sets another height, --unit \
             a unit)"
        );
        return Ok(scale("stature".into(), k, Some(note)));
    }
    let size = |u: &LengthUnit| height * u.scale_to_m();
    let u = NON_HUMAN_UNITS
        .into_iter()
        .find(|u| (lo..=hi).contains(&size(u)))
        .or_else(|| {
            let (a, b) = NON_HUMAN_SIZE_M;
            NON_HUMAN_UNITS
                .into_iter()
                .find(|u| (a..=b).contains(&size(u)))
        })
        .unwrap_or(LengthUnit::Cm);
    let note = format!(
        "not a human skeleton (no trunk and two legs among its joint names): its length unit, \
         {u}, was chosen from its size ({:.3} m tall; --unit or --stature override it)",
        size(&u)
    );
    Ok(scale(u.to_string(), u.scale_to_m(), Some(note)))
}
