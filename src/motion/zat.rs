//! The ζ-a-tₛ distribution function (method.md §7) in its normalized form
//! S(t) = q0 + Δ·G(t), evaluated with method.md's cancellation-free recipe so that
//! f32 on the chip stays within a few 1e-7 of the exact profile.
//!
//! [`Shape`] holds everything that depends only on (tₛ, a, n). All joints of a
//! move share one shape, so G is computed once per frame and each joint costs a
//! single multiply-add.
//!
//! Two refinements of method.md's recipe keep f32 within its 4e-7 claim (measured
//! against an independent f64 reference over tₛ ∈ [0.2, 10], n ∈ [1.1, 100]
//! for every monotone shape, worst 3.5e-7; forming δ plainly measured 1.8e-6,
//! forming the exponent from tₛ/t measured 5.4e-7):
//! δ = u_min − a is formed once per plan with √tₛ carried to double working
//! precision (δ's rounding is amplified by q in every sample), and the
//! exponent L·(1 − tₛ/t) is formed as −L·(tₛ − t)/t, exact near the end.

use crate::math::real::Real;
use crate::motion::{all_finite, Sample, TrajError};

/// Past this value of L·(tₛ/t − 1) the factor n^(1 − tₛ/t) is below 1e-34, so G
/// is returned as 0 without touching expm1 (whose argument would be huge).
const EARLY_OUT: f64 = 80.0;

/// Newton steps for the overshoot peak; the iteration converges monotonically
/// and quadratically, so this cap is never reached for representable inputs.
const PEAK_NEWTON_CAP: u8 = 60;

/// Shape parameters shared by all joints of a move.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapeParams<R> {
    /// Duration tₛ > 0.
    pub ts: R,
    /// Shape parameter, a < u_min(tₛ).
    pub a: R,
    /// Base n > 1.
    pub n: R,
}

/// ln 2 as `math::exp::ln(2.0)` gives it, to the bit (tested): the app's base.
const LN_2_F32: f32 = core::f32::consts::LN_2;

/// Whether `R` is the chip's f32 (decided at compile time; the other `Real`
/// is f64).
#[inline(always)]
fn is_f32<R: Real>() -> bool {
    R::EPSILON.to_f64() > 1e-10
}

/// L = ln n; for n = 2 on f32 (the app's base) a constant instead of a
/// logarithm, the same value to the bit.
#[inline(always)]
fn ln_base<R: Real>(n: R) -> R {
    if is_f32::<R>() && n.to_f32().to_bits() == 2.0f32.to_bits() {
        R::from_f32(LN_2_F32)
    } else {
        n.ln()
    }
}

/// t* = (1 + √(1 + L²·tₛ))/L, where the monotonicity margin φ of
/// [`Shape::monotone_margin`] is smallest on [√tₛ, ∞) (and where G′ dips on a
/// long move), for L = ln n.
#[inline]
pub fn t_star<R: Real>(ts: R, l: R) -> R {
    (R::ONE + (R::ONE + l * l * ts).sqrt()) / l
}

/// Minimum of u(t) = t + tₛ/t − 1 over (0, tₛ]: the bound a must stay below.
#[inline]
pub fn u_min<R: Real>(ts: R) -> R {
    if ts >= R::ONE {
        ts.sqrt().twice() - R::ONE
    } else {
        ts
    }
}

/// Splits the exact square of `s` into `s·s + err` (Dekker): the working
/// precision's splitter 2^⌈p/2⌉ + 1 makes each half's products exact.
#[inline]
fn square_err<R: Real>(s: R) -> (R, R) {
    let splitter = if is_f32::<R>() { R::lit(4097.0) } else { R::lit(134_217_729.0) };
    let c = splitter * s;
    let hi = c - (c - s);
    let lo = s - hi;
    let p = s * s;
    let err = ((hi * hi - p) + R::TWO * hi * lo) + lo * lo;
    (p, err)
}

