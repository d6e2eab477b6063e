//! Host twin of the screen: an RGB565 framebuffer that is an
//! embedded-graphics `DrawTarget`, PNG output, and a wrapper that counts
//! every pixel write (to check that partial redraws stay in their regions).

use std::convert::Infallible;
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::geometry::{Dimensions, OriginDimensions, Point, Size};
use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use embedded_graphics::primitives::{PointsIter, Rectangle};
use embedded_graphics::Pixel;
use touch_arm::ui::Canvas;

/// `width × height` pixels, row-major.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Framebuffer {
    width: u32,
    height: u32,
    pixels: Vec<Rgb565>,
}

/// 8-bit channels of an RGB565 colour, expanded by bit replication (so 0 →
/// 0 and full scale → 255).
pub fn to_rgb888(c: Rgb565) -> [u8; 3] {
    let (r, g, b) = (c.r(), c.g(), c.b());
    [(r << 3) | (r >> 2), (g << 2) | (g >> 4), (b << 3) | (b >> 2)]
}

impl Framebuffer {
    /// The ILI9341 in landscape: 320×240.
    pub fn landscape() -> Self {
        Self::new(320, 240, Rgb565::BLACK)
    }

    /// A `width × height` framebuffer, every pixel `fill`.
    pub fn new(width: u32, height: u32, fill: Rgb565) -> Self {
        Self { width, height, pixels: vec![fill; (width * height) as usize] }
    }

    /// Width, pixels.
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height, pixels.
    pub fn height(&self) -> u32 {
        self.height
    }

    fn index(&self, x: i32, y: i32) -> Option<usize> {
        let inside = x >= 0 && y >= 0 && (x as u32) < self.width && (y as u32) < self.height;
        inside.then(|| y as usize * self.width as usize + x as usize)
    }

    /// The colour at (x, y); `None` outside the buffer.
    pub fn pixel(&self, x: i32, y: i32) -> Option<Rgb565> {
        self.index(x, y).map(|i| self.pixels[i])
    }

    /// Sets (x, y) to `c`; a point outside the buffer is ignored, as a clipped draw is.
    pub fn set_pixel(&mut self, x: i32, y: i32, c: Rgb565) {
        if let Some(i) = self.index(x, y) {
            self.pixels[i] = c;
        }
    }

    /// Every pixel, row-major from the top-left.
    pub fn pixels(&self) -> &[Rgb565] {
        &self.pixels
    }

    /// How many pixels inside `area` have colour `c`.
    pub fn count_in(&self, area: &Rectangle, c: Rgb565) -> usize {
        area.points().filter(|p| self.pixel(p.x, p.y) == Some(c)).count()
    }

    /// Writes an 8-bit RGB PNG.
    pub fn save_png(&self, path: impl AsRef<Path>) -> std::io::Result<()> {
        let path = path.as_ref();
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)?;
        }
        self.write_png(BufWriter::new(File::create(path)?))
    }

    /// Encodes an 8-bit RGB PNG into `w`.
    pub fn write_png<W: std::io::Write>(&self, w: W) -> std::io::Result<()> {
        let mut enc = png::Encoder::new(w, self.width, self.height);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc.write_header().map_err(std::io::Error::other)?;
        let data: Vec<u8> = self.pixels.iter().flat_map(|&c| to_rgb888(c)).collect();
        writer.write_image_data(&data).map_err(std::io::Error::other)?;
        writer.finish().map_err(std::io::Error::other)
    }
}

impl Canvas for Framebuffer {}

impl<D: DrawTarget<Color = Rgb565>> Canvas for Counting<'_, D> {}

impl OriginDimensions for Framebuffer {
    fn size(&self) -> Size {
        Size::new(self.width, self.height)
    }
}

impl DrawTarget for Framebuffer {
    type Color = Rgb565;
    type Error = Infallible;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Pixel<Rgb565>>,
    {
        for Pixel(p, c) in pixels {
            self.set_pixel(p.x, p.y, c);
        }
        Ok(())
    }
}

/// Wraps a target and counts writes per pixel, plus the calls made, so a
/// test can tell exactly which pixels a draw touched and how it would load a
/// real bus (one address window per `fill_*` call).
pub struct Counting<'a, D> {
    /// The wrapped target, which receives every draw unchanged.
    pub inner: &'a mut D,
    width: u32,
    height: u32,
    writes: Vec<u16>,
    /// Writes that fell outside the target.
    pub outside: usize,
    /// `fill_solid` calls: one address window each on a real bus.
    pub fill_solid_calls: usize,
    /// `fill_contiguous` calls: one address window each on a real bus.
    pub fill_contiguous_calls: usize,
    /// `draw_iter` calls: a window per pixel on a real bus, the slow path.
    pub draw_iter_calls: usize,
}

