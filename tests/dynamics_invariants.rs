//! Physics the integrators must reproduce:
//! - a simple pendulum released from 2 rad swings with the large-amplitude period
//!   `T = 4 √(l/g) K(sin(θ₀/2))` (K the complete elliptic integral of the first kind);
//! - with τ = 0, no gravity and no friction, a free-floating tree conserves its kinetic energy
//!   and its spatial momentum (world frame); RK4 at 1 ms over 10 s keeps both to the drift
//!   printed by the test (measured: see the assertions' bounds);
//! - a free body spinning fast about its unstable intermediate axis keeps energy, momentum
//!   and a unit quaternion.

use articula::dynamics::samples::{SplitMix64, humanoid, random_tree, random_vector};
use articula::dynamics::{
    Integrator, Stepper, Workspace, aba, kinetic_energy, potential_energy, spatial_momentum,
};
use articula::model::{JointKind, Model, ModelBuilder};
use articula::spatial::{SpatialInertia, SpatialTransform};
use nalgebra::{Matrix3, Vector3};

/// K(k) by the arithmetic-geometric mean: `K = π / (2 AGM(1, √(1 − k²)))`.
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0, (1.0 - k * k).sqrt());
    while (a - b).abs() > 1e-16 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    std::f64::consts::PI / (2.0 * a)
}

/// Integrates `model` with τ = 0 for `steps` steps, calling `each(t, q, v)` after every step.
fn free_motion(
    model: &Model,
    integrator: Integrator,
    dt: f64,
    steps: usize,
    q: &mut [f64],
    v: &mut [f64],
    mut each: impl FnMut(f64, &[f64], &[f64]),
) {
    let mut ws = Workspace::new(model);
    let mut stepper = Stepper::new(model, integrator);
    let tau = vec![0.0; model.nv];
    let mut f = |_t: f64, q: &[f64], v: &[f64], acc: &mut [f64]| {
        acc.copy_from_slice(aba(model, &mut ws, q, v, &tau, None)?.as_slice());
        Ok(())
    };
    for n in 0..steps {
        let t = n as f64 * dt;
        stepper.step(model, t, dt, q, v, &mut f).unwrap();
        each(t + dt, q, v);
    }
}

#[test]
fn pendulum_period_matches_the_elliptic_integral() {
    let (m, l, g, theta0) = (1.5, 0.8, 9.81, 2.0f64);
    let mut mb = ModelBuilder::new("pendulum", Vector3::new(0.0, -g, 0.0));
    mb.add_body(
        0,
        "bob",
        "hinge",
        JointKind::Revolute { axis: Vector3::z() },
        SpatialTransform::IDENTITY,
        SpatialInertia::new(m, Vector3::new(0.0, -l, 0.0), Matrix3::zeros()),
    );
    let model = mb.build();
    let expected = 4.0 * (l / g).sqrt() * elliptic_k((theta0 / 2.0).sin());
    for (integrator, dt, tol) in [
        (Integrator::Rk4, 1e-3, 1e-9),
        ("dopri5:1e-10".parse().unwrap(), 1e-3, 1e-8),
        (Integrator::SemiImplicitEuler, 1e-4, 1e-4),
    ] {
        // downward zero crossings of θ, linearly interpolated (θ̈ = 0 there)
        let mut crossings = vec![];
        let (mut q, mut v) = (vec![theta0], vec![0.0]);
        let mut prev = (0.0, theta0);
        let steps = (3.2 * expected / dt) as usize;
        free_motion(&model, integrator, dt, steps, &mut q, &mut v, |t, q, _| {
            if prev.1 > 0.0 && q[0] <= 0.0 {
                crossings.push(prev.0 + (t - prev.0) * prev.1 / (prev.1 - q[0]));
            }
            prev = (t, q[0]);
        });
        assert!(crossings.len() >= 3, "{integrator}: {crossings:?}");
        let period = (crossings[2] - crossings[0]) / 2.0;
        let err = (period - expected).abs() / expected;
        eprintln!("{integrator} dt={dt}: period {period:.12} s vs {expected:.12} s ({err:.1e})");
        assert!(
            err < tol,
            "{integrator}: period {period} vs {expected} ({err:e})"
        );
    }
}

/// Kinetic energy and spatial momentum (world frame) of a model with no gravity.
fn invariants(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
) -> (f64, Vector3<f64>, Vector3<f64>) {
    let t = kinetic_energy(model, ws, q, v);
    let h = spatial_momentum(model, ws, q, v);
    (t, h.lin, h.ang)
}

