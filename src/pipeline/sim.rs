//! Simulation jobs: computed-torque tracking of a take, the `bench` timings and the
//! speed/accuracy `tradeoff` table.

use super::{PerJoint, States, Take, TakeOptions, load_take, parse_flag};
use crate::dynamics::{self, Workspace};
use crate::error::Error;
use crate::model::bvh::JointModel;
use crate::model::{JointKind, Model};
use std::path::Path;

/// Settings of a tracked simulation, validated.
#[derive(Debug, Clone, PartialEq)]
pub struct SimSettings {
    /// Integrator, step and mass error; its gains are replaced by `kp`/`kv` resolved against
    /// the model when a simulation starts ([`SimSettings::options_for`]).
    pub options: dynamics::simulate::SimOptions,
    /// Computed-torque gains (1/s², 1/s), per coordinate by joint or coordinate name.
    pub kp: PerJoint,
    pub kv: PerJoint,
    /// Simulated time from the start of the take (s); `None`: the whole take.
    pub duration_s: Option<f64>,
}

impl SimSettings {
    /// From the user's flags (`--integrator`, `--dt`, `--kp`, `--kv`, `--mass-error`,
    /// `--duration`).
    pub fn parse(
        integrator: &str,
        dt: f64,
        kp: &PerJoint,
        kv: &PerJoint,
        mass_error: f64,
        duration_s: Option<f64>,
    ) -> Result<Self, Error> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(Error::Invalid(format!(
                "--dt {dt}: expected a positive step in seconds, e.g. 0.001"
            )));
        }
        if !(mass_error > -1.0 && mass_error.is_finite()) {
            return Err(Error::Invalid(format!(
                "--mass-error {mass_error}: expected a fraction above −1, e.g. 0.1 for 10 % heavy"
            )));
        }
        if let Some(d) = duration_s
            && !(d > 0.0 && d.is_finite())
        {
            return Err(Error::Invalid(format!(
                "--duration {d}: expected seconds > 0"
            )));
        }
        // every coordinate's gains here; the overrides, once matched to a model, by the
        // controller (`ComputedTorque::new` validates the gains it is given)
        let gains = dynamics::control::Gains::scalar(kp.all, kv.all);
        gains.validate(1)?;
        Ok(Self {
            kp: kp.clone(),
            kv: kv.clone(),
            options: dynamics::simulate::SimOptions {
                integrator: parse_flag("integrator", integrator)?,
                dt,
                gains,
                mass_error,
                ..Default::default()
            },
            duration_s,
        })
    }

    /// The simulation options for `model`: the gains per coordinate (`kp`, `kv` matched by
    /// name, [`super::per_coordinate`]), the rest as parsed.
    ///
    /// # Errors
    /// A gain override that names no coordinate of `model`.
    pub fn options_for(&self, model: &Model) -> Result<dynamics::simulate::SimOptions, Error> {
        let mut o = self.options.clone();
        if !(self.kp.joints.is_empty() && self.kv.joints.is_empty()) {
            o.gains = dynamics::control::Gains {
                kp: super::per_coordinate(model, &self.kp, 0, "kp")?,
                kv: super::per_coordinate(model, &self.kv, 0, "kv")?,
            };
        }
        Ok(o)
    }
}

/// The reference a simulation tracks: the take's states, cut to `duration_s`.
pub fn reference(states: &States, duration_s: Option<f64>) -> dynamics::control::Reference {
    let t0 = states.time.first().copied().unwrap_or(0.0);
    let n = match duration_s {
        Some(d) => states
            .time
            .iter()
            .position(|&t| t - t0 > d + 1e-9)
            .unwrap_or(states.len())
            .max(2.min(states.len())),
        None => states.len(),
    };
    dynamics::control::Reference {
        time: states.time[..n].to_vec(),
        q: states.q[..n].to_vec(),
        v: states.v[..n].to_vec(),
        a: states.a[..n].to_vec(),
    }
}

/// A tracked simulation needs a motion: at least two samples.
fn check_motion(states: &States) -> Result<(), Error> {
    if states.len() < 2 {
        return Err(Error::Invalid(format!(
            "the take has {} frame(s): a simulation needs a motion of at least two frames to \
             track (a one-frame take is a pose; `articula id` gives its static load)",
            states.len()
        )));
    }
    Ok(())
}

/// What `articula simulate` prints.
#[derive(Debug, Clone)]
pub struct SimSummary {
    pub result: dynamics::simulate::SimResult,
}

impl SimSummary {
    /// Keys: rms_error_rad, max_error_rad, steps, integrator, dt (and per-coordinate detail).
    pub fn json(&self) -> serde_json::Value {
        self.result.summary_json()
    }

