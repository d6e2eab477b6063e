//! The seam between the pure app and the hardware: small traits implemented by
//! the AVR board layer (`board`, on the chip) and by `hal-sim` (the host twin).
//! Everything above these traits is pure and tested on the host.

/// One sample of the panel: X and Y positions and the pressure measure
/// (see [`crate::touch::filter::pressure`]), all in ADC counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RawSample {
    pub x: u16,
    pub y: u16,
    pub z: u16,
}

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
    /// Commands the pulse widths for the next PWM period, in Timer5 ticks of
    /// 0.5 µs (the timer's resolution: 3000 = 1500 µs). The implementation
    /// clamps to its own configured limits as well, so no caller can drive a
    /// servo outside them.
    fn set_pulses(&mut self, ticks: &[u16; 3]);
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

/// Byte-addressed non-volatile memory (the AVR EEPROM, or a test double).
pub trait Storage {
    fn read(&mut self, addr: u16, buf: &mut [u8]) -> Result<(), StorageError>;
    fn write(&mut self, addr: u16, data: &[u8]) -> Result<(), StorageError>;
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StorageError {
    /// The access would run past the end of the memory.
    OutOfRange,
    /// The device reported a failure.
    Device,
}
