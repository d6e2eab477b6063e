//! USART0 (D0/D1, the USB serial): 115200 baud 8N1. Transmit is blocking;
//! receive is interrupt-driven into a fixed ring buffer, so bytes arriving
//! while the app computes a frame are kept (at 115200 baud a byte comes every
//! 87 µs; the 1-byte hardware buffer alone would overrun within a frame).
//!
//! The receive interrupt only fires once interrupts are enabled globally.

use core::cell::Cell;

use avr_device::atmega2560::USART0;
use avr_device::interrupt::{CriticalSection, Mutex};

use crate::seam::SerialPort;

/// 16 MHz / (8 · (16 + 1)) = 117 647 baud with U2X: 2.1 % off 115200, the
/// setting every Arduino bootloader and USB bridge uses for this rate.
const UBRR_115200_U2X: u16 = 16;

/// Receive buffer size: a power of two, so indices wrap with a mask. 128 bytes
/// hold 11 ms of continuous input at 115200 baud, and more than any command
/// line the parser accepts.
pub const RX_CAPACITY: usize = 128;
const RX_MASK: u8 = (RX_CAPACITY - 1) as u8;
/// One 10-bit frame at 117 647 baud is 85 µs.
const FRAME_US: u32 = 90;

/// What went wrong on the receive side since the last [`Usart0::take_rx_errors`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct RxErrors {
    /// Bytes were lost: the ring was full (the app did not read fast enough)
    /// or the hardware overran (the ISR was held off too long).
    pub overflow: bool,
    /// A byte arrived with a bad stop bit (wrong baud rate or line noise);
    /// it was dropped.
    pub framing: bool,
}

/// The ring shared between the ISR (producer) and `read_byte` (consumer).
/// Cells inside the interrupt mutex: no RefCell, so no borrow panic path.
struct RxRing {
    buf: [Cell<u8>; RX_CAPACITY],
    /// Next slot the ISR writes; free-running, wraps at 256 (a multiple of
    /// the capacity), so `head - tail` is the fill level.
    head: Cell<u8>,
    /// Next slot the reader takes.
    tail: Cell<u8>,
    overflow: Cell<bool>,
    framing: Cell<bool>,
}

impl RxRing {
    const fn new() -> Self {
        RxRing {
            buf: [const { Cell::new(0) }; RX_CAPACITY],
            head: Cell::new(0),
            tail: Cell::new(0),
            overflow: Cell::new(false),
            framing: Cell::new(false),
        }
    }

    fn push(&self, b: u8) {
        let head = self.head.get();
        if head.wrapping_sub(self.tail.get()) as usize >= RX_CAPACITY {
            self.overflow.set(true);
            return;
        }
        if let Some(slot) = self.buf.get((head & RX_MASK) as usize) {
            slot.set(b);
        }
        self.head.set(head.wrapping_add(1));
    }

    fn pop(&self) -> Option<u8> {
        let tail = self.tail.get();
        if tail == self.head.get() {
            return None;
        }
        let b = self.buf.get((tail & RX_MASK) as usize).map(Cell::get);
        self.tail.set(tail.wrapping_add(1));
        b
    }

    fn len(&self) -> usize {
        self.head.get().wrapping_sub(self.tail.get()) as usize
    }

    fn clear(&self) {
        self.tail.set(self.head.get());
        self.overflow.set(false);
        self.framing.set(false);
    }
}

static RX: Mutex<RxRing> = Mutex::new(RxRing::new());

/// USART0, owned; the receive ring is shared with its interrupt.
pub struct Usart0 {
    regs: USART0,
}

impl Usart0 {
    /// 115200 8N1, transmitter and receiver on, receive interrupt enabled,
    /// receive buffer emptied.
    pub fn new(regs: USART0) -> Self {
        // UCSR0B is not cleared first: simavr then drops UDRE0 for good.
        regs.ubrr0().write(|w| w.set(UBRR_115200_U2X));
        regs.ucsr0a().write(|w| w.u2x0().set_bit());
        regs.ucsr0c().write(|w| w.ucsz0().chr8());
        avr_device::interrupt::free(|cs| RX.borrow(cs).clear());
        regs.ucsr0b().write(|w| w.txen0().set_bit().rxen0().set_bit().rxcie0().set_bit());
        Self { regs }
    }