/// √tₛ as a rounded value plus a correction (√tₛ ≈ s + c to about twice the
/// working precision). f32 (the chip) takes the residual tₛ − s² from the
/// integer square of s's mantissa ([`crate::math::sqrt_split::sqrt_split`]); wider
/// types split s by Dekker's method.
#[inline]
fn sqrt_split<R: Real>(ts: R) -> (R, R) {
    if is_f32::<R>() {
        let (s, c) = crate::math::sqrt_split::sqrt_split(ts.to_f32());
        return (R::from_f32(s), R::from_f32(c));
    }
    let s = ts.sqrt();
    let (p, err) = square_err(s);
    // tₛ − p is exact (Sterbenz), so only the last step rounds.
    let r = (ts - p) - err;
    (s, r / (R::TWO * s))
}

/// (u_min, δ) = (2s − 1, (2√tₛ − 1) − a) for tₛ ≥ 1 from √tₛ ≈ s + c:
/// 2s − 1 is exact (s ≥ 1) and equals [`u_min`]'s, and where δ is small
/// u_min − a is exact too (Sterbenz), so δ is good to about one ulp of itself.
#[inline(always)]
fn long_bounds<R: Real>(s: R, c: R, a: R) -> (R, R) {
    let um = s.twice() - R::ONE;
    (um, (um - a) + c.twice())
}

/// δ = u_min(tₛ) − a, the distance to the pole, accurate to about an ulp of
/// δ itself (not of u_min): every per-sample w = u − a inherits this error
/// amplified by q, so it is worth computing once carefully.
/// `a` is admissible exactly when this is > 0.
pub fn pole_margin<R: Real>(ts: R, a: R) -> R {
    if ts >= R::ONE {
        let (s, c) = sqrt_split(ts);
        long_bounds(s, c, a).1
    } else {
        ts - a
    }
}

/// The "smooth stop" shape a* = tₛ − log_n tₛ, the only a with G′(tₛ⁻) = 0.
/// `None` when it is not admissible (tₛ ≤ 1, or ln n ≥ ln tₛ/(√tₛ − 1)²).
pub fn smooth_stop_a<R: Real>(ts: R, n: R) -> Option<R> {
    if !(ts.is_finite() && n.is_finite() && R::ONE.lt_cold(ts) && R::ONE.lt_cold(n)) {
        return None;
    }
    let a = ts - ts.ln() / ln_base(n);
    if !a.is_finite() {
        return None;
    }
    // The same tests as Shape::new, so every a returned here is accepted there.
    let (s, c) = sqrt_split(ts);
    let (um, delta) = long_bounds(s, c, a);
    if a.lt_cold(um) && delta.is_positive() {
        Some(a)
    } else {
        None
    }
}

/// Parameters of one ζ-a-tₛ move q0 → S_f.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ZatParams<R> {
    /// Start value.
    pub q0: R,
    /// End value S_f.
    pub sf: R,
    /// Duration tₛ > 0, s.
    pub ts: R,
    /// Shape parameter, a < u_min(tₛ).
    pub a: R,
    /// Base n > 1.
    pub n: R,
}

impl<R: Real> ZatParams<R> {
    /// The (tₛ, a, n) part, shared by all joints of a move.
    #[inline]
    pub fn shape(&self) -> ShapeParams<R> {
        ShapeParams { ts: self.ts, a: self.a, n: self.n }
    }
}

/// The papers' ζ = tₛ − log_n(|S_f − q0|·(n^tₛ − n^a)), computed as
/// −(ln|Δ| + ln(1 − n^(a − tₛ)))/ln n so that n^tₛ never overflows.
/// `None` when S_f = q0 (ζ = ∞) or the value is undefined (n ≤ 1, a ≥ tₛ,
/// non-finite inputs).
///
/// ```
/// use touch_arm::motion::zat::{zeta, ZatParams};
///
/// // tₛ = 4, a = 0, n = 2 and a move of 1/15: |Δ|·(n^tₛ − n^a) = 15/15 = 1, ζ = tₛ.
/// let p = ZatParams { q0: 0.0_f64, sf: 1.0 / 15.0, ts: 4.0, a: 0.0, n: 2.0 };
/// assert!((zeta(&p).unwrap() - 4.0).abs() < 1e-14);
/// // A move of 1: ζ = 4 − log₂ 15.
/// assert!((zeta(&ZatParams { sf: 1.0, ..p }).unwrap() - (4.0 - 15f64.log2())).abs() < 1e-14);
/// // No move, ζ = ∞.
/// assert_eq!(zeta(&ZatParams { sf: 0.0, ..p }), None);
/// ```
pub fn zeta<R: Real>(p: &ZatParams<R>) -> Option<R> {
    if all_finite(&[p.q0, p.sf, p.ts, p.a, p.n]).is_err() || p.n <= R::ONE || p.a >= p.ts {
        return None;
    }
    let d = (p.sf - p.q0).abs();
    if d == R::ZERO {
        return None;
    }
    let l = ln_base(p.n);
    zeta_from(l, end_e(l, p.ts - p.a).1, d)
}

