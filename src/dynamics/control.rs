//! Computed-torque control, the paper's equation 2:
//! `q̈cmd = q̈d + Kv (q̇d − q̇) + Kp (qd ⊖ q)`, `τ = RNEA(q, q̇, q̈cmd)`, with diagonal gains, and
//! the reference trajectory it tracks. The position error uses [`Model::difference`], so it is
//! a proper rotation error for ball and free joints.
//!
//! With the controller's model equal to the plant, the closed loop is `ë + Kv ė + Kp e = 0` for
//! every coordinate (Craig 2005, *Introduction to Robotics*, §10.6; critically damped at
//! `Kv = 2√Kp`). A controller model with wrong masses (`mass_error`) leaves a residual that the
//! PD terms have to correct.

use super::{Workspace, rnea};
use crate::error::Error;
use crate::model::Model;
use nalgebra::DVector;

/// Diagonal PD gains: one value for every coordinate, or one per coordinate (`nv`).
#[derive(Debug, Clone, PartialEq)]
pub struct Gains {
    /// Position gains `Kp` (1/s²).
    pub kp: Vec<f64>,
    /// Velocity gains `Kv` (1/s).
    pub kv: Vec<f64>,
}

impl Gains {
    /// The same gains on every coordinate.
    pub fn scalar(kp: f64, kv: f64) -> Self {
        Self {
            kp: vec![kp],
            kv: vec![kv],
        }
    }
    /// Critically damped scalar gains for a natural frequency `omega` (rad/s):
    /// `Kp = ω²`, `Kv = 2ω`.
    pub fn critical(omega: f64) -> Self {
        Self::scalar(omega * omega, 2.0 * omega)
    }
    /// `Kp` of coordinate k.
    #[inline]
    pub fn kp(&self, k: usize) -> f64 {
        if self.kp.len() == 1 {
            self.kp[0]
        } else {
            self.kp[k]
        }
    }
    /// `Kv` of coordinate k.
    #[inline]
    pub fn kv(&self, k: usize) -> f64 {
        if self.kv.len() == 1 {
            self.kv[0]
        } else {
            self.kv[k]
        }
    }
    /// Checks the sizes (1 or `nv`) and that every gain is finite and ≥ 0.
    pub fn validate(&self, nv: usize) -> Result<(), Error> {
        for (name, g) in [("kp", &self.kp), ("kv", &self.kv)] {
            if g.len() != 1 && g.len() != nv {
                return Err(Error::Invalid(format!(
                    "{} {name} gains for a model with {nv} coordinates: give one value or {nv}",
                    g.len()
                )));
            }
            if let Some(x) = g.iter().find(|x| !(x.is_finite() && **x >= 0.0)) {
                return Err(Error::Invalid(format!(
                    "{name} gain {x}: gains must be finite and ≥ 0"
                )));
            }
        }
        Ok(())
    }
}

/// A reference trajectory sampled at increasing times: `q` (`nq` per sample), `v` and `a`
/// (`nv` per sample), SI. Between samples `q` is the cubic Hermite curve through both samples'
/// positions and velocities, taken in the tangent space at `q_k`
/// (`q_k ⊕ p(s)`, `p(0) = 0`, `p(1) = q_{k+1} ⊖ q_k`, `p'(0) = h v_k`, `p'(1) = h v_{k+1}`), `v` is
/// its derivative and `a` is interpolated linearly, so the three stay consistent to O(h²) and
/// an exact-model controller tracks the interpolated reference; before the first sample and
/// after the last the reference holds the end sample.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Reference {
    /// Sample times (s), strictly increasing.
    pub time: Vec<f64>,
    pub q: Vec<Vec<f64>>,
    pub v: Vec<Vec<f64>>,
    pub a: Vec<Vec<f64>>,
}

