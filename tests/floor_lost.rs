//! A take whose capture leaves its floor says so, and a flight does not (issue 14 item 1: every
//! take "says by how much it missed and why").
//!
//! Invariant: over frames in which the feet carry nothing, the vertical force the motion needs
//! averages `m g + m Δċ / T`: zero for a ballistic flight (the centre of mass accelerates at
//! −g), body weight for a body that stays up. The generated walk (a foot always down) is
//! written twice more, both with its root 30 cm up for half a second:
//! - lifted: raised over 0.4 s, held 0.5 s, lowered over 0.4 s, its feet walking in the air
//!   (a capture that drifted up from its floor): the frames off the floor are reported as the
//!   floor lost, with the lowest foot's height and the needed force near body weight, in the
//!   notes and in the `why` of `anatomy --json` and `id --json`, and marked beyond the
//!   thresholds;
//! - jumping: a ballistic flight of 0.5 s (`v₀ = gT/2`, 31 cm high) from one frame to the
//!   next, landing where it left: its feet are as high, yet it is not reported.
//!
//! On the real takes (`ARTICULA_REAL_TAKES=../shared/data/bvh`, ignored by default) no take
//! stands on a floor it leaves: the run's flights and CMU 01_01's jumps are not reported.

mod common;

use articula::io::bvh::{self, Bvh};
use articula::io::generate::{WalkParams, walk};
use articula::pipeline::{self, Contact, TakeOptions, consistency::consistent_take};
use common::cli::{articula, json_of};
use std::path::Path;

const G: f64 = 9.81;
/// When the root leaves its path (s), and how long it stays up (s).
const UP_AT: f64 = 1.4;
const UP_FOR: f64 = 0.5;

/// The C² ramp `10u³ − 15u⁴ + 6u⁵`, `u` clamped to [0, 1].
fn ramp(u: f64) -> f64 {
    let u = u.clamp(0.0, 1.0);
    u * u * u * (10.0 - 15.0 * u + 6.0 * u * u)
}

/// The generated walk (4 s, 120 fps, cm) with `lift(t)` (m) added to its root's height.
fn walk_lifted(lift: impl Fn(f64) -> f64) -> Bvh {
    let mut b = walk(&WalkParams::default());
    let y = b.joints[0]
        .channels
        .iter()
        .position(|c| *c == bvh::Channel::Yposition)
        .unwrap()
        + b.joints[0].first_channel;
    for k in 0..b.frames {
        b.motion[k * b.channel_count + y] += 100.0 * lift(k as f64 * b.frame_time);
    }
    b
}

/// How long the lift takes to rise and to come down (s).
const RAMP_S: f64 = 0.4;

/// How high the lifted walk's root is lifted at time `t` (m): 30 cm, reached over
/// [`RAMP_S`], held for [`UP_FOR`] from [`UP_AT`], lowered over [`RAMP_S`].
fn lift(t: f64) -> f64 {
    0.3 * (ramp((t - UP_AT + RAMP_S) / RAMP_S) - ramp((t - UP_AT - UP_FOR) / RAMP_S))
}

fn lifted() -> Bvh {
    walk_lifted(lift)
}

/// A ballistic flight of [`UP_FOR`] from [`UP_AT`].
fn jumping() -> Bvh {
    let v0 = G * UP_FOR / 2.0;
    walk_lifted(|t| {
        let s = t - UP_AT;
        if (0.0..UP_FOR).contains(&s) {
            v0 * s - 0.5 * G * s * s
        } else {
            0.0
        }
    })
}

fn take_of(b: Bvh) -> pipeline::Take {
    let options = TakeOptions {
        contact: Contact::Feet,
        ..TakeOptions::default()
    };
    let mut t = pipeline::take_from_bvh(Path::new("generated.bvh"), b, &options).unwrap();
    pipeline::resolve_contact(&mut t);
    t
}

#[test]
fn a_root_held_up_off_the_floor_has_left_its_floor() {
    let take = take_of(lifted());
    let (_, g, c) = consistent_take(&take, false, None).unwrap();
    let dt = take.bvh.frame_time;
    assert_eq!(c.floor_lost.len(), 1, "{:?}", c.floor_lost);
    let l = c.floor_lost[0];
    // the held half-second lies inside the run, and the run inside the lift
    let (first, last) = (l.first as f64 * dt, l.last as f64 * dt);
    println!(
        "lifted walk: floor lost {first:.3}–{last:.3} s, lowest foot {:.3}–{:.3} m (median \
         {:.3}), needed {:.2} body weights",
        l.lowest_m.0, l.lowest_m.2, l.lowest_m.1, l.needed_share
    );
    assert!(first > UP_AT - 0.4 && first < UP_AT, "{first}");
    assert!(
        last > UP_AT + UP_FOR && last < UP_AT + UP_FOR + 0.4,
        "{last}"
    );
    // the walk's feet, 30 cm higher: the lowest one at least 20 cm up in the median frame
    assert!(l.lowest_m.1 > 0.2, "{:?}", l.lowest_m);
    // a body held up, not falling: body weight on average, less what the lift's vertical
    // velocity loses from the run's first frame to its last, m Δv / T (the run begins on the
    // way up and ends on the way down; the walk's own bounce is a few cm/s)
    let rate = |t: f64| (lift(t + 1e-6) - lift(t - 1e-6)) / 2e-6;
    let want = 1.0 + (rate(last) - rate(first)) / (G * (last - first));
    println!("lifted walk: m g + m Δv / T = {want:.3} body weights");
    assert!(want < 0.9, "{want}: the run should see the lift turn");
    assert!(
        (l.needed_share - want).abs() < 0.1,
        "{} vs {want}",
        l.needed_share
    );
    // its frames carry no ground force and are the feet's unexplained ones
    for k in l.first..=l.last {
        assert!(g.grf[k].iter().all(|f| f.norm() == 0.0), "frame {k}");
        assert!(c.beyond[k], "frame {k} not marked beyond");
    }
    let note = c.floor_lost_note.as_deref().unwrap();
    assert!(
        note.starts_with("the capture leaves its floor at frames"),
        "{note}"
    );
    assert_eq!(c.why.first().map(String::as_str), Some(note));
}

