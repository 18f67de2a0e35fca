//! Residual reduction (issue 14 item 4; OpenSim's RRA, Delp et al. 2007): the trunk's mass
//! centre, a smooth pelvis offset and rotation (and the mass, against measured forces) adjusted so that the root residuals fall within Hicks et
//! al.'s 2015 thresholds (peak force ≤ 5 % of the peak external force, RMS moment ≤ 1 % of COM
//! height × peak external force).
//!
//! Invariants tested: a trunk mass centre moved by a known offset in a take made consistent is
//! found again (the reduction moves it back) and the residuals fall back within the
//! thresholds; a uniform change of mass changes no residual percentage (why RRA's mass
//! adjustment has nothing to find when the ground reactions are estimated from the motion);
//! every shared walk and run either meets the thresholds after reduction or says by how much it
//! missed and why.

mod common;

use articula::dynamics::residual::with_trunk_offset;
use articula::pipeline::consistency::{anatomy_consistent, consistent_take, trunk_bodies};
use articula::pipeline::{self, Contact, Take, TakeOptions};
use articula::spatial::SpatialInertia;
use nalgebra::Vector3;
use std::path::Path;

fn opts() -> TakeOptions {
    TakeOptions {
        joints: "ball".parse().unwrap(),
        contact: Contact::Feet,
        ..TakeOptions::default()
    }
}

fn demo() -> Take {
    pipeline::load_take(&common::repo("data/demo_walk.bvh"), &opts()).unwrap()
}

#[test]
fn the_demo_walk_meets_hicks_thresholds_after_reduction_and_not_before() {
    let (adjusted, _, c) = consistent_take(&demo(), true, None).unwrap();
    let after = c.after.unwrap();
    eprintln!("{}", c.text());
    assert!(!c.before.meets(), "{:?}", c.before);
    assert!(after.meets(), "{}", c.text());
    assert!(after.rms_moment_nm < 0.5 * c.before.rms_moment_nm);
    // the adjustments keep within their bounds
    let a = c.adjustments.unwrap();
    assert!(a.trunk_offset_m.norm() <= a.bounds.trunk_com_m + 1e-12);
    assert!(a.pelvis_peak_m <= a.bounds.pelvis_peak_m + 1e-12);
    assert!(a.pelvis_rms_m <= a.bounds.pelvis_rms_m + 1e-12);
    assert!(a.pelvis_peak_m > 0.0 && a.trunk_offset_m.norm() > 0.0);
    assert!(adjusted.is_some());
    assert!(c.why.is_empty());
}

#[test]
fn a_trunk_mass_centre_moved_3_cm_forward_is_found_again() {
    // the demo walk made consistent is the truth; its trunk's mass centre moved 3 cm along the
    // walk in the model used for estimation (the ball model's root position is q[0..3], world)
    let (truth, _, c0) = consistent_take(&demo(), true, None).unwrap();
    let truth = truth.unwrap();
    let trunk = trunk_bodies(&truth);
    assert!(!trunk.is_empty());
    let (q0, q1) = (&truth.states.q[0], truth.states.q.last().unwrap());
    let up = truth.up.index();
    let forward = [(up + 1) % 3, (up + 2) % 3]
        .into_iter()
        .max_by(|&a, &b| (q1[a] - q0[a]).abs().total_cmp(&(q1[b] - q0[b]).abs()))
        .unwrap();
    let moved = Vector3::ith(forward, 0.03);
    let mut wrong = truth.clone();
    wrong.model = with_trunk_offset(&truth.model, &trunk, &moved);
    let (_, _, c) = consistent_take(&wrong, true, None).unwrap();
    let after = c.after.unwrap();
    let found = c.adjustments.as_ref().unwrap().trunk_offset_m;
    let truth_rms = c0.after.unwrap().rms_moment_nm;
    eprintln!(
        "axis {forward}: residual moment {:.1} → {:.1} N·m (truth {truth_rms:.1}); offset found \
         {:?} cm",
        c.before.rms_moment_nm,
        after.rms_moment_nm,
        found * 100.0
    );
    assert!(c.before.rms_moment_nm > 1.1 * truth_rms);
    assert!(
        after.rms_moment_nm < c.before.rms_moment_nm && after.meets(),
        "{}",
        c.text()
    );
    // moved back along the walk by at least half the move, within the bound. Not closer: the
    // residual is flat in the trunk's mass centre (3 cm raise it by only a third), and with the
    // double supports' ramps (grf::transitions) the fit lands 1.8 cm past the truth, where the
    // residual is lower than the truth's own (5.1 vs 6.1 N·m)
    assert!(
        (-0.05..=-0.015).contains(&found[forward]),
        "found {found:?} for a 3 cm move along axis {forward}"
    );
}

