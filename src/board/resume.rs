//! The `.noinit` RAM block behind "no jump after a reset" (`app::resume`
//! has the format and what boot does with it).
//!
//! avr-gcc's linker script (avr6) places `.noinit*` input sections right
//! after `.bss`, in the static RAM below the stack (the post-link check
//! counts it there), and the C runtime clears `.bss` only (`__bss_start` to
//! `__bss_end`) and copies `.data`: this block keeps whatever it held before
//! a reset. The stock bootloader's own variables sit at the bottom of RAM and
//! its stack at the top, clear of it; whatever overwrote it anyway fails the
//! block's CRC.

use core::mem::MaybeUninit;
use core::ptr::{addr_of, addr_of_mut};

use crate::app::resume::Snapshot;

/// The block. Never read or written but through the volatile accesses below.
#[link_section = ".noinit.touch_arm_resume"]
static mut BLOCK: MaybeUninit<[u8; Snapshot::BYTES]> = MaybeUninit::uninit();

fn cell(i: usize) -> *mut u8 {
    // SAFETY: a pointer into the block, not a reference (nothing else
    // touches it; the firmware is single-threaded and no interrupt uses it).
    unsafe { addr_of_mut!(BLOCK).cast::<u8>().add(i) }
}

/// The pulses the block holds, if it is valid.
pub fn load() -> Option<Snapshot> {
    let mut b = [0u8; Snapshot::BYTES];
    for (i, v) in b.iter_mut().enumerate() {
        // SAFETY: inside the block. Volatile: after a power-up these bytes
        // are whatever the RAM came up with, and the decode judges them.
        *v = unsafe { core::ptr::read_volatile(addr_of!(BLOCK).cast::<u8>().add(i)) };
    }
    Snapshot::decode(&b)
}

/// Writes `s` to the block. The magic word goes last, so a reset while the
/// block is written leaves it invalid (the power-up behaviour), never a mix
/// of two frames' pulses.
pub fn save(s: &Snapshot) {
    let b = s.encode();
    // SAFETY: inside the block.
    unsafe {
        core::ptr::write_volatile(cell(0), 0);
        for (i, v) in b.iter().enumerate().skip(1) {
            core::ptr::write_volatile(cell(i), *v);
        }
        core::ptr::write_volatile(cell(0), b[0]);
    }
}

/// Saves the widths `pwm` sends in this period, once every joint has a
/// pulse (before that the block keeps what the last reset left: a reset
/// during boot resumes the same pulses). Called at each period start.
/// Out of line: the snapshot and its encoding stay out of `main`'s frame.
#[inline(never)] // avr-trap: frame-size
pub fn record(pwm: &super::servo_pwm::ServoPwm) {
    if let Some(s) = pwm.snapshot() {
        save(&s);
    }
}

/// Invalidates the block: the outputs were cut (a fault, a panic), so the
/// next boot homes instead of commanding pulses the servos no longer get.
pub fn forget() {
    // SAFETY: inside the block.
    unsafe { core::ptr::write_volatile(cell(0), 0) };
}
