//! The motor report's duty (issue 15): a frame whose motor torque exceeds the chosen class's
//! torque–speed envelope `τ_peak(1 − |ω_m|/ω0)` is counted, one under it is not; the reflected
//! rotor inertia term is `J_m·N²·q̈` sample by sample (on the demo, through a session); the
//! energy driven and the energy regenerated add up to `∫|P| dt` and differ by `∫P dt`.

mod common;

use articula::report::motor::{JointMotion, MotorClass, MotorSpec, parse_catalogue, size_motor};
use articula::report::motor_duty::{Envelope, energy};
use common::cli::articula;

fn spec(n: f64, j: f64) -> MotorSpec {
    MotorSpec {
        km_nm_per_a: 0.1,
        gear_ratio: n,
        efficiency: None,
        rotor_inertia_kg_m2: j,
    }
}

/// One class: rated 4.5 N·m up to 100 rad/s, peak 5 N·m, no-load speed 1000 rad/s (its rated
/// point lies under the peak line: 5·(1 − 0.1) = 4.5).
fn class() -> MotorClass {
    MotorClass {
        name: "test".into(),
        rated_torque_nm: 4.5,
        peak_torque_nm: 5.0,
        rated_speed_rad_s: 100.0,
        no_load_speed_rad_s: Some(1000.0),
    }
}

/// Two samples a second apart: (τ, q̇) then an idle one.
fn two(tau: f64, qd: f64) -> JointMotion {
    JointMotion {
        joint: "j".into(),
        t: vec![0.0, 1.0],
        tau: vec![tau, 0.1],
        qd: vec![qd, 0.0],
        qdd: vec![0.0, 0.0],
    }
}

#[test]
fn a_frame_above_the_envelope_is_counted_one_below_is_not() {
    let e = Envelope::of(&class()).unwrap();
    // at 90 rad/s the class gives 5·(1 − 0.09) = 4.55 N·m
    assert!((e.available(90.0) - 4.55).abs() < 1e-12);
    assert!((e.available(-90.0) - 4.55).abs() < 1e-12);
    assert_eq!(e.available(1200.0), 0.0);
    // 4.9 N·m at 90 rad/s: within the peak torque, the RMS and the rated speed (the class is
    // chosen), but beyond the envelope
    let over = size_motor(&two(4.9, 90.0), &spec(1.0, 0.0), &[class()]).unwrap();
    assert_eq!(over.class.as_ref().map(|c| c.name.as_str()), Some("test"));
    assert_eq!(over.frames_beyond_envelope, Some(1));
    // the same sign-flipped (either quadrant) is counted too
    let over = size_motor(&two(-4.9, -90.0), &spec(1.0, 0.0), &[class()]).unwrap();
    assert_eq!(over.frames_beyond_envelope, Some(1));
    // 4.0 N·m at 90 rad/s lies under it
    let under = size_motor(&two(4.0, 90.0), &spec(1.0, 0.0), &[class()]).unwrap();
    assert_eq!(under.frames_beyond_envelope, Some(0));
    // a class without a no-load speed has no envelope: nothing counted, and said so
    let plain = MotorClass {
        no_load_speed_rad_s: None,
        ..class()
    };
    let l = size_motor(&two(4.9, 90.0), &spec(1.0, 0.0), &[plain]).unwrap();
    assert_eq!(l.frames_beyond_envelope, None);
}

#[test]
fn a_catalogue_whose_rated_point_lies_beyond_its_peak_line_is_an_error() {
    let text = |w0: f64| {
        format!(
            "[[class]]\nname = \"x\"\nrated_torque_nm = 1.0\npeak_torque_nm = 2.0\n\
             rated_speed_rpm = 3000\nno_load_speed_rpm = {w0}\n"
        )
    };
    let path = std::path::Path::new("c.toml");
    // 2·(1 − 3000/8000) = 1.25 ≥ 1: fine; 2·(1 − 3000/5000) = 0.8 < 1: the rated point is out
    assert!(parse_catalogue(&text(8000.0), path).is_ok());
    let e = parse_catalogue(&text(5000.0), path)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("c.toml") && e.contains("no_load_speed_rpm"),
        "{e}"
    );
    // the bundled catalogue gives every class its envelope
    let all = articula::report::motor::default_catalogue().unwrap();
    assert!(all.iter().all(|c| Envelope::of(c).is_some()));
}

