//! The frame lines of a BVH file read fast: one pass over the bytes, each value written
//! straight into its slot of the take's `frames × channel_count` table (allocated once, from
//! the `Frames:` count), nothing allocated per value or per line.
//!
//! Numbers by Clinger's exact fast path on the digits just scanned (most capture values: at
//! most 19 digits, no exponent) or else by `fast-float2` (the same correctly rounded decimal
//! → `f64` algorithm as `str::parse`), so every value is bit-identical to
//! `str::parse::<f64>`. Under more than one rayon thread the lines are cut into chunks at
//! line ends, each chunk written into its own rows of the same table.
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
use std::mem::MaybeUninit;

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
    // each value takes at least two bytes ("0 "): a count the text cannot hold is not
    // allocated (the careful reader says the MOTION section is truncated)
    if channel_count == 0 || total > text.len() / 2 + 1 {
        return None;
    }
    // the table is not zeroed first: every slot is written once below (zeroing it cost a
    // pass over fresh pages, or a `memset` of reused ones)
    let mut motion = Vec::with_capacity(total);
    let mut decimals = Vec::with_capacity(total);
    let (m, d) = (
        &mut motion.spare_capacity_mut()[..total],
        &mut decimals.spare_capacity_mut()[..total],
    );
    let in_chunks = par::slots() > 1
        && text.len() >= MIN_PARALLEL_BYTES
        && chunks(text, channel_count, m, d, par::slots());
    if !in_chunks && rows(text, channel_count, m, d)? != frames {
        return None;
    }
    // SAFETY: every slot of the first `total` is written: by the chunks, each of which filled
    // exactly its rows, or by the serial reader, which filled `frames` rows of
    // `channel_count` values
    unsafe {
        motion.set_len(total);
        decimals.set_len(total);
    }
    Some((motion, decimals))
}

