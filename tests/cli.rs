//! End to end: the real `articula` binary, as a user runs it (assert_cmd).
//!
//! Every take here is made by the project (`articula generate walk`); the Pinocchio fixtures
//! give the robot cases an independent answer.

mod common;

use common::cli::{articula, walk};

use articula::report::csv::read_columns;
use predicates::prelude::*;
use std::path::Path;

fn column<'a>(h: &[String], c: &'a [Vec<f64>], name: &str) -> &'a [f64] {
    let i = h
        .iter()
        .position(|x| x == name)
        .unwrap_or_else(|| panic!("no column {name} in {h:?}"));
    &c[i]
}

#[test]
fn info_json_has_exactly_the_documented_keys() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 1.0);
    let out = articula()
        .arg("info")
        .arg(&take)
        .arg("--json")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let mut keys: Vec<&str> = v.as_object().unwrap().keys().map(|k| k.as_str()).collect();
    keys.sort();
    assert_eq!(
        keys,
        [
            "contact",
            "frame_time",
            "frames",
            "gravity",
            "human",
            "joints",
            "mass_kg",
            "notes",
            "nq",
            "nv",
            "scale_to_m",
            "segments",
            "segments_stature_m",
            "skeleton",
            "smooth",
            "stature_m",
            "unit",
            "up",
        ]
    );
    // the notes: what contact auto chose on this walk, and why; then each foot's contact model
    assert_eq!(v["contact"], "feet");
    let notes = v["notes"].as_array().unwrap();
    assert_eq!(notes.len(), 2, "{notes:?}");
    assert!(
        notes[1]
            .as_str()
            .unwrap()
            .starts_with("contact model per foot"),
        "{notes:?}"
    );
    assert!(
        notes[0]
            .as_str()
            .unwrap()
            .starts_with("contact auto: feet: the feet stand on a floor"),
        "{notes:?}"
    );
    assert_eq!(v["smooth"], "butterworth:6hz");
    // the segment masses: the regression, at the take's stature
    assert_eq!(v["segments"], "regression");
    assert_eq!(v["segments_stature_m"], v["stature_m"]);
    assert_eq!(v["frames"], 60);
    assert_eq!(v["up"], "y");
    assert!(
        (v["scale_to_m"].as_f64().unwrap() - 0.01).abs() < 1e-12,
        "{v}"
    );
    assert!((v["mass_kg"].as_f64().unwrap() - 75.0).abs() < 1e-9, "{v}");
    assert_eq!(v["gravity"][1].as_f64().unwrap(), -9.81);
    let stature = v["stature_m"].as_f64().unwrap();
    assert!((1.5..1.95).contains(&stature), "{stature}");
    // the human-readable form names the semantics chosen for the position channels
    let text = articula().arg("info").arg(&take).output().unwrap();
    let text = String::from_utf8(text.stdout).unwrap();
    assert!(text.contains("positions: "), "{text}");
    assert!(
        text.contains(&format!("Zatsiorsky–Seluyanov (1983) regression on body mass and stature (75 kg, stature {stature:.3} m)")),
        "{text}"
    );
    let json = |flag: &str| -> serde_json::Value {
        let out = articula()
            .arg("info")
            .arg(&take)
            .args(["--segments", flag, "--json"])
            .output()
            .unwrap();
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let v = json("fractions");
    assert_eq!(v["segments"], "fractions");
    assert_eq!(v["segments_stature_m"], serde_json::Value::Null);
}

#[test]
fn inverse_dynamics_of_a_take_has_one_column_per_coordinate_and_scales_with_mass() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 1.0);
    let run = |mass: &str, segments: &str, out: &str| {
        let p = dir.path().join(out);
        articula()
            .arg("id")
            .arg(&take)
            .args(["--mass", mass, "--segments", segments, "-o"])
            .arg(&p)
            .assert()
            .success();
        read_columns(&p).unwrap()
    };
    let (h, c) = run("60", "fractions", "t60.csv");
    let (h2, c2) = run("90", "fractions", "t90.csv");
    assert_eq!(h[0], "time");
    assert!(h.iter().any(|x| x == "tau:LeftLeg.Xrotation"), "{h:?}");
    assert!(h.iter().any(|x| x == "tau:Hips.Yposition"), "{h:?}");
    assert_eq!(h, h2);
    assert_eq!(c[0].len(), 60);
    // with de Leva's fractions every link mass scales with the body mass, so every torque
    // does too (same kinematics)
    let k60 = column(&h, &c, "tau:LeftLeg.Xrotation");
    let k90 = column(&h2, &c2, "tau:LeftLeg.Xrotation");
    let peak = k60.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(peak > 1.0, "knee torque peak {peak} N·m");
    for (a, b) in k60.iter().zip(k90) {
        assert!((b - a * 1.5).abs() <= 1e-9 * (1.0 + b.abs()), "{a} {b}");
    }
    // with the regression (the default) the 90 kg body is not the 60 kg one scaled
    let (h, c) = run("60", "regression", "r60.csv");
    let (h2, c2) = run("90", "regression", "r90.csv");
    let k60 = column(&h, &c, "tau:LeftLeg.Xrotation");
    let k90 = column(&h2, &c2, "tau:LeftLeg.Xrotation");
    let gap = k60
        .iter()
        .zip(k90)
        .map(|(a, b)| (b - a * 1.5).abs())
        .fold(0.0, f64::max);
    assert!(gap > 1e-3 * peak, "{gap} N·m");
}

