//! Bounds of the joints' path rates |θ′(s)| and |θ″(s)| over a whole stretch
//! [s_a, s_b] of a [`Path`] (issue #24, F4): a sampled check sees the rates
//! at its points only, and near the stretched arm or the base axis they
//! spike between them.
//!
//! Interval arithmetic on closed forms of the rates, each built from
//! quantities whose exact range over the stretch is known. With the
//! shoulder at the origin, r² = |P|² decides the elbow (cos θ₃ = (r² − l₂² −
//! l₃²)/(2l₂l₃)), so with N = P·P′ = (r²)′/2 and D = l₂l₃ sin θ₃:
//! θ₃′ = −N/D, θ₃″ = −N′/D − l₂l₃·cos θ₃·N²/D³. The shoulder is θ₂ = α − β
//! with α the wrist's direction in the arm's plane (α′ = u×u′/r², α″ =
//! u×u″/r² − 2N·u×u′/r⁴, u = (ρ, z)) and β = atan2(l₃ sin θ₃, l₂ + l₃ cos θ₃),
//! β′ = k·θ₃′, k = l₃(l₃ + l₂ cos θ₃)/r², k′ = N(1 − 2k)/r². The base is
//! θ₁′ = K/ρ², θ₁″ = −2K·(P_xy·P′_xy)/ρ⁴ (K = P_xy × P′_xy, constant on a line;
//! a circle lies in a plane through the axis: θ₁ is constant).
//! On a line r², ρ² are quadratic in s and N, P_xy·P′_xy, ρ²P′_z − z·P_xy·P′_xy
//! affine; on a circle every one is affine in cos ψ and sin ψ, ψ the angle
//! from the centre's direction: their ranges are exact. What the interval
//! operations add (each factor at its own worst point) shrinks with the
//! stretch, so a caller splits a stretch whose bound is well above its ends'.
//! Rounding is not directed: the bound holds to the arithmetic's precision.

use crate::geometry::ik::{Branch, Links};
use crate::geometry::path::Path;
use crate::math::real::Real;

/// A closed interval [lo, hi].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Iv<R> {
    /// Lower end.
    pub lo: R,
    /// Upper end.
    pub hi: R,
}

impl<R: Real> Iv<R> {
    /// The interval between `a` and `b` (either order).
    #[inline(never)] // reason: code-size
    pub fn of(a: R, b: R) -> Self {
        if a.is_finite() && b.is_finite() {
            // What min and max give, by `lt_num` (on the AVR a test of the
            // bits, where a float comparison is a library call).
            if b.lt_num(a) {
                Iv { lo: b, hi: a }
            } else if a.lt_num(b) {
                Iv { lo: a, hi: b }
            } else {
                Iv { lo: a, hi: a }
            }
        } else {
            Iv { lo: a.min(b), hi: a.max(b) }
        }
    }
    /// The point `a`.
    pub fn pt(a: R) -> Self {
        Iv { lo: a, hi: a }
    }
    /// The sum.
    pub fn plus(self, o: Self) -> Self {
        Iv { lo: self.lo + o.lo, hi: self.hi + o.hi }
    }
    /// The difference.
    pub fn minus(self, o: Self) -> Self {
        Iv { lo: self.lo - o.hi, hi: self.hi - o.lo }
    }
    /// Times the number `k`.
    pub fn scale(self, k: R) -> Self {
        Iv::of(self.lo * k, self.hi * k)
    }
    /// The product.
    pub fn times(self, o: Self) -> Self {
        let (a, b) = (Iv::of(self.lo * o.lo, self.lo * o.hi), Iv::of(self.hi * o.lo, self.hi * o.hi));
        Iv { lo: a.lo.min(b.lo), hi: a.hi.max(b.hi) }
    }
    /// The square (0 at least when it spans 0).
    pub fn sqr(self) -> Self {
        let (a, b) = (self.lo * self.lo, self.hi * self.hi);
        if self.lo.is_negative() && !self.hi.is_negative() {
            Iv { lo: R::ZERO, hi: a.max(b) }
        } else {
            Iv::of(a, b)
        }
    }
    /// 1/x for an interval of positive numbers (an infinite bound when it
    /// reaches 0: the caller splits or refuses).
    pub fn recip_pos(self) -> Self {
        Iv { lo: self.hi.recip(), hi: self.lo.recip() }
    }
    /// Both ends finite (not NaN either).
    #[inline(never)] // reason: code-size
    pub fn is_finite(&self) -> bool {
        self.lo.is_finite() && self.hi.is_finite()
    }
    /// The largest |x|.
    pub fn mag(self) -> R {
        self.lo.abs().max(self.hi.abs())
    }
}

