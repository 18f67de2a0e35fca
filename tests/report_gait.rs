//! The clinical gait view (report::gait): cycles from one foot strike to the next, moments
//! time-normalised to 0…100 % and averaged with their SD, stance from the toe-off; the
//! Schwartz 2008 band chosen by dimensionless speed; a side without two strikes is a note, a
//! take without any cycle an error; reachable from `report gait` and `anatomy --gait`.

mod common;

use articula::pipeline::anatomy::Anatomy;
use articula::report::chart::ImageFormat;
use articula::report::gait::{GaitContext, gait_chart, normative_bands, side_cycles, speed_class};

/// Four 1 s cycles at 100 Hz: the foot is down for the first 60 % of each (strikes at frames
/// 100, 200, 300, 400); the knee moment is `sin 2πt` (N·m/kg), the same in every cycle.
fn walker(right_strikes: bool) -> Anatomy {
    let time: Vec<f64> = (0..=450).map(|k| k as f64 / 100.0).collect();
    let left: Vec<bool> = (0..time.len()).map(|k| k >= 100 && k % 100 < 60).collect();
    // the right foot lands once only (or never)
    let right: Vec<bool> = (0..time.len())
        .map(|k| right_strikes && (150..210).contains(&k))
        .collect();
    let m: Vec<f64> = time
        .iter()
        .map(|t| (2.0 * std::f64::consts::PI * t).sin())
        .collect();
    Anatomy {
        names: vec![
            "knee_l:flexion:moment_per_kg".into(),
            "knee_r:flexion:moment_per_kg".into(),
        ],
        columns: vec![m.clone(), m],
        time,
        mass_kg: 70.0,
        notes: vec![],
        contact: vec![("left".into(), left), ("right".into(), right)],
        consistency: None,
        edge: 0,
        include_edges: false,
    }
}

#[test]
fn cycles_are_normalised_averaged_and_their_stance_measured() {
    let a = walker(true);
    let s = side_cycles(&a, "left", &a.contact[0].1).unwrap();
    assert_eq!(s.cycles, 3);
    assert!((s.stance_pct - 60.0).abs() < 1e-9, "{}", s.stance_pct);
    let knee = &s.joints[0];
    assert_eq!(knee.joint, "knee");
    assert_eq!(knee.mean.len(), 101);
    // every cycle is the same sine: the mean is sin(2π p/100), the SD zero
    for p in [0, 25, 50, 75, 100] {
        let want = (2.0 * std::f64::consts::PI * p as f64 / 100.0).sin();
        assert!((knee.mean[p] - want).abs() < 1e-9, "{p}: {}", knee.mean[p]);
        assert!(knee.sd[p].abs() < 1e-9);
    }
}

#[test]
fn a_side_with_one_strike_is_a_note_and_no_cycle_at_all_an_error() {
    let a = walker(true);
    let (svg, notes) = gait_chart(&a, &GaitContext::default(), ImageFormat::Svg).unwrap();
    assert!(
        notes[0].starts_with("left: 3 cycles, stance 60 %"),
        "{notes:?}"
    );
    assert!(
        notes
            .iter()
            .any(|n| n.contains("right foot: 1 foot strike")),
        "{notes:?}"
    );
    let svg = String::from_utf8(svg).unwrap();
    assert!(svg.contains("left (3 cycles)") && !svg.contains("right ("));
    assert!(svg.contains("Knee extensor (+) / flexor (−) moment"));
    let mut none = walker(false);
    none.contact.truncate(1);
    none.contact[0].1 = vec![false; none.time.len()];
    let err = gait_chart(&none, &GaitContext::default(), ImageFormat::Svg).unwrap_err();
    assert!(err.to_string().contains("no gait cycle"), "{err}");
    assert!(err.to_string().contains("0 foot strike"), "{err}");
}

