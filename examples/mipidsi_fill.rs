//! mipidsi on the shield (feature `mipidsi`, `cargo avr-mipidsi`): mipidsi's
//! ILI9341 driver initialises the screen through [`ShieldBus`] as its
//! `Interface` (the firmware's landscape, BGR like the shields' panels),
//! clears it to blue
//! and fills a red 100×50 rectangle at (10, 20), then prints `done`. The
//! `mipidsi` simavr test checks the decoded screen.
#![no_std]
#![no_main]

use avr_device::atmega2560 as pac;
use embedded_graphics::draw_target::DrawTarget;
use embedded_graphics::geometry::{Point, Size};
use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use embedded_graphics::primitives::Rectangle;
use mipidsi::models::ILI9341Rgb565;
use mipidsi::options::{ColorOrder, Orientation, Rotation};
use touch_arm::board::fault::halt;
use touch_arm::board::shield::ShieldBus;
use touch_arm::board::usart::Usart0;
use touch_arm::board::{Delay, Fmt};
use ufmt::uwriteln;

#[avr_device::entry]
fn main() -> ! {
    let Some(dp) = pac::Peripherals::take() else { halt() };
    let mut serial = Usart0::new(dp.USART0);
    let mut bus = ShieldBus::new(dp.PORTE, dp.PORTF, dp.PORTG, dp.PORTH);
    let Ok(mut display) = mipidsi::Builder::new(ILI9341Rgb565, &mut bus)
        // The firmware's landscape (MADCTL MV|BGR = 0x28): mipidsi's 90° has
        // the columns reversed, which the flip undoes.
        .orientation(Orientation::new().rotate(Rotation::Deg90).flip_vertical())
        .color_order(ColorOrder::Bgr)
        .init(&mut Delay)
    else {
        halt()
    };
    let _ = display.clear(Rgb565::BLUE);
    let _ = display.fill_solid(&Rectangle::new(Point::new(10, 20), Size::new(100, 50)), Rgb565::RED);
    let _ = uwriteln!(Fmt(&mut serial), "done");
    let _ = embedded_io::Write::flush(&mut serial);
    halt()
}
