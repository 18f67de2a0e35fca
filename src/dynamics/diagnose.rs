//! Diagnostics users can run on their own model and states (MuJoCo's `mj_compareFwdInv`):
//! how well inverse and direct dynamics agree, and how close `D(q)` is to singular.

use super::aba::aba;
use super::forward::forward_dynamics_cholesky;
use super::rnea::rnea;
use super::workspace::Workspace;
use crate::error::Error;
use crate::model::Model;

/// The forward/inverse consistency at one state.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Consistency {
    /// `max |ABA(q, v, RNEA(q, v, a)) − a|` relative to `max(|a|, 1)`.
    pub aba_vs_rnea: f64,
    /// `max |q̈_cholesky − q̈_aba|` relative to `max(|q̈_aba|, 1)`, same torques.
    pub cholesky_vs_aba: f64,
    /// The smallest `LᵀDL` pivot of `D(q)` relative to its diagonal entry: 1 for decoupled
    /// coordinates, → 0 near a singularity (gimbal lock of the euler model); below
    /// [`SINGULAR_RTOL`](super::aba::SINGULAR_RTOL) the direct dynamics refuse the state.
    pub min_pivot_ratio: f64,
    /// The velocity coordinate of that pivot.
    pub min_pivot_coord: usize,
}

/// Runs `τ = RNEA(q, v, a)`, then ABA and the Cholesky route on `τ`, and reports how far they
/// come back from `a` and from each other, and the conditioning margin of `D(q)`.
///
/// # Errors
/// [`Error::Numerical`] when `D(q)` is singular at this state (naming the coordinate).
pub fn forward_inverse_residual(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    v: &[f64],
    a: &[f64],
) -> Result<Consistency, Error> {
    // (a diagnostic, not a hot loop: it keeps copies of τ and the ABA result)
    let tau = rnea(model, ws, q, v, a, None).clone();
    let q_aba = aba(model, ws, q, v, tau.as_slice(), None)?.clone();
    let a_scale = a.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    let aba_vs_rnea = q_aba
        .iter()
        .zip(a)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / a_scale;
    let q_chol = forward_dynamics_cholesky(model, ws, q, v, tau.as_slice(), None)?;
    let cholesky_vs_aba = (q_chol - &q_aba).amax() / q_aba.amax().max(1.0);
    // LᵀDL pivots relative to the diagonal of D
    let (mut min_pivot_ratio, mut min_pivot_coord) = (f64::INFINITY, 0);
    for k in 0..model.nv {
        let r = ws.ltdl[(k, k)] / ws.mass_matrix[(k, k)];
        if r < min_pivot_ratio {
            (min_pivot_ratio, min_pivot_coord) = (r, k);
        }
    }
    Ok(Consistency {
        aba_vs_rnea,
        cholesky_vs_aba,
        min_pivot_ratio,
        min_pivot_coord,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::samples::euler_avatar;

    #[test]
    fn the_pivot_margin_falls_towards_gimbal_lock() {
        let model = euler_avatar();
        let mut ws = Workspace::new(&model);
        let x = model.v_index("LeftArm.Xrotation").unwrap();
        let z = model.v_index("LeftArm.Zrotation").unwrap();
        let (v, a) = (vec![0.1; model.nv], vec![0.2; model.nv]);
        let mut last = f64::INFINITY;
        for delta in [1.0, 1e-1, 1e-2, 1e-3] {
            let mut q = model.neutral();
            q[x] = std::f64::consts::FRAC_PI_2 - delta;
            let c = forward_inverse_residual(&model, &mut ws, &q, &v, &a).unwrap();
            assert!(
                c.aba_vs_rnea < 1e-6 && c.cholesky_vs_aba < 1e-6,
                "{delta}: {c:?}"
            );
            assert!(c.min_pivot_ratio < last, "{delta}: {c:?}");
            if delta < 0.005 {
                assert_eq!(c.min_pivot_coord, z, "{delta}: {c:?}");
            }
            last = c.min_pivot_ratio;
        }
        let mut q = model.neutral();
        q[x] = std::f64::consts::FRAC_PI_2;
        assert!(forward_inverse_residual(&model, &mut ws, &q, &v, &a).is_err());
    }
}
