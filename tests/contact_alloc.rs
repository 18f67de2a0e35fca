//! The ground-reaction estimate (the `contact` stage of `articula id`: its kinematics and RNEA
//! pass, the contact phases, the feet's loads, RNEA with them) allocates per frame only its
//! output rows: `contact`, `loaded`, `grf`, `cop`, `free_moment` and `tau` of
//! [`GroundReactions`](articula::dynamics::grf::GroundReactions), six per frame; each worker's
//! `Workspace` and external forces are made once per call, the kept poses in one block.
//! Checked as `tests/pipeline_alloc.rs` checks the other stages: the allocations of a take
//! and of the same take there and back (twice the frames), serial and with two workers. One
//! test in its own binary, since the count is global.

mod common;

use articula::pipeline::{self, States, TakeOptions};
use common::alloc::allocations;
use std::path::PathBuf;

#[global_allocator]
static GLOBAL: common::alloc::Counting = common::alloc::Counting;

/// The take and then its frames backward (the motion stays continuous, so the feet touch the
/// floor as often again), every `dt` seconds.
fn there_and_back(s: &States, dt: f64) -> States {
    let back = |x: &Vec<Vec<f64>>| x.iter().chain(x.iter().rev()).cloned().collect::<Vec<_>>();
    States {
        time: (0..2 * s.len()).map(|k| k as f64 * dt).collect(),
        q: back(&s.q),
        v: back(&s.v),
        a: back(&s.a),
    }
}

#[test]
fn the_ground_reaction_estimate_allocates_only_its_output_rows() {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/demo_walk.bvh");
    let opts = TakeOptions {
        contact: pipeline::Contact::Feet,
        ..TakeOptions::default()
    };
    let take = pipeline::load_take(&path, &opts).unwrap();
    let n = take.states.len();
    let mut long = take.clone();
    long.states = std::sync::Arc::new(there_and_back(&take.states, take.bvh.frame_time));
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        // besides the rows: a few lists per contact phase, step and flight of the take (the
        // phases, the transitions, the frames a spread force reaches), which the take there
        // and back has twice of: seen 25 for the demo's 480 frames, far below one per frame;
        // and with two workers rayon's queue blocks (`tests/pipeline_alloc.rs`)
        let slack = n / 8 + if threads == 1 { 0 } else { n / 16 };
        pool.install(|| {
            let count = |t: &pipeline::Take| {
                allocations(|| drop(pipeline::estimate_take_ground_reactions(t).unwrap()))
            };
            let (a, b) = (count(&take), count(&long));
            let extra = b.abs_diff(a);
            assert!(
                extra.abs_diff(6 * n) <= slack,
                "{threads} threads: {extra} more allocations for {n} more frames, expected {}",
                6 * n
            );
        });
    }
}