    /// Sends `b`, first waiting for the data register to be free (up to one
    /// frame, 85 µs).
    pub fn write_byte(&mut self, b: u8) {
        while self.regs.ucsr0a().read().udre0().bit_is_clear() {}
        self.regs.udr0().write(|w| w.set(b));
    }

    /// Waits until the last byte has left the shift register (before a reset
    /// or halt, so the final message is not cut): once UDRE0 is set the last
    /// byte is in the shift register, which needs at most one frame to empty.
    /// (TXC0 would say so exactly, but only if cleared before every byte, and
    /// simavr throttles polling while TXC0 is clear.)
    pub fn flush(&mut self) {
        if self.regs.ucsr0b().read().txen0().bit_is_clear() {
            return;
        }
        while self.regs.ucsr0a().read().udre0().bit_is_clear() {}
        super::delay_us(FRAME_US);
    }

    /// The oldest received byte, if any. Never blocks.
    pub fn read_byte(&mut self) -> Option<u8> {
        avr_device::interrupt::free(|cs| RX.borrow(cs).pop())
    }

    /// Bytes waiting in the receive buffer.
    pub fn rx_len(&self) -> usize {
        avr_device::interrupt::free(|cs| RX.borrow(cs).len())
    }

    /// Receive errors since the last call, clearing them.
    pub fn take_rx_errors(&mut self) -> RxErrors {
        avr_device::interrupt::free(|cs| {
            let r = RX.borrow(cs);
            let e = RxErrors { overflow: r.overflow.get(), framing: r.framing.get() };
            r.overflow.set(false);
            r.framing.set(false);
            e
        })
    }
}

impl ufmt::uWrite for Usart0 {
    type Error = core::convert::Infallible;

    fn write_str(&mut self, s: &str) -> Result<(), Self::Error> {
        for b in s.bytes() {
            self.write_byte(b);
        }
        Ok(())
    }
}

impl SerialPort for Usart0 {
    fn read_byte(&mut self) -> Option<u8> {
        Usart0::read_byte(self)
    }

    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.write_byte(b);
        }
    }
}

impl embedded_io::ErrorType for Usart0 {
    type Error = core::convert::Infallible;
}

/// Blocks until the first byte arrives (interrupts must be enabled: the
/// receive interrupt fills the ring), then takes what else the ring holds.
impl embedded_io::Read for Usart0 {
    fn read(&mut self, buf: &mut [u8]) -> Result<usize, Self::Error> {
        let mut n = 0;
        for slot in buf.iter_mut() {
            *slot = match Usart0::read_byte(self) {
                Some(b) => b,
                None if n == 0 => loop {
                    if let Some(b) = Usart0::read_byte(self) {
                        break b;
                    }
                },
                None => break,
            };
            n += 1;
        }
        Ok(n)
    }
}

impl embedded_io::ReadReady for Usart0 {
    fn read_ready(&mut self) -> Result<bool, Self::Error> {
        Ok(self.rx_len() > 0)
    }
}

/// Blocking, like [`Usart0::write_byte`]; `flush` waits until the last byte
/// has left the line.
impl embedded_io::Write for Usart0 {
    fn write(&mut self, buf: &[u8]) -> Result<usize, Self::Error> {
        for &b in buf {
            self.write_byte(b);
        }
        Ok(buf.len())
    }

    fn flush(&mut self) -> Result<(), Self::Error> {
        Usart0::flush(self);
        Ok(())
    }
}

fn receive(cs: CriticalSection<'_>) {
    // SAFETY: the ISR only reads UCSR0A and UDR0; `Usart0` never reads UDR0
    // and only reads/clears flags in UCSR0A that the ISR ignores. The status
    // must be read before the data (reading UDR0 pops the flags with it).
    let regs = unsafe { &*USART0::ptr() };
    let status = regs.ucsr0a().read();
    let frame_error = status.fe0().bit_is_set();
    let overrun = status.dor0().bit_is_set();
    let b = regs.udr0().read().bits();
    let ring = RX.borrow(cs);
    if overrun {
        ring.overflow.set(true);
    }
    if frame_error {
        ring.framing.set(true);
    } else {
        ring.push(b);
    }
}

// Private: avr-device exports the handler by its vector name and wraps it in a
// public function that no doc comment reaches; it is no API.
mod vector {
    // A byte arrived: into the ring, or a framing error noted.
    #[avr_device::interrupt(atmega2560)]
    fn USART0_RX() {
        avr_device::interrupt::free(super::receive);
    }
}
