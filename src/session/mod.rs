//! The session language: a [`Workbench`] state changed only by [`Command`]s, session files
//! (lists of commands) and their replay ([`run_session_with`], over a [`Frontend`]; the TUI's
//! headless replay is `tui::run_session`).
//!
//! The terminal UI turns keys into the same commands, and its `:` command line takes the same
//! syntax, so anything done by hand can be written down and replayed.
//!
//! # Grammar
//!
//! One command per line. Blank lines and lines starting with `#` are ignored. Words are
//! separated by spaces; `"…"` quotes a word that contains spaces. Relative input paths are
//! read from the session file's folder; relative output paths are written under the output
//! folder (`--out DIR`).
//!
//! Units: a number may carry its unit right after it (`40deg`, `0.7rad`, `12cm`, `500ms`,
//! `80kg`, `120N·m`); the unit is checked against the quantity, and a unit of another one
//! (`expect peak X torque between 10deg 20deg`) is an error naming the line and the units the
//! quantity takes. The units ([`units::UNITS`]): angles `deg` `°` `rad`; lengths `m` `cm`
//! `mm`; angular velocities `deg/s` `°/s` `rad/s`, velocities `m/s` `cm/s` `mm/s`; angular
//! accelerations `deg/s2` `deg/s²` `°/s²` `rad/s2` `rad/s²`, accelerations `m/s2` `m/s²`;
//! torques `N·m` `Nm` `N.m`; forces `N`; masses `kg`; times `s` `ms`; rates `Hz` `hz`.
//! **A bare number is in the unit the workbench shows**: degrees (deg, deg/s, deg/s²) for
//! the angles of revolute coordinates and ball-joint rotation components, metres (m, m/s,
//! m/s²) for translations, N·m for torques, N for the forces of prismatic coordinates, kg,
//! s. One exception: the values of a `trajectory` pose are rad or m when bare, as DH tables
//! and URDF write joint values (and `pi` multiples are radians). Gains (`kp`, `kv`) and drive
//! values (`motor.*`) are plain numbers and take no unit. Messages print every value in its
//! coordinate's own unit (deg for a rotation, m for a translation, N·m or N), rounded to what
//! is meaningful ([`units::format_value`]: 0.1°, 1 mm, 0.1 N·m with 3 significant digits
//! below 100, 0.01 kg); CSV files stay SI at full precision.
//!
//! | command | effect |
//! |---|---|
//! | `load PATH [as NAME]` | load and make active: a BVH take (`demo:walk`: the generated demo walk), a DH table (`.toml`, `data/puma560.toml`) or a URDF (`.urdf`, fixed base, gravity −z); a states CSV (`.csv`, the `articula export states` or `export csv` format) becomes the active robot's motion |
//! | `trajectory POSE [POSE …] over T [at HZ]` | the active robot's motion: quintic point-to-point moves of T s between the poses (zero speed and acceleration at each pose, Corke's `jtraj`), sampled at HZ (default 500); a pose is one value per coordinate, comma separated, rad or m when bare, `pi` multiples allowed (`0,pi/4,-pi,0,pi/4,0`), or with a unit (`0,45deg,-180deg,0,45deg,0`, `5cm`); one pose is held for T (the gravity load) |
//! | `scene PATH` | read a TOML scene (io::scene) exactly as `--scene` does (`pipeline::TakeOptions::from_scene`): unit, stature, up, position, joints, mass, sex, link masses, smooth, locks, subtree, contact, keep_first_frame and joint_translations become the take options, its gains `kp`/`kv`; its takes are loaded (the first active) |
//! | `set KEY VALUE` | change a parameter (below); results recompute on the next use |
//! | `run id` | inverse dynamics over the active take (RNEA at every frame) |
//! | `run sim` | computed-torque simulation tracking the active take (`kp`, `kv`, `integrator`, `dt`); the message gives the tracking error |
//! | `blend A B T0:T1` | take A until T0, take B from T1, a C² blend between (s; B's root and heading aligned to A's); the result, named `A+B`, becomes active |
//! | `take next\|prev\|N\|NAME` | make another loaded take active (N from 1, in load order); its results are computed anew and the selection kept when the take has it (a human's left knee otherwise) |
//! | `select JOINT` | select a coordinate (`LeftLeg.Xrotation`, `LeftLeg:wx`, `j2`) or a joint: its rotation coordinate with the largest range of motion over the take (the flexion axis of a knee or elbow; `J:wx`… for ball joints) |
//! | `frame N` | go to frame N (0-based) |
//! | `play`, `pause` | start / stop playback |
//! | `export csv\|svg\|png\|bvh\|urdf\|mjcf PATH` | write the results (CSV: `time`, `q:`, `v:`, `a:`, `tau:` per coordinate, SI), the angle and torque chart of the selection (the paper's figure 4; `png`: the same chart as a bitmap; docs/reports.md), the active take's motion as BVH as it is seen (blended, smoothed with the current `smooth`), the model as URDF, or as MuJoCo MJCF with each motor's gear `N·η` from the drives (`set motor.gear`) |
//! | `export states\|trc\|grf PATH` | the active BVH take as `articula export states\|trc\|grf` writes it under the current settings: states (`.sto` for OpenSim, euler joints, else CSV), joint centres as OpenSim markers (`.trc`, mm), the estimated ground reactions (`.mot` with its ExternalLoads XML beside it, else CSV) |
//! | `export id PATH` | the active BVH take's inverse dynamics as `articula id` writes them (residual reduction as `set consistent`): OpenSim's `.sto` (`<coord>_moment` N·m, `<coord>_force` N) when PATH ends so, else `id`'s CSV with its sidecar |
//! | `export bvh sim PATH` | the motion of the last `run sim` (under the current parameters) as BVH |
//! | `compare weights 60,80,100 [joint J] PATH` | re-run inverse dynamics at each body mass; J's torque (default: the selection) per mass: a chart with the peak/RMS table (`.svg`, or `.png` as a bitmap) or the curves (`.csv`, `time`, `tau:<coord>:<m>kg`, with its sidecar) |
//! | `report motor PATH` | motor sizing (report::motor) of every revolute joint of a robot (or of the selected joint of an avatar): torque, speed, power and current curves with the table of peak/RMS torque, peak speed and power, peak/RMS current and the motor class each needs (`.svg`, or `.png` as a bitmap), or the table alone (`.csv`) |
//! | `report gait PATH` | the clinical gait view (report::gait; docs/reports.md) of the active human take: hip, knee and ankle moments (N·m/kg) over the gait cycle from each foot's strikes, mean ± SD, left and right, stance shaded, the speed-matched Schwartz 2008 band (`.svg` or `.png`); its message gives each side's cycles and stance |
//! | `report motor curves PATH.csv` | the plotted curves: `time`, `tau:<joint>`, `v:`, `power:`, `current:` (s, N·m, rad/s, W, A) |
//! | `expect …` | an assertion (below); a failed expect fails the replay |
//! | `screen PATH` | write the current screen of the TUI (as text) to PATH |
//! | `key KEYS` | inject keystrokes into the TUI: characters as written, special keys as `<Enter>`, `<Esc>`, `<Tab>`, `<Space>`, `<Up>`, `<Down>`, `<Left>`, `<Right>`, `<BS>`, `<C-c>` |
//! | `quit` | leave the TUI (ends a replay) |
//!
//! `set` keys of a BVH take (the pipeline's `TakeOptions`, with the CLI flags' syntax):
//! `body.mass KG`, `body.sex male|female`, `body.segments regression|fractions` (segment masses
//! by Zatsiorsky–Seluyanov's regression on body mass and the take's stature, the default, or
//! de Leva's fixed fractions: `--segments`), `unit auto|m|dm|cm|mm|in|cmu|METRES`,
//! `stature auto|M`, `up auto|x|y|z`, `positions auto|add|replace`, `subtree none|JOINT`,
//! `joints euler|ball`, `smooth none|gaussian:W|butterworth:F[hz][:ORDER]` (W in s, F in Hz),
//! `contact auto|feet|none`, `consistent auto|on|off` (residual reduction with ground contact,
//! as `--consistent`: auto is on when contact is feet, or auto settled on feet; the status line
//! then says the take's residuals against Hicks et al.'s thresholds), `edges exclude|include`
//! (whether the frames within the smoothing's reach of the take's ends count in the
//! accelerations' and torques' min, max, peak, mean and RMS, as `anatomy --edges`; frames whose
//! residuals stay beyond the thresholds never count), `overlay mirror|angle|feet|weights|sim|none`
//! (what the curves add: the selected coordinate's mirror, `knee_r` beside `knee_l`; the moment
//! against the angle; both feet's vertical ground forces; the torques of the last `compare
//! weights` per body mass; the last `run sim`'s tracking error: a view setting, nothing is
//! recomputed), `link.<joint>.mass KG`,
//! `lock J1,J2,…` (or `none`),
//! `keep_first_frame true|false` (keep a rest pose stored as frame 0, `--keep-first-frame`; it
//! acts when a take is read, so it applies to the takes loaded after it),
//! `joint_translations weld|keep` (position channels on joints below the body's root held at
//! their mean, or prismatic coordinates, `--joint-translations`); `bvh_style portable|as-read`
//! (how `export bvh` writes the take, `--bvh-style`); of the simulation:
//! `kp X`, `kv X` (every coordinate's gain, 1/s² and 1/s), `kp.<joint> X`, `kv.<joint> X` (one
//! joint's coordinates or one coordinate: diagonal gains, as `--kp LeftLeg=900`),
//! `integrator euler|semi-implicit|rk4|dopri5`, `dt S`; `blend.window S`.
//! A robot's masses are those of its DH table or URDF.
//! Every key is one row of [`settings::SETTINGS`]; `set KEY` without a value is an error
//! that quotes the key's row (`usage: set KEY VALUE (set smooth none|gaussian:W|…: the
//! smoothing of the joint angles …)`).
//!
//! Motor drives for `report motor` (the gear relations of report::motor: `τ_m = τ/(N·η)`,
//! `ω_m = N·q̇`, `I = τ/(Km·N·η)`): `motor.km` (Km, N·m/A), `motor.gear` (N, motor turns per
//! joint turn), `motor.efficiency` (η in (0, 1]), `motor.rotor_inertia` (J_m, kg·m², motor
//! shaft: the reflected term `J_m·N²·q̈` of report::motor_duty) set the drive of every joint;
//! `motor.<coord>.km|gear|efficiency` override it for one coordinate (`motor.j2.gear 107.815`);
//! `motor.catalogue PATH|auto` chooses the catalogue of motor classes (TOML, the format of the
//! bundled `data/motor_classes.toml`, values on the motor shaft).
//!
//! `expect` forms (bare bounds in the unit the workbench shows, see Units above):
//! - `expect nv N`, `expect nq N`, `expect frames N`, `expect frame N`, `expect selected NAME`;
//! - `expect mass between LO HI` (kg);
//! - `expect peak|min|max|mean|rms|now COORD angle|velocity|acceleration|torque between LO HI`
//!   (peak is the largest |x| over the take, now the value at the current frame; the angle of
//!   a ball joint coordinate `J:wx` is the rotation-vector component). Bare LO and HI are deg,
//!   deg/s, deg/s² on a rotation and m, m/s, m/s² on a translation; torques N·m, forces N.
//!   E.g. `expect max LeftLeg.Xrotation angle between 30 60` (degrees), the same as
//!   `between 30deg 60deg` or `between 0.5236rad 1.0472rad`;
//!   `expect peak LeftLeg.Xrotation torque between 20 150`; `expect now j3 angle between 19cm
//!   21cm` (a prismatic joint). A failure prints the value rounded in the coordinate's unit:
//!   `peak LeftLeg.Xrotation torque 131.4 N·m not in [110, 120] N·m`;
//! - `expect screen contains TEXT`, `expect message contains TEXT`.
//!
//! `expect`, `export`, `compare`, `report` and `screen` run inverse dynamics first when the results are missing or
//! stale, so a session needs no explicit `run id`.
//!
//! # Replay
//!
//! [`run_session_with`] parses the whole file first (a syntax error anywhere stops before anything
//! runs), then applies the commands in order and stops at the first failure; every error
//! carries the session file and line. Replays are deterministic: no wall clock, no threads,
//! shortest round-trip number formatting, so the same session writes byte-identical files.
//!
//! # Long commands
//!
//! `load`, `scene`, `trajectory`, `blend`, `run`, `export`, `compare weights`, `report motor`
//! and an `expect` whose results are stale are prepared as a [`Job`]
//! ([`Workbench::prepare`]): a snapshot of what they read, runnable on any thread with a
//! [`Control`] for progress and cancel, whose result only [`Workbench::finish`] stores. The
//! terminal UI runs them on its worker thread; [`Workbench::apply`] (replays, tests) runs the
//! same job inline, so both write the same bytes. A cancelled or failed job changes nothing:
//! files are written last, through `io::write_atomic`, after the last cancel check.

