//! The terminal UI driven through ratatui's `TestBackend`: keys become commands on the
//! workbench, and what the user needs is on screen (joint tree, sparkline labels with running
//! min/max and the current value, timeline, status), at 80×24 and larger, across resizes.

mod common;

use common::tui::{press, screen};

use articula::session::{Workbench, units};
use articula::tui::{Focus, Ui, draw};
use ratatui::Terminal;
use ratatui::backend::TestBackend;

fn demo(width: u16, height: u16) -> (Ui, Workbench) {
    common::tui::demo_in(width, height, Workbench::default())
}

#[test]
fn the_demo_screen_shows_tree_sparklines_timeline_and_status() {
    let (mut ui, mut wb) = demo(80, 24);
    // after loading, inverse dynamics ran and, the take being a human's, its left knee's
    // anatomical flexion is selected
    assert_eq!(wb.selection.as_deref(), Some("knee_l:flexion"));
    // ← and → step through the anatomical joint's axes
    press(&mut ui, &mut wb, "l");
    assert_eq!(wb.selection.as_deref(), Some("knee_l:adduction"));
    press(&mut ui, &mut wb, "hh");
    assert_eq!(wb.selection.as_deref(), Some("knee_l:rotation"));
    press(&mut ui, &mut wb, "l");
    assert_eq!(wb.selection.as_deref(), Some("knee_l:flexion"));
    // down the tree to LeftUpLeg's child LeftLeg: select it from the command line
    // a joint selects its coordinate with the largest range of motion: knee flexion
    press(&mut ui, &mut wb, ":select LeftLeg<Enter>");
    assert_eq!(wb.selection.as_deref(), Some("LeftLeg.Xrotation"));
    // ← and → step through the joint's coordinates (channel order Z X Y)
    press(&mut ui, &mut wb, "h");
    assert_eq!(wb.selection.as_deref(), Some("LeftLeg.Zrotation"));
    press(&mut ui, &mut wb, "l");
    assert_eq!(wb.selection.as_deref(), Some("LeftLeg.Xrotation"));
    press(&mut ui, &mut wb, "}}}");
    assert_eq!(wb.frame, 30);
    let s = screen(&ui, &wb, 80, 24);
    for text in [
        "Joints",
        "Spine1",
        "LeftLeg",
        "Parameters",
        "LeftLeg.Xrotation angle [deg]",
        "LeftLeg.Xrotation torque [N·m]",
        "frame 30/479",
        "? help",
    ] {
        assert!(s.contains(text), "missing {text:?} in\n{s}");
    }
    // the labels carry the running min/max up to the current frame and the current value
    let r = wb.fresh_results().unwrap().clone();
    let j = r.tau.col_index("LeftLeg.Xrotation").unwrap();
    let tau = r.tau.column(j);
    let (Some((min, max)), now) = draw::running_stats(&tau, 30, |k| r.quoted(k)).unwrap() else {
        panic!("frames 0..=30 have quoted frames")
    };
    // rounded as every value the workbench shows (0.1 N·m, 3 significant digits below 100)
    let n = |x| units::format_number(units::Kind::Torque, x);
    let label = format!("min {}  max {}  now {}", n(min), n(max), n(now));
    assert!(s.contains(&label), "missing {label:?} in\n{s}");
    // stepping forward widens (never narrows) the running range
    press(&mut ui, &mut wb, "}}}}}}");
    let (Some((min2, max2)), _) = draw::running_stats(&tau, 90, |k| r.quoted(k)).unwrap() else {
        panic!("frames 0..=90 have quoted frames")
    };
    assert!(min2 <= min && max2 >= max);
}

