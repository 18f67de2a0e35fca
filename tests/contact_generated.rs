//! Ground reactions of BVH takes that need no capture data:
//! - the project's generated walk (`io::generate::walk`: planted feet rolling heel → flat →
//!   ball, 60 % stance, double supports, a smooth pelvis path): a foot is always down, with
//!   double supports; over whole strides the force the motion needs averages body weight (the
//!   centre of mass neither rises nor sinks) and the feet carry all of it (the root force drops
//!   by orders of magnitude); the stance knee is loaded, and at 80 kg its peak stays in the
//!   range of walking forces (below 2.5 N·m/kg; above Winter's 0.5–1 N·m/kg, at the other
//!   foot's heel strike, where the trailing foot's force can only be taken parallel to the
//!   whole-body force: docs/knee-study.md);
//! - `data/demo_walk.bvh` is exactly what `articula generate walk` writes;
//! - feet across naming schemes, placed through the channel map: a Daz-style foot without a
//!   toe joint takes its toe point from its End Site, a Bandai-style one from its toe joint,
//!   and the notes say which (issue 14 item 1).

use articula::dynamics::grf::estimate_ground_reactions_with_feet;
use articula::io::bvh::{self, PositionMode, UpAxis};
use articula::io::generate::{WalkParams, walk};
use articula::model::bvh::{BvhModelOptions, build_bvh_model};
use articula::motion::contact::{ContactParams, feet_of_bvh};
use articula::motion::derive::differentiate_columns;
use articula::motion::smooth::{SmoothSpec, smooth_columns};
use articula::motion::take::Trajectory;
use articula::pipeline::{self, Contact, TakeOptions};
use nalgebra::Vector3;
use std::path::Path;

const G: f64 = 9.81;

#[test]
fn the_generated_walk_is_carried_by_its_feet() {
    // four whole strides at 120 fps
    let params = WalkParams {
        duration_s: 4.4,
        cycle_s: 1.1,
        ..WalkParams::default()
    };
    let take = walk(&params);
    let positions = bvh::resolve_position_modes(&take, PositionMode::Auto);
    let opts = BvhModelOptions::new("walk", 0.01, UpAxis::Y, positions);
    let (model, map) = build_bvh_model(&take, &opts).unwrap();
    let traj = Trajectory::from_bvh(&take, &model, &map);
    let rows = |c: &[Vec<f64>]| -> Vec<Vec<f64>> {
        (0..c[0].len())
            .map(|k| c.iter().map(|x| x[k]).collect())
            .collect()
    };
    // the pipeline's low-pass (Winter's 6 Hz Butterworth): the root height follows the lowest
    // foot point, which has corners
    let n = traj.q.len();
    let dt = take.frame_time;
    let mut cols: Vec<Vec<f64>> = (0..model.nq)
        .map(|j| traj.q.iter().map(|q| q[j]).collect())
        .collect();
    let spec = SmoothSpec::Butterworth {
        cutoff_hz: 6.0,
        order: 2,
    };
    smooth_columns(spec, dt, &mut cols).unwrap();
    let q = rows(&cols);
    let mut vc = vec![vec![0.0; n]; model.nv];
    differentiate_columns(&cols, dt, &mut vc);
    let mut ac = vec![vec![0.0; n]; model.nv];
    differentiate_columns(&vc, dt, &mut ac);
    let (v, a) = (rows(&vc), rows(&ac));

    let feet = feet_of_bvh(&take, &map, &model);
    let joints: Vec<&str> = feet.iter().map(|f| f.joint.as_str()).collect();
    assert_eq!(joints, ["LeftFoot", "RightFoot"]);
    let gr = estimate_ground_reactions_with_feet(
        &model,
        &feet,
        &traj.time,
        &q,
        &v,
        &a,
        1,
        &ContactParams::default(),
    )
    .unwrap();

    let weight = model.total_mass() * G;
    let mean = gr
        .grf
        .iter()
        .map(|f| f.iter().map(|x| x.y).sum::<f64>())
        .sum::<f64>()
        / n as f64
        / weight;
    let rms = |w: &[[f64; 6]]| {
        (w.iter()
            .map(|x| x[0] * x[0] + x[1] * x[1] + x[2] * x[2])
            .sum::<f64>()
            / n as f64)
            .sqrt()
    };
    let (none, with) = (rms(&gr.wrench), rms(&gr.residual));
    let needed = gr.wrench.iter().map(|w| w[1]).sum::<f64>() / n as f64 / weight;
    println!("generated walk: mean needed vertical force {needed:.4} BW");
    let both = gr.contact.iter().filter(|c| c[0] && c[1]).count();
    println!(
        "generated walk: mean vertical GRF {mean:.4} BW; root force rms {none:.1} N top-down, \
         {with:.2} N with the feet; double support in {both} of {n} frames"
    );
    let pulls = gr.wrench.iter().filter(|w| w[1] < 0.0).count();
    println!("generated walk: the floor would have to pull in {pulls} of {n} frames");
    assert!((needed - 1.0).abs() < 0.01, "{needed}");
    assert!((mean - 1.0).abs() < 0.02, "{mean}");
    assert_eq!(pulls, 0);
    assert!(
        gr.contact.iter().all(|c| c[0] || c[1]),
        "a walk has no flight"
    );
    assert!(both > n / 40, "double support {both}/{n}");
    assert!(with < none / 100.0, "{with} vs {none}");

    // the stance knee carries body weight: tens of N·m, where hanging it holds a few
    let knee = model.v_index("LeftLeg.Xrotation").unwrap();
    let peak = (0..n)
        .filter(|&k| gr.contact[k][0])
        .map(|k| gr.tau[k][knee].abs())
        .fold(0.0, f64::max);
    println!(
        "generated walk: left stance knee peak {peak:.1} N·m ({:.2} N·m/kg)",
        peak / model.total_mass()
    );
    assert!(peak / model.total_mass() > 0.3, "{peak}");
}

