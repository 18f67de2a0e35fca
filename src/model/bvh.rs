//! Models from BVH skeletons, in two joint models, and the map between BVH channels and the
//! model's generalized coordinates.
//!
//! - **euler** (the paper's): each rotation channel is a revolute joint about its axis, in
//!   channel order, with massless zero-length fictitious links between; each position channel
//!   is a prismatic joint (a 6-channel root: 3 prismatic + 3 revolute). Position channels come
//!   first whatever their place in the file, as the BVH semantics `T(offset)·T(pos)·R` say.
//!   Coordinates and bodies are named `<joint>.<channel>` (`LeftUpLeg.Zrotation`).
//! - **ball**: one spherical joint per BVH joint (`<joint>:qx` … `<joint>:qw`); a joint with
//!   position channels (the root, and every joint of some datasets) gets a free joint
//!   (`<joint>:x` … `<joint>:qw`).
//!
//! In both, q = 0 (identity quaternions) is the rest pose: a prismatic coordinate is
//! `value · scale_to_m` for position channels that add to the OFFSET and
//! `(value − offset) · scale_to_m` for those that replace it. The link of a BVH joint (the body
//! whose frame is the joint's frame: the last channel body in the euler model) carries the
//! de Leva mass, inertia and shape from [`anthropometry`](crate::model::anthropometry).
//! Lengths are multiplied by `scale_to_m`; gravity is −9.81 m/s² along −up.
//!
//! Position channels held at a value ([`BvhModelOptions::held_positions`]: the pipeline welds
//! those of joints below the body's root at their mean, `motion::weld`) are no coordinate in
//! either model: the joint is placed at `T(offset) · T(held)` and keeps only its rotation (a
//! spherical joint in the ball model, not a free one).
//!
//! Joints without channels, locked joints and the branches outside the subtree of interest are
//! welded to their parent by [`simplify`](crate::model::simplify); the [`BvhMap`] follows.

use crate::error::Error;
use crate::io::bvh::{Bvh, Channel};
use crate::model::anthropometry::{self, BodyParams, Bone, SegmentTable};
use crate::model::simplify;
use crate::model::{JointKind, Model, ModelBuilder};
use crate::spatial::{SpatialInertia, SpatialTransform};
use nalgebra::Vector3;
use std::str::FromStr;

pub use crate::io::bvh::{ResolvedPosition, UpAxis};

/// Standard gravity (m/s²).
pub const STANDARD_GRAVITY: f64 = 9.81;

/// How BVH joints become model joints.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum JointModel {
    /// One revolute joint per rotation channel, one prismatic per position channel.
    #[default]
    Euler,
    /// One spherical joint per BVH joint, free joints where there are position channels.
    Ball,
}

impl FromStr for JointModel {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s.trim().to_ascii_lowercase().as_str() {
            "euler" => Ok(JointModel::Euler),
            "ball" => Ok(JointModel::Ball),
            other => Err(Error::Invalid(format!(
                "unknown joint model {other:?}: expected \"euler\" or \"ball\""
            ))),
        }
    }
}

impl std::fmt::Display for JointModel {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            JointModel::Euler => "euler",
            JointModel::Ball => "ball",
        })
    }
}

