//! Stages 1–4 of the module doc, and the [`Take`] they make: read the BVH (a rest pose as
//! frame 0 dropped), then axes, unit and stature, position semantics, the model (de Leva masses,
//! a helper root folded, joint translations welded, twist helpers folded), and the states of
//! stages 5–7 (`states/`), reused from a previous take of the same motion when they would be
//! the same.

use super::anatomy;
use super::reduce;
use super::stages::Stage;
use super::{States, TakeOptions, apply_damping, default_smoothing, take_states_marked};
use crate::error::Error;
use crate::io::bvh::{self, Bvh, JointTranslations, ResolvedPosition, UpAxis};
use crate::model::Model;
use crate::model::anthropometry::{BodyParams, SegmentTable};
use crate::model::bvh::{BvhMap, BvhModelOptions, build_bvh_model};
use crate::motion::smooth::SmoothSpec;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Frame times below this (10 kHz) are noted as likely wrong: motion capture runs at 1 kHz at
/// most.
const MIN_PLAUSIBLE_FRAME_TIME_S: f64 = 1e-4;

/// A loaded take: the file, what was detected, the model and its states.
#[derive(Debug, Clone)]
pub struct Take {
    pub path: PathBuf,
    pub bvh: Arc<Bvh>,
    pub options: TakeOptions,
    pub up: UpAxis,
    /// The unit used (detected or given); with `--stature`, the scale is in `scale_to_m`.
    pub unit: String,
    /// Metres per file length unit.
    pub scale_to_m: f64,
    /// Rest-pose stature (m) after scaling.
    pub stature_m: f64,
    /// The table that gave the segment masses (with `stature_m` for the regression); `None`:
    /// no trunk among the joint names, link masses by bone volume.
    pub segments: Option<SegmentTable>,
    pub positions: Vec<ResolvedPosition>,
    pub model: Model,
    pub map: BvhMap,
    /// The smoothing applied: the one given, or the default that fits the take.
    pub smooth: SmoothSpec,
    /// A massless helper root folded into its child (`motion::fold`): `bvh` holds the folded
    /// motion, this the file's root channels, so outputs can give the root motion back.
    pub fold: Option<crate::motion::fold::Fold>,
    /// The position channels held at their mean (`motion::weld`): `bvh` holds them so, as the
    /// model does.
    pub welded: Vec<crate::motion::weld::Welded>,
    /// The joints inside a human's long bones and whether each was folded into the next joint
    /// as a twist helper (`motion::twist`): `bvh` holds the folded motion, as the model does.
    pub twists: Vec<crate::motion::twist::Twist>,
    /// q, v, a after unwrapping, smoothing and differentiation; shared (not copied) by a take
    /// made again with the same motion ([`take_from_bvh_reusing`]) and by the take's clones.
    pub states: Arc<States>,
    /// What stages 5–7 found (passages near gimbal lock, capture glitches), also in `notes`.
    pub passages: Vec<String>,
    /// What the loader changed on its own, for `info` (e.g. a folded helper root).
    pub notes: Vec<String>,
    /// The skeleton's human landmarks (`model::skeleton`), or why it is not a human's.
    pub human: Result<crate::model::skeleton::Human, String>,
    /// The contact of the take it was derived from, when it is not to be found from its own
    /// feet: `None` as loaded; a take derived from another by residual reduction
    /// (`pipeline::consistency`) keeps its source's, since moving the pelvis moves no floor and
    /// lifts no foot (its feet slide instead, by `stance_slide_m`).
    pub held_contact: Option<HeldContact>,
    /// What `--contact auto` settled on and why (`pipeline::resolve_contact`); `None` while
    /// unsettled, or when the contact was chosen by the user.
    pub contact_auto: Option<(super::Contact, String)>,
    /// The contact thresholds fitted to this take's feet, kept by `pipeline::resolve_contact`
    /// for the estimate and the reduction that follow ([`Take::kept_fit`]); `None` as loaded.
    pub contact_fit: Option<super::KeptFit>,
}

