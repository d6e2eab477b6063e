//! Via-point trajectory (method.md §8): one signed form
//! S(t) = q0 + (S_v − q0)·Gv(t) + (S_f − S_v)·G(t), where Gv is the ζ-a-tₛ shape
//! over (t_v, a_v, n_v) (≡ 1 after t_v) and G the one over (tₛ, a, n).
//!
//! S_v is chosen so that S(t_v) = θ_v. Since S(t_v) = S_v + r·(S_f − S_v) with
//! r = G(t_v), that is linear in S_v and solved in closed form; the paper's
//! fixed-point iteration is kept for reproduction and converges only if r < 1.

use core::fmt;

use crate::math::real::Real;
use crate::motion::zat::{smooth_stop_a, Shape, ShapeParams};
use crate::motion::{all_finite, Sample, TrajError};

/// A via-point move q0 → (θ_v at t_v) → S_f.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViaParams<R> {
    /// Start value.
    pub q0: R,
    /// The value the trajectory must pass through at t_v.
    pub theta_v: R,
    /// End value S_f.
    pub sf: R,
    /// Via time, in (0, tₛ).
    pub tv: R,
    /// Duration of the whole move tₛ, s.
    pub ts: R,
    /// Shape parameter of the main term G.
    pub a: R,
    /// Base of the main term G, > 1.
    pub n: R,
    /// Shape and base of the via segment Gv.
    pub av: R,
    /// Base of the via segment Gv, > 1.
    pub nv: R,
}

impl<R: Real> ViaParams<R> {
    /// Every parameter finite. Out of line: the plan then reads each
    /// parameter where it is used instead of holding all nine from the
    /// start (spilled on the AVR). Written out rather than through
    /// `all_finite`, whose nine-value array cost 364 cycles more here.
    #[inline(never)] // reason: register-pressure
    fn finite(&self) -> bool {
        self.q0.is_finite()
            && self.theta_v.is_finite()
            && self.sf.is_finite()
            && self.tv.is_finite()
            && self.ts.is_finite()
            && self.a.is_finite()
            && self.n.is_finite()
            && self.av.is_finite()
            && self.nv.is_finite()
    }
}

/// The a_v that makes velocity continuous at t_v (Gv′(t_v⁻) = 0):
/// a_v = t_v − log_{n_v} t_v, `None` when not admissible.
#[inline]
pub fn smooth_via_a<R: Real>(tv: R, nv: R) -> Option<R> {
    smooth_stop_a(tv, nv)
}

/// Where the via value lies relative to the end points (the paper's four
/// printed conditions).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ViaCondition {
    /// 1: q0 ≤ S_v ≤ S_f.
    Between = 1,
    /// 2: S_v above both ends (ties with the upper end of a falling move count here).
    Above = 2,
    /// 3: S_v below both ends (ties with the lower end of a falling move count here).
    Below = 3,
    /// 4: S_f < S_v < q0.
    BetweenFalling = 4,
}

impl ViaCondition {
    /// The paper's condition number 1–4.
    #[inline]
    pub fn number(self) -> u8 {
        self as u8
    }
}

/// Classifies S_v against q0 and S_f.
pub fn via_condition<R: Real>(q0: R, sv: R, sf: R) -> ViaCondition {
    if q0 <= sv && sv <= sf {
        ViaCondition::Between
    } else if sf < sv && sv < q0 {
        ViaCondition::BetweenFalling
    } else if sv >= q0.max(sf) {
        ViaCondition::Above
    } else {
        ViaCondition::Below
    }
}

/// Validates the inputs and builds (Gv, G). Inlined so the shapes are built
/// in place (a copy is a library call on the AVR).
#[inline(always)]
fn shapes<R: Real>(p: &ViaParams<R>) -> Result<(Shape<R>, Shape<R>), TrajError<R>> {
    if !p.finite() {
        return Err(TrajError::NotFinite);
    }
    let g = Shape::from_finite(&ShapeParams { ts: p.ts, a: p.a, n: p.n }, None)?;
    if !(p.tv.is_positive() && p.tv.lt_cold(p.ts)) {
        return Err(TrajError::ViaTimeOutOfRange);
    }
    // One logarithm when both segments share the base.
    let lv = if g.has_base(p.nv) { Some(g.ln_n()) } else { None };
    let gv = Shape::from_finite(&ShapeParams { ts: p.tv, a: p.av, n: p.nv }, lv)?;
    Ok((gv, g))
}

