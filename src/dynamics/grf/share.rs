//! How a frame's needed wrench is shared among the feet (the module documentation of
//! [`super`] gives the method): Ren et al.'s step transition, the lever rule with its ramps in
//! and out of the single supports, each foot's support region, centre of pressure and friction
//! cone.

use crate::motion::contact::{ContactParams, Foot};
use crate::spatial::{ForceVec, SpatialTransform};
use nalgebra::Vector3;

/// A step in double support: the trailing foot and its share of the load.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Step {
    pub(super) trailing: usize,
    pub(super) leading: usize,
    pub(super) trailing_share: f64,
}

/// How a frame of double support shares the needed wrench between the feet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Transition {
    /// Between a single support of one foot and a single support of the other: Ren et al.'s
    /// ramp ([`assign_step`]).
    Step(Step),
    /// Any other double support (at the take's start or end, standing, a foot tapping, before
    /// or after flight): the lever rule, entered and left without a jump. Within
    /// [`Transition::Open::ramp_s`] of the single support of `from` before it, the loads blend
    /// from that support's (`from` keeping what it carried alone, the other foot taking the
    /// rest) with weight `entry`; within that of the single support of `to` after it, towards
    /// that support's (`to` carrying all) with weight `exit`.
    Open {
        from: Option<usize>,
        to: Option<usize>,
        entry: f64,
        exit: f64,
    },
}

impl Transition {
    /// The double support a step's transition lasts when the take has no step to measure it
    /// by (s): about 10 % of a walking stride (Winter 2009, ch. 1; Perry & Burnfield 2010).
    pub(super) const DEFAULT_RAMP_S: f64 = 0.1;
}

/// The C² ramp `10u³ − 15u⁴ + 6u⁵` from 0 at `u ≤ 0` to 1 at `u ≥ 1`.
pub(super) fn smoothstep(u: f64) -> f64 {
    let u = u.clamp(0.0, 1.0);
    u * u * u * (10.0 - 15.0 * u + 6.0 * u * u)
}

/// For every frame of double support, how the load is shared ([`Transition`]): a double
/// support between a single support of one foot and one of the other is a step (Ren et al.
/// 2008), `u` running from 0 at the trailing foot's last single-support frame to 1 at the
/// leading foot's first, and the trailing share `1 − (10u³ − 15u⁴ + 6u⁵)`. Every other double
/// support is [`Transition::Open`], its entry and exit ramps as long as the take's median
/// step transition ([`Transition::DEFAULT_RAMP_S`] without a step), at most half the double
/// support each: so no foot's load jumps where a double support begins or ends, at the take's
/// first or last contact included (the demo walk's right foot went 0 → 332 N in one frame at
/// its last heel strike, the knee −15 → −115 N·m).
pub(super) fn transitions(contact: &[Vec<bool>], time: &[f64]) -> Vec<Option<Transition>> {
    let n = contact.len();
    let only = |k: usize| {
        let on: Vec<usize> = (0..contact[k].len()).filter(|&j| contact[k][j]).collect();
        (on.len() == 1).then(|| on[0])
    };
    let double = |k: usize| contact[k].iter().filter(|c| **c).count() == 2;
    // the double supports: (first frame, end frame, foot alone before, foot alone after)
    let mut spans = vec![];
    for run in crate::motion::runs(n, double) {
        let (s, k) = (run.start, run.end);
        let before = if s > 0 { only(s - 1) } else { None };
        let after = if k < n { only(k) } else { None };
        spans.push((s, k, before, after));
    }
    let mut step_lengths: Vec<f64> = spans
        .iter()
        .filter(|(_, _, b, a)| matches!((b, a), (Some(b), Some(a)) if b != a))
        .map(|&(s, e, _, _)| time[e] - time[s - 1])
        .collect();
    step_lengths.sort_by(f64::total_cmp);
    let ramp = step_lengths
        .get(step_lengths.len() / 2)
        .copied()
        .unwrap_or(Transition::DEFAULT_RAMP_S);

    let mut out = vec![None; n];
    for (s, e, before, after) in spans {
        if let (Some(trailing), Some(leading)) = (before, after)
            && trailing != leading
        {
            let (t0, t1) = (time[s - 1], time[e]);
            for (m, step) in out.iter_mut().enumerate().take(e).skip(s) {
                *step = Some(Transition::Step(Step {
                    trailing,
                    leading,
                    trailing_share: 1.0 - smoothstep((time[m] - t0) / (t1 - t0)),
                }));
            }
            continue;
        }
        // the ramps are measured from the single supports either side (or the take's ends)
        let t0 = if s > 0 { time[s - 1] } else { time[0] };
        let t1 = if e < n { time[e] } else { time[n - 1] };
        let r = ramp.min(0.5 * (t1 - t0)).max(f64::MIN_POSITIVE);
        for (m, t) in out.iter_mut().enumerate().take(e).skip(s) {
            *t = Some(Transition::Open {
                from: before,
                to: after,
                entry: before.map_or(0.0, |_| 1.0 - smoothstep((time[m] - t0) / r)),
                exit: after.map_or(0.0, |_| 1.0 - smoothstep((t1 - time[m]) / r)),
            });
        }
    }
    out
}