/// ζ = −ln(|Δ|·(1 − n^(a − tₛ)))/L from L and 1 − n^(a − tₛ), the shape's
/// [`end_e`]`.1`: one formula for [`zeta`] and [`Shape::zeta`], so they agree
/// to the bit. One logarithm of the product (its rounding costs ε absolute in
/// the logarithm, less than a second logarithm would); two where the product
/// could be subnormal.
#[inline]
fn zeta_from<R: Real>(l: R, one_minus: R, d: R) -> Option<R> {
    let prod = d * one_minus;
    // Only d = ∞ in `zeta` can make prod NaN, which the finiteness test
    // catches either way.
    let ln_sum = if !prod.lt_cold(R::EPSILON) && prod.is_finite() { prod.ln() } else { d.ln() + one_minus.ln() };
    let z = -ln_sum / l;
    if z.is_finite() {
        Some(z)
    } else {
        None
    }
}

/// (E, 1/(1 + Q_s)) for L·(tₛ − a) = `l·ts_a`, with E = expm1(L·(tₛ − a))
/// = 1/Q_s and 1/(1 + Q_s) = E/(1 + E) = 1 − n^(a − tₛ): one division, no
/// cancellation for a near tₛ either.
#[inline(always)]
fn end_e<R: Real>(l: R, ts_a: R) -> (R, R) {
    let e = (l * ts_a).expm1();
    // E = ∞ (L·(tₛ − a) > 88 in f32): Q_s = 0 and 1 − n^(a − tₛ) = 1.
    let one_minus = if e.is_finite() { e / (R::ONE + e) } else { R::ONE };
    (e, one_minus)
}

/// Whether a shape is known to be monotone (decided where it came free).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Mono {
    Unknown,
    Yes,
    No,
}

/// A validated ζ-a-tₛ shape with its per-plan constants. Kept small: plans
/// copy it around (a byte costs about seven cycles to copy on the AVR).
/// Equality ignores how much is known about monotonicity (a cache).
#[derive(Debug, Clone, Copy)]
pub struct Shape<R> {
    ts: R,
    a: R,
    n: R,
    /// L = ln n.
    l: R,
    /// √tₛ ≈ sqrt_ts + sqrt_corr.
    sqrt_ts: R,
    sqrt_corr: R,
    /// L·δ, δ = u_min − a > 0 the distance to the pole.
    l_delta: R,
    /// tₛ ≥ 1 (which form of u − a applies), decided once.
    long: bool,
    /// E = expm1(L·(tₛ − a)) = 1/Q_s, Q_s = q(tₛ) (formed where needed:
    /// only at t = tₛ).
    e_s: R,
    /// 1/(1 + Q_s) = 1 − n^(a − tₛ).
    inv_ps: R,
    mono: Mono,
}

impl<R: PartialEq> PartialEq for Shape<R> {
    fn eq(&self, o: &Self) -> bool {
        self.ts == o.ts
            && self.a == o.a
            && self.n == o.n
            && self.l == o.l
            && self.sqrt_ts == o.sqrt_ts
            && self.sqrt_corr == o.sqrt_corr
            && self.l_delta == o.l_delta
            && self.long == o.long
            && self.e_s == o.e_s
            && self.inv_ps == o.inv_ps
    }
}

/// What G looks like at one instant inside (0, tₛ].
struct Inner<R> {
    g: R,
    q: R,
    /// 1 + q.
    p: R,
    t: R,
    /// t − √tₛ.
    d: R,
    inv_t: R,
    /// L/t.
    l_it: R,
}

impl<R: Real> Shape<R> {
    /// Validates (tₛ > 0, n > 1, all finite, a < u_min) and precomputes:
    /// one square root, one logarithm (none for n = 2 on f32), one expm1
    /// and one division.
    pub fn new(p: &ShapeParams<R>) -> Result<Self, TrajError<R>> {
        if !(p.ts.is_finite() && p.a.is_finite() && p.n.is_finite()) {
            return Err(TrajError::NotFinite);
        }
        Self::from_finite(p, None)
    }

