//! The pipeline's per-frame loops allocate nothing but their outputs: unwrapping and smoothing
//! (per joint, whatever the take's length), derivatives (one v and one a row per frame) and
//! inverse dynamics (one torque row per frame; each worker's `Workspace` made once, not per
//! frame or per block). Checked by counting the allocations of a take and of the same take
//! twice as long, serial and with two worker threads: the difference is the output rows
//! exactly on the serial path; with two threads, rayon's own job queues may add a block now and
//! then (crossbeam's injector allocates one per 63 jobs), in either run, far fewer than one per
//! frame. One test in its own binary, since the count is global (worker threads allocate on
//! their own threads).

use articula::motion::smooth::SmoothSpec;
use articula::pipeline::{self, States, TakeOptions};
use std::alloc::{GlobalAlloc, Layout, System};
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};

struct Counting;

static ALLOCS: AtomicUsize = AtomicUsize::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations(f: impl FnOnce()) -> usize {
    let before = ALLOCS.load(Ordering::SeqCst);
    f();
    ALLOCS.load(Ordering::SeqCst) - before
}

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

#[test]
fn per_frame_loops_allocate_only_their_outputs_serial_and_in_parallel() {
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

                // inverse dynamics: a torque row per frame
                let count = |s: &States| allocations(|| drop(pipeline::inverse_dynamics(model, s)));
                let (a, b) = (count(&short), count(&long));
                within(b.abs_diff(a), n, "inverse dynamics");
            });
        }
    }
}
