//! The contact phases of a set of feet: a point planted while near its floor level and nearly
//! still (hysteresis, run forward and backward in time), a foot in contact while its heel or
//! toe is, short phases absorbed; the thresholds, and the window over which the estimated
//! accelerations average the true ones.

use super::FootPoints;
use super::floor::{belt_velocity, point_levels, velocity};
use crate::error::Error;
use crate::motion::derive::differentiate;
use crate::motion::smooth::{SmoothSpec, Smoother};
use nalgebra::Vector3;

/// Thresholds of contact detection and of the ground reaction estimate
/// ([`crate::dynamics::grf`]). Lengths in m, speeds in m/s, times in s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactParams {
    /// A point enters contact below this height above its floor level. Default 0.04 m: a
    /// planted heel or toe point moves 1–3 cm vertically in captured takes (heel roll, skin
    /// and solver noise, the low-pass filter rounding the heel strike), while a swinging foot
    /// that clears the floor by less (the toe at mid-swing) moves fast, which the speed test
    /// rejects.
    pub height_on: f64,
    /// A point leaves contact above this height. Default 0.07 m.
    pub height_off: f64,
    /// A point enters contact below this speed. Default 0.8 m/s: planted points move at
    /// < 0.3 m/s (heel roll, push-off) but the low-pass filter (6 Hz) smears the last
    /// 1–2 m/s of a heel strike over ~0.05 s; swinging feet move at 2–5 m/s in walking
    /// (Winter 2009, *Biomechanics and Motor Control of Human Movement*, 4th ed., ch. 2 toe
    /// trajectory) and faster in running.
    pub speed_on: f64,
    /// A point leaves contact above this speed. Default 1.2 m/s.
    pub speed_off: f64,
    /// Contact or flight phases shorter than this are absorbed by their neighbours (except at
    /// the ends of the take). Default 0.04 s: one frame at 30 fps, five at 120 fps; flight in
    /// running lasts ~0.1 s, so it survives.
    pub min_phase_s: f64,
    /// Half-width (m) of the support region around the heel–toe segment inside which a centre
    /// of pressure is kept. Default 0.05 m: half a foot's width, and the heel and the tips of
    /// the toes lie ~5 cm beyond the ankle and toe joints (de Leva 1996 foot lengths).
    pub cop_margin: f64,
    /// Friction coefficient bounding the horizontal ground force (|F_h| ≤ μ F_v). Default 1.0:
    /// shoe on a dry floor is 0.6–1.0, and walking needs ≤ 0.3 (Chang et al. 2015, "The
    /// required coefficient of friction during walking", *Gait & Posture*), so the bound only
    /// removes noise spikes, which stay in the residual.
    pub friction: f64,
    /// Half-width (s) of the window over which the estimated accelerations average the true
    /// ones ([`acceleration_spread_s`] of the take's smoothing and frame time). Frames of flight
    /// within it of a contact phase carry, on the foot of that contact, the part of the needed
    /// wrench that the smoothing and differencing moved out of the stance (while it presses on
    /// the floor). Default 0: no such frames; [`ContactParams::for_take`] sets it.
    pub spread_s: f64,
    /// The floor's velocity (m/s, world axes, horizontal) when it is known for the take:
    /// [`ContactParams::fitted_to`] finds it once from the take's own feet
    /// ([`belt_velocity`]), as it fits the heights, so that residual reduction's trial pelvis
    /// paths are measured against the floor the take stands on, not one found again from
    /// each trial's feet. `None` (the default): found from the feet each contact test is
    /// given.
    pub floor_velocity: Option<Vector3<f64>>,
}

impl ContactParams {
    /// The default thresholds, with [`spread_s`](Self::spread_s) set for a take sampled every
    /// `dt` seconds and smoothed by `smooth` (what `--contact feet` uses).
    pub fn for_take(smooth: &SmoothSpec, dt: f64) -> Result<Self, Error> {
        Ok(Self {
            spread_s: acceleration_spread_s(smooth, dt)?,
            ..Self::default()
        })
    }
}

