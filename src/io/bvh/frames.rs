//! The frame lines of a BVH file read fast: one pass over the bytes, no allocation per value
//! or per line, numbers by Clinger's exact fast path on the digits just scanned (most capture
//! values: at most 19 digits, no exponent) or else by `fast-float2` (the same correctly
//! rounded decimal → `f64` algorithm as `str::parse`), so every value is bit-identical; the
//! lines are cut into chunks read in parallel when the rayon pool has more than one thread.
//!
//! This reader only ever succeeds: it accepts the common form of frame lines (numbers of the
//! grammar below separated by spaces or tabs, lines ended by LF, CRLF or a lone CR, blank
//! lines between them) and gives up (`None`) at the first thing it does not expect. The
//! reader of `parse` then reads the whole file again, and reports what is wrong exactly as
//! it always has (file, line, column, what was expected) — so no error message depends on
//! this module.
//!
//! ```text
//! number = [+-]? digit* ("." digit*)? ([eE] [+-]? digit+)?    (at least one mantissa digit)
//! ```

use super::SHORTEST;
use crate::par;
use rayon::prelude::*;

/// Below this many bytes of frame lines the chunks are not worth a thread.
const MIN_PARALLEL_BYTES: usize = 1 << 18;

/// The values of `text`'s frame lines (everything after the `Frame Time:` line) and the
/// decimals each was written with ([`super::decimals_of`]), when `text` holds exactly
/// `frames` lines of `channel_count` values each in the common form; `None` otherwise.
pub(super) fn read(
    text: &[u8],
    frames: usize,
    channel_count: usize,
) -> Option<(Vec<f64>, Vec<u8>)> {
    let total = frames.checked_mul(channel_count)?;
    if channel_count == 0 {
        return None;
    }
    let slots = par::slots();
    if slots <= 1 || text.len() < MIN_PARALLEL_BYTES {
        let mut out = Values::with_capacity(total.min(text.len() / 2 + 1));
        let n = lines(text, channel_count, &mut out)?;
        return (n == frames).then_some((out.motion, out.decimals));
    }
    // chunks of about equal size, each ending just after a '\n'
    let chunks = split_after_newlines(text, slots);
    let read: Vec<Option<(usize, Values)>> = chunks
        .par_iter()
        .map(|chunk| {
            let mut out = Values::with_capacity(total.min(chunk.len() / 2 + 1));
            lines(chunk, channel_count, &mut out).map(|n| (n, out))
        })
        .collect();
    let mut count = 0;
    let mut all = Values::with_capacity(total.min(text.len() / 2 + 1));
    for part in read {
        let (n, values) = part?;
        count += n;
        all.motion.extend_from_slice(&values.motion);
        all.decimals.extend_from_slice(&values.decimals);
    }
    (count == frames).then_some((all.motion, all.decimals))
}

/// Values read so far and their decimals, in the same order.
struct Values {
    motion: Vec<f64>,
    decimals: Vec<u8>,
}

impl Values {
    fn with_capacity(n: usize) -> Self {
        Values {
            motion: Vec::with_capacity(n),
            decimals: Vec::with_capacity(n),
        }
    }
}

/// `text` cut into at most `parts` slices, each but the last ending just after a `\n`.
fn split_after_newlines(text: &[u8], parts: usize) -> Vec<&[u8]> {
    let mut out = Vec::with_capacity(parts);
    let mut start = 0;
    for p in 1..parts {
        let target = (text.len() * p / parts).max(start);
        let Some(nl) = memchr::memchr(b'\n', &text[target..]) else {
            break;
        };
        let end = target + nl + 1;
        out.push(&text[start..end]);
        start = end;
    }
    out.push(&text[start..]);
    out
}

/// Reads every line of `text` into `out`: each holds `channel_count` values or none (a blank
/// line). The number of value lines; `None` at anything else.
fn lines(text: &[u8], channel_count: usize, out: &mut Values) -> Option<usize> {
    let mut i = 0;
    let mut frames = 0;
    let n = text.len();
    loop {
        // blank lines and the blanks before the first value
        while i < n && matches!(text[i], b' ' | b'\t' | b'\r' | b'\n') {
            i += 1;
        }
        if i == n {
            return Some(frames);
        }
        for c in 0..channel_count {
            if c > 0 {
                // a value ends at a blank; the next one is on the same line
                let before = i;
                while i < n && matches!(text[i], b' ' | b'\t') {
                    i += 1;
                }
                if i == before || i == n || matches!(text[i], b'\r' | b'\n') {
                    return None;
                }
            }
            let (v, d, end) = number(text, i)?;
            out.motion.push(v);
            out.decimals.push(d);
            i = end;
        }
        // the line ends after its last value (trailing blanks allowed)
        while i < n && matches!(text[i], b' ' | b'\t') {
            i += 1;
        }
        if i < n && !matches!(text[i], b'\r' | b'\n') {
            return None;
        }
        frames += 1;
    }
}

