//! Units the user sees: the suffixes a session number may carry (`40deg`, `12cm`, `1.5N·m`)
//! and how a value is shown (rotations in degrees, as the workbench draws them, rounded to
//! what is meaningful).
//!
//! Everything inside articula stays SI (rad, m, s, kg, N, N·m); this module is the edge. Two
//! tables of data hold it all: [`UNITS`], every unit a number may be written in with its
//! factor to SI, and `SHOWN`, per [`Kind`] the unit values are shown in and their rounding.
//! [`shown`], [`format_number`] and [`format_value`] give any front end (messages, the TUI,
//! charts of anatomical curves) the display value and unit of an SI value.

use std::f64::consts::PI;

/// What a number measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[non_exhaustive]
pub enum Kind {
    /// A rotation (revolute coordinate, rotation-vector component of a ball joint).
    Angle,
    /// A translation (prismatic coordinate), a stature.
    Length,
    AngularVelocity,
    Velocity,
    AngularAcceleration,
    Acceleration,
    /// The generalized force of a rotation.
    Torque,
    /// The generalized force of a translation.
    Force,
    Mass,
    Time,
    Frequency,
}

impl Kind {
    /// The kind's name in a sentence ("an angle").
    pub fn name(self) -> &'static str {
        match self {
            Kind::Angle => "an angle",
            Kind::Length => "a length",
            Kind::AngularVelocity => "an angular velocity",
            Kind::Velocity => "a velocity",
            Kind::AngularAcceleration => "an angular acceleration",
            Kind::Acceleration => "an acceleration",
            Kind::Torque => "a torque",
            Kind::Force => "a force",
            Kind::Mass => "a mass",
            Kind::Time => "a time",
            Kind::Frequency => "a frequency",
        }
    }
}

/// A unit a number may be written in: `symbol` right after the number (`40deg`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Unit {
    pub symbol: &'static str,
    pub kind: Kind,
    /// SI value of 1 symbol (`deg`: π/180 rad).
    pub to_si: f64,
}

const DEG: f64 = PI / 180.0;

const fn unit(symbol: &'static str, kind: Kind, to_si: f64) -> Unit {
    Unit {
        symbol,
        kind,
        to_si,
    }
}

/// Every unit a session number may carry. The first of each kind is the one values of that
/// kind are written in when a message lists the choices.
pub const UNITS: &[Unit] = &[
    unit("deg", Kind::Angle, DEG),
    unit("°", Kind::Angle, DEG),
    unit("rad", Kind::Angle, 1.0),
    unit("m", Kind::Length, 1.0),
    unit("cm", Kind::Length, 0.01),
    unit("mm", Kind::Length, 0.001),
    unit("deg/s", Kind::AngularVelocity, DEG),
    unit("°/s", Kind::AngularVelocity, DEG),
    unit("rad/s", Kind::AngularVelocity, 1.0),
    unit("m/s", Kind::Velocity, 1.0),
    unit("cm/s", Kind::Velocity, 0.01),
    unit("mm/s", Kind::Velocity, 0.001),
    unit("deg/s2", Kind::AngularAcceleration, DEG),
    unit("deg/s²", Kind::AngularAcceleration, DEG),
    unit("°/s²", Kind::AngularAcceleration, DEG),
    unit("rad/s2", Kind::AngularAcceleration, 1.0),
    unit("rad/s²", Kind::AngularAcceleration, 1.0),
    unit("m/s2", Kind::Acceleration, 1.0),
    unit("m/s²", Kind::Acceleration, 1.0),
    unit("N·m", Kind::Torque, 1.0),
    unit("Nm", Kind::Torque, 1.0),
    unit("N.m", Kind::Torque, 1.0),
    unit("N", Kind::Force, 1.0),
    unit("kg", Kind::Mass, 1.0),
    unit("s", Kind::Time, 1.0),
    unit("ms", Kind::Time, 0.001),
    unit("Hz", Kind::Frequency, 1.0),
    unit("hz", Kind::Frequency, 1.0),
];

/// How values of one kind are shown: in `symbol` (`per_si` of them per SI unit), with at
/// least `decimals` decimals and at least `significant` significant digits (a torque of
/// 131.42 N·m is 131.4, one of 0.028252 N·m is 0.0283).
struct Shown {
    kind: Kind,
    symbol: &'static str,
    per_si: f64,
    decimals: i32,
    significant: i32,
}

const fn show(kind: Kind, symbol: &'static str, per_si: f64, decimals: i32, sig: i32) -> Shown {
    Shown {
        kind,
        symbol,
        per_si,
        decimals,
        significant: sig,
    }
}

