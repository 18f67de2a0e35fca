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
use share::*;

/// Ground reactions and the inverse dynamics with them, frame by frame. World quantities are in
/// the take's axes, moments about the root joint's origin (the pelvis) unless said otherwise.
#[derive(Debug, Clone, PartialEq)]
pub struct GroundReactions {
    /// Foot names (`left`, `right`): the order of every per-foot vector below.
    pub feet: Vec<String>,
    /// The body each foot's load acts on (the foot's `ankle_body`).
    pub bodies: Vec<usize>,
    /// The up axis (0, 1, 2) of the world.
    pub up: usize,
    /// Floor height along the up axis (m).
    pub floor: f64,
    /// `[frame][foot]`: the foot is in contact.
    pub contact: Vec<Vec<bool>>,
    /// `[frame][foot]`: the foot carries load: it is in contact, or the frame is a flight frame
    /// within [`ContactParams::spread_s`] of the foot's contact phase, where the smoothed
    /// estimate still needs a pressing force (see [`carry_across_spread`]).
    pub loaded: Vec<Vec<bool>>,
    /// `[frame]`: the height (m) of the lowest foot point over the floor: the least of every
    /// foot's heel and toe heights over the floor levels of the heel and of the toe points,
    /// the heights the contact test measures ([`point_levels`]); where it exceeds the contact
    /// height no foot can touch the floor ([`GroundReactions::floor_lost`]). Empty for
    /// measured ground reactions, whose feet's paths are not known, and for the residual alone
    /// ([`estimate_ground_residuals`], residual reduction's trials).
    ///
    /// [`point_levels`]: crate::motion::contact::point_levels
    pub foot_height: Vec<f64>,
    /// `[frame][foot]`: force of the ground on the foot (N, world axes); zero off the floor.
    pub grf: Vec<Vec<Vector3<f64>>>,
    /// `[frame][foot]`: centre of pressure of that force on the floor (m, world); for an
    /// unloaded foot, its ankle's projection on the floor (so that plots stay continuous).
    pub cop: Vec<Vec<Vector3<f64>>>,
    /// `[frame][foot]`: free moment of the ground on the foot about the vertical (N·m).
    pub free_moment: Vec<Vec<f64>>,
    /// `[frame]`: the whole-body external wrench the motion needs, `[fx, fy, fz, tx, ty, tz]`
    /// (N, N·m about the root joint's origin, world axes): the root residual without contact.
    pub wrench: Vec<[f64; 6]>,
    /// `[frame]`: what the root still supplies with the ground reactions applied, same layout.
    pub residual: Vec<[f64; 6]>,
    /// `[frame]`: the root joint's origin (m, world): the point `wrench` and `residual` are
    /// taken about.
    pub pelvis: Vec<Vector3<f64>>,
    /// `[frame]`: the whole-body centre of mass (m, world;
    /// [`centre_of_mass`](super::residual::centre_of_mass) of the frame's kinematics).
    pub com: Vec<Vector3<f64>>,
    /// `[frame]`: how far (m, along the floor) the centre of pressure of the feet's loads
    /// together lies from the one the whole-body wrench needs; 0 where they coincide, where no
    /// foot is loaded, or where the motion needs no pressing force. It grows where the needed
    /// centre of pressure leaves the feet (the loads keep theirs inside) or a force leaves the
    /// friction cone: the motion asks for a ground force no foot can give, and the joint
    /// torques there are those of the nearest one the feet can ([`GroundReactions::quality`]).
    pub cop_gap: Vec<f64>,
    /// `[frame][nv]`: generalized forces with the ground reactions applied (N·m, N).
    pub tau: Vec<Vec<f64>>,
    /// The bodies whose net moment with the ground reactions was kept (asked of
    /// [`estimate_ground_reactions_keeping`]; empty otherwise), sorted, each once.
    pub moment_bodies: Vec<usize>,
    /// `[frame * moment_bodies.len() + j]`: the net moment `f.ang` of RNEA with the ground
    /// reactions on body `moment_bodies[j]` (N·m, the body's frame, as `ws.f` holds it): what
    /// the joint moments of `pipeline::anatomy` read, from the estimate's own pass.
    pub moments: Vec<Vector3<f64>>,
}