#[test]
fn robot_inverse_dynamics_matches_pinocchio() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("tau.csv");
    articula()
        .arg("id")
        .arg("--urdf")
        .arg(common::repo("data/arm7.urdf"))
        .arg("--states")
        .arg(common::repo("tests/fixtures/pinocchio/arm7/states.csv"))
        .arg("-o")
        .arg(&out)
        .assert()
        .success();
    let (h, c) = read_columns(&out).unwrap();
    let (hp, cp) = read_columns(&common::repo("tests/fixtures/pinocchio/arm7/rnea.csv")).unwrap();
    for (j, name) in hp.iter().enumerate() {
        let ours = column(&h, &c, name);
        for (a, b) in ours.iter().zip(&cp[j]) {
            assert!(
                (a - b).abs() <= 1e-9 * (1.0 + b.abs()),
                "{name}: {a} vs {b}"
            );
        }
    }
}

#[test]
fn export_states_then_fd_of_id_gives_back_the_accelerations() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.5);
    let states = dir.path().join("s.csv");
    let tau = dir.path().join("t.csv");
    let acc = dir.path().join("a.csv");
    articula()
        .args(["export", "states"])
        .arg(&take)
        .arg("-o")
        .arg(&states)
        .assert()
        .success();
    // fd has no contact model: the torques that give the motion back are those without
    // ground reactions
    articula()
        .arg("id")
        .arg(&take)
        .args(["--contact", "none", "-o"])
        .arg(&tau)
        .assert()
        .success();
    articula()
        .arg("fd")
        .arg(&take)
        .arg("--states")
        .arg(&states)
        .arg("--torques")
        .arg(&tau)
        .arg("-o")
        .arg(&acc)
        .assert()
        .success();
    let (hs, cs) = read_columns(&states).unwrap();
    let (ha, ca) = read_columns(&acc).unwrap();
    let mut n = 0;
    for name in ha.iter().filter(|h| h.starts_with("a:")) {
        let want = column(&hs, &cs, name);
        let got = column(&ha, &ca, name);
        for (w, g) in want.iter().zip(got) {
            assert!(
                (w - g).abs() <= 1e-6 * (1.0 + w.abs()),
                "{name}: {w} vs {g}"
            );
        }
        n += 1;
    }
    assert!(n > 50, "{n} acceleration columns");
}

#[test]
fn mass_matrix_is_symmetric_row_major() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("m.csv");
    articula()
        .arg("mass-matrix")
        .arg("--dh")
        .arg(common::repo("data/puma560.toml"))
        .arg("--states")
        .arg(common::repo("tests/fixtures/rtb/puma560/states.csv"))
        .arg("-o")
        .arg(&out)
        .assert()
        .success();
    let (h, c) = read_columns(&out).unwrap();
    assert_eq!(h.len(), 1 + 36);
    for i in 0..6 {
        for j in 0..6 {
            let a = column(&h, &c, &format!("M:{i}:{j}"));
            let b = column(&h, &c, &format!("M:{j}:{i}"));
            assert_eq!(a, b);
        }
        assert!(
            column(&h, &c, &format!("M:{i}:{i}"))
                .iter()
                .all(|&d| d > 0.0)
        );
    }
}

#[test]
fn simulate_json_summary() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.3);
    let out = articula()
        .arg("simulate")
        .arg(&take)
        .args(["--dt", "0.002", "--json"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for k in [
        "rms_error_rad",
        "max_error_rad",
        "steps",
        "integrator",
        "dt",
    ] {
        assert!(v.get(k).is_some(), "{k} missing from {v}");
    }
    assert_eq!(v["integrator"], "rk4");
    assert_eq!(v["dt"], 0.002);
    // starting on the reference with exact model and feed-forward, the PD terms only mop up
    // the interpolation error: far below a degree
    assert!(v["max_error_rad"].as_f64().unwrap() < 0.01, "{v}");
}

/// `simulate -o` records, per step, q, q̇, τ and the tracking error of every coordinate; the
/// recorded q̇ is the derivative of the recorded q (central differences agree to O(dt²)).
#[test]
fn simulate_csv_records_q_v_tau_and_error() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.3);
    let csv = dir.path().join("sim.csv");
    let out = articula()
        .arg("simulate")
        .arg(&take)
        .args(["--dt", "0.002", "-o"])
        .arg(&csv)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (h, cols) = articula::report::csv::read_columns(&csv).unwrap();
    let col = |name: &str| {
        &cols[h
            .iter()
            .position(|x| x == name)
            .unwrap_or_else(|| panic!("{name} in {h:?}"))]
    };
    let c = "LeftLeg.Xrotation";
    for prefix in ["q:", "v:", "tau:", "err:"] {
        col(&format!("{prefix}{c}"));
    }
    let (t, q, v) = (col("time"), col(&format!("q:{c}")), col(&format!("v:{c}")));
    let mut worst: f64 = 0.0;
    for k in 1..t.len() - 1 {
        let fd = (q[k + 1] - q[k - 1]) / (t[k + 1] - t[k - 1]);
        worst = worst.max((fd - v[k]).abs());
    }
    let vmax = v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(vmax > 0.1 && worst < 0.02 * vmax, "worst {worst} of {vmax}");
}