/// Everything [`build_bvh_model`] needs besides the skeleton.
#[derive(Debug, Clone, PartialEq)]
pub struct BvhModelOptions {
    /// Model name (the take's file stem).
    pub name: String,
    /// Joint model.
    pub joints: JointModel,
    /// Metres per file length unit (> 0).
    pub scale_to_m: f64,
    /// The take's up axis (gravity is −9.81 m/s² along it).
    pub up: UpAxis,
    /// Position-channel semantics per BVH joint (from `resolve_position_modes`); empty means
    /// `Add` for every joint with position channels.
    pub positions: Vec<ResolvedPosition>,
    /// Body mass, sex, segment table, stature (`None`: the skeleton's rest-pose stature, scaled),
    /// link mass overrides.
    pub body: BodyParams,
    /// BVH joints (all their channels) or single coordinates (`LeftLeg.Yrotation`) to lock at
    /// rest.
    pub lock: Vec<String>,
    /// Keep only this BVH joint's subtree and the chain that carries it.
    pub subtree: Option<String>,
    /// The segment of every joint's link (`model::skeleton::segment_classes`, by topology);
    /// `None`: by the joint names (`anthropometry::classes_by_name`).
    pub segments: Option<Vec<anthropometry::SegmentOf>>,
    /// Position channels held at a value instead of being coordinates, by BVH joint
    /// (`motion::weld`): `Some(v)` places the joint at `T(offset) · T(p)`, `p` what its
    /// position channels at the values `v` (file units, by axis) mean under its position mode,
    /// and gives them no coordinate; `None` (or an empty list): each is a coordinate.
    pub held_positions: Vec<Option<Vector3<f64>>>,
    /// Twist helpers folded into their only child (`motion::twist`, BVH joint indices): each is
    /// welded to its parent at rest (its rotation is in the child's channels), massless, and its
    /// bone is part of its parent's (the parent's end at the helper becomes the helper's child:
    /// one link with the whole bone's centre of mass and inertia). Empty: none.
    pub folded: Vec<usize>,
    /// Each BVH joint's translation in its parent's frame (file units) that the segments'
    /// bones are measured on (lengths, centres of mass, inertias): the pipeline gives the
    /// skeleton as held (`motion::weld::held_shape`: position channels below the body's root
    /// at their mean), so that the same motion written with those means in its OFFSETs gets
    /// the same segments. Empty: the OFFSETs.
    pub bone_offsets: Vec<Vector3<f64>>,
}

impl BvhModelOptions {
    /// Euler model of a 75 kg male body, nothing locked.
    pub fn new(
        name: impl Into<String>,
        scale_to_m: f64,
        up: UpAxis,
        positions: Vec<ResolvedPosition>,
    ) -> Self {
        Self {
            name: name.into(),
            joints: JointModel::Euler,
            scale_to_m,
            up,
            positions,
            body: BodyParams::default(),
            lock: vec![],
            subtree: None,
            segments: None,
            held_positions: vec![],
            folded: vec![],
            bone_offsets: vec![],
        }
    }
}

impl BvhModelOptions {
    /// These options with the model choices of a scene: joint model, body mass, sex and segment
    /// table, link mass overrides, locked joints and subtree. (Units, axes and position modes
    /// are resolved from the take by the caller, since they need it.)
    pub fn with_scene(mut self, scene: &crate::io::scene::Scene) -> Result<Self, Error> {
        self.joints = scene.joints.parse()?;
        self.body = BodyParams {
            mass_kg: scene.mass,
            sex: scene.sex.parse()?,
            segments: scene.segments.parse()?,
            height_m: None,
            link_mass: scene.link_mass.clone(),
        };
        self.lock = scene.lock.clone();
        self.subtree = scene.subtree.clone();
        Ok(self)
    }
}

/// How one BVH channel reaches q.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChannelMap {
    /// Column in a frame row.
    pub column: usize,
    /// The channel.
    pub channel: Channel,
    /// The q coordinate it sets: euler: its revolute/prismatic joint; ball: position channels
    /// only (rotations go through [`JointMap::quat_q`]). `None`: locked (held at rest).
    pub q: Option<usize>,
    /// Position channels: the value (file units) that means "at rest" (the OFFSET component for
    /// `Replace`, 0 for `Add`), or the value a held channel is held at
    /// ([`BvhModelOptions::held_positions`]); 0 for rotations.
    pub rest: f64,
}

/// How one BVH joint appears in the model.
#[derive(Debug, Clone, PartialEq)]
pub struct JointMap {
    /// The body whose frame carries the BVH joint's frame (rigidly).
    pub body: usize,
    /// Pose of the BVH joint frame in that body's frame (identity unless the joint was welded
    /// to a parent by locking or pruning; then valid at rest).
    pub frame: SpatialTransform,
    /// The joint's channels in file order.
    pub channels: Vec<ChannelMap>,
    /// Ball model: first q index of the joint's quaternion `[qx, qy, qz, qw]`, if its rotation
    /// is a coordinate.
    pub quat_q: Option<usize>,
}