/// The range of c0 + c1·s + c2·s² over [sa, sb].
#[inline(never)] // reason: code-size
fn quad<R: Real>(c: &[R; 3], sa: R, sb: R) -> Iv<R> {
    let f = |s: R| c[0] + (c[1] + c[2] * s) * s;
    let mut iv = Iv::of(f(sa), f(sb));
    if !c[2].is_zero() {
        let v = -c[1] / c[2].twice();
        if sa < v && v < sb {
            let fv = f(v);
            iv = Iv { lo: iv.lo.min(fv), hi: iv.hi.max(fv) };
        }
    }
    iv
}

/// The planar quantities of a stretch, as ranges.
struct Planar<R> {
    /// r² = |P|².
    r2: Iv<R>,
    /// N = P·P′.
    n: Iv<R>,
    /// N′ = |P′|² + P·P″.
    dn: Iv<R>,
    /// u×u′ = ρz′ − zρ′ (u = (ρ, z)).
    x1: Iv<R>,
    /// u×u″.
    x2: Iv<R>,
    /// θ₁′ and θ₁″.
    b1: Iv<R>,
    b2: Iv<R>,
}

#[inline(never)] // reason: code-size
fn line<R: Real>(from: &[R; 3], d: &[R; 3], sa: R, sb: R) -> Option<Planar<R>> {
    let dot = |a: &[R; 3], b: &[R; 3], n: usize| {
        let mut acc = R::ZERO;
        for i in 0..n {
            acc += a[i] * b[i];
        }
        acc
    };
    let (a0, a1, a2) = (dot(from, from, 2), dot(from, d, 2), dot(d, d, 2));
    let k = from[0] * d[1] - from[1] * d[0];
    // ρ² and P_xy·P′_xy from the stretch's own ends, not from the quadratic
    // a0 + 2a1·s + a2·s²: next to the base axis that is a difference of
    // nearly equal terms, and in f32 its rounding (ε·a0) reached the size of
    // ρ² itself (a line 6e-4 from the axis: the base's rate bound 31 % low,
    // tests/path_bound.rs). The minimum inside is K²/a2, the line's distance
    // from the axis, squared.
    let xy = |s: R| [from[0] + d[0] * s, from[1] + d[1] * s];
    let (pa, pb) = (xy(sa), xy(sb));
    let (ra, rb) = (pa[0] * pa[0] + pa[1] * pa[1], pb[0] * pb[0] + pb[1] * pb[1]);
    let (ga, gb) = (pa[0] * d[0] + pa[1] * d[1], pb[0] * d[0] + pb[1] * d[1]);
    let mut rho2 = Iv::of(ra, rb);
    if a2.is_positive() {
        let v = -a1 / a2;
        if sa < v && v < sb {
            rho2.lo = rho2.lo.min(k * k / a2);
        }
    }
    if !rho2.lo.is_positive() {
        return None;
    }
    let (z0, dz) = (from[2], d[2]);
    let aff = |c0: R, c1: R| Iv::of(c0 + c1 * sa, c0 + c1 * sb);
    let rho = Iv { lo: rho2.lo.sqrt(), hi: rho2.hi.sqrt() };
    let inv_rho = rho.recip_pos();
    let inv_rho2 = rho2.recip_pos();
    let (za, zb) = (z0 + dz * sa, z0 + dz * sb);
    // Each range formed where it is stored: few of them live at once (a
    // frame within the AVR's 63-byte reach of Y).
    Some(Planar {
        r2: quad(&[a0 + z0 * z0, (a1 + z0 * dz).twice(), a2 + dz * dz], sa, sb),
        n: aff(a1 + z0 * dz, a2 + dz * dz),
        dn: Iv::pt(a2 + dz * dz),
        // ρ²·z′ − z·(P_xy·P′_xy): affine in s (its s² terms cancel), so its
        // ends give its range.
        x1: Iv::of(ra * dz - za * ga, rb * dz - zb * gb).times(inv_rho),
        // u″ = (ρ″, 0), ρ″ = K²/ρ³.
        x2: Iv::of(za, zb).times(inv_rho2.times(inv_rho)).scale(-(k * k)),
        b1: inv_rho2.scale(k),
        // P_xy·P′_xy.
        b2: Iv::of(ga, gb).times(inv_rho2.sqr()).scale(-(k.twice())),
    })
}

