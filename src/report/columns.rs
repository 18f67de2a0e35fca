//! The one naming scheme of every CSV articula writes, and the SI unit of every column.
//!
//! A column is named `KIND:SUBJECT[:COMPONENT]`: the kind says the quantity (`q` a joint
//! coordinate, `tau` a generalized force, `grf` a ground reaction force, …), the subject what
//! it is of (a coordinate, a foot, a joint), the component which part of it (`x`, `y`, `z` in
//! the take's world axes; `flexion`, `adduction`, `rotation` on an anatomical axis). A few
//! columns are bare words (`time`, `edge`). [`KINDS`] is the table: each kind's quantity and
//! unit, where the unit of a coordinate's quantity depends on the coordinate (a rotation in
//! rad, a translation in m; [`UnitRule::ByCoordinate`]). Values are SI, except the anatomical
//! angles (`angle:`), in degrees as gait labs report them.
//!
//! A coordinate's quantity at a given body mass (`compare weights`) takes the mass as its
//! component: `tau:<coord>:<mass>kg` (`tau:LeftLeg.Xrotation:80kg`), in the coordinate's
//! unit ([`body_mass_component`]).
//!
//! Readers use the same table: [`kind_of`] splits a name, [`unit_of`] gives its unit for a
//! model. OpenSim's `.sto` / `.mot` keep OpenSim's own names (`report::opensim`).

use crate::error::Error;
use crate::model::{JointKind, Model};

/// How a kind's unit is found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UnitRule {
    /// The same for every column of the kind.
    Fixed(&'static str),
    /// By the coordinate named in the column (`q:`: the `q` coordinate; the others: the `v`
    /// one): rotational, translational, or a unit-quaternion component (dimensionless, `1`).
    ByCoordinate {
        angular: &'static str,
        linear: &'static str,
    },
    /// By the component (last part of the name), e.g. `residual:fx` N, `residual:tx` N·m.
    ByComponent(&'static [(&'static str, &'static str)]),
    /// `peak:<column>`, `rms:<column>`: a figure of another column, in that column's unit. In a
    /// table with one row per revolute coordinate (the motor table) the column is a bare
    /// coordinate kind (`peak:tau`) and takes its rotational unit; without a model, a
    /// coordinate's column takes the unit a `known` table gives ([`unit_of_known`]).
    OfColumn,
    /// `M:<i>:<j>`: the mass matrix entry between `v` coordinates i and j (kg·m² between two
    /// rotations, kg·m between a rotation and a translation, kg between two translations).
    MassMatrix,
}

/// One kind of column: its prefix (or bare name), the quantity, and the rule for its unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Kind {
    /// The text before the first `:` (or the whole name for a bare column).
    pub prefix: &'static str,
    /// What the column holds, for documentation and sidecars.
    pub quantity: &'static str,
    pub unit: UnitRule,
}

const fn kind(prefix: &'static str, quantity: &'static str, unit: UnitRule) -> Kind {
    Kind {
        prefix,
        quantity,
        unit,
    }
}

const fn by_coord(angular: &'static str, linear: &'static str) -> UnitRule {
    UnitRule::ByCoordinate { angular, linear }
}

