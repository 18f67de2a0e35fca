//! Folding a redundant root into its only child.
//!
//! Some exporters put a helper joint above the pelvis: the Bandai-Namco takes start with
//! `ROOT joint_Root` (6 channels, OFFSET 0) whose only child `Hips` has 6 channels again. The
//! helper has no body segment, so it carries no mass, and its six coordinates move exactly what
//! the child's six move: the mass matrix is singular (forward dynamics and simulation fail at
//! the first step) and the root residual is shared between two sets of coordinates.
//!
//! [`fold_root_into_child`] rewrites the motion so that the child carries the whole motion:
//! at every frame the child's channels are set to the composite transform
//! `T(root) · T(child)` (relative to the root's rest pose), and the root's channels to its rest
//! values. The world pose of every joint below the root is unchanged (the massless root itself
//! now stays at its rest pose); the root then holds still, and the
//! pipeline welds it to the world (`pipeline::take_from_bvh`), which removes the redundant
//! coordinates. Where the root does not rotate (all the Bandai takes), the child's rotation
//! channels are kept bit for bit and only its positions change.

use crate::io::bvh::{Bvh, ResolvedPosition, joint_rotation, joint_translation};
use crate::rotation::{euler_to_matrix, matrix_to_euler_near};

/// The index of the root's only child when the root's motion is redundant with it: the root
/// has channels and exactly one child joint, and that child has three position channels (one
/// per axis) and three rotation channels (a Tait–Bryan order), so any root motion can be
/// expressed by the child's channels alone. Mass is the caller's business (see the module doc).
pub fn redundant_root_child(bvh: &Bvh) -> Option<usize> {
    let root = bvh.joints.first()?;
    if root.channels.is_empty() {
        return None;
    }
    let mut children = bvh
        .joints
        .iter()
        .enumerate()
        .filter(|(_, j)| j.parent == Some(0));
    let (c, child) = children.next()?;
    if children.next().is_some() {
        return None;
    }
    let full_position = child.position_columns().iter().all(Option::is_some);
    let rotations = child.channels.iter().filter(|ch| ch.is_rotation()).count();
    (full_position && rotations == 3 && child.euler_order().is_some()).then_some(c)
}

/// Moves the root's motion into its only child `c` (from [`redundant_root_child`]), frame by
/// frame, so that the world pose of every joint below the root is unchanged and the root's
/// channels hold their
/// rest values (zero rotation; position = OFFSET in `replace` mode, 0 in `add` mode). `modes`
/// are the resolved position modes (indexed like `bvh.joints`).
pub fn fold_root_into_child(bvh: &mut Bvh, modes: &[ResolvedPosition], c: usize) {
    let root = bvh.joints[0].clone();
    let child = bvh.joints[c].clone();
    let order = child
        .euler_order()
        .expect("redundant_root_child checked the child's rotation order");
    let rot_cols = rotation_columns(&child);
    let mut previous = [0.0; 3];
    for k in 0..bvh.frames {
        let row = bvh.frame(k);
        let (t_root, r_root) = (
            joint_translation(&root, modes[0], row),
            joint_rotation(&root, row),
        );
        let t_child = joint_translation(&child, modes[c], row);
        let angles = [row[rot_cols[0]], row[rot_cols[1]], row[rot_cols[2]]];
        let root_turns = root
            .channels
            .iter()
            .enumerate()
            .any(|(n, ch)| ch.is_rotation() && row[root.first_channel + n] != 0.0);

        // composite, relative to the root at rest (translation = OFFSET, no rotation)
        let t = t_root + r_root * t_child - root.offset;
        let new_angles = if root_turns {
            let r = r_root * euler_to_matrix(order, angles.map(f64::to_radians));
            matrix_to_euler_near(order, &r, previous.map(f64::to_radians)).map(f64::to_degrees)
        } else {
            angles
        };
        previous = new_angles;

        let row = &mut bvh.motion[k * bvh.channel_count..(k + 1) * bvh.channel_count];
        for (n, ch) in root.channels.iter().enumerate() {
            row[root.first_channel + n] = match (ch.is_rotation(), modes[0]) {
                (true, _) | (false, ResolvedPosition::Add) => 0.0,
                (false, _) => root.offset[ch.axis()],
            };
        }
        set_channels(row, &child, modes[c], &t, new_angles);
    }
}

