//! `exp`, `expm1` and `ln` for f32 with a 32-bit integer core: the chip's
//! per-frame exponentials
//! and plan-time logarithms, and the very same code on the host, so host tests
//! check the chip's results bit for bit (the cores are integer arithmetic; the
//! only float operations are in the rarely used negative-`expm1` branch).
//!
//! Why not avr-libc's `exp`/`log` (~2 500 cycles each) or a float polynomial:
//! every soft-float operation costs 150–550 cycles on the AVR, while a
//! 32×32-bit high product built from four hardware 16×16 products costs ~100.
//!
//! `exp` method: x·log₂e = k + f with k an integer and f ∈ [0, 1), formed
//! exactly from the float's bits (|x| < 128 as Q7.25, a 64-bit product with
//! log₂e in Q1.31). Then 2^f = 1 + f·S(f) with S(f) = (2^f − 1)/f a degree-5
//! polynomial (near-minimax, |error| ≤ 1.1e-8) in Q1.31 by Horner, and 2^k
//! goes into the exponent field. `expm1` for 0 < x < ln 2 forms f = x·log₂e
//! from the mantissa (relative precision, no cancellation) and returns
//! f·S(f); above, 2^k·2^f − 1 loses at most one bit of 32. `ln`: see [`ln`].
//!
//! Accuracy (checked against f64 over dense sweeps in tests/chip_accuracy.rs):
//! `exp` and `expm1` for x ≥ 0 within 1 ulp; `expm1` for −ln 2 < x < 0 (only
//! used at plan time) within 3 ulp; `ln` within 1 ulp (measured 0.65) over
//! the whole positive range, subnormals included. Results below the smallest
//! normal f32 are returned as 0 (avr-libc has no subnormals either). Cost on
//! the chip: ~800 cycles for `exp`, ~870–1 000 for `expm1`, ~900–1 150 for
//! `ln` (BENCHMARKS.md).

use super::fixed::{
    flash_u32, leading_zeros, mul16, mul_full, mul_hi, mul_hi_approx, pack, round_mant, shl, shr, HIDDEN, MANT_MASK,
};

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

/// x·log₂e = k + f, f ∈ [0, 1) in Q0.32, for 2⁻²⁵ ≤ |x| < 128 (`be` the
/// biased exponent, `m` the mantissa with hidden bit).
#[inline]
fn split(neg: bool, be: u8, m: u32) -> (i16, u32) {
    // |x| = m·2^(be − 150) = X·2⁻²⁵ with X < 2³² (exact for |x| ≥ 0.25;
    // smaller |x| round to 2⁻²⁶, far below the result's ulp near 1).
    // = round(m·2⁸ / 2^s), s = 133 − be ∈ [0, 31]; for s ≤ 8 the low bits
    // are zero and the rounding changes nothing. One shift, no branch on be.
    let s = u32::from(133 - be);
    let v = m << 8;
    let w = shr(v, s.saturating_sub(1));
    let xq = if s == 0 { v } else { (w + 1) >> 1 };
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
    // One byte: compares on it are single instructions on the AVR.
    let be = (b >> 23) as u8;
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
    // One byte: compares on it are single instructions on the AVR.
    let be = (b >> 23) as u8;
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
        // 2^k·2^f − 1 = (mm − 2^(31 − k))·2^(k − 31); beyond k = 31 the 1 is
        // lost. 2^(31 − k) as 2³¹ >> k: k is small for the usual arguments,
        // so the shift loop is short (31 − k steps cost up to ~350 cycles).
        let one = shr(1 << 31, u32::from((k as u16).min(31)));
        let mut d = if k <= 31 { mm - one } else { mm };
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
        let v = shr(mm, sh.min(31));
        let v = if sh >= 32 { 0 } else { v };
        if v == 0 {
            return -1.0;
        }
        let d = 0u32.wrapping_sub(v);
        let lz = leading_zeros(d);
        pack(1 << 31, 126 - lz, round_mant(shl(d, lz)))
    }
}

