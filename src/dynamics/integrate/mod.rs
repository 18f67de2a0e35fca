//! Time integration of `(q, v)` under any acceleration function: explicit Euler, semi-implicit
//! (symplectic) Euler, classic Runge-Kutta 4 (the paper's) and the adaptive Dormand-Prince
//! 5(4). The explicit methods are one Runge-Kutta loop over a Butcher tableau kept as data
//! (MuJoCo's `mj_RungeKutta`).
//!
//! Positions live on the configuration manifold: every stage moves `q` as
//! [`Model::integrate`] does (the exponential map, so quaternions stay unit; on the 1-DoF
//! joints, found once per stepper, a plain sum over runs of coordinates), from the step's start
//! along a tangent offset `Ω`; stage velocities are mapped into that tangent space by the
//! inverse of the exponential's differential, `Ω̇ = dexp⁻¹_{−Ω}(v)` — the Runge-Kutta
//! Munthe-Kaas method (Munthe-Kaas 1998, "Runge-Kutta methods on Lie groups", BIT 38), which
//! keeps each method's classical order on rotations.

use crate::error::Error;
use crate::model::{JointKind, Model};
use nalgebra::Vector3;
use std::str::FromStr;

/// A time integrator.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Integrator {
    /// Explicit (forward) Euler, order 1: `q ← q ⊕ h v`, `v ← v + h a(q, v)`.
    Euler,
    /// Semi-implicit (symplectic) Euler, order 1: `v ← v + h a(q, v)`, then `q ← q ⊕ h v`.
    SemiImplicitEuler,
    /// Classic Runge-Kutta, order 4 (the paper's integrator).
    #[default]
    Rk4,
    /// Dormand-Prince 5(4) with step-size control (Hairer, Nørsett, Wanner 1993, §II.4-5):
    /// each call to [`Stepper::step`] takes as many sub-steps as the tolerances need.
    Dopri5 {
        /// Relative tolerance per coordinate.
        rtol: f64,
        /// Absolute tolerance per coordinate (rad, m, rad/s, m/s).
        atol: f64,
    },
}

impl FromStr for Integrator {
    type Err = Error;
    /// `euler`, `semi-implicit`, `rk4`, `dopri5` (tolerance 1e-6), `dopri5:TOL` or
    /// `dopri5:RTOL,ATOL`.
    fn from_str(s: &str) -> Result<Self, Error> {
        let s = s.trim();
        let bad = || {
            Error::Invalid(format!(
                "integrator `{s}`: expected `euler`, `semi-implicit`, `rk4`, `dopri5`, \
                 `dopri5:TOL` or `dopri5:RTOL,ATOL` (tolerances > 0, e.g. dopri5:1e-8)"
            ))
        };
        let (name, tol) = match s.split_once(':') {
            Some((n, t)) => (n, Some(t)),
            None => (s, None),
        };
        match (name, tol) {
            ("euler", None) => Ok(Integrator::Euler),
            ("semi-implicit" | "semi-implicit-euler" | "symplectic-euler", None) => {
                Ok(Integrator::SemiImplicitEuler)
            }
            ("rk4", None) => Ok(Integrator::Rk4),
            ("dopri5", None) => Ok(Integrator::Dopri5 {
                rtol: 1e-6,
                atol: 1e-6,
            }),
            ("dopri5", Some(t)) => {
                let parse = |x: &str| x.trim().parse::<f64>().ok().filter(|v| *v > 0.0);
                let (rtol, atol) = match t.split_once(',') {
                    Some((r, a)) => (parse(r), parse(a)),
                    None => (parse(t), parse(t)),
                };
                match (rtol, atol) {
                    (Some(rtol), Some(atol)) => Ok(Integrator::Dopri5 { rtol, atol }),
                    _ => Err(bad()),
                }
            }
            _ => Err(bad()),
        }
    }
}

