//! Ground contact of a take: the `--contact auto|feet|none` setting and how `auto` is
//! settled ([`contact_choice`], [`resolve_contact`]), the feet the ground reactions act on, the
//! ground reactions themselves (`dynamics::grf` on the take's states), and the frames at a
//! take's ends whose accelerations are not trustworthy ([`edge_frames`]).

use super::{Take, at_file};
use crate::dynamics::{self, Workspace};
use crate::error::Error;
use std::str::FromStr;
use std::sync::Arc;

/// Ground contact model of a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Contact {
    /// No contact: a floating avatar hangs from its root residual.
    None,
    /// Feet on a detected floor: ground reaction forces estimated. A take on which no foot is
    /// ever planted on a floor is an error.
    Feet,
    /// Feet when the take stands on a floor, none when it never touches one (the default;
    /// [`contact_choice`] decides and says why).
    Auto,
}

impl Contact {
    /// The names `none`, `feet`, `auto` and their variants: the one table parsing and printing
    /// read.
    const NAMES: [(&'static str, Contact); 3] = [
        ("none", Contact::None),
        ("feet", Contact::Feet),
        ("auto", Contact::Auto),
    ];
}

impl FromStr for Contact {
    type Err = Error;
    fn from_str(s: &str) -> Result<Self, Error> {
        let s = s.trim();
        Contact::NAMES
            .iter()
            .find(|(n, _)| *n == s)
            .map(|(_, c)| *c)
            .ok_or_else(|| {
                Error::Invalid(format!("contact `{s}`: expected `auto`, `feet` or `none`"))
            })
    }
}

impl std::fmt::Display for Contact {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        let name = Contact::NAMES
            .iter()
            .find(|(_, c)| c == self)
            .map(|(n, _)| *n);
        f.write_str(name.unwrap_or("?"))
    }
}

/// What `--contact auto` gives on `take` ([`Contact::Feet`] or [`Contact::None`]) and why, for
/// a user: feet when the take is a floating body with feet of which at least one is planted on
/// a floor some of the time ([`stance`](crate::dynamics::grf::stance)); otherwise none, and
/// the reason (too few frames, no floating root, no feet, no foot ever planted).
pub fn contact_choice(take: &Take) -> (Contact, String) {
    contact_choice_for(take, &contact_feet(take), &mut FitOnce::new(None))
}

/// A take's contact fit for one [`resolve_contact_after`]: the one given, else the take's kept
/// one, else made where it is first read (the auto choice or the heights note) and then kept.
struct FitOnce<'a> {
    given: Option<&'a ContactFit>,
    made: Option<Result<Arc<ContactFit>, String>>,
}

impl<'a> FitOnce<'a> {
    fn new(given: Option<&'a ContactFit>) -> Self {
        Self { given, made: None }
    }

    /// The fit of `take`'s `feet` ([`ContactFit::of`]), made on the first call.
    fn get(
        &mut self,
        take: &Take,
        feet: &[crate::motion::contact::Foot],
    ) -> Result<&ContactFit, String> {
        if let Some(f) = self.given {
            return Ok(f);
        }
        let made = self
            .made
            .get_or_insert_with(|| kept_or_new_fit(take, Some(feet)).map_err(|e| e.to_string()));
        made.as_deref().map_err(Clone::clone)
    }
}

