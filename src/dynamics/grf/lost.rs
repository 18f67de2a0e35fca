//! Where a take's capture has left its floor: runs of frames in which the feet carry nothing
//! and stay off the floor, yet the motion is not a flight.
//!
//! A body off the floor is in free fall: its centre of mass accelerates at −g, and the
//! vertical force the motion needs, `m (c̈ + g)·up`, is zero. Over a run of frames from `t₀` to
//! `t₁` its mean is `m g + m (ċ(t₁) − ċ(t₀))·up / (t₁ − t₀)`: zero for a ballistic flight
//! (the vertical velocity turns from `+v` to `−v` in `2v/g`), about body weight for a body
//! that stays up (a dancer whose video capture drifted 20 cm above the floor, a body sitting
//! or hanging on something the take does not show). The mean is taken, not each frame's
//! force: a body hopping on an invisible floor needs −0.9 to 3 body weights frame by frame
//! (Rokoko's `jesse_dance`), and a flight's frames hold the estimator's noise.
//!
//! So a run of at least [`MIN_LOST_S`] in which no foot carries load
//! ([`GroundReactions::loaded`]: the flight frames within the estimator's spread of a contact
//! carry it) has lost its floor when the lowest foot point stays, in the median frame, above
//! the height from which no part of a foot touches the floor ([`GroundReactions::foot_height`];
//! the caller's: `pipeline::consistency` takes the contact test's exit height plus the sole's
//! reach beyond the foot points, 7 + 5 cm by default, since a foot lower than that with no
//! contact is more likely a contact the test missed, one sliding or on its toes, than a floor
//! gone) and the vertical force it needs averages at least [`HELD_SHARE`] of body weight. The median, not every
//! frame: a body hopping on a floor that is not the capture's comes down towards its own
//! floor at every landing, its feet passing within a few cm of the capture's. Its ground
//! force is zero, the root holds the body up, and the frames are those the feet cannot
//! explain.

use super::GroundReactions;
use crate::motion::contact::{FootPoints, point_levels};

/// Shortest run of frames (s) that can have lost its floor: 0.1 s, longer than the spread of
/// the estimated accelerations around a contact (±0.07–0.1 s with the 6 Hz Butterworth), so
/// that a landing's spread force alone is never one.
pub const MIN_LOST_S: f64 = 0.1;

/// The share of body weight that the vertical force a run of frames needs must average for
/// its body to be held up rather than in flight: half, between free fall (0) and a body held
/// at a constant height (1).
pub const HELD_SHARE: f64 = 0.5;

/// A run of frames in which the take's capture has left its floor (or the floor moved).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FloorLost {
    /// The run's first and last frame.
    pub first: usize,
    pub last: usize,
    /// The lowest foot point's height over the floor there (m): least, median and largest
    /// over the run.
    pub lowest_m: (f64, f64, f64),
    /// The vertical force the motion needs there, averaged over the run, as a share of body
    /// weight (1: held at a constant height; 0: free fall).
    pub needed_share: f64,
}

impl FloorLost {
    /// Frames in the run.
    pub fn frames(&self) -> usize {
        self.last + 1 - self.first
    }
}

/// One sentence for a user on the runs `lost` (none: `None`), `frames` the take's frame
/// count and `dt` its frame time (s): where, how long, how high the lowest foot was and how
/// much of body weight the motion needed there, e.g. `the capture leaves its floor at frames
/// 451–900 (4.50 s, 45 % of the take): the feet carry nothing and stay off it (the lowest foot
/// point 4–47 cm above it, a median 16 cm), yet the body is not in flight (…)`.
pub fn floor_lost_text(lost: &[FloorLost], frames: usize, dt: f64) -> Option<String> {
    if lost.is_empty() {
        return None;
    }
    const SHOWN: usize = 4;
    let mut runs: Vec<String> = lost
        .iter()
        .take(SHOWN)
        .map(|l| format!("{}–{}", l.first, l.last))
        .collect();
    if lost.len() > SHOWN {
        runs.push("…".into());
    }
    let count: usize = lost.iter().map(FloorLost::frames).sum();
    let needed = lost
        .iter()
        .map(|l| l.needed_share * l.frames() as f64)
        .sum::<f64>()
        / count as f64;
    let low = lost
        .iter()
        .map(|l| l.lowest_m.0)
        .fold(f64::INFINITY, f64::min);
    let high = lost
        .iter()
        .map(|l| l.lowest_m.2)
        .fold(f64::NEG_INFINITY, f64::max);
    // the longest run's median height: where the feet mostly are
    let longest = lost
        .iter()
        .max_by_key(|l| l.frames())
        .map_or(0.0, |l| l.lowest_m.1);
    Some(format!(
        "the capture leaves its floor at frames {} ({:.2} s, {:.0} % of the take): the feet \
         carry nothing and stay off it (the lowest foot point {:.0}–{:.0} cm above it, a \
         median {:.0} cm{}), yet the body is not in flight: the motion needs {:.0} % of body \
         weight upward there on average (free fall 0 %), which the root supplies (a capture \
         that drifted up from its floor, a moving floor, or a support the take does not \
         show)",
        runs.join(", "),
        count as f64 * dt,
        100.0 * count as f64 / frames.max(1) as f64,
        100.0 * low,
        100.0 * high,
        100.0 * longest,
        if lost.len() > 1 {
            " over the longest run"
        } else {
            ""
        },
        100.0 * needed
    ))
}

