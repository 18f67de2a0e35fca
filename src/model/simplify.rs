//! "Model only what a scene requires": locking joints and pruning to a subtree remove degrees of
//! freedom from a [`Model`], lumping the removed bodies' inertia into the body they are now
//! welded to.
//!
//! A locked joint is held at its neutral configuration (q = 0: the rest pose for BVH models), or
//! at a configuration given ([`lock_bodies_at`]: e.g. its mean pose over a take), so the reduced
//! model is exact for motions in which the locked coordinates stay there; at rest: its
//! inverse dynamics equals the full model's for the kept coordinates when the locked ones have
//! `q = 0`, `v = a = 0` (the lumped inertia is the composite rigid body of Featherstone 2008,
//! §6.2). Bodies welded to the world keep their mass in the world's inertia entry, so
//! [`Model::total_mass`] is unchanged; the dynamics never read it.
//!
//! A removed body's drawing shape moves with it when the body it joins has none; otherwise it
//! is dropped.

use crate::error::Error;
use crate::model::{Model, ModelBuilder, Superquadric};
use crate::spatial::SpatialTransform;

/// A reduced model and where every body of the original went.
#[derive(Debug, Clone)]
pub struct Reduction {
    /// The reduced model.
    pub model: Model,
    /// For each body of the original model: the body of the reduced model it is part of, and
    /// its rest pose in that body's frame (identity for kept bodies).
    pub body_map: Vec<(usize, SpatialTransform)>,
    /// For each body of the original model: its index in the reduced model if its joint was
    /// kept.
    pub kept: Vec<Option<usize>>,
}

/// Removes the joints of the bodies with `lock[i] == true` (`lock[0]`, the world, is ignored):
/// each such body is welded to its parent at the joint's neutral configuration.
pub fn lock_bodies(model: &Model, lock: &[bool]) -> Reduction {
    lock_bodies_at(model, lock, None)
}

/// [`lock_bodies`] with each locked joint held at its coordinates in `hold` (a configuration of
/// `model`, `nq` long: e.g. the mean pose over a take, [`mean_configuration`]) instead of its
/// neutral one; `None`: neutral. The reduced model is then exact for motions in which the
/// locked coordinates stay at `hold` with `v = a = 0`.
pub fn lock_bodies_at(model: &Model, lock: &[bool], hold: Option<&[f64]>) -> Reduction {
    let n = model.nbodies();
    let mut b = ModelBuilder::new(model.name.clone(), model.gravity);
    let mut body_map = vec![(0usize, SpatialTransform::IDENTITY); n];
    let mut kept = vec![None; n];
    kept[0] = Some(0);
    let mut damping = vec![];
    let mut world_inertia = model.inertia[0];
    for i in 1..n {
        let joint = &model.joints[i];
        let (target, x_t_p) = body_map[model.parent[i]];
        let placement = x_t_p.compose(&model.placement[i]);
        if lock.get(i).copied().unwrap_or(false) {
            // weld body i to `target` where it is held: lump its inertia, move its shape
            let mut q0 = [0.0; 7];
            match hold {
                Some(h) => {
                    let iq = model.idx_q[i];
                    q0[..joint.nq()].copy_from_slice(&h[iq..iq + joint.nq()]);
                }
                None => joint.neutral(&mut q0[..joint.nq()]),
            }
            let x = placement.compose(&joint.transform(&q0[..joint.nq()]));
            body_map[i] = (target, x);
            let lumped = model.inertia[i].transformed(&x);
            if target == 0 {
                world_inertia = world_inertia.add(&lumped);
            } else {
                let sum = b.model().inertia[target].add(&lumped);
                b.set_inertia(target, sum);
                if let (None, Some(s)) = (b.model().shapes[target], model.shapes[i]) {
                    b.set_shape(target, move_shape(&s, &x));
                }
            }
        } else {
            let k = b.add_body(
                target,
                model.body_names[i].clone(),
                model.joint_names[i].clone(),
                *joint,
                placement,
                model.inertia[i],
            );
            if let Some(s) = model.shapes[i] {
                b.set_shape(k, s);
            }
            let iv = model.idx_v[i];
            damping.extend_from_slice(&model.damping[iv..iv + joint.nv()]);
            body_map[i] = (k, SpatialTransform::IDENTITY);
            kept[i] = Some(k);
        }
    }
    let mut reduced = b.build();
    reduced.inertia[0] = world_inertia;
    reduced.damping = damping;
    Reduction {
        model: reduced,
        body_map,
        kept,
    }
}

