//! The project's own random testing (issue #11): the app in the host twin,
//! driven by seeded random input — touches with noise and glitches, serial
//! lines valid and garbage, floods, EEPROM corruption and power loss during
//! saves, reboots, a clock about to wrap — and checked after every frame
//! against the README's promises:
//! - every pulse lies inside the configured pulse and angle limits;
//! - no servo pulse changes faster than its joint's max speed allows;
//! - while STOP stays latched the pulses do not change;
//! - every non-empty line gets exactly one reply (`random_input::replies_in`),
//!   and the app never writes more than the port has room for;
//! - no panic (the test profile checks integer overflow).
//!
//! `cargo test -p hal-sim --test random_inputs` runs a short run (two seeds,
//! with and without the touch screen). The long run is
//! `cargo test -p hal-sim --test random_inputs -- --ignored --nocapture`
//! (10⁶ inputs, in the test profile so integer overflow is checked;
//! `TOUCH_ARM_RANDOM_INPUTS=<n>` and `TOUCH_ARM_RANDOM_SEED=<s>` change it);
//! its figures are in BENCHMARKS.md.

use hal_sim::random_input::{replies_in, Inputs};
use hal_sim::{Sim, SimSetup};
use touch_arm::app::{State, FRAME_S};
use touch_arm::config::settings::Config;
use touch_arm::config::store::{RECORD_LEN, SLOT_B_ADDR};

/// What a run did.
#[derive(Debug, Default)]
struct Tally {
    inputs: u64,
    frames: u64,
    lines: u64,
    replies: u64,
    lost_lines: u64,
    touches: u64,
    floods: u64,
    eeprom_faults: u64,
    reboots: u64,
    moves: u64,
    frames_stopped: u64,
    max_step_share: f64,
}

/// The pulse window of joint `j` (angle and pulse limits), widened by the
/// 1 µs of rounding.
fn window(c: &Config, j: usize) -> (f64, f64) {
    cal_window(&c.joints[j])
}

/// [`window`] of one calibration (a joint's or the gripper's).
fn cal_window(k: &touch_arm::servo::map::JointCal) -> (f64, f64) {
    let (a, b) = (
        k.offset_us as f64 + k.us_per_rad as f64 * k.min_rad as f64,
        k.offset_us as f64 + k.us_per_rad as f64 * k.max_rad as f64,
    );
    ((k.min_us as f64).max(a.min(b)) - 1.0, (k.max_us as f64).min(a.max(b)) + 1.0)
}

struct Run {
    sim: Sim,
    gen: Inputs,
    t: Tally,
    /// Lines sent that must be answered, lines answered.
    sent: u64,
    answered: u64,
    prev_pulses: Option<[u16; 3]>,
    prev_grip: Option<u16>,
    prev_state: State,
}

impl Run {
    fn new(seed: u64, screen: bool) -> Run {
        let mut setup = SimSetup { seed, ..SimSetup::default() };
        setup.params.screen = screen;
        let mut sim = Sim::new(&setup).unwrap();
        // 10 s before the millisecond clock wraps.
        sim.clock.ms = u32::MAX - 10_000;
        Run {
            sim,
            gen: Inputs::new(seed ^ 0x5eed),
            t: Tally::default(),
            sent: 0,
            answered: 0,
            prev_pulses: None,
            prev_grip: None,
            prev_state: State::Off,
        }
    }

