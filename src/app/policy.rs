//! Motion planning policy: how long a move takes (tₛ), which ζ-a-tₛ shape it
//! uses (a), and why a move is refused.
//!
//! # Duration
//! Every joint follows `q0 + Δ_j·g(t)` with one shared profile g, so joint j
//! peaks at `|Δ_j|·max g′`. The move may use `ω_j` (rad/s) on joint j (the
//! caller derives it from the joint's `max_speed_rad_s`, the speed preset and
//! a safety margin), so the requirement is `r · max g′ ≤ 1` with the *time
//! ratio* `r = max_j |Δ_j|/ω_j` (seconds).
//! - Classic laws scale with their duration T: `max g′ = c/T` with c = 1
//!   (linear), 1.5 (cubic, trapezoid with T/3 ramps), 1.875 (quintic), so
//!   `T = max(ts_min, c·r)` is the shortest admissible duration, in closed form.
//! - ζ-a-tₛ is written in seconds, so its shape changes with tₛ and so does
//!   `P(tₛ) = max g′`. P is found numerically ([`zat_peak_rate`](crate::peak_rate::zat_peak_rate): Newton on
//!   G″ = 0 per hump, exact to 1e-4 and never below the true peak) and tₛ by
//!   a Newton search ([`super::duration`]) on `ln(r·P)` over `ln(tₛ − 1)`
//!   between `zat_ts_min` and `ts_max`, with the derivative of ln P from the
//!   envelope theorem. The answer is always a tₛ whose P was *verified*
//!   (computed exactly, not estimated); it is at most [`TS_SEARCH_TOL`](super::duration::TS_SEARCH_TOL) = 1 %
//!   longer than the shortest admissible tₛ (0.4 % on average; checked
//!   against bisection on dense f64 scans in the tests for n ∈ [1.3, 8]).
//!   With n = 2, P falls from 1.8/s at tₛ = 1.2 s to about 0.7/s at 4 s and
//!   then only slowly (0.51/s at 10 s, 0.27/s at 20 s): beyond the smooth
//!   stop's range a ζ-a-tₛ move is a hump of width ~√tₛ around t ≈ √tₛ, a
//!   near-stop and a slow creep, so large slow moves get long tₛ. P falls
//!   with tₛ for n ≥ 1.25; for smaller n it rises on part of [1, 2] s, and
//!   the search then returns a verified tₛ that need not be the shortest.
//!
//! # Shape
//! The smooth stop a* while it is monotone, else the largest monotone a:
//! see [`super::shape_choice`].
//!
//! # Cost on the chip
//! Measured (bench row `app_plan_move`, n = 2, joint speeds 0.5 rad/s, moves
//! needing tₛ from 1.6 s to 20 s): median 192 000 cycles (12 ms at 16 MHz),
//! at most 201 000; the search this replaced took 1 756 000 (max 2 060 000).
//! A search evaluates 2–4 candidates for n = 2 (at most 12 for any n): each
//! builds its shape (~12 000–16 000 cycles) and estimates P from about one
//! evaluation of G with its first three log-derivatives (~14 000), and the
//! one returned gets one or two more. Larger n costs more where the creep
//! after t* must be searched too (n = 5: about 10 evaluations per search).
//! The frame that plans may overrun; the PWM keeps its last pulses meanwhile
//! and the plan clock counts frames, so this delays the move, it never jerks
//! it.

use super::duration::zat_duration;
use super::shape_choice::AChoice;
use crate::laws::Law;
use crate::motion::TrajError;
use crate::peak_rate::classic_peak_factor;
use crate::plan::{JointLaw, LawKind, MultiPlan, JOINTS};
use crate::real::Real;
use crate::servo::Joint;

/// Lowest `zat_ts_min` the app accepts: just above tₛ = 1 the smooth stop
/// lies within 1e-3 of the pole and G′ is a spike f32 resolves poorly (see
/// [`crate::peak_rate::zat_peak_rate`]).
pub const ZAT_TS_FLOOR: f32 = 1.05;

/// Why the app refuses a request (and keeps holding its pose).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    /// STOP is latched: send `resume` first.
    Stopped,
    /// Power-up: the home pose is still settling.
    Homing,
    /// A move is running (calibration changes and saves wait for rest).
    Busy,
    /// A raw touch outside the calibrated panel span.
    OutsideCalibration,
    /// The mapped point is not in [−1, 1] × [0, 1] (or the scale is bad).
    OutsideWorkspace,
    /// The IK target lies outside the arm's annulus.
    Unreachable,
    /// The IK target is the shoulder itself (undefined shoulder angle).
    Singular,
    /// The target angle of this joint is outside its configured limits (it is
    /// refused, never clamped into a different pose).
    JointLimit(Joint),
    /// The joints' speed limits cannot be met within `ts_max`.
    SpeedLimit,
    /// The trajectory is inadmissible or not monotone.
    Trajectory,
    /// A non-finite number where a pose was expected.
    NotFinite,
    /// A setpoint the servo layer refused (a bug): STOP was latched.
    Fault,
    /// The calibration change would put the held pose outside the limits.
    HeldPoseOutside,
}