impl GroundReactions {
    /// CSV column names: `grf:<foot>:x|y|z`, `cop:<foot>:x|y|z` per foot, then
    /// `residual:fx|fy|fz|tx|ty|tz`.
    pub fn columns(&self) -> Vec<String> {
        let mut c = vec![];
        for what in ["grf", "cop"] {
            for f in &self.feet {
                c.extend(["x", "y", "z"].map(|a| format!("{what}:{f}:{a}")));
            }
        }
        c.extend(["fx", "fy", "fz", "tx", "ty", "tz"].map(|a| format!("residual:{a}")));
        c
    }

    /// The values of [`columns`](Self::columns) at frame `k`, appended to `out`.
    pub fn row(&self, k: usize, out: &mut Vec<f64>) {
        for per_foot in [&self.grf[k], &self.cop[k]] {
            for p in per_foot {
                out.extend_from_slice(p.as_slice());
            }
        }
        out.extend_from_slice(&self.residual[k]);
    }

    /// The ground's loads at frame `k` as external forces per body for
    /// [`rnea`](super::rnea) (`out` has `nbodies` entries, zeroed first): each foot's force at
    /// its centre of pressure with its free moment, in the frame of the body it acts on, from
    /// the world poses `o_x_i` of that frame (`forward_kinematics`).
    pub fn external_forces(&self, k: usize, o_x_i: &[SpatialTransform], out: &mut [ForceVec]) {
        out.fill(ForceVec::ZERO);
        for (j, &b) in self.bodies.iter().enumerate() {
            out[b] += o_x_i[b].act_inv_force(&self.foot_wrench(k, j));
        }
    }

    /// Foot `j`'s load at frame `k` as a wrench about the world origin (world axes): its force
    /// at its centre of pressure with its free moment about the vertical.
    pub fn foot_wrench(&self, k: usize, j: usize) -> ForceVec {
        let load = FootLoad {
            force: self.grf[k][j],
            cop: self.cop[k][j],
            free_moment: self.free_moment[k][j],
        };
        load.wrench(&Vector3::ith(self.up, 1.0))
    }

    /// The ground's loads at frame `k` taken from what RNEA without them left: from the
    /// generalized forces `tau` (when given) and from the net moments `moments` (each body's
    /// frame, as `ws.f[b].ang`) of `moment_bodies` (sorted). Inverse dynamics is linear in the
    /// external forces, so this is RNEA with the loads to rounding; it is how every caller
    /// applies them (the estimate's pass 3, the measured loads, the anatomical series), so all
    /// give the same bits. `ws.o_x_i` holds frame `k`'s world poses of the bodies on the feet's
    /// paths to the world (`forward_kinematics`).
    pub fn take_from(
        &self,
        model: &Model,
        k: usize,
        ws: &Workspace,
        mut tau: Option<&mut [f64]>,
        (moment_bodies, moments): (&[usize], &mut [Vector3<f64>]),
    ) {
        for (j, &b) in self.bodies.iter().enumerate() {
            let w = self.foot_wrench(k, j);
            passes::take_load(
                model,
                ws,
                &w,
                b,
                tau.as_deref_mut(),
                (moment_bodies, moments),
            );
        }
    }

    /// How far the feet can give the ground force the motion needs, over the frames of single
    /// support (one foot loaded), where the needed force and centre of pressure are the
    /// motion's alone (in double support they also depend on how the load is shared): the
    /// share of them whose [`cop_gap`](Self::cop_gap) exceeds [`COP_GAP_TOLERANCE`], the
    /// median gap and the largest.
    pub fn quality(&self) -> GroundQuality {
        let mut single: Vec<usize> = (0..self.loaded.len())
            .filter(|&k| self.loaded[k].iter().filter(|l| **l).count() == 1)
            .collect();
        let outside = single
            .iter()
            .filter(|&&k| self.cop_gap[k] > COP_GAP_TOLERANCE)
            .count();
        single.sort_by(|&a, &b| self.cop_gap[a].total_cmp(&self.cop_gap[b]));
        GroundQuality {
            single_support_frames: single.len(),
            outside_frames: outside,
            median_gap: single
                .get(single.len() / 2)
                .map_or(0.0, |&k| self.cop_gap[k]),
            largest_gap: single.last().map_or(0.0, |&k| self.cop_gap[k]),
            largest_gap_frame: single.last().copied().unwrap_or(0),
        }
    }
}