/// A foot's support region on the floor: its ankle and toe projected.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Support {
    pub(super) heel: Vector3<f64>,
    pub(super) toe: Vector3<f64>,
}

impl Support {
    pub(super) fn new(foot: &Foot, o_x_i: &[SpatialTransform], up: usize, floor: f64) -> Self {
        let mut heel = foot.heel(o_x_i);
        let mut toe = foot.toe(o_x_i);
        heel[up] = floor;
        toe[up] = floor;
        Self { heel, toe }
    }

    /// `p` (on the floor) moved to the nearest point of the heel–toe segment widened by
    /// `margin`, if it lies outside.
    pub(super) fn clamp(&self, p: &Vector3<f64>, margin: f64) -> Vector3<f64> {
        let d = self.toe - self.heel;
        let len2 = d.norm_squared();
        let s = if len2 > 0.0 {
            self.heel + d * ((p - self.heel).dot(&d) / len2).clamp(0.0, 1.0)
        } else {
            self.heel
        };
        let off = p - s;
        let dist = off.norm();
        if dist > margin {
            s + off * (margin / dist)
        } else {
            *p
        }
    }
}

impl Support {
    /// The largest free moment (N·m, about the vertical) the sole can hold by friction under
    /// the vertical force `f_up`, whatever the pressure under it: on the sole the centre of
    /// pressure may take (the heel–toe segment widened by `params.cop_margin` at both ends,
    /// length ℓ) no point lies farther than ℓ/2 from the centre of pressure's side of it, so
    /// the friction forces (μ times the pressure, f_up in all) twist it by at most
    /// μ f_up ℓ / 2 (pressed evenly, μ f_up ℓ / 4). The bound, not the even pressure's value: it
    /// only removes twists no sole could hold, and leaves the rest to the estimate. Without it
    /// a foot that barely touched the floor took whatever twist the whole body needed about a
    /// centre of pressure metres away (7808 N·m under 1 N on a Bandai run).
    pub(super) fn torsion_limit(&self, f_up: f64, params: &ContactParams) -> f64 {
        let length = (self.toe - self.heel).norm() + 2.0 * params.cop_margin;
        params.friction * f_up.max(0.0) * length / 2.0
    }
}

/// `free` within the torsional friction of the foot on `support` under `load`'s vertical
/// force ([`Support::torsion_limit`]).
fn within_torsion(
    free: f64,
    load: &FootLoad,
    support: &Support,
    up: usize,
    p: &ContactParams,
) -> f64 {
    let limit = support.torsion_limit(load.force[up], p);
    free.clamp(-limit, limit)
}

/// One foot's share of the ground reaction.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(super) struct FootLoad {
    pub(super) force: Vector3<f64>,
    pub(super) cop: Vector3<f64>,
    pub(super) free_moment: f64,
}

