//! parse → write → parse is lossless: the same skeleton, channels, frame time and every value
//! bit for bit (the writer prints shortest round-tripping numbers). Checked on random
//! skeletons and takes (property test), on the layout Blender and three.js expect, and on
//! every real take when `ARTICULA_REAL_TAKES` is set.

mod common;

use articula::io::bvh::{self, Bvh, BvhJoint, Channel};
use nalgebra::Vector3;
use proptest::prelude::*;
use std::path::Path;

const ALL: [Channel; 6] = [
    Channel::Xposition,
    Channel::Yposition,
    Channel::Zposition,
    Channel::Xrotation,
    Channel::Yrotation,
    Channel::Zrotation,
];

/// Bit-exact equality (so that -0.0 ≠ 0.0 counts).
fn same_bits(a: &Bvh, b: &Bvh) {
    assert_eq!(a.joints.len(), b.joints.len());
    for (x, y) in a.joints.iter().zip(&b.joints) {
        assert_eq!(x.name, y.name);
        assert_eq!(x.parent, y.parent);
        assert_eq!(x.channels, y.channels);
        assert_eq!(x.first_channel, y.first_channel);
        for n in 0..3 {
            assert_eq!(x.offset[n].to_bits(), y.offset[n].to_bits(), "{}", x.name);
        }
        assert_eq!(x.end_sites.len(), y.end_sites.len());
        for (s, t) in x.end_sites.iter().zip(&y.end_sites) {
            for n in 0..3 {
                assert_eq!(s[n].to_bits(), t[n].to_bits());
            }
        }
    }
    assert_eq!(a.frames, b.frames);
    assert_eq!(a.channel_count, b.channel_count);
    assert_eq!(a.frame_time.to_bits(), b.frame_time.to_bits());
    assert_eq!(a.motion.len(), b.motion.len());
    for (n, (u, v)) in a.motion.iter().zip(&b.motion).enumerate() {
        assert_eq!(u.to_bits(), v.to_bits(), "value {n}: {u} vs {v}");
    }
}

fn value() -> impl Strategy<Value = f64> {
    prop_oneof![
        -1000.0..1000.0f64,
        any::<f64>().prop_filter("finite", |v| v.is_finite()),
        Just(-0.0),
        Just(0.0),
        (-1e-300..1e-300f64),
    ]
}

/// A random tree: parent of joint i is any earlier joint; random channel subsets and orders.
fn random_bvh() -> impl Strategy<Value = Bvh> {
    (1usize..12, 1usize..5).prop_flat_map(|(n, frames)| {
        let parents = proptest::collection::vec(any::<proptest::sample::Index>(), n);
        let channels = proptest::collection::vec(
            proptest::sample::subsequence(ALL.to_vec(), 0..=6).prop_shuffle(),
            n,
        );
        let offsets = proptest::collection::vec(proptest::array::uniform3(value()), n);
        let sites = proptest::collection::vec(
            proptest::collection::vec(proptest::array::uniform3(value()), 0..3),
            n,
        );
        (
            parents,
            channels,
            offsets,
            sites,
            Just(frames),
            1e-4..1.0f64,
        )
            .prop_flat_map(|(parents, channels, offsets, sites, frames, frame_time)| {
                let mut joints = Vec::new();
                let mut first = 0;
                // a file needs a channel somewhere (frames of nothing are refused)
                let mut channels = channels;
                if channels.iter().all(|c| c.is_empty()) {
                    channels[0].push(ALL[0]);
                }
                for i in 0..parents.len() {
                    joints.push(BvhJoint {
                        name: format!("j{i}:a.b_{i}"),
                        parent: if i == 0 {
                            None
                        } else {
                            Some(parents[i].index(i))
                        },
                        offset: Vector3::from(offsets[i]),
                        channels: channels[i].clone(),
                        first_channel: first,
                        end_sites: sites[i].iter().map(|s| Vector3::from(*s)).collect(),
                        line: 0,
                    });
                    first += channels[i].len();
                }
                // file order is depth-first: renumber the random tree in pre-order
                let joints = preorder(joints);
                let count = first;
                proptest::collection::vec(value(), frames * count).prop_map(move |motion| Bvh {
                    joints: joints.clone(),
                    frame_time,
                    frames,
                    channel_count: count,
                    motion,
                    first_frame: 0,
                    decimals: Vec::new(),
                })
            })
    })
}

/// The joints renumbered depth-first (children in index order), first channels recomputed.
fn preorder(joints: Vec<BvhJoint>) -> Vec<BvhJoint> {
    let n = joints.len();
    let mut order = Vec::with_capacity(n);
    let mut stack = vec![0usize];
    while let Some(j) = stack.pop() {
        order.push(j);
        let kids: Vec<usize> = (0..n).filter(|&k| joints[k].parent == Some(j)).collect();
        stack.extend(kids.into_iter().rev());
    }
    let mut new_index = vec![0; n];
    for (new, &old) in order.iter().enumerate() {
        new_index[old] = new;
    }
    let mut first = 0;
    order
        .iter()
        .map(|&old| {
            let mut j = joints[old].clone();
            j.parent = j.parent.map(|p| new_index[p]);
            j.first_channel = first;
            first += j.channels.len();
            j
        })
        .collect()
}

