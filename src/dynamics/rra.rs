//! Residual reduction: the small changes of model and motion that make a take's ground
//! reactions explain its motion, as OpenSim's Residual Reduction Algorithm does (Delp et al.
//! 2007, "OpenSim: open-source software to create and analyze dynamic simulations of
//! movement", *IEEE TBME* 54, 1940–1950; the OpenSim user's guide, "How RRA works") and
//! AddBiomechanics (Werling et al. 2023, *PLoS ONE* 18, e0295152: mass centres and the root
//! trajectory fitted to the ground reactions).
//!
//! What the feet cannot give stays at the root ([`super::grf`]): mostly a moment, the needed
//! centre of pressure lying off the feet times the vertical force. Two adjustments move it:
//!
//! 1. **the trunk's mass centre**: a constant offset `δc` (m, in each trunk body's frame)
//!    moves the whole-body centre of mass by `(m_trunk / M) δc` and the needed centre of
//!    pressure with it (RRA's torso COM adjustment);
//! 2. **the pelvis trajectory**: a smooth horizontal offset `δp(t)` of the root translation
//!    (a cubic B-spline with knots every [`ReductionBounds::knot_spacing_s`], the whole body
//!    moving with it, as in RRA), whose whole-body force `M δp̈` acting at the centre of mass
//!    moves the needed centre of pressure by about `−h δp̈ / g`.
//!
//! The total mass is not adjusted: RRA finds it from the mean vertical residual force against
//! measured force plates, but here the ground reactions are estimated from the same motion,
//! so the feet carry the needed vertical force whatever the mass, and a mass change scales
//! every force and moment alike: no residual percentage changes.
//!
//! Method: Gauss–Newton on the residuals of the counted frames
//! ([`super::residual::counted_frames`]), `Σ |n|² + h² |f|²` (moment `n` about the pelvis,
//! force `f`, `h` the mean COM height), with the exact change of the needed wrench (RNEA is
//! linear in the inertial parameters; a rigid translation adds `M δp̈` at the centre of mass)
//! passed to the residual where a clamp holds (the feet's centre of pressure at the edge of the
//! support, a force at the friction cone, flight); a Tikhonov term keeps the adjustments
//! within [`ReductionBounds`] (raised until they are), and each step is kept only if the
//! re-estimated residuals fall (the clamps are not linear).

use super::grf::{GroundReactions, about, estimate_ground_reactions_progress, floating_root};
use super::residual::{centre_of_mass, with_trunk_offset};
use super::{Workspace, forward_kinematics, rnea};
use crate::error::Error;
use crate::model::{JointKind, Model};
use crate::motion::contact::{ContactParams, Foot};
use crate::motion::spline::UniformBSpline;
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

/// How far residual reduction may change the model and the motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReductionBounds {
    /// Largest trunk mass-centre offset (m).
    pub trunk_com_m: f64,
    /// Largest horizontal pelvis offset (m) at any frame (OpenSim's guidelines for RRA: a
    /// tracked translation within 2–5 cm at its largest, 2 cm RMS).
    pub pelvis_peak_m: f64,
    /// Largest RMS of the pelvis offset over the take (m): Hicks et al. 2015 ask that the
    /// tracked kinematics stay within 2 cm.
    pub pelvis_rms_m: f64,
    /// Knot spacing of the pelvis offset (s): each basis function spans four intervals (0.6 s
    /// at the default 0.15 s, about a step), the fastest change the offset makes. Measured on
    /// the shared walks: 0.3 s removes a tenth of the residual moment, 0.15 s most of it.
    pub knot_spacing_s: f64,
    /// Gauss–Newton iterations at most.
    pub iterations: usize,
}

/// The most knots the pelvis offset gets per axis: the normal equations are dense, so their
/// size is bounded (Cholesky of 2·256 + 3 unknowns takes milliseconds); a take longer than
/// 256 × 0.15 s = 38 s gets a coarser offset ([`ReductionBounds::for_take`]).
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

