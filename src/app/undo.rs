//! Undo (issue #20 §2): `undo` (and the screen's Undo button) takes the arm
//! back to the pose it held before the last accepted target or pose, up to
//! [`UNDO_STEPS`] steps, as a target of its own: the same planner, limits
//! and refusals (and the `path`/`lift` setting) as any target.
//!
//! What counts as a step: a target accepted while the arm holds a pose
//! (a touch, `move`, `goto`, `pose go`, `park`) leaves that pose behind,
//! once its plan (or its path check) has accepted it; a refused target
//! leaves nothing. A target while the arm moves changes the running move's
//! course, so the pose held before that move stays the step to undo. A
//! circle ends where it started and leaves nothing; a calibration slew is
//! not a target. An undo takes its step off once its own move is accepted,
//! and leaves none behind, so two undos go two steps back, never back and
//! forth. The oldest step is forgotten beyond [`UNDO_STEPS`]; a reset
//! forgets them all (they are not stored).
//!
//! Refused while STOP is latched (`stopped (send resume)`: an undo never
//! starts motion behind a STOP) and when no step is left (`nothing to
//! undo`). The gripper is not undone: an undo moves the arm only (a hand
//! that opened by itself could drop what it holds), and when the gripper
//! stands elsewhere than when the step was taken the reply says so
//! (`grip kept <deg>`).

use super::refusal::Refusal;
use super::{App, MoveKind};
use crate::motion::plan::JOINTS;

/// Steps kept.
pub const UNDO_STEPS: usize = 4;

/// The gripper counts as moved beyond half a hundredth of a degree (the
/// resolution of `grip` and of its reply).
const GRIP_SAME_RAD: f32 = 0.5 * 0.01 * core::f32::consts::PI / 180.0;

/// The poses to go back to, and what the move being planned will do to them.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Undo {
    /// Held poses (rad), oldest first; `len` of them are used.
    poses: [[f32; JOINTS]; UNDO_STEPS],
    /// The gripper's commanded angle when each pose was left (rad).
    grips: [f32; UNDO_STEPS],
    len: u8,
    /// Applied when the accepted target's plan or check decides.
    pending: Pending,
    /// The last undo left the gripper at this angle (rad), not where its
    /// step was taken: its reply says so.
    grip_kept: Option<f32>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Pending {
    Nothing,
    /// A target from rest: this pose (and gripper angle) becomes a step.
    Push([f32; JOINTS], f32),
    /// An undo: its step comes off.
    Pop,
}

impl Undo {
    /// No step.
    pub(super) const EMPTY: Undo = Undo {
        poses: [[0.0; JOINTS]; UNDO_STEPS],
        grips: [0.0; UNDO_STEPS],
        len: 0,
        pending: Pending::Nothing,
        grip_kept: None,
    };

    /// Steps left.
    pub(super) fn left(&self) -> u8 {
        self.len
    }

    /// Where the last undo left the gripper, if not where its step was
    /// taken (rad).
    pub(super) fn grip_kept(&self) -> Option<f32> {
        self.grip_kept
    }

    fn last(&self) -> Option<(&[f32; JOINTS], f32)> {
        let i = usize::from(self.len).checked_sub(1)?;
        Some((self.poses.get(i)?, *self.grips.get(i)?))
    }

    fn push(&mut self, pose: &[f32; JOINTS], grip: f32) {
        if usize::from(self.len) == UNDO_STEPS {
            self.poses.copy_within(1.., 0);
            self.grips.copy_within(1.., 0);
            self.len -= 1;
        }
        if let (Some(p), Some(g)) =
            (self.poses.get_mut(usize::from(self.len)), self.grips.get_mut(usize::from(self.len)))
        {
            *p = *pose;
            *g = grip;
            self.len += 1;
        }
    }
}

impl App {
    /// An accepted target (`machine::accept`): from rest it leaves the held
    /// pose behind, once its verdict is in ([`App::undo_verdict`]).
    pub(super) fn undo_note_target(&mut self, kind: MoveKind) {
        let from_rest = self.track.is_done() && !self.path_busy();
        self.undo.pending = match kind {
            MoveKind::Circle { .. } => Pending::Nothing,
            _ if from_rest => Pending::Push(self.commanded, self.grip_angle()),
            _ => Pending::Nothing,
        };
    }

    /// The accepted target's plan or path check decided (`answer_plan`).
    pub(super) fn undo_verdict(&mut self, accepted: bool) {
        let pending = core::mem::replace(&mut self.undo.pending, Pending::Nothing);
        if !accepted {
            return;
        }
        match pending {
            Pending::Nothing => {}
            Pending::Push(pose, grip) => self.undo.push(&pose, grip),
            Pending::Pop => {
                if let Some((_, grip)) = self.undo.last() {
                    let now = self.grip_angle();
                    self.undo.grip_kept = ((now - grip).abs() > GRIP_SAME_RAD).then_some(now);
                }
                self.undo.len = self.undo.len.saturating_sub(1);
            }
        }
    }

    /// `undo`: a target to the last step's pose (module doc).
    pub(super) fn undo(&mut self) -> Result<(), Refusal> {
        let r = self.start_undo();
        if let Err(e) = r {
            self.last_refusal = Some(e);
        }
        r
    }

    fn start_undo(&mut self) -> Result<(), Refusal> {
        if self.stopped {
            return Err(Refusal::Stopped);
        }
        let target = *self.undo.last().ok_or(Refusal::NothingToUndo)?.0;
        self.start_move(&target, None)?;
        self.undo.pending = Pending::Pop;
        Ok(())
    }
}
