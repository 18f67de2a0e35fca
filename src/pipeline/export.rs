//! The plain exports of a take: its states, its joints' world positions, its model as URDF,
//! and the generated demo walk. Row tables go to CSV through `report::csv`'s row writer,
//! the writer every CSV output shares.

use super::{Take, table};
use crate::error::Error;
use crate::io::bvh::{self, Bvh};
use crate::report::columns;
use crate::report::csv::write_filled_rows;
use std::path::Path;

/// `articula export states`.
pub fn export_states(take: &Take, path: &Path) -> Result<(), Error> {
    table::write_states_csv(&take.model, &take.states, path)
}

/// `articula export positions`: world position of every BVH joint, `pos:<joint>:x|y|z` (m, the
/// take's own axes), straight from the BVH definition (independent of the model).
pub fn export_positions(take: &Take, path: &Path) -> Result<(), Error> {
    let c = joint_centres(take);
    let mut header = vec!["time".to_string()];
    for name in &c.names {
        for a in ["x", "y", "z"] {
            header.push(columns::name("pos", &[name, a]));
        }
    }
    let fill = |k: usize, r: &mut Vec<f64>| {
        r.push(c.time[k]);
        r.extend(c.positions[k].iter().flatten());
    };
    write_filled_rows(path, &header, c.time.len(), &fill)
}

/// The world positions of a take's joints (`export positions`, `export trc`).
#[derive(Debug, Clone)]
pub struct JointCentres {
    /// The BVH joints' names, in file order.
    pub names: Vec<String>,
    /// Frame times (s, the file's clock: [`Bvh::time`]).
    pub time: Vec<f64>,
    /// `[frame][joint]`: world position (m, the take's own axes).
    pub positions: Vec<Vec<[f64; 3]>>,
}

/// Every BVH joint's world position per frame, straight from the BVH definition (independent
/// of the model), a folded helper root given its motion back ([`as_in_file`]).
pub fn joint_centres(take: &Take) -> JointCentres {
    let b = &as_in_file(take, (*take.bvh).clone());
    let positions = (0..b.frames)
        .map(|k| {
            bvh::bvh_world_positions(b, &take.positions, k)
                .iter()
                .map(|x| [x.x, x.y, x.z].map(|c| c * take.scale_to_m))
                .collect()
        })
        .collect();
    JointCentres {
        names: b.joints.iter().map(|j| j.name.clone()).collect(),
        time: (0..b.frames).map(|k| b.time(k)).collect(),
        positions,
    }
}

/// `b` (the take's skeleton, its frames possibly rewritten) with a folded helper root's motion
/// given back to the root, as the file had it ([`Take::fold`]).
pub(crate) fn as_in_file(take: &Take, mut b: Bvh) -> Bvh {
    if let Some(f) = &take.fold {
        crate::motion::fold::unfold_root(&mut b, &take.positions, f);
    }
    b
}

/// `articula export urdf`.
pub fn export_urdf(take: &Take, path: &Path) -> Result<(), Error> {
    let text = crate::io::urdf_write::model_to_urdf(&take.model)?;
    crate::io::write_atomic(path, text.as_bytes())
}

/// `articula generate walk`: the bundled demo take is made this way.
pub fn generate_walk(path: &Path, fps: f64, duration_s: f64, scale: f64) -> Result<(), Error> {
    if !(fps > 0.0 && duration_s > 0.0 && scale > 0.0) {
        return Err(Error::Invalid(
            "generate walk: --fps, --duration and --scale must be positive".into(),
        ));
    }
    let take = crate::io::generate::walk(&crate::io::generate::WalkParams {
        fps,
        duration_s,
        scale,
        ..Default::default()
    });
    let modes = bvh::resolve_position_modes(&take, bvh::PositionMode::Auto);
    bvh::write(&bvh::portable(&take, &modes), path)
}
