//! What the terminal says of an [`Anatomy`]: each joint's range, and each knee's figures over
//! the gait cycles (a stride: foot strike, stance, toe-off, swing, the next strike).

use super::Anatomy;

/// One knee over the gait cycles of a take (medians over its strides).
#[derive(Debug, Clone, PartialEq)]
pub struct KneeCycles {
    /// `knee_l`, `knee_r`.
    pub knee: String,
    /// Foot strikes followed by a whole stance and swing before the next.
    pub strides: usize,
    /// Largest flexion in swing (deg).
    pub swing_flexion_deg: f64,
    /// The loading-response peak as the gait literature reports it (Kadaba et al. 1989; Schwartz
    /// et al. 2008): the largest internal extensor moment over the first half of stance
    /// (N·m/kg), of the frames [`Anatomy::quoted`] keeps. Its normative peak lies at 12–15 %
    /// of the gait cycle (Winter 2009), about a fifth of stance, just where the estimated load
    /// reaches the leading foot at the end of the double support: a window of a fifth of
    /// stance, four frames at 30 fps, caught the Bandai walk's knees before it. `None`: no
    /// stride has a quoted frame there (all beyond Hicks et al.'s thresholds or at the take's
    /// ends), so there is nothing to quote.
    pub loading_extensor_nm_kg: Option<f64>,
    /// Knee flexion at that moment's peak (deg); `None` with the moment.
    pub loading_flexion_deg: Option<f64>,
}

/// The gait-cycle figures of each knee from its foot's contact phases (a stride: foot strike,
/// stance, toe-off, swing, the next strike); empty without contact or a whole stride.
pub fn knee_cycles(a: &Anatomy) -> Vec<KneeCycles> {
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied()
    };
    let mut out = vec![];
    for (foot, on) in &a.contact {
        let knee = if foot == "left" { "knee_l" } else { "knee_r" };
        let (Some(flex), Some(moment)) = (
            a.column(&format!("{knee}:flexion:angle")),
            a.column(&format!("{knee}:flexion:moment_per_kg")),
        ) else {
            continue;
        };
        let strikes: Vec<usize> = (1..on.len()).filter(|&k| on[k] && !on[k - 1]).collect();
        let (mut swing, mut load, mut load_flex) = (vec![], vec![], vec![]);
        for w in strikes.windows(2) {
            let (s0, s1) = (w[0], w[1]);
            let Some(off) = (s0..s1).find(|&k| !on[k]) else {
                continue;
            };
            swing.push(
                flex[off..s1]
                    .iter()
                    .copied()
                    .fold(f64::NEG_INFINITY, f64::max),
            );
            let end = s0 + ((off - s0) / 2).max(1);
            let Some(k) = (s0..end)
                .filter(|&k| a.quoted(k))
                .max_by(|&x, &y| moment[x].total_cmp(&moment[y]))
            else {
                continue;
            };
            load.push(moment[k]);
            load_flex.push(flex[k]);
        }
        if swing.is_empty() {
            continue;
        }
        out.push(KneeCycles {
            knee: knee.into(),
            strides: swing.len(),
            swing_flexion_deg: median(swing).unwrap_or(f64::NAN),
            loading_extensor_nm_kg: median(load),
            loading_flexion_deg: median(load_flex),
        });
    }
    out
}

