//! The display controller on the UNO-form shield's 8-bit parallel bus
//! (docs/hardware.md), as an embedded-graphics `DrawTarget<Color = Rgb565>` and a UI
//! [`Canvas`]: the MIPI DCS controllers (ILI9341, ST7789V, ILI9486, ST7796S) and the
//! register-indexed ILI9325, told apart at boot by their ID registers
//! ([`Lcd::start`], `lcd/start.rs`). They differ only in their
//! initialisation, their size and how a window is set (`lcd/indexed.rs` for
//! the ILI9325); the pixel stream after the window is the same RGB565 byte
//! pairs, so every fast path below serves all five.
//!
//! Pins: RD PF0, WR PF1, RS PF2, CS PF3, RST PF4; D0 PH5, D1 PH6, D2 PE4,
//! D3 PE5, D4 PG5, D5 PE3, D6 PH3, D7 PH4. A byte is three port stores (the
//! data bits are spread over E, G and H) and a WR pulse made by writing WR's
//! bit to PINF twice (each write toggles the pin: low, then high): 6 cycles.
//! A colour's port values are computed once per run, so a solid run costs
//! ~8 cycles per byte (4 per pixel when both bytes are equal), and the UI's
//! bulk operations ([`Canvas::fill_runs`] for map rows,
//! [`Canvas::fill_glyph`] for characters) run in the same tight loops with
//! one address window each. The last column/page window is remembered, so
//! windows on one row send only CASET or nothing but RAMWR.
//!
//! [`Bus8`] is the byte-level interface the driver needs; [`RawShieldBus`]
//! implements it by owning ports E, F, G and H. Whatever owns the shield pins
//! (the LCD/touch `ShieldBus`) can implement [`Bus8`] with the same `unsafe`
//! helpers ([`write_command`], [`write_data`], [`repeat_pixels`],
//! [`run_pixels`], [`glyph_pixels`], [`stream_pixels`]) and hand `&mut` of
//! itself to [`Lcd`] for the length of a draw (`Lcd::new(&mut shield_bus)`),
//! so drawing and touch sampling cannot overlap.
//!
//! Assumptions of the fast path: WR idles high between bytes (every owner of
//! the pins restores it), and no interrupt handler writes PORTE, PORTF,
//! PORTG or PORTH while a byte is sent (the non-LCD bits of those ports are
//! read at the start of each transfer and written back unchanged).
//! Timing: the WR low and high phases are one cycle (62.5 ns) each and
//! back-to-back strobes are 2 cycles apart (125 ns), within the ILI9341's
//! and ST7789V's 8080-I write cycle (≥ 66 ns, each phase ≥ 15 ns) and the
//! slowest of the five, the ILI9325's (≥ 100 ns, each phase ≥ 50 ns); the
//! ST7796S is taken to be the ST7789V's sibling here (not checked against
//! its datasheet's timing table).

use crate::board::shield::ShieldBus;
use core::ptr::{read_volatile, write_volatile};

use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::geometry::{OriginDimensions, Size};
use embedded_graphics::pixelcolor::raw::RawU16;
use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::prelude::RawData;
use embedded_graphics::primitives::{PointsIter, Rectangle};
use embedded_graphics::Pixel;

use crate::ui::draw::{GlyphCell, RunPixels};
use crate::ui::{Canvas, Run};

/// Data-space addresses (ATmega2560 datasheet, register summary).
const PINF: *mut u8 = 0x2F as *mut u8;
const PORTF_R: *mut u8 = 0x31 as *mut u8;
const PORTE_R: *mut u8 = 0x2E as *mut u8;
const PORTG_R: *mut u8 = 0x34 as *mut u8;
const PORTH_R: *mut u8 = 0x102 as *mut u8;

const WR: u8 = 1 << 1;
const RS: u8 = 1 << 2;
const CS: u8 = 1 << 3;
const RST: u8 = 1 << 4;
/// PE4 = D2, PE5 = D3, PE3 = D5.
const E_MASK: u8 = 0b0011_1000;
/// PG5 = D4.
const G_MASK: u8 = 0b0010_0000;
/// PH5 = D0, PH6 = D1, PH3 = D6, PH4 = D7.
const H_MASK: u8 = 0b0111_1000;

