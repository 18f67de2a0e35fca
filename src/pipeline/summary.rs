//! What the commands report besides their files: the sidecar of every CSV they write
//! ([`crate::report::sidecar`]) and the `--json` summaries of `id`, `info`, `export`, `smooth`
//! and `blend`, as serde-derived structs (keys documented in docs/formats.md).

use super::{Job, Take, Torques};
use crate::dynamics::grf::{GroundQuality, GroundReactions};
use crate::error::Error;
use crate::model::Model;
use crate::report::columns;
use crate::report::sidecar::{self, Sidecar};
use serde::Serialize;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Who wrote a CSV, from what and how: the sidecar's content besides the columns.
#[derive(Debug, Clone, Copy)]
pub struct Provenance<'a> {
    /// The command (`id`, `export states`, a session's `export csv`).
    pub command: &'a str,
    /// Its arguments as given (the command line after the program's name, or the session's
    /// command line).
    pub arguments: &'a [String],
    /// The take it was computed from, if any.
    pub take: Option<&'a Take>,
    /// The model whose coordinates the columns name (the take's, or a robot's).
    pub model: Option<&'a Model>,
    /// Notes beyond the take's own.
    pub notes: &'a [String],
    /// `(column, unit)` of the columns a summary's `peak:<column>` / `rms:<column>` names that
    /// neither the scheme nor the model settles (a batch's, read from its outputs' sidecars).
    pub known_units: &'a [(String, String)],
    /// With ground contact, the take's consistency the columns were computed with (issue 14:
    /// the moments carry the residual figures against the thresholds).
    pub consistency: Option<&'a super::consistency::Consistency>,
}

/// A take's resolved settings as text, for sidecars.
pub fn take_settings(take: &Take) -> BTreeMap<String, String> {
    let o = &take.options;
    let mut s: BTreeMap<String, String> = [
        ("unit", take.unit.clone()),
        ("scale_to_m", take.scale_to_m.to_string()),
        ("stature_m", take.stature_m.to_string()),
        ("up", take.up.to_string()),
        ("positions", o.positions.to_string()),
        ("joints", o.joints.to_string()),
        ("mass_kg", o.body.mass_kg.to_string()),
        ("sex", o.body.sex.to_string()),
        ("segments", o.body.segments.to_string()),
        ("smooth", take.smooth.to_string()),
        ("contact", o.contact.to_string()),
        ("keep_first_frame", o.keep_first_frame.to_string()),
        ("joint_translations", o.joint_translations.to_string()),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect();
    if !o.lock.is_empty() {
        s.insert("lock".into(), o.lock.join(","));
    }
    if let Some(t) = &o.subtree {
        s.insert("subtree".into(), t.clone());
    }
    for (joint, kg) in &o.body.link_mass {
        s.insert(format!("link_mass:{joint}"), kg.to_string());
    }
    s
}

/// Writes the sidecar of the CSV just written at `csv` (its header read back, so the sidecar
/// describes the file as it is); nothing for standard output or a device. Returns its path.
pub fn write_sidecar(csv: &Path, p: &Provenance) -> Result<Option<PathBuf>, Error> {
    if sidecar::path_for(csv).is_none() {
        return Ok(None);
    }
    let header = sidecar::read_header(csv)?;
    let model = p.model.or(p.take.map(|t| &t.model));
    let mut notes: Vec<String> = p.take.map(|t| t.notes.clone()).unwrap_or_default();
    notes.extend(p.notes.iter().cloned());
    let s = Sidecar {
        file: csv
            .file_name()
            .map_or(String::new(), |f| f.to_string_lossy().into_owned()),
        articula_version: env!("CARGO_PKG_VERSION").into(),
        command: p.command.into(),
        arguments: p.arguments.to_vec(),
        take: p.take.map(|t| t.path.display().to_string()),
        settings: p.take.map(take_settings).unwrap_or_default(),
        columns: sidecar::describe(&header, model, p.known_units)?,
        notes,
        consistency: p.consistency.map(super::consistency::Consistency::json),
    };
    sidecar::write(csv, &s)
}

/// Peak |x|, the time of that peak, and RMS of one column.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ColumnStats {
    pub name: String,
    pub unit: String,
    pub peak_abs: f64,
    pub peak_time_s: f64,
    pub rms: f64,
    /// With estimated ground reactions: where the peak and RMS lie against the frames whose
    /// needed ground force the feet cannot give ([`OnFlagged`]); null otherwise.
    pub contact: Option<OnFlagged>,
}

