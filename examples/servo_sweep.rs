//! Servo sweep: checks a servo's range against its configured pulse window.
//!
//! It loads the calibration from the EEPROM as the firmware does (defaults
//! when none is stored) and sweeps one joint's servo from the middle of its
//! window (`min_us..max_us`) to one end, to the other, and so on, at
//! 1000 µs/s. Watch whether the servo follows over the whole sweep: a servo
//! that stops short or hums against its stop at an end needs a narrower
//! window (`cal set <joint> min_us|max_us ...` in the firmware). Timer5's
//! clamp (`ServoPwm`) holds every pulse inside the window, whatever the
//! sweep commands.
//!
//! Prints `window <joint> <min_us> <max_us> <stored|defaults>` when a sweep
//! starts and `end <joint> <us>` at each turn. Keys on the console: `0`, `1`,
//! `2` sweep base, shoulder, elbow (the joint left holds its last pulse);
//! `3` the gripper on D11 (Timer1, started with Timer5: its pulses start
//! with the joints'), over the servo range (`window grip 500 2500
//! servo-range`: it has no calibration yet); space pauses and resumes. Only
//! the swept servos get pulses: the others stay limp.
//!
//! Run it with the arm free to move (or the servo off the arm).
//! `cargo avr` builds it; `cargo avr-run --example servo-sweep` flashes it
//! and opens the console.
#![no_std]
#![no_main]

use avr_device::atmega2560 as pac;
use embedded_hal::delay::DelayNs;
use embedded_hal::pwm::SetDutyCycle;
use embedded_io::{Read, ReadReady};
use touch_arm::board::eeprom::Eeprom;
use touch_arm::board::fault::halt;
use touch_arm::board::servo_pwm::{ServoPwm, TickLimits, GRIP_CHANNEL};
use touch_arm::board::usart::Usart0;
use touch_arm::board::{Delay, Fmt};
use touch_arm::config::store::{self, Source};
use touch_arm::servo::map::Joint;
use touch_arm::t;
use ufmt::uwriteln;

/// Ticks (0.5 µs) per 20 ms step: 1000 µs/s.
const STEP: u16 = 40;
const STEP_MS: u32 = 20;

#[avr_device::entry]
fn main() -> ! {
    let Some(dp) = pac::Peripherals::take() else { halt() };
    let mut serial = Usart0::new(dp.USART0);
    let loaded = store::load(&mut Eeprom::new(dp.EEPROM));
    let source = if loaded.source == Source::Defaults { t!("defaults") } else { t!("stored") };
    let limits = loaded.config.joints.map(|j| TickLimits::of_joint(&j));
    let mut pwm = ServoPwm::new(dp.TC5, dp.TC1, &dp.PORTL, &dp.PORTB, &limits);
    // SAFETY: the receive interrupt's ring is initialised by `Usart0::new`.
    unsafe { avr_device::interrupt::enable() };
    let mut delay = Delay;

    let mut ch = Joint::Base.index();
    let mut sweep = Sweep::start(&pwm, ch);
    let _ = uwriteln!(Fmt(&mut serial), "window {} {} {} {}", name(ch), sweep.lim.min / 2, sweep.lim.max / 2, source);
    let mut paused = false;
    loop {
        let mut key = [0u8];
        if serial.read_ready() == Ok(true) && serial.read(&mut key) == Ok(1) {
            match key[0] {
                b'0'..=b'3' => {
                    ch = usize::from(key[0] - b'0');
                    sweep = Sweep::start(&pwm, ch);
                    paused = false;
                    let (min, max) = (sweep.lim.min / 2, sweep.lim.max / 2);
                    let from = if ch == GRIP_CHANNEL { t!("servo-range") } else { source };
                    let _ = uwriteln!(Fmt(&mut serial), "window {} {} {} {}", name(ch), min, max, from);
                }
                b' ' => paused = !paused,
                _ => {}
            }
        }
        if !paused {
            if sweep.advance() {
                let _ = uwriteln!(Fmt(&mut serial), "end {} {}", name(ch), sweep.pos / 2);
            }
            if let Some(mut out) = pwm.channel(ch) {
                let _ = out.set_duty_cycle(sweep.pos);
            }
        }
        delay.delay_ms(STEP_MS);
    }
}

/// A channel's name: the joint's, or `grip`.
fn name(ch: usize) -> touch_arm::text::Text {
    match Joint::ALL.get(ch) {
        Some(j) => j.name(),
        None => t!("grip"),
    }
}

/// A triangle wave over one channel's window, in ticks.
struct Sweep {
    lim: TickLimits,
    pos: u16,
    up: bool,
}

impl Sweep {
    /// From the middle of channel `ch`'s window, upwards.
    fn start(pwm: &ServoPwm, ch: usize) -> Sweep {
        let lim = pwm.limits(ch).unwrap_or(TickLimits { min: 0, max: 0 });
        Sweep { lim, pos: lim.min + (lim.max - lim.min) / 2, up: true }
    }

    /// One step; true when it reached an end (and turned).
    fn advance(&mut self) -> bool {
        let (lo, hi) = (self.lim.min, self.lim.max);
        let next = if self.up { self.pos.saturating_add(STEP).min(hi) } else { self.pos.saturating_sub(STEP).max(lo) };
        self.pos = next;
        let end = if self.up { next == hi } else { next == lo };
        if end {
            self.up = !self.up;
        }
        end
    }
}
