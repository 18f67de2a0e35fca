//! BVH channels ↔ generalized coordinates, frame by frame, through a [`BvhMap`].
//!
//! Conversions (the only place where BVH units meet SI): rotation channels are degrees and
//! become radians; position channels become `(value − rest) · scale_to_m` metres, `rest` being
//! the OFFSET component for position channels that replace it and 0 for those that add to it
//! (ARCHITECTURE.md, BVH semantics). In the ball model a joint's rotation channels
//! `c1 c2 c3` become the quaternion of `R = R_c1(a1)·R_c2(a2)·R_c3(a3)`.
//! Locked channels are held at rest (q = 0) and written back as their rest value.

use crate::error::Error;
use crate::io::bvh::Bvh;
use crate::io::bvh::joint_rotation;
use crate::model::Model;
use crate::model::bvh::BvhMap;
use crate::par;
use crate::rotation::matrix_to_euler_near;
use crate::spatial::{quat_from_xyzw, quat_to_xyzw};
use nalgebra::{Rotation3, UnitQuaternion};

/// A joint-space trajectory sampled at `time`.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// Sample times (s) on the file's clock ([`Bvh::time`]): from 0, or from the first kept
    /// frame's time when frames before it were dropped.
    pub time: Vec<f64>,
    /// One configuration (`nq` values, SI) per sample.
    pub q: Vec<Vec<f64>>,
}

impl Trajectory {
    /// The take's frames as configurations of `model`, with quaternions kept in one hemisphere
    /// from frame to frame (q and −q are the same rotation; a sign flip would look like a jump).
    /// [`q_columns`] by frame.
    pub fn from_bvh(bvh: &Bvh, model: &Model, map: &BvhMap) -> Trajectory {
        let n = bvh.frames;
        let cols = q_columns(bvh, model, map);
        let q = (0..n)
            .map(|k| (0..model.nq).map(|j| cols[j * n + k]).collect())
            .collect();
        Trajectory {
            time: (0..n).map(|k| bvh.time(k)).collect(),
            q,
        }
    }
}

/// Frames per block of [`q_columns`]: the block's rows stay in the cache while every channel
/// is copied out of them.
const BLOCK_FRAMES: usize = 64;

/// Pieces of frames per worker in [`q_columns`] (pieces of unequal speed keep every worker
/// busy; a fixed number, so the work allocates the same whatever the take's length).
const PIECES_PER_WORKER: usize = 4;

/// The take's frames as configurations of `model`, stored by coordinate: coordinate `j` of
/// frame `k` is `[j·frames + k]` (`nq × frames` values). Each frame is [`frame_to_q`] of its
/// row, bit for bit, with each quaternion turned into the hemisphere of the previous frame's.
/// The scalar channels are copied column by column over blocks of frames, pieces of the take
/// in parallel; the quaternions are made frame by frame.
pub fn q_columns(bvh: &Bvh, model: &Model, map: &BvhMap) -> Vec<f64> {
    let (n, nq, cc) = (bvh.frames, model.nq, bvh.channel_count);
    debug_assert_eq!(bvh.motion.len(), n * cc);
    let mut cols = vec![0.0; nq * n];
    if n == 0 {
        return cols;
    }
    // locked and unmapped coordinates: rest (the others are all written below)
    let mut rest = vec![0.0; nq];
    for i in 1..model.nbodies() {
        let joint = &model.joints[i];
        let iq = model.idx_q[i];
        joint.neutral(&mut rest[iq..iq + joint.nq()]);
    }
    let mut written = vec![false; nq];
    for j in &map.joints {
        for k in j.channels.iter().filter_map(|c| c.q) {
            written[k] = true;
        }
        if let Some(k) = j.quat_q {
            written[k..k + 4].fill(true);
        }
    }
    for ((col, &r), _) in cols
        .chunks_mut(n)
        .zip(&rest)
        .zip(&written)
        .filter(|x| !*x.1)
    {
        col.fill(r);
    }
    // channels: degrees → rad, lengths → m from the rest value; each piece of frames gets
    // its part of every column
    let pieces = (par::slots() * PIECES_PER_WORKER).min(n.div_ceil(BLOCK_FRAMES));
    let piece = n.div_ceil(pieces).next_multiple_of(BLOCK_FRAMES);
    let mut parts: Vec<Vec<&mut [f64]>> = (0..n.div_ceil(piece))
        .map(|_| Vec::with_capacity(nq))
        .collect();
    for col in cols.chunks_mut(n) {
        for (part, p) in parts.iter_mut().zip(col.chunks_mut(piece)) {
            part.push(p);
        }
    }
    let mut scratch = par::scratch(|| ());
    par::for_each_block(&mut parts, 1, &mut scratch, |_, first, block| {
        for part in block {
            copy_channels(bvh, map, first * piece, part);
        }
    });
    // quaternions [x, y, z, w], each in the previous frame's hemisphere
    for (j, bj) in map.joints.iter().zip(&bvh.joints) {
        let Some(k) = j.quat_q else { continue };
        let mut prev: Option<[f64; 4]> = None;
        for f in 0..n {
            let r = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(
                joint_rotation(bj, bvh.frame(f)),
            ));
            let mut x = [0.0; 4];
            quat_to_xyzw(&r, &mut x);
            if let Some(p) = prev {
                let dot: f64 = (0..4).map(|c| p[c] * x[c]).sum();
                if dot < 0.0 {
                    x.iter_mut().for_each(|x| *x = -*x);
                }
            }
            for (c, xc) in x.iter().enumerate() {
                cols[(k + c) * n + f] = *xc;
            }
            prev = Some(x);
        }
    }
    cols
}

