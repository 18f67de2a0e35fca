//! The built-in engine over the library's stage functions ([`Builtin`]).

use super::analysis::{anatomy_table, contact_brief, table, vertical_forces};
use super::{
    Analysis, Control, Engine, LeftOut, Params, Robot, Table, Take, TakeData, no_motion,
    pipeline_take, summarize_notes,
};
use crate::dynamics::rra::Warm;
use crate::error::Error;
use crate::io::bvh::detect_up;
use crate::model::Model;
use crate::motion::blend::{Align, BlendOptions, TimeMap, WarpWindow};
use crate::pipeline::stages::Stage;
use crate::pipeline::{self, States};
use std::path::Path;
use std::sync::Arc;

/// The engine over the library's stage functions.
#[derive(Debug, Clone, Copy, Default)]
pub struct Builtin;

/// The built-in demo take (`demo:walk`).
pub const DEMO_WALK: &str = "demo:walk";

fn cancelled() -> Error {
    Error::Cancelled
}

impl Engine for Builtin {
    fn load(&self, path: &Path, params: &Params) -> Result<Take, Error> {
        let source = path.to_string_lossy().into_owned();
        let name = path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| source.clone())
            .replace("demo:", "");
        let ext = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        let robot = |model: Model, kind| {
            TakeData::Robot(Robot {
                model: Arc::new(model),
                kind,
                motion: None,
                motion_source: String::new(),
            })
        };
        let mut notes = vec![];
        let data = if source == DEMO_WALK {
            TakeData::Bvh(Arc::new(crate::io::generate::walk(
                &crate::io::generate::WalkParams::default(),
            )))
        } else if ext == "toml" {
            let table = crate::io::dh::read(path)?;
            robot(crate::model::dh::build_dh_model(&table)?, "DH table")
        } else if ext == "urdf" {
            let opts = crate::model::urdf::UrdfOptions::default();
            robot(crate::model::urdf::read_urdf(path, &opts)?, "URDF")
        } else {
            // as `pipeline::load_take`: a rest pose stored as frame 0 is dropped unless kept
            let (bvh, trimmed) = pipeline::read_take(path, params.take.keep_first_frame)?;
            // a take the pipeline cannot turn into a model and states under these settings
            // fails here, and the workbench keeps the take it had (it became the active take
            // and every later command repeated its error)
            let t = pipeline::take_from_bvh(path, bvh.clone(), &params.take)?;
            notes.extend(trimmed);
            notes.extend(t.notes);
            TakeData::Bvh(Arc::new(bvh))
        };
        Ok(Take {
            name,
            source,
            data,
            notes,
        })
    }

    fn load_motion(&self, model: &Model, path: &Path) -> Result<States, Error> {
        let s = pipeline::read_states(model, path)?;
        if s.len() < 2 {
            return Err(Error::Invalid(format!(
                "{}: {} sample(s); a motion needs two or more",
                path.display(),
                s.len()
            )));
        }
        Ok(s)
    }

    fn inverse_dynamics(
        &self,
        take: &Take,
        params: &Params,
        ctl: &Control,
    ) -> Result<Analysis, Error> {
        self.inverse_dynamics_after(take, params, None, ctl)
    }

    fn inverse_dynamics_after(
        &self,
        take: &Take,
        params: &Params,
        previous: Option<&Analysis>,
        ctl: &Control,
    ) -> Result<Analysis, Error> {
        inverse_dynamics_as(take, params, previous, false, ctl)
    }

    fn preview_after(
        &self,
        take: &Take,
        params: &Params,
        previous: Option<&Analysis>,
        ctl: &Control,
    ) -> Option<Analysis> {
        let p = previous?;
        let source = p.source.as_deref()?;
        // an edit of the masses alone, whose residual reduction would start cold
        let masses_alone = |o: &pipeline::TakeOptions| pipeline::TakeOptions {
            body: Default::default(),
            keep_first_frame: false,
            ..o.clone()
        };
        // (the stature is the skeleton's, set when the model is built)
        let body = |o: &pipeline::TakeOptions| crate::model::anthropometry::BodyParams {
            height_m: None,
            ..o.body.clone()
        };
        let fits = p.reduction.is_some()
            && params.consistent.unwrap_or(true)
            && matches!(take.data, TakeData::Bvh(_))
            && masses_alone(&source.options) == masses_alone(&params.take)
            && body(&source.options) != body(&params.take);
        // no preview is no error: the results proper follow and say what went wrong
        fits.then(|| inverse_dynamics_as(take, params, previous, true, ctl).ok())
            .flatten()
    }

    fn simulate(&self, take: &Take, params: &Params, ctl: &Control) -> Result<Analysis, Error> {
        // computed-torque tracking of the take's (smoothed) motion, or of a robot's motion
        ctl.check()?;
        let (model, states, scale) = match &take.data {
            TakeData::Bvh(bvh) => {
                let t = pipeline::take_from_bvh_with(
                    Path::new(&take.source),
                    (**bvh).clone(),
                    &params.take,
                    &mut ctl.stage(0.0, 0.05),
                )?;
                (Arc::new(t.model), t.states, t.scale_to_m)
            }
            TakeData::Robot(r) => {
                let m = r.motion.clone().ok_or_else(|| no_motion(take))?;
                (r.model.clone(), m, 1.0)
            }
        };
        ctl.set_progress(0.05);
        ctl.check()?;
        let settings = pipeline::SimSettings::parse(
            &params.integrator,
            params.dt,
            &params.kp,
            &params.kv,
            0.0,
            None,
        )?;
        let r = pipeline::simulate_states(&model, &states, &settings, &mut ctl.stage(0.05, 1.0))?
            .result;
        ctl.set_progress(1.0);
        // the configurations it tracked
        let reference = table(&model.q_names, &states.q);
        // accelerations are not recorded: differentiate the simulated velocities
        let dt = r.time.get(1).map_or(params.dt, |t1| t1 - r.time[0]);
        let mut a = Table::zeros(model.v_names.clone(), r.time.len());
        let mut da = vec![0.0; r.time.len()];
        let mut vj = vec![0.0; r.time.len()];
        for j in 0..model.nv {
            for (x, row) in vj.iter_mut().zip(&r.v) {
                *x = row[j];
            }
            crate::motion::derive::differentiate(&vj, dt, &mut da);
            for (k, x) in da.iter().enumerate() {
                a.row_mut(k)[j] = *x;
            }
        }
        Ok(Analysis {
            q: Arc::new(table(&model.q_names, &r.q)),
            v: Arc::new(table(&model.v_names, &r.v)),
            a: Arc::new(a),
            tau: table(&model.v_names, &r.tau),
            time: r.time.clone(),
            scale,
            note: format!(
                "tracking error RMS {}, max {}",
                crate::session::units::format_value(
                    crate::session::units::Kind::Angle,
                    r.rms_error_rad()
                ),
                crate::session::units::format_value(
                    crate::session::units::Kind::Angle,
                    r.max_error_rad()
                )
            ),
            brief: String::new(),
            model,
            anatomy: Table::zeros(vec![], 0),
            left_out: vec![],
            anatomy_joints: vec![],
            feet: Table::zeros(vec![], 0),
            source: None,
            calibration: None,
            contact_auto: None,
            contact_fit: None,
            reduction: None,
            consistency: None,
            states: None,
            reference,
        })
    }

    fn blend(&self, a: &Take, b: &Take, window: (f64, f64)) -> Result<Take, Error> {
        let (Some(ba), Some(bb)) = (a.bvh(), b.bvh()) else {
            return Err(Error::Invalid(format!(
                "blend {} {}: only BVH takes blend (a robot's motion is a trajectory)",
                a.name, b.name
            )));
        };
        // motion::blend: C² ramp, shortest-arc slerp per joint, b's root and heading aligned
        // to a's at the window start
        let opts = BlendOptions {
            align: Align::ALL,
            up_axis: detect_up(ba).index(),
            ..BlendOptions::default()
        };
        let w = WarpWindow {
            t0: window.0,
            t1: window.1,
        };
        let bvh = crate::motion::blend::blend(ba, bb, w, TimeMap::IDENTITY, &opts)?;
        Ok(Take {
            name: format!("{}+{}", a.name, b.name),
            source: format!("blend {} {} {}:{}", a.name, b.name, window.0, window.1),
            data: TakeData::Bvh(Arc::new(bvh)),
            notes: vec![],
        })
    }

    fn export_bvh(
        &self,
        take: &Take,
        params: &Params,
        motion: Option<&Analysis>,
        path: &Path,
        ctl: &Control,
    ) -> Result<(), Error> {
        // the pipeline's take under the current options: its q are what the user sees
        let mut t = pipeline_take(take, params, "export bvh", &mut ctl.stage(0.0, 0.9))?;
        if let Some(m) = motion {
            if m.q.rows() != t.states.len() || m.q.names != t.model.q_names {
                return Err(Error::Invalid(format!(
                    "export bvh sim: the simulation has {} rows of {} coordinates, the take {} \
                     frames of {}; run sim again",
                    m.q.rows(),
                    m.q.cols(),
                    t.states.len(),
                    t.model.nq
                )));
            }
            for (k, row) in Arc::make_mut(&mut t.states).q.iter_mut().enumerate() {
                row.copy_from_slice(m.q.row(k));
            }
        }
        ctl.check()?;
        pipeline::export_smoothed_bvh_as(&t, path, params.bvh_style)
    }
}

