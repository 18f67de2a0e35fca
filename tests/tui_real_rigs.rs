//! The workbench on real rigs and where it starts (issue 15): a Mixamo take's joint tree reads
//! without the `mixamorig:` every name carries, on rows wide enough for the names; a human
//! take opens on its left knee, marked in the tree and the avatar; `report motor` never sizes
//! a motor for the root's residual coordinates; the status line's contact verdicts read at
//! 80 columns, and under the curves the residual figures the pipeline computes for the take,
//! against Hicks et al.'s thresholds (issue 14 item 5).

mod common;

use common::tui::{press, screen};

use articula::pipeline::{self, consistency};
use articula::session::{Builtin, Command, Workbench};
use articula::tui::{Ui, draw};
use std::path::Path;
use std::sync::Arc;

/// The demo walk with every joint renamed as Mixamo names them (`mixamorig:LeftLeg`), in `dir`.
fn mixamo_walk(dir: &Path) -> std::path::PathBuf {
    let text = std::fs::read_to_string(common::repo("data/demo_walk.bvh")).unwrap();
    let renamed: String = text
        .lines()
        .map(|l| {
            let t = l.trim_start();
            let indent = &l[..l.len() - t.len()];
            match t.split_once(' ') {
                Some((kw @ ("ROOT" | "JOINT"), name)) => {
                    format!("{indent}{kw} mixamorig:{}\n", name.trim())
                }
                _ => format!("{l}\n"),
            }
        })
        .collect();
    let path = dir.join("mixamo_walk.bvh");
    std::fs::write(&path, renamed).unwrap();
    path
}

fn open(path: &Path, w: u16, h: u16) -> (Ui, Workbench) {
    let mut ui = Ui::headless(w, h);
    ui.color = false;
    let dir = path.parent().unwrap();
    let mut wb = Workbench::new(Arc::new(Builtin), dir, dir);
    ui.exec(
        &mut wb,
        &Command::Load {
            path: path.into(),
            name: None,
        },
    );
    assert!(ui.error.is_none(), "{:?}", ui.error);
    (ui, wb)
}

/// Regression: the tree was 24 columns whatever the names, so a Mixamo rig read as rows of
/// `mixamorig:RightHan`.
#[test]
fn a_mixamo_tree_drops_the_shared_prefix_and_opens_on_the_left_knee() {
    let dir = tempfile::tempdir().unwrap();
    let path = mixamo_walk(dir.path());
    for (w, h) in [(80, 24), (180, 50)] {
        let (ui, wb) = open(&path, w, h);
        // a human: the left knee's flexion, on the row of the knee's BVH joint
        assert_eq!(wb.selection.as_deref(), Some("knee_l:flexion"));
        let tree = Ui::tree(&wb);
        assert_eq!(
            tree[Ui::tree_cursor(&wb).unwrap()].0,
            "mixamorig:LeftLeg",
            "{w}×{h}"
        );
        let s = screen(&ui, &wb, w, h);
        let rows: Vec<&str> = s.lines().skip(1).take(h as usize - 10).collect();
        for name in ["Spine1", "LeftUpLeg", "LeftLeg"] {
            assert!(
                rows.iter().any(|r| r.starts_with('│') && r.contains(name)),
                "{w}×{h}: no {name} in\n{s}"
            );
        }
        // every row of the tree pane (left of the avatar) is free of the prefix
        let tree_w = draw::tree_width(&tree, if w >= 100 { 26 } else { 20 }, w) as usize;
        for r in s.lines().skip(1).take(h as usize - 9) {
            let cells: String = r.chars().take(tree_w).collect();
            assert!(!cells.contains("mixamorig"), "{w}×{h}: {r}");
        }
        // the link mass row names the joint as the tree does
        assert!(s.contains("│LeftLeg "), "{w}×{h}:\n{s}");
    }
}

#[test]
fn the_selected_knee_is_marked_in_the_avatar() {
    let (ui, wb) = open(&common::repo("data/demo_walk.bvh"), 100, 30);
    assert_eq!(wb.selection.as_deref(), Some("knee_l:flexion"));
    assert_eq!(wb.selected_joint().as_deref(), Some("LeftLeg"));
    let s = screen(&ui, &wb, 100, 30);
    assert_eq!(s.matches(draw::SELECTED_GLYPH).count(), 1, "{s}");
}

#[test]
fn report_motor_refuses_the_root_and_sizes_the_selected_knee() {
    let dir = tempfile::tempdir().unwrap();
    let mut ui = Ui::headless(100, 30);
    let mut wb = Workbench::new(Arc::new(Builtin), common::repo("data"), dir.path());
    ui.exec(
        &mut wb,
        &Command::Load {
            path: "demo_walk.bvh".into(),
            name: None,
        },
    );
    // the anatomical knee maps to LeftLeg's revolute coordinates
    press(&mut ui, &mut wb, ":report motor knee.csv<Enter>");
    assert!(ui.error.is_none(), "{:?}", ui.error);
    let table = std::fs::read_to_string(dir.path().join("knee.csv")).unwrap();
    assert!(table.contains("LeftLeg."), "{table}");
    // the root's coordinates are residuals: no motor
    press(
        &mut ui,
        &mut wb,
        ":select Hips<Enter>:report motor root.csv<Enter>",
    );
    let e = ui.error.clone().expect("refused");
    assert!(
        e.contains("Hips is the root") && e.contains("residual"),
        "{e}"
    );
    assert!(!dir.path().join("root.csv").exists());
}

