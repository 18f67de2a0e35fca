//! Motor sizing: the current is I = τ / (Km · N · η) on hand-computed cases, the motor-side
//! loads go through the gear (τ/(Nη), N·q̇), the class chosen is the smallest whose rated
//! torque, peak torque and rated speed all cover the load (limits inclusive), and the report
//! SVG and CSV carry every joint.

use articula::report::motor::{
    JointLoad, JointMotion, MOTOR_TABLE_HEADER, MotorClass, MotorSpec, choose_class, class_name,
    default_catalogue, motor_current, motor_curves_csv, motor_svg, motor_table_csv,
    parse_catalogue,
};

fn classes() -> Vec<MotorClass> {
    default_catalogue().unwrap()
}

fn size_motor(m: &JointMotion, s: &MotorSpec) -> Result<JointLoad, articula::error::Error> {
    articula::report::motor::size_motor(m, s, &classes())
}

fn size_motors(
    m: &[JointMotion],
    s: &[MotorSpec],
) -> Result<Vec<JointLoad>, articula::error::Error> {
    articula::report::motor::size_motors(m, s, &classes())
}

fn spec(km: f64, n: f64, eta: Option<f64>) -> MotorSpec {
    MotorSpec {
        km_nm_per_a: km,
        gear_ratio: n,
        efficiency: eta,
        rotor_inertia_kg_m2: 0.0,
    }
}

fn constant(joint: &str, tau: f64, qd: f64) -> JointMotion {
    JointMotion {
        joint: joint.into(),
        t: vec![0.0, 1.0],
        tau: vec![tau, tau],
        qd: vec![qd, qd],
        qdd: vec![0.0, 0.0],
    }
}

#[test]
fn current_is_torque_over_km_n_eta() {
    // 12 N·m through a 100:1 gear on a 0.05 N·m/A motor: 12 / (0.05·100) = 2.4 A
    assert!((motor_current(12.0, &spec(0.05, 100.0, None)) - 2.4).abs() < 1e-12);
    // with an 80 % efficient gear the motor works harder: 2.4 / 0.8 = 3 A
    assert!((motor_current(12.0, &spec(0.05, 100.0, Some(0.8))) - 3.0).abs() < 1e-12);
    assert!((motor_current(-6.0, &spec(0.1, 50.0, None)) + 1.2).abs() < 1e-12);
}

#[test]
fn joint_load_by_hand() {
    // τ = 20 sin(πt) N·m, q̇ = 2 cos(πt) rad/s on [0, 1], sampled finely
    let t: Vec<f64> = (0..=2000).map(|i| i as f64 / 2000.0).collect();
    let pi = std::f64::consts::PI;
    let m = JointMotion {
        joint: "elbow".into(),
        tau: t.iter().map(|&t| 20.0 * (pi * t).sin()).collect(),
        qd: t.iter().map(|&t| 2.0 * (pi * t).cos()).collect(),
        qdd: t.iter().map(|&t| -2.0 * pi * (pi * t).sin()).collect(),
        t,
    };
    let l = size_motor(&m, &spec(0.05, 100.0, Some(0.8))).unwrap();
    assert_eq!(l.joint, "elbow");
    assert!((l.peak_torque_nm - 20.0).abs() < 1e-9);
    // RMS of 20 sin over a half period: 20/√2
    assert!((l.rms_torque_nm - 20.0 / 2f64.sqrt()).abs() < 1e-4);
    assert_eq!(l.peak_speed_rad_s, 2.0);
    // P = 40 sin cos = 20 sin 2πt: peak 20 W
    assert!((l.peak_power_w - 20.0).abs() < 1e-6);
    // motor side: 20 / (100·0.8) = 0.25 N·m, 200 rad/s, 0.25 / 0.05 = 5 A
    assert!((l.motor_peak_torque_nm - 0.25).abs() < 1e-12);
    assert_eq!(l.motor_peak_speed_rad_s, 200.0);
    assert!((l.peak_current_a - 5.0).abs() < 1e-9);
    assert!((l.rms_current_a - 5.0 / 2f64.sqrt()).abs() < 1e-4);
    // 0.177 N·m RMS, 0.25 N·m peak, 200 rad/s: BLDC-42 (0.12 rated) is too weak, BLDC-60 fits
    assert_eq!(class_name(&l), "BLDC-60 (200 W)");
}

