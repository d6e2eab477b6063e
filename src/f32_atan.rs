//! `atan2` for f32 with a 32-bit integer core, in the style of
//! [`crate::f32_exp`]: the same code on the chip and on the host, so host
//! tests check the chip's results bit for bit. avr-libc's `atan2` costs
//! ~3 000 cycles; this one is one float division plus a few hardware 16×16
//! products.
//!
//! Method: t = min(|y|, |x|)/max(|y|, |x|) ∈ [0, 1] (one IEEE division, the
//! only float operation). For t < 1/8, atan t = t·P(t²) with P a degree-3
//! polynomial in Q1.31, kept relative to t (small angles keep their relative
//! precision). For t ∈ [1/8, 1], atan t is one of fourteen degree-4 polynomials
//! in d = t − (2k + 1)/32 (|d| ≤ 1/32, near-minimax, |error| ≤ 2.6e-10) in
//! Q0.31, coefficients in flash. The octant is then folded in fixed point
//! (π/2 − a, π − a, Q2.30) and the result rounded once.
//!
//! Accuracy (tests/chip_accuracy.rs, against f64 over dense sweeps of both
//! arguments): within 1.5 ulp; the rounding of t contributes up to ½ ulp of
//! a result below π/4, the fixed-point core under 0.1 ulp, the final rounding
//! ½ ulp. Special values follow IEEE 754 / C99 `atan2`.

use crate::f32_exp::{flash_u32, mul_hi, mul_hi_approx, pack, round_mant, shl, shr, HIDDEN, MANT_MASK};

/// π/2, π/4, 3π/4 and π in Q2.30 (rounded).
const PI_2_Q30: u32 = 1_686_629_713;
const PI_4_Q30: u32 = 843_314_857;
const PI_3_4_Q30: u32 = 2_529_944_570;
const PI_Q30: u32 = 3_373_259_426;

/// atan on [k/16, (k+1)/16], k = 2..15, as Σ cⱼ·dʲ with d = t − (2k+1)/32,
/// c₄ first, i32 in Q0.31 (as bit patterns); near-minimax (Chebyshev fit),
/// |error| ≤ 2.6e-10. In flash on the AVR, not in RAM.
#[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
static ATAN_TABLE: [[u32; 5]; 14] = [
    [0x11B2_9E68, 0xDB3D_566C, 0xECF1_2298, 0x7CF3_1081, 0x13D6_EEE9],
    [0x1617_91B5, 0xE040_A782, 0xE67F_B9DA, 0x7A27_9AA1, 0x1B90_D753],
    [0x186D_B62A, 0xE61B_A1B3, 0xE115_9ABD, 0x769E_0062, 0x2317_EB46],
    [0x18CD_CD37, 0xEC4C_346E, 0xDCCE_E5BF, 0x7279_2E50, 0x2A61_5B33],
    [0x178E_18CB, 0xF25E_B7DB, 0xD9B0_68F7, 0x6DDE_1895, 0x3164_9A73],
    [0x1525_1257, 0xF7F9_B168, 0xD7AB_9102, 0x68F1_09CF, 0x381B_6993],
    [0x120D_D660, 0xFCE2_532A, 0xD6A3_DE4C, 0x63D3_8C00, 0x3E81_BA17],
    [0x0EB4_5AA5, 0x00FA_FC77, 0xD674_98FD, 0x5EA3_070D, 0x4495_7670],
    [0x0B6B_25CF, 0x043D_F925, 0xD6F5_D795, 0x5978_0CC8, 0x4A56_3965],
    [0x0869_191C, 0x06B6_BD27, 0xD800_5B74, 0x5466_33F0, 0x4FC4_FEE2],
    [0x05CC_7D4B, 0x087B_49F1, 0xD970_2636, 0x4F7C_5A31, 0x54E3_D5EE],
    [0x03A0_8AA6, 0x09A6_B2DF, 0xDB25_EA13, 0x4AC5_25F2, 0x59B5_98E5],
    [0x01E3_5FB3, 0x0A55_1980, 0xDD07_95C0, 0x4647_A726, 0x5E3D_AEF5],
    [0x008B_391C, 0x0AA1_138B, 0xDF00_427D, 0x4207_FF0A, 0x627F_D7FD],
];

/// atan(√u)/√u = 1 − u·(P1 − u·(P2 − u·P3)) on u ∈ [0, 1/64], Q0.32
/// (near-minimax; |error| ≤ 1e-10).
const P1: u32 = 1_431_655_321;
const P2: u32 = 858_851_118;
const P3: u32 = 598_911_783;

/// ⌊a·b / 2³²⌋ (or one or two less) for signed a, b, from the unsigned
/// product: a two's-complement factor adds 2³² times the other one.
#[inline]
fn mul_hi_signed(a: i32, b: i32) -> i32 {
    let mut h = mul_hi_approx(a as u32, b as u32);
    if a < 0 {
        h = h.wrapping_sub(b as u32);
    }
    if b < 0 {
        h = h.wrapping_sub(a as u32);
    }
    h as i32
}

