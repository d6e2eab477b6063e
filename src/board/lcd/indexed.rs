//! The ILI9325's addressing: it has no MADCTL, so an orientation is an entry
//! mode (which way the address counter moves, R03h) plus a mapping of the
//! logical pixel to its GRAM column and row; a window is R50h–R53h in GRAM
//! coordinates, and the counter starts at the logical top-left pixel
//! (R20h/R21h: unlike RAMWR, R22h does not reset the address). With the
//! scan directions the initialisation sets (SS and GS, as the shields'
//! reference code does), portrait shows GRAM column x, row y at (x, y).
//!
//! | rotation          | entry (R03h)      | GRAM column | GRAM row  |
//! |-------------------|-------------------|-------------|-----------|
//! | Portrait          | rows up, cols up  | x           | y         |
//! | Landscape         | vertical, rows up | 239 − y     | x         |
//! | PortraitFlipped   | rows, cols down   | 239 − x     | 319 − y   |
//! | LandscapeFlipped  | vertical, cols up | y           | 319 − x   |

use super::{reg, Bus8, Lcd, Rotation};
use crate::ui::ili9325::entry;

/// The last GRAM column and row (240 × 320).
const LAST_COL: u16 = 239;
const LAST_ROW: u16 = 319;

/// R03h for `rotation`: BGR and the counter's directions.
pub(super) fn entry_mode(rotation: Rotation) -> u16 {
    entry::BGR
        | match rotation {
            Rotation::Portrait => entry::ROW_UP | entry::COL_UP,
            Rotation::Landscape => entry::VERTICAL | entry::ROW_UP,
            Rotation::PortraitFlipped => 0,
            Rotation::LandscapeFlipped => entry::VERTICAL | entry::COL_UP,
        }
}

/// GRAM (column, row) of logical pixel (x, y).
fn gram(rotation: Rotation, x: u16, y: u16) -> (u16, u16) {
    match rotation {
        Rotation::Portrait => (x, y),
        Rotation::Landscape => (LAST_COL - y, x),
        Rotation::PortraitFlipped => (LAST_COL - x, LAST_ROW - y),
        Rotation::LandscapeFlipped => (y, LAST_ROW - x),
    }
}

impl<B: Bus8> Lcd<B> {
    /// The window as GRAM ranges (skipped when unchanged), the address of
    /// its first pixel, then R22h: pixels follow.
    pub(super) fn window_indexed(&mut self, x0: u16, y0: u16, x1: u16, y1: u16) {
        let (c0, r0) = gram(self.rotation, x0, y0);
        if self.columns != Some((x0, x1)) || self.pages != Some((y0, y1)) {
            let (c1, r1) = gram(self.rotation, x1, y1);
            self.write_reg(reg::WINDOW_X0, c0.min(c1));
            self.write_reg(reg::WINDOW_X1, c0.max(c1));
            self.write_reg(reg::WINDOW_Y0, r0.min(r1));
            self.write_reg(reg::WINDOW_Y1, r0.max(r1));
            self.columns = Some((x0, x1));
            self.pages = Some((y0, y1));
        }
        self.write_reg(reg::GRAM_X, c0);
        self.write_reg(reg::GRAM_Y, r0);
        self.bus.command(0x00);
        self.bus.command(reg::GRAM_DATA);
    }
}
