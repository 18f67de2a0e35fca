//! Model only what the study needs, and say what it cost (`articula tradeoff --reduce`,
//! `--lock auto:TOL`).
//!
//! A study reads a few outputs — a gait lab the knee moments, a robotics engineer every joint
//! torque — and a model can often do without joints far from them. Locking a joint (its body
//! welded to its parent, [`simplify::lock_bodies_at`]) changes the outputs through the mass it
//! no longer moves; how much is measured here, on the take itself, against the full model:
//!
//! 1. the outputs: `--of` names (anatomical joints such as `knee_l`, BVH joints, coordinates),
//!    each standing for the generalized forces of its coordinates (N·m); by default a human's
//!    knees (`knee_l`, `knee_r`), otherwise every joint coordinate the reduced model keeps;
//! 2. the candidates: every BVH joint with coordinates, except the floating root and the
//!    outputs' own joints;
//! 3. greedy search: at each step, the candidate whose locking (with those locked before)
//!    changes the outputs least — by the peak |reduced − full| over the frames and outputs —
//!    is locked. The first round measures each joint alone held at its rest pose and at its
//!    mean pose over the take ([`simplify::mean_configuration`]) and keeps the hold with the
//!    smaller peak error (rest on a tie); later rounds hold it so. The search runs on a
//!    subsample of the frames (every `s`-th, `s` the smallest step leaving at most
//!    [`SEARCH_FRAMES`] frames, but never under 30 fps), then every step is verified on all
//!    frames;
//! 4. with ground contact (`--contact auto` settled on the full take), each model's torques are
//!    those with its own estimated ground reactions, as `articula id` computes them: locking
//!    an arm changes the body's momentum, hence the ground force, hence the knee moment.
//!
//! `--lock auto:TOL` (`auto:2%`: of the outputs' peak |τ| over the take; `auto:1nm`) runs the
//! search until the search error exceeds TOL, takes the last step within it, verifies it on
//! all frames and steps back while the verified error exceeds TOL: the model it keeps is within
//! TOL on every frame of the take. The search costs O(candidates²) inverse dynamics runs over
//! the subsample.

mod table;
mod tolerance;

pub use tolerance::{Tolerance, parse_auto, split_lock};

use super::{Contact, States, Take, contact_choice};
use crate::error::Error;
use crate::model::Model;
use crate::model::bvh::{BvhMap, follow_reduction};
use crate::model::simplify::{self, Reduction};
use serde::Serialize;
use std::fmt::Write as _;
use std::sync::Arc;

/// The search uses at most about this many frames of the take (every `s`-th frame).
pub const SEARCH_FRAMES: usize = 200;

/// The search's subsample keeps at least this rate (frames per second), so that contact
/// phases and their transitions stay resolved.
const MIN_SEARCH_FPS: f64 = 30.0;

/// Batches of the per-frame timing (bench machinery, `dynamics::bench::time_rnea`).
const TIMING_BATCHES: usize = 7;

/// States timed per model: the first of the search frames.
const TIMING_STATES: usize = 32;

/// Where a locked joint is held.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Hold {
    /// The rest pose (q = 0, identity quaternions).
    Rest,
    /// The joint's mean pose over the take.
    Mean,
}

impl Hold {
    pub fn name(self) -> &'static str {
        match self {
            Hold::Rest => "rest",
            Hold::Mean => "mean",
        }
    }
}

/// The outputs a reduction is measured on.
#[derive(Debug, Clone, PartialEq)]
pub struct Outputs {
    /// As the user reads them (`knee_l, knee_r`, `every joint`).
    pub label: String,
    /// Velocity coordinates of the take's model; `None`: every joint coordinate the reduced
    /// model keeps (rotations, not the floating root).
    pub coordinates: Option<Vec<String>>,
    /// BVH joints holding the outputs (never locked).
    pub joints: Vec<usize>,
}

