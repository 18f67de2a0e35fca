//! Time-series SVG charts (the paper's figure 4): the output is well-formed XML holding the
//! title, axis titles, one legend entry per series, and for each curve its minimum and maximum
//! marked with their values; the same input gives the same bytes; bad data is an error.

use articula::error::Error;
use articula::report::chart::{
    Panel, Series, Table, fmt_value, series_columns, stacked_svg, time_series_svg, write_svg,
};

/// Text content of every `<text>` element, trimmed.
fn texts(svg: &str) -> Vec<String> {
    let doc = roxmltree::Document::parse(svg).expect("SVG is well-formed XML");
    assert_eq!(doc.root_element().tag_name().name(), "svg");
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| n.text().unwrap_or("").trim().to_string())
        .collect()
}

fn walk() -> Vec<Series> {
    let t: Vec<f64> = (0..241).map(|i| i as f64 / 120.0).collect();
    // knee flexion-like torque: max 42.5 N·m at t = 0.5 s, min −17.0 at 1.5 s
    let knee: Vec<f64> = t
        .iter()
        .map(|&t| 12.75 + 29.75 * (std::f64::consts::PI * t).sin())
        .collect();
    let hip: Vec<f64> = t.iter().map(|&t| 5.0 * (2.0 * t).cos()).collect();
    vec![
        Series::new("knee (right)", t.clone(), knee),
        Series::new("hip & <pelvis>", t, hip),
    ]
}

#[test]
fn svg_holds_title_axes_legend_and_min_max_labels() {
    let svg = time_series_svg("Joint torques", "time (s)", "torque (N·m)", &walk(), true).unwrap();
    let texts = texts(&svg);
    for want in [
        "Joint torques",
        "time (s)",
        "torque (N·m)",
        "knee (right)",
        "hip & <pelvis>",
    ] {
        assert!(
            texts.iter().any(|t| t == want),
            "no text {want:?} in {texts:?}"
        );
    }
    // knee: max 12.75 + 29.75 = 42.5 at t = 0.5, min 12.75 − 29.75 = −17 at t = 1.5
    assert!(
        texts.contains(&"max 42.50 @ 0.5000".to_string()),
        "{texts:?}"
    );
    assert!(
        texts.contains(&"min -17.00 @ 1.500".to_string()),
        "{texts:?}"
    );
    // hip: 5 cos 2t over [0, 2]: max 5 at 0, min −5 at t = π/2 → nearest sample 1.575
    assert!(texts.contains(&"max 5.000 @ 0".to_string()), "{texts:?}");
    assert!(
        texts.iter().any(|t| t.starts_with("min -5.000 @ 1.5")),
        "{texts:?}"
    );
    // one marker dot per min and max
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let dots = doc
        .descendants()
        .filter(|n| n.has_tag_name("circle"))
        .count();
    assert_eq!(dots, 4);
    // one polyline per curve (plus the legend's samples)
    let lines = doc
        .descendants()
        .filter(|n| n.has_tag_name("polyline"))
        .count();
    assert!(lines >= 2, "{lines}");
}

#[test]
fn without_markers_there_are_no_min_max_labels() {
    let svg = time_series_svg("T", "time (s)", "angle (rad)", &walk(), false).unwrap();
    let texts = texts(&svg);
    assert!(
        !texts
            .iter()
            .any(|t| t.starts_with("max ") || t.starts_with("min "))
    );
    assert!(!svg.contains("<circle"));
}

#[test]
fn same_input_same_bytes() {
    let a = time_series_svg("T", "time (s)", "torque (N·m)", &walk(), true).unwrap();
    let b = time_series_svg("T", "time (s)", "torque (N·m)", &walk(), true).unwrap();
    assert_eq!(a, b);
    let mut other = walk();
    other[0].y[10] += 1.0;
    let c = time_series_svg("T", "time (s)", "torque (N·m)", &other, true).unwrap();
    assert_ne!(a, c);
}

#[test]
fn degenerate_data_draws() {
    // a flat curve is idle: drawn, but no min / max label (issue 15)
    let constant = Series::new("flat", vec![0.0, 1.0, 2.0], vec![3.0; 3]);
    let svg = time_series_svg("c", "t (s)", "y", &[constant], true).unwrap();
    assert!(!texts(&svg).iter().any(|t| t.starts_with("max ")));
    let one = Series::new("one", vec![0.5], vec![-2.0]);
    let svg = time_series_svg("o", "t (s)", "y", &[one], true).unwrap();
    assert!(texts(&svg).contains(&"one".to_string()));
    let zero = Series::new("zero", vec![0.0, 0.0], vec![0.0, 0.0]);
    texts(&time_series_svg("z", "t (s)", "y", &[zero], true).unwrap());
}

