//! Headless replay of sessions over the generated demo walk: outputs land under the output
//! folder, a passing `expect` passes, a failing one fails the replay with its line number, and
//! two replays write byte-identical files.

use articula::tui::run_session;
use std::path::Path;

fn write(dir: &Path, name: &str, text: &str) -> std::path::PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

const STUDY: &str = "\
# knee torque of the demo walk at two body masses
load demo:walk as walk
set body.mass 80
set smooth gaussian:0.02
expect frames 480
expect nv 66
expect mass between 79.99 80.01
select LeftLeg.Xrotation
expect selected LeftLeg.Xrotation
expect peak LeftLeg.Xrotation torque between 1 400
expect max LeftLeg.Xrotation angle between 0.5rad 1.5rad
export csv torques.csv
expect message contains torques.csv
set body.segments fractions
compare weights 60,100 joint LeftLeg.Xrotation knee.csv
set body.segments regression
compare weights 60,80,100 joint LeftLeg.Xrotation knee.svg
export svg knee_angle_torque.svg
set motor.gear 30
report motor motors.svg
expect message contains LeftLeg.Xrotation BLDC
frame 240
key ]]
expect frame 242
screen screen.txt
expect screen contains LeftLeg.Xrotation torque
";

#[test]
fn a_study_replays_and_writes_its_outputs_deterministically() {
    let dir = tempfile::tempdir().unwrap();
    let session = write(dir.path(), "study.session", STUDY);
    let out1 = dir.path().join("out1");
    let out2 = dir.path().join("out2");
    let r1 = run_session(&session, &out1).unwrap_or_else(|e| panic!("{e}"));
    let r2 = run_session(&session, &out2).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(r1.expects, 10);
    assert_eq!((r1.commands, r1.expects), (r2.commands, r2.expects));
    assert_eq!(r1.written.len(), 6);
    for name in [
        "torques.csv",
        "knee.csv",
        "knee.svg",
        "knee_angle_torque.svg",
        "motors.svg",
        "screen.txt",
    ] {
        let a = std::fs::read(out1.join(name)).unwrap();
        let b = std::fs::read(out2.join(name)).unwrap();
        assert!(!a.is_empty());
        assert_eq!(a, b, "{name} differs between replays");
    }
    // the CSV: a header with time, q, v, a and tau columns, one row per frame
    let csv = std::fs::read_to_string(out1.join("torques.csv")).unwrap();
    let header = csv.lines().next().unwrap();
    assert!(header.starts_with("time,q:Hips.Xposition"));
    assert!(header.contains(",tau:LeftLeg.Xrotation"));
    assert_eq!(csv.lines().count(), 481);
    assert_eq!(header.split(',').count(), 1 + 4 * 66);
    // with de Leva's fractions the knee torque scales with body mass (the masses scale every
    // link alike), on every row to the residual reduction's tolerance (the workbench reduces
    // with contact; its "met" threshold is a share of body weight, so both masses take the
    // same steps up to where two costs agree to rounding: 1e-6; an absolute threshold once
    // made 60 and 100 kg reduce differently, up to 4 % apart)
    let knee = std::fs::read_to_string(out1.join("knee.csv")).unwrap();
    assert!(
        knee.starts_with("time,tau:LeftLeg.Xrotation:60kg,tau:LeftLeg.Xrotation:100kg\n"),
        "{knee}"
    );
    for row in knee.lines().skip(1) {
        let v: Vec<f64> = row.split(',').map(|x| x.parse().unwrap()).collect();
        assert!(
            (v[2] - v[1] * 100.0 / 60.0).abs() < 1e-6 * v[2].abs().max(1.0),
            "{row}"
        );
    }
    // the charts are valid SVG with the expected labels
    for (name, labels) in [
        (
            "knee.svg",
            &["60 kg", "80 kg", "100 kg", "LeftLeg.Xrotation"][..],
        ),
        (
            "knee_angle_torque.svg",
            &["angle (deg)", "torque (N·m)", "max"][..],
        ),
        (
            "motors.svg",
            &["LeftLeg.Xrotation", "LeftLeg.Zrotation"][..],
        ),
    ] {
        let svg = std::fs::read_to_string(out1.join(name)).unwrap();
        roxmltree::Document::parse(&svg).unwrap_or_else(|e| panic!("{name}: {e}"));
        for l in labels {
            assert!(svg.contains(l), "{name} lacks {l}");
        }
    }
}

#[test]
fn a_failing_expect_fails_the_replay_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    let session = write(
        dir.path(),
        "bad.session",
        "load demo:walk\n# impossible range\n\nexpect peak LeftLeg.Xrotation torque between 1000 2000\nexport csv never.csv\n",
    );
    let err = run_session(&session, &dir.path().join("out")).unwrap_err();
    assert_eq!(err.line(), Some(4));
    assert!(err.is_expect());
    let shown = err.to_string();
    assert!(shown.contains("bad.session:4:"), "{shown}");
    assert!(shown.contains(" N·m not in [1000, 2000] N·m"), "{shown}");
    // nothing after the failure ran
    assert!(!dir.path().join("out/never.csv").exists());
}

#[test]
fn a_failing_command_and_a_syntax_error_carry_their_lines() {
    let dir = tempfile::tempdir().unwrap();
    let s = write(dir.path(), "a.session", "load demo:walk\nselect Tail\n");
    let err = run_session(&s, &dir.path().join("out")).unwrap_err();
    assert_eq!(err.line(), Some(2));
    assert!(!err.is_expect());
    assert!(err.to_string().contains("no joint called 'Tail'"), "{err}");

    // a syntax error anywhere stops the replay before anything runs
    let s = write(
        dir.path(),
        "b.session",
        "load demo:walk\nexport csv x.csv\nfrobnicate\n",
    );
    let err = run_session(&s, &dir.path().join("out2")).unwrap_err();
    assert_eq!(err.line(), Some(3));
    assert!(
        err.to_string().starts_with(&format!("{}:3: ", s.display())),
        "{err}"
    );
    assert!(!dir.path().join("out2/x.csv").exists());
}

