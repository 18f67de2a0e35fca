//! Contact on takes that are not an overground walk (issue 14, "feet and floor on any biped"):
//! - the same walk on a treadmill (the root's mean horizontal velocity taken out, as a game's
//!   in-place cycle is written: the planted foot slides back at the walking speed) or as it
//!   goes on a 1 m/s belt finds the same stance in every frame and gives the same joint moments
//!   in every frame (to 1e-9 of their peak; measured ≤ 2e-9 N·m, rounding): a floor moving at a
//!   constant velocity is an inertial frame. Nothing is spared at the ends: the smoothing's odd
//!   padding carries the drift's straight line through them unchanged (the foot paths of the
//!   Bandai walk and its variants differ by the drift to 3e-15 m in every frame), and the
//!   floor's velocity is found from the feet alone, by a rule that moves with the floor
//!   (`motion::contact::belt_velocity`: the planted feet's cluster, never tested against the
//!   world's rest; once a still floor over ground and the feet's skate added to a belt, which
//!   put 2–98 frames in another stance on the CMU dance 05_20, the Bandai run and the
//!   pirouette), and the legs are the skeleton's wherever it stands (a foot with several toe
//!   chains once took its toe from the rounding of its joints' positions,
//!   `tests/skeleton_topology.rs`); and after residual reduction, which holds the take's
//!   contact phases and floor, the same moments to 1e-6 of their peak (the demo walk);
//! - a take on which no foot is ever planted (the body rising through the air) is an error with
//!   `--contact feet`, and `--contact auto` settles on none and says why.
//!
//! Generated from the demo walk and, with `ARTICULA_REAL_TAKES`, from every shared take that
//! stands on a floor.

mod common;

use articula::io::bvh::{self, Bvh, Channel};
use articula::pipeline::{self, Contact, Take, TakeOptions};
use std::path::Path;

/// Both joint models: the euler model's root is three prismatic joints along the world axes,
/// the ball model's a free joint whose linear velocity is differenced along its path in the
/// world (`pipeline::derivatives`); either way a drift taken out of the root's position
/// changes no joint torque. (Differenced on SE(3), as the ball model once was, a straight line
/// with a turning body is not a constant twist: the Bandai walk's knee moved 4.8 N·m at 30 fps
/// on a 1.25 m/s belt, AV_8Walk's spine 0.7 N·m on a 2.5 m/s one.)
const JOINTS: [&str; 2] = ["euler", "ball"];

fn opts_with(contact: Contact, joints: &str) -> TakeOptions {
    TakeOptions {
        joints: joints.parse().unwrap(),
        contact,
        ..TakeOptions::default()
    }
}

fn opts(contact: Contact) -> TakeOptions {
    opts_with(contact, "ball")
}

fn load(path: &Path, b: Bvh, contact: Contact) -> Result<Take, articula::error::Error> {
    pipeline::take_from_bvh(path, b, &opts(contact))
}

/// The root's position channel along world axis `axis` (0, 1, 2), if it has one.
fn root_position(b: &Bvh, axis: usize) -> Option<usize> {
    let want = [Channel::Xposition, Channel::Yposition, Channel::Zposition][axis];
    let root = &b.joints[0];
    let i = root.channels.iter().position(|c| *c == want)?;
    Some(root.first_channel + i)
}

/// `b` with `f(axis, frame)` (file units) added to the root's position channel along each axis.
fn moved(b: &Bvh, f: impl Fn(usize, usize) -> f64) -> Bvh {
    let mut out = b.clone();
    for axis in 0..3 {
        if let Some(c) = root_position(b, axis) {
            for k in 0..b.frames {
                out.motion[k * b.channel_count + c] += f(axis, k);
            }
        }
    }
    out
}

/// The floors a walk is tried on.
#[derive(Debug, Clone, Copy)]
enum Floor {
    /// The walk's own mean horizontal velocity taken out of every frame, as a treadmill or a
    /// game's in-place cycle has it; where that leaves the floor nearly still (a walk around a
    /// figure 8 goes nowhere on the whole), a belt of 1 m/s along the first horizontal axis
    /// instead.
    InPlace,
    /// The walk as it goes, on a belt of 1 m/s along the first horizontal axis.
    Belt,
}

impl Floor {
    const ALL: [Floor; 2] = [Floor::InPlace, Floor::Belt];

