//! Takes made by the project itself: a parametric walk on a standard 21-joint skeleton.
//!
//! The demo take in `data/` is generated here (`articula generate walk`), never copied from a
//! capture. It is a planted-foot gait built from the feet up, as gait is described by Perry &
//! Burnfield (*Gait Analysis: Normal and Pathological Function*, 2nd ed., 2010, ch. 2–3: the
//! heel, ankle and forefoot rockers) and Winter (*Biomechanics and Motor Control of Human
//! Movement*, 4th ed., 2009, ch. 4: timing and normative curves):
//!
//! - timing: stance 60 % and swing 40 % of the cycle for each foot, the other foot striking at
//!   50 %, hence two double supports of 10 % (heel strike to opposite toe-off);
//! - each stance rolls the foot over the floor without sliding: from heel strike (the foot
//!   pitched 15° toes-up) it turns about the heel's contact point until flat (heel rocker, to
//!   8 % of the cycle), stays still (ankle rocker, to 35 %), then turns about the ball of the
//!   foot until toe-off at 60 % with the heel up, the foot 40° toes-down (forefoot rocker);
//!   angles follow the C² ramp `10u³ − 15u⁴ + 6u⁵`, so each rocker starts and ends at rest;
//! - the swing carries the foot from its toe-off pose to the next heel strike one stride ahead
//!   on the same C² ramp, clearing the floor by a bump of 6 cm at the ankle;
//! - the pelvis moves forward at constant speed (1.1 m/s), 2.5 cm up and down (highest at mid single
//!   support, lowest in double support: two cycles per stride) and 2 cm side to side over the
//!   stance foot; it tilts, rolls and yaws a few degrees; its mean height is the highest that
//!   keeps the knee flexed at least 9° over the whole cycle;
//! - the legs reach the feet by analytic inverse kinematics (hip flexion and abduction, knee
//!   flexion from the hip–ankle distance by the law of cosines), the ankle takes whatever
//!   rotation puts the foot in its pose; the arms swing against the legs.
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

/// The C² ramp `10u³ − 15u⁴ + 6u⁵` (0 → 1 with zero slope and curvature at both ends),
/// `u` clamped to [0, 1].
fn ramp(u: f64) -> f64 {
    let u = u.clamp(0.0, 1.0);
    u * u * u * (10.0 - 15.0 * u + 6.0 * u * u)
}

/// Gait events as fractions of the cycle, from heel strike (0) of one foot.
const FOOT_FLAT: f64 = 0.08;
const HEEL_OFF: f64 = 0.35;
const TOE_OFF: f64 = 0.6;
/// Foot pitch (deg, toes up positive) at heel strike and at toe-off.
const PITCH_STRIKE: f64 = 15.0;
const PITCH_TOE_OFF: f64 = -40.0;
/// The largest hip–ankle distance over the thigh + shank length (the knee flexed 9° at most
/// extension: Winter 2009's stance knee stays at 5–20°).
const MAX_REACH: f64 = 0.997;
/// Swing clearance bump of the ankle (cm, unscaled).
const CLEARANCE: f64 = 6.0;

/// Points of the foot in the ankle's frame when the foot is flat (cm, unscaled): the heel and
/// the ball contact points of the sole, 8 cm below the ankle (the toe joint is 6 cm below and
/// 13 cm ahead: the ball contact is under it).
const HEEL: [f64; 3] = [0.0, -8.0, -5.0];
const BALL: [f64; 3] = [0.0, -8.0, 13.0];

fn rot_x(deg: f64) -> Matrix3<f64> {
    Rotation3::from_axis_angle(&Vector3::x_axis(), deg.to_radians()).into_inner()
}

/// World rotation of a foot pitched `pitch` degrees toes-up (heading +Z): dorsiflexion lifts
/// the toes, a negative rotation about X.
fn foot_rot(pitch: f64) -> Matrix3<f64> {
    rot_x(-pitch)
}

