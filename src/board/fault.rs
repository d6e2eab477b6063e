//! The end of the line for every firmware on this board: stop safely, and
//! say why over USART0 when a panic brought us here.

use avr_device::atmega2560 as pac;
use ufmt::uwriteln;

use super::usart::Usart0;

/// Stops for good: interrupts off, servo outputs disconnected (pins low, the
/// servos go limp rather than hold a stale command), CPU asleep. An enabled
/// watchdog still resets the chip into its power-up state; under simavr the
/// sleep with interrupts off ends the run.
pub fn halt() -> ! {
    avr_device::interrupt::disable();
    // SAFETY: normal operation is abandoned; only the Timer5 and Timer1 compare outputs
    // and the sleep control are touched.
    let dp = unsafe { pac::Peripherals::steal() };
    dp.TC5.tccr5a().write(|w| w.com5a().disconnected().com5b().disconnected().com5c().disconnected());
    // The gripper's OC1A too (it kept pulsing before issue #21).
    dp.TC1.tccr1a().write(|w| w.com1a().disconnected().com1b().disconnected().com1c().disconnected());
    // The servos go limp: a reset after this must not command the pulses
    // they had (`board::resume`).
    super::resume::forget();
    dp.CPU.smcr().write(|w| w.se().set_bit());
    loop {
        avr_device::asm::sleep();
    }
}

/// One panic handler for every binary: reports the location, then halts.
#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    avr_device::interrupt::disable();
    // SAFETY: whatever owned USART0 is dead; reclaim it to say where.
    let dp = unsafe { pac::Peripherals::steal() };
    let mut serial = Usart0::new(dp.USART0);
    match info.location() {
        Some(l) => {
            let _ = uwriteln!(serial, "PANIC {}:{}", l.file(), l.line());
        }
        None => {
            let _ = uwriteln!(serial, "PANIC");
        }
    }
    serial.flush();
    halt()
}
