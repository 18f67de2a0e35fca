//! Commands of the session language and their parser (one command per line).
//!
//! The grammar is documented in the [module doc of `session`](super).

use super::SessionError;
use super::units::{self, Kind, Measure, UnitError};
use std::path::PathBuf;

/// What `export` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExportKind {
    /// Time, q, v, a and τ of the current results, one column per coordinate (SI).
    Csv,
    /// Angle and torque curves of the selected coordinate (report chart).
    Svg,
    /// The same chart as a PNG bitmap (`report::chart`, same layout).
    Png,
    /// The active take's motion as the user sees it (blended, smoothed) as a BVH take.
    Bvh,
    /// The motion of the last `run sim` as a BVH take.
    BvhSim,
    /// The current model as URDF.
    Urdf,
    /// The current model as MuJoCo MJCF, motor gears from the drives (`set motor.gear`).
    Mjcf,
    /// The active take's states as `articula export states` writes them: CSV, or OpenSim's
    /// `.sto` when the path ends so (euler joints).
    States,
    /// The active take's joint centres as OpenSim markers (`.trc`, mm), as `articula export trc`.
    Trc,
    /// The active take's estimated ground reactions as `articula export grf`: CSV, or an
    /// OpenSim external-loads `.mot` with its ExternalLoads XML beside it.
    Grf,
    /// The active take as glTF 2.0 binary (`.glb`): skeleton, skinned superquadric links and
    /// the animation, as `articula export gltf`.
    Gltf,
    /// The active take's inverse dynamics as `articula id` writes them: CSV, or OpenSim's
    /// `.sto` (`<coord>_moment` N·m, `<coord>_force` N) when the path ends so.
    Id,
}

/// Every `export` word and its kind (`bvh sim` is `bvh` followed by `sim`).
pub const EXPORT_WORDS: &[(&str, ExportKind)] = &[
    ("csv", ExportKind::Csv),
    ("svg", ExportKind::Svg),
    ("bvh", ExportKind::Bvh),
    ("bvh sim", ExportKind::BvhSim),
    ("urdf", ExportKind::Urdf),
    ("mjcf", ExportKind::Mjcf),
    ("states", ExportKind::States),
    ("trc", ExportKind::Trc),
    ("grf", ExportKind::Grf),
    ("gltf", ExportKind::Gltf),
    ("png", ExportKind::Png),
    ("id", ExportKind::Id),
];

impl ExportKind {
    /// The command's word for the kind (`export WORD PATH`).
    pub fn word(self) -> &'static str {
        EXPORT_WORDS
            .iter()
            .find(|(_, k)| *k == self)
            .map_or("?", |(w, _)| w)
    }

    /// The files the pipeline writes for the active take (not from the workbench's results).
    pub fn take_file(self) -> bool {
        matches!(
            self,
            ExportKind::States
                | ExportKind::Trc
                | ExportKind::Grf
                | ExportKind::Gltf
                | ExportKind::Id
        )
    }
}

/// What a computation runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunKind {
    /// Inverse dynamics over the take (RNEA at every frame).
    Id,
    /// Computed-torque simulation tracking the take.
    Sim,
}

/// A per-frame series of the current results that `expect` can measure.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// q (rad or m).
    Angle,
    /// v (rad/s or m/s).
    Velocity,
    /// a (rad/s² or m/s²).
    Acceleration,
    /// τ (N·m or N).
    Torque,
}

impl Quantity {
    /// The kind of this quantity on a rotational (`angular`) or a translational coordinate.
    pub fn kind(self, angular: bool) -> Kind {
        match (self, angular) {
            (Quantity::Angle, true) => Kind::Angle,
            (Quantity::Angle, false) => Kind::Length,
            (Quantity::Velocity, true) => Kind::AngularVelocity,
            (Quantity::Velocity, false) => Kind::Velocity,
            (Quantity::Acceleration, true) => Kind::AngularAcceleration,
            (Quantity::Acceleration, false) => Kind::Acceleration,
            (Quantity::Torque, true) => Kind::Torque,
            (Quantity::Torque, false) => Kind::Force,
        }
    }

