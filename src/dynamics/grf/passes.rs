//! The frame passes of the ground-reaction estimate, each computing what it reads once.
//!
//! 1. [`needed_wrenches`] (frames in parallel): forward kinematics and RNEA without external
//!    forces at every frame — the whole-body wrench the motion needs, and the joint torques
//!    without the ground when they are asked for — and the world poses of the few bodies the
//!    later steps read ([`Poses`]: the feet's ankle and toe bodies, the root and the
//!    root-level bodies). The contact phases, the floor, the supports, the ground loads and
//!    the residual all read those poses, so no later step runs the whole kinematics again.
//! 2. the loads' assignment (serial in the caller: a foot's load is carried from frame to
//!    frame), from the kept poses; the residual is the needed wrench less the feet's.
//! 3. [`with_ground_reactions`] (frames in parallel): the feet's loads taken from pass 1's
//!    torques along the feet's paths to the world (inverse dynamics is linear in the external
//!    forces), instead of a second RNEA.
//!
//! Every frame computes the same operations in the same order as a kinematics pass of its own
//! would, so the kept poses are bit-identical to recomputed ones, and the results do not
//! depend on the number of threads (`crate::par`).

use super::{PROGRESS_EVERY, root_wrench};
use crate::dynamics::kinematics::forward_kinematics_of;
use crate::dynamics::residual::centre_of_mass;
use crate::dynamics::rnea::{JointStep, rnea_after_kinematics};
use crate::dynamics::{Workspace, forward_kinematics, forward_kinematics_through};
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
    /// for the foot paths without the dynamics ([`super::fitted_foot_paths`]).
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

/// What pass 1 keeps for pass 3 besides the needed wrenches: RNEA's generalized forces without
/// the ground (`tau`, one row of `nv` per frame) and the net moment `f.ang` (the body's frame)
/// of each of `bodies` (`moments[frame * bodies.len() + j]`).
pub(super) struct Unloaded<'a> {
    pub tau: &'a mut [Vec<f64>],
    pub bodies: &'a [usize],
    pub moments: &'a mut [Vector3<f64>],
}

/// Pass 1: the whole-body wrench each frame needs (world axes, about the world origin:
/// RNEA without external forces, the force the world gives the root-level bodies), the
/// whole-body centre of mass (m, world), and the poses of `bodies` at every frame; with
/// `unloaded`, also RNEA's torques and the moments pass 3 starts from. Frames in parallel, in
/// blocks of [`PROGRESS_EVERY`]; `report(first)` as blocks finish, as
/// [`crate::par::for_each_block_reporting`] says. `None` when stopped.
pub(super) fn needed_wrenches(
    model: &Model,
    bodies: Vec<usize>,
    [q, v, a]: [&[Vec<f64>]; 3],
    unloaded: Option<Unloaded>,
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
        Option<(&'a mut Vec<f64>, &'a mut [Vector3<f64>])>,
    );
    let (moment_bodies, nm) = unloaded
        .as_ref()
        .map_or((&[][..], 0), |u| (u.bodies, u.bodies.len()));
    let mut frames: Vec<Frame> = needed
        .iter_mut()
        .zip(com.iter_mut())
        .zip(at.chunks_mut(m))
        .map(|((w, c), x)| (w, c, x, None))
        .collect();
    if let Some(u) = unloaded {
        // each frame's row of torques and of moments (none without bodies)
        let mut moments = u.moments.chunks_mut(nm.max(1));
        for (f, t) in frames.iter_mut().zip(u.tau.iter_mut()) {
            let mine = if nm > 0 { moments.next() } else { None };
            f.3 = Some((t, mine.unwrap_or_default()));
        }
    }
    let mut workspaces = crate::par::scratch(|| Workspace::new(model));
    let reached = crate::par::for_each_block_reporting(
        &mut frames,
        PROGRESS_EVERY,
        &mut workspaces,
        |ws, first, block| {
            for (i, (w, c, x, keep)) in block.iter_mut().enumerate() {
                let k = first + i;
                forward_kinematics(model, ws, &q[k]);
                for (x, &b) in x.iter_mut().zip(&bodies) {
                    *x = ws.o_x_i[b];
                }
                **c = centre_of_mass(model, ws);
                // (RNEA reads the sines and cosines the kinematics took)
                rnea_after_kinematics(model, ws, &q[k], &v[k], &a[k]);
                **w = root_wrench(model, ws);
                if let Some((t, m)) = keep {
                    t.copy_from_slice(ws.tau.as_slice());
                    for (m, &b) in m.iter_mut().zip(moment_bodies) {
                        *m = ws.f[b].ang;
                    }
                }
            }
        },
        report,
    );
    drop(frames);
    (reached == n).then_some((needed, com, Poses { bodies, at }))
}

