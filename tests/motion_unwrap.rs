//! Unwrapping recovers a continuous angle from one stored modulo a full turn, in the unit the
//! caller names, and leaves a continuous signal alone.

use articula::motion::unwrap::{AngleUnit, unwrap_angles};

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
