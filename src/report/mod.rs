//! Reports: plotters SVG charts (embedded font), knee-load comparison, motor sizing, CSV
//! tables and superquadric geometry for drawing links.

pub mod chart;
pub mod csv;
pub mod knee;
pub mod motor;
pub mod superquadric;