/// Issue 14: a torque's running min/max leave out the frames the workbench does not quote (the
/// edge frames, where the smoothed accelerations see past the take; those whose residuals stay
/// beyond what the feet can give), its sparkline shades them, and `expect` never quotes them
/// unless `set edges include`.
#[test]
fn torque_extremes_leave_out_edge_frames_and_the_sparkline_shades_them() {
    let (mut ui, mut wb) = demo(100, 30);
    press(&mut ui, &mut wb, ":select LeftLeg.Xrotation<Enter>");
    let r = wb.fresh_results().unwrap().clone();
    let n = r.time.len();
    // the demo's 120 fps, butterworth:6hz: 8 edge frames at each end
    let edge = (0..n).take_while(|&k| r.left_out[k].is_some()).count();
    assert!((4..=12).contains(&edge), "{edge} edge frames");
    assert!((n - edge..n).all(|k| !r.quoted(k)));
    let j = r.tau.col_index("LeftLeg.Xrotation").unwrap();
    let tau = r.tau.column(j);
    // on the first frames only the current value is shown
    assert!(
        draw::running_stats(&tau, 0, |k| r.quoted(k))
            .unwrap()
            .0
            .is_none()
    );
    let all = draw::running_stats(&tau, n - 1, |_| true)
        .unwrap()
        .0
        .unwrap();
    let quoted = draw::running_stats(&tau, n - 1, |k| r.quoted(k))
        .unwrap()
        .0
        .unwrap();
    let inner: Vec<f64> = (0..n).filter(|&k| r.quoted(k)).map(|k| tau[k]).collect();
    let lo = inner.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = inner.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    assert_eq!(quoted, (lo, hi));
    assert!(all.0 <= quoted.0 && all.1 >= quoted.1);
    // the sparkline's first and last columns (edge frames) are dim, a middle one is not
    press(&mut ui, &mut wb, "G");
    let mut term = Terminal::new(TestBackend::new(100, 30)).unwrap();
    term.draw(|f| draw::draw(&ui, &wb, f)).unwrap();
    let buf = term.backend().buffer().clone();
    let text = draw::buffer_text(&buf);
    let row = text
        .lines()
        .position(|l| l.contains("LeftLeg.Xrotation torque"))
        .expect("the torque label");
    assert!(text.contains("shaded frames not quoted"), "{text}");
    let bars = (row + 1) as u16;
    let line: Vec<_> = (0..100).map(|x| &buf[(x, bars + 1)]).collect();
    let first = line.iter().position(|c| c.symbol() != " ").expect("bars");
    let last = line.iter().rposition(|c| c.symbol() != " ").expect("bars");
    let dim = |c: &ratatui::buffer::Cell| c.modifier.contains(ratatui::style::Modifier::DIM);
    assert!(
        dim(line[first]) && dim(line[last]),
        "edge columns are shaded"
    );
    // as many shaded columns as the share of frames left out, give or take the sampling
    let shaded = line[first..=last].iter().filter(|c| dim(c)).count() as f64;
    let share = (0..n).filter(|&k| !r.quoted(k)).count() as f64 / n as f64;
    let width = (last - first + 1) as f64;
    assert!(
        (shaded / width - share).abs() < 0.05 && shaded < width,
        "{shaded} of {width} columns shaded, {share} of the frames left out"
    );
    // expect: the peak is of the quoted frames; `set edges include` quotes the edge frames, never
    // those beyond the feet
    for setting in ["include", "exclude"] {
        press(&mut ui, &mut wb, &format!(":set edges {setting}<Enter>"));
        let got = wb.fresh_results().unwrap().clone();
        assert_eq!(got.quoted(0), setting == "include");
        assert!(
            got.left_out
                .iter()
                .all(|w| setting == "exclude" || *w != Some(articula::session::LeftOut::Edge))
        );
        let tau = got.tau.column(j);
        let want = (0..n)
            .filter(|&k| got.quoted(k))
            .fold(0.0f64, |m, k| m.max(tau[k].abs()));
        let line = format!(
            "expect peak LeftLeg.Xrotation torque between {} {}",
            want - 0.06,
            want + 0.06
        );
        let cmd = articula::session::command::parse_line(&line, 1)
            .unwrap()
            .unwrap();
        ui.exec(&mut wb, &cmd);
        assert!(ui.error.is_none(), "edges {setting}: {:?}", ui.error);
    }
}

