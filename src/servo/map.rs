//! Joint angle ↔ servo pulse mapping and the Timer5 compare values (docs/hardware.md).
//!
//! # Angle convention (the IK's)
//! All angles are radians.
//! - **Base** α ∈ [0, π]: direction of the touched point, α = atan2(y_p, x_p);
//!   0 points to the screen's +x side, π/2 straight ahead, π to the −x side.
//! - **Shoulder** q2: upper arm measured from the horizontal, in the arm plane
//!   selected by the base; 0 = horizontal pointing outward (toward the target),
//!   π/2 = vertical up, π = horizontal pointing backward. Default range [0, π].
//! - **Elbow** q3: forearm relative to the upper arm (q3 = 0: arm straight),
//!   positive counter-clockwise in the arm plane, so the hand is at
//!   (l2·cos q2 + l3·cos(q2+q3), l2·sin q2 + l3·sin(q2+q3)). The app solves the
//!   IK on [`ELBOW_BRANCH`] = [`Branch::Minus`], the **elbow-up** branch,
//!   q3 = −acos(c) ∈ [−π, 0], and the defaults match it: with the target's
//!   height ≥ 0 and l2 ≥ l3 that branch keeps q2 = atan2(y, x) + β in [0, π]
//!   (β ∈ [0, π/2]) and the elbow above the line from the shoulder to the hand,
//!   so every reachable workspace point lies inside the default limits. The
//!   other branch (q2 = atan2(y, x) − β) needs q2 down to −90° for targets near
//!   the shoulder, below a shoulder servo's range. An arm built for the other
//!   branch changes the constant and recalibrates (`min_rad = 0, max_rad = π`).
//!
//! # Pulse convention
//! `pulse_us = offset_us + us_per_rad · angle`: `offset_us` is the pulse at the
//! reference angle **0 rad of the joint's own convention** (it may lie outside
//! the servo's range, e.g. for a joint whose range does not include 0), and the
//! sign of `us_per_rad` is the servo's direction. A 180° hobby servo spans about
//! 2000 µs over π (500..2500 µs nominal), but many stall against their end
//! stops at the extremes, so the defaults use the safer 600..2400 µs for
//! 0..π, i.e. 1800/π ≈ 573 µs/rad. The true slope of a given servo differs by
//! ±10 %; `cal set` corrects it.
//!
//! # Safety
//! [`ServoMap`] can only be built from a validated [`JointCal`], and
//! [`ServoMap::angle_to_pulse`] clamps to the joint's angle limits *and* its
//! pulse limits (and finally to the absolute 500..2500 µs), so no angle, however
//! wrong, drives a servo past its configured range. A non-finite angle (NaN, ±∞)
//! is a bug upstream, not a direction: it is refused with
//! [`ServoError::NotFinite`] and the caller keeps the previous pulse (hold).

use crate::geometry::ik::Branch;
use crate::math::real::Real;

/// The IK elbow branch the app uses; the default joint limits assume it.
pub const ELBOW_BRANCH: Branch = Branch::Minus;

/// Absolute pulse limits no calibration may exceed.
pub const ABS_MIN_US: u16 = 500;
/// The longest pulse ever sent, µs.
pub const ABS_MAX_US: u16 = 2500;

/// Timer5 in mode 14 (fast PWM, TOP = ICR5), prescaler 8 at 16 MHz: 0.5 µs per
/// tick, 40000 ticks = 20 ms = 50 Hz.
pub const TIMER5_TOP: u16 = 39_999;
/// Timer5 ticks per µs of pulse (0.5 µs resolution).
pub const TICKS_PER_US: u16 = 2;

/// Joint servos in Timer5 channel order: OC5A (D46), OC5B (D45), OC5C (D44).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Joint {
    /// Turns the arm about the vertical axis (α).
    Base,
    /// Raises the upper arm (q2).
    Shoulder,
    /// Bends the forearm relative to the upper arm (q3).
    Elbow,
}

impl Joint {
    /// Every joint, in [`Joint::index`] order.
    pub const ALL: [Joint; 3] = [Joint::Base, Joint::Shoulder, Joint::Elbow];

