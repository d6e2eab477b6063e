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
//!   `P(tₛ) = max g′`. P is found numerically ([`zat_peak_rate`]: Newton on
//!   G″ = 0 per hump, exact to 1e-4 and never below the true peak) and tₛ by
//!   a Newton search ([`zat_duration`]) on `ln(r·P)` over `ln(tₛ − 1)`
//!   between `zat_ts_min` and `ts_max`, with the derivative of ln P from the
//!   envelope theorem. The answer is always a tₛ whose P was *verified*
//!   (computed exactly, not estimated); it is at most [`TS_SEARCH_TOL`] = 1 %
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
//! [`choose_a`]: the smooth stop a* = tₛ − log_n tₛ (zero end velocity) while
//! it is monotone, i.e. L·(tₛ − 1) ≤ 2; otherwise the largest a whose profile
//! is still monotone, which has the smallest end velocity a monotone profile
//! can have (the end rate falls as a grows toward a*). For tₛ > 1 that limit
//! has a closed form ([`monotone_limit_a`]); for tₛ ≤ 1 every admissible a is
//! monotone and the end rate only approaches its infimum L/tₛ as a → −∞, so
//! a = tₛ − 16/L is used (within 1e-7 of the infimum). One [`Shape`] is
//! built per tₛ.
//!
//! # Cost on the chip
//! Measured (bench row `app_plan_move`, n = 2, joint speeds 0.5 rad/s, moves
//! needing tₛ from 1.6 s to 20 s): median 212 000 cycles (13 ms at 16 MHz),
//! at most 222 000; the search this replaced took 1 756 000 (max 2 060 000).
//! A search evaluates 2–4 candidates for n = 2 (at most 12 for any n): each
//! builds its shape (~12 000–16 000 cycles) and estimates P from about one
//! evaluation of G with its first three log-derivatives (~14 000), and the
//! one returned gets one or two more. Larger n costs more where the creep
//! after t* must be searched too (n = 5: about 10 evaluations per search).
//! The frame that plans may overrun; the PWM keeps its last pulses meanwhile
//! and the plan clock counts frames, so this delays the move, it never jerks
//! it.

use crate::laws::Law;
use crate::motion::TrajError;
use crate::plan::{JointLaw, LawKind, MultiPlan, JOINTS};
use crate::real::Real;
use crate::servo::Joint;
use crate::zat::{u_min, Shape, ShapeParams};

/// The peak search stops once the last Newton step predicts G′ to rise by
/// less than this (relative), and reports the quadratic model's maximum plus
/// that rise once more: never below the true peak in the tests (the model's
/// own error, cubic in the step, stayed below 2.1e-6), at most 1e-4 above.
const PEAK_TOL: f64 = 1e-4;
/// The estimate a candidate steers the duration search with: the model's
/// maximum once the predicted rise is below this (usually after one
/// evaluation; its error is second order in the remaining step).
const PEAK_ROUGH: f64 = 3e-2;
/// Cap on the peak search's iterations (Newton needs 1–3; a step it cannot
/// take bisects the bracket).
const PEAK_STEPS: u8 = 32;
/// First guess of where G′ peaks, in units of √tₛ (0.77 for n = 2 at
/// tₛ = 1.2, 0.69–0.94 over tₛ ∈ [1.2, 30]); later candidates of a search
/// start from the previous candidate's peak.
const PEAK_GUESS: f64 = 0.8;
/// Lowest `zat_ts_min` the app accepts: see [`zat_peak_rate`].
pub const ZAT_TS_FLOOR: f32 = 1.05;
/// The duration search's tolerance: the returned tₛ is at most this much
/// (relative) above the shortest admissible one.
pub const TS_SEARCH_TOL: f64 = 0.01;
/// Where the search aims, relative to its prediction of the shortest tₛ:
/// far enough past it that the prediction's error rarely lands the
/// candidate on the failing side, well inside the tolerance.
const TS_SEARCH_AIM: f64 = 0.004;
/// Candidates after the first before the search settles for the shortest
/// passing one, or ts_max (n = 2 needs 1–3).
pub const TS_SEARCH_STEPS: u8 = 10;
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
    let t_star = (R::ONE + (R::ONE + l * l * ts).sqrt()) / l;
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
struct ZatShape<R> {
    shape: Shape<R>,
    kind: AKind,
    /// t* = (1 + √(1 + L²tₛ))/L when it lies inside the motion, else 0: G′
    /// dips to about 0 there (see [`zat_peak_rate`]).
    t_star: R,
    /// da/dtₛ of the choice.
    da: R,
}

