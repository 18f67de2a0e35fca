//! `articula export gltf`: a take as a glTF 2.0 binary for game engines and 3-D tools — the
//! BVH skeleton as nodes, the model's superquadric links as meshes skinned to it, and the take
//! as one animation ([`crate::io::gltf_write`] writes the file).
//!
//! The edge conversions, all here: lengths from file units to metres (`Take::scale_to_m`);
//! axes from the take's up axis to glTF's +Y up by a proper rotation ([`TO_Y_UP`]: Z-up
//! `(x, y, z) → (x, z, −y)`, X-up `(x, y, z) → (−y, x, z)`), applied to every translation `t`
//! as `C·t` and every rotation `R` as `C·R·Cᵀ`, so a joint's glTF world position is `C` times
//! its position in the take (`export positions`); BVH Euler angles to quaternions; frame `k`
//! at the file's time [`Bvh::time`]. Joints with position channels get a translation track
//! (in the mode articula resolved for them), joints with rotation channels a rotation track.

use super::Take;
use crate::error::Error;
use crate::io::bvh::{self, Bvh, UpAxis};
use crate::io::gltf_write::{Rig, RigJoint, RigPart, to_glb};
use crate::report::superquadric::superquadric_points;
use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3};
use std::path::Path;

/// The rotation `C` taking a take's axes to glTF's (+Y up), per up axis: rows of `C`.
pub const TO_Y_UP: [(UpAxis, [[f64; 3]; 3]); 3] = [
    (
        UpAxis::X,
        [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
    ),
    (
        UpAxis::Y,
        [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
    ),
    (
        UpAxis::Z,
        [[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]],
    ),
];

/// Parallels and meridians of each link's superquadric mesh.
const MESH_U: usize = 9;
const MESH_V: usize = 12;

/// `C` for `up` ([`TO_Y_UP`]).
pub fn to_y_up(up: UpAxis) -> Matrix3<f64> {
    let rows = TO_Y_UP
        .iter()
        .find(|(u, _)| *u == up)
        .map_or([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], |r| r.1);
    Matrix3::from_fn(|i, j| rows[i][j])
}

/// `articula export gltf` / the session's `export gltf`: [`take_rig`] written as `.glb`.
pub fn export_gltf(take: &Take, path: &Path) -> Result<(), Error> {
    crate::io::write_atomic(path, &to_glb(&take_rig(take))?)
}

/// The take as a [`Rig`] in glTF's conventions (see the module documentation).
pub fn take_rig(take: &Take) -> Rig {
    let b = super::as_in_file(take, (*take.bvh).clone());
    let c = to_y_up(take.up);
    let s = take.scale_to_m;
    let modes = &take.positions;
    let moves = |j: usize| modes[j] != bvh::ResolvedPosition::None;
    let translation = |j: usize, k: usize| {
        let t = c * bvh::joint_translation(&b.joints[j], modes[j], b.frame(k)) * s;
        [t.x, t.y, t.z]
    };
    let joints = b
        .joints
        .iter()
        .enumerate()
        .map(|(j, joint)| RigJoint {
            name: joint.name.clone(),
            parent: joint.parent,
            rest: if moves(j) && b.frames > 0 {
                translation(j, 0)
            } else {
                let t = c * joint.offset * s;
                [t.x, t.y, t.z]
            },
        })
        .collect();
    let translations = (0..b.joints.len())
        .map(|j| moves(j).then(|| (0..b.frames).map(|k| translation(j, k)).collect()))
        .collect();
    let rotations = b
        .joints
        .iter()
        .map(|joint| {
            joint
                .channels
                .iter()
                .any(|ch| ch.is_rotation())
                .then(|| rotation_track(&b, joint, &c))
        })
        .collect();
    Rig {
        name: take.model.name.clone(),
        joints,
        parts: link_parts(take, &b, &c),
        times: (0..b.frames).map(|k| b.time(k)).collect(),
        translations,
        rotations,
    }
}

/// The joint's rotation at every frame as `[x, y, z, w]` of `C·R·Cᵀ`, each quaternion in the
/// previous one's hemisphere so that interpolation between keys takes the short way.
fn rotation_track(b: &Bvh, joint: &bvh::BvhJoint, c: &Matrix3<f64>) -> Vec<[f64; 4]> {
    let mut prev: Option<UnitQuaternion<f64>> = None;
    (0..b.frames)
        .map(|k| {
            let r = c * bvh::joint_rotation(joint, b.frame(k)) * c.transpose();
            let mut q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r));
            if prev.is_some_and(|p| p.coords.dot(&q.coords) < 0.0) {
                q = UnitQuaternion::new_unchecked(-q.into_inner());
            }
            prev = Some(q);
            [q.i, q.j, q.k, q.w]
        })
        .collect()
}

