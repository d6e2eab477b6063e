//! The MIPI DCS controllers: ILI9341 and ST7789V (240×320 GRAM), ILI9486
//! and ST7796S (320×480), one model with each chip's GRAM size and ID
//! answers.
//!
//! Implemented: SWRESET (01h), SLPIN/SLPOUT (10h/11h), INVOFF/INVON
//! (20h/21h, [`Dcs::inverted`]), DISPOFF/DISPON
//! (28h/29h), CASET (2Ah), PASET (2Bh), RAMWR (2Ch), RAMWR continue (3Ch),
//! MADCTL (36h), COLMOD (3Ah), and the two ID reads: RDDID (04h) and Read
//! ID4 (D3h), each a dummy byte and then the ID bytes the chip's datasheet
//! gives (below). Other commands and their parameters are logged and
//! otherwise ignored; a read after any other command is not answered (the
//! data lines float, so the firmware's pull-ups read ones).
//! MADCTL: MV swaps the logical column/page to GRAM row/column, MX mirrors
//! the GRAM column, MY the GRAM row; with the BGR bit set colours are shown
//! as sent (the shields' panels are BGR), without it red and blue swap.
//! [`Dcs::landscape`] shows the GRAM as the user sees a landscape screen:
//! MADCTL = MV|BGR (0x28) reads upright there.

use embedded_graphics::pixelcolor::raw::RawU16;
use embedded_graphics::pixelcolor::{Rgb565, RgbColor};

use super::{cmd, BusStats, Chip};
use hal_sim::display::Framebuffer;

/// The ILI9341's (and ST7789V's) GRAM: 240 columns.
pub const GRAM_W: u16 = 240;
/// ... and 320 rows.
pub const GRAM_H: u16 = 320;

/// MADCTL (36h) bits: the memory access order the firmware sets.
pub mod madctl {
    /// Row address order (bottom to top).
    pub const MY: u8 = 0x80;
    /// Column address order (right to left).
    pub const MX: u8 = 0x40;
    /// Row/column exchange (landscape).
    pub const MV: u8 = 0x20;
    /// BGR colour order.
    pub const BGR: u8 = 0x08;
}

/// What a chip answers on RDDID (04h) and Read ID4 (D3h), after the dummy
/// byte.
fn id_answers(chip: Chip) -> ([u8; 3], Option<[u8; 3]>) {
    match chip {
        // ILI9341 datasheet, "Read ID4 (D3h)": IC version 00h, model 93h 41h;
        // RDDID: the module IDs, unprogrammed (00h).
        Chip::Ili9341 => ([0x00, 0x00, 0x00], Some([0x00, 0x93, 0x41])),
        // ST7789V datasheet, "RDDID (04h)": 85h 85h 52h; no D3h command.
        Chip::St7789 => ([0x85, 0x85, 0x52], None),
        // ILI9486 datasheet, "Read ID4 (D3h)": 00h 94h 86h.
        Chip::Ili9486 => ([0x00, 0x00, 0x00], Some([0x00, 0x94, 0x86])),
        // ST7796S datasheet, "Read ID4 (D3h)": 00h 77h 96h (MCUFRIEND_kbv
        // reads 7796h there); RDDID modelled unprogrammed.
        Chip::St7796 => ([0x00, 0x00, 0x00], Some([0x00, 0x77, 0x96])),
        // A clone that answers zeros everywhere.
        Chip::Ili9325 | Chip::Unknown => ([0x00, 0x00, 0x00], Some([0x00, 0x00, 0x00])),
    }
}

/// A DCS controller: registers, address counters and GRAM.
#[derive(Debug, Clone)]
pub struct Dcs {
    chip: Chip,
    gram_w: u16,
    gram_h: u16,
    gram: Vec<Rgb565>,
    /// MADCTL (36h) as last written.
    pub madctl: u8,
    /// COLMOD (3Ah) as last written (0x55: 16 bits a pixel).
    pub colmod: u8,
    /// In sleep mode (after SLPIN, before SLPOUT).
    pub sleeping: bool,
    /// DISPON received (and no DISPOFF since).
    pub display_on: bool,
    /// INVON received (and no INVOFF or reset since): the panel shows every
    /// colour inverted (the GRAM keeps what was written).
    pub inverted: bool,
    /// Column and page windows (inclusive ends) and the write pointer.
    pub sc: u16,
    /// End column of the window.
    pub ec: u16,
    /// Start page (row) of the window.
    pub sp: u16,
    /// End page (row) of the window.
    pub ep: u16,
    col: u16,
    page: u16,
    current: Option<u8>,
    params: [u8; 4],
    nparams: usize,
    high: Option<u8>,
    /// Bytes the next RD strobes return (an ID read in progress).
    answer: Vec<u8>,
    /// Every command byte in order.
    pub command_log: Vec<u8>,
    /// What went over the bus.
    pub stats: BusStats,
}

