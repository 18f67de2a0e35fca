//! An edit recomputes only what it changes (issue 17 item 4), and what it recomputes equals a
//! full recompute bit for bit:
//! - a mass edit (body mass, a link's mass) builds the model again and reruns contact and
//!   inverse dynamics, but not the coordinates, unwrapping, smoothing or derivatives, nor the
//!   fit of the contact thresholds to the feet: the smoothed states and the feet's paths read
//!   no mass;
//! - a smoothing edit reruns the smoothing and all that follows;
//! - a gain, integrator or step edit is the simulation's: inverse dynamics stays fresh.
//!
//! Stage runs are counted through the pipeline's `done(Stage)` hook (`Control::done`,
//! `Workbench::stage_runs`), never timed.

mod common;

use articula::pipeline::stages::Stage;
use articula::session::{Analysis, Workbench};
use common::workbench::{ok, wb_in};
use std::sync::Arc;

/// Every number of the results as bits: q, v, a, torques, anatomical series, feet's forces.
fn bits(r: &Analysis) -> Vec<u64> {
    [
        &r.q.data,
        &r.v.data,
        &r.a.data,
        &r.tau.data,
        &r.anatomy.data,
        &r.feet.data,
        &r.time,
    ]
    .into_iter()
    .flatten()
    .map(|x| x.to_bits())
    .collect()
}

fn results(wb: &Workbench) -> Arc<Analysis> {
    wb.fresh_results().expect("fresh results").clone()
}

/// A fresh workbench on the demo walk with `settings` applied before its only run.
fn full_recompute(dir: &std::path::Path, settings: &[&str]) -> Arc<Analysis> {
    let mut wb = wb_in(dir);
    ok(&mut wb, "load demo:walk");
    for s in settings {
        ok(&mut wb, s);
    }
    ok(&mut wb, "run id");
    assert_eq!(wb.stage_runs(Stage::Smooth), 1);
    results(&wb)
}

#[test]
fn a_mass_edit_reruns_inverse_dynamics_but_not_the_smoothing_and_equals_a_full_recompute() {
    let dir = tempfile::tempdir().unwrap();
    // `auto` settles on feet for the demo walk; the edit keeps that choice (its stance reads
    // no mass) rather than finding it again, with the same results and notes
    for contact in ["set contact none", "set contact feet", "set contact auto"] {
        let mut wb = wb_in(dir.path());
        ok(&mut wb, "load demo:walk");
        ok(&mut wb, contact);
        ok(&mut wb, "run id");
        let first = results(&wb);
        let (smooth, model, id) = (
            wb.stage_runs(Stage::Smooth),
            wb.stage_runs(Stage::Model),
            wb.stage_runs(Stage::InverseDynamics) + wb.stage_runs(Stage::Contact),
        );
        assert_eq!(smooth, 1, "{contact}");

        ok(&mut wb, "set body.mass 91");
        ok(&mut wb, "set link.LeftLeg.mass 4.5");
        ok(&mut wb, "run id");
        let edited = results(&wb);
        assert_eq!(
            wb.stage_runs(Stage::Smooth),
            smooth,
            "{contact}: smoothing reran"
        );
        assert_eq!(wb.stage_runs(Stage::Derivatives), smooth, "{contact}");
        assert_eq!(wb.stage_runs(Stage::Model), model + 1, "{contact}");
        assert_eq!(
            wb.stage_runs(Stage::InverseDynamics) + wb.stage_runs(Stage::Contact),
            id + 1,
            "{contact}: inverse dynamics (or contact) did not rerun"
        );
        // the edit changed the torques, and they are those of a full recompute
        assert_ne!(bits(&first), bits(&edited), "{contact}");
        let full = full_recompute(
            dir.path(),
            &[contact, "set body.mass 91", "set link.LeftLeg.mass 4.5"],
        );
        assert!(bits(&edited) == bits(&full), "{contact}: not bit-identical");
        assert_eq!(edited.note, full.note);
        assert_eq!(edited.brief, full.brief);
        assert_eq!(edited.contact_auto, full.contact_auto);
        assert_eq!(edited.left_out, full.left_out);
        assert_eq!(
            edited.contact_auto.is_some(),
            contact.ends_with("auto"),
            "{contact}"
        );
        // the contact thresholds fitted to the feet read no mass: the edit reuses them
        match (&first.contact_fit, &edited.contact_fit) {
            (None, None) => assert!(contact.ends_with("none")),
            (Some(a), Some(b)) => assert!(Arc::ptr_eq(a, b), "{contact}: fitted again"),
            _ => panic!("{contact}: a fit on one side only"),
        }
    }
}

#[test]
fn a_smoothing_edit_reruns_the_smoothing_and_a_gain_edit_reruns_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let mut wb = wb_in(dir.path());
    ok(&mut wb, "load demo:walk");
    ok(&mut wb, "run id");
    assert_eq!(wb.stage_runs(Stage::Smooth), 1);

    // the simulation's settings leave inverse dynamics fresh: nothing to recompute
    for s in [
        "set kp 500",
        "set kv 45",
        "set integrator euler",
        "set dt 2ms",
    ] {
        ok(&mut wb, s);
        assert!(wb.fresh_results().is_some(), "{s} made the results stale");
    }

    let first = results(&wb);
    ok(&mut wb, "set smooth gaussian:0.02");
    assert!(wb.fresh_results().is_none());
    ok(&mut wb, "run id");
    assert_eq!(wb.stage_runs(Stage::Smooth), 2);
    let edited = results(&wb);
    // another motion: its contact thresholds are fitted again
    let (a, b) = (first.contact_fit.as_ref(), edited.contact_fit.as_ref());
    assert!(!Arc::ptr_eq(a.unwrap(), b.unwrap()));
    let full = full_recompute(dir.path(), &["set smooth gaussian:0.02"]);
    assert!(bits(&edited) == bits(&full));

    // a model edit (the joint model) recomputes everything too
    ok(&mut wb, "set joints ball");
    ok(&mut wb, "run id");
    assert_eq!(wb.stage_runs(Stage::Smooth), 3);
}

