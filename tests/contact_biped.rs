//! Ground reactions of a hand-built biped (free pelvis, two legs with hip, knee and ankle hinges,
//! a foot and a toe point), on motions whose physics is known:
//! - standing still, each foot carries half the weight, its centre of pressure right under its
//!   ankle (the body's centre of mass is above the mid-point of the ankles), and nothing is
//!   left at the root;
//! - during the flight of a hop nothing touches the ground (the whole body falls freely, so the
//!   needed external wrench is zero), on the ground again the weight is back;
//! - in a squat with both feet planted, the feet explain the whole wrench: the residual is zero
//!   and the vertical ground force is the weight plus mass times the vertical acceleration of
//!   the centre of mass.

use articula::dynamics::grf::estimate_ground_reactions;
use articula::dynamics::{Workspace, rnea};
use articula::model::{JointKind, Model, ModelBuilder};
use articula::motion::contact::{ContactParams, foot_bodies};
use articula::spatial::{SpatialInertia, SpatialTransform};
use nalgebra::{Matrix3, Vector3};

const G: f64 = 9.81;
const THIGH: f64 = 0.43;
const SHANK: f64 = 0.43;
/// Ankle height above the floor when the foot is flat (the toe point is on the floor).
const ANKLE_Y: f64 = 0.06;
/// Hip joints below the pelvis origin.
const HIP_DROP: f64 = 0.05;
const HIP_X: f64 = 0.09;
const MASS: f64 = 40.0 + 2.0 * (8.0 + 3.5 + 1.0);

fn inertia(m: f64, com: [f64; 3], r: f64) -> SpatialInertia {
    SpatialInertia::new(
        m,
        Vector3::from(com),
        Matrix3::identity() * (0.4 * m * r * r),
    )
}

/// Y up, facing +Z; pelvis on a free joint; hips, knees, ankles hinge about x.
fn biped() -> Model {
    let mut mb = ModelBuilder::new("biped", Vector3::new(0.0, -G, 0.0));
    let pelvis = mb.add_body(
        0,
        "Hips",
        "Hips",
        JointKind::Free,
        SpatialTransform::IDENTITY,
        inertia(40.0, [0.0, 0.1, 0.0], 0.15),
    );
    let x = JointKind::Revolute { axis: Vector3::x() };
    for (side, sx) in [("Left", HIP_X), ("Right", -HIP_X)] {
        let at = |x: f64, y: f64, z: f64| SpatialTransform::from_translation(Vector3::new(x, y, z));
        let thigh = mb.add_body(
            pelvis,
            format!("{side}UpLeg"),
            format!("{side}UpLeg"),
            x,
            at(sx, -HIP_DROP, 0.0),
            inertia(8.0, [0.0, -0.19, 0.0], 0.06),
        );
        let shank = mb.add_body(
            thigh,
            format!("{side}Leg"),
            format!("{side}Leg"),
            x,
            at(0.0, -THIGH, 0.0),
            inertia(3.5, [0.0, -0.19, 0.0], 0.04),
        );
        let foot = mb.add_body(
            shank,
            format!("{side}Foot"),
            format!("{side}Foot"),
            x,
            at(0.0, -SHANK, 0.0),
            inertia(1.0, [0.0, -0.04, 0.0], 0.03),
        );
        mb.add_body(
            foot,
            format!("{side}ToeBase"),
            format!("{side}ToeBase"),
            JointKind::Fixed,
            at(0.0, -ANKLE_Y, 0.13),
            SpatialInertia::ZERO,
        );
    }
    mb.build()
}

/// Standing height of the pelvis origin with straight legs.
fn stand_y() -> f64 {
    ANKLE_Y + SHANK + THIGH + HIP_DROP
}

/// A state with the pelvis at height `y` (vertical rate `yd`, `ydd`), upright, and both legs at
/// hip `h`, knee `k`, ankle `an` (each with rate and acceleration).
struct Pose {
    y: [f64; 3],
    hip: [f64; 3],
    knee: [f64; 3],
    ankle: [f64; 3],
}