/// [`contact_choice`] with the take's feet already found ([`contact_feet`]) and its fit
/// ([`FitOnce`]).
fn contact_choice_for(
    take: &Take,
    feet: &[crate::motion::contact::Foot],
    fit: &mut FitOnce,
) -> (Contact, String) {
    use crate::motion::contact::{ContactParams, heights_note};
    let s = &take.states;
    if s.len() < 3 {
        return (
            Contact::None,
            format!("a take of {} frame(s) has no contact phases", s.len()),
        );
    }
    if crate::dynamics::grf::floating_root(&take.model).is_none() {
        return (
            Contact::None,
            "the model has no floating root: nothing of it stands on a floor".into(),
        );
    }
    if feet.is_empty() {
        return (Contact::None, "no feet found on the skeleton".into());
    }
    let (params, wobble, points) = match fit.get(take, feet) {
        Ok(f) => (f.params, f.wobble, &f.paths.points),
        Err(e) => return (Contact::None, e),
    };
    let up = take.up.index();
    match crate::dynamics::grf::stance(points, &s.time, up, &params) {
        Ok(by_foot) => {
            let share = |c: &Vec<bool>| {
                100.0 * c.iter().filter(|x| **x).count() as f64 / c.len().max(1) as f64
            };
            let on: Vec<String> = feet
                .iter()
                .zip(&by_foot)
                .map(|(f, c)| format!("{} {:.0} %", f.name, share(c)))
                .collect();
            let heights = heights_note(&params, &ContactParams::default(), wobble)
                .map_or(String::new(), |n| format!("; {n}"));
            (
                Contact::Feet,
                format!(
                    "the feet stand on a floor (frames on it: {}){heights}",
                    on.join(", ")
                ),
            )
        }
        Err(why) => (Contact::None, why),
    }
}

/// The contact thresholds of `take` and the wobble of its planted feet that set their
/// heights: [`ContactParams::for_take`] (the spread of the take's smoothing and frame time)
/// with the heights fitted to the heel and toe paths of its feet
/// ([`ContactParams::fitted_to`]; a take without feet or frames keeps the default heights).
/// What contact detection, the ground reactions and residual reduction all use.
///
/// [`ContactParams::for_take`]: crate::motion::contact::ContactParams::for_take
/// [`ContactParams::fitted_to`]: crate::motion::contact::ContactParams::fitted_to
pub fn contact_params(
    take: &Take,
) -> Result<
    (
        crate::motion::contact::ContactParams,
        Option<crate::motion::contact::Wobble>,
    ),
    Error,
> {
    kept_or_new_fit(take, None).map(|f| (f.params, f.wobble))
}

/// The contact fit of `take`: the one it keeps ([`Take::kept_fit`]), else one made now for
/// `feet` (default: [`contact_feet`]). The one way every reader of the thresholds and paths
/// gets them.
pub(super) fn kept_or_new_fit(
    take: &Take,
    feet: Option<&[crate::motion::contact::Foot]>,
) -> Result<Arc<ContactFit>, Error> {
    if let Some(f) = take.kept_fit() {
        return Ok(f);
    }
    match feet {
        Some(feet) => ContactFit::of(take, feet),
        None => ContactFit::new(take),
    }
    .map(Arc::new)
}

/// A take's contact thresholds fitted to its feet ([`contact_params`]) and the heel and toe
/// paths they were fitted to: what no mass changes, made once per motion. The workbench keeps
/// it with its results and a mass edit reuses it ([`same_motion`]); the auto choice, the
/// notes, the estimate and residual reduction all read it.
#[derive(Debug, Clone)]
pub struct ContactFit {
    pub params: crate::motion::contact::ContactParams,
    pub wobble: Option<crate::motion::contact::Wobble>,
    /// The feet with their heel points fitted, and their heel and toe paths.
    pub paths: crate::dynamics::grf::FootPaths,
}

impl ContactFit {
    /// The fit of `take`'s contact feet ([`contact_feet`]).
    pub fn new(take: &Take) -> Result<Self, Error> {
        Self::of(take, &contact_feet(take))
    }

    fn of(take: &Take, feet: &[crate::motion::contact::Foot]) -> Result<Self, Error> {
        let (params, wobble, paths) = fitted_params(take, feet)?;
        Ok(Self {
            params,
            wobble,
            paths,
        })
    }
}

