//! √x split into a rounded root and its correction, from the exact integer
//! residual: twice f32's precision where the plan needs it (the smooth-stop
//! and via computations subtract nearly equal roots).

use super::fixed::{mul_full, shl, HIDDEN, MANT_MASK};

/// √x as (s, c): s the rounded root, c ≈ √x − s (|c| ≤ ulp(s)/2, good to
/// about 2⁻²⁴ of itself), so s + c carries √x to twice the precision. The
/// residual x − s² is exact in integers (|x − s²| ≤ s·ulp(s), 24 bits), so
/// only c = (x − s²)/(2s) rounds. x ≤ 0, subnormal or not finite: c = 0.
pub fn sqrt_split(x: f32) -> (f32, f32) {
    let s = crate::math::real::Real::sqrt(x);
    let (bx, bs) = (x.to_bits(), s.to_bits());
    let (ex, es) = ((bx >> 23) as i16, (bs >> 23) as i16);
    if bx >> 31 != 0 || ex == 0 || ex == 0xFF || es == 0 || es == 0xFF {
        return (s, 0.0);
    }
    let (mx, ms) = ((bx & MANT_MASK) | HIDDEN, (bs & MANT_MASK) | HIDDEN);
    // x = mx·2^(ex − 150), s² = ms²·2^(2es − 300): x − s² = R·2^(2es − 300)
    // with R = mx·2^d − ms², d = ex + 150 − 2es (23 or 24).
    let d = ex + 150 - 2 * es;
    if !(0..32).contains(&d) {
        return (s, 0.0);
    }
    // d is 21…24 for normal x: a constant shift by 20, then at most four
    // one-bit steps (the 23-step loop of a plain variable shift cost ~280
    // cycles).
    let mxd = if d >= 20 { shl(mx << 20, d as u32 - 20) } else { shl(mx, d as u32) };
    let r = mxd.wrapping_sub(mul_full(ms, ms).1) as i32;
    // c = R·2^(2es − 300)/(2s) = R/(ms·2^(151 − es)); the divisor is a float
    // with ms's mantissa and exponent 174 − es (normal: es ∈ [64, 190]).
    let den = f32::from_bits((((301 - es) as u32) << 23) | (ms & MANT_MASK));
    (s, r as f32 / den)
}
