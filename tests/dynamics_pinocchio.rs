//! articula's dynamics against Pinocchio 4.1 (golden data in `tests/fixtures/pinocchio`, made by
//! `tools/pinocchio_fixtures.py`): on `data/arm7.urdf` (fixed base), `data/humanoid.urdf` (fixed
//! base) and the humanoid with a free-flyer root, at 8 states each, `rnea`, the mass matrix
//! (`crba`), `aba`, the gravity term `c(q)`, `h + c` (`nle`) and the kinetic and potential
//! energies agree to 1e-10 relative (to the largest entry of the row, or 1). Coordinates are
//! matched by name: Pinocchio orders URDF children by name, articula by file order.

mod common;

use articula::dynamics::{
    Workspace, aba, crba, gravity_terms, kinetic_energy, nonlinear_effects, potential_energy, rnea,
};
use articula::model::Model;
use articula::model::urdf::{UrdfOptions, read_urdf};
use std::path::Path;

const RTOL: f64 = 1e-10;

/// A fixture CSV: header and rows.
fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .filter(|l| !l.is_empty())
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

/// One fixture file's columns picked by name.
struct Table {
    header: Vec<String>,
    rows: Vec<Vec<f64>>,
}

impl Table {
    fn read(dir: &Path, file: &str) -> Self {
        let (header, rows) = read_csv(&dir.join(file));
        Self { header, rows }
    }
    fn get(&self, row: usize, name: &str) -> f64 {
        let k = self
            .header
            .iter()
            .position(|h| h == name)
            .unwrap_or_else(|| panic!("no column {name}"));
        self.rows[row][k]
    }
    /// `prefix:<name>` for every name, in that order.
    fn pick(&self, row: usize, prefix: &str, names: &[String]) -> Vec<f64> {
        names
            .iter()
            .map(|n| self.get(row, &format!("{prefix}:{n}")))
            .collect()
    }
}

/// Largest difference relative to the largest reference entry (or 1).
fn rel(got: &[f64], want: &[f64]) -> f64 {
    let scale = want.iter().fold(1.0f64, |m, x| m.max(x.abs()));
    got.iter()
        .zip(want)
        .fold(0.0f64, |m, (g, w)| m.max((g - w).abs()))
        / scale
}

fn check(fixture: &str, floating: bool) {
    let model: Model = read_urdf(
        &common::repo(if fixture == "arm7" {
            "data/arm7.urdf"
        } else {
            "data/humanoid.urdf"
        }),
        &UrdfOptions {
            floating,
            ..Default::default()
        },
    )
    .unwrap();
    let dir = common::repo(&format!("tests/fixtures/pinocchio/{fixture}"));
    let meta: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("model.json")).unwrap()).unwrap();
    // Pinocchio's v order, to read M:<i>:<j>
    let pin_v: Vec<String> = meta["v_names"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_str().unwrap().to_string())
        .collect();
    let pin_index: Vec<usize> = model
        .v_names
        .iter()
        .map(|n| {
            pin_v
                .iter()
                .position(|p| p == n)
                .unwrap_or_else(|| panic!("{n} not in Pinocchio"))
        })
        .collect();
    let states = Table::read(&dir, "states.csv");
    let t_rnea = Table::read(&dir, "rnea.csv");
    let t_crba = Table::read(&dir, "crba.csv");
    let t_aba = Table::read(&dir, "aba.csv");
    let t_grav = Table::read(&dir, "gravity.csv");
    let t_nle = Table::read(&dir, "nle.csv");
    let t_energy = Table::read(&dir, "energy.csv");
    let mut ws = Workspace::new(&model);
    let mut worst = [0.0f64; 7];
    for row in 0..states.rows.len() {
        let q = states.pick(row, "q", &model.q_names);
        let v = states.pick(row, "v", &model.v_names);
        let a = states.pick(row, "a", &model.v_names);
        let tau = states.pick(row, "tau", &model.v_names);

        let got = rnea(&model, &mut ws, &q, &v, &a, None).as_slice().to_vec();
        worst[0] = worst[0].max(rel(&got, &t_rnea.pick(row, "tau", &model.v_names)));

        let d = crba(&model, &mut ws, &q).clone();
        let mut want = vec![];
        let mut mine = vec![];
        for (i, &pi) in pin_index.iter().enumerate() {
            for (j, &pj) in pin_index.iter().enumerate() {
                mine.push(d[(i, j)]);
                want.push(t_crba.get(row, &format!("M:{pi}:{pj}")));
            }
        }
        worst[1] = worst[1].max(rel(&mine, &want));

        let got = aba(&model, &mut ws, &q, &v, &tau, None)
            .unwrap()
            .as_slice()
            .to_vec();
        worst[2] = worst[2].max(rel(&got, &t_aba.pick(row, "a", &model.v_names)));

        let got = gravity_terms(&model, &mut ws, &q).as_slice().to_vec();
        worst[3] = worst[3].max(rel(&got, &t_grav.pick(row, "g", &model.v_names)));

        let got = nonlinear_effects(&model, &mut ws, &q, &v)
            .as_slice()
            .to_vec();
        worst[4] = worst[4].max(rel(&got, &t_nle.pick(row, "nle", &model.v_names)));

        let kin = kinetic_energy(&model, &mut ws, &q, &v);
        worst[5] = worst[5].max(rel(&[kin], &[t_energy.get(row, "kinetic")]));
        let pot = potential_energy(&model, &mut ws, &q);
        worst[6] = worst[6].max(rel(&[pot], &[t_energy.get(row, "potential")]));
    }
    eprintln!(
        "{fixture}: worst relative difference rnea {:.1e}, crba {:.1e}, aba {:.1e}, gravity \
         {:.1e}, nle {:.1e}, kinetic {:.1e}, potential {:.1e}",
        worst[0], worst[1], worst[2], worst[3], worst[4], worst[5], worst[6]
    );
    let names = [
        "rnea",
        "crba",
        "aba",
        "gravity",
        "nle",
        "kinetic",
        "potential",
    ];
    for (w, n) in worst.iter().zip(names) {
        assert!(*w < RTOL, "{fixture}: {n} differs from Pinocchio by {w:e}");
    }
}

#[test]
fn arm7_matches_pinocchio() {
    check("arm7", false);
}

#[test]
fn humanoid_fixed_base_matches_pinocchio() {
    check("humanoid", false);
}

#[test]
fn humanoid_floating_matches_pinocchio() {
    check("humanoid_floating", true);
}
