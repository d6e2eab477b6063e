//! Panel probe: which of the known touch wirings (`TouchWiring::A/B/C`,
//! README "Which panel wiring?") this shield has, then raw panel readings.
//!
//! With nobody touching the screen, it runs the firmware's own wiring probe
//! (`touch::wiring::Probe` through [`ShieldBus::probe_step`]: every pair of
//! a digital panel candidate (D6..D9) and an analog one (A1..A3), the median
//! of three reads): the two ends of one plate (a few hundred ohms) read under
//! 20 counts, an open pair 1023. It prints each pair with its last read, then
//! every preset whose two plates are exactly the linked pairs. (b and c use
//! the same two plates with X and Y exchanged: both match such a shield, and
//! either works, since the touch calibration sets the axis swap and
//! directions; the firmware takes b.) Then it reads
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
use touch_arm::board::gpio::mega::{A1, A2, D6, D7, D8, D9};
use touch_arm::board::gpio::{self, Pin};
use touch_arm::board::shield::{ShieldBus, TouchWiring};
use touch_arm::board::usart::Usart0;
use touch_arm::board::{Delay, Fmt};
use touch_arm::seam::{RawSample, TouchPanel};
use touch_arm::t;
use touch_arm::text::Text;
use touch_arm::touch::filter::FilterConfig;
use touch_arm::touch::wiring::{pair_index, Probe, Wiring, READS_PER_PAIR};
use ufmt::uwriteln;

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
    let mut probe = Probe::new();
    let mut reads = 0;
    while let Some((d, s)) = probe.next() {
        let count = bus.plate_link(&mut adc, d, s).ok();
        probe.record(count);
        reads += 1;
        if reads % READS_PER_PAIR != 0 {
            continue;
        }
        let bit = pair_index(d, s).map_or(0, |i| 1u16 << i);
        let links = probe.links();
        let verdict = match () {
            _ if links.plate & bit != 0 => t!("plate"),
            _ if links.open & bit != 0 => t!("open"),
            _ => t!("unclear"),
        };
        match count {
            Some(c) => {
                let _ = uwriteln!(out, "link {} {} {} {}", name(d), name(s), c, verdict);
            }
            None => {
                let _ = uwriteln!(out, "link {} {} failed", name(d), name(s));
            }
        }
    }
    let mut found: Option<TouchWiring> = None;
    for w in Wiring::ALL {
        if probe.links().fit(w) {
            let _ = uwriteln!(out, "match {}", w.name());
            found = found.or(Some(TouchWiring::preset(w)));
        }
    }
    let Some(wiring) = found else {
        let _ = uwriteln!(out, "no known wiring matches");
        halt()
    };
    let _ = uwriteln!(out, "reading: touch the screen");
    let z_min = FilterConfig::DEFAULT.z_min;
    loop {
        let mut s = [RawSample { x: 0, y: 0, z: 0, z1: 0 }];
        if bus.touch(&mut adc, Some(&wiring)).read(&mut s).is_ok() && s[0].z >= z_min {
            let _ = uwriteln!(out, "raw {} {} {}", s[0].x, s[0].y, s[0].z);
            let _ = led.toggle();
        }
        delay.delay_ms(100);
    }
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
