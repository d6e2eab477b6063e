//! ATmega2560 board support: the small HAL this firmware needs, written on
//! `avr-device` registers (arduino-hal is not available as a crate).
//! Everything here is AVR-only; the logic above it is pure and host-tested.
//!
//! The seam traits are implemented here: `TouchPanel` (touch::TouchReader),
//! `ServoOutputs` (servo_pwm::ServoPwm), `Clock` (tick::Tick), `SerialPort`
//! (usart::Usart0), `Storage` (eeprom::Eeprom, as embedded-storage's
//! `ReadStorage` + `Storage`).

pub mod adc;
pub mod cycles;
pub mod eeprom;
pub mod fault;
pub mod gpio;
pub mod lcd;
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