#[test]
fn the_demo_walk_is_the_generated_walk() {
    let file = std::fs::read_to_string(
        std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/demo_walk.bvh"),
    )
    .unwrap();
    let made = bvh::write_string(&walk(&WalkParams::default()));
    assert!(
        file == made,
        "data/demo_walk.bvh is stale: run `articula generate walk -o data/demo_walk.bvh`"
    );
}

#[test]
fn the_demo_walk_knee_at_80_kg_is_in_the_range_of_walking() {
    use articula::pipeline::{Contact, TakeOptions, estimate_take_ground_reactions, load_take};
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/demo_walk.bvh");
    let mut opts = TakeOptions {
        contact: Contact::Feet,
        ..TakeOptions::default()
    };
    opts.body.mass_kg = 80.0;
    let take = load_take(&path, &opts).unwrap();
    let gr = estimate_take_ground_reactions(&take).unwrap();
    for (j, knee) in ["LeftLeg.Xrotation", "RightLeg.Xrotation"]
        .iter()
        .enumerate()
    {
        let i = take.model.v_index(knee).unwrap();
        let peak = gr.tau.iter().map(|t| t[i].abs()).fold(0.0, f64::max);
        let stance = (0..gr.tau.len())
            .filter(|&k| gr.contact[k][j])
            .map(|k| gr.tau[k][i].abs())
            .fold(0.0, f64::max);
        println!("demo walk, 80 kg: {knee} peak {peak:.1} N·m, in stance {stance:.1} N·m");
        assert!(
            (0.5 * 80.0..2.5 * 80.0).contains(&peak),
            "{knee}: {peak} N·m"
        );
    }
    let rms = |w: &[[f64; 6]]| {
        (w.iter()
            .map(|x| x[0] * x[0] + x[1] * x[1] + x[2] * x[2])
            .sum::<f64>()
            / w.len() as f64)
            .sqrt()
    };
    assert!(rms(&gr.residual) < 1.0, "{}", rms(&gr.residual));
}