/// On the worker, the status line says how long the recompute after an edit took, and its
/// preview (its first clause, which a narrow terminal drops before the verdicts); a mass edit
/// there reruns no smoothing either.
#[test]
fn the_status_line_shows_the_recompute_time_of_an_edit() {
    use articula::session::parse_line;
    use articula::tui::Ui;
    let dir = tempfile::tempdir().unwrap();
    let mut wb = wb_in(dir.path());
    let mut ui = Ui::new();
    ui.color = false;
    let wait = |ui: &mut Ui, wb: &mut Workbench| {
        let start = std::time::Instant::now();
        while ui.running.is_some() {
            ui.poll(wb);
            assert!(start.elapsed().as_secs() < 120, "no result: a hang");
            std::thread::sleep(std::time::Duration::from_millis(2));
        }
    };
    ui.exec(&mut wb, &parse_line("load demo:walk", 1).unwrap().unwrap());
    wait(&mut ui, &mut wb);
    ui.exec(
        &mut wb,
        &parse_line("set body.mass 90", 1).unwrap().unwrap(),
    );
    assert!(ui.running.is_some(), "the edit started no recompute");
    wait(&mut ui, &mut wb);
    assert!(ui.error.is_none(), "{:?}", ui.error);
    assert_eq!(wb.stage_runs(Stage::Smooth), 1);
    assert!(ui.recompute_ms.is_some());
    // wide enough for the whole line, the time is its first clause
    let screen = articula::tui::draw::render_text(&ui, &wb, 240, 30);
    let status = screen.lines().last().unwrap_or("");
    // the demo walk is reduced: the mass edit drew a preview first
    assert!(
        status.starts_with("preview in ") && status.contains(" ms, recomputed in "),
        "{status}"
    );
    assert!(status.contains(" ms; "), "{status}");
    // at 80 columns it is the clause dropped first: the verdicts that end the line stay
    let screen = articula::tui::draw::render_text(&ui, &wb, 80, 24);
    let status = screen.lines().last().unwrap_or("");
    assert!(
        !status.contains("recomputed in") && status.contains("residuals"),
        "{status}"
    );
    // another message replaces it
    ui.exec(
        &mut wb,
        &parse_line("select LeftUpLeg", 1).unwrap().unwrap(),
    );
    let screen = ui.render_text(&wb);
    assert!(!screen.contains("recomputed in"), "{screen}");
}

/// On the worker, a mass edit of a reduced take draws a preview first (`Job::preview`: the
/// last residual reduction evaluated on the new masses), said in the status line and never
/// fresh; then the results proper replace it, the same bits as a fresh session's at that mass
/// (the preview leaves no trace). A smoothing edit draws none.
#[test]
fn a_mass_edit_draws_a_preview_then_the_results_of_a_fresh_session() {
    use articula::dynamics::rra::Started;
    use articula::session::parse_line;
    use articula::tui::Ui;
    let dir = tempfile::tempdir().unwrap();
    let mut wb = wb_in(dir.path());
    let mut ui = Ui::new();
    ui.color = false;
    let started = |r: &Analysis| {
        r.consistency
            .as_ref()
            .and_then(|c| c.adjustments.as_ref())
            .map(|a| a.started)
    };
    // polls until the job is done; returns whether a preview was drawn before, checking it
    let wait = |ui: &mut Ui, wb: &mut Workbench| -> bool {
        let start = std::time::Instant::now();
        let mut previewed = false;
        while ui.running.is_some() {
            ui.poll(wb);
            if !previewed && ui.running.as_ref().is_some_and(|r| r.preview_ms.is_some()) {
                let p = wb
                    .preview
                    .clone()
                    .expect("a preview once the worker sent one");
                assert_eq!(started(&p), Some(Started::Preview));
                assert!(wb.fresh_results().is_none(), "a preview is never fresh");
                assert!(Arc::ptr_eq(wb.latest_results().unwrap(), &p));
                let screen = articula::tui::draw::render_text(ui, wb, 240, 30);
                let status = screen.lines().last().unwrap_or("");
                assert!(status.contains("drawn: a preview in "), "{status}");
                previewed = true;
            }
            assert!(start.elapsed().as_secs() < 120, "no result: a hang");
            std::thread::sleep(std::time::Duration::from_millis(1));
        }
        previewed
    };
    let exec = |ui: &mut Ui, wb: &mut Workbench, line: &str| {
        ui.exec(wb, &parse_line(line, 1).unwrap().unwrap());
    };
    exec(&mut ui, &mut wb, "load demo:walk");
    assert!(
        !wait(&mut ui, &mut wb),
        "the first results have nothing to preview"
    );
    exec(&mut ui, &mut wb, "set body.mass 90");
    assert!(wait(&mut ui, &mut wb), "the mass edit drew no preview");
    assert!(ui.error.is_none(), "{:?}", ui.error);
    assert!(wb.preview.is_none(), "the results replace the preview");
    let edited = results(&wb);
    assert_eq!(started(&edited), Some(Started::Cold));
    let full = full_recompute(dir.path(), &["set body.mass 90"]);
    assert!(bits(&edited) == bits(&full));
    // another smoothing: no preview (the reduction's motion is another)
    exec(&mut ui, &mut wb, "set smooth butterworth:8hz");
    assert!(!wait(&mut ui, &mut wb), "a smoothing edit drew a preview");
}
