//! Bones do not stretch: position channels on joints below the body's root, held at their mean.
//!
//! Some exporters write six channels on every joint (Bandai-Namco, Perception Neuron, the
//! LaFAN1 re-solves). Below the joint that carries the body through space, those position
//! channels restate the bone's OFFSET (Bandai: the same value in every frame) or move it by
//! the capture system's noise and solver slack (Perception Neuron: up to 2.4 cm). As
//! coordinates they double the model (a 22-joint Bandai rig: nq 126 instead of 66) and carry
//! "forces" of hundreds of newtons along bones that no muscle makes. [`weld_at_mean`] holds
//! each such channel at its mean over the take, in the take's own frames, so that the model
//! (`model::bvh`, [`held_positions`]) places the joint at `T(offset) · T(mean)` with no
//! coordinate there, and every output of the take (world positions, a written BVH) agrees
//! with it. The largest variation from the mean is reported ([`note`]); a joint that moves
//! more than a capture error ([`Welded::animated`]) is said to be animated on purpose, and the
//! user keeps the channels with `--joint-translations keep`.
//!
//! The joints whose position channels stay are the body's root ([`carriers`]): the first joint
//! from the top that has position channels and, below a helper root without a body segment
//! (`motion::fold::redundant_root_child`, Bandai's `joint_Root`), the six-channel pelvis too,
//! whether the pipeline folds the helper into it or the user keeps it with a mass.

use crate::io::bvh::{Bvh, PositionMode, ResolvedPosition, portable, resolve_position_modes};
use nalgebra::Vector3;

/// The position channels of one joint, held at their mean over the take.
#[derive(Debug, Clone, PartialEq)]
pub struct Welded {
    /// The BVH joint (index in `bvh.joints`).
    pub joint: usize,
    /// The value each position channel is held at, by axis (file units, as the channels are
    /// written); an axis without a channel holds 0.
    pub values: Vector3<f64>,
    /// The largest distance of the joint's translation from the held one over the frames (m).
    pub variation_m: f64,
    /// The frame where that distance is largest.
    pub frame: usize,
    /// The bone's length as held: the joint's distance from its parent joint (m).
    pub bone_m: f64,
}

/// Capture error moves a joint centre by up to this much (m): soft tissue carries skin markers
/// over the bones by centimetres, and joint centres fitted to them move as much (Leardini et
/// al. 2005, *Gait & Posture* 21, 212–225); an inertial suit's solver adjusts its segments too
/// (Perception Neuron's hips: 2.4 cm over a sit-to-stand).
pub const CAPTURE_ERROR_M: f64 = 0.05;

/// On a short bone (fingers, an animal's toes) a translation of more than this fraction of its
/// length is no capture error either.
pub const CAPTURE_ERROR_OF_BONE: f64 = 0.25;

/// Below this (m) any variation is noise, however short the bone (a zero-length bone).
pub const NOISE_FLOOR_M: f64 = 0.01;

impl Welded {
    /// The largest variation a capture error explains: a quarter of the bone, between 1 and
    /// 5 cm ([`CAPTURE_ERROR_OF_BONE`], [`NOISE_FLOOR_M`], [`CAPTURE_ERROR_M`]).
    pub fn capture_error_m(&self) -> f64 {
        (CAPTURE_ERROR_OF_BONE * self.bone_m).clamp(NOISE_FLOOR_M, CAPTURE_ERROR_M)
    }

    /// True when the joint moves more than a capture error: the file animates its
    /// translation on purpose (a stretchy rig, a prop), and welding changes the motion.
    pub fn animated(&self) -> bool {
        self.variation_m > self.capture_error_m()
    }
}

/// The joints whose position channels carry the body through space (see the module doc), in
/// file order: the first joint from the top with position channels, and `pelvis`, the
/// six-channel only child of a helper root (the pipeline knows it is one: it has no body
/// segment).
pub fn carriers(bvh: &Bvh, pelvis: Option<usize>) -> Vec<usize> {
    let Some(first) = bvh.joints.iter().position(|j| j.has_position()) else {
        return vec![];
    };
    let mut c = vec![first];
    c.extend(pelvis.filter(|&p| p > first));
    c
}

