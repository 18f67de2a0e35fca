//! Issue 14 item 5: the moments are read with the take's consistency. Every chart of joint
//! moments a session or the command line writes (the selection's angle and torque, `report
//! gait`, `articula anatomy --gait`) carries in its caption the residual figures against Hicks
//! et al.'s thresholds — peak residual force as % of the peak external force, RMS residual
//! moment as % of COM height × peak external force, the verdict, and the figures before
//! reduction —, `compare weights` in its table per mass, and the sidecar of every CSV of
//! moments computed with ground contact (`anatomy`, `id`, a session's `export csv` and `export
//! id`) holds them as `anatomy --json` prints them. Without contact, neither. The figures are
//! the pipeline's for the take; the workbench's row under the curves shows the same
//! (tests/tui_real_rigs.rs).

mod common;

use articula::pipeline::{self, consistency};
use common::workbench::{ok, wb_in};
use std::path::Path;

/// The texts of an SVG's `<text>` elements, trimmed.
fn svg_texts(path: &Path) -> Vec<String> {
    let svg = std::fs::read_to_string(path).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| n.text().unwrap_or("").trim().to_string())
        .collect()
}

/// The caption parts (`key value`) of `c`, each whole in one line of the chart's caption.
fn assert_caption_carries(path: &Path, c: &consistency::Consistency) {
    let texts = svg_texts(path);
    for (k, v) in c.caption_parts() {
        let part = format!("{k} {v}");
        assert!(
            texts.iter().any(|t| t.contains(&part)),
            "{}: {part:?} not in the caption {texts:#?}",
            path.display()
        );
    }
}

/// `sidecar`'s `consistency` holds the figures of `c`.
fn assert_sidecar_carries(csv: &Path, c: &consistency::Consistency) {
    let mut name = csv.as_os_str().to_owned();
    name.push(".json");
    let side: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&name).unwrap()).unwrap();
    let got = &side["consistency"];
    let close = |v: &serde_json::Value, x: f64| {
        let v = v.as_f64().unwrap_or(f64::NAN);
        (v - x).abs() <= 1e-12 * x.abs().max(1.0)
    };
    let after = c.after.as_ref().expect("reduced");
    assert!(
        close(&got["after"]["rms_residual_moment_pct"], after.moment_pct())
            && close(&got["after"]["peak_residual_force_pct"], after.force_pct())
            && close(
                &got["before"]["rms_residual_moment_pct"],
                c.before.moment_pct()
            )
            && got["meets"] == after.meets()
            && got["thresholds"]["peak_force_pct"] == 5.0
            && got["thresholds"]["rms_moment_pct"] == 1.0,
        "{}: {got}",
        csv.display()
    );
}

#[test]
fn a_sessions_charts_and_tables_of_moments_carry_the_takes_residual_figures() {
    let out = tempfile::tempdir().unwrap();
    let mut wb = wb_in(out.path());
    ok(&mut wb, "load data/demo_walk.bvh as walk");
    ok(&mut wb, "set contact feet");
    ok(&mut wb, "run id");
    ok(&mut wb, "select knee_l:flexion");
    for line in [
        "export svg sel.svg",
        "export csv sel.csv",
        "export id id.csv",
        "report gait gait.svg",
    ] {
        ok(&mut wb, line);
    }
    let mass = wb.params.take.body.mass_kg;
    ok(
        &mut wb,
        &format!("compare weights {mass},{} cmp.svg", mass + 20.0),
    );
    // what the pipeline computes for the take under the workbench's settings
    let take = pipeline::load_take(&common::repo("data/demo_walk.bvh"), &wb.params.take).unwrap();
    let (_, _, c) = consistency::consistent_take(&take, true, None).unwrap();
    let shown = wb.latest_results().unwrap().consistency.clone().unwrap();
    assert_eq!(shown.caption_parts(), c.caption_parts());
    assert_caption_carries(&out.path().join("sel.svg"), &c);
    assert_sidecar_carries(&out.path().join("sel.csv"), &c);
    assert_sidecar_carries(&out.path().join("id.csv"), &c);
    // the comparison's table: each mass's figures, the session's mass's those above (each
    // mass's reduction starts cold, as the first run's did)
    let texts = svg_texts(&out.path().join("cmp.svg"));
    let f = c.last();
    for want in [
        "residual force (% ≤ 5)".to_string(),
        "residual moment (% ≤ 1)".into(),
        format!("{:.1}", f.force_pct()),
        format!("{:.2}", f.moment_pct()),
    ] {
        assert!(texts.contains(&want), "{want:?} not in {texts:#?}");
    }
    // the gait view's moments are `anatomy`'s (ball joints by default there, the same take
    // options otherwise): its own consistency, in its caption
    let texts = svg_texts(&out.path().join("gait.svg"));
    assert!(
        texts
            .iter()
            .any(|t| t.contains("residual moment RMS") && t.contains("(≤ 1 %)")),
        "{texts:#?}"
    );

    // without contact: no residual figures anywhere
    ok(&mut wb, "set contact none");
    ok(&mut wb, "run id");
    ok(&mut wb, "export svg none.svg");
    ok(&mut wb, "export csv none.csv");
    let texts = svg_texts(&out.path().join("none.svg"));
    assert!(
        !texts.iter().any(|t| t.contains("residual force peak")),
        "{texts:#?}"
    );
    let side: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.path().join("none.csv.json")).unwrap())
            .unwrap();
    assert!(side["consistency"].is_null(), "{side}");
}

