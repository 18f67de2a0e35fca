//! A structure-aware mutation fuzzer of the BVH reader and the whole take pipeline (issue 12),
//! on the stable toolchain (no libFuzzer): every execution mutates a small seed take, parses it
//! and, when it parses, loads it as a take with the euler and the ball joint model, runs inverse
//! dynamics over its states and estimates its ground reactions.
//!
//! Run (from the repository root):
//!
//! ```text
//! cargo run --release --example fuzz_takes -- [--execs N] [--seed S] [--threads T]
//!     [--corpus DIR] [--findings DIR] [--mem-mb M]
//! cargo run --release --example fuzz_takes -- --replay FILE   # one input, panics uncaught
//! cargo run --release --example fuzz_takes -- --explain-parse-errors [--execs N] [--corpus DIR]
//! ```
//!
//! (`--explain-parse-errors`: the commonest reader errors of the first N inputs, to tune the
//! mutations so enough of them reach the pipeline.)
//!
//! - Seeds: `data/demo_walk.bvh` cut to 4, 8 and 12 frames, small synthetic skeletons built
//!   here (a human with feet, a helper root above it, 6 channels on every joint, a lone root,
//!   1- and 2-frame takes, CRLF), and every `.bvh` of `--corpus DIR`, each cut to a few frames.
//! - Mutations (1 to 8 stacked per execution, chosen by a SplitMix64 seeded from `--seed` and
//!   the execution's index, so every input can be rebuilt): a number replaced by an extreme
//!   (0, -0, 1e-300, 1e300, -1e308, NaN, inf, huge integers, …), `Frames:` and `Frame Time:`
//!   changed, lines deleted / duplicated / swapped / spliced from another seed, a CHANNELS count
//!   or its channel names changed (duplicate axes, 0, 7 or 9 channels, unknown names), joints
//!   renamed (empty, duplicates, `:` `.`, keywords, long, non-ASCII), braces removed or
//!   inserted, deeper nesting, a channel's column made constant, huge, NaN or jumping, bytes
//!   inserted (NUL, invalid UTF-8, CR, BOM, NBSP), truncation, bit flips and random bytes.
//!   Two thirds of the mutated inputs are then "repaired": every frame line gets exactly the number
//!   of values the CHANNELS lines name and `Frames:` the number of frame lines, so damage to
//!   the structure and the numbers reaches the pipeline instead of stopping at the reader.
//! - The work runs in `--threads` worker processes (this example re-invoked with `--worker`),
//!   so an abort (allocation failure under the `--mem-mb` address-space limit, stack overflow)
//!   kills only a worker: before each execution the worker writes its counters and the input
//!   to a state file, and the parent records the input it died on and restarts it after it.
//!   A worker whose state file does not change for 20 s is killed and counted as a hang.
//! - Each execution runs under `catch_unwind` with a silent panic hook; a panic is saved once
//!   per (message with digits masked, location) to the findings directory
//!   (`fuzz-findings/<time>-seed<S>/`, git-ignored), an execution slower than 1 s is a hang
//!   and saved too. At the end: executions, executions/s, parse errors, pipeline errors,
//!   successes, panics, hangs, aborts, the slowest execution and every finding.

use articula::io::bvh;
use articula::pipeline::{self, TakeOptions};
use std::collections::VecDeque;
use std::fmt::Write as _;
use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::Mutex;
use std::time::{Duration, Instant, SystemTime};

/// An execution slower than this is a hang.
const HANG: Duration = Duration::from_secs(1);
/// A worker whose state file does not change for this long is stuck: killed, a hang.
const STUCK: Duration = Duration::from_secs(20);

// ---------------------------------------------------------------------------------------------
// PRNG

/// SplitMix64 (Steele, Lea, Flood 2014).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        if n == 0 {
            0
        } else {
            (self.next() % n as u64) as usize
        }
    }
    fn chance(&mut self, one_in: usize) -> bool {
        self.below(one_in) == 0
    }
    fn pick<'a, T>(&mut self, xs: &'a [T]) -> &'a T {
        &xs[self.below(xs.len())]
    }
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The generator of execution `index` of a run seeded with `seed`.
fn exec_rng(seed: u64, index: u64) -> Rng {
    let mut r = Rng(seed ^ index.wrapping_mul(0xD1B5_4A32_D192_ED03));
    r.next();
    r
}

// ---------------------------------------------------------------------------------------------
// Seeds

/// Lines of a text (split on `\n`, a `\r` stays on its line).
fn lines(b: &[u8]) -> Vec<Vec<u8>> {
    b.split(|&c| c == b'\n').map(|l| l.to_vec()).collect()
}

fn join(ls: &[Vec<u8>]) -> Vec<u8> {
    let mut out = Vec::with_capacity(ls.iter().map(|l| l.len() + 1).sum());
    for (i, l) in ls.iter().enumerate() {
        if i > 0 {
            out.push(b'\n');
        }
        out.extend_from_slice(l);
    }
    out
}

/// Whitespace-separated tokens of a line, as byte ranges.
fn tokens(l: &[u8]) -> Vec<(usize, usize)> {
    let mut out = vec![];
    let mut i = 0;
    while i < l.len() {
        while i < l.len() && l[i].is_ascii_whitespace() {
            i += 1;
        }
        let s = i;
        while i < l.len() && !l[i].is_ascii_whitespace() {
            i += 1;
        }
        if i > s {
            out.push((s, i));
        }
    }
    out
}

fn first_token(l: &[u8]) -> &[u8] {
    tokens(l).first().map_or(&[][..], |&(s, e)| &l[s..e])
}

fn starts_with_ci(l: &[u8], word: &str) -> bool {
    first_token(l).eq_ignore_ascii_case(word.as_bytes())
}

/// Index of the line that starts with `Frame` `Time:` (the last header line).
fn frame_time_line(ls: &[Vec<u8>]) -> Option<usize> {
    ls.iter().position(|l| {
        let t = tokens(l);
        t.len() >= 2
            && l[t[0].0..t[0].1].eq_ignore_ascii_case(b"frame")
            && l[t[1].0..t[1].1].to_ascii_lowercase().starts_with(b"time")
    })
}

