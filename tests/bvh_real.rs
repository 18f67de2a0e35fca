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
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn real_takes_have_documented_up_unit_and_plausible_stature() {
    let takes = common::real_takes();
    println!("| file | joints | frames | up | unit | stature_m | position modes (auto) |");
    println!("|---|---|---|---|---|---|---|");
    for path in takes {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let b = bvh::read(&path).unwrap_or_else(|e| panic!("{e}"));
        // parse time (in memory, best of 5: the machine is shared)
        let bytes = std::fs::read(&path).unwrap();
        let parse_ms = (0..5)
            .map(|_| {
                let t0 = std::time::Instant::now();
                std::hint::black_box(bvh::parse_bytes(&bytes, &path).unwrap());
                t0.elapsed().as_secs_f64() * 1e3
            })
            .fold(f64::INFINITY, f64::min);
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

/// The lowest body point (file units) over every `step`-th frame, End Sites included, the
/// placement root (a root with one child, Bandai's `joint_Root`) left out.
fn lowest_point(b: &bvh::Bvh, modes: &[ResolvedPosition], up: usize, step: usize) -> f64 {
    let skip = usize::from(b.joints.iter().filter(|j| j.parent == Some(0)).count() == 1);
    (0..b.frames)
        .step_by(step)
        .map(|k| {
            let mut p = bvh::bvh_world_positions(b, modes, k);
            p.extend(bvh::bvh_end_site_positions(b, modes, k));
            p.iter()
                .skip(skip)
                .map(|x| x[up])
                .fold(f64::INFINITY, f64::min)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Highest minus lowest body point along `up` at frame `k` (file units).
fn height_at(b: &bvh::Bvh, modes: &[ResolvedPosition], up: usize, k: usize) -> f64 {
    let skip = usize::from(b.joints.iter().filter(|j| j.parent == Some(0)).count() == 1);
    let mut p = bvh::bvh_world_positions(b, modes, k);
    p.extend(bvh::bvh_end_site_positions(b, modes, k));
    let v: Vec<f64> = p.iter().skip(skip).map(|x| x[up]).collect();
    v.iter().copied().fold(f64::NEG_INFINITY, f64::max)
        - v.iter().copied().fold(f64::INFINITY, f64::min)
}

/// With the `auto` position modes every captured take touches the floor (up = 0) at some
/// frame: its lowest point over the take is within a few cm of 0 (End Sites sit at the
/// ankle or toe, not the sole, and captures have noise: 12 cm margin). Where `add` and
/// `replace` disagree (PyMO's root, all the Bandai joints) the other mode floats the body
/// (PyMO add: lowest point 0.9 m) or doubles every bone (Bandai add: a 2.7 m body): the
/// auto choice is the one the data supports. `makehuman_tpose.bvh` is left out:
/// its origin is at the pelvis, not the floor.
#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn auto_position_modes_put_the_feet_on_the_floor() {
    let takes = common::real_takes();
    for path in takes {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        if name == "makehuman_tpose.bvh" {
            continue;
        }
        let b = bvh::read(&path).unwrap();
        let up = bvh::detect_up(&b);
        let scale = bvh::detect_unit(&b, up).0.scale_to_m();
        let auto = bvh::resolve_position_modes(&b, PositionMode::Auto);
        let low = lowest_point(&b, &auto, up.index(), 1) * scale;
        assert!(
            (-0.12..0.12).contains(&low),
            "{name}: lowest point {low:.3} m"
        );
        for other in [PositionMode::Add, PositionMode::Replace] {
            let modes = bvh::resolve_position_modes(&b, other);
            let off = lowest_point(&b, &modes, up.index(), 1) * scale;
            // a zero OFFSET (CMU roots) makes both modes the same: nothing to tell apart
            if (off - low).abs() > 1e-9 {
                let height = height_at(&b, &modes, up.index(), 0) * scale;
                assert!(
                    (off - low).abs() > 0.1 || height > 2.3,
                    "{name}: {other} gives a plausible body too (lowest {off:.3} m, height {height:.2} m)"
                );
            }
        }
    }
}
