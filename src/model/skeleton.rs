//! Which joints of a human skeleton are its pelvis, hips, knees, ankles, toes, lumbar spine,
//! thorax, shoulders, elbows and wrists: found by topology and geometry, names only as hints.
//!
//! Exporters name a segment by its proximal joint (`RightHip` is the thigh in an inertial
//! suit's rig), by its bone (`RightUpLeg`), or by nothing a table knows (`J7`); a skeleton's
//! shape says the same thing whatever the names. From world positions of the joints over a
//! few frames of the motion (and of their End Sites):
//! - **legs** are the chains from the pelvis to two ends near the floor (within 15 % of the
//!   body's height of the lowest) whose branching point stands more than a quarter of the
//!   body's height above them, the pair most alike in length (a cane or a prop that reaches
//!   the floor is not a leg); that branching joint is the **pelvis**;
//! - along a leg, the **ankle** is the first joint from which the rest of the chain (foot and
//!   toes, to the end) is shorter than [`FOOT_REACH`] of the body's height (of a rig without a
//!   trunk, the height its pelvis gives: [`HIP_HEIGHT_SHARE`]); the **knee** is the
//!   joint between hip and ankle where the chain bends most over the motion, among those a
//!   plausible shank length above the ankle ([`SHANK_SHARE`]); the **hip** is the most proximal
//!   joint from which the chain runs straight to the knee (twist helpers along a femur lie on
//!   that line; a pelvis bone such as CMU's `LHipJoint` does not);
//! - the **head** is the highest end outside the legs without a mirror image (hands and eyes
//!   come in pairs of ends equally far from the pelvis); when every end comes in a pair (a face
//!   rig: eyes, ears, the jaw's sides, none of the head's own, as MakeHuman's), the joint where
//!   the highest end's pair branches; the spine is the path to it from the
//!   pelvis's branch, its first joint the **lumbar** joint; **arms** are the two longest
//!   branches that leave the spine (one trunk joint may carry them all), their branching joint the
//!   **thorax**, their **wrist** the common joint of the branch's ends that reach at least
//!   half as far as its farthest (fingers, props; not a twist bone halfway down the arm), the
//!   elbow and shoulder found as the knee and the hip are.
//!
//! Sides come from the names when both legs carry a side in their names, otherwise from the
//! geometry: the right is forward × up, forward the way the toes point from the ankles.

use crate::model::anthropometry::{Segment, SegmentOf, Side};
use nalgebra::Vector3;

/// Fraction of the body's height within which the foot (ankle to the end of the chain) lies.
pub const FOOT_REACH: f64 = 0.2;
/// Range of the shank's share of the leg chain's length (from its first joint below the
/// pelvis to the ankle) searched for the knee; de Leva's (1996) segment lengths put it at
/// 0.45–0.5 (shank 0.25, thigh 0.24 and a pelvis bone up to 0.06 of the stature).
pub const SHANK_SHARE: (f64, f64) = (0.3, 0.62);
/// Range of the forearm's share of the arm chain's length (from its first joint off the
/// spine to the wrist) searched for the elbow (de Leva: forearm 0.27 m, upper arm 0.28 m,
/// clavicle about 0.15 m).
pub const FOREARM_SHARE: (f64, f64) = (0.25, 0.55);

/// Pairs of leg ends whose relative difference in length ([`find_human`]) is within this of
/// each other are equally alike, and the first is kept: a nanometre per metre, far above the
/// rounding of joint positions far from the origin, on which the choice among a foot's mirror
/// toe chains once hung (`tests/skeleton_topology.rs`).
pub const ALIKE: f64 = 1e-9;

/// Why a skeleton with a third limb on the floor is not a biped (a quadruped, a crab).
pub const MANY_LIMBS: &str = "more than two limbs stand on the floor, not a biped";

/// Joint positions (m, world) at one sampled frame.
#[derive(Debug, Clone)]
pub struct Pose {
    /// One per joint.
    pub joints: Vec<Vector3<f64>>,
    /// The joint's first End Site, if it has one.
    pub ends: Vec<Option<Vector3<f64>>>,
}

impl Pose {
    /// The same pose with every length multiplied by `s` (file units to metres).
    pub fn scaled(&self, s: f64) -> Pose {
        Pose {
            joints: self.joints.iter().map(|p| p * s).collect(),
            ends: self.ends.iter().map(|e| e.map(|p| p * s)).collect(),
        }
    }
}

