//! The frame passes of the ground-reaction estimate, each computing what it reads once.
//!
//! 1. [`needed_wrenches`] (frames in parallel): forward kinematics and RNEA without external
//!    forces at every frame — the whole-body wrench the motion needs — and the world poses of
//!    the few bodies the later steps read ([`Poses`]: the feet's ankle and toe bodies, the root
//!    and the root-level bodies). The contact phases, the floor, the supports, the ground
//!    loads and the residual all read those poses, so no later step runs the kinematics again.
//! 2. the loads' assignment (serial in the caller: a foot's load is carried from frame to
//!    frame), from the kept poses.
//! 3. [`with_ground_reactions`] (frames in parallel): RNEA with the feet's wrenches, the
//!    root's residual about the pelvis.
//!
//! Every frame computes the same operations in the same order as a kinematics pass of its own
//! would, so the kept poses are bit-identical to recomputed ones, and the results do not
//! depend on the number of threads (`crate::par`).

use super::{PROGRESS_EVERY, about, root_wrench};
use crate::dynamics::residual::centre_of_mass;
use crate::dynamics::{Workspace, forward_kinematics, forward_kinematics_through, rnea};
use crate::model::Model;
use crate::motion::contact::{Foot, FootPoints};
use crate::spatial::{ForceVec, SpatialTransform};
use nalgebra::Vector3;

/// World poses of a few bodies at every frame, flat `[frame][body]` in the order of
/// `bodies`.
pub(super) struct Poses {
    /// The bodies kept (indices into the model's bodies), each once.
    bodies: Vec<usize>,
    /// `[frame * bodies.len() + j]`: world pose `0X_i` of body `bodies[j]` (as
    /// `forward_kinematics` writes `ws.o_x_i`).
    at: Vec<SpatialTransform>,
}

impl Poses {
    /// The bodies the estimate reads after its first pass: each foot's ankle and toe body,
    /// the root, and the bodies hung from the world (their poses give the root wrench).
    pub(super) fn bodies(model: &Model, feet: &[Foot], root: usize) -> Vec<usize> {
        let mut b: Vec<usize> = feet
            .iter()
            .flat_map(|f| [f.ankle_body, f.toe_body])
            .chain([root])
            .chain((1..model.nbodies()).filter(|&i| model.parent[i] == 0))
            .collect();
        b.sort_unstable();
        b.dedup();
        b
    }

    /// Writes frame `k`'s kept poses into `o_x_i` (indexed by body); the other bodies' entries
    /// are left as they are.
    pub(super) fn restore(&self, k: usize, o_x_i: &mut [SpatialTransform]) {
        let m = self.bodies.len();
        for (x, &b) in self.at[k * m..(k + 1) * m].iter().zip(&self.bodies) {
            o_x_i[b] = *x;
        }
    }

    /// The world pose of `body` (one of the kept ones) at frame `k`.
    fn of(&self, k: usize, body: usize) -> &SpatialTransform {
        let j = self
            .bodies
            .binary_search(&body)
            .expect("a kept body: Poses::bodies lists every foot body");
        &self.at[k * self.bodies.len() + j]
    }

    /// Poses of `bodies` given (`[frame * bodies.len() + j]`).
    pub(super) fn from_parts(bodies: Vec<usize>, at: Vec<SpatialTransform>) -> Self {
        Self { bodies, at }
    }

    /// Frames kept.
    pub(super) fn frames(&self) -> usize {
        self.at.len() / self.bodies.len().max(1)
    }

    /// The world poses of `bodies` over `q` by forward kinematics alone (serial, through the
    /// last of them only: the same bits as the whole pass): what [`needed_wrenches`] keeps,
    /// for the foot paths without the dynamics ([`super::foot_points`]).
    pub(super) fn of_motion(model: &Model, bodies: Vec<usize>, q: &[Vec<f64>]) -> Self {
        let mut ws = Workspace::new(model);
        let mut at = Vec::with_capacity(q.len() * bodies.len());
        let last = bodies.iter().copied().max().unwrap_or(0);
        for qk in q {
            forward_kinematics_through(model, &mut ws, qk, last);
            at.extend(bodies.iter().map(|&b| ws.o_x_i[b]));
        }
        Self { bodies, at }
    }

    /// Each foot's ankle-body poses over the take (`[foot][frame]`, for
    /// [`fit_heel_points`](crate::motion::contact::fit_heel_points)) and its toe path.
    pub(super) fn feet(&self, feet: &[Foot]) -> (Vec<Vec<SpatialTransform>>, Vec<FootPoints>) {
        let n = self.frames();
        let poses = feet
            .iter()
            .map(|f| (0..n).map(|k| *self.of(k, f.ankle_body)).collect())
            .collect();
        let paths = feet
            .iter()
            .map(|f| FootPoints {
                heel: vec![],
                toe: (0..n)
                    .map(|k| self.of(k, f.toe_body).transform_point(&f.toe_point))
                    .collect(),
            })
            .collect();
        (poses, paths)
    }
}

