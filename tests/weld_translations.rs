//! Bones do not stretch (issue 13): position channels on the joints below the body's root are
//! welded at their mean by default, so a take written with six channels on every joint gets
//! the model of the same take written with rotations alone.
//!
//! - Where the channels restate the OFFSET exactly (added as zeros, or replacing it with its
//!   own value), the welded model *is* the rotations-only model: the same coordinates, and
//!   bit for bit the same torques, top-down and with the feet on the floor, in both joint
//!   models.
//! - Where they add capture noise, the joint sits at the noise's mean, the note reports the
//!   largest distance from it (the injected noise's, to 1e-12 m) and the torques move by no
//!   more than the weight of the body over the mean's displacement can explain.
//! - `--joint-translations keep` keeps a prismatic coordinate per channel (nq 126 on the
//!   walk's 21 joints).
//! - What the take writes agrees with its model: world positions are the model's forward
//!   kinematics; a BVH written from it keeps every channel of the file, the welded ones at
//!   their mean, and loads back to the same torques.
//!
//! The takes are the generated demo walk (`io::generate::walk`) rewritten with three position
//! channels before each joint's rotations.

mod common;

use articula::dynamics::{Workspace, forward_kinematics};
use articula::io::bvh::{self, Bvh, Channel, JointTranslations};
use articula::io::generate::{WalkParams, walk};
use articula::motion::smooth::SmoothSpec;
use articula::pipeline::{self, Contact, Take, TakeOptions};
use nalgebra::Vector3;
use std::path::Path;

/// The walk, 2 s at 60 fps (its 21 joints in cm, 6 channels on the root only).
fn plain() -> Bvh {
    walk(&WalkParams {
        fps: 60.0,
        duration_s: 2.0,
        ..WalkParams::default()
    })
}

/// How the added position channels state the OFFSET.
#[derive(Clone, Copy)]
enum Restate {
    /// Channel = OFFSET + noise (they replace it).
    Replace,
    /// Channel = noise (they add to it).
    Add,
}

/// `b` with `Xposition Yposition Zposition` before the rotations of every joint but the root,
/// restating the OFFSET as `how` says plus `noise(joint, frame, axis)` (cm).
fn six_channels(b: &Bvh, how: Restate, noise: impl Fn(usize, usize, usize) -> f64) -> Bvh {
    let mut out = b.clone();
    let mut first = 0;
    for (j, joint) in out.joints.iter_mut().enumerate() {
        if j > 0 {
            let mut c = vec![Channel::Xposition, Channel::Yposition, Channel::Zposition];
            c.extend(&joint.channels);
            joint.channels = c;
        }
        joint.first_channel = first;
        first += joint.channels.len();
    }
    out.channel_count = first;
    out.motion = Vec::with_capacity(b.frames * first);
    for k in 0..b.frames {
        let row = b.frame(k);
        for (j, joint) in b.joints.iter().enumerate() {
            if j > 0 {
                for a in 0..3 {
                    let stated = match how {
                        Restate::Replace => joint.offset[a],
                        Restate::Add => 0.0,
                    };
                    out.motion.push(stated + noise(j, k, a));
                }
            }
            let n = joint.channels.len();
            out.motion
                .extend_from_slice(&row[joint.first_channel..joint.first_channel + n]);
        }
    }
    out
}

/// Uniform noise in [−amp, amp] (cm), reproducible: a hash of joint, frame and axis.
fn noise(amp: f64) -> impl Fn(usize, usize, usize) -> f64 {
    move |j, k, a| {
        let mut x = (j as u64 * 1_000_003 + k as u64 * 7_919 + a as u64 * 104_729 + 1)
            .wrapping_mul(0x9E37_79B9_7F4A_7C15);
        x ^= x >> 31;
        x = x.wrapping_mul(0xBF58_476D_1CE4_E5B9);
        x ^= x >> 29;
        amp * (2.0 * (x >> 11) as f64 / (1u64 << 53) as f64 - 1.0)
    }
}

