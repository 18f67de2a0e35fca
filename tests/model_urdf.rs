//! A URDF read by articula has Pinocchio's kinematics and dynamics: every joint and link frame
//! (fixed links merged into their parent included) and the inverse dynamics (RNEA, gravity
//! included) match `tests/fixtures/pinocchio/{arm7,humanoid,humanoid_floating}` to 1e-9, with
//! coordinates matched by name (Pinocchio orders URDF children by name, we by file order).
//! A model written back as URDF and re-read is the same model (FK and RNEA agree to 1e-12).

mod common;

use articula::dynamics::{Workspace, forward_kinematics, rnea};
use articula::io::urdf_write::model_to_urdf;
use articula::model::Model;
use articula::model::urdf::{UrdfOptions, parse_urdf, parse_urdf_links, read_urdf};
use std::path::Path;

fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .filter(|l| !l.is_empty())
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

fn col(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"))
}

fn check(fixture: &str, urdf: &str, floating: bool) {
    check_with(
        fixture,
        urdf,
        floating,
        nalgebra::Vector3::new(0.0, 0.0, -9.81),
    );
}

fn check_with(fixture: &str, urdf: &str, floating: bool, gravity: nalgebra::Vector3<f64>) {
    let path = common::repo(urdf);
    let opts = UrdfOptions { floating, gravity };
    let text = std::fs::read_to_string(&path).unwrap();
    let (model, links) = parse_urdf_links(&text, &path, &opts).unwrap();
    let dir = common::repo(&format!("tests/fixtures/pinocchio/{fixture}"));
    let meta: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("model.json")).unwrap()).unwrap();
    assert_eq!(model.nq, meta["nq"].as_u64().unwrap() as usize);
    assert_eq!(model.nv, meta["nv"].as_u64().unwrap() as usize);
    let dyn_mass: f64 = model.inertia[1..].iter().map(|i| i.mass).sum();
    assert!((dyn_mass - meta["total_mass"].as_f64().unwrap()).abs() < 1e-9);

    let (sh, states) = read_csv(&dir.join("states.csv"));
    let (th, taus) = read_csv(&dir.join("rnea.csv"));
    let (fh, fks) = read_csv(&dir.join("fk.csv"));
    let mut ws = Workspace::new(&model);
    let (mut worst_fk, mut worst_tau): (f64, f64) = (0.0, 0.0);
    for ((s, tau_ref), fk) in states.iter().zip(&taus).zip(&fks) {
        let q: Vec<f64> = model
            .q_names
            .iter()
            .map(|n| s[col(&sh, &format!("q:{n}"))])
            .collect();
        let pick = |p: &str| -> Vec<f64> {
            model
                .v_names
                .iter()
                .map(|n| s[col(&sh, &format!("{p}:{n}"))])
                .collect()
        };
        let (v, a) = (pick("v"), pick("a"));
        forward_kinematics(&model, &mut ws, &q);
        // joint frames
        for i in 1..model.nbodies() {
            let name = &model.joint_names[i];
            for (c, axis) in ["x", "y", "z"].iter().enumerate() {
                let Some(k) = fh.iter().position(|h| h == &format!("{name}:{axis}")) else {
                    assert_eq!(name, "root_joint");
                    continue;
                };
                worst_fk = worst_fk.max((ws.o_x_i[i].trans[c] - fk[k]).abs());
            }
        }
        // link frames, merged links included
        for l in &links {
            let x = ws.o_x_i[l.body].compose(&l.pose);
            for (c, axis) in ["x", "y", "z"].iter().enumerate() {
                let want = fk[col(&fh, &format!("{}:{axis}", l.link))];
                worst_fk = worst_fk.max((x.trans[c] - want).abs());
            }
            for r in 0..3 {
                for c in 0..3 {
                    let want = fk[col(&fh, &format!("{}:r{r}{c}", l.link))];
                    worst_fk = worst_fk.max((x.rot[(r, c)] - want).abs());
                }
            }
        }
        let tau = rnea(&model, &mut ws, &q, &v, &a, None);
        for (k, n) in model.v_names.iter().enumerate() {
            let want = tau_ref[col(&th, &format!("tau:{n}"))];
            // relative to the torque's size (the exported take's prismatic root may sit
            // hundreds of metres out in Pinocchio's random states)
            worst_tau = worst_tau.max((tau[k] - want).abs() / (1.0 + want.abs()));
        }
    }
    assert!(worst_fk < 1e-9, "{fixture}: fk {worst_fk}");
    assert!(worst_tau < 1e-9, "{fixture}: rnea (relative) {worst_tau}");
}

#[test]
fn arm7_matches_pinocchio() {
    check("arm7", "data/arm7.urdf", false);
}

#[test]
fn humanoid_fixed_base_matches_pinocchio() {
    check("humanoid", "data/humanoid.urdf", false);
}

#[test]
fn humanoid_floating_base_matches_pinocchio() {
    check("humanoid_floating", "data/humanoid.urdf", true);
}

