//! The shield's pins: LCD mode by default, lent to the touch panel on demand.
//!
//! The resistive panel shares four pins with the LCD (docs/hardware.md): two analog
//! ones among LCD_WR/RS/CS (A1..A3) and two data lines. To read the panel they
//! are driven and floated in ways the LCD must never see as bus traffic, and
//! afterwards every one of them has to be back exactly as it was: an LCD pin
//! left as an input floats, and the controller then latches noise (a white or
//! corrupt screen), or a strobe left low clocks garbage into it.
//!
//! [`ShieldBus`] owns the PAC peripherals of ports E, F, G and H, so it is the
//! only code that can change these pins. Outside [`ShieldBus::with_touch`]
//! they are in LCD mode, and the only touch-mode handle ([`TouchPins`]) exists
//! inside that call, which restores all 13 pins before it returns. A caller
//! holding the bus therefore cannot observe touch mode, and drawing (which
//! needs `&mut ShieldBus`) cannot overlap a touch read.
//!
//! Reading the controller (its ID at boot) turns the eight data pins around
//! the same way: [`ShieldBus::with_read`] makes them pulled-up inputs, lends a
//! [`ReadPins`] that only strobes RD and samples them, and puts all 13 pins
//! back before it returns.

use avr_device::atmega2560::{PORTE, PORTF, PORTG, PORTH};

use super::adc::{Adc, AdcError};
use super::delay_us;
use super::gpio::mega::{LCD_CS, LCD_DATA, LCD_RD, LCD_RS, LCD_RST, LCD_WR};
use super::gpio::{Pin, PinMode};
use crate::seam::pins::PanelPinout;
use crate::touch::wiring::{Probe, Wiring};

/// Every LCD pin, in the order they are restored after a touch read: data and
/// RS first, then the RD/WR strobes, chip select last. Had CS been left active
/// by the display code, re-selecting the chip only after WR is back at its
/// idle level keeps a WR edge from the panel read from becoming a write.
const RESTORE_ORDER: [Pin; 13] = [
    LCD_RST,
    LCD_RS,
    LCD_DATA[0],
    LCD_DATA[1],
    LCD_DATA[2],
    LCD_DATA[3],
    LCD_DATA[4],
    LCD_DATA[5],
    LCD_DATA[6],
    LCD_DATA[7],
    LCD_RD,
    LCD_WR,
    LCD_CS,
];

/// Pins the panel may use: only these are owned (through their ports) and
/// saved/restored by the bus.
const SHIELD_PINS: [Pin; 13] = RESTORE_ORDER;

/// A control line of the LCD.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LcdLine {
    /// LCD_RD (A0), read strobe, active low.
    Rd,
    /// LCD_WR (A1), write strobe, active low.
    Wr,
    /// LCD_RS (A2): low = command, high = data.
    Rs,
    /// LCD_CS (A3), chip select, active low.
    Cs,
    /// LCD_RST (A4), reset, active low.
    Rst,
}

impl LcdLine {
    const fn pin(self) -> Pin {
        match self {
            LcdLine::Rd => LCD_RD,
            LcdLine::Wr => LCD_WR,
            LcdLine::Rs => LCD_RS,
            LcdLine::Cs => LCD_CS,
            LcdLine::Rst => LCD_RST,
        }
    }
}

/// Data bit k of the LCD bus on port E: PE4 = D2, PE5 = D3, PE3 = D5.
const E_MASK: u8 = 0b0011_1000;
/// PG5 = D4.
const G_MASK: u8 = 0b0010_0000;
/// PH5 = D0, PH6 = D1, PH3 = D6, PH4 = D7.
const H_MASK: u8 = 0b0111_1000;

/// Owner of the shield's LCD/touch pins, in LCD mode.
pub struct ShieldBus {
    e: PORTE,
    // Held for ownership only: ports F and G pins go through `Pin`, and
    // nothing else may reach them.
    _f: PORTF,
    g: PORTG,
    h: PORTH,
}

