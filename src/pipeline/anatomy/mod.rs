//! `articula anatomy`: anatomical joint angles and net internal moments of a human take
//! (`dynamics::anatomy` for the conventions, `model::skeleton` for how the joints are found).
//!
//! Segment frames (X anterior, Y proximal, Z right), each fixed to the body that carries the
//! segment's bone, are calibrated once per take from its motion:
//! - pelvis: Z along the hip centres (left → right), Y from the mid-hip point to the lumbar
//!   spine (a skeleton has no pelvic landmarks, ASIS or PSIS, to tilt it by; the world's up on
//!   average over the take when the skeleton has no spine);
//! - thorax: Z along the shoulder centres, Y towards the neck;
//! - thigh, shank, upper arm, forearm: Y the bone (distal → proximal joint centre, every
//!   frame), Z the knee's (elbow's) functional flexion axis
//!   ([`functional_axis`](crate::dynamics::anatomy::functional_axis)) pointing right, or the
//!   pelvis's Z when the joint hardly moves;
//! - foot: Z the ankle's functional axis, X the direction from the ankle to the toe (or the
//!   foot's end) held level: its mean over the frames where the foot lies flat and lowest, so
//!   that the ankle reads zero with the sole flat under a vertical shank.
//!
//! Moments are the joint forces of inverse dynamics (with the take's ground reactions when
//! `contact` is `feet`) at the joint centre, projected on the joint's axes.

mod gait;
mod series;

pub use gait::{KneeCycles, knee_cycles, summary};
pub use series::{Calibration, inverse_dynamics_and_moments, moment_bodies};

use super::{Take, ground_reactions};
use crate::dynamics::Workspace;
use crate::dynamics::anatomy::{
    self as jcs, ANKLE, AXES, ELBOW, HIP, JointKind, KNEE, LUMBAR, PELVIS, SHOULDER, frame_from_yz,
    frame_from_zx, functional_axis,
};
use crate::dynamics::grf::GroundReactions;
use crate::error::Error;
use crate::io::bvh::{self, Bvh, ResolvedPosition, UpAxis};
use crate::model::anthropometry::SegmentOf;
use crate::model::skeleton::{Human, Pose, Topology, find_human, segment_classes};
use nalgebra::{Matrix3, Vector3};

/// Angles (deg), moments (N·m) and moments per body mass (N·m/kg) per frame.
#[derive(Debug, Clone)]
pub struct Anatomy {
    pub time: Vec<f64>,
    /// Column names after `time`: `<joint>[_l|_r]:<flexion|adduction|rotation>:<angle|moment|
    /// moment_per_kg>`.
    pub names: Vec<String>,
    /// One per name, one value per frame.
    pub columns: Vec<Vec<f64>>,
    /// The body mass the per-kg moments divide by (kg).
    pub mass_kg: f64,
    /// How the joints and frames were found.
    pub notes: Vec<String>,
    /// With ground contact: per foot (`left`, `right`), whether it is on the floor per frame.
    pub contact: Vec<(String, Vec<bool>)>,
    /// With ground contact through [`anatomy_consistent`](super::consistency::anatomy_consistent):
    /// the take's residuals against Hicks et al.'s thresholds, before and after reduction.
    pub consistency: Option<super::consistency::Consistency>,
    /// Frames at each end of the take whose accelerations are not trustworthy
    /// ([`edge_frames`](super::edge_frames)): marked in the CSV (`edge`), and left out of the
    /// summary's ranges unless [`include_edges`](Self::include_edges).
    pub edge: usize,
    /// The summary's ranges include the edge frames (`articula anatomy --edges include`).
    pub include_edges: bool,
}

impl Anatomy {
    /// The frames whose values the summary reports: all with
    /// [`include_edges`](Self::include_edges), else all but [`edge`](Self::edge) at each end.
    pub fn reported(&self) -> std::ops::Range<usize> {
        let n = self.time.len();
        if self.include_edges || 2 * self.edge >= n {
            0..n
        } else {
            self.edge..n - self.edge
        }
    }

    /// Whether frame `k` lies beyond Hicks et al.'s thresholds (the motion needs a force the
    /// feet cannot give there).
    pub fn beyond(&self, k: usize) -> bool {
        self.consistency
            .as_ref()
            .is_some_and(|c| c.beyond.get(k) == Some(&true))
    }

