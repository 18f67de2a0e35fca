//! Stages 5–7 of a take: channels → q, unwrapped (Euler branches and turns), smoothed, then v
//! and a. Coordinates are worked on as columns (one contiguous run of frames per coordinate,
//! a joint's coordinates side by side), joints and frames in parallel ([`super::par`]); every
//! column and every frame computes what the serial path computes, in the same order, so the
//! results do not depend on the number of threads.

use super::stages::Stage;
use super::{GLITCH_SPEED, NEAR_LOCK, States};
use crate::error::Error;
use crate::io::bvh::Bvh;
use crate::model::bvh::BvhMap;
use crate::model::{JointKind, Model};
use crate::motion::smooth::{SmoothSpec, Smoother};
use crate::motion::unwrap::{AngleUnit, unwrap_angles};
use crate::par::{self, for_each_block, rounds};
use crate::rotation::EulerOrder;
use nalgebra::{Quaternion, UnitQuaternion};

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
    let traj = crate::motion::take::Trajectory::from_bvh(bvh, model, map);
    done(Stage::Coordinates);
    let dt = bvh.frame_time;
    let mut q = traj.q;
    let mut cols = Columns::of_rows(&q, model.nq);
    let notes = euler_continuity(bvh, map, &mut cols);
    unwrap_revolute(model, &mut cols);
    done(Stage::Unwrap);
    smooth_columns(model, &mut cols, dt, smooth, &mut |f| keep_going(0.9 * f))?;
    cols.to_rows(&mut q);
    done(Stage::Smooth);
    if !keep_going(0.9) {
        return Err(Error::Cancelled);
    }
    let (v, a) = derivatives(model, &q, dt);
    done(Stage::Derivatives);
    let states = States {
        time: traj.time,
        q,
        v,
        a,
    };
    Ok((states, notes))
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

    /// Writes the columns back into `rows`, in parallel over frames.
    fn to_rows(&self, rows: &mut [Vec<f64>]) {
        let (n, data) = (self.frames, &self.data);
        let block = par::even_block(rows.len());
        for_each_block(rows, block, &mut par::scratch(|| ()), |_, first, chunk| {
            for (i, row) in chunk.iter_mut().enumerate() {
                let k = first + i;
                for (j, x) in row.iter_mut().enumerate() {
                    *x = data[j * n + k];
                }
            }
        });
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
    let mut scratch = par::scratch(|| Vec::<[f64; 3]>::with_capacity(n));
    for_each_block(&mut triples, 1, &mut scratch, |frames, _, block| {
        for t in block {
            continuous_triple(bvh, t, frames);
        }
    });
    triples.into_iter().flat_map(|t| t.notes).collect()
}

