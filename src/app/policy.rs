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
//!   `P(tₛ) = max g′`. P is found numerically ([`zat_peak_rate`]) and tₛ by a
//!   bracketed search ([`zat_duration`]) between `zat_ts_min` and `ts_max`:
//!   both ends are evaluated, then at most [`TS_SEARCH_STEPS`] Illinois
//!   (regula falsi) steps on `ln(r·P)` over `ln tₛ`. The answer is always a
//!   tₛ where the bound was *verified*; the search only makes it shorter.
//!   With n = 2, P falls from 1.8/s at tₛ = 1.2 s to about 0.7/s at 4 s and
//!   then only slowly (0.51/s at 10 s, 0.27/s at 20 s): beyond the smooth
//!   stop's range a ζ-a-tₛ move is a hump of width ~√tₛ around t ≈ √tₛ, a
//!   near-stop and a slow creep, so large slow moves get long tₛ.
//!
//! # Shape
//! [`choose_a`]: the smooth stop a* = tₛ − log_n tₛ (zero end velocity) when it
//! is admissible *and* monotone; otherwise the largest a whose profile is
//! still monotone, which has the smallest end velocity a monotone profile can
//! have (the end rate falls as a grows toward a*). For tₛ > 1 that limit has a
//! closed form ([`monotone_limit_a`]); for tₛ ≤ 1 every admissible a is
//! monotone and the end rate only approaches its infimum L/tₛ as a → −∞, so
//! a = tₛ − 16/L is used (within 1e-7 of the infimum).
//!
//! # Cost on the chip
//! One ζ-a-tₛ candidate costs up to three [`Shape`] constructions and
//! `2·(PEAK_GRID + 2 + PEAK_GOLDEN_STEPS)` = 32 evaluations of G and G′ (two
//! exponentials each); a search evaluates at most `2 + TS_SEARCH_STEPS` = 8
//! candidates, about 550 exponentials (~100 ms of AVR soft-float at worst,
//! one candidate ~15 ms). The frame that plans may overrun; the PWM keeps its
//! last pulses meanwhile and the plan clock counts frames, so this delays the
//! move, it never jerks it.

use crate::laws::Law;
use crate::motion::TrajError;
use crate::plan::{JointLaw, LawKind, MultiPlan, JOINTS};
use crate::real::Real;
use crate::servo::Joint;
use crate::zat::{smooth_stop_a, u_min, Shape, ShapeParams};

/// Points of the coarse scan of G′ per piece (the last one is the piece's end).
pub const PEAK_GRID: u16 = 6;
/// Golden-section steps refining the best two grid cells (0.618⁸ ≈ 2 %).
pub const PEAK_GOLDEN_STEPS: u8 = 8;
/// Lowest `zat_ts_min` the app accepts: see [`zat_peak_rate`].
pub const ZAT_TS_FLOOR: f32 = 1.05;
/// Illinois steps of the ζ-a-tₛ duration search after its two end points.
pub const TS_SEARCH_STEPS: u8 = 6;
/// The search stops when the bracket is narrower than this ratio (1 %).
const TS_SEARCH_RATIO: f64 = 1.01;
/// tₛ ≤ 1: a = tₛ − A_FLOOR/L, q(tₛ) = 1/expm1(16) ≈ 1e-7.
const A_FLOOR: f64 = 16.0;
/// Relative step below the closed-form monotonicity limit, so that rounding
/// cannot put the chosen a on the wrong side of it.
const A_BACKOFF: f64 = 1e-4;

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

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AChoice<R> {
    pub a: R,
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
    if !(ts.is_finite() && n.is_finite()) || ts <= R::ONE || n <= R::ONE {
        return None;
    }
    let l = n.ln();
    let t_star = (R::ONE + (R::ONE + l * l * ts).sqrt()) / l;
    let tm = t_star.min(ts);
    let a = tm + ts / tm - R::ONE - (tm * tm / ts).ln() / l;
    if a.is_finite() {
        Some(a)
    } else {
        None
    }
}