impl ContactParams {
    /// The floor's velocity under `feet` (whose heel and toe floor levels are `levels`):
    /// [`floor_velocity`](Self::floor_velocity) when known, else [`belt_velocity`] of them.
    pub fn floor_velocity_under(
        &self,
        feet: &[FootPoints],
        levels: (f64, f64),
        up: usize,
        dt: f64,
    ) -> Vector3<f64> {
        self.floor_velocity
            .unwrap_or_else(|| belt_velocity(feet, levels, up, dt, self))
    }
}

impl Default for ContactParams {
    fn default() -> Self {
        Self {
            height_on: 0.04,
            height_off: 0.07,
            speed_on: 0.8,
            speed_off: 1.2,
            min_phase_s: 0.04,
            cop_margin: 0.05,
            friction: 1.0,
            spread_s: 0.0,
            floor_velocity: None,
        }
    }
}

/// Contact of every foot in every frame (`[foot][frame]`), from the heel and toe points of each
/// foot sampled every `dt` seconds, `up` being the index (0, 1, 2) of the vertical axis.
///
/// A point is planted while it is within `height_on` of its floor level and slower than
/// `speed_on`, and stays planted until it rises above `height_off` or moves faster than
/// `speed_off`; a foot is in contact while its heel or its toe is planted. Speeds are central
/// differences (one-sided at the ends), measured against the floor, which moves under a take
/// walked in place ([`ContactParams::floor_velocity`], else [`belt_velocity`]).
pub fn contact_phases(
    feet: &[FootPoints],
    up: usize,
    dt: f64,
    params: &ContactParams,
) -> Vec<Vec<bool>> {
    let levels = point_levels(feet, up);
    let belt = params.floor_velocity_under(feet, levels, up, dt);
    let min_frames = (params.min_phase_s / dt).ceil().max(1.0) as usize;
    feet.iter()
        .map(|f| {
            let heel = planted(&f.heel, up, levels.0, dt, belt, params);
            let toe = planted(&f.toe, up, levels.1, dt, belt, params);
            let mut c: Vec<bool> = heel.iter().zip(&toe).map(|(h, t)| *h || *t).collect();
            absorb_short_phases(&mut c, min_frames);
            c
        })
        .collect()
}

/// Why no foot of a take is ever planted ([`contact_phases`] all false), for a user: how close
/// each kind of point comes to its floor level while slow enough, and how slow it is there.
pub fn why_no_contact(feet: &[FootPoints], up: usize, dt: f64, params: &ContactParams) -> String {
    let (heel_level, toe_level) = point_levels(feet, up);
    let belt = params.floor_velocity_under(feet, (heel_level, toe_level), up, dt);
    let mut slowest_near = f64::INFINITY;
    for f in feet {
        for (path, level) in [(&f.heel, heel_level), (&f.toe, toe_level)] {
            for k in 0..path.len() {
                if path[k][up] - level < params.height_on {
                    slowest_near = slowest_near.min((velocity(path, k, dt) - belt).norm());
                }
            }
        }
    }
    let frames = feet.first().map_or(0, |f| f.heel.len());
    if slowest_near.is_finite() {
        format!(
            "no foot is ever planted on a floor: within {:.0} cm of the floor the feet never \
             move slower than {:.2} m/s (planted feet move below {:.1} m/s) over {frames} \
             frames; a foot sliding over the floor, a take in the air or in water",
            100.0 * params.height_on,
            slowest_near,
            params.speed_on
        )
    } else {
        format!(
            "no foot is ever planted on a floor: no foot comes within {:.0} cm of its lowest \
             level over {frames} frames",
            100.0 * params.height_on
        )
    }
}

