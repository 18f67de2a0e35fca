//! What a residual reduction found, kept to start the next one from ([`Seed`]): a session
//! that edits the body's masses reduces the same take again and again.
//!
//! The reduction is invariant under a uniform scaling of every mass and rotational inertia
//! (its thresholds are relative: [`super::problem`]), so a body scaled alike is reduced by the
//! same adjustments: the seed's are evaluated on the new model and nothing is solved
//! ([`Start::Scaled`]). Any other change (other inertias, the motion, the frames counted, the
//! feet and contact parameters, the trunk, the bounds, the model's kinematics) and the
//! reduction starts cold, from zero, as `articula id` and `anatomy` do: a result never
//! depends on what a session computed before it. (A Gauss–Newton warm-started from the seed
//! was tried and not kept: the residual is flat along the adjustments, so it stopped near the
//! cold result but not on it, the demo walk's torques 1.1 % RMS and the Bandai walk's 5 % RMS
//! away from those of a fresh session at the same mass, and cmu_01_01's `body.mass` edit
//! still took 1.9–2.4 s.)

use super::{Ground, Motion, ReductionBounds, Trunk};
use crate::model::{JointKind, Model};
use crate::motion::contact::{ContactParams, Foot};
use crate::spatial::{SpatialInertia, SpatialTransform};
use nalgebra::{DVector, Vector3};

/// What residual reduction found, to start another reduction of the same problem from
/// ([`super::reduce_residuals`]); against estimated ground reactions only.
#[derive(Debug, Clone)]
pub struct Seed {
    /// Everything the problem is besides the inertias.
    pub(super) key: Key,
    /// Per body: the inertias of the model it was found for (before the trunk's offset).
    pub(super) inertia: Vec<SpatialInertia>,
    /// The smooth adjustments' parameters (trunk, pelvis offset, rotation; `problem::Layout`).
    pub(super) x: DVector<f64>,
    /// The residual force's weight (m): the mean COM height of the unadjusted motion.
    pub(super) height: f64,
    /// The floor's height (m, along `up`) under the unadjusted motion: kinematic, so the same
    /// for any inertias.
    pub(super) floor: f64,
    /// The refinement near the foot changes, when it was kept (`super::refine`).
    pub(super) refined: Option<RefinedSeed>,
    /// Gauss–Newton steps the reduction took.
    pub(super) steps: usize,
}

/// The refinement's parameters and knot spacing (s).
#[derive(Debug, Clone)]
pub(super) struct RefinedSeed {
    pub x: DVector<f64>,
    pub spacing_s: f64,
}

/// What a reduction depends on besides the inertias, compared whole.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Key {
    parent: Vec<usize>,
    joints: Vec<JointKind>,
    placement: Vec<SpatialTransform>,
    gravity: Vector3<f64>,
    damping: Vec<f64>,
    /// Per body: the mass centre (m, body frame).
    com: Vec<Vector3<f64>>,
    time: Vec<f64>,
    /// A digest of the motion's q, v, a (their bits, in order).
    motion: u64,
    counted: Vec<bool>,
    up: usize,
    bounds: ReductionBounds,
    trunk_bodies: Vec<usize>,
    across: [Vector3<f64>; 2],
    feet: Vec<Foot>,
    params: ContactParams,
    /// The contact phases held through the trials (`Ground::Estimated::held`).
    held: Option<Vec<Vec<bool>>>,
}

impl Key {
    /// The key of a problem; `None` against measured ground reactions (their reduction
    /// adjusts the mass too, and starts cold).
    pub fn of(
        model: &Model,
        ground: &Ground,
        trunk: &Trunk,
        motion: &Motion,
        up: usize,
        counted: &[bool],
        bounds: &ReductionBounds,
    ) -> Option<Self> {
        let Ground::Estimated { feet, params, held } = *ground else {
            return None;
        };
        Some(Self {
            parent: model.parent.clone(),
            joints: model.joints.clone(),
            placement: model.placement.clone(),
            gravity: model.gravity,
            damping: model.damping.clone(),
            com: model.inertia.iter().map(|i| i.com).collect(),
            time: motion.time.to_vec(),
            motion: digest(&[motion.q, motion.v, motion.a]),
            counted: counted.to_vec(),
            up,
            bounds: *bounds,
            trunk_bodies: trunk.bodies.to_vec(),
            across: trunk.across,
            feet: feet.to_vec(),
            params: *params,
            held: held.map(<[Vec<bool>]>::to_vec),
        })
    }
}