/// One byte as the three port values to store.
#[derive(Clone, Copy)]
struct PortBytes {
    e: u8,
    g: u8,
    h: u8,
}

/// The non-LCD bits of ports E, G, H as they are now.
#[inline(always)]
unsafe fn base() -> PortBytes {
    PortBytes {
        e: read_volatile(PORTE_R) & !E_MASK,
        g: read_volatile(PORTG_R) & !G_MASK,
        h: read_volatile(PORTH_R) & !H_MASK,
    }
}

#[inline(always)]
fn spread(b: u8, base: PortBytes) -> PortBytes {
    let bit = |k: u8, to: u8| ((b >> k) & 1) << to;
    PortBytes {
        e: base.e | bit(2, 4) | bit(3, 5) | bit(5, 3),
        g: base.g | bit(4, 5),
        h: base.h | bit(0, 5) | bit(1, 6) | bit(6, 3) | bit(7, 4),
    }
}

/// Puts a byte on D0..D7 and strobes WR (latched on the rising edge).
#[inline(always)]
unsafe fn put(p: PortBytes) {
    write_volatile(PORTE_R, p.e);
    write_volatile(PORTG_R, p.g);
    write_volatile(PORTH_R, p.h);
    write_volatile(PINF, WR);
    write_volatile(PINF, WR);
}

#[inline(always)]
unsafe fn rs(high: bool) {
    let v = read_volatile(PORTF_R);
    write_volatile(PORTF_R, if high { v | RS } else { v & !RS });
}

/// Sends a command byte (RS low during the strobe).
///
/// # Safety
/// The caller owns ports E–H, the bus is in LCD mode (all 13 pins outputs)
/// with WR high, and no interrupt writes those ports meanwhile.
pub unsafe fn write_command(c: u8) {
    let b = base();
    rs(false);
    put(spread(c, b));
    rs(true);
}

/// Sends parameter / data bytes (RS high).
///
/// # Safety
/// As [`write_command`].
pub unsafe fn write_data(bytes: &[u8]) {
    let b = base();
    for &d in bytes {
        put(spread(d, b));
    }
}

/// Sends `n` pixels of one RGB565 colour, high byte first.
///
/// # Safety
/// As [`write_command`].
pub unsafe fn repeat_pixels(color: u16, n: u32) {
    let b = base();
    let mut n = n;
    while n > 0xFFFF {
        send_run(b, color, 0xFFFF);
        n -= 0xFFFF;
    }
    send_run(b, color, n as u16);
}

/// Sends `n` pixels of one colour inside a pixel stream (after RAMWR).
///
/// # Safety
/// As [`write_command`].
pub unsafe fn run_pixels(color: u16, n: u16) {
    send_run(base(), color, n);
}

/// `n` pixels of `color` with the other port bits `b`.
#[inline(never)] // reason: code-size
unsafe fn send_run(b: PortBytes, color: u16, n: u16) {
    if n == 0 {
        return;
    }
    let [hi, lo] = color.to_be_bytes();
    let (h, l) = (spread(hi, b), spread(lo, b));
    // 256-pixel blocks with an 8-bit counter: a wider count would cost
    // more per pixel than the port stores.
    let mut blocks = (n >> 8) as u8;
    let mut rest = n as u8;
    if hi == lo {
        // One byte pattern: the data pins stay put, only WR moves.
        put(h);
        write_volatile(PINF, WR);
        write_volatile(PINF, WR);
        // That was one pixel.
        if rest == 0 {
            blocks -= 1;
        }
        rest = rest.wrapping_sub(1);
        loop {
            while rest != 0 {
                write_volatile(PINF, WR);
                write_volatile(PINF, WR);
                write_volatile(PINF, WR);
                write_volatile(PINF, WR);
                rest -= 1;
            }
            if blocks == 0 {
                return;
            }
            blocks -= 1;
            // 256 pixels: `rest` wraps from 0.
            write_volatile(PINF, WR);
            write_volatile(PINF, WR);
            write_volatile(PINF, WR);
            write_volatile(PINF, WR);
            rest = 255;
        }
    }
    loop {
        while rest != 0 {
            put(h);
            put(l);
            rest -= 1;
        }
        if blocks == 0 {
            return;
        }
        blocks -= 1;
        put(h);
        put(l);
        rest = 255;
    }
}