impl std::fmt::Display for Integrator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Integrator::Euler => f.write_str("euler"),
            Integrator::SemiImplicitEuler => f.write_str("semi-implicit"),
            Integrator::Rk4 => f.write_str("rk4"),
            Integrator::Dopri5 { rtol, atol } if rtol == atol => write!(f, "dopri5:{rtol:e}"),
            Integrator::Dopri5 { rtol, atol } => write!(f, "dopri5:{rtol:e},{atol:e}"),
        }
    }
}

impl Integrator {
    /// The Butcher tableau of an explicit Runge-Kutta integrator (`None` for semi-implicit
    /// Euler, which is not one).
    pub fn tableau(&self) -> Option<&'static ButcherTableau> {
        match self {
            Integrator::Euler => Some(&EULER),
            Integrator::SemiImplicitEuler => None,
            Integrator::Rk4 => Some(&RK4),
            Integrator::Dopri5 { .. } => Some(&DOPRI5),
        }
    }
}

/// An explicit Runge-Kutta method as data: `k_s = f(t + c_s h, y + h Σ_j a_sj k_j)`,
/// `y₁ = y + h Σ_s b_s k_s`, and for embedded pairs the error estimate `h Σ_s e_s k_s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ButcherTableau {
    /// Name for messages.
    pub name: &'static str,
    /// Order of the propagated solution.
    pub order: u32,
    /// `a_sj`, row s holding the s coefficients of the earlier stages.
    pub a: &'static [&'static [f64]],
    /// Weights of the solution.
    pub b: &'static [f64],
    /// Nodes.
    pub c: &'static [f64],
    /// `b − b̂` (solution minus embedded weights), for the error estimate of adaptive pairs.
    pub e: Option<&'static [f64]>,
}

impl ButcherTableau {
    /// Every row of `a` has at most one nonzero term (forward Euler, RK4): each stage starts
    /// from one earlier stage.
    pub fn one_term_rows(&self) -> bool {
        self.a
            .iter()
            .all(|row| row.iter().filter(|&&a| a != 0.0).count() <= 1)
    }
}

/// Forward Euler.
pub const EULER: ButcherTableau = ButcherTableau {
    name: "euler",
    order: 1,
    a: &[&[]],
    b: &[1.0],
    c: &[0.0],
    e: None,
};

/// Classic fourth-order Runge-Kutta (Kutta 1901).
pub const RK4: ButcherTableau = ButcherTableau {
    name: "rk4",
    order: 4,
    a: &[&[], &[0.5], &[0.0, 0.5], &[0.0, 0.0, 1.0]],
    b: &[1.0 / 6.0, 1.0 / 3.0, 1.0 / 3.0, 1.0 / 6.0],
    c: &[0.0, 0.5, 0.5, 1.0],
    e: None,
};

/// Dormand-Prince 5(4) (Dormand & Prince 1980; Hairer, Nørsett, Wanner 1993, table 5.2).
pub const DOPRI5: ButcherTableau = ButcherTableau {
    name: "dopri5",
    order: 5,
    a: &[
        &[],
        &[1.0 / 5.0],
        &[3.0 / 40.0, 9.0 / 40.0],
        &[44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0],
        &[
            19372.0 / 6561.0,
            -25360.0 / 2187.0,
            64448.0 / 6561.0,
            -212.0 / 729.0,
        ],
        &[
            9017.0 / 3168.0,
            -355.0 / 33.0,
            46732.0 / 5247.0,
            49.0 / 176.0,
            -5103.0 / 18656.0,
        ],
        &[
            35.0 / 384.0,
            0.0,
            500.0 / 1113.0,
            125.0 / 192.0,
            -2187.0 / 6784.0,
            11.0 / 84.0,
        ],
    ],
    b: &[
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
        0.0,
    ],
    c: &[0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0],
    e: Some(&[
        35.0 / 384.0 - 5179.0 / 57600.0,
        0.0,
        500.0 / 1113.0 - 7571.0 / 16695.0,
        125.0 / 192.0 - 393.0 / 640.0,
        -2187.0 / 6784.0 + 92097.0 / 339200.0,
        11.0 / 84.0 - 187.0 / 2100.0,
        -1.0 / 40.0,
    ]),
};

/// Most stages of the tableaux above (Dormand-Prince's seven).
const MAX_STAGES: usize = 7;

