//! The interface state ([`Ui`]) and input handling: keys and mouse → [`Command`]s applied to
//! the [`Workbench`]. Drawing is in [`super::draw`], a pure function of `(Ui, Workbench)`.

use crate::session::command::COMMAND_WORDS;
use crate::session::command::Expectation;
use crate::session::engine::Control;
use crate::session::settings::{self, Setting, Subject};
use crate::session::workbench::Overlay;
use crate::session::{
    Command, Frontend, Job, JobResult, Outcome, RunKind, SessionError, TakeRef, Workbench,
    apply_frontend, apply_with, parse_line,
};
use crossterm::event::{KeyCode, KeyEvent, KeyModifiers, MouseButton, MouseEvent, MouseEventKind};
use ratatui::layout::Rect;
use std::cell::Cell;
use std::collections::VecDeque;
use std::sync::Arc;
use std::sync::mpsc::{self, Receiver, TryRecvError};

/// The pane that arrows and hjkl act on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Focus {
    Tree,
    View,
    Params,
    Timeline,
}

impl Focus {
    fn next(self, back: bool) -> Focus {
        const ORDER: [Focus; 4] = [Focus::Tree, Focus::View, Focus::Params, Focus::Timeline];
        let i = ORDER.iter().position(|f| *f == self).unwrap_or(0);
        ORDER[(i + if back { 3 } else { 1 }) % 4]
    }
    pub fn name(self) -> &'static str {
        match self {
            Focus::Tree => "joints",
            Focus::View => "avatar",
            Focus::Params => "parameters",
            Focus::Timeline => "timeline",
        }
    }
}

/// The rows of the parameter panel for the active take (the settings' table's panel rows:
/// a robot's drives and simulation, or a human take's body, smoothing and simulation).
pub fn params_of(wb: &Workbench) -> Vec<&'static Setting> {
    settings::panel(wb.take().is_some_and(|t| t.robot().is_some()))
}

/// A computation running on the worker thread, as the UI sees it.
#[derive(Debug)]
pub struct Running {
    /// What it computes, for the status line.
    pub label: String,
    /// Its progress and cancel.
    pub control: Arc<Control>,
    /// Inverse dynamics of the active take (a recompute): a newer request replaces it.
    pub replaceable: bool,
    /// Where the worker sends its preview, then its result.
    rx: Receiver<Sent>,
    /// When the job started (the recompute time in the status line).
    started: std::time::Instant,
    /// When its preview arrived (ms after the start), if it sent one.
    pub preview_ms: Option<u128>,
}

/// What the worker sends: a recompute's preview first ([`Job::preview`], when it has one),
/// then the job's result.
#[derive(Debug)]
enum Sent {
    Preview(JobResult),
    Done(JobResult),
}

impl Drop for Running {
    fn drop(&mut self) {
        // nobody waits for the result any more: let the worker stop
        self.control.cancel();
    }
}

/// True for the commands after which the active take (or its motion) is another.
fn changes_take(cmd: &Command) -> bool {
    matches!(
        cmd,
        Command::Load { .. }
            | Command::Take(_)
            | Command::Blend { .. }
            | Command::Trajectory { .. }
            | Command::Scene { .. }
    )
}