impl FootLoad {
    /// The load as a wrench about the world origin (world axes), `e_up` the vertical.
    pub(super) fn wrench(&self, e_up: &Vector3<f64>) -> ForceVec {
        ForceVec::new(
            self.cop.cross(&self.force) + e_up * self.free_moment,
            self.force,
        )
    }
}

/// The centre of pressure of wrench `w` (about the world origin) on the floor plane at height
/// `floor`, and the free moment about the vertical there; `None` if the wrench does not press
/// on the floor. With `(i, j, u)` a right-handed permutation of the axes, `u` vertical, the
/// moment about `p` has no `i`, `j` components when
/// `p_i = (h f_i − n_j) / f_u`, `p_j = (h f_j + n_i) / f_u` (Winter 2009, force plate CoP).
pub(super) fn centre_of_pressure(
    w: &ForceVec,
    up: usize,
    floor: f64,
) -> Option<(Vector3<f64>, f64)> {
    let (i, j) = ((up + 1) % 3, (up + 2) % 3);
    let f = &w.lin;
    if f[up].is_nan() || f[up] <= 1e-9 {
        return None;
    }
    let mut p = Vector3::zeros();
    p[up] = floor;
    p[i] = (floor * f[i] - w.ang[j]) / f[up];
    p[j] = (floor * f[j] + w.ang[i]) / f[up];
    let free = (w.ang - p.cross(f))[up];
    Some((p, free))
}

/// The floor: its up axis (0, 1, 2) and height along it (m).
#[derive(Debug, Clone, Copy)]
pub(super) struct Floor {
    pub(super) up: usize,
    pub(super) height: f64,
}

/// Work buffers of [`assign`], allocated once per take.
pub(super) struct Scratch {
    pub(super) share: Vec<f64>,
    pub(super) other: Vec<FootLoad>,
    pub(super) alone: Vec<bool>,
}

impl Scratch {
    pub(super) fn new(feet: usize) -> Self {
        Self {
            share: vec![0.0; feet],
            other: vec![FootLoad::default(); feet],
            alone: vec![false; feet],
        }
    }
}

/// Shares the needed wrench `w` among the feet loaded in this frame (`c`), writing `loads`:
/// a step by [`assign_step`] (from the trailing foot's last single-support load in
/// `last_single`), an open double support by the lever rule blended with the single supports
/// either side ([`Transition::Open`]), anything else by [`assign_to_feet`].
#[allow(clippy::too_many_arguments)]
pub(super) fn assign(
    w: &ForceVec,
    support: &[Support],
    c: &[bool],
    transition: Option<Transition>,
    last_single: &[Option<FootLoad>],
    floor: Floor,
    params: &ContactParams,
    scratch: &mut Scratch,
    loads: &mut [FootLoad],
) {
    let (up, h) = (floor.up, floor.height);
    let step = match transition {
        Some(Transition::Step(step)) => Some(step),
        _ => None,
    };
    if let Some(step) = step
        && let Some(last) = last_single[step.trailing]
    {
        let toe = support[step.trailing].toe;
        return assign_step(w, support, step, &last, toe, up, h, params, loads);
    }
    assign_to_feet(
        w,
        support,
        c,
        step,
        up,
        h,
        params,
        &mut scratch.share,
        loads,
    );
    let Some(Transition::Open {
        from,
        to,
        entry,
        exit,
    }) = transition
    else {
        return;
    };
    // entering from a single support: that foot keeps what it carried alone
    let other = |a: usize| (0..c.len()).find(|&j| c[j] && j != a);
    if let Some(a) = from
        && entry > 0.0
        && let (Some(last), Some(leading)) = (last_single[a], other(a))
    {
        let step = Step {
            trailing: a,
            leading,
            trailing_share: 1.0,
        };
        let toe = support[a].toe;
        assign_step(
            w,
            support,
            step,
            &last,
            toe,
            up,
            h,
            params,
            &mut scratch.other,
        );
        blend(loads, &scratch.other, entry, support, floor);
    }
    // leaving to a single support: that foot carries all
    if let Some(b) = to
        && exit > 0.0
    {
        scratch.alone.fill(false);
        scratch.alone[b] = true;
        let (alone, share, other) = (&scratch.alone, &mut scratch.share, &mut scratch.other);
        assign_to_feet(w, support, alone, None, up, h, params, share, other);
        blend(loads, &scratch.other, exit, support, floor);
    }
}