/// What residual reduction found: the adjusted model and motion and their ground reactions.
#[derive(Debug, Clone)]
pub struct Reduction {
    /// The model with the trunk's mass centre moved.
    pub model: Model,
    /// The motion with the pelvis offset (nq, nv, nv per sample).
    pub q: Vec<Vec<f64>>,
    pub v: Vec<Vec<f64>>,
    pub a: Vec<Vec<f64>>,
    /// Ground reactions of the adjusted model and motion.
    pub ground: GroundReactions,
    /// The trunk's mass-centre offset (m, trunk bodies' frame).
    pub trunk_offset: Vector3<f64>,
    /// The trunk's mass (kg) and its share of the body's.
    pub trunk_mass_kg: f64,
    /// Per frame: the pelvis offset (m, world).
    pub pelvis: Vec<Vector3<f64>>,
    /// The bounds the adjustments end against, within a tenth (`trunk`, `pelvis`).
    pub bounded: Vec<&'static str>,
    /// Gauss–Newton steps kept.
    pub steps: usize,
}

impl Reduction {
    /// Largest and RMS pelvis offset (m).
    pub fn pelvis_peak_rms(&self) -> (f64, f64) {
        peak_rms(&self.pelvis)
    }
}

fn peak_rms(p: &[Vector3<f64>]) -> (f64, f64) {
    let peak = p.iter().map(|x| x.norm()).fold(0.0, f64::max);
    let ms = p.iter().map(|x| x.norm_squared()).sum::<f64>() / p.len().max(1) as f64;
    (peak, ms.sqrt())
}

/// How the root's translation enters q, v, a: a free joint, or three prismatic joints from the
/// world before any rotation (their world axes).
#[derive(Debug, Clone, Copy)]
enum RootTranslation {
    Free {
        placement: Matrix3<f64>,
    },
    Prismatic {
        iq: [usize; 3],
        iv: [usize; 3],
        inverse: Matrix3<f64>,
    },
}

fn root_translation(model: &Model) -> Option<RootTranslation> {
    let root = floating_root(model)?;
    if model.joints[1] == JointKind::Free {
        return Some(RootTranslation::Free {
            placement: model.placement[1].rot,
        });
    }
    let mut ws = Workspace::new(model);
    forward_kinematics(model, &mut ws, &model.neutral());
    let (mut iq, mut iv, mut axes) = (vec![], vec![], vec![]);
    for i in 1..=root {
        match model.joints[i] {
            JointKind::Prismatic { axis } => {
                iq.push(model.idx_q[i]);
                iv.push(model.idx_v[i]);
                axes.push(ws.o_x_i[i].rot * axis);
            }
            JointKind::Fixed => {}
            _ => break,
        }
    }
    let [a0, a1, a2] = axes[..] else {
        return None;
    };
    let inverse = Matrix3::from_columns(&[a0, a1, a2]).try_inverse()?;
    Some(RootTranslation::Prismatic {
        iq: iq.try_into().ok()?,
        iv: iv.try_into().ok()?,
        inverse,
    })
}

