//! Forward dynamics by the articulated-body algorithm, O(n).

use super::Workspace;
use super::crba::{WorldInertia, world_poses};
use super::inertia6::SymInertia6;
use crate::error::Error;
use crate::model::Model;
use crate::spatial::SpatialTransform;
use crate::spatial::{ForceVec, MotionVec};
use nalgebra::{DVector, Matrix6, Vector3, Vector6};

/// A joint-space pivot (an articulated inertia `D_i = S_iᵀ I^A_i S_i`, or an `LᵀDL` pivot of
/// `D(q)`) at or below this fraction of its reference scale makes `D(q)` numerically singular.
/// Near gimbal lock of an euler joint model the ratio falls as δ², δ the distance to the lock,
/// while the condition number of `D` grows as 1/δ² (on the sample avatar, 8.8e9 at δ = 1e-2 rad
/// and 8.8e13 at 1e-4 rad): 1e-8 stops within ~1e-4 rad (0.006°) of the lock, before the
/// accelerations lose all their digits.
pub const SINGULAR_RTOL: f64 = 1e-8;

/// Forward dynamics by the articulated-body algorithm (Featherstone 2008, table 7.1; Pinocchio's
/// `aba` with `Convention::WORLD`): the accelerations `q̈` produced by the generalized forces
/// `τ` at state `(q, v)`, with the model's joint friction `b q̇` and optional external forces
/// `f_ext` (one per body, body frame, acting on the body) — the inverse of [`rnea`](super::rnea).
///
/// Everything is in world axes about each body's own origin: no articulated inertia is ever
/// rotated (a body's rigid inertia is turned into world axes once, ten numbers), and one is
/// handed to the parent by moving its reference point along the lever `d_i` between the two
/// origins and adding its 21 numbers ([`SymInertia6`]). Lever arms stay those of the joints, so
/// the accuracy is that of the body-frame algorithm (about one world point, as Pinocchio's
/// `WORLD` convention, the accelerations of distal joints lose digits as |lever|²).
///
/// Pass 1 (outward): world poses, motion subspaces `S_i` in world axes, velocities
/// `v_i = v_λ + S_i q̇_i` (`v_λ` moved to i's origin), velocity-product accelerations `c_i = v_i ×ₘ S_i q̇_i` (a body-fixed
/// axis turns with its body: `Ṡ_i = v_i ×ₘ S_i`) and rigid-body bias forces
/// `p^A_i = v_i ×* I_i v_i − f_ext,i`. Pass 2 (inward): `U_i = I^A_i S_i`, `D_i = S_iᵀ U_i`,
/// `u_i = τ_i − b_i q̇_i − S_iᵀ p^A_i`, `I^a = I^A_i − U_i D_i⁻¹ U_iᵀ` (for a 1-DoF joint the
/// rank-1 update of the 21 numbers), `p^a = p^A_i + I^a c_i + U_i D_i⁻¹ u_i`, added to the
/// parent's (moved to its origin). Pass 3 (outward): `a'_i = a_λ + c_i` (`a_λ` moved), `q̈_i = D_i⁻¹ (u_i − U_iᵀ a'_i)`,
/// `a_i = a'_i + S_i q̈_i`, starting from `a_0 = −g`.
///
/// # Errors
/// [`Error::Numerical`] when some `D_i` is not positive definite (massless chain, or gimbal lock
/// of an euler joint model): the message names the coordinate and suggests the ball joint model.
///
/// Writes `ws.o_x_i`, `ws.lever`, `ws.s_world`, `ws.ov`, `ws.oa`, `ws.c`, `ws.oyaba` (articulated
/// inertias), `ws.p_a`, `ws.u_f`, `ws.d_inv`, `ws.u_vec` and `ws.qdd`; returns `&ws.qdd`.
pub fn aba<'w>(
    model: &Model,
    ws: &'w mut Workspace,
    q: &[f64],
    v: &[f64],
    tau: &[f64],
    f_ext: Option<&[ForceVec]>,
) -> Result<&'w DVector<f64>, Error> {
    let n = model.nbodies();

    // pass 1: poses, velocities, velocity-product terms, rigid-body inertias and bias forces
    world_poses(model, ws, q);
    ws.ov[0] = MotionVec::ZERO;
    for i in 1..n {
        let (joint, p) = (&model.joints[i], model.parent[i]);
        let iv = model.idx_v[i];
        // world axes about the body's origin
        let rot = SpatialTransform::from_rotation(ws.o_x_i[i].rot);
        let d = ws.o_x_i[i].trans - ws.o_x_i[p].trans;
        ws.lever[i] = d;
        let mut vj = MotionVec::ZERO;
        if let Some(k) = joint.revolute_coordinate_axis() {
            // S = e_k (angular) in body axes: column k of the rotation in world axes
            let s = MotionVec::new(rot.rot.column(k).into_owned(), Vector3::zeros());
            vj.ang = s.ang * v[iv];
            ws.s_world[iv] = s;
        } else {
            for k in 0..joint.nv() {
                let s = rot.act_motion(&joint.subspace_col(k));
                vj += s * v[iv + k];
                ws.s_world[iv + k] = s;
            }
        }
        let vi = moved(&ws.ov[p], &d) + vj;
        let inertia = &model.inertia[i];
        let (yi, mut pa) = if inertia.is_zero() {
            (SymInertia6::default(), ForceVec::ZERO)
        } else {
            let y = WorldInertia::of_body(inertia, &rot);
            (
                SymInertia6::from_world(&y),
                vi.cross_force(&y.mul_motion(&vi)),
            )
        };
        if let Some(fx) = f_ext {
            pa -= rot.act_force(&fx[i]);
        }
        ws.ov[i] = vi;
        ws.c[i] = vi.cross_motion(&vj);
        ws.oyaba[i] = yi;
        ws.p_a[i] = pa;
    }

    // pass 2: articulated inertias and bias forces, leaves first
    for i in (1..n).rev() {
        let joint = &model.joints[i];
        let (iv, nvi) = (model.idx_v[i], joint.nv());
        let pa = ws.p_a[i];
        let (ia_red, pa_red) = if nvi == 1 {
            // one degree of freedom: D_i and u_i are scalars, the reduction is rank 1
            let mut ia = ws.oyaba[i];
            let s = ws.s_world[iv];
            let u = if s.lin == Vector3::zeros() {
                ia.mul_ang(&s.ang)
            } else {
                ia.mul_motion(&s)
            };
            let d = s.dot(&u);
            check_pivot(model, iv, d, pivot_scale(&ia, &joint.subspace_col(0)))?;
            let uu = tau[iv] - model.damping[iv] * v[iv] - s.dot(&pa);
            let d_inv = 1.0 / d;
            ws.u_f[iv] = u;
            ws.d_inv[i][(0, 0)] = d_inv;
            ws.u_vec[i][0] = uu;
            ia.sub_outer(&u, d_inv);
            let pa_red = pa + ia.mul_motion(&ws.c[i]) + u * (uu * d_inv);
            (ia, pa_red)
        } else {
            reduce_multi(model, ws, i, v, tau)?
        };
        // hand the articulated body over to the parent: same axes, moved to its origin
        let p = model.parent[i];
        if p > 0 {
            let d = ws.lever[i];
            let (mut ia_red, mut pa_red) = (ia_red, pa_red);
            // zero-length links (a BVH euler model's fictitious ones) need no move
            if d != Vector3::zeros() {
                ia_red.move_by(&-d);
                pa_red.ang += d.cross(&pa_red.lin);
            }
            ws.oyaba[p].add(&ia_red);
            ws.p_a[p] += pa_red;
        }
    }

    // pass 3: accelerations, root first
    ws.oa[0] = MotionVec::new(Vector3::zeros(), -model.gravity);
    for i in 1..n {
        let nvi = model.joints[i].nv();
        let iv = model.idx_v[i];
        let mut ai = moved(&ws.oa[model.parent[i]], &ws.lever[i]) + ws.c[i];
        let qdd = &mut ws.qdd.as_mut_slice()[iv..iv + nvi];
        if nvi == 1 {
            qdd[0] = ws.d_inv[i][(0, 0)] * (ws.u_vec[i][0] - ai.dot(&ws.u_f[iv]));
        } else {
            let mut r = [0.0; 6];
            for (k, rk) in r.iter_mut().enumerate().take(nvi) {
                *rk = ws.u_vec[i][k] - ai.dot(&ws.u_f[iv + k]);
            }
            for (k, out) in qdd.iter_mut().enumerate() {
                *out = (0..nvi).map(|l| ws.d_inv[i][(k, l)] * r[l]).sum();
            }
        }
        for (k, x) in qdd.iter().enumerate() {
            ai += ws.s_world[iv + k] * *x;
        }
        ws.oa[i] = ai;
    }
    Ok(&ws.qdd)
}

