//! The curves of the selected coordinate use the room they are given (issue 15): on a tall
//! terminal (36 rows and more) a third of the height, as braille line charts with y ticks at
//! round values in the coordinate's unit, a zero line, the time axis on the file's clock, the
//! current-frame cursor and the running min/max marked; at 80×24 and 100×30 the compact
//! sparklines. Geometry is read from the drawn buffer, as a user reads the screen.

mod common;

use articula::session::Workbench;
use articula::tui::curves::{CHARTS_FROM_ROWS, curves_height, nice_ticks};
use common::tui::{buffer, press, screen};
use ratatui::style::{Color, Modifier};

fn demo(width: u16, height: u16) -> (articula::tui::Ui, Workbench) {
    common::tui::demo_in(width, height, Workbench::default())
}

/// The row (0-based) of the first line that starts with `prefix`.
fn row_of(text: &str, prefix: &str) -> usize {
    text.lines()
        .position(|l| l.starts_with(prefix))
        .unwrap_or_else(|| panic!("no line starts with {prefix:?}:\n{text}"))
}

#[test]
fn tall_terminals_give_the_curves_a_third_of_the_height_as_line_charts() {
    let (w, h) = (180, 50);
    let (mut ui, mut wb) = demo(w, h);
    press(&mut ui, &mut wb, "}}}}}}}}}}}}");
    let text = screen(&ui, &wb, w, h);
    let angle = row_of(&text, "knee_l:flexion angle [deg]");
    let torque = row_of(&text, "knee_l:flexion torque [N·m]");
    let timeline = row_of(&text, "⏸");
    assert!(timeline - angle >= (h / 3) as usize, "{text}");
    assert!(torque - angle >= 6, "each chart has room: {text}");
    let lines: Vec<&str> = text.lines().collect();
    // y ticks: round numbers, the top one with the unit, on an axis
    // (the first row with an axis: a chart may leave its top row blank to fit its ticks)
    let top = |from: usize| lines[from + 1..].iter().find(|l| l.contains('│')).unwrap();
    assert!(top(angle).contains(" deg│"), "{}", top(angle));
    assert!(top(torque).contains(" N·m│"), "{}", top(torque));
    let tick = |l: &str| -> Option<f64> {
        let (head, _) = l.split_once('│')?;
        head.split_whitespace().next()?.parse().ok()
    };
    let ticks: Vec<f64> = lines[torque + 1..timeline]
        .iter()
        .filter_map(|l| tick(l))
        .collect();
    assert!(ticks.len() >= 3, "{ticks:?}");
    // the demo's knee moment changes sign: zero is a tick, and a dotted zero line runs along it
    let zero_row = (torque + 1..timeline)
        .find(|&r| tick(lines[r]) == Some(0.0))
        .expect("a 0 tick");
    assert!(
        lines[zero_row].matches('•').count() > 10,
        "{}",
        lines[zero_row]
    );
    // the time axis: the file's clock from the first to the last frame, under the lower chart
    // (and over the take's residual figures: the demo walk stands on a floor)
    assert!(
        lines[timeline - 1].starts_with("residuals after reduction"),
        "{text}"
    );
    let axis = lines[timeline - 2];
    assert!(
        axis.trim_start().starts_with("0.00 s") && axis.trim_end().ends_with("3.99 s"),
        "{axis}"
    );
    // the running min and max are marked on the curves
    let marks = lines[angle..timeline]
        .iter()
        .map(|l| l.matches('█').count())
        .sum::<usize>();
    assert!(marks >= 2, "{text}");
}

/// The columns of the cells drawn in `color` between rows `a..b`.
fn columns_in(buf: &ratatui::buffer::Buffer, a: u16, b: u16, color: Color) -> Vec<u16> {
    let mut cols: Vec<u16> = (a..b)
        .flat_map(|y| (0..buf.area.width).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let c = &buf[(x, y)];
            c.fg == color && c.symbol() != " "
        })
        .map(|(x, _)| x)
        .collect();
    cols.sort_unstable();
    cols.dedup();
    cols
}

#[test]
fn the_cursor_is_one_column_that_follows_the_frame() {
    let (w, h) = (180, 50);
    let (mut ui, mut wb) = demo(w, h);
    ui.color = true;
    let text = screen(&ui, &wb, w, h);
    let (a, b) = (
        row_of(&text, "knee_l:flexion angle") as u16,
        row_of(&text, "⏸") as u16,
    );
    let frames = wb.frames();
    let mut seen = vec![];
    for k in [frames / 4, frames / 2, 3 * frames / 4] {
        press(&mut ui, &mut wb, "g");
        for _ in 0..k / 10 {
            press(&mut ui, &mut wb, "}");
        }
        let buf = buffer(&ui, &wb, w, h);
        let cols = columns_in(&buf, a, b, Color::Yellow);
        // one braille dot column: one cell, or two where it falls on a cell's edge
        assert!(
            cols.len() == 1 || (cols.len() == 2 && cols[1] == cols[0] + 1),
            "one cursor column at frame {}: {cols:?}",
            wb.frame
        );
        seen.push((wb.frame, cols[0]));
    }
    // the column moves in proportion to the frame: equal steps of frames, equal steps of columns
    let (d1, d2) = (seen[1].1 - seen[0].1, seen[2].1 - seen[1].1);
    assert!(d1 > 20 && (d1 as i32 - d2 as i32).abs() <= 1, "{seen:?}");
}