/// Every kind of column, the table the writers name their columns by and the readers and
/// sidecars read units from. Units are written in ASCII (`N*m`, `rad/s^2`).
pub const KINDS: &[Kind] = &[
    kind("time", "time", UnitRule::Fixed("s")),
    kind("q", "joint coordinate", by_coord("rad", "m")),
    kind("v", "joint velocity", by_coord("rad/s", "m/s")),
    kind("a", "joint acceleration", by_coord("rad/s^2", "m/s^2")),
    kind("tau", "generalized force", by_coord("N*m", "N")),
    kind(
        "err",
        "tracking error (reference - simulated)",
        by_coord("rad", "m"),
    ),
    kind(
        "pos",
        "joint centre position, world axes",
        UnitRule::Fixed("m"),
    ),
    kind(
        "grf",
        "ground reaction force, world axes",
        UnitRule::Fixed("N"),
    ),
    kind(
        "cop",
        "centre of pressure, world axes",
        UnitRule::Fixed("m"),
    ),
    kind(
        "moment",
        "moment (a foot's free moment, world axes; a joint's net internal moment on an \
         anatomical axis)",
        UnitRule::Fixed("N*m"),
    ),
    kind(
        "moment_per_kg",
        "net internal joint moment per body mass",
        UnitRule::Fixed("N*m/kg"),
    ),
    kind("angle", "anatomical joint angle", UnitRule::Fixed("deg")),
    kind(
        "residual",
        "what the root still needs (force, moment; world axes)",
        UnitRule::ByComponent(&[
            ("fx", "N"),
            ("fy", "N"),
            ("fz", "N"),
            ("tx", "N*m"),
            ("ty", "N*m"),
            ("tz", "N*m"),
            ("force", "N"),
            ("moment", "N*m"),
            ("beyond", "1"),
        ]),
    ),
    kind(
        "contact",
        "foot on the floor (1) or not (0)",
        UnitRule::Fixed("1"),
    ),
    kind(
        "edge",
        "frame within the smoothing's reach of an end (1) or not (0)",
        UnitRule::Fixed("1"),
    ),
    kind("M", "joint-space mass matrix entry", UnitRule::MassMatrix),
    kind("power", "mechanical power tau * v", UnitRule::Fixed("W")),
    kind("current", "motor current", UnitRule::Fixed("A")),
    kind(
        "step",
        "reduction step: joints locked so far (0: the full model)",
        UnitRule::Fixed("1"),
    ),
    kind(
        "locked",
        "the joint locked at this step (a name)",
        UnitRule::Fixed("text"),
    ),
    kind(
        "hold",
        "where the locked joint is held: rest (its rest pose) or mean (its mean pose over the take)",
        UnitRule::Fixed("text"),
    ),
    kind(
        "nv",
        "degrees of freedom of the model",
        UnitRule::Fixed("1"),
    ),
    kind(
        "time_per_frame",
        "inverse dynamics (RNEA) time per frame at the take's states",
        UnitRule::Fixed("s"),
    ),
    kind(
        "error",
        "reduced minus full model on the outputs (search: the searched frames; all: every \
         frame): peak |e| or RMS",
        UnitRule::ByComponent(&[("peak", "N*m"), ("rms", "N*m")]),
    ),
    kind(
        "error_pct",
        "error in % of the full model's outputs: peak |e| / peak |tau|, RMS e / RMS tau",
        UnitRule::Fixed("%"),
    ),
    kind(
        "peak",
        "peak |x| over the frames of the column named after it",
        UnitRule::OfColumn,
    ),
    kind(
        "rms",
        "RMS over the frames of the column named after it",
        UnitRule::OfColumn,
    ),
    // summary tables (one row per run, per joint, per take): docs/formats.md
    kind(
        "joint",
        "the coordinate the row is of (a name)",
        UnitRule::Fixed("text"),
    ),
    kind(
        "joints",
        "joint model: euler (hinge chains) or ball",
        UnitRule::Fixed("text"),
    ),
    kind("integrator", "integrator (a name)", UnitRule::Fixed("text")),
    kind("dt", "integration time step", UnitRule::Fixed("s")),
    kind(
        "wall_per_sim",
        "wall-clock seconds per simulated second",
        UnitRule::Fixed("s/s"),
    ),
    kind(
        "deviation",
        "largest joint-angle difference at the end of the run from the reference run",
        UnitRule::Fixed("rad"),
    ),
    kind(
        "energy_drift",
        "relative change of kinetic energy over a passive run (tau = 0, no gravity)",
        UnitRule::Fixed("1"),
    ),
    kind(
        "pareto",
        "1 when no other row is both faster and more accurate, else 0",
        UnitRule::Fixed("1"),
    ),
    kind(
        "motor_tau",
        "torque on the motor shaft tau / (N * efficiency)",
        UnitRule::Fixed("N*m"),
    ),
    kind(
        "motor_v",
        "speed of the motor shaft N * v",
        UnitRule::Fixed("rad/s"),
    ),
    kind(
        "class",
        "the motor class chosen from the catalogue (a name)",
        UnitRule::Fixed("text"),
    ),
    kind("km", "motor torque constant", UnitRule::Fixed("N*m/A")),
    kind(
        "gear",
        "gear ratio N (motor turns per joint turn)",
        UnitRule::Fixed("1"),
    ),
    kind("efficiency", "gearbox efficiency", UnitRule::Fixed("1")),
    kind(
        "rotor_inertia",
        "motor rotor inertia J_m (motor shaft)",
        UnitRule::Fixed("kg*m^2"),
    ),
    kind(
        "rotor_tau",
        "reflected rotor inertia torque J_m * N^2 * a (joint side)",
        UnitRule::Fixed("N*m"),
    ),
    kind(
        "energy_driven",
        "energy the joint took in over the take, integral of max(tau * v, 0)",
        UnitRule::Fixed("J"),
    ),
    kind(
        "energy_regen",
        "energy the joint gave back (regenerated) over the take, integral of max(-tau * v, 0)",
        UnitRule::Fixed("J"),
    ),
    kind(
        "beyond_envelope",
        "frames whose motor torque exceeds the class's torque-speed envelope (empty: no envelope)",
        UnitRule::Fixed("1"),
    ),
    kind("take", "the take's path (a name)", UnitRule::Fixed("text")),
    kind(
        "setting",
        "a varied setting's value, as passed to the command (`setting:<flag>`)",
        UnitRule::Fixed("text"),
    ),
    kind("status", "ok, failed or skipped", UnitRule::Fixed("text")),
    kind(
        "wall_time",
        "wall-clock time of the run",
        UnitRule::Fixed("s"),
    ),
    kind("frames", "rows of the output", UnitRule::Fixed("1")),
    kind("output", "the output's path", UnitRule::Fixed("text")),
    kind(
        "failure",
        "why the run failed (the last line of its error output), empty when it did not",
        UnitRule::Fixed("text"),
    ),
];

