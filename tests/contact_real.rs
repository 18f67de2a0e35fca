//! Ground reactions on real captures (run with `ARTICULA_REAL_TAKES=../shared/data/bvh`), each
//! take through the default pipeline (euler model, 75 kg de Leva body, 6 Hz Butterworth):
//! - over a walk the vertical ground force averages body weight (the centre of mass neither
//!   rises nor sinks over whole strides: the mean of m·(g + z̈) is m·g), within 2 %;
//! - with the feet carrying the whole-body wrench, the force left at the root drops by more
//!   than an order of magnitude from the top-down value (where the root carries all of it);
//! - in flight (run, jumps) the feet carry nothing, and away from the take-off and landing
//!   the body is in free fall: the wrench the motion needs is small;
//! - standing, both feet share the weight and the root carries nothing;
//! - the stance knee torque differs from the top-down one (which only swings the shank and
//!   foot) by an order of magnitude, and lies in the range of gait data. Reference: the
//!   sagittal knee moment of Winter 2009 (*Biomechanics and Motor Control of Human Movement*,
//!   4th ed., ch. 5 and appendix A), peaks of about 0.5–1 N·m/kg at natural cadence and
//!   higher at fast cadence. The captures here bounce more than Winter's subjects (vertical
//!   ground force peaks of 1.3–1.5 body weights against 1.1–1.2) and the double supports are
//!   only a few frames long, so their 95th percentiles reach 1.2–1.6 N·m/kg: the bound below is
//!   0.3–2 N·m/kg, which a hanging (top-down) knee, at ~0.1 N·m/kg, fails.
//!
//! Each test prints its measurements (`cargo test --test contact_real -- --nocapture`).

mod common;

use articula::dynamics::grf::GroundReactions;
use articula::dynamics::{Workspace, rnea};
use articula::motion::contact::{ContactParams, feet_of_bvh};
use articula::pipeline::{Take, TakeOptions, estimate_take_ground_reactions, load_take};

const G: f64 = 9.81;

fn load(name: &str) -> Option<(Take, GroundReactions)> {
    let path = common::real_take(name)?;
    let take = load_take(&path, &TakeOptions::default()).unwrap();
    let feet = feet_of_bvh(&take.bvh, &take.map, &take.model);
    assert_eq!(feet.len(), 2, "{name}: feet {feet:?}");
    // what `--contact feet` computes
    let gr = estimate_take_ground_reactions(&take).unwrap();
    Some((take, gr))
}

fn weight(take: &Take) -> f64 {
    take.model.total_mass() * G
}

/// Mean vertical ground force over the take, in body weights.
fn mean_vertical(take: &Take, gr: &GroundReactions) -> f64 {
    let up = take.up.index();
    let sum: f64 = gr.grf.iter().flat_map(|f| f.iter().map(|x| x[up])).sum();
    sum / gr.grf.len() as f64 / weight(take)
}

/// RMS over frames of the force part of a root wrench (N).
fn rms_force(w: &[[f64; 6]]) -> f64 {
    (w.iter()
        .map(|x| x[0] * x[0] + x[1] * x[1] + x[2] * x[2])
        .sum::<f64>()
        / w.len() as f64)
        .sqrt()
}

/// The flexion coordinate of the knee above `foot` (the rotation channel of the foot's parent
/// joint with the largest range over the take).
fn knee_flexion(take: &Take, foot_joint: &str) -> usize {
    let foot = take.bvh.joint_index(foot_joint).unwrap();
    let knee = take.bvh.joints[foot].parent.unwrap();
    let range = |i: usize| {
        let (lo, hi) = take
            .states
            .q
            .iter()
            .fold((f64::MAX, f64::MIN), |(l, h), q| (l.min(q[i]), h.max(q[i])));
        hi - lo
    };
    take.map.joints[knee]
        .channels
        .iter()
        .filter(|c| c.channel.is_rotation())
        .filter_map(|c| c.q)
        .max_by(|a, b| range(*a).total_cmp(&range(*b)))
        .unwrap()
}

/// The 95th percentile of |τ| over the frames where `foot` is in contact (N·m/kg), with and
/// without contact: a peak that one noisy frame cannot set.
fn stance_knee(take: &Take, gr: &GroundReactions, foot: usize, joint: &str) -> (f64, f64) {
    let k_flex = knee_flexion(take, joint);
    let model = &take.model;
    let s = &take.states;
    let mut ws = Workspace::new(model);
    let (mut with, mut without) = (vec![], vec![]);
    for k in (0..s.len()).filter(|&k| gr.contact[k][foot]) {
        with.push(gr.tau[k][k_flex].abs());
        without.push(rnea(model, &mut ws, &s.q[k], &s.v[k], &s.a[k], None)[k_flex].abs());
    }
    let p95 = |mut x: Vec<f64>| {
        x.sort_by(f64::total_cmp);
        x[(x.len() * 95) / 100] / model.total_mass()
    };
    (p95(with), p95(without))
}