fn frames_line(ls: &[Vec<u8>]) -> Option<usize> {
    ls.iter()
        .position(|l| first_token(l).to_ascii_lowercase().starts_with(b"frames"))
}

/// `text` with `k` frame lines from frame `from` (fewer if the take is shorter), or `None`.
fn cut(text: &[u8], from: usize, k: usize) -> Option<Vec<u8>> {
    let ls = lines(text);
    let ft = frame_time_line(&ls)?;
    let fl = frames_line(&ls)?;
    let frames: Vec<&Vec<u8>> = ls[ft + 1..]
        .iter()
        .filter(|l| !tokens(l).is_empty())
        .collect();
    if frames.is_empty() {
        return None;
    }
    let from = from.min(frames.len() - 1);
    let take: Vec<Vec<u8>> = frames[from..(from + k).min(frames.len())]
        .iter()
        .map(|l| l.to_vec())
        .collect();
    let mut out: Vec<Vec<u8>> = ls[..=ft].to_vec();
    let cr = if ls[fl].ends_with(b"\r") { "\r" } else { "" };
    out[fl] = format!("Frames: {}{cr}", take.len()).into_bytes();
    out.extend(take);
    out.push(vec![]);
    Some(join(&out))
}

/// A joint of a synthetic skeleton: name, parent, offset, channels (0, 3 rotations, 6).
type J = (&'static str, Option<usize>, [f64; 3], usize);

/// A BVH of `joints` with `frames` frames of smooth motion at `ft` s per frame.
fn synth(joints: &[J], frames: usize, ft: f64, eol: &str) -> Vec<u8> {
    fn body(js: &[J], j: usize, depth: usize, eol: &str, out: &mut String) {
        let pad = "\t".repeat(depth);
        let (name, parent, o, ch) = js[j];
        let kw = if parent.is_none() { "ROOT" } else { "JOINT" };
        let _ = write!(out, "{pad}{kw} {name}{eol}{pad}{{{eol}");
        let _ = write!(out, "{pad}\tOFFSET {} {} {}{eol}", o[0], o[1], o[2]);
        let names = match ch {
            0 => "",
            3 => " Zrotation Xrotation Yrotation",
            _ => " Xposition Yposition Zposition Zrotation Xrotation Yrotation",
        };
        let _ = write!(out, "{pad}\tCHANNELS {ch}{names}{eol}");
        let kids: Vec<usize> = (0..js.len()).filter(|&k| js[k].1 == Some(j)).collect();
        if kids.is_empty() {
            let _ = write!(
                out,
                "{pad}\tEnd Site{eol}{pad}\t{{{eol}{pad}\t\tOFFSET {} {} {}{eol}{pad}\t}}{eol}",
                o[0] * 0.5,
                o[1] * 0.5 + 2.0,
                o[2] * 0.5
            );
        }
        for k in kids {
            body(js, k, depth + 1, eol, out);
        }
        let _ = write!(out, "{pad}}}{eol}");
    }
    let mut out = format!("HIERARCHY{eol}");
    body(joints, 0, 0, eol, &mut out);
    let _ = write!(out, "MOTION{eol}Frames: {frames}{eol}Frame Time: {ft}{eol}");
    for f in 0..frames {
        let t = f as f64 * ft;
        let mut vals = vec![];
        for (j, &(_, _, o, ch)) in joints.iter().enumerate() {
            if ch == 6 {
                vals.extend([o[0] + 20.0 * t, o[1] + (6.0 * t).sin(), o[2]]);
            }
            for c in 0..ch.min(3) {
                vals.push(25.0 * (5.0 * t + j as f64 + c as f64).sin());
            }
        }
        let line: Vec<String> = vals.iter().map(|v| format!("{v:.4}")).collect();
        let _ = write!(out, "{}{eol}", line.join(" "));
    }
    out.into_bytes()
}

fn human(root_ch: usize) -> Vec<J> {
    let l = |x: f64| x;
    vec![
        ("Hips", None, [0.0, 95.0, 0.0], root_ch),
        ("Spine", Some(0), [0.0, 10.0, 0.0], 3),
        ("Chest", Some(1), [0.0, 20.0, 0.0], 3),
        ("Neck", Some(2), [0.0, 20.0, 0.0], 3),
        ("Head", Some(3), [0.0, 10.0, 0.0], 3),
        ("LeftUpLeg", Some(0), [l(9.0), -5.0, 0.0], 3),
        ("LeftLeg", Some(5), [0.0, -42.0, 0.0], 3),
        ("LeftFoot", Some(6), [0.0, -40.0, 0.0], 3),
        ("LeftToeBase", Some(7), [0.0, -6.0, 13.0], 3),
        ("RightUpLeg", Some(0), [-9.0, -5.0, 0.0], 3),
        ("RightLeg", Some(9), [0.0, -42.0, 0.0], 3),
        ("RightFoot", Some(10), [0.0, -40.0, 0.0], 3),
        ("RightToeBase", Some(11), [0.0, -6.0, 13.0], 3),
        ("LeftArm", Some(2), [16.0, 15.0, 0.0], 3),
        ("LeftForeArm", Some(13), [28.0, 0.0, 0.0], 3),
        ("LeftHand", Some(14), [25.0, 0.0, 0.0], 3),
        ("RightArm", Some(2), [-16.0, 15.0, 0.0], 3),
        ("RightForeArm", Some(16), [-28.0, 0.0, 0.0], 3),
        ("RightHand", Some(17), [-25.0, 0.0, 0.0], 3),
    ]
}

/// Every seed: (name, bytes).
fn seeds(repo: &Path, corpus: Option<&Path>) -> Vec<(String, Vec<u8>)> {
    let mut out = vec![];
    let mut add_cuts = |name: &str, text: &[u8], cuts: &[(usize, usize)]| {
        for &(from, k) in cuts {
            if let Some(c) = cut(text, from, k) {
                out.push((format!("{name}[{from}+{k}]"), c));
            }
        }
    };
    let demo = std::fs::read(repo.join("data/demo_walk.bvh")).expect("data/demo_walk.bvh");
    add_cuts("demo_walk", &demo, &[(0, 4), (100, 8), (200, 12)]);
    if let Some(dir) = corpus {
        let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
            .unwrap_or_else(|e| panic!("--corpus {}: {e}", dir.display()))
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p.extension().is_some_and(|e| e.eq_ignore_ascii_case("bvh")))
            .collect();
        files.sort();
        for f in files {
            let text = std::fs::read(&f).unwrap_or_default();
            let name = f.file_name().unwrap().to_string_lossy().into_owned();
            add_cuts(&name, &text, &[(0, 6), (60, 10)]);
        }
    }
    let h6 = human(6);
    out.push(("human".into(), synth(&h6, 10, 1.0 / 60.0, "\n")));
    out.push(("human_crlf_30fps".into(), synth(&h6, 8, 1.0 / 30.0, "\r\n")));
    out.push(("human_1_frame".into(), synth(&h6, 1, 1.0 / 60.0, "\n")));
    out.push(("human_2_frames".into(), synth(&h6, 2, 1.0 / 120.0, "\n")));
    out.push(("human_root3".into(), synth(&human(3), 6, 1.0 / 60.0, "\n")));
    let mut all6 = human(6);
    for j in &mut all6 {
        j.3 = 6;
    }
    out.push(("human_all6".into(), synth(&all6, 6, 1.0 / 60.0, "\n")));
    // a massless helper root above Hips, both with 6 channels (Bandai: folded, welded)
    let mut helper: Vec<J> = vec![("joint_Root", None, [0.0, 0.0, 0.0], 6)];
    helper.extend(
        h6.iter()
            .map(|&(n, p, o, c)| (n, Some(p.map_or(0, |p| p + 1)), o, c)),
    );
    out.push(("helper_root".into(), synth(&helper, 6, 1.0 / 60.0, "\n")));
    out.push((
        "lone_root".into(),
        synth(&[("Root", None, [0.0, 0.0, 0.0], 6)], 3, 0.04, "\n"),
    ));
    out.push((
        "chain".into(),
        synth(
            &[
                ("A", None, [0.0, 0.0, 0.0], 6),
                ("B", Some(0), [0.0, 1.0, 0.0], 3),
                ("C", Some(1), [0.0, 1.0, 0.0], 0),
                ("D", Some(2), [1.0, 0.0, 0.0], 3),
            ],
            5,
            0.01,
            "\n",
        ),
    ));
    out
}

