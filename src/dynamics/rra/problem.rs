//! The least-squares problem residual reduction solves ([`super`]): its parameters, one
//! evaluation of the adjusted model and motion, and the Gauss–Newton normal equations.
//!
//! Parameters `x`, in blocks: the trunk offset's two coordinates; the pelvis offset's spline
//! coefficients along each horizontal axis; the pelvis rotation's along each world axis (when
//! the root can be rotated, [`super::root::root_rotation`]); the mass scale (with measured
//! ground reactions only: estimated ones carry whatever the motion needs).

use super::relative::RootRelative;
use super::root::{BodyRotation, RootRotation, RootTranslation, rotate_root, shift_root};
use super::{Ground, Motion, ReductionBounds, Trunk, peak_rms};
use crate::dynamics::grf::measured::apply_ground_reactions;
use crate::dynamics::grf::{
    GroundReactions, estimate_ground_reactions_keeping, estimate_ground_residuals,
    estimate_ground_residuals_given, kept_bodies,
};
use crate::dynamics::residual::with_trunk_offset;
use crate::dynamics::{Workspace, forward_kinematics_through};
use crate::error::Error;
use crate::model::Model;
use crate::motion::spline::UniformBSpline;
use crate::spatial::SpatialInertia;
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
    /// What the evaluations reuse ([`Reuse`]).
    pub reuse: Reuse,
}