/// Pass 1: the whole-body wrench each frame needs (world axes, about the world origin:
/// RNEA without external forces, the force the world gives the root-level bodies), the
/// whole-body centre of mass (m, world), and the poses of `bodies` at every frame. Frames in parallel, in blocks of [`PROGRESS_EVERY`];
/// `report(first)` between blocks as [`crate::par::rounds`] says. `None` when stopped.
pub(super) fn needed_wrenches(
    model: &Model,
    bodies: Vec<usize>,
    q: &[Vec<f64>],
    v: &[Vec<f64>],
    a: &[Vec<f64>],
    report: &mut dyn FnMut(usize) -> bool,
) -> Option<(Vec<ForceVec>, Vec<Vector3<f64>>, Poses)> {
    let (n, m) = (q.len(), bodies.len().max(1));
    let mut needed = vec![ForceVec::ZERO; n];
    let mut com = vec![Vector3::zeros(); n];
    let mut at = vec![SpatialTransform::IDENTITY; n * m];
    type Frame<'a> = (
        &'a mut ForceVec,
        &'a mut Vector3<f64>,
        &'a mut [SpatialTransform],
    );
    let mut frames: Vec<Frame> = needed
        .iter_mut()
        .zip(com.iter_mut())
        .zip(at.chunks_mut(m))
        .map(|((w, c), x)| (w, c, x))
        .collect();
    let mut workspaces = crate::par::scratch(|| Workspace::new(model));
    let reached = crate::par::rounds(
        &mut frames,
        PROGRESS_EVERY,
        &mut workspaces,
        |ws, first, block| {
            for (i, (w, c, x)) in block.iter_mut().enumerate() {
                let k = first + i;
                forward_kinematics(model, ws, &q[k]);
                for (x, &b) in x.iter_mut().zip(&bodies) {
                    *x = ws.o_x_i[b];
                }
                **c = centre_of_mass(model, ws);
                rnea(model, ws, &q[k], &v[k], &a[k], None);
                **w = root_wrench(model, ws);
            }
        },
        report,
    );
    drop(frames);
    (reached == n).then_some((needed, com, Poses { bodies, at }))
}

/// Pass 3's outputs: `tau`, `residual` and the kept moments with their bodies.
type MomentsOut<'a> = (
    &'a mut [Vec<f64>],
    &'a mut [[f64; 6]],
    (&'a [usize], &'a mut [Vector3<f64>]),
);

/// One frame of pass 3's outputs.
type Frame3<'a> = (&'a mut Vec<f64>, &'a mut [f64; 6], &'a mut [Vector3<f64>]);

/// Pass 3: at every frame, RNEA with the feet's wrenches `wrenches` (`[frame * feet + j]`,
/// world axes about the world origin, acting on `bodies[j]`): the generalized forces into
/// `tau`, what the root still supplies, about the root's origin, into `residual`, and the
/// net moment `f.ang` (the body's frame) of each of `moment_bodies` into `moments`
/// (`[frame * moment_bodies.len() + j]`). Frames in parallel as in [`needed_wrenches`].
/// False when stopped.
#[allow(clippy::too_many_arguments)]
pub(super) fn with_ground_reactions(
    model: &Model,
    root: usize,
    poses: &Poses,
    bodies: &[usize],
    wrenches: &[ForceVec],
    [q, v, a]: [&[Vec<f64>]; 3],
    (tau, residual, (moment_bodies, moments)): MomentsOut,
    report: &mut dyn FnMut(usize) -> bool,
) -> bool {
    let n = tau.len();
    let nf = bodies.len();
    let nm = moment_bodies.len();
    let mut frames: Vec<Frame3> = if nm == 0 {
        tau.iter_mut()
            .zip(residual.iter_mut())
            .map(|(t, r)| (t, r, &mut [][..]))
            .collect()
    } else {
        tau.iter_mut()
            .zip(residual.iter_mut())
            .zip(moments.chunks_mut(nm))
            .map(|((t, r), m)| (t, r, m))
            .collect()
    };
    let mut scratch =
        crate::par::scratch(|| (Workspace::new(model), vec![ForceVec::ZERO; model.nbodies()]));
    let reached = crate::par::rounds(
        &mut frames,
        PROGRESS_EVERY,
        &mut scratch,
        |(ws, f_ext), first, block| {
            for (i, (tau, residual, m)) in block.iter_mut().enumerate() {
                let k = first + i;
                poses.restore(k, &mut ws.o_x_i);
                // the ground's loads, each in the frame of the body it acts on
                f_ext.fill(ForceVec::ZERO);
                for (w, &b) in wrenches[k * nf..(k + 1) * nf].iter().zip(bodies) {
                    f_ext[b] += ws.o_x_i[b].act_inv_force(w);
                }
                // inverse dynamics with the ground reactions; what the root still supplies
                let t = rnea(model, ws, &q[k], &v[k], &a[k], Some(f_ext));
                tau.copy_from_slice(t.as_slice());
                **residual = about(&root_wrench(model, ws), &ws.o_x_i[root].trans);
                for (m, &b) in m.iter_mut().zip(moment_bodies) {
                    *m = ws.f[b].ang;
                }
            }
        },
        report,
    );
    reached == n
}
