//! A take's dynamic consistency (`--consistent`): its residuals against Hicks et al.'s
//! thresholds (`dynamics::residual`), before and after residual reduction (`dynamics::rra`:
//! the trunk's mass centre and a smooth pelvis offset, as OpenSim's RRA), the adjustments,
//! and where and why a take misses the thresholds.

use super::{States, Take, anatomy::find_take_human, contact_feet};
use crate::dynamics::grf::measured::{FootLoads, apply_ground_reactions};
use crate::dynamics::grf::{FloorLost, GroundReactions, floor_lost_text};
use crate::dynamics::residual::{
    FORCE_SHARE, MOMENT_SHARE, ResidualFigures, counted_frames, external_forces, residual_figures,
    split_norms,
};
use crate::dynamics::rra::{
    Ground, Motion, ReductionBounds, Seed, Started, Trunk, Warm, com_heights, reduce_residuals,
};
use crate::error::Error;
use crate::motion::contact::ContactParams;
use nalgebra::Vector3;
use std::sync::Arc;

/// What residual reduction changed (`None` fields: not reduced).
#[derive(Debug, Clone, PartialEq)]
pub struct Adjustments {
    /// The trunk's mass-centre offset (m, in the trunk bodies' frame: the file's axes at rest).
    pub trunk_offset_m: Vector3<f64>,
    /// The trunk's mass (kg): the bodies from the lumbar joint to the head.
    pub trunk_mass_kg: f64,
    /// Largest and RMS horizontal pelvis offset over the take (m).
    pub pelvis_peak_m: f64,
    pub pelvis_rms_m: f64,
    /// Largest and RMS pelvis rotation over the take (rad); `None`: not adjusted (a root that
    /// is neither a free joint nor three hinges about coordinate axes).
    pub rotation_peak_rms_rad: Option<(f64, f64)>,
    /// The total mass's change (kg): against measured ground reactions only, else 0.
    pub mass_change_kg: f64,
    /// Whether the ground reactions were measured (`--grf`) rather than estimated.
    pub measured: bool,
    /// The largest change of the pelvis offset within one foot's contact phase (m): how far
    /// the offset slides a foot on the floor (the whole body moves with it, as in RRA).
    pub stance_slide_m: f64,
    /// The bounds the adjustments end against (`trunk`, `pelvis`).
    pub bounded: Vec<&'static str>,
    /// The bounds used.
    pub bounds: ReductionBounds,
    /// The knot spacing (s) of the pelvis offset's refinement near the foot changes, when the
    /// smooth adjustments left the take beyond the thresholds (`dynamics::rra`).
    pub refined_knot_spacing_s: Option<f64>,
    /// How the reduction started: cold, or from a seed of the same take (`dynamics::rra`).
    pub started: Started,
}

/// A take's consistency: the residual figures before and after reduction, per frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Consistency {
    /// The residuals of the take as loaded.
    pub before: ResidualFigures,
    /// After residual reduction (`None`: `--consistent off`).
    pub after: Option<ResidualFigures>,
    pub adjustments: Option<Adjustments>,
    /// The body mass as loaded (kg); residual reduction adjusts it against measured ground
    /// reactions only (`dynamics::rra`: estimated ones make it unobservable).
    pub mass_kg: f64,
    /// Per frame: |residual force| (N) and |residual moment| (N·m) of the final model and
    /// motion, whether the frame counts, and whether it lies beyond the thresholds.
    pub force_n: Vec<f64>,
    pub moment_nm: Vec<f64>,
    pub counted: Vec<bool>,
    pub beyond: Vec<bool>,
    /// The runs of frames in which the take's capture has left its floor (the feet unloaded
    /// and off it, yet no free fall: [`GroundReactions::floor_lost`]); their counted frames
    /// are among those `beyond`.
    pub floor_lost: Vec<FloorLost>,
    /// What the take's notes say of them (`None`: no such run).
    pub floor_lost_note: Option<String>,
    /// Why the thresholds are missed, when they are (empty when met).
    pub why: Vec<String>,
}

