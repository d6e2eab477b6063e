//! The control loop's per-frame work: a [`MultiPlan`] bound to the joints'
//! servo mappings, evaluated once per 50 Hz frame into pulses with integer
//! arithmetic (the hot path; its cost is in BENCHMARKS.md).

use crate::math::fixed::mul_hi;
use crate::motion::plan::{MultiPlan, JOINTS};
use crate::servo::map::ServoMap;

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
    /// Pulse widths in Timer5 ticks (0.5 µs), clamped to each joint's angle
    /// and pulse limits.
    pub pulses: [u16; JOINTS],
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
    /// The pulse (Timer5 ticks) at g·2³⁰ = gq.
    #[inline(always)]
    fn at(&self, gq: u32) -> u16 {
        // span·2¹⁶ · g·2³⁰ / 2³² = span·g·2¹⁴, < 2³¹ by TRACK_RANGE_US.
        let step = mul_hi(self.span, gq) as i32;
        let v = if self.span_neg { self.base - step } else { self.base + step };
        let v = v.max(self.lo).min(self.hi);
        // µs·2¹⁴ to ticks (µs·2), rounded half up as servo::map rounds.
        ((v + (1 << (PULSE_FRAC - 2))) >> (PULSE_FRAC - 1)) as u16
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
/// pulse to the intersection. Rounding is [`super::map`]'s (half up); the
/// intermediate differs from its f32 value by < 1e-3 µs, so a pulse can
/// differ by one tick only when the exact value lies that close to the middle
/// between two ticks. At
/// t ≤ 0 and t ≥ duration the pulses are [`super::map`]'s own for the start and the
/// target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoTrack {
    plan: MultiPlan<f32>,
    lines: [PulseLine; JOINTS],
    start_ticks: [u16; JOINTS],
    end_ticks: [u16; JOINTS],
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
            start_ticks: [0; JOINTS],
            end_ticks: [0; JOINTS],
            rate_limit: f32::INFINITY,
            duration_bits: plan.duration().to_bits() as i32,
        };
        let q14 = (1u32 << PULSE_FRAC) as f32;
        let joints = maps
            .iter()
            .zip(plan.start().iter().zip(plan.target().iter()).zip(plan.delta().iter()))
            .zip(t.lines.iter_mut().zip(t.start_ticks.iter_mut().zip(t.end_ticks.iter_mut())));
        for ((m, ((&s, &e), &d)), (line, (su, eu))) in joints {
            let c = m.cal();
            let base = c.offset_us + c.us_per_rad * s;
            let span = c.us_per_rad * d;
            if !(base.abs() <= TRACK_RANGE_US && span.abs() <= TRACK_RANGE_US) {
                return Err(TrackError::OutOfRange);
            }
            let (pa, pb) = (c.offset_us + c.us_per_rad * c.min_rad, c.offset_us + c.us_per_rad * c.max_rad);
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
            *su = ps.ticks;
            *eu = pe.ticks;
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
        let (g, rate) = self.plan.law().g_rate(t);
        // Floats order like their bit patterns read as i32 when one side is
        // positive (no soft-float compare call): a NaN rate counts as too
        // fast, a NaN time as the end.
        let too_fast = rate.abs().to_bits() > self.rate_limit.to_bits();
        let tb = t.to_bits() as i32;
        let pulses = if tb >= self.duration_bits {
            self.end_ticks
        } else if tb <= 0 {
            self.start_ticks
        } else {
            let gq = unit_q30(g);
            let [l0, l1, l2] = &self.lines;
            [l0.at(gq), l1.at(gq), l2.at(gq)]
        };
        ServoFrame { pulses, g, rate, too_fast }
    }

    /// Joint velocities (rad/s) for a frame's rate g′.
    pub fn velocities(&self, rate: f32) -> [f32; JOINTS] {
        let [d0, d1, d2] = *self.plan.delta();
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