/// Sends a character cell: for each of the 8 glyph rows, `scale` pixel rows
/// of 5 columns × `scale` pixels (bit 4 of the row = leftmost column, set =
/// `fg`) and `gap` background pixels. All port values are precomputed, so a
/// pixel is two byte writes and a counter.
///
/// # Safety
/// As [`write_command`].
pub unsafe fn glyph_pixels(rows: &[u8; 8], scale: u8, gap: u8, fg: u16, bg: u16) {
    let b = base();
    let [fh, fl] = fg.to_be_bytes();
    let [bh, bl] = bg.to_be_bytes();
    let (f1, f2) = (spread(fh, b), spread(fl, b));
    let (b1, b2) = (spread(bh, b), spread(bl, b));
    for &bits in rows {
        let mut rep = scale;
        while rep != 0 {
            let mut mask = 0x10u8;
            while mask != 0 {
                let mut k = scale;
                if bits & mask != 0 {
                    while k != 0 {
                        put(f1);
                        put(f2);
                        k -= 1;
                    }
                } else {
                    while k != 0 {
                        put(b1);
                        put(b2);
                        k -= 1;
                    }
                }
                mask >>= 1;
            }
            let mut g = gap;
            while g != 0 {
                put(b1);
                put(b2);
                g -= 1;
            }
            rep -= 1;
        }
    }
}

/// Sends one pixel per colour of `colors`, high byte first, as runs of
/// equal colours: the per-pixel work is a compare and a count, and each run
/// goes out through the same tight loop as a solid fill.
///
/// # Safety
/// As [`write_command`].
pub unsafe fn stream_pixels<I: Iterator<Item = u16>>(colors: I) {
    let b = base();
    let mut color: u16 = 0;
    let mut len: u16 = 0;
    // `for_each` lets an iterator run its own (nested) loops.
    colors.for_each(|c| {
        if c == color && len != 0 && len != u16::MAX {
            len += 1;
        } else {
            send_run(b, color, len);
            color = c;
            len = 1;
        }
    });
    send_run(b, color, len);
}

/// The byte-level bus the driver talks through.
pub trait Bus8 {
    /// Sends command byte `c` (RS low).
    fn command(&mut self, c: u8);
    /// Sends parameter or pixel bytes (RS high).
    fn data(&mut self, bytes: &[u8]);
    /// `n` pixels of one RGB565 colour, high byte first.
    fn repeat(&mut self, color: u16, n: u32);
    /// One pixel per RGB565 colour of `colors`, high byte first.
    fn stream<I: Iterator<Item = u16>>(&mut self, colors: I);
    /// `n` pixels of one colour (part of a longer pixel stream).
    fn run(&mut self, color: u16, n: u16);
    /// A character cell's pixels (see `ui::draw::GlyphCell`), row by row.
    fn glyph(&mut self, rows: &[u8; 8], scale: u8, gap: u8, fg: u16, bg: u16);
    /// Chip select (active low on the pin; `true` selects).
    fn select(&mut self, on: bool);
    /// The RST line level.
    fn set_reset(&mut self, high: bool);
    /// Reads `out.len()` bytes from the controller (RS high, one RD strobe
    /// each), the data pins switched to inputs meanwhile and put back after.
    fn read(&mut self, out: &mut [u8]);
}

impl<B: Bus8> Bus8 for &mut B {
    fn command(&mut self, c: u8) {
        (**self).command(c)
    }
    fn data(&mut self, bytes: &[u8]) {
        (**self).data(bytes)
    }
    fn repeat(&mut self, color: u16, n: u32) {
        (**self).repeat(color, n)
    }
    fn stream<I: Iterator<Item = u16>>(&mut self, colors: I) {
        (**self).stream(colors)
    }
    fn run(&mut self, color: u16, n: u16) {
        (**self).run(color, n)
    }
    fn glyph(&mut self, rows: &[u8; 8], scale: u8, gap: u8, fg: u16, bg: u16) {
        (**self).glyph(rows, scale, gap, fg, bg)
    }
    fn select(&mut self, on: bool) {
        (**self).select(on)
    }
    fn set_reset(&mut self, high: bool) {
        (**self).set_reset(high)
    }
    fn read(&mut self, out: &mut [u8]) {
        (**self).read(out)
    }
}