fn options() -> TakeOptions {
    TakeOptions {
        smooth: Some(SmoothSpec::None),
        ..TakeOptions::default()
    }
}

fn load(b: Bvh, opts: &TakeOptions) -> Take {
    pipeline::take_from_bvh(Path::new("six.bvh"), b, opts).unwrap()
}

fn torques(t: &Take) -> Vec<Vec<f64>> {
    pipeline::inverse_dynamics(&t.model, &t.states).tau
}

fn largest_difference(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .flat_map(|(x, y)| x.iter().zip(y).map(|(p, q)| (p - q).abs()))
        .fold(0.0, f64::max)
}

#[test]
fn restated_offsets_weld_to_the_rotations_only_model_bit_for_bit() {
    let b = plain();
    for joints in ["euler", "ball"] {
        let mut opts = options();
        opts.joints = joints.parse().unwrap();
        let reference = load(b.clone(), &opts);
        let mut feet = opts.clone();
        feet.contact = Contact::Feet;
        let reference_feet = pipeline::estimate_take_ground_reactions(&load(b.clone(), &feet))
            .unwrap()
            .tau;
        for how in [Restate::Replace, Restate::Add] {
            let six = six_channels(&b, how, |_, _, _| 0.0);
            let t = load(six.clone(), &opts);
            // 6 root coordinates and 3 rotations for each of the 20 other joints
            assert_eq!(t.model.nv, 6 + 3 * 20, "{joints}");
            assert_eq!(t.model.q_names, reference.model.q_names, "{joints}");
            assert_eq!(torques(&t), torques(&reference), "{joints}");
            let grf = pipeline::estimate_take_ground_reactions(&load(six, &feet)).unwrap();
            assert_eq!(grf.tau, reference_feet, "{joints}: torques with the feet");
            let note = t.notes.iter().find(|n| n.contains("welded at their mean"));
            let note = note.unwrap_or_else(|| panic!("{:?}", t.notes));
            assert!(note.contains("20 non-root joints"), "{note}");
            assert!(note.contains("each constant over the take"), "{note}");
        }
    }
}

#[test]
fn capture_noise_is_welded_at_its_mean_and_reported() {
    let b = plain();
    let amp = 0.3; // cm
    let six = six_channels(&b, Restate::Replace, noise(amp));
    let t = load(six, &options());
    assert_eq!(t.model.nq, 6 + 3 * 20);
    assert!(
        t.model
            .q_names
            .iter()
            .all(|n| !n.contains("position") || n.starts_with("Hips."))
    );

    // the injected noise's mean and largest distance from it, joint by joint
    let n = b.frames as f64;
    let mut largest = (0.0, 0);
    assert_eq!(t.welded.len(), 20);
    for w in &t.welded {
        let mean = Vector3::from_fn(|a, _| {
            (0..b.frames)
                .map(|k| noise(amp)(w.joint, k, a))
                .sum::<f64>()
                / n
        });
        let want = b.joints[w.joint].offset + mean;
        assert!(
            (w.values - want).norm() < 1e-12,
            "{}",
            b.joints[w.joint].name
        );
        let spread = (0..b.frames)
            .map(|k| (Vector3::from_fn(|a, _| noise(amp)(w.joint, k, a)) - mean).norm())
            .fold(0.0, f64::max);
        assert!((w.variation_m - 0.01 * spread).abs() < 1e-12);
        if spread > largest.0 {
            largest = (spread, w.joint);
        }
    }
    let note = t
        .notes
        .iter()
        .find(|n| n.contains("welded at their mean"))
        .unwrap();
    let want = format!(
        "largest variation {:.1} cm, `{}`",
        largest.0, b.joints[largest.1].name
    );
    assert!(note.contains(&want), "{note} lacks {want}");
    assert!(!note.contains("on purpose"), "{note}");

    // each joint sits by its noise's mean from its OFFSET (a fraction of a mm), so a joint
    // moves by at most the sum of those down its chain from the hips; a torque changes by at
    // most the whole body's weight and inertial load times that
    let reference = load(b.clone(), &options());
    let moved = |j: usize| {
        t.welded
            .iter()
            .find(|w| w.joint == j)
            .map_or(0.0, |w| 0.01 * (w.values - b.joints[j].offset).norm())
    };
    let chain = |mut j: usize| {
        let mut d = 0.0;
        while let Some(p) = b.joints[j].parent {
            d += moved(j);
            j = p;
        }
        d
    };
    let displacement = (0..b.joints.len()).map(chain).fold(0.0, f64::max);
    assert!(displacement < 2e-3, "{displacement} m");
    let load_n = 75.0 * (9.81 + 30.0); // the walk's accelerations stay under 30 m/s²
    let diff = largest_difference(&torques(&t), &torques(&reference));
    println!("torques moved by {diff} N·m; the joints by {displacement} m at most");
    assert!(
        diff < load_n * displacement,
        "{diff} N·m against {}",
        load_n * displacement
    );
    assert!(diff > 0.0);
}

