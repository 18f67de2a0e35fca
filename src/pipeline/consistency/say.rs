//! The words of a take's consistency: the terminal table, the JSON, the one-line forms for
//! the workbench and the charts' captions, and the adjustments as text.

use super::{Adjustments, Consistency, FORCE_SHARE, MOMENT_SHARE, ResidualFigures, runs};

impl Adjustments {
    /// The adjustments as lines for the terminal (`mass_kg`: the body mass as loaded).
    fn text(&self, mass_kg: f64) -> String {
        let c = self.trunk_offset_m * 100.0;
        let mass = if self.measured {
            format!(
                "mass {:.1} → {:.1} kg ({:+.1} %, bound {:.0} %; the measured vertical forces \
                 against the motion's)",
                mass_kg,
                mass_kg + self.mass_change_kg,
                100.0 * self.mass_change_kg / mass_kg.max(1e-12),
                100.0 * self.bounds.mass_share
            )
        } else {
            format!(
                "mass {mass_kg:.1} kg, unchanged (the ground reactions are estimated from the \
                 motion: a mass change scales every force and moment alike)"
            )
        };
        let rotation = match self.rotation_peak_rms_rad {
            Some((peak, rms)) => format!(
                "pelvis rotation peak {:.1}°, RMS {:.1}° (bounds {:.0}°, {:.0}°)",
                peak.to_degrees(),
                rms.to_degrees(),
                self.bounds.rotation_peak_rad.to_degrees(),
                self.bounds.rotation_rms_rad.to_degrees()
            ),
            None => "pelvis rotation not adjusted (the root is neither a free joint nor three \
                     hinges about coordinate axes: --joints ball adjusts it)"
                .into(),
        };
        format!(
            "adjustments: {mass}; trunk mass centre ({:+.1}, {:+.1}, {:+.1}) cm = {:.1} cm (trunk \
             {:.1} kg, its frame; bound {:.0} cm); pelvis offset peak {:.1} cm, RMS {:.1} cm \
             (horizontal, knots every {:.2} s{}; bounds {:.0} cm, {:.0} cm); {rotation}{}; the \
             pelvis offset slides a foot in contact by up to {:.1} cm\n",
            c.x,
            c.y,
            c.z,
            c.norm(),
            self.trunk_mass_kg,
            100.0 * self.bounds.trunk_com_m,
            100.0 * self.pelvis_peak_m,
            100.0 * self.pelvis_rms_m,
            self.bounds.knot_spacing_s,
            self.refined_knot_spacing_s
                .map_or(String::new(), |h| format!(
                    ", refined every {h:.3} s within the estimator's spread of the foot changes"
                )),
            100.0 * self.bounds.pelvis_peak_m,
            100.0 * self.bounds.pelvis_rms_m,
            if self.bounded.is_empty() {
                String::new()
            } else {
                format!("; at the {} bound", self.bounded.join(" and "))
            },
            100.0 * self.stance_slide_m
        )
    }
}

impl Consistency {
    /// The table for the terminal: the residual figures before and after against Hicks et
    /// al.'s thresholds, the adjustments, and why the thresholds are missed.
    pub fn text(&self) -> String {
        let force =
            |f: &ResidualFigures| format!("{:.0} N ({:.1} %)", f.peak_force_n, f.force_pct());
        let moment =
            |f: &ResidualFigures| format!("{:.1} N·m ({:.2} %)", f.rms_moment_nm, f.moment_pct());
        let after = |g: &dyn Fn(&ResidualFigures) -> String| {
            self.after.as_ref().map_or("(not reduced)".into(), g)
        };
        let b = &self.before;
        let mut out = format!(
            "consistency (Hicks et al. 2015; {} frames, peak external force {:.0} N, COM height \
             {:.2} m)\n{:<28} {:>20} {:>20} {:>10}\n",
            b.frames,
            self.last().peak_external_n,
            self.last().com_height_m,
            "residual",
            "before",
            "after",
            "threshold"
        );
        out += &format!(
            "{:<28} {:>20} {:>20} {:>10}\n",
            "peak force (% peak ext.)",
            force(b),
            after(&force),
            format!("{:.0} %", 100.0 * FORCE_SHARE)
        );
        out += &format!(
            "{:<28} {:>20} {:>20} {:>10}\n",
            "RMS moment (% h × peak ext.)",
            moment(b),
            after(&moment),
            format!("{:.0} %", 100.0 * MOMENT_SHARE)
        );
        if let Some(a) = &self.adjustments {
            out += &a.text(self.mass_kg);
        }
        if self.last().meets() {
            out += "consistency: within Hicks et al.'s thresholds\n";
        } else {
            out += "consistency: beyond Hicks et al.'s thresholds; the joint moments carry the \
                    residual's error\n";
            for w in &self.why {
                out += &format!("  {w}\n");
            }
        }
        out
    }

