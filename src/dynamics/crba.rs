//! The joint-space inertia (mass) matrix by the composite rigid body algorithm.

use super::rnea::JointStep;
use super::workspace::NO_DOF;
use super::{Workspace, forward_kinematics};
use crate::model::Model;
use crate::spatial::{ForceVec, MotionVec, SpatialInertia, SpatialTransform};
use nalgebra::{DMatrix, Vector3};

/// A rigid-body (or composite) spatial inertia in world axes about a fixed point O, in the 10
/// numbers that define it (Pinocchio's `Inertia`, Featherstone 2008 §2.13): mass `m` (kg),
/// first moment `h = m c` (kg·m, c the centre of mass relative to O) and the rotational inertia
/// `I_O` about O (kg·m², symmetric: `[xx, yy, zz, xy, xz, yz]`). Inertias about the same point
/// in the same axes add number by number, which is what makes CRBA in world axes cheap.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct WorldInertia {
    pub m: f64,
    pub h: Vector3<f64>,
    pub i: [f64; 6],
}

impl WorldInertia {
    /// A body's inertia `I` (about its centre of mass, body axes) placed by `o`, the body's pose
    /// relative to O: `c = p + R c_b`, `I_O = R I_c Rᵀ + m (|c|² 1 − c cᵀ)` (parallel axes).
    #[inline(always)]
    pub fn of_body(inertia: &SpatialInertia, o: &SpatialTransform) -> Self {
        let (r, m) = (&o.rot, inertia.mass);
        let c = o.trans + r * inertia.com;
        let a = r * inertia.inertia_com; // R I_c, then (R I_c) Rᵀ on the upper triangle
        let e = |k: usize, l: usize| {
            a[(k, 0)] * r[(l, 0)] + a[(k, 1)] * r[(l, 1)] + a[(k, 2)] * r[(l, 2)]
        };
        let (cx, cy, cz) = (c.x, c.y, c.z);
        WorldInertia {
            m,
            h: c * m,
            i: [
                e(0, 0) + m * (cy * cy + cz * cz),
                e(1, 1) + m * (cx * cx + cz * cz),
                e(2, 2) + m * (cx * cx + cy * cy),
                e(0, 1) - m * cx * cy,
                e(0, 2) - m * cx * cz,
                e(1, 2) - m * cy * cz,
            ],
        }
    }

    #[inline]
    fn add(&mut self, o: &WorldInertia) {
        self.m += o.m;
        self.h += o.h;
        for (a, b) in self.i.iter_mut().zip(&o.i) {
            *a += b;
        }
    }

    /// `I · S`, the force `[n; f]` about O that gives the body the spatial velocity (or
    /// acceleration) `S = [ω; v]` about O: `n = I_O ω + h × v`, `f = m v − h × ω`.
    #[inline]
    pub fn mul_motion(&self, s: &MotionVec) -> ForceVec {
        let [xx, yy, zz, xy, xz, yz] = self.i;
        let w = &s.ang;
        let io_w = Vector3::new(
            xx * w.x + xy * w.y + xz * w.z,
            xy * w.x + yy * w.y + yz * w.z,
            xz * w.x + yz * w.y + zz * w.z,
        );
        ForceVec {
            ang: io_w + self.h.cross(&s.lin),
            lin: s.lin * self.m - self.h.cross(w),
        }
    }
}

