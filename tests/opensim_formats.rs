//! OpenSim's formats, written by the real binary on the bundled demo take and read back here
//! without OpenSim: the `.sto` / `.mot` header (name, `version=1`, `nRows`, `nColumns` with the
//! time column, `inDegrees`, units, `endheader`, a tab-separated label line), OpenSim's column
//! names, the `.trc` header, the ExternalLoads XML beside a `.mot`, and every number equal to
//! the CSV of the same command within the 11 significant digits the files carry (degrees for
//! rotations in states). `tools/check_opensim.py` loads the same files with OpenSim itself.

use articula::report::csv::read_columns;
use assert_cmd::Command;
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// Relative tolerance of a number written with 11 significant digits, plus an absolute one for
/// values that are zero up to rounding.
const RTOL: f64 = 1e-10;
const ATOL: f64 = 1e-12;

fn articula() -> Command {
    Command::cargo_bin("articula").expect("binary")
}

fn demo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/demo_walk.bvh")
}

fn write(take: &Path, args: &[&str], out: &Path) {
    articula()
        .args(args)
        .arg(take)
        .arg("-o")
        .arg(out)
        .assert()
        .success();
}

/// A parsed `.sto`: header lines before `endheader`, labels after `time`, the time column and
/// the columns by label.
struct Sto {
    header: Vec<String>,
    labels: Vec<String>,
    time: Vec<f64>,
    columns: HashMap<String, Vec<f64>>,
}

fn read_sto(text: &str) -> Sto {
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .by_ref()
        .take_while(|l| *l != "endheader")
        .map(String::from)
        .collect();
    let label_line = lines.next().expect("a label line after endheader");
    let mut labels: Vec<String> = label_line.split('\t').map(String::from).collect();
    assert_eq!(labels.remove(0), "time", "{label_line}");
    let mut time = vec![];
    let mut columns: HashMap<String, Vec<f64>> = HashMap::new();
    for l in lines {
        let mut f = l.split('\t');
        time.push(f.next().unwrap().parse().unwrap());
        let values: Vec<&str> = f.collect();
        assert_eq!(values.len(), labels.len(), "{l}");
        for (label, v) in labels.iter().zip(values) {
            check_digits(v);
            columns
                .entry(label.clone())
                .or_default()
                .push(v.parse().unwrap());
        }
    }
    Sto {
        header,
        labels,
        time,
        columns,
    }
}

/// No round-trip noise: at most 11 significant digits in a number's text.
fn check_digits(v: &str) {
    let mantissa = v.split('e').next().unwrap();
    let digits = mantissa
        .trim_start_matches('-')
        .replace('.', "")
        .trim_start_matches('0')
        .len();
    assert!(digits <= 11, "{v} has {digits} significant digits");
}

fn close(what: &str, got: f64, want: f64) {
    assert!(
        (got - want).abs() <= RTOL * want.abs() + ATOL,
        "{what}: {got} vs {want}"
    );
}

fn csv(path: &Path) -> (Vec<String>, HashMap<String, Vec<f64>>) {
    let (h, c) = read_columns(path).unwrap();
    (h.clone(), h.into_iter().zip(c).collect())
}

