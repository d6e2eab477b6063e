//! Raw touch-panel readings ↔ normalized workspace coordinates (method.md §3), and
//! the derivation of a [`Calibration`] from touched crosshairs.
//!
//! Coordinates: `x_p ∈ [−1, 1]` (left → right), `y_p ∈ [0, 1]` (bottom → top of
//! the workspace). "Panel" raw values are the two ADC channels as the touch
//! driver reads them; a calibration says which channel follows which screen axis
//! (`swap_xy`), in which direction (`invert_*`) and over which raw span.

use crate::math::real::Real;

/// Largest value of the 10-bit ADC.
pub const ADC_MAX: u16 = 1023;

/// A screen axis, to say where a calibration problem is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// Screen X, left → right (`x_p`).
    X,
    /// Screen Y, bottom → top (`y_p`).
    Y,
}

/// Why a calibration is invalid, or could not be fitted or applied.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CalibrationError {
    /// `min >= max` on this screen axis.
    EmptyRange {
        /// The axis.
        axis: Axis,
    },
    /// A limit above [`ADC_MAX`] on this screen axis.
    AboveAdcRange {
        /// The axis.
        axis: Axis,
    },
    /// Inverse mapping of a point outside `[−1, 1] × [0, 1]` or not finite.
    PointOutOfRange,
    /// Fewer crosshairs than the fit needs (2 with a known swap, 3 to detect it).
    TooFewPoints,
    /// Crosshair screen positions that do not determine the fit: not finite,
    /// all at one x or one y, or (when detecting the swap) all on one line.
    DegeneratePositions,
    /// A crosshair raw reading above [`ADC_MAX`].
    RawReadingOutOfRange,
    /// Neither channel assignment explains the readings clearly (each channel
    /// follows both screen axes, or a channel does not change at all).
    AmbiguousAxes,
    /// The fitted raw value at an end of this screen axis lies outside the ADC
    /// range (readings far off the panel's response).
    FitOutOfAdcRange {
        /// The axis.
        axis: Axis,
    },
}

/// Raw span, channel assignment and directions of one touch panel.
///
/// `x_min..x_max` is the raw span of the channel that follows the screen's X
/// axis *after* the optional swap, likewise `y_min..y_max`. Without inversion
/// `x_min` is the left edge and `y_min` the bottom; `invert_x` / `invert_y` flip
/// that. Fields are public so stored calibrations can be rebuilt; every use goes
/// through [`Calibration::validate`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Calibration {
    /// Raw value at the screen's left edge (right edge with `invert_x`).
    pub x_min: u16,
    /// Raw value at the other X edge; above `x_min`.
    pub x_max: u16,
    /// Raw value at the bottom edge (top with `invert_y`).
    pub y_min: u16,
    /// Raw value at the other Y edge; above `y_min`.
    pub y_max: u16,
    /// Panel channel `raw_y` follows screen X and `raw_x` follows screen Y.
    pub swap_xy: bool,
    /// Raw value grows from right to left.
    pub invert_x: bool,
    /// Raw value grows from top to bottom.
    pub invert_y: bool,
}

/// A normalized point. `clamped` is set when a raw value lay outside the
/// calibrated span and was pulled onto its edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MappedPoint<R> {
    /// −1..=1, left → right.
    pub x_p: R,
    /// 0..=1, bottom → top.
    pub y_p: R,
    /// A raw value lay outside the span and was pulled onto its edge.
    pub clamped: bool,
}

/// Two panel channels as read, before any swap.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RawPoint {
    /// The X channel (`RawSample::x`), ADC counts.
    pub x: u16,
    /// The Y channel (`RawSample::y`), ADC counts.
    pub y: u16,
}

/// One calibration touch: the crosshair was drawn at the normalized position
/// `(x_p, y_p)` and the panel read `(raw_x, raw_y)` (channels as read, no swap).
/// Positions need not lie inside the workspace; insets from the edges are usual.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Crosshair<R> {
    /// Crosshair position, normalized X.
    pub x_p: R,
    /// Crosshair position, normalized Y.
    pub y_p: R,
    /// The X channel's reading there.
    pub raw_x: u16,
    /// The Y channel's reading there.
    pub raw_y: u16,
}

/// How [`Calibration::from_crosshairs`] decides `swap_xy`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SwapMode {
    /// Find it from the readings: needs at least 3 crosshairs not on one line
    /// (two diagonal crosshairs move both channels and cannot tell them apart).
    Detect,
    /// Use this value: 2 crosshairs at distinct x and distinct y suffice.
    Known(bool),
}

fn check_axis(min: u16, max: u16, axis: Axis) -> Result<(), CalibrationError> {
    if min > ADC_MAX || max > ADC_MAX {
        return Err(CalibrationError::AboveAdcRange { axis });
    }
    if min >= max {
        return Err(CalibrationError::EmptyRange { axis });
    }
    Ok(())
}