    pub fn text(&self) -> String {
        let r = &self.result;
        let mut s = format!(
            "{} at dt {} s: {} steps, tracking error RMS {:.3e} rad, max {:.3e} rad \
             (joint angles, root excluded)\n",
            r.integrator,
            r.dt,
            r.steps,
            r.rms_error_rad(),
            r.max_error_rad()
        );
        if r.root_nv > 0 {
            s.push_str(
                "root residual actuator (non-physical: the force the 6 root coordinates need), \
                 RMS / max:\n",
            );
            for k in 0..r.root_nv {
                s.push_str(&format!(
                    "  {:<28} {:>12.3} {:>12.3}\n",
                    r.names[k], r.root_residual_rms[k], r.root_residual_max[k]
                ));
            }
        }
        s
    }
}

/// `articula simulate`: computed-torque tracking of the take; optionally writes
/// `time`, `q:<coord>`, `v:<coord>`, `tau:<coord>`, `err:<coord>` per recorded row (SI).
pub fn simulate(
    take: &Take,
    settings: &SimSettings,
    output: Option<&Path>,
) -> Result<SimSummary, Error> {
    check_motion(&take.states)?;
    let reference = reference(&take.states, settings.duration_s);
    let options = settings.options_for(&take.model)?;
    let result = dynamics::simulate::simulate(&take.model, &reference, &options)?;
    if let Some(path) = output {
        super::table::simulation_table(&take.model, &result).write_csv(path)?;
    }
    Ok(SimSummary { result })
}