/// The frame columns of `joint`'s rotation channels, in file order.
fn rotation_columns(joint: &crate::io::bvh::BvhJoint) -> Vec<usize> {
    (joint.channels.iter().enumerate())
        .filter(|(_, ch)| ch.is_rotation())
        .map(|(n, _)| joint.first_channel + n)
        .collect()
}

/// Writes `joint`'s channels in `row` for the local translation `t` (file units, its position
/// channels under `mode`) and the Euler angles `angles` (degrees, in its rotation order).
fn set_channels(
    row: &mut [f64],
    joint: &crate::io::bvh::BvhJoint,
    mode: ResolvedPosition,
    t: &nalgebra::Vector3<f64>,
    angles: [f64; 3],
) {
    let mut r = 0;
    for (n, ch) in joint.channels.iter().enumerate() {
        let col = joint.first_channel + n;
        if ch.is_rotation() {
            row[col] = angles[r.min(2)];
            r += 1;
        } else {
            let a = ch.axis();
            row[col] = match mode {
                ResolvedPosition::Add => t[a] - joint.offset[a],
                _ => t[a],
            };
        }
    }
}

/// What folding changed, to undo it on output: the child it went into and the root's channel
/// values as the file had them (`frames × root channels`, row-major).
#[derive(Debug, Clone, PartialEq)]
pub struct Fold {
    pub child: usize,
    pub root_values: Vec<f64>,
}

impl Fold {
    /// Records the root's channels of `bvh` (before [`fold_root_into_child`]).
    pub fn record(bvh: &Bvh, child: usize) -> Fold {
        let root = &bvh.joints[0];
        let n = root.channels.len();
        let root_values = (0..bvh.frames)
            .flat_map(|k| bvh.frame(k)[root.first_channel..root.first_channel + n].to_vec())
            .collect();
        Fold { child, root_values }
    }
}