impl Consistency {
    /// The final figures: after reduction, else before.
    pub fn last(&self) -> &ResidualFigures {
        self.after.as_ref().unwrap_or(&self.before)
    }
}

/// The take's ground reactions and consistency; with `reduce`, residual reduction first, and
/// the take returned is the adjusted one (its model and states), whose joint moments every
/// output then reads.
pub fn consistent_take(
    take: &Take,
    reduce: bool,
    measured: Option<&FootLoads>,
) -> Result<(Option<Take>, GroundReactions, Consistency), Error> {
    consistent_take_keeping(take, reduce, measured, &[], Warm::Cold, None)
        .map(|(t, g, c, _)| (t, g, c))
}

/// [`consistent_take`] whose estimate keeps the net moments on `moment_bodies`
/// ([`GroundReactions::moments`], for the anatomical series) when the take is not reduced,
/// and whose residual reduction starts as `warm` says (`dynamics::rra::Warm`: from what an
/// earlier reduction of the same take found, kept by a session between edits of the masses,
/// when it fits; or a workbench's preview), with the take's contact thresholds `fit` when
/// given (a session's, kept across edits that change no motion; else they are fitted here).
/// Returns besides what the reduction found to start the next one from.
pub fn consistent_take_keeping(
    take: &Take,
    reduce: bool,
    measured: Option<&FootLoads>,
    moment_bodies: &[usize],
    warm: Warm,
    fit: Option<&super::ContactFit>,
) -> Result<(Option<Take>, GroundReactions, Consistency, Option<Seed>), Error> {
    let s = &take.states;
    let up = take.up.index();
    // the moments of the take as it is are read only when it stays as it is
    let keep = if reduce { &[][..] } else { moment_bodies };
    // the contact thresholds and the feet's paths, made once: the estimate and the reduction's
    // trials read them (given, else the take's kept fit, `resolve_contact`, else fitted now)
    let made;
    let fit = match fit {
        Some(f) => f,
        None => {
            made = super::contact::kept_or_new_fit(take, None)?;
            &*made
        }
    };
    let params = fit.params;
    let before = match measured {
        Some(loads) => apply_ground_reactions(&take.model, loads, &s.time, &s.q, &s.v, &s.a, up)?,
        None => {
            let paths = Some(&fit.paths);
            super::contact::estimate_with_params(take, &params, paths, keep, &mut |_| true)?
        }
    };
    let counted = counted_frames(s.len(), super::edge_frames(take));
    // the centre of mass and the pelvis of the estimate's own kinematics
    let heights = com_heights_of(&before);
    let fig_before = figures(&before, &heights, &counted);
    let mass_kg = take.model.total_mass();
    let travel = pelvis_travel(&before.pelvis, up);
    // where the capture has left its floor: a property of the take as captured, read from its
    // own estimate (residual reduction holds its contact phases, and moves the feet by
    // centimetres and the needed force by little)
    let dt = take.bvh.frame_time;
    let floor = (
        before.floor_lost(
            mass_kg * take.model.gravity.norm(),
            off_floor_height(&params),
            dt,
        ),
        dt,
    );
    if !reduce {
        let c = finish(
            fig_before, None, None, mass_kg, &before, counted, travel, floor,
        );
        return Ok((None, before, c, None));
    }
    let duration = s.time.last().copied().unwrap_or(0.0) - s.time.first().copied().unwrap_or(0.0);
    let bounds = ReductionBounds::for_take(duration, take.bvh.frame_time);
    let feet = contact_feet(take);
    let bodies = trunk_bodies(take);
    let across = trunk_long_axis(take)
        .and_then(|e| Trunk::across(&e))
        .unwrap_or([Vector3::zeros(); 2]);
    let ground = match measured {
        Some(loads) => Ground::Measured(loads),
        None => Ground::Estimated {
            feet: &feet,
            params: &params,
            held: Some(&before.contact),
        },
    };
    let r = reduce_residuals(
        &take.model,
        ground,
        Trunk {
            bodies: &bodies,
            across,
        },
        Motion {
            time: &s.time,
            q: &s.q,
            v: &s.v,
            a: &s.a,
        },
        up,
        &counted,
        &bounds,
        warm,
    )
    .map_err(|e| Error::Invalid(format!("{}: {e}", take.path.display())))?;
    let heights = com_heights(&r.model, &r.q, r.ground.up, r.ground.floor);
    let fig_after = figures(&r.ground, &heights, &counted);
    let (pelvis_peak_m, pelvis_rms_m) = r.pelvis_peak_rms();
    let adjustments = Adjustments {
        trunk_offset_m: r.trunk_offset,
        trunk_mass_kg: r.trunk_mass_kg,
        pelvis_peak_m,
        pelvis_rms_m,
        rotation_peak_rms_rad: r.rotation_peak_rms(),
        mass_change_kg: (r.mass_scale - 1.0) * mass_kg,
        measured: measured.is_some(),
        stance_slide_m: stance_slide(&r.pelvis, &r.ground.contact),
        bounded: r.bounded.clone(),
        bounds,
        refined_knot_spacing_s: r.refined_knot_spacing_s,
        started: r.started,
    };
    let c = finish(
        fig_before,
        Some(fig_after),
        Some(adjustments),
        mass_kg,
        &r.ground,
        counted,
        travel,
        floor,
    );
    let mut adjusted = take.clone();
    adjusted.model = r.model;
    adjusted.states = Arc::new(States {
        time: take.states.time.clone(),
        q: r.q,
        v: r.v,
        a: r.a,
    });
    // the feet's contact as the take was loaded: the reduction held it through its trials
    adjusted.held_contact = measured.is_none().then(|| super::HeldContact {
        floor_velocity: params.floor_velocity,
        phases: before.contact.clone(),
    });
    Ok((Some(adjusted), r.ground, c, r.seed))
}

