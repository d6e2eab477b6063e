//! End-effector paths (the lab note): a straight segment P_a → P_b and one
//! turn of a circle in the arm's vertical plane, both parametrized by the
//! progress s ∈ [0, 1] (the motion law supplies s = g(t)), and the joint
//! angles along them with their first two derivatives in s ([`ik_jet`]), from
//! which a planner gets joint speeds and accelerations by the chain rule.
//!
//! Coordinates are the 3-DoF IK's ([`ik3`]): x, y horizontal (the base turns
//! by θ1 = atan2(y, x)), z up; the planar IK works on (ρ, z), ρ = √(x² + y²).

use crate::geometry::ik::{ik3, Branch, IkError, Links};
use crate::math::real::Real;

/// A point or vector (x, y, z).
pub type Vec3<R> = [R; 3];

/// Why a path was refused before any joint angle was looked at.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PathShapeError {
    /// A coordinate or the radius is NaN or infinite.
    NotFinite,
    /// A segment of zero length, or a radius ≤ 0.
    Degenerate,
    /// The path runs through the base axis (x = y = 0), where θ1 is
    /// undefined and flips by π: no servo can follow it.
    CrossesBaseAxis,
}

/// A path in space, traversed as s runs 0 → 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Path<R> {
    /// P(s) = P_a + (P_b − P_a)·s.
    Line {
        /// Start P_a.
        from: Vec3<R>,
        /// End P_b, returned exactly at s = 1.
        to: Vec3<R>,
        /// P_b − P_a.
        delta: Vec3<R>,
    },
    /// P(s) = C + r·(cos 2πs·e_ρ + sin 2πs·e_z): one turn in the vertical
    /// plane through the base axis and C, starting at the point farthest out
    /// and rising first.
    Circle {
        /// Centre C.
        center: Vec3<R>,
        /// Radius r > 0.
        radius: R,
        /// (cos, sin) of the plane's direction in the top view.
        dir: [R; 2],
    },
}

/// P, dP/ds and d²P/ds² at one progress s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathJet<R> {
    /// Position.
    pub p: Vec3<R>,
    /// dP/ds.
    pub dp: Vec3<R>,
    /// d²P/ds².
    pub ddp: Vec3<R>,
}

fn finite3<R: Real>(v: &Vec3<R>) -> bool {
    v.iter().all(|c| c.is_finite())
}

impl<R: Real> Path<R> {
    /// The segment `from` → `to`. Refused when it is empty or its top view
    /// passes through the base axis.
    pub fn line(from: &Vec3<R>, to: &Vec3<R>) -> Result<Self, PathShapeError> {
        if !(finite3(from) && finite3(to)) {
            return Err(PathShapeError::NotFinite);
        }
        let delta = [to[0] - from[0], to[1] - from[1], to[2] - from[2]];
        if !finite3(&delta) {
            return Err(PathShapeError::NotFinite);
        }
        if delta.iter().all(|c| c.is_zero()) {
            return Err(PathShapeError::Degenerate);
        }
        // Closest approach of the top view to the origin: at s* = −(a·d)/|d|²
        // clamped to [0, 1]; the axis is crossed when the distance there is 0.
        let (ax, ay, dx, dy) = (from[0], from[1], delta[0], delta[1]);
        let dd = dx * dx + dy * dy;
        let s = if dd.is_zero() { R::ZERO } else { (-(ax * dx + ay * dy) / dd).max(R::ZERO).min(R::ONE) };
        let (cx, cy) = (ax + dx * s, ay + dy * s);
        if (cx * cx + cy * cy).is_zero() {
            return Err(PathShapeError::CrossesBaseAxis);
        }
        Ok(Path::Line { from: *from, to: *to, delta })
    }

