//! The time-scaled ζ-a-tₛ profile, the app's default law: one reference
//! shape (n = 2, T₀ = 1.5 s, the smooth stop a* = T₀ − log₂ T₀) evaluated on
//! the normalized time τ = t·T₀/tₛ, so g(t) = G(t·T₀/tₛ) for a move of any
//! duration tₛ.
//!
//! The papers write ζ-a-tₛ in seconds, so its shape changes with tₛ: the
//! peak-to-mean velocity ratio grows from 2.02 at tₛ = 1.5 s to 4.47 at
//! 7.4 s, and beyond tₛ ≈ 3.9 s (n = 2) the smooth stop overshoots, so long
//! moves end with a velocity. Scaling one shape in time keeps what it has
//! at T₀ for every move: zero end velocity, and fixed ratios of peak
//! velocity, acceleration and jerk to the mean ([`VEL_RATIO`],
//! [`ACC_RATIO`], [`JERK_RATIO`]), so the shortest duration under velocity
//! and acceleration limits has a closed form like the classic laws'.
//!
//! Why (2, 1.5 s) (docs/method.md §10 has the comparison): against the
//! quintic (1.875, 5.77, 60) it takes at most 1.08× the time under a
//! velocity limit and 1.07× under an acceleration limit, with the same jerk
//! (62). Bases nearer 1.4 lower the velocity ratio below the quintic's but
//! double the acceleration and raise the jerk sevenfold, and the best
//! compromise found (n = 1.65, T₀ = 1.4: 0.99×) still doubles the jerk. n = 2
//! also keeps the chip's constant ln 2, and the pole is far (L·δ = 0.37), so
//! the f32 evaluation is the well-conditioned one of `zat`, exact at the end.

use crate::math::real::Real;
use crate::motion::zat::Shape;
use crate::motion::{Sample, TrajError};

/// The reference shape's base.
pub const REF_N: f64 = 2.0;
/// The reference shape's duration, s.
pub const REF_T0: f64 = 1.5;
/// max g′·tₛ: the peak velocity over the mean (at τ/T₀ = 0.578). Rounded up.
pub const VEL_RATIO: f64 = 2.020_156;
/// max |g″|·tₛ²: the peak acceleration over Δ/tₛ² (braking, at
/// τ/T₀ = 0.797; the largest positive one is 5.30 at 0.353). Rounded up.
pub const ACC_RATIO: f64 = 6.636_934;
/// max |g‴|·tₛ³. Rounded up.
pub const JERK_RATIO: f64 = 62.3396;

/// A time-scaled ζ-a-tₛ profile of duration tₛ: g(t) = G(t·T₀/tₛ), 0 → 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScaledZat<R> {
    shape: Shape<R>,
    /// T₀/tₛ: normalized time per second.
    k: R,
    ts: R,
}

impl<R: Real> ScaledZat<R> {
    /// The reference shape, for a move of `ts` seconds (> 0, finite).
    pub fn new(ts: R) -> Result<Self, TrajError<R>> {
        if !ts.is_finite() {
            return Err(TrajError::NotFinite);
        }
        if !ts.is_positive() {
            return Err(TrajError::NonPositiveDuration);
        }
        let shape = Shape::smooth_stop(R::lit(REF_T0), R::lit(REF_N))?;
        let k = R::lit(REF_T0) / ts;
        if !(k.is_finite() && k.is_positive()) {
            return Err(TrajError::NotFinite);
        }
        Ok(ScaledZat { shape, k, ts })
    }

    /// The move's duration tₛ, s.
    #[inline]
    pub fn ts(&self) -> R {
        self.ts
    }

    /// The reference shape (in its own time, 0 < τ ≤ T₀).
    #[inline]
    pub fn reference(&self) -> &Shape<R> {
        &self.shape
    }

    /// τ for 0 < t < tₛ; `None` at and after the end, where the reference's
    /// own end values apply (t·T₀/tₛ may round to either side of T₀).
    #[inline]
    fn tau(&self, t: R) -> Option<R> {
        if t.lt_num(self.ts) {
            Some(t * self.k)
        } else {
            None
        }
    }

    /// g(t): 0 for t ≤ 0, exactly 1 from tₛ on.
    #[inline]
    pub fn g(&self, t: R) -> R {
        match self.tau(t) {
            Some(tau) => self.shape.g(tau),
            None => R::ONE,
        }
    }

    /// (g, g′); at tₛ the left limit (0 up to rounding: the smooth stop),
    /// after it 0.
    pub fn g_rate(&self, t: R) -> (R, R) {
        let (g, r) = match self.tau(t) {
            Some(tau) => self.shape.g_rate(tau),
            None if self.ts.lt_num(t) => return (R::ONE, R::ZERO),
            None => (R::ONE, self.shape.end_rate()),
        };
        (g, r * self.k)
    }

    /// g and its first three derivatives (left limits at tₛ, zero after).
    pub fn g_derivs(&self, t: R) -> Sample<R> {
        let tau = match self.tau(t) {
            Some(tau) => tau,
            None if self.ts.lt_num(t) => return Sample::at_rest(R::ONE),
            None => self.shape.ts(),
        };
        let d = self.shape.g_derivs(tau);
        let k2 = self.k * self.k;
        Sample { s: d.s, v: d.v * self.k, acc: d.acc * k2, jerk: d.jerk * k2 * self.k }
    }

    /// g′(tₛ⁻): the smooth stop's, 0 up to rounding.
    pub fn end_rate(&self) -> R {
        self.shape.end_rate() * self.k
    }
}