/// Pass 2 of [`aba`] at body `i` whose joint has several (or no) degrees of freedom: `D_i` is
/// `nv_i × nv_i`, inverted by Cholesky; the reduction on the full 6×6 matrix. Returns the
/// reduced articulated inertia and bias force.
fn reduce_multi(
    model: &Model,
    ws: &mut Workspace,
    i: usize,
    v: &[f64],
    tau: &[f64],
) -> Result<(SymInertia6, ForceVec), Error> {
    let joint = &model.joints[i];
    let (iv, nvi) = (model.idx_v[i], joint.nv());
    let sym = ws.oyaba[i];
    let ia = sym.to_matrix();
    let pa = ws.p_a[i];
    let mut u = Matrix6::zeros();
    let mut uu = Vector6::zeros();
    let mut d = Matrix6::zeros();
    let mut scale = [0.0; 6];
    for k in 0..nvi {
        let s = ws.s_world[iv + k];
        let uk = sym.mul_motion(&s);
        u.set_column(k, &uk.to_vector6());
        ws.u_f[iv + k] = uk;
        uu[k] = tau[iv + k] - model.damping[iv + k] * v[iv + k] - s.dot(&pa);
        scale[k] = pivot_scale(&sym, &joint.subspace_col(k));
    }
    for k in 0..nvi {
        for l in 0..nvi {
            d[(k, l)] = ws.s_world[iv + k].dot(&ws.u_f[iv + l]);
        }
    }
    let d_inv = spd_inverse(&d, nvi, &scale)
        .map_err(|(k, pivot)| singular_error(model, iv + k, pivot, scale[k]))?;
    let ud = u * d_inv;
    ws.d_inv[i] = d_inv;
    ws.u_vec[i] = uu;
    let ia_red = ia - ud * u.transpose();
    let pa_red = pa.to_vector6() + ia_red * ws.c[i].to_vector6() + ud * uu;
    Ok((
        SymInertia6::from_matrix(&ia_red),
        ForceVec::from_vector6(&pa_red),
    ))
}

