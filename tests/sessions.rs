//! Every session shipped in `sessions/` replays headless, passes its `expect`s, writes what it
//! says, and replays byte-identically (deterministic outputs).

mod common;

use articula::tui::run_session;
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

#[test]
fn motor_sizing_session_sizes_every_puma_joint_with_its_own_drive() {
    let out = tempfile::tempdir().unwrap();
    run_session(&common::repo("sessions/motor_sizing.session"), out.path()).unwrap();
    // the table: one row per joint, I = τ / (Km·N·η) with each joint's own drive
    let table = std::fs::read_to_string(out.path().join("puma_motors.csv")).unwrap();
    let mut rdr = csv::Reader::from_reader(table.as_bytes());
    let h: Vec<String> = rdr.headers().unwrap().iter().map(String::from).collect();
    let col = |name: &str| h.iter().position(|x| x == name).unwrap();
    let rows: Vec<csv::StringRecord> = rdr.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), 6);
    let gears = [62.6111, 107.815, 53.7063, 76.0364, 71.923, 76.686];
    for (r, n) in rows.iter().zip(gears) {
        let f = |c: &str| r[col(c)].parse::<f64>().unwrap();
        assert_eq!(f("gear"), n);
        assert_eq!(f("efficiency"), 0.9);
        let i = f("peak:tau") / (f("km") * n * 0.9);
        assert!((f("peak:current") - i).abs() <= 1e-12 * i.abs().max(1.0));
    }
    assert_eq!(&rows[1][col("class")], "BLDC-80 (600 W)");
    // the curves: time and four columns per joint, current = τ/(Km·N·η) sample by sample
    let text = std::fs::read_to_string(out.path().join("puma_motor_curves.csv")).unwrap();
    let (h, cols) =
        articula::report::csv::parse_columns(&text, std::path::Path::new("c.csv")).unwrap();
    assert_eq!(h.len(), 1 + 6 * 5);
    let (tau, cur) = (
        h.iter().position(|x| x == "tau:j2").unwrap(),
        h.iter().position(|x| x == "current:j2").unwrap(),
    );
    assert_eq!(cols[0].len(), 2251);
    for k in [0, 700, 2250] {
        let want = cols[tau][k] / (0.26 * 107.815 * 0.9);
        assert!((cols[cur][k] - want).abs() < 1e-12, "{k}");
    }
    // the chart: four panels and the table
    let svg = std::fs::read_to_string(out.path().join("puma_motors.svg")).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("valid SVG XML");
    let texts: Vec<&str> = doc
        .descendants()
        .filter(|n| n.is_text())
        .filter_map(|n| n.text())
        .collect();
    for want in [
        "Joint torque",
        "Joint speed ω",
        "Joint power τ·ω: driving (> 0) and regenerating (< 0)",
        "Motor current I = τ_m/Km",
        "Torque–speed on the motor shaft against the class's envelope",
        "BLDC-80 (600 W)",
        "j6",
    ] {
        assert!(texts.iter().any(|t| t.trim() == want), "no {want:?}");
    }
}
