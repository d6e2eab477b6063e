//! A synchronized multi-joint move: every joint follows q0 + Δ·g(t) with one
//! shared normalized profile g (0 → 1 over the same duration), so all joints
//! arrive together and a frame costs one profile evaluation plus a
//! multiply-add per joint.

use crate::f32_exp::mul_hi;
use crate::laws::{Law, LawParams, LawPlan};
use crate::motion::{all_finite, Sample, TrajError};
use crate::real::Real;
use crate::servo::ServoMap;
use crate::zat::{Shape, ShapeParams};

/// Base, shoulder, elbow.
pub const JOINTS: usize = 3;

/// The user-selectable motion law (the `law` command, stored in the
/// configuration record by [`LawKind::id`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LawKind {
    /// The ζ-a-tₛ trajectory (SPEC §5).
    Zat,
    Quintic,
    Cubic,
    Trapezoid,
    Linear,
}

impl LawKind {
    pub const ALL: [LawKind; 5] = [
        LawKind::Zat,
        LawKind::Quintic,
        LawKind::Cubic,
        LawKind::Trapezoid,
        LawKind::Linear,
    ];

    /// Stable id of the EEPROM record (never renumber).
    pub fn id(self) -> u8 {
        match self {
            LawKind::Zat => 0,
            LawKind::Quintic => 1,
            LawKind::Cubic => 2,
            LawKind::Trapezoid => 3,
            LawKind::Linear => 4,
        }
    }

    pub fn from_id(id: u8) -> Option<LawKind> {
        LawKind::ALL.iter().copied().find(|l| l.id() == id)
    }

    /// The name used by the `law` command.
    pub fn name(self) -> crate::text::Text {
        match self {
            LawKind::Zat => t!("zat"),
            LawKind::Quintic => t!("quintic"),
            LawKind::Cubic => t!("cubic"),
            LawKind::Trapezoid => t!("trapezoid"),
            LawKind::Linear => t!("linear"),
        }
    }

    pub fn from_name(name: &[u8]) -> Option<LawKind> {
        LawKind::ALL.iter().copied().find(|l| l.name().eq_bytes(name))
    }
}

/// A normalized profile g: g(t) = 0 for t ≤ 0, 1 for t ≥ duration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointLaw<R> {
    Zat(Shape<R>),
    /// A classic law planned 0 → 1 over [0, duration].
    Classic(LawPlan<R>),
}

impl<R: Real> JointLaw<R> {
    /// A ζ-a-tₛ profile (admissibility checked; monotonicity is checked by
    /// [`MultiPlan`]).
    pub fn zat(p: &ShapeParams<R>) -> Result<Self, TrajError<R>> {
        Ok(JointLaw::Zat(Shape::new(p)?))
    }

    /// A classic law over [0, duration].
    pub fn classic(law: Law, duration: R) -> Result<Self, TrajError<R>> {
        if !duration.is_finite() {
            return Err(TrajError::NotFinite);
        }
        if !(duration > R::ZERO) {
            return Err(TrajError::NonPositiveDuration);
        }
        Ok(JointLaw::Classic(LawPlan::new(
            law,
            &LawParams {
                t0: R::ZERO,
                tf: duration,
                s0: R::ZERO,
                sf: R::ONE,
            },
        )?))
    }

    /// Builds the law the user picked; `shape` supplies tₛ for every law and
    /// (a, n) for ζ-a-tₛ.
    pub fn from_kind(kind: LawKind, shape: &ShapeParams<R>) -> Result<Self, TrajError<R>> {
        match kind {
            LawKind::Zat => Self::zat(shape),
            LawKind::Quintic => Self::classic(Law::Quintic, shape.ts),
            LawKind::Cubic => Self::classic(Law::Cubic, shape.ts),
            LawKind::Trapezoid => Self::classic(Law::Trapezoid, shape.ts),
            LawKind::Linear => Self::classic(Law::Linear, shape.ts),
        }
    }

    #[inline]
    pub fn duration(&self) -> R {
        match self {
            JointLaw::Zat(s) => s.ts(),
            JointLaw::Classic(l) => l.tf(),
        }
    }

    /// g(t).
    #[inline]
    pub fn g(&self, t: R) -> R {
        match self {
            JointLaw::Zat(s) => s.g(t),
            JointLaw::Classic(l) => l.position(t),
        }
    }