/// Everything the interface keeps besides the workbench: focus, cursors, the command line and
/// its history, the view angles, the help overlay, and where the last draw put the panes (for
/// the mouse).
#[derive(Debug)]
pub struct Ui {
    pub focus: Focus,
    /// Row of the parameter panel under the cursor.
    pub param_cursor: usize,
    /// The `:` command line being edited, if open.
    pub cmdline: Option<String>,
    /// Command lines entered, oldest first.
    pub history: Vec<String>,
    /// Position in `history` while browsing it with ↑/↓.
    history_pos: Option<usize>,
    /// Candidates shown after an ambiguous Tab.
    pub completions: Vec<String>,
    pub help: bool,
    /// View angles of the avatar (rad): yaw about the up axis, pitch about the screen x.
    pub yaw: f64,
    pub pitch: f64,
    /// Draw with colours (false when `NO_COLOR` is set).
    pub color: bool,
    /// Run computations inline (headless replay, tests) instead of on a worker thread.
    pub sync: bool,
    /// The computation running on the worker thread.
    pub running: Option<Running>,
    /// Commands given while a job ran, applied in order once it is done.
    pub queue: VecDeque<Command>,
    /// A recompute (inverse dynamics of the active take) waits for the running job.
    recompute: bool,
    /// The last error, shown in the status line until the next command.
    pub error: Option<String>,
    /// The wall time of the last recompute on the worker (ms) and the number of messages
    /// once it was stored: the status line shows it beside that message, after the time of
    /// its preview if it drew one. Never set in sync mode, so replays stay deterministic.
    pub recompute_ms: Option<(u128, Option<u128>, usize)>,
    pub quit: bool,
    /// Screen size for `screen` in headless mode.
    pub size: (u16, u16),
    /// Size of the last draw (columns, rows): what `screen` writes in the terminal.
    pub drawn: Cell<(u16, u16)>,
    /// Pane rectangles of the last draw (mouse hit tests).
    pub tree_area: Cell<Rect>,
    pub timeline_area: Cell<Rect>,
    /// First visible row of the joint tree at the last draw.
    pub tree_scroll: Cell<usize>,
    /// Fractional frames accumulated by playback.
    play_acc: f64,
}

impl Ui {
    /// An interface that runs computations on a worker thread (the terminal).
    pub fn new() -> Self {
        Self {
            focus: Focus::Tree,
            param_cursor: 0,
            cmdline: None,
            history: vec![],
            history_pos: None,
            completions: vec![],
            help: false,
            yaw: 0.6,
            pitch: 0.15,
            color: std::env::var_os("NO_COLOR").is_none_or(|v| v.is_empty()),
            sync: false,
            running: None,
            queue: VecDeque::new(),
            recompute: false,
            error: None,
            recompute_ms: None,
            quit: false,
            size: (80, 24),
            drawn: Cell::new((0, 0)),
            tree_area: Cell::new(Rect::default()),
            timeline_area: Cell::new(Rect::default()),
            tree_scroll: Cell::new(0),
            play_acc: 0.0,
        }
    }

    /// An interface for headless use: computations inline, a `width × height` screen.
    pub fn headless(width: u16, height: u16) -> Self {
        Self {
            sync: true,
            size: (width, height),
            ..Self::new()
        }
    }

    /// Applies a command from a key, the command line or the initial list, reporting errors in
    /// the status line. Long commands go to the worker (or run inline in sync mode); a `set`
    /// or `load` that makes the results stale starts a recompute.
    pub fn exec(&mut self, wb: &mut Workbench, cmd: &Command) {
        if let Err(e) = self.try_exec(wb, cmd) {
            self.show_error(wb, e);
        }
    }

    fn show_error(&mut self, wb: &mut Workbench, e: SessionError) {
        let msg = e.to_string();
        wb.messages.push(format!("error: {msg}"));
        self.error = Some(msg);
    }

    /// True while a job other than a recompute runs, or commands wait for one. Then a command
    /// that needs the worker waits its turn, and so does every later command but the view's
    /// (`frame`, `select`, `play`, `pause`, `screen`, `quit`), so that commands apply in the
    /// order given, as a replay applies them. A command that needs no job (`set`) applies at
    /// once when nothing waits: the running job computes from its own snapshot; the recompute
    /// it asks for follows the job.
    pub fn busy(&self) -> bool {
        self.running.as_ref().is_some_and(|r| !r.replaceable) || !self.queue.is_empty()
    }

    /// [`exec`](Self::exec), returning the error instead of showing it.
    pub fn try_exec(&mut self, wb: &mut Workbench, cmd: &Command) -> Result<Outcome, SessionError> {
        self.error = None;
        let view = matches!(
            cmd,
            Command::Frame(_)
                | Command::Play
                | Command::Pause
                | Command::Select(_)
                | Command::Quit
                | Command::Screen { .. }
                | Command::Expect(Expectation::ScreenContains(_))
        );
        if !self.sync && !view && !self.queue.is_empty() {
            self.queue.push_back(cmd.clone());
            return Ok(Outcome::default());
        }
        let outcome = match cmd {
            Command::Quit => {
                self.quit = true;
                Outcome::default()
            }
            // threaded: long commands go to the worker; the screen is the one shown now
            _ if !self.sync => match wb.prepare(cmd)? {
                Some(job) => {
                    if changes_take(cmd) {
                        self.recompute = true;
                    }
                    self.submit(cmd, job)?;
                    Outcome::default()
                }
                None => apply_frontend(wb, self, cmd, false)?,
            },
            _ => apply_with(wb, self, cmd)?,
        };
        if outcome.quit {
            self.quit = true;
        }
        // keep results in step with the parameters and the take
        if (changes_take(cmd) || matches!(cmd, Command::Set { .. }))
            && wb.frames() > 0
            && wb.fresh_results().is_none()
        {
            self.try_exec(wb, &Command::Run(RunKind::Id))?;
        }
        Ok(outcome)
    }

