//! The clinical gait view: sagittal hip, knee and ankle moments per body mass (N·m/kg) over
//! the gait cycle, left and right together, as a gait laboratory reports them.
//!
//! - **Cycles** run from a foot's strike (its contact phase begins: the frame where the foot
//!   lands after a swing) to the same foot's next strike; stance ends at the first frame of
//!   the cycle where the foot is off the ground. A cycle is kept when it lies within the
//!   frames the take quotes at its ends ([`Anatomy::reported`]: the smoothing cannot estimate
//!   accelerations near the ends) and has a toe-off.
//! - **Time normalisation**: each cycle's moment is sampled at 0, 1, …, 100 % of its duration by
//!   linear interpolation; the chart draws the mean over cycles and a band of ± one standard
//!   deviation (sample SD, `n − 1`; none with one cycle), and shades stance (0 % to the mean
//!   toe-off of both sides).
//! - **Signs** are the anatomy's (Winter 2009, `dynamics::anatomy`): internal extensor moments
//!   positive (ankle: plantarflexor).
//! - **Normative band**: Schwartz, Rozumalski & Trost 2008 (typically developing children at
//!   five speed classes), the bundled table `data/normative/schwartz2008_moments.toml` (its
//!   header cites the source), chosen by the take's dimensionless walking speed
//!   `v / sqrt(g · leg)` (Hof 1996): the class with the nearest mean speed, when the take's
//!   lies within the speeds of all the study's subjects; none outside them, and a note says so.
//!
//! A side with fewer than two foot strikes has no cycle: it is left out with a note; with no
//! cycle on either side the report is an error, never an empty chart.

use crate::error::Error;
use crate::pipeline::anatomy::Anatomy;
use crate::report::chart::{Band, ImageFormat, Panel, Series, stacked_chart};

/// The bundled normative table.
pub const NORMATIVE: &str = include_str!("../../data/normative/schwartz2008_moments.toml");

/// Standard gravity (m/s²), for the dimensionless speed.
const G: f64 = 9.80665;

/// Hip (greater trochanter) height as a fraction of stature (Winter 2009, *Biomechanics and
/// Motor Control of Human Movement*, fig. 4.1): the leg length of the dimensionless speed.
pub const LEG_OF_STATURE: f64 = 0.530;

/// One normative curve: a joint's moment band at one speed class.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct NormBand {
    /// Speed class (`VerySlow`, `Slow`, `Free`, `Fast`, `VeryFast`).
    pub class: String,
    /// The class's dimensionless speed: mean, smallest and largest subject's.
    pub speed: [f64; 3],
    /// `hip`, `knee` or `ankle`.
    pub joint: String,
    /// % of the gait cycle.
    pub percent: Vec<f64>,
    /// The band's edges (N·m/kg).
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
}

#[derive(serde::Deserialize)]
#[serde(deny_unknown_fields)]
struct NormFile {
    band: Vec<NormBand>,
}

/// The bundled normative bands.
pub fn normative_bands() -> Result<Vec<NormBand>, Error> {
    let f: NormFile = toml::from_str(NORMATIVE)
        .map_err(|e| Error::Invalid(format!("data/normative/schwartz2008_moments.toml: {e}")))?;
    Ok(f.band)
}

/// The speed class of dimensionless speed `s`: the class with the nearest mean speed, when
/// `s` lies within the speeds of all the classes' subjects (slowest to fastest); `None`
/// outside them.
pub fn speed_class(bands: &[NormBand], s: f64) -> Option<&str> {
    let lo = bands
        .iter()
        .map(|b| b.speed[1])
        .fold(f64::INFINITY, f64::min);
    let hi = bands
        .iter()
        .map(|b| b.speed[2])
        .fold(f64::NEG_INFINITY, f64::max);
    if !(lo..=hi).contains(&s) {
        return None;
    }
    bands
        .iter()
        .min_by(|a, b| (a.speed[0] - s).abs().total_cmp(&(b.speed[0] - s).abs()))
        .map(|b| b.class.as_str())
}

/// One side's cycles of one joint: mean and SD per 1 % of the cycle.
#[derive(Debug, Clone, PartialEq)]
pub struct JointCycles {
    /// `hip`, `knee`, `ankle`.
    pub joint: String,
    /// 101 values, 0…100 % (N·m/kg).
    pub mean: Vec<f64>,
    /// Sample SD at each %; zeros for one cycle.
    pub sd: Vec<f64>,
}

