//! The saved poses over serial (`pose save|go|clear <n>`, `pose list`):
//! kept in RAM from boot, every change stored at once in the EEPROM
//! (`config::poses`: two copies, the configuration's CRC, tear-proof).
//!
//! A pose is the pose commanded when it was saved, the gripper's angle
//! included, in centidegrees; `pose go` is the `goto` of those angles and
//! the `grip` of the gripper's, so it goes through the same state checks,
//! joint and gripper limits, planner and refusals as every target (a touch
//! included), and its reply is `goto`'s. Both are checked before either
//! moves; the gripper waits for the arm's verdict (its plan, or under `path
//! line` or a lift its check, some frames later), so a refused pose moves
//! neither; its plan follows in the next frame that may plan (one plan a
//! frame, none in a catch-up frame, `grip.rs`), and should it fail a `warn
//! pose <n> grip <reason>` line says so. A pose saved before the gripper
//! existed leaves the gripper as it is. Saving is refused while the arm or
//! the gripper moves or the arm homes (no pose is held then); while STOP is
//! latched the held pose is saved. Clearing is refused while the arm moves
//! (`busy moving`), as `cal save` is: an EEPROM write blocks the frame for
//! 3.4 ms a changed byte, tens of them for a slot, which would stall a
//! running move's pulses for several periods.

use super::refusal::Refusal;
use super::text::Line;
use super::{App, Mode};
use crate::config::poses::{self, Pose};
use crate::math::units::{centideg_to_rad, rad_to_centideg};
use crate::protocol::command::PoseCmd;
use crate::seam::Storage;

impl App {
    /// Carries out a `pose` command.
    pub(super) fn pose<E: Storage>(&mut self, cmd: PoseCmd, storage: &mut E) -> Result<PoseDone, Refusal> {
        match cmd {
            PoseCmd::List => Ok(PoseDone::List),
            PoseCmd::Go(n) => match self.poses.get(n) {
                Some(p) => self.pose_go(n, &p),
                None => Ok(PoseDone::Empty(n)),
            },
            PoseCmd::Save(n) => {
                if self.is_moving() {
                    return Err(Refusal::Busy);
                }
                if matches!(self.mode, Mode::Homing { .. } | Mode::Boot) {
                    return Err(Refusal::Homing);
                }
                if self.grip.is_moving() {
                    return Err(Refusal::GripBusy);
                }
                let held = Pose {
                    joints: self.commanded.map(rad_to_centideg),
                    grip: Some(rad_to_centideg(self.grip_angle())),
                };
                Ok(PoseDone::Stored(n, true, self.store_pose(storage, n, Some(held))))
            }
            PoseCmd::Clear(n) => {
                // The EEPROM write would stall a running move (module doc).
                if self.is_moving() {
                    return Err(Refusal::Busy);
                }
                Ok(PoseDone::Stored(n, false, self.store_pose(storage, n, None)))
            }
        }
    }

    /// `pose go <n>`: the gripper's target checked, then the arm's accepted,
    /// then the gripper's (a gripper already there is left alone).
    fn pose_go(&mut self, n: u8, p: &Pose) -> Result<PoseDone, Refusal> {
        let grip = match p.grip {
            Some(c) if c != rad_to_centideg(self.grip_angle()) => Some(self.check_grip(centideg_to_rad(c))?),
            _ => None,
        };
        self.move_to_angles(&p.joints)?;
        if let Some(g) = grip {
            self.pose_grip_due(g, n);
        }
        Ok(PoseDone::Went(n))
    }

    /// Slot `n` := `pose`, stored; the RAM copy changes only once stored.
    fn store_pose<E: Storage>(&mut self, storage: &mut E, n: u8, pose: Option<Pose>) -> Result<u16, PoseStoreError> {
        let mut next = self.poses;
        if !next.set(n, pose) {
            return Err(PoseStoreError::Range);
        }
        let seq = poses::save(storage, &next).map_err(PoseStoreError::Save)?;
        self.poses = next;
        Ok(seq)
    }

    /// `ok pose list` and each slot: `<n> <base> <shoulder> <elbow> grip
    /// <gripper>` in degrees with two decimals (no `grip …` for a pose saved
    /// before the gripper existed), or `<n> empty`.
    #[cfg_attr(target_arch = "avr", optimize(size))] // reason: cold
    pub(super) fn pose_list(&self, r: &mut Line) {
        r.str(t!("ok pose list"));
        for (k, slot) in self.poses.slots.iter().enumerate() {
            r.bytes(b" ").u32(k as u32 + 1);
            match slot {
                Some(p) => {
                    for v in p.joints {
                        r.bytes(b" ").centi(v);
                    }
                    if let Some(g) = p.grip {
                        r.word(t!("grip")).bytes(b" ").centi(g);
                    }
                }
                None => {
                    r.word(t!("empty"));
                }
            }
        }
    }
}

/// What a `pose` command did, for its reply (formatted with the others',
/// in `serial.rs`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum PoseDone {
    /// `pose save|clear <n>` (true for save) and how storing went.
    Stored(u8, bool, Result<u16, PoseStoreError>),
    /// `pose go <n>`, planned.
    Went(u8),
    /// `pose go <n>` of an empty slot.
    Empty(u8),
    /// `pose list`.
    List,
}

/// Why a pose was not stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum PoseStoreError {
    /// An angle beyond ±360° (a held pose never is; kept for the record's rule).
    Range,
    /// The EEPROM save failed.
    Save(crate::config::store::SaveError),
}
