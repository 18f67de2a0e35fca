//! Knee-load comparison across body weights (the paper's figure 5): the same take re-run at
//! several body masses, one torque curve per mass, with a legend (`"60 kg"`, …) and a table of
//! the peak and RMS torque per mass.
//!
//! The input is plain data (a time series of one joint's torque per body mass), so this module
//! does not depend on how the torques were computed. Statistics are over the whole time series:
//! - only the samples a run quotes count ([`MassRun::quoted`]: the edge frames and those
//!   beyond what the feet can give are not, issue 14; the chart shades them);
//! - peak `|τ|` = `max_i |τ_i|` and the time of its first occurrence;
//! - RMS `τ` = `sqrt( (1/T) ∫ τ² dt )` by the trapezoid rule over the samples (the usual
//!   duty-cycle RMS of motor sizing, independent of the sampling rate), with `T = t_last −
//!   t_first`; a single sample gives `|τ_0|`.

use crate::error::Error;
use crate::io::shortest::plain;
use crate::report::chart::{ImageFormat, Panel, Series, Table, fmt_value, stacked_chart};

/// One joint's torque over time for one body mass.
#[derive(Debug, Clone, PartialEq)]
pub struct MassRun {
    /// Total body mass the take was run at (kg).
    pub mass_kg: f64,
    /// Sample times (s), non-decreasing.
    pub t: Vec<f64>,
    /// Joint torque at each sample (N·m).
    pub tau: Vec<f64>,
    /// Per sample, whether its torque is quoted (issue 14: the edge frames and the frames
    /// beyond what the feet can give are not); empty: every sample is. The peak and RMS are of
    /// the quoted samples, the chart shades the others.
    pub quoted: Vec<bool>,
    /// The take's consistency at this mass (issue 14: the moments are read with it): the peak
    /// residual force as % of the peak external force and the RMS residual moment as % of
    /// COM height × peak external force, against Hicks et al.'s 5 % and 1 %
    /// (`pipeline::consistency`); `None` without ground contact. The chart's table gives them.
    pub residual_pct: Option<(f64, f64)>,
}

impl MassRun {
    /// Whether sample `i` is quoted.
    pub fn is_quoted(&self, i: usize) -> bool {
        self.quoted.get(i).is_none_or(|q| *q)
    }
}

/// Peak and RMS torque of one [`MassRun`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoadRow {
    /// Total body mass (kg).
    pub mass_kg: f64,
    /// `max |τ|` (N·m).
    pub peak_nm: f64,
    /// Time-weighted RMS of τ (N·m), see the module documentation.
    pub rms_nm: f64,
    /// Time of the first sample where `|τ|` reaches its peak (s).
    pub peak_time_s: f64,
}

/// The legend label of a mass: `"60 kg"`, `"62.5 kg"`.
pub fn mass_label(mass_kg: f64) -> String {
    format!("{} kg", plain(mass_kg))
}

/// Checks a time series: same lengths, at least one sample, finite values, time non-decreasing.
/// `what` names the series in messages.
pub(crate) fn check_series(what: &str, t: &[f64], ys: &[(&str, &[f64])]) -> Result<(), Error> {
    if t.is_empty() {
        return Err(Error::Invalid(format!("{what}: no samples")));
    }
    for (name, y) in ys {
        if y.len() != t.len() {
            return Err(Error::Invalid(format!(
                "{what}: {} times but {} {name} values",
                t.len(),
                y.len()
            )));
        }
        if let Some(i) = y.iter().position(|v| !v.is_finite()) {
            return Err(Error::Invalid(format!(
                "{what}: {name} at sample {i} is {}; every value must be finite",
                y[i]
            )));
        }
    }
    if let Some(i) = t.iter().position(|v| !v.is_finite()) {
        return Err(Error::Invalid(format!(
            "{what}: time at sample {i} is {}",
            t[i]
        )));
    }
    if let Some(i) = t.windows(2).position(|w| w[1] < w[0]) {
        return Err(Error::Invalid(format!(
            "{what}: time goes back at sample {} ({} s after {} s)",
            i + 1,
            t[i + 1],
            t[i]
        )));
    }
    Ok(())
}

/// `max |y|` and the index of its first occurrence (non-empty `y`).
pub(crate) fn peak_abs(y: &[f64]) -> (f64, usize) {
    let mut best = (y[0].abs(), 0);
    for (i, v) in y.iter().enumerate() {
        if v.abs() > best.0 {
            best = (v.abs(), i);
        }
    }
    best
}