/// `loads` ← `(1 − α)·loads + α·other`, foot by foot as wrenches: the force and the moment
/// interpolate, and the centre of pressure is the vertical-force-weighted mean of the two (so
/// it stays in the foot's support, which is convex), the free moment what the interpolated
/// moment leaves about it.
pub(super) fn blend(
    loads: &mut [FootLoad],
    other: &[FootLoad],
    alpha: f64,
    support: &[Support],
    f: Floor,
) {
    let e_up = Vector3::ith(f.up, 1.0);
    for ((l, o), s) in loads.iter_mut().zip(other).zip(support) {
        let w = l.wrench(&e_up) * (1.0 - alpha) + o.wrench(&e_up) * alpha;
        *l = match centre_of_pressure(&w, f.up, f.height) {
            Some((cop, free_moment)) => FootLoad {
                force: w.lin,
                cop,
                free_moment,
            },
            None => FootLoad {
                force: Vector3::zeros(),
                cop: s.heel,
                free_moment: 0.0,
            },
        };
    }
}

/// Shares `w` among the feet in contact (see the module documentation), writing `loads`.
#[allow(clippy::too_many_arguments)]
pub(super) fn assign_to_feet(
    w: &ForceVec,
    support: &[Support],
    contact: &[bool],
    step: Option<Step>,
    up: usize,
    floor: f64,
    params: &ContactParams,
    share: &mut [f64],
    loads: &mut [FootLoad],
) {
    for (l, s) in loads.iter_mut().zip(support) {
        *l = FootLoad {
            force: Vector3::zeros(),
            cop: s.heel,
            free_moment: 0.0,
        };
    }
    let Some((p, free)) = centre_of_pressure(w, up, floor) else {
        return;
    };
    let mut on = (0..contact.len()).filter(|&j| contact[j]);
    let (first, second) = (on.next(), on.next());
    let count = contact.iter().filter(|c| **c).count();

    // shares: one foot takes all; a step ramps trailing → leading; otherwise the lever rule
    share.fill(0.0);
    match (first, second, step) {
        (None, _, _) => return,
        (Some(j), None, _) => share[j] = 1.0,
        (_, _, Some(s)) => {
            share[s.trailing] = s.trailing_share;
            share[s.leading] = 1.0 - s.trailing_share;
        }
        (Some(a), Some(b), None) if count == 2 => {
            let (ca, cb) = (support[a].heel, support[b].heel);
            let d = ca - cb;
            let r = if d.norm_squared() > 1e-12 {
                ((p - cb).dot(&d) / d.norm_squared()).clamp(0.0, 1.0)
            } else {
                0.5
            };
            share[a] = r;
            share[b] = 1.0 - r;
        }
        _ => many_feet_shares(&p, support, contact, count, share),
    }

    // each foot: the force share, pushing, within the friction cone
    for j in (0..contact.len()).filter(|&j| contact[j]) {
        let mut force = w.lin * share[j];
        let horizontal = force - Vector3::ith(up, force[up]);
        let limit = params.friction * force[up];
        if horizontal.norm() > limit {
            force -= horizontal * (1.0 - limit / horizontal.norm());
        }
        // first guess: p shifted by the foot's offset from the load-weighted heel centre
        // (the centres of pressure nearest the heels whose weighted mean is p)
        let centre: Vector3<f64> = support.iter().zip(&*share).map(|(s, r)| s.heel * *r).sum();
        loads[j] = FootLoad {
            force,
            cop: support[j].clamp(&(p + support[j].heel - centre), params.cop_margin),
            free_moment: free * share[j],
        };
    }

    // where a clamp broke Σ rₖ pₖ = p, let the other feet make up for it: block coordinate
    // descent on |p − Σ rₖ pₖ|², each foot's centre moved by the error over its share and
    // clamped again, the most loaded foot first
    for _ in 0..3 {
        let mut done = 0u64;
        while let Some(j) = (0..contact.len())
            .filter(|&j| contact[j] && done & (1 << j) == 0 && share[j] > 1e-6)
            .max_by(|&a, &b| share[a].total_cmp(&share[b]))
        {
            done |= 1 << j;
            let reached: Vector3<f64> = loads.iter().zip(&*share).map(|(l, r)| l.cop * *r).sum();
            let moved = loads[j].cop + (p - reached) / share[j];
            loads[j].cop = support[j].clamp(&moved, params.cop_margin);
        }
    }
    for (l, s) in loads.iter_mut().zip(support) {
        l.free_moment = within_torsion(l.free_moment, l, s, up, params);
    }
}

