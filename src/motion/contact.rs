//! Foot contact from kinematics alone: which bodies are the feet, where the floor is, and in
//! which frames each foot is on it.
//!
//! Method: the height-and-speed test on foot points that motion-capture pipelines use to find
//! footplants (Le Callennec & Boulic 2006, "Robust kinematic constraint detection for motion
//! data", *Proc. ACM SIGGRAPH/Eurographics SCA*; Ikemoto, Arikan & Forsyth 2006, "Knowing when
//! to put your foot down", *Proc. I3D*, whose hand annotations this test approximates): a foot
//! point is planted when it is near its own floor level **and** nearly still; a foot is in
//! contact when its heel or its toe is planted (heel strike, flat foot, push-off on the toe).
//! Each test has an entry and an exit threshold (hysteresis, a Schmitt trigger), so noise at a
//! threshold does not toggle the state, and phases shorter than [`ContactParams::min_phase_s`]
//! are absorbed by their neighbours.
//!
//! Foot points: the heel is the ankle joint (the origin of the foot joint's frame), the toe is
//! the toe joint (the ball of the foot) or, for skeletons without one, a point of the foot
//! segment. Their heights differ at rest (an ankle is 6–10 cm above the floor), so each kind of
//! point is measured against its own floor level ([`detect_floor`] over both feet), and a foot
//! that never comes down stays above that level.

use crate::error::Error;
use crate::io::bvh::Bvh;
use crate::model::Model;
use crate::model::bvh::BvhMap;
use crate::motion::derive::differentiate;
use crate::motion::smooth::{SmoothSpec, Smoother};
use nalgebra::Vector3;

/// Thresholds of contact detection and of the ground reaction estimate
/// ([`crate::dynamics::grf`]). Lengths in m, speeds in m/s, times in s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactParams {
    /// A point enters contact below this height above its floor level. Default 0.04 m: a
    /// planted heel or toe point moves 1–3 cm vertically in captured takes (heel roll, skin
    /// and solver noise, the low-pass filter rounding the heel strike), while a swinging foot
    /// that clears the floor by less (the toe at mid-swing) moves fast, which the speed test
    /// rejects.
    pub height_on: f64,
    /// A point leaves contact above this height. Default 0.07 m.
    pub height_off: f64,
    /// A point enters contact below this speed. Default 0.8 m/s: planted points move at
    /// < 0.3 m/s (heel roll, push-off) but the low-pass filter (6 Hz) smears the last
    /// 1–2 m/s of a heel strike over ~0.05 s; swinging feet move at 2–5 m/s in walking
    /// (Winter 2009, *Biomechanics and Motor Control of Human Movement*, 4th ed., ch. 2 toe
    /// trajectory) and faster in running.
    pub speed_on: f64,
    /// A point leaves contact above this speed. Default 1.2 m/s.
    pub speed_off: f64,
    /// Contact or flight phases shorter than this are absorbed by their neighbours (except at
    /// the ends of the take). Default 0.04 s: one frame at 30 fps, five at 120 fps; flight in
    /// running lasts ~0.1 s, so it survives.
    pub min_phase_s: f64,
    /// Half-width (m) of the support region around the heel–toe segment inside which a centre
    /// of pressure is kept. Default 0.05 m: half a foot's width, and the heel and the tips of
    /// the toes lie ~5 cm beyond the ankle and toe joints (de Leva 1996 foot lengths).
    pub cop_margin: f64,
    /// Friction coefficient bounding the horizontal ground force (|F_h| ≤ μ F_v). Default 1.0:
    /// shoe on a dry floor is 0.6–1.0, and walking needs ≤ 0.3 (Chang et al. 2015, "The
    /// required coefficient of friction during walking", *Gait & Posture*), so the bound only
    /// removes noise spikes, which stay in the residual.
    pub friction: f64,
    /// Half-width (s) of the window over which the estimated accelerations average the true
    /// ones ([`acceleration_spread_s`] of the take's smoothing and frame time). Frames of flight
    /// within it of a contact phase carry, on the foot of that contact, the part of the needed
    /// wrench that the smoothing and differencing moved out of the stance (while it presses on
    /// the floor). Default 0: no such frames; [`ContactParams::for_take`] sets it.
    pub spread_s: f64,
}

