//! Inverse and forward kinematics of the planar 2-link arm (shoulder q2, elbow
//! q3) and of the 3-DoF arm with a base rotation θ1 (method.md §6). Radians; q3 is
//! the elbow angle relative to the upper link, counter-clockwise positive.

use crate::math::real::Real;

/// Why link lengths were refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinksError {
    /// A length (or its square) is NaN or infinite.
    NotFinite,
    /// A length is zero or negative.
    NotPositive,
}

/// Why the IK has no solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum IkError<R> {
    /// The target lies outside the annulus `|l2 − l3| ≤ r ≤ l2 + l3`.
    Unreachable {
        /// The elbow cosine it would need (|c| > 1).
        c: R,
    },
    /// The shoulder angle is undefined: the target is the shoulder itself
    /// (possible only with `l2 = l3`).
    Singular,
    /// A coordinate is NaN or infinite.
    NotFinite,
}

/// Which of the two elbow solutions: `Plus` ⇒ `q3 = +acos(c) ∈ [0, π]`,
/// `Minus` ⇒ `q3 = −acos(c)`. For a target right of the shoulder, `Plus` puts
/// the elbow below the shoulder–target line ("elbow down"), `Minus` above it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Branch {
    /// `q3 = +acos(c)`, in [0, π].
    Plus,
    /// `q3 = −acos(c)`, in [−π, 0]: the elbow-up pose the app uses.
    Minus,
}

/// Link lengths with the constants IK needs precomputed. Always valid: build
/// with [`Links::new`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Links<R> {
    l2: R,
    l3: R,
    /// (l2 − l3)/l3: zero exactly when l2 = l3
    diff_over_l3: R,
    /// l2² + l3²
    sum_sq: R,
    /// l2² + l3² (where c = 0) kept within [r_min_sq, r_max_sq]: the radius²
    /// that decides which of 1 ± c is the small one
    mid_sq: R,
    /// (l2 − l3)², the inner radius squared
    r_min_sq: R,
    /// (l2 + l3)², the outer radius squared
    r_max_sq: R,
    /// 1 / (2·l2·l3)
    inv_2l2l3: R,
    /// 8·ε/(2·l2·l3): the slack on 1 ± c per unit of x² + y² + l2² + l3²
    slack_scale: R,
}

/// Planar IK solution, radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointAngles2<R> {
    /// Shoulder angle from the horizontal, counter-clockwise positive.
    pub q2: R,
    /// Elbow angle relative to the upper link, counter-clockwise positive.
    pub q3: R,
}

/// 3-DoF IK solution ([`ik3`]), radians.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointAngles3<R> {
    /// Base rotation about the vertical axis, atan2(y_e, x_e).
    pub th1: R,
    /// Shoulder angle in the arm's vertical plane (the planar `q2`).
    pub th2: R,
    /// Elbow angle relative to the upper link (the planar `q3`).
    pub th3: R,
}

/// Slack on |c| ≤ 1, in units of ε times the magnitude of the terms that form
/// c (see [`ik2`]).
const C_SLACK_ULPS: f64 = 8.0;

impl<R: Real> Links<R> {
    /// Checks `l2`, `l3` (finite, positive, squares finite) and precomputes
    /// the IK's constants.
    pub fn new(l2: R, l3: R) -> Result<Self, LinksError> {
        if !(l2.is_finite() && l3.is_finite()) {
            return Err(LinksError::NotFinite);
        }
        if !(l2 > R::ZERO && l3 > R::ZERO) {
            return Err(LinksError::NotPositive);
        }
        let diff = l2 - l3;
        let sum = l2 + l3;
        let (sum_sq, r_min_sq, r_max_sq) = (l2 * l2 + l3 * l3, diff * diff, sum * sum);
        let inv_2l2l3 = (R::TWO * l2 * l3).recip();
        let links = Self {
            l2,
            l3,
            diff_over_l3: diff / l3,
            sum_sq,
            // r_min_sq ≤ r_max_sq holds after rounding too (both squares of
            // rounded |l2 ∓ l3|), so the clamp is well defined.
            mid_sq: sum_sq.max(r_min_sq).min(r_max_sq),
            r_min_sq,
            r_max_sq,
            inv_2l2l3,
            slack_scale: R::lit(C_SLACK_ULPS) * R::EPSILON * inv_2l2l3,
        };
        // Squares can overflow or underflow even for finite positive lengths.
        if !(links.r_max_sq.is_finite() && links.inv_2l2l3.is_finite()) {
            return Err(LinksError::NotFinite);
        }
        Ok(links)
    }