    /// The same as JSON: `before`, `after` (figures), `adjustments`, `meets`, `why`,
    /// `frames_beyond`.
    pub fn json(&self) -> serde_json::Value {
        let fig = |f: &ResidualFigures| {
            serde_json::json!({
                "peak_external_force_n": f.peak_external_n,
                "peak_residual_force_n": f.peak_force_n,
                "peak_residual_force_frame": f.peak_force_frame,
                "peak_residual_force_pct": f.force_pct(),
                "rms_residual_moment_nm": f.rms_moment_nm,
                "rms_residual_moment_pct": f.moment_pct(),
                "com_height_m": f.com_height_m,
                "frames": f.frames,
                "meets": f.meets(),
            })
        };
        let adjustments = self.adjustments.as_ref().map(|a| {
            serde_json::json!({
                "mass_kg": self.mass_kg,
                "mass_change_kg": a.mass_change_kg,
                "ground_reactions": if a.measured { "measured" } else { "estimated" },
                "pelvis_rotation_peak_deg": a.rotation_peak_rms_rad.map(|r| r.0.to_degrees()),
                "pelvis_rotation_rms_deg": a.rotation_peak_rms_rad.map(|r| r.1.to_degrees()),
                "trunk_com_offset_m": a.trunk_offset_m.as_slice(),
                "trunk_mass_kg": a.trunk_mass_kg,
                "pelvis_offset_peak_m": a.pelvis_peak_m,
                "pelvis_offset_rms_m": a.pelvis_rms_m,
                "stance_slide_m": a.stance_slide_m,
                "refined_knot_spacing_s": a.refined_knot_spacing_s,
                "bounded_by": a.bounded,
                "bounds": {
                    "trunk_com_m": a.bounds.trunk_com_m,
                    "pelvis_peak_m": a.bounds.pelvis_peak_m,
                    "pelvis_rms_m": a.bounds.pelvis_rms_m,
                    "pelvis_rotation_peak_deg": a.bounds.rotation_peak_rad.to_degrees(),
                    "pelvis_rotation_rms_deg": a.bounds.rotation_rms_rad.to_degrees(),
                    "mass_share": a.bounds.mass_share,
                    "knot_spacing_s": a.bounds.knot_spacing_s,
                },
            })
        });
        serde_json::json!({
            "thresholds": { "peak_force_pct": 100.0 * FORCE_SHARE, "rms_moment_pct": 100.0 * MOMENT_SHARE },
            "before": fig(&self.before),
            "after": self.after.as_ref().map(fig),
            "adjustments": adjustments,
            "meets": self.last().meets(),
            "why": self.why,
            "frames_beyond": runs(&self.beyond),
            "floor_lost": self.floor_lost.iter().map(|l| serde_json::json!({
                "first": l.first,
                "last": l.last,
                "frames": l.frames(),
                "lowest_foot_m": [l.lowest_m.0, l.lowest_m.1, l.lowest_m.2],
                "needed_vertical_share": l.needed_share,
            })).collect::<Vec<_>>(),
        })
    }
}

impl Consistency {
    /// One line to read with every moment: the final figures against the thresholds.
    pub fn headline(&self) -> String {
        let f = self.last();
        format!(
            "consistency{}: residual force peak {:.1} % (≤ {:.0} %), residual moment RMS {:.2} % \
             (≤ {:.0} %): {}",
            if self.after.is_some() {
                " after residual reduction"
            } else {
                ""
            },
            f.force_pct(),
            100.0 * FORCE_SHARE,
            f.moment_pct(),
            100.0 * MOMENT_SHARE,
            if f.meets() {
                "within Hicks et al.'s thresholds"
            } else {
                "beyond Hicks et al.'s thresholds (see below)"
            }
        )
    }

    /// The final figures against the thresholds in one line, in forms from the longest to
    /// the shortest, for a view with room for one (the workbench takes the first that fits
    /// its width): the peak residual force as % of the peak external force, the RMS residual
    /// moment as % of COM height × peak external force, the verdict, and the figures before
    /// reduction when the take was reduced.
    pub fn figure_lines(&self) -> Vec<String> {
        let f = self.last();
        let (fs, ms) = (100.0 * FORCE_SHARE, 100.0 * MOMENT_SHARE);
        let verdict = if f.meets() { "within" } else { "beyond" };
        let (force, moment) = (pct(f.force_pct(), 1), pct(f.moment_pct(), 2));
        let b = &self.before;
        let (bf, bm) = (pct(b.force_pct(), 1), pct(b.moment_pct(), 2));
        let reduced = self.after.is_some();
        let short =
            format!("residual force {force} (≤{fs:.0} %), moment {moment} (≤{ms:.0} %): {verdict}");
        let (long, middle, tail) = if reduced {
            (
                format!("; before reduction: force {bf}, moment {bm}"),
                format!("; before {bf}, {bm}"),
                format!("; before {bf}, {bm}"),
            )
        } else {
            (String::new(), String::new(), "; not reduced".to_string())
        };
        let when = if reduced {
            "after reduction"
        } else {
            "not reduced"
        };
        vec![
            format!(
                "residuals {when}: peak force {force} of peak external (≤ {fs:.0} %), RMS \
                 moment {moment} of COM height × peak external (≤ {ms:.0} %): {verdict} Hicks \
                 et al. 2015{long}"
            ),
            format!(
                "residuals {when}: force {force} (≤ {fs:.0} %), moment {moment} (≤ {ms:.0} %): \
                 {verdict} Hicks et al.{middle}"
            ),
            format!("{short}{tail}"),
            format!(
                "residual force {force} (≤{fs:.0}), moment {moment} (≤{ms:.0}): {verdict}{tail}"
            ),
            short,
        ]
    }

