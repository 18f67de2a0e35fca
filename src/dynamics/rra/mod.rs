//! Residual reduction: the small changes of model and motion that make a take's ground
//! reactions explain its motion, as OpenSim's Residual Reduction Algorithm does (Delp et al.
//! 2007, "OpenSim: open-source software to create and analyze dynamic simulations of
//! movement", *IEEE TBME* 54, 1940–1950; the OpenSim user's guide, "How RRA works") and
//! AddBiomechanics (Werling et al. 2023, *PLoS ONE* 18, e0295152: mass centres and the root
//! trajectory fitted to the ground reactions).
//!
//! What the feet cannot give stays at the root ([`super::grf`]): mostly a moment, the needed
//! centre of pressure lying off the feet times the vertical force. The adjustments that move
//! it:
//!
//! 1. **the trunk's mass centre**: a constant offset `δc` (m, in each trunk body's frame)
//!    moves the whole-body centre of mass by `(m_trunk / M) δc` and the needed centre of
//!    pressure with it (RRA's torso COM adjustment);
//! 2. **the pelvis trajectory**: a smooth horizontal offset `δp(t)` of the root translation
//!    (a cubic B-spline with knots every [`ReductionBounds::knot_spacing_s`], the whole body
//!    moving with it, as in RRA), whose whole-body force `M δp̈` acting at the centre of mass
//!    moves the needed centre of pressure by about `−h δp̈ / g`;
//! 3. **the pelvis rotations**: a smooth rotation `R_δ(t) = exp([θ(t)])` of the whole body
//!    about the pelvis (tilt, list and rotation, as RRA's pelvis coordinates; same knots),
//!    whose moment `I θ̈` (and gravity's, as the body tilts) changes the needed wrench
//!    ([`root`]); the euler root follows it through its Euler angles at any pose, near
//!    gimbal lock too; a root of other joints is not rotated, and the report says so;
//! 4. **the total mass**, against measured ground reactions only ([`Ground::Measured`]): RRA
//!    finds it from the mean vertical residual force. Against estimated ones it is not
//!    adjusted: the feet carry the needed vertical force whatever the mass, and a mass change
//!    scales every force and moment alike, so no residual percentage changes.
//!
//! Method: Gauss–Newton on the residuals of the counted frames
//! ([`super::residual::counted_frames`]), `Σ |n|² + h² |f|²` (moment `n` about the pelvis,
//! force `f`, `h` the mean COM height), with the change of the needed wrench (exact for the
//! trunk and mass: RNEA is linear in the inertial parameters; a rigid translation adds `M δp̈`
//! at the centre of mass; finite differences of inverse dynamics for the rotation) passed to
//! the residual where a clamp holds (the feet's centre of pressure at the edge of the support,
//! a force at the friction cone, flight) or whole against measured forces; a Tikhonov term per
//! block keeps the adjustments within [`ReductionBounds`] (raised until they are), and each
//! step is kept only if the re-evaluated residuals fall (the clamps are not linear).

mod jacobian;
mod problem;
mod relative;
mod root;
mod seed;

use super::grf::measured::FootLoads;
use super::grf::{GroundReactions, floating_root};
use super::residual::{centre_of_mass, external_forces, residual_figures};
use super::{Workspace, forward_kinematics};
use crate::error::Error;
use crate::model::Model;
use crate::motion::contact::{ContactParams, Foot};
use crate::motion::spline::UniformBSpline;
use nalgebra::{DVector, Vector3};
use problem::{Adjusted, Evaluated, Problem};
use root::{root_rotation, root_translation};
pub use seed::Seed;
use seed::{Key, RefinedSeed, Start};

