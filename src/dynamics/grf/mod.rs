//! Ground reaction forces estimated from kinematics alone, and inverse dynamics with them.
//!
//! Top-down inverse dynamics of a floating avatar (RNEA from the root) hangs the body from its
//! root: the six root coordinates act as a non-physical actuator that supplies whatever wrench
//! the motion needs. On the ground that wrench comes through the feet. Method (Winter 2009,
//! *Biomechanics and Motor Control of Human Movement*, 4th ed., ch. 5 — the whole-body
//! equations of motion give the ground reaction when one foot is down; Ren, Jones & Howard
//! 2008, "Whole body inverse dynamics over a complete gait cycle based only on measured
//! kinematics", *J. Biomech.* 41, 2750–2759 — the same with a smooth transition assumption to
//! share the load in double support; the residual reported as a quality figure as OpenSim's
//! residual reduction does, Delp et al. 2007, *IEEE TBME* 54):
//!
//! 1. the whole-body external wrench `W` the motion needs: RNEA without external forces, the
//!    force each root-level body receives from the world, summed in world axes;
//! 2. its centre of pressure `p` on the floor (the point about which `W`'s moment is vertical:
//!    a force through `p` plus a free moment about the vertical);
//! 3. `W` assigned to the feet in contact ([`crate::motion::contact`]): one foot carries all of
//!    it; in the double support of a step, Ren et al.'s smooth transition — the trailing foot
//!    keeps the wrench it carried alone at its last single-support frame (its push-off force,
//!    centre of pressure and free moment), scaled down from 1 to 0 by the C² ramp
//!    `1 − (10u³ − 15u⁴ + 6u⁵)` between that frame and the leading foot's first single-support
//!    frame (their shape is an exponential decay, ours a polynomial that reaches exactly 0 and
//!    1), and the leading foot takes the rest of `W` ([`assign_step`]; where the rest's centre
//!    of pressure would leave the leading foot, the trailing foot's moves the other way to make
//!    up the moment, within its own support), so that each foot's
//!    force keeps a direction of its own (the trailing one pushing off, the leading one
//!    braking; a share of `W` would give both the direction of the sum, and the trailing knee
//!    an extensor moment it does not have in pre-swing); double supports that are not a step
//!    (standing, landing on both feet, the take's first and last double supports) share by
//!    the lever rule, in proportion to how close `p` lies to each ankle, entered from the
//!    single support before them and left to the one after over a ramp as long as the take's
//!    median step transition (wrenches interpolated, [`transitions`]), so that no foot's load
//!    jumps where a double support begins or ends; three or more feet (an animal's) by the
//!    lever rule generalised: the shares whose load-weighted ankle centre comes nearest `p`,
//!    among those the nearest to equal shares (`share::many_feet_shares`); in flight the feet carry nothing, except within the estimator's
//!    spread of a contact (below);
//! 4. each foot's force acts at `p` shifted by the foot's offset from the load-weighted ankle
//!    centre (so the shares together still reproduce `W`), kept inside the foot's support
//!    region (the heel–toe segment widened by [`ContactParams::cop_margin`]), pushing only
//!    (vertical force ≥ 0) and inside the friction cone; what these limits remove is left to
//!    the root;
//! 5. RNEA again with the foot wrenches as external forces; the root's six generalized forces
//!    that remain are the **residual**, the part of the motion the feet cannot explain (capture
//!    noise, mass model errors, a missed contact);
//! 6. how far the feet's loads together reproduce `W`'s centre of pressure, per frame
//!    ([`GroundReactions::cop_gap`]); the root's horizontal moment is that gap times the
//!    vertical force. Over single support, where the needed force and centre of pressure are
//!    the motion's alone, [`GroundReactions::quality`] summarises it for the user (`articula id
//!    --contact feet`, the workbench's status line): a take whose needed centre of pressure
//!    often leaves the foot asks for a ground force no foot can give, and its joint torques
//!    there are those of the nearest one the foot can.
//!
//! The spread of the estimate. The accelerations at a frame are a weighted average of the true
//! ones over ±[`ContactParams::spread_s`] (smoothing, then central differences:
//! [`acceleration_spread_s`], ±0.09–0.1 s with the default 6 Hz Butterworth), so the force of a
//! landing appears in the needed wrench before the foot touches down, and a push-off's after it
//! has left, while the body is in the air. Measured on the running take (30 fps) and the
//! jumps of CMU 01_01 (120 fps), that is where the root residual was: 0.5–1.2 body weights in
//! the 2–10 frames before each touch-down, nothing in stance; without smoothing the run shows
//! the same (at 30 fps the differences alone spread a frame each side). Such flight frames are
//! carried by the foot of the nearer contact, as long as the needed force presses on the floor
//! ([`carry_across_spread`]); the reported ground force is then the estimator's view of the
//! impact, spread in time as the accelerations are. Frames further from contact are flight and
//! carry nothing.
//!
//! [`acceleration_spread_s`]: crate::motion::contact::acceleration_spread_s

