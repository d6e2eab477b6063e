//! ILI9341 on the UNO-form shield's 8-bit parallel bus (SPEC §8), as an
//! embedded-graphics `DrawTarget<Color = Rgb565>`.
//!
//! Pins: RD PF0, WR PF1, RS PF2, CS PF3, RST PF4; D0 PH5, D1 PH6, D2 PE4,
//! D3 PE5, D4 PG5, D5 PE3, D6 PH3, D7 PH4. A byte is three port stores (the
//! data bits are spread over E, G and H) and a WR pulse made by writing WR's
//! bit to PINF twice (each write toggles the pin: low, then high). A
//! colour's port values are computed once per fill (and cached for the two
//! colours of a glyph), so a pixel stream costs a few cycles per byte.
//!
//! [`Bus8`] is the byte-level interface the driver needs; [`RawShieldBus`]
//! implements it by owning ports E, F, G and H. Whatever owns the shield pins
//! (the LCD/touch `ShieldBus`) can implement [`Bus8`] with the same
//! `unsafe` helpers ([`write_command`], [`write_data`], [`repeat_pixels`],
//! [`stream_pixels`]) and hand `&mut` of itself to [`Lcd`] for the length of
//! a draw, so drawing and touch sampling cannot overlap.
//!
//! Assumptions of the fast path: WR idles high between bytes (every owner of
//! the pins restores it), and no interrupt handler writes PORTE, PORTF,
//! PORTG or PORTH while a byte is sent (the non-LCD bits of those ports are
//! read at the start of each transfer and written back unchanged).

use core::ptr::{read_volatile, write_volatile};

use avr_device::atmega2560::{PORTE, PORTF, PORTG, PORTH};
use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::geometry::{OriginDimensions, Size};
use embedded_graphics::pixelcolor::raw::RawU16;
use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::prelude::RawData;
use embedded_graphics::primitives::{PointsIter, Rectangle};
use embedded_graphics::Pixel;

/// Data-space addresses (ATmega2560 datasheet, register summary).
const PINF: *mut u8 = 0x2F as *mut u8;
const PORTF_R: *mut u8 = 0x31 as *mut u8;
const DDRF_R: *mut u8 = 0x30 as *mut u8;
const PORTE_R: *mut u8 = 0x2E as *mut u8;
const DDRE_R: *mut u8 = 0x2D as *mut u8;
const PORTG_R: *mut u8 = 0x34 as *mut u8;
const DDRG_R: *mut u8 = 0x33 as *mut u8;
const PORTH_R: *mut u8 = 0x102 as *mut u8;
const DDRH_R: *mut u8 = 0x101 as *mut u8;

const RD: u8 = 1 << 0;
const WR: u8 = 1 << 1;
const RS: u8 = 1 << 2;
const CS: u8 = 1 << 3;
const RST: u8 = 1 << 4;
const CONTROL: u8 = RD | WR | RS | CS | RST;
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
    let [hi, lo] = color.to_be_bytes();
    let (h, l) = (spread(hi, b), spread(lo, b));
    let mut n = n;
    if n == 0 {
        return;
    }
    if hi == lo {
        // One byte pattern: the data pins stay put, only WR moves.
        put(h);
        write_volatile(PINF, WR);
        write_volatile(PINF, WR);
        n -= 1;
        while n != 0 {
            write_volatile(PINF, WR);
            write_volatile(PINF, WR);
            write_volatile(PINF, WR);
            write_volatile(PINF, WR);
            n -= 1;
        }
        return;
    }
    while n != 0 {
        put(h);
        put(l);
        n -= 1;
    }
}

/// Sends one pixel per colour of `colors`, high byte first. The port values
/// of the last two colours are cached (a glyph has two).
///
/// # Safety
/// As [`write_command`].
pub unsafe fn stream_pixels<I: Iterator<Item = u16>>(colors: I) {
    let b = base();
    let mut slots: [(u16, PortBytes, PortBytes); 2] = [(0, spread(0, b), spread(0, b)); 2];
    let mut valid = [false; 2];
    let mut older = 0usize;
    for c in colors {
        let hit = if valid[0] && slots[0].0 == c {
            0
        } else if valid[1] && slots[1].0 == c {
            1
        } else {
            let [hi, lo] = c.to_be_bytes();
            let i = older;
            slots[i] = (c, spread(hi, b), spread(lo, b));
            valid[i] = true;
            older = 1 - i;
            i
        };
        let (_, h, l) = slots[hit];
        put(h);
        put(l);
    }
}

/// The byte-level bus the driver talks through.
pub trait Bus8 {
    fn command(&mut self, c: u8);
    fn data(&mut self, bytes: &[u8]);
    fn repeat(&mut self, color: u16, n: u32);
    fn stream<I: Iterator<Item = u16>>(&mut self, colors: I);
    /// Chip select (active low on the pin; `true` selects).
    fn select(&mut self, on: bool);
    /// The RST line level.
    fn set_reset(&mut self, high: bool);
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
    fn select(&mut self, on: bool) {
        (**self).select(on)
    }
    fn set_reset(&mut self, high: bool) {
        (**self).set_reset(high)
    }
}

/// The shield bus on its own: owns ports E, F, G, H (use it when nothing
/// else shares the pins; with the touch panel, the shared-pin owner
/// implements [`Bus8`] instead).
pub struct RawShieldBus {
    _e: PORTE,
    _f: PORTF,
    _g: PORTG,
    _h: PORTH,
}

