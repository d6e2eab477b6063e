//! The access settings: the carer's (issue #20 §3: the PIN that locks the
//! user's pages, which items a locked screen hides, and the speed cap; the
//! carer decides what the user may change, as a clinician profile does on a
//! powered wheelchair's controls) and the assistive switch's (§4: off, on,
//! or on with the whole glass as a second switch, and the scan's sweep
//! time).
//!
//! Stored in their own small EEPROM record, beside the display overrides
//! and in the same way: two copies with a sequence number and the CRC-16 of
//! [`super::crc`], each written in the tear-proof three steps of
//! [`super::store`] (byte 0 is the same commit byte), so a save cut by a
//! power loss leaves the settings before it or the new ones. A board that
//! never stored them (or whose two copies are damaged) runs with
//! [`ACCESS_DEFAULT`]: no PIN, so it never locks and a maker is not locked
//! out; everything hideable hidden once a PIN is set; no cap.
//!
//! Whether the screen is locked is not stored: a board with a PIN boots
//! locked, so a power cycle always ends carer mode.
//!
//! # Record layout (version 2, little-endian, 20 bytes)
//! | offset | size | field |
//! |-------:|-----:|-------|
//! | 0 | 2 | magic `b"TC"` |
//! | 2 | 1 | layout version (2) |
//! | 3 | 2 | sequence counter (u16, serial arithmetic as the configuration's) |
//! | 5 | 1 | hidden items: bit 0 cal, 1 line, 2 lift, 3 fast, 4 touch (other bits 0) |
//! | 6 | 1 | speed cap ([`SpeedPreset::id`]) |
//! | 7 | 1 | PIN length: 0 (no PIN) or [`PIN_MIN`]..=[`PIN_MAX`] |
//! | 8 | 8 | PIN digits, ASCII, then zeros |
//! | 16 | 1 | switch flags ([`SwitchUse`]): bit 0 on, bit 1 the glass as a switch too (only with bit 0; other bits 0) (version 2) |
//! | 17 | 1 | switch sweep per axis, tenths of a second, [`SWEEP_MIN_DS`]..=[`SWEEP_MAX_DS`] (version 2) |
//! | 18 | 2 | CRC-16/CCITT-FALSE of bytes 0..18 |
//!
//! A version-1 record (before the switch) ends with its CRC of bytes 0..16
//! at 16; it reads with the switch off and the default sweep, and the next
//! save writes version 2.
//!
//! Copy A lives at [`ACCESS_SLOT_A`], copy B at [`ACCESS_SLOT_B`], past the
//! display overrides' two slots.

use super::crc::crc16;
use super::settings::SpeedPreset;
use super::store::{copy, next_write, pick_copy, seal, write_both, RecordError, SaveError, Source, UNCOMMITTED};
use crate::seam::Storage;
use crate::text::Text;

/// Bytes of one record, CRC included.
pub const ACCESS_RECORD_LEN: usize = 20;
/// A version-1 record's length (its CRC at 16).
const ACCESS_RECORD_LEN_V1: usize = 18;
/// EEPROM address of the first copy (the display overrides use 768..809).
pub const ACCESS_SLOT_A: u16 = 832;
/// EEPROM address of the second copy.
pub const ACCESS_SLOT_B: u16 = 864;
/// The record's first bytes; byte 0 is the commit byte of [`super::store`].
pub const ACCESS_MAGIC: [u8; 2] = *b"TC";
/// Layout version of the record.
pub const ACCESS_VERSION: u8 = 2;
/// The shortest sweep per axis, tenths of a second (`switch sweep 2`).
pub const SWEEP_MIN_DS: u8 = 20;
/// The longest sweep per axis, tenths of a second (`switch sweep 20`).
pub const SWEEP_MAX_DS: u8 = 200;
/// The sweep of a board that never set one: 6 s to cross the map.
pub const SWEEP_DEFAULT_DS: u8 = 60;
/// Fewest digits of a PIN.
pub const PIN_MIN: usize = 4;
/// Most digits of a PIN.
pub const PIN_MAX: usize = 8;

