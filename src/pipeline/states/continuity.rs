//! Stage 5's Euler branches: an euler joint's three angles re-picked, frame by frame, as the
//! equivalent triple nearest the previous frame's, and notes for the joints that sit near or
//! pass near gimbal lock, or turn faster than any joint (a capture glitch).

use super::Columns;
use crate::io::bvh::Bvh;
use crate::model::bvh::BvhMap;
use crate::par::{self, for_each_block};
use crate::rotation::EulerOrder;

/// A turn of more than 90° in one frame is a capture glitch only this fast (rad/s): 90° a
/// frame at 20 fps. Slower, it is a keyframed or low-rate take's ordinary step.
const GLITCH_SPEED: f64 = 1800.0 * std::f64::consts::PI / 180.0;

/// An Euler triple whose middle angle is within this of ±90° is near gimbal lock (rad).
const NEAR_LOCK: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// An euler joint's three rotation coordinates, to be made continuous, and what was noted.
struct Triple<'a> {
    joint: usize,
    order: EulerOrder,
    cols: [&'a mut [f64]; 3],
    notes: Vec<String>,
}

/// Euler model: where a joint's three rotation channels flip to the other Tait–Bryan branch
/// near a singularity (or jump by whole turns), re-picks for every frame the equivalent triple
/// nearest the previous frame (`motion::unwrap::make_euler_continuous`). The rotation of every
/// frame is unchanged; only its coordinates become continuous.
///
/// Returns a note for each joint whose continuous triple still passes near gimbal lock
/// (`motion::unwrap::scan_triples`): there its coordinates turn much faster than the joint,
/// and the euler model's velocities, accelerations and torques spike; the ball model has no
/// such coordinates. And one for each joint that turns more than 90° in one frame (a capture
/// glitch).
pub fn make_euler_triples_continuous(bvh: &Bvh, map: &BvhMap, q: &mut [Vec<f64>]) -> Vec<String> {
    let nq = q.first().map_or(0, Vec::len);
    let mut cols = Columns::of_rows(q, nq);
    let notes = euler_continuity(bvh, map, &mut cols);
    cols.to_rows(q);
    notes
}

/// [`make_euler_triples_continuous`] on columns, joints in parallel.
pub(super) fn euler_continuity(bvh: &Bvh, map: &BvhMap, cols: &mut Columns) -> Vec<String> {
    let n = cols.frames;
    let mut slots = cols.each_mut();
    let mut triples: Vec<Triple> = vec![];
    for (j, (joint, jm)) in bvh.joints.iter().zip(&map.joints).enumerate() {
        let (Some(order), None) = (joint.euler_order(), jm.quat_q) else {
            continue;
        };
        let idx: Vec<usize> = jm
            .channels
            .iter()
            .filter(|c| c.channel.is_rotation())
            .filter_map(|c| c.q)
            .collect();
        let [i0, i1, i2] = idx[..] else {
            continue; // a locked or partial rotation: nothing to re-pick
        };
        let (Some(c0), Some(c1), Some(c2)) = (
            slots[i0].take(),
            slots.get_mut(i1).and_then(Option::take),
            slots.get_mut(i2).and_then(Option::take),
        ) else {
            continue;
        };
        triples.push(Triple {
            joint: j,
            order,
            cols: [c0, c1, c2],
            notes: vec![],
        });
    }
    for_each_block(&mut triples, 1, &mut par::scratch(|| ()), |_, _, block| {
        for t in block {
            continuous_triple(bvh, t, n);
        }
    });
    triples.into_iter().flat_map(|t| t.notes).collect()
}

/// One joint of [`euler_continuity`] (`n` frames): re-picks its triples and notes its
/// passages and jumps.
fn continuous_triple(bvh: &Bvh, t: &mut Triple, n: usize) {
    let [c0, c1, c2] = &mut t.cols;
    let order = t.order;
    let name = &bvh.joints[t.joint].name;
    let scan = crate::motion::unwrap::make_euler_columns_continuous_and_scan(
        order,
        [&mut c0[..], &mut c1[..], &mut c2[..]],
    );
    // sitting near the lock (not passing through it) makes D(q) nearly singular all along
    let near = c1.iter().filter(|&&a2| near_lock(a2)).count();
    if scan.passage.is_none() && near * 100 >= n {
        t.notes.push(format!(
            "`{name}` sits within {:.0}° of gimbal lock in {:.0} % of the frames (its middle \
             {order} angle near ±90°): the euler model's mass matrix is nearly singular \
             there and `simulate` may fail; use the ball joint model (`--joints ball`, `set \
             joints ball`)",
            NEAR_LOCK.to_degrees(),
            100.0 * near as f64 / n as f64
        ));
    }
    if let Some(p) = scan.passage {
        t.notes.push(format!(
            "`{name}` passes near gimbal lock between frames {} and {}: its {order} angles turn \
             {:.0}° in one frame while the joint turns {:.1}°, so the euler model's torques \
             spike there; use the ball joint model (`--joints ball`, `set joints ball`)",
            p.frame,
            p.frame + 1,
            p.coordinate_step.to_degrees(),
            p.rotation_step.to_degrees()
        ));
    }
    // a keyframed take at 1 fps turns 96° between keys at an ordinary 96°/s
    if let Some((frame, angle)) = scan.jump
        && angle / bvh.frame_time > GLITCH_SPEED
    {
        t.notes.push(format!(
            "`{name}` turns {:.0}° between frames {frame} and {} ({:.0}°/s): no joint does \
             that, a capture glitch (a marker or solver swap) does; torques near it are not \
             physical",
            angle.to_degrees(),
            frame + 1,
            angle.to_degrees() / bvh.frame_time
        ));
    }
}

/// `|cos a2| < sin(NEAR_LOCK)`: the middle angle `a2` within [`NEAR_LOCK`] of gimbal lock.
/// Decided by the angle's distance from the lock
/// ([`lock_distance`](crate::motion::unwrap::lock_distance)) without a cosine, unless that
/// lies within 1e-9 rad of `NEAR_LOCK`, where the cosine decides as it always has.
fn near_lock(a2: f64) -> bool {
    match crate::motion::unwrap::lock_distance(a2) {
        Some(e) if (e - NEAR_LOCK).abs() > 1e-9 => e < NEAR_LOCK,
        _ => a2.cos().abs() < NEAR_LOCK.sin(),
    }
}
