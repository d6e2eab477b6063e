//! On-chip check of the touch-screen UI: probes the display controller over
//! the shield bus (as the product does), initialises it and draws the fixed
//! script of `touch_arm::ui::demo` in the controller's layout, one step per
//! byte received on USART0, reporting `S <step> <cycles>` after each draw
//! (Timer1 at clk/256, so cycles are multiples of 256). The simavr tests
//! `ui_firmware` and `lcd_controllers` decode the bus and compare the
//! picture with the host rendering of the same script.
#![no_std]
#![no_main]

use core::mem::MaybeUninit;

use avr_device::atmega2560 as pac;
use touch_arm::board::fault::halt;
use touch_arm::board::lcd::{Lcd, Rotation};
use touch_arm::board::shield::ShieldBus;
use touch_arm::board::usart::Usart0;
use touch_arm::ui::controller::Controller;
use touch_arm::ui::demo::{self, Screen};
use touch_arm::ui::Ui;
use ufmt::uwriteln;

#[avr_device::entry]
fn main() -> ! {
    let Some(dp) = pac::Peripherals::take() else { halt() };
    // Timer1 free-running at 62.5 kHz: 16 µs ticks, 1.05 s range.
    dp.TC1.tccr1a().write(|w| unsafe { w.bits(0) });
    dp.TC1.tccr1b().write(|w| w.cs1().prescale_256());
    let tc1 = dp.TC1;
    let mut serial = Usart0::new(dp.USART0);
    let mut lcd = Lcd::new(ShieldBus::new(dp.PORTE, dp.PORTF, dp.PORTG, dp.PORTH));
    let t0 = tc1.tcnt1().read().bits();
    let (_, found) = lcd.start(Rotation::Landscape);
    let boot = tc1.tcnt1().read().bits().wrapping_sub(t0);
    let controller = found.unwrap_or(Controller::Ili9341);
    let layout = controller.layout();
    // In .bss, as the product's (inside its `App`): the stack figure the
    // simavr test reads is the drawing's, not the demo's own copy of the UI.
    // SAFETY: `main` runs once and never returns; this is the only
    // reference ever made to UI.
    let ui = unsafe { &mut *core::ptr::addr_of_mut!(UI) }.write(Ui::with_layout(&demo::CONFIG, layout));
    let _ = uwriteln!(serial, "lcd {} start {}", found.is_some() as u8, u32::from(boot) * 256);
    let _ = uwriteln!(serial, "ui-demo {}", demo::STEPS);
    for k in 0..demo::STEPS {
        wait_byte();
        let t0 = tc1.tcnt1().read().bits();
        let screen = demo::screen(k, &layout);
        let ok = match &screen {
            Screen::Main(m) => ui.draw(m, &mut lcd).is_ok(),
            Screen::Calibration(f) => ui.draw_calibration(f, &mut lcd).is_ok(),
        };
        let dt = tc1.tcnt1().read().bits().wrapping_sub(t0);
        let _ = uwriteln!(serial, "S {} {} {}", k, u32::from(dt) * 256, ok as u8);
    }
    let _ = uwriteln!(serial, "done");
    serial.flush();
    halt()
}

static mut UI: MaybeUninit<Ui> = MaybeUninit::uninit();

fn wait_byte() -> u8 {
    // SAFETY: only USART0's receive side is read; `Usart0` only transmits.
    let dp = unsafe { pac::Peripherals::steal() };
    while dp.USART0.ucsr0a().read().rxc0().bit_is_clear() {}
    dp.USART0.udr0().read().bits()
}
