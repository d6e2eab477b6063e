//! From a screen point to the arm's joint angles: the paper's whole chain after
//! the touch mapping (condition and α, transform, 2-link IK). One place, used by
//! the firmware's app and by `armsim plan`, so both compute the same pose.

use crate::geometry::ik::{ik2_toward, Branch, IkError, Links, LinksError};
use crate::geometry::workspace::{Condition, WorkspaceError, WorkspacePoint};
use crate::math::real::Real;

/// The arm's geometry as the mapping sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArmGeometry<R> {
    /// Screen-to-arm scale of the linear transform.
    pub k: R,
    /// Upper arm and forearm.
    pub links: Links<R>,
    /// Elbow solution used.
    pub branch: Branch,
}

impl<R: Real> ArmGeometry<R> {
    /// The arm of links `l2`, `l3` measured in any one unit (the firmware's
    /// `cal set arm`: millimetres), in the map's arm unit: the links' mean
    /// length, so l2 + l3 = 2 arm units. The paper's equal links are then
    /// 1 and 1 whatever their length, and the map (scaled by `k`) covers the
    /// same share of every arm's reach: with unequal links only the
    /// near-base disc of radius |l2 − l3| drops out.
    pub fn from_lengths(k: R, l2: R, l3: R, branch: Branch) -> Result<Self, LinksError> {
        // Checked as given first (as `Links::new` would): a unit made of bad
        // lengths would hide why.
        if !(l2.is_finite() && l3.is_finite()) {
            return Err(LinksError::NotFinite);
        }
        if !(l2 > R::ZERO && l3 > R::ZERO) {
            return Err(LinksError::NotPositive);
        }
        let unit = (l2 + l3) * R::HALF;
        Ok(ArmGeometry { k, links: Links::new(l2 / unit, l3 / unit)?, branch })
    }
}

/// Where a screen point sends the arm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pose<R> {
    /// Triangle condition (zone 1–4) of the point.
    pub condition: Condition,
    /// Base direction α in radians, [0, π].
    pub alpha: R,
    /// Planar IK target: k·|x_p| and k·y_p.
    pub reach: R,
    /// Height of the planar IK target, k·y_p.
    pub height: R,
    /// Shoulder and elbow angles (radians) from the IK.
    pub q2: R,
    /// Elbow angle relative to the upper arm (radians) from the IK.
    pub q3: R,
}

/// Why a point has no pose.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PoseError<R> {
    /// The point is not in the workspace, or k is bad.
    Workspace(WorkspaceError),
    /// The arm cannot reach the transformed point.
    Ik(IkError<R>),
}

/// Solves the pose for a normalized screen point (x_p, y_p) ∈ \[−1,1\]×\[0,1\].
pub fn pose_for_point<R: Real>(geo: &ArmGeometry<R>, x_p: R, y_p: R) -> Result<Pose<R>, PoseError<R>> {
    let p = WorkspacePoint::new(x_p, y_p).map_err(PoseError::Workspace)?;
    let t = p.target(geo.k).map_err(PoseError::Workspace)?;
    // The IK target (k·|x_p|, k·y_p) points at atan2(y_p, |x_p|) (k > 0
    // scales both): α itself, or π − α left of centre. One arctangent less.
    let phi = if p.x_p().is_negative() { (R::PI - t.alpha).barrier() } else { t.alpha };
    let q = ik2_toward(&geo.links, t.reach, t.height, phi, geo.branch).map_err(PoseError::Ik)?;
    Ok(Pose { condition: t.condition, alpha: t.alpha, reach: t.reach, height: t.height, q2: q.q2, q3: q.q3 })
}
