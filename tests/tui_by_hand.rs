//! What a user found by hand in the workbench (issue 15), one regression test each: the
//! playhead and the selected link read without colours; the command line edits as readline
//! does (Ctrl-U, Ctrl-W) and Backspace never closes it; `screen` and relative exports say
//! the absolute path they wrote; `select` after `set joints` chooses on the model the
//! parameters now build; Tab completes file paths.

mod common;

use common::tui::{buffer, press};

use articula::session::{Builtin, Command, Workbench, apply_with, parse_line};
use articula::tui::ui::complete;
use articula::tui::{Ui, draw};
use ratatui::buffer::Buffer;
use ratatui::style::Modifier;
use std::path::Path;
use std::sync::Arc;

/// The demo walk in a headless interface without colours, its outputs under `out`.
fn demo(out: &Path) -> (Ui, Workbench) {
    common::tui::demo_in(100, 30, Workbench::new(Arc::new(Builtin), out, out))
}

/// The row of `buf` holding `text`.
fn row_with(buf: &Buffer, text: &str) -> Option<u16> {
    (0..buf.area.height).find(|&y| {
        (0..buf.area.width)
            .map(|x| buf[(x, y)].symbol())
            .collect::<String>()
            .contains(text)
    })
}

#[test]
fn no_color_still_shows_the_playhead_and_the_selected_link() {
    let out = tempfile::tempdir().unwrap();
    let (mut ui, mut wb) = demo(out.path());
    ui.exec(&mut wb, &Command::Frame(240));
    for (w, h) in [(80, 24), (100, 30), (180, 50)] {
        let buf = buffer(&ui, &wb, w, h);
        // the timeline: played thick, unplayed thin, with the change at the playhead
        let y = row_with(&buf, "frame 240/479").expect("the timeline");
        let line: Vec<&str> = (0..w).map(|x| buf[(x, y)].symbol()).collect();
        let played = line.iter().filter(|s| **s == draw::PLAYED).count();
        let unplayed = line.iter().filter(|s| **s == draw::UNPLAYED).count();
        assert!(played > 0 && unplayed > 0, "{w}×{h}: {line:?}");
        let last_played = line.iter().rposition(|s| *s == draw::PLAYED).unwrap();
        assert_eq!(line[last_played + 1], draw::UNPLAYED, "{w}×{h}");
        // the selected link: a glyph in reverse video over the avatar
        let marked = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .filter(|&p| buf[p].symbol() == draw::SELECTED_GLYPH)
            .collect::<Vec<_>>();
        assert_eq!(marked.len(), 1, "{w}×{h}");
        assert!(buf[marked[0]].modifier.contains(Modifier::REVERSED));
    }
}

#[test]
fn ctrl_u_clears_the_command_line_and_ctrl_w_deletes_a_word() {
    let out = tempfile::tempdir().unwrap();
    let (mut ui, mut wb) = demo(out.path());
    press(&mut ui, &mut wb, ":select LeftLeg  <C-w>");
    assert_eq!(ui.cmdline.as_deref(), Some("select "));
    press(&mut ui, &mut wb, "<C-w>");
    assert_eq!(ui.cmdline.as_deref(), Some(""));
    press(&mut ui, &mut wb, "frame 12<C-u>");
    assert_eq!(ui.cmdline.as_deref(), Some(""));
    press(&mut ui, &mut wb, "frame 3<Enter>");
    assert_eq!(wb.frame, 3);
}

#[test]
fn backspace_on_an_empty_command_line_keeps_it_open() {
    let out = tempfile::tempdir().unwrap();
    let (mut ui, mut wb) = demo(out.path());
    press(&mut ui, &mut wb, ":f<BS><BS><BS>");
    assert_eq!(ui.cmdline.as_deref(), Some(""));
    press(&mut ui, &mut wb, "<Esc>");
    assert_eq!(ui.cmdline, None);
}

#[test]
fn screen_says_the_path_it_wrote() {
    let out = tempfile::tempdir().unwrap();
    let (mut ui, mut wb) = demo(out.path());
    press(&mut ui, &mut wb, ":screen shot.txt<Enter>");
    let path = out.path().join("shot.txt");
    assert!(path.exists());
    let msg = wb.last_message().to_string();
    assert!(
        msg.contains(&path.display().to_string()) && msg.contains("30 lines"),
        "{msg}"
    );
    // and the status line shows it
    let s = draw::buffer_text(&buffer(&ui, &wb, 100, 30));
    assert!(s.contains("wrote the screen"), "{s}");
}

#[test]
fn relative_exports_of_the_terminal_name_their_absolute_path() {
    let wb = articula::tui::workbench_here();
    let p = wb.out_path(Path::new("knee.svg"));
    assert!(p.is_absolute(), "{}", p.display());
    assert_eq!(p, std::env::current_dir().unwrap().join("knee.svg"));
}

/// A `key` computes results (euler) before `set joints ball`: the next `select` must choose
/// among the ball model's coordinates, not the stale results' (`LeftLeg.Xrotation`).
#[test]
fn select_after_set_joints_follows_the_current_model() {
    let out = tempfile::tempdir().unwrap();
    let mut ui = Ui::headless(100, 30);
    let mut wb = Workbench::new(Arc::new(Builtin), out.path(), out.path());
    for line in [
        "load demo:walk",
        "key :frame 3<Enter>",
        "set joints ball",
        "select LeftLeg",
    ] {
        let cmd = parse_line(line, 1).unwrap().unwrap();
        apply_with(&mut wb, &mut ui, &cmd).unwrap();
    }
    let sel = wb.selection.clone().unwrap();
    assert!(sel.starts_with("LeftLeg:w"), "{sel}");
    assert!(
        wb.last_message().contains("LeftLeg:w"),
        "{}",
        wb.last_message()
    );
    // it stays once the ball model's results are computed
    wb.refresh().unwrap();
    assert_eq!(wb.selection.as_deref(), Some(sel.as_str()));
}

#[test]
fn tab_completes_file_paths_for_load_and_exports() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("walk.bvh"), "").unwrap();
    std::fs::write(dir.path().join("notes.txt"), "").unwrap();
    std::fs::create_dir(dir.path().join("takes")).unwrap();
    std::fs::write(dir.path().join("takes/run.bvh"), "").unwrap();
    std::fs::write(dir.path().join("takes/rig.toml"), "").unwrap();
    let wb = Workbench::new(Arc::new(Builtin), dir.path(), dir.path());
    // load offers folders and what it reads
    let (line, cands) = complete(&wb, "load ");
    assert_eq!(line, "load ");
    assert_eq!(cands, ["takes/", "walk.bvh"]);
    // a folder completes without a space, so that Tab goes on into it
    assert_eq!(complete(&wb, "load t").0, "load takes/");
    assert_eq!(complete(&wb, "load takes/ru").0, "load takes/run.bvh ");
    assert_eq!(complete(&wb, "load w").0, "load walk.bvh ");
    // an export offers every file (to overwrite) and folder
    let (_, cands) = complete(&wb, "export svg ");
    assert_eq!(cands, ["notes.txt", "takes/", "walk.bvh"]);
    assert_eq!(complete(&wb, "export csv n").0, "export csv notes.txt ");
    let (_, cands) = complete(&wb, "report motor ");
    assert!(cands.contains(&"curves".to_string()) && cands.contains(&"takes/".to_string()));
}
