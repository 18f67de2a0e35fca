//! Sines, cosines and arctangents of many values at once, for the euler model's per-frame
//! rotations (`motion::euler`): the very operations of [`spatial::sin_cos`] and
//! [`spatial::atan2`] (musl's `atan2` by the `libm` crate) on each value, written without
//! branches so that the compiler runs them on the processor's vector lanes, two values at a
//! time on baseline x86-64 (SSE2) and four with AVX2, chosen at run time.
//!
//! Every value comes out bit for bit what the scalar function gives, whatever the lane width:
//! the kernels use no fused multiply–add (which would round once where the scalar code rounds
//! twice), so the AVX2 and SSE2 versions, and the scalar functions, agree to the last bit, and
//! the result does not depend on the machine's vector unit or on how frames are split among
//! threads. Each branch of the scalar functions becomes a select between values computed for
//! every lane; values outside the common path (NaN, infinities, zeros and ratios beyond
//! 2^±60 for `atan2`, `|x| ≥ 823,549.6` for `sin_cos`) are then recomputed by the scalar
//! function.
//!
//! Why not the `wide` crate: its `f64x4::sin_cos` and `atan2` are other polynomials (Agner
//! Fog's vector class library, with fused multiply–adds where compiled for FMA), so the
//! states would no longer be the scalar path's to the bit, and it picks its AVX or SSE2 form
//! when compiled (`cfg(target_feature)`), not at run time, so the default x86-64 build would
//! never use AVX.
//!
//! [`spatial::sin_cos`]: crate::spatial::sin_cos
//! [`spatial::atan2`]: crate::spatial::atan2

/// Whether the AVX2 versions run (checked once by the standard library, then cached).
#[cfg(target_arch = "x86_64")]
#[inline]
fn avx2() -> bool {
    std::arch::is_x86_feature_detected!("avx2")
}

/// Whether every value of `x` is finite, every value looked at (no early exit, so the loop
/// vectorises): the check a whole state or row gets before its culprit is searched for.
#[inline]
pub fn all_finite(x: &[f64]) -> bool {
    x.iter().fold(true, |ok, x| ok & x.is_finite())
}

/// `(s[i], c[i]) = sin_cos(x[i])` ([`crate::spatial::sin_cos`], bit for bit) for every `x[i]`;
/// `s` and `c` at least as long as `x`.
pub fn sin_cos_many(x: &[f64], s: &mut [f64], c: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    if avx2() {
        // SAFETY: the processor has AVX2 (checked just above)
        unsafe { sin_cos_avx2(x, s, c) };
        return;
    }
    sin_cos_body(x, s, c);
}

