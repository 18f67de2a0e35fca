//! Biovision BVH: the plain description of a take (skeleton + raw channel values).
//!
//! Written by hand: the BVH crates on crates.io are unmaintained and lossy (they drop
//! per-joint rotation orders, position channels on non-root joints, or exact values). This
//! reader keeps everything as written and reports malformed input as
//! [`Error::Parse`](crate::error::Error::Parse) with file, line, column and what was expected;
//! it never panics.
//!
//! - [`parse_str`] / [`parse_bytes`] / [`read`]: text → [`Bvh`] (`parse` module);
//! - [`write_string`] / [`write`](fn@write): [`Bvh`] → text that Blender and three.js read,
//!   values printed in their shortest exact form so parse → write → parse is lossless
//!   (`write` module);
//! - [`semantics`]: what the numbers mean: position-channel modes, forward kinematics straight
//!   from the definition, up axis, length unit and stature.
//!
//! Everything in this module is in the file's own units (lengths as written, angles in
//! degrees). Conversion to SI happens when a `Model` and a trajectory are built.
//!
//! # BVH semantics and variants
//!
//! - **Rotations.** Rotation channels `c1 c2 c3` mean `R = R_c1(a1) · R_c2(a2) · R_c3(a3)`
//!   (intrinsic rotations in the listed order, right-handed, degrees), see
//!   [`crate::rotation`]. Orders differ per joint (Daz/Poser files: root ZYX, others ZXY).
//!   Angles are kept as written, unwrapped (pirouette.bvh reaches 573.6°).
//! - **Local transform.** A joint's pose in its parent frame is `T(offset) · T(p) · R`, where
//!   `p` comes from its position channels. Position channels may appear on any joint (Bandai
//!   and MakeHuman files have them on non-root joints), in any order, with or without
//!   rotations. Below the body's root the pipeline welds them at their mean by default
//!   ([`semantics::JointTranslations`], `motion::weld`): bones do not stretch.
//! - **Add or replace.** Files disagree on whether position channels *add* to the OFFSET
//!   (MakeHuman: all zeros; most parsers) or *replace* it (Blender's importer; Bandai: channel
//!   values equal to the OFFSET; PyMO's root). [`semantics::PositionMode`] chooses `add`,
//!   `replace`, or `auto` (per joint from the data, see
//!   [`semantics::resolve_position_modes`]).
//! - **End Sites** carry only an OFFSET (zero in some files); a joint may have several.
//! - **Units and axes** are not in the file: [`semantics::detect_up`] takes the axis of
//!   largest body extent over the take (the rest pose breaks T-pose ties), and
//!   [`semantics::detect_unit`] the unit that makes the stature plausible (1.0–2.3 m, nearest
//!   1.7 m): m, dm, cm, mm, inches, or the CMU conversion's unit of 1/0.45 in ≈ 0.0564 m.
//!   MakeHuman files are Z-up in decimetres, the rest Y-up. Users override both (`--up`,
//!   `--unit`, `--stature`).
//! - **Rest poses that are not standing:** the Bandai files' bones lie along local X, so the
//!   OFFSET-only pose lies on its side; the stature then comes from the frames
//!   ([`semantics::stature`]).
//! - **Lexical variants accepted:** CRLF, LF, lone CR and mixtures in one file; a missing final
//!   newline; a UTF-8 byte-order mark; tabs or spaces; trailing whitespace; blank lines;
//!   keywords in any letter case; `Frames:\t592` or `Frames : 592`; `Frame Time: .0083333`;
//!   scientific notation; `-0`; joint names with `:` `.` `_` or any other non-blank
//!   characters (one word).
//! - **Rejected:** anything else (see `tests/bvh_malformed.rs`): a missing section, an
//!   unknown channel, a channel listed twice, more than 6 channels, duplicate joint names, a
//!   second ROOT, End Sites with channels or children, non-numeric or non-finite values,
//!   frame lines with the wrong number of values, fewer or more frame lines than `Frames:`,
//!   `Frames: 0`, a zero or negative frame time, unbalanced braces.

mod frames;
pub mod parse;
pub mod portable;
pub mod semantics;
pub mod write;

pub use parse::{parse_bytes, parse_str, read};
pub use portable::{BVH_STYLES, BvhStyle, portable, styled};
pub use semantics::{
    JointTranslations, LengthUnit, PositionMode, ResolvedPosition, STANDARD_STATURE_M,
    STATURE_RANGE_M, Scale, UpAxis, bvh_end_site_positions, bvh_world_poses, bvh_world_positions,
    check_given_stature, check_stature, choose_scale, detect_unit, detect_up, detect_up_by_feet,
    detect_up_by_legs, joint_rotation, joint_translation, resolve_position_modes, rest_points,
    rest_stature, scale_for_stature, stature,
};
pub use write::{write, write_string};

use crate::rotation::EulerOrder;
use nalgebra::Vector3;

/// One channel of a BVH joint, in the order the file lists them.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Channel {
    Xposition,
    Yposition,
    Zposition,
    Xrotation,
    Yrotation,
    Zrotation,
}

