//! Persistent configuration in the ATmega2560's 4 KiB EEPROM.
//!
//! # Record layout (version 8, little-endian, 127 bytes)
//! | offset | size | field |
//! |-------:|-----:|-------|
//! | 0  | 2  | magic `b"TA"` |
//! | 2  | 1  | layout version (8) |
//! | 3  | 2  | sequence counter (u16, wraps; compared by serial arithmetic) |
//! | 5  | 72 | 3 × joint (base, shoulder, elbow), 24 bytes each: `offset_us` f32, `us_per_rad` f32, `min_us` u16, `max_us` u16, `min_rad` f32, `max_rad` f32, `max_speed_rad_s` f32 |
//! | 77 | 8  | touch `x_min`, `x_max`, `y_min`, `y_max` u16 |
//! | 85 | 1  | touch flags: bit 0 swap, bit 1 invert_x, bit 2 invert_y (other bits 0) |
//! | 86 | 1  | speed preset id ([`SpeedPreset`]) |
//! | 87 | 1  | motion law id ([`LawKind::id`]) |
//! | 88 | 12 | 3 × joint `max_accel_rad_s2` f32 (version 2) |
//! | 100 | 1 | touch wiring id ([`Wiring::id`]; 0 = none identified yet) (version 3) |
//! | 101 | 1 | path mode id ([`PathMode::id`]: 0 joint, 1 line) (version 4) |
//! | 102 | 1 | lift, hundredths of a workspace unit, 1..=50; 0 = off; never with line (version 4) |
//! | 103 | 1 | touch `hold`, hundredths of a second, 4..=200 (version 5) |
//! | 104 | 1 | touch `repeat`, hundredths of a second, 0..=200 (version 5) |
//! | 105 | 1 | touch cancel `radius`, ADC counts, 20..=255 (version 5) |
//! | 106 | 4 | arm `l2`, `l3` u16, hundredths of a millimetre, 1000..=65000, at most 4× apart (version 6) |
//! | 110 | 6 | home pose: base, shoulder, elbow i16, hundredths of a degree (version 6) |
//! | 116 | 6 | park pose, as home (version 6) |
//! | 122 | 1 | touch mode: 0 `tap`, 1 `hold` (version 7) |
//! | 123 | 2 | touch `plate` ratio u16, 256 = 1, 64..=1024; 0 = not measured (version 8) |
//! | 125 | 2 | CRC-16/CCITT-FALSE of bytes 0..125 |
//!
//! Older records are still read, and the next save writes version 8:
//! - version 7 (before the panel's plate ratio) ends with its CRC of bytes
//!   0..123 at 123; it reads with the ratio not measured (the
//!   second-contact check by the ratio off until a touch calibration);
//! - version 6 (before hold to run) ends with its CRC of bytes 0..122 at
//!   122; it reads with `mode tap`;
//! - version 5 (before the arm's own geometry) ends with its CRC of bytes
//!   0..106 at 106; it reads with the default [`ArmSettings`] (equal links,
//!   home and park at 90°, 90°, −90°);
//! - version 4 (before the touch's hold, repeat and radius) ends with its
//!   CRC of bytes 0..103 at 103; it reads with the default
//!   [`PressSettings`];
//! - version 3 (before the path and lift settings) ends with its CRC of
//!   bytes 0..101 at 101; it reads with joint moves and no lift;
//! - version 2 (before the measured wiring) ends with its CRC of bytes
//!   0..100 at 100; it reads with no wiring either, so the firmware probes
//!   the panel at boot;
//! - version 1 (before acceleration limits) ends with its CRC of bytes 0..88
//!   at 88; it reads with the default acceleration limits
//!   ([`JointCal::DEFAULTS`]) too.
//!
//! Every version before 5 reads with the default [`PressSettings`], every
//! version before 6 with the default [`ArmSettings`], every version before 7
//! with `mode tap`, every version before 8 with no plate ratio.
//!
//! Floats are stored as their IEEE-754 bit patterns (`to_le_bytes`), so a
//! record is bit-identical on the chip and on the host.
//!
//! # Two copies
//! Copy A lives at [`SLOT_A_ADDR`], copy B at [`SLOT_B_ADDR`]. [`save`] writes the
//! new record (sequence + 1) to both, **first to the slot [`load`] would not
//! pick, then to the other** (one function, [`pick`], decides for both, ties
//! included), verifying each by reading it back. A power loss while writing
//! the first slot leaves the picked slot's copy intact; a loss while writing
//! the second leaves the first slot's complete new copy, which has the higher
//! sequence number.
//!
//! # Tear-proof by construction
//! Byte 0 (the magic's `T`) is the record's commit byte, and a slot is written
//! in three steps: byte 0 := [`UNCOMMITTED`] (≠ `T`) if it reads `T` (left alone
//! otherwise), then bytes 1..126 (body and CRC), then byte 0 := `T`. A power
//! loss tears at most the one byte being written; whatever value that byte is
//! left with:
//! - during step 1 the body is untouched and byte 0 read `T` before: the slot
//!   holds its old content unchanged, or nothing valid (were byte 0 rewritten
//!   when it was not `T`, a tear could turn it into `T` and commit a stale body
//!   left by an earlier interrupted save);
//! - during step 2 byte 0 is [`UNCOMMITTED`], so the slot is invalid whatever
//!   the body holds;
//! - during step 3 the body and CRC are complete: the slot is the complete new
//!   record if byte 0 came out `T`, else invalid.
//!
//! So a slot is never read as a mixture of two records; the CRC is left to
//! catch what it is for (cells that decay or are overwritten), not tears.
//! [`load`] takes the copy [`pick`] chooses; with no valid copy it returns the
//! defaults and a [`Warning`].

