//! The pipeline's per-frame loops allocate nothing but their outputs: reading the BVH text
//! (per file, whatever the take's length), the Euler re-pick, unwrapping and smoothing
//! (per joint), derivatives (one v and one a row per frame), the whole way from a take's
//! frames to its states (one q, v and a row per frame) and
//! inverse dynamics (one torque row per frame; each worker's `Workspace` made once, not per
//! frame or per block). Checked by counting the allocations of a take and of the same take
//! twice as long, serial and with two worker threads: the difference is the output rows
//! exactly on the serial path; with two threads, rayon's own job queues may add a block now and
//! then (crossbeam's injector allocates one per 63 jobs), in either run, far fewer than one per
//! frame. Tests in their own binary, one at a time (`ONE_AT_A_TIME`), since the count is
//! global (worker threads allocate on their own threads).

mod common;

use articula::io::bvh::{self, Bvh};
use articula::motion::smooth::SmoothSpec;
use articula::pipeline::{self, States, TakeOptions};
use common::alloc::allocations;
use std::path::PathBuf;

#[global_allocator]
static GLOBAL: common::alloc::Counting = common::alloc::Counting;

/// Held by each test for its whole run: the count is global, the test harness runs tests on
/// several threads.
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// The states twice as long: the frames, then the same frames again.
fn doubled(s: &States) -> States {
    let twice = |x: &Vec<Vec<f64>>| x.iter().chain(x).cloned().collect::<Vec<_>>();
    States {
        time: (0..2 * s.len()).map(|k| k as f64).collect(),
        q: twice(&s.q),
        v: twice(&s.v),
        a: twice(&s.a),
    }
}

/// `bvh` with its frames twice over.
fn doubled_bvh(bvh: &Bvh) -> Bvh {
    let mut long = bvh.clone();
    long.motion.extend_from_slice(&bvh.motion);
    long.decimals.extend_from_slice(&bvh.decimals);
    long.frames *= 2;
    long
}

/// Reading a take allocates per joint and per file, never per frame line or per value: the
/// text of a take and of the same take twice as long cost the same number of allocations,
/// serial and with two threads (the frame lines then read in chunks, one set of buffers per
/// chunk). The text is written large enough (the demo cycled to over 256 KiB) for the chunks
/// to be read in parallel.
#[test]
fn reading_a_take_allocates_nothing_per_frame() {
    let _alone = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/demo_walk.bvh");
    let mut bvh = bvh::read(&path).unwrap();
    while bvh::write_string(&bvh).len() < 1 << 18 {
        bvh = doubled_bvh(&bvh);
    }
    let short = bvh::write_string(&bvh);
    let long = bvh::write_string(&doubled_bvh(&bvh));
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let count = |text: &str| {
                allocations(|| {
                    let mut read = bvh::parse_str(text, &path).unwrap();
                    let _ = articula::motion::trim::trim_rest_first_frame(&mut read);
                })
            };
            let (a, b) = (count(&short), count(&long));
            // with two threads, rayon's job queues and its waking workers allocate now and then
            // (seen: 6 under a load of 10 on 2 cores); a frame line or a value apiece would be
            // hundreds or tens of thousands
            let slack = if threads == 1 { 0 } else { 16 };
            assert!(
                a.abs_diff(b) <= slack,
                "{threads} threads: {a} allocations to read {} frames, {b} for twice as many",
                bvh.frames
            );
        });
    }
}

#[test]
fn per_frame_loops_allocate_only_their_outputs_serial_and_in_parallel() {
    let _alone = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("data/demo_walk.bvh");
    for joints in ["euler", "ball"] {
        let opts = TakeOptions {
            joints: joints.parse().unwrap(),
            ..TakeOptions::default()
        };
        let take = pipeline::load_take(&path, &opts).unwrap();
        let (model, dt) = (&take.model, take.bvh.frame_time);
        let short = take.states.clone();
        let long = doubled(&short);
        let n = short.len();
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            // rayon's queue blocks, with more than one worker (see the module doc); and a few
            // one-off allocations of the pool's sleeping workers, which a loaded machine
            // wakes at other moments (seen: 2, once, under a load of 11 on 2 cores) — far
            // below one per frame
            let slack = 4 + if threads == 1 { 0 } else { n / 16 };
            let within = |extra: usize, expected: usize, what: &str| {
                assert!(
                    extra.abs_diff(expected) <= slack,
                    "{joints}, {threads} threads, {what}: {extra} more allocations for {n} more \
                     frames, expected {expected}"
                );
            };
            pool.install(|| {
                // the Euler re-pick and scan: per joint, nothing per frame
                let count = |s: &States| {
                    let mut q = s.q.clone();
                    allocations(|| {
                        drop(pipeline::make_euler_triples_continuous(
                            &take.bvh, &take.map, &mut q,
                        ));
                    })
                };
                let (a, b) = (count(&short), count(&long));
                within(b.abs_diff(a), 0, "Euler re-pick");

                // unwrapping and smoothing: per joint, nothing per frame
                let smooth = SmoothSpec::Butterworth {
                    cutoff_hz: 6.0,
                    order: 2,
                };
                let count = |s: &States| {
                    let mut q = s.q.clone();
                    allocations(|| {
                        pipeline::unwrap_and_smooth(model, &mut q, dt, &smooth).unwrap();
                    })
                };
                let (a, b) = (count(&short), count(&long));
                within(b.abs_diff(a), 0, "unwrap and smooth");

                // derivatives: a v row and an a row per frame
                let count =
                    |s: &States| allocations(|| drop(pipeline::derivatives(model, &s.q, dt)));
                let (a, b) = (count(&short), count(&long));
                within(b.abs_diff(a), 2 * n, "derivatives");

                // the take's states from its frames (channels → q, re-pick, unwrap, smoothing,
                // derivatives): a q, a v and an a row per frame
                let count = |bvh: &Bvh| {
                    allocations(|| {
                        drop(pipeline::take_states(bvh, model, &take.map, &smooth).unwrap());
                    })
                };
                let (a, b) = (count(&take.bvh), count(&doubled_bvh(&take.bvh)));
                within(b.abs_diff(a), 3 * take.bvh.frames, "take states");

                // inverse dynamics: a torque row per frame
                let count = |s: &States| allocations(|| drop(pipeline::inverse_dynamics(model, s)));
                let (a, b) = (count(&short), count(&long));
                within(b.abs_diff(a), n, "inverse dynamics");
            });
        }
    }
}