#[test]
fn the_demo_walk_feet_do_not_slide_in_stance() {
    // through the model built from the file (not the generator's own kinematics), without
    // smoothing: while a foot is flat (8–35 % of its cycle) its ankle and toe joints stay put;
    // while it rolls over the ball of the foot (35–60 %, the foot turning 40°) its toe joint,
    // 2 cm above the ball, moves at most 2 cm·sin 40° = 1.3 cm
    use articula::dynamics::{Workspace, forward_kinematics};
    use articula::motion::smooth::SmoothSpec;
    use articula::pipeline::{TakeOptions, load_take};
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/demo_walk.bvh");
    let opts = TakeOptions {
        smooth: Some(SmoothSpec::None),
        ..TakeOptions::default()
    };
    let take = load_take(&path, &opts).unwrap();
    let feet = feet_of_bvh(&take.bvh, &take.map, &take.model);
    let mut ws = Workspace::new(&take.model);
    let cycle = WalkParams::default().cycle_s;
    let mut flat: Vec<Option<(Vector3<f64>, Vector3<f64>)>> = vec![None; 2];
    let mut roll: Vec<Option<Vector3<f64>>> = vec![None; 2];
    let (mut flat_moved, mut roll_moved): (f64, f64) = (0.0, 0.0);
    for (k, t) in take.states.time.iter().enumerate() {
        forward_kinematics(&take.model, &mut ws, &take.states.q[k]);
        for (j, shift) in [(0, 0.0), (1, 0.5)] {
            let p = (t / cycle - shift).rem_euclid(1.0);
            let (ankle, toe) = (feet[j].ankle(&ws.o_x_i), feet[j].toe(&ws.o_x_i));
            if (0.085..0.345).contains(&p) {
                let (a, b) = *flat[j].get_or_insert((ankle, toe));
                flat_moved = flat_moved.max((ankle - a).norm()).max((toe - b).norm());
            } else {
                flat[j] = None;
            }
            if (0.35..0.6).contains(&p) {
                let b = *roll[j].get_or_insert(toe);
                roll_moved = roll_moved.max((toe - b).xz().norm());
            } else {
                roll[j] = None;
            }
        }
    }
    println!(
        "demo walk: flat feet move {flat_moved:.1e} m; the toe joint moves {roll_moved:.4} m \
         while the foot rolls over its ball"
    );
    assert!(flat_moved < 1e-6, "{flat_moved} m");
    assert!(
        roll_moved < 0.02 * 40f64.to_radians().sin() + 1e-3,
        "{roll_moved} m"
    );
}

/// A lower body in centimetres, Y up, with the given foot and toe names; `toe: None` gives the
/// foot an End Site instead of a toe joint.
fn legs(hips: &str, side: [(&str, &str, &str, Option<&str>); 2]) -> String {
    let mut s = format!(
        "HIERARCHY\nROOT {hips}\n{{\n OFFSET 0 90 0\n CHANNELS 6 Xposition Yposition \
         Zposition Zrotation Xrotation Yrotation\n"
    );
    for (x, (thigh, shin, foot, toe)) in [10.0, -10.0].iter().zip(side) {
        s += &format!(
            " JOINT {thigh}\n {{\n  OFFSET {x} -5 0\n  CHANNELS 3 Zrotation Xrotation \
             Yrotation\n  JOINT {shin}\n  {{\n   OFFSET 0 -40 0\n   CHANNELS 3 Zrotation \
             Xrotation Yrotation\n   JOINT {foot}\n   {{\n    OFFSET 0 -40 0\n    CHANNELS 3 \
             Zrotation Xrotation Yrotation\n"
        );
        match toe {
            Some(t) => {
                s += &format!(
                    "    JOINT {t}\n    {{\n     OFFSET 0 -7 12\n     CHANNELS 3 Zrotation \
                     Xrotation Yrotation\n     End Site\n     {{\n      OFFSET 0 0 5\n     \
                     }}\n    }}\n"
                )
            }
            None => s += "    End Site\n    {\n     OFFSET 0 -7 17\n    }\n",
        }
        s += "   }\n  }\n }\n";
    }
    s += "}\nMOTION\nFrames: 1\nFrame Time: 0.01\n";
    let channels = s.matches("CHANNELS 3").count() * 3 + 6;
    s += &vec!["0"; channels].join(" ");
    s.push('\n');
    s
}