impl ShieldBus {
    /// Takes the shield ports and puts all 13 LCD pins in LCD mode: outputs,
    /// CS/RD/WR/RST at their inactive high level, RS high (data), D0..D7 low.
    /// CS goes first so the controller is deselected before anything moves.
    pub fn new(e: PORTE, f: PORTF, g: PORTG, h: PORTH) -> Self {
        for p in [LCD_CS, LCD_RD, LCD_WR, LCD_RST, LCD_RS] {
            p.set_mode(PinMode::OutputHigh);
        }
        for p in LCD_DATA {
            p.set_mode(PinMode::OutputLow);
        }
        Self { e, _f: f, g, h }
    }

    /// Sets an LCD control line.
    pub fn set_line(&mut self, line: LcdLine, high: bool) {
        line.pin().write(high);
    }

    /// Puts `byte` on LCD D0..D7 (bit k on data line k). Each of the three
    /// ports is changed with one masked store, all inside one critical section.
    pub fn write_data(&mut self, byte: u8) {
        let b = |k: u8, to: u8| ((byte >> k) & 1) << to;
        let e = b(2, 4) | b(3, 5) | b(5, 3);
        let g = b(4, 5);
        let h = b(0, 5) | b(1, 6) | b(6, 3) | b(7, 4);
        avr_device::interrupt::free(|_| {
            // SAFETY: any bit pattern is valid in PORTx; bits outside the
            // masks keep their values.
            self.e.porte().modify(|r, w| unsafe { w.bits((r.bits() & !E_MASK) | e) });
            self.g.portg().modify(|r, w| unsafe { w.bits((r.bits() & !G_MASK) | g) });
            self.h.porth().modify(|r, w| unsafe { w.bits((r.bits() & !H_MASK) | h) });
        });
    }

    /// Lends the panel pins to `f` and hands them back in LCD mode.
    ///
    /// Before `f` runs, the (DDR, PORT) state of all 13 LCD pins is saved and
    /// the controller is idled: CS, RD and WR are driven high unless the
    /// wiring uses that line for the panel, so panel traffic on the others is
    /// ignored. After `f` returns, every pin is put back exactly as saved
    /// (see `RESTORE_ORDER`), whatever `f` did. `TouchPins` cannot outlive
    /// the call, so touch mode is never visible outside it. (Panics abort the
    /// firmware, so there is no unwinding path that skips the restore.)
    pub fn with_touch<R>(&mut self, adc: &mut Adc, wiring: &TouchWiring, f: impl FnOnce(&mut TouchPins<'_>) -> R) -> R {
        let saved = snapshot();
        for p in [LCD_CS, LCD_RD, LCD_WR] {
            if !wiring.uses(p) {
                p.set_mode(PinMode::OutputHigh);
            }
        }
        let r = f(&mut TouchPins::lend(adc, wiring));
        restore(&saved);
        r
    }
}

/// RD low to sampling: the slowest access time of the supported
/// controllers' 8080 read cycle is 340 ns (frame-memory reads of the
/// ILI9341, ILI9486 and ST7789V; ID and register reads are faster).
const RD_ACCESS_CYCLES: u32 = 8;
/// RD high before the next strobe (the read cycles' high phase and cycle
/// time, 90–450 ns).
const RD_RECOVER_CYCLES: u32 = 8;

impl ShieldBus {
    /// Lends the data lines to the controller for a read and hands them back
    /// in LCD mode.
    ///
    /// Before `f` runs, the (DDR, PORT) state of all 13 LCD pins is saved;
    /// WR and RD are driven high (no write strobe can happen, the read
    /// strobe is idle), RS high (reads return data), and D0..D7 become
    /// inputs with their pull-ups, so a controller that does not answer reads
    /// as all ones instead of floating. CS stays as the caller left it (it
    /// selects the controller for the read). After `f`, every pin is put back
    /// exactly as saved, as [`ShieldBus::with_touch`] does; the data lines
    /// turn back into outputs only after RD is high again, so the bus is
    /// never driven from both ends.
    pub fn with_read<R>(&mut self, f: impl FnOnce(&mut ReadPins<'_>) -> R) -> R {
        let saved = snapshot();
        for p in [LCD_WR, LCD_RD, LCD_RS] {
            p.set_mode(PinMode::OutputHigh);
        }
        for p in LCD_DATA {
            p.set_mode(PinMode::PullUp);
        }
        let r = f(&mut ReadPins { _bus: core::marker::PhantomData });
        restore(&saved);
        r
    }
}

/// The data lines while they are inputs, inside [`ShieldBus::with_read`].
pub struct ReadPins<'a> {
    _bus: core::marker::PhantomData<&'a mut ShieldBus>,
}

impl ReadPins<'_> {
    /// One RD strobe: RD low, wait the access time, sample D0..D7, RD high,
    /// wait the recovery time.
    pub fn byte(&mut self) -> u8 {
        LCD_RD.write(false);
        avr_device::asm::delay_cycles(RD_ACCESS_CYCLES);
        let mut b = 0u8;
        for (k, p) in LCD_DATA.iter().enumerate() {
            if p.is_high() {
                b |= 1 << k;
            }
        }
        LCD_RD.write(true);
        avr_device::asm::delay_cycles(RD_RECOVER_CYCLES);
        b
    }
}