    /// One frame and every check.
    fn frame(&mut self) {
        self.sim.step();
        self.t.frames += 1;
        // Keep memory flat over millions of frames.
        self.sim.history.clear();
        self.sim.servos.history.clear();
        if let Some(end) = self.sim.serial.output.iter().rposition(|&b| b == b'\n') {
            let out: Vec<u8> = self.sim.serial.output.drain(..=end).collect();
            for l in String::from_utf8_lossy(&out).split('\n') {
                let l = l.trim_end_matches('\r');
                let n = replies_in(l);
                self.answered += n;
                if l.starts_with("err input lost") {
                    self.t.lost_lines += n;
                }
                if l.starts_with("ok move") || l.starts_with("ok goto") || l.starts_with("info touch") {
                    self.t.moves += 1;
                }
            }
        }
        let ctx = || format!("frame {}", self.t.frames);
        assert!(self.answered <= self.sent, "{}: {} replies to {} lines", ctx(), self.answered, self.sent);
        assert_eq!(self.sim.serial.tx_overflow, 0, "{}: the app wrote past the port's room", ctx());
        let st = self.sim.app.status();
        let cfg = *self.sim.app.config();
        let pulses = self.sim.servos.pulses();
        if let Some(p) = pulses {
            for (j, &pulse) in p.iter().enumerate() {
                let (lo, hi) = window(&cfg, j);
                // The servos get Timer5 ticks of 0.5 µs.
                let us = f64::from(pulse) * 0.5;
                assert!(us >= lo && us <= hi, "{}: joint {j} pulse {us} outside [{lo}, {hi}] ({cfg:?})", ctx());
            }
            if let Some(q) = self.prev_pulses {
                for j in 0..3 {
                    let k = &cfg.joints[j];
                    let step = (f64::from(p[j]) - f64::from(q[j])).abs() * 0.5;
                    let max = k.max_speed_rad_s as f64 * (k.us_per_rad as f64).abs() * FRAME_S as f64;
                    assert!(step <= max + 1.0, "{}: joint {j} pulse stepped {step} us > {max:.2} + 1", ctx());
                    self.t.max_step_share = self.t.max_step_share.max((step - 1.0).max(0.0) / max);
                }
                if st.state == State::Stopped && self.prev_state == State::Stopped {
                    assert_eq!(p, q, "{}: pulses changed while stopped", ctx());
                }
            }
        }
        // The gripper: inside its window, no faster than its speed limit,
        // frozen while stopped.
        let grip = self.sim.servos.grip_pulse();
        if let Some(g) = grip {
            let k = *self.sim.app.grip_cal();
            let (lo, hi) = cal_window(&k);
            let us = f64::from(g) * 0.5;
            assert!(us >= lo && us <= hi, "{}: gripper pulse {us} outside [{lo}, {hi}] ({k:?})", ctx());
            if let Some(q) = self.prev_grip {
                let step = (f64::from(g) - f64::from(q)).abs() * 0.5;
                let max = k.max_speed_rad_s as f64 * (k.us_per_rad as f64).abs() * FRAME_S as f64;
                assert!(step <= max + 1.0, "{}: gripper pulse stepped {step} us > {max:.2} + 1", ctx());
                if st.state == State::Stopped && self.prev_state == State::Stopped {
                    assert_eq!(g, q, "{}: the gripper moved while stopped", ctx());
                }
            }
        }
        if st.state == State::Stopped {
            self.t.frames_stopped += 1;
        }
        self.prev_grip = grip;
        self.prev_pulses = pulses;
        self.prev_state = st.state;
    }

    fn frames(&mut self, n: u64) {
        for _ in 0..n {
            self.frame();
        }
    }

    fn send(&mut self, bytes: &[u8], answered: bool) {
        self.sim.serial.send(bytes);
        self.sent += u64::from(answered);
        self.t.lines += 1;
    }

    /// Runs until every line sent has its reply (at most 60 s).
    fn drain(&mut self) {
        for _ in 0..3000 {
            if self.answered == self.sent && self.sim.serial.input.is_empty() {
                return;
            }
            self.frame();
        }
        panic!("{} lines sent, {} answered after 60 s (frame {})", self.sent, self.answered, self.t.frames);
    }