impl<'a, D: DrawTarget<Color = Rgb565> + OriginDimensions> Counting<'a, D> {
    /// Starts counting draws to `inner`, all counters at zero.
    pub fn new(inner: &'a mut D) -> Self {
        let s = inner.size();
        Self {
            inner,
            width: s.width,
            height: s.height,
            writes: vec![0; (s.width * s.height) as usize],
            outside: 0,
            fill_solid_calls: 0,
            fill_contiguous_calls: 0,
            draw_iter_calls: 0,
        }
    }
}

impl<D> Counting<'_, D> {
    fn count(&mut self, p: Point) {
        if p.x >= 0 && p.y >= 0 && (p.x as u32) < self.width && (p.y as u32) < self.height {
            let i = p.y as usize * self.width as usize + p.x as usize;
            self.writes[i] = self.writes[i].saturating_add(1);
        } else {
            self.outside += 1;
        }
    }

    /// Writes to pixel `(x, y)`.
    pub fn writes_at(&self, x: i32, y: i32) -> u16 {
        if x < 0 || y < 0 || x as u32 >= self.width || y as u32 >= self.height {
            return 0;
        }
        self.writes[y as usize * self.width as usize + x as usize]
    }

    /// Total pixel writes.
    pub fn total_writes(&self) -> u64 {
        self.writes.iter().map(|&w| u64::from(w)).sum::<u64>() + self.outside as u64
    }

    /// Pixels written at least once.
    pub fn touched(&self) -> usize {
        self.writes.iter().filter(|&&w| w > 0).count()
    }

    /// Written pixels outside every one of `allowed`.
    pub fn touched_outside(&self, allowed: &[Rectangle]) -> Vec<Point> {
        let mut out = Vec::new();
        for y in 0..self.height as i32 {
            for x in 0..self.width as i32 {
                let p = Point::new(x, y);
                if self.writes_at(x, y) > 0 && !allowed.iter().any(|r| r.contains(p)) {
                    out.push(p);
                }
            }
        }
        out
    }

    /// Bounding box of every written pixel, if any.
    pub fn touched_bounds(&self) -> Option<Rectangle> {
        let mut b: Option<(i32, i32, i32, i32)> = None;
        for y in 0..self.height as i32 {
            for x in 0..self.width as i32 {
                if self.writes_at(x, y) > 0 {
                    b = Some(match b {
                        None => (x, y, x, y),
                        Some((x0, y0, x1, y1)) => (x0.min(x), y0.min(y), x1.max(x), y1.max(y)),
                    });
                }
            }
        }
        b.map(|(x0, y0, x1, y1)| Rectangle::with_corners(Point::new(x0, y0), Point::new(x1, y1)))
    }
}

impl<D: Dimensions> Dimensions for Counting<'_, D> {
    fn bounding_box(&self) -> Rectangle {
        self.inner.bounding_box()
    }
}

impl<D: DrawTarget<Color = Rgb565>> DrawTarget for Counting<'_, D> {
    type Color = Rgb565;
    type Error = D::Error;

    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Pixel<Rgb565>>,
    {
        self.draw_iter_calls += 1;
        let v: Vec<Pixel<Rgb565>> = pixels.into_iter().collect();
        for p in &v {
            self.count(p.0);
        }
        self.inner.draw_iter(v)
    }

    fn fill_contiguous<I>(&mut self, area: &Rectangle, colors: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Rgb565>,
    {
        self.fill_contiguous_calls += 1;
        let colors: Vec<Rgb565> =
            colors.into_iter().take(area.size.width as usize * area.size.height as usize).collect();
        assert_eq!(
            colors.len(),
            (area.size.width * area.size.height) as usize,
            "fill_contiguous got fewer colours than its area holds: {area:?}"
        );
        for p in area.points() {
            self.count(p);
        }
        self.inner.fill_contiguous(area, colors)
    }

    fn fill_solid(&mut self, area: &Rectangle, color: Rgb565) -> Result<(), Self::Error> {
        self.fill_solid_calls += 1;
        for p in area.points() {
            self.count(p);
        }
        self.inner.fill_solid(area, color)
    }
}