fn state(p: &Pose) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
    // q: [x y z qx qy qz qw, (hip knee ankle) ×2]; v, a: [vx vy vz wx wy wz, (…) ×2]
    let mut q = vec![0.0, p.y[0], 0.0, 0.0, 0.0, 0.0, 1.0];
    let mut v = vec![0.0, p.y[1], 0.0, 0.0, 0.0, 0.0];
    let mut a = vec![0.0, p.y[2], 0.0, 0.0, 0.0, 0.0];
    for _ in 0..2 {
        for (d, j) in [p.hip, p.knee, p.ankle].iter().enumerate() {
            let _ = d;
            q.push(j[0]);
            v.push(j[1]);
            a.push(j[2]);
        }
    }
    (q, v, a)
}

type Take = (Vec<f64>, Vec<Vec<f64>>, Vec<Vec<f64>>, Vec<Vec<f64>>);

fn take(n: usize, dt: f64, pose: impl Fn(f64) -> Pose) -> Take {
    let time: Vec<f64> = (0..n).map(|k| k as f64 * dt).collect();
    let (mut q, mut v, mut a) = (vec![], vec![], vec![]);
    for &t in &time {
        let (qk, vk, ak) = state(&pose(t));
        q.push(qk);
        v.push(vk);
        a.push(ak);
    }
    (time, q, v, a)
}

fn still(y: f64) -> Pose {
    Pose {
        y: [y, 0.0, 0.0],
        hip: [0.0; 3],
        knee: [0.0; 3],
        ankle: [0.0; 3],
    }
}

#[test]
fn the_feet_are_found_by_name() {
    let model = biped();
    let feet = foot_bodies(&model);
    let names: Vec<(&str, &str, &str)> = feet
        .iter()
        .map(|f| {
            (
                f.name.as_str(),
                model.body_names[f.ankle_body].as_str(),
                model.body_names[f.toe_body].as_str(),
            )
        })
        .collect();
    assert_eq!(
        names,
        [
            ("left", "LeftFoot", "LeftToeBase"),
            ("right", "RightFoot", "RightToeBase")
        ]
    );
}

#[test]
fn standing_still_each_foot_carries_half_the_weight_under_its_ankle() {
    let model = biped();
    let (time, q, v, a) = take(100, 0.01, |_| still(stand_y()));
    let gr =
        estimate_ground_reactions(&model, &time, &q, &v, &a, 1, &ContactParams::default()).unwrap();
    assert!(gr.floor.abs() < 1e-12, "floor {}", gr.floor);
    for k in 0..time.len() {
        assert_eq!(gr.contact[k], [true, true], "frame {k}");
        for (j, x) in [HIP_X, -HIP_X].into_iter().enumerate() {
            let f = gr.grf[k][j];
            assert!(
                (f - Vector3::new(0.0, MASS * G / 2.0, 0.0)).norm() < 1e-9,
                "frame {k} foot {j}: {f}"
            );
            assert!(
                (gr.cop[k][j] - Vector3::new(x, 0.0, 0.0)).norm() < 1e-9,
                "cop {}",
                gr.cop[k][j]
            );
        }
        // top-down: the root holds the whole weight; with contact, nothing
        assert!((gr.wrench[k][1] - MASS * G).abs() < 1e-9);
        assert!(
            gr.residual[k].iter().all(|r| r.abs() < 1e-9),
            "{:?}",
            gr.residual[k]
        );
    }
}