    /// Starts `job` (for `cmd`) on a worker thread. A running recompute is cancelled (a new
    /// one replaces it; another job computes the results it needs, and the recompute follows
    /// if they are still stale); a recompute asked for while another job runs follows it.
    fn submit(&mut self, cmd: &Command, job: Job) -> Result<(), SessionError> {
        if let Some(r) = &self.running {
            if r.replaceable {
                r.control.cancel();
                if !job.is_inverse_dynamics() {
                    self.recompute = true;
                }
            } else if job.is_inverse_dynamics() {
                self.recompute = true;
                return Ok(());
            } else {
                self.queue.push_back(cmd.clone());
                return Ok(());
            }
        }
        let control = Arc::new(Control::default());
        let (tx, rx) = mpsc::channel();
        let c = control.clone();
        let label = job.label().to_string();
        let replaceable = job.is_inverse_dynamics();
        std::thread::Builder::new()
            .name("articula-worker".into())
            .spawn(move || {
                // the receiver is gone when the job was replaced or the UI quit
                if let Some(p) = job.preview(&c) {
                    let _ = tx.send(Sent::Preview(p));
                }
                let _ = tx.send(Sent::Done(job.run(&c)));
            })
            .map_err(|e| SessionError::Engine(crate::error::Error::io("worker thread", e)))?;
        self.running = Some(Running {
            label,
            control,
            replaceable,
            rx,
            started: std::time::Instant::now(),
            preview_ms: None,
        });
        Ok(())
    }

    /// Takes what the worker finished, if it did, then applies the commands that waited for
    /// it and the recompute that followed it; shows a recompute's preview when it comes.
    /// Returns true when a job finished or sent its preview (the screen changed).
    pub fn poll(&mut self, wb: &mut Workbench) -> bool {
        let Some(r) = &mut self.running else {
            return false;
        };
        let done = match r.rx.try_recv() {
            Ok(Sent::Done(done)) => done,
            Ok(Sent::Preview(p)) => {
                r.preview_ms = Some(r.started.elapsed().as_millis());
                wb.show_preview(p);
                return true;
            }
            Err(TryRecvError::Empty) => return false,
            Err(TryRecvError::Disconnected) => {
                // the job panicked: nothing was stored
                let label = r.label.clone();
                self.running = None;
                self.show_error(
                    wb,
                    SessionError::Command(format!(
                        "{label} stopped unexpectedly (the worker panicked); nothing was changed"
                    )),
                );
                self.next(wb);
                return true;
            }
        };
        let (ms, recompute) = (r.started.elapsed().as_millis(), r.replaceable);
        let preview_ms = r.preview_ms;
        let stored = !done.is_cancelled();
        self.finish(wb, done);
        if recompute && stored && self.error.is_none() {
            self.recompute_ms = Some((ms, preview_ms, wb.messages.len()));
        }
        true
    }

    /// Takes what the worker computed, then starts what waits.
    pub fn finish(&mut self, wb: &mut Workbench, done: JobResult) {
        self.running = None;
        if done.is_cancelled() {
            // the preview of a cancelled recompute goes with it
            wb.preview = None;
            wb.messages.push(format!("cancelled {}", done.label()));
        } else if let Err(e) = wb.finish(done) {
            self.show_error(wb, e);
        }
        self.next(wb);
    }