impl Channel {
    /// The name as written in a BVH file (`Xrotation`, ...).
    pub fn name(self) -> &'static str {
        match self {
            Channel::Xposition => "Xposition",
            Channel::Yposition => "Yposition",
            Channel::Zposition => "Zposition",
            Channel::Xrotation => "Xrotation",
            Channel::Yrotation => "Yrotation",
            Channel::Zrotation => "Zrotation",
        }
    }
    /// 0, 1, 2 for X, Y, Z.
    pub fn axis(self) -> usize {
        match self {
            Channel::Xposition | Channel::Xrotation => 0,
            Channel::Yposition | Channel::Yrotation => 1,
            Channel::Zposition | Channel::Zrotation => 2,
        }
    }
    /// The six channels.
    pub const ALL: [Channel; 6] = [
        Channel::Xposition,
        Channel::Yposition,
        Channel::Zposition,
        Channel::Xrotation,
        Channel::Yrotation,
        Channel::Zrotation,
    ];
    /// The channel called `name` (`Xrotation`, ...; ASCII case ignored).
    pub fn from_name(name: &str) -> Option<Channel> {
        Self::ALL
            .into_iter()
            .find(|c| c.name().eq_ignore_ascii_case(name))
    }
    /// True for `Xrotation`, `Yrotation`, `Zrotation`.
    pub fn is_rotation(self) -> bool {
        matches!(
            self,
            Channel::Xrotation | Channel::Yrotation | Channel::Zrotation
        )
    }
}

/// One ROOT or JOINT of the hierarchy.
#[derive(Debug, Clone, PartialEq)]
pub struct BvhJoint {
    /// Name as written (may contain `:` `.` `_`).
    pub name: String,
    /// Index of the parent joint in `Bvh::joints`; `None` for the root. Always `parent < self`.
    pub parent: Option<usize>,
    /// OFFSET, file length units, parent joint frame.
    pub offset: Vector3<f64>,
    /// CHANNELS in file order.
    pub channels: Vec<Channel>,
    /// Column of this joint's first channel in a frame row.
    pub first_channel: usize,
    /// End Site OFFSETs below this joint (file length units, this joint's frame). Usually 0 or 1.
    pub end_sites: Vec<Vector3<f64>>,
    /// 1-based line of the ROOT/JOINT keyword, for error messages downstream.
    pub line: usize,
}

impl BvhJoint {
    /// The Euler order of this joint's rotation channels in file order, when it has exactly
    /// three (on distinct axes, which the parser guarantees); `None` otherwise.
    pub fn euler_order(&self) -> Option<EulerOrder> {
        let mut axes = [0; 3];
        let mut n = 0;
        for c in self.channels.iter().filter(|c| c.is_rotation()) {
            if n == 3 {
                return None;
            }
            axes[n] = c.axis();
            n += 1;
        }
        if n == 3 {
            EulerOrder::from_axes(axes)
        } else {
            None
        }
    }
    /// Column (within this joint's channels) of each position axis, if present.
    pub fn position_columns(&self) -> [Option<usize>; 3] {
        let mut cols = [None; 3];
        for (n, c) in self.channels.iter().enumerate() {
            if !c.is_rotation() {
                cols[c.axis()] = Some(n);
            }
        }
        cols
    }
    /// True when the joint has at least one position channel.
    pub fn has_position(&self) -> bool {
        self.channels.iter().any(|c| !c.is_rotation())
    }
}

/// A parsed BVH file.
#[derive(Debug, Clone, PartialEq)]
pub struct Bvh {
    /// Joints in file (depth-first) order; `joints[0]` is the root.
    pub joints: Vec<BvhJoint>,
    /// Seconds per frame, > 0, as written.
    pub frame_time: f64,
    /// Number of frames.
    pub frames: usize,
    /// Total channels per frame.
    pub channel_count: usize,
    /// Raw values, `frames × channel_count`, row-major, as written (file units, degrees).
    pub motion: Vec<f64>,
    /// The file's index of `motion`'s first frame: 0 as read, 1 once a rest pose stored as frame
    /// 0 was dropped (`motion::trim`), so that frame `k` keeps the file's time
    /// [`Bvh::time`] `= (first_frame + k)·frame_time`.
    pub first_frame: usize,
    /// Decimal places each value of `motion` was written with (same layout as `motion`:
    /// `-12.50` has 2, see [`decimals_of`]), so the writer prints a value at the precision it was read
    /// with: an unchanged value comes back as written, a changed one without float noise
    /// (`3.4357`, not `3.4356999999999998`). Empty when the values were not read from text (a
    /// take built by code): the writer then prints shortest round-trip numbers.
    /// [`SHORTEST`] for a value whose text has more decimals than an `f64` holds.
    pub decimals: Vec<u8>,
}

/// A [`Bvh::decimals`] entry: print the value in its shortest round-trip form.
pub const SHORTEST: u8 = u8::MAX;

/// The decimal places of a number as written (`-12.50` → 2, `7` → 0, `.5` → 1); [`SHORTEST`]
/// for one in exponent form (`1.5e-05`: printed back in shortest form, as most writers of
/// such files do) or with more than 17 decimals (more than an `f64` holds).
pub fn decimals_of(text: &str) -> u8 {
    if text.contains(['e', 'E']) {
        return SHORTEST;
    }
    match text.split_once('.').map_or(0, |(_, f)| f.len()) {
        d if d <= 17 => d as u8,
        _ => SHORTEST,
    }
}

impl Bvh {
    /// The time (s) of frame `k` on the file's clock: `(first_frame + k)·frame_time`, so
    /// outputs stay in step with the video and force plates the file came with when frames
    /// before it were dropped.
    pub fn time(&self, k: usize) -> f64 {
        (self.first_frame + k) as f64 * self.frame_time
    }

    /// The take's precision: the most decimals any value of `motion` was written with as a
    /// plain decimal ([`Bvh::decimals`]); `None` for a take built by code or written only in
    /// exponent form. The writer prints changed values at it.
    pub fn precision(&self) -> Option<u8> {
        if self.decimals.len() != self.motion.len() {
            return None;
        }
        self.decimals
            .iter()
            .copied()
            .filter(|&d| d != SHORTEST)
            .max()
    }

    /// The raw values of frame `k`.
    pub fn frame(&self, k: usize) -> &[f64] {
        &self.motion[k * self.channel_count..(k + 1) * self.channel_count]
    }
    /// Index of the joint called `name`.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }
}