/// How far residual reduction may change the model and the motion (OpenSim's guidelines for
/// RRA, "Simulation with OpenSim — Best Practices": kinematics within 2 cm and 2° RMS, 5 cm
/// and 5° at the largest; the mass within 5 %).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReductionBounds {
    /// Largest trunk mass-centre offset (m).
    pub trunk_com_m: f64,
    /// Largest horizontal pelvis offset (m) at any frame.
    pub pelvis_peak_m: f64,
    /// Largest RMS of the pelvis offset over the take (m): Hicks et al. 2015 ask that the
    /// tracked kinematics stay within 2 cm.
    pub pelvis_rms_m: f64,
    /// Largest pelvis rotation (rad, the angle of `R_δ`) at any frame.
    pub rotation_peak_rad: f64,
    /// Largest RMS of the pelvis rotation over the take (rad).
    pub rotation_rms_rad: f64,
    /// Largest relative change of the total mass (measured ground reactions only).
    pub mass_share: f64,
    /// Knot spacing of the pelvis offset and rotation (s): each basis function spans four
    /// intervals (0.6 s at the default 0.15 s, about a step), the fastest change they make.
    /// Measured on the shared walks: 0.3 s removes a tenth of the residual moment, 0.15 s
    /// most of it.
    pub knot_spacing_s: f64,
    /// Gauss–Newton iterations at most.
    pub iterations: usize,
}

/// The most knots the pelvis offset gets per axis: the normal equations are dense, so their
/// size is bounded (Cholesky of 5·256 + 3 unknowns takes a fraction of a second); a take
/// longer than 256 × 0.15 s = 38 s gets a coarser offset ([`ReductionBounds::for_take`]).
pub const MAX_KNOTS: usize = 256;

impl ReductionBounds {
    /// The default bounds with the knot spacing widened to fit a take of `duration_s` sampled
    /// every `dt` s: at least three frames per interval (a keyframed take at 1 s per frame
    /// gets 3 s), and at most [`MAX_KNOTS`] knots (a long take gets slower corrections, which
    /// may leave more of its residual: the report says the spacing used). A banded solver
    /// would lift the cap.
    pub fn for_take(duration_s: f64, dt: f64) -> Self {
        let d = Self::default();
        Self {
            knot_spacing_s: d
                .knot_spacing_s
                .max(3.0 * dt)
                .max(duration_s / MAX_KNOTS as f64),
            ..d
        }
    }
}

impl Default for ReductionBounds {
    fn default() -> Self {
        Self {
            trunk_com_m: 0.05,
            pelvis_peak_m: 0.05,
            pelvis_rms_m: 0.02,
            rotation_peak_rad: 5f64.to_radians(),
            rotation_rms_rad: 2f64.to_radians(),
            mass_share: 0.05,
            knot_spacing_s: 0.15,
            iterations: 12,
        }
    }
}

/// A take's motion: sample times (s) and q, v, a per sample.
#[derive(Debug, Clone, Copy)]
pub struct Motion<'a> {
    pub time: &'a [f64],
    pub q: &'a [Vec<f64>],
    pub v: &'a [Vec<f64>],
    pub a: &'a [Vec<f64>],
}

/// The ground reactions the residuals are reduced against.
#[derive(Debug, Clone, Copy)]
pub enum Ground<'a> {
    /// Estimated from the motion with the feet `feet` ([`super::grf`]), again at each step,
    /// with the contact phases `held` through every step when given (those of the motion as
    /// loaded: [`super::grf::Held`]), else found again from each step's feet.
    Estimated {
        feet: &'a [Foot],
        params: &'a ContactParams,
        held: super::grf::Held<'a>,
    },
    /// Measured (force plates, `id --grf`): they stay as they are; the mass is adjusted too.
    Measured(&'a FootLoads),
}

/// What residual reduction found: the adjusted model and motion and their ground reactions.
#[derive(Debug, Clone)]
pub struct Reduction {
    /// The model with the trunk's mass centre moved (and the mass scaled).
    pub model: Model,
    /// The motion with the pelvis offset and rotation (nq, nv, nv per sample).
    pub q: Vec<Vec<f64>>,
    pub v: Vec<Vec<f64>>,
    pub a: Vec<Vec<f64>>,
    /// Ground reactions of the adjusted model and motion.
    pub ground: GroundReactions,
    /// The trunk's mass-centre offset (m, trunk bodies' frame).
    pub trunk_offset: Vector3<f64>,
    /// The trunk's mass (kg).
    pub trunk_mass_kg: f64,
    /// Per frame: the pelvis offset (m, world).
    pub pelvis: Vec<Vector3<f64>>,
    /// Per frame: the pelvis rotation vector (rad, world); `None`: not adjusted (a root that
    /// is neither a free joint nor three hinges about coordinate axes).
    pub rotation: Option<Vec<Vector3<f64>>>,
    /// The mass scale (1: not adjusted).
    pub mass_scale: f64,
    /// The bounds the adjustments end against, within a tenth (`trunk`, `pelvis offset`,
    /// `pelvis rotation`, `mass`).
    pub bounded: Vec<&'static str>,
    /// Gauss–Newton steps kept.
    pub steps: usize,
    /// The knot spacing (s) of the pelvis offset's refinement near the foot changes
    /// ([`refine`]); `None`: not refined (the take met the thresholds without it, or it did
    /// not lower the residuals).
    pub refined_knot_spacing_s: Option<f64>,
    /// What starts the next reduction of the same take ([`Seed`]); `None` against measured
    /// ground reactions.
    pub seed: Option<Seed>,
    /// How the reduction started.
    pub started: Started,
}

