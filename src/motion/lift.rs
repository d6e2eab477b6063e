//! A move that lifts over what stands on the table (issue #13's "lift
//! over"): every joint follows the via-point form of the 2023 paper
//! (docs/method.md §8), S(t) = q0 + (S_v − q0)·Gv(t) + (S_f − S_v)·G(t), through
//! the via pose at t_v = tₛ/2, where the effector stands h above the higher of
//! start and target, halfway along the base rotation and the reach. S_v is the
//! closed form S_v* = (θ_v − r·S_f)/(1 − r), r = G(t_v).
//!
//! Both shapes are time-scaled from fixed references, as the default law is
//! (docs/method.md §10.2): in the papers' own form r = G(t_v) climbs towards 1
//! as tₛ grows (0.22 at tₛ = 2.2 s, 0.95 at 10 s with t_v = tₛ/2), and S_v*
//! then overshoots by 1/(1 − r), while t_v near 1 s makes the via shape a
//! spike. Scaled, r is one number for every tₛ, and so are the overshoot and
//! the peaks per unit of time: the angle limits are decided once and the
//! shortest duration under the speed and acceleration limits is closed-form.
//! Each reference is the c2 smooth stop of its duration T (n = e^(2/(T − 1)),
//! a = T − log_n T): velocity and acceleration vanish at the via time and at
//! the end, and L·(T − 1) = 2 keeps the shape monotone.

use core::fmt;

use crate::geometry::ik::{fk3_pose, ik2, Branch, Links};
use crate::math::real::Real;
use crate::motion::lift_hull;
use crate::motion::path::{PathLimits, JOINT_NAMES};
use crate::motion::plan::JOINTS;
use crate::motion::via::c2_ln_base;
use crate::motion::zat::Shape;
use crate::motion::{Sample, TrajError};

/// Largest lift, workspace units.
pub const LIFT_MAX: f64 = 0.5;
/// The via term's reference duration, s (n_v = e²).
pub const VIA_REF_T: f64 = 2.0;
/// The main term's reference duration, s (n = e): r = G(T/2) ≈ 0.544.
pub const MAIN_REF_T: f64 = 3.0;
/// Scan intervals over the normalized move (its points: [`lift_hull`]).
pub const LIFT_SCAN: u16 = 512;

/// Why a lift cannot be planned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum LiftError<R> {
    /// h not in (0, [`LIFT_MAX`]] or a non-finite input.
    BadHeight,
    /// The via pose is out of the arm's reach (or singular).
    ViaUnreachable,
    /// A joint would leave its angle limits: at the via pose, or on the way
    /// (the sum of the two terms can overshoot both ends).
    JointLimit {
        /// 0 base, 1 shoulder, 2 elbow.
        joint: u8,
    },
    /// The speed and acceleration limits need more than `ts_max`.
    TooSlow {
        /// The duration they need, s.
        ts_min: R,
    },
    /// The reference shapes could not be built (a build inconsistency).
    Trajectory(TrajError<R>),
}

impl<R: Real> fmt::Display for LiftError<R> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            LiftError::BadHeight => f.write_str("lift height must be in (0, 0.5]"),
            LiftError::ViaUnreachable => f.write_str("the via pose is out of reach"),
            LiftError::JointLimit { joint } => {
                write!(f, "{} joint limit on the lift", JOINT_NAMES.get(joint as usize).copied().unwrap_or("?"))
            }
            LiftError::TooSlow { ts_min } => {
                write!(f, "the joints' limits need a lift of {:.3} s, beyond the longest move", ts_min.to_f64())
            }
            LiftError::Trajectory(e) => write!(f, "lift shapes: {e}"),
        }
    }
}

/// What a lift asks for.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LiftRequest<R> {
    /// Joint angles at rest now, rad (base, shoulder, elbow).
    pub start: [R; JOINTS],
    /// Joint angles to reach, rad.
    pub target: [R; JOINTS],
    /// Lift above the higher of start and target, workspace units.
    pub h: R,
    /// Upper arm and forearm.
    pub links: Links<R>,
    /// Elbow solution of the via pose.
    pub branch: Branch,
    /// Shortest move, s.
    pub ts_min: R,
}

/// A planned lift.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LiftPlan<R> {
    gv: Shape<R>,
    g: Shape<R>,
    ts: R,
    start: [R; JOINTS],
    sv: [R; JOINTS],
    target: [R; JOINTS],
    via: [R; JOINTS],
    via_point: [R; 3],
}

/// The c2 smooth stop of duration `t` (n = e^(2/(t − 1))); `t` in `R`, so the
/// callers' constants convert at compile time on the AVR (an f64 argument
/// linked the run-time `__truncdfsf2`).
fn reference<R: Real>(t: R) -> Result<Shape<R>, LiftError<R>> {
    let l = c2_ln_base(t).ok_or(LiftError::Trajectory(TrajError::NotFinite))?;
    Shape::smooth_stop(t, l.exp()).map_err(LiftError::Trajectory)
}