// ---------------------------------------------------------------------------------------------
// Mutations

const EXTREMES: &[&str] = &[
    "0",
    "-0",
    "1e-300",
    "1e300",
    "-1e308",
    "1e309",
    "-1e309",
    "NaN",
    "nan",
    "-NaN",
    "inf",
    "-inf",
    "infinity",
    "4.9e-324",
    "1.7976931348623157e308",
    "18446744073709551615",
    "18446744073709551616",
    "9223372036854775807",
    "4294967296",
    "99999999999999999999999999999",
    "-1",
    "1e-7",
    "-1e-7",
    "1e-12",
    "360",
    "-180",
    "90",
    "89.9999999",
    "720000",
    "1e9",
    "1e15",
    "0x10",
    "1e",
    "+5",
    "--1",
    "1,5",
    ".",
    "",
];
const FRAMES: &[&str] = &[
    "0",
    "1",
    "2",
    "3",
    "-1",
    "+4",
    "4.0",
    "1e3",
    "999999999",
    "4294967296",
    "18446744073709551615",
    "18446744073709551616",
    "abc",
    "",
];
const FRAME_TIMES: &[&str] = &[
    "0", "-0", "-0.0083", "1e-7", "1e-12", "1e-300", "4.9e-324", "NaN", "inf", "-inf", "1e300",
    "86400", "1", "0.5", "0.1", "1e-3", ".0083333", "0.04", "",
];
const CHANNELS: &[&str] = &[
    "Xposition",
    "Yposition",
    "Zposition",
    "Xrotation",
    "Yrotation",
    "Zrotation",
    "xrotation",
    "ZROTATION",
    "Wrotation",
    "rotation",
    "Xposition",
    "Zrotation",
];
const NAMES: &[&str] = &[
    "",
    "Hips",
    "Spine",
    "LeftFoot",
    "RightFoot",
    "LeftToeBase",
    "RightToe_End",
    "Head",
    "LeftUpLeg",
    "RightLeg",
    "mixamorig:LeftFoot",
    "a.b",
    "a:b",
    ":",
    ".",
    "..",
    "End",
    "Site",
    "JOINT",
    "ROOT",
    "MOTION",
    "OFFSET",
    "CHANNELS",
    "{",
    "}",
    "Frames:",
    "joint_Root",
    "\u{fffd}",
    "名前",
    "Left Foot",
];
const BYTES: &[&[u8]] = &[
    b"\0",
    b"\xff",
    b"\xc3",
    b"\xe2\x82",
    "é".as_bytes(),
    "\u{feff}".as_bytes(),
    "\u{a0}".as_bytes(),
    "\u{2028}".as_bytes(),
    b"\r",
    b"\r\n",
    b"\n",
    b"\t",
    b" ",
    b"\x0b",
    b"\x0c",
    b"{",
    b"}",
    b"-",
    b".",
    b"e",
    b"#",
];

/// Replaces token `t` of line `li` by `by` (a token `""` removes it).
fn set_token(ls: &mut [Vec<u8>], li: usize, t: (usize, usize), by: &[u8]) {
    let l = &mut ls[li];
    l.splice(t.0..t.1, by.iter().copied());
}

/// Every number token: (line, token range).
fn number_tokens(ls: &[Vec<u8>]) -> Vec<(usize, (usize, usize))> {
    let mut out = vec![];
    for (i, l) in ls.iter().enumerate() {
        for t in tokens(l) {
            let s = &l[t.0..t.1];
            if std::str::from_utf8(s).is_ok_and(|s| s.parse::<f64>().is_ok()) {
                out.push((i, t));
            }
        }
    }
    out
}