/// How a reduction started ([`reduce_residuals`]'s `warm`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Started {
    /// Gauss–Newton from zero (no seed, or one of another take or settings).
    Cold,
    /// Every mass and inertia the seed's times one factor: its adjustments, evaluated.
    Scaled,
    /// A preview ([`Warm::Preview`]): the seed's adjustments evaluated on masses that are not
    /// the seed's scaled, so not this model's reduction; only a workbench shows it, until the
    /// reduction proper replaces it.
    Preview,
}

/// Where [`reduce_residuals`] starts.
#[derive(Debug, Clone, Copy)]
pub enum Warm<'a> {
    /// From zero.
    Cold,
    /// From what an earlier reduction found ([`Seed`]): its adjustments evaluated when the
    /// problem is the seed's with every mass and inertia scaled alike (by the reduction's
    /// invariance they are this model's), else from zero. A result never depends on the seed.
    Seed(&'a Seed),
    /// A preview of the reduction of another body mass (the workbench's first redraw after a
    /// mass edit, before the reduction proper): the seed's adjustments evaluated on this
    /// model, nothing solved ([`Started::Preview`]; no seed is returned). An error when the
    /// problem is not the seed's but for the inertias, or when its inertias are the seed's
    /// scaled (then `Warm::Seed` is as quick, and exact).
    Preview(&'a Seed),
}

impl<'a> From<Option<&'a Seed>> for Warm<'a> {
    fn from(seed: Option<&'a Seed>) -> Self {
        seed.map_or(Warm::Cold, Warm::Seed)
    }
}

impl Reduction {
    /// Largest and RMS pelvis offset (m).
    pub fn pelvis_peak_rms(&self) -> (f64, f64) {
        peak_rms(&self.pelvis)
    }

    /// Largest and RMS pelvis rotation (rad); `None` when not adjusted.
    pub fn rotation_peak_rms(&self) -> Option<(f64, f64)> {
        self.rotation.as_deref().map(peak_rms)
    }
}

fn peak_rms(p: &[Vector3<f64>]) -> (f64, f64) {
    let peak = p.iter().map(|x| x.norm()).fold(0.0, f64::max);
    let ms = p.iter().map(|x| x.norm_squared()).sum::<f64>() / p.len().max(1) as f64;
    (peak, ms.sqrt())
}

/// The trunk whose mass centre residual reduction moves: its bodies, and the two directions
/// (in their frames) across its long axis along which it may move. RRA moves the torso's mass
/// centre forward–back and side to side only: along the trunk, the offset changes the needed
/// wrench through the trunk's rotational accelerations alone and is not to be found from it.
#[derive(Debug, Clone, Copy)]
pub struct Trunk<'a> {
    pub bodies: &'a [usize],
    pub across: [Vector3<f64>; 2],
}

impl Trunk<'_> {
    /// The two unit directions across `long` (a direction along the trunk in its bodies'
    /// frame, from the lumbar joint to the head); `None` if `long` is zero.
    pub fn across(long: &Vector3<f64>) -> Option<[Vector3<f64>; 2]> {
        let e = long.try_normalize(1e-12)?;
        let seed = Vector3::ith(e.iamin(), 1.0);
        let u = e.cross(&seed).normalize();
        Some([u, e.cross(&u)])
    }
}