    /// Applies the queued commands until one starts a job, then the recompute that waits.
    fn next(&mut self, wb: &mut Workbench) {
        // taken out of the queue, so that they apply now instead of waiting again
        let mut waiting = std::mem::take(&mut self.queue);
        while self.running.as_ref().is_none_or(|r| r.replaceable) {
            let Some(cmd) = waiting.pop_front() else {
                break;
            };
            // an error is shown and the next command still runs, as if typed one by one
            self.exec(wb, &cmd);
        }
        waiting.append(&mut self.queue);
        self.queue = waiting;
        if self.running.is_none()
            && std::mem::take(&mut self.recompute)
            && wb.frames() > 0
            && wb.fresh_results().is_none()
        {
            self.exec(wb, &Command::Run(RunKind::Id));
        }
    }

    /// Cancels the running job and drops the commands that wait for it (Esc).
    pub fn cancel(&mut self, wb: &mut Workbench) {
        self.recompute = false;
        let dropped = std::mem::take(&mut self.queue).len();
        if let Some(r) = &self.running {
            r.control.cancel();
            let mut msg = format!("cancelling {}", r.label);
            if dropped > 0 {
                msg.push_str(&format!("; dropped {dropped} waiting command(s)"));
            }
            wb.messages.push(msg);
        }
    }

    /// Cancels the running job and waits up to `wait` for it to stop (quit): the loops check
    /// for cancel every few dozen frames, so this is quick unless the job is parsing a file.
    pub fn shutdown(&mut self, wait: std::time::Duration) {
        self.queue.clear();
        if let Some(r) = self.running.take() {
            r.control.cancel();
            let _ = r.rx.recv_timeout(wait);
        }
    }

    /// Advances playback by `elapsed` seconds of wall time.
    pub fn tick(&mut self, wb: &mut Workbench, elapsed: f64) {
        if !wb.playing || wb.frames() == 0 {
            self.play_acc = 0.0;
            return;
        }
        let dt = wb.take().map_or(1.0, |t| t.frame_time());
        self.play_acc += elapsed / dt;
        let steps = self.play_acc.floor();
        if steps >= 1.0 {
            self.play_acc -= steps;
            let n = (wb.frame + steps as usize) % wb.frames();
            self.exec(wb, &Command::Frame(n));
        }
    }

    /// The joints of the active take (BVH joints, or a robot's joints) in tree order, with
    /// their depths.
    pub fn tree(wb: &Workbench) -> Vec<(String, usize)> {
        wb.take().map_or(vec![], |t| t.joint_tree())
    }

    /// Row of the selected joint in the tree.
    pub fn tree_cursor(wb: &Workbench) -> Option<usize> {
        let sel = wb.selection.as_deref()?;
        let tree = Self::tree(wb);
        // the joint of the selection (an anatomical joint's BVH joint: `knee_l` → `LeftLeg`)
        if let Some(j) = wb.selected_joint()
            && let Some(i) = tree.iter().position(|(n, _)| *n == j)
        {
            return Some(i);
        }
        // the longest joint name the selection starts with (`LeftLeg.Xrotation`, `LeftLeg:wx`)
        tree.iter()
            .enumerate()
            .filter(|(_, (n, _))| {
                sel == n
                    || sel
                        .strip_prefix(n.as_str())
                        .is_some_and(|r| r.starts_with(['.', ':']))
            })
            .max_by_key(|(_, (n, _))| n.len())
            .map(|(i, _)| i)
    }

