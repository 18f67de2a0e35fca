//! Twist helpers inside a long bone, folded into the next joint.
//!
//! Rigs made for skinning put helper joints inside the long bones so that the skin twists
//! smoothly: MakeHuman's `upperleg02` between the hip (`upperleg01`) and the knee
//! (`lowerleg01`), `lowerleg02` above the ankle, `upperarm02`, `lowerarm02`; a `*Twist*`
//! bone. Such a helper carries no segment of its own (a segment runs from one landmark joint
//! to the next, `model::skeleton::inside_long_bones`). Given a share of the bone's mass, it
//! splits one rigid segment into two links; made massless as it should be, its rotation and
//! the next joint's move nothing with mass apart, and D(q) is singular (MakeHuman's
//! `lowerleg02.R` twist is undone by `foot.R`'s).
//!
//! [`fold_twists`] removes the helper's rotation: for a helper H whose only child is C, at
//! every frame C's rotation becomes `R_H · R_C` (in C's own Euler order, the triple nearest the
//! previous frame's) and H's the identity. The orientation of C and the pose of everything
//! below it are unchanged, except that C's position moves by `|R_H t_C − t_C|` (`t_C`, C's
//! translation from H): nothing when `R_H` turns about the bone (`R_H t_C = t_C`). A helper is
//! folded only when that displacement stays within [`TWIST_TOLERANCE_M`] at every frame; one
//! that bends the limb is kept as a joint, with its share of the bone's mass as before, and
//! named in the note. The model then welds a folded helper to its parent at rest, massless,
//! and gives its bone to the parent's link (`model::bvh::BvhModelOptions::folded`): the
//! segment is one rigid link, with the whole bone's centre of mass and inertia, as if the
//! helper were not there. The take's frames hold the folded motion, so BVH outputs write the
//! twist on the next joint.

use crate::io::bvh::{Bvh, ResolvedPosition, joint_rotation, joint_translation};
use crate::motion::weld::centimetres;
use crate::rotation::{euler_to_matrix, matrix_to_euler_near};
use nalgebra::Matrix3;

/// A helper is folded when its rotation moves the next joint by no more than this (m) at any
/// frame: a millimetre, well below capture error (`motion::weld::CAPTURE_ERROR_M`).
pub const TWIST_TOLERANCE_M: f64 = 0.001;

/// A joint inside a long bone, and what its rotation does to the next joint.
#[derive(Debug, Clone, PartialEq)]
pub struct Twist {
    /// The helper (index in `bvh.joints`).
    pub helper: usize,
    /// Its only child joint, which takes the helper's rotation when folded.
    pub child: usize,
    /// The largest displacement of the child's position by the helper's rotation over the
    /// frames, `max |R_H t_C − t_C|` (m).
    pub displacement_m: f64,
    /// The frame where it is largest.
    pub frame: usize,
    /// Whether the helper was folded (`displacement_m ≤ TWIST_TOLERANCE_M`).
    pub folded: bool,
}

/// The rotation columns of `joint` (file order).
fn rotation_columns(joint: &crate::io::bvh::BvhJoint) -> Vec<usize> {
    (joint.channels.iter().enumerate())
        .filter(|(_, ch)| ch.is_rotation())
        .map(|(n, _)| joint.first_channel + n)
        .collect()
}