/// Lines whose first token is one of `words`.
fn lines_of(ls: &[Vec<u8>], words: &[&str]) -> Vec<usize> {
    (0..ls.len())
        .filter(|&i| words.iter().any(|w| starts_with_ci(&ls[i], w)))
        .collect()
}

/// The first line of the motion data (after `Frame Time:`), or the line count.
fn data_start(ls: &[Vec<u8>]) -> usize {
    frame_time_line(ls).map_or(ls.len(), |i| i + 1)
}

fn random_number(rng: &mut Rng) -> String {
    match rng.below(4) {
        0 => rng.pick(EXTREMES).to_string(),
        1 => format!("{}", (rng.unit() - 0.5) * 10f64.powi(rng.below(12) as i32)),
        2 => format!("{}", rng.below(2000) as i64 - 1000),
        _ => format!(
            "{:e}",
            (rng.unit() - 0.5) * 10f64.powi(rng.below(600) as i32 - 300)
        ),
    }
}

fn mutate(rng: &mut Rng, input: &mut Vec<u8>, seeds: &[(String, Vec<u8>)]) {
    let mut ls = lines(input);
    let n = ls.len().max(1);
    let byte_level = |input: &mut Vec<u8>, ls: &[Vec<u8>]| {
        *input = join(ls);
    };
    match rng.below(30) {
        // a number replaced by an extreme or a random value
        0..=6 => {
            let nums = number_tokens(&ls);
            if !nums.is_empty() {
                let &(li, t) = rng.pick(&nums);
                let by = random_number(rng);
                set_token(&mut ls, li, t, by.as_bytes());
            }
        }
        // Frames:
        7 => {
            if let Some(li) = frames_line(&ls) {
                let v = if rng.chance(2) {
                    rng.pick(FRAMES).to_string()
                } else {
                    let t = tokens(&ls[li]);
                    let cur: i64 = t
                        .get(1)
                        .and_then(|&(s, e)| std::str::from_utf8(&ls[li][s..e]).ok())
                        .and_then(|s| s.parse().ok())
                        .unwrap_or(4);
                    (cur + rng.below(5) as i64 - 2).to_string()
                };
                ls[li] = format!("Frames: {v}").into_bytes();
            }
        }
        // Frame Time:
        8 | 9 => {
            if let Some(li) = frame_time_line(&ls) {
                let v = if rng.chance(3) {
                    random_number(rng)
                } else {
                    rng.pick(FRAME_TIMES).to_string()
                };
                let sep = *rng.pick(&[" ", "\t", "", "  "]);
                ls[li] = format!("Frame Time:{sep}{v}").into_bytes();
            }
        }
        // delete, duplicate, swap lines
        10 => {
            let k = 1 + if rng.chance(4) { rng.below(8) } else { 0 };
            let i = rng.below(n);
            let e = (i + k).min(ls.len());
            ls.drain(i..e);
        }
        11 => {
            let i = rng.below(n);
            if i < ls.len() {
                let l = ls[i].clone();
                for _ in 0..1 + rng.below(3) {
                    ls.insert(i, l.clone());
                }
            }
        }
        12 => {
            let (i, j) = (rng.below(n), rng.below(n));
            if i < ls.len() && j < ls.len() {
                ls.swap(i, j);
            }
        }
        // CHANNELS count
        13 => {
            let ch = lines_of(&ls, &["CHANNELS"]);
            if !ch.is_empty() {
                let li = *rng.pick(&ch);
                let t = tokens(&ls[li]);
                if let Some(&c) = t.get(1) {
                    let v = *rng.pick(&["0", "1", "2", "3", "4", "6", "7", "9", "-3", "3.0", "99"]);
                    set_token(&mut ls, li, c, v.as_bytes());
                }
            }
        }
        // CHANNELS names
        14 | 15 => {
            let ch = lines_of(&ls, &["CHANNELS"]);
            if !ch.is_empty() {
                let li = *rng.pick(&ch);
                let k = *rng.pick(&[0, 1, 2, 3, 3, 3, 4, 6, 6, 7, 9]);
                let names: Vec<&str> = if rng.chance(2) {
                    // a permutation / repetition of the usual ones
                    (0..k).map(|_| *rng.pick(&CHANNELS[..6])).collect()
                } else {
                    (0..k).map(|_| *rng.pick(CHANNELS)).collect()
                };
                let count = if rng.chance(8) { k + 1 } else { k };
                ls[li] = format!("CHANNELS {count} {}", names.join(" ")).into_bytes();
            }
        }
        // rename a joint
        16 | 17 => {
            let js = lines_of(&ls, &["ROOT", "JOINT"]);
            if !js.is_empty() {
                let li = *rng.pick(&js);
                let t = tokens(&ls[li]);
                let name: Vec<u8> = match rng.below(4) {
                    0 => {
                        // another joint's name: duplicates
                        let o = *rng.pick(&js);
                        let to = tokens(&ls[o]);
                        to.get(1).map_or(vec![], |&(s, e)| ls[o][s..e].to_vec())
                    }
                    1 => "x".repeat(1 + rng.below(5000)).into_bytes(),
                    _ => rng.pick(NAMES).as_bytes().to_vec(),
                };
                match t.get(1) {
                    Some(&nt) => set_token(&mut ls, li, nt, &name),
                    None => ls[li].extend_from_slice(&name),
                }
            }
        }
        // remove or insert a brace
        18 => {
            let bs = lines_of(&ls, &["{", "}"]);
            if !bs.is_empty() {
                ls.remove(*rng.pick(&bs));
            }
        }
        19 => {
            let i = rng.below(n + 1).min(ls.len());
            ls.insert(i, rng.pick(&[&b"{"[..], b"}", b"{ }", b"}}"]).to_vec());
        }
        // nest deeper: a chain inserted before a JOINT or End Site line
        20 | 21 => {
            let at = lines_of(&ls, &["JOINT", "End"]);
            if !at.is_empty() {
                let li = *rng.pick(&at);
                let depth = if rng.chance(50) {
                    1 + rng.below(400)
                } else {
                    1 + rng.below(12)
                };
                let ch = *rng.pick(&[0, 3, 3, 6]);
                let names = match ch {
                    0 => "",
                    3 => " Zrotation Xrotation Yrotation",
                    _ => " Xposition Yposition Zposition Zrotation Xrotation Yrotation",
                };
                let o = *rng.pick(&["0 0 0", "0 1 0", "0 1e-9 0", "0 1e6 0", "1 2 3"]);
                let mut chain = vec![];
                let tag = rng.below(1_000_000);
                for d in 0..depth {
                    chain.push(format!("JOINT Deep{tag}_{d}").into_bytes());
                    chain.push(b"{".to_vec());
                    chain.push(format!("OFFSET {o}").into_bytes());
                    chain.push(format!("CHANNELS {ch}{names}").into_bytes());
                }
                chain.push(b"End Site".to_vec());
                chain.push(b"{".to_vec());
                chain.push(format!("OFFSET {o}").into_bytes());
                chain.push(b"}".to_vec());
                chain.extend((0..depth).map(|_| b"}".to_vec()));
                ls.splice(li..li, chain);
            }
        }
        // a channel's column changed over all frames
        22 | 23 => {
            let s = data_start(&ls);
            if s < ls.len() {
                let cols = tokens(&ls[s]).len().max(1);
                let c = rng.below(cols);
                let kind = rng.below(5);
                let v = random_number(rng);
                let jump_at = s + rng.below(ls.len() - s);
                for li in s..ls.len() {
                    let t = tokens(&ls[li]);
                    if let Some(&tc) = t.get(c) {
                        let old: f64 = std::str::from_utf8(&ls[li][tc.0..tc.1])
                            .ok()
                            .and_then(|x| x.parse().ok())
                            .unwrap_or(0.0);
                        let new = match kind {
                            0 => v.clone(),
                            1 => format!("{}", old * 1e6),
                            2 => format!("{}", old + if li >= jump_at { 360.0 } else { 0.0 }),
                            3 => format!("{}", old + if li >= jump_at { 1e4 } else { 0.0 }),
                            _ => format!("{}", -old),
                        };
                        set_token(&mut ls, li, tc, new.as_bytes());
                    }
                }
            }
        }
        // splice lines from another seed
        24 => {
            let other = lines(&rng.pick(seeds).1);
            let a = rng.below(other.len());
            let b = (a + 1 + rng.below(20)).min(other.len());
            let i = rng.below(n + 1).min(ls.len());
            let e = (i + rng.below(20)).min(ls.len());
            ls.splice(i..e, other[a..b].iter().cloned());
        }
        // insert bytes
        25 => {
            byte_level(input, &ls);
            let at = rng.below(input.len() + 1);
            let b = *rng.pick(BYTES);
            let k = if rng.chance(8) { 1 + rng.below(64) } else { 1 };
            for _ in 0..k {
                input.splice(at..at, b.iter().copied());
            }
            return;
        }
        // truncate
        26 => {
            byte_level(input, &ls);
            let at = rng.below(input.len() + 1);
            input.truncate(at);
            return;
        }
        // bit flips, random bytes, deleted ranges
        _ => {
            byte_level(input, &ls);
            if input.is_empty() {
                return;
            }
            for _ in 0..1 + rng.below(4) {
                let i = rng.below(input.len());
                match rng.below(4) {
                    0 => input[i] ^= 1 << rng.below(8),
                    1 => input[i] = rng.next() as u8,
                    2 => {
                        let e = (i + 1 + rng.below(16)).min(input.len());
                        input.drain(i..e);
                    }
                    _ => input.insert(i, rng.next() as u8),
                }
                if input.is_empty() {
                    return;
                }
            }
            return;
        }
    }
    *input = join(&ls);
}