/// The contact a take derived by residual reduction keeps from its source ([`Take::held_contact`]).
#[derive(Debug, Clone, PartialEq)]
pub struct HeldContact {
    /// The velocity (m/s, world axes, horizontal) of the floor the source stands on
    /// (`motion::contact::ContactParams::floor_velocity`).
    pub floor_velocity: Option<nalgebra::Vector3<f64>>,
    /// The source's contact phases, per frame, per foot (`dynamics::grf::Held`).
    pub phases: Vec<Vec<bool>>,
}

/// Stages 1–7 of the module doc.
pub fn load_take(path: &Path, opts: &TakeOptions) -> Result<Take, Error> {
    load_take_marked(path, None, opts, &mut |_| {})
}

/// [`load_take`] that calls `done` at the end of each stage ([`Stage`]); `text`, when given,
/// is the file's content already read (the bench's cycled take), else the file is read.
pub fn load_take_marked(
    path: &Path,
    text: Option<&[u8]>,
    opts: &TakeOptions,
    done: &mut dyn FnMut(Stage),
) -> Result<Take, Error> {
    // read; a rest pose stored as frame 0 (CMU conversions) is dropped
    let (bvh, note) = match text {
        Some(bytes) => trim_take(bvh::parse_bytes(bytes, path)?, opts.keep_first_frame),
        None => read_take(path, opts.keep_first_frame)?,
    };
    done(Stage::Parse);
    let mut take = take_from_bvh_marked(path, bvh, opts, &mut |_| true, done)?;
    take.notes.extend(note);
    Ok(take)
}

/// Stage 1: parses a BVH and, unless `keep_first_frame`, drops its frame 0 when that is a rest
/// pose before the motion (`motion::trim`); the note says so, for `info`.
pub fn read_take(path: &Path, keep_first_frame: bool) -> Result<(Bvh, Option<String>), Error> {
    Ok(trim_take(bvh::read(path)?, keep_first_frame))
}

/// The trimming half of [`read_take`].
fn trim_take(mut bvh: Bvh, keep_first_frame: bool) -> (Bvh, Option<String>) {
    if keep_first_frame {
        return (bvh, None);
    }
    let note = crate::motion::trim::trim_rest_first_frame(&mut bvh).map(|r| {
        format!(
            "frame 0 was dropped: a rest pose, not part of the motion (its step to frame 1 is \
             {:.0}× the median frame-to-frame step of the rotations, {:.0}× of the root \
             position); --keep-first-frame keeps it",
            r.rotation_ratio, r.position_ratio
        )
    });
    (bvh, note)
}

/// Stages 2–7 on an already parsed take.
pub fn take_from_bvh(path: &Path, bvh: Bvh, opts: &TakeOptions) -> Result<Take, Error> {
    take_from_bvh_with(path, bvh, opts, &mut |_| true)
}

/// [`take_from_bvh`] that reports its progress (0‥1) to `keep_going` (the smoothing once per
/// coordinate group, [`unwrap_and_smooth_with`]) and stops with [`Error::Cancelled`] when it
/// returns false.
///
/// [`unwrap_and_smooth_with`]: super::unwrap_and_smooth_with
pub fn take_from_bvh_with(
    path: &Path,
    bvh: Bvh,
    opts: &TakeOptions,
    keep_going: &mut dyn FnMut(f64) -> bool,
) -> Result<Take, Error> {
    take_from_bvh_marked(path, bvh, opts, keep_going, &mut |_| {})
}

/// [`take_from_bvh_with`] that calls `done` at the end of each stage ([`Stage::Model`], then
/// those of [`take_states_marked`]).
pub fn take_from_bvh_marked(
    path: &Path,
    bvh: Bvh,
    opts: &TakeOptions,
    keep_going: &mut dyn FnMut(f64) -> bool,
    done: &mut dyn FnMut(Stage),
) -> Result<Take, Error> {
    take_from_bvh_reusing(path, bvh, opts, None, keep_going, done)
}

