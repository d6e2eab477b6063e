//! Register indices and bits of the ILI9325 (ILITEK ILI9325 datasheet,
//! "Instruction" register list and "System Interface"), the register-indexed
//! controller of the 2.4–2.8" shields: the host writes a 16-bit index (RS
//! low), then the register's 16-bit value (RS high); on the 8-bit bus each
//! is two transfers, upper byte first. Shared by the chip's driver
//! (`board::lcd`) and the host's bus decoder (`touch_arm_rig::lcd_bus`).

/// R00h: reading it returns the driver code, 9325h.
pub const DRIVER_CODE: u8 = 0x00;
/// R01h, driver output control 1: SS (bit 8) reverses the source (column)
/// scan.
pub const DRIVER_OUTPUT: u8 = 0x01;
/// R02h, LCD driving control (line inversion).
pub const DRIVING_WAVE: u8 = 0x02;
/// R03h, entry mode: [`entry`] bits.
pub const ENTRY_MODE: u8 = 0x03;
/// R07h, display control 1: D1:0 = 11 shows the GRAM, BASEE (bit 8) the base
/// image, GON and DTE (bits 5, 4) the gate outputs.
pub const DISPLAY_CONTROL: u8 = 0x07;
/// R08h, display control 2: front and back porch.
pub const PORCH: u8 = 0x08;
/// R10h, power control 1: SAP, BT, AP, SLP, STB.
pub const POWER1: u8 = 0x10;
/// R11h, power control 2: DC1, DC0, VC.
pub const POWER2: u8 = 0x11;
/// R12h, power control 3: VCIRE, VRH.
pub const POWER3: u8 = 0x12;
/// R13h, power control 4: VDV (VCOM amplitude).
pub const POWER4: u8 = 0x13;
/// R20h: GRAM horizontal address (column, 0..=239).
pub const GRAM_X: u8 = 0x20;
/// R21h: GRAM vertical address (row, 0..=319).
pub const GRAM_Y: u8 = 0x21;
/// R22h: write (or read) GRAM; pixels follow, two transfers each.
pub const GRAM_DATA: u8 = 0x22;
/// R29h, power control 7: VCM (VCOMH).
pub const POWER7: u8 = 0x29;
/// R2Bh: frame rate and colour control.
pub const FRAME_RATE: u8 = 0x2B;
/// R50h: window horizontal start (column).
pub const WINDOW_X0: u8 = 0x50;
/// R51h: window horizontal end (column, inclusive).
pub const WINDOW_X1: u8 = 0x51;
/// R52h: window vertical start (row).
pub const WINDOW_Y0: u8 = 0x52;
/// R53h: window vertical end (row, inclusive).
pub const WINDOW_Y1: u8 = 0x53;
/// R60h, driver output control 2: GS (bit 15) reverses the gate (row) scan,
/// NL (bits 13:8) the number of lines (27h: 320).
pub const GATE_SCAN: u8 = 0x60;
/// R61h, base image display control: REV (bit 0) grey-scale inversion.
pub const BASE_IMAGE: u8 = 0x61;

/// The driver code R00h returns.
pub const ID: u16 = 0x9325;

/// Bits of R03h (entry mode).
pub mod entry {
    /// Pixels are sent as B, G, R (the shields' panels are wired BGR).
    pub const BGR: u16 = 1 << 12;
    /// I/D1: the vertical (row) address counts up, else down.
    pub const ROW_UP: u16 = 1 << 5;
    /// I/D0: the horizontal (column) address counts up, else down.
    pub const COL_UP: u16 = 1 << 4;
    /// AM: the address moves vertically first (row by row within a column).
    pub const VERTICAL: u16 = 1 << 3;
}

/// Bits of R01h and R60h.
pub mod scan {
    /// R01h SS: source outputs S720 → S1 (columns mirrored on the glass).
    pub const SS: u16 = 1 << 8;
    /// R60h GS: gate outputs G320 → G1 (rows mirrored on the glass).
    pub const GS: u16 = 1 << 15;
}
