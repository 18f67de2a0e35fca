//! The euler joint model (each BVH joint three hinges with massless links between) moves
//! every body as the ball model does (issue 14): each joint's rotation is smoothed on SO(3)
//! and its rates come from the rotation (`motion::euler`), so for the same take and smoothing
//! the root residuals, the ground reactions and the anatomical moments are the ball model's
//! (≤ 1e-6 relative; the two differ by rounding only), and they do not depend on the order in
//! which the take writes its rotations, near gimbal lock included. Generated from the bundled
//! demo walk here, from AV_8Walk and a Bandai walk in the real suite.

mod common;

use articula::io::bvh::{self, Bvh};
use articula::pipeline::consistency::consistent_take;
use articula::pipeline::{self, Take, TakeOptions, anatomy::Anatomy};
use articula::rotation::EulerOrder;
use std::path::Path;

fn take(b: &Bvh, joints: &str) -> Take {
    let o = TakeOptions {
        joints: joints.parse().unwrap(),
        ..common::anatomy_opts()
    };
    pipeline::take_from_bvh(Path::new("walk.bvh"), b.clone(), &o).unwrap()
}

/// What is compared: per frame the root residual force and moment, each foot's ground
/// reaction, and every anatomical angle and moment.
struct Seen {
    residuals: Vec<(String, Vec<f64>)>,
    anatomy: Anatomy,
}

fn see(t: &Take) -> Seen {
    let (_, grf, c) = consistent_take(t, false, None).unwrap();
    let mut residuals = vec![
        ("residual force".to_string(), c.force_n.clone()),
        ("residual moment".to_string(), c.moment_nm.clone()),
    ];
    for (f, forces) in grf.feet.iter().zip(&grf.grf) {
        for axis in 0..3 {
            let col = forces.iter().map(|g| g[axis]).collect();
            residuals.push((format!("{f} ground force {axis}"), col));
        }
    }
    let anatomy = pipeline::anatomy::anatomy(t).unwrap();
    Seen { residuals, anatomy }
}

/// Every column of `a` and `b` equal within `rel` of the column's peak (at least 1).
fn assert_same(label: &str, a: &Seen, b: &Seen, rel: f64) {
    let columns = |s: &Seen| -> Vec<(String, Vec<f64>)> {
        let mut all = s.residuals.clone();
        all.extend(
            s.anatomy
                .names
                .iter()
                .cloned()
                .zip(s.anatomy.columns.clone()),
        );
        all
    };
    let (ca, cb) = (columns(a), columns(b));
    assert_eq!(
        ca.iter().map(|c| &c.0).collect::<Vec<_>>(),
        cb.iter().map(|c| &c.0).collect::<Vec<_>>(),
        "{label}: columns"
    );
    assert!(a.anatomy.names.iter().any(|n| is_knee_moment(n)));
    let mut worst = (0.0, String::new());
    for ((name, x), (_, y)) in ca.iter().zip(&cb) {
        let scale = x.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
        for (k, (u, v)) in x.iter().zip(y).enumerate() {
            let e = (u - v).abs() / scale;
            if e > worst.0 {
                worst = (e, format!("{name} at frame {k}: {u} vs {v}"));
            }
        }
    }
    eprintln!(
        "{label}: worst relative difference {:.1e} ({})",
        worst.0, worst.1
    );
    assert!(worst.0 <= rel, "{label}: {}", worst.1);
}

fn is_knee_moment(name: &str) -> bool {
    name.contains("knee") && name.contains("moment") && !name.contains("per_kg")
}

fn euler_is_ball(b: &Bvh, label: &str) {
    let euler = see(&take(b, "euler"));
    let ball = see(&take(b, "ball"));
    assert_same(&format!("{label}, euler vs ball"), &euler, &ball, 1e-6);
}

#[test]
fn the_demo_walk_on_the_euler_model_moves_as_on_the_ball_model() {
    let b = bvh::read(&common::repo("data/demo_walk.bvh")).unwrap();
    euler_is_ball(&b, "demo walk");
}