/// A leg: the joints at the hip, knee and ankle centres, and the toe joint if the foot has one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Leg {
    pub side: Side,
    pub hip: usize,
    pub knee: usize,
    pub ankle: usize,
    pub toe: Option<usize>,
    /// The lowest end of the leg (a toe, or the ankle itself).
    pub end: usize,
}

/// An arm: the joints at the shoulder (glenohumeral), elbow and wrist centres.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Arm {
    pub side: Side,
    pub shoulder: usize,
    pub elbow: usize,
    pub wrist: usize,
}

/// The trunk above the pelvis.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Spine {
    /// The first joint on the way from the pelvis to the head (its moment is the lumbar one).
    pub lumbar: usize,
    /// Where the arms branch off (the upper trunk).
    pub thorax: usize,
    /// The next joint above the thorax on the way to the head, if any (the neck).
    pub neck: Option<usize>,
    /// The highest end outside the legs.
    pub head: usize,
    /// Left, right.
    pub arms: Option<[Arm; 2]>,
}

/// The landmarks of a human skeleton.
#[derive(Debug, Clone, PartialEq)]
pub struct Human {
    /// The joint both legs branch from.
    pub pelvis: usize,
    /// Left, right.
    pub legs: [Leg; 2],
    pub spine: Option<Spine>,
    /// Whether left and right came from the joint names (else from forward × up).
    pub sides_from_names: bool,
    /// Median angle (rad) of the pelvis-to-head line from the vertical over the frames (π/2
    /// without a trunk): how upright the body stands about the up axis given.
    pub lean: f64,
    /// The body's standing height from its own dimensions, whatever its pose or rest pose
    /// (m if the poses are): the ankle's height over the floor where the foot is lowest (the
    /// 5th percentile over the frames), plus the leg (ankle to knee to hip centre), plus the
    /// longest reach from the mid-hip point to the head's end over the frames (a head without
    /// an End Site above its joint is given [`HEAD_ABOVE_JOINT`] of the stature above it).
    pub standing_height: f64,
}

/// A skeleton as parent links and names (names are hints only).
pub struct Topology<'a> {
    pub names: &'a [&'a str],
    pub parent: &'a [Option<usize>],
}

impl Topology<'_> {
    fn path_to_root(&self, mut j: usize) -> Vec<usize> {
        let mut p = vec![j];
        while let Some(q) = self.parent[j] {
            p.push(q);
            j = q;
        }
        p
    }
    /// Whether `j` is `ancestor` or lies below it.
    fn descends(&self, j: usize, ancestor: usize) -> bool {
        self.path_to_root(j).contains(&ancestor)
    }
    /// Lowest common ancestor.
    fn lca(&self, a: usize, b: usize) -> usize {
        let pa = self.path_to_root(a);
        let pb = self.path_to_root(b);
        *pa.iter()
            .find(|j| pb.contains(j))
            .unwrap_or(&pa[pa.len() - 1])
    }
    /// The chain from just below `top` down to `end` (top exclusive, end inclusive), or `None`
    /// if `top` is not an ancestor of `end`.
    fn chain(&self, top: usize, end: usize) -> Option<Vec<usize>> {
        let mut p = self.path_to_root(end);
        let i = p.iter().position(|&j| j == top)?;
        p.truncate(i);
        p.reverse();
        Some(p)
    }
    fn is_end(&self, j: usize, poses: &[Pose]) -> bool {
        !self.parent.contains(&Some(j)) || poses.first().is_some_and(|p| p.ends[j].is_some())
    }
}

/// Median over samples of `f(pose)`.
fn median(poses: &[Pose], f: impl Fn(&Pose) -> f64) -> f64 {
    let mut v: Vec<f64> = poses.iter().map(f).collect();
    v.sort_by(f64::total_cmp);
    if v.is_empty() {
        return 0.0;
    }
    v[v.len() / 2]
}

/// Where a chain ends: the joint's End Site if it has one, else the joint.
fn tip(p: &Pose, j: usize) -> Vector3<f64> {
    p.ends[j].unwrap_or(p.joints[j])
}

/// Median length of the path along `chain` from `chain[from]` to its tip (End Site included).
fn path_length(poses: &[Pose], chain: &[usize], from: usize) -> f64 {
    median(poses, |p| {
        let mut s = 0.0;
        for w in chain[from..].windows(2) {
            s += (p.joints[w[1]] - p.joints[w[0]]).norm();
        }
        let last = chain[chain.len() - 1];
        s + (tip(p, last) - p.joints[last]).norm()
    })
}