/// The bodies on the paths from `bodies` to the world: each of them and every ancestor,
/// ascending (a list [`forward_kinematics_of`] takes).
pub(super) fn paths_to_world(model: &Model, bodies: &[usize]) -> Vec<usize> {
    let mut on = vec![false; model.nbodies()];
    for &b in bodies {
        let mut i = b;
        while i != 0 && !on[i] {
            on[i] = true;
            i = model.parent[i];
        }
    }
    (1..model.nbodies()).filter(|&i| on[i]).collect()
}

/// Pass 3's outputs, holding pass 1's [`Unloaded`] values on entry: `tau` and the kept
/// moments with their bodies (sorted).
type MomentsOut<'a> = (&'a mut [Vec<f64>], (&'a [usize], &'a mut [Vector3<f64>]));

/// One frame of pass 3's outputs.
type Frame3<'a> = (&'a mut Vec<f64>, &'a mut [Vector3<f64>]);

/// Pass 3: the ground reactions' share of the generalized forces and of the kept moments, added
/// to pass 1's (inverse dynamics is linear in the external forces: RNEA with the feet's loads
/// is RNEA without them less `Jᵀ w` of each load). The feet's wrenches `wrenches`
/// (`[frame * feet + j]`, world axes about the world origin) act on `bodies[j]`; a wrench `w`
/// on a body takes `S · w` from each coordinate on the body's path to the world (`S` the
/// coordinate's motion subspace in world axes about the world origin, [`crba`]'s `s_world`: an
/// axis `u` through the body's origin `p` takes `u · (n − p × f)`), and `X* w` (the body's
/// frame) from the net force of each body on that path. Only the poses of the bodies on the
/// feet's paths are needed ([`forward_kinematics_of`]), so the frame costs a few dozen poses
/// instead of RNEA. Frames in parallel as in [`needed_wrenches`]. False when stopped.
///
/// A foot off the floor carries a zero wrench, whose share is a signed zero taken from each
/// value on its path: that changes no bit of a value other than `−0` (`x − (±0) = x`), so such
/// a foot is skipped, and the kinematics run along the loaded feet's paths only
/// ([`Unloaded::skips`] says when that is exact).
///
/// [`crba`]: crate::dynamics::crba
pub(super) fn with_ground_reactions(
    model: &Model,
    bodies: &[usize],
    wrenches: &[ForceVec],
    q: &[Vec<f64>],
    (tau, (moment_bodies, moments)): MomentsOut,
    report: &mut dyn FnMut(usize) -> bool,
) -> bool {
    let n = tau.len();
    let nf = bodies.len();
    let nm = moment_bodies.len();
    let feet = FeetPaths::new(model, bodies, moment_bodies);
    let mut frames: Vec<Frame3> = if nm == 0 {
        tau.iter_mut().map(|t| (t, &mut [][..])).collect()
    } else {
        tau.iter_mut().zip(moments.chunks_mut(nm)).collect()
    };
    let mut scratch = crate::par::scratch(|| Workspace::new(model));
    let reached = crate::par::for_each_block_reporting(
        &mut frames,
        PROGRESS_EVERY,
        &mut scratch,
        |ws, first, block| {
            for (i, (tau, m)) in block.iter_mut().enumerate() {
                let k = first + i;
                let w = &wrenches[k * nf..(k + 1) * nf];
                // the kinematics along the paths of the feet that carry a load
                let loaded = feet.loaded(w);
                let mut posed = feet.path(loaded);
                forward_kinematics_of(model, ws, &q[k], posed);
                for (j, (w, &b)) in w.iter().zip(bodies).enumerate() {
                    if loaded >> j & 1 == 0 && feet.skips(model, j, &q[k], tau, m) {
                        continue;
                    }
                    // (a zero load that must be taken after all: the whole paths posed)
                    if loaded >> j & 1 == 0 && posed.len() < feet.all.len() {
                        posed = &feet.all;
                        forward_kinematics_of(model, ws, &q[k], posed);
                    }
                    take_load(model, ws, w, b, Some(tau), (feet.slot(), m));
                }
            }
        },
        report,
    );
    reached == n
}

/// The feet's paths to the world for pass 3 ([`with_ground_reactions`]), decided once per
/// estimate: those of each set of loaded feet, and each body's place among the kept moments.
struct FeetPaths {
    /// The bodies on the paths of every foot ([`paths_to_world`]).
    all: Vec<usize>,
    /// `[set]`: the bodies on the paths of the feet in `set` (bit `j`: foot `j`), for up to
    /// [`FeetPaths::SETS`] feet; empty beyond (every frame then poses `all`).
    of_set: Vec<Vec<usize>>,
    /// `[foot]`: the bodies on the foot's own path, from the foot up.
    up: Vec<Vec<usize>>,
    /// `[body]`: its index among the kept moments' bodies, if kept.
    slots: Vec<Option<usize>>,
}

