//! One naming scheme for every CSV, a sidecar beside each, and `--json` everywhere
//! (issue 16 item 4).
//!
//! Invariants: every column of every CSV the binary writes has a kind in
//! `report::columns::KINDS` and a unit (one table-driven test over the commands); the sidecar
//! `NAME.csv.json` parses, lists exactly the header's columns, and gives each the unit the table
//! gives it; each `--json` parses and has its documented keys.

mod common;

use common::cli::{articula, walk};

use articula::report::columns;
use articula::report::csv::read_columns;
use articula::report::sidecar::Sidecar;
use std::path::Path;

/// Runs `args` (`{take}` replaced by the take, `{out}` by `out`), which must succeed; its
/// standard output.
fn run(args: &[&str], take: &Path, out: &Path) -> Vec<u8> {
    let args: Vec<String> = args
        .iter()
        .map(|a| match *a {
            "{take}" => take.display().to_string(),
            "{out}" => out.display().to_string(),
            a => a.to_string(),
        })
        .collect();
    let o = articula().args(&args).output().unwrap();
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    o.stdout
}

/// `NAME.csv.json` beside `NAME.csv` (docs/formats.md).
fn sidecar_path(csv: &Path) -> std::path::PathBuf {
    let mut name = csv.as_os_str().to_owned();
    name.push(".json");
    name.into()
}

fn sidecar_of(csv: &Path) -> Sidecar {
    let text = std::fs::read_to_string(sidecar_path(csv))
        .unwrap_or_else(|e| panic!("{}: no sidecar: {e}", csv.display()));
    serde_json::from_str(&text).unwrap()
}

/// The model the take's coordinates belong to, for the units of `q:`, `tau:` … columns.
fn model(take: &Path) -> articula::model::Model {
    articula::pipeline::load_take(take, &articula::pipeline::TakeOptions::default())
        .unwrap()
        .model
}

#[test]
fn every_csv_header_follows_the_scheme_and_its_sidecar_gives_the_units() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.5);
    let m = model(&take);
    let d = dir.path();
    // the states and torques the robot-free commands read back
    run(
        &["export", "states", "{take}", "-o", "{out}"],
        &take,
        &d.join("s.csv"),
    );
    run(
        &["id", "{take}", "--contact", "none", "-o", "{out}"],
        &take,
        &d.join("t0.csv"),
    );
    // every command that writes a CSV: (its arguments, whether its columns name coordinates)
    let commands: &[(&str, &[&str])] = &[
        ("id.csv", &["id", "{take}", "-o", "{out}"]),
        ("states.csv", &["export", "states", "{take}", "-o", "{out}"]),
        (
            "positions.csv",
            &["export", "positions", "{take}", "-o", "{out}"],
        ),
        ("grf.csv", &["export", "grf", "{take}", "-o", "{out}"]),
        ("anatomy.csv", &["anatomy", "{take}", "-o", "{out}"]),
        (
            "fd.csv",
            &["fd", "{take}", "--torques", "T0", "-o", "{out}"],
        ),
        ("mass.csv", &["mass-matrix", "{take}", "-o", "{out}"]),
        (
            "sim.csv",
            &["simulate", "{take}", "--duration", "0.3", "-o", "{out}"],
        ),
    ];
    let t0 = d.join("t0.csv").display().to_string();
    for (name, args) in commands {
        let out = d.join(name);
        let args: Vec<&str> = args
            .iter()
            .map(|a| if *a == "T0" { t0.as_str() } else { *a })
            .collect();
        run(&args, &take, &out);
        let (header, cols) = read_columns(&out).unwrap();
        assert_eq!(header[0], "time", "{name}");
        assert!(cols[0].len() > 10, "{name}");
        let side = sidecar_of(&out);
        assert_eq!(side.file, *name);
        assert_eq!(side.articula_version, env!("CARGO_PKG_VERSION"));
        assert_eq!(
            side.take.as_deref(),
            Some(take.display().to_string().as_str())
        );
        assert_eq!(side.settings["up"], "y", "{name}");
        let names: Vec<&str> = side.columns.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, header, "{name}: the sidecar lists the header");
        for (c, h) in side.columns.iter().zip(&header) {
            let kind = columns::kind_of(h).unwrap_or_else(|| panic!("{name}: {h} has no kind"));
            assert_eq!(c.quantity, kind.quantity, "{name}: {h}");
            assert_eq!(
                c.unit,
                columns::unit_of(h, Some(&m)).unwrap(),
                "{name}: {h}"
            );
        }
    }
    // units that depend on the coordinate: a rotation's torque in N*m, a translation's in N
    let id = sidecar_of(&d.join("id.csv"));
    let unit = |n: &str| {
        id.columns
            .iter()
            .find(|c| c.name == n)
            .unwrap()
            .unit
            .clone()
    };
    assert_eq!(unit("tau:LeftLeg.Xrotation"), "N*m");
    assert_eq!(unit("tau:Hips.Yposition"), "N");
    assert_eq!(unit("grf:left:y"), "N");
    assert_eq!(unit("residual:tx"), "N*m");
    let sim = sidecar_of(&d.join("sim.csv"));
    let q = sim
        .columns
        .iter()
        .find(|c| c.name == "q:LeftLeg.Xrotation")
        .unwrap();
    assert_eq!(q.unit, "rad");
    let anatomy = read_columns(&d.join("anatomy.csv")).unwrap().0;
    assert!(
        anatomy.iter().any(|h| h == "moment:knee_l:flexion"),
        "{anatomy:?}"
    );
    assert!(
        anatomy.iter().any(|h| h == "angle:knee_r:flexion"),
        "{anatomy:?}"
    );
}

