//! The formats a job's table is written in, and the OpenSim outputs of a take: states and
//! inverse dynamics as `.sto`, ground reactions as an external-loads `.mot` with its
//! ExternalLoads XML, joint centres as `.trc` markers (`report::opensim` writes the text).
//!
//! A table's format is `--format` when given, else its output's extension ([`TABLE_FORMATS`]),
//! else CSV; `-` (standard output) is CSV unless `--format` says otherwise. Every time is the
//! file's ([`crate::io::bvh::Bvh::time`]); every file states its units in its header.

use super::{Job, Take, ground_reactions, job_torques, joint_centres};
use crate::dynamics::grf::GroundReactions;
use crate::error::Error;
use crate::report::csv::write_columns;
use crate::report::opensim::{self, Sto, Trc, TrcUnits};
use std::path::{Path, PathBuf};

/// The format of a table output.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TableFormat {
    /// Comma-separated, shortest round-trip numbers, SI (`report::csv`).
    Csv,
    /// OpenSim's `.sto` / `.mot` (`report::opensim`).
    Sto,
}

/// Every table format by its name and extension (`--format NAME`, `-o FILE.NAME`).
pub const TABLE_FORMATS: &[(&str, TableFormat)] = &[
    ("csv", TableFormat::Csv),
    ("sto", TableFormat::Sto),
    ("mot", TableFormat::Sto),
];

impl TableFormat {
    /// The format's name as `--format` takes it (`csv`, `sto`, `mot`).
    pub fn name(self) -> &'static str {
        TABLE_FORMATS
            .iter()
            .find(|f| f.1 == self)
            .map_or("csv", |f| f.0)
    }

    /// `explicit` (`--format`) when given, else `path`'s extension when it is one of
    /// [`TABLE_FORMATS`], else CSV.
    pub fn choose(path: &Path, explicit: Option<&str>) -> Result<TableFormat, Error> {
        let find = |name: &str| {
            TABLE_FORMATS
                .iter()
                .find(|(n, _)| n.eq_ignore_ascii_case(name.trim()))
                .map(|f| f.1)
        };
        if let Some(name) = explicit {
            return find(name).ok_or_else(|| {
                let names: Vec<&str> = TABLE_FORMATS.iter().map(|f| f.0).collect();
                Error::Invalid(format!(
                    "--format {name}: expected one of {}",
                    names.join(", ")
                ))
            });
        }
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        Ok(find(ext).unwrap_or(TableFormat::Csv))
    }
}

/// The take's name for a table's first header line: its file stem and `what`.
fn table_name(take: Option<&Take>, what: &str) -> String {
    match take.and_then(|t| t.path.file_stem()) {
        Some(stem) => format!("{} {what}", stem.to_string_lossy()),
        None => what.to_string(),
    }
}

/// The take's axes, for headers: which world axis is up.
fn axes(take: &Take) -> String {
    format!(
        "the take's world axes, {} up",
        ["x", "y", "z"][take.up.index()]
    )
}