pub mod command;
pub mod edit_bench;
pub mod engine;
pub mod settings;
pub mod trajectory;
pub mod units;
pub mod workbench;

pub use command::{Command, Expectation, ExportKind, RunKind, TakeRef, parse_line, parse_session};
pub use engine::{Analysis, Builtin, Control, Engine, LeftOut, Params, Take};
pub use workbench::{Job, JobResult, Outcome, Workbench};

use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Errors of the session language.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SessionError {
    /// A line that does not parse.
    #[error("{}{line}: {message}", file.as_ref().map(|f| format!("{}:", f.display())).unwrap_or_else(|| "line ".into()))]
    Syntax {
        file: Option<PathBuf>,
        line: usize,
        message: String,
    },
    /// A command that cannot be applied to the current state (unknown joint, no take, ...).
    #[error("{0}")]
    Command(String),
    /// A failed `expect`.
    #[error("expect failed: {0}")]
    Expect(String),
    /// The library failed (bad file, numerical failure, ...).
    #[error(transparent)]
    Engine(#[from] crate::error::Error),
    /// A command of a session file failed.
    #[error("{}:{line}: `{command}`: {source}", file.display())]
    At {
        file: PathBuf,
        line: usize,
        command: String,
        #[source]
        source: Box<SessionError>,
    },
    /// Reading the session file failed.
    #[error("{}: {source}", path.display())]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

impl SessionError {
    /// The 1-based line of the session file this error comes from, if known.
    pub fn line(&self) -> Option<usize> {
        match self {
            SessionError::Syntax { line, .. } | SessionError::At { line, .. } => Some(*line),
            _ => None,
        }
    }
    /// True when a computation stopped because it was cancelled (directly or at a line).
    pub fn is_cancelled(&self) -> bool {
        match self {
            SessionError::Engine(crate::error::Error::Cancelled) => true,
            SessionError::At { source, .. } => source.is_cancelled(),
            _ => false,
        }
    }
    /// True for a failed `expect` (directly or at a line).
    pub fn is_expect(&self) -> bool {
        match self {
            SessionError::Expect(_) => true,
            SessionError::At { source, .. } => source.is_expect(),
            _ => false,
        }
    }
}

/// What a replay did.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Report {
    /// Commands applied.
    pub commands: usize,
    /// `expect`s that passed.
    pub expects: usize,
    /// Files written, in order.
    pub written: Vec<PathBuf>,
    /// Every message, in order.
    pub messages: Vec<String>,
    /// Every `expect` replayed, in order: the one that failed (if any) last.
    pub expectations: Vec<ExpectRecord>,
}

/// `articula run --json`: a replay's [`Report`] with how it ended.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ReportJson<'a> {
    pub session: String,
    /// True when every command ran and every `expect` passed.
    pub ok: bool,
    /// Why the replay stopped, if it did.
    pub error: Option<String>,
    /// Commands applied.
    pub commands: usize,
    pub expectations: &'a [ExpectRecord],
    pub written: Vec<String>,
    pub messages: &'a [String],
}