use super::crc::crc16;
use super::settings::{ArmSettings, Config, ConfigError, PathMode, PressSettings, SpeedPreset, LIFT_MAX_CENTI};
use crate::motion::plan::LawKind;
use crate::seam::{Storage, StorageError};
use crate::servo::map::JointCal;
use crate::touch::map::Calibration;
use crate::touch::wiring::Wiring;

/// EEPROM size of the ATmega2560.
pub const EEPROM_SIZE: u16 = 4096;
/// Bytes of one record, CRC included.
pub const RECORD_LEN: usize = 127;
/// A version-7 record's length (its CRC at 123).
const RECORD_LEN_V7: usize = 125;
/// A version-6 record's length (its CRC at 122).
const RECORD_LEN_V6: usize = 124;
/// A version-5 record's length (its CRC at 106).
const RECORD_LEN_V5: usize = 108;
/// A version-4 record's length (its CRC at 103).
const RECORD_LEN_V4: usize = 105;
/// A version-3 record's length (its CRC at 101).
const RECORD_LEN_V3: usize = 103;
/// A version-2 record's length (its CRC at 100).
const RECORD_LEN_V2: usize = 102;
/// A version-1 record's length (its CRC at 88).
const RECORD_LEN_V1: usize = 90;
/// EEPROM address of the first copy.
pub const SLOT_A_ADDR: u16 = 0;
/// Leaves room for the record to grow to 128 bytes.
pub const SLOT_B_ADDR: u16 = 128;
/// The record's first bytes: tells a written slot from erased or foreign
/// contents.
pub const MAGIC: [u8; 2] = *b"TA";
/// Layout version of the record written; versions 1 to 7 are still read
/// (see the module doc), any other is not.
pub const VERSION: u8 = 8;

const CRC_OFFSET: usize = RECORD_LEN - 2;
/// Byte 0 of a slot while its record is being written: anything but `MAGIC[0]`.
pub const UNCOMMITTED: u8 = 0x00;
const _: () = assert!(UNCOMMITTED != MAGIC[0]);
const _: () = assert!(SLOT_A_ADDR as usize + RECORD_LEN <= SLOT_B_ADDR as usize);
const FLAG_SWAP: u8 = 1 << 0;
const FLAG_INVERT_X: u8 = 1 << 1;
const FLAG_INVERT_Y: u8 = 1 << 2;

