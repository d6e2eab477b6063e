//! Drawing primitives on any embedded-graphics `DrawTarget<Color = Rgb565>`:
//! solid rectangles, frames and text in the UI's own font.
//!
//! Everything goes through `fill_solid` and `fill_contiguous`, which a display
//! driver turns into one address window plus a pixel stream. Coordinates are
//! `i16`/`u16` so that no function takes more than 18 bytes of arguments
//! (the ATmega2560 miscompiles stack-passed ones).

use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::geometry::Dimensions;
use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::prelude::{Point, Size};
use embedded_graphics::primitives::Rectangle;
use embedded_graphics::Pixel;

use super::flash::{Chars, TextSource};
use super::font::{glyph_row, CELL_H};

/// A screen rectangle in pixels (8 bytes, cheap to pass by value).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Area {
    /// Left column.
    pub x: i16,
    /// Top row.
    pub y: i16,
    /// Width in pixels.
    pub w: u16,
    /// Height in pixels.
    pub h: u16,
}

impl Area {
    /// The `w`×`h` rectangle with its top-left pixel at (`x`, `y`).
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

    /// No pixel inside.
    pub const fn is_empty(&self) -> bool {
        self.w == 0 || self.h == 0
    }

    /// Pixel (`x`, `y`) lies inside.
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

    /// The middle pixel line along the long side of a 3-pixel line:
    /// its middle column (`columns`) or its middle row.
    pub const fn shrink_across(&self, columns: bool) -> Area {
        if columns {
            Area::new(self.x + 1, self.y, 1, self.h)
        } else {
            Area::new(self.x, self.y + 1, self.w, 1)
        }
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

    /// The pixel at the middle (rounded up and left).
    pub const fn centre(&self) -> (i16, i16) {
        (self.x + (self.w / 2) as i16, self.y + (self.h / 2) as i16)
    }

    /// A square of side `2r + 1` centred on `(cx, cy)`.
    pub fn around(cx: i16, cy: i16, r: u16) -> Area {
        Area::new(cx.saturating_sub(r as i16), cy.saturating_sub(r as i16), 2 * r + 1, 2 * r + 1)
    }

    /// The same rectangle for embedded-graphics.
    pub fn to_rect(self) -> Rectangle {
        Rectangle::new(
            Point::new(i32::from(self.x), i32::from(self.y)),
            Size::new(u32::from(self.w), u32::from(self.h)),
        )
    }
}

/// Fills `a` with one colour.
#[inline(never)] // reason: code-size
pub fn fill<D: Canvas>(d: &mut D, a: Area, c: Rgb565) -> Result<(), D::Error> {
    if a.is_empty() {
        return Ok(());
    }
    d.fill_solid(&a.to_rect(), c)
}

/// A `t`-pixel frame just inside `a`.
pub fn frame<D: Canvas>(d: &mut D, a: Area, t: u16, c: Rgb565) -> Result<(), D::Error> {
    for side in frame_sides(a, t).iter().flatten() {
        fill(d, *side, c)?;
    }
    Ok(())
}

/// The four sides of [`frame`] in drawing order (top, bottom, left,
/// right), none when the frame is empty. Not generic and out of line: one
/// copy for every canvas type that draws frames.
#[inline(never)] // reason: code-size
fn frame_sides(a: Area, t: u16) -> Option<[Area; 4]> {
    let t = t.min(a.w / 2).min(a.h / 2);
    if t == 0 {
        return None;
    }
    let ti = t as i16;
    Some([
        Area::new(a.x, a.y, a.w, t),
        Area::new(a.x, a.bottom() - ti, a.w, t),
        Area::new(a.x, a.y + ti, t, a.h - 2 * t),
        Area::new(a.right() - ti, a.y + ti, t, a.h - 2 * t),
    ])
}

/// How text is drawn: `scale` ≥ 1 multiplies the 5×8 glyphs, `gap` is the
/// blank column after each glyph in pixels (normally `scale`: the 6×8 cell;
/// 1 for tight big labels), `bg` = `None` draws only the ink (transparent).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TextStyle {
    /// Pixels per font pixel, ≥ 1.
    pub scale: u8,
    /// Blank columns after each glyph, pixels.
    pub gap: u8,
    /// Ink colour.
    pub fg: Rgb565,
    /// Background colour; `None` leaves it as it was.
    pub bg: Option<Rgb565>,
}