#[test]
fn tree_navigation_parameters_and_help() {
    let (mut ui, mut wb) = demo(100, 30);
    // the knee's anatomical flexion sits on the tree's row of the knee's BVH joint
    let tree = Ui::tree(&wb);
    assert_eq!(tree[Ui::tree_cursor(&wb).unwrap()].0, "LeftLeg");
    press(&mut ui, &mut wb, ":select Hips<Enter>jj");
    let largest = |wb: &Workbench, joint: &str| {
        articula::session::workbench::best_coordinate(wb.latest_results().unwrap(), joint)
    };
    assert_eq!(wb.selection, largest(&wb, "Spine1"));
    assert!(wb.selection.as_deref().unwrap().starts_with("Spine1."));
    press(&mut ui, &mut wb, "k");
    assert_eq!(wb.selection, largest(&wb, "Spine"));
    let spine = wb.selection.clone();
    // parameters: Tab twice, → raises the body mass by 5 kg and recomputes
    press(&mut ui, &mut wb, "<Tab><Tab>");
    assert_eq!(ui.focus, Focus::Params);
    let before = wb.fresh_results().unwrap().clone();
    press(&mut ui, &mut wb, "<Right>");
    assert_eq!(wb.params.take.body.mass_kg, 80.0);
    let after = wb.fresh_results().unwrap().clone();
    assert!((after.model.total_mass() - 80.0).abs() < 1e-9);
    assert_ne!(before.tau, after.tau);
    let s = screen(&ui, &wb, 100, 30);
    assert!(s.contains("Hips"), "{s}");
    assert!(s.contains("body.mass") && s.contains("80 kg"), "{s}");
    // help overlay, closed by any key
    press(&mut ui, &mut wb, "?");
    assert!(screen(&ui, &wb, 100, 30).contains("Help"));
    press(&mut ui, &mut wb, "x");
    assert!(!ui.help);
    // a bad command shows an error in the status line and changes nothing
    press(&mut ui, &mut wb, ":select Tail<Enter>");
    assert!(screen(&ui, &wb, 100, 30).contains("error: no joint called 'Tail'"));
    assert_eq!(wb.selection, spine);
    // history brings the last command back
    press(&mut ui, &mut wb, ":<Up>");
    assert_eq!(ui.cmdline.as_deref(), Some("select Tail"));
    press(&mut ui, &mut wb, "<Esc>q");
    assert!(ui.quit);
}

#[test]
fn tab_completes_commands_and_joint_names() {
    let (mut ui, mut wb) = demo(80, 24);
    press(&mut ui, &mut wb, ":sel<Tab>LeftU<Tab>");
    assert_eq!(ui.cmdline.as_deref(), Some("select LeftUpLeg "));
    press(&mut ui, &mut wb, "<Enter>");
    // the hip's largest range of motion is flexion (Xrotation)
    assert_eq!(wb.selection.as_deref(), Some("LeftUpLeg.Xrotation"));
    press(&mut ui, &mut wb, ":se<Tab>");
    assert_eq!(ui.completions, ["set", "select"]);
    press(&mut ui, &mut wb, "t<Tab>bo<Tab>");
    assert_eq!(ui.cmdline.as_deref(), Some("set body."));
    assert_eq!(ui.completions, ["body.mass", "body.sex", "body.segments"]);
    // any other key makes the hint stale (it stayed while typing and browsing history)
    press(&mut ui, &mut wb, "m");
    assert!(ui.completions.is_empty());
    press(&mut ui, &mut wb, "<Tab><Up>");
    assert!(ui.completions.is_empty());
}

#[test]
fn playback_and_scrubbing_move_the_frame() {
    let (mut ui, mut wb) = demo(80, 24);
    press(&mut ui, &mut wb, "<Space>");
    assert!(wb.playing);
    // half a second of wall time at 120 fps
    ui.tick(&mut wb, 0.5);
    assert_eq!(wb.frame, 60);
    press(&mut ui, &mut wb, "<Space>[[");
    assert!(!wb.playing);
    assert_eq!(wb.frame, 58);
    press(&mut ui, &mut wb, "G");
    assert_eq!(wb.frame, 479);
    press(&mut ui, &mut wb, "]");
    assert_eq!(wb.frame, 479, "scrubbing stops at the last frame");
}

