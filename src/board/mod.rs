//! ATmega2560 board support: the small HAL this firmware needs, written on
//! `avr-device` registers (arduino-hal is not available as a crate).
//! Everything here is AVR-only; the logic above it is pure and host-tested.
//!
//! The seam traits are implemented here: `TouchPanel` (touch::TouchReader),
//! `ServoOutputs` (servo_pwm::ServoPwm), `Clock` (tick::Tick), `SerialPort`
//! (usart::Usart0), `Storage` (eeprom::Eeprom, as embedded-storage's
//! `ReadStorage` + `Storage`).
//!
//! So do the embedded-hal 1.0 family's, for drivers and examples written
//! against them (the product calls none of them; they cost it no flash):
//! `DelayNs` ([`Delay`]), `SetDutyCycle` per servo channel
//! (servo_pwm::ServoChannel), `OutputPin`/`InputPin` on the ports no driver
//! owns (gpio::split), embedded-io's `Read`/`Write` on USART0. The shield's
//! pins have none of these: they stay behind `ShieldBus` (see shield.rs).

pub mod adc;
pub mod cycles;
pub mod eeprom;
pub mod fault;
pub mod frame;
pub mod gpio;
pub mod lcd;
#[cfg(feature = "mipidsi")]
pub mod mipidsi;
pub mod resume;
pub mod servo_pwm;
pub mod shield;
pub mod stack;
pub mod tick;
pub mod touch;
pub mod usart;
pub mod watchdog;

/// CPU clock of the Mega 2560.
pub const CPU_HZ: u32 = 16_000_000;
const CYCLES_PER_US: u32 = CPU_HZ / 1_000_000;

/// Busy-waits at least `us` microseconds (longer if interrupts run meanwhile).
#[inline(always)]
pub fn delay_us(us: u32) {
    avr_device::asm::delay_cycles(us.saturating_mul(CYCLES_PER_US));
}

/// ufmt's `uwrite!`/`uwriteln!` onto any embedded-io writer ([`usart::Usart0`]
/// or another crate's), for text and numbers without `core::fmt` (which
/// costs kilobytes of flash here).
pub struct Fmt<W>(pub W);

impl<W: embedded_io::Write> ufmt::uWrite for Fmt<W> {
    type Error = W::Error;

    fn write_str(&mut self, s: &str) -> Result<(), W::Error> {
        self.0.write_all(s.as_bytes())
    }
}

/// embedded-hal's [`DelayNs`](embedded_hal::delay::DelayNs) by busy-waiting:
/// at least the time asked, longer when interrupts run meanwhile. Zero-sized
/// and `Copy`: make one wherever a driver wants a delay.
#[derive(Clone, Copy, Debug, Default)]
pub struct Delay;

impl embedded_hal::delay::DelayNs for Delay {
    fn delay_ns(&mut self, ns: u32) {
        // A cycle is 62.5 ns, so `ns` needs ns·0.016 cycles; ns/64 + ns/2048
        // is ns·0.01611 (two shifts instead of a 32-bit division), and + 2
        // covers what the two floors drop.
        avr_device::asm::delay_cycles((ns >> 6) + (ns >> 11) + 2);
    }

    fn delay_us(&mut self, us: u32) {
        delay_us(us);
    }

    fn delay_ms(&mut self, ms: u32) {
        // Per millisecond: `ms` · 16 000 cycles would overflow past 268 s.
        for _ in 0..ms {
            delay_us(1000);
        }
    }
}