/// One foot's pose over its own cycle: ankle position (cm, scaled) and pitch (deg) at phase
/// `p` ∈ [0, 1) after its heel strike, the heel striking at `strike` (world, floor y = 0).
/// The heel strikes of successive cycles are `stride` apart along +Z.
fn foot_pose(p: f64, strike: Vector3<f64>, stride: f64, scale: f64) -> (Vector3<f64>, f64) {
    let heel = Vector3::from(HEEL) * scale;
    let ball = Vector3::from(BALL) * scale;
    // the ankle of a foot pitched `a` whose point `pt` (ankle frame) sits at `at`
    let pivot = |at: Vector3<f64>, pt: Vector3<f64>, a: f64| at - foot_rot(a) * pt;
    // ball contact while flat
    let flat_ball = strike - heel + ball;
    if p < FOOT_FLAT {
        let a = PITCH_STRIKE * (1.0 - ramp(p / FOOT_FLAT));
        (pivot(strike, heel, a), a)
    } else if p < HEEL_OFF {
        (pivot(strike, heel, 0.0), 0.0)
    } else if p < TOE_OFF {
        let a = PITCH_TOE_OFF * ramp((p - HEEL_OFF) / (TOE_OFF - HEEL_OFF));
        (pivot(flat_ball, ball, a), a)
    } else {
        // swing: from the toe-off pose to the next heel strike
        let u = (p - TOE_OFF) / (1.0 - TOE_OFF);
        let r = ramp(u);
        let from = pivot(flat_ball, ball, PITCH_TOE_OFF);
        let next = strike + Vector3::new(0.0, 0.0, stride);
        let to = pivot(next, heel, PITCH_STRIKE);
        let mut ankle = from + (to - from) * r;
        ankle.y += CLEARANCE * scale * (PI * u).sin().powi(2);
        (ankle, PITCH_TOE_OFF + (PITCH_STRIKE - PITCH_TOE_OFF) * r)
    }
}

/// Rotation of the `Zrotation Xrotation Yrotation` channel layout (degrees).
fn rot_zxy(z: f64, x: f64, y: f64) -> Matrix3<f64> {
    let r = |axis: Vector3<f64>, deg: f64| {
        Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), deg.to_radians())
            .into_inner()
    };
    r(Vector3::z(), z) * r(Vector3::x(), x) * r(Vector3::y(), y)
}

/// The `(z, x, y)` angles (deg) of `R = Rz(z)·Rx(x)·Ry(y)` (|x| < 90°).
fn zxy_of(r: &Matrix3<f64>) -> [f64; 3] {
    let x = r[(2, 1)].clamp(-1.0, 1.0).asin();
    let z = (-r[(0, 1)]).atan2(r[(1, 1)]);
    let y = (-r[(2, 0)]).atan2(r[(2, 2)]);
    [z.to_degrees(), x.to_degrees(), y.to_degrees()]
}

fn index(name: &str) -> usize {
    SKELETON.iter().position(|s| s.0 == name).unwrap_or(0)
}

/// Pelvis rotation and the upper body's channels at cycle phase `p` (of the left foot), as
/// `(z, x, y)` per joint in skeleton order; the legs are left at zero.
fn upper_body(p: f64) -> Vec<[f64; 3]> {
    let w = 2.0 * PI * p;
    let mut out = vec![[0.0; 3]; SKELETON.len()];
    let mut set = |name: &str, z: f64, x: f64, y: f64| out[index(name)] = [z, x, y];
    // pelvis: obliquity (roll about Z, the swing side drops), tilt, yaw with the stride
    set(
        "Hips",
        -3.0 * (w - 0.3 * 2.0 * PI).sin(),
        2.0,
        4.0 * w.cos(),
    );
    set(
        "Spine",
        1.5 * (w - 0.3 * 2.0 * PI).sin(),
        1.0,
        -2.5 * w.cos(),
    );
    set("Spine1", 0.0, 1.0, -1.5 * w.cos());
    set("Neck", 0.0, -2.0, 0.0);
    set("Head", 0.0, -1.0, 0.0);
    // arms swing against the legs of the same side; elbows slightly flexed
    set("LeftShoulder", -2.0, 0.0, 0.0);
    set("RightShoulder", 2.0, 0.0, 0.0);
    set("LeftArm", 6.0, 16.0 * w.cos(), 0.0);
    set("RightArm", -6.0, -16.0 * w.cos(), 0.0);
    set("LeftForeArm", 0.0, -(18.0 + 8.0 * w.cos()), 0.0);
    set("RightForeArm", 0.0, -(18.0 - 8.0 * w.cos()), 0.0);
    out
}

