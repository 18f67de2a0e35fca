//! `articula export mjcf`: a take's model as MuJoCo's MJCF, with a floor under its feet.

use super::Take;
use crate::error::Error;
use crate::io::bvh;
use crate::io::mjcf_write::{MjcfOptions, model_to_mjcf};
use crate::motion::contact::detect_floor;
use std::path::Path;

/// `articula export mjcf`: the take's model ([`model_to_mjcf`]) with the floor plane at
/// [`floor_level`], every motor's gear 1 (the command line has no drive settings).
pub fn export_mjcf(take: &Take, path: &Path) -> Result<(), Error> {
    let opts = MjcfOptions {
        floor: Some(floor_level(take)),
        ..MjcfOptions::default()
    };
    let text = model_to_mjcf(&take.model, &opts)?;
    crate::io::write_atomic(path, text.as_bytes())
}

/// The floor's height along up (m): the floor level ([`detect_floor`], a low quantile) of the
/// lowest joint's height in each frame of the take.
pub fn floor_level(take: &Take) -> f64 {
    let b = &take.bvh;
    let up = take.up.index();
    let lowest: Vec<f64> = (0..b.frames)
        .map(|k| {
            bvh::bvh_world_positions(b, &take.positions, k)
                .iter()
                .map(|p| p[up] * take.scale_to_m)
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    detect_floor(&lowest)
}
