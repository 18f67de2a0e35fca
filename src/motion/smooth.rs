//! Smoothing of joint trajectories: the paper's Gaussian kernel, a zero-lag Butterworth
//! low-pass, or nothing. Accelerations of raw capture are noise; these filters are how the
//! user trades smoothness against fidelity (`--smooth gaussian:0.02`, `--smooth
//! butterworth:6hz`, `--smooth none`).
//!
//! Both filters are linear and zero-phase, so a trajectory is never delayed. Their magnitude
//! responses (the gain applied to a sinusoid of frequency `f`; `fs = 1/dt`):
//!
//! - **Gaussian** of width `σ` (seconds), weights `wₖ ∝ exp(−(k·dt)²/2σ²)` for
//!   `|k·dt| ≤ 4σ`, normalised to sum to one. Its response is that of the continuous kernel,
//!   `G(f) = exp(−2π²σ²f²)` (the Fourier transform of a unit-area Gaussian), within 0.1 % for
//!   `σ ≥ dt`; the exact response of the sampled kernel is [`Smoother::gain`]. The −3 dB point is
//!   `f₋₃ = √(ln 2) / (2πσ) ≈ 0.1325/σ`: 6.6 Hz for σ = 0.02 s, 2.65 Hz for σ = 0.05 s.
//! - **Butterworth** of order `N` and cutoff `fc`, run forward then backward (Winter 2009,
//!   *Biomechanics and Motor Control of Human Movement*, 4th ed., §3.4.4). One pass of the
//!   digital filter made by the bilinear transform has `|H|² = 1/(1 + (Ω/Ωc)^{2N})` with
//!   `Ω = tan(π f dt)`; two passes square it, so the zero-lag response is
//!   `|H(f)| = 1/(1 + (Ω/Ωc)^{2N})`. The double pass would pull the −3 dB point below `fc`;
//!   Winter's correction (§3.4.4) designs each pass at `Ωc = tan(π fc dt) / C` with
//!   `C = (√2 − 1)^{1/(2N)}` (`C = 0.802` for N = 2, Winter's factor for two passes), which
//!   puts the −3 dB point of the zero-lag filter exactly at `fc`: `|H(fc)| = 1/√2`. Well above
//!   `fc` the gain falls as `(f/fc)^{−2N}`, 12·N dB per octave.
//! - **None**: gain 1 everywhere.
//!
//! Ends of the take: both filters need samples beyond the ends. The signal is extended by odd
//! (point) reflection about each end sample, `x(−k) = 2x(0) − x(k)` (the padding of
//! Smith 1989, *J. Biomech.* 22(8-9), "Padding point extrapolation techniques for the
//! Butterworth digital filter", and of SciPy's `filtfilt`), the one that keeps the Gaussian exact on straight lines: a constant and a ramp come out
//! unchanged up to the last frame (a renormalised truncated kernel would bend a ramp toward its
//! interior mean, zero padding would droop toward zero). The IIR passes start from the steady
//! state of the first padded sample and the padding is long enough for what is left of the
//! start-up transient to decay below 1e-12 of the signal before it reaches the data.
//!
//! Quaternions (ball joints) are smoothed as a hemisphere-consistent curve in ℝ⁴ and
//! renormalised: for the Gaussian this is the weighted chordal mean of the rotations in the
//! window (Markley et al. 2007, *J. Guidance* 30(4), "Averaging Quaternions", the
//! normalised-sum approximation for nearby rotations). The ends are padded by geodesic point
//! reflection, `q(−k) = q(0) · q(k)⁻¹ · q(0)`, the rotation analogue of odd reflection. A
//! rotation at constant rate about a fixed axis has components that are sinusoids of one
//! frequency, all scaled by the same gain, so it passes through unchanged after normalisation.

use crate::error::Error;
use nalgebra::{Quaternion, UnitQuaternion};
use std::fmt;
use std::str::FromStr;

/// Which smoothing to apply, with its parameter in physical units.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum SmoothSpec {
    /// No smoothing.
    #[default]
    None,
    /// Gaussian kernel of standard deviation `sigma_s` (s), the paper's width `p`.
    Gaussian { sigma_s: f64 },
    /// Zero-lag Butterworth low-pass: −3 dB at `cutoff_hz` (Hz) after the forward-backward
    /// pass; `order` is the order of each pass (2 in Winter's biomechanics practice).
    Butterworth { cutoff_hz: f64, order: usize },
}

/// The order used when `butterworth:6hz` gives none (Winter 2009 §3.4.4: a second-order filter
/// run twice).
pub const DEFAULT_BUTTERWORTH_ORDER: usize = 2;

const SYNTAX: &str = "expected `none`, `gaussian:SIGMA` (seconds, e.g. `gaussian:0.02`, \
                      `gaussian:20ms`) or `butterworth:CUTOFF` (Hz, e.g. `butterworth:6hz`, \
                      `butterworth:6hz:4` for a 4th-order pass)";

impl FromStr for SmoothSpec {
    type Err = Error;