/// [`take_from_bvh_marked`] that takes the states (stages 5–7: q, unwrap, smoothing, v, a)
/// from `previous`, a take of the same file, when they are the ones it would compute: the
/// same motion after the model stage's folds and welds, the same coordinates and joint kinds,
/// the same smoothing. The states read no mass, so an edit of the body mass, the sex, the
/// segment table or a link's mass keeps them: only the model (stages 2–4) is built again, and
/// `done` is called for [`Stage::Model`] alone. The result is the same, bit for bit, as
/// without `previous`.
pub fn take_from_bvh_reusing(
    path: &Path,
    mut bvh: Bvh,
    opts: &TakeOptions,
    previous: Option<&Take>,
    keep_going: &mut dyn FnMut(f64) -> bool,
    done: &mut dyn FnMut(Stage),
) -> Result<Take, Error> {
    let mut notes = vec![];
    let found = axes_and_unit(path, &bvh, opts, &mut notes)?;
    let built = model_stage(path, &mut bvh, opts, found, &mut notes)?;

    // q, smooth, v, a
    if !keep_going(0.1) {
        return Err(Error::Cancelled);
    }
    let smooth = chosen_smoothing(opts, bvh.frame_time, &mut notes);
    done(Stage::Model);
    let same_states = |p: &&Take| {
        p.smooth == smooth
            && p.model.q_names == built.model.q_names
            && p.model.v_names == built.model.v_names
            && p.model.joints == built.model.joints
            && p.model.parent == built.model.parent
            && p.model.idx_q == built.model.idx_q
            && p.map == built.map
            && *p.bvh == bvh
    };
    // the previous take's motion and states shared, not copied, when they are the same
    let (bvh, states, passages) = match previous.filter(same_states) {
        Some(p) => (p.bvh.clone(), p.states.clone(), p.passages.clone()),
        None => {
            let (states, passages) = take_states_marked(
                &bvh,
                &built.model,
                &built.map,
                &smooth,
                &mut |f| keep_going(0.1 + 0.9 * f),
                done,
            )?;
            (Arc::new(bvh), Arc::new(states), passages)
        }
    };
    notes.extend(passages.iter().cloned());
    let take = Take {
        path: path.to_path_buf(),
        bvh,
        options: opts.clone(),
        up: built.found.up,
        unit: built.found.unit,
        scale_to_m: built.found.scale_to_m,
        stature_m: built.found.stature_m,
        segments: built.segments,
        positions: built.found.positions,
        model: built.model,
        map: built.map,
        smooth,
        fold: built.fold,
        welded: built.welded,
        twists: built.twists,
        states,
        passages,
        notes,
        human: built.found.landmarks,
        held_contact: None,
        contact_auto: None,
        contact_fit: None,
    };
    match built.auto_lock {
        Some(tol) => reduce::lock_auto(take, tol),
        None => Ok(take),
    }
}

/// The smoothing given, or the default that fits the take ([`default_smoothing`]; a note when
/// that is none).
fn chosen_smoothing(opts: &TakeOptions, frame_time: f64, notes: &mut Vec<String>) -> SmoothSpec {
    match opts.smooth {
        Some(s) => s,
        None => {
            let (s, note) = default_smoothing(frame_time);
            notes.extend(note);
            s
        }
    }
}

/// What stages 2 and 3 find on a take, before its model is built.
struct Found {
    /// Each joint's position channel semantics.
    positions: Vec<ResolvedPosition>,
    /// The skeleton's geometry as the model holds it (`motion::weld::held_shape`: below the
    /// body's root, position channels at their mean in the OFFSETs) and its semantics; `None`:
    /// the take's own.
    held_shape: Option<(Bvh, Vec<ResolvedPosition>)>,
    up: UpAxis,
    /// The unit used (detected or given).
    unit: String,
    /// Metres per file length unit.
    scale_to_m: f64,
    /// Rest-pose stature (m) after scaling, or a human's standing height.
    stature_m: f64,
    /// A joint name reads as a trunk.
    trunk: bool,
    /// The skeleton's human landmarks, or why it is not a human's.
    landmarks: Result<crate::model::skeleton::Human, String>,
}

