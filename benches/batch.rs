//! Criterion bench of `articula batch` throughput: the same corpus of generated walks (eight
//! takes of 4 s at 120 fps, skeleton scales 0.9–1.2) through `batch … --force -- id` with
//! `--jobs 1` and `--jobs 2`; the throughput is takes per second, so the ratio of the two is
//! the speed-up from one core to two (issue 18 asks ≥ 1.8× on the shared takes; with
//! `ARTICULA_REAL_TAKES` set, the shared takes are benched too, read in place).
//!
//! `cargo bench --bench batch` (about a minute on 2 cores; more with the shared takes).

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::Duration;

const TAKES: usize = 8;

fn articula() -> Command {
    Command::new(env!("CARGO_BIN_EXE_articula"))
}

fn run(c: &mut Command) {
    let status = c.stdout(Stdio::null()).stderr(Stdio::null()).status();
    assert!(status.is_ok_and(|s| s.success()), "{c:?} failed");
}

/// Eight generated walks in `dir`.
fn corpus(dir: &Path) -> PathBuf {
    let takes = dir.join("takes");
    std::fs::create_dir_all(&takes).unwrap();
    for k in 0..TAKES {
        let scale = 0.9 + 0.3 * k as f64 / (TAKES - 1) as f64;
        run(articula()
            .args(["generate", "walk", "--scale", &scale.to_string(), "-o"])
            .arg(takes.join(format!("walk{k}.bvh"))));
    }
    takes
}

fn count_takes(dir: &Path) -> usize {
    std::fs::read_dir(dir)
        .map(|d| {
            d.flatten()
                .filter(|e| e.path().extension().is_some_and(|x| x == "bvh"))
                .count()
        })
        .unwrap_or(0)
}

fn bench_folder(c: &mut Criterion, name: &str, takes: &Path, out: &Path) {
    let mut g = c.benchmark_group(format!("batch/{name}"));
    g.sample_size(10).measurement_time(Duration::from_secs(20));
    g.throughput(Throughput::Elements(count_takes(takes) as u64));
    for jobs in [1, 2] {
        g.bench_with_input(BenchmarkId::new("jobs", jobs), &jobs, |b, &jobs| {
            b.iter(|| {
                let mut cmd = articula();
                cmd.arg("batch").arg(takes).arg("-o").arg(out);
                cmd.args(["--force", "--jobs", &jobs.to_string(), "--", "id"]);
                // exit 1: some take failed (a row of the summary, as in real use); 2: the
                // batch itself could not run, which would measure nothing
                let s = cmd.stdout(Stdio::null()).stderr(Stdio::null()).status();
                assert!(s.is_ok_and(|s| matches!(s.code(), Some(0 | 1))), "{cmd:?}");
            })
        });
    }
    g.finish();
}

fn batch(c: &mut Criterion) {
    let dir = tempfile::tempdir().unwrap();
    let takes = corpus(dir.path());
    bench_folder(c, "generated", &takes, &dir.path().join("out"));
    if let Some(shared) = std::env::var_os("ARTICULA_REAL_TAKES") {
        bench_folder(
            c,
            "shared",
            Path::new(&shared),
            &dir.path().join("out-shared"),
        );
    }
}

criterion_group! {
    name = benches;
    // no plots: the machines this runs on may have no fonts for criterion's plotters backend
    config = Criterion::default().without_plots();
    targets = batch
}
criterion_main!(benches);
