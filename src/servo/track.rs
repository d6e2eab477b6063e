//! The control loop's per-frame work: a motion (a move, or a move with a
//! correction superposed: [`Superposed`]) bound to the joints' servo
//! mappings, evaluated once per 50 Hz frame into pulses with integer
//! arithmetic (the hot path; its cost is in BENCHMARKS.md).

use crate::math::fixed::mul_hi;
use crate::motion::plan::{JointLaw, LawKind, MultiPlan, JOINTS};
use crate::motion::planner::cells::cell_table;
use crate::motion::planner::correction::{correction_duration_within, Correction, Running};
use crate::motion::planner::plan_move::scaling_law;
use crate::motion::planner::request::{PlanError, PlanLimits};
use crate::motion::superpose::{Superposed, Term, ACTIVE, TERMS};
use crate::servo::map::ServoMap;

/// Why a [`ServoTrack`] could not be built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrackError {
    /// A joint's target pulse or a term's pulse travel (µs, before clamping)
    /// exceeds ±60000 µs: angles far outside any servo's range.
    OutOfRange,
}

/// What one 50 Hz frame sends to the servos.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoFrame {
    /// Pulse widths in Timer5 ticks (0.5 µs), clamped to each joint's angle
    /// and pulse limits.
    pub pulses: [u16; JOINTS],
    /// Each term's profile g and rate g′ (1/s; 0 and 0 for an empty slot):
    /// joint j moves at Σ Δ_kj·g′_k ([`ServoTrack::velocities`]).
    pub g: [f32; TERMS],
    /// Each term's g′, 1/s.
    pub rate: [f32; TERMS],
    /// A single move would put some joint over its `max_speed_rad_s`
    /// (|Δ_j·g′| > limit); a superposed motion's speed is the planner's
    /// bound, not checked here.
    pub too_fast: bool,
}

/// A new target for a running motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Replan<'a> {
    /// The new target's joint angles, rad.
    pub target: &'a [f32; JOINTS],
    /// The correction's law.
    pub law: LawKind,
    /// The speed and acceleration limits of this move.
    pub lim: &'a PlanLimits<f32>,
    /// Factor (≥ 1) on the limits for the sum of two terms
    /// ([`crate::motion::planner::correction`]).
    pub slack: f32,
}

/// Largest |target pulse| and |pulse travel| a track accepts (µs): keeps the
/// Q.14 pulse arithmetic inside i32.
const TRACK_RANGE_US: f32 = 60_000.0;
/// Pulses carry 14 fractional bits (µs·2¹⁴).
const PULSE_FRAC: u32 = 14;
/// 1 in the Q30 weights.
const ONE_Q30: u32 = 1 << 30;

/// One joint's pulse travel under one term: |µs/rad · Δ|·2¹⁶ and its sign.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Span {
    mag: u32,
    neg: bool,
}

impl Span {
    const ZERO: Span = Span { mag: 0, neg: false };

    /// The term's pulse travel for a joint moving Δ under calibration `m`.
    fn of(m: &ServoMap, delta: f32) -> Result<Span, TrackError> {
        let span = m.cal().us_per_rad * delta;
        if !span.abs().le(&TRACK_RANGE_US) {
            return Err(TrackError::OutOfRange);
        }
        Ok(Span { mag: (span.abs() * 65_536.0) as u32, neg: span < 0.0 })
    }

    /// span·w (µs·2¹⁴) with its sign, for a weight w·2³⁰: span·2¹⁶ · w·2³⁰ /
    /// 2³² = span·w·2¹⁴, < 2³¹ by TRACK_RANGE_US.
    #[inline(always)]
    fn at(&self, wq: u32) -> i32 {
        let v = mul_hi(self.mag, wq) as i32;
        if self.neg {
            -v
        } else {
            v
        }
    }
}