/// The ILI9341 model (the DCS model for that chip).
pub type Ili9341 = Dcs;

impl Default for Dcs {
    fn default() -> Self {
        Self::new()
    }
}

impl Dcs {
    /// An ILI9341 at power-on: GRAM black, sleeping, display off.
    pub fn new() -> Self {
        Self::of(Chip::Ili9341)
    }

    /// `chip` at power-on (any chip but the ILI9325 is modelled as DCS; the
    /// ILI9325 and the unknown chip get the ILI9341's geometry and zeros on
    /// both ID reads).
    pub fn of(chip: Chip) -> Self {
        let (gram_w, gram_h) = if matches!(chip, Chip::Ili9486 | Chip::St7796) { (320, 480) } else { (GRAM_W, GRAM_H) };
        let mut s = Self {
            chip,
            gram_w,
            gram_h,
            gram: vec![Rgb565::BLACK; usize::from(gram_w) * usize::from(gram_h)],
            madctl: 0,
            colmod: 0x66,
            sleeping: true,
            display_on: false,
            inverted: false,
            sc: 0,
            ec: gram_w - 1,
            sp: 0,
            ep: gram_h - 1,
            col: 0,
            page: 0,
            current: None,
            params: [0; 4],
            nparams: 0,
            high: None,
            answer: Vec::new(),
            command_log: Vec::new(),
            stats: BusStats::default(),
        };
        s.reset_registers();
        s
    }

    /// The chip modelled.
    pub fn chip(&self) -> Chip {
        self.chip
    }

    /// GRAM columns and rows (portrait).
    pub fn gram_size(&self) -> (u16, u16) {
        (self.gram_w, self.gram_h)
    }

    /// SWRESET / hardware reset: registers to defaults, GRAM kept.
    fn reset_registers(&mut self) {
        self.madctl = 0;
        self.colmod = 0x66;
        self.sleeping = true;
        self.display_on = false;
        self.inverted = false;
        self.sc = 0;
        self.ec = self.gram_w - 1;
        self.sp = 0;
        self.ep = self.gram_h - 1;
        self.current = None;
        self.high = None;
        self.answer.clear();
    }

    /// A pulse on RESET: the registers return to their power-on values (the GRAM keeps its content) and the reset is counted.
    pub fn hardware_reset(&mut self) {
        self.stats.hardware_resets += 1;
        self.reset_registers();
    }

    /// A byte with RS low.
    pub fn command(&mut self, c: u8) {
        self.stats.commands += 1;
        self.command_log.push(c);
        self.current = Some(c);
        self.nparams = 0;
        self.high = None;
        self.answer.clear();
        let (rddid, id4) = id_answers(self.chip);
        match c {
            cmd::SWRESET => self.reset_registers(),
            cmd::SLPIN => self.sleeping = true,
            cmd::SLPOUT => self.sleeping = false,
            cmd::DISPOFF => self.display_on = false,
            cmd::DISPON => self.display_on = true,
            cmd::INVOFF => self.inverted = false,
            cmd::INVON => self.inverted = true,
            cmd::RAMWR => {
                self.col = self.sc;
                self.page = self.sp;
            }
            // A dummy byte first, then the ID.
            cmd::RDDID => self.answer = [&[0u8][..], &rddid].concat(),
            cmd::RDID4 => {
                if let Some(id) = id4 {
                    self.answer = [&[0u8][..], &id].concat();
                }
            }
            _ => {}
        }
        // Served from the front.
        self.answer.reverse();
    }

    /// An RD strobe: the next byte the controller drives, or `None` when it
    /// leaves the bus floating.
    pub fn read(&mut self) -> Option<u8> {
        self.answer.pop()
    }