    /// Handles one key.
    pub fn handle_key(&mut self, wb: &mut Workbench, key: KeyEvent) {
        if key.modifiers.contains(KeyModifiers::CONTROL) && key.code == KeyCode::Char('c') {
            if self.running.is_some() {
                self.cancel(wb);
            } else {
                self.quit = true;
            }
            return;
        }
        if self.cmdline.is_some() {
            self.cmdline_key(wb, key);
            return;
        }
        if self.help {
            // any key closes the help
            self.help = false;
            return;
        }
        let frames = wb.frames();
        let frame_to = |ui: &mut Ui, wb: &mut Workbench, n: isize| {
            if frames > 0 {
                let n = n.clamp(0, frames as isize - 1) as usize;
                ui.exec(wb, &Command::Frame(n));
            }
        };
        let cur = wb.frame as isize;
        match key.code {
            KeyCode::Char('q') => self.quit = true,
            KeyCode::Char('?') => self.help = true,
            KeyCode::Char(':') => {
                self.cmdline = Some(String::new());
                self.history_pos = None;
                self.completions.clear();
            }
            KeyCode::Esc => {
                self.cancel(wb);
                self.error = None;
            }
            KeyCode::Tab => self.focus = self.focus.next(false),
            KeyCode::BackTab => self.focus = self.focus.next(true),
            KeyCode::Char(' ') => {
                let c = if wb.playing {
                    Command::Pause
                } else {
                    Command::Play
                };
                self.exec(wb, &c);
            }
            KeyCode::Char('[') => frame_to(self, wb, cur - 1),
            KeyCode::Char(']') => frame_to(self, wb, cur + 1),
            KeyCode::Char('{') => frame_to(self, wb, cur - 10),
            KeyCode::Char('}') => frame_to(self, wb, cur + 10),
            KeyCode::Home | KeyCode::Char('g') => frame_to(self, wb, 0),
            KeyCode::End | KeyCode::Char('G') => frame_to(self, wb, frames as isize - 1),
            // the next / previous loaded take
            KeyCode::Char('t') => self.exec(wb, &Command::Take(TakeRef::Next)),
            // the mirror joint's curve beside the selected one's: `set overlay mirror|none`
            KeyCode::Char('m') => {
                let value = if wb.overlay == Overlay::Mirror {
                    "none"
                } else {
                    "mirror"
                };
                let cmd = Command::Set {
                    key: "overlay".into(),
                    value: value.into(),
                };
                self.exec(wb, &cmd)
            }
            KeyCode::Char('T') => self.exec(wb, &Command::Take(TakeRef::Prev)),
            KeyCode::Char('<') => self.yaw -= 0.2,
            KeyCode::Char('>') => self.yaw += 0.2,
            KeyCode::Char('r') => {
                self.yaw = 0.6;
                self.pitch = 0.15;
            }
            KeyCode::Up | KeyCode::Down | KeyCode::Left | KeyCode::Right => {
                self.pane_key(wb, key.code)
            }
            KeyCode::Char(c @ ('h' | 'j' | 'k' | 'l')) => {
                let code = match c {
                    'h' => KeyCode::Left,
                    'j' => KeyCode::Down,
                    'k' => KeyCode::Up,
                    _ => KeyCode::Right,
                };
                self.pane_key(wb, code)
            }
            KeyCode::Char('+') | KeyCode::Char('=') if self.focus == Focus::Params => {
                self.adjust(wb, 1.0)
            }
            KeyCode::Char('-') if self.focus == Focus::Params => self.adjust(wb, -1.0),
            KeyCode::Enter if self.focus == Focus::Params => {
                if let Some((key, value)) = self.param_row(wb, self.param_cursor) {
                    self.cmdline = Some(format!("set {key} {value}"));
                }
            }
            _ => {}
        }
    }

    /// Arrows in the focused pane.
    fn pane_key(&mut self, wb: &mut Workbench, code: KeyCode) {
        let frames = wb.frames() as isize;
        match self.focus {
            Focus::Tree => {
                let tree = Self::tree(wb);
                if tree.is_empty() {
                    return;
                }
                let cur = Self::tree_cursor(wb).unwrap_or(0);
                match code {
                    KeyCode::Up | KeyCode::Down => {
                        let n = if code == KeyCode::Up {
                            cur.saturating_sub(1)
                        } else {
                            (cur + 1).min(tree.len() - 1)
                        };
                        self.exec(wb, &Command::Select(tree[n].0.clone()));
                    }
                    _ => {
                        // ←/→: the previous / next coordinate of the joint (of an
                        // anatomical joint: its flexion, adduction and rotation axes)
                        let sel = wb.selection.clone().unwrap_or_default();
                        let coords = wb
                            .anatomical_axes(&sel)
                            .unwrap_or_else(|| wb.joint_coords(&tree[cur].0));
                        if coords.is_empty() {
                            return;
                        }
                        let at = coords.iter().position(|c| *c == sel).unwrap_or(0);
                        let n = if code == KeyCode::Left {
                            (at + coords.len() - 1) % coords.len()
                        } else {
                            (at + 1) % coords.len()
                        };
                        let name = coords[n].clone();
                        self.exec(wb, &Command::Select(name));
                    }
                }
            }
            Focus::View => match code {
                KeyCode::Left => self.yaw -= 0.2,
                KeyCode::Right => self.yaw += 0.2,
                KeyCode::Up => self.pitch = (self.pitch + 0.1).min(1.5),
                _ => self.pitch = (self.pitch - 0.1).max(-1.5),
            },
            Focus::Params => match code {
                KeyCode::Up => self.param_cursor = self.param_cursor.saturating_sub(1),
                KeyCode::Down => {
                    self.param_cursor = (self.param_cursor + 1).min(params_of(wb).len() - 1)
                }
                KeyCode::Left => self.adjust(wb, -1.0),
                _ => self.adjust(wb, 1.0),
            },
            Focus::Timeline => {
                if frames == 0 {
                    return;
                }
                let step = match code {
                    KeyCode::Left => -1,
                    KeyCode::Right => 1,
                    KeyCode::Up => 10,
                    _ => -10,
                };
                let n = (wb.frame as isize + step).clamp(0, frames - 1) as usize;
                self.exec(wb, &Command::Frame(n));
            }
        }
    }