/// The bodies of `model` that carry BVH joint `j`'s coordinates (none: no coordinate).
fn joint_bodies(model: &Model, map: &BvhMap, j: usize) -> Vec<usize> {
    let owner = |q: usize| {
        (1..model.nbodies())
            .find(|&i| (model.idx_q[i]..model.idx_q[i] + model.joints[i].nq()).contains(&q))
    };
    let m = &map.joints[j];
    let mut bodies: Vec<usize> = m
        .channels
        .iter()
        .filter_map(|c| c.q)
        .chain(m.quat_q)
        .filter_map(owner)
        .collect();
    bodies.sort_unstable();
    bodies.dedup();
    bodies
}

/// The velocity coordinates of `bodies`.
fn body_coordinates(model: &Model, bodies: &[usize]) -> Vec<usize> {
    bodies
        .iter()
        .flat_map(|&i| model.idx_v[i]..model.idx_v[i] + model.joints[i].nv())
        .collect()
}

/// Whether velocity coordinate `k` of `model` is a joint's rotation (not the floating root's,
/// not a translation): what an output may be.
fn joint_rotation(model: &Model, k: usize) -> bool {
    k >= crate::dynamics::floating_root_nv(model) && model.is_angular(k)
}

/// Resolves `--of` (none: the default) on a take: anatomical joint names of a human (`knee_l`,
/// `hip_r`, `lumbar`, …), BVH joints, or velocity coordinates (`LeftLeg.Xrotation`).
///
/// Errors: a name that is none of these, or a coordinate that is a translation or the root's.
pub fn outputs(take: &Take, of: Option<&[String]>) -> Result<Outputs, Error> {
    let anatomical = match &take.human {
        Ok(h) => super::anatomy::anatomical_joints(h, &take.bvh),
        Err(_) => vec![],
    };
    let names: Vec<String> = match of {
        Some(of) => of.iter().map(|s| s.trim().to_string()).collect(),
        None if anatomical.is_empty() => {
            return Ok(Outputs {
                label: "every joint".into(),
                coordinates: None,
                joints: vec![],
            });
        }
        None => vec!["knee_l".into(), "knee_r".into()],
    };
    let model = &take.model;
    let mut coordinates: Vec<String> = vec![];
    let mut joints = vec![];
    for name in &names {
        let joint = anatomical
            .iter()
            .find(|(a, _)| a == name)
            .map(|(_, j)| j.as_str())
            .unwrap_or(name);
        let ks: Vec<usize> = match take.bvh.joint_index(joint) {
            Some(j) => {
                joints.push(j);
                body_coordinates(model, &joint_bodies(model, &take.map, j))
                    .into_iter()
                    .filter(|&k| joint_rotation(model, k))
                    .collect()
            }
            None => match model.v_index(name) {
                Some(k) if joint_rotation(model, k) => {
                    let body = model.body_of_v(k);
                    if let Some(j) = (0..take.map.joints.len())
                        .find(|&j| joint_bodies(model, &take.map, j).contains(&body))
                    {
                        joints.push(j);
                    }
                    vec![k]
                }
                Some(_) => {
                    return Err(Error::Invalid(format!(
                        "--of {name}: a translation or the floating root's coordinate; the \
                         outputs are joint moments (rotations, N·m)"
                    )));
                }
                None => {
                    let some: Vec<&str> = anatomical.iter().map(|(a, _)| a.as_str()).collect();
                    return Err(Error::Invalid(format!(
                        "--of {name}: neither an anatomical joint ({}), a joint of the take nor \
                         a coordinate of its model (e.g. {})",
                        if some.is_empty() {
                            "none: not a human".into()
                        } else {
                            some.join(", ")
                        },
                        model.v_names.last().map(String::as_str).unwrap_or("")
                    )));
                }
            },
        };
        if ks.is_empty() {
            return Err(Error::Invalid(format!(
                "--of {name}: the joint has no rotation coordinate in the model (locked, \
                 welded or without channels)"
            )));
        }
        coordinates.extend(ks.into_iter().map(|k| model.v_names[k].clone()));
    }
    coordinates.dedup();
    joints.sort_unstable();
    joints.dedup();
    Ok(Outputs {
        label: names.join(", "),
        coordinates: Some(coordinates),
        joints,
    })
}

