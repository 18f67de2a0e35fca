//! The `articula` binary for the end-to-end tests, and the takes they generate with it.

use assert_cmd::Command;
use std::path::{Path, PathBuf};

/// The binary built from this crate.
pub fn articula() -> Command {
    Command::cargo_bin("articula").expect("binary")
}

/// A generated walk of `secs` seconds at 60 fps in `dir`.
pub fn walk(dir: &Path, secs: f64) -> PathBuf {
    let p = dir.join("walk.bvh");
    articula()
        .args(["generate", "walk", "--fps", "60", "--duration"])
        .arg(secs.to_string())
        .arg("-o")
        .arg(&p)
        .assert()
        .success();
    p
}

/// Runs `cmd`, asserts it succeeded (its stderr is the failure message) and parses its
/// standard output as JSON.
pub fn json_of(cmd: &mut Command) -> serde_json::Value {
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).unwrap()
}
