//! Unwrapping recovers a continuous angle from one stored modulo a full turn, in the unit the
//! caller names, and leaves a continuous signal alone.

use articula::motion::unwrap::{AngleUnit, make_euler_continuous, unwrap_angles};

fn wrap(x: f64, turn: f64) -> f64 {
    x - turn * (x / turn).round()
}

#[test]
fn wrapped_ramps_are_recovered_in_degrees_and_radians() {
    for unit in [AngleUnit::Degrees, AngleUnit::Radians] {
        let turn = unit.full_turn();
        // three turns forward then one back, with a wobble: steps stay below half a turn
        let truth: Vec<f64> = (0..500)
            .map(|k| {
                let s = k as f64 / 499.0;
                turn * (3.0 * s - 4.0 * (s - 0.75).max(0.0)) + 0.05 * turn * (40.0 * s).sin()
            })
            .collect();
        let mut x: Vec<f64> = truth.iter().map(|&v| wrap(v, turn)).collect();
        assert!(
            x.windows(2).any(|w| (w[1] - w[0]).abs() > 0.5 * turn),
            "test has no jump"
        );
        unwrap_angles(unit, &mut x);
        for (a, b) in x.iter().zip(&truth) {
            assert!((a - b).abs() < 1e-9 * turn, "{unit:?}: {a} vs {b}");
        }
        // idempotent on a continuous signal
        let before = x.clone();
        unwrap_angles(unit, &mut x);
        assert_eq!(x, before);
    }
}

#[test]
fn unit_matters() {
    // a 300° step is a −60° move in degrees, but 300 rad is many turns in radians
    let mut deg = [0.0, 300.0];
    unwrap_angles(AngleUnit::Degrees, &mut deg);
    assert!((deg[1] + 60.0).abs() < 1e-12);
    let mut rad = [0.0, 3.0];
    unwrap_angles(AngleUnit::Radians, &mut rad);
    assert!((rad[1] - 3.0).abs() < 1e-12);
    let mut rad = [0.0, 4.0];
    unwrap_angles(AngleUnit::Radians, &mut rad);
    assert!((rad[1] - (4.0 - std::f64::consts::TAU)).abs() < 1e-12);
}

#[test]
fn euler_triples_are_repicked_through_gimbal_lock_and_turns() {
    use articula::rotation::{EulerOrder, euler_to_matrix, matrix_to_euler};
    use std::f64::consts::FRAC_PI_2;
    for order in EulerOrder::ALL {
        // a smooth path whose middle angle swings past ±90° and whose first angle turns 3 times
        let truth: Vec<[f64; 3]> = (0..2000)
            .map(|k| {
                let t = k as f64 * 0.005;
                [
                    2.0 * t - 1.0,
                    FRAC_PI_2 * (0.3 + 0.9 * (0.7 * t).sin()),
                    0.5 * (1.3 * t).cos(),
                ]
            })
            .collect();
        // what a capture stores: the principal triple, which flips branch and wraps
        let mut frames: Vec<[f64; 3]> = truth
            .iter()
            .map(|a| matrix_to_euler(order, &euler_to_matrix(order, *a)))
            .collect();
        let step = |f: &[[f64; 3]]| {
            f.windows(2)
                .map(|w| {
                    (0..3)
                        .map(|i| (w[1][i] - w[0][i]).abs())
                        .fold(0.0, f64::max)
                })
                .fold(0.0, f64::max)
        };
        assert!(
            step(&frames) > 1.0,
            "{order}: the stored path has no flip to repair"
        );
        make_euler_continuous(order, &mut frames);
        for (k, (got, want)) in frames.iter().zip(&truth).enumerate() {
            let err = (0..3).map(|i| (got[i] - want[i]).abs()).fold(0.0, f64::max);
            assert!(err < 1e-6, "{order} frame {k}: {got:?} vs {want:?}");
        }
        assert!(step(&frames) < 0.05);
    }
}