fn figures(g: &GroundReactions, heights: &[f64], counted: &[bool]) -> ResidualFigures {
    residual_figures(&g.residual, &external_forces(g), heights, counted)
}

/// The bodies of the trunk whose mass centre residual reduction moves: those of the joints
/// from the lumbar joint up to the head (arms left out), with mass.
pub fn trunk_bodies(take: &Take) -> Vec<usize> {
    let Ok(human) = find_take_human(take) else {
        return vec![];
    };
    let Some(spine) = human.spine else {
        return vec![];
    };
    let mut bodies = vec![];
    let mut j = Some(spine.head);
    while let Some(joint) = j {
        let b = take.map.joints[joint].body;
        if take.model.inertia[b].mass > 0.0 && !bodies.contains(&b) {
            bodies.push(b);
        }
        if joint == spine.lumbar {
            break;
        }
        j = take.bvh.joints[joint].parent;
    }
    bodies
}

/// The largest change of the offsets `pelvis` (per frame) over one foot's contact phase (m).
fn stance_slide(pelvis: &[Vector3<f64>], contact: &[Vec<bool>]) -> f64 {
    let feet = contact.first().map_or(0, Vec::len);
    let mut slide: f64 = 0.0;
    for j in 0..feet {
        let on: Vec<bool> = contact.iter().map(|c| c[j]).collect();
        for (a, b) in runs(&on) {
            for k in a..=b {
                slide = slide.max((pelvis[k] - pelvis[a]).norm());
            }
        }
    }
    slide
}

/// The trunk's long axis, from the lumbar joint to the head, in the frame of the lumbar joint's
/// body at the rest pose (`None`: no trunk).
fn trunk_long_axis(take: &Take) -> Option<Vector3<f64>> {
    let spine = find_take_human(take).ok()?.spine?;
    let model = &take.model;
    let mut ws = crate::dynamics::Workspace::new(model);
    crate::dynamics::forward_kinematics(model, &mut ws, &model.neutral());
    let at = |j: usize| {
        let m = &take.map.joints[j];
        ws.o_x_i[m.body].compose(&m.frame).trans
    };
    let lumbar = &ws.o_x_i[take.map.joints[spine.lumbar].body];
    Some(lumbar.rot.transpose() * (at(spine.head) - at(spine.lumbar)))
}

