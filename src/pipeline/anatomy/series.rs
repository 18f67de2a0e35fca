//! The anatomical series in two parts: what a change of masses does not touch, and the
//! moments that it does.
//!
//! [`Calibration`] is everything the series read from the take's motion alone: one forward
//! kinematics pass (the world pose of every mapped joint's body at every frame), the segment
//! frames calibrated on it, and what the series read of them: the angle columns and, per
//! frame, each joint coordinate system's axes the moments are projected on
//! ([`jcs::joint_angles_axes`]), the column names and notes. It depends on the model's kinematics
//! (tree, joints, placements), the map, the up axis and `q`, never on a mass or an inertia, so
//! the workbench keeps it across a `body.mass` or `link.<joint>.mass` edit
//! ([`Calibration::fits`]). [`Calibration::series`] then turns the net moments of inverse
//! dynamics (`ws.f[body].ang` of RNEA, in the body's frame, for each of
//! [`Calibration::moment_bodies`]) into the moment columns: the moment in world axes is the
//! kept pose's rotation times it, projected on the kept axes ([`jcs::joint_moments`]),
//! exactly what a single pass computes, so the table is bit-identical. A mass edit redoes
//! only these projections, not the segment frames and angles.
//!
//! The moments come from any RNEA over the same `q, v, a`: [`net_moments`] runs one with the
//! take's ground reactions (as `articula anatomy` did), [`inverse_dynamics_and_moments`] the
//! one inverse dynamics runs anyway without contact (one RNEA per frame for torques and
//! moments).

use super::{AXES, unwrap_degrees};
use super::{Anatomy, Joint, Posed, Take, find_take_human, frame_angles, joints_of, posed};
use crate::dynamics::anatomy as jcs;
use crate::dynamics::grf::GroundReactions;
use crate::dynamics::{self, Workspace};
use crate::error::Error;
use crate::pipeline::States;
use crate::spatial::SpatialTransform;
use nalgebra::Vector3;

/// What the anatomical series read that masses do not change (see the module doc).
pub struct Calibration {
    /// The anatomical joints and their segment frames.
    joints: Vec<Joint>,
    /// Three per joint (flexion, adduction, rotation; deg, whole turns unwrapped), one value
    /// per frame: the angle columns of the series.
    angles: Vec<Vec<f64>>,
    /// `[frame * moment joints + i]`: the joint coordinate system's axes (world) of the
    /// `i`-th joint with a moment, which its moments are projected on.
    axes: Vec<[Vector3<f64>; 3]>,
    /// Why the series cannot be made (a frame where a joint's segments have no frame).
    missing: Option<String>,
    /// The series' column names (`knee_l:flexion:angle`, …).
    names: Vec<String>,
    /// How the joints and frames were found.
    notes: Vec<String>,
    /// The bodies whose world poses are kept: each mapped joint's body, sorted, each once.
    kept: Vec<usize>,
    /// `[frame * kept.len() + j]`: world pose `0X_i` of body `kept[j]` (as
    /// `forward_kinematics` writes `ws.o_x_i`).
    poses: Vec<SpatialTransform>,
    /// What the calibration was made from (for [`fits`](Self::fits)): the model's
    /// kinematics and the take's configurations.
    key: Key,
}

/// The inputs of a calibration besides the BVH skeleton's shape.
struct Key {
    parent: Vec<usize>,
    joints: Vec<crate::model::joint::JointKind>,
    placement: Vec<SpatialTransform>,
    map: crate::model::bvh::BvhMap,
    up: crate::io::bvh::UpAxis,
    scale_to_m: f64,
    frame_time: f64,
    human: Result<crate::model::skeleton::Human, String>,
    /// The take's states (shared, not copied), whose `q` the calibration read.
    states: std::sync::Arc<crate::pipeline::States>,
}

impl Key {
    fn of(take: &Take) -> Self {
        Key {
            parent: take.model.parent.clone(),
            joints: take.model.joints.clone(),
            placement: take.model.placement.clone(),
            map: take.map.clone(),
            up: take.up,
            scale_to_m: take.scale_to_m,
            frame_time: take.bvh.frame_time,
            human: take.human.clone(),
            states: take.states.clone(),
        }
    }

