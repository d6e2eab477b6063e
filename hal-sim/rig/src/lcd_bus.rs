//! The shield's display controller on its 8-bit parallel bus, decoded from
//! the pins of a firmware running under simavr: the picture the real ELF
//! draws, as a framebuffer and PNG, for each controller the firmware
//! supports ([`Chip`]).
//!
//! Bus (docs/hardware.md, Mega pins): RD PF0, WR PF1, RS PF2 (D/C), CS PF3, RST PF4;
//! D0 PH5, D1 PH6, D2 PE4, D3 PE5, D4 PG5, D5 PE3, D6 PH3, D7 PH4. A byte is
//! latched on the rising edge of WR while CS is low and RST high; RS low
//! makes it a command (an index half on the ILI9325), high a parameter or
//! pixel data. On the falling edge of RD (CS low) the controller drives the
//! data lines with the next byte of a read (an ID read at boot), as an
//! input pin sees it; a controller with nothing to say leaves them
//! floating, so pulled-up inputs read ones. When RD rises the lines are let
//! go (pulled-up inputs return to one).
//!
//! The controllers ([`dcs`] for the MIPI DCS ones, [`ili9325`] for the
//! register-indexed one) implement what drawing and the ID probe use, from
//! their datasheets; anything else is logged and ignored.

use std::cell::RefCell;
use std::rc::Rc;

use embedded_graphics::pixelcolor::raw::RawU16;
use embedded_graphics::pixelcolor::Rgb565;
use embedded_graphics::prelude::RawData;

use crate::avr::{Avr, Error, Pin, PinDrive, PortLevels};
use hal_sim::display::Framebuffer;
use touch_arm::seam::pins::mega;
use touch_arm::ui::Layout;

pub mod dcs;
pub mod ili9325;

pub use dcs::{madctl, Dcs, Ili9341, GRAM_H, GRAM_W};
pub use ili9325::Ili9325;
pub use touch_arm::ui::ili9341 as cmd;

/// The display controller on the simulated shield.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Chip {
    /// ILI9341, 240×320 (the default).
    Ili9341,
    /// ST7789V, 240×320.
    St7789,
    /// ILI9486, 320×480.
    Ili9486,
    /// ILI9325, 240×320, register-indexed.
    Ili9325,
    /// ST7796S, 320×480 (the 3.5"/4" shields).
    St7796,
    /// A DCS controller with the ILI9341's geometry that answers zeros on
    /// every ID read (what an unknown clone does): the firmware must warn and
    /// still draw through its ILI9341 driver.
    Unknown,
}

impl Chip {
    /// The controllers the firmware supports, by their `--lcd` names.
    pub const SUPPORTED: [Chip; 5] = [Chip::Ili9341, Chip::St7789, Chip::Ili9486, Chip::Ili9325, Chip::St7796];

    /// The name used by `--lcd` and in the firmware's `info lcd` line.
    pub fn name(self) -> &'static str {
        match self {
            Chip::Ili9341 => "ili9341",
            Chip::St7789 => "st7789",
            Chip::Ili9486 => "ili9486",
            Chip::Ili9325 => "ili9325",
            Chip::St7796 => "st7796",
            Chip::Unknown => "unknown",
        }
    }

    /// A supported controller by name.
    pub fn from_name(name: &str) -> Option<Chip> {
        Chip::SUPPORTED.into_iter().find(|c| c.name() == name)
    }

    /// The screen held in landscape: width, height.
    pub fn landscape_size(self) -> (u16, u16) {
        match self {
            Chip::Ili9486 | Chip::St7796 => (480, 320),
            _ => (320, 240),
        }
    }

    /// The firmware's UI layout for this screen.
    pub fn layout(self) -> Layout {
        let (w, h) = self.landscape_size();
        Layout::for_size(w, h).unwrap_or(Layout::QVGA)
    }
}

/// A controller model.
#[derive(Debug, Clone)]
pub enum Model {
    /// ILI9341, ST7789V, ILI9486, ST7796S or the unknown clone.
    Dcs(Dcs),
    /// The ILI9325.
    Indexed(Ili9325),
}

impl Model {
    /// `chip` at power-on.
    pub fn of(chip: Chip) -> Model {
        match chip {
            Chip::Ili9325 => Model::Indexed(Ili9325::new()),
            _ => Model::Dcs(Dcs::of(chip)),
        }
    }

    /// The bus counters of the model, whichever it is.
    pub fn stats(&self) -> &BusStats {
        match self {
            Model::Dcs(m) => &m.stats,
            Model::Indexed(m) => &m.stats,
        }
    }

    fn stats_mut(&mut self) -> &mut BusStats {
        match self {
            Model::Dcs(m) => &mut m.stats,
            Model::Indexed(m) => &mut m.stats,
        }
    }