#[test]
fn bad_data_is_an_error_not_a_panic() {
    let nan = Series::new("n", vec![0.0, 1.0], vec![0.0, f64::NAN]);
    let err = time_series_svg("T", "t", "y", &[nan], true).unwrap_err();
    assert!(matches!(err, Error::Invalid(_)));
    assert!(err.to_string().contains("sample 1"), "{err}");
    let inf = Series::new("i", vec![0.0, f64::INFINITY], vec![0.0, 1.0]);
    assert!(time_series_svg("T", "t", "y", &[inf], true).is_err());
    let ragged = Series::new("r", vec![0.0, 1.0], vec![0.0]);
    assert!(time_series_svg("T", "t", "y", &[ragged], true).is_err());
    let empty = Series::new("e", vec![], vec![]);
    assert!(time_series_svg("T", "t", "y", &[empty], true).is_err());
    assert!(time_series_svg("T", "t", "y", &[], true).is_err());
    let huge = Series::new("h", vec![0.0, 1.0], vec![-f64::MAX, f64::MAX]);
    assert!(time_series_svg("T", "t", "y", &[huge], true).is_err());
}

#[test]
fn stacked_panels_and_table() {
    let s = walk();
    let panels = [
        Panel {
            title: "torque",
            x_label: "time (s)",
            y_label: "τ (N·m)",
            series: &s,
            mark_min_max: true,
            shaded: &[(0.0, 0.1)],
            shaded_label: "not quoted",
            bands: &[],
        },
        Panel {
            title: "speed",
            x_label: "time (s)",
            y_label: "q̇ (rad/s)",
            series: &s[..1],
            mark_min_max: false,
            shaded: &[],
            shaded_label: "",
            bands: &[],
        },
    ];
    let table = Table {
        header: vec!["joint".into(), "peak (N·m)".into()],
        rows: vec![
            vec!["knee".into(), "42.50".into()],
            vec!["hip".into(), "5.000".into()],
        ],
    };
    let svg = stacked_svg(&panels, Some(&table)).unwrap();
    let texts = texts(&svg);
    for want in [
        "torque",
        "speed",
        "τ (N·m)",
        "q̇ (rad/s)",
        "joint",
        "peak (N·m)",
        "knee",
        "42.50",
        "5.000",
    ] {
        assert!(texts.iter().any(|t| t == want), "no text {want:?}");
    }
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let h: u32 = doc
        .root_element()
        .attribute("height")
        .unwrap()
        .parse()
        .unwrap();
    assert!(h > 2 * articula::report::chart::PANEL_HEIGHT);
}

#[test]
fn write_svg_writes_the_document() {
    let dir = tempfile::tempdir().unwrap();
    let p = dir.path().join("c.svg");
    let svg = time_series_svg("T", "t (s)", "y", &walk(), true).unwrap();
    write_svg(&p, &svg).unwrap();
    assert_eq!(std::fs::read_to_string(&p).unwrap(), svg);
}

#[test]
fn series_export_needs_a_shared_time_base() {
    let s = walk();
    let (h, cols) = series_columns("t_s", &s).unwrap();
    assert_eq!(h, ["t_s", "knee (right)", "hip & <pelvis>"]);
    assert_eq!(cols.len(), 3);
    assert_eq!(cols[1], &s[0].y[..]);
    let shifted = Series::new(
        "late",
        s[0].x.iter().map(|t| t + 0.1).collect(),
        s[0].y.clone(),
    );
    assert!(series_columns("t_s", &[s[0].clone(), shifted]).is_err());
}

#[test]
fn value_labels_have_four_significant_digits() {
    assert_eq!(fmt_value(42.5), "42.50");
    assert_eq!(fmt_value(-0.001234567), "-0.001235");
    assert_eq!(fmt_value(1234.6), "1235");
    assert_eq!(fmt_value(0.0), "0");
    assert_eq!(fmt_value(1.5e9), "1.500e9");
}

#[test]
fn long_series_are_reduced_to_the_pixels_keeping_extremes() {
    use articula::report::chart::decimate_m4;
    // 36 000 samples (5 min at 120 Hz) of a noisy sine with one spike
    let t: Vec<f64> = (0..36_000).map(|i| i as f64 / 120.0).collect();
    let mut y: Vec<f64> = t
        .iter()
        .map(|&t| t.sin() + 0.1 * (37.0 * t).sin())
        .collect();
    y[12_345] = 7.5;
    let keep = decimate_m4(&t, &y, 0.0, t[35_999], 800);
    assert!(keep.len() <= 4 * 800, "{}", keep.len());
    assert!(keep.windows(2).all(|w| w[0] < w[1]), "in order, no repeats");
    assert_eq!(keep[0], 0);
    assert_eq!(*keep.last().unwrap(), 35_999);
    assert!(keep.contains(&12_345), "the spike survives");
    // within every pixel column the kept samples span the same y range as all samples
    let column = |v: f64| ((v / t[35_999] * 800.0) as usize).min(799);
    for c in [0, 137, 411, 799] {
        let all: Vec<f64> = (0..36_000)
            .filter(|&i| column(t[i]) == c)
            .map(|i| y[i])
            .collect();
        let kept: Vec<f64> = keep
            .iter()
            .filter(|&&i| column(t[i]) == c)
            .map(|&i| y[i])
            .collect();
        let range = |v: &[f64]| {
            (
                v.iter().copied().fold(f64::MAX, f64::min),
                v.iter().copied().fold(f64::MIN, f64::max),
            )
        };
        assert_eq!(range(&all), range(&kept), "column {c}");
    }
    // short or unsorted series are kept whole
    assert_eq!(decimate_m4(&t[..100], &y[..100], 0.0, 1.0, 800).len(), 100);
    let back = [0.0, 2.0, 1.0];
    assert_eq!(decimate_m4(&back, &[0.0; 3], 0.0, 2.0, 0).len(), 3);
    assert_eq!(decimate_m4(&t[..100], &y[..100], 0.0, 1.0, 0).len(), 100);
    let descending: Vec<f64> = (0..100).map(|i| -(i as f64)).collect();
    assert_eq!(
        decimate_m4(&descending, &y[..100], -99.0, 0.0, 2).len(),
        100
    );
    // the chart of the long series stays small and still marks the spike
    let svg = time_series_svg("long", "time (s)", "y", &[Series::new("s", t, y)], true).unwrap();
    assert!(svg.len() < 200_000, "{} bytes", svg.len());
    assert!(
        texts(&svg).iter().any(|s| s == "max 7.500 @ 102.9"),
        "{:?}",
        texts(&svg)
    );
}

