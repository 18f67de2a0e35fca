//! Stage 7: v and a by second-order central differences on the configuration manifold
//! (one-sided at the ends), joints in parallel; an euler joint's rates from its rotation, a
//! free joint's linear rates from its position's path in the world.

use super::Columns;
use crate::model::{EulerTriple, JointKind, Model};
use crate::motion::euler::{TripleScratch, at_gimbal_lock, triple_rates};
use crate::par::{self, for_each_block};
use crate::rotation::EulerOrder;

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
    v: &'a mut [f64],
    a: &'a mut [f64],
    /// An euler joint's frames at gimbal lock, whose rates are its angles' differences (its
    /// `a` is filled at every frame).
    locked_frames: usize,
}

/// The v and a columns of a take whose euler joints' rates were made with their smoothing
/// (`smooth_columns`): every euler joint's three v and a columns filled, and
/// for each euler joint with frames at gimbal lock, its first hinge body and their number.
pub(super) struct EulerRates {
    pub v: Columns,
    pub a: Columns,
    pub locked: Vec<(usize, usize)>,
}

impl EulerRates {
    /// Zero v and a columns (`nv × frames` each) to fill.
    pub fn new(nv: usize, frames: usize) -> Self {
        let zeros = || Columns {
            frames,
            data: vec![0.0; nv * frames],
        };
        Self {
            v: zeros(),
            a: zeros(),
            locked: vec![],
        }
    }
}

/// [`derivatives`] on columns: joints in parallel for v (scalar joints column by column,
/// ball and free joints through [`Model::difference`]'s joint formula frame by frame, euler
/// joints from their rotation with their a, [`triple_rates`] of their angles' rotations, unless
/// `euler` holds them already, made from the smoothed rotations), then every other v column in
/// parallel for a. Each value is computed by the same expression as frame by frame, so the
/// result does not depend on the layout or the number of threads. Also returns, for each
/// euler joint that comes within [`LOCK_DET`](crate::motion::euler::LOCK_DET) of gimbal lock,
/// its first hinge body and the number of those frames, whose rates are its angles'
/// differences.
pub(super) fn derivative_columns(
    model: &Model,
    triples: &[EulerTriple],
    q: &Columns,
    euler: Option<EulerRates>,
    dt: f64,
) -> (Columns, Columns, Vec<(usize, usize)>) {
    let (n, nv) = (q.frames, model.nv);
    let euler_done = euler.is_some();
    let EulerRates {
        mut v,
        mut a,
        locked: locked_before,
    } = euler.unwrap_or_else(|| EulerRates::new(nv, n));
    if n < 2 {
        return (v, a, vec![]);
    }
    // each joint's v and a columns, split off in velocity order (idx_v grows with the body
    // index), an euler joint's three hinges together
    let mut next_triple = triples.iter().peekable();
    let mut joints = Vec::with_capacity(model.nbodies());
    let (mut rest_v, mut rest_a): (&mut [f64], &mut [f64]) = (&mut v.data, &mut a.data);
    let mut at = 0;
    let mut i = 1;
    while i < model.nbodies() {
        let euler = next_triple.next_if(|t| t.body == i).map(|t| t.order);
        let bodies = if euler.is_some() { 3 } else { 1 };
        let iv = model.idx_v[i];
        let nvj: usize = (i..i + bodies).map(|b| model.joints[b].nv()).sum();
        let (_, tail_v) = std::mem::take(&mut rest_v).split_at_mut((iv - at) * n);
        let (_, tail_a) = std::mem::take(&mut rest_a).split_at_mut((iv - at) * n);
        let (mine_v, tail_v) = tail_v.split_at_mut(nvj * n);
        let (mine_a, tail_a) = tail_a.split_at_mut(nvj * n);
        if euler.is_some() && euler_done {
            // made with the joint's smoothing
        } else {
            joints.push(JointRates {
                body: i,
                euler,
                v: mine_v,
                a: mine_a,
                locked_frames: 0,
            });
        }
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
    for t in triples {
        let iv = model.idx_v[t.body];
        done[iv..iv + 3].fill(true);
    }
    let mut locked = locked_before;
    for j in joints
        .iter()
        .filter(|j| j.euler.is_some() && j.locked_frames > 0)
    {
        locked.push((j.body, j.locked_frames));
    }
    drop(joints);
    if n == 2 {
        return (v, a, locked);
    }
    accelerations(&v, &mut a, &done, dt);
    world_translation_rates(model, q, dt, &mut v, &mut a);
    (v, a, locked)
}

/// a: the same second-order differences on each v column not `done` (`n ≥ 3` frames), columns
/// in parallel.
fn accelerations(v: &Columns, a: &mut Columns, done: &[bool], dt: f64) {
    let n = v.frames;
    let nv = done.len();
    let h2 = 2.0 * dt;
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
                let vc = v.col(first / n + c);
                ac[0] = (-3.0 * vc[0] + 4.0 * vc[1] - vc[2]) / h2;
                for k in 1..n - 1 {
                    ac[k] = (vc[k + 1] - vc[k - 1]) / h2;
                }
                ac[n - 1] = (3.0 * vc[n - 1] - 4.0 * vc[n - 2] + vc[n - 3]) / h2;
            }
        },
    );
}