#[test]
fn nothing_touches_the_ground_in_the_flight_of_a_hop() {
    // stand 0.5 s, hop with take-off speed 2 m/s (flight 2·v0/g ≈ 0.41 s), stand again
    let model = biped();
    let (v0, t0) = (2.0, 0.5);
    let t1 = t0 + 2.0 * v0 / G;
    let y = stand_y();
    let (time, q, v, a) = take(150, 0.01, |t| {
        if t > t0 && t < t1 {
            let s = t - t0;
            Pose {
                y: [y + v0 * s - 0.5 * G * s * s, v0 - G * s, -G],
                ..still(0.0)
            }
        } else {
            still(y)
        }
    });
    let gr =
        estimate_ground_reactions(&model, &time, &q, &v, &a, 1, &ContactParams::default()).unwrap();
    let mut flight_frames = 0;
    for (k, &t) in time.iter().enumerate() {
        let total: Vector3<f64> = gr.grf[k].iter().sum();
        if t > t0 + 0.02 && t < t1 - 0.02 {
            // high and fast: no contact; and free fall needs no external force anyway
            assert_eq!(gr.contact[k], [false, false], "t = {t}");
            assert!(total.norm() < 1e-9, "t = {t}: {total}");
            assert!(gr.residual[k].iter().all(|r| r.abs() < 1e-9));
            flight_frames += 1;
        } else if t < t0 - 0.02 || t > t1 + 0.05 {
            assert_eq!(gr.contact[k], [true, true], "t = {t}");
            assert!((total.y - MASS * G).abs() < 1e-9, "t = {t}: {total}");
        }
    }
    assert!(flight_frames > 30);
}

#[test]
fn in_a_squat_the_feet_explain_the_whole_wrench() {
    // hip −θ, knee 2θ, ankle −θ keeps each ankle under its hip and the foot flat: the pelvis
    // height is ANKLE_Y + (THIGH + SHANK)·cos θ + HIP_DROP (equal segments)
    let model = biped();
    let w = 2.0 * std::f64::consts::PI * 0.8;
    let (time, q, v, a) = take(200, 0.01, |t| {
        let (th, thd, thdd) = (
            0.5 + 0.3 * (w * t).sin(),
            0.3 * w * (w * t).cos(),
            -0.3 * w * w * (w * t).sin(),
        );
        let l = THIGH;
        Pose {
            y: [
                ANKLE_Y + 2.0 * l * th.cos() + HIP_DROP,
                -2.0 * l * th.sin() * thd,
                -2.0 * l * (th.cos() * thd * thd + th.sin() * thdd),
            ],
            hip: [-th, -thd, -thdd],
            knee: [2.0 * th, 2.0 * thd, 2.0 * thdd],
            ankle: [-th, -thd, -thdd],
        }
    });
    let gr =
        estimate_ground_reactions(&model, &time, &q, &v, &a, 1, &ContactParams::default()).unwrap();
    let mut ws = Workspace::new(&model);
    let mut max_knee_change: f64 = 0.0;
    for k in 0..time.len() {
        assert_eq!(gr.contact[k], [true, true], "frame {k}");
        assert!(
            gr.residual[k].iter().all(|r| r.abs() < 1e-8),
            "frame {k}: {:?}",
            gr.residual[k]
        );
        // the ground's vertical force is what the top-down root needed
        let total: Vector3<f64> = gr.grf[k].iter().sum();
        assert!((total.y - gr.wrench[k][1]).abs() < 1e-8);
        // symmetric legs share equally
        assert!((gr.grf[k][0] - gr.grf[k][1]).norm() < 1e-8);
        // the knee torque changes: top-down it only holds the hanging shank and foot
        let top_down = rnea(&model, &mut ws, &q[k], &v[k], &a[k], None).clone();
        let knee = model.v_index("LeftLeg").unwrap();
        max_knee_change = max_knee_change.max((gr.tau[k][knee] - top_down[knee]).abs());
    }
    // bent knees under body weight: tens of N·m
    assert!(max_knee_change > 20.0, "{max_knee_change}");
}

