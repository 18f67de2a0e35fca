//! The curves pane shows more than the selection's two curves (issue 15), each a session
//! command (`set overlay mirror|angle|feet|weights|sim|none`), at 180×50 as charts and at
//! 80×24 still readable:
//! - `feet`: both feet's vertical ground forces, whose sum carries the body's weight on
//!   average over a walk (Newton's second law over a take that starts and ends at speed);
//! - `angle`: the moment against the angle (the joint's work loop);
//! - `weights`: the torques of the last `compare weights`, one curve per body mass, the
//!   heavier body's peak the larger;
//! - `sim`: the simulated angle over the reference and the tracking error `q_sim − q_ref`,
//!   whose value now is the difference of the two series.

mod common;

use articula::session::workbench::{Overlay, angle_series, reference_series, simulated_coord};
use articula::session::{Builtin, Workbench};
use common::tui::{press, screen};
use std::sync::Arc;

fn demo_at(dir: &std::path::Path, w: u16, h: u16) -> (articula::tui::Ui, Workbench) {
    common::tui::demo_in(w, h, Workbench::new(Arc::new(Builtin), dir, dir))
}

fn line_with<'a>(text: &'a str, part: &str) -> &'a str {
    text.lines()
        .find(|l| l.contains(part))
        .unwrap_or_else(|| panic!("no line with {part:?}:\n{text}"))
}

#[test]
fn feet_draws_both_feet_vertical_ground_forces_which_carry_the_weight() {
    let dir = tempfile::tempdir().unwrap();
    for (w, h) in [(180, 50), (80, 24)] {
        let (mut ui, mut wb) = demo_at(dir.path(), w, h);
        press(&mut ui, &mut wb, ":set overlay feet<Enter>");
        assert_eq!(wb.overlay, Overlay::Feet);
        // without contact the pane says how to get them
        press(&mut ui, &mut wb, ":set contact none<Enter>");
        let text = screen(&ui, &wb, w, h);
        assert!(
            text.contains("no ground forces: set contact feet"),
            "{text}"
        );
        press(&mut ui, &mut wb, ":set contact feet<Enter>");
        assert!(ui.error.is_none(), "{:?}", ui.error);
        let text = screen(&ui, &wb, w, h);
        let label = line_with(&text, "foot vertical ground force");
        assert!(
            label.contains("[N]") && label.contains("foot now"),
            "{label}"
        );
        // the upper curve is the selection's torque
        assert!(text.contains("knee_l:flexion torque"), "{text}");
    }
    let (mut ui, mut wb) = demo_at(dir.path(), 100, 30);
    press(&mut ui, &mut wb, ":set contact feet<Enter>");
    let r = wb.fresh_results().unwrap();
    assert_eq!(r.feet.names.len(), 2, "{:?}", r.feet.names);
    // the mean of both feet's vertical force is the body's weight, within a tenth
    let n = r.feet.rows() as f64;
    let mean = (0..r.feet.rows())
        .map(|k| r.feet.row(k).iter().sum::<f64>())
        .sum::<f64>()
        / n;
    let weight = r.model.total_mass() * 9.81;
    assert!(
        (mean - weight).abs() < 0.1 * weight,
        "mean {mean} N, weight {weight} N"
    );
    press(&mut ui, &mut wb, ":set overlay nonsense<Enter>");
    let e = ui.error.clone().unwrap();
    assert!(
        e.contains("mirror, angle, feet, weights, sim or none"),
        "{e}"
    );
}

#[test]
fn angle_draws_the_moment_against_the_angle_at_any_size() {
    let dir = tempfile::tempdir().unwrap();
    for (w, h) in [(180, 50), (80, 24)] {
        let (mut ui, mut wb) = demo_at(dir.path(), w, h);
        press(&mut ui, &mut wb, ":set overlay angle<Enter>");
        assert_eq!(wb.overlay, Overlay::Angle);
        let text = screen(&ui, &wb, w, h);
        // the angle over time above, the moment against it below, its x axis in degrees
        assert!(text.contains("knee_l:flexion angle [deg]"), "{text}");
        assert!(
            text.contains("knee_l:flexion torque against angle [N·m]"),
            "{text}"
        );
        if h >= 36 {
            // the axes' ends labelled with their units
            assert!(text.contains("angle [deg] "), "{text}");
            assert!(text.contains(" N·m│"), "{text}");
        }
    }
}

#[test]
fn weights_draws_the_last_comparison_one_curve_per_mass() {
    let dir = tempfile::tempdir().unwrap();
    let (mut ui, mut wb) = demo_at(dir.path(), 180, 50);
    press(&mut ui, &mut wb, ":set overlay weights<Enter>");
    let text = screen(&ui, &wb, 180, 50);
    assert!(text.contains("no comparison: compare weights"), "{text}");
    press(
        &mut ui,
        &mut wb,
        ":compare weights 60,90,120 joint LeftLeg cmp.svg<Enter>",
    );
    assert!(ui.error.is_none(), "{:?}", ui.error);
    assert!(wb.last_message().contains("set overlay weights"));
    let cmp = wb.comparison.clone().expect("a comparison");
    assert_eq!(cmp.runs.len(), 3);
    let peak = |x: &[f64]| x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    assert!(peak(&cmp.runs[0].1) < peak(&cmp.runs[2].1));
    for (w, h) in [(180, 50), (80, 24)] {
        let text = screen(&ui, &wb, w, h);
        let label = line_with(&text, " at 60 kg torque");
        assert!(
            label.starts_with("LeftLeg.Xrotation at 60 kg torque"),
            "{label}"
        );
        assert!(label.contains("│ 90 kg now"), "{label}");
    }
    // another take has no comparison
    press(&mut ui, &mut wb, ":load demo:walk as other<Enter>");
    assert!(wb.comparison.is_none());
}

#[test]
fn sim_draws_the_tracking_error_of_the_selection() {
    let dir = tempfile::tempdir().unwrap();
    let (mut ui, mut wb) = demo_at(dir.path(), 180, 50);
    press(&mut ui, &mut wb, ":set overlay sim<Enter>");
    let text = screen(&ui, &wb, 180, 50);
    assert!(text.contains("no simulation: run sim"), "{text}");
    press(
        &mut ui,
        &mut wb,
        ":set kp 100<Enter>:set kv 20<Enter>:run sim<Enter>",
    );
    assert!(ui.error.is_none(), "{:?}", ui.error);
    press(&mut ui, &mut wb, "}}}}}}");
    let text = screen(&ui, &wb, 180, 50);
    // the selection is an anatomical axis: the simulation shows its joint's coordinate
    let (r, sim) = (wb.latest_results().unwrap(), &wb.sim.as_ref().unwrap().0);
    let c = simulated_coord(r, sim, wb.selection.as_deref().unwrap()).unwrap();
    assert_eq!(c, "LeftLeg.Xrotation");
    let (q, y) = (
        angle_series(sim, &c).unwrap(),
        reference_series(sim, &c).unwrap(),
    );
    let k = wb.frame;
    let e = (q[k] - y[k]).to_degrees();
    let label = line_with(&text, "tracking error [deg]");
    let now = label
        .split("now ")
        .nth(1)
        .unwrap()
        .split_whitespace()
        .next()
        .unwrap();
    let shown: f64 = now.parse().unwrap();
    assert!((shown - e).abs() < 0.051, "{label}: expected {e}");
    assert!(line_with(&text, "simulated [deg]").contains("│ reference now"));
    let text = screen(&ui, &wb, 80, 24);
    assert!(text.contains("tracking error [deg]"), "{text}");
}