/// One side over its gait cycles.
#[derive(Debug, Clone, PartialEq)]
pub struct SideCycles {
    /// `left` or `right`.
    pub side: String,
    pub cycles: usize,
    /// Mean toe-off (% of the cycle).
    pub stance_pct: f64,
    pub joints: Vec<JointCycles>,
}

/// The joints drawn, in order, with their anatomical name and sign convention.
const JOINTS: [(&str, &str); 3] = [
    ("hip", "Hip extensor (+) / flexor (−) moment"),
    ("knee", "Knee extensor (+) / flexor (−) moment"),
    ("ankle", "Ankle plantarflexor (+) / dorsiflexor (−) moment"),
];

/// `y` at time `t` by linear interpolation over `time` (increasing) between frames `a..=b`.
fn interp(time: &[f64], y: &[f64], a: usize, b: usize, t: f64) -> f64 {
    let k = (a..b)
        .find(|&k| time[k + 1] >= t)
        .unwrap_or(b.saturating_sub(1).max(a));
    if k >= b {
        return y[b];
    }
    let span = time[k + 1] - time[k];
    let f = if span > 0.0 {
        (t - time[k]) / span
    } else {
        0.0
    };
    y[k] + f * (y[k + 1] - y[k])
}

/// Mean and sample SD of each column of `rows` (all the same length).
fn mean_sd(rows: &[Vec<f64>]) -> (Vec<f64>, Vec<f64>) {
    let n = rows.len() as f64;
    let len = rows.first().map_or(0, Vec::len);
    let mean: Vec<f64> = (0..len)
        .map(|i| rows.iter().map(|r| r[i]).sum::<f64>() / n)
        .collect();
    let sd = (0..len)
        .map(|i| {
            if rows.len() < 2 {
                return 0.0;
            }
            let ss: f64 = rows.iter().map(|r| (r[i] - mean[i]).powi(2)).sum();
            (ss / (n - 1.0)).sqrt()
        })
        .collect();
    (mean, sd)
}

/// The cycles of one side (`foot` `left`/`right`, suffix `_l`/`_r`), or a note saying why
/// it has none.
pub fn side_cycles(a: &Anatomy, foot: &str, on: &[bool]) -> Result<SideCycles, String> {
    let suffix = if foot == "left" { "_l" } else { "_r" };
    let strikes: Vec<usize> = (1..on.len()).filter(|&k| on[k] && !on[k - 1]).collect();
    if strikes.len() < 2 {
        return Err(format!(
            "{foot} foot: {} foot strike(s) in the take; a gait cycle needs two (strike to the \
             next strike of the same foot): the {foot} side is not drawn",
            strikes.len()
        ));
    }
    let reported = a.reported();
    let mut cycles: Vec<(usize, usize, f64)> = vec![];
    for w in strikes.windows(2) {
        let (s0, s1) = (w[0], w[1]);
        if !reported.contains(&s0) || !reported.contains(&s1) {
            continue;
        }
        let Some(off) = (s0..s1).find(|&k| !on[k]) else {
            continue;
        };
        let (t0, t1) = (a.time[s0], a.time[s1]);
        cycles.push((s0, s1, 100.0 * (a.time[off] - t0) / (t1 - t0)));
    }
    if cycles.is_empty() {
        return Err(format!(
            "{foot} foot: {} foot strikes but no whole cycle with a toe-off inside the frames \
             the take quotes: the {foot} side is not drawn",
            strikes.len()
        ));
    }
    let mut joints = vec![];
    for (joint, _) in JOINTS {
        let Some(m) = a.column(&format!("{joint}{suffix}:flexion:moment_per_kg")) else {
            continue;
        };
        let rows: Vec<Vec<f64>> = cycles
            .iter()
            .map(|&(s0, s1, _)| {
                let (t0, t1) = (a.time[s0], a.time[s1]);
                (0..=100)
                    .map(|p| interp(&a.time, m, s0, s1, t0 + (t1 - t0) * p as f64 / 100.0))
                    .collect()
            })
            .collect();
        let (mean, sd) = mean_sd(&rows);
        joints.push(JointCycles {
            joint: joint.into(),
            mean,
            sd,
        });
    }
    Ok(SideCycles {
        side: foot.into(),
        cycles: cycles.len(),
        stance_pct: cycles.iter().map(|c| c.2).sum::<f64>() / cycles.len() as f64,
        joints,
    })
}