#[test]
fn standard_output_gets_no_sidecar_and_old_bare_torque_names_are_still_read() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.5);
    let d = dir.path();
    let out = run(&["id", "{take}", "--contact", "none", "-o", "-"], &take, d);
    let text = String::from_utf8(out).unwrap();
    assert!(text.starts_with("time,tau:"), "{}", &text[..60]);
    assert!(!d.join("-.json").exists() && !d.join("-.csv.json").exists());
    // torques under the bare names `id` wrote before the scheme give the same accelerations
    let t = d.join("t.csv");
    std::fs::write(&t, &text).unwrap();
    let (h, c) = read_columns(&t).unwrap();
    let bare: Vec<String> = h
        .iter()
        .map(|n| n.trim_start_matches("tau:").to_string())
        .collect();
    let refs: Vec<&[f64]> = c.iter().map(Vec::as_slice).collect();
    let old = d.join("old.csv");
    articula::report::csv::write_columns(&old, &bare, &refs).unwrap();
    let fd = |torques: &Path, out: &str| {
        let o = d.join(out);
        articula()
            .arg("fd")
            .arg(&take)
            .arg("--torques")
            .arg(torques)
            .arg("-o")
            .arg(&o)
            .assert()
            .success();
        read_columns(&o).unwrap()
    };
    assert_eq!(fd(&t, "a_new.csv"), fd(&old, "a_old.csv"));
}

