//! Register access for the GPIO pins of the pin map ([`crate::seam::pins`]:
//! ports, pins and the Arduino Mega names of the shield signals, re-exported
//! here), and the pins of the ports no driver owns as embedded-hal pins
//! ([`split`]).
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

    /// The level on the pin (its PINx bit), whatever drives it.
    #[inline]
    pub(crate) fn is_high(self) -> bool {
        // SAFETY: see `mode`; reading PINx has no side effect.
        unsafe { read_volatile(self.port().pin_reg() as *const u8) & self.mask() != 0 }
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

/// A port that no driver of this board owns: A, B, C, D, J and K. Ports E,
/// F, G and H carry the shield's LCD/touch pins and belong to
/// [`ShieldBus`](super::shield::ShieldBus); port L carries the servo signals
/// (PL3..PL5) of [`ServoPwm`](super::servo_pwm::ServoPwm).
pub trait FreePort: sealed::Sealed {
    /// Which port the PAC peripheral is.
    const PORT: Port;
}

mod sealed {
    pub trait Sealed {}
}

macro_rules! free_ports {
    ($($pac:ident => $port:ident),*) => {$(
        impl sealed::Sealed for avr_device::atmega2560::$pac {}
        impl FreePort for avr_device::atmega2560::$pac {
            const PORT: Port = Port::$port;
        }
    )*};
}

free_ports!(PORTA => A, PORTB => B, PORTC => C, PORTD => D, PORTJ => J, PORTK => K);

/// The eight pins of a free port, bit 0 first. Takes the PAC port: owning
/// it is the right to change its pins (`Peripherals::take` hands it out
/// once), and each returned pin is the right to one bit.
pub fn split<P: FreePort>(_port: P) -> [FreePin; 8] {
    core::array::from_fn(|bit| FreePin { pin: Pin::new(P::PORT, bit as u8) })
}

/// One pin of a free port, not yet configured (as the chip left it).
pub struct FreePin {
    pin: Pin,
}

impl FreePin {
    /// The (port, bit) this handle stands for.
    pub fn pin(&self) -> Pin {
        self.pin
    }

    /// An output starting at `high`.
    pub fn into_output(self, high: bool) -> Output {
        self.pin.set_mode(if high { PinMode::OutputHigh } else { PinMode::OutputLow });
        Output { pin: self.pin }
    }

    /// An input, with the internal pull-up (20–50 kΩ) if `pull_up`.
    pub fn into_input(self, pull_up: bool) -> Input {
        self.pin.set_mode(if pull_up { PinMode::PullUp } else { PinMode::Floating });
        Input { pin: self.pin }
    }
}

/// A free pin driven as an output: embedded-hal's `OutputPin` and
/// `StatefulOutputPin`.
pub struct Output {
    pin: Pin,
}

/// A free pin as an input: embedded-hal's `InputPin`.
pub struct Input {
    pin: Pin,
}

impl embedded_hal::digital::ErrorType for Output {
    type Error = core::convert::Infallible;
}

impl embedded_hal::digital::ErrorType for Input {
    type Error = core::convert::Infallible;
}

impl embedded_hal::digital::OutputPin for Output {
    fn set_low(&mut self) -> Result<(), Self::Error> {
        self.pin.write(false);
        Ok(())
    }

    fn set_high(&mut self) -> Result<(), Self::Error> {
        self.pin.write(true);
        Ok(())
    }
}

impl embedded_hal::digital::StatefulOutputPin for Output {
    fn is_set_high(&mut self) -> Result<bool, Self::Error> {
        Ok(self.pin.mode() == PinMode::OutputHigh)
    }

    fn is_set_low(&mut self) -> Result<bool, Self::Error> {
        Ok(self.pin.mode() == PinMode::OutputLow)
    }
}

impl embedded_hal::digital::InputPin for Input {
    fn is_high(&mut self) -> Result<bool, Self::Error> {
        Ok(self.pin.is_high())
    }

    fn is_low(&mut self) -> Result<bool, Self::Error> {
        Ok(!self.pin.is_high())
    }
}
