//! What an engine call returns: per-frame [`Table`]s gathered in an [`Analysis`], and the
//! helpers that build them from the pipeline's results.

use crate::error::Error;
use crate::model::Model;
use crate::pipeline;
use std::sync::Arc;

/// The ground contact's verdicts in a few words: how often the foot gives the force the
/// motion needs in single support (its centre of pressure within `COP_GAP_TOLERANCE` of the
/// foot), and whether the residuals meet Hicks et al.'s thresholds.
pub(super) fn contact_brief(q: &crate::dynamics::grf::GroundQuality, meets: bool) -> String {
    let feet = if q.single_support_frames == 0 {
        "contact: no single support".to_string()
    } else {
        format!(
            "feet give the force in {:.0} % of single support",
            100.0 * (1.0 - q.outside_share())
        )
    };
    let residuals = if meets { "within" } else { "beyond" };
    format!("{feet}; residuals {residuals} Hicks et al.")
}

/// The anatomical angles (rad) and moments (N·m) of a human take as a table
/// ([`Analysis::anatomy`]); empty for a take that is not a human's, or whose segments have no
/// frame somewhere (the inverse dynamics stands without them).
pub(super) fn anatomy_table(a: Result<pipeline::anatomy::Anatomy, Error>) -> Table {
    let Ok(a) = a else {
        return Table::zeros(vec![], 0);
    };
    let keep: Vec<(usize, String, f64)> = a
        .names
        .iter()
        .enumerate()
        .filter_map(|(i, n)| {
            if let Some(b) = n.strip_suffix(":angle") {
                Some((i, format!("{b}:angle"), 1f64.to_radians()))
            } else {
                n.strip_suffix(":moment")
                    .map(|b| (i, format!("{b}:moment"), 1.0))
            }
        })
        .collect();
    let frames = a.time.len();
    let mut out = Table::zeros(keep.iter().map(|k| k.1.clone()).collect(), frames);
    for k in 0..frames {
        let row = out.row_mut(k);
        for (c, (i, _, f)) in keep.iter().enumerate() {
            row[c] = a.columns[*i][k] * f;
        }
    }
    out
}

/// A per-frame table: `frames × names.len()` values, row-major.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Table {
    pub names: Vec<String>,
    pub data: Vec<f64>,
}

impl Table {
    /// An all-zero table.
    pub fn zeros(names: Vec<String>, frames: usize) -> Self {
        let data = vec![0.0; frames * names.len()];
        Self { names, data }
    }
    /// Number of columns.
    pub fn cols(&self) -> usize {
        self.names.len()
    }
    /// Number of rows (frames).
    pub fn rows(&self) -> usize {
        self.data.len().checked_div(self.cols()).unwrap_or(0)
    }
    /// Row `k`.
    pub fn row(&self, k: usize) -> &[f64] {
        &self.data[k * self.cols()..(k + 1) * self.cols()]
    }
    /// Row `k`, mutable.
    pub fn row_mut(&mut self, k: usize) -> &mut [f64] {
        let c = self.cols();
        &mut self.data[k * c..(k + 1) * c]
    }
    /// Index of the column called `name`.
    pub fn col_index(&self, name: &str) -> Option<usize> {
        self.names.iter().position(|n| n == name)
    }
    /// Column `j` as a vector.
    pub fn column(&self, j: usize) -> Vec<f64> {
        (0..self.rows()).map(|k| self.row(k)[j]).collect()
    }
}

