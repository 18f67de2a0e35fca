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
//! with. A joint needs the first class of [`MOTOR_CLASSES`] whose rated continuous torque is at
//! least the RMS motor torque, whose peak torque is at least the peak motor torque, and whose
//! rated speed is at least the peak motor speed (all inclusive).

use crate::error::Error;
use crate::report::chart::{Panel, Series, Table, fmt_value, stacked_svg};
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
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotorClass {
    pub name: &'static str,
    /// Rated continuous torque (N·m), compared with the RMS motor torque.
    pub rated_torque_nm: f64,
    /// Peak (intermittent) torque (N·m), compared with the peak motor torque.
    pub peak_torque_nm: f64,
    /// Rated speed (rad/s), compared with the peak motor speed.
    pub rated_speed_rad_s: f64,
}

/// rpm → rad/s, for the catalogue below (rated speeds are quoted in rpm by vendors).
const fn rpm(x: f64) -> f64 {
    x * std::f64::consts::PI / 30.0
}

/// An illustrative catalogue of brushless DC servo motor classes, smallest first, by frame size
/// and rated power (`rated torque × rated speed`). The figures are round values of the order of
/// magnitude found in vendors' catalogues of BLDC servo motors; they are not any vendor's data
/// and only illustrate the selection. Every column grows with the class except the rated speed,
/// which falls as motors get larger.
pub const MOTOR_CLASSES: &[MotorClass] = &[
    MotorClass {
        name: "BLDC-22 (20 W)",
        rated_torque_nm: 0.02,
        peak_torque_nm: 0.1,
        rated_speed_rad_s: rpm(10000.0),
    },
    MotorClass {
        name: "BLDC-32 (50 W)",
        rated_torque_nm: 0.06,
        peak_torque_nm: 0.3,
        rated_speed_rad_s: rpm(8000.0),
    },
    MotorClass {
        name: "BLDC-42 (75 W)",
        rated_torque_nm: 0.12,
        peak_torque_nm: 0.6,
        rated_speed_rad_s: rpm(6000.0),
    },
    MotorClass {
        name: "BLDC-60 (200 W)",
        rated_torque_nm: 0.4,
        peak_torque_nm: 2.0,
        rated_speed_rad_s: rpm(5000.0),
    },
    MotorClass {
        name: "BLDC-80 (600 W)",
        rated_torque_nm: 1.3,
        peak_torque_nm: 5.0,
        rated_speed_rad_s: rpm(4500.0),
    },
    MotorClass {
        name: "BLDC-110 (1.1 kW)",
        rated_torque_nm: 3.5,
        peak_torque_nm: 12.0,
        rated_speed_rad_s: rpm(3000.0),
    },
    MotorClass {
        name: "BLDC-130 (2.6 kW)",
        rated_torque_nm: 10.0,
        peak_torque_nm: 30.0,
        rated_speed_rad_s: rpm(2500.0),
    },
    MotorClass {
        name: "BLDC-180 (7.3 kW)",
        rated_torque_nm: 35.0,
        peak_torque_nm: 90.0,
        rated_speed_rad_s: rpm(2000.0),
    },
];

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
    /// The smallest class of [`MOTOR_CLASSES`] that carries the load; `None` when none does
    /// (lower the torque with a larger gear ratio, or the speed with a smaller one).
    pub class: Option<&'static MotorClass>,
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
    catalogue: &'static [MotorClass],
    rms_torque_nm: f64,
    peak_torque_nm: f64,
    peak_speed_rad_s: f64,
) -> Option<&'static MotorClass> {
    catalogue.iter().find(|c| {
        c.rated_torque_nm >= rms_torque_nm
            && c.peak_torque_nm >= peak_torque_nm
            && c.rated_speed_rad_s >= peak_speed_rad_s
    })
}