impl Config {
    /// Serializes with sequence number `seq`.
    pub fn encode(&self, seq: u16) -> [u8; RECORD_LEN] {
        let mut buf = [0u8; RECORD_LEN];
        let mut w = Writer::new(&mut buf);
        w.put(&MAGIC);
        w.put(&[VERSION]);
        w.put(&seq.to_le_bytes());
        for j in self.joints.iter() {
            w.put_joint(j);
        }
        let t = &self.touch;
        for v in [t.x_min, t.x_max, t.y_min, t.y_max] {
            w.put(&v.to_le_bytes());
        }
        let mut flags = 0u8;
        if t.swap_xy {
            flags |= FLAG_SWAP;
        }
        if t.invert_x {
            flags |= FLAG_INVERT_X;
        }
        if t.invert_y {
            flags |= FLAG_INVERT_Y;
        }
        w.put(&[flags, self.speed.id(), self.law.id()]);
        for j in self.joints.iter() {
            w.put(&j.max_accel_rad_s2.to_le_bytes());
        }
        w.put(&[self.wiring.map_or(0, Wiring::id), self.path.id(), self.lift_centi.unwrap_or(0)]);
        let p = &self.press;
        w.put(&[p.hold_cs, p.repeat_cs, p.radius]);
        let a = &self.arm;
        w.put(&a.l2_cmm.to_le_bytes());
        w.put(&a.l3_cmm.to_le_bytes());
        for v in a.home.iter().chain(a.park.iter()) {
            w.put(&v.to_le_bytes());
        }
        w.put(&[u8::from(self.hold_to_run)]);
        w.put(&p.plate.to_le_bytes());
        seal(&mut buf);
        buf
    }

