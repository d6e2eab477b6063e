//! Angles as the screen shows them: whole degrees with the font's degree
//! glyph, `--` when unknown.

use super::font::DEGREE;
use crate::math::units::{rad_to_deg, round_i32};
use crate::text::line::Line;

/// Radians to whole degrees, rounded half away from zero; `None` when not
/// finite. Clamped to ±9999 so the text stays short.
pub fn whole_deg(rad: f32) -> Option<i16> {
    if !rad.is_finite() {
        return None;
    }
    Some(round_i32(rad_to_deg(rad).clamp(-9999.0, 9999.0)) as i16)
}

/// Appending an angle to a line of screen text.
pub trait PushDeg {
    /// `v` degrees with the degree glyph, or `--` for `None`.
    fn deg(&mut self, v: Option<i16>) -> &mut Self;
}

impl<const N: usize> PushDeg for Line<N> {
    fn deg(&mut self, v: Option<i16>) -> &mut Self {
        match v {
            Some(d) => self.i32(i32::from(d)).bytes(&[DEGREE]),
            None => self.bytes(b"--"),
        }
    }
}
