//! Output lines built in a fixed buffer from integers, so the chip links no
//! `core::fmt` float code. Fixed-point values print as `-12.05`.

use crate::config::settings::round_i32;
use crate::text::Text;

/// Longest line the app writes, terminator included: the longest `status`
/// (every optional field, the widest values and the longest words; tested).
pub const LINE_CAP: usize = 240;
const _: () = assert!(LINE_CAP <= crate::protocol::rx_loss::TX_BUFFER);

/// Radians to hundredths of a degree.
const CENTIDEG_PER_RAD: f32 = 18_000.0 / core::f32::consts::PI;

/// One output line. Text past the capacity is dropped (the line still ends
/// with its terminator, and [`Line::truncated`] says so), never written out
/// of bounds.
#[derive(Clone)]
pub struct Line {
    buf: [u8; LINE_CAP],
    len: usize,
    truncated: bool,
}

impl Default for Line {
    fn default() -> Self {
        Self::new()
    }
}

impl Line {
    pub const fn new() -> Self {
        Line { buf: [0; LINE_CAP], len: 0, truncated: false }
    }

    pub fn clear(&mut self) -> &mut Self {
        self.len = 0;
        self.truncated = false;
        self
    }

    /// Text was dropped for want of room.
    pub fn truncated(&self) -> bool {
        self.truncated
    }

    /// Room left for text, keeping two bytes for the terminator.
    fn room(&self) -> usize {
        (LINE_CAP - 2).saturating_sub(self.len)
    }

    /// Appends bytes, keeping two bytes for the terminator.
    pub fn bytes(&mut self, b: &[u8]) -> &mut Self {
        let n = b.len().min(self.room());
        if let (Some(dst), Some(src)) = (self.buf.get_mut(self.len..self.len + n), b.get(..n)) {
            dst.copy_from_slice(src);
            self.len += n;
        }
        self.truncated |= n < b.len();
        self
    }

    /// Appends constant text (read from flash on the chip).
    pub fn str(&mut self, s: Text) -> &mut Self {
        let n = s.len().min(self.room());
        if let Some(dst) = self.buf.get_mut(self.len..self.len + n) {
            for (i, slot) in dst.iter_mut().enumerate() {
                *slot = s.byte(i);
            }
            self.len += n;
        }
        self.truncated |= n < s.len();
        self
    }

    /// A space, then `s`.
    pub fn word(&mut self, s: Text) -> &mut Self {
        self.bytes(b" ").str(s)
    }

    pub fn u32(&mut self, v: u32) -> &mut Self {
        let mut digits = [0u8; 10];
        let n = crate::text::decimal(v, &mut digits);
        self.bytes(digits.get(..n).unwrap_or(&[]))
    }

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

    /// Hundredths as a decimal with two places: 1205 → `12.05`, −5 → `-0.05`.
    pub fn centi(&mut self, v: i32) -> &mut Self {
        let m = v.unsigned_abs();
        if v < 0 {
            self.bytes(b"-");
        }
        self.u32(m / 100).bytes(b".");
        let f = (m % 100) as u8;
        self.bytes(&[b'0' + f / 10, b'0' + f % 10])
    }

    pub fn as_bytes(&self) -> &[u8] {
        self.buf.get(..self.len).unwrap_or(&[])
    }

    /// Appends the `\r\n` terminator and returns the finished line.
    pub fn finish(&mut self) -> &[u8] {
        for &c in b"\r\n" {
            if let Some(slot) = self.buf.get_mut(self.len) {
                *slot = c;
                self.len += 1;
            }
        }
        self.as_bytes()
    }
}

/// Radians to the nearest hundredth of a degree (saturating).
pub fn centideg(rad: f32) -> i32 {
    round_i32(rad * CENTIDEG_PER_RAD)
}

/// A value in thousandths (e.g. mrad/s from rad/s), rounded, saturating.
pub fn milli(v: f32) -> i32 {
    round_i32(v * 1000.0)
}
