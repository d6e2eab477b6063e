//! touch-arm firmware for the Arduino Mega 2560 (ATmega2560, 16 MHz).
//!
//! Foundation stage: runs a fixed 3-joint ζ-a-tₛ demo move in f32 at 50 Hz frame
//! times, aligned with the Timer5 servo PWM period, and reports each frame on
//! USART0 (115200 8N1) as fixed-point integers. Servo outputs stay disconnected:
//! nothing moves until the app commands a pose.
//!
//! Frame line: `F <k> <t_us> <q_base> <q_shoulder> <q_elbow> <v_base> <v_shoulder> <v_elbow> <eval_cycles>`
//! with angles in µrad and velocities in µrad/s.
#![no_std]
#![no_main]

use avr_device::atmega2560 as pac;
use touch_arm::board::servo_pwm::{ServoPwm, TickLimits, CHANNELS};
use touch_arm::board::usart::Usart0;
use touch_arm::plan::{MultiPlan, JOINTS};
use touch_arm::zat::{smooth_stop_a, ShapeParams};
use ufmt::uwriteln;

/// 50 Hz: one frame per servo PWM period.
const FRAME_US: u32 = 20_000;
/// Timer5 runs at 2 MHz: 8 CPU cycles per tick.
const CYCLES_PER_TICK: u32 = 8;

/// The demo move: home pose to a reachable target, in radians.
const DEMO_START: [f32; JOINTS] = [1.570_796_3, 0.785_398_2, 1.570_796_3];
const DEMO_TARGET: [f32; JOINTS] = [0.785_398_2, 0.2, 2.2];
const DEMO_TS: f32 = 2.0;
const DEMO_N: f32 = 2.0;

#[avr_device::entry]
fn main() -> ! {
    // `take` only fails on a second call; there is none.
    let Some(dp) = pac::Peripherals::take() else { halt() };
    let mut serial = Usart0::new(dp.USART0);
    // Outputs stay disconnected: the demo only computes.
    let limits = [TickLimits { min: 1000, max: 5000 }; CHANNELS];
    let mut pwm = ServoPwm::new(dp.TC5, &dp.PORTL, &limits);

    let _ = uwriteln!(serial, "touch-arm {} demo", env!("CARGO_PKG_VERSION"));
    let a = match smooth_stop_a(DEMO_TS, DEMO_N) {
        Some(a) => a,
        None => {
            let _ = uwriteln!(serial, "err demo shape has no smooth stop");
            halt()
        }
    };
    let shape = ShapeParams { ts: DEMO_TS, a, n: DEMO_N };
    let plan = match MultiPlan::new(&DEMO_START, &DEMO_TARGET, &shape) {
        Ok(p) => p,
        Err(_) => {
            let _ = uwriteln!(serial, "err demo plan rejected");
            halt()
        }
    };
    let _ = uwriteln!(serial, "P {} {} {}", micro(DEMO_TS), micro(a), micro(DEMO_N));

    let frames = (DEMO_TS * 50.0) as u32 + 2;
    let mut k: u32 = 0;
    while k <= frames {
        while !pwm.period_started() {}
        let t_us = k * FRAME_US;
        let c0 = pwm.counter();
        let s = plan.sample(t_us as f32 * 1e-6);
        let c1 = pwm.counter();
        let cycles = u32::from(c1.wrapping_sub(c0)) * CYCLES_PER_TICK;
        let _ = uwriteln!(
            serial,
            "F {} {} {} {} {} {} {} {} {}",
            k,
            t_us,
            micro(s[0].pos),
            micro(s[1].pos),
            micro(s[2].pos),
            micro(s[0].vel),
            micro(s[1].vel),
            micro(s[2].vel),
            cycles
        );
        k += 1;
    }
    let _ = uwriteln!(serial, "done");
    serial.flush();
    halt()
}

/// Value × 10⁶ rounded to the nearest integer (saturating).
fn micro(v: f32) -> i32 {
    let x = v * 1e6;
    (if x >= 0.0 { x + 0.5 } else { x - 0.5 }) as i32
}

/// Stops for good: interrupts off, servo outputs disconnected, CPU asleep.
fn halt() -> ! {
    avr_device::interrupt::disable();
    // SAFETY: single-threaded; we are abandoning normal operation and only
    // disconnect the Timer5 compare outputs.
    let dp = unsafe { pac::Peripherals::steal() };
    dp.TC5.tccr5a().write(|w| w.com5a().disconnected().com5b().disconnected().com5c().disconnected());
    // Sleep enabled with interrupts off: the CPU stops here (and simavr ends
    // the run instead of spinning).
    dp.CPU.smcr().write(|w| w.se().set_bit());
    loop {
        avr_device::asm::sleep();
    }
}

#[panic_handler]
fn panic(info: &core::panic::PanicInfo) -> ! {
    avr_device::interrupt::disable();
    // SAFETY: the app is dead; reclaim USART0 to say where.
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
