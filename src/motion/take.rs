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
    pub fn from_bvh(bvh: &Bvh, model: &Model, map: &BvhMap) -> Trajectory {
        let mut q: Vec<Vec<f64>> = Vec::with_capacity(bvh.frames);
        for k in 0..bvh.frames {
            let mut row = vec![0.0; model.nq];
            frame_to_q(bvh, map, model, bvh.frame(k), &mut row);
            if let Some(prev) = q.last() {
                for j in &map.joints {
                    if let Some(iq) = j.quat_q {
                        let dot: f64 = (0..4).map(|c| prev[iq + c] * row[iq + c]).sum();
                        if dot < 0.0 {
                            row[iq..iq + 4].iter_mut().for_each(|x| *x = -*x);
                        }
                    }
                }
            }
            q.push(row);
        }
        Trajectory {
            time: (0..bvh.frames).map(|k| bvh.time(k)).collect(),
            q,
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
