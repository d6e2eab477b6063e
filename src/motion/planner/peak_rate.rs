//! The largest rate `max g′` of a motion profile: what a move's joint speeds
//! peak at (joint j at `|Δ_j|·max g′`), and its largest `|g″|`. Closed form
//! for the laws whose profile only scales with its duration (the classic
//! laws and the time-scaled ζ-a-tₛ: [`Ratios`]); for the papers' ζ-a-tₛ a
//! safeguarded Newton search on G″ = 0 ([`zat_peak_rate`]), plus what a
//! duration search needs to steer with it (rough estimates, a bound for the
//! slow creep before the end, and d ln P/dtₛ), and a search for the largest
//! |G″| ([`zat_peak_acc`]).

use crate::math::real::Real;
use crate::motion::laws::Law;
use crate::motion::plan::{JointLaw, LawKind};
use crate::motion::scaled::{ScaledZat, ACC_RATIO, JERK_RATIO, VEL_RATIO};
use crate::motion::zat::{t_star, Shape};

/// The peak search stops once the last Newton step predicts G′ to rise by
/// less than this (relative), and reports the quadratic model's maximum plus
/// that rise once more: never below the true peak in the tests (the model's
/// own error, cubic in the step, stayed below 2.1e-6), at most 1e-4 above.
pub const PEAK_TOL: f64 = 1e-4;
/// The estimate a candidate steers the duration search with: the model's
/// maximum once the predicted rise is below this (usually after one
/// evaluation; its error is second order in the remaining step).
pub(crate) const PEAK_ROUGH: f64 = 3e-2;
/// Cap on the peak search's iterations (Newton needs 1–3; a step it cannot
/// take bisects the bracket).
const PEAK_STEPS: u8 = 32;
/// First guess of where G′ peaks, in units of √tₛ (0.77 for n = 2 at
/// tₛ = 1.2, 0.69–0.94 over tₛ ∈ [1.2, 30]); later candidates of a search
/// start from the previous candidate's peak.
pub(crate) const PEAK_GUESS: f64 = 0.8;

/// `max g′` of a classic law per unit of 1/T.
pub fn classic_peak_factor(law: Law) -> f64 {
    match law {
        Law::Linear => 1.0,
        Law::Cubic => 1.5,
        Law::Quintic => 1.875,
        Law::Trapezoid => 1.5,
    }
}

/// The peaks of a profile that only scales with its duration T,
/// g(t) = f(t/T): velocity `|Δ|·vel/T`, acceleration `|Δ|·acc/T²`, jerk
/// `|Δ|·jerk/T³`; `None` where the law steps (linear: the velocity at both
/// ends, so no acceleration limit can hold; trapezoid: the acceleration).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ratios<R> {
    /// Peak velocity ratio.
    pub vel: R,
    /// Peak acceleration ratio, if the acceleration is bounded.
    pub acc: Option<R>,
    /// Peak jerk ratio, if the jerk is bounded.
    pub jerk: Option<R>,
}

/// [`Ratios`] of a law (docs/method.md §9–10); `None` for the papers'
/// ζ-a-tₛ, whose shape changes with tₛ. In `R`, each constant converted in
/// its own arm: on the AVR the f64 → f32 conversion folds away (a table of
/// f64 chosen at run time links compiler-builtins' `__truncdfsf2`).
#[inline]
pub fn law_ratios<R: Real>(kind: LawKind) -> Option<Ratios<R>> {
    let r = |vel: f64, acc: Option<f64>, jerk: Option<f64>| Ratios {
        vel: R::lit(vel),
        acc: acc.map(R::lit),
        jerk: jerk.map(R::lit),
    };
    Some(match kind {
        LawKind::Zat => r(VEL_RATIO, Some(ACC_RATIO), Some(JERK_RATIO)),
        LawKind::ZatPaper => return None,
        // f″ = 60(τ − 3τ² + 2τ³) peaks at τ = (3 ∓ √3)/6 with 10/√3; f‴ at
        // the ends with 60.
        LawKind::Quintic => r(1.875, Some(5.773_502_691_896_258), Some(60.0)),
        LawKind::Cubic => r(1.5, Some(6.0), Some(12.0)),
        LawKind::Trapezoid => r(1.5, Some(4.5), None),
        LawKind::Linear => r(1.0, None, None),
    })
}

