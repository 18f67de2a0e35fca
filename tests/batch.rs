//! `articula batch`: one take command over a folder of takes, each in a child process.
//!
//! A failing take is a row with its error, never the end of the batch; a re-run skips what is up
//! to date and `--force` redoes it; a sweep gives one row per take × setting. The takes are two
//! copies of the bundled demo walk (in subfolders) and a corrupt file.

use articula::report::csv::read_columns;
use assert_cmd::Command;
use std::path::{Path, PathBuf};

fn articula() -> Command {
    Command::cargo_bin("articula").expect("binary")
}

fn demo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/demo_walk.bvh")
}

/// `dir/takes/{a,b}/walk.bvh` (the demo) and `dir/takes/broken.bvh`.
fn corpus(dir: &Path) -> PathBuf {
    let takes = dir.join("takes");
    for sub in ["a", "b"] {
        std::fs::create_dir_all(takes.join(sub)).unwrap();
        std::fs::copy(demo(), takes.join(sub).join("walk.bvh")).unwrap();
    }
    std::fs::write(
        takes.join("broken.bvh"),
        "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0\n",
    )
    .unwrap();
    takes
}

/// The summary as (header, rows of cells).
fn summary(out: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut rdr = csv::Reader::from_path(out.join("summary.csv")).expect("summary.csv");
    let header = rdr.headers().unwrap().iter().map(String::from).collect();
    let rows = rdr
        .records()
        .map(|r| r.unwrap().iter().map(String::from).collect())
        .collect();
    (header, rows)
}

fn cell<'a>(header: &[String], row: &'a [String], name: &str) -> &'a str {
    let i = header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"));
    &row[i]
}

fn statuses(out: &Path) -> Vec<(String, String)> {
    let (h, rows) = summary(out);
    rows.iter()
        .map(|r| {
            (
                cell(&h, r, "take").to_string(),
                cell(&h, r, "status").to_string(),
            )
        })
        .collect()
}

#[test]
fn a_corrupt_take_is_a_failed_row_and_the_rest_are_done_then_resumed_and_forced() {
    let dir = tempfile::tempdir().unwrap();
    let takes = corpus(dir.path());
    let out = dir.path().join("out");
    let batch = |extra: &[&str]| {
        let mut c = articula();
        c.arg("batch").arg(&takes).arg("-o").arg(&out);
        c.args(["--jobs", "2"]).args(extra).args(["--", "id"]);
        c
    };

    // first run: two ok, the corrupt one failed with its error; exit status non-zero
    let first = batch(&["--json"]).assert().code(1);
    let (h, rows) = summary(&out);
    let json: serde_json::Value = serde_json::from_slice(&first.get_output().stdout).unwrap();
    assert_eq!(json[2]["status"], "failed");
    assert!(
        json[2]["failure"].as_str().unwrap().contains("broken.bvh"),
        "{json}"
    );
    assert_eq!(
        statuses(&out),
        [
            ("a/walk.bvh".into(), "ok".into()),
            ("b/walk.bvh".into(), "ok".into()),
            ("broken.bvh".into(), "failed".into()),
        ]
    );
    assert!(
        cell(&h, &rows[2], "failure").contains("broken.bvh"),
        "{rows:?}"
    );
    for r in &rows[..2] {
        assert_eq!(cell(&h, r, "frames"), "480");
        let peak: f64 = cell(&h, r, "peak:residual:tx").parse().unwrap();
        assert!(peak > 1.0, "root residual moment peak {peak}");
    }
    for sub in ["a", "b"] {
        let (_, cols) = read_columns(&out.join(sub).join("walk.csv")).unwrap();
        assert_eq!(cols[0].len(), 480);
        assert!(out.join(sub).join("walk.bvh.log").exists());
    }
    assert!(out.join("broken.bvh.log").exists());

    // re-run: the done takes are skipped, the broken one tried again
    batch(&[]).assert().code(1);
    let s = statuses(&out);
    assert_eq!(s[0].1, "skipped");
    assert_eq!(s[1].1, "skipped");
    assert_eq!(s[2].1, "failed");

    // other options are not the same run: redone, then up to date again
    let with_mass = |c: &mut Command| {
        c.args(["--mass", "90"]);
    };
    let mut c = batch(&[]);
    with_mass(&mut c);
    c.assert().code(1);
    assert_eq!(statuses(&out)[0].1, "ok");
    let mut c = batch(&[]);
    with_mass(&mut c);
    c.assert().code(1);
    assert_eq!(statuses(&out)[0].1, "skipped");

    // --force redoes them
    batch(&["--force"]).assert().code(1);
    let s = statuses(&out);
    assert_eq!(s[0].1, "ok");
    assert_eq!(s[1].1, "ok");
}

