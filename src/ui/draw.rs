//! Drawing primitives on any embedded-graphics `DrawTarget<Color = Rgb565>`:
//! solid rectangles, frames and text in the UI's own font.
//!
//! Everything goes through `fill_solid` and `fill_contiguous`, which a display
//! driver turns into one address window plus a pixel stream. Coordinates are
//! `i16`/`u16` so that no function takes more than 18 bytes of arguments
//! (the ATmega2560 miscompiles stack-passed ones).

use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::prelude::{Point, Size};
use embedded_graphics::primitives::Rectangle;
use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::geometry::Dimensions;
use embedded_graphics::Pixel;

use super::flash::TextSource;
use super::font::{glyph_row, CELL_H};

/// A screen rectangle in pixels (8 bytes, cheap to pass by value).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Area {
    pub x: i16,
    pub y: i16,
    pub w: u16,
    pub h: u16,
}

impl Area {
    pub const fn new(x: i16, y: i16, w: u16, h: u16) -> Self {
        Self { x, y, w, h }
    }

    /// One past the last column.
    pub const fn right(&self) -> i16 {
        self.x.saturating_add(self.w as i16)
    }

    /// One past the last row.
    pub const fn bottom(&self) -> i16 {
        self.y.saturating_add(self.h as i16)
    }

    pub const fn is_empty(&self) -> bool {
        self.w == 0 || self.h == 0
    }

    pub const fn contains(&self, x: i16, y: i16) -> bool {
        x >= self.x && x < self.right() && y >= self.y && y < self.bottom()
    }

    /// The common part, if any.
    pub fn intersect(&self, other: &Area) -> Option<Area> {
        let x0 = self.x.max(other.x);
        let y0 = self.y.max(other.y);
        let x1 = self.right().min(other.right());
        let y1 = self.bottom().min(other.bottom());
        if x1 > x0 && y1 > y0 {
            Some(Area::new(x0, y0, (x1 - x0) as u16, (y1 - y0) as u16))
        } else {
            None
        }
    }

    /// Grows by `d` on every side.
    pub fn inflate(&self, d: u16) -> Area {
        Area::new(
            self.x.saturating_sub(d as i16),
            self.y.saturating_sub(d as i16),
            self.w.saturating_add(2 * d),
            self.h.saturating_add(2 * d),
        )
    }

    /// Shrinks by `d` on every side (empty when too small).
    pub fn shrink(&self, d: u16) -> Area {
        Area::new(
            self.x.saturating_add(d as i16),
            self.y.saturating_add(d as i16),
            self.w.saturating_sub(2 * d),
            self.h.saturating_sub(2 * d),
        )
    }

    /// A square of side `2r + 1` centred on `(cx, cy)`.
    pub fn around(cx: i16, cy: i16, r: u16) -> Area {
        Area::new(cx.saturating_sub(r as i16), cy.saturating_sub(r as i16), 2 * r + 1, 2 * r + 1)
    }

    pub fn to_rect(self) -> Rectangle {
        Rectangle::new(
            Point::new(i32::from(self.x), i32::from(self.y)),
            Size::new(u32::from(self.w), u32::from(self.h)),
        )
    }
}

/// Fills `a` with one colour.
#[inline]
pub fn fill<D: DrawTarget<Color = Rgb565>>(d: &mut D, a: Area, c: Rgb565) -> Result<(), D::Error> {
    if a.is_empty() {
        return Ok(());
    }
    d.fill_solid(&a.to_rect(), c)
}

/// A `t`-pixel frame just inside `a`.
pub fn frame<D: DrawTarget<Color = Rgb565>>(d: &mut D, a: Area, t: u16, c: Rgb565) -> Result<(), D::Error> {
    let t = t.min(a.w / 2).min(a.h / 2);
    if t == 0 {
        return Ok(());
    }
    let ti = t as i16;
    fill(d, Area::new(a.x, a.y, a.w, t), c)?;
    fill(d, Area::new(a.x, a.bottom() - ti, a.w, t), c)?;
    fill(d, Area::new(a.x, a.y + ti, t, a.h - 2 * t), c)?;
    fill(d, Area::new(a.right() - ti, a.y + ti, t, a.h - 2 * t), c)
}

/// How text is drawn: `scale` ≥ 1 multiplies the 5×8 glyphs, `gap` is the
/// blank column after each glyph in pixels (normally `scale`: the 6×8 cell;
/// 1 for tight big labels), `bg` = `None` draws only the ink (transparent).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TextStyle {
    pub scale: u8,
    pub gap: u8,
    pub fg: Rgb565,
    pub bg: Option<Rgb565>,
}

impl TextStyle {
    pub const fn opaque(scale: u8, fg: Rgb565, bg: Rgb565) -> Self {
        Self { scale, gap: scale, fg, bg: Some(bg) }
    }

    pub const fn ink(scale: u8, fg: Rgb565) -> Self {
        Self { scale, gap: scale, fg, bg: None }
    }

    /// The same with a one-pixel gap between glyphs.
    pub const fn tight(self) -> Self {
        Self { gap: 1, ..self }
    }

    fn scale(&self) -> u16 {
        u16::from(self.scale.max(1))
    }

    /// Width of one glyph cell (ink plus gap).
    pub fn advance(&self) -> u16 {
        5 * self.scale() + u16::from(self.gap)
    }

    /// Size of `len` characters.
    pub fn extent(&self, len: usize) -> (u16, u16) {
        (self.advance() * (len.min(400) as u16), CELL_H * self.scale())
    }
}

