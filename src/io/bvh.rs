//! Biovision BVH: the plain description of a take (skeleton + raw channel values).
//!
//! Written by hand: the BVH crates on crates.io are unmaintained and lossy (they drop
//! per-joint rotation orders, position channels on non-root joints, or exact values).
//!
//! Semantics (see ARCHITECTURE.md): rotation channels `c1 c2 c3` mean
//! `R = R_c1(a1) · R_c2(a2) · R_c3(a3)` (intrinsic, in listed order, degrees); a joint's local
//! transform is `T(offset) · T(position channels) · R`.
//!
//! Everything in this module is in the file's own units (lengths as written, angles in
//! degrees). Conversion to SI happens when a `Model` and a trajectory are built.

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
}

impl Bvh {
    /// The raw values of frame `k`.
    pub fn frame(&self, k: usize) -> &[f64] {
        &self.motion[k * self.channel_count..(k + 1) * self.channel_count]
    }
    /// Index of the joint called `name`.
    pub fn joint_index(&self, name: &str) -> Option<usize> {
        self.joints.iter().position(|j| j.name == name)
    }
}