    fn hardware_reset(&mut self) {
        match self {
            Model::Dcs(m) => m.hardware_reset(),
            Model::Indexed(m) => m.hardware_reset(),
        }
    }

    fn command(&mut self, b: u8) {
        match self {
            Model::Dcs(m) => m.command(b),
            Model::Indexed(m) => m.command(b),
        }
    }

    fn data(&mut self, b: u8) {
        match self {
            Model::Dcs(m) => m.data(b),
            Model::Indexed(m) => m.data(b),
        }
    }

    fn read(&mut self) -> Option<u8> {
        match self {
            Model::Dcs(m) => m.read(),
            Model::Indexed(m) => m.read(),
        }
    }

    /// Whether a command or index just selected pixel data (for the stream
    /// timing statistics).
    fn streaming(&self, byte: u8) -> bool {
        match self {
            Model::Dcs(_) => byte == cmd::RAMWR || byte == cmd::RAMWRC,
            Model::Indexed(_) => byte == touch_arm::ui::ili9325::GRAM_DATA,
        }
    }

    /// The display is on (DISPON; R07h on the ILI9325).
    pub fn display_on(&self) -> bool {
        match self {
            Model::Dcs(m) => m.display_on,
            Model::Indexed(m) => m.display_on(),
        }
    }

    /// The panel shows its colours inverted: INVON on a DCS controller;
    /// on the ILI9325, R61h's REV cleared (its panels need REV set to show
    /// colours as sent, as the reference initialisation does).
    pub fn inverted(&self) -> bool {
        match self {
            Model::Dcs(m) => m.inverted,
            Model::Indexed(m) => m.reg(touch_arm::ui::ili9325::BASE_IMAGE) & 1 == 0,
        }
    }

    /// The screen held in landscape, at the panel's size.
    pub fn landscape(&self) -> Framebuffer {
        match self {
            Model::Dcs(m) => m.landscape(),
            Model::Indexed(m) => m.landscape(),
        }
    }
}

/// Counters of what went over the bus.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BusStats {
    /// Command bytes (RS low) written.
    pub commands: u64,
    /// Parameter bytes of commands written.
    pub params: u64,
    /// Pixels written to the GRAM.
    pub pixels: u64,
    /// Pixels addressed outside the column/page space (dropped).
    pub pixels_clipped: u64,
    /// Data bytes outside any command that takes them.
    pub stray_data: u64,
    /// Pixel bytes while COLMOD was not 16-bit.
    pub wrong_format: u64,
    /// RD strobes with CS low.
    pub reads: u64,
    /// RD strobes the controller answered (drove the data lines).
    pub reads_answered: u64,
    /// RD strobes while a data pin was an output: the MCU and the
    /// controller would both drive the bus.
    pub read_conflicts: u64,
    /// WR strobes with CS low while a data pin was not an output (the bus
    /// was left in touch mode): the byte is garbage.
    pub undriven_writes: u64,
    /// WR strobes with CS high (ignored by the controller).
    pub deselected_writes: u64,
    /// Hardware resets (RESET pulled low).
    pub hardware_resets: u64,
    /// Cycles between consecutive bytes of one RAMWR pixel stream, summed,
    /// and how many such gaps (gaps over 400 cycles, e.g. a new window, are
    /// left out).
    pub stream_gap_cycles: u64,
    /// The number of gaps summed in `stream_gap_cycles`.
    pub stream_gaps: u64,
    /// Smallest gap seen between two WR rising edges.
    pub min_gap_cycles: Option<u64>,
    /// CPU cycle of the first WR strobe.
    pub first_write_cycle: Option<u64>,
    /// When the first pixel reached the GRAM (boot time to first pixel).
    pub first_pixel_cycle: Option<u64>,
    /// CPU cycle of the last WR strobe.
    pub last_write_cycle: Option<u64>,
}

impl BusStats {
    /// Mean cycles per byte inside pixel streams.
    pub fn cycles_per_stream_byte(&self) -> Option<f64> {
        (self.stream_gaps > 0).then(|| self.stream_gap_cycles as f64 / self.stream_gaps as f64)
    }
}

/// Which MCU pins carry the bus.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BusPins {
    /// Read strobe (RD, active low).
    pub rd: Pin,
    /// Write strobe (WR, active low; the controller latches on the rising edge).
    pub wr: Pin,
    /// Register select (RS, D/CX): low for a command, high for data.
    pub rs: Pin,
    /// Chip select (CS, active low).
    pub cs: Pin,
    /// Reset (RST, active low).
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
    lcd: Rc<RefCell<Model>>,
    wr: bool,
    rd: bool,
    rst: bool,
    last_wr_cycle: Option<u64>,
    in_stream: bool,
}

