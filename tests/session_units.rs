//! Units the user sees. A number of a session may carry its unit (`40deg`, `0.7rad`, `12cm`,
//! `500ms`, `80kg`); a bare number in `expect … angle|velocity|acceleration` is in the unit the
//! workbench shows (deg, deg/s, deg/s² on a rotation, m on a translation). The same bound
//! written in another unit gives the same verdict (metamorphic), a unit of the wrong quantity
//! is an error naming the line and the units it takes, and messages print each coordinate's
//! own unit, rounded to what is meaningful.

mod common;

use articula::session::Workbench;
use articula::session::units::{self, Kind, UNITS};
use articula::tui::run_session;
use std::path::Path;

use common::workbench::{apply, fails, ok, wb_in};

/// The demo walk with the knee-load study's settings (sessions/knee_load.session).
fn walk(out: &Path) -> Workbench {
    let mut wb = wb_in(out);
    ok(&mut wb, "load demo:walk as walk");
    ok(&mut wb, "set body.mass 80kg");
    ok(&mut wb, "set smooth butterworth:6hz");
    ok(&mut wb, "set contact feet");
    ok(&mut wb, "run id");
    wb
}

#[test]
fn an_angle_bound_means_the_same_in_bare_degrees_deg_and_rad() {
    let out = tempfile::tempdir().unwrap();
    let mut wb = walk(out.path());
    let r = wb.fresh_results().unwrap().clone();
    let q = articula::session::workbench::angle_series(&r, "LeftLeg.Xrotation").unwrap();
    let max_deg = q.iter().copied().fold(f64::MIN, f64::max).to_degrees();
    // the knee flexes by tens of degrees: within 30°‥70° (a bare rad reading would be 1700°+)
    assert!((30.0..70.0).contains(&max_deg), "{max_deg}");
    ok(
        &mut wb,
        "expect max LeftLeg.Xrotation angle between 30deg 70deg",
    );
    ok(&mut wb, "expect max LeftLeg.Xrotation angle between 30 70");
    ok(
        &mut wb,
        "expect max LeftLeg.Xrotation angle between 30° 70°",
    );
    ok(
        &mut wb,
        "expect max LeftLeg.Xrotation angle between 0.5236rad 1.2217rad",
    );
    // just above and just below the value, in each unit: all fail
    for (lo, hi) in [
        (max_deg + 0.05, max_deg + 1.0),
        (max_deg - 1.0, max_deg - 0.05),
    ] {
        for line in [
            format!("expect max LeftLeg.Xrotation angle between {lo} {hi}"),
            format!("expect max LeftLeg.Xrotation angle between {lo}deg {hi}deg"),
            format!(
                "expect max LeftLeg.Xrotation angle between {}rad {}rad",
                lo.to_radians(),
                hi.to_radians()
            ),
        ] {
            let e = fails(&mut wb, &line);
            assert!(e.contains(" deg not in ["), "{line}: {e}");
        }
    }
    // a velocity bound in deg/s and in rad/s
    let v = r.v.column(r.v.col_index("LeftLeg.Xrotation").unwrap());
    let peak = v.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    ok(
        &mut wb,
        &format!(
            "expect peak LeftLeg.Xrotation velocity between {} {}",
            peak.to_degrees() * 0.99,
            peak.to_degrees() * 1.01
        ),
    );
    ok(
        &mut wb,
        &format!(
            "expect peak LeftLeg.Xrotation velocity between {}rad/s {}rad/s",
            peak * 0.99,
            peak * 1.01
        ),
    );
    fails(
        &mut wb,
        &format!(
            "expect peak LeftLeg.Xrotation velocity between {} {}",
            peak * 0.99,
            peak * 1.01
        ),
    );
}