impl Refusal {
    /// Text of the `err <reason>` reply.
    pub fn reason(self) -> crate::text::Text {
        match self {
            Refusal::Stopped => t!("stopped (send resume)"),
            Refusal::Homing => t!("homing"),
            Refusal::Busy => t!("busy moving"),
            Refusal::OutsideCalibration => t!("outside calibrated area"),
            Refusal::OutsideWorkspace => t!("outside workspace"),
            Refusal::Unreachable => t!("unreachable"),
            Refusal::Singular => t!("singular point"),
            Refusal::JointLimit(Joint::Base) => t!("joint limit base"),
            Refusal::JointLimit(Joint::Shoulder) => t!("joint limit shoulder"),
            Refusal::JointLimit(Joint::Elbow) => t!("joint limit elbow"),
            Refusal::SpeedLimit => t!("speed limit needs ts above max"),
            Refusal::Trajectory => t!("trajectory not admissible"),
            Refusal::NotFinite => t!("not finite"),
            Refusal::Fault => t!("fault: setpoint refused, stopped"),
            Refusal::HeldPoseOutside => t!("held pose outside new limits"),
        }
    }
}

/// Durations and the ζ-a-tₛ base for planning, and the speed each joint may
/// use in this move.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlanLimits<R> {
    /// Largest joint speed for this move, rad/s, per joint (> 0).
    pub speed: [R; JOINTS],
    /// Shortest classic move, s.
    pub ts_min: R,
    /// Shortest ζ-a-tₛ move, s (> 1 keeps the smooth stop available).
    pub zat_ts_min: R,
    /// Longest move of any law, s.
    pub ts_max: R,
    /// ζ-a-tₛ base n.
    pub n: R,
}

/// One move to plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MoveRequest<R> {
    pub start: [R; JOINTS],
    pub target: [R; JOINTS],
    pub law: LawKind,
}

/// A planned move and what the app reports about it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlannedMove<R> {
    pub plan: MultiPlan<R>,
    /// Duration, s.
    pub ts: R,
    /// The ζ-a-tₛ shape choice; `None` for the classic laws.
    pub a: Option<AChoice<R>>,
    /// max g′ of the profile, 1/s.
    pub peak_rate: R,
    /// Joint velocities just before the end (rad/s): a step to 0 unless 0.
    pub end_velocity: [R; JOINTS],
}

/// `max_j |Δ_j|/ω_j` in seconds: the duration a profile with max g′ = 1/T
/// would need.
pub fn time_ratio<R: Real>(req: &MoveRequest<R>, speed: &[R; JOINTS]) -> Result<R, Refusal> {
    let mut r = R::ZERO;
    for ((s, e), w) in req.start.iter().zip(req.target.iter()).zip(speed.iter()) {
        let d = (*e - *s).abs();
        if !(d.is_finite() && w.is_finite()) {
            return Err(Refusal::NotFinite);
        }
        if !(*w > R::ZERO) {
            return Err(Refusal::SpeedLimit);
        }
        r = r.max(d / *w);
    }
    Ok(r)
}

/// Plans a move under the speed limits (see the module doc).
pub fn plan_move<R: Real>(req: &MoveRequest<R>, lim: &PlanLimits<R>) -> Result<PlannedMove<R>, Refusal> {
    let ratio = time_ratio(req, &lim.speed)?;
    let (law, ts, a, peak) = match req.law {
        LawKind::Zat => {
            let (z, peak) = zat_duration(ratio, lim)?;
            (JointLaw::Zat(z.shape), z.shape.ts(), Some(z.choice()), peak)
        }
        kind => {
            let (classic, factor) = match kind {
                LawKind::Quintic => (Law::Quintic, classic_peak_factor(Law::Quintic)),
                LawKind::Cubic => (Law::Cubic, classic_peak_factor(Law::Cubic)),
                LawKind::Trapezoid => (Law::Trapezoid, classic_peak_factor(Law::Trapezoid)),
                _ => (Law::Linear, classic_peak_factor(Law::Linear)),
            };
            let ts = (R::lit(factor) * ratio).max(lim.ts_min);
            if !(ts <= lim.ts_max) {
                return Err(Refusal::SpeedLimit);
            }
            let law = JointLaw::classic(classic, ts).map_err(|_| Refusal::Trajectory)?;
            (law, ts, None, R::lit(factor) / ts)
        }
    };
    let plan = MultiPlan::with_law(&req.start, &req.target, &law).map_err(|e| match e {
        TrajError::NotFinite => Refusal::NotFinite,
        _ => Refusal::Trajectory,
    })?;
    // Defence in depth: the bound the choice above was made to satisfy.
    let tol = R::ONE + R::lit(1e-4);
    for ((s, e), w) in req.start.iter().zip(req.target.iter()).zip(lim.speed.iter()) {
        if (*e - *s).abs() * peak > *w * tol {
            return Err(Refusal::SpeedLimit);
        }
    }
    Ok(PlannedMove {
        end_velocity: plan.end_velocities(),
        plan,
        ts,
        a,
        peak_rate: peak,
    })
}
