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
    /// A path (line or circle) from here is empty or runs through the base
    /// axis, where the base would have to turn by half a turn at once.
    PathShape,
    /// A point of the path is out of the arm's reach.
    PathUnreachable,
    /// The path meets a singular pose (base axis, arm straight or folded).
    PathSingular,
    /// A joint would leave its angle limits somewhere along the path.
    PathJointLimit(Joint),
    /// The joints' speed and acceleration limits need a path move longer
    /// than the longest move.
    PathTooSlow,
    /// The papers' own ζ-a-tₛ changes shape with tₛ: not offered for paths.
    PathLaw,
    /// STOP came while the path was being checked: the move never started.
    PathStopped,
    /// `undo` with no step left (`undo.rs`).
    NothingToUndo,
    /// The pose held now (or a line's target pose) is not the IK's solution
    /// of its effector point: on the other elbow branch, or a joint past the
    /// IK's range; a path from it would start (or end) with a jump.
    PathBranch,
    /// The lift's via pose is out of the arm's reach.
    LiftViaUnreachable,
    /// A joint would leave its angle limits on the lift (at the via pose or
    /// where the two terms overshoot).
    LiftJointLimit(Joint),
    /// The joints' limits need a lift longer than the longest move.
    LiftTooSlow,
    /// `lift` with `path line`, or `path line` with a lift: one at a time.
    LiftWithLine,
    /// The carer lock hides what this changes (`access.rs`).
    Locked,
    /// `access unlock` with a PIN that is not the one set.
    WrongPin,
    /// `access unlock` after three wrong PINs, within the wait.
    PinWait,
    /// `access lock` (or the screen's gesture) with no PIN set.
    NoPin,
}

impl Refusal {
    /// Every refusal (so the longest reply can be sized and tested).
    pub const ALL: [Refusal; 38] = [
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
        Refusal::PathShape,
        Refusal::PathUnreachable,
        Refusal::PathSingular,
        Refusal::PathJointLimit(Joint::Base),
        Refusal::PathJointLimit(Joint::Shoulder),
        Refusal::PathJointLimit(Joint::Elbow),
        Refusal::PathTooSlow,
        Refusal::PathLaw,
        Refusal::PathStopped,
        Refusal::NothingToUndo,
        Refusal::PathBranch,
        Refusal::LiftViaUnreachable,
        Refusal::LiftJointLimit(Joint::Base),
        Refusal::LiftJointLimit(Joint::Shoulder),
        Refusal::LiftJointLimit(Joint::Elbow),
        Refusal::LiftTooSlow,
        Refusal::LiftWithLine,
        Refusal::Locked,
        Refusal::WrongPin,
        Refusal::PinWait,
        Refusal::NoPin,
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
            Refusal::Fault => t!("fault: bad setpoint, stopped"),
            Refusal::HeldPoseOutside => t!("held pose outside new limits"),
            Refusal::GripLimit => t!("grip limit"),
            Refusal::GripBusy => t!("busy gripping"),
            Refusal::PathShape => t!("path empty or through base axis"),
            Refusal::PathUnreachable => t!("path leaves reach"),
            Refusal::PathSingular => t!("path meets singular pose"),
            Refusal::PathJointLimit(Joint::Base) => t!("path joint limit base"),
            Refusal::PathJointLimit(Joint::Shoulder) => t!("path joint limit shoulder"),
            Refusal::PathJointLimit(Joint::Elbow) => t!("path joint limit elbow"),
            Refusal::PathTooSlow => t!("path needs ts above max"),
            Refusal::PathLaw => t!("path: law zat-paper not offered"),
            Refusal::PathStopped => t!("path check stopped"),
            Refusal::NothingToUndo => t!("nothing to undo"),
            Refusal::PathBranch => t!("path pose off IK range"),
            Refusal::LiftViaUnreachable => t!("lift via pose unreachable"),
            Refusal::LiftJointLimit(Joint::Base) => t!("lift joint limit base"),
            Refusal::LiftJointLimit(Joint::Shoulder) => t!("lift joint limit shoulder"),
            Refusal::LiftJointLimit(Joint::Elbow) => t!("lift joint limit elbow"),
            Refusal::LiftTooSlow => t!("lift needs ts above max"),
            Refusal::LiftWithLine => t!("lift and path line exclusive"),
            Refusal::Locked => t!("locked"),
            Refusal::WrongPin => t!("wrong pin"),
            Refusal::PinWait => t!("wrong pin 3 times: wait 30 s"),
            Refusal::NoPin => t!("no pin set (access pin <digits>)"),
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
