//! No jump after a reset (issue #21 §1), on the real firmware ELF in simavr:
//! after an external reset (the RESET pin, SRAM kept) or a watchdog reset,
//! mid-hold and mid-move, the first pulses of every servo (the gripper's
//! too) are the last ones before the reset, to the tick; the arm holds there
//! and its first move runs at the slow preset; a power cycle (SRAM garbage
//! or zero) still homes, and so does a brown-out that RAM survived, while a
//! reset with no flag (a bootloader that cleared MCUSR) resumes; a resumed
//! pulse the saved calibration does not allow is pulled into its window and
//! reported, never sent.
//!
//! Speed bounds, in Timer5 ticks (0.5 µs) per 20 ms frame, with the default
//! calibration (1800/π ≈ 572.96 µs/rad, 3 rad/s max): at full speed
//! 3 · 0.02 · 572.96 · 2 = 68.75 ticks; at the slow preset (25 % of it, less
//! the 2 % margin) 0.25 · 0.98 · 68.75 = 16.8 ticks; one tick more for the
//! rounding of each pulse.

use touch_arm_rig::avr::PowerFill;
use touch_arm_rig::firmware::{self, Session, GRIPPER_PIN, SERVO_PINS};

const PERIOD: u64 = 320_000;
/// Full speed and slow preset step bounds (module doc), ticks per frame.
const FULL_STEP: u16 = 69 + 1;
const SLOW_STEP: u16 = 17 + 1;

/// Every complete pulse per output (base, shoulder, elbow, gripper): (rise
/// cycle, ticks).
fn trains(s: &Session) -> [Vec<(u64, u16)>; 4] {
    let pins = [SERVO_PINS[0], SERVO_PINS[1], SERVO_PINS[2], GRIPPER_PIN];
    pins.map(|p| firmware::pulse_ticks(&s.avr.pulses(p)))
}

/// Runs to the middle of a PWM period (10 ms after the last rise), clear of
/// every pulse, so a reset there cuts none.
fn to_mid_period(s: &mut Session) {
    let last = trains(s)[0].last().expect("pulses before the reset").0;
    let phase = (s.avr.cycles() - last) % PERIOD;
    let wait = (PERIOD / 2 + PERIOD - phase) % PERIOD;
    s.avr.run_cycles(wait.max(1)).unwrap();
}

/// The last pulse of each output before `cycle` and the pulses after it.
fn split(s: &Session, cycle: u64) -> ([u16; 4], [Vec<u16>; 4]) {
    let t = trains(s);
    let before = std::array::from_fn(|j| t[j].iter().rev().find(|(c, _)| *c < cycle).expect("a pulse before").1);
    let after = std::array::from_fn(|j| t[j].iter().filter(|(c, _)| *c > cycle).map(|(_, w)| *w).collect());
    (before, after)
}

/// Waits for the `info reset` line after byte `from`; returns it.
fn reset_line(s: &mut Session, from: usize) -> String {
    let (line, _) = s
        .await_line(from, &["info reset "], 2.0)
        .unwrap()
        .unwrap_or_else(|| panic!("no `info reset` line:\n{}", String::from_utf8_lossy(&s.avr.uart_output()[from..])));
    line
}

/// `resume pulses 1500 1500.5 …` as ticks.
fn resumed_ticks(line: &str) -> Vec<Option<u16>> {
    let rest = line.split(" resume pulses ").nth(1).unwrap_or_else(|| panic!("{line}"));
    rest.split(' ').map(|w| w.parse::<f64>().ok().map(|us| (us * 2.0).round() as u16)).collect()
}

fn max_step(p: &[u16]) -> u16 {
    p.windows(2).map(|w| w[0].abs_diff(w[1])).max().unwrap_or(0)
}

enum Kind {
    External,
    Watchdog,
}

