//! Measured ground reactions in (`articula id --grf FILE [--grf-offset S]`): an OpenSim
//! external-loads `.mot` / `.sto` (per foot `<foot>_ground_force_v[xyz]`,
//! `<foot>_ground_force_p[xyz]`, optional `<foot>_ground_torque_[xyz]`) or a CSV with
//! articula's own columns (`grf:<foot>:x|y|z`, `cop:<foot>:x|y|z`, optional
//! `moment:<foot>:x|y|z`), as `articula export grf` writes both; N, m, N·m in the take's world
//! axes. The loads are resampled to the take's frames by linear interpolation at the take's
//! time plus the offset (the file's time of the take's frame k is `t_k + offset`); outside
//! the file, no load. The free moment is the torque's vertical component. Feet are matched by
//! name (`left`, `right`) to the take's.

use super::{Job, Take, take_feet};
use crate::dynamics::grf::GroundReactions;
use crate::dynamics::grf::measured::{FootLoads, apply_ground_reactions};
use crate::error::Error;
use nalgebra::Vector3;
use std::path::Path;

/// A ground-reaction file as read: its times and, per foot, force, point and torque per sample.
#[derive(Debug, Clone)]
pub struct MeasuredGrf {
    /// Sample times (s, the file's clock).
    pub time: Vec<f64>,
    /// Foot names, the order of the per-foot vectors.
    pub feet: Vec<String>,
    /// `[foot][sample]` force (N), point (m), torque (N·m).
    pub force: Vec<Vec<Vector3<f64>>>,
    pub point: Vec<Vec<Vector3<f64>>>,
    pub torque: Vec<Vec<Vector3<f64>>>,
}

/// The column names of one foot's force, point and torque in each file kind: `(.mot, CSV)`
/// stems, `{}` the foot, then the axis.
const COLUMNS: [(&str, &str, bool); 3] = [
    ("{}_ground_force_v", "grf:{}:", true),
    ("{}_ground_force_p", "cop:{}:", true),
    ("{}_ground_torque_", "moment:{}:", false),
];

/// Reads `path`: `.mot` / `.sto` as OpenSim's table, anything else as CSV.
pub fn read_measured_grf(path: &Path) -> Result<MeasuredGrf, Error> {
    let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
    let opensim = ["mot", "sto"].iter().any(|e| e.eq_ignore_ascii_case(ext));
    let (labels, columns) = if opensim {
        parse_sto(path)?
    } else {
        crate::report::csv::read_columns(path)?
    };
    let col = |name: &str| labels.iter().position(|l| l == name).map(|i| &columns[i]);
    let time = col("time")
        .ok_or_else(|| Error::Invalid(format!("{}: no `time` column", path.display())))?
        .clone();
    // the feet: every name with a force's x column
    let feet: Vec<String> = labels
        .iter()
        .filter_map(|l| {
            if opensim {
                l.strip_suffix("_ground_force_vx").map(String::from)
            } else {
                l.strip_prefix("grf:")
                    .and_then(|r| r.strip_suffix(":x"))
                    .map(String::from)
            }
        })
        .collect();
    if feet.is_empty() {
        return Err(Error::Invalid(format!(
            "{}: no ground force columns (expected `<foot>_ground_force_vx` … in a .mot, \
             `grf:<foot>:x` … in a CSV, as `articula export grf` writes)",
            path.display()
        )));
    }
    let mut out = MeasuredGrf {
        time,
        feet: feet.clone(),
        force: vec![],
        point: vec![],
        torque: vec![],
    };
    for foot in &feet {
        for (w, (mot, csv, required)) in COLUMNS.iter().enumerate() {
            let stem = if opensim { mot } else { csv }.replace("{}", foot);
            let axes: Vec<Option<&Vec<f64>>> = ["x", "y", "z"]
                .iter()
                .map(|a| col(&format!("{stem}{a}")))
                .collect();
            let series: Vec<Vector3<f64>> = match axes[..] {
                [Some(x), Some(y), Some(z)] => (0..out.time.len())
                    .map(|k| Vector3::new(x[k], y[k], z[k]))
                    .collect(),
                _ if !required => vec![Vector3::zeros(); out.time.len()],
                _ => {
                    return Err(Error::Invalid(format!(
                        "{}: no columns {stem}x, {stem}y, {stem}z for foot {foot}",
                        path.display()
                    )));
                }
            };
            [&mut out.force, &mut out.point, &mut out.torque][w].push(series);
        }
    }
    if out.time.windows(2).any(|w| w[1] <= w[0]) {
        return Err(Error::Invalid(format!(
            "{}: times must increase from row to row",
            path.display()
        )));
    }
    Ok(out)
}

