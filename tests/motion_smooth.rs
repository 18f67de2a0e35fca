//! Smoothing: what the filters promise in their doc comments.
//!
//! - both filters keep a constant and a straight line exactly, up to the first and last frame
//!   (no droop toward zero, no bending of a ramp at the ends);
//! - their gain at a test frequency is the documented formula: the zero-lag Butterworth is at
//!   1/√2 at its cutoff for every order, and has no phase lag; the Gaussian follows
//!   `exp(−2π²σ²f²)` with its −3 dB point at `√(ln 2)/(2πσ)`;
//! - quaternion smoothing keeps unit norm and hemisphere consistency, leaves a uniform rotation
//!   unchanged and brings a noisy one closer to the truth.

use articula::motion::smooth::{SmoothSpec, Smoother, smooth_columns, smooth_quaternions};
use nalgebra::{UnitQuaternion, Vector3};
use std::f64::consts::{FRAC_1_SQRT_2, PI, SQRT_2};

const DT: f64 = 1.0 / 120.0;

fn specs() -> Vec<SmoothSpec> {
    let mut v: Vec<SmoothSpec> = [0.005, 0.02, 0.05, 0.3]
        .iter()
        .map(|&s| SmoothSpec::Gaussian { sigma_s: s })
        .collect();
    for order in 1..=4 {
        for fc in [4.0, 6.0, 10.0] {
            v.push(SmoothSpec::Butterworth {
                cutoff_hz: fc,
                order,
            });
        }
    }
    v
}

/// Amplitude and phase (rad) of the component at `f` of `y` over frames `range`, by least
/// squares on `a sin(2πft) + b cos(2πft)`.
fn fit_sinusoid(y: &[f64], f: f64, range: std::ops::Range<usize>) -> (f64, f64) {
    let (mut ss, mut sc, mut cc, mut ys, mut yc) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for k in range {
        let w = 2.0 * PI * f * k as f64 * DT;
        let (s, c) = w.sin_cos();
        ss += s * s;
        sc += s * c;
        cc += c * c;
        ys += y[k] * s;
        yc += y[k] * c;
    }
    let det = ss * cc - sc * sc;
    let a = (ys * cc - yc * sc) / det;
    let b = (yc * ss - ys * sc) / det;
    ((a * a + b * b).sqrt(), b.atan2(a))
}

fn sine(f: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|k| (2.0 * PI * f * k as f64 * DT).sin())
        .collect()
}

#[test]
fn constant_and_line_survive_to_the_last_frame() {
    for spec in specs() {
        for n in [3usize, 17, 240] {
            let constant = vec![1.7; n];
            let line: Vec<f64> = (0..n).map(|k| -0.4 + 2.5 * k as f64 * DT).collect();
            let mut cols = vec![constant.clone(), line.clone()];
            smooth_columns(spec, DT, &mut cols).unwrap();
            for (got, want) in cols.iter().zip([&constant, &line]) {
                let err = got
                    .iter()
                    .zip(want.iter())
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                assert!(err < 1e-9, "{spec}, {n} frames: error {err}");
            }
        }
    }
}

#[test]
fn renormalised_or_zero_padded_kernels_would_fail_the_end_test() {
    // the same line smoothed with zero padding droops and with a renormalised truncated kernel
    // bends: the end treatment is what the previous test checks, not a tautology
    let sigma = 0.05;
    let h = (4.0 * sigma / DT).ceil() as isize;
    let n = 120isize;
    let line: Vec<f64> = (0..n).map(|k| 1.0 + k as f64 * DT).collect();
    let w = |k: isize| (-(k as f64 * DT).powi(2) / (2.0 * sigma * sigma)).exp();
    let (mut zero_pad, mut renorm) = (0.0, 0.0);
    let total: f64 = (-h..=h).map(w).sum();
    let inside: f64 = (0..=h).map(w).sum();
    for k in 0..=h {
        zero_pad += w(k) * line[k as usize] / total;
        renorm += w(k) * line[k as usize] / inside;
    }
    assert!((zero_pad - line[0]).abs() > 0.3);
    assert!((renorm - line[0]).abs() > 0.01);
    let mut ours = vec![line.clone()];
    smooth_columns(SmoothSpec::Gaussian { sigma_s: sigma }, DT, &mut ours).unwrap();
    assert!((ours[0][0] - line[0]).abs() < 1e-12);
}

#[test]
fn butterworth_is_minus_3db_at_its_cutoff_with_no_lag() {
    let n = 2400;
    for order in 1..=4 {
        for fc in [4.0, 6.0, 10.0] {
            let spec = SmoothSpec::Butterworth {
                cutoff_hz: fc,
                order,
            };
            let mut s = Smoother::new(spec, DT).unwrap();
            // the documented formula, written out independently of the implementation
            let omega_c = (PI * fc * DT).tan() / (SQRT_2 - 1.0).powf(1.0 / (2.0 * order as f64));
            let formula =
                |f: f64| 1.0 / (1.0 + ((PI * f * DT).tan() / omega_c).powi(2 * order as i32));
            for (f, want) in [
                (fc, FRAC_1_SQRT_2),
                (0.5 * fc, formula(0.5 * fc)),
                (2.0 * fc, formula(2.0 * fc)),
            ] {
                let mut y = sine(f, n);
                s.smooth(&mut y);
                let (amp, phase) = fit_sinusoid(&y, f, 400..n - 400);
                assert!(
                    (amp - want).abs() < 1e-3,
                    "{spec} at {f} Hz: gain {amp}, formula {want}"
                );
                assert!((s.gain(f) - want).abs() < 1e-12);
                assert!(phase.abs() < 1e-3, "{spec} at {f} Hz: phase {phase}");
            }
            assert!((formula(fc) - FRAC_1_SQRT_2).abs() < 1e-12);
        }
    }
}