mod lost;
pub mod measured;
mod passes;
mod reactions;
mod share;

use super::Workspace;
use crate::error::Error;
use crate::model::{JointKind, Model};
use crate::motion::contact::{
    ContactParams, Foot, FootPoints, contact_phases, fit_heel_points, floor_height, foot_bodies,
    why_no_contact,
};
use crate::spatial::{ForceVec, SpatialTransform};
pub use lost::{FloorLost, HELD_SHARE, MIN_LOST_S, floor_lost_text};
use nalgebra::Vector3;
pub use reactions::{COP_GAP_TOLERANCE, GroundQuality, GroundReactions};
use share::*;

/// Estimates ground reaction forces and the joint torques with them for a take given as
/// samples `time` (s) of `q`, `v`, `a` (nq, nv, nv per sample), `up` being the index of the
/// vertical axis (0, 1, 2), with the feet found by body names ([`foot_bodies`]). For a BVH
/// take prefer [`estimate_ground_reactions_with_feet`] with [`feet_of_bvh`], which also knows
/// End Sites and welded joints:
///
/// ```ignore
/// let feet = feet_of_bvh(&take.bvh, &take.map, &take.model);
/// let s = &take.states;
/// let gr = estimate_ground_reactions_with_feet(&take.model, &feet, &s.time, &s.q, &s.v, &s.a,
///     take.up.index(), &ContactParams::default())?;
/// ```
///
/// [`feet_of_bvh`]: crate::motion::contact::feet_of_bvh
pub fn estimate_ground_reactions(
    model: &Model,
    time: &[f64],
    q: &[Vec<f64>],
    v: &[Vec<f64>],
    a: &[Vec<f64>],
    up: usize,
    params: &ContactParams,
) -> Result<GroundReactions, Error> {
    let feet = foot_bodies(model);
    estimate_ground_reactions_with_feet(model, &feet, time, q, v, a, up, params)
}

/// [`estimate_ground_reactions`] with the feet given. See the module documentation for the
/// method.
///
/// Errors: sizes that disagree, fewer than two samples, a model whose gravity does not point
/// down the up axis, without a floating root (three translations and three rotations from the
/// world), or no feet.
#[allow(clippy::too_many_arguments)]
pub fn estimate_ground_reactions_with_feet(
    model: &Model,
    feet: &[Foot],
    time: &[f64],
    q: &[Vec<f64>],
    v: &[Vec<f64>],
    a: &[Vec<f64>],
    up: usize,
    params: &ContactParams,
) -> Result<GroundReactions, Error> {
    estimate_ground_reactions_progress(model, feet, time, q, v, a, up, params, &mut |_| true)
}

/// Frames between two calls of the progress callback of [`estimate_ground_reactions_progress`].
pub const PROGRESS_EVERY: usize = 64;