/// The via pose's joint angles and effector point for a request.
fn via_pose<R: Real>(r: &LiftRequest<R>) -> Result<([R; JOINTS], [R; 3]), LiftError<R>> {
    let (s, e) = (&r.start, &r.target);
    let [xa, ya, za] = fk3_pose(&r.links, s);
    let [xb, yb, zb] = fk3_pose(&r.links, e);
    let (rho_a, rho_b) = ((xa * xa + ya * ya).sqrt(), (xb * xb + yb * yb).sqrt());
    let base = (s[0] + e[0]) * R::HALF;
    let rho = (rho_a + rho_b) * R::HALF;
    let z = za.max(zb) + r.h;
    let q = ik2(&r.links, rho, z, r.branch).map_err(|_| LiftError::ViaUnreachable)?;
    Ok(([base, q.q2, q.q3], [rho * base.cos(), rho * base.sin(), z]))
}

/// A lift's plan worked out a bounded amount at a time
/// ([`LiftCheck::step`]: one vertex of [`lift_hull`]'s tables a unit), so
/// the chip can spread it over frames; [`LiftPlan::new`] runs one to the
/// end. The same result either way.
///
/// Both reference shapes are fixed, so every lift's scan of the normalized
/// move (tₛ = 1 s, τ = i/[`LIFT_SCAN`]) visits the same points of (Gv, G)
/// and of their scaled rates; a lift only weighs them per joint: the angle
/// is q0 + (S_v − q0)·Gv + (S_f − S_v)·G, the rates likewise. A weighted sum's
/// largest and smallest value over the scan's points are at vertices of
/// their convex hull (of the points and their negatives, for the |rates|),
/// so visiting the hull's vertices decides what the scan of all 513 points
/// decides, in a third of the units and without evaluating a shape. The
/// tables hold the f64 shapes' points rounded to f32, so the two differ only
/// where an extreme sits within that rounding of a limit (`tests/lift.rs`
/// recomputes the hulls from the shapes and runs both checks on random
/// lifts: the same refusals, the same duration to 1e-6).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LiftCheck<R> {
    /// The plan at tₛ = 1 s until decided.
    plan: LiftPlan<R>,
    lim: PathLimits<R>,
    ts_min: R,
    /// The next vertex: the angles' hull, then the speeds', then the
    /// accelerations' ([`lift_hull::UNITS`] in all).
    i: u16,
    /// Peak speed and acceleration per joint so far, at tₛ = 1 s.
    v: [R; JOINTS],
    a: [R; JOINTS],
    /// Decided: the duration, or the refusal.
    outcome: Option<Result<R, LiftError<R>>>,
}

impl<R: Real> LiftCheck<R> {
    /// The via pose and S_v per joint; the vertices are to come.
    #[inline(never)] // reason: code-size
    pub fn new(r: &LiftRequest<R>, lim: &PathLimits<R>) -> Result<Self, LiftError<R>> {
        let finite = r.start.iter().chain(r.target.iter()).all(|v| v.is_finite()) && r.ts_min.is_finite();
        if !(finite && r.h.is_positive() && r.h <= R::lit(LIFT_MAX)) {
            return Err(LiftError::BadHeight);
        }
        let (via, via_point) = via_pose(r)?;
        let (gv, g) = (reference(R::lit(VIA_REF_T))?, reference(R::lit(MAIN_REF_T))?);
        let rr = g.g(R::lit(MAIN_REF_T * 0.5));
        let mut sv = [R::ZERO; JOINTS];
        for (j, s) in sv.iter_mut().enumerate() {
            *s = (via[j] - rr * r.target[j]) / (R::ONE - rr);
        }
        // At tₛ = 1 s: the peaks per unit of time.
        let plan = LiftPlan { gv, g, ts: R::ONE, start: r.start, sv, target: r.target, via, via_point };
        let zero = [R::ZERO; JOINTS];
        Ok(LiftCheck { plan, lim: *lim, ts_min: r.ts_min, i: 0, v: zero, a: zero, outcome: None })
    }

    /// Does up to `units` vertices (each: two products and a sum per joint);
    /// the plan or the refusal once decided, and from then on.
    #[inline(never)] // reason: code-size
    pub fn step(&mut self, units: u16) -> Option<Result<LiftPlan<R>, LiftError<R>>> {
        for _ in 0..units {
            if self.outcome.is_some() {
                break;
            }
            self.outcome = self.visit();
        }
        let plan = self.plan;
        self.outcome.map(|r| {
            r.map(|ts| {
                let mut p = plan;
                p.ts = ts;
                p
            })
        })
    }

