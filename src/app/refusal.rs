//! Why the app refuses a request, and the reason text of its `err` reply.

use crate::motion::planner::request::PlanError;
use crate::servo::map::Joint;

/// Why the app refuses a request (and keeps holding its pose).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    /// STOP is latched: send `resume` first.
    Stopped,
    /// Power-up: the home pose is still settling.
    Homing,
    /// A move is running (calibration changes and saves wait for rest).
    Busy,
    /// A raw touch outside the calibrated panel span.
    OutsideCalibration,
    /// The mapped point is not in [−1, 1] × [0, 1] (or the scale is bad).
    OutsideWorkspace,
    /// The IK target lies outside the arm's annulus.
    Unreachable,
    /// The IK target is the shoulder itself (undefined shoulder angle).
    Singular,
    /// The target angle of this joint is outside its configured limits (it is
    /// refused, never clamped into a different pose).
    JointLimit(Joint),
    /// The joints' speed limits cannot be met within `ts_max`.
    SpeedLimit,
    /// The trajectory is inadmissible or not monotone.
    Trajectory,
    /// A non-finite number where a pose was expected.
    NotFinite,
    /// A setpoint the servo layer refused (a bug): STOP was latched.
    Fault,
    /// The calibration change would put the held pose outside the limits.
    HeldPoseOutside,
    /// The gripper's target angle is outside its configured limits (refused,
    /// never clamped).
    GripLimit,
    /// The gripper is moving: a new grip target (or its calibration, or a
    /// pose save) waits until it rests.
    GripBusy,
}

impl Refusal {
    /// Every refusal (so the longest reply can be sized and tested).
    pub const ALL: [Refusal; 17] = [
        Refusal::Stopped,
        Refusal::Homing,
        Refusal::Busy,
        Refusal::OutsideCalibration,
        Refusal::OutsideWorkspace,
        Refusal::Unreachable,
        Refusal::Singular,
        Refusal::JointLimit(Joint::Base),
        Refusal::JointLimit(Joint::Shoulder),
        Refusal::JointLimit(Joint::Elbow),
        Refusal::SpeedLimit,
        Refusal::Trajectory,
        Refusal::NotFinite,
        Refusal::Fault,
        Refusal::HeldPoseOutside,
        Refusal::GripLimit,
        Refusal::GripBusy,
    ];

    /// Text of the `err <reason>` reply.
    pub fn reason(self) -> crate::text::Text {
        match self {
            Refusal::Stopped => t!("stopped (send resume)"),
            Refusal::Homing => t!("homing"),
            Refusal::Busy => t!("busy moving"),
            Refusal::OutsideCalibration => t!("outside calibrated area"),
            Refusal::OutsideWorkspace => t!("outside workspace"),
            Refusal::Unreachable => t!("unreachable"),
            Refusal::Singular => t!("singular point"),
            Refusal::JointLimit(Joint::Base) => t!("joint limit base"),
            Refusal::JointLimit(Joint::Shoulder) => t!("joint limit shoulder"),
            Refusal::JointLimit(Joint::Elbow) => t!("joint limit elbow"),
            Refusal::SpeedLimit => t!("speed limit needs ts above max"),
            Refusal::Trajectory => t!("trajectory not admissible"),
            Refusal::NotFinite => t!("not finite"),
            Refusal::Fault => t!("fault: setpoint refused, stopped"),
            Refusal::HeldPoseOutside => t!("held pose outside new limits"),
            Refusal::GripLimit => t!("grip limit"),
            Refusal::GripBusy => t!("busy gripping"),
        }
    }
}

impl From<PlanError> for Refusal {
    fn from(e: PlanError) -> Self {
        match e {
            PlanError::SpeedLimit => Refusal::SpeedLimit,
            PlanError::Trajectory => Refusal::Trajectory,
            PlanError::NotFinite => Refusal::NotFinite,
        }
    }
}