#[test]
fn keep_makes_a_prismatic_coordinate_of_every_channel() {
    let six = six_channels(&plain(), Restate::Replace, noise(0.3));
    let mut opts = options();
    opts.joint_translations = JointTranslations::Keep;
    let t = load(six.clone(), &opts);
    assert_eq!(t.model.nq, 6 * 21);
    assert!(t.model.q_names.iter().any(|n| n == "LeftLeg.Yposition"));
    assert!(t.welded.is_empty());
    assert!(!t.notes.iter().any(|n| n.contains("welded at their mean")));
    opts.joints = "ball".parse().unwrap();
    let t = load(six, &opts);
    // free joints everywhere: 6 velocity coordinates each
    assert_eq!(t.model.nv, 6 * 21);
}

#[test]
fn outputs_of_a_welded_take_agree_with_its_model() {
    let dir = tempfile::tempdir().unwrap();
    let b = plain();
    let six = six_channels(&b, Restate::Replace, noise(0.3));
    let file = dir.path().join("six.bvh");
    bvh::write(&six, &file).unwrap();
    let t = pipeline::load_take(&file, &options()).unwrap();

    // world positions: the model's forward kinematics, welded joints at their mean
    let out = dir.path().join("p.csv");
    pipeline::export_positions(&t, &out).unwrap();
    let (_, cols) = articula::report::csv::read_columns(&out).unwrap();
    let mut ws = Workspace::new(&t.model);
    for k in [0, 37, b.frames - 1] {
        forward_kinematics(&t.model, &mut ws, &t.states.q[k]);
        for (j, m) in t.map.joints.iter().enumerate() {
            let p = ws.o_x_i[m.body].compose(&m.frame).trans;
            for a in 0..3 {
                let x = cols[1 + 3 * j + a][k];
                assert!(
                    (x - p[a]).abs() < 1e-9,
                    "frame {k} {}: {x} vs {}",
                    b.joints[j].name,
                    p[a]
                );
            }
        }
    }

    // a BVH written from it, portable (docs/animation-tools.md): the welded joints' channels
    // folded into their OFFSET at their held (mean) translation, the root's OFFSET zero and its
    // channels its translation, every other channel of the file as it was
    let written = dir.path().join("w.bvh");
    pipeline::export_smoothed_bvh(&t, &written).unwrap();
    let w = bvh::read(&written).unwrap();
    let adds = |j: usize| t.positions[j] == bvh::ResolvedPosition::Add;
    for wj in &t.welded {
        let joint = &w.joints[wj.joint];
        let held = if adds(wj.joint) {
            six.joints[wj.joint].offset + wj.values
        } else {
            wj.values
        };
        assert!(!joint.has_position(), "{}", joint.name);
        assert!(
            (joint.offset - held).norm() < 1e-9,
            "{}: {}",
            joint.name,
            joint.offset
        );
    }
    assert_eq!(w.joints[0].offset, nalgebra::Vector3::zeros());
    for (j, (jw, js)) in w.joints.iter().zip(&six.joints).enumerate() {
        for (n, c) in jw.channels.iter().enumerate() {
            let m = js
                .channels
                .iter()
                .position(|d| d == c)
                .expect("a channel of the file");
            let shift = if j == 0 && !c.is_rotation() && adds(0) {
                js.offset[c.axis()]
            } else {
                0.0
            };
            for k in 0..w.frames {
                let x = w.frame(k)[jw.first_channel + n];
                let y = six.frame(k)[js.first_channel + m] + shift;
                assert!((x - y).abs() < 1e-9, "{} {}: {x} vs {y}", jw.name, c.name());
            }
        }
    }
    // the same body: the model's geometry (stature, landmarks, bones) is the skeleton as held,
    // which is what the written file's OFFSETs say (`motion::weld::held_shape`), so the same
    // torques read back; the file was written with shortest round-trip numbers, so nothing
    // was rounded: equal to 1e-9 of the peak (the sums' own rounding)
    let again = pipeline::load_take(&written, &options()).unwrap();
    let t = pipeline::load_take(&file, &options()).unwrap();
    assert_eq!(again.stature_m, t.stature_m);
    let (a, b) = (torques(&again), torques(&t));
    let peak = b.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
    let gap = largest_difference(&a, &b);
    assert!(gap < 1e-9 * peak, "torques differ by {gap} (peak {peak})");
    assert!(again.welded.iter().all(|w| w.variation_m == 0.0));
}