    /// Index into per-joint arrays, also the Timer5 channel (0 = A).
    pub fn index(self) -> usize {
        match self {
            Joint::Base => 0,
            Joint::Shoulder => 1,
            Joint::Elbow => 2,
        }
    }

    /// The joint's word in `cal set`, `cal show` and the replies.
    pub fn name(self) -> crate::text::Text {
        match self {
            Joint::Base => t!("base"),
            Joint::Shoulder => t!("shoulder"),
            Joint::Elbow => t!("elbow"),
        }
    }
}

/// One joint's calibration as stored (plain data; validate before use).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointCal {
    /// Pulse at angle 0 rad, µs.
    pub offset_us: f32,
    /// µs per radian; the sign is the servo's direction.
    pub us_per_rad: f32,
    /// Pulse limits, µs, within 500..=2500.
    pub min_us: u16,
    /// Longest pulse, µs; above `min_us`, at most 2500.
    pub max_us: u16,
    /// Angle limits, rad.
    pub min_rad: f32,
    /// Largest angle, rad; above `min_rad`, within ±2π.
    pub max_rad: f32,
    /// Largest joint speed the planner may command, rad/s.
    pub max_speed_rad_s: f32,
    /// Largest joint acceleration the planner may command, rad/s².
    pub max_accel_rad_s2: f32,
}

/// Accepted |µs per rad|: a 360° servo over 500..2500 µs is ~318; a 90° one ~1273.
pub const MIN_US_PER_RAD: f32 = 100.0;
/// Largest accepted |µs per rad| (see [`MIN_US_PER_RAD`]).
pub const MAX_US_PER_RAD: f32 = 3000.0;
/// Accepted |offset| (keeps `offset + k·angle` exact to well below 1 µs in f32).
pub const MAX_ABS_OFFSET_US: f32 = 20_000.0;
/// Angle limits must lie in [−2π, 2π].
pub const MAX_ABS_ANGLE_RAD: f32 = 2.0 * core::f32::consts::PI;
/// Largest accepted `max_speed_rad_s` (a fast hobby servo unloaded is ~10 rad/s).
pub const MAX_SPEED_LIMIT_RAD_S: f32 = 50.0;
/// Largest accepted `max_accel_rad_s2` (an unloaded hobby servo reaches its
/// speed in some 50 ms: ~200 rad/s²).
pub const MAX_ACCEL_LIMIT_RAD_S2: f32 = 1000.0;

const PI: f32 = core::f32::consts::PI;
/// 600..2400 µs over π rad.
const DEFAULT_US_PER_RAD: f32 = 1800.0 / PI;
/// ≈ 170°/s: a margin below what a loaded MG996R/SG90-class servo manages.
const DEFAULT_MAX_SPEED: f32 = 3.0;
/// 1000°/s² ≈ 17.5 rad/s²: an unloaded MG996R/SG90-class servo reaches its
/// ~6 rad/s in some 50–100 ms (60–120 rad/s²) and an arm link on it cuts
/// that by about three, so this keeps a margin of two or more; the default
/// speed is reached in 0.17 s. At the fast preset it lengthens only moves
/// below ~45° (docs/method.md §10), which it keeps from jerking off.
const DEFAULT_MAX_ACCEL: f32 = 1000.0 * PI / 180.0;

impl JointCal {
    /// Base: α ∈ [0, π] → 600..2400 µs.
    pub const BASE_DEFAULT: JointCal = JointCal {
        offset_us: 600.0,
        us_per_rad: DEFAULT_US_PER_RAD,
        min_us: 600,
        max_us: 2400,
        min_rad: 0.0,
        max_rad: PI,
        max_speed_rad_s: DEFAULT_MAX_SPEED,
        max_accel_rad_s2: DEFAULT_MAX_ACCEL,
    };
    /// Shoulder: q2 ∈ [0, π] → 600..2400 µs.
    pub const SHOULDER_DEFAULT: JointCal = JointCal::BASE_DEFAULT;
    /// Elbow (elbow-up branch): q3 ∈ [−π, 0] → 600..2400 µs (0 rad = straight = 2400 µs).
    pub const ELBOW_DEFAULT: JointCal = JointCal {
        offset_us: 2400.0,
        us_per_rad: DEFAULT_US_PER_RAD,
        min_us: 600,
        max_us: 2400,
        min_rad: -PI,
        max_rad: 0.0,
        max_speed_rad_s: DEFAULT_MAX_SPEED,
        max_accel_rad_s2: DEFAULT_MAX_ACCEL,
    };
    /// Defaults in [`Joint::index`] order.
    pub const DEFAULTS: [JointCal; 3] = [JointCal::BASE_DEFAULT, JointCal::SHOULDER_DEFAULT, JointCal::ELBOW_DEFAULT];

