//! The float abstraction: every formula in the core is written once, generic over
//! [`Real`], and runs as `f32` on the chip and as `f64` in `armsim` and the tests.
//!
//! f32 `exp`, `expm1`, `ln` ([`crate::math::exp`]) and `atan2`
//! ([`crate::math::atan`]) are integer-core routines on every target, so host
//! tests check the chip's exact results. The other f32 transcendentals
//! (`sqrt`, `sin`, `cos`, `acos`) come from avr-libc's hand-written assembly
//! libm on AVR (linked with `-lm`; several times faster than the portable Rust
//! `libm` crate) and from the `libm` crate on the host; f64 always uses the
//! `libm` crate.

use core::fmt::Debug;
use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

/// A floating-point scalar the core can compute with.
pub trait Real:
    Copy
    + Debug
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
{
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// 2.
    const TWO: Self;
    /// 0.5.
    const HALF: Self;
    /// π rounded to the type.
    const PI: Self;
    /// Relative machine precision of the type.
    const EPSILON: Self;

    /// Converts a compile-time constant (f64 literal). Inlined, so on AVR the
    /// conversion folds away and no double arithmetic is linked.
    fn lit(v: f64) -> Self;
    /// Widens an f32 exactly (f64), or keeps it (f32).
    fn from_f32(v: f32) -> Self;
    /// Exact in both types.
    fn to_f64(self) -> f64;
    /// Rounds to nearest (f64), or keeps it (f32).
    fn to_f32(self) -> f32;
    /// Exact in both types.
    fn from_u16(v: u16) -> Self;

    /// |self|, by clearing the sign bit (NaN stays NaN).
    fn abs(self) -> Self;
    /// Square root (NaN below 0).
    fn sqrt(self) -> Self;
    /// eˣ (f32: the integer-core routine of [`crate::math::exp`]).
    fn exp(self) -> Self;
    /// `exp(x) - 1` without cancellation for small `x`.
    fn expm1(self) -> Self;
    /// Natural logarithm (f32: integer core; NaN below 0, −∞ at 0).
    fn ln(self) -> Self;
    /// Sine of radians.
    fn sin(self) -> Self;
    /// Cosine of radians.
    fn cos(self) -> Self;
    /// Arc cosine in [0, π]; NaN outside [−1, 1].
    fn acos(self) -> Self;
    /// Angle of the point (x, self) in (−π, π] (f32: [`crate::math::atan`]).
    fn atan2(self, x: Self) -> Self;
    /// Neither infinite nor NaN.
    fn is_finite(self) -> bool;

    /// The larger of the two; `self` when they are unordered (NaN).
    #[inline]
    fn max(self, o: Self) -> Self {
        if o > self {
            o
        } else {
            self
        }
    }
    /// The smaller of the two; `self` when they are unordered (NaN).
    #[inline]
    fn min(self, o: Self) -> Self {
        if o < self {
            o
        } else {
            self
        }
    }
    /// `self == 0` (either sign).
    #[inline]
    fn is_zero(self) -> bool {
        self == Self::ZERO
    }
    /// `self < 0`: false for −0 and NaN.
    #[inline]
    fn is_negative(self) -> bool {
        self < Self::ZERO
    }
    /// `2·self`, exactly (a power of two).
    #[inline]
    fn twice(self) -> Self {
        self + self
    }
    /// `self`, opaque to the optimizer. On the AVR, LLVM takes a float
    /// operation for one cheap instruction and runs it on both paths of an
    /// `if` to select the result afterwards; it is a ~170-cycle library call
    /// there. The result of a conditional operation passed through this stays
    /// on its path.
    #[inline(always)]
    fn barrier(self) -> Self {
        self
    }
    /// `self <= o` for operands that are not NaN (with a NaN the answer is
    /// unspecified: callers have checked finiteness).
    #[inline]
    fn le_num(self, o: Self) -> bool {
        self <= o
    }
    /// `self < o` for operands that are not NaN (as [`Real::le_num`]).
    #[inline]
    fn lt_num(self, o: Self) -> bool {
        !o.le_num(self)
    }
    /// `self > 0`: false for ±0 and NaN.
    #[inline]
    fn is_positive(self) -> bool {
        self > Self::ZERO
    }
    /// [`Real::le_num`] for code off the frame's path (planning, set-up):
    /// on f32 one called body instead of the inlined compare.
    #[inline]
    fn le_cold(self, o: Self) -> bool {
        self.le_num(o)
    }
    /// [`Real::lt_num`] as [`Real::le_cold`].
    #[inline]
    fn lt_cold(self, o: Self) -> bool {
        !o.le_cold(self)
    }
    /// `self == o` for operands that are not NaN.
    #[inline]
    fn eq_num(self, o: Self) -> bool {
        self == o
    }
    /// 1 / self.
    #[inline]
    fn recip(self) -> Self {
        Self::ONE / self
    }
    /// selfⁿ by repeated multiplication (1 for n = 0).
    #[inline]
    fn powi(self, n: u32) -> Self {
        let mut r = Self::ONE;
        let mut i = 0;
        while i < n {
            r *= self;
            i += 1;
        }
        r
    }
}

