//! BVH semantics from the definition: `R = R_c1(a1)·R_c2(a2)·R_c3(a3)` in degrees, a joint's
//! local transform `T(offset)·T(p)·R`, position channels that add to or replace the OFFSET,
//! and the inferred up axis, unit and stature of a skeleton.

use articula::error::Error;
use articula::io::bvh::{
    self, Bvh, BvhJoint, Channel, LengthUnit, PositionMode, ResolvedPosition, UpAxis,
};
use articula::rotation::{EulerOrder, euler_to_matrix};
use nalgebra::Vector3;
use std::path::Path;

fn parse(text: &str) -> Bvh {
    bvh::parse_str(text, Path::new("inline.bvh")).unwrap_or_else(|e| panic!("{e}"))
}

/// A root with 6 channels (ZXY) and a child with `child_channels`, one frame of `values`.
fn two_joints(child_channels: &str, child_offset: &str, values: &str) -> Bvh {
    parse(&format!(
        "HIERARCHY\nROOT r\n{{\nOFFSET 0 0 0\nCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n\
         JOINT c\n{{\nOFFSET {child_offset}\nCHANNELS {child_channels}\nEnd Site\n{{\nOFFSET 0 5 0\n}}\n}}\n}}\n\
         MOTION\nFrames: 1\nFrame Time: 0.1\n{values}\n"
    ))
}

fn near(a: Vector3<f64>, b: Vector3<f64>) -> bool {
    (a - b).norm() < 1e-12
}

#[test]
fn rotation_is_the_product_in_channel_order_in_degrees() {
    let b = two_joints(
        "3 Yrotation Zrotation Xrotation",
        "0 10 0",
        "0 0 0 10 20 30 40 50 60",
    );
    let row = b.frame(0);
    let r = bvh::joint_rotation(&b.joints[1], row);
    let expected = euler_to_matrix(
        EulerOrder::YZX,
        [40f64.to_radians(), 50f64.to_radians(), 60f64.to_radians()],
    );
    assert!((r - expected).abs().max() < 1e-15);
    let r0 = bvh::joint_rotation(&b.joints[0], row);
    let e0 = euler_to_matrix(
        EulerOrder::ZXY,
        [10f64.to_radians(), 20f64.to_radians(), 30f64.to_radians()],
    );
    assert!((r0 - e0).abs().max() < 1e-15);
}

#[test]
fn world_positions_by_hand() {
    // root at (1, 2, 3) turned 90° about Z: the child's OFFSET (0, 10, 0) points along −x
    let b = two_joints(
        "3 Zrotation Xrotation Yrotation",
        "0 10 0",
        "1 2 3 90 0 0 0 0 0",
    );
    let modes = bvh::resolve_position_modes(&b, PositionMode::Auto);
    let p = bvh::bvh_world_positions(&b, &modes, 0);
    assert!(near(p[0], Vector3::new(1.0, 2.0, 3.0)));
    assert!(near(p[1], Vector3::new(-9.0, 2.0, 3.0)), "{}", p[1]);
    // the child turns a further 90° about its own X: its End Site (0, 5, 0) goes along the
    // world z axis (R = Rz(90°)·Rx(90°) maps y to z)
    let b = two_joints(
        "3 Zrotation Xrotation Yrotation",
        "0 10 0",
        "1 2 3 90 0 0 0 90 0",
    );
    let s = bvh::bvh_end_site_positions(&b, &modes, 0);
    assert_eq!(s.len(), 1);
    assert!(near(s[0], Vector3::new(-9.0, 2.0, 8.0)), "{}", s[0]);
}

#[test]
fn translation_adds_or_replaces_per_axis() {
    let b = two_joints(
        "4 Xposition Zrotation Xrotation Yrotation",
        "3 10 0",
        "0 0 0 0 0 0 7 0 0 0",
    );
    let j = &b.joints[1];
    let row = b.frame(0);
    assert_eq!(
        bvh::joint_translation(j, ResolvedPosition::Add, row),
        Vector3::new(10.0, 10.0, 0.0)
    );
    assert_eq!(
        bvh::joint_translation(j, ResolvedPosition::Replace, row),
        Vector3::new(7.0, 10.0, 0.0)
    );
    assert_eq!(
        bvh::joint_translation(j, ResolvedPosition::None, row),
        Vector3::new(3.0, 10.0, 0.0)
    );
}

#[test]
fn forced_modes_apply_to_joints_with_position_channels_only() {
    let b = two_joints(
        "3 Zrotation Xrotation Yrotation",
        "0 10 0",
        "0 0 0 0 0 0 0 0 0",
    );
    use ResolvedPosition as R;
    assert_eq!(
        bvh::resolve_position_modes(&b, PositionMode::Add),
        vec![R::Add, R::None]
    );
    assert_eq!(
        bvh::resolve_position_modes(&b, PositionMode::Replace),
        vec![R::Replace, R::None]
    );
}