    fn fits(&self, take: &Take) -> bool {
        let m = &take.model;
        self.parent == m.parent
            && self.joints == m.joints
            && self.placement == m.placement
            && self.up == take.up
            && self.scale_to_m == take.scale_to_m
            && self.frame_time == take.bvh.frame_time
            && self.map == take.map
            && self.human == take.human
            && (std::sync::Arc::ptr_eq(&self.states, &take.states)
                || self.states.q == take.states.q)
    }
}

impl std::fmt::Debug for Calibration {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Calibration")
            .field("names", &self.names.len())
            .field("frames", &self.angles.first().map_or(0, Vec::len))
            .field("bodies", &self.kept)
            .finish_non_exhaustive()
    }
}

impl Calibration {
    /// One kinematics pass over the take and the segment frames calibrated on it; an error
    /// for a take that is not a human's.
    pub fn new(take: &Take) -> Result<Self, Error> {
        let human = find_take_human(take)?;
        let model = &take.model;
        let s = &take.states;
        let mut ws = Workspace::new(model);
        // the world poses the moments read later (each mapped joint's body), kept from this
        // one kinematics pass
        let kept = moment_bodies(take);
        let mut poses = Vec::with_capacity(s.len() * kept.len());
        let frames: Vec<Posed> =
            s.q.iter()
                .map(|q| {
                    dynamics::forward_kinematics(model, &mut ws, q);
                    poses.extend(kept.iter().map(|&b| ws.o_x_i[b]));
                    posed(take, &ws)
                })
                .collect();
        let mut notes = vec![];
        if !human.sides_from_names {
            notes.push(
                "left and right were told from the geometry (forward × up), not the names".into(),
            );
        }
        let joints = joints_of(take, &human, &frames, &mut notes);
        let up = Vector3::ith(take.up.index(), 1.0);
        let (angles, axes, missing) = angles_and_axes(take, &joints, &frames, &up);
        let mut names = vec![];
        for j in &joints {
            for what in ["angle", "moment", "moment_per_kg"] {
                if what != "angle" && j.moment_at.is_none() {
                    continue;
                }
                for axis in AXES {
                    names.push(format!("{}{}:{axis}:{what}", j.kind.name, j.suffix));
                }
            }
        }
        Ok(Self {
            joints,
            angles,
            axes,
            missing,
            names,
            notes,
            kept,
            poses,
            key: Key::of(take),
        })
    }

    /// True when this calibration is the one [`new`](Self::new) would make of `take`: the
    /// same model kinematics, map, up axis, unit, landmarks and configurations (masses may
    /// differ). The BVH skeleton is `take`'s own when the caller keeps it (the workbench's
    /// edits of one take).
    pub fn fits(&self, take: &Take) -> bool {
        self.key.fits(take)
    }

    /// The bodies whose net moments [`series`](Self::series) reads, in the order it reads
    /// them: [`moment_bodies`] of the take.
    pub fn bodies(&self) -> &[usize] {
        &self.kept
    }