/// Median distance from joint `top` to joint `first` (the step onto a chain).
fn span_from(poses: &[Pose], top: usize, first: usize) -> f64 {
    median(poses, |p| (p.joints[first] - p.joints[top]).norm())
}

/// Median path length between two joints of a chain (`from < to`).
fn span(poses: &[Pose], chain: &[usize], from: usize, to: usize) -> f64 {
    median(poses, |p| {
        chain[from..=to]
            .windows(2)
            .map(|w| (p.joints[w[1]] - p.joints[w[0]]).norm())
            .sum()
    })
}

/// Range (95th − 5th percentile, rad) over samples of the angle the chain turns at `chain[i]`,
/// between the nearest distinct points above (`top` if none on the chain) and below.
fn bend_range(poses: &[Pose], top: usize, chain: &[usize], i: usize, below: usize) -> f64 {
    let eps = 1e-3;
    let mut angles: Vec<f64> = poses
        .iter()
        .filter_map(|p| {
            let c = p.joints[chain[i]];
            let above = chain[..i]
                .iter()
                .rev()
                .map(|&j| p.joints[j])
                .chain(std::iter::once(p.joints[top]))
                .find(|x| (x - c).norm() > eps)?;
            let next = chain[i + 1..=below]
                .iter()
                .map(|&j| p.joints[j])
                .find(|x| (x - c).norm() > eps)?;
            Some((c - above).angle(&(next - c)))
        })
        .collect();
    if angles.len() < 2 {
        return 0.0;
    }
    angles.sort_by(f64::total_cmp);
    let n = angles.len() - 1;
    angles[(0.95 * n as f64).round() as usize] - angles[(0.05 * n as f64).round() as usize]
}

/// The middle joint of a limb (knee, elbow) between the chain's start and `chain[distal]`: the
/// one whose share of the path to the distal joint lies in `share` and where the chain bends
/// most over the motion; without motion (a single pose), the one whose share is nearest the
/// middle of `share`.
fn middle_joint(
    poses: &[Pose],
    top: usize,
    chain: &[usize],
    distal: usize,
    share: (f64, f64),
) -> Option<usize> {
    // the chain's own length (not the step onto it from the trunk: a spine joint low in the
    // back makes that step long)
    let total = median(poses, |p| {
        chain[..=distal]
            .windows(2)
            .map(|w| (p.joints[w[1]] - p.joints[w[0]]).norm())
            .sum::<f64>()
    });
    if total <= 0.0 {
        return None;
    }
    let mid = 0.5 * (share.0 + share.1);
    let candidates: Vec<(usize, f64, f64)> = (0..distal)
        .map(|i| (i, span(poses, chain, i, distal) / total))
        .filter(|(_, s)| (share.0..=share.1).contains(s))
        .map(|(i, s)| (i, s, bend_range(poses, top, chain, i, distal)))
        .collect();
    let most = candidates.iter().map(|c| c.2).fold(0.0, f64::max);
    let pick = if most > 10f64.to_radians() {
        candidates.iter().max_by(|a, b| a.2.total_cmp(&b.2))
    } else {
        candidates
            .iter()
            .min_by(|a, b| (a.1 - mid).abs().total_cmp(&(b.1 - mid).abs()))
    };
    pick.map(|c| c.0)
}

/// The proximal joint of a limb (hip, shoulder) above `chain[mid]`: the most proximal chain
/// joint from which every joint down to the middle one lies on the straight line to it
/// (within 3 % of that length, median over samples).
fn proximal_joint(poses: &[Pose], chain: &[usize], mid: usize) -> usize {
    let on_line = |i: usize| {
        median(poses, |p| {
            let (a, b) = (p.joints[chain[i]], p.joints[chain[mid]]);
            let l = (b - a).norm();
            if l <= 1e-9 {
                return f64::INFINITY;
            }
            let u = (b - a) / l;
            chain[i + 1..mid]
                .iter()
                .map(|&j| {
                    let d = p.joints[j] - a;
                    (d - u * d.dot(&u)).norm() / l
                })
                .fold(0.0, f64::max)
        }) < 0.03
    };
    (0..mid)
        .find(|&i| on_line(i))
        .unwrap_or(mid.saturating_sub(1))
}

/// The first joint of a chain after `chain[i]` at a distinct position, if any.
fn next_distinct(poses: &[Pose], chain: &[usize], i: usize) -> Option<usize> {
    let p = poses.first()?;
    chain[i + 1..]
        .iter()
        .copied()
        .find(|&j| (p.joints[j] - p.joints[chain[i]]).norm() > 1e-3)
}

