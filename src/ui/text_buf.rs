//! A fixed-size line buffer for composing screen text without alloc.

use super::flash::TextSource;
use super::font::DEGREE;

/// Up to `N` bytes; pushes beyond that are dropped (a screen line is short).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Line<const N: usize> {
    bytes: [u8; N],
    len: usize,
}

impl<const N: usize> Default for Line<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> Line<N> {
    pub const fn new() -> Self {
        Self { bytes: [b' '; N], len: 0 }
    }

    pub fn as_bytes(&self) -> &[u8] {
        self.bytes.get(..self.len).unwrap_or(&[])
    }

    pub fn push<T: TextSource + ?Sized>(&mut self, s: &T) -> &mut Self {
        for i in 0..s.len() {
            self.push_byte(s.at(i));
        }
        self
    }

    pub fn push_byte(&mut self, b: u8) -> &mut Self {
        if let Some(slot) = self.bytes.get_mut(self.len) {
            *slot = b;
            self.len += 1;
        }
        self
    }

    pub fn push_int(&mut self, v: i32) -> &mut Self {
        if v < 0 {
            self.push_byte(b'-');
        }
        let mut digits = [0u8; 10];
        let n = crate::text::decimal(v.unsigned_abs(), &mut digits);
        self.push(digits.get(..n).unwrap_or(&[]));
        self
    }

    /// `v` degrees, or `--` for `None`.
    pub fn push_deg(&mut self, v: Option<i16>) -> &mut Self {
        match v {
            Some(d) => self.push_int(i32::from(d)).push_byte(DEGREE),
            None => self.push_byte(b'-').push_byte(b'-'),
        }
    }
}

/// Radians to whole degrees, rounded half away from zero; `None` when not
/// finite. Clamped to ±9999 so the text stays short.
pub fn rad_to_deg(rad: f32) -> Option<i16> {
    if !rad.is_finite() {
        return None;
    }
    let deg = rad * (180.0 / core::f32::consts::PI);
    let deg = deg.clamp(-9999.0, 9999.0);
    let rounded = if deg >= 0.0 { deg + 0.5 } else { deg - 0.5 };
    Some(rounded as i16)
}