/// What every evaluation of one problem reuses: the root's world rotation at every frame of
/// the motion (the trials' adjustments are made about it; made at the first evaluation), and
/// the states of rejected or superseded trials, whose rows the next trial overwrites
/// ([`Problem::recycle`]) instead of allocating its own.
#[derive(Default)]
pub(super) struct Reuse {
    root_rotations: std::sync::OnceLock<Vec<Matrix3<f64>>>,
    spare: std::sync::Mutex<Vec<[Vec<Vec<f64>>; 3]>>,
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
pub(super) fn with_mass_scale(model: &Model, s: f64) -> Model {
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
    pub(super) fn horizontal(&self) -> [usize; 2] {
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
            Ground::Estimated { feet, params, held } => match self.relative(feet) {
                Some(relative) => {
                    let given = relative.needed(&model, self.mass_scale(x), [&q, &v, &a]);
                    let up = self.up;
                    estimate_ground_residuals_given(&model, feet, time, given, up, params, held)?
                }
                None => {
                    let qva = [&q[..], &v[..], &a[..]];
                    estimate_ground_residuals(&model, feet, time, qva, self.up, params, held)?
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
        if let Ground::Estimated { feet, params, held } = self.ground {
            let (time, up) = (self.motion.time, self.up);
            e.ground = estimate_ground_reactions_keeping(
                &e.model,
                feet,
                time,
                [&e.q, &e.v, &e.a],
                up,
                (params, held, None),
                &[],
                &mut |_| true,
            )?;
        }
        Ok(())
    }

    /// The model and motion adjusted by `x` (no ground reactions); frames in parallel, each
    /// computing what it would alone (`crate::par`).
    pub fn adjusted(&self, x: &DVector<f64>) -> Result<Adjusted, Error> {
        let trunk = with_trunk_offset(self.model, self.trunk.bodies, &self.trunk_offset(x));
        let s = self.mass_scale(x);
        let model = if s == 1.0 {
            trunk
        } else {
            with_mass_scale(&trunk, s)
        };
        let rotations = self.root_rotations();
        let ([mut q, mut v, mut a], recycled) = self.states();
        // a recycled row differs from the motion's in the root's coordinates alone (all a
        // trial moves), which come first: those are copied back (else the whole row)
        let (nq, nv) = match (recycled, self.root_coordinates()) {
            (false, _) => (0, 0),
            (true, Some(n)) => n,
            (true, None) => (self.model.nq, self.model.nv),
        };
        // per frame: its rows, and whether the root could follow the rotation there
        let mut frames: Vec<_> = q
            .iter_mut()
            .zip(v.iter_mut())
            .zip(a.iter_mut())
            .map(|((q, v), a)| (q, v, a, true))
            .collect();
        let m = self.motion;
        crate::par::for_each_block(
            &mut frames,
            crate::par::even_block(m.q.len()),
            &mut crate::par::scratch(|| ()),
            |_, first, block| {
                for (i, (q, v, a, ok)) in block.iter_mut().enumerate() {
                    let k = first + i;
                    q[..nq].copy_from_slice(&m.q[k][..nq]);
                    v[..nv].copy_from_slice(&m.v[k][..nv]);
                    a[..nv].copy_from_slice(&m.a[k][..nv]);
                    let t = m.time[k];
                    let [p, dp, ddp] = self.pelvis_at(x, t);
                    let rot = &rotations[k];
                    shift_root(&self.translation, rot, &p, &dp, &ddp, q, v, a);
                    if let (Some(r), Some([th, dth, ddth])) =
                        (&self.rotation, self.rotation_at(x, t))
                    {
                        let d = BodyRotation::exp(&th, &dth, &ddth);
                        *ok = rotate_root(r, rot, &d, q, v, a);
                    }
                }
            },
        );
        if let Some(k) = frames.iter().position(|f| !f.3) {
            let t = m.time[k];
            return Err(Error::Invalid(format!(
                "residual reduction: the root's Euler angles reach gimbal lock at \
                 {t:.3} s under the pelvis rotation; use --joints ball or \
                 --consistent off"
            )));
        }
        drop(frames);
        Ok(Adjusted { model, q, v, a })
    }

    /// Per frame of the motion: the root body's world rotation (made once).
    fn root_rotations(&self) -> &[Matrix3<f64>] {
        self.reuse.root_rotations.get_or_init(|| {
            let mut ws = Workspace::new(self.model);
            self.motion
                .q
                .iter()
                .map(|q| {
                    forward_kinematics_through(self.model, &mut ws, q, self.root);
                    ws.o_x_i[self.root].rot
                })
                .collect()
        })
    }

    /// Rows for an evaluation's states: a recycled trial's (`true`), else a copy of the
    /// motion.
    fn states(&self) -> ([Vec<Vec<f64>>; 3], bool) {
        let spare = self.reuse.spare.lock().ok().and_then(|mut s| s.pop());
        match spare {
            Some(rows) => (rows, true),
            None => {
                let m = self.motion;
                ([m.q.to_vec(), m.v.to_vec(), m.a.to_vec()], false)
            }
        }
    }

    /// How many of q's and v's first coordinates are the root's joints' (bodies `1..=root`),
    /// when no other body's come before them.
    fn root_coordinates(&self) -> Option<(usize, usize)> {
        let m = self.model;
        let end = |b: usize| (m.idx_q[b] + m.joints[b].nq(), m.idx_v[b] + m.joints[b].nv());
        let (nq, nv) = (1..=self.root)
            .map(end)
            .fold((0, 0), |(q, v), (bq, bv)| (q.max(bq), v.max(bv)));
        let after = |b: usize| {
            (m.joints[b].nq() == 0 || m.idx_q[b] >= nq)
                && (m.joints[b].nv() == 0 || m.idx_v[b] >= nv)
        };
        (self.root + 1..m.nbodies()).all(after).then_some((nq, nv))
    }

    /// Keeps the states of an evaluation no longer needed for the next one's rows (they
    /// differ from the motion in the root's coordinates alone).
    pub fn recycle(&self, e: Evaluated) {
        if let Ok(mut s) = self.reuse.spare.lock() {
            s.push([e.q, e.v, e.a]);
        }
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
    pub(super) fn weighted(&self, r: &[f64; 6]) -> [f64; 6] {
        let h = self.height;
        [r[3], r[4], r[5], h * r[0], h * r[1], h * r[2]]
    }
}

impl Problem<'_> {
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
        // held: a held parameter's step is zero (its row and column of the system the unit's)
        let held = |i: usize| self.free.as_ref().is_some_and(|f| !f[i]);
        let mut system = KnotSystem::new(&jtj, &order, &held);
        for _ in 0..20 {
            let mut rhs = -&jtr;
            for i in 0..np {
                let block = blocks[i];
                let l = mu[block] * s[block];
                rhs[i] = if held(i) { 0.0 } else { rhs[i] - l * x[i] };
            }
            let diagonal = |i: usize| {
                if held(i) {
                    1.0
                } else {
                    jtj[(i, i)] + mu[blocks[i]] * s[blocks[i]]
                }
            };
            let next = x + system.solve(&jtj, &diagonal, &rhs)?;
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

/// The system `A x = b` of one Gauss–Newton step, solved by a sparse Cholesky factor
/// (`nalgebra-sparse`, CSparse's up-looking algorithm) of `A` with its rows and columns taken
/// in `order` ([`Problem::knot_order`]): the band of the spline coefficients and the dense
/// last rows fill nothing outside them, so the factor costs O(n·w²) instead of the dense
/// O(n³) (n ≈ 700, w ≈ 20 on a 23 s take); the same solution to rounding (a test compares it
/// with the dense one). `A` is `JᵀJ` with another diagonal (the Tikhonov weights) and the held
/// parameters' rows and columns the unit's: its pattern, and the symbolic factor, are made
/// once per step, and each trial of the weights only refactors the values.
struct KnotSystem<'a> {
    order: &'a [usize],
    /// `A`'s stored entries in knot order (CSC: the diagonal, and the non-zero entries of
    /// `JᵀJ` between free parameters).
    pattern: nalgebra_sparse::pattern::SparsityPattern,
    /// Per stored entry: its row and column in `x`'s order.
    at: Vec<(usize, usize)>,
    factor: Option<nalgebra_sparse::factorization::CscCholesky<f64>>,
}

impl<'a> KnotSystem<'a> {
    fn new(jtj: &DMatrix<f64>, order: &'a [usize], held: &dyn Fn(usize) -> bool) -> Self {
        let n = order.len();
        let (mut offsets, mut rows, mut at) = (Vec::with_capacity(n + 1), vec![], vec![]);
        offsets.push(0);
        for &j in order {
            for (ii, &i) in order.iter().enumerate() {
                if i == j || (!held(i) && !held(j) && jtj[(i, j)] != 0.0) {
                    rows.push(ii);
                    at.push((i, j));
                }
            }
            offsets.push(rows.len());
        }
        let pattern = nalgebra_sparse::pattern::SparsityPattern::try_from_offsets_and_indices(
            n, n, offsets, rows,
        )
        .expect("rows ascend within each column");
        Self {
            order,
            pattern,
            at,
            factor: None,
        }
    }

    /// The solution for `A`'s off-diagonal entries `jtj`'s, its diagonal `diagonal`, and the
    /// right-hand side `b`; `None` when `A` is not positive definite.
    fn solve(
        &mut self,
        jtj: &DMatrix<f64>,
        diagonal: &dyn Fn(usize) -> f64,
        b: &DVector<f64>,
    ) -> Option<DVector<f64>> {
        use nalgebra_sparse::factorization::{CscCholesky, CscSymbolicCholesky};
        let values: Vec<f64> = self
            .at
            .iter()
            .map(|&(i, j)| if i == j { diagonal(i) } else { jtj[(i, j)] })
            .collect();
        match &mut self.factor {
            Some(f) => f.refactor(&values).ok()?,
            None => {
                let symbolic = CscSymbolicCholesky::factor(self.pattern.clone());
                self.factor = Some(CscCholesky::factor_numerical(symbolic, &values).ok()?);
            }
        }
        let f = self.factor.as_ref()?;
        let n = self.order.len();
        let y = f.solve(&DMatrix::from_iterator(
            n,
            1,
            self.order.iter().map(|&i| b[i]),
        ));
        let mut x = DVector::zeros(n);
        for (ii, &i) in self.order.iter().enumerate() {
            x[i] = y[(ii, 0)];
        }
        Some(x)
    }
}

/// The solution of `a x = b` (`a` symmetric positive definite, `None` otherwise) by
/// [`KnotSystem`] in `order`, every parameter free.
#[cfg(test)]
fn solve_by_knots(a: &DMatrix<f64>, b: &DVector<f64>, order: &[usize]) -> Option<DVector<f64>> {
    KnotSystem::new(a, order, &|_| false).solve(a, &|i| a[(i, i)], b)
}

#[cfg(test)]
mod tests {
    use super::{KnotSystem, solve_by_knots};
    use nalgebra::{DMatrix, DVector};

    /// A band of half-width 4 along the permutation `order`, with three dense last rows, made
    /// symmetric positive definite: the normal equations' shape.
    fn banded(n: usize, order: &[usize], next: &mut dyn FnMut() -> f64) -> DMatrix<f64> {
        let mut m = DMatrix::zeros(n, n);
        for (ii, &i) in order.iter().enumerate() {
            for (jj, &j) in order.iter().enumerate() {
                if ii.abs_diff(jj) <= 4 || ii >= n - 3 || jj >= n - 3 {
                    m[(i, j)] = next();
                }
            }
        }
        let a = m.transpose() * &m;
        (&a + a.transpose()) * 0.5
    }

    fn xorshift(mut rng: u64) -> impl FnMut() -> f64 {
        move || {
            rng ^= rng << 13;
            rng ^= rng >> 7;
            rng ^= rng << 17;
            (rng >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        }
    }

    /// A step tries several Tikhonov weights on one system, factoring its pattern once and
    /// refactoring the values for each: every trial's solution must be the bits a system made
    /// afresh for it gives (what each trial computed before), held parameters included, whose
    /// step is zero and whose rows and columns leave the others' solution that of the system
    /// without them.
    #[test]
    fn refactoring_a_knot_system_gives_a_fresh_ones_bits() {
        let n = 41;
        let order: Vec<usize> = (0..n).map(|k| (k * 7) % n).collect();
        let mut next = xorshift(0x9e37_79b9_7f4a_7c15);
        let jtj = banded(n, &order, &mut next);
        let b = DVector::from_fn(n, |_, _| next());
        let held = |i: usize| i % 5 == 2;
        let mut kept = KnotSystem::new(&jtj, &order, &held);
        for mu in [1e-4, 4e-4, 1.6e-3, 1e-1] {
            let diagonal = |i: usize| if held(i) { 1.0 } else { jtj[(i, i)] + mu };
            let rhs = DVector::from_fn(n, |i, _| if held(i) { 0.0 } else { b[i] });
            let again = kept.solve(&jtj, &diagonal, &rhs).unwrap();
            let fresh = KnotSystem::new(&jtj, &order, &held)
                .solve(&jtj, &diagonal, &rhs)
                .unwrap();
            let bits = |x: &DVector<f64>| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&again), bits(&fresh), "mu {mu}");
            // the dense solve of the same system, held rows and columns the unit's
            let mut a = jtj.clone();
            for i in 0..n {
                for j in 0..n {
                    if i != j && (held(i) || held(j)) {
                        a[(i, j)] = 0.0;
                    }
                }
                a[(i, i)] = diagonal(i);
            }
            let dense = a.cholesky().unwrap().solve(&rhs);
            assert!((&again - &dense).amax() < 1e-12 * dense.amax(), "mu {mu}");
            assert!((0..n).filter(|&i| held(i)).all(|i| again[i] == 0.0));
        }
    }

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
}