    /// The final figures as a chart caption's parts (`report::chart::caption`, each shorter
    /// than a caption line): the figures against the thresholds, the verdict, and the figures
    /// before reduction when the take was reduced.
    pub fn caption_parts(&self) -> Vec<(&'static str, String)> {
        let f = self.last();
        let reduced = self.after.is_some();
        let mut parts = vec![
            (
                "residual force peak",
                format!(
                    "{} of peak external force (≤ {:.0} %)",
                    pct(f.force_pct(), 1),
                    100.0 * FORCE_SHARE
                ),
            ),
            (
                "residual moment RMS",
                format!(
                    "{} of COM height × peak external force (≤ {:.0} %)",
                    pct(f.moment_pct(), 2),
                    100.0 * MOMENT_SHARE
                ),
            ),
            (
                "consistency",
                format!(
                    "{} Hicks et al. 2015's thresholds{}",
                    if f.meets() { "within" } else { "beyond" },
                    if reduced {
                        " after residual reduction"
                    } else {
                        ", residuals not reduced"
                    }
                ),
            ),
        ];
        if reduced {
            let b = &self.before;
            parts.push((
                "before reduction",
                format!(
                    "force {}, moment {}",
                    pct(b.force_pct(), 1),
                    pct(b.moment_pct(), 2)
                ),
            ));
        }
        parts
    }
}

/// A percentage with `decimals`: `0.08 %`.
fn pct(x: f64, decimals: usize) -> String {
    format!("{x:.decimals$} %")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Figures over 100 frames against a peak external force of 1000 N and a COM 1 m high:
    /// `force_n` N is `force_n / 10` %, `moment_nm` N·m is `moment_nm / 10` %.
    fn figures(force_n: f64, moment_nm: f64) -> ResidualFigures {
        ResidualFigures {
            peak_external_n: 1000.0,
            peak_force_n: force_n,
            peak_force_frame: 0,
            rms_moment_nm: moment_nm,
            com_height_m: 1.0,
            frames: 100,
        }
    }

    fn consistency(before: ResidualFigures, after: Option<ResidualFigures>) -> Consistency {
        Consistency {
            before,
            after,
            adjustments: None,
            mass_kg: 75.0,
            force_n: vec![],
            moment_nm: vec![],
            counted: vec![],
            beyond: vec![],
            floor_lost: vec![],
            floor_lost_note: None,
            why: vec![],
        }
    }

    /// The one-line forms carry the final figures against the thresholds, longest first; with
    /// a take as far off as the inertial-suit walk (18.5 % and 10.5 % before
    /// reduction), a form with the figures before and after it still fits 80 columns.
    #[test]
    fn figure_lines_shorten_and_keep_before_and_after_within_80_columns() {
        let c = consistency(figures(185.0, 105.0), Some(figures(30.0, 15.0)));
        let lines = c.figure_lines();
        let len = |l: &String| l.chars().count();
        assert!(
            lines.windows(2).all(|w| len(&w[0]) >= len(&w[1])),
            "{lines:#?}"
        );
        for l in &lines {
            assert!(
                l.contains("force 3.0 %") && l.contains("moment 1.50 %") && l.contains("beyond"),
                "{l}"
            );
        }
        let fit = lines.iter().find(|l| len(l) <= 80).unwrap();
        assert!(fit.contains("before 18.5 %, 10.50 %"), "{fit}");
        let parts = c.caption_parts();
        assert_eq!(
            parts[..2],
            [
                (
                    "residual force peak",
                    "3.0 % of peak external force (≤ 5 %)".into()
                ),
                (
                    "residual moment RMS",
                    "1.50 % of COM height × peak external force (≤ 1 %)".into()
                )
            ]
        );
        assert!(
            parts[2].1.starts_with("beyond") && parts[2].1.ends_with("after residual reduction")
        );
        assert_eq!(
            parts[3],
            ("before reduction", "force 18.5 %, moment 10.50 %".into())
        );

        // not reduced: the take's own figures, no "before"
        let c = consistency(figures(0.0, 5.0), None);
        for l in c.figure_lines() {
            assert!(l.contains("moment 0.50 %") && l.contains("within"), "{l}");
            assert!(!l.contains("before"), "{l}");
        }
        assert!(c.figure_lines()[2].ends_with("; not reduced"));
        assert_eq!(c.caption_parts().len(), 3);
        assert!(c.caption_parts()[2].1.ends_with("residuals not reduced"));
    }
}
