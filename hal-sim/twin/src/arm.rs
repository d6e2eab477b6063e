//! Forward kinematics of the arm for the end effector (f64, independent of
//! the app's f32 IK): the planar 2-link FK gives reach and height in the arm
//! plane, the base turns that plane by its angle.

use touch_arm::geometry::ik::{fk2, Links};

/// End effector of joint angles (base, shoulder, elbow), rad.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Effector {
    /// Distance from the base axis in the arm plane.
    pub reach: f64,
    /// Height above the shoulder.
    pub height: f64,
    /// Cartesian position: the arm plane turned by the base angle.
    pub xyz: [f64; 3],
}

/// The end effector the joint `angles` (base, shoulder, elbow; rad) put at, for links `links`.
pub fn effector(links: &Links<f64>, angles: &[f64; 3]) -> Effector {
    let [base, q2, q3] = *angles;
    let (reach, height) = fk2(links, q2, q3);
    Effector { reach, height, xyz: [reach * base.cos(), reach * base.sin(), height] }
}