/// A motion bound to the joints' servo mappings: the control loop's
/// per-frame work. A frame is one profile evaluation (g, g′) per running
/// term, then per joint and term a 32-bit integer multiply-add for the
/// pulse; the speed check of a single move is one integer comparison of
/// |g′| with the tightest joint's limit, so joint velocities (float
/// multiplications) are formed only when asked for.
///
/// The pulse of joint j is the one [`ServoMap::angle_to_pulse`] gives for
/// `target_j − Σ_k Δ_kj·(1 − g_k)`, computed as `base_j − Σ_k span_kj·(1 −
/// g_k)` with base = the pulse at the target and span = µs/rad · Δ (both
/// unclamped), then clamped to the window where neither the angle limits
/// nor the pulse limits act: the map is linear and monotone, so clamping the
/// angle and then the pulse is clamping the pulse to the intersection.
/// Rounding is [`super::map`]'s (half up); the intermediate differs from its
/// f32 value by < 1e-3 µs, so a pulse can differ by one tick only when the
/// exact value lies that close to the middle between two ticks. Before a
/// single move starts and once every term has ended, the pulses are
/// [`super::map`]'s own for the start and the target.
///
/// Time: the track counts frames since it was built; term k runs at that
/// count plus its lead (the frames it had run before, or minus the frames it
/// still waits), so a term keeps its clock, bit for bit, across a re-plan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoTrack {
    motion: Superposed<f32>,
    /// Per joint: the pulse at the target (µs·2¹⁴) and the clamp window.
    base: [i32; JOINTS],
    lo: [i32; JOINTS],
    hi: [i32; JOINTS],
    /// Per term, per joint.
    spans: [[Span; JOINTS]; TERMS],
    /// Per term, frames run before the track was built (< 0: still to wait).
    lead: [i16; TERMS],
    /// Frames since the track was built.
    n: u16,
    frame_s: f32,
    start_ticks: [u16; JOINTS],
    end_ticks: [u16; JOINTS],
    /// A single move's |g′| above this puts some joint over its speed limit.
    rate_limit: f32,
}

impl ServoTrack {
    /// A single move, for frames of `frame_s` seconds.
    pub fn new(plan: &MultiPlan<f32>, maps: &[ServoMap; JOINTS], frame_s: f32) -> Result<Self, TrackError> {
        let mut t = Self::idle(plan.start(), frame_s);
        t.start(plan, maps)?;
        Ok(t)
    }

    /// No motion: resting on `pose` (pulses come from the caller then).
    pub fn idle(pose: &[f32; JOINTS], frame_s: f32) -> Self {
        ServoTrack {
            motion: Superposed::resting(pose),
            base: [0; JOINTS],
            lo: [0; JOINTS],
            hi: [0; JOINTS],
            spans: [[Span::ZERO; JOINTS]; TERMS],
            lead: [0; TERMS],
            n: 0,
            frame_s,
            start_ticks: [0; JOINTS],
            end_ticks: [0; JOINTS],
            rate_limit: f32::INFINITY,
        }
    }

