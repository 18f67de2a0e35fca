//! A DH table typed in Corke's conventions gives the Robotics Toolbox's kinematics and dynamics:
//! the end-effector pose and every DH link frame origin (`fkine`, `fkine_all`) and the inverse
//! dynamics (`rne`, gravity included) of the Puma 560 (standard and modified DH) and the
//! Stanford arm (prismatic joint 3) match `tests/fixtures/rtb` to 1e-9.

mod common;

use articula::dynamics::{Workspace, forward_kinematics, rnea};
use articula::io::dh;
use articula::model::dh::{build_dh_model, link_frame};
use std::path::Path;

/// Header and rows of a numeric fixture CSV.
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

fn check(name: &str) {
    let table = dh::read(&common::repo(&format!("data/{name}.toml"))).unwrap();
    let model = build_dh_model(&table).unwrap();
    let n = table.links.len();
    assert_eq!(model.nv, n);
    let dir = common::repo(&format!("tests/fixtures/rtb/{name}"));
    let (sh, states) = read_csv(&dir.join("states.csv"));
    let (th, taus) = read_csv(&dir.join("rnea.csv"));
    let (fh, fks) = read_csv(&dir.join("fk.csv"));
    let mut ws = Workspace::new(&model);
    let (mut worst_fk, mut worst_tau): (f64, f64) = (0.0, 0.0);
    for ((s, tau_ref), fk) in states.iter().zip(&taus).zip(&fks) {
        let pick =
            |p: &str| -> Vec<f64> { (1..=n).map(|j| s[col(&sh, &format!("{p}:j{j}"))]).collect() };
        let (q, v, a) = (pick("q"), pick("v"), pick("a"));
        forward_kinematics(&model, &mut ws, &q);
        // DH link frame origins
        for i in 0..n {
            let f = ws.o_x_i[i + 1].compose(&link_frame(&table, i));
            for (c, axis) in ["x", "y", "z"].iter().enumerate() {
                let want = fk[col(&fh, &format!("j{}:{axis}", i + 1))];
                worst_fk = worst_fk.max((f.trans[c] - want).abs());
            }
        }
        // end effector: position and rotation
        let ee = ws.o_x_i[n].compose(&link_frame(&table, n - 1));
        for (c, axis) in ["x", "y", "z"].iter().enumerate() {
            worst_fk = worst_fk.max((ee.trans[c] - fk[col(&fh, axis)]).abs());
        }
        for r in 0..3 {
            for c in 0..3 {
                let want = fk[col(&fh, &format!("r{r}{c}"))];
                worst_fk = worst_fk.max((ee.rot[(r, c)] - want).abs());
            }
        }
        let tau = rnea(&model, &mut ws, &q, &v, &a, None);
        for j in 0..n {
            let want = tau_ref[col(&th, &format!("tau:j{}", j + 1))];
            worst_tau = worst_tau.max((tau[j] - want).abs());
        }
    }
    assert!(worst_fk < 1e-9, "{name}: fk {worst_fk}");
    assert!(worst_tau < 1e-9, "{name}: rnea {worst_tau}");
}

#[test]
fn puma560_standard_dh_matches_the_robotics_toolbox() {
    check("puma560");
}

#[test]
fn puma560_modified_dh_matches_the_robotics_toolbox() {
    check("puma560_mdh");
}

#[test]
fn stanford_arm_with_a_prismatic_joint_matches_the_robotics_toolbox() {
    check("stanford");
}

#[test]
fn the_documented_example_builds() {
    let table = dh::read(&common::repo("data/dh_example.toml")).unwrap();
    let model = build_dh_model(&table).unwrap();
    assert_eq!(model.nv, table.links.len());
    assert!((model.total_mass() - 11.1).abs() < 1e-12);
    // at q = 0 the tool is 0.35 + 0.25 m out, 0.4 m up, then 0.05 + 0.08 m down the quill
    let mut ws = Workspace::new(&model);
    forward_kinematics(&model, &mut ws, &[0.0; 4]);
    let ee = ws.o_x_i[4].compose(&link_frame(&table, 3)).trans;
    assert!(
        (ee - nalgebra::Vector3::new(0.6, 0.0, 0.27)).norm() < 1e-12,
        "{ee}"
    );
}
