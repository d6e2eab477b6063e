//! Watchdog: a hung main loop resets the chip, and a reset is a safe state:
//! the servo PWM starts with its outputs disconnected until the app has
//! loaded its configuration, and then sends the pulses the servos had before
//! the reset (`board::resume`: the arm holds where it was, the interrupted
//! move is not continued) or, after a power-up, the home pose.
//!
//! Boot order matters. After a watchdog reset the hardware sets WDRF, and
//! while WDRF is set the watchdog stays enabled (WDE forced on) with its
//! shortest timeout, 16 ms: firmware that does not clear WDRF and disable or
//! reconfigure the watchdog within 16 ms of reset resets again, forever.
//! So [`Watchdog::boot`] must be the first thing `main` does (the C runtime's
//! .data/.bss setup before it takes well under 1 ms). It also returns the
//! reset cause, so the app can report "reset by watchdog".
//!
//! A bootloader runs before the app and may already have read and cleared
//! MCUSR (some Mega bootloaders do); then no cause is reported.

use avr_device::atmega2560::{CPU, WDT};

/// WDTCSR bits.
const WDCE: u8 = 1 << 4;
const WDE: u8 = 1 << 3;

/// MCUSR bits.
const PORF: u8 = 1 << 0;
const EXTRF: u8 = 1 << 1;
const BORF: u8 = 1 << 2;
const WDRF: u8 = 1 << 3;

/// Watchdog timeout (the 128 kHz watchdog oscillator: ±10 % or worse).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Timeout {
    /// About 250 ms.
    Ms250,
    /// About 500 ms.
    Ms500,
    /// About 1 s.
    S1,
    /// About 2 s.
    S2,
}

impl Timeout {
    /// WDP3:0 in WDTCSR (WDP3 = bit 5 is 0 for all of these).
    const fn prescaler_bits(self) -> u8 {
        match self {
            Timeout::Ms250 => 0b100,
            Timeout::Ms500 => 0b101,
            Timeout::S1 => 0b110,
            Timeout::S2 => 0b111,
        }
    }
}

/// The MCUSR flags found at boot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ResetCause {
    bits: u8,
}

impl ResetCause {
    /// The watchdog reset the chip (a hang, or a deliberate watchdog reset).
    pub const fn watchdog(self) -> bool {
        self.bits & WDRF != 0
    }
    /// Power was applied.
    pub const fn power_on(self) -> bool {
        self.bits & PORF != 0
    }
    /// The RESET pin was pulled low (the reset button, or a bootloader upload).
    pub const fn external(self) -> bool {
        self.bits & EXTRF != 0
    }
    /// The supply dropped below the brown-out level (e.g. servos on the
    /// board's 5 V).
    pub const fn brown_out(self) -> bool {
        self.bits & BORF != 0
    }
    /// The raw MCUSR value.
    pub const fn bits(self) -> u8 {
        self.bits
    }
}

/// The watchdog timer, owned.
pub struct Watchdog {
    regs: WDT,
}

impl Watchdog {
    /// Reads and clears the reset flags, then switches the watchdog off (it is
    /// still running after a watchdog reset). Call first in `main`.
    pub fn boot(regs: WDT, cpu: &CPU) -> (Watchdog, ResetCause) {
        let bits = cpu.mcusr().read().bits();
        // WDRF must be cleared before WDE can be.
        // SAFETY: writing 0 clears all reset flags; no other effect.
        cpu.mcusr().write(|w| unsafe { w.bits(0) });
        let mut wd = Watchdog { regs };
        wd.disable();
        (wd, ResetCause { bits })
    }

    /// Starts (or changes) the watchdog in reset mode. From now on `feed`
    /// must be called more often than `timeout`.
    pub fn enable(&mut self, timeout: Timeout) {
        self.timed_write(WDE | timeout.prescaler_bits());
    }

    /// Stops the watchdog.
    pub fn disable(&mut self) {
        self.timed_write(0);
    }

    /// Restarts the watchdog's count (`wdr`).
    pub fn feed(&self) {
        feed();
    }

    /// The timed sequence: set WDCE and WDE, then write the new value within
    /// 4 cycles. Interrupts are off so nothing can stretch the gap; the
    /// counter is reset first so the change cannot itself time out.
    fn timed_write(&mut self, value: u8) {
        avr_device::interrupt::free(|_| {
            avr_device::asm::wdr();
            // SAFETY: WDCE|WDE opens the change window; `value` is a valid
            // configuration (WDE and prescaler bits only).
            self.regs.wdtcsr().write(|w| unsafe { w.bits(WDCE | WDE) });
            self.regs.wdtcsr().write(|w| unsafe { w.bits(value) });
        });
    }
}

/// Resets the watchdog counter (`wdr`). Free function so drivers with long
/// bounded operations (EEPROM writes) can call it without owning the WDT; a
/// no-op while the watchdog is off.
#[inline(always)]
pub fn feed() {
    avr_device::asm::wdr();
}
