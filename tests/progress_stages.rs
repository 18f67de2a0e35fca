//! The long stages report progress from inside their loops and stop mid-way when asked, so a
//! user interface can show how far a job is and cancel it promptly:
//! - the smoothing once per ball or free joint and per group of up to four scalar
//!   coordinates, which it filters side by side ([`unwrap_and_smooth_with`]), through
//!   [`take_from_bvh_with`] (reading a take);
//! - the ground-reaction estimate every 64 frames of each of its two passes;
//! - a job's [`Control`] maps each stage's 0‥1 into its span of the whole job.
//!
//! Called with a callback that never stops them, they compute exactly what the plain
//! functions compute (the CLI's path), bit for bit.

use articula::error::Error;
use articula::pipeline::{self, Contact, TakeOptions};
use articula::session::Control;
use std::path::Path;

fn demo_bvh() -> articula::io::bvh::Bvh {
    articula::io::generate::walk(&articula::io::generate::WalkParams::default())
}

#[test]
fn smoothing_reports_once_per_joint_and_stops_when_told() {
    let path = Path::new("demo.bvh");
    let opts = TakeOptions::default();
    let plain = pipeline::take_from_bvh(path, demo_bvh(), &opts).unwrap();
    let mut seen = vec![];
    let with = pipeline::take_from_bvh_with(path, demo_bvh(), &opts, &mut |f| {
        seen.push(f);
        true
    })
    .unwrap();
    assert_eq!(with.states, plain.states);
    // from the start of the smoothing to the derivatives, never backwards, within 0‥1; at
    // least once per four joints (a group of scalar coordinates is smoothed side by side)
    let joints = plain.model.nbodies() - 1;
    assert!(
        seen.len() >= joints.div_ceil(4),
        "{} calls for {joints} joints",
        seen.len()
    );
    assert!(seen.windows(2).all(|w| w[0] <= w[1]), "{seen:?}");
    assert!(seen.iter().all(|f| (0.0..=1.0).contains(f)), "{seen:?}");

    // stop at the fifth report: a typed error, no take
    let mut calls = 0;
    let e = pipeline::take_from_bvh_with(path, demo_bvh(), &opts, &mut |_| {
        calls += 1;
        calls < 5
    })
    .unwrap_err();
    assert!(matches!(e, Error::Cancelled), "{e}");
    assert_eq!(calls, 5);
}

#[test]
fn ground_reactions_report_every_64_frames_of_both_passes_and_stop_when_told() {
    let opts = TakeOptions {
        contact: Contact::Feet,
        ..TakeOptions::default()
    };
    let take = pipeline::take_from_bvh(Path::new("demo.bvh"), demo_bvh(), &opts).unwrap();
    let plain = pipeline::ground_reactions(&take).unwrap().unwrap();
    let mut seen = vec![];
    let with = pipeline::ground_reactions_with(&take, &mut |f| {
        seen.push(f);
        true
    })
    .unwrap()
    .unwrap();
    assert_eq!(with.tau, plain.tau);
    assert_eq!(with.residual, plain.residual);
    let n = take.states.len();
    let per_pass = n.div_ceil(articula::dynamics::grf::PROGRESS_EVERY);
    assert_eq!(seen.len(), 2 * per_pass, "{n} frames");
    assert!(seen.windows(2).all(|w| w[0] < w[1]), "{seen:?}");
    assert!(seen[0] == 0.0 && *seen.last().unwrap() < 1.0);

    // stop in the second pass
    let mut calls = 0;
    let e = pipeline::ground_reactions_with(&take, &mut |_| {
        calls += 1;
        calls <= per_pass + 1
    })
    .unwrap_err();
    assert!(matches!(e, Error::Cancelled), "{e}");
    assert_eq!(calls, per_pass + 2);
    // with `contact none` there is nothing to estimate and nothing is reported
    let opts = TakeOptions {
        contact: articula::pipeline::Contact::None,
        ..TakeOptions::default()
    };
    let none = pipeline::take_from_bvh(Path::new("demo.bvh"), demo_bvh(), &opts).unwrap();
    let mut called = false;
    assert!(
        pipeline::ground_reactions_with(&none, &mut |_| {
            called = true;
            true
        })
        .unwrap()
        .is_none()
    );
    assert!(!called);
}

#[test]
fn a_control_maps_each_stage_into_its_span_of_the_job() {
    let ctl = Control::default();
    assert_eq!(ctl.span(), (0.0, 1.0));
    ctl.set_progress(0.5);
    assert!((ctl.progress() - 0.5).abs() < 1e-6);
    // the second of four masses: 0.25‥0.5 of the job
    ctl.set_span(0.25, 0.5);
    assert!((ctl.progress() - 0.25).abs() < 1e-6);
    ctl.set_progress(0.5);
    assert!((ctl.progress() - 0.375).abs() < 1e-6);
    // a stage callback over 0.2‥1 of the span, half way
    let mut stage = ctl.stage(0.2, 1.0);
    assert!(stage(0.5));
    assert!((ctl.progress() - (0.25 + 0.25 * 0.6)).abs() < 1e-6);
    ctl.cancel();
    assert!(!stage(0.6), "a cancelled control stops the stage");
    assert!(matches!(ctl.check(), Err(Error::Cancelled)));
}
