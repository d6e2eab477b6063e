//! The seam between the pure app and the hardware: small traits implemented by
//! the AVR board layer (`board`, on the chip) and by `hal-sim` (the host twin).
//! Everything above these traits is pure and tested on the host.

pub use crate::config_store::{Storage, StorageError};
use crate::touch_filter::RawSample;

/// The 4-wire resistive panel. An implementation drives and floats the panel
/// pins, lets the voltage settle, samples, and hands every pin it shares with
/// the LCD back exactly as it found it before returning.
pub trait TouchPanel {
    /// Fills `out` with consecutive raw readings (x, y, pressure) and returns how
    /// many it filled (fewer on a hardware fault).
    fn read(&mut self, out: &mut [RawSample]) -> usize;
}

/// The three servo signal outputs (base, shoulder, elbow).
pub trait ServoOutputs {
    /// Commands the pulse widths in µs for the next PWM period. The
    /// implementation clamps to its own configured limits as well, so no caller
    /// can drive a servo outside them.
    fn set_pulses(&mut self, pulses_us: &[u16; 3]);
    /// Stops the pulses (servos go limp) until the next `set_pulses`.
    fn disable(&mut self);
}

/// A monotonic millisecond clock.
pub trait Clock {
    fn now_ms(&self) -> u32;
}

/// The line-oriented serial port (USART0 on the chip).
pub trait SerialPort {
    /// The next received byte, if any (never blocks).
    fn read_byte(&mut self) -> Option<u8>;
    /// Queues bytes for transmission.
    fn write(&mut self, bytes: &[u8]);
}