/// `max g′` over (0, tₛ] of a ζ-a-tₛ profile.
///
/// G′ is not unimodal in general: where the monotonicity margin φ is
/// smallest, at t* = (1 + √(1 + L²tₛ))/L, G′ dips (to about 0 for the
/// monotone-limit shapes the app chooses for long tₛ), so a long move is a
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
/// plans below [`super::request::ZAT_TS_FLOOR`].
pub fn zat_peak_rate<R: Real>(shape: &Shape<R>) -> R {
    let ts = shape.ts();
    let l = shape.ln_n();
    let t_star = t_star(ts, l);
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
pub(crate) fn peak_guess<R: Real>(ts: R, hi: R, rho: R) -> R {
    let g = rho * ts.sqrt();
    if g > R::ZERO && g < hi {
        g
    } else {
        R::lit(0.9) * hi
    }
}

/// One piece (lo, hi] of (0, tₛ] on which G′ is taken to be unimodal.
pub(crate) struct Piece<R> {
    pub(crate) lo: R,
    pub(crate) hi: R,
    /// Where to start inside the piece (≥ hi: from the end's Newton step).
    pub(crate) guess: R,
    /// A G′ above this fails the candidate anyway, so a rough maximum does.
    pub(crate) limit: R,
    /// Predicted relative rise at which to stop.
    pub(crate) tol: R,
    /// The maximum may be at hi = tₛ: look at G″(tₛ⁻) first.
    pub(crate) end: bool,
}

/// The largest G′ of a piece, and where.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Hump<R> {
    pub(crate) rate: R,
    /// Where it is, with q and h1 = G′/G there (for d ln P/dtₛ).
    pub(crate) t: R,
    pub(crate) q: R,
    pub(crate) h1: R,
    /// Where the search would go on (the last Newton step's target).
    pub(crate) next: R,
    /// The maximum is the end value G′(tₛ⁻).
    pub(crate) at_end: bool,
    /// An evaluated G′ exceeds the piece's limit.
    pub(crate) over: bool,
    /// `rate` is the maximum to [`PEAK_TOL`] (not only the piece's `tol`).
    pub(crate) exact: bool,
}

