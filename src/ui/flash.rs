//! Constant text and tables in program memory.
//!
//! On the AVR, constants the compiler would otherwise copy into SRAM at
//! start-up (every string literal: the UI's words would take 1 KiB of the
//! 8 KiB) are placed in `.progmem.data` instead, which the linker keeps in
//! flash below 64 KiB, and read back one byte at a time with `lpm`. A
//! [`Text`] can only be read through [`TextSource::at`], so flash
//! contents are never dereferenced as data. On the host everything is a
//! normal static.

pub use crate::text::flash_byte;
use crate::text::Text;

/// Bytes of text, wherever they are kept.
pub trait TextSource {
    /// Bytes of text.
    fn len(&self) -> usize;
    /// Byte `i` (0 past the end).
    fn at(&self, i: usize) -> u8;
    /// No bytes.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The text as either kind, so a drawing function has one copy for
    /// both (`ui::draw::text_centered`, `ui::screen`'s text boxes).
    fn chars(&self) -> Chars<'_>;
}

/// Text in flash or in RAM: what the drawing functions that take either
/// kind are built for once.
#[derive(Clone, Copy)]
pub enum Chars<'a> {
    /// Constant text.
    Flash(Text),
    /// Composed text.
    Ram(&'a [u8]),
}

impl TextSource for Chars<'_> {
    fn len(&self) -> usize {
        match self {
            Chars::Flash(t) => t.len(),
            Chars::Ram(b) => b.len(),
        }
    }

    fn at(&self, i: usize) -> u8 {
        match self {
            Chars::Flash(t) => t.byte(i),
            Chars::Ram(b) => b.get(i).copied().unwrap_or(0),
        }
    }

    fn chars(&self) -> Chars<'_> {
        *self
    }
}

impl TextSource for [u8] {
    fn len(&self) -> usize {
        <[u8]>::len(self)
    }

    fn at(&self, i: usize) -> u8 {
        self.get(i).copied().unwrap_or(0)
    }

    fn chars(&self) -> Chars<'_> {
        Chars::Ram(self)
    }
}

impl TextSource for Text {
    fn len(&self) -> usize {
        Text::len(self)
    }

    fn at(&self, i: usize) -> u8 {
        self.byte(i)
    }

    fn chars(&self) -> Chars<'_> {
        Chars::Flash(*self)
    }
}
