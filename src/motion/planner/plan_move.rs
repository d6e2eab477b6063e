//! [`plan_move`]: the duration, shape and plan of one synchronized move (see
//! the [module doc](super) for the policy).

use super::duration::zat_duration;
use super::peak_rate::{law_ratios, zat_peak_acc, zat_peak_rate, Ratios};
use super::request::{time_ratio, MoveRequest, PlanError, PlanLimits, PlannedMove};
use super::shape_choice::{zat_shape, AChoice, ZatShape};
use crate::math::real::Real;
use crate::motion::laws::Law;
use crate::motion::plan::{JointLaw, LawKind, MultiPlan};
use crate::motion::scaled::ScaledZat;
use crate::motion::TrajError;

/// Longer durations the papers' ζ-a-tₛ tries for its acceleration limit
/// before it settles for the shortest passing one (3–5 suffice where
/// max |G″| falls with tₛ).
const ACC_SEARCH_STEPS: u8 = 16;
/// ln of the growth of tₛ when the secant gives no step (×1.25).
const ACC_SEARCH_GROW: f64 = 0.223;
/// How far below f = 0 the acceleration search aims (so that a candidate
/// usually passes).
const ACC_SEARCH_AIM: f64 = 0.005;
/// The acceleration search's tolerance on ln tₛ: the tₛ returned is at most
/// 1 % above the shortest one that passes.
const ACC_SEARCH_TOL: f64 = 0.01;

/// Plans a move under the speed and acceleration limits (see the module
/// doc): [`choose_law`], then [`plan_chosen`]. Not inlined, so that the
/// chosen law is not part of the caller's stack frame.
// The ChosenLaw it holds across the search stays out
// of its callers' frames.
#[inline(never)] // avr-trap: frame-size
pub fn plan_move<R: Real>(req: &MoveRequest<R>, lim: &PlanLimits<R>) -> Result<PlannedMove<R>, PlanError> {
    // By reference: a `?` would copy the law out of its Result.
    let chosen = choose_law(req, lim);
    plan_chosen(req, lim, chosen.as_ref().map_err(|e| *e)?)
}

/// The law a move is planned by ([`choose_law`]) and the bounds it was
/// chosen to satisfy.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChosenLaw<R> {
    /// The profile every joint follows.
    pub law: JointLaw<R>,
    /// The papers' ζ-a-tₛ shape choice; `None` for the other laws.
    pub a: Option<AChoice<R>>,
    /// max g′ of the profile, 1/s.
    pub peak: R,
    /// max |g″| of the profile, 1/s² (∞ for the linear law).
    pub peak_acc: R,
}

/// The duration search of a move: the law and its duration within the
/// limits. Kept apart from [`plan_chosen`]'s plan (the move's largest
/// value), so that a caller holding the plan's space is not on the stack
/// during the search.
// The duration searches below run deep; no plan
// (nor the caller's plan space) may share their callers' frames.
#[inline(never)] // avr-trap: frame-size
pub fn choose_law<R: Real>(req: &MoveRequest<R>, lim: &PlanLimits<R>) -> Result<ChosenLaw<R>, PlanError> {
    let ratio = time_ratio(req, &lim.speed)?;
    let acc_ratio = time_ratio(req, &lim.accel)?;
    match law_ratios(req.law) {
        None => {
            // By reference: a `?` would copy the shape out of its Result.
            let found = zat_paper(ratio, acc_ratio, lim);
            let (z, peak, peak_acc) = found.as_ref().map_err(|e| *e)?;
            Ok(ChosenLaw { law: JointLaw::Zat(z.shape), a: Some(z.choice()), peak: *peak, peak_acc: *peak_acc })
        }
        Some(r) => {
            let ts = scaled_duration(&r, &[ratio, acc_ratio], lim)?;
            let law = scaling_law(req.law, ts).map_err(|_| PlanError::Trajectory)?;
            let peak_acc = match r.acc {
                Some(c) => c / (ts * ts),
                None => R::lit(f64::INFINITY),
            };
            Ok(ChosenLaw { law, a: None, peak: r.vel / ts, peak_acc })
        }
    }
}