    /// One turn of radius r around `center` in the vertical plane through
    /// the base axis and the centre. Refused when the centre is on the base
    /// axis (no plane) or the circle reaches it (r ≥ the centre's ρ).
    pub fn circle(center: &Vec3<R>, radius: R) -> Result<Self, PathShapeError> {
        if !(finite3(center) && radius.is_finite()) {
            return Err(PathShapeError::NotFinite);
        }
        if !radius.is_positive() {
            return Err(PathShapeError::Degenerate);
        }
        let rho = (center[0] * center[0] + center[1] * center[1]).sqrt();
        if !rho.is_finite() {
            return Err(PathShapeError::NotFinite);
        }
        if !radius.lt_cold(rho) {
            return Err(PathShapeError::CrossesBaseAxis);
        }
        let dir = [center[0] / rho, center[1] / rho];
        Ok(Path::Circle { center: *center, radius, dir })
    }

    /// Progress values where the joint rates can peak in a spike narrower
    /// than any fixed grid resolves: for a segment, its closest approach to
    /// the base axis in the top view (θ1′ = (a × d)/ρ² peaks there) and to the
    /// shoulder (the folded arm is singular); for a circle, its points
    /// farthest from and nearest to the shoulder (the straight and the most
    /// folded elbow). Its other extremes are at the ends, which every scan
    /// visits and (`motion::path`) refines around as around these.
    pub fn critical_points(&self) -> [R; 2] {
        match *self {
            Path::Line { from, delta, .. } => {
                let closest = |n: usize| {
                    let (mut ad, mut dd) = (R::ZERO, R::ZERO);
                    for i in 0..n {
                        ad += from[i] * delta[i];
                        dd += delta[i] * delta[i];
                    }
                    if dd.is_zero() {
                        R::ZERO
                    } else {
                        (-ad / dd).max(R::ZERO).min(R::ONE)
                    }
                };
                [closest(2), closest(3)]
            }
            Path::Circle { center, dir, .. } => {
                // In the plane the centre sits at (ρ_c, z_c); the farthest
                // point lies along that direction.
                let rho_c = center[0] * dir[0] + center[1] * dir[1];
                let turn = R::PI.twice();
                let far = center[2].atan2(rho_c) / turn;
                let far = if far.is_negative() { far + R::ONE } else { far };
                let near = if far < R::HALF { far + R::HALF } else { far - R::HALF };
                [far, near]
            }
        }
    }

    /// Where the path starts (s = 0).
    pub fn start(&self) -> Vec3<R> {
        self.point(R::ZERO)
    }

    /// Where the path ends (s = 1): a line's P_b exactly.
    pub fn end(&self) -> Vec3<R> {
        self.point(R::ONE)
    }

    /// P(s) (the per-frame path: no derivatives).
    pub fn point(&self, s: R) -> Vec3<R> {
        match *self {
            Path::Line { from, to, delta } => {
                if s < R::ONE {
                    [from[0] + delta[0] * s, from[1] + delta[1] * s, from[2] + delta[2] * s]
                } else {
                    to
                }
            }
            Path::Circle { center, radius, dir } => {
                let phi = R::PI.twice() * s;
                let (pr, pz) = (radius * phi.cos(), radius * phi.sin());
                [center[0] + pr * dir[0], center[1] + pr * dir[1], center[2] + pz]
            }
        }
    }

    /// P and its first two derivatives in s.
    pub fn jet(&self, s: R) -> PathJet<R> {
        match *self {
            Path::Line { from, to, delta } => PathJet {
                // P_a + (P_b − P_a)·1 can miss P_b by an ulp; the target is exact.
                p: if s < R::ONE {
                    [from[0] + delta[0] * s, from[1] + delta[1] * s, from[2] + delta[2] * s]
                } else {
                    to
                },
                dp: delta,
                ddp: [R::ZERO; 3],
            },
            Path::Circle { center, radius, dir } => {
                let w = R::PI.twice();
                let phi = w * s;
                let (c, sn) = (phi.cos(), phi.sin());
                // Radial (in the plane's top-view direction) and vertical parts.
                let (pr, pz) = (radius * c, radius * sn);
                let (dr, dz) = (-radius * w * sn, radius * w * c);
                let (ddr, ddz) = (-w * w * pr, -w * w * pz);
                PathJet {
                    p: [center[0] + pr * dir[0], center[1] + pr * dir[1], center[2] + pz],
                    dp: [dr * dir[0], dr * dir[1], dz],
                    ddp: [ddr * dir[0], ddr * dir[1], ddz],
                }
            }
        }
    }
}