impl ContactParams {
    /// The default thresholds, with [`spread_s`](Self::spread_s) set for a take sampled every
    /// `dt` seconds and smoothed by `smooth` (what `--contact feet` uses).
    pub fn for_take(smooth: &SmoothSpec, dt: f64) -> Result<Self, Error> {
        Ok(Self {
            spread_s: acceleration_spread_s(smooth, dt)?,
            ..Self::default()
        })
    }
}

impl Default for ContactParams {
    fn default() -> Self {
        Self {
            height_on: 0.04,
            height_off: 0.07,
            speed_on: 0.8,
            speed_off: 1.2,
            min_phase_s: 0.04,
            cop_margin: 0.05,
            friction: 1.0,
            spread_s: 0.0,
        }
    }
}

/// World positions of one foot's heel and toe points over the take (m, the take's axes), one
/// entry per frame.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FootPoints {
    pub heel: Vec<Vector3<f64>>,
    pub toe: Vec<Vector3<f64>>,
}

/// The fraction of a take's samples below which the floor lies: [`detect_floor`] returns this
/// quantile. 5 %: robust to a few glitched frames (a minimum is one noisy sample) and still
/// within the stance cluster as long as the feet are down for more than ~10 % of the take.
pub const FLOOR_QUANTILE: f64 = 0.05;

/// The floor level of a set of heights (m): their [`FLOOR_QUANTILE`] quantile (linear
/// interpolation between order statistics). Non-finite heights are ignored; with none left the
/// result is 0 (the world's origin plane).
pub fn detect_floor(heights: &[f64]) -> f64 {
    let mut h: Vec<f64> = heights.iter().copied().filter(|x| x.is_finite()).collect();
    if h.is_empty() {
        return 0.0;
    }
    h.sort_by(f64::total_cmp);
    let pos = FLOOR_QUANTILE * (h.len() - 1) as f64;
    let (lo, frac) = (pos.floor() as usize, pos.fract());
    let hi = (lo + 1).min(h.len() - 1);
    h[lo] + (h[hi] - h[lo]) * frac
}

/// The floor height (m along the up axis) under a set of feet: the floor level of their toe
/// points, the lowest points a foot stands on.
pub fn floor_height(feet: &[FootPoints], up: usize) -> f64 {
    let toes: Vec<f64> = feet
        .iter()
        .flat_map(|f| f.toe.iter().map(|p| p[up]))
        .collect();
    detect_floor(&toes)
}

/// Contact of every foot in every frame (`[foot][frame]`), from the heel and toe points of each
/// foot sampled every `dt` seconds, `up` being the index (0, 1, 2) of the vertical axis.
///
/// A point is planted while it is within `height_on` of its floor level and slower than
/// `speed_on`, and stays planted until it rises above `height_off` or moves faster than
/// `speed_off`; a foot is in contact while its heel or its toe is planted. Speeds are central
/// differences (one-sided at the ends), measured against the floor, which moves under a take
/// walked in place ([`belt_velocity`]).
pub fn contact_phases(
    feet: &[FootPoints],
    up: usize,
    dt: f64,
    params: &ContactParams,
) -> Vec<Vec<bool>> {
    let levels = point_levels(feet, up);
    let belt = belt_velocity(feet, up, dt, params);
    let min_frames = (params.min_phase_s / dt).ceil().max(1.0) as usize;
    feet.iter()
        .map(|f| {
            let heel = planted(&f.heel, up, levels.0, dt, belt, params);
            let toe = planted(&f.toe, up, levels.1, dt, belt, params);
            let mut c: Vec<bool> = heel.iter().zip(&toe).map(|(h, t)| *h || *t).collect();
            absorb_short_phases(&mut c, min_frames);
            c
        })
        .collect()
}

/// The floor levels of the heel points and of the toe points, over all feet (m along `up`).
fn point_levels(feet: &[FootPoints], up: usize) -> (f64, f64) {
    let level = |pick: fn(&FootPoints) -> &Vec<Vector3<f64>>| {
        let h: Vec<f64> = feet
            .iter()
            .flat_map(|f| pick(f).iter().map(|p| p[up]))
            .collect();
        detect_floor(&h)
    };
    (level(|f| &f.heel), level(|f| &f.toe))
}

/// The central-difference velocity of point path `p` at frame `k` (one-sided at the ends; zero
/// for a path of one frame).
fn velocity(p: &[Vector3<f64>], k: usize, dt: f64) -> Vector3<f64> {
    let (a, b) = (k.saturating_sub(1), (k + 1).min(p.len() - 1));
    if b > a {
        (p[b] - p[a]) / ((b - a) as f64 * dt)
    } else {
        Vector3::zeros()
    }
}