/// The gait of a walk: speed, stride, pelvis path and foot placement (cm, scaled).
struct Gait {
    cycle_s: f64,
    scale: f64,
    /// Forward speed (cm/s).
    speed: f64,
    /// Stride length (cm): one cycle's travel.
    stride: f64,
    /// Mean pelvis height (cm).
    height: f64,
}

impl Gait {
    fn phase(&self, t: f64) -> f64 {
        (t / self.cycle_s).rem_euclid(1.0)
    }

    /// Pelvis position at time `t`: forward at constant speed, above the midstance ankle,
    /// up at mid single support, over the stance foot.
    fn pelvis(&self, t: f64) -> Vector3<f64> {
        let p = t / self.cycle_s;
        let s = self.scale;
        // at left midstance (p = 0.3) the hips are 8 cm ahead of the left ankle, whose heel
        // struck at z = 0 (the ankle 5 cm ahead of the heel)
        let z = self.speed * t + (5.0 + 8.0) * s - self.speed * 0.3 * self.cycle_s;
        let y = self.height + 2.5 * s * (4.0 * PI * (p - 0.3)).cos();
        let x = 2.0 * s * (2.0 * PI * (p - 0.05)).sin();
        Vector3::new(x, y, z)
    }

    /// Ankle position and pitch of the left (`side` = 1) or right (−1) foot at time `t`.
    fn foot(&self, t: f64, side: f64) -> (Vector3<f64>, f64) {
        let s = self.scale;
        // the left heel strikes at t = 0 at z = 0, the right half a cycle later
        let shift = if side > 0.0 { 0.0 } else { 0.5 };
        let cycles = t / self.cycle_s - shift;
        let k = cycles.floor();
        let p = cycles - k;
        let strike = Vector3::new(side * 9.0 * s, 0.0, (k + shift) * self.stride);
        foot_pose(p, strike, self.stride, s)
    }

    /// Channel values `(z, x, y)` per joint at time `t`, and the leg reach used (hip–ankle
    /// distance over thigh + shank length, the largest of both legs).
    fn pose(&self, t: f64) -> (Vec<[f64; 3]>, f64) {
        let s = self.scale;
        let mut out = upper_body(self.phase(t));
        let h = out[0];
        let r_pelvis = rot_zxy(h[0], h[1], h[2]);
        let pelvis = self.pelvis(t);
        let mut reach: f64 = 0.0;
        for (side, up_leg, leg, foot) in [
            (1.0, "LeftUpLeg", "LeftLeg", "LeftFoot"),
            (-1.0, "RightUpLeg", "RightLeg", "RightFoot"),
        ] {
            let (ankle, pitch) = self.foot(t, side);
            let hip = pelvis + r_pelvis * Vector3::from(SKELETON[index(up_leg)].2) * s;
            let (l1, l2) = (
                -SKELETON[index(leg)].2[1] * s,
                -SKELETON[index(foot)].2[1] * s,
            );
            // the ankle in the pelvis frame, from the hip
            let target = r_pelvis.transpose() * (ankle - hip);
            let d = target.norm().min(0.999 * (l1 + l2));
            reach = reach.max(target.norm() / (l1 + l2));
            // knee flexion κ: d² = l1² + l2² + 2 l1 l2 cos κ
            let kappa = ((d * d - l1 * l1 - l2 * l2) / (2.0 * l1 * l2))
                .clamp(-1.0, 1.0)
                .acos();
            // hip abduction β about Z, then flexion α about X (the leg plane)
            let r = (target.x * target.x + target.y * target.y).sqrt();
            let beta = target.x.atan2(-target.y);
            let (vy, vz) = (-l1 - l2 * kappa.cos(), -l2 * kappa.sin());
            let alpha = (target.z.atan2(-r) - vz.atan2(vy) + PI).rem_euclid(2.0 * PI) - PI;
            let hip_rot = rot_zxy(beta.to_degrees(), alpha.to_degrees(), 0.0);
            let knee_rot = rot_zxy(0.0, kappa.to_degrees(), 0.0);
            out[index(up_leg)] = [beta.to_degrees(), alpha.to_degrees(), 0.0];
            out[index(leg)] = [0.0, kappa.to_degrees(), 0.0];
            // the ankle turns the foot into its world pose
            let shank = r_pelvis * hip_rot * knee_rot;
            out[index(foot)] = zxy_of(&(shank.transpose() * foot_rot(pitch)));
        }
        (out, reach)
    }
}