#[test]
fn states_sto_has_opensims_header_and_degrees() {
    let dir = tempfile::tempdir().unwrap();
    let (sto, csv_path) = (dir.path().join("s.sto"), dir.path().join("s.csv"));
    write(&demo(), &["export", "states"], &sto);
    write(&demo(), &["export", "states"], &csv_path);
    let (header, cols) = csv(&csv_path);
    let s = read_sto(&std::fs::read_to_string(&sto).unwrap());
    let n = cols["time"].len();
    assert_eq!(s.header[0], "demo_walk states");
    assert_eq!(
        &s.header[1..5],
        [
            "version=1".to_string(),
            format!("nRows={n}"),
            format!("nColumns={}", header.len()),
            "inDegrees=yes".to_string()
        ]
    );
    assert!(
        s.header[5].starts_with("units=rotations deg"),
        "{:?}",
        s.header
    );
    assert_eq!(s.labels.len() + 1, header.len());
    assert_eq!(s.time.len(), n);
    for (k, (got, want)) in s.time.iter().zip(&cols["time"]).enumerate() {
        close(&format!("time row {k}"), *got, *want);
    }
    for h in &header[1..] {
        let (kind, coord) = h.split_once(':').unwrap();
        let label = format!(
            "{coord}{}",
            ["", "_u", "_dudt"][["q", "v", "a"].iter().position(|k| *k == kind).unwrap()]
        );
        let scale = if coord.contains("rotation") {
            180.0 / std::f64::consts::PI
        } else {
            1.0
        };
        for (k, (got, want)) in s.columns[&label].iter().zip(&cols[h]).enumerate() {
            close(&format!("{label} row {k}"), *got, want * scale);
        }
    }
    // the root's height is a translation, in m; a hip angle in degrees
    assert!(s.columns["Hips.Yposition"][0] > 0.8 && s.columns["Hips.Yposition"][0] < 1.1);
}

#[test]
fn id_sto_names_moments_and_forces() {
    let dir = tempfile::tempdir().unwrap();
    let (sto, csv_path) = (dir.path().join("id.sto"), dir.path().join("id.csv"));
    write(&demo(), &["id"], &sto);
    write(&demo(), &["id"], &csv_path);
    let (header, cols) = csv(&csv_path);
    let s = read_sto(&std::fs::read_to_string(&sto).unwrap());
    assert_eq!(s.header[4], "inDegrees=no");
    assert!(s.header[5].starts_with("units=moments N*m, forces N"));
    let coords: Vec<&String> = header[1..]
        .iter()
        .filter(|h| h.starts_with("tau:"))
        .collect();
    assert_eq!(s.labels.len(), coords.len());
    for (label, column) in s.labels.iter().zip(&coords) {
        let coord = column.strip_prefix("tau:").unwrap();
        let kind = if coord.contains("position") {
            "force"
        } else {
            "moment"
        };
        assert_eq!(label, &format!("{coord}_{kind}"));
        for (k, (got, want)) in s.columns[label].iter().zip(&cols[*column]).enumerate() {
            close(&format!("{label} row {k}"), *got, *want);
        }
    }
}

#[test]
fn grf_mot_and_its_external_loads_xml() {
    let dir = tempfile::tempdir().unwrap();
    let (mot, csv_path) = (dir.path().join("grf.mot"), dir.path().join("grf.csv"));
    write(&demo(), &["export", "grf"], &mot);
    write(&demo(), &["export", "grf"], &csv_path);
    let (_, cols) = csv(&csv_path);
    let s = read_sto(&std::fs::read_to_string(&mot).unwrap());
    assert_eq!(s.header[3], "nColumns=19");
    let mut expected = vec![];
    for foot in ["left", "right"] {
        for (stem, what) in [
            ("ground_force_v", "grf"),
            ("ground_force_p", "cop"),
            ("ground_torque_", "moment"),
        ] {
            for a in ["x", "y", "z"] {
                let label = format!("{foot}_{stem}{a}");
                for (k, (got, want)) in s.columns[&label]
                    .iter()
                    .zip(&cols[&format!("{what}:{foot}:{a}")])
                    .enumerate()
                {
                    close(&format!("{label} row {k}"), *got, *want);
                }
                expected.push(label);
            }
        }
    }
    assert_eq!(s.labels, expected);
    // the body weight is carried: the vertical forces of the feet add up to ~m·g on average
    let mean_fy: f64 = (0..s.time.len())
        .map(|k| s.columns["left_ground_force_vy"][k] + s.columns["right_ground_force_vy"][k])
        .sum::<f64>()
        / s.time.len() as f64;
    assert!((mean_fy / (75.0 * 9.81) - 1.0).abs() < 0.1, "{mean_fy}");

    let xml = std::fs::read_to_string(dir.path().join("grf.xml")).unwrap();
    for needle in [
        "<ExternalLoads",
        "<ExternalForce name=\"left\">",
        "<applied_to_body>LeftFoot</applied_to_body>",
        "<applied_to_body>RightFoot</applied_to_body>",
        "<force_expressed_in_body>ground</force_expressed_in_body>",
        "<point_expressed_in_body>ground</point_expressed_in_body>",
        "<force_identifier>right_ground_force_v</force_identifier>",
        "<point_identifier>right_ground_force_p</point_identifier>",
        "<torque_identifier>right_ground_torque_</torque_identifier>",
        "<datafile>grf.mot</datafile>",
    ] {
        assert!(xml.contains(needle), "{needle} not in\n{xml}");
    }
    roxmltree::Document::parse(&xml).expect("well-formed XML");
}