    /// Whether frame `k`'s moments are quoted: [`reported`](Self::reported) and not
    /// [`beyond`](Self::beyond).
    pub fn quoted(&self, k: usize) -> bool {
        self.reported().contains(&k) && !self.beyond(k)
    }

    /// The column called `name`.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        let i = self.names.iter().position(|n| n == name)?;
        Some(&self.columns[i])
    }
}

/// A segment's frame: how its axes follow the bodies.
#[derive(Debug, Clone, Copy)]
enum Frame {
    /// The world's up and a heading (the lab, for the pelvis's angles).
    Lab { x: Vector3<f64> },
    /// Both axes fixed in the body of joint `body` (pelvis, thorax).
    Body {
        body: usize,
        y: Vector3<f64>,
        z: Vector3<f64>,
    },
    /// Y from joint `dist`'s centre to joint `prox`'s, Z fixed in the body of joint `body`.
    Bone {
        prox: usize,
        dist: usize,
        body: usize,
        z: Vector3<f64>,
    },
    /// Z and X fixed in the body of joint `body` (foot).
    Foot {
        body: usize,
        z: Vector3<f64>,
        x: Vector3<f64>,
    },
}

/// One anatomical joint of the take.
#[derive(Debug, Clone)]
struct Joint {
    kind: JointKind,
    /// `""`, `_l` or `_r`.
    suffix: &'static str,
    proximal: Frame,
    distal: Frame,
    /// The BVH joint whose joint force is this joint's moment (`None`: angles only).
    moment_at: Option<usize>,
}

/// World rotation (BVH joint frame) and position of every BVH joint at one frame.
struct Posed {
    rot: Vec<Matrix3<f64>>,
    pos: Vec<Vector3<f64>>,
}

fn posed(take: &Take, ws: &Workspace) -> Posed {
    let (rot, pos) = take
        .map
        .joints
        .iter()
        .map(|jm| {
            let o = ws.o_x_i[jm.body].compose(&jm.frame);
            (o.rot, o.trans)
        })
        .unzip();
    Posed { rot, pos }
}

impl Frame {
    fn at(&self, p: &Posed, up: &Vector3<f64>) -> Option<Matrix3<f64>> {
        match *self {
            Frame::Lab { x } => Some(Matrix3::from_columns(&[x, *up, x.cross(up)])),
            Frame::Body { body, y, z } => frame_from_yz(&(p.rot[body] * y), &(p.rot[body] * z)),
            Frame::Bone {
                prox,
                dist,
                body,
                z,
            } => frame_from_yz(&(p.pos[prox] - p.pos[dist]), &(p.rot[body] * z)),
            Frame::Foot { body, z, x } => frame_from_zx(&(p.rot[body] * z), &(p.rot[body] * x)),
        }
    }
}

/// Mean of `f(frame)` over the frames, normalised (`None` if it vanishes).
fn mean_dir(frames: &[Posed], f: impl Fn(&Posed) -> Vector3<f64>) -> Option<Vector3<f64>> {
    frames
        .iter()
        .map(f)
        .fold(Vector3::zeros(), |s, v| s + v)
        .try_normalize(1e-12)
}