/// The velocity of the floor under the feet (m/s, horizontal): zero over ground. A take walked
/// in place (a treadmill; a game's in-place cycle, whose root stays while the planted foot
/// slides back at the walking speed) has its feet, while at the floor, move together at the
/// belt's velocity; a floor moving at a constant velocity is an inertial frame, so the
/// dynamics are the same and only the contact test must measure speeds against it.
///
/// Estimated from the horizontal velocities of the heel and toe points over the frames where
/// they are within `height_on` of their floor level (stance dominates those: a walk's swing
/// foot clears the floor): their component-wise median, refined to the median of those within
/// `speed_on` / 2 of it (the planted feet's cluster), is taken as a belt when it exceeds
/// `speed_on` / 2, at least half of them lie within `speed_on` of it, and more than twice as
/// many lie within `speed_on` of it as of rest (a still floor is the usual one: the Bandai
/// run's swing feet pass low and fast, and on the pelvis paths residual reduction tries its
/// heel strikes and push-offs pull the median forward to 0.6 m/s; it keeps a still floor,
/// with 0.7–0.9 as many of them still as moving with that median).
///
/// The belt and its counts move with the floor: the same take on a floor moving at `c` has the
/// belt `c` whatever its own travel (up to the median slip of its planted feet, which a belt's
/// speed cannot be told from: the Bandai walk's 1.5 cm/s); the count at rest only decides
/// against a belt that carries fewer than twice as many. Before, a
/// fifth of them slower than `speed_on` meant a still floor: the Bandai walk going on at
/// 1.25 m/s over a 1 m/s belt, its feet passing through rest at each heel strike and toe-off on
/// their way between the swing's speed and the belt's, was measured against a still floor; its
/// planted feet, sliding at 1 m/s, stayed under the exit speed, and every stance came out a
/// frame longer at both ends (168 of 195 frames agreed; now all do, and 0.25 as many of its
/// feet at the floor are still as move with the belt).
pub fn belt_velocity(
    feet: &[FootPoints],
    up: usize,
    dt: f64,
    params: &ContactParams,
) -> Vector3<f64> {
    let (heel_level, toe_level) = point_levels(feet, up);
    let mut near: Vec<Vector3<f64>> = vec![];
    for f in feet {
        for (path, level) in [(&f.heel, heel_level), (&f.toe, toe_level)] {
            for k in 0..path.len() {
                if path[k][up] - level < params.height_on {
                    let mut v = velocity(path, k, dt);
                    v[up] = 0.0;
                    near.push(v);
                }
            }
        }
    }
    if near.is_empty() {
        return Vector3::zeros();
    }
    // the median, then the median of the velocities near it (the planted feet's cluster,
    // without the swing feet that pass low and drag the whole median towards them)
    let median = |vs: &[&Vector3<f64>]| {
        let mut m = Vector3::zeros();
        for i in (0..3).filter(|&i| i != up) {
            let mut c: Vec<f64> = vs.iter().map(|v| v[i]).collect();
            c.sort_by(f64::total_cmp);
            m[i] = c[c.len() / 2];
        }
        m
    };
    let support = |b: &Vector3<f64>| {
        near.iter()
            .filter(|v| (*v - b).norm() < params.speed_on)
            .count()
    };
    let first = median(&near.iter().collect::<Vec<_>>());
    let mut belt = first;
    for _ in 0..5 {
        let close: Vec<&Vector3<f64>> = near
            .iter()
            .filter(|v| (*v - belt).norm() < 0.5 * params.speed_on)
            .collect();
        if close.is_empty() {
            break;
        }
        belt = median(&close);
    }
    // a refinement that gathers fewer of the velocities (a short take's few samples) is not
    if support(&first) > support(&belt) {
        belt = first;
    }
    // the belt, when it carries the feet at the floor together, and more than twice as many
    // of them as a still floor would
    let together = support(&belt);
    let still = support(&Vector3::zeros());
    if belt.norm() > 0.5 * params.speed_on && 2 * together >= near.len() && 2 * still < together {
        belt
    } else {
        Vector3::zeros()
    }
}