/// `tests/fixtures/pinocchio/walk_euler/model.urdf` is `model_to_urdf` of the generated walk's
/// euler model (75 kg), as Pinocchio 4.1 loads it with `buildModelFromUrdf` (fixed base: the
/// `world` link is the root): Pinocchio reads our export as we do, massless fictitious links
/// included.
#[test]
fn exported_bvh_model_loads_in_pinocchio_unchanged() {
    check_with(
        "walk_euler",
        "tests/fixtures/pinocchio/walk_euler/model.urdf",
        false,
        nalgebra::Vector3::new(0.0, -9.81, 0.0),
    );
}

/// The same coordinates, FK and RNEA (1e-12) for `a` and `b` at a few states.
fn assert_same_model(a: &Model, b: &Model) {
    assert_eq!(a.q_names, b.q_names);
    assert_eq!(a.nv, b.nv);
    assert!((a.total_mass() - b.total_mass()).abs() < 1e-12);
    assert_eq!(a.gravity, b.gravity);
    let (mut wa, mut wb) = (Workspace::new(a), Workspace::new(b));
    for s in 0..4 {
        let f = |k: usize, c: f64| ((k as f64 + 1.0) * c + s as f64).sin();
        let mut q = a.neutral();
        for (k, x) in q.iter_mut().enumerate() {
            *x += 0.8 * f(k, 0.7);
        }
        a.normalize(&mut q);
        let v: Vec<f64> = (0..a.nv).map(|k| f(k, 1.3)).collect();
        let acc: Vec<f64> = (0..a.nv).map(|k| 2.0 * f(k, 0.4)).collect();
        forward_kinematics(a, &mut wa, &q);
        forward_kinematics(b, &mut wb, &q);
        for i in 1..a.nbodies() {
            let j = b.body_index(&a.body_names[i]).unwrap();
            let (xa, xb) = (wa.o_x_i[i], wb.o_x_i[j]);
            assert!((xa.trans - xb.trans).norm() < 1e-12 && (xa.rot - xb.rot).norm() < 1e-12);
        }
        let ta = rnea(a, &mut wa, &q, &v, &acc, None).clone();
        let tb = rnea(b, &mut wb, &q, &v, &acc, None);
        assert!((ta - tb).norm() < 1e-12 * (1.0 + tb.norm()), "{s}");
    }
}

#[test]
fn written_urdf_reads_back_as_the_same_model() {
    for (urdf, floating) in [("data/arm7.urdf", false), ("data/humanoid.urdf", true)] {
        let opts = UrdfOptions {
            floating,
            ..Default::default()
        };
        let model = read_urdf(&common::repo(urdf), &opts).unwrap();
        let text = model_to_urdf(&model).unwrap();
        let back = parse_urdf(&text, Path::new("written.urdf"), &UrdfOptions::default()).unwrap();
        assert_same_model(&model, &back);
    }
}

#[test]
fn bvh_euler_model_exports_and_reads_back() {
    use articula::io::bvh::{PositionMode, UpAxis, resolve_position_modes};
    use articula::io::generate::{WalkParams, walk};
    use articula::model::bvh::{BvhModelOptions, JointModel, build_bvh_model};
    let take = walk(&WalkParams::default());
    let modes = resolve_position_modes(&take, PositionMode::Auto);
    let mut opts = BvhModelOptions::new("walk", 0.01, UpAxis::Y, modes);
    let (model, _) = build_bvh_model(&take, &opts).unwrap();
    let text = model_to_urdf(&model).unwrap();
    assert!(text.contains("<joint name=\"LeftUpLeg.Zrotation\" type=\"revolute\">"));
    assert!(text.contains("gravity (world frame, m/s^2): 0 -9.81 0"));
    let back = parse_urdf(
        &text,
        Path::new("walk.urdf"),
        &UrdfOptions {
            floating: false,
            gravity: model.gravity,
        },
    )
    .unwrap();
    assert_same_model(&model, &back);
    // the ball model has spherical joints, which URDF cannot express
    opts.joints = JointModel::Ball;
    let (ball, _) = build_bvh_model(&take, &opts).unwrap();
    assert!(model_to_urdf(&ball).is_err());
}

#[test]
fn malformed_urdf_is_an_error_with_a_line() {
    let cases = [
        "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/></robot>",
        "<robot name=\"r\"><link name=\"a\"/>\n<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"zz\"/></joint></robot>",
        "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/>\n<joint name=\"j\" type=\"planar\"><parent link=\"a\"/><child link=\"b\"/></joint></robot>",
        "<robot name=\"r\"><link name=\"a\"/><link name=\"b\"/>\n<joint name=\"j\" type=\"revolute\"><parent link=\"a\"/><child link=\"b\"/><axis xyz=\"0 0 0\"/></joint></robot>",
        "<robot name=\"r\"><link name=\"a\"",
    ];
    for text in cases {
        let err = parse_urdf(text, Path::new("bad.urdf"), &UrdfOptions::default());
        match err {
            // errors about a joint point at its line
            Err(articula::error::Error::Parse { at, .. }) => {
                assert_eq!(
                    at.line,
                    if text.contains("joint") { 2 } else { 1 },
                    "{text}"
                )
            }
            other => panic!("{text}: {other:?}"),
        }
    }
}
