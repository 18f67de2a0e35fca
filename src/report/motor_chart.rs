//! The motor report's chart (`report motor PATH.svg|png`): torque, speed ω, driving and
//! regenerating power, motor current, the reflected rotor inertia torque and the torque–speed
//! path against the class envelopes, over the sizing table ([`super::motor`] sizes,
//! [`super::motor_duty`] the duty).

use super::motor::{JointLoad, JointMotion, MotorClass, MotorSpec, class_name, motor_current};
use super::motor_duty as duty;
use crate::error::Error;
use crate::report::chart::{ImageFormat, Panel, Series, Table, fmt_value, stacked_chart};
use crate::report::knee::check_series;

/// Torque, speed, driving and regenerating power, motor current (with `specs[k]` for
/// `joints[k]`), the reflected rotor inertia torque (when a spec gives a rotor inertia) and the
/// torque–speed panel, followed by the sizing table of `loads`.
pub fn motor_svg(
    joints: &[JointMotion],
    specs: &[MotorSpec],
    loads: &[JointLoad],
) -> Result<String, Error> {
    let bytes = motor_chart(joints, specs, loads, &[], None, ImageFormat::Svg)?;
    String::from_utf8(bytes).map_err(|e| Error::Invalid(format!("chart: SVG is not UTF-8: {e}")))
}

/// [`motor_svg`] as SVG or PNG bytes, with the drive parameters each joint was sized with
/// under the sizing table (gear `N`, `Km`, efficiency `η`; a value is followed by `(default)`
/// where `defaults[k]` says joint `k`'s `[gear, Km, η]` was not set) and `caption` (the
/// figure's context) under it all.
pub fn motor_chart(
    joints: &[JointMotion],
    specs: &[MotorSpec],
    loads: &[JointLoad],
    defaults: &[[bool; 3]],
    caption: Option<&str>,
    format: ImageFormat,
) -> Result<Vec<u8>, Error> {
    check_input(joints, specs, loads)?;
    let curves = |f: &dyn Fn(&JointMotion) -> Vec<f64>| -> Vec<Series> {
        joints
            .iter()
            .map(|m| Series::new(m.joint.clone(), m.t.clone(), f(m)))
            .collect()
    };
    let torque = curves(&|m| m.tau.clone());
    let speed = curves(&|m| m.qd.clone());
    let power = power_series(joints);
    // the motor's torque: the joint's through the gear plus the rotor's own inertia
    let rotor: Vec<Vec<f64>> = (joints.iter().zip(specs))
        .map(|(m, s)| duty::rotor_torque(s.rotor_inertia_kg_m2, s.gear_ratio, &m.qdd))
        .collect();
    let geared: Vec<Vec<f64>> = (joints.iter().zip(specs).zip(&rotor))
        .map(|((m, s), r)| duty::geared_torque(&m.tau, r, s.eta()))
        .collect();
    let current: Vec<Series> = (joints.iter().zip(specs).zip(&geared))
        .map(|((m, s), g)| {
            let i = g.iter().map(|t| motor_current(*t, s)).collect();
            Series::new(m.joint.clone(), m.t.clone(), i)
        })
        .collect();
    let rotor_curves: Vec<Series> = (joints.iter().zip(&rotor))
        .map(|(m, r)| Series::new(m.joint.clone(), m.t.clone(), r.clone()))
        .collect();
    let torque_speed = torque_speed_series(joints, specs, loads, &geared);
    let panel = |title, y_label, series| Panel {
        title,
        x_label: "time (s)",
        y_label,
        series,
        mark_min_max: true,
        shaded: &[],
        shaded_label: "",
        bands: &[],
    };
    let table = sizing_table(joints, specs, loads, defaults);
    let mut panels = vec![
        panel("Joint torque", "torque (N·m)", &torque),
        panel("Joint speed ω", "speed (rad/s)", &speed),
        Panel {
            mark_min_max: false,
            ..panel(
                "Joint power τ·ω: driving (> 0) and regenerating (< 0)",
                "power (W)",
                &power,
            )
        },
        panel("Motor current I = τ_m/Km", "current (A)", &current),
    ];
    if specs.iter().any(|s| s.rotor_inertia_kg_m2 > 0.0) {
        panels.push(panel(
            "Reflected rotor inertia J_m·N²·α (α: joint acceleration)",
            "torque (N·m)",
            &rotor_curves,
        ));
    }
    panels.push(Panel {
        x_label: "motor speed |ω_m| (rad/s)",
        mark_min_max: false,
        ..panel(
            "Torque–speed on the motor shaft against the class's envelope",
            "motor torque |τ_m| (N·m)",
            &torque_speed,
        )
    });
    stacked_chart(&panels, Some(&table), caption, format)
}

