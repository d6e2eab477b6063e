//! The display overrides (`cal set lcd …`): which controller to drive
//! instead of the one the boot probe finds (MCUFRIEND_kbv's `begin(ID)`),
//! colour inversion and a screen turned by 180° (the shield mounted upside
//! down). They are read once at boot, before the display starts
//! (`board::lcd`), so a change takes effect at the next boot.
//!
//! Stored in their own small EEPROM record, beside the gripper's and the
//! poses' and in the same way: two copies with a sequence number and the
//! CRC-16 of [`super::crc`], each written in the tear-proof three steps of
//! [`super::store`] (byte 0 is the same commit byte), so a save cut by a
//! power loss leaves the overrides before it or the new ones. Not a field of
//! the configuration's record, which then needs no new version; a board
//! that never stored overrides (or whose record is damaged) runs with
//! [`LCD_DEFAULT`]: the probe decides, no inversion, no turn.
//!
//! # Record layout (version 1, little-endian, 9 bytes)
//! | offset | size | field |
//! |-------:|-----:|-------|
//! | 0 | 2 | magic `b"TL"` |
//! | 2 | 1 | layout version (1) |
//! | 3 | 2 | sequence counter (u16, serial arithmetic as the configuration's) |
//! | 5 | 1 | controller ([`LcdChoice`] id: 0 auto, 1 ili9341, 2 st7789, 3 ili9486, 4 ili9325, 5 st7796) |
//! | 6 | 1 | flags: bit 0 invert, bit 1 rotate 180 (other bits 0) |
//! | 7 | 2 | CRC-16/CCITT-FALSE of bytes 0..7 |
//!
//! Copy A lives at [`LCD_SLOT_A`], copy B at [`LCD_SLOT_B`], past the
//! gripper's two slots.

use super::crc::crc16;
use super::store::{next_write, pick_copy, seal, write_both, RecordError, SaveError, Source, UNCOMMITTED};
use crate::seam::Storage;
use crate::text::Text;

/// Bytes of one record, CRC included.
pub const LCD_RECORD_LEN: usize = 9;
/// EEPROM address of the first copy (the gripper uses 512..675).
pub const LCD_SLOT_A: u16 = 768;
/// EEPROM address of the second copy.
pub const LCD_SLOT_B: u16 = 800;
/// The record's first bytes; byte 0 is the commit byte of [`super::store`].
pub const LCD_MAGIC: [u8; 2] = *b"TL";
/// Layout version of the record.
pub const LCD_VERSION: u8 = 1;

const CRC_AT: usize = LCD_RECORD_LEN - 2;
const FLAG_INVERT: u8 = 1 << 0;
const FLAG_ROTATE: u8 = 1 << 1;
const _: () = assert!(LCD_MAGIC[0] == super::store::MAGIC[0] && UNCOMMITTED != LCD_MAGIC[0]);
const _: () = assert!(super::grip::GRIP_SLOT_B as usize + super::grip::GRIP_RECORD_LEN <= LCD_SLOT_A as usize);
const _: () = assert!(LCD_SLOT_A as usize + LCD_RECORD_LEN <= LCD_SLOT_B as usize);
const _: () = assert!(LCD_SLOT_B as usize + LCD_RECORD_LEN <= super::store::EEPROM_SIZE as usize);

/// `cal set lcd <name>`: the probe's choice, or a controller forced.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LcdChoice {
    /// The boot probe decides (`ui::controller`).
    Auto = 0,
    /// ILITEK ILI9341.
    Ili9341 = 1,
    /// Sitronix ST7789V.
    St7789 = 2,
    /// ILITEK ILI9486.
    Ili9486 = 3,
    /// ILITEK ILI9325.
    Ili9325 = 4,
    /// Sitronix ST7796S.
    St7796 = 5,
}

impl LcdChoice {
    /// Every choice, by id.
    pub const ALL: [LcdChoice; 6] = [
        LcdChoice::Auto,
        LcdChoice::Ili9341,
        LcdChoice::St7789,
        LcdChoice::Ili9486,
        LcdChoice::Ili9325,
        LcdChoice::St7796,
    ];

    /// The word of `cal set lcd` (and the controller's name on serial).
    pub fn name(self) -> Text {
        match self {
            LcdChoice::Auto => t!("auto"),
            LcdChoice::Ili9341 => t!("ili9341"),
            LcdChoice::St7789 => t!("st7789"),
            LcdChoice::Ili9486 => t!("ili9486"),
            LcdChoice::Ili9325 => t!("ili9325"),
            LcdChoice::St7796 => t!("st7796"),
        }
    }

