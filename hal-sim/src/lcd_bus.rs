//! The ILI9341 on the shield's 8-bit parallel bus, decoded from the pins of a
//! firmware running under simavr: the picture the real ELF draws, as a
//! framebuffer and PNG.
//!
//! Bus (SPEC §8, Mega pins): RD PF0, WR PF1, RS PF2 (D/C), CS PF3, RST PF4;
//! D0 PH5, D1 PH6, D2 PE4, D3 PE5, D4 PG5, D5 PE3, D6 PH3, D7 PH4. A byte is
//! latched on the rising edge of WR while CS is low and RST high; RS low
//! makes it a command, high a parameter or pixel data. RD strobes are
//! counted (nothing drives the data pins back).
//!
//! The controller model keeps its 240×320 GRAM in the panel's native
//! portrait order and implements what drawing uses: SWRESET (0x01), SLPIN/
//! SLPOUT (0x10/0x11), DISPOFF/DISPON (0x28/0x29), CASET (0x2A), PASET (0x2B),
//! RAMWR (0x2C), RAMWR continue (0x3C), MADCTL (0x36) and COLMOD (0x3A);
//! other commands and their parameters are logged and otherwise ignored.
//! MADCTL: MV swaps the logical column/page to GRAM row/column, MX mirrors
//! the GRAM column, MY the GRAM row; with the BGR bit set colours are shown
//! as sent (the shields' panels are BGR), without it red and blue swap.
//! [`Ili9341::landscape`] shows the GRAM as the user sees a landscape screen:
//! MADCTL = MV|BGR (0x28) reads upright there.

use std::cell::RefCell;
use std::rc::Rc;

use embedded_graphics::pixelcolor::raw::RawU16;
use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use embedded_graphics::prelude::RawData;

use crate::avr::{Avr, Error, Pin, PortLevels};
use crate::display::Framebuffer;
use touch_arm::seam::pins::mega;

pub const GRAM_W: u16 = 240;
pub const GRAM_H: u16 = 320;

pub use touch_arm::ui::ili9341 as cmd;

pub mod madctl {
    pub const MY: u8 = 0x80;
    pub const MX: u8 = 0x40;
    pub const MV: u8 = 0x20;
    pub const BGR: u8 = 0x08;
}

/// Counters of what went over the bus.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BusStats {
    pub commands: u64,
    pub params: u64,
    pub pixels: u64,
    /// Pixels addressed outside the column/page space (dropped).
    pub pixels_clipped: u64,
    /// Data bytes outside any command that takes them.
    pub stray_data: u64,
    /// Pixel bytes while COLMOD was not 16-bit.
    pub wrong_format: u64,
    /// RD strobes with CS low.
    pub reads: u64,
    /// WR strobes with CS low while a data pin was not an output (the bus
    /// was left in touch mode): the byte is garbage.
    pub undriven_writes: u64,
    /// WR strobes with CS high (ignored by the controller).
    pub deselected_writes: u64,
    pub hardware_resets: u64,
    /// Cycles between consecutive bytes of one RAMWR pixel stream, summed,
    /// and how many such gaps (gaps over 400 cycles, e.g. a new window, are
    /// left out).
    pub stream_gap_cycles: u64,
    pub stream_gaps: u64,
    /// Smallest gap seen between two WR rising edges.
    pub min_gap_cycles: Option<u64>,
    pub first_write_cycle: Option<u64>,
    pub last_write_cycle: Option<u64>,
}

impl BusStats {
    /// Mean cycles per byte inside pixel streams.
    pub fn cycles_per_stream_byte(&self) -> Option<f64> {
        (self.stream_gaps > 0).then(|| self.stream_gap_cycles as f64 / self.stream_gaps as f64)
    }
}

/// The controller: registers, address counters and GRAM.
#[derive(Debug, Clone)]
pub struct Ili9341 {
    gram: Vec<Rgb565>,
    pub madctl: u8,
    pub colmod: u8,
    pub sleeping: bool,
    pub display_on: bool,
    /// Column and page windows (inclusive ends) and the write pointer.
    pub sc: u16,
    pub ec: u16,
    pub sp: u16,
    pub ep: u16,
    col: u16,
    page: u16,
    current: Option<u8>,
    params: [u8; 4],
    nparams: usize,
    high: Option<u8>,
    /// Every command byte in order.
    pub command_log: Vec<u8>,
    pub stats: BusStats,
}

impl Default for Ili9341 {
    fn default() -> Self {
        Self::new()
    }
}

