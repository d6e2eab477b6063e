//! The ILI9325, register-indexed (ILI9325 datasheet, "System Interface" and
//! the instruction list): on the 8-bit bus every transfer is two bytes,
//! upper first; RS low carries a register index, RS high the register's
//! 16-bit value, or pixels after R22h (RGB565, as DCS controllers take them).
//! An RD strobe after an index returns that register, upper byte first
//! (R00h: the driver code 9325h).
//!
//! The address counter is what the datasheet describes: R20h/R21h set it,
//! each pixel written moves it one step per the entry mode (R03h: AM picks
//! the vertical or horizontal direction first, I/D1 and I/D0 up or down)
//! inside the window R50h–R53h, wrapping at the window's edges to the next
//! line; R22h does not move it. TRI/DFM (R03h bits 15, 14) must be 0 for
//! 16-bit pixels in two transfers. R07h D1:0 = 11 turns the display on.
//!
//! The glass: the shields mount it so that the reference initialisation's
//! scan directions (SS in R01h, GS in R60h) show GRAM column x, row y at
//! (x, y) in portrait; [`Ili9325::landscape`] turns that a quarter, as the
//! DCS view does, so both shields show the UI in the same place.

use std::collections::BTreeMap;

use embedded_graphics::pixelcolor::raw::RawU16;
use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use touch_arm::ui::ili9325 as reg;

use super::BusStats;
use hal_sim::display::Framebuffer;

const W: u16 = 240;
const H: u16 = 320;

/// The controller: registers, the address counter and the GRAM.
#[derive(Debug, Clone)]
pub struct Ili9325 {
    gram: Vec<Rgb565>,
    /// Every register written, by index.
    pub regs: BTreeMap<u8, u16>,
    /// The index register and the upper byte of a pending index or value.
    index: u16,
    index_high: Option<u8>,
    data_high: Option<u8>,
    /// The address counter (column, row).
    col: u16,
    row: u16,
    /// Bytes the next RD strobes return.
    answer: Vec<u8>,
    /// Every register index written, in order.
    pub index_log: Vec<u16>,
    /// What went over the bus.
    pub stats: BusStats,
}

impl Default for Ili9325 {
    fn default() -> Self {
        Self::new()
    }
}

impl Ili9325 {
    /// Power-on state: GRAM black, display off, registers at their
    /// defaults (window the whole GRAM, counter at 0).
    pub fn new() -> Self {
        let mut s = Self {
            gram: vec![Rgb565::BLACK; usize::from(W) * usize::from(H)],
            regs: BTreeMap::new(),
            index: 0,
            index_high: None,
            data_high: None,
            col: 0,
            row: 0,
            answer: Vec::new(),
            index_log: Vec::new(),
            stats: BusStats::default(),
        };
        s.reset_registers();
        s
    }

    fn reset_registers(&mut self) {
        self.regs.clear();
        self.regs.insert(reg::ENTRY_MODE, 0x0030);
        self.regs.insert(reg::WINDOW_X1, W - 1);
        self.regs.insert(reg::WINDOW_Y1, H - 1);
        self.index = 0;
        self.index_high = None;
        self.data_high = None;
        self.col = 0;
        self.row = 0;
        self.answer.clear();
    }

    /// A pulse on RESET: the registers and the address counter return to their power-on values (the GRAM keeps its content) and the reset is counted.
    pub fn hardware_reset(&mut self) {
        self.stats.hardware_resets += 1;
        self.reset_registers();
    }

    /// Register `r` as last written (0 if never).
    pub fn reg(&self, r: u8) -> u16 {
        self.regs.get(&r).copied().unwrap_or(0)
    }

    /// R07h D1:0 = 11: the GRAM is shown.
    pub fn display_on(&self) -> bool {
        self.reg(reg::DISPLAY_CONTROL) & 0b11 == 0b11
    }

    /// A byte with RS low: half an index.
    pub fn command(&mut self, b: u8) {
        self.data_high = None;
        let Some(h) = self.index_high.take() else {
            self.index_high = Some(b);
            return;
        };
        let index = u16::from_be_bytes([h, b]);
        self.stats.commands += 1;
        self.index_log.push(index);
        self.index = index;
        self.answer.clear();
        if let Ok(r) = u8::try_from(index) {
            if r != reg::GRAM_DATA {
                let v = if r == reg::DRIVER_CODE { reg::ID } else { self.reg(r) };
                // Served from the back: upper byte first.
                self.answer = vec![v as u8, (v >> 8) as u8];
            }
        }
    }