/// [`estimate_ground_reactions_with_feet`] that reports its progress (0‥1) to `keep_going`
/// every [`PROGRESS_EVERY`] frames of its two passes over the take and stops with
/// [`Error::Cancelled`] when it returns false (the callback is called by reference; nothing is
/// allocated for it).
#[allow(clippy::too_many_arguments)]
pub fn estimate_ground_reactions_progress(
    model: &Model,
    feet: &[Foot],
    time: &[f64],
    q: &[Vec<f64>],
    v: &[Vec<f64>],
    a: &[Vec<f64>],
    up: usize,
    params: &ContactParams,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<GroundReactions, Error> {
    let qva = [q, v, a];
    let contact = (params, None, None);
    estimate_ground_reactions_keeping(model, feet, time, qva, up, contact, &[], keep_going)
}

/// [`estimate_ground_reactions_progress`] that also keeps the net moments of RNEA with the
/// ground reactions on `moment_bodies` (sorted, each once) at every frame
/// ([`GroundReactions::moments`]), from the pass that computes the torques: the joint moments
/// need no RNEA of their own; with the contact phases `held` when given ([`Held`]), and the
/// feet's fitted paths when already made for these feet over these configurations
/// ([`FootPaths`]; paths made for other feet or another number of frames are not read).
#[allow(clippy::too_many_arguments)]
pub fn estimate_ground_reactions_keeping(
    model: &Model,
    feet: &[Foot],
    time: &[f64],
    qva: [&[Vec<f64>]; 3],
    up: usize,
    (params, held, paths): ContactInputs,
    moment_bodies: &[usize],
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<GroundReactions, Error> {
    let third = Third::Torques(moment_bodies);
    estimate(
        model,
        feet,
        time,
        qva,
        up,
        (params, held, paths),
        third,
        keep_going,
    )
}

/// Contact phases held from an earlier estimate of the same take
/// ([`GroundReactions::contact`]: per frame, per foot), or `None`: found from the motion the
/// estimate is given. Residual reduction holds those of the take as loaded through its
/// trials and in its adjusted take, as OpenSim's RRA holds its measured forces: a trial's
/// pelvis path moves the feet by centimetres, and a foot that crossed a threshold a frame
/// sooner made the reduction's cost jump between neighbouring trials.
pub type Held<'a> = Option<&'a [Vec<bool>]>;

/// What the estimate finds contact with: the thresholds, the phases when held ([`Held`]) and
/// the feet's fitted paths when already made ([`FootPaths`]).
pub type ContactInputs<'a> = (&'a ContactParams, Held<'a>, Option<&'a FootPaths>);

/// [`estimate_ground_reactions_progress`] without the joint torques (`tau` and `moments`
/// empty), what residual reduction evaluates at each trial of its adjustments: the residual
/// is the needed wrench less the feet's (inverse dynamics is linear in the external forces),
/// the same to rounding as what RNEA with the feet's loads leaves at the root, without that
/// RNEA (a fifth of a cold reduction's instructions).
pub fn estimate_ground_residuals(
    model: &Model,
    feet: &[Foot],
    time: &[f64],
    qva: [&[Vec<f64>]; 3],
    up: usize,
    params: &ContactParams,
    held: Held,
) -> Result<GroundReactions, Error> {
    let contact = (params, held, None);
    estimate(
        model,
        feet,
        time,
        qva,
        up,
        contact,
        Third::Residual,
        &mut |_| true,
    )
}

/// Pass 1 of the estimate supplied by the caller: per frame, the whole-body wrench the motion
/// needs (world axes, about the world origin, as RNEA without external forces gives it), the
/// centre of mass (m, world), and the world poses of the bodies [`kept_bodies`] lists
/// (`[frame * bodies + j]`). Residual reduction computes them from root-relative terms
/// ([`crate::dynamics::rra`]) for each trial, without the frames' kinematics and RNEA.
pub(crate) struct NeededWrenches {
    pub needed: Vec<ForceVec>,
    pub com: Vec<Vector3<f64>>,
    pub poses: Vec<SpatialTransform>,
}

/// The bodies whose world poses the estimate reads after its first pass (each foot's ankle and
/// toe body, the floating root, the bodies hung from the world), sorted; `None` without a
/// floating root.
pub(crate) fn kept_bodies(model: &Model, feet: &[Foot]) -> Option<Vec<usize>> {
    Some(passes::Poses::bodies(model, feet, floating_root(model)?))
}

/// [`estimate_ground_residuals`] from a supplied pass 1 (`given`, over the frames of `time`,
/// the poses of [`kept_bodies`]).
pub(crate) fn estimate_ground_residuals_given(
    model: &Model,
    feet: &[Foot],
    time: &[f64],
    given: NeededWrenches,
    up: usize,
    params: &ContactParams,
    held: Held,
) -> Result<GroundReactions, Error> {
    let (root, bodies) = match (floating_root(model), kept_bodies(model, feet)) {
        (Some(r), Some(b)) => (r, b),
        _ => {
            return Err(Error::Invalid(
                "ground contact needs a floating root".into(),
            ));
        }
    };
    let n = time.len();
    if given.needed.len() != n || given.com.len() != n || given.poses.len() != n * bodies.len() {
        return Err(Error::Invalid(format!(
            "a supplied first pass of {} frames for a take of {n}",
            given.needed.len()
        )));
    }
    let pass1 = (
        given.needed,
        given.com,
        passes::Poses::from_parts(bodies, given.poses),
    );
    estimate_from(
        model,
        feet,
        time,
        root,
        pass1,
        up,
        (params, held, None),
        Third::Residual,
        None,
    )
}

/// What the estimate's third pass computes.
#[derive(Clone, Copy)]
enum Third<'a> {
    /// RNEA with the feet's loads: the joint torques, the residual, and the net moments of
    /// these bodies.
    Torques(&'a [usize]),
    /// The residual only, as the needed wrench less the feet's.
    Residual,
}

#[allow(clippy::too_many_arguments)]
fn estimate(
    model: &Model,
    feet: &[Foot],
    time: &[f64],
    [q, v, a]: [&[Vec<f64>]; 3],
    up: usize,
    contact: ContactInputs,
    third: Third,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<GroundReactions, Error> {
    let n = time.len();
    check_inputs(model, time, q, v, a, up)?;
    let root = floating_root(model).ok_or_else(|| {
        Error::Invalid(format!(
            "model {}: ground contact needs a floating root (a free joint, or three prismatic \
             and three revolute joints from the world); use --contact none",
            model.name
        ))
    })?;
    if feet.is_empty() {
        return Err(Error::Invalid(format!(
            "model {}: no feet found (joints named like LeftFoot/RightFoot, lFoot, Foot_L, \
             foot.L); use --contact none",
            model.name
        )));
    }
    // pass 1: the whole-body wrench each frame needs (world axes, about the world origin),
    // and the poses of the bodies every later step reads (frames in parallel: `passes`)
    // (with the torques: pass 1 also keeps RNEA's torques and moments without the ground,
    // which pass 3 takes the feet's loads from)
    let bodies = passes::Poses::bodies(model, feet, root);
    let (mut tau, mut moments) = match third {
        Third::Torques(b) => (
            vec![vec![0.0; model.nv]; n],
            vec![Vector3::zeros(); n * b.len()],
        ),
        Third::Residual => (vec![], vec![]),
    };
    let unloaded = match third {
        Third::Torques(b) => Some(passes::Unloaded {
            tau: &mut tau,
            bodies: b,
            moments: &mut moments,
        }),
        Third::Residual => None,
    };
    let pass1 = passes::needed_wrenches(model, bodies, [q, v, a], unloaded, &mut |k| {
        keep_going(0.5 * k as f64 / n as f64)
    })
    .ok_or(Error::Cancelled)?;
    let rest = Some(PassThree {
        q,
        tau,
        moments,
        keep_going,
    });
    estimate_from(model, feet, time, root, pass1, up, contact, third, rest)
}

/// What pass 3 needs beyond the loads: the motion, pass 1's torques and moments without the
/// ground ([`passes::Unloaded`]), and the progress to report to.
struct PassThree<'a, 'b> {
    q: &'a [Vec<f64>],
    tau: Vec<Vec<f64>>,
    moments: Vec<Vector3<f64>>,
    keep_going: &'b mut dyn FnMut(f64) -> bool,
}

/// The estimate after its first pass (`pass1`: the needed wrenches, centre of mass and kept
/// poses): the contact phases, the loads (pass 2) and, for [`Third::Torques`], RNEA with them
/// (pass 3, over the motion and with the progress `rest` holds).
#[allow(clippy::too_many_arguments)]
fn estimate_from(
    model: &Model,
    feet: &[Foot],
    time: &[f64],
    root: usize,
    (needed, com, poses): (Vec<ForceVec>, Vec<Vector3<f64>>, passes::Poses),
    up: usize,
    (params, held, paths): ContactInputs,
    third: Third,
    rest: Option<PassThree>,
) -> Result<GroundReactions, Error> {
    let moment_bodies = match third {
        Third::Torques(b) => b,
        Third::Residual => &[],
    };
    let n = time.len();
    let dt = (time[n - 1] - time[0]) / (n - 1) as f64;

    // contact phases from the heel and toe paths, unless held; the paths from the fit that
    // made `params` when it was made for these feet over these frames (the same bits: the
    // fit's kinematics are the first pass's, `passes::Poses::of_motion`)
    use std::borrow::Cow;
    let (feet, points): (Cow<[Foot]>, Cow<[FootPoints]>) = match paths {
        Some(p) if p.given == feet && p.points.iter().all(|f| f.toe.len() == n) => {
            (Cow::Borrowed(&p.feet), Cow::Borrowed(&p.points))
        }
        _ => {
            let mut feet = feet.to_vec();
            let points = foot_paths(&poses, &mut feet, up);
            (Cow::Owned(feet), Cow::Owned(points))
        }
    };
    let floor = floor_height(&points, up);
    let contact: Vec<Vec<bool>> = match held {
        Some(c) if c.len() == n && c.iter().all(|f| f.len() == feet.len()) => c.to_vec(),
        Some(c) => {
            return Err(Error::Invalid(format!(
                "contact phases held for {} frames of {} feet, for a take of {n} frames and {} feet",
                c.len(),
                c.first().map_or(0, Vec::len),
                feet.len()
            )));
        }
        None => {
            let by_foot = planted_feet(&points, up, dt, params).map_err(|why| {
                Error::Invalid(format!(
                    "model {}: {why}; use --contact none (`set contact none` in the workbench)",
                    model.name
                ))
            })?;
            (0..n)
                .map(|k| by_foot.iter().map(|c| c[k]).collect())
                .collect()
        }
    };
    let shares = transitions(&contact, time);
    let up_force: Vec<f64> = needed.iter().map(|w| w.lin[up]).collect();
    let spread = (params.spread_s / dt).round() as usize;
    let loaded = carry_across_spread(&contact, &up_force, spread);

    let nf = feet.len();
    let mut out = GroundReactions {
        feet: feet.iter().map(|f| f.name.clone()).collect(),
        bodies: feet.iter().map(|f| f.ankle_body).collect(),
        up,
        floor,
        contact,
        loaded,
        foot_height: match third {
            Third::Torques(_) => lost::lowest_point_heights(&points, up),
            Third::Residual => vec![],
        },
        grf: vec![vec![Vector3::zeros(); nf]; n],
        cop: vec![vec![Vector3::zeros(); nf]; n],
        free_moment: vec![vec![0.0; nf]; n],
        wrench: vec![[0.0; 6]; n],
        residual: vec![[0.0; 6]; n],
        pelvis: vec![Vector3::zeros(); n],
        com,
        cop_gap: vec![0.0; n],
        // pass 1's torques and moments, with the loads taken from them by pass 3
        tau: vec![],
        moment_bodies: moment_bodies.to_vec(),
        moments: vec![],
    };
    // pass 2 (serial: a foot's load carries from frame to frame): the feet's loads
    let wrenches = assign_loads(
        model, &feet, root, &poses, &needed, &shares, params, &mut out,
    );

    // the residual: the needed wrench less the feet's, about the pelvis
    for (k, r) in out.residual.iter_mut().enumerate() {
        let mut w = needed[k];
        for f in &wrenches[k * nf..(k + 1) * nf] {
            w -= *f;
        }
        *r = about(&w, &out.pelvis[k]);
    }
    if let Third::Residual = third {
        return Ok(out);
    }
    // pass 3: the feet's loads taken from pass 1's torques and moments (frames in parallel)
    let Some(PassThree {
        q,
        tau,
        moments,
        keep_going,
    }) = rest
    else {
        return Err(Error::Invalid(
            "the joint torques need the motion, not a supplied first pass".into(),
        ));
    };
    (out.tau, out.moments) = (tau, moments);
    let finished = passes::with_ground_reactions(
        model,
        &out.bodies,
        &wrenches,
        q,
        (&mut out.tau, (moment_bodies, &mut out.moments)),
        &mut |k| keep_going(0.5 + 0.5 * k as f64 / n as f64),
    );
    if !finished {
        return Err(Error::Cancelled);
    }
    Ok(out)
}

/// Pass 2 of the estimate: the loads of the feet at every frame, from the needed wrenches
/// `needed` and the kept poses, written into `out` (`pelvis`, `wrench`, `grf`, `cop`,
/// `free_moment`, `cop_gap`; `out.loaded` read). Returns each foot's wrench (`[frame * feet + j]`, world
/// axes about the world origin) for pass 3.
#[allow(clippy::too_many_arguments)]
fn assign_loads(
    model: &Model,
    feet: &[Foot],
    root: usize,
    poses: &passes::Poses,
    needed: &[ForceVec],
    shares: &[Option<Transition>],
    params: &ContactParams,
    out: &mut GroundReactions,
) -> Vec<ForceVec> {
    let (n, nf, up, floor) = (needed.len(), feet.len(), out.up, out.floor);
    let mut o_x_i = vec![SpatialTransform::IDENTITY; model.nbodies()];
    let mut wrenches = vec![ForceVec::ZERO; n * nf];
    let mut loads = vec![FootLoad::default(); nf];
    let mut scratch = Scratch::new(nf);
    let mut support = vec![Support::default(); nf];
    let mut last_single: Vec<Option<FootLoad>> = vec![None; nf];
    let e_up = Vector3::ith(up, 1.0);
    for k in 0..n {
        // whole-body wrench the motion needs (world axes, about the world origin)
        poses.restore(k, &mut o_x_i);
        let w = needed[k];
        let pelvis = o_x_i[root].trans;
        out.pelvis[k] = pelvis;
        out.wrench[k] = about(&w, &pelvis);

        // the feet's shares and their wrenches
        for (s, f) in support.iter_mut().zip(feet) {
            *s = Support::new(f, &o_x_i, up, floor);
        }
        let c = &out.loaded[k];
        let floor_at = Floor { up, height: floor };
        assign(
            &w,
            &support,
            c,
            shares[k],
            &last_single,
            floor_at,
            params,
            &mut scratch,
            &mut loads,
        );
        // a foot alone on the floor: what it carries now is where its next step starts from
        // (its centre of pressure kept relative to its toe, about which it rolls off)
        if c.iter().filter(|c| **c).count() == 1 {
            let j = c.iter().position(|c| *c).unwrap_or(0);
            last_single.fill(None);
            last_single[j] = Some(FootLoad {
                cop: loads[j].cop - support[j].toe,
                ..loads[j]
            });
        }
        let mut given = ForceVec::ZERO;
        for (j, load) in loads.iter().enumerate() {
            out.grf[k][j] = load.force;
            out.cop[k][j] = load.cop;
            out.free_moment[k][j] = load.free_moment;
            let wj = load.wrench(&e_up);
            wrenches[k * nf + j] = wj;
            given += wj;
        }
        if let (Some((p, _)), Some((p_feet, _))) = (
            centre_of_pressure(&w, up, floor),
            centre_of_pressure(&given, up, floor),
        ) {
            out.cop_gap[k] = (p - p_feet).norm();
        }
    }
    wrenches
}

/// The contact phases (`[foot][frame]`) of the feet whose heel and toe paths over samples
/// `time` are `points` ([`foot_points`]; the first step of
/// [`estimate_ground_reactions_with_feet`]), or, when no foot is ever planted on a floor, why
/// not ([`why_no_contact`]): what `--contact auto` decides by.
pub fn stance(
    points: &[FootPoints],
    time: &[f64],
    up: usize,
    params: &ContactParams,
) -> Result<Vec<Vec<bool>>, String> {
    let n = time.len();
    let sized = |p: &FootPoints| p.heel.len() == n && p.toe.len() == n;
    if n < 2 || points.is_empty() || !points.iter().all(sized) {
        return Err(format!(
            "{n} frames and {} feet: no contact phases",
            points.len()
        ));
    }
    let dt = (time[n - 1] - time[0]) / (n - 1) as f64;
    planted_feet(points, up, dt, params)
}

/// Feet with their heel points fitted to a take ([`fit_heel_points`]: the rest pose of some
/// skeletons is not standing) and the world paths of their heel and toe points over it: what
/// the contact phases are found from and the contact heights are fitted to
/// ([`ContactParams::fitted_to`]). Made once per motion (`pipeline::ContactFit`); the estimate
/// takes them rather than fitting the same feet to the same poses again.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FootPaths {
    /// The feet as they were given.
    pub given: Vec<Foot>,
    /// The same feet, their heel points fitted.
    pub feet: Vec<Foot>,
    /// Each foot's heel and toe paths (world, m), one point per frame.
    pub points: Vec<FootPoints>,
}

/// The [`FootPaths`] of `feet` over the configurations `q`.
pub fn fitted_foot_paths(model: &Model, feet: &[Foot], q: &[Vec<f64>], up: usize) -> FootPaths {
    let mut fitted = feet.to_vec();
    let bodies = feet
        .iter()
        .flat_map(|f| [f.ankle_body, f.toe_body])
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    let poses = passes::Poses::of_motion(model, bodies, q);
    let points = foot_paths(&poses, &mut fitted, up);
    FootPaths {
        given: feet.to_vec(),
        feet: fitted,
        points,
    }
}

/// The contact phases of the feet whose heel and toe paths are `points`, or why no foot is
/// ever planted ([`why_no_contact`]).
fn planted_feet(
    points: &[FootPoints],
    up: usize,
    dt: f64,
    params: &ContactParams,
) -> Result<Vec<Vec<bool>>, String> {
    let by_foot = contact_phases(points, up, dt, params);
    if by_foot.iter().flatten().all(|c| !c) {
        return Err(why_no_contact(points, up, dt, params));
    }
    Ok(by_foot)
}

fn check_inputs(
    model: &Model,
    time: &[f64],
    q: &[Vec<f64>],
    v: &[Vec<f64>],
    a: &[Vec<f64>],
    up: usize,
) -> Result<(), Error> {
    let n = time.len();
    if n < 2 {
        return Err(Error::Invalid(format!(
            "ground reactions need a motion: the take has {n} frame{}, and contact is found \
             from how the feet move (use --contact none, `set contact none` in the workbench)",
            if n == 1 { "" } else { "s" }
        )));
    }
    if q.len() != n || v.len() != n || a.len() != n {
        return Err(Error::Invalid(format!(
            "ground reactions need at least two samples of time, q, v, a of equal length (got \
             {n}, {}, {}, {})",
            q.len(),
            v.len(),
            a.len()
        )));
    }
    if let Some(k) =
        (0..n).find(|&k| q[k].len() != model.nq || v[k].len() != model.nv || a[k].len() != model.nv)
    {
        return Err(Error::Invalid(format!(
            "sample {k}: q, v, a have {}, {}, {} values; model {} has nq = {}, nv = {}",
            q[k].len(),
            v[k].len(),
            a[k].len(),
            model.name,
            model.nq,
            model.nv
        )));
    }
    if time[n - 1].partial_cmp(&time[0]) != Some(std::cmp::Ordering::Greater) {
        return Err(Error::Invalid(format!(
            "sample times must increase (first {}, last {})",
            time[0],
            time[n - 1]
        )));
    }
    if up > 2 || model.gravity[up].partial_cmp(&0.0) != Some(std::cmp::Ordering::Less) {
        return Err(Error::Invalid(format!(
            "up axis {up}: expected 0, 1 or 2 with the model's gravity {:?} pointing down it",
            model.gravity.as_slice()
        )));
    }
    Ok(())
}

/// The last body of the floating root chain: bodies `1..=r` form a chain from the world whose
/// joints give three translations and three rotations (one free joint, or prismatic and
/// revolute/spherical joints), owning velocity coordinates `0..6`.
pub fn floating_root(model: &Model) -> Option<usize> {
    if model.nv < 6 {
        return None;
    }
    let r = model.body_of_v(5);
    let (mut lin, mut ang) = (0, 0);
    for i in 1..=r {
        if model.parent[i] != i - 1 {
            return None;
        }
        match model.joints[i] {
            JointKind::Free => (lin, ang) = (lin + 3, ang + 3),
            JointKind::Prismatic { .. } => lin += 1,
            JointKind::Revolute { .. } => ang += 1,
            JointKind::Spherical => ang += 3,
            JointKind::Fixed => {}
        }
    }
    (lin == 3 && ang == 3).then_some(r)
}

/// World path of each foot's heel and toe over the take, from the kept poses, after fitting
/// each heel point to the take ([`fit_heel_points`]: the rest pose of some skeletons is not
/// standing).
fn foot_paths(poses: &passes::Poses, feet: &mut [Foot], up: usize) -> Vec<FootPoints> {
    let (ankle_poses, mut paths) = poses.feet(feet);
    let floor = floor_height(&paths, up);
    fit_heel_points(feet, &ankle_poses, up, floor);
    for ((p, x), f) in paths.iter_mut().zip(&ankle_poses).zip(&*feet) {
        p.heel = x.iter().map(|x| x.transform_point(&f.heel_point)).collect();
    }
    paths
}

/// The wrench the world applies on the model through the joints of the root-level bodies
/// (world axes, about the world origin), from `ws.f` and `ws.o_x_i`.
pub(crate) fn root_wrench(model: &Model, ws: &Workspace) -> ForceVec {
    (1..model.nbodies())
        .filter(|&i| model.parent[i] == 0)
        .map(|i| ws.o_x_i[i].act_force(&ws.f[i]))
        .fold(ForceVec::ZERO, |s, f| s + f)
}

/// `[fx, fy, fz, tx, ty, tz]` of a wrench given about the world origin, taken about `point`.
pub(crate) fn about(w: &ForceVec, point: &Vector3<f64>) -> [f64; 6] {
    let n = w.ang - point.cross(&w.lin);
    [w.lin.x, w.lin.y, w.lin.z, n.x, n.y, n.z]
}

/// Which feet carry the needed wrench in each frame: the feet in contact; and in a frame of
/// flight (no foot in contact) that lies within `spread` frames of the contact before or after
/// it, the feet of that contact (the nearer one), as long as the needed vertical force
/// `up_force` (N) still presses on the floor from that contact to the frame.
///
/// Why: the estimated accelerations at a frame average the true ones over
/// ±[`ContactParams::spread_s`] ([`acceleration_spread_s`]), so the force of a landing shows
/// up to that long before touch-down, and a push-off's after lift-off, while the body is in
/// the air. That force is the stance's, spread by the estimator: it belongs to the foot that
/// is about to land (or has just left), not to the root. Frames further from contact, or where
/// the needed force pulls, are flight and carry nothing.
///
/// [`acceleration_spread_s`]: crate::motion::contact::acceleration_spread_s
pub fn carry_across_spread(
    contact: &[Vec<bool>],
    up_force: &[f64],
    spread: usize,
) -> Vec<Vec<bool>> {
    let n = contact.len();
    let mut loaded = contact.to_vec();
    let flight = |k: usize| contact[k].iter().all(|c| !c);
    for run in crate::motion::runs(n, flight) {
        let (s, k) = (run.start, run.end);
        // frames s..k are flight; distance (in frames) from the contact before and after
        let reach = |range: &mut dyn Iterator<Item = usize>| -> Vec<usize> {
            range
                .take(spread)
                .take_while(|&j| up_force[j] > 0.0)
                .collect()
        };
        let after = if s > 0 { reach(&mut (s..k)) } else { vec![] };
        let before = if k < n {
            reach(&mut (s..k).rev())
        } else {
            vec![]
        };
        for &j in &after {
            let nearer_next = k < n && before.contains(&j) && k - j < j + 1 - s;
            if !nearer_next {
                loaded[j].clone_from(&contact[s - 1]);
            }
        }
        for &j in &before {
            let nearer_prev = s > 0 && after.contains(&j) && j + 1 - s <= k - j;
            if !nearer_prev {
                loaded[j].clone_from(&contact[k]);
            }
        }
    }
    loaded
}

#[cfg(test)]
mod tests;
