//! Criterion benches of the dynamics core on the named models: rnea, crba, aba, forward
//! dynamics by Cholesky and one RK4 step on the 7-DoF arm `data/arm7.urdf`, the 29-DoF URDF
//! humanoid `data/humanoid.urdf` (both fixed base, gravity −9.81 z) and the demo take
//! `data/demo_walk.bvh` (euler joint model, 66 DoF); with `ARTICULA_REAL_TAKES` set, also CMU
//! 01_01 from that folder (`cmu_01_01.bvh`, euler, 96 DoF; read in place, never copied). Then
//! every frame of a take through RNEA: the bare loop over the take's own q, v, a (what the
//! 50 ms target is about) and `pipeline::inverse_dynamics` (that loop plus one output row per
//! frame, what `articula id` runs before writing), and the bare loop over 7,200 frames (one
//! minute at 120 fps: the take's frames cycled). States for the per-call benches: 16 random
//! states as `articula bench` draws them (SplitMix64, fixed seed), cycled.
//!
//! `cargo bench --bench dynamics` (about 3 minutes with the real take); a subset:
//! `cargo bench --bench dynamics -- rnea`.

use articula::dynamics::samples::{SplitMix64, random_configuration, random_vector};
use articula::dynamics::{
    Integrator, Stepper, Workspace, aba, crba, forward_dynamics_cholesky, rnea,
};
use articula::model::Model;
use articula::pipeline::{self, Job, ModelSource, TakeOptions};
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("data")
        .join(name)
}

/// The named models: (label, model, the take's job when it is a take).
fn models() -> Vec<(String, Model, Option<Job>)> {
    let opts = TakeOptions::default();
    let mut out = vec![];
    for urdf in ["arm7", "humanoid"] {
        let src = ModelSource::Urdf(data(&format!("{urdf}.urdf")), Default::default());
        let m = pipeline::load_model(&src, &opts).expect("URDF");
        out.push((urdf.to_string(), m, None));
    }
    let mut takes = vec![("demo_walk".to_string(), data("demo_walk.bvh"))];
    if let Some(dir) = std::env::var_os("ARTICULA_REAL_TAKES") {
        takes.push(("cmu_01_01".into(), PathBuf::from(dir).join("cmu_01_01.bvh")));
    }
    for (name, path) in takes {
        let job = pipeline::load_source(&ModelSource::Take(path), None, &opts).expect("take");
        out.push((name, job.model.clone(), Some(job)));
    }
    out
}

/// 16 random states (q, v, a) as `articula bench` draws them.
fn states(model: &Model) -> Vec<(Vec<f64>, Vec<f64>, Vec<f64>)> {
    let mut rng = SplitMix64(42);
    (0..16)
        .map(|_| {
            let mut q = vec![0.0; model.nq];
            let (mut v, mut a) = (vec![0.0; model.nv], vec![0.0; model.nv]);
            random_configuration(model, &mut rng, &mut q);
            random_vector(&mut rng, 1.0, &mut v);
            random_vector(&mut rng, 1.0, &mut a);
            (q, v, a)
        })
        .collect()
}

fn algorithms(c: &mut Criterion) {
    let mut group = c.benchmark_group("dynamics");
    group
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(1))
        .sample_size(20);
    for (name, model, _) in &models() {
        let id = |what: &str| BenchmarkId::new(what, format!("{name} ({} dof)", model.nv));
        let st = states(model);
        let mut ws = Workspace::new(model);
        let zero = vec![0.0; model.nv];
        let mut k = 0;
        let mut next = || {
            k = (k + 1) % st.len();
            &st[k]
        };
        group.bench_function(id("rnea"), |b| {
            b.iter(|| {
                let (q, v, a) = next();
                black_box(rnea(model, &mut ws, q, v, a, None)[0])
            })
        });
        group.bench_function(id("crba"), |b| {
            b.iter(|| black_box(crba(model, &mut ws, &next().0)[(0, 0)]))
        });
        group.bench_function(id("aba"), |b| {
            b.iter(|| {
                let (q, v, _) = next();
                black_box(aba(model, &mut ws, q, v, &zero, None).unwrap()[0])
            })
        });
        group.bench_function(id("fd_cholesky"), |b| {
            b.iter(|| {
                let (q, v, _) = next();
                black_box(forward_dynamics_cholesky(model, &mut ws, q, v, &zero, None).unwrap()[0])
            })
        });
        let mut stepper = Stepper::new(model, Integrator::Rk4);
        let (mut qs, mut vs) = (st[0].0.clone(), st[0].1.clone());
        group.bench_function(id("rk4_step"), |b| {
            b.iter(|| {
                let (q, v, _) = next();
                qs.copy_from_slice(q);
                vs.copy_from_slice(v);
                let mut f = |_t: f64, q: &[f64], v: &[f64], acc: &mut [f64]| {
                    acc.copy_from_slice(aba(model, &mut ws, q, v, &zero, None)?.as_slice());
                    Ok(())
                };
                stepper
                    .step(model, 0.0, 1e-3, &mut qs, &mut vs, &mut f)
                    .unwrap();
                black_box(qs[0])
            })
        });
    }
    group.finish();
}

fn take_through_rnea(c: &mut Criterion) {
    let mut group = c.benchmark_group("take");
    group
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3))
        .sample_size(10);
    for (name, model, job) in &models() {
        let Some(job) = job else { continue };
        let s = &job.states;
        let label = format!("{name} ({} frames, {} dof)", s.len(), model.nv);
        let mut ws = Workspace::new(model);
        group.bench_function(BenchmarkId::new("rnea every frame", &label), |b| {
            b.iter(|| {
                let mut sum = 0.0;
                for k in 0..s.len() {
                    sum += rnea(model, &mut ws, &s.q[k], &s.v[k], &s.a[k], None)[0];
                }
                black_box(sum)
            })
        });
        group.bench_function(
            BenchmarkId::new("pipeline::inverse_dynamics", &label),
            |b| b.iter(|| black_box(pipeline::inverse_dynamics(model, s).tau.len())),
        );
        // the target's size: one minute at 120 fps, the take's own frames cycled
        let label = format!("{name} (7200 frames cycled, {} dof)", model.nv);
        group.bench_function(BenchmarkId::new("rnea every frame", &label), |b| {
            b.iter(|| {
                let mut sum = 0.0;
                for f in 0..7200 {
                    let k = f % s.len();
                    sum += rnea(model, &mut ws, &s.q[k], &s.v[k], &s.a[k], None)[0];
                }
                black_box(sum)
            })
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    // no plots: the machines this runs on may have no fonts for criterion's plotters backend
    config = Criterion::default().without_plots();
    targets = algorithms, take_through_rnea
}
criterion_main!(benches);