/// Moves the root of one sample by the world offset `p` with rate `dp` and acceleration
/// `ddp`, the whole body with it. For a free joint (v linear in the body frame,
/// `R` its world rotation): `δv = Rᵀ δṗ`, `δa = Rᵀ δp̈ − ω × Rᵀ δṗ`.
#[allow(clippy::too_many_arguments)]
fn shift_root(
    t: &RootTranslation,
    rot: &Matrix3<f64>,
    p: &Vector3<f64>,
    dp: &Vector3<f64>,
    ddp: &Vector3<f64>,
    q: &mut [f64],
    v: &mut [f64],
    a: &mut [f64],
) {
    match t {
        RootTranslation::Free { placement } => {
            let dq = placement.transpose() * p;
            let dv = rot.transpose() * dp;
            let w = Vector3::new(v[3], v[4], v[5]);
            let da = rot.transpose() * ddp - w.cross(&dv);
            for k in 0..3 {
                q[k] += dq[k];
                v[k] += dv[k];
                a[k] += da[k];
            }
        }
        RootTranslation::Prismatic { iq, iv, inverse } => {
            let (dq, dv, da) = (inverse * p, inverse * dp, inverse * ddp);
            for k in 0..3 {
                q[iq[k]] += dq[k];
                v[iv[k]] += dv[k];
                a[iv[k]] += da[k];
            }
        }
    }
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

/// Parameters: the trunk offset's two coordinates, then the pelvis spline's coefficients
/// along the first horizontal axis, then along the second.
const NT: usize = 2;

/// The problem residual reduction solves, fixed over its iterations.
struct Problem<'a> {
    model: &'a Model,
    feet: &'a [Foot],
    trunk: Trunk<'a>,
    motion: Motion<'a>,
    up: usize,
    params: &'a ContactParams,
    counted: &'a [bool],
    spline: UniformBSpline,
    translation: RootTranslation,
    root: usize,
    /// Weight of the residual force against the moment (m): the mean COM height.
    height: f64,
}

/// One evaluation: the adjusted model, motion and their ground reactions.
struct Evaluated {
    model: Model,
    q: Vec<Vec<f64>>,
    v: Vec<Vec<f64>>,
    a: Vec<Vec<f64>>,
    ground: GroundReactions,
    cost: f64,
    /// Gauss–Newton steps taken to reach it.
    steps: usize,
}

impl Problem<'_> {
    /// The two horizontal axes.
    fn horizontal(&self) -> [usize; 2] {
        [(self.up + 1) % 3, (self.up + 2) % 3]
    }

    /// The trunk's mass-centre offset (m, its bodies' frame) for parameters `x`.
    fn trunk_offset(&self, x: &DVector<f64>) -> Vector3<f64> {
        self.trunk.across[0] * x[0] + self.trunk.across[1] * x[1]
    }

    /// The pelvis offset, its rate and acceleration at time `t` for parameters `x`.
    fn pelvis_at(&self, x: &DVector<f64>, t: f64) -> [Vector3<f64>; 3] {
        let nb = self.spline.len();
        let (i, b) = self.spline.basis(t);
        let mut out = [Vector3::zeros(); 3];
        for (h, axis) in self.horizontal().into_iter().enumerate() {
            let c = &x.as_slice()[NT + h * nb..NT + (h + 1) * nb];
            for (order, o) in out.iter_mut().enumerate() {
                o[axis] = (0..4).map(|j| b[order][j] * c[i + j]).sum();
            }
        }
        out
    }

    fn pelvis(&self, x: &DVector<f64>) -> Vec<Vector3<f64>> {
        self.motion
            .time
            .iter()
            .map(|&t| self.pelvis_at(x, t)[0])
            .collect()
    }

    /// The model and motion adjusted by `x`, their ground reactions and cost.
    fn evaluate(&self, x: &DVector<f64>) -> Result<Evaluated, Error> {
        let model = with_trunk_offset(self.model, self.trunk.bodies, &self.trunk_offset(x));
        let (mut q, mut v, mut a) = (
            self.motion.q.to_vec(),
            self.motion.v.to_vec(),
            self.motion.a.to_vec(),
        );
        let mut ws = Workspace::new(&model);
        for k in 0..q.len() {
            let [p, dp, ddp] = self.pelvis_at(x, self.motion.time[k]);
            forward_kinematics(&model, &mut ws, &q[k]);
            let rot = ws.o_x_i[self.root].rot;
            shift_root(
                &self.translation,
                &rot,
                &p,
                &dp,
                &ddp,
                &mut q[k],
                &mut v[k],
                &mut a[k],
            );
        }
        let ground = estimate_ground_reactions_progress(
            &model,
            self.feet,
            self.motion.time,
            &q,
            &v,
            &a,
            self.up,
            self.params,
            &mut |_| true,
        )?;
        let cost = self.cost(&ground);
        Ok(Evaluated {
            model,
            q,
            v,
            a,
            ground,
            cost,
            steps: 0,
        })
    }

    /// `Σ |n|² + h² |f|²` over the counted frames.
    fn cost(&self, g: &GroundReactions) -> f64 {
        (0..g.residual.len())
            .filter(|&k| self.counted[k])
            .map(|k| {
                self.weighted(&g.residual[k])
                    .iter()
                    .map(|r| r * r)
                    .sum::<f64>()
            })
            .sum()
    }

    /// A residual `[fx, fy, fz, tx, ty, tz]` as the least-squares residual `[n; h f]`.
    fn weighted(&self, r: &[f64; 6]) -> [f64; 6] {
        let h = self.height;
        [r[3], r[4], r[5], h * r[0], h * r[1], h * r[2]]
    }
}

