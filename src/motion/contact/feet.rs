//! Which bodies of a model are the feet — by name (across naming schemes), by the skeleton's
//! shape (`model::skeleton`), or the limb ends of a skeleton that is not a human's — and their
//! ankle, heel and toe points.

use crate::io::bvh::Bvh;
use crate::model::Model;
use crate::model::bvh::BvhMap;
use nalgebra::Vector3;

/// Left or right.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    Left,
    Right,
    /// A limb end of a skeleton that is not a human's (a quadruped's foot, a crab's claw tip).
    Limb,
}

impl Side {
    /// `left` / `right`, the foot names of output columns.
    pub fn name(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
            Side::Limb => "limb",
        }
    }
}

/// One foot of a model: the bodies whose points are its heel and toe.
#[derive(Debug, Clone, PartialEq)]
pub struct Foot {
    /// `left` or `right` (output column names: `grf:left:x`, …).
    pub name: String,
    pub side: Side,
    /// The skeleton's name of the ankle joint (`LeftFoot`, `lFoot`, `Foot_L`, `foot.L`, …).
    pub joint: String,
    /// The body that carries the ankle joint's frame: ground reactions act on it. In the euler
    /// model, the body of the joint's last rotation channel.
    pub ankle_body: usize,
    /// The ankle joint's origin in the frame of `ankle_body` (m); zero unless the joint was
    /// welded into its parent.
    pub ankle_point: Vector3<f64>,
    /// The heel point in the frame of `ankle_body` (m): the ankle moved down, in the rest pose,
    /// to the height of the toe point — the back of the sole, which touches first at heel
    /// strike while the ankle itself is still rising and falling with the foot's pitch.
    pub heel_point: Vector3<f64>,
    /// The body that carries the toe point.
    pub toe_body: usize,
    /// The toe point in the frame of `toe_body` (m): the toe joint's origin (the ball of the
    /// foot), or without a toe joint the foot's End Site, the far end of the foot's drawing
    /// shape, or the ankle itself.
    pub toe_point: Vector3<f64>,
}

impl Foot {
    /// World position of the heel point (m), from world body poses (`ws.o_x_i`).
    pub fn heel(&self, o_x_i: &[crate::spatial::SpatialTransform]) -> Vector3<f64> {
        o_x_i[self.ankle_body].transform_point(&self.heel_point)
    }
    /// World position of the ankle joint (m), from world body poses (`ws.o_x_i`).
    pub fn ankle(&self, o_x_i: &[crate::spatial::SpatialTransform]) -> Vector3<f64> {
        o_x_i[self.ankle_body].transform_point(&self.ankle_point)
    }
    /// World position of the toe point (m), from world body poses (`ws.o_x_i`).
    pub fn toe(&self, o_x_i: &[crate::spatial::SpatialTransform]) -> Vector3<f64> {
        o_x_i[self.toe_body].transform_point(&self.toe_point)
    }
}

/// The role a skeleton joint name plays for contact.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Role {
    /// `foot`, `ankle`.
    Foot,
    /// `ankle` in skeletons that also have a `foot` (SMPL: `L_Ankle`, `L_Foot` = the toes).
    Ankle,
    /// `toe`, `toes`, `toebase`, `toe1-1`, …
    Toe,
}

/// The skeleton joint a body stands for: its name without the euler model's channel suffix
/// (`LeftFoot.Zrotation` → `LeftFoot`, `foot.L.Xrotation` → `foot.L`).
pub fn skeleton_joint(body_name: &str) -> &str {
    const CHANNELS: [&str; 6] = [
        ".Xrotation",
        ".Yrotation",
        ".Zrotation",
        ".Xposition",
        ".Yposition",
        ".Zposition",
    ];
    CHANNELS
        .iter()
        .find_map(|c| body_name.strip_suffix(c))
        .unwrap_or(body_name)
}

