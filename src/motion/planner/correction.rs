//! The duration of a correction superposed on a running move
//! ([`crate::motion::superpose`]): the shortest T found for which the sum
//! keeps every joint within its speed, acceleration and angle limits.
//!
//! # Bounds
//! After the running term ends, the correction runs alone: its own closed
//! form bounds T from below ([`super::plan_move::scaled_duration`]), and its
//! positions go monotonically from the old target to the new one, both
//! within the limits. Before that the two overlap. The overlap is cut at
//! the running term's cells ([`super::cells`]); on each piece the running
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
//! From the correction's own shortest T, ×1.25 until a T passes (a
//! longer correction is slower while the running term is fast), then three
//! bisections on ln T: the result is at most 1.25^(1/8) ≈ 2.8 %
//! above the shortest passing T on the table's bounds. A T beyond ts_max is
//! refused (`SpeedLimit`).

use super::cells::{cell_table, CellTable, CELLS};
use super::peak_rate::law_ratios;
use super::plan_move::scaled_duration;
use super::request::{time_ratio, MoveRequest, PlanError, PlanLimits};
use crate::math::real::Real;
use crate::motion::plan::{LawKind, JOINTS};

/// Growth of the candidate T until one passes.
const GROW: f64 = 1.25;
/// Bisections on ln T after the first pass.
const REFINE: u8 = 3;

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

/// The shortest T found for `c` (see the module doc); `run`: the term that
/// still runs when the correction starts, if any.
pub fn correction_duration<R: Real>(
    c: &Correction<R>,
    run: Option<&Running<R>>,
    lim: &PlanLimits<R>,
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
    let check = |t: R| fits(t, &joints, run, tab_r, tab_c);
    let grow = R::lit(GROW);
    let mut t = t0;
    while !check(t) {
        if !t.lt(&lim.ts_max) {
            return Err(PlanError::SpeedLimit);
        }
        t = (t * grow).min(lim.ts_max);
    }
    if t > t0 {
        let (mut lo, mut hi) = ((t / grow).max(t0), t);
        let mut n = 0;
        while n < REFINE {
            n += 1;
            let mid = (lo * hi).sqrt();
            if check(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        t = hi;
    }
    Ok(t)
}

/// Whether a correction of duration `t` keeps the sum within the limits
/// while the running term runs (see the module doc).
#[inline(never)]
fn fits<R: Real>(t: R, joints: &[Joint<R>; JOINTS], run: &Running<R>, tab_r: &CellTable, tab_c: &CellTable) -> bool {
    let n = R::from_u16(CELLS as u16);
    let it = t.recip();
    // The correction's time per second of the running term's cells, in cells.
    let x_r = run.elapsed / run.duration;
    let rc = run.duration * it;
    let mut k = cell_index(x_r * n);
    while k < CELLS {
        // The piece: from max(k/16, x_r) to (k + 1)/16 of the running term,
        // s1..s2 of the correction (in cells, from its start).
        let k_lo = R::from_u16(k as u16) / n;
        let w0 = if k_lo > x_r { k_lo - x_r } else { R::ZERO };
        let w1 = R::from_u16(k as u16 + 1) / n - x_r;
        let j1 = cell_index(w0 * rc * n);
        let j2 = cell_index_up(w1 * rc * n);
        let (vc, ac) = tab_c.max_over::<R>(j1, j2);
        // Left on the correction at the piece's end, at least.
        let gc = R::ONE - tab_c.f_at::<R>(j2);
        let (vr, ar) = tab_r.max_over::<R>(k, k + 1);
        // Left on the running term at the piece's start, at most.
        let gr = R::ONE - tab_r.f_at::<R>(k);
        k += 1;
        for j in joints.iter() {
            let cv = j.cor_d * it;
            if j.ka * ar + cv * it * ac * j.inv_a > R::ONE {
                return false;
            }
            if j.same {
                if j.kv * vr + cv * vc * j.inv_w > R::ONE {
                    return false;
                }
            } else if j.run_d * gr - j.cor_d * gc > j.room {
                return false;
            }
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