/// A one-frame take is a pose: `simulate` says it needs a motion instead of "tracking" zero
/// steps; `id` gives the pose's static load.
#[test]
fn simulate_refuses_a_one_frame_take() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 1.0);
    let text = std::fs::read_to_string(&take).unwrap();
    let (head, motion) = text.split_once("MOTION").unwrap();
    let first = motion.lines().nth(3).unwrap();
    let one = dir.path().join("pose.bvh");
    std::fs::write(
        &one,
        format!("{head}MOTION\nFrames: 1\nFrame Time: 0.00833333\n{first}\n"),
    )
    .unwrap();
    let out = articula().arg("simulate").arg(&one).output().unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("needs a motion of at least two frames"),
        "{err}"
    );
    let out = articula()
        .arg("id")
        .arg(&one)
        .arg("-o")
        .arg(dir.path().join("t.csv"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Diagonal gains by joint: with the controller's masses 30 % off, stiffer knee gains shrink
/// the knee's tracking error (PD error dynamics: the error falls as the gains rise) and zero
/// knee gains let the knee drift, while a joint whose gains did not change tracks as before.
#[test]
fn simulate_takes_gains_per_joint() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.5);
    let run = |extra: &[&str]| -> std::collections::BTreeMap<String, f64> {
        let out = articula()
            .arg("simulate")
            .arg(&take)
            .args(["--dt", "0.002", "--mass-error", "0.3", "--json"])
            .args(extra)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        v["coordinates"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| {
                (
                    c["name"].as_str().unwrap().to_string(),
                    c["rms"].as_f64().unwrap(),
                )
            })
            .collect()
    };
    let base = run(&[]);
    let stiff = run(&["--kp", "400", "--kp", "LeftLeg=4000", "--kv", "LeftLeg=120"]);
    let limp = run(&["--kp", "LeftLeg=0", "--kv", "LeftLeg=0"]);
    // the same limp knee from a scene's [gains] tables (regression: --scene dropped them)
    let scene = dir.path().join("limp.toml");
    std::fs::write(
        &scene,
        format!(
            "takes = [{:?}]\n[gains]\nkp = {{ \"*\" = 400.0, LeftLeg = 0.0 }}\n\
             kv = {{ \"*\" = 40.0, LeftLeg = 0.0 }}\n",
            take.display().to_string()
        ),
    )
    .unwrap();
    let scene_arg = scene.display().to_string();
    let from_scene = run(&["--scene", &scene_arg]);
    let (knee, other) = ("LeftLeg.Xrotation", "RightLeg.Xrotation");
    assert!(base[knee] > 0.0);
    assert!(
        stiff[knee] < base[knee] / 4.0,
        "{} vs {}",
        stiff[knee],
        base[knee]
    );
    assert!(
        limp[knee] > base[knee] * 4.0,
        "{} vs {}",
        limp[knee],
        base[knee]
    );
    assert!(
        (from_scene[knee] - limp[knee]).abs() < 1e-9 * limp[knee],
        "scene {} vs flags {}",
        from_scene[knee],
        limp[knee]
    );
    for r in [&stiff, &limp] {
        assert!(
            (r[other] - base[other]).abs() < 0.05 * base[other],
            "{} vs {}",
            r[other],
            base[other]
        );
    }
    // a name that is no coordinate, and a negative gain, are refused with what was expected
    for (bad, says) in [
        ("Knee=5", "no coordinate of the model is named so"),
        ("LeftLeg=-5", "expected X or JOINT=X with X ≥ 0"),
    ] {
        let out = articula()
            .arg("simulate")
            .arg(&take)
            .args(["--kp", bad])
            .output()
            .unwrap();
        assert!(!out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(says), "{err}");
    }
}

#[test]
fn bench_json_keys() {
    let out = articula()
        .arg("bench")
        .arg("--urdf")
        .arg(common::repo("data/arm7.urdf"))
        .arg("--json")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["nv"], 7);
    for k in ["rnea_ns", "crba_ns", "aba_ns", "rk4_step_ns"] {
        assert!(v[k].as_f64().unwrap() > 0.0, "{k}: {v}");
    }
}

