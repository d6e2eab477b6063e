//! Register access for the GPIO pins of the pin map ([`crate::seam::pins`]:
//! ports, pins and the Arduino Mega names of the shield signals, re-exported
//! here).
//!
//! A [`Pin`] is only a descriptor (two bytes, `Copy`). Its register accessors
//! are crate-private: the right to change a pin comes from owning the PAC port
//! peripheral, and the shield's ports E, F, G and H are owned by
//! [`ShieldBus`](super::shield::ShieldBus). So nothing outside the board layer
//! can reach a shared LCD/touch pin except through the bus.
//!
//! Every read-modify-write of DDRx/PORTx runs with interrupts disabled. Ports
//! H, J, K and L live in extended I/O space where no `sbi`/`cbi` exists, so
//! even a single-bit change is a load/modify/store that an interrupt touching
//! the same port could otherwise undo; on ports A–G the compiler might emit
//! `sbi`/`cbi` for constant pins, but the pins here are runtime values.

use core::ptr::{read_volatile, write_volatile};

pub use crate::seam::pins::{mega, Pin, Port};

impl Port {
    /// Data-space address of PINx; DDRx and PORTx follow at +1 and +2.
    const fn pin_reg(self) -> usize {
        match self {
            Port::A => 0x20,
            Port::B => 0x23,
            Port::C => 0x26,
            Port::D => 0x29,
            Port::E => 0x2C,
            Port::F => 0x2F,
            Port::G => 0x32,
            Port::H => 0x100,
            Port::J => 0x103,
            Port::K => 0x106,
            Port::L => 0x109,
        }
    }
}

/// The four states a pin can be in: the (DDR, PORT) bit pair.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PinMode {
    /// DDR 0, PORT 0: high impedance, no pull-up (what an ADC input needs).
    Floating,
    /// DDR 0, PORT 1.
    PullUp,
    /// DDR 1, PORT 0.
    OutputLow,
    /// DDR 1, PORT 1.
    OutputHigh,
}

impl PinMode {
    const fn from_bits(ddr: bool, port: bool) -> PinMode {
        match (ddr, port) {
            (false, false) => PinMode::Floating,
            (false, true) => PinMode::PullUp,
            (true, false) => PinMode::OutputLow,
            (true, true) => PinMode::OutputHigh,
        }
    }
    const fn is_output(self) -> bool {
        matches!(self, PinMode::OutputLow | PinMode::OutputHigh)
    }
    const fn port_bit(self) -> bool {
        matches!(self, PinMode::PullUp | PinMode::OutputHigh)
    }
}

/// Register access of a pin (the descriptor is the pin map's, `seam::pins`).
impl Pin {
    const fn mask(self) -> u8 {
        1 << self.bit()
    }

    /// The pin's current (DDR, PORT) state.
    #[inline]
    pub(crate) fn mode(self) -> PinMode {
        let base = self.port().pin_reg();
        avr_device::interrupt::free(|_| {
            // SAFETY: fixed, always-mapped I/O registers of the ATmega2560;
            // byte-wide volatile access is their defined interface.
            let (ddr, port) =
                unsafe { (read_volatile((base + 1) as *const u8), read_volatile((base + 2) as *const u8)) };
            PinMode::from_bits(ddr & self.mask() != 0, port & self.mask() != 0)
        })
    }

    /// Puts the pin into `mode` without passing through a state that drives
    /// the wrong level: becoming an output, PORT is written first (so the pin
    /// starts driving the intended level, at worst after a moment of pull-up);
    /// becoming an input, DDR is cleared first (so it stops driving before the
    /// pull-up setting changes). An LCD strobe line (WR, CS) therefore never
    /// sees a spurious low pulse from a mode change.
    #[inline]
    pub(crate) fn set_mode(self, mode: PinMode) {
        let base = self.port().pin_reg();
        let ddr_reg = (base + 1) as *mut u8;
        let port_reg = (base + 2) as *mut u8;
        let m = self.mask();
        avr_device::interrupt::free(|_| {
            // SAFETY: see `mode`; only this pin's bit changes.
            unsafe {
                let port = read_volatile(port_reg);
                let port = if mode.port_bit() { port | m } else { port & !m };
                let ddr = read_volatile(ddr_reg);
                if mode.is_output() {
                    write_volatile(port_reg, port);
                    write_volatile(ddr_reg, ddr | m);
                } else {
                    write_volatile(ddr_reg, ddr & !m);
                    write_volatile(port_reg, port);
                }
            }
        });
    }

    /// Sets the PORT bit (drives the level if the pin is an output).
    #[inline]
    pub(crate) fn write(self, high: bool) {
        let port_reg = (self.port().pin_reg() + 2) as *mut u8;
        let m = self.mask();
        avr_device::interrupt::free(|_| {
            // SAFETY: see `mode`; only this pin's bit changes.
            unsafe {
                let v = read_volatile(port_reg);
                write_volatile(port_reg, if high { v | m } else { v & !m });
            }
        });
    }
}