impl RawShieldBus {
    /// Takes the ports and puts the 13 LCD pins in LCD mode: controls high
    /// (deselected, idle strobes, RS = data, RST released), data low.
    pub fn new(e: PORTE, f: PORTF, g: PORTG, h: PORTH) -> Self {
        // SAFETY: we own the four ports; only LCD bits are changed.
        unsafe {
            write_volatile(PORTF_R, read_volatile(PORTF_R) | CONTROL);
            write_volatile(DDRF_R, read_volatile(DDRF_R) | CONTROL);
            write_volatile(PORTE_R, read_volatile(PORTE_R) & !E_MASK);
            write_volatile(PORTG_R, read_volatile(PORTG_R) & !G_MASK);
            write_volatile(PORTH_R, read_volatile(PORTH_R) & !H_MASK);
            write_volatile(DDRE_R, read_volatile(DDRE_R) | E_MASK);
            write_volatile(DDRG_R, read_volatile(DDRG_R) | G_MASK);
            write_volatile(DDRH_R, read_volatile(DDRH_R) | H_MASK);
        }
        Self { _e: e, _f: f, _g: g, _h: h }
    }
}

impl Bus8 for RawShieldBus {
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
}

pub mod cmd {
    pub const SWRESET: u8 = 0x01;
    pub const SLPOUT: u8 = 0x11;
    pub const DISPON: u8 = 0x29;
    pub const CASET: u8 = 0x2A;
    pub const PASET: u8 = 0x2B;
    pub const RAMWR: u8 = 0x2C;
    pub const MADCTL: u8 = 0x36;
    pub const COLMOD: u8 = 0x3A;
}

/// Screen orientation as MADCTL values (BGR set: the shields' panels are
/// BGR).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rotation {
    /// 240×320, MX.
    Portrait = 0x48,
    /// 320×240, MV: the UI's orientation.
    Landscape = 0x28,
    /// 240×320, MY.
    PortraitFlipped = 0x88,
    /// 320×240, MV|MX|MY.
    LandscapeFlipped = 0xE8,
}

impl Rotation {
    pub const fn size(self) -> (u16, u16) {
        match self {
            Rotation::Landscape | Rotation::LandscapeFlipped => (320, 240),
            Rotation::Portrait | Rotation::PortraitFlipped => (240, 320),
        }
    }
}

fn delay_ms(ms: u16) {
    avr_device::asm::delay_cycles(16_000 * u32::from(ms));
}

/// The display. Holds the bus (by value or `&mut`) and the orientation.
pub struct Lcd<B> {
    bus: B,
    rotation: Rotation,
}

impl<B: Bus8> Lcd<B> {
    pub fn new(bus: B) -> Self {
        Self { bus, rotation: Rotation::Landscape }
    }

    /// Hardware and software reset, wake-up, 16-bit pixels, `rotation`,
    /// display on (~270 ms of waits, as the datasheet asks after RST, SWRESET
    /// and SLPOUT). Leaves the chip selected.
    pub fn init(&mut self, rotation: Rotation) {
        self.bus.select(false);
        self.bus.set_reset(true);
        delay_ms(1);
        self.bus.set_reset(false);
        delay_ms(1);
        self.bus.set_reset(true);
        delay_ms(120);
        self.bus.select(true);
        self.bus.command(cmd::SWRESET);
        delay_ms(5);
        self.bus.command(cmd::SLPOUT);
        delay_ms(120);
        self.bus.command(cmd::COLMOD);
        self.bus.data(&[0x55]);
        self.set_rotation(rotation);
        self.bus.command(cmd::DISPON);
    }

    pub fn set_rotation(&mut self, rotation: Rotation) {
        self.rotation = rotation;
        self.bus.command(cmd::MADCTL);
        self.bus.data(&[rotation as u8]);
    }

    pub fn rotation(&self) -> Rotation {
        self.rotation
    }

    /// Gives the bus back (e.g. to lend the pins to the touch panel).
    pub fn release(self) -> B {
        self.bus
    }

    /// Sets the address window (inclusive) and starts a memory write.
    fn window(&mut self, x0: u16, y0: u16, x1: u16, y1: u16) {
        let [a, b] = x0.to_be_bytes();
        let [c, d] = x1.to_be_bytes();
        self.bus.command(cmd::CASET);
        self.bus.data(&[a, b, c, d]);
        let [a, b] = y0.to_be_bytes();
        let [c, d] = y1.to_be_bytes();
        self.bus.command(cmd::PASET);
        self.bus.data(&[a, b, c, d]);
        self.bus.command(cmd::RAMWR);
    }

    /// The part of `area` on the screen as inclusive corners.
    fn clip(&self, area: &Rectangle) -> Option<(u16, u16, u16, u16)> {
        let (w, h) = self.rotation.size();
        let x0 = area.top_left.x.max(0);
        let y0 = area.top_left.y.max(0);
        let x1 = (area.top_left.x + area.size.width as i32).min(i32::from(w));
        let y1 = (area.top_left.y + area.size.height as i32).min(i32::from(h));
        if x1 <= x0 || y1 <= y0 {
            return None;
        }
        Some((x0 as u16, y0 as u16, (x1 - 1) as u16, (y1 - 1) as u16))
    }
}

fn raw(c: Rgb565) -> u16 {
    RawU16::from(c).into_inner()
}

impl<B: Bus8> OriginDimensions for Lcd<B> {
    fn size(&self) -> Size {
        let (w, h) = self.rotation.size();
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
        let (w, h) = self.rotation.size();
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
            return self.draw_iter(
                area.points().zip(colors).map(|(p, c)| Pixel(p, c)),
            );
        }
        self.window(x0, y0, x1, y1);
        let n = area.size.width * area.size.height;
        self.bus.stream(colors.into_iter().take(n as usize).map(raw));
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