/// The shield's one bus owner ([`ShieldBus`]) drives the LCD: it owns ports
/// E, F, G and H and keeps the pins in LCD mode except inside a touch read,
/// so drawing and sampling can never overlap.
impl Bus8 for ShieldBus {
    fn command(&mut self, c: u8) {
        // SAFETY: `self` owns the ports and keeps them in LCD mode.
        unsafe { write_command(c) }
    }
    fn data(&mut self, bytes: &[u8]) {
        // SAFETY: as above.
        unsafe { write_data(bytes) }
    }
    fn repeat(&mut self, color: u16, n: u32) {
        // SAFETY: as above.
        unsafe { repeat_pixels(color, n) }
    }
    fn stream<I: Iterator<Item = u16>>(&mut self, colors: I) {
        // SAFETY: as above.
        unsafe { stream_pixels(colors) }
    }
    fn run(&mut self, color: u16, n: u16) {
        // SAFETY: as above.
        unsafe { run_pixels(color, n) }
    }
    fn glyph(&mut self, rows: &[u8; 8], scale: u8, gap: u8, fg: u16, bg: u16) {
        // SAFETY: as above.
        unsafe { glyph_pixels(rows, scale, gap, fg, bg) }
    }
    fn select(&mut self, on: bool) {
        // SAFETY: only the CS bit of the owned port F changes.
        unsafe {
            let v = read_volatile(PORTF_R);
            write_volatile(PORTF_R, if on { v & !CS } else { v | CS });
        }
    }
    fn set_reset(&mut self, high: bool) {
        // SAFETY: only the RST bit of the owned port F changes.
        unsafe {
            let v = read_volatile(PORTF_R);
            write_volatile(PORTF_R, if high { v | RST } else { v & !RST });
        }
    }
    fn read(&mut self, out: &mut [u8]) {
        self.with_read(|pins| out.iter_mut().for_each(|b| *b = pins.byte()))
    }
}

pub use crate::ui::controller::{Controller, IdReads, Protocol};
pub use crate::ui::ili9325 as reg;
pub use crate::ui::ili9341 as cmd;

mod indexed;
mod start;

/// Screen orientation: the MADCTL value of the DCS controllers (BGR set: the
/// shields' panels are BGR); the ILI9325 gets the same picture through its
/// entry mode and address mapping (`lcd/indexed.rs`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rotation {
    /// Portrait (240×320 or 320×480), MX.
    Portrait = 0x48,
    /// Landscape (320×240 or 480×320), MV: the UI's orientation.
    Landscape = 0x28,
    /// Portrait upside down, MY.
    PortraitFlipped = 0x88,
    /// Landscape upside down, MV|MX|MY.
    LandscapeFlipped = 0xE8,
}

impl Rotation {
    /// Rows and columns are exchanged (MV).
    pub const fn is_landscape(self) -> bool {
        matches!(self, Rotation::Landscape | Rotation::LandscapeFlipped)
    }
}

fn delay_ms(ms: u16) {
    avr_device::asm::delay_cycles(16_000 * u32::from(ms));
}

/// The display. Holds the bus (by value or `&mut`), which controller is on
/// it, the orientation and the last column and page ranges sent: the
/// controller keeps them, so a run of windows on one row (map rows, a line
/// of text) skips the repeats.
pub struct Lcd<B> {
    bus: B,
    controller: Controller,
    rotation: Rotation,
    columns: Option<(u16, u16)>,
    pages: Option<(u16, u16)>,
}

impl<B: Bus8> Lcd<B> {
    /// Wraps a bus whose ILI9341 is already initialised in landscape (or
    /// call [`Lcd::init`] or [`Lcd::start`]). The window cache starts empty.
    pub fn new(bus: B) -> Self {
        Self::with_controller(bus, Controller::Ili9341)
    }

    /// Wraps a bus whose `controller` is already initialised in landscape
    /// (what [`Lcd::start`] found at boot).
    pub fn with_controller(bus: B, controller: Controller) -> Self {
        Self::oriented(bus, controller, Rotation::Landscape)
    }

