//! Where the floor is under a take's feet (a low quantile of their heights, robust to
//! glitches) and how fast it moves under them (a treadmill, a cycle walked in place).

use super::ContactParams;
use nalgebra::Vector3;

/// World positions of one foot's heel and toe points over the take (m, the take's axes), one
/// entry per frame.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FootPoints {
    pub heel: Vec<Vector3<f64>>,
    pub toe: Vec<Vector3<f64>>,
}

/// The fraction of a take's samples below which the floor lies: [`detect_floor`] returns this
/// quantile. 5 %: robust to a few glitched frames (a minimum is one noisy sample) and still
/// within the stance cluster as long as the feet are down for more than ~10 % of the take.
pub const FLOOR_QUANTILE: f64 = 0.05;

/// The floor level of a set of heights (m): their [`FLOOR_QUANTILE`] quantile (linear
/// interpolation between order statistics). Non-finite heights are ignored; with none left the
/// result is 0 (the world's origin plane).
pub fn detect_floor(heights: &[f64]) -> f64 {
    let mut h: Vec<f64> = heights.iter().copied().filter(|x| x.is_finite()).collect();
    if h.is_empty() {
        return 0.0;
    }
    // the two order statistics by selection (the values a sort would put there)
    let pos = FLOOR_QUANTILE * (h.len() - 1) as f64;
    let (lo, frac) = (pos.floor() as usize, pos.fract());
    let (_, &mut low, above) = h.select_nth_unstable_by(lo, f64::total_cmp);
    let high = above.iter().copied().min_by(f64::total_cmp).unwrap_or(low);
    low + (high - low) * frac
}

/// The floor height (m along the up axis) under a set of feet: the floor level of their toe
/// points, the lowest points a foot stands on.
pub fn floor_height(feet: &[FootPoints], up: usize) -> f64 {
    let toes: Vec<f64> = feet
        .iter()
        .flat_map(|f| f.toe.iter().map(|p| p[up]))
        .collect();
    detect_floor(&toes)
}

/// The floor levels of the heel points and of the toe points, over all feet (m along `up`).
pub(super) fn point_levels(feet: &[FootPoints], up: usize) -> (f64, f64) {
    let level = |pick: fn(&FootPoints) -> &Vec<Vector3<f64>>| {
        let h: Vec<f64> = feet
            .iter()
            .flat_map(|f| pick(f).iter().map(|p| p[up]))
            .collect();
        detect_floor(&h)
    };
    (level(|f| &f.heel), level(|f| &f.toe))
}

/// The central-difference velocity of point path `p` at frame `k` (one-sided at the ends; zero
/// for a path of one frame).
pub(super) fn velocity(p: &[Vector3<f64>], k: usize, dt: f64) -> Vector3<f64> {
    let (a, b) = (k.saturating_sub(1), (k + 1).min(p.len() - 1));
    if b > a {
        (p[b] - p[a]) / ((b - a) as f64 * dt)
    } else {
        Vector3::zeros()
    }
}