/// The mean configuration of `model` over the configurations `qs` (each `nq` long): the
/// arithmetic mean of every revolute and prismatic coordinate and of a free joint's position;
/// for a quaternion (spherical and free joints), the normalized sum of the quaternions each
/// turned to the hemisphere of the first (a chordal mean, close to the rotation mean for the
/// spreads of a joint over a take). Neutral for an empty `qs`.
pub fn mean_configuration<'a>(model: &Model, qs: impl IntoIterator<Item = &'a [f64]>) -> Vec<f64> {
    let mut sum = vec![0.0; model.nq];
    let mut first: Option<Vec<f64>> = None;
    let mut count = 0usize;
    let quat = |i: usize| match model.joints[i] {
        crate::model::JointKind::Spherical => Some(model.idx_q[i]),
        crate::model::JointKind::Free => Some(model.idx_q[i] + 3),
        _ => None,
    };
    for q in qs {
        let f = first.get_or_insert_with(|| q.to_vec());
        for (s, x) in sum.iter_mut().zip(q) {
            *s += x;
        }
        // quaternions: q and −q are the same rotation; add the one near the first's
        for i in 1..model.nbodies() {
            if let Some(k) = quat(i) {
                let dot: f64 = (0..4).map(|c| q[k + c] * f[k + c]).sum();
                if dot < 0.0 {
                    for c in 0..4 {
                        sum[k + c] -= 2.0 * q[k + c];
                    }
                }
            }
        }
        count += 1;
    }
    if count == 0 {
        return model.neutral();
    }
    for s in &mut sum {
        *s /= count as f64;
    }
    model.normalize(&mut sum);
    sum
}

/// `shape` (given in a body frame b) expressed in frame a, where `x` is b's pose in a.
fn move_shape(shape: &Superquadric, x: &SpatialTransform) -> Superquadric {
    Superquadric {
        center: x.transform_point(&shape.center),
        rot: x.rot * shape.rot,
        ..*shape
    }
}

/// The bodies whose joint or body name is one of `names`.
///
/// Errors: a name that is neither, listing the joints there are.
pub fn bodies_named(model: &Model, names: &[impl AsRef<str>]) -> Result<Vec<bool>, Error> {
    let mut lock = vec![false; model.nbodies()];
    for name in names {
        let name = name.as_ref();
        let mut found = false;
        for (i, l) in lock.iter_mut().enumerate().skip(1) {
            if model.joint_names[i] == name || model.body_names[i] == name {
                *l = true;
                found = true;
            }
        }
        if !found {
            return Err(Error::Invalid(format!(
                "cannot lock {name:?}: no joint or body has that name (joints: {})",
                model.joint_names[1..].join(", ")
            )));
        }
    }
    Ok(lock)
}

/// Locks the joints named in `names` (joint or body names).
pub fn lock(model: &Model, names: &[impl AsRef<str>]) -> Result<Reduction, Error> {
    Ok(lock_bodies(model, &bodies_named(model, names)?))
}

/// The bodies outside the subtree of interest rooted at `body`: everything except `body`, its
/// descendants and its ancestors (the chain that carries it).
pub fn outside_subtree(model: &Model, body: usize) -> Vec<bool> {
    let n = model.nbodies();
    let mut keep = vec![false; n];
    // ancestors
    let mut i = body;
    while i != 0 {
        keep[i] = true;
        i = model.parent[i];
    }
    // descendants (parent < child: one forward pass)
    for i in body + 1..n {
        if keep[model.parent[i]] && model.parent[i] >= body {
            keep[i] = true;
        }
    }
    keep[0] = true;
    keep.iter().map(|k| !k).collect()
}