/// One joint of [`euler_continuity`]: re-picks its triples and notes its passages and jumps.
fn continuous_triple(bvh: &Bvh, t: &mut Triple, frames: &mut Vec<[f64; 3]>) {
    let [c0, c1, c2] = &mut t.cols;
    let order = t.order;
    let name = &bvh.joints[t.joint].name;
    frames.clear();
    frames.extend((0..c0.len()).map(|k| [c0[k], c1[k], c2[k]]));
    let scan = crate::motion::unwrap::make_euler_continuous_and_scan(order, frames);
    for (k, f) in frames.iter().enumerate() {
        (c0[k], c1[k], c2[k]) = (f[0], f[1], f[2]);
    }
    // sitting near the lock (not passing through it) makes D(q) nearly singular all along
    let near = frames
        .iter()
        .filter(|f| f[1].cos().abs() < NEAR_LOCK.sin())
        .count();
    if scan.passage.is_none() && near * 100 >= frames.len() {
        t.notes.push(format!(
            "`{name}` sits within {:.0}° of gimbal lock in {:.0} % of the frames (its middle \
             {order} angle near ±90°): the euler model's mass matrix is nearly singular \
             there and `simulate` may fail; use the ball joint model (`--joints ball`, `set \
             joints ball`)",
            NEAR_LOCK.to_degrees(),
            100.0 * near as f64 / frames.len() as f64
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

/// [`unwrap_and_smooth`] that reports its progress (0‥1) to `keep_going` once per joint's
/// coordinates and stops with [`Error::Cancelled`] when it returns false (`q` is then partly
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
    smooth_columns(model, &mut cols, dt, smooth, keep_going)?;
    cols.to_rows(q);
    Ok(())
}

/// A joint's coordinates (columns side by side) to smooth.
struct JointColumns<'a> {
    kind: JointKind,
    cols: &'a mut [f64],
}

/// What one worker smooths with: its filter's buffers and a quaternion trajectory.
struct SmoothScratch {
    smoother: Smoother,
    quats: Vec<UnitQuaternion<f64>>,
}

/// Smooths every joint's coordinates, joints in parallel; `keep_going` is told once per joint
/// (in joint order) and stops the work with [`Error::Cancelled`].
fn smooth_columns(
    model: &Model,
    cols: &mut Columns,
    dt: f64,
    smooth: &SmoothSpec,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<(), Error> {
    let n = cols.frames;
    if n == 0 {
        return Ok(());
    }
    let smoother = Smoother::new(*smooth, dt)?;
    // each joint's columns, split off in coordinate order (idx_q grows with the body index)
    let nb = model.nbodies();
    let mut joints = Vec::with_capacity(nb - 1);
    let mut rest: &mut [f64] = &mut cols.data;
    let mut at = 0;
    for i in 1..nb {
        let (iq, nq) = (model.idx_q[i], model.joints[i].nq());
        debug_assert!(iq >= at, "coordinates in body order");
        let (_, tail) = std::mem::take(&mut rest).split_at_mut((iq - at) * n);
        let (mine, tail) = tail.split_at_mut(nq * n);
        joints.push(JointColumns {
            kind: model.joints[i],
            cols: mine,
        });
        rest = tail;
        at = iq + nq;
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
    Ok(())
}

/// One joint of [`smooth_columns`].
fn smooth_joint(s: &mut SmoothScratch, j: &mut JointColumns, n: usize) {
    let quat_at = match j.kind {
        JointKind::Revolute { .. } | JointKind::Prismatic { .. } => {
            s.smoother.smooth(&mut j.cols[..n]);
            return;
        }
        JointKind::Free => {
            for c in j.cols[..3 * n].chunks_mut(n) {
                s.smoother.smooth(c);
            }
            3 * n
        }
        JointKind::Spherical => 0,
        JointKind::Fixed => return,
    };
    // quaternions [x, y, z, w] on the rotation manifold
    let c = &mut j.cols[quat_at..quat_at + 4 * n];
    s.quats.clear();
    s.quats.extend((0..n).map(|k| {
        UnitQuaternion::new_normalize(Quaternion::new(c[3 * n + k], c[k], c[n + k], c[2 * n + k]))
    }));
    s.smoother.smooth_quaternions(&mut s.quats);
    for (k, r) in s.quats.iter().enumerate() {
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
fn world_translation_rates(
    model: &Model,
    q: &[Vec<f64>],
    dt: f64,
    v: &mut [Vec<f64>],
    a: &mut [Vec<f64>],
) {
    use crate::motion::derive::differentiate;
    let n = q.len();
    if n < 3 {
        return;
    }
    let (mut x, mut rate, mut acc) = (vec![0.0; n], vec![vec![0.0; n]; 3], vec![vec![0.0; n]; 3]);
    for i in (1..model.nbodies()).filter(|&i| model.joints[i] == JointKind::Free) {
        let (iq, iv) = (model.idx_q[i], model.idx_v[i]);
        for c in 0..3 {
            for (xk, qk) in x.iter_mut().zip(q) {
                *xk = qk[iq + c];
            }
            differentiate(&x, dt, &mut rate[c]);
            differentiate(&rate[c], dt, &mut acc[c]);
        }
        for k in 0..n {
            let r = crate::spatial::quat_from_xyzw(&q[k][iq + 3..iq + 7]);
            let world = |m: &[Vec<f64>]| nalgebra::Vector3::new(m[0][k], m[1][k], m[2][k]);
            let lin = r.inverse() * world(&rate);
            let omega = nalgebra::Vector3::from_column_slice(&v[k][iv + 3..iv + 6]);
            let lin_acc = r.inverse() * world(&acc) - omega.cross(&lin);
            v[k][iv..iv + 3].copy_from_slice(lin.as_slice());
            a[k][iv..iv + 3].copy_from_slice(lin_acc.as_slice());
        }
    }
}

/// v and a by second-order central differences on the configuration manifold
/// (`v_k = (q_{k+1} ⊖ q_{k−1}) / 2dt`, one-sided second-order formulas at the ends), then the
/// same on v (the formulas of [`differentiate`](crate::motion::derive::differentiate), frame by
/// frame). Takes of one or two frames get v = a = 0 (one frame) or first differences. Frames
/// in parallel, each worker with its own two difference buffers.
pub fn derivatives(model: &Model, q: &[Vec<f64>], dt: f64) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let n = q.len();
    let nv = model.nv;
    let mut v = vec![vec![0.0; nv]; n];
    let mut a = vec![vec![0.0; nv]; n];
    if n < 2 {
        return (v, a);
    }
    let mut scratch = par::scratch(|| (vec![0.0; nv], vec![0.0; nv]));
    if n == 2 {
        let d1 = &mut scratch[0].0;
        model.difference(&q[0], &q[1], d1);
        for x in d1.iter_mut() {
            *x /= dt;
        }
        v[0].copy_from_slice(d1);
        v[1].copy_from_slice(d1);
        return (v, a);
    }
    let block = par::even_block(n);
    for_each_block(&mut v, block, &mut scratch, |(d1, d2), first, rows| {
        for (i, vk) in rows.iter_mut().enumerate() {
            velocity_at(model, q, first + i, dt, d1, d2, vk);
        }
    });
    // a: the same second-order differences on each v column
    let h2 = 2.0 * dt;
    let vr = &v;
    for_each_block(&mut a, block, &mut scratch, |_, first, rows| {
        for (i, ak) in rows.iter_mut().enumerate() {
            let k = first + i;
            for (j, x) in ak.iter_mut().enumerate() {
                *x = if k == 0 {
                    (-3.0 * vr[0][j] + 4.0 * vr[1][j] - vr[2][j]) / h2
                } else if k == n - 1 {
                    (3.0 * vr[n - 1][j] - 4.0 * vr[n - 2][j] + vr[n - 3][j]) / h2
                } else {
                    (vr[k + 1][j] - vr[k - 1][j]) / h2
                };
            }
        }
    });
    world_translation_rates(model, q, dt, &mut v, &mut a);
    (v, a)
}

/// `v` at frame `k` of `n ≥ 3`: the central difference inside, one-sided at the ends
/// (`v0 = (−3 q0 + 4 q1 − q2) / 2dt = (4 (q1 ⊖ q0) − (q2 ⊖ q0)) / 2dt`).
fn velocity_at(
    model: &Model,
    q: &[Vec<f64>],
    k: usize,
    dt: f64,
    d1: &mut [f64],
    d2: &mut [f64],
    vk: &mut [f64],
) {
    let n = q.len();
    if k == 0 || k == n - 1 {
        let (o, s) = if k == 0 { (0, 1isize) } else { (n - 1, -1) };
        let p1 = (o as isize + s) as usize;
        let p2 = (o as isize + 2 * s) as usize;
        model.difference(&q[o], &q[p1], d1);
        model.difference(&q[o], &q[p2], d2);
        for j in 0..vk.len() {
            vk[j] = s as f64 * (4.0 * d1[j] - d2[j]) / (2.0 * dt);
        }
    } else {
        model.difference(&q[k - 1], &q[k + 1], d1);
        for j in 0..vk.len() {
            vk[j] = d1[j] / (2.0 * dt);
        }
    }
}