/// Peak and RMS of the outputs' error, in N·m and in % of the full model's outputs.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Figures {
    pub peak_nm: f64,
    pub rms_nm: f64,
    pub peak_pct: f64,
    pub rms_pct: f64,
}

/// One step of the reduction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Step {
    /// The joint locked at this step (`None`: step 0, the full model).
    pub locked: Option<String>,
    /// Where it is held.
    pub hold: Option<Hold>,
    pub nv: usize,
    /// RNEA time per frame (s), median of the bench machinery at the take's states.
    pub time_per_frame_s: f64,
    /// Error on the search's frames.
    pub search: Figures,
    /// Error on every frame.
    pub all: Figures,
}

/// A joint's error locked alone at its rest and at its mean pose (search frames), and the
/// hold chosen.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HoldChoice {
    pub joint: String,
    pub rest: Figures,
    pub mean: Figures,
    pub chosen: Hold,
}

/// What `articula tradeoff --reduce` prints: the greedy steps and what they cost.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Reduce {
    pub take: String,
    pub outputs: String,
    /// The velocity coordinates measured (`None`: every kept joint rotation).
    pub coordinates: Option<Vec<String>>,
    pub contact: String,
    pub frames: usize,
    pub search_frames: usize,
    /// Every `search_every`-th frame is searched on.
    pub search_every: usize,
    /// The full model's outputs over every frame: peak |τ| and RMS (N·m), the 100 % of the
    /// percentages.
    pub output_peak_nm: f64,
    pub output_rms_nm: f64,
    pub steps: Vec<Step>,
    pub holds: Vec<HoldChoice>,
    /// Candidates the search had to leave out (their model failed), with why.
    pub skipped: Vec<String>,
}

/// A locked candidate: index into [`Reducer::candidates`] and its hold.
type Lock = (usize, Hold);

/// Outputs over frames, by velocity coordinate name.
type Series = Vec<(String, Vec<f64>)>;

/// What the greedy search found: each step's lock, nv and search figures; the holds chosen;
/// the candidates left out, with why.
struct Greedy {
    steps: Vec<(Lock, usize, Figures)>,
    holds: Vec<HoldChoice>,
    skipped: Vec<String>,
}

/// The search's state: the take, its scratch copy whose model, map and states each evaluation
/// replaces, the candidates and the full model's outputs.
pub struct Reducer<'a> {
    take: &'a Take,
    scratch: Take,
    contact: bool,
    outputs: Outputs,
    /// BVH joint index, name and bodies of each candidate.
    candidates: Vec<(usize, String, Vec<usize>)>,
    mean: Vec<f64>,
    search: Vec<usize>,
    all: Vec<usize>,
    /// The full model's outputs on the search's frames and on all, by coordinate name.
    reference_search: Series,
    reference_all: Series,
    peak: f64,
    rms: f64,
}

/// Which frames an evaluation runs on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Frames {
    Search,
    All,
}

