//! Locking joints and pruning to a subtree really remove DOFs from a BVH model, and lose no
//! mass; the reduced model's inverse dynamics equals the full model's when the removed joints
//! are held at rest (q = 0, v = a = 0), for any state of the remaining joints.

use articula::dynamics::{Workspace, rnea};
use articula::io::bvh::{PositionMode, UpAxis, resolve_position_modes};
use articula::io::generate::{WalkParams, walk};
use articula::model::bvh::{BvhModelOptions, build_bvh_model};

/// Full and reduced models of the generated walk; returns the worst |τ_reduced − τ_full| over
/// a few states and the two DOF counts.
fn compare(lock: &[&str], subtree: Option<&str>) -> (f64, usize, usize) {
    let take = walk(&WalkParams::default());
    let modes = resolve_position_modes(&take, PositionMode::Auto);
    let opts = BvhModelOptions::new("walk", 0.01, UpAxis::Y, modes);
    let (full, _) = build_bvh_model(&take, &opts).unwrap();
    let mut reduced_opts = opts.clone();
    reduced_opts.lock = lock.iter().map(|s| s.to_string()).collect();
    reduced_opts.subtree = subtree.map(String::from);
    let (reduced, _) = build_bvh_model(&take, &reduced_opts).unwrap();
    assert!((reduced.total_mass() - full.total_mass()).abs() < 1e-9);

    let (mut wf, mut wr) = (Workspace::new(&full), Workspace::new(&reduced));
    let mut worst: f64 = 0.0;
    for s in 0..3 {
        let f = |k: usize, c: f64| ((k as f64 + 1.0) * c + s as f64).sin();
        // the kept coordinates move; the removed ones stay at rest
        let mut q = vec![0.0; full.nq];
        let mut v = vec![0.0; full.nv];
        let mut a = vec![0.0; full.nv];
        let (mut qr, mut vr, mut ar) = (vec![], vec![], vec![]);
        for (k, name) in full.q_names.iter().enumerate() {
            if reduced.q_names.contains(name) {
                q[k] = 0.6 * f(k, 0.7);
                v[k] = f(k, 1.3);
                a[k] = 2.0 * f(k, 0.4);
                qr.push(q[k]);
                vr.push(v[k]);
                ar.push(a[k]);
            }
        }
        let tf = rnea(&full, &mut wf, &q, &v, &a, None).clone();
        let tr = rnea(&reduced, &mut wr, &qr, &vr, &ar, None);
        for (k, name) in reduced.v_names.iter().enumerate() {
            let kf = full.v_index(name).unwrap();
            worst = worst.max((tr[k] - tf[kf]).abs());
        }
    }
    (worst, full.nv, reduced.nv)
}

#[test]
fn locked_joints_leave_the_model_and_the_rest_is_unchanged() {
    let (err, nv_full, nv) = compare(&["LeftArm", "RightForeArm", "Spine1.Yrotation"], None);
    assert_eq!(nv, nv_full - 7);
    assert!(err < 1e-9, "{err}");
}

#[test]
fn pruning_to_a_leg_keeps_its_chain_and_lumps_the_rest_into_the_hips() {
    let (err, _, nv) = compare(&[], Some("LeftUpLeg"));
    assert_eq!(nv, 6 + 4 * 3);
    assert!(err < 1e-9, "{err}");
}
