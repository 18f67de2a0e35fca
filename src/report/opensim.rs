//! OpenSim's file formats: `.sto` / `.mot` tables, `.trc` marker files and the ExternalLoads
//! XML that applies the forces of a `.mot` to bodies.
//!
//! - `.sto` / `.mot` (one text format, two extensions): a header of `name`, `version=1`,
//!   `nRows=`, `nColumns=` (the time column included), `inDegrees=`, any further `key=value`
//!   lines (the units, here), `endheader`; then a tab-separated `time\t<label>…` line and one
//!   line per row. OpenSim's `STOFileAdapter` reads it (`opensim.TimeSeriesTable`); the extra
//!   keys become the table's metadata.
//! - `.trc`: `PathFileType 4 (X/Y/Z) NAME`, a line of the keys `DataRate CameraRate NumFrames
//!   NumMarkers Units OrigDataRate OrigDataStartFrame OrigNumFrames` and one of their values,
//!   then `Frame# Time` and each marker's name over its three columns, a line `X1 Y1 Z1 X2 …`,
//!   a blank line and the rows (`opensim.TimeSeriesTableVec3`).
//! - ExternalLoads XML: one `ExternalForce` per loaded body, its force, point and torque read
//!   from the `.mot` columns `<prefix>ground_force_v[xyz]`, `<prefix>ground_force_p[xyz]` and
//!   `<prefix>ground_torque_[xyz]`, all expressed in ground (OpenSim's naming, as in its gait
//!   examples and its `ExternalLoads` documentation).
//!
//! Numbers are printed with [`SIGNIFICANT_DIGITS`] significant digits, trailing zeros dropped
//! (`3.4357`, not the shortest round trip `3.4356999999999998` of a value that went through
//! degrees → radians → degrees): a relative error below 5·10⁻¹¹, far under any measurement's.
//! A non-finite value is never written: the export fails naming its column and row. Files go
//! through [`crate::io::write_atomic`] (`-` is standard output).

use crate::error::Error;
use std::fmt::Write as _;
use std::path::Path;

/// Significant digits of every number written in these formats.
pub const SIGNIFICANT_DIGITS: usize = 11;

/// `x` with [`SIGNIFICANT_DIGITS`] significant digits, trailing zeros (and a bare point)
/// dropped; plain decimals from 10⁻⁵ to 10¹⁵, scientific notation (`1.5e-13`) outside.
pub fn format_number(x: f64) -> String {
    if x == 0.0 {
        return "0".into();
    }
    let sci = format!("{:.*e}", SIGNIFICANT_DIGITS - 1, x);
    let (mantissa, exp) = sci.split_once('e').expect("`{:e}` always has an exponent");
    let exp: i32 = exp.parse().expect("`{:e}` writes an integer exponent");
    if (-5..15).contains(&exp) {
        let decimals = (SIGNIFICANT_DIGITS as i32 - 1 - exp).max(0) as usize;
        trim_zeros(format!("{x:.decimals$}"))
    } else {
        format!("{}e{exp}", trim_zeros(mantissa.to_string()))
    }
}

fn trim_zeros(s: String) -> String {
    if !s.contains('.') {
        return s;
    }
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// A `.sto` / `.mot` table: a time column and one column per label.
#[derive(Debug, Clone)]
pub struct Sto<'a> {
    /// The first header line (OpenSim shows it as the table's name).
    pub name: &'a str,
    /// `inDegrees=yes`: the rotational columns are in degrees (OpenSim converts them to
    /// radians when it applies the table to a model).
    pub in_degrees: bool,
    /// Further `key=value` header lines, e.g. `("units", "…")`.
    pub metadata: &'a [(&'a str, String)],
    /// Sample times (s).
    pub time: &'a [f64],
    /// Column labels after `time` (no tab or newline inside).
    pub labels: &'a [String],
    /// One column per label, each as long as `time`.
    pub columns: &'a [&'a [f64]],
}

/// The `.sto` text of `t`; errors on labels and columns of different counts or lengths, on a
/// label holding a tab or a newline, and on a value that is not finite.
pub fn sto_to_string(t: &Sto) -> Result<String, Error> {
    check_table("OpenSim table", t.time, t.labels, t.columns)?;
    let mut out = String::new();
    let _ = writeln!(out, "{}", one_line(t.name));
    let _ = writeln!(out, "version=1");
    let _ = writeln!(out, "nRows={}", t.time.len());
    let _ = writeln!(out, "nColumns={}", t.labels.len() + 1);
    let _ = writeln!(out, "inDegrees={}", if t.in_degrees { "yes" } else { "no" });
    for (k, v) in t.metadata {
        let _ = writeln!(out, "{k}={}", one_line(v));
    }
    out.push_str("endheader\ntime");
    for l in t.labels {
        let _ = write!(out, "\t{l}");
    }
    out.push('\n');
    for (i, time) in t.time.iter().enumerate() {
        out.push_str(&format_number(*time));
        for c in t.columns {
            out.push('\t');
            out.push_str(&format_number(c[i]));
        }
        out.push('\n');
    }
    Ok(out)
}