    /// Pulse (unclamped, µs) at `angle`.
    fn pulse_at(&self, angle: f32) -> f32 {
        self.offset_us + self.us_per_rad * angle
    }

    /// Checks every field against the limits above and that the angle range
    /// reaches the pulse range; the first failure is returned.
    pub fn validate(&self) -> Result<(), JointCalError> {
        let floats =
            [self.offset_us, self.us_per_rad, self.min_rad, self.max_rad, self.max_speed_rad_s, self.max_accel_rad_s2];
        if floats.iter().any(|v| !v.is_finite()) {
            return Err(JointCalError::NotFinite);
        }
        if self.min_us < ABS_MIN_US || self.max_us > ABS_MAX_US || self.min_us >= self.max_us {
            return Err(JointCalError::PulseLimits);
        }
        if self.min_rad >= self.max_rad || self.min_rad < -MAX_ABS_ANGLE_RAD || self.max_rad > MAX_ABS_ANGLE_RAD {
            return Err(JointCalError::AngleLimits);
        }
        let k = self.us_per_rad.abs();
        if !(MIN_US_PER_RAD..=MAX_US_PER_RAD).contains(&k) {
            return Err(JointCalError::Scale);
        }
        if self.offset_us.abs() > MAX_ABS_OFFSET_US {
            return Err(JointCalError::Offset);
        }
        if !(self.max_speed_rad_s > 0.0 && self.max_speed_rad_s <= MAX_SPEED_LIMIT_RAD_S) {
            return Err(JointCalError::Speed);
        }
        if !(self.max_accel_rad_s2 > 0.0 && self.max_accel_rad_s2 <= MAX_ACCEL_LIMIT_RAD_S2) {
            return Err(JointCalError::Accel);
        }
        // The angle range must reach the pulse range, else every command would
        // end at a pulse limit: a calibration mistake, not a usable joint.
        let (a, b) = (self.pulse_at(self.min_rad), self.pulse_at(self.max_rad));
        let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
        if hi < self.min_us as f32 || lo > self.max_us as f32 {
            return Err(JointCalError::NoOverlap);
        }
        Ok(())
    }
}

/// Why a joint calibration is refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointCalError {
    /// A field is NaN or infinite.
    NotFinite,
    /// Pulse limits outside 500..=2500 µs or `min_us >= max_us`.
    PulseLimits,
    /// `min_rad >= max_rad` or a limit outside ±2π.
    AngleLimits,
    /// |µs per rad| outside 100..=3000.
    Scale,
    /// |offset| above 20000 µs.
    Offset,
    /// Max speed not in (0, 50] rad/s.
    Speed,
    /// Max acceleration not in (0, 1000] rad/s².
    Accel,
    /// The angle range maps entirely outside the pulse range.
    NoOverlap,
}

impl JointCalError {
    /// The reason as the `err` reply states it.
    pub fn reason(self) -> crate::text::Text {
        match self {
            JointCalError::NotFinite => t!("not finite"),
            JointCalError::PulseLimits => t!("pulse limits"),
            JointCalError::AngleLimits => t!("angle limits"),
            JointCalError::Scale => t!("scale"),
            JointCalError::Offset => t!("offset"),
            JointCalError::Speed => t!("speed"),
            JointCalError::Accel => t!("accel"),
            JointCalError::NoOverlap => t!("angle range misses pulse range"),
        }
    }
}

/// Which limit changed a commanded pulse.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Limit {
    /// Below the joint's `min_rad`.
    AngleMin,
    /// Above the joint's `max_rad`.
    AngleMax,
    /// Below the joint's `min_us`.
    PulseMin,
    /// Above the joint's `max_us`.
    PulseMax,
}