/// The inverse of [`fold_root_into_child`] on a folded take `bvh` (its frames possibly
/// rewritten since, e.g. smoothed): the root gets the file's channel values back, and the child
/// the local transform that keeps its world pose (`T_child = T_root⁻¹ · T_root,rest ·
/// T_child,folded`), so the root motion is on the top joint where the file had it (game
/// engines take root motion from there) and every joint's world pose is unchanged.
pub fn unfold_root(bvh: &mut Bvh, modes: &[ResolvedPosition], fold: &Fold) {
    let root = bvh.joints[0].clone();
    let c = fold.child;
    let child = bvh.joints[c].clone();
    let Some(order) = child.euler_order() else {
        return;
    };
    let rot_cols = rotation_columns(&child);
    let nr = root.channels.len();
    let mut previous = [0.0; 3];
    for k in 0..bvh.frames {
        let original = &fold.root_values[k * nr..(k + 1) * nr];
        let row = &mut bvh.motion[k * bvh.channel_count..(k + 1) * bvh.channel_count];
        // the folded child's world pose: the root rests at its OFFSET, unrotated
        let world = root.offset + joint_translation(&child, modes[c], row);
        let angles = [row[rot_cols[0]], row[rot_cols[1]], row[rot_cols[2]]];
        let r_child = euler_to_matrix(order, angles.map(f64::to_radians));
        row[root.first_channel..root.first_channel + nr].copy_from_slice(original);
        let (t_root, r_root) = (
            joint_translation(&root, modes[0], row),
            joint_rotation(&root, row),
        );
        let t = r_root.transpose() * (world - t_root);
        let new_angles = if original
            .iter()
            .zip(&root.channels)
            .any(|(v, ch)| ch.is_rotation() && *v != 0.0)
        {
            let r = r_root.transpose() * r_child;
            matrix_to_euler_near(order, &r, previous.map(f64::to_radians)).map(f64::to_degrees)
        } else {
            angles
        };
        previous = new_angles;
        set_channels(row, &child, modes[c], &t, new_angles);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::bvh::{self, PositionMode, bvh_world_positions, resolve_position_modes};

    fn take(root_rot: &str, hips_mode_values: &str) -> Bvh {
        let text = format!(
            "HIERARCHY\nROOT joint_Root\n{{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n  JOINT Hips\n  {{\n    OFFSET 0 90 -3\n    CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n    JOINT Leg\n    {{\n      OFFSET 10 -40 0\n      CHANNELS 3 Zrotation Xrotation Yrotation\n      End Site\n      {{\n        OFFSET 0 -40 0\n      }}\n    }}\n  }}\n}}\nMOTION\nFrames: 3\nFrame Time: 0.01\n\
             0 0 0 0 0 0 {h} 0 0 0\n\
             5 0 20 {r} {h} 10 20 30\n\
             10 1 40 {r} {h} 15 25 35\n",
            r = root_rot,
            h = hips_mode_values,
        );
        bvh::parse_str(&text, std::path::Path::new("fold.bvh")).unwrap()
    }

    fn check_same_world(before: &Bvh, after: &Bvh) {
        let modes = resolve_position_modes(before, PositionMode::Replace);
        for k in 0..before.frames {
            let a = bvh_world_positions(before, &modes, k);
            let b = bvh_world_positions(after, &modes, k);
            for (p, q) in a.iter().zip(&b).skip(1) {
                assert!((p - q).norm() < 1e-9, "frame {k}: {p} vs {q}");
            }
        }
    }

    #[test]
    fn folding_keeps_every_world_pose_and_stills_the_root() {
        for root_rot in ["0 0 0", "30 -20 45"] {
            let before = take(root_rot, "1 92 -2 5 -10 15");
            assert_eq!(redundant_root_child(&before), Some(1));
            let mut after = before.clone();
            let modes = resolve_position_modes(&before, PositionMode::Replace);
            fold_root_into_child(&mut after, &modes, 1);
            check_same_world(&before, &after);
            for k in 0..after.frames {
                assert_eq!(&after.frame(k)[..6], &[0.0; 6], "root still at frame {k}");
                // the leg's channels are untouched
                assert_eq!(&after.frame(k)[12..], &before.frame(k)[12..]);
            }
            if root_rot == "0 0 0" {
                // no root rotation: the hips' rotation channels are kept bit for bit
                for k in 0..after.frames {
                    assert_eq!(&after.frame(k)[9..12], &before.frame(k)[9..12]);
                }
            }
        }
    }

    #[test]
    fn unfolding_gives_the_file_back() {
        for (root_rot, mode) in [
            ("0 0 0", PositionMode::Replace),
            ("30 -20 45", PositionMode::Replace),
            ("10 0 0", PositionMode::Add),
        ] {
            let before = take(root_rot, "1 92 -2 5 -10 15");
            let modes = resolve_position_modes(&before, mode);
            let fold = Fold::record(&before, 1);
            let mut after = before.clone();
            fold_root_into_child(&mut after, &modes, 1);
            unfold_root(&mut after, &modes, &fold);
            for (a, b) in after.motion.iter().zip(&before.motion) {
                assert!((a - b).abs() < 1e-9, "{root_rot}: {a} vs {b}");
            }
        }
    }

    #[test]
    fn add_mode_children_fold_too() {
        let before = take("10 0 0", "1 2 -2 5 -10 15");
        let mut after = before.clone();
        let modes = resolve_position_modes(&before, PositionMode::Add);
        fold_root_into_child(&mut after, &modes, 1);
        for k in 0..before.frames {
            let a = bvh_world_positions(&before, &modes, k);
            let b = bvh_world_positions(&after, &modes, k);
            for (p, q) in a.iter().zip(&b).skip(1) {
                assert!((p - q).norm() < 1e-9, "frame {k}: {p} vs {q}");
            }
        }
    }

    #[test]
    fn only_a_root_with_one_full_child_is_redundant() {
        let text = "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n  JOINT Spine\n  {\n    OFFSET 0 10 0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n    End Site\n    {\n      OFFSET 0 10 0\n    }\n  }\n}\nMOTION\nFrames: 1\nFrame Time: 0.01\n0 0 0 0 0 0 0 0 0\n";
        let b = bvh::parse_str(text, std::path::Path::new("plain.bvh")).unwrap();
        assert_eq!(redundant_root_child(&b), None);
    }
}