/// Side and role of a skeleton joint name, across the naming schemes of common skeletons:
/// CMU/Mixamo/Motionbuilder `LeftFoot` `LeftToeBase` (with or without a `mixamorig:`
/// namespace), Daz/Poser `lFoot` `lToe`, Bandai-Namco `Foot_L` `Toes_L`, MakeHuman `foot.L`
/// `toe1-1.L`, SMPL `L_Ankle` `L_Foot`, 3ds Max Biped `Bip01_L_Foot` `Bip01 L Toe0`, MakeHuman's
/// CMU rig `lfoot`, and `LFoot`/`RFoot` styles.
fn classify(name: &str) -> Option<(Side, Role)> {
    let name = name.rsplit(':').next().unwrap_or(name);
    let lower = name.to_lowercase();
    let chars: Vec<char> = name.chars().collect();
    let (side, base) = if let Some(rest) = lower.strip_prefix("left") {
        (Side::Left, rest.to_string())
    } else if let Some(rest) = lower.strip_prefix("right") {
        (Side::Right, rest.to_string())
    } else if let Some(rest) = lower.strip_suffix("left") {
        (Side::Left, rest.to_string())
    } else if let Some(rest) = lower.strip_suffix("right") {
        (Side::Right, rest.to_string())
    } else if ["_l", ".l", "-l", " l"].iter().any(|s| lower.ends_with(s)) {
        (Side::Left, lower[..lower.len() - 2].to_string())
    } else if ["_r", ".r", "-r", " r"].iter().any(|s| lower.ends_with(s)) {
        (Side::Right, lower[..lower.len() - 2].to_string())
    } else if let Some(i) = lower.find("_l_").or_else(|| lower.find(" l ")) {
        (Side::Left, lower[i + 3..].to_string())
    } else if let Some(i) = lower.find("_r_").or_else(|| lower.find(" r ")) {
        (Side::Right, lower[i + 3..].to_string())
    } else if matches!(chars.first(), Some('l' | 'r'))
        && (["foot", "ankle"].contains(&&lower[1..]) || lower[1..].starts_with("toe"))
    {
        let side = if chars[0] == 'l' {
            Side::Left
        } else {
            Side::Right
        };
        (side, lower[1..].to_string())
    } else if chars.len() > 1
        && (chars[1].is_uppercase() || chars[1] == '_')
        && matches!(chars[0], 'l' | 'L' | 'r' | 'R')
    {
        let side = if matches!(chars[0], 'l' | 'L') {
            Side::Left
        } else {
            Side::Right
        };
        (side, lower[1..].to_string())
    } else {
        return None;
    };
    let base = base.trim_matches(|c| matches!(c, '_' | '.' | '-' | ' '));
    let role = if base == "foot" {
        Role::Foot
    } else if base == "ankle" {
        Role::Ankle
    } else if base.starts_with("toe") {
        Role::Toe
    } else {
        return None;
    };
    Some((side, role))
}

/// The feet of a model, found by joint names (see [`classify`] for the schemes), left first.
/// Empty when the model has no recognisable feet (an arm, a robot).
///
/// For each side: the ankle is the `ankle` joint if there is one (SMPL, whose `foot` is then the
/// toe), else the `foot` joint; the toe is the first toe joint below the ankle in body order
/// (MakeHuman's `toe1-1`, the big toe). Without a toe joint the toe point is the far end of
/// the foot body's drawing shape along its long axis, or the ankle itself.
pub fn foot_bodies(model: &Model) -> Vec<Foot> {
    // the frame body of each named skeleton joint: the last body carrying its name
    let n = model.nbodies();
    let mut joints: Vec<(String, usize, Side, Role)> = vec![];
    for i in 1..n {
        let name = skeleton_joint(&model.body_names[i]);
        let Some((side, role)) = classify(name) else {
            continue;
        };
        match joints.iter_mut().find(|j| j.0 == name) {
            Some(j) => j.1 = i,
            None => joints.push((name.to_string(), i, side, role)),
        }
    }
    let descends = |mut i: usize, ancestor: usize| {
        while i > ancestor {
            i = model.parent[i];
        }
        i == ancestor
    };
    let mut feet = vec![];
    for side in [Side::Left, Side::Right] {
        let of = |role: Role| joints.iter().find(|j| j.2 == side && j.3 == role);
        let has_ankle = of(Role::Ankle).is_some();
        let Some(ankle) = of(Role::Ankle).or_else(|| of(Role::Foot)) else {
            continue;
        };
        let toe = joints
            .iter()
            .filter(|j| j.2 == side && (j.3 == Role::Toe || (has_ankle && j.3 == Role::Foot)))
            .filter(|j| descends(j.1, ankle.1))
            .min_by_key(|j| j.1);
        let (toe_body, toe_point) = match toe {
            Some(t) => (t.1, Vector3::zeros()),
            None => (ankle.1, shape_tip(model, ankle.1)),
        };
        feet.push(Foot {
            name: side.name().to_string(),
            side,
            joint: ankle.0.clone(),
            ankle_body: ankle.1,
            ankle_point: Vector3::zeros(),
            heel_point: Vector3::zeros(),
            toe_body,
            toe_point,
        });
    }
    set_heel_points(model, &mut feet);
    feet
}