impl Real for f64 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const TWO: Self = 2.0;
    const HALF: Self = 0.5;
    const PI: Self = core::f64::consts::PI;
    const EPSILON: Self = f64::EPSILON;

    #[inline(always)]
    fn lit(v: f64) -> Self {
        v
    }
    #[inline(always)]
    fn from_f32(v: f32) -> Self {
        v as f64
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline(always)]
    fn to_f32(self) -> f32 {
        self as f32
    }
    #[inline(always)]
    fn from_u16(v: u16) -> Self {
        v as f64
    }
    #[inline]
    fn abs(self) -> Self {
        libm::fabs(self)
    }
    #[inline]
    fn sqrt(self) -> Self {
        libm::sqrt(self)
    }
    #[inline]
    fn exp(self) -> Self {
        libm::exp(self)
    }
    #[inline]
    fn expm1(self) -> Self {
        libm::expm1(self)
    }
    #[inline]
    fn ln(self) -> Self {
        libm::log(self)
    }
    #[inline]
    fn sin(self) -> Self {
        libm::sin(self)
    }
    #[inline]
    fn cos(self) -> Self {
        libm::cos(self)
    }
    #[inline]
    fn acos(self) -> Self {
        libm::acos(self)
    }
    #[inline]
    fn atan2(self, x: Self) -> Self {
        libm::atan2(self, x)
    }
    #[inline]
    fn is_finite(self) -> bool {
        f64::is_finite(self)
    }
}

/// avr-libc's libm. On AVR `double` is 32 bits, so these `double` entry points
/// are the single-precision routines.
#[cfg(target_arch = "avr")]
mod avr_libm {
    extern "C" {
        pub fn sin(x: f32) -> f32;
        pub fn cos(x: f32) -> f32;
        pub fn acos(x: f32) -> f32;
        pub fn sqrt(x: f32) -> f32;
    }
}

/// Chooses the f32 backend: avr-libc on the chip, the `libm` crate elsewhere.
macro_rules! f32_fn {
    ($avr:ident, $host:ident ( $($a:ident),* )) => {{
        #[cfg(target_arch = "avr")]
        // SAFETY: avr-libc's pure math functions take and return floats by value.
        let r = unsafe { avr_libm::$avr($($a),*) };
        #[cfg(not(target_arch = "avr"))]
        let r = libm::$host($($a),*);
        r
    }};
}

/// The bits of `v`, the top byte passed through
/// [`crate::math::fixed::opaque_byte`]: LLVM otherwise recognizes sign and zero
/// tests on a float's bits and turns them back into float comparisons, i.e.
/// library calls on the AVR.
#[inline(always)]
fn opaque_bits(v: f32) -> u32 {
    let b = v.to_bits();
    let hi = crate::math::fixed::opaque_byte((b >> 24) as u8);
    (b & 0x00FF_FFFF) | (u32::from(hi) << 24)
}

