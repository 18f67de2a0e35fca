//! Criterion benches of the stages a take goes through in `articula id` (the keys of
//! `articula bench --stages`), one by one on the demo take `data/demo_walk.bvh` (480 frames,
//! euler model, 66 DoF, feet on the floor), each stage's own library call on the previous
//! stage's output: parse (`io::bvh::parse_bytes`), model (`take_from_bvh_with` stopped right
//! after the model is built), coordinates (`Trajectory::from_bvh`), unwrap
//! (`make_euler_triples_continuous` and the revolute turns), smooth (`unwrap_and_smooth` on
//! unwrapped q), derivatives, contact (`ground_reactions`) and inverse dynamics. The job
//! stage (copies) is left to `bench --stages`. Threads: all cores, or `RAYON_NUM_THREADS=1` for
//! the serial path.
//!
//! `cargo bench --bench stages` (about half a minute); a subset: `cargo bench --bench stages
//! -- smooth`.

use articula::io::bvh;
use articula::motion::smooth::SmoothSpec;
use articula::motion::take::Trajectory;
use articula::pipeline::{self, Contact, TakeOptions};
use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Duration;

fn stages(c: &mut Criterion) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/demo_walk.bvh");
    let text = std::fs::read(&path).expect("demo take");
    let opts = TakeOptions {
        contact: Contact::Feet,
        ..TakeOptions::default()
    };
    let take = pipeline::load_take(&path, &opts).expect("demo take loads");
    let (model, dt) = (&take.model, take.bvh.frame_time);
    let raw_q = Trajectory::from_bvh(&take.bvh, model, &take.map).q;
    let mut unwrapped = raw_q.clone();
    pipeline::make_euler_triples_continuous(&take.bvh, &take.map, &mut unwrapped);
    pipeline::unwrap_and_smooth(model, &mut unwrapped, dt, &SmoothSpec::None).unwrap();

    let mut g = c.benchmark_group("stages/demo_walk");
    g.bench_function("parse", |b| {
        b.iter(|| bvh::parse_bytes(black_box(&text), &path).unwrap())
    });
    g.bench_function("model", |b| {
        b.iter_batched(
            || (*take.bvh).clone(),
            |bvh| pipeline::take_from_bvh_with(&path, bvh, &opts, &mut |_| false),
            BatchSize::LargeInput,
        )
    });
    g.bench_function("coordinates", |b| {
        b.iter(|| Trajectory::from_bvh(&take.bvh, model, &take.map))
    });
    g.bench_function("unwrap", |b| {
        b.iter_batched(
            || raw_q.clone(),
            |mut q| {
                pipeline::make_euler_triples_continuous(&take.bvh, &take.map, &mut q);
                pipeline::unwrap_and_smooth(model, &mut q, dt, &SmoothSpec::None).unwrap();
                q
            },
            BatchSize::LargeInput,
        )
    });
    g.bench_function("smooth", |b| {
        b.iter_batched(
            || unwrapped.clone(),
            |mut q| {
                pipeline::unwrap_and_smooth(model, &mut q, dt, &take.smooth).unwrap();
                q
            },
            BatchSize::LargeInput,
        )
    });
    g.bench_function("derivatives", |b| {
        b.iter(|| pipeline::derivatives(model, &take.states.q, dt))
    });
    g.bench_function("contact", |b| {
        b.iter(|| pipeline::ground_reactions(&take).unwrap())
    });
    g.bench_function("inverse_dynamics", |b| {
        b.iter(|| pipeline::inverse_dynamics(model, &take.states))
    });
    g.finish();
}

criterion_group! {
    name = benches;
    // no plots: the machines this runs on may have no fonts for criterion's plotters backend
    config = Criterion::default()
        .without_plots()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(300))
        .measurement_time(Duration::from_secs(2));
    targets = stages
}
criterion_main!(benches);