#[test]
fn bad_input_is_a_located_error_and_leaves_outputs_alone() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.bvh");
    std::fs::write(
        &bad,
        "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 3 Xrotation Yrotation Wrotation\n}\n",
    )
    .unwrap();
    let out = dir.path().join("t.csv");
    std::fs::write(&out, "keep me").unwrap();
    let o = articula()
        .arg("id")
        .arg(&bad)
        .arg("-o")
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("bad.bvh:5"), "{err}");
    assert!(err.contains("Wrotation"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "keep me");
}

#[test]
fn a_human_no_unit_fits_is_scaled_to_a_standard_stature_and_stature_always_wins() {
    // a character three times human size (5.2 m in cm): no unit puts it at 1.0–2.3 m
    let dir = tempfile::tempdir().unwrap();
    let take = dir.path().join("giant.bvh");
    articula()
        .args([
            "generate",
            "walk",
            "--fps",
            "60",
            "--duration",
            "0.5",
            "--scale",
            "3",
        ])
        .arg("-o")
        .arg(&take)
        .assert()
        .success();
    let o = articula()
        .arg("info")
        .arg(&take)
        .arg("--json")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(
        (v["stature_m"].as_f64().unwrap() - 1.75).abs() < 1e-9,
        "{v}"
    );
    assert_eq!(v["unit"], "stature");
    let notes = v["notes"].to_string();
    assert!(
        notes.contains("standard adult stature") && notes.contains("--stature"),
        "{notes}"
    );
    // an explicit unit is used as given, with a note
    let o = articula()
        .arg("info")
        .arg(&take)
        .args(["--unit", "m", "--json"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(v["notes"].to_string().contains("used as given"), "{v}");
    // a stature that is no height is an error that says what to give
    let o = articula()
        .arg("info")
        .arg(&take)
        .args(["--stature", "0"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("expected a height in metres"));
    // and --stature wins
    let o = articula()
        .arg("info")
        .arg(&take)
        .args(["--stature", "1.80", "--json"])
        .output()
        .unwrap();
    assert!(o.status.success());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert!(
        (v["stature_m"].as_f64().unwrap() - 1.80).abs() < 1e-9,
        "{v}"
    );
}

#[test]
fn smooth_and_blend_write_takes_that_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 1.0);
    let smooth = dir.path().join("smooth.bvh");
    articula()
        .arg("smooth")
        .arg(&take)
        .args(["--smooth", "gaussian:0.02", "-o"])
        .arg(&smooth)
        .assert()
        .success();
    let blended = dir.path().join("blend.bvh");
    articula()
        .arg("blend")
        .arg(&take)
        .arg(&smooth)
        .args(["--window", "0.3:0.6", "-o"])
        .arg(&blended)
        .assert()
        .success();
    for p in [&smooth, &blended] {
        let b = articula::io::bvh::read(p).unwrap();
        assert_eq!(b.joints.len(), 21);
        assert!(b.frames >= 59, "{}", b.frames);
    }
}

#[test]
fn scene_file_sets_the_options_and_flags_override_it() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 1.0);
    let scene = dir.path().join("study.toml");
    std::fs::write(
        &scene,
        "takes = [\"walk.bvh\"]\nmass = 60.0\nsex = \"female\"\ncontact = \"feet\"\n",
    )
    .unwrap();
    let info = |extra: &[&str]| {
        let o = articula()
            .arg("info")
            .arg(&take)
            .arg("--scene")
            .arg(&scene)
            .args(extra)
            .arg("--json")
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap()
    };
    assert!((info(&[])["mass_kg"].as_f64().unwrap() - 60.0).abs() < 1e-9);
    assert!((info(&["--mass", "80"])["mass_kg"].as_f64().unwrap() - 80.0).abs() < 1e-9);
    // contact = "feet" from the scene: the torque file gains ground reaction columns, and the
    // run says how far the feet give the force the motion needs
    let out = dir.path().join("t.csv");
    articula()
        .arg("id")
        .arg(&take)
        .arg("--scene")
        .arg(&scene)
        .arg("-o")
        .arg(&out)
        .assert()
        .success()
        .stderr(
            predicates::str::contains("ground reactions: in ")
                .and(predicates::str::contains("single-support frames")),
        );
    let (h, c) = read_columns(&out).unwrap();
    for name in ["grf:left:y", "cop:right:z", "residual:fy", "residual:tz"] {
        assert!(h.iter().any(|x| x == name), "{name} missing: {h:?}");
    }
    // the feet carry load in some frames (the physics of the estimate: tests/contact_*.rs)
    let loaded = column(&h, &c, "grf:left:y")
        .iter()
        .zip(column(&h, &c, "grf:right:y"))
        .filter(|(l, r)| **l + **r > 100.0)
        .count();
    assert!(
        loaded > c[0].len() / 2,
        "{loaded} loaded frames of {}",
        c[0].len()
    );
    // a bad scene value is reported with its line
    std::fs::write(&scene, "takes = [\"walk.bvh\"]\nmass = -3\n").unwrap();
    let o = articula()
        .arg("info")
        .arg(&take)
        .arg("--scene")
        .arg(&scene)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("study.toml") && err.contains('2'), "{err}");
}

