//! The workspace `[−1, 1] × [0, 1]`: direction α, the four triangle conditions
//! and the two linear transforms to the arm (method.md §4–5).
//!
//! All angles are radians unless a name ends in `_deg`.

use crate::math::real::Real;
use crate::math::units::rad_to_deg;

/// Why a workspace computation was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WorkspaceError {
    /// A coordinate is NaN or infinite.
    NotFinite,
    /// The point lies outside `[−1, 1] × [0, 1]`.
    OutOfWorkspace,
    /// The scale `k` is not a positive finite number.
    BadScale,
}

/// The four right triangles of equal area cut by the diagonals through the
/// origin: 1: 0–45°, 2: 45–90°, 3: 90–135°, 4: 135–180°. A point on 45°, 90° or
/// 135° belongs to the lower-numbered one, the origin to 1.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Condition {
    /// 0–45°, right of the base, low.
    C1,
    /// 45–90°, right of the base, high.
    C2,
    /// 90–135°, left of the base, high.
    C3,
    /// 135–180°, left of the base, low.
    C4,
}

impl Condition {
    /// The paper's number, 1..=4.
    pub const fn number(self) -> u8 {
        match self {
            Condition::C1 => 1,
            Condition::C2 => 2,
            Condition::C3 => 3,
            Condition::C4 => 4,
        }
    }

    /// The label transform 2 gives a point: 1↔4, 2↔3.
    pub const fn mirrored(self) -> Self {
        match self {
            Condition::C1 => Condition::C4,
            Condition::C2 => Condition::C3,
            Condition::C3 => Condition::C2,
            Condition::C4 => Condition::C1,
        }
    }

    /// Exact comparisons of the coordinates, never of a rounded α, so the
    /// boundary rules hold to the last bit. Requires `y ≥ 0` (a
    /// [`WorkspacePoint`] guarantees it).
    #[inline]
    fn classify<R: Real>(x: R, y: R) -> Self {
        if y.le_cold(x) {
            // 0..=45°, and the origin.
            Condition::C1
        } else if !x.is_negative() {
            // (45°, 90°]
            Condition::C2
        } else if (-x).le_cold(y) {
            // (90°, 135°]
            Condition::C3
        } else {
            Condition::C4
        }
    }
}

/// A validated point of the workspace. Signed zeros are normalized to +0 so
/// that α and the condition never depend on the sign of a zero.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WorkspacePoint<R> {
    x_p: R,
    y_p: R,
}

/// Result of a linear transform: the arm-frame point, its angle and its label.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transformed<R> {
    /// Arm-frame x, arm units.
    pub x: R,
    /// Arm-frame y (height), arm units.
    pub y: R,
    /// The point's direction, radians.
    pub alpha: R,
    /// The condition (mirrored for transform 2).
    pub condition: Condition,
}

/// What the arm needs for a touched point: the planar IK target `(reach,
/// height)` and the base angle `alpha` (radians), plus the point's condition.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Target<R> {
    /// Horizontal distance from the shoulder, k·|x_p|.
    pub reach: R,
    /// Height above the shoulder, k·y_p.
    pub height: R,
    /// Base direction α, radians, [0, π].
    pub alpha: R,
    /// The touched point's condition.
    pub condition: Condition,
}

impl<R: Real> Target<R> {
    /// α in degrees, [0, 180].
    pub fn alpha_deg(&self) -> R {
        rad_to_deg(self.alpha)
    }
}

fn check_scale<R: Real>(k: R) -> Result<(), WorkspaceError> {
    if k.is_finite() && k.is_positive() {
        Ok(())
    } else {
        Err(WorkspaceError::BadScale)
    }
}

impl<R: Real> WorkspacePoint<R> {
    /// A finite point inside `[−1, 1] × [0, 1]` (−0 is stored as +0).
    #[inline]
    pub fn new(x_p: R, y_p: R) -> Result<Self, WorkspaceError> {
        if !(x_p.is_finite() && y_p.is_finite()) {
            return Err(WorkspaceError::NotFinite);
        }
        if !(x_p.abs().le_cold(R::ONE) && !y_p.is_negative() && y_p.le_cold(R::ONE)) {
            return Err(WorkspaceError::OutOfWorkspace);
        }
        let plus_zero = |v: R| if v.is_zero() { R::ZERO } else { v };
        Ok(Self { x_p: plus_zero(x_p), y_p: plus_zero(y_p) })
    }