    /// Its name in messages (`angle`).
    pub fn name(self) -> &'static str {
        match self {
            Quantity::Angle => "angle",
            Quantity::Velocity => "velocity",
            Quantity::Acceleration => "acceleration",
            Quantity::Torque => "torque",
        }
    }
}

/// A statistic of a series over the whole take.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Statistic {
    /// max |x|.
    Peak,
    Min,
    Max,
    Mean,
    /// sqrt(mean x²).
    Rms,
    /// The value at the current frame.
    Now,
}

/// An assertion on the state or the results. `Mass` is in kg; the bounds of `Stat` are kept
/// as written, since what a bare number means (deg or m) depends on the coordinate.
#[derive(Debug, Clone, PartialEq)]
pub enum Expectation {
    /// `expect nv N`: degrees of freedom of the current model.
    Nv(usize),
    /// `expect nq N`.
    Nq(usize),
    /// `expect frames N`: frames of the active take.
    Frames(usize),
    /// `expect mass between LO HI`: total mass of the current model (kg).
    Mass { lo: f64, hi: f64 },
    /// `expect STAT COORD QUANTITY between LO HI`: LO and HI as written (a bare number is in
    /// the unit the workbench shows: deg, deg/s, deg/s² on a rotation, m, m/s, m/s² on a
    /// translation, N·m or N).
    Stat {
        stat: Statistic,
        coord: String,
        quantity: Quantity,
        lo: Measure,
        hi: Measure,
    },
    /// `expect screen contains TEXT`: the current screen (as `screen` writes it) contains TEXT.
    ScreenContains(String),
    /// `expect message contains TEXT`: the last message contains TEXT.
    MessageContains(String),
    /// `expect selected NAME`: the selected coordinate.
    Selected(String),
    /// `expect frame N`: the current frame.
    Frame(usize),
}

/// One command of the session language.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// `load PATH [as NAME]`: a BVH take (or `demo:walk`, the generated walk), a DH table
    /// (`.toml`), a URDF (`.urdf`), or a states CSV (`.csv`) as the active robot's motion.
    Load { path: PathBuf, name: Option<String> },
    /// `trajectory POSE [POSE …] over T [at HZ]`: the active robot's motion, quintic
    /// point-to-point moves of T seconds between the poses (comma separated, one value per
    /// coordinate; bare values rad or m, or with a unit: `40deg`, `5cm`), sampled at HZ
    /// (default 500).
    Trajectory {
        poses: Vec<Vec<Measure>>,
        duration_s: f64,
        rate_hz: f64,
    },
    /// `scene PATH`: a TOML scene.
    Scene { path: PathBuf },
    /// `set KEY VALUE`.
    Set { key: String, value: String },
    /// `run id` / `run sim`.
    Run(RunKind),
    /// `blend A B WINDOW`: blend take B into take A over WINDOW (`t0:t1`, seconds).
    Blend {
        a: String,
        b: String,
        window: (f64, f64),
    },
    /// `take next|prev|N|NAME`: make another loaded take active (N counts from 1, in load
    /// order).
    Take(TakeRef),
    /// `select JOINT`: a coordinate (`LeftLeg.Xrotation`) or a BVH joint (its first coordinate).
    Select(String),
    /// `frame N` (0-based).
    Frame(usize),
    /// `play`.
    Play,
    /// `pause`.
    Pause,
    /// `export csv|svg|png|bvh|urdf|mjcf PATH`.
    Export { kind: ExportKind, path: PathBuf },
    /// `compare weights 60,80,100 [joint J] PATH`.
    CompareWeights {
        masses: Vec<f64>,
        joint: Option<String>,
        path: PathBuf,
    },
    /// `report motor [curves] PATH`: the sizing (SVG chart and table, or the CSV table), or
    /// with `curves` the plotted curves as CSV.
    ReportMotor { path: PathBuf, curves: bool },
    /// `report gait PATH`: the clinical gait view (report::gait) of the active human take.
    ReportGait { path: PathBuf },
    /// `expect …`.
    Expect(Expectation),
    /// `screen PATH`: write the current screen as text.
    Screen { path: PathBuf },
    /// `key KEYS`: inject keystrokes (`<Enter>`, `<Esc>`, `<Left>`, `<Space>`, … or characters).
    Key(String),
    /// `quit`.
    Quit,
}

