//! The least-squares problem residual reduction solves ([`super`]): its parameters, one
//! evaluation of the adjusted model and motion, and the Gauss–Newton normal equations.
//!
//! Parameters `x`, in blocks: the trunk offset's two coordinates; the pelvis offset's spline
//! coefficients along each horizontal axis; the pelvis rotation's along each world axis (when
//! the root can be rotated, [`super::root::root_rotation`]); the mass scale (with measured
//! ground reactions only: estimated ones carry whatever the motion needs).

use super::relative::{Composite, RootRelative};
use super::root::{BodyRotation, RootRotation, RootTranslation, rotate_root, shift_root};
use super::{Ground, Motion, ReductionBounds, Trunk, peak_rms};
use crate::dynamics::grf::measured::apply_ground_reactions;
use crate::dynamics::grf::{
    GroundReactions, about, estimate_ground_reactions_progress, estimate_ground_residuals,
    estimate_ground_residuals_given, kept_bodies, root_wrench,
};
use crate::dynamics::residual::{centre_of_mass, with_trunk_offset};
use crate::dynamics::{
    Workspace, forward_kinematics, forward_kinematics_through, last_root_level_body, rnea,
};
use crate::error::Error;
use crate::model::Model;
use crate::motion::spline::UniformBSpline;
use crate::spatial::{ForceVec, SpatialInertia};
use nalgebra::{DMatrix, DVector, Matrix3, Vector3};

/// The trunk offset's coordinates.
pub(super) const NT: usize = 2;

/// The problem residual reduction solves, fixed over its iterations.
pub(super) struct Problem<'a> {
    pub model: &'a Model,
    pub ground: Ground<'a>,
    pub trunk: Trunk<'a>,
    pub motion: Motion<'a>,
    pub up: usize,
    pub counted: &'a [bool],
    pub spline: UniformBSpline,
    pub translation: RootTranslation,
    /// `None`: the root's rotations are not adjusted.
    pub rotation: Option<RootRotation>,
    pub root: usize,
    /// Weight of the residual force against the moment (m): the mean COM height.
    pub height: f64,
    /// Per frame: a pelvis offset already applied to `motion` (m, world; empty: none), which
    /// the bounds count with this problem's own ([`super::refine`]).
    pub base_pelvis: &'a [Vector3<f64>],
    /// Per parameter: whether it may change (`None`: all may); a held one stays where it is.
    pub free: Option<Vec<bool>>,
    /// The motion's root-relative terms, made at the first trial against estimated forces
    /// (`None` inside: a model they do not fit; trials then run the whole estimate); shared
    /// with the refinement's problem ([`super::refine`]).
    pub relative: std::sync::Arc<std::sync::OnceLock<Option<RootRelative>>>,
}

/// One evaluation: the adjusted model, motion and their ground reactions.
pub(super) struct Evaluated {
    pub model: Model,
    pub q: Vec<Vec<f64>>,
    pub v: Vec<Vec<f64>>,
    pub a: Vec<Vec<f64>>,
    pub ground: GroundReactions,
    pub cost: f64,
    /// Gauss–Newton steps taken to reach it.
    pub steps: usize,
}

/// The model and motion adjusted by some `x` ([`Problem::adjusted`]).
pub(super) struct Adjusted {
    pub model: Model,
    pub q: Vec<Vec<f64>>,
    pub v: Vec<Vec<f64>>,
    pub a: Vec<Vec<f64>>,
}

/// Where the parameter blocks start in `x`, and its length.
#[derive(Debug, Clone, Copy)]
pub(super) struct Layout {
    pub translation: usize,
    pub rotation: Option<usize>,
    pub mass: Option<usize>,
    pub len: usize,
}

/// `model` with every body's mass and inertia scaled by `s` (its mass centres kept).
fn with_mass_scale(model: &Model, s: f64) -> Model {
    let mut m = model.clone();
    for i in m.inertia.iter_mut() {
        *i = SpatialInertia::new(i.mass * s, i.com, i.inertia_com * s);
    }
    m
}