/// A [`ContactFit`] kept on the take it was made for ([`Take::contact_fit`]), read back
/// ([`Take::kept_fit`]) only while the take has the very states it was fitted to (the same
/// allocation: residual reduction, which moves the pelvis, gives the take new ones) and the
/// same body placements and up axis, what the heel and toe paths also read.
#[derive(Debug, Clone)]
pub struct KeptFit {
    fit: Arc<ContactFit>,
    states: std::sync::Weak<super::States>,
    placement: Vec<crate::spatial::SpatialTransform>,
    up: crate::model::bvh::UpAxis,
}

impl Take {
    /// The contact fit kept on this take ([`Take::contact_fit`]) while it is still this take's.
    pub fn kept_fit(&self) -> Option<Arc<ContactFit>> {
        let k = self.contact_fit.as_ref()?;
        let same = std::ptr::eq(k.states.as_ptr(), Arc::as_ptr(&self.states))
            && k.up == self.up
            && k.placement == self.model.placement;
        same.then(|| k.fit.clone())
    }

    /// Keeps `fit`, made for this take as it is now.
    fn keep_fit(&mut self, fit: Arc<ContactFit>) {
        self.contact_fit = Some(KeptFit {
            fit,
            states: Arc::downgrade(&self.states),
            placement: self.model.placement.clone(),
            up: self.up,
        });
    }
}

/// [`contact_params`] of `take` for its `feet`, and the heel and toe paths they were fitted
/// to (none when the take has no feet or fewer than two frames).
fn fitted_params(
    take: &Take,
    feet: &[crate::motion::contact::Foot],
) -> Result<
    (
        crate::motion::contact::ContactParams,
        Option<crate::motion::contact::Wobble>,
        crate::dynamics::grf::FootPaths,
    ),
    Error,
> {
    use crate::motion::contact::ContactParams;
    let base = ContactParams {
        floor_velocity: take.held_contact.as_ref().and_then(|h| h.floor_velocity),
        ..ContactParams::for_take(&take.smooth, take.bvh.frame_time)?
    };
    let s = &take.states;
    if s.len() < 2 || feet.is_empty() {
        return Ok((base, None, Default::default()));
    }
    let up = take.up.index();
    let paths = crate::dynamics::grf::fitted_foot_paths(&take.model, feet, &s.q, up);
    let dt = (s.time[s.len() - 1] - s.time[0]) / (s.len() - 1) as f64;
    let (params, wobble) = base.fitted_to(&paths.points, up, dt);
    Ok((params, wobble, paths))
}

/// The note of the contact heights of `take` with its `feet` when they were fitted below the
/// defaults (`--contact auto` says so in its choice, [`contact_choice`]).
fn fitted_heights_note(
    take: &Take,
    feet: &[crate::motion::contact::Foot],
    fit: &mut FitOnce,
) -> Option<String> {
    use crate::motion::contact::{ContactParams, heights_note};
    let f = fit.get(take, feet).ok()?;
    heights_note(&f.params, &ContactParams::default(), f.wobble)
}

/// The contact model of each of `feet`, for the notes: the sole a segment from its heel point
/// to its toe point, and where the toe point is (a toe joint's origin, or without one a point
/// along the foot's own bone), lengths at the take's first frame. `None` without feet.
fn contact_model_note(take: &Take, feet: &[crate::motion::contact::Foot]) -> Option<String> {
    let q = take.states.q.first()?;
    if feet.is_empty() {
        return None;
    }
    let mut ws = crate::dynamics::Workspace::new(&take.model);
    crate::dynamics::forward_kinematics(&take.model, &mut ws, q);
    let each: Vec<String> = feet
        .iter()
        .map(|f| {
            let length = 100.0 * (f.toe(&ws.o_x_i) - f.heel(&ws.o_x_i)).norm();
            let toe_joint = take
                .bvh
                .joints
                .iter()
                .zip(&take.map.joints)
                .find(|(j, m)| {
                    f.toe_body != f.ankle_body && m.body == f.toe_body && j.name != f.joint
                })
                .map(|(j, _)| j.name.as_str());
            match toe_joint {
                Some(toe) => format!(
                    "{} `{}`: heel and toe points {length:.1} cm apart, the toe at `{toe}`",
                    f.name, f.joint
                ),
                None => format!(
                    "{} `{}`: no toe joint, the toe point {length:.1} cm from the heel along \
                     the foot's own bone",
                    f.name, f.joint
                ),
            }
        })
        .collect();
    Some(format!(
        "contact model per foot (the sole a segment from the heel point to the toe point; the \
         centre of pressure kept on it): {}",
        each.join("; ")
    ))
}