/// Which loaded take `take` makes active.
#[derive(Debug, Clone, PartialEq)]
pub enum TakeRef {
    Next,
    Prev,
    /// 1-based, in load order.
    Index(usize),
    Name(String),
}

/// Every command word, for completion and error messages.
pub const COMMAND_WORDS: &[&str] = &[
    "load",
    "scene",
    "set",
    "run",
    "trajectory",
    "blend",
    "take",
    "select",
    "frame",
    "play",
    "pause",
    "export",
    "compare",
    "report",
    "expect",
    "screen",
    "key",
    "quit",
];

/// A joint value of a pose: a number, or a multiple of π (`pi`, `-pi/2`, `3pi/4`, `0.5*pi`).
pub fn parse_angle(w: &str) -> Option<f64> {
    let x = match w.split_once("pi") {
        None => w.parse::<f64>().ok()?,
        Some((coef, den)) => {
            let coef = coef.trim_end_matches('*');
            let c = match coef {
                "" => 1.0,
                "-" => -1.0,
                c => c.parse::<f64>().ok()?,
            };
            let d = match den {
                "" => 1.0,
                d => d.strip_prefix('/')?.parse::<f64>().ok()?,
            };
            c * std::f64::consts::PI / d
        }
    };
    x.is_finite().then_some(x)
}

/// Splits a line into words: whitespace separated, `"…"` quotes a word with spaces.
fn words(line: &str, lineno: usize) -> Result<Vec<String>, SessionError> {
    let mut out = vec![];
    let mut chars = line.chars().peekable();
    while let Some(&c) = chars.peek() {
        if c.is_whitespace() {
            chars.next();
        } else if c == '#' {
            // a comment to the end of the line, as in a shell: `load a.bvh  # the walk`
            break;
        } else if c == '"' {
            chars.next();
            let mut w = String::new();
            loop {
                match chars.next() {
                    Some('"') => break,
                    Some(c) => w.push(c),
                    None => return Err(syntax(lineno, "unterminated \"quoted\" word")),
                }
            }
            out.push(w);
        } else {
            let mut w = String::new();
            while let Some(&c) = chars.peek() {
                if c.is_whitespace() {
                    break;
                }
                w.push(c);
                chars.next();
            }
            out.push(w);
        }
    }
    Ok(out)
}

fn syntax(line: usize, message: impl Into<String>) -> SessionError {
    SessionError::Syntax {
        file: None,
        line,
        message: message.into(),
    }
}

/// A number of `kind` in SI: a unit may be written (`500ms`), a bare number is in the unit
/// the workbench shows.
fn quantity(w: &str, line: usize, kind: Kind, what: &str) -> Result<f64, SessionError> {
    units::parse_si(w, kind, what).map_err(|e| unit_error(line, what, e))
}

/// A unit error at `line`, for `what`.
fn unit_error(line: usize, what: &str, e: UnitError) -> SessionError {
    match e {
        UnitError::NotANumber { word } => {
            syntax(line, format!("expected {what} (a number), found '{word}'"))
        }
        e => syntax(line, e.to_string()),
    }
}

fn count(w: &str, line: usize, what: &str) -> Result<usize, SessionError> {
    w.parse::<usize>().map_err(|_| {
        syntax(
            line,
            format!("expected {what} (a whole number), found '{w}'"),
        )
    })
}