/// The gait of `params`: speed 1.1 m/s scaled with the skeleton, and the highest mean pelvis
/// height that keeps every hip–ankle distance within [`MAX_REACH`] of the leg length.
fn gait(params: &WalkParams) -> Gait {
    let s = params.scale;
    let speed = 110.0 * s;
    let mut g = Gait {
        cycle_s: params.cycle_s,
        scale: s,
        speed,
        stride: speed * params.cycle_s,
        height: 0.0,
    };
    let max_reach = |g: &Gait| {
        (0..200)
            .map(|k| g.pose(k as f64 * g.cycle_s / 200.0).1)
            .fold(0.0, f64::max)
    };
    // bisection on the mean height (cm): reach grows with it
    let (mut lo, mut hi) = (40.0 * s, 100.0 * s);
    for _ in 0..50 {
        g.height = 0.5 * (lo + hi);
        if max_reach(&g) > MAX_REACH {
            hi = g.height;
        } else {
            lo = g.height;
        }
    }
    g.height = lo;
    g
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

    // motion: the pelvis path and the angles that put the feet where the gait places them
    let g = gait(params);
    let mut motion = Vec::with_capacity(frames * first_channel);
    for k in 0..frames {
        let t = k as f64 * dt;
        let (angles, _) = g.pose(t);
        let p = g.pelvis(t);
        motion.extend_from_slice(&[p.x, p.y, p.z]);
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
        first_frame: 0,
        decimals: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// World positions (cm) of the joints of one frame, from its channel values (`root` the root
    /// position, `angles` the `(z, x, y)` rotations per joint).
    fn joint_positions(
        root: Vector3<f64>,
        angles: &[[f64; 3]],
        scale: f64,
    ) -> Vec<(Vector3<f64>, Matrix3<f64>)> {
        let mut out: Vec<(Vector3<f64>, Matrix3<f64>)> = Vec::with_capacity(SKELETON.len());
        for (i, (_, parent, off)) in SKELETON.iter().enumerate() {
            let r = rot_zxy(angles[i][0], angles[i][1], angles[i][2]);
            let x = match SKELETON.iter().position(|s| s.0 == *parent) {
                Some(p) => {
                    let (pp, pr) = out[p];
                    (pp + pr * Vector3::from(*off) * scale, pr * r)
                }
                None => (root, r),
            };
            out.push(x);
        }
        out
    }

    /// Per frame: the world positions (cm) of each foot's heel and ball contact points, and
    /// the root height — from the written channels (forward kinematics of the BVH), so the
    /// inverse kinematics is checked too.
    fn contact_points(take: &Bvh) -> Vec<[[Vector3<f64>; 2]; 2]> {
        (0..take.frames)
            .map(|k| {
                let f = take.frame(k);
                let angles: Vec<[f64; 3]> = (0..SKELETON.len())
                    .map(|j| {
                        let c = take.joints[j].first_channel + if j == 0 { 3 } else { 0 };
                        [f[c], f[c + 1], f[c + 2]]
                    })
                    .collect();
                let x = joint_positions(Vector3::new(f[0], f[1], f[2]), &angles, 1.0);
                ["LeftFoot", "RightFoot"].map(|foot| {
                    let (p, r) = x[index(foot)];
                    [p + r * Vector3::from(HEEL), p + r * Vector3::from(BALL)]
                })
            })
            .collect()
    }

    /// Which contact points of a foot carry weight at its phase `p` (heel, ball).
    fn pivots(p: f64) -> [bool; 2] {
        if p < FOOT_FLAT {
            [true, false]
        } else if p < HEEL_OFF {
            [true, true]
        } else if p < TOE_OFF {
            [false, true]
        } else {
            [false, false]
        }
    }

    #[test]
    fn stance_feet_roll_on_the_floor_without_sliding() {
        let params = WalkParams::default();
        let take = walk(&params);
        let pts = contact_points(&take);
        let dt = take.frame_time;
        let mut double = 0;
        for k in 0..take.frames {
            let t = k as f64 * dt;
            let mut down = 0;
            for (foot, shift) in [(0, 0.0), (1, 0.5)] {
                let p = (t / params.cycle_s - shift).rem_euclid(1.0);
                let on = pivots(p);
                for (i, planted) in on.iter().enumerate() {
                    let x = pts[k][foot][i];
                    // nothing goes through the floor; planted points are on it
                    assert!(x.y > -1e-6, "frame {k} foot {foot}: {x}");
                    if *planted {
                        assert!(x.y.abs() < 1e-6, "frame {k} foot {foot} point {i}: {x}");
                        // and stay where they are while planted
                        if k > 0 {
                            let q =
                                (((k - 1) as f64 * dt) / params.cycle_s - shift).rem_euclid(1.0);
                            if pivots(q)[i] && q < p {
                                let moved = (x - pts[k - 1][foot][i]).norm();
                                assert!(moved < 1e-6, "frame {k} foot {foot}: slid {moved} cm");
                            }
                        }
                    }
                }
                if on.iter().any(|x| *x) {
                    down += 1;
                }
                // in swing the foot clears the floor (after leaving it)
                if p > TOE_OFF + 0.05 && p < 0.95 {
                    let low = pts[k][foot].iter().map(|x| x.y).fold(f64::MAX, f64::min);
                    assert!(low > 0.5, "frame {k} foot {foot}: {low} cm");
                }
            }
            assert!(down >= 1, "frame {k}: no foot down");
            if down == 2 {
                double += 1;
            }
        }
        // two double supports of 10 % of the cycle
        let frac = double as f64 / take.frames as f64;
        assert!((0.17..0.23).contains(&frac), "double support {frac}");
    }

    #[test]
    fn the_pelvis_moves_smoothly_at_walking_speed_and_height() {
        let take = walk(&WalkParams::default());
        let n = take.frames;
        let dt = take.frame_time;
        let last = take.frame(n - 1);
        let speed_m_s = (last[2] - take.frame(0)[2]) / 100.0 / ((n - 1) as f64 * dt);
        assert!((1.0..1.5).contains(&speed_m_s), "{speed_m_s} m/s");
        // the hips stay at a standing height (cm), and the vertical acceleration of the pelvis
        // is that of a 2.5 cm bob at two cycles per stride: no kinks
        let y: Vec<f64> = (0..n).map(|k| take.frame(k)[1]).collect();
        assert!(y.iter().all(|h| (80.0..100.0).contains(h)), "{y:?}");
        let acc = (1..n - 1)
            .map(|k| (y[k + 1] - 2.0 * y[k] + y[k - 1]).abs() / (dt * dt) / 100.0)
            .fold(0.0, f64::max);
        let bob = 0.025 * (4.0 * PI / 1.1f64).powi(2);
        assert!(acc < 1.01 * bob, "{acc} m/s²");
        // the knees never lock straight: every hip–ankle distance within MAX_REACH of the leg
        let g = gait(&WalkParams::default());
        for k in 0..n {
            assert!(g.pose(k as f64 * dt).1 <= MAX_REACH + 1e-9);
        }
    }
}