/// Most sub-steps the adaptive integrator takes inside one [`Stepper::step`].
pub const MAX_SUBSTEPS: usize = 100_000;

/// Integrates `(q, v)` step by step; owns every buffer, so a step allocates nothing.
#[derive(Debug, Clone)]
pub struct Stepper {
    /// The method.
    pub integrator: Integrator,
    /// Sub-step size the adaptive method will try next (s); 0 before the first step.
    pub h_next: f64,
    /// Sub-steps taken and rejected by the adaptive method so far.
    pub substeps: usize,
    pub rejected: usize,
    nq: usize,
    nv: usize,
    /// Stage tangent rates `Ω̇_s` (stages × nv) and accelerations `a_s` (stages × nv).
    kq: Vec<f64>,
    kv: Vec<f64>,
    /// Tangent offset of the current stage (nv), stage position (nq), stage velocity (nv).
    omega: Vec<f64>,
    q_stage: Vec<f64>,
    v_stage: Vec<f64>,
    /// Candidate end of a sub-step (nq, nv) and its error estimate (nv, nv).
    q_new: Vec<f64>,
    v_new: Vec<f64>,
    err_q: Vec<f64>,
    err_v: Vec<f64>,
    /// The model's coordinates split by how a stage moves them (set once in `new`).
    layout: Layout,
}

/// `out = q ⊕ Ω` on body `i`'s spherical or free joint ([`JointKind::integrate`] with
/// `dt = 1`; `q`, `omega` and `out` whole states, the joint's slots read and written).
fn manifold_step(model: &Model, i: usize, q: &[f64], omega: &[f64], out: &mut [f64]) {
    let j = &model.joints[i];
    let (iq, iv) = (model.idx_q[i], model.idx_v[i]);
    let (q, omega) = (&q[iq..iq + j.nq()], &omega[iv..iv + j.nv()]);
    j.integrate(q, omega, 1.0, &mut out[iq..iq + j.nq()]);
}

/// `(0 + Σ_s hb_s Ω̇_s, v + Σ_s hb_s a_s)` at coordinate `r`, each sum in stage order, over
/// the stages `hb` weighs (`kq`, `kv` stage-major, `nv` each).
fn stage_sums(hb: &[f64], kq: &[f64], kv: &[f64], nv: usize, r: usize, v: f64) -> (f64, f64) {
    let (mut o, mut w) = (0.0, v);
    for (s, &hb) in hb.iter().enumerate() {
        o += hb * kq[s * nv + r];
        w += hb * kv[s * nv + r];
    }
    (o, w)
}

/// `q += 0 + Σ_s hb_s Ω̇_s` and `v += Σ_s hb_s a_s`, each sum in stage order, over the `S`
/// stages of `kq` and `kv` (stage-major, `nv` each) from coordinate `iv` on, for `v.len()`
/// coordinates: the stage loop unrolled.
fn solution<const S: usize>(
    hb: &[f64; MAX_STAGES],
    kq: &[f64],
    kv: &[f64],
    nv: usize,
    iv: usize,
    q: &mut [f64],
    v: &mut [f64],
) {
    let n = v.len();
    let kq: [&[f64]; S] = std::array::from_fn(|s| &kq[s * nv + iv..][..n]);
    let kv: [&[f64]; S] = std::array::from_fn(|s| &kv[s * nv + iv..][..n]);
    let q = &mut q[..n];
    for i in 0..n {
        let (mut o, mut w) = (0.0, v[i]);
        for s in 0..S {
            o += hb[s] * kq[s][i];
            w += hb[s] * kv[s][i];
        }
        q[i] += o;
        v[i] = w;
    }
}

/// Where a stage's `q ⊕ Ω` and `Ω̇ = dexp⁻¹_{−Ω}(v)` are plain vector operations: runs of
/// consecutive 1-DoF joints (revolute, prismatic), on which `q ⊕ Ω = q + Ω` and `Ω̇ = v`
/// exactly as [`Model::integrate`] and [`tangent_rate`] compute them there, and the bodies whose
/// joints live on a manifold (spherical, free), which go through those functions' joint code.
#[derive(Debug, Clone, Default)]
struct Layout {
    /// `(first q index, first v index, length)` of each run of 1-DoF coordinates.
    runs: Vec<(usize, usize, usize)>,
    /// Bodies with a spherical or free joint.
    manifold: Vec<usize>,
}

