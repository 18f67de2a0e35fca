//! Contact phases found from heel and toe paths alone agree with the schedule that made the
//! paths, on the four kinds of takes the detector must handle: walking (a foot always down,
//! double support at each step), running (flight between steps), jumping (both feet leave
//! together) and standing (both feet down throughout), at 120 and 30 frames per second, with
//! a few millimetres of capture noise and the floor away from zero.

use articula::motion::contact::{ContactParams, FootPoints, contact_phases, floor_height};
use nalgebra::Vector3;

const FLOOR: f64 = 0.37;

/// A foot that is planted while `(t / cycle + phase) mod 1 < duty`, and otherwise swings
/// forward by `stride` (smooth C² profile) lifting its heel by `lift`. Y up, walking along +Z.
struct Schedule {
    cycle: f64,
    duty: f64,
    phase: f64,
    stride: f64,
    lift: f64,
    x: f64,
}

impl Schedule {
    fn planted(&self, t: f64) -> bool {
        (t / self.cycle + self.phase).rem_euclid(1.0) < self.duty
    }

    /// The heel position at `t` (the toe is 13 cm ahead and 6 cm lower).
    fn heel(&self, t: f64) -> Vector3<f64> {
        let c = t / self.cycle + self.phase;
        let (n, u) = (c.floor(), c.rem_euclid(1.0));
        let (forward, up) = if u < self.duty {
            (0.0, 0.0)
        } else {
            let s = (u - self.duty) / (1.0 - self.duty);
            (
                s * s * s * (10.0 - 15.0 * s + 6.0 * s * s),
                (std::f64::consts::PI * s).sin(),
            )
        };
        Vector3::new(
            self.x,
            FLOOR + 0.08 + self.lift * up,
            (n + forward) * self.stride,
        )
    }
}

/// A deterministic ±`amp` noise (a linear congruential generator).
struct Noise(u64, f64);

impl Noise {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * self.1
    }
    fn vec(&mut self) -> Vector3<f64> {
        Vector3::new(self.next(), self.next(), self.next())
    }
}

/// Paths of the feet over `duration` at `fps`, and the true contact per foot per frame.
fn paths(feet: &[Schedule], fps: f64, duration: f64) -> (Vec<FootPoints>, Vec<Vec<bool>>) {
    let n = (duration * fps) as usize;
    let mut noise = Noise(7, 0.003);
    let toe = Vector3::new(0.0, -0.06, 0.13);
    let mut points = vec![];
    let mut truth = vec![];
    for f in feet {
        let mut p = FootPoints::default();
        let mut c = vec![];
        for k in 0..n {
            let t = k as f64 / fps;
            let heel = f.heel(t);
            p.heel.push(heel + noise.vec());
            p.toe.push(heel + toe + noise.vec());
            c.push(f.planted(t));
        }
        points.push(p);
        truth.push(c);
    }
    (points, truth)
}

/// Frames where detection and truth differ must lie within `tol` seconds of a true transition.
fn check(name: &str, feet: &[Schedule], fps: f64) -> Vec<Vec<bool>> {
    let (points, truth) = paths(feet, fps, 4.0);
    let found = contact_phases(&points, 1, 1.0 / fps, &ContactParams::default());
    let floor = floor_height(&points, 1);
    assert!(
        (floor - (FLOOR + 0.02)).abs() < 0.01,
        "{name}: floor {floor}"
    );
    let tol = (0.08 * fps).ceil() as usize;
    for (j, (f, t)) in found.iter().zip(&truth).enumerate() {
        for k in 0..f.len() {
            if f[k] != t[k] {
                let near = (k.saturating_sub(tol)..(k + tol + 1).min(t.len()))
                    .any(|m| m > 0 && t[m] != t[m - 1]);
                assert!(near, "{name} at {fps} fps: foot {j} frame {k} is {}", f[k]);
            }
        }
    }
    found
}

fn feet(cycle: f64, duty: f64, stride: f64, lift: f64, half: f64) -> [Schedule; 2] {
    [
        Schedule {
            cycle,
            duty,
            phase: 0.0,
            stride,
            lift,
            x: 0.1,
        },
        Schedule {
            cycle,
            duty,
            phase: half,
            stride,
            lift,
            x: -0.1,
        },
    ]
}

#[test]
fn walking_always_has_a_foot_down_and_double_support_at_each_step() {
    for fps in [120.0, 30.0] {
        let c = check("walk", &feet(1.1, 0.62, 1.4, 0.1, 0.5), fps);
        let n = c[0].len();
        assert!((0..n).all(|k| c[0][k] || c[1][k]), "a walk has no flight");
        let double = (0..n).filter(|&k| c[0][k] && c[1][k]).count();
        assert!(
            double as f64 > 0.1 * n as f64,
            "double support {double}/{n}"
        );
    }
}

#[test]
fn running_has_flight_between_steps() {
    for fps in [120.0, 30.0] {
        let c = check("run", &feet(0.7, 0.35, 2.4, 0.25, 0.5), fps);
        let n = c[0].len();
        let flight = (0..n).filter(|&k| !c[0][k] && !c[1][k]).count();
        assert!(flight as f64 > 0.1 * n as f64, "flight {flight}/{n}");
        assert!(
            (0..n).all(|k| !(c[0][k] && c[1][k])),
            "no double support in a run"
        );
    }
}

#[test]
fn jumping_feet_leave_and_land_together() {
    for fps in [120.0, 30.0] {
        let c = check("jump", &feet(0.9, 0.55, 0.5, 0.35, 0.0), fps);
        let n = c[0].len();
        let flight = (0..n).filter(|&k| !c[0][k] && !c[1][k]).count();
        assert!(flight as f64 > 0.25 * n as f64, "flight {flight}/{n}");
    }
}

#[test]
fn standing_keeps_both_feet_down() {
    for fps in [120.0, 30.0] {
        // a duty of 1: never swings
        let c = check("stand", &feet(1.0, 1.0, 0.0, 0.0, 0.0), fps);
        assert!(c.iter().all(|f| f.iter().all(|&x| x)));
    }
}

#[test]
fn a_foot_held_up_never_touches_down() {
    // standing on the left foot, the right foot held 20 cm up and still (a balance pose)
    let fps = 60.0;
    let [left, mut right] = feet(1.0, 1.0, 0.0, 0.0, 0.0);
    right.x = -0.1;
    let (mut points, _) = paths(&[left, right], fps, 3.0);
    let right = &mut points[1];
    for p in right.heel.iter_mut().chain(right.toe.iter_mut()) {
        p.y += 0.2;
    }
    let c = contact_phases(&points, 1, 1.0 / fps, &ContactParams::default());
    assert!(c[0].iter().all(|&x| x));
    assert!(c[1].iter().all(|&x| !x));
}