fn side_from_names(names: &[&str], chain: &[usize]) -> Option<Side> {
    let mut votes = [0usize; 2];
    for &j in chain {
        match crate::model::anthropometry::name_side(names[j]) {
            Side::Left => votes[0] += 1,
            Side::Right => votes[1] += 1,
            Side::Center => {}
        }
    }
    match votes {
        [l, r] if l > r => Some(Side::Left),
        [l, r] if r > l => Some(Side::Right),
        _ => None,
    }
}

/// Finds the landmarks of a human (biped) skeleton; `Err` says why the skeleton is not one.
/// `poses` are a few frames of the motion (world positions, m), `up` the up axis.
pub fn find_human(topo: &Topology, poses: &[Pose], up: usize) -> Result<Human, String> {
    let n = topo.parent.len();
    if poses.is_empty() || n < 5 {
        return Err("a human skeleton needs at least 5 joints and one frame".into());
    }
    let height = |j: usize| median(poses, |p| tip(p, j)[up]);
    let ends: Vec<usize> = (0..n).filter(|&j| topo.is_end(j, poses)).collect();
    let tops = (0..n).map(|j| median(poses, |p| p.joints[j][up]));
    let (lo, hi) = tops.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), h| {
        (a.min(h), b.max(h))
    });
    let body = (hi - lo).max(ends.iter().map(|&e| height(e)).fold(lo, f64::max) - lo);
    if body <= 0.0 {
        return Err("the skeleton has no height".into());
    }

    // legs: two ends near the floor whose branching point stands well above them, as alike
    // in length as two legs are (a cane or a prop that reaches the floor is not a leg)
    let mut by_height = ends.clone();
    by_height.sort_by(|&a, &b| height(a).total_cmp(&height(b)));
    let floor = height(*by_height.first().ok_or("no ends")?);
    let low: Vec<usize> = by_height
        .iter()
        .copied()
        .take_while(|&e| height(e) - floor <= 0.15 * body)
        .collect();
    let reach = |top: usize, e: usize| {
        topo.chain(top, e).map_or(0.0, |c| {
            path_length(poses, &c, 0) + span_from(poses, top, c[0])
        })
    };
    let mut best: Option<(usize, f64, usize, usize)> = None;
    for (i, &a) in low.iter().enumerate() {
        for &b in &low[i + 1..] {
            let l = topo.lca(a, b);
            if l == a || l == b || median(poses, |p| p.joints[l][up]) - floor <= 0.25 * body {
                continue;
            }
            let (la, lb) = (reach(l, a), reach(l, b));
            let unlike = (la - lb).abs() / la.max(lb).max(1e-12);
            // legs branch nearest the root (hands on the floor branch from the chest); pairs
            // alike to within ALIKE are equals, and the first (the lowest ends) is kept
            let depth = topo.path_to_root(l).len();
            if best.is_none_or(|(d, u, _, _)| depth < d || (depth == d && unlike < u - ALIKE)) {
                best = Some((depth, unlike, a, b));
            }
        }
    }
    let (_, _, e1, e2) =
        best.ok_or("no two legs: no two ends near the floor branch from high enough above it")?;
    let pelvis = topo.lca(e1, e2);
    let top = (0..n).map(&height).fold(hi, f64::max);
    let body = body.max(trunkless_height(
        median(poses, |p| p.joints[pelvis][up]),
        floor,
        top,
    ));
    let mut legs = vec![];
    for e in [e1, e2] {
        let chain = topo.chain(pelvis, e).ok_or("leg chain")?;
        let ankle = (0..chain.len())
            .find(|&i| path_length(poses, &chain, i) <= FOOT_REACH * body)
            .ok_or("no ankle: every joint of a leg lies far above its end")?;
        let knee = middle_joint(poses, pelvis, &chain, ankle, SHANK_SHARE)
            .ok_or("no knee: no joint of the leg lies a shank's length above the ankle")?;
        let hip = proximal_joint(poses, &chain, knee);
        legs.push(Leg {
            side: Side::Center,
            hip: chain[hip],
            knee: chain[knee],
            ankle: chain[ankle],
            toe: next_distinct(poses, &chain, ankle),
            end: e,
        });
    }

    // a biped has two limbs below its knees: a third (a quadruped's, a crab's legs) is not one
    let knees = 0.5
        * (median(poses, |p| p.joints[legs[0].knee][up])
            + median(poses, |p| p.joints[legs[1].knee][up]));
    let in_legs = |e: usize| topo.descends(e, legs[0].hip) || topo.descends(e, legs[1].hip);
    // (by the end joints, not their End Sites: a cane's tip reaches the floor from a hand)
    let joint_height = |j: usize| median(poses, |p| p.joints[j][up]);
    if let Some(&other) = ends
        .iter()
        .find(|&&e| !in_legs(e) && joint_height(e) < knees)
    {
        return Err(format!(
            "`{}` reaches below the knees too: {MANY_LIMBS}",
            topo.names[other]
        ));
    }

    // sides: names if both legs have one and they differ, else forward × up
    let named: Vec<Option<Side>> = [e1, e2]
        .iter()
        .map(|&e| side_from_names(topo.names, &topo.chain(pelvis, e).unwrap_or_default()))
        .collect();
    let sides_from_names = matches!(
        (named[0], named[1]),
        (Some(a), Some(b)) if a != b
    );
    let first_is_left = if sides_from_names {
        named[0] == Some(Side::Left)
    } else {
        // the first leg is on the left if it lies on the −right side of the second
        median(poses, |p| {
            let fwd = |l: &Leg| {
                let t = tip(p, l.end) - p.joints[l.ankle];
                let mut t = t;
                t[up] = 0.0;
                t
            };
            let forward = fwd(&legs[0]) + fwd(&legs[1]);
            let right = forward.cross(&Vector3::ith(up, 1.0));
            (p.joints[legs[1].hip] - p.joints[legs[0].hip]).dot(&right)
        }) > 0.0
    };
    if !first_is_left {
        legs.swap(0, 1);
    }
    legs[0].side = Side::Left;
    legs[1].side = Side::Right;
    let legs = [legs[0], legs[1]];
    let spine = find_spine(topo, poses, up, pelvis, &legs, &ends, body);
    let mut lean_median = std::f64::consts::FRAC_PI_2;
    if let Some(s) = &spine {
        // upright at some time (a lift bends it for most of a take; a quadruped never)
        let mut lean: Vec<f64> = poses
            .iter()
            .map(|p| (tip(p, s.head) - p.joints[pelvis]).angle(&Vector3::ith(up, 1.0)))
            .collect();
        lean.sort_by(f64::total_cmp);
        lean_median = lean[lean.len() / 2];
        let most_upright = lean[lean.len() / 10];
        if most_upright > 45f64.to_radians() {
            return Err(format!(
                "the trunk is never upright (pelvis to head at least {:.0}° from the vertical in \
                 nine frames of ten): not a biped",
                most_upright.to_degrees()
            ));
        }
    }
    let standing_height = standing_height(poses, up, &legs, spine.as_ref().map(|s| s.head));
    Ok(Human {
        pelvis,
        legs,
        spine,
        sides_from_names,
        lean: lean_median,
        standing_height,
    })
}