/// The display rule of every kind: rotations in degrees to 0.1°, lengths to the millimetre,
/// torques and forces to 0.1 (3 significant digits below 100), masses to 10 g.
const SHOWN: &[Shown] = &[
    show(Kind::Angle, "deg", 1.0 / DEG, 1, 2),
    show(Kind::Length, "m", 1.0, 3, 3),
    show(Kind::AngularVelocity, "deg/s", 1.0 / DEG, 1, 2),
    show(Kind::Velocity, "m/s", 1.0, 3, 3),
    show(Kind::AngularAcceleration, "deg/s²", 1.0 / DEG, 1, 2),
    show(Kind::Acceleration, "m/s²", 1.0, 2, 3),
    show(Kind::Torque, "N·m", 1.0, 1, 3),
    show(Kind::Force, "N", 1.0, 1, 3),
    show(Kind::Mass, "kg", 1.0, 2, 3),
    show(Kind::Time, "s", 1.0, 3, 3),
    show(Kind::Frequency, "Hz", 1.0, 1, 3),
];

fn rule(kind: Kind) -> &'static Shown {
    // every kind has a row: tests/session_units.rs checks that each kind is shown in a unit
    // of its own (the first row, degrees, would fail that)
    SHOWN.iter().find(|s| s.kind == kind).unwrap_or(&SHOWN[0])
}

/// The unit values of `kind` are shown in (`deg` for angles).
pub fn shown_unit(kind: Kind) -> &'static str {
    rule(kind).symbol
}

/// The display value and unit of the SI value `si` of `kind`: `(57.29…, "deg")` for 1 rad.
pub fn shown(kind: Kind, si: f64) -> (f64, &'static str) {
    let r = rule(kind);
    (si * r.per_si, r.symbol)
}

/// Decimals that show `x` (already in the display unit) as the rule of `kind` asks; a value
/// that needs more than 4 decimals beyond the rule's to show is shown as zero.
fn decimals(kind: Kind, x: f64) -> usize {
    let r = rule(kind);
    let by_digits = if x == 0.0 || !x.is_finite() {
        0
    } else {
        r.significant - 1 - x.abs().log10().floor() as i32
    };
    let d = if by_digits > r.decimals + 4 {
        r.decimals
    } else {
        r.decimals.max(by_digits)
    };
    d.clamp(0, 15) as usize
}

/// `x` with `d` decimals, never `-0.0`.
pub fn fixed(x: f64, d: usize) -> String {
    let s = format!("{x:.d$}");
    match s.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => s,
    }
}

/// The SI value `si` of `kind` in its display unit, rounded as the kind's rule asks, without
/// the unit: `131.4` for a torque of 131.4213 N·m, `57.3` for an angle of 1 rad.
pub fn format_number(kind: Kind, si: f64) -> String {
    let (x, _) = shown(kind, si);
    fixed(x, decimals(kind, x))
}

/// [`format_number`] followed by the unit: `131.4 N·m`, `57.3 deg`.
pub fn format_value(kind: Kind, si: f64) -> String {
    format!("{} {}", format_number(kind, si), shown_unit(kind))
}

/// A bound written by the user, shown back: 6 significant digits, no trailing zeros.
fn format_bound(x: f64) -> String {
    let rounded: f64 = format!("{x:.5e}").parse().unwrap_or(x);
    if rounded == 0.0 {
        "0".into()
    } else {
        rounded.to_string()
    }
}

/// `value` against `[lo, hi]` (all SI, of `kind`), in the display unit:
/// `131.4 N·m not in [110, 120] N·m` or `131.4 N·m in [110, 160] N·m`. The value gets the
/// kind's rounding, and more decimals while rounding would put it on another side of a bound
/// (below, within, above) than it is.
pub fn format_check(kind: Kind, value: f64, lo: f64, hi: f64) -> String {
    let r = rule(kind);
    let (x, a, b) = (value * r.per_si, lo * r.per_si, hi * r.per_si);
    let side = |y: f64| (y >= a) as i8 + (y > b) as i8;
    let mut d = decimals(kind, x);
    let mut sx = fixed(x, d);
    while d < 15 && sx.parse::<f64>().is_ok_and(|y| side(y) != side(x)) {
        d += 1;
        sx = fixed(x, d);
    }
    let verdict = if (lo..=hi).contains(&value) {
        "in"
    } else {
        "not in"
    };
    let (sa, sb) = (format_bound(a), format_bound(b));
    format!("{sx} {} {verdict} [{sa}, {sb}] {}", r.symbol, r.symbol)
}

/// A number as written in a session: its value and the unit written after it, if any.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measure {
    pub value: f64,
    pub unit: Option<Unit>,
}

/// What a bare number (no unit written) means.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bare {
    /// The unit the workbench shows the kind in (`deg` for angles): `expect`, `set`.
    Shown,
    /// SI (rad, m): the poses of `trajectory`, as DH tables and URDF write joint values.
    Si,
}

