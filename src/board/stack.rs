//! Stack high-water mark by painting: at boot, [`paint`] fills the free RAM
//! between the end of static data (`__bss_end`, from avr-gcc's linker script)
//! and the stack pointer with [`PATTERN`]; later [`high_water`] finds the
//! lowest byte the stack has overwritten since.
//!
//! Call [`paint`] first thing in `main` (before anything deep runs) and
//! [`high_water`] after the worst scenario; both firmwares can. The figure
//! counts everything from the top of RAM down, including `main`'s own frame
//! and any interrupt frames. A pushed byte that happens to equal the pattern
//! can hide at most the bytes below it that were also left untouched, so the
//! mark is a lower bound only in that unlikely case.

/// 0xC5: not 0x00 or 0xFF, and not a common small integer or pointer byte.
pub const PATTERN: u8 = 0xC5;

/// Last address of the ATmega2560's internal SRAM; the stack starts here.
const RAMEND: u16 = 0x21FF;

/// SPL/SPH in data space.
const SP_ADDR: *const u8 = 0x5D as *const u8;

extern "C" {
    /// First address after .bss (avr-gcc's default linker script).
    static __bss_end: u8;
}

#[inline(always)]
fn bss_end() -> u16 {
    // Only the symbol's address is taken; the byte itself is never read.
    core::ptr::addr_of!(__bss_end) as u16
}

/// The stack pointer now: the next byte a push would write.
#[inline(always)]
pub fn stack_pointer() -> u16 {
    // SAFETY: SPL/SPH are always readable I/O registers; read low byte first.
    unsafe {
        let lo = core::ptr::read_volatile(SP_ADDR);
        let hi = core::ptr::read_volatile(SP_ADDR.add(1));
        u16::from_le_bytes([lo, hi])
    }
}

/// Fills [__bss_end, SP) with [`PATTERN`]. Everything below SP is free (no
/// heap); the loop itself lives in registers and this frame, above SP.
#[inline(never)] // reason: stack-paint
pub fn paint() {
    let end = stack_pointer();
    let mut a = bss_end();
    while a < end {
        // SAFETY: a lies between the end of static data and the stack
        // pointer: memory no one owns yet.
        unsafe { core::ptr::write_volatile(a as *mut u8, PATTERN) };
        a += 1;
    }
}

/// Bytes of stack used at the deepest point since [`paint`]: from the top of
/// RAM down to the lowest byte no longer holding the pattern.
pub fn high_water() -> u16 {
    let top = RAMEND + 1;
    let mut a = bss_end();
    let sp = stack_pointer();
    while a < sp {
        // SAFETY: between static data and SP; reading a free byte is harmless.
        let b = unsafe { core::ptr::read_volatile(a as *const u8) };
        if b != PATTERN {
            break;
        }
        a += 1;
    }
    top - a
}

/// Bytes between the end of static data and the stack pointer right now.
pub fn free_now() -> u16 {
    stack_pointer().saturating_sub(bss_end())
}
