//! The fast paths of the dynamics give the generic answer.
//!
//! A revolute joint about a coordinate axis `e_k` takes the fast form of
//! `Model::parent_transform` (a principal-axis rotation after a translation when its placement
//! has no rotation, two mixed columns when it has); any other axis — negative, oblique, not of
//! unit length — takes the generic one. Turning `e_k` into `−e_k` and negating that
//! coordinate's q, q̇, q̈ and τ describes the same motion through the generic path, so RNEA,
//! CRBA and ABA (and forward kinematics, which crosses joints as they do) must agree to
//! rounding between the two models. Bodies without mass or inertia
//! (skipped in RNEA's inertial terms) are mixed in, as in a BVH euler model.

use articula::dynamics::samples::{SplitMix64, random_configuration, random_tree, random_vector};
use articula::dynamics::{
    Workspace, aba, crba, forward_kinematics, forward_kinematics_through, rnea,
};
use articula::model::{JointKind, Model};
use articula::spatial::{SpatialInertia, SpatialTransform};
use nalgebra::{Matrix3, Vector3};

/// A random tree whose revolute joints are about coordinate axes, some bodies massless and every other placement free of rotation (some also of translation).
fn coordinate_axis_tree(seed: u64, floating: bool) -> Model {
    let mut m = random_tree(24, seed, floating);
    for i in 1..m.nbodies() {
        if let JointKind::Revolute { .. } = m.joints[i] {
            m.joints[i] = JointKind::Revolute {
                axis: Vector3::ith(i % 3, 1.0),
            };
        }
        if i % 2 == 0 {
            m.placement[i].rot = Matrix3::identity();
        }
        if i % 4 == 0 {
            m.placement[i] = SpatialTransform::IDENTITY;
        }
    }
    // massless links carry revolute joints about other axes, as in a BVH euler model (a massless
    // leaf, or one carrying a ball joint, would make D singular)
    for i in (3..m.nbodies()).step_by(3) {
        let children: Vec<usize> = (i + 1..m.nbodies()).filter(|&c| m.parent[c] == i).collect();
        let fine = |c: &usize| {
            m.joints[*c]
                .revolute_coordinate_axis()
                .is_some_and(|k| k != i % 3)
                && m.inertia[*c] != SpatialInertia::ZERO
        };
        let revolute = m.joints[i].revolute_coordinate_axis().is_some();
        if revolute && !children.is_empty() && children.iter().all(fine) {
            m.inertia[i] = SpatialInertia::ZERO;
        }
    }
    m
}

/// The same model with every coordinate axis negated, and the sign of each of its coordinates.
fn negated(m: &Model) -> (Model, Vec<f64>) {
    let mut n = m.clone();
    let mut sign = vec![1.0; m.nv];
    for i in 1..m.nbodies() {
        if let Some(k) = m.joints[i].revolute_coordinate_axis() {
            n.joints[i] = JointKind::Revolute {
                axis: -Vector3::ith(k, 1.0),
            };
            assert_eq!(n.joints[i].revolute_coordinate_axis(), None);
            sign[m.idx_v[i]] = -1.0;
        }
    }
    (n, sign)
}

