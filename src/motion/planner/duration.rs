//! How long a ζ-a-tₛ move takes: the shortest tₛ whose peak rate keeps
//! every joint within its speed (`zat_duration`; the reasoning is in
//! [`super`]'s module doc).

use super::peak_rate::{creep_bound, ln_peak_slope, peak_guess, piece_max, Piece, PEAK_GUESS, PEAK_ROUGH, PEAK_TOL};
use super::request::{PlanError, PlanLimits};
use super::shape_choice::{zat_shape, AKind, ZatShape};
use crate::math::real::Real;

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
    #[inline(never)] // avr-trap: frame-size
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
#[inline(never)] // avr-trap: frame-size
fn estimate<R: Real>(c: &mut ZatCandidate<R>, s: &Search<R>) {
    let ts = c.ts();
    let hi = c.z.first_end();
    let behind = ts.sqrt() - s.off;
    let guess =
        if c.z.t_star > R::ZERO && behind > R::ZERO && behind < hi { behind } else { peak_guess(ts, hi, s.rho) };
    // A smooth stop ends with G′ = 0, and G′ ≈ 0 at t*: only the floor shapes
    // can peak at the end of their first piece.
    let pc = Piece { lo: R::ZERO, hi, guess, limit: s.limit, tol: R::lit(PEAK_ROUGH), end: c.z.kind == AKind::Floor };
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
#[inline(never)] // avr-trap: frame-size
fn creep<R: Real>(c: &mut ZatCandidate<R>, s: &Search<R>, tol: R) {
    let t_star = c.z.t_star;
    if !t_star.is_positive() || c.over {
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
#[inline(never)] // avr-trap: frame-size
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
#[inline(never)] // avr-trap: frame-size
pub(super) fn zat_duration<R: Real>(ratio: R, lim: &PlanLimits<R>) -> Result<(ZatShape<R>, R), PlanError> {
    let l = lim.n.ln();
    let mut s = Search { ratio, limit: ratio.recip(), rho: R::lit(PEAK_GUESS), off: R::ZERO, creep: false };
    let tol = R::lit(TS_SEARCH_TOL);
    let z_max = ts_z(lim.ts_max);
    let mut ts = lim.zat_ts_min;
    let mut zn = ts_z(ts);
    let mut c = ZatCandidate::of(zat_shape(ts, lim.n, l).map_err(|_| PlanError::Trajectory)?);
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
            c.z = zat_shape(ts, lim.n, l).map_err(|_| PlanError::Trajectory)?;
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
            if !lim.ts_max.gt(&lim.zat_ts_min) {
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
        if !zn.gt(&z_lo) || wild {
            zn = mid;
        }
        at_max = false;
        if !zn.lt(&z_best) {
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
        None => Err(PlanError::SpeedLimit),
    }
}