/// The height of a human (m if the positions are) whose skeleton has no trunk (a pelvis and two
/// legs), from its pelvis's height `pelvis` over the `floor` where the highest point of the
/// skeleton is `top`: the pelvis at [`HIP_HEIGHT_SHARE`] of the stature; 0 when the skeleton
/// rises above its pelvis by more than a quarter of the pelvis's height (a trunk: a human's
/// head lies 0.45 of its stature above its hips, a quarter of their height is 0.13).
///
/// A trunkless rig stands half a human's height, so that along its legs the thresholds made
/// from its own height mistook its toes for its ankles: its foot, ankle to toe tip, is longer
/// than [`FOOT_REACH`] of that height (a 19 cm foot under a 92 cm rig), and the foot's joint
/// was taken for one inside the shank (`tests/legs_only.rs`).
fn trunkless_height(pelvis: f64, floor: f64, top: f64) -> f64 {
    let hips = pelvis - floor;
    if hips <= 0.0 || top - pelvis > 0.25 * hips {
        return 0.0;
    }
    hips / HIP_HEIGHT_SHARE
}

/// The hip joint's height as a share of the stature: 0.53 (Drillis & Contini 1966, *Body
/// segment parameters*, Report 1166-03, New York University; Winter 2009, *Biomechanics and
/// Motor Control of Human Movement*, 4th ed., fig. 4.1).
pub const HIP_HEIGHT_SHARE: f64 = 0.53;