/// The mass matrix `D(q)` of the paper's equation 1 (`D q̈ + h + c = τ`), by the composite rigid
/// body algorithm (Featherstone 2008, table 6.2), in world coordinates as Pinocchio's `crba`
/// with `Convention::WORLD` (Carpentier et al. 2019, *The Pinocchio C++ library*, §IV).
///
/// Forward pass: the world pose `0X_i = 0X_λ λX_i` of each body, its inertia `I_i` and its
/// joint's motion subspace `S_i` in world coordinates (world axes, about the origin of the
/// first body with mass rather than the world origin, for precision far from it). Backward
/// pass: the composite inertia of each subtree, `I^c_λ += I^c_i` (all about one point in one
/// frame, so no transform: ten additions, [`WorldInertia`]). Then for each coordinate `k` of
/// joint i, `F = I^c_i S_k` is the force that accelerates the whole subtree at unit `q̈_k`, and
/// `D[j, k] = D[k, j] = S_jᵀ F` for k and every coordinate j on its path to the root
/// (`ws.dof_parent`).
///
/// Entries between coordinates of different branches are zero: they are zero from
/// [`Workspace::new`] and no call writes them, so they are not cleared on each call.
///
/// Symmetric; positive definite unless the model has a massless chain or an euler joint model
/// is in gimbal lock. Bodies without mass or inertia (the fictitious links of a BVH euler model)
/// add nothing and are skipped. Writes `ws.o_x_i` (poses relative to that point),
/// `ws.s_world`, `ws.ycrb` (composite inertias, world axes, about that point) and
/// `ws.mass_matrix`, and returns `&ws.mass_matrix`.
pub fn crba<'w>(model: &Model, ws: &'w mut Workspace, q: &[f64]) -> &'w DMatrix<f64> {
    let nv = model.nv;
    let n = model.nbodies();

    // forward pass: world poses 0X_i = 0X_λ λX_i; inertias and motion subspaces in world axes
    // about the origin of the first body with mass
    let r = world_poses(model, ws, q);
    for i in 1..n {
        let o = &mut ws.o_x_i[i];
        o.trans -= r;
        let inertia = &model.inertia[i];
        ws.ycrb[i] = if inertia.is_zero() {
            WorldInertia::default()
        } else {
            WorldInertia::of_body(inertia, o)
        };
        let iv = model.idx_v[i];
        match ws.joint_steps[i] {
            JointStep::Axis { k, .. }
            | JointStep::Triple { k: [k, _, _], .. }
            | JointStep::InTriple { k } => {
                // S = [e_k; 0] in body axes: column k of the rotation, about the body's origin
                let ang = o.rot.column(k).into_owned();
                ws.s_world[iv] = MotionVec::new(ang, o.trans.cross(&ang));
            }
            JointStep::General => {
                let joint = &model.joints[i];
                if let Some(k) = joint.revolute_coordinate_axis() {
                    // a coordinate axis under a rotated placement: still a column pick
                    let ang = o.rot.column(k).into_owned();
                    ws.s_world[iv] = MotionVec::new(ang, o.trans.cross(&ang));
                } else {
                    for k in 0..joint.nv() {
                        ws.s_world[iv + k] = o.act_motion(&joint.subspace_col(k));
                    }
                }
            }
        }
    }

    // backward pass: composite inertias I^c_λ += I^c_i
    for i in (2..n).rev() {
        let p = model.parent[i];
        if p > 0 {
            let ic = ws.ycrb[i];
            ws.ycrb[p].add(&ic);
        }
    }

    // columns: F = I^c_i S_k, projected on k and on every coordinate above it (the branch-induced
    // sparsity: only the coordinates on k's path to the root)
    let (s_world, dof_parent) = (&ws.s_world[..nv], &ws.dof_parent[..nv]);
    let (idx_v, joints, ycrb) = (&model.idx_v[..n], &model.joints[..n], &ws.ycrb[..n]);
    let h = ws.mass_matrix.as_mut_slice();
    for i in 1..n {
        let iv = idx_v[i];
        for k in iv..iv + joints[i].nv() {
            let f = ycrb[i].mul_motion(&s_world[k]);
            // D is stored column-major: D[r, c] at r + c·nv
            let col = k * nv;
            let mut j = k;
            while j != NO_DOF {
                let x = s_world[j].dot(&f);
                h[j + col] = x;
                h[k + j * nv] = x;
                j = dof_parent[j];
            }
        }
    }
    &ws.mass_matrix
}

/// The forward pass of the world-axes algorithms (CRBA, ABA): [`forward_kinematics`] (every
/// `ws.o_x_i`), and the origin of the first body with mass (an avatar's pelvis, an arm's base),
/// which the caller takes as the reference point of its world-axes sums so that lever arms stay
/// short wherever a take walks to (world-frame sums lose digits as |lever|²; the shift itself
/// is exact to round-off). Zero when no body has mass.
#[inline]
pub(crate) fn world_poses(model: &Model, ws: &mut Workspace, q: &[f64]) -> Vector3<f64> {
    forward_kinematics(model, ws, q);
    (1..model.nbodies())
        .find(|&i| !model.inertia[i].is_zero())
        .map_or(Vector3::zeros(), |b| ws.o_x_i[b].trans)
}

#[cfg(test)]
mod tests {
    //! The ten-number world inertia is the 6×6 congruence `X* I X⁻¹` it replaces, and the
    //! entries CRBA does not write (coordinates of different branches) stay zero however often
    //! one workspace is reused: a reused workspace gives exactly what a fresh one gives.
    use super::*;
    use crate::dynamics::samples::{SplitMix64, random_configuration, random_inertia, random_tree};

    #[test]
    fn world_inertia_is_the_transformed_spatial_inertia() {
        let mut rng = SplitMix64(7);
        for _ in 0..20 {
            let inertia = random_inertia(&mut rng, 0.1, 20.0);
            let o =
                SpatialTransform::new(*rng.rotation().to_rotation_matrix().matrix(), rng.vec3(2.0));
            let y = WorldInertia::of_body(&inertia, &o);
            let six = inertia.transformed(&o).to_matrix();
            let s = MotionVec::new(rng.vec3(1.0), rng.vec3(1.0));
            let (a, b) = (
                y.mul_motion(&s),
                ForceVec::from_vector6(&(six * s.to_vector6())),
            );
            assert!((a.ang - b.ang).norm() + (a.lin - b.lin).norm() < 1e-12 * six.norm());
        }
    }

    #[test]
    fn a_reused_workspace_gives_a_fresh_workspaces_matrix() {
        let model = random_tree(24, 11, true);
        let mut reused = Workspace::new(&model);
        let mut rng = SplitMix64(3);
        let mut q = vec![0.0; model.nq];
        for _ in 0..8 {
            random_configuration(&model, &mut rng, &mut q);
            let d = crba(&model, &mut reused, &q).clone();
            let fresh = crba(&model, &mut Workspace::new(&model), &q).clone();
            assert_eq!(d, fresh);
        }
    }
}