/// A residual this small is met (N·m; N): the feet give the wrench there.
const MET: f64 = 1e-3;
/// The step of the trunk offset's finite differences (m); the needed wrench is linear in the
/// first moments `mᵢ cᵢ`, nearly so in `cᵢ` (the parallel-axis term is second order).
const TRUNK_STEP: f64 = 0.005;
/// Columns of one frame's Jacobian: the trunk's, and four spline coefficients per axis.
const LOCAL: usize = NT + 8;

/// What one frame's residual does with a change of the needed wrench (about the pelvis):
/// passed whole in flight; in stance, the moment where a clamp holds, less the moment of the
/// force change at the feet's centre of pressure `cop`, and the force where one holds.
struct Pass {
    flight: bool,
    moment_clamped: bool,
    force_clamped: bool,
    lever: Vector3<f64>,
    height: f64,
}

impl Pass {
    fn new(g: &GroundReactions, k: usize, pelvis: &Vector3<f64>, height: f64) -> Self {
        let r = &g.residual[k];
        let load: f64 = g.grf[k].iter().map(|f| f[g.up]).sum();
        let flight = load <= 1e-9;
        let cop = if flight {
            *pelvis
        } else {
            g.grf[k]
                .iter()
                .zip(&g.cop[k])
                .map(|(f, c)| c * f[g.up])
                .sum::<Vector3<f64>>()
                / load
        };
        Self {
            flight,
            moment_clamped: Vector3::new(r[3], r[4], r[5]).norm() > MET,
            force_clamped: Vector3::new(r[0], r[1], r[2]).norm() > MET,
            lever: cop - pelvis,
            height,
        }
    }

    fn apply(&self, dn: Vector3<f64>, df: Vector3<f64>) -> [f64; 6] {
        let (n, f) = if self.flight {
            (dn, df)
        } else {
            let zero = Vector3::zeros();
            let n = if self.moment_clamped {
                dn - self.lever.cross(&df)
            } else {
                zero
            };
            (n, if self.force_clamped { df } else { zero })
        };
        let h = self.height;
        [n.x, n.y, n.z, h * f.x, h * f.y, h * f.z]
    }
}