/// Holds the position channels of every joint with some, other than the [`carriers`] (with
/// `pelvis`, the six-channel child of a helper root), at their mean over the frames (in `bvh`
/// itself, every frame), and returns what was held, in joint order. `modes` are the resolved
/// position modes (indexed like `bvh.joints`; empty: `add`), `scale_to_m` metres per file unit.
///
/// The mean is taken as `x₀ + mean(x − x₀)`, so a channel constant in every frame is held at
/// exactly its value.
pub fn weld_at_mean(
    bvh: &mut Bvh,
    modes: &[ResolvedPosition],
    scale_to_m: f64,
    pelvis: Option<usize>,
) -> Vec<Welded> {
    // joints before the last carrier have no position channels (file order is depth first)
    let Some(last_carrier) = carriers(bvh, pelvis).pop() else {
        return vec![];
    };
    let n = bvh.frames;
    let cc = bvh.channel_count;
    let mut welded = vec![];
    for (j, joint) in bvh.joints.iter().enumerate().skip(last_carrier + 1) {
        let cols = joint.position_columns();
        if n == 0 || cols.iter().all(Option::is_none) {
            continue;
        }
        // mean of each channel, from its first value
        let mut values = Vector3::zeros();
        for (a, col) in cols.iter().enumerate() {
            if let Some(c) = col.map(|c| joint.first_channel + c) {
                let x0 = bvh.motion[c];
                let sum: f64 = (0..n).map(|k| bvh.motion[k * cc + c] - x0).sum();
                values[a] = x0 + sum / n as f64;
            }
        }
        // the largest distance from it
        let (mut variation, mut frame) = (0.0, 0);
        for k in 0..n {
            let d2: f64 = (cols.iter().enumerate())
                .filter_map(|(a, col)| col.map(|c| (a, joint.first_channel + c)))
                .map(|(a, c)| (bvh.motion[k * cc + c] - values[a]).powi(2))
                .sum();
            if d2.sqrt() > variation {
                (variation, frame) = (d2.sqrt(), k);
            }
        }
        // the bone as held: T(offset) · T(values) under the joint's mode
        let mut bone = joint.offset;
        for (a, col) in cols.iter().enumerate() {
            if col.is_some() {
                match modes.get(j) {
                    Some(ResolvedPosition::Replace) => bone[a] = values[a],
                    _ => bone[a] += values[a],
                }
            }
        }
        welded.push(Welded {
            joint: j,
            values,
            variation_m: variation * scale_to_m,
            frame,
            bone_m: bone.norm() * scale_to_m,
        });
    }
    // the take's frames say what the model uses
    for w in &welded {
        let joint = &bvh.joints[w.joint];
        for (a, col) in joint.position_columns().iter().enumerate() {
            if let Some(c) = col.map(|c| joint.first_channel + c) {
                for k in 0..n {
                    bvh.motion[k * cc + c] = w.values[a];
                }
            }
        }
    }
    welded
}