    fn from_str(s: &str) -> Result<Self, Error> {
        let bad = |why: &str| Error::Invalid(format!("smoothing `{s}`: {why}; {SYNTAX}"));
        let t = s.trim().to_ascii_lowercase();
        let mut parts = t.split(':');
        let kind = parts.next().unwrap_or("");
        let spec = match kind {
            "none" => SmoothSpec::None,
            "gaussian" => {
                let p = parts.next().ok_or_else(|| bad("missing the width"))?;
                let (num, scale) = if let Some(ms) = p.strip_suffix("ms") {
                    (ms, 1e-3)
                } else {
                    (p.strip_suffix('s').unwrap_or(p), 1.0)
                };
                let v: f64 = num
                    .trim()
                    .parse()
                    .map_err(|_| bad(&format!("`{p}` is not a number")))?;
                SmoothSpec::Gaussian { sigma_s: v * scale }
            }
            "butterworth" => {
                let p = parts.next().ok_or_else(|| bad("missing the cutoff"))?;
                let num = p.strip_suffix("hz").unwrap_or(p);
                let cutoff_hz: f64 = num
                    .trim()
                    .parse()
                    .map_err(|_| bad(&format!("`{p}` is not a frequency")))?;
                let order = match parts.next() {
                    None => DEFAULT_BUTTERWORTH_ORDER,
                    Some(o) => o
                        .trim()
                        .parse()
                        .map_err(|_| bad(&format!("order `{o}` is not a whole number")))?,
                };
                SmoothSpec::Butterworth { cutoff_hz, order }
            }
            _ => return Err(bad(&format!("unknown method `{kind}`"))),
        };
        if parts.next().is_some() {
            return Err(bad("too many `:` fields"));
        }
        spec.validate().map_err(|e| bad(&e))?;
        Ok(spec)
    }
}

impl fmt::Display for SmoothSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            SmoothSpec::None => write!(f, "none"),
            SmoothSpec::Gaussian { sigma_s } => write!(f, "gaussian:{sigma_s}"),
            SmoothSpec::Butterworth { cutoff_hz, order } if order == DEFAULT_BUTTERWORTH_ORDER => {
                write!(f, "butterworth:{cutoff_hz}hz")
            }
            SmoothSpec::Butterworth { cutoff_hz, order } => {
                write!(f, "butterworth:{cutoff_hz}hz:{order}")
            }
        }
    }
}

impl SmoothSpec {
    /// Checks the parameter alone (positive, finite, order 1–8).
    fn validate(&self) -> Result<(), String> {
        match *self {
            SmoothSpec::None => Ok(()),
            SmoothSpec::Gaussian { sigma_s } if !(sigma_s > 0.0 && sigma_s.is_finite()) => Err(
                format!("the Gaussian width must be a positive number of seconds, not {sigma_s}"),
            ),
            SmoothSpec::Butterworth { cutoff_hz, .. }
                if !(cutoff_hz > 0.0 && cutoff_hz.is_finite()) =>
            {
                Err(format!(
                    "the Butterworth cutoff must be a positive frequency in Hz, not {cutoff_hz}"
                ))
            }
            SmoothSpec::Butterworth { order, .. } if !(1..=8).contains(&order) => Err(format!(
                "the Butterworth order must be between 1 and 8, not {order}"
            )),
            _ => Ok(()),
        }
    }

    /// The frequency (Hz) where the gain is 1/√2 (−3 dB): `√(ln 2)/(2πσ)` for the Gaussian,
    /// the cutoff for the Butterworth, `None` for no smoothing.
    pub fn minus3db_hz(&self) -> Option<f64> {
        match *self {
            SmoothSpec::None => None,
            SmoothSpec::Gaussian { sigma_s } => {
                Some(std::f64::consts::LN_2.sqrt() / (2.0 * std::f64::consts::PI * sigma_s))
            }
            SmoothSpec::Butterworth { cutoff_hz, .. } => Some(cutoff_hz),
        }
    }
}

/// One second-order (or first-order, `b2 = a2 = 0`) section, normalised so `a0 = 1`, run in
/// direct form II transposed.
#[derive(Debug, Clone, Copy)]
struct Section {
    b: [f64; 3],
    a: [f64; 3],
}

impl Section {
    /// Filters `x` in place, forward, starting from the steady state of a constant `x[0]`.
    fn run_forward(&self, x: &mut [f64]) {
        self.run(x.as_chunks_mut::<1>().0, false);
    }
    /// Same, backward in time.
    fn run_backward(&self, x: &mut [f64]) {
        self.run(x.as_chunks_mut::<1>().0, true);
    }
    /// Filters `L` signals side by side (sample `k` of signal `l` is `x[k][l]`), forward or
    /// backward in time, each starting from the steady state of a constant first sample: per
    /// signal the very operations of one signal alone, so the same bits, with `L` independent
    /// recurrences for the processor to overlap.
    fn run<const L: usize>(&self, x: &mut [[f64; L]], backward: bool) {
        let [b0, b1, b2] = self.b;
        let [_, a1, a2] = self.a;
        let Some(&x0) = (if backward { x.last() } else { x.first() }) else {
            return;
        };
        // steady state for a constant input (DC gain 1): z2 = (b2 − a2)x0, z1 = (b1 − a1)x0 + z2
        let mut z2 = x0.map(|u| (b2 - a2) * u);
        let mut z1 = [0.0; L];
        for l in 0..L {
            z1[l] = (b1 - a1) * x0[l] + z2[l];
        }
        let mut step = |xi: &mut [f64; L]| {
            for l in 0..L {
                let u = xi[l];
                let y = b0 * u + z1[l];
                z1[l] = b1 * u - a1 * y + z2[l];
                z2[l] = b2 * u - a2 * y;
                xi[l] = y;
            }
        };
        if backward {
            x.iter_mut().rev().for_each(&mut step);
        } else {
            x.iter_mut().for_each(&mut step);
        }
    }
}

