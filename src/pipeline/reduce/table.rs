//! The reduction's table as `articula tradeoff --reduce` prints it and as CSV (one row per
//! step, `report::columns`' scheme, through the one table writer).

use super::{Figures, Hold, Reduce};
use crate::error::Error;
use std::fmt::Write as _;
use std::path::Path;

impl Reduce {
    /// The table `articula tradeoff --reduce` prints.
    pub fn text(&self) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "reduce {}: outputs {} ({}), contact {}",
            self.take,
            self.outputs,
            match &self.coordinates {
                Some(c) => format!("tau of {}", c.join(", ")),
                None => "every joint rotation the model keeps".into(),
            },
            self.contact
        );
        let _ = writeln!(
            s,
            "search on {} of {} frames (every {}), each step verified on all; error = reduced − \
             full model on the outputs, % of their peak |τ| {:.3} N·m and RMS {:.3} N·m",
            self.search_frames,
            self.frames,
            self.search_every,
            self.output_peak_nm,
            self.output_rms_nm
        );
        let _ = writeln!(
            s,
            "{:>4}  {:<22} {:<5} {:>4} {:>9}  {:>22}  {:>22}",
            "step",
            "locked",
            "hold",
            "nv",
            "µs/frame",
            "search peak / RMS N·m",
            "all peak / RMS N·m"
        );
        for (k, st) in self.steps.iter().enumerate() {
            let f =
                |x: &Figures| format!("{:.3} ({:.1}%) / {:.3}", x.peak_nm, x.peak_pct, x.rms_nm);
            let _ = writeln!(
                s,
                "{:>4}  {:<22} {:<5} {:>4} {:>9.2}  {:>22}  {:>22}",
                k,
                st.locked.as_deref().unwrap_or("(full model)"),
                st.hold.map_or("", Hold::name),
                st.nv,
                st.time_per_frame_s * 1e6,
                f(&st.search),
                f(&st.all)
            );
        }
        let mean: Vec<&str> = self
            .holds
            .iter()
            .filter(|h| h.chosen == Hold::Mean)
            .map(|h| h.joint.as_str())
            .collect();
        let _ = writeln!(
            s,
            "held at their mean pose over the take (less error than at rest): {}",
            if mean.is_empty() {
                "none".into()
            } else {
                mean.join(", ")
            }
        );
        for k in &self.skipped {
            let _ = writeln!(s, "left out: {k}");
        }
        s
    }

    /// The CSV header (`report::columns`' scheme).
    pub fn header() -> Vec<String> {
        let mut h: Vec<String> = ["step", "locked", "hold", "nv", "time_per_frame"]
            .map(String::from)
            .to_vec();
        for frames in ["search", "all"] {
            for (kind, which) in [
                ("error", "peak"),
                ("error", "rms"),
                ("error_pct", "peak"),
                ("error_pct", "rms"),
            ] {
                h.push(crate::report::columns::name(kind, &[frames, which]));
            }
        }
        h
    }

    /// Writes the steps as CSV, one row per step ([`Reduce::header`]; SI: s, N·m, %).
    pub fn write_csv(&self, path: &Path) -> Result<(), Error> {
        let mut buf = crate::io::shortest::Shortest::new();
        let mut num = |x: f64| buf.format(x).to_string();
        let rows: Vec<Vec<String>> = self
            .steps
            .iter()
            .enumerate()
            .map(|(k, s)| {
                let mut r = vec![
                    k.to_string(),
                    s.locked.clone().unwrap_or_default(),
                    s.hold.map_or("", Hold::name).to_string(),
                    s.nv.to_string(),
                    num(s.time_per_frame_s),
                ];
                for f in [&s.search, &s.all] {
                    for x in [f.peak_nm, f.rms_nm, f.peak_pct, f.rms_pct] {
                        r.push(num(x));
                    }
                }
                r
            })
            .collect();
        crate::report::csv::write_table(path, &Self::header(), &rows)
    }
}