#[test]
fn driven_and_regenerated_energy_add_to_the_absolute_work_and_differ_by_the_net_work() {
    // P = 20 sin(2πt) + 3 on an uneven grid: both signs, zero crossings between samples
    let t: Vec<f64> = (0..=700)
        .map(|i| (i as f64 / 700.0).powf(1.3) * 1.7)
        .collect();
    let p: Vec<f64> = t
        .iter()
        .map(|&t| 20.0 * (2.0 * std::f64::consts::PI * t).sin() + 3.0)
        .collect();
    let trapz = |f: &dyn Fn(f64) -> f64| -> f64 {
        t.windows(2)
            .zip(p.windows(2))
            .map(|(t, p)| 0.5 * (t[1] - t[0]) * (f(p[0]) + f(p[1])))
            .sum()
    };
    let e = energy(&t, &p);
    assert!(e.driven_j > 1.0 && e.regen_j > 1.0, "{e:?}");
    let (abs, net) = (trapz(&f64::abs), trapz(&|x| x));
    assert!(
        (e.driven_j + e.regen_j - abs).abs() <= 1e-12 * abs,
        "{e:?} {abs}"
    );
    assert!(
        (e.driven_j - e.regen_j - net).abs() <= 1e-12 * abs,
        "{e:?} {net}"
    );
    // the sizing carries the same figures of τ·q̇
    let m = JointMotion {
        joint: "j".into(),
        tau: p.clone(),
        qd: vec![1.0; t.len()],
        qdd: vec![0.0; t.len()],
        t: t.clone(),
    };
    let l = size_motor(&m, &spec(10.0, 0.0), &[class()]).unwrap();
    assert_eq!(l.energy, e);
}

#[test]
fn the_rotor_term_is_j_n_squared_times_the_acceleration_on_the_demo() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (j, n) = (3.0e-5, 80.0);
    let session = d.join("rotor.session");
    std::fs::write(
        &session,
        format!(
            "load demo:walk\nselect LeftLeg\nset motor.gear {n}\nset motor.rotor_inertia {j}\n\
             report motor curves {}\nexport csv {}\nreport motor {}\n",
            d.join("curves.csv").display(),
            d.join("states.csv").display(),
            d.join("table.csv").display(),
        ),
    )
    .unwrap();
    articula().arg("run").arg(&session).assert().success();
    let (hc, curves) = articula::report::csv::read_columns(&d.join("curves.csv")).unwrap();
    let (hs, states) = articula::report::csv::read_columns(&d.join("states.csv")).unwrap();
    let col = |h: &[String], name: &str| h.iter().position(|x| x == name).unwrap();
    let coord = "LeftLeg.Xrotation";
    let rotor = &curves[col(&hc, &format!("rotor_tau:{coord}"))];
    let a = &states[col(&hs, &format!("a:{coord}"))];
    assert_eq!(rotor.len(), a.len());
    let peak = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(peak > 1.0, "the knee accelerates: {peak} rad/s²");
    for (r, a) in rotor.iter().zip(a) {
        assert!(
            (r - j * n * n * a).abs() <= 1e-12 * (j * n * n * peak),
            "{r} vs J·N²·{a}"
        );
    }
    // the current carries it: I = (τ + η·J·N²·q̈) / (Km·N·η), η = 1, Km = 0.1
    let tau = &curves[col(&hc, &format!("tau:{coord}"))];
    let current = &curves[col(&hc, &format!("current:{coord}"))];
    for k in 0..tau.len() {
        let want = (tau[k] + rotor[k]) / (0.1 * n);
        assert!((current[k] - want).abs() <= 1e-9 * want.abs().max(1.0));
    }
    // and the table shows its peak
    let text = std::fs::read_to_string(d.join("table.csv")).unwrap();
    let mut rdr = csv::Reader::from_reader(text.as_bytes());
    let h: Vec<String> = rdr.headers().unwrap().iter().map(String::from).collect();
    let row = rdr
        .records()
        .map(Result::unwrap)
        .find(|r| &r[0] == coord)
        .unwrap();
    let peak_rotor: f64 = row[col(&h, "peak:rotor_tau")].parse().unwrap();
    assert!((peak_rotor - j * n * n * peak).abs() <= 1e-9 * peak_rotor);
    assert_eq!(row[col(&h, "rotor_inertia")].parse::<f64>().unwrap(), j);
}

#[test]
fn a_negative_rotor_inertia_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let session = dir.path().join("bad.session");
    std::fs::write(&session, "load demo:walk\nset motor.rotor_inertia -1\n").unwrap();
    articula()
        .arg("run")
        .arg(&session)
        .assert()
        .failure()
        .stderr(predicates::str::contains("bad.session:2"))
        .stderr(predicates::str::contains("rotor inertia in kg·m²"))
        .stderr(predicates::str::contains("non-negative"));
}