/// The skeleton as any BVH articula writes of the take holds it: `bvh` with the position
/// channels below the body's root held at their mean ([`weld_at_mean`], the helper root's
/// six-channel child, `motion::fold::redundant_root_child`, taken as a carrier) and folded into
/// the OFFSETs ([`portable`](crate::io::bvh::portable)), and its position modes under `mode`.
/// Geometry read from it (up axis, unit, stature, landmarks, the segments' bones) is the same
/// for the take and for the take written and read back, so both get the same model. `None`
/// when no joint below the root has position channels (`bvh` is its own shape).
pub fn held_shape(bvh: &Bvh, mode: PositionMode) -> Option<(Bvh, Vec<ResolvedPosition>)> {
    let pelvis = crate::motion::fold::redundant_root_child(bvh);
    let last_carrier = *carriers(bvh, pelvis).last()?;
    if !(bvh.joints.iter().skip(last_carrier + 1)).any(|j| j.has_position()) {
        return None;
    }
    let modes = resolve_position_modes(bvh, mode);
    let mut held = bvh.clone();
    weld_at_mean(&mut held, &modes, 1.0, pelvis);
    // exact translations: the same body whatever decimals the file printed (a file in another
    // unit); a written file's rounding to its decimals moves them by half a unit of the last
    held.decimals.clear();
    let shape = portable(&held, &modes);
    let shape_modes = resolve_position_modes(&shape, mode);
    Some((shape, shape_modes))
}

/// The held values by BVH joint, as `model::bvh::BvhModelOptions::held_positions` takes them:
/// `Some(values)` for a welded joint, `None` for the others (`joints` of them).
pub fn held_positions(welded: &[Welded], joints: usize) -> Vec<Option<Vector3<f64>>> {
    let mut held = vec![None; joints];
    for w in welded {
        held[w.joint] = Some(w.values);
    }
    held
}

/// A length (m) in cm for a note: one decimal, or two significant digits below 0.05 cm (the
/// last digits of a file that restates its OFFSETs: `1.2e-11 cm`).
pub fn centimetres(m: f64) -> String {
    let cm = 100.0 * m;
    if cm == 0.0 || cm >= 0.05 {
        format!("{cm:.1} cm")
    } else {
        format!("{cm:.1e} cm")
    }
}