#[test]
fn a_uniform_change_of_mass_changes_no_residual_percentage() {
    let take = demo();
    let (_, _, c) = consistent_take(&take, false, None).unwrap();
    let mut heavy = take.clone();
    for i in heavy.model.inertia.iter_mut() {
        *i = SpatialInertia::new(i.mass * 1.02, i.com, i.inertia_com * 1.02);
    }
    let (_, _, h) = consistent_take(&heavy, false, None).unwrap();
    assert!((h.before.peak_external_n / c.before.peak_external_n - 1.02).abs() < 1e-9);
    assert!((h.before.moment_pct() - c.before.moment_pct()).abs() < 1e-9);
    assert!((h.before.force_pct() - c.before.force_pct()).abs() < 1e-9);
    assert!(c.after.is_none() && c.adjustments.is_none());
}

/// Metamorphic: a body whose every mass is scaled alike (60 → 100 kg by de Leva's fixed
/// fractions) needs the same adjustments, and its reduced joint torques scale exactly. A knee
/// study across body weights then compares like with like; an absolute "met" threshold in N·m
/// once made the two reductions take different steps (the demo's knee 4 % off the ratio).
/// Equal to the solver's tolerance, not to rounding: a Gauss–Newton step is kept when the
/// cost falls, and where two costs agree to rounding the two masses may keep different ones
/// (1e-6 m, 1e-6 of the peak torque).
#[test]
fn a_body_scaled_alike_is_reduced_by_the_same_adjustments() {
    // the workbench study's settings (tests/session_replay.rs): euler joints, a Gaussian,
    // de Leva's fractions at 60 and 100 kg
    let load = |mass_kg: f64| {
        let mut options = TakeOptions {
            contact: Contact::Feet,
            smooth: Some("gaussian:0.02".parse().unwrap()),
            ..TakeOptions::default()
        };
        options.body.mass_kg = mass_kg;
        options.body.segments = "fractions".parse().unwrap();
        pipeline::load_take(&common::repo("data/demo_walk.bvh"), &options).unwrap()
    };
    let (take, heavy) = (load(60.0), load(100.0));
    let (light_take, _, l) = consistent_take(&take, true, None).unwrap();
    let (heavy_take, _, h) = consistent_take(&heavy, true, None).unwrap();
    let (la, ha) = (l.adjustments.unwrap(), h.adjustments.unwrap());
    assert!(
        (la.trunk_offset_m - ha.trunk_offset_m).norm() < 1e-6,
        "{la:?} vs {ha:?}"
    );
    assert!((la.pelvis_peak_m - ha.pelvis_peak_m).abs() < 1e-6);
    assert!((la.pelvis_rms_m - ha.pelvis_rms_m).abs() < 1e-6);
    let (lt, ht) = (light_take.unwrap(), heavy_take.unwrap());
    let (lg, hg) = (
        pipeline::ground_reactions(&lt).unwrap().unwrap(),
        pipeline::ground_reactions(&ht).unwrap().unwrap(),
    );
    let peak = lg.tau.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    for (a, b) in lg.tau.iter().zip(&hg.tau) {
        for (x, y) in a.iter().zip(b) {
            assert!((y - x * 5.0 / 3.0).abs() < 1e-6 * peak, "{x} vs {y}");
        }
    }
}

