//! `exp` and `expm1` for f32 with a 32-bit integer core: the chip's per-frame
//! exponentials, and the very same code on the host, so host tests check the
//! chip's results bit for bit (the core is integer arithmetic; the only float
//! operations are in the rarely used negative-`expm1` branch).
//!
//! Why not avr-libc's `exp` (~2 500 cycles) or a float polynomial: every
//! soft-float operation costs 150–550 cycles on the AVR, while a 32×32-bit
//! high product built from four hardware 16×16 products costs ~100.
//!
//! Method: x·log₂e = k + f with k an integer and f ∈ [0, 1), formed exactly
//! from the float's bits (|x| < 128 as Q7.25, a 64-bit product with log₂e in
//! Q1.31). Then 2^f = 1 + f·S(f) with S(f) = (2^f − 1)/f a degree-5 polynomial
//! (near-minimax, |error| ≤ 1.1e-8) in Q1.31 by Horner, and 2^k goes into the
//! exponent field. `expm1` for 0 < x < ln 2 forms f = x·log₂e from the
//! mantissa (relative precision, no cancellation) and returns f·S(f); above,
//! 2^k·2^f − 1 loses at most one bit of 32.
//!
//! Accuracy (checked against f64 over dense sweeps in tests/chip_accuracy.rs):
//! `exp` and `expm1` for x ≥ 0 within 1 ulp; `expm1` for −ln 2 < x < 0 (only
//! used at plan time) within 3 ulp. Results below the smallest normal f32
//! are returned as 0 (avr-libc has no subnormals either). Cost on the chip:
//! ~900 cycles for `exp`, ~1 000–1 300 for `expm1` (BENCHMARKS.md).

/// log₂e in Q1.31.
const LOG2E_Q31: u32 = 0xB8AA_3B29;

/// S(f) = (2^f − 1)/f on [0, 1] = Σ Sₖ·fᵏ, Q1.31 (near-minimax, from a
/// Chebyshev fit; |error| ≤ 1.06e-8). Immediates, not a table: a table
/// would sit in RAM on the AVR.
const S5: u32 = 447_061;
const S4: u32 = 2_725_622;
const S3: u32 = 20_727_931;
const S2: u32 = 119_176_803;
const S1: u32 = 515_883_993;
const S0: u32 = 1_488_522_215;

const MANT_MASK: u32 = 0x007F_FFFF;
const HIDDEN: u32 = 0x0080_0000;

/// a·b for 16-bit a, b. On AVR written out as libgcc's `__umulhisi3` (four
/// 8×8 `mul`s, ~20 cycles): in plain Rust, LLVM fuses the four products of
/// [`mul_full`] back into a 64-bit multiply, a ~700-cycle library call.
#[cfg(not(target_arch = "avr"))]
#[inline(always)]
fn mul16(a: u16, b: u16) -> u32 {
    u32::from(a) * u32::from(b)
}

#[cfg(target_arch = "avr")]
#[inline(always)]
fn mul16(a: u16, b: u16) -> u32 {
    let lo: u16;
    let hi: u16;
    // SAFETY: register-only arithmetic; `mul` writes r1:r0, and r1 (the
    // zero register) is cleared again before the block ends.
    unsafe {
        core::arch::asm!(
            "mul {a:l}, {b:l}",
            "movw {lo}, r0",
            "mul {a:h}, {b:h}",
            "movw {hi}, r0",
            "mul {a:l}, {b:h}",
            "add {lo:h}, r0",
            "adc {hi:l}, r1",
            "eor r1, r1",
            "adc {hi:h}, r1",
            "mul {a:h}, {b:l}",
            "add {lo:h}, r0",
            "adc {hi:l}, r1",
            "eor r1, r1",
            "adc {hi:h}, r1",
            a = in(reg_pair) a,
            b = in(reg_pair) b,
            lo = out(reg_pair) lo,
            hi = out(reg_pair) hi,
            options(pure, nomem, nostack),
        );
    }
    (u32::from(hi) << 16) | u32::from(lo)
}