    /// Replaces whatever runs with a single move, in place (the app's
    /// track is its largest object: no copy of it on the stack). Unchanged
    /// on error. Not inlined, for the same reason.
    #[inline(never)] // avr-trap: frame-size
    pub fn start(&mut self, plan: &MultiPlan<f32>, maps: &[ServoMap; JOINTS]) -> Result<(), TrackError> {
        let q14 = (1u32 << PULSE_FRAC) as f32;
        let (mut base, mut lo, mut hi) = ([0i32; JOINTS], [0i32; JOINTS], [0i32; JOINTS]);
        let mut spans = [Span::ZERO; JOINTS];
        let (mut start, mut end) = ([0u16; JOINTS], [0u16; JOINTS]);
        let mut rate_limit = f32::INFINITY;
        let joints = maps.iter().zip(plan.start().iter().zip(plan.target().iter()).zip(plan.delta().iter()));
        let lines = base.iter_mut().zip(lo.iter_mut().zip(hi.iter_mut()));
        let out = lines.zip(spans.iter_mut().zip(start.iter_mut().zip(end.iter_mut())));
        for ((m, ((&s, &e), &d)), ((base, (lo, hi)), (span, (su, eu)))) in joints.zip(out) {
            let c = m.cal();
            let at_target = c.offset_us + c.us_per_rad * e;
            if !at_target.abs().le(&TRACK_RANGE_US) {
                return Err(TrackError::OutOfRange);
            }
            let (pa, pb) = (c.offset_us + c.us_per_rad * c.min_rad, c.offset_us + c.us_per_rad * c.max_rad);
            *lo = (pa.min(pb).max(c.min_us as f32) * q14) as i32;
            *hi = (pa.max(pb).min(c.max_us as f32) * q14) as i32;
            *base = (at_target * q14) as i32;
            *span = Span::of(m, d)?;
            // Finite angles always map: angle_to_pulse only refuses NaN/∞.
            let (Ok(ps), Ok(pe)) = (m.angle_to_pulse(s), m.angle_to_pulse(e)) else {
                return Err(TrackError::OutOfRange);
            };
            *su = ps.ticks;
            *eu = pe.ticks;
            if d != 0.0 {
                rate_limit = rate_limit.min(m.max_speed::<f32>() / d.abs());
            }
        }
        self.motion.start(plan);
        (self.base, self.lo, self.hi) = (base, lo, hi);
        self.spans = [spans, [Span::ZERO; JOINTS], [Span::ZERO; JOINTS]];
        self.lead = [0; TERMS];
        self.n = 0;
        (self.start_ticks, self.end_ticks) = (start, end);
        self.rate_limit = rate_limit;
        Ok(())
    }

    /// Stops: every term is dropped ([`ServoTrack::is_done`]).
    pub fn halt(&mut self) {
        self.motion.halt();
    }

    /// Adds a correction of `delta` toward `target` under `law` in `slot`
    /// ([`Superposed::add_correction`]), starting after `wait` frames (0: in
    /// this frame): the running terms keep their clocks and pulse travel,
    /// and the target's pulse moves by the correction's travel exactly, so
    /// the pulses of this frame do not change. Unchanged on error.
    fn superpose(&mut self, c: &Superposing, maps: &[ServoMap; JOINTS]) -> Result<(), TrackError> {
        // Everything that can fail first.
        let mut spans = [Span::ZERO; JOINTS];
        let mut end = [0u16; JOINTS];
        for (((s, e), m), (d, q)) in
            spans.iter_mut().zip(end.iter_mut()).zip(maps.iter()).zip(c.delta.iter().zip(c.target.iter()))
        {
            *s = Span::of(m, *d)?;
            let Ok(p) = m.angle_to_pulse(*q) else { return Err(TrackError::OutOfRange) };
            *e = p.ticks;
        }
        let Some(old) = self.spans.get(c.slot).copied() else { return Err(TrackError::OutOfRange) };
        self.motion.add_correction(&c.target, &c.law, c.slot).map_err(|_| TrackError::OutOfRange)?;
        // A waiting term being replaced adds its whole travel: take it out,
        // then put the new one in.
        for ((b, o), s) in self.base.iter_mut().zip(old.iter()).zip(spans.iter()) {
            if c.replaces {
                *b -= o.at(ONE_Q30);
            }
            *b += s.at(ONE_Q30);
        }
        // Every clock restarts at this frame.
        for l in self.lead.iter_mut() {
            *l = l.saturating_add(self.n as i16);
        }
        self.n = 0;
        if let (Some(s), Some(l)) = (self.spans.get_mut(c.slot), self.lead.get_mut(c.slot)) {
            *s = spans;
            *l = -(c.wait as i16);
        }
        self.end_ticks = end;
        self.rate_limit = f32::INFINITY;
        Ok(())
    }

    /// The move being tracked.
    #[inline]
    pub fn motion(&self) -> &Superposed<f32> {
        &self.motion
    }

    /// Each term's local time in this frame, s (0 for empty slots).
    pub fn times(&self) -> [f32; TERMS] {
        let mut out = [0.0f32; TERMS];
        for (o, l) in out.iter_mut().zip(self.lead.iter()).take(self.motion.len()) {
            *o = self.frames_s(i32::from(self.n) + i32::from(*l));
        }
        out
    }

