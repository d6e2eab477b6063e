//! Drawing in slices that fit what a frame leaves (issue #11): a redraw is
//! cut into drawing operations of bounded size, the [`DrawBudget`] is asked
//! before each, and when it says no the redraw pauses; the next call replays
//! the same deterministic drawing and skips the operations already done.
//!
//! [`Slicer`] is the canvas that does the counting: it passes operations on to
//! the real canvas, splits a large `fill_solid` into bands of at most
//! [`MAX_OP_PIXELS`], and once the budget is spent lets the rest of the step
//! run without drawing ([`Slicer::paused`]). Every drawing function of the UI
//! is generic over the canvas, so it runs on a `Slicer` unchanged; pausing is
//! not an error, so the canvas's error type stays the real one (the display's
//! `Infallible`, and the compiler drops every error path).

use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::geometry::Dimensions;
use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::primitives::Rectangle;
use embedded_graphics::Pixel;

use super::draw::{Canvas, GlyphCell, Run};

/// Largest single drawing operation, pixels: a solid fill is split into row
/// bands of at most this many (a glyph cell is at most 18 × 24 = 432, a map
/// row 240).
pub const MAX_OP_PIXELS: u32 = 1024;
const _: () = assert!(MAX_OP_PIXELS <= u16::MAX as u32);

/// Pixels an operation of unknown size (a pixel iterator) is charged as.
const ITER_PIXELS: u32 = 432;

/// Says whether the next drawing operation still fits in this frame.
pub trait DrawBudget {
    /// Called before every operation with its size in pixels; `false`
    /// pauses the redraw before it.
    fn allows(&mut self, pixels: u32) -> bool;

    /// Called before a redraw starts working out what to draw (the model, a
    /// resumed step's replay); `false` leaves the screen for the next frame.
    fn may_start(&mut self) -> bool {
        self.allows(0)
    }
}

/// No limit: the whole redraw at once.
pub struct Unlimited;

impl DrawBudget for Unlimited {
    fn allows(&mut self, _pixels: u32) -> bool {
        true
    }
}

/// At most `pixels` pixels of operations (host tests of slicing).
pub struct PixelBudget {
    /// Pixels still allowed.
    pub pixels: u32,
}

impl DrawBudget for PixelBudget {
    fn allows(&mut self, pixels: u32) -> bool {
        if pixels > self.pixels {
            return false;
        }
        self.pixels -= pixels;
        true
    }
}

/// The counting canvas (see the module doc).
pub struct Slicer<'a, D, B> {
    /// The canvas that really draws.
    pub inner: &'a mut D,
    /// What this call may still draw.
    pub budget: &'a mut B,
    /// Operations already drawn by an earlier call: skipped.
    pub skip: u32,
    /// Operations met so far (drawn or skipped) before the pause.
    pub ops: u32,
    /// The budget said no: nothing more is drawn in this call.
    pub paused: bool,
}

impl<'a, D: Canvas, B: DrawBudget> Slicer<'a, D, B> {
    /// Draws on `inner` within `budget`, skipping the first `skip`
    /// operations (drawn by an earlier call).
    pub fn new(inner: &'a mut D, budget: &'a mut B, skip: u32) -> Self {
        Slicer { inner, budget, skip, ops: 0, paused: false }
    }

    /// Whether to draw the next operation of `pixels` pixels: skipped ones
    /// are not, and a spent budget pauses. (Here and below `inline(never)`:
    /// the UI has hundreds of drawing calls; inlined, each would carry the
    /// budget check.)
    #[inline(never)] // reason: code-size
    fn gate(&mut self, pixels: u32) -> bool {
        if self.paused {
            return false;
        }
        let n = self.ops;
        if n < self.skip {
            self.ops += 1;
            return false;
        }
        if !self.budget.allows(pixels) {
            self.paused = true;
            return false;
        }
        self.ops += 1;
        true
    }
}

fn pixels_of(r: &Rectangle) -> u32 {
    r.size.width.saturating_mul(r.size.height)
}

impl<D: Canvas, B> Dimensions for Slicer<'_, D, B> {
    fn bounding_box(&self) -> Rectangle {
        self.inner.bounding_box()
    }
}

impl<D: Canvas, B: DrawBudget> DrawTarget for Slicer<'_, D, B> {
    type Color = Rgb565;
    type Error = D::Error;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Pixel<Rgb565>>,
    {
        if self.gate(ITER_PIXELS) {
            self.inner.draw_iter(pixels)?;
        }
        Ok(())
    }

    fn fill_contiguous<I>(&mut self, area: &Rectangle, colors: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Rgb565>,
    {
        if self.gate(pixels_of(area)) {
            self.inner.fill_contiguous(area, colors)?;
        }
        Ok(())
    }

    #[inline(never)] // reason: code-size
    fn fill_solid(&mut self, area: &Rectangle, color: Rgb565) -> Result<(), Self::Error> {
        // Paused: the rest of the step runs only to return, so at no cost.
        if self.paused {
            return Ok(());
        }
        // 16-bit division: the UI's areas are screen-sized.
        let w = area.size.width.clamp(1, u32::from(u16::MAX)) as u16;
        let rows = u32::from((MAX_OP_PIXELS as u16 / w).max(1));
        let mut y = 0;
        while y < area.size.height {
            let h = rows.min(area.size.height - y);
            let band = Rectangle::new(
                area.top_left + embedded_graphics::geometry::Point::new(0, y as i32),
                embedded_graphics::geometry::Size::new(area.size.width, h),
            );
            if self.gate(pixels_of(&band)) {
                self.inner.fill_solid(&band, color)?;
            }
            y += h;
        }
        Ok(())
    }
}

impl<D: Canvas, B: DrawBudget> Canvas for Slicer<'_, D, B> {
    #[inline(never)] // reason: code-size
    fn fill_runs(&mut self, area: &Rectangle, runs: &[Run]) -> Result<(), Self::Error> {
        if self.gate(pixels_of(area)) {
            self.inner.fill_runs(area, runs)?;
        }
        Ok(())
    }

    fn paused(&self) -> bool {
        self.paused
    }

    fn skip_op(&mut self) -> bool {
        if self.paused || self.ops >= self.skip {
            return false;
        }
        self.ops += 1;
        true
    }

    #[inline(never)] // reason: code-size
    fn fill_glyph(&mut self, x: i16, y: i16, cell: &GlyphCell) -> Result<(), Self::Error> {
        if self.gate(u32::from(cell.width()) * u32::from(cell.height())) {
            self.inner.fill_glyph(x, y, cell)?;
        }
        Ok(())
    }
}