    /// Parses and validates a record (version 8; 7 without a plate ratio; 6 also with `mode tap`; 5 also with the default arm
    /// settings; 4 also with the default touch hold, repeat and radius; 3 also with joint moves and no lift; 2 also
    /// without a wiring; 1 also with the default acceleration limits). Checks, in order: magic, version, CRC, field values.
    #[cfg_attr(target_arch = "avr", optimize(size))] // reason: cold
    pub fn decode(buf: &[u8; RECORD_LEN]) -> Result<Record, RecordError> {
        let mut r = Reader::at(buf, 0);
        if r.take::<2>() != MAGIC {
            return Err(RecordError::NoMagic);
        }
        let [version] = r.take::<1>();
        let crc_at = match version {
            VERSION => CRC_OFFSET,
            7 => RECORD_LEN_V7 - 2,
            6 => RECORD_LEN_V6 - 2,
            5 => RECORD_LEN_V5 - 2,
            4 => RECORD_LEN_V4 - 2,
            3 => RECORD_LEN_V3 - 2,
            2 => RECORD_LEN_V2 - 2,
            1 => RECORD_LEN_V1 - 2,
            v => return Err(RecordError::Version(v)),
        };
        let (body, rest) = buf.split_at(crc_at);
        if rest.get(..2).is_none_or(|stored| crc16(body).to_le_bytes() != stored) {
            return Err(RecordError::Crc);
        }
        let seq = u16::from_le_bytes(r.take());
        let mut joints = JointCal::DEFAULTS;
        for j in joints.iter_mut() {
            r.take_joint(j);
        }
        let x_min = u16::from_le_bytes(r.take());
        let x_max = u16::from_le_bytes(r.take());
        let y_min = u16::from_le_bytes(r.take());
        let y_max = u16::from_le_bytes(r.take());
        let [flags, speed, law] = r.take::<3>();
        if flags & !(FLAG_SWAP | FLAG_INVERT_X | FLAG_INVERT_Y) != 0 {
            return Err(RecordError::Invalid);
        }
        let (Some(speed), Some(law)) = (SpeedPreset::from_id(speed), LawKind::from_id(law)) else {
            return Err(RecordError::Invalid);
        };
        if version >= 2 {
            for j in joints.iter_mut() {
                j.max_accel_rad_s2 = f32::from_le_bytes(r.take());
            }
        }
        let wiring = match version {
            VERSION | 7 | 6 | 5 | 4 | 3 => match r.take::<1>() {
                [0] => None,
                [id] => Some(Wiring::from_id(id).ok_or(RecordError::Invalid)?),
            },
            _ => None,
        };
        let (mut path, mut lift_centi) = (PathMode::Joint, None);
        if version >= 4 {
            let [p, h] = r.take::<2>();
            path = PathMode::from_id(p).ok_or(RecordError::Invalid)?;
            lift_centi = match h {
                0 => None,
                h if h <= LIFT_MAX_CENTI && path == PathMode::Joint => Some(h),
                _ => return Err(RecordError::Invalid),
            };
        }
        let mut press = PressSettings::DEFAULT;
        if version >= 5 {
            let [hold_cs, repeat_cs, radius] = r.take::<3>();
            press = PressSettings { hold_cs, repeat_cs, radius, plate: 0 };
        }
        let mut arm = ArmSettings::DEFAULT;
        if version >= 6 {
            arm.l2_cmm = u16::from_le_bytes(r.take());
            arm.l3_cmm = u16::from_le_bytes(r.take());
            for v in arm.home.iter_mut().chain(arm.park.iter_mut()) {
                *v = i16::from_le_bytes(r.take());
            }
        }
        let hold_to_run = match version {
            VERSION | 7 => match r.take::<1>() {
                [0] => false,
                [1] => true,
                _ => return Err(RecordError::Invalid),
            },
            _ => false,
        };
        if version == VERSION {
            // Ranged by `validate` below.
            press.plate = u16::from_le_bytes(r.take());
        }
        let config = Config {
            joints,
            touch: Calibration {
                x_min,
                x_max,
                y_min,
                y_max,
                swap_xy: flags & FLAG_SWAP != 0,
                invert_x: flags & FLAG_INVERT_X != 0,
                invert_y: flags & FLAG_INVERT_Y != 0,
            },
            speed,
            law,
            wiring,
            path,
            lift_centi,
            press,
            arm,
            hold_to_run,
        };
        config.validate().map_err(|_| RecordError::Invalid)?;
        Ok(Record { seq, config })
    }
}

/// Copies `src` into `dst` (as many bytes as the shorter holds), for every
/// record's encode and decode. Not `copy_from_slice`: out of line (the
/// firmware's inline threshold is 0), its length check keeps a panic
/// location in static RAM per call site, for lengths that always match
/// here.
pub fn copy(dst: &mut [u8], src: &[u8]) {
    for (d, s) in dst.iter_mut().zip(src) {
        *d = *s;
    }
}

/// Writes a record's fields in order, little-endian, for every record
/// stored this way (configuration, poses, gripper); bytes past the end are
/// dropped (each layout is sized so none are).
pub(super) struct Writer<'a> {
    buf: &'a mut [u8],
    pos: usize,
}

impl<'a> Writer<'a> {
    pub(super) fn new(buf: &'a mut [u8]) -> Self {
        Writer { buf, pos: 0 }
    }

    pub(super) fn put(&mut self, bytes: &[u8]) {
        let end = self.pos + bytes.len();
        if let Some(dst) = self.buf.get_mut(self.pos..end) {
            copy(dst, bytes);
        }
        self.pos = end;
    }

    /// A joint's calibration up to its speed limit (24 bytes): the block
    /// the configuration's version 1 has per joint; its acceleration limit
    /// goes where each layout puts it.
    pub(super) fn put_joint(&mut self, j: &JointCal) {
        self.put(&j.offset_us.to_le_bytes());
        self.put(&j.us_per_rad.to_le_bytes());
        self.put(&j.min_us.to_le_bytes());
        self.put(&j.max_us.to_le_bytes());
        self.put(&j.min_rad.to_le_bytes());
        self.put(&j.max_rad.to_le_bytes());
        self.put(&j.max_speed_rad_s.to_le_bytes());
    }
}

