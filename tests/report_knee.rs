//! Knee-load comparison across body weights (the paper's figure 5): the chart holds one curve
//! and one legend entry per mass, the table gives max |τ| with its time and the time-weighted
//! RMS, the CSV round-trips exactly, and the same input gives the same bytes.

use articula::report::csv::parse_columns;
use articula::report::knee::{
    LoadRow, MassRun, curves_csv, knee_svg, knee_svg_with_table, load_row, load_table,
    load_table_csv, mass_label,
};
use std::f64::consts::PI;
use std::path::Path;

/// A knee torque that scales with body mass: τ = (m/80)·(10 + 40 sin 2πt) over one second.
fn runs() -> Vec<MassRun> {
    let t: Vec<f64> = (0..=1000).map(|i| i as f64 / 1000.0).collect();
    [60.0, 80.0, 100.0]
        .iter()
        .map(|&m| MassRun {
            mass_kg: m,
            tau: t
                .iter()
                .map(|&t| m / 80.0 * (10.0 + 40.0 * (2.0 * PI * t).sin()))
                .collect(),
            t: t.clone(),
            quoted: vec![],
            residual_pct: None,
        })
        .collect()
}

fn texts(svg: &str) -> Vec<String> {
    let doc = roxmltree::Document::parse(svg).expect("SVG is well-formed XML");
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| n.text().unwrap_or("").trim().to_string())
        .collect()
}

#[test]
fn peak_and_rms_match_the_closed_form() {
    // τ = k(10 + 40 sin 2πt): peak |τ| = 50k at t = 0.25;
    // mean of τ² over a period = k²(100 + 1600/2) = 900 k² → RMS = 30k
    for (run, row) in runs().iter().zip(load_table(&runs()).unwrap()) {
        let k = run.mass_kg / 80.0;
        assert_eq!(row.mass_kg, run.mass_kg);
        assert!((row.peak_nm - 50.0 * k).abs() < 1e-9, "{row:?}");
        assert_eq!(row.peak_time_s, 0.25);
        assert!((row.rms_nm - 30.0 * k).abs() < 1e-3 * k, "{row:?}");
    }
}

#[test]
fn rms_is_time_weighted_on_uneven_samples() {
    // τ = 2 on [0, 1] (samples at 0, 0.1, 1), then a linear ramp to 0 at t = 3
    let run = MassRun {
        mass_kg: 70.0,
        t: vec![0.0, 0.1, 1.0, 3.0],
        tau: vec![2.0, 2.0, 2.0, 0.0],
        quoted: vec![],
        residual_pct: None,
    };
    let row = load_row(&run).unwrap();
    // trapezoid: 0.1·4 + 0.9·4 + 2·(4 + 0)/2 = 8 over T = 3
    assert!((row.rms_nm - (8.0f64 / 3.0).sqrt()).abs() < 1e-12);
    assert_eq!(row.peak_nm, 2.0);
    assert_eq!(row.peak_time_s, 0.0);
    // a negative peak counts by magnitude
    let neg = MassRun {
        mass_kg: 70.0,
        t: vec![0.0, 1.0],
        tau: vec![1.0, -3.0],
        quoted: vec![],
        residual_pct: None,
    };
    let row = load_row(&neg).unwrap();
    assert_eq!((row.peak_nm, row.peak_time_s), (3.0, 1.0));
    // one sample
    let one = MassRun {
        mass_kg: 70.0,
        t: vec![0.0],
        tau: vec![-4.0],
        quoted: vec![],
        residual_pct: None,
    };
    assert_eq!(load_row(&one).unwrap().rms_nm, 4.0);
}

#[test]
fn bad_runs_are_errors() {
    let bad = |mass_kg: f64, t: Vec<f64>, tau: Vec<f64>| {
        load_row(&MassRun {
            mass_kg,
            t,
            tau,
            quoted: vec![],
            residual_pct: None,
        })
    };
    assert!(bad(0.0, vec![0.0], vec![1.0]).is_err());
    assert!(bad(f64::NAN, vec![0.0], vec![1.0]).is_err());
    assert!(bad(60.0, vec![], vec![]).is_err());
    assert!(bad(60.0, vec![0.0, 1.0], vec![1.0]).is_err());
    assert!(bad(60.0, vec![0.0, 1.0], vec![1.0, f64::NAN]).is_err());
    let back = bad(60.0, vec![0.0, 1.0, 0.5], vec![1.0, 1.0, 1.0]).unwrap_err();
    assert!(back.to_string().contains("sample 2"), "{back}");
    assert!(knee_svg("knee", &[]).is_err());
}

#[test]
fn chart_has_one_legend_entry_per_mass_and_the_table() {
    let svg = knee_svg_with_table("right knee", &runs()).unwrap();
    let all = texts(&svg);
    for want in ["60 kg", "80 kg", "100 kg", "time (s)", "joint torque (N·m)"] {
        assert!(all.iter().any(|t| t == want), "no {want:?} in {all:?}");
    }
    assert!(all.iter().any(|t| t.contains("right knee")));
    // table: header and the peak of each mass (50·m/80 N·m)
    for want in [
        "mass (kg)",
        "peak |τ| (N·m)",
        "RMS τ (N·m)",
        "37.50",
        "50.00",
        "62.50",
    ] {
        assert!(all.iter().any(|t| t == want), "no {want:?} in table");
    }
    // the curves alone carry no table
    let plain = texts(&knee_svg("right knee", &runs()).unwrap());
    assert!(!plain.iter().any(|t| t == "mass (kg)"));
    assert!(plain.iter().any(|t| t == "100 kg"));
}