    /// The series of every frame from the net moments of inverse dynamics: `moments[k *
    /// bodies().len() + j]` is `f.ang` (N·m, the body's frame, as RNEA writes `ws.f`) of
    /// body `bodies()[j]` at frame `k`; `grf` gives the contact columns. Frames in
    /// parallel.
    pub fn series(
        &self,
        take: &Take,
        moments: &[Vector3<f64>],
        grf: Option<&GroundReactions>,
    ) -> Result<Anatomy, Error> {
        if let Some(why) = &self.missing {
            return Err(Error::Numerical(why.clone()));
        }
        let s = &take.states;
        let n = s.len();
        let nb = self.kept.len();
        let nm = self.joints.iter().filter(|j| j.moment_at.is_some()).count();
        let mass = take.model.total_mass();
        // the joints with a moment, each with its kept body
        let with_moment: Vec<(&Joint, usize)> = (self.joints.iter())
            .filter_map(|j| {
                let at = j.moment_at?;
                let b = self.kept.binary_search(&take.map.joints[at].body);
                Some((j, b.expect("a mapped joint's body")))
            })
            .collect();
        // the moments frame by frame (each frame's kept poses, moments and axes read in order):
        // the world moment, the kept pose's rotation times the body-frame one, on the axes
        let mut moment = vec![[vec![0.0; n], vec![0.0; n], vec![0.0; n]]; nm];
        for k in 0..n {
            let (poses, body) = (&self.poses[k * nb..], &moments[k * nb..]);
            for (i, ((j, b), out)) in with_moment.iter().zip(&mut moment).enumerate() {
                let world = poses[*b].rot * body[*b];
                let m =
                    jcs::joint_moments(j.kind, j.suffix != "_l", &self.axes[k * nm + i], &world);
                for (col, x) in out.iter_mut().zip(m) {
                    col[k] = x;
                }
            }
        }
        let mut columns = Vec::with_capacity(self.names.len());
        let mut angles = self.angles.iter();
        let mut moment = moment.into_iter();
        for j in &self.joints {
            columns.extend(angles.by_ref().take(3).cloned());
            if j.moment_at.is_none() {
                continue;
            }
            let moment = moment.next().expect("a moment per joint with one");
            let per_kg: Vec<Vec<f64>> = moment
                .iter()
                .map(|col| col.iter().map(|x| x / mass).collect())
                .collect();
            columns.extend(moment);
            columns.extend(per_kg);
        }
        let contact = grf.map_or(vec![], |g| {
            g.feet
                .iter()
                .enumerate()
                .map(|(j, f)| (f.clone(), g.contact.iter().map(|c| c[j]).collect()))
                .collect()
        });
        Ok(Anatomy {
            time: s.time.clone(),
            names: self.names.clone(),
            columns,
            mass_kg: mass,
            notes: self.notes.clone(),
            contact,
            consistency: None,
            edge: super::super::edge_frames(take),
            include_edges: false,
        })
    }

    /// The net moments [`series`](Self::series) reads, by RNEA at every frame with the
    /// ground reactions `grf` (none: without contact), the loads taken from RNEA's moments
    /// without them as the estimate takes them ([`GroundReactions::take_from`]); those the
    /// estimate kept ([`GroundReactions::moments`]) when it kept these bodies'. Frames in
    /// parallel.
    pub fn net_moments(&self, take: &Take, grf: Option<&GroundReactions>) -> Vec<Vector3<f64>> {
        if let Some(g) = grf
            && g.moment_bodies == self.kept
        {
            return g.moments.clone();
        }
        let model = &take.model;
        let s = &take.states;
        let nb = self.kept.len();
        let mut out = vec![Vector3::zeros(); s.len() * nb];
        if nb == 0 {
            return out;
        }
        let mut rows: Vec<&mut [Vector3<f64>]> = out.chunks_mut(nb).collect();
        let mut scratch = crate::par::scratch(|| Workspace::new(model));
        crate::par::for_each_block(&mut rows, 64, &mut scratch, |ws, first, block| {
            for (i, row) in block.iter_mut().enumerate() {
                let k = first + i;
                dynamics::rnea(model, ws, &s.q[k], &s.v[k], &s.a[k], None);
                for (m, &b) in row.iter_mut().zip(&self.kept) {
                    *m = ws.f[b].ang;
                }
                if let Some(g) = grf {
                    // the poses along the feet's paths
                    dynamics::forward_kinematics(model, ws, &s.q[k]);
                    g.take_from(model, k, ws, None, (&self.kept, row));
                }
            }
        });
        out
    }
}

/// One frame's angles, moment axes and whether a joint had no segment frame.
type FrameRow<'a> = (&'a mut [f64], &'a mut [[Vector3<f64>; 3]], &'a mut bool);

/// The angle columns, moment axes and missing frame of [`Calibration`].
type AnglesAndAxes = (Vec<Vec<f64>>, Vec<[Vector3<f64>; 3]>, Option<String>);