    /// Horizontal coordinate, −1..=1 (0 below the base).
    pub fn x_p(&self) -> R {
        self.x_p
    }

    /// Vertical coordinate, 0..=1.
    pub fn y_p(&self) -> R {
        self.y_p
    }

    /// α = atan2(y_p, x_p) ∈ [0, π]: π/2 straight up, 0 at the origin (method.md
    /// §4; the printed atan(y/x) is off by π for x < 0).
    #[inline]
    pub fn alpha(&self) -> R {
        if self.y_p.is_zero() {
            // Explicit so that no libm's atan2(0, 0) or atan2(0, −x) convention matters.
            if self.x_p.is_negative() {
                R::PI
            } else {
                R::ZERO
            }
        } else {
            self.y_p.atan2(self.x_p)
        }
    }

    /// α in degrees, [0, 180].
    pub fn alpha_deg(&self) -> R {
        rad_to_deg(self.alpha())
    }

    /// The triangle condition the point lies in.
    #[inline]
    pub fn condition(&self) -> Condition {
        Condition::classify(self.x_p, self.y_p)
    }

    /// Transform 1 (counter-clockwise base rotation): `(k·x, k·y, α)`, same
    /// condition.
    pub fn transform1(&self, k: R) -> Result<Transformed<R>, WorkspaceError> {
        check_scale(k)?;
        Ok(Transformed { x: k * self.x_p, y: k * self.y_p, alpha: self.alpha(), condition: self.condition() })
    }

    /// Transform 2 (clockwise): `(−k·x, k·y, π − α)`, condition mirrored
    /// (1↔4, 2↔3). The result is the mirror image of the point; its label is the
    /// mirrored label of the source. Re-classifying the mirrored point gives the
    /// same label except on the shared boundaries (45°/135°, 90°, origin), where
    /// the lower-number rule is not mirror-symmetric.
    pub fn transform2(&self, k: R) -> Result<Transformed<R>, WorkspaceError> {
        check_scale(k)?;
        Ok(Transformed {
            x: -(k * self.x_p),
            y: k * self.y_p,
            alpha: R::PI - self.alpha(),
            condition: self.condition().mirrored(),
        })
    }

    /// method.md §4–5 "net effect": conditions 1–2 use transform 1, 3–4 transform 2;
    /// either way the planar target is `(k·|x_p|, k·y_p)` and the base turns to α.
    #[inline]
    pub fn target(&self, k: R) -> Result<Target<R>, WorkspaceError> {
        check_scale(k)?;
        Ok(Target { reach: k * self.x_p.abs(), height: k * self.y_p, alpha: self.alpha(), condition: self.condition() })
    }
}

/// α in radians of a workspace point, see [`WorkspacePoint::alpha`].
pub fn alpha<R: Real>(x_p: R, y_p: R) -> Result<R, WorkspaceError> {
    Ok(WorkspacePoint::new(x_p, y_p)?.alpha())
}

/// α in degrees of a workspace point.
pub fn alpha_deg<R: Real>(x_p: R, y_p: R) -> Result<R, WorkspaceError> {
    Ok(WorkspacePoint::new(x_p, y_p)?.alpha_deg())
}

/// Condition of a workspace point.
pub fn condition<R: Real>(x_p: R, y_p: R) -> Result<Condition, WorkspaceError> {
    Ok(WorkspacePoint::new(x_p, y_p)?.condition())
}

/// Planar IK target and base angle for a touched point, see
/// [`WorkspacePoint::target`].
pub fn ik_target<R: Real>(x_p: R, y_p: R, k: R) -> Result<Target<R>, WorkspaceError> {
    WorkspacePoint::new(x_p, y_p)?.target(k)
}