/// How many columns [`Smoother::smooth_side_by_side`] filters at once.
const LANES: usize = 4;

/// The filter a spec becomes once the frame time is known.
#[derive(Debug, Clone)]
enum Method {
    None,
    /// Symmetric FIR: `kernel[k]` is the weight of offsets ±k; the weights sum to one.
    Fir {
        kernel: Vec<f64>,
    },
    /// Cascade of sections run forward then backward; `omega_c` is the prewarped design
    /// frequency `Ωc` of each pass, `order` its order.
    Iir {
        sections: Vec<Section>,
        omega_c: f64,
        order: usize,
    },
}

/// A smoothing filter for one frame time, owning its kernel and work buffers: after the first
/// call on the longest trajectory (or [`Smoother::reserve`]), smoothing allocates nothing.
#[derive(Debug, Clone)]
pub struct Smoother {
    spec: SmoothSpec,
    /// Frame time (s).
    dt: f64,
    method: Method,
    /// Samples of padding at each end (the FIR half-width, or the IIR settling length).
    pad: usize,
    /// Padded scalar signal, `n + 2·pad`, written by `smooth` / `smooth_quaternions`.
    buf: Vec<f64>,
    /// Padded quaternion trajectory, hemisphere-aligned, written by `smooth_quaternions`.
    qbuf: Vec<UnitQuaternion<f64>>,
    /// Smoothed quaternion components `[w, x, y, z]` (`n`), written by the Gaussian's
    /// `smooth_quaternions`.
    comp: Vec<[f64; LANES]>,
    /// Padded signals side by side (`n + 2·pad` samples of [`LANES`]), written by
    /// `smooth_side_by_side`.
    lanes: Vec<[f64; LANES]>,
}