    /// Upper arm length.
    pub fn l2(&self) -> R {
        self.l2
    }

    /// Forearm length.
    pub fn l3(&self) -> R {
        self.l3
    }

    /// Inner radius of the reachable annulus, |l2 − l3|.
    pub fn r_min(&self) -> R {
        (self.l2 - self.l3).abs()
    }

    /// Outer radius of the reachable annulus, l2 + l3.
    pub fn r_max(&self) -> R {
        self.l2 + self.l3
    }
}

/// Planar IK (method.md §6): `c = (x² + y² − l2² − l3²)/(2·l2·l3)`,
/// `q3 = ±acos(c)`, `q2 = atan2(y, x) ∓ atan2(l3·sin|q3|, l2 + l3·cos q3)`.
/// `q2` is wrapped into (−π, π]. `fk2(ik2(p)) = p` for both branches.
///
/// Evaluated without cancellations the geometry does not have. The printed
/// form subtracts l2² + l3² from r²; near the inner rim with l2 ≈ l3 (targets
/// close to the shoulder: the bottom centre of the screen with the paper's
/// l2 = l3) that leaves 1 + c with few correct digits, and `√(1 − c²)` and
/// `l2 + l3·c` then cancel again (f32: a miss of 3e-6 of the arm's span seen).
/// Here `1 + c = (r² − (l2 − l3)²)/(2·l2·l3)` and
/// `1 − c = ((l2 + l3)² − r²)/(2·l2·l3)` are formed directly, the smaller one
/// fixes the other, and `sin|q3| = √((1 + c)(1 − c))`, `|q3| = atan2(sin|q3|, c)`
/// (= acos c), `(l2 + l3·c)/l3 = (1 + c) + (l2 − l3)/l3`. Near the outer rim q3
/// is inherently sensitive (∝ √(r_max − r)); the reached position is not.
///
/// Boundary: a point exactly on a boundary circle (r = l2 + l3 or |l2 − l3|)
/// is reachable, but rounding can push its computed c a few ulps past ±1. So
/// |c| may exceed 1 by at most `8·ε·(x² + y² + l2² + l3²)/(2·l2·l3)` — a bound
/// on the rounding error of c, i.e. a radial distance of a few ε·r — and is
/// then taken as exactly ±1. Anything further out is `Unreachable`, never
/// clamped.
///
/// ```
/// use touch_arm::geometry::ik::{fk2, ik2, Branch, IkError, Links};
/// use std::f64::consts::FRAC_PI_2;
///
/// // Unit links, target (1, 1): r² = 2, so c = (2 − 1 − 1)/2 = 0, a square
/// // elbow; on the Plus branch q3 = +π/2 and q2 = π/4 − atan2(1, 1) = 0.
/// let links = Links::new(1.0_f64, 1.0).unwrap();
/// let q = ik2(&links, 1.0, 1.0, Branch::Plus).unwrap();
/// assert!((q.q3 - FRAC_PI_2).abs() < 1e-15 && q.q2.abs() < 1e-15);
/// // The other elbow: q3 = −π/2, q2 = π/2.
/// let m = ik2(&links, 1.0, 1.0, Branch::Minus).unwrap();
/// assert!((m.q3 + FRAC_PI_2).abs() < 1e-15 && (m.q2 - FRAC_PI_2).abs() < 1e-15);
/// // Forward kinematics lands on the target again.
/// let (x, y) = fk2(&links, m.q2, m.q3);
/// assert!((x - 1.0).abs() < 1e-15 && (y - 1.0).abs() < 1e-15);
/// // Past the outer rim r = 2: c = (9 − 2)/2 = 3.5, refused rather than clamped.
/// assert_eq!(ik2(&links, 3.0, 0.0, Branch::Plus), Err(IkError::Unreachable { c: 3.5 }));
/// ```
pub fn ik2<R: Real>(links: &Links<R>, x: R, y: R, branch: Branch) -> Result<JointAngles2<R>, IkError<R>> {
    if !(x.is_finite() && y.is_finite()) {
        return Err(IkError::NotFinite);
    }
    // atan2 gives −π for (−0, x < 0), and (rounded) for y a hair below the
    // negative x axis: that direction is +π in (−π, π], which `ik2_toward` needs.
    let phi = y.atan2(x);
    let phi = if phi.le_num(-R::PI) { R::PI } else { phi };
    ik2_toward(links, x, y, phi, branch)
}