/// Writes [`sto_to_string`] to `path` (`-`: standard output).
pub fn write_sto(path: &Path, t: &Sto) -> Result<(), Error> {
    let text = sto_to_string(t)?;
    crate::io::write_atomic(path, text.as_bytes())
}

/// The length unit of a `.trc` file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrcUnits {
    Mm,
    M,
}

/// Every `.trc` unit: its name in the header and on the command line, and metres → unit.
const TRC_UNITS: &[(TrcUnits, &str, f64)] =
    &[(TrcUnits::Mm, "mm", 1000.0), (TrcUnits::M, "m", 1.0)];

impl TrcUnits {
    /// The header's (and the flag's) name of the unit.
    pub fn name(self) -> &'static str {
        TRC_UNITS.iter().find(|u| u.0 == self).map_or("mm", |u| u.1)
    }
    /// Unit per metre.
    pub fn per_metre(self) -> f64 {
        TRC_UNITS
            .iter()
            .find(|u| u.0 == self)
            .map_or(1000.0, |u| u.2)
    }
}

impl std::str::FromStr for TrcUnits {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        TRC_UNITS
            .iter()
            .find(|u| u.1 == s.trim())
            .map(|u| u.0)
            .ok_or_else(|| Error::Invalid(format!("TRC units {s:?}: expected mm or m")))
    }
}

/// A `.trc` marker file: marker positions over time.
#[derive(Debug, Clone)]
pub struct Trc<'a> {
    /// The file name written on the first line.
    pub name: &'a str,
    /// Frames per second (DataRate, CameraRate, OrigDataRate).
    pub rate_hz: f64,
    /// The unit of `positions`, declared in the header.
    pub units: TrcUnits,
    /// `Frame#` of the first row (1-based, on the source's own frame count).
    pub first_frame: usize,
    /// Frames of the source (OrigNumFrames).
    pub orig_frames: usize,
    /// Sample times (s).
    pub time: &'a [f64],
    /// Marker names (no tab or newline inside).
    pub markers: &'a [String],
    /// `[frame][marker]` positions, in metres (converted to `units` when written).
    pub positions: &'a [Vec<[f64; 3]>],
}

/// The `.trc` text of `t`; errors on a row without one position per marker and on a value
/// that is not finite.
pub fn trc_to_string(t: &Trc) -> Result<String, Error> {
    if t.positions.len() != t.time.len() {
        return Err(Error::Invalid(format!(
            "TRC export: {} rows of positions for {} times",
            t.positions.len(),
            t.time.len()
        )));
    }
    let per_m = t.units.per_metre();
    let mut out = String::new();
    let _ = writeln!(out, "PathFileType\t4\t(X/Y/Z)\t{}", one_line(t.name));
    out.push_str(
        "DataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\tOrigDataRate\tOrigDataStartFrame\t\
         OrigNumFrames\n",
    );
    let rate = format_number(t.rate_hz);
    let _ = writeln!(
        out,
        "{rate}\t{rate}\t{}\t{}\t{}\t{rate}\t{}\t{}",
        t.time.len(),
        t.markers.len(),
        t.units.name(),
        t.first_frame,
        t.orig_frames
    );
    out.push_str("Frame#\tTime");
    for m in t.markers {
        let _ = write!(out, "\t{m}\t\t");
    }
    out.push_str("\n\t");
    for i in 1..=t.markers.len() {
        let _ = write!(out, "\tX{i}\tY{i}\tZ{i}");
    }
    out.push_str("\n\n");
    for (k, (time, row)) in t.time.iter().zip(t.positions).enumerate() {
        if row.len() != t.markers.len() {
            return Err(Error::Invalid(format!(
                "TRC export: row {} has {} positions for {} markers",
                k + 1,
                row.len(),
                t.markers.len()
            )));
        }
        let _ = write!(out, "{}\t{}", t.first_frame + k, format_number(*time));
        for (m, p) in row.iter().enumerate() {
            for x in p {
                if !x.is_finite() {
                    return Err(Error::Numerical(format!(
                        "TRC export: marker {:?} is {x} at row {}; nothing written",
                        t.markers[m],
                        k + 1
                    )));
                }
                let _ = write!(out, "\t{}", format_number(x * per_m));
            }
        }
        out.push('\n');
    }
    Ok(out)
}

/// Writes [`trc_to_string`] to `path` (`-`: standard output).
pub fn write_trc(path: &Path, t: &Trc) -> Result<(), Error> {
    let text = trc_to_string(t)?;
    crate::io::write_atomic(path, text.as_bytes())
}

/// The `.mot` column labels of one body's external load, prefix `<prefix>_`: force
/// `ground_force_v[xyz]` (N), point `ground_force_p[xyz]` (m), torque `ground_torque_[xyz]`
/// (N·m), in this order.
pub fn external_load_labels(prefix: &str) -> Vec<String> {
    let mut l = vec![];
    for stem in ["ground_force_v", "ground_force_p", "ground_torque_"] {
        l.extend(["x", "y", "z"].map(|a| format!("{prefix}_{stem}{a}")));
    }
    l
}