/// A pulse width to output, in Timer5 ticks of 0.5 µs (the timer's full
/// resolution), and the limit that shaped it, if any. A clamp is reported
/// only when it moves the pulse by more than 0.5 µs, so float noise at a limit
/// (an IK returning −1e−7 for a limit of 0) is not a clamp. The move is
/// judged in total, from the unclamped pulse: an angle clamp and a pulse
/// clamp of 0.5 µs each are a clamp of 1 µs (judged apart, two calibration
/// changes in a row walked a held pose out of its window, issue #24 F5). If
/// both an angle and a pulse limit act, the pulse limit (applied last) is
/// reported.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pulse {
    /// Width, Timer5 ticks (0.5 µs).
    pub ticks: u16,
    /// The limit that changed it, if one did (by > 0.5 µs in total).
    pub clamped: Option<Limit>,
}

impl Pulse {
    /// The width in µs (a multiple of 0.5).
    pub fn us(self) -> f32 {
        f32::from(self.ticks) * 0.5
    }
}

/// Why no pulse was computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ServoError {
    /// The requested angle is NaN or infinite: hold the previous pulse.
    NotFinite,
}

/// A validated joint mapping, ready for the control loop.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoMap {
    cal: JointCal,
    min_us: f32,
    max_us: f32,
    rad_per_us: f32,
}

impl ServoMap {
    /// A mapping for `cal`, once it validates.
    pub fn new(cal: &JointCal) -> Result<ServoMap, JointCalError> {
        cal.validate()?;
        Ok(ServoMap {
            cal: *cal,
            min_us: cal.min_us as f32,
            max_us: cal.max_us as f32,
            rad_per_us: 1.0 / cal.us_per_rad,
        })
    }

    /// The calibration it was built from.
    pub fn cal(&self) -> &JointCal {
        &self.cal
    }

    /// Pulse for `angle` (rad), clamped to the angle and pulse limits and
    /// rounded (half up) to the nearest Timer5 tick (0.5 µs).
    pub fn angle_to_pulse<R: Real>(&self, angle: R) -> Result<Pulse, ServoError> {
        if !angle.is_finite() {
            return Err(ServoError::NotFinite);
        }
        let c = &self.cal;
        let (min_rad, max_rad) = (R::from_f32(c.min_rad), R::from_f32(c.max_rad));
        let (offset, k) = (R::from_f32(c.offset_us), R::from_f32(c.us_per_rad));
        let mut limit = None;
        let a = if angle < min_rad {
            limit = Some(Limit::AngleMin);
            min_rad
        } else if angle > max_rad {
            limit = Some(Limit::AngleMax);
            max_rad
        } else {
            angle
        };
        let raw = offset + k * a;
        let (lo, hi) = (R::from_f32(self.min_us), R::from_f32(self.max_us));
        let us = if raw < lo {
            limit = Some(Limit::PulseMin);
            lo
        } else if raw > hi {
            limit = Some(Limit::PulseMax);
            hi
        } else {
            raw
        };
        // Both clamps judged together (the type's doc).
        let clamped = if (us - (offset + k * angle)).abs() > R::HALF { limit } else { None };
        // `us` is within 500..=2500 here; the final clamp is defence in depth.
        let ticks = ((us.twice() + R::HALF).to_f32() as u16).max(c.min_us * TICKS_PER_US).min(c.max_us * TICKS_PER_US);
        Ok(Pulse { ticks, clamped })
    }

    /// Angle (rad) that a pulse of `ticks` (0.5 µs) stands for; not clamped
    /// (it reports, it does not command).
    pub fn pulse_to_angle<R: Real>(&self, ticks: u16) -> R {
        (R::from_u16(ticks) * R::HALF - R::from_f32(self.cal.offset_us)) * R::from_f32(self.rad_per_us)
    }

    /// The angles whose pulse no limit changes: the angle limits intersected
    /// with the pulse limits seen as angles (non-empty: `validate` refuses a
    /// calibration whose angle range misses its pulse range).
    pub fn output_window(&self) -> (f32, f32) {
        let c = &self.cal;
        let a = (self.min_us - c.offset_us) * self.rad_per_us;
        let b = (self.max_us - c.offset_us) * self.rad_per_us;
        let (lo, hi) = if a <= b { (a, b) } else { (b, a) };
        let lo = lo.max(c.min_rad);
        (lo, hi.min(c.max_rad).max(lo))
    }

