//! Geometry of every chart: no min/max label crosses a curve (its backing would hide the curve),
//! no two labels overlap, no legend entry overlaps another or a label, every text stays inside
//! the image, and the curves of one panel never share a colour. Checked on synthetic crowds (11
//! body masses peaking together) and on every SVG the shipped sessions write.
//!
//! A text's box is taken from the SVG as the viewer lays it out: `x`, `y`, `dy` (`0.76em`:
//! `y` is the top; `0.5ex`: the middle; none: the baseline), `text-anchor`, and 0.6 em a glyph
//! (Hack's advance, at least as wide as the common sans-serif faces), one em high.

mod common;

use articula::report::chart::{Panel, Series, stacked_svg, time_series_svg};

/// One `<text>`'s box `[left, top, right, bottom]` and its content.
#[derive(Debug, Clone)]
struct TextBox {
    text: String,
    b: [f64; 4],
    /// Drawn rotated (the y axis title): its box is not where `b` says.
    rotated: bool,
    /// In the monospace face: a cell of the table under the panels.
    mono: bool,
}

/// A curve: a polyline drawn 2 px wide, its colour and points.
struct Curve {
    color: String,
    points: Vec<(f64, f64)>,
}

struct Drawing {
    width: f64,
    height: f64,
    texts: Vec<TextBox>,
    curves: Vec<Curve>,
}

fn parse(svg: &str) -> Drawing {
    let doc = roxmltree::Document::parse(svg).expect("SVG is well-formed XML");
    let root = doc.root_element();
    let num = |n: &roxmltree::Node, a: &str| n.attribute(a).unwrap_or("0").parse::<f64>().unwrap();
    let texts = doc
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| {
            let text = n.text().unwrap_or("").trim().to_string();
            let (x, y, size) = (num(&n, "x"), num(&n, "y"), num(&n, "font-size"));
            let w = 0.6 * size * text.chars().count() as f64;
            let top = match n.attribute("dy") {
                Some("0.76em") => y,
                Some("0.5ex") => y - size / 2.0,
                _ => y - 0.8 * size,
            };
            let left = match n.attribute("text-anchor") {
                Some("middle") => x - w / 2.0,
                Some("end") => x - w,
                _ => x,
            };
            TextBox {
                text,
                b: [left, top, left + w, top + size],
                rotated: n.attribute("transform").is_some(),
                mono: n.attribute("font-family") == Some("monospace"),
            }
        })
        .collect();
    let curves = doc
        .descendants()
        .filter(|n| n.has_tag_name("polyline") && n.attribute("stroke-width") == Some("2"))
        .map(|n| Curve {
            color: n.attribute("stroke").unwrap_or("").to_string(),
            points: n
                .attribute("points")
                .unwrap_or("")
                .split_whitespace()
                .filter_map(|p| {
                    let (a, b) = p.split_once(',')?;
                    Some((a.parse().ok()?, b.parse().ok()?))
                })
                .collect(),
        })
        .collect();
    Drawing {
        width: num(&root, "width"),
        height: num(&root, "height"),
        texts,
        curves,
    }
}

fn overlaps(a: &[f64; 4], b: &[f64; 4]) -> bool {
    a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3]
}

