//! Portable BVH: a take rewritten so that every reader reads it the same way.
//!
//! Readers disagree on position channels: three.js's BVHLoader (and most parsers) *add* them to
//! the OFFSET, Blender's importer *replaces* the OFFSET with them. The two readings agree
//! exactly when a joint's position channels are gone or its OFFSET is zero on their axes, so
//! [`portable`] rewrites each joint with position channels (in the mode articula resolved for
//! it, [`ResolvedPosition`]) one of two ways:
//!
//! - **constant** position channels below the root (they restate the OFFSET, or hold a welded
//!   joint's mean) are folded into the OFFSET and dropped: the OFFSET becomes the joint's
//!   translation;
//! - **the root's and moving ones** (a joint kept with `--joint-translations keep`) get an OFFSET of
//!   zero and channels on all three axes holding the joint's translation in its parent's frame
//!   (`OFFSET + value` for a joint that adds, the value for one that replaces, the OFFSET on an
//!   axis without a channel). Zeroing the OFFSET was chosen over dropping because moving
//!   channels cannot be dropped; for the root, whose OFFSET most files already write as zero,
//!   it leaves the values of a replacing take (LaFAN1, PyMO) exactly as the file wrote them.
//!
//! Rotations, End Sites and every value not rewritten are kept as they are, with the decimal
//! places they were read with ([`Bvh::decimals`]); a rewritten value (`OFFSET + value`) gets
//! the larger of its two precisions, so the writer prints no float noise.

use super::{Bvh, BvhJoint, Channel, ResolvedPosition, SHORTEST, decimals_of, joint_translation};

/// How articula writes a take's BVH (`--bvh-style`, the session's `set bvh_style`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BvhStyle {
    /// [`portable`]: every reader reads it alike (the default).
    #[default]
    Portable,
    /// The channel layout as read: every joint keeps the channels and OFFSET the file gave it
    /// (a welded joint's channels hold their mean in every frame); readers that treat position
    /// channels differently (three.js adds, Blender replaces) may then disagree, as they did
    /// on the input.
    AsRead,
}

/// Every [`BvhStyle`] by its name, for the parser and the messages.
pub const BVH_STYLES: &[(&str, BvhStyle)] = &[
    ("portable", BvhStyle::Portable),
    ("as-read", BvhStyle::AsRead),
];

impl std::str::FromStr for BvhStyle {
    type Err = crate::error::Error;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let t = s.trim().to_ascii_lowercase();
        BVH_STYLES
            .iter()
            .find(|(n, _)| *n == t)
            .map(|(_, v)| *v)
            .ok_or_else(|| {
                let names: Vec<&str> = BVH_STYLES.iter().map(|(n, _)| *n).collect();
                crate::error::Error::Invalid(format!(
                    "unknown BVH style {s:?}: expected {}",
                    names.join(" or ")
                ))
            })
    }
}

/// `bvh` as `style` writes it: [`portable`] (with `modes`), or as it is.
pub fn styled<'a>(
    bvh: &'a Bvh,
    modes: &[ResolvedPosition],
    style: BvhStyle,
) -> std::borrow::Cow<'a, Bvh> {
    match style {
        BvhStyle::Portable => std::borrow::Cow::Owned(portable(bvh, modes)),
        BvhStyle::AsRead => std::borrow::Cow::Borrowed(bvh),
    }
}

