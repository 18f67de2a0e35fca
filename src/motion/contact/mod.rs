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
//!
//! Where each part lives: `phases.rs` (the thresholds, the planted test and its hysteresis, the
//! contact phases of a set of feet, the window the estimated accelerations average over),
//! `heights.rs` (how much a take's planted points wobble, and the contact heights fitted to
//! it),
//! `floor.rs` (the floor level under the feet, and its velocity under a take walked in place),
//! `feet.rs` (which bodies are the feet, by name or by the skeleton's shape, and their heel,
//! ankle and toe points).

mod feet;
mod floor;
mod heights;
mod phases;

pub use feet::{
    Foot, Side, feet_at, feet_of_bvh, fit_heel_points, foot_bodies, limb_ends, skeleton_joint,
};
pub use floor::{
    FLOOR_QUANTILE, FootPoints, belt_velocity, detect_floor, floor_height, point_levels,
};
pub use heights::{
    HEIGHT_PER_WOBBLE, MIN_HEIGHT_ON, MIN_SAMPLES, MIN_STILL_SHARE, REACH_PER_SPREAD, STILL_SHARE,
    WOBBLE_QUANTILE, Wobble, heights_note, planted_wobble,
};
pub use phases::{ContactParams, acceleration_spread_s, contact_phases, why_no_contact};
