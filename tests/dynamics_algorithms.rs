//! The dynamics algorithms checked against each other (Pinocchio's `unittest/crba.cpp`,
//! `unittest/aba.cpp`), on random trees (revolute, prismatic, spherical, free joints) and on the
//! sample arm, humanoid and euler avatar:
//! - column k of `D(q)` is `RNEA(q, 0, e_k) − RNEA(q, 0, 0)`, and `D` is symmetric positive
//!   definite;
//! - ABA inverts RNEA: `ABA(q, v, RNEA(q, v, a, f_ext), f_ext) = a`, with friction and external
//!   forces; the Cholesky route gives the same `q̈` to 1e-10;
//! - `h = RNEA(q, v, 0) − c − b v`, `h + c = nle`, `c = ∂V/∂q`, `T = ½ vᵀ D v`.

use articula::dynamics::samples::{
    SplitMix64, arm7, euler_avatar, humanoid, random_configuration, random_tree, random_vector,
};
use articula::dynamics::{
    Workspace, aba, coriolis_terms, crba, forward_dynamics_cholesky, gravity_terms, kinetic_energy,
    nonlinear_effects, potential_energy, rnea,
};
use articula::model::Model;
use articula::spatial::ForceVec;
use nalgebra::{DMatrix, DVector};

fn models() -> Vec<Model> {
    let mut out = vec![arm7(), humanoid(false), humanoid(true), euler_avatar()];
    for seed in 0..6 {
        out.push(random_tree(12, seed, seed % 2 == 1));
    }
    // friction on every coordinate of a couple of models
    for m in out.iter_mut().skip(4).step_by(2) {
        for (k, b) in m.damping.iter_mut().enumerate() {
            *b = 0.1 + 0.05 * k as f64;
        }
    }
    out
}

/// A random state (q, v, a) of `model`.
fn state(model: &Model, rng: &mut SplitMix64) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    let mut q = vec![0.0; model.nq];
    random_configuration(model, rng, &mut q);
    if model.name == "euler_avatar" {
        // keep the euler chains away from gimbal lock (middle angle ±π/2), where D is singular
        q.iter_mut().for_each(|x| *x *= 0.4);
    }
    let mut v = vec![0.0; model.nv];
    random_vector(rng, 2.0, &mut v);
    let mut a = vec![0.0; model.nv];
    random_vector(rng, 4.0, &mut a);
    (q, v, a)
}

fn rel_err(a: &DVector<f64>, b: &DVector<f64>) -> f64 {
    (a - b).amax() / b.amax().max(1.0)
}

#[test]
fn mass_matrix_columns_are_rnea_differences() {
    let mut rng = SplitMix64(1);
    for model in models() {
        let mut ws = Workspace::new(&model);
        let (q, _, _) = state(&model, &mut rng);
        let zero = vec![0.0; model.nv];
        let c = rnea(&model, &mut ws, &q, &zero, &zero, None).clone();
        let d = crba(&model, &mut ws, &q).clone();
        let scale = d.amax();
        for k in 0..model.nv {
            let mut e = zero.clone();
            e[k] = 1.0;
            let col = rnea(&model, &mut ws, &q, &zero, &e, None) - &c;
            let err = (col - d.column(k)).amax() / scale;
            assert!(err < 1e-12, "{}: column {k} off by {err:e}", model.name);
        }
        // symmetric positive definite
        assert_eq!(d, d.transpose(), "{}", model.name);
        assert!(d.clone().cholesky().is_some(), "{}: D not SPD", model.name);
    }
}

