//! `atan2` for f32 with a 32-bit integer core, in the style of
//! [`crate::math::exp`]: the same code on the chip and on the host, so host
//! tests check the chip's results bit for bit. avr-libc's `atan2` costs
//! ~3 000 cycles; this one is one float division plus a few hardware 16×16
//! products.
//!
//! Method: t = min(|y|, |x|)/max(|y|, |x|) ∈ [0, 1] (one IEEE division, the
//! only float operation). For t < 1/8, atan t = t·P(t²) with P a degree-3
//! polynomial in Q1.31, kept relative to t (small angles keep their relative
//! precision). For t ∈ [1/8, 1], atan t is one of 56 degree-3 polynomials
//! in d = t − k/64 (0 ≤ d ≤ 1/64, near-minimax, |error| ≤ 9.1e-11) with
//! unsigned Horner steps in Q0.32, coefficients in flash. The octant is then
//! folded in fixed point (π/2 − a, π − a, Q2.30) and the result rounded once.
//!
//! Accuracy (tests/chip_accuracy.rs, against f64 over dense sweeps of both
//! arguments): within 1.5 ulp; the rounding of t contributes up to ½ ulp of
//! a result below π/4, the fixed-point core under 0.1 ulp, the final rounding
//! ½ ulp. Special values follow IEEE 754 / C99 `atan2`.

use crate::math::fixed::{
    flash_u32, leading_zeros, mul16, mul_hi, mul_hi_approx, pack, round_mant, shl, shr, HIDDEN, MANT_MASK,
};

/// π/2, π/4, 3π/4 and π in Q2.30 (rounded).
const PI_2_Q30: u32 = 1_686_629_713;
const PI_4_Q30: u32 = 843_314_857;
const PI_3_4_Q30: u32 = 2_529_944_570;
const PI_Q30: u32 = 3_373_259_426;