/// A few lines for the terminal: per joint, the flexion range (deg) and the largest extensor
/// and flexor moments (N·m/kg) over the take's [`reported`](Anatomy::reported) frames, the
/// moments without the frames beyond Hicks et al.'s thresholds (issue 14: frames where the
/// needed force is beyond what the feet can give are never quoted as peaks).
pub fn summary(a: &Anatomy) -> String {
    let mut out = a
        .consistency
        .as_ref()
        .map_or(String::new(), |c| format!("{}\n", c.headline()));
    out += &format!(
        "{:<12} {:>22} {:>30}\n",
        "joint", "flexion min..max (deg)", "flexion moment min..max (N·m/kg)"
    );
    let reported = a.reported();
    // moments are never quoted where the motion needs a force the feet cannot give (beyond
    // Hicks et al.'s thresholds after residual reduction)
    let beyond = |k: usize| a.beyond(k);
    let range = |c: &[f64], skip_beyond: bool| {
        reported
            .clone()
            .filter(|&k| !(skip_beyond && beyond(k)))
            .map(|k| c[k])
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                (lo.min(x), hi.max(x))
            })
    };
    for name in a.names.iter().filter(|n| n.ends_with(":flexion:angle")) {
        let joint = name.trim_end_matches(":flexion:angle");
        let (lo, hi) = range(a.column(name).unwrap_or(&[]), false);
        let m = a
            .column(&format!("{joint}:flexion:moment_per_kg"))
            .map(|c| match range(c, true) {
                (l, h) if l <= h => format!("{l:.2}..{h:.2}"),
                _ => "- (every frame beyond)".into(),
            })
            .unwrap_or_else(|| "-".into());
        out += &format!("{joint:<12} {:>22} {m:>30}\n", format!("{lo:.1}..{hi:.1}"));
    }
    let n = a.time.len();
    let left_out = reported.clone().filter(|&k| beyond(k)).count();
    if left_out > 0 {
        out += &format!(
            "(moment ranges leave out the {left_out} frames where the residuals stay beyond \
             Hicks et al.'s thresholds: the motion needs a force the feet cannot give there; \
             CSV column `residual:beyond`)\n"
        );
    }
    if reported.len() < n {
        let dt = if n > 1 {
            (a.time[n - 1] - a.time[0]) / (n - 1) as f64
        } else {
            0.0
        };
        out += &format!(
            "(ranges leave out the {} frames ({:.2} s) at each end of the take, whose \
             accelerations the smoothing cannot estimate (CSV column `edge`); --edges include \
             keeps them)\n",
            a.edge,
            a.edge as f64 * dt
        );
    }
    for c in knee_cycles(a) {
        let loading = match (c.loading_extensor_nm_kg, c.loading_flexion_deg) {
            (Some(m), Some(f)) => format!("{m:.2} N·m/kg at {f:.1}° flexion"),
            _ => "not quoted (no stride's early stance has a frame within Hicks et al.'s \
                  thresholds and away from the take's ends)"
                .into(),
        };
        out += &format!(
            "{}: {} strides (medians): swing flexion peak {:.1}°, loading-response extensor \
             moment {loading} ({:.0} kg body)\n",
            c.knee, c.strides, c.swing_flexion_deg, a.mass_kg
        );
    }
    if let Some(c) = &a.consistency {
        out += &c.text();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A knee over three cycles of 20 frames (stance 0–9, swing 10–19: one whole stride from
    /// the strike at 20 to the next at 40), its moment peaking early in stance; `edge` frames at
    /// each end not reported.
    fn strides(edge: usize) -> Anatomy {
        let n = 60;
        let on: Vec<bool> = (0..n).map(|k| k % 20 < 10).collect();
        let phase = |k: usize| (k % 20) as f64 / 20.0;
        let flex = (0..n).map(|k| 10.0 + 50.0 * phase(k)).collect();
        let moment = (0..n)
            .map(|k| if k % 20 == 2 { 0.8 } else { 0.1 })
            .collect();
        Anatomy {
            time: (0..n).map(|k| k as f64 / 30.0).collect(),
            names: vec![
                "knee_l:flexion:angle".into(),
                "knee_l:flexion:moment_per_kg".into(),
            ],
            columns: vec![flex, moment],
            mass_kg: 75.0,
            notes: vec![],
            contact: vec![("left".into(), on)],
            consistency: None,
            edge,
            include_edges: false,
        }
    }

    #[test]
    fn the_loading_response_is_the_early_stance_peak() {
        let c = &knee_cycles(&strides(1))[0];
        assert_eq!(c.strides, 1);
        assert_eq!(c.loading_extensor_nm_kg, Some(0.8));
        assert_eq!(c.loading_flexion_deg, Some(15.0));
        assert!(summary(&strides(1)).contains("moment 0.80 N·m/kg at 15.0° flexion"));
    }

    /// Before, a take with no quoted early-stance frame printed "NaN N·m/kg at NaN° flexion"
    /// (the Rokoko dance jesse_dance, every such frame beyond Hicks et al.'s thresholds).
    #[test]
    fn no_quoted_early_stance_frame_says_so_and_prints_no_nan() {
        let a = strides(26);
        let c = &knee_cycles(&a)[0];
        assert_eq!(c.loading_extensor_nm_kg, None);
        let text = summary(&a);
        assert!(!text.contains("NaN"), "{text}");
        assert!(
            text.contains("loading-response extensor moment not quoted"),
            "{text}"
        );
    }
}