/// `articula export states` in `format`: as CSV ([`super::export_states`]) or as `.sto`: per
/// coordinate `<coord>` (q), `<coord>_u` (v) and `<coord>_dudt` (a), OpenSim's names for a
/// coordinate's value, speed and acceleration; rotations in degrees (`inDegrees=yes`: deg,
/// deg/s, deg/s²), translations in m, m/s, m/s². Needs the euler model: the ball model's
/// quaternions are no OpenSim coordinates.
pub fn export_states_as(take: &Take, path: &Path, format: TableFormat) -> Result<(), Error> {
    if format == TableFormat::Csv {
        return super::export_states(take, path);
    }
    let (m, s) = (&take.model, &take.states);
    if m.nq != m.nv {
        return Err(Error::Invalid(format!(
            "{}: states as .sto need one coordinate per degree of freedom (the euler model); \
             the ball model's quaternions are no OpenSim coordinates: add --joints euler, or \
             write CSV",
            path.display()
        )));
    }
    let scale: Vec<f64> = (0..m.nv)
        .map(|k| {
            if m.is_angular(k) {
                180.0 / std::f64::consts::PI
            } else {
                1.0
            }
        })
        .collect();
    let mut labels = vec![];
    let mut columns: Vec<Vec<f64>> = vec![];
    for (suffix, rows) in [("", &s.q), ("_u", &s.v), ("_dudt", &s.a)] {
        for (k, name) in m.v_names.iter().enumerate() {
            let coord = if suffix.is_empty() {
                &m.q_names[k]
            } else {
                name
            };
            labels.push(format!("{coord}{suffix}"));
            columns.push(rows.iter().map(|r| r[k] * scale[k]).collect());
        }
    }
    let refs: Vec<&[f64]> = columns.iter().map(Vec::as_slice).collect();
    let metadata = [(
        "units",
        format!(
            "rotations deg, deg/s, deg/s^2; translations m, m/s, m/s^2; time s; {}",
            axes(take)
        ),
    )];
    opensim::write_sto(
        path,
        &Sto {
            name: &table_name(Some(take), "states"),
            in_degrees: true,
            metadata: &metadata,
            time: &s.time,
            labels: &labels,
            columns: &refs,
        },
    )
}

/// `articula id` in `format`: as CSV ([`super::write_inverse_dynamics`]) or as `.sto` with
/// OpenSim's inverse-dynamics names, `<coord>_moment` (N·m) for a rotation and `<coord>_force`
/// (N) for a translation (`inDegrees=no`); the ground reactions then go to `export grf`. With
/// contact, the `.sto` header says the take's consistency (`residuals=`, the longest of
/// [`Consistency::figure_lines`](super::consistency::Consistency::figure_lines): the residual
/// figures against Hicks et al.'s thresholds), which OpenSim keeps as the table's metadata; a
/// CSV's sidecar has it as its `consistency` key.
pub fn write_inverse_dynamics_as(
    job: &Job,
    path: &Path,
    format: TableFormat,
    consistency: Option<&super::consistency::Consistency>,
) -> Result<super::IdOutcome, Error> {
    if format == TableFormat::Csv {
        return super::write_inverse_dynamics(job, path);
    }
    let (t, grf) = job_torques(job)?;
    let m = &job.model;
    let labels: Vec<String> = t
        .names
        .iter()
        .enumerate()
        .map(|(k, n)| {
            let kind = if m.is_angular(k) { "moment" } else { "force" };
            format!("{n}_{kind}")
        })
        .collect();
    let columns: Vec<Vec<f64>> = (0..t.names.len())
        .map(|k| t.tau.iter().map(|r| r[k]).collect())
        .collect();
    let refs: Vec<&[f64]> = columns.iter().map(Vec::as_slice).collect();
    let with = if grf.is_some() {
        "with the ground reactions applied"
    } else {
        "without ground contact"
    };
    let mut metadata = vec![("units", format!("moments N*m, forces N, time s; {with}"))];
    if let Some(line) = consistency.and_then(|c| c.figure_lines().into_iter().next()) {
        metadata.push(("residuals", line));
    }
    opensim::write_sto(
        path,
        &Sto {
            name: &table_name(job.take.as_ref(), "inverse dynamics"),
            in_degrees: false,
            metadata: &metadata,
            time: &t.time,
            labels: &labels,
            columns: &refs,
        },
    )?;
    Ok(super::IdOutcome::new(job, &t, grf.as_deref()))
}

/// What `export grf` wrote besides the table: the ExternalLoads XML, or why none.
#[derive(Debug, Clone, PartialEq)]
pub enum ExternalLoadsXml {
    /// Written at this path.
    Written(PathBuf),
    /// Not written, and why (a CSV output, or standard output).
    None(String),
}