#[test]
fn deterministic_bytes() {
    assert_eq!(
        knee_svg_with_table("knee", &runs()).unwrap(),
        knee_svg_with_table("knee", &runs()).unwrap()
    );
}

#[test]
fn table_csv_round_trips() {
    let rows = load_table(&runs()).unwrap();
    let text = load_table_csv(&rows);
    let (h, cols) = parse_columns(&text, Path::new("t.csv")).unwrap();
    assert_eq!(
        h,
        ["mass_kg", "peak_abs_tau_Nm", "rms_tau_Nm", "peak_time_s"]
    );
    let back: Vec<LoadRow> = (0..rows.len())
        .map(|i| LoadRow {
            mass_kg: cols[0][i],
            peak_nm: cols[1][i],
            rms_nm: cols[2][i],
            peak_time_s: cols[3][i],
        })
        .collect();
    assert_eq!(back, rows);
}

#[test]
fn curves_csv_has_time_and_one_column_per_mass() {
    let r = runs();
    let text = curves_csv("tau", "knee_l", &r).unwrap();
    let (h, cols) = parse_columns(&text, Path::new("c.csv")).unwrap();
    assert_eq!(
        h,
        [
            "time",
            "tau:knee_l:60kg",
            "tau:knee_l:80kg",
            "tau:knee_l:100kg"
        ]
    );
    assert_eq!(cols[0], r[0].t);
    assert_eq!(cols[3], r[2].tau);
    let mut late = r.clone();
    late[1].t[5] += 1e-9;
    assert!(curves_csv("tau", "knee_l", &late).is_err());
}

#[test]
fn mass_labels() {
    assert_eq!(mass_label(60.0), "60 kg");
    assert_eq!(mass_label(62.5), "62.5 kg");
}

/// Issue 14: the samples a run does not quote (edge frames, frames beyond what the feet can
/// give) are out of its peak and RMS, and shaded in the chart, whose markers skip them.
#[test]
fn samples_left_out_are_not_quoted_and_are_shaded() {
    // a spike at the first sample, left out; τ = 1 elsewhere
    let run = MassRun {
        mass_kg: 70.0,
        t: vec![0.0, 0.5, 1.0, 1.5],
        tau: vec![-9.0, 1.0, 1.0, 1.0],
        quoted: vec![false, true, true, true],
        residual_pct: None,
    };
    let row = load_row(&run).unwrap();
    assert_eq!((row.peak_nm, row.peak_time_s), (1.0, 0.5));
    assert!((row.rms_nm - 1.0).abs() < 1e-12);
    let all = load_row(&MassRun {
        quoted: vec![],
        ..run.clone()
    })
    .unwrap();
    assert_eq!(all.peak_nm, 9.0);
    // every sample left out, or more flags than samples: errors
    let none = MassRun {
        quoted: vec![false; 4],
        ..run.clone()
    };
    assert!(load_row(&none).is_err());
    let long = MassRun {
        quoted: vec![true; 5],
        ..run.clone()
    };
    assert!(load_row(&long).is_err());
    // the chart: a shading rectangle and its legend, no marker at the spike (the quoted
    // samples vary, so the curve is not idle and its quoted extremes are marked)
    let run = MassRun {
        tau: vec![-9.0, 1.0, 2.0, 1.0],
        ..run
    };
    let svg = knee_svg_with_table("knee", std::slice::from_ref(&run)).unwrap();
    let t = texts(&svg);
    assert!(t.iter().any(|s| s.starts_with("not quoted")), "{t:?}");
    assert!(!t.iter().any(|s| s.starts_with("min -9")), "{t:?}");
    assert!(t.iter().any(|s| s.starts_with("min 1")), "{t:?}");
    assert!(
        svg.contains("#DDDDDD") || svg.contains("#dddddd"),
        "a shaded span"
    );
    let clean = knee_svg_with_table(
        "knee",
        &[MassRun {
            quoted: vec![],
            ..run
        }],
    )
    .unwrap();
    assert!(!clean.contains("#DDDDDD") && !clean.contains("#dddddd"));
}

/// Issue 14 item 5: with contact each mass's residual figures against Hicks et al.'s
/// thresholds are columns of the table under the chart (`-` for a run without them); without
/// contact the table has no such columns.
#[test]
fn the_table_gives_each_masss_residual_figures_against_the_thresholds() {
    let mut with = runs();
    with[0].residual_pct = Some((1.5, 0.75));
    let t = texts(&knee_svg_with_table("knee", &with).unwrap());
    for want in [
        "residual force (% ≤ 5)",
        "residual moment (% ≤ 1)",
        "1.5",
        "0.75",
        "-",
    ] {
        assert!(t.iter().any(|s| s == want), "{want:?} not in {t:?}");
    }
    let t = texts(&knee_svg_with_table("knee", &runs()).unwrap());
    assert!(!t.iter().any(|s| s.starts_with("residual")), "{t:?}");
}