/// Resets the chip at mid-period (`kind`), waits for the firmware to boot
/// and hold for 0.6 s; returns the reset's cycle, the pulses before and
/// after, and the `info reset` line.
fn reset(s: &mut Session, kind: Kind) -> (u64, [u16; 4], [Vec<u16>; 4], String) {
    to_mid_period(s);
    let from = s.avr.uart_output().len();
    let resets = s.avr.resets();
    let at = match kind {
        Kind::External => {
            let at = s.avr.cycles();
            s.avr.external_reset();
            at
        }
        Kind::Watchdog => {
            // Stop Timer5's clock (TCCR5B): the frame loop waits for a period
            // that never comes and the watchdog resets the chip (500 ms).
            s.avr.write_io(0x121, 0).unwrap();
            s.avr.run_until(|a| a.resets() > resets, firmware::CPU_HZ as u64).expect("watchdog reset within 1 s");
            s.avr.cycles()
        }
    };
    assert_eq!(s.avr.resets(), resets + 1);
    let line = reset_line(s, from);
    s.run_for(0.6).unwrap();
    let (before, after) = split(s, at);
    (at, before, after, line)
}

/// The firmware after its slow first move, at the fast preset, at rest.
fn moved() -> Session {
    Session::start_moved_fast(11).expect("firmware ELF (cargo avr)")
}

/// The first pulses after the reset are the last before, to the tick, on
/// every output; the line says so with the same pulses; then they hold.
fn assert_resumed(before: &[u16; 4], after: &[Vec<u16>; 4], line: &str, cause: &str) {
    assert!(line.starts_with(&format!("info reset {cause} resume pulses ")), "{line}");
    let said: Vec<Option<u16>> = before.iter().map(|t| Some(*t)).collect();
    assert_eq!(resumed_ticks(line), said, "{line}");
    for (j, (b, a)) in before.iter().zip(after.iter()).enumerate() {
        assert!(a.len() > 10, "output {j}: {} pulses after the reset", a.len());
        assert_eq!(a[0], *b, "output {j}: first pulse after the reset");
        assert!(a.iter().all(|t| t == b), "output {j} holds {b} after the reset: {a:?}");
    }
}

/// After a resume: `holding` at once, the first move slow; a `goto` from
/// the resumed pose moves every joint within the slow preset's step.
fn assert_first_move_slow(s: &mut Session, at: u64) {
    let status = s.command("status").unwrap();
    assert!(status.starts_with("ok status holding") && status.contains("first_move_slow"), "{status}");
    let reply = s.command("goto 60 110 -80").unwrap();
    assert!(reply.starts_with("ok goto"), "{reply}");
    s.run_for(firmware::reply_ts(&reply).unwrap() + 0.3).unwrap();
    let (_, after) = split(s, at);
    for (j, p) in after.iter().take(3).enumerate() {
        let step = max_step(p);
        assert!(step <= SLOW_STEP, "joint {j}: a step of {step} ticks after the reset (slow preset ≤ {SLOW_STEP})");
    }
    let status = s.command("status").unwrap();
    assert!(status.starts_with("ok status holding") && !status.contains("first_move_slow"), "{status}");
}

#[test]
fn an_external_reset_mid_hold_resumes_the_pulses_to_the_tick() {
    let mut s = moved();
    s.run_for(0.3).unwrap();
    let (at, before, after, line) = reset(&mut s, Kind::External);
    let out = s.avr.uart_output_string();
    assert!(out.contains(" reset external\r\n"), "the first boot line names the cause:\n{out}");
    assert_resumed(&before, &after, &line, "external");
    // 90° 100° −100° and the gripper open (600 µs).
    assert_eq!(line, "info reset external resume pulses 1500 1600 1400 600");
    assert_first_move_slow(&mut s, at);
}

#[test]
fn an_external_reset_mid_move_stops_the_arm_where_it_was() {
    let mut s = moved();
    let reply = s.command("goto 30 130 -40").unwrap();
    let ts = firmware::reply_ts(&reply).unwrap();
    s.run_for(ts * 0.4).unwrap();
    let (at, before, after, line) = reset(&mut s, Kind::External);
    // Mid-move: the last pulses are neither the start nor the target.
    assert!(before[0] != 3000 && before[0] != 1800, "{before:?}");
    assert_resumed(&before, &after, &line, "external");
    // Before the reset the move stayed within the full-speed step, and so
    // does the train across it (the reset adds no step).
    let t = trains(&s);
    for (j, p) in t.iter().take(3).enumerate() {
        let w: Vec<u16> = p.iter().map(|(_, w)| *w).collect();
        assert!(max_step(&w) <= FULL_STEP, "joint {j}: step {}", max_step(&w));
    }
    assert_first_move_slow(&mut s, at);
}