#[test]
fn id_json_has_figures_per_coordinate_and_the_root_residual() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 1.0);
    let out = dir.path().join("t.csv");
    let stdout = run(&["id", "{take}", "--json", "-o", "{out}"], &take, &out);
    let v: serde_json::Value = serde_json::from_slice(&stdout).unwrap();
    for key in [
        "frames",
        "ground_reactions",
        "coordinates",
        "root_residual",
        "contact_quality",
        "consistency",
        "notes",
    ] {
        assert!(v.get(key).is_some(), "no {key} in {v}");
    }
    assert_eq!(v["ground_reactions"], "estimated");
    // the figures are those of the file's columns
    let (h, c) = read_columns(&out).unwrap();
    let coords = v["coordinates"].as_array().unwrap();
    assert_eq!(
        coords.len(),
        h.iter().filter(|n| n.starts_with("tau:")).count()
    );
    for e in coords {
        let name = e["name"].as_str().unwrap();
        let col = &c[h.iter().position(|n| n == name).unwrap()];
        let peak = col.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        // (serde_json parses floats to within an ulp)
        let got = e["peak_abs"].as_f64().unwrap();
        assert!(
            (got - peak).abs() <= 1e-15 * (1.0 + peak),
            "{name}: {got} {peak}"
        );
        let rms = (col.iter().map(|x| x * x).sum::<f64>() / col.len() as f64).sqrt();
        assert!(
            (e["rms"].as_f64().unwrap() - rms).abs() <= 1e-12 * (1.0 + rms),
            "{name}"
        );
    }
    let residual: Vec<&str> = v["root_residual"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["name"].as_str().unwrap())
        .collect();
    assert_eq!(residual[0], "residual:fx");
    assert_eq!(residual.len(), 6);
    assert!(
        v["contact_quality"]["single_support_frames"]
            .as_u64()
            .is_some()
    );
    // with `-o -` the JSON goes to standard error, the data alone to standard output
    let o = articula()
        .arg("id")
        .arg(&take)
        .args(["--contact", "none", "--json", "-o", "-"])
        .output()
        .unwrap();
    assert!(o.status.success());
    assert!(String::from_utf8_lossy(&o.stdout).starts_with("time,"));
    let err = String::from_utf8_lossy(&o.stderr);
    let json = &err[err.find('{').unwrap()..=err.rfind('}').unwrap()];
    let v: serde_json::Value = serde_json::from_str(json).unwrap();
    assert_eq!(v["ground_reactions"], "none");
    assert_eq!(v["root_residual"].as_array().unwrap().len(), 0);
}

/// Issue 16: `id --json` says, per coordinate, whether its peak and RMS lie on frames whose
/// needed ground force the feet cannot give (`cop_gap` beyond 2 cm): the peak frame flagged or
/// not, the RMS² share of the flagged frames, the peak over the others; figures recomputed here
/// from the estimate's own per-frame gap and the torques.
#[test]
fn id_json_says_per_coordinate_how_much_lies_on_frames_the_feet_cannot_carry() {
    use articula::dynamics::grf::COP_GAP_TOLERANCE;
    use articula::pipeline::{self, Contact, StateColumns, TakeOptions};
    let dir = tempfile::tempdir().unwrap();
    let take = common::repo("data/demo_walk.bvh");
    let out = dir.path().join("id.csv");
    let v: serde_json::Value = serde_json::from_slice(&run(
        &["id", "{take}", "--contact", "feet", "--json", "-o", "{out}"],
        &take,
        &out,
    ))
    .unwrap();
    // the same job in the library: its estimate's flagged frames
    let opts = TakeOptions {
        contact: Contact::Feet,
        ..TakeOptions::default()
    };
    let src = pipeline::ModelSource::Take(take.clone());
    let job = pipeline::load_source_with(&src, None, &opts, StateColumns::QVA).unwrap();
    let (t, grf) = pipeline::job_torques(&job).unwrap();
    let flagged: Vec<bool> = (grf.unwrap().cop_gap.iter())
        .map(|&g| g > COP_GAP_TOLERANCE)
        .collect();
    let n_flagged = flagged.iter().filter(|&&f| f).count();
    assert!(n_flagged > 0 && n_flagged < flagged.len(), "{n_flagged}");
    assert_eq!(v["contact_quality"]["flagged_frames"], n_flagged);
    let coords = v["coordinates"].as_array().unwrap();
    assert_eq!(coords.len(), t.names.len());
    let (mut on_peak, mut off_peak) = (0, 0);
    for (j, e) in coords.iter().enumerate() {
        let x: Vec<f64> = t.tau.iter().map(|r| r[j]).collect();
        let c = &e["contact"];
        let peak_k = (0..x.len())
            .max_by(|&a, &b| x[a].abs().total_cmp(&x[b].abs()).then(b.cmp(&a)))
            .unwrap();
        assert_eq!(c["peak_frame_flagged"], flagged[peak_k], "{}", e["name"]);
        let unflagged = (0..x.len())
            .filter(|&k| !flagged[k])
            .map(|k| x[k].abs())
            .fold(0.0, f64::max);
        let got = c["peak_abs_unflagged"].as_f64().unwrap();
        assert!((got - unflagged).abs() <= 1e-12 * (1.0 + unflagged));
        let total: f64 = x.iter().map(|a| a * a).sum();
        let share = (0..x.len())
            .filter(|&k| flagged[k])
            .map(|k| x[k] * x[k])
            .sum::<f64>()
            / total;
        let got = c["rms_share_flagged"].as_f64().unwrap();
        assert!((got - share).abs() < 1e-9, "{}: {got} {share}", e["name"]);
        if flagged[peak_k] {
            on_peak += 1
        } else {
            off_peak += 1
        }
    }
    // the walk has coordinates of both sorts
    assert!(on_peak > 0 && off_peak > 0, "{on_peak} {off_peak}");
    // without contact there is nothing to judge by
    let v: serde_json::Value = serde_json::from_slice(&run(
        &["id", "{take}", "--contact", "none", "--json", "-o", "{out}"],
        &take,
        &out,
    ))
    .unwrap();
    assert!(v["coordinates"][0]["contact"].is_null());
}