/// `articula anatomy` and `articula id` with contact: the CSV's sidecar holds the
/// consistency `--json` prints, the gait view's caption its figures; `id` without contact
/// writes null.
#[test]
fn the_command_lines_moments_carry_the_consistency_json_prints() {
    let dir = tempfile::tempdir().unwrap();
    let take = common::repo("data/demo_walk.bvh");
    let (csv, gait) = (dir.path().join("a.csv"), dir.path().join("g.svg"));
    let json = common::cli::json_of(
        common::cli::articula()
            .arg("anatomy")
            .arg(&take)
            .args(["--contact", "feet", "--json", "-o"])
            .arg(&csv)
            .arg("--gait")
            .arg(&gait),
    );
    let sidecar = |csv: &Path| -> serde_json::Value {
        let mut name = csv.as_os_str().to_owned();
        name.push(".json");
        serde_json::from_str(&std::fs::read_to_string(name).unwrap()).unwrap()
    };
    assert_eq!(
        sidecar(&csv)["consistency"],
        json,
        "the sidecar is --json's"
    );
    // the caption's figures are those of the JSON
    let pct = |k: &str, d: usize| format!("{:.d$} %", json["after"][k].as_f64().unwrap(), d = d);
    let texts = svg_texts(&gait).join("\n");
    for want in [
        format!(
            "residual force peak {} of peak external force (≤ 5 %)",
            pct("peak_residual_force_pct", 1)
        ),
        format!(
            "residual moment RMS {} of COM height × peak external force (≤ 1 %)",
            pct("rms_residual_moment_pct", 2)
        ),
        "after residual reduction".to_string(),
        format!(
            "before reduction force {:.1} %, moment {:.2} %",
            json["before"]["peak_residual_force_pct"].as_f64().unwrap(),
            json["before"]["rms_residual_moment_pct"].as_f64().unwrap()
        ),
    ] {
        assert!(texts.contains(&want), "{want:?} not in {texts}");
    }

    let id = dir.path().join("i.csv");
    let json = common::cli::json_of(
        common::cli::articula()
            .arg("id")
            .arg(&take)
            .args(["--contact", "feet", "--json", "-o"])
            .arg(&id),
    );
    assert_eq!(sidecar(&id)["consistency"], json["consistency"]);
    assert!(json["consistency"]["before"].is_object());
    // OpenSim's table: its header says the same figures, as metadata (`residuals=`)
    let sto = dir.path().join("i.sto");
    let json = common::cli::json_of(
        common::cli::articula()
            .arg("id")
            .arg(&take)
            .args(["--contact", "feet", "--consistent", "on", "--json", "-o"])
            .arg(&sto),
    );
    let text = std::fs::read_to_string(&sto).unwrap();
    let header = &text[..text.find("endheader").unwrap()];
    let line = header
        .lines()
        .find(|l| l.starts_with("residuals="))
        .unwrap_or_else(|| panic!("no residuals= in {header}"));
    let c = &json["consistency"];
    for want in [
        "residuals after reduction:".to_string(),
        format!(
            "{:.1} %",
            c["after"]["peak_residual_force_pct"].as_f64().unwrap()
        ),
        format!(
            "{:.2} %",
            c["after"]["rms_residual_moment_pct"].as_f64().unwrap()
        ),
        format!(
            "{:.2} %",
            c["before"]["rms_residual_moment_pct"].as_f64().unwrap()
        ),
    ] {
        assert!(line.contains(&want), "{want:?} not in {line}");
    }
    let none = dir.path().join("n.csv");
    common::cli::articula()
        .arg("id")
        .arg(&take)
        .args(["--contact", "none", "-o"])
        .arg(&none)
        .assert()
        .success();
    assert!(sidecar(&none)["consistency"].is_null());
}
