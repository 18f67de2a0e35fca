//! Reports: plotters SVG charts (embedded font), knee-load comparison, motor sizing, CSV
//! tables and superquadric geometry for drawing links.
//!
//! Pure functions on plain data (time series as `Vec<f64>`, SI units), so reports do not depend
//! on how the numbers were computed:
//! - [`chart`]: curves over time with min/max marked (the paper's figure 4), stacked panels and
//!   text tables, as deterministic SVG; [`chart::write_svg`] writes atomically;
//! - [`knee`]: one joint's torque at several body masses (the paper's figure 5), with a table of
//!   peak |τ| and RMS τ per mass, as SVG and CSV;
//! - [`motor`]: per-joint torque, speed, power, current `I = τ / (Km·N·η)` and the motor class
//!   needed from an illustrative catalogue, as SVG and CSV;
//! - [`columns`]: the one naming scheme of every CSV's columns and their units; [`sidecar`]:
//!   the `NAME.csv.json` beside each CSV;
//! - [`csv`]: column tables with shortest round-trip numbers and located read errors;
//! - [`opensim`]: OpenSim's `.sto` / `.mot` tables, `.trc` markers and ExternalLoads XML;
//! - [`superquadric`]: Barr's superquadric surface points and wireframes for drawing links.

pub mod caption;
pub mod chart;
pub mod columns;
pub mod csv;
pub mod gait;
pub mod knee;
pub mod labels;
pub mod legend;
pub mod motor;
pub mod motor_chart;
pub mod motor_duty;
pub mod opensim;
pub mod sidecar;
pub mod superquadric;