/// `bvh` with every joint's position channels made unambiguous (see the module
/// documentation); `modes` is the position mode of each joint (`resolve_position_modes`).
/// Forward kinematics of the result in either mode equals that of `bvh` in `modes`.
pub fn portable(bvh: &Bvh, modes: &[ResolvedPosition]) -> Bvh {
    let read_with = bvh.decimals.len() == bvh.motion.len();
    let plans: Vec<Plan> = bvh
        .joints
        .iter()
        .enumerate()
        .map(|(j, joint)| plan(bvh, joint, modes.get(j).copied(), read_with))
        .collect();
    // the joints: channels and offsets per plan, first channels renumbered in joint order
    let mut joints = Vec::with_capacity(bvh.joints.len());
    let mut first = 0;
    for (joint, plan) in bvh.joints.iter().zip(&plans) {
        let mut j = joint.clone();
        j.first_channel = first;
        match plan {
            Plan::Keep => {}
            Plan::Fold { offset } => {
                j.offset = *offset;
                j.channels.retain(|c| c.is_rotation());
            }
            Plan::Absolute { .. } => {
                j.offset = joint.offset.map(|_| 0.0);
                j.channels = [Channel::Xposition, Channel::Yposition, Channel::Zposition]
                    .into_iter()
                    .chain(joint.channels.iter().copied().filter(|c| c.is_rotation()))
                    .collect();
            }
        }
        first += j.channels.len();
        joints.push(j);
    }
    // the frames: each joint's kept values, and the translations of absolute ones
    let mut motion = Vec::with_capacity(bvh.frames * first);
    let mut decimals = Vec::with_capacity(if read_with { motion.capacity() } else { 0 });
    for k in 0..bvh.frames {
        let row = bvh.frame(k);
        let own = |c: usize| bvh.decimals[k * bvh.channel_count + c];
        for ((joint, plan), mode) in bvh.joints.iter().zip(&plans).zip(modes) {
            if let Plan::Absolute { axis_decimals } = plan {
                let t = joint_translation(joint, *mode, row);
                let cols = joint.position_columns();
                for axis in 0..3 {
                    motion.push(t[axis]);
                    if read_with {
                        let d = cols[axis].map(|n| own(joint.first_channel + n));
                        decimals.push(widest(d, axis_decimals[axis]));
                    }
                }
            }
            for (n, c) in joint.channels.iter().enumerate() {
                if c.is_rotation() || matches!(plan, Plan::Keep) {
                    motion.push(row[joint.first_channel + n]);
                    if read_with {
                        decimals.push(own(joint.first_channel + n));
                    }
                }
            }
        }
    }
    Bvh {
        joints,
        frame_time: bvh.frame_time,
        frames: bvh.frames,
        channel_count: first,
        motion,
        first_frame: bvh.first_frame,
        decimals,
    }
}

/// What [`portable`] does with one joint.
enum Plan {
    /// No position channels: as it is.
    Keep,
    /// Constant position channels: dropped, `offset` the joint's translation (file units).
    Fold { offset: nalgebra::Vector3<f64> },
    /// Moving ones: OFFSET zero, X/Y/Z position channels with the translation; the decimals
    /// the OFFSET contributes per axis (0 on an axis where the channel replaces it).
    Absolute { axis_decimals: [u8; 3] },
}

fn plan(bvh: &Bvh, joint: &BvhJoint, mode: Option<ResolvedPosition>, read_with: bool) -> Plan {
    let mode = match mode {
        Some(m @ (ResolvedPosition::Add | ResolvedPosition::Replace)) if joint.has_position() => m,
        _ => return Plan::Keep,
    };
    let cols = joint.position_columns();
    // decimals the OFFSET adds to each axis's translation: where the channel adds to it, or
    // where there is no channel
    let mut shortest = crate::io::shortest::Shortest::new();
    let axis_decimals: [u8; 3] = std::array::from_fn(|axis| {
        let counts = cols[axis].is_none() || mode == ResolvedPosition::Add;
        if counts {
            decimals_of(shortest.format(joint.offset[axis]))
        } else {
            0
        }
    });
    let constant = cols.iter().flatten().all(|&n| {
        let c = joint.first_channel + n;
        let v0 = bvh.motion.get(c).copied();
        (0..bvh.frames).all(|k| Some(bvh.frame(k)[c]) == v0)
    });
    // the root keeps its channels even when they do not move: without them a reader (and
    // articula) would take the body as fixed to the world
    if !constant || joint.parent.is_none() {
        return Plan::Absolute { axis_decimals };
    }
    let row = if bvh.frames > 0 { bvh.frame(0) } else { &[] };
    if row.is_empty() {
        return Plan::Fold {
            offset: joint.offset,
        };
    }
    let t = joint_translation(joint, mode, row);
    let offset = nalgebra::Vector3::from_fn(|axis, _| {
        if !read_with {
            return t[axis];
        }
        let d = cols[axis].map(|n| bvh.decimals[joint.first_channel + n]);
        match widest(d, axis_decimals[axis]) {
            SHORTEST => t[axis],
            d => round_to(t[axis], d),
        }
    });
    Plan::Fold { offset }
}

/// The larger of a value's decimals and the OFFSET's ([`SHORTEST`] wins).
fn widest(value: Option<u8>, offset: u8) -> u8 {
    match value {
        Some(SHORTEST) => SHORTEST,
        Some(d) => d.max(offset),
        None => offset,
    }
}

/// `x` rounded to `d` decimal places (through its decimal text, so no float noise remains).
fn round_to(x: f64, d: u8) -> f64 {
    format!("{x:.*}", d as usize).parse().unwrap_or(x)
}