/// parse(write(b)).
fn reparse(b: &Bvh) -> Bvh {
    let text = bvh::write_string(b);
    bvh::parse_str(&text, Path::new("written.bvh")).unwrap_or_else(|e| panic!("{e}\n{text}"))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 200, ..ProptestConfig::default() })]

    #[test]
    fn random_takes_round_trip_exactly(b in random_bvh()) {
        let back = reparse(&b);
        same_bits(&b, &back);
        let again = bvh::write_string(&back);
        prop_assert_eq!(again, bvh::write_string(&b));
    }
}

#[test]
fn layout_is_the_one_blender_and_threejs_read() {
    let text = "HIERARCHY\nROOT Hips\n{\n  OFFSET 0 0 0\n  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n  JOINT Spine\n  {\n    OFFSET 0 10.5 -0\n    CHANNELS 3 Zrotation Xrotation Yrotation\n    End Site\n    {\n      OFFSET 0 5 0\n    }\n  }\n}\nMOTION\nFrames:\t1\nFrame Time: .008333\n1 2 3 4 5 6 7 8 1.87007e-05\n";
    let b = bvh::parse_str(text, Path::new("a.bvh")).unwrap();
    let out = bvh::write_string(&b);
    let expected = "HIERARCHY\nROOT Hips\n{\n\tOFFSET 0 0 0\n\tCHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n\tJOINT Spine\n\t{\n\t\tOFFSET 0 10.5 -0\n\t\tCHANNELS 3 Zrotation Xrotation Yrotation\n\t\tEnd Site\n\t\t{\n\t\t\tOFFSET 0 5 0\n\t\t}\n\t}\n}\nMOTION\nFrames: 1\nFrame Time: 0.008333\n1 2 3 4 5 6 7 8 0.0000187007\n";
    assert_eq!(out, expected);
}

#[test]
fn write_to_a_file_and_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("out.bvh");
    let b = bvh::parse_str(
        "HIERARCHY\nROOT a\n{\nOFFSET 1 2 3\nCHANNELS 3 Xrotation Yrotation Zrotation\n}\nMOTION\nFrames: 1\nFrame Time: 0.5\n1 2 3\n",
        Path::new("a.bvh"),
    )
    .unwrap();
    bvh::write(&b, &path).unwrap();
    same_bits(&b, &bvh::read(&path).unwrap());
}

#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn real_takes_round_trip_exactly() {
    let takes = common::real_takes();
    for path in takes {
        let b = bvh::read(&path).unwrap();
        let back = reparse(&b);
        same_bits(&b, &back);
    }
}

/// A description built in a parent-before-child order that is not depth-first is written
/// depth-first with its frame values moved along: read back, every joint (found by name)
/// has the same OFFSET, channels and values.
#[test]
fn non_depth_first_order_is_written_consistently() {
    let joint = |name: &str, parent: Option<usize>, y: f64, first: usize| BvhJoint {
        name: name.into(),
        parent,
        offset: Vector3::new(0.0, y, 0.0),
        channels: vec![Channel::Zrotation, Channel::Xrotation, Channel::Yrotation],
        first_channel: first,
        end_sites: vec![],
        line: 0,
    };
    // root, then two children of the root, then a child of the first: a, b, a1 is not
    // depth-first (depth-first is root, a, a1, b)
    let b = Bvh {
        joints: vec![
            joint("root", None, 0.0, 0),
            joint("a", Some(0), 1.0, 3),
            joint("b", Some(0), 2.0, 6),
            joint("a1", Some(1), 3.0, 9),
        ],
        frame_time: 0.01,
        frames: 1,
        channel_count: 12,
        motion: (0..12).map(f64::from).collect(),
        first_frame: 0,
        decimals: Vec::new(),
    };
    let back = reparse(&b);
    let names: Vec<&str> = back.joints.iter().map(|j| j.name.as_str()).collect();
    assert_eq!(names, ["root", "a", "a1", "b"]);
    for j in &b.joints {
        let k = back.joint_index(&j.name).unwrap();
        let jb = &back.joints[k];
        assert_eq!(jb.offset, j.offset);
        assert_eq!(
            back.parent_name(k),
            j.parent.map(|p| b.joints[p].name.as_str())
        );
        let vals = &b.motion[j.first_channel..j.first_channel + 3];
        let back_vals = &back.motion[jb.first_channel..jb.first_channel + 3];
        assert_eq!(vals, back_vals, "{}", j.name);
    }
}

trait ParentName {
    fn parent_name(&self, j: usize) -> Option<&str>;
}

impl ParentName for Bvh {
    fn parent_name(&self, j: usize) -> Option<&str> {
        self.joints[j].parent.map(|p| self.joints[p].name.as_str())
    }
}