#[test]
fn auto_replaces_values_that_repeat_the_offset() {
    // Bandai style: the child's channel values equal its OFFSET
    let b = two_joints(
        "6 Xposition Yposition Zposition Zrotation Xrotation Yrotation",
        "0 10 0",
        "0 90 0 0 0 0 0 10 0 0 0 0",
    );
    let modes = bvh::resolve_position_modes(&b, PositionMode::Auto);
    assert_eq!(modes[1], ResolvedPosition::Replace);
    // the root (OFFSET 0: no evidence of its own) follows the file's majority
    assert_eq!(modes[0], ResolvedPosition::Replace);
    let p = bvh::bvh_world_positions(&b, &modes, 0);
    assert!(
        near(p[1], Vector3::new(0.0, 100.0, 0.0)),
        "bone not doubled: {}",
        p[1]
    );
}

#[test]
fn auto_adds_values_around_zero() {
    // MakeHuman style: the child's channel values are zero deltas
    let b = two_joints(
        "6 Xposition Yposition Zposition Zrotation Xrotation Yrotation",
        "0 10 0",
        "0 90 0 0 0 0 0 0 0 0 0 0",
    );
    let modes = bvh::resolve_position_modes(&b, PositionMode::Auto);
    assert_eq!(modes, vec![ResolvedPosition::Add, ResolvedPosition::Add]);
    let p = bvh::bvh_world_positions(&b, &modes, 0);
    assert!(near(p[1], Vector3::new(0.0, 100.0, 0.0)));
}

#[test]
fn auto_on_a_lone_root_compares_distances() {
    // PyMO style: root OFFSET roughly the capture start, values absolute → replace
    let text = |offset: &str, values: &str| {
        format!(
            "HIERARCHY\nROOT r\n{{\nOFFSET {offset}\nCHANNELS 6 Xposition Yposition Zposition Xrotation Yrotation Zrotation\n\
             End Site\n{{\nOFFSET 0 5 0\n}}\n}}\nMOTION\nFrames: 2\nFrame Time: 0.1\n{values}\n"
        )
    };
    let b = parse(&text(
        "11.27 35.42 -54.33",
        "-6.5 35.55 -163 0 0 0\n-20 35.5 -120 0 0 0",
    ));
    assert_eq!(
        bvh::resolve_position_modes(&b, PositionMode::Auto),
        vec![ResolvedPosition::Replace]
    );
    // a root OFFSET with travelling deltas → add
    let b = parse(&text("0 1.2 9.5", "0 0 0 0 0 0\n3 0 0.5 0 0 0"));
    assert_eq!(
        bvh::resolve_position_modes(&b, PositionMode::Auto),
        vec![ResolvedPosition::Add]
    );
}

#[test]
fn option_strings() {
    for m in ["add", "replace", "auto"] {
        assert_eq!(m.parse::<PositionMode>().unwrap().to_string(), m);
    }
    assert!("sum".parse::<PositionMode>().is_err());
    assert_eq!("Z".parse::<UpAxis>().unwrap(), UpAxis::Z);
    assert_eq!(UpAxis::Y.index(), 1);
    assert!("w".parse::<UpAxis>().is_err());
    assert_eq!("cm".parse::<LengthUnit>().unwrap(), LengthUnit::Cm);
    assert_eq!("in".parse::<LengthUnit>().unwrap().scale_to_m(), 0.0254);
    assert!((LengthUnit::Cmu.scale_to_m() - 0.05644).abs() < 1e-5);
    assert_eq!(
        "0.05".parse::<LengthUnit>().unwrap(),
        LengthUnit::Custom(0.05)
    );
    assert!("-1".parse::<LengthUnit>().is_err());
    assert!("furlong".parse::<LengthUnit>().is_err());
}

