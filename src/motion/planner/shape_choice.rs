//! Which ζ-a-tₛ shape a move of duration tₛ uses ([`choose_a`]): the smooth
//! stop a* = tₛ − log_n tₛ (zero end velocity) while it is monotone, i.e.
//! L·(tₛ − 1) ≤ 2; otherwise the largest a whose profile is still monotone,
//! which has the smallest end velocity a monotone profile can have (the end
//! rate falls as a grows toward a*). For tₛ > 1 that limit has a closed form
//! ([`monotone_limit_a`]); for tₛ ≤ 1 every admissible a is monotone and the
//! end rate only approaches its infimum L/tₛ as a → −∞, so a = tₛ − 16/L is
//! used (within 1e-7 of the infimum). One [`Shape`] is built per tₛ
//! (`zat_shape`), with what the peak and duration searches reuse.

use crate::math::real::Real;
use crate::motion::zat::{t_star, u_min, Shape, ShapeParams};
use crate::motion::TrajError;

/// tₛ ≤ 1: a = tₛ − A_FLOOR/L, q(tₛ) = 1/expm1(16) ≈ 1e-7.
const A_FLOOR: f64 = 16.0;
/// Relative step below the closed-form monotonicity limit, so that rounding
/// cannot put the chosen a on the wrong side of it.
const A_BACKOFF: f64 = 1e-4;

/// How [`choose_a`] picked a.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AKind {
    /// a* = tₛ − log_n tₛ: zero end velocity.
    SmoothStop,
    /// The largest monotone a (a* overshoots or is not admissible).
    MonotoneLimit,
    /// tₛ ≤ 1: a far below u_min, the end rate at its infimum L/tₛ.
    Floor,
}

/// The shape parameter a the planner chose, and why.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AChoice<R> {
    /// The ζ-a-tₛ shape parameter.
    pub a: R,
    /// Which rule gave it.
    pub kind: AKind,
}

/// For tₛ > 1 and n > 1: the largest a whose profile is monotone.
///
/// From `Shape::monotone_margin`: G is monotone iff φ(t) = L·(u(t) − a) −
/// ln(t²/tₛ) ≥ 0 on [√tₛ, tₛ]; φ is convex with its minimum at
/// t_m = min(t*, tₛ), t* = (1 + √(1 + L²tₛ))/L, and t_m does not depend on a.
/// So the limit is `a = u(t_m) − ln(t_m²/tₛ)/L`; at t_m = tₛ this is a*.
/// It is below u_min because φ(√tₛ) = L·(u_min − a) > φ(t_m) = 0.
pub fn monotone_limit_a<R: Real>(ts: R, n: R) -> Option<R> {
    if !n.is_finite() || n <= R::ONE {
        return None;
    }
    monotone_limit(ts, n.ln()).map(|(a, _)| a)
}

/// [`monotone_limit_a`] given L = ln n, with t_m.
fn monotone_limit<R: Real>(ts: R, l: R) -> Option<(R, R)> {
    if !(ts.is_finite() && l.is_finite()) || ts <= R::ONE || l <= R::ZERO {
        return None;
    }
    let t_star = t_star(ts, l);
    let tm = t_star.min(ts);
    let a = tm + ts / tm - R::ONE - (tm * tm / ts).ln() / l;
    if a.is_finite() {
        Some((a, tm))
    } else {
        None
    }
}

/// The shape parameter for a ζ-a-tₛ move of duration `ts` (see the module doc).
pub fn choose_a<R: Real>(ts: R, n: R) -> Result<AChoice<R>, TrajError<R>> {
    if !n.is_finite() {
        return Err(TrajError::NotFinite);
    }
    if n <= R::ONE {
        return Err(TrajError::BaseNotAboveOne);
    }
    let z = zat_shape(ts, n, n.ln())?;
    z.shape.check_monotone()?;
    Ok(z.choice())
}

/// The shape [`choose_a`] picks, built once, with what the peak and
/// duration searches reuse.
#[derive(Debug, Clone, Copy)]
pub(super) struct ZatShape<R> {
    pub(super) shape: Shape<R>,
    pub(super) kind: AKind,
    /// t* = (1 + √(1 + L²tₛ))/L when it lies inside the motion, else 0: G′
    /// dips to about 0 there (see [`crate::motion::planner::peak_rate::zat_peak_rate`]).
    pub(super) t_star: R,
    /// da/dtₛ of the choice.
    pub(super) da: R,
}

impl<R: Real> ZatShape<R> {
    pub(super) fn choice(&self) -> AChoice<R> {
        AChoice { a: self.shape.a(), kind: self.kind }
    }

    /// The end of the first hump's piece.
    pub(super) fn first_end(&self) -> R {
        if self.t_star > R::ZERO {
            self.t_star
        } else {
            self.shape.ts()
        }
    }
}

/// [`choose_a`]'s shape given L = ln n. Monotonicity is not checked here for
/// the monotone-limit and floor shapes (they are monotone by construction;
/// [`crate::motion::plan::MultiPlan::with_law`] checks the one a plan uses).
// Not inlined, so that its callees' frames are not part of the callers'.
#[inline(never)] // avr-trap: frame-size
pub(super) fn zat_shape<R: Real>(ts: R, n: R, l: R) -> Result<ZatShape<R>, TrajError<R>> {
    if !(ts.is_finite() && n.is_finite() && l.is_finite()) {
        return Err(TrajError::NotFinite);
    }
    if ts <= R::ZERO {
        return Err(TrajError::NonPositiveDuration);
    }
    if n <= R::ONE {
        return Err(TrajError::BaseNotAboveOne);
    }
    let inv_lts = (l * ts).recip();
    // φ's minimum is at tₛ (where φ(tₛ) = 0 for a*) exactly while t* ≥ tₛ,
    // i.e. L·(tₛ − 1) ≤ 2; a* is then admissible too ((√tₛ − 1)² <
    // (tₛ − 1)·ln tₛ/2 ≤ ln tₛ/L). Beyond, a* is not monotone.
    if ts > R::ONE && l * (ts - R::ONE) <= R::TWO {
        if let Ok(shape) = Shape::smooth_stop(ts, n) {
            if shape.is_monotone() {
                // a* = tₛ − ln tₛ/L.
                let da = R::ONE - inv_lts;
                return Ok(ZatShape { shape, kind: AKind::SmoothStop, t_star: R::ZERO, da });
            }
        }
    }
    let (a, kind, t_star, da) = match monotone_limit(ts, l) {
        Some((lim, tm)) => {
            let a = lim - R::lit(A_BACKOFF) * (R::ONE + lim.abs());
            // By the envelope theorem da/dtₛ = ∂/∂tₛ of u(t) − ln(t²/tₛ)/L at t_m.
            let (t_star, da) = if tm < ts { (tm, tm.recip() + inv_lts) } else { (R::ZERO, R::ONE - inv_lts) };
            (a, AKind::MonotoneLimit, t_star, da)
        }
        None => (ts - R::lit(A_FLOOR) / l, AKind::Floor, R::ZERO, R::ONE),
    };
    // Guards against the (not expected) case that the limit sits on the pole.
    let a = a.min(u_min(ts) - R::lit(A_BACKOFF) * (R::ONE + ts));
    let shape = Shape::new(&ShapeParams { ts, a, n })?;
    Ok(ZatShape { shape, kind, t_star, da })
}