/// The planted state of one point over time: hysteresis on height above `level` and speed
/// (against the floor's velocity `belt`), run forward and backward in time and the two results
/// joined.
///
/// A Schmitt trigger run forward enters late and leaves late: a landing foot still moving at
/// `speed_on` when it touches down (a heel strike, a landing from a run or a jump, sampled at
/// 30 fps: the central-difference speed of the touch-down frame spans the end of the descent)
/// enters contact a frame or more after it touched, while the push-off is followed to the
/// exit thresholds. Run backward it does the opposite. Joining both (a zero-lag trigger, as the
/// forward-backward pass makes a filter zero-lag) treats touch-down and lift-off alike: a
/// point is planted from the first frame after which it is continuously within the exit
/// thresholds up to a frame within the entry thresholds, to the last such frame after.
fn planted(
    p: &[Vector3<f64>],
    up: usize,
    level: f64,
    dt: f64,
    belt: Vector3<f64>,
    params: &ContactParams,
) -> Vec<bool> {
    let n = p.len();
    let test = |k: usize| {
        let speed = (velocity(p, k, dt) - belt).norm();
        let h = p[k][up] - level;
        (
            h < params.height_on && speed < params.speed_on,
            h <= params.height_off && speed <= params.speed_off,
        )
    };
    let tests: Vec<(bool, bool)> = (0..n).map(test).collect();
    let trigger = |state: &mut bool, (enter, stay): (bool, bool)| {
        *state = if *state { stay } else { enter };
        *state
    };
    let mut state = false;
    let mut out: Vec<bool> = tests.iter().map(|t| trigger(&mut state, *t)).collect();
    state = false;
    for (o, t) in out.iter_mut().zip(&tests).rev() {
        *o |= trigger(&mut state, *t);
    }
    out
}

/// The half-width (s) of the window of true accelerations that the pipeline's estimate of an
/// acceleration at one frame averages: the smallest `h` such that the estimator's impulse
/// response (smoothing `smooth`, then second-order central differences twice, as
/// `pipeline::take_states` does) has 95 % of its absolute area within `±h`.
///
/// Computed, not tabulated: a unit velocity step at the centre of a 4 s ramp (`x = max(0, t)`,
/// whose true acceleration is a unit impulse) goes through the same [`Smoother`] and
/// [`differentiate`] as a take; the result is the estimator's kernel. Without smoothing it is
/// `[¼, ½, ¼]/dt` (one frame each side: 33 ms at 30 fps, 8 ms at 120 fps); the 6 Hz
/// Butterworth widens it to ±0.07 s (0.067 s at 120 fps, 0.1 s at 30 fps).
///
/// A force the ground applies between `t₀` and `t₁` therefore shows in the estimated whole-body
/// wrench over `[t₀ − h, t₁ + h]`: a landing appears before the foot touches down
/// ([`crate::dynamics::grf`] lets the landing foot carry it).
///
/// The ramp reaches ±2 s, or the filter's reach and the differences' frames when that is
/// shorter (the impulse response lies within them): a `Frame Time: 1e-9` asked for 4·10⁹
/// samples and aborted, a hostile `1e-300` for more memory than exists (found by hand and by
/// `examples/fuzz_takes.rs`).
///
/// [`Smoother`]: crate::motion::smooth::Smoother
/// [`differentiate`]: crate::motion::derive::differentiate
pub fn acceleration_spread_s(smooth: &SmoothSpec, dt: f64) -> Result<f64, Error> {
    let mut smoother = Smoother::new(*smooth, dt)?;
    // the impulse response lies within the filter's reach and the differences' two frames;
    // 2 s of frames at most (`Frame Time: 1e-9` asked for 4·10⁹ samples)
    let half = (smoother.reach() + 4).min((2.0 / dt).ceil() as usize);
    let n = 2 * half + 1;
    let mut x: Vec<f64> = (0..n)
        .map(|k| (k as f64 - half as f64).max(0.0) * dt)
        .collect();
    smoother.smooth(&mut x);
    let (mut v, mut a) = (vec![0.0; n], vec![0.0; n]);
    differentiate(&x, dt, &mut v);
    differentiate(&v, dt, &mut a);
    let total: f64 = a.iter().map(|x| x.abs()).sum();
    let mut inside = a[half].abs();
    let mut h = 0;
    while inside < 0.95 * total && h < half {
        h += 1;
        inside += a[half - h].abs() + a[half + h].abs();
    }
    Ok(h as f64 * dt)
}

