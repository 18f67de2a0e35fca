//! Inverse dynamics through a blend window. Inside the window the blended motion is, to first
//! order, `q = (1−λ)qa + λqb`, so `q̈ = (1−λ)q̈a + λq̈b + 2λ̇(q̇b − q̇a) + λ̈(qb − qa)`: besides
//! mixing the two inputs' torques, the transition itself needs the torque
//! `τtr = D(q)·(2λ̇Δq̇ + λ̈Δq)` (D the joint-space inertia).
//!
//! Invariant tested, on two generated walks of different cadence blended over 0.6 s: with the C²
//! ramp every joint torque of the blend stays within the range of the two inputs' torques at
//! that frame, widened by `|τtr|` plus a stated margin of half the larger input's peak in the
//! window on that coordinate or, for a rotation channel, on any rotation channel of its joint
//! (plus 1 N·m). The margin covers what the linear decomposition leaves out: velocity products
//! (the blend's q̇ carries `λ̇Δq`, and Coriolis/centrifugal terms are quadratic in q̇) and the
//! slerp of rotations, which mixes a joint's channels (the hip's flexion torque leaks into its
//! abduction channel when the two walks' thighs point apart). Measured: the quintic uses 0.87
//! of it (1.5 with a per-coordinate peak, on the hip abduction channel of the planted-foot
//! walks, whose abduction torque peaks at 7 N·m in the window). A linear
//! (C⁰) ramp breaks it at the edges by an order of magnitude (22× on these walks; on the
//! earlier generated walk 14×: 2200 N on the root's forward coordinate at t1 against inputs
//! within ±50 N): its q̇ jumps, so q̈ carries a spike
//! of height ~|Δq̇|/dt that no smooth margin covers.

use articula::dynamics::{Workspace, rnea};
use articula::io::bvh::Bvh;
use articula::io::generate::{WalkParams, walk};
use articula::model::Model;
use articula::model::bvh::{BvhMap, BvhModelOptions, UpAxis, build_bvh_model};
use articula::motion::blend::{Align, BlendOptions, TimeMap, WarpWindow, blend};
use articula::motion::derive::{differentiate, second_derivative};
use articula::motion::ramp::RampShape;
use articula::motion::take::Trajectory;

/// q, q̇, q̈ per frame (euler model: every coordinate a scalar), by second-order differences.
struct States {
    q: Vec<Vec<f64>>,
    v: Vec<Vec<f64>>,
    a: Vec<Vec<f64>>,
}

fn states(take: &Bvh, model: &Model, map: &BvhMap) -> States {
    let q = Trajectory::from_bvh(take, model, map).q;
    let n = q.len();
    let dt = take.frame_time;
    let (mut v, mut a) = (vec![vec![0.0; model.nv]; n], vec![vec![0.0; model.nv]; n]);
    let (mut col, mut d1, mut d2) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for i in 0..model.nq {
        col.iter_mut().zip(&q).for_each(|(c, q)| *c = q[i]);
        differentiate(&col, dt, &mut d1);
        second_derivative(&col, dt, &mut d2);
        for k in 0..n {
            v[k][i] = d1[k];
            a[k][i] = d2[k];
        }
    }
    States { q, v, a }
}

fn torques(s: &States, model: &Model, ws: &mut Workspace) -> Vec<Vec<f64>> {
    (0..s.q.len())
        .map(|k| {
            rnea(model, ws, &s.q[k], &s.v[k], &s.a[k], None)
                .as_slice()
                .to_vec()
        })
        .collect()
}