#[test]
fn feet_are_placed_through_the_channel_map_across_naming_schemes() {
    let daz = legs(
        "hip",
        [
            ("lThigh", "lShin", "lFoot", None),
            ("rThigh", "rShin", "rFoot", None),
        ],
    );
    let bandai = legs(
        "Hips",
        [
            ("UpperLeg_L", "LowerLeg_L", "Foot_L", Some("Toes_L")),
            ("UpperLeg_R", "LowerLeg_R", "Foot_R", Some("Toes_R")),
        ],
    );
    for (text, foot, toe_joint, toe_at) in [
        (daz, "lFoot", None, Vector3::new(0.0, -0.07, 0.17)),
        (
            bandai,
            "Foot_L",
            Some("Toes_L"),
            Vector3::new(0.0, -0.07, 0.12),
        ),
    ] {
        let take = bvh::parse_str(&text, Path::new("legs.bvh")).unwrap();
        let positions = bvh::resolve_position_modes(&take, PositionMode::Auto);
        let opts = BvhModelOptions::new("legs", 0.01, UpAxis::Y, positions);
        let (model, map) = build_bvh_model(&take, &opts).unwrap();
        let feet = feet_of_bvh(&take, &map, &model);
        assert_eq!(feet.len(), 2, "{foot}");
        assert_eq!(feet[0].joint, foot);
        assert_eq!(feet[0].name, "left");
        // in the rest pose every frame is aligned with the world: toe = ankle + offset
        let rest = |body: usize| {
            let mut i = body;
            let mut x = articula::spatial::SpatialTransform::IDENTITY;
            while i > 0 {
                x = model.placement[i].compose(&x);
                i = model.parent[i];
            }
            x
        };
        let ankle = rest(feet[0].ankle_body).transform_point(&feet[0].ankle_point);
        let toe = rest(feet[0].toe_body).transform_point(&feet[0].toe_point);
        assert!(
            (toe - ankle - toe_at).norm() < 1e-12,
            "{foot}: {}",
            toe - ankle
        );
        // the heel lies under the ankle, at the toe's height
        let heel = rest(feet[0].ankle_body).transform_point(&feet[0].heel_point);
        assert!(
            (heel - ankle - Vector3::new(0.0, toe_at.y, 0.0)).norm() < 1e-12,
            "{heel}"
        );
        // the notes state a toe-less foot's contact model: a point along the foot's own
        // bone, as far from the heel as the rest pose puts it (the toe joint's case: below)
        if toe_joint.is_none() {
            let note = contact_model_note(&take);
            let want = format!(
                "left `{foot}`: no toe joint, the toe point {:.1} cm from the heel along the \
                 foot's own bone",
                100.0 * toe_at.z
            );
            assert!(note.contains(&want), "{note}\nwants {want}");
        }
    }
}

/// The note of a take's contact model per foot, loaded with contact feet (cm, Y up, its only
/// frame kept).
fn contact_model_note(take: &bvh::Bvh) -> String {
    let options = TakeOptions {
        contact: Contact::Feet,
        up: Some(UpAxis::Y),
        unit: Some("cm".parse().unwrap()),
        keep_first_frame: true,
        ..TakeOptions::default()
    };
    let mut t = pipeline::take_from_bvh(Path::new("t.bvh"), take.clone(), &options).unwrap();
    pipeline::resolve_contact(&mut t);
    t.notes
        .iter()
        .find(|n| n.starts_with("contact model per foot"))
        .unwrap_or_else(|| panic!("no contact model in {:?}", t.notes))
        .clone()
}

/// A foot with a toe joint: the notes name it, and the heel and toe points lie as far apart as
/// the demo skeleton's rest pose puts the ball of the foot from the heel under the ankle.
#[test]
fn the_notes_give_each_feet_contact_model() {
    let b = bvh::read(Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/data/demo_walk.bvh"
    )))
    .unwrap();
    let note = contact_model_note(&b);
    for side in ["Left", "Right"] {
        let toe = b
            .joints
            .iter()
            .position(|j| j.name == format!("{side}ToeBase"))
            .unwrap();
        // the toe's offset from the ankle; the heel is under the ankle at the toe's height
        let o = b.joints[toe].offset * 0.01;
        let length = 100.0 * (o.x * o.x + o.z * o.z).sqrt();
        let want = format!(
            "`{side}Foot`: heel and toe points {length:.1} cm apart, the toe at `{side}ToeBase`"
        );
        assert!(note.contains(&want), "{note}\nwants {want}");
    }
}