/// Computed-torque tracking of any model's states (a take's or a robot's motion), whole
/// length, reporting progress (0‥1) to `keep_going` and stopping with an error
/// (`cancelled`) when it returns false (`dynamics::simulate::simulate_with`).
pub fn simulate_states(
    model: &crate::model::Model,
    states: &States,
    settings: &SimSettings,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<SimSummary, Error> {
    check_motion(states)?;
    let reference = reference(states, settings.duration_s);
    let options = settings.options_for(model)?;
    let result = dynamics::simulate::simulate_with(model, &reference, &options, keep_going)?;
    Ok(SimSummary { result })
}

/// What `articula bench` prints.
#[derive(Debug, Clone)]
pub struct Bench {
    pub result: dynamics::bench::BenchResult,
    pub model: String,
}

impl Bench {
    /// Keys: nv, rnea_ns, crba_ns, aba_ns, rk4_step_ns.
    pub fn json(&self) -> serde_json::Value {
        let r = &self.result;
        serde_json::json!({
            "nv": r.nv,
            "rnea_ns": r.rnea_ns,
            "crba_ns": r.crba_ns,
            "aba_ns": r.aba_ns,
            "rk4_step_ns": r.rk4_step_ns,
        })
    }

    pub fn text(&self) -> String {
        let r = &self.result;
        format!(
            "{} (nv {}), ns per call, median of batches:\n  rnea      {:>12.0}\n  crba      \
             {:>12.0}\n  aba       {:>12.0}\n  rk4 step  {:>12.0}\n",
            self.model, r.nv, r.rnea_ns, r.crba_ns, r.aba_ns, r.rk4_step_ns
        )
    }
}

/// `articula bench`: the median of 7 batches.
pub fn bench(model: &Model) -> Result<Bench, Error> {
    bench_batches(model, 7)
}

/// `articula bench --batches N`: the median of `batches` batches (more batches ride out a busy
/// machine better).
pub fn bench_batches(model: &Model, batches: usize) -> Result<Bench, Error> {
    Ok(Bench {
        result: dynamics::bench::time_algorithms(model, batches)?,
        model: model.name.clone(),
    })
}

/// One row of the speed/accuracy table.
#[derive(Debug, Clone, PartialEq)]
pub struct TradeoffRow {
    pub joints: JointModel,
    pub integrator: String,
    pub dt: f64,
    /// Wall time per simulated second (s/s); infinite when the run diverged.
    pub wall_per_sim_s: f64,
    /// Largest joint-angle deviation at the end from the fine-step reference run (rad).
    pub deviation_rad: f64,
    /// RMS tracking error against the capture (rad, joint angles).
    pub tracking_rms_rad: f64,
    /// Relative energy drift of a passive run (τ = 0, no gravity) from the take's first state.
    pub energy_drift: f64,
    /// On the Pareto front of (wall time, deviation).
    pub pareto: bool,
    /// Why the run failed, if it did.
    pub failure: Option<String>,
}

/// The table `articula tradeoff` prints.
#[derive(Debug, Clone)]
pub struct Tradeoff {
    pub rows: Vec<TradeoffRow>,
    pub duration_s: f64,
    pub reference: String,
}

/// Integrators and steps `tradeoff` measures.
pub const TRADEOFF_INTEGRATORS: [&str; 4] = ["euler", "semi-implicit", "rk4", "dopri5:1e-6"];
pub const TRADEOFF_STEPS: [f64; 5] = [0.0005, 0.001, 0.002, 0.005, 0.01];
/// The fine-step reference every row is compared with.
pub const TRADEOFF_REFERENCE: (&str, f64) = ("rk4", 0.0001);

/// `articula tradeoff`: every integrator × step × joint model tracking the first `duration_s`
/// of the take (Kp 400, Kv 40), timed, and compared with a fine-step RK4 run of the same model.
pub fn tradeoff(path: &Path, opts: &TakeOptions, duration_s: f64) -> Result<Tradeoff, Error> {
    tradeoff_grid(
        path,
        opts,
        duration_s,
        &TRADEOFF_INTEGRATORS,
        &TRADEOFF_STEPS,
    )
}

/// [`tradeoff`] over a chosen grid.
pub fn tradeoff_grid(
    path: &Path,
    opts: &TakeOptions,
    duration_s: f64,
    integrators: &[&str],
    steps: &[f64],
) -> Result<Tradeoff, Error> {
    let mut rows = vec![];
    for joints in [JointModel::Euler, JointModel::Ball] {
        let mut o = opts.clone();
        o.joints = joints;
        let take = load_take(path, &o)?;
        let reference = reference(&take.states, Some(duration_s));
        let run =
            |integrator: &str, dt: f64| -> Result<(dynamics::simulate::SimResult, f64), Error> {
                let s = SimSettings::parse(
                    integrator,
                    dt,
                    &PerJoint::all(400.0),
                    &PerJoint::all(40.0),
                    0.0,
                    None,
                )?;
                let start = std::time::Instant::now();
                let r = dynamics::simulate::simulate(&take.model, &reference, &s.options)?;
                Ok((r, start.elapsed().as_secs_f64()))
            };
        let (fine, _) = run(TRADEOFF_REFERENCE.0, TRADEOFF_REFERENCE.1)?;
        let fine_end = fine.q.last().cloned().unwrap_or_default();
        let sim_s = reference.time.last().copied().unwrap_or(0.0) - reference.time[0];
        for integ in integrators {
            for &dt in steps {
                let mut row = TradeoffRow {
                    joints,
                    integrator: integ.to_string(),
                    dt,
                    wall_per_sim_s: f64::INFINITY,
                    deviation_rad: f64::INFINITY,
                    tracking_rms_rad: f64::INFINITY,
                    energy_drift: f64::INFINITY,
                    pareto: false,
                    failure: None,
                };
                match run(integ, dt) {
                    Ok((r, wall)) => {
                        row.wall_per_sim_s = wall / sim_s.max(1e-12);
                        row.tracking_rms_rad = r.rms_error_rad();
                        let end = r.q.last().cloned().unwrap_or_default();
                        row.deviation_rad = angle_deviation(&take.model, &fine_end, &end);
                    }
                    Err(e) => row.failure = Some(e.to_string()),
                }
                row.energy_drift =
                    passive_energy_drift(&take.model, &take.states, integ, dt, sim_s)
                        .unwrap_or(f64::INFINITY);
                rows.push(row);
            }
        }
    }
    mark_pareto(&mut rows);
    Ok(Tradeoff {
        rows,
        duration_s,
        reference: format!("{} at dt {} s", TRADEOFF_REFERENCE.0, TRADEOFF_REFERENCE.1),
    })
}

/// Largest |q1 ⊖ q0| over the angular coordinates outside the root (rad).
fn angle_deviation(model: &Model, q0: &[f64], q1: &[f64]) -> f64 {
    if q0.len() != model.nq || q1.len() != model.nq {
        return f64::INFINITY;
    }
    let mut d = vec![0.0; model.nv];
    model.difference(q0, q1, &mut d);
    let root = dynamics::simulate::floating_root_nv(model);
    let mut worst: f64 = 0.0;
    for i in 1..model.nbodies() {
        if matches!(model.joints[i], JointKind::Prismatic { .. }) {
            continue;
        }
        let iv = model.idx_v[i];
        for k in 0..model.joints[i].nv() {
            let j = iv + k;
            // linear components of a free joint are lengths, not angles
            let linear = matches!(model.joints[i], JointKind::Free) && k < 3;
            if j >= root && !linear {
                worst = worst.max(d[j].abs());
            }
        }
    }
    worst
}

/// Relative change of kinetic energy of a passive run (τ = 0, no gravity, no damping) started
/// from the take's first state with the take's velocities, over `duration_s`.
pub fn passive_energy_drift(
    model: &Model,
    states: &States,
    integrator: &str,
    dt: f64,
    duration_s: f64,
) -> Result<f64, Error> {
    let mut m = model.clone();
    m.gravity = nalgebra::Vector3::zeros();
    m.damping.iter_mut().for_each(|b| *b = 0.0);
    let integ: dynamics::integrate::Integrator = parse_flag("integrator", integrator)?;
    let mut stepper = dynamics::integrate::Stepper::new(&m, integ);
    let mut ws = Workspace::new(&m);
    let mut ws_e = Workspace::new(&m);
    let (mut q, mut v) = (states.q[0].clone(), states.v[0].clone());
    let tau = vec![0.0; m.nv];
    let e0 = dynamics::kinetic_energy(&m, &mut ws_e, &q, &v);
    let steps = (duration_s / dt).round().max(1.0) as usize;
    let mut f = |_t: f64, q: &[f64], v: &[f64], a: &mut [f64]| -> Result<(), Error> {
        let acc = dynamics::aba(&m, &mut ws, q, v, &tau, None)?;
        a.copy_from_slice(acc.as_slice());
        Ok(())
    };
    for n in 0..steps {
        stepper.step(&m, n as f64 * dt, dt, &mut q, &mut v, &mut f)?;
    }
    let e1 = dynamics::kinetic_energy(&m, &mut ws_e, &q, &v);
    Ok(((e1 - e0) / e0.max(1e-12)).abs())
}

/// Marks the rows no other row beats on both wall time and deviation.
fn mark_pareto(rows: &mut [TradeoffRow]) {
    let pts: Vec<(f64, f64, bool)> = rows
        .iter()
        .map(|r| (r.wall_per_sim_s, r.deviation_rad, r.failure.is_none()))
        .collect();
    for (i, r) in rows.iter_mut().enumerate() {
        let (ti, ei, ok) = pts[i];
        r.pareto = ok
            && !pts.iter().enumerate().any(|(j, &(tj, ej, okj))| {
                j != i && okj && tj <= ti && ej <= ei && (tj < ti || ej < ei)
            });
    }
}

impl Tradeoff {
    /// The CSV header (`report::columns`' scheme; units in the sidecar: s, s/s, rad, 1).
    pub fn header() -> Vec<String> {
        [
            "joints",
            "integrator",
            "dt",
            "wall_per_sim",
            "deviation",
            "rms:err",
            "energy_drift",
            "pareto",
        ]
        .map(String::from)
        .to_vec()
    }

    pub fn text(&self) -> String {
        let mut s = format!(
            "speed/accuracy over the first {} s (deviation: largest joint-angle difference at \
             the end from {}; energy drift: passive run, τ = 0, no gravity)\n",
            self.duration_s, self.reference
        );
        s.push_str(&format!(
            "{:<6} {:<14} {:>8} {:>14} {:>14} {:>14} {:>12}  pareto\n",
            "joints",
            "integrator",
            "dt (s)",
            "wall s/sim s",
            "deviation rad",
            "tracking rad",
            "energy drift"
        ));
        for r in &self.rows {
            if let Some(f) = &r.failure {
                s.push_str(&format!(
                    "{:<6} {:<14} {:>8} failed: {}\n",
                    r.joints.to_string(),
                    r.integrator,
                    r.dt,
                    f.lines().next().unwrap_or("")
                ));
                continue;
            }
            s.push_str(&format!(
                "{:<6} {:<14} {:>8} {:>14.4e} {:>14.3e} {:>14.3e} {:>12.3e}  {}\n",
                r.joints.to_string(),
                r.integrator,
                r.dt,
                r.wall_per_sim_s,
                r.deviation_rad,
                r.tracking_rms_rad,
                r.energy_drift,
                if r.pareto { "*" } else { "" }
            ));
        }
        s
    }

    /// Writes the table as CSV through the one CSV writer ([`Tradeoff::header`]; failed runs:
    /// infinite numbers, `pareto` 0).
    pub fn write_csv(&self, path: &Path) -> Result<(), Error> {
        let mut buf = crate::io::shortest::Shortest::new();
        let mut num = |x: f64| buf.format(x).to_string();
        let rows: Vec<Vec<String>> = (self.rows.iter())
            .map(|r| {
                vec![
                    r.joints.to_string(),
                    r.integrator.clone(),
                    num(r.dt),
                    num(r.wall_per_sim_s),
                    num(r.deviation_rad),
                    num(r.tracking_rms_rad),
                    num(r.energy_drift),
                    u8::from(r.pareto).to_string(),
                ]
            })
            .collect();
        crate::report::csv::write_table(path, &Self::header(), &rows)
    }
}