/// Why `take` has no ground contact, for a message: `contact auto chose none: <its reason>`
/// when `auto` settled on none ([`resolve_contact`] keeps it in `Take::contact_auto`), else
/// `None` (the user chose `--contact none`).
pub fn auto_chose_none(take: &Take) -> Option<String> {
    match &take.contact_auto {
        Some((Contact::None, why)) => Some(format!("contact auto chose none: {why}")),
        _ => None,
    }
}

/// Settles `--contact auto` on a loaded take: sets [`TakeOptions::contact`] to what
/// [`contact_choice`] gives and notes the choice (`info`, the commands' notes, the workbench's
/// status line); any other setting is left as it is (`feet` notes contact heights fitted
/// below the defaults). With feet, notes each foot's contact model.
pub fn resolve_contact(take: &mut Take) {
    resolve_contact_after(take, None, None);
}

/// [`resolve_contact`] after `previous`, a take whose `auto` was settled as `choice`: when
/// [`same_motion`] says the two differ at most in their masses (a workbench mass edit), its
/// choice is taken as it is (the stance it found reads no mass), else the stance is found
/// again. Returns the choice `auto` settled on (`None`: the take's contact was not `auto`).
/// The take's feet are found once for the choice and the notes; `fit`, when given, is the
/// take's [`ContactFit`] (else it is made where needed).
pub fn resolve_contact_after(
    take: &mut Take,
    previous: Option<(&Take, &(Contact, String))>,
    fit: Option<&ContactFit>,
) -> Option<(Contact, String)> {
    let auto = take.options.contact == Contact::Auto;
    let feet = (take.options.contact != Contact::None).then(|| contact_feet(take));
    let feet = feet.as_deref().unwrap_or(&[]);
    // without a fit given, the one the choice or the notes make is kept on the take for the
    // estimate and the reduction that follow (`kept_fit`): fitted once
    let mut fit = FitOnce::new(fit);
    let choice = auto.then(|| match previous.filter(|(p, _)| same_motion(p, take)) {
        Some((_, choice)) => choice.clone(),
        None => contact_choice_for(take, feet, &mut fit),
    });
    if let Some((contact, why)) = &choice {
        take.options.contact = *contact;
        take.notes.push(format!("contact auto: {contact}: {why}"));
        take.contact_auto = Some((*contact, why.clone()));
    }
    if take.options.contact == Contact::Feet {
        // `auto` says fitted heights in its choice
        let heights = if auto {
            None
        } else {
            fitted_heights_note(take, feet, &mut fit)
        };
        let model = contact_model_note(take, feet);
        take.notes.extend(heights.into_iter().chain(model));
    }
    if let Some(Ok(f)) = fit.made {
        take.keep_fit(f);
    }
    choice
}

/// True when `a` and `b` have the same motion, skeleton and model kinematics (tree, joints,
/// placements, map, up axis, unit, smoothing, landmarks, times and configurations): all that
/// the contact phases and the anatomical frames read. Masses and inertias may differ.
pub fn same_motion(a: &Take, b: &Take) -> bool {
    let (ma, mb) = (&a.model, &b.model);
    ma.parent == mb.parent
        && ma.joints == mb.joints
        && ma.placement == mb.placement
        && ma.gravity == mb.gravity
        && a.map == b.map
        && a.up == b.up
        && a.scale_to_m == b.scale_to_m
        && a.smooth == b.smooth
        && a.human == b.human
        && (Arc::ptr_eq(&a.states, &b.states)
            || (a.states.time == b.states.time && a.states.q == b.states.q))
        && (Arc::ptr_eq(&a.bvh, &b.bvh) || a.bvh == b.bvh)
}