    fn name(self) -> &'static str {
        match self {
            Floor::InPlace => "in place",
            Floor::Belt => "on a 1 m/s belt",
        }
    }
}

/// `b` walked on `floor`: a drift added to the top joint's position channels (every joint
/// below moves with them, a helper root's as well as a pelvis's). The walk's travel is read
/// from `ground`'s root path in the world (m), not from the top joint's channels, which on a
/// rig with a helper root carry nothing: the Bandai walk's `joint_Root` has six channels at
/// zero and its `Hips` carry the travel. (Read from there, the travel came out zero and the
/// walk "in place" was the walk going on at 1.25 m/s over a 1 m/s belt: now [`Floor::Belt`].)
fn on_floor(b: &Bvh, ground: &Take, floor: Floor) -> Bvh {
    let (s, up, to_file) = (&ground.states, ground.up.index(), 1.0 / ground.scale_to_m);
    let n = s.len();
    let mut drift = [0.0; 3];
    if let Floor::InPlace = floor {
        for axis in (0..3).filter(|&a| a != up) {
            drift[axis] = (s.q[n - 1][axis] - s.q[0][axis]) / (n - 1) as f64 * to_file;
        }
    }
    let speed = drift.iter().map(|d| d * d).sum::<f64>().sqrt() / to_file / b.frame_time;
    if speed < 0.5 {
        drift[(up + 1) % 3] += 1.0 * to_file * b.frame_time;
    }
    moved(b, |axis, k| -drift[axis] * k as f64)
}

/// [`check_treadmill_with`] on both joint models and every [`Floor`].
fn check_treadmill(path: &Path) {
    for joints in JOINTS {
        for floor in Floor::ALL {
            check_treadmill_with(path, joints, floor);
        }
    }
}

/// The take and its variant on `floor` find the same feet on the floor in every frame, and the
/// same hip and knee moments in every frame.
fn check_treadmill_with(path: &Path, joints: &str, floor: Floor) {
    let b = bvh::read(path).unwrap();
    let load = |b: Bvh| pipeline::take_from_bvh(path, b, &opts_with(Contact::Feet, joints));
    let ground = load(b.clone()).unwrap();
    let up = ground.up.index();
    let speed = {
        let s = &ground.states;
        let n = s.len();
        let p = |k: usize| {
            let mut x = nalgebra::Vector3::from_column_slice(&s.q[k][0..3]);
            x[up] = 0.0;
            x
        };
        (p(n - 1) - p(0)).norm() / (s.time[n - 1] - s.time[0])
    };
    let belt = load(on_floor(&b, &ground, floor)).unwrap();
    let (g0, g1) = (
        pipeline::ground_reactions(&ground).unwrap().unwrap(),
        pipeline::ground_reactions(&belt).unwrap().unwrap(),
    );
    let n = g0.contact.len();
    let same = (0..n).filter(|&k| g0.contact[k] == g1.contact[k]).count();
    let place = floor.name();
    eprintln!(
        "{} ({joints}): walking at {speed:.2} m/s; {place} {same} of {n} frames have the same \
         feet on the floor",
        path.display()
    );
    assert_eq!(
        same,
        n,
        "{}: {place} only {same} of {n} frames find the same stance",
        path.display()
    );
    // the joint moments, frame by frame
    let (a0, a1) = (
        pipeline::anatomy::anatomy(&ground).unwrap(),
        pipeline::anatomy::anatomy(&belt).unwrap(),
    );
    for joint in ["knee_l", "knee_r", "hip_l", "hip_r"] {
        let name = format!("{joint}:flexion:moment");
        let (m0, m1) = (a0.column(&name).unwrap(), a1.column(&name).unwrap());
        let peak = m0.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let worst = (0..n)
            .map(|k| ((m0[k] - m1[k]).abs(), k))
            .fold((0.0, 0), |a, b| if b.0 > a.0 { b } else { a });
        eprintln!(
            "  {name}: largest difference {:.2e} N·m at frame {} (peak {peak:.1})",
            worst.0, worst.1
        );
        let worst = worst.0;
        assert!(
            worst <= 1e-9 * peak,
            "{}: {name} differs by {worst:.2} N·m {place} (peak {peak:.1} N·m)",
            path.display()
        );
    }
}