    /// The choice stored as `id`.
    pub fn from_id(id: u8) -> Option<LcdChoice> {
        Some(match id {
            0 => LcdChoice::Auto,
            1 => LcdChoice::Ili9341,
            2 => LcdChoice::St7789,
            3 => LcdChoice::Ili9486,
            4 => LcdChoice::Ili9325,
            5 => LcdChoice::St7796,
            _ => return None,
        })
    }
}

/// The display overrides.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct LcdSettings {
    /// The controller to drive (auto: the probe's).
    pub controller: LcdChoice,
    /// Colours inverted (the controller's inversion command).
    pub invert: bool,
    /// The picture and the touch mapping turned by 180°.
    pub rotate_180: bool,
}

/// No overrides: the probe decides, no inversion, no turn.
pub const LCD_DEFAULT: LcdSettings = LcdSettings { controller: LcdChoice::Auto, invert: false, rotate_180: false };

/// One `cal set lcd …` change.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LcdSet {
    /// `cal set lcd auto|<controller>`.
    Controller(LcdChoice),
    /// `cal set lcd invert on|off`.
    Invert(bool),
    /// `cal set lcd rotate 0|180`.
    Rotate180(bool),
}

impl LcdSettings {
    /// These settings with `set` applied.
    pub fn with(mut self, set: LcdSet) -> LcdSettings {
        match set {
            LcdSet::Controller(c) => self.controller = c,
            LcdSet::Invert(on) => self.invert = on,
            LcdSet::Rotate180(on) => self.rotate_180 = on,
        }
        self
    }
}

/// Serializes `s` with sequence number `seq`.
pub fn encode(s: &LcdSettings, seq: u16) -> [u8; LCD_RECORD_LEN] {
    let [q0, q1] = seq.to_le_bytes();
    let flags = if s.invert { FLAG_INVERT } else { 0 } | if s.rotate_180 { FLAG_ROTATE } else { 0 };
    let mut buf = [LCD_MAGIC[0], LCD_MAGIC[1], LCD_VERSION, q0, q1, s.controller as u8, flags, 0, 0];
    seal(&mut buf);
    buf
}

/// Parses and validates a record: magic, version, CRC, a known controller
/// id and no unknown flag. Returns the sequence number and the settings.
pub fn decode(buf: &[u8; LCD_RECORD_LEN]) -> Result<(u16, LcdSettings), RecordError> {
    let [m0, m1, version, q0, q1, id, flags, c0, c1] = *buf;
    if [m0, m1] != LCD_MAGIC {
        return Err(RecordError::NoMagic);
    }
    if version != LCD_VERSION {
        return Err(RecordError::Version(version));
    }
    let (body, _) = buf.split_at(CRC_AT);
    if crc16(body).to_le_bytes() != [c0, c1] {
        return Err(RecordError::Crc);
    }
    let controller = LcdChoice::from_id(id).ok_or(RecordError::Invalid)?;
    if flags & !(FLAG_INVERT | FLAG_ROTATE) != 0 {
        return Err(RecordError::Invalid);
    }
    let s = LcdSettings { controller, invert: flags & FLAG_INVERT != 0, rotate_180: flags & FLAG_ROTATE != 0 };
    Ok((u16::from_le_bytes([q0, q1]), s))
}

fn read_slot<S: Storage>(storage: &mut S, addr: u16) -> Result<(u16, LcdSettings), RecordError> {
    let mut buf = [0u8; LCD_RECORD_LEN];
    storage.read(u32::from(addr), &mut buf).map_err(RecordError::Storage)?;
    decode(&buf)
}

/// Reads both copies and picks the overrides the way the configuration's
/// load does (`store::pick`); with no valid copy, [`LCD_DEFAULT`]. Returns
/// the slot used, its sequence number (0 for none) and the settings.
pub fn load<S: Storage>(storage: &mut S) -> (Source, u16, LcdSettings) {
    let a = read_slot(storage, LCD_SLOT_A);
    let b = read_slot(storage, LCD_SLOT_B);
    pick_copy(&a, &b).unwrap_or((Source::Defaults, 0, LCD_DEFAULT))
}

/// Writes `s` to both copies (the one [`load`] does not use first) and
/// returns the new sequence number.
pub fn save<S: Storage>(storage: &mut S, s: &LcdSettings) -> Result<u16, SaveError> {
    let a = read_slot(storage, LCD_SLOT_A);
    let b = read_slot(storage, LCD_SLOT_B);
    let (seq, order) = next_write(pick_copy(&a, &b).map(|(s, seq, _)| (s, seq)), [LCD_SLOT_A, LCD_SLOT_B]);
    write_both(storage, order, &encode(s, seq))?;
    Ok(seq)
}
