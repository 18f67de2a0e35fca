//! Inverse dynamics by the recursive Newton-Euler algorithm.

use super::Workspace;
use crate::model::Model;
use crate::spatial::{AxisRotation, ForceVec, MotionVec, SpatialInertia};
use nalgebra::{DVector, Matrix3, Vector3};

/// Inverse dynamics, recursive Newton-Euler: the generalized forces `τ` that produce the
/// accelerations `a` at state `(q, v)` (Featherstone 2008, table 5.1; the paper's forward sweep
/// of velocities and accelerations and backward sweep of forces and moments), including the
/// model's viscous joint friction `bᵢ q̇ᵢ` and optional external forces `f_ext` (one per body,
/// body frame, acting on the body).
///
/// `τ = D(q) a + h(q, v) + c(q) + b·v − Σ Jᵢᵀ f_ext,i`. Writes `ws.x_up`, `ws.v`, `ws.a`,
/// `ws.f`, `ws.tau` (and `ws.joint_rot`) and returns `&ws.tau`.
///
/// Cost: a revolute joint about a coordinate axis under an unrotated placement (every rotation
/// channel of a BVH euler model) takes a step specialised to its axis ([`JointStep::Axis`]: 4
/// multiplications per rotated vector, no lever terms across the zero-length links of an euler
/// triple, nothing re-decided per call), and bodies without mass or inertia (the fictitious
/// links of a BVH euler model, two in three bodies) skip the inertial terms `I a + v ×* I v`.
/// The three joints of an euler triple are crossed in one forward step ([`JointStep::Triple`]).
/// The numbers are those of the general formulas, operation for operation.
pub fn rnea<'w>(
    model: &Model,
    ws: &'w mut Workspace,
    q: &[f64],
    v: &[f64],
    a: &[f64],
    f_ext: Option<&[ForceVec]>,
) -> &'w DVector<f64> {
    rnea_terms(model, ws, q, Some(v), Some(a), f_ext, true);
    &ws.tau
}

/// The recursive Newton-Euler sweeps with any of the terms switched off: `v = None` is
/// `v = 0` (and no friction), `a = None` is `a = 0`, `gravity = false` drops `c(q)`. The
/// bias-term functions ([`super::bias`]) are this with some terms off. Writes `ws.joint_rot`
/// and `ws.x_up`, `ws.v`, `ws.a`, `ws.f`, `ws.tau`.
pub(crate) fn rnea_terms(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    v: Option<&[f64]>,
    a: Option<&[f64]>,
    f_ext: Option<&[ForceVec]>,
    gravity: bool,
) {
    assert_eq!(
        ws.joint_steps.len(),
        model.nbodies(),
        "a workspace of another model"
    );
    forward_pass(model, ws, q, v, a, f_ext, gravity, false);
    backward_pass(model, ws, v);
}

/// [`rnea`] right after [`forward_kinematics`](super::forward_kinematics) of the same `q` in
/// `ws`: the forward pass reads the sines and cosines the kinematics took (`ws.sin_q`,
/// `ws.cos_q`, the same [`crate::lanes::sin_cos_many`] of the same angles) instead of taking
/// them again. The same bits as [`rnea`]; writes what it writes.
pub fn rnea_after_kinematics<'w>(
    model: &Model,
    ws: &'w mut Workspace,
    q: &[f64],
    v: &[f64],
    a: &[f64],
) -> &'w DVector<f64> {
    assert_eq!(
        ws.joint_steps.len(),
        model.nbodies(),
        "a workspace of another model"
    );
    debug_assert!(
        (q[..model.nq].iter().zip(&ws.sin_q).zip(&ws.cos_q))
            .all(|((x, s), c)| crate::spatial::sin_cos(*x) == (*s, *c)),
        "the sines of another configuration: run forward_kinematics of q first"
    );
    forward_pass(model, ws, q, Some(v), Some(a), None, true, true);
    backward_pass(model, ws, Some(v));
    &ws.tau
}