impl Smoother {
    /// A smoother for trajectories sampled every `dt` seconds. Fails when the parameter does
    /// not fit the sampling (a Butterworth cutoff at or above the Nyquist frequency `1/(2dt)`).
    pub fn new(spec: SmoothSpec, dt: f64) -> Result<Self, Error> {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(Error::Invalid(format!(
                "smoothing needs a positive frame time, not {dt} s"
            )));
        }
        spec.validate()
            .map_err(|e| Error::Invalid(format!("smoothing `{spec}`: {e}")))?;
        let (method, pad) = match spec {
            SmoothSpec::None => (Method::None, 0),
            SmoothSpec::Gaussian { sigma_s } => {
                check_span(spec, dt, (4.0 * sigma_s / dt).ceil())?;
                let kernel = gaussian_kernel(sigma_s, dt);
                let pad = kernel.len() - 1;
                (Method::Fir { kernel }, pad)
            }
            SmoothSpec::Butterworth { cutoff_hz, order } => {
                let nyquist = 0.5 / dt;
                if cutoff_hz >= nyquist {
                    return Err(Error::Invalid(format!(
                        "smoothing `{spec}`: the cutoff {cutoff_hz} Hz is not below the Nyquist \
                         frequency {nyquist} Hz of a take sampled every {dt} s; choose a lower \
                         cutoff"
                    )));
                }
                let (sections, omega_c) = butterworth_sections(cutoff_hz, order, dt);
                // pad until the start-up transient has decayed by e⁻²⁸ (≈ 1e-12): the least
                // damped pole pair decays at 2π·fc·sin(π/2N) (the analog prototype)
                let decay = 2.0
                    * std::f64::consts::PI
                    * cutoff_hz
                    * (std::f64::consts::PI / (2.0 * order as f64)).sin();
                let settle = (28.0 / (decay * dt)).ceil();
                check_span(spec, dt, settle)?;
                let pad = settle as usize + 2;
                (
                    Method::Iir {
                        sections,
                        omega_c,
                        order,
                    },
                    pad,
                )
            }
        };
        Ok(Self {
            spec,
            dt,
            method,
            pad,
            buf: Vec::new(),
            qbuf: Vec::new(),
            comp: Vec::new(),
            lanes: Vec::new(),
        })
    }

    /// The spec this smoother was made from.
    pub fn spec(&self) -> SmoothSpec {
        self.spec
    }

    /// Frame time (s).
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// How many frames to each side of a frame the filter reaches (the Gaussian's half-width,
    /// the Butterworth's settling length; 0 without smoothing).
    pub fn reach(&self) -> usize {
        self.pad
    }

    /// Allocates the work buffers for trajectories of up to `frames` samples.
    pub fn reserve(&mut self, frames: usize) {
        let len = frames + 2 * self.pad;
        self.buf.reserve(len.saturating_sub(self.buf.len()));
        self.qbuf.reserve(len.saturating_sub(self.qbuf.len()));
        self.comp.reserve(frames.saturating_sub(self.comp.len()));
        self.lanes.reserve(len.saturating_sub(self.lanes.len()));
    }

    /// The exact magnitude response of this discrete filter at `f_hz` (the gain it applies to a
    /// sinusoid far from the ends): `Σ wₖ cos(2πf k dt)` for the Gaussian kernel,
    /// `1/(1 + (tan(πf dt)/Ωc)^{2N})` for the forward-backward Butterworth, 1 for none.
    pub fn gain(&self, f_hz: f64) -> f64 {
        match &self.method {
            Method::None => 1.0,
            Method::Fir { kernel } => {
                let w = 2.0 * std::f64::consts::PI * f_hz * self.dt;
                kernel[0]
                    + 2.0
                        * kernel[1..]
                            .iter()
                            .enumerate()
                            .map(|(k, wk)| wk * (w * (k + 1) as f64).cos())
                            .sum::<f64>()
            }
            Method::Iir { omega_c, order, .. } => {
                let r = (std::f64::consts::PI * f_hz * self.dt).tan() / omega_c;
                1.0 / (1.0 + r.powi(2 * *order as i32))
            }
        }
    }

    /// Smooths one scalar trajectory in place (an angle in rad or degrees, a position in m:
    /// the filter is linear, units pass through). Angles must be continuous first
    /// (see `unwrap`). Allocates nothing once the buffers are large enough.
    pub fn smooth(&mut self, x: &mut [f64]) {
        let n = x.len();
        if n < 2 || matches!(self.method, Method::None) {
            return;
        }
        let p = self.pad;
        self.buf.clear();
        pad_odd(x, p, &mut self.buf);
        filter_padded(&self.method, p, &mut self.buf, x);
    }

    /// Smooths the columns of `cols` (`n` samples each, one after the other) in place: what
    /// [`Smoother::smooth`] gives each, bit for bit. The Butterworth filters up to [`LANES`]
    /// columns at once, side by side (its recurrence is a chain of dependent multiplications
    /// and additions per sample: several columns keep the processor busy while one waits);
    /// the Gaussian goes column by column. Allocates nothing once the buffers are large enough.
    pub fn smooth_side_by_side(&mut self, cols: &mut [f64], n: usize) {
        if n < 2 || !matches!(self.method, Method::Iir { .. }) {
            for c in cols.chunks_mut(n.max(1)) {
                self.smooth(c);
            }
            return;
        }
        let p = self.pad;
        let Method::Iir { sections, .. } = &self.method else {
            return;
        };
        for group in cols.chunks_mut(LANES * n) {
            // the padded signals side by side (lanes past the group's columns stay zero)
            self.lanes.clear();
            self.lanes.resize(n + 2 * p, [0.0; LANES]);
            for (l, x) in group.chunks(n).enumerate() {
                self.buf.clear();
                pad_odd(x, p, &mut self.buf);
                for (dst, v) in self.lanes.iter_mut().zip(&self.buf) {
                    dst[l] = *v;
                }
            }
            // forward pass through the cascade, then backward, as `filter_padded`
            for s in sections {
                s.run(&mut self.lanes, false);
            }
            for s in sections {
                s.run(&mut self.lanes, true);
            }
            for (l, x) in group.chunks_mut(n).enumerate() {
                for (o, v) in x.iter_mut().zip(&self.lanes[p..p + n]) {
                    *o = v[l];
                }
            }
        }
    }

    /// Smooths a ball-joint trajectory in place: components of the hemisphere-aligned
    /// quaternions are filtered like [`Smoother::smooth`] and renormalised (see the module
    /// doc). The output has unit norm and consecutive quaternions in the same hemisphere
    /// (`q[k]·q[k+1] ≥ 0`).
    pub fn smooth_quaternions(&mut self, q: &mut [UnitQuaternion<f64>]) {
        let n = q.len();
        if n == 0 {
            return;
        }
        align_hemispheres(q);
        if n < 2 || matches!(self.method, Method::None) {
            return;
        }
        let p = self.pad;
        self.qbuf.clear();
        let mut powers = None;
        self.qbuf.extend(
            (0..n + 2 * p)
                .map(|i| geodesic_extension_cached(q, i as isize - p as isize, &mut powers)),
        );
        align_hemispheres(&mut self.qbuf);
        // the centre must keep the sign of the aligned input
        if self.qbuf[p].coords.dot(&q[0].coords) < 0.0 {
            self.qbuf.iter_mut().for_each(|r| *r = negate(r));
        }
        // the four components side by side, each filtered by the very operations of
        // `filter_padded` on it alone (the same bits)
        self.lanes.clear();
        self.lanes
            .extend(self.qbuf.iter().map(|r| [r.w, r.i, r.j, r.k]));
        let smoothed: &[[f64; LANES]] = match &self.method {
            Method::None => return,
            Method::Fir { kernel } => {
                self.comp.clear();
                self.comp.extend((0..n).map(|i| {
                    let c = i + p;
                    let mut acc = self.lanes[c].map(|x| kernel[0] * x);
                    for (k, wk) in kernel.iter().enumerate().skip(1) {
                        let (before, after) = (self.lanes[c - k], self.lanes[c + k]);
                        for l in 0..LANES {
                            acc[l] += wk * (before[l] + after[l]);
                        }
                    }
                    acc
                }));
                &self.comp
            }
            Method::Iir { sections, .. } => {
                for s in sections {
                    s.run(&mut self.lanes, false);
                }
                for s in sections {
                    s.run(&mut self.lanes, true);
                }
                &self.lanes[p..p + n]
            }
        };
        for (qk, c) in q.iter_mut().zip(smoothed) {
            let raw = Quaternion::new(c[0], c[1], c[2], c[3]);
            // a zero mean would need rotations half a turn apart inside one window
            if raw.norm() > 1e-9 {
                *qk = UnitQuaternion::new_normalize(raw);
            }
        }
    }
}