#[test]
fn a_failed_expect_prints_the_value_rounded_in_the_coordinates_own_unit() {
    let out = tempfile::tempdir().unwrap();
    let mut wb = walk(out.path());
    let e = fails(
        &mut wb,
        "expect peak LeftLeg.Xrotation torque between 110 120",
    );
    insta::assert_snapshot!(e, @"expect failed: peak LeftLeg.Xrotation torque 146.2 N·m not in [110, 120] N·m");
    let e = fails(&mut wb, "expect max LeftLeg.Xrotation angle between 10 20");
    insta::assert_snapshot!(e, @"expect failed: max LeftLeg.Xrotation angle 57.9 deg not in [10, 20] deg");
    // bounds written in rad are shown back in the coordinate's unit
    let e = fails(
        &mut wb,
        "expect max LeftLeg.Xrotation angle between 0.1rad 0.2rad",
    );
    insta::assert_snapshot!(e, @"expect failed: max LeftLeg.Xrotation angle 57.9 deg not in [5.72958, 11.4592] deg");
    let e = fails(&mut wb, "expect mass between 90 100");
    insta::assert_snapshot!(e, @"expect failed: total mass 80.00 kg not in [90, 100] kg");
    // a passing expect says so in the same words
    let m = ok(
        &mut wb,
        "expect peak LeftLeg.Xrotation torque between 110 160",
    );
    assert_eq!(
        m,
        "ok: peak LeftLeg.Xrotation torque 146.2 N·m in [110, 160] N·m"
    );
    // no message prints 17 digits or the old `rad|m`
    for m in &wb.messages {
        assert!(!m.contains("rad|m"), "{m}");
    }
}

#[test]
fn rounding_never_hides_which_side_of_a_tight_bound_a_value_is() {
    // 131.42 N·m against [131.4, 131.41]: 131.4 would read as inside
    let m = units::format_check(Kind::Torque, 131.42, 131.4, 131.41);
    assert_eq!(m, "131.42 N·m not in [131.4, 131.41] N·m");
    // just above a bound reads as above it, not below the other; below reads as below
    let m = units::format_check(Kind::Torque, 31.64001, 31.6398, 31.64);
    assert_eq!(m, "31.64001 N·m not in [31.6398, 31.64] N·m");
    let m = units::format_check(Kind::Torque, 31.63979, 31.6398, 31.64);
    assert_eq!(m, "31.6 N·m not in [31.6398, 31.64] N·m");
    let m = units::format_check(Kind::Torque, 31.63988, 31.6398, 31.64);
    assert_eq!(m, "31.64 N·m in [31.6398, 31.64] N·m");
}

#[test]
fn display_rules_round_each_kind_to_what_is_meaningful() {
    let cases = [
        (Kind::Angle, 1.0, "57.3 deg"),
        (Kind::Angle, -0.0001, "-0.0057 deg"),
        (Kind::Angle, -1e-9, "0.0 deg"),
        (Kind::Length, 0.91234, "0.912 m"),
        (
            Kind::AngularVelocity,
            std::f64::consts::PI * 1.25,
            "225.0 deg/s",
        ),
        (Kind::Torque, 131.4213, "131.4 N·m"),
        (Kind::Torque, 0.028252, "0.0283 N·m"),
        (Kind::Force, 5.2, "5.20 N"),
        (Kind::Mass, 3.8479, "3.85 kg"),
        (Kind::Time, 0.5, "0.500 s"),
    ];
    for (kind, si, want) in cases {
        assert_eq!(units::format_value(kind, si), want, "{kind:?} {si}");
    }
    // every kind is shown in a unit a session may write it in, so what the workbench shows can
    // be typed back
    for kind in [
        Kind::Angle,
        Kind::Length,
        Kind::AngularVelocity,
        Kind::Velocity,
        Kind::AngularAcceleration,
        Kind::Acceleration,
        Kind::Torque,
        Kind::Force,
        Kind::Mass,
        Kind::Time,
        Kind::Frequency,
    ] {
        let shown = units::shown_unit(kind);
        let u = UNITS.iter().find(|u| u.symbol == shown && u.kind == kind);
        let u = u.unwrap_or_else(|| panic!("{kind:?} is shown in {shown}, not in UNITS"));
        // and a value shown is read back to within its rounding
        let (x, _) = units::shown(kind, 1.234);
        assert!((x * u.to_si - 1.234).abs() < 1e-12, "{kind:?}");
        let back = units::parse_si(&units::format_number(kind, 1.234), kind, "x").unwrap();
        assert!((back - 1.234).abs() < 0.01, "{kind:?}: {back}");
    }
}

