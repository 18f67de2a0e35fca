//! What issue 17's parse and smoothing targets would take on this machine: each stage next to
//! the least work it cannot avoid, each timed alone, one thread, best of N runs (ms).
//!
//! - **parse** (target ≤ 3 ms on the take cycled to a minute): `io::bvh::parse_bytes` (what the
//!   `parse` stage runs, before the rest-pose test) against one pass over the frame lines that
//!   only counts their line ends (`memchr`), one that only finds where each number starts and
//!   ends, and `fast-float2` (Eisel–Lemire, the fastest general decimal reader in the
//!   registries) on numbers already cut out: the last two together are what any reader built on
//!   the best general parser must spend.
//! - **smooth** (the largest part of model → derivatives, target ≤ 10 ms for all of it): an
//!   euler joint is smoothed as the rotation it is (`motion::euler`), which needs three sines
//!   and cosines per joint and frame (the rotation) and four arctangents (three angles written
//!   back, one rotation logarithm for `ω`); their time on the vector lanes (`lanes`) at that
//!   count is a floor below which no arrangement of the rest can bring the stage.
//!
//! Run: `cargo run --release --example floors -- [TAKE] [RUNS]` (default
//! `../shared/data/bvh/cmu_01_01.bvh`, 15 runs). Prints a table; nothing is written.

use articula::io::bvh;
use articula::lanes::{atan2_many, sin_cos_many};
use articula::pipeline::{self, TakeOptions, stages::cycle_take_text};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Instant;

/// The best of `runs` timings of `f`, in ms.
fn best_ms(runs: usize, mut f: impl FnMut()) -> f64 {
    (0..runs)
        .map(|_| {
            let t = Instant::now();
            f();
            t.elapsed().as_secs_f64() * 1e3
        })
        .fold(f64::INFINITY, f64::min)
}

/// Where each number of `text` starts and ends (separated by blanks and line ends), 64 bytes
/// at a time: a mask of the blanks ([`blanks`]), the starts and ends as its edges, read off by
/// counting zeros (simdjson's first stage, without its checks).
fn tokens(text: &[u8]) -> Vec<(u32, u32)> {
    let mut starts = Vec::with_capacity(text.len() / 4);
    let mut ends = Vec::with_capacity(text.len() / 4);
    let mut previous_blank = 1u64; // the text starts after a blank
    for (k, chunk) in text.chunks(64).enumerate() {
        let mut blank = blanks(chunk);
        if chunk.len() < 64 {
            blank |= !0u64 << chunk.len();
        }
        let shifted = (blank << 1) | previous_blank;
        let (mut start, mut end) = (!blank & shifted, blank & !shifted);
        let base = (k * 64) as u32;
        while start != 0 {
            starts.push(base + start.trailing_zeros());
            start &= start - 1;
        }
        while end != 0 {
            ends.push(base + end.trailing_zeros());
            end &= end - 1;
        }
        previous_blank = blank >> 63;
    }
    if ends.len() < starts.len() {
        ends.push(text.len() as u32);
    }
    starts.into_iter().zip(ends).collect()
}