#[test]
fn info_export_smooth_and_blend_json_parse_with_their_keys() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.5);
    let d = dir.path();
    let info: serde_json::Value =
        serde_json::from_slice(&run(&["info", "{take}", "--json"], &take, d)).unwrap();
    let skeleton = info["skeleton"].as_array().unwrap();
    assert_eq!(skeleton.len(), info["joints"].as_u64().unwrap() as usize);
    assert_eq!(skeleton[0]["name"], "Hips");
    assert!(skeleton[0]["parent"].is_null());
    assert_eq!(skeleton[1]["parent"], "Hips");
    assert!(info["notes"].is_array());
    let keys = [
        "command",
        "takes",
        "written",
        "format",
        "frames",
        "frame_time_s",
        "settings",
        "notes",
    ];
    let parse = |bytes: Vec<u8>| -> serde_json::Value {
        let v: serde_json::Value = serde_json::from_slice(&bytes).unwrap();
        for k in keys {
            assert!(v.get(k).is_some(), "no {k} in {v}");
        }
        v
    };
    let states = d.join("s.csv");
    let v = parse(run(
        &["export", "states", "{take}", "--json", "-o", "{out}"],
        &take,
        &states,
    ));
    assert_eq!(v["format"], "csv");
    assert_eq!(v["written"][1], sidecar_path(&states).display().to_string());
    assert_eq!(
        v["frames"].as_u64().unwrap() as usize,
        read_columns(&states).unwrap().1[0].len()
    );
    let v = parse(run(
        &["export", "urdf", "{take}", "--json", "-o", "{out}"],
        &take,
        &d.join("m.urdf"),
    ));
    assert!(v["frames"].is_null());
    let smooth = d.join("smooth.bvh");
    let v = parse(run(
        &["smooth", "{take}", "--json", "-o", "{out}"],
        &take,
        &smooth,
    ));
    assert_eq!(v["command"], "smooth");
    assert_eq!(
        v["frames"].as_u64().unwrap() as usize,
        articula::io::bvh::read(&smooth).unwrap().frames
    );
    let blend = d.join("blend.bvh");
    let v = parse(run(
        &[
            "blend", "{take}", "{take}", "--window", "0.2:0.3", "--json", "-o", "{out}",
        ],
        &take,
        &blend,
    ));
    assert_eq!(v["takes"].as_array().unwrap().len(), 2);
    assert!(blend.exists());
}