#[test]
fn a_prismatic_coordinate_is_in_metres_and_its_force_in_newtons() {
    // the Stanford arm's third joint slides
    let out = tempfile::tempdir().unwrap();
    let mut wb = wb_in(out.path());
    ok(&mut wb, "load data/stanford.toml");
    ok(
        &mut wb,
        "trajectory 0,0,0.2,0,0,0 0,0,30cm,0,0,0 over 0.5 at 100",
    );
    ok(&mut wb, "frame 0");
    // bare is metres on a translation; cm and mm as written
    ok(&mut wb, "expect now j3 angle between 0.19 0.21");
    ok(&mut wb, "expect now j3 angle between 19cm 210mm");
    ok(&mut wb, "expect max j3 angle between 29.9cm 30.1cm");
    let e = fails(&mut wb, "expect now j3 angle between 0.5 0.6");
    assert!(
        e.ends_with("now j3 angle 0.200 m not in [0.5, 0.6] m"),
        "{e}"
    );
    let e = fails(&mut wb, "expect peak j3 torque between 1e6 2e6");
    assert!(e.contains(" N not in [1000000, 2000000] N"), "{e}");
    assert!(!e.contains("N·m"), "{e}");
    // an angle on a translation, a length on a rotation: errors naming the units they take
    let e = apply(&mut wb, "expect now j3 angle between 10deg 20deg").unwrap_err();
    assert!(
        e.contains("'10deg' is an angle; the angle of j3 (a translation) takes m, cm, mm"),
        "{e}"
    );
    let e = apply(&mut wb, "expect now j2 angle between 1cm 2cm").unwrap_err();
    assert!(
        e.contains("'1cm' is a length; the angle of j2 (a rotation) takes deg, °, rad"),
        "{e}"
    );
    let e = apply(&mut wb, "expect peak j3 torque between 1N·m 2N·m").unwrap_err();
    assert!(e.contains("takes N (force; a bare number is N)"), "{e}");
    // a pose of deg on the slider is refused, and nothing changes
    let e = apply(&mut wb, "trajectory 0,0,10deg,0,0,0 over 0.5").unwrap_err();
    assert!(
        e.contains("j3 (a prismatic coordinate) takes m, cm, mm"),
        "{e}"
    );
    ok(&mut wb, "expect frames 51");
}

#[test]
fn a_pose_in_degrees_is_the_pose_in_radians() {
    let out = tempfile::tempdir().unwrap();
    let mut wb = wb_in(out.path());
    ok(&mut wb, "load data/puma560.toml");
    ok(&mut wb, "trajectory 0,pi/4,-pi,0,pi/4,0 over 0.5 at 100");
    ok(&mut wb, "run id");
    let rad = wb.fresh_results().unwrap().clone();
    ok(
        &mut wb,
        "trajectory 0,45deg,-180°,0deg,0.7853981633974483rad,0 over 500ms at 100Hz",
    );
    ok(&mut wb, "run id");
    let deg = wb.fresh_results().unwrap();
    for (a, b) in rad.tau.row(0).iter().zip(deg.tau.row(0)) {
        assert!((a - b).abs() < 1e-12, "{a} vs {b}");
    }
    assert_eq!(rad.time, deg.time);
    // the gravity load of j2 at qn, as the Robotics Toolbox gives it (31.63988 N·m)
    ok(&mut wb, "expect max j2 torque between 31.6398N·m 31.64Nm");
}

