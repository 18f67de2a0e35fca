//! A rest pose stored as frame 0 (takes converted from the CMU database start so) is not part of
//! the motion: loading drops it by default, says so in `articula info`, and keeps it with
//! `--keep-first-frame` (or `keep_first_frame = true` in a scene). Takes whose frame 0 is
//! continuous with the rest keep it.
//!
//! Default suite: a synthetic take, with and without a rest frame, through the real binary and
//! the pipeline. Real suite (`ARTICULA_REAL_TAKES`): the CMU-derived takes lose their frame 0,
//! the others keep theirs, and without the rest frame the first 0.1 s of CMU 01_01 no longer
//! needs several body weights at the root.

mod common;

use articula::pipeline::{TakeOptions, load_take};
use assert_cmd::Command;
use std::path::{Path, PathBuf};

/// A standing figure swaying for one second at 60 fps (hips, a leg, a spine), optionally preceded by a
/// rest frame (every rotation 0, the root 30 cm higher).
fn write_take(dir: &Path, name: &str, rest: bool) -> PathBuf {
    let mut rows = vec![];
    if rest {
        rows.push("0 120 0 0 0 0 0 0 0 0 0 0 0 0 0".to_string());
    }
    for k in 0..60 {
        let s = (2.0 * std::f64::consts::PI * k as f64 / 60.0).sin();
        rows.push(format!(
            "{} 90 0 {} 5 {} {} 0 0 {} 0 0 0 2 0",
            s,
            2.0 * s,
            -3.0 * s,
            20.0 + 10.0 * s,
            -10.0 - 5.0 * s
        ));
    }
    let text = format!(
        "HIERARCHY\nROOT Hips\n{{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition \
         Zrotation Xrotation Yrotation\n JOINT LeftUpLeg\n {{\n  OFFSET 10 -5 0\n  CHANNELS 3 \
         Zrotation Xrotation Yrotation\n  JOINT LeftLeg\n  {{\n   OFFSET 0 -42 0\n   CHANNELS 3 \
         Zrotation Xrotation Yrotation\n   End Site\n   {{\n    OFFSET 0 -43 0\n   }}\n  }}\n \
         }}\n JOINT Spine\n {{\n  OFFSET 0 70 0\n  CHANNELS 3 Zrotation Xrotation Yrotation\n  End Site\n  {{\n   OFFSET 0 20 0\n  }}\n \
         }}\n}}\nMOTION\nFrames: {}\nFrame Time: 0.0166667\n{}\n",
        rows.len(),
        rows.join("\n")
    );
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn info(path: &Path, extra: &[&str]) -> String {
    let out = Command::cargo_bin("articula")
        .unwrap()
        .arg("info")
        .arg(path)
        .args(extra)
        .output()
        .unwrap();
    assert!(out.status.success(), "{out:?}");
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn a_rest_frame_is_dropped_by_default_and_kept_on_request() {
    let dir = tempfile::tempdir().unwrap();
    let with = write_take(dir.path(), "rest.bvh", true);
    let without = write_take(dir.path(), "plain.bvh", false);

    // the pipeline: the same states as the take without the rest frame
    let dropped = load_take(&with, &TakeOptions::default()).unwrap();
    let plain = load_take(&without, &TakeOptions::default()).unwrap();
    assert_eq!(dropped.bvh.frames, 60);
    assert_eq!(dropped.states.q, plain.states.q);
    assert!(
        dropped
            .notes
            .iter()
            .any(|n| n.contains("frame 0 was dropped"))
    );
    assert!(plain.notes.iter().all(|n| !n.contains("frame 0")));
    let keep = TakeOptions {
        keep_first_frame: true,
        ..TakeOptions::default()
    };
    let kept = load_take(&with, &keep).unwrap();
    assert_eq!(kept.bvh.frames, 61);
    assert!(kept.notes.iter().all(|n| !n.contains("frame 0")));

    // the binary: `info` says so, `--keep-first-frame` keeps it
    let text = info(&with, &[]);
    assert!(text.contains("60 frames"), "{text}");
    assert!(text.contains("frame 0 was dropped"), "{text}");
    assert!(text.contains("--keep-first-frame"), "{text}");
    let text = info(&with, &["--keep-first-frame"]);
    assert!(
        text.contains("61 frames") && !text.contains("dropped"),
        "{text}"
    );
    let text = info(&without, &[]);
    assert!(
        text.contains("60 frames") && !text.contains("dropped"),
        "{text}"
    );

    // a scene can keep it too
    let scene = dir.path().join("scene.toml");
    std::fs::write(&scene, "takes = [\"rest.bvh\"]\nkeep_first_frame = true\n").unwrap();
    let o = TakeOptions::from_scene_file(&scene).unwrap();
    assert!(o.keep_first_frame);
    assert_eq!(load_take(&with, &o).unwrap().bvh.frames, 61);
}

#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn the_cmu_takes_lose_their_rest_frame_and_the_others_keep_frame_zero() {
    let takes = common::real_takes();
    let rest = [
        "cmu_01_01.bvh",
        "cmu_05_20-daz.bvh",
        "cmu_05_20-mb.bvh",
        "pirouette.bvh",
    ];
    for path in takes {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let bvh = articula::io::bvh::read(&path).unwrap();
        let found = articula::motion::trim::rest_first_frame(&bvh);
        println!("{name}: {found:?}");
        assert_eq!(found.is_some(), rest.contains(&name.as_str()), "{name}");
    }

    // CMU 01_01: with the rest frame, the smoothed start needs several body weights at the
    // root; without it, about one (standing)
    let path = common::real_take("cmu_01_01.bvh");
    let peak_start = |keep: bool| {
        let o = TakeOptions {
            keep_first_frame: keep,
            ..TakeOptions::default()
        };
        let take = load_take(&path, &o).unwrap();
        let gr = articula::pipeline::estimate_take_ground_reactions(&take).unwrap();
        let up = take.up.index();
        let w = take.model.total_mass() * 9.81;
        let n = (0.1 / take.bvh.frame_time) as usize;
        gr.wrench[..n].iter().map(|x| x[up] / w).fold(0.0, f64::max)
    };
    let (kept, dropped) = (peak_start(true), peak_start(false));
    println!(
        "cmu_01_01: peak needed vertical force over the first 0.1 s {kept:.2} BW with the rest frame, {dropped:.2} BW without"
    );
    assert!(kept > 3.0 && dropped < 1.5, "{kept} {dropped}");
}

/// `articula blend` reads its takes as every other command does: a rest frame 0 is dropped,
/// so the blend starts with the motion (root height 90, not the rest pose's 120), and
/// `--keep-first-frame` keeps it.
#[test]
fn blend_drops_a_rest_frame_unless_kept() {
    let dir = tempfile::tempdir().unwrap();
    let with = write_take(dir.path(), "rest.bvh", true);
    let plain = write_take(dir.path(), "plain.bvh", false);
    let blend = |extra: &[&str], out: &str| {
        let out = dir.path().join(out);
        let o = Command::cargo_bin("articula")
            .unwrap()
            .arg("blend")
            .arg(&with)
            .arg(&plain)
            .args(["--window", "0.4:0.6", "--align", "none"])
            .args(extra)
            .arg("-o")
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{o:?}");
        let stderr = String::from_utf8(o.stderr).unwrap();
        (articula::io::bvh::read(&out).unwrap(), stderr)
    };
    let (dropped, said) = blend(&[], "dropped.bvh");
    // frame 0: Xposition Yposition … of the first take's motion
    assert_eq!(dropped.motion[1], 90.0, "{:?}", &dropped.motion[..6]);
    assert!(said.contains("frame 0 was dropped"), "{said}");
    let (kept, said) = blend(&["--keep-first-frame"], "kept.bvh");
    assert_eq!(kept.motion[1], 120.0, "{:?}", &kept.motion[..6]);
    assert!(!said.contains("dropped"), "{said}");
}

/// Sessions read takes the same way, and `set keep_first_frame true|false` chooses, for the
/// takes loaded after it.
#[test]
fn a_session_keeps_the_rest_frame_on_request() {
    let dir = tempfile::tempdir().unwrap();
    write_take(dir.path(), "rest.bvh", true);
    let session = dir.path().join("keep.session");
    std::fs::write(
        &session,
        "load rest.bvh as a\nexpect frames 60\nset keep_first_frame true\nload rest.bvh as b\n\
         expect frames 61\nset keep_first_frame false\nload rest.bvh as c\nexpect frames 60\n",
    )
    .unwrap();
    articula::tui::run_session(&session, dir.path()).unwrap();
    // and a wrong value is an error naming the key
    std::fs::write(&session, "set keep_first_frame yes\n").unwrap();
    let e = articula::tui::run_session(&session, dir.path()).unwrap_err();
    assert!(e.to_string().contains("keep_first_frame"), "{e}");
}

/// The file's clock: frame k of the file is at k·dt in every output, also when the rest frame
/// 0 was dropped (the first row is then the file's frame 1, at 1·dt, not 0). Regression: the
/// dropped frame used to shift every output one frame off the video and force plates the take
/// came with.
#[test]
fn a_dropped_rest_frame_keeps_the_files_clock() {
    let dir = tempfile::tempdir().unwrap();
    let with = write_take(dir.path(), "rest.bvh", true);
    let dt = 0.0166667;

    // the pipeline: the states start at the file's frame 1; kept, at frame 0
    let dropped = load_take(&with, &TakeOptions::default()).unwrap();
    assert_eq!(dropped.bvh.first_frame, 1);
    assert_eq!(dropped.states.time[0], dt);
    assert!((dropped.states.time[59] - 60.0 * dt).abs() < 1e-12);
    let keep = TakeOptions {
        keep_first_frame: true,
        ..TakeOptions::default()
    };
    let kept = load_take(&with, &keep).unwrap();
    assert_eq!(kept.states.time[0], 0.0);
    assert_eq!(kept.states.time[1], dropped.states.time[0]);

    // every CSV the binary writes: its `time` column starts at 1·dt
    for args in [
        &["export", "states"][..],
        &["export", "positions"],
        &["id", "--contact", "none"],
    ] {
        let out = Command::cargo_bin("articula")
            .unwrap()
            .args(args)
            .arg(&with)
            .args(["-o", "-"])
            .output()
            .unwrap();
        assert!(out.status.success(), "{args:?}: {out:?}");
        let text = String::from_utf8(out.stdout).unwrap();
        let first: f64 = text
            .lines()
            .nth(1)
            .unwrap()
            .split(',')
            .next()
            .unwrap()
            .parse()
            .unwrap();
        assert_eq!(first, dt, "{args:?}: the first row's time");
    }
}