    /// (g, g′).
    pub fn g_rate(&self, t: R) -> (R, R) {
        match self {
            JointLaw::Zat(s) => s.g_rate(t),
            JointLaw::Classic(l) => {
                let d = l.sample(t);
                (d.s, d.v)
            }
        }
    }

    /// g and its first three derivatives.
    pub fn g_derivs(&self, t: R) -> Sample<R> {
        match self {
            JointLaw::Zat(s) => s.g_derivs(t),
            JointLaw::Classic(l) => l.sample(t),
        }
    }

    /// g′ at the end (left limit).
    pub fn end_rate(&self) -> R {
        match self {
            JointLaw::Zat(s) => s.end_rate(),
            JointLaw::Classic(l) => l.end_velocity(),
        }
    }

    /// `Err(Overshoot)` for a ζ-a-tₛ shape that is not monotone; the classic
    /// laws always are.
    pub fn check_monotone(&self) -> Result<(), TrajError<R>> {
        match self {
            JointLaw::Zat(s) => s.check_monotone(),
            JointLaw::Classic(_) => Ok(()),
        }
    }
}

/// Position and velocity of one joint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointState<R> {
    pub pos: R,
    pub vel: R,
}

/// All joints moving start → target under one shared profile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MultiPlan<R> {
    law: JointLaw<R>,
    start: [R; JOINTS],
    target: [R; JOINTS],
    delta: [R; JOINTS],
}

impl<R: Real> MultiPlan<R> {
    /// A ζ-a-tₛ move. Rejects inadmissible shapes and, since this feeds the
    /// servos, shapes whose profile overshoots or backtracks (`Overshoot`).
    pub fn new(
        start: &[R; JOINTS],
        target: &[R; JOINTS],
        shape: &ShapeParams<R>,
    ) -> Result<Self, TrajError<R>> {
        Self::with_law(start, target, &JointLaw::zat(shape)?)
    }

    /// A move under any profile (monotonicity is enforced here too).
    pub fn with_law(
        start: &[R; JOINTS],
        target: &[R; JOINTS],
        law: &JointLaw<R>,
    ) -> Result<Self, TrajError<R>> {
        // Joint values as scalars, so the plan is written where the caller
        // wants it instead of being assembled and copied.
        let [s0, s1, s2] = *start;
        let [e0, e1, e2] = *target;
        all_finite(&[s0, s1, s2])?;
        all_finite(&[e0, e1, e2])?;
        law.check_monotone()?;
        let delta = [e0 - s0, e1 - s1, e2 - s2];
        all_finite(&delta)?;
        Ok(MultiPlan {
            law: *law,
            start: [s0, s1, s2],
            target: [e0, e1, e2],
            delta,
        })
    }

    #[inline]
    pub fn law(&self) -> &JointLaw<R> {
        &self.law
    }
    #[inline]
    pub fn duration(&self) -> R {
        self.law.duration()
    }
    #[inline]
    pub fn start(&self) -> &[R; JOINTS] {
        &self.start
    }
    #[inline]
    pub fn target(&self) -> &[R; JOINTS] {
        &self.target
    }
    #[inline]
    pub fn is_finished(&self, t: R) -> bool {
        t >= self.duration()
    }

    /// Joint positions: exactly `start` for t ≤ 0 and exactly `target` from
    /// the end time on; one profile evaluation per call.
    pub fn positions(&self, t: R) -> [R; JOINTS] {
        self.positions_with(t, self.law.g(t))
    }

    /// [`MultiPlan::positions`] from an already evaluated profile value
    /// `g = g(t)` (the frame evaluates it once for pulses and angles).
    pub fn positions_with(&self, t: R, g: R) -> [R; JOINTS] {
        if t >= self.duration() {
            return self.target;
        }
        if t <= R::ZERO {
            return self.start;
        }
        let mut out = self.start;
        for (o, d) in out.iter_mut().zip(self.delta.iter()) {
            *o += *d * g;
        }
        out
    }

