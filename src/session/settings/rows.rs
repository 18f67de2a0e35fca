//! The rows of [`SETTINGS`](super::SETTINGS), and the checks, panel values and steps of
//! those longer than a line.

use super::super::SessionError;
use super::super::units::Kind;
use super::super::workbench::{Overlay, Workbench};
use super::{Arg, PanelRow, Recompute, Setting, Subject};
use crate::motion::smooth::SmoothSpec;
use crate::pipeline::PerJoint;
use crate::report::motor;
use std::path::Path;

/// The integrators `set integrator` takes.
pub const INTEGRATORS: [&str; 4] = ["euler", "semi-implicit", "rk4", "dopri5"];

// panel values and steps

/// A number stepped by `by`, not below `min`.
fn stepped(value: &str, dir: f64, by: f64, min: f64) -> Option<String> {
    let x = value.parse::<f64>().ok()?;
    Some(format!("{}", (x + by * dir).max(min)))
}

/// The mass (kg) the latest results give joint `joint`: its own link's, or auto.
fn show_link_mass(wb: &Workbench, joint: &str) -> Option<String> {
    if joint.is_empty() {
        return None;
    }
    Some(match wb.params.take.body.link_mass.get(joint) {
        Some(m) => format!("{m}"),
        None => match wb.latest_results() {
            Some(r) => {
                // the mass sits on the last body of the joint's chain
                let m: f64 = r
                    .model
                    .body_names
                    .iter()
                    .zip(&r.model.inertia)
                    .zip(&r.model.joint_names)
                    .filter(|((n, _), jn)| {
                        *jn == joint || n.rsplit_once('.').map_or(n.as_str(), |(j, _)| j) == joint
                    })
                    .map(|(x, _)| x)
                    .map(|(_, i)| i.mass)
                    .sum();
                format!("{}", (m * 1000.0).round() / 1000.0)
            }
            None => "auto".into(),
        },
    })
}

/// A drive field of the selected coordinate.
fn show_motor(wb: &Workbench, coord: &str, field: &str) -> Option<String> {
    if coord.is_empty() {
        return None;
    }
    let m = wb.params.motor_of(coord);
    let value = match field {
        "gear" => m.gear_ratio,
        "km" => m.km_nm_per_a,
        _ => m.eta(),
    };
    Some(format!("{value}"))
}

/// Gear ratio and Km by 5 % steps.
fn step_ratio(_: &Workbench, value: &str, dir: f64) -> Option<String> {
    let x = value.parse::<f64>().ok()?;
    let f = if dir > 0.0 { 1.05 } else { 1.0 / 1.05 };
    Some(format!("{}", (x * f * 1e4).round() / 1e4))
}

/// Efficiency by 0.05 in (0, 1].
fn step_efficiency(_: &Workbench, value: &str, dir: f64) -> Option<String> {
    let x = value.parse::<f64>().ok()?;
    Some(format!(
        "{}",
        ((x + 0.05 * dir).clamp(0.05, 1.0) * 100.0).round() / 100.0
    ))
}

/// The smoothing one step wider (`dir` -1) or narrower; `auto` steps from the default it
/// stands for.
fn step_smooth(wb: &Workbench, _: &str, dir: f64) -> Option<String> {
    let s = wb.params.take.smooth.unwrap_or(SmoothSpec::Butterworth {
        cutoff_hz: crate::pipeline::DEFAULT_CUTOFF_HZ,
        order: 2,
    });
    Some(match s {
        SmoothSpec::None if dir > 0.0 => "gaussian:0.005".into(),
        SmoothSpec::None => return None,
        SmoothSpec::Gaussian { sigma_s } => {
            let w = ((sigma_s + 0.005 * dir) * 1000.0).round() / 1000.0;
            if w <= 0.0 {
                "none".into()
            } else {
                format!("gaussian:{w}")
            }
        }
        // a wider kernel is a lower cutoff; the order is kept
        SmoothSpec::Butterworth { cutoff_hz, order } => SmoothSpec::Butterworth {
            cutoff_hz: (cutoff_hz - dir).max(1.0),
            order,
        }
        .to_string(),
    })
}

// the rows' apply functions (those longer than a line)

fn set_stature(wb: &mut Workbench, a: &Arg) -> Result<(), SessionError> {
    wb.params.take.stature_m = if a.auto() {
        None
    } else {
        let s = a.num(Some(Kind::Length), "a stature in m")?;
        crate::io::bvh::check_given_stature(s).map_err(|e| a.error(e))?;
        Some(s)
    };
    Ok(())
}