/// The torque–speed panel's series: each joint's path `(|ω_m|, |τ_m|)` over the take, the
/// peak line and continuous limit of every class chosen (once each), and the frames beyond
/// their joint's envelope as dots.
fn torque_speed_series(
    joints: &[JointMotion],
    specs: &[MotorSpec],
    loads: &[JointLoad],
    geared: &[Vec<f64>],
) -> Vec<Series> {
    let mut out = Vec::new();
    let (mut bx, mut by) = (vec![], vec![]);
    let mut classes: Vec<&MotorClass> = vec![];
    for (((m, s), l), g) in joints.iter().zip(specs).zip(loads).zip(geared) {
        let reduce = s.gear_ratio * s.eta();
        let w: Vec<f64> = m.qd.iter().map(|q| (q * s.gear_ratio).abs()).collect();
        let t: Vec<f64> = g.iter().map(|x| (x / reduce).abs()).collect();
        if let Some(c) = &l.class {
            if let Some(e) = duty::Envelope::of(c) {
                for (k, over) in duty::beyond(&e, &w, &t).into_iter().enumerate() {
                    if over {
                        bx.push(w[k]);
                        by.push(t[k]);
                    }
                }
            }
            if !classes.iter().any(|k| k.name == c.name) {
                classes.push(c);
            }
        }
        out.push(Series::new(m.joint.clone(), w, t));
    }
    for c in classes {
        let Some(e) = duty::Envelope::of(c) else {
            continue;
        };
        let line = |name: &str, pts: [(f64, f64); 2]| {
            Series::new(
                format!("{} {name}", c.name),
                pts.iter().map(|p| p.0).collect(),
                pts.iter().map(|p| p.1).collect(),
            )
        };
        out.push(line("peak", e.peak_line()));
        out.push(line("rated", e.continuous_line()));
    }
    if !bx.is_empty() {
        out.push(Series::dots(
            format!("beyond envelope ({} frames)", bx.len()),
            bx,
            by,
        ));
    }
    out
}

/// The duty under the drives: a blank line, a heading line, and per joint its peak reflected
/// rotor torque, the energy driven and regenerated, and the frames beyond its class's envelope.
fn duty_rows(loads: &[JointLoad]) -> Vec<Vec<String>> {
    let mut rows = vec![
        vec![],
        [
            "duty",
            "rotor pk (N·m)",
            "E drive (J)",
            "E regen (J)",
            "beyond env.",
        ]
        .map(String::from)
        .to_vec(),
    ];
    for l in loads {
        rows.push(vec![
            l.joint.clone(),
            fmt_value(l.peak_rotor_torque_nm),
            fmt_value(l.energy.driven_j),
            fmt_value(l.energy.regen_j),
            match (&l.class, l.frames_beyond_envelope) {
                (_, Some(n)) => n.to_string(),
                (None, None) => "no class".into(),
                (Some(_), None) => "no envelope".into(),
            },
        ]);
    }
    rows
}