/// A via-point trajectory with a fixed S_v.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViaPlan<R> {
    gv: Shape<R>,
    g: Shape<R>,
    q0: R,
    sv: R,
    sf: R,
    /// r = G(t_v).
    r: R,
}

impl<R: Real> ViaPlan<R> {
    /// Solves S_v* = (θ_v − r·S_f)/(1 − r) so that S(t_v) = θ_v.
    /// `ViaDiverges { r }` when r = 1 (no solution).
    pub fn new(p: &ViaParams<R>) -> Result<Self, TrajError<R>> {
        let (gv, g) = shapes(p)?;
        let r = g.g_inline(p.tv);
        if !r.is_finite() {
            return Err(TrajError::NotFinite);
        }
        if r.eq_num(R::ONE) {
            return Err(TrajError::ViaDiverges { r });
        }
        let sv = (p.theta_v - r * p.sf) / (R::ONE - r);
        if !sv.is_finite() {
            return Err(TrajError::NotFinite);
        }
        Ok(ViaPlan { gv, g, q0: p.q0, sv, sf: p.sf, r })
    }

    /// The trajectory for a given S_v (θ_v is ignored).
    pub fn with_sv(p: &ViaParams<R>, sv: R) -> Result<Self, TrajError<R>> {
        let (gv, g) = shapes(p)?;
        if !sv.is_finite() {
            return Err(TrajError::NotFinite);
        }
        let r = g.g(p.tv);
        Ok(ViaPlan { gv, g, q0: p.q0, sv, sf: p.sf, r })
    }

    /// The via term's target S_v that makes S(t_v) = θ_v.
    #[inline]
    pub fn sv(&self) -> R {
        self.sv
    }
    /// r = G(t_v).
    #[inline]
    pub fn r(&self) -> R {
        self.r
    }
    /// Via time t_v, s.
    #[inline]
    pub fn tv(&self) -> R {
        self.gv.ts()
    }
    /// Duration tₛ, s.
    #[inline]
    pub fn ts(&self) -> R {
        self.g.ts()
    }
    /// Gv, the shape of the via term over (t_v, a_v, n_v).
    #[inline]
    pub fn via_shape(&self) -> &Shape<R> {
        &self.gv
    }
    /// G, the shape of the main term over (tₛ, a, n).
    #[inline]
    pub fn main_shape(&self) -> &Shape<R> {
        &self.g
    }

    /// Where S_v lies relative to q0 and S_f (the paper's conditions 1–4).
    #[inline]
    pub fn condition(&self) -> ViaCondition {
        via_condition(self.q0, self.sv, self.sf)
    }

    /// ζ of the main term: (S_v → S_f, n, a, tₛ). `None` when S_v = S_f.
    pub fn zeta(&self) -> Option<R> {
        self.g.zeta(self.sf - self.sv)
    }

    /// ζ_v of the via term: (q0 → S_v, n_v, a_v, t_v). `None` when S_v = q0.
    pub fn zeta_v(&self) -> Option<R> {
        self.gv.zeta(self.sv - self.q0)
    }

    /// S(t): q0 for t ≤ 0, exactly S_f for t ≥ tₛ.
    pub fn position(&self, t: R) -> R {
        if t <= R::ZERO {
            self.q0
        } else if t >= self.g.ts() {
            self.sf
        } else {
            self.q0 + (self.sv - self.q0) * self.gv.g(t) + (self.sf - self.sv) * self.g.g(t)
        }
    }

    /// S and its derivatives; at t_v (and tₛ) the derivatives are left limits.
    pub fn sample(&self, t: R) -> Sample<R> {
        let dv = self.gv.g_derivs(t);
        let dg = self.g.g_derivs(t);
        let (kv, kg) = (self.sv - self.q0, self.sf - self.sv);
        Sample {
            s: self.position(t),
            v: kv * dv.v + kg * dg.v,
            acc: kv * dv.acc + kg * dg.acc,
            jerk: kv * dv.jerk + kg * dg.jerk,
        }
    }

    /// Right limit minus left limit at t_v of (position, velocity, acceleration,
    /// jerk): the via term stops abruptly, so each jump is −(S_v − q0)·Gv⁽ᵏ⁾(t_v⁻).
    pub fn jumps(&self) -> Sample<R> {
        let d = self.gv.g_derivs(self.gv.ts());
        let k = -(self.sv - self.q0);
        Sample { s: R::ZERO, v: k * d.v, acc: k * d.acc, jerk: k * d.jerk }
    }