impl Layout {
    fn new(model: &Model) -> Self {
        let mut out = Layout::default();
        for i in 1..model.nbodies() {
            let (iq, iv) = (model.idx_q[i], model.idx_v[i]);
            match model.joints[i] {
                JointKind::Fixed => {}
                JointKind::Revolute { .. } | JointKind::Prismatic { .. } => {
                    match out.runs.last_mut() {
                        Some((q0, v0, n)) if *q0 + *n == iq && *v0 + *n == iv => *n += 1,
                        _ => out.runs.push((iq, iv, 1)),
                    }
                }
                JointKind::Spherical | JointKind::Free => out.manifold.push(i),
            }
        }
        out
    }

    /// `out = q ⊕ Ω` ([`Model::integrate`] with `dt = 1`).
    fn integrate(&self, model: &Model, q: &[f64], omega: &[f64], out: &mut [f64]) {
        for &(iq, iv, n) in &self.runs {
            let (q, o, out) = (&q[iq..iq + n], &omega[iv..iv + n], &mut out[iq..iq + n]);
            for ((x, q), o) in out.iter_mut().zip(q).zip(o) {
                *x = q + o;
            }
        }
        for &i in &self.manifold {
            manifold_step(model, i, q, omega, out);
        }
    }

    /// `out = dexp⁻¹_{−Ω}(v)` ([`tangent_rate`]).
    fn tangent_rate(&self, model: &Model, omega: &[f64], v: &[f64], out: &mut [f64]) {
        for &(_, iv, n) in &self.runs {
            out[iv..iv + n].copy_from_slice(&v[iv..iv + n]);
        }
        for &i in &self.manifold {
            joint_tangent_rate(model, i, omega, v, out);
        }
    }
}

impl Stepper {
    /// A stepper for `model` (buffers sized once here).
    pub fn new(model: &Model, integrator: Integrator) -> Self {
        let (nq, nv) = (model.nq, model.nv);
        let stages = integrator.tableau().map_or(1, |t| t.b.len());
        Self {
            integrator,
            h_next: 0.0,
            substeps: 0,
            rejected: 0,
            nq,
            nv,
            kq: vec![0.0; stages * nv],
            kv: vec![0.0; stages * nv],
            omega: vec![0.0; nv],
            q_stage: vec![0.0; nq],
            v_stage: vec![0.0; nv],
            q_new: vec![0.0; nq],
            v_new: vec![0.0; nv],
            err_q: vec![0.0; nv],
            err_v: vec![0.0; nv],
            layout: Layout::new(model),
        }
    }

    /// Advances `(q, v)` from time `t` by `dt`, with accelerations from
    /// `f(t, q, v, a_out)` (e.g. [`aba`](super::aba) with a controller's torques).
    ///
    /// # Errors
    /// Whatever `f` returns; [`Error::Numerical`] if the state stops being finite, or if the
    /// adaptive method's sub-step underflows or needs more than [`MAX_SUBSTEPS`].
    pub fn step<F>(
        &mut self,
        model: &Model,
        t: f64,
        dt: f64,
        q: &mut [f64],
        v: &mut [f64],
        f: &mut F,
    ) -> Result<(), Error>
    where
        F: FnMut(f64, &[f64], &[f64], &mut [f64]) -> Result<(), Error>,
    {
        assert_eq!((q.len(), v.len()), (self.nq, self.nv), "state size");
        match self.integrator {
            Integrator::SemiImplicitEuler => {
                // v ← v + h a(q, v), then q ← q ⊕ h v
                let a = &mut self.kv[..self.nv];
                f(t, q, v, a)?;
                for (vk, ak) in v.iter_mut().zip(a.iter()) {
                    *vk += dt * ak;
                }
                model.integrate(q, v, dt, &mut self.q_new);
                q.copy_from_slice(&self.q_new);
            }
            Integrator::Euler | Integrator::Rk4 => {
                let tab = self.integrator.tableau().expect("explicit method");
                // both start each stage from one earlier stage (a test says so)
                self.rk_one_term(model, tab, t, dt, q, v, f)?;
            }
            Integrator::Dopri5 { rtol, atol } => {
                self.adaptive(model, t, dt, q, v, f, rtol, atol)?
            }
        }
        // the culprit named after the whole state is looked at
        if crate::lanes::all_finite(q) & crate::lanes::all_finite(v) {
            return Ok(());
        }
        match q.iter().chain(v.iter()).position(|x| !x.is_finite()) {
            None => Ok(()),
            Some(k) => {
                let name = if k < self.nq {
                    &model.q_names[k]
                } else {
                    &model.v_names[k - self.nq]
                };
                Err(Error::Numerical(format!(
                    "{} step at t = {t} s (dt = {dt} s) made `{name}` non-finite",
                    self.integrator
                )))
            }
        }
    }