/// RNEA's forward pass: writes `ws.joint_rot`, `ws.x_up`, `ws.v`, `ws.a` and each body's own
/// net force in `ws.f`; with `sines_taken`, `ws.sin_q` and `ws.cos_q` already hold `q`'s
/// (else it writes them).
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn forward_pass(
    model: &Model,
    ws: &mut Workspace,
    q: &[f64],
    v: Option<&[f64]>,
    a: Option<&[f64]>,
    f_ext: Option<&[ForceVec]>,
    gravity: bool,
    sines_taken: bool,
) {
    let n = model.nbodies();
    // the per-body tables cut to the body count once, so that indexing by i needs no checks
    let (parent, idx_q, idx_v) = (&model.parent[..n], &model.idx_q[..n], &model.idx_v[..n]);
    let (placement, inertia) = (&model.placement[..n], &model.inertia[..n]);
    let Workspace {
        joint_steps,
        joint_rot,
        x_up,
        v: wv,
        a: wa,
        f: wf,
        sin_q,
        cos_q,
        ..
    } = ws;
    let (steps, joint_rot, x_up) = (&joint_steps[..n], &mut joint_rot[..n], &mut x_up[..n]);
    // every angle's sine and cosine at once (the axis joints' rotations), vectorised
    let nq = model.nq;
    if !sines_taken {
        crate::lanes::sin_cos_many(&q[..nq], &mut sin_q[..nq], &mut cos_q[..nq]);
    }
    let rotation = |k: usize, iq: usize| AxisRotation::from_sin_cos(k, sin_q[iq], cos_q[iq]);
    let (wv, wa, wf) = (&mut wv[..n], &mut wa[..n], &mut wf[..n]);

    // the world: at rest, accelerating upward to stand in for gravity
    wv[0] = MotionVec::ZERO;
    wa[0] = if gravity {
        MotionVec::new(Vector3::zeros(), -model.gravity)
    } else {
        MotionVec::ZERO
    };

    // forward pass: velocities, accelerations and the net force each body needs
    //   v_i = iX_λ v_λ + S_i q̇_i,   a_i = iX_λ a_λ + S_i q̈_i + v_i ×ₘ S_i q̇_i
    //   f_i = I_i a_i + v_i ×* I_i v_i − f_ext,i
    let rate = |x: Option<&[f64]>, iv: usize| x.map_or(0.0, |x| x[iv]);
    let external = |i: usize| f_ext.map_or(ForceVec::ZERO, |fx| ForceVec::ZERO - fx[i]);
    let mut i = 1;
    while i < n {
        let p = parent[i];
        match steps[i] {
            JointStep::Axis { k, shifted } => {
                let iv = idx_v[i];
                let rot = rotation(k, idx_q[i]);
                joint_rot[i] = rot;
                let t = shifted.then_some(&placement[i].trans);
                let (vi, ai) = axis_step(k, rot, t, &wv[p], &wa[p], rate(v, iv), rate(a, iv));
                wf[i] = body_force(&inertia[i], &vi, &ai, f_ext, i);
                wv[i] = vi;
                wa[i] = ai;
                i += 1;
            }
            JointStep::Triple { k, shifted } => {
                // three axis steps in a row, v and a carried in registers; the first two
                // bodies are massless: their own force is only the external one
                let (mut vb, mut ab) = (wv[p], wa[p]);
                for (j, &kj) in k.iter().enumerate() {
                    let b = i + j;
                    let iv = idx_v[b];
                    let rot = rotation(kj, idx_q[b]);
                    joint_rot[b] = rot;
                    let t = (shifted && j == 0).then_some(&placement[i].trans);
                    (vb, ab) = axis_step(kj, rot, t, &vb, &ab, rate(v, iv), rate(a, iv));
                    wv[b] = vb;
                    wa[b] = ab;
                }
                wf[i] = external(i);
                wf[i + 1] = external(i + 1);
                wf[i + 2] = body_force(&inertia[i + 2], &vb, &ab, f_ext, i + 2);
                i += 3;
            }
            JointStep::InTriple { .. } => {
                unreachable!("joint_steps starts every triple with JointStep::Triple")
            }
            JointStep::General => {
                let iv = idx_v[i];
                let joint = &model.joints[i];
                let x = model.parent_transform_sc(i, q, |iq| (sin_q[iq], cos_q[iq]));
                let (mut vi, mut ai) = (x.act_inv_motion(&wv[p]), x.act_inv_motion(&wa[p]));
                let vj = v.map_or(MotionVec::ZERO, |v| joint.motion(&v[iv..iv + joint.nv()]));
                let aj = a.map_or(MotionVec::ZERO, |a| joint.motion(&a[iv..iv + joint.nv()]));
                vi += vj;
                ai += aj + vi.cross_motion(&vj);
                x_up[i] = x;
                wf[i] = body_force(&inertia[i], &vi, &ai, f_ext, i);
                wv[i] = vi;
                wa[i] = ai;
                i += 1;
            }
        }
    }
}