/// expm1 for 2⁻²⁴ ≤ x < ln 2: f = x·log₂e < 1 carried with its own exponent,
/// e^x − 1 = 2^f − 1 = f·S(f).
#[inline]
fn expm1_small(be: u8, m: u32) -> f32 {
    // f = mt·2^(be − 157), mt ∈ [1.44·2³⁰, 1.45·2³¹).
    let mt = mul_hi(m << 8, LOG2E_Q31);
    // f in Q0.32 for the polynomial (absolute precision suffices there).
    // (mt << 1) >> s without losing mt's top bit.
    let w = shr(mt, u32::from(126 - be).saturating_sub(1));
    let fq = if be == 126 { mt << 1 } else { w };
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
    pack(0, u32::from(be) + 2 - lz, round_mant(rn))
}

// ------------------------------------------------------------------- ln

/// ln 2 in Q0.32 (rounded; error 0.18·2⁻³²).
const LN2_Q32: u32 = 0xB172_17F8;

/// For k = 1..14 (mantissa m ∈ [1 + k/16, 1 + (k+1)/16)): C ≈ 1/(1 + (k+½)/16)
/// in Q0.32 and −ln C in Q0.32 (of the stored C, rounded). m·C − 1 then lies
/// within ±1/35. In flash on the AVR (read with `lpm`), not in RAM.
#[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
static LN_TABLE: [[u32; 2]; 14] = [
    [0xEA0E_A0EA, 0x16F0_D28B],
    [0xDD67_C8A6, 0x252A_A5F0],
    [0xD20D_20D2, 0x32A4_B53A],
    [0xC7CE_0C7D, 0x3F72_30DB],
    [0xBE82_FA0C, 0x4BA3_8AEB],
    [0xB60B_60B6, 0x5746_F6FD],
    [0xAE4C_415D, 0x6268_CE1A],
    [0xA72F_0539, 0x6D13_DDF0],
    [0xA0A0_A0A1, 0x7751_A812],
    [0x9A90_E7D9, 0x812A_952E],
    [0x94F2_094F, 0x8AA6_1E98],
    [0x8FB8_23EE, 0x93CA_F094],
    [0x8AD8_F2FC, 0x9C9F_069A],
    [0x864B_8A7E, 0xA527_C2ED],
];

/// |S(r)| = −(ln(1 + r) − r)/r² on r ∈ [−1/32, 1/16] as Σ Tᵢ·|r|ⁱ with the
/// signs of the alternating series folded in (see [`ln_s`]); Q0.32,
/// near-minimax (Chebyshev fit), |error| ≤ 9.7e-8 (r² times that in ln).
const T0: u32 = 2_147_483_562;
const T1: u32 = 1_431_691_999;
const T2: u32 = 1_074_270_779;
const T3: u32 = 816_956_759;

/// |S(r)| for r = ±ρ (ρ = |r| ≤ 1/16 in Q0.32), Q0.32: S's coefficients
/// alternate in sign, so for r < 0 every term adds and for r > 0 every
/// bracket stays positive; either way only unsigned products.
/// One body for [`ln_near_one`] and [`ln_sum`] (three inlined multiplies
/// each otherwise).
#[inline(never)] // reason: code-size
fn ln_s(rho: u32, neg: bool) -> u32 {
    if neg {
        let t = T2 + mul_hi_approx(T3, rho);
        let t = T1 + mul_hi_approx(t, rho);
        T0 + mul_hi_approx(t, rho)
    } else {
        let t = T2 - mul_hi_approx(T3, rho);
        let t = T1 - mul_hi_approx(t, rho);
        T0 - mul_hi_approx(t, rho)
    }
}

/// (biased exponent, fraction) of a subnormal's mantissa `m` ≠ 0, as if
/// the exponent field could go below 1. Out of line: it shifts by an amount
/// of its own (see the note on shifts above).
#[cold]
#[inline(never)] // reason: cold
fn normalize_subnormal(m: u32) -> (i16, u32) {
    let sh = leading_zeros(m) - 8;
    (1 - sh as i16, shl(m, sh) & MANT_MASK)
}

