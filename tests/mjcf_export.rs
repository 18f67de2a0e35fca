//! `articula export mjcf` writes a model MuJoCo can load that is articula's model: well-formed
//! XML with exactly one `<freejoint/>` (the floating root, in place of the euler model's 3
//! slides + 3 hinges or the ball model's free joint), one hinge per remaining coordinate of the
//! euler model (consecutive joints of one body per BVH joint, no massless fictitious bodies) or
//! one ball joint per BVH joint of the ball model, a motor per degree of freedom below the
//! root, link masses that add up to the model's mass, and gravity of 9.81 m/s² along the take's
//! −up. That MuJoCo's `mj_inverse` gives articula's torques is `tools/check_mujoco.py`'s job
//! (it needs the `mujoco` wheel).
//!
//! The URDF export says the same gravity in MuJoCo's `<mujoco><option gravity>` extension and
//! gives every link with a shape visual and collision geometry. The workbench's `export mjcf`
//! takes each motor's gear from its drives (`N·η`).

use articula::model::JointKind;
use articula::model::bvh::JointModel;
use articula::pipeline::{TakeOptions, load_take};
use std::path::{Path, PathBuf};

mod common;

use common::cli::articula;

/// A generated 1 s walk (Y up) in `dir`.
fn walk(dir: &Path) -> PathBuf {
    let p = dir.join("walk.bvh");
    articula()
        .args(["generate", "walk", "--fps", "60", "--duration", "1", "-o"])
        .arg(&p)
        .assert()
        .success();
    p
}

/// `export mjcf` of `take` with `args`, as text.
fn export(take: &Path, args: &[&str]) -> String {
    let out = take.with_file_name(format!("model{}.xml", args.join("_")));
    articula()
        .args(["export", "mjcf"])
        .arg(take)
        .args(args)
        .arg("-o")
        .arg(&out)
        .assert()
        .success();
    std::fs::read_to_string(out).expect("mjcf")
}

fn numbers(s: &str) -> Vec<f64> {
    s.split_whitespace()
        .map(|x| x.parse().expect("number"))
        .collect()
}

/// What the checks below count in an MJCF.
struct Counts {
    free: usize,
    hinges: usize,
    balls: usize,
    motors: usize,
    bodies: usize,
    mass: f64,
    gravity: Vec<f64>,
    /// Numbers in the keyframe's qpos (MuJoCo's nq).
    key_qpos: usize,
}

fn counts(xml: &str) -> Counts {
    let doc = roxmltree::Document::parse(xml).expect("well-formed XML");
    let root = doc.root_element();
    assert_eq!(root.tag_name().name(), "mujoco");
    let all = |tag: &'static str| root.descendants().filter(move |n| n.has_tag_name(tag));
    let joints = |kind: &str| {
        all("joint")
            .filter(|j| j.attribute("type") == Some(kind))
            .count()
    };
    // every motor drives a joint of the file
    let names: Vec<&str> = all("joint").filter_map(|j| j.attribute("name")).collect();
    for m in all("motor") {
        let j = m.attribute("joint").expect("motor joint");
        assert!(names.contains(&j), "motor on unknown joint {j}");
    }
    Counts {
        free: all("freejoint").count(),
        hinges: joints("hinge"),
        balls: joints("ball"),
        motors: all("motor").count(),
        bodies: all("body").count(),
        mass: all("inertial")
            .map(|i| i.attribute("mass").expect("mass").parse::<f64>().unwrap())
            .sum(),
        gravity: numbers(
            all("option")
                .find_map(|o| o.attribute("gravity"))
                .expect("option gravity"),
        ),
        key_qpos: numbers(
            all("key")
                .find_map(|k| k.attribute("qpos"))
                .expect("keyframe"),
        )
        .len(),
    }
}

fn model_of(take: &Path, joints: JointModel) -> articula::model::Model {
    let opts = TakeOptions {
        joints,
        ..TakeOptions::default()
    };
    load_take(take, &opts).expect("take").model
}

#[test]
fn euler_model_is_a_free_root_and_hinge_chains_with_the_models_mass() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path());
    let model = model_of(&take, JointModel::Euler);
    let c = counts(&export(&take, &[]));
    assert_eq!(c.free, 1);
    // the root's 6 coordinates are the free joint; every other one a hinge and a motor
    assert_eq!(c.hinges, model.nv - 6);
    assert_eq!(c.balls, 0);
    assert_eq!(c.motors, model.nv - 6);
    // one MuJoCo body per massive link: no fictitious bodies
    let massive = model.inertia.iter().filter(|i| i.mass > 0.0).count();
    assert_eq!(c.bodies, massive);
    assert!((c.mass - model.total_mass()).abs() <= 1e-12 * model.total_mass());
    assert_eq!(c.gravity, vec![0.0, -9.81, 0.0]);
    // the first frame as a keyframe: the free root's 7 numbers in place of the 6 coordinates
    assert_eq!(c.key_qpos, model.nq + 1);
}