impl TextStyle {
    /// `fg` on `bg`, the normal 6×8 cell scaled.
    pub const fn opaque(scale: u8, fg: Rgb565, bg: Rgb565) -> Self {
        Self { scale, gap: scale, fg, bg: Some(bg) }
    }

    /// Only the ink, in `fg`, over whatever is there.
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

/// A run of one colour in a row-major pixel stream.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Run {
    /// Pixels in the run.
    pub len: u16,
    /// Their colour.
    pub color: Rgb565,
}

/// What the UI draws on: any embedded-graphics target of RGB565 colours,
/// plus two bulk operations whose defaults go through `fill_contiguous`: a
/// row of colour runs (map rows) and a character cell. A display driver
/// overrides them with tight loops instead of an iterator step per pixel
/// (several times faster on the ATmega2560); for any other target
/// `impl Canvas for T {}` is enough.
pub trait Canvas: DrawTarget<Color = Rgb565> {
    /// Fills `area` row by row with `runs` in order. Runs beyond the area are
    /// dropped; if they are shorter, the rest of the area is left as it was.
    fn fill_runs(&mut self, area: &Rectangle, runs: &[Run]) -> Result<(), Self::Error> {
        self.fill_contiguous(area, RunPixels::new(runs))
    }

    /// Paints `cell` with its top-left corner at `(x, y)`, every pixel of
    /// the cell exactly once.
    fn fill_glyph(&mut self, x: i16, y: i16, cell: &GlyphCell) -> Result<(), Self::Error> {
        let area = Area::new(x, y, cell.width(), cell.height());
        self.fill_contiguous(&area.to_rect(), CellPixels { cell, x: 0, y: 0 })
    }

    /// Drawing stopped for this call (a sliced redraw ran out of budget,
    /// `ui::slice`): loops that compute before they draw return early.
    fn paused(&self) -> bool {
        false
    }

    /// The next drawing operation was done by an earlier call of a sliced
    /// redraw: it is counted as done and the caller skips it, without
    /// computing it (a glyph's rows, a map row's runs).
    fn skip_op(&mut self) -> bool {
        false
    }
}

/// The pixels of a run list, colour by colour (for [`Canvas::fill_runs`]).
pub struct RunPixels<'a> {
    runs: &'a [Run],
    k: usize,
    left: u16,
}

impl<'a> RunPixels<'a> {
    /// Starts at the first pixel of the first run.
    pub fn new(runs: &'a [Run]) -> Self {
        Self { runs, k: 0, left: runs.first().map_or(0, |r| r.len) }
    }
}

impl Iterator for RunPixels<'_> {
    type Item = Rgb565;

    fn next(&mut self) -> Option<Rgb565> {
        while self.left == 0 {
            self.k += 1;
            self.left = self.runs.get(self.k)?.len;
        }
        self.left -= 1;
        self.runs.get(self.k).map(|r| r.color)
    }
}

/// One opaque character cell: 8 glyph rows (bit 4 = leftmost of 5
/// columns), each column `scale` pixels wide and each row `scale` high,
/// then `gap` background columns.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct GlyphCell {
    /// The glyph's rows, top first; bit 4 is the leftmost column.
    pub rows: [u8; 8],
    /// Pixels per font pixel, ≥ 1.
    pub scale: u8,
    /// Background columns after the glyph, pixels.
    pub gap: u8,
    /// Ink colour.
    pub fg: Rgb565,
    /// Background colour.
    pub bg: Rgb565,
}

impl GlyphCell {
    /// The cell's width in pixels, gap included.
    pub fn width(&self) -> u16 {
        5 * u16::from(self.scale) + u16::from(self.gap)
    }

    /// The cell's height in pixels.
    pub fn height(&self) -> u16 {
        CELL_H * u16::from(self.scale)
    }

