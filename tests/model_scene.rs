//! The documented scene example reads, and its model choices reach the model: the locked
//! joints leave (fewer DOFs), the overridden link masses are kept, and the total is the
//! scene's body mass.

mod common;

use articula::io::bvh::{LengthUnit, PositionMode, UpAxis, resolve_position_modes};
use articula::io::generate::{WalkParams, walk};
use articula::io::scene::{self, PerJoint};
use articula::model::anthropometry::SegmentTable;
use articula::model::bvh::{BvhModelOptions, build_bvh_model};

#[test]
fn the_scene_example_builds_the_model_it_describes() {
    let path = common::repo("data/scene_example.toml");
    let s = scene::read(&path).unwrap();
    assert_eq!(s.takes, vec![common::repo("data/walk.bvh")]);
    assert_eq!(s.unit, Some(LengthUnit::Cm));
    assert_eq!(s.up, None);
    assert_eq!(s.position, PositionMode::Auto);
    let gains = s.gains.clone().unwrap();
    assert_eq!(gains.kp, PerJoint::all(400.0));
    assert_eq!(gains.kv.all, 40.0);
    assert_eq!(gains.kv.joints.get("LeftLeg"), Some(&60.0));

    let take = walk(&WalkParams::default());
    let modes = resolve_position_modes(&take, s.position);
    let scale = s.unit.unwrap().scale_to_m();
    let opts = BvhModelOptions::new("walk", scale, UpAxis::Y, modes)
        .with_scene(&s)
        .unwrap();
    let (model, _) = build_bvh_model(&take, &opts).unwrap();
    // four 3-channel joints locked
    assert_eq!(model.nv, take.channel_count - 12);
    assert!((model.total_mass() - 72.0).abs() < 1e-9);
    let thigh = model.body_index("LeftUpLeg.Yrotation").unwrap();
    assert_eq!(model.inertia[thigh].mass, 10.0);
    // its segment table (the regression) reaches the body; `segments = "fractions"` changes
    // the other links' masses
    assert_eq!(opts.body.segments, SegmentTable::Regression);
    let text = std::fs::read_to_string(&path)
        .unwrap()
        .replace("segments = \"regression\"", "segments = \"fractions\"");
    let f = scene::parse_str(&text, &path).unwrap();
    let fopts = BvhModelOptions::new("walk", scale, UpAxis::Y, opts.positions.clone())
        .with_scene(&f)
        .unwrap();
    assert_eq!(fopts.body.segments, SegmentTable::Fractions);
    let (fmodel, _) = build_bvh_model(&take, &fopts).unwrap();
    assert!((fmodel.total_mass() - 72.0).abs() < 1e-9);
    let head = model.body_index("Head.Yrotation").unwrap();
    assert!((fmodel.inertia[head].mass - model.inertia[head].mass).abs() > 1e-3);
}
