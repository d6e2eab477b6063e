//! Up to four saved poses ("drink", "table": the presets assistive arms
//! offer), kept in the EEPROM beside the configuration and stored the same
//! way: two copies with a sequence number and the CRC-16 of [`super::crc`],
//! each written in the tear-proof three steps of [`super::store`] (the
//! record's byte 0 is the same commit byte), so a save cut by a power loss
//! leaves the poses before it or the new ones, never a mixture.
//!
//! A pose is the three joint angles and the gripper's angle in hundredths
//! of a degree, the units of `goto`, `grip` and `cal show`: a saved pose is
//! reached exactly as the `goto` and the `grip` of those angles would be
//! (same planner, limits and refusals), and what is saved round-trips
//! through the record bit for bit.
//!
//! # Record layout (version 2, little-endian, 75 bytes)
//! | offset | size | field |
//! |-------:|-----:|-------|
//! | 0 | 2 | magic `b"TP"` |
//! | 2 | 1 | layout version (2) |
//! | 3 | 2 | sequence counter (u16, serial arithmetic as the configuration's) |
//! | 5 | 68 | 4 × pose: 1 flag byte (bit 0 used, bit 1 with a gripper angle; other bits 0), then base, shoulder, elbow, gripper as i32 centidegrees (0 where absent) |
//! | 73 | 2 | CRC-16/CCITT-FALSE of bytes 0..73 |
//!
//! Version 1 (before the gripper: 59 bytes, 13 per pose, a used byte 0 or 1
//! and the three joints, its CRC of bytes 0..57 at 57) is still read: its
//! poses have no gripper angle (`pose go` leaves the gripper as it is), and
//! the next save writes version 2. Both fit the 128-byte slot.
//!
//! Copy A lives at [`POSE_SLOT_A`], copy B at [`POSE_SLOT_B`], past the
//! configuration's two 128-byte slots.

use super::crc::crc16;
use super::store::{
    copy, next_write, pick_copy, seal, write_both, RecordError, SaveError, Source, Writer, UNCOMMITTED,
};
use crate::seam::Storage;

/// Saved poses at most.
pub const POSES: usize = 4;
/// A pose's angles within ±360.00°, as `goto` accepts them.
pub const POSE_MAX_CENTIDEG: i32 = 36_000;
/// Bytes of one record, CRC included.
pub const POSE_RECORD_LEN: usize = 75;
/// A version-1 record's length (its CRC at 57).
pub const POSE_RECORD_LEN_V1: usize = 59;
/// EEPROM address of the first copy (the configuration uses 0..256).
pub const POSE_SLOT_A: u16 = 256;
/// EEPROM address of the second copy.
pub const POSE_SLOT_B: u16 = 384;
/// The record's first bytes; byte 0 is the commit byte of [`super::store`].
pub const POSE_MAGIC: [u8; 2] = *b"TP";
/// Layout version of the record.
pub const POSE_VERSION: u8 = 2;

const CRC_AT: usize = POSE_RECORD_LEN - 2;
const FLAG_USED: u8 = 1 << 0;
const FLAG_GRIP: u8 = 1 << 1;
const _: () = assert!(POSE_MAGIC[0] == super::store::MAGIC[0] && UNCOMMITTED != POSE_MAGIC[0]);
const _: () = assert!(POSE_SLOT_A as usize + POSE_RECORD_LEN <= POSE_SLOT_B as usize);
const _: () = assert!(super::store::SLOT_B_ADDR as usize + super::store::RECORD_LEN <= POSE_SLOT_A as usize);

/// One pose, hundredths of a degree.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pose {
    /// Base, shoulder, elbow.
    pub joints: [i32; 3],
    /// The gripper; `None` in a pose saved before the gripper existed.
    pub grip: Option<i32>,
}

impl Pose {
    /// Every angle within ±360°.
    fn in_range(&self) -> bool {
        self.joints.iter().chain(self.grip.iter()).all(|v| v.abs() <= POSE_MAX_CENTIDEG)
    }
}

/// The four pose slots, numbered 1..=4 on the serial line and the screen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Poses {
    /// Slot `n` is `slots[n - 1]`; `None` when empty.
    pub slots: [Option<Pose>; POSES],
}

impl Poses {
    /// No pose saved.
    pub const EMPTY: Poses = Poses { slots: [None; POSES] };

    /// The pose in slot `n` (1..=4), if saved.
    pub fn get(&self, n: u8) -> Option<Pose> {
        self.slots.get(usize::from(n).wrapping_sub(1)).copied().flatten()
    }

    /// Puts `pose` (or nothing) in slot `n` (1..=4); false for another `n`
    /// or an angle beyond ±360°.
    pub fn set(&mut self, n: u8, pose: Option<Pose>) -> bool {
        if pose.is_some_and(|p| !p.in_range()) {
            return false;
        }
        match self.slots.get_mut(usize::from(n).wrapping_sub(1)) {
            Some(slot) => {
                *slot = pose;
                true
            }
            None => false,
        }
    }

