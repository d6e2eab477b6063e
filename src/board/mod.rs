//! ATmega2560 board support: the small HAL this firmware needs, written on
//! `avr-device` registers (arduino-hal is not available as a crate).
//! Everything here is AVR-only; the logic above it is pure and host-tested.

pub mod lcd;
pub mod servo_pwm;
pub mod usart;