/// The feet of a model built from a BVH skeleton ([`build_bvh_model`]), found by the BVH joint
/// names (see [`classify`]) and placed through the channel map, so that welded joints and End
/// Sites are handled: the heel point is the ankle joint's origin, the toe point the first toe
/// joint below it, else the ankle joint's End Site, else the far end of its drawing shape.
///
/// [`build_bvh_model`]: crate::model::bvh::build_bvh_model
pub fn feet_of_bvh(bvh: &Bvh, map: &BvhMap, model: &Model) -> Vec<Foot> {
    let roles: Vec<Option<(Side, Role)>> = bvh.joints.iter().map(|j| classify(&j.name)).collect();
    let descends = |mut j: usize, ancestor: usize| loop {
        if j == ancestor {
            return true;
        }
        match bvh.joints[j].parent {
            Some(p) => j = p,
            None => return false,
        }
    };
    let mut feet = vec![];
    for side in [Side::Left, Side::Right] {
        let of = |role: Role| roles.iter().position(|r| *r == Some((side, role)));
        let has_ankle = of(Role::Ankle).is_some();
        let Some(ankle) = of(Role::Ankle).or_else(|| of(Role::Foot)) else {
            continue;
        };
        let toe = (0..bvh.joints.len()).find(|&j| {
            j != ankle
                && matches!(roles[j], Some((s, r)) if s == side
                    && (r == Role::Toe || (has_ankle && r == Role::Foot)))
                && descends(j, ankle)
        });
        feet.push((side, ankle, toe));
    }
    feet_at(bvh, map, model, &feet)
}

/// The feet whose ankle and toe joints are known (`(side, ankle, toe)`; without a toe joint
/// the toe point is the ankle's End Site, or the far end of its drawing shape), each with its
/// heel point placed as [`feet_of_bvh`] places it.
pub fn feet_at(
    bvh: &Bvh,
    map: &BvhMap,
    model: &Model,
    joints: &[(Side, usize, Option<usize>)],
) -> Vec<Foot> {
    let mut feet: Vec<Foot> = joints
        .iter()
        .map(|&(side, ankle, toe)| {
            let a = &map.joints[ankle];
            let (toe_body, toe_point) = match (toe, bvh.joints[ankle].end_sites.first()) {
                (Some(t), _) => (map.joints[t].body, map.joints[t].frame.trans),
                (None, Some(end)) => (a.body, a.frame.transform_point(&(end * map.scale_to_m))),
                (None, None) => (a.body, shape_tip(model, a.body)),
            };
            Foot {
                name: side.name().to_string(),
                side,
                joint: bvh.joints[ankle].name.clone(),
                ankle_body: a.body,
                ankle_point: a.frame.trans,
                heel_point: a.frame.trans,
                toe_body,
                toe_point,
            }
        })
        .collect();
    set_heel_points(model, &mut feet);
    feet
}

/// Every limb end of a skeleton, as a foot candidate for a skeleton that is not a human's (a
/// quadruped, a crab): each joint without child joints, named by its joint, its ankle the
/// joint's origin and its toe the first End Site (else the joint itself). Which of them reach
/// the floor is for the caller to say from the motion (`pipeline` keeps those that come down
/// to the lowest level). Each foot's heel point is placed as [`feet_of_bvh`] places it.
pub fn limb_ends(bvh: &Bvh, map: &BvhMap, model: &Model) -> Vec<Foot> {
    let mut feet: Vec<Foot> = (0..bvh.joints.len())
        .filter(|&j| !bvh.joints.iter().any(|c| c.parent == Some(j)))
        .map(|j| {
            let (joint, m) = (&bvh.joints[j], &map.joints[j]);
            let toe = joint
                .end_sites
                .first()
                .map_or(Vector3::zeros(), |e| e * map.scale_to_m);
            Foot {
                name: joint.name.clone(),
                side: Side::Limb,
                joint: joint.name.clone(),
                ankle_body: m.body,
                ankle_point: m.frame.trans,
                heel_point: m.frame.trans,
                toe_body: m.body,
                toe_point: m.frame.transform_point(&toe),
            }
        })
        .collect();
    set_heel_points(model, &mut feet);
    feet
}

