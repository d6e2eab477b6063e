//! A soak of the real firmware ELF in simavr (issue #11): seeded random
//! serial lines (valid and garbage, some in floods at full baud) and touches
//! (map, buttons, anywhere on the glass, with noise), ≥ 10⁴ inputs, and a few
//! watchdog resets provoked on purpose. Checked throughout:
//! - every servo pulse measured on PL3/PL4/PL5 lies within the configured
//!   pulse limits (the soak changes offsets, scales, angle limits and speeds,
//!   never `min_us`/`max_us`, so the limits stay 600..2400 µs);
//! - every non-empty line gets exactly one reply (`random_input::replies_in`);
//! - the chip resets only when the soak provokes it, and never panics.
//!
//! `TOUCH_ARM_SOAK_INPUTS=<n>` and `TOUCH_ARM_SOAK_SEED=<s>` change the run.

use hal_sim::random_input::{replies_in, Inputs};
use touch_arm_rig::avr::RxPacing;
use touch_arm_rig::firmware::{self, Session};
use touch_arm_rig::panel::PanelWiring;

/// The default pulse limits (`JointCal::DEFAULTS`), with the harness's
/// edge-stamp jitter (≤ 4 cycles = 0.25 µs).
const PULSE_MIN_US: f64 = 600.0 - 0.25;
const PULSE_MAX_US: f64 = 2400.0 + 0.25;
const FRAME_CYCLES: u64 = 320_000;

fn env(name: &str, default: u64) -> u64 {
    std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

struct Soak {
    s: Session,
    sent: u64,
    /// Replies counted in the output up to `read`.
    replies: u64,
    read: usize,
    pulses_checked: u64,
    /// Pulses already checked, per joint.
    seen: [usize; 3],
    provoked: u32,
}

impl Soak {
    /// Replies so far (complete output lines only).
    fn answered(&mut self) -> u64 {
        let out = self.s.avr.uart_output();
        if let Some(end) = out[self.read..].iter().rposition(|&b| b == b'\n') {
            let new = &out[self.read..self.read + end + 1];
            self.replies += String::from_utf8_lossy(new).lines().map(|l| replies_in(l.trim_end())).sum::<u64>();
            self.read += end + 1;
        }
        self.replies
    }

    /// Runs `frames` frames and checks every new pulse.
    fn run(&mut self, frames: u64) {
        self.s.avr.run_cycles(frames * FRAME_CYCLES).unwrap_or_else(|e| panic!("firmware stopped: {e}"));
        let trains = self.s.pulses();
        for (j, train) in trains.iter().enumerate() {
            for &(t, w) in &train[self.seen[j].min(train.len())..] {
                assert!(
                    (PULSE_MIN_US..=PULSE_MAX_US).contains(&w),
                    "joint {j}: a {w} µs pulse at {t:.3} s, outside 600..2400 µs"
                );
                self.pulses_checked += 1;
            }
            self.seen[j] = train.len();
        }
    }

    /// Runs until every line sent is answered (at most 30 s).
    fn drain(&mut self) {
        for _ in 0..1500 {
            if self.answered() >= self.sent && self.s.avr.uart_rx_pending() == 0 {
                break;
            }
            self.run(1);
        }
        let answered = self.answered();
        assert_eq!(answered, self.sent, "lines answered");
    }

    /// Stops Timer5's clock: the frame loop waits for a period that never
    /// comes, nothing feeds the watchdog, and it resets the chip.
    fn provoke_watchdog_reset(&mut self) {
        self.drain();
        let resets = self.s.avr.resets();
        self.s.avr.write_io(0x121, 0).unwrap();
        self.s
            .avr
            .run_until(|a| a.resets() > resets, firmware::CPU_HZ as u64)
            .expect("the watchdog resets a hung frame loop within 1 s");
        self.provoked += 1;
        // Boot, configuration, homing.
        self.run(75);
    }
}

#[test]
fn the_firmware_survives_ten_thousand_random_inputs() {
    let inputs = env("TOUCH_ARM_SOAK_INPUTS", 10_000);
    let seed = env("TOUCH_ARM_SOAK_SEED", 5);
    let mut s = Session::start(&firmware::default_elf(), PanelWiring::A, seed).expect("firmware ELF (cargo avr)");
    s.avr.set_uart_rx_pacing(RxPacing::LineRate);
    let mut soak = Soak { s, sent: 0, replies: 0, read: 0, pulses_checked: 0, seen: [0; 3], provoked: 0 };
    soak.run(75);
    let mut gen = Inputs::new(seed);
    let (mut lines, mut touches, mut floods) = (0u64, 0u64, 0u64);
    let mut k = 0;
    while k < inputs {
        match gen.rng.below(100) {
            0..=59 => {
                // A few lines at once, answered before the next ones.
                for _ in 0..1 + gen.rng.below(4) {
                    let l = loop {
                        let l = gen.line();
                        let text = String::from_utf8_lossy(&l.bytes);
                        if !text.contains("min_us") && !text.contains("max_us") {
                            break l;
                        }
                    };
                    soak.s.avr.uart_send(&l.bytes);
                    soak.sent += u64::from(l.answered);
                    lines += 1;
                    k += 1;
                }
                soak.drain();
            }
            60..=61 => {
                // A flood: more than the receive buffer holds.
                floods += 1;
                for _ in 0..20 + gen.rng.below(20) {
                    let l = gen.line();
                    if String::from_utf8_lossy(&l.bytes).contains("_us") {
                        continue;
                    }
                    soak.s.avr.uart_send(&l.bytes);
                    soak.sent += u64::from(l.answered);
                    lines += 1;
                    k += 1;
                }
                soak.drain();
            }
            62 if soak.provoked < 3 && k > inputs / 4 => soak.provoke_watchdog_reset(),
            _ => {
                let (x, y, force, frames) = gen.touch();
                let noisy = gen.rng.below(4) == 0;
                soak.s.set_noise(if noisy { 4.0 } else { 0.0 }, if noisy { 0.02 } else { 0.0 });
                let _ = force;
                soak.s.press_raw(x, y).unwrap();
                soak.run(3 + frames.min(8));
                soak.s.release();
                soak.run(2);
                touches += 1;
                k += 1;
            }
        }
    }
    soak.drain();
    let out = soak.s.avr.uart_output_string();
    assert!(!out.contains("PANIC"), "the firmware panicked");
    assert_eq!(soak.s.avr.resets(), soak.provoked, "resets other than the provoked watchdog ones");
    assert_eq!(out.matches("info reset watchdog ").count() as u32, soak.provoked);
    eprintln!(
        "soak: {lines} lines ({} to answer, all answered; {floods} floods), {touches} touches, {} watchdog resets provoked, {} pulses checked, {:.0} s simulated",
        soak.sent,
        soak.provoked,
        soak.pulses_checked,
        soak.s.avr.time_s()
    );
    assert!(lines + touches >= inputs && soak.pulses_checked > 3 * inputs);
}