/// `articula export grf`: the ground reactions of a take with ground contact, per foot. As
/// CSV: `time`, `grf:<foot>:x|y|z` (N), `cop:<foot>:x|y|z` (m), `moment:<foot>:x|y|z` (the
/// free moment, N·m), world axes. As `.mot` (OpenSim external loads): per foot
/// `<foot>_ground_force_v[xyz]`, `<foot>_ground_force_p[xyz]`, `<foot>_ground_torque_[xyz]`,
/// with the ExternalLoads XML `NAME.xml` beside it applying each foot's force at its point,
/// with its torque, to the foot's body, all expressed in ground.
pub fn export_grf(
    take: &Take,
    path: &Path,
    format: TableFormat,
) -> Result<ExternalLoadsXml, Error> {
    let g = ground_reactions(take)?.ok_or_else(|| {
        // `auto`'s reason when it settled on none (advising `--contact feet` there would send
        // the user to its own refusal: no foot planted), else the user's `--contact none`
        let why = super::contact::auto_chose_none(take)
            .unwrap_or_else(|| "contact none was chosen: add --contact feet (or auto)".into());
        Error::Invalid(format!(
            "{}: no ground contact, so no ground reactions to write ({why})",
            take.path.display()
        ))
    })?;
    let (labels, columns) = grf_columns(&g, format);
    let refs: Vec<&[f64]> = columns.iter().map(Vec::as_slice).collect();
    let time = &take.states.time;
    if format == TableFormat::Csv {
        let mut header = vec!["time".to_string()];
        header.extend(labels);
        let columns: Vec<&[f64]> = std::iter::once(&time[..])
            .chain(refs.iter().copied())
            .collect();
        write_columns(path, &header, &columns)?;
        return Ok(ExternalLoadsXml::None("a CSV output".into()));
    }
    let metadata = [(
        "units",
        format!(
            "force N, point m, torque N*m, time s; {}; expressed in ground",
            axes(take)
        ),
    )];
    opensim::write_sto(
        path,
        &Sto {
            name: &table_name(Some(take), "ground reactions"),
            in_degrees: false,
            metadata: &metadata,
            time,
            labels: &labels,
            columns: &refs,
        },
    )?;
    if path.as_os_str() == "-" {
        return Ok(ExternalLoadsXml::None(
            "the table went to standard output: give -o NAME.mot to have NAME.xml written beside \
             it"
            .into(),
        ));
    }
    let datafile = path
        .file_name()
        .map_or_else(|| "grf.mot".into(), |n| n.to_string_lossy().into_owned());
    let prefixes: Vec<String> = g.feet.iter().map(|f| prefix(f)).collect();
    let loads: Vec<(&str, &str)> = prefixes
        .iter()
        .zip(&g.bodies)
        .map(|(p, &b)| (p.as_str(), segment_name(take, b)))
        .collect();
    let xml = opensim::external_loads_xml("externalloads", &datafile, &loads);
    let xml_path = path.with_extension("xml");
    crate::io::write_atomic(&xml_path, xml.as_bytes())?;
    Ok(ExternalLoadsXml::Written(xml_path))
}

/// The BVH joint whose segment body `b` is: the euler model names its bodies
/// `<joint>.<channel>`, one per channel, the ball model `<joint>`.
fn segment_name(take: &Take, b: usize) -> &str {
    let body = take.model.body_names[b].as_str();
    take.bvh
        .joints
        .iter()
        .map(|j| j.name.as_str())
        .filter(|j| {
            body == *j
                || body
                    .strip_prefix(j)
                    .is_some_and(|rest| rest.starts_with('.'))
        })
        .max_by_key(|j| j.len())
        .unwrap_or(body)
}

/// A foot's name as a column prefix: no spaces or tabs.
fn prefix(foot: &str) -> String {
    foot.replace(|c: char| c.is_whitespace(), "_")
}