    /// `k` frames in seconds. Not inlined: LLVM would run the float work
    /// of a skipped branch on the AVR anyway (a call it does not).
    #[inline(never)] // reason: speculation
    fn frames_s(&self, k: i32) -> f32 {
        k as f32 * self.frame_s
    }

    /// The frame at `t` seconds after the track was built (each term at its
    /// own clock).
    pub fn frame(&self, t: f32) -> ServoFrame {
        let mut ts = [t; TERMS];
        for (o, l) in ts.iter_mut().zip(self.lead.iter()).take(self.motion.len()) {
            if *l != 0 {
                *o = t + self.frames_s(i32::from(*l));
            }
        }
        self.frame_at(&ts)
    }

    /// The frame with term k at local time `t[k]`.
    pub fn frame_at(&self, t: &[f32; TERMS]) -> ServoFrame {
        if let [Some(term), None, _] = self.motion.terms() {
            return self.single(term, t[0]);
        }
        let mut acc = self.base;
        let mut out = ServoFrame { pulses: self.end_ticks, g: [1.0; TERMS], rate: [0.0; TERMS], too_fast: false };
        let (mut moving, mut started) = (false, false);
        let slots = self.motion.terms().iter().zip(t.iter()).zip(self.spans.iter());
        for (((term, tk), spans), (g_out, r_out)) in slots.zip(out.g.iter_mut().zip(out.rate.iter_mut())) {
            let Some(term) = term else { continue };
            let (g, rate) = term.law.g_rate(*tk);
            *g_out = g;
            *r_out = rate;
            // Floats order like their bit patterns read as i32 when one side
            // is positive (no soft-float compare call): a NaN time counts as
            // the end.
            let tb = tk.to_bits() as i32;
            if tb >= term.duration().to_bits() as i32 {
                continue;
            }
            moving = true;
            started |= tb > 0;
            let wq = ONE_Q30 - unit_q30(g);
            for (a, s) in acc.iter_mut().zip(spans.iter()) {
                *a -= s.at(wq);
            }
        }
        if !moving {
            return out;
        }
        if !started && self.motion.len() == 1 {
            out.pulses = self.start_ticks;
            return out;
        }
        if self.motion.len() == 1 {
            // Some joint over its speed limit (a NaN rate counts as too fast).
            out.too_fast = out.rate[0].abs().to_bits() > self.rate_limit.to_bits();
        }
        for ((p, a), (lo, hi)) in out.pulses.iter_mut().zip(acc.iter()).zip(self.lo.iter().zip(self.hi.iter())) {
            *p = ticks(*a, *lo, *hi);
        }
        out
    }

    /// [`ServoTrack::frame_at`] of a single move (the common case, kept as
    /// short as the frame's cycle budget wants).
    #[inline(always)]
    fn single(&self, term: &Term<f32>, t: f32) -> ServoFrame {
        let (g, rate) = term.law.g_rate(t);
        let mut out = ServoFrame { pulses: self.end_ticks, g: [g, 1.0, 1.0], rate: [rate, 0.0, 0.0], too_fast: false };
        let tb = t.to_bits() as i32;
        if tb >= term.duration().to_bits() as i32 {
            return out;
        }
        if tb <= 0 {
            out.pulses = self.start_ticks;
            return out;
        }
        // Some joint over its speed limit (a NaN rate counts as too fast).
        out.too_fast = rate.abs().to_bits() > self.rate_limit.to_bits();
        out.pulses = self.first_term_ticks(ONE_Q30 - unit_q30(g));
        out
    }

    /// The pulses when the first term alone has `wq` (1 − g, Q30) of its
    /// travel left.
    #[inline(always)]
    fn first_term_ticks(&self, wq: u32) -> [u16; JOINTS] {
        let [s0, s1, s2] = &self.spans[0];
        let [b0, b1, b2] = self.base;
        let [l0, l1, l2] = self.lo;
        let [h0, h1, h2] = self.hi;
        [ticks(b0 - s0.at(wq), l0, h0), ticks(b1 - s1.at(wq), l1, h1), ticks(b2 - s2.at(wq), l2, h2)]
    }