/// Wait before sampling a link: the 20–50 kΩ pull-up charges the sense line
/// (the ADC's sample-and-hold, the LCD input, any filter capacitor a shield
/// puts there: up to ~10 nF, τ ≤ 0.5 ms) through no plate when the pair is
/// open.
const LINK_SETTLE_US: u32 = 2_000;

/// Why [`ShieldBus::plate_link`] measured nothing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LinkError {
    /// A pin is not one of the 13 shield LCD pins.
    NotShieldPin,
    /// `sense` has no ADC channel.
    NotAnalog,
    /// `drive` and `sense` are the same pin.
    Same,
    /// The conversion failed (see [`AdcError`]).
    Adc(AdcError),
}

impl ShieldBus {
    /// How `drive` and `sense` are connected through the panel: the ADC count
    /// on `sense`, pulled up by its 20–50 kΩ, while `drive` is low. The two
    /// ends of one plate (a few hundred ohms) read under 20 counts; an open
    /// pair reads 1023. Nobody may touch the panel meanwhile (the plates would
    /// meet).
    ///
    /// Every other shield pin but RST is a pulled-up input meanwhile, so no
    /// pin is driven against `drive` through a plate, CS, RD and WR stay at
    /// their inactive high level unless a plate pulls one of them low (and a
    /// plate has two ends, so never two of them), and no LCD line can fake a
    /// link by driving the far end of `sense`'s plate. RST stays high. All 13
    /// pins are restored as [`ShieldBus::with_touch`] restores them.
    pub fn plate_link(&mut self, adc: &mut Adc, drive: Pin, sense: Pin) -> Result<u16, LinkError> {
        if !(is_shield_pin(drive) && is_shield_pin(sense)) {
            return Err(LinkError::NotShieldPin);
        }
        if drive == sense {
            return Err(LinkError::Same);
        }
        let channel = sense.adc_channel().ok_or(LinkError::NotAnalog)?;
        let saved = snapshot();
        // CS first: the controller is deselected before anything else moves.
        for p in RESTORE_ORDER.iter().rev() {
            if *p != LCD_RST && *p != drive {
                p.set_mode(PinMode::PullUp);
            }
        }
        drive.set_mode(PinMode::OutputLow);
        delay_us(LINK_SETTLE_US);
        let count = adc.read(channel);
        restore(&saved);
        count.map_err(LinkError::Adc)
    }
}

impl ShieldBus {
    /// The next read of a wiring probe ([`Probe`], `touch::wiring`): one
    /// [`ShieldBus::plate_link`] of the pair it names, recorded (a failed
    /// conversion as a failed read). Returns false once the probe is
    /// finished. About [`LINK_SETTLE_US`] plus a conversion.
    pub fn probe_step(&mut self, adc: &mut Adc, probe: &mut Probe) -> bool {
        let Some((drive, sense)) = probe.next() else { return false };
        probe.record(self.plate_link(adc, drive, sense).ok());
        true
    }
}

fn snapshot() -> [PinMode; 13] {
    RESTORE_ORDER.map(|p| p.mode())
}

fn restore(saved: &[PinMode; 13]) {
    for (p, m) in RESTORE_ORDER.iter().zip(saved.iter()) {
        p.set_mode(*m);
    }
}

/// Which shield pins carry the panel's four electrodes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TouchWiring {
    pub(super) xp: Pin,
    pub(super) xm: Pin,
    pub(super) yp: Pin,
    pub(super) ym: Pin,
    pub(super) xm_channel: u8,
    pub(super) yp_channel: u8,
}