/// The range of (|C|cos ψ, |C|sin ψ) for ψ from `a` to `b` (< π apart),
/// given as (|C|cos ψ, |C|sin ψ) at both ends, |C| = `c`.
#[inline(never)] // reason: code-size
fn arc<R: Real>(ends: &[(R, R); 2], c: R) -> (Iv<R>, Iv<R>) {
    // Both ends in one array (four numbers: not promoted back to values).
    let [a, b] = *ends;
    let (mut ic, mut is) = (Iv::of(a.0, b.0), Iv::of(a.1, b.1));
    // A turn through ψ = 0, π/2, π, −π/2 (sin or cos changes sign on the
    // side of the axis it crosses) reaches that extreme.
    // Each sign tested once (the tests are opaque to LLVM, which would
    // repeat them).
    let [pa0, pa1, pb0, pb1] = [a.0, a.1, b.0, b.1].map(R::is_positive);
    let [na0, na1, nb0, nb1] = [a.0, a.1, b.0, b.1].map(R::is_negative);
    if !pa1 && !nb1 && (pa0 || pb0) {
        ic.hi = c;
    }
    if !na1 && !pb1 && (na0 || nb0) {
        ic.lo = -c;
    }
    if !na0 && !pb0 && (pa1 || pb1) {
        is.hi = c;
    }
    if !pa0 && !nb0 && (na1 || nb1) {
        is.lo = -c;
    }
    (ic, is)
}

/// A circle's stretch: its fields and [sa, sb], in one place (passed by
/// reference: as values, or as references LLVM's argument promotion turns
/// back into values, they would take the stack, docs/avr-traps.md trap 1).
struct CircleStretch<R> {
    center: [R; 3],
    radius: R,
    dir: [R; 2],
    sa: R,
    sb: R,
}

#[inline(never)] // reason: code-size
fn circle<R: Real>(st: &CircleStretch<R>) -> Planar<R> {
    let CircleStretch { center, radius, dir, sa, sb } = *st;
    let (rc, zc) = (center[0] * dir[0] + center[1] * dir[1], center[2]);
    let c = (rc * rc + zc * zc).sqrt();
    let w = R::PI.twice();
    let at = |s: R| {
        let phi = w * s;
        let (co, si) = (phi.cos(), phi.sin());
        (rc * co + zc * si, rc * si - zc * co)
    };
    let (cc, cs) =
        if R::lit(0.25) < sb - sa { (Iv { lo: -c, hi: c }, Iv { lo: -c, hi: c }) } else { arc(&[at(sa), at(sb)], c) };
    let rw = radius * w;
    let rww = rw * w;
    Planar {
        r2: cc.scale(radius.twice()).plus(Iv::pt(c * c + radius * radius)),
        n: cs.scale(-rw),
        dn: cc.scale(-rww),
        x1: cc.scale(rw).plus(Iv::pt(rw * radius)),
        x2: cs.scale(-rww),
        b1: Iv::pt(R::ZERO),
        b2: Iv::pt(R::ZERO),
    }
}

