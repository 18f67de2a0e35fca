//! A take whose Euler triples flip branch near the singularity (as exporters write them, from
//! `matrix_to_euler` frame by frame) gives continuous q in the euler model, with every frame's
//! rotation unchanged.

use articula::io::bvh::parse_str;
use articula::motion::smooth::SmoothSpec;
use articula::pipeline::{TakeOptions, take_from_bvh};
use articula::rotation::{EulerOrder, euler_to_matrix, matrix_to_euler};
use std::path::Path;

#[test]
fn euler_branch_flips_are_repicked_and_rotations_kept() {
    // the arm pitches through X = 90° (the ZXY singularity) while yawing: the canonical
    // extraction jumps to the other branch (±180° on Z and Y) after the pole
    let n = 60;
    let mut motion = String::new();
    let mut raw = vec![];
    for k in 0..n {
        let t = k as f64 / (n - 1) as f64;
        let r = euler_to_matrix(
            EulerOrder::ZXY,
            [0.3 * t, (60.0 + 60.0 * t).to_radians(), 0.2],
        );
        let a = matrix_to_euler(EulerOrder::ZXY, &r).map(f64::to_degrees);
        raw.push(a);
        motion.push_str(&format!(
            "0 0 0 0 0 0 {} {} {} 0 0 0 0 0 0\n",
            a[0], a[1], a[2]
        ));
    }
    let jumps = raw.windows(2).any(|w| (w[1][0] - w[0][0]).abs() > 90.0);
    assert!(jumps, "the test take must contain a branch flip");
    let text = take_text(n, &motion);
    // the flip is on the Spine (the root stays upright)
    let bvh = parse_str(&text, Path::new("flip.bvh")).unwrap();
    let opts = TakeOptions {
        smooth: Some(SmoothSpec::None),
        stature_m: Some(1.75),
        ..TakeOptions::default()
    };
    let take = take_from_bvh(Path::new("flip.bvh"), bvh, &opts).unwrap();
    let m = &take.model;
    let iz = m
        .q_names
        .iter()
        .position(|n| n == "Spine.Zrotation")
        .unwrap();
    let s = &take.states;
    for (k, file_angles) in raw.iter().enumerate().skip(1) {
        for j in iz..iz + 3 {
            let d = (s.q[k][j] - s.q[k - 1][j]).abs();
            assert!(
                d < 0.2,
                "frame {k} coordinate {}: jump {d} rad",
                m.q_names[j]
            );
        }
        // same rotation as written
        let ours = euler_to_matrix(
            EulerOrder::ZXY,
            [s.q[k][iz], s.q[k][iz + 1], s.q[k][iz + 2]],
        );
        let file = euler_to_matrix(EulerOrder::ZXY, file_angles.map(f64::to_radians));
        assert!((ours - file).norm() < 1e-9, "frame {k}");
    }
}

/// A take with (a) a spine that passes near gimbal lock — ZXY at X = 88°, where `Rz(θ)·Rx·Ry(−θ)`
/// barely moves while θ sweeps 40° a frame — and (b) a leg whose rotation jumps 150° for two
/// frames and back (a solver swap) gets a note for each: the joint, the frame and what it means
/// for the euler model's torques; `articula id` prints them before writing. A calm take gets
/// none.
#[test]
fn passages_near_gimbal_lock_and_capture_glitches_are_noted() {
    let n = 40;
    let mut motion = String::new();
    for k in 0..n {
        let t = k as f64;
        // the spine: near the pole for frames 10..20, calm elsewhere
        let th = if (10..20).contains(&k) {
            40.0 * (t - 10.0)
        } else {
            0.0
        };
        let spine = [th, 88.0, -th];
        let leg_yaw = if k == 25 || k == 26 { 150.0 } else { 5.0 };
        motion.push_str(&format!(
            "0 0 0 0 0 0 {} {} {} 0 0 0 {} 0 0\n",
            spine[0], spine[1], spine[2], leg_yaw
        ));
    }
    let text = take_text(n, &motion);
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("glitch.bvh");
    std::fs::write(&path, &text).unwrap();
    let opts = TakeOptions {
        stature_m: Some(1.75),
        ..TakeOptions::default()
    };
    let take = take_from_bvh(&path, parse_str(&text, &path).unwrap(), &opts).unwrap();
    let notes = take.notes.join("\n");
    assert!(
        notes.contains("`Spine` passes near gimbal lock between frames 1"),
        "{notes}"
    );
    assert!(
        notes.contains("`Leg` turns 145° between frames 24 and 25"),
        "{notes}"
    );
    assert!(notes.contains("capture glitch"), "{notes}");
    assert!(
        !notes.contains("`Head`") && !notes.contains("`Hips`"),
        "{notes}"
    );

    let out = assert_cmd::Command::cargo_bin("articula")
        .unwrap()
        .args(["id", "--stature", "1.75"])
        .arg(&path)
        .arg("-o")
        .arg(dir.path().join("tau.csv"))
        .output()
        .unwrap();
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("note: `Spine` passes near gimbal lock"),
        "{err}"
    );
    assert!(err.contains("note: `Leg` turns 145°"), "{err}");
    let out = assert_cmd::Command::cargo_bin("articula")
        .unwrap()
        .args(["simulate", "--stature", "1.75", "--duration", "0.05"])
        .arg(&path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("note: `Spine` passes near gimbal lock"),
        "simulate: {err}"
    );

    // the workbench says so after inverse dynamics (the TUI's status line)
    let mut wb = articula::session::Workbench::new(
        std::sync::Arc::new(articula::session::Builtin),
        dir.path(),
        dir.path(),
    );
    for line in ["set stature 1.75", "load glitch.bvh", "run id"] {
        let cmd = articula::session::parse_line(line, 1).unwrap().unwrap();
        let msg = wb.apply(&cmd).unwrap().message;
        if line == "run id" {
            assert!(
                msg.contains("note: `Spine` passes near gimbal lock"),
                "{msg}"
            );
            assert!(
                // the other passage, and that this skeleton, not a human's, has de Leva's
                // masses through its `Hips`, what contact auto chose and each foot's contact
                // model
                msg.contains("(+4 more; `articula info` lists every note)"),
                "{msg}"
            );
        }
    }
}

/// A ZXY skeleton (Hips with six channels; Spine → Head, and Leg, three rotations each) with
/// `n` frames of `motion` (one line per frame, 15 numbers), at 100 fps.
fn take_text(n: usize, motion: &str) -> String {
    format!(
        "HIERARCHY\nROOT Hips\n{{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition \
         Zrotation Xrotation Yrotation\n JOINT Spine\n {{\n  OFFSET 0 100 0\n  CHANNELS 3 \
         Zrotation Xrotation Yrotation\n  JOINT Head\n  {{\n   OFFSET 0 70 0\n   CHANNELS 3 \
         Zrotation Xrotation Yrotation\n   End Site\n   {{\n    OFFSET 0 20 0\n   }}\n  }}\n }}\n \
         JOINT Leg\n {{\n  OFFSET 0 -90 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End \
         Site\n  {{\n   OFFSET 0 -10 0\n  }}\n }}\n}}\nMOTION\nFrames: {n}\nFrame Time: 0.01\n{motion}"
    )
}
