//! `articula export gltf` (issue 16, item 7): a glTF 2.0 binary that a glTF reader (here the
//! `gltf` crate, with validation) opens as the take's skeleton, skinned links and animation.
//!
//! Invariants:
//! - one node per BVH joint plus the mesh node; the skin's joints are the joint nodes, each
//!   inverse bind matrix the inverse of its joint's bind pose; every vertex bound to one joint
//!   with weight 1;
//! - one animation whose samplers have one key per frame of the take, at the file's times;
//! - composing the nodes' animated translations and rotations at any frame gives every joint
//!   where articula puts it — its own forward kinematics of the model at that frame's q, and
//!   the BVH definition's joint centres (`export positions`) — turned to glTF's +Y up by
//!   `TO_Y_UP`, within f32's precision (1e-5 m);
//! - metamorphic: the same walk written lying along +X (X up) gives the same heights.
//!
//! three.js and Blender load the same files in `tools/check_threejs.mjs` and
//! `tools/check_blender.py`.

use articula::dynamics::{Workspace, kinematics::forward_kinematics};
use articula::motion::smooth::SmoothSpec;
use articula::pipeline::{TakeOptions, joint_centres, load_take, to_y_up};
use nalgebra::{Quaternion, UnitQuaternion, Vector3};
use std::path::{Path, PathBuf};

mod common;

use common::cli::articula;

/// The glTF of `take` written by the CLI, parsed and validated.
fn export(take: &Path, out: &Path) -> gltf::Gltf {
    articula()
        .args(["export", "gltf"])
        .arg(take)
        .arg("-o")
        .arg(out)
        .assert()
        .success();
    let bytes = std::fs::read(out).expect("glb");
    assert_eq!(&bytes[..4], b"glTF");
    assert_eq!(
        u32::from_le_bytes(bytes[8..12].try_into().unwrap()) as usize,
        bytes.len()
    );
    gltf::Gltf::from_slice(&bytes).expect("a valid glTF 2.0 binary")
}

/// World position (m, glTF axes) of every node at animation key `k`, by node index.
fn node_positions(g: &gltf::Gltf, k: usize) -> Vec<Vector3<f64>> {
    let doc = &g.document;
    let blob = g.blob.as_deref();
    let n = doc.nodes().len();
    let mut t: Vec<Vector3<f64>> = vec![Vector3::zeros(); n];
    let mut r: Vec<UnitQuaternion<f64>> = vec![UnitQuaternion::identity(); n];
    for node in doc.nodes() {
        let (tr, rot, _) = node.transform().decomposed();
        t[node.index()] = Vector3::from(tr.map(f64::from));
        let [x, y, z, w] = rot.map(f64::from);
        r[node.index()] = UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z));
    }
    let anim = doc.animations().next().expect("an animation");
    for ch in anim.channels() {
        let reader = ch.reader(|_| blob);
        let i = ch.target().node().index();
        match reader.read_outputs().expect("outputs") {
            gltf::animation::util::ReadOutputs::Translations(mut v) => {
                t[i] = Vector3::from(v.nth(k).expect("key").map(f64::from));
            }
            gltf::animation::util::ReadOutputs::Rotations(v) => {
                let [x, y, z, w] = v.into_f32().nth(k).expect("key").map(f64::from);
                r[i] = UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z));
            }
            _ => panic!("only translations and rotations are animated"),
        }
    }
    // compose from the scene's roots down
    let mut world = vec![(Vector3::zeros(), UnitQuaternion::identity()); n];
    let mut stack: Vec<(usize, Vector3<f64>, UnitQuaternion<f64>)> = doc
        .default_scene()
        .expect("a scene")
        .nodes()
        .map(|nd| (nd.index(), Vector3::zeros(), UnitQuaternion::identity()))
        .collect();
    while let Some((i, pp, pr)) = stack.pop() {
        let p = pp + pr * t[i];
        let q = pr * r[i];
        world[i] = (p, q);
        for c in doc.nodes().nth(i).unwrap().children() {
            stack.push((c.index(), p, q));
        }
    }
    world.into_iter().map(|(p, _)| p).collect()
}

fn walk(dir: &Path) -> PathBuf {
    let p = dir.join("walk.bvh");
    articula()
        .args(["generate", "walk", "--fps", "30", "--duration", "1", "-o"])
        .arg(&p)
        .assert()
        .success();
    p
}

#[test]
fn the_glb_holds_the_skeleton_the_skinned_links_and_one_key_per_frame() {
    let dir = tempfile::tempdir().unwrap();
    let take_path = walk(dir.path());
    let g = export(&take_path, &dir.path().join("walk.glb"));
    let take = load_take(&take_path, &TakeOptions::default()).unwrap();
    let joints = take.bvh.joints.len();
    let doc = &g.document;
    assert_eq!(
        doc.nodes().len(),
        joints + 1,
        "a node per joint and the mesh node"
    );
    for (node, joint) in doc.nodes().zip(&take.bvh.joints) {
        assert_eq!(node.name(), Some(joint.name.as_str()));
    }
    let skin = doc.skins().next().expect("a skin");
    assert_eq!(skin.joints().count(), joints);
    // inverse bind matrices undo each joint's bind position
    let blob = g.blob.as_deref();
    let rest = node_rest_world(doc);
    for (m, joint) in skin
        .reader(|_| blob)
        .read_inverse_bind_matrices()
        .unwrap()
        .zip(skin.joints())
    {
        let back = Vector3::new(m[3][0], m[3][1], m[3][2]).map(f64::from);
        assert!((back + rest[joint.index()]).norm() < 1e-5);
    }
    // every vertex moves with one joint
    let prim = doc
        .meshes()
        .next()
        .expect("a mesh")
        .primitives()
        .next()
        .unwrap();
    let reader = prim.reader(|_| blob);
    let vertices = reader.read_positions().unwrap().count();
    assert!(vertices > 0);
    for (j, w) in reader
        .read_joints(0)
        .unwrap()
        .into_u16()
        .zip(reader.read_weights(0).unwrap().into_f32())
    {
        assert!((j[0] as usize) < joints);
        assert_eq!(w, [1.0, 0.0, 0.0, 0.0]);
    }
    assert!(
        reader
            .read_indices()
            .unwrap()
            .into_u32()
            .all(|i| (i as usize) < vertices)
    );
    // the animation: every sampler has one key per frame, at the file's times
    let anim = doc.animations().next().expect("an animation");
    assert!(anim.channels().count() >= joints);
    for s in anim.samplers() {
        let keys = s.input().count();
        assert_eq!(keys, take.bvh.frames);
    }
    let ch = anim.channels().next().unwrap();
    let times: Vec<f32> = ch.reader(|_| blob).read_inputs().unwrap().collect();
    for (k, t) in times.iter().enumerate() {
        assert!((f64::from(*t) - take.bvh.time(k)).abs() < 1e-6);
    }
}