impl Ili9341 {
    /// Power-on state: GRAM black, sleeping, display off.
    pub fn new() -> Self {
        let mut s = Self {
            gram: vec![Rgb565::BLACK; usize::from(GRAM_W) * usize::from(GRAM_H)],
            madctl: 0,
            colmod: 0x66,
            sleeping: true,
            display_on: false,
            sc: 0,
            ec: GRAM_W - 1,
            sp: 0,
            ep: GRAM_H - 1,
            col: 0,
            page: 0,
            current: None,
            params: [0; 4],
            nparams: 0,
            high: None,
            command_log: Vec::new(),
            stats: BusStats::default(),
        };
        s.reset_registers();
        s
    }

    /// SWRESET / hardware reset: registers to defaults, GRAM kept.
    fn reset_registers(&mut self) {
        self.madctl = 0;
        self.colmod = 0x66;
        self.sleeping = true;
        self.display_on = false;
        self.sc = 0;
        self.ec = GRAM_W - 1;
        self.sp = 0;
        self.ep = GRAM_H - 1;
        self.current = None;
        self.high = None;
    }

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
        match c {
            cmd::SWRESET => self.reset_registers(),
            cmd::SLPIN => self.sleeping = true,
            cmd::SLPOUT => self.sleeping = false,
            cmd::DISPOFF => self.display_on = false,
            cmd::DISPON => self.display_on = true,
            cmd::RAMWR => {
                self.col = self.sc;
                self.page = self.sp;
            }
            _ => {}
        }
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
            (cmd::SWRESET | cmd::SLPIN | cmd::SLPOUT | cmd::DISPON | cmd::DISPOFF | cmd::NOP, _) => {
                self.stats.stray_data += 1
            }
            _ => {}
        }
    }

    /// Logical address space: 320×240 with MV, else 240×320.
    fn logical_size(&self) -> (u16, u16) {
        if self.madctl & madctl::MV != 0 {
            (GRAM_H, GRAM_W)
        } else {
            (GRAM_W, GRAM_H)
        }
    }

    fn pixel(&mut self, raw: u16) {
        let (w, h) = self.logical_size();
        let (c, p) = (self.col, self.page);
        if c < w && p < h {
            let (a, b) = if self.madctl & madctl::MV != 0 { (p, c) } else { (c, p) };
            let x = if self.madctl & madctl::MX != 0 { GRAM_W - 1 - a } else { a };
            let y = if self.madctl & madctl::MY != 0 { GRAM_H - 1 - b } else { b };
            let mut color = Rgb565::from(RawU16::new(raw));
            if self.madctl & madctl::BGR == 0 {
                color = Rgb565::new(color.b(), color.g(), color.r());
            }
            self.gram[usize::from(y) * usize::from(GRAM_W) + usize::from(x)] = color;
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

    /// GRAM pixel at native column `x` (0..240), row `y` (0..320).
    pub fn gram(&self, x: u16, y: u16) -> Option<Rgb565> {
        (x < GRAM_W && y < GRAM_H).then(|| self.gram[usize::from(y) * usize::from(GRAM_W) + usize::from(x)])
    }

    /// The GRAM as the panel shows it held upright (240×320).
    pub fn portrait(&self) -> Framebuffer {
        let mut fb = Framebuffer::new(u32::from(GRAM_W), u32::from(GRAM_H), Rgb565::BLACK);
        for y in 0..GRAM_H {
            for x in 0..GRAM_W {
                fb.set_pixel(x.into(), y.into(), self.gram[usize::from(y) * usize::from(GRAM_W) + usize::from(x)]);
            }
        }
        fb
    }

    /// The GRAM as a landscape screen (320×240): view `(x, y)` is GRAM column
    /// `y`, row `x`, so MADCTL = MV|BGR draws upright here.
    pub fn landscape(&self) -> Framebuffer {
        let mut fb = Framebuffer::new(u32::from(GRAM_H), u32::from(GRAM_W), Rgb565::BLACK);
        for vy in 0..GRAM_W {
            for vx in 0..GRAM_H {
                fb.set_pixel(vx.into(), vy.into(), self.gram[usize::from(vx) * usize::from(GRAM_W) + usize::from(vy)]);
            }
        }
        fb
    }
}

/// Which MCU pins carry the bus.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BusPins {
    pub rd: Pin,
    pub wr: Pin,
    pub rs: Pin,
    pub cs: Pin,
    pub rst: Pin,
    /// D0..D7.
    pub data: [Pin; 8],
}

impl BusPins {
    /// The UNO-form shield on the Mega 2560: the firmware's pin map.
    pub const MEGA_SHIELD: BusPins = BusPins {
        rd: Pin::of(mega::LCD_RD),
        wr: Pin::of(mega::LCD_WR),
        rs: Pin::of(mega::LCD_RS),
        cs: Pin::of(mega::LCD_CS),
        rst: Pin::of(mega::LCD_RST),
        data: [
            Pin::of(mega::LCD_DATA[0]),
            Pin::of(mega::LCD_DATA[1]),
            Pin::of(mega::LCD_DATA[2]),
            Pin::of(mega::LCD_DATA[3]),
            Pin::of(mega::LCD_DATA[4]),
            Pin::of(mega::LCD_DATA[5]),
            Pin::of(mega::LCD_DATA[6]),
            Pin::of(mega::LCD_DATA[7]),
        ],
    };