    /// An RD strobe: the next byte driven, or `None` (bus left floating).
    pub fn read(&mut self) -> Option<u8> {
        self.answer.pop()
    }

    /// A byte with RS high: half a register value or pixel.
    pub fn data(&mut self, b: u8) {
        if self.index_high.is_some() {
            // RS rose between the two halves of an index.
            self.stats.stray_data += 1;
            self.index_high = None;
        }
        let Some(h) = self.data_high.take() else {
            self.data_high = Some(b);
            return;
        };
        let v = u16::from_be_bytes([h, b]);
        let Ok(r) = u8::try_from(self.index) else {
            self.stats.stray_data += 1;
            return;
        };
        if r == reg::GRAM_DATA {
            self.pixel(v);
            return;
        }
        self.stats.params += 2;
        self.regs.insert(r, v);
        match r {
            reg::GRAM_X => self.col = v & 0xFF,
            reg::GRAM_Y => self.row = v & 0x1FF,
            _ => {}
        }
    }

    fn window(&self) -> (u16, u16, u16, u16) {
        (self.reg(reg::WINDOW_X0), self.reg(reg::WINDOW_X1), self.reg(reg::WINDOW_Y0), self.reg(reg::WINDOW_Y1))
    }

    fn pixel(&mut self, raw: u16) {
        let entry = self.reg(reg::ENTRY_MODE);
        if entry & 0xC000 != 0 {
            self.stats.wrong_format += 1;
        }
        if self.col < W && self.row < H {
            let mut color = Rgb565::from(RawU16::new(raw));
            if entry & reg::entry::BGR == 0 {
                color = Rgb565::new(color.b(), color.g(), color.r());
            }
            self.gram[usize::from(self.row) * usize::from(W) + usize::from(self.col)] = color;
            self.stats.pixels += 1;
        } else {
            self.stats.pixels_clipped += 1;
        }
        let (hsa, hea, vsa, vea) = self.window();
        let col_up = entry & reg::entry::COL_UP != 0;
        let row_up = entry & reg::entry::ROW_UP != 0;
        // One step along a line; at its edge, back to the line's start.
        let step = |v: u16, up: bool, lo: u16, hi: u16| -> (u16, bool) {
            match (up, v) {
                (true, v) if v >= hi => (lo, true),
                (true, v) => (v + 1, false),
                (false, v) if v <= lo => (hi, true),
                (false, v) => (v - 1, false),
            }
        };
        if entry & reg::entry::VERTICAL != 0 {
            let (row, wrapped) = step(self.row, row_up, vsa, vea);
            self.row = row;
            if wrapped {
                self.col = step(self.col, col_up, hsa, hea).0;
            }
        } else {
            let (col, wrapped) = step(self.col, col_up, hsa, hea);
            self.col = col;
            if wrapped {
                self.row = step(self.row, row_up, vsa, vea).0;
            }
        }
    }

    /// GRAM pixel at column `x` (0..240), row `y` (0..320).
    pub fn gram(&self, x: u16, y: u16) -> Option<Rgb565> {
        (x < W && y < H).then(|| self.gram[usize::from(y) * usize::from(W) + usize::from(x)])
    }

    /// What the glass shows in portrait at (x, y): the GRAM through the
    /// scan directions (SS mirrors columns, GS rows).
    fn shown(&self, x: u16, y: u16) -> Rgb565 {
        let ss = self.reg(reg::DRIVER_OUTPUT) & reg::scan::SS != 0;
        let gs = self.reg(reg::GATE_SCAN) & reg::scan::GS != 0;
        let col = if ss { x } else { W - 1 - x };
        let row = if gs { y } else { H - 1 - y };
        self.gram[usize::from(row) * usize::from(W) + usize::from(col)]
    }

    /// The screen held in landscape (320×240): view (x, y) is portrait
    /// (239 − y, x).
    pub fn landscape(&self) -> Framebuffer {
        let mut fb = Framebuffer::new(u32::from(H), u32::from(W), Rgb565::BLACK);
        for vy in 0..W {
            for vx in 0..H {
                fb.set_pixel(vx.into(), vy.into(), self.shown(W - 1 - vy, vx));
            }
        }
        fb
    }
}
