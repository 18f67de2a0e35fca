//! Contact heights that fit the take: how much its planted heel and toe points wobble in
//! height, and the entry and exit heights of the contact test scaled down to it.
//!
//! The default heights ([`ContactParams::height_on`] 4 cm, [`ContactParams::height_off`]
//! 7 cm) are sized for captured takes, whose planted points rise and fall 1–3 cm (heel roll,
//! skin and solver noise, per-step offsets of the floor level). A take whose planted feet do
//! not wobble (made by a simulation, a solver that pins the feet, keyframed to a floor) needs
//! far less: with the defaults a foot lowered slowly onto the floor is taken for planted, and
//! loaded, while still 4–7 cm up (`tests/fd_ground_truth.rs`).

use super::FootPoints;
use super::floor::{point_levels, velocity};
use super::phases::ContactParams;

/// The heights (m) above its floor level that a still point near the floor reaches, over a
/// take: what its planted feet wobble. Measured by [`planted_wobble`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Wobble {
    /// The [`WOBBLE_QUANTILE`] quantile of the heights (m) above their floor level of the heel
    /// and toe points at their stances (the frames [`planted_wobble`] measures).
    pub height: f64,
    /// How many point-frames it was measured on.
    pub samples: usize,
    /// How many point-frames the contact test could plant (near the floor and slow), those
    /// measured among them.
    pub plantable: usize,
}

/// The quantile of a still point's heights that [`planted_wobble`] reports: 95 %, the
/// heights planted points reach in all but their rarest frames (a glitch, a slow heel rise).
pub const WOBBLE_QUANTILE: f64 = 0.95;

/// A point is still below this fraction of [`ContactParams::speed_on`] (0.1 m/s with the
/// default 0.8 m/s): planted heel and toe points of captured takes are that slow through
/// mid-stance.
pub const STILL_SHARE: f64 = 1.0 / 8.0;

/// The frames measured around a still frame reach this many times
/// [`ContactParams::spread_s`] each side (±0.13–0.2 s with the default smoothing): the
/// smoothing rounds a stance's ends over ±`spread_s`, and a heel strike rolls onto the foot
/// and a push-off onto the toes over about as long again (Winter 2009, ch. 2: heel strike to
/// foot flat ~0.1 s); those frames are where the contact test needs its heights.
pub const REACH_PER_SPREAD: f64 = 2.0;

/// At least this many point-frames must be measured ([`planted_wobble`]): their 95th
/// percentile is then at worst the second largest, so that one glitched frame does not set
/// the heights.
pub const MIN_SAMPLES: usize = 40;

/// At least this share of the frames the contact test could plant must lie within the reach
/// of a still frame ([`planted_wobble`]). Captured walks, runs, jumps and dances: 0.8–1.0; a
/// take whose feet move about near the floor without standing still (a dance skimming the
/// floor: Rokoko's video-captured `jesse_dance`, 0.38) says little by its few still frames
/// about how high its contacts are, and keeps the default heights.
pub const MIN_STILL_SHARE: f64 = 0.5;

/// The entry height is this many times the wobble: a planted point's heights spread around
/// the level it stands at, the wobble is their 95th percentile, and the entry test must catch
/// every stance with room for one that stands a little higher than the take's usual (a heel
/// point a few mm off between steps).
pub const HEIGHT_PER_WOBBLE: f64 = 4.0;

/// The lowest entry height (m): 1 cm, about a shoe sole's compression and the depth of the
/// heel and toe points under the sole's edge; a BVH writer's precision (1e-4 cm) and a 6 Hz
/// smoothing of a still point leave far less.
pub const MIN_HEIGHT_ON: f64 = 0.01;