/// Frames at each end of a take whose estimated accelerations are not trustworthy: those
/// within the estimator's reach of its first or last frame
/// ([`acceleration_spread_s`](crate::motion::contact::acceleration_spread_s) of the take's
/// smoothing: 8 frames at 120 fps and 3 at 30 fps with `butterworth:6hz`, 1 without
/// smoothing), where the smoothing and the differences see past the take's ends. 0 on a take
/// too short to spare them (one that would keep fewer than a third of its frames, as
/// [`counted_frames`](crate::dynamics::residual::counted_frames) says). The residual figures
/// count the same frames (`pipeline::consistency`).
pub fn edge_frames(take: &Take) -> usize {
    let dt = take.bvh.frame_time;
    let Ok(h) = crate::motion::contact::acceleration_spread_s(&take.smooth, dt) else {
        return 0;
    };
    let e = (h / dt).round().max(1.0) as usize;
    if take.states.len() < 6 * e { 0 } else { e }
}

/// Ground reactions of a take with `--contact feet` (`None` with `--contact none`; with
/// `auto`, as [`contact_choice`] decides).
pub fn ground_reactions(
    take: &Take,
) -> Result<Option<crate::dynamics::grf::GroundReactions>, Error> {
    ground_reactions_with(take, &mut |_| true)
}

