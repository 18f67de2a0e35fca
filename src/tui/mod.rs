//! The terminal UI (ratatui + crossterm): draws the [`Workbench`], turns keys and mouse into
//! [`Command`]s.
//!
//! State, events and drawing are kept apart: [`Ui`] holds the interface state and turns input
//! into commands ([`ui`]), [`draw::draw`] is a pure function of `(Ui, Workbench)`, and
//! [`run`] is the event loop. Long computations (`run id`, recomputes after `set`) go to a
//! worker thread with a [`Control`] for progress and cancel (Esc); the loop polls input every
//! 30 ms, so input never blocks. The terminal is restored on exit, on error and on panic (a
//! panic hook). `NO_COLOR` turns colours off. Keys: see [`draw::HELP`] (`?` in the UI).

pub mod draw;
pub mod keys;
pub mod ui;

pub use ui::{Focus, Ui};

use crate::error::Error;
use crate::session::engine::Control;
use crate::session::{Builtin, Command, JobResult, Workbench};
use crossterm::event::{self, DisableMouseCapture, EnableMouseCapture, Event, KeyEventKind};
use crossterm::execute;
use crossterm::terminal::{
    EnterAlternateScreen, LeaveAlternateScreen, disable_raw_mode, enable_raw_mode,
};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::sync::{Arc, Once};
use std::time::{Duration, Instant};

/// True while the terminal is in raw mode on the alternate screen.
static ACTIVE: AtomicBool = AtomicBool::new(false);
static HOOK: Once = Once::new();

/// Leaves raw mode and the alternate screen (idempotent).
fn restore_terminal() {
    if ACTIVE.swap(false, Ordering::SeqCst) {
        let _ = disable_raw_mode();
        let _ = execute!(
            std::io::stdout(),
            DisableMouseCapture,
            LeaveAlternateScreen,
            crossterm::cursor::Show
        );
    }
}

/// Restores the terminal when dropped (normal exit and `?` errors).
struct Guard;

impl Drop for Guard {
    fn drop(&mut self) {
        restore_terminal();
    }
}

fn io_err(e: std::io::Error) -> Error {
    Error::io("terminal", e)
}

/// Opens the terminal UI, applies `initial` (e.g. `load demo:walk`), and runs until `q`.
/// Relative paths of `:` commands are relative to the current folder.
pub fn run(initial: Vec<Command>) -> Result<(), Error> {
    // restore the terminal before the panic message is printed
    HOOK.call_once(|| {
        let previous = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            restore_terminal();
            previous(info);
        }));
    });
    enable_raw_mode().map_err(io_err)?;
    ACTIVE.store(true, Ordering::SeqCst);
    let _guard = Guard;
    execute!(std::io::stdout(), EnterAlternateScreen, EnableMouseCapture).map_err(io_err)?;
    let backend = ratatui::backend::CrosstermBackend::new(std::io::stdout());
    let mut terminal = ratatui::Terminal::new(backend).map_err(io_err)?;
    terminal.clear().map_err(io_err)?;

    let mut wb = Workbench::new(Arc::new(Builtin), ".", ".");
    let mut ui = Ui::new();
    for c in &initial {
        ui.exec(&mut wb, c);
    }
    event_loop(&mut terminal, &mut ui, &mut wb)
}

/// The worker thread of a running computation.
struct Worker {
    rx: Receiver<JobResult>,
}

fn event_loop<B: ratatui::backend::Backend>(
    terminal: &mut ratatui::Terminal<B>,
    ui: &mut Ui,
    wb: &mut Workbench,
) -> Result<(), Error>
where
    B::Error: Into<std::io::Error>,
{
    let mut worker: Option<Worker> = None;
    let mut last = Instant::now();
    while !ui.quit {
        // start what the last input asked for (a newer request cancels the running one)
        if let Some(job) = ui.pending.take() {
            let control = Arc::new(Control::default());
            let (tx, rx) = mpsc::channel();
            let c = control.clone();
            let label = job.label();
            std::thread::spawn(move || {
                let _ = tx.send(job.run(&c));
            });
            if let Some(r) = &ui.running {
                r.control.cancel();
            }
            ui.running = Some(ui::Running { label, control });
            worker = Some(Worker { rx });
        }
        terminal
            .draw(|f| draw::draw(ui, wb, f))
            .map_err(|e| io_err(e.into()))?;
        if event::poll(Duration::from_millis(30)).map_err(io_err)? {
            match event::read().map_err(io_err)? {
                Event::Key(k) if k.kind != KeyEventKind::Release => ui.handle_key(wb, k),
                Event::Mouse(m) => ui.handle_mouse(wb, m),
                // the next draw uses the new size
                Event::Resize(_, _) => terminal.autoresize().map_err(|e| io_err(e.into()))?,
                _ => {}
            }
        }
        if let Some(w) = &worker {
            match w.rx.try_recv() {
                Ok(done) => {
                    ui.finish(wb, done);
                    worker = None;
                }
                Err(TryRecvError::Disconnected) => {
                    ui.running = None;
                    worker = None;
                }
                Err(TryRecvError::Empty) => {}
            }
        }
        let now = Instant::now();
        ui.tick(wb, (now - last).as_secs_f64());
        last = now;
    }
    Ok(())
}