impl Real for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const TWO: Self = 2.0;
    const HALF: Self = 0.5;
    const PI: Self = core::f32::consts::PI;
    const EPSILON: Self = f32::EPSILON;

    #[inline(always)]
    fn lit(v: f64) -> Self {
        v as f32
    }
    #[inline(always)]
    fn from_f32(v: f32) -> Self {
        v
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self as f64
    }
    #[inline(always)]
    fn to_f32(self) -> f32 {
        self
    }
    #[inline(always)]
    fn from_u16(v: u16) -> Self {
        v as f32
    }
    #[inline]
    fn abs(self) -> Self {
        f32::from_bits(self.to_bits() & 0x7fff_ffff)
    }
    #[inline]
    fn sqrt(self) -> Self {
        f32_fn!(sqrt, sqrtf(self))
    }
    #[inline]
    fn exp(self) -> Self {
        crate::math::exp::exp(self)
    }
    #[inline]
    fn expm1(self) -> Self {
        crate::math::exp::expm1(self)
    }
    #[inline]
    fn ln(self) -> Self {
        crate::math::exp::ln(self)
    }
    #[inline]
    fn sin(self) -> Self {
        f32_fn!(sin, sinf(self))
    }
    #[inline]
    fn cos(self) -> Self {
        f32_fn!(cos, cosf(self))
    }
    #[inline]
    fn acos(self) -> Self {
        f32_fn!(acos, acosf(self))
    }
    #[inline]
    fn atan2(self, x: Self) -> Self {
        crate::math::atan::atan2(self, x)
    }
    // Sign, zero and order tests on the bits: a float comparison is a library
    // call of ~100 cycles on the AVR, these are a few instructions.
    #[inline]
    fn is_zero(self) -> bool {
        opaque_bits(self) << 1 == 0
    }
    #[inline]
    fn is_negative(self) -> bool {
        // Above −0 and at most −∞: the negative numbers, not the NaNs.
        opaque_bits(self).wrapping_sub(0x8000_0001) < 0x7F80_0000
    }
    // One body for its ~20 callers (~50 B inlined each).
    #[inline(never)] // reason: code-size
    fn twice(self) -> Self {
        let b = self.to_bits();
        // Exponent field 1..=253: one more in the exponent is the exact double
        // (zero, subnormals, the largest binade, ∞ and NaN take the add).
        if (b & 0x7F80_0000).wrapping_sub(0x0080_0000) < 0x7E80_0000 {
            f32::from_bits(b + 0x0080_0000)
        } else {
            (self + self).barrier()
        }
    }
    #[inline(always)]
    fn barrier(self) -> Self {
        f32::from_bits(opaque_bits(self))
    }
    #[inline]
    fn le_num(self, o: Self) -> bool {
        // Sign and magnitude to two's complement: the integers are then in the
        // order of the numbers, ±0 both 0 (NaNs land beyond ±∞).
        fn key(v: f32) -> i32 {
            let b = v.to_bits();
            let m = (b & 0x7FFF_FFFF) as i32;
            if b >> 31 != 0 {
                -m
            } else {
                m
            }
        }
        key(self) <= key(o)
    }
    // One body for the cold callers (~30 B inlined each).
    #[inline(never)] // reason: code-size
    fn le_cold(self, o: Self) -> bool {
        self.le_num(o)
    }
    #[inline]
    fn is_positive(self) -> bool {
        // Positive numbers up to +∞ are the positive i32 patterns up to ∞'s;
        // NaNs lie beyond it, −0 and the negatives are negative.
        let b = self.to_bits() as i32;
        b > 0 && b <= 0x7F80_0000
    }
    #[inline]
    fn eq_num(self, o: Self) -> bool {
        let (a, b) = (self.to_bits(), o.to_bits());
        // Equal patterns, or +0 against −0.
        a == b || (a | b) << 1 == 0
    }
    #[inline]
    fn is_finite(self) -> bool {
        // The exponent field is all ones only for ±∞ and NaN; a bit test,
        // where the float comparison would be a library call on the AVR.
        self.to_bits() & 0x7F80_0000 != 0x7F80_0000
    }
}