impl<'a> Reducer<'a> {
    /// Prepares the search on `take` for `outputs`: the candidates, the mean pose, the frames,
    /// the contact setting and the full model's outputs.
    pub fn new(take: &'a Take, outputs: Outputs) -> Result<Self, Error> {
        let model = &take.model;
        let root = crate::dynamics::floating_root_nv(model);
        let candidates: Vec<(usize, String, Vec<usize>)> = (0..take.map.joints.len())
            .filter(|j| !outputs.joints.contains(j))
            .filter_map(|j| {
                let bodies = joint_bodies(model, &take.map, j);
                let coords = body_coordinates(model, &bodies);
                (!coords.is_empty() && coords.iter().all(|&k| k >= root))
                    .then(|| (j, take.bvh.joints[j].name.clone(), bodies))
            })
            .collect();
        let n = take.states.len();
        let fps = 1.0 / take.bvh.frame_time;
        let every = (n / SEARCH_FRAMES)
            .min((fps / MIN_SEARCH_FPS).floor() as usize)
            .max(1);
        let contact = match take.options.contact {
            Contact::Auto => contact_choice(take).0,
            c => c,
        } == Contact::Feet;
        let mut scratch = take.clone();
        scratch.options.contact = if contact {
            Contact::Feet
        } else {
            Contact::None
        };
        let mean = simplify::mean_configuration(model, take.states.q.iter().map(Vec::as_slice));
        let mut r = Reducer {
            take,
            scratch,
            contact,
            outputs,
            candidates,
            mean,
            search: (0..n).step_by(every).collect(),
            all: (0..n).collect(),
            reference_search: vec![],
            reference_all: vec![],
            peak: 0.0,
            rms: 0.0,
        };
        r.reference_search = r.outputs_of(&[], Frames::Search)?.1;
        r.reference_all = r.outputs_of(&[], Frames::All)?.1;
        let (peak, rms) = peak_rms(r.reference_all.iter().flat_map(|(_, x)| x));
        (r.peak, r.rms) = (peak, rms);
        Ok(r)
    }

    /// The reduced model of `locks` and where every body of the take's model went.
    fn reduction(&self, locks: &[Lock]) -> (Reduction, Vec<f64>) {
        let model = &self.take.model;
        let mut mask = vec![false; model.nbodies()];
        let mut hold = model.neutral();
        for &(c, h) in locks {
            for &i in &self.candidates[c].2 {
                mask[i] = true;
                if h == Hold::Mean {
                    let q = model.idx_q[i]..model.idx_q[i] + model.joints[i].nq();
                    hold[q.clone()].copy_from_slice(&self.mean[q]);
                }
            }
        }
        (simplify::lock_bodies_at(model, &mask, Some(&hold)), hold)
    }

    /// The reduced model of `locks` with its map and its states on `frames`.
    fn reduced_take_parts(&self, locks: &[Lock], frames: &[usize]) -> (Model, BvhMap, States) {
        let (r, hold) = self.reduction(locks);
        let mut map = self.take.map.clone();
        follow_reduction(&self.take.model, &r, Some(&hold), &mut map);
        let states = project(&self.take.states, frames, &self.take.model, &r);
        (r.model, map, states)
    }

    /// The outputs of the model reduced by `locks` on `frames`: its nv and, per output
    /// coordinate it has, the generalized force at each frame (with its own ground reactions
    /// when the take has contact).
    fn outputs_of(&mut self, locks: &[Lock], frames: Frames) -> Result<(usize, Series), Error> {
        let idx = match frames {
            Frames::Search => &self.search,
            Frames::All => &self.all,
        };
        let (model, map, states) = self.reduced_take_parts(locks, idx);
        self.scratch.model = model;
        self.scratch.map = map;
        self.scratch.states = Arc::new(states);
        let t = &self.scratch;
        let tau = if self.contact {
            super::estimate_take_ground_reactions(t)?.tau
        } else {
            super::inverse_dynamics(&t.model, &t.states).tau
        };
        let m = &t.model;
        let wanted: Vec<usize> = match &self.outputs.coordinates {
            Some(names) => names.iter().filter_map(|n| m.v_index(n)).collect(),
            None => (0..m.nv).filter(|&k| joint_rotation(m, k)).collect(),
        };
        let out = wanted
            .into_iter()
            .map(|k| (m.v_names[k].clone(), tau.iter().map(|row| row[k]).collect()))
            .collect::<Series>();
        if out.iter().any(|(_, x)| x.iter().any(|v| !v.is_finite())) {
            return Err(Error::Numerical("an output is not finite".into()));
        }
        Ok((m.nv, out))
    }