    /// One explicit Runge-Kutta step of size `h` from `(q, v)`: fills the stages and writes the
    /// result to `q_new`, `v_new` (and, for embedded pairs, the error estimate).
    #[allow(clippy::too_many_arguments)]
    fn rk_stages<F>(
        &mut self,
        model: &Model,
        tab: &ButcherTableau,
        t: f64,
        h: f64,
        q: &[f64],
        v: &[f64],
        f: &mut F,
    ) -> Result<(), Error>
    where
        F: FnMut(f64, &[f64], &[f64], &mut [f64]) -> Result<(), Error>,
    {
        let nv = self.nv;
        for (s, row) in tab.a.iter().enumerate() {
            let kv_s = s * nv..(s + 1) * nv;
            // stage state: Ω = h Σ a_sj Ω̇_j, q_s = q ⊕ Ω, v_s = v + h Σ a_sj a_j
            let Some(j0) = row.iter().position(|&a| a != 0.0) else {
                // the step's start (Ω = 0): q_s = q, v_s = v and Ω̇_s = dexp⁻¹_0(v) = v
                f(t + tab.c[s] * h, q, v, &mut self.kv[kv_s.clone()])?;
                self.kq[kv_s].copy_from_slice(v);
                continue;
            };
            // the first term written, the others added, in stage order (the sums of
            // `0 + Σ` and `v + Σ` term by term)
            let ha = h * row[j0];
            let (kq, kv) = (&self.kq[j0 * nv..][..nv], &self.kv[j0 * nv..][..nv]);
            for (o, k) in self.omega.iter_mut().zip(kq) {
                *o = 0.0 + ha * k;
            }
            for ((x, v), k) in self.v_stage.iter_mut().zip(v).zip(kv) {
                *x = v + ha * k;
            }
            for (j, &a) in row.iter().enumerate().skip(j0 + 1) {
                if a != 0.0 {
                    let ha = h * a;
                    let (kq, kv) = (&self.kq[j * nv..][..nv], &self.kv[j * nv..][..nv]);
                    for (o, k) in self.omega.iter_mut().zip(kq) {
                        *o += ha * k;
                    }
                    for (x, k) in self.v_stage.iter_mut().zip(kv) {
                        *x += ha * k;
                    }
                }
            }
            self.layout
                .integrate(model, q, &self.omega, &mut self.q_stage);
            // stage derivatives: a_s = f(…), Ω̇_s = dexp⁻¹_{−Ω}(v_s)
            f(
                t + tab.c[s] * h,
                &self.q_stage,
                &self.v_stage,
                &mut self.kv[kv_s.clone()],
            )?;
            self.layout
                .tangent_rate(model, &self.omega, &self.v_stage, &mut self.kq[kv_s]);
        }
        // solution (and error estimate): Ω = h Σ b_s Ω̇_s, v₁ = v + h Σ b_s a_s
        self.omega.fill(0.0);
        self.v_new.copy_from_slice(v);
        if tab.e.is_some() {
            self.err_q.fill(0.0);
            self.err_v.fill(0.0);
        }
        for (s, &b) in tab.b.iter().enumerate() {
            let (kq, kv) = (&self.kq[s * nv..][..nv], &self.kv[s * nv..][..nv]);
            let hb = h * b;
            for (o, k) in self.omega.iter_mut().zip(kq) {
                *o += hb * k;
            }
            for (x, k) in self.v_new.iter_mut().zip(kv) {
                *x += hb * k;
            }
            if let Some(e) = tab.e {
                let he = h * e[s];
                for (x, k) in self.err_q.iter_mut().zip(kq) {
                    *x += he * k;
                }
                for (x, k) in self.err_v.iter_mut().zip(kv) {
                    *x += he * k;
                }
            }
        }
        self.layout
            .integrate(model, q, &self.omega, &mut self.q_new);
        Ok(())
    }