    fn ports(&self) -> Vec<char> {
        let mut v: Vec<char> =
            [self.rd, self.wr, self.rs, self.cs, self.rst].iter().chain(&self.data).map(|p| p.port).collect();
        v.sort_unstable();
        v.dedup();
        v
    }
}

/// Edge detector between the pins and the controller.
struct Decoder {
    pins: BusPins,
    lcd: Rc<RefCell<Ili9341>>,
    wr: bool,
    rd: bool,
    rst: bool,
    last_wr_cycle: Option<u64>,
    in_stream: bool,
}

impl Decoder {
    fn on_write(&mut self, cycle: u64, lv: &PortLevels) {
        let p = self.pins;
        let (wr, rd, rst, cs) = (lv.level(p.wr), lv.level(p.rd), lv.level(p.rst), lv.level(p.cs));
        let mut lcd = self.lcd.borrow_mut();
        if self.rst && !rst {
            lcd.hardware_reset();
        }
        self.rst = rst;
        let wr_rise = wr && !self.wr;
        let rd_fall = !rd && self.rd;
        self.wr = wr;
        self.rd = rd;
        if !rst {
            return;
        }
        if rd_fall && !cs {
            lcd.stats.reads += 1;
        }
        if !wr_rise {
            return;
        }
        if cs {
            lcd.stats.deselected_writes += 1;
            return;
        }
        let mut byte = 0u8;
        let mut driven = true;
        for (i, pin) in p.data.iter().enumerate() {
            if lv.level(*pin) {
                byte |= 1 << i;
            }
            driven &= lv.is_output(*pin);
        }
        if !driven {
            lcd.stats.undriven_writes += 1;
        }
        let s = &mut lcd.stats;
        if let Some(prev) = self.last_wr_cycle {
            let gap = cycle - prev;
            s.min_gap_cycles = Some(s.min_gap_cycles.map_or(gap, |m| m.min(gap)));
            let rs = lv.level(p.rs);
            if self.in_stream && rs && gap <= 400 {
                s.stream_gap_cycles += gap;
                s.stream_gaps += 1;
            }
        }
        s.first_write_cycle.get_or_insert(cycle);
        s.last_write_cycle = Some(cycle);
        self.last_wr_cycle = Some(cycle);
        if lv.level(p.rs) {
            lcd.data(byte);
        } else {
            lcd.command(byte);
            self.in_stream = byte == cmd::RAMWR || byte == cmd::RAMWRC;
        }
    }
}

/// A controller attached to a running [`Avr`]'s pins.
#[derive(Clone)]
pub struct LcdBus {
    lcd: Rc<RefCell<Ili9341>>,
}

impl LcdBus {
    /// Starts decoding `pins` of `avr` from now on.
    pub fn attach(avr: &mut Avr, pins: BusPins) -> Result<LcdBus, Error> {
        let lcd = Rc::new(RefCell::new(Ili9341::new()));
        let ports = avr.ports();
        let level = |pin: Pin| ports.level(pin).unwrap_or(false);
        let mut dec = Decoder {
            pins,
            lcd: lcd.clone(),
            wr: level(pins.wr),
            rd: level(pins.rd),
            rst: level(pins.rst),
            last_wr_cycle: None,
            in_stream: false,
        };
        avr.add_port_listener(&pins.ports(), move |_, cycle, lv| dec.on_write(cycle, lv))?;
        Ok(LcdBus { lcd })
    }

    /// The controller state (borrow it briefly, not across `run_*`).
    pub fn lcd(&self) -> std::cell::Ref<'_, Ili9341> {
        self.lcd.borrow()
    }

    pub fn stats(&self) -> BusStats {
        self.lcd.borrow().stats
    }

    pub fn landscape(&self) -> Framebuffer {
        self.lcd.borrow().landscape()
    }

    /// Forgets the command log (a long-running session would grow it forever).
    pub fn forget_command_log(&self) {
        self.lcd.borrow_mut().command_log.clear();
    }
}

/// `Rgb565` from its 16-bit bus value.
pub fn rgb565(raw: u16) -> Rgb565 {
    Rgb565::from(RawU16::new(raw))
}

/// The 16-bit bus value of a colour.
pub fn raw565(c: Rgb565) -> u16 {
    RawU16::from(c).into_inner()
}
