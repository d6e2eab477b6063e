//! The shield's 8-bit LCD bus as mipidsi's [`Interface`] (feature `mipidsi`),
//! so mipidsi's display drivers (ILI9341 and the other MIPI-DCS controllers
//! these shields carry) draw on the screen:
//!
//! ```ignore
//! let mut display = mipidsi::Builder::new(ILI9341Rgb565, &mut bus).init(&mut Delay)?;
//! ```
//!
//! Bytes go out through the firmware's own fast paths ([`Bus8`] on
//! [`ShieldBus`]; a repeated RGB565 pixel is the solid-fill loop). The pins
//! stay behind the bus: a display holds `&mut ShieldBus` while it lives, so
//! drawing and touch reads still cannot overlap. mipidsi resets the
//! controller by command (SWRESET): the RST line is the bus's, not an
//! `OutputPin`.

use core::convert::Infallible;

use ::mipidsi::interface::{Interface, InterfaceKind};

use super::lcd::Bus8;
use super::shield::ShieldBus;

impl Interface for ShieldBus {
    type Word = u8;
    type Error = Infallible;

    const KIND: InterfaceKind = InterfaceKind::Parallel8Bit;

    /// Selects the controller (CS stays low, as with the firmware's driver),
    /// then the command byte and its parameters.
    fn send_command(&mut self, command: u8, args: &[u8]) -> Result<(), Infallible> {
        self.select(true);
        self.command(command);
        self.data(args);
        Ok(())
    }

    fn send_pixels<const N: usize>(&mut self, pixels: impl IntoIterator<Item = [u8; N]>) -> Result<(), Infallible> {
        match N {
            // RGB565: runs of equal colours go out through the fill loop.
            2 => self.stream(pixels.into_iter().map(|p| rgb565(&p))),
            _ => pixels.into_iter().for_each(|p| self.data(&p)),
        }
        Ok(())
    }

    fn send_repeated_pixel<const N: usize>(&mut self, pixel: [u8; N], count: u32) -> Result<(), Infallible> {
        match N {
            2 => self.repeat(rgb565(&pixel), count),
            _ => (0..count).for_each(|_| self.data(&pixel)),
        }
        Ok(())
    }
}

/// An RGB565 pixel's two bytes (high first) as the 16-bit colour.
fn rgb565(p: &[u8]) -> u16 {
    u16::from_be_bytes([p.first().copied().unwrap_or(0), p.get(1).copied().unwrap_or(0)])
}