/// Why a number with a unit is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum UnitError {
    /// Not a finite number (with or without a unit).
    #[error("'{word}' is not a number")]
    NotANumber { word: String },
    /// A unit of the wrong kind for the quantity.
    #[error("'{word}' is {}; {what} takes {expected}", found.name())]
    WrongUnit {
        word: String,
        found: Kind,
        what: String,
        expected: String,
    },
    /// A unit on a number that takes none (a gain, a ratio).
    #[error("'{word}': {what} is a plain number, without a unit")]
    Unitless { word: String, what: String },
}

/// The symbols of the units of `kind`, comma separated (`deg, °, rad`).
pub fn symbols(kind: Kind) -> String {
    UNITS
        .iter()
        .filter(|u| u.kind == kind)
        .map(|u| u.symbol)
        .collect::<Vec<_>>()
        .join(", ")
}

/// What values of `kinds` take, for a message: `deg, °, rad (bare: deg)`, joined by `or`.
pub fn accepted(kinds: &[Kind], bare: Bare) -> String {
    kinds
        .iter()
        .map(|&k| {
            let b = match bare {
                Bare::Shown => shown_unit(k),
                Bare::Si => UNITS
                    .iter()
                    .find(|u| u.kind == k && u.to_si == 1.0)
                    .map_or("", |u| u.symbol),
            };
            format!("{} ({}; a bare number is {b})", symbols(k), kind_word(k))
        })
        .collect::<Vec<_>>()
        .join(" or ")
}

/// The kind as a noun without article, for lists.
fn kind_word(kind: Kind) -> &'static str {
    let n = kind.name();
    n.strip_prefix("an ")
        .or_else(|| n.strip_prefix("a "))
        .unwrap_or(n)
}

/// Splits `word` into a number (as `number` reads it) and the unit written after it: the
/// longest symbol of [`UNITS`] that ends the word.
pub fn split_unit<T>(
    word: &str,
    number: impl Fn(&str) -> Option<T>,
) -> Result<(T, Option<Unit>), UnitError> {
    let not_a_number = || UnitError::NotANumber {
        word: word.to_string(),
    };
    if let Some(x) = number(word) {
        return Ok((x, None));
    }
    let u = UNITS
        .iter()
        .filter(|u| word.len() > u.symbol.len() && word.ends_with(u.symbol))
        .max_by_key(|u| u.symbol.len())
        .ok_or_else(not_a_number)?;
    let x = number(&word[..word.len() - u.symbol.len()]).ok_or_else(not_a_number)?;
    Ok((x, Some(*u)))
}

fn finite(w: &str) -> Option<f64> {
    w.parse::<f64>().ok().filter(|x| x.is_finite())
}

/// Reads a number with an optional unit, whose kind is checked later ([`Measure::to_si`]).
pub fn parse_measure(word: &str) -> Result<Measure, UnitError> {
    let (value, unit) = split_unit(word, finite)?;
    Ok(Measure { value, unit })
}

/// Reads a number of `kind` in SI: a written unit must be one of `kind`'s, a bare number is
/// in the unit the workbench shows (`what` names the value in an error).
pub fn parse_si(word: &str, kind: Kind, what: &str) -> Result<f64, UnitError> {
    parse_measure(word)?.to_si(word, kind, Bare::Shown, what)
}

/// Reads a plain number (a gain, a ratio): a unit is an error.
pub fn parse_plain(word: &str, what: &str) -> Result<f64, UnitError> {
    match parse_measure(word)? {
        Measure { value, unit: None } => Ok(value),
        _ => Err(UnitError::Unitless {
            word: word.to_string(),
            what: what.to_string(),
        }),
    }
}

impl Measure {
    /// The kind of the written unit, if any.
    pub fn kind(&self) -> Option<Kind> {
        self.unit.map(|u| u.kind)
    }

    /// The value in SI for a quantity of `kind` (`word` is how it was written, `what` names
    /// the quantity in an error): a written unit must be of `kind`; a bare number is in
    /// `bare`'s unit.
    pub fn to_si(&self, word: &str, kind: Kind, bare: Bare, what: &str) -> Result<f64, UnitError> {
        match (self.unit, bare) {
            (Some(u), _) if u.kind == kind => Ok(self.value * u.to_si),
            (Some(u), _) => Err(UnitError::WrongUnit {
                word: word.to_string(),
                found: u.kind,
                what: what.to_string(),
                expected: accepted(&[kind], bare),
            }),
            (None, Bare::Si) => Ok(self.value),
            (None, Bare::Shown) => Ok(self.value / rule(kind).per_si),
        }
    }

    /// The measure as it was written (`40deg`, `0.5`).
    pub fn written(&self) -> String {
        match self.unit {
            Some(u) => format!("{}{}", self.value, u.symbol),
            None => self.value.to_string(),
        }
    }
}
