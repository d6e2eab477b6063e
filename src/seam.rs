//! The seam between the pure app and the hardware: small traits implemented by
//! the AVR board layer (`board`, on the chip) and by `hal-sim` (the host twin).
//! Everything above these traits is pure and tested on the host.
//!
//! # Failure convention
//!
//! One rule for every trait here, decided by what the device can do:
//!
//! - **A device that can fail returns `Result<_, E>`**, and `E` says what
//!   failed ([`TouchError`]: a conversion of the ADC never finished;
//!   [`StorageError`]: an access past the end, or the EEPROM stuck). A failed
//!   call hands back no partial data as if it were good; the caller decides
//!   what the fault means (the app counts a failed panel read as a miss and
//!   reports a save it could not write).
//! - **A device that cannot fail returns plainly**: the Timer5 compare
//!   registers ([`ServoOutputs`]), the millisecond counter ([`Clock`]) and the
//!   USART transmitter ([`SerialPort::write`]) accept every call. A `Result`
//!   that is always `Ok` would cost code on the chip and teach callers to
//!   ignore errors.
//! - **Nothing there yet is not a failure**: `Option` ([`SerialPort::read_byte`]
//!   when no byte has arrived).
//!
//! This is the convention of the embedded-hal family (`embedded_storage` and
//! `embedded_io` return `Result` with an error type that names the fault), so a
//! trait here can be replaced by theirs without changing how callers handle
//! faults. An implementation that could lose data (a full transmit buffer)
//! must either wait for room or report it through its return value: nothing
//! is dropped silently.

pub mod pins;

/// One sample of the panel: X and Y positions, the pressure measure
/// (see [`crate::touch::filter::pressure`]) and the first pressure reading,
/// all in ADC counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RawSample {
    /// Voltage on the Y plate with the X plate driven, ADC counts 0..=1023.
    pub x: u16,
    /// Voltage on the X plate with the Y plate driven, ADC counts 0..=1023.
    pub y: u16,
    /// Pressure measure, 0..=2046, ≈ 0 untouched.
    pub z: u16,
    /// The pressure read's z1 (XM with XP low and YM high): the X plate's
    /// voltage at the contact, 0..=1023. With `x`, `y` and `z` it gives the
    /// panel's plate ratio, which a second contact breaks
    /// ([`crate::touch::filter::plate_ratio`]).
    pub z1: u16,
}

/// The 4-wire resistive panel. An implementation drives and floats the panel
/// pins, lets the voltage settle, samples, and hands every pin it shares with
/// the LCD back exactly as it found it before returning.
pub trait TouchPanel {
    /// Fills every slot of `out` with consecutive raw readings (x, y,
    /// pressure), or fails; after a failure the contents of `out` are
    /// unspecified.
    fn read(&mut self, out: &mut [RawSample]) -> Result<(), TouchError>;
}

/// Why a panel read failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TouchError {
    /// An ADC conversion did not finish (the converter is stuck or disabled).
    Adc,
}

/// The servo signal outputs: the three joints (base, shoulder, elbow) and
/// the gripper.
pub trait ServoOutputs {
    /// Commands the pulse widths for the next PWM period, in Timer5 ticks of
    /// 0.5 µs (the timer's resolution: 3000 = 1500 µs). The implementation
    /// clamps to its own configured limits as well, so no caller can drive a
    /// servo outside them.
    fn set_pulses(&mut self, ticks: &[u16; 3]);
    /// Commands the gripper's pulse width for the next PWM period, in the
    /// same ticks and under the same clamping; the gripper's output gets no
    /// pulse before the first call (after `disable`, none until the next).
    fn set_grip(&mut self, ticks: u16);
    /// Stops every pulse (servos go limp) until the next `set_pulses` (the
    /// gripper's until the next `set_grip`).
    fn disable(&mut self);
    /// Timer ticks (0.5 µs) left in the current PWM period, 0 once the next
    /// one has started; `None` where the outputs keep no time (the host
    /// twin). The app spreads long work (a path check) over frames by it.
    fn period_ticks_left(&self) -> Option<u16> {
        None
    }
}

/// A monotonic millisecond clock.
pub trait Clock {
    /// Milliseconds since start; wraps after 49.7 days, so compare with
    /// `wrapping_sub`.
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
    /// A one-byte STOP (`protocol::command::STOP_BYTE`, `!`) arrived since
    /// the last call. The port takes that byte out of the stream as it
    /// arrives (it is no part of a line, and a full buffer or an open loss
    /// does not hold it back), so the app latches STOP in its next frame
    /// without waiting for a line. The default: a port that passes `!` on
    /// in the stream, where the app acts on it when it reads it.
    fn take_stop_byte(&mut self) -> bool {
        false
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

/// Byte-addressed non-volatile memory (the AVR EEPROM, the twin's, a test
/// double): embedded-storage's [`ReadStorage`](embedded_storage::ReadStorage) and [`Storage`](embedded_storage::Storage)
/// (reads and writes of any length at a byte offset; `write` erases as
/// needed) whose error is [`StorageError`]. Implement those two traits; this
/// one then holds by itself, so any embedded-storage driver with this error
/// plugs into the configuration store and the app.
pub trait Storage: embedded_storage::Storage<Error = StorageError> {}

impl<T: embedded_storage::Storage<Error = StorageError> + ?Sized> Storage for T {}

/// Why a storage access failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StorageError {
    /// The access would run past the end of the memory.
    OutOfRange,
    /// The device reported a failure.
    Device,
}