    /// The error figures of the model reduced by `locks` on `frames`, and its nv.
    fn error(&mut self, locks: &[Lock], frames: Frames) -> Result<(usize, Figures), Error> {
        let (nv, out) = self.outputs_of(locks, frames)?;
        let reference = match frames {
            Frames::Search => &self.reference_search,
            Frames::All => &self.reference_all,
        };
        let diff = out.iter().flat_map(|(name, x)| {
            let r = reference
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, r)| r.as_slice())
                .unwrap_or(&[]);
            x.iter().zip(r).map(|(a, b)| a - b)
        });
        let (peak, rms) = peak_rms(diff);
        let pct = |x: f64, of: f64| if of > 0.0 { 100.0 * x / of } else { 0.0 };
        Ok((
            nv,
            Figures {
                peak_nm: peak,
                rms_nm: rms,
                peak_pct: pct(peak, self.peak),
                rms_pct: pct(rms, self.rms),
            },
        ))
    }

    /// RNEA time per frame of the model reduced by `locks`, at the take's states.
    fn time_per_frame(&self, locks: &[Lock]) -> f64 {
        let frames: Vec<usize> = self.search.iter().copied().take(TIMING_STATES).collect();
        let (model, _, s) = self.reduced_take_parts(locks, &frames);
        let ns = crate::dynamics::bench::time_rnea(
            &model,
            &rows(&s.q),
            &rows(&s.v),
            &rows(&s.a),
            TIMING_BATCHES,
        );
        ns * 1e-9
    }

    /// The greedy search (module doc), until every candidate is locked or, with `stop` (N·m),
    /// just past the first step whose search error exceeds it.
    fn greedy(&mut self, stop: Option<f64>) -> Greedy {
        let mut locked: Vec<Lock> = vec![];
        let mut steps = vec![];
        let mut holds = vec![];
        let mut skipped = vec![];
        let mut hold = vec![Hold::Rest; self.candidates.len()];
        let mut remaining: Vec<usize> = (0..self.candidates.len()).collect();
        let mut first = true;
        while !remaining.is_empty() {
            let mut best: Option<(usize, usize, Figures)> = None;
            let mut failed = vec![];
            for &c in &remaining {
                let mut with = locked.clone();
                let result = if first {
                    // alone, at rest and at its mean pose: the hold that costs least
                    with.push((c, Hold::Rest));
                    let rest = self.error(&with, Frames::Search);
                    with.last_mut().expect("pushed").1 = Hold::Mean;
                    let mean = self.error(&with, Frames::Search);
                    match (rest, mean) {
                        (Ok((nv, r)), Ok((_, m))) => {
                            hold[c] = if m.peak_nm < r.peak_nm {
                                Hold::Mean
                            } else {
                                Hold::Rest
                            };
                            holds.push(HoldChoice {
                                joint: self.candidates[c].1.clone(),
                                rest: r,
                                mean: m,
                                chosen: hold[c],
                            });
                            Ok((nv, if hold[c] == Hold::Mean { m } else { r }))
                        }
                        (Err(e), _) | (_, Err(e)) => Err(e),
                    }
                } else {
                    with.push((c, hold[c]));
                    self.error(&with, Frames::Search)
                };
                match result {
                    Ok((nv, f)) => {
                        if best.is_none_or(|(_, _, b)| f.peak_nm < b.peak_nm) {
                            best = Some((c, nv, f));
                        }
                    }
                    Err(e) => {
                        skipped.push(format!("{}: {e}", self.candidates[c].1));
                        failed.push(c);
                    }
                }
            }
            first = false;
            remaining.retain(|c| !failed.contains(c));
            let Some((c, nv, f)) = best else { break };
            locked.push((c, hold[c]));
            remaining.retain(|&r| r != c);
            steps.push(((c, hold[c]), nv, f));
            if stop.is_some_and(|tol| f.peak_nm > tol) {
                break;
            }
        }
        Greedy {
            steps,
            holds,
            skipped,
        }
    }

    /// A step's row: the locks up to it verified on all frames and timed.
    fn step(&mut self, locks: &[Lock], search: Figures) -> Result<Step, Error> {
        let (nv, all) = self.error(locks, Frames::All)?;
        let last = locks.last();
        Ok(Step {
            locked: last.map(|&(c, _)| self.candidates[c].1.clone()),
            hold: last.map(|&(_, h)| h),
            nv,
            time_per_frame_s: self.time_per_frame(locks),
            search,
            all,
        })
    }

    /// The names of the joints the search may lock, in file order.
    pub fn candidates(&self) -> Vec<&str> {
        self.candidates.iter().map(|c| c.1.as_str()).collect()
    }

    /// The error on the outputs of the model with `joints` locked (BVH joint names, each with
    /// its hold), on the search's frames or on all, and its nv: any lock set, for a check of
    /// the search from outside.
    ///
    /// Errors: a name that is no candidate ([`Reducer::candidates`]); the model's failure.
    pub fn error_of(
        &mut self,
        joints: &[(&str, Hold)],
        all_frames: bool,
    ) -> Result<(usize, Figures), Error> {
        let locks = joints
            .iter()
            .map(|&(name, h)| {
                self.candidates
                    .iter()
                    .position(|c| c.1 == name)
                    .map(|c| (c, h))
                    .ok_or_else(|| {
                        Error::Invalid(format!("{name}: not a joint the reduction may lock"))
                    })
            })
            .collect::<Result<Vec<Lock>, Error>>()?;
        let frames = if all_frames {
            Frames::All
        } else {
            Frames::Search
        };
        self.error(&locks, frames)
    }

    /// `articula tradeoff --reduce`: every greedy step, verified on all frames and timed.
    pub fn run(mut self) -> Result<Reduce, Error> {
        let Greedy {
            steps,
            holds,
            skipped,
        } = self.greedy(None);
        let mut rows = vec![self.step(&[], Figures::default())?];
        let locks: Vec<Lock> = steps.iter().map(|s| s.0).collect();
        for (k, (_, _, f)) in steps.iter().enumerate() {
            rows.push(self.step(&locks[..=k], *f)?);
        }
        Ok(self.report(rows, holds, skipped))
    }

    fn report(&self, steps: Vec<Step>, holds: Vec<HoldChoice>, skipped: Vec<String>) -> Reduce {
        Reduce {
            take: self.take.path.display().to_string(),
            outputs: self.outputs.label.clone(),
            coordinates: self.outputs.coordinates.clone(),
            contact: if self.contact { "feet" } else { "none" }.into(),
            frames: self.all.len(),
            search_frames: self.search.len(),
            search_every: self.search.get(1).map_or(1, |&s| s),
            output_peak_nm: self.peak,
            output_rms_nm: self.rms,
            steps,
            holds,
            skipped,
        }
    }

    /// `--lock auto:TOL`: the locks of the smallest model the search finds within `tol` on
    /// every frame (possibly none), and the report of the steps tried (the last one kept).
    fn within(&mut self, tol: Tolerance) -> Result<(Vec<Lock>, Reduce), Error> {
        let tol_nm = tol.newton_metres(self.peak);
        let Greedy {
            steps,
            holds,
            skipped,
        } = self.greedy(Some(tol_nm));
        let locks: Vec<Lock> = steps.iter().map(|s| s.0).collect();
        // the last step within TOL on the search frames, then back while all frames disagree
        let mut k = steps.iter().take_while(|s| s.2.peak_nm <= tol_nm).count();
        let mut rows = vec![];
        while k > 0 {
            let row = self.step(&locks[..k], steps[k - 1].2)?;
            if row.all.peak_nm <= tol_nm {
                rows.push(row);
                break;
            }
            rows.push(row);
            k -= 1;
        }
        if k == 0 {
            rows.push(self.step(&[], Figures::default())?);
        }
        // the report's steps: the kept one last
        Ok((locks[..k].to_vec(), self.report(rows, holds, skipped)))
    }
}