/// The drive parameters under the sizing table: a blank line, a heading line, and per joint
/// its gear ratio, torque constant and efficiency, each marked `(default)` when so.
fn drive_rows(
    joints: &[JointMotion],
    specs: &[MotorSpec],
    defaults: &[[bool; 3]],
) -> Vec<Vec<String>> {
    let mut rows = vec![
        vec![],
        [
            "drive",
            "gear N",
            "Km (N·m/A)",
            "efficiency η",
            "J_m (kg·m²)",
        ]
        .map(String::from)
        .to_vec(),
    ];
    for (k, (m, s)) in joints.iter().zip(specs).enumerate() {
        let d = defaults.get(k).copied().unwrap_or([false; 3]);
        let cell = |v: f64, default: bool| {
            let v = crate::io::shortest::plain(v);
            if default { format!("{v} (default)") } else { v }
        };
        rows.push(vec![
            m.joint.clone(),
            cell(s.gear_ratio, d[0]),
            cell(s.km_nm_per_a, d[1]),
            cell(s.efficiency.unwrap_or(1.0), d[2]),
            cell(s.rotor_inertia_kg_m2, false),
        ]);
    }
    rows
}

/// Rejects inputs the chart cannot draw: no joint, a spec or load count that differs from the
/// joints', a series that is not a time series.
fn check_input(
    joints: &[JointMotion],
    specs: &[MotorSpec],
    loads: &[JointLoad],
) -> Result<(), Error> {
    if joints.is_empty() {
        return Err(Error::Invalid("motor report: no joint to plot".into()));
    }
    if specs.len() != joints.len() {
        return Err(Error::Invalid(format!(
            "motor report: {} joints but {} motor specs",
            joints.len(),
            specs.len()
        )));
    }
    for m in joints {
        check_series(
            &format!("motor report of {:?}", m.joint),
            &m.t,
            &[
                ("torque", &m.tau),
                ("speed", &m.qd),
                ("acceleration", &m.qdd),
            ],
        )?;
    }
    if loads.len() != joints.len() {
        return Err(Error::Invalid(format!(
            "motor report: {} joints but {} loads",
            joints.len(),
            loads.len()
        )));
    }
    Ok(())
}

/// The joint power `τ·q̇` of every joint as two curves: driving (P > 0) and regenerating
/// (P < 0), zero elsewhere.
fn power_series(joints: &[JointMotion]) -> Vec<Series> {
    let mut power = Vec::with_capacity(2 * joints.len());
    for m in joints {
        let p: Vec<f64> = m.tau.iter().zip(&m.qd).map(|(t, w)| t * w).collect();
        let part = |f: fn(f64) -> f64| p.iter().map(|&x| f(x)).collect::<Vec<f64>>();
        power.push(Series::new(
            format!("{} driving", m.joint),
            m.t.clone(),
            part(|x| x.max(0.0)),
        ));
        power.push(Series::new(
            format!("{} regen", m.joint),
            m.t.clone(),
            part(|x| x.min(0.0)),
        ));
    }
    power
}

/// The sizing table: per joint its peaks, RMS and class, then the drives and the duty.
fn sizing_table(
    joints: &[JointMotion],
    specs: &[MotorSpec],
    loads: &[JointLoad],
    defaults: &[[bool; 3]],
) -> Table {
    // a column's values below its resolution (report::labels) are noise: printed as 0
    let quote = |v: f64, f: &dyn Fn(&JointLoad) -> f64| {
        let column: Vec<f64> = loads.iter().map(f).collect();
        let res = crate::report::labels::resolution([column.as_slice()]);
        fmt_value(crate::report::labels::denoise(v, res))
    };
    let mut table = Table {
        header: [
            "joint",
            "peak τ (N·m)",
            "RMS τ (N·m)",
            "peak ω (rad/s)",
            "peak P (W)",
            "peak I (A)",
            "class",
        ]
        .map(String::from)
        .to_vec(),
        rows: loads
            .iter()
            .map(|l| {
                vec![
                    l.joint.clone(),
                    quote(l.peak_torque_nm, &|l| l.peak_torque_nm),
                    quote(l.rms_torque_nm, &|l| l.rms_torque_nm),
                    quote(l.peak_speed_rad_s, &|l| l.peak_speed_rad_s),
                    quote(l.peak_power_w, &|l| l.peak_power_w),
                    quote(l.peak_current_a, &|l| l.peak_current_a),
                    class_name(l).to_string(),
                ]
            })
            .collect(),
    };
    table.rows.extend(drive_rows(joints, specs, defaults));
    table.rows.extend(duty_rows(loads));
    table
}