/// The pixels of one opaque glyph cell in row-major order, for one
/// `fill_contiguous` per glyph. Counters only, no division: the chip has no
/// divider and this runs once per pixel.
struct GlyphPixels {
    ch: u8,
    scale: u8,
    gap: u8,
    fg: Rgb565,
    bg: Rgb565,
    /// Current glyph row's bits, and the bit of the current column (0 once
    /// in the gap).
    bits: u8,
    mask: u8,
    /// Glyph row, and pixels left in the current column / pixel row.
    row: u8,
    left_x: u8,
    left_y: u8,
}

impl GlyphPixels {
    fn new(ch: u8, style: &TextStyle, bg: Rgb565) -> Self {
        let s = style.scale.max(1);
        Self {
            ch,
            scale: s,
            gap: style.gap,
            fg: style.fg,
            bg,
            bits: glyph_row(ch, 0),
            mask: 0x10,
            row: 0,
            left_x: s,
            left_y: s,
        }
    }
}

impl Iterator for GlyphPixels {
    type Item = Rgb565;

    #[inline]
    fn next(&mut self) -> Option<Rgb565> {
        if self.row >= CELL_H as u8 {
            return None;
        }
        let ink = self.bits & self.mask != 0;
        self.left_x -= 1;
        if self.left_x == 0 {
            if self.mask > 1 {
                self.mask >>= 1;
                self.left_x = self.scale;
            } else if self.mask == 1 {
                // Into the gap (possibly zero wide).
                self.mask = 0;
                self.left_x = self.gap;
            }
            if self.left_x == 0 {
                // End of a pixel row.
                self.mask = 0x10;
                self.left_x = self.scale;
                self.left_y -= 1;
                if self.left_y == 0 {
                    self.left_y = self.scale;
                    self.row += 1;
                    self.bits = glyph_row(self.ch, self.row);
                }
            }
        }
        Some(if ink { self.fg } else { self.bg })
    }
}

/// Draws `text` with its top-left corner at `(x, y)` and returns the x just
/// after it. Opaque text writes every pixel of its cells exactly once (one
/// `fill_contiguous` per glyph); transparent text writes only ink runs (one
/// `fill_solid` per run per glyph row).
pub fn text<D: DrawTarget<Color = Rgb565>, T: TextSource + ?Sized>(
    d: &mut D,
    x: i16,
    y: i16,
    text: &T,
    style: &TextStyle,
) -> Result<i16, D::Error> {
    let s = style.scale();
    let width = style.advance();
    let mut cx = x;
    for i in 0..text.len() {
        let ch = text.at(i);
        match style.bg {
            Some(bg) => {
                let area = Area::new(cx, y, width, CELL_H * s);
                let pixels = GlyphPixels::new(ch, style, bg);
                d.fill_contiguous(&area.to_rect(), pixels)?;
            }
            None => glyph_ink(d, cx, y, ch, style)?,
        }
        cx = cx.saturating_add(width as i16);
    }
    Ok(cx)
}

fn glyph_ink<D: DrawTarget<Color = Rgb565>>(d: &mut D, x: i16, y: i16, ch: u8, style: &TextStyle) -> Result<(), D::Error> {
    let s = style.scale();
    for row in 0..CELL_H as u8 {
        let bits = glyph_row(ch, row);
        let mut col: u16 = 0;
        while col < 5 {
            if bits >> (4 - col) & 1 == 0 {
                col += 1;
                continue;
            }
            let start = col;
            while col < 5 && bits >> (4 - col) & 1 == 1 {
                col += 1;
            }
            let run = Area::new(x + (start * s) as i16, y + (u16::from(row) * s) as i16, (col - start) * s, s);
            fill(d, run, style.fg)?;
        }
    }
    Ok(())
}

/// Draws `text` centred in `a` (horizontally and vertically), clipped to
/// nothing: the caller sizes `a` to fit.
pub fn text_centered<D: DrawTarget<Color = Rgb565>, T: TextSource + ?Sized>(
    d: &mut D,
    a: Area,
    text_bytes: &T,
    style: &TextStyle,
) -> Result<(), D::Error> {
    let (w, h) = style.extent(text_bytes.len());
    let w = w.saturating_sub(u16::from(style.gap));
    let x = a.x + (a.w.saturating_sub(w) / 2) as i16;
    let y = a.y + (a.h.saturating_sub(h) / 2) as i16;
    text(d, x, y, text_bytes, style).map(|_| ())
}

/// Passes only what falls inside `clip` on to the wrapped target: used to
/// repaint a small box of a layered picture (background, labels, markers).
pub struct Clip<'a, D> {
    pub inner: &'a mut D,
    pub clip: Area,
}

impl<D: DrawTarget<Color = Rgb565>> Dimensions for Clip<'_, D> {
    fn bounding_box(&self) -> Rectangle {
        self.clip.to_rect()
    }
}

impl<D: DrawTarget<Color = Rgb565>> DrawTarget for Clip<'_, D> {
    type Color = Rgb565;
    type Error = D::Error;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Pixel<Rgb565>>,
    {
        let clip = self.clip.to_rect();
        self.inner.draw_iter(pixels.into_iter().filter(|p| clip.contains(p.0)))
    }

    fn fill_solid(&mut self, area: &Rectangle, color: Rgb565) -> Result<(), Self::Error> {
        let r = area.intersection(&self.clip.to_rect());
        if r.size.width == 0 || r.size.height == 0 {
            return Ok(());
        }
        self.inner.fill_solid(&r, color)
    }
}