/// The angle columns (deg, whole turns unwrapped) and the moment axes of [`Calibration`],
/// frames in parallel ([`frame_angles`]); and why the series cannot be made, when a frame has
/// a joint whose segments have no frame.
fn angles_and_axes(
    take: &Take,
    joints: &[Joint],
    frames: &[Posed],
    up: &Vector3<f64>,
) -> AnglesAndAxes {
    let n = frames.len();
    let na = 3 * joints.len();
    let nm = joints.iter().filter(|j| j.moment_at.is_some()).count();
    let mut values = vec![0.0; n * na];
    let mut axes = vec![[Vector3::zeros(); 3]; n * nm];
    let mut missing = vec![false; n];
    if na > 0 {
        let mut rows: Vec<FrameRow> = if nm == 0 {
            values
                .chunks_mut(na)
                .zip(missing.iter_mut())
                .map(|(v, m)| (v, &mut [][..], m))
                .collect()
        } else {
            values
                .chunks_mut(na)
                .zip(axes.chunks_mut(nm))
                .zip(missing.iter_mut())
                .map(|((v, a), m)| (v, a, m))
                .collect()
        };
        let mut scratch = crate::par::scratch(|| ());
        let block = crate::par::even_block(n).min(256);
        crate::par::for_each_block(&mut rows, block, &mut scratch, |_, first, block| {
            for (i, (row, axes, missing)) in block.iter_mut().enumerate() {
                **missing = frame_angles(joints, &frames[first + i], up, row, axes).is_none();
            }
        });
    }
    let why = missing.iter().position(|m| *m).map(|k| {
        let p = &frames[k];
        let j = joints
            .iter()
            .find(|j| j.proximal.at(p, up).is_none() || j.distal.at(p, up).is_none())
            .unwrap_or(&joints[0]);
        format!(
            "{}: frame {k}: the {}{} joint's segments have no frame (a bone of zero length or \
             parallel to its lateral axis)",
            take.path.display(),
            j.kind.name,
            j.suffix
        )
    });
    let mut angles: Vec<Vec<f64>> = (0..na)
        .map(|c| (0..n).map(|k| values[k * na + c]).collect())
        .collect();
    for col in &mut angles {
        unwrap_degrees(col);
    }
    (angles, axes, why)
}

/// The bodies whose net moments the anatomical series read: each mapped joint's body, sorted,
/// each once (what [`consistent_take_keeping`] asks the estimate to keep).
///
/// [`consistent_take_keeping`]: crate::pipeline::consistency::consistent_take_keeping
pub fn moment_bodies(take: &Take) -> Vec<usize> {
    let mut b: Vec<usize> = take.map.joints.iter().map(|jm| jm.body).collect();
    b.sort_unstable();
    b.dedup();
    b
}

/// `tau[frame][nv]` and `moments[frame * bodies + j]` of [`inverse_dynamics_and_moments`].
pub type TorquesAndMoments = (Vec<Vec<f64>>, Vec<Vector3<f64>>);

/// Inverse dynamics without contact and the net moments of `bodies` from the same RNEA:
/// `tau[frame]` as [`inverse_dynamics_with`](crate::pipeline::inverse_dynamics_with) computes
/// it (bit for bit), and `moments[frame * bodies.len() + j]` the body-frame `f.ang` of
/// `bodies[j]` ([`Calibration::series`]'s layout). Frames in parallel, progress (0‥1) to
/// `keep_going` every [`PROGRESS_EVERY`](crate::pipeline::PROGRESS_EVERY) frames; `None` when
/// it returned false.
pub fn inverse_dynamics_and_moments(
    model: &crate::model::Model,
    states: &States,
    bodies: &[usize],
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Option<TorquesAndMoments> {
    let n = states.len();
    let nb = bodies.len();
    let mut tau = vec![vec![0.0; model.nv]; n];
    let mut moments = vec![Vector3::zeros(); n * nb];
    let mut rows: Vec<(&mut Vec<f64>, &mut [Vector3<f64>])> = if nb == 0 {
        tau.iter_mut().map(|t| (t, &mut [][..])).collect()
    } else {
        tau.iter_mut().zip(moments.chunks_mut(nb)).collect()
    };
    let mut workspaces = crate::par::scratch(|| Workspace::new(model));
    let reached = crate::par::for_each_block_reporting(
        &mut rows,
        crate::pipeline::PROGRESS_EVERY,
        &mut workspaces,
        |ws, first, block| {
            for (i, (tau, m)) in block.iter_mut().enumerate() {
                let k = first + i;
                let t = dynamics::rnea(model, ws, &states.q[k], &states.v[k], &states.a[k], None);
                tau.copy_from_slice(t.as_slice());
                for (m, &b) in m.iter_mut().zip(bodies) {
                    *m = ws.f[b].ang;
                }
            }
        },
        &mut |k| keep_going(k as f64 / n.max(1) as f64),
    );
    drop(rows);
    (reached == n).then_some((tau, moments))
}
