//! What the views, exports and `expect` read from results: a coordinate's angle and torque
//! series, its joint, its mirror, statistics, the selection's chart and the results' CSV.

use super::super::SessionError;
use super::super::command::Statistic;
use super::super::engine::{Analysis, Table};
use super::err;
use crate::model::{JointKind, Model};
use crate::report::chart::{ImageFormat, Panel, Series, stacked_chart};
use std::fmt::Write as _;
use std::path::Path;

/// The image format of a chart path: PNG for `.png`, SVG for anything else.
pub(super) fn image_format(p: &Path) -> ImageFormat {
    ImageFormat::of_path(p).unwrap_or(ImageFormat::Svg)
}

/// True for a `.csv` path (anything else is written as SVG).
pub(super) fn is_csv(p: &Path) -> bool {
    p.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"))
}

/// The paper's figure 4 for one coordinate: its angle (deg) or position (m) and its torque
/// over time, minimum and maximum marked.
pub fn selection_svg(r: &Analysis, coord: &str) -> Result<String, SessionError> {
    let bytes = selection_chart(r, coord, None, ImageFormat::Svg)?;
    String::from_utf8(bytes).map_err(|e| err(format!("chart: SVG is not UTF-8: {e}")))
}

/// [`selection_svg`] as SVG or PNG bytes, with `caption` (the figure's context) under it.
pub fn selection_chart(
    r: &Analysis,
    coord: &str,
    caption: Option<&str>,
    format: ImageFormat,
) -> Result<Vec<u8>, SessionError> {
    let (Some(q), Some(tau)) = (angle_series(r, coord), torque_series(r, coord)) else {
        return Err(err(format!("no coordinate '{coord}' in the model")));
    };
    let rotation = r.model.v_index(coord).is_none_or(|k| r.model.is_angular(k));
    let (factor, angle_label, torque_label) = if rotation {
        (180.0 / std::f64::consts::PI, "angle (deg)", "torque (N·m)")
    } else {
        (1.0, "position (m)", "force (N)")
    };
    let angle = [Series::new(
        coord,
        r.time.clone(),
        q.iter().map(|x| x * factor).collect(),
    )];
    let torque = [Series::new(coord, r.time.clone(), tau)];
    // the frames whose forces are not quoted (edge frames, residuals beyond the feet)
    let half = r
        .time
        .get(1)
        .zip(r.time.first())
        .map_or(0.0, |(b, a)| (b - a) / 2.0);
    let shaded: Vec<(f64, f64)> = r
        .left_out_runs()
        .iter()
        .map(|&(a, b, _)| (r.time[a] - half, r.time[b] + half))
        .collect();
    let title_a = format!("{coord} {}", angle_label.split(' ').next().unwrap_or(""));
    let title_t = format!("{coord} {}", torque_label.split(' ').next().unwrap_or(""));
    let panels = [
        Panel {
            title: &title_a,
            x_label: "time (s)",
            y_label: angle_label,
            series: &angle,
            mark_min_max: true,
            shaded: &[],
            shaded_label: "",
            bands: &[],
        },
        Panel {
            title: &title_t,
            x_label: "time (s)",
            y_label: torque_label,
            series: &torque,
            mark_min_max: true,
            shaded: &shaded,
            shaded_label: "not quoted (edge/feet)",
            bands: &[],
        },
    ];
    Ok(stacked_chart(&panels, None, caption, format)?)
}

/// A statistic over a series (0 for an empty one).
pub fn statistic(stat: Statistic, x: &[f64]) -> f64 {
    if x.is_empty() {
        return 0.0;
    }
    let n = x.len() as f64;
    match stat {
        Statistic::Peak => x.iter().fold(0.0, |m, v| m.max(v.abs())),
        Statistic::Min => x.iter().copied().fold(f64::INFINITY, f64::min),
        Statistic::Max => x.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        Statistic::Mean => x.iter().sum::<f64>() / n,
        Statistic::Rms => (x.iter().map(|v| v * v).sum::<f64>() / n).sqrt(),
        Statistic::Now => x[0],
    }
}

