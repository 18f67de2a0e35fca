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

/// The re-pick that skips the matrix (`repick_fast`: away from the lock, and with every angle
/// within 45° of the previous one, no `nearest_branch` search either) is `repick` with the
/// frame's matrix, bit for bit: over random triples on both branches, wrapped by whole
/// turns, middle angles from far to exactly at the lock, previous triples near either branch
/// and far from both.
#[test]
fn repick_fast_is_repick_bit_for_bit() {
    use articula::motion::unwrap::{repick, repick_fast};
    use articula::rotation::{EulerOrder, euler_to_matrix};
    use std::f64::consts::{FRAC_PI_2, PI};
    let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut fast_paths = 0;
    for order in EulerOrder::ALL {
        for n in 0..30_000 {
            let a1 = (uniform() - 0.5) * 6.0 * PI;
            let a3 = (uniform() - 0.5) * 6.0 * PI;
            // middle angles down to the lock itself, on both sides, and whole turns away
            let off = [1.0, 1e-2, 1e-4, 3e-5, 2e-5, 1e-5, 1e-7, 0.0][n % 8] * uniform();
            let side = if n % 16 < 8 { 1.0 } else { -1.0 };
            let a2 = side * (FRAC_PI_2 - off) + [0.0, PI, -2.0 * PI][n % 3];
            let x = [a1, a2, a3];
            let base = if n % 2 == 0 {
                x
            } else {
                [a1 + PI, PI - a2, a3 + PI]
            };
            // previous triples from a hair to 3 rad away, or exactly x, or x with a −0
            let spread = [1e-9, 0.1, 1.5, 6.0][(n / 2) % 4];
            let mut prev = base.map(|a| {
                a + 2.0 * PI * ((uniform() * 3.0).floor() - 1.0) * f64::from(n % 5 == 0)
                    + (uniform() - 0.5) * spread
            });
            if n % 97 == 0 {
                prev = x;
            }
            let x = if n % 89 == 0 { [-0.0, a2, 0.0] } else { x };
            let want = repick(order, &euler_to_matrix(order, x), x, prev);
            let got = repick_fast(order, x, prev);
            assert_eq!(
                got.map(f64::to_bits),
                want.map(f64::to_bits),
                "{order}: x {x:?} prev {prev:?}: {got:?} vs {want:?}"
            );
            if (0..3).all(|i| (x[i] - prev[i]).abs() < 0.7) {
                fast_paths += 1;
            }
        }
    }
    assert!(fast_paths > 10_000, "{fast_paths}");
}

/// The re-pick and scan on columns (what the pipeline runs, with the rotation's step computed
/// only where it can matter) gives what the frame-by-frame loop with both matrices at every
/// frame gives: the same triples bit for bit, the same passage and jump, on random walks
/// through gimbal lock, branch flips, wrapped turns and glitches.
#[test]
fn columns_repick_and_scan_equal_the_matrix_at_every_frame() {
    use articula::motion::unwrap::{
        GimbalPassage, TripleScan, make_euler_columns_continuous_and_scan, repick,
    };
    use articula::rotation::{EulerOrder, euler_to_matrix};
    use std::f64::consts::PI;
    // the loop as it was: the matrix of every frame as given, the rotation's step at each
    fn reference(order: EulerOrder, frames: &mut [[f64; 3]]) -> TripleScan {
        let mut out = TripleScan::default();
        let mut prev = euler_to_matrix(order, frames[0]);
        for k in 1..frames.len() {
            let r = euler_to_matrix(order, frames[k]);
            frames[k] = repick(order, &r, frames[k], frames[k - 1]);
            let (a, b) = (frames[k - 1], frames[k]);
            let cos = ((prev.transpose() * r).trace() - 1.0) / 2.0;
            let rotation_step = cos.clamp(-1.0, 1.0).acos();
            let step = (0..3).map(|i| (b[i] - a[i]).abs()).fold(0.0, f64::max);
            if step > PI / 6.0
                && step > 5.0 * rotation_step
                && out
                    .passage
                    .is_none_or(|w| step / rotation_step > w.coordinate_step / w.rotation_step)
            {
                out.passage = Some(GimbalPassage {
                    frame: k - 1,
                    coordinate_step: step,
                    rotation_step,
                });
            }
            if rotation_step > PI / 2.0 && out.jump.is_none_or(|(_, a)| rotation_step > a) {
                out.jump = Some((k - 1, rotation_step));
            }
            prev = r;
        }
        out
    }
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut uniform = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut passages, mut jumps) = (0, 0);
    for (w, order) in EulerOrder::ALL.into_iter().cycle().take(60).enumerate() {
        // a random walk whose middle angle wanders across ±90°, stored wrapped to ±180°,
        // with steps from small to glitch-sized
        let step = [0.02, 0.2, 0.6][w % 3];
        // every other walk sweeps its outer angles against each other near the lock (a
        // passage: they turn 40° a frame while the rotation barely moves)
        let sweep = w % 2 == 0;
        let mut a = [0.0, if sweep { 1.55 } else { 1.2 }, 0.0];
        let raw: Vec<[f64; 3]> = (0..400)
            .map(|k| {
                for x in &mut a {
                    *x += (uniform() - 0.5) * step;
                }
                if sweep {
                    a[0] += 0.7;
                    a[2] -= 0.7;
                    a[1] = 1.55 + (uniform() - 0.5) * 0.02;
                }
                let glitch = if k % 137 == 50 { 2.2 } else { 0.0 };
                [a[0] + glitch, a[1], a[2]].map(|x| x - 2.0 * PI * (x / (2.0 * PI)).round())
            })
            .collect();
        let mut want = raw.clone();
        let scan_want = reference(order, &mut want);
        let mut cols: [Vec<f64>; 3] = [0, 1, 2].map(|i| raw.iter().map(|t| t[i]).collect());
        let [c0, c1, c2] = &mut cols;
        let scan = make_euler_columns_continuous_and_scan(order, [c0, c1, c2]);
        for (k, t) in want.iter().enumerate() {
            let got = [cols[0][k], cols[1][k], cols[2][k]];
            assert_eq!(
                got.map(f64::to_bits),
                t.map(f64::to_bits),
                "{order} walk {w} frame {k}"
            );
        }
        assert_eq!(scan, scan_want, "{order} walk {w}");
        passages += usize::from(scan.passage.is_some());
        jumps += usize::from(scan.jump.is_some());
    }
    // the walks hold both kinds of event
    assert!(
        passages > 5 && jumps > 5,
        "{passages} passages, {jumps} jumps"
    );
}
