//! Constant text and tables in program memory.
//!
//! On the AVR, constants the compiler would otherwise copy into SRAM at
//! start-up (every string literal: the UI's words would take 1 KiB of the
//! 8 KiB) are placed in `.progmem.data` instead, which the linker keeps in
//! flash below 64 KiB, and read back one byte at a time with `lpm`. A
//! [`FlashText`] can only be read through [`TextSource::at`], so flash
//! contents are never dereferenced as data. On the host everything is a
//! normal static.

/// One byte of program memory.
#[cfg(target_arch = "avr")]
#[inline]
pub fn flash_byte(p: *const u8) -> u8 {
    let byte: u8;
    // SAFETY: `lpm` reads program memory and has no other effect; callers
    // pass addresses of `.progmem.data` statics (below 64 KiB).
    unsafe {
        core::arch::asm!("lpm {0}, Z", out(reg) byte, in("Z") p, options(pure, readonly, nostack, preserves_flags));
    }
    byte
}

/// One byte of a constant (host: a plain read).
#[cfg(not(target_arch = "avr"))]
#[inline]
pub fn flash_byte(p: *const u8) -> u8 {
    // SAFETY: callers pass pointers into live `'static` arrays.
    unsafe { p.read() }
}

/// Bytes of text, wherever they are kept.
pub trait TextSource {
    fn len(&self) -> usize;
    /// Byte `i` (0 past the end).
    fn at(&self, i: usize) -> u8;
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl TextSource for [u8] {
    fn len(&self) -> usize {
        <[u8]>::len(self)
    }

    fn at(&self, i: usize) -> u8 {
        self.get(i).copied().unwrap_or(0)
    }
}

/// A string literal stored in flash (made by [`ftext!`](crate::ftext)).
/// Equality is identity (same static), never a read of the contents.
#[derive(Clone, Copy)]
pub struct FlashText(&'static [u8]);

impl PartialEq for FlashText {
    fn eq(&self, other: &Self) -> bool {
        core::ptr::eq(self.0, other.0)
    }
}

impl Eq for FlashText {}

impl core::fmt::Debug for FlashText {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "FlashText({} bytes)", self.0.len())
    }
}

impl FlashText {
    /// `bytes` must be a `.progmem.data` static on the AVR; use
    /// [`ftext!`](crate::ftext).
    #[doc(hidden)]
    pub const fn new(bytes: &'static [u8]) -> Self {
        Self(bytes)
    }
}

impl TextSource for FlashText {
    fn len(&self) -> usize {
        // The length is part of the fat pointer, not read from memory.
        self.0.len()
    }

    fn at(&self, i: usize) -> u8 {
        if i < self.0.len() {
            flash_byte(self.0.as_ptr().wrapping_add(i))
        } else {
            0
        }
    }
}

/// A byte-string literal kept in flash, as a [`FlashText`].
#[macro_export]
macro_rules! ftext {
    ($s:literal) => {{
        #[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
        static TEXT: [u8; $s.len()] = *$s;
        $crate::ui::flash::FlashText::new(&TEXT)
    }};
}