impl Problem<'_> {
    /// The Gauss–Newton normal equations `JᵀJ`, `Jᵀr` at `x` (evaluated as `e`): per counted
    /// frame, the residual `r = [n; h f]` and how each parameter changes it (module doc).
    fn normal_equations(&self, x: &DVector<f64>, e: &Evaluated) -> (DMatrix<f64>, DVector<f64>) {
        let np = x.len();
        let (mut jtj, mut jtr) = (DMatrix::zeros(np, np), DVector::zeros(np));
        let offset = self.trunk_offset(x);
        let moved: Vec<Model> = self
            .trunk
            .across
            .iter()
            .map(|u| with_trunk_offset(self.model, self.trunk.bodies, &(offset + u * TRUNK_STEP)))
            .collect();
        let mut ws = Workspace::new(&e.model);
        let mut ws_moved = Workspace::new(&e.model);
        let mut cols = [0usize; LOCAL];
        let mut jac = [[0.0; LOCAL]; 6];
        for k in (0..e.q.len()).filter(|&k| self.counted[k]) {
            forward_kinematics(&e.model, &mut ws, &e.q[k]);
            let pelvis = ws.o_x_i[self.root].trans;
            let pass = Pass::new(&e.ground, k, &pelvis, self.height);
            // trunk: finite differences of the needed wrench
            for (j, m) in moved.iter().enumerate() {
                forward_kinematics(m, &mut ws_moved, &e.q[k]);
                rnea(m, &mut ws_moved, &e.q[k], &e.v[k], &e.a[k], None);
                let w = about(&super::grf::root_wrench(m, &ws_moved), &pelvis);
                let d: [f64; 6] =
                    std::array::from_fn(|c| (w[c] - e.ground.wrench[k][c]) / TRUNK_STEP);
                let col = pass.apply(
                    Vector3::new(d[3], d[4], d[5]),
                    Vector3::new(d[0], d[1], d[2]),
                );
                cols[j] = j;
                (0..6).for_each(|row| jac[row][j] = col[row]);
            }
            self.pelvis_columns(&e.model, &ws, k, &pass, &mut cols, &mut jac);
            let rk = self.weighted(&e.ground.residual[k]);
            accumulate(&cols, &jac, &rk, &mut jtj, &mut jtr);
        }
        (jtj, jtr)
    }

    /// The pelvis spline's columns of frame `k`'s Jacobian (from `LOCAL − 8`): a rigid
    /// translation adds the force `M δp̈` at the centre of mass (`ws` at frame `k`).
    fn pelvis_columns(
        &self,
        model: &Model,
        ws: &Workspace,
        k: usize,
        pass: &Pass,
        cols: &mut [usize; LOCAL],
        jac: &mut [[f64; LOCAL]; 6],
    ) {
        let nb = self.spline.len();
        let mass = model.total_mass();
        let lever = centre_of_mass(model, ws) - ws.o_x_i[self.root].trans;
        let (i0, b) = self.spline.basis(self.motion.time[k]);
        for (h, axis) in self.horizontal().into_iter().enumerate() {
            for (j, ddb) in b[2].iter().enumerate() {
                let df = Vector3::ith(axis, mass * ddb);
                let col = pass.apply(lever.cross(&df), df);
                let c = NT + 4 * h + j;
                cols[c] = NT + h * nb + i0 + j;
                (0..6).for_each(|row| jac[row][c] = col[row]);
            }
        }
    }

    /// Whether `x` keeps within the bounds: (trunk, pelvis).
    fn within(&self, x: &DVector<f64>, bounds: &ReductionBounds) -> (bool, bool) {
        let trunk = self.trunk_offset(x).norm() <= bounds.trunk_com_m;
        let (peak, rms) = peak_rms(&self.pelvis(x));
        (
            trunk,
            peak <= bounds.pelvis_peak_m && rms <= bounds.pelvis_rms_m,
        )
    }

    /// One regularized Gauss–Newton step from `x`, its Tikhonov weights raised until the step
    /// keeps within the bounds; `mu` (trunk, pelvis) keeps the weights reached.
    fn step(
        &self,
        x: &DVector<f64>,
        e: &Evaluated,
        bounds: &ReductionBounds,
        mu: &mut [f64; 2],
    ) -> Option<DVector<f64>> {
        let (jtj, jtr) = self.normal_equations(x, e);
        let np = x.len();
        let scale = |r: std::ops::Range<usize>| {
            let s: f64 = r.clone().map(|i| jtj[(i, i)]).sum::<f64>() / r.len() as f64;
            s.max(1e-12)
        };
        let s = [scale(0..NT), scale(NT..np)];
        for _ in 0..20 {
            let mut a = jtj.clone();
            let mut b = -&jtr;
            for i in 0..np {
                let block = usize::from(i >= NT);
                let l = mu[block] * s[block];
                a[(i, i)] += l;
                b[i] -= l * x[i];
            }
            let next = x + a.cholesky()?.solve(&b);
            let (trunk, pelvis) = self.within(&next, bounds);
            if trunk && pelvis {
                return Some(next);
            }
            for (ok, m) in [(trunk, 0), (pelvis, 1)] {
                if !ok {
                    mu[m] *= 4.0;
                }
            }
        }
        None
    }
}

