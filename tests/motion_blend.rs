//! Blending takes through a window (the paper's section 4).
//!
//! Invariants: the blend of a take with itself is the take; take b's root aligned to a undoes
//! a rigid turn and shift of b about the vertical; a re-timed b is resampled at a's frames; the
//! result is continuous across the window edges in q and q̇ for both ramps, and in q̈ only with
//! the C² quintic: with a linear (C⁰) ramp the estimated q̈ at the edges grows like 1/dt (a
//! velocity jump) while the quintic's converges; different skeletons are refused by naming the
//! first joint that differs.

mod common;

use articula::io::bvh::{Bvh, BvhJoint, Channel};
use articula::io::generate::{WalkParams, walk};
use articula::motion::blend::{
    Align, BlendOptions, TimeMap, WarpWindow, blend, blend_chain, check_same_skeleton,
};
use articula::motion::ramp::RampShape;
use articula::rotation::{EulerOrder, euler_to_matrix};
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::PI;

/// A four-joint take: root (6 channels), chest and arm (ZXY), knee (one Xrotation), with every
/// channel given by `f(t)` (13 values: cm and degrees).
fn fixture(fps: f64, duration: f64, f: impl Fn(f64) -> [f64; 13]) -> Bvh {
    use Channel::*;
    let spec: [(&str, Option<usize>, Vec<Channel>); 4] = [
        (
            "Hips",
            None,
            vec![
                Xposition, Yposition, Zposition, Zrotation, Xrotation, Yrotation,
            ],
        ),
        ("Chest", Some(0), vec![Zrotation, Xrotation, Yrotation]),
        ("Arm", Some(1), vec![Zrotation, Xrotation, Yrotation]),
        ("Knee", Some(0), vec![Xrotation]),
    ];
    let mut first = 0;
    let joints = spec
        .into_iter()
        .map(|(name, parent, channels)| {
            let j = BvhJoint {
                name: name.into(),
                parent,
                offset: Vector3::new(0.0, 10.0, 0.0),
                first_channel: first,
                end_sites: vec![],
                line: 0,
                channels,
            };
            first += j.channels.len();
            j
        })
        .collect();
    let frames = (duration * fps).round() as usize + 1;
    let motion = (0..frames).flat_map(|k| f(k as f64 / fps)).collect();
    Bvh {
        joints,
        frame_time: 1.0 / fps,
        frames,
        channel_count: 13,
        motion,
        first_frame: 0,
        decimals: Vec::new(),
    }
}

fn take_a(fps: f64) -> Bvh {
    fixture(fps, 3.0, |t| {
        let s = (2.0 * PI * t).sin();
        let c = (2.0 * PI * t).cos();
        [
            3.0 * s,
            90.0 + 2.0 * c,
            100.0 * t,
            10.0 * s,
            5.0 * c,
            20.0 * t,
            30.0 * s,
            20.0 * c,
            -10.0 + 5.0 * s,
            60.0 * c,
            -40.0 + 30.0 * s,
            15.0 * c,
            30.0 + 25.0 * s,
        ]
    })
}

fn take_b(fps: f64) -> Bvh {
    fixture(fps, 3.0, |t| {
        let s = (2.0 * PI * 1.3 * t + 1.0).sin();
        let c = (2.0 * PI * 1.3 * t + 1.0).cos();
        [
            -20.0 + 4.0 * c,
            85.0 + 3.0 * s,
            30.0 + 150.0 * t,
            -15.0 * c,
            8.0 * s,
            60.0 - 30.0 * t,
            -40.0 * c,
            10.0 * s,
            20.0 * c,
            -50.0 * s,
            10.0 + 20.0 * c,
            -25.0 * s,
            70.0 - 40.0 * c,
        ]
    })
}

