//! Direct dynamics the paper's way: `D(q) q̈ = τ − b q̇ − (h + c)`, solved by a sparse `LᵀDL`
//! factorisation of `D` that follows the tree (Featherstone 2008, §6.5, tables 6.3 and 6.4).
//! And [`ForwardMethod`], the choice between this and the articulated-body algorithm.

use super::aba::{aba, check_pivot};
use super::bias::remove_friction;
use super::crba::crba;
use super::rnea::rnea_terms;
use super::workspace::{NO_DOF, Workspace};
use crate::error::Error;
use crate::model::Model;
use crate::spatial::ForceVec;
use nalgebra::DVector;
use std::str::FromStr;

/// How direct dynamics is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ForwardMethod {
    /// The articulated-body algorithm, O(n) ([`aba`]).
    #[default]
    Aba,
    /// Mass matrix, bias terms and a sparse Cholesky (`LᵀDL`) solve, O(n d²) for tree depth d
    /// ([`forward_dynamics_cholesky`]): the paper's way.
    Cholesky,
}

impl FromStr for ForwardMethod {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        match s.trim() {
            "aba" => Ok(ForwardMethod::Aba),
            "cholesky" | "crba" => Ok(ForwardMethod::Cholesky),
            other => Err(Error::Invalid(format!(
                "forward dynamics method `{other}`: expected `aba` or `cholesky`"
            ))),
        }
    }
}

impl std::fmt::Display for ForwardMethod {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            ForwardMethod::Aba => "aba",
            ForwardMethod::Cholesky => "cholesky",
        })
    }
}

/// Direct dynamics `q̈` by `method`; see [`aba`] and [`forward_dynamics_cholesky`] (same inputs,
/// same result to round-off). Returns `&ws.qdd`.
pub fn forward_dynamics<'w>(
    method: ForwardMethod,
    model: &Model,
    ws: &'w mut Workspace,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    f_ext: Option<&[ForceVec]>,
) -> Result<&'w DVector<f64>, Error> {
    match method {
        ForwardMethod::Aba => aba(model, ws, q, v, tau, f_ext),
        ForwardMethod::Cholesky => forward_dynamics_cholesky(model, ws, q, v, tau, f_ext),
    }
}

/// Direct dynamics by the paper's route: `D(q)` by [`crba`], `h + c` (minus the external forces'
/// share `Σ Jᵢᵀ f_ext,i`) by the Newton-Euler sweeps, then `D q̈ = τ − b q̇ − (h + c)` solved by
/// the `LᵀDL` factorisation that exploits the tree's sparsity (Featherstone 2008, table 6.3: `D`
/// is factored in place, with fill-in only between a coordinate and its ancestors; table 6.4 for
/// the back-substitutions). Allocation-free.
///
/// # Errors
/// [`Error::Numerical`] naming the coordinate whose pivot is not positive (relative to its
/// diagonal entry in `D`), as [`aba`] does.
///
/// Writes the `crba` and `rnea` buffers, `ws.nle`, `ws.ltdl` and `ws.qdd`; returns `&ws.qdd`.
pub fn forward_dynamics_cholesky<'w>(
    model: &Model,
    ws: &'w mut Workspace,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    f_ext: Option<&[ForceVec]>,
) -> Result<&'w DVector<f64>, Error> {
    // right-hand side: τ − b q̇ − (h + c − Σ Jᵀ f_ext)
    rnea_terms(model, ws, q, Some(v), None, f_ext, true);
    remove_friction(model, v, &mut ws.tau);
    ws.nle.copy_from(&ws.tau);
    for (k, x) in ws.qdd.iter_mut().enumerate() {
        *x = tau[k] - model.damping[k] * v[k] - ws.nle[k];
    }

    // D = Lᵀ diag L in place (table 6.3), coordinates leaves first
    crba(model, ws, q);
    ws.ltdl.copy_from(&ws.mass_matrix);
    let lambda = &ws.dof_parent;
    let h = &mut ws.ltdl;
    for k in (0..model.nv).rev() {
        check_pivot(model, k, h[(k, k)], ws.mass_matrix[(k, k)])?;
        let mut i = lambda[k];
        while i != NO_DOF {
            let a = h[(k, i)] / h[(k, k)];
            let mut j = i;
            while j != NO_DOF {
                h[(i, j)] -= a * h[(k, j)];
                j = lambda[j];
            }
            h[(k, i)] = a;
            i = lambda[i];
        }
    }

    // solve Lᵀ diag L q̈ = rhs (table 6.4): Lᵀ leaves first, the diagonal, then L root first
    let x = &mut ws.qdd;
    for k in (0..model.nv).rev() {
        let mut i = lambda[k];
        while i != NO_DOF {
            x[i] -= h[(k, i)] * x[k];
            i = lambda[i];
        }
    }
    for k in 0..model.nv {
        x[k] /= h[(k, k)];
    }
    for k in 0..model.nv {
        let mut i = lambda[k];
        while i != NO_DOF {
            x[k] -= h[(k, i)] * x[i];
            i = lambda[i];
        }
    }
    Ok(&ws.qdd)
}