/// A centre of pressure gap ([`GroundReactions::cop_gap`]) up to this is agreement (m): 2 cm,
/// within the 5 cm the support is widened by ([`ContactParams::cop_margin`]).
pub const COP_GAP_TOLERANCE: f64 = 0.02;

/// [`GroundReactions::quality`]: how far the ground force the motion needs in single support
/// is one the foot can give.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundQuality {
    /// Frames where exactly one foot carries load.
    pub single_support_frames: usize,
    /// Of those, frames whose centre of pressure gap exceeds [`COP_GAP_TOLERANCE`].
    pub outside_frames: usize,
    /// The median gap over those frames (m).
    pub median_gap: f64,
    /// The largest gap (m) and its frame.
    pub largest_gap: f64,
    pub largest_gap_frame: usize,
}

impl GroundQuality {
    /// The share of single-support frames where the foot cannot give the needed ground force.
    pub fn outside_share(&self) -> f64 {
        self.outside_frames as f64 / self.single_support_frames.max(1) as f64
    }
}

impl std::fmt::Display for GroundQuality {
    /// One line for a user, e.g. `ground reactions: in 68 % of the 146 single-support frames
    /// the motion needs its centre of pressure more than 2 cm outside the foot (median 4.5 cm,
    /// up to 12.6 cm at frame 72); there the joint torques are those of the nearest force the
    /// foot can give, and the rest stays at the root (residual columns)`.
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        let tol = 100.0 * COP_GAP_TOLERANCE;
        if self.single_support_frames == 0 {
            return write!(f, "ground reactions: no frame of single support");
        }
        if self.outside_frames == 0 {
            return write!(
                f,
                "ground reactions: in all {} single-support frames the foot gives the force the \
                 motion needs (centre of pressure within {tol:.0} cm)",
                self.single_support_frames
            );
        }
        write!(
            f,
            "ground reactions: in {:.0} % of the {} single-support frames the motion needs its \
             centre of pressure more than {tol:.0} cm outside the foot (median {:.1} cm, up to \
             {:.1} cm at frame {}); there the joint torques are those of the nearest force the \
             foot can give, and the rest stays at the root (residual columns)",
            100.0 * self.outside_share(),
            self.single_support_frames,
            100.0 * self.median_gap,
            100.0 * self.largest_gap,
            self.largest_gap_frame
        )
    }
}

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
    estimate_ground_reactions_keeping(model, feet, time, qva, up, params, None, &[], keep_going)
}

