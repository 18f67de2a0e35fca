//! Stages 5–7 of a take: channels → q, unwrapped (Euler branches and turns), smoothed, then v
//! and a. Coordinates are worked on as columns (one contiguous run of frames per coordinate,
//! a joint's coordinates side by side), joints and frames in parallel ([`super::par`]); every
//! column and every frame computes what the serial path computes, in the same order, so the
//! results do not depend on the number of threads.

use super::States;
use super::stages::Stage;
use crate::error::Error;
use crate::io::bvh::Bvh;
use crate::model::bvh::BvhMap;
use crate::model::{EulerTriple, JointKind, Model};
use crate::motion::euler::{TripleScratch, at_gimbal_lock, smooth_triple, triple_rates};
use crate::motion::smooth::{SmoothSpec, Smoother};
use crate::motion::unwrap::{AngleUnit, unwrap_angles};
use crate::par::{self, for_each_block, rounds};
use crate::rotation::EulerOrder;
use nalgebra::{Quaternion, UnitQuaternion};

/// A turn of more than 90° in one frame is a capture glitch only this fast (rad/s): 90° a
/// frame at 20 fps. Slower, it is a keyframed or low-rate take's ordinary step.
const GLITCH_SPEED: f64 = 1800.0 * std::f64::consts::PI / 180.0;

/// An Euler triple whose middle angle is within this of ±90° is near gimbal lock (rad).
const NEAR_LOCK: f64 = 5.0 * std::f64::consts::PI / 180.0;

/// Stages 5–7: channels → q (unwrapped), smoothed, then v and a.
pub fn take_states(
    bvh: &Bvh,
    model: &Model,
    map: &BvhMap,
    smooth: &SmoothSpec,
) -> Result<States, Error> {
    take_states_with(bvh, model, map, smooth, &mut |_| true).map(|(s, _)| s)
}

/// [`take_states`] with progress and cancel ([`unwrap_and_smooth_with`]; the derivatives are
/// the last tenth), and a note for each euler joint that passes near gimbal lock or jumps
/// ([`make_euler_triples_continuous`]).
pub fn take_states_with(
    bvh: &Bvh,
    model: &Model,
    map: &BvhMap,
    smooth: &SmoothSpec,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<(States, Vec<String>), Error> {
    take_states_marked(bvh, model, map, smooth, keep_going, &mut |_| {})
}

/// [`take_states_with`] that calls `done` at the end of each of its stages
/// ([`Stage::Coordinates`], [`Stage::Unwrap`], [`Stage::Smooth`], [`Stage::Derivatives`]).
pub fn take_states_marked(
    bvh: &Bvh,
    model: &Model,
    map: &BvhMap,
    smooth: &SmoothSpec,
    keep_going: &mut dyn FnMut(f64) -> bool,
    done: &mut dyn FnMut(Stage),
) -> Result<(States, Vec<String>), Error> {
    let n = bvh.frames;
    let mut cols = Columns {
        frames: n,
        data: crate::motion::take::q_columns(bvh, model, map),
    };
    done(Stage::Coordinates);
    let dt = bvh.frame_time;
    let triples = model.euler_triples();
    let mut notes = euler_continuity(bvh, map, &mut cols);
    unwrap_revolute(model, &mut cols);
    done(Stage::Unwrap);
    let rotations = smooth_columns(model, &triples, &mut cols, dt, smooth, &mut |f| {
        keep_going(0.9 * f)
    })?;
    done(Stage::Smooth);
    if !keep_going(0.9) {
        return Err(Error::Cancelled);
    }
    let (v, a, locked) = derivative_columns(model, &triples, &cols, Some(&rotations), dt);
    notes.extend(locked.iter().map(|&(b, frames)| {
        let joint = bvh_joint_name(bvh, map, model.idx_q[b]);
        format!(
            "`{joint}` reaches gimbal lock at {frames} frame(s) (its middle angle within \
             0.00001° of ±90°): there its rates cannot come from its rotation, so its \
             velocities and accelerations are its angles' differences, which may spike; use \
             the ball joint model (`--joints ball`, `set joints ball`)"
        )
    }));
    let states = States {
        time: (0..n).map(|k| bvh.time(k)).collect(),
        q: cols.rows(),
        v: v.rows(),
        a: a.rows(),
    };
    done(Stage::Derivatives);
    Ok((states, notes))
}

/// The name of the BVH joint whose rotation channel sets coordinate `iq` (an euler joint's
/// first hinge).
fn bvh_joint_name<'a>(bvh: &'a Bvh, map: &BvhMap, iq: usize) -> &'a str {
    map.joints
        .iter()
        .position(|jm| jm.channels.iter().any(|c| c.q == Some(iq)))
        .map_or("?", |j| bvh.joints[j].name.as_str())
}