impl<R: Real> ZatShape<R> {
    fn choice(&self) -> AChoice<R> {
        AChoice { a: self.shape.a(), kind: self.kind }
    }

    /// The end of the first hump's piece.
    fn first_end(&self) -> R {
        if self.t_star > R::ZERO {
            self.t_star
        } else {
            self.shape.ts()
        }
    }
}

/// [`choose_a`]'s shape given L = ln n. Monotonicity is not checked here for
/// the monotone-limit and floor shapes (they are monotone by construction;
/// [`MultiPlan::with_law`] checks the one a plan uses).
// Not inlined, so that its callees' frames are not part of the callers'.
#[inline(never)]
fn zat_shape<R: Real>(ts: R, n: R, l: R) -> Result<ZatShape<R>, TrajError<R>> {
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
/// hump near √tₛ, a near-stop at t* and a slow creep to the target whose
/// rate rises to the end or peaks once before it. The search treats (0, t*]
/// and [t*, tₛ] separately when t* < tₛ, each one hump: safeguarded Newton
/// on G″ = 0 (G‴ from [`Shape::rate_terms`]; a step leaving the bracket that
/// the signs of G″ keep bisects it), stopped when the step predicts a rise
/// of G′ below 1e-4 (`PEAK_TOL`); it reports that quadratic model's maximum plus
/// the predicted rise once more, which covers the model's neglected cubic
/// term: never below the true peak and at most 1e-4 above it (f32: 2e-5
/// below to 1.2e-4 above), checked against dense scans refined by golden
/// section in f64 in the tests for n ∈ [1.1, 10]. A piece ending at
/// tₛ first looks at G″(tₛ⁻): when G′ still rises there, its end value is
/// the piece's maximum. Just above tₛ = 1 the smooth stop a* lies within
/// 1e-3 of the pole and G′ is a spike that f32 resolves poorly; the app never
/// plans below [`ZAT_TS_FLOOR`].
pub fn zat_peak_rate<R: Real>(shape: &Shape<R>) -> R {
    let ts = shape.ts();
    let l = shape.ln_n();
    let t_star = (R::ONE + (R::ONE + l * l * ts).sqrt()) / l;
    let split = t_star < ts && t_star > R::ZERO;
    let hi = if split { t_star } else { ts };
    let mut pc = Piece {
        lo: R::ZERO,
        hi,
        guess: peak_guess(ts, hi, R::lit(PEAK_GUESS)),
        limit: R::lit(f64::MAX),
        tol: R::lit(PEAK_TOL),
        end: !split,
    };
    let p = piece_max(shape, &pc).rate;
    if split {
        pc.lo = t_star;
        pc.hi = ts;
        pc.guess = ts;
        pc.end = true;
        p.max(piece_max(shape, &pc).rate)
    } else {
        p
    }
}

/// ρ·√tₛ inside (0, hi).
fn peak_guess<R: Real>(ts: R, hi: R, rho: R) -> R {
    let g = rho * ts.sqrt();
    if g > R::ZERO && g < hi {
        g
    } else {
        R::lit(0.9) * hi
    }
}

/// One piece (lo, hi] of (0, tₛ] on which G′ is taken to be unimodal.
struct Piece<R> {
    lo: R,
    hi: R,
    /// Where to start inside the piece (≥ hi: from the end's Newton step).
    guess: R,
    /// A G′ above this fails the candidate anyway, so a rough maximum does.
    limit: R,
    /// Predicted relative rise at which to stop.
    tol: R,
    /// The maximum may be at hi = tₛ: look at G″(tₛ⁻) first.
    end: bool,
}

/// The largest G′ of a piece, and where.
#[derive(Debug, Clone, Copy)]
struct Hump<R> {
    rate: R,
    /// Where it is, with q and h1 = G′/G there (for d ln P/dtₛ).
    t: R,
    q: R,
    h1: R,
    /// Where the search would go on (the last Newton step's target).
    next: R,
    /// The maximum is the end value G′(tₛ⁻).
    at_end: bool,
    /// An evaluated G′ exceeds the piece's limit.
    over: bool,
    /// `rate` is the maximum to [`PEAK_TOL`] (not only the piece's `tol`).
    exact: bool,
}

/// Safeguarded Newton for the maximum of G′ on a piece (see [`zat_peak_rate`]).
// Not inlined: several call sites, and one inlined search makes a function
// too long for the AVR's relative jumps (the linker refuses it).
#[inline(never)]
fn piece_max<R: Real>(shape: &Shape<R>, pc: &Piece<R>) -> Hump<R> {
    let (mut lo, mut hi) = (pc.lo, pc.hi);
    let mut t = pc.guess;
    let mut best = Hump {
        rate: R::ZERO,
        t,
        q: R::ZERO,
        h1: R::ZERO,
        next: t,
        at_end: false,
        over: false,
        exact: false,
    };
    if pc.end {
        if let Some(r) = shape.rate_terms(hi) {
            let rate = r.g * r.h1;
            let c2 = r.h1 * r.h1 + r.h2;
            best = Hump { rate, t: hi, q: r.q, h1: r.h1, next: hi, at_end: true, over: rate > pc.limit, exact: true };
            if !(c2 < R::ZERO) {
                return best;
            }
            best.exact = false;
            let c3 = r.h1 * (r.h1 * r.h1 + R::lit(3.0) * r.h2) + r.h3;
            let next = hi - c2 / c3;
            if t >= hi && c3 < R::ZERO && next > lo && next < hi {
                t = next;
            }
        }
    }
    if !(t > lo && t < hi) {
        t = R::HALF * (lo + hi);
    }
    let mut k = 0;
    while k < PEAK_STEPS {
        k += 1;
        let mut next = None;
        match shape.rate_terms(t) {
            // G below 1e-34: far left of the peak.
            None => lo = t,
            Some(r) => {
                let h1 = r.h1;
                let rate = r.g * h1;
                // G″/G and G‴/G.
                let c2 = h1 * h1 + r.h2;
                let c3 = h1 * (h1 * h1 + R::lit(3.0) * r.h2) + r.h3;
                if rate > pc.limit {
                    best.over = true;
                }
                if c2 > R::ZERO {
                    lo = t;
                } else {
                    hi = t;
                }
                if rate > best.rate {
                    best = Hump { rate, t, q: r.q, h1, next: t, at_end: false, over: best.over, exact: false };
                }
                if c3 < R::ZERO {
                    let dt = -c2 / c3;
                    // The quadratic model's rise of G′/G to its maximum (≥ 0).
                    let gain = R::HALF * c2 * dt;
                    let stepped = t + dt;
                    // A candidate that fails anyway only needs the estimate.
                    let tol = if best.over { pc.tol.max(R::lit(PEAK_ROUGH)) } else { pc.tol };
                    if gain <= tol * h1 {
                        // Converged: the model's maximum plus the rise once
                        // more, which covers the neglected cubic term (the
                        // tests find no underestimate). Rough: the model's.
                        let exact = gain <= R::lit(PEAK_TOL) * h1;
                        let top = r.g * (h1 + if exact { gain + gain } else { gain });
                        if top >= best.rate {
                            // q and h1 carried to the model's maximizer to first
                            // order (q′ = −L·q·(1 + q)·u′), so that
                            // [`ln_peak_slope`] sees the maximum, not t.
                            let up = R::ONE - shape.ts() / (t * t);
                            let dq = -shape.ln_n() * r.q * (R::ONE + r.q) * up * dt;
                            best = Hump {
                                rate: top,
                                t: stepped,
                                q: r.q + dq,
                                h1: h1 + r.h2 * dt,
                                next: stepped,
                                at_end: false,
                                over: best.over,
                                exact,
                            };
                        }
                        return best;
                    }
                    if stepped > lo && stepped < hi {
                        next = Some(stepped);
                    }
                }
            }
        }
        let t_next = next.unwrap_or(R::HALF * (lo + hi));
        best.next = t_next;
        if !(hi - lo > R::lit(8.0) * R::EPSILON * hi) {
            // Bracket collapsed onto the maximum.
            best.exact = true;
            break;
        }
        t = t_next;
    }
    best
}

/// An upper bound of G′ on [t*, tₛ] for a monotone shape: there 1 + q(t) ≤
/// 1 + q(t*) ≤ t*²/(t*² − tₛ) (from φ(t*) ≥ 0), so G ≤ n^(1 − tₛ/t)·t*²/(t*² − tₛ),
/// and G′/G = L·(tₛ/t² − q·u′) ≤ L·tₛ/t²; the product of the t-dependent
/// parts peaks at t = L·tₛ/2.
fn creep_bound<R: Real>(shape: &Shape<R>, t_star: R) -> R {
    let (ts, l) = (shape.ts(), shape.ln_n());
    let tb = (R::HALF * l * ts).max(t_star).min(ts);
    let it = tb.recip();
    let s2 = t_star * t_star;
    s2 / (s2 - ts) * (l * ts * it * it) * (l * (R::ONE - ts * it)).exp()
}

/// d ln P/dtₛ at a candidate's maximum (`da` = da/dtₛ of its a), by the
/// envelope theorem: the partial derivatives of ln G′ in tₛ and a at the
/// fixed maximizer (for an end maximum, of ln G′(tₛ⁻), G(tₛ) = 1).
/// With ln G = −L·(tₛ/t − 1) + ψ(u − a) − ψ(tₛ − a), ψ(w) = ln(1 + q(w)),
/// ψ′ = −L·q, q′ = −L·q·p and h1 = L·(tₛ·p/t² − q):
/// ∂ln G′/∂tₛ = L·(Q_s − p/t) + (L·p/t)·(1/t + L·q·u′)/h1,
/// ∂ln G′/∂a = L·(q − Q_s) − L²·q·p·u′/h1.
fn ln_peak_slope<R: Real>(shape: &Shape<R>, h: &Hump<R>, da: R) -> R {
    let (ts, l) = (shape.ts(), shape.ln_n());
    let qs = shape.end_q();
    if h.at_end {
        // G′(tₛ⁻) = L·((1 + Q_s)/tₛ − Q_s), dQ_s/dtₛ = −L·Q_s·(1 + Q_s)·(1 − a′).
        let ps = R::ONE + qs;
        let it = ts.recip();
        l * (l * qs * ps * (R::ONE - da) * (R::ONE - it) - ps * it * it) / h.rate
    } else {
        let it = h.t.recip();
        let p = R::ONE + h.q;
        let up = R::ONE - ts * it * it;
        let lp_t = l * p * it;
        let ih1 = h.h1.recip();
        let d_ts = l * qs - lp_t + lp_t * (it + l * h.q * up) * ih1;
        let d_a = l * (h.q - qs) - l * l * h.q * p * up * ih1;
        d_ts + da * d_a
    }
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

/// A ζ-a-tₛ profile of duration `ts` with its peak rate, as the duration
/// search keeps it (kept small: the AVR's stack is 2 KiB).
#[derive(Debug, Clone, Copy)]
struct ZatCandidate<R> {
    z: ZatShape<R>,
    /// P(tₛ) = max g′: an estimate to [`PEAK_ROUGH`] until [`verify`] makes
    /// it exact.
    peak: R,
    /// d ln P/dz, z = ln(tₛ − 1).
    slope: R,
    /// The first hump's maximum G′ (estimated until `hump_exact`), where it
    /// is and where its search goes on.
    hump: R,
    t_peak: R,
    next: R,
    /// [`creep_bound`] once computed (< 0: not yet).
    bound: R,
    /// Where the creep's search goes on.
    creep_next: R,
    /// An evaluated G′ exceeds the limit.
    over: bool,
    /// The first hump's maximum is exact.
    hump_exact: bool,
    /// The creep rose above the first hump.
    creep_won: bool,
    /// [`verify`] has run.
    exact: bool,
}

impl<R: Real> ZatCandidate<R> {
    /// A candidate of this shape, its peak not yet estimated.
    fn of(z: ZatShape<R>) -> Self {
        let ts = z.shape.ts();
        ZatCandidate {
            z,
            peak: R::ZERO,
            slope: R::ZERO,
            hump: R::ZERO,
            t_peak: ts,
            next: ts,
            bound: -R::ONE,
            creep_next: ts,
            over: false,
            hump_exact: false,
            creep_won: false,
            exact: false,
        }
    }

    fn ts(&self) -> R {
        self.z.shape.ts()
    }

    /// ratio·P ≤ 1 as far as known (for sure once `exact`).
    fn passes(&self, ratio: R) -> bool {
        !self.over && ratio * self.peak <= R::ONE
    }

    /// Known to fail: an evaluated G′ exceeds the limit, or the exact P does.
    fn fails_for_sure(&self, ratio: R) -> bool {
        self.over || (self.exact && !self.passes(ratio))
    }

    /// A passing candidate close enough to the shortest admissible tₛ (see
    /// [`zat_duration`]): a tₛ within the tolerance below it fails for sure
    /// (`ts_sure`), or its Newton step puts the root within 0.9 of it.
    #[inline(never)]
    fn near(&self, ratio: R, ts_sure: R) -> bool {
        let ts = self.ts();
        let tol = R::lit(TS_SEARCH_TOL);
        let f = (ratio * self.peak).ln();
        -f * (ts - R::ONE) <= R::lit(0.9) * tol * ts * -self.slope || ts <= ts_sure * (R::ONE + tol)
    }
}

/// What every candidate of one duration search shares.
struct Search<R> {
    ratio: R,
    /// 1/ratio: the largest admissible G′.
    limit: R,
    /// Peak guess ρ·√tₛ (smooth stops) ...
    rho: R,
    /// ... or √tₛ − off (monotone limits, whose peak sits a nearly constant
    /// distance before √tₛ), from the previous candidate.
    off: R,
    /// A candidate's creep rose above its first hump: estimate it from now
    /// on (before, only [`verify`] looks at it; with n = 2 it wins only
    /// beyond tₛ ≈ 85 s).
    creep: bool,
}

/// Estimates a candidate's peak to [`PEAK_ROUGH`], enough to steer (its
/// shape in place: the candidate is reused, a copy costs stack on the AVR).
#[inline(never)]
fn estimate<R: Real>(c: &mut ZatCandidate<R>, s: &Search<R>) {
    let ts = c.ts();
    let hi = c.z.first_end();
    let behind = ts.sqrt() - s.off;
    let guess = if c.z.t_star > R::ZERO && behind > R::ZERO && behind < hi {
        behind
    } else {
        peak_guess(ts, hi, s.rho)
    };
    // A smooth stop ends with G′ = 0, and G′ ≈ 0 at t*: only the floor shapes
    // can peak at the end of their first piece.
    let pc = Piece {
        lo: R::ZERO,
        hi,
        guess,
        limit: s.limit,
        tol: R::lit(PEAK_ROUGH),
        end: c.z.kind == AKind::Floor,
    };
    let h = piece_max(&c.z.shape, &pc);
    c.slope = (ts - R::ONE) * ln_peak_slope(&c.z.shape, &h, c.z.da);
    c.peak = h.rate;
    c.hump = h.rate;
    c.t_peak = h.t;
    c.next = h.next;
    c.bound = -R::ONE;
    c.creep_next = ts;
    c.over = h.over;
    c.hump_exact = h.exact;
    c.creep_won = false;
    c.exact = false;
    // A candidate the first hump fails already needs no more.
    if s.creep && c.passes(s.ratio) {
        creep(c, s, R::lit(PEAK_ROUGH));
    }
}

/// Adds the creep after t* to a candidate's P, to `tol`, wherever
/// [`creep_bound`] cannot rule it out (for n = 2 it can up to tₛ ≈ 37 s).
#[inline(never)]
fn creep<R: Real>(c: &mut ZatCandidate<R>, s: &Search<R>, tol: R) {
    let t_star = c.z.t_star;
    if !(t_star > R::ZERO) || c.over {
        return;
    }
    let shape = &c.z.shape;
    if c.bound < R::ZERO {
        c.bound = creep_bound(shape, t_star);
    }
    if c.bound > c.peak {
        let ts = shape.ts();
        let h = piece_max(shape, &Piece { lo: t_star, hi: ts, guess: c.creep_next, limit: s.limit, tol, end: true });
        c.creep_next = h.next;
        c.over |= h.over;
        if h.rate > c.peak {
            c.creep_won = true;
            c.peak = h.rate;
            c.slope = (ts - R::ONE) * ln_peak_slope(shape, &h, c.z.da);
        }
    }
}

/// Makes a candidate's P exact: both humps to [`PEAK_TOL`] (the creep only
/// where [`creep_bound`] cannot rule it out). Returns whether it passes.
#[inline(never)]
fn verify<R: Real>(c: &mut ZatCandidate<R>, s: &Search<R>) -> bool {
    if c.exact {
        return c.passes(s.ratio);
    }
    c.exact = true;
    if !c.hump_exact && !c.over {
        let pc = Piece {
            lo: R::ZERO,
            hi: c.z.first_end(),
            guess: c.next,
            limit: s.limit,
            tol: R::lit(PEAK_TOL),
            end: c.z.kind == AKind::Floor,
        };
        let h = piece_max(&c.z.shape, &pc);
        c.hump = h.rate;
        c.t_peak = h.t;
        c.next = h.next;
        c.over |= h.over;
    }
    // The first hump's exact value replaces the estimate; the creep is redone.
    c.peak = c.hump;
    creep(c, s, R::lit(PEAK_TOL));
    c.passes(s.ratio)
}

/// z = ln(tₛ − 1), the duration search's variable (ln P is nearly linear in
/// it while the smooth stop is used).
fn ts_z<R: Real>(ts: R) -> R {
    (ts - R::ONE).max(R::lit(1e-3)).ln()
}

/// Which candidate the duration search settled on.
enum Pick {
    Last,
    Best,
    Refuse,
}

/// The ζ-a-tₛ duration: the shortest tₛ in [zat_ts_min, ts_max] with
/// `ratio · P(tₛ) ≤ 1`, to [`TS_SEARCH_TOL`]. Err(SpeedLimit) if even ts_max
/// is too fast. Returns the shape and its (exact) P.
///
/// Newton on f(z) = ln(ratio·P) over z = ln(tₛ − 1), with f′ from
/// [`ln_peak_slope`], aimed [`TS_SEARCH_AIM`] past the predicted root so
/// that the candidate usually passes; a step outside the bracket (the
/// longest failing, the shortest passing tₛ), or one that crosses its middle
/// away from where it starts (P nearly flat), bisects it. Candidates steer
/// with estimated peaks ([`estimate`]); one that looks near the root is
/// [`verify`]ed, and returned if it passes and is still near: a tₛ within
/// the tolerance below it fails for sure, or the Newton step from its exact
/// P puts the root within 0.9 of the tolerance below it (P is smooth in tₛ,
/// so that step's error is second order). After [`TS_SEARCH_STEPS`]
/// candidates the shortest passing one is verified, else ts_max.
#[inline(never)]
fn zat_duration<R: Real>(ratio: R, lim: &PlanLimits<R>) -> Result<(ZatShape<R>, R), Refusal> {
    let l = lim.n.ln();
    let mut s = Search {
        ratio,
        limit: ratio.recip(),
        rho: R::lit(PEAK_GUESS),
        off: R::ZERO,
        creep: false,
    };
    let tol = R::lit(TS_SEARCH_TOL);
    let z_max = ts_z(lim.ts_max);
    let mut ts = lim.zat_ts_min;
    let mut zn = ts_z(ts);
    let mut c = ZatCandidate::of(zat_shape(ts, lim.n, l).map_err(|_| Refusal::Trajectory)?);
    // The bracket: the longest failing z, the shortest passing candidate
    // (its z in `z_best`), and the longest tₛ known to fail for sure (0:
    // none yet).
    let mut z_lo = zn;
    let mut best: Option<ZatCandidate<R>> = None;
    let mut z_best = z_max;
    let mut ts_sure = R::ZERO;
    let mut at_max = false;
    // Candidates after the first; past the cap, ts_max is the last resort.
    let mut k = 0;
    let pick = loop {
        if k > 0 {
            c.z = zat_shape(ts, lim.n, l).map_err(|_| Refusal::Trajectory)?;
        }
        estimate(&mut c, &s);
        if k > TS_SEARCH_STEPS {
            break if verify(&mut c, &s) { Pick::Last } else { Pick::Refuse };
        }
        let mut pass = c.passes(ratio);
        if k == 0 {
            if pass {
                pass = verify(&mut c, &s);
                if pass {
                    break Pick::Last;
                }
            }
            if !(lim.ts_max > lim.zat_ts_min) {
                break Pick::Refuse;
            }
        } else {
            if pass && c.near(ratio, ts_sure) {
                pass = verify(&mut c, &s);
                if pass && c.near(ratio, ts_sure) {
                    break Pick::Last;
                }
            } else if !pass && at_max {
                // Refuse only on the exact P.
                pass = verify(&mut c, &s);
            }
            let close_below_best = match &best {
                Some(b) => b.ts() <= ts * (R::ONE + tol),
                None => false,
            };
            if !pass && close_below_best && !c.fails_for_sure(ratio) {
                // An estimated failure this close below the shortest passing
                // candidate decides the search: make it sure.
                pass = verify(&mut c, &s);
                if pass && c.near(ratio, ts_sure) {
                    break Pick::Last;
                }
            }
        }
        if pass {
            best = Some(c);
            z_best = zn;
        } else {
            if at_max {
                break Pick::Refuse;
            }
            z_lo = zn;
            if c.fails_for_sure(ratio) {
                ts_sure = ts;
            }
            if let Some(b) = &mut best {
                if b.ts() <= ts_sure * (R::ONE + tol) {
                    if verify(b, &s) {
                        break Pick::Best;
                    }
                    // It only looked passing: the bracket starts there.
                    z_lo = z_best;
                    ts_sure = b.ts();
                    c = *b;
                    zn = z_best;
                    best = None;
                    z_best = z_max;
                }
            }
        }
        k += 1;
        if k > TS_SEARCH_STEPS {
            if let Some(b) = &mut best {
                if verify(b, &s) {
                    break Pick::Best;
                }
            }
            ts = lim.ts_max;
            continue;
        }
        // The next candidate: a Newton step from this one.
        let root = c.ts().sqrt();
        s.rho = c.t_peak / root;
        s.off = root - c.t_peak;
        if c.creep_won && !s.creep {
            s.creep = true;
            // The shortest passing candidate passed on its first hump alone.
            if let Some(b) = &mut best {
                creep(b, &s, R::lit(PEAK_ROUGH));
                if !b.passes(ratio) {
                    z_lo = z_lo.max(z_best);
                    best = None;
                    z_best = z_max;
                }
            }
        }
        let z = zn;
        let cts = c.ts();
        let f = (ratio * c.peak).ln();
        let aim = R::lit(TS_SEARCH_AIM) * cts / (cts - R::ONE);
        zn = if c.slope < R::ZERO { z - f / c.slope + aim } else { z_best };
        let mid = R::HALF * (z_lo + z_best);
        let wild = best.is_some() && if z <= z_lo { zn > mid } else { zn < mid };
        if !(zn > z_lo) || wild {
            zn = mid;
        }
        at_max = false;
        if !(zn < z_best) {
            if best.is_none() {
                at_max = true;
                zn = z_max;
            } else {
                zn = mid;
            }
        }
        ts = if at_max { lim.ts_max } else { zn.exp() + R::ONE };
    };
    let chosen = match pick {
        Pick::Last => Some(&c),
        Pick::Best => best.as_ref(),
        Pick::Refuse => None,
    };
    match chosen {
        Some(c) => Ok((c.z, c.peak)),
        None => Err(Refusal::SpeedLimit),
    }
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