/// The net force body `i` needs, `I a + v ×* I v − f_ext` (no inertial terms for a body
/// without mass or inertia).
#[inline(always)]
fn body_force(
    inertia: &SpatialInertia,
    vi: &MotionVec,
    ai: &MotionVec,
    f_ext: Option<&[ForceVec]>,
    i: usize,
) -> ForceVec {
    let mut fi = if inertia.is_zero() {
        ForceVec::ZERO
    } else {
        inertia.mul_motion(ai) + vi.cross_force(&inertia.mul_motion(vi))
    };
    if let Some(fx) = f_ext {
        fi -= fx[i];
    }
    fi
}

/// RNEA's backward pass: accumulates `ws.f` into each parent and writes `ws.tau`.
fn backward_pass(model: &Model, ws: &mut Workspace, v: Option<&[f64]>) {
    let n = model.nbodies();
    let (parent, idx_v, placement) = (&model.parent[..n], &model.idx_v[..n], &model.placement[..n]);
    let Workspace {
        joint_steps,
        joint_rot,
        x_up,
        f: wf,
        tau,
        ..
    } = ws;
    let (steps, joint_rot, x_up, wf) =
        (&joint_steps[..n], &joint_rot[..n], &x_up[..n], &mut wf[..n]);

    // backward pass: project each body's force on its joint, pass it on to the parent
    //   τ_i = S_iᵀ f_i + b_i q̇_i,   f_λ += λX_i f_i
    let tau = tau.as_mut_slice();
    for i in (1..n).rev() {
        let (iv, p, fi) = (idx_v[i], parent[i], wf[i]);
        let fp = match steps[i] {
            JointStep::Axis { k, shifted }
            | JointStep::Triple {
                k: [k, _, _],
                shifted,
            } => {
                tau[iv] = fi.ang[k] + v.map_or(0.0, |v| model.damping[iv] * v[iv]);
                let t = shifted.then_some(&placement[i].trans);
                axis_back(k, joint_rot[i], t, &fi)
            }
            JointStep::InTriple { k } => {
                tau[iv] = fi.ang[k] + v.map_or(0.0, |v| model.damping[iv] * v[iv]);
                axis_back(k, joint_rot[i], None, &fi)
            }
            JointStep::General => {
                let joint = &model.joints[i];
                let nv = joint.nv();
                let tau = &mut tau[iv..iv + nv];
                joint.project_force(&fi, tau);
                if let Some(v) = v {
                    for ((t, b), vk) in tau
                        .iter_mut()
                        .zip(&model.damping[iv..iv + nv])
                        .zip(&v[iv..])
                    {
                        *t += b * vk;
                    }
                }
                x_up[i].act_force(&fi)
            }
        };
        if p > 0 {
            wf[p] += fp;
        }
    }
}