/// The rotation of every euler joint ([`Model::euler_triples`], in that order) at every
/// frame, as [`smooth_triple`] leaves it (smoothed): triple `t`'s frames are
/// `data[t·frames .. (t+1)·frames]`. The derivatives take the joints' rates from these, not
/// from rotations rebuilt from the angles written back.
struct TripleRotations {
    frames: usize,
    data: Vec<UnitQuaternion<f64>>,
}

impl TripleRotations {
    /// Room for `triples` joints of `frames` frames.
    fn new(triples: usize, frames: usize) -> Self {
        Self {
            frames,
            data: vec![UnitQuaternion::identity(); triples * frames],
        }
    }

    /// Triple `t`'s rotations.
    fn of(&self, t: usize) -> &[UnitQuaternion<f64>] {
        &self.data[t * self.frames..(t + 1) * self.frames]
    }
}

/// Configurations stored by coordinate: column `j` (every frame of coordinate `j`) is
/// `data[j·frames .. (j+1)·frames]`, so a joint's coordinates are one contiguous slice.
struct Columns {
    frames: usize,
    data: Vec<f64>,
}

impl Columns {
    /// The columns of `rows` (`frames × nq`), filled in parallel.
    fn of_rows(rows: &[Vec<f64>], nq: usize) -> Self {
        let frames = rows.len();
        let mut data = vec![0.0; nq * frames];
        if frames > 0 {
            let block = frames * par::even_block(nq);
            for_each_block(
                &mut data,
                block,
                &mut par::scratch(|| ()),
                |_, first, chunk| {
                    for (c, col) in chunk.chunks_mut(frames).enumerate() {
                        let j = first / frames + c;
                        for (x, row) in col.iter_mut().zip(rows) {
                            *x = row[j];
                        }
                    }
                },
            );
        }
        Self { frames, data }
    }

    /// Writes the columns back into `rows`, in parallel over frames; within a worker's frames,
    /// a few dozen rows at a time, column by column (each column read in one run while those
    /// rows stay in the cache).
    fn to_rows(&self, rows: &mut [Vec<f64>]) {
        const ROWS_AT_ONCE: usize = 32;
        let (n, data) = (self.frames, &self.data);
        let block = par::even_block(rows.len());
        for_each_block(rows, block, &mut par::scratch(|| ()), |_, first, chunk| {
            for (b, some) in chunk.chunks_mut(ROWS_AT_ONCE).enumerate() {
                let k0 = first + b * ROWS_AT_ONCE;
                let width = some.first().map_or(0, Vec::len);
                for j in 0..width {
                    let col = &data[j * n + k0..j * n + k0 + some.len()];
                    for (row, x) in some.iter_mut().zip(col) {
                        row[j] = *x;
                    }
                }
            }
        });
    }

    /// The rows (`frames × columns`), made in parallel over frames.
    fn rows(&self) -> Vec<Vec<f64>> {
        let width = self.data.len().checked_div(self.frames).unwrap_or(0);
        let mut rows = vec![vec![0.0; width]; self.frames];
        self.to_rows(&mut rows);
        rows
    }

    /// Column `j`.
    fn col(&self, j: usize) -> &[f64] {
        &self.data[j * self.frames..(j + 1) * self.frames]
    }

