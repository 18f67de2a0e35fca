//! Portable BVH is the default; `--bvh-style as-read` (on `smooth` and `blend`) and the
//! session's `set bvh_style as-read` (for `export bvh`) write the take with the channel layout
//! it was read with (issue 16): every joint keeps its channels and OFFSET, so a tool that
//! expects the producer's layout (six channels on every joint, as Perception Neuron writes)
//! gets it back. The motion is the same either way: the written files read back to the same
//! joint positions.
//!
//! The take: the demo walk with three position channels on every joint below the root that
//! replace the OFFSET with itself plus up to 0.5 cm.

mod common;

use articula::io::bvh::{self, Bvh, Channel};
use common::cli::articula;
use std::path::{Path, PathBuf};

fn six_channel_demo(dir: &Path) -> PathBuf {
    let b = bvh::read(&common::repo("data/demo_walk.bvh")).unwrap();
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
    out.motion.clear();
    for k in 0..b.frames {
        let row = b.frame(k);
        for (j, joint) in b.joints.iter().enumerate() {
            if j > 0 {
                for a in 0..3 {
                    let noise = 0.5 * (0.3 * k as f64 + (j * 5 + a) as f64).sin();
                    out.motion.push(joint.offset[a] + noise);
                }
            }
            let own = &row[joint.first_channel..joint.first_channel + joint.channels.len()];
            out.motion.extend_from_slice(own);
        }
    }
    out.decimals = vec![6; out.motion.len()];
    let path = dir.join("six.bvh");
    bvh::write(&out, &path).unwrap();
    path
}

/// Every joint's channels and OFFSET, the layout a reader sees.
fn layout(b: &Bvh) -> Vec<(String, Vec<Channel>, [f64; 3])> {
    b.joints
        .iter()
        .map(|j| (j.name.clone(), j.channels.clone(), j.offset.into()))
        .collect()
}

/// `export positions` of `take` (m, every joint), read back.
fn positions(take: &Path, out: &Path) -> Vec<Vec<f64>> {
    articula()
        .args(["export", "positions"])
        .arg(take)
        .arg("-o")
        .arg(out)
        .assert()
        .success();
    articula::report::csv::read_columns(out).unwrap().1
}

fn largest_gap(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    (a.iter().flatten())
        .zip(b.iter().flatten())
        .fold(0.0, |m, (x, y)| m.max((x - y).abs()))
}

#[test]
fn smooth_as_read_keeps_the_channel_layout_and_portable_does_not() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let six = six_channel_demo(d);
    let input = bvh::read(&six).unwrap();
    let write = |style: Option<&str>, name: &str| {
        let out = d.join(name);
        let mut cmd = articula();
        cmd.arg("smooth").arg(&six).args(["--smooth", "none"]);
        if let Some(s) = style {
            cmd.args(["--bvh-style", s]);
        }
        cmd.arg("-o").arg(&out).assert().success();
        out
    };
    let as_read = write(Some("as-read"), "as_read.bvh");
    let portable = write(None, "portable.bvh");
    assert_eq!(
        std::fs::read(&portable).unwrap(),
        std::fs::read(write(Some("portable"), "p2.bvh")).unwrap(),
        "portable is the default"
    );
    let a = bvh::read(&as_read).unwrap();
    assert_eq!(layout(&a), layout(&input));
    assert_eq!(a.frames, input.frames);
    // portable: the welded joints' channels are folded into their OFFSETs
    let p = bvh::read(&portable).unwrap();
    assert!(p.joints[1..].iter().all(|j| !j.has_position()));
    // both are the same motion: the same joint positions (to the printed 6 decimals, cm)
    let reference = positions(&portable, &d.join("p.csv"));
    let gap = largest_gap(&positions(&as_read, &d.join("a.csv")), &reference);
    assert!(gap < 1e-7, "{gap} m");
    // a style that does not exist is refused, naming the ones that do
    articula()
        .arg("smooth")
        .arg(&six)
        .args(["--bvh-style", "blender", "-o"])
        .arg(d.join("x.bvh"))
        .assert()
        .failure()
        .stderr(predicates::str::contains("portable or as-read"));
}

#[test]
fn blend_as_read_keeps_the_first_takes_channel_layout() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let six = six_channel_demo(d);
    let out = d.join("blend.bvh");
    articula()
        .arg("blend")
        .arg(&six)
        .arg(&six)
        .args(["--window", "1:1.5", "--bvh-style", "as-read", "-o"])
        .arg(&out)
        .assert()
        .success();
    let input = bvh::read(&six).unwrap();
    assert_eq!(layout(&bvh::read(&out).unwrap()), layout(&input));
}

#[test]
fn the_session_exports_bvh_as_read_after_set_bvh_style() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let six = six_channel_demo(d);
    let session = d.join("s.session");
    let (a, p) = (d.join("as_read.bvh"), d.join("portable.bvh"));
    std::fs::write(
        &session,
        format!(
            "load {}\nset smooth none\nexport bvh {}\nset bvh_style as-read\nexport bvh {}\n",
            six.display(),
            p.display(),
            a.display()
        ),
    )
    .unwrap();
    articula().arg("run").arg(&session).assert().success();
    let input = bvh::read(&six).unwrap();
    assert_eq!(layout(&bvh::read(&a).unwrap()), layout(&input));
    assert!(
        bvh::read(&p).unwrap().joints[1..]
            .iter()
            .all(|j| !j.has_position())
    );
    // the CLI's as-read and the session's are the same file
    let cli = d.join("cli.bvh");
    articula()
        .arg("smooth")
        .arg(&six)
        .args(["--smooth", "none", "--bvh-style", "as-read", "-o"])
        .arg(&cli)
        .assert()
        .success();
    assert_eq!(std::fs::read(&cli).unwrap(), std::fs::read(&a).unwrap());
    // and a wrong value is a clear error
    std::fs::write(
        &session,
        format!("load {}\nset bvh_style blender\n", six.display()),
    )
    .unwrap();
    articula()
        .arg("run")
        .arg(&session)
        .assert()
        .failure()
        .stderr(predicates::str::contains("bvh_style"));
}