#[test]
fn the_demo_walk_on_a_treadmill_stands_as_it_does_over_ground() {
    check_treadmill(&common::repo("data/demo_walk.bvh"));
}

/// Residual reduction holds the take's contact phases and the floor it stands on
/// (`dynamics::grf::Held`): the demo walk reduced in place, on a 1 m/s belt and on a floor
/// creeping at 0.1 mm/s gives the knee and hip moments, and the residuals, it gives reduced
/// over ground. Before, each trial found the phases again against a floor found again from
/// its own feet, and the reduction was discontinuous in the floor: the left knee's reduced
/// peak (`articula anatomy --mass 80 --sex female`) was 1.94 N·m/kg over ground and 1.78 on
/// the creeping floor, the RMS residual moment 0.38 % and 0.41 %, and 0.20 % on the belt
/// (now the moments within 4e-6 N·m of each other at every frame, the RMS within 2e-8 N·m).
#[test]
fn the_demo_walk_reduced_on_any_floor_gives_what_it_gives_over_ground() {
    use articula::pipeline::consistency::anatomy_consistent;
    let path = common::repo("data/demo_walk.bvh");
    let b = bvh::read(&path).unwrap();
    for joints in JOINTS {
        let load =
            |b: Bvh| pipeline::take_from_bvh(&path, b, &opts_with(Contact::Feet, joints)).unwrap();
        let ground = load(b.clone());
        let (up, to_file) = (ground.up.index(), 1.0 / ground.scale_to_m);
        let creep = moved(&b, |axis, k| {
            let per_frame = if axis == (up + 1) % 3 { 1e-4 } else { 0.0 };
            -per_frame * to_file * b.frame_time * k as f64
        });
        let a0 = anatomy_consistent(&ground, true).unwrap();
        let c0 = a0.consistency.as_ref().unwrap().after.unwrap();
        for (place, variant) in [
            ("in place", on_floor(&b, &ground, Floor::InPlace)),
            ("on a 1 m/s belt", on_floor(&b, &ground, Floor::Belt)),
            ("on a floor creeping at 0.1 mm/s", creep),
        ] {
            let a1 = anatomy_consistent(&load(variant), true).unwrap();
            let c1 = a1.consistency.as_ref().unwrap().after.unwrap();
            let rms = (c0.rms_moment_nm, c1.rms_moment_nm);
            eprintln!("{joints} {place}: RMS residual moment {rms:?} N·m");
            assert!(
                (rms.0 - rms.1).abs() <= 1e-6 * rms.0,
                "{joints} {place}: {rms:?}"
            );
            for joint in ["knee_l", "knee_r", "hip_l", "hip_r"] {
                let name = format!("{joint}:flexion:moment");
                let (m0, m1) = (a0.column(&name).unwrap(), a1.column(&name).unwrap());
                let peak = m0.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                let worst = m0
                    .iter()
                    .zip(m1.iter())
                    .fold(0.0f64, |w, (x, y)| w.max((x - y).abs()));
                eprintln!("  {name}: largest difference {worst:.2e} N·m (peak {peak:.1})");
                assert!(
                    worst <= 1e-6 * peak,
                    "{joints} {place}: {name} differs by {worst:.3} N·m (peak {peak:.1} N·m)"
                );
            }
        }
    }
}

#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn every_shared_take_that_stands_on_a_floor_stands_the_same_on_a_treadmill() {
    // every shared take whose feet stand on a floor (`--contact auto` settles on feet) and
    // whose skeleton is a human's (the hip and knee moments compared are anatomical)
    let mut tried = vec![];
    for path in common::real_takes() {
        let b = bvh::read(&path).unwrap();
        let mut take = load(&path, b, Contact::Auto).unwrap();
        pipeline::resolve_contact(&mut take);
        if take.options.contact != Contact::Feet || take.human.is_err() {
            continue;
        }
        check_treadmill(&path);
        tried.push(path.file_name().unwrap().to_string_lossy().into_owned());
    }
    // among them the walks of the first tests, and those on which the floor's velocity was
    // found with the planted feet's skate on a belt and without it over ground (the CMU
    // dance 05_20 in both conversions: 998 and 1036 of 1096 frames in place; the Bandai run:
    // 20 of 24 on a belt; the pirouette: 591 of 592)
    for name in [
        "AV_8Walk_Meredith_HVHA_Rep1.bvh",
        "dataset-1_walk_normal_001.bvh",
        "cmu_05_20-daz.bvh",
        "cmu_05_20-mb.bvh",
        "dataset-1_run_normal_001.bvh",
        "pirouette.bvh",
    ] {
        assert!(
            tried.iter().any(|t| t == name),
            "{name} not tried: {tried:?}"
        );
    }
}