impl Found {
    /// The skeleton's geometry as the model holds it ([`Found::held_shape`], else `bvh`).
    fn shape<'a>(&'a self, bvh: &'a Bvh) -> &'a Bvh {
        match &self.held_shape {
            Some((b, _)) => b,
            None => bvh,
        }
    }
}

/// Stages 2–3: position semantics, up axis, whether the skeleton is a human's (by its names,
/// else by its shape), unit and stature, landmarks; `notes` gets what was assumed.
fn axes_and_unit(
    path: &Path,
    bvh: &Bvh,
    opts: &TakeOptions,
    notes: &mut Vec<String>,
) -> Result<Found, Error> {
    // axes and unit
    let named_human =
        crate::model::anthropometry::looks_human(bvh.joints.iter().map(|j| j.name.as_str()));
    let positions = bvh::resolve_position_modes(bvh, opts.positions);
    // the skeleton's geometry as the model holds it and any BVH written of the take says it:
    // below the body's root, position channels at their mean in the OFFSETs
    // (`motion::weld::held_shape`; with `--joint-translations keep` too, where the channels
    // move about that mean), so that the take written and read back gets the same up axis,
    // unit, stature, landmarks and segments
    let held_shape = crate::motion::weld::held_shape(bvh, opts.positions);
    let (shape, shape_positions) = match &held_shape {
        Some((b, m)) => (b, m.as_slice()),
        None => (bvh, positions.as_slice()),
    };
    let mut up = up_axis(bvh, shape, named_human, opts.up);
    // a human whose names say nothing (`J1`, `J2`, …) is one by its shape: two legs under an
    // upright trunk (`model::skeleton`); then the hips stand over its ankles
    let mut human = named_human;
    // (about the axis along which its trunk stands most upright)
    let sampled = anatomy::sample_bvh_poses(shape, shape_positions);
    if !named_human && let Some(u) = human_by_shape(shape, &sampled, up, opts.up) {
        human = true;
        up = u;
    }
    let scale = bvh::choose_scale(shape, up, opts.unit, opts.stature_m, human)
        .map_err(|e| at_file(path, e))?;
    // a human's segments by topology and geometry (names only as hints)
    let in_metres: Vec<_> = sampled.iter().map(|p| p.scaled(scale.scale_to_m)).collect();
    let landmarks = anatomy::human_of_bvh(shape, &in_metres, up);
    let trunk = crate::model::anthropometry::has_trunk(bvh.joints.iter().map(|j| j.name.as_str()));
    if landmarks.is_err() && !trunk {
        notes.push(
            "neither the shape (two legs under an upright trunk) nor a joint name reads as a \
             human's: link masses follow bone volume (de Leva's segment table needs a trunk)"
                .into(),
        );
    } else if landmarks.is_err() {
        // a biped rig's names on an animal (3ds Max `Bip01_Pelvis` on an elephant)
        notes.push(
            "not a human skeleton, but a joint name reads as a trunk: link masses follow the \
             human segment table (--segments: regression on mass and stature, or de Leva's \
             fractions) by the joint names, the missing segments' mass given to the trunk"
                .into(),
        );
    }
    let (unit, scale_to_m, mut stature_m) = (scale.unit, scale.scale_to_m, scale.stature_m);
    // a human's stature from its own dimensions, the same whatever its rest pose, so that the
    // same body written another way gets the same masses; a given stature always wins
    // (one scaled to a stature, given or fitted, keeps it)
    if opts.stature_m.is_none()
        && unit != "stature"
        && let Ok(h) = &landmarks
        && h.standing_height > 0.0
    {
        stature_m = h.standing_height;
    }
    notes.extend(scale.note);
    notes.extend(timing_notes(bvh));
    Ok(Found {
        positions,
        held_shape,
        up,
        unit,
        scale_to_m,
        stature_m,
        trunk,
        landmarks,
    })
}