/// [`ik2`] for finite (x, y) whose direction `phi` = atan2(y, x) ∈ (−π, π]
/// the caller already has (the pose chain derives it from the base angle α,
/// saving an arctangent). Always inlined: the path frame's [`ik3`] is
/// shared by the library's callers, and a call to this body cost it some
/// 100 cycles (BENCHMARKS.md `path_frame`, issue #13's 16 000).
#[inline(always)]
pub(crate) fn ik2_toward<R: Real>(
    links: &Links<R>,
    x: R,
    y: R,
    phi: R,
    branch: Branch,
) -> Result<JointAngles2<R>, IkError<R>> {
    let Elbow { s, p } = elbow(links, x, y)?;
    let (beta, q3) = if links.diff_over_l3.is_zero() {
        // s = 0 too: c = −1 with l2 = l3, i.e. (numerically) the shoulder.
        if p.is_zero() {
            return Err(IkError::Singular);
        }
        // With l2 = l3, β = atan2(s, 1 + c) is exactly |q3|/2 (the half-angle
        // identity): one arctangent less, and well conditioned near c = −1.
        let beta = s.atan2(p);
        (beta, beta.twice())
    } else {
        // tan β = l3·s/(l2 + l3·c) = s/(1 + c + (l2 − l3)/l3).
        let bx = p + links.diff_over_l3;
        if s.is_zero() && bx.is_zero() {
            return Err(IkError::Singular);
        }
        // |q3| = atan2(s, c) = acos c, accurate also near c = ±1.
        (s.atan2(bx), s.atan2(p - R::ONE))
    };
    // φ ∈ (−π, π] and β ∈ [0, π]: each branch can leave (−π, π] on one side only.
    let two_pi = R::TWO * R::PI;
    Ok(match branch {
        Branch::Plus => {
            let q2 = phi - beta;
            JointAngles2 { q2: if q2.le_num(-R::PI) { (q2 + two_pi).barrier() } else { q2 }, q3 }
        }
        Branch::Minus => {
            let q2 = phi + beta;
            JointAngles2 { q2: if q2.le_num(R::PI) { q2 } else { (q2 - two_pi).barrier() }, q3: -q3 }
        }
    })
}

/// The elbow of the planar IK: `s = sin|q3|` and `p = 1 + c`.
struct Elbow<R> {
    s: R,
    p: R,
}

