//! What the ground-reaction estimate gives ([`GroundReactions`]: the feet's loads, the
//! residual, the joint torques with them, frame by frame) and how far the feet could give the
//! force the motion needs ([`GroundQuality`]).

use super::share::*;
use super::{Model, Workspace, passes};
use crate::spatial::{ForceVec, SpatialTransform};
use nalgebra::Vector3;

/// Ground reactions and the inverse dynamics with them, frame by frame. World quantities are in
/// the take's axes, moments about the root joint's origin (the pelvis) unless said otherwise.
#[derive(Debug, Clone, PartialEq)]
pub struct GroundReactions {
    /// Foot names (`left`, `right`): the order of every per-foot vector below.
    pub feet: Vec<String>,
    /// The body each foot's load acts on (the foot's `ankle_body`).
    pub bodies: Vec<usize>,
    /// The up axis (0, 1, 2) of the world.
    pub up: usize,
    /// Floor height along the up axis (m).
    pub floor: f64,
    /// `[frame][foot]`: the foot is in contact.
    pub contact: Vec<Vec<bool>>,
    /// `[frame][foot]`: the foot carries load: it is in contact, or the frame is a flight frame
    /// within [`ContactParams::spread_s`] of the foot's contact phase, where the smoothed
    /// estimate still needs a pressing force (see [`carry_across_spread`]).
    pub loaded: Vec<Vec<bool>>,
    /// `[frame]`: the height (m) of the lowest foot point over the floor: the least of every
    /// foot's heel and toe heights over the floor levels of the heel and of the toe points,
    /// the heights the contact test measures ([`point_levels`]); where it exceeds the contact
    /// height no foot can touch the floor ([`GroundReactions::floor_lost`]). Empty for
    /// measured ground reactions, whose feet's paths are not known, and for the residual alone
    /// ([`estimate_ground_residuals`], residual reduction's trials).
    ///
    /// [`point_levels`]: crate::motion::contact::point_levels
    pub foot_height: Vec<f64>,
    /// `[frame][foot]`: force of the ground on the foot (N, world axes); zero off the floor.
    pub grf: Vec<Vec<Vector3<f64>>>,
    /// `[frame][foot]`: centre of pressure of that force on the floor (m, world); for an
    /// unloaded foot, its ankle's projection on the floor (so that plots stay continuous).
    pub cop: Vec<Vec<Vector3<f64>>>,
    /// `[frame][foot]`: free moment of the ground on the foot about the vertical (N·m).
    pub free_moment: Vec<Vec<f64>>,
    /// `[frame]`: the whole-body external wrench the motion needs, `[fx, fy, fz, tx, ty, tz]`
    /// (N, N·m about the root joint's origin, world axes): the root residual without contact.
    pub wrench: Vec<[f64; 6]>,
    /// `[frame]`: what the root still supplies with the ground reactions applied, same layout.
    pub residual: Vec<[f64; 6]>,
    /// `[frame]`: the root joint's origin (m, world): the point `wrench` and `residual` are
    /// taken about.
    pub pelvis: Vec<Vector3<f64>>,
    /// `[frame]`: the whole-body centre of mass (m, world;
    /// [`centre_of_mass`](super::residual::centre_of_mass) of the frame's kinematics).
    pub com: Vec<Vector3<f64>>,
    /// `[frame]`: how far (m, along the floor) the centre of pressure of the feet's loads
    /// together lies from the one the whole-body wrench needs; 0 where they coincide, where no
    /// foot is loaded, or where the motion needs no pressing force. It grows where the needed
    /// centre of pressure leaves the feet (the loads keep theirs inside) or a force leaves the
    /// friction cone: the motion asks for a ground force no foot can give, and the joint
    /// torques there are those of the nearest one the feet can ([`GroundReactions::quality`]).
    pub cop_gap: Vec<f64>,
    /// `[frame][nv]`: generalized forces with the ground reactions applied (N·m, N).
    pub tau: Vec<Vec<f64>>,
    /// The bodies whose net moment with the ground reactions was kept (asked of
    /// [`estimate_ground_reactions_keeping`]; empty otherwise), sorted, each once.
    pub moment_bodies: Vec<usize>,
    /// `[frame * moment_bodies.len() + j]`: the net moment `f.ang` of RNEA with the ground
    /// reactions on body `moment_bodies[j]` (N·m, the body's frame, as `ws.f` holds it): what
    /// the joint moments of `pipeline::anatomy` read, from the estimate's own pass.
    pub moments: Vec<Vector3<f64>>,
}

impl GroundReactions {
    /// CSV column names: `grf:<foot>:x|y|z`, `cop:<foot>:x|y|z` per foot, then
    /// `residual:fx|fy|fz|tx|ty|tz`.
    pub fn columns(&self) -> Vec<String> {
        let mut c = vec![];
        for what in ["grf", "cop"] {
            for f in &self.feet {
                c.extend(["x", "y", "z"].map(|a| format!("{what}:{f}:{a}")));
            }
        }
        c.extend(["fx", "fy", "fz", "tx", "ty", "tz"].map(|a| format!("residual:{a}")));
        c
    }

    /// The values of [`columns`](Self::columns) at frame `k`, appended to `out`.
    pub fn row(&self, k: usize, out: &mut Vec<f64>) {
        for per_foot in [&self.grf[k], &self.cop[k]] {
            for p in per_foot {
                out.extend_from_slice(p.as_slice());
            }
        }
        out.extend_from_slice(&self.residual[k]);
    }