    /// [`Shape::new`] for parameters already known to be finite, built in
    /// the caller (no copy of the result); `l` = ln n when the caller has it.
    #[inline(always)]
    pub(crate) fn from_finite(p: &ShapeParams<R>, l: Option<R>) -> Result<Self, TrajError<R>> {
        if !p.ts.is_positive() {
            return Err(TrajError::NonPositiveDuration);
        }
        if !R::ONE.lt_cold(p.n) {
            return Err(TrajError::BaseNotAboveOne);
        }
        let l = match l {
            Some(l) => l,
            None => ln_base(p.n),
        };
        Self::build(p, l, Mono::Unknown)
    }

    /// The smooth-stop shape: a = a* = tₛ − log_n tₛ ([`smooth_stop_a`]),
    /// the same shape as [`Shape::new`] with that a, bit for bit. The plan
    /// path: ln tₛ, ln n and √tₛ are formed once for a*, the shape and its
    /// monotonicity, which is decided here (the check a plan makes is then
    /// free). Not admissible (tₛ ≤ 1, or n too large for tₛ):
    /// `ShapeNotAdmissible`.
    pub fn smooth_stop(ts: R, n: R) -> Result<Self, TrajError<R>> {
        Self::check_basics(ts, n)?;
        let (ln_ts, l) = (ts.ln(), ln_base(n));
        let a = ts - ln_ts / l;
        if !a.is_finite() {
            return Err(TrajError::NotFinite);
        }
        let p = ShapeParams { ts, a, n };
        // Where min φ is φ(tₛ) (L·(tₛ − 1) ≤ 2), a* makes φ(tₛ) = 0 exactly;
        // computed, |φ(tₛ)| ≤ 2ε·L·(tₛ + |a|) (three roundings of ln tₛ/L, one
        // of a, one of L·(tₛ − a)), an eighth of `margin_tol`: monotone,
        // as `monotone_margin` finds, without forming it.
        if !R::TWO.lt_cold(l * (ts - R::ONE)) {
            return Self::build(&p, l, Mono::Yes);
        }
        let s = Self::build(&p, l, Mono::Unknown)?;
        let mono = match s.margin_with(ln_ts) {
            Some(m) if m < R::ZERO && m < -s.margin_tol() => Mono::No,
            _ => Mono::Yes,
        };
        Ok(Shape { mono, ..s })
    }

    /// ts, n finite, ts > 0, n > 1 (in that order of refusal).
    #[inline(always)]
    fn check_basics(ts: R, n: R) -> Result<(), TrajError<R>> {
        if !(ts.is_finite() && n.is_finite()) {
            return Err(TrajError::NotFinite);
        }
        if !ts.is_positive() {
            return Err(TrajError::NonPositiveDuration);
        }
        if !R::ONE.lt_cold(n) {
            return Err(TrajError::BaseNotAboveOne);
        }
        Ok(())
    }

    /// Whether this shape's base is `n` (then ln n = [`Shape::ln_n`]).
    #[inline(always)]
    pub(crate) fn has_base(&self, n: R) -> bool {
        self.n.eq_num(n)
    }

