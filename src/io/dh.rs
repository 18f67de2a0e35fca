//! Denavit–Hartenberg tables in TOML, with the fields and frame conventions of Peter Corke's
//! Robotics Toolbox (Corke, *Robotics, Vision and Control*, 2nd ed., 2017, §7.1 and §7.4;
//! `rtb.DHRobot`), so that published tables (Puma 560, Stanford arm) can be typed in.
//! The format is documented, with an example, in `data/dh_example.toml`.
//!
//! ```toml
//! name = "two-link"
//! convention = "standard"          # or "modified" (Craig)
//! gravity = [0.0, 0.0, -9.81]      # gravitational acceleration, world frame, m/s²
//! [[link]]
//! type = "R"                       # "R" revolute (theta is q) or "P" prismatic (d is q)
//! d = 0.0                          # m
//! a = 0.5                          # m
//! alpha = 0.0                      # rad
//! offset = 0.0                     # added to q: theta = q + offset (R), d = q + offset (P)
//! qlim = [-3.14, 3.14]             # rad or m
//! m = 2.0                          # kg
//! r = [-0.25, 0.0, 0.0]            # COM in the link frame, m
//! I = [0.0, 0.04, 0.04, 0.0, 0.0, 0.0]  # [Ixx, Iyy, Izz, Ixy, Iyz, Ixz] about the COM, kg m²
//! ```
//! Everything is SI already; nothing is converted.

use crate::error::Error;
use nalgebra::{Matrix3, Vector3};
use serde::Deserialize;
use std::path::Path;

/// Standard (Denavit–Hartenberg 1955, as Corke's `RevoluteDH`) or modified (Craig 1986,
/// Corke's `RevoluteMDH`) parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum DhConvention {
    /// `A_i = Rz(θ_i) Tz(d_i) Tx(a_i) Rx(α_i)`; link frame i at the distal end of link i.
    Standard,
    /// `A_i = Rx(α_i) Tx(a_i) Rz(θ_i) Tz(d_i)`, where α_i, a_i describe the link before
    /// joint i; link frame i on joint i's axis.
    Modified,
}

/// The joint variable of a link.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
pub enum DhJointType {
    /// Revolute: θ = q + offset.
    R,
    /// Prismatic: d = q + offset.
    P,
}

/// One `[[link]]` row.
#[derive(Debug, Clone, PartialEq)]
pub struct DhLink {
    pub joint_type: DhJointType,
    /// rad (unused for R: θ is the joint variable).
    pub theta: f64,
    /// m (unused for P: d is the joint variable).
    pub d: f64,
    /// m.
    pub a: f64,
    /// rad.
    pub alpha: f64,
    /// Added to q before use (rad or m).
    pub offset: f64,
    /// `[lower, upper]` of q, if given.
    pub qlim: Option<[f64; 2]>,
    /// kg.
    pub m: f64,
    /// COM in the link frame (m).
    pub r: Vector3<f64>,
    /// Inertia about the COM in link-frame axes (kg·m²).
    pub inertia: Matrix3<f64>,
    /// 1-based line of the `[[link]]` header, for messages.
    pub line: usize,
}

/// A DH table.
#[derive(Debug, Clone, PartialEq)]
pub struct DhTable {
    pub name: String,
    pub convention: DhConvention,
    /// Gravitational acceleration in the base (world) frame (m/s²), e.g. `[0, 0, −9.81]`.
    pub gravity: Vector3<f64>,
    /// Base to tip.
    pub links: Vec<DhLink>,
}

