//! ILI9341 command codes (datasheet §8), shared by the chip's driver
//! (`board::lcd`) and the host's bus decoder (`hal_sim::lcd_bus`).

pub const NOP: u8 = 0x00;
pub const SWRESET: u8 = 0x01;
pub const SLPIN: u8 = 0x10;
pub const SLPOUT: u8 = 0x11;
pub const DISPOFF: u8 = 0x28;
pub const DISPON: u8 = 0x29;
pub const CASET: u8 = 0x2A;
pub const PASET: u8 = 0x2B;
pub const RAMWR: u8 = 0x2C;
pub const MADCTL: u8 = 0x36;
pub const COLMOD: u8 = 0x3A;
pub const RAMWRC: u8 = 0x3C;