#[test]
fn export_positions_are_world_joint_positions_in_metres() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.5);
    let out = dir.path().join("pos.csv");
    articula()
        .args(["export", "positions"])
        .arg(&take)
        .arg("-o")
        .arg(&out)
        .assert()
        .success();
    let (h, c) = read_columns(&out).unwrap();
    let bvh = articula::io::bvh::read(&take).unwrap();
    assert_eq!(h.len(), 1 + 3 * bvh.joints.len());
    assert_eq!(&h[1..4], ["pos:Hips:x", "pos:Hips:y", "pos:Hips:z"]);
    // the hips at frame 0 are where the root channels put them (cm → m, add mode)
    let f0 = bvh.frame(0);
    for (k, axis) in ["x", "y", "z"].iter().enumerate() {
        let p = column(&h, &c, &format!("pos:Hips:{axis}"))[0];
        assert!((p - (bvh.joints[0].offset[k] + f0[k]) * 0.01).abs() < 1e-12);
    }
    // a foot is near the floor (y = 0) at some frame, the head well above it
    let foot_min = column(&h, &c, "pos:LeftToeBase:y")
        .iter()
        .cloned()
        .fold(f64::MAX, f64::min);
    let head = column(&h, &c, "pos:Head:y")[0];
    assert!(foot_min < 0.1 && head > 1.4, "toe {foot_min} head {head}");
}

#[test]
fn damping_adds_exactly_b_times_the_joint_rate_to_the_torques() {
    // τ(b) − τ(0) = b q̇ on every joint coordinate, per joint where overridden, and nothing on
    // the six root coordinates (the residual actuator of the floating avatar)
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.5);
    let run = |extra: &[&str], out: &str| {
        let p = dir.path().join(out);
        articula()
            .arg("id")
            .arg(&take)
            .args(extra)
            .arg("-o")
            .arg(&p)
            .assert()
            .success();
        read_columns(&p).unwrap()
    };
    let (h0, t0) = run(&[], "t0.csv");
    let (h1, t1) = run(&["--damping", "0.5", "--damping", "LeftLeg=2"], "t1.csv");
    assert_eq!(h0, h1);
    let states = dir.path().join("s.csv");
    articula()
        .args(["export", "states"])
        .arg(&take)
        .arg("-o")
        .arg(&states)
        .assert()
        .success();
    let (hs, s) = read_columns(&states).unwrap();
    let mut checked = 0;
    // the coordinates' torques (with contact auto the ground reactions' columns follow them)
    let coords = h0.iter().enumerate().skip(1);
    let coords = coords.filter_map(|(k, n)| n.strip_prefix("tau:").map(|n| (k, n)));
    for (k, name) in coords.filter(|(_, n)| hs.contains(&format!("v:{n}"))) {
        let v = column(&hs, &s, &format!("v:{name}"));
        let root = name.starts_with("Hips.");
        let b = if root {
            0.0
        } else if name.starts_with("LeftLeg.") {
            2.0
        } else {
            0.5
        };
        for f in 0..v.len() {
            let d = t1[k][f] - t0[k][f];
            assert!(
                (d - b * v[f]).abs() <= 1e-9 * (1.0 + t0[k][f].abs()),
                "{name} frame {f}: Δτ {d} vs b q̇ {}",
                b * v[f]
            );
        }
        checked += usize::from(!root && v.iter().any(|x| x.abs() > 1e-3));
    }
    assert!(checked >= 10, "only {checked} moving joint coordinates");
    // a joint the model does not have is an error that says so
    articula()
        .arg("id")
        .arg(&take)
        .args(["--damping", "Tail=1", "-o"])
        .arg(dir.path().join("t2.csv"))
        .assert()
        .failure()
        .stderr(predicates::str::contains("damping Tail=1"));
}

#[test]
fn an_error_names_the_missing_file_once() {
    let dir = tempfile::tempdir().unwrap();
    let session = dir.path().join("s.session");
    std::fs::write(&session, "load no_such_take.bvh\n").unwrap();
    let out = articula().arg("run").arg(&session).assert().failure();
    let err = String::from_utf8_lossy(&out.get_output().stderr).into_owned();
    assert!(err.contains("s.session:1"), "{err}");
    assert_eq!(err.matches("no_such_take.bvh: ").count(), 1, "{err}");
    let out = articula()
        .args(["info", "no_such_take.bvh"])
        .assert()
        .failure();
    let err = String::from_utf8_lossy(&out.get_output().stderr).into_owned();
    assert_eq!(err.matches("no_such_take.bvh").count(), 1, "{err}");
}