/// The shape parameter for a ζ-a-tₛ move of duration `ts` (see the module doc).
pub fn choose_a<R: Real>(ts: R, n: R) -> Result<AChoice<R>, TrajError<R>> {
    if !(ts.is_finite() && n.is_finite()) {
        return Err(TrajError::NotFinite);
    }
    if ts <= R::ZERO {
        return Err(TrajError::NonPositiveDuration);
    }
    if n <= R::ONE {
        return Err(TrajError::BaseNotAboveOne);
    }
    if let Some(a) = smooth_stop_a(ts, n) {
        if let Ok(s) = Shape::new(&ShapeParams { ts, a, n }) {
            if s.is_monotone() {
                return Ok(AChoice { a, kind: AKind::SmoothStop });
            }
        }
    }
    let (a, kind) = match monotone_limit_a(ts, n) {
        Some(lim) => (lim - R::lit(A_BACKOFF) * (R::ONE + lim.abs()), AKind::MonotoneLimit),
        None => (ts - R::lit(A_FLOOR) / n.ln(), AKind::Floor),
    };
    // Guards against the (not expected) case that the limit sits on the pole.
    let a = a.min(u_min(ts) - R::lit(A_BACKOFF) * (R::ONE + ts));
    let shape = Shape::new(&ShapeParams { ts, a, n })?;
    shape.check_monotone()?;
    Ok(AChoice { a, kind })
}

/// `max g′` of a classic law per unit of 1/T.
pub fn classic_peak_factor(law: Law) -> f64 {
    match law {
        Law::Linear => 1.0,
        Law::Cubic => 1.5,
        Law::Quintic => 1.875,
        Law::Trapezoid => 1.5,
    }
}

/// `max g′` over (0, tₛ] of a ζ-a-tₛ profile.
///
/// G′ is not unimodal in general: where the monotonicity margin φ is
/// smallest, at t* = (1 + √(1 + L²tₛ))/L, G′ dips (to about 0 for the
/// monotone-limit shapes [`choose_a`] makes for long tₛ), so a long move is a
/// hump near √tₛ, a near-stop at t* and a slow creep to the target. The search
/// therefore treats (0, t*] and [t*, tₛ] separately when t* < tₛ (each one
/// hump), each with a grid of [`PEAK_GRID`] points ending at the piece's end
/// (at tₛ: the left limit) and golden-section steps on the two cells around
/// the best point. Golden section never overestimates a maximum; the result
/// is within 1e-3 of the true peak for n ∈ [1.1, 10] and tₛ outside
/// (1, [`ZAT_TS_FLOOR`]) (checked against dense scans in the tests). Just above
/// tₛ = 1 the smooth stop a* lies within 1e-3 of the pole and G′ is a spike
/// the grid can straddle (0.8 % low seen at tₛ = 1.0004); the app never plans
/// there.
pub fn zat_peak_rate<R: Real>(shape: &Shape<R>) -> R {
    let ts = shape.ts();
    let l = shape.ln_n();
    let t_star = (R::ONE + (R::ONE + l * l * ts).sqrt()) / l;
    if t_star < ts && t_star > R::ZERO {
        peak_on(shape, R::ZERO, t_star).max(peak_on(shape, t_star, ts))
    } else {
        peak_on(shape, R::ZERO, ts)
    }
}

/// Grid plus golden section for the largest G′ on (lo, hi].
fn peak_on<R: Real>(shape: &Shape<R>, lo: R, hi: R) -> R {
    let h = (hi - lo) / R::from_u16(PEAK_GRID);
    let rate = |t: R| shape.g_rate(t).1;
    let mut best = R::ZERO;
    let mut best_i: u16 = 0;
    let mut i: u16 = 1;
    while i <= PEAK_GRID {
        let t = if i == PEAK_GRID { hi } else { lo + h * R::from_u16(i) };
        let r = rate(t);
        if r > best {
            best = r;
            best_i = i;
        }
        i += 1;
    }
    let inv_phi = R::lit(0.618_033_988_749_895);
    let mut a = lo + h * R::from_u16(best_i.saturating_sub(1));
    let mut b = (lo + h * R::from_u16(best_i + 1)).min(hi);
    let mut c = b - (b - a) * inv_phi;
    let mut d = a + (b - a) * inv_phi;
    let (mut fc, mut fd) = (rate(c), rate(d));
    let mut k = 0;
    while k < PEAK_GOLDEN_STEPS {
        if fc > fd {
            b = d;
            d = c;
            fd = fc;
            c = b - (b - a) * inv_phi;
            fc = rate(c);
        } else {
            a = c;
            c = d;
            fc = fd;
            d = a + (b - a) * inv_phi;
            fd = rate(d);
        }
        k += 1;
    }
    best.max(fc).max(fd)
}

