//! Criterion benches of the dynamics core: rnea, crba, aba, forward dynamics by Cholesky and
//! one RK4 step, on a 7-DoF arm (like `data/arm7.urdf`), a 29-DoF humanoid-like tree and a
//! 96-DoF euler-model avatar; plus a 1-minute 120 fps take (7200 frames) through RNEA on the
//! avatar. Random states from SplitMix64 (fixed seed), so runs compare.
//!
//! `cargo bench --bench dynamics -- --warm-up-time 1 --measurement-time 2`

use articula::dynamics::samples::{
    SplitMix64, arm7, euler_avatar, humanoid, random_configuration, random_vector,
};
use articula::dynamics::{
    Integrator, Stepper, Workspace, aba, crba, forward_dynamics_cholesky, rnea,
};
use articula::model::Model;
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use std::hint::black_box;

/// A random state, the euler avatar's angles kept within ±0.4 π of zero (away from gimbal
/// lock).
fn state(model: &Model, seed: u64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut rng = SplitMix64(seed);
    let mut q = vec![0.0; model.nq];
    random_configuration(model, &mut rng, &mut q);
    if model.name == "euler_avatar" {
        q.iter_mut().for_each(|x| *x *= 0.4);
    }
    let (mut v, mut a) = (vec![0.0; model.nv], vec![0.0; model.nv]);
    random_vector(&mut rng, 1.0, &mut v);
    random_vector(&mut rng, 1.0, &mut a);
    (q, v, a)
}

fn algorithms(c: &mut Criterion) {
    let models = [arm7(), humanoid(false), euler_avatar()];
    let mut group = c.benchmark_group("dynamics");
    for model in &models {
        let id = |what: &str| BenchmarkId::new(what, format!("{} ({} dof)", model.name, model.nv));
        let (q, v, a) = state(model, 7);
        let mut ws = Workspace::new(model);
        let tau = rnea(model, &mut ws, &q, &v, &a, None).as_slice().to_vec();
        group.bench_function(id("rnea"), |b| {
            b.iter(|| black_box(rnea(model, &mut ws, black_box(&q), &v, &a, None)[0]))
        });
        group.bench_function(id("crba"), |b| {
            b.iter(|| black_box(crba(model, &mut ws, black_box(&q))[(0, 0)]))
        });
        group.bench_function(id("aba"), |b| {
            b.iter(|| black_box(aba(model, &mut ws, black_box(&q), &v, &tau, None).unwrap()[0]))
        });
        group.bench_function(id("fd_cholesky"), |b| {
            b.iter(|| {
                black_box(
                    forward_dynamics_cholesky(model, &mut ws, black_box(&q), &v, &tau, None)
                        .unwrap()[0],
                )
            })
        });
        let mut stepper = Stepper::new(model, Integrator::Rk4);
        let (mut qs, mut vs) = (q.clone(), v.clone());
        group.bench_function(id("rk4_step"), |b| {
            b.iter(|| {
                qs.copy_from_slice(&q);
                vs.copy_from_slice(&v);
                let mut f = |_t: f64, q: &[f64], v: &[f64], acc: &mut [f64]| {
                    acc.copy_from_slice(aba(model, &mut ws, q, v, &tau, None)?.as_slice());
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
    // 7200 frames (one minute at 120 fps) of the 96-DoF avatar
    let model = euler_avatar();
    let frames: Vec<_> = (0..7200).map(|k| state(&model, k)).collect();
    let mut ws = Workspace::new(&model);
    let mut group = c.benchmark_group("take");
    group.sample_size(10);
    group.bench_function("rnea 7200 frames euler_avatar (96 dof)", |b| {
        b.iter(|| {
            let mut s = 0.0;
            for (q, v, a) in &frames {
                s += rnea(&model, &mut ws, q, v, a, None)[0];
            }
            black_box(s)
        })
    });
    group.finish();
}

criterion_group! {
    name = benches;
    // no plots: the machines this runs on may have no fonts for criterion's plotters backend
    config = Criterion::default().without_plots();
    targets = algorithms, take_through_rnea
}
criterion_main!(benches);