/// Residual reduction (module doc) of the motion `motion` of `model` against the ground
/// reactions `ground`, with the trunk `trunk` (whose mass centre may move across it) and the
/// frames `counted` ([`super::residual::counted_frames`]), started as `warm` says ([`Warm`]).
///
/// Errors: those of the ground reactions' estimate or application; a model without a floating
/// root whose translation is three prismatic joints or a free joint; a motion of one instant.
#[allow(clippy::too_many_arguments)]
pub fn reduce_residuals(
    model: &Model,
    ground: Ground,
    trunk: Trunk,
    motion: Motion,
    up: usize,
    counted: &[bool],
    bounds: &ReductionBounds,
    warm: Warm,
) -> Result<Reduction, Error> {
    let translation = root_translation(model).ok_or_else(|| {
        Error::Invalid(format!(
            "model {}: residual reduction moves the root, and needs a floating root (a free \
             joint, or three prismatic joints then the rotations); use --consistent off",
            model.name
        ))
    })?;
    let n = motion.time.len();
    let spline = match (motion.time.first(), motion.time.last()) {
        (Some(&t0), Some(&t1)) if counted.len() == n => {
            UniformBSpline::new(t0, t1, bounds.knot_spacing_s)
        }
        _ => None,
    }
    .ok_or_else(|| {
        Error::Invalid(format!(
            "residual reduction needs a motion over time and a mask per frame (got {n} samples, \
             {} flags); use --consistent off",
            counted.len()
        ))
    })?;
    let mut problem = Problem {
        model,
        ground,
        trunk,
        motion,
        up,
        counted,
        spline,
        translation,
        rotation: None,
        root: floating_root(model).unwrap_or(1),
        height: 1.0,
        base_pelvis: &[],
        free: None,
        relative: Default::default(),
        reuse: Default::default(),
    };
    let key = Key::of(model, &ground, &trunk, &motion, up, counted, bounds);
    let start = match warm {
        Warm::Cold => Start::Cold,
        Warm::Seed(s) => Start::of(Some(s), key.as_ref(), model),
        Warm::Preview(s) => Start::preview(s, key.as_ref(), model).ok_or_else(|| {
            Error::Invalid(
                "residual reduction: no preview (the seed is of another problem, or of these \
                 masses scaled alike)"
                    .into(),
            )
        })?,
    };
    let preview = matches!(warm, Warm::Preview(_));
    let (found, started) = match start {
        Start::Cold => (cold(&mut problem, bounds)?, Started::Cold),
        Start::Scaled(s) if preview => (scaled(&mut problem, s)?, Started::Preview),
        Start::Scaled(s) => (scaled(&mut problem, s)?, Started::Scaled),
    };
    let Found {
        x,
        mut e,
        pelvis,
        refined,
        floor,
    } = found;
    problem.with_torques(&mut e)?;
    let rotation = problem.rotation.map(|_| problem.pelvis_rotation(&x));
    // the bounds the adjustments end against (within a tenth of them)
    let (peak, rms) = peak_rms(&pelvis);
    let (rpeak, rrms) = rotation.as_deref().map_or((0.0, 0.0), peak_rms);
    let mass_scale = problem.mass_scale(&x);
    let near = |value: f64, bound: f64| value > 0.9 * bound;
    let mut bounded = vec![];
    for (name, at) in [
        (
            "trunk",
            near(problem.trunk_offset(&x).norm(), bounds.trunk_com_m),
        ),
        (
            "pelvis offset",
            near(peak, bounds.pelvis_peak_m) || near(rms, bounds.pelvis_rms_m),
        ),
        (
            "pelvis rotation",
            near(rpeak, bounds.rotation_peak_rad) || near(rrms, bounds.rotation_rms_rad),
        ),
        ("mass", near((mass_scale - 1.0).abs(), bounds.mass_share)),
    ] {
        if at {
            bounded.push(name);
        }
    }
    let refined_knot_spacing_s = refined.as_ref().map(|r| r.spacing_s);
    let trunk_offset = problem.trunk_offset(&x);
    // a preview's adjustments are not this model's reduction: nothing to start from
    let seed = key.filter(|_| !preview).map(|key| Seed {
        key,
        inertia: model.inertia.clone(),
        x,
        height: problem.height,
        floor,
        refined,
        steps: e.steps,
    });
    Ok(Reduction {
        pelvis,
        rotation,
        mass_scale,
        trunk_offset,
        trunk_mass_kg: trunk.bodies.iter().map(|&b| model.inertia[b].mass).sum(),
        model: e.model,
        q: e.q,
        v: e.v,
        a: e.a,
        ground: e.ground,
        bounded,
        steps: e.steps,
        refined_knot_spacing_s,
        seed,
        started,
    })
}