/// One joint of [`derivative_columns`]: an euler joint's v and a from its angles' rotation
/// ([`euler_rates`]), or else each of its bodies' v ([`joint_velocity`]).
fn joint_rates(model: &Model, q: &Columns, dt: f64, s: &mut TripleScratch, j: &mut JointRates) {
    if let Some(order) = j.euler {
        let iq = model.idx_q[j.body];
        let cols = [q.col(iq), q.col(iq + 1), q.col(iq + 2)];
        j.locked_frames = euler_rates(s, order, cols, dt, j.v, j.a);
        return;
    }
    joint_velocity(model, q, dt, j.body, j.v);
}

/// One euler joint's v and a (`v`, `a`: its three columns of `n ≥ 2` frames side by side) from
/// its angle columns `cols` and their rotations by [`triple_rates`], then
/// [`lock_differences`]. Returns the number of frames at gimbal lock.
fn euler_rates(
    s: &mut TripleScratch,
    order: EulerOrder,
    cols: [&[f64]; 3],
    dt: f64,
    v: &mut [f64],
    a: &mut [f64],
) -> usize {
    let n = cols[0].len();
    let (v0, rest) = v.split_at_mut(n);
    let (v1, v2) = rest.split_at_mut(n);
    let (a0, rest) = a.split_at_mut(n);
    let (a1, a2) = rest.split_at_mut(n);
    let locked_frames = triple_rates(s, order, cols, None, dt, [v0, v1, v2], [a0, a1, a2]);
    if locked_frames > 0 {
        lock_differences(cols, dt, v, a);
    }
    locked_frames
}

/// An euler joint's rates at its frames at gimbal lock, which [`triple_rates`] leaves: its
/// angles' differences (`cols`, `n` frames each), v first, then a from the whole v (`v`,
/// `a`: three columns side by side).
pub(super) fn lock_differences(cols: [&[f64]; 3], dt: f64, v: &mut [f64], a: &mut [f64]) {
    let n = cols[0].len();
    let locked = |k: usize| at_gimbal_lock(cols[1][k]);
    for (m, v) in v.chunks_mut(n).enumerate() {
        (0..n)
            .filter(|&k| locked(k))
            .for_each(|k| v[k] = difference_at(cols[m], k, dt));
    }
    if n > 2 {
        for (v, a) in v.chunks(n).zip(a.chunks_mut(n)) {
            (0..n)
                .filter(|&k| locked(k))
                .for_each(|k| a[k] = difference_at(v, k, dt));
        }
    }
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