#[test]
fn a_ballistic_flight_as_high_has_not_left_its_floor() {
    let take = take_of(jumping());
    for reduce in [false, true] {
        let (_, _, c) = consistent_take(&take, reduce, None).unwrap();
        assert!(c.floor_lost.is_empty(), "{:?}", c.floor_lost);
        assert!(c.floor_lost_note.is_none());
        assert!(
            c.why.iter().all(|w| !w.contains("leaves its floor")),
            "{:?}",
            c.why
        );
    }
    // not for want of a flight as high: frames in which the feet carry nothing and stay well
    // off the floor, over which the needed vertical force averages next to nothing
    let (_, g, _) = consistent_take(&take, false, None).unwrap();
    let weight = take.model.total_mass() * G;
    let off: Vec<usize> = (0..g.loaded.len())
        .filter(|&k| g.loaded[k].iter().all(|l| !l) && g.foot_height[k] > 0.1)
        .collect();
    let seconds = off.len() as f64 * take.bvh.frame_time;
    let mean = off.iter().map(|&k| g.wrench[k][g.up]).sum::<f64>() / off.len() as f64;
    println!(
        "jump: {seconds:.3} s off the floor unloaded, needing {:.3} body weights on average",
        mean / weight
    );
    assert!(seconds > 0.2, "{seconds}");
    assert!(mean.abs() < 0.1 * weight, "{}", mean / weight);
}

#[test]
fn anatomy_and_id_say_it_in_their_json_and_notes() {
    let dir = tempfile::tempdir().unwrap();
    let take = dir.path().join("lifted.bvh");
    std::fs::write(&take, bvh::write_string(&lifted())).unwrap();
    for command in ["anatomy", "id"] {
        let out = dir.path().join(format!("{command}.csv"));
        let o = articula()
            .arg(command)
            .arg(&take)
            .args(["--contact", "feet", "--json", "-o"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
        // id's summary holds the consistency under its own key
        let c = if command == "id" {
            &json["consistency"]
        } else {
            &json
        };
        let why = c["why"][0].as_str().unwrap_or_default();
        assert!(
            why.starts_with("the capture leaves its floor"),
            "{command}: {c}"
        );
        let runs = c["floor_lost"].as_array().unwrap();
        assert_eq!(runs.len(), 1, "{command}: {runs:?}");
        assert!(
            runs[0]["lowest_foot_m"][1].as_f64().unwrap() > 0.2,
            "{runs:?}"
        );
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert!(
            stderr.contains("note: the capture leaves its floor"),
            "{command}: {stderr}"
        );
    }
    // the generated walk itself stands on its floor throughout
    let plain = dir.path().join("walk.bvh");
    std::fs::write(&plain, bvh::write_string(&walk(&WalkParams::default()))).unwrap();
    let c = json_of(
        articula()
            .arg("anatomy")
            .arg(&plain)
            .args(["--json", "-o"])
            .arg(dir.path().join("walk.csv")),
    );
    assert_eq!(c["floor_lost"].as_array().map(Vec::len), Some(0), "{c}");
}

#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn no_shared_take_leaves_its_floor_and_no_flight_is_taken_for_it() {
    let mut flights = 0;
    for path in common::real_takes() {
        let Ok(mut take) = pipeline::load_take(&path, &TakeOptions::default()) else {
            continue;
        };
        pipeline::resolve_contact(&mut take);
        if take.options.contact != Contact::Feet {
            continue;
        }
        let (_, g, c) = consistent_take(&take, false, None).unwrap();
        let name = path.file_name().unwrap().to_string_lossy();
        // the frames in flight: no foot in contact (the run's, at 30 fps, all within the
        // estimator's spread of a contact, carry its force)
        let off = g.contact.iter().filter(|c| c.iter().all(|c| !c)).count();
        println!(
            "{name}: {off} frames in flight; floor lost {:?}",
            c.floor_lost
        );
        assert!(c.floor_lost.is_empty(), "{name}: {:?}", c.floor_lost);
        if name.starts_with("cmu_01_01") || name.contains("_run_") {
            assert!(off > 0, "{name}: no flight");
            flights += 1;
        }
    }
    assert_eq!(flights, 2, "the run and the jumps");
}
