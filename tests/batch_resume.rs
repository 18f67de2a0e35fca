//! An interrupted `articula batch` resumes: killed (SIGKILL) in the middle of its takes, the
//! re-run skips exactly the takes it had finished (their sidecars recorded), redoes the one it
//! was running and those it had not reached, and writes a complete summary. Each take's
//! sidecar records the version of articula that made its output.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

const TAKES: usize = 6;

fn articula() -> Command {
    Command::new(assert_cmd::cargo::cargo_bin!("articula"))
}

/// The finished takes' sidecars under `out/.batch`.
fn sidecars(out: &Path) -> Vec<PathBuf> {
    fn walk(dir: &Path, found: &mut Vec<PathBuf>) {
        for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(&p, found);
            } else if p.extension().is_some_and(|x| x == "args") {
                found.push(p);
            }
        }
    }
    let mut found = Vec::new();
    walk(&out.join(".batch"), &mut found);
    found.sort();
    found
}

fn batch(takes: &Path, out: &Path) -> Command {
    let mut c = articula();
    c.arg("batch").arg(takes).arg("-o").arg(out);
    // one at a time, each long enough to be caught in the middle
    c.args(["--jobs", "1", "--", "simulate", "--duration", "1.5"]);
    c
}

#[test]
fn a_batch_killed_mid_run_resumes_the_unfinished_takes() {
    let dir = tempfile::tempdir().unwrap();
    let takes = dir.path().join("takes");
    std::fs::create_dir_all(&takes).unwrap();
    let demo = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/demo_walk.bvh");
    for k in 0..TAKES {
        std::fs::copy(&demo, takes.join(format!("walk{k}.bvh"))).unwrap();
    }
    let out = dir.path().join("out");

    // kill the batch once its first take is done, while the others wait or run
    let mut child = batch(&takes, &out)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let deadline = Instant::now() + Duration::from_secs(300);
    while sidecars(&out).is_empty() {
        assert!(
            child.try_wait().unwrap().is_none(),
            "the batch ended before a take finished"
        );
        assert!(Instant::now() < deadline, "no take finished in 5 minutes");
        std::thread::sleep(Duration::from_millis(20));
    }
    child.kill().unwrap(); // SIGKILL
    child.wait().unwrap();
    // the killed batch's running child finishes on its own, but records no sidecar: only the
    // batch does, after a success
    let done: Vec<PathBuf> = sidecars(&out);
    assert!(
        !done.is_empty() && done.len() < TAKES,
        "killed with {} of {TAKES} takes done",
        done.len()
    );
    let recorded = std::fs::read_to_string(&done[0]).unwrap();
    assert_eq!(
        recorded.lines().next(),
        Some(format!("# articula {}", env!("CARGO_PKG_VERSION")).as_str()),
        "{recorded}"
    );
    assert!(
        !out.join("summary.csv").exists(),
        "a killed batch wrote its summary"
    );

    // the re-run: the finished takes skipped, every other one done, the summary complete
    let status = batch(&takes, &out).stdout(Stdio::null()).status().unwrap();
    assert!(status.success());
    let mut rdr = csv::Reader::from_path(out.join("summary.csv")).unwrap();
    let h: Vec<String> = rdr.headers().unwrap().iter().map(String::from).collect();
    let col = |n: &str| h.iter().position(|x| x == n).unwrap();
    let rows: Vec<csv::StringRecord> = rdr.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), TAKES);
    let skipped: Vec<String> = rows
        .iter()
        .filter(|r| &r[col("status")] == "skipped")
        .map(|r| format!("{}.args", r[col("take")].trim_end_matches(".bvh")))
        .collect();
    let done_names: Vec<String> = done
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(skipped, done_names);
    for r in &rows {
        assert!(matches!(&r[col("status")], "ok" | "skipped"), "{r:?}");
        assert!(r[col("frames")].parse::<usize>().unwrap() > 0, "{r:?}");
    }
    assert_eq!(sidecars(&out).len(), TAKES);
}