    /// The ground's loads at frame `k` as external forces per body for
    /// [`rnea`](super::rnea) (`out` has `nbodies` entries, zeroed first): each foot's force at
    /// its centre of pressure with its free moment, in the frame of the body it acts on, from
    /// the world poses `o_x_i` of that frame (`forward_kinematics`).
    pub fn external_forces(&self, k: usize, o_x_i: &[SpatialTransform], out: &mut [ForceVec]) {
        out.fill(ForceVec::ZERO);
        for (j, &b) in self.bodies.iter().enumerate() {
            out[b] += o_x_i[b].act_inv_force(&self.foot_wrench(k, j));
        }
    }

    /// Foot `j`'s load at frame `k` as a wrench about the world origin (world axes): its force
    /// at its centre of pressure with its free moment about the vertical.
    pub fn foot_wrench(&self, k: usize, j: usize) -> ForceVec {
        let load = FootLoad {
            force: self.grf[k][j],
            cop: self.cop[k][j],
            free_moment: self.free_moment[k][j],
        };
        load.wrench(&Vector3::ith(self.up, 1.0))
    }

    /// The ground's loads at frame `k` taken from what RNEA without them left: from the
    /// generalized forces `tau` (when given) and from the net moments `moments` (each body's
    /// frame, as `ws.f[b].ang`) of `moment_bodies` (sorted). Inverse dynamics is linear in the
    /// external forces, so this is RNEA with the loads to rounding; it is how every caller
    /// applies them (the estimate's pass 3, the measured loads, the anatomical series), so all
    /// give the same bits. `ws.o_x_i` holds frame `k`'s world poses of the bodies on the feet's
    /// paths to the world (`forward_kinematics`).
    pub fn take_from(
        &self,
        model: &Model,
        k: usize,
        ws: &Workspace,
        mut tau: Option<&mut [f64]>,
        (moment_bodies, moments): (&[usize], &mut [Vector3<f64>]),
    ) {
        for (j, &b) in self.bodies.iter().enumerate() {
            let w = self.foot_wrench(k, j);
            passes::take_load(
                model,
                ws,
                &w,
                b,
                tau.as_deref_mut(),
                (|i| moment_bodies.binary_search(&i).ok(), &mut *moments),
            );
        }
    }

    /// How far the feet can give the ground force the motion needs, over the frames of single
    /// support (one foot loaded), where the needed force and centre of pressure are the
    /// motion's alone (in double support they also depend on how the load is shared): the
    /// share of them whose [`cop_gap`](Self::cop_gap) exceeds [`COP_GAP_TOLERANCE`], the
    /// median gap and the largest.
    pub fn quality(&self) -> GroundQuality {
        let mut single: Vec<usize> = (0..self.loaded.len())
            .filter(|&k| self.loaded[k].iter().filter(|l| **l).count() == 1)
            .collect();
        let outside = single
            .iter()
            .filter(|&&k| self.cop_gap[k] > COP_GAP_TOLERANCE)
            .count();
        single.sort_by(|&a, &b| self.cop_gap[a].total_cmp(&self.cop_gap[b]));
        GroundQuality {
            single_support_frames: single.len(),
            outside_frames: outside,
            median_gap: single
                .get(single.len() / 2)
                .map_or(0.0, |&k| self.cop_gap[k]),
            largest_gap: single.last().map_or(0.0, |&k| self.cop_gap[k]),
            largest_gap_frame: single.last().copied().unwrap_or(0),
        }
    }
}

/// A centre of pressure gap ([`GroundReactions::cop_gap`]) up to this is agreement (m): 2 cm,
/// within the 5 cm the support is widened by ([`ContactParams::cop_margin`]).
pub const COP_GAP_TOLERANCE: f64 = 0.02;

/// [`GroundReactions::quality`]: how far the ground force the motion needs in single support
/// is one the foot can give.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GroundQuality {
    /// Frames where exactly one foot carries load.
    pub single_support_frames: usize,
    /// Of those, frames whose centre of pressure gap exceeds [`COP_GAP_TOLERANCE`].
    pub outside_frames: usize,
    /// The median gap over those frames (m).
    pub median_gap: f64,
    /// The largest gap (m) and its frame.
    pub largest_gap: f64,
    pub largest_gap_frame: usize,
}

impl GroundQuality {
    /// The share of single-support frames where the foot cannot give the needed ground force.
    pub fn outside_share(&self) -> f64 {
        self.outside_frames as f64 / self.single_support_frames.max(1) as f64
    }
}

impl std::fmt::Display for GroundQuality {
    /// One line for a user, e.g. `ground reactions: in 68 % of the 146 single-support frames
    /// the motion needs its centre of pressure more than 2 cm outside the foot (median 4.5 cm,
    /// up to 12.6 cm at frame 72); there the joint torques are those of the nearest force the
    /// foot can give, and the rest stays at the root (residual columns)`.
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        let tol = 100.0 * COP_GAP_TOLERANCE;
        if self.single_support_frames == 0 {
            return write!(f, "ground reactions: no frame of single support");
        }
        if self.outside_frames == 0 {
            return write!(
                f,
                "ground reactions: in all {} single-support frames the foot gives the force the \
                 motion needs (centre of pressure within {tol:.0} cm)",
                self.single_support_frames
            );
        }
        write!(
            f,
            "ground reactions: in {:.0} % of the {} single-support frames the motion needs its \
             centre of pressure more than {tol:.0} cm outside the foot (median {:.1} cm, up to \
             {:.1} cm at frame {}); there the joint torques are those of the nearest force the \
             foot can give, and the rest stays at the root (residual columns)",
            100.0 * self.outside_share(),
            self.single_support_frames,
            100.0 * self.median_gap,
            100.0 * self.largest_gap,
            self.largest_gap_frame
        )
    }
}
