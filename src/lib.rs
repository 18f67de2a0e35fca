//! articula: a terminal workbench for the dynamics of articulated avatars.
//!
//! Data flows one way (see ARCHITECTURE.md):
//! `io` → `model` → `motion` → `dynamics` → `report`, with `pipeline` (the shared
//! take → model → states path), `session` (the command language) and `tui` on top.

pub mod dynamics;
pub mod error;
pub mod io;
pub mod lanes;
pub mod model;
pub mod motion;
pub mod par;
pub mod pipeline;
pub mod report;
pub mod rotation;
pub mod session;
pub mod spatial;
pub mod tui;
