//! `expect`: the assertions of a session, checked against the workbench.

use super::super::SessionError;
use super::super::command::{Expectation, Quantity, Statistic};
use super::super::units::{self, Bare, Kind, Measure};
use super::{Outcome, Workbench, angle_series, err, is_anatomical, statistic, torque_series};

impl Workbench {
    /// Checks one expectation (results computed first when it needs them and they are stale).
    pub(super) fn expect(&mut self, e: &Expectation) -> Result<Outcome, SessionError> {
        let fail = |m: String| Err(SessionError::Expect(m));
        let within = |x: f64, lo: f64, hi: f64| (lo..=hi).contains(&x);
        let count = |n: usize| Some((n as f64, ""));
        let (msg, found) = match e {
            Expectation::Nv(n) | Expectation::Nq(n) => {
                let r = self.ensure_results()?;
                let (what, got) = match e {
                    Expectation::Nv(_) => ("nv", r.model.nv),
                    _ => ("nq", r.model.nq),
                };
                if got != *n {
                    return fail(format!("{what} is {got}, expected {n}"));
                }
                (format!("{what} = {n}"), count(got))
            }
            Expectation::Frames(n) => {
                let got = self.frames();
                if got != *n {
                    return fail(format!("the take has {got} frames, expected {n}"));
                }
                (format!("frames = {n}"), count(got))
            }
            Expectation::Frame(n) => {
                if self.frame != *n {
                    return fail(format!("the current frame is {}, expected {n}", self.frame));
                }
                (format!("frame = {n}"), count(self.frame))
            }
            Expectation::Selected(s) => {
                if self.selection.as_deref() != Some(s.as_str()) {
                    return fail(format!(
                        "selected is {}, expected {s}",
                        self.selection.as_deref().unwrap_or("nothing")
                    ));
                }
                (format!("selected = {s}"), None)
            }
            Expectation::Mass { lo, hi } => {
                let m = self.ensure_results()?.model.total_mass();
                let check = units::format_check(Kind::Mass, m, *lo, *hi);
                if !within(m, *lo, *hi) {
                    return fail(format!("total mass {check}"));
                }
                (format!("mass {check}"), Some(units::shown(Kind::Mass, m)))
            }
            Expectation::Stat {
                stat,
                coord,
                quantity,
                lo,
                hi,
            } => {
                let r = self.ensure_results()?;
                let table = match quantity {
                    Quantity::Angle | Quantity::Velocity => &r.v,
                    Quantity::Acceleration => &r.a,
                    Quantity::Torque => &r.tau,
                };
                // an anatomical axis (`knee_l:flexion`) has an angle and a moment
                let anatomical = is_anatomical(&r, coord);
                if anatomical && matches!(quantity, Quantity::Velocity | Quantity::Acceleration) {
                    return Err(err(format!(
                        "{coord} is an anatomical axis: it has an angle and a moment (torque), \
                         not a {}",
                        quantity.name()
                    )));
                }
                let j = if anatomical {
                    0
                } else {
                    table.col_index(coord).ok_or_else(|| {
                        err(format!(
                            "no coordinate '{coord}' (expected e.g. {})",
                            table.names.first().map_or("", String::as_str)
                        ))
                    })?
                };
                // the coordinate's own unit: a rotation's angle in deg, a translation's in m
                let angular = anatomical
                    || r.model
                        .v_index(coord)
                        .is_some_and(|k| r.model.is_angular(k));
                let kind = quantity.kind(angular);
                let what = format!(
                    "the {} of {coord} (a {})",
                    quantity.name(),
                    if angular { "rotation" } else { "translation" }
                );
                let bound = |m: &Measure| {
                    m.to_si(&m.written(), kind, Bare::Shown, &what)
                        .map_err(|e| err(e.to_string()))
                };
                let (lo, hi) = (bound(lo)?, bound(hi)?);
                if hi < lo {
                    return Err(err(format!(
                        "between {} {}: HI is below LO",
                        units::format_value(kind, lo),
                        units::format_value(kind, hi)
                    )));
                }
                // angles of ball and free joints: rotation-vector components (angle_series)
                let x = match quantity {
                    Quantity::Angle => angle_series(&r, coord)
                        .ok_or_else(|| err(format!("no angle for '{coord}'")))?,
                    Quantity::Torque if anatomical => torque_series(&r, coord)
                        .ok_or_else(|| err(format!("no moment for '{coord}'")))?,
                    _ => table.column(j),
                };
                // accelerations and torques: never of the frames left out (issue 14)
                let forces = matches!(quantity, Quantity::Acceleration | Quantity::Torque);
                let quoted: Vec<f64> = x
                    .iter()
                    .enumerate()
                    .filter(|&(k, _)| !forces || r.quoted(k))
                    .map(|(_, v)| *v)
                    .collect();
                let value = match stat {
                    Statistic::Now => x.get(self.frame).copied().unwrap_or(0.0),
                    _ if quoted.is_empty() => {
                        return Err(err(format!(
                            "{coord}: every frame is left out of the quoted figures (edge                              frames or residuals beyond the feet; `set edges include` quotes                              the edges)"
                        )));
                    }
                    _ => statistic(*stat, &quoted),
                };
                let name = format!(
                    "{} {coord} {}",
                    format!("{stat:?}").to_lowercase(),
                    quantity.name()
                );
                let check = units::format_check(kind, value, lo, hi);
                if !within(value, lo, hi) {
                    return fail(format!("{name} {check}"));
                }
                (format!("{name} {check}"), Some(units::shown(kind, value)))
            }
            Expectation::MessageContains(text) => {
                let last = self
                    .messages
                    .iter()
                    .rev()
                    .find(|m| !m.starts_with("ok: "))
                    .map_or("", String::as_str);
                if !last.contains(text.as_str()) {
                    return fail(format!(
                        "the last message is '{last}', expected it to contain '{text}'"
                    ));
                }
                (format!("message contains '{text}'"), None)
            }
            Expectation::ScreenContains(_) => {
                return Err(err("expect screen needs a front end (the TUI)"));
            }
        };
        let mut outcome = self.say(format!("ok: {msg}"));
        outcome.value = found;
        Ok(outcome)
    }
}