#[test]
fn floating_trees_conserve_energy_and_momentum_with_rk4_at_1ms() {
    let mut rng = SplitMix64(11);
    let cases = [
        (humanoid(true), "humanoid (free root, 35 DoF)"),
        (
            random_tree(10, 3, true),
            "random tree (free root, ball joints)",
        ),
    ];
    for (mut model, what) in cases {
        model.gravity = Vector3::zeros();
        let mut ws = Workspace::new(&model);
        let mut q = model.neutral();
        // a pose away from neutral, and a tumble
        let mut dq = vec![0.0; model.nv];
        random_vector(&mut rng, 0.5, &mut dq);
        let q0 = q.clone();
        model.integrate(&q0, &dq, 1.0, &mut q);
        let mut v = vec![0.0; model.nv];
        random_vector(&mut rng, 1.0, &mut v);
        let (t0, p0, l0) = invariants(&model, &mut ws, &q, &v);
        let mut ws2 = Workspace::new(&model);
        let (mut de, mut dp, mut dl) = (0.0f64, 0.0f64, 0.0f64);
        let mut qn: f64 = 0.0;
        free_motion(
            &model,
            Integrator::Rk4,
            1e-3,
            10_000,
            &mut q,
            &mut v,
            |_, q, v| {
                let (t, p, l) = invariants(&model, &mut ws2, q, v);
                de = de.max((t - t0).abs() / t0);
                dp = dp.max((p - p0).norm() / p0.norm().max(1.0));
                dl = dl.max((l - l0).norm() / l0.norm().max(1.0));
                qn = qn.max((q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt() - 1.0).abs());
            },
        );
        eprintln!(
            "{what}: over 10 s, max relative drift energy {de:.2e}, linear momentum {dp:.2e}, \
             angular momentum {dl:.2e}; |quaternion| − 1 ≤ {qn:.1e} (T₀ = {t0:.3} J)"
        );
        assert!(de < 1e-7, "{what}: energy drift {de:e}");
        assert!(dp < 1e-7, "{what}: linear momentum drift {dp:e}");
        assert!(dl < 1e-6, "{what}: angular momentum drift {dl:e}");
        assert!(qn < 1e-12, "{what}: quaternion norm off by {qn:e}");
        // gravity-free: potential energy is identically zero
        assert_eq!(potential_energy(&model, &mut ws, &q), 0.0);
    }
}

#[test]
fn very_fast_spin_about_the_intermediate_axis() {
    // a free box-like body, principal moments 1 : 2 : 3, spinning at 100 rad/s mostly about
    // its intermediate axis (it flips periodically: the Dzhanibekov effect)
    let mut mb = ModelBuilder::new("spinner", Vector3::zeros());
    mb.add_body(
        0,
        "box",
        "root",
        JointKind::Free,
        SpatialTransform::IDENTITY,
        SpatialInertia::new(
            2.0,
            Vector3::zeros(),
            Matrix3::from_diagonal(&Vector3::new(0.1, 0.2, 0.3)),
        ),
    );
    let model = mb.build();
    let mut ws = Workspace::new(&model);
    for (integrator, dt, tol) in [
        (Integrator::Rk4, 1e-4, 1e-6),
        ("dopri5:1e-10".parse().unwrap(), 1e-3, 1e-6),
    ] {
        let mut q = model.neutral();
        let mut v = vec![0.3, 0.0, -0.2, 0.5, 100.0, 0.5];
        let (t0, p0, l0) = invariants(&model, &mut ws, &q, &v);
        let steps = (1.0 / dt) as usize;
        let (mut de, mut dl, mut flipped) = (0.0f64, 0.0f64, false);
        free_motion(&model, integrator, dt, steps, &mut q, &mut v, |_, q, v| {
            let (t, p, l) = invariants(&model, &mut Workspace::new(&model), q, v);
            de = de.max((t - t0).abs() / t0);
            dl = dl
                .max((l - l0).norm() / l0.norm())
                .max((p - p0).norm() / p0.norm());
            flipped |= v[4] < -50.0;
        });
        eprintln!("spin, {integrator} dt={dt}: energy drift {de:.1e}, momentum drift {dl:.1e}");
        assert!(
            flipped,
            "{integrator}: the intermediate axis should flip within 1 s"
        );
        assert!(de < tol && dl < tol, "{integrator}: drift {de:e} {dl:e}");
        let n = q[3..7].iter().map(|x| x * x).sum::<f64>().sqrt();
        assert!((n - 1.0).abs() < 1e-12);
    }
}
