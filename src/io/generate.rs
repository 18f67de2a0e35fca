//! Takes made by the project itself: a parametric walk on a standard 21-joint skeleton.
//!
//! The demo take in `data/` is generated here (`articula generate walk`), never copied from a
//! capture. Joint angles are smooth periodic curves shaped like the normative sagittal gait
//! curves of Winter (*Biomechanics and Motor Control of Human Movement*, 4th ed., 2009, ch. 4):
//! hip flexion about +30° at heel strike and −10° at 50 % of the cycle, knee flexion peaks of
//! about 15° in loading response and 60° in swing, ankle plantarflexion of about 20° at
//! toe-off. The pelvis bobs and yaws, the arms swing against the legs, and the root height is
//! set every frame so that the lowest foot point touches the floor (y = 0).
//!
//! Output: Y-up, centimetres, facing +Z, root channels
//! `Xposition Yposition Zposition Zrotation Xrotation Yrotation`, other joints
//! `Zrotation Xrotation Yrotation`, degrees (the Daz/Poser layout).

use crate::io::bvh::{Bvh, BvhJoint, Channel};
use nalgebra::{Matrix3, Rotation3, Vector3};
use std::f64::consts::PI;

/// Parameters of a generated walk.
#[derive(Debug, Clone, PartialEq)]
pub struct WalkParams {
    /// Frames per second.
    pub fps: f64,
    /// Length of the take (s).
    pub duration_s: f64,
    /// Gait cycle (stride) period (s).
    pub cycle_s: f64,
    /// Scale of the skeleton relative to the 1.72 m default.
    pub scale: f64,
}

impl Default for WalkParams {
    fn default() -> Self {
        Self {
            fps: 120.0,
            duration_s: 4.0,
            cycle_s: 1.1,
            scale: 1.0,
        }
    }
}

/// (name, parent name, offset in cm). Rest pose: standing, arms down, facing +Z, Y up.
const SKELETON: &[(&str, &str, [f64; 3])] = &[
    ("Hips", "", [0.0, 0.0, 0.0]),
    ("Spine", "Hips", [0.0, 10.0, 0.0]),
    ("Spine1", "Spine", [0.0, 15.0, 0.0]),
    ("Neck", "Spine1", [0.0, 20.0, 0.0]),
    ("Head", "Neck", [0.0, 10.0, 0.0]),
    ("LeftShoulder", "Spine1", [3.0, 17.0, 0.0]),
    ("LeftArm", "LeftShoulder", [15.0, 0.0, 0.0]),
    ("LeftForeArm", "LeftArm", [0.0, -29.0, 0.0]),
    ("LeftHand", "LeftForeArm", [0.0, -26.0, 0.0]),
    ("RightShoulder", "Spine1", [-3.0, 17.0, 0.0]),
    ("RightArm", "RightShoulder", [-15.0, 0.0, 0.0]),
    ("RightForeArm", "RightArm", [0.0, -29.0, 0.0]),
    ("RightHand", "RightForeArm", [0.0, -26.0, 0.0]),
    ("LeftUpLeg", "Hips", [9.0, -5.0, 0.0]),
    ("LeftLeg", "LeftUpLeg", [0.0, -43.0, 0.0]),
    ("LeftFoot", "LeftLeg", [0.0, -43.0, 0.0]),
    ("LeftToeBase", "LeftFoot", [0.0, -6.0, 13.0]),
    ("RightUpLeg", "Hips", [-9.0, -5.0, 0.0]),
    ("RightLeg", "RightUpLeg", [0.0, -43.0, 0.0]),
    ("RightFoot", "RightLeg", [0.0, -43.0, 0.0]),
    ("RightToeBase", "RightFoot", [0.0, -6.0, 13.0]),
];

/// End Sites: (joint, offset in cm).
const END_SITES: &[(&str, [f64; 3])] = &[
    ("Head", [0.0, 18.0, 0.0]),
    ("LeftHand", [0.0, -18.0, 0.0]),
    ("RightHand", [0.0, -18.0, 0.0]),
    ("LeftToeBase", [0.0, 0.0, 6.0]),
    ("RightToeBase", [0.0, 0.0, 6.0]),
];

/// A periodic bump of height 1 centred at phase `c` with width `w` (phase units).
fn bump(phase: f64, c: f64, w: f64) -> f64 {
    let d = (phase - c + 0.5).rem_euclid(1.0) - 0.5;
    (-0.5 * (d / w).powi(2)).exp()
}