impl GroundReactions {
    /// The runs of frames in which the take's capture has left its floor (module
    /// documentation): no foot loaded for at least [`MIN_LOST_S`] (`dt` the frame time, s),
    /// the lowest foot point higher than `height_m` over the floor in the median frame, and
    /// the needed vertical force averaging at least [`HELD_SHARE`] of `weight_n` (N). None for
    /// measured ground reactions (no foot heights).
    pub fn floor_lost(&self, weight_n: f64, height_m: f64, dt: f64) -> Vec<FloorLost> {
        let up_force: Vec<f64> = self.wrench.iter().map(|w| w[self.up]).collect();
        let min_frames = (MIN_LOST_S / dt).ceil().max(1.0) as usize;
        lost_runs(
            &self.loaded,
            &self.foot_height,
            &up_force,
            weight_n,
            height_m,
            min_frames,
        )
    }
}

/// [`GroundReactions::floor_lost`] over its per-frame inputs: `loaded` (`[frame][foot]`),
/// `foot_height` (m, empty: none known) and the needed vertical force `up_force` (N).
fn lost_runs(
    loaded: &[Vec<bool>],
    foot_height: &[f64],
    up_force: &[f64],
    weight_n: f64,
    height_m: f64,
    min_frames: usize,
) -> Vec<FloorLost> {
    let n = foot_height.len().min(loaded.len()).min(up_force.len());
    let off = |k: usize| loaded[k].iter().all(|l| !l);
    let mut out = vec![];
    for run in crate::motion::runs(n, off) {
        let (first, k) = (run.start, run.end);
        if run.len() < min_frames {
            continue;
        }
        let mut heights = foot_height[run.clone()].to_vec();
        heights.sort_by(f64::total_cmp);
        let mean = up_force[run.clone()].iter().sum::<f64>() / run.len() as f64;
        let needed_share = mean / weight_n.max(f64::MIN_POSITIVE);
        if heights[heights.len() / 2] <= height_m || needed_share < HELD_SHARE {
            continue;
        }
        out.push(FloorLost {
            first,
            last: k - 1,
            lowest_m: (
                heights[0],
                heights[heights.len() / 2],
                heights[heights.len() - 1],
            ),
            needed_share,
        });
    }
    out
}

/// Per frame, the height (m) of the lowest foot point over its floor level: the least of
/// every foot's heel and toe heights over the floor levels of the heel and of the toe points
/// ([`point_levels`]), the heights the contact test measures.
pub(super) fn lowest_point_heights(points: &[FootPoints], up: usize) -> Vec<f64> {
    let (heel_level, toe_level) = point_levels(points, up);
    let n = points.first().map_or(0, |p| p.heel.len());
    (0..n)
        .map(|k| {
            points
                .iter()
                .map(|p| (p.heel[k][up] - heel_level).min(p.toe[k][up] - toe_level))
                .fold(f64::INFINITY, f64::min)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 100 frames, two feet; the frames `off` in the air: no foot loaded, 30 cm up.
    fn air(off: std::ops::Range<usize>) -> (Vec<Vec<bool>>, Vec<f64>) {
        let loaded = (0..100).map(|k| vec![!off.contains(&k); 2]).collect();
        let height = (0..100)
            .map(|k| if off.contains(&k) { 0.3 } else { 0.0 })
            .collect();
        (loaded, height)
    }

    #[test]
    fn a_body_held_up_off_the_floor_has_lost_it_and_a_flight_has_not() {
        let w = 700.0;
        let (loaded, height) = air(40..70);
        // held up: body weight on average, bouncing ±1.5 body weights frame by frame
        let held: Vec<f64> = (0..100)
            .map(|k| w * (1.0 + 1.5 * (k as f64 * 0.7).sin()))
            .collect();
        let lost = lost_runs(&loaded, &height, &held, w, 0.04, 10);
        assert_eq!(lost.len(), 1, "{lost:?}");
        let l = lost[0];
        assert_eq!((l.first, l.last, l.frames()), (40, 69, 30));
        assert_eq!(l.lowest_m, (0.3, 0.3, 0.3));
        assert!((l.needed_share - 1.0).abs() < 0.1, "{l:?}");
        // a ballistic flight: the needed force is the estimator's noise around zero
        let flight: Vec<f64> = (0..100).map(|k| 0.2 * w * (k as f64).sin()).collect();
        assert!(lost_runs(&loaded, &height, &flight, w, 0.04, 10).is_empty());
        // a run shorter than the least frames, or feet within the contact height: not lost
        assert!(lost_runs(&loaded, &height, &held, w, 0.04, 31).is_empty());
        assert!(lost_runs(&loaded, &height, &held, w, 0.5, 10).is_empty());
        // measured ground reactions know no foot heights
        assert!(lost_runs(&loaded, &[], &held, w, 0.04, 10).is_empty());
    }

    #[test]
    fn a_loaded_foot_splits_a_run() {
        let w = 700.0;
        let (mut loaded, height) = air(20..80);
        // a foot carries the spread force of a contact in frames 45..50, high above the floor
        for l in &mut loaded[45..50] {
            l[0] = true;
        }
        let lost = lost_runs(&loaded, &height, &[w; 100], w, 0.04, 10);
        let runs: Vec<(usize, usize)> = lost.iter().map(|l| (l.first, l.last)).collect();
        assert_eq!(runs, [(20, 44), (50, 79)]);
    }
}
