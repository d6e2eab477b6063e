//! One line of text composed in a fixed buffer from constant text and
//! integers, so the chip links no `core::fmt` number code: the serial replies
//! (`app`, `Line<LINE_CAP>` with its `\r\n` terminator) and the screen's text
//! (`ui`, a few dozen bytes per line) are built with it.

use super::Text;

/// Up to `N` bytes of text. Text past the capacity is dropped, never written
/// out of bounds ([`Line::truncated`] says so); [`Line::finish`] still fits
/// the terminator.
#[derive(Clone, Debug)]
pub struct Line<const N: usize> {
    buf: [u8; N],
    len: usize,
    truncated: bool,
}

impl<const N: usize> Default for Line<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Line<N> {
    /// An empty line.
    pub const fn new() -> Self {
        Line { buf: [0; N], len: 0, truncated: false }
    }

    /// Empties the line for reuse.
    pub fn clear(&mut self) -> &mut Self {
        self.len = 0;
        self.truncated = false;
        self
    }

    /// Text was dropped for want of room (or cut for the terminator).
    pub fn truncated(&self) -> bool {
        self.truncated
    }

    /// Appends bytes, as many as fit.
    #[inline(never)] // reason: code-size
    pub fn bytes(&mut self, b: &[u8]) -> &mut Self {
        self.truncated |= !push_bytes(&mut self.buf, &mut self.len, b);
        self
    }

    /// Appends constant text (read from flash on the chip).
    #[inline(never)] // reason: code-size
    pub fn str(&mut self, s: Text) -> &mut Self {
        self.truncated |= !push_text(&mut self.buf, &mut self.len, s);
        self
    }

    /// A space, then `s`.
    pub fn word(&mut self, s: Text) -> &mut Self {
        self.bytes(b" ").str(s)
    }

    /// `v` in decimal.
    pub fn u32(&mut self, v: u32) -> &mut Self {
        self.truncated |= !push_u32(&mut self.buf, &mut self.len, v);
        self
    }

    /// `v` in decimal, with a `-` when negative.
    pub fn i32(&mut self, v: i32) -> &mut Self {
        if v < 0 {
            self.bytes(b"-");
        }
        self.u32(v.unsigned_abs())
    }

    /// A space, then `v`.
    pub fn num(&mut self, v: i32) -> &mut Self {
        self.bytes(b" ").i32(v)
    }

    /// `0x` and the low `digits` (1..=8) hex digits of `v`, lowercase: an
    /// ID read from a chip (`hex(0x9341, 4)` → `0x9341`).
    pub fn hex(&mut self, v: u32, digits: u8) -> &mut Self {
        self.truncated |= !push_hex(&mut self.buf, &mut self.len, v, digits);
        self
    }

    /// Hundredths as a decimal with two places: 1205 → `12.05`, −5 → `-0.05`.
    pub fn centi(&mut self, v: i32) -> &mut Self {
        let m = v.unsigned_abs();
        if v < 0 {
            self.bytes(b"-");
        }
        self.u32(m / 100).bytes(b".");
        let f = (m % 100) as u8;
        // One byte at a time: as a two-byte array on the stack
        // (`&[b'0' + f / 10, b'0' + f % 10]`) the second byte came out wrong
        // on the chip (`600.0p`, `171.8J`); the e2e test
        // `cal_show_prints_the_decimals_it_was_given` holds it.
        self.bytes(&[b'0' + f / 10]).bytes(&[b'0' + f % 10])
    }

    /// A pulse in Timer5 ticks as µs: 3001 → `1500.5`, 3000 → `1500`.
    pub fn ticks_us(&mut self, ticks: u16) -> &mut Self {
        self.u32(u32::from(ticks / 2));
        if ticks % 2 == 1 {
            self.bytes(b".5");
        }
        self
    }

    /// The text so far.
    pub fn as_bytes(&self) -> &[u8] {
        self.buf.get(..self.len).unwrap_or(&[])
    }

    /// Appends the `\r\n` terminator, cutting the text if the line is too
    /// full for it, and returns the finished line.
    pub fn finish(&mut self) -> &[u8] {
        let room = N.saturating_sub(2);
        self.truncated |= self.len > room;
        self.len = self.len.min(room);
        self.bytes(b"\r\n").as_bytes()
    }
}

// The work is done on slices, once for every capacity: the lines of
// different sizes share this code instead of each getting a copy.

// Each returns whether everything fitted.

fn push_bytes(buf: &mut [u8], len: &mut usize, b: &[u8]) -> bool {
    for &c in b {
        match buf.get_mut(*len) {
            Some(slot) => *slot = c,
            None => return false,
        }
        *len += 1;
    }
    true
}

fn push_text(buf: &mut [u8], len: &mut usize, s: Text) -> bool {
    let mut fit = true;
    for b in s.bytes() {
        fit &= push_bytes(buf, len, &[b]);
    }
    fit
}

fn push_hex(buf: &mut [u8], len: &mut usize, v: u32, digits: u8) -> bool {
    let mut fit = push_bytes(buf, len, b"0x");
    let k = digits.clamp(1, 8);
    // The first digit wanted to the top nibble, then one nibble per step.
    let mut v = v << (4 * (8 - k));
    for _ in 0..k {
        let d = (v >> 28) as u8;
        v <<= 4;
        fit &= push_bytes(buf, len, &[if d < 10 { b'0' + d } else { b'a' + d - 10 }]);
    }
    fit
}

fn push_u32(buf: &mut [u8], len: &mut usize, v: u32) -> bool {
    let mut digits = [0u8; 10];
    let n = super::decimal(v, &mut digits);
    push_bytes(buf, len, digits.get(..n).unwrap_or(&[]))
}
