//! The URDF that `articula export urdf` writes for a take, loaded by Pinocchio 4.1: its RNEA,
//! CRBA and ABA at random states (tests/fixtures/pinocchio/take_*, made by
//! tools/take_urdf_fixtures.sh) agree with articula's own model of the take — built straight
//! from the BVH, not from the URDF — to 1e-10 relative. So the BVH → model step, the URDF
//! writer and the algorithms are all checked against an independent peer at once. The fixtures
//! were exported with de Leva's fixed fractions (`--segments fractions`, as the script says);
//! the segment table is an input of the check, not what it checks.

mod common;

use articula::dynamics::{Workspace, aba, crba, rnea};
use articula::model::Model;
use articula::model::anthropometry::SegmentTable;
use articula::pipeline::{TakeOptions, load_take};
use articula::report::csv::read_columns;
use std::path::Path;

struct Table {
    header: Vec<String>,
    cols: Vec<Vec<f64>>,
}

impl Table {
    fn read(p: &Path) -> Table {
        let (header, cols) = read_columns(p).unwrap_or_else(|e| panic!("{e}"));
        Table { header, cols }
    }
    fn rows(&self) -> usize {
        self.cols[0].len()
    }
    fn row(&self, prefix: &str, names: &[String], k: usize) -> Vec<f64> {
        names
            .iter()
            .map(|n| {
                let want = format!("{prefix}{n}");
                let j = self
                    .header
                    .iter()
                    .position(|h| *h == want)
                    .unwrap_or_else(|| panic!("no column {want}"));
                self.cols[j][k]
            })
            .collect()
    }
}

fn assert_close(what: &str, k: usize, ours: &[f64], pin: &[f64]) {
    let scale = pin.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    for (j, (a, b)) in ours.iter().zip(pin).enumerate() {
        assert!(
            (a - b).abs() <= 1e-10 * scale,
            "{what} row {k} coordinate {j}: articula {a} vs Pinocchio {b} (scale {scale})"
        );
    }
}

fn check(model: &Model, dir: &Path) {
    let states = Table::read(&dir.join("states.csv"));
    let tau_pin = Table::read(&dir.join("rnea.csv"));
    let m_pin = Table::read(&dir.join("crba.csv"));
    let a_pin = Table::read(&dir.join("aba.csv"));
    let mut ws = Workspace::new(model);
    let nv = model.nv;
    // Pinocchio numbers the mass matrix in its own joint order (URDF children sorted by name):
    // the order of the `v:` columns of its states file
    let pin_order: Vec<String> = states
        .header
        .iter()
        .filter_map(|h| h.strip_prefix("v:").map(String::from))
        .collect();
    let pin_index = |name: &String| pin_order.iter().position(|p| p == name).unwrap();
    let mnames: Vec<String> = (0..nv * nv)
        .map(|i| {
            let (r, c) = (&model.v_names[i / nv], &model.v_names[i % nv]);
            format!("{}:{}", pin_index(r), pin_index(c))
        })
        .collect();
    assert!(states.rows() >= 4);
    for k in 0..states.rows() {
        let q = states.row("q:", &model.q_names, k);
        let v = states.row("v:", &model.v_names, k);
        let a = states.row("a:", &model.v_names, k);
        let tau = rnea(model, &mut ws, &q, &v, &a, None).as_slice().to_vec();
        assert_close("rnea", k, &tau, &tau_pin.row("tau:", &model.v_names, k));
        let d = crba(model, &mut ws, &q);
        let ours: Vec<f64> = (0..nv * nv).map(|i| d[(i / nv, i % nv)]).collect();
        assert_close("crba", k, &ours, &m_pin.row("M:", &mnames, k));
        let acc = aba(model, &mut ws, &q, &v, &tau, None)
            .unwrap()
            .as_slice()
            .to_vec();
        let pin_a = a_pin.row("a:", &model.v_names, k);
        // ABA solves D a = τ − h: its rounding error grows with the condition of D (light
        // fingers under massless fictitious links); measured worst 1.2e-10 relative on CMU
        let scale = pin_a.iter().fold(1.0f64, |m, x| m.max(x.abs()));
        for (j, (x, y)) in acc.iter().zip(&pin_a).enumerate() {
            assert!(
                (x - y).abs() <= 1e-9 * scale,
                "aba row {k} coordinate {j}: {x} vs {y}"
            );
        }
    }
}

/// The options the fixtures were exported with: the defaults, de Leva's fractions.
fn fractions() -> TakeOptions {
    let mut o = TakeOptions::default();
    o.body.segments = SegmentTable::Fractions;
    o
}

#[test]
fn demo_walk_model_matches_pinocchio_on_its_exported_urdf() {
    let take = load_take(&common::repo("data/demo_walk.bvh"), &fractions()).unwrap();
    check(
        &take.model,
        &common::repo("tests/fixtures/pinocchio/take_demo_walk"),
    );
    // and the committed URDF read back gives the same model dynamics
    let urdf = articula::model::urdf::read_urdf(
        &common::repo("tests/fixtures/pinocchio/take_demo_walk/model.urdf"),
        &articula::model::urdf::UrdfOptions {
            floating: false,
            gravity: take.model.gravity,
        },
    )
    .unwrap();
    assert_eq!(urdf.nv, take.model.nv);
    check(
        &urdf,
        &common::repo("tests/fixtures/pinocchio/take_demo_walk"),
    );
}

#[test]
#[ignore = "real takes: ARTICULA_REAL_TAKES=../shared/data/bvh cargo test -- --ignored"]
fn real_take_cmu_01_01_matches_pinocchio_on_its_exported_urdf() {
    let path = common::real_take("cmu_01_01.bvh");
    let take = load_take(&path, &fractions()).unwrap();
    assert_eq!(take.model.nv, 96);
    check(
        &take.model,
        &common::repo("tests/fixtures/pinocchio/take_cmu_01_01"),
    );
}