    /// One vertex; the outcome after the last.
    fn visit(&mut self) -> Option<Result<R, LiftError<R>>> {
        let (lim, i) = (&self.lim, usize::from(self.i));
        let p = &self.plan;
        match lift_hull::vertex::<R>(i) {
            Some((lift_hull::Set::Angle, x, y)) => {
                for j in 0..JOINTS {
                    let q = p.start[j] + (p.sv[j] - p.start[j]) * x + (p.target[j] - p.sv[j]) * y;
                    if !(lim.min[j] <= q && q <= lim.max[j]) {
                        return Some(Err(LiftError::JointLimit { joint: j as u8 }));
                    }
                }
            }
            Some((set, x, y)) => {
                let peaks = if set == lift_hull::Set::Speed { &mut self.v } else { &mut self.a };
                for (j, peak) in peaks.iter_mut().enumerate() {
                    *peak = peak.max(((p.sv[j] - p.start[j]) * x + (p.target[j] - p.sv[j]) * y).abs());
                }
            }
            None => {}
        }
        if i + 1 < lift_hull::UNITS {
            self.i += 1;
            return None;
        }
        let mut ts = self.ts_min;
        for j in 0..JOINTS {
            ts = ts.max(self.v[j] / lim.speed[j]).max((self.a[j] / lim.accel[j]).sqrt());
        }
        if !ts.is_finite() {
            return Some(Err(LiftError::BadHeight));
        }
        if lim.ts_max < ts {
            return Some(Err(LiftError::TooSlow { ts_min: ts }));
        }
        Some(Ok(ts))
    }
}

impl<R: Real> LiftPlan<R> {
    /// Plans the lift: the via pose, S_v per joint, the angle limits on a scan
    /// of the normalized move, and the shortest duration (at least `ts_min`)
    /// whose peaks keep every joint within its speed and acceleration limits
    /// ([`LiftCheck`] run to the end).
    pub fn new(r: &LiftRequest<R>, lim: &PathLimits<R>) -> Result<Self, LiftError<R>> {
        let mut check = LiftCheck::new(r, lim)?;
        loop {
            if let Some(r) = check.step(u16::MAX) {
                return r;
            }
        }
    }

    /// Duration tₛ, s.
    #[inline]
    pub fn ts(&self) -> R {
        self.ts
    }

    /// Via time t_v = tₛ/2, s.
    #[inline]
    pub fn tv(&self) -> R {
        self.ts * R::HALF
    }

    /// The via pose's joint angles, rad.
    #[inline]
    pub fn via(&self) -> &[R; JOINTS] {
        &self.via
    }

    /// The via pose's effector point (x, y, z).
    #[inline]
    pub fn via_point(&self) -> &[R; 3] {
        &self.via_point
    }

    /// The via term's targets S_v, rad.
    #[inline]
    pub fn sv(&self) -> &[R; JOINTS] {
        &self.sv
    }

    /// r = G(t_v), the same for every duration.
    pub fn r(&self) -> R {
        self.g.g(R::lit(MAIN_REF_T * 0.5))
    }

    /// Every joint's angle and derivatives at t; at t_v the left limits, at
    /// and after tₛ exactly the target at rest.
    pub fn samples(&self, t: R) -> [Sample<R>; JOINTS] {
        if self.ts <= t {
            return self.target.map(Sample::at_rest);
        }
        let (kv, k) = (R::lit(VIA_REF_T) * R::TWO / self.ts, R::lit(MAIN_REF_T) / self.ts);
        let scale = |d: Sample<R>, k: R| Sample { s: d.s, v: d.v * k, acc: d.acc * k * k, jerk: d.jerk * k * k * k };
        let dv = scale(self.gv.g_derivs(t * kv), kv);
        let dg = scale(self.g.g_derivs(t * k), k);
        let mut out = self.start.map(Sample::at_rest);
        for (j, o) in out.iter_mut().enumerate() {
            let (wv, w) = (self.sv[j] - self.start[j], self.target[j] - self.sv[j]);
            *o = Sample {
                s: self.start[j] + wv * dv.s + w * dg.s,
                v: wv * dv.v + w * dg.v,
                acc: wv * dv.acc + w * dg.acc,
                jerk: wv * dv.jerk + w * dg.jerk,
            };
        }
        out
    }

    /// Joint angles at time t.
    pub fn positions(&self, t: R) -> [R; JOINTS] {
        self.samples(t).map(|s| s.s)
    }

    /// Joint angles at time t from both shapes' G alone (the via frame: no
    /// derivatives); [`LiftPlan::positions`]' values.
    pub fn angles(&self, t: R) -> [R; JOINTS] {
        if self.ts <= t {
            return self.target;
        }
        let (kv, k) = (R::lit(VIA_REF_T) * R::TWO / self.ts, R::lit(MAIN_REF_T) / self.ts);
        let (gv, g) = (self.gv.g(t * kv), self.g.g(t * k));
        let mut out = self.start;
        for (j, o) in out.iter_mut().enumerate() {
            *o = self.start[j] + (self.sv[j] - self.start[j]) * gv + (self.target[j] - self.sv[j]) * g;
        }
        out
    }

    /// The pose the move starts from at rest, rad.
    #[inline]
    pub fn start(&self) -> &[R; JOINTS] {
        &self.start
    }

    /// The target, rad.
    #[inline]
    pub fn target(&self) -> &[R; JOINTS] {
        &self.target
    }
}
