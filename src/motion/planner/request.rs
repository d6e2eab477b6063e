//! What the planner is asked ([`MoveRequest`] under [`PlanLimits`]), what it
//! answers ([`PlannedMove`]) and why it can refuse ([`PlanError`]).

use super::shape_choice::AChoice;
use crate::math::real::Real;
use crate::motion::plan::{LawKind, MultiPlan, JOINTS};

/// Lowest `zat_ts_min` the app accepts: just above tₛ = 1 the smooth stop
/// lies within 1e-3 of the pole and G′ is a spike f32 resolves poorly (see
/// [`crate::motion::planner::peak_rate::zat_peak_rate`]).
pub const ZAT_TS_FLOOR: f32 = 1.05;

/// Why a move cannot be planned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlanError {
    /// The joints' speed limits cannot be met within `ts_max`.
    SpeedLimit,
    /// The trajectory is inadmissible or not monotone.
    Trajectory,
    /// A non-finite number where a pose or a limit was expected.
    NotFinite,
}

/// Durations and the ζ-a-tₛ base for planning, and the speed and
/// acceleration each joint may use in this move.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanLimits<R> {
    /// Largest joint speed for this move, rad/s, per joint (> 0).
    pub speed: [R; JOINTS],
    /// Largest joint acceleration for this move, rad/s², per joint (> 0).
    pub accel: [R; JOINTS],
    /// Shortest classic move, s.
    pub ts_min: R,
    /// Shortest move of the papers' ζ-a-tₛ, s (> 1 keeps the smooth stop
    /// available); the time-scaled one takes `ts_min` like the classic laws.
    pub zat_ts_min: R,
    /// Longest move of any law, s.
    pub ts_max: R,
    /// The papers' ζ-a-tₛ base n.
    pub n: R,
}

/// One move to plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveRequest<R> {
    /// Joint angles now, rad (base, shoulder, elbow).
    pub start: [R; JOINTS],
    /// Joint angles to reach, rad.
    pub target: [R; JOINTS],
    /// The law to move by.
    pub law: LawKind,
}

/// A planned move and what the app reports about it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlannedMove<R> {
    /// The synchronized move itself.
    pub plan: MultiPlan<R>,
    /// Duration, s.
    pub ts: R,
    /// The papers' ζ-a-tₛ shape choice; `None` for the other laws.
    pub a: Option<AChoice<R>>,
    /// max g′ of the profile, 1/s.
    pub peak_rate: R,
    /// max |g″| of the profile, 1/s² (∞ for the linear law, which steps).
    pub peak_acc: R,
    /// Joint velocities just before the end (rad/s): a step to 0 unless 0.
    pub end_velocity: [R; JOINTS],
}

/// `max_j |Δ_j|/ω_j`: with the speeds, in seconds, the duration a profile
/// with max g′ = 1/T would need; with the accelerations (`max_j |Δ_j|/α_j`),
/// in s², the squared duration a profile with max |g″| = 1/T² would need.
pub fn time_ratio<R: Real>(req: &MoveRequest<R>, limit: &[R; JOINTS]) -> Result<R, PlanError> {
    let mut r = R::ZERO;
    for ((s, e), w) in req.start.iter().zip(req.target.iter()).zip(limit.iter()) {
        let d = (*e - *s).abs();
        if !(d.is_finite() && w.is_finite()) {
            return Err(PlanError::NotFinite);
        }
        if *w <= R::ZERO {
            return Err(PlanError::SpeedLimit);
        }
        r = r.max(d / *w);
    }
    Ok(r)
}