/// Why no foot of a take is ever planted ([`contact_phases`] all false), for a user: how close
/// each kind of point comes to its floor level while slow enough, and how slow it is there.
pub fn why_no_contact(feet: &[FootPoints], up: usize, dt: f64, params: &ContactParams) -> String {
    let (heel_level, toe_level) = point_levels(feet, up);
    let belt = belt_velocity(feet, up, dt, params);
    let mut slowest_near = f64::INFINITY;
    for f in feet {
        for (path, level) in [(&f.heel, heel_level), (&f.toe, toe_level)] {
            for k in 0..path.len() {
                if path[k][up] - level < params.height_on {
                    slowest_near = slowest_near.min((velocity(path, k, dt) - belt).norm());
                }
            }
        }
    }
    let frames = feet.first().map_or(0, |f| f.heel.len());
    if slowest_near.is_finite() {
        format!(
            "no foot is ever planted on a floor: within {:.0} cm of the floor the feet never \
             move slower than {:.2} m/s (planted feet move below {:.1} m/s) over {frames} \
             frames; a foot sliding over the floor, a take in the air or in water",
            100.0 * params.height_on,
            slowest_near,
            params.speed_on
        )
    } else {
        format!(
            "no foot is ever planted on a floor: no foot comes within {:.0} cm of its lowest \
             level over {frames} frames",
            100.0 * params.height_on
        )
    }
}

/// The planted state of one point over time: hysteresis on height above `level` and speed
/// (against the floor's velocity `belt`), run forward and backward in time and the two results
/// joined.
///
/// A Schmitt trigger run forward enters late and leaves late: a landing foot still moving at
/// `speed_on` when it touches down (a heel strike, a landing from a run or a jump, sampled at
/// 30 fps: the central-difference speed of the touch-down frame spans the end of the descent)
/// enters contact a frame or more after it touched, while the push-off is followed to the
/// exit thresholds. Run backward it does the opposite. Joining both (a zero-lag trigger, as the
/// forward-backward pass makes a filter zero-lag) treats touch-down and lift-off alike: a
/// point is planted from the first frame after which it is continuously within the exit
/// thresholds up to a frame within the entry thresholds, to the last such frame after.
fn planted(
    p: &[Vector3<f64>],
    up: usize,
    level: f64,
    dt: f64,
    belt: Vector3<f64>,
    params: &ContactParams,
) -> Vec<bool> {
    let n = p.len();
    let test = |k: usize| {
        let speed = (velocity(p, k, dt) - belt).norm();
        let h = p[k][up] - level;
        (
            h < params.height_on && speed < params.speed_on,
            h <= params.height_off && speed <= params.speed_off,
        )
    };
    let tests: Vec<(bool, bool)> = (0..n).map(test).collect();
    let trigger = |state: &mut bool, (enter, stay): (bool, bool)| {
        *state = if *state { stay } else { enter };
        *state
    };
    let mut state = false;
    let mut out: Vec<bool> = tests.iter().map(|t| trigger(&mut state, *t)).collect();
    state = false;
    for (o, t) in out.iter_mut().zip(&tests).rev() {
        *o |= trigger(&mut state, *t);
    }
    out
}

/// The half-width (s) of the window of true accelerations that the pipeline's estimate of an
/// acceleration at one frame averages: the smallest `h` such that the estimator's impulse
/// response (smoothing `smooth`, then second-order central differences twice, as
/// `pipeline::take_states` does) has 95 % of its absolute area within `±h`.
///
/// Computed, not tabulated: a unit velocity step at the centre of a 4 s ramp (`x = max(0, t)`,
/// whose true acceleration is a unit impulse) goes through the same [`Smoother`] and
/// [`differentiate`] as a take; the result is the estimator's kernel. Without smoothing it is
/// `[¼, ½, ¼]/dt` (one frame each side: 33 ms at 30 fps, 8 ms at 120 fps); the 6 Hz
/// Butterworth widens it to ±0.07 s (0.067 s at 120 fps, 0.1 s at 30 fps).
///
/// A force the ground applies between `t₀` and `t₁` therefore shows in the estimated whole-body
/// wrench over `[t₀ − h, t₁ + h]`: a landing appears before the foot touches down
/// ([`crate::dynamics::grf`] lets the landing foot carry it).
///
/// The ramp reaches ±2 s, or the filter's reach and the differences' frames when that is
/// shorter (the impulse response lies within them): a `Frame Time: 1e-9` asked for 4·10⁹
/// samples and aborted, a hostile `1e-300` for more memory than exists (found by hand and by
/// `examples/fuzz_takes.rs`).
///
/// [`Smoother`]: crate::motion::smooth::Smoother
/// [`differentiate`]: crate::motion::derive::differentiate
pub fn acceleration_spread_s(smooth: &SmoothSpec, dt: f64) -> Result<f64, Error> {
    let mut smoother = Smoother::new(*smooth, dt)?;
    // the impulse response lies within the filter's reach and the differences' two frames;
    // 2 s of frames at most (`Frame Time: 1e-9` asked for 4·10⁹ samples)
    let half = (smoother.reach() + 4).min((2.0 / dt).ceil() as usize);
    let n = 2 * half + 1;
    let mut x: Vec<f64> = (0..n)
        .map(|k| (k as f64 - half as f64).max(0.0) * dt)
        .collect();
    smoother.smooth(&mut x);
    let (mut v, mut a) = (vec![0.0; n], vec![0.0; n]);
    differentiate(&x, dt, &mut v);
    differentiate(&v, dt, &mut a);
    let total: f64 = a.iter().map(|x| x.abs()).sum();
    let mut inside = a[half].abs();
    let mut h = 0;
    while inside < 0.95 * total && h < half {
        h += 1;
        inside += a[half - h].abs() + a[half + h].abs();
    }
    Ok(h as f64 * dt)
}