/// How RNEA crosses joint i, decided once per model from its joints, placements and which
/// bodies are massless ([`joint_steps`]); kept in [`Workspace::joint_steps`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointStep {
    /// A revolute joint about coordinate axis `k` whose placement has no rotation: the
    /// transform is a rotation about `e_k` after the placement's translation, `S = e_k`.
    /// `shifted` is false when that translation is zero too (the second and third links of a
    /// BVH euler triple), and the lever terms `r × ·` are skipped: they are exactly zero.
    Axis { k: usize, shifted: bool },
    /// The first joint of an euler triple (a BVH joint's three rotation channels): bodies
    /// `i`, `i+1`, `i+2` in a chain, each an axis joint (axes `k`), the second and third at
    /// their parent's origin (`shifted` is the first's), bodies `i` and `i+1` massless. The
    /// forward pass crosses the three joints in one step, carrying `v` and `a` from one to
    /// the next, and skips the inertial terms of the two massless links; the backward pass
    /// takes each of the three as [`JointStep::Axis`]. The arithmetic is the three axis steps'.
    Triple { k: [usize; 3], shifted: bool },
    /// The second or third joint of a [`JointStep::Triple`] (axis `k`, no translation):
    /// crossed by the triple's step in the forward pass, as an axis joint in the backward.
    InTriple { k: usize },
    /// Any other joint: [`Model::parent_transform`] and the joint's own `S`.
    General,
}

/// [`JointStep`] of every body (entry 0, the world, is `General` and never used).
///
/// A triple is recognised where the pattern holds exactly (consecutive bodies in a chain,
/// unrotated placements, no translation inside, zero inertia on the first two); anywhere else
/// the joints take [`JointStep::Axis`] or [`JointStep::General`] one by one. The massless
/// links are those of the model the workspace is made for: a workspace made before giving
/// such a link mass would skip its inertial terms (the project's edits change the massive
/// bodies, and remake the workspace with the model).
pub fn joint_steps(model: &Model) -> Vec<JointStep> {
    let n = model.nbodies();
    let mut steps: Vec<JointStep> = (0..n)
        .map(|i| {
            let placement = &model.placement[i];
            match model.joints[i].revolute_coordinate_axis() {
                Some(k) if i > 0 && placement.rot == Matrix3::identity() => JointStep::Axis {
                    k,
                    shifted: placement.trans != Vector3::zeros(),
                },
                _ => JointStep::General,
            }
        })
        .collect();
    let mut i = 1;
    while i + 2 < n {
        let axis = |b: usize| match steps[b] {
            JointStep::Axis { k, shifted } => Some((k, shifted)),
            _ => None,
        };
        let triple = match (axis(i), axis(i + 1), axis(i + 2)) {
            (Some((k0, shifted)), Some((k1, false)), Some((k2, false)))
                if model.parent[i + 1] == i
                    && model.parent[i + 2] == i + 1
                    && model.inertia[i].is_zero()
                    && model.inertia[i + 1].is_zero() =>
            {
                Some(([k0, k1, k2], shifted))
            }
            _ => None,
        };
        match triple {
            Some((k, shifted)) => {
                steps[i] = JointStep::Triple { k, shifted };
                steps[i + 1] = JointStep::InTriple { k: k[1] };
                steps[i + 2] = JointStep::InTriple { k: k[2] };
                i += 3;
            }
            None => i += 1,
        }
    }
    steps
}

/// [`axis_forward`] for the axis `k` of the joint.
#[inline(always)]
fn axis_step(
    k: usize,
    rot: AxisRotation,
    t: Option<&Vector3<f64>>,
    vp: &MotionVec,
    ap: &MotionVec,
    qd: f64,
    qdd: f64,
) -> (MotionVec, MotionVec) {
    match k {
        0 => axis_forward::<0>(rot, t, vp, ap, qd, qdd),
        1 => axis_forward::<1>(rot, t, vp, ap, qd, qdd),
        _ => axis_forward::<2>(rot, t, vp, ap, qd, qdd),
    }
}