/// The BVH (or robot) joint that velocity coordinate `k` belongs to: the joint name of its
/// body, without the `.Xrotation` of an euler-model channel body.
pub(super) fn joint_of(model: &Model, k: usize) -> &str {
    let name = model.joint_names[model.body_of_v(k)].as_str();
    match name.rsplit_once('.') {
        Some((j, c)) if crate::io::bvh::Channel::ALL.iter().any(|ch| ch.name() == c) => j,
        _ => name,
    }
}

/// The joint of a selection in results `r`: the BVH joint at an anatomical joint's centre
/// (`knee_l:flexion` → `LeftLeg`), the joint of a coordinate of the model.
pub(super) fn joint_of_selection(r: &Analysis, sel: &str) -> Option<String> {
    if is_anatomical(r, sel) {
        let joint = sel.split(':').next()?;
        return r
            .anatomy_joints
            .iter()
            .find(|(a, _)| a == joint)
            .map(|(_, j)| j.clone());
    }
    joint_of_name(&r.model, sel)
}

/// The joint of a coordinate name, if the model has that coordinate.
pub(super) fn joint_of_name(model: &Model, coord: &str) -> Option<String> {
    model.v_index(coord).map(|k| joint_of(model, k).to_string())
}

/// The velocity coordinates of `joint` (a BVH joint or a robot joint), in model order.
pub fn coords_of_joint(model: &Model, joint: &str) -> Vec<String> {
    (0..model.nv)
        .filter(|&k| joint_of(model, k) == joint)
        .map(|k| model.v_names[k].clone())
        .collect()
}

/// The angle (rad) or position (m) of velocity coordinate `coord` over the take: the q column
/// of a 1-DoF joint; for a ball joint (and the rotation of a free joint) the component of the
/// rotation vector `θ·u = log(q)` in the joint frame named by the coordinate (`J:wx` → x), whose
/// derivative is the angular velocity `J:wx` for rotations about a fixed axis; for the
/// translation of a free joint (`J:vx`) its position `J:x` in the parent frame.
pub fn angle_series(r: &Analysis, coord: &str) -> Option<Vec<f64>> {
    if let Some(j) = r.anatomy.col_index(&format!("{coord}:angle"))
        && r.q.col_index(coord).is_none()
    {
        return Some(r.anatomy.column(j));
    }
    q_series(&r.model, &r.q, coord)
}

/// [`angle_series`] of a simulation's reference (the configurations it tracked).
pub fn reference_series(sim: &Analysis, coord: &str) -> Option<Vec<f64>> {
    (sim.reference.rows() > 0)
        .then(|| q_series(&sim.model, &sim.reference, coord))
        .flatten()
}

/// The coordinate of simulation `sim` that selection `sel` shows: `sel` itself, or for an
/// anatomical axis (of results `r`) its joint's coordinate of largest range of motion.
pub fn simulated_coord(r: &Analysis, sim: &Analysis, sel: &str) -> Option<String> {
    if sim.model.v_index(sel).is_some() {
        return Some(sel.to_string());
    }
    let joint = joint_of_selection(r, sel)?;
    best_coordinate(sim, &joint)
}

/// The angle (rad) or position (m) of `coord` in configurations `q` of `m` (see
/// [`angle_series`]).
fn q_series(m: &Model, q: &Table, coord: &str) -> Option<Vec<f64>> {
    if let Some(j) = q.col_index(coord) {
        return Some(q.column(j));
    }
    let k = m.v_index(coord)?;
    let b = m.body_of_v(k);
    let (iq, off) = (m.idx_q[b], k - m.idx_v[b]);
    let quat_at = match m.joints[b] {
        JointKind::Spherical => iq,
        JointKind::Free if off < 3 => {
            return Some((0..q.rows()).map(|f| q.row(f)[iq + off]).collect());
        }
        JointKind::Free => iq + 3,
        _ => return None,
    };
    let c = if matches!(m.joints[b], JointKind::Free) {
        off - 3
    } else {
        off
    };
    Some(
        (0..q.rows())
            .map(|f| {
                let q = crate::spatial::quat_from_xyzw(&q.row(f)[quat_at..quat_at + 4]);
                q.scaled_axis()[c]
            })
            .collect(),
    )
}