    /// Positions and velocities, from one profile evaluation (g and g′
    /// together); the positions are exactly those of [`MultiPlan::positions`].
    pub fn sample(&self, t: R) -> [JointState<R>; JOINTS] {
        let (g, rate) = self.law.g_rate(t);
        let end = t >= self.duration();
        let rest = t <= R::ZERO;
        let mut out = [JointState {
            pos: R::ZERO,
            vel: R::ZERO,
        }; JOINTS];
        for (((o, s), e), d) in out
            .iter_mut()
            .zip(self.start.iter())
            .zip(self.target.iter())
            .zip(self.delta.iter())
        {
            o.pos = if end {
                *e
            } else if rest {
                *s
            } else {
                *s + *d * g
            };
            o.vel = *d * rate;
        }
        out
    }

    /// Positions and their first three derivatives.
    pub fn sample_full(&self, t: R) -> [Sample<R>; JOINTS] {
        let pos = self.positions(t);
        let g = self.law.g_derivs(t);
        let mut out = [Sample::at_rest(R::ZERO); JOINTS];
        for ((o, p), d) in out.iter_mut().zip(pos.iter()).zip(self.delta.iter()) {
            *o = Sample {
                s: *p,
                v: *d * g.v,
                acc: *d * g.acc,
                jerk: *d * g.jerk,
            };
        }
        out
    }

    /// Joint velocities just before the end (a step to zero unless the
    /// profile stops smoothly).
    pub fn end_velocities(&self) -> [R; JOINTS] {
        let r = self.law.end_rate();
        let mut out = self.delta;
        for o in out.iter_mut() {
            *o *= r;
        }
        out
    }
}

/// Why a [`ServoTrack`] could not be built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TrackError {
    /// A joint's start pulse or pulse travel (µs, before clamping) exceeds
    /// ±60000 µs: angles far outside any servo's range.
    OutOfRange,
}

/// What one 50 Hz frame sends to the servos.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoFrame {
    /// Pulse widths (µs), clamped to each joint's angle and pulse limits.
    pub pulses_us: [u16; JOINTS],
    /// The profile g and its rate g′ (1/s): joint j moves at Δ_j·g′
    /// ([`ServoTrack::velocities`]).
    pub g: f32,
    pub rate: f32,
    /// Some joint would exceed its `max_speed_rad_s` (|Δ_j·g′| > limit).
    pub too_fast: bool,
}

/// Largest |start pulse| and |pulse travel| a track accepts (µs): keeps the
/// Q.14 pulse arithmetic inside i32.
const TRACK_RANGE_US: f32 = 60_000.0;
/// Pulses carry 14 fractional bits (µs·2¹⁴).
const PULSE_FRAC: u32 = 14;

/// One joint's pulse as a function of g: `base + span·g`, clamped.
#[derive(Debug, Clone, Copy, PartialEq)]
struct PulseLine {
    /// Pulse at the start, µs·2¹⁴.
    base: i32,
    /// |µs/rad · Δ|·2¹⁶ and its sign.
    span: u32,
    span_neg: bool,
    /// Clamp window, µs·2¹⁴.
    lo: i32,
    hi: i32,
}

impl PulseLine {
    /// The pulse (µs) at g·2³⁰ = gq.
    #[inline(always)]
    fn at(&self, gq: u32) -> u16 {
        // span·2¹⁶ · g·2³⁰ / 2³² = span·g·2¹⁴, < 2³¹ by TRACK_RANGE_US.
        let step = mul_hi(self.span, gq) as i32;
        let v = if self.span_neg { self.base - step } else { self.base + step };
        let v = v.max(self.lo).min(self.hi);
        ((v + (1 << (PULSE_FRAC - 1))) >> PULSE_FRAC) as u16
    }
}