impl Report {
    /// The report of the replay of `session` as JSON, `error` the one it stopped on.
    pub fn json(&self, session: &Path, error: Option<&SessionError>) -> ReportJson<'_> {
        ReportJson {
            session: session.display().to_string(),
            ok: error.is_none(),
            error: error.map(|e| e.to_string()),
            commands: self.commands,
            expectations: &self.expectations,
            written: self
                .written
                .iter()
                .map(|p| p.display().to_string())
                .collect(),
            messages: &self.messages,
        }
    }
}

/// One `expect` of a replay (`articula run --json`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ExpectRecord {
    /// 1-based line in the session file.
    pub line: usize,
    /// The command as written.
    pub expect: String,
    /// What was found: the value in the coordinate's own unit with the bounds (`mean
    /// LeftLeg.Xrotation torque 12.3 N·m within [10, 15] N·m`), or why it failed.
    pub result: String,
    /// The value a passed `expect` found (unrounded) and its unit (the one `result` shows it
    /// in; empty for a count); null for a failed one (`result` gives it) and for those with no
    /// number (`selected`, `message`, `screen`).
    pub value: Option<f64>,
    pub unit: Option<String>,
    pub pass: bool,
}

/// What a session needs from a user interface: `key` and `screen` (and `expect screen`).
pub trait Frontend {
    /// Feeds keystrokes (the `key` syntax) to the interface, which applies the commands they
    /// make to `wb`.
    fn keys(&mut self, wb: &mut Workbench, keys: &str) -> Result<Outcome, SessionError>;
    /// The current screen as text, one line per row.
    fn screen(&mut self, wb: &Workbench) -> String;
}