/// The rotation coordinate of `joint` with the largest range of motion (max − min of
/// [`angle_series`]) over the take; `None` when the model has no coordinate of that joint.
pub fn best_coordinate(r: &Analysis, joint: &str) -> Option<String> {
    let coords = coords_of_joint(&r.model, joint);
    let range = |c: &String| {
        angle_series(r, c).map_or(0.0, |x| {
            let hi = x.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let lo = x.iter().copied().fold(f64::INFINITY, f64::min);
            hi - lo
        })
    };
    let rotations: Vec<&String> = coords
        .iter()
        .filter(|c| r.model.v_index(c).is_some_and(|k| r.model.is_angular(k)))
        .collect();
    let pool = if rotations.is_empty() {
        coords.iter().collect()
    } else {
        rotations
    };
    // the first of equal ranges wins (deterministic)
    pool.into_iter()
        .fold(None::<(&String, f64)>, |best, c| {
            let x = range(c);
            match best {
                Some((_, b)) if b >= x => best,
                _ => Some((c, x)),
            }
        })
        .map(|(c, _)| c.clone())
}

/// Before any result: `J.CHANNEL` checked against the BVH joint's channels, or for a bare
/// joint its rotation channel with the largest range over the take; named as the joint model
/// names it (`J.Xrotation` euler, `J:wx` ball).
pub(super) fn channel_by_range(
    bvh: &crate::io::bvh::Bvh,
    name: &str,
    joints: crate::model::bvh::JointModel,
) -> Result<String, SessionError> {
    let (joint, channel) = match bvh.joint_index(name) {
        Some(_) => (name, ""),
        None => name.rsplit_once('.').unwrap_or((name, "")),
    };
    let j = bvh
        .joint_index(joint)
        .ok_or_else(|| err(format!("no joint called '{joint}'")))?;
    let bj = &bvh.joints[j];
    let chans = &bj.channels;
    let range = |i: usize| {
        let col = bj.first_channel + i;
        let x = (0..bvh.frames).map(|f| bvh.frame(f)[col]);
        let hi = x.clone().fold(f64::NEG_INFINITY, f64::max);
        let lo = x.fold(f64::INFINITY, f64::min);
        hi - lo
    };
    let ch = if channel.is_empty() {
        let rot = (0..chans.len()).filter(|&i| chans[i].is_rotation());
        rot.fold(None::<(usize, f64)>, |best, i| match best {
            Some((_, b)) if b >= range(i) => best,
            _ => Some((i, range(i))),
        })
        .map(|(i, _)| i)
        .or((!chans.is_empty()).then_some(0))
    } else {
        chans.iter().position(|c| c.name() == channel)
    };
    let Some(i) = ch else {
        return Err(err(format!(
            "{joint} has no channel '{channel}' (it has {})",
            chans
                .iter()
                .map(|c| c.name())
                .collect::<Vec<_>>()
                .join(", ")
        )));
    };
    let c = chans[i].name();
    Ok(match joints {
        crate::model::bvh::JointModel::Euler => format!("{joint}.{c}"),
        _ => {
            let axis = c[..1].to_ascii_lowercase();
            let kind = if chans[i].is_rotation() { "w" } else { "v" };
            format!("{joint}:{kind}{axis}")
        }
    })
}

