//! Panel probe: which of the known touch wirings (`TouchWiring::A/B/C`,
//! README "Which panel wiring?") this shield has, then raw panel readings.
//!
//! With nobody touching the screen, it measures every pair of a digital
//! panel candidate (D6..D9) and an analog one (A1..A3): the two ends of one
//! plate (a few hundred ohms) read under 20 counts with the analog pin pulled
//! up and the digital one low, an open pair 1023
//! ([`ShieldBus::plate_link`]). It prints each pair, then every preset whose
//! two plates are exactly the linked pairs. (b and c use the same two plates
//! with X and Y exchanged: both match such a shield, and either works, since
//! the touch calibration sets the axis swap and directions.) Then it reads
//! the panel with the first match and prints `raw x y z` for every touch,
//! ten times a second, so pressing the corners shows the calibration values.
//! The on-board LED (D13) blinks with each reading.
//!
//! `cargo avr` builds it; `cargo avr-run --example panel-probe` flashes it
//! and opens the console.
#![no_std]
#![no_main]

use avr_device::atmega2560 as pac;
use embedded_hal::delay::DelayNs;
use embedded_hal::digital::StatefulOutputPin;
use touch_arm::board::adc::Adc;
use touch_arm::board::fault::halt;
use touch_arm::board::gpio::mega::{A1, A2, A3, D6, D7, D8, D9};
use touch_arm::board::gpio::{self, Pin};
use touch_arm::board::shield::{ShieldBus, TouchWiring};
use touch_arm::board::usart::Usart0;
use touch_arm::board::{Delay, Fmt};
use touch_arm::seam::{RawSample, TouchPanel};
use touch_arm::t;
use touch_arm::text::Text;
use touch_arm::touch::filter::FilterConfig;
use ufmt::uwriteln;

/// The presets' X+/Y− pins (driven low) and X−/Y+ pins (analog, sensed).
const DRIVES: [Pin; 4] = [D6, D7, D8, D9];
const SENSES: [Pin; 3] = [A1, A2, A3];
/// Below this a pair is one plate: a plate of up to ~10 kΩ against the
/// 20–50 kΩ pull-up; an open pair reads 1023.
const LINKED_BELOW: u16 = 256;

#[avr_device::entry]
fn main() -> ! {
    let Some(dp) = pac::Peripherals::take() else { halt() };
    let mut serial = Usart0::new(dp.USART0);
    let mut adc = Adc::new(dp.ADC);
    let mut bus = ShieldBus::new(dp.PORTE, dp.PORTF, dp.PORTG, dp.PORTH);
    // D13 = PB7: a port no driver owns, so its pins are embedded-hal pins.
    let [.., led] = gpio::split(dp.PORTB);
    let mut led = led.into_output(false);
    let mut delay = Delay;
    // SAFETY: the receive interrupt's ring is initialised by `Usart0::new`.
    unsafe { avr_device::interrupt::enable() };
    let mut out = Fmt(&mut serial);

    let _ = uwriteln!(out, "probe touch wiring: do not touch the screen");
    let mut linked = [[false; SENSES.len()]; DRIVES.len()];
    for (d, row) in DRIVES.iter().zip(linked.iter_mut()) {
        for (s, cell) in SENSES.iter().zip(row.iter_mut()) {
            match bus.plate_link(&mut adc, *d, *s) {
                Ok(count) => {
                    *cell = count < LINKED_BELOW;
                    let verdict = if *cell { t!("plate") } else { t!("open") };
                    let _ = uwriteln!(out, "link {} {} {} {}", name(*d), name(*s), count, verdict);
                }
                Err(_) => {
                    let _ = uwriteln!(out, "link {} {} failed", name(*d), name(*s));
                }
            }
        }
    }
    let mut found: Option<TouchWiring> = None;
    for (id, w) in TouchWiring::PRESETS {
        if matches(&linked, &w) {
            let _ = uwriteln!(out, "match {}", id);
            found = found.or(Some(w));
        }
    }
    let Some(wiring) = found else {
        let _ = uwriteln!(out, "no known wiring matches");
        halt()
    };
    let _ = uwriteln!(out, "reading: touch the screen");
    let z_min = FilterConfig::DEFAULT.z_min;
    loop {
        let mut s = [RawSample { x: 0, y: 0, z: 0 }];
        if bus.touch(&mut adc, &wiring).read(&mut s).is_ok() && s[0].z >= z_min {
            let _ = uwriteln!(out, "raw {} {} {}", s[0].x, s[0].y, s[0].z);
            let _ = led.toggle();
        }
        delay.delay_ms(100);
    }
}

/// True if the linked pairs are exactly the wiring's two plates (X+ to X−,
/// Y− to Y+).
fn matches(linked: &[[bool; SENSES.len()]; DRIVES.len()], w: &TouchWiring) -> bool {
    DRIVES.iter().zip(linked.iter()).all(|(d, row)| {
        SENSES.iter().zip(row.iter()).all(|(s, l)| {
            let plate = (*d == w.xp() && *s == w.xm()) || (*d == w.ym() && *s == w.yp());
            *l == plate
        })
    })
}

fn name(p: Pin) -> Text {
    match () {
        _ if p == D6 => t!("D6"),
        _ if p == D7 => t!("D7"),
        _ if p == D8 => t!("D8"),
        _ if p == D9 => t!("D9"),
        _ if p == A1 => t!("A1"),
        _ if p == A2 => t!("A2"),
        _ => t!("A3"),
    }
}