/// The scale a pivot along motion `s` (the joint's subspace column in the body's own frame) is
/// compared with: `|s_ω|² tr(A) + |s_v|² tr(C)` for the inertia `[A B; Bᵀ C]` about the body's
/// origin — what the subtree would resist with if its own joints were locked (`ia` is in world
/// axes about that origin: traces do not see the axes).
#[inline]
fn pivot_scale(ia: &SymInertia6, s: &MotionVec) -> f64 {
    s.ang.norm_squared() * ia.trace_a() + s.lin.norm_squared() * ia.trace_c()
}

/// A motion (velocity or acceleration) about one point, about the point `d` further on: the
/// linear part gains `ω × d`.
#[inline]
fn moved(m: &MotionVec, d: &Vector3<f64>) -> MotionVec {
    if *d == Vector3::zeros() {
        *m
    } else {
        MotionVec::new(m.ang, m.lin + m.ang.cross(d))
    }
}

/// `Ok` when `pivot > SINGULAR_RTOL · scale` (and is a number).
#[inline]
pub(crate) fn check_pivot(
    model: &Model,
    coord: usize,
    pivot: f64,
    scale: f64,
) -> Result<(), Error> {
    if pivot > SINGULAR_RTOL * scale && pivot.is_finite() {
        Ok(())
    } else {
        Err(singular_error(model, coord, pivot, scale))
    }
}