/// Fits the feet's heel points to a take, for skeletons whose rest pose is not standing (some
/// rest poses lay the legs along a horizontal axis): for each foot, over the frames where its
/// ankle is lowest (its lowest 10 %, the foot flat on the floor), the mean downward direction
/// in the ankle body's frame; and for all feet the smallest mean height of an ankle above the
/// `floor` over those frames (the same for both feet, so that a foot that never comes down
/// does not get a heel reaching for the floor). `poses[foot]` are the world poses of that
/// foot's `ankle_body`, one per frame. A foot without poses keeps its heel point.
pub fn fit_heel_points(
    feet: &mut [Foot],
    poses: &[Vec<crate::spatial::SpatialTransform>],
    up: usize,
    floor: f64,
) {
    let down = -Vector3::ith(up, 1.0);
    let mut drop = f64::INFINITY;
    let mut dirs = vec![None; feet.len()];
    for ((foot, poses), dir) in feet.iter().zip(poses).zip(&mut dirs) {
        let heights: Vec<f64> = poses
            .iter()
            .map(|x| x.transform_point(&foot.ankle_point)[up])
            .collect();
        if heights.is_empty() {
            continue;
        }
        let mut order = heights.clone();
        let tenth = order.len() / 10;
        let cut = *order.select_nth_unstable_by(tenth, f64::total_cmp).1;
        let (mut sum, mut height, mut count) = (Vector3::zeros(), 0.0, 0.0);
        for (x, h) in poses.iter().zip(&heights).filter(|(_, h)| **h <= cut) {
            sum += x.rot.tr_mul(&down);
            height += h;
            count += 1.0;
        }
        *dir = sum.try_normalize(1e-9);
        drop = drop.min((height / count - floor).max(0.0));
    }
    for (foot, dir) in feet.iter_mut().zip(dirs) {
        if let Some(dir) = dir {
            foot.heel_point = foot.ankle_point + dir * drop;
        }
    }
}

/// Places each foot's heel point under its ankle: in the rest pose (q = neutral, every joint
/// transform the identity), the ankle moved along gravity down to the height of the toe point.
fn set_heel_points(model: &Model, feet: &mut [Foot]) {
    let Some(down) = model.gravity.try_normalize(1e-12) else {
        return;
    };
    let mut rest = vec![crate::spatial::SpatialTransform::IDENTITY; model.nbodies()];
    for i in 1..model.nbodies() {
        rest[i] = rest[model.parent[i]].compose(&model.placement[i]);
    }
    for f in feet {
        let (ankle, toe) = (f.ankle(&rest), f.toe(&rest));
        let drop = (toe - ankle).dot(&down).max(0.0);
        f.heel_point = f.ankle_point + rest[f.ankle_body].rot.tr_mul(&(down * drop));
    }
}

/// The far end of body `i`'s drawing shape along the shape's long (local z) axis, body frame;
/// the body origin when it has no shape.
fn shape_tip(model: &Model, i: usize) -> Vector3<f64> {
    match &model.shapes[i] {
        Some(s) => {
            let axis = s.rot * Vector3::z() * s.size.z;
            let (a, b) = (s.center + axis, s.center - axis);
            if a.norm() >= b.norm() { a } else { b }
        }
        None => Vector3::zeros(),
    }
}
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn side_and_role_across_naming_schemes() {
        use Role::*;
        use Side::*;
        let cases = [
            ("LeftFoot", Some((Left, Foot))),
            ("RightToeBase", Some((Right, Toe))),
            ("mixamorig:LeftFoot", Some((Left, Foot))),
            ("mixamorig:RightToe_End", Some((Right, Toe))),
            ("lFoot", Some((Left, Foot))),
            ("rToe", Some((Right, Toe))),
            ("Foot_L", Some((Left, Foot))),
            ("Toes_R", Some((Right, Toe))),
            ("foot.L", Some((Left, Foot))),
            ("toe1-1.R", Some((Right, Toe))),
            ("L_Ankle", Some((Left, Ankle))),
            ("R_Foot", Some((Right, Foot))),
            ("LFoot", Some((Left, Foot))),
            ("lfoot", Some((Left, Foot))),
            ("rfoot", Some((Right, Foot))),
            ("Bip01_L_Foot", Some((Left, Foot))),
            ("Bip01 R Toe0", Some((Right, Toe))),
            ("Bip01_R_Calf", None),
            ("lhip", None),
            ("LeftLeg", None),
            ("LHipJoint", None),
            ("Hips", None),
            ("lShin", None),
            ("lowerleg01.L", None),
            ("Root", None),
        ];
        for (name, want) in cases {
            assert_eq!(classify(name), want, "{name}");
        }
    }

    #[test]
    fn channel_suffix_is_stripped_but_dots_in_names_stay() {
        assert_eq!(skeleton_joint("LeftFoot.Zrotation"), "LeftFoot");
        assert_eq!(skeleton_joint("foot.L.Xrotation"), "foot.L");
        assert_eq!(skeleton_joint("foot.L"), "foot.L");
    }
}