fn max_abs_diff(a: &Bvh, b: &Bvh) -> f64 {
    assert_eq!((a.frames, a.channel_count), (b.frames, b.channel_count));
    a.motion
        .iter()
        .zip(&b.motion)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

fn column(t: &Bvh, c: usize) -> Vec<f64> {
    (0..t.frames).map(|k| t.frame(k)[c]).collect()
}

#[test]
fn blend_of_a_take_with_itself_is_the_take() {
    let walk = walk(&WalkParams::default());
    let a = take_a(120.0);
    for (take, window) in [(&walk, "1.0:1.6"), (&a, "0.5:2.0"), (&a, "0:3")] {
        for align in [Align::NONE, Align::ALL] {
            let opts = BlendOptions {
                align,
                ..Default::default()
            };
            let w: WarpWindow = window.parse().unwrap();
            let out = blend(take, take, w, TimeMap::IDENTITY, &opts).unwrap();
            let d = max_abs_diff(&out, take);
            assert!(d < 1e-9, "window {window}, align {align}: {d}");
            assert_eq!(out.frame_time, take.frame_time);
            assert_eq!(out.joints, take.joints);
        }
    }
}

#[test]
fn skeleton_mismatch_names_the_first_joint_that_differs() {
    let a = walk(&WalkParams::default());
    let mut b = a.clone();
    b.joints[7].name = "LeftElbow".into();
    let e = check_same_skeleton(&a, &b).unwrap_err().to_string();
    assert!(e.contains("LeftForeArm") && e.contains("LeftElbow"), "{e}");
    let e = blend(
        &a,
        &b,
        "1:2".parse().unwrap(),
        TimeMap::IDENTITY,
        &BlendOptions::default(),
    )
    .unwrap_err()
    .to_string();
    assert!(e.contains("LeftElbow"), "{e}");

    let mut b = a.clone();
    b.joints[14].channels.swap(0, 1);
    let e = check_same_skeleton(&a, &b).unwrap_err().to_string();
    assert!(
        e.contains("`LeftLeg`") && e.contains("Zrotation Xrotation Yrotation"),
        "{e}"
    );

    let mut b = a.clone();
    b.joints[14].parent = Some(0);
    let e = check_same_skeleton(&a, &b).unwrap_err().to_string();
    assert!(
        e.contains("`LeftLeg`") && e.contains("`LeftUpLeg`") && e.contains("`Hips`"),
        "{e}"
    );

    let mut b = a.clone();
    let extra = b.joints.pop().unwrap();
    let e = check_same_skeleton(&a, &b).unwrap_err().to_string();
    assert!(
        e.contains(&format!("`{}` is only in take a", extra.name)),
        "{e}"
    );

    // other bone lengths are the same skeleton (another actor)
    let tall = walk(&WalkParams {
        scale: 1.1,
        ..Default::default()
    });
    check_same_skeleton(&a, &tall).unwrap();
}

/// Largest |Δ^order q / dt^order| over all channels, on the frames within 0.1 s of an edge.
fn edge_derivative(out: &Bvh, window: WarpWindow, order: usize) -> f64 {
    let dt = out.frame_time;
    let mut worst: f64 = 0.0;
    for c in 0..out.channel_count {
        let mut x = column(out, c);
        for _ in 0..order {
            x = x.windows(2).map(|w| (w[1] - w[0]) / dt).collect();
        }
        for (k, v) in x.iter().enumerate() {
            let t = (k as f64 + order as f64 / 2.0) * dt;
            if (t - window.t0).abs() < 0.1 || (t - window.t1).abs() < 0.1 {
                worst = worst.max(v.abs());
            }
        }
    }
    worst
}

#[test]
fn the_quintic_ramp_keeps_q_qdot_qddot_continuous_the_linear_one_does_not() {
    let window: WarpWindow = "1.0:1.5".parse().unwrap();
    let at = |fps: f64, ramp: RampShape| {
        let opts = BlendOptions {
            ramp,
            ..Default::default()
        };
        let out = blend(&take_a(fps), &take_b(fps), window, TimeMap::IDENTITY, &opts).unwrap();
        [1, 2, 3].map(|order| edge_derivative(&out, window, order))
    };
    let (q120, q240) = (at(120.0, RampShape::Quintic), at(240.0, RampShape::Quintic));
    let (l120, l240) = (at(120.0, RampShape::Linear), at(240.0, RampShape::Linear));
    // q̇ (first differences) converges for both: q is continuous
    for (c, f) in [(q120[0], q240[0]), (l120[0], l240[0])] {
        assert!((f / c - 1.0).abs() < 0.1, "q̇ estimate {c} → {f}");
    }
    // q̈: converges with the quintic, doubles with each halving of dt with the linear ramp
    assert!(
        (q240[1] / q120[1] - 1.0).abs() < 0.1,
        "quintic q̈ {} → {}",
        q120[1],
        q240[1]
    );
    assert!(
        l240[1] / l120[1] > 1.8,
        "linear q̈ {} → {}",
        l120[1],
        l240[1]
    );
    // q⃛ stays bounded with the quintic (q̈ continuous); ×4 per halving with the linear ramp
    assert!(
        q240[2] / q120[2] < 1.3,
        "quintic q⃛ {} → {}",
        q120[2],
        q240[2]
    );
    assert!(
        l240[2] / l120[2] > 3.5,
        "linear q⃛ {} → {}",
        l120[2],
        l240[2]
    );
}

#[test]
fn outside_the_window_the_result_is_each_take() {
    let (a, b) = (take_a(120.0), take_b(120.0));
    let window: WarpWindow = "1.0:1.5".parse().unwrap();
    let out = blend(&a, &b, window, TimeMap::IDENTITY, &BlendOptions::default()).unwrap();
    assert_eq!(out.frames, b.frames);
    for k in 0..out.frames {
        let t = k as f64 / 120.0;
        let reference = if t < 1.0 - 1e-9 {
            &a
        } else if t > 1.5 + 1e-9 {
            &b
        } else {
            continue;
        };
        // the same rotations (channels may differ by whole turns: continuity is kept)
        for (x, y) in out.frame(k).iter().zip(reference.frame(k)) {
            let d = (x - y) - 360.0 * ((x - y) / 360.0).round();
            assert!(d.abs() < 1e-8, "frame {k}: {x} vs {y}");
        }
    }
}

/// `t` turned by `yaw` (rad) about the vertical through the origin, shifted by `shift` (cm).
fn turned(t: &Bvh, yaw: f64, shift: Vector3<f64>) -> Bvh {
    let r = Matrix3::from(nalgebra::Rotation3::from_axis_angle(
        &Vector3::y_axis(),
        yaw,
    ));
    let order = EulerOrder::ZXY;
    let mut out = t.clone();
    let mut prev = None;
    for k in 0..t.frames {
        let row = &mut out.motion[k * t.channel_count..(k + 1) * t.channel_count];
        let p = r * Vector3::new(row[0], row[1], row[2]) + shift;
        row[..3].copy_from_slice(p.as_slice());
        let rot = r * euler_to_matrix(order, [row[3], row[4], row[5]].map(f64::to_radians));
        let near = prev.unwrap_or([row[3], row[4], row[5]].map(f64::to_radians));
        let e = articula::rotation::matrix_to_euler_near(order, &rot, near);
        row[3..6].copy_from_slice(&e.map(f64::to_degrees));
        prev = Some(e);
    }
    out
}

#[test]
fn aligning_root_and_heading_undoes_a_turn_and_shift_of_take_b() {
    let a = take_a(120.0);
    let window: WarpWindow = "1.0:1.6".parse().unwrap();
    let b = turned(&a, 70f64.to_radians(), Vector3::new(300.0, 0.0, -200.0));
    let opts = BlendOptions {
        align: Align::ALL,
        ..Default::default()
    };
    let out = blend(&a, &b, window, TimeMap::IDENTITY, &opts).unwrap();
    let d = max_abs_diff(&out, &a);
    assert!(d < 1e-6, "aligned blend differs from a by {d}");
    // without alignment the end of the result is b, turned away
    let raw = blend(&a, &b, window, TimeMap::IDENTITY, &BlendOptions::default()).unwrap();
    assert!(max_abs_diff(&raw, &a) > 100.0);
    // the root height of b is kept: only the ground plane is aligned
    let lifted = turned(&a, 0.0, Vector3::new(0.0, 5.0, 0.0));
    let out = blend(&a, &lifted, window, TimeMap::IDENTITY, &opts).unwrap();
    let last = out.frames - 1;
    assert!((out.frame(last)[1] - a.frame(last)[1] - 5.0).abs() < 1e-9);
    assert!((out.frame(last)[0] - a.frame(last)[0]).abs() < 1e-9);
}

#[test]
fn take_b_is_retimed_and_resampled_at_a_frames() {
    let a = take_a(120.0);
    let window: WarpWindow = "1.0:1.6".parse().unwrap();
    let opts = BlendOptions::default();
    // b starts 0.25 s later: an offset of −0.25 s lines it up again, exactly
    let m = 30;
    let mut late = a.clone();
    late.motion.drain(..m * a.channel_count);
    late.frames -= m;
    let tm = TimeMap {
        offset: -0.25,
        scale: 1.0,
    };
    let out = blend(&a, &late, window, tm, &opts).unwrap();
    assert_eq!(out.frames, a.frames);
    assert!(max_abs_diff(&out, &a) < 1e-9);
    // b plays twice as fast (every other frame): scale 0.5 slows it back down, interpolated
    let mut fast = a.clone();
    fast.motion = (0..a.frames)
        .step_by(2)
        .flat_map(|k| a.frame(k).to_vec())
        .collect();
    fast.frames = fast.motion.len() / a.channel_count;
    let out = blend(
        &a,
        &fast,
        window,
        TimeMap {
            offset: 0.0,
            scale: 0.5,
        },
        &opts,
    )
    .unwrap();
    assert!(max_abs_diff(&out, &a) < 0.1, "{}", max_abs_diff(&out, &a));
    // b captured at another rate (50 fps)
    let b50 = take_a(50.0);
    let out = blend(&a, &b50, window, TimeMap::IDENTITY, &opts).unwrap();
    assert_eq!(out.frames, a.frames);
    assert!(max_abs_diff(&out, &a) < 0.2, "{}", max_abs_diff(&out, &a));
}

#[test]
fn windows_outside_the_takes_are_refused() {
    let (a, b) = (take_a(120.0), take_b(120.0));
    let opts = BlendOptions::default();
    let e = blend(&a, &b, "2.5:3.5".parse().unwrap(), TimeMap::IDENTITY, &opts).unwrap_err();
    assert!(e.to_string().contains("ends after take a"), "{e}");
    let tm = TimeMap {
        offset: -2.0,
        scale: 1.0,
    };
    let e = blend(&a, &b, "1.0:2.5".parse().unwrap(), tm, &opts).unwrap_err();
    assert!(e.to_string().contains("time offset"), "{e}");
}

#[test]
fn chained_windows_visit_each_take() {
    let (a, b) = (take_a(120.0), take_b(120.0));
    let windows: Vec<WarpWindow> = ["0.5:0.8", "1.8:2.2"]
        .iter()
        .map(|w| w.parse().unwrap())
        .collect();
    let opts = BlendOptions::default();
    let out = blend_chain(&[&a, &b, &a], &windows, &[], &opts).unwrap();
    let same = |k: usize, t: &Bvh| {
        out.frame(k).iter().zip(t.frame(k)).all(|(x, y)| {
            let d = (x - y) - 360.0 * ((x - y) / 360.0).round();
            d.abs() < 1e-8
        })
    };
    assert!((0..60).all(|k| same(k, &a)));
    assert!((97..216).all(|k| same(k, &b)));
    assert!((265..out.frames).all(|k| same(k, &a)));
    // one link is a plain blend
    let one = blend_chain(&[&a, &b], &windows[..1], &[], &opts).unwrap();
    let direct = blend(&a, &b, windows[0], TimeMap::IDENTITY, &opts).unwrap();
    assert_eq!(one, direct);
    // windows must follow one another and match the takes
    let overlapping: Vec<WarpWindow> = ["0.5:2.0", "1.8:2.2"]
        .iter()
        .map(|w| w.parse().unwrap())
        .collect();
    assert!(blend_chain(&[&a, &b, &a], &overlapping, &[], &opts).is_err());
    assert!(blend_chain(&[&a, &b, &a], &windows[..1], &[], &opts).is_err());
}

/// Largest difference between the joint rotations (Frobenius norm of `Ra − Rb`) and positions of
/// two takes of one skeleton, frame by frame.
fn same_rotations(a: &Bvh, b: &Bvh) -> f64 {
    assert_eq!(a.frames, b.frames);
    let mut worst: f64 = 0.0;
    for k in 0..a.frames {
        let (fa, fb) = (a.frame(k), b.frame(k));
        for j in &a.joints {
            let cols: Vec<usize> = (0..j.channels.len()).map(|i| j.first_channel + i).collect();
            let rot = |f: &[f64]| {
                j.channels
                    .iter()
                    .zip(&cols)
                    .filter(|(c, _)| c.is_rotation())
                    .fold(Matrix3::<f64>::identity(), |r, (c, &col)| {
                        r * articula::rotation::axis_rotation(c.axis(), f[col].to_radians())
                    })
            };
            worst = worst.max((rot(fa) - rot(fb)).norm());
            for (c, &col) in j.channels.iter().zip(&cols) {
                if !c.is_rotation() {
                    worst = worst.max((fa[col] - fb[col]).abs());
                }
            }
        }
    }
    worst
}

#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn real_takes_of_one_skeleton_blend_and_others_are_refused() {
    let read = |name: &str| articula::io::bvh::read(&common::real_take(name)).unwrap();
    // Bandai walk into kick: same skeleton, position channels on every joint, 30 fps
    let (walk, kick) = (
        read("dataset-1_walk_normal_001.bvh"),
        read("dataset-1_kick_normal_001.bvh"),
    );
    let window: WarpWindow = "3.0:3.5".parse().unwrap();
    let opts = BlendOptions {
        align: Align::ALL,
        ..Default::default()
    };
    let out = blend(
        &walk,
        &kick,
        window,
        TimeMap {
            offset: 2.0,
            scale: 1.0,
        },
        &opts,
    )
    .unwrap();
    // largest frame-to-frame change of any channel, around the window edges and in the inputs
    let step = |t: &Bvh, frames: std::ops::Range<usize>| {
        frames
            .map(|k| {
                t.frame(k)
                    .iter()
                    .zip(t.frame(k - 1))
                    .map(|(x, y)| (x - y).abs())
                    .fold(0.0, f64::max)
            })
            .fold(0.0, f64::max)
    };
    let edges = step(&out, 85..96).max(step(&out, 100..111));
    let inputs = step(&walk, 1..walk.frames).max(step(&kick, 1..kick.frames));
    assert!(
        edges <= inputs,
        "step at the edges {edges}, inputs {inputs}"
    );
    // the root heading and ground position of the kick start where the walk is at 3.0 s
    let (a90, o90) = (walk.frame(90), out.frame(90));
    for c in [0, 2] {
        assert!((a90[c] - o90[c]).abs() < 1e-9);
    }
    // self blend on real takes: the same rotations (channels kept continuous: pirouette's
    // captured channels flip branch, the blend's do not)
    for name in [
        "cmu_01_01.bvh",
        "pirouette.bvh",
        "AV_8Walk_Meredith_HVHA_Rep1.bvh",
    ] {
        let take = read(name);
        let again = blend(
            &take,
            &take,
            "1.0:2.0".parse().unwrap(),
            TimeMap::IDENTITY,
            &opts,
        )
        .unwrap();
        assert!(same_rotations(&again, &take) < 1e-9, "{name}");
    }
    // other skeletons are refused, naming the joint
    let (jump, dance, daz) = (
        read("cmu_01_01.bvh"),
        read("cmu_05_20-mb.bvh"),
        read("cmu_05_20-daz.bvh"),
    );
    let e = check_same_skeleton(&jump, &dance).unwrap_err().to_string();
    assert!(
        e.contains("`LFingers`") && e.contains("`LeftHandIndex1`"),
        "{e}"
    );
    let e = check_same_skeleton(&dance, &daz).unwrap_err().to_string();
    assert!(e.contains("`Hips`") && e.contains("`hip`"), "{e}");
}
