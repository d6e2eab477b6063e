//! Output lines built in a fixed buffer from integers, so the chip links no
//! `core::fmt` float code. Fixed-point values print as `-12.05`.

use crate::config::settings::round_i32;
use crate::text::Text;

/// Longest line the app writes, terminator included.
pub const LINE_CAP: usize = 192;

/// Radians to hundredths of a degree.
const CENTIDEG_PER_RAD: f32 = 18_000.0 / core::f32::consts::PI;

/// One output line. Text past the capacity is dropped (the line still ends
/// with its terminator), never written out of bounds.
#[derive(Clone)]
pub struct Line {
    buf: [u8; LINE_CAP],
    len: usize,
}

impl Default for Line {
    fn default() -> Self {
        Self::new()
    }
}

impl Line {
    pub const fn new() -> Self {
        Line { buf: [0; LINE_CAP], len: 0 }
    }

    pub fn clear(&mut self) -> &mut Self {
        self.len = 0;
        self
    }

    /// Appends bytes, keeping two bytes for the terminator.
    pub fn bytes(&mut self, b: &[u8]) -> &mut Self {
        for &c in b {
            if self.len + 2 >= LINE_CAP {
                break;
            }
            if let Some(slot) = self.buf.get_mut(self.len) {
                *slot = c;
                self.len += 1;
            }
        }
        self
    }

    /// Appends constant text (read from flash on the chip).
    pub fn str(&mut self, s: Text) -> &mut Self {
        for b in s.bytes() {
            self.bytes(&[b]);
        }
        self
    }

    /// A space, then `s`.
    pub fn word(&mut self, s: Text) -> &mut Self {
        self.bytes(b" ").str(s)
    }

    pub fn u32(&mut self, mut v: u32) -> &mut Self {
        let mut digits = [0u8; 10];
        let mut n = 0;
        loop {
            if let Some(d) = digits.get_mut(n) {
                *d = b'0' + (v % 10) as u8;
            }
            n += 1;
            v /= 10;
            if v == 0 || n >= digits.len() {
                break;
            }
        }
        while n > 0 {
            n -= 1;
            let d = digits.get(n).copied().unwrap_or(b'0');
            self.bytes(&[d]);
        }
        self
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

    /// A pulse in Timer5 ticks as µs: 3001 → `1500.5`, 3000 → `1500`.
    pub fn ticks_us(&mut self, ticks: u16) -> &mut Self {
        self.u32(u32::from(ticks / 2));
        if ticks % 2 == 1 {
            self.bytes(b".5");
        }
        self
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