/// `t0:t1` in seconds, `t0 < t1`.
pub fn parse_window(w: &str, line: usize) -> Result<(f64, f64), SessionError> {
    let (a, b) = w
        .split_once(':')
        .ok_or_else(|| syntax(line, format!("expected a window t0:t1 (s), found '{w}'")))?;
    let (t0, t1) = (
        quantity(a, line, Kind::Time, "t0")?,
        quantity(b, line, Kind::Time, "t1")?,
    );
    if t1 <= t0 {
        return Err(syntax(line, format!("window {w}: t1 must be after t0")));
    }
    Ok((t0, t1))
}

/// Parses one line of a session. `Ok(None)` for blank lines and `#` comments; a word that
/// begins with `#` starts a comment to the end of the line (`load a.bvh  # the walk`; quote
/// a word that begins with `#`; `key` lines are keystrokes, taken verbatim). `lineno` is
/// 1-based and goes into the error.
pub fn parse_line(line: &str, lineno: usize) -> Result<Option<Command>, SessionError> {
    let trimmed = line.trim();
    if trimmed.is_empty() || trimmed.starts_with('#') {
        return Ok(None);
    }
    // `key` takes the rest of the line verbatim (spaces are keystrokes too)
    if let Some(rest) = trimmed.strip_prefix("key ") {
        return Ok(Some(Command::Key(rest.trim_start().to_string())));
    }
    let w = words(trimmed, lineno)?;
    let (head, args) = (w[0].as_str(), &w[1..]);
    let arity = |n: &[usize], usage: &str| -> Result<(), SessionError> {
        if n.contains(&args.len()) {
            Ok(())
        } else {
            Err(syntax(lineno, format!("usage: {usage}")))
        }
    };
    let cmd = match head {
        "load" => {
            arity(&[1, 3], "load PATH [as NAME]")?;
            if args.len() == 3 && args[1] != "as" {
                return Err(syntax(lineno, "usage: load PATH [as NAME]"));
            }
            Command::Load {
                path: PathBuf::from(&args[0]),
                name: args.get(2).cloned(),
            }
        }
        "scene" => {
            arity(&[1], "scene PATH")?;
            Command::Scene {
                path: PathBuf::from(&args[0]),
            }
        }
        "set" => {
            // the settings' table: a known key without a value gets its own help
            let row = args.first().and_then(|k| super::settings::find(k));
            if args.len() < 2 {
                let help = row.map_or(String::new(), |(r, _)| format!(" ({})", r.usage()));
                return Err(syntax(lineno, format!("usage: set KEY VALUE{help}")));
            }
            let key = args[0].clone();
            if row.is_none() {
                return Err(syntax(
                    lineno,
                    format!(
                        "unknown setting '{key}' (expected one of {})",
                        super::settings::names().collect::<Vec<_>>().join(", ")
                    ),
                ));
            }
            Command::Set {
                key,
                value: args[1..].join(" "),
            }
        }
        "run" => {
            arity(&[1], "run id|sim")?;
            match args[0].as_str() {
                "id" => Command::Run(RunKind::Id),
                "sim" => Command::Run(RunKind::Sim),
                o => {
                    return Err(syntax(
                        lineno,
                        format!("run: expected id or sim, found '{o}'"),
                    ));
                }
            }
        }
        "trajectory" => parse_trajectory(args, lineno)?,
        "blend" => {
            arity(&[3], "blend A B WINDOW (t0:t1 in seconds)")?;
            Command::Blend {
                a: args[0].clone(),
                b: args[1].clone(),
                window: parse_window(&args[2], lineno)?,
            }
        }
        "take" => {
            arity(&[1], "take next|prev|N|NAME")?;
            Command::Take(match args[0].as_str() {
                "next" => TakeRef::Next,
                "prev" => TakeRef::Prev,
                n => match n.parse::<usize>() {
                    Ok(i) if i >= 1 => TakeRef::Index(i),
                    Ok(_) => return Err(syntax(lineno, "take N: takes count from 1")),
                    Err(_) => TakeRef::Name(n.to_string()),
                },
            })
        }
        "select" => {
            arity(&[1], "select JOINT")?;
            Command::Select(args[0].clone())
        }
        "frame" => {
            arity(&[1], "frame N")?;
            Command::Frame(count(&args[0], lineno, "a frame index")?)
        }
        "play" => {
            arity(&[0], "play")?;
            Command::Play
        }
        "pause" => {
            arity(&[0], "pause")?;
            Command::Pause
        }
        "quit" => {
            arity(&[0], "quit")?;
            Command::Quit
        }
        "export" => {
            let usage = "export csv|svg|bvh|urdf|mjcf|states|trc|grf|gltf|png|id PATH, or export bvh sim PATH";
            arity(&[2, 3], usage)?;
            if args.len() == 3 && (args[0] != "bvh" || args[1] != "sim") {
                return Err(syntax(lineno, format!("usage: {usage}")));
            }
            let word = if args.len() == 3 {
                "bvh sim".to_string()
            } else {
                args[0].clone()
            };
            let Some(&(_, kind)) = EXPORT_WORDS.iter().find(|(w, _)| *w == word) else {
                let words: Vec<&str> = EXPORT_WORDS
                    .iter()
                    .map(|(w, _)| *w)
                    .filter(|w| !w.contains(' '))
                    .collect();
                return Err(syntax(
                    lineno,
                    format!(
                        "export: expected one of {}, found '{word}'",
                        words.join(", ")
                    ),
                ));
            };
            Command::Export {
                kind,
                path: PathBuf::from(args.last().map(String::as_str).unwrap_or_default()),
            }
        }
        "compare" => {
            let usage = "compare weights 60,80,100 [joint J] PATH";
            arity(&[3, 5], usage)?;
            if args[0] != "weights" || (args.len() == 5 && args[2] != "joint") {
                return Err(syntax(lineno, format!("usage: {usage}")));
            }
            let masses = args[1]
                .split(',')
                .map(|m| quantity(m, lineno, Kind::Mass, "a body mass in kg"))
                .collect::<Result<Vec<_>, _>>()?;
            if let Some(m) = masses.iter().find(|m| **m <= 0.0) {
                return Err(syntax(lineno, format!("body mass {m} kg must be positive")));
            }
            Command::CompareWeights {
                masses,
                joint: (args.len() == 5).then(|| args[3].clone()),
                path: PathBuf::from(args.last().map(String::as_str).unwrap_or_default()),
            }
        }
        "report" => {
            let usage = "usage: report motor [curves] PATH, or report gait PATH";
            arity(&[2, 3], usage)?;
            if args[0] == "gait" {
                arity(&[2], usage)?;
                return Ok(Some(Command::ReportGait {
                    path: PathBuf::from(&args[1]),
                }));
            }
            if args[0] != "motor" || (args.len() == 3 && args[1] != "curves") {
                return Err(syntax(lineno, usage));
            }
            Command::ReportMotor {
                path: PathBuf::from(args.last().map(String::as_str).unwrap_or_default()),
                curves: args.len() == 3,
            }
        }
        "expect" => Command::Expect(parse_expect(args, lineno)?),
        "screen" => {
            arity(&[1], "screen PATH")?;
            Command::Screen {
                path: PathBuf::from(&args[0]),
            }
        }
        "key" => return Err(syntax(lineno, "usage: key KEYS")),
        o => {
            return Err(syntax(
                lineno,
                format!(
                    "unknown command '{o}' (expected one of {})",
                    COMMAND_WORDS.join(", ")
                ),
            ));
        }
    };
    Ok(Some(cmd))
}