/// Ends a record: the CRC of all its bytes but the last two, in those two.
pub(super) fn seal(buf: &mut [u8]) {
    let at = buf.len().saturating_sub(2);
    let crc = crc16(buf.get(..at).unwrap_or(&[]));
    if let Some(dst) = buf.get_mut(at..) {
        copy(dst, &crc.to_le_bytes());
    }
}

/// Reads what [`Writer`] wrote; bytes past the end read as zero.
pub(super) struct Reader<'a> {
    buf: &'a [u8],
    pos: usize,
}

impl<'a> Reader<'a> {
    /// Reads `buf` from byte `pos` on.
    pub(super) fn at(buf: &'a [u8], pos: usize) -> Self {
        Reader { buf, pos }
    }

    // Out of line: inlined at every field of every record's decode, it
    // was most of their code.
    #[inline(never)] // reason: code-size
    pub(super) fn take<const K: usize>(&mut self) -> [u8; K] {
        let mut out = [0u8; K];
        if let Some(src) = self.buf.get(self.pos..self.pos + K) {
            copy(&mut out, src);
        }
        self.pos += K;
        out
    }

    /// [`Writer::put_joint`]'s block into `j` (its acceleration limit kept).
    pub(super) fn take_joint(&mut self, j: &mut JointCal) {
        j.offset_us = f32::from_le_bytes(self.take());
        j.us_per_rad = f32::from_le_bytes(self.take());
        j.min_us = u16::from_le_bytes(self.take());
        j.max_us = u16::from_le_bytes(self.take());
        j.min_rad = f32::from_le_bytes(self.take());
        j.max_rad = f32::from_le_bytes(self.take());
        j.max_speed_rad_s = f32::from_le_bytes(self.take());
    }
}

/// A decoded, valid record.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Record {
    /// Save counter (wraps; compared with [`seq_newer`]).
    pub seq: u16,
    /// The configuration it holds, validated.
    pub config: Config,
}

/// Why a slot holds no usable record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RecordError {
    /// No magic: never written (erased EEPROM reads 0xFF) or overwritten.
    NoMagic,
    /// Written by another layout version.
    Version(u8),
    /// The CRC does not match: a torn or damaged write.
    Crc,
    /// CRC correct but a value is out of range (written by a buggy build).
    Invalid,
    /// The storage could not be read.
    Storage(StorageError),
}

/// Which copy a loaded configuration came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Source {
    /// The copy at [`SLOT_A_ADDR`].
    SlotA,
    /// The copy at [`SLOT_B_ADDR`].
    SlotB,
    /// No usable copy: the built-in defaults.
    Defaults,
}

/// What was wrong with the stored configuration at load.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Warning {
    /// Neither copy was ever written: defaults in use.
    Missing,
    /// No usable copy (CRC, values or read failure): defaults in use.
    Corrupt,
    /// A copy of another layout version and no usable one: defaults in use.
    VersionMismatch,
    /// One copy is bad, the other was used; the next save repairs it.
    CopyDamaged,
}

impl Warning {
    /// Every warning, for tests that go through them all.
    pub const ALL: [Warning; 4] = [Warning::Missing, Warning::Corrupt, Warning::VersionMismatch, Warning::CopyDamaged];

    /// The warning as the boot log and `status` state it.
    pub fn reason(self) -> crate::text::Text {
        match self {
            Warning::Missing => t!("no stored config, defaults"),
            Warning::Corrupt => t!("stored config corrupt, defaults"),
            Warning::VersionMismatch => t!("stored config version mismatch, defaults"),
            Warning::CopyDamaged => t!("one config copy damaged"),
        }
    }
}

/// What [`load`] found: the configuration to run with and where it came from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Loaded {
    /// The configuration to run with (always valid).
    pub config: Config,
    /// Which copy it is.
    pub source: Source,
    /// Sequence number of the copy used (0 for defaults).
    pub seq: u16,
    /// Set when a copy was missing or bad.
    pub warning: Option<Warning>,
}

