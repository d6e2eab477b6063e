//! The duration of a correction superposed on a running move
//! ([`crate::motion::superpose`]): the shortest T found for which the sum
//! keeps every joint within its speed, acceleration and angle limits.
//!
//! # Bounds
//! After the running term ends, the correction runs alone: its own closed
//! form bounds T from below ([`super::plan_move::scaled_duration`]), and its
//! positions go monotonically from the old target to the new one, both
//! within the limits. Before that the two overlap. The overlap is cut at
//! the running term's cells ([`super::cells`]), two per piece; on each piece the running
//! term's speed, |acceleration| and remaining travel are bounded by its cell
//! and the correction's by the cells its own time covers there, and per
//! joint:
//! - the |accelerations| add (a bound whatever their signs);
//! - where both move the joint the same way, the speeds add; where they
//!   oppose, the speed is at most the larger, which each keeps alone, but
//!   the position can swing past the new target toward the old one by the
//!   running term's remaining travel less the correction's: that swing must
//!   stay within the joint's angle range.
//!
//! Every bound holds over the whole piece, so a T that passes is verified
//! for the continuous motion, not only at the samples of a frame. The sum
//! may use the planning margin the single moves keep (`slack`): a
//! correction that starts before the running move's speed peak adds a
//! little to that peak on its fastest joint, however slowly it starts.
//!
//! # Search
//! From the correction's own shortest T, doubling until a T passes (a
//! longer correction is slower while the running term is fast), then
//! bisections on ln T, with at most [`MAX_CHECKS`] checks in all: a re-plan
//! runs after its frame's pulses on the chip (BENCHMARKS.md, `app_replan`).
//! The result passes, and is at most 2^(1/16) ≈ 4.4 % above the shortest
//! passing T on the table's bounds when the doubling took at most three
//! steps (a correction up to 8× its own shortest duration; more steps leave
//! fewer bisections: at six, one, 41 %). A T beyond ts_max is refused
//! (`SpeedLimit`).

use super::cells::{cell_table, CellTable, CELLS};
use super::peak_rate::law_ratios;
use super::plan_move::scaled_duration;
use super::request::{time_ratio, MoveRequest, PlanError, PlanLimits};
use crate::math::real::Real;
use crate::motion::plan::{LawKind, JOINTS};

/// Checks of a candidate T per re-plan, at most: the first, the doublings
/// (six cover the 60× span from the 0.5 s floor to 30 s) and the bisections
/// after the first pass. The bisections stop earlier when the caller's
/// time runs out ([`correction_duration_within`]); the doublings cannot,
/// so this bounds the part that can't be cut short to seven checks.
pub const MAX_CHECKS: u8 = 8;
/// Cells of the running term per piece: a piece's bounds are the maxima
/// over its cells (a little above each cell's own), and a check costs its
/// pieces (BENCHMARKS.md, `app_replan`).
const PIECE: usize = 2;
/// Bisections on ln T after the first pass, when the budget leaves room.
const REFINE: u8 = 4;

/// The term that runs beside a correction, as the correction starts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Running<R> {
    /// The running term's law.
    pub law: LawKind,
    /// Per joint: how far it moves in all.
    pub delta: [R; JOINTS],
    /// Its duration, s.
    pub duration: R,
    /// Its local time when the correction starts.
    pub elapsed: R,
}

/// A correction to plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Correction<R> {
    /// How far it moves each joint: the new target − the old target.
    pub delta: [R; JOINTS],
    /// The new target.
    pub target: [R; JOINTS],
    /// The correction's law.
    pub law: LawKind,
    /// Per joint, the angles (rad) the motion must stay within.
    pub range: [[R; 2]; JOINTS],
    /// Factor (≥ 1) on the speed and acceleration limits for the sum of the
    /// two terms (see the module doc).
    pub slack: R,
}

/// Per joint, what every candidate's check reuses.
#[derive(Clone, Copy)]
struct Joint<R> {
    /// Both terms move the joint the same way.
    same: bool,
    /// The running term's speed and acceleration per unit of its cell bound,
    /// over the (slack) limits.
    kv: R,
    ka: R,
    /// |Δ| of the running term and of the correction, and the room between
    /// the new target and the limit on the running term's side.
    run_d: R,
    cor_d: R,
    room: R,
    /// 1/(slack·ω) and 1/(slack·α).
    inv_w: R,
    inv_a: R,
}