/// [`ground_reactions`] that reports its progress (0‥1) to `keep_going` every
/// [`PROGRESS_EVERY`](crate::dynamics::grf::PROGRESS_EVERY) frames and stops with [`Error::Cancelled`] when it returns false.
pub fn ground_reactions_with(
    take: &Take,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<Option<crate::dynamics::grf::GroundReactions>, Error> {
    let contact = match take.options.contact {
        Contact::Auto => contact_choice(take).0,
        c => c,
    };
    if contact == Contact::None {
        return Ok(None);
    }
    estimate_take_ground_reactions_with(take, keep_going).map(Some)
}

/// Ground reactions of a take whatever its `contact` option: the feet found through the BVH
/// skeleton ([`feet_of_bvh`](crate::motion::contact::feet_of_bvh)), the contact thresholds
/// fitted to the take ([`contact_params`]).
pub fn estimate_take_ground_reactions(
    take: &Take,
) -> Result<crate::dynamics::grf::GroundReactions, Error> {
    estimate_take_ground_reactions_with(take, &mut |_| true)
}

/// [`estimate_take_ground_reactions`] with progress and cancel
/// ([`estimate_ground_reactions_progress`](crate::dynamics::grf::estimate_ground_reactions_progress)).
pub fn estimate_take_ground_reactions_with(
    take: &Take,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<crate::dynamics::grf::GroundReactions, Error> {
    estimate_take_ground_reactions_keeping(take, &[], keep_going)
}

/// [`estimate_take_ground_reactions_with`] that keeps the net moments on `moment_bodies`
/// ([`GroundReactions::moments`](crate::dynamics::grf::GroundReactions::moments): the
/// anatomical series read them, `pipeline::anatomy::moment_bodies`).
pub fn estimate_take_ground_reactions_keeping(
    take: &Take,
    moment_bodies: &[usize],
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<crate::dynamics::grf::GroundReactions, Error> {
    let f = kept_or_new_fit(take, None).map_err(|e| at_file(&take.path, e))?;
    estimate_with_params(take, &f.params, Some(&f.paths), moment_bodies, keep_going)
}

/// [`estimate_take_ground_reactions_keeping`] with the take's thresholds already made
/// ([`contact_params`]; residual reduction reads the same ones), and the feet's paths they
/// were fitted to when the caller has them ([`ContactFit::paths`]).
pub(super) fn estimate_with_params(
    take: &Take,
    params: &crate::motion::contact::ContactParams,
    paths: Option<&crate::dynamics::grf::FootPaths>,
    moment_bodies: &[usize],
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<crate::dynamics::grf::GroundReactions, Error> {
    let s = &take.states;
    crate::dynamics::grf::estimate_ground_reactions_keeping(
        &take.model,
        &contact_feet(take),
        &s.time,
        [&s.q, &s.v, &s.a],
        take.up.index(),
        (
            params,
            take.held_contact.as_ref().map(|h| &h.phases[..]),
            paths,
        ),
        moment_bodies,
        keep_going,
    )
    .map_err(|e| at_file(&take.path, e))
}

/// The feet that carry a take's ground reactions: a human's [`take_feet`]; for a skeleton that
/// is not a human's, the limb ends that come down to the floor when they are more than the feet
/// its names give (an animal, a rig whose names no scheme knows, a quadruped rigged as a biped
/// whose front legs are named arms), else the named feet.
pub fn contact_feet(take: &Take) -> Vec<crate::motion::contact::Foot> {
    let feet = take_feet(take);
    if take.human.is_ok() {
        return feet;
    }
    let ends = limb_ends_on_floor(take);
    if ends.len() > feet.len() { ends } else { feet }
}

/// A human's feet at the ankles and toes its topology found (`model::skeleton`), else the
/// feet its names say ([`feet_of_bvh`](crate::motion::contact::feet_of_bvh)).
pub fn take_feet(take: &Take) -> Vec<crate::motion::contact::Foot> {
    use crate::motion::contact::{Side, feet_at, feet_of_bvh};
    match &take.human {
        Ok(h) => {
            let side = |l: &crate::model::skeleton::Leg| match l.side {
                crate::model::anthropometry::Side::Left => Side::Left,
                _ => Side::Right,
            };
            let legs: Vec<_> = h.legs.iter().map(|l| (side(l), l.ankle, l.toe)).collect();
            feet_at(&take.bvh, &take.map, &take.model, &legs)
        }
        Err(_) => feet_of_bvh(&take.bvh, &take.map, &take.model),
    }
}

/// The feet of a skeleton that is not a human's: the limb ends
/// ([`limb_ends`](crate::motion::contact::limb_ends)) that come down to the floor, their
/// lowest point over the take (ankle or toe, at up to 64 evenly spaced frames) within 15 % of
/// the stature of the lowest of all: a quadruped's four feet, a crab's eight legs, not its
/// nose, tail or raised claws.
fn limb_ends_on_floor(take: &Take) -> Vec<crate::motion::contact::Foot> {
    let (model, up) = (&take.model, take.up.index());
    let mut ends = crate::motion::contact::limb_ends(&take.bvh, &take.map, model);
    let mut ws = Workspace::new(model);
    let mut lowest = vec![f64::INFINITY; ends.len()];
    let n = take.states.len();
    for k in (0..n).step_by(n.div_ceil(64).max(1)) {
        dynamics::forward_kinematics(model, &mut ws, &take.states.q[k]);
        for (low, f) in lowest.iter_mut().zip(&ends) {
            let a = ws.o_x_i[f.ankle_body].transform_point(&f.ankle_point)[up];
            let t = ws.o_x_i[f.toe_body].transform_point(&f.toe_point)[up];
            *low = low.min(a).min(t);
        }
    }
    let floor = lowest.iter().copied().fold(f64::INFINITY, f64::min);
    let reach = 0.15 * take.stature_m;
    let mut keep = lowest.iter().map(|l| *l <= floor + reach);
    ends.retain(|_| keep.next().unwrap_or(false));
    ends
}

#[cfg(test)]
mod tests {
    //! A take's contact fit is made once, by `resolve_contact`, and read back by what follows
    //! (the estimate, residual reduction: [`contact_params`]) only while the take has the states
    //! and body placements it was made for.
    use super::*;
    use crate::pipeline::{TakeOptions, load_take};

    fn demo(contact: Contact) -> Take {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/demo_walk.bvh");
        let opts = TakeOptions {
            contact,
            ..TakeOptions::default()
        };
        load_take(&path, &opts).unwrap()
    }

    #[test]
    fn the_estimate_from_the_fits_foot_paths_is_the_estimate_that_fits_them_again() {
        // the estimate reads the kept fit's fitted feet and heel and toe paths instead of
        // fitting the same feet to the same poses: the same ground reactions, bit for bit
        // (the fit's kinematics are the first pass's), torques and kept moments included
        let mut take = demo(Contact::Auto);
        resolve_contact(&mut take);
        let kept = take.kept_fit().expect("kept by resolve_contact");
        let bodies = [1, 2];
        let estimate = |paths| {
            estimate_with_params(&take, &kept.params, paths, &bodies, &mut |_| true).unwrap()
        };
        let (read, fitted) = (estimate(Some(&kept.paths)), estimate(None));
        assert_eq!(read, fitted);
        assert_eq!(
            estimate_take_ground_reactions_keeping(&take, &bodies, &mut |_| true).unwrap(),
            fitted
        );
        // and they are read: paths with their heels moved give other loads
        let mut moved = kept.paths.clone();
        for f in &mut moved.feet {
            f.heel_point.x += 0.05;
        }
        assert_ne!(estimate(Some(&moved)), fitted);
        // paths made for other feet, or other frames, are not read
        let mut other = kept.paths.clone();
        other.given[0].toe_point.x += 0.01;
        other.feet = moved.feet.clone();
        assert_eq!(estimate(Some(&other)), fitted);
        let mut shorter = moved.clone();
        for p in &mut shorter.points {
            p.toe.pop();
        }
        assert_eq!(estimate(Some(&shorter)), fitted);
    }

    #[test]
    fn the_fit_resolve_contact_makes_is_read_back_while_the_motion_is_the_same() {
        for contact in [Contact::Auto, Contact::Feet] {
            let mut take = demo(contact);
            assert!(take.kept_fit().is_none(), "none as loaded");
            let fresh = contact_params(&take).unwrap();
            resolve_contact(&mut take);
            assert_eq!(take.options.contact, Contact::Feet);
            let kept = take.kept_fit().expect("kept by resolve_contact");
            assert_eq!((kept.params, kept.wobble), fresh, "{contact}");
            assert!(!kept.paths.points.is_empty());

            // read back, not fitted again: a changed kept threshold is what the estimate gets
            let mut changed = (*kept).clone();
            changed.params.height_on += 0.5;
            take.keep_fit(Arc::new(changed));
            let read = contact_params(&take).unwrap().0.height_on;
            assert_eq!(read, fresh.0.height_on + 0.5);
            assert!(
                take.clone().kept_fit().is_some(),
                "a clone shares the states"
            );

            // new states (residual reduction gives the take new ones), moved bodies or another
            // up axis: fitted again
            let mut moved = take.clone();
            moved.states = Arc::new((*take.states).clone());
            assert!(moved.kept_fit().is_none());
            assert_eq!(contact_params(&moved).unwrap(), fresh);
            let mut placed = take.clone();
            placed.model.placement[2].trans.x += 0.01;
            assert!(placed.kept_fit().is_none());
            let mut turned = take.clone();
            turned.up = match take.up {
                crate::model::bvh::UpAxis::Y => crate::model::bvh::UpAxis::Z,
                _ => crate::model::bvh::UpAxis::Y,
            };
            assert!(turned.kept_fit().is_none());
        }
    }

    #[test]
    fn no_fit_is_made_without_contact() {
        let mut take = demo(Contact::None);
        resolve_contact(&mut take);
        assert!(take.contact_fit.is_none());
    }
}