#[test]
fn the_anatomy_csv_carries_the_residual_per_frame() {
    let a = anatomy_consistent(&demo(), true).unwrap();
    let c = a.consistency.as_ref().unwrap();
    assert_eq!(c.force_n.len(), a.time.len());
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("a.csv");
    pipeline::anatomy::write_anatomy(&a, &out).unwrap();
    let (h, cols) = articula::report::csv::read_columns(&out).unwrap();
    for name in ["residual:force", "residual:moment", "residual:beyond"] {
        let i = h.iter().position(|x| x == name).unwrap();
        assert_eq!(cols[i].len(), a.time.len());
    }
    assert!(pipeline::anatomy::summary(&a).contains("consistency after residual reduction"));
}

/// Residual reduction holds the contact phases of the take as loaded (`dynamics::grf::Held`),
/// as OpenSim's RRA holds its measured forces: the reduced estimate, and an estimate made again
/// on the adjusted take (as the workbench's later stages make it), load the feet in the frames
/// the take as loaded does, in both joint models. Before, each trial found them again from
/// feet its pelvis offset had moved by centimetres: four of the demo walk's phases began or
/// ended a frame apart after reduction, and the reduction's cost jumped between neighbouring
/// trials (with the floor's velocity found from the feet, `knee_load.session`'s peak was
/// 155.1 N·m under a still floor and 142.5 under one moving at 0.1 mm/s).
#[test]
fn reduction_holds_the_contact_phases_of_the_take_as_loaded() {
    for joints in ["ball", "euler"] {
        let o = TakeOptions {
            joints: joints.parse().unwrap(),
            ..opts()
        };
        let take = pipeline::load_take(&common::repo("data/demo_walk.bvh"), &o).unwrap();
        assert_same_phases_after_reduction(&take);
    }
}

fn assert_same_phases_after_reduction(take: &Take) {
    let (_, before, _) = consistent_take(take, false, None).unwrap();
    let (adjusted, after, c) = consistent_take(take, true, None).unwrap();
    let adjusted = adjusted.unwrap();
    // the pelvis offset moved the feet, by more than a contact test's tolerance per frame
    let slide = c.adjustments.unwrap().stance_slide_m;
    assert!(slide > 0.01, "{slide} m");
    let name = take.path.display();
    assert_eq!(after.contact, before.contact, "{name}");
    let again = pipeline::estimate_take_ground_reactions(&adjusted).unwrap();
    assert_eq!(again.contact, before.contact, "{name}");
    assert!(before.contact.iter().flatten().any(|&c| c));
}

/// The same on the shared walks and run, in both joint models: before, Bandai's walk's right
/// stance began at frame 154 in the ball model after reduction and at 155 in the euler model.
#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn reduction_holds_the_contact_phases_of_every_shared_walk_and_run() {
    let takes = shared_walks_and_runs();
    for p in takes {
        for joints in ["ball", "euler"] {
            let o = TakeOptions {
                joints: joints.parse().unwrap(),
                ..opts()
            };
            assert_same_phases_after_reduction(&pipeline::load_take(&p, &o).unwrap());
        }
    }
}

/// The shared takes named as walks or runs (at least four).
fn shared_walks_and_runs() -> Vec<std::path::PathBuf> {
    let takes: Vec<_> = common::real_takes()
        .into_iter()
        .filter(|p| {
            let n = p.file_name().unwrap().to_string_lossy().to_lowercase();
            n.contains("walk") || n.contains("run")
        })
        .collect();
    assert!(takes.len() >= 4, "{takes:?}");
    takes
}

#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn every_shared_walk_and_run_meets_the_thresholds_or_says_by_how_much_it_missed() {
    let takes = shared_walks_and_runs();
    for p in takes {
        let take = pipeline::load_take(&p, &opts()).unwrap();
        let a = anatomy_consistent(&take, true).unwrap();
        let c = a.consistency.unwrap();
        let after = c.after.unwrap();
        eprintln!("{}\n{}", p.display(), c.text());
        assert!(
            after.moment_pct() <= c.before.moment_pct() + 1e-9,
            "{}: reduction raised the residual moment",
            p.display()
        );
        if !after.meets() {
            assert!(
                c.why.iter().any(|w| w.contains("× the")),
                "{}: misses without saying by how much: {:?}",
                p.display(),
                c.why
            );
            assert!(
                c.beyond.iter().any(|b| *b),
                "{}: no frame marked",
                p.display()
            );
        }
    }
}

