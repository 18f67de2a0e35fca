//! Motor sizing for an arm: for each joint, from its torque `τ(t)` (N·m) and speed `q̇(t)`
//! (rad/s), the loads a motor behind a gearbox must carry and the smallest catalogue class that
//! carries them.
//!
//! The motor drives the joint through a gear of ratio `N` (motor turns per joint turn) and
//! efficiency `η` (1 when not given). On the motor shaft (standard gear-train relations, e.g.
//! Siciliano et al. 2009, *Robotics: Modelling, Planning and Control*, §5.1 and §8.7):
//!
//! ```text
//! τ_m = τ / (N · η)          motor torque (N·m)
//! ω_m = N · q̇                motor speed (rad/s)
//! I   = τ_m / Km = τ / (Km · N · η)   motor current (A), Km the torque constant (N·m/A)
//! P   = τ · q̇                mechanical power at the joint (W)
//! ```
//!
//! Peaks are `max |·|` over the samples; RMS values are time-weighted (trapezoid rule, see
//! [`crate::report::knee`]), which is what a motor's continuous (thermal) rating is compared
//! with. A joint needs the first class of the catalogue whose rated continuous torque is at
//! least the RMS motor torque, whose peak torque is at least the peak motor torque, and whose
//! rated speed is at least the peak motor speed (all inclusive).
//!
//! The catalogue is a TOML file of `[[class]]` tables, `name`, `rated_torque_nm`,
//! `peak_torque_nm`, `rated_speed_rpm` (motor shaft values); the bundled one is
//! `data/motor_classes.toml` ([`default_catalogue`]), another is read by [`read_catalogue`].

use crate::error::Error;
use crate::report::chart::{ImageFormat, Panel, Series, Table, fmt_value, stacked_chart};
use crate::report::knee::{check_series, peak_abs, rms};

/// Motor constant and transmission of one joint's drive.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotorSpec {
    /// Torque constant `Km` (N·m/A), > 0.
    pub km_nm_per_a: f64,
    /// Gear ratio `N` (motor turns per joint turn), > 0.
    pub gear_ratio: f64,
    /// Gearbox efficiency `η` in (0, 1]; `None` means 1 (ideal gear).
    pub efficiency: Option<f64>,
}

/// One class of a motor catalogue (values on the motor shaft).
#[derive(Debug, Clone, PartialEq)]
pub struct MotorClass {
    pub name: String,
    /// Rated continuous torque (N·m), compared with the RMS motor torque.
    pub rated_torque_nm: f64,
    /// Peak (intermittent) torque (N·m), compared with the peak motor torque.
    pub peak_torque_nm: f64,
    /// Rated speed (rad/s), compared with the peak motor speed.
    pub rated_speed_rad_s: f64,
}

/// rpm → rad/s (rated speeds are quoted in rpm by vendors and in the catalogue file).
pub fn rpm(x: f64) -> f64 {
    x * std::f64::consts::PI / 30.0
}

/// The bundled catalogue file (`data/motor_classes.toml`).
pub const DEFAULT_CATALOGUE: &str = include_str!("../../data/motor_classes.toml");

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct CatalogueFile {
    class: Vec<ClassRow>,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct ClassRow {
    name: String,
    rated_torque_nm: f64,
    peak_torque_nm: f64,
    rated_speed_rpm: f64,
}

/// Parses a catalogue (the format of `data/motor_classes.toml`); `path` names it in errors.
/// Every number must be positive and a class's peak torque at least its rated torque.
pub fn parse_catalogue(text: &str, path: &std::path::Path) -> Result<Vec<MotorClass>, Error> {
    let file: CatalogueFile = toml::from_str(text).map_err(|e| {
        Error::Invalid(format!(
            "{}: {e}expected [[class]] tables with name, rated_torque_nm, peak_torque_nm, \
             rated_speed_rpm",
            path.display()
        ))
    })?;
    if file.class.is_empty() {
        return Err(Error::Invalid(format!(
            "{}: no [[class]] in the catalogue",
            path.display()
        )));
    }
    file.class
        .into_iter()
        .map(|c| {
            let pos = |x: f64| x.is_finite() && x > 0.0;
            if !(pos(c.rated_torque_nm) && pos(c.peak_torque_nm) && pos(c.rated_speed_rpm))
                || c.peak_torque_nm < c.rated_torque_nm
            {
                return Err(Error::Invalid(format!(
                    "{}: class {:?}: torques and speed must be positive, the peak torque at \
                     least the rated one",
                    path.display(),
                    c.name
                )));
            }
            Ok(MotorClass {
                name: c.name,
                rated_torque_nm: c.rated_torque_nm,
                peak_torque_nm: c.peak_torque_nm,
                rated_speed_rad_s: rpm(c.rated_speed_rpm),
            })
        })
        .collect()
}

/// Reads a catalogue file.
pub fn read_catalogue(path: &std::path::Path) -> Result<Vec<MotorClass>, Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    parse_catalogue(&text, path)
}