#[test]
fn the_normative_band_is_the_nearest_speed_class() {
    let bands = normative_bands().unwrap();
    assert_eq!(bands.len(), 15);
    for b in &bands {
        assert_eq!(b.percent.len(), 51);
        assert_eq!(b.lower.len(), 51);
        assert!(
            b.lower.iter().zip(&b.upper).all(|(l, u)| l <= u),
            "{}",
            b.class
        );
        assert!(b.upper.iter().all(|u| u.abs() < 3.0), "N·m/kg, not N·mm/kg");
    }
    // Schwartz et al.'s free-speed knee: an extensor peak in loading response
    let knee = bands
        .iter()
        .find(|b| b.class == "Free" && b.joint == "knee")
        .unwrap();
    let (k, _) = knee.percent[..16]
        .iter()
        .enumerate()
        .max_by(|a, b| {
            (knee.lower[a.0] + knee.upper[a.0]).total_cmp(&(knee.lower[b.0] + knee.upper[b.0]))
        })
        .unwrap();
    let peak = (knee.lower[k] + knee.upper[k]) / 2.0;
    assert!((0.2..0.6).contains(&peak), "{peak}");
    assert_eq!(speed_class(&bands, 0.43), Some("Free"));
    assert_eq!(speed_class(&bands, 0.37), Some("Free"));
    assert_eq!(speed_class(&bands, 0.30), Some("Slow"));
    assert_eq!(speed_class(&bands, 0.05), None);
    assert_eq!(speed_class(&bands, 0.9), None);
    // drawn with its legend entry when the speed is known
    let ctx = GaitContext {
        dimensionless_speed: Some(0.43),
        caption: Some("take t"),
    };
    let (svg, _) = gait_chart(&walker(true), &ctx, ImageFormat::Svg).unwrap();
    let svg = String::from_utf8(svg).unwrap();
    assert!(svg.contains("Schwartz 2008 Free"));
    assert!(svg.contains("walking speed v/√(g·leg) 0.43"));
}

#[test]
fn report_gait_session_writes_svg_and_png() {
    let out = tempfile::tempdir().unwrap();
    let r = articula::tui::run_session(&common::repo("sessions/gait_report.session"), out.path())
        .unwrap();
    assert_eq!(r.written.len(), 2);
    let svg = std::fs::read_to_string(out.path().join("gait.svg")).unwrap();
    for want in [
        "Hip extensor (+) / flexor (−) moment",
        "Knee extensor (+) / flexor (−) moment",
        "Ankle plantarflexor (+) / dorsiflexor (−) moment",
        "gait cycle (%)",
        "left (2 cycles)",
        "right (3 cycles)",
        "Schwartz 2008 Free",
    ] {
        assert!(svg.contains(want), "no {want:?}");
    }
    let png = std::fs::read(out.path().join("gait.png")).unwrap();
    assert_eq!(&png[..8], b"\x89PNG\r\n\x1a\n");
}

#[test]
fn anatomy_gait_flag_writes_the_view_and_refuses_other_formats() {
    let dir = tempfile::tempdir().unwrap();
    let take = common::repo("data/demo_walk.bvh");
    let ok = common::cli::articula()
        .arg("anatomy")
        .arg(&take)
        .args(["--contact", "feet", "-o"])
        .arg(dir.path().join("a.csv"))
        .arg("--gait")
        .arg(dir.path().join("g.svg"))
        .output()
        .unwrap();
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    let svg = std::fs::read_to_string(dir.path().join("g.svg")).unwrap();
    assert!(svg.contains("Knee extensor (+) / flexor (−) moment"));
    assert!(
        svg.contains("joints ball"),
        "the caption says the joint model"
    );
    let bad = common::cli::articula()
        .arg("anatomy")
        .arg(&take)
        .args(["--contact", "feet", "-o"])
        .arg(dir.path().join("b.csv"))
        .arg("--gait")
        .arg(dir.path().join("g.pdf"))
        .output()
        .unwrap();
    assert!(!bad.status.success());
    let err = String::from_utf8_lossy(&bad.stderr);
    assert!(err.contains("written as .svg or .png"), "{err}");
}
