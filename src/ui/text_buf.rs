//! A fixed-size line buffer for composing screen text without alloc.

use super::flash::TextSource;
use super::font::DEGREE;
use crate::math::units::{rad_to_deg, round_i32};

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
        let mut n = v.unsigned_abs();
        let mut digits = [0u8; 10];
        let mut k = 0;
        loop {
            if let Some(d) = digits.get_mut(k) {
                *d = b'0' + (n % 10) as u8;
            }
            k += 1;
            n /= 10;
            if n == 0 || k >= digits.len() {
                break;
            }
        }
        while k > 0 {
            k -= 1;
            if let Some(&d) = digits.get(k) {
                self.push_byte(d);
            }
        }
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
pub fn whole_deg(rad: f32) -> Option<i16> {
    if !rad.is_finite() {
        return None;
    }
    Some(round_i32(rad_to_deg(rad).clamp(-9999.0, 9999.0)) as i16)
}