    /// Admissibility and the per-plan constants, given L = ln n. Inlined so
    /// the shape is built in place (a copy is a library call on the AVR).
    ///
    /// Comparisons are the bit tests of [`Real`] (`lt_num`, `is_positive`):
    /// every operand here is finite or ±∞ (inputs finite), never NaN.
    #[inline(always)]
    fn build(p: &ShapeParams<R>, l: R, mono: Mono) -> Result<Self, TrajError<R>> {
        let long = !p.ts.lt_cold(R::ONE);
        let (sqrt_ts, sqrt_corr) = sqrt_split(p.ts);
        let (um, delta) = if long { long_bounds(sqrt_ts, sqrt_corr, p.a) } else { (p.ts, p.ts - p.a) };
        // u_min > 0 (tₛ > 0).
        if !(p.a.lt_cold(um) && delta.is_positive()) {
            return Err(TrajError::ShapeNotAdmissible { a: p.a, u_min: um });
        }
        let l_delta = l * delta;
        let (e_s, inv_ps) = end_e(l, p.ts - p.a);
        // The largest q on (0, tₛ] is 1/expm1(L·δ), at the minimum of u, and
        // Q_s = 1/E; if they are not representable the plan sits numerically
        // on the pole. expm1 returns its argument below ε, and only there can
        // 1/· overflow, so the test needs no expm1; E ≥ L·δ (tₛ − a ≥ δ), so
        // both are fine once L·δ ≥ ε. (L > 0 follows from n > 1.)
        let on_pole = l_delta.lt_cold(R::EPSILON) && !(l_delta.recip().is_finite() && e_s.recip().is_finite());
        // L = ln n and √tₛ (both parts) are finite for finite n > 1, tₛ > 0,
        // and 1 − n^(a − tₛ) lies in [0, 1]; only L·δ can overflow.
        if on_pole || !l_delta.is_finite() {
            return Err(TrajError::NotFinite);
        }
        Ok(Shape { ts: p.ts, a: p.a, n: p.n, l, sqrt_ts, sqrt_corr, l_delta, long, e_s, inv_ps, mono })
    }

    /// The parameters it was built from.
    #[inline]
    pub fn params(&self) -> ShapeParams<R> {
        ShapeParams { ts: self.ts, a: self.a, n: self.n }
    }
    /// Duration tₛ, s.
    #[inline]
    pub fn ts(&self) -> R {
        self.ts
    }
    /// Shape parameter a.
    #[inline]
    pub fn a(&self) -> R {
        self.a
    }
    /// Base n.
    #[inline]
    pub fn n(&self) -> R {
        self.n
    }
    /// L = ln n.
    #[inline]
    pub fn ln_n(&self) -> R {
        self.l
    }
    /// u_min(tₛ), bit for bit as [`u_min`] gives it.
    #[inline]
    pub fn u_min(&self) -> R {
        if self.long {
            self.sqrt_ts.twice() - R::ONE
        } else {
            self.ts
        }
    }

    /// The papers' ζ for a move of |Δ| = `d` under this shape (`None` for
    /// d = 0); equal to [`zeta`] for the same parameters, bit for bit, at one
    /// logarithm and a division (`zeta` also forms L and 1 − n^(a − tₛ)).
    pub fn zeta(&self, d: R) -> Option<R> {
        let d = d.abs();
        if !d.is_positive() || !d.is_finite() {
            return None;
        }
        zeta_from(self.l, self.inv_ps, d)
    }
    /// t − √tₛ, accurate also where the two nearly cancel.
    #[inline]
    fn d(&self, t: R) -> R {
        (t - self.sqrt_ts) - self.sqrt_corr
    }

    /// (u(t) − a − δ)·t ≥ 0, the part of u − a that varies, formed without
    /// the cancellation of computing u first (d = t − √tₛ).
    #[inline]
    fn w_rest_t(&self, t: R, d: R) -> R {
        if self.long {
            // t − s is exact near √tₛ; the correction keeps (t − √tₛ)² accurate
            // relative to itself where it competes with a small δ.
            d * d
        } else {
            (R::ONE - t) * (self.ts - t)
        }
    }

    /// L·(u(t) − a) for t > 0.
    #[inline]
    fn l_w(&self, t: R, inv_t: R) -> R {
        self.l_delta + self.w_rest_t(t, self.d(t)) * (self.l * inv_t)
    }

    /// G and its ingredients for 0 < t < tₛ; `None` where G is below 1e-34
    /// (taken as 0). The per-frame path: one division for 1/t, one for q,
    /// one `exp`, one `expm1` and six multiplications.
    #[inline(always)]
    fn inner(&self, t: R) -> Option<Inner<R>> {
        let inv_t = t.recip();
        let l_it = self.l * inv_t;
        // L·(tₛ/t − 1) as (tₛ − t)·L/t: tₛ − t is exact near the end, where
        // forming tₛ/t first would cost up to L/2 ulp of G.
        let y = (self.ts - t) * l_it;
        // y > 0 here (0 < t < tₛ), not NaN.
        if R::lit(EARLY_OUT).lt_num(y) {
            return None;
        }
        let d = self.d(t);
        // L·w = L·δ + L·(w − δ); expm1 overflowing to ∞ gives q = 0, the
        // right limit.
        let q = (self.l_delta + self.w_rest_t(t, d) * l_it).expm1().recip();
        let p = R::ONE + q;
        let g = (-y).exp() * p * self.inv_ps;
        Some(Inner { g, q, p, t, d, inv_t, l_it })
    }

