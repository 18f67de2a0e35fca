//! Every session shipped in `sessions/` replays headless, passes its `expect`s, writes what it
//! says, and replays byte-identically (deterministic outputs).

mod common;

use articula::session::run_session;
use std::path::PathBuf;

fn sessions() -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(common::repo("sessions"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "session"))
        .collect();
    v.sort();
    v
}

#[test]
fn every_shipped_session_replays_and_is_deterministic() {
    let all = sessions();
    assert!(all.len() >= 3, "{all:?}");
    for s in &all {
        let (a, b) = (tempfile::tempdir().unwrap(), tempfile::tempdir().unwrap());
        let ra = run_session(s, a.path()).unwrap_or_else(|e| panic!("{}: {e}", s.display()));
        let rb = run_session(s, b.path()).unwrap();
        assert!(!ra.written.is_empty(), "{} writes nothing", s.display());
        assert_eq!(ra.written.len(), rb.written.len());
        for (pa, pb) in ra.written.iter().zip(&rb.written) {
            let (mut x, mut y) = (std::fs::read(pa).unwrap(), std::fs::read(pb).unwrap());
            assert!(!x.is_empty(), "{} is empty", pa.display());
            // a screen dump may show the output folder in its status line
            if pa.extension().is_some_and(|e| e == "txt") {
                let strip = |v: &[u8], dir: &std::path::Path| {
                    String::from_utf8_lossy(v)
                        .replace(&dir.display().to_string(), "OUT")
                        .into_bytes()
                };
                (x, y) = (strip(&x, a.path()), strip(&y, b.path()));
            }
            assert!(
                x == y,
                "{}: {} differs between replays",
                s.display(),
                pa.display()
            );
        }
    }
}

#[test]
fn knee_load_session_compares_three_body_masses_in_one_svg() {
    let out = tempfile::tempdir().unwrap();
    run_session(&common::repo("sessions/knee_load.session"), out.path()).unwrap();
    let svg = std::fs::read_to_string(out.path().join("knee_loads.svg")).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("valid SVG XML");
    let text: String = doc
        .descendants()
        .filter(|n| n.is_text())
        .map(|n| n.text().unwrap_or(""))
        .collect::<Vec<_>>()
        .join("|");
    for label in ["60 kg", "80 kg", "100 kg"] {
        assert!(
            text.contains(label),
            "{label} missing from the legend: {text}"
        );
    }
}