#[test]
fn trc_markers_are_the_joint_centres_in_the_declared_unit() {
    let dir = tempfile::tempdir().unwrap();
    let pos = dir.path().join("p.csv");
    write(&demo(), &["export", "positions"], &pos);
    let (header, cols) = csv(&pos);
    for (units, scale) in [("mm", 1000.0), ("m", 1.0)] {
        let trc = dir.path().join(format!("m_{units}.trc"));
        articula()
            .args(["export", "trc"])
            .arg(demo())
            .args(["--trc-units", units, "-o"])
            .arg(&trc)
            .assert()
            .success();
        let text = std::fs::read_to_string(&trc).unwrap();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines[0], format!("PathFileType\t4\t(X/Y/Z)\tm_{units}.trc"));
        assert_eq!(
            lines[1],
            "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\t\
             OrigDataStartFrame\tOrigNumFrames"
        );
        assert_eq!(lines[2], format!("120\t120\t480\t21\t{units}\t120\t1\t480"));
        let markers: Vec<&str> = lines[3].split('\t').skip(2).step_by(3).collect();
        assert_eq!(markers.len(), 21);
        assert_eq!(lines[4].split('\t').nth(2), Some("X1"));
        assert_eq!(lines[5], "");
        for (k, l) in lines[6..].iter().enumerate() {
            let f: Vec<f64> = l.split('\t').map(|x| x.parse().unwrap()).collect();
            assert_eq!(f[0], (k + 1) as f64);
            close("time", f[1], cols["time"][k]);
            for (m, name) in markers.iter().enumerate() {
                for (a, ax) in ["x", "y", "z"].iter().enumerate() {
                    let h = format!("pos:{name}:{ax}");
                    assert!(header.contains(&h));
                    close(&h, f[2 + 3 * m + a], cols[&h][k] * scale);
                }
            }
        }
    }
}

/// `-o -` streams: CSV by default, the .sto with `--format sto`; no file named `-`.
#[test]
fn standard_output_takes_format_from_the_flag() {
    let dir = tempfile::tempdir().unwrap();
    let run = |extra: &[&str]| {
        let out = articula()
            .current_dir(dir.path())
            .args(["export", "states"])
            .arg(demo())
            .args(extra)
            .args(["-o", "-"])
            .output()
            .unwrap();
        assert!(out.status.success(), "{out:?}");
        String::from_utf8(out.stdout).unwrap()
    };
    assert!(run(&[]).starts_with("time,q:"));
    assert!(run(&["--format", "sto"]).starts_with("demo_walk states\nversion=1\n"));
    assert!(!dir.path().join("-").exists());
    articula()
        .args(["export", "urdf"])
        .arg(demo())
        .args(["--format", "sto", "-o", "-"])
        .assert()
        .failure();
    articula()
        .args(["export", "states"])
        .arg(demo())
        .args(["--joints", "ball", "-o"])
        .arg(dir.path().join("b.sto"))
        .assert()
        .failure()
        .stderr(predicates::str::contains("--joints euler"));
}