/// Reach check and elbow of [`ik2`] for finite (x, y).
///
/// Of `1 + c = (r² − (l2 − l3)²)/(2·l2·l3)` and `1 − c = ((l2 + l3)² − r²)/(2·l2·l3)`
/// only the smaller is formed (which one follows from comparing r² with
/// `mid_sq`); the other is 2 minus it. One value then drives s, β and q3
/// alike, or a short l2 (large 1/(2·l2·l3)) would turn independent roundings
/// into a tangential miss; and the larger one is ≥ 0 by construction, so only
/// the smaller needs the reach check.
#[inline]
fn elbow<R: Real>(links: &Links<R>, x: R, y: R) -> Result<Elbow<R>, IkError<R>> {
    let inv = links.inv_2l2l3;
    let r_sq = x * x + y * y;
    let inner = r_sq.le_num(links.mid_sq);
    let d = if inner { r_sq - links.r_min_sq } else { links.r_max_sq - r_sq };
    let mut small = d * inv;
    // r² overflows for huge finite x: then d = −∞, and the slack would be ∞ too.
    if small.is_negative() {
        let slack = (r_sq + links.sum_sq) * links.slack_scale;
        if !(r_sq.is_finite() && small >= -slack) {
            return Err(IkError::Unreachable { c: (r_sq - links.sum_sq) * inv });
        }
        small = R::ZERO;
    }
    if x.is_zero() && y.is_zero() {
        return Err(IkError::Singular);
    }
    let (p, m) = if inner { (small, R::TWO - small) } else { (R::TWO - small, small) };
    Ok(Elbow { s: (p * m).sqrt(), p })
}

/// Planar FK: `x = l2·cos q2 + l3·cos(q2 + q3)`, `y = l2·sin q2 + l3·sin(q2 + q3)`.
pub fn fk2<R: Real>(links: &Links<R>, q2: R, q3: R) -> (R, R) {
    let q23 = q2 + q3;
    (links.l2 * q2.cos() + links.l3 * q23.cos(), links.l2 * q2.sin() + links.l3 * q23.sin())
}

/// 3-DoF IK (lab note): `θ1 = atan2(y_e, x_e)`, then the planar IK on
/// `(√(x_e² + y_e²), z_e)` gives `θ2, θ3`. Straight above the base
/// (x_e = y_e = 0) θ1 is free; it is then 0.
#[inline]
pub fn ik3<R: Real>(links: &Links<R>, x_e: R, y_e: R, z_e: R, branch: Branch) -> Result<JointAngles3<R>, IkError<R>> {
    if !(x_e.is_finite() && y_e.is_finite() && z_e.is_finite()) {
        return Err(IkError::NotFinite);
    }
    let th1 = base_angle(x_e, y_e);
    let rho = (x_e * x_e + y_e * y_e).sqrt();
    if !rho.is_finite() {
        // x_e² overflowed: far beyond any arm.
        return Err(IkError::Unreachable { c: rho });
    }
    // ik2's body: its direction, then the planar IK toward it (here, not a
    // call to ik2, which the lift's via pose shares).
    let phi = z_e.atan2(rho);
    let phi = if phi.le_num(-R::PI) { R::PI } else { phi };
    let planar = ik2_toward(links, rho, z_e, phi, branch)?;
    Ok(JointAngles3 { th1, th2: planar.q2, th3: planar.q3 })
}

/// θ1 of [`ik3`]: `atan2(y_e, x_e)`, 0 straight above the base. Defined
/// whether or not the planar part is reachable.
pub fn base_angle<R: Real>(x_e: R, y_e: R) -> R {
    let on_axis = x_e == R::ZERO && y_e == R::ZERO;
    if on_axis {
        R::ZERO
    } else {
        y_e.atan2(x_e)
    }
}

/// 3-DoF FK: the planar FK gives (ρ, z), the base turns ρ by θ1.
pub fn fk3<R: Real>(links: &Links<R>, th1: R, th2: R, th3: R) -> (R, R, R) {
    let (rho, z) = fk2(links, th2, th3);
    (rho * th1.cos(), rho * th1.sin(), z)
}

/// [`fk3`] of a pose (θ1, θ2, θ3) by reference, as `[x, y, z]`: the chip's
/// form. `fk3`'s four arguments and returned tuple put one argument on the
/// AVR's stack, which LLVM miscompiles (the post-link lint in
/// `xtask/tests/firmware_elf.rs` caught it: a path move from the wrong
/// start).
#[inline(never)] // avr-trap: stack-args
pub fn fk3_pose<R: Real>(links: &Links<R>, q: &[R; 3]) -> [R; 3] {
    let (rho, z) = fk2(links, q[1], q[2]);
    [rho * q[0].cos(), rho * q[0].sin(), z]
}