/// Smooths every column (one coordinate each, sampled every `dt` s) in place.
pub fn smooth_columns(spec: SmoothSpec, dt: f64, columns: &mut [Vec<f64>]) -> Result<(), Error> {
    let mut s = Smoother::new(spec, dt)?;
    for c in columns.iter_mut() {
        s.smooth(c);
    }
    Ok(())
}

/// Smooths a ball-joint trajectory (sampled every `dt` s) in place; see
/// [`Smoother::smooth_quaternions`].
pub fn smooth_quaternions(
    spec: SmoothSpec,
    dt: f64,
    q: &mut [UnitQuaternion<f64>],
) -> Result<(), Error> {
    Smoother::new(spec, dt)?.smooth_quaternions(q);
    Ok(())
}

/// Flips signs so that consecutive quaternions lie in the same hemisphere (`q[k]·q[k−1] ≥ 0`);
/// `q` and `−q` are the same rotation, so only the representation changes.
pub fn align_hemispheres(q: &mut [UnitQuaternion<f64>]) {
    for k in 1..q.len() {
        if q[k].coords.dot(&q[k - 1].coords) < 0.0 {
            q[k] = negate(&q[k]);
        }
    }
}

fn negate(q: &UnitQuaternion<f64>) -> UnitQuaternion<f64> {
    UnitQuaternion::new_unchecked(-q.into_inner())
}

/// The most samples a filter may reach on each side of a sample (the Gaussian's half-width, the
/// Butterworth's settling length): 20,000 frames, 80 times what 6 Hz needs at 240 fps and
/// twice what it needs at 10 kHz. A
/// frame time so short that the filter would reach further (`Frame Time: 1e-7`) would cost
/// memory and time out of all proportion to the take, so it is refused with what to change.
pub const MAX_FILTER_SPAN: f64 = 20_000.0;

fn check_span(spec: SmoothSpec, dt: f64, samples: f64) -> Result<(), Error> {
    if samples <= MAX_FILTER_SPAN {
        return Ok(());
    }
    Err(Error::Invalid(format!(
        "smoothing `{spec}` on a take sampled every {dt} s would reach {samples:.0} frames to \
         each side of every frame (at most {MAX_FILTER_SPAN:.0}): check the file's Frame Time, \
         or choose a higher cutoff, a narrower kernel or none"
    )))
}

/// The normalised Gaussian kernel `kernel[k] ∝ exp(−(k dt)²/2σ²)`, `0 ≤ k ≤ ⌈4σ/dt⌉`, with
/// `kernel[0] + 2 Σ_{k≥1} kernel[k] = 1`.
fn gaussian_kernel(sigma_s: f64, dt: f64) -> Vec<f64> {
    let h = (4.0 * sigma_s / dt).ceil().max(1.0) as usize;
    let mut w: Vec<f64> = (0..=h)
        .map(|k| {
            let t = k as f64 * dt;
            (-t * t / (2.0 * sigma_s * sigma_s)).exp()
        })
        .collect();
    let sum = w[0] + 2.0 * w[1..].iter().sum::<f64>();
    w.iter_mut().for_each(|x| *x /= sum);
    w
}