/// The bundled catalogue, [`DEFAULT_CATALOGUE`]: brushless DC servo motor classes, smallest
/// first. Its figures are illustrative round values (see the file), not any vendor's data.
pub fn default_catalogue() -> Result<Vec<MotorClass>, Error> {
    parse_catalogue(
        DEFAULT_CATALOGUE,
        std::path::Path::new("data/motor_classes.toml"),
    )
}

/// One joint's trajectory: torque and speed over time.
#[derive(Debug, Clone, PartialEq)]
pub struct JointMotion {
    /// Joint (coordinate) name, e.g. `"shoulder_pitch"`.
    pub joint: String,
    /// Sample times (s), non-decreasing.
    pub t: Vec<f64>,
    /// Joint torque (N·m).
    pub tau: Vec<f64>,
    /// Joint speed `q̇` (rad/s).
    pub qd: Vec<f64>,
}

/// What one joint asks of its motor.
#[derive(Debug, Clone, PartialEq)]
pub struct JointLoad {
    pub joint: String,
    /// Joint side: `max |τ|` (N·m).
    pub peak_torque_nm: f64,
    /// Joint side: time-weighted RMS of τ (N·m).
    pub rms_torque_nm: f64,
    /// Joint side: `max |q̇|` (rad/s).
    pub peak_speed_rad_s: f64,
    /// `max |τ · q̇|` (W).
    pub peak_power_w: f64,
    /// Motor side: peak torque `max|τ| / (N·η)` (N·m).
    pub motor_peak_torque_nm: f64,
    /// Motor side: RMS torque `rms(τ) / (N·η)` (N·m).
    pub motor_rms_torque_nm: f64,
    /// Motor side: peak speed `N · max|q̇|` (rad/s).
    pub motor_peak_speed_rad_s: f64,
    /// Peak current `max|τ| / (Km·N·η)` (A).
    pub peak_current_a: f64,
    /// RMS current `rms(τ) / (Km·N·η)` (A).
    pub rms_current_a: f64,
    /// The drive it was sized with.
    pub spec: MotorSpec,
    /// The first class of the catalogue that carries the load; `None` when none does (lower
    /// the torque with a larger gear ratio, or the speed with a smaller one).
    pub class: Option<MotorClass>,
}

impl MotorSpec {
    /// `η`, 1 when not given.
    pub fn eta(&self) -> f64 {
        self.efficiency.unwrap_or(1.0)
    }

    fn validate(&self) -> Result<(), Error> {
        let pos = |x: f64| x.is_finite() && x > 0.0;
        if !pos(self.km_nm_per_a) {
            return Err(Error::Invalid(format!(
                "motor constant Km = {} N·m/A must be positive",
                self.km_nm_per_a
            )));
        }
        if !pos(self.gear_ratio) {
            return Err(Error::Invalid(format!(
                "gear ratio N = {} must be positive",
                self.gear_ratio
            )));
        }
        let eta = self.eta();
        if !(eta > 0.0 && eta <= 1.0) {
            return Err(Error::Invalid(format!(
                "gear efficiency {eta} must be in (0, 1]"
            )));
        }
        Ok(())
    }
}

/// Motor current for joint torque `tau`: `I = τ / (Km · N · η)` (A).
pub fn motor_current(tau_nm: f64, spec: &MotorSpec) -> f64 {
    tau_nm / (spec.km_nm_per_a * spec.gear_ratio * spec.eta())
}

/// The smallest class of `catalogue` (ordered smallest first) carrying an RMS motor torque,
/// a peak motor torque and a peak motor speed; limits are inclusive.
pub fn choose_class(
    catalogue: &[MotorClass],
    rms_torque_nm: f64,
    peak_torque_nm: f64,
    peak_speed_rad_s: f64,
) -> Option<&MotorClass> {
    catalogue.iter().find(|c| {
        c.rated_torque_nm >= rms_torque_nm
            && c.peak_torque_nm >= peak_torque_nm
            && c.rated_speed_rad_s >= peak_speed_rad_s
    })
}