    /// One mutable slice per column.
    fn each_mut(&mut self) -> Vec<Option<&mut [f64]>> {
        if self.frames == 0 {
            return vec![];
        }
        self.data.chunks_mut(self.frames).map(Some).collect()
    }
}

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
fn euler_continuity(bvh: &Bvh, map: &BvhMap, cols: &mut Columns) -> Vec<String> {
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

/// Unwraps every revolute coordinate (±2π jumps), columns in parallel.
fn unwrap_revolute(model: &Model, cols: &mut Columns) {
    let mut revolute: Vec<&mut [f64]> = vec![];
    let mut slots = cols.each_mut();
    for i in 1..model.nbodies() {
        if matches!(model.joints[i], JointKind::Revolute { .. })
            && let Some(c) = slots[model.idx_q[i]].take()
        {
            revolute.push(c);
        }
    }
    let block = par::even_block(revolute.len());
    for_each_block(&mut revolute, block, &mut par::scratch(|| ()), |_, _, b| {
        for c in b {
            unwrap_angles(AngleUnit::Radians, c);
        }
    });
}

/// Unwraps revolute coordinates (±2π jumps) and smooths every coordinate: scalar coordinates
/// column by column, quaternions of ball and free joints on the rotation manifold.
pub fn unwrap_and_smooth(
    model: &Model,
    q: &mut [Vec<f64>],
    dt: f64,
    smooth: &SmoothSpec,
) -> Result<(), Error> {
    unwrap_and_smooth_with(model, q, dt, smooth, &mut |_| true)
}

/// [`unwrap_and_smooth`] that reports its progress (0‥1) to `keep_going` once per ball or free
/// joint and per group of up to four scalar coordinates (smoothed side by side) and stops with [`Error::Cancelled`] when it returns false (`q` is then partly
/// smoothed: the caller drops it).
pub fn unwrap_and_smooth_with(
    model: &Model,
    q: &mut [Vec<f64>],
    dt: f64,
    smooth: &SmoothSpec,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<(), Error> {
    if q.is_empty() {
        return Ok(());
    }
    let mut cols = Columns::of_rows(q, model.nq);
    unwrap_revolute(model, &mut cols);
    smooth_columns(
        model,
        &model.euler_triples(),
        &mut cols,
        dt,
        smooth,
        keep_going,
    )?;
    cols.to_rows(q);
    Ok(())
}

/// Coordinates (columns side by side) to smooth: one ball or free joint's, one euler joint's
/// three hinges ([`Model::euler_triples`]), or up to four consecutive scalar coordinates,
/// which the filter runs side by side.
struct JointColumns<'a> {
    kind: Group,
    cols: &'a mut [f64],
    /// An euler joint's rotation at every frame ([`TripleRotations`]); empty for the others.
    rotations: &'a mut [UnitQuaternion<f64>],
}

/// What a group of coordinates is.
#[derive(Clone, Copy)]
enum Group {
    /// Scalar coordinates, filtered side by side.
    Scalars,
    /// A ball or free joint.
    Joint(JointKind),
    /// Three hinges that make one ball joint: smoothed as its rotation.
    Euler(EulerOrder),
}

/// Scalar coordinates smoothed side by side in one group.
const SIDE_BY_SIDE: usize = 4;

/// What one worker smooths with: its filter's buffers and a ball joint's rotations.
struct SmoothScratch {
    smoother: Smoother,
    quats: Vec<UnitQuaternion<f64>>,
}

/// Smooths every joint's coordinates, groups in parallel (a ball or free joint alone, up to
/// four consecutive scalar coordinates together); `keep_going` is told once per group (in
/// coordinate order) and stops the work with [`Error::Cancelled`]. Returns the euler joints'
/// smoothed rotations (`triples`, [`Model::euler_triples`]).
fn smooth_columns(
    model: &Model,
    triples: &[EulerTriple],
    cols: &mut Columns,
    dt: f64,
    smooth: &SmoothSpec,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<TripleRotations, Error> {
    let n = cols.frames;
    let mut rotations = TripleRotations::new(triples.len(), n);
    if n == 0 {
        return Ok(rotations);
    }
    let smoother = Smoother::new(*smooth, dt)?;
    // the groups of columns: consecutive scalar coordinates up to four together, each ball
    // or free joint alone (coordinate order: idx_q grows with the body index)
    // and each euler joint's three hinges alone
    let mut triples = triples.iter().peekable();
    let mut groups: Vec<(usize, usize, Group)> = vec![];
    let mut i = 1;
    while i < model.nbodies() {
        let (iq, nq, kind) = (model.idx_q[i], model.joints[i].nq(), model.joints[i]);
        if let Some(t) = triples.next_if(|t| t.body == i) {
            groups.push((iq, 3, Group::Euler(t.order)));
            i += 3;
            continue;
        }
        match kind {
            JointKind::Fixed => {}
            JointKind::Revolute { .. } | JointKind::Prismatic { .. } => match groups.last_mut() {
                Some((at, m, Group::Scalars)) if *at + *m == iq && *m < SIDE_BY_SIDE => *m += 1,
                _ => groups.push((iq, nq, Group::Scalars)),
            },
            JointKind::Spherical | JointKind::Free => groups.push((iq, nq, Group::Joint(kind))),
        }
        i += 1;
    }
    let mut joints = Vec::with_capacity(groups.len());
    let mut rest: &mut [f64] = &mut cols.data;
    let mut rest_rotations: &mut [UnitQuaternion<f64>] = &mut rotations.data;
    let mut at = 0;
    for (iq, m, kind) in groups {
        debug_assert!(iq >= at, "coordinates in body order");
        let (_, tail) = std::mem::take(&mut rest).split_at_mut((iq - at) * n);
        let (mine, tail) = tail.split_at_mut(m * n);
        let frames = if matches!(kind, Group::Euler(_)) {
            n
        } else {
            0
        };
        let (rotations, tail_rotations) = std::mem::take(&mut rest_rotations).split_at_mut(frames);
        joints.push(JointColumns {
            kind,
            cols: mine,
            rotations,
        });
        (rest, rest_rotations) = (tail, tail_rotations);
        at = iq + m;
    }
    let mut scratch = par::scratch(|| {
        let mut smoother = smoother.clone();
        smoother.reserve(n);
        SmoothScratch {
            smoother,
            quats: Vec::with_capacity(n),
        }
    });
    let total = joints.len();
    let reached = rounds(
        &mut joints,
        1,
        &mut scratch,
        |s, _, block| {
            for j in block {
                smooth_joint(s, j, n);
            }
        },
        &mut |k| keep_going(k as f64 / total as f64),
    );
    if reached < total {
        return Err(Error::Cancelled);
    }
    Ok(rotations)
}

/// One group of [`smooth_columns`].
fn smooth_joint(s: &mut SmoothScratch, j: &mut JointColumns, n: usize) {
    let quat_at = match j.kind {
        Group::Scalars => {
            s.smoother.smooth_side_by_side(j.cols, n);
            return;
        }
        Group::Euler(order) => {
            let (c0, rest) = j.cols.split_at_mut(n);
            let (c1, c2) = rest.split_at_mut(n);
            smooth_triple(&mut s.smoother, order, [c0, c1, c2], j.rotations);
            return;
        }
        Group::Joint(JointKind::Free) => {
            s.smoother.smooth_side_by_side(&mut j.cols[..3 * n], n);
            3 * n
        }
        Group::Joint(JointKind::Spherical) => 0,
        Group::Joint(_) => return,
    };
    // quaternions [x, y, z, w] on the rotation manifold
    let c = &mut j.cols[quat_at..quat_at + 4 * n];
    let quats = &mut s.quats;
    quats.clear();
    quats.extend((0..n).map(|k| {
        UnitQuaternion::new_normalize(Quaternion::new(c[3 * n + k], c[k], c[n + k], c[2 * n + k]))
    }));
    s.smoother.smooth_quaternions(quats);
    for (k, r) in quats.iter().enumerate() {
        (c[k], c[n + k], c[2 * n + k], c[3 * n + k]) = (r.i, r.j, r.k, r.w);
    }
}

/// The linear velocity and acceleration of every free joint from its position's path in the
/// parent's axes, in body coordinates, replacing the translation part of the SE(3)
/// differences: `v = Rᵀṗ` and `a = Rᵀp̈ − ω × v` (the derivative of the body coordinates, the
/// free joint's q̈), `ṗ` and `p̈` by the same second-order differences as every other column
/// ([`differentiate`](crate::motion::derive::differentiate), once and twice), `ω` the body's
/// angular velocity from the SO(3) difference. A captured root moves along a path in the
/// world, not along a screw: the SE(3) logarithm couples the translation with the turn over the
/// difference's span, which is not Galilean invariant. The same walk on a treadmill (a
/// constant velocity taken out) gave other accelerations, 4.8 N·m at the Bandai walk's knee at
/// 30 fps; with `Rᵀp̈` the body's classical acceleration (`a + ω × v`) is the same whatever
/// the floor's velocity (`tests/contact_in_place.rs`).
fn world_translation_rates(model: &Model, q: &Columns, dt: f64, v: &mut Columns, a: &mut Columns) {
    use crate::motion::derive::differentiate;
    let n = q.frames;
    if n < 3 {
        return;
    }
    let (mut rate, mut acc) = (vec![vec![0.0; n]; 3], vec![vec![0.0; n]; 3]);
    for i in (1..model.nbodies()).filter(|&i| model.joints[i] == JointKind::Free) {
        let (iq, iv) = (model.idx_q[i], model.idx_v[i]);
        for c in 0..3 {
            differentiate(q.col(iq + c), dt, &mut rate[c]);
            differentiate(&rate[c], dt, &mut acc[c]);
        }
        for k in 0..n {
            let xyzw = [0, 1, 2, 3].map(|c| q.data[(iq + 3 + c) * n + k]);
            let r = crate::spatial::quat_from_xyzw(&xyzw);
            let world = |m: &[Vec<f64>]| nalgebra::Vector3::new(m[0][k], m[1][k], m[2][k]);
            let lin = r.inverse() * world(&rate);
            let omega = nalgebra::Vector3::from_fn(|c, _| v.data[(iv + 3 + c) * n + k]);
            let lin_acc = r.inverse() * world(&acc) - omega.cross(&lin);
            for c in 0..3 {
                v.data[(iv + c) * n + k] = lin[c];
                a.data[(iv + c) * n + k] = lin_acc[c];
            }
        }
    }
}

/// v and a by second-order central differences on the configuration manifold
/// (`v_k = (q_{k+1} ⊖ q_{k−1}) / 2dt`, one-sided second-order formulas at the ends), then the
/// same on v (the formulas of [`differentiate`](crate::motion::derive::differentiate), frame by
/// frame). Takes of one or two frames get v = a = 0 (one frame) or first differences.
/// [`derivative_columns`] on the rows' columns.
pub fn derivatives(model: &Model, q: &[Vec<f64>], dt: f64) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let cols = Columns::of_rows(q, model.nq);
    let (v, a, _) = derivative_columns(model, &model.euler_triples(), &cols, None, dt);
    (v.rows(), a.rows())
}

/// A joint's velocity and acceleration columns (`nv × frames` each, side by side) to fill from
/// its coordinates: one body's, or an euler joint's three hinges.
struct JointRates<'a> {
    body: usize,
    euler: Option<EulerOrder>,
    /// An euler joint's rotations ([`TripleRotations`]; `None`: its angles').
    rotations: Option<&'a [UnitQuaternion<f64>]>,
    v: &'a mut [f64],
    a: &'a mut [f64],
    /// An euler joint's frames at gimbal lock, whose rates are its angles' differences (its
    /// `a` is filled at every frame).
    locked_frames: usize,
}

