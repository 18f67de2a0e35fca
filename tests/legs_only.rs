//! A rig of a pelvis and two legs, without a trunk, loaded through the pipeline: its hips,
//! knees, ankles and toes land on their joints, named or not (issue 14 item 1: feet found on
//! any biped). Such a rig stands half a human's height, and its feet (ankle to toe tip) are
//! longer than the fifth of its own height within which `model::skeleton` looks for the ankle:
//! its toes were its ankles and its foot joints lay "inside the shank" (found by the lead while
//! writing `tests/contact_generated.rs`'s toe test). Its height for those thresholds is now
//! its pelvis's over the floor over 0.53 (`skeleton::HIP_HEIGHT_SHARE`).

use articula::io::bvh::UpAxis;
use articula::pipeline::{self, TakeOptions};

/// A lower body in centimetres, Y up: the pelvis 90 cm up, thighs and shanks of 40 cm, a foot
/// with a toe joint 7 cm below and 12 cm ahead of its ankle and a 5 cm toe; `frames` frames
/// of a knee bend (`bend` degrees at the hips and knees, the ankles keeping the feet flat).
fn legs_bvh(frames: usize, bend: f64) -> String {
    let mut s = String::from(
        "HIERARCHY\nROOT Hips\n{\n OFFSET 0 0 0\n CHANNELS 6 Xposition Yposition Zposition \
         Zrotation Xrotation Yrotation\n",
    );
    for (x, side) in [(10.0, "Left"), (-10.0, "Right")] {
        s += &format!(
            " JOINT {side}UpLeg\n {{\n  OFFSET {x} -5 0\n  CHANNELS 3 Zrotation Xrotation \
             Yrotation\n  JOINT {side}Leg\n  {{\n   OFFSET 0 -40 0\n   CHANNELS 3 Zrotation \
             Xrotation Yrotation\n   JOINT {side}Foot\n   {{\n    OFFSET 0 -40 0\n    CHANNELS \
             3 Zrotation Xrotation Yrotation\n    JOINT {side}ToeBase\n    {{\n     OFFSET 0 -7 \
             12\n     CHANNELS 3 Zrotation Xrotation Yrotation\n     End Site\n     {{\n      \
             OFFSET 0 0 5\n     }}\n    }}\n   }}\n  }}\n }}\n"
        );
    }
    s += &format!("}}\nMOTION\nFrames: {frames}\nFrame Time: 0.01\n");
    for k in 0..frames {
        // hips flex by a, knees by −2a, ankles by a: thigh and shank lean, the foot stays flat
        let a = bend * (std::f64::consts::PI * k as f64 / frames as f64).sin();
        let drop = 80.0 * (1.0 - a.to_radians().cos());
        let mut row = vec![0.0, 90.0 - drop, 0.0, 0.0, 0.0, 0.0];
        for _ in 0..2 {
            row.extend([0.0, -a, 0.0, 0.0, 2.0 * a, 0.0, 0.0, -a, 0.0, 0.0, 0.0, 0.0]);
        }
        let row: Vec<String> = row.iter().map(|v| format!("{v:.4}")).collect();
        s += &row.join(" ");
        s.push('\n');
    }
    s
}

/// The take's legs as joint names: (hip, knee, ankle, toe) for the left, then the right.
fn landmarks(take: &pipeline::Take) -> Vec<[String; 4]> {
    let name = |j: usize| take.bvh.joints[j].name.clone();
    let human = take.human.as_ref().unwrap();
    human
        .legs
        .iter()
        .map(|l| {
            [
                name(l.hip),
                name(l.knee),
                name(l.ankle),
                l.toe.map_or("-".into(), name),
            ]
        })
        .collect()
}

#[test]
fn a_legs_only_rig_finds_its_ankles_at_its_ankles() {
    let dir = tempfile::tempdir().unwrap();
    let text = legs_bvh(60, 30.0);
    // the same rig with names that say nothing: the shape alone must tell
    let mut blind = text.clone();
    for (i, name) in ["ToeBase", "Foot", "UpLeg", "Leg"].iter().enumerate() {
        for side in ["Left", "Right"] {
            blind = blind.replace(&format!("{side}{name}"), &format!("J{side}{i}"));
        }
    }
    for (what, text, unit) in [
        ("named, unit given", &text, Some("cm")),
        ("named, unit found", &text, None),
        ("unnamed", &blind, Some("cm")),
    ] {
        let path = dir.path().join("legs.bvh");
        std::fs::write(&path, text).unwrap();
        let options = TakeOptions {
            up: Some(UpAxis::Y),
            unit: unit.map(|u| u.parse().unwrap()),
            ..TakeOptions::default()
        };
        let take = pipeline::load_take(&path, &options).unwrap();
        let got = landmarks(&take);
        println!("{what}: {got:?}");
        let want: Vec<[String; 4]> = if what == "unnamed" {
            ["Left", "Right"]
                .map(|s| [2, 3, 1, 0].map(|i| format!("J{s}{i}")))
                .to_vec()
        } else {
            ["Left", "Right"]
                .map(|s| ["UpLeg", "Leg", "Foot", "ToeBase"].map(|j| format!("{s}{j}")))
                .to_vec()
        };
        assert_eq!(got, want, "{what}");
        // the feet the ground reactions stand on: at the ankles, the toe at the toe joint
        let feet = pipeline::contact_feet(&take);
        let joints: Vec<&str> = feet.iter().map(|f| f.joint.as_str()).collect();
        assert_eq!(joints, [&want[0][2], &want[1][2]], "{what}");
        // and no foot joint is taken for one inside the shank
        assert!(
            take.notes.iter().all(|n| !n.contains("inside a long bone")),
            "{what}: {:?}",
            take.notes
        );
    }
}