/// An OpenSim `.sto` / `.mot`: the labels (with `time`) and columns after `endheader`.
fn parse_sto(path: &Path) -> Result<(Vec<String>, Vec<Vec<f64>>), Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let mut lines = text.lines().enumerate();
    if !lines.by_ref().any(|(_, l)| l.trim() == "endheader") {
        return Err(Error::parse(path, 1, 1, "no `endheader` line"));
    }
    let Some((_, header)) = lines.next() else {
        return Err(Error::parse(
            path,
            1,
            1,
            "no column labels after `endheader`",
        ));
    };
    let labels: Vec<String> = header.split('\t').map(|l| l.trim().to_string()).collect();
    let mut columns = vec![Vec::new(); labels.len()];
    for (i, l) in lines.filter(|(_, l)| !l.trim().is_empty()) {
        let fields: Vec<&str> = l.split_whitespace().collect();
        if fields.len() != labels.len() {
            return Err(Error::parse(
                path,
                i + 1,
                1,
                format!("{} fields, expected {}", fields.len(), labels.len()),
            ));
        }
        for (c, f) in columns.iter_mut().zip(&fields) {
            c.push(
                f.parse()
                    .map_err(|_| Error::parse(path, i + 1, 1, format!("{f:?} is not a number")))?,
            );
        }
    }
    Ok((labels, columns))
}

/// `m`'s loads at the take's frames: linear interpolation at `t_k + offset_s`, none outside
/// the file.
fn resample(m: &MeasuredGrf, j: usize, t: f64) -> (Vector3<f64>, Vector3<f64>, Vector3<f64>) {
    let n = m.time.len();
    let eps = 1e-9;
    if n == 0 || t < m.time[0] - eps || t > m.time[n - 1] + eps {
        let p = if n == 0 {
            Vector3::zeros()
        } else {
            m.point[j][if t < m.time[0] { 0 } else { n - 1 }]
        };
        return (Vector3::zeros(), p, Vector3::zeros());
    }
    let i = m.time.partition_point(|&x| x <= t).clamp(1, n.max(2) - 1);
    if n == 1 {
        return (m.force[j][0], m.point[j][0], m.torque[j][0]);
    }
    let (t0, t1) = (m.time[i - 1], m.time[i]);
    let u = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
    let lerp = |s: &[Vector3<f64>]| s[i - 1] * (1.0 - u) + s[i] * u;
    (lerp(&m.force[j]), lerp(&m.point[j]), lerp(&m.torque[j]))
}

/// The ground reactions of `take` from the file `path` (its clock = the take's + `offset_s`):
/// the loads resampled to the take's frames and inverse dynamics with them.
pub fn measured_ground_reactions(
    take: &Take,
    path: &Path,
    offset_s: f64,
) -> Result<GroundReactions, Error> {
    let loads = measured_loads(take, path, offset_s)?;
    let s = &take.states;
    apply_ground_reactions(
        &take.model,
        &loads,
        &s.time,
        &s.q,
        &s.v,
        &s.a,
        take.up.index(),
    )
}

/// The loads of the file `path` on `take`'s feet, resampled to its frames (the file's clock
/// = the take's + `offset_s`).
pub fn measured_loads(take: &Take, path: &Path, offset_s: f64) -> Result<FootLoads, Error> {
    if !offset_s.is_finite() {
        return Err(Error::Invalid(format!(
            "--grf-offset {offset_s}: expected seconds"
        )));
    }
    let m = read_measured_grf(path)?;
    let feet = take_feet(take);
    let s = &take.states;
    let up = take.up.index();
    let e_up = Vector3::ith(up, 1.0);
    let mut loads = FootLoads {
        force: vec![vec![]; s.len()],
        cop: vec![vec![]; s.len()],
        free_moment: vec![vec![]; s.len()],
        ..Default::default()
    };
    for (j, name) in m.feet.iter().enumerate() {
        let foot = feet.iter().find(|f| f.name.eq_ignore_ascii_case(name)).ok_or_else(|| {
            let names: Vec<&str> = feet.iter().map(|f| f.name.as_str()).collect();
            Error::Invalid(format!(
                "{}: foot {name:?} is none of the take's feet ({}); name the columns after them",
                path.display(),
                names.join(", ")
            ))
        })?;
        loads.feet.push(foot.name.clone());
        loads.bodies.push(foot.ankle_body);
        for k in 0..s.len() {
            let (f, p, t) = resample(&m, j, s.time[k] + offset_s);
            loads.force[k].push(f);
            loads.cop[k].push(p);
            loads.free_moment[k].push(t.dot(&e_up));
        }
    }
    Ok(loads)
}

/// Makes `job` use the measured ground reactions of `path` (`articula id --grf`).
pub fn use_measured_grf(job: &mut Job, path: &Path, offset_s: f64) -> Result<(), Error> {
    let take = job.take.as_ref().ok_or_else(|| {
        Error::Invalid("--grf needs a take: ground reactions act on an avatar's feet".into())
    })?;
    job.measured = Some(measured_ground_reactions(take, path, offset_s)?);
    Ok(())
}