    /// The `set` key and current value of parameter row `i`.
    pub fn param_row(&self, wb: &Workbench, i: usize) -> Option<(String, String)> {
        let row = *params_of(wb).get(i)?;
        let panel = row.panel?;
        // a pattern key's joint: the tree cursor's, or the selected coordinate
        let subject = match panel.subject {
            Subject::None => String::new(),
            Subject::Joint => Self::tree(wb)[Self::tree_cursor(wb)?].0.clone(),
            Subject::Selection => wb.selection.clone()?,
        };
        let value = (panel.show)(wb, &subject)?;
        Some((row.key_for(&subject), value))
    }

    /// Steps the parameter under the cursor up (`dir = 1`) or down (`-1`) and applies it.
    fn adjust(&mut self, wb: &mut Workbench, dir: f64) {
        let Some((key, value)) = self.param_row(wb, self.param_cursor) else {
            return;
        };
        let Some(panel) = params_of(wb)[self.param_cursor].panel else {
            return;
        };
        if let Some(new) = (panel.step)(wb, &value, dir) {
            self.exec(wb, &Command::Set { key, value: new });
        }
    }

    /// Keys while the `:` command line is open.
    fn cmdline_key(&mut self, wb: &mut Workbench, key: KeyEvent) {
        // the completion hint belongs to the last Tab; any other key makes it stale
        if key.code != KeyCode::Tab {
            self.completions.clear();
        }
        let Some(line) = self.cmdline.as_mut() else {
            return;
        };
        match key.code {
            KeyCode::Esc => self.cmdline = None,
            KeyCode::Enter => {
                let text = std::mem::take(line);
                self.cmdline = None;
                self.completions.clear();
                if !text.trim().is_empty() {
                    self.history.push(text.clone());
                }
                match parse_line(&text, 1) {
                    Ok(Some(cmd)) => self.exec(wb, &cmd),
                    Ok(None) => {}
                    Err(e) => {
                        let msg = match e {
                            SessionError::Syntax { message, .. } => message,
                            e => e.to_string(),
                        };
                        wb.messages.push(format!("error: {msg}"));
                        self.error = Some(msg);
                    }
                }
            }
            // an empty line stays open (Esc closes it)
            KeyCode::Backspace => {
                line.pop();
            }
            // readline: Ctrl-U clears to the start of the line (the cursor is at its end),
            // Ctrl-W deletes the word before the cursor and the spaces after it
            KeyCode::Char('u') if key.modifiers.contains(KeyModifiers::CONTROL) => line.clear(),
            KeyCode::Char('w') if key.modifiers.contains(KeyModifiers::CONTROL) => {
                let kept = line.trim_end().len();
                line.truncate(kept);
                let start = line.rfind(' ').map_or(0, |i| i + 1);
                line.truncate(start);
            }
            KeyCode::Tab => {
                let (done, cands) = complete(wb, line);
                *line = done;
                self.completions = cands;
            }
            KeyCode::Up | KeyCode::Down => {
                if self.history.is_empty() {
                    return;
                }
                let n = self.history.len();
                let pos = match (self.history_pos, key.code) {
                    (None, KeyCode::Up) => n - 1,
                    (None, _) => return,
                    (Some(p), KeyCode::Up) => p.saturating_sub(1),
                    (Some(p), _) if p + 1 < n => p + 1,
                    (Some(_), _) => {
                        self.history_pos = None;
                        line.clear();
                        return;
                    }
                };
                self.history_pos = Some(pos);
                *line = self.history[pos].clone();
            }
            KeyCode::Char(c) if !key.modifiers.contains(KeyModifiers::CONTROL) => line.push(c),
            _ => {}
        }
    }