    /// G′/G = L·(1 − u′·p). L·u′ = L·(t − √tₛ)(t + √tₛ)/t² keeps u′ accurate
    /// relative to itself near t = √tₛ, where p = 1 + q is largest (near the
    /// pole): forming 1 − tₛ/t² there costs ε·L·p absolute, 2e-5 for δ = 0.01.
    /// Shared by every path that reports G′, so they agree to the bit.
    #[inline]
    fn h1(&self, i: &Inner<R>) -> R {
        let lu = i.d * (i.t + self.sqrt_ts) * (i.inv_t * i.l_it);
        self.l - lu * i.p
    }

    /// G(t): 0 for t ≤ 0, 1 (exactly) for t ≥ tₛ. The cheap per-frame path.
    ///
    /// ```
    /// use touch_arm::motion::zat::{Shape, ShapeParams};
    ///
    /// // tₛ = 4, a = 0, n = 2 at t = 2: u = t + tₛ/t − 1 = 3 and
    /// // G = n^(1 − tₛ/t) · n^(u−a)/(n^(u−a) − 1) · (n^(tₛ−a) − 1)/n^(tₛ−a)
    /// //   = 2⁻¹ · 8/7 · 15/16 = 15/28.
    /// let shape = Shape::new(&ShapeParams { ts: 4.0_f64, a: 0.0, n: 2.0 }).unwrap();
    /// assert!((shape.g(2.0) - 15.0 / 28.0).abs() < 1e-15);
    /// assert_eq!((shape.g(0.0), shape.g(4.0)), (0.0, 1.0));
    /// ```
    ///
    /// Not `#[inline]`: too large to be inlined anyway, and an inline
    /// generic is instantiated again in each crate that calls it (the
    /// firmware binary carried a second copy).
    pub fn g(&self, t: R) -> R {
        self.g_inline(t)
    }

    /// [`Shape::g`], inlined where the shape is still in registers.
    #[inline(always)]
    pub(crate) fn g_inline(&self, t: R) -> R {
        if !t.is_positive() {
            R::ZERO
        } else if !t.lt_num(self.ts) {
            R::ONE
        } else {
            match self.inner(t) {
                Some(i) => i.g,
                None => R::ZERO,
            }
        }
    }

    /// G and G′ together (three multiplications and two subtractions more
    /// than [`Shape::g`]). At t = tₛ G′ is the left limit; beyond tₛ it is 0.
    pub fn g_rate(&self, t: R) -> (R, R) {
        if !t.is_positive() {
            return (R::ZERO, R::ZERO);
        }
        let i = if !t.lt_num(self.ts) {
            if self.ts.lt_num(t) {
                return (R::ONE, R::ZERO);
            }
            self.end()
        } else {
            match self.inner(t) {
                Some(i) => i,
                None => return (R::ZERO, R::ZERO),
            }
        };
        (i.g, i.g * self.h1(&i))
    }

    /// The state at t = tₛ: G = 1 and q = Q_s exactly, so derivatives there
    /// are the left limits, consistent with [`Shape::end_rate`].
    #[inline]
    fn end(&self) -> Inner<R> {
        let q_s = self.e_s.recip();
        let inv_t = self.ts.recip();
        Inner { g: R::ONE, q: q_s, p: R::ONE + q_s, t: self.ts, d: self.d(self.ts), inv_t, l_it: self.l * inv_t }
    }

    /// Like `inner`, but t = tₛ gives [`Shape::end`].
    #[inline]
    fn at(&self, t: R) -> Option<Inner<R>> {
        if t >= self.ts {
            Some(self.end())
        } else {
            self.inner(t)
        }
    }

    /// G, G′, G″, G‴ (in the `s, v, acc, jerk` fields). t ≤ 0 and t > tₛ give
    /// zero derivatives; at t = tₛ they are the left limits.
    pub fn g_derivs(&self, t: R) -> Sample<R> {
        if t <= R::ZERO || t > self.ts {
            return Sample::at_rest(self.g(t));
        }
        let Some(r) = self.rate_terms(t) else {
            return Sample::at_rest(R::ZERO);
        };
        let (g, h1, h2) = (r.g, r.h1, r.h2);
        Sample { s: g, v: g * h1, acc: g * (h1 * h1 + h2), jerk: g * (h1 * (h1 * h1 + R::lit(3.0) * h2) + r.h3) }
    }