fn check_walk(name: &str) {
    let Some((take, gr)) = load(name) else {
        return;
    };
    let mean = mean_vertical(&take, &gr);
    let (none, feet) = (rms_force(&gr.wrench), rms_force(&gr.residual));
    let up = take.up.index();
    let peak = gr
        .grf
        .iter()
        .map(|f| f.iter().map(|x| x[up]).sum::<f64>())
        .fold(0.0, f64::max)
        / weight(&take);
    println!(
        "{name}: mean vertical GRF {mean:.4} BW (peak {peak:.2} BW); root force rms {none:.1} N \
         top-down, {feet:.1} N with the feet"
    );
    assert!((mean - 1.0).abs() < 0.02, "{name}: {mean}");
    assert!(feet < none / 10.0, "{name}: {feet} vs {none}");
    for (j, f) in gr.feet.iter().enumerate() {
        let joint = feet_of_bvh(&take.bvh, &take.map, &take.model)[j]
            .joint
            .clone();
        let (with, without) = stance_knee(&take, &gr, j, &joint);
        println!(
            "{name}: {f} stance knee |τ| p95 {with:.2} N·m/kg with contact, {without:.2} \
             top-down"
        );
        assert!(with > 5.0 * without, "{name} {f}: {with} vs {without}");
        assert!((0.3..2.0).contains(&with), "{name} {f}: {with} N·m/kg");
    }
}

#[test]
fn walk_bandai_carries_body_weight_and_loads_the_stance_knee() {
    check_walk("dataset-1_walk_normal_001.bvh");
}

#[test]
fn walk_meredith_carries_body_weight_and_loads_the_stance_knee() {
    check_walk("AV_8Walk_Meredith_HVHA_Rep1.bvh");
}

/// Flight: frames where no foot is in contact. The feet carry nothing there, except within
/// the estimator's spread of a contact (`ContactParams::spread_s`: the smoothed accelerations
/// move part of a landing's force before touch-down), and only while that force presses; away
/// from contact the body is in free fall and the wrench the motion needs is small. With the
/// feet, the root force drops by more than an order of magnitude.
fn check_flight(name: &str, min_flight: f64, max_mid_flight_bw: f64) {
    let Some((take, gr)) = load(name) else {
        return;
    };
    let up = take.up.index();
    let n = gr.grf.len();
    let dt = take.states.time[1] - take.states.time[0];
    let spread = ContactParams::for_take(&take.options.smooth, dt)
        .unwrap()
        .spread_s;
    let flight: Vec<usize> = (0..n)
        .filter(|&k| gr.contact[k].iter().all(|c| !c))
        .collect();
    // no force unless a foot is loaded, and a foot is loaded in flight only within the spread
    // of its own contact
    let reach = (spread / dt).round() as usize;
    for &k in &flight {
        for (j, f) in gr.grf[k].iter().enumerate() {
            if !gr.loaded[k][j] {
                assert_eq!(f.norm(), 0.0, "{name} frame {k}");
            } else {
                let near =
                    (k.saturating_sub(reach)..=(k + reach).min(n - 1)).any(|i| gr.contact[i][j]);
                assert!(
                    near,
                    "{name} frame {k}: foot {j} loaded far from its contact"
                );
                assert!(f[up] >= 0.0, "{name} frame {k}");
            }
        }
    }
    let m = reach.max((0.05 / dt).ceil() as usize);
    let mid: Vec<usize> = flight
        .iter()
        .copied()
        .filter(|&k| {
            k >= m && k + m < n && (k - m..=k + m).all(|j| gr.contact[j].iter().all(|c| !c))
        })
        .collect();
    for &k in &mid {
        assert!(
            gr.grf[k].iter().all(|f| f.norm() == 0.0),
            "{name} frame {k}"
        );
    }
    let needed = mid.iter().map(|&k| gr.wrench[k][up]).sum::<f64>()
        / mid.len().max(1) as f64
        / weight(&take);
    let stance = |k: usize| gr.grf[k].iter().map(|f| f[up]).sum::<f64>() / weight(&take);
    let peak = (0..n).map(stance).fold(0.0, f64::max);
    let in_flight = flight.iter().map(|&k| stance(k)).sum::<f64>() / flight.len().max(1) as f64;
    let (none, feet) = (rms_force(&gr.wrench), rms_force(&gr.residual));
    println!(
        "{name}: {} flight frames of {n} (spread {spread:.3} s), {} of them beyond it from \
         contact with mean needed vertical force {needed:.3} BW; mean vertical GRF in flight \
         {in_flight:.3} BW, peak {peak:.2} BW; root force rms {none:.1} N top-down, {feet:.1} N \
         with the feet ({:.1}×)",
        flight.len(),
        mid.len(),
        none / feet
    );
    assert!(flight.len() as f64 >= min_flight * n as f64, "{name}");
    assert!(needed.abs() < max_mid_flight_bw, "{name}: {needed}");
    assert!(feet < none / 10.0, "{name}: {feet} vs {none}");
}

#[test]
fn run_has_flight_without_ground_force() {
    // 24 frames at 30 fps: flights of 3–4 frames, all within the estimator's spread (0.1 s at
    // 30 fps) of a contact, so there is no mid-flight frame to test for free fall
    check_flight("dataset-1_run_normal_001.bvh", 0.2, 1.0);
}

#[test]
fn jumps_have_flight_in_free_fall() {
    check_flight("cmu_01_01.bvh", 0.1, 0.15);
}

#[test]
fn standing_shares_the_weight_and_leaves_nothing_at_the_root() {
    let Some((take, gr)) = load("dataset-1_bye_old_001.bvh") else {
        return;
    };
    let n = gr.grf.len();
    let both = (0..n).filter(|&k| gr.contact[k].iter().all(|c| *c)).count();
    let mean = mean_vertical(&take, &gr);
    let feet = rms_force(&gr.residual);
    println!(
        "standing: both feet down in {both} of {n} frames; mean vertical GRF {mean:.4} BW; \
         root force rms {:.1} N top-down, {feet:.2} N with the feet",
        rms_force(&gr.wrench)
    );
    assert!(both as f64 > 0.9 * n as f64);
    assert!((mean - 1.0).abs() < 0.02);
    assert!(feet < 0.01 * weight(&take));
}