/// The take's dimensionless walking speed `v / sqrt(g · leg)`: `speed_m_s` the root's mean
/// horizontal speed, leg [`LEG_OF_STATURE`] of `stature_m`.
pub fn dimensionless_speed(speed_m_s: f64, stature_m: f64) -> f64 {
    speed_m_s / (G * LEG_OF_STATURE * stature_m).sqrt()
}

/// What the gait chart is drawn from besides the anatomy.
#[derive(Debug, Clone, Default)]
pub struct GaitContext<'a> {
    /// The take's dimensionless walking speed; `None`: unknown (no band).
    pub dimensionless_speed: Option<f64>,
    /// The caption (the figure's context), if any.
    pub caption: Option<&'a str>,
}

/// The gait chart of `a` (one panel per joint the anatomy has: hip, knee, ankle) and notes: per
/// side drawn its cycles and stance (`left: 3 cycles, stance 61 %`), then what was left out and
/// why; an error when neither side has a cycle.
pub fn gait_chart(
    a: &Anatomy,
    ctx: &GaitContext<'_>,
    format: ImageFormat,
) -> Result<(Vec<u8>, Vec<String>), Error> {
    let mut notes = vec![];
    let mut sides = vec![];
    for (foot, on) in &a.contact {
        match side_cycles(a, foot, on) {
            Ok(s) => sides.push(s),
            Err(n) => notes.push(n),
        }
    }
    if a.contact.is_empty() {
        notes.push(
            "no foot contact: the take has no contact phases (set contact feet; the gait \
             view needs a walking take whose feet touch a floor)"
                .into(),
        );
    }
    for (k, s) in sides.iter().enumerate() {
        notes.insert(
            k,
            format!(
                "{}: {} cycles, stance {:.0} %",
                s.side, s.cycles, s.stance_pct
            ),
        );
    }
    if sides.is_empty() {
        return Err(Error::Invalid(format!(
            "gait report: no gait cycle on either side: {}",
            notes.join("; ")
        )));
    }
    // the normative band of the take's speed class
    let bands = normative_bands()?;
    let class = ctx.dimensionless_speed.and_then(|s| speed_class(&bands, s));
    let norm_label = match (ctx.dimensionless_speed, class) {
        (Some(_), Some(c)) => format!("Schwartz 2008 {c}"),
        (Some(s), None) => {
            notes.push(format!(
                "dimensionless speed {s:.2} lies outside Schwartz et al.'s speed classes: no \
                 normative band"
            ));
            String::new()
        }
        (None, _) => String::new(),
    };
    let pct: Vec<f64> = (0..=100).map(f64::from).collect();
    let stance = sides.iter().map(|s| s.stance_pct).sum::<f64>() / sides.len() as f64;
    let stance_label = format!(
        "stance {}",
        sides
            .iter()
            .map(|s| format!("{}{:.0}%", &s.side[..1].to_uppercase(), s.stance_pct))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let mut panels_data = vec![];
    for (joint, title) in JOINTS {
        let mut series = vec![];
        let mut sd_bands = vec![];
        for (k, s) in sides.iter().enumerate() {
            let Some(j) = s.joints.iter().find(|j| j.joint == joint) else {
                continue;
            };
            series.push(Series::new(
                format!("{} ({} cycles)", s.side, s.cycles),
                pct.clone(),
                j.mean.clone(),
            ));
            sd_bands.push(Band {
                label: String::new(),
                x: pct.clone(),
                lo: j.mean.iter().zip(&j.sd).map(|(m, d)| m - d).collect(),
                hi: j.mean.iter().zip(&j.sd).map(|(m, d)| m + d).collect(),
                color: Some(k),
            });
        }
        if series.is_empty() {
            continue;
        }
        if let Some(c) = class
            && let Some(b) = bands.iter().find(|b| b.class == c && b.joint == joint)
        {
            sd_bands.insert(
                0,
                Band {
                    label: norm_label.clone(),
                    x: b.percent.clone(),
                    lo: b.lower.clone(),
                    hi: b.upper.clone(),
                    color: None,
                },
            );
        }
        panels_data.push((title, series, sd_bands));
    }
    let shaded = [(0.0, stance)];
    let panels: Vec<Panel<'_>> = panels_data
        .iter()
        .map(|(title, series, bands)| Panel {
            title,
            x_label: "gait cycle (%)",
            y_label: "moment (N·m/kg), mean ± SD",
            series,
            mark_min_max: false,
            shaded: &shaded,
            shaded_label: &stance_label,
            bands,
        })
        .collect();
    // the caption says the speed the band was matched to
    let caption = match (ctx.caption, ctx.dimensionless_speed) {
        (Some(c), Some(s)) => Some(format!("{c} · walking speed v/√(g·leg) {s:.2}")),
        (c, _) => c.map(str::to_string),
    };
    let bytes = stacked_chart(&panels, None, caption.as_deref(), format)?;
    Ok((bytes, notes))
}

/// The mean horizontal speed (m/s) of a BVH take's root: the length of its horizontal path
/// (the axes other than `up`, scaled to metres) sampled every [`SPEED_STEP_S`] (so the
/// side-to-side sway of each step does not count, and a walk round a circle still does), over
/// the duration; `None` without root position channels or duration.
pub fn root_speed(bvh: &crate::io::bvh::Bvh, up: usize, scale_to_m: f64) -> Option<f64> {
    let root = bvh.joints.first()?;
    let cols = root.position_columns();
    let n = bvh.frames;
    if n < 2 || bvh.frame_time <= 0.0 {
        return None;
    }
    let at = |k: usize| -> Option<[f64; 2]> {
        let mut p = [0.0; 2];
        for (i, axis) in (0..3).filter(|&i| i != up).enumerate() {
            p[i] = bvh.frame(k)[root.first_channel + cols[axis]?] * scale_to_m;
        }
        Some(p)
    };
    let step = ((SPEED_STEP_S / bvh.frame_time).round() as usize).max(1);
    let mut frames: Vec<usize> = (0..n).step_by(step).collect();
    if frames.last() != Some(&(n - 1)) {
        frames.push(n - 1);
    }
    let mut path = 0.0;
    for w in frames.windows(2) {
        let (a, b) = (at(w[0])?, at(w[1])?);
        path += (b[0] - a[0]).hypot(b[1] - a[1]);
    }
    let duration = bvh.time(n - 1) - bvh.time(0);
    (duration > 0.0).then(|| path / duration)
}

/// The sampling of the root's path for [`root_speed`] (s): about half a step.
pub const SPEED_STEP_S: f64 = 0.25;

/// A caption for a take loaded by the pipeline (the CLI's): take file, body, joint model,
/// smoothing, contact and, with contact, whether residuals were reduced and the residual
/// figures against Hicks et al.'s thresholds (`consistency`, issue 14: the moments are read
/// with them).
pub fn take_caption(
    take: &crate::pipeline::Take,
    reduced: bool,
    consistency: Option<&crate::pipeline::consistency::Consistency>,
) -> String {
    let o = &take.options;
    let file = take.path.file_name().map_or_else(
        || take.path.display().to_string(),
        |f| f.to_string_lossy().into(),
    );
    let mut parts = vec![
        ("take", file),
        (
            "body",
            format!(
                "{} kg, {:.2} m, {}",
                o.body.mass_kg, take.stature_m, o.body.sex
            ),
        ),
        ("joints", o.joints.to_string()),
        ("smoothing", take.smooth.to_string()),
        ("contact", o.contact.to_string()),
    ];
    if o.contact == crate::pipeline::Contact::Feet {
        let r = if reduced { "on" } else { "off" };
        parts.push(("residual reduction", r.into()));
        parts.extend(consistency.map(|c| c.caption_parts()).unwrap_or_default());
    }
    crate::report::chart::caption(&parts)
}

/// Writes the gait view of `a` (computed from `take`) to `path` (`.svg` or `.png`)
/// atomically, the dimensionless speed from the take's root; returns the notes on what it
/// left out.
pub fn write_gait(
    a: &Anatomy,
    take: &crate::pipeline::Take,
    caption: Option<&str>,
    path: &std::path::Path,
) -> Result<Vec<String>, Error> {
    let format = ImageFormat::of_path(path).ok_or_else(|| {
        Error::Invalid(format!(
            "{}: the gait view is written as .svg or .png",
            path.display()
        ))
    })?;
    let speed = root_speed(&take.bvh, take.up.index(), take.scale_to_m)
        .map(|v| dimensionless_speed(v, take.stature_m));
    let ctx = GaitContext {
        dimensionless_speed: speed,
        caption,
    };
    let (bytes, notes) = gait_chart(a, &ctx, format)?;
    crate::io::write_atomic(path, &bytes)?;
    Ok(notes)
}