/// The up axis: `given`, else detected on `shape` — a human's hips stand over its feet
/// however the body bends, a quadruped's feet tell where the floor is.
fn up_axis(bvh: &Bvh, shape: &Bvh, named_human: bool, given: Option<UpAxis>) -> UpAxis {
    match given {
        Some(u) => u,
        // hips stand over the feet, however the body bends
        None if named_human => {
            let joints: Vec<(&str, Option<usize>)> = bvh
                .joints
                .iter()
                .map(|j| (j.name.as_str(), j.parent))
                .collect();
            let (hips, feet) = crate::model::anthropometry::hips_and_feet(&joints);
            bvh::detect_up_by_legs(shape, &hips, &feet).unwrap_or_else(|| bvh::detect_up(shape))
        }
        // a quadruped is longer than tall: its feet tell where the floor is
        None => bvh::detect_up_by_feet(shape).unwrap_or_else(|| bvh::detect_up(shape)),
    }
}

/// The up axis of a skeleton whose names say nothing when its shape is a human's (about the
/// axis along which its trunk stands most upright; `up`, the detected one, or `given`);
/// `None`: not a human's.
fn human_by_shape(
    shape: &Bvh,
    sampled: &[crate::model::skeleton::Pose],
    up: UpAxis,
    given: Option<UpAxis>,
) -> Option<UpAxis> {
    let axes = match given {
        Some(u) => vec![u],
        None => vec![UpAxis::X, UpAxis::Y, UpAxis::Z],
    };
    let (axis, h) = axes
        .into_iter()
        .filter_map(|a| {
            anatomy::human_of_bvh(shape, sampled, a)
                .ok()
                .map(|h| (a, h))
        })
        // about another axis than the detected one, only a body that stands (its trunk
        // within 30° of the vertical in the median frame): an animal on its side does not
        .filter(|(a, h)| *a == up || h.lean < 30f64.to_radians())
        .min_by(|a, b| a.1.lean.total_cmp(&b.1.lean))?;
    let hips = [h.legs[0].hip, h.legs[1].hip];
    let ankles = [h.legs[0].ankle, h.legs[1].ankle];
    Some(match given {
        Some(u) => u,
        None => bvh::detect_up_by_legs(shape, &hips, &ankles).unwrap_or(axis),
    })
}

/// Notes on a frame time no capture system has and on a take too short to differentiate.
fn timing_notes(bvh: &Bvh) -> Vec<String> {
    let mut notes = vec![];
    if bvh.frame_time < MIN_PLAUSIBLE_FRAME_TIME_S {
        notes.push(format!(
            "the frame time, {} s ({:.0} fps), is shorter than any capture system's: check the \
             file's Frame Time (velocities scale with it, accelerations with its square)",
            bvh.frame_time,
            1.0 / bvh.frame_time
        ));
    }
    if bvh.frames < 3 {
        notes.push(format!(
            "the take has {} frame{}: velocities and accelerations need three frames or more \
             (they are {} here), so the torques hold gravity and the pose alone",
            bvh.frames,
            if bvh.frames == 1 { "" } else { "s" },
            if bvh.frames == 1 {
                "zero"
            } else {
                "one difference, and zero"
            }
        ));
    }
    notes
}

/// What stage 4 makes of a take: its model and how its motion was changed to fit it.
struct Built {
    found: Found,
    model: Model,
    map: BvhMap,
    segments: Option<SegmentTable>,
    fold: Option<crate::motion::fold::Fold>,
    welded: Vec<crate::motion::weld::Welded>,
    twists: Vec<crate::motion::twist::Twist>,
    /// `--lock auto:TOL`, applied once the take's states are known.
    auto_lock: Option<reduce::Tolerance>,
}