    /// Velocity step at t_v (right minus left limit), per second.
    #[inline]
    pub fn velocity_jump(&self) -> R {
        -(self.sv - self.q0) * self.gv.end_rate()
    }

    /// Acceleration step at t_v (right minus left limit), per second².
    #[inline]
    pub fn acc_jump(&self) -> R {
        self.jumps().acc
    }

    /// S′(tₛ⁻) (the via term is constant by then).
    #[inline]
    pub fn end_velocity(&self) -> R {
        (self.sf - self.sv) * self.g.end_rate()
    }
}

/// Outcome of the paper's iteration.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ViaIteration<R> {
    /// Index i of the accepted iterate (0 when θ_v itself already meets the tolerance).
    pub iterations: u16,
    /// The accepted S_v,i.
    pub sv: R,
    /// Its via error e_i = S_i(t_v) − θ_v.
    pub error: R,
    /// ζ_i and ζ_v,i of the accepted iterate (`None` = ∞).
    pub zeta: Option<R>,
    /// ζ_v,i of the accepted iterate (`None` = ∞).
    pub zeta_v: Option<R>,
}

/// The paper's feedback iteration, as method.md §8 restates it: S_v,0 = θ_v; at step
/// i compute ζ_i, ζ_v,i and e_i = S_i(t_v) − θ_v; stop at the first |e_i| < tol;
/// else S_v,i+1 = θ_v − σ_i·M_i(t_v) with the printed
/// M_i(t_v) = n^(t_v − ζ_i)/|n^(t_v + tₛ/t_v − 1) − n^a| (evaluated in log form
/// so it cannot overflow) and σ_i = +1 when S_v,i ≤ S_f, else −1.
///
/// `ViaDiverges { r }` up front when r = G(t_v) ≥ 1; `NoConvergence` when no
/// iterate within `max_iter` updates meets the tolerance.
pub fn iterate_paper<R: Real>(p: &ViaParams<R>, tol: R, max_iter: u16) -> Result<ViaIteration<R>, TrajError<R>> {
    let (gv, g) = shapes(p)?;
    all_finite(&[tol])?;
    let r = g.g(p.tv);
    if !r.is_finite() {
        return Err(TrajError::NotFinite);
    }
    if r >= R::ONE {
        return Err(TrajError::ViaDiverges { r });
    }
    let l = g.ln_n();
    let u = p.tv + p.ts / p.tv - R::ONE;
    // ln(1 − n^(a − u)), u − a > 0 by admissibility.
    let ln_den_rest = (-(-(l * (u - p.a))).expm1()).ln();
    let mut sv = p.theta_v;
    let mut i: u16 = 0;
    loop {
        // Shape::zeta is zat::zeta for these parameters, bit for bit.
        let zi = g.zeta(p.sf - sv);
        let zvi = gv.zeta(sv - p.q0);
        // S_i(t_v) with Gv(t_v) = 1.
        let s_tv = p.q0 + (sv - p.q0) + (p.sf - sv) * r;
        let e = s_tv - p.theta_v;
        if !e.is_finite() {
            return Err(TrajError::NotFinite);
        }
        if e.abs() < tol {
            return Ok(ViaIteration { iterations: i, sv, error: e, zeta: zi, zeta_v: zvi });
        }
        if i >= max_iter {
            return Err(TrajError::NoConvergence);
        }
        let m = match zi {
            Some(z) => (l * (p.tv - z - u) - ln_den_rest).exp(),
            None => R::ZERO,
        };
        let sigma = if sv <= p.sf { R::ONE } else { -R::ONE };
        sv = p.theta_v - sigma * m;
        i += 1;
    }
}

/// How smooth the via term's stop at t_v must be: the via shape Gv is the
/// only term that changes its law at t_v, so its left derivatives there are
/// the jumps of the whole trajectory (times −(S_v − q0)).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Continuity {
    /// Position only: (a_v, n_v) as given.
    C0,
    /// Velocity too: a_v = t_v − log_{n_v} t_v for the given n_v.
    C1,
    /// Velocity and acceleration: n_v = e^(2/(t_v − 1)) and its a_v.
    C2,
}