    /// G′(tₛ⁻) = L·[1 − (1 − 1/tₛ)(1 + Q_s)]; the end velocity is Δ times this.
    pub fn end_rate(&self) -> R {
        self.h1(&self.end())
    }

    /// φ(t) = L·(u(t) − a) − ln(t²/tₛ) (`ln_ts` = ln tₛ). On t > √tₛ,
    /// G′(t) ≥ 0 ⇔ φ(t) ≥ 0 (from G′ = G·L·(1 − u′·(1 + q)) and
    /// 1 + q = 1/(1 − e^(−L·w))).
    #[inline]
    fn phi(&self, t: R, ln_ts: R) -> R {
        self.phi_it(t, t.recip(), ln_ts)
    }

    /// φ(t) given 1/t.
    #[inline]
    fn phi_it(&self, t: R, inv_t: R, ln_ts: R) -> R {
        self.l_w(t, inv_t) - (R::TWO * t.ln() - ln_ts)
    }

    /// min of φ over [√tₛ, tₛ]: ≥ 0 exactly when G is monotone. `None` for
    /// tₛ ≤ 1, where u′ ≤ 0 on the whole motion and G is always monotone.
    ///
    /// φ″ = 2L·tₛ/t³ + 2/t² > 0, so φ is convex; its unconstrained minimum is at
    /// t* = (1 + √(1 + L²·tₛ))/L > √tₛ, and the constrained one at min(t*, tₛ).
    /// t* ≥ tₛ ⇔ L·(tₛ − 1) ≤ 2 (square 1 + √(1 + L²tₛ) ≥ L·tₛ), which needs
    /// neither the root nor a division; there φ(tₛ) = L·(tₛ − a) − ln tₛ.
    pub fn monotone_margin(&self) -> Option<R> {
        self.margin_with(self.ts.ln())
    }

    /// [`Shape::monotone_margin`] given ln tₛ.
    fn margin_with(&self, ln_ts: R) -> Option<R> {
        if self.ts <= R::ONE {
            return None;
        }
        let l = self.l;
        if l * (self.ts - R::ONE) <= R::TWO {
            Some(l * (self.ts - self.a) - ln_ts)
        } else {
            Some(self.phi(t_star(self.ts, l).min(self.ts), ln_ts))
        }
    }

    /// Rounding allowance for the sign test on φ: a* computed in the working
    /// precision must count as monotone. A φ this small changes G by far
    /// less than the evaluation error.
    #[inline]
    fn margin_tol(&self) -> R {
        R::lit(16.0) * R::EPSILON * (R::ONE + self.l * (self.ts + self.a.abs()))
    }

    /// G stays in [0, 1] and never decreases on (0, tₛ].
    pub fn is_monotone(&self) -> bool {
        match self.mono {
            Mono::Yes => return true,
            Mono::No => return false,
            Mono::Unknown => {}
        }
        match self.monotone_margin() {
            None => true,
            Some(m) => m >= -self.margin_tol(),
        }
    }

    /// max of G over (0, tₛ]: 1 for a monotone shape, else G at the first zero
    /// of G′ (found by Newton on the convex φ from √tₛ, which approaches the
    /// root from the left without overshooting).
    pub fn peak(&self) -> R {
        if self.is_monotone() {
            return R::ONE;
        }
        let l = self.l;
        let ln_ts = self.ts.ln();
        let mut t = self.sqrt_ts;
        let mut k = 0;
        while k < PEAK_NEWTON_CAP {
            let it = t.recip();
            let f = self.phi_it(t, it, ln_ts);
            let df = l * (R::ONE - self.ts * it * it) - R::TWO * it;
            if !f.is_positive() || !df.is_negative() {
                break;
            }
            let next = t - f / df;
            if next <= t || !next.is_finite() {
                break;
            }
            t = next.min(self.ts);
            k += 1;
        }
        self.g(t).max(R::ONE)
    }

