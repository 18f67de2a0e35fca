//! Computed-torque tracking (the paper's equation 2) and its behaviour at the extremes.
//!
//! With the exact model the closed loop is `ë + Kv ė + Kp e = 0`: starting on the reference,
//! the error stays at integration round-off. With link masses off by x %, the error is what the
//! PD terms cannot correct, and it shrinks as the gains grow. Past an integrator's stability
//! limit the simulation stops with a clear error naming the step, the time and the coordinate;
//! the adaptive integrator sub-steps instead. A singular mass matrix (gimbal lock of the euler
//! model) is reported naming the joint. Extreme gains (0 to 1e6), link masses (1e-6 to 1e4 kg)
//! and a 100 000-sample reference all run.

use articula::dynamics::samples::{arm7, euler_avatar, humanoid, random_tree};
use articula::dynamics::{
    Gains, Integrator, Reference, SimOptions, Workspace, aba, floating_root_nv,
    forward_dynamics_cholesky, rnea, simulate,
};
use articula::error::Error;
use articula::model::Model;

/// `q(t) = q_n + A_k sin(ω_k t + φ_k)` on every coordinate of a model whose coordinates are all
/// 1-DoF, sampled every `dt` for `duration`, with the analytic `v`, `a`.
fn sine_reference(model: &Model, amplitude: f64, duration: f64, dt: f64) -> Reference {
    assert_eq!(model.nq, model.nv);
    let n = (duration / dt).round() as usize + 1;
    let mut r = Reference::default();
    let q0 = model.neutral();
    for s in 0..n {
        let t = s as f64 * dt;
        let (mut q, mut v, mut a) = (q0.clone(), vec![0.0; model.nv], vec![0.0; model.nv]);
        for k in 0..model.nv {
            let (w, phi) = (1.0 + 0.37 * k as f64 % 2.3, 0.5 * k as f64);
            let amp = amplitude * (1.0 - 0.3 * (k % 3) as f64 / 2.0);
            q[k] += amp * (w * t + phi).sin();
            v[k] = amp * w * (w * t + phi).cos();
            a[k] = -amp * w * w * (w * t + phi).sin();
        }
        r.time.push(t);
        r.q.push(q);
        r.v.push(v);
        r.a.push(a);
    }
    r
}

fn opts(integrator: Integrator, dt: f64, kp: f64, mass_error: f64) -> SimOptions {
    SimOptions {
        integrator,
        dt,
        gains: Gains::scalar(kp, 2.0 * kp.sqrt()),
        mass_error,
        max_speed: 1e3,
        max_error: std::f64::consts::PI,
    }
}

fn numerical(r: Result<articula::dynamics::SimResult, Error>) -> String {
    match r {
        Err(Error::Numerical(m)) => m,
        Err(e) => panic!("expected a numerical error, got {e}"),
        Ok(r) => panic!(
            "expected a numerical error, got a result ({} steps)",
            r.steps
        ),
    }
}

#[test]
fn exact_model_tracks_to_round_off_and_mass_error_needs_gains() {
    let model = arm7();
    let reference = sine_reference(&model, 0.5, 2.0, 1.0 / 120.0);
    let exact = simulate(&model, &reference, &opts(Integrator::Rk4, 1e-3, 400.0, 0.0)).unwrap();
    assert_eq!(exact.steps, 2000);
    assert_eq!(exact.time.len(), reference.len());
    // what is left is the 120 Hz reference's interpolation (a linear, q cubic): O(h²)
    assert!(
        exact.max_error_rad() < 1e-5,
        "exact model: {:e}",
        exact.max_error_rad()
    );
    let fine = sine_reference(&model, 0.5, 2.0, 1e-3);
    let r = simulate(&model, &fine, &opts(Integrator::Rk4, 1e-3, 400.0, 0.0)).unwrap();
    assert!(
        r.max_error_rad() < 1e-7,
        "exact model, 1 kHz reference: {:e}",
        r.max_error_rad()
    );
    // masses 20 % heavy in the controller: the higher the gains, the smaller the error
    let mut last = f64::INFINITY;
    for kp in [10.0, 100.0, 1e3, 1e4] {
        let r = simulate(&model, &reference, &opts(Integrator::Rk4, 1e-3, kp, 0.2)).unwrap();
        eprintln!(
            "kp {kp}: rms {:.2e} rad, max {:.2e} rad",
            r.rms_error_rad(),
            r.max_error_rad()
        );
        assert!(r.rms_error_rad() < last, "kp {kp}");
        assert!(r.rms_error_rad() > 1e-6, "kp {kp}: a wrong model must show");
        last = r.rms_error_rad();
    }
    // the JSON summary carries what `articula simulate --json` promises
    let j = exact.summary_json();
    for key in [
        "rms_error_rad",
        "max_error_rad",
        "steps",
        "integrator",
        "dt",
    ] {
        assert!(j.get(key).is_some(), "{key}");
    }
    assert_eq!(j["integrator"], "rk4");
}