/// The shares of three or more feet in contact (a quadruped, a crab, a biped leaning on a hand):
/// the lever rule generalised, the shares `r` on the simplex (`r ≥ 0`, `Σ r = 1`) whose
/// load-weighted heel centre comes nearest the centre of pressure `p`, among those the nearest
/// to equal shares: `min |Σ rₖ cₖ − p|² + ε |r − 1/m|²` (`cₖ` the heels, `m` the feet in
/// contact, `ε` = (1 cm)², strictly convex so the shares move continuously with `p`). Equal
/// shares whatever `p` had left a standing elephant's pitching moment (176 N·m) to the root.
/// Solved by pairwise coordinate descent (each step moves load from one foot to another by
/// the exact minimiser along that direction, clamped to keep both shares ≥ 0), from equal
/// shares; two feet alone reduce to the lever rule.
fn many_feet_shares(
    p: &Vector3<f64>,
    support: &[Support],
    contact: &[bool],
    count: usize,
    share: &mut [f64],
) {
    const EPS: f64 = 1e-4;
    let equal = 1.0 / count as f64;
    let mut err = -p;
    for j in (0..contact.len()).filter(|&j| contact[j]) {
        share[j] = equal;
        err += support[j].heel * equal;
    }
    for _ in 0..64 {
        let mut moved = 0.0f64;
        for a in (0..contact.len()).filter(|&j| contact[j]) {
            for b in (a + 1..contact.len()).filter(|&j| contact[j]) {
                // r_a += δ, r_b −= δ: d/dδ of |err + δ d|² + ε((r_a − u + δ)² + (r_b − u − δ)²)
                let d = support[a].heel - support[b].heel;
                let den = d.norm_squared() + 2.0 * EPS;
                let delta =
                    (-(err.dot(&d) + EPS * (share[a] - share[b])) / den).clamp(-share[a], share[b]);
                share[a] += delta;
                share[b] -= delta;
                err += d * delta;
                moved = moved.max(delta.abs());
            }
        }
        if moved < 1e-12 {
            break;
        }
    }
}