    /// Handles a mouse event: a click in the tree selects a joint, a click on the timeline
    /// goes to that frame, the wheel scrolls the selection.
    pub fn handle_mouse(&mut self, wb: &mut Workbench, m: MouseEvent) {
        let tree = self.tree_area.get();
        let timeline = self.timeline_area.get();
        let inside = |r: Rect| {
            m.column >= r.x && m.column < r.x + r.width && m.row >= r.y && m.row < r.y + r.height
        };
        match m.kind {
            MouseEventKind::Down(MouseButton::Left) if inside(tree) => {
                self.focus = Focus::Tree;
                let row = (m.row - tree.y) as usize + self.tree_scroll.get();
                if let Some((name, _)) = Self::tree(wb).get(row) {
                    self.exec(wb, &Command::Select(name.clone()));
                }
            }
            MouseEventKind::Down(MouseButton::Left) | MouseEventKind::Drag(MouseButton::Left)
                if inside(timeline) && wb.frames() > 0 =>
            {
                self.focus = Focus::Timeline;
                let f = (m.column - timeline.x) as f64 / (timeline.width.max(2) - 1) as f64;
                let n = (f * (wb.frames() - 1) as f64).round() as usize;
                self.exec(wb, &Command::Frame(n.min(wb.frames() - 1)));
            }
            MouseEventKind::ScrollDown if inside(tree) => self.pane_key(wb, KeyCode::Down),
            MouseEventKind::ScrollUp if inside(tree) => self.pane_key(wb, KeyCode::Up),
            _ => {}
        }
    }

    /// The screen as text at the terminal's size (`self.size` headless).
    pub fn render_text(&self, wb: &Workbench) -> String {
        // the terminal's size once drawn; a headless interface has no other
        let (w, h) = match self.drawn.get() {
            (w, h) if !self.sync && w > 0 => (w, h),
            _ => self.size,
        };
        super::draw::render_text(self, wb, w, h)
    }
}

impl Default for Ui {
    fn default() -> Self {
        Self::new()
    }
}

impl Frontend for Ui {
    fn keys(&mut self, wb: &mut Workbench, keys: &str) -> Result<Outcome, SessionError> {
        for k in super::keys::parse_keys(keys)? {
            self.handle_key(wb, k);
            if self.quit {
                return Ok(Outcome {
                    quit: true,
                    ..Outcome::default()
                });
            }
        }
        Ok(Outcome::default())
    }
    fn screen(&mut self, wb: &Workbench) -> String {
        self.render_text(wb)
    }
}

