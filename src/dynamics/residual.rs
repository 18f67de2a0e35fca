//! How dynamically consistent a take is: the root residuals against Hicks et al.'s thresholds,
//! and the two model and motion adjustments that residual reduction makes (OpenSim's RRA).
//!
//! Hicks, Uchida, Seth, Rajagopal & Delp 2015, "Is my model good enough? Best practices for
//! verification and validation of musculoskeletal models and simulations of movement",
//! *J. Biomech. Eng.* 137, 020905, table 2: the peak residual force at most 5 % of the peak
//! external force, the RMS residual moment at most 1 % of the centre of mass height times the
//! peak external force. Here the external force is the feet's ground reactions together
//! ([`GroundReactions::grf`]) and the residual the root's ([`GroundReactions::residual`],
//! about the pelvis, world axes, as OpenSim reports the pelvis's FX..MZ).
//!
//! Which frames count: all but those within the estimator's spread
//! ([`ContactParams::spread_s`]) of the take's first and last frame, where the smoothed
//! accelerations are extrapolated and no one's to trust ([`counted_frames`]). Flight frames
//! count: a ballistic body needs no wrench, so what the motion needs there is residual too.
//!
//! [`ContactParams::spread_s`]: crate::motion::contact::ContactParams::spread_s

use super::Workspace;
use super::grf::GroundReactions;
use crate::model::Model;
use crate::spatial::SpatialInertia;
use nalgebra::Vector3;

/// Hicks et al. 2015: peak residual force ≤ this share of the peak external force.
pub const FORCE_SHARE: f64 = 0.05;
/// Hicks et al. 2015: RMS residual moment ≤ this share of COM height × peak external force.
pub const MOMENT_SHARE: f64 = 0.01;

/// A take's residual figures (Hicks et al. 2015) over its counted frames.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ResidualFigures {
    /// Largest |Σ feet ground force| (N).
    pub peak_external_n: f64,
    /// Largest |residual force| (N) and its frame.
    pub peak_force_n: f64,
    pub peak_force_frame: usize,
    /// RMS of |residual moment| about the pelvis (N·m).
    pub rms_moment_nm: f64,
    /// Mean height of the whole-body centre of mass over the floor (m).
    pub com_height_m: f64,
    /// Frames counted.
    pub frames: usize,
}

impl ResidualFigures {
    /// The peak residual force as a percentage of the peak external force (threshold 5 %).
    pub fn force_pct(&self) -> f64 {
        100.0 * self.peak_force_n / self.peak_external_n.max(1e-9)
    }
    /// The RMS residual moment as a percentage of COM height × peak external force (1 %).
    pub fn moment_pct(&self) -> f64 {
        100.0 * self.rms_moment_nm / (self.com_height_m * self.peak_external_n).max(1e-9)
    }
    /// The residual force a frame may have (N).
    pub fn force_limit_n(&self) -> f64 {
        FORCE_SHARE * self.peak_external_n
    }
    /// The RMS residual moment the take may have (N·m).
    pub fn moment_limit_nm(&self) -> f64 {
        MOMENT_SHARE * self.com_height_m * self.peak_external_n
    }
    /// Both of Hicks et al.'s thresholds met.
    pub fn meets(&self) -> bool {
        self.peak_external_n > 0.0
            && self.peak_force_n <= self.force_limit_n()
            && self.rms_moment_nm <= self.moment_limit_nm()
    }
    /// Whether frame `k`'s residual `r` (`[fx, fy, fz, tx, ty, tz]`) lies beyond the
    /// thresholds: its force beyond the force limit, or its moment beyond the RMS limit.
    pub fn beyond(&self, r: &[f64; 6]) -> bool {
        let (f, n) = split_norms(r);
        f > self.force_limit_n() || n > self.moment_limit_nm()
    }
}

/// |force| and |moment| of a residual `[fx, fy, fz, tx, ty, tz]`.
pub fn split_norms(r: &[f64; 6]) -> (f64, f64) {
    (
        Vector3::new(r[0], r[1], r[2]).norm(),
        Vector3::new(r[3], r[4], r[5]).norm(),
    )
}

/// The frames the figures count: all but `spread` frames at each end of a take of `n` (all,
/// when that would leave fewer than a third of them).
pub fn counted_frames(n: usize, spread: usize) -> Vec<bool> {
    if n < 3 * (2 * spread).max(1) {
        return vec![true; n];
    }
    (0..n).map(|k| k >= spread && k + spread < n).collect()
}