    /// Wraps a bus whose `controller` is already initialised in `rotation`
    /// (what [`Lcd::start_forced`] set up at boot).
    pub fn oriented(bus: B, controller: Controller, rotation: Rotation) -> Self {
        Self { bus, controller, rotation, columns: None, pages: None }
    }

    /// The controller driven.
    pub fn controller(&self) -> Controller {
        self.controller
    }

    /// Width and height in pixels in the current orientation.
    pub fn size(&self) -> (u16, u16) {
        let (w, h) = self.controller.size();
        if self.rotation.is_landscape() {
            (w, h)
        } else {
            (h, w)
        }
    }

    /// Hardware reset, then the controller's initialisation, `rotation` and
    /// display on (the waits its datasheet asks for: ~270 ms on the DCS
    /// controllers). Leaves the chip selected.
    pub fn init(&mut self, rotation: Rotation) {
        self.hardware_reset();
        self.configure(rotation, false);
    }

    /// Sets the scan direction; the window cache is dropped, since the
    /// controller's column and page ranges change meaning.
    pub fn set_rotation(&mut self, rotation: Rotation) {
        self.rotation = rotation;
        self.columns = None;
        self.pages = None;
        match self.controller.protocol() {
            Protocol::Dcs => {
                self.bus.command(cmd::MADCTL);
                self.bus.data(&[rotation as u8]);
            }
            Protocol::Indexed => self.write_reg(reg::ENTRY_MODE, indexed::entry_mode(rotation)),
        }
    }

    /// The orientation last set.
    pub fn rotation(&self) -> Rotation {
        self.rotation
    }

    /// Gives the bus back (e.g. to lend the pins to the touch panel).
    pub fn release(self) -> B {
        self.bus
    }

    /// Sets the address window (inclusive) and starts a memory write.
    fn window(&mut self, x0: u16, y0: u16, x1: u16, y1: u16) {
        if self.controller.protocol() == Protocol::Indexed {
            return self.window_indexed(x0, y0, x1, y1);
        }
        if self.columns != Some((x0, x1)) {
            let [a, b] = x0.to_be_bytes();
            let [c, d] = x1.to_be_bytes();
            self.bus.command(cmd::CASET);
            self.bus.data(&[a, b, c, d]);
            self.columns = Some((x0, x1));
        }
        if self.pages != Some((y0, y1)) {
            let [a, b] = y0.to_be_bytes();
            let [c, d] = y1.to_be_bytes();
            self.bus.command(cmd::PASET);
            self.bus.data(&[a, b, c, d]);
            self.pages = Some((y0, y1));
        }
        self.bus.command(cmd::RAMWR);
    }

    /// The part of `area` on the screen as inclusive corners.
    fn clip(&self, area: &Rectangle) -> Option<(u16, u16, u16, u16)> {
        let (w, h) = self.size();
        // Narrow to 16 bits first: 32-bit arithmetic is four times the work
        // here, and this runs for every window.
        let narrow = |v: i32| v.clamp(-0x4000, 0x4000) as i16;
        let x0 = narrow(area.top_left.x);
        let y0 = narrow(area.top_left.y);
        let x1 = x0.saturating_add(area.size.width.min(0x4000) as i16).min(w as i16);
        let y1 = y0.saturating_add(area.size.height.min(0x4000) as i16).min(h as i16);
        let (x0, y0) = (x0.max(0), y0.max(0));
        if x1 <= x0 || y1 <= y0 {
            return None;
        }
        Some((x0 as u16, y0 as u16, (x1 - 1) as u16, (y1 - 1) as u16))
    }
}

impl<B: Bus8> Canvas for Lcd<B> {
    /// One window, then each run through the solid-fill loop.
    fn fill_runs(&mut self, area: &Rectangle, runs: &[Run]) -> Result<(), Self::Error> {
        let Some((x0, y0, x1, y1)) = self.clip(area) else {
            return Ok(());
        };
        let whole = u32::from(x1 - x0 + 1) == area.size.width && u32::from(y1 - y0 + 1) == area.size.height;
        if !whole {
            return self.draw_iter(area.points().zip(RunPixels::new(runs)).map(|(p, c)| Pixel(p, c)));
        }
        self.window(x0, y0, x1, y1);
        let mut left = area.size.width * area.size.height;
        for r in runs {
            let n = u32::from(r.len).min(left);
            self.bus.run(raw(r.color), n as u16);
            left -= n;
            if left == 0 {
                break;
            }
        }
        Ok(())
    }

