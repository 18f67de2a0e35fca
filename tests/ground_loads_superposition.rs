//! The ground's loads are taken from inverse dynamics without them along the feet's paths to
//! the world (`GroundReactions::take_from`, the estimate's pass 3): inverse dynamics is linear
//! in the external forces, so the torques, the kept net moments and the root's residual must be,
//! to rounding, those of RNEA with the loads applied as external forces on the feet's bodies
//! (what the estimate ran before). Checked on the demo walk and every shared walk and run, with
//! both joint models and with joint damping (a term RNEA adds that the loads do not touch).
//! The estimate skips a foot off the floor (a zero wrench takes a signed zero from each value,
//! which changes no bit but a `−0`'s) and poses only the loaded feet's paths: its torques and
//! moments are, bit for bit, every foot's loads taken after a whole kinematics pass.

mod common;

use articula::dynamics::grf::GroundReactions;
use articula::dynamics::rra::Warm;
use articula::dynamics::{Workspace, forward_kinematics, rnea};
use articula::model::bvh::JointModel;
use articula::pipeline::anatomy::moment_bodies;
use articula::pipeline::{self, Contact, Take, TakeOptions, consistency};
use articula::spatial::ForceVec;
use std::path::Path;

fn load(path: &Path, joints: JointModel, damping: Option<f64>) -> Take {
    let mut o = TakeOptions {
        contact: Contact::Feet,
        joints,
        ..TakeOptions::default()
    };
    if let Some(d) = damping {
        o.damping = articula::io::scene::PerJoint::all(d);
    }
    pipeline::load_take(path, &o).unwrap()
}

/// The largest difference between the estimate's torques, moments and residual and RNEA's with
/// the loads as external forces, each over its peak (the residual's over the torques'); and the
/// torques' peak (N·m).
fn off(t: &Take, g: &GroundReactions, bodies: &[usize]) -> ([f64; 3], f64) {
    let (m, s) = (&t.model, &t.states);
    let mut ws = Workspace::new(m);
    let mut f_ext = vec![ForceVec::ZERO; m.nbodies()];
    let root = articula::dynamics::grf::floating_root(m).unwrap();
    let (mut diff, mut peak) = ([0.0f64; 3], [0.0f64; 3]);
    let mut at = |i: usize, a: f64, b: f64| {
        diff[i] = diff[i].max((a - b).abs());
        peak[i] = peak[i].max(b.abs());
    };
    for k in 0..s.len() {
        forward_kinematics(m, &mut ws, &s.q[k]);
        g.external_forces(k, &ws.o_x_i, &mut f_ext);
        let tau = rnea(m, &mut ws, &s.q[k], &s.v[k], &s.a[k], Some(&f_ext)).clone();
        for (a, b) in g.tau[k].iter().zip(tau.iter()) {
            at(0, *a, *b);
        }
        for (j, &b) in bodies.iter().enumerate() {
            for c in 0..3 {
                at(1, g.moments[k * bodies.len() + j][c], ws.f[b].ang[c]);
            }
        }
        // what the root still supplies, about its origin
        let w = (1..m.nbodies())
            .filter(|&i| m.parent[i] == 0)
            .map(|i| ws.o_x_i[i].act_force(&ws.f[i]))
            .fold(ForceVec::ZERO, |s, f| s + f);
        let p = ws.o_x_i[root].trans;
        let n = w.ang - p.cross(&w.lin);
        for c in 0..3 {
            at(2, g.residual[k][c], w.lin[c]);
            at(2, g.residual[k][3 + c], n[c]);
        }
    }
    // the residual is the needed wrench less the feet's: its rounding is the torques' (the
    // root's force is the body's weight), not its own small peak's
    let scale = [peak[0], peak[1], peak[0].max(peak[2])];
    let rel = [0, 1, 2].map(|i| diff[i] / scale[i].max(1.0));
    (rel, peak[0])
}

/// The values (torques and kept moments) where the estimate's differ in any bit from RNEA
/// without the loads, then every foot's load taken (`GroundReactions::take_from`, none
/// skipped) with the whole kinematics; and the frames with a foot that carries nothing.
fn bits_off(t: &Take, g: &GroundReactions, bodies: &[usize]) -> (usize, usize) {
    let (m, s) = (&t.model, &t.states);
    let mut ws = Workspace::new(m);
    let (mut off, mut unloaded) = (0, 0);
    for k in 0..s.len() {
        let mut tau = rnea(m, &mut ws, &s.q[k], &s.v[k], &s.a[k], None)
            .as_slice()
            .to_vec();
        let mut moments: Vec<_> = bodies.iter().map(|&b| ws.f[b].ang).collect();
        forward_kinematics(m, &mut ws, &s.q[k]);
        g.take_from(m, k, &ws, Some(&mut tau), (bodies, &mut moments));
        let same = |a: f64, b: f64| a.to_bits() == b.to_bits();
        off += g.tau[k]
            .iter()
            .zip(&tau)
            .filter(|(a, b)| !same(**a, **b))
            .count();
        off += (g.moments[k * bodies.len()..(k + 1) * bodies.len()].iter())
            .zip(&moments)
            .flat_map(|(a, b)| a.iter().zip(b.iter()))
            .filter(|(a, b)| !same(**a, **b))
            .count();
        unloaded += usize::from((0..g.feet.len()).any(|j| g.foot_wrench(k, j) == ForceVec::ZERO));
    }
    (off, unloaded)
}

/// The frames with a foot off the floor, over the variants checked.
fn check(path: &Path) -> usize {
    let mut skipped = 0;
    for joints in [JointModel::Euler, JointModel::Ball] {
        for damping in [None, Some(0.5)] {
            let t = load(path, joints, damping);
            let bodies = moment_bodies(&t);
            let (_, g, _, _) =
                consistency::consistent_take_keeping(&t, false, None, &bodies, Warm::Cold, None)
                    .unwrap();
            assert_eq!(g.moment_bodies, bodies);
            let (rel, peak) = off(&t, &g, &bodies);
            assert!(
                peak > 10.0,
                "{}: a take that loads its joints",
                path.display()
            );
            assert!(
                rel.iter().all(|r| *r < 1e-12),
                "{} {joints:?} damping {damping:?}: torques, moments, residual off by {rel:?} \
                 of their peaks",
                path.display()
            );
            let (off, unloaded) = bits_off(&t, &g, &bodies);
            assert_eq!(off, 0, "{} {joints:?}: values off by a bit", path.display());
            skipped += unloaded;
        }
    }
    skipped
}

#[test]
fn the_demo_walks_loads_taken_along_the_feet_are_rnea_with_them() {
    let skipped = check(&common::repo("data/demo_walk.bvh"));
    assert!(
        skipped > 0,
        "frames with a foot off the floor, whose load is skipped"
    );
}

#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn every_shared_takes_loads_taken_along_the_feet_are_rnea_with_them() {
    let mut checked = 0;
    for path in common::real_takes() {
        let t = load(&path, JointModel::Euler, None);
        if t.options.contact != Contact::Feet || pipeline::ground_reactions(&t).is_err() {
            continue;
        }
        check(&path);
        checked += 1;
    }
    eprintln!("{checked} takes with contact checked");
    assert!(checked >= 10, "{checked} takes with contact");
}