#[test]
fn the_contact_verdicts_read_in_the_status_line_at_80_columns() {
    let (mut ui, mut wb) = open(&common::repo("data/demo_walk.bvh"), 80, 24);
    press(&mut ui, &mut wb, ":set contact feet<Enter>");
    let s = screen(&ui, &wb, 80, 24);
    let status = s.lines().last().unwrap();
    assert!(
        status.contains("feet give the force in") && status.contains("Hicks et al."),
        "{status}"
    );
    // the whole message is one `?` away
    press(&mut ui, &mut wb, "?");
    let s = screen(&ui, &wb, 80, 24);
    assert!(s.contains("single-support frames"), "{s}");
}

#[test]
fn the_status_line_keeps_the_verdicts_and_drops_the_summary_first() {
    let msg = "inverse dynamics: 480 frames, nv 66, 75.0 kg; feet give the force in 94 % of \
               single support; residuals within Hicks et al.";
    let hint = "   [joints]  ? help  : command  q quit";
    let (t, h) = draw::fit_status(msg, hint, 200);
    assert_eq!((t.as_str(), h.as_str()), (msg, hint));
    let (t, h) = draw::fit_status(msg, hint, 130);
    assert_eq!((t.as_str(), h.as_str()), (msg, "  ? help"));
    let (t, h) = draw::fit_status(msg, hint, 80);
    assert_eq!(
        t,
        "…feet give the force in 94 % of single support; residuals within Hicks et al."
    );
    assert_eq!(h, "");
    // a short message is never cut
    assert_eq!(draw::fit_status("selected j2", hint, 80).0, "selected j2");
}

/// The row under the curves that holds the residual figures, if any.
fn residual_row(screen: &str) -> Option<&str> {
    screen.lines().find(|l| l.starts_with("residual"))
}

/// Issue 14 item 5: the knee's numbers are read with the take's consistency. Under the curves,
/// at 80 columns, the row gives the peak residual force and the RMS residual moment against
/// Hicks et al.'s thresholds as the pipeline computes them for the take, after residual
/// reduction and before it; with reduction off the take's own figures; without contact none.
/// The status line keeps its verdicts.
#[test]
fn the_residual_figures_read_under_the_curves_at_80_columns() {
    let path = common::repo("data/demo_walk.bvh");
    let (mut ui, mut wb) = open(&path, 80, 24);
    press(&mut ui, &mut wb, ":set contact feet<Enter>");
    assert!(ui.error.is_none(), "{:?}", ui.error);
    // what the pipeline computes for the take under the workbench's settings
    let take = pipeline::load_take(&path, &wb.params.take).unwrap();
    let (_, _, c) = consistency::consistent_take(&take, true, None).unwrap();
    let (before, after) = (c.before, c.after.expect("reduced"));
    let s = screen(&ui, &wb, 80, 24);
    let row = residual_row(&s).unwrap_or_else(|| panic!("no residual row:\n{s}"));
    let verdict = if after.meets() { "within" } else { "beyond" };
    for want in [
        format!("force {:.1} % (≤5 %)", after.force_pct()),
        format!("moment {:.2} % (≤1 %): {verdict}", after.moment_pct()),
        format!(
            "before {:.1} %, {:.2} %",
            before.force_pct(),
            before.moment_pct()
        ),
    ] {
        assert!(row.contains(&want), "{want:?} not in {row:?}");
    }
    // the reduction moved the figures: the row is not the before figures twice
    assert_ne!(
        format!("{:.2}", after.moment_pct()),
        format!("{:.2}", before.moment_pct())
    );
    let lines: Vec<&str> = s.lines().collect();
    let at = lines.iter().position(|l| *l == row).unwrap();
    // right under the torque's sparkline, above the timeline and the status line
    assert!(lines[at - 3].contains("torque"), "{s}");
    assert!(lines[at + 1].contains("frame"), "{s}");
    let status = lines[lines.len() - 1];
    assert!(
        status.contains("feet give the force in") && status.contains("Hicks et al."),
        "{status}"
    );

    // reduction off: the take's own figures, said to be so
    press(&mut ui, &mut wb, ":set consistent off<Enter>");
    assert!(ui.error.is_none(), "{:?}", ui.error);
    let s = screen(&ui, &wb, 80, 24);
    let row = residual_row(&s).unwrap_or_else(|| panic!("no residual row:\n{s}"));
    let verdict = if before.meets() { "within" } else { "beyond" };
    assert!(
        row.contains(&format!(
            "force {:.1} % (≤5 %), moment {:.2} % (≤1 %): {verdict}",
            before.force_pct(),
            before.moment_pct()
        )) && row.contains("not reduced"),
        "{row}"
    );
    // no contact, no residual figures: the row gives its place back
    press(&mut ui, &mut wb, ":set contact none<Enter>");
    let s = screen(&ui, &wb, 80, 24);
    assert!(residual_row(&s).is_none(), "{s}");
}