/// (name, parent, offset in cm with y up, End Site offset).
type Bone = (&'static str, Option<usize>, [f64; 3], Option<[f64; 3]>);

/// A standing T-pose, Y up, in cm (stature 170 from the heel at y = −95 to the head top at
/// y = 75), turned so that `up` is up, in units of `unit_m` metres.
fn t_pose(up: usize, unit_m: f64) -> Bvh {
    let k = 0.01 / unit_m;
    // (name, parent, offset in cm with y up, end site)
    let bones: &[Bone] = &[
        ("Hips", None, [0.0, 0.0, 0.0], None),
        ("Spine", Some(0), [0.0, 25.0, 0.0], None),
        ("Neck", Some(1), [0.0, 25.0, 0.0], None),
        ("Head", Some(2), [0.0, 5.0, 0.0], Some([0.0, 20.0, 0.0])),
        ("LArm", Some(2), [15.0, 0.0, 0.0], None),
        ("LHand", Some(4), [55.0, 0.0, 0.0], Some([15.0, 0.0, 0.0])),
        ("RArm", Some(2), [-15.0, 0.0, 0.0], None),
        ("RHand", Some(6), [-55.0, 0.0, 0.0], Some([-15.0, 0.0, 0.0])),
        ("LUpLeg", Some(0), [10.0, -5.0, 0.0], None),
        ("LLeg", Some(8), [0.0, -45.0, 0.0], None),
        ("LFoot", Some(9), [0.0, -45.0, 0.0], Some([0.0, 0.0, 15.0])),
        ("RUpLeg", Some(0), [-10.0, -5.0, 0.0], None),
        ("RLeg", Some(11), [0.0, -45.0, 0.0], None),
        ("RFoot", Some(12), [0.0, -45.0, 0.0], Some([0.0, 0.0, 15.0])),
    ];
    // rotate the y-up axes so that y goes to `up` (a cyclic permutation keeps handedness)
    let map = |v: [f64; 3]| {
        let s = (up + 2) % 3; // where x goes
        let mut out = Vector3::zeros();
        out[s] = v[0] * k;
        out[up] = v[1] * k;
        out[(up + 1) % 3] = v[2] * k;
        out
    };
    let mut joints = Vec::new();
    let mut first = 0;
    for (name, parent, offset, site) in bones {
        let channels = if parent.is_none() {
            vec![
                Channel::Xposition,
                Channel::Yposition,
                Channel::Zposition,
                Channel::Zrotation,
                Channel::Xrotation,
                Channel::Yrotation,
            ]
        } else {
            vec![Channel::Zrotation, Channel::Xrotation, Channel::Yrotation]
        };
        let n = channels.len();
        joints.push(BvhJoint {
            name: name.to_string(),
            parent: *parent,
            offset: map(*offset),
            channels,
            first_channel: first,
            end_sites: site.iter().map(|s| map(*s)).collect(),
            line: 0,
        });
        first += n;
    }
    let mut motion = vec![0.0; first];
    let hips = map([0.0, 95.0, 0.0]);
    motion[..3].copy_from_slice(hips.as_slice());
    Bvh {
        joints,
        frame_time: 1.0 / 30.0,
        frames: 1,
        channel_count: first,
        motion,
        first_frame: 0,
        decimals: Vec::new(),
    }
}

#[test]
fn rest_points_and_stature_of_a_t_pose() {
    let b = t_pose(1, 0.01);
    let pts = bvh::rest_points(&b);
    assert_eq!(pts.len(), 14 + 5);
    assert!(near(pts[5], Vector3::new(70.0, 50.0, 0.0)));
    assert!((bvh::rest_stature(&b, UpAxis::Y) - 170.0).abs() < 1e-9);
    assert!(
        (bvh::rest_stature(&b, UpAxis::X) - 170.0).abs() < 1e-9,
        "T-pose arm span"
    );
}

#[test]
fn up_axis_of_a_t_pose_in_every_orientation() {
    for (up, axis) in [(0, UpAxis::X), (1, UpAxis::Y), (2, UpAxis::Z)] {
        assert_eq!(bvh::detect_up(&t_pose(up, 0.01)), axis, "up = {up}");
    }
}

#[test]
fn unit_of_a_170_cm_skeleton_in_every_unit() {
    for unit in [
        LengthUnit::M,
        LengthUnit::Dm,
        LengthUnit::Cm,
        LengthUnit::Mm,
        LengthUnit::In,
        LengthUnit::Cmu,
    ] {
        let b = t_pose(1, unit.scale_to_m());
        let up = bvh::detect_up(&b);
        let (found, stature_m) = bvh::detect_unit(&b, up);
        assert_eq!(found, unit);
        assert!((stature_m - 1.70).abs() < 1e-9, "{unit}: {stature_m}");
        assert!(bvh::check_stature(stature_m).is_ok());
        let s = bvh::scale_for_stature(&b, up, 1.75);
        assert!((s * bvh::rest_stature(&b, up) - 1.75).abs() < 1e-12);
    }
}

#[test]
fn implausible_stature_names_the_options() {
    // a 170 mm "doll" read as any unit: none plausible, the nearest is returned and rejected
    let b = t_pose(1, 0.0001);
    let (_, stature_m) = bvh::detect_unit(&b, UpAxis::Y);
    let e = bvh::check_stature(stature_m).unwrap_err();
    assert!(matches!(e, Error::Invalid(_)));
    let m = e.to_string();
    assert!(
        m.contains("--unit") && m.contains("--stature 1.75") && m.contains("1–2.3 m"),
        "{m}"
    );
    assert!(bvh::check_stature(0.99).is_err() && bvh::check_stature(2.31).is_err());
    assert!(bvh::check_stature(f64::NAN).is_err());
    assert!(bvh::check_stature(1.0).is_ok() && bvh::check_stature(2.3).is_ok());
}

#[test]
fn a_rest_pose_on_its_side_uses_the_frames() {
    // Bandai style: the OFFSET-only pose lies along X, every frame stands along Y (the root
    // is turned 90° about Z); a placement root with one child stays on the floor at the origin
    let mut b = t_pose(0, 0.01);
    // root rotation channels: Zrotation first (index 3)
    b.motion[3] = 90.0;
    b.motion[..3].copy_from_slice(&[0.0, 95.0, 0.0]);
    assert_eq!(bvh::detect_up(&b), UpAxis::Y);
    assert!((bvh::stature(&b, UpAxis::Y) - 170.0).abs() < 1e-9);
    assert_eq!(bvh::detect_unit(&b, UpAxis::Y).0, LengthUnit::Cm);
}

mod homogeneous {
    //! `bvh_world_positions` against a second, independent reading of the definition: each
    //! joint's local transform as a 4×4 homogeneous matrix `T(offset) · T(p) · R` (with `p`
    //! added to or replacing the offset), chained root to leaf. Random trees, channel
    //! layouts, modes and values.
    use super::*;
    use nalgebra::Matrix4;
    use proptest::prelude::*;

    fn local(j: &BvhJoint, mode: ResolvedPosition, row: &[f64]) -> Matrix4<f64> {
        let mut offset = Matrix4::new_translation(&j.offset);
        let mut p = Vector3::zeros();
        let mut rot = Matrix4::identity();
        for (n, c) in j.channels.iter().enumerate() {
            let v = row[j.first_channel + n];
            if c.is_rotation() {
                let axis = [Vector3::x_axis(), Vector3::y_axis(), Vector3::z_axis()][c.axis()];
                rot *= Matrix4::from_axis_angle(&axis, v.to_radians());
            } else {
                p[c.axis()] = v;
                if mode == ResolvedPosition::Replace {
                    offset[(c.axis(), 3)] = 0.0;
                }
            }
        }
        if mode == ResolvedPosition::None {
            p = Vector3::zeros();
        }
        offset * Matrix4::new_translation(&p) * rot
    }

    const ALL: [Channel; 6] = [
        Channel::Xposition,
        Channel::Yposition,
        Channel::Zposition,
        Channel::Xrotation,
        Channel::Yrotation,
        Channel::Zrotation,
    ];

    proptest! {
        #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

        #[test]
        fn world_positions_equal_the_homogeneous_chain(
            n in 1usize..10,
            parents in proptest::collection::vec(any::<proptest::sample::Index>(), 10),
            layouts in proptest::collection::vec(proptest::sample::subsequence(ALL.to_vec(), 0..=6).prop_shuffle(), 10),
            offsets in proptest::collection::vec(proptest::array::uniform3(-50.0..50.0f64), 10),
            values in proptest::collection::vec(-400.0..400.0f64, 60),
            mode in prop_oneof![Just(PositionMode::Add), Just(PositionMode::Replace), Just(PositionMode::Auto)],
        ) {
            let mut joints = Vec::new();
            let mut first = 0;
            for i in 0..n {
                // parent before child: any earlier joint (the parser's order is depth-first,
                // but FK needs only parent < child)
                joints.push(BvhJoint {
                    name: format!("j{i}"),
                    parent: if i == 0 { None } else { Some(parents[i].index(i)) },
                    offset: Vector3::from(offsets[i]),
                    channels: layouts[i].clone(),
                    first_channel: first,
                    end_sites: vec![Vector3::new(1.0, 2.0, 3.0)],
                    line: 0,
                });
                first += layouts[i].len();
            }
            let b = Bvh { joints, frame_time: 0.1, frames: 1, channel_count: first, motion: values[..first].to_vec(), first_frame: 0, decimals: Vec::new() };
            let modes = bvh::resolve_position_modes(&b, mode);
            let p = bvh::bvh_world_positions(&b, &modes, 0);
            let s = bvh::bvh_end_site_positions(&b, &modes, 0);
            let mut world: Vec<Matrix4<f64>> = Vec::new();
            for (j, joint) in b.joints.iter().enumerate() {
                let l = local(joint, modes[j], b.frame(0));
                let w = match joint.parent { Some(q) => world[q] * l, None => l };
                world.push(w);
                let expect = w.fixed_view::<3, 1>(0, 3).into_owned();
                prop_assert!((p[j] - expect).norm() < 1e-9, "joint {}: {} vs {}", j, p[j], expect);
                let site = w * nalgebra::Vector4::new(1.0, 2.0, 3.0, 1.0);
                prop_assert!((s[j] - site.xyz()).norm() < 1e-9);
            }
        }
    }
}