/// The functional axis of the joint between the bodies of BVH joints `a` (proximal) and `b`,
/// in the frame of `a`'s body (or `b`'s with `in_b`), pointing the way `right` (world) does on
/// average. It must lie within 45° of `right` held in that body (averaged over the frames)
/// and more than 30° from the bone `bone(frame)`; otherwise (or when the joint hardly moves)
/// `right` held in the body is the axis, and `up` where that lies along the bone (an arm held
/// out sideways).
fn lateral_axis(
    frames: &[Posed],
    (a, b, in_b): (usize, usize, bool),
    right: &dyn Fn(&Posed) -> Vector3<f64>,
    up: &Vector3<f64>,
    bone: &dyn Fn(&Posed) -> Vector3<f64>,
    stride: usize,
) -> Option<Vector3<f64>> {
    let on = if in_b { b } else { a };
    let rel: Vec<Matrix3<f64>> = frames
        .iter()
        .map(|p| p.rot[a].transpose() * p.rot[b])
        .collect();
    // mean |cos| of the angle between an axis held in the body and the bone
    let along_bone = |axis: &Vector3<f64>| {
        frames
            .iter()
            .map(|p| {
                bone(p)
                    .try_normalize(1e-12)
                    .map_or(0.0, |u| u.dot(&(p.rot[on] * axis)).abs())
            })
            .sum::<f64>()
            / frames.len() as f64
    };
    let across = |axis: &Vector3<f64>| along_bone(axis) < 30f64.to_radians().cos();
    // without a functional axis: the pelvis's right, else (an arm held out sideways) the up
    let fallback = || {
        mean_dir(frames, |p| p.rot[on].transpose() * right(p))
            .filter(|z| across(z))
            .or_else(|| mean_dir(frames, |p| p.rot[on].transpose() * up))
    };
    let Some(axis) = functional_axis(&rel, stride, in_b, 10f64.to_radians()) else {
        return fallback();
    };
    let sign = frames
        .iter()
        .map(|p| (p.rot[on] * axis).dot(&right(p)))
        .sum::<f64>()
        .signum();
    let axis = axis * sign;
    // a joint that turned mostly about another axis in this take (an ankle that mostly
    // inverts) gives the pelvis's right instead
    let right_held = mean_dir(frames, |p| p.rot[on].transpose() * right(p));
    let near_right = right_held.is_none_or(|r| r.angle(&axis) < 45f64.to_radians());
    if !across(&axis) || !near_right {
        return fallback();
    }
    Some(axis)
}

/// The take's human skeleton, or why it is not one.
pub fn find_take_human(take: &Take) -> Result<Human, Error> {
    take.human.clone().map_err(|why| {
        Error::Invalid(format!(
            "{}: anatomical angles need a human skeleton (two legs from a pelvis): {why}",
            take.path.display()
        ))
    })
}

/// Joint positions and first End Sites of up to 64 evenly spaced frames of a BVH skeleton,
/// from the file's own forward kinematics, in file units (scale them with
/// [`Pose::scaled`]).
pub(crate) fn sample_bvh_poses(bvh: &Bvh, modes: &[ResolvedPosition]) -> Vec<Pose> {
    let n = bvh.frames;
    (0..n)
        .step_by(n.div_ceil(64).max(1))
        .map(|k| {
            let (joints, rot) = bvh::bvh_world_poses(bvh, modes, k);
            let ends = bvh
                .joints
                .iter()
                .enumerate()
                .map(|(j, joint)| joint.end_sites.first().map(|e| joints[j] + rot[j] * e))
                .collect();
            Pose { joints, ends }
        })
        .collect()
}

/// The human landmarks of a BVH skeleton (`model::skeleton::find_human`) in `poses`
/// ([`sample_bvh_poses`]) about the up axis `up`.
pub(crate) fn human_of_bvh(bvh: &Bvh, poses: &[Pose], up: UpAxis) -> Result<Human, String> {
    let names: Vec<&str> = bvh.joints.iter().map(|j| j.name.as_str()).collect();
    let parent: Vec<Option<usize>> = bvh.joints.iter().map(|j| j.parent).collect();
    find_human(
        &Topology {
            names: &names,
            parent: &parent,
        },
        poses,
        up.index(),
    )
}

/// The segment of every joint's link of a human take (by name for a take that is not a
/// human's).
pub fn segments_of_take(take: &Take) -> Vec<SegmentOf> {
    match &take.human {
        Ok(h) => segments_of(&take.bvh, h).0,
        Err(_) => {
            let bones = crate::model::bvh::bones(&take.bvh, take.map.scale_to_m);
            crate::model::anthropometry::classes_by_name(&bones)
        }
    }
}