/// The file's clock in OpenSim files: with a rest frame 0 prepended to the demo take (and
/// dropped on reading), the first row is the file's frame 1, at 1/120 s, `Frame#` 2.
#[test]
fn opensim_files_keep_the_files_clock_after_a_dropped_rest_frame() {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(demo()).unwrap();
    let (head, motion) = text.split_once("Frames: 480\n").unwrap();
    let channels = motion.lines().nth(1).unwrap().split_whitespace().count();
    let rest = vec!["0"; channels].join(" ");
    let (frame_time, frames) = motion.split_once('\n').unwrap();
    let take = dir.path().join("rest.bvh");
    std::fs::write(
        &take,
        format!("{head}Frames: 481\n{frame_time}\n{rest}\n{frames}"),
    )
    .unwrap();
    let sto = dir.path().join("s.sto");
    write(&take, &["export", "states"], &sto);
    let s = read_sto(&std::fs::read_to_string(&sto).unwrap());
    assert_eq!(s.time.len(), 480);
    close("first time", s.time[0], 1.0 / 120.0);
    let trc = dir.path().join("m.trc");
    write(&take, &["export", "trc"], &trc);
    let t = std::fs::read_to_string(&trc).unwrap();
    let lines: Vec<&str> = t.lines().collect();
    assert_eq!(lines[2], "120\t120\t480\t21\tmm\t120\t2\t481");
    assert!(lines[6].starts_with("2\t0.0083333333333\t"), "{}", lines[6]);
}

/// The session writes the same files as the CLI (issue 16: each format from the CLI and a
/// session command): `export states|trc|grf PATH` on the active take, the format by the
/// extension, byte for byte what `articula export …` writes with the same (default) options.
#[test]
fn a_session_exports_the_same_files_as_the_cli() {
    let dir = tempfile::tempdir().unwrap();
    let (cli, ses) = (dir.path().join("cli"), dir.path().join("ses"));
    std::fs::create_dir_all(&cli).unwrap();
    let files = [
        ("states", "s.sto"),
        ("states", "s.csv"),
        ("trc", "m.trc"),
        ("grf", "g.mot"),
        ("grf", "g.csv"),
    ];
    let mut session = format!("load {}\n", demo().display());
    for (what, name) in files {
        write(&demo(), &["export", what], &cli.join(name));
        session += &format!("export {what} {name}\n");
    }
    let s = dir.path().join("x.session");
    std::fs::write(&s, session).unwrap();
    articula()
        .arg("run")
        .arg(&s)
        .arg("--out")
        .arg(&ses)
        .assert()
        .success();
    for (_, name) in files {
        let a = std::fs::read(cli.join(name)).unwrap();
        let b = std::fs::read(ses.join(name)).unwrap();
        assert!(a == b, "{name}: the session's file differs from the CLI's");
    }
    // the external loads' XML beside the .mot
    let xml = std::fs::read_to_string(ses.join("g.xml")).unwrap();
    assert!(xml.contains("<ExternalLoads"), "{xml}");
}

/// Issue 16: a session's `export id PATH.sto|.csv` writes the active take's inverse dynamics
/// with `articula id`'s own writer: under the same settings (residual reduction on, the
/// session's default with contact), the very bytes of `articula id -o PATH`.
#[test]
fn session_export_id_is_the_cli_id_byte_for_byte() {
    let dir = tempfile::tempdir().unwrap();
    let p = |n: &str| dir.path().join(n);
    for ext in ["sto", "csv"] {
        write(
            &demo(),
            &["id", "--consistent", "on"],
            &p(&format!("cli.{ext}")),
        );
    }
    let session = p("id.session");
    std::fs::write(
        &session,
        format!(
            "load {}\nexport id {}\nexport id {}\n",
            demo().display(),
            p("session.sto").display(),
            p("session.csv").display()
        ),
    )
    .unwrap();
    articula().arg("run").arg(&session).assert().success();
    for ext in ["sto", "csv"] {
        let cli = std::fs::read(p(&format!("cli.{ext}"))).unwrap();
        let ses = std::fs::read(p(&format!("session.{ext}"))).unwrap();
        assert!(cli == ses, "export id .{ext} differs from articula id's");
    }
    let sto = std::fs::read_to_string(p("session.sto")).unwrap();
    assert!(sto.contains("LeftLeg.Xrotation_moment") && sto.contains("Hips.Yposition_force"));
}
