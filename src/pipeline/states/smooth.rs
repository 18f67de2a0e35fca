//! Stages 5–6 on columns: revolute coordinates unwrapped, then every coordinate smoothed —
//! scalar ones up to four side by side, ball and free joints' quaternions on the rotation
//! manifold, an euler joint's three hinges as its rotation — groups in parallel.

use super::Columns;
use super::derivatives::{EulerRates, lock_differences};
use crate::error::Error;
use crate::model::{EulerTriple, JointKind, Model};
use crate::motion::euler::{TripleScratch, smooth_triple, smooth_triple_and_rates};
use crate::motion::smooth::{SmoothSpec, Smoother};
use crate::motion::unwrap::{AngleUnit, unwrap_angles};
use crate::par::{self, for_each_block, for_each_block_reporting};
use crate::rotation::EulerOrder;
use nalgebra::{Quaternion, UnitQuaternion};

/// Unwraps every revolute coordinate (±2π jumps), columns in parallel.
pub(super) fn unwrap_revolute(model: &Model, cols: &mut Columns) {
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
        None,
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
    /// The group's first body.
    body: usize,
    cols: &'a mut [f64],
    /// An euler joint's v and a columns (three each, side by side) to fill from its smoothed
    /// rotations right after its smoothing; `None` for the others, or when the caller does not
    /// ask for rates.
    rates: Option<(&'a mut [f64], &'a mut [f64])>,
    /// The frames of those rates at gimbal lock, given their angles' differences
    /// ([`lock_differences`]).
    locked_frames: usize,
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

/// What one worker smooths with: its filter's buffers, a ball or euler joint's rotations and
/// an euler joint's rates' buffers.
struct SmoothScratch {
    smoother: Smoother,
    quats: Vec<UnitQuaternion<f64>>,
    rates: TripleScratch,
}

/// Smooths every joint's coordinates, groups in parallel (a ball or free joint alone, up to
/// four consecutive scalar coordinates together); `keep_going` is told once per group (in
/// coordinate order) and stops the work with [`Error::Cancelled`]. With `rates` (zero v and a
/// columns of `nv × frames`), each euler joint's (`triples`, [`Model::euler_triples`]) v and
/// a are made from its smoothed rotations in the same task, right after its smoothing, while
/// its frames are in the cache ([`smooth_triple_and_rates`]; `rates.locked` then lists its frames at
/// gimbal lock, in body order).
pub(super) fn smooth_columns(
    model: &Model,
    triples: &[EulerTriple],
    cols: &mut Columns,
    dt: f64,
    smooth: &SmoothSpec,
    rates: Option<&mut EulerRates>,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<(), Error> {
    let n = cols.frames;
    if n == 0 {
        return Ok(());
    }
    let smoother = Smoother::new(*smooth, dt)?;
    let groups = smoothing_groups(model, triples);
    let mut joints = Vec::with_capacity(groups.len());
    let mut rest: &mut [f64] = &mut cols.data;
    // the euler joints' v and a columns, split off in velocity order
    let with_rates = rates.is_some() && n >= 2;
    let (mut rest_v, mut rest_a, locked): (&mut [f64], &mut [f64], _) = match rates {
        Some(EulerRates { v, a, locked }) => (&mut v.data, &mut a.data, Some(locked)),
        None => (&mut [], &mut [], None),
    };
    let mut at_v = 0;
    let mut at = 0;
    for (iq, m, kind, body) in groups {
        debug_assert!(iq >= at, "coordinates in body order");
        let (_, tail) = std::mem::take(&mut rest).split_at_mut((iq - at) * n);
        let (mine, tail) = tail.split_at_mut(m * n);
        let rates = if with_rates && matches!(kind, Group::Euler(_)) {
            let iv = model.idx_v[body];
            let (_, tail_v) = std::mem::take(&mut rest_v).split_at_mut((iv - at_v) * n);
            let (_, tail_a) = std::mem::take(&mut rest_a).split_at_mut((iv - at_v) * n);
            let (v, tail_v) = tail_v.split_at_mut(3 * n);
            let (a, tail_a) = tail_a.split_at_mut(3 * n);
            (rest_v, rest_a, at_v) = (tail_v, tail_a, iv + 3);
            Some((v, a))
        } else {
            None
        };
        joints.push(JointColumns {
            kind,
            body,
            cols: mine,
            rates,
            locked_frames: 0,
        });
        rest = tail;
        at = iq + m;
    }
    let mut scratch = par::scratch(|| {
        let mut smoother = smoother.clone();
        smoother.reserve(n);
        SmoothScratch {
            smoother,
            quats: Vec::with_capacity(n),
            rates: TripleScratch::with_capacity(n),
        }
    });
    let total = joints.len();
    let reached = for_each_block_reporting(
        &mut joints,
        1,
        &mut scratch,
        |s, _, block| {
            for j in block {
                smooth_joint(s, j, n, dt);
            }
        },
        &mut |k| keep_going(k as f64 / total as f64),
    );
    if reached < total {
        return Err(Error::Cancelled);
    }
    if let Some(locked) = locked {
        for j in joints.iter().filter(|j| j.locked_frames > 0) {
            locked.push((j.body, j.locked_frames));
        }
    }
    Ok(())
}

/// The groups of columns [`smooth_columns`] smooths, as (first coordinate, coordinates, what
/// they are, first body): consecutive scalar coordinates up to four together, each ball or free joint
/// alone and each euler joint's three hinges alone (coordinate order: idx_q grows with the body
/// index).
fn smoothing_groups(model: &Model, triples: &[EulerTriple]) -> Vec<(usize, usize, Group, usize)> {
    let mut triples = triples.iter().peekable();
    let mut groups: Vec<(usize, usize, Group, usize)> = vec![];
    let mut i = 1;
    while i < model.nbodies() {
        let (iq, nq, kind) = (model.idx_q[i], model.joints[i].nq(), model.joints[i]);
        if let Some(t) = triples.next_if(|t| t.body == i) {
            groups.push((iq, 3, Group::Euler(t.order), i));
            i += 3;
            continue;
        }
        match kind {
            JointKind::Fixed => {}
            JointKind::Revolute { .. } | JointKind::Prismatic { .. } => match groups.last_mut() {
                Some((at, m, Group::Scalars, _)) if *at + *m == iq && *m < SIDE_BY_SIDE => *m += 1,
                _ => groups.push((iq, nq, Group::Scalars, i)),
            },
            JointKind::Spherical | JointKind::Free => groups.push((iq, nq, Group::Joint(kind), i)),
        }
        i += 1;
    }
    groups
}

/// One group of [`smooth_columns`] (and an euler joint's rates, when asked for).
fn smooth_joint(s: &mut SmoothScratch, j: &mut JointColumns, n: usize, dt: f64) {
    let quat_at = match j.kind {
        Group::Scalars => {
            s.smoother.smooth_side_by_side(j.cols, n);
            return;
        }
        Group::Euler(order) => {
            let (c0, rest) = j.cols.split_at_mut(n);
            let (c1, c2) = rest.split_at_mut(n);
            let Some((v, a)) = &mut j.rates else {
                s.quats.resize(n, UnitQuaternion::identity());
                smooth_triple(&mut s.smoother, order, [c0, c1, c2], &mut s.quats);
                return;
            };
            let (v0, rest) = v.split_at_mut(n);
            let (v1, v2) = rest.split_at_mut(n);
            let (a0, rest) = a.split_at_mut(n);
            let (a1, a2) = rest.split_at_mut(n);
            let (cols, dt) = ([&mut c0[..], &mut c1[..], &mut c2[..]], dt);
            let (vs, as_) = ([v0, v1, v2], [a0, a1, a2]);
            let rates = &mut s.rates;
            j.locked_frames =
                smooth_triple_and_rates(rates, &mut s.smoother, order, cols, dt, vs, as_);
            if j.locked_frames > 0 {
                lock_differences([&c0[..], &c1[..], &c2[..]], dt, v, a);
            }
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