/// World positions of the nodes in the bind pose (no animation).
fn node_rest_world(doc: &gltf::Document) -> Vec<Vector3<f64>> {
    let mut parent = vec![None; doc.nodes().len()];
    for n in doc.nodes() {
        for c in n.children() {
            parent[c.index()] = Some(n.index());
        }
    }
    let local: Vec<Vector3<f64>> = doc
        .nodes()
        .map(|n| Vector3::from(n.transform().decomposed().0.map(f64::from)))
        .collect();
    (0..local.len())
        .map(|mut i| {
            let mut p = local[i];
            while let Some(q) = parent[i] {
                p += local[q];
                i = q;
            }
            p
        })
        .collect()
}

#[test]
fn joint_positions_round_trip_through_the_glb() {
    let dir = tempfile::tempdir().unwrap();
    let take_path = walk(dir.path());
    let g = export(&take_path, &dir.path().join("walk.glb"));
    let opts = TakeOptions {
        smooth: Some(SmoothSpec::None),
        ..TakeOptions::default()
    };
    let take = load_take(&take_path, &opts).unwrap();
    let c = to_y_up(take.up);
    let centres = joint_centres(&take);
    let mut ws = Workspace::new(&take.model);
    let mut worst: f64 = 0.0;
    for k in [0, take.bvh.frames / 2, take.bvh.frames - 1] {
        let got = node_positions(&g, k);
        forward_kinematics(&take.model, &mut ws, &take.states.q[k]);
        for (j, map) in take.map.joints.iter().enumerate() {
            let model = ws.o_x_i[map.body].transform_point(&map.frame.trans);
            let defined = Vector3::from(centres.positions[k][j]);
            worst = worst
                .max((got[j] - c * model).norm())
                .max((got[j] - c * defined).norm());
        }
    }
    assert!(worst < 1e-5, "joint positions off by {worst} m");
}

#[test]
fn a_take_lying_along_x_has_the_same_heights_in_the_glb() {
    let dir = tempfile::tempdir().unwrap();
    let take_path = walk(dir.path());
    let b = articula::io::bvh::read(&take_path).unwrap();
    assert!(common::variants::lying_along_x_applies(&b));
    let lying = dir.path().join("lying.bvh");
    articula::io::bvh::write(&common::variants::lying_along_x(&b), &lying).unwrap();
    let upright = export(&take_path, &dir.path().join("upright.glb"));
    let turned = export(&lying, &dir.path().join("lying.glb"));
    for k in [0, 10, 20] {
        let (a, b) = (node_positions(&upright, k), node_positions(&turned, k));
        for (p, q) in a.iter().zip(&b) {
            assert!(
                (p.y - q.y).abs() < 1e-5,
                "frame {k}: heights {} and {}",
                p.y,
                q.y
            );
        }
    }
}

#[test]
fn the_session_exports_gltf() {
    let dir = tempfile::tempdir().unwrap();
    let mut wb = common::workbench::wb_in(dir.path());
    common::workbench::ok(&mut wb, "load demo:walk");
    let msg = common::workbench::ok(&mut wb, "export gltf walk.glb");
    assert!(msg.contains("walk.glb"), "{msg}");
    let g = gltf::Gltf::from_slice(&std::fs::read(dir.path().join("walk.glb")).unwrap())
        .expect("valid glTF");
    assert!(g.document.animations().count() == 1);
}

#[test]
fn flags_that_cannot_change_the_glb_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let take_path = walk(dir.path());
    articula()
        .args(["export", "gltf"])
        .arg(&take_path)
        .args(["--smooth", "none", "-o"])
        .arg(dir.path().join("x.glb"))
        .assert()
        .failure()
        .stderr(predicates::str::contains("--smooth"));
}

#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn real_takes_round_trip_through_the_glb() {
    let dir = tempfile::tempdir().unwrap();
    for path in common::real_takes() {
        let out = dir.path().join("t.glb");
        let g = export(&path, &out);
        let take = load_take(&path, &TakeOptions::default()).unwrap();
        let c = to_y_up(take.up);
        let centres = joint_centres(&take);
        for k in [0, take.bvh.frames / 2, take.bvh.frames - 1] {
            let got = node_positions(&g, k);
            for (j, p) in centres.positions[k].iter().enumerate() {
                let gap = (got[j] - c * Vector3::from(*p)).norm();
                assert!(
                    gap < 1e-4,
                    "{}: joint {j} frame {k}: {gap} m",
                    path.display()
                );
            }
        }
    }
}
