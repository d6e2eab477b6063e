//! USART0 (D0/D1, the USB serial): 115200 baud 8N1, interrupt-driven both
//! ways through fixed rings, so neither direction blocks a frame (at 115200
//! baud a byte takes 87 µs; a 240-byte reply written byte by byte would hold
//! the frame for 21 ms).
//!
//! Nothing is lost silently (`seam::SerialPort`'s contract):
//! - receive: the interrupt keeps bytes in a [`RX_BUFFER`]-byte ring; when it
//!   is full it drops them until the reader has read everything kept before,
//!   and counts what the drop cost in lines (`protocol::rx_loss`), which the
//!   reader takes with `take_rx_loss`. A byte with a framing error or lost to
//!   a hardware overrun counts as dropped too. The one-byte STOP (`!`,
//!   `protocol::command::STOP_BYTE`) never enters the ring: the interrupt
//!   sets a flag the app takes in its next frame (`take_stop_byte`), ring full
//!   or not;
//! - transmit: `SerialPort::write` queues into a [`TX_BUFFER`]-byte ring and
//!   returns at once; the data-register-empty interrupt sends. The app checks
//!   `tx_room` before writing, so nothing is dropped; bytes beyond the room
//!   would be counted in [`Usart0::tx_dropped`]. Diagnostic text through
//!   `ufmt` (boot line, panic report, the bench) waits for room instead.
//!
//! The interrupts only run once interrupts are enabled globally; with them
//! off, writing text and [`Usart0::flush`] send by polling.

use core::cell::Cell;

use avr_device::atmega2560::USART0;
use avr_device::interrupt::{CriticalSection, Mutex};

use crate::protocol::command::STOP_BYTE;
use crate::protocol::rx_loss::{LossCounter, RX_BUFFER, TX_BUFFER};
use crate::seam::{RxLoss, SerialPort};

/// 16 MHz / (8 · (16 + 1)) = 117 647 baud with U2X: 2.1 % off 115200, the
/// setting every Arduino bootloader and USB bridge uses for this rate.
const UBRR_115200_U2X: u16 = 16;

/// One 10-bit frame at 117 647 baud is 85 µs.
const FRAME_US: u32 = 90;

/// A byte ring of `N` (a power of two) with a free-running `u16` head and
/// a fill count, shared between an interrupt and the main code.
/// Cells inside the interrupt mutex: no RefCell, so no borrow panic path.
struct Ring<const N: usize> {
    buf: [Cell<u8>; N],
    /// Next slot to write.
    head: Cell<u16>,
    /// Bytes held.
    len: Cell<u16>,
}

impl<const N: usize> Ring<N> {
    const MASK: usize = N - 1;

    const fn new() -> Self {
        Ring { buf: [const { Cell::new(0) }; N], head: Cell::new(0), len: Cell::new(0) }
    }

    #[inline(always)]
    fn len(&self) -> usize {
        usize::from(self.len.get())
    }

    #[inline(always)]
    fn room(&self) -> usize {
        N - self.len()
    }

    #[inline(always)]
    fn push(&self, b: u8) -> bool {
        if self.room() == 0 {
            return false;
        }
        let head = self.head.get();
        if let Some(slot) = self.buf.get(usize::from(head) & Self::MASK) {
            slot.set(b);
        }
        self.head.set(head.wrapping_add(1));
        self.len.set(self.len.get() + 1);
        true
    }

    #[inline(always)]
    fn pop(&self) -> Option<u8> {
        let len = self.len.get();
        if len == 0 {
            return None;
        }
        let tail = usize::from(self.head.get()).wrapping_sub(usize::from(len)) & Self::MASK;
        self.len.set(len - 1);
        self.buf.get(tail).map(Cell::get)
    }

    fn clear(&self) {
        self.len.set(0);
    }
}

const _: () = assert!(RX_BUFFER.is_power_of_two() && RX_BUFFER <= 1 << 15);
const _: () = assert!(TX_BUFFER.is_power_of_two() && TX_BUFFER <= 1 << 15);

/// The receive side: the ring, the line count of what it dropped and the
/// one-byte STOP's flag.
struct Rx {
    ring: Ring<RX_BUFFER>,
    loss: Cell<LossCounter>,
    stop: Cell<bool>,
}