/// Natural logarithm. ln(±0) = −∞, ln(x < 0) = NaN, ln(∞) = ∞, NaN gives
/// NaN.
///
/// x = 2^e·m; the mantissa's top four fraction bits pick C ≈ 1/m from a
/// 14-entry table (m ≥ 1.9375 is taken as m/2 with e + 1, m < 1.0625 as is),
/// so ln x = e·ln 2 − ln C + ln(1 + r) with r = m·C − 1 ∈ [−1/32, 1/16] and
/// ln(1 + r) = r − r²·|S(r)|. Where e = 0 and C = 1 (x ∈ [0.96875, 1.0625))
/// r is exact and the result is formed as r·(1 − r·|S|) with relative
/// precision; elsewhere |ln x| > 0.03 and the sum is formed in Q.32 fixed
/// point. Within 1 ulp (tests/chip_accuracy.rs sweeps it against f64).
pub fn ln(x: f32) -> f32 {
    let b = x.to_bits();
    if b >= 0x7F80_0000 {
        // +∞, NaN, or negative (−0 included).
        return if b == 0x7F80_0000 {
            x
        } else if b == 0x8000_0000 {
            f32::NEG_INFINITY
        } else {
            f32::NAN
        };
    }
    let mut be = (b >> 23) as i16;
    let mut m = b & MANT_MASK;
    if be == 0 {
        if m == 0 {
            return f32::NEG_INFINITY;
        }
        (be, m) = normalize_subnormal(m);
    }
    let e = be - 127;
    let k = (m >> 19) as usize;
    // r in Q0.32 as a magnitude and a sign; −ln C = 0 here. Each path ends
    // in a call, so `ln` itself holds nothing across one.
    if k == 0 {
        let rho = m << 9;
        if e == 0 {
            return ln_near_one(rho, false);
        }
        ln_sum(e, 0, rho, false)
    } else if k == 15 {
        // m/2 with e + 1: r = m/2 − 1 < 0.
        let rho = (HIDDEN << 1).wrapping_sub(m | HIDDEN) << 8;
        if e == -1 {
            return ln_near_one(rho, true);
        }
        ln_sum(e + 1, 0, rho, true)
    } else {
        ln_table(e, m, k)
    }
}

/// [`ln`] for mantissas 1 + k/16 + … with k = 1..14: r = m·C − 1 from the
/// table's C, then the sum ([`ln_sum`]'s one body, called: a second inlined
/// copy took ~1.3 KB of flash).
#[inline(never)] // reason: register-pressure
fn ln_table(e: i16, m: u32, k: usize) -> f32 {
    let (c, ln_c) = match LN_TABLE.get(k.wrapping_sub(1)) {
        Some(row) => (flash_u32(&row[0]), flash_u32(&row[1])),
        None => return f32::NAN,
    };
    // m·C in Q1.63; r = m·C − 1 in Q0.32 from bits 31 + 32 down.
    let (hi, lo) = mul_full((m | HIDDEN) << 8, c);
    let r = (hi.wrapping_sub(1 << 31) << 1) | (lo >> 31);
    let neg = r >> 31 != 0;
    ln_sum(e, ln_c, if neg { r.wrapping_neg() } else { r }, neg)
}

/// ln(1 + r) for r = ±ρ exact (x ∈ [0.96875, 1.0625)), with relative
/// precision.
#[inline(never)] // reason: register-pressure
fn ln_near_one(rho: u32, neg: bool) -> f32 {
    if rho == 0 {
        return 0.0;
    }
    let s = ln_s(rho, neg);
    // ln(1 + r) = r·P, P = 1 − r·|S| in Q1.31 (P ∈ [0.97, 1.02]).
    let rs = mul_hi(rho, s) >> 1;
    let p = if neg { (1u32 << 31) + rs } else { (1u32 << 31) - rs };
    let lz = leading_zeros(rho);
    // r·P = h·2^(−31 − lz) with h ∈ [0.48, 1.02)·2³¹.
    let mut h = mul_hi(shl(rho, lz), p);
    let mut sh = lz;
    while h < 1 << 31 {
        h <<= 1;
        sh += 1;
    }
    pack(if neg { 1 << 31 } else { 0 }, 127 - sh, round_mant(h))
}

/// [`ln_sum_core`] for every k (for k = 0 and 15 −ln C = 0; [`ln_table`]
/// calls it for the others). Out of line: with the sum inlined into [`ln`], LLVM's AVR backend
/// produced wrong results (seen with nightly-2026-05-20; as code of its own
/// it is right, and bench_elf checks the chip against the host).
#[inline(never)] // avr-trap: inline-miscompile
fn ln_sum(e: i16, ln_c: u32, rho: u32, neg: bool) -> f32 {
    ln_sum_core(e, ln_c, rho, neg)
}