    /// This frame's output (each term at its clock).
    pub fn frame_now(&self) -> ServoFrame {
        self.frame_at(&self.times())
    }

    /// After a frame: every term that had ended in it is dropped (it adds
    /// exactly nothing from then on) and the clock advances. The motion is
    /// over, the frame having put every joint exactly on the target, when
    /// [`ServoTrack::is_done`].
    pub fn advance(&mut self) {
        let gone = self.motion.retire(&self.times());
        self.n = self.n.saturating_add(1);
        if gone != 0 {
            // Spans and leads follow their terms down.
            let mut k = 0;
            for (i, (span, lead)) in self.spans.into_iter().zip(self.lead).enumerate() {
                if gone & (1 << i) == 0 {
                    if let (Some(s), Some(l)) = (self.spans.get_mut(k), self.lead.get_mut(k)) {
                        *s = span;
                        *l = lead;
                    }
                    k += 1;
                }
            }
            // A correction left alone before its start (it waited for an
            // older term that has ended) starts from the pose the terms
            // reached, not from the first move's start: the single-term
            // path reads its start pulses from here.
            if self.motion.len() == 1 {
                self.start_ticks = self.first_term_ticks(ONE_Q30);
            }
        }
    }

    /// The newest term's share of its duration elapsed, 0..=1 (0 while it
    /// waits).
    pub fn progress(&self) -> f32 {
        let n = self.motion.len();
        let (Some(Some(term)), Some(t)) =
            (self.motion.terms().get(n.wrapping_sub(1)), self.times().get(n.wrapping_sub(1)).copied())
        else {
            return 1.0;
        };
        (t / term.duration()).clamp(0.0, 1.0)
    }

    /// No term left: the motion rests on its target.
    pub fn is_done(&self) -> bool {
        self.motion.is_empty()
    }

    /// Joint positions (rad) of a frame: target − Σ Δ_k·(1 − g_k).
    pub fn positions(&self, f: &ServoFrame) -> [f32; JOINTS] {
        let mut out = *self.motion.target();
        for (term, g) in self.motion.terms().iter().zip(f.g.iter()) {
            if let Some(term) = term {
                let w = 1.0 - *g;
                for (o, d) in out.iter_mut().zip(term.delta.iter()) {
                    *o -= *d * w;
                }
            }
        }
        out
    }

    /// Joint velocities (rad/s) of a frame: Σ Δ_k·g′_k.
    pub fn velocities(&self, f: &ServoFrame) -> [f32; JOINTS] {
        let mut out = [0.0f32; JOINTS];
        for (term, r) in self.motion.terms().iter().zip(f.rate.iter()) {
            if let Some(term) = term {
                for (o, d) in out.iter_mut().zip(term.delta.iter()) {
                    *o += *d * *r;
                }
            }
        }
        out
    }

    /// Frames since the track was built (the clock of [`ServoTrack::frame`]).
    pub fn frames(&self) -> u16 {
        self.n
    }

    /// When the last term ends, s on [`ServoTrack::frame`]'s clock.
    pub fn end_s(&self) -> f32 {
        let mut end = 0.0f32;
        for (term, lead) in self.motion.terms().iter().zip(self.lead.iter()) {
            if let Some(term) = term {
                end = end.max(term.duration() - self.frames_s(i32::from(*lead)));
            }
        }
        end
    }

    /// Frames term `slot` has run in this frame (< 0: still to wait).
    pub fn clock(&self, slot: usize) -> Option<i32> {
        self.lead.get(slot).map(|l| i32::from(self.n) + i32::from(*l))
    }