/// Reads `text` cut into up to `parts` chunks at line ends, in parallel, each into its own
/// rows of `motion` and `decimals`; the first row of a chunk is the count of `\n` before it.
/// True when every chunk filled exactly its rows (false at anything else, e.g. a blank line
/// or lone-CR line ends, where the line count is not the row count: the serial reader then
/// reads the whole text).
fn chunks(
    text: &[u8],
    channel_count: usize,
    motion: &mut [MaybeUninit<f64>],
    decimals: &mut [MaybeUninit<u8>],
    parts: usize,
) -> bool {
    // the text starts with the end of the `Frame Time:` line: not a row
    let first = text
        .iter()
        .position(|b| !matches!(b, b' ' | b'\t' | b'\r' | b'\n'))
        .unwrap_or(text.len());
    let chunks = split_after_newlines(&text[first..], parts);
    let newlines: Vec<usize> = chunks
        .par_iter()
        .map(|c| memchr::memchr_iter(b'\n', c).count())
        .collect();
    // each chunk's rows: its line count, the last one the rest
    let mut work = Vec::with_capacity(chunks.len());
    let (mut motion, mut decimals) = (motion, decimals);
    for (k, chunk) in chunks.iter().enumerate() {
        let n = if k + 1 == chunks.len() {
            motion.len() / channel_count
        } else {
            newlines[k]
        };
        let Some(len) = n.checked_mul(channel_count).filter(|&l| l <= motion.len()) else {
            return false;
        };
        let (m, m_rest) = motion.split_at_mut(len);
        let (d, d_rest) = decimals.split_at_mut(len);
        (motion, decimals) = (m_rest, d_rest);
        work.push((*chunk, n, m, d));
    }
    work.into_par_iter()
        .all(|(chunk, n, m, d)| rows(chunk, channel_count, m, d) == Some(n))
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

/// Reads every line of `text` into the rows of `motion` and `decimals` (`channel_count`
/// values each, in order): each line holds `channel_count` values or none (a blank line).
/// The number of value lines, every slot of their rows written; `None` at anything else or
/// at more lines than rows.
fn rows(
    text: &[u8],
    channel_count: usize,
    motion: &mut [MaybeUninit<f64>],
    decimals: &mut [MaybeUninit<u8>],
) -> Option<usize> {
    let mut i = 0;
    let mut frames = 0;
    let n = text.len();
    let mut rows = motion
        .chunks_exact_mut(channel_count)
        .zip(decimals.chunks_exact_mut(channel_count));
    loop {
        // blank lines and the blanks before the first value
        while i < n && matches!(text[i], b' ' | b'\t' | b'\r' | b'\n') {
            i += 1;
        }
        if i == n {
            return Some(frames);
        }
        let (values, places) = rows.next()?;
        i = line(text, i, values, places)?;
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

/// The values of the line whose first value starts at `text[i]`, into `values` and `places`
/// (one per slot, separated by spaces or tabs); the index just after the last one.
#[inline]
fn line(
    text: &[u8],
    mut i: usize,
    values: &mut [MaybeUninit<f64>],
    places: &mut [MaybeUninit<u8>],
) -> Option<usize> {
    for (c, (v, d)) in values.iter_mut().zip(places.iter_mut()).enumerate() {
        if c > 0 {
            // one space before a value, or a run of spaces and tabs (a line end or the end of
            // the text here is refused by the number scanners: no digit)
            if text.get(i) == Some(&b' ') && !matches!(text.get(i + 1), Some(b' ' | b'\t')) {
                i += 1;
            } else {
                let from = i;
                while matches!(text.get(i), Some(b' ' | b'\t')) {
                    i += 1;
                }
                if i == from {
                    return None;
                }
            }
        }
        let (value, decimals, end) = number(text, i)?;
        v.write(value);
        d.write(decimals);
        i = end;
    }
    Some(i)
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
            let (v, d) = read_both(t).unwrap_or_else(|| panic!("{t}"));
            assert_eq!(v.to_bits(), t.parse::<f64>().unwrap().to_bits(), "{t}");
            assert_eq!(d, super::super::decimals_of(t), "{t}");
        }
        for t in [
            "",
            "-",
            ".",
            "-.",
            "+",
            "e5",
            "1e",
            "1e+",
            "1x",
            "nan",
            "inf",
            "1e400",
            "--1",
            "1..2",
            "-+1",
            "1-",
            "12345678.12345678x",
            "0.5\x0b",
            "1,5",
        ] {
            assert!(read_both(t).is_none(), "{t}");
        }
    }

    /// `t` read by `number` at the end of a text and with a line end and blanks after it, as
    /// inside a take: both must agree on the value's bits, its decimals and where it ends.
    fn read_both(t: &str) -> Option<(f64, u8)> {
        let at_end = number(t.as_bytes(), 0);
        let inside = format!("{t}\n                  ");
        let bytes = inside.as_bytes();
        let read = number(bytes, 0);
        match (at_end, read) {
            (None, None) => None,
            (Some((v, d, e)), Some((w, c, f))) => {
                assert_eq!((v.to_bits(), d, e), (w.to_bits(), c, f), "{t}");
                assert_eq!(e, t.len(), "{t}");
                Some((v, d))
            }
            (a, b) => panic!("{t}: at the end {a:?}, inside {b:?}"),
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
            let (v, d) = read_both(&t).unwrap_or_else(|| panic!("{t}"));
            assert_eq!(v.to_bits(), t.parse::<f64>().unwrap().to_bits(), "{t}");
            assert_eq!(d, super::super::decimals_of(&t), "{t}");
        }
    }

    /// `n` slots holding `fill`, for the readers to write into.
    fn slots<T: Copy>(n: usize, fill: T) -> Vec<MaybeUninit<T>> {
        vec![MaybeUninit::new(fill); n]
    }

    /// The values of slots made by [`slots`].
    fn values<T: Copy>(slots: &[MaybeUninit<T>]) -> Vec<T> {
        // SAFETY: every slot was initialised when made
        slots.iter().map(|x| unsafe { x.assume_init() }).collect()
    }

    #[test]
    fn lines_need_exactly_the_channel_count() {
        let (mut motion, mut decimals) = (slots(9, f64::NAN), slots(9, 0));
        let text = b"1 2 3\r\n\n 4\t5 6 \r7 8 9";
        assert_eq!(rows(text, 3, &mut motion, &mut decimals), Some(3));
        assert_eq!(
            values(&motion),
            [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]
        );
        for bad in [
            &b"1 2\n3\n"[..],
            b"1 2 3 4\n",
            b"1 2 3\x0b\n",
            b"1 2,3\n",
            b"1 2 3\n4 5 6\n7 8 9\n1 2 3\n",
        ] {
            assert_eq!(rows(bad, 3, &mut slots(9, 0.0), &mut slots(9, 0)), None);
        }
    }

    /// The table `read` hands out has every slot written, though it is not zeroed first: a
    /// take's values come back as written, and a text that does not fill the declared rows is
    /// refused rather than handed out with unwritten slots.
    #[test]
    fn read_writes_every_slot_of_the_table() {
        let text = b"\n0 -1.5 2\n3 4 5e1\r\n6 7 -8\n";
        let (motion, decimals) = read(text, 3, 3).unwrap();
        assert_eq!(motion, [0.0, -1.5, 2.0, 3.0, 4.0, 50.0, 6.0, 7.0, -8.0]);
        assert_eq!(decimals, [0, 1, 0, 0, 0, SHORTEST, 0, 0, 0]);
        assert!(read(text, 4, 3).is_none());
        assert!(read(text, 2, 3).is_none());
    }

    /// Frame lines after the `Frame Time:` line's end are read in chunks (not left to the
    /// serial reader), into the same rows; a blank line between them sends them to it.
    #[test]
    fn chunks_fill_the_rows_the_serial_reader_fills() {
        let text: String = (0..40).map(|k| format!("\n{k} -{k}.5 {k}e1")).collect();
        let text = format!("{text}\n");
        let (mut serial, mut places) = (slots(120, f64::NAN), slots(120, 0));
        assert_eq!(rows(text.as_bytes(), 3, &mut serial, &mut places), Some(40));
        let serial = (values(&serial), values(&places));
        for parts in 2..6 {
            let (mut m, mut d) = (slots(120, f64::NAN), slots(120, 0));
            assert!(chunks(text.as_bytes(), 3, &mut m, &mut d, parts), "{parts}");
            assert_eq!((values(&m), values(&d)), serial);
        }
        let blank = text.replace("\n20 ", "\n\n20 ");
        let (mut m, mut d) = (slots(120, 0.0), slots(120, 0));
        assert!(!chunks(blank.as_bytes(), 3, &mut m, &mut d, 4));
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