/// e·ln 2 − ln C + r − r²·|S| (r = ±ρ) in Q.32 fixed point (|sum| < 2⁴⁰),
/// rounded to f32; |result| > 0.03 here.
#[inline(always)]
fn ln_sum_core(e: i16, ln_c: u32, rho: u32, neg: bool) -> f32 {
    let s = ln_s(rho, neg);
    // |e| ≤ 149: two hardware products.
    let ea = e.unsigned_abs();
    let e_ln2 = (u64::from(mul16(ea, (LN2_Q32 >> 16) as u16)) << 16) + u64::from(mul16(ea, LN2_Q32 as u16));
    let r2s = mul_hi_approx(mul_hi_approx(rho, rho), s);
    // −ln C ± ρ − r²·|S| as a sum and a difference of magnitudes (each
    // < 2³²: −ln C < 0.65, ρ ≤ 1/16), so no signed 64-bit work.
    let (plus, minus) = if neg { (ln_c, rho + r2s) } else { (ln_c + rho, r2s) };
    // The sum has the sign of ln x, which is e's: e < 0 means x < 1, and
    // e ≥ 0 here means x > 1.06 (e = 0 with C = 1 took the other path);
    // |ln x| > 0.03 dwarfs the sum's error. So the magnitude is formed
    // directly, |e|·ln 2 plus one part minus the other, with no sign test
    // or negation on 64 bits.
    let (sign, add, sub) = if e < 0 { (1u32 << 31, minus, plus) } else { (0, plus, minus) };
    let mag = e_ln2 + u64::from(add) - u64::from(sub);
    // Normalize the 40-bit mag: its top 32 bits and the byte below them,
    // shifted left until bit 31 is set; the exponent counts down from 134
    // (lz = 0: mag ≥ 2³⁹). |ln x| > 0.03 puts mag ≥ 2²⁷, so where the top
    // byte is zero the next one is ≥ 8 and a byte move leaves at most 4
    // one-bit steps; otherwise at most 7.
    let (top, low, be) = if mag >> 32 == 0 { (mag as u32, 0, 126) } else { ((mag >> 8) as u32, mag as u8, 134) };
    if top == 0 {
        // Unreachable (mag ≥ 2²⁷); keeps the normalization finite.
        return 0.0;
    }
    let (top, be) = normalize(top, low, be);
    pack(sign, u32::from(be), round_mant(top))
}

/// Shifts the 40-bit `top:low` left until bit 31 of `top` is set, one bit
/// per step, decrementing `be` per step; `top` ≠ 0. On the AVR a five-byte
/// rotate loop (8 cycles a step): LLVM's code for the same loop in Rust
/// took 20.
#[inline(always)]
fn normalize(top: u32, low: u8, be: u8) -> (u32, u8) {
    #[cfg(target_arch = "avr")]
    {
        let (mut hi, mut lo, mut low, mut be) = ((top >> 16) as u16, top as u16, low, be);
        // SAFETY: register-only arithmetic on the operands; terminates as
        // top ≠ 0.
        unsafe {
            core::arch::asm!(
                "tst {hi:h}",
                "brmi 2f",
                "1:",
                "dec {be}",
                "lsl {low}",
                "rol {lo:l}",
                "rol {lo:h}",
                "rol {hi:l}",
                "rol {hi:h}",
                "brpl 1b",
                "2:",
                hi = inout(reg_pair) hi,
                lo = inout(reg_pair) lo,
                low = inout(reg) low,
                be = inout(reg) be,
                options(pure, nomem, nostack),
            );
        }
        let _ = low;
        ((u32::from(hi) << 16) | u32::from(lo), be)
    }
    #[cfg(not(target_arch = "avr"))]
    {
        let (mut top, mut low, mut be) = (top, low, be);
        while top < 1 << 31 {
            top = (top << 1) | u32::from(low >> 7);
            low <<= 1;
            be -= 1;
        }
        (top, be)
    }
}