/// The transmit side: the ring and the bytes `write` could not queue.
struct Tx {
    ring: Ring<TX_BUFFER>,
    dropped: Cell<u16>,
}

static RX: Mutex<Rx> =
    Mutex::new(Rx { ring: Ring::new(), loss: Cell::new(LossCounter::new()), stop: Cell::new(false) });
static TX: Mutex<Tx> = Mutex::new(Tx { ring: Ring::new(), dropped: Cell::new(0) });

/// USART0, owned; the receive ring is shared with its interrupt.
pub struct Usart0 {
    regs: USART0,
}

impl Usart0 {
    /// 115200 8N1, transmitter and receiver on, receive interrupt enabled,
    /// both rings emptied.
    pub fn new(regs: USART0) -> Self {
        // UCSR0B is not cleared first: simavr then drops UDRE0 for good.
        regs.ubrr0().write(|w| w.set(UBRR_115200_U2X));
        regs.ucsr0a().write(|w| w.u2x0().set_bit());
        regs.ucsr0c().write(|w| w.ucsz0().chr8());
        avr_device::interrupt::free(|cs| {
            let rx = RX.borrow(cs);
            rx.ring.clear();
            rx.loss.set(LossCounter::new());
            rx.stop.set(false);
            let tx = TX.borrow(cs);
            tx.ring.clear();
            tx.dropped.set(0);
        });
        regs.ucsr0b().write(|w| w.txen0().set_bit().rxen0().set_bit().rxcie0().set_bit());
        Self { regs }
    }

    /// Queues one byte, waiting for room (diagnostic text only: the app's
    /// output never waits). With interrupts off nothing drains the ring, so
    /// the byte (after whatever is queued) goes out by polling, as before
    /// there was a ring.
    pub fn write_byte(&mut self, b: u8) {
        if !avr_device::interrupt::is_enabled() {
            while self.send_polled() {}
            while self.regs.ucsr0a().read().udre0().bit_is_clear() {}
            self.regs.udr0().write(|w| w.set(b));
            return;
        }
        while !avr_device::interrupt::free(|cs| TX.borrow(cs).ring.push(b)) {}
        self.start_sending();
    }

    /// Waits until every queued byte has left the shift register (before a
    /// reset or halt, so the final message is not cut): once the ring is
    /// empty and UDRE0 is set the last byte is in the shift register, which
    /// needs at most one frame to empty. (TXC0 would say so exactly, but only
    /// if cleared before every byte, and simavr throttles polling while TXC0
    /// is clear.)
    pub fn flush(&mut self) {
        if self.regs.ucsr0b().read().txen0().bit_is_clear() {
            return;
        }
        if avr_device::interrupt::is_enabled() {
            while avr_device::interrupt::free(|cs| TX.borrow(cs).ring.len()) > 0 {}
        } else {
            while self.send_polled() {}
        }
        while self.regs.ucsr0a().read().udre0().bit_is_clear() {}
        super::delay_us(FRAME_US);
    }

    /// With interrupts off: the oldest queued byte into the data register
    /// once it is free; false when nothing is queued.
    fn send_polled(&mut self) -> bool {
        let Some(b) = avr_device::interrupt::free(|cs| TX.borrow(cs).ring.pop()) else {
            return false;
        };
        while self.regs.ucsr0a().read().udre0().bit_is_clear() {}
        self.regs.udr0().write(|w| w.set(b));
        true
    }

    /// Lets the data-register-empty interrupt send what is queued.
    fn start_sending(&mut self) {
        self.regs.ucsr0b().modify(|_, w| w.udrie0().set_bit());
    }

    /// Bytes [`SerialPort::write`] dropped for want of room since power-up
    /// (0 unless a caller ignored `tx_room`).
    pub fn tx_dropped(&self) -> u16 {
        avr_device::interrupt::free(|cs| TX.borrow(cs).dropped.get())
    }

    /// The oldest received byte, if any. Never blocks.
    pub fn read_byte(&mut self) -> Option<u8> {
        avr_device::interrupt::free(|cs| RX.borrow(cs).ring.pop())
    }