#[test]
fn set_values_take_their_units_and_refuse_others() {
    let out = tempfile::tempdir().unwrap();
    let mut wb = wb_in(out.path());
    ok(&mut wb, "load demo:walk");
    ok(&mut wb, "set body.mass 72.5kg");
    assert_eq!(wb.params.take.body.mass_kg, 72.5);
    ok(&mut wb, "set dt 2ms");
    assert!((wb.params.dt - 0.002).abs() < 1e-15);
    ok(&mut wb, "set blend.window 250ms");
    assert!((wb.params.blend_window - 0.25).abs() < 1e-15);
    ok(&mut wb, "set stature 175cm");
    assert!((wb.params.take.stature_m.unwrap() - 1.75).abs() < 1e-12);
    let e = apply(&mut wb, "set dt 5kg").unwrap_err();
    assert!(
        e.contains("'5kg' is a mass; a positive step in seconds takes s, ms"),
        "{e}"
    );
    let e = apply(&mut wb, "set kp 400deg").unwrap_err();
    assert!(e.contains("is a plain number, without a unit"), "{e}");
    let e = apply(&mut wb, "set body.mass 80N").unwrap_err();
    assert!(e.contains("'80N' is a force"), "{e}");
    // nothing changed by the refused values
    assert!((wb.params.dt - 0.002).abs() < 1e-15);
    assert_eq!(wb.params.take.body.mass_kg, 72.5);
}

#[test]
fn a_wrong_unit_in_a_session_file_names_the_line_and_the_units_it_takes() {
    let dir = tempfile::tempdir().unwrap();
    let s = dir.path().join("bad.session");
    std::fs::write(
        &s,
        "load demo:walk\nselect LeftLeg\nexpect peak LeftLeg.Xrotation torque between 10deg 20deg\n",
    )
    .unwrap();
    let e = run_session(&s, &dir.path().join("out")).unwrap_err();
    assert_eq!(e.line(), Some(3));
    let shown = e.to_string();
    assert!(shown.contains("bad.session:3: '10deg' is an angle; a torque takes N·m, Nm, N.m"));
    assert!(shown.contains("or N (force"), "{shown}");
    // nothing ran: the whole file is parsed first
    assert!(!dir.path().join("out").exists());
}

#[test]
fn a_session_of_degrees_and_explicit_units_replays() {
    let dir = tempfile::tempdir().unwrap();
    let s = dir.path().join("units.session");
    std::fs::write(
        &s,
        "\
load demo:walk as walk
set body.mass 80kg
set smooth butterworth:6hz
set contact feet
# the take as loaded (residual reduction, on by default with contact, moves the knee's peak);
# its peak torque is of the frames whose residuals are within Hicks et al.'s thresholds
# (88 of 458 here: the other frames need a force the feet cannot give and are not quoted)
set consistent off
# the knee flexes to 58 deg: bare degrees, deg, and rad
expect max LeftLeg.Xrotation angle between 30deg 60deg
expect max LeftLeg.Xrotation angle between 50 60
expect max LeftLeg.Xrotation angle between 0.7rad 1.1rad
expect peak LeftLeg.Xrotation torque between 85N·m 100Nm
expect mass between 79.99kg 80.01kg
set joints ball
# a ball joint's rotation-vector component is an angle in deg too
expect peak LeftLeg:wx angle between 30 90
",
    )
    .unwrap();
    let r = run_session(&s, &dir.path().join("out")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(r.expects, 6);
    assert!(
        r.messages
            .iter()
            .any(|m| m.starts_with("ok: max LeftLeg.Xrotation angle 57.9 deg in [30, 60] deg")),
        "{:?}",
        r.messages
    );
}

#[test]
fn the_tracking_error_is_in_degrees() {
    let out = tempfile::tempdir().unwrap();
    let mut wb = wb_in(out.path());
    ok(&mut wb, "load data/puma560.toml");
    ok(&mut wb, "trajectory 0,0,0,0,0,0 0,1,0,0,0,0 over 0.2 at 50");
    let m = ok(&mut wb, "run sim");
    assert!(
        m.contains("tracking error RMS ") && m.contains(" deg, max "),
        "{m}"
    );
    assert!(m.ends_with(" deg"), "{m}");
    assert!(!m.contains("rad") && !m.contains("e-"), "{m}");
}