/// The full 64-bit product a·b as (high, low) words, from four 16×16 products
/// (the AVR's hardware multiplier; a `u64` multiply is a slow library call).
#[inline]
pub fn mul_full(a: u32, b: u32) -> (u32, u32) {
    let (a1, a0) = ((a >> 16) as u16, a as u16);
    let (b1, b0) = ((b >> 16) as u16, b as u16);
    let ll = mul16(a0, b0);
    let lh = mul16(a0, b1);
    let hl = mul16(a1, b0);
    let hh = mul16(a1, b1);
    // Each term < 2¹⁶, so the sum < 3·2¹⁶: no overflow.
    let mid = (ll >> 16) + (lh & 0xFFFF) + (hl & 0xFFFF);
    let hi = hh + (lh >> 16) + (hl >> 16) + (mid >> 16);
    let lo = (mid << 16) | (ll & 0xFFFF);
    (hi, lo)
}

/// ⌊a·b / 2³²⌋.
#[inline]
pub fn mul_hi(a: u32, b: u32) -> u32 {
    mul_full(a, b).0
}

/// ⌊a·b / 2³²⌋ or one less: the low×low product is left out (three hardware
/// products instead of four). Enough inside the polynomial, where each step
/// already truncates.
#[inline]
fn mul_hi_approx(a: u32, b: u32) -> u32 {
    let (a1, a0) = ((a >> 16) as u16, a as u16);
    let (b1, b0) = ((b >> 16) as u16, b as u16);
    let lh = mul16(a0, b1);
    let hl = mul16(a1, b0);
    let hh = mul16(a1, b1);
    let mid = (lh & 0xFFFF) + (hl & 0xFFFF);
    hh + (lh >> 16) + (hl >> 16) + (mid >> 16)
}

/// 2^f − 1 in Q1.31 for f ∈ [0, 1) in Q0.32 (|error| < 2e-8 relative to 2^f).
#[inline]
fn pow2m1_q31(f: u32) -> u32 {
    mul_hi_approx(s_poly(f), f)
}

/// S(f) = (2^f − 1)/f in Q1.31 (values in [ln 2, 1]); each truncating step
/// adds at most 2⁻³⁰.
#[inline]
fn s_poly(f: u32) -> u32 {
    let s = S4 + mul_hi_approx(S5, f);
    let s = S3 + mul_hi_approx(s, f);
    let s = S2 + mul_hi_approx(s, f);
    let s = S1 + mul_hi_approx(s, f);
    S0 + mul_hi_approx(s, f)
}

/// Rounds a Q1.31 value in [1, 2)·2³¹ (bit 31 set) to a 24-bit mantissa with
/// its hidden bit; may round up to 2²⁴ (the caller's exponent add carries it).
#[inline(always)]
fn round_mant(m: u32) -> u32 {
    (m >> 8) + ((m >> 7) & 1)
}

/// Packs 2^(e−127)·mant/2²³ for a mantissa from [`round_mant`] and a biased
/// exponent e ≥ 1; a carry out of the mantissa bumps the exponent.
#[inline(always)]
fn pack(sign: u32, biased_exp: u32, mant: u32) -> f32 {
    f32::from_bits(sign | ((biased_exp - 1) << 23).wrapping_add(mant))
}

/// x·log₂e = k + f, f ∈ [0, 1) in Q0.32, for 2⁻²⁵ ≤ |x| < 128 (`be` the
/// biased exponent, `m` the mantissa with hidden bit).
#[inline]
fn split(neg: bool, be: u32, m: u32) -> (i16, u32) {
    // |x| = m·2^(be − 150) = X·2⁻²⁵ with X < 2³² (exact for |x| ≥ 0.25;
    // smaller |x| round to 2⁻²⁶, far below the result's ulp near 1).
    let xq = if be >= 125 {
        m << (be - 125)
    } else {
        let r = 125 - be;
        (m + (1 << (r - 1))) >> r
    };
    // |x|·log₂e = (hi:lo)·2⁻⁵⁶: integer part hi >> 24, fraction the next 32 bits.
    let (hi, lo) = mul_full(xq, LOG2E_Q31);
    let k = (hi >> 24) as i16;
    let f = (hi << 8) | (lo >> 24);
    if !neg {
        (k, f)
    } else if f == 0 {
        (-k, 0)
    } else {
        (-k - 1, f.wrapping_neg())
    }
}