/// The segment of every joint's link by the skeleton's landmarks, and the names of the bones
/// that carry no body, which are massless: props, bones off the limbs' chains under a hand,
/// foot or head that reach farther than half a thigh (a prop held in a hand, a marker on a
/// stick); and branches, bones that leave a long bone (thigh, shank, upper arm, forearm) off
/// its chain from one landmark to the next (a skinning rig's twist or deformation bone: no
/// body part hangs from the middle of a long bone).
pub(crate) fn segments_of(bvh: &Bvh, human: &Human) -> (Vec<SegmentOf>, Vec<String>, Vec<String>) {
    use crate::model::anthropometry::Segment;
    let names: Vec<&str> = bvh.joints.iter().map(|j| j.name.as_str()).collect();
    let parent: Vec<Option<usize>> = bvh.joints.iter().map(|j| j.parent).collect();
    let topo = Topology {
        names: &names,
        parent: &parent,
    };
    let mut classes = segment_classes(&topo, human);
    let reach = |j: usize| {
        bvh.joints
            .iter()
            .filter(|c| c.parent == Some(j))
            .map(|c| c.offset)
            .chain(bvh.joints[j].end_sites.iter().copied())
            .map(|o| o.norm())
            .fold(0.0, f64::max)
    };
    let leg = human.legs[0];
    let mut thigh = 0.0;
    let mut j = leg.knee;
    while j != leg.hip {
        thigh += bvh.joints[j].offset.norm();
        match parent[j] {
            Some(p) => j = p,
            None => break,
        }
    }
    let mut marks = vec![human.pelvis];
    for l in &human.legs {
        marks.extend([l.hip, l.knee, l.ankle]);
        marks.extend(l.toe);
    }
    if let Some(s) = &human.spine {
        marks.extend([s.lumbar, s.thorax, s.head]);
        marks.extend(s.neck);
        for a in s.arms.iter().flatten() {
            marks.extend([a.shoulder, a.elbow, a.wrist]);
        }
    }
    let long_bones = crate::model::skeleton::on_long_bones(&topo, human);
    let (mut props, mut branches) = (vec![], vec![]);
    for (j, c) in classes.iter_mut().enumerate() {
        let distal = matches!(
            c.class,
            Some((Segment::Hand | Segment::Foot | Segment::Head, _))
        );
        let long = matches!(
            c.class,
            Some((
                Segment::Thigh | Segment::Shank | Segment::UpperArm | Segment::Forearm,
                _
            ))
        );
        if distal && !marks.contains(&j) && reach(j) > 0.5 * thigh {
            *c = SegmentOf::default();
            props.push(bvh.joints[j].name.clone());
        } else if long && !long_bones.contains(&j) {
            *c = SegmentOf::default();
            branches.push(bvh.joints[j].name.clone());
        }
    }
    (classes, props, branches)
}

