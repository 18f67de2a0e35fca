//! The settings' table is the one source of every `set` key: the parser accepts each row's
//! name (a pattern row with any joint), `set KEY` alone quotes the row's help, and what a row
//! says a change recomputes is what the workbench does — a view, report or simulation setting
//! leaves inverse dynamics fresh, any other makes it stale.

mod common;

use articula::session::settings::{Recompute, SETTINGS, find};
use articula::session::{Command, parse_line};
use common::workbench::{ok, wb_in};

/// A value of each row that differs from the default, on the demo walk.
fn sample(name: &str) -> &'static str {
    match name {
        "body.mass" => "80",
        "body.sex" => "female",
        "body.segments" => "fractions",
        "unit" => "cm",
        "stature" => "1.7",
        "up" => "z",
        "positions" => "add",
        "subtree" => "LeftUpLeg",
        "joints" => "ball",
        "smooth" => "gaussian:0.02",
        "contact" => "none",
        "consistent" => "off",
        "edges" => "include",
        "overlay" => "mirror",
        "keep_first_frame" => "true",
        "joint_translations" => "keep",
        "bvh_style" => "as-read",
        "kp" | "kp.<joint>" => "500",
        "kv" | "kv.<joint>" => "50",
        "integrator" => "euler",
        "dt" => "0.002",
        "link.<name>.mass" => "4",
        "lock" => "LeftHand",
        "blend.window" => "1",
        "motor.catalogue" => "auto",
        "motor.efficiency" | "motor.<joint>.efficiency" => "0.9",
        _ => "50",
    }
}

/// A row's key on the demo walk (a pattern's `<…>` a joint or coordinate of it).
fn key(name: &str) -> String {
    let row = find(name)
        .map(|(r, _)| r)
        .unwrap_or_else(|| SETTINGS.iter().find(|r| r.name == name).expect("a row"));
    let subject = if name.starts_with("motor.") {
        "LeftLeg.Xrotation"
    } else {
        "LeftLeg"
    };
    row.key_for(subject)
}

#[test]
fn every_row_parses_and_set_alone_quotes_its_help() {
    for row in SETTINGS {
        let k = key(row.name);
        let line = format!("set {k} {}", sample(row.name));
        match parse_line(&line, 1) {
            Ok(Some(Command::Set { key, .. })) => assert_eq!(key, k),
            other => panic!("{line}: {other:?}"),
        }
        let e = parse_line(&format!("set {k}"), 1).unwrap_err().to_string();
        assert!(
            e.contains("usage: set KEY VALUE") && e.contains(row.help),
            "{e}"
        );
    }
}

#[test]
fn what_a_row_says_it_recomputes_is_what_goes_stale() {
    let dir = tempfile::tempdir().unwrap();
    for row in SETTINGS {
        let mut wb = wb_in(dir.path());
        ok(&mut wb, "load demo:walk");
        ok(&mut wb, "run id");
        let line = format!("set {} {}", key(row.name), sample(row.name));
        ok(&mut wb, &line);
        let fresh = wb.fresh_results().is_some();
        let keeps = matches!(row.recompute, Recompute::Nothing | Recompute::Simulation);
        assert_eq!(fresh, keeps, "{line}: {:?}", row.recompute);
    }
}
