//! What a drive goes through over a take besides its peaks: the torque its rotor's own inertia
//! asks, the energy the joint takes in and gives back, and the frames where the motor works
//! beyond its class's torque–speed envelope ([`super::motor`] sizes it).
//!
//! ```text
//! τ_rotor = J_m · N² · q̈                  reflected rotor inertia, joint side (N·m)
//! τ_m     = τ / (N·η) + J_m · N · q̈       motor torque: the joint's through the gear, plus
//!         = (τ + η · τ_rotor) / (N·η)      the rotor's own acceleration (it does not pass the gear)
//! P       = τ · q̇                          joint power: driving where P > 0, regenerating where P < 0
//! E_drive = ∫ max(P, 0) dt   E_regen = ∫ max(−P, 0) dt   (trapezoid rule, J)
//! ```
//!
//! so that `E_drive + E_regen = ∫|P| dt` and `E_drive − E_regen = ∫P dt` (the trapezoid rule is
//! linear). The reflected inertia is the standard gear-train relation: a rotor of inertia `I_m`
//! behind a gear `k_r` adds `k_r² I_m` to the joint's inertia (Siciliano et al. 2009, *Robotics:
//! Modelling, Planning and Control*, ch. 7, the motors' kinetic energy).
//!
//! **Envelope.** A class with a no-load speed `ω0` has the linear speed–torque line of a DC or
//! brushless DC motor at its supply voltage, scaled to its peak torque (the short-term operating
//! range of vendors' operating-range diagrams, e.g. maxon's "Key information on maxon DC motor
//! and maxon EC motor", and Hughes & Drury 2013, *Electric Motors and Drives*, 4th ed., ch. 3's
//! torque–speed line): available torque `τ_peak · (1 − |ω_m|/ω0)` for `|ω_m| < ω0`, none beyond.
//! Its continuous limit is the rated torque up to the rated speed. A frame is **beyond the
//! envelope** when its motor torque `|τ_m|` exceeds the torque available at its motor speed
//! `|ω_m| = N·|q̇|`; the continuous limit is a thermal (RMS) one, which the sizing compares with
//! the RMS motor torque, so a frame above it alone is not counted.

use super::motor::MotorClass;

/// The torque–speed envelope of a motor class (motor shaft values).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Envelope {
    /// Peak (stall) torque at zero speed (N·m).
    pub peak_torque_nm: f64,
    /// No-load speed, where the peak line reaches zero torque (rad/s).
    pub no_load_speed_rad_s: f64,
    /// Continuous (rated) torque (N·m), up to the rated speed.
    pub rated_torque_nm: f64,
    /// Rated speed (rad/s).
    pub rated_speed_rad_s: f64,
}

impl Envelope {
    /// The envelope of `class`; `None` when the class gives no no-load speed.
    pub fn of(class: &MotorClass) -> Option<Self> {
        class.no_load_speed_rad_s.map(|w0| Self {
            peak_torque_nm: class.peak_torque_nm,
            no_load_speed_rad_s: w0,
            rated_torque_nm: class.rated_torque_nm,
            rated_speed_rad_s: class.rated_speed_rad_s,
        })
    }

    /// The torque available at motor speed `omega` (rad/s, either sign): `τ_peak(1 − |ω|/ω0)`,
    /// 0 at and beyond the no-load speed.
    pub fn available(&self, omega: f64) -> f64 {
        self.peak_torque_nm * (1.0 - omega.abs() / self.no_load_speed_rad_s).max(0.0)
    }

    /// Whether motor torque `tau` (N·m) at motor speed `omega` (rad/s) lies beyond the envelope.
    pub fn beyond(&self, omega: f64, tau: f64) -> bool {
        tau.abs() > self.available(omega)
    }

    /// The peak line as a polyline `(speed, torque)`: `(0, τ_peak)` to `(ω0, 0)`.
    pub fn peak_line(&self) -> [(f64, f64); 2] {
        [(0.0, self.peak_torque_nm), (self.no_load_speed_rad_s, 0.0)]
    }

    /// The continuous limit as a polyline: the rated torque from 0 to the rated speed.
    pub fn continuous_line(&self) -> [(f64, f64); 2] {
        [
            (0.0, self.rated_torque_nm),
            (self.rated_speed_rad_s, self.rated_torque_nm),
        ]
    }
}

/// The reflected rotor inertia torque `J_m · N² · q̈` (joint side, N·m) of each sample.
pub fn rotor_torque(rotor_inertia_kg_m2: f64, gear_ratio: f64, qdd: &[f64]) -> Vec<f64> {
    let k = rotor_inertia_kg_m2 * gear_ratio * gear_ratio;
    qdd.iter().map(|a| k * a).collect()
}

/// The joint-side torque the motor's torque stands for through a gear of efficiency `eta`:
/// `τ + η · τ_rotor`, so that the motor torque is this over `N·η` (module documentation).
pub fn geared_torque(tau: &[f64], rotor: &[f64], eta: f64) -> Vec<f64> {
    tau.iter().zip(rotor).map(|(t, r)| t + eta * r).collect()
}

/// Energy the joint takes in (driving, `P > 0`) and gives back (regenerating, `P < 0`), J.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Energy {
    pub driven_j: f64,
    pub regen_j: f64,
}

/// [`Energy`] of the power `p` sampled at times `t` (trapezoid rule on `max(P, 0)` and
/// `max(−P, 0)`; 0 when the samples span no time).
pub fn energy(t: &[f64], p: &[f64]) -> Energy {
    let trapz = |f: &dyn Fn(f64) -> f64| -> f64 {
        t.windows(2)
            .zip(p.windows(2))
            .map(|(t, p)| 0.5 * (t[1] - t[0]) * (f(p[0]) + f(p[1])))
            .sum()
    };
    Energy {
        driven_j: trapz(&|x| x.max(0.0)),
        regen_j: trapz(&|x| (-x).max(0.0)),
    }
}

/// Which samples lie beyond `envelope`: motor speeds `omega_m` (rad/s), motor torques `tau_m`
/// (N·m).
pub fn beyond(envelope: &Envelope, omega_m: &[f64], tau_m: &[f64]) -> Vec<bool> {
    omega_m
        .iter()
        .zip(tau_m)
        .map(|(w, t)| envelope.beyond(*w, *t))
        .collect()
}
