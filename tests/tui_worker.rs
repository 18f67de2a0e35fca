//! Long computations run on the terminal UI's worker thread: while one runs, the status line
//! shows its label and progress, keys are still handled (frames, selection, help, resize, the
//! command line), Esc cancels it and leaves the workbench as it was (no file written, an old
//! file untouched, commands that waited for it dropped), and `q` quits, cancelling it.
//!
//! Nothing here depends on how fast the machine is: a *gated* engine (the built-in engine, but
//! its inverse dynamics waits at a gate once done until the test opens it or the job is
//! cancelled) holds a job mid-way for as long as the test needs; waits poll with a generous
//! limit that only guards against a hang.

mod common;

use common::tui::{press, screen};

use articula::error::Error;
use articula::model::Model;
use articula::session::engine::{Analysis, Control, Engine, Params, States, Take};
use articula::session::{Builtin, Command, Workbench, parse_line};
use articula::tui::{Ui, draw};
use crossterm::event::{Event, KeyCode, KeyEvent, KeyModifiers};
use ratatui::Terminal;
use ratatui::backend::TestBackend;
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

/// Guards the waits below against a hang; never a measure of speed.
const LIMIT: Duration = Duration::from_secs(300);

/// The built-in engine whose inverse dynamics, while `armed`, waits at a gate after computing
/// until the gate opens (`Ok`) or the job is cancelled (`Err(Cancelled)`, counted in `stopped`).
#[derive(Default)]
struct Gate {
    armed: AtomicBool,
    open: Mutex<bool>,
    cv: Condvar,
    /// Jobs that stopped at the gate because they were cancelled.
    stopped: AtomicUsize,
    /// Inverse-dynamics runs that reached the gate.
    reached: AtomicUsize,
}

struct Gated(Arc<Gate>);

impl Gate {
    fn wait(&self, ctl: &Control) -> Result<(), Error> {
        self.reached.fetch_add(1, Ordering::SeqCst);
        let mut open = self.open.lock().unwrap();
        while !*open {
            if ctl.is_cancelled() {
                self.stopped.fetch_add(1, Ordering::SeqCst);
                return Err(Error::Cancelled);
            }
            open = self
                .cv
                .wait_timeout(open, Duration::from_millis(2))
                .unwrap()
                .0;
        }
        Ok(())
    }
}

impl Engine for Gated {
    fn load(&self, path: &Path, params: &Params) -> Result<Take, Error> {
        Builtin.load(path, params)
    }
    fn load_motion(&self, model: &Model, path: &Path) -> Result<States, Error> {
        Builtin.load_motion(model, path)
    }
    fn inverse_dynamics(
        &self,
        take: &Take,
        params: &Params,
        ctl: &Control,
    ) -> Result<Analysis, Error> {
        let r = Builtin.inverse_dynamics(take, params, ctl)?;
        if self.0.armed.load(Ordering::SeqCst) {
            self.0.wait(ctl)?;
        }
        Ok(r)
    }
    fn simulate(&self, take: &Take, params: &Params, ctl: &Control) -> Result<Analysis, Error> {
        Builtin.simulate(take, params, ctl)
    }
    fn blend(&self, a: &Take, b: &Take, window: (f64, f64)) -> Result<Take, Error> {
        Builtin.blend(a, b, window)
    }
    fn export_bvh(
        &self,
        take: &Take,
        params: &Params,
        motion: Option<&Analysis>,
        path: &Path,
        ctl: &Control,
    ) -> Result<(), Error> {
        Builtin.export_bvh(take, params, motion, path, ctl)
    }
}

/// Polls the worker until `done` holds (panics after [`LIMIT`]: a hang, not a slow machine).
fn wait_for(
    ui: &mut Ui,
    wb: &mut Workbench,
    what: &str,
    mut done: impl FnMut(&Ui, &Workbench) -> bool,
) {
    let start = Instant::now();
    while !done(ui, wb) {
        ui.poll(wb);
        assert!(start.elapsed() < LIMIT, "no {what} after {LIMIT:?}");
        std::thread::sleep(Duration::from_millis(2));
    }
}

fn idle(ui: &Ui, _: &Workbench) -> bool {
    ui.running.is_none()
}

