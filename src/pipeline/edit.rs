//! Editing jobs that write takes: the smoothed take and blends of several takes.

use super::{Take, parse_flag};
use crate::error::Error;
use crate::io::bvh::{self, Bvh, UpAxis};
use std::path::{Path, PathBuf};

/// `articula smooth`: the take's smoothed q written back as BVH channels (euler model), as
/// portable BVH ([`bvh::portable`]: every reader places the joints alike).
pub fn export_smoothed_bvh(take: &Take, path: &Path) -> Result<(), Error> {
    export_smoothed_bvh_as(take, path, bvh::BvhStyle::Portable)
}

/// [`export_smoothed_bvh`] in `style`: portable, or with the channel layout as read
/// ([`bvh::BvhStyle::AsRead`]: every joint's channels and OFFSET as the file had them).
pub fn export_smoothed_bvh_as(take: &Take, path: &Path, style: bvh::BvhStyle) -> Result<(), Error> {
    let mut out = (*take.bvh).clone();
    let cc = out.channel_count;
    for (k, q) in take.states.q.iter().enumerate() {
        crate::motion::take::q_to_frame(
            &take.bvh,
            &take.map,
            &take.model,
            q,
            &mut out.motion[k * cc..(k + 1) * cc],
        )?;
    }
    let out = super::as_in_file(take, out);
    bvh::write(&bvh::styled(&out, &take.positions, style), path)
}

/// `articula blend`: takes[0] into takes[1] (into takes[2] …) through one window per
/// transition, written in `style` (portable BVH, [`bvh::portable`], position modes as `auto`
/// finds them in the first take; or the first take's channel layout as read). Each take is read as every other job reads it
/// ([`super::read_take`]: a rest pose stored as frame 0 is dropped unless
/// `keep_first_frame`), so the windows are on the clock of the motion; returns what the reader
/// changed (one note per take it trimmed), for the user.
#[allow(clippy::too_many_arguments)]
pub fn blend_files(
    takes: &[PathBuf],
    windows: &[String],
    align: &str,
    offset_s: f64,
    time_scale: f64,
    up: Option<UpAxis>,
    keep_first_frame: bool,
    style: bvh::BvhStyle,
    path: &Path,
) -> Result<Vec<String>, Error> {
    use crate::motion::blend::{Align, BlendOptions, TimeMap, WarpWindow, blend_chain};
    if takes.len() < 2 {
        return Err(Error::Invalid("blend needs two takes or more".into()));
    }
    if windows.len() != takes.len() - 1 {
        return Err(Error::Invalid(format!(
            "{} takes need {} transition windows (--window T0:T1 each), got {}",
            takes.len(),
            takes.len() - 1,
            windows.len()
        )));
    }
    let mut bvhs = Vec::with_capacity(takes.len());
    let mut notes = vec![];
    for p in takes {
        let (b, note) = super::read_take(p, keep_first_frame)?;
        bvhs.push(b);
        notes.extend(note.map(|n| format!("{}: {n}", p.display())));
    }
    let windows = windows
        .iter()
        .map(|w| parse_flag::<WarpWindow>("window", w))
        .collect::<Result<Vec<_>, _>>()?;
    let align: Align = parse_flag("align", align)?;
    if !(time_scale > 0.0 && time_scale.is_finite() && offset_s.is_finite()) {
        return Err(Error::Invalid(format!(
            "--time-scale {time_scale} --offset {offset_s}: expected a scale > 0 and a finite \
             offset (s)"
        )));
    }
    let map = TimeMap {
        offset: offset_s,
        scale: time_scale,
    };
    let up = up.unwrap_or_else(|| bvh::detect_up(&bvhs[0]));
    let opts = BlendOptions {
        align,
        up_axis: up.index(),
        ..Default::default()
    };
    let refs: Vec<&Bvh> = bvhs.iter().collect();
    let maps = vec![map; takes.len() - 1];
    let out = blend_chain(&refs, &windows, &maps, &opts)?;
    let modes = bvh::resolve_position_modes(&bvhs[0], bvh::PositionMode::Auto);
    bvh::write(&bvh::styled(&out, &modes, style), path)?;
    Ok(notes)
}