#[test]
fn gaussian_follows_its_fourier_transform() {
    let n = 2400;
    for sigma in [0.01, 0.02, 0.05] {
        let spec = SmoothSpec::Gaussian { sigma_s: sigma };
        let mut s = Smoother::new(spec, DT).unwrap();
        let f3 = spec.minus3db_hz().unwrap();
        assert!((f3 - (2f64.ln()).sqrt() / (2.0 * PI * sigma)).abs() < 1e-12);
        for f in [0.5 * f3, f3, 2.0 * f3] {
            let want = (-2.0 * PI * PI * sigma * sigma * f * f).exp();
            let mut y = sine(f, n);
            s.smooth(&mut y);
            let (amp, phase) = fit_sinusoid(&y, f, 400..n - 400);
            assert!(
                (amp - want).abs() < 2e-3,
                "{spec} at {f} Hz: gain {amp}, formula {want}"
            );
            assert!((amp - s.gain(f)).abs() < 1e-4, "{spec}: discrete gain");
            assert!(phase.abs() < 1e-6);
        }
        let mut y = sine(f3, n);
        s.smooth(&mut y);
        assert!((fit_sinusoid(&y, f3, 400..n - 400).0 - FRAC_1_SQRT_2).abs() < 2e-3);
    }
}

#[test]
fn none_changes_nothing() {
    let mut cols = vec![sine(3.0, 50)];
    let before = cols.clone();
    smooth_columns(SmoothSpec::None, DT, &mut cols).unwrap();
    assert_eq!(cols, before);
}

/// A rotation about a wandering axis, deterministic pseudo-noise added.
fn rotation_path(n: usize, noise: f64) -> (Vec<UnitQuaternion<f64>>, Vec<UnitQuaternion<f64>>) {
    let mut seed = 12345u64;
    let mut rnd = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((seed >> 11) as f64 / (1u64 << 53) as f64) - 0.5
    };
    let truth: Vec<UnitQuaternion<f64>> = (0..n)
        .map(|k| {
            let t = k as f64 * DT;
            UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 2.0 * t, 0.0))
                * UnitQuaternion::from_scaled_axis(Vector3::new(0.6 * (3.0 * t).sin(), 0.0, 0.3))
        })
        .collect();
    let noisy = truth
        .iter()
        .enumerate()
        .map(|(k, q)| {
            let e = Vector3::new(rnd(), rnd(), rnd()) * noise;
            let r = q * UnitQuaternion::from_scaled_axis(e);
            // random sign flips: the same rotations, another representation
            if k % 7 == 3 {
                UnitQuaternion::new_unchecked(-r.into_inner())
            } else {
                r
            }
        })
        .collect();
    (truth, noisy)
}

#[test]
fn quaternion_smoothing_keeps_unit_norm_and_approaches_the_truth() {
    let n = 600; // 5 s: the path turns by 10 rad about y, several half-turns
    let (truth, noisy) = rotation_path(n, 0.05);
    let err = |a: &[UnitQuaternion<f64>]| {
        (a.iter()
            .zip(&truth)
            .map(|(x, y)| x.angle_to(y).powi(2))
            .sum::<f64>()
            / n as f64)
            .sqrt()
    };
    let raw = err(&noisy);
    for spec in [
        SmoothSpec::Gaussian { sigma_s: 0.02 },
        SmoothSpec::Butterworth {
            cutoff_hz: 6.0,
            order: 2,
        },
    ] {
        let mut q = noisy.clone();
        smooth_quaternions(spec, DT, &mut q).unwrap();
        for k in 0..n {
            assert!((q[k].coords.norm() - 1.0).abs() < 1e-12);
            if k > 0 {
                assert!(
                    q[k].coords.dot(&q[k - 1].coords) > 0.0,
                    "hemisphere flip at {k}"
                );
            }
        }
        let smoothed = err(&q);
        assert!(
            smoothed < 0.4 * raw,
            "{spec}: rms error {smoothed} vs raw {raw}"
        );
    }
}

#[test]
fn uniform_rotation_passes_unchanged() {
    let omega = Vector3::new(0.5, -2.0, 1.0);
    let q0 = UnitQuaternion::from_scaled_axis(Vector3::new(0.2, 0.1, -0.3));
    let path: Vec<UnitQuaternion<f64>> = (0..300)
        .map(|k| q0 * UnitQuaternion::from_scaled_axis(omega * (k as f64 * DT)))
        .collect();
    for spec in [
        SmoothSpec::Gaussian { sigma_s: 0.05 },
        SmoothSpec::Butterworth {
            cutoff_hz: 6.0,
            order: 2,
        },
    ] {
        let mut q = path.clone();
        smooth_quaternions(spec, DT, &mut q).unwrap();
        let worst = q
            .iter()
            .zip(&path)
            .map(|(a, b)| a.angle_to(b))
            .fold(0.0, f64::max);
        assert!(worst < 1e-7, "{spec}: {worst} rad");
    }
}