    /// [`rk_stages`](Self::rk_stages) for a tableau whose rows have at most one term (Euler,
    /// RK4; [`ButcherTableau::one_term_rows`]), with `(q, v)` advanced in place: the same sums
    /// in the same order, so the same bits, in fewer passes. On the runs of 1-DoF coordinates
    /// (`q ⊕ Ω = q + Ω`, `Ω̇ = v`) a stage's `q_s`, `v_s` and `Ω̇_s` take one pass, and the
    /// solution's sums over the stages one pass; the spherical and free joints go through
    /// their joint code.
    #[allow(clippy::too_many_arguments)]
    fn rk_one_term<F>(
        &mut self,
        model: &Model,
        tab: &ButcherTableau,
        t: f64,
        h: f64,
        q: &mut [f64],
        v: &mut [f64],
        f: &mut F,
    ) -> Result<(), Error>
    where
        F: FnMut(f64, &[f64], &[f64], &mut [f64]) -> Result<(), Error>,
    {
        // on 1-DoF joints only, v_s is Ω̇_s: written once, into its slot
        let (nv, flat) = (self.nv, self.layout.manifold.is_empty());
        for (s, row) in tab.a.iter().enumerate() {
            let (kq_done, kq_rest) = self.kq.split_at_mut(s * nv);
            let (kv_done, kv_rest) = self.kv.split_at_mut(s * nv);
            let (kq_s, kv_s) = (&mut kq_rest[..nv], &mut kv_rest[..nv]);
            let t_s = t + tab.c[s] * h;
            let Some(j) = row.iter().position(|&a| a != 0.0) else {
                // the step's start: q_s = q, v_s = v and Ω̇_s = v
                f(t_s, q, v, kv_s)?;
                kq_s.copy_from_slice(v);
                continue;
            };
            // Ω = 0 + h a Ω̇_j, q_s = q ⊕ Ω, v_s = v + h a a_j, and Ω̇_s = v_s on the runs
            let ha = h * row[j];
            let (kq_j, kv_j) = (&kq_done[j * nv..][..nv], &kv_done[j * nv..][..nv]);
            for &(iq, iv, n) in &self.layout.runs {
                let (x, dq) = (&mut self.q_stage[iq..][..n], &mut kq_s[iv..][..n]);
                let (q, v) = (&q[iq..][..n], &v[iv..][..n]);
                let (k, a) = (&kq_j[iv..][..n], &kv_j[iv..][..n]);
                for i in 0..n {
                    x[i] = q[i] + (0.0 + ha * k[i]);
                    dq[i] = v[i] + ha * a[i];
                }
                if !flat {
                    self.v_stage[iv..][..n].copy_from_slice(dq);
                }
            }
            for &i in &self.layout.manifold {
                let iv = model.idx_v[i];
                for r in iv..iv + model.joints[i].nv() {
                    self.omega[r] = 0.0 + ha * kq_j[r];
                    self.v_stage[r] = v[r] + ha * kv_j[r];
                }
                manifold_step(model, i, q, &self.omega, &mut self.q_stage);
            }
            // stage derivatives: a_s = f(…), Ω̇_s = dexp⁻¹_{−Ω}(v_s) on the manifold
            if flat {
                f(t_s, &self.q_stage, kq_s, kv_s)?;
            } else {
                f(t_s, &self.q_stage, &self.v_stage, kv_s)?;
                for &i in &self.layout.manifold {
                    joint_tangent_rate(model, i, &self.omega, &self.v_stage, kq_s);
                }
            }
        }
        self.one_term_solution(model, tab, h, q, v);
        Ok(())
    }