/// A threaded UI over the gated engine with `demo:walk` loaded and its results computed.
fn gated_demo(dir: &Path) -> (Ui, Workbench, Arc<Gate>) {
    let gate = Arc::new(Gate::default());
    let mut wb = Workbench::new(Arc::new(Gated(gate.clone())), dir, dir);
    let mut ui = Ui::new();
    ui.color = false;
    ui.exec(&mut wb, &parse_line("load demo:walk", 1).unwrap().unwrap());
    // the load and the recompute that follows it run on the worker
    assert!(ui.running.is_some());
    wait_for(&mut ui, &mut wb, "results", |ui, wb| {
        ui.running.is_none() && wb.fresh_results().is_some()
    });
    assert!(ui.error.is_none(), "{:?}", ui.error);
    (ui, wb, gate)
}

#[test]
fn a_running_comparison_shows_progress_keeps_keys_and_esc_leaves_the_workbench_unchanged() {
    let dir = tempfile::tempdir().unwrap();
    let (mut ui, mut wb, gate) = gated_demo(dir.path());
    press(&mut ui, &mut wb, ":select LeftLeg<Enter>");
    let results = wb.fresh_results().unwrap().clone();
    let (params, takes) = (wb.params.clone(), wb.takes.len());
    gate.armed.store(true, Ordering::SeqCst);

    press(
        &mut ui,
        &mut wb,
        ":compare weights 60,80,100 joint LeftLeg knee.svg<Enter>",
    );
    let ctl = ui
        .running
        .as_ref()
        .expect("the comparison runs")
        .control
        .clone();
    // the first mass is done and waits at the gate: a third of the job
    wait_for(&mut ui, &mut wb, "progress", |_, _| {
        gate.reached.load(Ordering::SeqCst) == 1
    });
    assert!(
        (ctl.progress() - 1.0 / 3.0).abs() < 1e-5,
        "{}",
        ctl.progress()
    );
    let s = screen(&ui, &wb, 80, 24);
    assert!(
        s.contains("⟳ compare weights 60, 80, 100 kg 33%  (Esc cancels)"),
        "{s}"
    );

    // keys while it runs: frames, the tree, help, resizes, the command line
    press(&mut ui, &mut wb, "]]}");
    assert_eq!(wb.frame, 12);
    press(&mut ui, &mut wb, "<Down>");
    let moved = wb.selection.clone();
    assert_ne!(moved.as_deref(), Some("LeftLeg.Xrotation"));
    press(&mut ui, &mut wb, "?");
    assert!(screen(&ui, &wb, 120, 40).contains("Help"));
    press(&mut ui, &mut wb, "x");
    for (w, h) in [(200, 60), (60, 16), (30, 8), (80, 24)] {
        let s = screen(&ui, &wb, w, h);
        assert_eq!(s.lines().count(), h as usize);
    }
    // another long command waits for the job, and so does a `set` typed after it (commands
    // apply in order, as in a replay)
    press(
        &mut ui,
        &mut wb,
        ":export csv all.csv<Enter>:set body.mass 90<Enter>",
    );
    assert_eq!(wb.params.take.body.mass_kg, 75.0);
    assert!(
        screen(&ui, &wb, 100, 30).contains("(Esc cancels, 2 command(s) wait)"),
        "{}",
        screen(&ui, &wb, 100, 30)
    );
    assert!(ui.running.is_some(), "held at the gate until cancelled");

    // Esc: the job stops at its next check, nothing is written, what waited is dropped
    press(&mut ui, &mut wb, "<Esc>");
    assert!(ctl.is_cancelled());
    wait_for(&mut ui, &mut wb, "the end of the job", idle);
    assert_eq!(gate.stopped.load(Ordering::SeqCst), 1);
    assert!(!dir.path().join("knee.svg").exists());
    assert!(!dir.path().join("all.csv").exists());
    assert!(
        wb.messages
            .iter()
            .any(|m| m == "cancelled compare weights 60, 80, 100 kg"),
        "{:?}",
        wb.messages
    );
    assert!(Arc::ptr_eq(wb.fresh_results().unwrap(), &results));
    assert_eq!(wb.params, params);
    assert_eq!(wb.takes.len(), takes);
    assert_eq!(wb.selection, moved);
    assert!(ui.queue.is_empty() && ui.error.is_none());

    // open the gate: the same comparison runs to the end and writes its chart
    *gate.open.lock().unwrap() = true;
    press(
        &mut ui,
        &mut wb,
        ":compare weights 60,80,100 joint LeftLeg knee.svg<Enter>",
    );
    wait_for(&mut ui, &mut wb, "the chart", idle);
    assert!(ui.error.is_none(), "{:?}", ui.error);
    let svg = std::fs::read_to_string(dir.path().join("knee.svg")).unwrap();
    assert!(svg.contains("100 kg"));
    assert!(
        wb.last_message()
            .starts_with("compared LeftLeg.Xrotation torque")
    );
}