/// Folds every helper of `candidates` (joints inside a long bone whose translation is fixed:
/// no position channels, or channels held by `motion::weld`) that has one child joint with
/// three rotation channels, no End Site, rotation channels of its own, and a rotation that
/// moves the child by at most [`TWIST_TOLERANCE_M`], into that child (see the module doc), in
/// `bvh`'s frames. Returns every such helper, folded or not, in file order. `modes` are the
/// resolved position modes (indexed like `bvh.joints`; empty: `add`), `scale_to_m` metres per
/// file unit.
pub fn fold_twists(
    bvh: &mut Bvh,
    modes: &[ResolvedPosition],
    scale_to_m: f64,
    candidates: &[usize],
) -> Vec<Twist> {
    let mode = |j: usize| modes.get(j).copied().unwrap_or(ResolvedPosition::Add);
    let mut sorted = candidates.to_vec();
    sorted.sort_unstable();
    sorted.dedup();
    let mut out = vec![];
    for h in sorted {
        let helper = bvh.joints[h].clone();
        let mut children = (0..bvh.joints.len()).filter(|&c| bvh.joints[c].parent == Some(h));
        let (Some(c), None) = (children.next(), children.next()) else {
            continue;
        };
        let child = bvh.joints[c].clone();
        let (h_cols, c_cols) = (rotation_columns(&helper), rotation_columns(&child));
        let Some(order) = child.euler_order() else {
            continue;
        };
        if !helper.end_sites.is_empty() || h_cols.is_empty() || c_cols.len() != 3 {
            continue;
        }
        // the child's largest displacement by the helper's rotation
        let (mut displacement, mut frame) = (0.0, 0);
        for k in 0..bvh.frames {
            let row = bvh.frame(k);
            let t = joint_translation(&child, mode(c), row);
            let d = (joint_rotation(&helper, row) * t - t).norm() * scale_to_m;
            if d > displacement {
                (displacement, frame) = (d, k);
            }
        }
        let folded = displacement <= TWIST_TOLERANCE_M;
        out.push(Twist {
            helper: h,
            child: c,
            displacement_m: displacement,
            frame,
            folded,
        });
        if !folded {
            continue;
        }
        // R_C ← R_H · R_C, R_H ← I (a helper that never turns leaves the child's angles as
        // they were, bit for bit)
        let mut previous = [0.0; 3];
        for k in 0..bvh.frames {
            let cc = bvh.channel_count;
            let row = &mut bvh.motion[k * cc..(k + 1) * cc];
            let r_h: Matrix3<f64> = joint_rotation(&helper, row);
            let angles = [row[c_cols[0]], row[c_cols[1]], row[c_cols[2]]];
            let new = if h_cols.iter().any(|&col| row[col] != 0.0) {
                let r = r_h * euler_to_matrix(order, angles.map(f64::to_radians));
                matrix_to_euler_near(order, &r, previous.map(f64::to_radians)).map(f64::to_degrees)
            } else {
                angles
            };
            previous = new;
            for (col, a) in c_cols.iter().zip(new) {
                row[*col] = a;
            }
            for &col in &h_cols {
                row[col] = 0.0;
            }
        }
    }
    out
}

/// The folded helpers (BVH joint indices), as `model::bvh::BvhModelOptions::folded` takes them.
pub fn folded(twists: &[Twist]) -> Vec<usize> {
    twists
        .iter()
        .filter(|t| t.folded)
        .map(|t| t.helper)
        .collect()
}

