//! articula: a terminal workbench for the dynamics of articulated avatars.
//!
//! Data flows one way (see ARCHITECTURE.md):
//! `io` → `model` → `motion` → `dynamics` → `report`, with `session` and `tui` on top.

pub mod dynamics;
pub mod error;
pub mod io;
pub mod model;
pub mod spatial;