/// [`derivatives`] on columns: joints in parallel for v (scalar joints column by column,
/// ball and free joints through [`Model::difference`]'s joint formula frame by frame, euler
/// joints from their rotation with their a, [`triple_rates`], the rotations `rotations` the
/// smoothing left or else their angles'), then every other v column in
/// parallel for a. Each value is computed by the same expression as frame by frame, so the
/// result does not depend on the layout or the number of threads. Also returns, for each
/// euler joint that comes within [`LOCK_DET`](crate::motion::euler::LOCK_DET) of gimbal lock,
/// its first hinge body and the number of those frames, whose rates are its angles'
/// differences.
fn derivative_columns(
    model: &Model,
    triples: &[EulerTriple],
    q: &Columns,
    rotations: Option<&TripleRotations>,
    dt: f64,
) -> (Columns, Columns, Vec<(usize, usize)>) {
    let (n, nv) = (q.frames, model.nv);
    let mut v = Columns {
        frames: n,
        data: vec![0.0; nv * n],
    };
    let mut a = Columns {
        frames: n,
        data: vec![0.0; nv * n],
    };
    if n < 2 {
        return (v, a, vec![]);
    }
    // each joint's v and a columns, split off in velocity order (idx_v grows with the body
    // index), an euler joint's three hinges together
    let mut triples = triples.iter().enumerate().peekable();
    let mut joints = Vec::with_capacity(model.nbodies());
    let (mut rest_v, mut rest_a): (&mut [f64], &mut [f64]) = (&mut v.data, &mut a.data);
    let mut at = 0;
    let mut i = 1;
    while i < model.nbodies() {
        let triple = triples.next_if(|(_, t)| t.body == i);
        let euler = triple.map(|(_, t)| t.order);
        let bodies = if euler.is_some() { 3 } else { 1 };
        let iv = model.idx_v[i];
        let nvj: usize = (i..i + bodies).map(|b| model.joints[b].nv()).sum();
        let (_, tail_v) = std::mem::take(&mut rest_v).split_at_mut((iv - at) * n);
        let (_, tail_a) = std::mem::take(&mut rest_a).split_at_mut((iv - at) * n);
        let (mine_v, tail_v) = tail_v.split_at_mut(nvj * n);
        let (mine_a, tail_a) = tail_a.split_at_mut(nvj * n);
        joints.push(JointRates {
            body: i,
            euler,
            rotations: triple.and_then(|(t, _)| rotations.map(|r| r.of(t))),
            v: mine_v,
            a: mine_a,
            locked_frames: 0,
        });
        (rest_v, rest_a) = (tail_v, tail_a);
        at = iv + nvj;
        i += bodies;
    }
    let block = par::even_block(joints.len());
    let mut scratch = par::scratch(|| TripleScratch::with_capacity(n));
    for_each_block(&mut joints, block, &mut scratch, |s, _, b| {
        for j in b {
            joint_rates(model, q, dt, s, j);
        }
    });
    // the columns whose a is done (every euler joint's), and the euler joints at lock
    let mut done = vec![false; nv];
    let mut locked = vec![];
    for j in joints.iter().filter(|j| j.euler.is_some()) {
        let iv = model.idx_v[j.body];
        done[iv..iv + 3].fill(true);
        if j.locked_frames > 0 {
            locked.push((j.body, j.locked_frames));
        }
    }
    drop(joints);
    if n == 2 {
        return (v, a, locked);
    }
    // a: the same second-order differences on each other v column
    let h2 = 2.0 * dt;
    let vr = &v;
    let block = n * par::even_block(nv);
    for_each_block(
        &mut a.data,
        block,
        &mut par::scratch(|| ()),
        |_, first, chunk| {
            for (c, ac) in chunk.chunks_mut(n).enumerate() {
                if done[first / n + c] {
                    continue;
                }
                let vc = vr.col(first / n + c);
                ac[0] = (-3.0 * vc[0] + 4.0 * vc[1] - vc[2]) / h2;
                for k in 1..n - 1 {
                    ac[k] = (vc[k + 1] - vc[k - 1]) / h2;
                }
                ac[n - 1] = (3.0 * vc[n - 1] - 4.0 * vc[n - 2] + vc[n - 3]) / h2;
            }
        },
    );
    world_translation_rates(model, q, dt, &mut v, &mut a);
    (v, a, locked)
}