/// `max g′` of any profile (closed form for the classic laws).
pub fn peak_rate<R: Real>(law: &JointLaw<R>) -> R {
    match law {
        JointLaw::Zat(s) => zat_peak_rate(s),
        JointLaw::Classic(p) => R::lit(classic_peak_factor(p.law())) / p.duration(),
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

/// A ζ-a-tₛ profile of duration `ts` with its a and peak rate.
#[derive(Debug, Clone, Copy)]
struct ZatCandidate<R> {
    ts: R,
    shape: Shape<R>,
    a: AChoice<R>,
    peak: R,
}

fn zat_candidate<R: Real>(ts: R, n: R) -> Result<ZatCandidate<R>, TrajError<R>> {
    let a = choose_a(ts, n)?;
    let shape = Shape::new(&ShapeParams { ts, a: a.a, n })?;
    let peak = zat_peak_rate(&shape);
    Ok(ZatCandidate { ts, shape, a, peak })
}

/// The ζ-a-tₛ duration: the shortest tₛ in [zat_ts_min, ts_max] (to about
/// 1 %) with `ratio · P(tₛ) ≤ 1`. Err(SpeedLimit) if even ts_max is too fast.
fn zat_duration<R: Real>(ratio: R, lim: &PlanLimits<R>) -> Result<ZatCandidate<R>, Refusal> {
    let cand = |ts: R| zat_candidate(ts, lim.n).map_err(|_| Refusal::Trajectory);
    let lo = cand(lim.zat_ts_min)?;
    if ratio * lo.peak <= R::ONE {
        return Ok(lo);
    }
    let hi = cand(lim.ts_max)?;
    if !(ratio * hi.peak <= R::ONE) {
        return Err(Refusal::SpeedLimit);
    }
    // f(x) = ln(ratio·P(eˣ)): > 0 at xl (too fast), ≤ 0 at xh (verified).
    let f = |c: &ZatCandidate<R>| (ratio * c.peak).ln();
    let (mut xl, mut fl) = (lo.ts.ln(), f(&lo));
    let (mut xh, mut fh) = (hi.ts.ln(), f(&hi));
    let mut best = hi;
    let stop = R::lit(TS_SEARCH_RATIO).ln();
    let mut side = 0i8;
    let mut k = 0;
    while k < TS_SEARCH_STEPS && xh - xl > stop {
        let w = xh - xl;
        let denom = fh - fl;
        let mut x = if denom < R::ZERO && denom.is_finite() {
            xh - fh * w / denom
        } else {
            xl + w * R::HALF
        };
        // Stay strictly inside the bracket so every step shrinks it.
        let guard = w * R::lit(0.05);
        x = x.max(xl + guard).min(xh - guard);
        let c = cand(x.exp())?;
        let fx = f(&c);
        if fx <= R::ZERO {
            xh = x;
            fh = fx;
            best = c;
            if side == 1 {
                fl *= R::HALF;
            }
            side = 1;
        } else {
            xl = x;
            fl = fx;
            if side == -1 {
                fh *= R::HALF;
            }
            side = -1;
        }
        k += 1;
    }
    Ok(best)
}

/// Plans a move under the speed limits (see the module doc).
pub fn plan_move<R: Real>(req: &MoveRequest<R>, lim: &PlanLimits<R>) -> Result<PlannedMove<R>, Refusal> {
    let ratio = time_ratio(req, &lim.speed)?;
    let (law, ts, a, peak) = match req.law {
        LawKind::Zat => {
            let c = zat_duration(ratio, lim)?;
            (JointLaw::Zat(c.shape), c.ts, Some(c.a), c.peak)
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