/// The sections of one pass of an order-`order` digital Butterworth low-pass whose
/// forward-backward application has its −3 dB point at `cutoff_hz`, and the prewarped design
/// frequency `Ωc` (Winter 2009 §3.4.4 correction; bilinear transform `s = (1 − z⁻¹)/(1 +
/// z⁻¹)` with prewarping, Oppenheim & Schafer, *Discrete-Time Signal Processing*, 3rd ed.,
/// §7.2.2).
fn butterworth_sections(cutoff_hz: f64, order: usize, dt: f64) -> (Vec<Section>, f64) {
    use std::f64::consts::{PI, SQRT_2};
    // correction for the double pass: |H(fc)|² per pass must be 1/√2
    let c = (SQRT_2 - 1.0).powf(1.0 / (2.0 * order as f64));
    let w = (PI * cutoff_hz * dt).tan() / c;
    let mut sections = Vec::with_capacity(order.div_ceil(2));
    // analog prototype: pole pairs s² + 2ζW s + W² with ζ = sin(π(2k+1)/(2N)), plus s + W
    // when N is odd; each mapped by the bilinear transform
    for k in 0..order / 2 {
        let zeta = (PI * (2 * k + 1) as f64 / (2.0 * order as f64)).sin();
        let a0 = 1.0 + 2.0 * zeta * w + w * w;
        let a1 = 2.0 * w * w - 2.0;
        let a2 = 1.0 - 2.0 * zeta * w + w * w;
        let b = w * w / a0;
        sections.push(Section {
            b: [b, 2.0 * b, b],
            a: [1.0, a1 / a0, a2 / a0],
        });
    }
    if order % 2 == 1 {
        let a0 = 1.0 + w;
        sections.push(Section {
            b: [w / a0, w / a0, 0.0],
            a: [1.0, (w - 1.0) / a0, 0.0],
        });
    }
    (sections, w)
}

/// `x` extended beyond its ends by odd reflection about the end samples, repeated as needed
/// for short signals: `x(−k) = 2x(0) − x(k)`, `x(n−1+k) = 2x(n−1) − x(n−1−k)`.
///
/// Two reflections make a period: `x(i + 2L) = x(i) + 2(x(L) − x(0))` with `L = n − 1`, so any
/// `i` is one reflection at most from `[0, L]` plus whole periods (constant time, however far
/// the padding reaches beyond a short take).
fn odd_extension(x: &[f64], i: isize) -> f64 {
    let last = x.len() as isize - 1;
    if last == 0 {
        return x[0];
    }
    let (m, r) = periods(i, last);
    let base = if r < 0 {
        2.0 * x[0] - x[(-r) as usize]
    } else {
        x[r as usize]
    };
    base + 2.0 * m as f64 * (x[last as usize] - x[0])
}

/// Appends `x` extended by `pad` samples at each end to `buf`: [`odd_extension`] at
/// `−pad … n − 1 + pad`, bit for bit, the samples `0 … n − 2` copied rather than computed one
/// by one (there `odd_extension` is `x[i] + 2·0·(x[L] − x[0])`: `x[i]` plus a signed zero;
/// at `L` itself it goes round one period).
fn pad_odd(x: &[f64], pad: usize, buf: &mut Vec<f64>) {
    let (n, p) = (x.len() as isize, pad as isize);
    if n < 2 {
        buf.extend((-p..n + p).map(|i| odd_extension(x, i)));
        return;
    }
    buf.extend((-p..0).map(|i| odd_extension(x, i)));
    let zero = 2.0 * 0.0 * (x[x.len() - 1] - x[0]);
    buf.extend(x[..x.len() - 1].iter().map(|&v| v + zero));
    buf.extend((n - 1..n + p).map(|i| odd_extension(x, i)));
}

/// `i = r + 2L·m` with `−L ≤ r < L`: whole periods `m` of the doubly reflected extension and
/// the remainder `r`.
fn periods(i: isize, last: isize) -> (isize, isize) {
    let m = (i + last).div_euclid(2 * last);
    (m, i - 2 * last * m)
}

/// `q` extended beyond its ends by geodesic point reflection about the end rotations:
/// `q(−k) = q(0) q(k)⁻¹ q(0)` (the rotation analogue of [`odd_extension`]).
///
/// As for scalars, two reflections make a period: `q(i + 2L) = A q(i) B` with `A = q(L) q(0)⁻¹`
/// and `B = q(0)⁻¹ q(L)`, so `q(r + 2L·m) = Aᵐ q(r) Bᵐ` (constant time, no recursion).
#[cfg(test)]
fn geodesic_extension(q: &[UnitQuaternion<f64>], i: isize) -> UnitQuaternion<f64> {
    geodesic_extension_cached(q, i, &mut None)
}

/// `(m, Aᵐ, Bᵐ)` of the last period [`geodesic_extension_cached`] met.
type PeriodPowers = Option<(isize, UnitQuaternion<f64>, UnitQuaternion<f64>)>;

/// [`geodesic_extension`] that keeps `Aᵐ` and `Bᵐ` in `cache` while consecutive samples stay in
/// one period: the same numbers, one pair of `powf` per period instead of per sample (a pad of
/// 10⁵ samples around a short take, `Frame Time: 5e-6`, spent a second in them; found by
/// `examples/fuzz_takes.rs`).
fn geodesic_extension_cached(
    q: &[UnitQuaternion<f64>],
    i: isize,
    cache: &mut PeriodPowers,
) -> UnitQuaternion<f64> {
    let last = q.len() as isize - 1;
    if last == 0 {
        return q[0];
    }
    let (m, r) = periods(i, last);
    let (q0, ql) = (q[0], q[last as usize]);
    let base = if r < 0 {
        q0 * q[(-r) as usize].inverse() * q0
    } else {
        q[r as usize]
    };
    if m == 0 {
        return base;
    }
    // the rotation by m times A's angle about A's axis (the sign of the quaternion is free:
    // the padded trajectory is hemisphere-aligned afterwards)
    let (a, b) = match *cache {
        Some((cm, a, b)) if cm == m => (a, b),
        _ => {
            let a = (ql * q0.inverse()).powf(m as f64);
            let b = (q0.inverse() * ql).powf(m as f64);
            *cache = Some((m, a, b));
            (a, b)
        }
    };
    a * base * b
}

