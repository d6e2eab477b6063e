//! A synchronized multi-joint move: every joint follows q0 + Δ·g(t) with one
//! shared normalized profile g (0 → 1 over the same duration), so all joints
//! arrive together and a frame costs one profile evaluation plus a
//! multiply-add per joint.

use crate::math::real::Real;
use crate::motion::laws::{Law, LawParams, LawPlan};
use crate::motion::scaled::ScaledZat;
use crate::motion::zat::{Shape, ShapeParams};
use crate::motion::{all_finite, Sample, TrajError};

/// Base, shoulder, elbow.
pub const JOINTS: usize = 3;

/// The user-selectable motion law (the `law` command, stored in the
/// configuration record by [`LawKind::id`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LawKind {
    /// The ζ-a-tₛ trajectory time-scaled from one reference shape
    /// ([`ScaledZat`]): the default.
    Zat,
    /// The papers' own ζ-a-tₛ (method.md §7): tₛ in seconds, the shape chosen per
    /// move (an expert option).
    ZatPaper,
    /// [`Law::Quintic`]: zero velocity and acceleration at both ends.
    Quintic,
    /// [`Law::Cubic`]: zero velocity at both ends.
    Cubic,
    /// [`Law::Trapezoid`]: constant acceleration, cruise, deceleration.
    Trapezoid,
    /// [`Law::Linear`]: constant velocity, steps at both ends.
    Linear,
}

impl LawKind {
    /// Every law, the product's own first.
    pub const ALL: [LawKind; 6] =
        [LawKind::Zat, LawKind::ZatPaper, LawKind::Quintic, LawKind::Cubic, LawKind::Trapezoid, LawKind::Linear];

    /// Stable id of the EEPROM record (never renumber).
    pub fn id(self) -> u8 {
        match self {
            LawKind::Zat => 0,
            LawKind::Quintic => 1,
            LawKind::Cubic => 2,
            LawKind::Trapezoid => 3,
            LawKind::Linear => 4,
            LawKind::ZatPaper => 5,
        }
    }

    /// The law stored as `id`; `None` for an unknown byte.
    pub fn from_id(id: u8) -> Option<LawKind> {
        LawKind::ALL.iter().copied().find(|l| l.id() == id)
    }

    /// The name used by the `law` command.
    pub fn name(self) -> crate::text::Text {
        match self {
            LawKind::Zat => t!("zat"),
            LawKind::ZatPaper => t!("zat-paper"),
            LawKind::Quintic => t!("quintic"),
            LawKind::Cubic => t!("cubic"),
            LawKind::Trapezoid => t!("trapezoid"),
            LawKind::Linear => t!("linear"),
        }
    }

    /// The law named `name` in a `law` command.
    pub fn from_name(name: &[u8]) -> Option<LawKind> {
        LawKind::ALL.iter().copied().find(|l| l.name().eq_bytes(name))
    }
}