/// What a reduction found, however it started: the smooth adjustments `x`, the final
/// evaluation (refined or not), the total pelvis offset per frame (m, world), the refinement
/// kept, and the floor under the unadjusted motion.
struct Found {
    x: DVector<f64>,
    e: Evaluated,
    pelvis: Vec<Vector3<f64>>,
    refined: Option<RefinedSeed>,
    floor: f64,
}

/// Gauss–Newton from zero: the translations first, then the rotations from there (each stage
/// keeps only steps that lower the residuals, so adding the rotations never ends above the
/// translations), then the refinement near the foot changes ([`refine`]).
fn cold(problem: &mut Problem, bounds: &ReductionBounds) -> Result<Found, Error> {
    problem.rotation = None;
    let x0 = DVector::zeros(problem.layout().len);
    let mut e = problem.evaluate(&x0)?;
    let floor = e.ground.floor;
    problem.height = mean_com_height(problem.model, &e.q, problem.counted, e.ground.up, floor);
    e.cost = problem.cost(&e.ground);
    let (mut x, mut e) = solve(problem, bounds, x0, e)?;
    if let Some(r) = root_rotation(problem.model) {
        let from = problem.layout();
        problem.rotation = Some(r);
        let to = problem.layout();
        let mut wider = DVector::zeros(to.len);
        wider
            .rows_mut(0, from.translation + 2 * problem.spline.len())
            .copy_from(&x.rows(0, from.translation + 2 * problem.spline.len()));
        if let (Some(a), Some(b)) = (from.mass, to.mass) {
            wider[b] = x[a];
        }
        (x, e) = solve(problem, bounds, wider, e)?;
    }
    finish(problem, bounds, x, e, floor)
}

/// The seed's adjustments on a model whose every mass and inertia is the seed's times one
/// factor: by the reduction's invariance they are this model's, so they are evaluated (the
/// refined ones when the seed was refined) and nothing is solved. A preview
/// ([`Warm::Preview`]) evaluates them the same way on other masses.
fn scaled(problem: &mut Problem, seed: &Seed) -> Result<Found, Error> {
    problem.rotation = root_rotation(problem.model);
    problem.height = seed.height;
    let x = seed.x.clone();
    let pelvis = problem.pelvis(&x);
    let (mut e, pelvis, refined) = match &seed.refined {
        None => (problem.evaluate(&x)?, pelvis, None),
        Some(r) => {
            let Adjusted { model, q, v, a } = problem.adjusted(&x)?;
            let Ground::Estimated { params, .. } = problem.ground else {
                unreachable!("a seed is of estimated ground reactions (Key::of)")
            };
            let fine = fine_spacing(problem, params)
                .and_then(|h| fine_problem_of(problem, &model, [&q, &v, &a], &pelvis, h))
                .filter(|f| f.spline.spacing == r.spacing_s && f.layout().len == r.x.len())
                .ok_or_else(|| {
                    Error::Invalid("residual reduction: the seed's refinement does not fit".into())
                })?;
            (fine.evaluate(&r.x)?, fine.pelvis(&r.x), Some(r.clone()))
        }
    };
    e.steps = seed.steps;
    Ok(Found {
        x,
        e,
        pelvis,
        refined,
        floor: seed.floor,
    })
}

/// The Tikhonov weights' start (per block, times the block's mean `JᵀJ` diagonal).
const MU0: f64 = 1e-4;

/// The smooth adjustments `x` (evaluated as `e`) refined near the foot changes when that
/// lowers the residuals.
fn finish(
    problem: &Problem,
    bounds: &ReductionBounds,
    x: DVector<f64>,
    e: Evaluated,
    floor: f64,
) -> Result<Found, Error> {
    let pelvis = problem.pelvis(&x);
    Ok(match refine(problem, bounds, &pelvis, &e)? {
        Some(r) => Found {
            x,
            e: r.evaluated,
            pelvis: r.pelvis,
            refined: Some(r.seed),
            floor,
        },
        None => Found {
            x,
            e,
            pelvis,
            refined: None,
            floor,
        },
    })
}