/// `JᵀJ += JₖᵀJₖ`, `Jᵀr += Jₖᵀrₖ` for one frame's local Jacobian `jac` over columns `cols`.
fn accumulate(
    cols: &[usize; LOCAL],
    jac: &[[f64; LOCAL]; 6],
    rk: &[f64; 6],
    jtj: &mut DMatrix<f64>,
    jtr: &mut DVector<f64>,
) {
    for a in 0..LOCAL {
        jtr[cols[a]] += (0..6).map(|row| jac[row][a] * rk[row]).sum::<f64>();
        for b in 0..LOCAL {
            jtj[(cols[a], cols[b])] += (0..6).map(|row| jac[row][a] * jac[row][b]).sum::<f64>();
        }
    }
}

/// Residual reduction (module doc) of the motion `motion` of `model` with the feet `feet`, the
/// trunk `trunk` (whose mass centre may move across it) and the frames `counted`
/// ([`super::residual::counted_frames`]).
///
/// Errors: those of [`estimate_ground_reactions_progress`]; a model without a floating root
/// whose translation is three prismatic joints or a free joint; a motion of one instant.
#[allow(clippy::too_many_arguments)]
pub fn reduce_residuals(
    model: &Model,
    feet: &[Foot],
    trunk: Trunk,
    motion: Motion,
    up: usize,
    params: &ContactParams,
    counted: &[bool],
    bounds: &ReductionBounds,
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
        feet,
        trunk,
        motion,
        up,
        params,
        counted,
        spline,
        translation,
        root: floating_root(model).unwrap_or(1),
        height: 1.0,
    };
    let (x, e) = problem.solve(bounds)?;
    // the bounds the adjustments end against (within a tenth of them)
    let pelvis = problem.pelvis(&x);
    let (peak, rms) = peak_rms(&pelvis);
    let mut bounded = vec![];
    if problem.trunk_offset(&x).norm() > 0.9 * bounds.trunk_com_m {
        bounded.push("trunk");
    }
    if peak > 0.9 * bounds.pelvis_peak_m || rms > 0.9 * bounds.pelvis_rms_m {
        bounded.push("pelvis");
    }
    Ok(Reduction {
        pelvis,
        trunk_offset: problem.trunk_offset(&x),
        trunk_mass_kg: trunk.bodies.iter().map(|&b| model.inertia[b].mass).sum(),
        model: e.model,
        q: e.q,
        v: e.v,
        a: e.a,
        ground: e.ground,
        bounded,
        steps: e.steps,
    })
}

impl Problem<'_> {
    /// Gauss–Newton from no adjustment: each step kept only if the re-estimated residuals
    /// fall (halved until they do, eight times at most); stops when a step gains less than
    /// a thousandth.
    fn solve(&mut self, bounds: &ReductionBounds) -> Result<(DVector<f64>, Evaluated), Error> {
        let mut x = DVector::zeros(NT + 2 * self.spline.len());
        let mut e = self.evaluate(&x)?;
        self.height = mean_com_height(self.model, &e, self.counted);
        e.cost = self.cost(&e.ground);
        let mut mu = [1e-4, 1e-4];
        for _ in 0..bounds.iterations {
            let Some(next) = self.step(&x, &e, bounds, &mut mu) else {
                break;
            };
            let mut accepted = None;
            let mut dx = &next - &x;
            for _ in 0..8 {
                let trial = &x + &dx;
                let t = self.evaluate(&trial)?;
                if t.cost < e.cost {
                    accepted = Some((trial, t));
                    break;
                }
                dx *= 0.5;
            }
            let Some((xn, mut en)) = accepted else {
                break;
            };
            let gain = (e.cost - en.cost) / e.cost.max(1e-12);
            en.steps = e.steps + 1;
            (x, e) = (xn, en);
            if gain < 1e-3 {
                break;
            }
        }
        Ok((x, e))
    }
}

