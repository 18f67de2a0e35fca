//! What a take command decides before it computes, shared by every front end (the command
//! line, the Python module): whether `id` and `anatomy` reduce the residuals, the joint model
//! `anatomy` defaults to, and `simulate`'s settings from its flags and a scene's gains.

use super::{PerJoint, SimSettings, TakeOptions, parse_per_joint};
use crate::error::Error;
use crate::io::scene::Gains;
use crate::model::bvh::JointModel;

/// Whether to reduce the residuals: `consistent` (`on`/`off`), else `default` (on for
/// `anatomy`, off for `id`). `--consistent` is refused on a take without ground contact: it
/// would be accepted and ignored. (`--json` is not: without contact it says so, with
/// `"contact": "none"` and why, [`no_contact_json`].)
pub fn reduce_residuals(
    consistent: Option<&str>,
    contact: bool,
    default: bool,
) -> Result<bool, Error> {
    let on = match consistent.map(str::trim) {
        None => default,
        Some("on") => true,
        Some("off") => false,
        Some(other) => {
            return Err(Error::Invalid(format!(
                "--consistent {other}: expected on or off"
            )));
        }
    };
    if consistent.is_some() && !contact {
        return Err(Error::Invalid(
            "--consistent has no effect without ground contact (contact none, or auto on a \
             take that never stands on a floor): residuals against the ground reactions need \
             --contact feet; remove it or add --contact feet"
                .into(),
        ));
    }
    Ok(on && contact)
}

/// `anatomy --json` on a take without ground contact: no consistency summary to print, so the
/// JSON says why (`contact auto`'s reason when it settled on none, else the user's `--contact
/// none`): `{"contact": "none", "meets": null, "why": …}`.
pub fn no_contact_json(take: &super::Take) -> serde_json::Value {
    let why = super::contact::auto_chose_none(take)
        .unwrap_or_else(|| "contact none: no ground reactions, so no residuals to reduce".into());
    serde_json::json!({ "contact": "none", "meets": null, "why": why })
}

/// `anatomy`'s joint model when neither a scene nor `--joints` chose one: ball (no gimbal
/// lock, and smoothing on rotations, not on one Euler order's angles).
pub fn anatomy_options(mut o: TakeOptions, joints_chosen: bool) -> TakeOptions {
    if !joints_chosen {
        o.joints = JointModel::Ball;
    }
    o
}

/// `simulate`'s flags as typed: `--integrator`, `--dt`, `--kp`/`--kv` (`X` or `JOINT=X`,
/// over the scene's gains, else 400 1/s² and 40 1/s), `--mass-error`, `--duration`.
#[derive(Debug, Clone, PartialEq)]
pub struct SimFlags<'a> {
    pub integrator: &'a str,
    pub dt: f64,
    pub kp: &'a [String],
    pub kv: &'a [String],
    pub mass_error: f64,
    pub duration_s: Option<f64>,
}

impl Default for SimFlags<'_> {
    /// The command line's defaults: RK4 at 1 ms, no mass error, the whole take.
    fn default() -> Self {
        Self {
            integrator: "rk4",
            dt: 0.001,
            kp: &[],
            kv: &[],
            mass_error: 0.0,
            duration_s: None,
        }
    }
}

/// [`SimSettings`] from `simulate`'s flags over a scene's gains.
pub fn sim_settings(flags: &SimFlags, scene: Option<Gains>) -> Result<SimSettings, Error> {
    let (mut kp, mut kv) = match scene {
        Some(g) => (g.kp, g.kv),
        None => (PerJoint::all(400.0), PerJoint::all(40.0)),
    };
    parse_per_joint("kp", flags.kp, &mut kp, "1/s²", "400 or LeftLeg=900")?;
    parse_per_joint("kv", flags.kv, &mut kv, "1/s", "40 or LeftLeg=60")?;
    SimSettings::parse(
        flags.integrator,
        flags.dt,
        &kp,
        &kv,
        flags.mass_error,
        flags.duration_s,
    )
}
