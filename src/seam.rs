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

/// The line-oriented serial port (USART0 on the chip). Neither direction
/// blocks: received bytes wait in a bounded buffer until read, written bytes
/// in a bounded buffer until sent.
///
/// Nothing is lost silently. Receive: when the buffer is full, arriving bytes
/// are dropped until the reader has read everything kept before them; then
/// [`SerialPort::read_byte`] returns `None` and [`SerialPort::take_rx_loss`]
/// says which lines the drop cost. Transmit: [`SerialPort::write`] queues
/// only what fits in [`SerialPort::tx_room`]; callers check the room first
/// (the port counts bytes it had to drop, a caller's bug).
///
/// The defaults describe an unbounded port that never loses anything.
pub trait SerialPort {
    /// The next received byte, if any (never blocks).
    fn read_byte(&mut self) -> Option<u8>;
    /// After `read_byte` returned `None`: the bytes dropped at this point of
    /// the stream, if any were; reading then resumes after them.
    fn take_rx_loss(&mut self) -> Option<RxLoss> {
        None
    }
    /// Bytes [`SerialPort::write`] can queue now.
    fn tx_room(&self) -> usize {
        usize::MAX
    }
    /// Queues bytes for transmission and returns at once.
    fn write(&mut self, bytes: &[u8]);
}

/// What a full receive buffer cost, counted in lines as the serial protocol
/// splits them (`\n`, `\r` or `\r\n` ends a line;
/// `protocol::rx_loss::LossCounter` does the counting).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RxLoss {
    /// Lines with at least one byte that lost a byte or their terminator,
    /// each counted once (a line the reader had started counts here; so does
    /// the line still arriving, if it lost bytes).
    pub lines: u16,
    /// The line that continues after the loss lost bytes: the reader drops
    /// the rest of it (it is counted, now or in an earlier loss).
    pub rest_damaged: bool,
    /// The last dropped byte was `\r` (so a `\n` right after the loss belongs
    /// to it and ends no line).
    pub after_cr: bool,
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