fn clamp_raw(v: u16, min: u16, max: u16) -> (u16, bool) {
    if v < min {
        (min, true)
    } else if v > max {
        (max, true)
    } else {
        (v, false)
    }
}

/// `v` as `R` for |v| ≤ 65535 (callers stay within ±2046).
fn from_i32<R: Real>(v: i32) -> R {
    let m = R::from_u16(v.unsigned_abs().min(u16::MAX as u32) as u16);
    if v < 0 {
        -m
    } else {
        m
    }
}

/// Rounds to the nearest raw value (ties up); `None` outside `[0, ADC_MAX]` or
/// not finite. `Real` has no float→int conversion, so the floor of `v + ½` is
/// built bit by bit by exact comparisons (ten of them).
fn round_raw<R: Real>(v: R) -> Option<u16> {
    let w = v + R::HALF;
    if !(w >= R::ZERO && w < R::from_u16(ADC_MAX + 1)) {
        return None;
    }
    let mut n: u16 = 0;
    let mut bit: u16 = 1 << 9;
    while bit != 0 {
        let c = n | bit;
        if R::from_u16(c) <= w {
            n = c;
        }
        bit >>= 1;
    }
    Some(n)
}

impl Calibration {
    /// method.md §3: X 123..932, Y 128..897, no swap, no inversion.
    pub const DEFAULT: Self =
        Self { x_min: 123, x_max: 932, y_min: 128, y_max: 897, swap_xy: false, invert_x: false, invert_y: false };

    /// Limits within the ADC range and `min < max` on both axes.
    pub fn validate(&self) -> Result<(), CalibrationError> {
        check_axis(self.x_min, self.x_max, Axis::X)?;
        check_axis(self.y_min, self.y_max, Axis::Y)
    }

    /// Maps a panel reading to the workspace. Raw values outside the span are
    /// clamped onto its edge and reported through `clamped`; the only error is
    /// an invalid calibration.
    ///
    /// `x_p = (2·raw − min − max)/(max − min)`, which is method.md's
    /// `(raw − mid)/half`, and `y_p = (raw − min)/(max − min)`: numerators and
    /// denominators are small integers (exact in f32), so each coordinate is the
    /// exact value rounded once and the span ends land on exactly −1, 1, 0, 1.
    ///
    /// ```
    /// use touch_arm::touch::map::Calibration;
    ///
    /// // The default span is X 123..932, Y 128..897.
    /// let cal = Calibration::DEFAULT;
    /// let corner = cal.map::<f64>(123, 897).unwrap();
    /// assert_eq!((corner.x_p, corner.y_p, corner.clamped), (-1.0, 1.0, false));
    /// // (549, 745): x_p = (2·549 − 123 − 932)/809 = 43/809, y_p = (745 − 128)/769.
    /// let p = cal.map::<f64>(549, 745).unwrap();
    /// assert_eq!((p.x_p, p.y_p), (43.0 / 809.0, 617.0 / 769.0));
    /// // Outside the span: clamped onto its edge, and said so.
    /// let out = cal.map::<f64>(1000, 100).unwrap();
    /// assert_eq!((out.x_p, out.y_p, out.clamped), (1.0, 0.0, true));
    /// ```
    pub fn map<R: Real>(&self, raw_x: u16, raw_y: u16) -> Result<MappedPoint<R>, CalibrationError> {
        self.validate()?;
        let (sx, sy) = if self.swap_xy { (raw_y, raw_x) } else { (raw_x, raw_y) };
        let (cx, clamped_x) = clamp_raw(sx, self.x_min, self.x_max);
        let (cy, clamped_y) = clamp_raw(sy, self.y_min, self.y_max);
        let (x_min, x_max) = (i32::from(self.x_min), i32::from(self.x_max));
        let mut num_x = 2 * i32::from(cx) - x_min - x_max;
        if self.invert_x {
            num_x = -num_x;
        }
        // Inverting y uses the distance from the top instead of 1 − y_p, which
        // would round twice.
        let num_y = if self.invert_y { self.y_max - cy } else { cy - self.y_min };
        Ok(MappedPoint {
            x_p: from_i32::<R>(num_x) / R::from_u16(self.x_max - self.x_min),
            y_p: R::from_u16(num_y) / R::from_u16(self.y_max - self.y_min),
            clamped: clamped_x || clamped_y,
        })
    }