impl Decoder {
    fn on_write(&mut self, cycle: u64, lv: &PortLevels, drive: &mut PinDrive<'_>) {
        let p = self.pins;
        let (wr, rd, rst, cs) = (lv.level(p.wr), lv.level(p.rd), lv.level(p.rst), lv.level(p.cs));
        let mut lcd = self.lcd.borrow_mut();
        if self.rst && !rst {
            lcd.hardware_reset();
        }
        self.rst = rst;
        let wr_rise = wr && !self.wr;
        let rd_fall = !rd && self.rd;
        let rd_rise = rd && !self.rd;
        self.wr = wr;
        self.rd = rd;
        if rd_rise {
            // The controller lets go; pulled-up lines float back to one.
            for pin in p.data {
                if lv.is_pulled_up(pin) {
                    drive.drive(pin, true);
                }
            }
        }
        if !rst {
            return;
        }
        if rd_fall && !cs {
            self.answer_read(&mut lcd, lv, drive);
        }
        if !wr_rise {
            return;
        }
        if cs {
            lcd.stats_mut().deselected_writes += 1;
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
        let rs = lv.level(p.rs);
        let in_stream = self.in_stream;
        let s = lcd.stats_mut();
        if !driven {
            s.undriven_writes += 1;
        }
        if let Some(prev) = self.last_wr_cycle {
            let gap = cycle - prev;
            s.min_gap_cycles = Some(s.min_gap_cycles.map_or(gap, |m| m.min(gap)));
            if in_stream && rs && gap <= 400 {
                s.stream_gap_cycles += gap;
                s.stream_gaps += 1;
            }
        }
        s.first_write_cycle.get_or_insert(cycle);
        s.last_write_cycle = Some(cycle);
        self.last_wr_cycle = Some(cycle);
        if rs {
            lcd.data(byte);
            let s = lcd.stats_mut();
            if s.pixels > 0 && s.first_pixel_cycle.is_none() {
                s.first_pixel_cycle = Some(cycle);
            }
        } else {
            lcd.command(byte);
            self.in_stream = lcd.streaming(byte);
        }
    }

    /// RD fell with CS low: the controller puts its next byte on the lines.
    fn answer_read(&self, lcd: &mut Model, lv: &PortLevels, drive: &mut PinDrive<'_>) {
        let conflict = self.pins.data.iter().any(|pin| lv.is_output(*pin));
        let answer = lcd.read();
        let s = lcd.stats_mut();
        s.reads += 1;
        s.read_conflicts += u64::from(conflict);
        if let Some(byte) = answer {
            s.reads_answered += 1;
            for (i, pin) in self.pins.data.iter().enumerate() {
                drive.drive(*pin, byte >> i & 1 == 1);
            }
        }
    }
}

/// A controller attached to a running [`Avr`]'s pins.
#[derive(Clone)]
pub struct LcdBus {
    chip: Chip,
    lcd: Rc<RefCell<Model>>,
}

impl LcdBus {
    /// Starts decoding `pins` of `avr` from now on, with an ILI9341 on them.
    pub fn attach(avr: &mut Avr, pins: BusPins) -> Result<LcdBus, Error> {
        Self::attach_chip(avr, pins, Chip::Ili9341)
    }

    /// Starts decoding `pins` of `avr` from now on, with `chip` on them.
    pub fn attach_chip(avr: &mut Avr, pins: BusPins, chip: Chip) -> Result<LcdBus, Error> {
        let lcd = Rc::new(RefCell::new(Model::of(chip)));
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
        avr.add_bus_device(&pins.ports(), move |_, cycle, lv, drive| dec.on_write(cycle, lv, drive))?;
        Ok(LcdBus { chip, lcd })
    }

    /// The controller on the bus.
    pub fn chip(&self) -> Chip {
        self.chip
    }

    /// The DCS controller's state (borrow it briefly, not across `run_*`).
    ///
    /// # Panics
    /// On the ILI9325, which is not a DCS controller: see [`LcdBus::model`].
    pub fn lcd(&self) -> std::cell::Ref<'_, Dcs> {
        std::cell::Ref::map(self.lcd.borrow(), |m| match m {
            Model::Dcs(d) => d,
            Model::Indexed(_) => panic!("LcdBus::lcd: the ILI9325 is not a DCS controller; use LcdBus::model"),
        })
    }

    /// The controller model, whichever it is.
    pub fn model(&self) -> std::cell::Ref<'_, Model> {
        self.lcd.borrow()
    }

    /// The bus counters so far.
    pub fn stats(&self) -> BusStats {
        *self.lcd.borrow().stats()
    }

    /// The screen held in landscape, at the panel's size.
    pub fn landscape(&self) -> Framebuffer {
        self.lcd.borrow().landscape()
    }

    /// Forgets the command log (a long-running session would grow it forever).
    pub fn forget_command_log(&self) {
        match &mut *self.lcd.borrow_mut() {
            Model::Dcs(d) => d.command_log.clear(),
            Model::Indexed(i) => i.index_log.clear(),
        }
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