/// Replays the session at `path` with front end `frontend`, keeping what the replay did up to
/// an error: the report (with the failed `expect` recorded, `pass` false) and the error, if any
/// (`articula run --json`). The TUI's headless replay is `tui::run_session_recorded`.
pub fn run_session_recorded_with(
    path: &Path,
    out_dir: &Path,
    frontend: &mut dyn Frontend,
) -> (Report, Result<(), SessionError>) {
    let mut report = Report::default();
    let result = replay(path, out_dir, frontend, &mut report);
    (report, result)
}

/// Replays the session file at `path` with front end `frontend` (the TUI's headless replay
/// is `tui::run_session`); relative outputs go under `out_dir` (created if needed).
pub fn run_session_with(
    path: &Path,
    out_dir: &Path,
    frontend: &mut dyn Frontend,
) -> Result<Report, SessionError> {
    let mut report = Report::default();
    replay(path, out_dir, frontend, &mut report)?;
    Ok(report)
}

/// Replays the session at `path` into `report` (filled as far as the replay went).
fn replay(
    path: &Path,
    out_dir: &Path,
    frontend: &mut dyn Frontend,
    report: &mut Report,
) -> Result<(), SessionError> {
    let text = std::fs::read_to_string(path).map_err(|source| SessionError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let commands = parse_session(&text).map_err(|e| match e {
        SessionError::Syntax { line, message, .. } => SessionError::Syntax {
            file: Some(path.to_path_buf()),
            line,
            message,
        },
        e => e,
    })?;
    std::fs::create_dir_all(out_dir).map_err(|source| SessionError::Io {
        path: out_dir.to_path_buf(),
        source,
    })?;
    let in_dir = path.parent().unwrap_or(Path::new("."));
    let mut wb = Workbench::new(Arc::new(Builtin), in_dir, out_dir);
    let lines: Vec<&str> = text.lines().collect();
    for (line, cmd) in &commands {
        let at = |source: SessionError| SessionError::At {
            file: path.to_path_buf(),
            line: *line,
            command: lines[line - 1].trim().to_string(),
            source: Box::new(source),
        };
        let outcome = apply_with(&mut wb, frontend, cmd);
        let is_expect = matches!(cmd, Command::Expect(_));
        if is_expect {
            report.expectations.push(ExpectRecord {
                line: *line,
                expect: lines[line - 1].trim().to_string(),
                result: match &outcome {
                    Ok(o) => o.message.trim_start_matches("ok: ").to_string(),
                    Err(e) => e.to_string(),
                },
                value: outcome.as_ref().ok().and_then(|o| o.value).map(|v| v.0),
                unit: outcome
                    .as_ref()
                    .ok()
                    .and_then(|o| o.value)
                    .map(|v| v.1.to_string()),
                pass: outcome.is_ok(),
            });
        }
        let outcome = match outcome {
            Ok(o) => o,
            Err(e) => {
                report.messages = wb.messages.clone();
                return Err(at(e));
            }
        };
        report.commands += 1;
        if is_expect {
            report.expects += 1;
        }
        report.written.extend(outcome.written);
        if outcome.quit {
            break;
        }
    }
    report.messages = wb.messages.clone();
    Ok(())
}

/// Applies `cmd` to `wb`, sending `key`, `screen` and `expect screen` to the front end.
/// `screen` and `expect screen` first bring stale results up to date (a replay shows what the
/// commands so far compute).
pub fn apply_with(
    wb: &mut Workbench,
    frontend: &mut dyn Frontend,
    cmd: &Command,
) -> Result<Outcome, SessionError> {
    apply_frontend(wb, frontend, cmd, true)
}

/// [`apply_with`]; with `refresh` false, `screen` and `expect screen` take the screen as it is
/// (an interactive front end whose worker is recomputing).
pub fn apply_frontend(
    wb: &mut Workbench,
    frontend: &mut dyn Frontend,
    cmd: &Command,
    refresh: bool,
) -> Result<Outcome, SessionError> {
    match cmd {
        Command::Key(keys) => frontend.keys(wb, keys),
        Command::Screen { path } => {
            if refresh {
                wb.refresh()?;
            }
            let out = wb.out_path(path);
            let text = frontend.screen(wb);
            crate::io::write_atomic(&out, text.as_bytes())?;
            // said in the status line too: the TUI shows the last message
            let rows = text.lines().count();
            let message = format!(
                "wrote the screen as text ({rows} lines) to {}",
                out.display()
            );
            wb.messages.push(message.clone());
            Ok(Outcome {
                message,
                written: vec![out],
                ..Outcome::default()
            })
        }
        Command::Expect(Expectation::ScreenContains(t)) => {
            if refresh {
                wb.refresh()?;
            }
            let screen = frontend.screen(wb);
            if screen.contains(t.as_str()) {
                Ok(Outcome {
                    message: format!("ok: screen contains '{t}'"),
                    ..Outcome::default()
                })
            } else {
                Err(SessionError::Expect(format!(
                    "the screen does not contain '{t}':\n{screen}"
                )))
            }
        }
        _ => wb.apply(cmd),
    }
}
