//! A rest pose stored as the first frame of a take, found and dropped.
//!
//! Takes converted from the CMU motion-capture database (its ASF/AMC files turned into BVH, as
//! by the Motionbuilder-friendly and Daz-friendly conversions, and takes retargeted from them)
//! often start with the skeleton's rest pose as frame 0: the root where the motion starts (or
//! at the rest position) and every joint at its rest rotation, followed by the capture from
//! frame 1. The jump from frame 0 to frame 1 is then a step of tens of degrees in one frame
//! time; smoothing spreads it over the first ~0.1 s as a burst of acceleration (several body
//! weights at the root of CMU 01_01) that no motion made.
//!
//! Test (per take, on the raw channels): the step between frames `k` and `k + 1` is measured
//! as the RMS over all rotation channels of the change (degrees, wrapped into ±180°) and,
//! separately, as the length of the root's position change (file units). Frame 0 is a rest
//! pose when, for either measure, the step from frame 0 is more than [`JUMP_RATIO`] times the
//! take's median step and more than [`NEXT_RATIO`] times the step from frame 1 (the capture
//! itself is continuous from frame 1 on). On the takes of the real suite the ratio to the
//! median is 29–58 for the takes that start with a rest pose and below 1 for all others.

use crate::io::bvh::Bvh;
use crate::par;

/// Frame 0 is a rest pose when its step is this many times the median step (and see
/// [`NEXT_RATIO`]). Measured: 11–58 on the CMU-derived takes (rotations or root position),
/// ≤ 1 on the others.
pub const JUMP_RATIO: f64 = 8.0;

/// … and this many times the step from frame 1 to frame 2.
pub const NEXT_RATIO: f64 = 3.0;

/// The steps out of frame 0 that made it a rest pose (what `articula info` reports).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RestFrame {
    /// RMS rotation-channel step from frame 0 to 1 over the take's median step.
    pub rotation_ratio: f64,
    /// Root position step from frame 0 to 1 over the take's median step (0 without position
    /// channels or without a step, infinite when only frame 0 steps).
    pub position_ratio: f64,
}

/// The per-frame steps `(rotation RMS in degrees, root position length)` between consecutive
/// frames `k` and `k + 1`.
fn steps(bvh: &Bvh) -> Vec<(f64, f64)> {
    let mut rot = vec![];
    let mut pos = vec![];
    for j in &bvh.joints {
        for (c, ch) in j.channels.iter().enumerate() {
            if ch.is_rotation() {
                rot.push(j.first_channel + c);
            } else if j.parent.is_none() {
                pos.push(j.first_channel + c);
            }
        }
    }
    let step = |k: usize| {
        let (a, b) = (bvh.frame(k), bvh.frame(k + 1));
        let change = |i: usize| (wrap_360(b[i] - a[i] + 180.0) - 180.0).powi(2);
        // four partial sums side by side: one running sum waited on each addition's latency
        // (93 in a row per frame of a CMU take)
        let fours = rot.chunks_exact(4);
        let rest: f64 = fours.remainder().iter().map(|&i| change(i)).sum();
        let mut part = [0.0; 4];
        for c in fours {
            for (p, &i) in part.iter_mut().zip(c) {
                *p += change(i);
            }
        }
        let r2 = ((part[0] + part[1]) + (part[2] + part[3])) + rest;
        let p2: f64 = pos.iter().map(|&i| (b[i] - a[i]).powi(2)).sum();
        ((r2 / rot.len().max(1) as f64).sqrt(), p2.sqrt())
    };
    // frames in parallel, each step the same operations whatever its thread
    let mut out = vec![(0.0, 0.0); bvh.frames.saturating_sub(1)];
    let mut scratch = par::scratch(|| ());
    par::for_each_block(&mut out, STEP_BLOCK, &mut scratch, |_, first, block| {
        for (d, x) in block.iter_mut().enumerate() {
            *x = step(first + d);
        }
    });
    out
}

/// Frames per block of [`steps`].
const STEP_BLOCK: usize = 512;

