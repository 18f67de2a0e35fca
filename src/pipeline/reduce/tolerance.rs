//! `--lock auto:TOL`: the tolerance as typed (`auto:2%`, `auto:1nm`) and the `--lock` values
//! split into it and the joints named.

use crate::error::Error;

/// How far a reduced model may move the outputs: their peak error over the take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tolerance {
    /// Percent of the full model's peak |τ| over the outputs (`auto:2%`).
    Percent(f64),
    /// N·m (`auto:1nm`).
    NewtonMetres(f64),
}

impl Tolerance {
    /// The tolerance in N·m for outputs whose full-model peak |τ| is `peak`.
    pub fn newton_metres(self, peak: f64) -> f64 {
        match self {
            Tolerance::Percent(p) => p / 100.0 * peak,
            Tolerance::NewtonMetres(x) => x,
        }
    }
}

impl std::fmt::Display for Tolerance {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        match self {
            Tolerance::Percent(p) => write!(f, "{p}%"),
            Tolerance::NewtonMetres(x) => write!(f, "{x}nm"),
        }
    }
}

/// What a tolerance's unit makes of its number.
type MakeTolerance = fn(f64) -> Tolerance;

/// Units a tolerance may be written in (lowercase), and what each makes of the number.
const TOLERANCE_UNITS: &[(&str, MakeTolerance)] = &[
    ("%", Tolerance::Percent),
    ("nm", Tolerance::NewtonMetres),
    ("n*m", Tolerance::NewtonMetres),
    ("n·m", Tolerance::NewtonMetres),
];

/// A `--lock` value: `auto:TOL` gives its tolerance, any other value `None` (a joint name).
///
/// Errors: `auto:` followed by anything but a number ≥ 0 with `%` or `nm`.
pub fn parse_auto(value: &str) -> Result<Option<Tolerance>, Error> {
    let Some(tol) = value.trim().strip_prefix("auto:") else {
        return Ok(None);
    };
    let bad = || {
        Error::Invalid(format!(
            "--lock {value}: expected auto:TOL with TOL the largest peak error allowed on the \
             outputs, in % of their peak (auto:2%) or in N·m (auto:1nm)"
        ))
    };
    let t = tol.trim().to_lowercase();
    let (number, make) = TOLERANCE_UNITS
        .iter()
        .find_map(|(unit, make)| t.strip_suffix(unit).map(|n| (n, make)))
        .ok_or_else(bad)?;
    let x: f64 = number.trim().parse().map_err(|_| bad())?;
    if !(x.is_finite() && x >= 0.0) {
        return Err(bad());
    }
    Ok(Some(make(x)))
}

/// The `--lock` values split into the one `auto:TOL` (if any) and the joints named.
///
/// Errors: a bad `auto:` value, or more than one.
pub fn split_lock(lock: &[String]) -> Result<(Option<Tolerance>, Vec<String>), Error> {
    let mut auto = None;
    let mut named = vec![];
    for l in lock {
        match parse_auto(l)? {
            Some(_) if auto.is_some() => {
                return Err(Error::Invalid(format!(
                    "--lock {l}: one auto:TOL at most (the joints named beside it are locked \
                     first)"
                )));
            }
            Some(t) => auto = Some(t),
            None => named.push(l.clone()),
        }
    }
    Ok((auto, named))
}