/// Why [`TouchWiring::new`] refused a wiring.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WiringError {
    /// A pin is not one of the 13 shield LCD pins (the bus owns no other).
    NotShieldPin,
    /// X− or Y+ has no ADC channel.
    NotAnalog,
    /// The same pin is named twice.
    Duplicate,
}

const fn same(a: Pin, b: Pin) -> bool {
    a.bit() == b.bit() && a.port() as u8 == b.port() as u8
}

const fn is_shield_pin(p: Pin) -> bool {
    let mut i = 0;
    while i < SHIELD_PINS.len() {
        if same(p, SHIELD_PINS[i]) {
            return true;
        }
        i += 1;
    }
    false
}

/// Unwraps a preset at compile time (an invalid preset fails the build).
const fn checked(w: Result<TouchWiring, WiringError>) -> TouchWiring {
    match w {
        Ok(w) => w,
        Err(_) => panic!("invalid touch wiring preset"),
    }
}

impl TouchWiring {
    /// (a) XP = D8, XM = A2, YP = A3, YM = D9.
    pub const A: TouchWiring = checked(TouchWiring::of(&PanelPinout::A));
    /// (b) XP = D6, XM = A2, YP = A1, YM = D7.
    pub const B: TouchWiring = checked(TouchWiring::of(&PanelPinout::B));
    /// (c) XP = D7, XM = A1, YP = A2, YM = D6.
    pub const C: TouchWiring = checked(TouchWiring::of(&PanelPinout::C));

    /// [`TouchWiring::new`] for a pinout of the pin map.
    pub const fn of(p: &PanelPinout) -> Result<TouchWiring, WiringError> {
        TouchWiring::new(p.xp, p.xm, p.yp, p.ym)
    }
    /// The known wirings with their names, for tools that try each.
    pub const PRESETS: [(char, TouchWiring); 3] = [('a', Self::A), ('b', Self::B), ('c', Self::C)];

    /// The preset of a measured or stored wiring.
    pub const fn preset(w: Wiring) -> TouchWiring {
        match w {
            Wiring::A => Self::A,
            Wiring::B => Self::B,
            Wiring::C => Self::C,
        }
    }

    /// Checks that all four are distinct shield pins and X−, Y+ are analog.
    pub const fn new(xp: Pin, xm: Pin, yp: Pin, ym: Pin) -> Result<TouchWiring, WiringError> {
        if !(is_shield_pin(xp) && is_shield_pin(xm) && is_shield_pin(yp) && is_shield_pin(ym)) {
            return Err(WiringError::NotShieldPin);
        }
        if same(xp, xm) || same(xp, yp) || same(xp, ym) || same(xm, yp) || same(xm, ym) || same(yp, ym) {
            return Err(WiringError::Duplicate);
        }
        match (xm.adc_channel(), yp.adc_channel()) {
            (Some(xm_channel), Some(yp_channel)) => Ok(TouchWiring { xp, xm, yp, ym, xm_channel, yp_channel }),
            _ => Err(WiringError::NotAnalog),
        }
    }

    /// The X+ electrode's pin.
    pub const fn xp(&self) -> Pin {
        self.xp
    }
    /// The X− electrode's pin (analog).
    pub const fn xm(&self) -> Pin {
        self.xm
    }
    /// The Y+ electrode's pin (analog).
    pub const fn yp(&self) -> Pin {
        self.yp
    }
    /// The Y− electrode's pin.
    pub const fn ym(&self) -> Pin {
        self.ym
    }

    /// True if `p` is one of the four panel pins.
    pub fn uses(&self, p: Pin) -> bool {
        p == self.xp || p == self.xm || p == self.yp || p == self.ym
    }
}

/// The panel pins while they are lent out by [`ShieldBus::with_touch`]; only
/// exists inside that call.
pub struct TouchPins<'a> {
    adc: &'a mut Adc,
    wiring: &'a TouchWiring,
}

impl<'a> TouchPins<'a> {
    fn lend(adc: &'a mut Adc, wiring: &'a TouchWiring) -> Self {
        Self { adc, wiring }
    }

    /// The ADC, for the measurement (`touch.rs`).
    pub(super) fn adc(&mut self) -> &mut Adc {
        self.adc
    }

    /// Which pins are the panel's.
    pub(super) fn wiring(&self) -> &'a TouchWiring {
        self.wiring
    }
}