/// A parameter changed while a job runs applies at once (the panel shows it; the job computes
/// from its own snapshot) and the recompute it needs follows the job.
#[test]
fn a_parameter_changed_during_a_job_applies_at_once_and_its_recompute_follows() {
    let dir = tempfile::tempdir().unwrap();
    let (mut ui, mut wb, gate) = gated_demo(dir.path());
    gate.armed.store(true, Ordering::SeqCst);
    press(
        &mut ui,
        &mut wb,
        ":compare weights 60,100 joint LeftLeg knee.csv<Enter>",
    );
    wait_for(&mut ui, &mut wb, "the first mass", |_, _| {
        gate.reached.load(Ordering::SeqCst) == 1
    });
    // the body mass row of the parameter panel, one step up
    press(&mut ui, &mut wb, "<Tab><Tab><Right>");
    assert_eq!(wb.params.take.body.mass_kg, 80.0);
    assert!(screen(&ui, &wb, 100, 30).contains("80 kg"));
    assert!(wb.fresh_results().is_none());
    assert!(
        ui.running
            .as_ref()
            .unwrap()
            .label
            .starts_with("compare weights")
    );
    // the comparison ends with its own masses; then the results are recomputed at 80 kg
    *gate.open.lock().unwrap() = true;
    wait_for(&mut ui, &mut wb, "the recompute", |ui, wb| {
        ui.running.is_none() && wb.fresh_results().is_some()
    });
    assert!(ui.error.is_none(), "{:?}", ui.error);
    let csv = std::fs::read_to_string(dir.path().join("knee.csv")).unwrap();
    assert!(
        csv.starts_with("time,tau:LeftLeg.Xrotation:60kg,tau:LeftLeg.Xrotation:100kg"),
        "{}",
        &csv[..60]
    );
    let r = wb.fresh_results().unwrap();
    assert!((r.model.total_mass() - 80.0).abs() < 1e-9);
}

#[test]
fn a_cancelled_export_leaves_the_old_file_and_a_waiting_recompute_is_dropped() {
    let dir = tempfile::tempdir().unwrap();
    let (mut ui, mut wb, gate) = gated_demo(dir.path());
    let out = dir.path().join("states.csv");
    std::fs::write(&out, "old\n").unwrap();
    let before = wb.fresh_results().unwrap().clone();
    gate.armed.store(true, Ordering::SeqCst);
    // the recompute after `set` runs; the export replaces it and computes the results itself
    press(&mut ui, &mut wb, ":set smooth none<Enter>");
    assert!(ui.running.as_ref().is_some_and(|r| r.replaceable));
    press(&mut ui, &mut wb, ":export csv states.csv<Enter>");
    let r = ui.running.as_ref().unwrap();
    assert_eq!(r.label, "export csv states.csv");
    assert!(!r.replaceable);
    let ctl = r.control.clone();
    wait_for(&mut ui, &mut wb, "the export's inverse dynamics", |_, _| {
        gate.reached.load(Ordering::SeqCst) >= 1 && ctl.progress() >= 0.8
    });
    press(&mut ui, &mut wb, "<Esc>");
    wait_for(&mut ui, &mut wb, "the end of the export", idle);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "old\n");
    // nothing was stored and no recompute started after the cancel
    assert!(wb.fresh_results().is_none());
    assert!(Arc::ptr_eq(wb.latest_results().unwrap(), &before));
    assert!(ui.running.is_none());
    // with the gate open, the export writes the unsmoothed results and keeps them
    *gate.open.lock().unwrap() = true;
    press(&mut ui, &mut wb, ":export csv states.csv<Enter>");
    wait_for(&mut ui, &mut wb, "the export", idle);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.starts_with("time,q:"),
        "{}",
        &text[..40.min(text.len())]
    );
    assert!(wb.fresh_results().is_some());
}