/// atan on [k/64, (k+1)/64], k = 8..63, as c₀ + c₁·d − (m₂ − c₃·d)·d² with
/// d = t − k/64 ∈ [0, 1/64] (m₂ = −c₂ > 0): degree-3 near-minimax (Remez),
/// |error| ≤ 9.1e-11. Rows [c₀, c₁, m₂, c₃] in Q0.32, c₃ as an i32 bit
/// pattern (its sign changes near t = 1/√3); every other Horner stage keeps
/// one sign, so the products are unsigned. In flash on the AVR, not in RAM.
/// `scripts/atan_table.py` regenerates it and checks [`atan_mid`] bit for bit.
#[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
static ATAN_TABLE: [[u32; 4]; 56] = [
    [0x1FD5_BA9A, 0xFC0F_C2EC, 0x1F08_48BE, 0xB350_E229],
    [0x23C3_F5F6, 0xFB09_23E4, 0x22A0_ABA0, 0xB55A_BE3D],
    [0x27AD_DDD1, 0xF9E6_23F7, 0x2620_94AA, 0xB791_774F],
    [0x2B93_023C, 0xF8A7_8F58, 0x2985_E94E, 0xB9F1_548E],
    [0x2F72_F697, 0xF74E_4257, 0x2CCE_BBB2, 0xBC76_6F5B],
    [0x334D_51D3, 0xF5DB_27FA, 0x2FF9_4CD8, 0xBF1C_BEAE],
    [0x3721_AEA5, 0xF44F_387E, 0x3304_0E38, 0xC1E0_2269],
    [0x3AEF_ABBE, 0xF2AB_77CB, 0x35ED_A2D7, 0xC4BC_6E84],
    [0x3EB6_EBF2, 0xF0F0_F3EA, 0x38B4_DFD6, 0xC7AD_75AE],
    [0x4277_165F, 0xEF20_C374, 0x3B58_CC7D, 0xCAAF_1388],
    [0x462F_D68C, 0xED3C_0400, 0x3DD8_A1D1, 0xCDBD_3631],
    [0x49E0_DC81, 0xEB43_D898, 0x4033_C9B9, 0xD0D3_E6F1],
    [0x4D89_DCDC, 0xE939_683C, 0x4269_DDB0, 0xD3EF_5219],
    [0x512A_90DB, 0xE71D_DC67, 0x447A_A526, 0xD70B_CDEB],
    [0x54C2_B665, 0xE4F2_5FA8, 0x4666_1384, 0xDA25_E08D],
    [0x5852_100C, 0xE2B8_1C4E, 0x482C_45EE, 0xDD3A_4500],
    [0x5BD8_6507, 0xE070_3B23, 0x49CD_80C6, 0xE045_EF19],
    [0x5F55_812D, 0xDE1B_E23A, 0x4B4A_2D05, 0xE346_0E86],
    [0x62C9_34E5, 0xDBBC_33D8, 0x4CA2_D569, 0xE638_10E4],
    [0x6633_5515, 0xD952_4D73, 0x4DD8_238A, 0xE919_A2F7],
    [0x6993_BB0F, 0xD6DF_46C3, 0x4EEA_DCEC, 0xEBE8_B113],
    [0x6CEA_4476, 0xD464_30F2, 0x4FDB_DFFA, 0xEEA3_66C3],
    [0x7036_D325, 0xD1E2_15DF, 0x50AC_2116, 0xF148_2DC1],
    [0x7379_4D0C, 0xCF59_F77A, 0x515C_A7AA, 0xF3D5_AC76],
    [0x76B1_9C15, 0xCCCC_CF37, 0x51EE_8B51, 0xF64A_C3C9],
    [0x79DF_ADFC, 0xCA3B_8D98, 0x5262_F119, 0xF8A6_8C9E],
    [0x7D03_742D, 0xC7A7_19CD, 0x52BB_08E2, 0xFAE8_54FD],
    [0x801C_E39E, 0xC510_5165, 0x52F8_0AE2, 0xFD0F_9CE5],
    [0x832B_F4A7, 0xC278_0814, 0x531B_3548, 0xFF1C_12F9],
    [0x8630_A2DB, 0xBFDF_0790, 0x5325_CA15, 0x010D_9100],
    [0x892A_ECE0, 0xBD46_0F78, 0x5319_0D0C, 0x02E4_1855],
    [0x8C1A_D446, 0xBAAD_D54C, 0x52F6_41E0, 0x049F_CE56],
    [0x8F00_5D5F, 0xB817_0476, 0x52BE_AA7F, 0x0640_F8CE],
    [0x91DB_8F16, 0xB582_3E5E, 0x5273_858E, 0x07C7_FA78],
    [0x94AC_72C9, 0xB2F0_1A8C, 0x5216_0D0C, 0x0935_4F9A],
    [0x9773_1420, 0xB061_26CB, 0x51A7_7526, 0x0A89_8ABE],
    [0x9A2F_80E6, 0xADD5_E763, 0x5128_EB25, 0x0BC5_5190],
    [0x9CE1_C8E6, 0xAB4E_D752, 0x509B_9489, 0x0CE9_59F1],
    [0x9F89_FDC5, 0xA8CC_6888, 0x5000_8E4D, 0x0DF6_672A],
    [0xA228_32DC, 0xA64F_0437, 0x4F58_EC40, 0x0EED_4758],
    [0xA4BC_7D19, 0xA3D7_0B16, 0x4EA5_B885, 0x0FCE_D10E],
    [0xA746_F2DE, 0xA164_D5B3, 0x4DE7_F330, 0x109B_E11C],
    [0xA9C7_ABDC, 0x9EF8_B4C7, 0x4D20_91F6, 0x1155_5896],
    [0xAC3E_C0FC, 0x9C92_F185, 0x4C50_8001, 0x11FC_1B00],
    [0xAEAC_4C39, 0x9A33_CDF4, 0x4B78_9DCE, 0x1291_0CB6],
    [0xB110_688B, 0x97DB_8540, 0x4A99_C124, 0x1315_1175],
    [0xB36B_31C9, 0x958A_4C12, 0x49B4_B51B, 0x1389_0B1A],
    [0xB5BC_C490, 0x9340_50E5, 0x48CA_3A37, 0x13ED_D882],
    [0xB805_3E2C, 0x90FD_BC59, 0x47DB_0684, 0x1444_5497],
    [0xBA44_BC7E, 0x8EC2_B187, 0x46E7_C5CF, 0x148D_5580],
    [0xBC7B_5DEB, 0x8C8F_4E51, 0x45F1_19D8, 0x14C9_ABEC],
    [0xBEA9_4145, 0x8A63_ABB4, 0x44F7_9A96, 0x14FA_2287],
    [0xC0CE_85B9, 0x883F_DE11, 0x43FB_D680, 0x151F_7D7C],
    [0xC2EB_4ABB, 0x8623_F57A, 0x42FE_52DD, 0x153A_7A26],
    [0xC4FF_AFFB, 0x840F_FDFD, 0x41FF_8C0F, 0x154B_CEB2],
    [0xC70B_D54D, 0x8203_FFE4, 0x40FF_F5F3, 0x1554_2A20],
];