/// One joint of [`derivative_columns`]: an euler joint's v and a from its rotation
/// ([`triple_rates`]), or else each of its bodies' v ([`joint_velocity`]).
fn joint_rates(model: &Model, q: &Columns, dt: f64, s: &mut TripleScratch, j: &mut JointRates) {
    let n = q.frames;
    if let Some(order) = j.euler {
        let iq = model.idx_q[j.body];
        let (v0, rest) = j.v.split_at_mut(n);
        let (v1, v2) = rest.split_at_mut(n);
        let (a0, rest) = j.a.split_at_mut(n);
        let (a1, a2) = rest.split_at_mut(n);
        let cols = [q.col(iq), q.col(iq + 1), q.col(iq + 2)];
        let (v, a) = ([v0, v1, v2], [a0, a1, a2]);
        j.locked_frames = triple_rates(s, order, cols, j.rotations, dt, v, a);
        if j.locked_frames > 0 {
            // at gimbal lock: the angles' differences, v first, then a from the whole v
            let locked = |k: usize| at_gimbal_lock(cols[1][k]);
            for (m, v) in j.v.chunks_mut(n).enumerate() {
                (0..n)
                    .filter(|&k| locked(k))
                    .for_each(|k| v[k] = difference_at(cols[m], k, dt));
            }
            if n > 2 {
                for (v, a) in j.v.chunks(n).zip(j.a.chunks_mut(n)) {
                    (0..n)
                        .filter(|&k| locked(k))
                        .for_each(|k| a[k] = difference_at(v, k, dt));
                }
            }
        }
        return;
    }
    joint_velocity(model, q, dt, j.body, j.v);
}

