//! Trajectories: the ζ-a-tₛ law ([`zat`]) and its time-scaled form
//! ([`scaled`]), via-point moves ([`via`]), the classic laws ([`laws`]),
//! end-effector paths paced by a law ([`path`]), moves lifted over a via
//! pose ([`lift`]), a
//! synchronized multi-joint move ([`plan`]) and the planner that picks its
//! duration and shape under the speed and acceleration limits ([`planner`]), and
//! the planned stop that brings any of them to rest along its path ([`stop`]). This module holds the types every law shares: one sample of
//! a motion and the error of all trajectory constructors.

pub mod laws;
pub mod lift;
pub mod lift_hull;
pub mod path;
pub mod plan;
pub mod planner;
pub mod scaled;
pub mod stop;
pub mod superpose;
pub mod via;
pub mod zat;

use core::fmt;

use crate::math::real::Real;

/// Position and its first three time derivatives at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample<R> {
    /// Position (rad for a joint, or normalized units).
    pub s: R,
    /// Velocity, per second.
    pub v: R,
    /// Acceleration, per second².
    pub acc: R,
    /// Jerk, per second³.
    pub jerk: R,
}

impl<R: Real> Sample<R> {
    /// A motion at rest at `s`.
    #[inline]
    pub fn at_rest(s: R) -> Self {
        Sample { s, v: R::ZERO, acc: R::ZERO, jerk: R::ZERO }
    }
}

/// Why a trajectory could not be planned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TrajError<R> {
    /// The duration tₛ (or t_v) is not > 0.
    NonPositiveDuration,
    /// The base n is not > 1.
    BaseNotAboveOne,
    /// The shape parameter puts a pole of the ζ-a-tₛ denominator inside the
    /// motion: it needs a < u_min.
    ShapeNotAdmissible {
        /// The shape parameter given.
        a: R,
        /// The bound it must stay below.
        u_min: R,
    },
    /// An input was NaN or infinite, or the parameters are so extreme that the
    /// plan's constants are not representable.
    NotFinite,
    /// The normalized profile leaves [0, 1] or runs backwards.
    Overshoot {
        /// The maximum of G (a peak ≤ 1 means it backtracks without
        /// overshooting).
        peak: R,
    },
    /// The via time t_v is not in (0, tₛ).
    ViaTimeOutOfRange,
    /// r = G(t_v) ≥ 1: the paper's via iteration diverges (and at r = 1 the
    /// closed form has no solution either).
    ViaDiverges {
        /// G(t_v).
        r: R,
    },
    /// The via iteration did not reach the tolerance within its iteration cap.
    NoConvergence,
    /// A motion law's interval has t_f ≤ t0.
    EmptyInterval,
}

impl<R: Real> fmt::Display for TrajError<R> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            TrajError::NonPositiveDuration => f.write_str("duration must be > 0"),
            TrajError::BaseNotAboveOne => f.write_str("base n must be > 1"),
            TrajError::ShapeNotAdmissible { a, u_min } => write!(
                f,
                "shape not admissible: a must be < u_min = {} (got a = {}); the trajectory has a pole",
                u_min.to_f64(),
                a.to_f64()
            ),
            TrajError::NotFinite => f.write_str("non-finite input or unrepresentable plan"),
            TrajError::Overshoot { peak } => {
                write!(f, "profile is not monotone (peak of G = {}): it would overshoot or backtrack", peak.to_f64())
            }
            TrajError::ViaTimeOutOfRange => f.write_str("via time must lie in (0, ts)"),
            TrajError::ViaDiverges { r } => write!(f, "via iteration diverges: r = G(tv) = {} is not < 1", r.to_f64()),
            TrajError::NoConvergence => f.write_str("via iteration did not converge"),
            TrajError::EmptyInterval => f.write_str("empty interval: tf must be > t0"),
        }
    }
}

/// `Ok(())` when every value is finite.
#[inline]
pub(crate) fn all_finite<R: Real>(vals: &[R]) -> Result<(), TrajError<R>> {
    for v in vals {
        if !v.is_finite() {
            return Err(TrajError::NotFinite);
        }
    }
    Ok(())
}