#[test]
fn class_limits_are_inclusive_and_all_three_count() {
    let all = classes();
    let c0 = &all[0];
    let exact = choose_class(
        &all,
        c0.rated_torque_nm,
        c0.peak_torque_nm,
        c0.rated_speed_rad_s,
    );
    assert_eq!(exact.map(|c| &c.name), Some(&c0.name));
    let up = |x: f64| f64::from_bits(x.to_bits() + 1);
    // a hair over any one limit moves to the next class (or to none for speed: bigger motors
    // are slower)
    let over_rms = choose_class(&all, up(c0.rated_torque_nm), 0.0, 0.0);
    assert_eq!(over_rms.map(|c| &c.name), Some(&all[1].name));
    let over_peak = choose_class(&all, 0.0, up(c0.peak_torque_nm), 0.0);
    assert_eq!(over_peak.map(|c| &c.name), Some(&all[1].name));
    assert!(choose_class(&all, 0.0, 0.0, up(c0.rated_speed_rad_s)).is_none());
    // torque of class 3 with more speed than class 3 has: none
    let c2 = &all[2];
    assert!(choose_class(&all, c2.rated_torque_nm, 0.0, up(c2.rated_speed_rad_s)).is_none());
    // beyond the largest class: none
    let last = all.last().unwrap();
    assert!(choose_class(&all, up(last.rated_torque_nm), 0.0, 0.0).is_none());
}

#[test]
fn sizing_picks_the_class_at_its_boundary() {
    // constant 0.08 N·m through a 4:1 ideal gear = exactly 0.02 N·m on the motor (class 1's
    // rated torque), 100 rad/s → 400 rad/s
    let l = size_motor(&constant("wrist", 0.08, 100.0), &spec(0.01, 4.0, None)).unwrap();
    assert_eq!(l.motor_rms_torque_nm, 0.02);
    assert_eq!(class_name(&l), classes()[0].name);
    let l = size_motor(
        &constant("wrist", f64::from_bits(0.08f64.to_bits() + 1), 100.0),
        &spec(0.01, 4.0, None),
    )
    .unwrap();
    assert_eq!(class_name(&l), classes()[1].name);
    // too fast for every class
    let l = size_motor(&constant("wrist", 0.08, 1000.0), &spec(0.01, 4.0, None)).unwrap();
    assert!(l.class.is_none());
    assert_eq!(class_name(&l), "none in catalogue");
}

#[test]
fn catalogue_is_ordered_smallest_first() {
    for w in classes().windows(2) {
        assert!(w[0].rated_torque_nm < w[1].rated_torque_nm);
        assert!(w[0].peak_torque_nm < w[1].peak_torque_nm);
        assert!(w[0].rated_speed_rad_s >= w[1].rated_speed_rad_s);
        assert!(
            w[0].rated_torque_nm * w[0].rated_speed_rad_s
                < w[1].rated_torque_nm * w[1].rated_speed_rad_s
        );
    }
}

#[test]
fn bad_specs_and_data_are_errors() {
    let m = constant("j", 1.0, 1.0);
    for s in [
        spec(0.0, 10.0, None),
        spec(0.1, -1.0, None),
        spec(0.1, 10.0, Some(1.5)),
        spec(0.1, 10.0, Some(0.0)),
        spec(f64::NAN, 1.0, None),
    ] {
        assert!(size_motor(&m, &s).is_err(), "{s:?}");
    }
    let mut nan = m.clone();
    nan.qd[1] = f64::NAN;
    assert!(size_motor(&nan, &spec(0.1, 10.0, None)).is_err());
    let mut short = m.clone();
    short.tau.pop();
    assert!(size_motor(&short, &spec(0.1, 10.0, None)).is_err());
    assert!(size_motors(&[m], &[]).is_err());
}