/// The plan of a move by the law [`choose_law`] chose for it, checked
/// against the limits again.
// The plan's temporaries stay out of the callers'
// frames (plan_move's is on the duration search's chain).
#[inline(never)] // avr-trap: frame-size
pub fn plan_chosen<R: Real>(
    req: &MoveRequest<R>,
    lim: &PlanLimits<R>,
    chosen: &ChosenLaw<R>,
) -> Result<PlannedMove<R>, PlanError> {
    let (peak, peak_acc) = (chosen.peak, chosen.peak_acc);
    let plan = MultiPlan::with_law(&req.start, &req.target, &chosen.law).map_err(|e| match e {
        TrajError::NotFinite => PlanError::NotFinite,
        _ => PlanError::Trajectory,
    })?;
    // Defence in depth: the bounds the choice above was made to satisfy
    // (the linear law's steps cannot satisfy an acceleration bound).
    let tol = R::ONE + R::lit(1e-4);
    let d = plan.delta();
    for ((d, w), acc) in d.iter().zip(lim.speed.iter()).zip(lim.accel.iter()) {
        if d.abs() * peak > *w * tol || (peak_acc.is_finite() && d.abs() * peak_acc > *acc * tol) {
            return Err(PlanError::SpeedLimit);
        }
    }
    let ts = plan.duration();
    Ok(PlannedMove { end_velocity: plan.end_velocities(), plan, ts, a: chosen.a, peak_rate: peak, peak_acc })
}

/// The profile of a law that scales with its duration, over `ts` (the
/// papers' ζ-a-tₛ gets the time-scaled one: it has no single shape).
#[inline(never)] // avr-trap: frame-size
pub fn scaling_law<R: Real>(kind: LawKind, ts: R) -> Result<JointLaw<R>, TrajError<R>> {
    let law = match kind {
        LawKind::Zat | LawKind::ZatPaper => return ScaledZat::new(ts).map(JointLaw::Scaled),
        LawKind::Quintic => Law::Quintic,
        LawKind::Cubic => Law::Cubic,
        LawKind::Trapezoid => Law::Trapezoid,
        LawKind::Linear => Law::Linear,
    };
    JointLaw::classic(law, ts)
}

/// The shortest duration of a profile that scales with its duration:
/// `max(ts_min, vel·ratio, √(acc·acc_ratio))` for `ratios` = [ratio,
/// acc_ratio] ([`time_ratio`] of the speeds and of the accelerations),
/// Err(SpeedLimit) past ts_max. Always inlined: LLVM would otherwise pass
/// its promoted arguments on the AVR's stack.
#[inline(always)]
pub fn scaled_duration<R: Real>(r: &Ratios<R>, ratios: &[R; 2], lim: &PlanLimits<R>) -> Result<R, PlanError> {
    let [ratio, acc_ratio] = *ratios;
    let mut ts = (r.vel * ratio).max(lim.ts_min);
    if let Some(c) = r.acc {
        ts = ts.max((c * acc_ratio).sqrt());
    }
    if ts <= lim.ts_max {
        Ok(ts)
    } else {
        Err(PlanError::SpeedLimit)
    }
}