/// The refinement near the foot changes: when the smooth adjustments leave a take beyond
/// Hicks et al.'s thresholds against estimated ground reactions, a second pelvis offset on
/// knots every half the estimator's spread ([`ContactParams::spread_s`], at least three
/// frames), free only where its basis functions reach within the spread of a foot change
/// (a contact starting or ending): there the smoothed accelerations move the force of one
/// contact phase into the next, and the residual lies in runs of a few frames that the
/// 0.15 s knots cannot follow. The trunk's mass centre, the smooth offset and the rotation
/// are held; the bounds count both offsets together. Gauss–Newton from zero. `None` when the
/// take meets the thresholds already (its adjustments stay low-frequency), the ground
/// reactions are measured, no foot changes, or the refinement does not lower the residuals.
fn refine(
    coarse: &Problem,
    bounds: &ReductionBounds,
    pelvis: &[Vector3<f64>],
    e: &Evaluated,
) -> Result<Option<Refined>, Error> {
    let Ground::Estimated { params, .. } = coarse.ground else {
        return Ok(None);
    };
    let heights = com_heights(&e.model, &e.q, e.ground.up, e.ground.floor);
    let external = external_forces(&e.ground);
    if residual_figures(&e.ground.residual, &external, &heights, coarse.counted).meets() {
        return Ok(None);
    }
    let time = coarse.motion.time;
    let changes = foot_changes(time, &e.ground.contact);
    if changes.is_empty() {
        return Ok(None);
    }
    let Some(spacing) = fine_spacing(coarse, params) else {
        return Ok(None);
    };
    let Some(mut fine) = fine_problem_of(coarse, &e.model, [&e.q, &e.v, &e.a], pelvis, spacing)
    else {
        return Ok(None);
    };
    let layout = fine.layout();
    let (t0, nb, h) = (time[0], fine.spline.len(), fine.spline.spacing);
    // basis function i is non-zero over (t0 + (i − 3) h, t0 + (i + 1) h)
    let near = |i: usize| {
        let (a, b) = (
            t0 + (i as f64 - 3.0) * h - params.spread_s,
            t0 + (i as f64 + 1.0) * h + params.spread_s,
        );
        changes.iter().any(|&t| a < t && t < b)
    };
    let free: Vec<bool> = (0..layout.len)
        .map(|i| {
            i >= layout.translation
                && i < layout.translation + 2 * nb
                && near((i - layout.translation) % nb)
        })
        .collect();
    let x0 = DVector::zeros(layout.len);
    fine.free = Some(free);
    let start = fine.evaluate(&x0)?;
    let (x, mut refined) = solve(&fine, bounds, x0, start)?;
    if refined.steps == 0 || refined.cost >= e.cost {
        return Ok(None);
    }
    refined.steps += e.steps;
    Ok(Some(Refined {
        pelvis: fine.pelvis(&x),
        evaluated: refined,
        seed: RefinedSeed { x, spacing_s: h },
    }))
}

/// The refinement's knot spacing (s, before the spline fits it to whole intervals): half the
/// estimator's spread, at least three frames, at most [`MAX_KNOTS`] knots.
fn fine_spacing(coarse: &Problem, params: &ContactParams) -> Option<f64> {
    let time = coarse.motion.time;
    let (&t0, &t1, dt) = (time.first()?, time.last()?, time.get(1)? - time[0]);
    Some(
        (0.5 * params.spread_s)
            .max(3.0 * dt)
            .max((t1 - t0) / MAX_KNOTS as f64),
    )
}