/// Shares `w` between the feet of a step (double support between the single supports of the
/// trailing and the leading foot), writing `loads`: Ren et al.'s smooth transition (2008). The
/// trailing foot keeps the wrench it carried alone at its last single-support frame (`last`,
/// its centre of pressure given relative to its toe point, here `toe`), scaled down by the
/// falling share; the leading foot takes the rest of `w`. So each foot keeps a direction of its
/// own — the trailing foot pushing off, the leading foot braking — where sharing `w` itself
/// would give both feet the direction of the sum. The trailing foot never presses harder than
/// `w` does (the leading foot then carries nothing); it also keeps the horizontal force that
/// the leading foot, pressing lightly, cannot hold within its friction cone; the leading
/// foot's centre of pressure is kept inside its support, and what that removes is left to the
/// root.
#[allow(clippy::too_many_arguments)]
pub(super) fn assign_step(
    w: &ForceVec,
    support: &[Support],
    step: Step,
    last: &FootLoad,
    toe: Vector3<f64>,
    up: usize,
    floor: f64,
    params: &ContactParams,
    loads: &mut [FootLoad],
) {
    for (l, s) in loads.iter_mut().zip(support) {
        *l = FootLoad {
            force: Vector3::zeros(),
            cop: s.heel,
            free_moment: 0.0,
        };
    }
    if w.lin[up].is_nan() || w.lin[up] <= 1e-9 {
        return;
    }
    let (t, l) = (step.trailing, step.leading);
    let mut share = step.trailing_share;
    if last.force[up] * share > w.lin[up] {
        share = w.lin[up] / last.force[up];
    }
    let mut cop = support[t].clamp(&(last.cop + toe), params.cop_margin);
    cop[up] = floor;
    loads[t] = FootLoad {
        force: last.force * share,
        cop,
        free_moment: last.free_moment * share,
    };
    let e_up = Vector3::ith(up, 1.0);
    // early in the double support the leading foot presses lightly: the horizontal force it
    // cannot hold within its friction cone stays with the trailing foot
    let rest = *w - loads[t].wrench(&e_up);
    let horizontal = rest.lin - e_up * rest.lin[up];
    let limit = params.friction * rest.lin[up].max(0.0);
    if horizontal.norm() > limit {
        loads[t].force += horizontal * (1.0 - limit / horizontal.norm());
    }
    let rest = *w - loads[t].wrench(&e_up);
    let Some((p, free)) = centre_of_pressure(&rest, up, floor) else {
        return;
    };
    let cop = support[l].clamp(&p, params.cop_margin);
    loads[l] = FootLoad {
        force: rest.lin,
        cop,
        free_moment: free,
    };
    // where the clamp moved the leading foot's centre of pressure, the trailing foot's moves
    // the other way to make up the moment, in proportion to the two vertical forces (and is
    // kept inside its own support): the feet together still give w where its centre of
    // pressure lies between them
    let (f_t, f_l) = (loads[t].force[up], rest.lin[up]);
    if f_t > 1e-9 {
        let mut moved = loads[t].cop + (p - cop) * (f_l / f_t);
        moved[up] = floor;
        let moved = support[t].clamp(&moved, params.cop_margin);
        // the leading foot's moment and free moment follow from what the trailing foot gives
        loads[t].cop = moved;
        let rest = *w - loads[t].wrench(&e_up);
        if let Some((p, free)) = centre_of_pressure(&rest, up, floor) {
            loads[l].cop = support[l].clamp(&p, params.cop_margin);
            loads[l].free_moment = free;
        }
    }
    // each foot's free moment within its torsional friction
    for j in [t, l] {
        loads[j].free_moment =
            within_torsion(loads[j].free_moment, &loads[j], &support[j], up, params);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A quadruped's four feet at the corners of a 1 m × 0.4 m rectangle (Y up), and a fifth
    /// foot off the ground.
    fn four_feet() -> (Vec<Support>, Vec<bool>) {
        let at = |x: f64, z: f64| Support {
            heel: Vector3::new(x, 0.0, z),
            toe: Vector3::new(x + 0.1, 0.0, z),
        };
        let support = vec![
            at(0.5, 0.2),
            at(0.5, -0.2),
            at(-0.5, 0.2),
            at(-0.5, -0.2),
            at(0.0, 0.0),
        ];
        (support, vec![true, true, true, true, false])
    }

    fn shares_for(p: Vector3<f64>) -> (Vec<f64>, Vector3<f64>) {
        let (support, contact) = four_feet();
        let mut share = vec![0.0; 5];
        many_feet_shares(&p, &support, &contact, 4, &mut share);
        let centre = support.iter().zip(&share).map(|(s, r)| s.heel * *r).sum();
        (share, centre)
    }

    #[test]
    fn many_feet_shares_reach_the_centre_of_pressure_inside_the_feet_and_stay_equal_at_the_middle()
    {
        let (share, _) = shares_for(Vector3::zeros());
        assert!(
            share[..4].iter().all(|r| (r - 0.25).abs() < 1e-9),
            "{share:?}"
        );
        assert_eq!(share[4], 0.0, "a foot off the ground carries nothing");
        // the mass centre 30 cm forward, 10 cm to the side: the heels' weighted centre reaches
        // it (within what ε = (1 cm)² trades for evenness), the front feet carry more
        for p in [Vector3::new(0.3, 0.0, 0.1), Vector3::new(-0.45, 0.0, -0.15)] {
            let (share, centre) = shares_for(p);
            assert!((share.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            assert!(share.iter().all(|r| *r >= 0.0), "{share:?}");
            assert!((centre - p).norm() < 2e-3, "{p} → {centre}");
        }
        let (front, _) = shares_for(Vector3::new(0.3, 0.0, 0.0));
        assert!(front[0] > 0.35 && front[2] < 0.15, "{front:?}");
    }

    #[test]
    fn many_feet_shares_go_to_the_nearest_feet_outside_them_and_move_continuously() {
        // beyond the front feet: they carry it all, shared evenly between them
        let (share, _) = shares_for(Vector3::new(1.0, 0.0, 0.0));
        assert!(
            (share[0] - 0.5).abs() < 1e-6 && (share[1] - 0.5).abs() < 1e-6,
            "{share:?}"
        );
        // a 1 mm move of the centre of pressure moves no share by more than a few per cent
        let mut last = shares_for(Vector3::new(-0.6, 0.0, -0.3)).0;
        for k in 1..=1200 {
            let p = Vector3::new(-0.6 + k as f64 * 1e-3, 0.0, -0.3 + k as f64 * 5e-4);
            let (share, _) = shares_for(p);
            let jump = share
                .iter()
                .zip(&last)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            assert!(jump < 0.03, "at {p}: {last:?} → {share:?}");
            last = share;
        }
    }

    /// A foot that barely presses twists within its sole's friction (`Support::torsion_limit`):
    /// a wrench whose centre of pressure lies 10 m off (1 N down, 50 N sideways) asked the
    /// foot for 500 N·m before; one pressing with its centre of pressure on the sole keeps the
    /// whole body's free moment.
    #[test]
    fn a_foot_twists_within_its_soles_friction() {
        let params = ContactParams::default();
        let sole = [Support {
            heel: Vector3::zeros(),
            toe: Vector3::new(0.13, 0.0, 0.0),
        }];
        let load = |w: ForceVec| {
            let (mut share, mut loads) = (vec![0.0], vec![FootLoad::default()]);
            let (contact, up) = ([true], 1);
            assign_to_feet(
                &w, &sole, &contact, None, up, 0.0, &params, &mut share, &mut loads,
            );
            loads[0]
        };
        // 1 N down at x = 10 m (moment about z 10 N·m), 50 N along z: 500 N·m about the vertical
        let far = load(ForceVec::new(
            Vector3::new(0.0, 0.0, 10.0),
            Vector3::new(0.0, 1.0, 50.0),
        ));
        let limit = sole[0].torsion_limit(1.0, &params);
        assert!((limit - 0.115).abs() < 1e-12, "{limit}");
        assert!(
            far.free_moment.abs() <= limit + 1e-12,
            "{}",
            far.free_moment
        );
        // 700 N down at the sole's middle and a 5 N·m twist: the foot gives all of it
        let p = Vector3::new(0.065, 0.0, 0.0);
        let f = Vector3::new(20.0, 700.0, -30.0);
        let on = load(ForceVec::new(p.cross(&f) + Vector3::new(0.0, 5.0, 0.0), f));
        assert!((on.free_moment - 5.0).abs() < 1e-9, "{}", on.free_moment);
        assert!((on.cop - p).norm() < 1e-12);
    }
}