/// A normalized profile g: g(t) = 0 for t ≤ 0, 1 for t ≥ duration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JointLaw<R> {
    /// The papers' ζ-a-tₛ G over [0, tₛ], tₛ in seconds.
    Zat(Shape<R>),
    /// The time-scaled ζ-a-tₛ.
    Scaled(ScaledZat<R>),
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
        if duration <= R::ZERO {
            return Err(TrajError::NonPositiveDuration);
        }
        Ok(JointLaw::Classic(LawPlan::new(law, &LawParams { t0: R::ZERO, tf: duration, s0: R::ZERO, sf: R::ONE })?))
    }

    /// Builds the law the user picked; `shape` supplies tₛ for every law and
    /// (a, n) for the papers' ζ-a-tₛ.
    pub fn from_kind(kind: LawKind, shape: &ShapeParams<R>) -> Result<Self, TrajError<R>> {
        match kind {
            LawKind::Zat => Ok(JointLaw::Scaled(ScaledZat::new(shape.ts)?)),
            LawKind::ZatPaper => Self::zat(shape),
            LawKind::Quintic => Self::classic(Law::Quintic, shape.ts),
            LawKind::Cubic => Self::classic(Law::Cubic, shape.ts),
            LawKind::Trapezoid => Self::classic(Law::Trapezoid, shape.ts),
            LawKind::Linear => Self::classic(Law::Linear, shape.ts),
        }
    }

    /// The law the user picks to get this profile.
    pub fn kind(&self) -> LawKind {
        match self {
            JointLaw::Zat(_) => LawKind::ZatPaper,
            JointLaw::Scaled(_) => LawKind::Zat,
            JointLaw::Classic(l) => match l.law() {
                Law::Quintic => LawKind::Quintic,
                Law::Cubic => LawKind::Cubic,
                Law::Trapezoid => LawKind::Trapezoid,
                Law::Linear => LawKind::Linear,
            },
        }
    }

    /// Time from 0 to the end of the profile, s (tₛ for ζ-a-tₛ).
    #[inline]
    pub fn duration(&self) -> R {
        match self {
            JointLaw::Zat(s) => s.ts(),
            JointLaw::Scaled(s) => s.ts(),
            JointLaw::Classic(l) => l.tf(),
        }
    }

    /// g(t).
    #[inline]
    pub fn g(&self, t: R) -> R {
        match self {
            JointLaw::Zat(s) => s.g(t),
            JointLaw::Scaled(s) => s.g(t),
            JointLaw::Classic(l) => l.position(t),
        }
    }

    /// (g, g′).
    pub fn g_rate(&self, t: R) -> (R, R) {
        match self {
            JointLaw::Zat(s) => s.g_rate(t),
            JointLaw::Scaled(s) => s.g_rate(t),
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
            JointLaw::Scaled(s) => s.g_derivs(t),
            JointLaw::Classic(l) => l.sample(t),
        }
    }

    /// g′ at the end (left limit).
    pub fn end_rate(&self) -> R {
        match self {
            JointLaw::Zat(s) => s.end_rate(),
            JointLaw::Scaled(s) => s.end_rate(),
            JointLaw::Classic(l) => l.end_velocity(),
        }
    }

    /// `Err(Overshoot)` for a ζ-a-tₛ shape that is not monotone; the classic
    /// laws always are.
    pub fn check_monotone(&self) -> Result<(), TrajError<R>> {
        match self {
            JointLaw::Zat(s) => s.check_monotone(),
            // The reference shape is a monotone smooth stop (tested).
            JointLaw::Scaled(_) | JointLaw::Classic(_) => Ok(()),
        }
    }
}

/// Position and velocity of one joint.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointState<R> {
    /// Angle, rad.
    pub pos: R,
    /// Angular velocity, rad/s.
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
    pub fn new(start: &[R; JOINTS], target: &[R; JOINTS], shape: &ShapeParams<R>) -> Result<Self, TrajError<R>> {
        Self::with_law(start, target, &JointLaw::zat(shape)?)
    }

    /// A move under any profile (monotonicity is enforced here too).
    pub fn with_law(start: &[R; JOINTS], target: &[R; JOINTS], law: &JointLaw<R>) -> Result<Self, TrajError<R>> {
        // Joint values as scalars, so the plan is written where the caller
        // wants it instead of being assembled and copied.
        let [s0, s1, s2] = *start;
        let [e0, e1, e2] = *target;
        all_finite(&[s0, s1, s2])?;
        all_finite(&[e0, e1, e2])?;
        law.check_monotone()?;
        let delta = [e0 - s0, e1 - s1, e2 - s2];
        all_finite(&delta)?;
        Ok(MultiPlan { law: *law, start: [s0, s1, s2], target: [e0, e1, e2], delta })
    }

    /// The shared profile.
    #[inline]
    pub fn law(&self) -> &JointLaw<R> {
        &self.law
    }
    /// Duration of the move, s.
    #[inline]
    pub fn duration(&self) -> R {
        self.law.duration()
    }
    /// Joint angles at t = 0, rad.
    #[inline]
    pub fn start(&self) -> &[R; JOINTS] {
        &self.start
    }
    /// Joint angles at the end, rad.
    #[inline]
    pub fn target(&self) -> &[R; JOINTS] {
        &self.target
    }
    /// `target − start` per joint.
    #[inline]
    pub fn delta(&self) -> &[R; JOINTS] {
        &self.delta
    }
    /// `t` (s since the start) is at or past the end.
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
        let mut out = [JointState { pos: R::ZERO, vel: R::ZERO }; JOINTS];
        for (((o, s), e), d) in out.iter_mut().zip(self.start.iter()).zip(self.target.iter()).zip(self.delta.iter()) {
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
            *o = Sample { s: *p, v: *d * g.v, acc: *d * g.acc, jerk: *d * g.jerk };
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