const CRC_AT: usize = ACCESS_RECORD_LEN - 2;
/// The PIN's digits' place (both versions).
const PIN_AT: usize = 8;
const SWITCH_AT: usize = PIN_AT + PIN_MAX;
const _: () = assert!(ACCESS_MAGIC[0] == super::store::MAGIC[0] && UNCOMMITTED != ACCESS_MAGIC[0]);
const _: () = assert!(super::lcd::LCD_SLOT_B as usize + super::lcd::LCD_RECORD_LEN <= ACCESS_SLOT_A as usize);
const _: () = assert!(ACCESS_SLOT_A as usize + ACCESS_RECORD_LEN <= ACCESS_SLOT_B as usize);
const _: () = assert!(ACCESS_SLOT_B as usize + ACCESS_RECORD_LEN <= super::store::EEPROM_SIZE as usize);

/// The items a locked screen can hide (`access hide|show <item>`), one bit
/// each in [`Access::hide`].
pub mod item {
    /// The Cal button and the calibration commands (`cal set` of the
    /// joints, the gripper, the arm, home, park and the display, `cal
    /// reset`, `cal save`).
    pub const CAL: u8 = 1 << 0;
    /// The Line toggle and `path`.
    pub const LINE: u8 = 1 << 1;
    /// The Lift toggle and `lift`.
    pub const LIFT: u8 = 1 << 2;
    /// The Fast button and `speed fast`.
    pub const FAST: u8 = 1 << 3;
    /// The touch settings: `cal set touch …` and the Cal button (the
    /// screen's calibration is the touch's).
    pub const TOUCH: u8 = 1 << 4;
    /// Every item.
    pub const ALL: u8 = CAL | LINE | LIFT | FAST | TOUCH;
}

/// The item bit `k` (0..=4) and its word; `None` past the last.
pub fn item_nth(k: u8) -> Option<(u8, Text)> {
    Some(match k {
        0 => (item::CAL, t!("cal")),
        1 => (item::LINE, t!("line")),
        2 => (item::LIFT, t!("lift")),
        3 => (item::FAST, t!("fast")),
        4 => (item::TOUCH, t!("touch")),
        _ => return None,
    })
}

/// A PIN: 0 digits (none) or [`PIN_MIN`]..=[`PIN_MAX`] ASCII digits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pin {
    /// Digits that count (0: no PIN).
    pub len: u8,
    /// The digits, ASCII, then zeros.
    pub digits: [u8; PIN_MAX],
}

impl Pin {
    /// No PIN.
    pub const NONE: Pin = Pin { len: 0, digits: [0; PIN_MAX] };

    /// `tok` as a PIN if it is 4–8 ASCII digits.
    pub fn parse(tok: &[u8]) -> Option<Pin> {
        if !(PIN_MIN..=PIN_MAX).contains(&tok.len()) || !tok.iter().all(u8::is_ascii_digit) {
            return None;
        }
        let mut pin = Pin { len: tok.len() as u8, digits: [0; PIN_MAX] };
        copy(&mut pin.digits, tok);
        Some(pin)
    }

    /// A PIN is set.
    pub fn is_set(&self) -> bool {
        self.len > 0
    }
}

/// The carer's settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Access {
    /// [`item`] bits hidden while locked.
    pub hide: u8,
    /// The fastest preset any move uses.
    pub cap: SpeedPreset,
    /// The PIN of `access unlock` ([`Pin::NONE`]: the screen never locks).
    pub pin: Pin,
    /// Whether the assistive switch is used, and the glass as one.
    pub switch: SwitchUse,
    /// The switch scan's sweep per axis, tenths of a second.
    pub sweep_ds: u8,
}

/// No PIN, everything hideable hidden (once a PIN locks), no cap; the
/// switch off, with a 6 s sweep.
pub const ACCESS_DEFAULT: Access = Access {
    hide: item::ALL,
    cap: SpeedPreset::Fast,
    pin: Pin::NONE,
    switch: SwitchUse::Off,
    sweep_ds: SWEEP_DEFAULT_DS,
};