/// e^x. NaN gives NaN, ±∞ gives ∞ / 0, overflow ∞, results below the
/// smallest normal f32 give 0.
pub fn exp(x: f32) -> f32 {
    let b = x.to_bits();
    let neg = b >> 31 != 0;
    let be = (b >> 23) & 0xFF;
    if be == 0xFF {
        return if b & MANT_MASK != 0 {
            x
        } else if neg {
            0.0
        } else {
            f32::INFINITY
        };
    }
    if be < 102 {
        // |x| < 2⁻²⁵: 1 + x rounds to 1.
        return 1.0;
    }
    if be >= 134 {
        return if neg { 0.0 } else { f32::INFINITY };
    }
    let (k, f) = split(neg, be, (b & MANT_MASK) | HIDDEN);
    if k > 127 {
        return f32::INFINITY;
    }
    if k < -126 {
        return 0.0;
    }
    let m = (1 << 31) + pow2m1_q31(f);
    pack(0, (k + 127) as u32, round_mant(m))
}

/// e^x − 1, accurate for small |x| (no cancellation).
pub fn expm1(x: f32) -> f32 {
    let b = x.to_bits();
    let neg = b >> 31 != 0;
    let be = (b >> 23) & 0xFF;
    if be == 0xFF {
        return if b & MANT_MASK != 0 {
            x
        } else if neg {
            -1.0
        } else {
            f32::INFINITY
        };
    }
    if be < 103 {
        // |x| < 2⁻²⁴: e^x − 1 = x·(1 + x/2 + …) rounds to x (zero and
        // subnormals included).
        return x;
    }
    if be >= 134 {
        return if neg { -1.0 } else { f32::INFINITY };
    }
    let m = (b & MANT_MASK) | HIDDEN;
    if be <= 126 && !neg && (be < 126 || m < 0x00B1_7218) {
        return expm1_small(be, m);
    }
    if neg && be <= 126 && (be < 126 || m < 0x00B1_7218) {
        // −ln 2 < x < 0: e^x − 1 = −e^|x|·(1 − e^−|x|) = −m/(1 + m) with
        // m = expm1(|x|) ∈ (0, 1): no cancellation, two more roundings.
        let p = expm1_small(be, m);
        return -(p / (1.0 + p));
    }
    let (k, f) = split(neg, be, m);
    // 2^f in Q1.31 (bit 31 set): the value is mm·2^(k − 31).
    let mm = (1 << 31) + pow2m1_q31(f);
    if k >= 1 {
        if k > 127 {
            return f32::INFINITY;
        }
        let mut e = k;
        let mut d = if k <= 31 { mm - (1 << (31 - k)) } else { mm };
        // d ≥ 2³⁰ (k ≥ 1): at most one normalizing shift.
        if d < (1 << 31) {
            d <<= 1;
            e -= 1;
        }
        pack(0, (e + 127) as u32, round_mant(d))
    } else {
        // k ≤ −1 (x ≤ −ln 2): e^x = v·2⁻³² ≤ 1/2, so 1 − e^x ≥ 1/2 in Q0.32
        // needs at most one normalizing shift.
        let sh = (-k - 1) as u32;
        let v = if sh >= 32 { 0 } else { mm >> sh };
        if v == 0 {
            return -1.0;
        }
        let d = 0u32.wrapping_sub(v);
        let lz = d.leading_zeros();
        pack(1 << 31, 126 - lz, round_mant(d << lz))
    }
}

/// expm1 for 2⁻²⁴ ≤ x < ln 2: f = x·log₂e < 1 carried with its own exponent,
/// e^x − 1 = 2^f − 1 = f·S(f).
#[inline]
fn expm1_small(be: u32, m: u32) -> f32 {
    // f = mt·2^(be − 157), mt ∈ [1.44·2³⁰, 1.45·2³¹).
    let mt = mul_hi(m << 8, LOG2E_Q31);
    // f in Q0.32 for the polynomial (absolute precision suffices there).
    let fq = if be == 126 { mt << 1 } else { mt >> (125 - be) };
    let s = s_poly(fq);
    // f·S = r·2^(be − 156); r ∈ [2²⁹, 2³¹) up to truncation (S ≥ ln 2).
    let r = mul_hi(mt, s);
    let (rn, lz) = if r >= 1 << 30 {
        (r << 1, 1)
    } else if r >= 1 << 29 {
        (r << 2, 2)
    } else {
        (r << 3, 3)
    };
    pack(0, be + 2 - lz, round_mant(rn))
}