impl ColumnStats {
    /// The figures of `x` (sampled at `time`) under `name` in `unit`.
    pub fn of(name: String, unit: &str, time: &[f64], x: &[f64]) -> Self {
        let (k, peak) = x.iter().enumerate().fold((0, 0.0f64), |(bk, b), (k, v)| {
            if v.abs() > b { (k, v.abs()) } else { (bk, b) }
        });
        let (_, rms) = super::table::peak_rms(x);
        Self {
            name,
            unit: unit.into(),
            peak_abs: peak,
            peak_time_s: time.get(k).copied().unwrap_or(0.0),
            rms,
            contact: None,
        }
    }

    /// [`of`](Self::of) with the figures against the `flagged` frames, when there are any to
    /// judge by (estimated ground reactions).
    fn of_flagged(
        name: String,
        unit: &str,
        time: &[f64],
        x: &[f64],
        flagged: Option<&[bool]>,
    ) -> Self {
        Self {
            contact: flagged.map(|f| OnFlagged::of(time, x, f)),
            ..Self::of(name, unit, time, x)
        }
    }
}

/// Where a column's figures lie against the frames whose needed ground force the feet cannot
/// give (estimated contact: [`GroundReactions::cop_gap`] beyond
/// [`COP_GAP_TOLERANCE`](crate::dynamics::grf::COP_GAP_TOLERANCE); there the torques are those
/// of the nearest force the feet can give).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct OnFlagged {
    /// Whether the frame of the column's peak |x| is flagged.
    pub peak_frame_flagged: bool,
    /// The share of the column's sum of squares (its RMS²) that flagged frames contribute.
    pub rms_share_flagged: f64,
    /// The peak |x| over the frames not flagged, and its time (s; null without such frames).
    pub peak_abs_unflagged: f64,
    pub peak_time_unflagged_s: Option<f64>,
}

impl OnFlagged {
    /// The figures of `x` (sampled at `time`) against `flagged` (per frame).
    pub fn of(time: &[f64], x: &[f64], flagged: &[bool]) -> Self {
        let is = |k: usize| flagged.get(k).copied().unwrap_or(false);
        let peak = x.iter().enumerate().fold((0, 0.0f64), |(bk, b), (k, v)| {
            if v.abs() > b { (k, v.abs()) } else { (bk, b) }
        });
        let unflagged = (x.iter().enumerate()).filter(|&(k, _)| !is(k)).fold(
            None,
            |best: Option<(usize, f64)>, (k, v)| match best {
                Some((_, b)) if b >= v.abs() => best,
                _ => Some((k, v.abs())),
            },
        );
        let total: f64 = x.iter().map(|v| v * v).sum();
        let on_flagged: f64 = (x.iter().enumerate())
            .filter(|&(k, _)| is(k))
            .map(|(_, v)| v * v)
            .sum();
        Self {
            peak_frame_flagged: !x.is_empty() && is(peak.0),
            rms_share_flagged: if total > 0.0 { on_flagged / total } else { 0.0 },
            peak_abs_unflagged: unflagged.map_or(0.0, |(_, v)| v),
            peak_time_unflagged_s: unflagged.and_then(|(k, _)| time.get(k).copied()),
        }
    }
}