/// Stage 4: the model at the take's stature, with de Leva's masses, its branch helpers and
/// props welded; then, folded into `bvh` and the model built again, a massless helper root,
/// the joint translations held at their mean, the twist helpers inside long bones; last, the
/// joints' damping.
fn model_stage(
    path: &Path,
    bvh: &mut Bvh,
    opts: &TakeOptions,
    found: Found,
    notes: &mut Vec<String>,
) -> Result<Built, Error> {
    // model
    let name = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "take".into());
    // the body at the take's stature (the regression's second variable)
    let body = BodyParams {
        height_m: Some(found.stature_m),
        ..opts.body.clone()
    };
    let segments = if found.trunk || found.landmarks.is_ok() {
        let masses =
            crate::model::anthropometry::segment_masses(&body).map_err(|e| at_file(path, e))?;
        notes.extend(masses.notes);
        let radii =
            crate::model::anthropometry::segment_radii(&body).map_err(|e| at_file(path, e))?;
        notes.extend(radii.notes);
        Some(masses.table)
    } else {
        None
    };
    // `--lock auto:TOL` applies once the take's states are known (below)
    let (auto_lock, named_locks) = reduce::split_lock(&opts.lock)?;
    let positions = &found.positions;
    let mut mopts = BvhModelOptions {
        name,
        joints: opts.joints,
        scale_to_m: found.scale_to_m,
        up: found.up,
        positions: positions.clone(),
        body,
        lock: named_locks,
        subtree: opts.subtree.clone(),
        segments: None,
        held_positions: vec![],
        folded: vec![],
        bone_offsets: (found.held_shape.as_ref())
            .map(|(b, _)| b.joints.iter().map(|j| j.offset).collect())
            .unwrap_or_default(),
    };
    if let Ok(h) = &found.landmarks {
        weld_non_segments(found.shape(bvh), h, &mut mopts, notes);
    }
    let (mut model, mut map) = build_bvh_model(bvh, &mopts).map_err(|e| at_file(path, e))?;
    let (fold, pelvis) = fold_helper_root(bvh, positions, &model, &map, opts, &mut mopts, notes);

    // bones do not stretch: the position channels of the joints below the body's root are
    // held at their mean, in the frames and in the model (`motion::weld`)
    let welded = match opts.joint_translations {
        JointTranslations::Weld => {
            crate::motion::weld::weld_at_mean(bvh, positions, found.scale_to_m, pelvis)
        }
        JointTranslations::Keep => vec![],
    };
    notes.extend(crate::motion::weld::note(bvh, &welded));
    let twists = fold_twist_helpers(bvh, &found, &welded, &mopts);
    notes.extend(crate::motion::twist::note(bvh, &twists));
    mopts.folded = crate::motion::twist::folded(&twists);
    if fold.is_some() || !welded.is_empty() || !mopts.folded.is_empty() {
        mopts.held_positions = crate::motion::weld::held_positions(&welded, bvh.joints.len());
        (model, map) = build_bvh_model(bvh, &mopts).map_err(|e| at_file(path, e))?;
    }
    apply_damping(&mut model, &opts.damping).map_err(|e| at_file(path, e))?;
    Ok(Built {
        found,
        model,
        map,
        segments,
        fold,
        welded,
        twists,
        auto_lock,
    })
}