/// The rate of the samples `x` (every `dt` s) at `k` by the differences [`joint_velocity`]
/// takes on a hinge: central inside, one-sided second order at the ends, the one difference
/// for two samples.
fn difference_at(x: &[f64], k: usize, dt: f64) -> f64 {
    let n = x.len();
    match (n, k) {
        (2, _) => (x[1] - x[0]) / dt,
        (_, 0) => (-3.0 * x[0] + 4.0 * x[1] - x[2]) / (2.0 * dt),
        _ if k == n - 1 => (3.0 * x[n - 1] - 4.0 * x[n - 2] + x[n - 3]) / (2.0 * dt),
        _ => (x[k + 1] - x[k - 1]) / (2.0 * dt),
    }
}

/// One joint of [`derivative_columns`]: `v` at every frame of `n ≥ 2`. Two frames: the
/// difference over dt at both. Else the central difference inside and one-sided at the ends
/// (`v0 = (−3 q0 + 4 q1 − q2) / 2dt = (4 (q1 ⊖ q0) − (q2 ⊖ q0)) / 2dt`).
fn joint_velocity(model: &Model, q: &Columns, dt: f64, body: usize, v: &mut [f64]) {
    let n = q.frames;
    let joint = model.joints[body];
    let (iq, nqj, nvj) = (model.idx_q[body], joint.nq(), joint.nv());
    if nvj == 0 {
        return;
    }
    if nqj == 1 {
        // revolute and prismatic: q1 ⊖ q0 = q1 − q0, column at a time
        let (x, out) = (q.col(iq), &mut v[..n]);
        if n == 2 {
            let d = (x[1] - x[0]) / dt;
            (out[0], out[1]) = (d, d);
            return;
        }
        let (d1, d2) = (x[1] - x[0], x[2] - x[0]);
        out[0] = 1.0 * (4.0 * d1 - d2) / (2.0 * dt);
        for k in 1..n - 1 {
            out[k] = (x[k + 1] - x[k - 1]) / (2.0 * dt);
        }
        let (d1, d2) = (x[n - 2] - x[n - 1], x[n - 3] - x[n - 1]);
        out[n - 1] = -(4.0 * d1 - d2) / (2.0 * dt);
        return;
    }
    // ball and free joints: the manifold difference frame by frame
    let row = |k: usize| -> [f64; 7] {
        let mut r = [0.0; 7];
        for (c, x) in r[..nqj].iter_mut().enumerate() {
            *x = q.data[(iq + c) * n + k];
        }
        r
    };
    let (mut d1, mut d2) = ([0.0; 6], [0.0; 6]);
    let diff = |k0: usize, k1: usize, out: &mut [f64; 6]| {
        joint.difference(&row(k0)[..nqj], &row(k1)[..nqj], &mut out[..nvj]);
    };
    let mut put = |k: usize, x: &[f64]| {
        for (c, xc) in x[..nvj].iter().enumerate() {
            v[c * n + k] = *xc;
        }
    };
    if n == 2 {
        diff(0, 1, &mut d1);
        let d = d1.map(|x| x / dt);
        put(0, &d);
        put(1, &d);
        return;
    }
    for k in 0..n {
        let mut vk = [0.0; 6];
        if k == 0 || k == n - 1 {
            let (o, s) = if k == 0 { (0, 1isize) } else { (n - 1, -1) };
            let p1 = (o as isize + s) as usize;
            let p2 = (o as isize + 2 * s) as usize;
            diff(o, p1, &mut d1);
            diff(o, p2, &mut d2);
            for c in 0..nvj {
                vk[c] = s as f64 * (4.0 * d1[c] - d2[c]) / (2.0 * dt);
            }
        } else {
            diff(k - 1, k + 1, &mut d1);
            for c in 0..nvj {
                vk[c] = d1[c] / (2.0 * dt);
            }
        }
        put(k, &vk);
    }
}