/// Keeps only the subtree rooted at `body` and the chain from the world to it; every other
/// branch is welded, at rest, to the body it hangs from.
pub fn prune_to_subtree(model: &Model, body: usize) -> Reduction {
    lock_bodies(model, &outside_subtree(model, body))
}

#[cfg(test)]
mod tests {
    //! Locking the middle joint of a 3-link chain leaves 2 DOF whose inverse dynamics equals
    //! the full model's with the middle joint at rest.
    use super::*;
    use crate::dynamics::{Workspace, rnea};
    use crate::model::JointKind;
    use crate::spatial::SpatialInertia;
    use nalgebra::{Matrix3, Vector3};

    fn chain() -> Model {
        let mut b = ModelBuilder::new("chain", Vector3::new(0.0, 0.0, -9.81));
        let link = |m: f64| {
            SpatialInertia::new(
                m,
                Vector3::new(0.1, 0.02, 0.25),
                Matrix3::from_diagonal(&Vector3::new(0.02, 0.03, 0.01)),
            )
        };
        let mut p = 0;
        for (k, axis) in [Vector3::x(), Vector3::y(), Vector3::z()]
            .iter()
            .enumerate()
        {
            p = b.add_body(
                p,
                format!("b{k}"),
                format!("j{k}"),
                JointKind::Revolute { axis: *axis },
                SpatialTransform::from_translation(Vector3::new(0.0, 0.1, 0.5)),
                link(1.0 + k as f64),
            );
        }
        b.build()
    }

    #[test]
    fn locked_joint_rnea_equals_full_model_at_rest() {
        let full = chain();
        let r = lock(&full, &["j1"]).unwrap();
        assert_eq!(r.model.nv, 2);
        assert!((r.model.total_mass() - full.total_mass()).abs() < 1e-12);
        let (q, v, a) = ([0.3, 0.0, -0.7], [1.1, 0.0, 0.4], [-0.5, 0.0, 2.0]);
        let mut ws = Workspace::new(&full);
        let tau = rnea(&full, &mut ws, &q, &v, &a, None).clone();
        let mut ws_r = Workspace::new(&r.model);
        let tau_r = rnea(
            &r.model,
            &mut ws_r,
            &[q[0], q[2]],
            &[v[0], v[2]],
            &[a[0], a[2]],
            None,
        );
        assert!((tau_r[0] - tau[0]).abs() < 1e-12, "{tau_r} vs {tau}");
        assert!((tau_r[1] - tau[2]).abs() < 1e-12, "{tau_r} vs {tau}");
        assert!(lock(&full, &["nope"]).is_err());
    }

    #[test]
    fn pruning_to_a_leaf_keeps_its_chain() {
        // a branch (body 4) off body 1, beside the subtree rooted at body 2
        let mut b = ModelBuilder::new("tree", Vector3::zeros());
        let full = chain();
        for i in 1..full.nbodies() {
            b.add_body(
                full.parent[i],
                full.body_names[i].clone(),
                full.joint_names[i].clone(),
                full.joints[i],
                full.placement[i],
                full.inertia[i],
            );
        }
        b.add_body(
            1,
            "branch",
            "jb",
            JointKind::Revolute { axis: Vector3::z() },
            SpatialTransform::from_translation(Vector3::new(0.3, 0.0, 0.0)),
            full.inertia[1],
        );
        let tree = b.build();
        assert_eq!(
            outside_subtree(&tree, 2),
            vec![false, false, false, false, true]
        );
        let r = prune_to_subtree(&tree, 2);
        assert_eq!(r.model.nv, 3);
        assert_eq!(r.body_map[4].0, 1);
        assert!((r.model.total_mass() - tree.total_mass()).abs() < 1e-12);
    }
}