#[test]
fn resize_from_large_to_tiny_and_back() {
    let (ui, wb) = demo(80, 24);
    let mut term = Terminal::new(TestBackend::new(200, 60)).unwrap();
    for (w, h) in [(200, 60), (80, 24), (40, 10), (1, 1), (120, 40), (80, 24)] {
        term.backend_mut().resize(w, h);
        term.autoresize().unwrap();
        term.draw(|f| draw::draw(&ui, &wb, f)).unwrap();
        let s = draw::buffer_text(term.backend().buffer());
        assert_eq!(s.lines().count(), h as usize);
        if w >= draw::MIN_SIZE.0 && h >= draw::MIN_SIZE.1 {
            assert!(s.contains("Joints"), "{w}×{h}:\n{s}");
        } else if w >= 40 {
            assert!(s.contains("needs at least"), "{w}×{h}:\n{s}");
        }
    }
}

/// Regression: with the ball joint model the angle sparkline was empty (q columns are `:qx`…,
/// the selection a velocity coordinate `:wx`); it now shows the rotation-vector component.
#[test]
fn ball_joints_show_a_rotation_vector_angle_sparkline() {
    let (mut ui, mut wb) = demo(100, 30);
    press(
        &mut ui,
        &mut wb,
        ":set joints ball<Enter>:select LeftLeg<Enter>",
    );
    assert!(ui.error.is_none(), "{:?}", ui.error);
    // the knee's largest range of motion is about its x axis
    assert_eq!(wb.selection.as_deref(), Some("LeftLeg:wx"));
    press(&mut ui, &mut wb, "}}}}}}");
    let s = screen(&ui, &wb, 100, 30);
    assert!(s.contains("LeftLeg:wx angle [deg]"), "{s}");
    assert!(!s.contains("angle: no results"), "{s}");
    let r = wb.fresh_results().unwrap();
    let angle = articula::session::workbench::angle_series(r, "LeftLeg:wx").unwrap();
    let deg: Vec<f64> = angle.iter().map(|x| x.to_degrees()).collect();
    // an angle's extremes are of every frame (the edge frames are left out of forces only)
    let (Some((min, max)), now) = draw::running_stats(&angle, 60, |_| true).unwrap() else {
        panic!("an angle's frames are all quoted")
    };
    let n = |x| units::format_number(units::Kind::Angle, x);
    let label = format!("min {}  max {}  now {}", n(min), n(max), n(now));
    assert!(s.contains(&label), "missing {label:?} in\n{s}");
    // a knee flexes by tens of degrees: the series is not flat
    let range =
        deg.iter().copied().fold(f64::MIN, f64::max) - deg.iter().copied().fold(f64::MAX, f64::min);
    assert!(range > 20.0, "{range}");
    // and it is the euler flexion angle, nearly: both describe the same knee motion
    press(&mut ui, &mut wb, ":set joints euler<Enter>");
    let e = wb.fresh_results().unwrap();
    let flex = e.q.column(e.q.col_index("LeftLeg.Xrotation").unwrap());
    let worst = flex
        .iter()
        .zip(&angle)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    assert!(
        worst < 0.1,
        "ball x-component and euler flexion differ by {worst} rad"
    );
}

