//! The display controllers the UNO-form shields carry, and how the firmware
//! tells them apart at boot from what each answers on its ID registers.
//!
//! The probe (run by `board::lcd` over the shield bus, data pins switched to
//! inputs with pull-ups, so a register nobody answers reads all ones):
//!
//! 1. Index 0000h written as two command bytes, two bytes read: the
//!    register-indexed ILI932x family answers its driver code (ILI9325
//!    datasheet, R00h "Driver Code Read": 9325h). On a MIPI DCS controller
//!    the two bytes are NOPs and nothing answers.
//! 2. Command D3h (Read ID4), four bytes read: a dummy byte, the IC version,
//!    then the model (ILI9341 datasheet, "Read ID4 (D3h)": 00h 93h 41h;
//!    ILI9486 datasheet, "Read ID4 (D3h)": 00h 94h 86h; ST7796S datasheet,
//!    "Read ID4 (D3h)": 00h 77h 96h, what MCUFRIEND_kbv reads as 7796h).
//! 3. Command 04h (RDDID), four bytes read: a dummy byte, then ID1 ID2 ID3
//!    (ST7789V datasheet, "RDDID (04h)": 85h 85h 52h).
//!
//! Each command goes out as 16 bits (a 00h byte first): a NOP for the DCS
//! controllers, the upper index byte for the ILI932x, so the probe keeps
//! both in step. A controller that answers none of these is unknown: the
//! firmware says so on serial and drives it as an ILI9341, the commonest.
//!
//! `cal set lcd <name>` (`config::lcd`) forces a controller instead: the
//! probe still runs, only to say at boot whether the shield answered as the
//! forced controller should.

use super::layout::Layout;
use crate::config::lcd::LcdChoice;
use crate::text::Text;

/// A display controller the firmware drives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Controller {
    /// ILITEK ILI9341, 240×320, MIPI DCS.
    Ili9341,
    /// Sitronix ST7789V, 240×320, MIPI DCS.
    St7789,
    /// ILITEK ILI9486, 320×480, MIPI DCS.
    Ili9486,
    /// ILITEK ILI9325, 240×320, register-indexed.
    Ili9325,
    /// Sitronix ST7796S, 320×480, MIPI DCS (the 3.5"/4" shields).
    St7796,
}

/// How a controller is addressed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Protocol {
    /// MIPI DCS: one command byte, then its parameters; the window is set
    /// with CASET/PASET and pixels follow RAMWR.
    Dcs,
    /// ILI932x: a 16-bit register index, then 16-bit register data; the
    /// window is R50h–R53h, the start address R20h/R21h, pixels follow R22h.
    Indexed,
}

impl Controller {
    /// Every controller the firmware drives.
    pub const ALL: [Controller; 5] =
        [Controller::Ili9341, Controller::St7789, Controller::Ili9486, Controller::Ili9325, Controller::St7796];

    /// The name used on serial, by `cal set lcd` and by `scripts/run.sh --lcd`.
    pub fn name(self) -> Text {
        self.choice().name()
    }

    /// The `cal set lcd` choice that forces this controller.
    pub const fn choice(self) -> LcdChoice {
        match self {
            Controller::Ili9341 => LcdChoice::Ili9341,
            Controller::St7789 => LcdChoice::St7789,
            Controller::Ili9486 => LcdChoice::Ili9486,
            Controller::Ili9325 => LcdChoice::Ili9325,
            Controller::St7796 => LcdChoice::St7796,
        }
    }

    /// The controller a `cal set lcd` choice forces (`None`: auto).
    pub fn forced(choice: LcdChoice) -> Option<Controller> {
        Some(match choice {
            LcdChoice::Auto => return None,
            LcdChoice::Ili9341 => Controller::Ili9341,
            LcdChoice::St7789 => Controller::St7789,
            LcdChoice::Ili9486 => Controller::Ili9486,
            LcdChoice::Ili9325 => Controller::Ili9325,
            LcdChoice::St7796 => Controller::St7796,
        })
    }

    /// How the controller is addressed.
    pub const fn protocol(self) -> Protocol {
        match self {
            Controller::Ili9325 => Protocol::Indexed,
            _ => Protocol::Dcs,
        }
    }

    /// The panel held in landscape, as the UI uses it: width, height.
    pub const fn size(self) -> (u16, u16) {
        match self {
            Controller::Ili9486 | Controller::St7796 => (480, 320),
            _ => (320, 240),
        }
    }

    /// The UI's layout for this panel.
    pub const fn layout(self) -> Layout {
        match self {
            Controller::Ili9486 | Controller::St7796 => Layout::HVGA,
            _ => Layout::QVGA,
        }
    }

    /// The identification the probe reads from it, as printed on serial:
    /// 9341h, 858552h, 9486h, 9325h, 7796h.
    pub const fn id(self) -> u32 {
        match self {
            Controller::Ili9341 => 0x9341,
            Controller::St7789 => 0x85_8552,
            Controller::Ili9486 => 0x9486,
            Controller::Ili9325 => 0x9325,
            Controller::St7796 => 0x7796,
        }
    }
}

/// What the three ID reads returned (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct IdReads {
    /// Register 0000h, upper byte first.
    pub reg00: [u8; 2],
    /// Read ID4 (D3h): dummy, version, model high, model low.
    pub id4: [u8; 4],
    /// RDDID (04h): dummy, ID1, ID2, ID3.
    pub rddid: [u8; 4],
}

impl IdReads {
    /// The controller these answers identify, if any.
    pub fn identify(&self) -> Option<Controller> {
        if u16::from_be_bytes(self.reg00) == super::ili9325::ID {
            return Some(Controller::Ili9325);
        }
        match self.id4 {
            [_, 0x00, 0x93, 0x41] => return Some(Controller::Ili9341),
            [_, 0x00, 0x94, 0x86] => return Some(Controller::Ili9486),
            [_, 0x00, 0x77, 0x96] => return Some(Controller::St7796),
            _ => {}
        }
        match self.rddid {
            [_, 0x85, 0x85, 0x52] => Some(Controller::St7789),
            _ => None,
        }
    }

    /// The Read ID4 answer without its dummy byte (what an unknown
    /// controller is reported by).
    pub fn id4_value(&self) -> u32 {
        u32::from_be_bytes([0, self.id4[1], self.id4[2], self.id4[3]])
    }

    /// The RDDID answer without its dummy byte.
    pub fn rddid_value(&self) -> u32 {
        u32::from_be_bytes([0, self.rddid[1], self.rddid[2], self.rddid[3]])
    }

    /// Register 0000h as read.
    pub fn reg00_value(&self) -> u16 {
        u16::from_be_bytes(self.reg00)
    }
}