/// Bit `i` set where `chunk[i] ≤ b' '` (a blank or a line end), `chunk` at most 64 bytes: two
/// 32-byte compares on AVX2, byte by byte otherwise.
fn blanks(chunk: &[u8]) -> u64 {
    #[cfg(target_arch = "x86_64")]
    if chunk.len() == 64 && std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: AVX2 checked just above; the loads read the chunk's 64 bytes
        return unsafe { blanks_avx2(chunk) };
    }
    chunk
        .iter()
        .enumerate()
        .fold(0, |m, (i, &b)| m | (u64::from(b <= b' ') << i))
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn blanks_avx2(chunk: &[u8]) -> u64 {
    use std::arch::x86_64::*;
    let p = chunk.as_ptr().cast::<__m256i>();
    // b ≤ 0x20 ⟺ min(b, 0x20) = b (unsigned)
    let limit = _mm256_set1_epi8(b' ' as i8);
    let mask = |v: __m256i| _mm256_movemask_epi8(_mm256_cmpeq_epi8(_mm256_min_epu8(v, limit), v));
    // SAFETY: the caller's chunk holds 64 bytes
    let (lo, hi) = unsafe { (_mm256_loadu_si256(p), _mm256_loadu_si256(p.add(1))) };
    u64::from(mask(lo) as u32) | (u64::from(mask(hi) as u32) << 32)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // one thread, as the targets are stated (the reader cuts the text into chunks otherwise)
    rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build_global()?;
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = PathBuf::from(
        args.first()
            .map_or("../shared/data/bvh/cmu_01_01.bvh", |s| s),
    );
    let runs: usize = args.get(1).map_or(Ok(15), |s| s.parse())?;
    let raw = std::fs::read_to_string(&path)?;
    let (text, _) = cycle_take_text(&raw, 1.0, &path)?;
    let text = text.into_bytes();
    let at = text
        .windows(11)
        .position(|w| w == b"Frame Time:")
        .ok_or("no `Frame Time:` line")?;
    let lines = &text[at + memchr::memchr(b'\n', &text[at..]).ok_or("no frame lines")? + 1..];
    let cut = tokens(lines);

    let parse = best_ms(runs, || {
        black_box(bvh::parse_bytes(black_box(&text), &path).expect("the take parses"));
    });
    let count = best_ms(runs, || {
        black_box(memchr::memchr_iter(b'\n', black_box(lines)).count());
    });
    let cutting = best_ms(runs, || {
        black_box(tokens(black_box(lines)));
    });
    let fast_float = best_ms(runs, || {
        let mut sum = 0.0;
        for &(s, e) in &cut {
            let v: f64 = fast_float2::parse(&lines[s as usize..e as usize]).expect("a number");
            sum += v;
        }
        black_box(sum);
    });
    let mb = lines.len() as f64 / 1e6;
    println!(
        "{} cycled to a minute: {:.2} MB of frame lines, {} numbers",
        path.display(),
        mb,
        cut.len()
    );
    println!("\nparse (target ≤ 3 ms)                              ms    GB/s");
    let row = |what: &str, ms: f64| println!("{what:<48} {ms:>6.2}  {:>6.2}", mb / ms);
    row("io::bvh::parse_bytes (the stage's reader)", parse);
    row("line ends counted (memchr), nothing read", count);
    row("numbers' boundaries found, nothing read", cutting);
    row("fast-float2 on numbers already cut out", fast_float);
    row(
        "boundaries + fast-float2 (a general reader)",
        cutting + fast_float,
    );

    // smoothing: the take's euler joints over a minute of frames
    let take = pipeline::load_take(&path, &TakeOptions::default())?;
    let joints = take.model.euler_triples().len();
    let frames = (60.0 / take.bvh.frame_time).round() as usize;
    let (n_sin, n_atan) = (3 * joints * frames, 4 * joints * frames);
    // angles and argument pairs as a capture gives them (several turns, every quadrant)
    let x: Vec<f64> = (0..n_sin)
        .map(|i| ((i as f64) * 0.0137).sin() * 2.9)
        .collect();
    let (mut s, mut c) = (vec![0.0; n_sin], vec![0.0; n_sin]);
    let y2: Vec<f64> = (0..n_atan)
        .map(|i| ((i as f64) * 0.011).sin() + 1e-3)
        .collect();
    let x2: Vec<f64> = (0..n_atan)
        .map(|i| ((i as f64) * 0.011).cos() + 2e-3)
        .collect();
    let mut out = vec![0.0; n_atan];
    let sin_cos = best_ms(runs, || sin_cos_many(black_box(&x), &mut s, &mut c));
    let atan2 = best_ms(runs, || atan2_many(black_box(&y2), &x2, &mut out));
    println!(
        "\nsmooth ({joints} euler joints × {frames} frames; model → derivatives ≤ 10 ms)   ms"
    );
    println!(
        "{:<52} {sin_cos:>6.2}",
        format!("{n_sin} sines and cosines (lanes::sin_cos_many)")
    );
    println!(
        "{:<52} {atan2:>6.2}",
        format!("{n_atan} arctangents (lanes::atan2_many)")
    );
    println!("{:<52} {:>6.2}", "the two together", sin_cos + atan2);
    Ok(())
}