/// How the assistive switch is used; the discriminant is the record's
/// switch flags byte.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub enum SwitchUse {
    /// Not used: the pin is not looked at (`switch off`).
    Off = 0,
    /// The switch on its pin, and the scan (`switch on`).
    On = 1,
    /// As `On`, and any touch on the glass is a press of the switch too,
    /// for a user who can touch but not aim (`switch glass`).
    Glass = 3,
}

impl SwitchUse {
    /// The word of `switch off|on|glass` and `cal access`.
    pub fn name(self) -> Text {
        match self {
            SwitchUse::Off => t!("off"),
            SwitchUse::On => t!("on"),
            SwitchUse::Glass => t!("glass"),
        }
    }
}

impl Access {
    /// `s`, or the cap if `s` is faster.
    pub fn capped(&self, s: SpeedPreset) -> SpeedPreset {
        if s.id() > self.cap.id() {
            self.cap
        } else {
            s
        }
    }
}

/// Serializes `a` with sequence number `seq`.
pub fn encode(a: &Access, seq: u16) -> [u8; ACCESS_RECORD_LEN] {
    let mut buf = [0u8; ACCESS_RECORD_LEN];
    let [q0, q1] = seq.to_le_bytes();
    let head = [ACCESS_MAGIC[0], ACCESS_MAGIC[1], ACCESS_VERSION, q0, q1, a.hide, a.cap.id(), a.pin.len];
    if let Some(dst) = buf.get_mut(..8) {
        copy(dst, &head);
    }
    if let Some(dst) = buf.get_mut(PIN_AT..SWITCH_AT) {
        copy(dst, &a.pin.digits);
    }
    if let Some(dst) = buf.get_mut(SWITCH_AT..CRC_AT) {
        copy(dst, &[a.switch as u8, a.sweep_ds]);
    }
    seal(&mut buf);
    buf
}

/// Parses and validates a record of version 2 or 1: magic, version, CRC,
/// no unknown item, a known cap, a PIN of 0 or 4–8 digits followed by
/// zeros, and (version 2) known switch flags and a sweep in range. Returns
/// the sequence number and the settings.
pub fn decode(buf: &[u8; ACCESS_RECORD_LEN]) -> Result<(u16, Access), RecordError> {
    let [m0, m1, version, q0, q1, hide, cap, pin_len, ..] = *buf;
    if [m0, m1] != ACCESS_MAGIC {
        return Err(RecordError::NoMagic);
    }
    let crc_at = match version {
        ACCESS_VERSION => CRC_AT,
        1 => ACCESS_RECORD_LEN_V1 - 2,
        v => return Err(RecordError::Version(v)),
    };
    let (body, rest) = buf.split_at(crc_at);
    if rest.get(..2) != Some(&crc16(body).to_le_bytes()[..]) {
        return Err(RecordError::Crc);
    }
    let cap = SpeedPreset::from_id(cap).ok_or(RecordError::Invalid)?;
    let (switch, sweep_ds) = match body.get(SWITCH_AT..) {
        Some(&[f, d]) if (SWEEP_MIN_DS..=SWEEP_MAX_DS).contains(&d) => (
            match f {
                0 => SwitchUse::Off,
                1 => SwitchUse::On,
                3 => SwitchUse::Glass,
                _ => return Err(RecordError::Invalid),
            },
            d,
        ),
        Some(&[]) | None => (SwitchUse::Off, SWEEP_DEFAULT_DS),
        _ => return Err(RecordError::Invalid),
    };
    let stored = body.get(PIN_AT..SWITCH_AT).unwrap_or(&[]);
    let (digits, rest) = stored.split_at(usize::from(pin_len).min(stored.len()));
    // Exactly what `encode` writes: the parsed PIN's digits, then zeros.
    let pin = if pin_len == 0 { Some(Pin::NONE) } else { Pin::parse(digits) };
    match pin {
        Some(pin) if pin.len == pin_len && hide & !item::ALL == 0 && rest.iter().all(|&b| b == 0) => {
            Ok((u16::from_le_bytes([q0, q1]), Access { hide, cap, pin, switch, sweep_ds }))
        }
        _ => Err(RecordError::Invalid),
    }
}