/// Each body's superquadric (the model's drawing shapes) as a mesh moving with the first BVH
/// joint the body carries, its vertices in that joint's frame (glTF axes, m).
fn link_parts(take: &Take, b: &Bvh, c: &Matrix3<f64>) -> Vec<RigPart> {
    let mut used = vec![false; take.model.shapes.len()];
    let mut parts = vec![];
    for (j, map) in take.map.joints.iter().enumerate().take(b.joints.len()) {
        let Some(Some(sq)) = take.model.shapes.get(map.body) else {
            continue;
        };
        if std::mem::replace(&mut used[map.body], true) {
            continue;
        }
        // body frame → the BVH joint's frame (`map.frame` is the joint's pose in the body)
        let f = &map.frame;
        let vertices = superquadric_points(sq, MESH_U, MESH_V)
            .iter()
            .map(|p| {
                let v = c * (f.rot.transpose() * (p - f.trans));
                [v.x, v.y, v.z]
            })
            .collect();
        parts.push(RigPart {
            joint: j,
            vertices,
            triangles: grid_triangles(MESH_U, MESH_V),
        });
    }
    parts
}

/// Triangles of a [`superquadric_points`] grid (`n_u` parallels from pole to pole, `n_v`
/// meridians), counter-clockwise from outside, none on the degenerate pole rows.
fn grid_triangles(n_u: usize, n_v: usize) -> Vec<[u32; 3]> {
    let mut out = Vec::with_capacity(2 * n_u * n_v);
    let at = |i: usize, j: usize| (i * n_v + j % n_v) as u32;
    for i in 0..n_u - 1 {
        for j in 0..n_v {
            let (a, b, c, d) = (at(i, j), at(i, j + 1), at(i + 1, j), at(i + 1, j + 1));
            if i > 0 {
                out.push([a, b, c]);
            }
            if i + 2 < n_u {
                out.push([b, d, c]);
            }
        }
    }
    out
}

/// World position (glTF axes, m) of every joint of `rig` at key `k`, by composing the nodes'
/// translations and rotations as a glTF reader does (used by tests and checks).
pub fn rig_world_positions(rig: &Rig, k: usize) -> Vec<Vector3<f64>> {
    let mut p: Vec<Vector3<f64>> = Vec::with_capacity(rig.joints.len());
    let mut r: Vec<UnitQuaternion<f64>> = Vec::with_capacity(rig.joints.len());
    for (j, joint) in rig.joints.iter().enumerate() {
        let t = Vector3::from(rig.translations[j].as_ref().map_or(joint.rest, |t| t[k]));
        let q = rig.rotations[j]
            .as_ref()
            .map_or(UnitQuaternion::identity(), |q| {
                let [x, y, z, w] = q[k];
                UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(w, x, y, z))
            });
        match joint.parent {
            Some(pa) => {
                p.push(p[pa] + r[pa] * t);
                r.push(r[pa] * q);
            }
            None => {
                p.push(t);
                r.push(q);
            }
        }
    }
    p
}
