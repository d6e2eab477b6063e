//! Classic point-to-point motion laws (method.md §9, with the lab note's printing
//! errors corrected), τ = (t − t0)/T, T = t_f − t0, Δ = s_f − s0.
//!
//! Conventions: outside [t0, t_f] the end value is held with zero derivatives;
//! t0 and t_f use the formula (so linear has velocity Δ/T there), with the
//! position at t_f returned as exactly s_f; at the trapezoid's phase boundaries
//! the later phase applies.

use crate::math::real::Real;
use crate::motion::{all_finite, Sample, TrajError};

/// The classic point-to-point laws.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Law {
    /// Velocity steps at both ends.
    Linear,
    /// 3τ² − 2τ³: zero velocity at both ends, acceleration steps.
    Cubic,
    /// 10τ³ − 15τ⁴ + 6τ⁵: zero velocity and acceleration at both ends.
    Quintic,
    /// Trapezoidal velocity with T_acc = T_dec = T/3.
    Trapezoid,
}

/// A move from `s0` at `t0` to `sf` at `tf`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LawParams<R> {
    /// Start time, s.
    pub t0: R,
    /// End time, s; must be after `t0`.
    pub tf: R,
    /// Start position.
    pub s0: R,
    /// End position.
    pub sf: R,
}

/// A validated law with its per-plan constants.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LawPlan<R> {
    law: Law,
    t0: R,
    tf: R,
    s0: R,
    sf: R,
    delta: R,
    inv_t: R,
}

impl<R: Real> LawPlan<R> {
    /// Checks the parameters (finite, `tf > t0`) and precomputes Δ and 1/T.
    pub fn new(law: Law, p: &LawParams<R>) -> Result<Self, TrajError<R>> {
        all_finite(&[p.t0, p.tf, p.s0, p.sf])?;
        if p.tf <= p.t0 {
            return Err(TrajError::EmptyInterval);
        }
        let t = p.tf - p.t0;
        let inv_t = t.recip();
        let delta = p.sf - p.s0;
        if !(t.is_finite() && inv_t.is_finite() && delta.is_finite()) || inv_t == R::ZERO {
            return Err(TrajError::NotFinite);
        }
        Ok(LawPlan { law, t0: p.t0, tf: p.tf, s0: p.s0, sf: p.sf, delta, inv_t })
    }

    /// Which law.
    #[inline]
    pub fn law(&self) -> Law {
        self.law
    }
    /// Start time, s.
    #[inline]
    pub fn t0(&self) -> R {
        self.t0
    }
    /// End time, s.
    #[inline]
    pub fn tf(&self) -> R {
        self.tf
    }
    /// T = t_f − t0, s.
    #[inline]
    pub fn duration(&self) -> R {
        self.tf - self.t0
    }

    /// Normalized profile f(τ) and its τ-derivatives f′, f″, f‴ for τ ∈ [0, 1].
    fn unit(&self, tau: R) -> [R; 4] {
        let z = R::ZERO;
        match self.law {
            Law::Linear => [tau, R::ONE, z, z],
            Law::Cubic => {
                let t2 = tau * tau;
                [
                    R::lit(3.0) * t2 - R::TWO * t2 * tau,
                    R::lit(6.0) * (tau - t2),
                    R::lit(6.0) * (R::ONE - R::TWO * tau),
                    R::lit(-12.0),
                ]
            }
            Law::Quintic => {
                let t2 = tau * tau;
                let t3 = t2 * tau;
                [
                    t3 * (R::lit(10.0) + tau * (R::lit(-15.0) + R::lit(6.0) * tau)),
                    R::lit(30.0) * t2 * (R::ONE + tau * (-R::TWO + tau)),
                    R::lit(60.0) * tau * (R::ONE + tau * (R::lit(-3.0) + R::TWO * tau)),
                    R::lit(60.0) * (R::ONE + tau * (R::lit(-6.0) + R::lit(6.0) * tau)),
                ]
            }
            Law::Trapezoid => {
                let three_tau = R::lit(3.0) * tau;
                if three_tau < R::ONE {
                    [R::lit(2.25) * tau * tau, R::lit(4.5) * tau, R::lit(4.5), z]
                } else if three_tau < R::TWO {
                    [(R::lit(6.0) * tau - R::ONE) * R::lit(0.25), R::lit(1.5), z, z]
                } else {
                    let m = R::ONE - tau;
                    [R::ONE - R::lit(2.25) * m * m, R::lit(4.5) * m, R::lit(-4.5), z]
                }
            }
        }
    }

    /// Position only (the per-frame path).
    pub fn position(&self, t: R) -> R {
        if t >= self.tf {
            self.sf
        } else if t <= self.t0 {
            self.s0
        } else {
            let tau = (t - self.t0) * self.inv_t;
            let f = self.unit(tau);
            self.s0 + self.delta * f[0]
        }
    }

    /// Position and its three derivatives at time `t` (at rest outside
    /// [t0, t_f]).
    pub fn sample(&self, t: R) -> Sample<R> {
        if t < self.t0 {
            return Sample::at_rest(self.s0);
        }
        if t > self.tf {
            return Sample::at_rest(self.sf);
        }
        let tau = if t >= self.tf { R::ONE } else { (t - self.t0) * self.inv_t };
        let f = self.unit(tau);
        let k1 = self.delta * self.inv_t;
        let k2 = k1 * self.inv_t;
        let k3 = k2 * self.inv_t;
        Sample { s: self.position(t), v: k1 * f[1], acc: k2 * f[2], jerk: k3 * f[3] }
    }

    /// Velocity at t_f⁻ (Δ/T for linear, 0 for the others).
    pub fn end_velocity(&self) -> R {
        self.delta * self.inv_t * self.unit(R::ONE)[1]
    }
}

/// Evaluates `law` once; build a [`LawPlan`] to sample repeatedly.
pub fn eval<R: Real>(law: Law, p: &LawParams<R>, t: R) -> Result<Sample<R>, TrajError<R>> {
    if !t.is_finite() {
        return Err(TrajError::NotFinite);
    }
    Ok(LawPlan::new(law, p)?.sample(t))
}
