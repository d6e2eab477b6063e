//! [`plan_move`]: the duration, shape and plan of one synchronized move (see
//! the [module doc](super) for the policy).

use super::duration::zat_duration;
use super::peak_rate::classic_peak_factor;
use super::request::{time_ratio, MoveRequest, PlanError, PlanLimits, PlannedMove};
use crate::math::real::Real;
use crate::motion::laws::Law;
use crate::motion::plan::{JointLaw, LawKind, MultiPlan};
use crate::motion::TrajError;

/// Plans a move under the speed limits (see the module doc).
pub fn plan_move<R: Real>(req: &MoveRequest<R>, lim: &PlanLimits<R>) -> Result<PlannedMove<R>, PlanError> {
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
            if !ts.le(&lim.ts_max) {
                return Err(PlanError::SpeedLimit);
            }
            let law = JointLaw::classic(classic, ts).map_err(|_| PlanError::Trajectory)?;
            (law, ts, None, R::lit(factor) / ts)
        }
    };
    let plan = MultiPlan::with_law(&req.start, &req.target, &law).map_err(|e| match e {
        TrajError::NotFinite => PlanError::NotFinite,
        _ => PlanError::Trajectory,
    })?;
    // Defence in depth: the bound the choice above was made to satisfy.
    let tol = R::ONE + R::lit(1e-4);
    for ((s, e), w) in req.start.iter().zip(req.target.iter()).zip(lim.speed.iter()) {
        if (*e - *s).abs() * peak > *w * tol {
            return Err(PlanError::SpeedLimit);
        }
    }
    Ok(PlannedMove { end_velocity: plan.end_velocities(), plan, ts, a, peak_rate: peak })
}