#[test]
fn a_sweep_has_one_row_per_take_and_setting_with_its_own_figures() {
    let dir = tempfile::tempdir().unwrap();
    let takes = corpus(dir.path());
    let out = dir.path().join("out");
    std::fs::remove_file(takes.join("broken.bvh")).unwrap();
    let assert = articula()
        .arg("batch")
        .arg(&takes)
        .arg("-o")
        .arg(&out)
        .args([
            "--jobs",
            "2",
            "--json",
            "--vary",
            "mass=60,100",
            "--",
            "anatomy",
        ])
        .assert()
        .success();
    let (h, rows) = summary(&out);
    assert_eq!(rows.len(), 2 * 2, "{rows:?}");
    assert!(h.contains(&"setting:mass".to_string()), "{h:?}");
    let peak = |r: &[String]| -> f64 { cell(&h, r, "peak:moment:knee_l:flexion").parse().unwrap() };
    let light = rows
        .iter()
        .find(|r| cell(&h, r, "setting:mass") == "60")
        .unwrap();
    let heavy = rows
        .iter()
        .find(|r| cell(&h, r, "setting:mass") == "100")
        .unwrap();
    assert!(
        peak(heavy) > 1.2 * peak(light),
        "{} vs {}",
        peak(heavy),
        peak(light)
    );
    for sub in ["a", "b"] {
        assert!(out.join(sub).join("walk__mass=60.csv").exists());
        assert!(out.join(sub).join("walk__mass=100.csv").exists());
    }

    // --json: the same rows on standard output, under the CSV's column names, figures as
    // numbers (the CSV's own text, parsed)
    let json: serde_json::Value = serde_json::from_slice(&assert.get_output().stdout).unwrap();
    let list = json.as_array().unwrap();
    assert_eq!(list.len(), rows.len());
    for (r, row) in list.iter().zip(&rows) {
        let object = r.as_object().unwrap();
        let mut keys: Vec<&String> = object.keys().collect();
        let mut columns: Vec<&String> = h.iter().collect();
        keys.sort();
        columns.sort();
        assert_eq!(keys, columns, "{r}");
        for (column, text) in h.iter().zip(row) {
            let v = &r[column.as_str()];
            match v.as_f64() {
                Some(x) => assert_eq!(x, text.parse::<f64>().unwrap(), "{column}: {v} vs {text}"),
                None if text.is_empty() && !v.is_string() => assert!(v.is_null(), "{column}"),
                None => assert_eq!(v.as_str(), Some(text.as_str()), "{column}"),
            }
        }
        assert!(r["wall_time"].is_number() && r["frames"].is_u64(), "{r}");
        assert_eq!(r["status"], "ok");
    }
}

#[test]
fn info_is_captured_from_its_json_for_the_takes_of_a_list() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let list = dir.path().join("list.txt");
    std::fs::write(&list, format!("# the demo\n{}\n", demo().display())).unwrap();
    articula()
        .arg("batch")
        .arg(format!("@{}", list.display()))
        .arg("-o")
        .arg(&out)
        .args(["--", "info"])
        .assert()
        .success();
    let (h, rows) = summary(&out);
    assert_eq!(rows.len(), 1);
    assert_eq!(cell(&h, &rows[0], "status"), "ok");
    assert_eq!(cell(&h, &rows[0], "frames"), "480");
    let text = std::fs::read_to_string(out.join("demo_walk.json")).unwrap();
    let info: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(info["frames"], 480);
}