#[test]
fn locks_and_subtrees_apply_to_a_welded_take() {
    let six = six_channels(&plain(), Restate::Replace, noise(0.3));
    let mut opts = options();
    opts.lock = vec!["LeftArm".into()];
    let t = load(six.clone(), &opts);
    assert_eq!(t.model.nv, 6 + 3 * 19);
    // a welded channel has no coordinate left to lock: it holds still already
    opts.lock = vec!["LeftLeg.Yposition".into(), "LeftLeg.Xrotation".into()];
    assert_eq!(load(six.clone(), &opts).model.nv, 6 + 3 * 20 - 1);
    opts.lock = vec!["LeftLeg.Wposition".into()];
    assert!(pipeline::take_from_bvh(Path::new("six.bvh"), six.clone(), &opts).is_err());
    opts.lock.clear();
    opts.subtree = Some("RightUpLeg".into());
    let t = load(six, &opts);
    // root (6) + right leg: hip, knee, ankle, toes (4 × 3)
    assert_eq!(t.model.nv, 6 + 12);
    assert!(torques(&t).iter().flatten().all(|x| x.is_finite()));
}

#[test]
fn a_translation_animated_on_purpose_is_welded_but_said_so() {
    let b = plain();
    let knee = b.joint_index("LeftLeg").unwrap();
    // the shin grows and shrinks by ±8 cm, a cartoon's squash and stretch
    let six = six_channels(&b, Restate::Replace, |j, k, a| {
        if j == knee && a == 1 {
            8.0 * (0.2 * k as f64).sin()
        } else {
            0.0
        }
    });
    let t = load(six, &options());
    assert_eq!(t.model.nq, 6 + 3 * 20);
    let note = t
        .notes
        .iter()
        .find(|n| n.contains("welded at their mean"))
        .unwrap();
    assert!(note.contains("capture error moves"), "{note}");
    assert!(note.contains("`LeftLeg` 8."), "{note}");
    assert!(note.contains("animates it on purpose"), "{note}");
    assert!(note.contains("--joint-translations keep"), "{note}");
}