/// The refinement's problem ([`refine`]) over the coarse adjustments' `model` and motion,
/// whose total pelvis offset is `pelvis`, its knots every `spacing` s at least (whole
/// intervals: the spline would shrink them to fit); every parameter free.
fn fine_problem_of<'a>(
    coarse: &Problem<'a>,
    model: &'a Model,
    [q, v, a]: [&'a [Vec<f64>]; 3],
    pelvis: &'a [Vector3<f64>],
    spacing: f64,
) -> Option<Problem<'a>> {
    let time = coarse.motion.time;
    let (&t0, &t1) = (time.first()?, time.last()?);
    let intervals = ((t1 - t0) / spacing).floor().max(1.0);
    let spline = UniformBSpline::new(t0, t1, (t1 - t0) / intervals * (1.0 + 1e-9))?;
    Some(Problem {
        model,
        ground: coarse.ground,
        trunk: Trunk {
            bodies: &[],
            across: [Vector3::zeros(); 2],
        },
        motion: Motion { time, q, v, a },
        up: coarse.up,
        counted: coarse.counted,
        spline,
        translation: coarse.translation,
        rotation: None,
        root: coarse.root,
        height: coarse.height,
        base_pelvis: pelvis,
        free: None,
        // the coarse problem's root-relative terms hold for the fine one (the same motion
        // relative to the root, the trunk's bodies apart): reused once made
        relative: if coarse.relative.get().is_some() {
            std::sync::Arc::clone(&coarse.relative)
        } else {
            Default::default()
        },
        reuse: Default::default(),
    })
}

/// What [`refine`] found: the total pelvis offset per frame (m, world), the refined
/// evaluation and what starts the next refinement.
struct Refined {
    pelvis: Vec<Vector3<f64>>,
    evaluated: Evaluated,
    seed: RefinedSeed,
}

/// The times (s) where a foot's contact starts or ends: midway between the two frames.
fn foot_changes(time: &[f64], contact: &[Vec<bool>]) -> Vec<f64> {
    let mut out = vec![];
    for k in 1..contact.len().min(time.len()) {
        if contact[k] != contact[k - 1] {
            out.push(0.5 * (time[k] + time[k - 1]));
        }
    }
    out
}

/// Gauss–Newton from `x` (evaluated as `e`), the Tikhonov weights from [`MU0`] (raised as
/// the bounds ask): each step kept only if the re-evaluated residuals fall (halved until they
/// do, eight times at most); stops when a step gains less than a thousandth.
fn solve(
    problem: &Problem,
    bounds: &ReductionBounds,
    mut x: DVector<f64>,
    mut e: Evaluated,
) -> Result<(DVector<f64>, Evaluated), Error> {
    let mut mu = [MU0; 4];
    for _ in 0..bounds.iterations {
        let Some(next) = problem.step(&x, &e, bounds, &mut mu) else {
            break;
        };
        let mut accepted = None;
        let mut dx = &next - &x;
        for _ in 0..8 {
            let trial = &x + &dx;
            let t = problem.evaluate(&trial)?;
            if t.cost < e.cost {
                accepted = Some((trial, t));
                break;
            }
            problem.recycle(t);
            dx *= 0.5;
        }
        let Some((xn, mut en)) = accepted else {
            break;
        };
        let gain = (e.cost - en.cost) / e.cost.max(1e-12);
        en.steps = e.steps + 1;
        let superseded = std::mem::replace(&mut e, en);
        problem.recycle(superseded);
        x = xn;
        if gain < 1e-3 {
            break;
        }
    }
    Ok((x, e))
}

/// Mean height of the whole-body centre of mass over the floor, over the counted frames (m).
fn mean_com_height(model: &Model, q: &[Vec<f64>], counted: &[bool], up: usize, floor: f64) -> f64 {
    com_heights(model, q, up, floor)
        .iter()
        .zip(counted)
        .filter(|(_, c)| **c)
        .map(|(h, _)| *h)
        .sum::<f64>()
        / counted.iter().filter(|c| **c).count().max(1) as f64
}

/// Per sample: the height of the whole-body centre of mass over the floor (m); samples in
/// parallel, each computing what it would alone (`crate::par`).
pub fn com_heights(model: &Model, q: &[Vec<f64>], up: usize, floor: f64) -> Vec<f64> {
    let mut out = vec![0.0; q.len()];
    crate::par::for_each_block(
        &mut out,
        crate::par::even_block(q.len()),
        &mut crate::par::scratch(|| Workspace::new(model)),
        |ws, first, block| {
            for (i, h) in block.iter_mut().enumerate() {
                forward_kinematics(model, ws, &q[first + i]);
                *h = centre_of_mass(model, ws)[up] - floor;
            }
        },
    );
    out
}