/// The inverse of the symmetric `n × n` top-left block of `d` (n ≤ 6) by Cholesky, checking
/// each pivot against `SINGULAR_RTOL · scale[k]`; `Err((k, pivot))` names the failing row.
fn spd_inverse(d: &Matrix6<f64>, n: usize, scale: &[f64; 6]) -> Result<Matrix6<f64>, (usize, f64)> {
    // d = L Lᵀ
    let mut l = Matrix6::zeros();
    for k in 0..n {
        let mut pivot = d[(k, k)];
        for j in 0..k {
            pivot -= l[(k, j)] * l[(k, j)];
        }
        if !(pivot > SINGULAR_RTOL * scale[k] && pivot.is_finite()) {
            return Err((k, pivot));
        }
        let lkk = pivot.sqrt();
        l[(k, k)] = lkk;
        for r in k + 1..n {
            let mut x = d[(r, k)];
            for j in 0..k {
                x -= l[(r, j)] * l[(k, j)];
            }
            l[(r, k)] = x / lkk;
        }
    }
    // d⁻¹ = L⁻ᵀ L⁻¹, column by column: solve L y = e_c, then Lᵀ x = y
    let mut inv = Matrix6::zeros();
    for c in 0..n {
        let mut y = [0.0; 6];
        for r in 0..n {
            let mut x = if r == c { 1.0 } else { 0.0 };
            for j in 0..r {
                x -= l[(r, j)] * y[j];
            }
            y[r] = x / l[(r, r)];
        }
        for r in (0..n).rev() {
            let mut x = y[r];
            for j in r + 1..n {
                x -= l[(j, r)] * inv[(j, c)];
            }
            inv[(r, c)] = x / l[(r, r)];
        }
    }
    Ok(inv)
}

/// The error for a singular joint-space pivot at velocity coordinate `coord`.
pub(crate) fn singular_error(model: &Model, coord: usize, pivot: f64, scale: f64) -> Error {
    let body = model.body_of_v(coord);
    let name = model.v_names.get(coord).map_or("?", String::as_str);
    let (joint, body) = (&model.joint_names[body], &model.body_names[body]);
    let ratio = pivot / scale;
    if scale > 0.0 && ratio.is_finite() {
        Error::Numerical(format!(
            "the mass matrix D(q) is singular at coordinate `{name}` (joint `{joint}`, body \
             `{body}`): its pivot is {ratio:.1e} of the inertia it moves. This is a gimbal lock \
             of the euler joint model (two rotation axes of one joint aligned) or a chain of \
             massless bodies; use the ball joint model (`--joints ball`), or give the bodies mass"
        ))
    } else {
        // the subtree's own inertia along the coordinate is zero to round-off: no ratio to give
        Error::Numerical(format!(
            "the mass matrix D(q) is singular at coordinate `{name}` (joint `{joint}`, body \
             `{body}`): nothing with mass resists motion along it (pivot {pivot:.1e}): the \
             bodies it moves are massless, or the joints below it can undo its motion (a \
             massless joint whose children turn about its own point); give those bodies mass \
             (`--link-mass JOINT=KG`) or lock the joint (`--lock JOINT`)"
        ))
    }
}

#[cfg(test)]
mod tests {
    //! A singular D(q) is an error naming the coordinate and what to change: a gimbal lock
    //! (the pivot a tiny fraction of the inertia the coordinate moves) or a coordinate that
    //! moves nothing with mass (no ratio to give).
    use super::*;
    use crate::model::{JointKind, ModelBuilder};
    use crate::spatial::{SpatialInertia, SpatialTransform};
    use nalgebra::Matrix3;

    #[test]
    fn a_joint_moving_nothing_with_mass_is_named_with_what_to_change() {
        let mut mb = ModelBuilder::new("t", Vector3::new(0.0, 0.0, -9.81));
        let ball =
            SpatialInertia::new(1.0, Vector3::new(0.3, 0.0, 0.0), Matrix3::identity() * 0.01);
        let arm = mb.add_body(
            0,
            "arm",
            "shoulder",
            JointKind::Revolute { axis: Vector3::z() },
            SpatialTransform::IDENTITY,
            ball,
        );
        mb.add_body(
            arm,
            "marker",
            "marker_hinge",
            JointKind::Revolute { axis: Vector3::x() },
            SpatialTransform::from_translation(Vector3::new(0.5, 0.0, 0.0)),
            SpatialInertia::ZERO,
        );
        let model = mb.build();
        let mut ws = Workspace::new(&model);
        let e = aba(&model, &mut ws, &[0.1, 0.2], &[0.0, 0.0], &[0.0, 0.0], None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("`marker_hinge`"), "{e}");
        assert!(
            e.contains("nothing with mass resists motion along it"),
            "{e}"
        );
        assert!(e.contains("--lock") && e.contains("--link-mass"), "{e}");
    }
}