    /// One window and the cell's pixels in a tight loop.
    fn fill_glyph(&mut self, x: i16, y: i16, cell: &GlyphCell) -> Result<(), Self::Error> {
        let area = Rectangle::new(
            embedded_graphics::geometry::Point::new(i32::from(x), i32::from(y)),
            Size::new(u32::from(cell.width()), u32::from(cell.height())),
        );
        let Some((x0, y0, x1, y1)) = self.clip(&area) else {
            return Ok(());
        };
        let whole = u32::from(x1 - x0 + 1) == area.size.width && u32::from(y1 - y0 + 1) == area.size.height;
        if !whole || cell.scale == 0 {
            let (w, h) = (cell.width(), cell.height());
            let pixels = (0..h).flat_map(|py| (0..w).map(move |px| (px, py)));
            return self.draw_iter(pixels.map(|(px, py)| {
                Pixel(
                    area.top_left + embedded_graphics::geometry::Point::new(i32::from(px), i32::from(py)),
                    cell.pixel(px, py),
                )
            }));
        }
        self.window(x0, y0, x1, y1);
        self.bus.glyph(&cell.rows, cell.scale, cell.gap, raw(cell.fg), raw(cell.bg));
        Ok(())
    }
}

fn raw(c: Rgb565) -> u16 {
    RawU16::from(c).into_inner()
}

impl<B: Bus8> OriginDimensions for Lcd<B> {
    fn size(&self) -> Size {
        let (w, h) = Lcd::size(self);
        Size::new(u32::from(w), u32::from(h))
    }
}

impl<B: Bus8> DrawTarget for Lcd<B> {
    type Color = Rgb565;
    type Error = core::convert::Infallible;

    /// One window per pixel: correct but slow; the UI never uses it.
    fn draw_iter<I>(&mut self, pixels: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Pixel<Rgb565>>,
    {
        let (w, h) = self.size();
        for Pixel(p, c) in pixels {
            if p.x >= 0 && p.y >= 0 && p.x < i32::from(w) && p.y < i32::from(h) {
                let (x, y) = (p.x as u16, p.y as u16);
                self.window(x, y, x, y);
                self.bus.repeat(raw(c), 1);
            }
        }
        Ok(())
    }

    fn fill_contiguous<I>(&mut self, area: &Rectangle, colors: I) -> Result<(), Self::Error>
    where
        I: IntoIterator<Item = Rgb565>,
    {
        let Some((x0, y0, x1, y1)) = self.clip(area) else {
            return Ok(());
        };
        let whole = u32::from(x1 - x0 + 1) == area.size.width && u32::from(y1 - y0 + 1) == area.size.height;
        if !whole {
            // Partly off screen: pixel by pixel through the clipping path.
            return self.draw_iter(area.points().zip(colors).map(|(p, c)| Pixel(p, c)));
        }
        self.window(x0, y0, x1, y1);
        // Colours beyond the area are dropped, as the trait asks. An
        // iterator that says it has at most `n` streams as is, so its own
        // `fold` (nested loops, e.g. a glyph's) drives the pixel loop.
        let n = (area.size.width * area.size.height) as usize;
        let colors = colors.into_iter();
        if colors.size_hint().1.is_some_and(|upper| upper <= n) {
            self.bus.stream(colors.map(raw));
        } else {
            self.bus.stream(colors.take(n).map(raw));
        }
        Ok(())
    }

    fn fill_solid(&mut self, area: &Rectangle, color: Rgb565) -> Result<(), Self::Error> {
        let Some((x0, y0, x1, y1)) = self.clip(area) else {
            return Ok(());
        };
        self.window(x0, y0, x1, y1);
        let n = u32::from(x1 - x0 + 1) * u32::from(y1 - y0 + 1);
        self.bus.repeat(raw(color), n);
        Ok(())
    }
}