/// See [`Human::standing_height`] (without a head, up to the pelvis's highest point).
fn standing_height(poses: &[Pose], up: usize, legs: &[Leg; 2], head: Option<usize>) -> f64 {
    let floor = poses
        .iter()
        .flat_map(|p| {
            legs.iter()
                .map(move |l| tip(p, l.end)[up].min(p.joints[l.ankle][up]))
        })
        .fold(f64::INFINITY, f64::min);
    let mut ankle: Vec<f64> = poses
        .iter()
        .flat_map(|p| legs.iter().map(move |l| p.joints[l.ankle][up] - floor))
        .collect();
    ankle.sort_by(f64::total_cmp);
    let ankle = ankle[ankle.len() / 20];
    let leg = legs
        .iter()
        .map(|l| {
            median(poses, |p| {
                (p.joints[l.hip] - p.joints[l.knee]).norm()
                    + (p.joints[l.knee] - p.joints[l.ankle]).norm()
            })
        })
        .sum::<f64>()
        / 2.0;
    let trunk = poses
        .iter()
        .map(|p| {
            let mid = 0.5 * (p.joints[legs[0].hip] + p.joints[legs[1].hip]);
            head.map_or(0.0, |h| (tip(p, h) - mid).norm())
        })
        .fold(0.0, f64::max);
    // a head that ends at its joint (no End Site above it, Bandai's at zero) stops at the
    // skull's base, about 11 % of the stature below the vertex (Drillis & Contini 1966)
    let topped =
        head.is_some_and(|h| median(poses, |p| (tip(p, h) - p.joints[h]).norm()) > 0.05 * leg);
    let base = ankle + leg + trunk;
    if topped {
        base
    } else {
        base / (1.0 - HEAD_ABOVE_JOINT)
    }
}

/// The share of the stature between a head joint at the skull's base and the vertex.
pub const HEAD_ABOVE_JOINT: f64 = 0.11;

