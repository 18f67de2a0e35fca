//! Several loaded takes (issue 15): `articula A.bvh B.bvh` loads both; `take next|prev|N|NAME`
//! (keys `t`, `T`) makes another active, with its own results and the human's left knee
//! selected; the avatar's title and the parameter panel list them; two files of one name
//! stay two takes.

mod common;

use common::tui::{press, screen};

use articula::session::{Builtin, Command, Workbench};
use articula::tui::Ui;
use std::path::Path;
use std::sync::Arc;

/// Two takes in `dir`: `a/walk.bvh` (the demo walk) and `b/walk.bvh`, its second half.
fn two_walks(dir: &Path) {
    let text = std::fs::read_to_string(common::repo("data/demo_walk.bvh")).unwrap();
    let (head, motion) = text.split_once("MOTION").unwrap();
    let rows: Vec<&str> = motion.lines().skip(3).filter(|l| !l.is_empty()).collect();
    let half = &rows[rows.len() / 2..];
    let frame_time = motion.lines().nth(2).unwrap();
    let short = format!(
        "{head}MOTION\nFrames: {}\n{frame_time}\n{}\n",
        half.len(),
        half.join("\n")
    );
    for (sub, body) in [("a", text.as_str()), ("b", short.as_str())] {
        std::fs::create_dir(dir.join(sub)).unwrap();
        std::fs::write(dir.join(sub).join("walk.bvh"), body).unwrap();
    }
}

#[test]
fn take_switches_between_loaded_takes_and_lists_them() {
    let dir = tempfile::tempdir().unwrap();
    two_walks(dir.path());
    let mut ui = Ui::headless(100, 30);
    ui.color = false;
    let mut wb = Workbench::new(Arc::new(Builtin), dir.path(), dir.path());
    for p in ["a/walk.bvh", "b/walk.bvh"] {
        ui.exec(
            &mut wb,
            &Command::Load {
                path: p.into(),
                name: None,
            },
        );
        assert!(ui.error.is_none(), "{:?}", ui.error);
    }
    // two files of one name are two takes
    assert_eq!(wb.take_names(), ["walk", "walk-2"]);
    assert_eq!(wb.active, Some(1));
    let frames_b = wb.frames();
    let s = screen(&ui, &wb, 100, 30);
    assert!(s.contains("walk-2 [2/2, t: next]"), "{s}");
    assert!(s.contains("takes (t/T):") && s.contains("▸2 walk-2"), "{s}");
    // t: the next (first) take, its own results, its left knee
    press(&mut ui, &mut wb, "t");
    assert_eq!(wb.active, Some(0));
    assert_eq!(wb.frame, 0);
    assert!(wb.frames() > frames_b);
    let r = wb.fresh_results().expect("results of the first take");
    assert_eq!(r.time.len(), wb.frames());
    assert_eq!(wb.selection.as_deref(), Some("knee_l:flexion"));
    assert!(wb.last_message().contains("inverse dynamics"));
    assert!(screen(&ui, &wb, 100, 30).contains("walk [1/2, t: next]"));
    // T, by number, by name
    press(&mut ui, &mut wb, "T");
    assert_eq!(wb.active, Some(1));
    press(&mut ui, &mut wb, ":take 1<Enter>");
    assert_eq!(wb.active, Some(0));
    press(&mut ui, &mut wb, ":take walk-2<Enter>");
    assert_eq!(wb.active, Some(1));
    assert_eq!(wb.fresh_results().unwrap().time.len(), frames_b);
    // errors name what is loaded
    press(&mut ui, &mut wb, ":take run<Enter>");
    let e = ui.error.clone().unwrap();
    assert!(
        e.contains("no take called 'run'") && e.contains("walk, walk-2"),
        "{e}"
    );
    press(&mut ui, &mut wb, ":take 3<Enter>");
    assert!(ui.error.clone().unwrap().contains("2 take(s)"));
    // Tab completes the names
    let (_, cands) = articula::tui::ui::complete(&wb, "take w");
    assert_eq!(cands, ["walk", "walk-2"]);
    // the same file loaded again replaces its take
    press(&mut ui, &mut wb, ":load a/walk.bvh<Enter>");
    assert_eq!(wb.take_names(), ["walk", "walk-2"]);
    assert_eq!(wb.active, Some(0));
}

#[test]
fn a_session_switches_takes_headless() {
    let dir = tempfile::tempdir().unwrap();
    two_walks(dir.path());
    let session = dir.path().join("two.session");
    std::fs::write(
        &session,
        "load a/walk.bvh\nload b/walk.bvh\ntake prev\nexpect frames 480\ntake next\n\
         screen s.txt\nexpect selected knee_l:flexion\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    let r = articula::tui::run_session(&session, &out).unwrap();
    assert_eq!(r.commands, 7);
    let s = std::fs::read_to_string(out.join("s.txt")).unwrap();
    assert!(s.contains("walk-2 [2/2, t: next]"), "{s}");
}
