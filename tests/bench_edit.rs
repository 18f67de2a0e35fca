//! `articula bench TAKE --edit SETTING=V1,V2`: the instrument for issue 17's workbench-edit
//! targets. It replays `set SETTING V` + `run id` on a take loaded once, and says what each
//! edit reran, counted by the pipeline's own stage reports: a body-mass edit rebuilds the
//! model and reruns the contact stage, never the smoothing. Times are not asserted (speed
//! lives in benchmarks).

mod common;

use common::cli::{articula, json_of};

fn edit_json(args: &[&str]) -> serde_json::Value {
    json_of(
        articula()
            .arg("bench")
            .arg(common::repo("data/demo_walk.bvh"))
            .args(["--repeat", "3", "--json"])
            .args(args),
    )
}

#[test]
fn a_mass_edit_is_timed_and_reruns_the_model_and_contact_but_not_the_smoothing() {
    let j = edit_json(&[
        "--edit",
        "body.mass=80,70",
        "--contact",
        "feet",
        "--set",
        "consistent=off",
    ]);
    assert_eq!(j["frames"], 480);
    assert_eq!(j["nv"], 66);
    assert_eq!(j["contact"], "feet");
    assert_eq!(j["edit"], "body.mass");
    assert_eq!(j["before"]["consistent"], "off");
    let ms = j["edit_ms"].as_array().unwrap();
    assert_eq!(ms.len(), 3);
    assert!(ms.iter().all(|t| t.as_f64().unwrap() > 0.0), "{ms:?}");
    let reran = j["reran"].as_object().unwrap();
    assert_eq!(reran["model"], 1.0, "{reran:?}");
    assert_eq!(reran["contact"], 1.0, "{reran:?}");
    for kept in ["parse", "coordinates", "unwrap", "smooth", "derivatives"] {
        assert!(!reran.contains_key(kept), "{kept} reran: {reran:?}");
    }

    // without reduction: no preview (nothing to preview)
    assert_eq!(j["preview_ms"].as_array().unwrap().len(), 0);
    assert!(j["preview_median_ms"].is_null());

    // with residual reduction (the default): each edit draws a preview first, timed apart,
    // and the preview's stages are not counted as the edit's
    let j = edit_json(&["--edit", "body.mass=80,70", "--contact", "feet"]);
    let preview = j["preview_ms"].as_array().unwrap();
    assert_eq!(preview.len(), 3, "{j}");
    for (p, e) in preview.iter().zip(j["edit_ms"].as_array().unwrap()) {
        assert!(p.as_f64().unwrap() > 0.0 && p.as_f64() < e.as_f64(), "{j}");
    }
    assert!(j["preview_median_ms"].as_f64().is_some());
    assert_eq!(j["reran"]["contact"], 1.0, "{j}");

    // without contact: inverse dynamics instead of the contact stage
    let j = edit_json(&["--edit", "body.mass=80,70", "--contact", "none"]);
    assert_eq!(j["contact"], "none");
    assert_eq!(j["preview_ms"].as_array().unwrap().len(), 0);
    let reran = j["reran"].as_object().unwrap();
    assert_eq!(reran["inverse_dynamics"], 1.0, "{reran:?}");
    assert!(!reran.contains_key("contact"), "{reran:?}");
}

#[test]
fn an_edit_that_changes_nothing_or_a_set_without_edit_is_refused() {
    for args in [
        vec!["bench", "data/demo_walk.bvh", "--edit", "body.mass=80"],
        vec!["bench", "data/demo_walk.bvh", "--edit", "body.mass=80,80"],
        vec!["bench", "data/demo_walk.bvh", "--edit", "body.mass"],
        vec!["bench", "data/demo_walk.bvh", "--set", "consistent=off"],
        vec![
            "bench",
            "data/demo_walk.bvh",
            "--edit",
            "body.mass=80,70",
            "--stages",
        ],
        vec!["bench", "data/demo_walk.bvh", "--edit", "nosuch=1,2"],
    ] {
        articula()
            .current_dir(common::repo(""))
            .args(&args)
            .assert()
            .failure();
    }
}

/// Regression: a take given relative to the working folder was read relative to its own
/// folder a second time (`data/data/demo_walk.bvh: No such file`).
#[test]
fn a_take_given_by_a_relative_path_is_found() {
    let out = articula()
        .current_dir(common::repo(""))
        .args(["bench", "data/demo_walk.bvh", "--edit", "body.mass=80,70"])
        .args(["--contact", "none", "--repeat", "1"])
        .assert()
        .success();
    let text = String::from_utf8_lossy(&out.get_output().stdout).into_owned();
    assert!(text.contains("480 frames"), "{text}");
}
