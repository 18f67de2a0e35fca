//! Every real take in `ARTICULA_REAL_TAKES` parses, and gets the up axis, length unit,
//! plausible stature and position-channel modes that its provenance (shared/data/bvh/
//! SOURCES.md) documents. Without the variable the test does nothing (fresh machines).
//! `cargo test --test bvh_real -- --nocapture` prints the table.

mod common;

use articula::io::bvh::{self, LengthUnit, PositionMode, ResolvedPosition, UpAxis};

/// (file, up, unit) as documented in SOURCES.md.
const EXPECTED: &[(&str, UpAxis, LengthUnit)] = &[
    ("AV_8Walk_Meredith_HVHA_Rep1.bvh", UpAxis::Y, LengthUnit::In),
    ("cmu_01_01.bvh", UpAxis::Y, LengthUnit::Cmu),
    ("cmu_05_20-daz.bvh", UpAxis::Y, LengthUnit::Cm),
    ("cmu_05_20-mb.bvh", UpAxis::Y, LengthUnit::Cmu),
    ("dataset-1_bye_old_001.bvh", UpAxis::Y, LengthUnit::Cm),
    ("dataset-1_kick_normal_001.bvh", UpAxis::Y, LengthUnit::Cm),
    ("dataset-1_run_normal_001.bvh", UpAxis::Y, LengthUnit::Cm),
    ("dataset-1_walk_normal_001.bvh", UpAxis::Y, LengthUnit::Cm),
    ("makehuman_tpose.bvh", UpAxis::Z, LengthUnit::Dm),
    ("makehuman_walk1.bvh", UpAxis::Z, LengthUnit::Dm),
    ("pfnn_hierarchy.bvh", UpAxis::Y, LengthUnit::M),
    ("pirouette.bvh", UpAxis::Y, LengthUnit::Cm),
];

#[test]
fn real_takes_have_documented_up_unit_and_plausible_stature() {
    let Some(takes) = common::real_takes() else {
        return;
    };
    println!("| file | joints | frames | up | unit | stature_m | position modes (auto) |");
    println!("|---|---|---|---|---|---|---|");
    for path in takes {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let t0 = std::time::Instant::now();
        let b = bvh::read(&path).unwrap_or_else(|e| panic!("{e}"));
        let parse_ms = t0.elapsed().as_secs_f64() * 1e3;
        let up = bvh::detect_up(&b);
        let (unit, stature_m) = bvh::detect_unit(&b, up);
        let modes = bvh::resolve_position_modes(&b, PositionMode::Auto);
        let mut counts = std::collections::BTreeMap::new();
        for (j, m) in b.joints.iter().zip(&modes) {
            if *m != ResolvedPosition::None {
                let who = if j.parent.is_none() { "root" } else { "other" };
                *counts.entry(format!("{who} {m}")).or_insert(0) += 1;
            }
        }
        println!(
            "| {name} | {} | {} | {up} | {unit} | {stature_m:.3} | {counts:?} | ({parse_ms:.1} ms)",
            b.joints.len(),
            b.frames
        );
        let &(_, want_up, want_unit) = EXPECTED
            .iter()
            .find(|e| e.0 == name)
            .unwrap_or_else(|| panic!("{name}: add it to EXPECTED"));
        assert_eq!(up, want_up, "{name}");
        assert_eq!(unit, want_unit, "{name}");
        bvh::check_stature(stature_m).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(b.motion.iter().all(|v| v.is_finite()));
        // position semantics documented in SOURCES.md
        let non_root: Vec<ResolvedPosition> = modes[1..]
            .iter()
            .copied()
            .filter(|m| *m != ResolvedPosition::None)
            .collect();
        if name.starts_with("dataset-1") {
            assert!(
                modes.iter().all(|m| *m == ResolvedPosition::Replace),
                "{name}"
            );
        }
        if name == "makehuman_tpose.bvh" {
            assert_eq!(non_root.len(), 143);
            assert!(non_root.iter().all(|m| *m == ResolvedPosition::Add));
        }
        if name.starts_with("AV_8Walk") {
            assert_eq!(
                modes[0],
                ResolvedPosition::Replace,
                "PyMO root position is absolute"
            );
        }
        if name == "makehuman_walk1.bvh" {
            assert_eq!(
                modes[0],
                ResolvedPosition::Add,
                "Root OFFSET plus zero deltas"
            );
        }
    }
}