    /// Bytes waiting in the receive buffer.
    pub fn rx_len(&self) -> usize {
        avr_device::interrupt::free(|cs| RX.borrow(cs).ring.len())
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

    fn take_rx_loss(&mut self) -> Option<RxLoss> {
        avr_device::interrupt::free(|cs| {
            let rx = RX.borrow(cs);
            // Only where the reader has reached the loss: everything kept
            // before it is read.
            if rx.ring.len() > 0 {
                return None;
            }
            let mut loss = rx.loss.get();
            let taken = loss.take();
            rx.loss.set(loss);
            taken
        })
    }

    fn take_stop_byte(&mut self) -> bool {
        avr_device::interrupt::free(|cs| RX.borrow(cs).stop.replace(false))
    }

    fn tx_room(&self) -> usize {
        avr_device::interrupt::free(|cs| TX.borrow(cs).ring.room())
    }

    fn write(&mut self, bytes: &[u8]) {
        // Sixteen bytes per critical section: a few hundred cycles with
        // interrupts off, well inside the receiver's two-byte buffer (170 µs).
        for chunk in bytes.chunks(16) {
            avr_device::interrupt::free(|cs| {
                let tx = TX.borrow(cs);
                for &b in chunk {
                    if !tx.ring.push(b) {
                        tx.dropped.set(tx.dropped.get().saturating_add(1));
                    }
                }
            });
        }
        self.start_sending();
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
    // and only reads flags in UCSR0A. The status must be read before the data
    // (reading UDR0 pops the flags with it).
    let regs = unsafe { &*USART0::ptr() };
    let status = regs.ucsr0a().read();
    let frame_error = status.fe0().bit_is_set();
    let overrun = status.dor0().bit_is_set();
    let b = regs.udr0().read().bits();
    let rx = RX.borrow(cs);
    if b == STOP_BYTE && !frame_error && !overrun {
        // Not line data: it bypasses the ring and the loss count, so it acts
        // even behind a full ring or mid-line. (First and alone: this keeps
        // the handler's frame, which every stack chain can meet, as small as
        // it was; after an overrun the path below counts the loss first.)
        rx.stop.set(true);
        return;
    }
    let mut loss = rx.loss.get();
    if overrun {
        // Bytes the hardware lost before this one: their values are gone, so
        // they count as one damaged line byte.
        loss.byte(0, false);
    }
    if b == STOP_BYTE && !frame_error {
        rx.stop.set(true);
    } else {
        let kept = !frame_error && !loss.is_open() && rx.ring.push(b);
        loss.byte(b, kept);
    }
    rx.loss.set(loss);
}

fn send(cs: CriticalSection<'_>) {
    // SAFETY: the ISR writes UDR0 and clears UDRIE0 when there is nothing
    // left; `Usart0` writes UDR0 only with interrupts off (`send_polled`) and
    // sets UDRIE0 inside no critical section that this ISR could split (a
    // read-modify-write of UCSR0B racing this clear at worst leaves UDRIE0
    // set with an empty ring, which the next interrupt clears).
    let regs = unsafe { &*USART0::ptr() };
    match TX.borrow(cs).ring.pop() {
        Some(b) => {
            regs.udr0().write(|w| w.set(b));
        }
        None => {
            regs.ucsr0b().modify(|_, w| w.udrie0().clear_bit());
        }
    }
}

// Private: avr-device exports each handler by its vector name and wraps it
// in a public function that no doc comment reaches; they are no API.
mod vector {
    use avr_device::interrupt::CriticalSection;

    // A byte arrived: into the ring, or a loss counted.
    #[avr_device::interrupt(atmega2560)]
    fn USART0_RX() {
        // SAFETY: an interrupt handler runs with interrupts disabled (no
        // nesting here), which is what a critical section guarantees.
        super::receive(unsafe { CriticalSection::new() });
    }

    // The data register is free: the next queued byte, if any.
    #[avr_device::interrupt(atmega2560)]
    fn USART0_UDRE() {
        // SAFETY: as in USART0_RX.
        super::send(unsafe { CriticalSection::new() });
    }
}
