//! A massless helper root above a six-channel pelvis (the Bandai `joint_Root` layout) is folded
//! into the pelvis and welded: the model has the pelvis' coordinates only, the inverse dynamics
//! equals that of the same motion without the helper, and simulation (which needs a regular
//! D(q)) runs. Real Bandai takes: tests/model_real_takes.rs and the real-take suite.

mod common;

use articula::io::bvh;
use articula::io::generate::{WalkParams, walk};
use articula::pipeline::{self as sim, TakeOptions, inverse_dynamics, load_take};
use std::fmt::Write;

/// The generated walk, and the same motion under a `joint_Root` helper that travels forward
/// while the hips' position channels are reduced by as much (so every world pose is the same).
fn write_takes(dir: &std::path::Path) -> (std::path::PathBuf, std::path::PathBuf) {
    let plain = walk(&WalkParams {
        duration_s: 1.0,
        ..WalkParams::default()
    });
    let text = bvh::write_string(&plain);
    let plain_path = dir.join("walk.bvh");
    std::fs::write(&plain_path, &text).unwrap();

    let (hierarchy, motion) = text.split_once("MOTION").unwrap();
    let hierarchy = hierarchy.replacen(
        "ROOT Hips",
        "ROOT joint_Root\n{\n\tOFFSET 0 0 0\n\tCHANNELS 6 Xposition Yposition Zposition \
         Zrotation Xrotation Yrotation\n\tJOINT Hips",
        1,
    ) + "}\n";
    let mut out = hierarchy + "MOTION";
    let mut lines = motion.lines();
    out.push_str(lines.next().unwrap()); // the rest of the MOTION line
    out.push('\n');
    for _ in 0..2 {
        writeln!(out, "{}", lines.next().unwrap()).unwrap(); // Frames:, Frame Time:
    }
    assert_eq!(plain.joints[0].channels.len(), 6);
    let z = plain.joints[0]
        .channels
        .iter()
        .position(|c| c.name() == "Zposition")
        .unwrap();
    for (k, line) in lines.filter(|l| !l.trim().is_empty()).enumerate() {
        let mut values: Vec<f64> = line
            .split_whitespace()
            .map(|v| v.parse().unwrap())
            .collect();
        let travel = 0.3 * k as f64; // cm per frame
        values[z] -= travel;
        write!(out, "0 0 {travel} 0 0 0").unwrap();
        for v in values {
            write!(out, " {v}").unwrap();
        }
        out.push('\n');
    }
    let wrapped_path = dir.join("walk_under_root.bvh");
    std::fs::write(&wrapped_path, out).unwrap();
    (plain_path, wrapped_path)
}

#[test]
fn a_massless_helper_root_is_folded_into_the_hips_and_welded() {
    let dir = tempfile::tempdir().unwrap();
    let (plain_path, wrapped_path) = write_takes(dir.path());
    let opts = TakeOptions::default();
    let plain = load_take(&plain_path, &opts).unwrap();
    let wrapped = load_take(&wrapped_path, &opts).unwrap();
    assert!(plain.notes.is_empty());
    assert_eq!(wrapped.notes.len(), 1, "{:?}", wrapped.notes);
    assert!(wrapped.notes[0].contains("joint_Root"));
    assert_eq!(wrapped.model.nv, plain.model.nv);
    assert_eq!(wrapped.model.v_names, plain.model.v_names);

    let (a, b) = (
        inverse_dynamics(&plain.model, &plain.states),
        inverse_dynamics(&wrapped.model, &wrapped.states),
    );
    let mut worst: f64 = 0.0;
    for (ta, tb) in a.tau.iter().zip(&b.tau) {
        for (x, y) in ta.iter().zip(tb) {
            worst = worst.max((x - y).abs() / (1.0 + x.abs()));
        }
    }
    assert!(worst < 1e-6, "torques differ by {worst:e} (relative)");

    // D(q) is regular: a short tracked simulation runs and tracks
    let settings = rk4_settings(0.2);
    let summary = sim::simulate(&wrapped, &settings, None).unwrap();
    assert!(summary.result.max_error_rad() < 1e-2, "{}", summary.text());
}