    /// The unrounded panel reading `(raw_x, raw_y)` (channels as read) that maps
    /// to `(x_p, y_p)`: the exact inverse of [`Calibration::map`] inside the span.
    pub fn unmap_exact<R: Real>(&self, x_p: R, y_p: R) -> Result<(R, R), CalibrationError> {
        self.validate()?;
        let inside = x_p >= -R::ONE && x_p <= R::ONE && y_p >= R::ZERO && y_p <= R::ONE;
        if !inside {
            // NaN fails every comparison and lands here too.
            return Err(CalibrationError::PointOutOfRange);
        }
        let x = if self.invert_x { -x_p } else { x_p };
        let sx = (R::from_u16(self.x_min + self.x_max) + x * R::from_u16(self.x_max - self.x_min)) * R::HALF;
        let span_y = R::from_u16(self.y_max - self.y_min);
        let sy =
            if self.invert_y { R::from_u16(self.y_max) - y_p * span_y } else { R::from_u16(self.y_min) + y_p * span_y };
        Ok(if self.swap_xy { (sy, sx) } else { (sx, sy) })
    }

    /// [`Calibration::unmap_exact`] rounded to the nearest raw values (ties up):
    /// what an ideal panel would read at that point.
    pub fn unmap<R: Real>(&self, x_p: R, y_p: R) -> Result<RawPoint, CalibrationError> {
        let (x, y) = self.unmap_exact(x_p, y_p)?;
        match (round_raw(x), round_raw(y)) {
            (Some(x), Some(y)) => Ok(RawPoint { x, y }),
            _ => Err(CalibrationError::PointOutOfRange),
        }
    }

    /// [`Calibration::unmap`] at the centre of glass pixel `(gx, gy)` of a
    /// `w`×`h` screen (the panel point `((2gx + 1)/w − 1, 1 − (2gy +
    /// 1)/2h)`), in integers: that centre lies `(2g + 1)/2n` of the way
    /// across, so `(2g + 1)/2n` of the span from the edge the calibration
    /// puts there, rounded to the nearest count. The float form cost the
    /// firmware 0.8 KB of flash where only pixels are unmapped (the
    /// switch's presses); within one count of it (`tests::
    /// unmap_pixel_is_unmap_at_the_pixel_centre`).
    pub fn unmap_pixel(&self, gx: i16, gy: i16, w: u16, h: u16) -> RawPoint {
        // x_p = −1 at the left edge: x_min there (x_max if inverted); y_p
        // = 1 at the top: y_max there (y_min if inverted).
        let (x0, x1) = if self.invert_x { (self.x_max, self.x_min) } else { (self.x_min, self.x_max) };
        let (y0, y1) = if self.invert_y { (self.y_min, self.y_max) } else { (self.y_max, self.y_min) };
        let (sx, sy) = (along(x0, x1, gx, w), along(y0, y1, gy, h));
        if self.swap_xy {
            RawPoint { x: sy, y: sx }
        } else {
            RawPoint { x: sx, y: sy }
        }
    }