/// The results of inverse dynamics over a take.
#[derive(Debug, Clone)]
pub struct Analysis {
    pub model: Arc<Model>,
    /// Time of each frame (s).
    pub time: Vec<f64>,
    /// Configuration per frame (`nq` columns, rad / m); shared with the last results when
    /// they are of the same [`states`](Self::states).
    pub q: Arc<Table>,
    /// Velocity (`nv` columns, rad/s, m/s), shared as `q`.
    pub v: Arc<Table>,
    /// Acceleration (`nv` columns, rad/s², m/s²), shared as `q`.
    pub a: Arc<Table>,
    /// Generalized forces (`nv` columns, N·m / N).
    pub tau: Table,
    /// Metres per file unit used for the take.
    pub scale: f64,
    /// A one-line summary for messages (a simulation's tracking error), or empty.
    pub note: String,
    /// [`note`](Self::note) in a few words for a status line (`feet give the force in 88 % of
    /// single support; residuals within Hicks et al.`), or empty.
    pub brief: String,
    /// A human take's anatomical series (`pipeline::anatomy`): `<joint>:<axis>:angle` (rad)
    /// and `<joint>:<axis>:moment` (N·m) per frame, `knee_l:flexion:angle`; empty otherwise.
    pub anatomy: Table,
    /// Per frame, why its accelerations and torques are not quoted (issue 14: peaks, minima,
    /// maxima and the charts' markers leave these frames out, the charts shade them); `None`
    /// for a frame that is. Empty: every frame is quoted.
    pub left_out: Vec<Option<LeftOut>>,
    /// A human take's anatomical joints and the BVH joint at each one's centre (`knee_l` →
    /// `LeftLeg`), from the landmarks the take's human was found by; empty otherwise.
    pub anatomy_joints: Vec<(String, String)>,
    /// With ground contact: each foot's vertical ground force per frame (N, up positive),
    /// columns named by foot (`left`, `right`); empty otherwise.
    pub feet: Table,
    /// A simulation's reference: the configurations it tracked (`nq` columns, as `q`); empty
    /// for inverse dynamics.
    pub reference: Table,
    /// The pipeline's take these results were computed from (a BVH take's model and smoothed
    /// states, before contact), so that an edit that keeps its states reuses them
    /// ([`pipeline::take_from_bvh_reusing`]); `None` for a robot or a simulation.
    pub source: Option<Arc<pipeline::Take>>,
    /// A human take's anatomical calibration (segment frames and kept poses: what masses do
    /// not change, `pipeline::anatomy::Calibration`), reused by an edit whose take has the
    /// same kinematics; `None` otherwise.
    pub calibration: Option<Arc<pipeline::anatomy::Calibration>>,
    /// What `contact auto` settled on for [`source`](Self::source) and why
    /// (`pipeline::resolve_contact_after`), reused by an edit of masses alone; `None` when the
    /// contact was not `auto`.
    pub contact_auto: Option<(pipeline::Contact, String)>,
    /// The contact thresholds fitted to [`source`](Self::source)'s feet
    /// (`pipeline::ContactFit`: no mass changes them), reused by an edit whose take has the
    /// same motion; `None` without contact.
    pub contact_fit: Option<Arc<pipeline::ContactFit>>,
    /// What residual reduction found for these results (`dynamics::rra::Seed`), where the
    /// next edit's reduction starts: an edit that scales every mass alike reuses its
    /// adjustments, one that changes masses otherwise starts cold (and the workbench's
    /// preview evaluates these adjustments on its masses: `Engine::preview_after`, whose
    /// results keep the seed they evaluated); `None` without reduction.
    pub reduction: Option<Arc<crate::dynamics::rra::Seed>>,
    /// With ground contact: the take's consistency (`pipeline::consistency`: the residual
    /// figures before and after reduction against Hicks et al.'s thresholds), which the
    /// curves and the charts of these results carry; `None` without contact.
    pub consistency: Option<Arc<pipeline::consistency::Consistency>>,
    /// The states `q`, `v` and `a` were made from (inverse dynamics: the take's, or the take
    /// residual reduction adjusted), so that an edit whose take has the same states (the same
    /// `Arc`: a mass edit, `pipeline::take_from_bvh_reusing`) shares the tables instead of
    /// copying them; `None` for a simulation.
    pub states: Option<Arc<pipeline::States>>,
}

/// Why a frame's accelerations and torques are left out of the figures quoted from them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LeftOut {
    /// Within the smoothing's reach of the take's ends, where the smoothed accelerations see
    /// past the take (`pipeline::edge_frames`); quoted with `set edges include`.
    Edge,
    /// The residuals stay beyond Hicks et al.'s thresholds: the motion needs a force the feet
    /// cannot give (`pipeline::consistency`, the CSV column `residual:beyond`).
    Beyond,
}

impl LeftOut {
    /// A short name for messages and legends.
    pub fn name(self) -> &'static str {
        match self {
            LeftOut::Edge => "edge",
            LeftOut::Beyond => "beyond the feet",
        }
    }
}

impl Analysis {
    /// Whether frame `k`'s accelerations and torques are quoted (not [`left_out`](Self::left_out)).
    pub fn quoted(&self, k: usize) -> bool {
        self.left_out.get(k).is_none_or(Option::is_none)
    }

    /// The runs of frames left out, as `(first, last, why)` with `first..=last` one reason.
    pub fn left_out_runs(&self) -> Vec<(usize, usize, LeftOut)> {
        let mut runs: Vec<(usize, usize, LeftOut)> = vec![];
        for (k, w) in self.left_out.iter().enumerate() {
            let Some(w) = *w else { continue };
            match runs.last_mut() {
                Some(r) if r.1 + 1 == k && r.2 == w => r.1 = k,
                _ => runs.push((k, k, w)),
            }
        }
        runs
    }
}

/// Rows as one row-major [`Table`].
pub(super) fn table(names: &[String], rows: &[Vec<f64>]) -> Table {
    Table {
        names: names.to_vec(),
        data: rows.concat(),
    }
}

/// Each foot's vertical ground force (N, up positive) per frame, columns named by foot.
pub(super) fn vertical_forces(g: &crate::dynamics::grf::GroundReactions) -> Table {
    let rows: Vec<Vec<f64>> = g
        .grf
        .iter()
        .map(|f| f.iter().map(|v| v[g.up]).collect())
        .collect();
    table(&g.feet, &rows)
}