/// [`Engine::inverse_dynamics_after`], or with `preview` its preview
/// ([`Engine::preview_after`]: the residual reduction of `previous` evaluated on this take's
/// masses, `dynamics::rra::Warm::Preview`; an error when it has none to give).
fn inverse_dynamics_as(
    take: &Take,
    params: &Params,
    previous: Option<&Analysis>,
    preview: bool,
    ctl: &Control,
) -> Result<Analysis, Error> {
    ctl.check()?;
    let (model, states, scale, tau, extras) = match &take.data {
        TakeData::Bvh(bvh) => {
            let (t, mut extras) = bvh_inverse_dynamics(take, bvh, params, previous, preview, ctl)?;
            let tau = extras.torques.take();
            (Arc::new(t.model), t.states, t.scale_to_m, tau, extras)
        }
        TakeData::Robot(r) => {
            let m = r.motion.clone().ok_or_else(|| no_motion(take))?;
            (r.model.clone(), m, 1.0, None, Extras::default())
        }
    };
    // inverse dynamics (RNEA) frame by frame, with progress and cancel
    let tau = match tau {
        Some(tau) => tau,
        None => {
            let t = pipeline::inverse_dynamics_with(&model, &states, &mut ctl.stage(0.2, 1.0));
            if t.tau.len() < states.len() {
                return Err(cancelled());
            }
            ctl.done(Stage::InverseDynamics);
            t.tau
        }
    };
    ctl.set_progress(1.0);
    check_finite(&model, &tau, params)?;
    // the state tables of the last results when they are of the same states, else made
    let same = previous.filter(|p| {
        p.states.as_ref().is_some_and(|s| Arc::ptr_eq(s, &states))
            && p.q.names == model.q_names
            && p.v.names == model.v_names
    });
    let (q, v, a) = match same {
        Some(p) => (p.q.clone(), p.v.clone(), p.a.clone()),
        None => (
            Arc::new(table(&model.q_names, &states.q)),
            Arc::new(table(&model.v_names, &states.v)),
            Arc::new(table(&model.v_names, &states.a)),
        ),
    };
    Ok(Analysis {
        q,
        v,
        a,
        tau: table(&model.v_names, &tau),
        time: states.time.clone(),
        scale,
        note: extras.note,
        brief: extras.brief,
        model,
        anatomy: extras.anatomy,
        left_out: extras.left_out,
        anatomy_joints: extras.anatomy_joints,
        feet: extras.feet,
        source: extras.source,
        calibration: extras.calibration,
        contact_auto: extras.contact_auto,
        contact_fit: extras.contact_fit,
        reduction: extras.reduction,
        consistency: extras.consistency,
        reference: Table::default(),
        states: Some(states),
    })
}