/// The shared captured walks and run that reduction brings within Hicks et al.'s thresholds
/// (Bandai's walk and run, 30 fps; AV_8Walk, 120 fps, with the pelvis offset refined near its
/// foot changes) meet them with the ball joints `articula anatomy` uses, every adjustment
/// within OpenSim's RRA bounds, and say nothing is missing. MakeHuman's walk1 still misses
/// (docs/residual-reduction.md says why, with numbers); the test above asks it to say by how
/// much.
#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn the_shared_bandai_walk_and_run_and_av_8walk_meet_hicks_thresholds_after_reduction() {
    for (name, refined) in [
        ("dataset-1_walk_normal_001.bvh", false),
        ("dataset-1_run_normal_001.bvh", false),
        ("AV_8Walk_Meredith_HVHA_Rep1.bvh", true),
    ] {
        let take = pipeline::load_take(&common::real_take(name), &opts()).unwrap();
        let a = anatomy_consistent(&take, true).unwrap();
        let c = a.consistency.unwrap();
        let after = c.after.as_ref().unwrap();
        eprintln!("{name}\n{}", c.text());
        assert!(
            !c.before.meets(),
            "{name}: met before reduction: {:?}",
            c.before
        );
        assert!(after.meets(), "{name}: {}", c.text());
        assert!(c.why.is_empty(), "{name}: {:?}", c.why);
        let adj = c.adjustments.as_ref().unwrap();
        let b = &adj.bounds;
        assert!(adj.trunk_offset_m.norm() <= b.trunk_com_m + 1e-12, "{name}");
        assert!(adj.pelvis_peak_m <= b.pelvis_peak_m + 1e-12, "{name}");
        assert!(adj.pelvis_rms_m <= b.pelvis_rms_m + 1e-12, "{name}");
        let (peak, rms) = adj.rotation_peak_rms_rad.expect("the ball root is rotated");
        assert!(peak <= b.rotation_peak_rad + 1e-12, "{name}");
        assert!(rms <= b.rotation_rms_rad + 1e-12, "{name}");
        // the refinement near the foot changes runs only where the smooth adjustments miss,
        // on knots at least three frames apart
        assert_eq!(
            adj.refined_knot_spacing_s.is_some(),
            refined,
            "{name}: {adj:?}"
        );
        if let Some(h) = adj.refined_knot_spacing_s {
            assert!(
                h >= 3.0 * take.bvh.frame_time - 1e-12 && h < b.knot_spacing_s,
                "{name}: {h}"
            );
        }
    }
}

/// MakeHuman's walk1 (24 fps, 14 frames, keyframed in place) misses even refined: its knots
/// cannot be closer than three frames, which the smooth offset's already are. The reduction
/// must still lower its residual moment by more than half and say by how much it missed.
#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn makehuman_walk1_is_reduced_by_more_than_half_and_says_by_how_much_it_missed() {
    let take = pipeline::load_take(&common::real_take("makehuman_walk1.bvh"), &opts()).unwrap();
    let a = anatomy_consistent(&take, true).unwrap();
    let c = a.consistency.unwrap();
    let after = c.after.as_ref().unwrap();
    eprintln!("{}", c.text());
    assert!(
        after.moment_pct() < 0.5 * c.before.moment_pct(),
        "{}",
        c.text()
    );
    assert!(!after.meets());
    assert!(c.why.iter().any(|w| w.contains("× the")), "{:?}", c.why);
}

use common::workbench;