#[test]
fn a_take_flag_a_command_would_ignore_is_refused() {
    // simulate --contact feet wrote the same bytes as without it; smooth --mass likewise
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.3);
    for (args, flag) in [
        (vec!["simulate", "--contact", "feet"], "--contact"),
        (vec!["smooth", "--mass", "80", "-o", "s.bvh"], "--mass"),
        (
            vec!["export", "positions", "--smooth", "none", "-o", "p.csv"],
            "--smooth",
        ),
        (vec!["info", "--damping", "2"], "--damping"),
        (
            vec!["export", "states", "--segments", "fractions", "-o", "s.csv"],
            "--segments",
        ),
    ] {
        let (cmd, rest) = args.split_at(if args[0] == "export" { 2 } else { 1 });
        let o = articula()
            .current_dir(dir.path())
            .args(cmd)
            .arg(&take)
            .args(rest)
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(flag) && err.contains("has no effect"), "{err}");
    }
    assert!(!dir.path().join("s.bvh").exists() && !dir.path().join("p.csv").exists());
    // and a table the flag does not know is an error that names the two it does
    let o = articula()
        .arg("info")
        .arg(&take)
        .args(["--segments", "dempster"])
        .output()
        .unwrap();
    assert!(!o.status.success());
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("--segments dempster")
            && err.contains("regression")
            && err.contains("fractions"),
        "{err}"
    );
}

/// `articula id TAKE -o OUT`, run in `dir`, and its standard output.
fn id_to(dir: &Path, take: &Path, out: &Path) -> Vec<u8> {
    let o = articula()
        .current_dir(dir)
        .arg("id")
        .arg(take)
        .arg("-o")
        .arg(out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    o.stdout
}

#[test]
fn dash_writes_only_the_csv_to_stdout_and_no_file_named_dash() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.5);
    let file = dir.path().join("t.csv");
    assert!(id_to(dir.path(), &take, &file).is_empty());
    let stdout = id_to(dir.path(), &take, Path::new("-"));
    assert_eq!(stdout, std::fs::read(&file).unwrap());
    assert!(!dir.path().join("-").exists(), "a file named `-`");
    // simulate's summary moves to stderr when its CSV goes to stdout
    let o = articula()
        .current_dir(dir.path())
        .arg("simulate")
        .arg(&take)
        .args(["--duration", "0.05", "--json", "-o", "-"])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let text = String::from_utf8(o.stdout).unwrap();
    let (h, _) = articula::report::csv::parse_columns(&text, Path::new("-")).unwrap();
    assert_eq!(h[0], "time");
    assert!(String::from_utf8_lossy(&o.stderr).contains("rms_error_rad"));
    assert!(!dir.path().join("-").exists(), "a file named `-`");
}

#[cfg(unix)]
#[test]
fn a_fifo_reader_gets_the_whole_csv_and_the_fifo_stays_a_fifo() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.5);
    let file = dir.path().join("t.csv");
    id_to(dir.path(), &take, &file);
    let fifo = dir.path().join("pipe");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(fifo).unwrap())
    };
    id_to(dir.path(), &take, &fifo);
    assert_eq!(reader.join().unwrap(), std::fs::read(&file).unwrap());
    let kind = std::fs::symlink_metadata(&fifo).unwrap().file_type();
    assert!(kind.is_fifo(), "the FIFO is now {kind:?}");
}

#[cfg(unix)]
#[test]
fn dev_null_takes_the_output_and_stays_a_device() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.5);
    id_to(dir.path(), &take, Path::new("/dev/null"));
    let kind = std::fs::symlink_metadata("/dev/null").unwrap().file_type();
    assert!(kind.is_char_device(), "/dev/null is now {kind:?}");
}

#[cfg(unix)]
#[test]
fn a_symlink_output_stays_a_link_and_its_target_gets_the_content() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.5);
    let file = dir.path().join("t.csv");
    id_to(dir.path(), &take, &file);
    let target = dir.path().join("target.csv");
    std::fs::write(&target, "old").unwrap();
    let link = dir.path().join("link.csv");
    std::os::unix::fs::symlink("target.csv", &link).unwrap();
    id_to(dir.path(), &take, &link);
    assert!(std::fs::symlink_metadata(&link).unwrap().is_symlink());
    assert_eq!(
        std::fs::read(&target).unwrap(),
        std::fs::read(&file).unwrap()
    );
}

