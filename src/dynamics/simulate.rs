//! Tracking simulation: the computed-torque controller (the paper's equation 2, with a possibly
//! wrong model) drives the true model, whose motion comes from the articulated-body algorithm
//! and an integrator. Records what happened and how well the reference was tracked.
//!
//! **The root residual actuator.** A floating avatar (a free root joint, or the euler model's
//! three prismatic and three revolute root joints) has six root coordinates that no muscle
//! drives: the torques the controller puts there are a non-physical residual actuator (OpenSim's
//! "residual actuators") that stands in for the missing ground contact. They are reported
//! separately from the joint torques ([`SimResult::root_residual_rms`]) and left out of the
//! tracking-error summary.

use super::control::{ComputedTorque, Gains, Reference};
use super::integrate::{Integrator, Stepper};
use super::{Workspace, aba};
use crate::error::Error;
use crate::model::{JointKind, Model};

/// How to simulate.
#[derive(Debug, Clone, PartialEq)]
pub struct SimOptions {
    pub integrator: Integrator,
    /// Step (s); the adaptive integrator sub-steps inside it.
    pub dt: f64,
    pub gains: Gains,
    /// Link masses (and inertias) of the controller's model scaled by `1 + mass_error`; the
    /// simulated model keeps the true ones.
    pub mass_error: f64,
    /// A coordinate faster than this (rad/s or m/s) stops the simulation as diverged.
    pub max_speed: f64,
    /// A joint angle (outside the root) further than this from its reference (rad) stops the
    /// simulation as diverged: past half a turn the controller no longer tracks the motion
    /// (explicit Euler at 0.1 s on a walk ends 46 rad off, below any speed limit).
    pub max_error: f64,
}

impl Default for SimOptions {
    /// RK4 at 1 ms, `Kp = 400`, `Kv = 40` (critically damped at 20 rad/s), exact model,
    /// divergence beyond 1000 rad/s or half a turn of tracking error.
    fn default() -> Self {
        Self {
            integrator: Integrator::Rk4,
            dt: 1e-3,
            gains: Gains::scalar(400.0, 40.0),
            mass_error: 0.0,
            max_speed: 1e3,
            max_error: std::f64::consts::PI,
        }
    }
}

/// What a simulation recorded. Rows are taken at the start, at the first step at or after each
/// reference sample time, and at the end (every step when `dt` is at least the reference
/// spacing); the error statistics use every step.
#[derive(Debug, Clone, PartialEq)]
pub struct SimResult {
    pub integrator: Integrator,
    pub dt: f64,
    /// Steps taken.
    pub steps: usize,
    /// Velocity coordinate names (`nv`), the columns of `v`, `tau`, `error`.
    pub names: Vec<String>,
    /// Recorded times (s).
    pub time: Vec<f64>,
    /// Simulated configuration per row (`nq`).
    pub q: Vec<Vec<f64>>,
    /// Simulated velocity per row (`nv`).
    pub v: Vec<Vec<f64>>,
    /// Controller torques per row (`nv`, N·m or N); the first `root_nv` are the root residual.
    pub tau: Vec<Vec<f64>>,
    /// Tracking error `qd ⊖ q` per row (`nv`, rad or m).
    pub error: Vec<Vec<f64>>,
    /// RMS and maximum absolute tracking error per coordinate over every step (`nv`).
    pub rms_error: Vec<f64>,
    pub max_error: Vec<f64>,
    /// Number of root residual coordinates (6 for a floating avatar, else 0); see the module
    /// doc.
    pub root_nv: usize,
    /// RMS and maximum absolute residual force of each root coordinate over every step
    /// (`root_nv`, N for translations, N·m for rotations).
    pub root_residual_rms: Vec<f64>,
    pub root_residual_max: Vec<f64>,
    /// Whether each coordinate is an angle (rad) rather than a length (m) (`nv`).
    pub angular: Vec<bool>,
}