    fn input(&mut self) {
        self.t.inputs += 1;
        let g = &mut self.gen;
        match g.rng.below(100) {
            0..=29 => {
                let l = g.line();
                self.send(&l.bytes, l.answered);
                let n = self.gen.rng.below(4);
                self.frames(n);
            }
            30 => {
                // A flood: many lines at once, more than a frame brings.
                self.t.floods += 1;
                for _ in 0..10 + self.gen.rng.below(30) {
                    let l = self.gen.line();
                    self.send(&l.bytes, l.answered);
                }
            }
            31..=57 => {
                self.t.touches += 1;
                let (x, y, force, frames) = g.touch();
                let (noise, spikes) =
                    if g.rng.below(4) == 0 { (g.rng.uniform() * 6.0, g.rng.uniform() * 0.05) } else { (0.0, 0.0) };
                let p = &mut self.sim.panel;
                p.noise_counts = noise;
                p.spike_prob = spikes;
                p.touch_raw(x, y, force).unwrap();
                self.frames(frames);
                self.sim.panel.release();
            }
            58..=59 => {
                // A decayed or overwritten cell in one of the two copies.
                self.t.eeprom_faults += 1;
                let slot = if g.rng.below(2) == 0 { 0 } else { SLOT_B_ADDR as u64 };
                let addr = (slot + g.rng.below(RECORD_LEN as u64)) as u16;
                let v = g.rng.below(256) as u8;
                self.sim.eeprom.corrupt(addr, v).unwrap();
            }
            60..=61 => {
                // The power fails in the middle of the next save.
                self.t.eeprom_faults += 1;
                let n = g.rng.below(2 * RECORD_LEN as u64 + 4) as usize;
                self.sim.eeprom.torn_value = g.rng.below(256) as u8;
                self.sim.eeprom.power_loss_after(n);
                self.send(b"cal save\n", true);
            }
            62 => {
                // A power cycle, once every line sent so far is answered (the
                // lines still in flight would die with the chip).
                self.drain();
                self.t.reboots += 1;
                self.sim.reboot().unwrap();
                self.prev_pulses = None;
                self.prev_state = State::Off;
            }
            _ => {
                let n = 1 + g.rng.below(60);
                self.frames(n);
            }
        }
    }
}

fn run(seed: u64, screen: bool, inputs: u64) -> Tally {
    let mut r = Run::new(seed, screen);
    for _ in 0..inputs {
        r.input();
    }
    r.drain();
    assert_eq!(r.answered, r.sent, "every non-empty line got one reply");
    r.t.replies = r.answered;
    r.t
}

fn env(name: &str, default: u64) -> u64 {
    std::env::var(name).ok().and_then(|v| v.parse().ok()).unwrap_or(default)
}

#[test]
fn random_inputs_short_run() {
    for (seed, screen) in [(1, false), (2, true)] {
        let t = run(seed, screen, 6000);
        eprintln!("seed {seed} screen {screen}: {t:?}");
        assert!(t.moves > 100 && t.lost_lines > 0 && t.frames_stopped > 100, "{t:?}");
    }
}

#[test]
#[ignore = "long run: cargo test -p hal-sim --test random_inputs -- --ignored --nocapture"]
fn random_inputs_long_run() {
    let inputs = env("TOUCH_ARM_RANDOM_INPUTS", 1_000_000);
    let seed = env("TOUCH_ARM_RANDOM_SEED", 11);
    let start = std::time::Instant::now();
    let mut total = Tally::default();
    for (k, screen) in [false, true].into_iter().enumerate() {
        let t = run(seed + k as u64, screen, inputs / 2);
        eprintln!("seed {} screen {screen}: {t:?}", seed + k as u64);
        total.inputs += t.inputs;
        total.frames += t.frames;
        total.lines += t.lines;
        total.replies += t.replies;
        total.lost_lines += t.lost_lines;
        total.touches += t.touches;
        total.floods += t.floods;
        total.eeprom_faults += t.eeprom_faults;
        total.reboots += t.reboots;
        total.moves += t.moves;
        total.frames_stopped += t.frames_stopped;
        total.max_step_share = total.max_step_share.max(t.max_step_share);
    }
    eprintln!("random inputs: {total:?} in {:.0} s", start.elapsed().as_secs_f64());
}