    /// Derives a calibration from crosshair touches.
    ///
    /// Each panel channel is modelled as affine in one screen axis. With
    /// [`SwapMode::Detect`] both channels are first fitted (least squares) as
    /// affine in *both* screen axes; the channel assignment whose coefficient
    /// product dominates (`|∂a/∂x·∂b/∂y|` vs `|∂a/∂y·∂b/∂x|`) by at least 4× is
    /// taken, otherwise the readings are [`CalibrationError::AmbiguousAxes`].
    /// Then each screen axis gets a 1-D least-squares line through its channel,
    /// evaluated at the axis ends (x = ±1, y = 0 and 1) and rounded; a falling
    /// line sets the inversion flag. With noisy readings more crosshairs (e.g.
    /// four corners plus the centre) average the noise out.
    pub fn from_crosshairs<R: Real>(points: &[Crosshair<R>], swap: SwapMode) -> Result<Self, CalibrationError> {
        let needed = match swap {
            SwapMode::Detect => 3,
            SwapMode::Known(_) => 2,
        };
        if points.len() < needed {
            return Err(CalibrationError::TooFewPoints);
        }
        let mut n = R::ZERO;
        let (mut mx, mut my, mut ma, mut mb) = (R::ZERO, R::ZERO, R::ZERO, R::ZERO);
        for p in points {
            if !(p.x_p.is_finite() && p.y_p.is_finite()) {
                return Err(CalibrationError::DegeneratePositions);
            }
            if p.raw_x > ADC_MAX || p.raw_y > ADC_MAX {
                return Err(CalibrationError::RawReadingOutOfRange);
            }
            n += R::ONE;
            mx += p.x_p;
            my += p.y_p;
            ma += R::from_u16(p.raw_x);
            mb += R::from_u16(p.raw_y);
        }
        let inv_n = n.recip();
        mx *= inv_n;
        my *= inv_n;
        ma *= inv_n;
        mb *= inv_n;
        // Centred sums keep f32 accurate with raw values near 1000.
        let (mut sxx, mut syy, mut sxy) = (R::ZERO, R::ZERO, R::ZERO);
        let (mut sxa, mut sxb, mut sya, mut syb) = (R::ZERO, R::ZERO, R::ZERO, R::ZERO);
        for p in points {
            let (dx, dy) = (p.x_p - mx, p.y_p - my);
            let (da, db) = (R::from_u16(p.raw_x) - ma, R::from_u16(p.raw_y) - mb);
            sxx += dx * dx;
            syy += dy * dy;
            sxy += dx * dy;
            sxa += dx * da;
            sxb += dx * db;
            sya += dy * da;
            syb += dy * db;
        }
        if !(sxx > R::ZERO && syy > R::ZERO) {
            return Err(CalibrationError::DegeneratePositions);
        }
        let swap_xy = match swap {
            SwapMode::Known(s) => s,
            SwapMode::Detect => {
                let det = sxx * syy - sxy * sxy;
                // 1 − (correlation of the positions)² > 1 %: not (nearly) one line.
                if !det.gt(&(R::lit(0.01) * sxx * syy)) {
                    return Err(CalibrationError::DegeneratePositions);
                }
                // Coefficients of the 2-D fits times det (> 0), which cancels in
                // the comparison.
                let a_x = syy * sxa - sxy * sya;
                let a_y = sxx * sya - sxy * sxa;
                let b_x = syy * sxb - sxy * syb;
                let b_y = sxx * syb - sxy * sxb;
                let straight = (a_x * b_y).abs();
                let crossed = (a_y * b_x).abs();
                let four = R::lit(4.0);
                if straight > four * crossed {
                    false
                } else if crossed > four * straight {
                    true
                } else {
                    return Err(CalibrationError::AmbiguousAxes);
                }
            }
        };
        let (s_x, m_cx, s_y, m_cy) = if swap_xy { (sxb, mb, sya, ma) } else { (sxa, ma, syb, mb) };
        let slope_x = s_x / sxx;
        let slope_y = s_y / syy;
        let at_x = |x: R| m_cx + slope_x * (x - mx);
        let at_y = |y: R| m_cy + slope_y * (y - my);
        let round = |v: R, axis: Axis| round_raw(v).ok_or(CalibrationError::FitOutOfAdcRange { axis });
        let left = round(at_x(-R::ONE), Axis::X)?;
        let right = round(at_x(R::ONE), Axis::X)?;
        let bottom = round(at_y(R::ZERO), Axis::Y)?;
        let top = round(at_y(R::ONE), Axis::Y)?;
        let invert_x = slope_x < R::ZERO;
        let invert_y = slope_y < R::ZERO;
        let (x_min, x_max) = if invert_x { (right, left) } else { (left, right) };
        let (y_min, y_max) = if invert_y { (top, bottom) } else { (bottom, top) };
        let cal = Self { x_min, x_max, y_min, y_max, swap_xy, invert_x, invert_y };
        cal.validate()?;
        Ok(cal)
    }
}

impl Default for Calibration {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// The raw value `(2g + 1)/2n` of the way from `from` to `to`, rounded
/// ([`Calibration::unmap_pixel`]). Out of line: one copy for both axes.
#[inline(never)] // reason: code-size
fn along(from: u16, to: u16, g: i16, n: u16) -> u16 {
    let (num, den) = (2 * u32::from(g.max(0) as u16) + 1, 2 * u32::from(n.max(1)));
    let d = ((u32::from(from.abs_diff(to)) * num + den / 2) / den) as u16;
    if to >= from {
        from.saturating_add(d)
    } else {
        from.saturating_sub(d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every pixel centre of both screens, under calibrations with each
    /// swap and inversion: the integer form agrees with the float one to
    /// a count.
    #[test]
    fn unmap_pixel_is_unmap_at_the_pixel_centre() {
        for (w, h) in [(320u16, 240u16), (480, 320)] {
            for flags in 0..8u8 {
                let c = Calibration {
                    x_min: 123,
                    x_max: 932,
                    y_min: 128,
                    y_max: 897,
                    swap_xy: flags & 1 != 0,
                    invert_x: flags & 2 != 0,
                    invert_y: flags & 4 != 0,
                };
                for gx in 0..w as i16 {
                    for gy in (0..h as i16).step_by(7) {
                        let x_p = (2.0 * f64::from(gx) + 1.0) / f64::from(w) - 1.0;
                        let y_p = 1.0 - (2.0 * f64::from(gy) + 1.0) / (2.0 * f64::from(h));
                        let want = c.unmap::<f64>(x_p, y_p).unwrap();
                        let got = c.unmap_pixel(gx, gy, w, h);
                        assert!(
                            got.x.abs_diff(want.x) <= 1 && got.y.abs_diff(want.y) <= 1,
                            "{w}x{h} {flags} ({gx}, {gy})"
                        );
                    }
                }
            }
        }
    }
}
