//! Text ↔ plain descriptions: BVH, DH tables, URDF, CSV, scene TOML. No physics here.

pub mod bvh;
pub mod generate;