/// The biped rebuilt from the left foot up: the world is the left foot (ankle at
/// `(HIP_X, ANKLE_Y, 0)`), then ankle, shank, knee, thigh, hip, pelvis, and the right leg as
/// before. Coordinates: left ankle, knee, hip (each the negative of the top-down angle), then
/// the right hip, knee, ankle. Returns the model and the index of the pelvis body.
fn biped_from_left_foot() -> (Model, usize) {
    let mut mb = ModelBuilder::new("biped-bottom-up", Vector3::new(0.0, -G, 0.0));
    let x = JointKind::Revolute { axis: Vector3::x() };
    let at = |x: f64, y: f64, z: f64| SpatialTransform::from_translation(Vector3::new(x, y, z));
    let shank = mb.add_body(
        0,
        "shank",
        "ankle",
        x,
        at(HIP_X, ANKLE_Y, 0.0),
        inertia(3.5, [0.0, SHANK - 0.19, 0.0], 0.04),
    );
    let thigh = mb.add_body(
        shank,
        "thigh",
        "knee",
        x,
        at(0.0, SHANK, 0.0),
        inertia(8.0, [0.0, THIGH - 0.19, 0.0], 0.06),
    );
    let pelvis = mb.add_body(
        thigh,
        "pelvis",
        "hip",
        x,
        at(0.0, THIGH, 0.0),
        inertia(40.0, [-HIP_X, 0.1 + HIP_DROP, 0.0], 0.15),
    );
    let rthigh = mb.add_body(
        pelvis,
        "RightUpLeg",
        "RightUpLeg",
        x,
        at(-2.0 * HIP_X, 0.0, 0.0),
        inertia(8.0, [0.0, -0.19, 0.0], 0.06),
    );
    let rshank = mb.add_body(
        rthigh,
        "RightLeg",
        "RightLeg",
        x,
        at(0.0, -THIGH, 0.0),
        inertia(3.5, [0.0, -0.19, 0.0], 0.04),
    );
    mb.add_body(
        rshank,
        "RightFoot",
        "RightFoot",
        x,
        at(0.0, -SHANK, 0.0),
        inertia(1.0, [0.0, -0.04, 0.0], 0.03),
    );
    (mb.build(), pelvis)
}