/// Joint angles (θ1, θ2, θ3) along a path and their first two derivatives
/// in the path's parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointJet<R> {
    /// Angles, rad ([`ik3`]'s).
    pub q: Vec3<R>,
    /// dq/ds.
    pub dq: Vec3<R>,
    /// d²q/ds².
    pub ddq: Vec3<R>,
}

/// Why a path point has no joint jet.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JetError<R> {
    /// The IK refused the point.
    Ik(IkError<R>),
    /// On the base axis (θ1's rate is unbounded) or with the arm straight
    /// or folded (sin θ3 = 0: the planar Jacobian is singular).
    Singular,
}

/// IK of `j.p` and the joint rates by the chain rule: θ1 = atan2(y, x)
/// differentiated directly; (θ2, θ3) from the planar Jacobian J of
/// (ρ, z) = FK(θ2, θ3), dq = J⁻¹·d(ρ, z) and ddq = J⁻¹·(dd(ρ, z) − J̇·dq),
/// det J = l2·l3·sin θ3. The rates grow without bound toward the base axis
/// and toward the rim of the workspace (sin θ3 → 0): a planner compares them
/// with the joints' limits.
pub fn ik_jet<R: Real>(links: &Links<R>, branch: Branch, j: &PathJet<R>) -> Result<JointJet<R>, JetError<R>> {
    let [x, y, _] = j.p;
    let q = ik3(links, x, y, j.p[2], branch).map_err(JetError::Ik)?;
    let [dx, dy, dz] = j.dp;
    let [ddx, ddy, ddz] = j.ddp;
    let rho_sq = x * x + y * y;
    if rho_sq.is_zero() {
        return Err(JetError::Singular);
    }
    let rho = rho_sq.sqrt();
    let cross = x * dy - y * dx;
    let dot = x * dx + y * dy;
    let d1 = cross / rho_sq;
    let dd1 = (x * ddy - y * ddx) / rho_sq - R::TWO * cross * dot / (rho_sq * rho_sq);
    let drho = dot / rho;
    let ddrho = (dx * dx + dy * dy + x * ddx + y * ddy - drho * drho) / rho;

    let (l2, l3) = (links.l2(), links.l3());
    let (s2, c2) = (q.th2.sin(), q.th2.cos());
    let q23 = q.th2 + q.th3;
    let (s23, c23) = (q23.sin(), q23.cos());
    let det = l2 * l3 * q.th3.sin();
    if det.is_zero() {
        return Err(JetError::Singular);
    }
    // J = [[−l2·s2 − l3·s23, −l3·s23], [l2·c2 + l3·c23, l3·c23]].
    let (j00, j01, j10, j11) = (-l2 * s2 - l3 * s23, -l3 * s23, l2 * c2 + l3 * c23, l3 * c23);
    let inv = det.recip();
    let solve = |a: R, b: R| ((j11 * a - j01 * b) * inv, (j00 * b - j10 * a) * inv);
    let (d2, d3) = solve(drho, dz);
    let w = d2 + d3;
    // J̇·dq: the centripetal terms of the planar FK's second derivative.
    let cr = -l2 * c2 * d2 * d2 - l3 * c23 * w * w;
    let cz = -l2 * s2 * d2 * d2 - l3 * s23 * w * w;
    let (dd2, dd3) = solve(ddrho - cr, ddz - cz);
    Ok(JointJet { q: [q.th1, q.th2, q.th3], dq: [d1, d2, d3], ddq: [dd1, dd2, dd3] })
}