impl FeetPaths {
    /// Feet beyond this many are all posed on every frame.
    const SETS: usize = 4;

    fn new(model: &Model, bodies: &[usize], moment_bodies: &[usize]) -> Self {
        let nf = bodies.len();
        let of_set = if nf <= Self::SETS {
            (0..1usize << nf)
                .map(|set| {
                    let feet: Vec<usize> = (0..nf)
                        .filter(|j| set >> j & 1 == 1)
                        .map(|j| bodies[j])
                        .collect();
                    paths_to_world(model, &feet)
                })
                .collect()
        } else {
            vec![]
        };
        let up = bodies
            .iter()
            .map(|&b| {
                std::iter::successors(Some(b), |&i| Some(model.parent[i]))
                    .take_while(|&i| i != 0)
                    .collect()
            })
            .collect();
        let slots = (0..model.nbodies())
            .map(|i| moment_bodies.binary_search(&i).ok())
            .collect();
        Self {
            all: paths_to_world(model, bodies),
            of_set,
            up,
            slots,
        }
    }

    /// The set of feet (bit `j`: foot `j`) whose wrench in `w` is not zero; every foot when
    /// there are more than [`FeetPaths::SETS`].
    fn loaded(&self, w: &[ForceVec]) -> usize {
        if self.of_set.is_empty() {
            return usize::MAX;
        }
        w.iter()
            .enumerate()
            .filter(|(_, w)| w.lin.iter().chain(w.ang.iter()).any(|x| *x != 0.0))
            .fold(0, |set, (j, _)| set | 1 << j)
    }

    /// The bodies on the paths of the feet in `set`.
    fn path(&self, set: usize) -> &[usize] {
        self.of_set.get(set).unwrap_or(&self.all)
    }

    /// Each body's index among the kept moments' bodies.
    fn slot(&self) -> impl Fn(usize) -> Option<usize> + '_ {
        |i| self.slots[i]
    }

    /// Whether foot `j`'s zero wrench may be skipped at a frame of configuration `q` with
    /// the values `tau` and `moments` as they are: its share `x − (±0)` leaves every value
    /// but `−0` as it is, when the poses it would be taken with are finite (`q` finite).
    fn skips(
        &self,
        model: &Model,
        j: usize,
        q: &[f64],
        tau: &[f64],
        moments: &[Vector3<f64>],
    ) -> bool {
        let negative_zero = |x: &f64| *x == 0.0 && x.is_sign_negative();
        q.iter().all(|x| x.is_finite())
            && self.up[j].iter().all(|&i| {
                let iv = model.idx_v[i];
                !tau[iv..iv + model.joints[i].nv()].iter().any(negative_zero)
                    && self.slots[i].is_none_or(|s| !moments[s].iter().any(negative_zero))
            })
    }
}

/// One foot's wrench `w` (world axes, about the world origin) on `body`: taken from the
/// generalized force of every coordinate on the body's path to the world (when `tau` is
/// given) and from the net moment `moments[slot(i)]` of each kept body `i` on it (`slot`: its
/// index among the kept bodies, `None` if not kept; see [`with_ground_reactions`]);
/// `ws.o_x_i` holds the path's poses.
pub(super) fn take_load(
    model: &Model,
    ws: &Workspace,
    w: &ForceVec,
    body: usize,
    mut tau: Option<&mut [f64]>,
    (slot, moments): (impl Fn(usize) -> Option<usize>, &mut [Vector3<f64>]),
) {
    let mut i = body;
    while i != 0 {
        let o = &ws.o_x_i[i];
        if let Some(tau) = tau.as_deref_mut() {
            let iv = model.idx_v[i];
            match ws.joint_steps[i] {
                JointStep::Axis { k, .. }
                | JointStep::Triple { k: [k, _, _], .. }
                | JointStep::InTriple { k } => {
                    // the axis u = R e_k through the body's origin p: u · (n − p × f)
                    let u = o.rot.column(k);
                    tau[iv] -= u.dot(&(w.ang - o.trans.cross(&w.lin)));
                }
                JointStep::General => {
                    let joint = &model.joints[i];
                    for c in 0..joint.nv() {
                        tau[iv + c] -= o.act_motion(&joint.subspace_col(c)).dot(w);
                    }
                }
            }
        }
        if let Some(j) = slot(i) {
            moments[j] -= o.act_inv_force(w).ang;
        }
        i = model.parent[i];
    }
}