/// atan t in Q0.31 for t ∈ [1/8, 1] given in Q1.31.
#[inline]
fn atan_mid(t31: u32) -> u32 {
    let k = (t31 >> 27).clamp(2, 15);
    // d = t − (2k + 1)/32 in Q0.32; |d| ≤ 1/32.
    let d = (t31.wrapping_sub((2 * k + 1) << 26) as i32) << 1;
    let Some(row) = ATAN_TABLE.get(k as usize - 2) else {
        return 0;
    };
    let mut v = flash_u32(&row[0]) as i32;
    for c in &row[1..] {
        v = (flash_u32(c) as i32).wrapping_add(mul_hi_signed(v, d));
    }
    v as u32
}

/// atan(t)/t in Q1.31 for t = mt·2^(et − 150) ∈ [2⁻²⁷, 1/8).
#[inline]
fn atan_small_ratio(et: u32, mt: u32) -> u32 {
    // t in Q0.32 = mt·2^(et − 118) = (mt·2⁵) >> (123 − et), et ∈ [100, 123].
    let u = {
        let t32 = shr(mt << 5, 123u32.saturating_sub(et));
        mul_hi(t32, t32)
    };
    let b = P2 - mul_hi_approx(P3, u);
    let b = P1 - mul_hi_approx(b, u);
    (1u32 << 31) - (mul_hi_approx(b, u) >> 1)
}

/// A positive Q(31 − `frac`).`frac` value (nonzero) as f32 with `sign`.
#[inline]
fn from_fixed(v: u32, frac: u32, sign: u32) -> f32 {
    let lz = v.leading_zeros();
    // v·2^−frac = (top/2³¹)·2^(31 − lz − frac).
    pack(sign, 158 - lz - frac, round_mant(shl(v, lz)))
}

/// The angle of (x, y) in (−π, π]; see the module notes.
pub fn atan2(y: f32, x: f32) -> f32 {
    let (by, bx) = (y.to_bits(), x.to_bits());
    let (ay, ax) = (by & 0x7FFF_FFFF, bx & 0x7FFF_FFFF);
    let sign = by & 0x8000_0000;
    let x_neg = bx >> 31 != 0;
    const INF: u32 = 0x7F80_0000;
    if ay > INF || ax > INF {
        return f32::NAN;
    }
    // |θ| in Q2.30, unless returned directly.
    let theta = if ay == 0 {
        if x_neg {
            PI_Q30
        } else {
            return y;
        }
    } else if ax == 0 {
        PI_2_Q30
    } else if ay == INF {
        if ax != INF {
            PI_2_Q30
        } else if x_neg {
            PI_3_4_Q30
        } else {
            PI_4_Q30
        }
    } else if ax == INF {
        if x_neg {
            PI_Q30
        } else {
            return f32::from_bits(sign);
        }
    } else {
        let swap = ay > ax;
        let (lo, hi) = if swap { (ax, ay) } else { (ay, ax) };
        let tb = (f32::from_bits(lo) / f32::from_bits(hi)).to_bits();
        let et = tb >> 23;
        let mt = (tb & MANT_MASK) | HIDDEN;
        // atan t, with t's relative precision wherever |θ| = atan t. Each
        // arm yields (value, right shift to Q0.31): see the note on shifts
        // in f32_exp (no arm shifts by an amount of its own).
        let direct = !swap && !x_neg;
        // t in Q1.31 where t ≥ 1/8 (a shift of 5..8); formed for every t.
        let t31 = shl(mt, et.saturating_sub(119).min(8));
        let (v, sh) = if et >= 124 {
            let a = atan_mid(t31);
            if direct {
                return from_fixed(a, 31, sign);
            }
            (a, 0)
        } else if et < 100 {
            // t < 2⁻²⁷ (or subnormal): atan t = t to far below an ulp.
            if direct {
                return f32::from_bits(tb | sign);
            }
            // t in Q0.31 = mt·2^(et − 119).
            if et == 0 || et + 32 <= 119 {
                (0, 0)
            } else {
                (mt, 119 - et)
            }
        } else {
            // t·P(t²) = h·2^(et − 157), h ∈ [0.49, 1)·2³¹.
            let h = mul_hi(mt << 8, atan_small_ratio(et, mt));
            if direct {
                let lz = h.leading_zeros();
                return pack(sign, et + 1 - lz, round_mant(shl(h, lz)));
            }
            (h, 126 - et)
        };
        let a31 = shr(v, sh);
        let a30 = (a31 + 1) >> 1;
        let b = if swap { PI_2_Q30 - a30 } else { a30 };
        if x_neg {
            PI_Q30 - b
        } else {
            b
        }
    };
    from_fixed(theta, 30, sign)
}
