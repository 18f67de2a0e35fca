//! The one way articula prints a number for a file: the shortest decimal text that reads back
//! as the same `f64`, so a write → read round trip is exact to the bit (`93.9241`, `-0.0`,
//! `0.0000187007`, `1e-7`, `1e16`).
//!
//! The digits come from `zmij` (Zverovich 2025, Schubfach with a faster digit generation; the
//! crate serde_json prints its floats with), which prints the shortest digits exactly as Ryū
//! does (Adams 2018, *Ryū: fast float-to-string conversion*, PLDI) two to three times as fast:
//! the text of a minute take's torques took a sixth of `articula id`'s time with Ryū. Its text
//! is Ryū's but for a positive exponent, written `1e+16` where Ryū writes `1e16`; the `+` is
//! dropped here, so every file articula writes keeps the text it had when Ryū printed it (a
//! test compares the two on random bit patterns and every boundary of the notation).
//! Non-finite values are the caller's to refuse (files never hold them).

/// A reusable buffer that prints numbers by [`Shortest::format`].
#[derive(Default)]
pub struct Shortest {
    digits: zmij::Buffer,
    /// The text of a number with a positive exponent, its `+` dropped.
    unsigned: [u8; 32],
}

impl Shortest {
    pub fn new() -> Self {
        Self::default()
    }

    /// The shortest text of `x` that reads back as `x` (`1.0` for one, `-0.0` for negative
    /// zero, an exponent beyond 10¹⁶ and below 10⁻⁵: `1e16`, `1e-7`); the text stays valid
    /// until the next call.
    #[inline]
    pub fn format(&mut self, x: f64) -> &str {
        let Self { digits, unsigned } = self;
        let s = digits.format(x);
        // a `+` can only be the exponent's sign, among the last five bytes (`e+308`)
        let tail = s.len().saturating_sub(5);
        let Some(plus) = s.as_bytes()[tail..].iter().position(|&b| b == b'+') else {
            return s;
        };
        let (head, exponent) = s.split_at(tail + plus);
        let n = head.len() + exponent.len() - 1;
        unsigned[..head.len()].copy_from_slice(head.as_bytes());
        unsigned[head.len()..n].copy_from_slice(&exponent.as_bytes()[1..]);
        std::str::from_utf8(&unsigned[..n]).expect("ASCII digits")
    }

    /// [`Shortest::format`] without the `.0` of an integral value (`60`, `62.5`, `-0`), as
    /// hand-written files and labels write them.
    #[inline]
    pub fn format_plain(&mut self, x: f64) -> &str {
        let s = self.format(x);
        s.strip_suffix(".0").unwrap_or(s)
    }
}

/// [`Shortest::format`] of `x` as a new string.
pub fn shortest(x: f64) -> String {
    Shortest::new().format(x).to_string()
}

/// [`Shortest::format_plain`] of `x` as a new string.
pub fn plain(x: f64) -> String {
    Shortest::new().format_plain(x).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::samples::SplitMix64;

    /// Ryū's text for every kind of number: random bit patterns (every exponent), the
    /// notation's boundaries (10ᵏ and its neighbours), integers, subnormals and zeros.
    #[test]
    fn the_text_is_ryus_and_reads_back_exactly() {
        let mut rng = SplitMix64(17);
        let mut values: Vec<f64> = (0..200_000)
            .map(|_| f64::from_bits(rng.next_u64()))
            .filter(|x| x.is_finite())
            .collect();
        for k in -330..=310 {
            let p: f64 = format!("1e{k}").parse().unwrap();
            for x in [
                p,
                p.next_up(),
                p.next_down(),
                9.5 * p,
                -p,
                1.234_567_890_123_45 * p,
            ] {
                values.push(x);
            }
        }
        values.extend([
            0.0,
            -0.0,
            1.0,
            -1.0,
            0.5,
            123_456.0,
            f64::MAX,
            f64::MIN_POSITIVE,
        ]);
        values.extend([
            5e-324,
            -5e-324,
            2.225_073_858_507_201e-308,
            9_007_199_254_740_993.0,
        ]);
        let (mut ours, mut ryu) = (Shortest::new(), ryu::Buffer::new());
        for x in values.into_iter().filter(|x| x.is_finite()) {
            let text = ours.format(x);
            assert_eq!(text, ryu.format(x), "{:e} ({:#x})", x, x.to_bits());
            assert_eq!(
                text.parse::<f64>().unwrap().to_bits(),
                x.to_bits(),
                "{text}"
            );
        }
        for (x, text) in [(60.0, "60"), (62.5, "62.5"), (-0.0, "-0"), (1e16, "1e16")] {
            assert_eq!(plain(x), text);
        }
    }
}