#[test]
fn a_bvh_file_next_to_the_session_loads_by_relative_path() {
    let dir = tempfile::tempdir().unwrap();
    let walk = articula::io::generate::walk(&articula::io::generate::WalkParams {
        duration_s: 1.0,
        ..Default::default()
    });
    articula::io::bvh::write(&walk, &dir.path().join("short walk.bvh")).unwrap();
    let s = write(
        dir.path(),
        "s.session",
        "load \"short walk.bvh\" as w\nexpect frames 120\nselect RightLeg\n# a joint selects its largest range of motion: knee flexion\nexpect selected RightLeg.Xrotation\nexpect rms RightLeg.Xrotation torque between 0.1 500\n",
    );
    let r = run_session(&s, &dir.path().join("out")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(r.expects, 3);
    assert!(
        r.messages[0].starts_with("loaded w (21 joints, 120 frames"),
        "{:?}",
        r.messages
    );
}

#[test]
fn screen_dump_for_the_readme() {
    // `screen` writes what the TUI shows; print it with --nocapture
    let dir = tempfile::tempdir().unwrap();
    let s = write(
        dir.path(),
        "s.session",
        "load demo:walk\nselect LeftLeg.Xrotation\nframe 60\nkey <Tab><Tab>\nscreen s.txt\nexpect screen contains Parameters\n",
    );
    run_session(&s, dir.path()).unwrap_or_else(|e| panic!("{e}"));
    let text = std::fs::read_to_string(dir.path().join("s.txt")).unwrap();
    println!("{text}");
    assert_eq!(text.lines().count(), 30);
    // the avatar pane holds braille dots (the superquadric links)
    assert!(
        text.chars()
            .filter(|c| ('\u{2801}'..='\u{28FF}').contains(c))
            .count()
            > 50
    );
}

#[test]
fn blend_then_export_bvh_and_urdf_and_reload() {
    let dir = tempfile::tempdir().unwrap();
    let s = write(
        dir.path(),
        "blend.session",
        "\
load demo:walk as a
load demo:walk as b
blend a b 1.0:1.5
expect message contains as a+b (480 frames)
export bvh blended.bvh
export urdf walker.urdf
load out/blended.bvh as again
expect frames 480
# a walk blended with itself is the walk
expect peak LeftLeg.Xrotation angle between 1.0rad 1.2rad
blend a nothing 1.0:1.5
",
    );
    let err = run_session(&s, &dir.path().join("out")).unwrap_err();
    // everything up to the last line ran; the last fails on the unknown take
    assert_eq!(err.line(), Some(11), "{err}");
    assert!(
        err.to_string().contains("no take called 'nothing'"),
        "{err}"
    );
    let urdf = std::fs::read_to_string(dir.path().join("out/walker.urdf")).unwrap();
    let doc = roxmltree::Document::parse(&urdf).unwrap();
    assert!(
        doc.descendants()
            .any(|n| n.has_tag_name("joint") && n.attribute("name") == Some("LeftLeg.Xrotation"))
    );
}

#[test]
fn ball_joints_and_foot_contact_run_through_the_pipeline() {
    let dir = tempfile::tempdir().unwrap();
    let s = write(
        dir.path(),
        "m.session",
        "\
load demo:walk
set contact feet
expect nv 66
# finite and non-zero (the size of the stance-knee torque with estimated ground reactions is
# the grf module's business)
expect peak LeftLeg.Xrotation torque between 1 10000
set contact none
set joints ball
expect nq 87
expect peak LeftLeg:wx torque between 1 400
",
    );
    let r = run_session(&s, &dir.path().join("out")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(r.expects, 4);
}

#[test]
fn run_sim_tracks_the_take_and_reports_its_error() {
    let dir = tempfile::tempdir().unwrap();
    let walk = articula::io::generate::walk(&articula::io::generate::WalkParams {
        duration_s: 0.5,
        ..Default::default()
    });
    articula::io::bvh::write(&walk, &dir.path().join("w.bvh")).unwrap();
    let s = write(
        dir.path(),
        "sim.session",
        "load w.bvh\nset integrator rk4\nset dt 0.002\nrun sim\nexpect message contains tracking error RMS\n",
    );
    let r = run_session(&s, &dir.path().join("out")).unwrap_or_else(|e| panic!("{e}"));
    let msg = r
        .messages
        .iter()
        .find(|m| m.starts_with("simulation"))
        .unwrap();
    assert!(msg.contains("nv 66"), "{msg}");
}

#[test]
fn a_scene_sets_the_parameters_and_loads_its_takes() {
    let dir = tempfile::tempdir().unwrap();
    let walk = articula::io::generate::walk(&articula::io::generate::WalkParams {
        duration_s: 0.5,
        ..Default::default()
    });
    articula::io::bvh::write(&walk, &dir.path().join("w.bvh")).unwrap();
    write(
        dir.path(),
        "study.toml",
        "takes = [\"w.bvh\"]\nmass = 60\nsex = \"female\"\nsmooth = \"none\"\nlock = [\"LeftHand\", \"RightHand\"]\n",
    );
    let s = write(
        dir.path(),
        "s.session",
        "scene study.toml\nexpect frames 60\nexpect mass between 59.999 60.001\nexpect nv 60\n",
    );
    let r = run_session(&s, &dir.path().join("out")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(r.expects, 3);
}