#[test]
fn the_flag_the_scene_and_the_session_choose_the_same() {
    use assert_cmd::Command;
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("six.bvh");
    bvh::write(&six_channels(&plain(), Restate::Replace, noise(0.3)), &file).unwrap();
    let nq = |args: &[&str]| -> u64 {
        let out = Command::cargo_bin("articula")
            .unwrap()
            .arg("info")
            .arg(&file)
            .args(args)
            .arg("--json")
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        v["nq"].as_u64().unwrap()
    };
    assert_eq!(nq(&[]), 66);
    assert_eq!(nq(&["--joint-translations", "weld"]), 66);
    assert_eq!(nq(&["--joint-translations", "keep"]), 126);
    let scene = dir.path().join("s.toml");
    std::fs::write(
        &scene,
        "takes = [\"six.bvh\"]\njoint_translations = \"keep\"\n",
    )
    .unwrap();
    assert_eq!(nq(&["--scene", scene.to_str().unwrap()]), 126);
    assert_eq!(
        nq(&[
            "--scene",
            scene.to_str().unwrap(),
            "--joint-translations",
            "weld"
        ]),
        66
    );

    // a bad value, and a robot, are refused
    Command::cargo_bin("articula")
        .unwrap()
        .args([
            "info",
            file.to_str().unwrap(),
            "--joint-translations",
            "stretch",
        ])
        .assert()
        .failure()
        .stderr(predicates::str::contains("expected weld or keep"));
    Command::cargo_bin("articula")
        .unwrap()
        .args(["bench", "--urdf"])
        .arg(common::repo("data/arm7.urdf"))
        .args(["--joint-translations", "keep"])
        .assert()
        .failure()
        .stderr(predicates::str::contains(
            "--joint-translations has no effect on a robot",
        ));

    // the session's `set joint_translations`
    let mut wb = articula::session::Workbench::new(
        std::sync::Arc::new(articula::session::Builtin),
        dir.path(),
        dir.path(),
    );
    for line in [
        "set joint_translations keep",
        "load six.bvh",
        "expect nq 126",
        "set joint_translations weld",
        "expect nq 66",
    ] {
        let cmd = articula::session::parse_line(line, 1).unwrap().unwrap();
        wb.apply(&cmd).unwrap_or_else(|e| panic!("{line}: {e}"));
    }
    let cmd = articula::session::parse_line("set joint_translations stretch", 1)
        .unwrap()
        .unwrap();
    assert!(wb.apply(&cmd).is_err());
}

/// Bandai-Namco's takes write on every joint the OFFSET again, in every frame: welded, the
/// 22-joint rig (its helper root folded into `Hips`) has 6 + 3 · 20 coordinates, not 126, and
/// the only position coordinates are the hips'.
#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn bandai_takes_have_no_coordinates_along_their_bones() {
    for name in [
        "dataset-1_walk_normal_001.bvh",
        "dataset-1_run_normal_001.bvh",
        "dataset-1_kick_normal_001.bvh",
        "dataset-1_bye_old_001.bvh",
    ] {
        let path = common::real_take(name);
        let t = pipeline::load_take(&path, &TakeOptions::default()).unwrap();
        assert_eq!(t.bvh.joints.len(), 22, "{name}");
        assert_eq!(t.model.nq, 6 + 3 * 20, "{name}");
        let positions: Vec<&String> = t
            .model
            .q_names
            .iter()
            .filter(|n| n.contains("position"))
            .collect();
        assert_eq!(
            positions,
            ["Hips.Xposition", "Hips.Yposition", "Hips.Zposition"],
            "{name}"
        );
        let largest = t.welded.iter().map(|w| w.variation_m).fold(0.0, f64::max);
        println!("{name}: nq {}, largest variation {largest:e} m", t.model.nq);
        assert!(largest < 1e-8, "{name}: {largest} m");
        assert!(
            t.notes.iter().any(|n| n.contains("20 non-root joints")),
            "{name}: {:?}",
            t.notes
        );
        let keep = TakeOptions {
            joint_translations: JointTranslations::Keep,
            ..TakeOptions::default()
        };
        assert_eq!(
            pipeline::load_take(&path, &keep).unwrap().model.nq,
            126,
            "{name}"
        );
    }
}
