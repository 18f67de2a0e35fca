//! The terminal UI (ratatui + crossterm): draws the [`Workbench`], turns keys and mouse into
//! [`Command`]s.
//!
//! State, events and drawing are kept apart: [`Ui`] holds the interface state and turns input
//! into commands ([`ui`]), [`draw::draw`] is a pure function of `(Ui, Workbench)`, and
//! [`run`] opens the terminal and runs [`event_loop`].
//!
//! # The worker
//!
//! Every command whose work can take longer than a frame on a big take is prepared as a
//! [`Job`](crate::session::Job) by the workbench and runs on a worker thread: `load` (takes,
//! DH tables, URDFs, states CSVs), `scene`, `trajectory`, `blend`, `run id`, `run sim`, the
//! recompute after `set`, `export …`, `compare weights`, `report motor`, and an `expect` whose
//! results are stale. Its [`Control`](crate::session::Control) carries progress (shown with
//! the job's label in the status line) and cancel (`Esc`, `Ctrl-C`; `q` cancels and quits).
//! The loop polls input every 30 ms ([`POLL`]), so keys, mouse and resizes are handled while a
//! job runs. While a job other than a recompute runs, another long command waits in
//! [`Ui::queue`], and so does every command after it; they apply in order when the job ends
//! (the view's commands — `frame`, `select`, `play`, `pause`, `screen` — apply at once). A
//! `set` with nothing waiting applies at once (the job computes from its own snapshot) and its
//! recompute follows the job; a newer recompute replaces a running one. A cancelled job changes nothing
//! (outputs are written last, atomically). In sync mode ([`Ui::headless`]: replays, tests) the
//! same jobs run inline. The terminal is restored on exit, on error and on panic (a
//! panic hook). `NO_COLOR` turns colours off. Keys: see [`draw::HELP`] (`?` in the UI).

pub mod curves;
pub mod draw;
pub mod keys;
pub mod ui;

pub use ui::{Focus, Ui};

use crate::error::Error;
use crate::session::{Builtin, Command, TakeRef, Workbench};
use crossterm::event::{self, DisableMouseCapture, EnableMouseCapture, Event, KeyEventKind};
use crossterm::execute;
use crossterm::terminal::{
    EnterAlternateScreen, LeaveAlternateScreen, disable_raw_mode, enable_raw_mode,
};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Once};
use std::time::{Duration, Instant};

/// Replays the session file at `path` headless, `key` and `screen` driving the UI on an
/// off-screen 100×30 buffer; relative outputs go under `out_dir` (created if needed).
pub fn run_session(
    path: &std::path::Path,
    out_dir: &std::path::Path,
) -> Result<crate::session::Report, crate::session::SessionError> {
    crate::session::run_session_with(path, out_dir, &mut Ui::headless(100, 30))
}

/// [`run_session`] that keeps what the replay did up to an error: the report (with the failed
/// `expect` recorded) and the error, if any (`articula run --json`).
pub fn run_session_recorded(
    path: &std::path::Path,
    out_dir: &std::path::Path,
) -> (
    crate::session::Report,
    Result<(), crate::session::SessionError>,
) {
    crate::session::run_session_recorded_with(path, out_dir, &mut Ui::headless(100, 30))
}

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

    let mut wb = workbench_here();
    let mut ui = Ui::new();
    for c in &initial {
        ui.exec(&mut wb, c);
    }
    // several takes open on the first (t and T switch); each load waits for the one before
    if initial
        .iter()
        .filter(|c| matches!(c, Command::Load { .. }))
        .count()
        > 1
    {
        ui.exec(&mut wb, &Command::Take(TakeRef::Index(1)));
    }
    event_loop(&mut terminal, &mut ui, &mut wb, |timeout| {
        if event::poll(timeout).map_err(io_err)? {
            event::read().map(Some).map_err(io_err)
        } else {
            Ok(None)
        }
    })
}

/// The workbench of the terminal: relative paths of `:` commands are read from and written
/// under the current folder, which messages name in full (`wrote /home/me/knee.svg`), so the
/// user sees where an export landed.
pub fn workbench_here() -> Workbench {
    let here = std::env::current_dir().unwrap_or_else(|_| ".".into());
    Workbench::new(Arc::new(Builtin), here.clone(), here)
}

/// How long [`event_loop`] waits for an event before it draws again (progress, playback).
pub const POLL: Duration = Duration::from_millis(30);

/// How long quitting waits for a cancelled job to stop.
pub const STOP_WAIT: Duration = Duration::from_secs(2);

/// The event loop over any backend and event source: `next(timeout)` gives the next event, or
/// `None` when none came within `timeout`. Draws, handles the event, takes what the worker
/// finished, advances playback; input is never blocked by a computation (they run on the
/// worker). On quit the running job is cancelled and given [`STOP_WAIT`] to stop.
pub fn event_loop<B, F>(
    terminal: &mut ratatui::Terminal<B>,
    ui: &mut Ui,
    wb: &mut Workbench,
    mut next: F,
) -> Result<(), Error>
where
    B: ratatui::backend::Backend,
    B::Error: Into<Box<dyn std::error::Error + Send + Sync>>,
    F: FnMut(Duration) -> Result<Option<Event>, Error>,
{
    let mut last = Instant::now();
    while !ui.quit {
        terminal
            .draw(|f| draw::draw(ui, wb, f))
            .map_err(|e| io_err(std::io::Error::other(e)))?;
        match next(POLL)? {
            Some(Event::Key(k)) if k.kind != KeyEventKind::Release => ui.handle_key(wb, k),
            Some(Event::Mouse(m)) => ui.handle_mouse(wb, m),
            // the next draw uses the new size
            Some(Event::Resize(_, _)) => terminal
                .autoresize()
                .map_err(|e| io_err(std::io::Error::other(e)))?,
            _ => {}
        }
        ui.poll(wb);
        let now = Instant::now();
        ui.tick(wb, (now - last).as_secs_f64());
        last = now;
    }
    ui.shutdown(STOP_WAIT);
    Ok(())
}