#[test]
fn a_helper_root_given_mass_is_kept() {
    let dir = tempfile::tempdir().unwrap();
    let (plain_path, wrapped_path) = write_takes(dir.path());
    let mut opts = TakeOptions::default();
    opts.body.link_mass.insert("joint_Root".into(), 1.0);
    let plain = load_take(&plain_path, &TakeOptions::default()).unwrap();
    let wrapped = load_take(&wrapped_path, &opts).unwrap();
    assert!(wrapped.notes.is_empty());
    assert_eq!(wrapped.model.nv, plain.model.nv + 6);
}

#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn bandai_takes_simulate_after_folding() {
    let dir = common::real_takes()[0].parent().unwrap().to_path_buf();
    for name in [
        "dataset-1_walk_normal_001.bvh",
        "dataset-1_run_normal_001.bvh",
    ] {
        let take = load_take(&dir.join(name), &TakeOptions::default()).unwrap();
        let folded = take
            .notes
            .iter()
            .filter(|n| n.contains("was folded into `Hips`"));
        assert_eq!(folded.count(), 1, "{name}: {:?}", take.notes);
        let settings = rk4_settings(0.1);
        let summary = sim::simulate(&take, &settings, None)
            .unwrap_or_else(|e| panic!("{name}: simulation failed: {e}"));
        assert!(
            summary.result.max_error_rad() < 0.1,
            "{name}: {}",
            summary.text()
        );
    }
}

/// RK4 at 1 ms with the default gains (400, 40), exact masses, for `duration` s of the take.
fn rk4_settings(duration: f64) -> sim::SimSettings {
    let gains = |x| articula::pipeline::PerJoint::all(x);
    sim::SimSettings::parse(
        "rk4",
        0.001,
        &gains(400.0),
        &gains(40.0),
        0.0,
        Some(duration),
    )
    .unwrap()
}

/// What the file had is what comes out: positions of the folded take are the file's (the
/// helper's frame-0 position was written on every frame), and a BVH written from it keeps the
/// root motion on the helper, where the file had it.
#[test]
fn outputs_of_a_folded_take_give_the_root_its_motion_back() {
    let dir = tempfile::tempdir().unwrap();
    let (_, wrapped) = write_takes(dir.path());
    let opts = TakeOptions {
        smooth: Some(articula::motion::smooth::SmoothSpec::None),
        ..TakeOptions::default()
    };
    let take = load_take(&wrapped, &opts).unwrap();
    assert!(take.fold.is_some());
    let file = bvh::read(&wrapped).unwrap();
    let modes = &take.positions;
    // positions, m: every joint where the file's own channels put it
    let out = dir.path().join("p.csv");
    sim::export_positions(&take, &out).unwrap();
    let (_, cols) = articula::report::csv::read_columns(&out).unwrap();
    assert_eq!(cols[0].len(), file.frames);
    for (k, row) in (0..file.frames).map(|k| (k, cols.iter().map(move |c| c[k]))) {
        let row: Vec<f64> = row.collect();
        let p = bvh::bvh_world_positions(&file, modes, k);
        for (j, pj) in p.iter().enumerate() {
            for a in 0..3 {
                let x = row[1 + 3 * j + a];
                let want = pj[a] * take.scale_to_m;
                assert!(
                    (x - want).abs() < 1e-9,
                    "frame {k} joint {j}: {x} vs {want}"
                );
            }
        }
    }
    // a BVH written from it (no smoothing): the file's values
    let written = dir.path().join("w.bvh");
    sim::export_smoothed_bvh(&take, &written).unwrap();
    let w = bvh::read(&written).unwrap();
    assert_eq!(w.frames, file.frames);
    for (a, b) in w.motion.iter().zip(&file.motion) {
        assert!((a - b).abs() < 1e-6, "{a} vs {b}");
    }
}