#[test]
fn q_during_a_job_cancels_it_and_the_event_loop_returns() {
    let dir = tempfile::tempdir().unwrap();
    let (mut ui, mut wb, gate) = gated_demo(dir.path());
    gate.armed.store(true, Ordering::SeqCst);
    press(&mut ui, &mut wb, ":compare weights 60,80 knee.csv<Enter>");
    let ctl = ui.running.as_ref().unwrap().control.clone();
    let mut term = Terminal::new(TestBackend::new(80, 24)).unwrap();
    // events: nothing until the job waits at the gate, a resize, a frame step, then `q`
    let mut script = vec![
        Event::Key(KeyEvent::new(KeyCode::Char('q'), KeyModifiers::NONE)),
        Event::Key(KeyEvent::new(KeyCode::Char(']'), KeyModifiers::NONE)),
        Event::Resize(100, 30),
    ];
    let start = Instant::now();
    let g = gate.clone();
    articula::tui::event_loop(&mut term, &mut ui, &mut wb, |_| {
        assert!(start.elapsed() < LIMIT, "the loop did not quit");
        if g.reached.load(Ordering::SeqCst) == 0 {
            std::thread::sleep(Duration::from_millis(2));
            return Ok(None);
        }
        Ok(script.pop())
    })
    .unwrap();
    assert!(ui.quit);
    assert!(ctl.is_cancelled());
    assert_eq!(wb.frame, 1);
    // the worker stops at the gate's next check (polled, not timed)
    let start = Instant::now();
    while gate.stopped.load(Ordering::SeqCst) == 0 {
        assert!(start.elapsed() < LIMIT, "the worker did not stop");
        std::thread::sleep(Duration::from_millis(2));
    }
    assert!(!dir.path().join("knee.csv").exists());
}

/// The real engine on a long generated take (20 s at 120 fps): loading, the recompute, and a
/// comparison at five masses all run on the worker; Esc right after the start cancels the
/// comparison long before its end, and run again it writes the same CSV as the inline
/// (headless) path.
#[test]
fn a_long_generated_take_loads_and_compares_on_the_worker() {
    let dir = tempfile::tempdir().unwrap();
    let take = dir.path().join("long.bvh");
    articula::pipeline::generate_walk(&take, 120.0, 20.0, 1.0).unwrap();
    let mut wb = Workbench::new(Arc::new(Builtin), dir.path(), dir.path());
    let mut ui = Ui::new();
    ui.exec(
        &mut wb,
        &Command::Load {
            path: take.clone(),
            name: None,
        },
    );
    assert_eq!(
        ui.running.as_ref().unwrap().label,
        format!("loading {}", take.display())
    );
    assert!(screen(&ui, &wb, 80, 24).contains("⟳ loading"));
    wait_for(&mut ui, &mut wb, "results", |ui, wb| {
        ui.running.is_none() && wb.fresh_results().is_some()
    });
    assert_eq!(wb.frames(), 2400);
    let line = ":compare weights 60,70,80,90,100 joint LeftLeg cmp.csv<Enter>";
    press(&mut ui, &mut wb, line);
    assert!(ui.running.is_some());
    press(&mut ui, &mut wb, "<Esc>");
    wait_for(&mut ui, &mut wb, "the cancel", idle);
    assert!(!dir.path().join("cmp.csv").exists());
    assert!(wb.last_message().starts_with("cancelled compare weights"));

    // to the end, watching the progress: it only grows
    press(&mut ui, &mut wb, line);
    let ctl = ui.running.as_ref().unwrap().control.clone();
    let mut last = 0.0;
    wait_for(&mut ui, &mut wb, "the comparison", |ui, _| {
        let p = ctl.progress();
        assert!(p >= last, "progress went back from {last} to {p}");
        last = p;
        ui.running.is_none()
    });
    assert!(ui.error.is_none(), "{:?}", ui.error);
    let threaded = std::fs::read(dir.path().join("cmp.csv")).unwrap();
    // the same command applied inline (a replay) writes the same bytes
    let mut inline = Workbench::new(Arc::new(Builtin), dir.path(), dir.path());
    for l in [
        format!("load {}", take.display()),
        "compare weights 60,70,80,90,100 joint LeftLeg inline.csv".into(),
    ] {
        inline.apply(&parse_line(&l, 1).unwrap().unwrap()).unwrap();
    }
    assert_eq!(
        threaded,
        std::fs::read(dir.path().join("inline.csv")).unwrap()
    );
}