#[test]
fn torques_through_the_window_stay_within_the_inputs_with_the_quintic_ramp() {
    let a = walk(&WalkParams::default());
    let b = walk(&WalkParams {
        cycle_s: 0.9,
        ..Default::default()
    });
    let opts = BvhModelOptions::new("walk", 0.01, UpAxis::Y, vec![]);
    let (model, map) = build_bvh_model(&a, &opts).unwrap();
    assert_eq!(model.nq, model.nv);
    let mut ws = Workspace::new(&model);
    let (sa, mut sb) = (states(&a, &model, &map), states(&b, &model, &map));
    let (ta, tb) = (torques(&sa, &model, &mut ws), torques(&sb, &model, &mut ws));
    let window: WarpWindow = "1.5:2.1".parse().unwrap();
    let dt = a.frame_time;
    let (k0, k1) = (180, 252);
    // b's root is moved onto a's ground position at t0 (a constant shift: b's torques do not
    // change, its root coordinates do)
    for name in ["Hips.Xposition", "Hips.Zposition"] {
        let i = model.v_index(name).unwrap();
        let shift = sa.q[k0][i] - sb.q[k0][i];
        sb.q.iter_mut().for_each(|q| q[i] += shift);
    }
    let align = Align {
        root: true,
        heading: false,
    };
    let zeros = vec![0.0; model.nv];
    // the coordinates that slerp couples with coordinate i: the other rotation channels of its
    // BVH joint (a position channel stands alone)
    let names = model.v_names.clone();
    let group = |i: usize| {
        let (joint, channel) = names[i].rsplit_once('.').unwrap_or((&names[i], ""));
        let rotation = channel.ends_with("rotation");
        let names = &names;
        (0..names.len()).filter(move |&c| {
            c == i
                || (rotation
                    && names[c]
                        .rsplit_once('.')
                        .is_some_and(|(j, ch)| j == joint && ch.ends_with("rotation")))
        })
    };
    let excess = |ramp: RampShape, ws: &mut Workspace| {
        let blend_opts = BlendOptions {
            align,
            ramp,
            ..Default::default()
        };
        let out = blend(&a, &b, window, TimeMap::IDENTITY, &blend_opts).unwrap();
        let so = states(&out, &model, &map);
        let tr = torques(&so, &model, ws);
        let mut worst: f64 = 0.0;
        for k in k0 - 5..=k1 + 5 {
            // the transition torque D(q)(2λ̇Δq̇ + λ̈Δq), from rnea with v = 0 minus gravity
            let s = (k as f64 * dt - window.t0) / (window.t1 - window.t0);
            let span = window.t1 - window.t0;
            let (l1, l2) = match ramp {
                RampShape::Quintic => (
                    articula::motion::ramp::smoothstep5_d1(s) / span,
                    articula::motion::ramp::smoothstep5_d2(s) / (span * span),
                ),
                RampShape::Linear => (ramp.d1(s) / span, 0.0),
            };
            let acc: Vec<f64> = (0..model.nv)
                .map(|i| 2.0 * l1 * (sb.v[k][i] - sa.v[k][i]) + l2 * (sb.q[k][i] - sa.q[k][i]))
                .collect();
            let gravity = rnea(&model, ws, &so.q[k], &zeros, &zeros, None).clone();
            let transition = rnea(&model, ws, &so.q[k], &zeros, &acc, None) - gravity;
            for i in 0..model.nv {
                let (ta, tb) = (&ta, &tb);
                let peak = group(i)
                    .flat_map(|c| (k0..=k1).map(move |j| ta[j][c].abs().max(tb[j][c].abs())))
                    .fold(0.0, f64::max);
                let margin = transition[i].abs() + 0.5 * peak + 1.0;
                let (lo, hi) = (ta[k][i].min(tb[k][i]), ta[k][i].max(tb[k][i]));
                let out_of = (lo - tr[k][i]).max(tr[k][i] - hi).max(0.0);
                worst = worst.max(out_of / margin);
            }
        }
        worst
    };
    let quintic = excess(RampShape::Quintic, &mut ws);
    let linear = excess(RampShape::Linear, &mut ws);
    println!("quintic {quintic}, linear {linear}");
    assert!(quintic <= 1.0, "quintic ramp: {quintic} margins outside");
    assert!(linear > 2.0, "linear ramp: only {linear} margins outside");
}