fn arm() -> Vec<JointMotion> {
    let t: Vec<f64> = (0..=200).map(|i| i as f64 / 100.0).collect();
    ["shoulder", "elbow"]
        .iter()
        .enumerate()
        .map(|(k, name)| JointMotion {
            joint: name.to_string(),
            tau: t
                .iter()
                .map(|&t| (30.0 - 10.0 * k as f64) * (t + k as f64).sin())
                .collect(),
            qd: t.iter().map(|&t| (1.0 + k as f64) * t.cos()).collect(),
            qdd: t.iter().map(|&t| -(1.0 + k as f64) * t.sin()).collect(),
            t: t.clone(),
        })
        .collect()
}

#[test]
fn report_svg_has_four_panels_every_joint_and_the_table() {
    let joints = arm();
    let specs = [spec(0.05, 100.0, None), spec(0.05, 50.0, Some(0.9))];
    let loads = size_motors(&joints, &specs).unwrap();
    let svg = motor_svg(&joints, &specs, &loads).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("well-formed");
    let texts: Vec<String> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| n.text().unwrap_or("").trim().to_string())
        .collect();
    for want in [
        "Joint torque",
        "Joint speed ω",
        "Joint power τ·ω: driving (> 0) and regenerating (< 0)",
        "torque (N·m)",
        "speed (rad/s)",
        "power (W)",
        "Motor current I = τ_m/Km",
        "motor speed |ω_m| (rad/s)",
        "current (A)",
        "peak I (A)",
        "class",
    ] {
        assert!(texts.iter().any(|t| t == want), "no {want:?}");
    }
    // each joint: a legend entry in the torque, speed, current and torque–speed panels, its
    // driving and regenerating power curves, its table row, its drive's row and its duty row
    for j in ["shoulder", "elbow"] {
        assert_eq!(texts.iter().filter(|t| *t == j).count(), 7, "{j}");
        assert!(texts.iter().any(|t| *t == format!("{j} driving")), "{j}");
        assert!(texts.iter().any(|t| *t == format!("{j} regen")), "{j}");
    }
    for l in &loads {
        assert!(texts.iter().any(|t| t == class_name(l)));
    }
    // 2 joints × 3 panels (torque, speed, current) × (min + max); the power and torque–speed
    // panels mark none
    assert_eq!(
        doc.descendants()
            .filter(|n| n.has_tag_name("circle") && n.attribute("r") == Some("4"))
            .count(),
        12
    );
    assert_eq!(svg, motor_svg(&joints, &specs, &loads).unwrap());
    assert!(motor_svg(&joints, &specs[..1], &loads).is_err());
}

#[test]
fn table_csv_has_a_row_per_joint() {
    let joints = arm();
    let mut loads =
        size_motors(&joints, &[spec(0.05, 100.0, None), spec(0.05, 50.0, None)]).unwrap();
    loads[0].joint = "shoulder, \"left\"".into();
    let text = motor_table_csv(&loads).unwrap();
    let mut rdr = csv::Reader::from_reader(text.as_bytes());
    let header: Vec<String> = rdr.headers().unwrap().iter().map(String::from).collect();
    assert_eq!(header, MOTOR_TABLE_HEADER);
    let rows: Vec<csv::StringRecord> = rdr.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), 2);
    for (r, l) in rows.iter().zip(&loads) {
        assert_eq!(&r[0], l.joint);
        assert_eq!(r[8].parse::<f64>().unwrap(), l.peak_current_a);
        assert_eq!(&r[10], class_name(l));
        // the drive it was sized with
        assert_eq!(r[11].parse::<f64>().unwrap(), l.spec.km_nm_per_a);
        assert_eq!(r[12].parse::<f64>().unwrap(), l.spec.gear_ratio);
        assert_eq!(r[13].parse::<f64>().unwrap(), 1.0);
    }
}