/// `articula a.bvh b.bvh` loads both: the second load and a `set` typed meanwhile wait for
/// the first and apply in order.
#[test]
fn commands_given_during_a_job_apply_in_order_when_it_ends() {
    let dir = tempfile::tempdir().unwrap();
    let mut wb = Workbench::new(Arc::new(Builtin), dir.path(), dir.path());
    let mut ui = Ui::new();
    for line in [
        "load demo:walk as a",
        "load demo:walk as b",
        "set body.mass 90",
    ] {
        ui.exec(&mut wb, &parse_line(line, 1).unwrap().unwrap());
    }
    assert_eq!(ui.queue.len(), 2, "the second load and the set wait");
    wait_for(&mut ui, &mut wb, "both takes", |ui, wb| {
        ui.running.is_none() && ui.queue.is_empty() && wb.fresh_results().is_some()
    });
    assert!(ui.error.is_none(), "{:?}", ui.error);
    let names: Vec<&str> = wb.takes.iter().map(|t| t.name.as_str()).collect();
    assert_eq!(names, ["a", "b"]);
    assert_eq!(wb.take().unwrap().name, "b");
    let r = wb.fresh_results().unwrap();
    assert!((r.model.total_mass() - 90.0).abs() < 1e-9);
}

/// xorshift64*: a tiny deterministic generator.
struct Rng(u64);
impl Rng {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) % n as u64) as usize
    }
}

/// Random keys against the threaded UI (jobs start, wait, get replaced and cancelled while
/// keys keep coming): no panic on the UI thread or in a worker, and the workbench stays
/// consistent after every event. The interleaving varies from run to run; the invariants do
/// not depend on it.
#[test]
fn random_keys_with_jobs_on_the_worker_never_panic() {
    let dir = tempfile::tempdir().unwrap();
    let mut wb = Workbench::new(Arc::new(Builtin), dir.path(), dir.path());
    let mut ui = Ui::new();
    ui.exec(&mut wb, &parse_line("load demo:walk", 1).unwrap().unwrap());
    wait_for(&mut ui, &mut wb, "results", |ui, wb| {
        ui.running.is_none() && wb.fresh_results().is_some()
    });
    // whole commands now and then, so that long jobs really start
    const LINES: [&str; 8] = [
        ":set body.mass 70<Enter>",
        ":compare weights 60,90 joint LeftLeg c.csv<Enter>",
        ":export svg s.svg<Enter>",
        ":set smooth gaussian:0.02<Enter>",
        ":run sim<Enter>",
        ":load demo:walk as w2<Enter>",
        ":expect peak LeftLeg.Xrotation torque between 0 1e9<Enter>",
        ":report motor m.csv<Enter>",
    ];
    const KEYS: &str = "qhjkl[]{}gG<>r?+-= x";
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let mut term = Terminal::new(TestBackend::new(80, 24)).unwrap();
    for i in 0..1500 {
        match rng.below(40) {
            0 => press(&mut ui, &mut wb, LINES[rng.below(LINES.len())]),
            1 => press(&mut ui, &mut wb, "<Esc>"),
            2 => press(&mut ui, &mut wb, "<Tab>"),
            _ => {
                let c = KEYS.chars().nth(rng.below(KEYS.len())).unwrap();
                ui.handle_key(&mut wb, KeyEvent::new(KeyCode::Char(c), KeyModifiers::NONE));
            }
        }
        ui.quit = false;
        ui.poll(&mut wb);
        term.draw(|f| draw::draw(&ui, &wb, f)).unwrap();
        assert!(
            wb.frame < wb.frames().max(1),
            "event {i}: frame {}",
            wb.frame
        );
        if let (Some(sel), Some(r)) = (&wb.selection, wb.fresh_results()) {
            assert!(
                r.model.v_index(sel).is_some()
                    || articula::session::workbench::is_anatomical(r, sel),
                "event {i}: selection {sel}"
            );
        }
    }
    // let everything started finish (or cancel it), then nothing panicked anywhere
    press(&mut ui, &mut wb, "<Esc>");
    wait_for(&mut ui, &mut wb, "the last job", idle);
    assert!(
        !wb.messages.iter().any(|m| m.contains("worker panicked")),
        "{:?}",
        wb.messages
            .iter()
            .filter(|m| m.contains("panicked"))
            .collect::<Vec<_>>()
    );
}