#[test]
fn aba_inverts_rnea_and_cholesky_agrees() {
    let mut rng = SplitMix64(2);
    for model in models() {
        let mut ws = Workspace::new(&model);
        for trial in 0..3 {
            let (q, v, a) = state(&model, &mut rng);
            // external forces on every body on the last trial
            let f_ext: Vec<ForceVec> = (0..model.nbodies())
                .map(|_| ForceVec::new(rng.vec3(5.0), rng.vec3(20.0)))
                .collect();
            let fx = (trial == 2).then_some(&f_ext[..]);
            let tau = rnea(&model, &mut ws, &q, &v, &a, fx).clone();
            let a_aba = aba(&model, &mut ws, &q, &v, tau.as_slice(), fx)
                .unwrap_or_else(|e| panic!("{}: {e}", model.name))
                .clone();
            let a_ref = DVector::from_column_slice(&a);
            let err = rel_err(&a_aba, &a_ref);
            // ABA works in world axes (about each body's origin) and RNEA in body axes: on the
            // euler avatar's random states (ill-conditioned D(q)) the two round differently;
            // 1.6e-10 (and 2.0e-10 against the Cholesky solve) measured with external forces on
            // every body
            assert!(
                err < 1e-9,
                "{} trial {trial}: aba off by {err:e}",
                model.name
            );
            let a_chol = forward_dynamics_cholesky(&model, &mut ws, &q, &v, tau.as_slice(), fx)
                .unwrap()
                .clone();
            let err = rel_err(&a_chol, &a_aba);
            assert!(
                err < 1e-9,
                "{} trial {trial}: cholesky vs aba {err:e}",
                model.name
            );
        }
    }
}

#[test]
fn bias_terms_split_the_equation_of_motion() {
    let mut rng = SplitMix64(3);
    for model in models() {
        let mut ws = Workspace::new(&model);
        let (q, v, a) = state(&model, &mut rng);
        let zero = vec![0.0; model.nv];
        let c = gravity_terms(&model, &mut ws, &q).clone();
        let h = coriolis_terms(&model, &mut ws, &q, &v).clone();
        let nle = nonlinear_effects(&model, &mut ws, &q, &v).clone();
        let d = crba(&model, &mut ws, &q).clone();
        let bv = DVector::from_iterator(model.nv, model.damping.iter().zip(&v).map(|(b, v)| b * v));
        let rnea_v0 = rnea(&model, &mut ws, &q, &v, &zero, None).clone();
        assert!(
            rel_err(&h, &(&rnea_v0 - &c - &bv)) < 1e-12,
            "{}",
            model.name
        );
        assert!(rel_err(&nle, &(&h + &c)) < 1e-12, "{}", model.name);
        // the paper's equation 1 with friction: D a + h + c + b v = τ
        let tau = rnea(&model, &mut ws, &q, &v, &a, None).clone();
        let lhs = &d * DVector::from_column_slice(&a) + &h + &c + &bv;
        assert!(rel_err(&lhs, &tau) < 1e-12, "{}", model.name);
    }
}

#[test]
fn gravity_term_is_the_gradient_of_potential_energy() {
    // c(q) = ∂V/∂q for coordinates whose velocity is the rate of q (revolute, prismatic)
    let mut rng = SplitMix64(4);
    for model in [arm7(), humanoid(false), euler_avatar()] {
        let mut ws = Workspace::new(&model);
        let (q, _, _) = state(&model, &mut rng);
        let c = gravity_terms(&model, &mut ws, &q).clone();
        let h = 1e-6;
        for k in 0..model.nv {
            let (mut qp, mut qm) = (q.clone(), q.clone());
            qp[k] += h;
            qm[k] -= h;
            let dv = (potential_energy(&model, &mut ws, &qp)
                - potential_energy(&model, &mut ws, &qm))
                / (2.0 * h);
            assert!(
                (dv - c[k]).abs() < 1e-6 * c.amax().max(1.0),
                "{} {k}: {dv} vs {}",
                model.name,
                c[k]
            );
        }
    }
}

#[test]
fn kinetic_energy_is_the_mass_matrix_quadratic_form() {
    let mut rng = SplitMix64(5);
    for model in models() {
        let mut ws = Workspace::new(&model);
        let (q, v, _) = state(&model, &mut rng);
        let d: DMatrix<f64> = crba(&model, &mut ws, &q).clone();
        let vv = DVector::from_column_slice(&v);
        let t = 0.5 * vv.dot(&(&d * &vv));
        let t2 = kinetic_energy(&model, &mut ws, &q, &v);
        assert!(
            (t - t2).abs() < 1e-12 * t.max(1.0),
            "{}: {t} vs {t2}",
            model.name
        );
    }
}