/// FxHash's mixing (rustc's hasher) over the bits of every value: a change of any value
/// changes it but for a 2⁻⁶⁴ chance (an accidental change, not an adversary's).
fn digest(rows: &[&[Vec<f64>]]) -> u64 {
    const K: u64 = 0x517c_c1b7_2722_0a95;
    let mut h: u64 = 0;
    for part in rows {
        h = (h.rotate_left(5) ^ part.len() as u64).wrapping_mul(K);
        for row in part.iter() {
            h = (h.rotate_left(5) ^ row.len() as u64).wrapping_mul(K);
            for x in row {
                h = (h.rotate_left(5) ^ x.to_bits()).wrapping_mul(K);
            }
        }
    }
    h
}

/// How a reduction starts.
pub(super) enum Start<'a> {
    /// From zero: no seed, or one of another problem.
    Cold,
    /// Every mass and rotational inertia is the seed's times one factor (within
    /// [`SCALED_TOL`]): the seed's adjustments are this model's, and are only evaluated.
    Scaled(&'a Seed),
}

/// The relative tolerance within which a model's inertias count as the seed's scaled.
pub const SCALED_TOL: f64 = 1e-12;

impl<'a> Start<'a> {
    /// How a reduction of `model` with the key `key` starts from `seed`.
    pub fn of(seed: Option<&'a Seed>, key: Option<&Key>, model: &Model) -> Self {
        match (seed, key) {
            (Some(s), Some(k)) if s.key == *k && s.inertia.len() == model.inertia.len() => {
                if scaled_alike(&s.inertia, &model.inertia) {
                    Start::Scaled(s)
                } else {
                    Start::Cold
                }
            }
            _ => Start::Cold,
        }
    }
}

impl<'a> Start<'a> {
    /// A preview's start ([`super::Warm::Preview`]): the seed's adjustments, when the problem
    /// is the seed's but for inertias that are not its scaled alike; `None` otherwise.
    pub fn preview(seed: &'a Seed, key: Option<&Key>, model: &Model) -> Option<Self> {
        (key == Some(&seed.key)
            && seed.inertia.len() == model.inertia.len()
            && !scaled_alike(&seed.inertia, &model.inertia))
        .then_some(Start::Scaled(seed))
    }
}

/// Whether every body of `new` is that of `old` with its mass and rotational inertia times
/// one factor (the ratio of the total masses), within [`SCALED_TOL`] of each; the mass
/// centres are the key's.
fn scaled_alike(old: &[SpatialInertia], new: &[SpatialInertia]) -> bool {
    let (m0, m1): (f64, f64) = (
        old.iter().map(|i| i.mass).sum(),
        new.iter().map(|i| i.mass).sum(),
    );
    if !(m0 > 0.0 && m1 > 0.0) {
        return false;
    }
    let s = m1 / m0;
    old.iter().zip(new).all(|(a, b)| {
        (b.mass - s * a.mass).abs() <= SCALED_TOL * b.mass.abs().max(f64::MIN_POSITIVE)
            && (b.inertia_com - a.inertia_com * s).norm()
                <= SCALED_TOL * b.inertia_com.norm().max(f64::MIN_POSITIVE)
    })
}

#[cfg(test)]
mod tests {
    //! A model counts as the seed's scaled only when every body's mass and inertia are, to
    //! 1e-12; one link off by a millionth, or another motion, starts cold.
    use super::*;
    use crate::dynamics::samples::random_tree;

    fn scaled(model: &Model, s: f64) -> Vec<SpatialInertia> {
        model
            .inertia
            .iter()
            .map(|i| SpatialInertia::new(i.mass * s, i.com, i.inertia_com * s))
            .collect()
    }

    #[test]
    fn only_a_body_scaled_alike_counts_as_scaled() {
        let model = random_tree(9, 3, true);
        assert!(scaled_alike(&model.inertia, &scaled(&model, 80.0 / 75.0)));
        assert!(scaled_alike(&model.inertia, &model.inertia));
        let mut one = scaled(&model, 1.1);
        one[4].mass *= 1.0 + 1e-6;
        assert!(!scaled_alike(&model.inertia, &one));
        let mut turned = scaled(&model, 1.1);
        turned[3].inertia_com[(0, 1)] += 1e-6 * turned[3].inertia_com.norm();
        turned[3].inertia_com[(1, 0)] = turned[3].inertia_com[(0, 1)];
        assert!(!scaled_alike(&model.inertia, &turned));
    }

    #[test]
    fn the_digest_sees_one_bit_of_the_motion() {
        let q: Vec<Vec<f64>> = vec![vec![0.1, 0.2], vec![0.3, 0.4]];
        let mut r = q.clone();
        r[1][1] = f64::from_bits(r[1][1].to_bits() ^ 1);
        assert_ne!(digest(&[&q, &q, &q]), digest(&[&q, &q, &r]));
        assert_ne!(digest(&[&q, &r, &q]), digest(&[&q, &q, &r]));
        assert_eq!(digest(&[&q, &q, &q]), digest(&[&q.clone(), &q, &q]));
    }
}