/// Calibrates the segment frames of `human` on the take's frames (see the module doc).
fn joints_of(take: &Take, human: &Human, frames: &[Posed], notes: &mut Vec<String>) -> Vec<Joint> {
    let bvh = &take.bvh;
    let up = Vector3::ith(take.up.index(), 1.0);
    let parent = |j: usize| bvh.joints[j].parent.unwrap_or(j);
    let [l, r] = human.legs;
    let right_of_pelvis = move |p: &Posed| p.pos[r.hip] - p.pos[l.hip];
    let stride = ((0.05 / take.bvh.frame_time).round() as usize).max(1);
    let pelvis = human.pelvis;
    let z_pelvis = mean_dir(frames, |p| p.rot[pelvis].transpose() * right_of_pelvis(p));
    // the pelvis's long axis: from the mid-hip point to the lumbar spine (the first trunk joint
    // a tenth of a thigh above it), else the world's up on average
    let mid_hip = move |p: &Posed| 0.5 * (p.pos[l.hip] + p.pos[r.hip]);
    let thigh = (frames[0].pos[l.hip] - frames[0].pos[l.knee]).norm();
    let lumbar = human.spine.and_then(|s| {
        [s.lumbar, s.thorax]
            .into_iter()
            .find(|&j| (frames[0].pos[j] - mid_hip(&frames[0])).norm() > 0.1 * thigh)
    });
    let y_pelvis = match lumbar {
        Some(j) => mean_dir(frames, |p| {
            p.rot[pelvis].transpose() * (p.pos[j] - mid_hip(p))
        }),
        None => mean_dir(frames, |p| p.rot[pelvis].transpose() * up),
    };
    let (Some(z), Some(y)) = (z_pelvis, y_pelvis) else {
        notes.push("the pelvis has no left–right extent: no anatomical angles".into());
        return vec![];
    };
    let pelvis_frame = Frame::Body { body: pelvis, y, z };
    let pelvis_right = move |p: &Posed| p.rot[pelvis] * z;
    let moment_at = |j: usize| {
        let welded = take.map.joints[j].body == take.map.joints[parent(j)].body;
        (!welded && bvh.joints[j].parent.is_some()).then_some(j)
    };
    let heading = mean_dir(frames, |p| {
        let x = p.rot[pelvis] * y.cross(&z);
        x - up * x.dot(&up)
    })
    .unwrap_or_else(|| Vector3::ith((take.up.index() + 1) % 3, 1.0));
    let mut out = vec![Joint {
        kind: PELVIS,
        suffix: "",
        proximal: Frame::Lab { x: heading },
        distal: pelvis_frame,
        moment_at: None,
    }];
    let limb = |kind_p: JointKind,
                kind_m: JointKind,
                suffix: &'static str,
                top: Frame,
                (a, b, c): (usize, usize, usize),
                out: &mut Vec<Joint>| {
        // a-b-c: hip, knee, ankle (shoulder, elbow, wrist); bodies of the two bones
        let (upper, lower) = (parent(b), parent(c));
        let bone_u = move |p: &Posed| p.pos[a] - p.pos[b];
        let bone_l = move |p: &Posed| p.pos[b] - p.pos[c];
        let zu = lateral_axis(
            frames,
            (upper, lower, false),
            &pelvis_right,
            &up,
            &bone_u,
            stride,
        );
        let zl = lateral_axis(
            frames,
            (upper, lower, true),
            &pelvis_right,
            &up,
            &bone_l,
            stride,
        );
        let (Some(zu), Some(zl)) = (zu, zl) else {
            return None;
        };
        let u = Frame::Bone {
            prox: a,
            dist: b,
            body: upper,
            z: zu,
        };
        let lo = Frame::Bone {
            prox: b,
            dist: c,
            body: lower,
            z: zl,
        };
        out.push(Joint {
            kind: kind_p,
            suffix,
            proximal: top,
            distal: u,
            moment_at: moment_at(a),
        });
        out.push(Joint {
            kind: kind_m,
            suffix,
            proximal: u,
            distal: lo,
            moment_at: moment_at(b),
        });
        Some(lo)
    };
    let mut legs = vec![];
    for (leg, suffix) in [(l, "_l"), (r, "_r")] {
        let mut pair = vec![];
        let shank = limb(
            HIP,
            KNEE,
            suffix,
            pelvis_frame,
            (leg.hip, leg.knee, leg.ankle),
            &mut pair,
        );
        legs.push((leg, suffix, shank, pair));
    }
    // the trunk next (output order: pelvis, lumbar, legs, arms)
    let spine = human.spine.and_then(|s| {
        let th = s.thorax;
        let zt = match s.arms {
            Some([al, ar]) => mean_dir(frames, |p| {
                p.rot[th].transpose() * (p.pos[ar.shoulder] - p.pos[al.shoulder])
            }),
            None => mean_dir(frames, |p| p.rot[th].transpose() * pelvis_right(p)),
        }?;
        let yt = match s.neck {
            Some(nk) => mean_dir(frames, |p| p.rot[th].transpose() * (p.pos[nk] - p.pos[th])),
            None => mean_dir(frames, |p| p.rot[th].transpose() * up),
        }?;
        Some((
            s,
            Frame::Body {
                body: th,
                y: yt,
                z: zt,
            },
        ))
    });
    if let Some((s, thorax)) = spine {
        out.push(Joint {
            kind: LUMBAR,
            suffix: "",
            proximal: pelvis_frame,
            distal: thorax,
            moment_at: moment_at(s.lumbar),
        });
    } else {
        notes.push(
            "no trunk above the pelvis was found: no lumbar, shoulder or elbow angles".into(),
        );
    }
    for (leg, suffix, shank, pair) in legs {
        let Some(shank) = shank else {
            notes.push(format!(
                "leg{suffix}: the hip and knee have no left–right axis: no angles"
            ));
            continue;
        };
        out.extend(pair);
        let Frame::Bone {
            body: shank_body, ..
        } = shank
        else {
            continue;
        };
        let foot_body = leg.toe.map_or(leg.ankle, parent);
        let toe = move |p: &Posed| match leg.toe {
            Some(t) => p.pos[t],
            None => {
                let e = bvh.joints[leg.ankle]
                    .end_sites
                    .first()
                    .copied()
                    .unwrap_or_default();
                p.pos[leg.ankle] + p.rot[leg.ankle] * (e * take.map.scale_to_m)
            }
        };
        let sole = move |p: &Posed| toe(p) - p.pos[leg.ankle];
        if foot_body == shank_body || sole(&frames[0]).norm() < 1e-6 {
            notes.push(format!(
                "ankle{suffix}: the foot has no bone of its own: no ankle angles"
            ));
            continue;
        }
        let zf = lateral_axis(
            frames,
            (shank_body, foot_body, true),
            &pelvis_right,
            &up,
            &sole,
            stride,
        );
        let xf = flat_sole(frames, foot_body, &sole, &|p| toe(p), &up);
        if let (Some(z), Some(x)) = (zf, xf) {
            out.push(Joint {
                kind: ANKLE,
                suffix,
                proximal: shank,
                distal: Frame::Foot {
                    body: foot_body,
                    z,
                    x,
                },
                moment_at: moment_at(leg.ankle),
            });
        }
    }
    if let Some((s, thorax)) = spine {
        for arm in s.arms.iter().flatten() {
            let suffix = if arm.side == crate::model::anthropometry::Side::Left {
                "_l"
            } else {
                "_r"
            };
            limb(
                SHOULDER,
                ELBOW,
                suffix,
                thorax,
                (arm.shoulder, arm.elbow, arm.wrist),
                &mut out,
            );
        }
    }
    out
}

