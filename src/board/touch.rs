//! Reading the 4-wire resistive panel on the pins it shares with the LCD.
//!
//! The wiring (which shield pin is X+, X−, Y+, Y−) differs between shields,
//! so it is configuration: [`TouchWiring`] with the three variants of docs/hardware.md.
//! X− and Y+ must be analog pins (A1..A3 on these shields = ADC1..3).
//!
//! One measurement (docs/hardware.md), each after [`PANEL_SETTLE_US`]:
//! - X: XP high, XM low, YP/YM floating; the Y plate picks up the X-plate
//!   voltage at the touch point: ADC on YP.
//! - Y: YP high, YM low, XP/XM floating: ADC on XM.
//! - pressure: XP low, YM high, XM/YP floating: z1 on XM, z2 on YP, combined
//!   by [`pressure`]. Untouched, the plates do not meet, XM sits at XP's 0 V
//!   and YP at YM's 5 V: z1 ≈ 0, z2 ≈ 1023, z ≈ 0.
//!
//! Floating means input without pull-up: a pull-up would add a 20–50 kΩ
//! source to the plate and bias the reading.
//!
//! The pins are only reachable through [`ShieldBus::with_touch`], which saves
//! and restores them; see `shield.rs` for why that matters. The shield owns
//! the wiring ([`TouchWiring`]) and the lent handle ([`TouchPins`]); this
//! module is the measurement made with them.

use crate::seam::RawSample;
use crate::seam::{TouchError, TouchPanel};
use crate::touch::filter::pressure;

use super::adc::{Adc, AdcError};
use super::delay_us;
use super::gpio::{Pin, PinMode};
use super::shield::{ShieldBus, TouchPins, TouchWiring};

/// Wait after switching the drive pins, before sampling. The plates are a few
/// hundred ohms and the floating one reaches the ADC through the contact
/// resistance (up to a few kΩ) against the 14 pF sample-and-hold: the
/// electrical time constant is well under 1 µs. 20 µs also covers shields
/// that put small filter capacitors on the lines, and is cheap next to the
/// 104 µs of a conversion.
pub const PANEL_SETTLE_US: u32 = 20;

/// The two raw pressure readings.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PressurePair {
    /// On XM.
    pub z1: u16,
    /// On YP.
    pub z2: u16,
}

impl TouchPins<'_> {
    /// Floats two pins first (so no two plates are ever driven against each
    /// other through the contact point), then drives the pair, then waits.
    #[inline]
    fn drive(high: Pin, low: Pin, float_a: Pin, float_b: Pin) {
        float_a.set_mode(PinMode::Floating);
        float_b.set_mode(PinMode::Floating);
        high.set_mode(PinMode::OutputHigh);
        low.set_mode(PinMode::OutputLow);
        delay_us(PANEL_SETTLE_US);
    }

    /// X position in ADC counts.
    pub fn read_x(&mut self) -> Result<u16, AdcError> {
        let w = self.wiring();
        Self::drive(w.xp, w.xm, w.yp, w.ym);
        self.adc().read(w.yp_channel)
    }

    /// Y position in ADC counts.
    pub fn read_y(&mut self) -> Result<u16, AdcError> {
        let w = self.wiring();
        Self::drive(w.yp, w.ym, w.xp, w.xm);
        self.adc().read(w.xm_channel)
    }

    /// z1 (XM) and z2 (YP) with XP low and YM high.
    pub fn read_pressure(&mut self) -> Result<PressurePair, AdcError> {
        let w = self.wiring();
        Self::drive(w.ym, w.xp, w.xm, w.yp);
        let z1 = self.adc().read(w.xm_channel)?;
        let z2 = self.adc().read(w.yp_channel)?;
        Ok(PressurePair { z1, z2 })
    }

    /// One X, Y, pressure triple, taken back to back so the three belong to
    /// the same finger position.
    pub fn sample(&mut self) -> Result<RawSample, AdcError> {
        let x = self.read_x()?;
        let y = self.read_y()?;
        let p = self.read_pressure()?;
        Ok(RawSample { x, y, z: pressure(p.z1, p.z2), z1: p.z1 })
    }

    /// Fills `out` with consecutive samples; stops at the first ADC fault.
    pub fn fill(&mut self, out: &mut [RawSample]) -> Result<(), TouchError> {
        for slot in out.iter_mut() {
            *slot = self.sample().map_err(|_| TouchError::Adc)?;
        }
        Ok(())
    }
}

/// Inside `with_touch`: the restore happens when that call returns.
impl TouchPanel for TouchPins<'_> {
    fn read(&mut self, out: &mut [RawSample]) -> Result<(), TouchError> {
        self.fill(out)
    }
}

/// [`TouchPanel`] for the app: borrows the bus and the ADC for as long as it
/// lives; every `read` lends the pins and restores them before returning.
/// Without a wiring (none known yet, or the probe identified none) the pins
/// stay the LCD's and every sample reads untouched (pressure 0): the panel
/// is not driven through pins that may not be its own.
pub struct TouchReader<'a> {
    bus: &'a mut ShieldBus,
    adc: &'a mut Adc,
    wiring: Option<&'a TouchWiring>,
}

impl<'a> TouchReader<'a> {
    /// A reader for the panel wired as `wiring`, or one that reads nothing.
    pub fn new(bus: &'a mut ShieldBus, adc: &'a mut Adc, wiring: Option<&'a TouchWiring>) -> Self {
        Self { bus, adc, wiring }
    }
}

impl TouchPanel for TouchReader<'_> {
    fn read(&mut self, out: &mut [RawSample]) -> Result<(), TouchError> {
        match self.wiring {
            Some(w) => self.bus.with_touch(self.adc, w, |p| p.fill(out)),
            None => {
                out.fill(RawSample { x: 0, y: 0, z: 0, z1: 0 });
                Ok(())
            }
        }
    }
}

impl ShieldBus {
    /// A [`TouchPanel`](crate::seam::TouchPanel) over this bus: each `read`
    /// is one `with_touch` call (none without a wiring).
    pub fn touch<'a>(&'a mut self, adc: &'a mut Adc, wiring: Option<&'a TouchWiring>) -> TouchReader<'a> {
        TouchReader::new(self, adc, wiring)
    }
}
