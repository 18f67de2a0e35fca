//! What the workbench writes and applies is what the user sees:
//! - `export bvh` writes the take as smoothed (and blended), `export bvh sim` the simulated
//!   motion; reading either back without smoothing gives those configurations again;
//! - a scene is applied exactly as the CLI's `--scene` applies it (`TakeOptions::from_scene`):
//!   stature, up axis, position semantics and subtree included;
//! - long computations report progress inside their loops and stop mid-way when cancelled,
//!   leaving the workbench as it was.

mod common;

use articula::pipeline::{self, TakeOptions};
use articula::session::engine::Control;
use articula::session::{Command, RunKind, Workbench, parse_line};
use std::path::Path;
use std::sync::Arc;

fn wb_in(dir: &Path) -> Workbench {
    Workbench::new(Arc::new(articula::session::Builtin), dir, dir)
}

fn ok(wb: &mut Workbench, line: &str) -> String {
    let cmd: Command = parse_line(line, 1).unwrap().unwrap();
    wb.apply(&cmd)
        .unwrap_or_else(|e| panic!("{line}: {e}"))
        .message
}

fn q_of(wb: &Workbench, coord: &str) -> Vec<f64> {
    let r = wb.fresh_results().unwrap();
    r.q.column(r.q.col_index(coord).unwrap())
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn export_bvh_writes_the_smoothed_take_and_it_reads_back_as_such() {
    let dir = tempfile::tempdir().unwrap();
    let mut wb = wb_in(dir.path());
    ok(&mut wb, "load demo:walk as walk");
    ok(&mut wb, "set smooth gaussian:0.05");
    ok(&mut wb, "run id");
    let coords = [
        "LeftLeg.Xrotation",
        "Hips.Yposition",
        "RightUpLeg.Zrotation",
    ];
    let seen: Vec<Vec<f64>> = coords.iter().map(|c| q_of(&wb, c)).collect();
    ok(&mut wb, "export bvh smooth.bvh");
    // raw, the take differs from what was seen
    ok(&mut wb, "set smooth none");
    ok(&mut wb, "run id");
    assert!(max_diff(&q_of(&wb, coords[0]), &seen[0]) > 1e-3);
    // the exported file, read without smoothing, is what was seen
    ok(&mut wb, "load smooth.bvh as exported");
    ok(&mut wb, "run id");
    for (c, s) in coords.iter().zip(&seen) {
        let d = max_diff(&q_of(&wb, c), s);
        assert!(d < 1e-9, "{c}: {d}");
    }
}

#[test]
fn export_bvh_sim_writes_the_simulated_motion() {
    let dir = tempfile::tempdir().unwrap();
    let walk = articula::io::generate::walk(&articula::io::generate::WalkParams {
        duration_s: 0.5,
        ..Default::default()
    });
    articula::io::bvh::write(&walk, &dir.path().join("w.bvh")).unwrap();
    let mut wb = wb_in(dir.path());
    ok(&mut wb, "load w.bvh");
    let e = wb
        .apply(&parse_line("export bvh sim s.bvh", 1).unwrap().unwrap())
        .unwrap_err();
    assert!(e.to_string().contains("run sim first"), "{e}");
    // a sloppy controller, so that the simulated motion differs from the take
    ok(&mut wb, "set kp 4");
    ok(&mut wb, "set kv 1");
    ok(&mut wb, "set dt 0.002");
    ok(&mut wb, "run sim");
    let sim = wb.sim.as_ref().unwrap().0.clone();
    ok(&mut wb, "export bvh sim s.bvh");
    ok(&mut wb, "set smooth none");
    ok(&mut wb, "load s.bvh as simulated");
    // the motion as written (residual reduction would move the pelvis a few mm)
    ok(&mut wb, "set consistent off");
    ok(&mut wb, "run id");
    let back = wb.fresh_results().unwrap();
    for c in ["LeftLeg.Xrotation", "Hips.Xposition"] {
        let want = sim.q.column(sim.q.col_index(c).unwrap());
        let d = max_diff(&q_of(&wb, c), &want);
        assert!(d < 1e-9, "{c}: {d}");
    }
    assert_eq!(back.time.len(), sim.time.len());
}

#[test]
fn a_scene_applies_stature_up_positions_and_subtree_as_the_cli_does() {
    let dir = tempfile::tempdir().unwrap();
    let walk = articula::io::generate::walk(&articula::io::generate::WalkParams {
        duration_s: 0.5,
        ..Default::default()
    });
    articula::io::bvh::write(&walk, &dir.path().join("w.bvh")).unwrap();
    let scene = dir.path().join("s.toml");
    std::fs::write(
        &scene,
        "takes = [\"w.bvh\"]\nmass = 62\nstature = 1.5\nup = \"y\"\nposition = \"add\"\n\
         subtree = \"LeftUpLeg\"\nsmooth = \"gaussian:0.03\"\ngains = { kp = 900, kv = 60 }\n",
    )
    .unwrap();
    let mut wb = wb_in(dir.path());
    let msg = ok(&mut wb, "scene s.toml");
    assert!(!msg.contains("not applied"), "{msg}");
    assert_eq!((wb.params.kp.all, wb.params.kv.all), (900.0, 60.0));
    ok(&mut wb, "run id");
    let r = wb.fresh_results().unwrap().clone();
    // the CLI's path: the same options from the same file, the same take
    let opts = TakeOptions::from_scene_file(&scene).unwrap();
    assert_eq!(wb.params.take, opts);
    let mut t = pipeline::load_take(&dir.path().join("w.bvh"), &opts).unwrap();
    // `articula id`'s torques: with the ground reactions when contact auto finds the foot
    // down, of the take made consistent (the workbench's `consistent auto`)
    pipeline::resolve_contact(&mut t);
    let tau = if t.options.contact == pipeline::Contact::Feet {
        let (_, g, _) = pipeline::consistency::consistent_take(&t, true, None).unwrap();
        g.tau.concat()
    } else {
        pipeline::inverse_dynamics(&t.model, &t.states).tau.concat()
    };
    assert_eq!(r.model.nv, t.model.nv);
    assert!(r.model.nv < 66, "subtree keeps only the left leg's chain");
    assert_eq!(r.scale, t.scale_to_m);
    assert_eq!(r.tau.data, tau);
    // the stature was applied: 1.5 m instead of the walk's own 1.75-ish
    assert!((t.stature_m - 1.5).abs() < 1e-9, "{}", t.stature_m);
}

#[test]
fn inverse_dynamics_reports_progress_and_stops_when_asked() {
    let take =
        pipeline::load_take(&common::repo("data/demo_walk.bvh"), &TakeOptions::default()).unwrap();
    let n = take.states.len();
    let mut seen = vec![];
    let full = pipeline::inverse_dynamics_with(&take.model, &take.states, &mut |f| {
        seen.push(f);
        true
    });
    assert_eq!(full.tau.len(), n);
    assert_eq!(seen.len(), n.div_ceil(pipeline::PROGRESS_EVERY));
    assert!(seen.windows(2).all(|w| w[0] < w[1]) && seen[0] == 0.0 && *seen.last().unwrap() < 1.0);
    // the same numbers as the plain call the CLI makes
    assert_eq!(
        full.tau,
        pipeline::inverse_dynamics(&take.model, &take.states).tau
    );
    // stop at the third report: two blocks computed
    let mut calls = 0;
    let part = pipeline::inverse_dynamics_with(&take.model, &take.states, &mut |_| {
        calls += 1;
        calls < 3
    });
    assert_eq!(part.tau.len(), 2 * pipeline::PROGRESS_EVERY);
    assert_eq!(part.tau[..], full.tau[..2 * pipeline::PROGRESS_EVERY]);
}

#[test]
fn a_simulation_stops_mid_way_when_cancelled() {
    let take =
        pipeline::load_take(&common::repo("data/demo_walk.bvh"), &TakeOptions::default()).unwrap();
    let settings = pipeline::SimSettings::parse(
        "euler",
        0.001,
        &articula::pipeline::PerJoint::all(400.0),
        &articula::pipeline::PerJoint::all(40.0),
        0.0,
        None,
    )
    .unwrap();
    let mut last = 0.0;
    let mut calls = 0;
    let e = pipeline::simulate_states(&take.model, &take.states, &settings, &mut |f| {
        calls += 1;
        last = f;
        calls < 3
    })
    .unwrap_err();
    assert!(e.to_string().contains("cancelled"), "{e}");
    // 4 s at 1 ms: about 4000 steps, stopped after 2 × 256
    assert_eq!(calls, 3);
    assert!(last > 0.0 && last < 0.2, "{last}");
}

#[test]
fn a_job_cancelled_from_another_thread_leaves_the_workbench_as_it_was() {
    let dir = tempfile::tempdir().unwrap();
    let mut wb = wb_in(dir.path());
    ok(&mut wb, "load demo:walk");
    ok(&mut wb, "run id");
    let before = wb.fresh_results().unwrap().clone();
    ok(&mut wb, "set integrator rk4");
    ok(&mut wb, "set dt 0.0005");
    let job = wb.prepare(&Command::Run(RunKind::Sim)).unwrap().unwrap();
    let ctl = Arc::new(Control::default());
    let c = ctl.clone();
    // cancel once the simulation loop has reported some progress
    let canceller = std::thread::spawn(move || {
        while c.progress() < 0.06 {
            std::thread::yield_now();
        }
        c.cancel();
    });
    let done = job.run(&ctl);
    canceller.join().unwrap();
    assert!(
        ctl.progress() < 0.9,
        "stopped mid-way, not at the end: {}",
        ctl.progress()
    );
    let e = wb.finish(done).unwrap_err();
    assert!(e.to_string().contains("cancelled"), "{e}");
    // nothing changed: no simulation, the inverse dynamics as before, and it still runs
    assert!(wb.sim.is_none());
    assert!(Arc::ptr_eq(wb.latest_results().unwrap(), &before));
    ok(&mut wb, "set dt 0.004");
    ok(&mut wb, "run sim");
    assert!(wb.last_message().contains("tracking error"));
}

#[test]
fn export_bvh_of_the_ball_model_writes_its_smoothed_rotations() {
    // ball joints are smoothed on the rotation manifold; the file holds those rotations as
    // Euler channels, so read back (ball model, no smoothing) they are the same rotations
    let dir = tempfile::tempdir().unwrap();
    let mut wb = wb_in(dir.path());
    ok(&mut wb, "load demo:walk");
    ok(&mut wb, "set joints ball");
    ok(&mut wb, "set smooth gaussian:0.04");
    ok(&mut wb, "run id");
    let seen = wb.fresh_results().unwrap().clone();
    ok(&mut wb, "export bvh ball.bvh");
    ok(&mut wb, "set smooth none");
    ok(&mut wb, "load ball.bvh as back");
    ok(&mut wb, "run id");
    let back = wb.fresh_results().unwrap();
    for c in ["LeftLeg:wx", "RightUpLeg:wz", "Spine:wy"] {
        let a = articula::session::workbench::angle_series(&seen, c).unwrap();
        let b = articula::session::workbench::angle_series(back, c).unwrap();
        let d = max_diff(&a, &b);
        assert!(d < 1e-9, "{c}: {d}");
    }
}

/// `set kp.<joint>` / `set kv.<joint>` give one joint its own gains in `run sim`. With the
/// controller's model exact, feed-forward alone tracks up to the reference's interpolation and
/// the integrator's error, which the PD terms mop up: with zero gains on the left knee, the
/// knee's error grows, and the right knee, whose gains did not change, tracks as before. A name
/// that is no coordinate is refused once a take is loaded.
#[test]
fn gains_per_joint_reach_the_simulation() {
    let dir = tempfile::tempdir().unwrap();
    let walk = articula::io::generate::walk(&articula::io::generate::WalkParams {
        duration_s: 1.0,
        ..Default::default()
    });
    articula::io::bvh::write(&walk, &dir.path().join("w.bvh")).unwrap();
    let mut wb = wb_in(dir.path());
    ok(&mut wb, "load w.bvh");
    // before any results, a name that is no joint of the take is refused too
    let e = wb
        .apply(&parse_line("set kv.Knee 5", 1).unwrap().unwrap())
        .unwrap_err();
    assert!(e.to_string().contains("no joint 'Knee'"), "{e}");
    // one step per frame, so that the simulation is recorded at the take's own frames
    ok(&mut wb, &format!("set dt {}", walk.frame_time));
    ok(&mut wb, "run id");
    let err = |wb: &Workbench, c: &str| {
        let (sim, _) = wb.sim.as_ref().unwrap();
        let q = sim.q.column(sim.q.col_index(c).unwrap());
        let want = wb
            .results
            .as_ref()
            .unwrap()
            .0
            .q
            .column(sim.q.col_index(c).unwrap());
        assert_eq!(q.len(), want.len());
        max_diff(&q, &want)
    };
    ok(&mut wb, "run sim");
    let (left, right) = (
        err(&wb, "LeftLeg.Xrotation"),
        err(&wb, "RightLeg.Xrotation"),
    );
    ok(&mut wb, "set kp.LeftLeg 0");
    ok(&mut wb, "set kv.LeftLeg 0");
    assert_eq!(wb.params.kp.joints.get("LeftLeg"), Some(&0.0));
    ok(&mut wb, "run sim");
    let (limp, right_again) = (
        err(&wb, "LeftLeg.Xrotation"),
        err(&wb, "RightLeg.Xrotation"),
    );
    assert!(limp > 3.0 * left, "limp {limp} vs tracked {left}");
    assert!(
        (right_again - right).abs() < 0.5 * right,
        "{right_again} vs {right}"
    );
    let e = wb
        .apply(&parse_line("set kp.Knee 5", 1).unwrap().unwrap())
        .unwrap_err();
    assert!(e.to_string().contains("no coordinate"), "{e}");
}

/// Regression: `set body.mass 1e308` made every torque infinite, and `export csv` and
/// `compare weights` wrote NaN into files. Now the inverse dynamics fails with what to change,
/// and no file is written.
#[test]
fn an_absurd_body_mass_writes_no_nan() {
    let dir = tempfile::tempdir().unwrap();
    let walk = articula::io::generate::walk(&articula::io::generate::WalkParams {
        duration_s: 0.3,
        ..Default::default()
    });
    articula::io::bvh::write(&walk, &dir.path().join("w.bvh")).unwrap();
    let mut wb = wb_in(dir.path());
    ok(&mut wb, "load w.bvh");
    ok(&mut wb, "set body.mass 1e308");
    for line in [
        "export csv huge.csv",
        "compare weights 60,1e308 joint LeftLeg.Xrotation huge_cmp.csv",
    ] {
        let e = wb
            .apply(&parse_line(line, 1).unwrap().unwrap())
            .unwrap_err();
        assert!(e.to_string().contains("not finite"), "{line}: {e}");
    }
    assert!(!dir.path().join("huge.csv").exists());
    assert!(!dir.path().join("huge_cmp.csv").exists());
}

#[test]
fn a_take_that_cannot_load_under_the_settings_leaves_the_workbench_as_it_was() {
    // a keyframed take under an explicit 6 Hz filter: the file parses, the pipeline refuses
    // it; it used to become the active take, and every later command repeated the error
    let dir = tempfile::tempdir().unwrap();
    let mut b = articula::io::generate::walk(&articula::io::generate::WalkParams::default());
    b.frame_time = 1.0;
    articula::io::bvh::write(&b, &dir.path().join("keys.bvh")).unwrap();
    let mut wb = wb_in(dir.path());
    ok(&mut wb, "load demo:walk as walk");
    ok(&mut wb, "set smooth butterworth:6hz");
    ok(&mut wb, "run id");
    let before = q_of(&wb, "LeftLeg.Xrotation");
    let cmd = parse_line("load keys.bvh", 1).unwrap().unwrap();
    let e = wb.apply(&cmd).unwrap_err().to_string();
    assert!(e.contains("Nyquist"), "{e}");
    assert_eq!(wb.take().unwrap().name, "walk");
    assert_eq!(q_of(&wb, "LeftLeg.Xrotation"), before);
    ok(&mut wb, "run id");
    // with the default smoothing it loads (not smoothed, with a note)
    ok(&mut wb, "set smooth auto");
    let m = ok(&mut wb, "load keys.bvh");
    assert_eq!(wb.take().unwrap().name, "keys");
    // and the load says what it assumed (the notes reached only `articula info`)
    assert!(m.contains("note: not smoothed"), "{m}");
    // and so does the recompute that replaces the load message at once in the TUI
    let m = ok(&mut wb, "run id");
    assert!(m.contains("note: not smoothed"), "{m}");
    // a filter this take cannot take is refused by the set itself, and nothing changes
    let cmd = parse_line("set smooth butterworth:6hz", 1)
        .unwrap()
        .unwrap();
    let e = wb.apply(&cmd).unwrap_err().to_string();
    assert!(e.contains("Nyquist"), "{e}");
    assert_eq!(wb.params.take.smooth, None);
}