/// How much the planted heel and toe points of `feet` (sampled every `dt` s, `up` the
/// vertical axis) wobble in height: the [`WOBBLE_QUANTILE`] quantile of their heights above
/// their floor level (each kind of point its own, [`detect_floor`](super::detect_floor)) over
/// the frames where the contact test could plant them (within `params.height_on` of it,
/// slower than `params.speed_on` against the floor, [`belt_velocity`](super::belt_velocity)) and that lie within
/// [`REACH_PER_SPREAD`] × `params.spread_s` of a frame where the point is still near the
/// floor (slower than [`STILL_SHARE`] of `speed_on`). `None` when fewer than
/// [`MIN_SAMPLES`] point-frames qualify (a take with almost no stance keeps the defaults), or
/// fewer than [`MIN_STILL_SHARE`] of those the contact test could plant.
///
/// What it is robust to. A foot lowered slowly onto the floor passes through the contact
/// test's heights at 0.1–0.5 m/s: slow enough to be planted, and not still until its last
/// millimetres; only its frames within the reach of those count, whatever the length of the
/// descent (a hover sets no height). The ends of a captured stance (the heel strike rounded
/// by the smoothing, the heel rolling onto the foot, the heel rising and the ball of the foot
/// lifting as the foot rolls onto the toes) lie within the reach of its still mid-stance and
/// do count: on every captured walk and run tried they keep the default heights.
pub fn planted_wobble(
    feet: &[FootPoints],
    up: usize,
    dt: f64,
    params: &ContactParams,
) -> Option<Wobble> {
    let (heel_level, toe_level) = point_levels(feet, up);
    let belt = params.floor_velocity_under(feet, (heel_level, toe_level), up, dt);
    let still = STILL_SHARE * params.speed_on;
    let reach = (REACH_PER_SPREAD * params.spread_s / dt).round() as usize;
    let mut heights: Vec<f64> = vec![];
    let mut plantable_frames = 0;
    for f in feet {
        for (path, level) in [(&f.heel, heel_level), (&f.toe, toe_level)] {
            // (height above the level, plantable, still) of each frame
            let n = path.len();
            let tests: Vec<(f64, bool, bool)> = (0..n)
                .map(|k| {
                    let h = path[k][up] - level;
                    let speed = (velocity(path, k, dt) - belt).norm();
                    let low = h < params.height_on;
                    (h, low && speed < params.speed_on, low && speed < still)
                })
                .collect();
            // the frames within the reach of a still frame
            let mut near_still = vec![false; n];
            for k in (0..n).filter(|&k| tests[k].2) {
                near_still[k.saturating_sub(reach)..(k + reach + 1).min(n)].fill(true);
            }
            for (&(h, plantable, _), near) in tests.iter().zip(&near_still) {
                plantable_frames += usize::from(plantable);
                if plantable && *near {
                    heights.push(h.max(0.0));
                }
            }
        }
    }
    if heights.len() < MIN_SAMPLES
        || (heights.len() as f64) < MIN_STILL_SHARE * plantable_frames as f64
    {
        return None;
    }
    let at = (WOBBLE_QUANTILE * (heights.len() - 1) as f64).round() as usize;
    let (_, &mut height, _) = heights.select_nth_unstable_by(at, f64::total_cmp);
    Some(Wobble {
        height,
        samples: heights.len(),
        plantable: plantable_frames,
    })
}

impl ContactParams {
    /// These thresholds with the contact heights fitted to `wobble`: the entry height
    /// [`HEIGHT_PER_WOBBLE`] times it, at least [`MIN_HEIGHT_ON`] and at most this
    /// `height_on`; the exit height in the same ratio to it as now (7/4 by default). Without a
    /// measurement, the thresholds as they are.
    pub fn fit_heights(self, wobble: Option<Wobble>) -> Self {
        let Some(w) = wobble else {
            return self;
        };
        let on =
            (HEIGHT_PER_WOBBLE * w.height).clamp(MIN_HEIGHT_ON.min(self.height_on), self.height_on);
        Self {
            height_on: on,
            height_off: self.height_off * on / self.height_on,
            ..self
        }
    }