    /// The end of [`rk_one_term`](Self::rk_one_term): `Ω = 0 + h Σ b_s Ω̇_s`, `q₁ = q ⊕ Ω`,
    /// `v₁ = v + h Σ b_s a_s`, each sum stage by stage, into `(q, v)`.
    fn one_term_solution(
        &mut self,
        model: &Model,
        tab: &ButcherTableau,
        h: f64,
        q: &mut [f64],
        v: &mut [f64],
    ) {
        let nv = self.nv;
        let mut hb = [0.0; MAX_STAGES];
        for (x, &b) in hb.iter_mut().zip(tab.b) {
            *x = h * b;
        }
        let (kq, kv) = (&self.kq[..], &self.kv[..]);
        let sums = |r: usize, v: f64| stage_sums(&hb[..tab.b.len()], kq, kv, nv, r, v);
        for &(iq, iv, n) in &self.layout.runs {
            let (q, v) = (&mut q[iq..][..n], &mut v[iv..][..n]);
            match tab.b.len() {
                1 => solution::<1>(&hb, kq, kv, nv, iv, q, v),
                4 => solution::<4>(&hb, kq, kv, nv, iv, q, v),
                _ => {
                    for i in 0..n {
                        let (o, w) = sums(iv + i, v[i]);
                        q[i] += o;
                        v[i] = w;
                    }
                }
            }
        }
        for &i in &self.layout.manifold {
            let j = &model.joints[i];
            let (iq, iv) = (model.idx_q[i], model.idx_v[i]);
            for (r, v) in v.iter_mut().enumerate().skip(iv).take(j.nv()) {
                (self.omega[r], *v) = sums(r, *v);
            }
            manifold_step(model, i, q, &self.omega, &mut self.q_new);
            q[iq..iq + j.nq()].copy_from_slice(&self.q_new[iq..iq + j.nq()]);
        }
    }

    /// Dormand-Prince sub-steps covering `[t, t + dt]`, each accepted when its scaled error
    /// norm is ≤ 1 (Hairer, Nørsett, Wanner 1993, eq. 4.11 and §II.4 "automatic step size
    /// control", safety 0.9, growth between 0.2 and 5).
    #[allow(clippy::too_many_arguments)]
    fn adaptive<F>(
        &mut self,
        model: &Model,
        t: f64,
        dt: f64,
        q: &mut [f64],
        v: &mut [f64],
        f: &mut F,
        rtol: f64,
        atol: f64,
    ) -> Result<(), Error>
    where
        F: FnMut(f64, &[f64], &[f64], &mut [f64]) -> Result<(), Error>,
    {
        let t_end = t + dt;
        let mut tc = t;
        let mut h = if self.h_next > 0.0 {
            self.h_next.min(dt)
        } else {
            dt
        };
        let mut n = 0;
        while tc < t_end {
            n += 1;
            let last = tc + h >= t_end - 1e-12 * dt.abs();
            let hs = if last { t_end - tc } else { h };
            if n > MAX_SUBSTEPS || hs.is_nan() || hs <= 1e-14 * t_end.abs().max(1.0) {
                return Err(Error::Numerical(format!(
                    "{}: sub-step fell to {hs:e} s at t = {tc} s after {n} sub-steps (the \
                     system is too stiff at these gains, or it diverges); use a looser \
                     tolerance, lower gains, or check the model",
                    self.integrator
                )));
            }
            self.rk_stages(model, &DOPRI5, tc, hs, q, v, f)?;
            // scaled RMS error over positions (tangent) and velocities
            let mut sum = 0.0;
            for (k, vk) in v.iter().enumerate() {
                let sq = atol + rtol * self.omega[k].abs();
                let sv = atol + rtol * vk.abs().max(self.v_new[k].abs());
                sum += (self.err_q[k] / sq).powi(2) + (self.err_v[k] / sv).powi(2);
            }
            let err = (sum / (2 * self.nv).max(1) as f64).sqrt();
            let grow = if err > 0.0 {
                (0.9 * err.powf(-0.2)).clamp(0.2, 5.0)
            } else {
                5.0
            };
            if err <= 1.0 && err.is_finite() {
                q.copy_from_slice(&self.q_new);
                v.copy_from_slice(&self.v_new);
                tc = if last { t_end } else { tc + hs };
                self.substeps += 1;
                // a clipped last sub-step says nothing about the size to try next
                if !last || hs >= h {
                    h = hs * grow;
                }
            } else {
                self.rejected += 1;
                h = hs * if err.is_finite() { grow.min(1.0) } else { 0.2 };
            }
        }
        self.h_next = h;
        Ok(())
    }
}