/// The foot's level direction (in its body's frame): the ankle → toe line with its vertical
/// part removed, averaged over the frames where the foot lies lowest (ankle and toe within
/// 2 cm of their lowest), all frames if none.
fn flat_sole(
    frames: &[Posed],
    body: usize,
    sole: &dyn Fn(&Posed) -> Vector3<f64>,
    toe: &dyn Fn(&Posed) -> Vector3<f64>,
    up: &Vector3<f64>,
) -> Option<Vector3<f64>> {
    let ankle_h: Vec<f64> = frames.iter().map(|p| (toe(p) - sole(p)).dot(up)).collect();
    let toe_h: Vec<f64> = frames.iter().map(|p| toe(p).dot(up)).collect();
    let low = |h: &[f64]| h.iter().copied().fold(f64::INFINITY, f64::min);
    let (la, lt) = (low(&ankle_h), low(&toe_h));
    let level = |p: &Posed| {
        let s = sole(p);
        p.rot[body].transpose() * (s - up * s.dot(up))
    };
    let flat: Vec<usize> = (0..frames.len())
        .filter(|&k| ankle_h[k] <= la + 0.02 && toe_h[k] <= lt + 0.02)
        .collect();
    let sum = flat
        .iter()
        .map(|&k| level(&frames[k]))
        .fold(Vector3::zeros(), |s, v| s + v);
    sum.try_normalize(1e-12).or_else(|| mean_dir(frames, level))
}

/// Anatomical angles and moments of every frame of a human take (see the module doc), with
/// the take's ground reactions when its `contact` is `feet`.
pub fn anatomy(take: &Take) -> Result<Anatomy, Error> {
    let grf = ground_reactions(take)?;
    anatomy_with(take, grf.as_ref())
}

/// [`anatomy`] with the ground reactions already estimated (`None`: no contact): the
/// calibration ([`Calibration`]), the net moments by RNEA with the ground reactions, the
/// series.
pub fn anatomy_with(take: &Take, grf: Option<&GroundReactions>) -> Result<Anatomy, Error> {
    let cal = Calibration::new(take)?;
    let moments = cal.net_moments(take, grf);
    cal.series(take, &moments, grf)
}

/// One frame's part of [`anatomy_with`]'s columns that masses do not change: per joint its
/// angles (deg) into `angles` (three per joint) and, for each joint with a moment, its joint
/// coordinate system's axes (world) into `axes`, which the moments are later projected on.
/// `None` when a joint's segments have no frame.
fn frame_angles(
    joints: &[Joint],
    p: &Posed,
    up: &Vector3<f64>,
    angles: &mut [f64],
    axes: &mut [[Vector3<f64>; 3]],
) -> Option<()> {
    let (mut c, mut i) = (0, 0);
    for j in joints {
        let (fp, fd) = (j.proximal.at(p, up)?, j.distal.at(p, up)?);
        let (ang, e) = jcs::joint_angles_axes(j.kind, j.suffix != "_l", &fp, &fd);
        for a in ang {
            angles[c] = a.to_degrees();
            c += 1;
        }
        if j.moment_at.is_some() {
            axes[i] = e;
            i += 1;
        }
    }
    Some(())
}