/// The height (m) of the foot points above which no part of a foot touches the floor, for
/// [`GroundReactions::floor_lost`]: the contact test's exit height (a point below it may still
/// be planted) plus the reach of the sole beyond the heel and toe points
/// (`ContactParams::cop_margin`: the heel and the tips of the toes). A foot point 7–12 cm up
/// is as often a foot on the tips of its toes, or one whose floor level the other foot set
/// (CMU 05_20's dancer standing on one foot, 7 cm over the level of both, through a kick), as a
/// capture off its floor.
fn off_floor_height(params: &ContactParams) -> f64 {
    params.height_off + params.cop_margin
}

#[allow(clippy::too_many_arguments)]
fn finish(
    before: ResidualFigures,
    after: Option<ResidualFigures>,
    adjustments: Option<Adjustments>,
    mass_kg: f64,
    g: &GroundReactions,
    counted: Vec<bool>,
    travel: f64,
    (floor_lost, dt): (Vec<FloorLost>, f64),
) -> Consistency {
    let last = after.unwrap_or(before);
    let (force_n, moment_nm): (Vec<f64>, Vec<f64>) = g.residual.iter().map(split_norms).unzip();
    // the frames the feet cannot explain: those beyond the thresholds, and those where the
    // capture has left its floor (the root holds the body up there, whatever the thresholds)
    let lost = |k: usize| floor_lost.iter().any(|l| (l.first..=l.last).contains(&k));
    let beyond: Vec<bool> = (0..g.residual.len())
        .map(|k| counted[k] && (last.beyond(&g.residual[k]) || lost(k)))
        .collect();
    let floor_lost_note = floor_lost_text(&floor_lost, g.residual.len(), dt);
    let mut why = vec![];
    if !last.meets() {
        why.extend(floor_lost_note.clone());
        if travel < IN_PLACE_M {
            why.push(format!(
                "the pelvis travels {:.0} cm over the take: it moves in place (a keyframed \
                 cycle or a treadmill), and its floor is taken as a belt under the planted feet \
                 at one constant velocity; feet that slide at other speeds than the belt's, or a \
                 belt that changes speed, leave residuals no ground force explains",
                100.0 * travel
            ));
        }
        why.extend(why_missed(&last, g, &counted, &beyond, &floor_lost));
        match adjustments.as_ref() {
            Some(a) if !a.bounded.is_empty() => why.push(format!(
                "the {} bound held the adjustments back (trunk mass centre ≤ {:.0} cm, pelvis \
                 offset ≤ {:.0} cm peak and {:.0} cm RMS, pelvis rotation ≤ {:.0}° and {:.0}°, \
                 OpenSim's guidelines for RRA): what remains would take a larger change of the \
                 model or the motion than they allow",
                a.bounded.join(" and "),
                100.0 * a.bounds.trunk_com_m,
                100.0 * a.bounds.pelvis_peak_m,
                100.0 * a.bounds.pelvis_rms_m,
                a.bounds.rotation_peak_rad.to_degrees(),
                a.bounds.rotation_rms_rad.to_degrees()
            )),
            Some(_) => why.push(
                "the adjustments stop inside their bounds: what remains is no smooth change of \
                 the trunk's mass centre or the pelvis path and orientation (the frames above)"
                    .into(),
            ),
            None => {}
        }
    }
    Consistency {
        before,
        after,
        adjustments,
        mass_kg,
        force_n,
        moment_nm,
        counted,
        beyond,
        floor_lost,
        floor_lost_note,
        why,
    }
}

/// A pelvis that travels less than this over a take (m) walks in place.
const IN_PLACE_M: f64 = 0.1;

/// Per frame, the height (m) of the whole-body centre of mass over the floor of `g`.
fn com_heights_of(g: &GroundReactions) -> Vec<f64> {
    g.com.iter().map(|c| c[g.up] - g.floor).collect()
}