/// `Ω̇ = dexp⁻¹_{−Ω}(v)`: the rate of the tangent offset `Ω` (from the step's start) that moves
/// the configuration with body velocity `v`, joint by joint. Identity for 1-DoF joints; for a
/// spherical joint on SO(3) and a free joint on SE(3) the Bernoulli series
/// `v + ½ ad_Ω v + 1/12 ad_Ω² v − 1/720 ad_Ω⁴ v` (Iserles et al. 2000, "Lie-group methods",
/// §2.3), enough for order 5 since `|Ω|` is one step's rotation.
pub fn tangent_rate(model: &Model, omega: &[f64], v: &[f64], out: &mut [f64]) {
    for i in 1..model.nbodies() {
        joint_tangent_rate(model, i, omega, v, out);
    }
}

/// [`tangent_rate`] for the coordinates of joint `i`.
fn joint_tangent_rate(model: &Model, i: usize, omega: &[f64], v: &[f64], out: &mut [f64]) {
    let iv = model.idx_v[i];
    match model.joints[i] {
        JointKind::Revolute { .. } | JointKind::Prismatic { .. } => out[iv] = v[iv],
        JointKind::Fixed => {}
        JointKind::Spherical => {
            let th = Vector3::new(omega[iv], omega[iv + 1], omega[iv + 2]);
            let w = Vector3::new(v[iv], v[iv + 1], v[iv + 2]);
            let ad1 = th.cross(&w);
            let ad2 = th.cross(&ad1);
            let ad4 = th.cross(&th.cross(&ad2));
            let r = w + ad1 * 0.5 + ad2 * (1.0 / 12.0) - ad4 * (1.0 / 720.0);
            out[iv..iv + 3].copy_from_slice(r.as_slice());
        }
        JointKind::Free => {
            // se(3), linear first: ad_(ρ,θ)(u, w) = (θ × u + ρ × w, θ × w)
            let rho = Vector3::new(omega[iv], omega[iv + 1], omega[iv + 2]);
            let th = Vector3::new(omega[iv + 3], omega[iv + 4], omega[iv + 5]);
            let ad = |u: &Vector3<f64>, w: &Vector3<f64>| (th.cross(u) + rho.cross(w), th.cross(w));
            let u0 = Vector3::new(v[iv], v[iv + 1], v[iv + 2]);
            let w0 = Vector3::new(v[iv + 3], v[iv + 4], v[iv + 5]);
            let (u1, w1) = ad(&u0, &w0);
            let (u2, w2) = ad(&u1, &w1);
            let (u3, w3) = ad(&u2, &w2);
            let (u4, w4) = ad(&u3, &w3);
            let u = u0 + u1 * 0.5 + u2 * (1.0 / 12.0) - u4 * (1.0 / 720.0);
            let w = w0 + w1 * 0.5 + w2 * (1.0 / 12.0) - w4 * (1.0 / 720.0);
            out[iv..iv + 3].copy_from_slice(u.as_slice());
            out[iv + 3..iv + 6].copy_from_slice(w.as_slice());
        }
    }
}

#[cfg(test)]
mod tests;