/// The papers' ζ-a-tₛ: the shortest tₛ for the speeds ([`zat_duration`]);
/// while the largest |G″| ([`zat_peak_acc`]) breaks an acceleration limit, a
/// search for a longer one on f = ln(acc_ratio·max|G″|) over ln tₛ: secant
/// steps (the first assumes max|G″| ∝ 1/tₛ²) aimed [`ACC_SEARCH_AIM`] below
/// f = 0, growth by a quarter or bisection where a step would leave the
/// bracket, until the shortest passing tₛ is within [`ACC_SEARCH_TOL`] of
/// the longest failing one. max |G″| falls with tₛ for n ≥ 2 but not always
/// for smaller n, where a shorter tₛ inside a dip can pass too: the result
/// passes and is near the start of the passing range the search brackets,
/// not always the shortest. The speed bound is verified again on the shape
/// returned, with its P and max |G″|.
// The acceleration search's candidates live in
// zat_acc_search's frame, not in this one across zat_duration's search.
#[inline(never)] // avr-trap: frame-size
fn zat_paper<R: Real>(ratio: R, acc_ratio: R, lim: &PlanLimits<R>) -> Result<(ZatShape<R>, R, R), PlanError> {
    let found = zat_duration(ratio, lim);
    let (z, peak) = found.as_ref().map_err(|e| *e)?;
    let acc = zat_peak_acc(&z.shape);
    if acc_ratio * acc <= R::ONE {
        return Ok((*z, *peak, acc));
    }
    let mut b = AccBracket { ratio, acc_ratio, lo: z.shape.ts().ln(), f_lo: (acc_ratio * acc).ln() };
    zat_acc_search(&mut b, lim)
}

/// [`zat_acc_search`]'s ratios and the longest failing ln tₛ with its f,
/// which the search moves up. Passed by `&mut`: LLVM splits a read-only
/// reference to a small aggregate into scalars, which here would pass
/// past the 18 argument bytes the AVR has registers for.
struct AccBracket<R> {
    ratio: R,
    acc_ratio: R,
    lo: R,
    f_lo: R,
}

/// [`zat_paper`]'s search for a longer tₛ from the bracket's failing end.
// Its candidates are dead before zat_duration's deep
// search runs (they would share zat_paper's frame).
#[inline(never)] // avr-trap: frame-size
fn zat_acc_search<R: Real>(b: &mut AccBracket<R>, lim: &PlanLimits<R>) -> Result<(ZatShape<R>, R, R), PlanError> {
    let (ratio, acc_ratio) = (b.ratio, b.acc_ratio);
    let l = lim.n.ln();
    // The shortest passing candidate.
    let mut best: Option<(ZatShape<R>, R, R)> = None;
    let mut slope = -R::TWO;
    let ln_max = lim.ts_max.ln();
    let mut k = 0;
    while k < ACC_SEARCH_STEPS {
        k += 1;
        let hi = match &best {
            Some((c, _, _)) => c.shape.ts().ln(),
            None => ln_max,
        };
        if best.is_some() && hi - b.lo <= R::lit(ACC_SEARCH_TOL) {
            break;
        }
        // A step must move a quarter of the tolerance away from both ends,
        // or it would only re-evaluate a known candidate.
        let gap = R::lit(0.25 * ACC_SEARCH_TOL);
        let mut x = b.lo - (b.f_lo + R::lit(ACC_SEARCH_AIM)) / slope;
        if !(x > b.lo + gap && x < hi - gap) {
            // No useful step: bisect the bracket, or grow by a quarter
            // while none passed yet (max |G″| need not fall with tₛ: for
            // small n it rises again over part of [1.2, 2] s).
            x = if best.is_some() { R::HALF * (b.lo + hi) } else { (b.lo + R::lit(ACC_SEARCH_GROW)).min(hi) };
        }
        let c = zat_shape(x.exp().min(lim.ts_max), lim.n, l).map_err(|_| PlanError::Trajectory)?;
        let acc = zat_peak_acc(&c.shape);
        let f = (acc_ratio * acc).ln();
        if f <= R::ZERO {
            let peak = zat_peak_rate(&c.shape);
            if ratio * peak <= R::ONE {
                best = Some((c, peak, acc));
                continue;
            }
        }
        if !x.lt(&ln_max) {
            break;
        }
        let s = (f - b.f_lo) / (x - b.lo);
        slope = if s < R::ZERO { s } else { -R::TWO };
        b.lo = x;
        b.f_lo = f;
    }
    best.ok_or(PlanError::SpeedLimit)
}