/// Sagittal angles (deg, anatomical sign: flexion positive) of one leg at gait phase `p`.
fn leg_angles(p: f64) -> (f64, f64, f64) {
    let hip = 10.0 + 20.0 * (2.0 * PI * p).cos();
    let knee = 4.0 + 14.0 * bump(p, 0.14, 0.06) + 58.0 * bump(p, 0.72, 0.1);
    let ankle_dorsi = -6.0 * bump(p, 0.07, 0.04) + 10.0 * bump(p, 0.42, 0.1)
        - 22.0 * bump(p, 0.63, 0.05)
        + 3.0 * bump(p, 0.85, 0.08);
    (hip, knee, ankle_dorsi)
}

/// Rotation of the `Zrotation Xrotation Yrotation` channel layout (degrees).
fn rot_zxy(z: f64, x: f64, y: f64) -> Matrix3<f64> {
    let r = |axis: Vector3<f64>, deg: f64| {
        Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), deg.to_radians())
            .into_inner()
    };
    r(Vector3::z(), z) * r(Vector3::x(), x) * r(Vector3::y(), y)
}

/// The channel values of one frame (before the root position is fixed), as
/// `[(z, x, y)]` per joint in skeleton order, plus the root yaw/roll.
fn pose(t: f64, cycle: f64) -> Vec<[f64; 3]> {
    let p = (t / cycle).rem_euclid(1.0);
    let q = (p + 0.5).rem_euclid(1.0);
    let (lh, lk, la) = leg_angles(p);
    let (rh, rk, ra) = leg_angles(q);
    let w = 2.0 * PI * p;
    let mut out = vec![[0.0; 3]; SKELETON.len()];
    let set = |out: &mut Vec<[f64; 3]>, name: &str, z: f64, x: f64, y: f64| {
        let i = SKELETON.iter().position(|s| s.0 == name).unwrap_or(0);
        out[i] = [z, x, y];
    };
    // pelvis: obliquity (roll about Z), small yaw (about Y) with the stride
    set(&mut out, "Hips", 3.0 * (2.0 * w).sin(), 2.0, 4.0 * w.cos());
    set(
        &mut out,
        "Spine",
        -1.5 * (2.0 * w).sin(),
        1.0,
        -2.5 * w.cos(),
    );
    set(&mut out, "Spine1", 0.0, 1.0, -1.5 * w.cos());
    set(&mut out, "Neck", 0.0, -2.0, 0.0);
    set(&mut out, "Head", 0.0, -1.0, 0.0);
    // hip flexion moves the thigh forward (+Z): a negative rotation about X
    set(&mut out, "LeftUpLeg", 0.0, -lh, 0.0);
    set(&mut out, "RightUpLeg", 0.0, -rh, 0.0);
    // knee flexion moves the shank backward: positive about X
    set(&mut out, "LeftLeg", 0.0, lk, 0.0);
    set(&mut out, "RightLeg", 0.0, rk, 0.0);
    // dorsiflexion lifts the toes: negative about X
    set(&mut out, "LeftFoot", 0.0, -la, 0.0);
    set(&mut out, "RightFoot", 0.0, -ra, 0.0);
    // arms swing against the legs of the same side; elbows slightly flexed
    set(&mut out, "LeftShoulder", -2.0, 0.0, 0.0);
    set(&mut out, "RightShoulder", 2.0, 0.0, 0.0);
    set(&mut out, "LeftArm", 6.0, 16.0 * w.cos(), 0.0);
    set(&mut out, "RightArm", -6.0, -16.0 * w.cos(), 0.0);
    set(&mut out, "LeftForeArm", 0.0, -(18.0 + 8.0 * w.cos()), 0.0);
    set(&mut out, "RightForeArm", 0.0, -(18.0 - 8.0 * w.cos()), 0.0);
    out
}