#[test]
fn curves_csv_holds_torque_speed_power_and_current() {
    let joints = arm();
    let specs = [spec(0.05, 100.0, None), spec(0.2, 50.0, Some(0.5))];
    let text = motor_curves_csv(&joints, &specs).unwrap();
    let (h, cols) =
        articula::report::csv::parse_columns(&text, std::path::Path::new("m.csv")).unwrap();
    assert_eq!(
        h[..4],
        ["time", "tau:shoulder", "v:shoulder", "power:shoulder"]
    );
    assert_eq!(h.len(), 11);
    assert_eq!(h[9], "current:elbow");
    assert_eq!(h[10], "rotor_tau:elbow");
    assert_eq!(cols[1], joints[0].tau);
    assert_eq!(cols[8][50], joints[1].tau[50] * joints[1].qd[50]);
    // I = τ / (Km·N·η) = τ / (0.2·50·0.5) = τ / 5 (no rotor inertia given: its term is 0)
    assert_eq!(cols[9][50], joints[1].tau[50] / 5.0);
    assert!(cols[10].iter().all(|&x| x == 0.0));
    assert!(motor_curves_csv(&joints, &specs[..1]).is_err());
}

#[test]
fn the_bundled_catalogue_is_the_data_file_and_bad_catalogues_are_errors() {
    let all = classes();
    assert_eq!(all.len(), 8);
    assert_eq!(all[3].name, "BLDC-60 (200 W)");
    // 5000 rpm = 5000·π/30 rad/s
    assert_eq!(
        all[3].rated_speed_rad_s,
        5000.0 * std::f64::consts::PI / 30.0
    );
    let p = std::path::Path::new("c.toml");
    let one = "[[class]]\nname = \"M\"\nrated_torque_nm = 1.0\npeak_torque_nm = 3.0\nrated_speed_rpm = 3000\n";
    let c = parse_catalogue(one, p).unwrap();
    assert_eq!(c[0].peak_torque_nm, 3.0);
    for bad in [
        "",
        "[[class]]\nname = \"M\"\n",
        &one.replace("3.0", "0.5"),
        &one.replace("3000", "-1"),
        &one.replace("name", "nom"),
    ] {
        let e = parse_catalogue(bad, p).unwrap_err().to_string();
        assert!(e.starts_with("c.toml"), "{e}");
    }
}

/// Issue 15: the report shows the drive parameters each joint was sized with, marked
/// `(default)` where not set, and prints a load below the column's resolution (a joint that
/// does not move) as 0, not as 1e-17.
#[test]
fn the_report_shows_the_drives_and_their_defaults_and_no_noise() {
    use articula::report::chart::ImageFormat;
    use articula::report::motor::motor_chart;
    let mut joints = arm();
    joints[1].tau = vec![1.234e-17; joints[1].t.len()];
    joints[1].qd = vec![0.0; joints[1].t.len()];
    let specs = [spec(0.05, 100.0, None), spec(0.26, 50.0, Some(0.9))];
    let loads = size_motors(&joints, &specs).unwrap();
    let defaults = [[true, true, true], [false, false, false]];
    let svg = motor_chart(&joints, &specs, &loads, &defaults, None, ImageFormat::Svg).unwrap();
    let svg = String::from_utf8(svg).unwrap();
    let doc = roxmltree::Document::parse(&svg).expect("well-formed");
    let texts: Vec<String> = doc
        .descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| n.text().unwrap_or("").trim().to_string())
        .collect();
    for want in [
        "drive",
        "gear N",
        "Km (N·m/A)",
        "efficiency η",
        "100 (default)",
        "0.05 (default)",
        "1 (default)",
        "50",
        "0.26",
        "0.9",
    ] {
        assert!(texts.iter().any(|t| t == want), "no {want:?} in {texts:?}");
    }
    assert!(!texts.iter().any(|t| t.contains("e-17")), "{texts:?}");
}