/// The ground reactions' labels and columns in `format`'s names (module doc of [`export_grf`]).
fn grf_columns(g: &GroundReactions, format: TableFormat) -> (Vec<String>, Vec<Vec<f64>>) {
    let n = g.grf.len();
    let e_up = nalgebra::Vector3::ith(g.up, 1.0);
    let per_foot = |j: usize, what: usize| -> [Vec<f64>; 3] {
        let at = |k: usize| match what {
            0 => g.grf[k][j],
            1 => g.cop[k][j],
            _ => e_up * g.free_moment[k][j],
        };
        [0, 1, 2].map(|a| (0..n).map(|k| at(k)[a]).collect())
    };
    let mut labels = vec![];
    let mut columns = vec![];
    for (j, foot) in g.feet.iter().enumerate() {
        let names = match format {
            TableFormat::Sto => opensim::external_load_labels(&prefix(foot)),
            TableFormat::Csv => ["grf", "cop", "moment"]
                .iter()
                .flat_map(|w| ["x", "y", "z"].map(|a| format!("{w}:{foot}:{a}")))
                .collect(),
        };
        labels.extend(names);
        for what in 0..3 {
            columns.extend(per_foot(j, what));
        }
    }
    (labels, columns)
}

/// `articula export trc`: every joint's world position (`export positions`) as a marker, in
/// `units` (declared in the header); `Frame#` and time are the file's.
pub fn export_trc(take: &Take, path: &Path, units: TrcUnits) -> Result<(), Error> {
    let c = joint_centres(take);
    let b = &take.bvh;
    let name = match path.file_name() {
        Some(n) if path.as_os_str() != "-" => n.to_string_lossy().into_owned(),
        _ => "markers.trc".into(),
    };
    opensim::write_trc(
        path,
        &Trc {
            name: &name,
            rate_hz: 1.0 / b.frame_time,
            units,
            first_frame: b.first_frame + 1,
            orig_frames: b.first_frame + b.frames,
            time: &c.time,
            markers: &c.names,
            positions: &c.positions,
        },
    )
}

/// Every `export WHAT`: its name and whether it writes a table (`--format` applies).
pub const EXPORTS: &[(&str, bool)] = &[
    ("positions", true),
    ("urdf", false),
    ("mjcf", false),
    ("states", true),
    ("grf", true),
    ("trc", false),
    ("gltf", false),
];

/// What an export wrote besides its output: `export grf`'s ExternalLoads XML, or why none.
pub type ExportExtras = Option<ExternalLoadsXml>;

/// `articula export WHAT` of a loaded take (the command line and the Python module): the
/// table format by `format` or the output's extension, `trc_units` for `export trc`. Flags
/// that do not apply to `what` are refused, never ignored.
pub fn export(
    take: &mut Take,
    what: &str,
    path: &Path,
    format: Option<&str>,
    trc_units: Option<&str>,
) -> Result<ExportExtras, Error> {
    let Some(&(_, table)) = EXPORTS.iter().find(|(w, _)| *w == what) else {
        let known: Vec<&str> = EXPORTS.iter().map(|(w, _)| *w).collect();
        return Err(Error::Invalid(format!(
            "export {what}: expected one of {}",
            known.join(", ")
        )));
    };
    if format.is_some() && !table {
        return Err(Error::Invalid(format!(
            "--format has no effect on `articula export {what}`; remove it"
        )));
    }
    if trc_units.is_some() && what != "trc" {
        return Err(Error::Invalid(
            "--trc-units is for `articula export trc`; remove it".into(),
        ));
    }
    let format = TableFormat::choose(path, format)?;
    if format != TableFormat::Csv && what == "positions" {
        return Err(Error::Invalid(
            "positions as OpenSim data are markers: use `articula export trc`, or write \
             positions as CSV"
                .into(),
        ));
    }
    match what {
        "positions" => super::export_positions(take, path)?,
        "urdf" => super::export_urdf(take, path)?,
        "mjcf" => super::export_mjcf(take, path)?,
        "gltf" => super::export_gltf(take, path)?,
        "states" => export_states_as(take, path, format)?,
        "grf" => {
            super::resolve_contact(take);
            let xml = export_grf(take, path, format)?;
            return Ok(Some(xml));
        }
        _ => {
            let units = match trc_units {
                Some(u) => u.parse()?,
                None => TrcUnits::Mm,
            };
            export_trc(take, path, units)?
        }
    }
    Ok(None)
}