/// [`axis_backward`] for the axis `k` of the joint.
#[inline(always)]
fn axis_back(k: usize, rot: AxisRotation, t: Option<&Vector3<f64>>, f: &ForceVec) -> ForceVec {
    match k {
        0 => axis_backward::<0>(rot, t, f),
        1 => axis_backward::<1>(rot, t, f),
        _ => axis_backward::<2>(rot, t, f),
    }
}

/// The forward-pass step across a revolute joint about coordinate axis `K` (rotation `rot`,
/// after the translation `trans` when there is one): the same arithmetic as
/// [`FastTransform::act_inv_motion`](crate::spatial::FastTransform::act_inv_motion) and [`MotionVec::cross_axis`], with the axis a constant
/// so that no step branches on it.
///   `v_i = Rᵀ (v_λ − r × ω_λ) + e_K q̇`,   `a_i = Rᵀ (a_λ − r × α_λ) + e_K q̈ + v_i ×ₘ e_K q̇`
#[inline(always)]
fn axis_forward<const K: usize>(
    rot: AxisRotation,
    trans: Option<&Vector3<f64>>,
    vp: &MotionVec,
    ap: &MotionVec,
    qd: f64,
    qdd: f64,
) -> (MotionVec, MotionVec) {
    let r = AxisRotation { axis: K, ..rot };
    let lever = |m: &MotionVec| trans.map_or(m.lin, |t| m.lin - t.cross(&m.ang));
    let mut vi = MotionVec {
        ang: r.rotate_inv(&vp.ang),
        lin: r.rotate_inv(&lever(vp)),
    };
    let mut ai = MotionVec {
        ang: r.rotate_inv(&ap.ang),
        lin: r.rotate_inv(&lever(ap)),
    };
    vi.ang[K] += qd;
    ai.ang[K] += qdd;
    ai += vi.cross_axis(K, qd);
    (vi, ai)
}

/// The backward-pass step across the same joint: the same arithmetic as
/// [`FastTransform::act_force`](crate::spatial::FastTransform::act_force), the axis a constant.
///   `f_λ += [R n + r × R f; R f]`
#[inline(always)]
fn axis_backward<const K: usize>(
    rot: AxisRotation,
    trans: Option<&Vector3<f64>>,
    f: &ForceVec,
) -> ForceVec {
    let r = AxisRotation { axis: K, ..rot };
    let lin = r.rotate(&f.lin);
    let ang = r.rotate(&f.ang);
    ForceVec {
        ang: trans.map_or(ang, |t| ang + t.cross(&lin)),
        lin,
    }
}

#[cfg(test)]
mod tests {
    //! A point-mass pendulum (mass m at distance l below a z-axis hinge, gravity −y) obeys
    //! `τ = m l² q̈ + m g l sin q + b q̇` exactly.
    use super::*;
    use crate::model::{JointKind, ModelBuilder};
    use crate::spatial::{SpatialInertia, SpatialTransform};
    use nalgebra::{Matrix3, Vector3};

    #[test]
    fn pendulum_matches_the_analytic_equation_of_motion() {
        let (m, l, g, b) = (2.0, 0.7, 9.81, 0.3);
        let mut mb = ModelBuilder::new("pendulum", Vector3::new(0.0, -g, 0.0));
        mb.add_body(
            0,
            "bob",
            "hinge",
            JointKind::Revolute { axis: Vector3::z() },
            SpatialTransform::IDENTITY,
            SpatialInertia::new(m, Vector3::new(0.0, -l, 0.0), Matrix3::zeros()),
        );
        let mut model = mb.build();
        model.damping[0] = b;
        let mut ws = Workspace::new(&model);
        for (q, v, a) in [(0.0, 0.0, 0.0), (0.4, 1.3, -2.0), (-2.5, -0.2, 5.0)] {
            let tau = rnea(&model, &mut ws, &[q], &[v], &[a], None)[0];
            let expected = m * l * l * a + m * g * l * f64::sin(q) + b * v;
            assert!((tau - expected).abs() < 1e-12, "q={q}: {tau} vs {expected}");
        }
    }
}
