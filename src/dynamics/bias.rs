//! The paper's velocity and gravity terms of `D(q) q̈ + h(q, q̇) + c(q) = τ` (its equation 1),
//! each available on its own so the equation can be inspected term by term.
//!
//! All three are the recursive Newton-Euler algorithm (Featherstone 2008, table 5.1; §5.3,
//! "calculating the bias force") with some inputs set to zero: `c = RNEA(q, 0, 0)`,
//! `h = RNEA(q, v, 0)` without gravity, `h + c = RNEA(q, v, 0)`. None of them includes the joint
//! friction `b q̇`, which `rnea` adds on top (as Pinocchio's `nonLinearEffects`).

use super::Workspace;
use super::rnea::rnea_terms;
use crate::model::Model;
use nalgebra::DVector;

/// Gravity term `c(q)` (N·m or N): the generalized forces that hold the model still against
/// gravity. Writes the `rnea` buffers and `ws.gravity`; returns `&ws.gravity`.
pub fn gravity_terms<'w>(model: &Model, ws: &'w mut Workspace, q: &[f64]) -> &'w DVector<f64> {
    rnea_terms(model, ws, q, None, None, None, true);
    ws.gravity.copy_from(&ws.tau);
    &ws.gravity
}

/// Velocity term `h(q, v)` (Coriolis and centripetal forces, N·m or N), gravity and friction
/// excluded. Writes the `rnea` buffers and `ws.coriolis`; returns `&ws.coriolis`.
pub fn coriolis_terms<'w>(
    model: &Model,
    ws: &'w mut Workspace,
    q: &[f64],
    v: &[f64],
) -> &'w DVector<f64> {
    rnea_terms(model, ws, q, Some(v), None, None, false);
    remove_friction(model, v, &mut ws.tau);
    ws.coriolis.copy_from(&ws.tau);
    &ws.coriolis
}

/// `h(q, v) + c(q)` (Pinocchio's `nonLinearEffects`), friction excluded. Writes the `rnea`
/// buffers and `ws.nle`; returns `&ws.nle`.
pub fn nonlinear_effects<'w>(
    model: &Model,
    ws: &'w mut Workspace,
    q: &[f64],
    v: &[f64],
) -> &'w DVector<f64> {
    rnea_terms(model, ws, q, Some(v), None, None, true);
    remove_friction(model, v, &mut ws.tau);
    ws.nle.copy_from(&ws.tau);
    &ws.nle
}

/// `τ −= b·v`: `rnea_terms` adds friction whenever it is given a velocity.
#[inline]
pub(crate) fn remove_friction(model: &Model, v: &[f64], tau: &mut DVector<f64>) {
    for ((t, b), vk) in tau.iter_mut().zip(&model.damping).zip(v) {
        *t -= b * vk;
    }
}