    /// Serializes with sequence number `seq`.
    pub fn encode(&self, seq: u16) -> [u8; POSE_RECORD_LEN] {
        let mut buf = [0u8; POSE_RECORD_LEN];
        let mut w = Writer::new(&mut buf);
        w.put(&POSE_MAGIC);
        w.put(&[POSE_VERSION]);
        w.put(&seq.to_le_bytes());
        for slot in self.slots.iter() {
            let flags = match slot {
                None => 0,
                Some(Pose { grip: None, .. }) => FLAG_USED,
                Some(Pose { grip: Some(_), .. }) => FLAG_USED | FLAG_GRIP,
            };
            w.put(&[flags]);
            let (joints, grip) = slot.map_or(([0; 3], 0), |p| (p.joints, p.grip.unwrap_or(0)));
            for v in joints {
                w.put(&v.to_le_bytes());
            }
            w.put(&grip.to_le_bytes());
        }
        seal(&mut buf);
        buf
    }

    /// Parses and validates a record (version 2, or version 1 whose poses
    /// have no gripper angle): magic, version, CRC, then the values (flags
    /// as documented, angles within ±360°, absent values zero). Returns the
    /// sequence number and the poses.
    pub fn decode(buf: &[u8; POSE_RECORD_LEN]) -> Result<(u16, Poses), RecordError> {
        if buf.get(..2) != Some(&POSE_MAGIC[..]) {
            return Err(RecordError::NoMagic);
        }
        let version = buf.get(2).copied().unwrap_or(0);
        // Per version: where the CRC is, and the bytes of one pose.
        let (crc_at, stride) = match version {
            POSE_VERSION => (CRC_AT, 17),
            1 => (POSE_RECORD_LEN_V1 - 2, 13),
            v => return Err(RecordError::Version(v)),
        };
        let (body, rest) = buf.split_at(crc_at);
        if rest.get(..2).is_none_or(|crc| crc16(body).to_le_bytes() != crc) {
            return Err(RecordError::Crc);
        }
        let word = |i: usize| -> i32 {
            let mut w = [0u8; 4];
            if let Some(src) = buf.get(i..i + 4) {
                copy(&mut w, src);
            }
            i32::from_le_bytes(w)
        };
        let seq = u16::from_le_bytes([buf[3], buf[4]]);
        let mut poses = Poses::EMPTY;
        for (k, slot) in poses.slots.iter_mut().enumerate() {
            let at = 5 + k * stride;
            let joints = [0, 1, 2].map(|j| word(at + 1 + 4 * j));
            // Version 1 has no gripper word: absent.
            let grip = if stride == 17 { word(at + 13) } else { 0 };
            let flags = buf.get(at).copied().unwrap_or(0xFF);
            let pose = match flags {
                0 if joints == [0; 3] && grip == 0 => None,
                FLAG_USED if grip == 0 => Some(Pose { joints, grip: None }),
                f if f == FLAG_USED | FLAG_GRIP && stride == 17 => Some(Pose { joints, grip: Some(grip) }),
                _ => return Err(RecordError::Invalid),
            };
            if pose.is_some_and(|p| !p.in_range()) {
                return Err(RecordError::Invalid);
            }
            *slot = pose;
        }
        Ok((seq, poses))
    }
}

/// What [`load`] found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LoadedPoses {
    /// The poses to run with (none when no copy is valid).
    pub poses: Poses,
    /// Which copy they came from.
    pub source: Source,
    /// Sequence number of that copy (0 for none).
    pub seq: u16,
    /// A copy was invalid: erased (never saved), or damaged.
    pub damaged: bool,
}

fn read_slot<S: Storage>(storage: &mut S, addr: u16) -> Result<(u16, Poses), RecordError> {
    let mut buf = [0u8; POSE_RECORD_LEN];
    storage.read(u32::from(addr), &mut buf).map_err(RecordError::Storage)?;
    Poses::decode(&buf)
}

/// Reads both copies and picks the poses the way the configuration's load
/// does (`store::pick`).
pub fn load<S: Storage>(storage: &mut S) -> LoadedPoses {
    let a = read_slot(storage, POSE_SLOT_A);
    let b = read_slot(storage, POSE_SLOT_B);
    let damaged = a.is_err() || b.is_err();
    match pick_copy(&a, &b) {
        Some((source, seq, poses)) => LoadedPoses { poses, source, seq, damaged },
        None => LoadedPoses { poses: Poses::EMPTY, source: Source::Defaults, seq: 0, damaged },
    }
}

/// Writes `poses` to both copies (the one [`load`] does not use first) and
/// returns the new sequence number.
pub fn save<S: Storage>(storage: &mut S, poses: &Poses) -> Result<u16, SaveError> {
    let a = read_slot(storage, POSE_SLOT_A);
    let b = read_slot(storage, POSE_SLOT_B);
    let (seq, order) = next_write(pick_copy(&a, &b).map(|(s, seq, _)| (s, seq)), [POSE_SLOT_A, POSE_SLOT_B]);
    write_both(storage, order, &poses.encode(seq))?;
    Ok(seq)
}
