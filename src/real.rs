//! The float abstraction: every formula in the core is written once, generic over
//! [`Real`], and runs as `f32` on the chip and as `f64` in `armsim` and the tests.
//!
//! f32 `exp`, `expm1`, `ln` ([`crate::f32_exp`]) and `atan2`
//! ([`crate::f32_atan`]) are integer-core routines on every target, so host
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
    const ZERO: Self;
    const ONE: Self;
    const TWO: Self;
    const HALF: Self;
    const PI: Self;
    /// Relative machine precision of the type.
    const EPSILON: Self;

    /// Converts a compile-time constant (f64 literal). Inlined, so on AVR the
    /// conversion folds away and no double arithmetic is linked.
    fn lit(v: f64) -> Self;
    fn from_f32(v: f32) -> Self;
    fn to_f64(self) -> f64;
    fn to_f32(self) -> f32;
    fn from_u16(v: u16) -> Self;

    fn abs(self) -> Self;
    fn sqrt(self) -> Self;
    fn exp(self) -> Self;
    /// `exp(x) - 1` without cancellation for small `x`.
    fn expm1(self) -> Self;
    fn ln(self) -> Self;
    fn sin(self) -> Self;
    fn cos(self) -> Self;
    fn acos(self) -> Self;
    fn atan2(self, x: Self) -> Self;
    fn is_finite(self) -> bool;

    #[inline]
    fn max(self, o: Self) -> Self {
        if o > self {
            o
        } else {
            self
        }
    }
    #[inline]
    fn min(self, o: Self) -> Self {
        if o < self {
            o
        } else {
            self
        }
    }
    #[inline]
    fn recip(self) -> Self {
        Self::ONE / self
    }
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
        crate::f32_exp::exp(self)
    }
    #[inline]
    fn expm1(self) -> Self {
        crate::f32_exp::expm1(self)
    }
    #[inline]
    fn ln(self) -> Self {
        crate::f32_exp::ln(self)
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
        crate::f32_atan::atan2(self, x)
    }
    #[inline]
    fn is_finite(self) -> bool {
        // The exponent field is all ones only for ±∞ and NaN; a bit test,
        // where the float comparison would be a library call on the AVR.
        self.to_bits() & 0x7F80_0000 != 0x7F80_0000
    }
}
