//! The anatomical series read the net moments of an RNEA that already runs, and keep what a
//! mass does not change, with the same bits:
//! - the moments inverse dynamics keeps without contact, and those the ground-reaction
//!   estimate keeps, are bit for bit those of a separate RNEA after its own forward kinematics
//!   with the same loads taken from it (`GroundReactions::take_from`, the one way loads are
//!   applied); and within rounding those of RNEA with the loads as external forces (inverse
//!   dynamics is linear in them);
//! - a calibration (segment frames, kept poses: `pipeline::anatomy::Calibration`) made at one
//!   body mass fits the take at another and gives, with that take's moments, the series a
//!   fresh `anatomy_with` gives; it does not fit a take whose motion differs.

mod common;

use articula::dynamics::grf::GroundReactions;
use articula::dynamics::rra::Warm;
use articula::dynamics::{Workspace, forward_kinematics, rnea};
use articula::motion::smooth::SmoothSpec;
use articula::pipeline::anatomy::{
    Calibration, anatomy_with, inverse_dynamics_and_moments, moment_bodies,
};
use articula::pipeline::{self, Contact, Take, TakeOptions, consistency};
use articula::spatial::ForceVec;
use nalgebra::Vector3;

fn demo(contact: Contact, mass_kg: f64) -> Take {
    let mut o = TakeOptions {
        contact,
        ..TakeOptions::default()
    };
    o.body.mass_kg = mass_kg;
    pipeline::load_take(&common::repo("data/demo_walk.bvh"), &o).unwrap()
}

/// The oracle: per frame, the full forward kinematics, RNEA, `f.ang` of `bodies`, and the
/// ground's loads taken from them.
fn separate_rnea(t: &Take, g: Option<&GroundReactions>, bodies: &[usize]) -> Vec<Vector3<f64>> {
    let m = &t.model;
    let s = &t.states;
    let mut ws = Workspace::new(m);
    let mut out = vec![];
    for k in 0..s.len() {
        forward_kinematics(m, &mut ws, &s.q[k]);
        rnea(m, &mut ws, &s.q[k], &s.v[k], &s.a[k], None);
        let mut row: Vec<Vector3<f64>> = bodies.iter().map(|&b| ws.f[b].ang).collect();
        if let Some(g) = g {
            g.take_from(m, k, &ws, None, (bodies, &mut row));
        }
        out.extend(row);
    }
    out
}

/// The physics: RNEA with the ground's loads as external forces on the feet's bodies.
fn rnea_with_loads(t: &Take, g: &GroundReactions, bodies: &[usize]) -> Vec<Vector3<f64>> {
    let m = &t.model;
    let s = &t.states;
    let mut ws = Workspace::new(m);
    let mut f_ext = vec![ForceVec::ZERO; m.nbodies()];
    let mut out = vec![];
    for k in 0..s.len() {
        forward_kinematics(m, &mut ws, &s.q[k]);
        g.external_forces(k, &ws.o_x_i, &mut f_ext);
        rnea(m, &mut ws, &s.q[k], &s.v[k], &s.a[k], Some(&f_ext));
        out.extend(bodies.iter().map(|&b| ws.f[b].ang));
    }
    out
}

fn bits(v: &[Vector3<f64>]) -> Vec<u64> {
    v.iter()
        .flat_map(|x| x.iter().map(|c| c.to_bits()))
        .collect()
}

fn anatomy_bits(a: &pipeline::anatomy::Anatomy) -> Vec<u64> {
    a.columns.iter().flatten().map(|x| x.to_bits()).collect()
}

#[test]
fn the_moments_inverse_dynamics_keeps_without_contact_are_a_separate_rnea_bit_for_bit() {
    let t = demo(Contact::None, 75.0);
    let bodies = moment_bodies(&t);
    assert!(bodies.len() > 10, "{bodies:?}");
    let (tau, moments) =
        inverse_dynamics_and_moments(&t.model, &t.states, &bodies, &mut |_| true).unwrap();
    let plain = pipeline::inverse_dynamics_with(&t.model, &t.states, &mut |_| true).tau;
    assert_eq!(tau, plain, "the torques are inverse dynamics' own");
    assert_eq!(bits(&moments), bits(&separate_rnea(&t, None, &bodies)));
}

#[test]
fn the_moments_the_estimate_keeps_are_a_separate_rnea_with_its_loads_bit_for_bit() {
    let t = demo(Contact::Feet, 75.0);
    let bodies = moment_bodies(&t);
    let (adjusted, g, _, _) =
        consistency::consistent_take_keeping(&t, false, None, &bodies, Warm::Cold, None).unwrap();
    assert!(adjusted.is_none());
    assert_eq!(g.moment_bodies, bodies);
    assert_eq!(
        bits(&g.moments),
        bits(&separate_rnea(&t, Some(&g), &bodies))
    );
    let physics = rnea_with_loads(&t, &g, &bodies);
    let peak = physics.iter().map(|x| x.norm()).fold(0.0, f64::max);
    let off = g
        .moments
        .iter()
        .zip(&physics)
        .map(|(a, b)| (a - b).norm())
        .fold(0.0, f64::max);
    assert!(peak > 10.0 && off < 1e-12 * peak, "{off} N·m of {peak}");
    // without bodies asked, the estimate is the one it was
    let (_, plain, _) = consistency::consistent_take(&t, false, None).unwrap();
    assert!(plain.moments.is_empty() && plain.moment_bodies.is_empty());
    assert_eq!(plain.tau, g.tau);
    assert_eq!(plain.residual, g.residual);
    // residual reduction changes the motion: nothing is kept of the take as loaded
    let (adjusted, reduced, _, _) =
        consistency::consistent_take_keeping(&t, true, None, &bodies, Warm::Cold, None).unwrap();
    assert!(adjusted.is_some() && reduced.moments.is_empty());
    // the series from the kept moments equal the series' own RNEA
    let cal = Calibration::new(&t).unwrap();
    let from_kept = cal
        .series(&t, &cal.net_moments(&t, Some(&g)), Some(&g))
        .unwrap();
    assert_eq!(
        anatomy_bits(&from_kept),
        anatomy_bits(&anatomy_with(&t, Some(&plain)).unwrap())
    );
}

#[test]
fn a_calibration_made_at_one_mass_gives_another_mass_its_fresh_series() {
    for contact in [Contact::None, Contact::Feet] {
        let light = demo(contact, 60.0);
        let heavy = demo(contact, 95.0);
        assert_ne!(light.model.total_mass(), heavy.model.total_mass());
        let cal = Calibration::new(&light).unwrap();
        assert!(cal.fits(&heavy), "masses are not part of the calibration");
        let g = pipeline::ground_reactions(&heavy).unwrap();
        let reused = cal
            .series(&heavy, &cal.net_moments(&heavy, g.as_ref()), g.as_ref())
            .unwrap();
        let fresh = anatomy_with(&heavy, g.as_ref()).unwrap();
        assert_eq!(reused.names, fresh.names);
        assert_eq!(anatomy_bits(&reused), anatomy_bits(&fresh), "{contact:?}");
        assert_eq!(reused.mass_kg, fresh.mass_kg);
    }
    // another smoothing is another motion: the calibration does not fit it
    let t = demo(Contact::None, 75.0);
    let mut o = TakeOptions {
        contact: Contact::None,
        smooth: Some(SmoothSpec::None),
        ..TakeOptions::default()
    };
    o.body.mass_kg = 75.0;
    let raw = pipeline::load_take(&common::repo("data/demo_walk.bvh"), &o).unwrap();
    assert!(!Calibration::new(&t).unwrap().fits(&raw));
}
