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

/// Byte-addressed non-volatile memory (the AVR EEPROM, the twin's, a test
/// double): embedded-storage's [`ReadStorage`](embedded_storage::ReadStorage) and [`Storage`](embedded_storage::Storage)
/// (reads and writes of any length at a byte offset; `write` erases as
/// needed) whose error is [`StorageError`]. Implement those two traits; this
/// one then holds by itself, so any embedded-storage driver with this error
/// plugs into the configuration store and the app.
pub trait Storage: embedded_storage::Storage<Error = StorageError> {}

impl<T: embedded_storage::Storage<Error = StorageError> + ?Sized> Storage for T {}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StorageError {
    /// The access would run past the end of the memory.
    OutOfRange,
    /// The device reported a failure.
    Device,
}