/// A human's joints that are no body part are made massless and welded (added to
/// `mopts.lock`), with a note each kind: helpers branching off a long bone, props and markers
/// reaching away from a hand, foot or head; the segments by topology go to `mopts.segments`.
fn weld_non_segments(
    shape: &Bvh,
    h: &crate::model::skeleton::Human,
    mopts: &mut BvhModelOptions,
    notes: &mut Vec<String>,
) {
    let (segments, props, branches) = anatomy::segments_of(shape, h);
    mopts.segments = Some(segments);
    if !branches.is_empty() {
        notes.push(format!(
            "massless and welded (they branch off a long bone between two joints of a limb: \
             twist or deformation helpers, no body part; the segment's mass stays on the \
             limb's own joints): {}",
            branches.join(", ")
        ));
        for b in branches {
            if !mopts.lock.contains(&b) {
                mopts.lock.push(b);
            }
        }
    }
    if !props.is_empty() {
        notes.push(format!(
            "massless and welded (they reach farther than half a thigh from a hand, foot or \
             head: a prop or a marker, not a body part; a massless joint would make D(q) \
             singular): {}",
            props.join(", ")
        ));
        for p in props {
            if !mopts.lock.contains(&p) {
                mopts.lock.push(p);
            }
        }
    }
}

/// A massless helper root whose only child has six channels of its own (Bandai's
/// `joint_Root` above `Hips`) duplicates the child's coordinates and makes D(q) singular: its
/// motion is folded into the child and it is welded (`motion::fold`). Returns the fold, and
/// the child when it carries the body below a helper root (for `motion::weld`).
fn fold_helper_root(
    bvh: &mut Bvh,
    positions: &[ResolvedPosition],
    model: &Model,
    map: &BvhMap,
    opts: &TakeOptions,
    mopts: &mut BvhModelOptions,
    notes: &mut Vec<String>,
) -> (Option<crate::motion::fold::Fold>, Option<usize>) {
    let mut fold = None;
    let mut pelvis = None; // below a helper root: it carries the body too (`motion::weld`)
    if let Some(c) = crate::motion::fold::redundant_root_child(bvh) {
        let root_body = map.joints[0].body;
        let root = bvh.joints[0].name.clone();
        let overridden = opts.body.link_mass.contains_key(&root);
        let massless = root_body != 0 && model.inertia[root_body].mass == 0.0;
        if massless || (root_body != 0 && overridden) {
            pelvis = Some(c);
        }
        if massless && !overridden {
            fold = Some(crate::motion::fold::Fold::record(bvh, c));
            crate::motion::fold::fold_root_into_child(bvh, positions, c);
            mopts.lock.push(root.clone());
            notes.push(format!(
                "root `{root}` is massless and `{}` has six channels of its own: its motion \
                 was folded into `{}` and it was welded (its coordinates were redundant)",
                bvh.joints[c].name, bvh.joints[c].name
            ));
        }
    }
    (fold, pelvis)
}

/// Twist helpers inside a human's long bone (no segment of their own) folded into the next
/// joint when they only turn the limb about the bone, and made massless (`motion::twist`); a
/// helper whose translation is a coordinate (`--joint-translations keep`) stays.
fn fold_twist_helpers(
    bvh: &mut Bvh,
    found: &Found,
    welded: &[crate::motion::weld::Welded],
    mopts: &BvhModelOptions,
) -> Vec<crate::motion::twist::Twist> {
    let Ok(h) = &found.landmarks else {
        return vec![];
    };
    let names: Vec<&str> = bvh.joints.iter().map(|j| j.name.as_str()).collect();
    let parent: Vec<Option<usize>> = bvh.joints.iter().map(|j| j.parent).collect();
    let topo = crate::model::skeleton::Topology {
        names: &names,
        parent: &parent,
    };
    let held = |j: usize| !bvh.joints[j].has_position() || welded.iter().any(|w| w.joint == j);
    let inside: Vec<usize> = crate::model::skeleton::inside_long_bones(&topo, h)
        .into_iter()
        .filter(|&j| held(j) && !mopts.lock.contains(&bvh.joints[j].name))
        .collect();
    crate::motion::twist::fold_twists(bvh, &found.positions, found.scale_to_m, &inside)
}

pub(crate) fn at_file(path: &Path, e: Error) -> Error {
    match e {
        Error::Invalid(m) => Error::Invalid(format!("{}: {m}", path.display())),
        other => other,
    }
}