/// The trunk, head and arms above the pelvis (`None` if the skeleton has no end above it).
fn find_spine(
    topo: &Topology,
    poses: &[Pose],
    up: usize,
    pelvis: usize,
    legs: &[Leg; 2],
    ends: &[usize],
    body: f64,
) -> Option<Spine> {
    let in_leg = |e: usize| topo.descends(e, legs[0].hip) || topo.descends(e, legs[1].hip);
    let height = |j: usize| median(poses, |p| tip(p, j)[up]);
    // the head: the highest end outside the legs that has no mirror image (hands, fingers and
    // eyes come in pairs of ends equally far from the pelvis; a hand waved above the head is
    // still a hand)
    let upper: Vec<usize> = ends.iter().copied().filter(|&e| !in_leg(e)).collect();
    let reach = |e: usize| {
        topo.path_to_root(e)
            .windows(2)
            .take_while(|w| w[0] != pelvis)
            .map(|w| median(poses, |p| (p.joints[w[0]] - p.joints[w[1]]).norm()))
            .sum::<f64>()
            + median(poses, |p| (tip(p, e) - p.joints[e]).norm())
    };
    let reaches: Vec<f64> = upper.iter().map(|&e| reach(e)).collect();
    let mirrored = |i: usize| {
        (0..upper.len()).any(|k| {
            let l = topo.lca(upper[i], upper[k]);
            k != i
                && l != upper[i]
                && l != upper[k]
                && (reaches[i] - reaches[k]).abs() <= 0.02 * reaches[i].max(reaches[k])
        })
    };
    let highest =
        |c: &mut dyn Iterator<Item = usize>| c.max_by(|&a, &b| height(a).total_cmp(&height(b)));
    // every end paired (a face rig: eyes, ears, lids, the jaw's sides, and no end of the head's
    // own): the head is where the highest end's pair branches, its nearest mirror image's
    // common ancestor with it (MakeHuman's eyes meet at `head`)
    let paired_head = || {
        let i = (0..upper.len()).max_by(|&a, &b| height(upper[a]).total_cmp(&height(upper[b])))?;
        let partner = (0..upper.len())
            .filter(|&k| {
                let l = topo.lca(upper[i], upper[k]);
                k != i && l != upper[i] && l != upper[k]
            })
            .min_by(|&a, &b| {
                (reaches[a] - reaches[i])
                    .abs()
                    .total_cmp(&(reaches[b] - reaches[i]).abs())
            })?;
        Some(topo.lca(upper[i], upper[partner]))
    };
    let head = highest(&mut (0..upper.len()).filter(|&i| !mirrored(i)).map(|i| upper[i]))
        .or_else(paired_head)
        .or_else(|| highest(&mut upper.iter().copied()))?;
    let base = topo.lca(pelvis, head);
    let spine = topo.chain(base, head)?;
    let lumbar = *spine.first()?;
    // arms: the ends that leave the spine above the lumbar joint, grouped by where they leave
    let mut groups: Vec<(usize, Vec<usize>)> = vec![]; // (off-spine first joint, ends)
    for &e in ends.iter().filter(|&&e| e != head && !in_leg(e)) {
        let path = topo.path_to_root(e);
        let Some(k) = path.iter().position(|j| spine.contains(j)) else {
            continue;
        };
        if k == 0 {
            continue; // an end on the spine itself
        }
        let first = path[k - 1];
        match groups.iter_mut().find(|g| g.0 == first) {
            Some(g) => g.1.push(e),
            None => groups.push((first, vec![e])),
        }
    }
    let reach = |g: &(usize, Vec<usize>)| {
        g.1.iter()
            .map(|&e| median(poses, |p| (tip(p, e) - p.joints[g.0]).norm()))
            .fold(0.0, f64::max)
    };
    groups.sort_by(|a, b| reach(b).total_cmp(&reach(a)));
    let arms = (groups.len() >= 2 && reach(&groups[1]) > 0.2 * body).then(|| {
        let arm = |g: &(usize, Vec<usize>)| -> Option<Arm> {
            // the wrist: the common joint of the ends that reach at least half as far as the
            // farthest (fingers, a held prop; not a twist bone's end halfway down the arm)
            let far = |e: usize| median(poses, |p| (tip(p, e) - p.joints[g.0]).norm());
            let most = reach(g);
            let mut ends = g.1.iter().copied().filter(|&e| far(e) >= 0.5 * most);
            let first = ends.next()?;
            let wrist = ends.fold(first, |a, e| topo.lca(a, e));
            let top = topo.parent[g.0]?;
            let chain = topo.chain(top, wrist)?;
            let w = chain.len() - 1;
            let elbow = middle_joint(poses, top, &chain, w, FOREARM_SHARE)?;
            let shoulder = proximal_joint(poses, &chain, elbow);
            Some(Arm {
                side: Side::Center,
                shoulder: chain[shoulder],
                elbow: chain[elbow],
                wrist,
            })
        };
        Some([arm(&groups[0])?, arm(&groups[1])?])
    });
    let mut arms = arms.flatten();
    let thorax = match &arms {
        Some(a) => topo.lca(a[0].shoulder, a[1].shoulder),
        None => *spine.get(spine.len().saturating_sub(3)).unwrap_or(&lumbar),
    };
    if let Some(a) = arms.as_mut() {
        // the left arm is on the side of the left hip
        let left_first = median(poses, |p| {
            let lr = p.joints[legs[1].hip] - p.joints[legs[0].hip];
            (p.joints[a[1].shoulder] - p.joints[a[0].shoulder]).dot(&lr)
        }) > 0.0;
        if !left_first {
            a.swap(0, 1);
        }
        a[0].side = Side::Left;
        a[1].side = Side::Right;
    }
    let neck = spine
        .iter()
        .position(|&j| j == thorax)
        .and_then(|i| next_distinct(poses, &spine, i));
    Some(Spine {
        lumbar,
        thorax,
        neck,
        head,
        arms,
    })
}

