//! A BVH model is a faithful re-expression of the take: forward kinematics of the model at the
//! configuration built from a frame puts every BVH joint where the BVH definition
//! (`T(offset)·T(pos)·R_c1·R_c2·R_c3`, scaled to metres) puts it, in both joint models; the
//! link masses sum to the body mass; the channel ↔ q map round-trips.

mod common;

use articula::dynamics::{Workspace, forward_kinematics};
use articula::io::bvh::Bvh;
use articula::io::generate::{WalkParams, walk};
use articula::model::Model;
use articula::model::bvh::{
    BvhMap, BvhModelOptions, JointModel, ResolvedPosition, UpAxis, build_bvh_model,
};
use articula::motion::take::{Trajectory, frame_to_q, q_to_frame};
use nalgebra::{Matrix3, Rotation3, Unit, Vector3};

/// World positions (m) of every BVH joint at frame `k`, straight from the BVH definition.
fn definition_positions(
    bvh: &Bvh,
    k: usize,
    scale: f64,
    modes: &[ResolvedPosition],
) -> Vec<Vector3<f64>> {
    let f = bvh.frame(k);
    let mut rot: Vec<Matrix3<f64>> = vec![];
    let mut pos: Vec<Vector3<f64>> = vec![];
    for (j, joint) in bvh.joints.iter().enumerate() {
        let mut local_t = joint.offset;
        let mut r = Matrix3::identity();
        for (c, ch) in joint.channels.iter().enumerate() {
            let x = f[joint.first_channel + c];
            if ch.is_rotation() {
                let axis = Unit::new_normalize(Vector3::ith(ch.axis(), 1.0));
                r *= Rotation3::from_axis_angle(&axis, x.to_radians()).into_inner();
            } else if modes[j] == ResolvedPosition::Replace {
                local_t[ch.axis()] = x;
            } else {
                local_t[ch.axis()] += x;
            }
        }
        let (pr, pp) = match joint.parent {
            Some(p) => (rot[p], pos[p]),
            None => (Matrix3::identity(), Vector3::zeros()),
        };
        pos.push(pp + pr * local_t * scale);
        rot.push(pr * r);
    }
    pos
}

/// World positions (m) of every BVH joint from the model's forward kinematics.
fn model_positions(
    model: &Model,
    map: &BvhMap,
    ws: &mut Workspace,
    q: &[f64],
) -> Vec<Vector3<f64>> {
    forward_kinematics(model, ws, q);
    map.joints
        .iter()
        .map(|j| ws.o_x_i[j.body].compose(&j.frame).trans)
        .collect()
}

fn walk_options(bvh: &Bvh, joints: JointModel) -> BvhModelOptions {
    let mut modes = vec![ResolvedPosition::None; bvh.joints.len()];
    modes[0] = ResolvedPosition::Add;
    let mut o = BvhModelOptions::new("walk", 0.01, UpAxis::Y, modes);
    o.joints = joints;
    o
}

/// Checks FK(model) = BVH definition on every `step`-th frame and returns the worst error (m).
fn check_fk(bvh: &Bvh, opts: &BvhModelOptions, step: usize) -> f64 {
    let (model, map) = build_bvh_model(bvh, opts).unwrap();
    let mut ws = Workspace::new(&model);
    let mut q = vec![0.0; model.nq];
    let mut worst: f64 = 0.0;
    for k in (0..bvh.frames).step_by(step) {
        frame_to_q(bvh, &map, &model, bvh.frame(k), &mut q);
        let got = model_positions(&model, &map, &mut ws, &q);
        let want = definition_positions(bvh, k, opts.scale_to_m, &opts.positions);
        for (g, w) in got.iter().zip(&want) {
            worst = worst.max((g - w).norm());
        }
    }
    worst
}

#[test]
fn generated_walk_fk_matches_the_bvh_definition_in_both_joint_models() {
    let take = walk(&WalkParams::default());
    for jm in [JointModel::Euler, JointModel::Ball] {
        let err = check_fk(&take, &walk_options(&take, jm), 7);
        assert!(err < 1e-9, "{jm}: {err} m");
    }
}

#[test]
fn replace_semantics_make_q_zero_the_rest_pose() {
    // the root's position channels hold absolute positions: q = value − offset
    let mut take = walk(&WalkParams::default());
    take.joints[0].offset = Vector3::new(1.0, 90.0, -2.0);
    let mut opts = walk_options(&take, JointModel::Euler);
    opts.positions[0] = ResolvedPosition::Replace;
    assert!(check_fk(&take, &opts, 11) < 1e-9);
    let (model, map) = build_bvh_model(&take, &opts).unwrap();
    let mut row = take.frame(0).to_vec();
    row[..3].copy_from_slice(&[1.0, 90.0, -2.0]);
    let mut q = vec![0.0; model.nq];
    frame_to_q(&take, &map, &model, &row, &mut q);
    assert!(q[..3].iter().all(|x| x.abs() < 1e-15), "{:?}", &q[..3]);
}