/// What every check of one correction reads, by reference: as six
/// arguments LLVM passed one on the stack on the AVR, which it miscompiles
/// there (the post-link lint in `xtask/tests/firmware_elf.rs`).
struct Check<'a, R> {
    joints: [Joint<R>; JOINTS],
    coarse: Coarse<R>,
    run: &'a Running<R>,
    tab_r: &'a CellTable,
    tab_c: &'a CellTable,
}

/// The running term's largest shares over the joints, for a first check of
/// a piece that passes for every joint at once (most pieces, far from the
/// binding one); only a piece that fails it is checked joint by joint.
#[derive(Clone, Copy)]
struct Coarse<R> {
    /// Largest `ka` of any joint and `kv` of the joints both terms move the
    /// same way.
    ka: R,
    kv: R,
    /// Largest run_d/room of the joints they move oppositely (huge where the
    /// new target is at the limit: those are checked joint by joint).
    swing: R,
}

/// The shortest T found for `c` (see the module doc); `run`: the term that
/// still runs when the correction starts, if any.
pub fn correction_duration<R: Real>(
    c: &Correction<R>,
    run: Option<&Running<R>>,
    lim: &PlanLimits<R>,
) -> Result<R, PlanError> {
    correction_duration_within(c, run, lim, &mut || true)
}

