//! A take's states (q, v, a of every frame, the largest thing a take holds) are shared, never
//! copied, between the take and its job, and between a take and the one a mass edit makes
//! from it; an edit that changes the motion makes new ones.

use articula::io::bvh::read;
use articula::motion::smooth::SmoothSpec;
use articula::pipeline::{self, ModelSource, TakeOptions};
use std::path::Path;
use std::sync::Arc;

const DEMO: &str = "data/demo_walk.bvh";

#[test]
fn the_job_holds_its_take_s_states() {
    let job = pipeline::load_source(
        &ModelSource::Take(DEMO.into()),
        None,
        &TakeOptions::default(),
    )
    .unwrap();
    let take = job.take.as_ref().unwrap();
    assert!(Arc::ptr_eq(&job.states, &take.states));
    assert!(!job.states.is_empty());
}

#[test]
fn a_mass_edit_keeps_the_states_a_smoothing_edit_makes_new_ones() {
    let path = Path::new(DEMO);
    let load = |opts: &TakeOptions, previous: Option<&pipeline::Take>| {
        pipeline::take_from_bvh_reusing(
            path,
            read(path).unwrap(),
            opts,
            previous,
            &mut |_| true,
            &mut |_| {},
        )
        .unwrap()
    };
    let opts = TakeOptions::default();
    let first = load(&opts, None);
    let mut heavier = opts.clone();
    heavier.body.mass_kg = 91.0;
    let edited = load(&heavier, Some(&first));
    assert!(
        Arc::ptr_eq(&first.states, &edited.states),
        "a mass edit copied or remade the states"
    );
    assert_ne!(first.model.inertia, edited.model.inertia);

    let mut smoother = opts.clone();
    smoother.smooth = Some(SmoothSpec::Gaussian { sigma_s: 0.02 });
    let resmoothed = load(&smoother, Some(&first));
    assert!(!Arc::ptr_eq(&first.states, &resmoothed.states));
    assert_ne!(first.states.q, resmoothed.states.q);
}