#[test]
fn a_watchdog_reset_mid_hold_and_mid_move_resumes_the_pulses() {
    let mut s = moved();
    let (_, before, after, line) = reset(&mut s, Kind::Watchdog);
    assert_resumed(&before, &after, &line, "watchdog");
    assert_eq!(line, "info reset watchdog resume pulses 1500 1600 1400 600");
    // Again, mid-move this time (the first move after the reset is slow).
    let reply = s.command("goto 150 60 -120").unwrap();
    let ts = firmware::reply_ts(&reply).unwrap();
    s.run_for(ts * 0.5).unwrap();
    let (at, before, after, line) = reset(&mut s, Kind::Watchdog);
    assert!(before[0] != 3000 && before[0] != 4200, "mid-move: {before:?}");
    assert_resumed(&before, &after, &line, "watchdog");
    assert_first_move_slow(&mut s, at);
}

#[test]
fn a_power_cycle_homes_whatever_ram_holds() {
    for fill in [PowerFill::Noise(0x5eed), PowerFill::Zero] {
        let mut s = moved();
        to_mid_period(&mut s);
        let from = s.avr.uart_output().len();
        let at = s.avr.cycles();
        s.avr.power_cycle(fill);
        let line = reset_line(&mut s, from);
        assert_eq!(line, "info reset power-on home", "{fill:?}");
        s.run_for(0.6).unwrap();
        let (_, after) = split(&s, at);
        // The home pose (1500 µs each) and the gripper open.
        for (j, want) in [3000u16, 3000, 3000, 1200].iter().enumerate() {
            assert!(!after[j].is_empty() && after[j].iter().all(|t| t == want), "{fill:?} output {j}: {:?}", after[j]);
        }
        let out = String::from_utf8_lossy(&s.avr.uart_output()[from..]).to_string();
        assert!(out.contains(" reset power-on\r\n"), "{out}");
    }
}

/// The running calibration allows 2100 µs on the base, the saved one only
/// up to 2000 µs: after the reset the base is held at 2000 µs (the saved
/// window's end) and the firmware says so; 2100 µs is never sent.
#[test]
fn a_resumed_pulse_outside_the_saved_limits_is_clamped_and_reported() {
    let mut s = moved();
    assert_eq!(s.command("cal set base max_us 2000").unwrap(), "ok cal set");
    assert!(s.command("cal save").unwrap().starts_with("ok cal save"));
    assert_eq!(s.command("cal set base max_us 2400").unwrap(), "ok cal set");
    // 150° on the base: 600 + 150 · 10 µs = 2100 µs.
    let reply = s.command("goto 150 100 -100").unwrap();
    s.run_for(firmware::reply_ts(&reply).unwrap() + 0.3).unwrap();
    let from = s.avr.uart_output().len();
    let (_, before, after, line) = reset(&mut s, Kind::External);
    assert_eq!(before[0], 4200);
    let out = String::from_utf8_lossy(&s.avr.uart_output()[from..]).to_string();
    assert!(out.contains("warn resume base 2100 outside its limits, held at 2000\r\n"), "{out}");
    assert_eq!(line, "info reset external resume pulses 2000 1600 1400 600");
    assert!(after[0].iter().all(|t| *t == 4000), "{:?}", after[0]);
    for j in 1..4 {
        assert!(after[j].iter().all(|t| *t == before[j]), "output {j}");
    }
}

/// The reset flags decide with the block: a brown-out that RAM survived
/// still homes (the supply failed; the servos may have sagged), and a reset
/// with no flag at all (a bootloader that read and cleared MCUSR) resumes
/// on the block's validity alone.
#[test]
fn a_brown_out_homes_and_a_reset_without_flags_resumes() {
    for (flags, first, want) in [
        (4u8, " reset brownout\r\n", "info reset brown-out home"),
        (0, " reset unknown\r\n", "info reset unknown resume pulses 1500 1600 1400 600"),
    ] {
        let mut s = moved();
        to_mid_period(&mut s);
        let from = s.avr.uart_output().len();
        s.avr.reset_with_mcusr(flags);
        assert_eq!(reset_line(&mut s, from), want);
        let out = String::from_utf8_lossy(&s.avr.uart_output()[from..]).to_string();
        assert!(out.contains(first), "{out}");
    }
}
