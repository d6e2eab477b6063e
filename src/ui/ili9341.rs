//! MIPI DCS command codes of the ILI9341 (ILITEK ILI9341 datasheet, chapter
//! 8 "Command"), shared by the chip's driver (`board::lcd`) and the host's
//! bus decoder (`touch_arm_rig::lcd_bus`). The ST7789V (Sitronix ST7789V
//! datasheet, "System Function Command Table 1") and the ILI9486 (ILITEK
//! ILI9486 datasheet, "Command List") use the same codes for every command
//! here, so one driver serves the three.

/// No operation.
pub const NOP: u8 = 0x00;
/// Software reset; wait 5 ms before the next command.
pub const SWRESET: u8 = 0x01;
/// Read display identification (RDDID): a dummy byte, then ID1, ID2, ID3
/// (the ST7789V answers 85h 85h 52h).
pub const RDDID: u8 = 0x04;
/// Enter sleep mode.
pub const SLPIN: u8 = 0x10;
/// Leave sleep mode; wait 120 ms before the next command.
pub const SLPOUT: u8 = 0x11;
/// Display inversion off (the default after a reset).
pub const INVOFF: u8 = 0x20;
/// Display inversion on: every pixel shown with its colour inverted.
pub const INVON: u8 = 0x21;
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
/// Read ID4 (RDID4): a dummy byte, the IC version, then the model in two
/// bytes (ILI9341: 00h 93h 41h; ILI9486: 00h 94h 86h).
pub const RDID4: u8 = 0xD3;
