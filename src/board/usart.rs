//! USART0 (D0/D1, the USB serial): 115200 baud 8N1, blocking transmit.

use avr_device::atmega2560::USART0;

/// 16 MHz / (8 · (16 + 1)) = 117 647 baud with U2X: 2.1 % off 115200, the
/// setting every Arduino bootloader and USB bridge uses for this rate.
const UBRR_115200_U2X: u16 = 16;

pub struct Usart0 {
    regs: USART0,
}

impl Usart0 {
    pub fn new(regs: USART0) -> Self {
        regs.ubrr0().write(|w| w.set(UBRR_115200_U2X));
        regs.ucsr0a().write(|w| w.u2x0().set_bit());
        regs.ucsr0c().write(|w| w.ucsz0().chr8());
        regs.ucsr0b().write(|w| w.txen0().set_bit().rxen0().set_bit());
        Self { regs }
    }

    pub fn write_byte(&mut self, b: u8) {
        while self.regs.ucsr0a().read().udre0().bit_is_clear() {}
        self.regs.udr0().write(|w| w.set(b));
    }

    /// Waits until the last byte has left the shift register (before a reset
    /// or halt, so the final message is not cut).
    pub fn flush(&mut self) {
        if self.regs.ucsr0b().read().txen0().bit_is_set() {
            while self.regs.ucsr0a().read().udre0().bit_is_clear() {}
        }
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