fn set_smooth(wb: &mut Workbench, a: &Arg) -> Result<(), SessionError> {
    let spec = crate::pipeline::parse_smooth(a.value).map_err(|e| a.error(e))?;
    // a filter the active take cannot take is refused now, with nothing changed
    // (it stayed in the panel, marked stale, after the recompute failed)
    let dt = wb.take().and_then(|t| t.bvh()).map(|b| b.frame_time);
    if let (Some(s), Some(dt)) = (spec, dt) {
        crate::motion::smooth::Smoother::new(s, dt).map_err(|e| a.error(e))?;
    }
    wb.params.take.smooth = spec;
    Ok(())
}

fn set_catalogue(wb: &mut Workbench, a: &Arg) -> Result<(), SessionError> {
    // read now, so a bad file fails here and not at the report
    if a.auto() {
        wb.motor_classes = motor::default_catalogue()?;
        wb.params.motor_catalogue = None;
    } else {
        let file = wb.in_path(Path::new(a.value));
        wb.motor_classes = motor::read_catalogue(&file)?;
        wb.params.motor_catalogue = Some(file);
    }
    Ok(())
}

/// A diagonal gain of one joint or coordinate (`kp.LeftLeg`, `kv.j2`).
fn set_joint_gain(wb: &mut Workbench, a: &Arg) -> Result<(), SessionError> {
    let (which, name) = (&a.key[..2], a.subject);
    let x = a.num(None, "a gain (1/s² for kp, 1/s for kv)")?;
    if let Some(m) = wb.model_to_check() {
        let mut one = PerJoint::default();
        one.joints.insert(name.to_string(), x);
        crate::pipeline::per_coordinate(&m, &one, 0, which).map_err(|e| a.error(e))?;
    } else if let Some(b) = wb.take().and_then(|t| t.bvh()) {
        // no model yet: a joint of the take, or one of its coordinates
        if !super::super::workbench::names_a_joint(b, name) {
            return Err(a.error(format!(
                "the take has no joint '{name}' (expected e.g. {})",
                b.joints.get(1).map_or("", |j| j.name.as_str())
            )));
        }
    }
    let p = &mut wb.params;
    let g = if which == "kp" { &mut p.kp } else { &mut p.kv };
    g.joints.insert(name.to_string(), x);
    Ok(())
}

/// A drive's Km, gear ratio or efficiency (`motor.km`, `motor.j2.gear`): positive, η ≤ 1.
fn motor_value(a: &Arg) -> Result<f64, SessionError> {
    let x = a.num(None, "a positive number")?;
    let efficiency = a.key.ends_with(".efficiency");
    if x <= 0.0 || (efficiency && x > 1.0) {
        return Err(a.error(format!(
            "{} is out of range (Km, N > 0; 0 < η ≤ 1)",
            a.value
        )));
    }
    Ok(x)
}

/// The override of one coordinate's drive, checked against the model when there is one.
fn motor_override<'w>(
    wb: &'w mut Workbench,
    a: &Arg,
) -> Result<&'w mut super::super::engine::MotorOverride, SessionError> {
    let joint = a.subject;
    if let Some(m) = wb.model_to_check().filter(|m| m.v_index(joint).is_none()) {
        return Err(a.error(format!(
            "no coordinate '{joint}' (expected e.g. {})",
            m.v_names.first().map_or("", String::as_str)
        )));
    }
    Ok(wb.params.motor_joint.entry(joint.to_string()).or_default())
}

fn set_link_mass(wb: &mut Workbench, a: &Arg) -> Result<(), SessionError> {
    let link = a.subject;
    if let Some(t) = wb.take()
        && !t.joint_tree().iter().any(|(n, _)| n == link)
    {
        return Err(a.error(format!("no joint called '{link}'")));
    }
    if wb.take().is_some_and(|t| t.robot().is_some()) {
        return Err(a.error("a robot's masses are those of its DH table or URDF"));
    }
    let m = a.num(Some(Kind::Mass), "a mass in kg")?;
    wb.params.take.body.link_mass.insert(link.to_string(), m);
    Ok(())
}

const fn on_panel(
    human: Option<u8>,
    robot: Option<u8>,
    subject: Subject,
    unit: &'static str,
    show: fn(&Workbench, &str) -> Option<String>,
    step: fn(&Workbench, &str, f64) -> Option<String>,
) -> Option<PanelRow> {
    Some(PanelRow {
        human,
        robot,
        subject,
        unit,
        show,
        step,
    })
}

