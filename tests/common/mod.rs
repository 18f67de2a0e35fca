//! Shared by the integration tests (owned by the lead; add helpers in your own test files).
#![allow(dead_code)]

use std::path::PathBuf;

/// The real takes of `ARTICULA_REAL_TAKES` (`../shared/data/bvh` in CI), sorted by name.
///
/// Unset variable: `None` (the default suite runs on a fresh machine without the data).
/// Set but naming a folder without `.bvh` files: panics, so CI cannot pass by accident.
pub fn real_takes() -> Option<Vec<PathBuf>> {
    let dir = std::env::var_os("ARTICULA_REAL_TAKES")?;
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
    Some(takes)
}

/// The real take called `name` (file name), if the real-take suite is on.
pub fn real_take(name: &str) -> Option<PathBuf> {
    let takes = real_takes()?;
    Some(
        takes
            .into_iter()
            .find(|p| p.file_name().is_some_and(|n| n == name))
            .unwrap_or_else(|| panic!("real take {name} missing from ARTICULA_REAL_TAKES")),
    )
}

/// A path inside the repository.
pub fn repo(path: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(path)
}