/// `x.rem_euclid(360.0)` bit for bit, without the library's `fmod` in the common case
/// `0 ≤ x < 360` (a step of less than half a turn), where it is `x` itself.
#[inline]
fn wrap_360(x: f64) -> f64 {
    if (0.0..360.0).contains(&x) {
        x
    } else {
        x.rem_euclid(360.0)
    }
}

/// The element at `len / 2` of `x` sorted by `total_cmp` (selected, not sorted).
fn median(mut x: Vec<f64>) -> f64 {
    let mid = x.len() / 2;
    *x.select_nth_unstable_by(mid, f64::total_cmp).1
}

/// Whether frame 0 of `bvh` is a rest pose that does not belong to the motion (see the module
/// documentation); `None` for takes of fewer than 4 frames and takes whose frame 0 is continuous
/// with the rest.
pub fn rest_first_frame(bvh: &Bvh) -> Option<RestFrame> {
    if bvh.frames < 4 || bvh.motion.len() < bvh.frames * bvh.channel_count {
        return None;
    }
    let s = steps(bvh);
    let med_r = median(s[1..].iter().map(|x| x.0).collect());
    let med_p = median(s[1..].iter().map(|x| x.1).collect());
    let ratio = |x: f64, med: f64| match (med > 0.0, x > 0.0) {
        (true, _) => x / med,
        (false, true) => f64::INFINITY,
        (false, false) => 0.0,
    };
    let found = RestFrame {
        rotation_ratio: ratio(s[0].0, med_r),
        position_ratio: ratio(s[0].1, med_p),
    };
    let jumps = |first: f64, next: f64, r: f64| r > JUMP_RATIO && first > NEXT_RATIO * next;
    (jumps(s[0].0, s[1].0, found.rotation_ratio) || jumps(s[0].1, s[1].1, found.position_ratio))
        .then_some(found)
}

/// Drops frame 0 of `bvh` (the frame time and everything else unchanged; the kept frames keep
/// the file's times, [`Bvh::first_frame`] counts the dropped one). Takes of one frame are left
/// as they are.
pub fn drop_first_frame(bvh: &mut Bvh) {
    if bvh.frames > 1 {
        bvh.motion.drain(..bvh.channel_count.min(bvh.motion.len()));
        let n = bvh.channel_count.min(bvh.decimals.len());
        bvh.decimals.drain(..n);
        bvh.frames -= 1;
        bvh.first_frame += 1;
    }
}