/// A column name from its kind and parts: `name("tau", &["LeftLeg.Xrotation"])` is
/// `tau:LeftLeg.Xrotation`. The kind must be in [`KINDS`] (checked in debug builds).
pub fn name(kind: &str, parts: &[&str]) -> String {
    debug_assert!(KINDS.iter().any(|k| k.prefix == kind), "kind {kind}");
    let mut s = kind.to_string();
    for p in parts {
        s.push(':');
        s.push_str(p);
    }
    s
}

/// `<coord>` of `<coord>:<mass>kg` (a positive number of kilograms as the last component: the
/// body mass a `compare weights` run set), else `None`.
pub fn body_mass_component(subject: &str) -> Option<&str> {
    let (coord, last) = subject.rsplit_once(':')?;
    let mass: f64 = last.strip_suffix("kg")?.parse().ok()?;
    (mass > 0.0 && mass.is_finite() && !coord.is_empty()).then_some(coord)
}

/// The kind of a column name (its text before the first `:`), if it follows the scheme.
pub fn kind_of(column: &str) -> Option<&'static Kind> {
    let prefix = column.split(':').next().unwrap_or(column);
    KINDS.iter().find(|k| k.prefix == prefix)
}

/// `unit` in the scheme's own spelling (a unit some kind of [`KINDS`] is measured in), for
/// units read back from a sidecar.
pub fn scheme_unit(unit: &str) -> Option<&'static str> {
    const MASS_MATRIX: [&str; 3] = ["kg*m^2", "kg*m", "kg"];
    let of_kind = |k: &Kind| -> Vec<&'static str> {
        match k.unit {
            UnitRule::Fixed(u) => vec![u],
            UnitRule::ByCoordinate { angular, linear } => vec![angular, linear, "1"],
            UnitRule::ByComponent(t) => t.iter().map(|(_, u)| *u).collect(),
            UnitRule::MassMatrix => MASS_MATRIX.to_vec(),
            UnitRule::OfColumn => vec![],
        }
    };
    KINDS.iter().flat_map(of_kind).find(|u| *u == unit)
}

/// How a coordinate's quantities are measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum CoordUnit {
    Angular,
    Linear,
    Quaternion,
}

/// The unit kind of `q` coordinate `k` of `model` (a free joint: x, y, z, then a unit
/// quaternion; a ball joint: a unit quaternion).
fn q_unit(model: &Model, k: usize) -> CoordUnit {
    let b = (1..model.nbodies())
        .find(|&b| (model.idx_q[b]..model.idx_q[b] + model.joints[b].nq()).contains(&k))
        .unwrap_or(0);
    match model.joints[b] {
        JointKind::Free if k - model.idx_q[b] < 3 => CoordUnit::Linear,
        JointKind::Free | JointKind::Spherical => CoordUnit::Quaternion,
        JointKind::Revolute { .. } => CoordUnit::Angular,
        JointKind::Prismatic { .. } | JointKind::Fixed => CoordUnit::Linear,
    }
}