    /// `Err(Overshoot { peak })` unless [`Shape::is_monotone`].
    pub fn check_monotone(&self) -> Result<(), TrajError<R>> {
        if self.is_monotone() {
            Ok(())
        } else {
            Err(TrajError::Overshoot { peak: self.peak() })
        }
    }

    /// G, q and h1 = G′/G with h1′, h1″ at 0 < t ≤ tₛ (left limits at tₛ),
    /// so G″ = G·(h1² + h1′): [`Shape::g_derivs`] and searches over G′ use
    /// them. `None` for t ≤ 0, t > tₛ and where G is below 1e-34.
    pub fn rate_terms(&self, t: R) -> Option<RateTerms<R>> {
        if !t.is_positive() || t > self.ts {
            return None;
        }
        let i = self.at(t)?;
        let l = self.l;
        let (q, p, it) = (i.q, i.p, i.inv_t);
        let x_t = self.ts * it * it; // tₛ/t²
        let up = R::ONE - x_t;
        let upp = R::TWO * x_t * it;
        let uppp = -R::lit(3.0) * upp * it;
        let pp = -l * up * p * q;
        let ppp = -l * (upp * p * q + up * pp * (R::TWO * p - R::ONE));
        Some(RateTerms {
            g: i.g,
            q,
            h1: self.h1(&i),
            h2: -l * (upp * p + up * pp),
            h3: -l * (uppp * p + R::TWO * upp * pp + up * ppp),
        })
    }

    /// Q_s = q(tₛ) = 1/expm1(L·(tₛ − a)).
    #[inline]
    pub fn end_q(&self) -> R {
        self.e_s.recip()
    }
}

/// See [`Shape::rate_terms`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RateTerms<R> {
    /// G(t), 0..=1.
    pub g: R,
    /// q(t) = 1/expm1(L·(u(t) − a)) with u(t) = t + tₛ/t − 1.
    pub q: R,
    /// G′/G.
    pub h1: R,
    /// h1′.
    pub h2: R,
    /// h1″.
    pub h3: R,
}

/// One ζ-a-tₛ move q0 → S_f: S(t) = q0 + Δ·G(t).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ZatPlan<R> {
    shape: Shape<R>,
    q0: R,
    sf: R,
    delta: R,
}

impl<R: Real> ZatPlan<R> {
    /// Validates the shape (admissibility only: a non-monotone plan is
    /// accepted here so it can be studied; see [`Shape::check_monotone`]).
    pub fn new(p: &ZatParams<R>) -> Result<Self, TrajError<R>> {
        all_finite(&[p.q0, p.sf])?;
        let shape = Shape::new(&p.shape())?;
        let delta = p.sf - p.q0;
        if !delta.is_finite() {
            return Err(TrajError::NotFinite);
        }
        Ok(ZatPlan { shape, q0: p.q0, sf: p.sf, delta })
    }

    /// The normalized profile G.
    #[inline]
    pub fn shape(&self) -> &Shape<R> {
        &self.shape
    }
    /// Start value.
    #[inline]
    pub fn q0(&self) -> R {
        self.q0
    }
    /// End value S_f.
    #[inline]
    pub fn sf(&self) -> R {
        self.sf
    }
    /// Δ = S_f − q0.
    #[inline]
    pub fn delta(&self) -> R {
        self.delta
    }

    /// S(t); exactly q0 for t ≤ 0 and exactly S_f for t ≥ tₛ.
    pub fn position(&self, t: R) -> R {
        if t >= self.shape.ts {
            self.sf
        } else if t <= R::ZERO {
            self.q0
        } else {
            self.q0 + self.delta * self.shape.g(t)
        }
    }

    /// S, S′, S″, S‴ (Δ·G⁽ᵏ⁾), with method.md's conventions at 0 and tₛ.
    pub fn sample(&self, t: R) -> Sample<R> {
        let g = self.shape.g_derivs(t);
        Sample { s: self.position(t), v: self.delta * g.v, acc: self.delta * g.acc, jerk: self.delta * g.jerk }
    }

    /// S′(tₛ⁻): nonzero unless a = a* (the motion ends with a velocity step).
    #[inline]
    pub fn end_velocity(&self) -> R {
        self.delta * self.shape.end_rate()
    }

    /// The papers' ζ; `None` for S_f = q0 (ζ = ∞).
    pub fn zeta(&self) -> Option<R> {
        self.shape.zeta(self.delta)
    }
}
