//! Robot arms in the workbench: `load` takes DH tables and URDF, a motion comes from a
//! generated quintic trajectory or a states CSV, and `run id` / `run sim` / `report motor`
//! work on it. Held still at a pose, inverse dynamics is the gravity load, which the Robotics
//! Toolbox fixtures give for the Puma 560 and the Stanford arm (a prismatic joint).

mod common;

use common::workbench::{apply, ok, wb_in};

fn rows(path: &str) -> Vec<Vec<f64>> {
    let text = std::fs::read_to_string(common::repo(path)).unwrap();
    text.lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect()
}

#[test]
fn held_poses_give_the_robotics_toolbox_gravity_load() {
    let out = tempfile::tempdir().unwrap();
    for robot in ["puma560", "stanford"] {
        let mut wb = wb_in(out.path());
        ok(&mut wb, &format!("load data/{robot}.toml"));
        let states = rows(&format!("tests/fixtures/rtb/{robot}/states.csv"));
        let gravity = rows(&format!("tests/fixtures/rtb/{robot}/gravity.csv"));
        for (s, g) in states.iter().zip(&gravity) {
            let pose: Vec<String> = s[..6].iter().map(|x| format!("{x:e}")).collect();
            ok(
                &mut wb,
                &format!("trajectory {} over 0.1 at 50", pose.join(",")),
            );
            ok(&mut wb, "run id");
            let r = wb.fresh_results().unwrap();
            for k in [0, r.tau.rows() - 1] {
                for (j, want) in g.iter().enumerate() {
                    let got = r.tau.row(k)[j];
                    assert!(
                        (got - want).abs() < 1e-9 * want.abs().max(1.0),
                        "{robot} q {s:?}: τ{} = {got}, toolbox {want}",
                        j + 1
                    );
                }
            }
        }
    }
}

#[test]
fn a_states_csv_written_by_export_csv_is_a_motion_and_gives_the_same_torques() {
    let out = tempfile::tempdir().unwrap();
    let mut wb = wb_in(out.path());
    ok(&mut wb, "load data/puma560.toml as puma");
    ok(
        &mut wb,
        "trajectory 0,0,0,0,0,0 0,pi/4,-pi,0,pi/4,0 over 1 at 200",
    );
    ok(&mut wb, "export csv moves.csv");
    let first = wb.fresh_results().unwrap().clone();
    let msg = ok(
        &mut wb,
        &format!("load {}", out.path().join("moves.csv").display()),
    );
    assert!(msg.contains("201 samples"), "{msg}");
    assert!(wb.results.is_none(), "a new motion drops the old results");
    ok(&mut wb, "run id");
    let again = wb.fresh_results().unwrap();
    assert_eq!(again.tau, first.tau);
    assert_eq!(again.time, first.time);
    // the motion of the arm: sim tracks it, motor sizing covers its six joints
    ok(&mut wb, "run sim");
    assert!(wb.last_message().contains("tracking error RMS"));
    let m = ok(&mut wb, "report motor m.csv");
    assert_eq!(
        m.matches(" BLDC-").count() + m.matches("none in").count(),
        6,
        "{m}"
    );
}

#[test]
fn a_urdf_arm_loads_moves_and_is_sized() {
    let out = tempfile::tempdir().unwrap();
    let mut wb = wb_in(out.path());
    let msg = ok(&mut wb, "load data/arm7.urdf");
    assert!(msg.contains("URDF: 7 joints, nv 7"), "{msg}");
    ok(
        &mut wb,
        "trajectory 0,0,0,0,0,0,0 0.5,0.5,0.5,0.5,0.5,0.5,0.5 over 0.5 at 100",
    );
    ok(&mut wb, "expect nv 7");
    ok(&mut wb, "select joint2");
    ok(&mut wb, "expect selected joint2");
    // the move starts and ends at rest: τ(0) is the gravity load, not zero at the shoulder
    ok(&mut wb, "frame 0");
    ok(&mut wb, "expect now joint2 velocity between 0 0");
    let tree: Vec<String> = wb
        .take()
        .unwrap()
        .joint_tree()
        .into_iter()
        .map(|(n, _)| n)
        .collect();
    assert_eq!(tree.len(), 7, "{tree:?}");
    ok(&mut wb, "report motor curves c.csv");
    assert!(out.path().join("c.csv").exists());
}

