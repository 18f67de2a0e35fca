//! `articula bench`: wall time per call of the core algorithms on a model, at random states.
//! (The criterion benches in `benches/dynamics.rs` are the careful measurement; this is the
//! quick one a user runs on their own model.)

use super::integrate::{Integrator, Stepper};
use super::samples::{SplitMix64, random_configuration, random_vector};
use super::{Workspace, aba, crba, rnea};
use crate::error::Error;
use crate::model::Model;
use std::hint::black_box;
use std::time::Instant;

/// Nanoseconds per call (median over batches) and the model size.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct BenchResult {
    pub nv: usize,
    pub rnea_ns: f64,
    pub crba_ns: f64,
    pub aba_ns: f64,
    /// One RK4 step (four ABA evaluations and the configuration updates) at τ = 0, dt = 1 ms.
    pub rk4_step_ns: f64,
}

/// Number of random states cycled through by every batch.
const STATES: usize = 16;

/// Times `rnea`, `crba`, `aba` and one RK4 step on `model`: `batches` batches (at least 1) of
/// at least ~2 ms each over 16 random states (SplitMix64, seed 42), median per call.
///
/// # Errors
/// [`Error::Numerical`] if ABA finds the model singular at one of the random states.
pub fn time_algorithms(model: &Model, batches: usize) -> Result<BenchResult, Error> {
    let (nq, nv) = (model.nq, model.nv);
    let mut rng = SplitMix64(42);
    let mut q = vec![0.0; STATES * nq];
    let mut v = vec![0.0; STATES * nv];
    let mut a = vec![0.0; STATES * nv];
    for s in 0..STATES {
        random_configuration(model, &mut rng, &mut q[s * nq..(s + 1) * nq]);
    }
    random_vector(&mut rng, 1.0, &mut v);
    random_vector(&mut rng, 1.0, &mut a);
    // the range of state s in a buffer of n-vectors
    let st = |n: usize, s: usize| s * n..(s + 1) * n;
    let mut ws = Workspace::new(model);
    let tau = vec![0.0; nv];

    // one untimed pass: fails early on a singular state
    for s in 0..STATES {
        aba(model, &mut ws, &q[st(nq, s)], &v[st(nv, s)], &tau, None)?;
    }
    let rnea_ns = median_ns(batches, || {
        for s in 0..STATES {
            black_box(rnea(
                model,
                &mut ws,
                &q[st(nq, s)],
                &v[st(nv, s)],
                &a[st(nv, s)],
                None,
            ));
        }
        STATES
    });
    let crba_ns = median_ns(batches, || {
        for s in 0..STATES {
            black_box(crba(model, &mut ws, &q[st(nq, s)]));
        }
        STATES
    });
    let aba_ns = median_ns(batches, || {
        for s in 0..STATES {
            let _ = black_box(aba(
                model,
                &mut ws,
                &q[st(nq, s)],
                &v[st(nv, s)],
                &tau,
                None,
            ));
        }
        STATES
    });
    let mut stepper = Stepper::new(model, Integrator::Rk4);
    let (mut qs, mut vs) = (q[..nq].to_vec(), v[..nv].to_vec());
    let rk4_step_ns = median_ns(batches, || {
        for s in 0..STATES {
            qs.copy_from_slice(&q[st(nq, s)]);
            vs.copy_from_slice(&v[st(nv, s)]);
            let mut f = |_t: f64, q: &[f64], v: &[f64], acc: &mut [f64]| {
                acc.copy_from_slice(aba(model, &mut ws, q, v, &tau, None)?.as_slice());
                Ok(())
            };
            let _ = black_box(stepper.step(model, 0.0, 1e-3, &mut qs, &mut vs, &mut f));
        }
        STATES
    });
    Ok(BenchResult {
        nv,
        rnea_ns,
        crba_ns,
        aba_ns,
        rk4_step_ns,
    })
}

/// Nanoseconds per RNEA call (median over `batches` batches of at least ~2 ms each) at the
/// given states, cycled through in order: the inverse dynamics cost of one frame of a take
/// (`articula tradeoff --reduce` times each reduced model so, at the take's own states).
/// `q`, `v`, `a` hold one state per entry (`nq`, `nv`, `nv` long); none: 0.
pub fn time_rnea(model: &Model, q: &[&[f64]], v: &[&[f64]], a: &[&[f64]], batches: usize) -> f64 {
    if q.is_empty() {
        return 0.0;
    }
    let mut ws = Workspace::new(model);
    median_ns(batches, || {
        for ((q, v), a) in q.iter().zip(v).zip(a) {
            black_box(rnea(model, &mut ws, q, v, a, None));
        }
        q.len()
    })
}

/// Median over `batches` of the time per call of `f` (which returns how many calls it made),
/// each batch repeating `f` for at least 2 ms.
fn median_ns(batches: usize, mut f: impl FnMut() -> usize) -> f64 {
    let mut per_call: Vec<f64> = (0..batches.max(1))
        .map(|_| {
            let start = Instant::now();
            let mut calls = 0;
            while calls == 0 || start.elapsed().as_secs_f64() < 2e-3 {
                calls += f();
            }
            start.elapsed().as_secs_f64() * 1e9 / calls as f64
        })
        .collect();
    per_call.sort_by(f64::total_cmp);
    per_call[per_call.len() / 2]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::samples::{arm7, euler_avatar};

    #[test]
    fn times_every_algorithm() {
        // (wall-clock ratios are not asserted: the machine may be loaded)
        for (model, nv) in [(arm7(), 7), (euler_avatar(), 96)] {
            let r = time_algorithms(&model, 3).unwrap();
            assert_eq!(r.nv, nv);
            for ns in [r.rnea_ns, r.crba_ns, r.aba_ns, r.rk4_step_ns] {
                assert!(ns.is_finite() && ns > 0.0, "{r:?}");
            }
        }
    }

    #[test]
    fn a_singular_model_is_an_error_not_a_time() {
        // a massless chain: D = 0
        let mut model = arm7();
        model
            .inertia
            .iter_mut()
            .for_each(|i| *i = crate::spatial::SpatialInertia::ZERO);
        assert!(matches!(
            time_algorithms(&model, 1),
            Err(Error::Numerical(_))
        ));
    }
}