impl Reference {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.time.len()
    }
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// Checks sizes against `model`, that times strictly increase and that every number is
    /// finite.
    pub fn validate(&self, model: &Model) -> Result<(), Error> {
        let n = self.time.len();
        if n == 0 {
            return Err(Error::Invalid("the reference trajectory is empty".into()));
        }
        if self.q.len() != n || self.v.len() != n || self.a.len() != n {
            return Err(Error::Invalid(format!(
                "reference: {n} times but {} q, {} v, {} a samples",
                self.q.len(),
                self.v.len(),
                self.a.len()
            )));
        }
        for k in 0..n {
            let sizes = (self.q[k].len(), self.v[k].len(), self.a[k].len());
            if sizes != (model.nq, model.nv, model.nv) {
                return Err(Error::Invalid(format!(
                    "reference sample {k}: q, v, a have {sizes:?} entries, the model needs \
                     ({}, {}, {})",
                    model.nq, model.nv, model.nv
                )));
            }
            if k > 0
                && self.time[k].partial_cmp(&self.time[k - 1]) != Some(std::cmp::Ordering::Greater)
            {
                return Err(Error::Invalid(format!(
                    "reference sample {k}: time {} does not increase (previous {})",
                    self.time[k],
                    self.time[k - 1]
                )));
            }
            let bad = self.q[k].iter().chain(&self.v[k]).chain(&self.a[k]);
            if !self.time[k].is_finite() || bad.clone().any(|x| !x.is_finite()) {
                return Err(Error::Invalid(format!(
                    "reference sample {k} (t = {} s) holds a non-finite number",
                    self.time[k]
                )));
            }
        }
        Ok(())
    }

    /// The reference at time `t` into `q` (`nq`), `v`, `a` (`nv`); `tmp` (`nv`) is scratch.
    pub fn sample(
        &self,
        model: &Model,
        t: f64,
        q: &mut [f64],
        v: &mut [f64],
        a: &mut [f64],
        tmp: &mut [f64],
    ) {
        let n = self.time.len();
        // the sample at or before t
        let k = self.time.partition_point(|&x| x <= t).saturating_sub(1);
        if k + 1 >= n || t <= self.time[0] {
            let k = if t <= self.time[0] { 0 } else { n - 1 };
            q.copy_from_slice(&self.q[k]);
            v.copy_from_slice(&self.v[k]);
            a.copy_from_slice(&self.a[k]);
            return;
        }
        let h = self.time[k + 1] - self.time[k];
        let s = (t - self.time[k]) / h;
        // Hermite basis and its derivative (per unit s)
        let (s2, s3) = (s * s, s * s * s);
        let (h10, h01, h11) = (s3 - 2.0 * s2 + s, 3.0 * s2 - 2.0 * s3, s3 - s2);
        let (d10, d01, d11) = (
            3.0 * s2 - 4.0 * s + 1.0,
            6.0 * s - 6.0 * s2,
            3.0 * s2 - 2.0 * s,
        );
        let (v0, v1) = (&self.v[k], &self.v[k + 1]);
        // Δ = q_{k+1} ⊖ q_k in tmp; p(s) in a (scratch until the end)
        model.difference(&self.q[k], &self.q[k + 1], tmp);
        for j in 0..model.nv {
            a[j] = h10 * h * v0[j] + h01 * tmp[j] + h11 * h * v1[j];
        }
        model.integrate(&self.q[k], a, 1.0, q);
        for j in 0..model.nv {
            v[j] = d10 * v0[j] + d01 * tmp[j] / h + d11 * v1[j];
            a[j] = self.a[k][j] + s * (self.a[k + 1][j] - self.a[k][j]);
        }
    }
}

/// A computed-torque controller with its own (possibly wrong) model and buffers.
#[derive(Debug, Clone)]
pub struct ComputedTorque {
    /// The controller's model: the plant's with link masses (and rotational inertias) scaled
    /// by `1 + mass_error`.
    pub model: Model,
    pub gains: Gains,
    ws: Workspace,
    /// Reference at the last call: `qd` (`nq`), `vd`, `ad` (`nv`).
    pub qd: Vec<f64>,
    pub vd: Vec<f64>,
    pub ad: Vec<f64>,
    /// Position error `qd ⊖ q` at the last call (`nv`, rad or m).
    pub error: Vec<f64>,
    /// Commanded acceleration at the last call (`nv`).
    pub a_cmd: Vec<f64>,
    tmp: Vec<f64>,
}

impl ComputedTorque {
    /// A controller for `plant` whose own model has every link's mass and inertia scaled by
    /// `1 + mass_error` (0: exact model).
    pub fn new(plant: &Model, gains: Gains, mass_error: f64) -> Result<Self, Error> {
        gains.validate(plant.nv)?;
        if !(mass_error > -1.0 && mass_error.is_finite()) {
            return Err(Error::Invalid(format!(
                "mass error {mass_error}: must be > -1 (masses scaled by 1 + error)"
            )));
        }
        let mut model = plant.clone();
        for i in model.inertia.iter_mut() {
            i.mass *= 1.0 + mass_error;
            i.inertia_com *= 1.0 + mass_error;
        }
        let nv = plant.nv;
        Ok(Self {
            ws: Workspace::new(&model),
            model,
            gains,
            qd: vec![0.0; plant.nq],
            vd: vec![0.0; nv],
            ad: vec![0.0; nv],
            error: vec![0.0; nv],
            a_cmd: vec![0.0; nv],
            tmp: vec![0.0; nv],
        })
    }

    /// The torques of the paper's equation 2 at time `t` and state `(q, v)`:
    /// `τ = RNEA(q, v, q̈d + Kv (q̇d − q̇) + Kp (qd ⊖ q))` with the controller's model. Also
    /// leaves the reference and the error in `self`.
    pub fn torque(&mut self, reference: &Reference, t: f64, q: &[f64], v: &[f64]) -> &DVector<f64> {
        reference.sample(
            &self.model,
            t,
            &mut self.qd,
            &mut self.vd,
            &mut self.ad,
            &mut self.tmp,
        );
        self.model.difference(q, &self.qd, &mut self.error);
        for (k, a) in self.a_cmd.iter_mut().enumerate() {
            *a = self.ad[k]
                + self.gains.kv(k) * (self.vd[k] - v[k])
                + self.gains.kp(k) * self.error[k];
        }
        rnea(&self.model, &mut self.ws, q, v, &self.a_cmd, None)
    }
}