#[test]
fn an_explicit_channel_is_kept_and_a_robot_shows_its_joints() {
    let (mut ui, mut wb) = demo(100, 30);
    press(&mut ui, &mut wb, ":select LeftLeg.Yrotation<Enter>");
    assert_eq!(wb.selection.as_deref(), Some("LeftLeg.Yrotation"));
    // a DH arm with a generated move: its joint tree, sparklines and links drawn, no panic
    let dh = concat!(env!("CARGO_MANIFEST_DIR"), "/data/puma560.toml");
    press(
        &mut ui,
        &mut wb,
        &format!(
            ":load {dh} as puma<Enter>:trajectory 0,0,0,0,0,0 0,pi/4,pi,0,pi/4,0 over 1 at 100<Enter>:select j2<Enter>}}}}}}"
        ),
    );
    assert!(ui.error.is_none(), "{:?}", ui.error);
    let s = screen(&ui, &wb, 100, 30);
    for want in [
        "j1",
        "j6",
        "j2 angle [deg]",
        "j2 torque [N·m]",
        "robot (DH table)",
        "frame 30/100",
    ] {
        assert!(s.contains(want), "missing {want:?} in\n{s}");
    }
    assert!(
        s.chars()
            .filter(|c| ('\u{2801}'..='\u{28FF}').contains(c))
            .count()
            > 10,
        "the arm's links are drawn:\n{s}"
    );
    // completion knows the motor keys of the arm's coordinates and the report forms
    press(&mut ui, &mut wb, ":set motor.j2.g<Tab>");
    assert_eq!(ui.cmdline.as_deref(), Some("set motor.j2.gear "));
    press(&mut ui, &mut wb, "107.815<Enter>");
    assert_eq!(wb.params.motor_of("j2").gear_ratio, 107.815);
    assert_eq!(wb.params.motor_of("j3").gear_ratio, 100.0);
    // the parameter panel of an arm: the selected joint's drive, its current and motor class
    let s = screen(&ui, &wb, 100, 30);
    for want in ["j2 gear", "107.815", "j2 km", "I peak", "→ BLDC-"] {
        assert!(s.contains(want), "missing {want:?} in\n{s}");
    }
    press(&mut ui, &mut wb, "<Tab><Tab><Right>");
    assert_eq!(ui.focus, Focus::Params);
    assert_eq!(wb.params.motor_of("j2").gear_ratio, 113.2058);
    press(&mut ui, &mut wb, ":rep<Tab>m<Tab>c<Tab>");
    assert_eq!(ui.cmdline.as_deref(), Some("report motor curves "));
    press(&mut ui, &mut wb, "<Esc>");
    // every key on the robot: nothing panics
    press(
        &mut ui,
        &mut wb,
        "jjjkhl<Tab><Tab><Right><Left><Enter><Esc><Tab>[]{}gG",
    );
    let _ = screen(&ui, &wb, 80, 24);
}

/// Regression: at 80 columns an error longer than the status line was cut off with no way to
/// read the rest. It now shows whole, wrapped in a box above the status line, until Esc; and
/// `?` ends with the last message, however long.
#[test]
fn a_long_error_is_shown_whole_at_80_columns_and_the_help_holds_the_last_message() {
    let (mut ui, mut wb) = demo(80, 24);
    press(
        &mut ui,
        &mut wb,
        ":load /no/such/folder/with/a/rather/long/name/take_number_one.bvh<Enter>",
    );
    let e = ui.error.clone().expect("an error");
    assert!(e.chars().count() + 7 > 80, "{e}");
    let s = screen(&ui, &wb, 80, 24);
    assert!(s.contains("Error (Esc closes)"), "{s}");
    // the end of the message is on screen (wrapped), not cut
    let joined: String = s
        .lines()
        .map(|l| l.trim_matches(|c| c == '│' || c == ' '))
        .collect();
    assert!(joined.contains("take_number_one.bvh"), "{s}");
    press(&mut ui, &mut wb, "<Esc>");
    assert!(!screen(&ui, &wb, 80, 24).contains("Error (Esc closes)"));
    press(&mut ui, &mut wb, "?");
    let s = screen(&ui, &wb, 80, 24);
    assert!(s.contains("Last message:"), "{s}");
}

/// The parameter panel says what `contact auto` settled on once a run has settled it (issue 14
/// item 2), and the setting as it is otherwise.
#[test]
fn the_panel_says_what_contact_auto_chose() {
    let (mut ui, mut wb) = demo(100, 30);
    let s = screen(&ui, &wb, 100, 30);
    assert!(s.contains("contact auto → feet"), "{s}");
    press(&mut ui, &mut wb, ":set contact none<Enter>:run id<Enter>");
    let s = screen(&ui, &wb, 100, 30);
    assert!(s.contains("contact none"), "{s}");
    assert!(!s.contains("contact auto"), "{s}");
}