#[test]
fn robot_mistakes_are_errors_that_say_what_to_do() {
    let out = tempfile::tempdir().unwrap();
    let mut wb = wb_in(out.path());
    let e = apply(&mut wb, "trajectory 0 1 over 1").unwrap_err();
    assert!(e.contains("load a DH table or URDF first"), "{e}");
    ok(&mut wb, "load demo:walk");
    let e = apply(&mut wb, "trajectory 0 1 over 1").unwrap_err();
    assert!(e.contains("is a BVH take"), "{e}");
    let e = apply(&mut wb, "load data/none.csv").unwrap_err();
    assert!(e.contains("is a BVH take"), "{e}");
    ok(&mut wb, "load data/puma560.toml as puma");
    let e = apply(&mut wb, "run id").unwrap_err();
    assert!(e.contains("puma has no motion yet"), "{e}");
    let e = apply(&mut wb, "trajectory 0,0,0 1,1,1 over 1").unwrap_err();
    assert!(e.contains("a pose of 3 values for 6 coordinates"), "{e}");
    let e = apply(&mut wb, "select elbow").unwrap_err();
    assert!(e.contains("no joint called 'elbow'"), "{e}");
    ok(&mut wb, "trajectory 0,0,0,0,0,0 0,1,0,0,0,0 over 0.2 at 50");
    let e = apply(&mut wb, "export bvh arm.bvh").unwrap_err();
    assert!(e.contains("is a robot model"), "{e}");
    let e = apply(&mut wb, "blend walk puma 1:2").unwrap_err();
    assert!(e.contains("only BVH takes blend"), "{e}");
    let e = apply(&mut wb, "set link.j2.mass 3").unwrap_err();
    assert!(e.contains("DH table or URDF"), "{e}");
    let e = apply(&mut wb, "set motor.j9.gear 3").unwrap_err();
    assert!(e.contains("no coordinate 'j9'"), "{e}");
    let e = apply(&mut wb, "set motor.j2.efficiency 1.5").unwrap_err();
    assert!(e.contains("out of range"), "{e}");
    let e = apply(&mut wb, "report motor curves c.svg").unwrap_err();
    assert!(e.contains(".csv"), "{e}");
    let e = apply(&mut wb, "set motor.catalogue data/puma560.toml").unwrap_err();
    assert!(e.contains("puma560.toml"), "{e}");
    // after all that, the arm still works
    ok(&mut wb, "run id");
    ok(&mut wb, "expect frames 11");
}

#[test]
fn a_motor_catalogue_file_replaces_the_bundled_one() {
    let out = tempfile::tempdir().unwrap();
    std::fs::write(
        out.path().join("cat.toml"),
        "[[class]]\nname = \"tiny\"\nrated_torque_nm = 0.001\npeak_torque_nm = 0.002\nrated_speed_rpm = 100000\n\n[[class]]\nname = \"huge\"\nrated_torque_nm = 100\npeak_torque_nm = 300\nrated_speed_rpm = 100000\n",
    )
    .unwrap();
    let mut wb = wb_in(out.path());
    ok(&mut wb, "load data/puma560.toml");
    ok(&mut wb, "trajectory 0,0,0,0,0,0 0,1,1,0,0,0 over 1 at 100");
    ok(
        &mut wb,
        &format!(
            "set motor.catalogue {}",
            out.path().join("cat.toml").display()
        ),
    );
    let m = ok(&mut wb, "report motor t.csv");
    // j2 carries tens of N·m: through 100:1 more than 1 mN·m, so "huge"; j6 carries nothing
    assert!(m.contains("j2 huge") && m.contains("j6 tiny"), "{m}");
}

/// Regression: loading an arm after selecting an avatar's knee kept `RightLeg.Xrotation`
/// selected, and the parameter panel and sparklines named a coordinate the arm does not have.
/// A load keeps the selection only where the new take has it.
#[test]
fn loading_an_arm_after_a_take_selects_one_of_its_joints() {
    let dir = tempfile::tempdir().unwrap();
    let mut wb = wb_in(dir.path());
    ok(&mut wb, "load demo:walk as walk");
    ok(&mut wb, "select RightLeg");
    assert_eq!(wb.selection.as_deref(), Some("RightLeg.Xrotation"));
    let dh = articula_data("stanford.toml");
    ok(&mut wb, &format!("load {dh} as arm"));
    assert_eq!(wb.selection.as_deref(), Some("j1"));
    // back on the take, a coordinate of the take: none until its results choose one (a
    // human's: its left knee's anatomical flexion)
    ok(&mut wb, "load demo:walk as walk2");
    ok(&mut wb, "run id");
    let sel = wb.selection.clone().unwrap();
    assert_eq!(sel, "knee_l:flexion");
    let r = wb.fresh_results().unwrap();
    assert!(
        articula::session::workbench::is_anatomical(r, &sel),
        "{sel}"
    );
}

fn articula_data(name: &str) -> String {
    format!("{}/data/{name}", env!("CARGO_MANIFEST_DIR"))
}