#[test]
fn a_take_whose_feet_never_touch_a_floor_says_so() {
    let path = common::repo("data/demo_walk.bvh");
    let b = bvh::read(&path).unwrap();
    let up = load(&path, b.clone(), Contact::None).unwrap().up.index();
    // rising at 1.5 m/s (file units: the demo walk is in cm): no foot is ever still
    let dt = b.frame_time;
    let flying = moved(&b, |axis, k| {
        if axis == up {
            150.0 * k as f64 * dt
        } else {
            0.0
        }
    });

    let feet = load(&path, flying.clone(), Contact::Feet).unwrap();
    let e = pipeline::ground_reactions(&feet).unwrap_err().to_string();
    assert!(e.contains("no foot is ever planted on a floor"), "{e}");
    assert!(e.contains("--contact none"), "{e}");

    let mut auto = load(&path, flying, Contact::Auto).unwrap();
    pipeline::resolve_contact(&mut auto);
    assert_eq!(auto.options.contact, Contact::None);
    let note = auto
        .notes
        .iter()
        .find(|n| n.starts_with("contact auto"))
        .unwrap();
    assert!(
        note.contains("contact auto: none: no foot is ever planted"),
        "{note}"
    );
    assert!(pipeline::ground_reactions(&auto).unwrap().is_none());
    // `export grf` says why it has nothing to write: auto's reason, not advice to add
    // `--contact feet`, which the take refuses (no foot is ever planted)
    let out = tempfile::tempdir().unwrap();
    let e = pipeline::formats::export_grf(
        &auto,
        &out.path().join("grf.csv"),
        pipeline::formats::TableFormat::Csv,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("contact auto chose none: no foot is ever planted"),
        "{e}"
    );
    assert!(!e.contains("--contact feet"), "{e}");

    // the walk itself stands
    let mut walk = load(&path, b, Contact::Auto).unwrap();
    pipeline::resolve_contact(&mut walk);
    assert_eq!(walk.options.contact, Contact::Feet);
    assert!(
        walk.notes
            .iter()
            .any(|n| n.starts_with("contact auto: feet:"))
    );
}

#[test]
fn feet_without_toe_joints_and_unfamiliar_names_find_their_stance() {
    // the demo walk with its toe joints cut to End Sites and every joint renamed J0, J1, …: the
    // feet are the shape's (model::skeleton), their toe points the End Sites
    let path = common::repo("data/demo_walk.bvh");
    let b = bvh::read(&path).unwrap();
    let cut = common::variants::without_leaf_joint(
        &common::variants::without_leaf_joint(&b, "LeftToeBase"),
        "RightToeBase",
    );
    let strange = common::variants::renamed(&cut);
    assert!(strange.joints.iter().all(|j| !j.name.contains("Toe")));
    let g0 = pipeline::ground_reactions(&load(&path, b, Contact::Feet).unwrap())
        .unwrap()
        .unwrap();
    let mut t = load(&path, strange, Contact::Auto).unwrap();
    pipeline::resolve_contact(&mut t);
    assert_eq!(t.options.contact, Contact::Feet, "{:?}", t.notes);
    let g1 = pipeline::ground_reactions(&t).unwrap().unwrap();
    let n = g0.contact.len();
    for (j, foot) in g0.feet.iter().enumerate() {
        let k1 = g1.feet.iter().position(|f| f == foot).unwrap_or(j);
        let same = (0..n)
            .filter(|&k| g0.contact[k][j] == g1.contact[k][k1])
            .count();
        let on = (0..n).filter(|&k| g1.contact[k][k1]).count();
        eprintln!("{foot}: {same} of {n} frames agree, {on} on the floor");
        assert!(same as f64 >= 0.9 * n as f64, "{foot}: {same} of {n}");
        assert!(
            on as f64 >= 0.4 * n as f64,
            "{foot}: {on} of {n} on the floor"
        );
    }
}