/// Drops frame 0 when it is a rest pose ([`rest_first_frame`]); returns what was found.
pub fn trim_rest_first_frame(bvh: &mut Bvh) -> Option<RestFrame> {
    let found = rest_first_frame(bvh)?;
    drop_first_frame(bvh);
    Some(found)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_360_is_rem_euclid_bit_for_bit() {
        for x in [
            0.0,
            -0.0,
            1e-300,
            179.5,
            359.99999999999994,
            360.0,
            360.5,
            -1e-300,
            -0.5,
            -360.0,
            -725.25,
            1e9,
            f64::NAN,
        ] {
            assert_eq!(wrap_360(x).to_bits(), x.rem_euclid(360.0).to_bits(), "{x}");
        }
    }
    use crate::io::bvh::parse_str;
    use std::path::Path;

    /// A two-joint take: a root swaying and a knee bending smoothly, 60 frames at 60 fps,
    /// optionally preceded by a rest frame (all rotations 0, root at `rest_y`).
    fn take(rest: Option<f64>) -> Bvh {
        let mut rows = vec![];
        if let Some(y) = rest {
            rows.push(format!("0 {y} 0 0 0 0 0 0 0"));
        }
        for k in 0..60 {
            let t = k as f64 / 60.0;
            let s = (2.0 * std::f64::consts::PI * t).sin();
            rows.push(format!(
                "{} 90 {} {} 5 {} {} 0 0",
                2.0 * s,
                100.0 * t,
                10.0 + 3.0 * s,
                -4.0 * s,
                30.0 + 20.0 * s
            ));
        }
        let text = format!(
            "HIERARCHY\nROOT Hips\n{{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition \
             Zrotation Xrotation Yrotation\n JOINT Knee\n {{\n  OFFSET 0 -45 0\n  CHANNELS 3 \
             Zrotation Xrotation Yrotation\n  End Site\n  {{\n   OFFSET 0 -45 0\n  }}\n }}\n}}\n\
             MOTION\nFrames: {}\nFrame Time: 0.0166667\n{}\n",
            rows.len(),
            rows.join("\n")
        );
        parse_str(&text, Path::new("rest.bvh")).unwrap()
    }

    #[test]
    fn a_rest_pose_before_the_motion_is_found_and_dropped() {
        let mut with = take(Some(90.0));
        let found = rest_first_frame(&with).expect("rest frame");
        assert!(found.rotation_ratio > JUMP_RATIO, "{found:?}");
        let without = take(None);
        assert_eq!(trim_rest_first_frame(&mut with), Some(found));
        // the same frames, on the file's clock: the first kept one is the file's frame 1
        assert_eq!(with.first_frame, 1);
        assert_eq!(with.time(0), with.frame_time);
        assert_eq!(
            Bvh {
                first_frame: 0,
                ..with
            },
            without
        );
    }

    /// The steps summed four channels at a time are the steps' definition: every rotation
    /// channel's change wrapped into ±180°, their mean square's root, and the root's
    /// displacement (six rotation channels here: one group of four and two left over).
    #[test]
    fn steps_are_the_rms_rotation_change_and_the_root_displacement() {
        let mut bvh = take(Some(90.0));
        // every channel moving, some across ±180°
        let n = bvh.channel_count;
        for (k, row) in bvh.motion.chunks_mut(n).enumerate() {
            for (c, x) in row.iter_mut().enumerate() {
                *x += (k * (c + 1)) as f64 * 7.3 % 400.0 - 200.0;
            }
        }
        let got = steps(&bvh);
        assert_eq!(got.len(), bvh.frames - 1);
        for (k, &(r, p)) in got.iter().enumerate() {
            let (a, b) = (bvh.frame(k), bvh.frame(k + 1));
            let wrapped = |i: usize| (b[i] - a[i] + 180.0).rem_euclid(360.0) - 180.0;
            let rot: Vec<f64> = (3..9).map(wrapped).collect();
            let want_r = (rot.iter().map(|x| x * x).sum::<f64>() / 6.0).sqrt();
            let want_p = (0..3).map(|i| (b[i] - a[i]).powi(2)).sum::<f64>().sqrt();
            assert!(
                (r - want_r).abs() <= 1e-12 * want_r.max(1.0),
                "{k}: {r} {want_r}"
            );
            assert!(
                (p - want_p).abs() <= 1e-12 * want_p.max(1.0),
                "{k}: {p} {want_p}"
            );
        }
    }

    #[test]
    fn a_rest_pose_that_only_moves_the_root_is_found() {
        // rotations continuous (the first frame copies the second's) but the root jumps
        let mut t = take(Some(90.0));
        let n = t.channel_count;
        let second: Vec<f64> = t.frame(1).to_vec();
        t.motion[3..n].copy_from_slice(&second[3..]);
        t.motion[1] = 60.0;
        let found = rest_first_frame(&t).expect("rest frame");
        assert!(found.position_ratio > JUMP_RATIO && found.rotation_ratio < 1.0);
    }

    #[test]
    fn continuous_takes_keep_their_first_frame() {
        assert_eq!(rest_first_frame(&take(None)), None);
        // a still take (no steps at all) and a short one
        let mut still = take(None);
        let (n, first) = (still.channel_count, still.frame(0).to_vec());
        for row in still.motion.chunks_mut(n) {
            row.copy_from_slice(&first);
        }
        assert_eq!(rest_first_frame(&still), None);
        let mut short = take(Some(90.0));
        short.frames = 3;
        short.motion.truncate(3 * short.channel_count);
        assert_eq!(rest_first_frame(&short), None);
    }
}