/// World positions (cm) of the foot contact points (heels, toe bases and toe tips) with the
/// root at the origin.
fn foot_points(angles: &[[f64; 3]], scale: f64) -> Vec<Vector3<f64>> {
    let n = SKELETON.len();
    let mut rot = vec![Matrix3::identity(); n];
    let mut pos = vec![Vector3::zeros(); n];
    for (i, (_, parent, off)) in SKELETON.iter().enumerate() {
        let r = rot_zxy(angles[i][0], angles[i][1], angles[i][2]);
        if let Some(p) = SKELETON.iter().position(|s| s.0 == *parent) {
            pos[i] = pos[p] + rot[p] * Vector3::from(*off) * scale;
            rot[i] = rot[p] * r;
        } else {
            rot[i] = r;
        }
    }
    let mut pts = vec![];
    for foot in ["LeftFoot", "RightFoot"] {
        let i = SKELETON.iter().position(|s| s.0 == foot).unwrap_or(0);
        // heel: 8 cm below and 5 cm behind the ankle
        pts.push(pos[i] + rot[i] * Vector3::new(0.0, -8.0, -5.0) * scale);
        let toe = i + 1;
        pts.push(pos[toe] + rot[toe] * Vector3::new(0.0, -2.0, 0.0) * scale);
        pts.push(pos[toe] + rot[toe] * Vector3::new(0.0, -2.0, 6.0) * scale);
    }
    pts
}

/// A walk on the standard skeleton: see the module doc.
pub fn walk(params: &WalkParams) -> Bvh {
    let s = params.scale;
    let dt = 1.0 / params.fps;
    let frames = ((params.duration_s * params.fps).round() as usize).max(1);

    // skeleton
    let mut joints: Vec<BvhJoint> = vec![];
    let mut first_channel = 0;
    for (i, (name, parent, off)) in SKELETON.iter().enumerate() {
        let parent = SKELETON.iter().position(|s| s.0 == *parent);
        let channels = if i == 0 {
            vec![
                Channel::Xposition,
                Channel::Yposition,
                Channel::Zposition,
                Channel::Zrotation,
                Channel::Xrotation,
                Channel::Yrotation,
            ]
        } else {
            vec![Channel::Zrotation, Channel::Xrotation, Channel::Yrotation]
        };
        let end_sites = END_SITES
            .iter()
            .filter(|e| e.0 == *name)
            .map(|e| Vector3::from(e.1) * s)
            .collect();
        let n = channels.len();
        joints.push(BvhJoint {
            name: name.to_string(),
            parent,
            offset: Vector3::from(*off) * s,
            channels,
            first_channel,
            end_sites,
            line: 0,
        });
        first_channel += n;
    }

    // forward speed: the stance foot's backward sweep relative to the hips over stance
    let stance = 0.6;
    let rel = |t: f64| foot_points(&pose(t, params.cycle_s), s)[0].z;
    let speed = (rel(0.0) - rel(stance * params.cycle_s)) / (stance * params.cycle_s);

    // motion: root height puts the lowest foot point on the floor
    let mut motion = Vec::with_capacity(frames * first_channel);
    for k in 0..frames {
        let t = k as f64 * dt;
        let angles = pose(t, params.cycle_s);
        let lowest = foot_points(&angles, s)
            .iter()
            .map(|p| p.y)
            .fold(f64::INFINITY, f64::min);
        motion.extend_from_slice(&[0.0, -lowest, speed * t]);
        for a in &angles {
            motion.extend_from_slice(a);
        }
    }
    Bvh {
        joints,
        frame_time: dt,
        frames,
        channel_count: first_channel,
        motion,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lowest_foot_point_touches_the_floor_every_frame() {
        let take = walk(&WalkParams::default());
        for k in 0..take.frames {
            let f = take.frame(k);
            let angles: Vec<[f64; 3]> = (0..SKELETON.len())
                .map(|j| {
                    let c = take.joints[j].first_channel + if j == 0 { 3 } else { 0 };
                    [f[c], f[c + 1], f[c + 2]]
                })
                .collect();
            let lowest = foot_points(&angles, 1.0)
                .iter()
                .map(|p| p.y + f[1])
                .fold(f64::INFINITY, f64::min);
            assert!(lowest.abs() < 1e-9, "frame {k}: {lowest}");
        }
    }

    #[test]
    fn walks_forward_at_a_plausible_speed() {
        let take = walk(&WalkParams::default());
        let last = take.frame(take.frames - 1);
        let speed_m_s = last[2] / 100.0 / ((take.frames - 1) as f64 * take.frame_time);
        assert!((0.8..1.8).contains(&speed_m_s), "{speed_m_s} m/s");
        // the hips stay at a standing height (cm)
        let h = take.frame(0)[1];
        assert!((85.0..105.0).contains(&h), "{h}");
    }
}