/// Sizes the motor of one joint (see the module documentation for the formulas).
pub fn size_motor(m: &JointMotion, spec: &MotorSpec) -> Result<JointLoad, Error> {
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
        class: choose_class(
            MOTOR_CLASSES,
            motor_rms_torque_nm,
            motor_peak_torque_nm,
            motor_peak_speed_rad_s,
        ),
    })
}

/// [`size_motor`] for every joint, `specs[k]` driving `joints[k]`.
pub fn size_motors(joints: &[JointMotion], specs: &[MotorSpec]) -> Result<Vec<JointLoad>, Error> {
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
        .map(|(m, s)| size_motor(m, s))
        .collect()
}

/// Name of a class for tables, `"none in catalogue"` when no class fits.
pub fn class_name(load: &JointLoad) -> &'static str {
    load.class.map_or("none in catalogue", |c| c.name)
}

/// Header of [`motor_table_csv`].
pub const MOTOR_TABLE_HEADER: &str = "joint,peak_tau_Nm,rms_tau_Nm,peak_qd_rad_s,peak_power_W,\
motor_peak_tau_Nm,motor_rms_tau_Nm,motor_peak_speed_rad_s,peak_current_A,rms_current_A,class";

/// The sizing table as CSV ([`MOTOR_TABLE_HEADER`], numbers shortest round-trip).
pub fn motor_table_csv(loads: &[JointLoad]) -> String {
    let mut out = format!("{MOTOR_TABLE_HEADER}\n");
    let mut b = ryu::Buffer::new();
    for l in loads {
        out.push_str(&csv_field(&l.joint));
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
            out.push(',');
            out.push_str(b.format(v));
        }
        out.push(',');
        out.push_str(&csv_field(class_name(l)));
        out.push('\n');
    }
    out
}

/// A text field quoted as RFC 4180 asks when it holds a comma, a quote or a line break.
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// Torque, speed and power curves (one panel each, one curve per joint, min/max marked),
/// followed by the sizing table of `loads`.
pub fn motor_svg(joints: &[JointMotion], loads: &[JointLoad]) -> Result<String, Error> {
    if joints.is_empty() {
        return Err(Error::Invalid("motor report: no joint to plot".into()));
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
    let panel = |title, y_label, series| Panel {
        title,
        x_label: "time (s)",
        y_label,
        series,
        mark_min_max: true,
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
                    fmt_value(l.peak_torque_nm),
                    fmt_value(l.rms_torque_nm),
                    fmt_value(l.peak_speed_rad_s),
                    fmt_value(l.peak_power_w),
                    fmt_value(l.peak_current_a),
                    class_name(l).to_string(),
                ]
            })
            .collect(),
    };
    stacked_svg(
        &[
            panel("Joint torque", "torque (N·m)", &torque),
            panel("Joint speed", "speed (rad/s)", &speed),
            panel("Mechanical power τ·q̇", "power (W)", &power),
        ],
        Some(&table),
    )
}

/// The plotted curves as CSV: `t_s`, then per joint `<joint>_tau_Nm`, `<joint>_qd_rad_s`,
/// `<joint>_power_W`. The joints must share their sample times.
pub fn motor_curves_csv(joints: &[JointMotion]) -> Result<String, Error> {
    let mut series = Vec::with_capacity(3 * joints.len());
    for m in joints {
        check_series(
            &format!("motor export of {:?}", m.joint),
            &m.t,
            &[("torque", &m.tau), ("speed", &m.qd)],
        )?;
        let p: Vec<f64> = m.tau.iter().zip(&m.qd).map(|(t, w)| t * w).collect();
        series.push(Series::new(
            format!("{}_tau_Nm", m.joint),
            m.t.clone(),
            m.tau.clone(),
        ));
        series.push(Series::new(
            format!("{}_qd_rad_s", m.joint),
            m.t.clone(),
            m.qd.clone(),
        ));
        series.push(Series::new(format!("{}_power_W", m.joint), m.t.clone(), p));
    }
    crate::report::chart::series_csv("t_s", &series)
}