/// atan(√u)/√u = 1 − u·(P1 − u·(P2 − u·P3)) on u ∈ [0, 1/64], Q0.32
/// (near-minimax; |error| ≤ 1e-10).
const P1: u32 = 1_431_655_321;
const P2: u32 = 858_851_118;
const P3: u32 = 598_911_783;

/// atan t in Q0.31 for t ∈ [1/8, 1] given in Q1.31: |error| < 1.3·2⁻³¹
/// (the fit, the truncating products and the final rounding).
#[inline]
fn atan_mid(t31: u32) -> u32 {
    let k = (t31 >> 25).clamp(8, 63);
    // d = t − k/64 in Q0.32, [0, 2²⁶].
    let d = t31.wrapping_sub(k << 25) << 1;
    let Some(row) = ATAN_TABLE.get(k as usize - 8) else {
        return 0;
    };
    let c3 = flash_u32(&row[3]) as i32;
    // c₃·d needs only ~16 bits (it is scaled by d² ≤ 2⁻¹² in the result):
    // one 16×16 product of the top halves (d < 2²⁶ + 1, so d/2¹¹ fits).
    let p3 = mul16((c3.unsigned_abs() >> 16) as u16, (d >> 11) as u16) >> 5;
    let m2 = flash_u32(&row[2]);
    let n2 = if c3 < 0 { m2 + p3 } else { m2 - p3 };
    let v1 = flash_u32(&row[1]) - mul_hi_approx(n2, d);
    let v0 = flash_u32(&row[0]) + mul_hi_approx(v1, d);
    (v0 >> 1) + (v0 & 1)
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
    // Every caller's v is at least 2²⁷ (an angle of at least atan(1/8) in
    // Q0.31 or π/4 in Q2.30): a few comparisons instead of the AVR's long
    // generic count.
    let lz = if v >= 1 << 30 {
        u32::from(v < 1 << 31)
    } else if v >= 1 << 28 {
        2 + u32::from(v < 1 << 29)
    } else if v >= 1 << 27 {
        4
    } else {
        leading_zeros(v)
    };
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
    // |θ| in Q2.30, unless returned directly.
    let theta = if ay.wrapping_sub(1) >= INF - 1 || ax.wrapping_sub(1) >= INF - 1 {
        // A zero, an infinity or a NaN: one test keeps them off the common path.
        if ay > INF || ax > INF {
            return f32::NAN;
        }
        if ay == 0 {
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
        } else if x_neg {
            // ax = ∞
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
        // in math::fixed (no arm shifts by an amount of its own).
        let direct = !swap && !x_neg;
        // t in Q1.31 where t ≥ 1/8 (et ≥ 124; t ≤ 1 so et ≤ 127); formed for
        // every t, with the shift kept within 0..=3.
        let t31 = shr(mt << 8, 127u32.saturating_sub(et).min(3));
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
                let lz = leading_zeros(h);
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