/// Runs `method` on the padded signal `buf` (`out.len() + 2·pad` samples) and writes the
/// smoothed centre to `out`. `buf` is used as scratch.
fn filter_padded(method: &Method, pad: usize, buf: &mut [f64], out: &mut [f64]) {
    let n = out.len();
    match method {
        Method::None => out.copy_from_slice(&buf[pad..pad + n]),
        Method::Fir { kernel } => {
            // y[i] = w0 x[i] + Σ_k wk (x[i−k] + x[i+k])
            for (i, o) in out.iter_mut().enumerate() {
                let c = i + pad;
                let mut acc = kernel[0] * buf[c];
                for (k, wk) in kernel.iter().enumerate().skip(1) {
                    acc += wk * (buf[c - k] + buf[c + k]);
                }
                *o = acc;
            }
        }
        Method::Iir { sections, .. } => {
            // forward pass through the cascade, then backward: zero phase, squared magnitude
            for s in sections {
                s.run_forward(buf);
            }
            for s in sections {
                s.run_backward(buf);
            }
            out.copy_from_slice(&buf[pad..pad + n]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_and_display_round_trip() {
        for (text, spec) in [
            ("none", SmoothSpec::None),
            ("gaussian:0.02", SmoothSpec::Gaussian { sigma_s: 0.02 }),
            ("gaussian:20ms", SmoothSpec::Gaussian { sigma_s: 0.02 }),
            (
                "butterworth:6hz",
                SmoothSpec::Butterworth {
                    cutoff_hz: 6.0,
                    order: 2,
                },
            ),
            (
                "Butterworth:6",
                SmoothSpec::Butterworth {
                    cutoff_hz: 6.0,
                    order: 2,
                },
            ),
            (
                "butterworth:10Hz:4",
                SmoothSpec::Butterworth {
                    cutoff_hz: 10.0,
                    order: 4,
                },
            ),
        ] {
            let parsed: SmoothSpec = text.parse().unwrap();
            match (parsed, spec) {
                (SmoothSpec::Gaussian { sigma_s: a }, SmoothSpec::Gaussian { sigma_s: b }) => {
                    assert!((a - b).abs() < 1e-15)
                }
                _ => assert_eq!(parsed, spec, "{text}"),
            }
            assert_eq!(parsed.to_string().parse::<SmoothSpec>().unwrap(), parsed);
        }
        assert_eq!(
            SmoothSpec::Butterworth {
                cutoff_hz: 6.0,
                order: 2
            }
            .to_string(),
            "butterworth:6hz"
        );
    }

    #[test]
    fn bad_specs_say_what_is_expected() {
        for bad in [
            "gauss:1",
            "gaussian",
            "gaussian:-1",
            "gaussian:abc",
            "butterworth:0",
            "butterworth:6hz:0",
            "butterworth:6hz:2:1",
        ] {
            let e = bad.parse::<SmoothSpec>().unwrap_err().to_string();
            assert!(e.contains(bad) && e.contains("expected"), "{bad}: {e}");
        }
        let e = Smoother::new(
            SmoothSpec::Butterworth {
                cutoff_hz: 20.0,
                order: 2,
            },
            1.0 / 30.0,
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("Nyquist"), "{e}");
    }

    #[test]
    fn pad_odd_is_odd_extension_bit_for_bit() {
        let signals: [&[f64]; 5] = [
            &[1.5],
            &[-0.0, -0.0, -0.0],
            &[0.0, -0.0, 3.25, -7.0],
            &[2.0, 1.0, -0.0, 0.5, 0.25, 1e-300],
            &[-0.0, 4.0],
        ];
        for x in signals {
            for pad in [0, 1, 3, 17] {
                let mut buf = vec![];
                pad_odd(x, pad, &mut buf);
                let want: Vec<u64> = (0..x.len() + 2 * pad)
                    .map(|i| odd_extension(x, i as isize - pad as isize).to_bits())
                    .collect();
                let got: Vec<u64> = buf.iter().map(|v| v.to_bits()).collect();
                assert_eq!(got, want, "{x:?} pad {pad}");
            }
        }
    }

    #[test]
    fn kernel_sums_to_one_and_odd_extension_is_affine() {
        let k = gaussian_kernel(0.02, 1.0 / 120.0);
        assert!((k[0] + 2.0 * k[1..].iter().sum::<f64>() - 1.0).abs() < 1e-15);
        let x = [1.0, 3.0, 4.0];
        assert_eq!(odd_extension(&x, -1), -1.0);
        assert_eq!(odd_extension(&x, 3), 5.0);
        // a line stays a line through any number of reflections
        let line = [2.0, 2.5];
        for i in -7..9 {
            assert!((odd_extension(&line, i) - (2.0 + 0.5 * i as f64)).abs() < 1e-12);
        }
    }

    /// The extensions' closed forms equal the reflections applied one at a time, however far
    /// beyond a short signal (the padding of a 6 Hz filter on a take sampled every 10 µs
    /// reaches 10⁵ frames; reflecting one at a time made that quadratic and the quaternion
    /// one recursive).
    #[test]
    fn extensions_far_beyond_the_ends_equal_the_reflections_one_at_a_time() {
        fn odd_by_reflections(x: &[f64], i: isize) -> f64 {
            let last = x.len() as isize - 1;
            if i < 0 {
                2.0 * x[0] - odd_by_reflections(x, -i)
            } else if i > last {
                2.0 * x[last as usize] - odd_by_reflections(x, 2 * last - i)
            } else {
                x[i as usize]
            }
        }
        fn geo_by_reflections(q: &[UnitQuaternion<f64>], i: isize) -> UnitQuaternion<f64> {
            let last = q.len() as isize - 1;
            if i < 0 {
                q[0] * geo_by_reflections(q, -i).inverse() * q[0]
            } else if i > last {
                let e = q[last as usize];
                e * geo_by_reflections(q, 2 * last - i).inverse() * e
            } else {
                q[i as usize]
            }
        }
        let x = [0.3, -1.2, 2.5, 0.7];
        let q: Vec<UnitQuaternion<f64>> = [(0.1, 0.2, 0.3), (0.4, -0.1, 0.2), (0.2, 0.5, -0.3)]
            .iter()
            .map(|&(r, p, y)| UnitQuaternion::from_euler_angles(r, p, y))
            .collect();
        for i in -40..45 {
            let (a, b) = (odd_extension(&x, i), odd_by_reflections(&x, i));
            assert!(
                (a - b).abs() < 1e-12 * (1.0 + b.abs()),
                "x({i}): {a} vs {b}"
            );
            let (a, b) = (geodesic_extension(&q, i), geo_by_reflections(&q, i));
            assert!(a.angle_to(&b) < 1e-9, "q({i}) off by {}", a.angle_to(&b));
        }
        // the cached powers of a sweep give the same numbers, bit for bit
        let mut cache = None;
        for i in -400..450 {
            let c = geodesic_extension_cached(&q, i, &mut cache);
            assert_eq!(c, geodesic_extension(&q, i), "q({i})");
        }
    }

    #[test]
    fn a_filter_reaching_past_its_limit_is_refused_with_what_to_change() {
        let e = Smoother::new("butterworth:6hz".parse().unwrap(), 1e-7)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("Frame Time") && e.contains("10503691 frames"),
            "{e}"
        );
        let e = Smoother::new("gaussian:0.02".parse().unwrap(), 1e-8)
            .unwrap_err()
            .to_string();
        assert!(e.contains("narrower kernel"), "{e}");
        // a short frame time inside the limit is smoothed, and quickly
        let mut s = Smoother::new("butterworth:6hz".parse().unwrap(), 1e-4).unwrap();
        let mut x: Vec<f64> = (0..600).map(|k| (k as f64 * 0.01).sin()).collect();
        s.smooth(&mut x);
        assert!(x.iter().all(|v| v.is_finite()));
    }

    #[test]
    fn quaternion_components_side_by_side_are_each_filtered_alone_bit_for_bit() {
        // the four components in one buffer must give what filtering each alone gives
        let q0: Vec<UnitQuaternion<f64>> = (0..157)
            .map(|k| {
                let t = k as f64 * 0.013;
                UnitQuaternion::from_euler_angles(1.3 * t.sin(), 0.4 * t - 0.2, (2.1 * t).cos())
            })
            .collect();
        for spec in ["gaussian:0.02", "butterworth:6hz", "butterworth:4hz:3"] {
            let mut s = Smoother::new(spec.parse().unwrap(), 1.0 / 120.0).unwrap();
            let mut q = q0.clone();
            s.smooth_quaternions(&mut q);
            // the same padding, then each component through `filter_padded` alone
            let (n, p) = (q0.len(), s.pad);
            let mut aligned = q0.clone();
            align_hemispheres(&mut aligned);
            let mut padded: Vec<_> = (0..n + 2 * p)
                .map(|i| geodesic_extension(&aligned, i as isize - p as isize))
                .collect();
            align_hemispheres(&mut padded);
            if padded[p].coords.dot(&aligned[0].coords) < 0.0 {
                padded.iter_mut().for_each(|r| *r = negate(r));
            }
            let mut comps = vec![vec![0.0; n]; 4];
            for (c, out) in comps.iter_mut().enumerate() {
                let mut buf: Vec<f64> = padded.iter().map(|r| r.coords[(c + 3) % 4]).collect();
                filter_padded(&s.method, p, &mut buf, out);
            }
            for k in 0..n {
                let raw = Quaternion::new(comps[0][k], comps[1][k], comps[2][k], comps[3][k]);
                let want = UnitQuaternion::new_normalize(raw);
                assert_eq!(q[k].coords, want.coords, "{spec}, frame {k}");
            }
        }
    }
}