fn read_slot<S: Storage>(storage: &mut S, addr: u16) -> Result<(u16, Access), RecordError> {
    let mut buf = [0u8; ACCESS_RECORD_LEN];
    storage.read(u32::from(addr), &mut buf).map_err(RecordError::Storage)?;
    decode(&buf)
}

/// Reads both copies and picks the settings the way the configuration's
/// load does (`store::pick`); with no valid copy, [`ACCESS_DEFAULT`].
/// Returns the slot used, its sequence number (0 for none) and the settings.
pub fn load<S: Storage>(storage: &mut S) -> (Source, u16, Access) {
    let a = read_slot(storage, ACCESS_SLOT_A);
    let b = read_slot(storage, ACCESS_SLOT_B);
    pick_copy(&a, &b).unwrap_or((Source::Defaults, 0, ACCESS_DEFAULT))
}

/// Writes `a` to both copies (the one [`load`] does not use first) and
/// returns the new sequence number.
pub fn save<S: Storage>(storage: &mut S, a: &Access) -> Result<u16, SaveError> {
    let x = read_slot(storage, ACCESS_SLOT_A);
    let y = read_slot(storage, ACCESS_SLOT_B);
    let (seq, order) = next_write(pick_copy(&x, &y).map(|(s, seq, _)| (s, seq)), [ACCESS_SLOT_A, ACCESS_SLOT_B]);
    write_both(storage, order, &encode(a, seq))?;
    Ok(seq)
}

#[cfg(test)]
mod tests {
    use super::*;

    const SET: Access = Access {
        hide: item::LINE | item::FAST,
        cap: SpeedPreset::Normal,
        pin: Pin { len: 4, digits: *b"2580\0\0\0\0" },
        switch: SwitchUse::On,
        sweep_ds: 35,
    };

    #[test]
    fn a_record_reads_back_as_written() {
        assert_eq!(decode(&encode(&SET, 7)), Ok((7, SET)));
        let off = Access { switch: SwitchUse::Off, sweep_ds: SWEEP_MAX_DS, ..SET };
        assert_eq!(decode(&encode(&off, 8)), Ok((8, off)));
        let glass = Access { switch: SwitchUse::Glass, sweep_ds: SWEEP_MIN_DS, ..SET };
        assert_eq!(encode(&glass, 9)[16], 3);
        assert_eq!(decode(&encode(&glass, 9)), Ok((9, glass)));
    }

    #[test]
    fn a_version_1_record_reads_with_the_switch_off() {
        // Version 1: the same first 16 bytes, its CRC at 16.
        let mut v1 = encode(&SET, 3);
        v1[2] = 1;
        let crc = crc16(&v1[..16]).to_le_bytes();
        v1[16] = crc[0];
        v1[17] = crc[1];
        v1[18] = 0xFF;
        v1[19] = 0xFF;
        let want = Access { switch: SwitchUse::Off, sweep_ds: SWEEP_DEFAULT_DS, ..SET };
        assert_eq!(decode(&v1), Ok((3, want)));
    }

    #[test]
    fn unknown_switch_bytes_are_refused() {
        // The glass without the switch (2), unknown bits, sweeps out of range.
        for (flags, sweep) in [(2u8, 60u8), (4, 60), (7, 60), (0x81, 60), (1, SWEEP_MIN_DS - 1), (3, SWEEP_MAX_DS + 1)]
        {
            let mut b = encode(&SET, 1);
            b[16] = flags;
            b[17] = sweep;
            seal(&mut b);
            assert_eq!(decode(&b), Err(RecordError::Invalid), "{flags} {sweep}");
        }
    }
}