#[test]
fn frames_not_quoted_are_drawn_apart_in_the_torque_chart() {
    let (w, h) = (180, 50);
    let (mut ui, wb) = demo(w, h);
    let r = wb.latest_results().unwrap();
    let left_out = (0..wb.frames()).filter(|&k| !r.quoted(k)).count();
    assert!(left_out > 0, "the demo's edge frames are left out");
    let text = screen(&ui, &wb, w, h);
    let (a, b) = (
        row_of(&text, "knee_l:flexion torque") as u16,
        row_of(&text, "⏸") as u16,
    );
    // without colours: dim
    let buf = buffer(&ui, &wb, w, h);
    let dim = (a + 1..b)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let c = &buf[(x, y)];
            c.modifier.contains(Modifier::DIM) && c.symbol() != " "
        })
        .count();
    assert!(dim > 5, "{text}");
    // with colours: grey
    ui.color = true;
    let buf = buffer(&ui, &wb, w, h);
    let grey = columns_in(&buf, a + 1, b, Color::DarkGray);
    assert!(grey.len() > 5, "{grey:?}");
}

#[test]
fn small_terminals_keep_the_compact_sparklines() {
    for (w, h) in [(80, 24), (100, 30), (120, CHARTS_FROM_ROWS - 1)] {
        let (ui, wb) = demo(w, h);
        let text = screen(&ui, &wb, w, h);
        assert!(
            !text.contains("deg│") && !text.contains("N·m│"),
            "{w}×{h}:\n{text}"
        );
        let angle = row_of(&text, "knee_l:flexion angle");
        let torque = row_of(&text, "knee_l:flexion torque");
        assert_eq!(torque - angle, 3, "{w}×{h}:\n{text}");
        assert_eq!(curves_height(h), 6);
    }
    assert_eq!(curves_height(CHARTS_FROM_ROWS), CHARTS_FROM_ROWS / 3);
}

#[test]
fn ticks_land_on_round_values_and_hold_zero() {
    for (lo, hi) in [
        (-56.9, 57.2),
        (-0.003, 0.0141),
        (3.3, 67.7),
        (-1200.0, -3.0),
    ] {
        let t = nice_ticks(lo, hi, 5);
        assert!(t[0] <= lo && *t.last().unwrap() >= hi, "{lo} {hi}: {t:?}");
        if lo < 0.0 && hi > 0.0 {
            assert!(t.contains(&0.0), "{t:?}");
        }
    }
}

#[test]
fn mirror_names_swap_the_sides_as_exporters_write_them() {
    use articula::session::workbench::mirror_names;
    for (a, b) in [
        ("knee_l:flexion", "knee_r:flexion"),
        ("LeftLeg.Xrotation", "RightLeg.Xrotation"),
        ("RightLeg.Xrotation", "LeftLeg.Xrotation"),
        ("lThigh.Zrotation", "rThigh.Zrotation"),
        ("LHipJoint.Yrotation", "RHipJoint.Yrotation"),
        ("Foot_L.Xrotation", "Foot_R.Xrotation"),
        ("thigh.L.Xrotation", "thigh.R.Xrotation"),
        ("mHipLeft.Xrotation", "mHipRight.Xrotation"),
        ("L_Knee.Zrotation", "R_Knee.Zrotation"),
        (
            "mixamorig:LeftUpLeg.Xrotation",
            "mixamorig:RightUpLeg.Xrotation",
        ),
        ("LeftLeg:wx", "RightLeg:wx"),
    ] {
        assert!(
            mirror_names(a).contains(&b.to_string()),
            "{a}: {:?}",
            mirror_names(a)
        );
    }
    // a name without a side has no mirror (`Hips`, `Spine1`; `lowerback` is not `l`+`owerback`)
    assert!(mirror_names("Hips.Xrotation").is_empty());
    assert!(mirror_names("lowerback.Xrotation").is_empty());
}

#[test]
fn m_draws_the_mirror_joints_curves_beside_the_selected_ones_without_recomputing() {
    let (w, h) = (180, 50);
    let (mut ui, mut wb) = demo(w, h);
    ui.color = true;
    press(&mut ui, &mut wb, "}}}}}}}}}}");
    let before = wb.latest_results().unwrap() as *const _;
    let text = screen(&ui, &wb, w, h);
    let (a, b) = (
        row_of(&text, "knee_l:flexion angle") as u16,
        row_of(&text, "⏸") as u16,
    );
    assert!(columns_in(&buffer(&ui, &wb, w, h), a + 1, b, Color::Green).is_empty());
    press(&mut ui, &mut wb, "m");
    assert_eq!(wb.overlay, articula::session::workbench::Overlay::Mirror);
    assert_eq!(
        wb.latest_results().unwrap() as *const _,
        before,
        "a view setting"
    );
    let text = screen(&ui, &wb, w, h);
    let angle = text.lines().nth(a as usize).unwrap();
    assert!(angle.contains("│ knee_r:flexion now "), "{angle}");
    let torque = text
        .lines()
        .find(|l| l.starts_with("knee_l:flexion torque"))
        .unwrap();
    assert!(torque.contains("│ knee_r:flexion now "), "{torque}");
    // the right knee's curve, in its own colour, across the take
    let green = columns_in(&buffer(&ui, &wb, w, h), a + 1, b, Color::Green);
    assert!(green.len() > 100, "{green:?}");
    // the same from a session command, and off again; the compact form says it in its label
    press(&mut ui, &mut wb, ":set overlay none<Enter>");
    assert_eq!(wb.overlay, articula::session::workbench::Overlay::None);
    let (mut ui, mut wb) = demo(80, 24);
    press(&mut ui, &mut wb, ":set overlay mirror<Enter>");
    let text = screen(&ui, &wb, 80, 24);
    assert!(text.contains("│ knee_r:flexion now"), "{text}");
    press(&mut ui, &mut wb, ":set overlay both<Enter>");
    assert!(
        ui.error
            .as_deref()
            .unwrap_or("")
            .contains("expected mirror, angle, feet, weights, sim or none")
    );
}