impl Problem<'_> {
    pub fn layout(&self) -> Layout {
        let nb = self.spline.len();
        let translation = NT;
        let mut len = NT + 2 * nb;
        let rotation = self.rotation.map(|_| {
            len += 3 * nb;
            len - 3 * nb
        });
        let mass = matches!(self.ground, Ground::Measured(_)).then(|| {
            len += 1;
            len - 1
        });
        Layout {
            translation,
            rotation,
            mass,
            len,
        }
    }

    /// The two horizontal axes.
    fn horizontal(&self) -> [usize; 2] {
        [(self.up + 1) % 3, (self.up + 2) % 3]
    }

    /// The trunk's mass-centre offset (m, its bodies' frame) for parameters `x`.
    pub fn trunk_offset(&self, x: &DVector<f64>) -> Vector3<f64> {
        self.trunk.across[0] * x[0] + self.trunk.across[1] * x[1]
    }

    /// The mass scale for parameters `x` (1 + the relative change).
    pub fn mass_scale(&self, x: &DVector<f64>) -> f64 {
        self.layout().mass.map_or(1.0, |i| 1.0 + x[i])
    }

    /// A spline curve on the axes `axes` from coefficients starting at `at`, and its first and
    /// second derivatives, at time `t`.
    fn curve(&self, x: &DVector<f64>, at: usize, axes: &[usize], t: f64) -> [Vector3<f64>; 3] {
        let nb = self.spline.len();
        let (i, b) = self.spline.basis(t);
        let mut out = [Vector3::zeros(); 3];
        for (h, &axis) in axes.iter().enumerate() {
            let c = &x.as_slice()[at + h * nb..at + (h + 1) * nb];
            for (order, o) in out.iter_mut().enumerate() {
                o[axis] = (0..4).map(|j| b[order][j] * c[i + j]).sum();
            }
        }
        out
    }

    /// The pelvis offset, its rate and acceleration at time `t` for parameters `x`.
    fn pelvis_at(&self, x: &DVector<f64>, t: f64) -> [Vector3<f64>; 3] {
        self.curve(x, self.layout().translation, &self.horizontal(), t)
    }

    /// The pelvis rotation vector `θ` (rad, world), its rate and acceleration at `t`.
    fn rotation_at(&self, x: &DVector<f64>, t: f64) -> Option<[Vector3<f64>; 3]> {
        let at = self.layout().rotation?;
        Some(self.curve(x, at, &[0, 1, 2], t))
    }

    /// Per frame: the pelvis offset (m, world), the base offset included.
    pub fn pelvis(&self, x: &DVector<f64>) -> Vec<Vector3<f64>> {
        self.motion
            .time
            .iter()
            .enumerate()
            .map(|(k, &t)| {
                self.pelvis_at(x, t)[0] + self.base_pelvis.get(k).copied().unwrap_or_default()
            })
            .collect()
    }

    /// Per frame: the pelvis rotation vector (rad, world); zeros when not adjusted.
    pub fn pelvis_rotation(&self, x: &DVector<f64>) -> Vec<Vector3<f64>> {
        self.motion
            .time
            .iter()
            .map(|&t| self.rotation_at(x, t).map_or(Vector3::zeros(), |r| r[0]))
            .collect()
    }

    /// The model and motion adjusted by `x`, their ground reactions and cost. Against
    /// estimated forces without the joint torques (`estimate_ground_residuals`: what a trial
    /// needs); [`Problem::with_torques`] completes the one kept.
    pub fn evaluate(&self, x: &DVector<f64>) -> Result<Evaluated, Error> {
        let Adjusted { model, q, v, a } = self.adjusted(x)?;
        let time = self.motion.time;
        let ground = match self.ground {
            Ground::Estimated { feet, params } => match self.relative(feet) {
                Some(relative) => {
                    let given = relative.needed(&model, self.mass_scale(x), [&q, &v, &a]);
                    estimate_ground_residuals_given(&model, feet, time, given, self.up, params)?
                }
                None => {
                    estimate_ground_residuals(&model, feet, time, [&q, &v, &a], self.up, params)?
                }
            },
            Ground::Measured(loads) => {
                apply_ground_reactions(&model, loads, time, &q, &v, &a, self.up)?
            }
        };
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

    /// The motion's root-relative terms ([`RootRelative`]), made once.
    fn relative(&self, feet: &[crate::motion::contact::Foot]) -> Option<&RootRelative> {
        self.relative
            .get_or_init(|| {
                let m = &self.motion;
                let kept = kept_bodies(self.model, feet)?;
                RootRelative::new(
                    self.model,
                    self.root,
                    kept,
                    self.trunk.bodies,
                    [m.q, m.v, m.a],
                )
            })
            .as_ref()
    }

    /// `e`'s ground reactions with the joint torques (and the residual that RNEA with the
    /// feet's loads leaves), when they were estimated without them.
    pub fn with_torques(&self, e: &mut Evaluated) -> Result<(), Error> {
        if let Ground::Estimated { feet, params } = self.ground {
            let (time, up) = (self.motion.time, self.up);
            e.ground = estimate_ground_reactions_progress(
                &e.model,
                feet,
                time,
                &e.q,
                &e.v,
                &e.a,
                up,
                params,
                &mut |_| true,
            )?;
        }
        Ok(())
    }

    /// The model and motion adjusted by `x` (no ground reactions).
    pub fn adjusted(&self, x: &DVector<f64>) -> Result<Adjusted, Error> {
        let trunk = with_trunk_offset(self.model, self.trunk.bodies, &self.trunk_offset(x));
        let s = self.mass_scale(x);
        let model = if s == 1.0 {
            trunk
        } else {
            with_mass_scale(&trunk, s)
        };
        let (mut q, mut v, mut a) = (
            self.motion.q.to_vec(),
            self.motion.v.to_vec(),
            self.motion.a.to_vec(),
        );
        let mut ws = Workspace::new(&model);
        for k in 0..q.len() {
            let t = self.motion.time[k];
            let [p, dp, ddp] = self.pelvis_at(x, t);
            forward_kinematics_through(&model, &mut ws, &q[k], self.root);
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
            if let (Some(r), Some([th, dth, ddth])) = (&self.rotation, self.rotation_at(x, t)) {
                let d = BodyRotation::exp(&th, &dth, &ddth);
                if !rotate_root(r, &rot, &d, &mut q[k], &mut v[k], &mut a[k]) {
                    return Err(Error::Invalid(format!(
                        "residual reduction: the root's Euler angles reach gimbal lock at \
                         {t:.3} s under the pelvis rotation; use --joints ball or \
                         --consistent off"
                    )));
                }
            }
        }
        Ok(Adjusted { model, q, v, a })
    }

    /// `Σ |n|² + h² |f|²` over the counted frames.
    pub fn cost(&self, g: &GroundReactions) -> f64 {
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

/// A residual this small is met, as a share of the body's weight `M g` (force) and of `M g h`
/// (moment about the pelvis, `h` the mean COM height): the feet give the wrench there. Relative,
/// so that the reduction of a body whose every mass is scaled alike takes the same steps and
/// ends at the same adjustments (a knee study across body weights compares like with like).
const MET: f64 = 1e-6;
/// The step of the trunk offset's finite differences (m); the needed wrench is linear in the
/// first moments `mᵢ cᵢ`, nearly so in `cᵢ` (the parallel-axis term is second order).
const TRUNK_STEP: f64 = 0.005;
/// The step of the rotation's finite differences (rad, rad/s, rad/s²): the needed wrench is
/// linear in the angular acceleration, smooth in the angle and rate.
const ROTATION_STEP: f64 = 1e-6;

/// What one frame's residual does with a change of the needed wrench (about the pelvis):
/// passed whole in flight and against measured forces; with estimated forces in stance, the
/// moment where a clamp holds, less the moment of the force change at the feet's centre of
/// pressure `cop`, and the force where one holds.
struct Pass {
    whole: bool,
    moment_clamped: bool,
    force_clamped: bool,
    lever: Vector3<f64>,
    height: f64,
}

impl Pass {
    fn new(
        g: &GroundReactions,
        k: usize,
        pelvis: &Vector3<f64>,
        height: f64,
        measured: bool,
        weight: f64,
    ) -> Self {
        let r = &g.residual[k];
        let load: f64 = g.grf[k].iter().map(|f| f[g.up]).sum();
        let whole = measured || load <= 1e-9;
        let cop = if whole {
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
            whole,
            moment_clamped: Vector3::new(r[3], r[4], r[5]).norm() > MET * weight * height,
            force_clamped: Vector3::new(r[0], r[1], r[2]).norm() > MET * weight,
            lever: cop - pelvis,
            height,
        }
    }

    fn apply(&self, dn: Vector3<f64>, df: Vector3<f64>) -> [f64; 6] {
        let (n, f) = if self.whole {
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

/// The most columns a frame's Jacobian has: the trunk's, four spline basis functions per
/// pelvis axis (two offsets, three rotations), the mass.
const FRAME_COLUMNS: usize = NT + 4 * (2 + 3) + 1;

/// One frame's Jacobian: its columns' indices in `x` and their entries (`[n; h f]`), the
/// first `len` of each; fixed arrays, so a take's frames are one allocation.
#[derive(Clone, Copy)]
struct Local {
    len: usize,
    cols: [usize; FRAME_COLUMNS],
    jac: [[f64; 6]; FRAME_COLUMNS],
}

impl Local {
    const EMPTY: Self = Self {
        len: 0,
        cols: [0; FRAME_COLUMNS],
        jac: [[0.0; 6]; FRAME_COLUMNS],
    };

    fn clear(&mut self) {
        self.len = 0;
    }

    fn push(&mut self, col: usize, entries: [f64; 6]) {
        self.cols[self.len] = col;
        self.jac[self.len] = entries;
        self.len += 1;
    }

    /// `JᵀJ += JₖᵀJₖ`, `Jᵀr += Jₖᵀrₖ`.
    fn accumulate(&self, rk: &[f64; 6], jtj: &mut DMatrix<f64>, jtr: &mut DVector<f64>) {
        let dot = |a: &[f64; 6], b: &[f64; 6]| (0..6).map(|r| a[r] * b[r]).sum::<f64>();
        let (cols, jac) = (&self.cols[..self.len], &self.jac[..self.len]);
        for (a, ja) in cols.iter().zip(jac) {
            jtr[*a] += dot(ja, rk);
            for (b, jb) in cols.iter().zip(jac) {
                jtj[(*a, *b)] += dot(ja, jb);
            }
        }
    }
}

/// What every frame's Jacobian shares, computed once per normal equations.
struct Shared {
    layout: Layout,
    /// The mass scale (1: not adjusted).
    mass_scale: f64,
    /// The adjusted model's total mass (kg) and weight (N).
    mass: f64,
    weight: f64,
    /// Whether the ground reactions are measured.
    measured: bool,
    /// The last root-level body: the poses through it are all the root's wrench reads
    /// after RNEA (`last_root_level_body`).
    root_level: usize,
}

/// Scratch for one frame's finite differences, allocated once per normal equations.
struct Scratch {
    ws: Workspace,
    q: Vec<f64>,
    v: Vec<f64>,
    a: Vec<f64>,
}

impl Problem<'_> {
    /// What every frame's Jacobian at `x` (evaluated as `e`) shares.
    fn shared(&self, x: &DVector<f64>, e: &Evaluated) -> Shared {
        let mass = e.model.total_mass();
        Shared {
            layout: self.layout(),
            mass_scale: self.mass_scale(x),
            mass,
            weight: mass * e.model.gravity.norm(),
            measured: matches!(self.ground, Ground::Measured(_)),
            root_level: last_root_level_body(&e.model),
        }
    }

    /// The Gauss–Newton normal equations `JᵀJ`, `Jᵀr` at `x` (evaluated as `e`): per counted
    /// frame, the residual `r = [n; h f]` and how each parameter changes it (module doc).
    pub fn normal_equations(
        &self,
        x: &DVector<f64>,
        e: &Evaluated,
    ) -> (DMatrix<f64>, DVector<f64>) {
        let shared = self.shared(x, e);
        let np = shared.layout.len;
        let (mut jtj, mut jtr) = (DMatrix::zeros(np, np), DVector::zeros(np));
        let offset = self.trunk_offset(x);
        let s = shared.mass_scale;
        let moved: Vec<Model> = self
            .trunk
            .across
            .iter()
            .map(|u| {
                let m =
                    with_trunk_offset(self.model, self.trunk.bodies, &(offset + u * TRUNK_STEP));
                if s == 1.0 { m } else { with_mass_scale(&m, s) }
            })
            .collect();
        // each counted frame's Jacobian, frames in parallel (each computes the same operations
        // whatever thread runs it), then summed in frame order: the same bits on any number
        // of threads (`crate::par`)
        let frames: Vec<usize> = (0..e.q.len()).filter(|&k| self.counted[k]).collect();
        let mut locals: Vec<(usize, Local)> = frames.iter().map(|&k| (k, Local::EMPTY)).collect();
        let mut scratch = crate::par::scratch(|| {
            (
                Workspace::new(&e.model),
                Scratch {
                    ws: Workspace::new(&e.model),
                    q: vec![0.0; e.model.nq],
                    v: vec![0.0; e.model.nv],
                    a: vec![0.0; e.model.nv],
                },
            )
        });
        crate::par::for_each_block(
            &mut locals,
            crate::par::even_block(frames.len()),
            &mut scratch,
            |(ws, scratch), _, block| {
                for (k, local) in block.iter_mut() {
                    self.frame_jacobian(&shared, e, *k, &moved, ws, scratch, local);
                }
            },
        );
        for (k, local) in &locals {
            let rk = self.weighted(&e.ground.residual[*k]);
            local.accumulate(&rk, &mut jtj, &mut jtr);
        }
        (jtj, jtr)
    }

    /// Frame `k`'s Jacobian into `local` (`moved`: the models with the trunk offset moved
    /// along each direction by [`TRUNK_STEP`]).
    #[allow(clippy::too_many_arguments)]
    fn frame_jacobian(
        &self,
        shared: &Shared,
        e: &Evaluated,
        k: usize,
        moved: &[Model],
        ws: &mut Workspace,
        scratch: &mut Scratch,
        local: &mut Local,
    ) {
        let layout = &shared.layout;
        local.clear();
        let relative = self.relative.get().and_then(Option::as_ref);
        let qva = [&e.q[k][..], &e.v[k], &e.a[k]];
        // the whole-body terms of the evaluated model at this frame, for its rotations
        let terms = relative.map(|r| (r, r.composite(k, &e.model, shared.mass_scale)));
        let com = match &terms {
            Some((r, c)) => {
                r.wrench(c, &e.model, qva, ws);
                ws.o_x_i[self.root].transform_point(&c.com())
            }
            None => {
                forward_kinematics(&e.model, ws, &e.q[k]);
                centre_of_mass(&e.model, ws)
            }
        };
        let pelvis = ws.o_x_i[self.root].trans;
        let pass = Pass::new(
            &e.ground,
            k,
            &pelvis,
            self.height,
            shared.measured,
            shared.weight,
        );
        let needed = e.ground.wrench[k];
        // trunk: finite differences of the needed wrench
        for (j, m) in moved.iter().enumerate() {
            let w = needed_wrench(relative, k, m, shared, qva, &mut scratch.ws);
            let w = about(&w, &pelvis);
            let d: [f64; 6] = std::array::from_fn(|c| (w[c] - needed[c]) / TRUNK_STEP);
            local.push(j, pass.apply(v3(&d, 3), v3(&d, 0)));
        }
        self.pelvis_columns(shared, &com, &pelvis, &e.ground, k, &pass, local);
        if let (Some(at), Some(r)) = (layout.rotation, &self.rotation) {
            let rot = ws.o_x_i[self.root].rot;
            let terms = terms.as_ref().map(|(r, c)| (*r, c));
            self.rotation_columns(
                e, k, at, r, &rot, &pelvis, &pass, shared, terms, scratch, local,
            );
        }
        if let Some(at) = layout.mass {
            // the needed wrench is linear in the inertial parameters
            let d: [f64; 6] = std::array::from_fn(|c| needed[c] / shared.mass_scale);
            local.push(at, pass.apply(v3(&d, 3), v3(&d, 0)));
        }
    }

    /// The pelvis spline's columns of frame `k`'s Jacobian: a rigid translation adds the force
    /// `M δp̈` at the centre of mass (`ws` at frame `k`); against measured forces, which stay
    /// where they act, the pelvis's move `δp` adds `δp × F` to the residual moment about it.
    #[allow(clippy::too_many_arguments)]
    fn pelvis_columns(
        &self,
        shared: &Shared,
        com: &Vector3<f64>,
        pelvis: &Vector3<f64>,
        g: &GroundReactions,
        k: usize,
        pass: &Pass,
        local: &mut Local,
    ) {
        let nb = self.spline.len();
        let (at, mass, measured) = (shared.layout.translation, shared.mass, shared.measured);
        let lever = com - pelvis;
        let applied: Vector3<f64> = g.grf[k].iter().sum();
        let (i0, b) = self.spline.basis(self.motion.time[k]);
        for (h, axis) in self.horizontal().into_iter().enumerate() {
            for (j, (value, acc)) in b[0].iter().zip(&b[2]).enumerate() {
                let df = Vector3::ith(axis, mass * acc);
                let mut dn = lever.cross(&df);
                if measured {
                    dn += Vector3::ith(axis, *value).cross(&applied);
                }
                local.push(at + h * nb + i0 + j, pass.apply(dn, df));
            }
        }
    }

    /// The pelvis rotation's columns of frame `k`'s Jacobian: the needed wrench's change with
    /// a rotation of the whole body about the pelvis, its rate and acceleration along each
    /// world axis (finite differences of inverse dynamics), chained with the spline's basis.
    #[allow(clippy::too_many_arguments)]
    fn rotation_columns(
        &self,
        e: &Evaluated,
        k: usize,
        at: usize,
        r: &RootRotation,
        rot: &Matrix3<f64>,
        pelvis: &Vector3<f64>,
        pass: &Pass,
        shared: &Shared,
        terms: Option<(&RootRelative, &Composite)>,
        scratch: &mut Scratch,
        local: &mut Local,
    ) {
        let nb = self.spline.len();
        let needed = e.ground.wrench[k];
        let (i0, b) = self.spline.basis(self.motion.time[k]);
        for axis in 0..3 {
            let mut d = [[0.0; 6]; 3];
            for (order, dk) in d.iter_mut().enumerate() {
                let e_axis = Vector3::ith(axis, ROTATION_STEP);
                let turn = match order {
                    0 => BodyRotation::exp(&e_axis, &Vector3::zeros(), &Vector3::zeros()),
                    1 => BodyRotation::exp(&Vector3::zeros(), &e_axis, &Vector3::zeros()),
                    _ => BodyRotation::exp(&Vector3::zeros(), &Vector3::zeros(), &e_axis),
                };
                scratch.q.copy_from_slice(&e.q[k]);
                scratch.v.copy_from_slice(&e.v[k]);
                scratch.a.copy_from_slice(&e.a[k]);
                if !rotate_root(
                    r,
                    rot,
                    &turn,
                    &mut scratch.q,
                    &mut scratch.v,
                    &mut scratch.a,
                ) {
                    continue;
                }
                let (sw, qva) = (&mut scratch.ws, [&scratch.q[..], &scratch.v, &scratch.a]);
                let w = match terms {
                    Some((r, c)) => r.wrench(c, &e.model, qva, sw),
                    None => {
                        forward_kinematics_through(&e.model, sw, qva[0], shared.root_level);
                        rnea(&e.model, sw, qva[0], qva[1], qva[2], None);
                        root_wrench(&e.model, sw)
                    }
                };
                let w = about(&w, pelvis);
                *dk = std::array::from_fn(|c| (w[c] - needed[c]) / ROTATION_STEP);
            }
            for j in 0..4usize {
                let col: [f64; 6] =
                    std::array::from_fn(|c| d.iter().zip(&b).map(|(dk, bk)| dk[c] * bk[j]).sum());
                let entries = pass.apply(v3(&col, 3), v3(&col, 0));
                local.push(at + axis * nb + i0 + j, entries);
            }
        }
    }

    /// The parameters in the order the normal equations are factored: the spline coefficients
    /// knot by knot (each knot's pelvis offset and rotation axes together), then the trunk
    /// and the mass. A frame's residual depends on the coefficients of four consecutive knots,
    /// so in this order `JᵀJ` is a band (about 20 wide) with the few dense parameters as its
    /// last rows, which a Cholesky factor fills no further ([`solve_by_knots`]).
    fn knot_order(&self) -> Vec<usize> {
        let l = self.layout();
        let nb = self.spline.len();
        let mut order = Vec::with_capacity(l.len);
        for i in 0..nb {
            order.extend((0..2).map(|h| l.translation + h * nb + i));
            if let Some(r) = l.rotation {
                order.extend((0..3).map(|axis| r + axis * nb + i));
            }
        }
        order.extend(0..NT);
        order.extend(l.mass);
        debug_assert_eq!(order.len(), l.len);
        order
    }

    /// Whether `x` keeps within the bounds, per block: trunk, pelvis offset, pelvis rotation,
    /// mass.
    pub fn within(&self, x: &DVector<f64>, bounds: &ReductionBounds) -> [bool; 4] {
        let trunk = self.trunk_offset(x).norm() <= bounds.trunk_com_m;
        let (peak, rms) = peak_rms(&self.pelvis(x));
        let (rpeak, rrms) = peak_rms(&self.pelvis_rotation(x));
        [
            trunk,
            peak <= bounds.pelvis_peak_m && rms <= bounds.pelvis_rms_m,
            rpeak <= bounds.rotation_peak_rad && rrms <= bounds.rotation_rms_rad,
            (self.mass_scale(x) - 1.0).abs() <= bounds.mass_share,
        ]
    }

    /// The block (0 trunk, 1 pelvis offset, 2 pelvis rotation, 3 mass) of parameter `i`.
    fn block(l: &Layout, i: usize) -> usize {
        if i < l.translation {
            0
        } else if l.mass == Some(i) {
            3
        } else if l.rotation.is_some_and(|r| i >= r) {
            2
        } else {
            1
        }
    }

    /// One regularized Gauss–Newton step from `x`, its Tikhonov weights raised until the step
    /// keeps within the bounds; `mu` (per block) keeps the weights reached.
    pub fn step(
        &self,
        x: &DVector<f64>,
        e: &Evaluated,
        bounds: &ReductionBounds,
        mu: &mut [f64; 4],
    ) -> Option<DVector<f64>> {
        let (jtj, jtr) = self.normal_equations(x, e);
        let np = x.len();
        let layout = self.layout();
        let order = self.knot_order();
        let blocks: Vec<usize> = (0..np).map(|i| Self::block(&layout, i)).collect();
        let mut s = [0.0; 4];
        let mut n = [0usize; 4];
        for i in 0..np {
            s[blocks[i]] += jtj[(i, i)];
            n[blocks[i]] += 1;
        }
        let s: [f64; 4] = std::array::from_fn(|b| (s[b] / n[b].max(1) as f64).max(1e-12));
        for _ in 0..20 {
            let mut a = jtj.clone();
            let mut rhs = -&jtr;
            for i in 0..np {
                let block = blocks[i];
                let l = mu[block] * s[block];
                a[(i, i)] += l;
                rhs[i] -= l * x[i];
            }
            // a held parameter's step is zero
            for (i, _) in self.free.iter().flatten().enumerate().filter(|(_, f)| !**f) {
                a.row_mut(i).fill(0.0);
                a.column_mut(i).fill(0.0);
                a[(i, i)] = 1.0;
                rhs[i] = 0.0;
            }
            let next = x + solve_by_knots(&a, &rhs, &order)?;
            let ok = self.within(&next, bounds);
            if ok.iter().all(|b| *b) {
                return Some(next);
            }
            for (b, within) in ok.iter().enumerate() {
                if !within {
                    mu[b] *= 4.0;
                }
            }
        }
        None
    }
}

/// Three entries of a wrench `[fx, fy, fz, tx, ty, tz]` from `at`.
/// The solution of `a x = b` (`a` symmetric positive definite, `None` otherwise) by a sparse
/// Cholesky factor (`nalgebra-sparse`, CSparse's up-looking algorithm) of `a` with its rows
/// and columns taken in `order` ([`Problem::knot_order`]): the band of the spline
/// coefficients and the dense last rows fill nothing outside them, so the factor costs
/// O(n·w²) instead of the dense O(n³) (n ≈ 700, w ≈ 20 on a 23 s take). The same solution
/// to rounding (a test compares it with the dense one).
fn solve_by_knots(a: &DMatrix<f64>, b: &DVector<f64>, order: &[usize]) -> Option<DVector<f64>> {
    use nalgebra_sparse::{CooMatrix, CscMatrix, factorization::CscCholesky};
    let n = order.len();
    let mut coo = CooMatrix::new(n, n);
    for (jj, &j) in order.iter().enumerate() {
        for (ii, &i) in order.iter().enumerate() {
            let v = a[(i, j)];
            if v != 0.0 {
                coo.push(ii, jj, v);
            }
        }
    }
    let factor = CscCholesky::factor(&CscMatrix::from(&coo)).ok()?;
    let y = factor.solve(&DMatrix::from_iterator(n, 1, order.iter().map(|&i| b[i])));
    let mut x = DVector::zeros(n);
    for (ii, &i) in order.iter().enumerate() {
        x[i] = y[(ii, 0)];
    }
    Some(x)
}

/// The wrench `model` needs at frame `k` over the state `qva` (world axes, about the world
/// origin): from the root-relative terms when there are some, else by kinematics through the
/// root-level bodies and RNEA.
fn needed_wrench(
    relative: Option<&RootRelative>,
    k: usize,
    model: &Model,
    shared: &Shared,
    [q, v, a]: [&[f64]; 3],
    ws: &mut Workspace,
) -> ForceVec {
    match relative {
        Some(r) => r.frame(k, model, shared.mass_scale, [q, v, a], ws).0,
        None => {
            forward_kinematics_through(model, ws, q, shared.root_level);
            rnea(model, ws, q, v, a, None);
            root_wrench(model, ws)
        }
    }
}

fn v3(w: &[f64; 6], at: usize) -> Vector3<f64> {
    Vector3::new(w[at], w[at + 1], w[at + 2])
}

#[cfg(test)]
mod tests {
    //! Against measured forces the residual is linear in the adjustments to first order and no
    //! clamp intervenes: the Jacobian's prediction of a small step must equal the change that
    //! evaluating the step gives (pelvis offset, rotation and mass).
    use super::super::root::{root_rotation, root_translation};
    use super::solve_by_knots;
    use super::*;
    use crate::dynamics::grf::measured::FootLoads;
    use crate::dynamics::samples::{SplitMix64, random_configuration, random_tree, random_vector};

    /// The sparse solve in a permuted order gives the dense Cholesky's solution, on a band with
    /// dense last rows (the normal equations' shape) and on a full matrix.
    #[test]
    fn the_solve_by_knots_is_the_dense_solve() {
        use nalgebra::{DMatrix, DVector};
        let n = 37;
        // a permutation: the band lies along `order`
        let order: Vec<usize> = (0..n).map(|k| (k * 10) % n).collect();
        let mut rng = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            (rng >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for band in [Some(5), None] {
            let mut m = DMatrix::zeros(n, n);
            for (ii, &i) in order.iter().enumerate() {
                for (jj, &j) in order.iter().enumerate() {
                    let near =
                        band.is_none_or(|w| ii.abs_diff(jj) <= w || ii >= n - 3 || jj >= n - 3);
                    if near {
                        m[(i, j)] = next();
                    }
                }
            }
            let a = m.transpose() * &m + DMatrix::identity(n, n);
            let a = (&a + a.transpose()) * 0.5;
            let b = DVector::from_fn(n, |_, _| next());
            let dense = a.clone().cholesky().unwrap().solve(&b);
            let sparse = solve_by_knots(&a, &b, &order).unwrap();
            let err = (&sparse - &dense).amax() / dense.amax();
            assert!(err < 1e-13, "{band:?}: {err:e}");
        }
        // not positive definite: no solution
        let a = -DMatrix::<f64>::identity(n, n);
        assert!(solve_by_knots(&a, &DVector::zeros(n), &order).is_none());
    }

    #[test]
    fn the_jacobian_predicts_a_small_step_against_measured_forces() {
        let model = random_tree(9, 21, true);
        let mut rng = SplitMix64(5);
        let n = 12;
        let time: Vec<f64> = (0..n).map(|k| 0.05 * k as f64).collect();
        let (mut q, mut v, mut a) = (vec![], vec![], vec![]);
        for _ in 0..n {
            let (mut qk, mut vk, mut ak) = (
                vec![0.0; model.nq],
                vec![0.0; model.nv],
                vec![0.0; model.nv],
            );
            random_configuration(&model, &mut rng, &mut qk);
            random_vector(&mut rng, 1.0, &mut vk);
            random_vector(&mut rng, 1.0, &mut ak);
            q.push(qk);
            v.push(vk);
            a.push(ak);
        }
        let loads = FootLoads {
            feet: vec!["left".into()],
            bodies: vec![3],
            force: (0..n).map(|_| vec![rng.vec3(200.0)]).collect(),
            cop: (0..n).map(|_| vec![rng.vec3(0.5)]).collect(),
            free_moment: (0..n).map(|_| vec![rng.range(-5.0, 5.0)]).collect(),
        };
        let counted = vec![true; n];
        let problem = Problem {
            model: &model,
            ground: Ground::Measured(&loads),
            trunk: Trunk {
                bodies: &[],
                across: [Vector3::zeros(); 2],
            },
            motion: Motion {
                time: &time,
                q: &q,
                v: &v,
                a: &a,
            },
            up: 2,
            counted: &counted,
            spline: UniformBSpline::new(0.0, time[n - 1], 0.15).unwrap(),
            translation: root_translation(&model).unwrap(),
            rotation: root_rotation(&model),
            root: 1,
            height: 1.0,
            base_pelvis: &[],
            free: None,
            relative: Default::default(),
        };
        let layout = problem.layout();
        assert!(layout.rotation.is_some() && layout.mass.is_some());
        let x0 = DVector::zeros(layout.len);
        let e0 = problem.evaluate(&x0).unwrap();
        let mut dx = DVector::zeros(layout.len);
        for i in NT..layout.len {
            dx[i] = rng.range(-1e-5, 1e-5);
        }
        let e1 = problem.evaluate(&dx).unwrap();
        let mut ws = Workspace::new(&e0.model);
        let mut scratch = Scratch {
            ws: Workspace::new(&e0.model),
            q: vec![0.0; model.nq],
            v: vec![0.0; model.nv],
            a: vec![0.0; model.nv],
        };
        let mut local = Local::EMPTY;
        let shared = problem.shared(&x0, &e0);
        for k in 0..n {
            problem.frame_jacobian(&shared, &e0, k, &[], &mut ws, &mut scratch, &mut local);
            let (r0, r1) = (
                problem.weighted(&e0.ground.residual[k]),
                problem.weighted(&e1.ground.residual[k]),
            );
            for row in 0..6 {
                let predicted: f64 = local.cols[..local.len]
                    .iter()
                    .zip(&local.jac[..local.len])
                    .map(|(c, j)| j[row] * dx[*c])
                    .sum();
                let actual = r1[row] - r0[row];
                assert!(
                    (predicted - actual).abs() <= 1e-3 * actual.abs().max(1e-4),
                    "frame {k} row {row}: predicted {predicted:e}, actual {actual:e}"
                );
            }
        }
    }
}