/// What welding did, for `info`: how many joints, the largest variation and where, and the
/// joints a capture error does not explain (the file animates them on purpose). `None` when
/// nothing was welded.
pub fn note(bvh: &Bvh, welded: &[Welded]) -> Option<String> {
    let largest = welded
        .iter()
        .max_by(|a, b| a.variation_m.total_cmp(&b.variation_m))?;
    let name = |w: &Welded| bvh.joints[w.joint].name.as_str();
    let count = welded.len();
    let plural = if count == 1 { "" } else { "s" };
    let variation = if largest.variation_m == 0.0 {
        "each constant over the take".to_string()
    } else {
        format!(
            "largest variation {}, `{}` at frame {}",
            centimetres(largest.variation_m),
            name(largest),
            largest.frame
        )
    };
    let mut s = format!(
        "position channels on {count} non-root joint{plural} were welded at their mean \
         ({variation}); BVH outputs write them at the mean; --joint-translations keep keeps \
         them as coordinates"
    );
    let animated: Vec<String> = welded
        .iter()
        .filter(|w| w.animated())
        .map(|w| {
            format!(
                "`{}` {:.1} cm on a {:.1} cm bone",
                name(w),
                100.0 * w.variation_m,
                100.0 * w.bone_m
            )
        })
        .collect();
    if !animated.is_empty() {
        s.push_str(&format!(
            ". More than capture error moves (a quarter of the bone, 1–5 cm): {}; the file \
             animates {} on purpose, and welded the motion is not the file's",
            animated.join(", "),
            if animated.len() == 1 { "it" } else { "them" }
        ));
    }
    Some(s)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::bvh;

    /// A root, a spine whose channels restate its OFFSET with ±0.3 units of noise, and a
    /// head that restates its own exactly.
    fn take() -> Bvh {
        let text = "HIERARCHY\nROOT Hips\n{\n OFFSET 0 90 0\n CHANNELS 6 Xposition Yposition \
                    Zposition Zrotation Xrotation Yrotation\n JOINT Spine\n {\n  OFFSET 0 20 0\n  \
                    CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n  \
                    JOINT Head\n  {\n   OFFSET 0 30 0\n   CHANNELS 6 Xposition Yposition \
                    Zposition Zrotation Xrotation Yrotation\n   End Site\n   {\n    OFFSET 0 10 \
                    0\n   }\n  }\n }\n}\nMOTION\nFrames: 3\nFrame Time: 0.1\n\
                    0 90 0 0 0 0 0.3 20 0 0 0 0 0 30 0 0 0 0\n\
                    10 91 0 0 5 0 0 20.3 0 0 0 0 0 30 0 0 0 0\n\
                    20 92 0 0 0 0 -0.3 19.7 0 0 0 0 0 30 0 0 0 0\n";
        bvh::parse_str(text, std::path::Path::new("w.bvh")).unwrap()
    }

    #[test]
    fn joints_below_the_root_are_held_at_their_mean() {
        let mut b = take();
        let modes = resolve_position_modes(&b, PositionMode::Auto);
        assert_eq!(carriers(&b, None), [0]);
        let w = weld_at_mean(&mut b, &modes, 0.01, None);
        assert_eq!(w.iter().map(|w| w.joint).collect::<Vec<_>>(), [1, 2]);
        assert!((w[0].values - Vector3::new(0.0, 20.0, 0.0)).norm() < 1e-12);
        // frame 0: (0.3, 0) from the mean, frame 1: (0, 0.3), frame 2: (−0.3, −0.3)
        assert!((w[0].variation_m - 0.01 * 0.3 * 2f64.sqrt()).abs() < 1e-12);
        assert_eq!(w[0].frame, 2);
        assert!((w[0].bone_m - 0.2).abs() < 1e-12);
        // an exact restatement is held at exactly its value, with no variation
        assert_eq!(w[1].values, Vector3::new(0.0, 30.0, 0.0));
        assert_eq!(w[1].variation_m, 0.0);
        // every frame now holds the mean; the root's channels are untouched
        for k in 0..3 {
            assert!((b.frame(k)[6] - 0.0).abs() < 1e-12 && (b.frame(k)[7] - 20.0).abs() < 1e-12);
        }
        assert_eq!(b.frame(2)[..2], [20.0, 92.0]);
        let n = note(&b, &w).unwrap();
        assert!(n.contains("2 non-root joints"), "{n}");
        assert!(n.contains("0.4 cm, `Spine` at frame 2"), "{n}");
        assert!(!n.contains("on purpose"), "{n}");
    }

    #[test]
    fn more_than_capture_error_is_said_to_be_animated() {
        let w = |variation_m, bone_m| Welded {
            joint: 1,
            values: Vector3::zeros(),
            variation_m,
            frame: 0,
            bone_m,
        };
        // a 40 cm shin: 5 cm; a 2 cm finger bone: 1 cm; a 12 cm hip offset: 3 cm
        assert!(!w(0.049, 0.4).animated() && w(0.051, 0.4).animated());
        assert!(!w(0.009, 0.02).animated() && w(0.011, 0.02).animated());
        assert!(!w(0.029, 0.12).animated() && w(0.031, 0.12).animated());
        let mut b = take();
        let modes = resolve_position_modes(&b, PositionMode::Auto);
        let mut welded = weld_at_mean(&mut b, &modes, 0.01, None);
        welded[1].variation_m = 0.2;
        let n = note(&b, &welded).unwrap();
        assert!(n.contains("`Head` 20.0 cm on a 30.0 cm bone"), "{n}");
        assert!(n.contains("on purpose"), "{n}");
        assert_eq!(centimetres(0.0123), "1.2 cm");
        assert_eq!(centimetres(1.23e-13), "1.2e-11 cm");
    }

    #[test]
    fn the_pelvis_below_a_helper_root_carries_the_body_too() {
        let mut b = take();
        assert_eq!(carriers(&b, Some(1)), [0, 1]);
        let w = weld_at_mean(&mut b, &[], 0.01, Some(1));
        assert_eq!(w.iter().map(|w| w.joint).collect::<Vec<_>>(), [2]);
        assert_eq!(b.frame(2)[6..8], [-0.3, 19.7]);
    }
}
