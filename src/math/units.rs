//! Angle units. The core computes in radians; people read and type degrees
//! (the screen, in whole degrees) and hundredths of a degree (the serial
//! protocol, `cal show`, telemetry). Every conversion between them is here.
//!
//! Two roundings, each for a reason:
//! - Degrees a person typed, and the hundredths read back from them (the
//!   serial protocol, `cal set` / `cal show`, telemetry), use factors formed
//!   from the type's own π (`π / 18000` in f32 on the chip). Round angles
//!   then land exactly on the code's constants (`goto 90 90 -90` gives the
//!   f32 `FRAC_PI_2` of the home pose, `max_deg 180` the f32 `PI` of the
//!   default limits), and every setting typed in hundredths of a degree
//!   reads back as typed (checked for all values within ±20 000.00°).
//! - Degrees as a real number ([`rad_to_deg`]: α in `armsim`, the screen's
//!   whole degrees) use 180/π rounded once into the type, the closest the
//!   type can print.

use super::real::Real;

/// Degrees per radian formed from the type's π (`180 / π` in `R`): for
/// per-degree values a person types, e.g. the servo scale in µs per degree.
#[inline]
pub fn deg_per_rad<R: Real>() -> R {
    R::lit(180.0) / R::PI
}

/// `rad` radians in degrees (180/π rounded once into `R`).
#[inline]
pub fn rad_to_deg<R: Real>(rad: R) -> R {
    rad * R::lit(180.0 / core::f64::consts::PI)
}

/// Hundredths of a degree to radians (any `i32`, without an integer-to-float
/// conversion wider than `u16`, which `Real` does not offer).
#[inline(never)] // reason: code-size
pub fn centideg_to_rad<R: Real>(centideg: i32) -> R {
    let mag = centideg.unsigned_abs();
    let hi = R::from_u16((mag >> 16) as u16);
    let lo = R::from_u16((mag & 0xFFFF) as u16);
    let rad = (hi * R::lit(65_536.0) + lo) * (R::PI / R::lit(18_000.0));
    if centideg < 0 {
        -rad
    } else {
        rad
    }
}

/// Radians to the nearest hundredth of a degree (saturating; NaN gives 0);
/// the inverse of [`centideg_to_rad`].
pub fn rad_to_centideg(rad: f32) -> i32 {
    round_i32(rad * (18_000.0 / core::f32::consts::PI))
}

/// Rounds half away from zero to an `i32`, saturating at its range (NaN
/// gives 0); `core` has no `f32::round`. The one rounding every conversion
/// to an integer unit uses.
#[inline(never)] // reason: code-size
pub fn round_i32(v: f32) -> i32 {
    if v >= 0.0 {
        (v + 0.5) as i32
    } else {
        (v - 0.5) as i32
    }
}
