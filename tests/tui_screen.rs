//! The terminal UI driven through ratatui's `TestBackend`: keys become commands on the
//! workbench, and what the user needs is on screen (joint tree, sparkline labels with running
//! min/max and the current value, timeline, status), at 80×24 and larger, across resizes.

use articula::session::{Command, Workbench};
use articula::tui::keys::parse_keys;
use articula::tui::{Focus, Ui, draw};
use ratatui::Terminal;
use ratatui::backend::TestBackend;

fn demo(width: u16, height: u16) -> (Ui, Workbench) {
    let mut ui = Ui::headless(width, height);
    ui.color = false;
    let mut wb = Workbench::default();
    ui.exec(
        &mut wb,
        &Command::Load {
            path: "demo:walk".into(),
            name: None,
        },
    );
    assert!(ui.error.is_none(), "{:?}", ui.error);
    (ui, wb)
}

fn press(ui: &mut Ui, wb: &mut Workbench, keys: &str) {
    for k in parse_keys(keys).unwrap() {
        ui.handle_key(wb, k);
    }
}

fn screen(ui: &Ui, wb: &Workbench, w: u16, h: u16) -> String {
    let mut term = Terminal::new(TestBackend::new(w, h)).unwrap();
    term.draw(|f| draw::draw(ui, wb, f)).unwrap();
    draw::buffer_text(term.backend().buffer())
}

#[test]
fn the_demo_screen_shows_tree_sparklines_timeline_and_status() {
    let (mut ui, mut wb) = demo(80, 24);
    // after loading, inverse dynamics ran and a rotation coordinate is selected
    assert_eq!(wb.selection.as_deref(), Some("Hips.Zrotation"));
    // down the tree to LeftUpLeg's child LeftLeg: select it from the command line
    press(&mut ui, &mut wb, ":select LeftLeg<Enter>");
    assert_eq!(wb.selection.as_deref(), Some("LeftLeg.Zrotation"));
    // its flexion coordinate with → (Z → X)
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
    let r = wb.fresh_results().unwrap();
    let j = r.tau.col_index("LeftLeg.Xrotation").unwrap();
    let tau = r.tau.column(j);
    let (min, max, now) = draw::running_stats(&tau, 30).unwrap();
    let label = format!("min {min:.1}  max {max:.1}  now {now:.1}");
    assert!(s.contains(&label), "missing {label:?} in\n{s}");
    // stepping forward widens (never narrows) the running range
    press(&mut ui, &mut wb, "}}}}}}");
    let (min2, max2, _) = draw::running_stats(&tau, 90).unwrap();
    assert!(min2 <= min && max2 >= max);
}

#[test]
fn tree_navigation_parameters_and_help() {
    let (mut ui, mut wb) = demo(100, 30);
    press(&mut ui, &mut wb, "jj");
    assert_eq!(wb.selection.as_deref(), Some("Spine1.Zrotation"));
    press(&mut ui, &mut wb, "k");
    assert_eq!(wb.selection.as_deref(), Some("Spine.Zrotation"));
    // parameters: Tab twice, → raises the body mass by 5 kg and recomputes
    press(&mut ui, &mut wb, "<Tab><Tab>");
    assert_eq!(ui.focus, Focus::Params);
    let before = wb.fresh_results().unwrap().clone();
    press(&mut ui, &mut wb, "<Right>");
    assert_eq!(wb.params.body_mass, 80.0);
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
    assert_eq!(wb.selection.as_deref(), Some("Spine.Zrotation"));
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
    assert_eq!(wb.selection.as_deref(), Some("LeftUpLeg.Zrotation"));
    press(&mut ui, &mut wb, ":se<Tab>");
    assert_eq!(ui.completions, ["set", "select"]);
    press(&mut ui, &mut wb, "t<Tab>bo<Tab>");
    assert_eq!(ui.cmdline.as_deref(), Some("set body."));
    assert_eq!(ui.completions, ["body.mass", "body.sex"]);
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
