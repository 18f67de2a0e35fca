//! Continuity of angle trajectories, before any smoothing or differentiation.
//!
//! Captures store each Euler angle in a bounded range (usually ±180°), so an angle that keeps
//! turning jumps by a full turn; and near gimbal lock (middle angle ±90°) the decomposition of a
//! rotation into a triple flips between the two equivalent triples `(a, b, c)` and
//! `(a ± 180°, 180° − b, c ± 180°)`. Both jumps are artefacts: the rotation itself moves
//! smoothly. Differentiating them gives spikes of thousands of degrees per second.
//!
//! [`unwrap_angles`] removes full turns from one angle; [`make_euler_continuous`] re-picks
//! whole triples, which also handles the branch flips.

use crate::rotation::{EulerOrder, euler_to_matrix, matrix_to_euler_near};

/// The unit of an angle trajectory: the period of a full turn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AngleUnit {
    /// Full turn = 360 (BVH channels).
    Degrees,
    /// Full turn = 2π (q).
    Radians,
}

impl AngleUnit {
    /// A full turn in this unit.
    pub fn full_turn(self) -> f64 {
        match self {
            AngleUnit::Degrees => 360.0,
            AngleUnit::Radians => std::f64::consts::TAU,
        }
    }
}

/// Removes full-turn jumps in place: every frame is shifted by a whole number of turns so that
/// it differs from the (already unwrapped) previous frame by at most half a turn (the classic
/// phase unwrapping, as NumPy's `unwrap`). The first frame is kept. Allocates nothing.
pub fn unwrap_angles(unit: AngleUnit, x: &mut [f64]) {
    let turn = unit.full_turn();
    for k in 1..x.len() {
        let d = x[k] - x[k - 1];
        x[k] -= turn * (d / turn).round();
    }
}

/// Makes a trajectory of Euler triples (radians, `R = R_c1(a1) R_c2(a2) R_c3(a3)` for
/// `order = c1 c2 c3`) continuous in place: every frame after the first is replaced by the
/// triple of the same rotation nearest to the previous (already continuous) frame
/// (`rotation::matrix_to_euler_near`: both Tait–Bryan branches, whole-turn shifts, and at
/// gimbal lock the first angle held). This removes both full-turn jumps and branch flips near
/// the singularity; the rotations themselves are unchanged. Allocates nothing.
pub fn make_euler_continuous(order: EulerOrder, frames: &mut [[f64; 3]]) {
    for k in 1..frames.len() {
        let r = euler_to_matrix(order, frames[k]);
        frames[k] = matrix_to_euler_near(order, &r, frames[k - 1]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn removes_turns_keeps_small_steps() {
        let mut x = [170.0, 179.0, -172.0, -165.0, 175.0, 10.0];
        unwrap_angles(AngleUnit::Degrees, &mut x);
        assert_eq!(x, [170.0, 179.0, 188.0, 195.0, 175.0, 10.0]);
    }
}
