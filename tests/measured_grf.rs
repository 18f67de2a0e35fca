//! Measured ground reactions in (`articula id --grf FILE [--grf-offset S]`): inverse dynamics
//! with given loads is the estimate's own when the loads are the estimate's. Written out by
//! `export grf` (CSV: shortest round-trip numbers, so the same torques to the bit; OpenSim
//! `.mot`: 11 significant digits, the same torques within 1e-6 N·m) and read back, they give
//! the same joint torques as `id` with the estimate; shifted by one frame (`--grf-offset`),
//! they leave a larger residual at the root: a lab's forces out of step are detected.

use articula::report::csv::read_columns;
use assert_cmd::Command;
use std::path::{Path, PathBuf};

fn articula() -> Command {
    Command::cargo_bin("articula").expect("binary")
}

fn demo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/demo_walk.bvh")
}

fn run(args: &[&str], out: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    articula().args(args).arg("-o").arg(out).assert().success();
    read_columns(out).unwrap()
}

/// The largest |difference| over the joint torque columns.
fn compare(a: &(Vec<String>, Vec<Vec<f64>>), b: &(Vec<String>, Vec<Vec<f64>>)) -> f64 {
    assert_eq!(a.0, b.0);
    a.0.iter()
        .enumerate()
        .filter(|(_, h)| h.starts_with("tau:"))
        .flat_map(|(i, _)| a.1[i].iter().zip(&b.1[i]).map(|(x, y)| (x - y).abs()))
        .fold(0.0, f64::max)
}

fn residual_rms(t: &(Vec<String>, Vec<Vec<f64>>)) -> f64 {
    let cols: Vec<&Vec<f64>> =
        t.0.iter()
            .zip(&t.1)
            .filter(|(h, _)| ["residual:fx", "residual:fy", "residual:fz"].contains(&h.as_str()))
            .map(|(_, c)| c)
            .collect();
    let n = cols[0].len() as f64;
    (cols
        .iter()
        .flat_map(|c| c.iter())
        .map(|x| x * x)
        .sum::<f64>()
        / n)
        .sqrt()
}

#[test]
fn the_estimates_own_forces_read_back_give_the_same_torques() {
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| dir.path().join(n);
    let take = demo();
    let take = take.to_str().unwrap();
    let estimated = run(&["id", take], &p("est.csv"));
    articula()
        .args(["export", "grf", take, "-o"])
        .arg(p("grf.csv"))
        .assert()
        .success();
    articula()
        .args(["export", "grf", take, "-o"])
        .arg(p("grf.mot"))
        .assert()
        .success();

    let grf_csv = p("grf.csv");
    let from_csv = run(
        &["id", take, "--grf", grf_csv.to_str().unwrap()],
        &p("m1.csv"),
    );
    assert_eq!(compare(&estimated, &from_csv), 0.0);
    let grf_mot = p("grf.mot");
    let from_mot = run(
        &["id", take, "--grf", grf_mot.to_str().unwrap()],
        &p("m2.csv"),
    );
    let d = compare(&estimated, &from_mot);
    assert!(d < 1e-6, "{d} N·m");

    // one frame late: the torques change and the root is left more to carry
    let shifted = run(
        &[
            "id",
            take,
            "--grf",
            grf_csv.to_str().unwrap(),
            "--grf-offset",
            "0.008333333333333333",
        ],
        &p("m3.csv"),
    );
    assert!(compare(&estimated, &shifted) > 1.0);
    let (r0, r1) = (residual_rms(&from_csv), residual_rms(&shifted));
    // in step the feet carry all the force the motion needs (the estimate's loads give the
    // root no force); a frame off, tens of newtons are left to the root
    assert!(
        r0 < 1e-6 && r1 > 10.0,
        "residual {r0} N in step, {r1} N a frame off"
    );
}

#[test]
fn a_file_without_force_columns_or_with_unknown_feet_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.csv");
    std::fs::write(&bad, "time,x\n0,1\n").unwrap();
    articula()
        .arg("id")
        .arg(demo())
        .arg("--grf")
        .arg(&bad)
        .args(["-o", "-"])
        .assert()
        .failure()
        .stderr(predicates::str::contains("no ground force columns"));
    let odd = dir.path().join("odd.csv");
    std::fs::write(
        &odd,
        "time,grf:hand:x,grf:hand:y,grf:hand:z,cop:hand:x,cop:hand:y,cop:hand:z\n0,0,0,0,0,0,0\n",
    )
    .unwrap();
    articula()
        .arg("id")
        .arg(demo())
        .arg("--grf")
        .arg(&odd)
        .args(["-o", "-"])
        .assert()
        .failure()
        .stderr(predicates::str::contains("none of the take's feet"));
}