/// The same take with every joint's rotation channels in another order is the same motion:
/// before, the euler model smoothed and differentiated other angles, and its moments moved.
#[test]
fn the_demo_walk_in_another_rotation_order_gives_the_same_euler_model_moments() {
    let b = bvh::read(&common::repo("data/demo_walk.bvh")).unwrap();
    let original = see(&take(&b, "euler"));
    let reordered = see(&take(
        &common::variants::another_rotation_order(&b),
        "euler",
    ));
    assert_same("demo walk, another order", &original, &reordered, 1e-6);
}

fn demo() -> Bvh {
    bvh::read(&common::repo("data/demo_walk.bvh")).unwrap()
}

/// `b` with its root's rotations written in `order` (the vertical axis in the middle: its
/// heading is the middle angle), and that angle's channel.
fn heading_in_the_middle(b: &Bvh, order: EulerOrder) -> (Bvh, usize) {
    let reordered = common::variants::turned_heading(b, 1, 0.0, order);
    let root = &reordered.joints[0];
    let middle = root.first_channel
        + (0..root.channels.len())
            .filter(|&i| root.channels[i].is_rotation())
            .nth(1)
            .unwrap();
    (reordered, middle)
}

/// The demo walk turned about the vertical so that its heading is the root's middle Euler
/// angle (Y-up, written Z-Y-X: within 6° of gimbal lock on most frames, the Xia takes' Hips)
/// is the same walk facing another way: the same residuals, ground reactions (turned) and
/// anatomical moments, so the same figures before reduction.
#[test]
fn the_demo_walk_turned_to_gimbal_lock_has_the_same_residuals_on_the_euler_model() {
    let (b, order) = (demo(), EulerOrder::ZYX);
    let (reordered, middle) = heading_in_the_middle(&b, order);
    let mut heading: Vec<f64> = (0..b.frames).map(|k| reordered.frame(k)[middle]).collect();
    heading.sort_by(f64::total_cmp);
    let turned = common::variants::turned_heading(&b, 1, 90.0 - heading[b.frames / 2], order);
    let near = (0..turned.frames)
        .filter(|&k| turned.frame(k)[middle].to_radians().cos().abs() < 6f64.to_radians().sin())
        .count();
    assert!(2 * near > turned.frames, "{near} frames near gimbal lock");
    let (t0, t1) = (take(&reordered, "euler"), take(&turned, "euler"));
    let figures = |t: &Take| consistent_take(t, false, None).unwrap().2.before;
    let (f0, f1) = (figures(&t0), figures(&t1));
    eprintln!(
        "before: {} / {} % moment, {} / {} % force",
        f0.moment_pct(),
        f1.moment_pct(),
        f0.force_pct(),
        f1.force_pct()
    );
    assert!((f0.moment_pct() - f1.moment_pct()).abs() < 1e-6 * f0.moment_pct().max(1.0));
    assert!((f0.force_pct() - f1.force_pct()).abs() < 1e-6 * f0.force_pct().max(1.0));
    let (a0, a1) = (
        pipeline::anatomy::anatomy(&t0).unwrap(),
        pipeline::anatomy::anatomy(&t1).unwrap(),
    );
    let knees = a0
        .names
        .iter()
        .enumerate()
        .filter(|(_, n)| is_knee_moment(n));
    for (c, name) in knees {
        let peak = a0.columns[c].iter().fold(1.0_f64, |m, v| m.max(v.abs()));
        for (x, y) in a0.columns[c].iter().zip(&a1.columns[c]) {
            assert!((x - y).abs() < 1e-6 * peak, "{name}: {x} vs {y}");
        }
    }
}

#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn shared_walks_on_the_euler_model_move_as_on_the_ball_model() {
    for name in [
        "AV_8Walk_Meredith_HVHA_Rep1.bvh",
        "dataset-1_walk_normal_001.bvh",
    ] {
        let (b, _) = pipeline::read_take(&common::real_take(name), false).unwrap();
        euler_is_ball(&b, name);
    }
}

