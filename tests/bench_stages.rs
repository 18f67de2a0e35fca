//! `articula bench --stages`: the instrument of issue 17. Its JSON has the keys the issue
//! asks for, and one stage per step of `articula id`'s way from the file to the torques, each
//! reported by the pipeline itself (a stage that did not report would be an error, not a
//! zero). Times are not asserted: the machine may be loaded (speed lives in benchmarks).

mod common;

use common::cli::{articula, json_of};

use articula::pipeline::{STAGES, stages::cycle_take_text};
use std::path::Path;

fn bench_json(args: &[&str]) -> serde_json::Value {
    json_of(
        articula()
            .args(["bench", "--stages"])
            .arg(common::repo("data/demo_walk.bvh"))
            .args(["--repeat", "1", "--json"])
            .args(args),
    )
}

#[test]
fn stages_json_has_the_issue_keys_and_every_stage_of_the_pipeline() {
    let j = bench_json(&["--threads", "2", "--contact", "feet"]);
    // the demo walk: 4 s at 120 fps, its 66 coordinates (euler model)
    assert_eq!(j["frames"], 480);
    assert_eq!(j["nv"], 66);
    assert_eq!(j["threads"], 2);
    assert_eq!(j["contact"], "feet");
    for key in ["stages_ms", "stages_min_ms"] {
        let stages = j[key].as_object().unwrap();
        let keys: Vec<&str> = stages.keys().map(String::as_str).collect();
        let mut expected: Vec<&str> = STAGES.iter().map(|s| s.key).collect();
        expected.sort_unstable();
        let mut keys = keys.clone();
        keys.sort_unstable();
        assert_eq!(keys, expected, "{key}");
        assert!(
            stages
                .values()
                .all(|v| v.as_f64().is_some_and(|x| x >= 0.0))
        );
    }
    // parse first, inverse dynamics last: the file to the torques
    assert_eq!(STAGES.first().unwrap().key, "parse");
    assert_eq!(STAGES.last().unwrap().key, "inverse_dynamics");
    for key in ["total_ms", "total_min_ms"] {
        assert!(j[key].as_f64().is_some_and(|x| x > 0.0), "{key}");
    }
}

#[test]
fn minutes_cycle_the_take_and_threads_one_is_reported() {
    // 0.1 min at 120 fps: 720 frames
    let j = bench_json(&["--minutes", "0.1", "--threads", "1", "--contact", "none"]);
    assert_eq!(j["frames"], 720);
    assert_eq!(j["threads"], 1);
    assert_eq!(j["contact"], "none");
    assert!(j["cycled"].as_str().unwrap().contains("720 frames"));
}

#[test]
fn the_cycled_text_plays_frames_forward_and_backward_after_frame_0() {
    let text = "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 1 Xposition\n End Site\n \
                {\n  OFFSET 0 1 0\n }\n}\nMOTION\nFrames: 4\nFrame Time: 0.5\n0\n1\n2\n3\n";
    // 0.1 min at 2 fps: 12 frames
    let (out, how) = cycle_take_text(text, 0.1, Path::new("t.bvh")).unwrap();
    assert!(out.contains("Frames: 12\n"), "{out}");
    let rows: Vec<&str> = out
        .split("Frame Time: 0.5\n")
        .nth(1)
        .unwrap()
        .lines()
        .collect();
    assert_eq!(
        rows,
        ["0", "1", "2", "3", "2", "1", "2", "3", "2", "1", "2", "3"]
    );
    assert!(how.contains("12 frames"), "{how}");
    // and the parser reads it as a take of 12 frames
    let bvh = articula::io::bvh::parse_str(&out, Path::new("t.bvh")).unwrap();
    assert_eq!(bvh.frames, 12);
}

#[test]
fn stage_flags_without_stages_or_on_a_robot_are_refused() {
    for args in [
        vec!["bench", "data/demo_walk.bvh", "--repeat", "3"],
        vec!["bench", "data/demo_walk.bvh", "--minutes", "1"],
        vec!["bench", "--stages", "data/demo_walk.bvh", "--batches", "3"],
        vec!["bench", "--stages", "--dh", "data/puma560.toml"],
    ] {
        articula()
            .current_dir(common::repo(""))
            .args(&args)
            .assert()
            .failure();
    }
    let out = articula()
        .current_dir(common::repo(""))
        .args(["bench", "--stages", "data/demo_walk.bvh", "--minutes", "-1"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert!(
        String::from_utf8_lossy(&out.stderr).contains("positive number of minutes"),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}
