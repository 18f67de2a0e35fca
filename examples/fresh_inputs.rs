//! What issue 17's RK4 target (one step ≤ 4.1 ABA) would take: ABA's time when it reads
//! states that sit in memory (as `articula bench` times ABA: 16 random states, cycled) next to
//! its time when it reads states just written, as every stage of an integrator step gives it
//! (`q ⊕ Ω`, `v + h a` written, then read). Also the copy alone (written, but ABA reads the
//! states in place) and a chain (each call's input depending on the previous call's output, as
//! an RK4 step's stages do).
//!
//! Run: `cargo run --release --example fresh_inputs -- URDF [--floating] [ROUNDS]` (e.g. UR5
//! from example-robot-data). Prints ns per ABA call for each way, one round per line.

use articula::dynamics::samples::{SplitMix64, random_configuration, random_vector};
use articula::dynamics::{Workspace, aba};
use articula::model::urdf::UrdfOptions;
use articula::pipeline::{self, ModelSource, TakeOptions};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Instant;

/// Calls per timing.
const CALLS: usize = 200_000;

/// ns per call of `f(k)` over [`CALLS`] calls.
fn ns(mut f: impl FnMut(usize)) -> f64 {
    let t0 = Instant::now();
    for k in 0..CALLS {
        f(k);
    }
    t0.elapsed().as_secs_f64() / CALLS as f64 * 1e9
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args: Vec<String> = std::env::args().skip(1).collect();
    let floating = args.iter().any(|a| a == "--floating");
    args.retain(|a| a != "--floating");
    let [path, rest @ ..] = &args[..] else {
        return Err("usage: fresh_inputs URDF [--floating] [ROUNDS]".into());
    };
    let rounds: usize = rest.first().map_or(Ok(5), |s| s.parse())?;
    let options = UrdfOptions {
        floating,
        ..Default::default()
    };
    let src = ModelSource::Urdf(PathBuf::from(path), options);
    let model = pipeline::load_model(&src, &TakeOptions::default())?;
    let (nq, nv) = (model.nq, model.nv);
    // the states `articula bench` times ABA at, drawn in its order (`dynamics::bench`:
    // SplitMix64 seed 42, the 16 configurations, then the 16 velocities), τ = 0
    let mut rng = SplitMix64(42);
    let mut qs = vec![0.0; 16 * nq];
    for q in qs.chunks_mut(nq.max(1)) {
        random_configuration(&model, &mut rng, q);
    }
    let mut vs = vec![0.0; 16 * nv];
    random_vector(&mut rng, 1.0, &mut vs);
    let states: Vec<(Vec<f64>, Vec<f64>)> = (0..16)
        .map(|s| (qs[s * nq..][..nq].to_vec(), vs[s * nv..][..nv].to_vec()))
        .collect();
    let tau = vec![0.0; nv];
    let mut ws = Workspace::new(&model);
    let (mut q, mut v) = (vec![0.0; nq], vec![0.0; nv]);
    println!("ns per ABA call, {} (nq {nq}, nv {nv})", path);
    println!("in place   just written   copy alone   chained");
    for _ in 0..rounds {
        let in_place = ns(|k| {
            let (q, v) = &states[k % 16];
            black_box(aba(&model, &mut ws, q, v, &tau, None).map(|a| a[0]).ok());
        });
        let written = ns(|k| {
            let (q2, v2) = &states[k % 16];
            q.copy_from_slice(q2);
            v.copy_from_slice(v2);
            black_box(aba(&model, &mut ws, &q, &v, &tau, None).map(|a| a[0]).ok());
        });
        let copy_alone = ns(|k| {
            let (q2, v2) = &states[k % 16];
            q.copy_from_slice(q2);
            v.copy_from_slice(v2);
            black_box((&q, &v));
            black_box(aba(&model, &mut ws, q2, v2, &tau, None).map(|a| a[0]).ok());
        });
        // the next input waits for this output (a zero the compiler cannot see through)
        let mut e = 0.0;
        let chained = ns(|k| {
            let (q2, v2) = &states[k % 16];
            for (x, y) in q.iter_mut().zip(q2) {
                *x = y + e;
            }
            for (x, y) in v.iter_mut().zip(v2) {
                *x = y + e;
            }
            let a0 = aba(&model, &mut ws, &q, &v, &tau, None).map_or(0.0, |a| a[0]);
            e = (a0 * 0.0).min(0.0);
        });
        println!("{in_place:8.1}   {written:12.1}   {copy_alone:10.1}   {chained:7.1}");
    }
    Ok(())
}