/// The de Leva segment of every joint's link, from the landmarks (names play no part): the
/// pelvis, the bones from it to the hips, the spine up to the thorax and the bones from the
/// thorax to the shoulders are the trunk (the shoulder bones and the trunk's other branches
/// as girdle bones); the neck and above the head; hip to knee the thigh, knee to
/// ankle the shank, the ankle and below the foot; shoulder to elbow the upper arm, elbow to
/// wrist the forearm, the wrist and below the hand. A joint on none of these chains takes its
/// parent's segment (a girdle bone if the parent is the trunk); joints above the pelvis and the
/// spine's base stay massless helpers.
pub fn segment_classes(topo: &Topology, human: &Human) -> Vec<SegmentOf> {
    use crate::model::anthropometry::Segment::*;
    let n = topo.parent.len();
    let mut out: Vec<Option<SegmentOf>> = vec![None; n];
    let set = |out: &mut Vec<Option<SegmentOf>>, j: usize, seg, side, girdle| {
        out[j] = Some(SegmentOf {
            class: Some((seg, side)),
            girdle,
        });
    };
    // a limb: proximal chain (girdle) from `top`, then three segments at a, b, c
    let limb = |out: &mut Vec<Option<SegmentOf>>,
                top: usize,
                [a, b, c]: [usize; 3],
                side,
                segs: [Segment; 3],
                girdle: bool| {
        let chain = topo.chain(top, c).unwrap_or_default();
        let mut seg = None;
        for &j in &chain {
            if j == a {
                seg = Some(segs[0]);
            } else if j == b {
                seg = Some(segs[1]);
            } else if j == c {
                seg = Some(segs[2]);
            }
            match seg {
                None => set(out, j, Trunk, Side::Center, girdle),
                Some(s) => set(out, j, s, side, false),
            }
        }
    };
    set(&mut out, human.pelvis, Trunk, Side::Center, false);
    for leg in &human.legs {
        limb(
            &mut out,
            human.pelvis,
            [leg.hip, leg.knee, leg.ankle],
            leg.side,
            [Thigh, Shank, Foot],
            false,
        );
    }
    if let Some(s) = &human.spine {
        let base = topo.parent[s.lumbar].unwrap_or(human.pelvis);
        set(&mut out, base, Trunk, Side::Center, false);
        let spine = topo.chain(base, s.head).unwrap_or_default();
        let mut seg = Trunk;
        for &j in &spine {
            if Some(j) == s.neck {
                seg = Head;
            }
            set(&mut out, j, seg, Side::Center, false);
        }
        for arm in s.arms.iter().flatten() {
            limb(
                &mut out,
                s.thorax,
                [arm.shoulder, arm.elbow, arm.wrist],
                arm.side,
                [UpperArm, Forearm, Hand],
                true,
            );
        }
    }
    // the rest inherit (in file order, parents first)
    let below_hub = |mut j: usize| loop {
        if j == human.pelvis || out[j].is_some() {
            return true;
        }
        match topo.parent[j] {
            Some(p) => j = p,
            None => return false,
        }
    };
    let mut result = vec![SegmentOf::default(); n];
    for j in 0..n {
        result[j] = match (out[j], topo.parent[j]) {
            (Some(c), _) => c,
            (None, Some(p)) if below_hub(p) => {
                let pc = result[p];
                SegmentOf {
                    class: pc.class,
                    girdle: pc.girdle || matches!(pc.class, Some((Trunk, _))),
                }
            }
            _ => SegmentOf::default(),
        };
    }
    result
}

/// The joints on a human's long bones, landmarks included: each leg's chain from the hip to the
/// ankle and each arm's from the shoulder to the wrist, in file order. A joint whose segment is
/// a thigh, shank, upper arm or forearm but which is not among them branches off a long bone
/// (`pipeline::anatomy::segments_of`: a twist or deformation bone, no body part).
pub fn on_long_bones(topo: &Topology, human: &Human) -> Vec<usize> {
    let mut on = vec![];
    for l in &human.legs {
        on.push(l.hip);
        on.extend(topo.chain(l.hip, l.ankle).unwrap_or_default());
    }
    for a in human.spine.iter().flat_map(|s| s.arms.iter().flatten()) {
        on.push(a.shoulder);
        on.extend(topo.chain(a.shoulder, a.wrist).unwrap_or_default());
    }
    on.sort_unstable();
    on.dedup();
    on
}

/// The joints inside a human's long bones: strictly between the hip and the knee, the knee and
/// the ankle, the shoulder and the elbow, the elbow and the wrist, in file order. They carry no
/// segment of their own (a segment runs from one landmark to the next): a skinning rig's twist
/// helpers (MakeHuman's `upperleg02`, `lowerleg02`, `lowerarm02`, a `*Twist*` bone), which
/// `motion::twist` folds into the next joint when they only turn the limb about the bone.
pub fn inside_long_bones(topo: &Topology, human: &Human) -> Vec<usize> {
    let mut bones: Vec<(usize, usize)> = vec![];
    for l in &human.legs {
        bones.extend([(l.hip, l.knee), (l.knee, l.ankle)]);
    }
    for a in human.spine.iter().flat_map(|s| s.arms.iter().flatten()) {
        bones.extend([(a.shoulder, a.elbow), (a.elbow, a.wrist)]);
    }
    let mut inside: Vec<usize> = bones
        .iter()
        .filter_map(|&(top, end)| topo.chain(top, end))
        .flat_map(|chain| chain[..chain.len().saturating_sub(1)].to_vec())
        .collect();
    inside.sort_unstable();
    inside.dedup();
    inside
}