    /// Colour of cell pixel `(x, y)`.
    pub fn pixel(&self, x: u16, y: u16) -> Rgb565 {
        let s = u16::from(self.scale.max(1));
        let col = x / s;
        let bits = self.rows.get(usize::from(y / s)).copied().unwrap_or(0);
        if col < 5 && bits & (0x10 >> col) != 0 {
            self.fg
        } else {
            self.bg
        }
    }
}

/// The pixels of a [`GlyphCell`], for the default [`Canvas::fill_glyph`].
struct CellPixels<'a> {
    cell: &'a GlyphCell,
    x: u16,
    y: u16,
}

impl Iterator for CellPixels<'_> {
    type Item = Rgb565;

    fn next(&mut self) -> Option<Rgb565> {
        if self.y >= self.cell.height() {
            return None;
        }
        let c = self.cell.pixel(self.x, self.y);
        self.x += 1;
        if self.x >= self.cell.width() {
            self.x = 0;
            self.y += 1;
        }
        Some(c)
    }
}

/// Draws `text` with its top-left corner at `(x, y)` and returns the x just
/// after it. Opaque text writes every pixel of its cells exactly once (one
/// [`Canvas::fill_glyph`] per character); transparent text writes only ink
/// runs (one `fill_solid` per run per glyph row).
pub fn text<D: Canvas, T: TextSource + ?Sized>(
    d: &mut D,
    x: i16,
    y: i16,
    text: &T,
    style: &TextStyle,
) -> Result<i16, D::Error> {
    let width = style.advance();
    let mut cx = x;
    for i in 0..text.len() {
        if d.paused() {
            break;
        }
        let ch = text.at(i);
        match style.bg {
            // One operation per opaque glyph.
            Some(_) if d.skip_op() => {}
            Some(bg) => glyph_opaque(d, cx, y, ch, bg, style)?,
            None => glyph_ink(d, cx, y, ch, style)?,
        }
        cx = cx.saturating_add(width as i16);
    }
    Ok(cx)
}

fn glyph_opaque<D: Canvas>(d: &mut D, x: i16, y: i16, ch: u8, bg: Rgb565, style: &TextStyle) -> Result<(), D::Error> {
    let mut rows = [0u8; 8];
    for (r, slot) in rows.iter_mut().enumerate() {
        *slot = glyph_row(ch, r as u8);
    }
    let cell = GlyphCell { rows, scale: style.scale.max(1), gap: style.gap, fg: style.fg, bg };
    d.fill_glyph(x, y, &cell)
}

fn glyph_ink<D: Canvas>(d: &mut D, x: i16, y: i16, ch: u8, style: &TextStyle) -> Result<(), D::Error> {
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
#[inline]
pub fn text_centered<D: Canvas, T: TextSource + ?Sized>(
    d: &mut D,
    a: Area,
    text_bytes: &T,
    style: &TextStyle,
) -> Result<(), D::Error> {
    text_centered_chars(d, a, &text_bytes.chars(), style)
}

/// [`text_centered`] for either kind of text: one copy for both.
fn text_centered_chars<D: Canvas>(
    d: &mut D,
    a: Area,
    text_bytes: &Chars<'_>,
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
    /// The target drawn on.
    pub inner: &'a mut D,
    /// The only area that may change.
    pub clip: Area,
}

impl<D: Canvas> Dimensions for Clip<'_, D> {
    fn bounding_box(&self) -> Rectangle {
        self.clip.to_rect()
    }
}

impl<D: Canvas> DrawTarget for Clip<'_, D> {
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
        // In 16 bits (the UI's areas are screen-sized): embedded-graphics'
        // i32 intersection is several times slower on the ATmega2560, and a
        // clipped repaint runs it for every ink run of every glyph it meets.
        let a = Area::new(
            area.top_left.x as i16,
            area.top_left.y as i16,
            area.size.width.min(u32::from(u16::MAX)) as u16,
            area.size.height.min(u32::from(u16::MAX)) as u16,
        );
        match a.intersect(&self.clip) {
            Some(r) => self.inner.fill_solid(&r.to_rect(), color),
            None => Ok(()),
        }
    }
}

impl<D: Canvas> Canvas for Clip<'_, D> {
    fn paused(&self) -> bool {
        self.inner.paused()
    }
}