#[test]
fn every_integrator_tracks_below_its_limit_and_fails_clearly_past_it() {
    let model = arm7();
    let reference = sine_reference(&model, 0.5, 2.0, 1.0 / 120.0);
    // Kp = 1e4, Kv = 200: closed-loop poles at -100 rad/s
    let integrators = [
        Integrator::Euler,
        Integrator::SemiImplicitEuler,
        Integrator::Rk4,
        "dopri5:1e-8".parse().unwrap(),
    ];
    for integrator in integrators {
        let r = simulate(&model, &reference, &opts(integrator, 1e-3, 1e4, 0.1)).unwrap();
        assert!(
            r.max_error_rad() < 1e-2,
            "{integrator}: {}",
            r.max_error_rad()
        );
        let past = simulate(&model, &reference, &opts(integrator, 0.05, 1e4, 0.1));
        if let Integrator::Dopri5 { .. } = integrator {
            // adaptive: it sub-steps through
            let r = past.unwrap();
            assert!(
                r.max_error_rad() < 1e-2,
                "{integrator}: {}",
                r.max_error_rad()
            );
        } else {
            let m = numerical(past);
            eprintln!("{integrator} at dt = 0.05 s: {m}");
            assert!(m.contains("simulation step") && m.contains("t = "), "{m}");
            assert!(m.contains("joint"), "names a coordinate: {m}");
            assert!(m.contains("--dt"), "says what to change: {m}");
        }
    }
}

#[test]
fn gains_from_zero_to_a_million() {
    let model = arm7();
    let reference = sine_reference(&model, 0.5, 1.0, 1.0 / 120.0);
    for kp in [0.0, 1.0, 1e2, 1e4, 1e6] {
        // exact model: feedforward alone tracks (open loop: the interpolation error drifts
        // unchecked); huge gains stay stable at 0.1 ms with rk4
        let dt = if kp > 1e5 { 1e-4 } else { 1e-3 };
        let r = simulate(&model, &reference, &opts(Integrator::Rk4, dt, kp, 0.0)).unwrap();
        let tol = if kp < 100.0 { 1e-3 } else { 1e-5 };
        assert!(r.max_error_rad() < tol, "kp {kp}: {:e}", r.max_error_rad());
        let r = simulate(&model, &reference, &opts(Integrator::Rk4, dt, kp, 0.1)).unwrap();
        // with a wrong model and weak or no feedback the arm drifts away (nothing blows up)
        assert!(r.max_error_rad().is_finite(), "kp {kp}");
        assert!(
            kp < 100.0 || r.max_error_rad() < 0.5,
            "kp {kp}: {}",
            r.max_error_rad()
        );
    }
    // gains of the wrong size or sign are input errors
    let mut o = opts(Integrator::Rk4, 1e-3, 1.0, 0.0);
    o.gains = Gains {
        kp: vec![1.0; 3],
        kv: vec![1.0],
    };
    assert!(matches!(
        simulate(&model, &reference, &o),
        Err(Error::Invalid(_))
    ));
    o.gains = Gains::scalar(-1.0, 1.0);
    assert!(matches!(
        simulate(&model, &reference, &o),
        Err(Error::Invalid(_))
    ));
}

#[test]
fn link_masses_from_a_microgram_to_ten_tonnes() {
    // alternate links of 1e-6 kg and 1e4 kg (inertias scaled alike)
    for base in [arm7(), random_tree(10, 5, false)] {
        let mut model = base.clone();
        for (i, inertia) in model.inertia.iter_mut().enumerate().skip(1) {
            let m = if i % 2 == 0 { 1e-6 } else { 1e4 };
            inertia.inertia_com *= m / inertia.mass;
            inertia.mass = m;
        }
        let mut ws = Workspace::new(&model);
        let q: Vec<f64> = (0..model.nq).map(|k| 0.3 * k as f64 - 1.0).collect();
        let q = if model.nq == model.nv {
            q
        } else {
            model.neutral()
        };
        let v: Vec<f64> = (0..model.nv).map(|k| 0.5 - 0.1 * k as f64).collect();
        let a: Vec<f64> = (0..model.nv).map(|k| 1.0 - 0.2 * k as f64).collect();
        let tau = rnea(&model, &mut ws, &q, &v, &a, None).clone();
        let a1 = aba(&model, &mut ws, &q, &v, tau.as_slice(), None)
            .unwrap()
            .clone();
        let a2 = forward_dynamics_cholesky(&model, &mut ws, &q, &v, tau.as_slice(), None)
            .unwrap()
            .clone();
        for k in 0..model.nv {
            assert!(
                (a1[k] - a[k]).abs() < 1e-6,
                "{} aba {k}: {} vs {}",
                model.name,
                a1[k],
                a[k]
            );
            assert!(
                (a2[k] - a[k]).abs() < 1e-6,
                "{} cholesky {k}: {} vs {}",
                model.name,
                a2[k],
                a[k]
            );
        }
    }
    let mut model = arm7();
    for (i, inertia) in model.inertia.iter_mut().enumerate().skip(1) {
        let m = if i % 2 == 0 { 1e-6 } else { 1e4 };
        inertia.inertia_com *= m / inertia.mass;
        inertia.mass = m;
    }
    let reference = sine_reference(&model, 0.5, 1.0, 1.0 / 120.0);
    let r = simulate(&model, &reference, &opts(Integrator::Rk4, 1e-3, 400.0, 0.0)).unwrap();
    assert!(r.max_error_rad() < 1e-5, "{:e}", r.max_error_rad());
}

