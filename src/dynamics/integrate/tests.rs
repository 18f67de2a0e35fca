//! The integrators' unit tests: tableaux, the stage layout and the in-place stages against
//! the general ones, bit for bit.

use super::*;
use crate::model::ModelBuilder;
use crate::spatial::{SpatialInertia, SpatialTransform};

/// The stepper's split of the coordinates moves a stage exactly as `Model::integrate` and
/// `tangent_rate` do, bit for bit, on trees with ball and free joints among the revolutes.
#[test]
fn stage_layout_is_integrate_and_tangent_rate_bit_for_bit() {
    use crate::dynamics::samples::{SplitMix64, random_configuration, random_tree, random_vector};
    for (seed, floating) in [(3, false), (4, true), (5, true)] {
        let model = random_tree(20, seed, floating);
        let layout = Layout::new(&model);
        let mut rng = SplitMix64(seed);
        let mut q = vec![0.0; model.nq];
        random_configuration(&model, &mut rng, &mut q);
        let (mut omega, mut v) = (vec![0.0; model.nv], vec![0.0; model.nv]);
        random_vector(&mut rng, 0.3, &mut omega);
        random_vector(&mut rng, 2.0, &mut v);
        let (mut a, mut b) = (vec![0.0; model.nq], vec![0.0; model.nq]);
        model.integrate(&q, &omega, 1.0, &mut a);
        layout.integrate(&model, &q, &omega, &mut b);
        assert_eq!(a, b, "integrate, seed {seed}");
        let (mut a, mut b) = (vec![0.0; model.nv], vec![0.0; model.nv]);
        tangent_rate(&model, &omega, &v, &mut a);
        layout.tangent_rate(&model, &omega, &v, &mut b);
        assert_eq!(a, b, "tangent rate, seed {seed}");
    }
}

/// The one-term stages advanced in place give the general stages' bits, on models of 1-DoF
/// joints only and on trees with ball and free joints among them, for Euler and RK4, both
/// called alone and through `step`.
#[test]
fn one_term_stages_in_place_are_the_general_stages_bit_for_bit() {
    use crate::dynamics::samples::{
        SplitMix64, arm7, euler_avatar, random_configuration, random_tree, random_vector,
    };
    use crate::dynamics::{Workspace, aba};
    assert!(EULER.one_term_rows() && RK4.one_term_rows() && !DOPRI5.one_term_rows());
    let models = [
        arm7(),
        euler_avatar(),
        random_tree(20, 3, false),
        random_tree(20, 4, true),
        random_tree(20, 5, true),
    ];
    for (k, model) in models.iter().enumerate() {
        assert_eq!(
            Layout::new(model).manifold.is_empty(),
            k < 2,
            "{}",
            model.name
        );
        let mut ws = Workspace::new(model);
        let mut rng = SplitMix64(11 + k as u64);
        let tau: Vec<f64> = (0..model.nv).map(|k| (k as f64).sin()).collect();
        let mut f = |_t: f64, q: &[f64], v: &[f64], acc: &mut [f64]| {
            acc.copy_from_slice(aba(model, &mut ws, q, v, &tau, None)?.as_slice());
            Ok(())
        };
        for integrator in [Integrator::Euler, Integrator::Rk4] {
            let tab = integrator.tableau().unwrap();
            let mut st = Stepper::new(model, integrator);
            let mut q = vec![0.0; model.nq];
            random_configuration(model, &mut rng, &mut q);
            if k == 1 {
                // the euler avatar away from its gimbal locks
                random_vector(&mut rng, 0.4, &mut q);
            }
            let mut v = vec![0.0; model.nv];
            random_vector(&mut rng, 2.0, &mut v);
            let t = 0.25;
            st.rk_stages(model, tab, t, 1e-3, &q, &v, &mut f).unwrap();
            let (q_new, v_new) = (st.q_new.clone(), st.v_new.clone());
            let (mut q1, mut v1) = (q.clone(), v.clone());
            st.rk_one_term(model, tab, t, 1e-3, &mut q1, &mut v1, &mut f)
                .unwrap();
            assert_eq!((&q1, &v1), (&q_new, &v_new), "{integrator}, {}", model.name);
            st.step(model, t, 1e-3, &mut q, &mut v, &mut f).unwrap();
            assert_eq!((q, v), (q_new, v_new), "{integrator} step, {}", model.name);
        }
    }
}

#[test]
fn names_round_trip() {
    for s in [
        "euler",
        "semi-implicit",
        "rk4",
        "dopri5:1e-8",
        "dopri5:1e-6,1e-9",
    ] {
        let i: Integrator = s.parse().unwrap();
        assert_eq!(i.to_string().parse::<Integrator>().unwrap(), i, "{s}");
    }
    assert_eq!(
        "dopri5".parse::<Integrator>().unwrap(),
        Integrator::Dopri5 {
            rtol: 1e-6,
            atol: 1e-6
        }
    );
    for bad in ["rk5", "dopri5:", "dopri5:-1", "dopri5:x", "euler:1"] {
        assert!(bad.parse::<Integrator>().is_err(), "{bad}");
    }
}

#[test]
fn tableaux_are_consistent() {
    // Σ b = 1, c_s = Σ_j a_sj, Σ e = 0
    for tab in [&EULER, &RK4, &DOPRI5] {
        assert!(
            (tab.b.iter().sum::<f64>() - 1.0).abs() < 1e-15,
            "{}",
            tab.name
        );
        for (row, c) in tab.a.iter().zip(tab.c) {
            assert!((row.iter().sum::<f64>() - c).abs() < 1e-15, "{}", tab.name);
        }
        if let Some(e) = tab.e {
            assert!(e.iter().sum::<f64>().abs() < 1e-15);
        }
    }
}

#[test]
fn tangent_rate_is_the_inverse_differential_of_integrate() {
    // q ⊕ (Ω + ε Ω̇) = (q ⊕ Ω) ⊕ ε v to first order in ε
    let mut mb = ModelBuilder::new("t", Vector3::zeros());
    let i = SpatialInertia::ZERO;
    let b = mb.add_body(0, "f", "f", JointKind::Free, SpatialTransform::IDENTITY, i);
    mb.add_body(
        b,
        "s",
        "s",
        JointKind::Spherical,
        SpatialTransform::IDENTITY,
        i,
    );
    let model = mb.build();
    let mut q0 = model.neutral();
    model.integrate(
        &q0.clone(),
        &[0.3, -0.2, 0.5, 0.7, -0.4, 0.2, 1.1, 0.3, -0.8],
        1.0,
        &mut q0,
    );
    let omega = [0.2, 0.1, -0.3, 0.25, -0.15, 0.3, 0.2, -0.35, 0.1];
    let v = [1.0, -0.5, 0.3, 0.4, 0.9, -0.7, -0.6, 0.2, 0.8];
    let mut rate = [0.0; 9];
    tangent_rate(&model, &omega, &v, &mut rate);
    let eps = 1e-6;
    let mut a = vec![0.0; model.nq];
    let o2: Vec<f64> = omega.iter().zip(&rate).map(|(o, r)| o + eps * r).collect();
    model.integrate(&q0, &o2, 1.0, &mut a);
    let mut mid = vec![0.0; model.nq];
    model.integrate(&q0, &omega, 1.0, &mut mid);
    let mut b = vec![0.0; model.nq];
    model.integrate(&mid, &v, eps, &mut b);
    for k in 0..model.nq {
        // series truncation ~|Ω|⁶/30240 plus the O(ε²) of the finite difference
        assert!((a[k] - b[k]).abs() < 1e-10, "q[{k}]: {} vs {}", a[k], b[k]);
    }
}