#[test]
fn the_workbench_reduces_with_contact_unless_told_not_to_and_says_so() {
    let out = tempfile::tempdir().unwrap();
    let mut wb = workbench::wb_in(out.path());
    workbench::ok(&mut wb, "load demo:walk as walk");
    workbench::ok(&mut wb, "set contact feet");
    let on = workbench::ok(&mut wb, "run id");
    assert!(on.contains("consistency after residual reduction"), "{on}");
    assert!(on.contains("within Hicks et al.'s thresholds"), "{on}");
    let peak = |wb: &mut articula::session::Workbench| {
        let m = workbench::fails(wb, "expect peak LeftLeg.Xrotation torque between 0 1");
        m.split("torque ")
            .nth(1)
            .unwrap()
            .split(' ')
            .next()
            .unwrap()
            .parse::<f64>()
            .unwrap()
    };
    let reduced = peak(&mut wb);
    workbench::ok(&mut wb, "set consistent off");
    let off = workbench::ok(&mut wb, "run id");
    assert!(off.contains("beyond Hicks et al.'s thresholds"), "{off}");
    assert!(
        (peak(&mut wb) - reduced).abs() > 1.0,
        "the knee's torque is the adjusted take's"
    );
    let e = workbench::fails(&mut wb, "set consistent maybe");
    assert!(e.contains("expected auto, on or off"), "{e}");
}