/// Frame lines with exactly the channel count the CHANNELS lines name, `Frames:` their count.
fn repair(rng: &mut Rng, input: &mut Vec<u8>) {
    let mut ls = lines(input);
    let Some(ft) = frame_time_line(&ls) else {
        return;
    };
    let mut total = 0;
    for li in lines_of(&ls[..ft], &["CHANNELS"]) {
        let t = tokens(&ls[li]);
        let names = t.len().saturating_sub(2);
        total += names;
        if let Some(&c) = t.get(1)
            && rng.below(10) < 8
        {
            set_token(&mut ls, li, c, names.to_string().as_bytes());
        }
    }
    let mut data: Vec<Vec<u8>> = ls[ft + 1..]
        .iter()
        .filter(|l| !tokens(l).is_empty())
        .cloned()
        .collect();
    for l in &mut data {
        let t = tokens(l);
        let mut vals: Vec<Vec<u8>> = t
            .iter()
            .take(total)
            .map(|&(s, e)| l[s..e].to_vec())
            .collect();
        while vals.len() < total {
            vals.push(format!("{:.3}", (rng.unit() - 0.5) * 20.0).into_bytes());
        }
        *l = vals.join(&b' ');
    }
    if data.is_empty() {
        return;
    }
    if let Some(fl) = frames_line(&ls[..ft]) {
        ls[fl] = format!("Frames: {}", data.len()).into_bytes();
    }
    ls.truncate(ft + 1);
    ls.extend(data);
    ls.push(vec![]);
    *input = join(&ls);
}

/// The input of execution `index`.
fn input_of(seed: u64, index: u64, seeds: &[(String, Vec<u8>)]) -> Vec<u8> {
    let mut rng = exec_rng(seed, index);
    let mut input = rng.pick(seeds).1.clone();
    let k = [1, 1, 1, 2, 2, 3, 4, 8][rng.below(8)];
    for _ in 0..k {
        mutate(&mut rng, &mut input, seeds);
    }
    if rng.below(3) < 2 {
        repair(&mut rng, &mut input);
    }
    input
}

// ---------------------------------------------------------------------------------------------
// One execution

#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Outcome {
    ParseError,
    PipelineError,
    Ok,
}