/// [`correction_duration`], asking `room` before each bisection whether
/// the caller has time for one more check: once it has not, the search ends
/// on the shortest T that passed so far (a valid T, only less refined). The
/// first pass is searched whatever `room` says: without a passing T there
/// is no move to start. On the chip `room` is the PWM period's time left
/// (`app::machine`), so a re-plan ends before the period does.
pub fn correction_duration_within<R: Real, F: FnMut() -> bool>(
    c: &Correction<R>,
    run: Option<&Running<R>>,
    lim: &PlanLimits<R>,
    room: &mut F,
) -> Result<R, PlanError> {
    let ratios = law_ratios(c.law).ok_or(PlanError::Trajectory)?;
    let req = MoveRequest { start: [R::ZERO; JOINTS], target: c.delta, law: c.law };
    let t0 = scaled_duration(&ratios, &[time_ratio(&req, &lim.speed)?, time_ratio(&req, &lim.accel)?], lim)?;
    let Some(run) = run else { return Ok(t0) };
    let (Some(tab_r), Some(tab_c)) = (cell_table(run.law), cell_table(c.law)) else {
        return Err(PlanError::Trajectory);
    };
    if !run.elapsed.lt(&run.duration) {
        return Ok(t0);
    }
    let mut joints = [Joint {
        same: false,
        kv: R::ZERO,
        ka: R::ZERO,
        run_d: R::ZERO,
        cor_d: R::ZERO,
        room: R::ZERO,
        inv_w: R::ZERO,
        inv_a: R::ZERO,
    }; JOINTS];
    let it = run.duration.recip();
    let mut k = 0;
    while k < JOINTS {
        let (Some(j), Some(dr), Some(dc), Some(target), Some(range), Some(w), Some(a)) = (
            joints.get_mut(k),
            run.delta.get(k),
            c.delta.get(k),
            c.target.get(k),
            c.range.get(k),
            lim.speed.get(k),
            lim.accel.get(k),
        ) else {
            break;
        };
        k += 1;
        if !(dr.is_finite() && dc.is_finite() && target.is_finite()) {
            return Err(PlanError::NotFinite);
        }
        j.inv_w = (c.slack * *w).recip();
        j.inv_a = (c.slack * *a).recip();
        j.run_d = dr.abs();
        j.cor_d = dc.abs();
        j.same = (*dr > R::ZERO) == (*dc > R::ZERO);
        j.kv = j.run_d * it * j.inv_w;
        j.ka = j.run_d * it * it * j.inv_a;
        let [lo, hi] = *range;
        // The swing goes toward the running term's start: below the new
        // target when it rises.
        j.room = if *dr > R::ZERO { *target - lo } else { hi - *target };
    }
    let mut coarse = Coarse { ka: R::ZERO, kv: R::ZERO, swing: R::ZERO };
    for j in joints.iter() {
        coarse.ka = coarse.ka.max(j.ka);
        if j.same {
            coarse.kv = coarse.kv.max(j.kv);
        } else {
            let s = if j.room > R::ZERO { j.run_d / j.room } else { R::lit(1e30) };
            coarse.swing = coarse.swing.max(s);
        }
    }
    let ctx = Check { joints, coarse, run, tab_r, tab_c };
    let check = |t: R| fits(t, &ctx);
    if check(t0) {
        return Ok(t0);
    }
    let mut checks = 1u8;
    let mut hi = t0;
    let mut lo;
    loop {
        if !hi.lt(&lim.ts_max) {
            return Err(PlanError::SpeedLimit);
        }
        lo = hi;
        hi = (hi + hi).min(lim.ts_max);
        checks += 1;
        if check(hi) {
            break;
        }
    }
    let mut n = 0;
    while n < REFINE && checks < MAX_CHECKS && room() {
        n += 1;
        checks += 1;
        let mid = (lo * hi).sqrt();
        if check(mid) {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok(hi)
}

/// Whether a correction of duration `t` keeps the sum within the limits
/// while the running term runs (see the module doc). Float work per piece
/// and joint is a multiply-add per condition: what does not depend on the
/// piece is taken out of the loops.
#[inline(never)] // avr-trap: frame-size
fn fits<R: Real>(t: R, ctx: &Check<'_, R>) -> bool {
    let Check { joints, coarse, run, tab_r, tab_c } = ctx;
    let n = R::from_u16(CELLS as u16);
    let cell = n.recip();
    let it = t.recip();
    // Per joint, the correction's speed and acceleration per unit of its
    // cell bound, over the (slack) limits.
    let mut cw = [R::ZERO; JOINTS];
    let mut ca = [R::ZERO; JOINTS];
    let (mut cw_max, mut ca_max) = (R::ZERO, R::ZERO);
    for ((w, a), j) in cw.iter_mut().zip(ca.iter_mut()).zip(joints.iter()) {
        *w = j.cor_d * it * j.inv_w;
        *a = j.cor_d * it * it * j.inv_a;
        ca_max = ca_max.max(*a);
        if j.same {
            cw_max = cw_max.max(*w);
        }
    }
    let x_r = run.elapsed / run.duration;
    // Cells of the correction per cell of the running term.
    let rcn = run.duration * it * n;
    let mut k = cell_index(x_r * n);
    let piece = R::from_u16(PIECE as u16) * cell;
    while k < CELLS {
        // The piece: from max(k/16, x_r) to (k + PIECE)/16 of the running
        // term, j1..j2 of the correction (in cells, from its start).
        let k_lo = R::from_u16(k as u16) * cell;
        let w0 = if k_lo > x_r { k_lo - x_r } else { R::ZERO };
        let w1 = k_lo + piece - x_r;
        let j1 = cell_index(w0 * rcn);
        let j2 = cell_index_up(w1 * rcn);
        let (vc, ac) = tab_c.max_over::<R>(j1, j2);
        // Left on the correction at the piece's end, at least.
        let gc = R::ONE - tab_c.f_at::<R>(j2);
        let (vr, ar) = tab_r.max_over::<R>(k, k + PIECE);
        // Left on the running term at the piece's start, at most.
        let gr = R::ONE - tab_r.f_at::<R>(k);
        k += PIECE;
        let passes = coarse.ka * ar + ca_max * ac <= R::ONE
            && coarse.kv * vr + cw_max * vc <= R::ONE
            && coarse.swing * gr <= R::ONE;
        for (j, (w, a)) in joints.iter().zip(cw.iter().zip(ca.iter())).filter(|_| !passes) {
            if j.ka * ar + *a * ac > R::ONE {
                return false;
            }
            if j.same {
                if j.kv * vr + *w * vc > R::ONE {
                    return false;
                }
            } else if j.run_d * gr - j.cor_d * gc > j.room {
                return false;
            }
        }
        // The correction has ended: the running term goes on alone, within
        // its own limits, and its swing past the new target only shrinks.
        if j1 >= CELLS {
            break;
        }
    }
    true
}

/// ⌊x⌋ as a cell index (0 for x ≤ 0, past the last for large x).
#[inline]
fn cell_index<R: Real>(x: R) -> usize {
    if !x.gt(&R::ZERO) {
        0
    } else if x < R::from_u16(CELLS as u16) {
        x.to_f32() as usize
    } else {
        CELLS
    }
}

/// ⌈x⌉ as a cell boundary, at most [`CELLS`].
#[inline]
fn cell_index_up<R: Real>(x: R) -> usize {
    let i = cell_index(x);
    if i < CELLS && R::from_u16(i as u16) < x {
        i + 1
    } else {
        i
    }
}