/// The scalar channels of the frames from `first` on into `part` (one slice per coordinate,
/// of as many frames), block by block of [`BLOCK_FRAMES`] frames.
fn copy_channels(bvh: &Bvh, map: &BvhMap, first: usize, part: &mut [&mut [f64]]) {
    let cc = bvh.channel_count;
    let frames = part.first().map_or(0, |p| p.len());
    for start in (0..frames).step_by(BLOCK_FRAMES) {
        let end = (start + BLOCK_FRAMES).min(frames);
        let rows = &bvh.motion[(first + start) * cc..(first + end) * cc];
        for c in map.joints.iter().flat_map(|j| &j.channels) {
            let Some(k) = c.q else { continue };
            let col = &mut part[k][start..end];
            let values = rows[c.column..].iter().step_by(cc);
            if c.channel.is_rotation() {
                for (x, v) in col.iter_mut().zip(values) {
                    *x = v.to_radians();
                }
            } else {
                for (x, v) in col.iter_mut().zip(values) {
                    *x = (v - c.rest) * map.scale_to_m;
                }
            }
        }
    }
}

/// The configuration of `model` at one BVH frame row (`bvh.channel_count` raw values) into
/// `q` (`model.nq`). Allocates nothing.
pub fn frame_to_q(bvh: &Bvh, map: &BvhMap, model: &Model, frame: &[f64], q: &mut [f64]) {
    debug_assert_eq!(frame.len(), bvh.channel_count);
    debug_assert_eq!(q.len(), model.nq);
    // locked and unmapped coordinates: rest
    for i in 1..model.nbodies() {
        let joint = &model.joints[i];
        let iq = model.idx_q[i];
        joint.neutral(&mut q[iq..iq + joint.nq()]);
    }
    for (j, bj) in map.joints.iter().zip(&bvh.joints) {
        for c in &j.channels {
            if let Some(k) = c.q {
                q[k] = if c.channel.is_rotation() {
                    frame[c.column].to_radians()
                } else {
                    (frame[c.column] - c.rest) * map.scale_to_m
                };
            }
        }
        if let Some(k) = j.quat_q {
            let r = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(
                joint_rotation(bj, frame),
            ));
            quat_to_xyzw(&r, &mut q[k..k + 4]);
        }
    }
}

/// The inverse of [`frame_to_q`]: a BVH frame row (file units, degrees) from a configuration.
/// Locked channels get their rest value. Ball joints go back to the joint's Euler order with
/// [`matrix_to_euler_near`], nearest to the angles already in `frame` (pass the previous
/// frame's row for continuous, unwrapped angles; zeros otherwise).
///
/// Errors: a ball joint whose rotation channels are not three distinct axes (its quaternion has
/// no unique Euler angles in that layout).
pub fn q_to_frame(
    bvh: &Bvh,
    map: &BvhMap,
    model: &Model,
    q: &[f64],
    frame: &mut [f64],
) -> Result<(), Error> {
    debug_assert_eq!(frame.len(), bvh.channel_count);
    debug_assert_eq!(q.len(), model.nq);
    for (j, bj) in map.joints.iter().zip(&bvh.joints) {
        for c in &j.channels {
            frame[c.column] = match (c.q, c.channel.is_rotation()) {
                (Some(k), true) => q[k].to_degrees(),
                (Some(k), false) => q[k] / map.scale_to_m + c.rest,
                (None, _) => c.rest,
            };
        }
        if let Some(k) = j.quat_q {
            let order = bj.euler_order().ok_or_else(|| {
                Error::Invalid(format!(
                    "joint {:?} (line {}): a ball joint converts back to BVH only with three \
                     rotation channels on distinct axes; export the euler joint model",
                    bj.name, bj.line
                ))
            })?;
            let mut cols = [0usize; 3];
            for (n, c) in j
                .channels
                .iter()
                .filter(|c| c.channel.is_rotation())
                .enumerate()
            {
                cols[n] = c.column;
            }
            let previous = [0, 1, 2].map(|n| frame[cols[n]].to_radians());
            let r = quat_from_xyzw(&q[k..k + 4])
                .to_rotation_matrix()
                .into_inner();
            let angles = matrix_to_euler_near(order, &r, previous);
            for n in 0..3 {
                frame[cols[n]] = angles[n].to_degrees();
            }
        }
    }
    Ok(())
}