/// Reader, then the take pipeline with both joint models, inverse dynamics and ground reactions.
fn execute(input: &[u8]) -> Outcome {
    let path = Path::new("fuzz.bvh");
    let Ok(parsed) = bvh::parse_bytes(input, path) else {
        return Outcome::ParseError;
    };
    // the writer's output reads back to the same take
    let again = bvh::parse_str(&bvh::write_string(&parsed), path)
        .unwrap_or_else(|e| panic!("write_string output does not parse: {e}"));
    assert_eq!(
        again.frames, parsed.frames,
        "write → parse changed the frames"
    );
    assert_eq!(
        again.joints.len(),
        parsed.joints.len(),
        "write → parse changed the joints"
    );
    let mut outcome = Outcome::Ok;
    for joints in ["euler", "ball"] {
        let mut b = parsed.clone();
        if joints == "euler" {
            // as load_take does by default
            articula::motion::trim::trim_rest_first_frame(&mut b);
        }
        let opts = TakeOptions {
            joints: joints.parse().unwrap(),
            ..TakeOptions::default()
        };
        match pipeline::take_from_bvh(path, b, &opts) {
            Ok(take) => {
                let tau = pipeline::inverse_dynamics(&take.model, &take.states);
                std::hint::black_box(&tau);
                let _ = std::hint::black_box(pipeline::estimate_take_ground_reactions(&take));
            }
            Err(_) => outcome = Outcome::PipelineError,
        }
    }
    outcome
}

// ---------------------------------------------------------------------------------------------
// Worker

/// The message and location of the last panic (the hook is silent).
static LAST_PANIC: Mutex<Option<(String, String, String)>> = Mutex::new(None);

#[derive(Default, Clone, Copy, Debug)]
struct Counts {
    execs: u64,
    parse_err: u64,
    pipeline_err: u64,
    ok: u64,
    panics: u64,
    hangs: u64,
    aborts: u64,
    slowest_ns: u64,
    slowest_index: u64,
}

impl Counts {
    fn add(&mut self, o: &Counts) {
        self.execs += o.execs;
        self.parse_err += o.parse_err;
        self.pipeline_err += o.pipeline_err;
        self.ok += o.ok;
        self.panics += o.panics;
        self.hangs += o.hangs;
        self.aborts += o.aborts;
        if o.slowest_ns > self.slowest_ns {
            self.slowest_ns = o.slowest_ns;
            self.slowest_index = o.slowest_index;
        }
    }
    fn header(&self, next: u64) -> String {
        format!(
            "next {next}\nexecs {}\nparse_err {}\npipeline_err {}\nok {}\npanics {}\nhangs {}\n\
             slowest_ns {}\nslowest_index {}\n---\n",
            self.execs,
            self.parse_err,
            self.pipeline_err,
            self.ok,
            self.panics,
            self.hangs,
            self.slowest_ns,
            self.slowest_index
        )
    }
    /// (next, counts, input) of a state file.
    fn parse_state(bytes: &[u8]) -> Option<(u64, Counts, Vec<u8>)> {
        let sep = bytes.windows(5).position(|w| w == b"\n---\n")?;
        let head = std::str::from_utf8(&bytes[..sep]).ok()?;
        let mut c = Counts::default();
        let mut next = None;
        for l in head.lines() {
            let (k, v) = l.split_once(' ')?;
            let v: u64 = v.parse().ok()?;
            match k {
                "next" => next = Some(v),
                "execs" => c.execs = v,
                "parse_err" => c.parse_err = v,
                "pipeline_err" => c.pipeline_err = v,
                "ok" => c.ok = v,
                "panics" => c.panics = v,
                "hangs" => c.hangs = v,
                "slowest_ns" => c.slowest_ns = v,
                "slowest_index" => c.slowest_index = v,
                _ => {}
            }
        }
        Some((next?, c, bytes[sep + 5..].to_vec()))
    }
}

fn digits_masked(s: &str) -> String {
    let mut out = String::new();
    let mut prev = false;
    for ch in s.chars() {
        let d = ch.is_ascii_digit();
        if !(d && prev) {
            out.push(if d { '#' } else { ch });
        }
        prev = d;
    }
    out
}