/// The map between BVH channels and model coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct BvhMap {
    /// The joint model the map was built for.
    pub joint_model: JointModel,
    /// Metres per file length unit.
    pub scale_to_m: f64,
    /// One entry per BVH joint, in file order.
    pub joints: Vec<JointMap>,
}

/// What `anthropometry::distribute` needs of each BVH joint: its name, parent and the offsets of
/// its children and End Sites in its frame, scaled to metres.
pub fn bones(bvh: &Bvh, scale: f64) -> Vec<Bone> {
    bones_on(bvh, scale, &[])
}

/// [`bones`] with each child's end at `offsets[child]` (file units; empty: its OFFSET),
/// [`BvhModelOptions::bone_offsets`].
fn bones_on(bvh: &Bvh, scale: f64, offsets: &[Vector3<f64>]) -> Vec<Bone> {
    let end_of = |c: usize| offsets.get(c).copied().unwrap_or(bvh.joints[c].offset) * scale;
    bvh.joints
        .iter()
        .enumerate()
        .map(|(j, joint)| Bone {
            name: joint.name.clone(),
            parent: joint.parent,
            ends: (0..bvh.joints.len())
                .filter(|&c| bvh.joints[c].parent == Some(j))
                .map(end_of)
                .chain(joint.end_sites.iter().map(|e| e * scale))
                .collect(),
        })
        .collect()
}

/// Makes each folded helper's bone part of its parent's ([`BvhModelOptions::folded`]): the
/// parent's end at the helper becomes the helper's own end (`o_H + o_C`, the helper holding
/// still at rest), the helper keeps no bone. Deepest helpers first, so a chain of helpers
/// composes into one bone.
fn fold_helper_bones(bvh: &Bvh, bones: &mut [Bone], folded: &[usize]) {
    let mut order = folded.to_vec();
    order.sort_unstable_by(|a, b| b.cmp(a));
    order.dedup();
    for h in order {
        let (Some(p), [end]) = (bvh.joints[h].parent, bones[h].ends.as_slice()) else {
            continue;
        };
        let end = *end;
        // the helper's place among its parent's ends (children in file order, then End Sites)
        let slot = (0..bvh.joints.len())
            .filter(|&c| bvh.joints[c].parent == Some(p))
            .position(|c| c == h);
        if let Some(e) = slot.and_then(|i| bones[p].ends.get_mut(i)) {
            *e += end;
        }
        bones[h].ends.clear();
    }
}

/// True when `name` is `<joint>.<position channel>` of a joint whose position channels are
/// held ([`BvhModelOptions::held_positions`]).
fn is_held(bvh: &Bvh, opts: &BvhModelOptions, name: &str) -> bool {
    let Some((joint, channel)) = name.rsplit_once('.') else {
        return false;
    };
    let (Some(j), Some(c)) = (bvh.joint_index(joint), Channel::from_name(channel)) else {
        return false;
    };
    !c.is_rotation()
        && bvh.joints[j].channels.contains(&c)
        && matches!(opts.held_positions.get(j), Some(Some(_)))
}