/// What a BVH take's inverse dynamics gives besides its model and states (the fields of
/// [`Analysis`] of the same names), and the torques when the contact's or the anatomy's RNEA
/// already computed them.
#[derive(Default)]
struct Extras {
    torques: Option<Vec<Vec<f64>>>,
    note: String,
    brief: String,
    anatomy: Table,
    left_out: Vec<Option<LeftOut>>,
    anatomy_joints: Vec<(String, String)>,
    feet: Table,
    source: Option<Arc<pipeline::Take>>,
    calibration: Option<Arc<pipeline::anatomy::Calibration>>,
    contact_auto: Option<(pipeline::Contact, String)>,
    contact_fit: Option<Arc<pipeline::ContactFit>>,
    reduction: Option<Arc<crate::dynamics::rra::Seed>>,
    consistency: Option<Arc<pipeline::consistency::Consistency>>,
}

/// A BVH take through the pipeline's stages: axes and unit, model, q, unwrap, smooth,
/// differentiate (the states of `previous` when the edit keeps them; progress 0–0.2), the
/// contact and residual reduction ([`contact`]; with `preview`, `previous`'s reduction
/// evaluated), then the anatomical series and, when they
/// come from the same RNEA, the torques ([`anatomy_and_torques`]). Returns the take the
/// torques are of and the rest of the results.
fn bvh_inverse_dynamics(
    take: &Take,
    bvh: &Arc<crate::io::bvh::Bvh>,
    params: &Params,
    previous: Option<&Analysis>,
    preview: bool,
    ctl: &Control,
) -> Result<(pipeline::Take, Extras), Error> {
    let mut t = pipeline::take_from_bvh_reusing(
        Path::new(&take.source),
        (**bvh).clone(),
        &params.take,
        previous.and_then(|p| p.source.as_deref()),
        &mut ctl.stage(0.0, 0.2),
        &mut |s| ctl.done(s),
    )?;
    ctl.set_progress(0.2);
    ctl.check()?;
    let mut x = Extras {
        source: Some(Arc::new(t.clone())),
        ..Extras::default()
    };
    // `contact auto` as the last results settled it when only masses changed
    let settled = previous.and_then(|p| Some((p.source.as_deref()?, p.contact_auto.as_ref()?)));
    x.contact_fit = contact_fit(&t, previous);
    x.contact_auto = pipeline::resolve_contact_after(&mut t, settled, x.contact_fit.as_deref());
    x.left_out = edge_marks(&t, params);
    x.note = summarize_notes(&t.notes);
    let (t, g) = contact(t, params, previous, preview, &mut x, ctl)?;
    ctl.check()?;
    let tau = anatomy_and_torques(&t, g.as_ref(), previous, &mut x, ctl)?;
    ctl.check()?;
    x.torques = g.map(|g| g.tau).or(tau);
    Ok((t, x))
}

