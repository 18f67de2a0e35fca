//! Inputs found by `examples/fuzz_takes.rs` (the mutation fuzzer of the take pipeline, see
//! docs/validation.md, "Fuzzing"), each cut down to the damage that mattered: they load or fail with an
//! error, never panic, abort or hang.

use articula::io::bvh;
use articula::motion::contact::acceleration_spread_s;
use articula::motion::smooth::SmoothSpec;
use articula::pipeline::{self, TakeOptions};
use std::path::Path;

/// A two-joint take with 4 frames and the given `Frame Time:` token.
fn take_with_frame_time(ft: &str) -> String {
    format!(
        "HIERARCHY\nROOT Hips\n{{\n\tOFFSET 0 90 0\n\tCHANNELS 6 Xposition Yposition Zposition \
         Zrotation Xrotation Yrotation\n\tJOINT LeftUpLeg\n\t{{\n\t\tOFFSET 10 0 0\n\t\t\
         CHANNELS 3 Zrotation Xrotation Yrotation\n\t\tEnd Site\n\t\t{{\n\t\t\tOFFSET 0 -80 0\n\
         \t\t}}\n\t}}\n}}\nMOTION\nFrames: 4\nFrame Time: {ft}\n\
         0 90 0 0 0 0 0 0 0\n1 90 0 1 2 3 4 5 6\n2 91 0 2 4 6 8 10 12\n3 90 0 3 6 9 12 15 18\n"
    )
}

/// Fuzz finding 1: a frame time so short (`1e-300`, `1e-12`, `1e-7`) that no filter applies
/// left the take unsmoothed, and the acceleration spread of the ground reactions then built a
/// ramp of 4 s / frame time samples: a capacity-overflow panic, or an abort allocating 32 TB.
#[test]
fn tiny_frame_time_ground_reactions_neither_panic_nor_allocate_the_world() {
    for ft in ["1e-300", "4.9e-324", "1e-12", "1e-7"] {
        let b = bvh::parse_str(&take_with_frame_time(ft), Path::new("tiny.bvh")).unwrap();
        let take =
            pipeline::take_from_bvh(Path::new("tiny.bvh"), b, &TakeOptions::default()).unwrap();
        let _ = pipeline::estimate_take_ground_reactions(&take);
    }
    // without smoothing the estimate's kernel is [¼, ½, ¼]: one frame each side, whatever dt
    for dt in [1e-300, 1e-12, 1e-7, 1e-5, 1.0 / 120.0] {
        let h = acceleration_spread_s(&SmoothSpec::None, dt).unwrap();
        assert_eq!(h, dt, "dt {dt}");
    }
    // and a filter that applies keeps its spread (about a tenth of a second for 6 Hz)
    let bw = SmoothSpec::Butterworth {
        cutoff_hz: 6.0,
        order: 2,
    };
    let h = acceleration_spread_s(&bw, 1.0 / 120.0).unwrap();
    assert!((0.05..0.15).contains(&h), "{h}");
}

/// Fuzz finding 2: a short take at `Frame Time: 5.4e-6` (185 kHz) is smoothed by the default
/// 6 Hz Butterworth, whose settling pad is ~2·10⁵ samples each side (just under
/// `MAX_FILTER_SPAN`), and the ball model's quaternion padding spent a second in two `powf`
/// per padded sample: now one pair per period of the extension (the same numbers). The load
/// stays bounded by `MAX_FILTER_SPAN` (a generous limit here, for loaded CI machines).
#[test]
fn a_short_take_sampled_at_185_khz_loads_in_bounded_time() {
    let b = bvh::parse_str(&take_with_frame_time("5.4e-6"), Path::new("fast.bvh")).unwrap();
    for joints in ["ball", "euler"] {
        let opts = TakeOptions {
            joints: joints.parse().unwrap(),
            ..TakeOptions::default()
        };
        // the default 6 Hz filter would pad each end with 194,000 frames (1.6 s on its own):
        // past the filters' reach, the default is none, with a note
        let take = pipeline::take_from_bvh(Path::new("fast.bvh"), b.clone(), &opts).unwrap();
        assert_eq!(take.smooth.to_string(), "none");
        assert!(
            take.notes.iter().any(|n| n.contains("cannot apply")),
            "{:?}",
            take.notes
        );
        assert!(take.states.q.iter().flatten().all(|x| x.is_finite()));
        let _ = pipeline::estimate_take_ground_reactions(&take);
    }
}
