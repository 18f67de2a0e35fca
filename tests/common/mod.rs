//! Shared by the integration tests (owned by the lead; add helpers in your own test files).
#![allow(dead_code)]

pub mod alloc;
pub mod cli;
pub mod tui;
pub mod variants;
pub mod workbench;

use std::path::PathBuf;

/// `articula anatomy`'s take options as the anatomy tests load takes: ball joints, feet on the
/// floor (explicit, not auto: a take that never stands is then an error, not a silent none).
pub fn anatomy_opts() -> articula::pipeline::TakeOptions {
    articula::pipeline::TakeOptions {
        joints: "ball".parse().unwrap(),
        contact: articula::pipeline::Contact::Feet,
        ..articula::pipeline::TakeOptions::default()
    }
}

/// The real takes of `ARTICULA_REAL_TAKES` (`../shared/data/bvh` in CI), sorted by name.
///
/// The takes are not in this repository, so every test that reads them is marked
/// `#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]`:
/// README's `cargo test` lists them as ignored, with that reason, and CI runs them with
/// `-- --ignored` (`.ci/run`). When they run, an unset variable, or one naming a folder
/// without `.bvh` files, panics: the suite can never pass without its data.
pub fn real_takes() -> Vec<PathBuf> {
    let dir = std::env::var_os("ARTICULA_REAL_TAKES").unwrap_or_else(|| {
        panic!("the real-take suite needs ARTICULA_REAL_TAKES=../shared/data/bvh (the folder of real takes)")
    });
    let dir = PathBuf::from(dir);
    let mut takes: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap_or_else(|e| panic!("ARTICULA_REAL_TAKES={}: {e}", dir.display()))
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "bvh"))
        .collect();
    takes.sort();
    assert!(
        !takes.is_empty(),
        "ARTICULA_REAL_TAKES={} holds no .bvh files",
        dir.display()
    );
    takes
}

/// The real take called `name` (file name), from [`real_takes`].
pub fn real_take(name: &str) -> PathBuf {
    real_takes()
        .into_iter()
        .find(|p| p.file_name().is_some_and(|n| n == name))
        .unwrap_or_else(|| panic!("real take {name} missing from ARTICULA_REAL_TAKES"))
}

/// A path inside the repository.
pub fn repo(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(path)
}