/// The frames within the smoothing's reach of the ends, marked [`LeftOut::Edge`], unless
/// `edges include`.
fn edge_marks(t: &pipeline::Take, params: &Params) -> Vec<Option<LeftOut>> {
    let mut left_out = vec![None; t.states.len()];
    if !params.include_edges {
        let e = pipeline::edge_frames(t);
        let n = left_out.len();
        for k in (0..e.min(n)).chain(n.saturating_sub(e)..n) {
            left_out[k] = Some(LeftOut::Edge);
        }
    }
    left_out
}

/// With `contact feet`: the estimated ground reactions (and how far the feet could give the
/// ground force the motion needs) of the take made consistent unless `consistent off`
/// (residual reduction, started from what `previous` found when it fits:
/// [`crate::dynamics::rra::Seed`]; with `preview`, what it found evaluated on this take's
/// masses, [`crate::dynamics::rra::Warm::Preview`], and kept as the seed); the frames beyond the feet marked [`LeftOut::Beyond`], the verdicts
/// in the note and brief. The estimate keeps the net moments of the bodies the anatomical
/// series read. Without contact, the take as it is.
fn contact(
    t: pipeline::Take,
    params: &Params,
    previous: Option<&Analysis>,
    preview: bool,
    x: &mut Extras,
    ctl: &Control,
) -> Result<
    (
        pipeline::Take,
        Option<crate::dynamics::grf::GroundReactions>,
    ),
    Error,