#[test]
fn frame_to_q_and_back_round_trips() {
    let take = walk(&WalkParams::default());
    let opts = walk_options(&take, JointModel::Euler);
    let (model, map) = build_bvh_model(&take, &opts).unwrap();
    let mut q = vec![0.0; model.nq];
    let mut back = vec![0.0; take.channel_count];
    for k in [0, 100, take.frames - 1] {
        frame_to_q(&take, &map, &model, take.frame(k), &mut q);
        q_to_frame(&take, &map, &model, &q, &mut back).unwrap();
        for (a, b) in back.iter().zip(take.frame(k)) {
            assert!((a - b).abs() < 1e-10 * (1.0 + b.abs()), "{a} vs {b}");
        }
    }
}

#[test]
fn trajectory_has_one_configuration_per_frame() {
    let take = walk(&WalkParams::default());
    let (model, map) = build_bvh_model(&take, &walk_options(&take, JointModel::Ball)).unwrap();
    let traj = Trajectory::from_bvh(&take, &model, &map);
    assert_eq!(traj.q.len(), take.frames);
    assert_eq!(traj.time[1], take.frame_time);
    // quaternions stay in one hemisphere from frame to frame
    let iq = map.joints[1].quat_q.unwrap();
    for w in traj.q.windows(2) {
        let dot: f64 = (0..4).map(|c| w[0][iq + c] * w[1][iq + c]).sum();
        assert!(dot > 0.0);
    }
}

#[test]
fn locked_joints_keep_the_other_joints_in_place_at_rest() {
    // with the left arm locked, a frame in which that arm is at rest has the same FK
    let mut take = walk(&WalkParams::default());
    let la = take.joint_index("LeftArm").unwrap();
    let c0 = take.joints[la].first_channel;
    let n = take.channel_count;
    for k in 0..take.frames {
        take.motion[k * n + c0..k * n + c0 + 3].fill(0.0);
    }
    let mut opts = walk_options(&take, JointModel::Euler);
    opts.lock = vec!["LeftArm".into()];
    assert!(check_fk(&take, &opts, 13) < 1e-9);
}

#[test]
fn ball_configurations_convert_back_to_the_same_frames() {
    let take = walk(&WalkParams::default());
    let (model, map) = build_bvh_model(&take, &walk_options(&take, JointModel::Ball)).unwrap();
    let traj = Trajectory::from_bvh(&take, &model, &map);
    let mut row = vec![0.0; take.channel_count];
    for (k, q) in traj.q.iter().enumerate().step_by(17) {
        // near the previous frame's angles, as a BVH export does
        row.copy_from_slice(take.frame(k.saturating_sub(1)));
        q_to_frame(&take, &map, &model, q, &mut row).unwrap();
        for (a, b) in row.iter().zip(take.frame(k)) {
            assert!(
                (a - b).abs() < 1e-9 * (1.0 + b.abs()),
                "frame {k}: {a} vs {b}"
            );
        }
    }
}

/// The configurations by column (`q_columns`, what the pipeline reads) are `frame_to_q` of
/// every frame, bit for bit, with each quaternion turned into the previous frame's
/// hemisphere: both joint models, a locked joint, and a take longer than one block of frames.
#[test]
fn q_columns_are_frame_to_q_bit_for_bit() {
    use articula::motion::take::q_columns;
    let take = walk(&WalkParams::default());
    assert!(
        take.frames > 64,
        "{} frames: more than one block",
        take.frames
    );
    for jm in [JointModel::Euler, JointModel::Ball] {
        for lock in [vec![], vec!["LeftArm".to_string()]] {
            let mut opts = walk_options(&take, jm);
            opts.lock = lock.clone();
            let (model, map) = build_bvh_model(&take, &opts).unwrap();
            let cols = q_columns(&take, &model, &map);
            let n = take.frames;
            let mut prev: Option<Vec<f64>> = None;
            for k in 0..n {
                let mut q = vec![0.0; model.nq];
                frame_to_q(&take, &map, &model, take.frame(k), &mut q);
                if let Some(p) = &prev {
                    for j in &map.joints {
                        if let Some(iq) = j.quat_q {
                            let dot: f64 = (0..4).map(|c| p[iq + c] * q[iq + c]).sum();
                            if dot < 0.0 {
                                q[iq..iq + 4].iter_mut().for_each(|x| *x = -*x);
                            }
                        }
                    }
                }
                for (j, x) in q.iter().enumerate() {
                    assert_eq!(
                        cols[j * n + k].to_bits(),
                        x.to_bits(),
                        "{jm} {lock:?}: frame {k}, {}",
                        model.q_names[j]
                    );
                }
                prev = Some(q);
            }
        }
    }
}