/// `sqrt((1/T) ∫ y² dt)` by the trapezoid rule; `|y_0|` when the samples span no time.
pub(crate) fn rms(t: &[f64], y: &[f64]) -> f64 {
    let span = t[t.len() - 1] - t[0];
    if span <= 0.0 {
        // all samples at one instant: plain RMS of the values
        return (y.iter().map(|v| v * v).sum::<f64>() / y.len() as f64).sqrt();
    }
    let integral: f64 = t
        .windows(2)
        .zip(y.windows(2))
        .map(|(t, y)| 0.5 * (t[1] - t[0]) * (y[0] * y[0] + y[1] * y[1]))
        .sum();
    (integral / span).sqrt()
}

/// Peak and RMS torque of one run.
pub fn load_row(run: &MassRun) -> Result<LoadRow, Error> {
    if !(run.mass_kg.is_finite() && run.mass_kg > 0.0) {
        return Err(Error::Invalid(format!(
            "knee load: body mass {} kg must be a positive number",
            run.mass_kg
        )));
    }
    check_series(
        &format!("knee load at {}", mass_label(run.mass_kg)),
        &run.t,
        &[("torque", &run.tau)],
    )?;
    if run.quoted.len() > run.t.len() || !(0..run.t.len()).any(|i| run.is_quoted(i)) {
        return Err(Error::Invalid(format!(
            "knee load at {}: {} flags for {} samples, or every sample left out of the \
             quoted figures",
            mass_label(run.mass_kg),
            run.quoted.len(),
            run.t.len()
        )));
    }
    if run.quoted.is_empty() {
        let (peak_nm, i) = peak_abs(&run.tau);
        return Ok(LoadRow {
            mass_kg: run.mass_kg,
            peak_nm,
            rms_nm: rms(&run.t, &run.tau),
            peak_time_s: run.t[i],
        });
    }
    // the quoted samples only: the peak among them, the RMS over the intervals between two
    // quoted samples (the plain RMS of their values when no such interval spans time)
    let kept: Vec<usize> = (0..run.t.len()).filter(|&i| run.is_quoted(i)).collect();
    let i = kept.iter().copied().fold(kept[0], |b, i| {
        if run.tau[i].abs() > run.tau[b].abs() {
            i
        } else {
            b
        }
    });
    let (mut integral, mut span) = (0.0, 0.0);
    for w in kept.windows(2).filter(|w| w[1] == w[0] + 1) {
        let (a, b) = (w[0], w[1]);
        let dt = run.t[b] - run.t[a];
        integral += 0.5 * dt * (run.tau[a].powi(2) + run.tau[b].powi(2));
        span += dt;
    }
    let rms_nm = if span > 0.0 {
        (integral / span).sqrt()
    } else {
        (kept.iter().map(|&k| run.tau[k].powi(2)).sum::<f64>() / kept.len() as f64).sqrt()
    };
    Ok(LoadRow {
        mass_kg: run.mass_kg,
        peak_nm: run.tau[i].abs(),
        rms_nm,
        peak_time_s: run.t[i],
    })
}

/// One [`LoadRow`] per run, in the order given.
pub fn load_table(runs: &[MassRun]) -> Result<Vec<LoadRow>, Error> {
    runs.iter().map(load_row).collect()
}

/// The table as CSV: `mass_kg,peak_abs_tau_Nm,rms_tau_Nm,peak_time_s`, numbers shortest
/// round-trip ([`crate::io::shortest`]).
pub fn load_table_csv(rows: &[LoadRow]) -> String {
    let mut out = String::from("mass_kg,peak_abs_tau_Nm,rms_tau_Nm,peak_time_s\n");
    let mut b = crate::io::shortest::Shortest::new();
    for r in rows {
        for (k, v) in [r.mass_kg, r.peak_nm, r.rms_nm, r.peak_time_s]
            .iter()
            .enumerate()
        {
            if k > 0 {
                out.push(',');
            }
            out.push_str(b.format(*v));
        }
        out.push('\n');
    }
    out
}