/// Why no (a_v, n_v) gives the asked continuity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ContinuityError<R> {
    /// t_v ≤ 1 s: Gv′(t_v⁻) = 0 needs n_v^(t_v − a_v) = t_v > 1 with
    /// a_v < u_min(t_v), which has no solution for t_v ≤ 1.
    ViaTooEarly {
        /// The via time given.
        tv: R,
    },
    /// The smooth stop's a_v lies past the pole for this base: C1 needs
    /// ln n_v < ln t_v/(√t_v − 1)².
    BaseTooLarge {
        /// The base given.
        nv: R,
        /// The bound it must stay below.
        max: R,
    },
    /// A non-finite input, or t_v so close to 1 that e^(2/(t_v − 1))
    /// overflows.
    NotFinite,
}

impl<R: Real> fmt::Display for ContinuityError<R> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            ContinuityError::ViaTooEarly { tv } => write!(
                f,
                "no continuous velocity at the via point: t_v = {} s, but a_v = t_v - log_nv(t_v) is admissible only for t_v > 1 s",
                tv.to_f64()
            ),
            ContinuityError::BaseTooLarge { nv, max } => write!(
                f,
                "no continuous velocity at the via point for n_v = {}: a_v = t_v - log_nv(t_v) is admissible only for n_v < {}",
                nv.to_f64(),
                max.to_f64()
            ),
            ContinuityError::NotFinite => {
                f.write_str("non-finite via parameters (or t_v so close to 1 s that n_v = e^(2/(t_v - 1)) overflows)")
            }
        }
    }
}

/// The one base that also makes the acceleration continuous at t_v:
/// with Gv′(t_v⁻) = 0, Gv″(t_v⁻) = h2 = (L/t_v)·(L − 2/(t_v − 1)) (L = ln n_v,
/// method.md §7's h2 at u′·p = 1), so L = 2/(t_v − 1). That L always lies inside
/// C1's domain ln t_v/(√t_v − 1)², since ln s > 2(s − 1)/(s + 1) for s = √t_v > 1.
#[inline]
pub fn c2_ln_base<R: Real>(tv: R) -> Option<R> {
    if !(tv.is_finite() && R::ONE.lt_cold(tv)) {
        return None;
    }
    let l = R::TWO / (tv - R::ONE);
    if l.is_finite() && l.exp().is_finite() {
        Some(l)
    } else {
        None
    }
}

/// The largest base for which C1 is admissible: e^(ln t_v/(√t_v − 1)²).
pub fn c1_max_base<R: Real>(tv: R) -> R {
    let s = tv.sqrt() - R::ONE;
    (tv.ln() / (s * s)).exp()
}

/// (a_v, n_v) for the asked continuity at t_v; `av`, `nv` are the user's
/// values (C0 keeps both, C1 keeps n_v, C2 replaces both). C0 does no checks
/// here: the plan validates the shape.
pub fn via_shape_for<R: Real>(tv: R, av: R, nv: R, c: Continuity) -> Result<(R, R), ContinuityError<R>> {
    match c {
        Continuity::C0 => Ok((av, nv)),
        Continuity::C1 => {
            if !(tv.is_finite() && nv.is_finite()) {
                return Err(ContinuityError::NotFinite);
            }
            if !R::ONE.lt_cold(tv) {
                return Err(ContinuityError::ViaTooEarly { tv });
            }
            match smooth_via_a(tv, nv) {
                Some(a) => Ok((a, nv)),
                None => Err(ContinuityError::BaseTooLarge { nv, max: c1_max_base(tv) }),
            }
        }
        Continuity::C2 => {
            if !tv.is_finite() {
                return Err(ContinuityError::NotFinite);
            }
            if !R::ONE.lt_cold(tv) {
                return Err(ContinuityError::ViaTooEarly { tv });
            }
            let nv = c2_ln_base(tv).ok_or(ContinuityError::NotFinite)?.exp();
            // Inside C1's domain by construction; a refusal here is rounding
            // at the edge of the representable bases.
            let a = smooth_via_a(tv, nv).ok_or(ContinuityError::NotFinite)?;
            Ok((a, nv))
        }
    }
}

/// Gv‴(t_v⁻) of the C2 shape, 4(t_v + 1)/(t_v²·(t_v − 1)³) (method.md §7's h3 with
/// h1 = h2 = 0): never 0, so no (a_v, n_v) of this family also makes the
/// jerk continuous; the jerk steps by −(S_v − q0) times this.
pub fn c2_via_jerk<R: Real>(tv: R) -> R {
    let d = tv - R::ONE;
    R::lit(4.0) * (tv + R::ONE) / (tv * tv * d * d * d)
}