    /// A byte with RS high.
    pub fn data(&mut self, b: u8) {
        let Some(c) = self.current else {
            self.stats.stray_data += 1;
            return;
        };
        match c {
            cmd::RAMWR | cmd::RAMWRC => {
                if self.colmod & 0x0f != 0x05 {
                    self.stats.wrong_format += 1;
                }
                match self.high.take() {
                    None => self.high = Some(b),
                    Some(h) => self.pixel(u16::from_be_bytes([h, b])),
                }
                return;
            }
            _ => {}
        }
        self.stats.params += 1;
        if let Some(slot) = self.params.get_mut(self.nparams) {
            *slot = b;
        }
        self.nparams += 1;
        let p = self.params;
        match (c, self.nparams) {
            (cmd::CASET, 4) => {
                self.sc = u16::from_be_bytes([p[0], p[1]]);
                self.ec = u16::from_be_bytes([p[2], p[3]]);
            }
            (cmd::PASET, 4) => {
                self.sp = u16::from_be_bytes([p[0], p[1]]);
                self.ep = u16::from_be_bytes([p[2], p[3]]);
            }
            (cmd::MADCTL, 1) => self.madctl = b,
            (cmd::COLMOD, 1) => self.colmod = b,
            (
                cmd::SWRESET
                | cmd::SLPIN
                | cmd::SLPOUT
                | cmd::DISPON
                | cmd::DISPOFF
                | cmd::INVON
                | cmd::INVOFF
                | cmd::NOP,
                _,
            ) => self.stats.stray_data += 1,
            _ => {}
        }
    }

    /// Logical address space: rows and columns swapped with MV.
    fn logical_size(&self) -> (u16, u16) {
        if self.madctl & madctl::MV != 0 {
            (self.gram_h, self.gram_w)
        } else {
            (self.gram_w, self.gram_h)
        }
    }

    fn pixel(&mut self, raw: u16) {
        let (w, h) = self.logical_size();
        let (c, p) = (self.col, self.page);
        if c < w && p < h {
            let (a, b) = if self.madctl & madctl::MV != 0 { (p, c) } else { (c, p) };
            let x = if self.madctl & madctl::MX != 0 { self.gram_w - 1 - a } else { a };
            let y = if self.madctl & madctl::MY != 0 { self.gram_h - 1 - b } else { b };
            let mut color = Rgb565::from(RawU16::new(raw));
            if self.madctl & madctl::BGR == 0 {
                color = Rgb565::new(color.b(), color.g(), color.r());
            }
            self.gram[usize::from(y) * usize::from(self.gram_w) + usize::from(x)] = color;
            self.stats.pixels += 1;
        } else {
            self.stats.pixels_clipped += 1;
        }
        // Column first, then page; past the window's end back to its start.
        if self.col >= self.ec {
            self.col = self.sc;
            self.page = if self.page >= self.ep { self.sp } else { self.page + 1 };
        } else {
            self.col += 1;
        }
    }

    /// GRAM pixel at native column `x`, row `y`.
    pub fn gram(&self, x: u16, y: u16) -> Option<Rgb565> {
        (x < self.gram_w && y < self.gram_h)
            .then(|| self.gram[usize::from(y) * usize::from(self.gram_w) + usize::from(x)])
    }

    /// The GRAM as the panel shows it held upright (portrait).
    pub fn portrait(&self) -> Framebuffer {
        let mut fb = Framebuffer::new(u32::from(self.gram_w), u32::from(self.gram_h), Rgb565::BLACK);
        for y in 0..self.gram_h {
            for x in 0..self.gram_w {
                fb.set_pixel(x.into(), y.into(), self.gram[usize::from(y) * usize::from(self.gram_w) + usize::from(x)]);
            }
        }
        fb
    }

    /// The GRAM as a landscape screen (320×240, 480×320): view `(x, y)` is
    /// GRAM column `y`, row `x`, so MADCTL = MV|BGR draws upright here.
    pub fn landscape(&self) -> Framebuffer {
        let (w, h) = (self.gram_h, self.gram_w);
        let mut fb = Framebuffer::new(u32::from(w), u32::from(h), Rgb565::BLACK);
        for vy in 0..h {
            for vx in 0..w {
                let i = usize::from(vx) * usize::from(self.gram_w) + usize::from(vy);
                fb.set_pixel(vx.into(), vy.into(), self.gram[i]);
            }
        }
        fb
    }
}