/// Tab completion of the last word of a command line: the completed line and, when several
/// candidates remain, the candidates.
pub fn complete(wb: &Workbench, line: &str) -> (String, Vec<String>) {
    let words: Vec<&str> = line.split(' ').collect();
    let last = words.last().copied().unwrap_or("");
    let head = &words[..words.len() - 1];
    let joints: Vec<String> = Ui::tree(wb).into_iter().map(|(n, _)| n).collect();
    let coords: Vec<String> = wb
        .latest_results()
        .map(|r| r.model.v_names.clone())
        .unwrap_or_default();
    let pool: Vec<String> = match head {
        [] => COMMAND_WORDS.iter().map(|s| s.to_string()).collect(),
        ["set"] => settings::names()
            .filter(|k| !k.contains('<'))
            .map(|s| s.to_string())
            .chain(joints.iter().map(|j| format!("link.{j}.mass")))
            .chain(
                coords
                    .iter()
                    .take(12)
                    .flat_map(|c| ["km", "gear", "efficiency"].map(|f| format!("motor.{c}.{f}"))),
            )
            .collect(),
        // a setting's values, from its row
        ["set", key] if settings::find(key).is_some_and(|(r, _)| !r.values.is_empty()) => {
            settings::find(key).map_or(vec![], |(r, _)| {
                r.values.iter().map(|v| v.to_string()).collect()
            })
        }
        // joints first; coordinates once the word names a joint and a dot
        ["select"] | ["compare", "weights", _, "joint"] if last.contains('.') => coords.clone(),
        ["select"] | ["compare", "weights", _, "joint"] => joints.clone(),
        ["run"] => vec!["id".into(), "sim".into()],
        ["take"] => ["next", "prev"]
            .map(String::from)
            .into_iter()
            .chain(wb.take_names())
            .collect(),
        ["export"] => crate::session::command::EXPORT_WORDS
            .iter()
            .map(|(w, _)| *w)
            .filter(|w| !w.contains(' '))
            .map(String::from)
            .collect(),
        ["export", "bvh"] => std::iter::once("sim".to_string())
            .chain(paths(wb, last, None))
            .collect(),
        ["report"] => vec!["motor".into()],
        ["report", "motor"] => std::iter::once("curves".to_string())
            .chain(paths(wb, last, None))
            .collect(),
        ["compare"] => vec!["weights".into()],
        ["expect"] => [
            "nv", "nq", "frames", "frame", "selected", "mass", "peak", "min", "max", "mean", "rms",
            "now", "screen", "message",
        ]
        .map(String::from)
        .to_vec(),
        ["expect", _, _] => ["angle", "velocity", "acceleration", "torque"]
            .map(String::from)
            .to_vec(),
        ["expect", s] if ["peak", "min", "max", "mean", "rms", "now"].contains(s) => coords.clone(),
        // paths: what `load` and `scene` read, where exports and reports are written
        ["load"] => paths(wb, last, Some(&["bvh", "toml", "urdf", "csv"])),
        ["scene"] => paths(wb, last, Some(&["toml"])),
        ["export", _]
        | ["export", "bvh", "sim"]
        | ["report", "motor", "curves"]
        | ["compare", "weights", _]
        | ["compare", "weights", _, "joint", _]
        | ["screen"] => paths(wb, last, None),
        _ => vec![],
    };
    let mut cands: Vec<String> = pool.into_iter().filter(|c| c.starts_with(last)).collect();
    cands.dedup();
    let prefix_of = |v: &[String]| -> String {
        let mut p = v[0].clone();
        for c in &v[1..] {
            while !c.starts_with(&p) {
                p.pop();
            }
        }
        p
    };
    let mut out: Vec<&str> = head.to_vec();
    match cands.len() {
        0 => (line.to_string(), vec![]),
        // a folder is completed without the space, so that Tab goes on into it
        1 if cands[0].ends_with('/') => {
            out.push(&cands[0]);
            (out.join(" "), vec![])
        }
        1 => {
            let w = format!("{} ", cands[0]);
            out.push(&w);
            (out.join(" "), vec![])
        }
        _ => {
            let p = prefix_of(&cands);
            out.push(&p);
            (out.join(" "), cands)
        }
    }
}

/// Path candidates for the word `word`: the entries of its folder (relative to the folder
/// relative input paths are read from) whose names start with its last part, folders with a
/// trailing `/`, files only with one of `exts` when given; hidden entries only when the part
/// starts with a dot. Sorted, as the word would be written.
fn paths(wb: &Workbench, word: &str, exts: Option<&[&str]>) -> Vec<String> {
    let (dir, part) = match word.rfind('/') {
        Some(i) => (&word[..=i], &word[i + 1..]),
        None => ("", word),
    };
    let folder = wb.in_path(std::path::Path::new(if dir.is_empty() { "." } else { dir }));
    let Ok(entries) = std::fs::read_dir(folder) else {
        return vec![];
    };
    let mut out: Vec<String> = entries
        .flatten()
        .filter_map(|e| {
            let name = e.file_name().to_str()?.to_string();
            if !name.starts_with(part) || (name.starts_with('.') && !part.starts_with('.')) {
                return None;
            }
            // a link to a folder is a folder
            if e.path().is_dir() {
                return Some(format!("{dir}{name}/"));
            }
            let ext = std::path::Path::new(&name)
                .extension()
                .and_then(|x| x.to_str())
                .map(str::to_ascii_lowercase);
            let wanted = exts.is_none_or(|xs| ext.is_some_and(|x| xs.contains(&x.as_str())));
            wanted.then(|| format!("{dir}{name}"))
        })
        .collect();
    out.sort();
    out
}
