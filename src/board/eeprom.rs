//! The 4 KiB internal EEPROM as embedded-storage's [`ReadStorage`] and
//! [`Storage`] (the seam's storage, [`crate::seam::Storage`]).
//!
//! Writes use the atomic erase-and-write mode (3.4 ms per byte) and skip bytes
//! that already hold the value: a cell survives ~100 000 writes, and a config
//! save usually changes a few bytes of its record. A byte write also feeds
//! the watchdog, because a whole 90-byte record can take ~300 ms, longer than
//! the watchdog timeout; every wait here is bounded, so this cannot hide a
//! hang.

use avr_device::atmega2560::EEPROM;

use embedded_storage::{ReadStorage, Storage};

use crate::seam::StorageError;

use super::delay_us;
use super::watchdog;

/// Bytes of EEPROM on the ATmega2560; addresses are 0..EEPROM_SIZE.
pub const EEPROM_SIZE: u16 = 4096;

/// Polls of EEPE, ≥ 1 µs apart, before the EEPROM counts as stuck: ≥ 10 ms
/// against 3.4 ms for a write.
const MAX_POLLS: u16 = 10_000;

/// The EEPROM controller, owned.
pub struct Eeprom {
    regs: EEPROM,
}

impl Eeprom {
    /// Takes the controller; no access happens until the first read or write.
    pub fn new(regs: EEPROM) -> Self {
        Self { regs }
    }

    /// Waits for a running write to finish (EEAR and EEDR must not change
    /// while it runs).
    fn wait_ready(&mut self) -> Result<(), StorageError> {
        for _ in 0..MAX_POLLS {
            if self.regs.eecr().read().eepe().bit_is_clear() {
                return Ok(());
            }
            delay_us(1);
        }
        Err(StorageError::Device)
    }

    /// The byte at `addr`, after any write still in progress has finished.
    pub fn read_byte(&mut self, addr: u16) -> Result<u8, StorageError> {
        if addr >= EEPROM_SIZE {
            return Err(StorageError::OutOfRange);
        }
        self.wait_ready()?;
        self.regs.eear().write(|w| w.set(addr));
        // EERE halts the CPU for 4 cycles and leaves the byte in EEDR.
        self.regs.eecr().write(|w| w.eere().set_bit());
        Ok(self.regs.eedr().read().bits())
    }

    /// Writes one byte unless it already holds `value`. Returns once the
    /// write has started (the next access waits for it to finish).
    pub fn write_byte(&mut self, addr: u16, value: u8) -> Result<(), StorageError> {
        if self.read_byte(addr)? == value {
            return Ok(());
        }
        watchdog::feed();
        self.wait_ready()?;
        avr_device::interrupt::free(|_| {
            self.regs.eear().write(|w| w.set(addr));
            self.regs.eedr().write(|w| w.set(value));
            // EEPE must follow EEMPE within 4 cycles (an interrupt in between
            // would void the write, hence the critical section). EEPM = 00:
            // erase and write in one operation.
            self.regs.eecr().write(|w| w.eempe().set_bit());
            self.regs.eecr().write(|w| w.eempe().set_bit().eepe().set_bit());
        });
        Ok(())
    }
}

/// `addr .. addr + len` must lie inside the EEPROM.
fn check_range(addr: u16, len: usize) -> Result<(), StorageError> {
    match (addr as usize).checked_add(len) {
        Some(end) if end <= EEPROM_SIZE as usize => Ok(()),
        _ => Err(StorageError::OutOfRange),
    }
}

/// An embedded-storage offset as an EEPROM address.
#[inline(always)]
fn address(offset: u32) -> Result<u16, StorageError> {
    u16::try_from(offset).map_err(|_| StorageError::OutOfRange)
}

impl Eeprom {
    fn read_at(&mut self, addr: u16, buf: &mut [u8]) -> Result<(), StorageError> {
        check_range(addr, buf.len())?;
        let mut a = addr;
        for slot in buf.iter_mut() {
            *slot = self.read_byte(a)?;
            a = a.wrapping_add(1);
        }
        Ok(())
    }

    fn write_at(&mut self, addr: u16, data: &[u8]) -> Result<(), StorageError> {
        check_range(addr, data.len())?;
        let mut a = addr;
        for &b in data {
            self.write_byte(a, b)?;
            a = a.wrapping_add(1);
        }
        Ok(())
    }
}

// The trait methods only narrow the offset: inlined into the callers, whose
// offsets are 16-bit constants, they cost nothing over 16-bit addresses.
impl ReadStorage for Eeprom {
    type Error = StorageError;

    #[inline(always)]
    fn read(&mut self, offset: u32, bytes: &mut [u8]) -> Result<(), StorageError> {
        self.read_at(address(offset)?, bytes)
    }

    fn capacity(&self) -> usize {
        EEPROM_SIZE as usize
    }
}

/// Every byte of `bytes` that differs is erased and written (see the module
/// doc), so a `write` is all a caller needs.
impl Storage for Eeprom {
    #[inline(always)]
    fn write(&mut self, offset: u32, bytes: &[u8]) -> Result<(), StorageError> {
        self.write_at(address(offset)?, bytes)
    }
}