/// Sizes the motor of one joint (see the module documentation for the formulas), choosing
/// from `catalogue` (ordered smallest first).
pub fn size_motor(
    m: &JointMotion,
    spec: &MotorSpec,
    catalogue: &[MotorClass],
) -> Result<JointLoad, Error> {
    spec.validate()
        .map_err(|e| Error::Invalid(format!("motor sizing of {:?}: {e}", m.joint)))?;
    check_series(
        &format!("motor sizing of {:?}", m.joint),
        &m.t,
        &[("torque", &m.tau), ("speed", &m.qd)],
    )?;
    // joint side
    let (peak_torque_nm, _) = peak_abs(&m.tau);
    let rms_torque_nm = rms(&m.t, &m.tau);
    let (peak_speed_rad_s, _) = peak_abs(&m.qd);
    let peak_power_w = m
        .tau
        .iter()
        .zip(&m.qd)
        .map(|(t, w)| (t * w).abs())
        .fold(0.0, f64::max);
    // motor side through the gear: τ_m = τ / (N·η), ω_m = N·q̇, I = τ_m / Km
    let reduce = spec.gear_ratio * spec.eta();
    let motor_peak_torque_nm = peak_torque_nm / reduce;
    let motor_rms_torque_nm = rms_torque_nm / reduce;
    let motor_peak_speed_rad_s = peak_speed_rad_s * spec.gear_ratio;
    Ok(JointLoad {
        joint: m.joint.clone(),
        peak_torque_nm,
        rms_torque_nm,
        peak_speed_rad_s,
        peak_power_w,
        motor_peak_torque_nm,
        motor_rms_torque_nm,
        motor_peak_speed_rad_s,
        peak_current_a: motor_current(peak_torque_nm, spec),
        rms_current_a: motor_current(rms_torque_nm, spec),
        spec: *spec,
        class: choose_class(
            catalogue,
            motor_rms_torque_nm,
            motor_peak_torque_nm,
            motor_peak_speed_rad_s,
        )
        .cloned(),
    })
}

/// [`size_motor`] for every joint, `specs[k]` driving `joints[k]`.
pub fn size_motors(
    joints: &[JointMotion],
    specs: &[MotorSpec],
    catalogue: &[MotorClass],
) -> Result<Vec<JointLoad>, Error> {
    if joints.len() != specs.len() {
        return Err(Error::Invalid(format!(
            "motor sizing: {} joints but {} motor specs; give one per joint",
            joints.len(),
            specs.len()
        )));
    }
    joints
        .iter()
        .zip(specs)
        .map(|(m, s)| size_motor(m, s, catalogue))
        .collect()
}

/// Name of a class for tables, `"none in catalogue"` when no class fits.
pub fn class_name(load: &JointLoad) -> &str {
    load.class
        .as_ref()
        .map_or("none in catalogue", |c| c.name.as_str())
}

/// Header of [`motor_table_csv`], in the column scheme (`report::columns`): one row per
/// revolute coordinate, so `peak:tau` is that coordinate's peak |τ| in N·m (units in the
/// sidecar: docs/formats.md).
pub const MOTOR_TABLE_HEADER: &[&str] = &[
    "joint",
    "peak:tau",
    "rms:tau",
    "peak:v",
    "peak:power",
    "peak:motor_tau",
    "rms:motor_tau",
    "peak:motor_v",
    "peak:current",
    "rms:current",
    "class",
    "km",
    "gear",
    "efficiency",
];

/// The sizing table as CSV ([`MOTOR_TABLE_HEADER`], numbers shortest round-trip), through the
/// one CSV writer.
pub fn motor_table_csv(loads: &[JointLoad]) -> Result<String, Error> {
    let mut b = ryu::Buffer::new();
    let mut num = |x: f64| b.format(x).to_string();
    let rows: Vec<Vec<String>> = loads
        .iter()
        .map(|l| {
            let mut r = vec![l.joint.clone()];
            for v in [
                l.peak_torque_nm,
                l.rms_torque_nm,
                l.peak_speed_rad_s,
                l.peak_power_w,
                l.motor_peak_torque_nm,
                l.motor_rms_torque_nm,
                l.motor_peak_speed_rad_s,
                l.peak_current_a,
                l.rms_current_a,
            ] {
                r.push(num(v));
            }
            r.push(class_name(l).to_string());
            for v in [l.spec.km_nm_per_a, l.spec.gear_ratio, l.spec.eta()] {
                r.push(num(v));
            }
            r
        })
        .collect();
    let header: Vec<String> = MOTOR_TABLE_HEADER.iter().map(|h| h.to_string()).collect();
    crate::report::csv::table_to_string(&header, &rows)
}

