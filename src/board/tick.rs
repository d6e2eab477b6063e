//! Monotonic millisecond tick on Timer0.
//!
//! CTC mode, prescaler 64, OCR0A = 249: 16 MHz / 64 / 250 = exactly 1 kHz.
//! Timer0 is free on this board (its outputs OC0A/OC0B are PB7/PG5, and PG5
//! is LCD_D4, so they stay disconnected). The compare-match interrupt counts
//! a `u32` that wraps after 49.7 days; compare times with `wrapping_sub`.
//! The counter only runs while interrupts are enabled.

use core::cell::Cell;

use avr_device::atmega2560::TC0;
use avr_device::interrupt::Mutex;

use crate::seam::Clock;

const OCR0A_1KHZ: u8 = 249;

static MILLIS: Mutex<Cell<u32>> = Mutex::new(Cell::new(0));

/// The millisecond clock; owns Timer0.
pub struct Tick {
    _tc0: TC0,
}

impl Tick {
    /// Starts the 1 kHz interrupt from 0 ms. Takes effect once interrupts
    /// are enabled (`avr_device::interrupt::enable`).
    pub fn new(tc0: TC0) -> Self {
        tc0.tccr0b().write(|w| w.cs0().no_clock());
        tc0.tccr0a().write(|w| w.wgm0().ctc());
        tc0.ocr0a().write(|w| w.set(OCR0A_1KHZ));
        tc0.tcnt0().write(|w| w.set(0));
        // A stale compare flag would count a millisecond early.
        tc0.tifr0().write(|w| w.ocf0a().set_bit());
        avr_device::interrupt::free(|cs| MILLIS.borrow(cs).set(0));
        tc0.timsk0().write(|w| w.ocie0a().set_bit());
        tc0.tccr0b().write(|w| w.cs0().prescale_64());
        Self { _tc0: tc0 }
    }

    /// Milliseconds since `new` (a 4-byte value the ISR updates, so it is
    /// read with interrupts off).
    pub fn now_ms(&self) -> u32 {
        avr_device::interrupt::free(|cs| MILLIS.borrow(cs).get())
    }

    /// Waits at least `ms` milliseconds. With interrupts disabled the tick
    /// stands still, so it then falls back to counting CPU cycles instead of
    /// hanging.
    pub fn delay_ms(&self, ms: u32) {
        if !avr_device::interrupt::is_enabled() {
            for _ in 0..ms {
                super::delay_us(1000);
            }
            return;
        }
        let start = self.now_ms();
        // +1: the first tick may come right after `start` was read.
        while self.now_ms().wrapping_sub(start) < ms.saturating_add(1) {}
    }
}

impl Clock for Tick {
    fn now_ms(&self) -> u32 {
        Tick::now_ms(self)
    }
}

// Private: avr-device exports the handler by its vector name and wraps it in a
// public function that no doc comment reaches; it is no API.
mod vector {
    // One millisecond has passed: count it.
    #[avr_device::interrupt(atmega2560)]
    fn TIMER0_COMPA() {
        avr_device::interrupt::free(|cs| {
            let c = super::MILLIS.borrow(cs);
            c.set(c.get().wrapping_add(1));
        });
    }
}