#[test]
fn run_json_gives_every_expect_with_its_value_and_the_failing_one() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 0.5);
    let session = dir.path().join("s.session");
    let text = |hi: &str| {
        format!(
            "load {}\nexpect frames 30\nexpect peak LeftLeg.Xrotation torque between 1 {hi}\n\
             export csv r.csv\nexport states st.csv\n",
            take.display()
        )
    };
    std::fs::write(&session, text("1000")).unwrap();
    let o = articula()
        .arg("run")
        .arg(&session)
        .arg("--out")
        .arg(dir.path())
        .arg("--json")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["ok"], true);
    let e = v["expectations"].as_array().unwrap();
    assert_eq!(e.len(), 2);
    assert_eq!(e[0]["line"], 2);
    assert_eq!(e[0]["result"], "frames = 30");
    assert!(e[1]["result"].as_str().unwrap().contains("N·m"), "{}", e[1]);
    assert_eq!(e[0]["value"], 30.0);
    assert_eq!(e[0]["unit"], "");
    // the value is the knee's peak |τ| unrounded (over the quoted frames: at most the peak of
    // every frame in the session's export), the one the result shows rounded
    assert_eq!(e[1]["unit"], "N·m");
    let (h, c) = read_columns(&dir.path().join("r.csv")).unwrap();
    let knee = &c[h.iter().position(|n| n == "tau:LeftLeg.Xrotation").unwrap()];
    let peak = knee.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let got = e[1]["value"].as_f64().unwrap();
    assert!(got > 1.0 && got <= peak * (1.0 + 1e-12), "{got} vs {peak}");
    let shown = format!("{got:.1} N·m");
    assert!(
        e[1]["result"].as_str().unwrap().contains(&shown),
        "{shown}: {}",
        e[1]
    );
    assert_eq!(e[1]["pass"], true);
    // the session's CSVs have their sidecars too, their units from the same table
    let m = model(&take);
    for (csv, command) in [("r.csv", "export csv"), ("st.csv", "export states")] {
        let path = dir.path().join(csv);
        let side = sidecar_of(&path);
        assert_eq!(side.command, command);
        let header = read_columns(&path).unwrap().0;
        let names: Vec<&str> = side.columns.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, header);
        for c in &side.columns {
            assert_eq!(
                c.unit,
                columns::unit_of(&c.name, Some(&m)).unwrap(),
                "{}",
                c.name
            );
        }
    }
    // a failing expect: the JSON still comes, with pass false, and the run fails
    std::fs::write(&session, text("2")).unwrap();
    let o = articula()
        .arg("run")
        .arg(&session)
        .arg("--out")
        .arg(dir.path())
        .arg("--json")
        .output()
        .unwrap();
    assert!(!o.status.success());
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["ok"], false);
    assert_eq!(v["expectations"][1]["pass"], false);
    assert!(v["error"].as_str().unwrap().contains("expect"), "{v}");
}

/// Issue 16: the session's tables follow the scheme and get their sidecars too: `compare
/// weights` (`time`, `tau:<coord>:<mass>kg`) and `report motor curves` (`time`, then per joint
/// `tau:`, `v:`, `power:`, `current:`), each with `NAME.csv.json` giving every column its unit.
#[test]
fn the_session_tables_follow_the_scheme_with_their_sidecars() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let take = walk(d, 0.5);
    let m = model(&take);
    // (the session command, the file, a column it must have with its unit)
    let writers: &[(&str, &str, &str, &str)] = &[
        (
            "compare weights 60,80 joint LeftLeg.Xrotation",
            "weights.csv",
            "tau:LeftLeg.Xrotation:80kg",
            "N*m",
        ),
        (
            "report motor curves",
            "motor.csv",
            "current:LeftLeg.Xrotation",
            "A",
        ),
    ];
    let mut text = format!("load {}\nselect LeftLeg\n", take.display());
    for (command, file, _, _) in writers {
        text.push_str(&format!("{command} {}\n", d.join(file).display()));
    }
    let session = d.join("tables.session");
    std::fs::write(&session, text).unwrap();
    articula().arg("run").arg(&session).assert().success();
    for (command, file, column, unit) in writers {
        let out = d.join(file);
        let (header, cols) = read_columns(&out).unwrap();
        assert_eq!(header[0], "time", "{command}");
        assert!(cols[0].len() > 10, "{command}");
        let side = sidecar_of(&out);
        assert_eq!(side.file, *file);
        let names: Vec<&str> = side.columns.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, header, "{command}: the sidecar lists the header");
        for (c, h) in side.columns.iter().zip(&header) {
            let kind = columns::kind_of(h).unwrap_or_else(|| panic!("{command}: {h} has no kind"));
            assert_eq!(c.quantity, kind.quantity, "{command}: {h}");
            assert_eq!(
                c.unit,
                columns::unit_of(h, Some(&m)).unwrap(),
                "{command}: {h}"
            );
        }
        let c = side.columns.iter().find(|c| c.name == *column);
        assert_eq!(
            c.map(|c| c.unit.as_str()),
            Some(*unit),
            "{command}: {column} in {header:?}"
        );
    }
    // the mass is a component of the name: 60 kg and 80 kg of the same coordinate
    let (header, _) = read_columns(&d.join("weights.csv")).unwrap();
    assert_eq!(
        header,
        [
            "time",
            "tau:LeftLeg.Xrotation:60kg",
            "tau:LeftLeg.Xrotation:80kg"
        ]
    );
}