#[test]
fn gimbal_lock_of_the_euler_model_names_the_joint() {
    let model = euler_avatar();
    let mut ws = Workspace::new(&model);
    let x = model.v_index("LeftArm.Xrotation").unwrap();
    let tau = vec![0.0; model.nv];
    let v = vec![0.0; model.nv];
    // Z X Y: with X at ±90°, the Z and Y axes line up
    for delta in [0.0, 1e-5] {
        let mut q = model.neutral();
        q[x] = std::f64::consts::FRAC_PI_2 - delta;
        for r in [
            aba(&model, &mut ws, &q, &v, &tau, None).map(|_| ()),
            forward_dynamics_cholesky(&model, &mut ws, &q, &v, &tau, None).map(|_| ()),
        ] {
            let Err(Error::Numerical(m)) = r else {
                panic!("delta {delta}: gimbal lock not detected")
            };
            assert!(m.contains("LeftArm.Zrotation"), "{m}");
            assert!(m.contains("ball"), "{m}");
        }
    }
    // 1e-3 rad (0.06°) away the model is usable (D conditioned ~1e12 on this avatar)
    let mut q = model.neutral();
    q[x] = std::f64::consts::FRAC_PI_2 - 1e-3;
    aba(&model, &mut ws, &q, &v, &tau, None).unwrap();
    forward_dynamics_cholesky(&model, &mut ws, &q, &v, &tau, None).unwrap();

    // a reference that swings through the lock: the simulation stops and says where
    let mut reference = sine_reference(&model, 0.2, 1.0, 1.0 / 120.0);
    for (s, q) in reference.q.iter_mut().enumerate() {
        let t = s as f64 / 120.0;
        q[x] = std::f64::consts::FRAC_PI_2 * t; // reaches 90° at t = 1 s
    }
    for (s, v) in reference.v.iter_mut().enumerate() {
        let _ = s;
        v[x] = std::f64::consts::FRAC_PI_2;
    }
    reference.a.iter_mut().for_each(|a| a[x] = 0.0);
    let m = numerical(simulate(
        &model,
        &reference,
        &opts(Integrator::Rk4, 1e-3, 400.0, 0.0),
    ));
    eprintln!("{m}");
    assert!(
        m.contains("LeftArm.Zrotation") && m.contains("simulation step"),
        "{m}"
    );
}

#[test]
fn a_hundred_thousand_sample_reference() {
    let model = arm7();
    // 100 s at 1 kHz, simulated at 10 ms
    let reference = sine_reference(&model, 0.3, 99.999, 1e-3);
    assert_eq!(reference.len(), 100_000);
    let r = simulate(&model, &reference, &opts(Integrator::Rk4, 1e-2, 100.0, 0.0)).unwrap();
    assert_eq!(r.steps, 10_000);
    assert_eq!(r.time.len(), 10_001);
    assert!(r.max_error_rad() < 1e-3, "{}", r.max_error_rad());
    assert!(
        r.q.iter()
            .flatten()
            .chain(r.tau.iter().flatten())
            .all(|x| x.is_finite())
    );
}

#[test]
fn the_root_residual_is_reported_apart() {
    assert_eq!(floating_root_nv(&arm7()), 0);
    assert_eq!(floating_root_nv(&humanoid(false)), 0);
    assert_eq!(floating_root_nv(&humanoid(true)), 6);
    assert_eq!(floating_root_nv(&euler_avatar()), 6);
    // the euler avatar hangs from its root: the residual carries its weight
    let model = euler_avatar();
    let reference = sine_reference(&model, 0.1, 0.5, 1.0 / 120.0);
    let r = simulate(&model, &reference, &opts(Integrator::Rk4, 1e-3, 400.0, 0.0)).unwrap();
    assert_eq!(r.root_nv, 6);
    let weight = model.total_mass() * 9.81;
    let z = model.v_index("Hips.Zposition").unwrap();
    assert!(
        (r.root_residual_max[z] - weight).abs() < 0.5 * weight,
        "root z residual {} N vs weight {weight} N",
        r.root_residual_max[z]
    );
    let summary = r.summary_json();
    let names: Vec<&str> = summary["root_residual"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["name"].as_str().unwrap())
        .collect();
    assert_eq!(names[0], "Hips.Xposition");
    assert!(r.max_error_rad() < 1e-6, "{}", r.max_error_rad());
}