/// The ExternalLoads XML that applies, for each `(prefix, body)`, the force, point and torque
/// columns [`external_load_labels`]`(prefix)` of `datafile` to `body`, force, point and torque
/// expressed in ground (OpenSim 4's `ExternalLoads` / `ExternalForce`).
pub fn external_loads_xml(name: &str, datafile: &str, loads: &[(&str, &str)]) -> String {
    let mut out = String::from(
        "<?xml version=\"1.0\" encoding=\"UTF-8\" ?>\n<OpenSimDocument Version=\"40000\">\n",
    );
    let _ = writeln!(out, "\t<ExternalLoads name=\"{}\">", xml_escape(name));
    out.push_str("\t\t<objects>\n");
    for (prefix, body) in loads {
        let (p, b) = (xml_escape(prefix), xml_escape(body));
        let _ = write!(
            out,
            "\t\t\t<ExternalForce name=\"{p}\">\n\
             \t\t\t\t<applied_to_body>{b}</applied_to_body>\n\
             \t\t\t\t<force_expressed_in_body>ground</force_expressed_in_body>\n\
             \t\t\t\t<point_expressed_in_body>ground</point_expressed_in_body>\n\
             \t\t\t\t<force_identifier>{p}_ground_force_v</force_identifier>\n\
             \t\t\t\t<point_identifier>{p}_ground_force_p</point_identifier>\n\
             \t\t\t\t<torque_identifier>{p}_ground_torque_</torque_identifier>\n\
             \t\t\t\t<data_source_name>{}</data_source_name>\n\
             \t\t\t</ExternalForce>\n",
            xml_escape(datafile)
        );
    }
    out.push_str("\t\t</objects>\n\t\t<groups />\n");
    let _ = writeln!(out, "\t\t<datafile>{}</datafile>", xml_escape(datafile));
    out.push_str("\t</ExternalLoads>\n</OpenSimDocument>\n");
    out
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// A header value on one line: newlines and tabs become spaces.
fn one_line(s: &str) -> String {
    s.replace(['\n', '\r', '\t'], " ")
}

/// Shape and finiteness checks shared by the tables.
fn check_table(
    what: &str,
    time: &[f64],
    labels: &[String],
    columns: &[&[f64]],
) -> Result<(), Error> {
    if labels.len() != columns.len() {
        return Err(Error::Invalid(format!(
            "{what}: {} labels for {} columns; give one label per column",
            labels.len(),
            columns.len()
        )));
    }
    if let Some(l) = labels.iter().find(|l| l.contains(['\t', '\n', '\r'])) {
        return Err(Error::Invalid(format!(
            "{what}: the label {l:?} holds a tab or a line break, which would split the column"
        )));
    }
    let all = std::iter::once(("time", time)).chain(
        labels
            .iter()
            .map(String::as_str)
            .zip(columns.iter().copied()),
    );
    for (label, c) in all {
        if c.len() != time.len() {
            return Err(Error::Invalid(format!(
                "{what}: column {label:?} has {} values for {} times",
                c.len(),
                time.len()
            )));
        }
        if let Some(i) = c.iter().position(|x| !x.is_finite()) {
            return Err(Error::Numerical(format!(
                "{what}: column {label:?} is {} at row {}; nothing written",
                c[i],
                i + 1
            )));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_have_fixed_significant_digits_not_round_trip_noise() {
        assert_eq!(format_number(3.4356999999999998), "3.4357");
        assert_eq!(format_number(-44.00030000000001), "-44.0003");
        assert_eq!(format_number(0.0), "0");
        assert_eq!(format_number(120.0), "120");
        assert_eq!(format_number(1.5e-13), "1.5e-13");
        assert_eq!(format_number(-2.5e20), "-2.5e20");
        assert_eq!(format_number(0.0166667), "0.0166667");
        let x = std::f64::consts::PI * 1e3;
        let back: f64 = format_number(x).parse().unwrap();
        assert!(((back - x) / x).abs() < 1e-10, "{back}");
    }

    #[test]
    fn sto_header_counts_the_time_column() {
        let t = Sto {
            name: "states",
            in_degrees: true,
            metadata: &[("units", "deg".to_string())],
            time: &[0.0, 0.5],
            labels: &["a".to_string()],
            columns: &[&[1.0, 2.25]],
        };
        assert_eq!(
            sto_to_string(&t).unwrap(),
            "states\nversion=1\nnRows=2\nnColumns=2\ninDegrees=yes\nunits=deg\nendheader\n\
             time\ta\n0\t1\n0.5\t2.25\n"
        );
        let bad = Sto {
            columns: &[&[1.0, f64::NAN]],
            ..t
        };
        assert!(
            sto_to_string(&bad)
                .unwrap_err()
                .to_string()
                .contains("row 2")
        );
    }
}