/// Regression: three body masses of one take peak at the same instant, and their min/max labels
/// were drawn on top of each other, with the legend box over the right-hand ones. Every label's
/// box (Hack is 0.6 em a glyph, one em high) overlaps no other label, and all of them lie left
/// of the legend, which has a strip of its own.
#[test]
fn min_max_labels_of_curves_peaking_together_do_not_overlap_or_hide_under_the_legend() {
    let t: Vec<f64> = (0..1200).map(|i| i as f64 / 120.0).collect();
    let base: Vec<f64> = t
        .iter()
        .map(|&t| {
            40.0 * (-(t - 9.0f64).powi(2) * 8.0).exp() - 60.0 * (-(t - 7.2f64).powi(2) * 30.0).exp()
        })
        .collect();
    let series: Vec<Series> = [60.0, 80.0, 100.0]
        .iter()
        .map(|m| {
            Series::new(
                format!("{m} kg"),
                t.clone(),
                base.iter().map(|y| y * m / 60.0).collect(),
            )
        })
        .collect();
    let svg = time_series_svg("knee", "time (s)", "torque (N·m)", &series, true).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let boxes = |pred: &dyn Fn(&str) -> bool| -> Vec<[f64; 4]> {
        doc.descendants()
            .filter(|n| n.has_tag_name("text") && pred(n.text().unwrap_or("").trim()))
            .map(|n| {
                let num = |a: &str| n.attribute(a).unwrap().parse::<f64>().unwrap();
                let (x, y, size) = (num("x"), num("y"), num("font-size"));
                let len = n.text().unwrap().trim().chars().count() as f64;
                [x, y, x + 0.6 * size * len, y + size]
            })
            .collect()
    };
    let labels = boxes(&|s: &str| s.starts_with("max ") || s.starts_with("min "));
    assert_eq!(labels.len(), 6);
    for (i, a) in labels.iter().enumerate() {
        for b in &labels[i + 1..] {
            let overlap = a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3];
            assert!(!overlap, "{a:?} overlaps {b:?}");
        }
    }
    let legend = boxes(&|s: &str| s.ends_with(" kg"));
    assert_eq!(legend.len(), 3);
    let legend_left = legend.iter().map(|b| b[0]).fold(f64::INFINITY, f64::min);
    for l in &labels {
        assert!(
            l[2] < legend_left,
            "label {l:?} reaches the legend at x = {legend_left}"
        );
    }
}

/// A very long series name does not squeeze the plot: the legend strip takes at most a quarter
/// of the chart's width and the name is shortened with an ellipsis in the middle, keeping its
/// start and its end (the end tells `…LeftUpLeg.Xrotation` from `…LeftUpLeg.Zrotation`).
#[test]
fn a_long_legend_entry_is_shortened_not_allowed_to_squeeze_the_plot() {
    let mut series = walk();
    series[0].label = "knee flexion of the left leg of subject 17, trial 4, after surgery".into();
    let svg = time_series_svg("knee", "time (s)", "torque (N·m)", &series, false).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let width: f64 = doc
        .root_element()
        .attribute("width")
        .unwrap()
        .parse()
        .unwrap();
    let entry = doc
        .descendants()
        .find(|n| {
            n.has_tag_name("text") && {
                let t = n.text().unwrap_or("").trim();
                t.starts_with("knee") && t.contains('…')
            }
        })
        .expect("legend entry");
    let text = entry.text().unwrap().trim();
    assert!(text.ends_with("after surgery"), "{text}");
    assert!(
        text.chars().count() < series[0].label.chars().count(),
        "{text}"
    );
    let x: f64 = entry.attribute("x").unwrap().parse().unwrap();
    assert!(x > 0.7 * width, "legend entry at x = {x} of {width}");
}
