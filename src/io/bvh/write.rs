//! The BVH writer.
//!
//! Layout: the one Blender's exporter writes and that Blender's and three.js's importers read:
//! keywords in their usual case, one tab per nesting level, `End Site` blocks after a joint's
//! child joints, `Frames: N`, `Frame Time: 0.008333`, one line per frame with values separated
//! by single spaces, LF line ends and a final newline.
//!
//! Channel values read from text are printed at the precision they were read with
//! ([`Bvh::decimals`]): a value that was not changed (beyond float noise, a relative 1e-9, as
//! degrees → radians → degrees leaves) is written as the file wrote it (`-12.50` stays
//! `-12.50`, byte for byte for a plain decimal of up to 15 significant digits); a changed one
//! at the take's precision (the most decimals any of its values was read with), so a smoothed take
//! has no float-noise digits (`3.4357`, not `3.4356999999999998`). Other numbers (OFFSETs,
//! the frame time, values of a take built by code) are printed in their shortest form that
//! parses back to the same `f64` ([`Shortest`]; e.g. `93.9241`, `-0`, `0.0000187007`, `1e-7`), so
//! parse → write → parse reproduces every value exactly. Integral values drop the `.0` (`0`,
//! `-0`, `90`) as most BVH files do.

use super::Bvh;
use crate::error::Error;
use crate::io::shortest::Shortest;
use std::fmt::Write as _;
use std::path::Path;

/// The BVH text of `bvh`.
///
/// Joints are written depth-first (children in index order) and each frame line follows
/// that order, so a description whose joints are in another parent-before-child order (as
/// code may build one) is written correctly and reads back renumbered. A well-formed `Bvh`
/// has one root; several roots would be written as several ROOT blocks, which the reader
/// rejects. Motion rows are `bvh.channel_count` wide; each joint's values are taken from
/// its `first_channel` columns.
pub fn write_string(bvh: &Bvh) -> String {
    let mut out = String::with_capacity(64 * bvh.joints.len() + 10 * bvh.motion.len() + 64);
    let mut children: Vec<Vec<usize>> = vec![Vec::new(); bvh.joints.len()];
    for (j, joint) in bvh.joints.iter().enumerate() {
        if let Some(p) = joint.parent {
            children[p].push(j);
        }
    }
    let mut shortest = Shortest::new();
    // joints in the order they are written (depth-first), for the motion columns
    let mut written: Vec<usize> = Vec::with_capacity(bvh.joints.len());
    out.push_str("HIERARCHY\n");
    // depth-first over the roots (one in a parsed file); `Close(j)` ends joint j's body
    enum Step {
        Open(usize, usize),
        Close(usize, usize),
    }
    let mut stack: Vec<Step> = bvh
        .joints
        .iter()
        .enumerate()
        .rev()
        .filter(|(_, j)| j.parent.is_none())
        .map(|(j, _)| Step::Open(j, 0))
        .collect();
    while let Some(step) = stack.pop() {
        match step {
            Step::Open(j, depth) => {
                written.push(j);
                let joint = &bvh.joints[j];
                indent(&mut out, depth);
                out.push_str(if joint.parent.is_none() {
                    "ROOT "
                } else {
                    "JOINT "
                });
                out.push_str(&joint.name);
                out.push('\n');
                indent(&mut out, depth);
                out.push_str("{\n");
                indent(&mut out, depth + 1);
                out.push_str("OFFSET");
                for v in joint.offset.iter() {
                    out.push(' ');
                    out.push_str(shortest.format_plain(*v));
                }
                out.push('\n');
                indent(&mut out, depth + 1);
                let _ = write!(out, "CHANNELS {}", joint.channels.len());
                for c in &joint.channels {
                    out.push(' ');
                    out.push_str(c.name());
                }
                out.push('\n');
                stack.push(Step::Close(j, depth));
                for &c in children[j].iter().rev() {
                    stack.push(Step::Open(c, depth + 1));
                }
            }
            Step::Close(j, depth) => {
                for site in &bvh.joints[j].end_sites {
                    indent(&mut out, depth + 1);
                    out.push_str("End Site\n");
                    indent(&mut out, depth + 1);
                    out.push_str("{\n");
                    indent(&mut out, depth + 2);
                    out.push_str("OFFSET");
                    for v in site.iter() {
                        out.push(' ');
                        out.push_str(shortest.format_plain(*v));
                    }
                    out.push('\n');
                    indent(&mut out, depth + 1);
                    out.push_str("}\n");
                }
                indent(&mut out, depth);
                out.push_str("}\n");
            }
        }
    }
    out.push_str("MOTION\n");
    let _ = writeln!(out, "Frames: {}", bvh.frames);
    out.push_str("Frame Time: ");
    out.push_str(shortest.format_plain(bvh.frame_time));
    out.push('\n');
    if bvh.channel_count > 0 {
        let read_with = bvh.decimals.len() == bvh.motion.len();
        let precision = bvh.precision();
        for (k, row) in bvh.motion.chunks(bvh.channel_count).enumerate() {
            let mut first = true;
            for &j in &written {
                let joint = &bvh.joints[j];
                let columns = joint.first_channel..joint.first_channel + joint.channels.len();
                for (c, &v) in columns.clone().zip(&row[columns]) {
                    if !first {
                        out.push(' ');
                    }
                    first = false;
                    let own = read_with.then(|| bvh.decimals[k * bvh.channel_count + c]);
                    value(&mut out, &mut shortest, v, own, precision);
                }
            }
            out.push('\n');
        }
    }
    out
}

/// Appends channel value `v`: shortest when it was read in exponent form; at its `own`
/// decimals when that reproduces it up to float noise (it was not changed), else at its
/// the take's `precision`; shortest for a take built by code. A value that rounds to zero is
/// written with a minus sign only when it is `-0` itself (float noise below zero is no sign).
fn value(
    out: &mut String,
    shortest: &mut Shortest,
    v: f64,
    own: Option<u8>,
    precision: Option<u8>,
) {
    let start = out.len();
    let fixed = |out: &mut String, d: u8| {
        let at = out.len();
        let _ = write!(out, "{v:.*}", d as usize);
        let zero = !out[at..].bytes().any(|b| (b'1'..=b'9').contains(&b));
        if zero && v != 0.0 && out[at..].starts_with('-') {
            out.remove(at);
        }
    };
    if own == Some(super::SHORTEST) {
        // read in exponent form (or past f64's digits): shortest form again
        out.push_str(shortest.format_plain(v));
        return;
    }
    if let Some(d) = own {
        fixed(out, d);
        let noise = 1e-9 * v.abs().max(1.0);
        if out[start..]
            .parse::<f64>()
            .is_ok_and(|back| (back - v).abs() <= noise)
        {
            return;
        }
        out.truncate(start);
    }
    match precision {
        Some(d) => fixed(out, d),
        None => out.push_str(shortest.format_plain(v)),
    }
}

/// Writes `bvh` to `path` atomically (see [`crate::io::write_atomic`]).
pub fn write(bvh: &Bvh, path: &Path) -> Result<(), Error> {
    crate::io::write_atomic(path, write_string(bvh).as_bytes())
}

fn indent(out: &mut String, depth: usize) {
    for _ in 0..depth {
        out.push('\t');
    }
}