/// Builds the model of a BVH skeleton and the channel ↔ coordinate map (see the module doc).
///
/// Errors: a non-positive `scale_to_m`, `positions` of the wrong length, anthropometry errors
/// (body mass, overrides), unknown joints in `lock` or `subtree`.
pub fn build_bvh_model(bvh: &Bvh, opts: &BvhModelOptions) -> Result<(Model, BvhMap), Error> {
    let scale = opts.scale_to_m;
    if !(scale.is_finite() && scale > 0.0) {
        return Err(Error::Invalid(format!(
            "scale_to_m = {scale}: the length unit must be positive (--unit or --stature)"
        )));
    }
    if !opts.positions.is_empty() && opts.positions.len() != bvh.joints.len() {
        return Err(Error::Invalid(format!(
            "{} position modes for {} joints",
            opts.positions.len(),
            bvh.joints.len()
        )));
    }
    if !opts.held_positions.is_empty() && opts.held_positions.len() != bvh.joints.len() {
        return Err(Error::Invalid(format!(
            "{} held positions for {} joints",
            opts.held_positions.len(),
            bvh.joints.len()
        )));
    }
    // the regression needs the stature: the caller's (the pipeline's), else the skeleton's
    let mut body = opts.body.clone();
    if body.segments == SegmentTable::Regression && body.height_m.is_none() {
        body.height_m = Some(crate::io::bvh::stature(bvh, opts.up) * scale);
    }
    let mut bones = bones_on(bvh, scale, &opts.bone_offsets);
    let links = if opts.folded.is_empty() {
        match &opts.segments {
            Some(c) => anthropometry::distribute_classes(&bones, &body, c)?,
            None => anthropometry::distribute(&bones, &body)?,
        }
    } else {
        // folded helpers: massless, their bone their parent's
        let mut classes = match &opts.segments {
            Some(c) => c.clone(),
            None => anthropometry::classes_by_name(&bones),
        };
        for &h in &opts.folded {
            if let Some(c) = classes.get_mut(h) {
                *c = anthropometry::SegmentOf::default();
            }
        }
        fold_helper_bones(bvh, &mut bones, &opts.folded);
        anthropometry::distribute_classes(&bones, &body, &classes)?
    };
    let mut gravity = Vector3::zeros();
    gravity[opts.up.index()] = -STANDARD_GRAVITY;
    let mut b = ModelBuilder::new(opts.name.clone(), gravity);

    // the full model: every channel a coordinate
    let mut maps: Vec<JointMap> = Vec::with_capacity(bvh.joints.len());
    let mut first_body = vec![0usize; bvh.joints.len()];
    let mut weld = vec![false]; // bodies to weld to their parent (joints without channels)
    for (j, joint) in bvh.joints.iter().enumerate() {
        let parent_body = joint.parent.map_or(0, |p| maps[p].body);
        let replace = matches!(opts.positions.get(j), Some(ResolvedPosition::Replace));
        let rest_of = |c: Channel| {
            if !c.is_rotation() && replace {
                joint.offset[c.axis()]
            } else {
                0.0
            }
        };
        let mut channels: Vec<ChannelMap> = joint
            .channels
            .iter()
            .enumerate()
            .map(|(k, &c)| ChannelMap {
                column: joint.first_channel + k,
                channel: c,
                q: None,
                rest: rest_of(c),
            })
            .collect();
        // held position channels: the joint placed where they hold it, no coordinate
        let mut t = joint.offset * scale;
        let held = opts.held_positions.get(j).copied().flatten();
        if let Some(v) = held {
            for c in channels.iter_mut().filter(|c| !c.channel.is_rotation()) {
                let a = c.channel.axis();
                t[a] += (v[a] - c.rest) * scale;
                c.rest = v[a];
            }
        }
        let placement = SpatialTransform::from_translation(t);
        let is_coordinate = |c: Channel| c.is_rotation() || held.is_none();
        let link = &links[j];
        let inertia = SpatialInertia::new(link.mass, link.com, link.inertia_com);
        let has_pos = joint
            .channels
            .iter()
            .any(|&c| !c.is_rotation() && is_coordinate(c));
        let has_rot = joint.channels.iter().any(|c| c.is_rotation());
        let mut quat_q = None;
        let mut coordinate_bodies = 0;
        let body = match opts.joints {
            _ if !joint.channels.iter().any(|&c| is_coordinate(c)) => {
                weld.push(true);
                b.add_body(
                    parent_body,
                    joint.name.clone(),
                    joint.name.clone(),
                    JointKind::Fixed,
                    placement,
                    inertia,
                )
            }
            JointModel::Euler => {
                // position channels first (T(offset)·T(pos)·R), then rotations in file order
                let mut order: Vec<usize> = (0..channels.len())
                    .filter(|&k| !channels[k].channel.is_rotation())
                    .filter(|&k| is_coordinate(channels[k].channel))
                    .collect();
                order.extend((0..channels.len()).filter(|&k| channels[k].channel.is_rotation()));
                let mut prev = parent_body;
                for (n, &k) in order.iter().enumerate() {
                    let c = channels[k].channel;
                    let axis = Vector3::ith(c.axis(), 1.0);
                    let kind = if c.is_rotation() {
                        JointKind::Revolute { axis }
                    } else {
                        JointKind::Prismatic { axis }
                    };
                    let last = n + 1 == order.len();
                    let name = format!("{}.{}", joint.name, c.name());
                    prev = b.add_body(
                        prev,
                        name.clone(),
                        name,
                        kind,
                        if n == 0 {
                            placement
                        } else {
                            SpatialTransform::IDENTITY
                        },
                        if last { inertia } else { SpatialInertia::ZERO },
                    );
                    weld.push(false);
                    channels[k].q = Some(b.model().idx_q[prev]);
                }
                coordinate_bodies = order.len();
                prev
            }
            JointModel::Ball => {
                let kind = if has_pos {
                    JointKind::Free
                } else {
                    JointKind::Spherical
                };
                let i = b.add_body(
                    parent_body,
                    joint.name.clone(),
                    joint.name.clone(),
                    kind,
                    placement,
                    inertia,
                );
                weld.push(false);
                let iq = b.model().idx_q[i];
                if has_pos {
                    for c in channels.iter_mut().filter(|c| !c.channel.is_rotation()) {
                        c.q = Some(iq + c.channel.axis());
                    }
                }
                if has_rot {
                    quat_q = Some(if has_pos { iq + 3 } else { iq });
                }
                i
            }
        };
        // euler: the joint's first coordinate body; otherwise its one body
        first_body[j] = body + 1 - coordinate_bodies.max(1);
        if let Some(s) = link.shape {
            b.set_shape(body, s);
        }
        maps.push(JointMap {
            body,
            frame: SpatialTransform::IDENTITY,
            channels,
            quat_q,
        });
    }
    let full = b.build();

    // what to weld: channel-less joints, locked joints, folded helpers, branches outside the
    // subtree
    let mut lock = weld;
    for &j in opts.folded.iter().filter(|&&j| j < bvh.joints.len()) {
        lock[first_body[j]..=maps[j].body].fill(true);
    }
    for name in &opts.lock {
        if let Some(j) = bvh.joint_index(name) {
            lock[first_body[j]..=maps[j].body].fill(true);
        } else if let Some(i) = full.body_index(name) {
            lock[i] = true;
        } else if is_held(bvh, opts, name) {
            // a held position channel has no coordinate to lock: it holds still already
        } else {
            return Err(Error::Invalid(format!(
                "cannot lock {name:?}: it is neither a joint nor a coordinate of {} \
                 (joints: {})",
                opts.name,
                bvh.joints
                    .iter()
                    .map(|j| j.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            )));
        }
    }
    if let Some(name) = &opts.subtree {
        let j = bvh.joint_index(name).ok_or_else(|| {
            Error::Invalid(format!(
                "subtree {name:?} is not a joint of {} (the root is {:?})",
                opts.name,
                bvh.joints.first().map(|j| j.name.as_str()).unwrap_or("")
            ))
        })?;
        for (i, out) in simplify::outside_subtree(&full, first_body[j])
            .into_iter()
            .enumerate()
        {
            lock[i] |= out;
        }
    }
    if !lock.iter().any(|&l| l) {
        let map = BvhMap {
            joint_model: opts.joints,
            scale_to_m: scale,
            joints: maps,
        };
        return Ok((full, map));
    }

    // the reduced model; the map follows the bodies
    let r = simplify::lock_bodies(&full, &lock);
    let mut map = BvhMap {
        joint_model: opts.joints,
        scale_to_m: scale,
        joints: maps,
    };
    follow_reduction(&full, &r, None, &mut map);
    Ok((r.model, map))
}

/// Makes `map`, a map of `full`, one of the reduced model `r` (`simplify::lock_bodies_at`
/// on `full` with `hold`): each channel's coordinate moves to the reduced model's or, when its
/// joint was locked, becomes none, its rest value then the held one (`hold`'s coordinate,
/// in file units; `None`: rest stays rest); each BVH joint's frame follows its body.
pub fn follow_reduction(
    full: &Model,
    r: &simplify::Reduction,
    hold: Option<&[f64]>,
    map: &mut BvhMap,
) {
    let ch_body = |q: usize| {
        (1..full.nbodies())
            .rev()
            .find(|&i| full.idx_q[i] <= q && full.joints[i].nq() > 0)
            .unwrap_or(0)
    };
    let scale = map.scale_to_m;
    for m in &mut map.joints {
        for c in &mut m.channels {
            let Some(q) = c.q else { continue };
            let i = ch_body(q);
            c.q = r.kept[i].map(|k| r.model.idx_q[k] + (q - full.idx_q[i]));
            if let (None, Some(h)) = (c.q, hold) {
                c.rest = if c.channel.is_rotation() {
                    h[q].to_degrees()
                } else {
                    h[q] / scale + c.rest
                };
            }
        }
        m.quat_q = m.quat_q.and_then(|q| {
            let i = ch_body(q);
            r.kept[i].map(|k| r.model.idx_q[k] + (q - full.idx_q[i]))
        });
        let (body, x) = r.body_map[m.body];
        m.body = body;
        m.frame = x.compose(&m.frame);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::generate::{WalkParams, walk};

    fn opts(joints: JointModel) -> BvhModelOptions {
        let take = walk(&WalkParams::default());
        let mut o = BvhModelOptions::new(
            "walk",
            0.01,
            UpAxis::Y,
            vec![ResolvedPosition::None; take.joints.len()],
        );
        o.positions[0] = ResolvedPosition::Add;
        o.joints = joints;
        o
    }

    #[test]
    fn euler_model_has_one_coordinate_per_channel() {
        let take = walk(&WalkParams::default());
        let (model, map) = build_bvh_model(&take, &opts(JointModel::Euler)).unwrap();
        assert_eq!(model.nq, take.channel_count);
        assert_eq!(model.nv, take.channel_count);
        assert_eq!(model.q_names[0], "Hips.Xposition");
        assert_eq!(model.q_names[3], "Hips.Zrotation");
        assert!(model.v_index("LeftUpLeg.Xrotation").is_some());
        assert_eq!(model.gravity, Vector3::new(0.0, -9.81, 0.0));
        assert!((model.total_mass() - 75.0).abs() < 1e-12);
        // every channel maps to its own coordinate, in column order for this layout
        for jm in &map.joints {
            for c in &jm.channels {
                assert_eq!(c.q, Some(c.column));
            }
        }
    }

    #[test]
    fn ball_model_has_a_free_root_and_spherical_joints() {
        let take = walk(&WalkParams::default());
        let (model, map) = build_bvh_model(&take, &opts(JointModel::Ball)).unwrap();
        assert_eq!(model.joints[1], JointKind::Free);
        assert_eq!(model.nv, 6 + 3 * (take.joints.len() - 1));
        assert_eq!(model.q_names[3], "Hips:qx");
        assert_eq!(map.joints[0].quat_q, Some(3));
    }

    #[test]
    fn locking_and_pruning_remove_coordinates() {
        let take = walk(&WalkParams::default());
        let mut o = opts(JointModel::Euler);
        o.lock = vec!["LeftArm".into(), "RightLeg.Yrotation".into()];
        let (model, map) = build_bvh_model(&take, &o).unwrap();
        assert_eq!(model.nv, take.channel_count - 4);
        assert!((model.total_mass() - 75.0).abs() < 1e-12);
        let la = take.joint_index("LeftArm").unwrap();
        assert!(map.joints[la].channels.iter().all(|c| c.q.is_none()));
        o.lock = vec!["Nope".into()];
        assert!(build_bvh_model(&take, &o).is_err());
        o.lock.clear();
        o.subtree = Some("RightUpLeg".into());
        let (model, _) = build_bvh_model(&take, &o).unwrap();
        // root (6) + right leg: hip, knee, ankle, toes (4 × 3)
        assert_eq!(model.nv, 6 + 12);
        assert!((model.total_mass() - 75.0).abs() < 1e-12);
    }
}