/// Safeguarded Newton for the maximum of G′ on a piece (see [`zat_peak_rate`]).
// Not inlined: several call sites, and one inlined search makes a function
// too long for the AVR's relative jumps (the linker refuses it).
#[inline(never)] // reason: branch-range
pub(crate) fn piece_max<R: Real>(shape: &Shape<R>, pc: &Piece<R>) -> Hump<R> {
    let (mut lo, mut hi) = (pc.lo, pc.hi);
    let mut t = pc.guess;
    let mut best =
        Hump { rate: R::ZERO, t, q: R::ZERO, h1: R::ZERO, next: t, at_end: false, over: false, exact: false };
    if pc.end {
        if let Some(r) = shape.rate_terms(hi) {
            let rate = r.g * r.h1;
            let c2 = r.h1 * r.h1 + r.h2;
            best = Hump { rate, t: hi, q: r.q, h1: r.h1, next: hi, at_end: true, over: rate > pc.limit, exact: true };
            if !c2.is_negative() {
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
        if !(hi - lo).gt(&(R::lit(8.0) * R::EPSILON * hi)) {
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
pub(crate) fn creep_bound<R: Real>(shape: &Shape<R>, t_star: R) -> R {
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
pub(crate) fn ln_peak_slope<R: Real>(shape: &Shape<R>, h: &Hump<R>, da: R) -> R {
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

/// `max g′` of any profile (closed form for the classic laws and the
/// time-scaled ζ-a-tₛ).
pub fn peak_rate<R: Real>(law: &JointLaw<R>) -> R {
    match law {
        JointLaw::Zat(s) => zat_peak_rate(s),
        JointLaw::Scaled(s) => scaled_peak(s, VEL_RATIO),
        JointLaw::Classic(p) => R::lit(classic_peak_factor(p.law())) / p.duration(),
    }
}

fn scaled_peak<R: Real>(s: &ScaledZat<R>, ratio: f64) -> R {
    R::lit(ratio) / s.ts()
}

/// Grid points per piece on which [`zat_peak_acc`] looks for the humps of G″.
const ACC_GRID: u8 = 16;
/// Illinois steps per hump (superlinear: 6–8 suffice).
const ACC_STEPS: u8 = 16;

/// `max |g″|` over (0, tₛ] of the papers' ζ-a-tₛ. G″ = G·(h1² + h2) and
/// G‴ = G·(h1³ + 3h1·h2 + h3) come from [`Shape::rate_terms`]. As in
/// [`zat_peak_rate`], (0, t*] and [t*, tₛ] are searched apart when t* < tₛ:
/// the first holds G′'s hump and its steep fall into the near-stop at t*
/// (two humps of G″ that can lie a tenth of t* apart), the second the slow
/// creep. Every sign change of G‴ on a uniform grid of 16 points
/// per piece brackets a hump of G″, whose top is found by the Illinois method
/// on G‴ = 0; the end value G″(tₛ⁻) counts too. A hump is flat at its top, so
/// the value found is the peak to 1e-5 (the tests compare with dense scans
/// for tₛ ∈ [1.05, 40], n ∈ [1.3, 8]).
#[inline(never)] // avr-trap: frame-size
pub fn zat_peak_acc<R: Real>(shape: &Shape<R>) -> R {
    let ts = shape.ts();
    let t_star = t_star(ts, shape.ln_n());
    let split = t_star < ts && t_star > R::ZERO;
    let first = acc_piece(shape, R::ZERO, if split { t_star } else { ts });
    if split {
        first.max(acc_piece(shape, t_star, ts))
    } else {
        first
    }
}

/// The largest |G″| on (lo, hi] (see [`zat_peak_acc`]). A hump before the
/// first grid point where G is representable has no sign change of G‴ on
/// the grid to bracket it: when |G″| already falls there, the cell before
/// it is scanned on a grid of its own (once).
fn acc_piece<R: Real>(shape: &Shape<R>, lo: R, hi: R) -> R {
    acc_scan(shape, lo, hi, true)
}

// Recurses once at most (the inner call passes `refine_first = false`):
// hal-sim's stack bound counts on it (`stack_bound::FIRMWARE_RECURSION`).
fn acc_scan<R: Real>(shape: &Shape<R>, lo: R, hi: R, refine_first: bool) -> R {
    // (G″, G‴) at t, None where G is below 1e-34 (far left of everything).
    let at = |t: R| {
        shape.rate_terms(t).map(|r| {
            let h1 = r.h1;
            (r.g * (h1 * h1 + r.h2), r.g * (h1 * (h1 * h1 + R::lit(3.0) * r.h2) + r.h3))
        })
    };
    let mut best = R::ZERO;
    let mut prev: Option<(R, R)> = None;
    let mut before = lo;
    let step = (hi - lo) / R::from_u16(u16::from(ACC_GRID));
    let mut k = 1u8;
    while k <= ACC_GRID {
        let t = if k == ACC_GRID { hi } else { lo + step * R::from_u16(u16::from(k)) };
        k += 1;
        let Some((g2, g3)) = at(t) else {
            prev = None;
            before = t;
            continue;
        };
        best = best.max(g2.abs());
        match prev {
            Some((tp, g3p)) if (g3p > R::ZERO) != (g3 > R::ZERO) && g3p != R::ZERO => {
                best = best.max(hump_top(&at, (tp, g3p), (t, g3)));
            }
            // |G″| falls at the first point: its hump is in the cell before.
            None if refine_first && (g2 > R::ZERO) != (g3 > R::ZERO) => {
                best = best.max(acc_scan(shape, before, t, false));
            }
            _ => {}
        }
        prev = Some((t, g3));
    }
    best
}

/// |G″| at the zero of G‴ between `a` and `b` (opposite signs of G‴), by
/// the Illinois method (regula falsi that halves a stale end's value); the
/// largest |G″| it evaluated.
fn hump_top<R: Real>(at: &impl Fn(R) -> Option<(R, R)>, a: (R, R), b: (R, R)) -> R {
    let ((mut ta, mut fa), (mut tb, mut fb)) = (a, b);
    let mut best = R::ZERO;
    let mut k = 0;
    while k < ACC_STEPS {
        k += 1;
        let t = tb - fb * (tb - ta) / (fb - fa);
        if !(t > ta.min(tb) && t < ta.max(tb)) {
            break;
        }
        let Some((g2, g3)) = at(t) else { break };
        best = best.max(g2.abs());
        if (g3 > R::ZERO) != (fb > R::ZERO) {
            ta = tb;
            fa = fb;
        } else {
            fa *= R::HALF;
        }
        tb = t;
        fb = g3;
        if !(tb - ta).abs().gt(&(R::lit(1e-6) * tb)) {
            break;
        }
    }
    best
}