/// How far the feet could give the ground force the motion needs
/// ([`GroundQuality`], over the single-support frames).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ContactQuality {
    /// Frames (of all, any support) whose needed ground force the feet cannot give: the
    /// frames [`OnFlagged`] judges each column's figures against.
    pub flagged_frames: usize,
    pub single_support_frames: usize,
    pub outside_frames: usize,
    pub outside_share: f64,
    pub median_gap_m: f64,
    pub largest_gap_m: f64,
    pub largest_gap_frame: usize,
}

impl From<&GroundQuality> for ContactQuality {
    fn from(q: &GroundQuality) -> Self {
        Self {
            flagged_frames: 0,
            single_support_frames: q.single_support_frames,
            outside_frames: q.outside_frames,
            outside_share: q.outside_share(),
            median_gap_m: q.median_gap,
            largest_gap_m: q.largest_gap,
            largest_gap_frame: q.largest_gap_frame,
        }
    }
}

/// `articula id --json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IdSummary {
    /// Frames (samples) computed.
    pub frames: usize,
    /// `estimated`, `measured` (`--grf`) or `none`.
    pub ground_reactions: String,
    /// `tau:<coord>` of every coordinate: peak |τ|, its time, RMS (N·m or N).
    pub coordinates: Vec<ColumnStats>,
    /// `residual:fx` … `residual:tz`: what the root still needs beyond the ground reactions
    /// (N, N·m); empty without ground contact (the root coordinates' τ then carry the body).
    pub root_residual: Vec<ColumnStats>,
    /// The estimate's quality (null for measured forces or without contact).
    pub contact_quality: Option<ContactQuality>,
    /// The consistency summary (`--contact feet`, estimated forces), else null.
    pub consistency: Option<serde_json::Value>,
    pub notes: Vec<String>,
}

/// The figures of an inverse-dynamics result `t` (with the ground reactions `grf` when the
/// take has contact; `measured` when they came from `--grf`).
pub fn id_summary(job: &Job, t: &Torques, grf: Option<&GroundReactions>) -> IdSummary {
    let m = &job.model;
    let column = |j: usize, rows: &[Vec<f64>]| -> Vec<f64> { rows.iter().map(|r| r[j]).collect() };
    // the frames whose needed ground force the feet cannot give (estimated forces only)
    let measured = job.measured.is_some();
    let flagged: Option<Vec<bool>> = grf.filter(|_| !measured).map(|g| {
        (g.cop_gap.iter())
            .map(|&gap| gap > crate::dynamics::grf::COP_GAP_TOLERANCE)
            .collect()
    });
    let flagged = flagged.as_deref();
    let coordinates = t
        .names
        .iter()
        .enumerate()
        .map(|(j, n)| {
            let unit = if m.is_angular(j) { "N*m" } else { "N" };
            ColumnStats::of_flagged(
                columns::name("tau", &[n]),
                unit,
                &t.time,
                &column(j, &t.tau),
                flagged,
            )
        })
        .collect();
    let residual_rows: Vec<Vec<f64>> =
        grf.map_or(vec![], |g| g.residual.iter().map(|r| r.to_vec()).collect());
    let root_residual = if residual_rows.is_empty() {
        vec![]
    } else {
        ["fx", "fy", "fz", "tx", "ty", "tz"]
            .iter()
            .enumerate()
            .map(|(j, c)| {
                let name = columns::name("residual", &[c]);
                let unit = columns::unit_of(&name, None).unwrap_or("");
                ColumnStats::of_flagged(name, unit, &t.time, &column(j, &residual_rows), flagged)
            })
            .collect()
    };
    IdSummary {
        frames: t.tau.len(),
        ground_reactions: match (grf.is_some(), measured) {
            (_, true) => "measured",
            (true, false) => "estimated",
            (false, false) => "none",
        }
        .into(),
        coordinates,
        root_residual,
        contact_quality: grf.filter(|_| !measured).map(|g| ContactQuality {
            flagged_frames: flagged.map_or(0, |f| f.iter().filter(|&&x| x).count()),
            ..ContactQuality::from(&g.quality())
        }),
        consistency: None,
        notes: job
            .take
            .as_ref()
            .map(|t| t.notes.clone())
            .unwrap_or_default(),
    }
}

