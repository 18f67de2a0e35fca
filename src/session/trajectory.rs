//! Joint-space trajectories for a robot arm: quintic point-to-point moves through a list of
//! poses (the `trajectory` command), the motion a motor-sizing study runs inverse dynamics
//! over.
//!
//! Each move from pose `q₀` to pose `q₁` takes `T` seconds and follows the quintic polynomial
//! with zero velocity and acceleration at both ends (Corke 2017, *Robotics, Vision and
//! Control*, 2nd ed., §3.3.1, the toolbox's `jtraj`; Craig 2005, *Introduction to Robotics*,
//! §7.3):
//!
//! ```text
//! s(τ) = 10τ³ − 15τ⁴ + 6τ⁵,  τ = t/T ∈ [0, 1]
//! q(t) = q₀ + (q₁ − q₀) s(τ)
//! q̇(t) = (q₁ − q₀) (30τ² − 60τ³ + 30τ⁴) / T
//! q̈(t) = (q₁ − q₀) (60τ − 180τ² + 120τ³) / T²
//! ```
//!
//! so the peak speed of a joint is `1.875 |Δq| / T` (at mid-move) and its peak acceleration
//! `10/√3 · |Δq| / T² ≈ 5.774 |Δq| / T²` (at `τ = 1/2 ∓ √3/6`). The velocities and
//! accelerations are exact (no numerical differentiation), so the torques are those of the
//! move and not of a filter. A single pose is held for `T` (the static gravity load).
//! Consecutive moves share their end sample; the motion is sampled at `rate_hz`.

use crate::error::Error;
use crate::pipeline::States;

/// `s(τ)`, `s'(τ)`, `s''(τ)` of the quintic with zero end velocity and acceleration.
pub fn quintic(tau: f64) -> (f64, f64, f64) {
    let t = tau.clamp(0.0, 1.0);
    let (t2, t3) = (t * t, t * t * t);
    (
        t3 * (10.0 - 15.0 * t + 6.0 * t2),
        30.0 * t2 * (1.0 - 2.0 * t + t2),
        60.0 * t * (1.0 - 3.0 * t + 2.0 * t2),
    )
}

/// The motion through `poses` (each `n` values, rad or m), `duration_s` per move, sampled at
/// `rate_hz`: `time`, `q`, `v`, `a` per sample (one pose: held still for `duration_s`).
pub fn quintic_moves(poses: &[Vec<f64>], duration_s: f64, rate_hz: f64) -> Result<States, Error> {
    let n = poses.first().map_or(0, Vec::len);
    if poses.is_empty()
        || poses
            .iter()
            .any(|p| p.len() != n || p.iter().any(|x| !x.is_finite()))
    {
        return Err(Error::Invalid(
            "trajectory: give one or more poses of the same length, finite values".into(),
        ));
    }
    if !(duration_s > 0.0 && rate_hz > 0.0 && duration_s.is_finite() && rate_hz.is_finite()) {
        return Err(Error::Invalid(format!(
            "trajectory: move time {duration_s} s and rate {rate_hz} Hz must be positive"
        )));
    }
    // samples per move (the last sample of a move is the first of the next)
    let per_move = (duration_s * rate_hz).round().max(1.0) as usize;
    let moves: Vec<(&[f64], &[f64])> = if poses.len() == 1 {
        vec![(&poses[0], &poses[0])]
    } else {
        poses.windows(2).map(|w| (&w[0][..], &w[1][..])).collect()
    };
    let total = moves.len() * per_move + 1;
    let mut s = States {
        time: Vec::with_capacity(total),
        q: Vec::with_capacity(total),
        v: Vec::with_capacity(total),
        a: Vec::with_capacity(total),
    };
    for (m, (q0, q1)) in moves.iter().enumerate() {
        let last = m + 1 == moves.len();
        for k in 0..per_move + usize::from(last) {
            let tau = k as f64 / per_move as f64;
            let (p, dp, ddp) = quintic(tau);
            let dq = q0.iter().zip(q1.iter()).map(|(a, b)| b - a);
            s.time
                .push((m * per_move + k) as f64 * duration_s / per_move as f64);
            s.q.push(
                q0.iter()
                    .zip(q1.iter())
                    .map(|(a, b)| a + (b - a) * p)
                    .collect(),
            );
            s.v.push(dq.clone().map(|d| d * dp / duration_s).collect());
            s.a.push(dq.map(|d| d * ddp / (duration_s * duration_s)).collect());
        }
    }
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_move_starts_and_ends_at_rest_on_its_poses_with_the_quintic_peaks() {
        let (q0, q1) = (vec![0.0, 1.0], vec![1.0, -1.0]);
        let s = quintic_moves(&[q0.clone(), q1.clone()], 2.0, 1000.0).unwrap();
        assert_eq!(s.len(), 2001);
        assert_eq!(s.q[0], q0);
        assert_eq!(*s.q.last().unwrap(), q1);
        for row in [&s.v[0], &s.a[0], s.v.last().unwrap(), s.a.last().unwrap()] {
            assert!(row.iter().all(|x| x.abs() < 1e-12), "{row:?}");
        }
        // peak speed 1.875 |Δq| / T at mid-move, peak acceleration 10/√3 |Δq| / T²
        let peak_v = s.v.iter().map(|r| r[1].abs()).fold(0.0, f64::max);
        assert!((peak_v - 1.875 * 2.0 / 2.0).abs() < 1e-9, "{peak_v}");
        let peak_a = s.a.iter().map(|r| r[0].abs()).fold(0.0, f64::max);
        assert!((peak_a - 10.0 / 3f64.sqrt() / 4.0).abs() < 1e-5, "{peak_a}");
        // v is the derivative of q and a of v (central differences, O(dt²))
        let dt = 1e-3;
        for k in [300, 1000, 1700] {
            let dq = (s.q[k + 1][0] - s.q[k - 1][0]) / (2.0 * dt);
            let dv = (s.v[k + 1][0] - s.v[k - 1][0]) / (2.0 * dt);
            assert!((dq - s.v[k][0]).abs() < 1e-5 && (dv - s.a[k][0]).abs() < 1e-4);
        }
    }

    #[test]
    fn moves_chain_without_repeating_the_shared_pose_and_one_pose_is_held() {
        let s = quintic_moves(&[vec![0.0], vec![1.0], vec![0.0]], 1.0, 10.0).unwrap();
        assert_eq!(s.len(), 21);
        assert_eq!(s.q[10], vec![1.0]);
        assert!(s.time.windows(2).all(|w| (w[1] - w[0] - 0.1).abs() < 1e-12));
        let hold = quintic_moves(&[vec![0.5, 2.0]], 0.5, 10.0).unwrap();
        assert!(hold.q.iter().all(|q| q == &vec![0.5, 2.0]));
        assert!(hold.v.iter().chain(&hold.a).flatten().all(|x| *x == 0.0));
        assert!(quintic_moves(&[vec![0.0], vec![1.0, 2.0]], 1.0, 10.0).is_err());
        assert!(quintic_moves(&[vec![0.0]], -1.0, 10.0).is_err());
    }
}