/// Whether segment p–q meets box b (Liang–Barsky).
fn hits(p: (f64, f64), q: (f64, f64), b: &[f64; 4]) -> bool {
    let (dx, dy) = (q.0 - p.0, q.1 - p.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (den, num) in [
        (-dx, p.0 - b[0]),
        (dx, b[2] - p.0),
        (-dy, p.1 - b[1]),
        (dy, b[3] - p.1),
    ] {
        if den == 0.0 {
            if num < 0.0 {
                return false;
            }
        } else {
            let t = num / den;
            if den < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
            if t0 > t1 {
                return false;
            }
        }
    }
    true
}

fn is_label(t: &TextBox) -> bool {
    t.text.starts_with("max ") || t.text.starts_with("min ")
}

/// Every geometric rule of the module documentation; `what` names the chart in failures.
fn assert_clean(svg: &str, what: &str) {
    let d = parse(svg);
    let labels: Vec<&TextBox> = d.texts.iter().filter(|t| is_label(t)).collect();
    for (i, a) in labels.iter().enumerate() {
        for b in &labels[i + 1..] {
            assert!(!overlaps(&a.b, &b.b), "{what}: label {a:?} overlaps {b:?}");
        }
        for c in &d.curves {
            // the legend's 22 px samples are curves too: a label never covers them either
            for s in c.points.windows(2) {
                assert!(
                    !hits(s[0], s[1], &a.b),
                    "{what}: label {:?} at {:?} covers a curve ({}) at {:?}–{:?}",
                    a.text,
                    a.b,
                    c.color,
                    s[0],
                    s[1]
                );
            }
        }
    }
    // the legend (texts right of the plot, vertically centred) and the labels
    let legend: Vec<&TextBox> = d
        .texts
        .iter()
        .filter(|t| !is_label(t) && t.b[0] > 0.7 * d.width)
        .collect();
    for (i, a) in legend.iter().enumerate() {
        for b in legend[i + 1..].iter().chain(&labels) {
            assert!(!overlaps(&a.b, &b.b), "{what}: {a:?} overlaps {b:?}");
        }
    }
    for t in d.texts.iter().filter(|t| !t.rotated) {
        assert!(
            t.b[0] >= -0.5 && t.b[2] <= d.width + 0.5 && t.b[1] >= -0.5 && t.b[3] <= d.height + 0.5,
            "{what}: {t:?} leaves the {}×{} image",
            d.width,
            d.height
        );
    }
}

/// A knee-like torque at `n` body masses, all peaking at the same instants.
fn crowd(n: usize) -> Vec<Series> {
    let t: Vec<f64> = (0..1200).map(|i| i as f64 / 120.0).collect();
    let base: Vec<f64> = t
        .iter()
        .map(|&t| {
            40.0 * (-(t - 9.0f64).powi(2) * 8.0).exp() - 60.0 * (-(t - 7.2f64).powi(2) * 30.0).exp()
        })
        .collect();
    (0..n)
        .map(|k| {
            let m = 50.0 + 10.0 * k as f64;
            Series::new(
                format!("{m} kg"),
                t.clone(),
                base.iter().map(|y| y * m / 60.0).collect(),
            )
        })
        .collect()
}

/// Regression: with 11 body masses (50…150 kg) the labels piled up over the curves and 50 and
/// 150 kg were both blue.
#[test]
fn eleven_body_masses_get_eleven_colours_and_no_label_over_a_curve() {
    let series = crowd(11);
    let svg = time_series_svg("knee", "time (s)", "torque (N·m)", &series, true).unwrap();
    assert_clean(&svg, "11 masses");
    let d = parse(&svg);
    let mut colours: Vec<&str> = d.curves.iter().map(|c| c.color.as_str()).collect();
    colours.sort();
    colours.dedup();
    assert_eq!(colours.len(), 11, "{colours:?}");
    // the crowd is thinned, not dropped: some labels are still there
    assert!(d.texts.iter().any(is_label), "no label at all");
}

/// Up to the palette's twelve colours every curve has its own; more draw dashed.
#[test]
fn twelve_curves_have_twelve_colours_a_thirteenth_is_dashed() {
    use articula::report::chart::{PALETTE, series_style};
    let mut seen: Vec<_> = (0..12).map(|k| series_style(k).0).collect();
    seen.dedup();
    assert_eq!(seen.len(), PALETTE.len());
    for (k, a) in PALETTE.iter().enumerate() {
        assert!(!series_style(k).1);
        for (j, b) in PALETTE[..k].iter().enumerate() {
            assert_ne!(a, b, "{k} and {j}");
        }
    }
    assert!(series_style(12).1);
    let svg = time_series_svg("c", "t (s)", "y", &crowd(14), true).unwrap();
    assert_clean(&svg, "14 masses");
}

/// Regression: `min -9.872e-21 @ 0.3160`, a peak of 1.2e-17 and six stacked `min 0 @ 0`:
/// values below the panel's resolution print as 0, and a flat curve gets no labels.
#[test]
fn noise_is_never_labelled_as_data() {
    let t: Vec<f64> = (0..100).map(|i| i as f64 / 100.0).collect();
    let real: Vec<f64> = t.iter().map(|&t| 30.0 * (6.0 * t).sin()).collect();
    // a curve that should be 0 but carries rounding noise, one more that is exactly 0
    let noise: Vec<f64> = t
        .iter()
        .enumerate()
        .map(|(i, _)| {
            if i == 31 {
                -9.872e-21
            } else {
                1.2e-17 * (i % 3) as f64
            }
        })
        .collect();
    let series = [
        Series::new("knee", t.clone(), real),
        Series::new("root", t.clone(), noise.clone()),
        Series::new("locked", t.clone(), vec![0.0; 100]),
    ];
    let svg = time_series_svg("p", "t (s)", "τ (N·m)", &series, true).unwrap();
    assert_clean(&svg, "noise");
    let d = parse(&svg);
    let labels: Vec<&str> = d
        .texts
        .iter()
        .filter(|t| is_label(t))
        .map(|t| t.text.as_str())
        .collect();
    assert_eq!(
        labels.len(),
        2,
        "only the real curve is labelled: {labels:?}"
    );
    assert!(labels.iter().all(|l| !l.contains('e')), "{labels:?}");
    // a panel of noise alone: no labels, and the axis is not scaled to the noise
    let svg = time_series_svg("p", "t (s)", "τ (N·m)", &series[1..2], true).unwrap();
    let d = parse(&svg);
    assert!(!d.texts.iter().any(is_label));
    assert!(
        !d.texts.iter().any(|t| t.text.contains("e-")),
        "tick in e-17"
    );
    // a real small value is kept
    let small: Vec<f64> = t.iter().map(|&t| 2e-4 * t).collect();
    let svg = time_series_svg("p", "t (s)", "y", &[Series::new("s", t, small)], true).unwrap();
    assert!(
        parse(&svg)
            .texts
            .iter()
            .any(|x| x.text == "max 0.0001980 @ 0.9900")
    );
}

/// Regression: `mixamorig:LeftLeg.Z56.47tation`: the rig's prefix heads the legend once and
/// the entries keep the joint names.
#[test]
fn a_common_prefix_heads_the_legend_and_names_stay_readable() {
    let t: Vec<f64> = (0..50).map(|i| i as f64 / 50.0).collect();
    let series: Vec<Series> = [
        "LeftLeg.Zrotation",
        "LeftUpLeg.Zrotation",
        "RightLeg.Zrotation",
    ]
    .iter()
    .enumerate()
    .map(|(k, n)| {
        Series::new(
            format!("mixamorig:{n}"),
            t.clone(),
            t.iter().map(|x| (x * (k + 2) as f64).sin()).collect(),
        )
    })
    .collect();
    let panels = [Panel {
        title: "torques",
        x_label: "time (s)",
        y_label: "τ (N·m)",
        series: &series,
        mark_min_max: true,
        shaded: &[],
        shaded_label: "",
        bands: &[],
    }];
    let svg = stacked_svg(&panels, None).unwrap();
    assert_clean(&svg, "prefix");
    let texts: Vec<String> = parse(&svg).texts.into_iter().map(|t| t.text).collect();
    for want in ["mixamorig:…", "LeftLeg.Zrotation", "LeftUpLeg.Zrotation"] {
        assert!(texts.iter().any(|t| t == want), "{want} in {texts:?}");
    }
    assert_eq!(
        articula::report::chart::common_prefix(&["a_b", "a_c"]),
        "a_"
    );
    assert_eq!(articula::report::chart::common_prefix(&["ab", "ac"]), "");
    assert_eq!(articula::report::chart::common_prefix(&["x:", "x:y"]), "");
}

/// Every SVG the shipped sessions write passes the geometric checks.
#[test]
fn every_report_of_the_shipped_sessions_is_clean() {
    let mut sessions: Vec<_> = std::fs::read_dir(common::repo("sessions"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "session"))
        .collect();
    sessions.sort();
    let mut checked = 0;
    for s in &sessions {
        let out = tempfile::tempdir().unwrap();
        let r = articula::tui::run_session(s, out.path())
            .unwrap_or_else(|e| panic!("{}: {e}", s.display()));
        for p in r
            .written
            .iter()
            .filter(|p| p.extension().is_some_and(|e| e == "svg"))
        {
            let svg = std::fs::read_to_string(p).unwrap();
            assert_clean(&svg, &format!("{}: {}", s.display(), p.display()));
            checked += 1;
        }
    }
    assert!(checked >= 4, "only {checked} SVGs checked");
}

/// `export png` writes the chart `export svg` writes, as a PNG of the same size, and both carry
/// the caption: take, body, joint model, smoothing, contact and version.
#[test]
fn png_beside_svg_same_layout_and_the_caption_says_the_context() {
    let dir = tempfile::tempdir().unwrap();
    let session = dir.path().join("c.session");
    let take = common::repo("data/demo_walk.bvh");
    std::fs::write(
        &session,
        format!(
            "load {} as walk\nset body.mass 80\nselect LeftLeg.Xrotation\nexport svg a.svg\n\
             export png a.png\ncompare weights 60,80 b.png\n",
            take.display()
        ),
    )
    .unwrap();
    articula::tui::run_session(&session, dir.path()).unwrap();
    let svg = std::fs::read_to_string(dir.path().join("a.svg")).unwrap();
    assert_clean(&svg, "a.svg");
    let d = parse(&svg);
    let caption: String = d
        .texts
        .iter()
        .filter(|t| t.text.starts_with("take ") || t.text.contains("articula "))
        .map(|t| t.text.clone())
        .collect::<Vec<_>>()
        .join(" ");
    for want in [
        "take demo_walk.bvh",
        "body 80 kg, 1.",
        "male",
        "joints euler",
        "smoothing default (butterworth",
        "contact ",
        &format!("articula {}", env!("CARGO_PKG_VERSION")),
    ] {
        assert!(
            caption.contains(want),
            "{want:?} not in caption {caption:?}"
        );
    }
    for (png, height) in [("a.png", d.height), ("b.png", 0.0)] {
        let bytes = std::fs::read(dir.path().join(png)).unwrap();
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let reader = decoder.read_info().expect("a PNG");
        let info = reader.info();
        assert_eq!(info.width as f64, d.width, "{png}");
        if height > 0.0 {
            assert_eq!(info.height as f64, height, "{png}");
        }
    }
}

/// The SVGs of every shipped session plus a motor report with a rotor inertia and the class
/// envelopes (its six panels) and a gait report; `(name, svg)`.
fn every_report() -> Vec<(String, String)> {
    let mut sessions: Vec<_> = std::fs::read_dir(common::repo("sessions"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "session"))
        .collect();
    sessions.sort();
    let dir = tempfile::tempdir().unwrap();
    let motor = dir.path().join("motor.session");
    std::fs::write(
        &motor,
        format!(
            "load {}\nselect LeftLeg\nset motor.rotor_inertia 3e-5\nreport motor m.svg\n",
            common::repo("data/demo_walk.bvh").display()
        ),
    )
    .unwrap();
    sessions.push(motor);
    let mut out = vec![];
    for s in &sessions {
        let o = tempfile::tempdir().unwrap();
        let r = articula::tui::run_session(s, o.path())
            .unwrap_or_else(|e| panic!("{}: {e}", s.display()));
        for p in r
            .written
            .iter()
            .filter(|p| p.extension().is_some_and(|e| e == "svg"))
        {
            let name = format!("{}: {}", s.display(), p.display());
            out.push((name, std::fs::read_to_string(p).unwrap()));
        }
    }
    out
}

/// Issue 15: the motor report with the reflected rotor inertia panel and the torque–speed
/// panel against the envelopes is as clean as the others.
#[test]
fn the_motor_report_with_rotor_inertia_and_envelope_is_clean() {
    let reports = every_report();
    let (name, svg) = reports
        .iter()
        .find(|(n, _)| n.ends_with("m.svg"))
        .expect("the motor report");
    assert_clean(svg, name);
    let d = parse(svg);
    for want in ["Reflected rotor inertia", "Torque–speed", "BLDC-"] {
        assert!(
            d.texts.iter().any(|t| t.text.contains(want)),
            "{name}: no {want:?}"
        );
    }
}

/// Every character of every text the reports draw has a glyph in the embedded font (Hack), so
/// the PNG, drawn with that font alone, shows no box: `q̇` (q + U+0307, a combining dot Hack
/// lacks) drew one; the reports now write `ω`.
#[test]
fn every_report_text_has_its_glyph_in_the_embedded_font() {
    let face = ttf_parser::Face::parse(epaint_default_fonts::HACK_REGULAR, 0).expect("Hack");
    // the check tells: the combining dot above of `q̇` is missing, `ω` is there
    assert!(face.glyph_index('\u{307}').is_none());
    assert!(face.glyph_index('ω').is_some());
    let mut checked = 0;
    for (name, svg) in every_report() {
        for t in parse(&svg).texts {
            for c in t.text.chars().filter(|c| !c.is_whitespace()) {
                assert!(
                    face.glyph_index(c).is_some(),
                    "{name}: {:?} in {:?} (U+{:04X}) has no glyph in the chart font",
                    c,
                    t.text,
                    c as u32
                );
                checked += 1;
            }
        }
    }
    assert!(checked > 1000, "only {checked} characters checked");
}

/// Issue 15: in the motor report's table, a long joint name (a Mixamo take's
/// `mixamorig:LeftUpLeg.Xrotation`) never runs into the numbers beside it: columns are as wide
/// as their widest cell, names elided in the middle only when the table would not fit.
#[test]
fn motor_table_cells_never_overlap_with_long_mixamo_names() {
    let dir = tempfile::tempdir().unwrap();
    let demo = std::fs::read_to_string(common::repo("data/demo_walk.bvh")).unwrap();
    let mixamo = ["ROOT ", "JOINT "]
        .iter()
        .fold(demo, |b, k| b.replace(k, &format!("{k}mixamorig:")));
    let take = dir.path().join("mixamo.bvh");
    std::fs::write(&take, mixamo).unwrap();
    let session = dir.path().join("motor.session");
    std::fs::write(
        &session,
        format!(
            "load {}\nselect mixamorig:LeftUpLeg\nreport motor m.svg\n",
            take.display()
        ),
    )
    .unwrap();
    let r = articula::tui::run_session(&session, dir.path()).expect("the session runs");
    let svg = r
        .written
        .iter()
        .find(|p| p.extension().is_some_and(|e| e == "svg"))
        .expect("the motor report");
    let d = parse(&std::fs::read_to_string(svg).unwrap());
    let cells: Vec<&TextBox> = d.texts.iter().filter(|t| t.mono).collect();
    assert!(
        cells.iter().any(|t| t.text.starts_with("mixa")),
        "no long name in the table: {cells:?}"
    );
    assert!(cells.iter().any(|t| t.text.contains("N·m")), "no header");
    // names elided, when they must be, keep the end that tells the rows apart
    let names: std::collections::BTreeSet<&str> = cells
        .iter()
        .filter(|t| t.text.starts_with("mixa"))
        .map(|t| t.text.as_str())
        .collect();
    assert!(names.len() >= 3, "rows no longer told apart: {names:?}");
    for (i, a) in cells.iter().enumerate() {
        for b in &cells[i + 1..] {
            assert!(!overlaps(&a.b, &b.b), "table cell {a:?} overlaps {b:?}");
        }
        assert!(a.b[2] <= d.width + 0.5, "{a:?} leaves the image");
    }
    // the legends (the torque-speed panel's mixes joints and classes: no shared prefix) keep
    // each joint's axis: three distinct entries ending in their coordinate, none cut before it
    let legend: std::collections::BTreeSet<&str> = d
        .texts
        .iter()
        .filter(|t| !t.mono && t.text.contains('…') && !t.text.ends_with('…'))
        .map(|t| t.text.as_str())
        .collect();
    assert!(!legend.is_empty(), "no elided legend entry: {:?}", d.texts);
    for entry in &legend {
        assert!(
            ["Xrotation", "Yrotation", "Zrotation"]
                .iter()
                .any(|axis| entry.ends_with(axis)),
            "a legend entry lost its coordinate: {entry:?} (of {legend:?})"
        );
    }
}