#[test]
fn ball_model_is_a_free_root_and_a_ball_per_joint_with_three_motors_each() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path());
    let model = model_of(&take, JointModel::Ball);
    let spherical = model
        .joints
        .iter()
        .filter(|j| **j == JointKind::Spherical)
        .count();
    let c = counts(&export(&take, &["--joints", "ball"]));
    assert_eq!(c.free, 1);
    assert_eq!(c.balls, spherical);
    assert_eq!(c.hinges, 0);
    assert_eq!(c.motors, 3 * spherical);
    assert_eq!(model.nv, 6 + 3 * spherical);
    assert_eq!(c.key_qpos, model.nq);
    assert!((c.mass - model.total_mass()).abs() <= 1e-12 * model.total_mass());
}

#[test]
fn gravity_and_floor_follow_the_takes_up_axis() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path());
    let xml = export(&take, &["--up", "z"]);
    assert_eq!(counts(&xml).gravity, vec![0.0, 0.0, -9.81]);
    let doc = roxmltree::Document::parse(&xml).unwrap();
    let floor = doc
        .descendants()
        .find(|n| n.attribute("type") == Some("plane"))
        .expect("a floor plane");
    // z up: the plane's normal is its own z, so no rotation
    assert_eq!(floor.attribute("quat"), None);
    // Y up: the plane is turned so that its normal is +y (w, x, y, z = cos 45°, −sin 45°, 0, 0)
    let y_up = export(&take, &[]);
    let doc = roxmltree::Document::parse(&y_up).unwrap();
    let q = numbers(
        doc.descendants()
            .find(|n| n.attribute("type") == Some("plane"))
            .and_then(|n| n.attribute("quat"))
            .expect("quat"),
    );
    let half = std::f64::consts::FRAC_1_SQRT_2;
    assert!(
        (q[0] - half).abs() < 1e-15 && (q[1] + half).abs() < 1e-15,
        "{q:?}"
    );
}

#[test]
fn links_collide_with_the_floor_but_not_with_each_other() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path());
    let xml = export(&take, &[]);
    let doc = roxmltree::Document::parse(&xml).unwrap();
    let bits = |n: roxmltree::Node, a: &str| -> u32 { n.attribute(a).unwrap().parse().unwrap() };
    let geoms: Vec<_> = doc
        .descendants()
        .filter(|n| n.has_tag_name("geom"))
        .collect();
    let (floor, links): (Vec<_>, Vec<_>) = geoms
        .into_iter()
        .partition(|g| g.attribute("type") == Some("plane"));
    assert_eq!(floor.len(), 1);
    assert!(!links.is_empty());
    let touch = |a: roxmltree::Node, b: roxmltree::Node| {
        bits(a, "contype") & bits(b, "conaffinity") != 0
            || bits(b, "contype") & bits(a, "conaffinity") != 0
    };
    for l in &links {
        assert_eq!(l.attribute("type"), Some("ellipsoid"));
        assert!(touch(*l, floor[0]));
        assert!(!touch(*l, links[0]));
    }
}

#[test]
fn urdf_has_link_geometry_and_gravity_in_mujocos_option() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path());
    let out = dir.path().join("walk.urdf");
    articula()
        .args(["export", "urdf"])
        .arg(&take)
        .args(["--up", "z", "-o"])
        .arg(&out)
        .assert()
        .success();
    let text = std::fs::read_to_string(out).unwrap();
    let doc = roxmltree::Document::parse(&text).expect("well-formed XML");
    let option = doc
        .descendants()
        .find(|n| n.has_tag_name("option") && n.parent().is_some_and(|p| p.has_tag_name("mujoco")))
        .expect("<mujoco><option>");
    assert_eq!(
        numbers(option.attribute("gravity").unwrap()),
        vec![0.0, 0.0, -9.81]
    );
    let model = model_of(&take, JointModel::Euler);
    let shaped = model.shapes.iter().filter(|s| s.is_some()).count();
    for tag in ["visual", "collision"] {
        let n = doc.descendants().filter(|n| n.has_tag_name(tag)).count();
        assert_eq!(n, shaped, "{tag}");
    }
    assert!(shaped > 0);
}

#[test]
fn workbench_export_takes_motor_gears_from_the_drives() {
    let dir = tempfile::tempdir().unwrap();
    let mut wb = common::workbench::wb_in(dir.path());
    common::workbench::ok(&mut wb, "load demo:walk");
    common::workbench::ok(&mut wb, "set motor.gear 50");
    common::workbench::ok(&mut wb, "set motor.efficiency 0.9");
    common::workbench::ok(&mut wb, "set motor.LeftLeg.Xrotation.gear 120");
    common::workbench::ok(&mut wb, "export mjcf walk.xml");
    let xml = std::fs::read_to_string(dir.path().join("walk.xml")).unwrap();
    let doc = roxmltree::Document::parse(&xml).expect("well-formed XML");
    let gear = |motor: &str| -> f64 {
        doc.descendants()
            .find(|n| n.has_tag_name("motor") && n.attribute("name") == Some(motor))
            .and_then(|n| n.attribute("gear"))
            .unwrap_or_else(|| panic!("motor {motor}"))
            .parse()
            .unwrap()
    };
    assert_eq!(gear("LeftLeg.Xrotation"), 120.0 * 0.9);
    assert_eq!(gear("RightLeg.Xrotation"), 50.0 * 0.9);
    assert_eq!(counts(&xml).free, 1);
}
