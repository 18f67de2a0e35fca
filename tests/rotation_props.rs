//! Euler angles ↔ rotation matrices in all six orders, including at and near gimbal lock
//! (middle angle ±90°). Invariants: `euler_to_matrix` is a proper rotation and is the product
//! `R_c1 · R_c2 · R_c3`; `matrix_to_euler` gives back a triple that reproduces the matrix;
//! away from the poles it gives back the canonical triple itself; `matrix_to_euler_near`
//! picks the equivalent triple nearest the previous one, so slightly perturbed, unwrapped
//! angle sequences come back unchanged.

use articula::rotation::{
    EulerOrder, axis_rotation, euler_to_matrix, matrix_to_euler, matrix_to_euler_near,
};
use nalgebra::Matrix3;
use proptest::prelude::*;
use std::f64::consts::{FRAC_PI_2, PI};

fn order() -> impl Strategy<Value = EulerOrder> {
    proptest::sample::select(EulerOrder::ALL.to_vec())
}

/// Middle angles spread over the whole circle, with extra weight on and near ±90°.
fn middle_angle() -> impl Strategy<Value = f64> {
    prop_oneof![
        -PI..PI,
        Just(FRAC_PI_2),
        Just(-FRAC_PI_2),
        (-1e-6..1e-6f64).prop_map(|d| FRAC_PI_2 + d),
        (-1e-6..1e-6f64).prop_map(|d| -FRAC_PI_2 + d),
        (-1e-12..1e-12f64).prop_map(|d| FRAC_PI_2 + d),
    ]
}

fn close(a: &Matrix3<f64>, b: &Matrix3<f64>, tol: f64) -> bool {
    (a - b).abs().max() < tol
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

    #[test]
    fn matrix_is_the_ordered_product_and_a_rotation(o in order(), a in -7.0..7.0f64, b in middle_angle(), c in -7.0..7.0f64) {
        let r = euler_to_matrix(o, [a, b, c]);
        let [i, j, k] = o.axes();
        let product = axis_rotation(i, a) * axis_rotation(j, b) * axis_rotation(k, c);
        prop_assert!(close(&r, &product, 1e-15));
        prop_assert!(close(&(r.transpose() * r), &Matrix3::identity(), 1e-14));
        prop_assert!((r.determinant() - 1.0).abs() < 1e-14);
    }

    #[test]
    fn extraction_reproduces_the_matrix(o in order(), a in -7.0..7.0f64, b in middle_angle(), c in -7.0..7.0f64) {
        let r = euler_to_matrix(o, [a, b, c]);
        let e = matrix_to_euler(o, &r);
        prop_assert!(close(&euler_to_matrix(o, e), &r, 1e-12), "{:?} -> {:?}", [a, b, c], e);
        prop_assert!(e[1].abs() <= FRAC_PI_2 + 1e-12);
        prop_assert!(e[0].abs() <= PI + 1e-12 && e[2].abs() <= PI + 1e-12);
    }

    #[test]
    fn canonical_triples_come_back(o in order(), a in -3.1..3.1f64, b in -1.5..1.5f64, c in -3.1..3.1f64) {
        let e = matrix_to_euler(o, &euler_to_matrix(o, [a, b, c]));
        prop_assert!((e[0] - a).abs() < 1e-9 && (e[1] - b).abs() < 1e-9 && (e[2] - c).abs() < 1e-9,
            "{:?} -> {:?}", [a, b, c], e);
    }

    /// Unwrapped angles (several turns) with a previous triple slightly off still come back
    /// exactly, on either branch, as long as the middle angle is away from the pole.
    #[test]
    fn nearest_triple_follows_the_previous_one(
        o in order(), a in -20.0..20.0f64, b in -10.0..10.0f64, c in -20.0..20.0f64,
        d in proptest::array::uniform3(-0.05..0.05f64),
    ) {
        prop_assume!(b.cos().abs() > 0.2);
        let r = euler_to_matrix(o, [a, b, c]);
        let e = matrix_to_euler_near(o, &r, [a + d[0], b + d[1], c + d[2]]);
        prop_assert!((e[0] - a).abs() < 1e-9 && (e[1] - b).abs() < 1e-9 && (e[2] - c).abs() < 1e-9,
            "{:?} -> {:?}", [a, b, c], e);
    }

    /// At and near the pole the result still reproduces the matrix and stays continuous:
    /// within a small step of the previous triple when the motion is a small step.
    #[test]
    fn nearest_triple_is_continuous_through_the_pole(
        o in order(), a in -3.0..3.0f64, c in -3.0..3.0f64, sign in prop_oneof![Just(1.0), Just(-1.0)],
        db in -1e-3..1e-3f64, step in proptest::array::uniform3(-1e-4..1e-4f64),
    ) {
        let prev = [a, sign * FRAC_PI_2 + db, c];
        let next = [a + step[0], prev[1] + step[1], c + step[2]];
        let r = euler_to_matrix(o, next);
        let e = matrix_to_euler_near(o, &r, prev);
        prop_assert!(close(&euler_to_matrix(o, e), &r, 1e-12));
        let jump: f64 = (0..3).map(|n| (e[n] - prev[n]).abs()).fold(0.0, f64::max);
        // near the pole, a and c trade off; the jump stays of the order of the step / cos b
        prop_assert!(jump < 0.5, "prev {:?} next {:?} got {:?}", prev, next, e);
    }
}

#[test]
fn exact_gimbal_lock_keeps_the_first_angle() {
    for o in EulerOrder::ALL {
        for b in [FRAC_PI_2, -FRAC_PI_2] {
            let r = euler_to_matrix(o, [0.7, b, -0.2]);
            let e = matrix_to_euler_near(o, &r, [0.7, b, 0.0]);
            assert!((e[0] - 0.7).abs() < 1e-9, "{o}: {e:?}");
            assert!(close(&euler_to_matrix(o, e), &r, 1e-12), "{o}: {e:?}");
        }
    }
}