/// `time`, then `q:<coord>` (rad, m), `v:` (rad/s, m/s), `a:` (rad/s², m/s²) and `tau:`
/// (N·m, N) per coordinate; shortest round-trip decimal formatting, so replays are
/// byte-identical.
pub fn results_csv(r: &Analysis) -> String {
    let mut text = String::from("time");
    for (prefix, t) in [("q", &*r.q), ("v", &*r.v), ("a", &*r.a), ("tau", &r.tau)] {
        for n in &t.names {
            let _ = write!(text, ",{prefix}:{n}");
        }
    }
    text.push('\n');
    for (k, time) in r.time.iter().enumerate() {
        let _ = write!(text, "{time}");
        for t in [&r.q, &r.v, &r.a, &r.tau] {
            for x in t.row(k) {
                let _ = write!(text, ",{x}");
            }
        }
        text.push('\n');
    }
    text
}

/// The generalized force of coordinate `coord` (N·m, N), or the net moment about an
/// anatomical axis (`knee_l:flexion`, N·m, signed as `pipeline::anatomy` signs it).
pub fn torque_series(r: &Analysis, coord: &str) -> Option<Vec<f64>> {
    if let Some(j) = r.tau.col_index(coord) {
        return Some(r.tau.column(j));
    }
    let j = r.anatomy.col_index(&format!("{coord}:moment"))?;
    Some(r.anatomy.column(j))
}

/// The selected coordinate's mirror in the results, whose angle is known: the same name with
/// left and right swapped in the joint's name, as exporters write them (`knee_l` / `knee_r`,
/// `LeftLeg` / `RightLeg`, `lThigh` / `rThigh`, `Foot_L` / `Foot_R`, `thigh.L` / `thigh.R`,
/// `mHipLeft` / `mHipRight`, `L_Knee` / `R_Knee`). `None` when no swap names a coordinate.
pub fn mirror_coord(r: &Analysis, coord: &str) -> Option<String> {
    mirror_names(coord)
        .into_iter()
        .find(|m| m != coord && angle_series(r, m).is_some())
}

/// The names `coord` may have on the other side: each way of writing left and right swapped.
pub fn mirror_names(coord: &str) -> Vec<String> {
    // the joint's part: before the coordinate's separator (`.` before a channel, `:` before an
    // anatomical axis); a name's own `.L` / `.R` stays in the joint part
    let (joint, rest) = match coord.rfind([':', '.']) {
        Some(i) if !matches!(&coord[i..], ".L" | ".R" | ".l" | ".r") => coord.split_at(i),
        _ => (coord, ""),
    };
    const PAIRS: [(&str, &str); 12] = [
        ("Left", "Right"),
        ("left", "right"),
        ("LEFT", "RIGHT"),
        ("_l", "_r"),
        ("_L", "_R"),
        (".L", ".R"),
        (".l", ".r"),
        ("L_", "R_"),
        ("l_", "r_"),
        ("Lf", "Rt"),
        ("l", "r"),
        ("L", "R"),
    ];
    let mut out = vec![];
    for (a, b) in PAIRS {
        for (from, to) in [(a, b), (b, a)] {
            // a one-letter side is a prefix (`lThigh`, `LHipJoint`), the others anywhere
            let swapped = if from.len() == 1 {
                joint
                    .strip_prefix(from)
                    .filter(|t| t.starts_with(|c: char| c.is_uppercase()))
                    .map(|t| format!("{to}{t}"))
            } else if joint.contains(from) {
                Some(joint.replacen(from, to, 1))
            } else {
                None
            };
            if let Some(j) = swapped {
                out.push(format!("{j}{rest}"));
            }
        }
    }
    out
}

/// Whether `coord` is an anatomical axis of the results (`knee_l:flexion`).
pub fn is_anatomical(r: &Analysis, coord: &str) -> bool {
    r.anatomy.col_index(&format!("{coord}:angle")).is_some()
}

/// The anatomical axis a name means: `knee_l` → `knee_l:flexion`, `knee_l:adduction` as it is.
pub(super) fn anatomical_axis(r: &Analysis, name: &str) -> Option<String> {
    [name.to_string(), format!("{name}:flexion")]
        .into_iter()
        .find(|c| is_anatomical(r, c))
}