/// A root that reaches gimbal lock exactly (its middle angle written as 90° on a run of
/// frames, not smoothed): at those frames the euler joint's rates cannot come from its
/// rotation (`motion::euler::LOCK_DET`), so there its velocities and accelerations are its
/// angles' differences, and a note says so, naming the BVH joint and counting the frames.
/// Every other frame keeps its rates from the rotation: a few frames from the lock the euler
/// model's moments are the ball model's (which never locks). Before, the whole joint fell
/// back to its angles' differences, 16 % of the knee's peak off the ball model's all along
/// the take (the walk's heading within a few degrees of the lock amplifies them).
#[test]
fn a_root_at_exact_gimbal_lock_falls_back_to_its_angle_differences_and_says_so() {
    let (b, order) = (demo(), EulerOrder::ZYX);
    let (reordered, middle) = heading_in_the_middle(&b, order);
    let mid = b.frames / 2;
    let heading = reordered.frame(mid)[middle];
    let mut locked = common::variants::turned_heading(&b, 1, 90.0 - heading, order);
    let lock = mid - 2..mid + 3;
    for k in lock.clone() {
        locked.motion[k * locked.channel_count + middle] = 90.0;
    }
    let opts = |joints: &str| TakeOptions {
        joints: joints.parse().unwrap(),
        smooth: Some("none".parse().unwrap()),
        ..common::anatomy_opts()
    };
    let load = |joints: &str| {
        pipeline::take_from_bvh(Path::new("locked.bvh"), locked.clone(), &opts(joints)).unwrap()
    };
    let (euler, ball) = (load("euler"), load("ball"));
    let name = &locked.joints[0].name;
    let note = euler
        .notes
        .iter()
        .find(|n| n.contains("reaches gimbal lock"))
        .unwrap_or_else(|| panic!("no lock note in {:#?}", euler.notes));
    assert!(
        note.starts_with(&format!("`{name}` reaches gimbal lock at 5 frame(s)")),
        "{note}"
    );
    assert!(
        !ball.notes.iter().any(|n| n.contains("reaches gimbal lock")),
        "{:#?}",
        ball.notes
    );
    let s = &euler.states;
    for (k, (v, a)) in s.v.iter().zip(&s.a).enumerate() {
        assert!(
            v.iter().chain(a).all(|x| x.is_finite()),
            "frame {k} not finite"
        );
    }
    // the root's rates are not zero: the walk turns and sways at every frame
    let root_v: f64 =
        s.v.iter()
            .map(|v| v[3].abs() + v[4].abs() + v[5].abs())
            .sum();
    assert!(root_v > 1e-3 * s.len() as f64, "root rates {root_v}");
    let (ae, ab) = (
        pipeline::anatomy::anatomy(&euler).unwrap(),
        pipeline::anatomy::anatomy(&ball).unwrap(),
    );
    assert_eq!(ae.names, ab.names);
    // frames a few samples from the lock and from the take's ends
    let far = |k: usize| k + 3 < lock.start || k > lock.end + 3;
    let mut checked = 0;
    for (c, name) in ae
        .names
        .iter()
        .enumerate()
        .filter(|(_, n)| is_knee_moment(n))
    {
        let peak = ab.columns[c].iter().fold(1.0_f64, |m, v| m.max(v.abs()));
        let mut worst = 0.0_f64;
        for k in (0..s.len()).filter(|&k| far(k)) {
            worst = worst.max((ae.columns[c][k] - ab.columns[c][k]).abs() / peak);
            checked += 1;
        }
        eprintln!("{name}: away from the lock, euler within {worst:.2e} of the ball's peak");
        assert!(worst < 1e-6, "{name}: {worst}");
    }
    assert!(checked > 100, "{checked}");
}
