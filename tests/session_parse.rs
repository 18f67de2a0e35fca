//! Every command of the session language parses to the command it names, and every malformed
//! line is refused with its line number and what was expected.

use articula::session::command::{Expectation, Quantity, Statistic};
use articula::session::units::{Measure, UNITS};
use articula::session::{Command, ExportKind, RunKind, SessionError, parse_line, parse_session};
use std::path::PathBuf;

fn one(line: &str) -> Command {
    parse_line(line, 1)
        .unwrap_or_else(|e| panic!("{line}: {e}"))
        .unwrap_or_else(|| panic!("{line}: no command"))
}

/// A number as written without a unit.
fn bare(value: f64) -> Measure {
    Measure { value, unit: None }
}

/// A number written with `symbol` after it.
fn with(value: f64, symbol: &str) -> Measure {
    let unit = UNITS.iter().find(|u| u.symbol == symbol).copied();
    assert!(unit.is_some(), "no unit {symbol}");
    Measure { value, unit }
}

#[test]
fn every_command_parses() {
    let p = PathBuf::from;
    let cases: Vec<(&str, Command)> = vec![
        (
            "load walk.bvh",
            Command::Load {
                path: p("walk.bvh"),
                name: None,
            },
        ),
        (
            "load \"my take.bvh\" as a",
            Command::Load {
                path: p("my take.bvh"),
                name: Some("a".into()),
            },
        ),
        (
            "scene study.toml",
            Command::Scene {
                path: p("study.toml"),
            },
        ),
        (
            "set body.mass 80",
            Command::Set {
                key: "body.mass".into(),
                value: "80".into(),
            },
        ),
        (
            "set body.sex female",
            Command::Set {
                key: "body.sex".into(),
                value: "female".into(),
            },
        ),
        (
            "set unit cm",
            Command::Set {
                key: "unit".into(),
                value: "cm".into(),
            },
        ),
        (
            "set joints ball",
            Command::Set {
                key: "joints".into(),
                value: "ball".into(),
            },
        ),
        (
            "set smooth butterworth:6hz",
            Command::Set {
                key: "smooth".into(),
                value: "butterworth:6hz".into(),
            },
        ),
        (
            "set contact feet",
            Command::Set {
                key: "contact".into(),
                value: "feet".into(),
            },
        ),
        (
            "set kp 400",
            Command::Set {
                key: "kp".into(),
                value: "400".into(),
            },
        ),
        (
            "set kv 40",
            Command::Set {
                key: "kv".into(),
                value: "40".into(),
            },
        ),
        (
            "set integrator rk4",
            Command::Set {
                key: "integrator".into(),
                value: "rk4".into(),
            },
        ),
        (
            "set dt 0.001",
            Command::Set {
                key: "dt".into(),
                value: "0.001".into(),
            },
        ),
        (
            "set link.LeftLeg.mass 3.5",
            Command::Set {
                key: "link.LeftLeg.mass".into(),
                value: "3.5".into(),
            },
        ),
        (
            "set lock LeftHand, RightHand",
            Command::Set {
                key: "lock".into(),
                value: "LeftHand, RightHand".into(),
            },
        ),
        (
            "set blend.window 0.4",
            Command::Set {
                key: "blend.window".into(),
                value: "0.4".into(),
            },
        ),
        ("run id", Command::Run(RunKind::Id)),
        ("run sim", Command::Run(RunKind::Sim)),
        (
            "blend a b 2.0:2.6",
            Command::Blend {
                a: "a".into(),
                b: "b".into(),
                window: (2.0, 2.6),
            },
        ),
        (
            "select LeftLeg.Xrotation",
            Command::Select("LeftLeg.Xrotation".into()),
        ),
        ("frame 12", Command::Frame(12)),
        ("play", Command::Play),
        ("pause", Command::Pause),
        ("quit", Command::Quit),
        (
            "export csv out.csv",
            Command::Export {
                kind: ExportKind::Csv,
                path: p("out.csv"),
            },
        ),
        (
            "export svg k.svg",
            Command::Export {
                kind: ExportKind::Svg,
                path: p("k.svg"),
            },
        ),
        (
            "export bvh o.bvh",
            Command::Export {
                kind: ExportKind::Bvh,
                path: p("o.bvh"),
            },
        ),
        (
            "export urdf o.urdf",
            Command::Export {
                kind: ExportKind::Urdf,
                path: p("o.urdf"),
            },
        ),
        (
            "export mjcf o.xml",
            Command::Export {
                kind: ExportKind::Mjcf,
                path: p("o.xml"),
            },
        ),
        (
            "compare weights 60,80,100 knee.csv",
            Command::CompareWeights {
                masses: vec![60.0, 80.0, 100.0],
                joint: None,
                path: p("knee.csv"),
            },
        ),
        (
            "compare weights 60,80 joint LeftLeg knee.svg",
            Command::CompareWeights {
                masses: vec![60.0, 80.0],
                joint: Some("LeftLeg".into()),
                path: p("knee.svg"),
            },
        ),
        (
            "report motor motors.svg",
            Command::ReportMotor {
                path: p("motors.svg"),
                curves: false,
            },
        ),
        (
            "report motor curves c.csv",
            Command::ReportMotor {
                path: p("c.csv"),
                curves: true,
            },
        ),
        (
            "export bvh sim s.bvh",
            Command::Export {
                kind: ExportKind::BvhSim,
                path: p("s.bvh"),
            },
        ),
        (
            "trajectory 0,pi/4 -pi/2,0.5 over 1.5 at 200",
            Command::Trajectory {
                poses: vec![
                    vec![bare(0.0), bare(std::f64::consts::FRAC_PI_4)],
                    vec![bare(-std::f64::consts::FRAC_PI_2), bare(0.5)],
                ],
                duration_s: 1.5,
                rate_hz: 200.0,
            },
        ),
        (
            "trajectory 3pi/4,0.5*pi over 2s",
            Command::Trajectory {
                poses: vec![vec![
                    bare(3.0 * std::f64::consts::PI / 4.0),
                    bare(0.5 * std::f64::consts::PI),
                ]],
                duration_s: 2.0,
                rate_hz: 500.0,
            },
        ),
        (
            "trajectory 0,45deg,-pi/2rad,5cm 10°,0,0,0.1m over 500ms at 200Hz",
            Command::Trajectory {
                poses: vec![
                    vec![
                        bare(0.0),
                        with(45.0, "deg"),
                        with(-std::f64::consts::FRAC_PI_2, "rad"),
                        with(5.0, "cm"),
                    ],
                    vec![with(10.0, "°"), bare(0.0), bare(0.0), with(0.1, "m")],
                ],
                duration_s: 0.5,
                rate_hz: 200.0,
            },
        ),
        (
            "set motor.j2.gear 107.815",
            Command::Set {
                key: "motor.j2.gear".into(),
                value: "107.815".into(),
            },
        ),
        (
            "set motor.LeftLeg.Xrotation.km 0.2",
            Command::Set {
                key: "motor.LeftLeg.Xrotation.km".into(),
                value: "0.2".into(),
            },
        ),
        ("expect nv 69", Command::Expect(Expectation::Nv(69))),
        ("expect nq 70", Command::Expect(Expectation::Nq(70))),
        (
            "expect frames 480",
            Command::Expect(Expectation::Frames(480)),
        ),
        ("expect frame 3", Command::Expect(Expectation::Frame(3))),
        (
            "expect selected Hips.Zrotation",
            Command::Expect(Expectation::Selected("Hips.Zrotation".into())),
        ),
        (
            "expect mass between 74 76",
            Command::Expect(Expectation::Mass { lo: 74.0, hi: 76.0 }),
        ),
        (
            "expect peak LeftLeg.Xrotation torque between 20 150",
            Command::Expect(Expectation::Stat {
                stat: Statistic::Peak,
                coord: "LeftLeg.Xrotation".into(),
                quantity: Quantity::Torque,
                lo: bare(20.0),
                hi: bare(150.0),
            }),
        ),
        (
            "expect max LeftLeg.Xrotation angle between 30deg 1.05rad",
            Command::Expect(Expectation::Stat {
                stat: Statistic::Max,
                coord: "LeftLeg.Xrotation".into(),
                quantity: Quantity::Angle,
                lo: with(30.0, "deg"),
                hi: with(1.05, "rad"),
            }),
        ),
        (
            "expect now j3 angle between 12cm 0.2m",
            Command::Expect(Expectation::Stat {
                stat: Statistic::Now,
                coord: "j3".into(),
                quantity: Quantity::Angle,
                lo: with(12.0, "cm"),
                hi: with(0.2, "m"),
            }),
        ),
        (
            "expect peak j2 torque between 30N·m 32Nm",
            Command::Expect(Expectation::Stat {
                stat: Statistic::Peak,
                coord: "j2".into(),
                quantity: Quantity::Torque,
                lo: with(30.0, "N·m"),
                hi: with(32.0, "Nm"),
            }),
        ),
        (
            "expect mean j3 acceleration between -2deg/s2 2°/s²",
            Command::Expect(Expectation::Stat {
                stat: Statistic::Mean,
                coord: "j3".into(),
                quantity: Quantity::Acceleration,
                lo: with(-2.0, "deg/s2"),
                hi: with(2.0, "°/s²"),
            }),
        ),
        (
            "expect mass between 74kg 76",
            Command::Expect(Expectation::Mass { lo: 74.0, hi: 76.0 }),
        ),
        (
            "blend a b 1s:1500ms",
            Command::Blend {
                a: "a".into(),
                b: "b".into(),
                window: (1.0, 1.5),
            },
        ),
        (
            "expect rms Hips.Yposition velocity between 0 1e3",
            Command::Expect(Expectation::Stat {
                stat: Statistic::Rms,
                coord: "Hips.Yposition".into(),
                quantity: Quantity::Velocity,
                lo: bare(0.0),
                hi: bare(1000.0),
            }),
        ),
        (
            "expect screen contains LeftLeg torque",
            Command::Expect(Expectation::ScreenContains("LeftLeg torque".into())),
        ),
        (
            "expect message contains wrote",
            Command::Expect(Expectation::MessageContains("wrote".into())),
        ),
        (
            "screen shot.txt",
            Command::Screen {
                path: p("shot.txt"),
            },
        ),
        (
            "key jj:frame 3<Enter>",
            Command::Key("jj:frame 3<Enter>".into()),
        ),
        ("  key  <Space>", Command::Key("<Space>".into())),
    ];
    for (line, expected) in cases {
        assert_eq!(one(line), expected, "{line}");
    }
}