> {
    if t.options.contact != pipeline::Contact::Feet {
        return Ok((t, None));
    }
    let bodies = match &t.human {
        Ok(_) => pipeline::anatomy::moment_bodies(&t),
        Err(_) => vec![],
    };
    let reduce = params.consistent.unwrap_or(true);
    // residual reduction from what the last results' found, when they are of the same take
    // (the seed itself checks that nothing but the masses changed)
    let seed = previous.and_then(|p| p.reduction.as_ref());
    let warm = match (preview, seed) {
        (true, Some(s)) => Warm::Preview(s),
        (true, None) => return Err(Error::Invalid("no residual reduction to preview".into())),
        (false, s) => s.map(|s| &**s).into(),
    };
    let fit = x.contact_fit.clone();
    let (adjusted, g, c, found) = pipeline::consistency::consistent_take_keeping(
        &t,
        reduce,
        None,
        &bodies,
        warm,
        fit.as_deref(),
    )?;
    // a preview's adjustments are the seed's, not this model's: the next edit starts from it
    x.reduction = if preview {
        seed.cloned()
    } else {
        found.map(Arc::new)
    };
    for (k, b) in c.beyond.iter().enumerate() {
        if *b && k < x.left_out.len() {
            x.left_out[k] = Some(LeftOut::Beyond);
        }
    }
    x.brief = contact_brief(&g.quality(), c.last().meets());
    ctl.done(Stage::Contact);
    x.feet = vertical_forces(&g);
    let mut said = format!("{}; {}", g.quality(), c.headline());
    if let Some(lost) = &c.floor_lost_note {
        said = format!("{said}; {lost}");
    }
    x.note = if x.note.is_empty() {
        said
    } else {
        format!("{}; {said}", x.note)
    };
    x.consistency = Some(Arc::new(c));
    ctl.set_progress(0.9);
    Ok((adjusted.unwrap_or(t), Some(g)))
}

/// The contact thresholds fitted to `t`'s feet (`pipeline::ContactFit`): `previous`'s when
/// its take has the same motion (`pipeline::same_motion`: a mass edit; the fit reads no mass),
/// else fitted now; `None` without contact, or when the fit fails (the contact's own steps then
/// say why).
fn contact_fit(
    t: &pipeline::Take,
    previous: Option<&Analysis>,
) -> Option<Arc<pipeline::ContactFit>> {
    if t.options.contact == pipeline::Contact::None || t.held_contact.is_some() {
        return None;
    }
    previous
        .and_then(|p| Some((p.source.as_deref()?, p.contact_fit.as_ref()?)))
        .filter(|(source, _)| pipeline::same_motion(source, t))
        .map(|(_, fit)| fit.clone())
        .or_else(|| pipeline::ContactFit::new(t).ok().map(Arc::new))
}

/// The anatomical series of a human take: the calibration of `previous` when this take's
/// kinematics are theirs (a mass edit), else a new one; the moments from the estimate's RNEA
/// with contact, or without contact from one RNEA per frame that gives the torques too
/// (returned then; `None` otherwise).
fn anatomy_and_torques(
    t: &pipeline::Take,
    g: Option<&crate::dynamics::grf::GroundReactions>,
    previous: Option<&Analysis>,
    x: &mut Extras,
    ctl: &Control,
) -> Result<Option<Vec<Vec<f64>>>, Error> {
    if t.human.is_err() {
        return Ok(None);
    }
    x.calibration = previous
        .and_then(|p| p.calibration.clone())
        .filter(|c| c.fits(t))
        .or_else(|| pipeline::anatomy::Calibration::new(t).ok().map(Arc::new));
    let Some(cal) = x.calibration.as_deref() else {
        return Ok(None);
    };
    let tau = match g {
        Some(g) => {
            let moments = cal.net_moments(t, Some(g));
            x.anatomy = anatomy_table(cal.series(t, &moments, Some(g)));
            None
        }
        None => {
            let (tau, moments) = pipeline::anatomy::inverse_dynamics_and_moments(
                &t.model,
                &t.states,
                cal.bodies(),
                &mut ctl.stage(0.2, 1.0),
            )
            .ok_or_else(cancelled)?;
            ctl.done(Stage::InverseDynamics);
            x.anatomy = anatomy_table(cal.series(t, &moments, None));
            Some(tau)
        }
    };
    if !x.anatomy.names.is_empty()
        && let Ok(h) = &t.human
    {
        x.anatomy_joints = pipeline::anatomy::anatomical_joints(h, &t.bvh);
    }
    Ok(tau)
}

/// A non-finite torque (an absurd mass, a singular pose) is an error, so that no view,
/// expect or file ever shows one.
fn check_finite(model: &Model, tau: &[Vec<f64>], params: &Params) -> Result<(), Error> {
    for (k, row) in tau.iter().enumerate() {
        if let Some(j) = row.iter().position(|x| !x.is_finite()) {
            return Err(Error::Numerical(format!(
                "inverse dynamics: the torque on `{}` is not finite at frame {k} ({:.4e} kg \
                 body): check body.mass and the link masses",
                model.v_names[j], params.take.body.mass_kg
            )));
        }
    }
    Ok(())
}