/// True if sequence `a` is newer than `b` (RFC 1982 serial arithmetic, so the
/// counter may wrap).
pub fn seq_newer(a: u16, b: u16) -> bool {
    (a.wrapping_sub(b) as i16) > 0
}

#[cfg_attr(target_arch = "avr", optimize(size))] // reason: cold
fn read_slot<S: Storage>(storage: &mut S, addr: u16) -> Result<Record, RecordError> {
    let mut buf = [0u8; RECORD_LEN];
    storage.read(u32::from(addr), &mut buf).map_err(RecordError::Storage)?;
    Config::decode(&buf)
}

/// The sequence number of the slot at `addr` if it holds a valid record.
// Out of line: [`save`] needs only the two numbers, and two whole decoded
// records in its frame put the deepest call path over the stack budget
// (`cargo xtask elf-check`, stack-bound).
#[inline(never)] // avr-trap: frame-size
fn slot_seq<S: Storage>(storage: &mut S, addr: u16) -> Option<u16> {
    read_slot(storage, addr).ok().map(|r| r.seq)
}

/// Which of two read slots [`load`] uses: the valid one, or of two valid ones
/// the newer, A on a tie. [`save`] writes the other slot first.
pub fn pick(a: &Result<Record, RecordError>, b: &Result<Record, RecordError>) -> Option<Source> {
    pick_seq(a.as_ref().ok().map(|r| r.seq), b.as_ref().ok().map(|r| r.seq))
}

/// [`pick`] for any record stored this way: the sequence numbers of the
/// valid copies (`None` for an invalid one).
pub fn pick_seq(a: Option<u16>, b: Option<u16>) -> Option<Source> {
    match (a, b) {
        (Some(sa), Some(sb)) if seq_newer(sb, sa) => Some(Source::SlotB),
        (Some(_), _) => Some(Source::SlotA),
        (None, Some(_)) => Some(Source::SlotB),
        (None, None) => None,
    }
}

/// [`pick`] for a record read as (sequence number, value): the copy to use,
/// with its slot and sequence number.
pub(super) fn pick_copy<T: Copy, E>(a: &Result<(u16, T), E>, b: &Result<(u16, T), E>) -> Option<(Source, u16, T)> {
    match (pick_seq(a.as_ref().ok().map(|r| r.0), b.as_ref().ok().map(|r| r.0)), a, b) {
        (Some(Source::SlotA), Ok((seq, v)), _) => Some((Source::SlotA, *seq, *v)),
        (Some(Source::SlotB), _, Ok((seq, v))) => Some((Source::SlotB, *seq, *v)),
        _ => None,
    }
}

/// How a save writes a pair of slots `[a, b]` when the copy in use (from
/// [`pick`]) is `used` with its sequence number: the other slot first, and
/// the new record's sequence number, one past the one in use.
pub(super) fn next_write(used: Option<(Source, u16)>, [a, b]: [u16; 2]) -> (u16, [u16; 2]) {
    match used {
        Some((Source::SlotA, seq)) => (seq.wrapping_add(1), [b, a]),
        Some((Source::SlotB, seq)) => (seq.wrapping_add(1), [a, b]),
        _ => (1, [a, b]),
    }
}

/// Reads both copies and picks the configuration to run with.
pub fn load<S: Storage>(storage: &mut S) -> Loaded {
    let a = read_slot(storage, SLOT_A_ADDR);
    let b = read_slot(storage, SLOT_B_ADDR);
    let damaged = a.is_err() || b.is_err();
    let loaded = |r: &Record, source| Loaded {
        config: r.config,
        source,
        seq: r.seq,
        warning: if damaged { Some(Warning::CopyDamaged) } else { None },
    };
    match (pick(&a, &b), &a, &b) {
        (Some(Source::SlotA), Ok(ra), _) => loaded(ra, Source::SlotA),
        (Some(Source::SlotB), _, Ok(rb)) => loaded(rb, Source::SlotB),
        (_, Err(ea), Err(eb)) => Loaded {
            config: Config::DEFAULT,
            source: Source::Defaults,
            seq: 0,
            warning: Some(worse(classify(*ea), classify(*eb))),
        },
        // `pick` names a slot only when that slot read valid.
        _ => Loaded { config: Config::DEFAULT, source: Source::Defaults, seq: 0, warning: Some(Warning::Corrupt) },
    }
}