#[test]
fn blank_lines_and_comments_are_skipped() {
    assert_eq!(parse_line("", 1).unwrap(), None);
    assert_eq!(parse_line("   ", 1).unwrap(), None);
    assert_eq!(parse_line("# a comment", 1).unwrap(), None);
    assert_eq!(parse_line("   # indented", 1).unwrap(), None);
    let s = parse_session("# study\n\nload demo:walk\n  # note\nrun id\n").unwrap();
    assert_eq!(s.iter().map(|(l, _)| *l).collect::<Vec<_>>(), [3, 5]);
}

#[test]
fn a_trailing_comment_ends_the_line() {
    // it failed as "usage: load PATH [as NAME]"
    assert_eq!(
        one("load walk#2.bvh as w   # the second walk"),
        Command::Load {
            path: "walk#2.bvh".into(),
            name: Some("w".into())
        }
    );
    assert_eq!(one("run id # inverse dynamics"), one("run id"));
    // a quoted word keeps its #, and key lines are keystrokes
    assert_eq!(
        one("load \"#1.bvh\""),
        Command::Load {
            path: "#1.bvh".into(),
            name: None
        }
    );
    assert_eq!(one("key #"), Command::Key("#".into()));
}

#[test]
fn malformed_lines_name_their_line_and_what_was_expected() {
    let cases = [
        ("lod walk.bvh", "unknown command 'lod'"),
        ("load", "usage: load PATH [as NAME]"),
        ("load a.bvh called b", "usage: load PATH [as NAME]"),
        ("set body.mass", "usage: set KEY VALUE"),
        ("set body.height 1.8", "unknown setting 'body.height'"),
        ("run fast", "expected id or sim"),
        ("blend a b 2.6:2.0", "t1 must be after t0"),
        ("blend a b 2.0", "expected a window t0:t1"),
        ("frame -1", "expected a frame index"),
        ("frame x", "expected a frame index"),
        ("play now", "usage: play"),
        (
            "export pdf a.pdf",
            "expected one of csv, svg, bvh, urdf, mjcf, states, trc, grf",
        ),
        (
            "compare weights 60,x,100 k.csv",
            "expected a body mass in kg",
        ),
        ("compare weights 60,-5 k.csv", "must be positive"),
        ("compare heights 1,2 k.csv", "usage: compare weights"),
        ("report torque a.svg", "usage: report motor [curves] PATH"),
        (
            "report motor table a.csv",
            "usage: report motor [curves] PATH",
        ),
        (
            "export bvh simulated a.bvh",
            "usage: export csv|svg|bvh|urdf|mjcf|states|trc|grf|gltf|png|id PATH",
        ),
        ("set motor.j1.speed 3", "unknown setting 'motor.j1.speed'"),
        ("set motor..km 3", "unknown setting"),
        ("trajectory 0,0 1,1", "usage: trajectory POSE"),
        ("trajectory over 2", "usage: trajectory POSE"),
        ("trajectory 0,x over 2", "'x' in pose '0,x' is not a number"),
        ("trajectory 0,0 1 over 2", "the same number of values"),
        ("trajectory 0 1 over -2", "must be positive"),
        ("trajectory 0 1 over 2 at", "usage: trajectory POSE"),
        ("trajectory 0 1 over 0.001 at 10", "2 samples per move"),
        ("trajectory 0 1 over 1000 at 1000", "a million in all"),
        (
            "expect now j1 power between 1 2",
            "expected angle, velocity",
        ),
        ("expect", "usage: expect"),
        ("expect nv many", "expected nv"),
        (
            "expect peak LeftLeg.Xrotation force between 1 2",
            "expected angle, velocity",
        ),
        (
            "expect peak LeftLeg.Xrotation torque between 2 1",
            "HI is below LO",
        ),
        (
            "expect peak LeftLeg.Xrotation torque within 1 2",
            "usage: expect",
        ),
        (
            "expect peak LeftLeg.Xrotation torque between 1 inf",
            "expected HI",
        ),
        // a unit of another quantity names the units the quantity takes
        (
            "expect peak LeftLeg.Xrotation torque between 10deg 20deg",
            "'10deg' is an angle; a torque takes N·m, Nm, N.m (torque; a bare number is N·m) \
             or N (force; a bare number is N)",
        ),
        (
            "expect max LeftLeg.Xrotation angle between 10 20kg",
            "'20kg' is a mass; an angle takes deg, °, rad (angle; a bare number is deg) or m, \
             cm, mm (length; a bare number is m)",
        ),
        (
            "expect peak j1 velocity between 1rad/s2 2rad/s2",
            "velocity takes deg/s, °/s, rad/s",
        ),
        (
            "expect max j1 angle between 10deg 1m",
            "LO is an angle and HI a length",
        ),
        ("expect max j1 angle between 20deg 10deg", "HI is below LO"),
        ("expect max j1 angle between 10furlongs 2", "expected LO"),
        (
            "expect mass between 70deg 80",
            "'70deg' is an angle; LO (kg) takes kg",
        ),
        ("blend a b 1deg:2", "'1deg' is an angle; t0 takes s, ms"),
        ("compare weights 60,80N out.svg", "'80N' is a force"),
        ("trajectory 0,5kg over 1", "'5kg' in pose '0,5kg' is a mass"),
        (
            "trajectory 0,pi/2deg over 1",
            "multiplies π by a unit other than rad",
        ),
        ("trajectory 0,1 over 1deg", "T (s) takes s, ms"),
        ("screen", "usage: screen PATH"),
        ("key", "usage: key KEYS"),
        ("load \"unterminated", "unterminated"),
    ];
    for (i, (line, want)) in cases.iter().enumerate() {
        let lineno = i + 7;
        match parse_line(line, lineno) {
            Err(SessionError::Syntax {
                line: l,
                message,
                file: None,
            }) => {
                assert_eq!(l, lineno);
                assert!(message.contains(want), "{line}: {message} lacks {want}");
                let shown = parse_line(line, lineno).unwrap_err().to_string();
                assert!(shown.starts_with(&format!("line {lineno}: ")), "{shown}");
            }
            other => panic!("{line}: expected a syntax error, got {other:?}"),
        }
    }
}

#[test]
fn a_session_stops_at_its_first_bad_line() {
    let err = parse_session("load demo:walk\n\n# ok\nset body.mass\nrun id\n").unwrap_err();
    assert_eq!(err.line(), Some(4));
}
