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

/// The one-pass re-pick and scan (`make_euler_continuous_and_scan`, what the pipeline runs)
/// gives the two-pass result: the same triples bit for bit, the same worst passage and jump.
#[test]
fn one_pass_repick_and_scan_equals_the_two_passes() {
    use articula::motion::unwrap::{make_euler_continuous_and_scan, scan_triples};
    use articula::rotation::EulerOrder;
    let deg = |a: f64, b: f64, c: f64| [a.to_radians(), b.to_radians(), c.to_radians()];
    // a pass near gimbal lock, a branch flip, wrapped turns and a 120° glitch
    let raw: Vec<[f64; 3]> = (0..60)
        .map(|k| {
            let t = 40.0 * k as f64;
            let b = if k < 20 { 88.0 } else { 30.0 + k as f64 };
            let glitch = if k == 45 { 120.0 } else { 0.0 };
            deg(wrap(t + glitch, 360.0), b, wrap(-t, 360.0))
        })
        .collect();
    for order in [EulerOrder::XYZ, EulerOrder::ZXY, EulerOrder::YXZ] {
        let mut two = raw.clone();
        make_euler_continuous(order, &mut two);
        let scan = scan_triples(order, &two);
        let mut one = raw.clone();
        let fused = make_euler_continuous_and_scan(order, &mut one);
        let bits =
            |f: &[[f64; 3]]| -> Vec<[u64; 3]> { f.iter().map(|t| t.map(f64::to_bits)).collect() };
        assert_eq!(bits(&one), bits(&two), "{order}");
        // the rotation steps agree to rounding (the matrix of the frame as given, not of its
        // re-picked triple): the worst passage's ratio is the same, though among steps of equal
        // ratio (a steady sweep past the lock) another may win the tie
        let ratio =
            |p: articula::motion::unwrap::GimbalPassage| p.coordinate_step / p.rotation_step;
        match (fused.passage, scan.passage) {
            (Some(f), Some(s)) => {
                let (a, b) = (ratio(f), ratio(s));
                assert!((a - b).abs() <= 1e-6 * b, "{order}: {a} vs {b}");
            }
            (f, s) => assert_eq!(f.is_some(), s.is_some(), "{order}"),
        }
        assert_eq!(fused.jump.map(|j| j.0), scan.jump.map(|j| j.0), "{order}");
        // the fixture holds a passage (XYZ) and a glitch (every order)
        assert!(fused.jump.is_some(), "{order}: {fused:?}");
        assert!(
            order != EulerOrder::XYZ || fused.passage.is_some(),
            "{fused:?}"
        );
    }
}

/// The re-pick without the trip through the matrix (`repick`, away from gimbal lock) picks the
/// triple `matrix_to_euler_near` picks from the matrix, to a few ulps: over random triples on
/// both branches, wrapped by whole turns, middle angles from far to within a hair of the
/// lock, and previous triples near either branch.
#[test]
fn repick_agrees_with_the_trip_through_the_matrix() {
    use articula::motion::unwrap::repick;
    use articula::rotation::{EulerOrder, euler_to_matrix, matrix_to_euler_near};
    use std::f64::consts::{FRAC_PI_2, PI};
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut worst: f64 = 0.0;
    for order in EulerOrder::ALL {
        for n in 0..20_000 {
            let a1 = (uniform() - 0.5) * 6.0 * PI;
            let a3 = (uniform() - 0.5) * 6.0 * PI;
            // middle angles down to 1e-4 rad from the lock, on both sides of it
            let off = [0.5, 1e-2, 1e-3, 1e-4][n % 4] * uniform();
            let side = if n % 8 < 4 { 1.0 } else { -1.0 };
            let a2 = side * (FRAC_PI_2 - off) + if n % 3 == 0 { PI } else { 0.0 };
            let x = [a1, a2, a3];
            // a previous triple near x or near its other branch, up to 0.3 rad away
            let base = if n % 2 == 0 {
                x
            } else {
                [a1 + PI, PI - a2, a3 + PI]
            };
            let prev = base.map(|a| {
                a + 2.0 * PI * ((uniform() * 3.0).floor() - 1.0) + (uniform() - 0.5) * 0.6
            });
            let r = euler_to_matrix(order, x);
            let got = repick(order, &r, x, prev);
            let want = matrix_to_euler_near(order, &r, prev);
            let err = (0..3).map(|i| (got[i] - want[i]).abs()).fold(0.0, f64::max);
            let scale = 1.0 + want.iter().map(|a| a.abs()).fold(0.0, f64::max);
            worst = worst.max(err / scale);
            assert!(
                err <= 1e-9 * scale,
                "{order}: x {x:?} prev {prev:?}: {got:?} vs {want:?}"
            );
        }
    }
    eprintln!("largest difference / (1 + |angle|): {worst:e}");
}

/// `round_turns` is `round`, bit for bit, the sign of zero included.
#[test]
fn round_turns_is_round_bit_for_bit() {
    use articula::rotation::round_turns;
    let mut xs = vec![
        0.0,
        -0.0,
        0.5,
        -0.5,
        0.49999999999999994,
        -0.49999999999999994,
        1.5,
    ];
    xs.extend((-2000..2000).map(|k| k as f64 * 1.37e-3));
    xs.extend([f64::INFINITY, f64::NEG_INFINITY, 1e300, -1e-300]);
    for x in xs {
        assert_eq!(round_turns(x).to_bits(), x.round().to_bits(), "{x}");
    }
    assert!(round_turns(f64::NAN).is_nan());
}