/// `out[i] = atan2(y[i], x[i])` ([`crate::spatial::atan2`], bit for bit) for every `i`; `x`
/// and `out` at least as long as `y`.
pub fn atan2_many(y: &[f64], x: &[f64], out: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    if avx2() {
        // SAFETY: the processor has AVX2 (checked just above)
        unsafe { atan2_avx2(y, x, out) };
        return;
    }
    atan2_body(y, x, out);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn sin_cos_avx2(x: &[f64], s: &mut [f64], c: &mut [f64]) {
    sin_cos_body(x, s, c);
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn atan2_avx2(y: &[f64], x: &[f64], out: &mut [f64]) {
    atan2_body(y, x, out);
}

/// [`sin_cos_many`] in the caller's instruction set: the branch-free kernel over every value
/// (a loop the compiler vectorises), then the standard library's `sin_cos` where the kernel
/// does not hold, as [`crate::spatial::sin_cos`] does.
#[inline(always)]
fn sin_cos_body(x: &[f64], s: &mut [f64], c: &mut [f64]) {
    let n = x.len();
    let (s, c) = (&mut s[..n], &mut c[..n]);
    let mut outside = false;
    for i in 0..n {
        (s[i], c[i]) = sin_cos_lane(x[i]);
        outside |= beyond_sin_cos(x[i]);
    }
    if outside {
        for i in 0..n {
            if beyond_sin_cos(x[i]) {
                // what `spatial::sin_cos` gives there (it is this kernel within the range)
                (s[i], c[i]) = x[i].sin_cos();
            }
        }
    }
}

/// [`atan2_many`] in the caller's instruction set (see [`sin_cos_body`]).
#[inline(always)]
fn atan2_body(y: &[f64], x: &[f64], out: &mut [f64]) {
    let n = y.len();
    let (x, out) = (&x[..n], &mut out[..n]);
    let mut special = false;
    for i in 0..n {
        let r = (y[i] / x[i]).abs();
        out[i] = atan2_lane(y[i], x[i], r);
        special |= atan2_special(y[i], x[i], r);
    }
    if special {
        for i in 0..n {
            if atan2_special(y[i], x[i], (y[i] / x[i]).abs()) {
                out[i] = crate::spatial::atan2(y[i], x[i]);
            }
        }
    }
}

/// Below this `|x|` [`sin_cos_lane`] is [`crate::spatial::sin_cos`] (beyond, and for NaN, that
/// goes to the standard library).
const SIN_COS_RANGE: f64 = 823_549.6;

/// Whether `x` is beyond [`sin_cos_lane`]'s range: what sends [`crate::spatial::sin_cos`] to
/// the standard library.
#[inline(always)]
pub(crate) fn beyond_sin_cos(x: f64) -> bool {
    x.abs() >= SIN_COS_RANGE || x.is_nan()
}

/// [`crate::spatial::sin_cos`] for `|x| < SIN_COS_RANGE`, without branches: the same
/// reduction and kernels, the quadrant's swap and signs by bit masks.
#[inline(always)]
pub(crate) fn sin_cos_lane(x: f64) -> (f64, f64) {
    const TWO_OVER_PI: f64 = std::f64::consts::FRAC_2_PI;
    const P1: f64 = 1.570_796_326_734_125_6;
    const P2: f64 = 6.077_100_506_303_966e-11;
    const P3: f64 = 2.022_266_248_795_950_7e-21;
    const SHIFT: f64 = 6_755_399_441_055_744.0;
    let t = x * TWO_OVER_PI + SHIFT;
    let n = t - SHIFT;
    let r = ((x - n * P1) - n * P2) - n * P3;
    let z = r * r;
    let sin = r + r
        * z
        * (-1.666_666_666_666_663_2e-1
            + z * (8.333_333_333_322_49e-3
                + z * (-1.984_126_982_985_795e-4
                    + z * (2.755_731_370_707_007e-6
                        + z * (-2.505_076_025_340_686_3e-8 + z * 1.589_690_995_211_55e-10)))));
    let c = z
        * z
        * (4.166_666_666_666_659_4e-2
            + z * (-1.388_888_888_887_411e-3
                + z * (2.480_158_728_947_673e-5
                    + z * (-2.755_731_435_139_066_3e-7
                        + z * (2.087_572_321_298_175e-9 + z * -1.135_964_755_778_819_5e-11)))));
    let hz = 0.5 * z;
    let w = 1.0 - hz;
    let cos = w + (((1.0 - w) - hz) + c);
    // quadrant q = n mod 4: 0 (sin, cos), 1 (cos, −sin), 2 (−sin, −cos), 3 (−cos, sin)
    let q = t.to_bits() & 3;
    let swap = (q & 1).wrapping_neg();
    let (sb, cb) = (sin.to_bits(), cos.to_bits());
    let first = (cb & swap) | (sb & !swap);
    let second = (sb & swap) | (cb & !swap);
    let first = f64::from_bits(first ^ ((q >> 1) << 63));
    let second = f64::from_bits(second ^ ((((q + 1) >> 1) & 1) << 63));
    // below 2⁻²⁷: (x, 1) as the scalar function returns them (keeps the sign of −0)
    let tiny = x.abs() < 7.45e-9;
    (
        if tiny { x } else { first },
        if tiny { 1.0 } else { second },
    )
}

/// Whether `atan2(y, x)` is not [`atan2_lane`]'s: NaN or an infinity in either, `x = ±0`, or a
/// nonzero `y` with `r = |y/x|` outside `[2⁻⁶⁰, 2⁶⁰]` (libm's `x = 1` shortcut, `atan(y)`,
/// gives the same bits as its general path inside that range: `y/1 = y` and `atan` is odd to
/// the bit). A zero `y` is the lane's: `r = 0` takes `atan(r) = r`, so it gives `±0` for
/// `x > 0` and `±π` for `x < 0` (`π + π_lo` rounds to `π`), musl's own answers. Zero `y` is
/// common (the rotation of a joint that does not move, an identity step of a rotation) and,
/// sent to the scalar function, cost its block a second pass.
#[inline(always)]
fn atan2_special(y: f64, x: f64, r: f64) -> bool {
    const LOW: f64 = f64::from_bits((1023 - 60) << 52);
    const HIGH: f64 = f64::from_bits((1023 + 60) << 52);
    !(x.is_finite() && y.is_finite() && x != 0.0 && (y == 0.0 || (LOW..=HIGH).contains(&r)))
}

/// musl's `atan2(y, x)` (`libm::atan2`) where [`atan2_special`] is false, without branches:
/// `z = atan(r)` by [`atan_lane`] (`r = |y/x|`), then the quadrant from the signs.
#[inline(always)]
fn atan2_lane(y: f64, x: f64, r: f64) -> f64 {
    const PI: f64 = f64::from_bits(0x4009_21FB_5444_2D18);
    const PI_LO: f64 = f64::from_bits(0x3CA1_A626_3314_5C07);
    let z = atan_lane(r);
    let t = z - PI_LO;
    let (neg_y, neg_x) = (y.is_sign_negative(), x.is_sign_negative());
    match (neg_x, neg_y) {
        (false, false) => z,
        (false, true) => -z,
        (true, false) => PI - t,
        (true, true) => t - PI,
    }
}

/// musl's `atan(r)` (`libm::atan`) for `2⁻⁶⁰ ≤ r ≤ 2⁶⁰`, without branches: the argument's
/// reduction (one of five, by `r`'s range) as a quotient of selected numerator and
/// denominator, both tails computed and one selected.
#[inline(always)]
fn atan_lane(r: f64) -> f64 {
    // fdlibm's constants by their bits (s_atan.c)
    const ATANHI: [f64; 4] = [
        f64::from_bits(0x3FDD_AC67_0561_BB4F), // atan(0.5) high
        f64::from_bits(0x3FE9_21FB_5444_2D18), // atan(1) high
        f64::from_bits(0x3FEF_730B_D281_F69B), // atan(1.5) high
        f64::from_bits(0x3FF9_21FB_5444_2D18), // atan(∞) high
    ];
    const ATANLO: [f64; 4] = [
        f64::from_bits(0x3C7A_2B7F_222F_65E2),
        f64::from_bits(0x3C81_A626_3314_5C07),
        f64::from_bits(0x3C70_0788_7AF0_CBBD),
        f64::from_bits(0x3C91_A626_3314_5C07),
    ];
    const AT: [f64; 11] = [
        f64::from_bits(0x3FD5_5555_5555_550D),
        f64::from_bits(0xBFC9_9999_9998_EBC4),
        f64::from_bits(0x3FC2_4924_9200_83FF),
        f64::from_bits(0xBFBC_71C6_FE23_1671),
        f64::from_bits(0x3FB7_45CD_C54C_206E),
        f64::from_bits(0xBFB3_B0F2_AF74_9A6D),
        f64::from_bits(0x3FB1_0D66_A0D0_3D51),
        f64::from_bits(0xBFAD_DE2D_52DE_FD9A),
        f64::from_bits(0x3FA9_7B4B_2476_0DEB),
        f64::from_bits(0xBFA2_B444_2C6A_6C2F),
        f64::from_bits(0x3F90_AD3A_E322_DA11),
    ];
    // libm's ranges by the high word of r; for a positive double, high word < H ⟺ r < the
    // double whose bits are H·2³²
    let small = r < 0.4375; // 0x3fdc0000
    let below_11_16 = r < 0.6875; // 0x3fe60000
    let below_19_16 = r < 1.1875; // 0x3ff30000
    let below_39_16 = r < 2.4375; // 0x40038000
    let (num, den, hi, lo) = if small {
        (r, 1.0, 0.0, 0.0)
    } else if below_11_16 {
        (2. * r - 1., 2. + r, ATANHI[0], ATANLO[0])
    } else if below_19_16 {
        (r - 1., r + 1., ATANHI[1], ATANLO[1])
    } else if below_39_16 {
        (r - 1.5, 1. + 1.5 * r, ATANHI[2], ATANLO[2])
    } else {
        (-1., r, ATANHI[3], ATANLO[3])
    };
    // r / 1 is r: the small range's argument unchanged
    let x = num / den;
    let z = x * x;
    let w = z * z;
    let s1 = z * (AT[0] + w * (AT[2] + w * (AT[4] + w * (AT[6] + w * (AT[8] + w * AT[10])))));
    let s2 = w * (AT[1] + w * (AT[3] + w * (AT[5] + w * (AT[7] + w * AT[9]))));
    let near = x - x * (s1 + s2);
    let far = hi - (x * (s1 + s2) - lo - x);
    // below 2⁻²⁷ atan(r) is r
    if r < f64::from_bits((1023 - 27) << 52) {
        r
    } else if small {
        near
    } else {
        far
    }
}

/// Frames whose per-frame rotation arithmetic is done together: the callers' blocks.
pub const BLOCK: usize = 64;

/// [`crate::rotation::hinge_coordinate_rates`] (with `min_det = 0`) of up to [`BLOCK`] frames
/// side by side, bit for bit: fill `axes` (`H` column-major, entry `(r, c)` at `3c + r`), `w`
/// and `dw` for frames `0..m`, call [`HingeBlock::solve`], read `dq`, `ddq` and `ok` (false
/// where `H` is exactly singular: no rates).
#[derive(Debug, Clone)]
pub struct HingeBlock {
    pub axes: [[f64; BLOCK]; 9],
    pub w: [[f64; BLOCK]; 3],
    pub dw: [[f64; BLOCK]; 3],
    pub dq: [[f64; BLOCK]; 3],
    pub ddq: [[f64; BLOCK]; 3],
    pub ok: [bool; BLOCK],
}

impl Default for HingeBlock {
    fn default() -> Self {
        Self {
            axes: [[0.0; BLOCK]; 9],
            w: [[0.0; BLOCK]; 3],
            dw: [[0.0; BLOCK]; 3],
            dq: [[0.0; BLOCK]; 3],
            ddq: [[0.0; BLOCK]; 3],
            ok: [false; BLOCK],
        }
    }
}

impl HingeBlock {
    /// `q̇ = H⁻¹ ω` and `q̈ = H⁻¹ (α − Ḣ q̇)` of frames `0..m` (`m ≤ BLOCK`), in the caller's
    /// instruction set (call it inside [`vectorised`]): nalgebra's 3×3 inverse (its minors,
    /// determinant and quotients), matrix–vector products (`y = ((h₀x₀) + h₁x₁) + h₂x₂`) and
    /// cross products, in their order, frame by frame down the columns.
    #[inline(always)]
    pub fn solve(&mut self, m: usize) {
        hinge_solve_body(self, m);
    }
}

/// Runs `f` compiled for AVX2 where the processor has it (checked once, then cached), else
/// as built (SSE2 on baseline x86-64): for loops over frames side by side, which the compiler
/// then vectorises four or two values wide. `f` should be an `#[inline(always)]` closure
/// whose work is inlined into it. The results are the same bits either way: vectorising
/// neither reorders nor fuses floating-point operations.
#[inline(always)]
pub fn vectorised<R>(f: impl FnOnce() -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    if avx2() {
        #[target_feature(enable = "avx2")]
        fn with_avx2<R>(f: impl FnOnce() -> R) -> R {
            f()
        }
        // SAFETY: the processor has AVX2 (checked just above)
        return unsafe { with_avx2(f) };
    }
    f()
}

#[inline(always)]
fn hinge_solve_body(b: &mut HingeBlock, m: usize) {
    let m = m.min(BLOCK);
    let [a11, a21, a31, a12, a22, a32, a13, a23, a33] = &b.axes;
    let [w1, w2, w3] = &b.w;
    let [dw1, dw2, dw3] = &b.dw;
    let [dq1, dq2, dq3] = &mut b.dq;
    let [ddq1, ddq2, ddq3] = &mut b.ddq;
    let ok = &mut b.ok;
    for i in 0..m {
        let (m11, m21, m31) = (a11[i], a21[i], a31[i]);
        let (m12, m22, m32) = (a12[i], a22[i], a32[i]);
        let (m13, m23, m33) = (a13[i], a23[i], a33[i]);
        // nalgebra's Matrix3::try_inverse
        let minor_m12_m23 = m22 * m33 - m32 * m23;
        let minor_m11_m23 = m21 * m33 - m31 * m23;
        let minor_m11_m22 = m21 * m32 - m31 * m22;
        let det = m11 * minor_m12_m23 - m12 * minor_m11_m23 + m13 * minor_m11_m22;
        let i11 = minor_m12_m23 / det;
        let i12 = (m13 * m32 - m33 * m12) / det;
        let i13 = (m12 * m23 - m22 * m13) / det;
        let i21 = -minor_m11_m23 / det;
        let i22 = (m11 * m33 - m31 * m13) / det;
        let i23 = (m13 * m21 - m23 * m11) / det;
        let i31 = minor_m11_m22 / det;
        let i32 = (m12 * m31 - m32 * m11) / det;
        let i33 = (m11 * m22 - m21 * m12) / det;
        // q̇ = H⁻¹ ω
        let (x1, x2, x3) = (w1[i], w2[i], w3[i]);
        let d1 = i11 * x1 + i12 * x2 + i13 * x3;
        let d2 = i21 * x1 + i22 * x2 + i23 * x3;
        let d3 = i31 * x1 + i32 * x2 + i33 * x3;
        // Ḣ q̇ = (w₀ × w₁) q̇₁ + ((w₀ + w₁ q̇₁) × w₂) q̇₂, w₀ the first axis times q̇₀
        let (u1, u2, u3) = (m11 * d1, m21 * d1, m31 * d1);
        let f1 = (u2 * m32 - u3 * m22) * d2;
        let f2 = (u3 * m12 - u1 * m32) * d2;
        let f3 = (u1 * m22 - u2 * m12) * d2;
        let (t1, t2, t3) = (u1 + m12 * d2, u2 + m22 * d2, u3 + m32 * d2);
        let g1 = (t2 * m33 - t3 * m23) * d3;
        let g2 = (t3 * m13 - t1 * m33) * d3;
        let g3 = (t1 * m23 - t2 * m13) * d3;
        let (y1, y2, y3) = (dw1[i] - (f1 + g1), dw2[i] - (f2 + g2), dw3[i] - (f3 + g3));
        // q̈ = H⁻¹ (α − Ḣ q̇)
        ddq1[i] = i11 * y1 + i12 * y2 + i13 * y3;
        ddq2[i] = i21 * y1 + i22 * y2 + i23 * y3;
        ddq3[i] = i31 * y1 + i32 * y2 + i33 * y3;
        (dq1[i], dq2[i], dq3[i]) = (d1, d2, d3);
        ok[i] = det != 0.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values of every kind: the joint-angle range densely, the kernels' range boundaries,
    /// signed zeros, tiny, huge, infinite and NaN.
    fn values() -> Vec<f64> {
        let mut v = vec![
            0.0,
            -0.0,
            1.0,
            -1.0,
            f64::INFINITY,
            f64::NEG_INFINITY,
            f64::NAN,
            f64::MIN_POSITIVE,
            -5e-324,
            7.45e-9,
            7.44e-9,
            -7.46e-9,
            f64::from_bits((1023 - 27) << 52),
            0.4375,
            0.6875,
            1.1875,
            2.4375,
            823_549.5,
            823_549.6,
            -823_549.7,
            1e7,
            1e300,
            f64::from_bits((1023 - 60) << 52),
            f64::from_bits((1023 + 60) << 52),
        ];
        for b in [
            0.4375f64,
            0.6875,
            1.1875,
            2.4375,
            f64::from_bits((1023 - 27) << 52),
        ] {
            v.extend([b.next_up(), b.next_down(), -b.next_up(), -b.next_down()]);
        }
        // a simple reproducible spread over many magnitudes (no rand in the library's tests)
        let mut s = 0x9e37_79b9_7f4a_7c15_u64;
        for _ in 0..20_000 {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            let u = (s >> 11) as f64 / (1u64 << 53) as f64;
            let scale = [1e-12, 1e-6, 0.1, 1.0, 3.2, 10.0, 1e3, 1e6][(s % 8) as usize];
            v.push((2.0 * u - 1.0) * scale);
        }
        v
    }

    fn same(a: f64, b: f64) -> bool {
        a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
    }

    #[test]
    fn sin_cos_many_is_the_scalar_sin_cos_bit_for_bit() {
        let x = values();
        let (mut s, mut c) = (vec![0.0; x.len()], vec![0.0; x.len()]);
        // the dispatched version (AVX2 where the processor has it) and the baseline one
        sin_cos_many(&x, &mut s, &mut c);
        let (mut s0, mut c0) = (vec![0.0; x.len()], vec![0.0; x.len()]);
        sin_cos_body(&x, &mut s0, &mut c0);
        for i in 0..x.len() {
            let (ws, wc) = crate::spatial::sin_cos(x[i]);
            assert!(same(s[i], ws) && same(c[i], wc), "sin_cos({:e})", x[i]);
            assert!(same(s0[i], ws) && same(c0[i], wc), "sin_cos({:e})", x[i]);
        }
    }

    #[test]
    fn atan2_many_is_libm_atan2_bit_for_bit() {
        let v = values();
        // every pair of a sample of values (both orders), and the rotation-matrix kind
        let sample: Vec<f64> = v
            .iter()
            .step_by(97)
            .copied()
            .chain(v[..40].to_vec())
            .collect();
        let (mut y, mut x) = (vec![], vec![]);
        for &a in &sample {
            for &b in &sample {
                y.push(a);
                x.push(b);
            }
        }
        for k in 0..20_000 {
            let t = k as f64 * 3.7e-4 - 3.7;
            y.push(t.sin() * 0.93);
            x.push(t.cos() * 0.93);
        }
        let mut out = vec![0.0; y.len()];
        let mut out0 = vec![0.0; y.len()];
        atan2_many(&y, &x, &mut out);
        atan2_body(&y, &x, &mut out0);
        for i in 0..y.len() {
            let want = libm::atan2(y[i], x[i]);
            assert!(same(out[i], want), "atan2({:e}, {:e})", y[i], x[i]);
            assert!(same(out0[i], want), "atan2({:e}, {:e})", y[i], x[i]);
        }
    }

    #[test]
    fn all_finite_answers_as_every_value_is_finite() {
        assert!(all_finite(&[]) && all_finite(&[0.0, -1e308, 5e-324]));
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            for at in 0..5 {
                let mut x = [1.0; 5];
                x[at] = bad;
                assert!(!all_finite(&x), "{bad} at {at}");
            }
        }
    }

    #[test]
    fn hinge_block_is_hinge_coordinate_rates_bit_for_bit() {
        use crate::rotation::{EulerOrder, hinge_axes, hinge_coordinate_rates};
        use nalgebra::{Matrix3, Vector3};
        let mut b = HingeBlock::default();
        let mut want = vec![];
        let mut k = 0;
        let check = |b: &mut HingeBlock, want: &mut Vec<_>, m: usize| {
            let mut plain = b.clone();
            plain.solve(m);
            vectorised(|| b.solve(m));
            assert_eq!(format!("{:?}", plain.ddq), format!("{:?}", b.ddq));
            for (i, w) in want.drain(..).enumerate() {
                match w {
                    None => assert!(!b.ok[i], "frame {i}"),
                    Some((dq, ddq)) => {
                        let (dq, ddq): (Vector3<f64>, Vector3<f64>) = (dq, ddq);
                        assert!(b.ok[i], "frame {i}");
                        for r in 0..3 {
                            assert!(same(b.dq[r][i], dq[r]) && same(b.ddq[r][i], ddq[r]), "{i}");
                        }
                    }
                }
            }
        };
        for order in EulerOrder::ALL {
            for j in 0..200 {
                let t = j as f64 * 0.37 + order as usize as f64;
                // angles through the lock (a2 = ±π/2 exactly at some frames) and far from it
                let a2 = if j % 50 == 0 {
                    std::f64::consts::FRAC_PI_2
                } else {
                    (t * 0.7).sin() * 1.6
                };
                let x = [t.sin() * 3.0, a2, (t * 1.3).cos() * 2.5];
                let axes = if j % 67 == 0 {
                    Matrix3::zeros()
                } else {
                    hinge_axes(Matrix3::identity(), order, x)
                };
                let w = Vector3::new(t.cos(), -2.0 * t.sin(), 0.3 + t);
                let dw = Vector3::new(5.0 * t, (3.0 * t).sin(), -1.0);
                for e in 0..9 {
                    b.axes[e][k] = axes[(e % 3, e / 3)];
                }
                for r in 0..3 {
                    (b.w[r][k], b.dw[r][k]) = (w[r], dw[r]);
                }
                want.push(hinge_coordinate_rates(&axes, &w, &dw, 0.0));
                k += 1;
                if k == BLOCK || j == 199 {
                    check(&mut b, &mut want, k);
                    k = 0;
                }
            }
        }
    }
}
