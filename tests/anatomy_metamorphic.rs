//! Issue 13's metamorphic suite: the same motion written another way — (a) the rest pose
//! lying along +X with conjugated rotations, (b) another rotation order, (c) another length
//! unit, (d) Euler triples on the other branch for a stretch of frames, (e) every joint renamed —
//! gives the same world positions, link masses, anatomical angles and moments (≤ 1e-6
//! relative). Generated from the bundled demo walk here, from every shared take in the real
//! suite (where a variant applies: (a) needs no position channels below the root).

mod common;

use articula::dynamics::{self, Workspace};
use articula::io::bvh::{self, Bvh};
use articula::pipeline::{self, Contact, anatomy::Anatomy};
use common::variants::*;
use nalgebra::Vector3;
use std::path::Path;

struct Seen {
    positions: Vec<Vec<Vector3<f64>>>,
    masses: Vec<f64>,
    anatomy: Anatomy,
}

fn see(b: Bvh, label: &str) -> Seen {
    let mut o = common::anatomy_opts();
    if b.frames < 3 {
        o.contact = Contact::None; // a single pose: no contact phases (`anatomy` does the same)
    }
    let take = pipeline::take_from_bvh(Path::new("variant.bvh"), b, &o)
        .unwrap_or_else(|e| panic!("{label}: {e}"));
    let mut ws = Workspace::new(&take.model);
    let positions = take
        .states
        .q
        .iter()
        .map(|q| {
            dynamics::forward_kinematics(&take.model, &mut ws, q);
            take.map
                .joints
                .iter()
                .map(|jm| ws.o_x_i[jm.body].transform_point(&jm.frame.trans))
                .collect()
        })
        .collect();
    let masses = take
        .map
        .joints
        .iter()
        .map(|jm| take.model.inertia[jm.body].mass)
        .collect();
    let anatomy = pipeline::anatomy::anatomy(&take).unwrap_or_else(|e| panic!("{label}: {e}"));
    Seen {
        positions,
        masses,
        anatomy,
    }
}

fn close(what: &str, a: f64, b: f64, scale: f64, rel: f64) {
    assert!(
        (a - b).abs() <= rel * scale.max(1.0),
        "{what}: {a} vs {b} (scale {scale})"
    );
}

fn assert_same(label: &str, a: &Seen, b: &Seen, rel: f64) {
    assert_eq!(a.positions.len(), b.positions.len(), "{label}: frames");
    for (k, (pa, pb)) in a.positions.iter().zip(&b.positions).enumerate() {
        for (j, (x, y)) in pa.iter().zip(pb).enumerate() {
            assert!(
                (x - y).norm() <= rel * 2.0,
                "{label}: joint {j} at frame {k}: {x} vs {y}"
            );
        }
    }
    let total: f64 = a.masses.iter().sum();
    for (j, (x, y)) in a.masses.iter().zip(&b.masses).enumerate() {
        close(&format!("{label}: mass of joint {j}"), *x, *y, total, rel);
    }
    assert_eq!(a.anatomy.names, b.anatomy.names, "{label}: columns");
    for (name, (ca, cb)) in a
        .anatomy
        .names
        .iter()
        .zip(a.anatomy.columns.iter().zip(&b.anatomy.columns))
    {
        let scale = ca.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        for (k, (x, y)) in ca.iter().zip(cb).enumerate() {
            close(&format!("{label}: {name} at frame {k}"), *x, *y, scale, rel);
        }
    }
}

/// Every variant that applies to `b`, each against the original.
fn check_all_variants(b: &Bvh, label: &str) {
    let original = see(b.clone(), label);
    assert!(
        !original.anatomy.names.is_empty(),
        "{label}: no anatomical columns"
    );
    let n = b.frames;
    let mut variants: Vec<(&str, Bvh)> = vec![
        ("another rotation order", another_rotation_order(b)),
        (
            "other Euler branch",
            other_euler_branch(b, n / 3..2 * n / 3),
        ),
        ("renamed", renamed(b)),
    ];
    if lying_along_x_applies(b) {
        variants.push(("lying along +X", lying_along_x(b)));
    }
    let take =
        pipeline::take_from_bvh(Path::new("x.bvh"), b.clone(), &common::anatomy_opts()).unwrap();
    // in metres (mm if already metres): the unit detection must find the same scale
    let k = if take.scale_to_m == 1.0 {
        1000.0
    } else {
        take.scale_to_m
    };
    variants.push(("another unit", in_another_unit(b, k)));
    eprintln!(
        "{label}: {}",
        variants.iter().map(|v| v.0).collect::<Vec<_>>().join(", ")
    );
    for (name, v) in variants {
        let label = format!("{label}, {name}");
        assert_same(&label, &original, &see(v, &label), 1e-6);
    }
}

#[test]
fn the_demo_walk_written_five_other_ways_gives_the_same_anatomy() {
    let b = bvh::read(&common::repo("data/demo_walk.bvh")).unwrap();
    check_all_variants(&b, "demo walk");
}

#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn every_shared_human_take_written_other_ways_gives_the_same_anatomy() {
    for path in common::real_takes() {
        let (b, _) = pipeline::read_take(&path, false).unwrap();
        let label = path.file_name().unwrap().to_string_lossy().into_owned();
        let take = pipeline::take_from_bvh(&path, b.clone(), &common::anatomy_opts()).unwrap();
        if let Err(why) = &take.human {
            eprintln!("{label}: not a biped ({why})");
            continue;
        }
        check_all_variants(&b, &label);
    }
}