/// Torque, speed, power and motor current curves (one panel each, one curve per joint,
/// min/max marked; the current `I = τ / (Km·N·η)` with `specs[k]` for `joints[k]`), followed by
/// the sizing table of `loads`.
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
            &[("torque", &m.tau), ("speed", &m.qd)],
        )?;
    }
    let curves = |f: &dyn Fn(&JointMotion) -> Vec<f64>| -> Vec<Series> {
        joints
            .iter()
            .map(|m| Series::new(m.joint.clone(), m.t.clone(), f(m)))
            .collect()
    };
    let torque = curves(&|m| m.tau.clone());
    let speed = curves(&|m| m.qd.clone());
    let power = curves(&|m| m.tau.iter().zip(&m.qd).map(|(t, w)| t * w).collect());
    let current: Vec<Series> = joints
        .iter()
        .zip(specs)
        .map(|(m, s)| {
            let i = m.tau.iter().map(|t| motor_current(*t, s)).collect();
            Series::new(m.joint.clone(), m.t.clone(), i)
        })
        .collect();
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
    // a column's values below its resolution (report::labels) are noise: printed as 0
    let quote = |v: f64, f: &dyn Fn(&JointLoad) -> f64| {
        let column: Vec<f64> = loads.iter().map(f).collect();
        let res = crate::report::labels::resolution([column.as_slice()]);
        fmt_value(crate::report::labels::denoise(v, res))
    };
    let table = Table {
        header: [
            "joint",
            "peak τ (N·m)",
            "RMS τ (N·m)",
            "peak q̇ (rad/s)",
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
    let mut table = table;
    table.rows.extend(drive_rows(joints, specs, defaults));
    stacked_chart(
        &[
            panel("Joint torque", "torque (N·m)", &torque),
            panel("Joint speed", "speed (rad/s)", &speed),
            panel("Mechanical power τ·q̇", "power (W)", &power),
            panel("Motor current I = τ/(Km·N·η)", "current (A)", &current),
        ],
        Some(&table),
        caption,
        format,
    )
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
        ["drive", "gear N", "Km (N·m/A)", "efficiency η"]
            .map(String::from)
            .to_vec(),
    ];
    for (k, (m, s)) in joints.iter().zip(specs).enumerate() {
        let d = defaults.get(k).copied().unwrap_or([false; 3]);
        let cell = |v: f64, default: bool| {
            let v = ryu::Buffer::new()
                .format(v)
                .trim_end_matches(".0")
                .to_string();
            if default { format!("{v} (default)") } else { v }
        };
        rows.push(vec![
            m.joint.clone(),
            cell(s.gear_ratio, d[0]),
            cell(s.km_nm_per_a, d[1]),
            cell(s.efficiency.unwrap_or(1.0), d[2]),
        ]);
    }
    rows
}

/// The plotted curves as CSV, named by `report::columns`: `time` (s), then per joint
/// `tau:<joint>` (N·m), `v:<joint>` (rad/s), `power:<joint>` (W), `current:<joint>` (A) (with
/// `specs[k]` for `joints[k]`). The joints must
/// share their sample times.
pub fn motor_curves_csv(joints: &[JointMotion], specs: &[MotorSpec]) -> Result<String, Error> {
    if specs.len() != joints.len() {
        return Err(Error::Invalid(format!(
            "motor export: {} joints but {} motor specs",
            joints.len(),
            specs.len()
        )));
    }
    let mut series = Vec::with_capacity(4 * joints.len());
    for (m, spec) in joints.iter().zip(specs) {
        check_series(
            &format!("motor export of {:?}", m.joint),
            &m.t,
            &[("torque", &m.tau), ("speed", &m.qd)],
        )?;
        let p: Vec<f64> = m.tau.iter().zip(&m.qd).map(|(t, w)| t * w).collect();
        series.push(Series::new(
            super::columns::name("tau", &[&m.joint]),
            m.t.clone(),
            m.tau.clone(),
        ));
        series.push(Series::new(
            super::columns::name("v", &[&m.joint]),
            m.t.clone(),
            m.qd.clone(),
        ));
        series.push(Series::new(
            super::columns::name("power", &[&m.joint]),
            m.t.clone(),
            p,
        ));
        let i = m.tau.iter().map(|t| motor_current(*t, spec)).collect();
        series.push(Series::new(
            super::columns::name("current", &[&m.joint]),
            m.t.clone(),
            i,
        ));
    }
    crate::report::chart::series_csv("time", &series)
}