impl SimResult {
    /// RMS tracking error over the angular coordinates outside the root (rad).
    pub fn rms_error_rad(&self) -> f64 {
        let (sum, n) = self
            .joint_angles()
            .fold((0.0, 0), |(s, n), k| (s + self.rms_error[k].powi(2), n + 1));
        if n == 0 { 0.0 } else { (sum / n as f64).sqrt() }
    }
    /// Largest tracking error over the angular coordinates outside the root (rad).
    pub fn max_error_rad(&self) -> f64 {
        self.joint_angles()
            .map(|k| self.max_error[k])
            .fold(0.0, f64::max)
    }
    fn joint_angles(&self) -> impl Iterator<Item = usize> + '_ {
        (self.root_nv..self.names.len()).filter(|&k| self.angular[k])
    }
    /// The JSON summary of `articula simulate --json`.
    pub fn summary_json(&self) -> serde_json::Value {
        let per = |range: std::ops::Range<usize>, a: &[f64], b: &[f64], off: usize| {
            range
                .map(|k| {
                    serde_json::json!({"name": self.names[k], "rms": a[k - off], "max": b[k - off]})
                })
                .collect::<Vec<_>>()
        };
        serde_json::json!({
            "integrator": self.integrator.to_string(),
            "dt": self.dt,
            "steps": self.steps,
            "rms_error_rad": self.rms_error_rad(),
            "max_error_rad": self.max_error_rad(),
            "coordinates": per(0..self.names.len(), &self.rms_error, &self.max_error, 0),
            "root_residual": per(0..self.root_nv, &self.root_residual_rms, &self.root_residual_max, 0),
        })
    }
}

/// Number of root residual coordinates: 6 when the first joint hangs from the world and is a
/// free joint, or when bodies 1..6 are a chain from the world of three prismatic and three
/// revolute joints (the euler model's root); else 0.
pub fn floating_root_nv(model: &Model) -> usize {
    if model.nbodies() > 1 && model.parent[1] == 0 && model.joints[1] == JointKind::Free {
        return 6;
    }
    if model.nbodies() <= 6 {
        return 0;
    }
    let chain = (1..=6).all(|i| model.parent[i] == i - 1);
    let count = |f: fn(&JointKind) -> bool| (1..=6).filter(|&i| f(&model.joints[i])).count();
    let prismatic = count(|j| matches!(j, JointKind::Prismatic { .. }));
    let revolute = count(|j| matches!(j, JointKind::Revolute { .. }));
    if chain && prismatic == 3 && revolute == 3 {
        6
    } else {
        0
    }
}

/// Simulates `model` tracking `reference` under computed-torque control (see the module doc):
/// starts on the reference's first sample, steps with `opts.integrator` until its last time.
///
/// # Errors
/// [`Error::Invalid`] for inconsistent inputs (sizes, gains, `dt`); [`Error::Numerical`] when
/// the simulation diverges (a non-finite number, a speed beyond `opts.max_speed`, or a joint
/// angle further than `opts.max_error` from its reference) or the
/// model becomes singular, naming the step, the time and the coordinate. Nothing non-finite is
/// ever returned.
pub fn simulate(
    model: &Model,
    reference: &Reference,
    opts: &SimOptions,
) -> Result<SimResult, Error> {
    simulate_with(model, reference, opts, &mut |_| true)
}

/// Steps between two calls of the progress callback of [`simulate_with`].
pub const PROGRESS_EVERY: usize = 256;