    /// These thresholds fitted to the take whose planted points are `feet`: the floor's
    /// velocity under them, unless known ([`belt_velocity`](super::belt_velocity), kept in
    /// [`floor_velocity`](ContactParams::floor_velocity)), and the contact heights
    /// ([`planted_wobble`] measured with these thresholds, then
    /// [`fit_heights`](Self::fit_heights)); and the wobble measured.
    pub fn fitted_to(self, feet: &[FootPoints], up: usize, dt: f64) -> (Self, Option<Wobble>) {
        let floor = Self {
            floor_velocity: Some(self.floor_velocity_under(feet, point_levels(feet, up), up, dt)),
            ..self
        };
        let wobble = planted_wobble(feet, up, dt, &floor);
        (floor.fit_heights(wobble), wobble)
    }
}

/// What a user reads when the contact heights were fitted below `default`'s: `contact
/// heights 1.0/1.8 cm (defaults 4/7 cm): the planted heels and toes wobble ≤ 0.4 mm (…)`;
/// `None` when they are the default ones.
pub fn heights_note(
    params: &ContactParams,
    default: &ContactParams,
    wobble: Option<Wobble>,
) -> Option<String> {
    let w = wobble?;
    if params.height_on >= default.height_on {
        return None;
    }
    Some(format!(
        "contact heights {:.1}/{:.1} cm (defaults {:.0}/{:.0} cm): the planted heels and toes \
         wobble ≤ {:.1} mm ({:.0}th percentile over {} point-frames at their stances)",
        100.0 * params.height_on,
        100.0 * params.height_off,
        100.0 * default.height_on,
        100.0 * default.height_off,
        1000.0 * w.height,
        100.0 * WOBBLE_QUANTILE,
        w.samples
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    /// Two feet at 120 fps, y up, for 2 s: the left planted all along; the right hovering
    /// 3 cm over the floor while it moves forward at 0.3 m/s (slow enough for the contact
    /// test, never still) for 0.9 s, then lowered onto the floor over 0.1 s and planted at
    /// 1 s. Every planted point's height is `noise(k, point)` above its level.
    fn stance(noise: &dyn Fn(usize, usize) -> f64) -> Vec<FootPoints> {
        let (dt, n) = (1.0 / 120.0, 240);
        let hover = |k: usize| {
            let t = k as f64 * dt;
            let h = 0.03 * ((1.0 - t) / 0.1).clamp(0.0, 1.0);
            (0.3 * t.min(1.0), h)
        };
        let path = |point: usize, x0: f64, lifted: bool| -> Vec<Vector3<f64>> {
            (0..n)
                .map(|k| {
                    let (x, h) = if lifted { hover(k) } else { (0.0, 0.0) };
                    let planted = !lifted || k as f64 * dt >= 1.0;
                    let wobble = if planted { noise(k, point) } else { 0.0 };
                    Vector3::new(x0 + x, h + wobble, 0.0)
                })
                .collect()
        };
        vec![
            FootPoints {
                heel: path(0, 0.0, false),
                toe: path(1, 0.15, false),
            },
            FootPoints {
                heel: path(2, 0.3, true),
                toe: path(3, 0.45, true),
            },
        ]
    }

    fn params() -> ContactParams {
        ContactParams {
            spread_s: 0.05,
            ..ContactParams::default()
        }
    }

    #[test]
    fn a_clean_stance_gives_the_lowest_heights_and_a_noisy_one_the_defaults() {
        let (dt, defaults) = (1.0 / 120.0, params());
        // no wobble: the hovering right foot is not taken for one (counted whole, its 0.9 s
        // at 3 cm would be a quarter of the frames measured; within 0.1 s of its stance, 3–4 %);
        // the heights drop to the floor, the exit height in the default ratio, and the note
        // says so
        let clean = stance(&|_, _| 0.0);
        let w = planted_wobble(&clean, 1, dt, &defaults).unwrap();
        assert!(w.height < 1e-3, "{w:?}");
        let fitted = defaults.fit_heights(Some(w));
        assert_eq!(fitted.height_on, MIN_HEIGHT_ON);
        assert!((fitted.height_off / fitted.height_on - 7.0 / 4.0).abs() < 1e-12);
        let note = heights_note(&fitted, &defaults, Some(w)).unwrap();
        assert!(note.starts_with("contact heights 1.0/1.8 cm"), "{note}");
        // a 2 mm wobble (2 ± 2 mm of sway) sets the entry height to 4 × its 95th percentile,
        // between the floor and the default
        let sway = |k: usize, p: usize| 0.002 * (1.0 + (0.5 * k as f64 + p as f64).sin());
        let w = planted_wobble(&stance(&sway), 1, dt, &defaults).unwrap();
        assert!((0.0035..0.0041).contains(&w.height), "{w:?}");
        let fitted = defaults.fit_heights(Some(w));
        assert!((fitted.height_on - HEIGHT_PER_WOBBLE * w.height).abs() < 1e-12);
        // planted points that wander 0–3 cm (a capture's heel roll and per-step offsets)
        // keep the defaults, and no note
        let wander = |k: usize, p: usize| 0.015 * (1.0 + (0.05 * k as f64 + p as f64).sin());
        let w = planted_wobble(&stance(&wander), 1, dt, &defaults).unwrap();
        assert!(w.height > 0.01, "{w:?}");
        let kept = defaults.fit_heights(Some(w));
        assert_eq!(kept, defaults);
        assert_eq!(heights_note(&kept, &defaults, Some(w)), None);
    }

    #[test]
    fn too_few_still_frames_measure_nothing() {
        let dt = 1.0 / 120.0;
        // a point that never stands still on any floor: a foot skimming the floor at 0.4 m/s
        // round a circle of 20 cm (one gliding straight at a steady speed stands on a floor
        // that moves with it, a belt: no floor moving at a constant velocity carries this one
        // for long)
        let skim: Vec<Vector3<f64>> = (0..360)
            .map(|k| {
                let turn = 2.0 * k as f64 * dt;
                Vector3::new(0.2 * turn.cos(), 0.02, 0.2 * turn.sin())
            })
            .collect();
        let feet = vec![FootPoints {
            heel: skim.clone(),
            toe: skim,
        }];
        assert_eq!(planted_wobble(&feet, 1, dt, &params()), None);
        assert_eq!(params().fit_heights(None), params());
        // a take of a few frames
        let short: Vec<FootPoints> = stance(&|_, _| 0.0)
            .into_iter()
            .map(|f| FootPoints {
                heel: f.heel[..10].to_vec(),
                toe: f.toe[..10].to_vec(),
            })
            .collect();
        assert_eq!(planted_wobble(&short, 1, dt, &params()), None);
    }

    #[test]
    fn the_wobble_is_the_same_on_a_moving_floor() {
        // the clean stance seen from a frame moving at 1 m/s: the floor (and the planted
        // points) move, and are measured against it
        let dt = 1.0 / 120.0;
        let ground = stance(&|_, _| 0.0);
        let belt = Vector3::new(-1.0, 0.0, 0.0);
        let moving: Vec<FootPoints> = ground
            .iter()
            .map(|f| {
                let shift = |p: &Vec<Vector3<f64>>| -> Vec<Vector3<f64>> {
                    p.iter()
                        .enumerate()
                        .map(|(k, x)| x + belt * (k as f64 * dt))
                        .collect()
                };
                FootPoints {
                    heel: shift(&f.heel),
                    toe: shift(&f.toe),
                }
            })
            .collect();
        assert_eq!(
            planted_wobble(&moving, 1, dt, &params()),
            planted_wobble(&ground, 1, dt, &params())
        );
    }
}