/// The torque curves of coordinate `coord` as CSV: `time` then one `<kind>:<coord>:<mass>kg`
/// column per run (`report::columns`): `kind` is `tau` for a model coordinate (N·m or N, the
/// coordinate's), `moment` for an anatomical axis (`knee_l:flexion`, N·m). The runs must share
/// their sample times (the same take re-run), else an error.
pub fn curves_csv(kind: &str, coord: &str, runs: &[MassRun]) -> Result<String, Error> {
    let series = to_series(runs);
    let named: Vec<Series> = series
        .into_iter()
        .zip(runs)
        .map(|(s, r)| Series {
            label: crate::report::columns::name(kind, &[coord, &format!("{}kg", plain(r.mass_kg))]),
            ..s
        })
        .collect();
    crate::report::chart::series_csv("time", &named)
}

fn to_series(runs: &[MassRun]) -> Vec<Series> {
    runs.iter()
        .map(|r| Series::new(mass_label(r.mass_kg), r.t.clone(), r.tau.clone()))
        .collect()
}

fn panel_title(joint: &str) -> String {
    format!("{joint} torque across body masses")
}

/// The comparison chart: one curve of `joint`'s torque per run, legend `"60 kg"`, …, the peak
/// of each marked.
pub fn knee_svg(joint: &str, runs: &[MassRun]) -> Result<String, Error> {
    load_table(runs)?;
    utf8(knee_chart_impl(joint, runs, None, None, ImageFormat::Svg)?)
}

/// [`knee_svg`] with the table of [`load_table`] drawn as text under the chart.
pub fn knee_svg_with_table(joint: &str, runs: &[MassRun]) -> Result<String, Error> {
    utf8(knee_chart(joint, runs, None, ImageFormat::Svg)?)
}

fn utf8(bytes: Vec<u8>) -> Result<String, Error> {
    String::from_utf8(bytes).map_err(|e| Error::Invalid(format!("chart: SVG is not UTF-8: {e}")))
}

/// [`knee_svg_with_table`] as SVG or PNG bytes, with `caption` (the figure's context) under it.
pub fn knee_chart(
    joint: &str,
    runs: &[MassRun],
    caption: Option<&str>,
    format: ImageFormat,
) -> Result<Vec<u8>, Error> {
    let rows = load_table(runs)?;
    let mut header = ["mass (kg)", "peak |τ| (N·m)", "RMS τ (N·m)", "peak at (s)"]
        .map(String::from)
        .to_vec();
    // with contact, each mass's residual figures against Hicks et al.'s thresholds
    let residuals = runs.iter().any(|r| r.residual_pct.is_some());
    if residuals {
        header.push("residual force (% ≤ 5)".into());
        header.push("residual moment (% ≤ 1)".into());
    }
    let table = Table {
        header,
        rows: rows
            .iter()
            .zip(runs)
            .map(|(r, run)| {
                let mut row = vec![
                    plain(r.mass_kg),
                    fmt_value(r.peak_nm),
                    fmt_value(r.rms_nm),
                    fmt_value(r.peak_time_s),
                ];
                if residuals {
                    let (f, m) = run.residual_pct.map_or(("-".into(), "-".into()), |(f, m)| {
                        (format!("{f:.1}"), format!("{m:.2}"))
                    });
                    row.extend([f, m]);
                }
                row
            })
            .collect(),
    };
    knee_chart_impl(joint, runs, Some(&table), caption, format)
}

fn knee_chart_impl(
    joint: &str,
    runs: &[MassRun],
    table: Option<&Table>,
    caption: Option<&str>,
    format: ImageFormat,
) -> Result<Vec<u8>, Error> {
    if runs.is_empty() {
        return Err(Error::Invalid("knee load: no body mass to compare".into()));
    }
    let series = to_series(runs);
    let title = panel_title(joint);
    // the samples any run leaves out, shaded (half a sample beyond each, so one shows)
    let t = &runs[0].t;
    let half = t.get(1).map_or(0.0, |t1| (t1 - t[0]) / 2.0);
    let mut shaded: Vec<(f64, f64)> = vec![];
    for (i, &ti) in t.iter().enumerate() {
        if runs.iter().all(|r| r.is_quoted(i)) {
            continue;
        }
        match shaded.last_mut() {
            Some(s) if i > 0 && !runs.iter().all(|r| r.is_quoted(i - 1)) => s.1 = ti + half,
            _ => shaded.push((ti - half, ti + half)),
        }
    }
    stacked_chart(
        &[Panel {
            title: &title,
            x_label: "time (s)",
            y_label: "joint torque (N·m)",
            series: &series,
            mark_min_max: true,
            shaded: &shaded,
            shaded_label: "not quoted (edge/feet)",
            bands: &[],
        }],
        table,
        caption,
        format,
    )
}