/// Mean height of the whole-body centre of mass over the floor, over the counted frames (m).
fn mean_com_height(model: &Model, e: &Evaluated, counted: &[bool]) -> f64 {
    com_heights(model, &e.q, e.ground.up, e.ground.floor)
        .iter()
        .zip(counted)
        .filter(|(_, c)| **c)
        .map(|(h, _)| *h)
        .sum::<f64>()
        / counted.iter().filter(|c| **c).count().max(1) as f64
}

/// Per sample: the height of the whole-body centre of mass over the floor (m).
pub fn com_heights(model: &Model, q: &[Vec<f64>], up: usize, floor: f64) -> Vec<f64> {
    let mut ws = Workspace::new(model);
    q.iter()
        .map(|qk| {
            forward_kinematics(model, &mut ws, qk);
            centre_of_mass(model, &ws)[up] - floor
        })
        .collect()
}

#[cfg(test)]
mod tests {
    //! A rigid translation of the whole body by `δp(t)` (the pelvis offset) adds exactly the
    //! force `M δp̈` at the centre of mass to the wrench the motion needs: the linearization
    //! residual reduction's Jacobian uses, for a free root and for a root of three prismatic
    //! joints.
    use super::*;
    use crate::dynamics::samples::{
        SplitMix64, euler_avatar, random_configuration, random_tree, random_vector,
    };

    fn needed_about_pelvis(model: &Model, q: &[f64], v: &[f64], a: &[f64]) -> [f64; 6] {
        let mut ws = Workspace::new(model);
        forward_kinematics(model, &mut ws, q);
        rnea(model, &mut ws, q, v, a, None);
        let root = floating_root(model).unwrap();
        about(
            &super::super::grf::root_wrench(model, &ws),
            &ws.o_x_i[root].trans,
        )
    }

    #[test]
    fn a_rigid_translation_adds_m_times_its_acceleration_at_the_centre_of_mass() {
        let mut rng = SplitMix64(7);
        for model in [random_tree(9, 3, true), euler_avatar()] {
            let t = root_translation(&model).expect("a floating root");
            let root = floating_root(&model).unwrap();
            let (mut q, mut v, mut a) = (
                vec![0.0; model.nq],
                vec![0.0; model.nv],
                vec![0.0; model.nv],
            );
            random_configuration(&model, &mut rng, &mut q);
            random_vector(&mut rng, 1.0, &mut v);
            random_vector(&mut rng, 1.0, &mut a);
            let w0 = needed_about_pelvis(&model, &q, &v, &a);
            let mut ws = Workspace::new(&model);
            forward_kinematics(&model, &mut ws, &q);
            let (pelvis, rot) = (ws.o_x_i[root].trans, ws.o_x_i[root].rot);
            let com = centre_of_mass(&model, &ws);
            let (p, dp, ddp) = (rng.vec3(0.05), rng.vec3(0.3), rng.vec3(2.0));
            shift_root(&t, &rot, &p, &dp, &ddp, &mut q, &mut v, &mut a);
            forward_kinematics(&model, &mut ws, &q);
            assert!((ws.o_x_i[root].trans - pelvis - p).norm() < 1e-12);
            assert!((ws.o_x_i[root].rot - rot).norm() < 1e-12);
            let w1 = needed_about_pelvis(&model, &q, &v, &a);
            let df = ddp * model.total_mass();
            let dn = (com - pelvis).cross(&df);
            for c in 0..3 {
                assert!(
                    (w1[c] - w0[c] - df[c]).abs() < 1e-9,
                    "{}: force",
                    model.name
                );
                assert!(
                    (w1[3 + c] - w0[3 + c] - dn[c]).abs() < 1e-9,
                    "{}: moment",
                    model.name
                );
            }
        }
    }
}