/// Per joint (base, shoulder, elbow), ranges holding θ′ and θ″ over s in
/// [sa, sb] (signed: a caller keeps the cancellation of θ″·ġ² against
/// θ′·g̈ that the move off the rim has); `None` when the stretch may meet
/// the base axis, the rim or the folded arm (a bound is infinite or
/// undefined there).
pub fn jet_bound<R: Real>(
    links: &Links<R>,
    branch: Branch,
    path: &Path<R>,
    sa: R,
    sb: R,
) -> Option<[(Iv<R>, Iv<R>); 3]> {
    let p = match *path {
        Path::Line { from, delta, .. } => line(&from, &delta, sa, sb)?,
        Path::Circle { center, radius, dir } => circle(&CircleStretch { center, radius, dir, sa, sb }),
    };
    planar_bound(links, branch, &p)
}

/// The elbow's rates, and its cosine for the shoulder's.
struct Elbow<R> {
    c3: Iv<R>,
    d3: Iv<R>,
    dd3: Iv<R>,
}

#[inline(never)] // avr-trap: frame-size
fn planar_bound<R: Real>(links: &Links<R>, branch: Branch, p: &Planar<R>) -> Option<[(Iv<R>, Iv<R>); 3]> {
    let e = elbow(links, branch, p)?;
    let (d2, dd2) = shoulder(links, p, &e);
    let out = [(p.b1, p.b2), (d2, dd2), (e.d3, e.dd3)];
    for (v, a) in &out {
        // NaN too: from ∞·0 where a range reaches a singular pose.
        if !(v.is_finite() && a.is_finite()) {
            return None;
        }
    }
    Some(out)
}

/// θ₃′ and θ₃″; `None` at the rim or the folded arm.
#[inline(never)] // reason: code-size
fn elbow<R: Real>(links: &Links<R>, branch: Branch, p: &Planar<R>) -> Option<Elbow<R>> {
    let (l2, l3) = (links.l2(), links.l3());
    let l23 = l2 * l3;
    let inv2 = (l23.twice()).recip();
    // 1 − c₃ and 1 + c₃ from r², each formed where it is small.
    let (rmax2, rmin2) = ((l2 + l3) * (l2 + l3), (l2 - l3) * (l2 - l3));
    let one_m = Iv { lo: (rmax2 - p.r2.hi) * inv2, hi: (rmax2 - p.r2.lo) * inv2 };
    let one_p = Iv { lo: (p.r2.lo - rmin2) * inv2, hi: (p.r2.hi - rmin2) * inv2 };
    if !(one_m.lo.is_positive() && one_p.lo.is_positive()) {
        return None;
    }
    let c3 = one_p.minus(Iv::pt(R::ONE));
    let s3 = one_m.times(one_p);
    let s3 = Iv { lo: s3.lo.sqrt(), hi: s3.hi.sqrt().min(R::ONE) };
    let sigma = if branch == Branch::Plus { R::ONE } else { -R::ONE };
    let inv_d = s3.scale(l23).recip_pos();
    // θ₃′ = −σN/(l₂l₃|s₃|), θ₃″ = −σ(N′/(l₂l₃|s₃|) + c₃N²/((l₂l₃)²|s₃|³)).
    let d3 = p.n.times(inv_d).scale(-sigma);
    let dd3 = p.dn.times(inv_d).plus(c3.times(p.n.sqr()).times(inv_d.sqr().times(inv_d)).scale(l23)).scale(-sigma);
    Some(Elbow { c3, d3, dd3 })
}

/// θ₂′ and θ₂″ from the elbow's.
#[inline(never)] // reason: code-size
fn shoulder<R: Real>(links: &Links<R>, p: &Planar<R>, e: &Elbow<R>) -> (Iv<R>, Iv<R>) {
    let (l2, l3) = (links.l2(), links.l3());
    let inv_r2 = p.r2.recip_pos();
    let a1 = p.x1.times(inv_r2);
    let a2 = p.x2.times(inv_r2).minus(p.n.times(p.x1).times(inv_r2.sqr()).scale(R::TWO));
    let k = e.c3.scale(l2).plus(Iv::pt(l3)).times(inv_r2).scale(l3);
    let dk = p.n.times(Iv::pt(R::ONE).minus(k.scale(R::TWO))).times(inv_r2);
    let d2 = a1.minus(k.times(e.d3));
    let dd2 = a2.minus(dk.times(e.d3)).minus(k.times(e.dd3));
    (d2, dd2)
}
