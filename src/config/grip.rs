//! The gripper's calibration, in its own EEPROM record beside the
//! configuration's and the poses', stored the same way: two copies with a
//! sequence number and the CRC-16 of [`super::crc`], each written in the
//! tear-proof three steps of [`super::store`] (byte 0 is the same commit
//! byte), so a save cut by a power loss leaves the calibration before it or
//! the new one, never a mixture.
//!
//! Its own record rather than more fields in the configuration's: that
//! record's 128-byte slot is nearly full, and a separate record needs no
//! migration of the configuration (whose older versions stay readable as
//! they are); a configuration saved before the gripper existed simply finds
//! no gripper record and runs with [`GRIP_DEFAULT`].
//!
//! The gripper is calibrated like a joint ([`JointCal`]: offset, scale,
//! pulse and angle limits, speed and acceleration limits, the same
//! validation). Its angle is the servo's, in its own convention; **open is
//! the lower angle limit (`min_deg`), closed the upper one (`max_deg`)**,
//! so one pair of limits bounds every command and names both ends (a
//! gripper that closes toward shorter pulses gets a negative scale).
//!
//! # Record layout (version 1, little-endian, 35 bytes)
//! | offset | size | field |
//! |-------:|-----:|-------|
//! | 0 | 2 | magic `b"TG"` |
//! | 2 | 1 | layout version (1) |
//! | 3 | 2 | sequence counter (u16, serial arithmetic as the configuration's) |
//! | 5 | 28 | `offset_us` f32, `us_per_rad` f32, `min_us` u16, `max_us` u16, `min_rad` f32, `max_rad` f32, `max_speed_rad_s` f32, `max_accel_rad_s2` f32 |
//! | 33 | 2 | CRC-16/CCITT-FALSE of bytes 0..33 |
//!
//! Copy A lives at [`GRIP_SLOT_A`], copy B at [`GRIP_SLOT_B`], past the
//! poses' two 128-byte slots.

use super::crc::crc16;
use super::store::{
    next_write, pick_copy, seal, write_both, Reader, RecordError, SaveError, Source, Writer, UNCOMMITTED,
};
use crate::seam::Storage;
use crate::servo::map::JointCal;

/// Bytes of one record, CRC included.
pub const GRIP_RECORD_LEN: usize = 35;
/// EEPROM address of the first copy (the poses use 256..512).
pub const GRIP_SLOT_A: u16 = 512;
/// EEPROM address of the second copy.
pub const GRIP_SLOT_B: u16 = 640;
/// The record's first bytes; byte 0 is the commit byte of [`super::store`].
pub const GRIP_MAGIC: [u8; 2] = *b"TG";
/// Layout version of the record.
pub const GRIP_VERSION: u8 = 1;

const CRC_AT: usize = GRIP_RECORD_LEN - 2;
const _: () = assert!(GRIP_MAGIC[0] == super::store::MAGIC[0] && UNCOMMITTED != GRIP_MAGIC[0]);
const _: () = assert!(super::poses::POSE_SLOT_B as usize + 128 <= GRIP_SLOT_A as usize);
const _: () = assert!(GRIP_SLOT_A as usize + GRIP_RECORD_LEN <= GRIP_SLOT_B as usize);

const PI: f32 = core::f32::consts::PI;

/// The gripper's default calibration: a 180° hobby servo as the joints'
/// defaults (600 µs at 0°, 10 µs per degree), used over 0..90° (open at 0°
/// = 600 µs, closed at 90° = 1500 µs: what a servo claw of the SG90 class
/// travels), at the joints' default speed and acceleration limits.
pub const GRIP_DEFAULT: JointCal = JointCal {
    offset_us: 600.0,
    us_per_rad: 1800.0 / PI,
    min_us: 600,
    max_us: 1500,
    min_rad: 0.0,
    max_rad: PI / 2.0,
    max_speed_rad_s: JointCal::BASE_DEFAULT.max_speed_rad_s,
    max_accel_rad_s2: JointCal::BASE_DEFAULT.max_accel_rad_s2,
};