use Recompute as R;

/// Every `set` key. Plain keys are found before patterns ([`find`]).
pub static SETTINGS: &[Setting] = &[
    Setting {
        name: "body.mass",
        value: "KG",
        help: "the body mass (kg; a unit may be written: 80kg)",
        values: &[],
        recompute: R::Dynamics,
        apply: |wb, a| {
            wb.params.take.body.mass_kg = a.positive(Some(Kind::Mass), "a positive mass in kg")?;
            Ok(())
        },
        panel: on_panel(
            Some(0),
            None,
            Subject::None,
            " kg",
            |wb, _| Some(format!("{}", wb.params.take.body.mass_kg)),
            |_, v, dir| stepped(v, dir, 5.0, 5.0),
        ),
    },
    Setting {
        name: "body.sex",
        value: "male|female",
        help: "the sex of the segment tables",
        values: &["male", "female"],
        recompute: R::Dynamics,
        apply: |wb, a| {
            wb.params.take.body.sex = a.parsed()?;
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "body.segments",
        value: "regression|fractions",
        help: "the segment masses' table (as --segments)",
        values: &["regression", "fractions"],
        recompute: R::Dynamics,
        apply: |wb, a| {
            wb.params.take.body.segments = a.parsed()?;
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "unit",
        value: "UNIT|auto",
        help: "the take's length unit (as --unit); clears a given stature",
        values: &["auto", "m", "dm", "cm", "mm", "in", "cmu"],
        recompute: R::Take,
        apply: |wb, a| {
            wb.params.take.unit = a.parsed_or_auto()?;
            wb.params.take.stature_m = None;
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "stature",
        value: "M|auto",
        help: "the subject's stature, which scales the take (as --stature)",
        values: &["auto"],
        recompute: R::Take,
        apply: set_stature,
        panel: None,
    },
    Setting {
        name: "up",
        value: "x|y|z|auto",
        help: "the take's up axis (as --up)",
        values: &["auto", "x", "y", "z"],
        recompute: R::Take,
        apply: |wb, a| {
            wb.params.take.up = a.parsed_or_auto()?;
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "positions",
        value: "add|replace|auto",
        help: "what position channels mean (as --positions)",
        values: &["auto", "add", "replace"],
        recompute: R::Take,
        apply: |wb, a| {
            wb.params.take.positions = a.parsed()?;
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "subtree",
        value: "JOINT|none",
        help: "keep only the subtree of a joint",
        values: &["none"],
        recompute: R::Take,
        apply: |wb, a| {
            wb.params.take.subtree = (!a.auto()).then(|| a.value.to_string());
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "joints",
        value: "euler|ball",
        help: "the joint model",
        values: &["euler", "ball"],
        recompute: R::Take,
        apply: |wb, a| {
            wb.params.take.joints = a.parsed()?;
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "smooth",
        value: "none|gaussian:W|butterworth:F[hz][:ORDER]",
        help: "the smoothing of the joint angles (W in s, F in Hz)",
        values: &["none", "gaussian:0.02", "butterworth:6hz"],
        recompute: R::Smoothing,
        apply: set_smooth,
        panel: on_panel(
            Some(1),
            None,
            Subject::None,
            "",
            |wb, _| {
                Some(
                    wb.params
                        .take
                        .smooth
                        .map_or("auto".into(), |s| s.to_string()),
                )
            },
            step_smooth,
        ),
    },
    Setting {
        name: "contact",
        value: "auto|feet|none",
        help: "the ground contact model",
        values: &["auto", "feet", "none"],
        recompute: R::Dynamics,
        apply: |wb, a| {
            wb.params.take.contact = a.parsed()?;
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "consistent",
        value: "auto|on|off",
        help: "residual reduction with ground contact (as --consistent)",
        values: &["auto", "on", "off"],
        recompute: R::Dynamics,
        apply: |wb, a| {
            wb.params.consistent =
                [None, Some(true), Some(false)][a.one_of(&["auto", "on", "off"])?];
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "edges",
        value: "exclude|include",
        help: "whether the frames within the smoothing's reach of the ends are quoted",
        values: &["exclude", "include"],
        recompute: R::Dynamics,
        apply: |wb, a| {
            wb.params.include_edges = a.one_of(&["exclude", "include"])? == 1;
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "overlay",
        value: "mirror|angle|feet|weights|sim|none",
        help: "what the curves add: the mirror joint, the moment against the angle, both feet's \
               vertical ground forces, the last compare weights, the last run sim's tracking \
               error (a view setting: nothing is recomputed)",
        values: Overlay::WORDS,
        recompute: R::Nothing,
        apply: |wb, a| {
            wb.overlay = Overlay::ALL[a.one_of(Overlay::WORDS)?];
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "keep_first_frame",
        value: "true|false",
        help: "keep a rest pose stored as frame 0 (for the takes loaded after it)",
        values: &["true", "false"],
        recompute: R::Nothing,
        apply: |wb, a| {
            wb.params.take.keep_first_frame = a.parsed::<bool>()?;
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "joint_translations",
        value: "weld|keep",
        help: "position channels below the root held at their mean, or coordinates",
        values: &["weld", "keep"],
        recompute: R::Take,
        apply: |wb, a| {
            wb.params.take.joint_translations = a.parsed()?;
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "bvh_style",
        value: "portable|as-read",
        help: "BVH written by export bvh: portable (every reader reads it alike) or the input's \
               channel layout",
        values: &["portable", "as-read"],
        recompute: R::Nothing,
        apply: |wb, a| {
            wb.params.bvh_style = a.parsed()?;
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "kp",
        value: "X",
        help: "every coordinate's position gain of the simulation (1/s²)",
        values: &[],
        recompute: R::Simulation,
        apply: |wb, a| {
            wb.params.kp.all = a.num(None, "a gain in 1/s²")?;
            Ok(())
        },
        panel: on_panel(
            Some(4),
            Some(3),
            Subject::None,
            "",
            |wb, _| Some(format!("{}", wb.params.kp.all)),
            |_, v, dir| stepped(v, dir, 50.0, 0.0),
        ),
    },
    Setting {
        name: "kv",
        value: "X",
        help: "every coordinate's velocity gain of the simulation (1/s)",
        values: &[],
        recompute: R::Simulation,
        apply: |wb, a| {
            wb.params.kv.all = a.num(None, "a gain in 1/s")?;
            Ok(())
        },
        panel: on_panel(
            Some(5),
            Some(4),
            Subject::None,
            "",
            |wb, _| Some(format!("{}", wb.params.kv.all)),
            |_, v, dir| stepped(v, dir, 5.0, 0.0),
        ),
    },
    Setting {
        name: "kp.<joint>",
        value: "X",
        help: "one joint's or coordinate's position gain (1/s²)",
        values: &[],
        recompute: R::Simulation,
        apply: set_joint_gain,
        panel: None,
    },
    Setting {
        name: "kv.<joint>",
        value: "X",
        help: "one joint's or coordinate's velocity gain (1/s)",
        values: &[],
        recompute: R::Simulation,
        apply: set_joint_gain,
        panel: None,
    },
    Setting {
        name: "integrator",
        value: "euler|semi-implicit|rk4|dopri5",
        help: "the simulation's integrator",
        values: &INTEGRATORS,
        recompute: R::Simulation,
        apply: |wb, a| {
            if !INTEGRATORS.contains(&a.value) {
                return Err(a.error(format!(
                    "expected one of {}, found '{}'",
                    INTEGRATORS.join(", "),
                    a.value
                )));
            }
            wb.params.integrator = a.value.to_string();
            Ok(())
        },
        panel: on_panel(
            Some(6),
            Some(5),
            Subject::None,
            "",
            |wb, _| Some(wb.params.integrator.clone()),
            |_, v, dir| {
                let i = INTEGRATORS.iter().position(|x| *x == v).unwrap_or(2);
                Some(INTEGRATORS[(i + if dir > 0.0 { 1 } else { 3 }) % 4].to_string())
            },
        ),
    },
    Setting {
        name: "dt",
        value: "S",
        help: "the simulation's step (s)",
        values: &[],
        recompute: R::Simulation,
        apply: |wb, a| {
            wb.params.dt = a.positive(Some(Kind::Time), "a positive step in seconds")?;
            Ok(())
        },
        panel: on_panel(
            Some(7),
            Some(6),
            Subject::None,
            " s",
            |wb, _| Some(format!("{}", wb.params.dt)),
            |_, v, dir| {
                let d = v.parse::<f64>().ok()?;
                Some(format!("{}", if dir > 0.0 { d * 2.0 } else { d / 2.0 }))
            },
        ),
    },
    Setting {
        name: "link.<name>.mass",
        value: "KG",
        help: "one link's mass (kg), instead of the segment table's",
        values: &[],
        recompute: R::Dynamics,
        apply: set_link_mass,
        panel: on_panel(
            Some(3),
            None,
            Subject::Joint,
            " kg",
            show_link_mass,
            |_, v, dir| {
                let m = v.parse::<f64>().ok()?;
                Some(format!(
                    "{}",
                    ((m + 0.5 * dir).max(0.0) * 1000.0).round() / 1000.0
                ))
            },
        ),
    },
    Setting {
        name: "lock",
        value: "J1,J2,…|none",
        help: "joints welded in their mean pose",
        values: &["none"],
        recompute: R::Take,
        apply: |wb, a| {
            wb.params.take.lock = a
                .value
                .split([',', ' '])
                .filter(|s| !s.is_empty() && *s != "none")
                .map(str::to_string)
                .collect();
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "blend.window",
        value: "S",
        help: "the default blend window (s)",
        values: &[],
        recompute: R::Nothing,
        apply: |wb, a| {
            wb.params.blend_window = a.num(Some(Kind::Time), "a window length in seconds")?;
            Ok(())
        },
        panel: on_panel(
            Some(2),
            None,
            Subject::None,
            " s",
            |wb, _| Some(format!("{}", wb.params.blend_window)),
            |_, v, dir| {
                let w = v.parse::<f64>().ok()?;
                Some(format!(
                    "{}",
                    ((w + 0.1 * dir).max(0.1) * 10.0).round() / 10.0
                ))
            },
        ),
    },
    Setting {
        name: "motor.km",
        value: "X",
        help: "every drive's torque constant Km (N·m/A)",
        values: &[],
        recompute: R::Nothing,
        apply: |wb, a| {
            wb.params.motor.km_nm_per_a = motor_value(a)?;
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "motor.gear",
        value: "X",
        help: "every drive's gear ratio N (motor turns per joint turn)",
        values: &[],
        recompute: R::Nothing,
        apply: |wb, a| {
            wb.params.motor.gear_ratio = motor_value(a)?;
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "motor.efficiency",
        value: "X",
        help: "every drive's efficiency η in (0, 1]",
        values: &[],
        recompute: R::Nothing,
        apply: |wb, a| {
            wb.params.motor.efficiency = Some(motor_value(a)?);
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "motor.rotor_inertia",
        value: "X",
        help: "every motor's rotor inertia J_m (kg·m², motor shaft; 0: none): report motor adds \
               the reflected term J_m·N²·q̈ to the torque the motor gives",
        values: &[],
        recompute: R::Nothing,
        apply: |wb, a| {
            // a.num without a unit table: a finite number ≥ 0, else an error saying so
            wb.params.motor.rotor_inertia_kg_m2 = a.num(None, "a rotor inertia in kg·m²")?;
            Ok(())
        },
        panel: None,
    },
    Setting {
        name: "motor.<joint>.km",
        value: "X",
        help: "one coordinate's Km (N·m/A)",
        values: &[],
        recompute: R::Nothing,
        apply: |wb, a| {
            let x = motor_value(a)?;
            motor_override(wb, a)?.km = Some(x);
            Ok(())
        },
        panel: on_panel(
            None,
            Some(1),
            Subject::Selection,
            " N·m/A",
            |wb, c| show_motor(wb, c, "km"),
            step_ratio,
        ),
    },
    Setting {
        name: "motor.<joint>.gear",
        value: "X",
        help: "one coordinate's gear ratio",
        values: &[],
        recompute: R::Nothing,
        apply: |wb, a| {
            let x = motor_value(a)?;
            motor_override(wb, a)?.gear = Some(x);
            Ok(())
        },
        panel: on_panel(
            None,
            Some(0),
            Subject::Selection,
            "",
            |wb, c| show_motor(wb, c, "gear"),
            step_ratio,
        ),
    },
    Setting {
        name: "motor.<joint>.efficiency",
        value: "X",
        help: "one coordinate's efficiency in (0, 1]",
        values: &[],
        recompute: R::Nothing,
        apply: |wb, a| {
            let x = motor_value(a)?;
            motor_override(wb, a)?.efficiency = Some(x);
            Ok(())
        },
        panel: on_panel(
            None,
            Some(2),
            Subject::Selection,
            "",
            |wb, c| show_motor(wb, c, "efficiency"),
            step_efficiency,
        ),
    },
    Setting {
        name: "motor.catalogue",
        value: "PATH|auto",
        help: "the catalogue of motor classes (TOML, as data/motor_classes.toml)",
        values: &["auto"],
        recompute: R::Nothing,
        apply: set_catalogue,
        panel: None,
    },
];