/// The summary tables' columns: the header of `out` against its sidecar, every column with a
/// kind of the scheme and the unit `want` gives the named ones.
fn check_summary(out: &Path, command: &str, want: &[(&str, &str)]) {
    let text = std::fs::read_to_string(out).unwrap();
    let mut rdr = csv::Reader::from_reader(text.as_bytes());
    let header: Vec<String> = rdr.headers().unwrap().iter().map(String::from).collect();
    assert!(rdr.records().count() > 0, "{command}: no rows");
    let side = sidecar_of(out);
    assert_eq!(side.command, command);
    let names: Vec<&str> = side.columns.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(names, header, "{command}: the sidecar lists the header");
    for (c, h) in side.columns.iter().zip(&header) {
        let kind = columns::kind_of(h).unwrap_or_else(|| panic!("{command}: {h} has no kind"));
        assert_eq!(c.quantity, kind.quantity, "{command}: {h}");
        // no unit in a name: the sidecar says it
        for unit in ["_Nm", "_rad", "_s", "_A", "_W"] {
            assert!(
                !h.ends_with(unit),
                "{command}: {h} has its unit in its name"
            );
        }
    }
    for (name, unit) in want {
        let c = side.columns.iter().find(|c| c.name == *name);
        assert_eq!(
            c.map(|c| c.unit.as_str()),
            Some(*unit),
            "{command}: {name} in {header:?}"
        );
    }
}

/// Issue 16: the summary tables too (one row per run, joint or take) are in the scheme, units in
/// their sidecars: `tradeoff -o`, the session's `report motor PATH.csv` and `batch`'s
/// `summary.csv` (whose `peak:tau:<coord>` takes its unit from the outputs' own sidecars); `-`
/// streams the table with no sidecar.
#[test]
fn the_summary_tables_follow_the_scheme_with_their_sidecars() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let take = walk(d, 0.5);
    // tradeoff -o, and -o - on standard output
    let trade = d.join("trade.csv");
    let args = ["tradeoff", "{take}", "--duration", "0.1", "-o", "{out}"];
    run(&args, &take, &trade);
    check_summary(
        &trade,
        "tradeoff",
        &[
            ("dt", "s"),
            ("wall_per_sim", "s/s"),
            ("deviation", "rad"),
            ("rms:err", "rad"),
            ("pareto", "1"),
        ],
    );
    let piped = run(&args, &take, Path::new("-"));
    let first = String::from_utf8_lossy(&piped)
        .lines()
        .next()
        .map(String::from);
    assert_eq!(
        first.as_deref(),
        Some("joints,integrator,dt,wall_per_sim,deviation,rms:err,energy_drift,pareto")
    );
    assert!(!d.join("-.json").exists());
    // the session's motor table
    let motor = d.join("motor.csv");
    let session = d.join("motor.session");
    let text = format!(
        "load {}\nselect LeftLeg\nreport motor {}\n",
        take.display(),
        motor.display()
    );
    std::fs::write(&session, text).unwrap();
    articula().arg("run").arg(&session).assert().success();
    check_summary(
        &motor,
        "report motor",
        &[
            ("joint", "text"),
            ("peak:tau", "N*m"),
            ("peak:v", "rad/s"),
            ("peak:power", "W"),
            ("rms:motor_tau", "N*m"),
            ("peak:motor_v", "rad/s"),
            ("rms:current", "A"),
            ("km", "N*m/A"),
            ("gear", "1"),
        ],
    );
    // batch's summary, a swept setting and a coordinate's column among the figures
    let takes = d.join("takes");
    std::fs::create_dir(&takes).unwrap();
    std::fs::copy(&take, takes.join("walk.bvh")).unwrap();
    let out = d.join("out");
    articula()
        .arg("batch")
        .arg(&takes)
        .arg("-o")
        .arg(&out)
        .args([
            "--vary",
            "mass=60,80",
            "--of",
            "tau:LeftLeg.Xrotation,residual:fx",
        ])
        .args(["--", "id", "--contact", "auto"])
        .assert()
        .success();
    check_summary(
        &out.join("summary.csv"),
        "batch",
        &[
            ("take", "text"),
            ("setting:mass", "text"),
            ("wall_time", "s"),
            ("peak:tau:LeftLeg.Xrotation", "N*m"),
            ("rms:residual:fx", "N"),
            ("failure", "text"),
        ],
    );
}