fn classify(e: RecordError) -> Warning {
    match e {
        RecordError::NoMagic => Warning::Missing,
        RecordError::Version(_) => Warning::VersionMismatch,
        RecordError::Crc | RecordError::Invalid | RecordError::Storage(_) => Warning::Corrupt,
    }
}

/// The more informative of two warnings: a version mismatch explains more
/// than corruption, and corruption more than absence.
fn worse(a: Warning, b: Warning) -> Warning {
    let rank = |w| match w {
        Warning::VersionMismatch => 3,
        Warning::Corrupt => 2,
        Warning::CopyDamaged => 1,
        Warning::Missing => 0,
    };
    if rank(b) > rank(a) {
        b
    } else {
        a
    }
}

/// Why [`save`] did not complete.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SaveError {
    /// The configuration is invalid and was not written.
    Invalid(ConfigError),
    /// The storage failed a read or write.
    Storage(StorageError),
    /// A slot read back differently from what was written.
    Verify,
}

/// Writes `config` to both copies (see the module doc for the order and the
/// commit byte) and returns the new sequence number.
pub fn save<S: Storage>(storage: &mut S, config: &Config) -> Result<u16, SaveError> {
    config.validate().map_err(SaveError::Invalid)?;
    let a = slot_seq(storage, SLOT_A_ADDR);
    let b = slot_seq(storage, SLOT_B_ADDR);
    let used = match pick_seq(a, b) {
        Some(Source::SlotA) => a.map(|seq| (Source::SlotA, seq)),
        Some(Source::SlotB) => b.map(|seq| (Source::SlotB, seq)),
        _ => None,
    };
    let (seq, order) = next_write(used, [SLOT_A_ADDR, SLOT_B_ADDR]);
    write_both(storage, order, &config.encode(seq))?;
    Ok(seq)
}

/// Writes `record` to the two slots in the order given (the one [`pick`]
/// would not use first), each in the three steps of the module doc: the
/// same tear-proof save for any record whose byte 0 is [`MAGIC`]`[0]`.
pub(super) fn write_both<S: Storage>(storage: &mut S, order: [u16; 2], record: &[u8]) -> Result<(), SaveError> {
    for addr in order {
        write_slot(storage, addr, record)?;
    }
    Ok(())
}

/// One slot in the three steps of the module doc, then read back.
fn write_slot<S: Storage>(storage: &mut S, addr: u16, record: &[u8]) -> Result<(), SaveError> {
    let addr = u32::from(addr);
    let Some((commit, body)) = record.split_first() else { return Err(SaveError::Verify) };
    let mut first = [0u8];
    storage.read(addr, &mut first).map_err(SaveError::Storage)?;
    // Only a committed slot is uncommitted first: rewriting a byte that is
    // already uncommitted could tear it into `T` and commit a stale body.
    if first == [MAGIC[0]] {
        storage.write(addr, &[UNCOMMITTED]).map_err(SaveError::Storage)?;
    }
    storage.write(addr + 1, body).map_err(SaveError::Storage)?;
    storage.write(addr, core::slice::from_ref(commit)).map_err(SaveError::Storage)?;
    // Read back in pieces: no record-sized buffer on the stack.
    let mut check = [0u8; 16];
    for (i, part) in record.chunks(check.len()).enumerate() {
        let got = check.get_mut(..part.len()).unwrap_or(&mut []);
        storage.read(addr + (i * 16) as u32, got).map_err(SaveError::Storage)?;
        if got != part {
            return Err(SaveError::Verify);
        }
    }
    Ok(())
}
