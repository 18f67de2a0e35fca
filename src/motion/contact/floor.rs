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

/// The floor levels of the heel points and of the toe points, over all feet (m along `up`):
/// what the planted test measures each kind of point's height against.
pub fn point_levels(feet: &[FootPoints], up: usize) -> (f64, f64) {
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

/// At most this many of the velocities at the floor are tried as the centre of the planted
/// feet's cluster ([`belt_velocity`]): every `n / FLOOR_CANDIDATES`-th, so that finding it
/// costs at most 64 passes over them whatever the take's length.
pub const FLOOR_CANDIDATES: usize = 64;

/// The velocity of the floor under the feet (m/s, horizontal): the velocity at which the take's
/// planted feet move together. Over ground it is the slow slip of the planted feet (0–6.5 cm/s
/// on the captured walks tried); a take walked in place (a treadmill; a game's in-place cycle,
/// whose root stays while the planted foot slides back at the walking speed) has its feet,
/// while planted, move together at the belt's velocity. A floor moving at a constant velocity
/// is an inertial frame: the dynamics are the same, and the contact test measures speeds
/// against this velocity.
///
/// Found from the horizontal velocities of the heel and toe points over the frames where they
/// are within `height_on` of their floor level (`levels`: the heels' and the toes', as
/// [`point_levels`] gives them, which every caller has already): the densest cluster of them,
/// the one of ([`FLOOR_CANDIDATES`] evenly spread) velocities with the most others within
/// [`STILL_SHARE`] × `speed_on` (0.1 m/s) of it, moved to the mean of those until it stays (the
/// planted feet's cluster: swing feet that pass low go by at speeds spread over metres per
/// second, planted ones stand within centimetres per second of the floor's).
///
/// Equivariant, as a floor moving at `c` asks: the same take with `c` added to every foot's
/// velocity gives this velocity plus `c` (to rounding), since it reads only distances between
/// the velocities and their means, and none is tested against the world's rest; the take turned
/// about the vertical gives it turned (a component-wise median would not). Before, a floor
/// slower than `speed_on` / 2 was taken as still, and one whose cluster held fewer than twice
/// as many feet as rest did: over ground the planted feet's slip was read as zero, and on a
/// belt the same slip added to the belt's speed (the Bandai youthful walk: 5.5 cm/s, three
/// frames of 210 found in another stance); the median of all the velocities at the floor
/// started the search, which on a run (CMU 02_03 from iClone, 60 fps: its low swing feet
/// outnumber the planted ones) lay 0.9 m/s off the belt, and was refused over ground only by
/// the count at rest (13 frames of 86).
///
/// [`STILL_SHARE`]: super::STILL_SHARE
pub fn belt_velocity(
    feet: &[FootPoints],
    levels: (f64, f64),
    up: usize,
    dt: f64,
    params: &ContactParams,
) -> Vector3<f64> {
    // The velocities' two horizontal components, in index order, side by side: their up
    // component is zero, and a zero adds nothing to a sum of squares or a sum, so the distances
    // and the means below are those of the 3-vectors bit for bit, while the counts, the search's
    // 64 passes over every velocity, run on the vector lanes.
    let (h0, h1) = [(1, 2), (0, 2), (0, 1)][up];
    let (mut x, mut y) = (vec![], vec![]);
    for v in velocities_at_floor(feet, levels, up, dt, params) {
        x.push(v[h0]);
        y.push(v[h1]);
    }
    if x.is_empty() {
        return Vector3::zeros();
    }
    let radius = super::STILL_SHARE * params.speed_on;
    let r2 = radius * radius;
    let inside = move |(x, y): (f64, f64), (cx, cy): (f64, f64)| {
        let (dx, dy) = (x - cx, y - cy);
        dx * dx + dy * dy < r2
    };
    let (x, y) = (&x[..], &y[..]);
    let count = |c: (f64, f64)| -> usize {
        crate::lanes::vectorised(
            #[inline(always)]
            || {
                x.iter()
                    .zip(y)
                    .map(|(&x, &y)| usize::from(inside((x, y), c)))
                    .sum()
            },
        )
    };
    // the densest of the candidates (the first of equals: the same one under any belt)
    let stride = x.len().div_ceil(FLOOR_CANDIDATES);
    let (mut centre, mut most) = ((x[0], y[0]), 0);
    for k in (0..x.len()).step_by(stride) {
        let c = (x[k], y[k]);
        let n = count(c);
        if n > most {
            (centre, most) = (c, n);
        }
    }
    // moved to the mean of the velocities around it until they stay the same (a mean shift:
    // the mean, not a component-wise median, turns with the take); the sums in the velocities'
    // order
    let mut members = most;
    for _ in 0..16 {
        let (mut sx, mut sy, mut n) = (0.0, 0.0, 0usize);
        for (&x, &y) in x.iter().zip(y) {
            if inside((x, y), centre) {
                (sx, sy, n) = (sx + x, sy + y, n + 1);
            }
        }
        if n == 0 {
            break;
        }
        let next = (sx / n as f64, sy / n as f64);
        if n == members && next == centre {
            break;
        }
        (centre, members) = (next, n);
    }
    let mut v = Vector3::zeros();
    (v[h0], v[h1]) = centre;
    v
}

/// The velocities of the heel and toe points (`feet`, heels then toes, frame by frame) at the
/// frames where they are within `height_on` of their floor level: what [`belt_velocity`]
/// searches.
fn velocities_at_floor<'a>(
    feet: &'a [FootPoints],
    (heel_level, toe_level): (f64, f64),
    up: usize,
    dt: f64,
    params: &'a ContactParams,
) -> impl Iterator<Item = Vector3<f64>> + 'a {
    feet.iter()
        .flat_map(move |f| [(&f.heel, heel_level), (&f.toe, toe_level)])
        .flat_map(move |(path, level)| {
            (0..path.len())
                .filter(move |&k| path[k][up] - level < params.height_on)
                .map(move |k| velocity(path, k, dt))
        })
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
            with_toe_ahead(path)
        };
        vec![foot(0), foot(15)]
    }

    /// A foot whose heel follows `heel` and whose toe stays 15 cm ahead of it along x.
    fn with_toe_ahead(heel: Vec<Vector3<f64>>) -> FootPoints {
        let toe = heel
            .iter()
            .map(|p| p + Vector3::new(0.15, 0.0, 0.0))
            .collect();
        FootPoints { heel, toe }
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

    /// A run at 30 fps, y up, seen from a frame moving at `belt` (m/s, horizontal): each foot
    /// stands for 5 frames of 20, its heel and toe sliding forward at `slip` (a capture's
    /// skating feet), and swings for 15, of which the first and last 4 pass below 4 cm at
    /// 0.9–3.2 m/s (toe-off and landing): more of its frames at the floor are a swing's than
    /// a stance's, as on CMU 02_03 (iClone, 60 fps).
    fn run_on(belt: Vector3<f64>, slip: f64) -> Vec<FootPoints> {
        let dt = 1.0 / 30.0;
        let low_speed = [0.9, 1.6, 2.4, 3.2];
        let low_height = [0.01, 0.02, 0.03, 0.035];
        let foot = |phase: usize| {
            let (mut x, mut path) = (0.0, vec![]);
            for k in 0..120 {
                let f = (k + phase) % 20;
                let (speed, h) = match f {
                    0..5 => (slip, 0.0),
                    5..9 => (low_speed[f - 5], low_height[f - 5]),
                    9..16 => (5.0, 0.15),
                    _ => (low_speed[19 - f], low_height[19 - f]),
                };
                x += speed * dt;
                path.push(Vector3::new(x, h, 0.0) - belt * (k as f64 * dt));
            }
            with_toe_ahead(path)
        };
        vec![foot(0), foot(10)]
    }

    #[test]
    fn a_run_with_skating_feet_finds_them_on_any_floor() {
        // the floor is where the planted feet go, not where most of the feet near it go, nor
        // the world's rest: over ground the skate (0.1 m/s), on a belt the belt's velocity
        // with it, and the same stances on every floor. (Before: a still floor over ground,
        // and on a belt the median of the feet near the floor, among the swing's speeds.)
        let (dt, up, params) = (1.0 / 30.0, 1, ContactParams::default());
        let slip = Vector3::new(0.1, 0.0, 0.0);
        let ground = run_on(Vector3::zeros(), slip.x);
        let found = belt_velocity(&ground, point_levels(&ground, up), up, dt, &params);
        assert!((found - slip).norm() < 1e-9, "found {found:?}");
        let stances = contact_phases(&ground, up, dt, &params);
        assert!(stances.iter().all(|c| c.iter().any(|x| *x)));
        for belt in [
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(3.0, 0.0, 0.0),
            Vector3::new(-1.0, 0.0, 0.0),
            Vector3::new(0.6, 0.0, -0.8),
        ] {
            let on_belt = run_on(belt, slip.x);
            let found = belt_velocity(&on_belt, point_levels(&on_belt, up), up, dt, &params);
            assert!(
                (found - slip + belt).norm() < 1e-9,
                "{belt:?}: found {found:?}"
            );
            assert_eq!(
                contact_phases(&on_belt, up, dt, &params),
                stances,
                "{belt:?}"
            );
        }
    }

    /// The search as it was written on 3-vectors (the velocities with their up component
    /// zeroed, their distances and means as `nalgebra` takes them): the definition the
    /// two-component search must give bit for bit.
    fn belt_velocity_on_vectors(
        feet: &[FootPoints],
        levels: (f64, f64),
        up: usize,
        dt: f64,
        params: &ContactParams,
    ) -> Vector3<f64> {
        let near: Vec<Vector3<f64>> = velocities_at_floor(feet, levels, up, dt, params)
            .map(|mut v| {
                v[up] = 0.0;
                v
            })
            .collect();
        if near.is_empty() {
            return Vector3::zeros();
        }
        let radius = super::super::STILL_SHARE * params.speed_on;
        let r2 = radius * radius;
        let within = |c: Vector3<f64>| near.iter().filter(move |v| (*v - c).norm_squared() < r2);
        let stride = near.len().div_ceil(FLOOR_CANDIDATES);
        let (mut centre, mut most) = (near[0], 0);
        for c in near.iter().step_by(stride) {
            let count = within(*c).count();
            if count > most {
                (centre, most) = (*c, count);
            }
        }
        let mut members = most;
        for _ in 0..16 {
            let (sum, count) =
                within(centre).fold((Vector3::zeros(), 0), |(s, n), v| (s + v, n + 1));
            if count == 0 {
                break;
            }
            let next = sum / count as f64;
            if count == members && next == centre {
                break;
            }
            (centre, members) = (next, count);
        }
        centre
    }

    #[test]
    fn the_search_on_two_components_is_the_search_on_vectors_bit_for_bit() {
        // walks and runs on belts, with noise of every size on the points, turned so that each
        // axis is up in turn: the same velocity to the last bit, signed zeros included
        use crate::dynamics::samples::SplitMix64;
        let (dt, params) = (1.0 / 30.0, ContactParams::default());
        let mut rng = SplitMix64(41);
        let mut tried = 0;
        for belt in [
            Vector3::zeros(),
            Vector3::new(1.0, 0.0, 0.0),
            Vector3::new(0.6, 0.0, -0.8),
        ] {
            for noise in [0.0, 1e-4, 3e-3, 0.05] {
                for slip in [0.0, 0.1] {
                    let mut feet = run_on(belt, slip);
                    feet.extend(walk_on(belt));
                    for p in feet
                        .iter_mut()
                        .flat_map(|f| f.heel.iter_mut().chain(&mut f.toe))
                    {
                        *p += rng.vec3(noise);
                    }
                    for up in 0..3 {
                        // y up → `up` up: the axes turned by a cyclic permutation
                        let turn = |p: &Vector3<f64>| {
                            let mut q = Vector3::zeros();
                            for i in 0..3 {
                                q[(i + up + 2) % 3] = p[i];
                            }
                            q
                        };
                        let turned: Vec<FootPoints> = feet
                            .iter()
                            .map(|f| FootPoints {
                                heel: f.heel.iter().map(turn).collect(),
                                toe: f.toe.iter().map(turn).collect(),
                            })
                            .collect();
                        let levels = point_levels(&turned, up);
                        let want = belt_velocity_on_vectors(&turned, levels, up, dt, &params);
                        let got = belt_velocity(&turned, levels, up, dt, &params);
                        assert_eq!(
                            got.map(f64::to_bits),
                            want.map(f64::to_bits),
                            "belt {belt:?}, noise {noise}, up {up}: {got:?} against {want:?}"
                        );
                        tried += usize::from(want != Vector3::zeros());
                    }
                }
            }
        }
        assert!(tried > 40, "only {tried} searches found a moving floor");
        // no point near the floor: zero either way
        let high = vec![FootPoints {
            heel: vec![Vector3::new(0.0, 1.0, 0.0); 3],
            toe: vec![Vector3::new(0.0, 1.0, 0.0); 3],
        }];
        let got = belt_velocity(&high, (0.0, 0.0), 1, dt, &params);
        assert_eq!(
            got.map(f64::to_bits),
            Vector3::<f64>::zeros().map(f64::to_bits)
        );
    }
}