const TRAJECTORY_USAGE: &str = "usage: trajectory POSE [POSE …] over T [at HZ] (a pose: one \
     value per coordinate, comma separated, rad or m unless a unit is written, e.g. \
     0,pi/4,pi,0,pi/4,0 or 0,45deg,180deg,0,45deg,0)";

/// One value of a pose: a number or a multiple of π (rad or m), or a number with an angle or
/// length unit (`40deg`, `5cm`; `pi/2rad`).
fn pose_value(x: &str, pose: &str, lineno: usize) -> Result<Measure, SessionError> {
    let bad = |why: &str| syntax(lineno, format!("trajectory: '{x}' in pose '{pose}' {why}"));
    let (value, unit) = units::split_unit(x, parse_angle).map_err(|_| bad("is not a number"))?;
    match unit {
        Some(u) if x.contains("pi") && u.symbol != "rad" => {
            Err(bad("multiplies π by a unit other than rad"))
        }
        Some(u) if !matches!(u.kind, Kind::Angle | Kind::Length) => Err(bad(&format!(
            "is {}; a pose takes angles ({}) or lengths ({})",
            u.kind.name(),
            units::symbols(Kind::Angle),
            units::symbols(Kind::Length)
        ))),
        _ => Ok(Measure { value, unit }),
    }
}

