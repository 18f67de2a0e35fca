//! `articula export mjcf`: a take's model as MuJoCo's MJCF, with a floor under its feet.

use super::Take;
use crate::dynamics::{Workspace, kinematics::forward_kinematics};
use crate::error::Error;
use crate::io::mjcf_write::{MjcfOptions, model_to_mjcf};
use crate::model::Model;
use crate::motion::contact::detect_floor;
use std::path::Path;

/// `articula export mjcf`: the take's model ([`model_to_mjcf`]) with the floor plane at
/// [`floor_level`] over the take's frames, its first frame as the keyframe `first_frame`, every
/// motor's gear 1 (the command line has no drive
/// settings; the workbench's `export mjcf` uses its motor drives).
pub fn export_mjcf(take: &Take, path: &Path) -> Result<(), Error> {
    let opts = MjcfOptions {
        floor: Some(floor_level(
            &take.model,
            take.states.q.iter().map(Vec::as_slice),
        )),
        keyframe: take.states.q.first().cloned(),
        ..MjcfOptions::default()
    };
    let text = model_to_mjcf(&take.model, &opts)?;
    crate::io::write_atomic(path, text.as_bytes())
}

/// The floor's height along up (−gravity; z without gravity), m: the floor level
/// ([`detect_floor`], a low quantile) of the lowest body origin's height at each
/// configuration; 0 without any.
pub fn floor_level<'a>(model: &Model, q: impl IntoIterator<Item = &'a [f64]>) -> f64 {
    let g = model.gravity;
    let up = if g.norm() > 0.0 {
        -g / g.norm()
    } else {
        nalgebra::Vector3::z()
    };
    let mut ws = Workspace::new(model);
    let lowest: Vec<f64> = q
        .into_iter()
        .map(|q| {
            forward_kinematics(model, &mut ws, q);
            ws.o_x_i[1..]
                .iter()
                .map(|x| x.trans.dot(&up))
                .fold(f64::INFINITY, f64::min)
        })
        .collect();
    detect_floor(&lowest)
}