/// The number starting at `text[i]`: its finite value, its decimals ([`super::decimals_of`])
/// and the index just after it, which is a blank, a line end or the end of `text`.
#[inline]
fn number(text: &[u8], i: usize) -> Option<(f64, u8, usize)> {
    let n = text.len();
    let start = i;
    let mut i = i;
    if i < n && matches!(text[i], b'+' | b'-') {
        i += 1;
    }
    // the digits, also as one integer (exact while there are at most 19 of them)
    let mut mantissa: u64 = 0;
    let int_start = i;
    while i < n && text[i].is_ascii_digit() {
        mantissa = mantissa
            .wrapping_mul(10)
            .wrapping_add(u64::from(text[i] - b'0'));
        i += 1;
    }
    let mut digits = i - int_start;
    let mut decimals = 0;
    if i < n && text[i] == b'.' {
        i += 1;
        let frac_start = i;
        while i < n && text[i].is_ascii_digit() {
            mantissa = mantissa
                .wrapping_mul(10)
                .wrapping_add(u64::from(text[i] - b'0'));
            i += 1;
        }
        decimals = i - frac_start;
        digits += decimals;
    }
    if digits == 0 {
        return None;
    }
    let mut exponent = false;
    if i < n && matches!(text[i], b'e' | b'E') {
        exponent = true;
        i += 1;
        if i < n && matches!(text[i], b'+' | b'-') {
            i += 1;
        }
        let exp_start = i;
        while i < n && text[i].is_ascii_digit() {
            i += 1;
        }
        if i == exp_start {
            return None;
        }
    }
    if i < n && !matches!(text[i], b' ' | b'\t' | b'\r' | b'\n') {
        return None;
    }
    // Clinger's fast path: an integer below 2^53 and a power of ten up to 10^22 are exact
    // doubles, so their quotient, rounded once by the division, is the correctly rounded
    // value, as `str::parse` and fast-float2 give it (they take the same path); every
    // other number goes to fast-float2
    let v = if !exponent && digits <= 19 && mantissa <= 1 << 53 && decimals <= 22 {
        let m = mantissa as f64 / POW10[decimals];
        if text[start] == b'-' { -m } else { m }
    } else {
        let v: f64 = fast_float2::parse(&text[start..i]).ok()?;
        if !v.is_finite() {
            return None;
        }
        v
    };
    let d = if exponent || decimals > 17 {
        SHORTEST
    } else {
        decimals as u8
    };
    Some((v, d, i))
}

/// 10^0 … 10^22, every one an exact double.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

#[cfg(test)]
mod tests {
    use super::*;

    /// Every token the grammar accepts reads as `str::parse` reads it, bit for bit, with the
    /// decimals `decimals_of` gives; every other token is refused.
    #[test]
    fn numbers_are_std_parse_bit_for_bit() {
        for t in [
            "0",
            "-0",
            "+0",
            "7",
            "-12.50",
            ".5",
            "-.5",
            "5.",
            "1e5",
            "1E-5",
            "1.5e+05",
            "-0.000001",
            "123456789.123456789",
            "0.1234567890123456789",
            "1e-400",
            "179.99999999999997",
            "2.2250738585072014e-308",
            "9007199254740993",
            "9007199254740992",
            "0.9007199254740993",
            "-1234567890123456789",
            "12345678901234567890",
            "0.00000000000000000000001",
            "-0.0000000000000000000000001",
            "33.333333333333336",
            "0.1",
            "0.3",
            "-96.4418",
            "1.7976931348623157e308",
        ] {
            let (v, d, end) = number(t.as_bytes(), 0).unwrap_or_else(|| panic!("{t}"));
            assert_eq!(end, t.len(), "{t}");
            assert_eq!(v.to_bits(), t.parse::<f64>().unwrap().to_bits(), "{t}");
            assert_eq!(d, super::super::decimals_of(t), "{t}");
        }
        for t in [
            "", "-", ".", "e5", "1e", "1e+", "1x", "nan", "inf", "1e400", "--1", "1..2",
        ] {
            assert!(number(t.as_bytes(), 0).is_none(), "{t}");
        }
    }

    /// Many random decimals of 1–20 digits with 0–20 of them after the point, as captures
    /// write them: the same bits as `str::parse`.
    #[test]
    fn random_decimals_are_std_parse_bit_for_bit() {
        let mut state: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        for _ in 0..200_000 {
            let digits = 1 + (next() % 20) as usize;
            let point = (next() % (digits as u64 + 1)) as usize;
            let mut t = String::new();
            if next() % 2 == 0 {
                t.push('-');
            }
            for k in 0..digits {
                if k == point && k > 0 {
                    t.push('.');
                }
                t.push(char::from(b'0' + (next() % 10) as u8));
            }
            let (v, _, end) = number(t.as_bytes(), 0).unwrap_or_else(|| panic!("{t}"));
            assert_eq!(end, t.len(), "{t}");
            assert_eq!(v.to_bits(), t.parse::<f64>().unwrap().to_bits(), "{t}");
        }
    }

    #[test]
    fn lines_need_exactly_the_channel_count() {
        let mut out = Values::with_capacity(0);
        let text = b"1 2 3\r\n\n 4\t5 6 \r7 8 9";
        assert_eq!(lines(text, 3, &mut out), Some(3));
        assert_eq!(out.motion, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]);
        for bad in [&b"1 2\n3\n"[..], b"1 2 3 4\n", b"1 2 3\x0b\n", b"1 2,3\n"] {
            assert_eq!(lines(bad, 3, &mut Values::with_capacity(0)), None);
        }
    }

    #[test]
    fn chunks_end_after_newlines_and_cover_the_text() {
        let text = b"1 2\n3 4\r\n5 6\n7 8";
        for parts in 1..6 {
            let chunks = split_after_newlines(text, parts);
            assert_eq!(chunks.concat(), text);
            for c in &chunks[..chunks.len() - 1] {
                assert_eq!(c.last(), Some(&b'\n'));
            }
        }
    }
}