fn rel(a: &[f64], b: &[f64]) -> f64 {
    let scale = a.iter().fold(1.0f64, |s, x| s.max(x.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |e, (x, y)| e.max((x - y).abs()))
        / scale
}

#[test]
fn coordinate_axis_joints_agree_with_the_generic_path() {
    for (seed, floating) in [(1, false), (2, true), (3, false), (4, true)] {
        let m = coordinate_axis_tree(seed, floating);
        let (n, sign) = negated(&m);
        assert!(sign.iter().filter(|&&s| s < 0.0).count() >= 6);
        assert!(m.inertia.iter().skip(1).any(|i| *i == SpatialInertia::ZERO));
        let (mut wm, mut wn) = (Workspace::new(&m), Workspace::new(&n));
        let mut rng = SplitMix64(seed);
        for _ in 0..5 {
            let mut q = vec![0.0; m.nq];
            let (mut v, mut a) = (vec![0.0; m.nv], vec![0.0; m.nv]);
            random_configuration(&m, &mut rng, &mut q);
            random_vector(&mut rng, 2.0, &mut v);
            random_vector(&mut rng, 2.0, &mut a);
            // the negated model's state: revolute coordinates (nq = nv = 1) change sign
            let flip = |x: &[f64], idx: &dyn Fn(usize) -> usize| -> Vec<f64> {
                let mut y = x.to_vec();
                for i in 1..m.nbodies() {
                    if m.joints[i].revolute_coordinate_axis().is_some() {
                        y[idx(i)] = -y[idx(i)];
                    }
                }
                y
            };
            let (qn, vn, an) = (
                flip(&q, &|i| m.idx_q[i]),
                flip(&v, &|i| m.idx_v[i]),
                flip(&a, &|i| m.idx_v[i]),
            );
            let signed = |x: &[f64]| x.iter().zip(&sign).map(|(x, s)| x * s).collect::<Vec<_>>();

            // forward kinematics: the same world poses; a prefix pass writes the prefix's
            forward_kinematics(&m, &mut wm, &q);
            forward_kinematics(&n, &mut wn, &qn);
            for i in 1..m.nbodies() {
                let (x, y) = (&wm.o_x_i[i], &wn.o_x_i[i]);
                let e = (x.rot - y.rot).abs().max() + (x.trans - y.trans).abs().max();
                assert!(
                    e < 1e-12,
                    "forward kinematics, body {i}, seed {seed}: {e:e}"
                );
            }
            let mut prefix = Workspace::new(&m);
            let last = m.nbodies() / 2;
            forward_kinematics_through(&m, &mut prefix, &q, last);
            assert_eq!(prefix.o_x_i[..=last], wm.o_x_i[..=last], "seed {seed}");
            assert!(
                prefix.o_x_i[last + 1..]
                    .iter()
                    .all(|x| *x == SpatialTransform::IDENTITY)
            );

            let tm = rnea(&m, &mut wm, &q, &v, &a, None).as_slice().to_vec();
            let tn = rnea(&n, &mut wn, &qn, &vn, &an, None).as_slice().to_vec();
            assert!(rel(&tm, &signed(&tn)) < 1e-12, "rnea, seed {seed}");

            let dm = crba(&m, &mut wm, &q).clone();
            let dn = crba(&n, &mut wn, &qn).clone();
            for r in 0..m.nv {
                for c in 0..m.nv {
                    let e = (dm[(r, c)] - sign[r] * sign[c] * dn[(r, c)]).abs();
                    assert!(
                        e < 1e-12 * (1.0 + dm[(r, r)].abs()),
                        "crba ({r},{c}), seed {seed}"
                    );
                }
            }

            let am = aba(&m, &mut wm, &q, &v, &tm, None)
                .unwrap()
                .as_slice()
                .to_vec();
            let ab = aba(&n, &mut wn, &qn, &vn, &signed(&tm), None)
                .unwrap()
                .as_slice()
                .to_vec();
            assert!(rel(&am, &signed(&ab)) < 1e-9, "aba, seed {seed}");
            assert!(rel(&am, &a) < 1e-9, "aba∘rnea, seed {seed}");
        }
    }
}

#[test]
fn only_exact_unit_coordinate_axes_take_the_fast_path() {
    let r = |axis: Vector3<f64>| JointKind::Revolute { axis }.revolute_coordinate_axis();
    assert_eq!(r(Vector3::x()), Some(0));
    assert_eq!(r(Vector3::y()), Some(1));
    assert_eq!(r(Vector3::z()), Some(2));
    assert_eq!(r(-Vector3::z()), None);
    assert_eq!(r(Vector3::new(0.0, 2.0, 0.0)), None);
    assert_eq!(r(Vector3::new(1.0 - 1e-16, 0.0, 0.0)), None);
    assert_eq!(r(Vector3::new(0.6, 0.8, 0.0)), None);
    assert_eq!(
        JointKind::Prismatic { axis: Vector3::x() }.revolute_coordinate_axis(),
        None
    );
}

#[test]
fn parent_transform_is_placement_times_joint_transform() {
    let m = coordinate_axis_tree(9, true);
    let mut q = vec![0.0; m.nq];
    random_configuration(&m, &mut SplitMix64(5), &mut q);
    for i in 1..m.nbodies() {
        let j = &m.joints[i];
        let iq = m.idx_q[i];
        let want = m.placement[i].compose(&j.transform(&q[iq..iq + j.nq()]));
        let got = m.parent_transform(i, &q).to_transform();
        assert!((got.rot - want.rot).norm() < 1e-15, "body {i}");
        assert!((got.trans - want.trans).norm() < 1e-15, "body {i}");
    }
}

/// The axis and translation flag of a joint RNEA crosses by an axis step (alone or in a triple).
fn axis_of(step: articula::dynamics::rnea::JointStep) -> Option<(usize, bool)> {
    use articula::dynamics::rnea::JointStep;
    match step {
        JointStep::Axis { k, shifted } => Some((k, shifted)),
        JointStep::Triple { k, shifted } => Some((k[0], shifted)),
        JointStep::InTriple { k } => Some((k, false)),
        JointStep::General => None,
    }
}

/// The demo take's euler model: every rotation channel takes RNEA's axis step (the first of a
/// joint's triple across its bone, the other two at its origin, without lever terms), and its
/// torques, with the ws.v / ws.a / ws.f every body gets, equal those of the generic path
/// (every axis negated) to rounding.
#[test]
fn euler_model_takes_the_axis_step_and_agrees_with_the_generic_path() {
    use articula::dynamics::rnea::JointStep;
    use articula::pipeline::{self, ModelSource, TakeOptions};
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/demo_walk.bvh");
    let m = pipeline::load_model(&ModelSource::Take(path), &TakeOptions::default()).unwrap();
    let mut ws = Workspace::new(&m);
    let (mut at_origin, mut shifted) = (0, 0);
    for i in 1..m.nbodies() {
        match m.joints[i].revolute_coordinate_axis() {
            Some(k) => {
                let moved = m.placement[i].trans != Vector3::zeros();
                assert_eq!(axis_of(ws.joint_steps[i]), Some((k, moved)), "body {i}");
                if moved { shifted += 1 } else { at_origin += 1 }
            }
            None => assert_eq!(ws.joint_steps[i], JointStep::General, "body {i}"),
        }
    }
    assert!(
        at_origin >= 2 * shifted && shifted > 10,
        "{at_origin} {shifted}"
    );

    // nq = nv: q, v and a flip sign at the same indices
    assert_eq!(m.nq, m.nv);
    let (n, sign) = negated(&m);
    let mut wn = Workspace::new(&n);
    assert!(
        (1..n.nbodies()).all(|i| wn.joint_steps[i] == JointStep::General
            || n.joints[i].revolute_coordinate_axis().is_some())
    );
    let mut rng = SplitMix64(17);
    for _ in 0..5 {
        let mut q = vec![0.0; m.nq];
        let (mut v, mut a) = (vec![0.0; m.nv], vec![0.0; m.nv]);
        random_configuration(&m, &mut rng, &mut q);
        random_vector(&mut rng, 2.0, &mut v);
        random_vector(&mut rng, 2.0, &mut a);
        let signed = |x: &[f64]| x.iter().zip(&sign).map(|(x, s)| x * s).collect::<Vec<_>>();
        let tm = rnea(&m, &mut ws, &q, &v, &a, None).as_slice().to_vec();
        let tn = rnea(&n, &mut wn, &signed(&q), &signed(&v), &signed(&a), None)
            .as_slice()
            .to_vec();
        assert!(rel(&tm, &signed(&tn)) < 1e-12, "rnea");
        // the body quantities other algorithms read after RNEA are the same vectors
        for i in 1..m.nbodies() {
            let d = (ws.f[i].ang - wn.f[i].ang).norm() + (ws.f[i].lin - wn.f[i].lin).norm();
            let s = 1.0 + ws.f[i].ang.norm() + ws.f[i].lin.norm();
            assert!(d < 1e-12 * s, "f of body {i}");
            let d = (ws.a[i].ang - wn.a[i].ang).norm() + (ws.v[i].lin - wn.v[i].lin).norm();
            assert!(
                d < 1e-12 * (1.0 + ws.a[i].ang.norm() + ws.v[i].lin.norm()),
                "v, a of {i}"
            );
        }
    }
}

/// The euler triples of the demo take's model (three rotation channels crossed in one forward
/// step, the two massless links' inertial terms skipped) give the same bits as the same joints
/// crossed one by one as axis joints: torques and the v, a, f of every body, with and without
/// external forces. And a triple is only taken where its pattern holds: with mass on a
/// fictitious link, that link's triple falls back to single axis steps, and the torques follow
/// the mass.
#[test]
fn euler_triples_equal_single_axis_steps_bit_for_bit() {
    use articula::dynamics::rnea::JointStep;
    use articula::pipeline::{self, ModelSource, TakeOptions};
    use articula::spatial::ForceVec;
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/demo_walk.bvh");
    let m = pipeline::load_model(&ModelSource::Take(path), &TakeOptions::default()).unwrap();
    let mut fused = Workspace::new(&m);
    let triples = (1..m.nbodies())
        .filter(|&i| matches!(fused.joint_steps[i], JointStep::Triple { .. }))
        .collect::<Vec<_>>();
    // every joint of the skeleton but the root's translation is a triple
    assert!(triples.len() > 10, "{triples:?}");
    let mut single = Workspace::new(&m);
    for s in &mut single.joint_steps {
        if let Some((k, shifted)) = axis_of(*s) {
            *s = JointStep::Axis { k, shifted };
        }
    }
    let bits = |x: &[f64]| x.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let body_bits = |ws: &Workspace| {
        (1..m.nbodies())
            .flat_map(|i| {
                [
                    ws.v[i].ang,
                    ws.v[i].lin,
                    ws.a[i].ang,
                    ws.a[i].lin,
                    ws.f[i].ang,
                    ws.f[i].lin,
                ]
            })
            .flat_map(|x| [x.x.to_bits(), x.y.to_bits(), x.z.to_bits()])
            .collect::<Vec<_>>()
    };
    let mut rng = SplitMix64(23);
    for round in 0..6 {
        let mut q = vec![0.0; m.nq];
        let (mut v, mut a) = (vec![0.0; m.nv], vec![0.0; m.nv]);
        random_configuration(&m, &mut rng, &mut q);
        random_vector(&mut rng, 3.0, &mut v);
        random_vector(&mut rng, 3.0, &mut a);
        let mut fx = vec![ForceVec::ZERO; m.nbodies()];
        for f in fx.iter_mut().skip(1) {
            let mut w = vec![0.0; 6];
            random_vector(&mut rng, 50.0, &mut w);
            *f = ForceVec::new(
                Vector3::new(w[0], w[1], w[2]),
                Vector3::new(w[3], w[4], w[5]),
            );
        }
        let f_ext = (round % 2 == 1).then_some(&fx[..]);
        let tf = bits(rnea(&m, &mut fused, &q, &v, &a, f_ext).as_slice());
        let ts = bits(rnea(&m, &mut single, &q, &v, &a, f_ext).as_slice());
        assert_eq!(tf, ts, "torques, round {round}");
        assert_eq!(
            body_bits(&fused),
            body_bits(&single),
            "v, a, f, round {round}"
        );
    }

    // mass on the first link of a triple: that triple is crossed one joint at a time
    let mut heavy = m.clone();
    let t = triples[triples.len() / 2];
    heavy.inertia[t] =
        SpatialInertia::new(1.5, Vector3::new(0.0, 0.1, 0.0), Matrix3::identity() * 0.01);
    let mut wh = Workspace::new(&heavy);
    assert_eq!(axis_of(wh.joint_steps[t]), axis_of(fused.joint_steps[t]));
    assert!(matches!(wh.joint_steps[t], JointStep::Axis { .. }));
    assert!(matches!(wh.joint_steps[t + 1], JointStep::Axis { .. }));
    let mut q = vec![0.0; m.nq];
    let (mut v, mut a) = (vec![0.0; m.nv], vec![0.0; m.nv]);
    random_configuration(&m, &mut rng, &mut q);
    random_vector(&mut rng, 3.0, &mut v);
    random_vector(&mut rng, 3.0, &mut a);
    let light = rnea(&m, &mut fused, &q, &v, &a, None).clone();
    let with_mass = rnea(&heavy, &mut wh, &q, &v, &a, None).clone();
    assert!(
        (light - with_mass).norm() > 1e-3,
        "the mass of body {t} is counted"
    );
}

/// The centre of mass passes over the bodies without mass (`residual::centre_of_mass`): their
/// term is a signed zero and the sum, started at +0, is never −0, so every bit is the sum over
/// every body's.
#[test]
fn the_centre_of_mass_without_the_massless_bodies_is_the_sum_over_all_bit_for_bit() {
    use articula::dynamics::residual::centre_of_mass;
    let mut massless = 0;
    for seed in 0..20 {
        let m = coordinate_axis_tree(seed, seed % 2 == 0);
        massless += (1..m.nbodies())
            .filter(|&i| m.inertia[i].mass == 0.0)
            .count();
        let mut rng = SplitMix64(seed);
        let mut ws = Workspace::new(&m);
        let mut q = vec![0.0; m.nq];
        for _ in 0..20 {
            random_configuration(&m, &mut rng, &mut q);
            forward_kinematics(&m, &mut ws, &q);
            let (mut sum, mut mass) = (Vector3::zeros(), 0.0);
            for (i, inertia) in m.inertia.iter().enumerate().skip(1) {
                sum += ws.o_x_i[i].transform_point(&inertia.com) * inertia.mass;
                mass += inertia.mass;
            }
            let all = sum / f64::max(mass, 1e-12);
            let com = centre_of_mass(&m, &ws);
            assert_eq!(com.map(f64::to_bits), all.map(f64::to_bits), "seed {seed}");
        }
    }
    assert!(massless > 20, "{massless} bodies without mass");
}