    /// Superposes a correction toward `r.target` from this frame on, or,
    /// beside two running terms, from the frame after the older ends (a
    /// waiting correction is replaced: it has moved nothing): see
    /// [`Superposed`]. The duration is [`correction_duration_within`]'s, within the
    /// joints' angle windows; returns it and the frames the correction
    /// waits. `None`, and nothing changed, when the new law or a running one
    /// is not superposed (linear, the papers' ζ-a-tₛ: the caller re-plans
    /// from rest); unchanged on error too. `room` bounds the duration search
    /// ([`correction_duration_within`]): `&mut || true` for the full search.
    // Out of line: the correction's search stays out of plan_target's
    // frame, which is on the fresh plan's (the deepest) chain.
    #[inline(never)] // avr-trap: frame-size
    pub fn replan<F: FnMut() -> bool>(
        &mut self,
        r: &Replan,
        maps: &[ServoMap; JOINTS],
        room: &mut F,
    ) -> Result<Option<(f32, u16)>, PlanError> {
        let motion = &self.motion;
        let terms = motion.terms();
        if cell_table(r.law).is_none() || terms.iter().flatten().any(|t| cell_table(t.law.kind()).is_none()) {
            return Ok(None);
        }
        let n = motion.len();
        let clock = |k: usize| self.clock(k).unwrap_or(0);
        let last = n.saturating_sub(1);
        let (slot, wait) = if n > 0 && clock(last) < 0 {
            (last, -clock(last))
        } else if n < ACTIVE {
            (n, 0)
        } else {
            // The first frame at which the older term has ended.
            let older = terms.first().copied().flatten().map_or(0.0, |t| t.duration());
            (ACTIVE, ((older / self.frame_s) as i32 + 1 - clock(0)).max(0))
        };
        let wait = wait.clamp(0, i32::from(i16::MAX)) as u16;
        let delta = motion.correction_delta(r.target, slot).map_err(|_| PlanError::NotFinite)?;
        // The term still running when the correction starts.
        let mut run = None;
        for (k, term) in terms.iter().enumerate() {
            let Some(term) = term else { continue };
            let elapsed = (clock(k) + i32::from(wait)) as f32 * self.frame_s;
            if k != slot && elapsed >= 0.0 && elapsed < term.duration() {
                run = Some(Running { law: term.law.kind(), delta: term.delta, duration: term.duration(), elapsed });
            }
        }
        let mut range = [[0.0f32; 2]; JOINTS];
        for (w, map) in range.iter_mut().zip(maps.iter()) {
            *w = map.angle_window();
        }
        let c = Correction { delta, target: *r.target, law: r.law, range, slack: r.slack };
        let ts = correction_duration_within(&c, run.as_ref(), r.lim, room)?;
        let law = scaling_law(r.law, ts).map_err(|_| PlanError::Trajectory)?;
        let replaces = terms.get(slot).is_some_and(Option::is_some);
        let s = Superposing { law, delta, target: *r.target, slot, wait, replaces };
        self.superpose(&s, maps).map_err(|_| PlanError::Trajectory)?;
        Ok(Some((ts, wait)))
    }
}

/// A correction [`ServoTrack::superpose`] adds.
struct Superposing {
    law: JointLaw<f32>,
    delta: [f32; JOINTS],
    target: [f32; JOINTS],
    slot: usize,
    wait: u16,
    /// The slot holds a waiting correction, which this replaces.
    replaces: bool,
}

/// A pulse (µs·2¹⁴) clamped to [lo, hi] and rounded half up to ticks (µs·2),
/// as servo::map rounds.
#[inline(always)]
fn ticks(v: i32, lo: i32, hi: i32) -> u16 {
    ((v.max(lo).min(hi) + (1 << (PULSE_FRAC - 2))) >> (PULSE_FRAC - 1)) as u16
}

/// g ∈ [0, 1] as g·2³⁰, from the float's bits (no float operation): values
/// below 2⁻³⁰ give 0; anything above 1 (or NaN) is clamped to 1 and anything
/// negative to 0 (a monotone profile never leaves [0, 1]).
#[inline]
fn unit_q30(g: f32) -> u32 {
    let b = g.to_bits();
    if b >> 31 != 0 {
        return 0;
    }
    if b >= 0x3F80_0000 {
        return ONE_Q30;
    }
    let be = b >> 23;
    let m = (b & 0x007F_FFFF) | 0x0080_0000;
    // g = m·2^(be − 150), so g·2³⁰ = m·2^(be − 120).
    if be >= 120 {
        m << (be - 120)
    } else if be + 24 > 120 {
        m >> (120 - be)
    } else {
        0
    }
}