fn fnv(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

struct Args {
    execs: u64,
    seed: u64,
    threads: usize,
    corpus: Option<PathBuf>,
    findings: Option<PathBuf>,
    mem_mb: u64,
    worker: Option<(u64, u64)>,
    state: Option<PathBuf>,
    replay: Option<PathBuf>,
    explain: bool,
}

fn worker(a: &Args, from: u64, to: u64) {
    let seeds = seeds(Path::new("."), a.corpus.as_deref());
    let findings = a.findings.clone().expect("--findings");
    let state_path = a.state.clone().expect("--state");
    let mut state = std::fs::File::create(&state_path).expect("state file");
    std::panic::set_hook(Box::new(|info| {
        let msg = info
            .payload()
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| info.payload().downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "<non-string panic>".into());
        let loc = info.location().map_or("<unknown>".into(), |l| {
            format!("{}:{}:{}", l.file(), l.line(), l.column())
        });
        // a panic inside the standard library (capacity overflow, an index out of bounds in a
        // slice method) is located by the first frame of articula's own code
        let bt = std::backtrace::Backtrace::force_capture().to_string();
        let ours = bt
            .lines()
            .map(str::trim)
            .filter_map(|l| l.strip_prefix("at "))
            .find(|l| l.contains("/src/") && !l.starts_with("/rustc/") && !l.contains("/.cargo/"))
            .map(str::to_string);
        let loc = match ours {
            Some(o) if !loc.contains(&o) => format!("{loc} (in {o})"),
            _ => loc,
        };
        *LAST_PANIC.lock().unwrap_or_else(|e| e.into_inner()) = Some((msg, loc, bt));
    }));
    let mut c = Counts::default();
    let mut saved_hangs = 0;
    let mut buf = Vec::new();
    for i in from..to {
        let input = input_of(a.seed, i, &seeds);
        buf.clear();
        buf.extend_from_slice(c.header(i).as_bytes());
        buf.extend_from_slice(&input);
        state.seek(SeekFrom::Start(0)).unwrap();
        state.write_all(&buf).unwrap();
        state.set_len(buf.len() as u64).unwrap();
        let t0 = Instant::now();
        let r = std::panic::catch_unwind(|| execute(&input));
        let dt = t0.elapsed();
        c.execs += 1;
        match r {
            Ok(Outcome::ParseError) => c.parse_err += 1,
            Ok(Outcome::PipelineError) => c.pipeline_err += 1,
            Ok(Outcome::Ok) => c.ok += 1,
            Err(_) => {
                c.panics += 1;
                let (msg, loc, bt) = LAST_PANIC
                    .lock()
                    .unwrap_or_else(|e| e.into_inner())
                    .take()
                    .unwrap_or_default();
                let key = format!("{}\n{loc}", digits_masked(&msg));
                let stem = findings.join(format!("panic-{:016x}", fnv(&key)));
                if let Ok(mut f) = std::fs::OpenOptions::new()
                    .write(true)
                    .create_new(true)
                    .open(stem.with_extension("txt"))
                {
                    std::fs::write(stem.with_extension("bvh"), &input).unwrap();
                    let _ = write!(
                        f,
                        "panic at {loc}\nmessage: {msg}\nseed {} execution {i}\n",
                        a.seed
                    );
                    let _ = std::fs::write(stem.with_extension("backtrace"), bt);
                }
            }
        }
        let ns = dt.as_nanos() as u64;
        if ns > c.slowest_ns {
            c.slowest_ns = ns;
            c.slowest_index = i;
        }
        if dt > HANG {
            c.hangs += 1;
            if saved_hangs < 20 {
                saved_hangs += 1;
                let stem = findings.join(format!("hang-{i}"));
                std::fs::write(stem.with_extension("bvh"), &input).unwrap();
                let _ = std::fs::write(
                    stem.with_extension("txt"),
                    format!(
                        "hang: {:.3} s (> {} s)\nseed {} execution {i}\n",
                        dt.as_secs_f64(),
                        HANG.as_secs(),
                        a.seed
                    ),
                );
            }
        }
    }
    buf.clear();
    buf.extend_from_slice(c.header(to).as_bytes());
    state.seek(SeekFrom::Start(0)).unwrap();
    state.write_all(&buf).unwrap();
    state.set_len(buf.len() as u64).unwrap();
}

// ---------------------------------------------------------------------------------------------
// Parent

struct Slot {
    child: Child,
    from: u64,
    to: u64,
    state: PathBuf,
    err: PathBuf,
}

fn spawn(a: &Args, dir: &Path, k: usize, from: u64, to: u64) -> Slot {
    let work = dir.join(".work");
    let state = work.join(format!("worker-{k}.state"));
    let err = work.join(format!("worker-{k}.stderr"));
    let _ = std::fs::remove_file(&state);
    let exe = std::env::current_exe().expect("current_exe");
    let mut args: Vec<String> = vec![
        "--worker".into(),
        format!("{from}..{to}"),
        "--seed".into(),
        a.seed.to_string(),
        "--findings".into(),
        dir.display().to_string(),
        "--state".into(),
        state.display().to_string(),
    ];
    if let Some(c) = &a.corpus {
        args.extend(["--corpus".into(), c.display().to_string()]);
    }
    // an address-space limit, so a huge allocation fails (and aborts the worker) instead of
    // taking the machine's memory
    let mut cmd = Command::new("sh");
    cmd.arg("-c")
        .arg(format!(
            "ulimit -v {} 2>/dev/null; exec \"$0\" \"$@\"",
            a.mem_mb * 1024
        ))
        .arg(exe)
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(std::fs::File::create(&err).expect("stderr file"));
    let child = cmd.spawn().expect("spawn worker");
    Slot {
        child,
        from,
        to,
        state,
        err,
    }
}

fn parse_args() -> Args {
    let mut a = Args {
        execs: 100_000,
        seed: 1,
        threads: std::thread::available_parallelism().map_or(1, |n| n.get()),
        corpus: None,
        findings: None,
        mem_mb: 4096,
        worker: None,
        state: None,
        replay: None,
        explain: false,
    };
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut it = args.iter();
    let usage = "usage: fuzz_takes [--execs N] [--seed S] [--threads T] [--corpus DIR] \
                 [--findings DIR] [--mem-mb M] | --replay FILE";
    while let Some(f) = it.next() {
        let mut val = || {
            it.next()
                .unwrap_or_else(|| panic!("{f} needs a value\n{usage}"))
                .clone()
        };
        match f.as_str() {
            "--execs" => a.execs = val().replace('_', "").parse().expect("--execs N"),
            "--seed" => a.seed = val().parse().expect("--seed S"),
            "--threads" => a.threads = val().parse::<usize>().expect("--threads T").max(1),
            "--corpus" => a.corpus = Some(val().into()),
            "--findings" => a.findings = Some(val().into()),
            "--mem-mb" => a.mem_mb = val().parse().expect("--mem-mb M"),
            "--state" => a.state = Some(val().into()),
            "--replay" => a.replay = Some(val().into()),
            "--explain-parse-errors" => a.explain = true,
            "--worker" => {
                let v = val();
                let (f, t) = v.split_once("..").expect("--worker FROM..TO");
                a.worker = Some((f.parse().unwrap(), t.parse().unwrap()));
            }
            "-h" | "--help" => {
                println!("{usage}");
                std::process::exit(0);
            }
            other => panic!("unknown argument {other}\n{usage}"),
        }
    }
    a
}