/// A [`MultiPlan`] bound to the joints' servo mappings: the control loop's
/// per-frame work. A frame is one profile evaluation (g, g′), then per joint a
/// 32-bit integer multiply-add for the pulse; the speed check is one integer
/// comparison of |g′| with the tightest joint's limit, so joint velocities
/// (three float multiplications) are formed only when asked for.
///
/// The pulse of joint j is the one [`ServoMap::angle_to_pulse`] gives for
/// `start_j + Δ_j·g`, computed as `base_j + span_j·g` with base = pulse at the
/// start and span = µs/rad · Δ (both unclamped), then clamped to the window
/// where neither the angle limits nor the pulse limits act: the map is linear
/// and monotone, so clamping the angle and then the pulse is clamping the
/// pulse to the intersection. Rounding is servo.rs's (half up); the
/// intermediate differs from its f32 value by < 1e-3 µs, so a pulse can
/// differ by 1 µs only when the exact value lies that close to a half. At
/// t ≤ 0 and t ≥ duration the pulses are servo.rs's own for the start and the
/// target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoTrack {
    plan: MultiPlan<f32>,
    lines: [PulseLine; JOINTS],
    start_us: [u16; JOINTS],
    end_us: [u16; JOINTS],
    /// |g′| above this puts some joint over its speed limit.
    rate_limit: f32,
    /// The plan's duration (> 0) as bits, for an integer time compare.
    duration_bits: i32,
}

impl ServoTrack {
    pub fn new(plan: &MultiPlan<f32>, maps: &[ServoMap; JOINTS]) -> Result<Self, TrackError> {
        let zero = PulseLine { base: 0, span: 0, span_neg: false, lo: 0, hi: 0 };
        let mut t = ServoTrack {
            plan: *plan,
            lines: [zero; JOINTS],
            start_us: [0; JOINTS],
            end_us: [0; JOINTS],
            rate_limit: f32::INFINITY,
            duration_bits: plan.duration().to_bits() as i32,
        };
        let q14 = (1u32 << PULSE_FRAC) as f32;
        let joints = maps
            .iter()
            .zip(plan.start.iter().zip(plan.target.iter()).zip(plan.delta.iter()))
            .zip(t.lines.iter_mut().zip(t.start_us.iter_mut().zip(t.end_us.iter_mut())));
        for ((m, ((&s, &e), &d)), (line, (su, eu))) in joints {
            let c = m.cal();
            let base = c.offset_us + c.us_per_rad * s;
            let span = c.us_per_rad * d;
            if !(base.abs() <= TRACK_RANGE_US && span.abs() <= TRACK_RANGE_US) {
                return Err(TrackError::OutOfRange);
            }
            let (pa, pb) = (
                c.offset_us + c.us_per_rad * c.min_rad,
                c.offset_us + c.us_per_rad * c.max_rad,
            );
            let lo = pa.min(pb).max(c.min_us as f32);
            let hi = pa.max(pb).min(c.max_us as f32);
            // Finite angles always map: angle_to_pulse only refuses NaN/∞.
            let (Ok(ps), Ok(pe)) = (m.angle_to_pulse(s), m.angle_to_pulse(e)) else {
                return Err(TrackError::OutOfRange);
            };
            *line = PulseLine {
                base: (base * q14) as i32,
                span: (span.abs() * 65_536.0) as u32,
                span_neg: span < 0.0,
                lo: (lo * q14) as i32,
                hi: (hi * q14) as i32,
            };
            *su = ps.us;
            *eu = pe.us;
            if d != 0.0 {
                t.rate_limit = t.rate_limit.min(m.max_speed::<f32>() / d.abs());
            }
        }
        Ok(t)
    }

    #[inline]
    pub fn plan(&self) -> &MultiPlan<f32> {
        &self.plan
    }

    /// The frame at time t (s from the start of the move).
    pub fn frame(&self, t: f32) -> ServoFrame {
        let (g, rate) = self.plan.law.g_rate(t);
        // Floats order like their bit patterns read as i32 when one side is
        // positive (no soft-float compare call): a NaN rate counts as too
        // fast, a NaN time as the end.
        let too_fast = rate.abs().to_bits() > self.rate_limit.to_bits();
        let tb = t.to_bits() as i32;
        let pulses_us = if tb >= self.duration_bits {
            self.end_us
        } else if tb <= 0 {
            self.start_us
        } else {
            let gq = unit_q30(g);
            let [l0, l1, l2] = &self.lines;
            [l0.at(gq), l1.at(gq), l2.at(gq)]
        };
        ServoFrame { pulses_us, g, rate, too_fast }
    }

    /// Joint velocities (rad/s) for a frame's rate g′.
    pub fn velocities(&self, rate: f32) -> [f32; JOINTS] {
        let [d0, d1, d2] = self.plan.delta;
        [d0 * rate, d1 * rate, d2 * rate]
    }
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
        return 1 << 30;
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