/// How far the pelvis (`pelvis`, per frame, world) gets from where it starts, along the floor
/// (m, `up` the vertical axis), over the take.
fn pelvis_travel(pelvis: &[Vector3<f64>], up: usize) -> f64 {
    let mut start = None;
    let mut far: f64 = 0.0;
    for p in pelvis {
        let mut p = *p;
        p[up] = 0.0;
        let s = *start.get_or_insert(p);
        far = far.max((p - s).norm());
    }
    far
}

/// Runs of `true` in `flags` as `(first, last)` frames.
fn runs(flags: &[bool]) -> Vec<(usize, usize)> {
    crate::motion::runs(flags.len(), |k| flags[k])
        .into_iter()
        .map(|r| (r.start, r.end - 1))
        .collect()
}

/// A ratio to a threshold it exceeds as the reasons print it: `13.5×`, and below 1.1 with two
/// decimals rounded up (`1.04×`, `1.01×` for 1.004), so that a miss never reads as `1.0×` the
/// threshold (Mixamo's Gangnam Style: 14.9 N·m against 14.4 did).
fn times(ratio: f64) -> String {
    if ratio < 1.1 {
        format!("{:.2}×", (ratio * 100.0).ceil() / 100.0)
    } else {
        format!("{ratio:.1}×")
    }
}

/// Why the figures `f` miss the thresholds, from the frames `beyond` them (of those `counted`): how much of the
/// residual lies in flight and how far the needed centre of pressure lies off the feet.
fn why_missed(
    f: &ResidualFigures,
    g: &GroundReactions,
    counted: &[bool],
    beyond: &[bool],
    floor_lost: &[FloorLost],
) -> Vec<String> {
    let k = f.peak_force_frame;
    let lost_at = floor_lost.iter().find(|l| (l.first..=l.last).contains(&k));
    let mut why = vec![];
    if f.peak_force_n > f.force_limit_n() {
        why.push(format!(
            "peak residual force {:.0} N is {} the {:.0} % threshold ({:.0} N), at frame {}{}",
            f.peak_force_n,
            times(f.peak_force_n / f.force_limit_n().max(1e-9)),
            100.0 * FORCE_SHARE,
            f.force_limit_n(),
            f.peak_force_frame,
            if g.loaded[k].iter().any(|l| *l) {
                ": a foot is on the floor but the force leaves its friction cone or pulls".into()
            } else if let Some(l) = lost_at {
                format!(
                    ": no foot is on the floor, which the capture has left there (frames {}–{})",
                    l.first, l.last
                )
            } else {
                ": no foot is on the floor, yet the motion is not ballistic there (a missed \
                 contact, or the accelerations of a landing spread into the flight)"
                    .to_string()
            }
        ));
    }
    if f.rms_moment_nm > f.moment_limit_nm() {
        let frames: Vec<usize> = (0..beyond.len()).filter(|&k| beyond[k]).collect();
        let feet_on = |k: usize| g.loaded[k].iter().filter(|l| **l).count();
        // the centre-of-pressure gap of the frames with a foot down (in flight there is none
        // to measure, and a median over them read 0.0 cm on takes mostly in the air)
        let mut gaps: Vec<f64> = frames
            .iter()
            .filter(|&&k| feet_on(k) > 0)
            .map(|&k| g.cop_gap[k])
            .collect();
        gaps.sort_by(f64::total_cmp);
        let median = gaps.get(gaps.len() / 2).copied();
        let count = |n: usize| frames.iter().filter(|&&k| feet_on(k) == n).count();
        let (flight, single) = (count(0), count(1));
        let double = frames.len() - flight - single;
        // the share of the squared residual moment these frames hold
        let n2 = |k: usize| {
            let r = &g.residual[k];
            r[3] * r[3] + r[4] * r[4] + r[5] * r[5]
        };
        let total: f64 = (0..beyond.len()).filter(|&k| counted[k]).map(n2).sum();
        let share = frames.iter().map(|&k| n2(k)).sum::<f64>() / total.max(1e-12);
        why.push(format!(
            "RMS residual moment {:.1} N·m is {} the {:.0} % threshold ({:.1} N·m): {} frames \
             beyond it ({single} in single support, {double} in double support, {flight} in \
             flight) hold {:.0} % of it{}",
            f.rms_moment_nm,
            times(f.rms_moment_nm / f.moment_limit_nm().max(1e-9)),
            100.0 * MOMENT_SHARE,
            f.moment_limit_nm(),
            frames.len(),
            100.0 * share,
            match median {
                Some(m) => format!(
                    "; where a foot is down there, the needed centre of pressure lies a median \
                     {:.1} cm off the feet{}",
                    100.0 * m,
                    if m > 0.05 {
                        ": more than a smooth pelvis and trunk correction can move it (a \
                         missed contact, a prop, or feet that slide), not noise"
                    } else {
                        ""
                    }
                ),
                None => String::new(),
            }
        ));
    }
    let r = runs(beyond);
    if !r.is_empty() {
        let shown: Vec<String> = r
            .iter()
            .take(8)
            .map(|&(a, b)| {
                if a == b {
                    format!("{a}")
                } else {
                    format!("{a}–{b}")
                }
            })
            .collect();
        why.push(format!(
            "frames beyond the thresholds: {}{} (column residual:beyond)",
            shown.join(", "),
            if r.len() > 8 { ", …" } else { "" }
        ));
    }
    why
}