/// Removes jumps of whole turns from an angle series (deg).
fn unwrap_degrees(x: &mut [f64]) {
    for k in 1..x.len() {
        let d = x[k] - x[k - 1];
        x[k] -= 360.0 * (d / 360.0).round();
    }
}

/// The written name of an [`Anatomy`] column, in the one scheme of `report::columns`: the
/// quantity first, `knee_l:flexion:moment` → `moment:knee_l:flexion` (`angle:`, `moment:`,
/// `moment_per_kg:`).
pub fn column_name(name: &str) -> String {
    match name.rsplit_once(':') {
        Some((axis, what)) => crate::report::columns::name(what, &[axis]),
        None => name.to_string(),
    }
}

/// `articula anatomy -o PATH`: `time` (s), then every column of [`anatomy`] named by
/// [`column_name`] (`angle:<joint>:<axis>` in deg, `moment:…` in N·m, `moment_per_kg:…` in
/// N·m/kg), then with ground contact `contact:left`, `contact:right` (1 on
/// the floor, 0 off it), with the take's consistency `residual:force` (N),
/// `residual:moment` (N·m about the pelvis) and `residual:beyond` (1 where the frame lies
/// beyond Hicks et al.'s thresholds, 0 elsewhere), and last `edge` (1 within the smoothing's
/// reach of the take's first or last frame, whose accelerations are not trustworthy).
pub fn write_anatomy(a: &Anatomy, path: &std::path::Path) -> Result<(), Error> {
    anatomy_table(a).write_csv(path)
}

/// The table [`write_anatomy`] writes.
pub fn anatomy_table(a: &Anatomy) -> crate::pipeline::table::Table {
    let mut header = vec!["time".to_string()];
    header.extend(a.names.iter().map(|n| column_name(n)));
    let mut cols: Vec<&[f64]> = vec![&a.time];
    cols.extend(a.columns.iter().map(|c| c.as_slice()));
    let contact: Vec<Vec<f64>> = a
        .contact
        .iter()
        .map(|(_, on)| on.iter().map(|&c| if c { 1.0 } else { 0.0 }).collect())
        .collect();
    header.extend(a.contact.iter().map(|(f, _)| format!("contact:{f}")));
    cols.extend(contact.iter().map(|c| c.as_slice()));
    let beyond: Vec<f64>;
    if let Some(c) = &a.consistency {
        beyond = c
            .beyond
            .iter()
            .map(|&b| if b { 1.0 } else { 0.0 })
            .collect();
        header.extend(["residual:force", "residual:moment", "residual:beyond"].map(String::from));
        cols.extend([
            c.force_n.as_slice(),
            c.moment_nm.as_slice(),
            beyond.as_slice(),
        ]);
    }
    let n = a.time.len();
    let edge: Vec<f64> = (0..n)
        .map(|k| f64::from(u8::from(k < a.edge || k + a.edge >= n)))
        .collect();
    header.push("edge".into());
    cols.push(&edge);
    crate::pipeline::table::Table::from_columns(header, &cols)
}

/// The anatomical joints of human `h` (`pipeline::anatomy`'s names: `pelvis`, `lumbar`,
/// `hip_l`, `knee_l`, `ankle_l`, `shoulder_l`, `elbow_l`, …) and the BVH joint at each one's
/// centre, whose channels turn the distal segment.
pub fn anatomical_joints(
    h: &crate::model::skeleton::Human,
    bvh: &crate::io::bvh::Bvh,
) -> Vec<(String, String)> {
    use crate::model::anthropometry::Side;
    let name = |j: usize| bvh.joints[j].name.clone();
    let suffix = |s: Side| if s == Side::Left { "_l" } else { "_r" };
    let mut out = vec![("pelvis".to_string(), name(h.pelvis))];
    for leg in &h.legs {
        let side = suffix(leg.side);
        out.push((format!("hip{side}"), name(leg.hip)));
        out.push((format!("knee{side}"), name(leg.knee)));
        out.push((format!("ankle{side}"), name(leg.ankle)));
    }
    if let Some(s) = &h.spine {
        out.push(("lumbar".into(), name(s.lumbar)));
        for arm in s.arms.iter().flatten() {
            let side = suffix(arm.side);
            out.push((format!("shoulder{side}"), name(arm.shoulder)));
            out.push((format!("elbow{side}"), name(arm.elbow)));
        }
    }
    out
}