/// [`simulate`] that reports its progress (0‥1) to `keep_going` every [`PROGRESS_EVERY`]
/// steps and stops with `Error::Cancelled` when it returns false (for a user
/// interface's worker thread; the callback is called by reference, nothing is allocated).
pub fn simulate_with(
    model: &Model,
    reference: &Reference,
    opts: &SimOptions,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<SimResult, Error> {
    reference.validate(model)?;
    if !(opts.dt > 0.0 && opts.dt.is_finite()) {
        return Err(Error::Invalid(format!(
            "time step {} s: must be > 0",
            opts.dt
        )));
    }
    if opts.max_speed.is_nan() || opts.max_speed <= 0.0 {
        return Err(Error::Invalid(format!(
            "max speed {}: must be > 0",
            opts.max_speed
        )));
    }
    let nv = model.nv;
    let mut ctrl = ComputedTorque::new(model, opts.gains.clone(), opts.mass_error)?;
    let mut ws = Workspace::new(model);
    let mut stepper = Stepper::new(model, opts.integrator);
    let (t0, t_end) = (
        reference.time[0],
        *reference.time.last().expect("validated"),
    );
    let steps = ((t_end - t0) / opts.dt - 1e-9).ceil().max(0.0) as usize;
    let root_nv = floating_root_nv(model);

    let mut q = reference.q[0].clone();
    let mut v = reference.v[0].clone();
    let mut tau_now = vec![0.0; nv];
    let mut err_now = vec![0.0; nv];
    let mut tau_buf = vec![0.0; nv];
    let mut out = SimResult {
        integrator: opts.integrator,
        dt: opts.dt,
        steps,
        names: model.v_names.clone(),
        time: vec![],
        q: vec![],
        v: vec![],
        tau: vec![],
        error: vec![],
        rms_error: vec![0.0; nv],
        max_error: vec![0.0; nv],
        root_nv,
        root_residual_rms: vec![0.0; root_nv],
        root_residual_max: vec![0.0; root_nv],
        angular: (0..nv).map(|k| model.is_angular(k)).collect(),
    };
    let mut next_sample = 0;
    for n in 0..=steps {
        if n % PROGRESS_EVERY == 0 && !keep_going(n as f64 / (steps + 1) as f64) {
            return Err(Error::Cancelled);
        }
        let t = t0 + n as f64 * opts.dt;
        let context = |e: Error| match e {
            Error::Numerical(m) => Error::Numerical(format!(
                "simulation step {n} (t = {t:.6} s, {} at dt = {} s): {m}",
                opts.integrator, opts.dt
            )),
            other => other,
        };
        let record = n == steps
            || next_sample < reference.len() && t >= reference.time[next_sample] - 1e-9 * opts.dt;
        if record {
            out.time.push(t);
            out.q.push(q.clone());
            out.v.push(v.clone());
            next_sample = reference.time.partition_point(|&x| x <= t + 1e-9 * opts.dt);
        }
        if n < steps {
            // one step; the controller's first evaluation is at (t, q, v): keep its τ and error
            let mut first = true;
            let mut f = |ts: f64, qs: &[f64], vs: &[f64], acc: &mut [f64]| -> Result<(), Error> {
                tau_buf.copy_from_slice(ctrl.torque(reference, ts, qs, vs).as_slice());
                if first {
                    tau_now.copy_from_slice(&tau_buf);
                    err_now.copy_from_slice(&ctrl.error);
                    first = false;
                }
                if let Some(k) = tau_buf.iter().position(|x| !x.is_finite()) {
                    return Err(Error::Numerical(format!(
                        "the controller's torque on `{}` is not finite",
                        model.v_names[k]
                    )));
                }
                acc.copy_from_slice(aba(model, &mut ws, qs, vs, &tau_buf, None)?.as_slice());
                Ok(())
            };
            stepper
                .step(model, t, opts.dt, &mut q, &mut v, &mut f)
                .map_err(context)?;
        } else {
            tau_now.copy_from_slice(ctrl.torque(reference, t, &q, &v).as_slice());
            err_now.copy_from_slice(&ctrl.error);
        }
        // statistics and the recorded row, at (t, q_n, v_n)
        accumulate(&err_now, &mut out.rms_error, &mut out.max_error);
        let lost = |k: &usize| model.is_angular(*k) && err_now[*k].abs() > opts.max_error;
        if let Some(k) = (root_nv..model.nv).find(lost) {
            return Err(context(Error::Numerical(format!(
                "diverged: `{}` is {:.3e} rad off its reference at t = {t:.3} s (more than \
                 {:.2} rad: the controller has lost the motion); the step is past the \
                 integrator's stability limit for these gains: use a smaller --dt, lower \
                 gains, or rk4 / dopri5",
                model.v_names[k],
                err_now[k].abs(),
                opts.max_error
            ))));
        }
        accumulate(
            &tau_now[..root_nv],
            &mut out.root_residual_rms,
            &mut out.root_residual_max,
        );
        if record {
            out.tau.push(tau_now.clone());
            out.error.push(err_now.clone());
        }
        // divergence: the state after the step
        if n < steps {
            let too_fast = |x: &f64| x.is_nan() || x.abs() > opts.max_speed;
            if let Some(k) = v.iter().position(too_fast) {
                return Err(context(Error::Numerical(format!(
                    "diverged: `{}` reached {:.3e} {} (max speed {}); the step is past the \
                     integrator's stability limit for these gains: use a smaller --dt, lower \
                     gains, or rk4 / dopri5",
                    model.v_names[k],
                    v[k],
                    if model.is_angular(k) { "rad/s" } else { "m/s" },
                    opts.max_speed
                ))));
            }
        }
    }
    let rows = (steps + 1) as f64;
    out.rms_error
        .iter_mut()
        .for_each(|x| *x = (*x / rows).sqrt());
    out.root_residual_rms
        .iter_mut()
        .for_each(|x| *x = (*x / rows).sqrt());
    Ok(out)
}

/// `sum_sq += x²`, `max_abs = max(max_abs, |x|)` element by element.
fn accumulate(x: &[f64], sum_sq: &mut [f64], max_abs: &mut [f64]) {
    for ((x, s), m) in x.iter().zip(sum_sq.iter_mut()).zip(max_abs.iter_mut()) {
        *s += x * x;
        *m = m.max(x.abs());
    }
}