/// `articula id TAKE --grf F --consistent on --json` (`--mass`) and its consistency JSON.
fn id_against(take: &Path, grf: &Path, mass: &str, dir: &Path) -> serde_json::Value {
    let out = common::cli::articula()
        .arg("id")
        .arg(take)
        .args(["--mass", mass, "--consistent", "on", "--json", "--grf"])
        .arg(grf)
        .arg("-o")
        .arg(dir.join("id.csv"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    v["consistency"].clone()
}

/// Against measured ground reactions RRA adjusts the total mass from the mean vertical
/// residual (Delp et al. 2007): forces estimated for a 75 kg walker, given to the model of a
/// heavier and of a lighter one, bring the mass back to about 75 kg; the residuals fall.
#[test]
fn against_measured_forces_the_mass_is_found_again() {
    let dir = tempfile::tempdir().unwrap();
    let take = common::repo("data/demo_walk.bvh");
    let grf = dir.path().join("g.csv");
    common::cli::articula()
        .args(["export", "grf"])
        .arg(&take)
        .args(["--mass", "75", "-o"])
        .arg(&grf)
        .assert()
        .success();
    for mass in ["77.25", "72"] {
        let c = id_against(&take, &grf, mass, dir.path());
        let a = &c["adjustments"];
        assert_eq!(a["ground_reactions"], "measured");
        let m: f64 = mass.parse().unwrap();
        let found = m + a["mass_change_kg"].as_f64().unwrap();
        assert!((found - 75.0).abs() < 0.75, "{mass} kg → {found} kg\n{c:#}");
        let (before, after) = (&c["before"], &c["after"]);
        assert!(
            after["rms_residual_moment_nm"].as_f64() < before["rms_residual_moment_nm"].as_f64()
        );
        assert!(
            after["peak_residual_force_n"].as_f64() < before["peak_residual_force_n"].as_f64(),
            "{c:#}"
        );
        assert!(a["pelvis_rotation_peak_deg"].as_f64().unwrap() <= 5.0);
    }
}

/// The pelvis rotations are adjusted within their bounds and say so, in both joint models
/// (the euler root through its Euler angles), and the demo walk still meets the thresholds.
#[test]
fn the_pelvis_rotations_are_adjusted_within_bounds_in_both_joint_models() {
    for joints in ["ball", "euler"] {
        let o = TakeOptions {
            joints: joints.parse().unwrap(),
            ..opts()
        };
        let take = pipeline::load_take(&common::repo("data/demo_walk.bvh"), &o).unwrap();
        let (_, _, c) = consistent_take(&take, true, None).unwrap();
        let a = c.adjustments.as_ref().unwrap();
        let (peak, rms) = a.rotation_peak_rms_rad.expect("rotations adjusted");
        assert!(
            peak <= 5f64.to_radians() && rms <= 2f64.to_radians(),
            "{joints}"
        );
        assert!(c.text().contains("pelvis rotation peak"), "{}", c.text());
        assert!(c.after.unwrap().meets(), "{joints}: {}", c.text());
    }
}

/// Reduces `b` and the same walk turned about the vertical `up`, its root written with the
/// vertical in the middle of its Euler order so that the heading is the middle angle (the Xia
/// takes' Hips), turned so that the median heading comes to 90°, on the euler model; returns
/// the two consistencies and the share of the turned take's frames whose root lies within 6°
/// of gimbal lock.
fn unturned_and_turned_to_gimbal_lock(
    b: &articula::io::bvh::Bvh,
    up: usize,
) -> (
    articula::pipeline::consistency::Consistency,
    articula::pipeline::consistency::Consistency,
    f64,
) {
    use articula::rotation::EulerOrder;
    let order = EulerOrder::ALL
        .into_iter()
        .find(|o| o.axes()[1] == up)
        .unwrap();
    let root = &b.joints[0];
    let middle = root.first_channel
        + (0..root.channels.len())
            .filter(|&i| root.channels[i].is_rotation())
            .nth(1)
            .unwrap();
    let reordered = common::variants::turned_heading(b, up, 0.0, order);
    let mut heading: Vec<f64> = (0..b.frames).map(|k| reordered.frame(k)[middle]).collect();
    heading.sort_by(f64::total_cmp);
    let turn = 90.0 - heading[heading.len() / 2];
    let turned = common::variants::turned_heading(b, up, turn, order);
    let near = (0..turned.frames)
        .filter(|&k| turned.frame(k)[middle].to_radians().cos().abs() < 6f64.to_radians().sin())
        .count() as f64
        / turned.frames as f64;
    let o = TakeOptions {
        joints: "euler".parse().unwrap(),
        ..opts()
    };
    let reduce = |b: articula::io::bvh::Bvh| {
        let take = pipeline::take_from_bvh(Path::new("walk.bvh"), b, &o).unwrap();
        consistent_take(&take, true, None).unwrap().2
    };
    (reduce(b.clone()), reduce(turned), near)
}

/// Issue 14's gimbal case (the root's rotation adjustment exists at any pose,
/// `dynamics::rra::root`): the demo walk turned to gimbal lock, on most of its frames within 6°
/// of it, is reduced as the unturned one is, pelvis rotations included: the same verdict and
/// the RMS residual moment after reduction within 1e-4 point of it. The euler model smooths and
/// differentiates each joint's rotation, not its angles (`motion::euler`), so the turned take
/// moves as the unturned one does, turned: the two differ by the optimizer's rounding only
/// (before that fix the turned take's coordinates were smoothed otherwise near the lock, and
/// the figures after differed by 0.003 point).
#[test]
fn a_walk_turned_to_gimbal_lock_reduces_like_the_unturned_one() {
    let b = articula::io::bvh::read(&common::repo("data/demo_walk.bvh")).unwrap();
    let (c0, c1, near) = unturned_and_turned_to_gimbal_lock(&b, 1);
    let (a0, a1) = (c0.after.as_ref().unwrap(), c1.after.as_ref().unwrap());
    eprintln!(
        "near lock {near}: before {} / {} %, after {} / {} %",
        c0.before.moment_pct(),
        c1.before.moment_pct(),
        a0.moment_pct(),
        a1.moment_pct()
    );
    assert!(near > 0.5, "only {near} of the frames near gimbal lock");
    let rotation = |c: &articula::pipeline::consistency::Consistency| {
        c.adjustments.as_ref().unwrap().rotation_peak_rms_rad
    };
    assert!(rotation(&c0).is_some() && rotation(&c1).is_some());
    assert_eq!(a0.meets(), a1.meets(), "{}\n{}", c0.text(), c1.text());
    assert!(
        (a0.moment_pct() - a1.moment_pct()).abs() < 1e-4,
        "{}\n{}",
        c0.text(),
        c1.text()
    );
}

/// The gimbal case on a shared walk (the Xia takes' behaviour, issue 14): AV_8Walk, a figure of
/// eight whose heading sweeps every direction, turned and written so that its heading is the
/// root's middle Euler angle, passes within 6° of gimbal lock on 2 % of its frames (enough for
/// the former gate to leave the whole take's pelvis unrotated). On the euler model it is
/// reduced as the unturned take is: pelvis rotations adjusted in both, the same verdict, and
/// the RMS residual moment after reduction the same share of the one before within 1e-4
/// (measured 0.166 both, 3.75 → 0.62 %). Before the euler model smoothed and differentiated
/// each joint's rotation rather than its angles (`motion::euler`), the figures before differed
/// (5.95 and 7.04 %: near the lock the root's angles turn fast), and with the pelvis offset's
/// refinement near foot changes the shares did too (0.29 and 0.44). The ball model gives the
/// same verdict.
#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn a_shared_walk_turned_to_gimbal_lock_reduces_like_the_unturned_one() {
    let path = common::real_take("AV_8Walk_Meredith_HVHA_Rep1.bvh");
    let b = articula::io::bvh::read(&path).unwrap();
    let (c0, c1, near) = unturned_and_turned_to_gimbal_lock(&b, 1);
    let (a0, a1) = (c0.after.as_ref().unwrap(), c1.after.as_ref().unwrap());
    eprintln!(
        "near lock {near}: before {} / {} %, after {} / {} %",
        c0.before.moment_pct(),
        c1.before.moment_pct(),
        a0.moment_pct(),
        a1.moment_pct()
    );
    assert!(near > 0.01, "only {near} of the frames near gimbal lock");
    for c in [&c0, &c1] {
        let adj = c.adjustments.as_ref().unwrap();
        assert!(adj.rotation_peak_rms_rad.is_some(), "{}", c.text());
    }
    assert_eq!(a0.meets(), a1.meets());
    let share = |c: &articula::pipeline::consistency::Consistency| {
        c.after.unwrap().moment_pct() / c.before.moment_pct()
    };
    assert!((share(&c0) - share(&c1)).abs() < 1e-4);
    let ball = pipeline::load_take(&path, &opts()).unwrap();
    let (_, _, cb) = consistent_take(&ball, true, None).unwrap();
    assert_eq!(cb.after.unwrap().meets(), a1.meets(), "{}", cb.text());
}

#[test]
fn the_residual_without_the_torques_is_what_rnea_with_the_feet_leaves() {
    // residual reduction evaluates its trials without the third pass: the needed wrench less
    // the feet's must be the root's wrench of RNEA with the feet's loads, to rounding, and
    // everything else the same bits
    use articula::dynamics::grf::{estimate_ground_reactions_progress, estimate_ground_residuals};
    use articula::motion::contact::ContactParams;
    let ball = TakeOptions {
        joints: articula::model::bvh::JointModel::Ball,
        ..opts()
    };
    let ball = pipeline::load_take(&common::repo("data/demo_walk.bvh"), &ball).unwrap();
    for take in [demo(), ball] {
        let (s, up) = (&take.states, take.up.index());
        let feet = pipeline::contact_feet(&take);
        let params = ContactParams::for_take(&take.smooth, take.bvh.frame_time).unwrap();
        let full = estimate_ground_reactions_progress(
            &take.model,
            &feet,
            &s.time,
            &s.q,
            &s.v,
            &s.a,
            up,
            &params,
            &mut |_| true,
        )
        .unwrap();
        let qva = [&s.q[..], &s.v[..], &s.a[..]];
        let quick =
            estimate_ground_residuals(&take.model, &feet, &s.time, qva, up, &params, None).unwrap();
        assert!(quick.tau.is_empty() && full.tau.len() == s.len());
        // the phases held (as residual reduction holds the loaded take's) are the phases found
        let held = Some(&full.contact[..]);
        let again =
            estimate_ground_residuals(&take.model, &feet, &s.time, qva, up, &params, held).unwrap();
        assert_eq!((&again.grf, &again.residual), (&quick.grf, &quick.residual));
        assert_eq!((&quick.grf, &quick.cop), (&full.grf, &full.cop));
        assert_eq!(
            (&quick.contact, &quick.wrench),
            (&full.contact, &full.wrench)
        );
        let weight = take.model.total_mass() * 9.81;
        let mut largest = 0.0_f64;
        for (a, b) in quick.residual.iter().zip(&full.residual) {
            for c in 0..6 {
                largest = largest.max((a[c] - b[c]).abs());
            }
        }
        // a wrong sign or a missing foot is of the order of the weight
        assert!(largest < 1e-9 * weight, "{largest:e} N (N·m)");
        assert!(
            full.residual
                .iter()
                .any(|r| r.iter().any(|x| x.abs() > 1e-3 * weight))
        );
    }
}