/// `trajectory POSE [POSE …] over T [at HZ]`.
fn parse_trajectory(args: &[String], lineno: usize) -> Result<Command, SessionError> {
    let usage = || syntax(lineno, TRAJECTORY_USAGE);
    let over = args.iter().position(|w| w == "over").ok_or_else(usage)?;
    if over == 0 {
        return Err(usage());
    }
    let poses = args[..over]
        .iter()
        .map(|p| {
            p.split(',')
                .map(|x| pose_value(x.trim(), p, lineno))
                .collect::<Result<Vec<Measure>, _>>()
        })
        .collect::<Result<Vec<_>, _>>()?;
    if poses.iter().any(|p| p.len() != poses[0].len()) {
        return Err(syntax(
            lineno,
            "trajectory: every pose needs the same number of values",
        ));
    }
    let rest = &args[over + 1..];
    let time = |t: &str| quantity(t, lineno, Kind::Time, "T (s)");
    let rate = |hz: &str| quantity(hz, lineno, Kind::Frequency, "a rate (Hz)");
    let (duration_s, rate_hz) = match rest {
        [t] => (time(t)?, 500.0),
        [t, at, hz] if at == "at" => (time(t)?, rate(hz)?),
        _ => return Err(usage()),
    };
    if duration_s <= 0.0 || rate_hz <= 0.0 {
        return Err(syntax(
            lineno,
            "trajectory: the move time and the rate must be positive",
        ));
    }
    if duration_s * rate_hz < 2.0 || duration_s * rate_hz * poses.len() as f64 > 1e6 {
        return Err(syntax(
            lineno,
            "trajectory: T × HZ must give 2 samples per move or more, a million in all or less",
        ));
    }
    Ok(Command::Trajectory {
        poses,
        duration_s,
        rate_hz,
    })
}

const EXPECT_USAGE: &str = "expect nv N | nq N | frames N | frame N | selected NAME | \
     mass between LO HI | peak|min|max|mean|rms|now COORD angle|velocity|acceleration|torque \
     between LO HI | screen contains TEXT | message contains TEXT";