/// `articula export … --json`, `smooth --json`, `blend --json`: what was written.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WriteSummary {
    /// The command (`export states`, `smooth`, `blend`).
    pub command: String,
    /// The inputs (takes).
    pub takes: Vec<String>,
    /// The files written, the main output first (`-`: standard output).
    pub written: Vec<String>,
    /// The table format (`csv`, `sto`, `mot`, `trc`), the file kind otherwise (`bvh`, `urdf`,
    /// `mjcf`).
    pub format: String,
    /// Frames of the motion written (null for a model: URDF, MJCF).
    pub frames: Option<usize>,
    /// Frame time (s) of the motion written.
    pub frame_time_s: Option<f64>,
    /// The settings the take was read with (as in the sidecars), empty for `blend`.
    pub settings: BTreeMap<String, String>,
    pub notes: Vec<String>,
}

impl WriteSummary {
    /// What `command` wrote from `take` (`written`: the output first) in `format`; `motion`:
    /// the output holds the take's frames (not a model).
    pub fn of_take(
        command: &str,
        take: &Take,
        format: &str,
        written: &[PathBuf],
        motion: bool,
    ) -> Self {
        Self {
            command: command.into(),
            takes: vec![take.path.display().to_string()],
            written: written.iter().map(|p| p.display().to_string()).collect(),
            format: format.into(),
            frames: motion.then_some(take.states.len()),
            frame_time_s: motion.then_some(take.bvh.frame_time),
            settings: take_settings(take),
            notes: take.notes.clone(),
        }
    }
}

/// One joint of a take, for `info --json`'s `skeleton`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JointInfo {
    pub name: String,
    /// The parent joint's name (null for the root).
    pub parent: Option<String>,
    /// The BVH channels, in file order (`Xposition`, `Zrotation` …).
    pub channels: Vec<String>,
    /// Rotation order (e.g. `ZXY`), null without rotation channels.
    pub rotation_order: Option<String>,
    /// Offset from the parent in the rest pose (m, the take's axes).
    pub offset_m: [f64; 3],
}

/// Every joint of `take`'s skeleton, in file order.
pub fn skeleton(take: &Take) -> Vec<JointInfo> {
    let b = &take.bvh;
    b.joints
        .iter()
        .map(|j| JointInfo {
            name: j.name.clone(),
            parent: j.parent.map(|p| b.joints[p].name.clone()),
            channels: j.channels.iter().map(|c| c.name().to_string()).collect(),
            rotation_order: j.euler_order().map(|o| o.to_string()),
            offset_m: [j.offset.x, j.offset.y, j.offset.z].map(|c| c * take.scale_to_m),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::OnFlagged;

    #[test]
    fn figures_against_flagged_frames() {
        let t = [0.0, 0.1, 0.2, 0.3];
        let x = [1.0, -3.0, 2.0, 0.0];
        // the peak (frame 1) flagged: the unflagged peak is frame 2's
        let f = OnFlagged::of(&t, &x, &[false, true, false, false]);
        assert!(f.peak_frame_flagged);
        assert_eq!(f.peak_abs_unflagged, 2.0);
        assert_eq!(f.peak_time_unflagged_s, Some(0.2));
        assert!((f.rms_share_flagged - 9.0 / 14.0).abs() < 1e-15);
        // nothing flagged: the column's own figures
        let f = OnFlagged::of(&t, &x, &[false; 4]);
        assert!(!f.peak_frame_flagged && f.rms_share_flagged == 0.0);
        assert_eq!(f.peak_abs_unflagged, 3.0);
        // everything flagged: no unflagged frame
        let f = OnFlagged::of(&t, &x, &[true; 4]);
        assert_eq!((f.rms_share_flagged, f.peak_time_unflagged_s), (1.0, None));
    }
}
