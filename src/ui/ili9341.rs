//! ILI9341 command codes (datasheet §8), shared by the chip's driver
//! (`board::lcd`) and the host's bus decoder (`hal_sim::lcd_bus`).

/// No operation.
pub const NOP: u8 = 0x00;
/// Software reset; wait 5 ms before the next command.
pub const SWRESET: u8 = 0x01;
/// Enter sleep mode.
pub const SLPIN: u8 = 0x10;
/// Leave sleep mode; wait 120 ms before the next command.
pub const SLPOUT: u8 = 0x11;
/// Display off (the frame memory is kept).
pub const DISPOFF: u8 = 0x28;
/// Display on.
pub const DISPON: u8 = 0x29;
/// Column address set: first and last column, 16 bits each.
pub const CASET: u8 = 0x2A;
/// Page (row) address set: first and last row, 16 bits each.
pub const PASET: u8 = 0x2B;
/// Memory write: pixels follow, filling the window from its start.
pub const RAMWR: u8 = 0x2C;
/// Memory access control: scan direction and RGB/BGR order (rotation).
pub const MADCTL: u8 = 0x36;
/// Pixel format; 0x55 = 16 bits per pixel (RGB565).
pub const COLMOD: u8 = 0x3A;
/// Memory write continue: pixels follow from where the last write stopped.
pub const RAMWRC: u8 = 0x3C;