/// Serializes `cal` with sequence number `seq`.
pub fn encode(cal: &JointCal, seq: u16) -> [u8; GRIP_RECORD_LEN] {
    let mut buf = [0u8; GRIP_RECORD_LEN];
    let mut w = Writer::new(&mut buf);
    w.put(&GRIP_MAGIC);
    w.put(&[GRIP_VERSION]);
    w.put(&seq.to_le_bytes());
    w.put_joint(cal);
    w.put(&cal.max_accel_rad_s2.to_le_bytes());
    seal(&mut buf);
    buf
}

/// Parses and validates a record: magic, version, CRC, then the calibration
/// ([`JointCal::validate`]). Returns the sequence number and the calibration.
pub fn decode(buf: &[u8; GRIP_RECORD_LEN]) -> Result<(u16, JointCal), RecordError> {
    if buf.get(..2) != Some(&GRIP_MAGIC[..]) {
        return Err(RecordError::NoMagic);
    }
    let version = buf.get(2).copied().unwrap_or(0);
    if version != GRIP_VERSION {
        return Err(RecordError::Version(version));
    }
    let (body, crc) = buf.split_at(CRC_AT);
    if crc16(body).to_le_bytes() != crc {
        return Err(RecordError::Crc);
    }
    let mut r = Reader::at(buf, 3);
    let seq = u16::from_le_bytes(r.take());
    let mut cal = GRIP_DEFAULT;
    r.take_joint(&mut cal);
    cal.max_accel_rad_s2 = f32::from_le_bytes(r.take());
    cal.validate().map_err(|_| RecordError::Invalid)?;
    Ok((seq, cal))
}

/// What [`load`] found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoadedGrip {
    /// The calibration to run with ([`GRIP_DEFAULT`] when no copy is valid).
    pub cal: JointCal,
    /// Which copy it came from.
    pub source: Source,
    /// Sequence number of that copy (0 for none).
    pub seq: u16,
    /// A copy was invalid for another reason than never having been written
    /// (a damaged copy, or both: the defaults stand in).
    pub damaged: bool,
}

fn read_slot<S: Storage>(storage: &mut S, addr: u16) -> Result<(u16, JointCal), RecordError> {
    let mut buf = [0u8; GRIP_RECORD_LEN];
    storage.read(u32::from(addr), &mut buf).map_err(RecordError::Storage)?;
    decode(&buf)
}

/// Reads both copies and picks the calibration the way the configuration's
/// load does (`store::pick`).
pub fn load<S: Storage>(storage: &mut S) -> LoadedGrip {
    let a = read_slot(storage, GRIP_SLOT_A);
    let b = read_slot(storage, GRIP_SLOT_B);
    let bad = |r: &Result<(u16, JointCal), RecordError>| matches!(r, Err(e) if *e != RecordError::NoMagic);
    let damaged = bad(&a) || bad(&b);
    match pick_copy(&a, &b) {
        Some((source, seq, cal)) => LoadedGrip { cal, source, seq, damaged },
        None => LoadedGrip { cal: GRIP_DEFAULT, source: Source::Defaults, seq: 0, damaged },
    }
}

/// Writes `cal` to both copies (the one [`load`] does not use first) and
/// returns the new sequence number. An invalid calibration is not written.
pub fn save<S: Storage>(storage: &mut S, cal: &JointCal) -> Result<u16, SaveError> {
    cal.validate().map_err(|e| SaveError::Invalid(super::settings::ConfigError::Grip(e)))?;
    let a = read_slot(storage, GRIP_SLOT_A);
    let b = read_slot(storage, GRIP_SLOT_B);
    let (seq, order) = next_write(pick_copy(&a, &b).map(|(s, seq, _)| (s, seq)), [GRIP_SLOT_A, GRIP_SLOT_B]);
    write_both(storage, order, &encode(cal, seq))?;
    Ok(seq)
}