/// The rows of a states table as slices.
fn rows(x: &[Vec<f64>]) -> Vec<&[f64]> {
    x.iter().map(Vec::as_slice).collect()
}

/// Peak |x| and RMS of `x` (0 for none).
fn peak_rms<B: std::borrow::Borrow<f64>>(x: impl IntoIterator<Item = B>) -> (f64, f64) {
    let (mut peak, mut sum, mut n) = (0.0f64, 0.0, 0usize);
    for v in x {
        let v = *v.borrow();
        peak = peak.max(v.abs());
        sum += v * v;
        n += 1;
    }
    (peak, if n == 0 { 0.0 } else { (sum / n as f64).sqrt() })
}

/// `s`'s frames `frames` on the reduced model of `r` (a reduction of `full`): each kept
/// body's coordinates copied to its place.
fn project(s: &States, frames: &[usize], full: &Model, r: &Reduction) -> States {
    let m = &r.model;
    let ranges = |idx_f: &[usize], idx_r: &[usize], len: &dyn Fn(usize) -> usize| {
        (1..full.nbodies())
            .filter_map(|i| r.kept[i].map(|k| (idx_f[i], idx_r[k], len(i))))
            .filter(|&(_, _, n)| n > 0)
            .collect::<Vec<_>>()
    };
    let rq = ranges(&full.idx_q, &m.idx_q, &|i| full.joints[i].nq());
    let rv = ranges(&full.idx_v, &m.idx_v, &|i| full.joints[i].nv());
    let pick = |rows: &[Vec<f64>], ranges: &[(usize, usize, usize)], n: usize| {
        frames
            .iter()
            .map(|&k| {
                let mut out = vec![0.0; n];
                for &(f, t, len) in ranges {
                    out[t..t + len].copy_from_slice(&rows[k][f..f + len]);
                }
                out
            })
            .collect::<Vec<_>>()
    };
    States {
        time: frames.iter().map(|&k| s.time[k]).collect(),
        q: pick(&s.q, &rq, m.nq),
        v: pick(&s.v, &rv, m.nv),
        a: pick(&s.a, &rv, m.nv),
    }
}