/// Flips runs of equal states shorter than `min_frames` that have neighbours on both sides:
/// first short contacts (blips), then short gaps.
fn absorb_short_phases(c: &mut [bool], min_frames: usize) {
    for target in [true, false] {
        let mut k = 0;
        while k < c.len() {
            let start = k;
            while k < c.len() && c[k] == c[start] {
                k += 1;
            }
            let inner = start > 0 && k < c.len();
            if c[start] == target && inner && k - start < min_frames {
                c[start..k].fill(!target);
            }
        }
    }
}
#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_acceleration_spread_is_the_kernel_of_differences_and_smoothing() {
        // no smoothing: a = (x[k+2] − 2x[k] + x[k−2]) / 4dt² is [¼, ½, ¼]/dt on an impulse:
        // one frame each side
        for dt in [1.0 / 30.0, 1.0 / 120.0] {
            let h = acceleration_spread_s(&SmoothSpec::None, dt).unwrap();
            assert!((h - dt).abs() < 1e-12, "{h}");
        }
        // a low-pass widens it in time, roughly as 1/cutoff, not as the frame rate
        let bw = |hz: f64, dt: f64| {
            let spec = SmoothSpec::Butterworth {
                cutoff_hz: hz,
                order: 2,
            };
            acceleration_spread_s(&spec, dt).unwrap()
        };
        let (h6, h12) = (bw(6.0, 1.0 / 120.0), bw(12.0, 1.0 / 120.0));
        assert!((0.05..0.12).contains(&h6), "{h6}");
        assert!((h6 / h12 - 2.0).abs() < 0.3, "{h6} {h12}");
        assert!((bw(6.0, 1.0 / 30.0) - h6).abs() < 0.04);
        // a cutoff above Nyquist is an error, not a panic
        assert!(
            acceleration_spread_s(
                &SmoothSpec::Butterworth {
                    cutoff_hz: 20.0,
                    order: 2
                },
                1.0 / 30.0
            )
            .is_err()
        );
    }

    #[test]
    fn a_landing_enters_contact_on_its_touch_down_frame() {
        // a point falls at 2 m/s onto the floor, touching down at frame 10, and stays there;
        // at 30 fps the central-difference speed of frame 10 is 1 m/s, over the 0.8 m/s entry
        // speed: a forward trigger enters one frame late (11), the backward one holds contact
        // back to frame 10 (speed ≤ 1.2 m/s) and not to 9 (6.7 cm up, 2 m/s)
        let dt = 1.0 / 30.0;
        let p: Vec<Vector3<f64>> = (0..20)
            .map(|k| Vector3::new(0.0, (10.0 - k as f64).max(0.0) * 2.0 * dt, 0.0))
            .collect();
        let c = planted(&p, 1, 0.0, dt, Vector3::zeros(), &ContactParams::default());
        let first = c.iter().position(|x| *x).unwrap();
        assert_eq!(first, 10, "{c:?}");
        assert!(c[first..].iter().all(|x| *x));
        // and the mirror image, a lift-off, leaves symmetrically
        let rev: Vec<Vector3<f64>> = p.iter().rev().copied().collect();
        let r = planted(
            &rev,
            1,
            0.0,
            dt,
            Vector3::zeros(),
            &ContactParams::default(),
        );
        let back: Vec<bool> = c.iter().rev().copied().collect();
        assert_eq!(r, back);
    }

    #[test]
    fn short_blips_and_gaps_are_absorbed_but_not_at_the_ends() {
        let mut c = vec![
            true, false, false, false, true, false, false, true, true, false, true,
        ];
        absorb_short_phases(&mut c, 2);
        // the lone `true` at 4 is a blip → false; the lone false at 9 is a gap → true;
        // the first `true` touches the start and stays
        assert_eq!(
            c,
            vec![
                true, false, false, false, false, false, false, true, true, true, true
            ]
        );
    }
}