/// Flips runs of equal states shorter than `min_frames` that have neighbours on both sides:
/// first short contacts (blips), then short gaps.
fn absorb_short_phases(c: &mut [bool], min_frames: usize) {
    for target in [true, false] {
        let mut k = 0;
        while k < c.len() {
            let start = k;
            while k < c.len() && c[k] == c[start] {
                k += 1;
            }
            let inner = start > 0 && k < c.len();
            if c[start] == target && inner && k - start < min_frames {
                c[start..k].fill(!target);
            }
        }
    }
}

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
        let mut sorted = heights.clone();
        sorted.sort_by(f64::total_cmp);
        let Some(&cut) = sorted.get(sorted.len() / 10) else {
            continue;
        };
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

    #[test]
    fn floor_is_a_low_quantile_not_the_minimum() {
        // 100 samples at 0.0..0.99 plus one glitch far below
        let mut h: Vec<f64> = (0..100).map(|k| k as f64 * 0.01).collect();
        h.push(-5.0);
        let f = detect_floor(&h);
        assert!((0.03..0.06).contains(&f), "{f}");
        assert_eq!(detect_floor(&[]), 0.0);
    }

    #[test]
    fn the_acceleration_spread_is_the_kernel_of_differences_and_smoothing() {
        // no smoothing: a = (x[k+2] − 2x[k] + x[k−2]) / 4dt² is [¼, ½, ¼]/dt on an impulse:
        // one frame each side
        for dt in [1.0 / 30.0, 1.0 / 120.0] {
            let h = acceleration_spread_s(&SmoothSpec::None, dt).unwrap();
            assert!((h - dt).abs() < 1e-12, "{h}");
        }
        // a low-pass widens it in time, roughly as 1/cutoff, not as the frame rate
        let bw = |hz: f64, dt: f64| {
            let spec = SmoothSpec::Butterworth {
                cutoff_hz: hz,
                order: 2,
            };
            acceleration_spread_s(&spec, dt).unwrap()
        };
        let (h6, h12) = (bw(6.0, 1.0 / 120.0), bw(12.0, 1.0 / 120.0));
        assert!((0.05..0.12).contains(&h6), "{h6}");
        assert!((h6 / h12 - 2.0).abs() < 0.3, "{h6} {h12}");
        assert!((bw(6.0, 1.0 / 30.0) - h6).abs() < 0.04);
        // a cutoff above Nyquist is an error, not a panic
        assert!(
            acceleration_spread_s(
                &SmoothSpec::Butterworth {
                    cutoff_hz: 20.0,
                    order: 2
                },
                1.0 / 30.0
            )
            .is_err()
        );
    }

    #[test]
    fn a_landing_enters_contact_on_its_touch_down_frame() {
        // a point falls at 2 m/s onto the floor, touching down at frame 10, and stays there;
        // at 30 fps the central-difference speed of frame 10 is 1 m/s, over the 0.8 m/s entry
        // speed: a forward trigger enters one frame late (11), the backward one holds contact
        // back to frame 10 (speed ≤ 1.2 m/s) and not to 9 (6.7 cm up, 2 m/s)
        let dt = 1.0 / 30.0;
        let p: Vec<Vector3<f64>> = (0..20)
            .map(|k| Vector3::new(0.0, (10.0 - k as f64).max(0.0) * 2.0 * dt, 0.0))
            .collect();
        let c = planted(&p, 1, 0.0, dt, Vector3::zeros(), &ContactParams::default());
        let first = c.iter().position(|x| *x).unwrap();
        assert_eq!(first, 10, "{c:?}");
        assert!(c[first..].iter().all(|x| *x));
        // and the mirror image, a lift-off, leaves symmetrically
        let rev: Vec<Vector3<f64>> = p.iter().rev().copied().collect();
        let r = planted(
            &rev,
            1,
            0.0,
            dt,
            Vector3::zeros(),
            &ContactParams::default(),
        );
        let back: Vec<bool> = c.iter().rev().copied().collect();
        assert_eq!(r, back);
    }

    /// A walk at 0.75 m/s, 30 fps, y up: each foot's heel and toe hold still for 18 frames
    /// and swing for 12, the feet half a cycle apart; the swing leaves and reaches the floor
    /// through four frames below 4 cm at 0.6–1.5 m/s (a toe-off and a heel strike). `belt`
    /// (m/s, horizontal) is taken out of every point's motion: the same walk seen from a frame
    /// moving at `belt`, in which the floor moves at `−belt`.
    fn walk_on(belt: Vector3<f64>) -> Vec<FootPoints> {
        let dt = 1.0 / 30.0;
        let swing_speed = [0.6, 0.9, 1.2, 1.5, 3.0, 4.5, 4.5, 3.0, 1.5, 1.2, 0.9, 0.6];
        let swing_height = [
            0.005, 0.015, 0.025, 0.035, 0.08, 0.12, 0.12, 0.08, 0.035, 0.025, 0.015, 0.005,
        ];
        let foot = |phase: usize| {
            let (mut x, mut path) = (0.0, vec![]);
            for k in 0..120 {
                let f = (k + phase) % 30;
                let h = if f < 18 {
                    0.0
                } else {
                    x += swing_speed[f - 18] * dt;
                    swing_height[f - 18]
                };
                path.push(Vector3::new(x, h, 0.0) - belt * (k as f64 * dt));
            }
            let toe = path
                .iter()
                .map(|p| p + Vector3::new(0.15, 0.0, 0.0))
                .collect();
            FootPoints { heel: path, toe }
        };
        vec![foot(0), foot(15)]
    }

    #[test]
    fn the_same_walk_on_a_moving_floor_finds_the_floor_moving_and_the_same_stances() {
        let (dt, up, params) = (1.0 / 30.0, 1, ContactParams::default());
        let ground = walk_on(Vector3::zeros());
        assert_eq!(belt_velocity(&ground, up, dt, &params), Vector3::zeros());
        let stances = contact_phases(&ground, up, dt, &params);
        for belt in [
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(1.25, 0.0, 0.0),
            Vector3::new(2.5, 0.0, 0.0),
            Vector3::new(-1.0, 0.0, 0.0),
            Vector3::new(0.6, 0.0, -0.8),
        ] {
            let on_belt = walk_on(belt);
            let found = belt_velocity(&on_belt, up, dt, &params);
            assert!((found + belt).norm() < 1e-9, "{belt:?}: found {found:?}");
            assert_eq!(
                contact_phases(&on_belt, up, dt, &params),
                stances,
                "{belt:?}"
            );
        }
        // the case that fooled a count of still feet (a fifth of those at the floor slower than
        // `speed_on` meant a still floor): on a 1 m/s belt under the walk, the swing's ends
        // pass through rest on their way to and from the belt's speed
        let on_belt = walk_on(Vector3::new(1.0, 0.0, 0.0));
        let (mut near, mut still) = (0, 0);
        for f in &on_belt {
            for k in 0..f.heel.len() {
                if f.heel[k][up] < params.height_on {
                    near += 1;
                    still += usize::from(velocity(&f.heel, k, dt).norm() < params.speed_on);
                }
            }
        }
        assert!(5 * still >= near, "{still} of {near} slower than speed_on");
    }

    #[test]
    fn short_blips_and_gaps_are_absorbed_but_not_at_the_ends() {
        let mut c = vec![
            true, false, false, false, true, false, false, true, true, false, true,
        ];
        absorb_short_phases(&mut c, 2);
        // the lone `true` at 4 is a blip → false; the lone false at 9 is a gap → true;
        // the first `true` touches the start and stays
        assert_eq!(
            c,
            vec![
                true, false, false, false, false, false, false, true, true, true, true
            ]
        );
    }
}