/// What folding did, for `info`: the helpers folded into the next joint (and how far that
/// moved it at most), and those kept as joints because they bend the limb. `None` when the
/// skeleton has no joint inside a long bone.
pub fn note(bvh: &Bvh, twists: &[Twist]) -> Option<String> {
    if twists.is_empty() {
        return None;
    }
    let name = |j: usize| bvh.joints[j].name.as_str();
    let (folded, kept): (Vec<&Twist>, Vec<&Twist>) = twists.iter().partition(|t| t.folded);
    let mut parts = vec![];
    if let Some(largest) = folded
        .iter()
        .map(|t| t.displacement_m)
        .max_by(f64::total_cmp)
    {
        parts.push(format!(
            "twist helpers inside a long bone folded into the next joint, massless, their bone \
             part of the segment's link (the next joint takes their rotation, a turn about the \
             bone; it moves by at most {}; BVH outputs write the twist on it): {}",
            centimetres(largest),
            folded
                .iter()
                .map(|t| format!("`{}` into `{}`", name(t.helper), name(t.child)))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    if !kept.is_empty() {
        parts.push(format!(
            "joints inside a long bone kept as joints with a share of its mass (their rotation \
             moves the next joint by more than {}, so it is no twist about the bone): {}",
            centimetres(TWIST_TOLERANCE_M),
            kept.iter()
                .map(|t| format!(
                    "`{}` {} at frame {}",
                    name(t.helper),
                    centimetres(t.displacement_m),
                    t.frame
                ))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    Some(parts.join("; "))
}

#[cfg(test)]
mod tests {
    //! Folding a twist keeps every world pose below the helper (the child's position within the
    //! displacement the note reports); a helper that bends the limb is kept.

    use super::*;
    use crate::io::bvh::{self, bvh_world_poses};

    /// A leg: `Hip` → `Twist` (a helper halfway down the femur, turning about it) → `Knee` →
    /// End Site, over three frames; the knee bends about X.
    fn leg(twist_axis: &str) -> Bvh {
        let text = format!(
            "HIERARCHY\nROOT Hip\n{{\n OFFSET 0 90 0\n CHANNELS 6 Xposition Yposition \
             Zposition Zrotation Xrotation Yrotation\n JOINT Twist\n {{\n  OFFSET 0 -20 0\n  \
             CHANNELS 3 Zrotation Xrotation Yrotation\n  JOINT Knee\n  {{\n   OFFSET 0 -20 0\n   \
             CHANNELS 3 Zrotation Xrotation Yrotation\n   End Site\n   {{\n    OFFSET 0 -40 0\n   \
             }}\n  }}\n }}\n}}\nMOTION\nFrames: 3\nFrame Time: 0.1\n\
             0 90 0 5 10 0 {a0} 0 10 20\n\
             1 90 0 0 15 5 {a1} 5 40 -10\n\
             2 90 0 -5 20 10 {a2} 0 60 0\n",
            a0 = twist(twist_axis, 0.0),
            a1 = twist(twist_axis, 25.0),
            a2 = twist(twist_axis, -40.0),
        );
        bvh::parse_str(&text, std::path::Path::new("leg.bvh")).unwrap()
    }

    /// The helper's Z X Y channel values for a turn of `deg` about the named axis.
    fn twist(axis: &str, deg: f64) -> String {
        match axis {
            "y" => format!("0 0 {deg}"),
            _ => format!("0 {deg} 0"),
        }
    }

    #[test]
    fn a_twist_about_the_bone_moves_into_the_next_joint_and_every_pose_stays() {
        let mut b = leg("y");
        let add = [ResolvedPosition::Add; 3];
        let before: Vec<_> = (0..3).map(|k| bvh_world_poses(&b, &add, k)).collect();
        let t = fold_twists(&mut b, &add, 0.01, &[1]);
        assert_eq!(t.len(), 1);
        assert!(t[0].folded && t[0].child == 2 && t[0].displacement_m < 1e-12);
        for (k, (pos, rot)) in before.iter().enumerate() {
            let (p, r) = bvh_world_poses(&b, &add, k);
            for j in 0..3 {
                assert!((p[j] - pos[j]).norm() < 1e-9, "joint {j} frame {k}");
            }
            // the knee and below keep their orientation; the helper now follows the hip
            assert!((r[2] - rot[2]).norm() < 1e-12, "frame {k}");
            assert!((r[1] - r[0]).norm() < 1e-12, "frame {k}");
            assert!(b.frame(k)[6..9].iter().all(|&a| a == 0.0));
        }
        assert_eq!(folded(&t), [1]);
        let n = note(&b, &t).unwrap();
        assert!(n.contains("`Twist` into `Knee`"), "{n}");
    }

    #[test]
    fn a_helper_that_bends_the_limb_is_kept_and_named() {
        let mut b = leg("x");
        let before = b.motion.clone();
        let t = fold_twists(&mut b, &[], 0.01, &[1]);
        // a 40° bend at 20 cm from the knee moves it by 2 · 20 cm · sin 20° ≈ 13.7 cm
        assert!(!t[0].folded && t[0].frame == 2);
        let expected = 2.0 * 0.2 * 20f64.to_radians().sin();
        assert!((t[0].displacement_m - expected).abs() < 1e-12);
        assert_eq!(b.motion, before);
        assert!(folded(&t).is_empty());
        let n = note(&b, &t).unwrap();
        assert!(n.contains("`Twist` 13.7 cm at frame 2"), "{n}");
        // a joint without a child joint (the knee ends in an End Site) is no helper
        assert!(fold_twists(&mut b, &[], 0.01, &[2]).is_empty());
    }
}