/// `articula anatomy`: the angles and moments of the take, with ground contact those of the
/// take made consistent when `reduce` (residual reduction; else as loaded), and its
/// consistency in [`Anatomy::consistency`](super::anatomy::Anatomy::consistency).
pub fn anatomy_consistent(take: &Take, reduce: bool) -> Result<super::anatomy::Anatomy, Error> {
    if take.options.contact == super::Contact::None {
        return super::anatomy::anatomy(take);
    }
    let (adjusted, ground, c) = consistent_take(take, reduce, None)?;
    let mut a = super::anatomy::anatomy_with(adjusted.as_ref().unwrap_or(take), Some(&ground))?;
    a.notes.extend(c.floor_lost_note.clone());
    a.consistency = Some(c);
    Ok(a)
}

/// `articula id`: the consistency of a job's take with ground contact (`None`: a robot, or
/// contact none); when `reduce`, the job's model, states and take become the adjusted ones.
pub fn consistent_job(
    job: &mut super::Job,
    reduce: bool,
    own_states: bool,
    measured: Option<&FootLoads>,
) -> Result<Option<Consistency>, Error> {
    let Some(take) = job.take.as_ref() else {
        return Ok(None);
    };
    if take.options.contact == super::Contact::None && measured.is_none() {
        return Ok(None);
    }
    if reduce && !own_states {
        return Err(Error::Invalid(
            "residual reduction adjusts the take's own motion: drop --states, or use \
             --consistent off"
                .into(),
        ));
    }
    let feet = take.options.contact == super::Contact::Feet;
    let (mut adjusted, ground, c) = consistent_take(take, reduce, measured)?;
    if let Some(note) = &c.floor_lost_note {
        // the notes of the take every output then reads
        match adjusted.as_mut() {
            Some(t) => t.notes.push(note.clone()),
            None => job.take.iter_mut().for_each(|t| t.notes.push(note.clone())),
        }
    }
    if measured.is_some() {
        // the measured loads on the (adjusted) motion: what the root still supplies
        job.measured = Some(ground);
    } else if adjusted.is_none() && feet {
        // the take as it is: the very estimate `job_torques` would make again
        job.estimated = Some(ground);
    }
    if let Some(t) = adjusted {
        if measured.is_none() {
            job.estimated = None;
        }
        job.model = t.model.clone();
        job.states = t.states.clone();
        job.take = Some(t);
    }
    Ok(Some(c))
}

mod say;

#[cfg(test)]
mod tests {
    #[test]
    fn a_miss_never_reads_as_once_the_threshold() {
        assert_eq!(super::times(14.9 / 14.4), "1.04×");
        assert_eq!(super::times(1.004), "1.01×");
        assert_eq!(super::times(13.54), "13.5×");
    }
}
