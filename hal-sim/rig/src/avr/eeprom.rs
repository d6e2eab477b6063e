//! The EEPROM seen from outside the firmware: read it whole (what a power
//! cycle must carry over to the next core, since a new core starts erased)
//! and overwrite bytes (fault injection: a corrupted configuration record).
//!
//! simavr keeps the EEPROM in its `avr_eeprom_t` module and exposes it only
//! through the `AVR_IOCTL_EEPROM_GET/SET` ioctls, which copy in and out.

use simavr_ffi as ffi;

use super::{sys, Avr, Error};

const IOCTL_EEPROM_GET: u32 = sys::ioctl_def(b'e', b'e', b'g', b'p');
const IOCTL_EEPROM_SET: u32 = sys::ioctl_def(b'e', b'e', b's', b'p');

impl Avr {
    /// EEPROM size in bytes (E2END + 1; 4096 on the ATmega2560).
    pub fn eeprom_size(&self) -> usize {
        // SAFETY: live core; e2end is set by the core's constructor.
        unsafe { (*self.avr).e2end as usize + 1 }
    }

    /// A copy of the whole EEPROM.
    pub fn eeprom(&mut self) -> Result<Vec<u8>, Error> {
        let mut buf = vec![0xFF; self.eeprom_size()];
        let mut desc = ffi::avr_eeprom_desc_t { ee: buf.as_mut_ptr(), offset: 0, size: buf.len() as u32 };
        // SAFETY: live core, not inside a callback; simavr copies `size`
        // bytes into `buf`, which holds exactly that many.
        let rc =
            unsafe { ffi::avr_ioctl(self.avr, IOCTL_EEPROM_GET, (&mut desc as *mut ffi::avr_eeprom_desc_t).cast()) };
        if rc != 0 {
            return Err(Error::Missing("EEPROM".into()));
        }
        Ok(buf)
    }

    /// Overwrites EEPROM bytes from `offset`, as if they had always been
    /// there (no write cycle, no interrupt).
    pub fn set_eeprom(&mut self, offset: u16, bytes: &[u8]) -> Result<(), Error> {
        if bytes.is_empty() {
            return Ok(());
        }
        if usize::from(offset) + bytes.len() > self.eeprom_size() {
            return Err(Error::OutOfRange { addr: u32::from(offset), len: bytes.len() });
        }
        // simavr's SET takes a mutable pointer but only reads through it.
        let mut copy = bytes.to_vec();
        let mut desc = ffi::avr_eeprom_desc_t { ee: copy.as_mut_ptr(), offset, size: copy.len() as u32 };
        // SAFETY: live core; bounds checked above; simavr copies from `copy`.
        let rc =
            unsafe { ffi::avr_ioctl(self.avr, IOCTL_EEPROM_SET, (&mut desc as *mut ffi::avr_eeprom_desc_t).cast()) };
        if rc != 0 {
            return Err(Error::Missing("EEPROM".into()));
        }
        Ok(())
    }
}