/// Hicks et al.'s figures of the residuals `residual` (per frame, about the pelvis) against the
/// external forces `external` (per frame, N) and the heights `com_height` (m) of the centre of
/// mass, over the frames `counted`.
pub fn residual_figures(
    residual: &[[f64; 6]],
    external: &[Vector3<f64>],
    com_height: &[f64],
    counted: &[bool],
) -> ResidualFigures {
    let frames: Vec<usize> = (0..residual.len()).filter(|&k| counted[k]).collect();
    let mut out = ResidualFigures {
        peak_external_n: 0.0,
        peak_force_n: 0.0,
        peak_force_frame: 0,
        rms_moment_nm: 0.0,
        com_height_m: 0.0,
        frames: frames.len(),
    };
    let mut sum_n2 = 0.0;
    for &k in &frames {
        let (f, n) = split_norms(&residual[k]);
        out.peak_external_n = out.peak_external_n.max(external[k].norm());
        if f > out.peak_force_n {
            (out.peak_force_n, out.peak_force_frame) = (f, k);
        }
        sum_n2 += n * n;
        out.com_height_m += com_height[k];
    }
    let count = frames.len().max(1) as f64;
    out.rms_moment_nm = (sum_n2 / count).sqrt();
    out.com_height_m /= count;
    out
}

/// The feet's ground force together at each frame of `gr` (N, world).
pub fn external_forces(gr: &GroundReactions) -> Vec<Vector3<f64>> {
    gr.grf.iter().map(|g| g.iter().sum()).collect()
}

/// The whole-body centre of mass (world, m) from the poses `ws.o_x_i` of
/// [`forward_kinematics`](super::forward_kinematics): `Σ mᵢ cᵢ / Σ mᵢ`.
///
/// The bodies without mass (two in three of a BVH euler model's) are passed over: their term
/// is a signed zero (of a finite pose), and a sum started at `+0` is never `−0` (a sum is `−0`
/// only of two `−0`), so adding it changes no bit.
pub fn centre_of_mass(model: &Model, ws: &Workspace) -> Vector3<f64> {
    let mut sum = Vector3::zeros();
    let mut mass = 0.0;
    for (i, inertia) in model.inertia.iter().enumerate().skip(1) {
        if inertia.mass == 0.0 {
            continue;
        }
        sum += ws.o_x_i[i].transform_point(&inertia.com) * inertia.mass;
        mass += inertia.mass;
    }
    sum / mass.max(1e-12)
}

/// `model` with the centre of mass of each body in `trunk` moved by `offset` (m, in the
/// body's own frame; BVH bodies share the file's axes at rest), the rotational inertia about
/// each centre unchanged: RRA's torso mass-centre adjustment spread over a trunk of several
/// links.
pub fn with_trunk_offset(model: &Model, trunk: &[usize], offset: &Vector3<f64>) -> Model {
    let mut m = model.clone();
    for &b in trunk {
        let i = &model.inertia[b];
        m.inertia[b] = SpatialInertia::new(i.mass, i.com + offset, i.inertia_com);
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_are_the_peak_force_and_rms_moment_against_hicks_thresholds() {
        // 4 frames; the first and last not counted
        let residual = [
            [500.0, 0.0, 0.0, 0.0, 0.0, 900.0],
            [30.0, 40.0, 0.0, 3.0, 4.0, 0.0],
            [0.0, 0.0, 10.0, 0.0, 0.0, 10.0],
            [800.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        ];
        let external = [
            Vector3::new(0.0, 5000.0, 0.0),
            Vector3::new(0.0, 1000.0, 0.0),
            Vector3::new(0.0, 600.0, 800.0),
            Vector3::zeros(),
        ];
        let counted = counted_frames(4, 1);
        assert_eq!(counted, vec![true; 4], "too short to leave ends out");
        let counted = [false, true, true, false];
        let f = residual_figures(&residual, &external, &[0.9, 1.0, 0.8, 0.9], &counted);
        assert_eq!(f.frames, 2);
        assert!((f.peak_external_n - 1000.0).abs() < 1e-12);
        assert!((f.peak_force_n - 50.0).abs() < 1e-12 && f.peak_force_frame == 1);
        // moments 5 and 10 N·m: RMS √62.5
        assert!((f.rms_moment_nm - 62.5f64.sqrt()).abs() < 1e-12);
        assert!((f.com_height_m - 0.9).abs() < 1e-12);
        assert!((f.force_pct() - 5.0).abs() < 1e-12);
        assert!((f.moment_pct() - 100.0 * 62.5f64.sqrt() / 900.0).abs() < 1e-12);
        assert!(f.meets());
        assert!(f.beyond(&[0.0, 0.0, 0.0, 0.0, 9.1, 0.0]));
        assert!(!f.beyond(&[49.0, 0.0, 0.0, 0.0, 8.9, 0.0]));
        let worse = residual_figures(&residual, &external, &[0.9; 4], &[true; 4]);
        assert!(!worse.meets() && worse.peak_force_frame == 3);
        assert_eq!(
            counted_frames(12, 2),
            [vec![false; 2], vec![true; 8], vec![false; 2]].concat()
        );
    }
}