#[test]
fn in_single_stance_the_knee_and_hip_torques_equal_those_of_the_leg_rooted_at_the_foot() {
    //! With the left foot planted and the right one in the air, the ground reaction is the
    //! whole-body wrench, and inverse dynamics with it must give the same stance-knee and hip
    //! torques as inverse dynamics of the same motion computed from the foot up (where the
    //! foot is the fixed world and no ground force is needed): the physics the top-down
    //! hanging-from-the-pelvis model gets wrong. (A wide support region keeps the centre of
    //! pressure unclamped: this biped has no hip roll to shift its weight over the foot.)
    let (bottom_up, pelvis) = biped_from_left_foot();
    let mut kinematic = bottom_up.clone();
    kinematic.gravity = Vector3::zeros();
    let top_down = biped();
    let w = 2.0 * std::f64::consts::PI * 0.7;
    // bottom-up coordinates: (value, rate, acceleration) of c0 + c1·sin(w t + c2)
    let curves = [
        (0.05, 0.1, 0.0),
        (-0.5, 0.2, 1.0),
        (0.1, 0.2, 2.0),
        (-0.6, 0.2, 0.5),
        (1.3, 0.1, 0.0),
        (0.0, 0.1, 1.5),
    ];
    let (n, dt) = (120, 0.01);
    let mut ws = Workspace::new(&bottom_up);
    let mut tau_bu = vec![];
    let (mut time, mut q, mut v, mut a) = (vec![], vec![], vec![], vec![]);
    for k in 0..n {
        let t = k as f64 * dt;
        let qb: Vec<f64> = curves
            .iter()
            .map(|c| c.0 + c.1 * (w * t + c.2).sin())
            .collect();
        let vb: Vec<f64> = curves
            .iter()
            .map(|c| c.1 * w * (w * t + c.2).cos())
            .collect();
        let ab: Vec<f64> = curves
            .iter()
            .map(|c| -c.1 * w * w * (w * t + c.2).sin())
            .collect();
        tau_bu.push(rnea(&bottom_up, &mut ws, &qb, &vb, &ab, None).clone());
        // the pelvis motion, without gravity in the accelerations: body frame at the left hip
        rnea(&kinematic, &mut ws, &qb, &vb, &ab, None);
        articula::dynamics::forward_kinematics(&kinematic, &mut ws, &qb);
        let c_x_p = SpatialTransform::from_translation(Vector3::new(-HIP_X, HIP_DROP, 0.0));
        let o_x_p = ws.o_x_i[pelvis].compose(&c_x_p);
        let vp = c_x_p.act_inv_motion(&ws.v[pelvis]);
        let ap = c_x_p.act_inv_motion(&ws.a[pelvis]);
        let rot = nalgebra::UnitQuaternion::from_matrix(&o_x_p.rot);
        let mut qt = vec![
            o_x_p.trans.x,
            o_x_p.trans.y,
            o_x_p.trans.z,
            rot.i,
            rot.j,
            rot.k,
            rot.w,
        ];
        let mut vt = [vp.lin.as_slice(), vp.ang.as_slice()].concat();
        let mut at = [ap.lin.as_slice(), ap.ang.as_slice()].concat();
        // top-down legs: left hip, knee, ankle are minus the bottom-up hip, knee, ankle
        for j in [2, 1, 0] {
            qt.push(-qb[j]);
            vt.push(-vb[j]);
            at.push(-ab[j]);
        }
        qt.extend_from_slice(&qb[3..]);
        vt.extend_from_slice(&vb[3..]);
        at.extend_from_slice(&ab[3..]);
        time.push(t);
        q.push(qt);
        v.push(vt);
        a.push(at);
    }
    let params = ContactParams {
        cop_margin: 1.0,
        friction: 10.0,
        ..ContactParams::default()
    };
    let gr = estimate_ground_reactions(&top_down, &time, &q, &v, &a, 1, &params).unwrap();
    let (lhip, lknee) = (
        top_down.v_index("LeftUpLeg").unwrap(),
        top_down.v_index("LeftLeg").unwrap(),
    );
    let rhip = top_down.v_index("RightUpLeg").unwrap();
    let mut ws_td = Workspace::new(&top_down);
    let mut max_change: f64 = 0.0;
    for k in 0..n {
        assert_eq!(gr.contact[k], [true, false], "frame {k}");
        assert!(
            gr.residual[k].iter().all(|r| r.abs() < 1e-7),
            "{:?}",
            gr.residual[k]
        );
        let tau = &gr.tau[k];
        assert!(
            (tau[lknee] + tau_bu[k][1]).abs() < 1e-7,
            "knee {} vs {}",
            tau[lknee],
            -tau_bu[k][1]
        );
        assert!(
            (tau[lhip] + tau_bu[k][2]).abs() < 1e-7,
            "hip {} vs {}",
            tau[lhip],
            -tau_bu[k][2]
        );
        for j in 0..3 {
            assert!((tau[rhip + j] - tau_bu[k][3 + j]).abs() < 1e-7);
        }
        // and the top-down value, hanging from the pelvis, is far from it
        let hanging = rnea(&top_down, &mut ws_td, &q[k], &v[k], &a[k], None)[lknee];
        max_change = max_change.max((hanging - tau[lknee]).abs());
        assert!(gr.cop_gap[k] < 1e-9, "frame {k}: gap {}", gr.cop_gap[k]);
    }
    assert!(max_change > 20.0, "{max_change}");
    assert_eq!(gr.quality().outside_frames, 0);
    assert_eq!(gr.quality().single_support_frames, n);

    // with the foot's real support region (5 cm around the heel–toe line) the centre of
    // pressure this motion needs leaves it (the biped has no hip roll to bring its weight over
    // the foot): the foot's load keeps it inside, and the gap is the moment left at the root —
    // the root's force is still zero, so its horizontal moment is the gap times the vertical
    // force, about any point
    let params = ContactParams {
        friction: 10.0,
        ..ContactParams::default()
    };
    let gr = estimate_ground_reactions(&top_down, &time, &q, &v, &a, 1, &params).unwrap();
    for k in 0..n {
        let r = &gr.residual[k];
        assert!(r[..3].iter().all(|f| f.abs() < 1e-7), "{r:?}");
        let moment = r[3].hypot(r[5]);
        let f_up = gr.wrench[k][1];
        assert!(
            (moment - gr.cop_gap[k] * f_up).abs() < 1e-7 * f_up,
            "frame {k}: moment {moment} vs gap {} × {f_up}",
            gr.cop_gap[k]
        );
    }
    let quality = gr.quality();
    assert!(quality.outside_share() > 0.5, "{quality:?}");
    assert!(
        quality.to_string().contains("outside the foot"),
        "{quality}"
    );
}