/// [`estimate_ground_reactions_progress`] that also keeps the net moments of RNEA with the
/// ground reactions on `moment_bodies` (sorted, each once) at every frame
/// ([`GroundReactions::moments`]), from the pass that computes the torques: the joint moments
/// need no RNEA of their own; with the contact phases `held` when given ([`Held`]).
#[allow(clippy::too_many_arguments)]
pub fn estimate_ground_reactions_keeping(
    model: &Model,
    feet: &[Foot],
    time: &[f64],
    qva: [&[Vec<f64>]; 3],
    up: usize,
    params: &ContactParams,
    held: Held,
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
        (params, held),
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
    let contact = (params, held);
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
        (params, held),
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
    contact: (&ContactParams, Held),
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
    (params, held): (&ContactParams, Held),
    third: Third,
    rest: Option<PassThree>,
) -> Result<GroundReactions, Error> {
    let moment_bodies = match third {
        Third::Torques(b) => b,
        Third::Residual => &[],
    };
    let n = time.len();
    let dt = (time[n - 1] - time[0]) / (n - 1) as f64;

    // contact phases from the heel and toe paths, unless held
    let mut feet = feet.to_vec();
    let points = foot_paths(&poses, &mut feet, up);
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

/// The world paths of the heel and toe points of `feet` over the configurations `q` (their
/// heel points fitted to the take, [`fit_heel_points`]): what the contact phases are found
/// from, and what the contact heights are fitted to
/// ([`ContactParams::fitted_to`]).
pub fn foot_points(model: &Model, feet: &[Foot], q: &[Vec<f64>], up: usize) -> Vec<FootPoints> {
    let mut feet = feet.to_vec();
    let bodies = feet
        .iter()
        .flat_map(|f| [f.ankle_body, f.toe_body])
        .collect::<std::collections::BTreeSet<_>>()
        .into_iter()
        .collect();
    let poses = passes::Poses::of_motion(model, bodies, q);
    foot_paths(&poses, &mut feet, up)
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
mod tests {
    use super::*;

    #[test]
    fn centre_of_pressure_of_a_force_through_a_floor_point_is_that_point() {
        // a force F through p0 on the floor at height h, for each up axis
        for up in 0..3 {
            let h = 0.1;
            let mut p0 = Vector3::new(0.3, -0.7, 0.45);
            p0[up] = h;
            let mut f = Vector3::new(12.0, -30.0, 8.0);
            f[up] = 700.0;
            let free = 2.5;
            let w = ForceVec::new(p0.cross(&f) + Vector3::ith(up, free), f);
            let (p, m) = centre_of_pressure(&w, up, h).unwrap();
            assert!((p - p0).norm() < 1e-12, "up {up}: {p} vs {p0}");
            assert!((m - free).abs() < 1e-12);
        }
        let pull = ForceVec::new(Vector3::zeros(), Vector3::new(0.0, -10.0, 0.0));
        assert!(centre_of_pressure(&pull, 1, 0.0).is_none());
    }

    #[test]
    fn a_step_ramps_the_load_from_trailing_to_leading_foot() {
        // left alone, 4 frames of double support, right alone
        let c = |l, r| vec![l, r];
        let contact = vec![
            c(true, false),
            c(true, true),
            c(true, true),
            c(true, true),
            c(true, true),
            c(false, true),
        ];
        let time: Vec<f64> = (0..6).map(|k| k as f64 * 0.1).collect();
        let steps: Vec<Option<Step>> = transitions(&contact, &time)
            .into_iter()
            .map(|t| match t {
                Some(Transition::Step(s)) => Some(s),
                _ => None,
            })
            .collect();
        assert!(steps[0].is_none() && steps[5].is_none());
        let shares: Vec<f64> = steps[1..5]
            .iter()
            .map(|s| s.unwrap().trailing_share)
            .collect();
        assert!(steps[1].unwrap().trailing == 0 && steps[1].unwrap().leading == 1);
        assert!(shares.windows(2).all(|w| w[1] < w[0]), "{shares:?}");
        // symmetric about the middle of the double support
        assert!((shares[0] + shares[3] - 1.0).abs() < 1e-12);
        assert!(shares[0] > 0.8 && shares[3] < 0.2);
    }

    #[test]
    fn double_support_that_is_not_a_step_is_entered_and_left_without_a_jump() {
        // both feet from the start, then left alone, a step to the right, then both feet to
        // the end of the take (standing after a walk): 10 frames at 0.05 s
        let c = |l, r| vec![l, r];
        let mut contact = vec![c(true, true); 3];
        contact.extend([c(true, false), c(true, false)]);
        contact.extend([c(true, true), c(false, true)]);
        contact.extend(vec![c(true, true); 6]);
        let time: Vec<f64> = (0..contact.len()).map(|k| k as f64 * 0.05).collect();
        let t = transitions(&contact, &time);
        // the step (frame 5) is Ren's; its 0.1 s sets the open supports' ramps
        assert!(matches!(t[5], Some(Transition::Step(_))), "{:?}", t[5]);
        let open = |k: usize| match t[k] {
            Some(Transition::Open {
                from,
                to,
                entry,
                exit,
            }) => (from, to, entry, exit),
            other => panic!("frame {k}: {other:?}"),
        };
        // the take starts in double support: the lever rule, leaving towards the left foot alone
        let (from, to, entry, exit) = open(0);
        assert_eq!((from, to, entry), (None, Some(0), 0.0));
        assert_eq!(exit, 0.0, "frame 0 is more than the ramp away from frame 3");
        let exits: Vec<f64> = (0..3).map(|k| open(k).3).collect();
        assert!(exits.windows(2).all(|w| w[1] >= w[0]), "{exits:?}");
        assert!(exits[2] > 0.0 && exits[2] < 1.0, "{exits:?}");
        // the take ends in double support: entered from the right foot alone, lever afterwards
        let (from, to, entry, exit) = open(7);
        assert_eq!((from, to, exit), (Some(1), None, 0.0));
        assert!(entry > 0.5 && entry < 1.0, "frame 7: {entry}");
        assert_eq!(open(12).2, 0.0);
        let entries: Vec<f64> = (7..13).map(|k| open(k).2).collect();
        assert!(entries.windows(2).all(|w| w[1] <= w[0]), "{entries:?}");
    }

    #[test]
    fn a_blend_of_two_loads_is_their_wrenches_interpolated() {
        let up = 2;
        let support = [Support {
            heel: Vector3::new(0.0, 0.0, 0.0),
            toe: Vector3::new(0.2, 0.0, 0.0),
        }];
        let a = FootLoad {
            force: Vector3::new(50.0, 0.0, 600.0),
            cop: Vector3::new(0.02, 0.01, 0.0),
            free_moment: 1.0,
        };
        let b = FootLoad {
            force: Vector3::new(-30.0, 5.0, 200.0),
            cop: Vector3::new(0.18, -0.02, 0.0),
            free_moment: -2.0,
        };
        let mut loads = [a];
        blend(&mut loads, &[b], 0.25, &support, Floor { up, height: 0.0 });
        let e = Vector3::z();
        let want = a.wrench(&e) * 0.75 + b.wrench(&e) * 0.25;
        let got = loads[0].wrench(&e);
        assert!((got.lin - want.lin).norm() < 1e-9 && (got.ang - want.ang).norm() < 1e-9);
        // the centre of pressure lies between the two, weighted by vertical force
        let p = (a.cop * 0.75 * 600.0 + b.cop * 0.25 * 200.0) / (0.75 * 600.0 + 0.25 * 200.0);
        assert!(
            (loads[0].cop - p).norm() < 1e-12,
            "{:?} vs {p}",
            loads[0].cop
        );
    }

    #[test]
    fn in_a_step_each_foot_keeps_a_direction_of_its_own() {
        // z up, floor at 0; trailing foot (0) behind the leading foot (1)
        let up = 2;
        let support = [
            Support {
                heel: Vector3::new(0.0, 0.0, 0.0),
                toe: Vector3::new(0.2, 0.0, 0.0),
            },
            Support {
                heel: Vector3::new(0.6, 0.1, 0.0),
                toe: Vector3::new(0.8, 0.1, 0.0),
            },
        ];
        let params = ContactParams::default();
        let wrench = |l: &FootLoad| l.wrench(&Vector3::z());
        // alone, the trailing foot pushed off (forward and up) near its toe
        let last = FootLoad {
            force: Vector3::new(80.0, 5.0, 700.0),
            cop: Vector3::new(-0.02, 0.0, 0.0), // relative to its toe
            free_moment: 1.0,
        };
        let step = Step {
            trailing: 0,
            leading: 1,
            trailing_share: 0.6,
        };
        // the leading foot brakes (backward and up) near its heel
        let leading = FootLoad {
            force: Vector3::new(-100.0, -8.0, 500.0),
            cop: Vector3::new(0.62, 0.1, 0.0),
            free_moment: -0.5,
        };
        let trailing = FootLoad {
            force: last.force * 0.6,
            cop: Vector3::new(0.18, 0.0, 0.0),
            free_moment: 0.6,
        };
        let w = wrench(&trailing) + wrench(&leading);
        let mut loads = [FootLoad::default(); 2];
        let toe = support[0].toe;
        assign_step(&w, &support, step, &last, toe, up, 0.0, &params, &mut loads);
        for (got, want) in loads.iter().zip([trailing, leading]) {
            assert!(
                (got.force - want.force).norm() < 1e-9,
                "{got:?} vs {want:?}"
            );
            assert!((got.cop - want.cop).norm() < 1e-9, "{got:?} vs {want:?}");
            assert!((got.free_moment - want.free_moment).abs() < 1e-9);
        }
        // sharing w itself would have made the trailing foot brake too
        assert!(loads[0].force.x > 0.0 && loads[1].force.x < 0.0 && w.lin.x < 0.0);

        // the needed force lighter than the trailing foot's share: the trailing foot carries
        // all of it (the leading foot, pressing with nothing, can hold no horizontal force)
        let light = ForceVec::new(Vector3::zeros(), Vector3::new(0.0, 0.0, 300.0));
        assign_step(
            &light, &support, step, &last, toe, up, 0.0, &params, &mut loads,
        );
        assert!((loads[0].force - light.lin).norm() < 1e-9, "{:?}", loads[0]);
        assert!(loads[1].force.norm() < 1e-9, "{:?}", loads[1]);

        // the leading foot pressing lightly: what leaves its friction cone stays behind
        let slip = FootLoad {
            force: Vector3::new(-100.0, 0.0, 50.0),
            ..leading
        };
        let w = wrench(&trailing) + wrench(&slip);
        assign_step(&w, &support, step, &last, toe, up, 0.0, &params, &mut loads);
        assert!((loads[0].force + loads[1].force - w.lin).norm() < 1e-9);
        let h = loads[1].force.xy().norm();
        assert!((h - params.friction * 50.0).abs() < 1e-9, "{:?}", loads[1]);

        // the rest's centre of pressure 10 cm behind the leading heel (outside its support,
        // 5 cm margin): the leading foot keeps its own inside, the trailing foot's moves
        // back to make up the moment, and the two together still give w exactly
        let behind = FootLoad {
            cop: Vector3::new(0.5, 0.1, 0.0),
            ..leading
        };
        let w = wrench(&trailing) + wrench(&behind);
        assign_step(&w, &support, step, &last, toe, up, 0.0, &params, &mut loads);
        assert!(
            (loads[1].cop - Vector3::new(0.55, 0.1, 0.0)).norm() < 1e-9,
            "{loads:?}"
        );
        assert!(loads[0].cop.x < 0.18, "{:?}", loads[0]);
        let given = wrench(&loads[0]) + wrench(&loads[1]);
        assert!((given.lin - w.lin).norm() < 1e-9);
        assert!((given.ang - w.ang).norm() < 1e-9, "{given:?} vs {w:?}");
    }

    #[test]
    fn flight_frames_near_contact_carry_the_spread_force_of_the_nearer_foot() {
        // left stance 0..3, flight 3..9, right stance 9..12; spread 2 frames
        let contact: Vec<Vec<bool>> = (0..12).map(|k| vec![k < 3, k >= 9]).collect();
        let mut up = vec![500.0; 12];
        // the needed force pulls at frame 4 (free fall noise): the push-off's reach ends there
        up[4] = -10.0;
        let loaded = carry_across_spread(&contact, &up, 2);
        let want: Vec<Vec<bool>> = (0..12).map(|k| vec![k < 4, k >= 7]).collect();
        assert_eq!(loaded, want);
        // a short flight: each frame goes to the nearer contact (a tie to the earlier one)
        let contact: Vec<Vec<bool>> = (0..8).map(|k| vec![k < 3, k >= 6]).collect();
        let loaded = carry_across_spread(&contact, &[100.0; 8], 3);
        let want: Vec<Vec<bool>> = (0..8).map(|k| vec![k < 5, k >= 5]).collect();
        assert_eq!(loaded, want);
        // spread 0: only the contact
        assert_eq!(carry_across_spread(&contact, &[100.0; 8], 0), contact);
    }

    #[test]
    fn clamp_keeps_points_inside_and_moves_outside_points_to_the_edge() {
        let s = Support {
            heel: Vector3::new(0.0, 0.0, 0.0),
            toe: Vector3::new(0.0, 0.0, 0.2),
        };
        let inside = Vector3::new(0.03, 0.0, 0.1);
        assert_eq!(s.clamp(&inside, 0.05), inside);
        let ahead = s.clamp(&Vector3::new(0.0, 0.0, 0.5), 0.05);
        assert!((ahead - Vector3::new(0.0, 0.0, 0.25)).norm() < 1e-12);
        let side = s.clamp(&Vector3::new(0.4, 0.0, 0.1), 0.05);
        assert!((side - Vector3::new(0.05, 0.0, 0.1)).norm() < 1e-12);
    }
}
