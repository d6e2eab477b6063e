#![no_std]
#![no_main]

use avr_device::atmega2560 as pac;

#[avr_device::entry]
fn main() -> ! {
    let dp = pac::Peripherals::take().unwrap();
    let u = &dp.USART0;
    u.ubrr0().write(|w| w.set(16));
    u.ucsr0a().write(|w| w.u2x0().set_bit());
    u.ucsr0b().write(|w| w.txen0().set_bit().rxen0().set_bit());
    u.ucsr0c().write(|w| w.ucsz0().chr8());
    let x: f32 = core::hint::black_box(1.5f32);
    let y = touch_arm::real::Real::exp(x);
    for b in b"hello\n" { while u.ucsr0a().read().udre0().bit_is_clear() {} u.udr0().write(|w| w.set(*b)); }
    let v = (y * 1000.0) as u32;
    let _ = v;
    loop {}
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! { loop {} }