fn parse_expect(args: &[String], lineno: usize) -> Result<Expectation, SessionError> {
    let usage = || syntax(lineno, format!("usage: {EXPECT_USAGE}"));
    let between_words = |a: &[String]| -> Result<(String, String), SessionError> {
        if a.len() != 3 || a[0] != "between" {
            return Err(usage());
        }
        Ok((a[1].clone(), a[2].clone()))
    };
    let below = |lo: &str, hi: &str| syntax(lineno, format!("between {lo} {hi}: HI is below LO"));
    let Some(head) = args.first() else {
        return Err(usage());
    };
    let rest = &args[1..];
    let one = |what: &str| -> Result<usize, SessionError> {
        if rest.len() != 1 {
            return Err(usage());
        }
        count(&rest[0], lineno, what)
    };
    Ok(match head.as_str() {
        "nv" => Expectation::Nv(one("nv")?),
        "nq" => Expectation::Nq(one("nq")?),
        "frames" => Expectation::Frames(one("a frame count")?),
        "frame" => Expectation::Frame(one("a frame index")?),
        "selected" if rest.len() == 1 => Expectation::Selected(rest[0].clone()),
        "mass" => {
            let (a, b) = between_words(rest)?;
            let lo = quantity(&a, lineno, Kind::Mass, "LO (kg)")?;
            let hi = quantity(&b, lineno, Kind::Mass, "HI (kg)")?;
            if hi < lo {
                return Err(below(&a, &b));
            }
            Expectation::Mass { lo, hi }
        }
        "screen" | "message" if rest.len() >= 2 && rest[0] == "contains" => {
            let text = rest[1..].join(" ");
            if head == "screen" {
                Expectation::ScreenContains(text)
            } else {
                Expectation::MessageContains(text)
            }
        }
        "peak" | "min" | "max" | "mean" | "rms" | "now" => {
            if rest.len() != 5 {
                return Err(usage());
            }
            let stat = match head.as_str() {
                "peak" => Statistic::Peak,
                "min" => Statistic::Min,
                "max" => Statistic::Max,
                "mean" => Statistic::Mean,
                "now" => Statistic::Now,
                _ => Statistic::Rms,
            };
            let quantity = match rest[1].as_str() {
                "angle" | "q" => Quantity::Angle,
                "velocity" | "v" => Quantity::Velocity,
                "acceleration" | "a" => Quantity::Acceleration,
                "torque" | "tau" => Quantity::Torque,
                o => {
                    return Err(syntax(
                        lineno,
                        format!("expected angle, velocity, acceleration or torque, found '{o}'"),
                    ));
                }
            };
            let (a, b) = between_words(&rest[2..])?;
            let (lo, hi) = (
                stat_bound(&a, quantity, lineno, "LO")?,
                stat_bound(&b, quantity, lineno, "HI")?,
            );
            // HI below LO is known now when both are bare or both of one kind
            let si = |m: &Measure| m.unit.map_or(m.value, |u| m.value * u.to_si);
            if lo.kind() == hi.kind() && si(&hi) < si(&lo) {
                return Err(below(&a, &b));
            }
            if let (Some(k), Some(l)) = (lo.kind(), hi.kind())
                && k != l
            {
                return Err(syntax(
                    lineno,
                    format!("between {a} {b}: LO is {} and HI {}", k.name(), l.name()),
                ));
            }
            Expectation::Stat {
                stat,
                coord: rest[0].clone(),
                quantity,
                lo,
                hi,
            }
        }
        _ => return Err(usage()),
    })
}

/// A bound of `expect STAT COORD QUANTITY between LO HI`: a number, with a unit of the
/// quantity on a rotation or on a translation (which of the two the coordinate is, the
/// workbench checks when it runs).
fn stat_bound(
    w: &str,
    quantity: Quantity,
    lineno: usize,
    what: &str,
) -> Result<Measure, SessionError> {
    let m = units::parse_measure(w).map_err(|e| unit_error(lineno, what, e))?;
    let kinds = [quantity.kind(true), quantity.kind(false)];
    match m.kind() {
        Some(k) if !kinds.contains(&k) => Err(syntax(
            lineno,
            format!(
                "'{w}' is {}; {} {} takes {}",
                k.name(),
                if quantity == Quantity::Angle {
                    "an"
                } else {
                    "a"
                },
                quantity.name(),
                units::accepted(&kinds, units::Bare::Shown)
            ),
        )),
        _ => Ok(m),
    }
}

/// Parses a whole session text; the first bad line stops it. Returns `(line number, command)`.
pub fn parse_session(text: &str) -> Result<Vec<(usize, Command)>, SessionError> {
    let mut out = vec![];
    for (i, line) in text.lines().enumerate() {
        if let Some(c) = parse_line(line, i + 1)? {
            out.push((i + 1, c));
        }
    }
    Ok(out)
}
