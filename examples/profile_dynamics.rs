//! A fixed amount of work for a profiler (`perf record`, `valgrind --tool=callgrind`): N calls
//! of one algorithm at 16 random states (as `articula bench`), or RNEA over every frame of a
//! take's own states. Prints nothing but a checksum; time it with the profiler, not with this.
//!
//! Run: `cargo run --release --example profile_dynamics -- MODEL ALGORITHM [N] [--floating]`,
//! MODEL a BVH take (euler model, default options) or a URDF (`.urdf`, fixed base, or a free
//! joint at the root with `--floating`), ALGORITHM one of `rnea`, `crba`, `aba`, `rk4` (one
//! RK4 step of 1 ms under ABA with τ = 0, as `articula bench` times it), `take` (a take only:
//! RNEA over all its frames, N times). Instructions per call: the difference of two runs with
//! different N under `valgrind --tool=callgrind`, over the difference of N.

use articula::dynamics::integrate::{Integrator, Stepper};
use articula::dynamics::samples::{SplitMix64, random_configuration, random_vector};
use articula::dynamics::{Workspace, aba, crba, rnea};
use articula::model::urdf::UrdfOptions;
use articula::pipeline::{self, ModelSource, TakeOptions};
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let floating = args.iter().any(|a| a == "--floating");
    args.retain(|a| a != "--floating");
    let [path, what, rest @ ..] = &args[..] else {
        return Err("usage: profile_dynamics MODEL rnea|crba|aba|rk4|take [N] [--floating]".into());
    };
    let n: usize = rest.first().map_or(Ok(10_000), |s| s.parse())?;
    let path = PathBuf::from(path);
    let src = if path.extension().is_some_and(|e| e == "urdf") {
        let options = UrdfOptions {
            floating,
            ..Default::default()
        };
        ModelSource::Urdf(path, options)
    } else {
        ModelSource::Take(path)
    };
    let job = match (&src, what.as_str()) {
        (ModelSource::Take(_), "take") => {
            Some(pipeline::load_source(&src, None, &TakeOptions::default())?)
        }
        _ => None,
    };
    let model = match &job {
        Some(j) => j.model.clone(),
        None => pipeline::load_model(&src, &TakeOptions::default())?,
    };
    let (nq, nv) = (model.nq, model.nv);
    let mut rng = SplitMix64(42);
    let states: Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> = (0..16)
        .map(|_| {
            let (mut q, mut v, mut a) = (vec![0.0; nq], vec![0.0; nv], vec![0.0; nv]);
            random_configuration(&model, &mut rng, &mut q);
            random_vector(&mut rng, 1.0, &mut v);
            random_vector(&mut rng, 1.0, &mut a);
            (q, v, a)
        })
        .collect();
    let zero = vec![0.0; nv];
    let mut ws = Workspace::new(&model);
    let mut stepper = Stepper::new(&model, Integrator::Rk4);
    let (mut qs, mut vs) = (vec![0.0; nq], vec![0.0; nv]);
    let mut sum = 0.0;
    for k in 0..n {
        let (q, v, a) = &states[k % states.len()];
        sum += match what.as_str() {
            "rnea" => rnea(&model, &mut ws, q, v, a, None)[0],
            "crba" => crba(&model, &mut ws, q)[(0, 0)],
            "aba" => aba(&model, &mut ws, q, v, &zero, None)?[0],
            "rk4" => {
                qs.copy_from_slice(q);
                vs.copy_from_slice(v);
                let mut f = |_t: f64, q: &[f64], v: &[f64], acc: &mut [f64]| {
                    acc.copy_from_slice(aba(&model, &mut ws, q, v, &zero, None)?.as_slice());
                    Ok(())
                };
                stepper.step(&model, 0.0, 1e-3, &mut qs, &mut vs, &mut f)?;
                vs[0]
            }
            "take" => {
                let s = &job.as_ref().ok_or("`take` needs a BVH take")?.states;
                let mut t = 0.0;
                for f in 0..s.len() {
                    t += rnea(&model, &mut ws, &s.q[f], &s.v[f], &s.a[f], None)[0];
                }
                t
            }
            other => return Err(format!("unknown algorithm `{other}`").into()),
        };
    }
    println!("{sum}");
    Ok(())
}