fn main() {
    let a = parse_args();
    if let Some((from, to)) = a.worker {
        worker(&a, from, to);
        return;
    }
    if a.explain {
        // why inputs stop at the reader: the commonest parse errors of the first --execs inputs
        let seeds = seeds(Path::new("."), a.corpus.as_deref());
        let mut why = std::collections::BTreeMap::<String, u64>::new();
        for i in 0..a.execs {
            if let Err(e) = bvh::parse_bytes(&input_of(a.seed, i, &seeds), Path::new("f")) {
                let m = digits_masked(&e.to_string());
                let m = m.split_once(": ").map_or(m.as_str(), |x| x.1);
                *why.entry(m.chars().take(70).collect()).or_default() += 1;
            }
        }
        let mut v: Vec<_> = why.into_iter().collect();
        v.sort_by_key(|x| std::cmp::Reverse(x.1));
        for (m, n) in v.iter().take(25) {
            println!("{n:8} {m}");
        }
        return;
    }
    if let Some(file) = &a.replay {
        let input = std::fs::read(file).expect("--replay FILE");
        let t0 = Instant::now();
        let o = execute(&input);
        println!("{o:?} in {:.3} s", t0.elapsed().as_secs_f64());
        return;
    }
    let stamp = SystemTime::now()
        .duration_since(SystemTime::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs());
    let dir = a
        .findings
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("fuzz-findings/{stamp}-seed{}", a.seed)));
    std::fs::create_dir_all(dir.join(".work")).expect("findings directory");
    let n_seeds = seeds(Path::new("."), a.corpus.as_deref()).len();
    println!(
        "fuzz_takes: {} executions, seed {}, {} worker(s), {n_seeds} seed inputs{}, findings in {}",
        a.execs,
        a.seed,
        a.threads,
        a.corpus
            .as_ref()
            .map_or(String::new(), |c| format!(" (corpus {})", c.display())),
        dir.display()
    );
    // chunks small enough to spread the work, large enough that start-up is negligible
    let chunk = (a.execs / (a.threads as u64 * 16)).clamp(1, 50_000);
    let mut queue: VecDeque<(u64, u64)> = (0..a.execs.div_ceil(chunk))
        .map(|c| (c * chunk, ((c + 1) * chunk).min(a.execs)))
        .collect();
    let mut slots: Vec<Option<Slot>> = (0..a.threads).map(|_| None).collect();
    let mut total = Counts::default();
    let mut aborts = vec![];
    let t0 = Instant::now();
    let mut last_print = Instant::now();
    loop {
        for (k, s) in slots.iter_mut().enumerate() {
            if s.is_none()
                && let Some((f, t)) = queue.pop_front()
            {
                *s = Some(spawn(&a, &dir, k, f, t));
            }
        }
        if slots.iter().all(|s| s.is_none()) {
            break;
        }
        let mut in_flight = 0;
        for s in slots.iter_mut() {
            let Some(slot) = s else { continue };
            let status = slot.child.try_wait().expect("wait");
            let stuck = status.is_none()
                && std::fs::metadata(&slot.state)
                    .and_then(|m| m.modified())
                    .is_ok_and(|m| m.elapsed().unwrap_or_default() > STUCK);
            if status.is_none() && !stuck {
                if let Some((_, c, _)) = std::fs::read(&slot.state)
                    .ok()
                    .and_then(|b| Counts::parse_state(&b))
                {
                    in_flight += c.execs;
                }
                continue;
            }
            let status = if stuck {
                let _ = slot.child.kill();
                slot.child.wait().expect("wait")
            } else {
                status.unwrap()
            };
            let bytes = std::fs::read(&slot.state).unwrap_or_default();
            let (next, c, input) =
                Counts::parse_state(&bytes).unwrap_or((slot.from, Counts::default(), vec![]));
            total.add(&c);
            if status.success() && next >= slot.to && !stuck {
                *s = None;
                continue;
            }
            // died (or stuck) on execution `next`
            total.execs += 1;
            let what = if stuck {
                total.hangs += 1;
                "hang (stuck)"
            } else {
                total.aborts += 1;
                "abort"
            };
            let stderr = std::fs::read_to_string(&slot.err).unwrap_or_default();
            let head: String = stderr.lines().take(3).collect::<Vec<_>>().join("\n");
            let stem = dir.join(format!("{}-{next}", what.split(' ').next().unwrap()));
            let _ = std::fs::write(stem.with_extension("bvh"), &input);
            let note = format!(
                "{what} on seed {} execution {next}: {status}\nstderr: {head}\n",
                a.seed
            );
            let _ = std::fs::write(stem.with_extension("txt"), &note);
            aborts.push(note);
            if next + 1 < slot.to {
                queue.push_front((next + 1, slot.to));
            }
            *s = None;
        }
        if last_print.elapsed() > Duration::from_secs(60) {
            last_print = Instant::now();
            let done = total.execs + in_flight;
            eprintln!(
                "[{:.0} s] {done} executions ({:.0}/s), {} panics, {} hangs, {} aborts",
                t0.elapsed().as_secs_f64(),
                done as f64 / t0.elapsed().as_secs_f64(),
                total.panics,
                total.hangs,
                total.aborts
            );
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let secs = t0.elapsed().as_secs_f64();
    let mut report = String::new();
    let _ = writeln!(report, "executions:        {}", total.execs);
    let _ = writeln!(report, "wall time:         {secs:.1} s");
    let _ = writeln!(
        report,
        "executions/s:      {:.0}",
        total.execs as f64 / secs
    );
    let _ = writeln!(report, "parse errors:      {}", total.parse_err);
    let _ = writeln!(report, "pipeline errors:   {}", total.pipeline_err);
    let _ = writeln!(report, "successes:         {}", total.ok);
    let _ = writeln!(report, "panics:            {}", total.panics);
    let _ = writeln!(report, "hangs (> 1 s):     {}", total.hangs);
    let _ = writeln!(report, "aborts:            {}", total.aborts);
    let _ = writeln!(
        report,
        "slowest execution: {:.1} ms (execution {})",
        total.slowest_ns as f64 / 1e6,
        total.slowest_index
    );
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map(|d| d.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    files.retain(|p| p.extension().is_some_and(|e| e == "txt"));
    files.sort();
    let _ = writeln!(
        report,
        "findings:          {} (in {})",
        files.len(),
        dir.display()
    );
    for f in &files {
        let _ = writeln!(
            report,
            "--- {}\n{}",
            f.with_extension("bvh").display(),
            std::fs::read_to_string(f).unwrap_or_default().trim_end()
        );
    }
    print!("{report}");
}