#[test]
fn fd_needs_no_acceleration_columns_and_id_names_the_first_missing_one() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.5);
    let (states, tau) = (dir.path().join("s.csv"), dir.path().join("t.csv"));
    articula()
        .args(["export", "states"])
        .arg(&take)
        .arg("-o")
        .arg(&states)
        .assert()
        .success();
    articula()
        .arg("id")
        .arg(&take)
        .args(["--contact", "none", "-o"])
        .arg(&tau)
        .assert()
        .success();
    let (h, c) = read_columns(&states).unwrap();
    let keep: Vec<usize> = (0..h.len()).filter(|&i| !h[i].starts_with("a:")).collect();
    let qv = dir.path().join("qv.csv");
    let names: Vec<String> = keep.iter().map(|&i| h[i].clone()).collect();
    let cols: Vec<&[f64]> = keep.iter().map(|&i| c[i].as_slice()).collect();
    articula::report::csv::write_columns(&qv, &names, &cols).unwrap();
    let acc = dir.path().join("a.csv");
    articula()
        .arg("fd")
        .arg(&take)
        .arg("--states")
        .arg(&qv)
        .arg("--torques")
        .arg(&tau)
        .arg("-o")
        .arg(&acc)
        .assert()
        .success();
    let (ha, ca) = read_columns(&acc).unwrap();
    let mut n = 0;
    for name in ha.iter().filter(|x| x.starts_with("a:")) {
        for (w, g) in column(&h, &c, name).iter().zip(column(&ha, &ca, name)) {
            assert!(
                (w - g).abs() <= 1e-6 * (1.0 + w.abs()),
                "{name}: {w} vs {g}"
            );
        }
        n += 1;
    }
    assert!(n > 50, "{n} acceleration columns");
    // inverse dynamics does need them, and says which one is missing
    let first_a = h.iter().find(|x| x.starts_with("a:")).unwrap();
    articula()
        .arg("id")
        .arg(&take)
        .arg("--states")
        .arg(&qv)
        .arg("-o")
        .arg(dir.path().join("t2.csv"))
        .assert()
        .code(2)
        .stderr(predicate::str::contains(format!("no column `{first_a}`")));
}

#[test]
fn a_negative_number_reaches_the_flag_check_not_clap() {
    let take = common::repo("data/demo_walk.bvh");
    for (flag, says) in [
        ("--mass", "--mass -5: expected a body mass in kg"),
        ("--stature", "--stature -5: expected a height in metres"),
    ] {
        articula()
            .arg("info")
            .arg(&take)
            .args([flag, "-5"])
            .assert()
            .code(2)
            .stderr(predicate::str::contains(says))
            .stderr(predicate::str::contains("unexpected argument").not());
    }
    for (flag, says) in [
        ("--dt", "--dt -5: expected a positive step"),
        ("--kp", "--kp -5: expected X or JOINT=X with X ≥ 0"),
    ] {
        articula()
            .arg("simulate")
            .arg(&take)
            .args([flag, "-5"])
            .assert()
            .code(2)
            .stderr(predicate::str::contains(says));
    }
    let dir = tempfile::tempdir().unwrap();
    articula()
        .args(["generate", "walk", "--fps", "-60", "-o"])
        .arg(dir.path().join("w.bvh"))
        .assert()
        .code(2)
        .stderr(predicate::str::contains("must be positive"));
}

#[test]
fn a_diverged_simulation_is_an_error_that_says_so() {
    // explicit Euler at 0.1 s ended 46 rad off the walk and exited 0
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 1.0);
    let out = dir.path().join("sim.csv");
    let o = articula()
        .arg("simulate")
        .arg(&take)
        .args(["--dt", "0.1", "--integrator", "euler", "-o"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("diverged") && err.contains("--dt"), "{err}");
    assert!(!out.exists(), "no file from a diverged run");
}

#[test]
fn a_flag_that_means_nothing_for_the_source_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.3);
    let arm = common::repo("data/arm7.urdf");
    let cases: [(Vec<std::ffi::OsString>, &str); 4] = [
        (
            vec![
                "id".into(),
                "--urdf".into(),
                arm.clone().into(),
                "--mass".into(),
                "80".into(),
            ],
            "--mass has no effect on a robot",
        ),
        (
            vec![
                "id".into(),
                take.clone().into(),
                "--gravity".into(),
                "0,0,-9.81".into(),
            ],
            "--gravity has no effect without --urdf",
        ),
        (
            vec![
                "mass-matrix".into(),
                take.clone().into(),
                "--contact".into(),
                "feet".into(),
            ],
            "--contact has no effect",
        ),
        (
            vec![
                "id".into(),
                take.clone().into(),
                "--states".into(),
                "s.csv".into(),
                "--smooth".into(),
                "none".into(),
            ],
            "--smooth has no effect with --states",
        ),
    ];
    for (args, message) in cases {
        let o = articula()
            .current_dir(dir.path())
            .args(&args)
            .args(["-o", "out.csv"])
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains(message), "{args:?}: {err}");
    }
    assert!(!dir.path().join("out.csv").exists());
}