    /// `angle` pulled into [`ServoMap::output_window`]: the angle the pulse
    /// [`ServoMap::angle_to_pulse`] gives for `angle` stands for, so a pose
    /// held at it describes what the servo really gets.
    pub fn clamp_angle(&self, angle: f32) -> f32 {
        let (lo, hi) = self.output_window();
        // NaN maps to `lo` (a comparison with NaN is false).
        if angle > lo {
            angle.min(hi)
        } else {
            lo
        }
    }

    /// Angle limits (rad).
    pub fn angle_limits<R: Real>(&self) -> (R, R) {
        (R::from_f32(self.cal.min_rad), R::from_f32(self.cal.max_rad))
    }

    /// The angles (rad) no limit clamps: the angle limits and the pulse
    /// limits' angles, intersected.
    pub fn angle_window<R: Real>(&self) -> [R; 2] {
        let (lo, hi) = self.angle_limits::<R>();
        let (a, b) = (
            self.pulse_to_angle::<R>(self.cal.min_us * TICKS_PER_US),
            self.pulse_to_angle::<R>(self.cal.max_us * TICKS_PER_US),
        );
        let (plo, phi) = if a < b { (a, b) } else { (b, a) };
        [lo.max(plo), hi.min(phi)]
    }

    /// The joint's speed limit, rad/s.
    pub fn max_speed<R: Real>(&self) -> R {
        R::from_f32(self.cal.max_speed_rad_s)
    }

    /// The joint's acceleration limit, rad/s².
    pub fn max_accel<R: Real>(&self) -> R {
        R::from_f32(self.cal.max_accel_rad_s2)
    }
}

/// [`ServoMap::angle_to_pulse`]'s ticks without the report of which limit
/// clamped, for frames whose angles are not affine in one profile (a path
/// move): the same value in fewer float operations. The map with its clamps
/// and rounding is monotone, so clamping the rounded pulse of the raw angle
/// to the pulses of the window's ends is clamping the angle and the pulse
/// first. Built once per move from its [`ServoMap`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TickMap {
    offset_us: f32,
    us_per_rad: f32,
    /// The pulses at the ends of the output window, ticks, low first.
    window: [u16; 2],
}

impl TickMap {
    /// The fast map of `m`. `None` only if a limit angle has no pulse, which
    /// a validated calibration rules out.
    pub fn new(m: &ServoMap) -> Option<TickMap> {
        let c = m.cal();
        let (a, b) = (m.angle_to_pulse(c.min_rad).ok()?, m.angle_to_pulse(c.max_rad).ok()?);
        Some(TickMap {
            offset_us: c.offset_us,
            us_per_rad: c.us_per_rad,
            window: [a.ticks.min(b.ticks), a.ticks.max(b.ticks)],
        })
    }

    /// The pulse for `angle`, Timer5 ticks; `None` for a non-finite angle.
    #[inline]
    pub fn ticks(&self, angle: f32) -> Option<u16> {
        if !angle.is_finite() {
            return None;
        }
        let us = self.offset_us + self.us_per_rad * angle;
        // The float-to-integer cast saturates, which keeps the order.
        let raw = (us.twice() + 0.5) as i32;
        let [lo, hi] = self.window;
        Some(raw.clamp(i32::from(lo), i32::from(hi)) as u16)
    }
}

/// A pulse of `ticks` (0.5 µs) clamped to the absolute 500..=2500 µs, so
/// it is always a servo pulse (never 0 = off or ≥ TOP = always high).
pub fn clamp_ticks(ticks: u16) -> u16 {
    ticks.clamp(ABS_MIN_US * TICKS_PER_US, ABS_MAX_US * TICKS_PER_US)
}

/// Timer5 compare value (OCR5x) for a pulse of `us` µs: `2·us`, with `us`
/// first clamped to the absolute 500..=2500 µs, so the result is always a
/// servo pulse (never 0 = off or ≥ TOP = always high). The board converts
/// the pulse limits with this; pulses arrive in ticks ([`clamp_ticks`]).
pub fn us_to_ticks(us: u16) -> u16 {
    us.clamp(ABS_MIN_US, ABS_MAX_US) * TICKS_PER_US
}