#[test]
fn a_command_batch_cannot_run_is_refused_up_front() {
    let dir = tempfile::tempdir().unwrap();
    articula()
        .arg("batch")
        .arg(demo())
        .arg("-o")
        .arg(dir.path())
        .args(["--", "blend"])
        .assert()
        .code(2)
        .stderr(predicates::str::contains("not a take command"));
}

#[test]
fn a_diverged_simulation_is_a_failed_row_beside_the_settings_that_track() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    articula()
        .arg("batch")
        .arg(demo())
        .arg("-o")
        .arg(&out)
        .args(["--jobs", "2", "--vary", "dt=0.001,0.2", "--"])
        .args(["simulate", "--integrator", "euler", "--duration", "1"])
        .assert()
        .code(1);
    let (h, rows) = summary(&out);
    assert_eq!(rows.len(), 2);
    let fine = rows
        .iter()
        .find(|r| cell(&h, r, "setting:dt") == "0.001")
        .unwrap();
    let coarse = rows
        .iter()
        .find(|r| cell(&h, r, "setting:dt") == "0.2")
        .unwrap();
    assert_eq!(cell(&h, fine, "status"), "ok");
    assert_eq!(cell(&h, coarse, "status"), "failed");
    assert!(
        cell(&h, coarse, "failure").contains("diverged"),
        "{coarse:?}"
    );
    assert!(out.join("demo_walk__dt=0.001.csv").exists());
}

/// The issue's own command line, without `--` before the take command:
/// `articula batch TAKES -o OUT id --contact auto` runs `id --contact auto` on every take.
#[test]
fn the_take_command_may_follow_the_inputs_without_a_separator() {
    let dir = tempfile::tempdir().unwrap();
    let takes = corpus(dir.path());
    let out = dir.path().join("out");
    articula()
        .arg("batch")
        .arg(&takes)
        .arg("-o")
        .arg(&out)
        .args(["--jobs", "2", "id", "--contact", "auto"])
        .assert()
        .failure(); // the corpus holds a corrupt take
    let rows = statuses(&out);
    assert_eq!(
        rows.iter().filter(|(_, s)| s == "ok").count(),
        2,
        "{rows:?}"
    );
    assert_eq!(
        rows.iter().filter(|(_, s)| s == "failed").count(),
        1,
        "{rows:?}"
    );
}

/// Issue 16: a batch's `info` (`<take>.json`) and `id` (`<take>.csv` and its sidecar
/// `<take>.csv.json`) into one folder keep both: the sidecar's name is the CSV's whole name
/// with `.json` added, so it never takes another output's.
#[test]
fn info_and_id_into_one_folder_keep_both_their_json() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    for command in [&["info"][..], &["id", "--contact", "none"][..]] {
        articula()
            .arg("batch")
            .arg(demo())
            .arg("-o")
            .arg(&out)
            .arg("--")
            .args(command)
            .assert()
            .success();
    }
    let read = |name: &str| -> serde_json::Value {
        let text = std::fs::read_to_string(out.join(name)).unwrap();
        serde_json::from_str(&text).unwrap()
    };
    // info's own JSON, untouched by id's sidecar
    assert_eq!(read("demo_walk.json")["frames"], 480);
    let side = read("demo_walk.csv.json");
    assert_eq!(side["command"], "id");
    assert_eq!(side["file"], "demo_walk.csv");
    assert_eq!(side["columns"][0]["name"], "time");
    let (header, _) = read_columns(&out.join("demo_walk.csv")).unwrap();
    assert_eq!(side["columns"].as_array().unwrap().len(), header.len());
}