/// `articula tradeoff --reduce` on a loaded take for the outputs `of` (none: the default).
pub fn reduce(take: &Take, of: Option<&[String]>) -> Result<Reduce, Error> {
    let outputs = outputs(take, of)?;
    Reducer::new(take, outputs)?.run()
}

/// `--lock auto:TOL` on a loaded take: its model, map and states become those of the smallest
/// model within `tol` on the default outputs (a note says which joints were locked, where they
/// are held, and the error measured); the full model when no joint can go (a note says so).
pub fn lock_auto(mut take: Take, tol: Tolerance) -> Result<Take, Error> {
    let outputs = outputs(&take, None)?;
    let (full_nv, n) = (take.model.nv, take.states.len());
    let (report, names, parts) = {
        let mut r = Reducer::new(&take, outputs)?;
        let (locks, report) = r.within(tol)?;
        let names: Vec<String> = locks
            .iter()
            .map(|&(c, h)| format!("{} ({})", r.candidates[c].1, h.name()))
            .collect();
        let all = r.all.clone();
        let parts = (!locks.is_empty()).then(|| r.reduced_take_parts(&locks, &all));
        (report, names, parts)
    };
    let Some((model, map, states)) = parts else {
        take.notes.push(format!(
            "lock auto:{tol}: no joint can be locked within {tol} on {} (every candidate \
             changes them more): the full model is kept (nv {full_nv})",
            report.outputs
        ));
        return Ok(take);
    };
    let mut note = format!(
        "lock auto:{tol}: locked {} joints (each held at its rest or its mean pose over the \
         take, whichever moved the outputs less): {}; nv {full_nv} → {}; error on {} against \
         the full model",
        names.len(),
        names.join(", "),
        model.nv,
        report.outputs
    );
    if let Some(s) = report.steps.last() {
        let _ = write!(
            note,
            ": peak {:.3} N·m ({:.2} %), RMS {:.3} N·m ({:.2} %) on all {n} frames; on the \
             search's {} frames (every {}): peak {:.3} N·m",
            s.all.peak_nm,
            s.all.peak_pct,
            s.all.rms_nm,
            s.all.rms_pct,
            report.search_frames,
            report.search_every,
            s.search.peak_nm
        );
    }
    take.model = model;
    take.map = map;
    take.states = Arc::new(states);
    take.notes.push(note);
    Ok(take)
}