/// The velocity of the floor under the feet (m/s, horizontal): zero over ground. A take walked
/// in place (a treadmill; a game's in-place cycle, whose root stays while the planted foot
/// slides back at the walking speed) has its feet, while at the floor, move together at the
/// belt's velocity; a floor moving at a constant velocity is an inertial frame, so the
/// dynamics are the same and only the contact test must measure speeds against it.
///
/// Estimated from the horizontal velocities of the heel and toe points over the frames where
/// they are within `height_on` of their floor level (stance dominates those: a walk's swing
/// foot clears the floor; the levels of the heels and of the toes are given, as
/// [`point_levels`] finds them, since every caller has them already): their component-wise median, refined to the median of those within
/// `speed_on` / 2 of it (the planted feet's cluster), is taken as a belt when it exceeds
/// `speed_on` / 2, at least half of them lie within `speed_on` of it, and more than twice as
/// many lie within `speed_on` of it as of rest (a still floor is the usual one: the Bandai
/// run's swing feet pass low and fast, and on the pelvis paths residual reduction tries its
/// heel strikes and push-offs pull the median forward to 0.6 m/s; it keeps a still floor,
/// with 0.7–0.9 as many of them still as moving with that median).
///
/// The belt and its counts move with the floor: the same take on a floor moving at `c` has the
/// belt `c` whatever its own travel (up to the median slip of its planted feet, which a belt's
/// speed cannot be told from: the Bandai walk's 1.5 cm/s); the count at rest only decides
/// against a belt that carries fewer than twice as many. Before, a
/// fifth of them slower than `speed_on` meant a still floor: the Bandai walk going on at
/// 1.25 m/s over a 1 m/s belt, its feet passing through rest at each heel strike and toe-off on
/// their way between the swing's speed and the belt's, was measured against a still floor; its
/// planted feet, sliding at 1 m/s, stayed under the exit speed, and every stance came out a
/// frame longer at both ends (168 of 195 frames agreed; now all do, and 0.25 as many of its
/// feet at the floor are still as move with the belt).
pub fn belt_velocity(
    feet: &[FootPoints],
    (heel_level, toe_level): (f64, f64),
    up: usize,
    dt: f64,
    params: &ContactParams,
) -> Vector3<f64> {
    let mut near: Vec<Vector3<f64>> = vec![];
    for f in feet {
        for (path, level) in [(&f.heel, heel_level), (&f.toe, toe_level)] {
            for k in 0..path.len() {
                if path[k][up] - level < params.height_on {
                    let mut v = velocity(path, k, dt);
                    v[up] = 0.0;
                    near.push(v);
                }
            }
        }
    }
    if near.is_empty() {
        return Vector3::zeros();
    }
    // the median, then the median of the velocities near it (the planted feet's cluster,
    // without the swing feet that pass low and drag the whole median towards them)
    let median = |vs: &[&Vector3<f64>]| {
        let mut m = Vector3::zeros();
        for i in (0..3).filter(|&i| i != up) {
            let mut c: Vec<f64> = vs.iter().map(|v| v[i]).collect();
            let half = c.len() / 2;
            m[i] = *c.select_nth_unstable_by(half, f64::total_cmp).1;
        }
        m
    };
    let support = |b: &Vector3<f64>| {
        near.iter()
            .filter(|v| (*v - b).norm() < params.speed_on)
            .count()
    };
    let first = median(&near.iter().collect::<Vec<_>>());
    let mut belt = first;
    for _ in 0..5 {
        let close: Vec<&Vector3<f64>> = near
            .iter()
            .filter(|v| (*v - belt).norm() < 0.5 * params.speed_on)
            .collect();
        if close.is_empty() {
            break;
        }
        belt = median(&close);
    }
    // a refinement that gathers fewer of the velocities (a short take's few samples) is not
    if support(&first) > support(&belt) {
        belt = first;
    }
    // the belt, when it carries the feet at the floor together, and more than twice as many
    // of them as a still floor would
    let together = support(&belt);
    let still = support(&Vector3::zeros());
    if belt.norm() > 0.5 * params.speed_on && 2 * together >= near.len() && 2 * still < together {
        belt
    } else {
        Vector3::zeros()
    }
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::contact::contact_phases;

    #[test]
    fn floor_is_a_low_quantile_not_the_minimum() {
        // 100 samples at 0.0..0.99 plus one glitch far below
        let mut h: Vec<f64> = (0..100).map(|k| k as f64 * 0.01).collect();
        h.push(-5.0);
        let f = detect_floor(&h);
        assert!((0.03..0.06).contains(&f), "{f}");
        assert_eq!(detect_floor(&[]), 0.0);
    }

    #[test]
    fn the_floor_quantile_is_the_sorted_samples_interpolated() {
        // the order statistics found by selection are the sorted ones, bit for bit, at every
        // length (the interpolation's upper neighbour included), ties and non-finite samples too
        let mut x = 0.37_f64;
        for n in [1usize, 2, 3, 20, 21, 22, 41, 400, 1001] {
            let h: Vec<f64> = (0..n)
                .map(|k| {
                    x = (x * 3.9 * (1.0 - x)).clamp(1e-9, 1.0 - 1e-9);
                    if k % 7 == 3 { 0.25 } else { x - 0.5 }
                })
                .chain([f64::NAN, f64::INFINITY])
                .collect();
            let mut sorted: Vec<f64> = h.iter().copied().filter(|v| v.is_finite()).collect();
            sorted.sort_by(f64::total_cmp);
            let pos = FLOOR_QUANTILE * (sorted.len() - 1) as f64;
            let lo = pos.floor() as usize;
            let hi = (lo + 1).min(sorted.len() - 1);
            let want = sorted[lo] + (sorted[hi] - sorted[lo]) * pos.fract();
            assert_eq!(detect_floor(&h).to_bits(), want.to_bits(), "{n} samples");
        }
    }

    /// A walk at 0.75 m/s, 30 fps, y up: each foot's heel and toe hold still for 18 frames
    /// and swing for 12, the feet half a cycle apart; the swing leaves and reaches the floor
    /// through four frames below 4 cm at 0.6–1.5 m/s (a toe-off and a heel strike). `belt`
    /// (m/s, horizontal) is taken out of every point's motion: the same walk seen from a frame
    /// moving at `belt`, in which the floor moves at `−belt`.
    fn walk_on(belt: Vector3<f64>) -> Vec<FootPoints> {
        let dt = 1.0 / 30.0;
        let swing_speed = [0.6, 0.9, 1.2, 1.5, 3.0, 4.5, 4.5, 3.0, 1.5, 1.2, 0.9, 0.6];
        let swing_height = [
            0.005, 0.015, 0.025, 0.035, 0.08, 0.12, 0.12, 0.08, 0.035, 0.025, 0.015, 0.005,
        ];
        let foot = |phase: usize| {
            let (mut x, mut path) = (0.0, vec![]);
            for k in 0..120 {
                let f = (k + phase) % 30;
                let h = if f < 18 {
                    0.0
                } else {
                    x += swing_speed[f - 18] * dt;
                    swing_height[f - 18]
                };
                path.push(Vector3::new(x, h, 0.0) - belt * (k as f64 * dt));
            }
            let toe = path
                .iter()
                .map(|p| p + Vector3::new(0.15, 0.0, 0.0))
                .collect();
            FootPoints { heel: path, toe }
        };
        vec![foot(0), foot(15)]
    }

    #[test]
    fn the_same_walk_on_a_moving_floor_finds_the_floor_moving_and_the_same_stances() {
        let (dt, up, params) = (1.0 / 30.0, 1, ContactParams::default());
        let ground = walk_on(Vector3::zeros());
        assert_eq!(
            belt_velocity(&ground, point_levels(&ground, up), up, dt, &params),
            Vector3::zeros()
        );
        let stances = contact_phases(&ground, up, dt, &params);
        for belt in [
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(1.25, 0.0, 0.0),
            Vector3::new(2.5, 0.0, 0.0),
            Vector3::new(-1.0, 0.0, 0.0),
            Vector3::new(0.6, 0.0, -0.8),
        ] {
            let on_belt = walk_on(belt);
            let found = belt_velocity(&on_belt, point_levels(&on_belt, up), up, dt, &params);
            assert!((found + belt).norm() < 1e-9, "{belt:?}: found {found:?}");
            assert_eq!(
                contact_phases(&on_belt, up, dt, &params),
                stances,
                "{belt:?}"
            );
        }
        // the case that fooled a count of still feet (a fifth of those at the floor slower than
        // `speed_on` meant a still floor): on a 1 m/s belt under the walk, the swing's ends
        // pass through rest on their way to and from the belt's speed
        let on_belt = walk_on(Vector3::new(1.0, 0.0, 0.0));
        let (mut near, mut still) = (0, 0);
        for f in &on_belt {
            for k in 0..f.heel.len() {
                if f.heel[k][up] < params.height_on {
                    near += 1;
                    still += usize::from(velocity(&f.heel, k, dt).norm() < params.speed_on);
                }
            }
        }
        assert!(5 * still >= near, "{still} of {near} slower than speed_on");
    }
}