fn v_unit(model: &Model, k: usize) -> CoordUnit {
    if model.is_angular(k) {
        CoordUnit::Angular
    } else {
        CoordUnit::Linear
    }
}

/// The unit of `column` of a file written for `model` (`None`: a file without a model, e.g. a
/// robot-free table; then coordinate kinds are an error). An error names the column when it
/// does not follow the scheme or names no coordinate of the model.
pub fn unit_of(column: &str, model: Option<&Model>) -> Result<&'static str, Error> {
    unit_of_known(column, model, &|_| None)
}

/// [`unit_of`], with `known` giving the unit of a column that neither the scheme nor `model`
/// settles (the columns a batch's `peak:<column>` names, in its outputs' sidecars).
pub fn unit_of_known(
    column: &str,
    model: Option<&Model>,
    known: &dyn Fn(&str) -> Option<&'static str>,
) -> Result<&'static str, Error> {
    let bad = |why: String| Error::Invalid(format!("column {column:?}: {why}"));
    let k = kind_of(column).ok_or_else(|| {
        bad(
            "not in articula's column scheme (KIND:SUBJECT[:COMPONENT], see docs/formats.md)"
                .into(),
        )
    })?;
    let rest = column.strip_prefix(k.prefix).unwrap_or("");
    let rest = rest.strip_prefix(':').unwrap_or(rest);
    match k.unit {
        UnitRule::Fixed(u) => Ok(u),
        UnitRule::ByComponent(table) => {
            let c = rest.rsplit(':').next().unwrap_or(rest);
            table
                .iter()
                .find(|(n, _)| *n == c)
                .map(|(_, u)| *u)
                .ok_or_else(|| bad(format!("no component {c:?} of kind {}", k.prefix)))
        }
        UnitRule::ByCoordinate { angular, linear } => {
            let m = model.ok_or_else(|| bad("a coordinate's unit needs its model".into()))?;
            // `<coord>:<mass>kg`: the coordinate's quantity with the body's mass set to that
            // (`compare weights`)
            let named = |r: &str| m.q_names.iter().any(|n| n == r) || m.v_index(r).is_some();
            let rest = match body_mass_component(rest) {
                Some(coord) if !named(rest) => coord,
                _ => rest,
            };
            let unit = if k.prefix == "q" {
                m.q_names
                    .iter()
                    .position(|n| n == rest)
                    .map(|i| q_unit(m, i))
            } else {
                m.v_index(rest).map(|i| v_unit(m, i))
            };
            match unit.ok_or_else(|| bad(format!("no coordinate {rest:?} in {}", m.name)))? {
                CoordUnit::Angular => Ok(angular),
                CoordUnit::Linear => Ok(linear),
                CoordUnit::Quaternion => Ok("1"),
            }
        }
        UnitRule::OfColumn => {
            // a bare coordinate kind (`peak:tau` in a table of revolute coordinates): rotational
            if let Some(inner) = kind_of(rest).filter(|i| i.prefix == rest)
                && let UnitRule::ByCoordinate { angular, .. } = inner.unit
            {
                return Ok(angular);
            }
            unit_of_known(rest, model, known).or_else(|e| known(rest).ok_or(e))
        }
        UnitRule::MassMatrix => {
            let m =
                model.ok_or_else(|| bad("a mass matrix entry's unit needs its model".into()))?;
            let idx: Vec<usize> = rest.split(':').filter_map(|i| i.parse().ok()).collect();
            let [i, j] = idx[..] else {
                return Err(bad("expected M:<i>:<j>".into()));
            };
            if i >= m.nv || j >= m.nv {
                return Err(bad(format!("index beyond nv = {}", m.nv)));
            }
            Ok(match (m.is_angular(i), m.is_angular(j)) {
                (true, true) => "kg*m^2",
                (false, false) => "kg",
                _ => "kg*m",
            })
        }
    }
}