#[test]
fn fd_refuses_torques_computed_with_ground_reactions() {
    // `id` on a take that stands estimates ground reactions (contact auto); fd has no contact
    // model, so those torques would not give the motion back: said, not silently run
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.5);
    let tau = dir.path().join("t.csv");
    id_to(dir.path(), &take, &tau);
    let out = articula()
        .arg("fd")
        .arg(&take)
        .arg("--torques")
        .arg(&tau)
        .arg("-o")
        .arg(dir.path().join("a.csv"))
        .output()
        .unwrap();
    assert!(!out.status.success());
    let e = String::from_utf8_lossy(&out.stderr);
    assert!(e.contains("computed with ground reactions"), "{e}");
    assert!(e.contains("articula id --contact none"), "{e}");
    assert!(!dir.path().join("a.csv").exists());
}

#[test]
fn anatomy_reports_the_consistency_and_id_asks_for_contact_before_reducing() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 3.0);
    let out = dir.path().join("a.csv");
    // anatomy: residual reduction on by default with contact; the JSON summary on stdout
    let json = articula()
        .args(["anatomy", "--json", "-o"])
        .arg(&out)
        .arg(&take)
        .assert()
        .success()
        .stderr(predicate::str::contains(
            "consistency after residual reduction",
        ))
        .get_output()
        .stdout
        .clone();
    let v: serde_json::Value = serde_json::from_slice(&json).unwrap();
    for key in [
        "thresholds",
        "before",
        "after",
        "adjustments",
        "meets",
        "why",
        "frames_beyond",
    ] {
        assert!(v.get(key).is_some(), "no key {key} in {v}");
    }
    assert!(
        v["after"]["rms_residual_moment_pct"].as_f64().unwrap()
            <= v["before"]["rms_residual_moment_pct"].as_f64().unwrap()
    );
    // off: the figures of the take as loaded, and no adjustment
    articula()
        .args(["anatomy", "--consistent", "off", "-o"])
        .arg(&out)
        .arg(&take)
        .assert()
        .success()
        .stderr(predicate::str::contains("(not reduced)"));
    articula()
        .args(["anatomy", "--consistent", "maybe", "-o"])
        .arg(&out)
        .arg(&take)
        .assert()
        .failure()
        .stderr(predicate::str::contains("expected on or off"));
    // id: no contact, no residuals to reduce
    articula()
        .args(["id", "--contact", "none", "--consistent", "on", "-o"])
        .arg(dir.path().join("id.csv"))
        .arg(&take)
        .assert()
        .failure()
        .stderr(predicate::str::contains("need --contact feet"));
}

#[test]
fn anatomy_marks_the_edge_frames_and_leaves_them_out_of_its_ranges_unless_asked() {
    // the smoothing's reach at each end of a take: accelerations there are not trustworthy
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 2.0);
    let out = dir.path().join("a.csv");
    let run = |extra: &[&str]| {
        let o = articula()
            .arg("anatomy")
            .arg(&take)
            .args(extra)
            .arg("-o")
            .arg(&out)
            .output()
            .unwrap();
        (
            o.status.success(),
            String::from_utf8_lossy(&o.stderr).to_string(),
        )
    };
    let (ok, excluded) = run(&[]);
    assert!(ok, "{excluded}");
    assert!(excluded.contains("at each end of the take"), "{excluded}");
    let (h, c) = read_columns(&out).unwrap();
    let edge = column(&h, &c, "edge");
    let n = edge.len();
    let e = edge.iter().take_while(|x| **x == 1.0).count();
    assert!(e >= 1 && e < n / 4, "{e} edge frames of {n}");
    assert_eq!(edge.iter().rev().take_while(|x| **x == 1.0).count(), e);
    assert_eq!(edge.iter().filter(|x| **x == 1.0).count(), 2 * e);
    // the summary's ranges are those of the frames between the edges, or of all with include,
    // never those beyond Hicks et al.'s thresholds (`residual:beyond`)
    let m = column(&h, &c, "moment_per_kg:knee_l:flexion");
    let beyond = column(&h, &c, "residual:beyond");
    let printed_range = |summary: &str, frames: std::ops::Range<usize>| {
        let (lo, hi) = frames
            .filter(|&k| beyond[k] == 0.0)
            .map(|k| m[k])
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, u), x| {
                (l.min(x), u.max(x))
            });
        let line = summary.lines().find(|l| l.starts_with("knee_l ")).unwrap();
        assert!(
            line.ends_with(&format!("{lo:.2}..{hi:.2}")),
            "{line} vs {lo:.2}..{hi:.2}"
        );
    };
    printed_range(&excluded, e..n - e);
    let (ok, included) = run(&["--edges", "include"]);
    assert!(
        ok && !included.contains("at each end of the take"),
        "{included}"
    );
    printed_range(&included, 0..n);
    let (ok, e) = run(&["--edges", "maybe"]);
    assert!(
        !ok && e.contains("--edges maybe: expected exclude or include"),
        "{e}"
    );
}