/// `I` as Corke's six numbers or a full 3×3 matrix.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
enum InertiaSpec {
    Six([f64; 6]),
    Matrix([[f64; 3]; 3]),
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawLink {
    #[serde(rename = "type")]
    joint_type: DhJointType,
    #[serde(default)]
    theta: f64,
    #[serde(default)]
    d: f64,
    #[serde(default)]
    a: f64,
    #[serde(default)]
    alpha: f64,
    #[serde(default)]
    offset: f64,
    qlim: Option<[f64; 2]>,
    #[serde(default)]
    m: f64,
    #[serde(default)]
    r: [f64; 3],
    #[serde(rename = "I")]
    inertia: Option<InertiaSpec>,
}

fn default_gravity() -> [f64; 3] {
    [0.0, 0.0, -9.81]
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTable {
    #[serde(default)]
    name: Option<String>,
    convention: DhConvention,
    #[serde(default = "default_gravity")]
    gravity: [f64; 3],
    link: Vec<toml::Spanned<RawLink>>,
}

/// 1-based line and column of byte offset `pos` in `text`.
pub(crate) fn line_col(text: &str, pos: usize) -> (usize, usize) {
    let before = &text[..pos.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

/// A located error from a TOML (serde) error.
pub(crate) fn toml_error(path: &Path, text: &str, err: &toml::de::Error) -> Error {
    let (line, col) = err.span().map_or((1, 1), |s| line_col(text, s.start));
    Error::parse(path, line, col, err.message().trim().to_string())
}

/// Reads a DH table file.
pub fn read(path: &Path) -> Result<DhTable, Error> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    parse_str(&text, path)
}

/// Parses a DH table; `path` names the source in error messages.
///
/// Errors (with line and column): TOML syntax, unknown or missing fields, a `convention` other
/// than standard/modified, a `type` other than R/P, non-finite numbers, a negative mass, an
/// inertia that is not symmetric, `qlim` with lower > upper, no links.
pub fn parse_str(text: &str, path: &Path) -> Result<DhTable, Error> {
    let raw: RawTable = toml::from_str(text).map_err(|e| toml_error(path, text, &e))?;
    if raw.link.is_empty() {
        return Err(Error::parse(path, 1, 1, "expected at least one [[link]]"));
    }
    let g = Vector3::from(raw.gravity);
    if !g.iter().all(|x| x.is_finite()) {
        return Err(Error::parse(
            path,
            1,
            1,
            "gravity must be three finite numbers",
        ));
    }
    let mut links = Vec::with_capacity(raw.link.len());
    for spanned in &raw.link {
        let (line, col) = line_col(text, spanned.span().start);
        let l = spanned.get_ref();
        let bad = |what: String| Error::parse(path, line, col, what);
        let inertia = match &l.inertia {
            None => Matrix3::zeros(),
            Some(InertiaSpec::Six([xx, yy, zz, xy, yz, xz])) => {
                Matrix3::new(*xx, *xy, *xz, *xy, *yy, *yz, *xz, *yz, *zz)
            }
            Some(InertiaSpec::Matrix(rows)) => Matrix3::from_fn(|i, j| rows[i][j]),
        };
        let numbers = [l.theta, l.d, l.a, l.alpha, l.offset, l.m]
            .into_iter()
            .chain(l.r)
            .chain(inertia.iter().copied())
            .chain(l.qlim.into_iter().flatten());
        for x in numbers {
            if !x.is_finite() {
                return Err(bad(format!("non-finite number {x} in this link")));
            }
        }
        if l.m < 0.0 {
            return Err(bad(format!("m = {}: a mass must be ≥ 0 kg", l.m)));
        }
        if (inertia - inertia.transpose()).abs().max() > 1e-12 * (1.0 + inertia.abs().max()) {
            return Err(bad("I must be symmetric".into()));
        }
        if let Some([lo, hi]) = l.qlim
            && lo > hi
        {
            return Err(bad(format!("qlim = [{lo}, {hi}]: lower > upper")));
        }
        links.push(DhLink {
            joint_type: l.joint_type,
            theta: l.theta,
            d: l.d,
            a: l.a,
            alpha: l.alpha,
            offset: l.offset,
            qlim: l.qlim,
            m: l.m,
            r: Vector3::from(l.r),
            inertia,
            line,
        });
    }
    let name = raw.name.unwrap_or_else(|| {
        path.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "dh".into())
    });
    Ok(DhTable {
        name,
        convention: raw.convention,
        gravity: g,
        links,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<DhTable, Error> {
        parse_str(text, Path::new("t.toml"))
    }

    #[test]
    fn reads_both_inertia_forms() {
        let t = parse(
            "convention = \"standard\"\n[[link]]\ntype = \"R\"\nI = [1, 2, 3, 0.1, 0.2, 0.3]\n\
             [[link]]\ntype = \"P\"\nI = [[1, 0.1, 0.3], [0.1, 2, 0.2], [0.3, 0.2, 3]]\n",
        )
        .unwrap();
        assert_eq!(t.links[0].inertia, t.links[1].inertia);
        assert_eq!(t.links[0].inertia[(0, 2)], 0.3);
        assert_eq!(t.links[1].line, 5);
        assert_eq!(t.gravity, Vector3::new(0.0, 0.0, -9.81));
        assert_eq!(t.name, "t");
    }

    #[test]
    fn errors_name_the_line() {
        let cases = [
            ("convention = \"weird\"\n[[link]]\ntype = \"R\"\n", 1),
            ("convention = \"standard\"\n[[link]]\ntype = \"Q\"\n", 3),
            (
                "convention = \"standard\"\n[[link]]\ntype = \"R\"\nm = -1\n",
                2,
            ),
            (
                "convention = \"standard\"\n[[link]]\ntype = \"R\"\nqlim = [1, 0]\n",
                2,
            ),
            (
                "convention = \"standard\"\n[[link]]\ntype = \"R\"\nmass = 1\n",
                4,
            ),
            (
                "convention = \"standard\"\n[[link]]\ntype = \"R\"\n[[link]]\ntype = \"R\"\nI = [[1, 0, 0], [0.5, 1, 0], [0, 0, 1]]\n",
                4,
            ),
        ];
        for (text, line) in cases {
            match parse(text) {
                Err(Error::Parse { at, message }) => {
                    assert_eq!(at.line, line, "{text}: {message}")
                }
                other => panic!("{text}: {other:?}"),
            }
        }
    }
}