/// A session's `export csv` to an OpenSim name is an error that says what writes OpenSim's
/// tables (it once wrote CSV text into `x.sto`).
#[test]
fn session_export_csv_to_an_opensim_name_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let session = dir.path().join("sto.session");
    let out = dir.path().join("x.sto");
    std::fs::write(
        &session,
        format!("load demo:walk\nexport csv {}\n", out.display()),
    )
    .unwrap();
    articula()
        .arg("run")
        .arg(&session)
        .assert()
        .failure()
        .stderr(predicates::str::contains("sto.session:2"))
        .stderr(predicates::str::contains("export states|grf|id PATH.sto"));
    assert!(!out.exists());
}

/// `anatomy --json` on a take without ground contact says so, as JSON: from `contact auto`
/// on a take of two frames (its reason), and from `--contact none` (once an error, which made a
/// batch of `anatomy --json` fail on any take that never stands on a floor).
#[test]
fn anatomy_json_without_contact_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let take = walk(dir.path(), 1.0);
    let out = dir.path().join("a.csv");
    let stdout = run(
        &[
            "anatomy",
            "{take}",
            "--contact",
            "none",
            "--json",
            "-o",
            "{out}",
        ],
        &take,
        &out,
    );
    let v: serde_json::Value = serde_json::from_slice(&stdout).unwrap();
    assert_eq!(v["contact"], "none", "{v}");
    assert!(v["meets"].is_null(), "{v}");
    assert!(
        v["why"].as_str().unwrap().starts_with("contact none"),
        "{v}"
    );
    // two frames: `auto` settles on none and gives its reason
    let text = std::fs::read_to_string(&take).unwrap();
    let (head, motion) = text.split_once("MOTION").unwrap();
    let rows: Vec<&str> = motion.lines().skip(3).take(2).collect();
    let frame_time = motion.lines().nth(2).unwrap();
    let short = dir.path().join("two.bvh");
    std::fs::write(
        &short,
        format!(
            "{head}MOTION\nFrames: 2\n{frame_time}\n{}\n",
            rows.join("\n")
        ),
    )
    .unwrap();
    let stdout = run(
        &["anatomy", "{take}", "--json", "-o", "{out}"],
        &short,
        &out,
    );
    let v: serde_json::Value = serde_json::from_slice(&stdout).unwrap();
    assert_eq!(v["contact"], "none", "{v}");
    let why = v["why"].as_str().unwrap();
    assert!(why.starts_with("contact auto chose none: "), "{why}");
    assert!(why.contains("2 frame"), "{why}");
}
