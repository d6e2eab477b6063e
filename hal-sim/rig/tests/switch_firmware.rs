//! Switch access on the real firmware ELF in simavr (issue #20 §4): one
//! assistive switch on D22 = PA0 (pressed = the pin driven low), `switch on`
//! over serial, then three presses pick a map pixel and send the arm there:
//! one in the column sweep, one in the row sweep, one in the Go phase. While
//! the arm moves, a press is STOP.
//!
//! The numbers: the default sweep is 6.00 s, 300 frames of 20 ms; on the
//! 320×240 layout the map is 224×112 px at x 0..=223, y 0..=111, so the
//! column line stands on ⌊224 f / 300⌋ at frame f of its sweep and the row
//! line on 111 − ⌊112 f / 300⌋ (bottom to top). A press counts once the
//! switch has been down the touch `hold`, 0.10 s by default, but the scan
//! stands still while the switch is down: the press takes the line where
//! it was when the switch closed, and the next sweep (or phase) starts
//! when the switch opens, its release counted at the third open sample.
//! Go lasts a fifth of the sweep (1.2 s); a down within `repeat` (0.20 s)
//! of the last release is ignored.

use touch_arm::config::settings::Config;
use touch_arm::ui::Layout;
use touch_arm_rig::firmware::{self, Session};

/// One frame of the firmware: a 20 ms PWM period.
const FRAME_S: f64 = 0.02;
/// The default `switch sweep`, frames (6.00 s).
const SWEEP_FRAMES: f64 = 300.0;
/// The default touch `hold`: a press counts after this long down.
const HOLD_S: f64 = 0.10;
/// How long each press holds PA0 low (as the main job's `--switch` does).
const PRESS_S: f64 = 0.2;
/// From the pin going high to the release the firmware counts: the third
/// open sample (the touch's `release_confirm`), 2 to 3 frames; the middle.
const RELEASE_S: f64 = 2.5 * FRAME_S;
/// The map on the 320×240 layout.
const MAP_W: f64 = 224.0;
const MAP_H: f64 = 112.0;
/// The firmware samples the switch once per frame, so where a press lands
/// depends on the frame the samples fall in: the first down sample comes 0
/// to 1 frame after the pin goes low, the line the glass shows (the one a
/// press takes) may trail the scan by a frame, and the sweep's frame 0 is
/// the frame that answered `switch on` (its reply is sent inside that
/// frame) or, for the row, the frame that counted the column press's
/// release (half a frame either side of [`RELEASE_S`]). That is up to two
/// frames either way, 1.5 px at 0.75 px a frame (224 columns in 300
/// frames; rows move half as fast), plus the floor's rounding: within 2 px.
const TOLERANCE_PX: i64 = 2;

fn boot() -> Session {
    Session::boot_product(None).expect("firmware ELF (cargo avr)")
}

/// Runs until simulated time `at_s`, then holds the switch down for
/// [`PRESS_S`] and opens it.
fn press_at(s: &mut Session, at_s: f64) {
    s.run_for((at_s - s.avr.time_s()).max(0.0)).unwrap();
    s.set_switch(true).unwrap();
    s.run_for(PRESS_S).unwrap();
    s.set_switch(false).unwrap();
}

/// The first line after byte `from` starting with `prefix`, waiting at
/// most `max_s`, with the time of its first byte; the output so far in the
/// panic message when it does not come.
fn line(s: &mut Session, from: usize, prefix: &str, max_s: f64) -> (String, f64) {
    match s.await_line(from, &[prefix], max_s).unwrap() {
        Some(l) => l,
        None => panic!("no {prefix:?} within {max_s} s:\n{}", String::from_utf8_lossy(&s.avr.uart_output()[from..])),
    }
}

/// The integers after `prefix` in `line` (`info switch go 74 55` → [74, 55]).
fn values(line: &str, prefix: &str) -> Vec<i64> {
    let rest = line.strip_prefix(prefix).unwrap_or_else(|| panic!("{line:?} does not start with {prefix:?}"));
    rest.split_whitespace().map(|w| w.parse().unwrap_or_else(|_| panic!("{line:?}: {w:?}"))).collect()
}

/// `switch on`, answered with the default sweep; the time of the reply (the
/// column sweep's start) and the output's length before it.
fn switch_on(s: &mut Session) -> (usize, f64) {
    let from = s.avr.uart_output().len();
    // Stored in the EEPROM: the reply goes on with the record's sequence.
    let reply = s.command("switch on").unwrap();
    assert!(reply.starts_with("ok switch on sweep 6.00"), "{reply}");
    let (_, t) = line(s, from, "ok switch on", 0.0);
    (from, t)
}

/// Every measured pulse of every joint within the default calibration's
/// pulse limits and, through its map, within the joint's angle limits.
fn assert_within_limits(s: &Session) {
    let cfg = Config::DEFAULT;
    let maps = firmware::default_servo_maps().unwrap();
    for (j, train) in s.pulse_ticks().iter().enumerate() {
        let cal = &cfg.joints[j];
        for &(t, ticks) in train {
            let us = f64::from(ticks) / 2.0;
            assert!(
                us >= f64::from(cal.min_us) && us <= f64::from(cal.max_us),
                "joint {j} at {t:.3} s: {us} us outside {}..={}",
                cal.min_us,
                cal.max_us
            );
            let a: f64 = maps[j].pulse_to_angle(ticks);
            // Half a tick of rounding: 0.5 µs at 1800/π µs a radian.
            let slack = 0.5 / f64::from(cal.us_per_rad.abs());
            assert!(
                a >= f64::from(cal.min_rad) - slack && a <= f64::from(cal.max_rad) + slack,
                "joint {j} at {t:.3} s: {a} rad outside {}..={}",
                cal.min_rad,
                cal.max_rad
            );
        }
    }
}

#[test]
fn three_presses_pick_the_pixel_under_the_lines_and_the_arm_goes_there() {
    let mut s = boot();
    let home = s.last_pulses();
    let (from, t_on) = switch_on(&mut s);

    // Column: down 2.0 s into the sweep; it counts a hold later, at the
    // column the line stood on when the switch closed.
    let t_down = t_on + 2.0;
    press_at(&mut s, t_down);
    let (col_line, t_col) = line(&mut s, from, "info switch column ", 0.5);
    assert!(t_col - t_down >= HOLD_S, "{col_line} {:.3} s after the press: before the hold", t_col - t_down);
    let x = values(&col_line, "info switch column ")[0];
    let f = (t_down - t_on) / FRAME_S;
    let want_x = (f * MAP_W / SWEEP_FRAMES).floor() as i64;
    assert!((want_x - x).abs() <= TOLERANCE_PX, "{col_line}: column {x}, expected {want_x} (frame {f:.1})");

    // Row: down 3.0 s after the column press let go; the row sweep starts
    // once that release counts.
    let t_row0 = t_down + PRESS_S + RELEASE_S;
    let t_down = t_down + PRESS_S + 3.0;
    press_at(&mut s, t_down);
    let (row_line, t_row) = line(&mut s, from, "info switch row ", 0.5);
    let y = values(&row_line, "info switch row ")[0];
    let f = (t_down - t_row0) / FRAME_S;
    let want_y = (MAP_H - 1.0) as i64 - (f * MAP_H / SWEEP_FRAMES).floor() as i64;
    assert!((y - want_y).abs() <= TOLERANCE_PX, "{row_line}: row {y}, expected {want_y} (frame {f:.1})");

    // Go: 0.5 s after the row line, inside the Go phase (1.2 s from the
    // row press's release) and well clear of that release plus `repeat`.
    let before_go = s.avr.uart_output().len();
    press_at(&mut s, t_row + 0.5);
    let (go_line, t_go) = line(&mut s, from, "info switch go ", 0.5);
    assert_eq!(values(&go_line, "info switch go "), [x, y], "{go_line}");
    // Scanning moved nothing: every pulse from `switch on` to the Go is the
    // home pose's.
    for (j, train) in s.pulses().iter().enumerate() {
        for (t, w) in train.iter().filter(|(t, _)| *t > t_on && *t < t_go) {
            assert_eq!(Some(*w), home[j], "joint {j} at {t:.3} s, before the Go");
        }
    }
    // The arm goes to the chosen pixel's point (its centre, as for a touch):
    // the pulses leave home and end on the host's IK target for it.
    let (x_p, y_p) = Layout::QVGA.ws_pixel_to_point(x as i16, y as i16).expect("a map pixel");
    let host = firmware::host_target(f64::from(x_p), f64::from(y_p)).unwrap();
    assert!(host.within_limits, "pixel ({x}, {y}) is out of the arm's reach: pick other press times");
    s.run_for(0.5).unwrap();
    assert!(
        s.last_pulses().iter().zip(home).any(|(p, h)| (p.unwrap() - h.unwrap()).abs() > 5.0),
        "the pulses did not move after {go_line}:\n{}",
        String::from_utf8_lossy(&s.avr.uart_output()[before_go..])
    );
    s.run_for(8.0).unwrap();
    let status = s.command("status").unwrap();
    assert!(status.starts_with("ok status holding"), "{status}");
    for (j, (p, t)) in s.last_pulses().iter().zip(host.pulses_us).enumerate() {
        assert!((p.unwrap() - t).abs() <= 1.0, "joint {j}: {p:?} us, the host's target {t} us");
    }
    assert_within_limits(&s);
}

#[test]
fn a_press_while_the_arm_moves_is_stop_and_the_pulses_freeze() {
    let mut s = boot();
    let (from, _) = switch_on(&mut s);
    // A long move (the first after power-up runs at the slow preset).
    let reply = s.command("goto 20 150 -30").unwrap();
    assert!(reply.starts_with("ok goto "), "{reply}");
    let ts = firmware::reply_ts(&reply).unwrap();
    assert!(ts > 2.0, "{reply}");
    let t_move = s.avr.time_s();
    press_at(&mut s, t_move + 0.8);
    let (stop, t_stop) = line(&mut s, from, "info switch stop", 0.5);
    assert_eq!(stop, "info switch stop");
    // Counted a hold after the pin went low, within a frame or two.
    let after = t_stop - (t_move + 0.8);
    assert!((HOLD_S..HOLD_S + 3.0 * FRAME_S).contains(&after), "STOP {after:.3} s after the press");
    // The pulse of the period after the stop's frame is the last to change.
    s.run_for(2.0 * FRAME_S).unwrap();
    let frozen = s.last_pulses();
    s.run_for(1.0).unwrap();
    assert_eq!(s.last_pulses(), frozen, "the pulses moved after {stop}");
    // Stopped mid-move: not at the goto's pose (20° 150° −30°: 800, 2100, 2100 µs).
    let target = [800.0, 2100.0, 2100.0];
    assert!(frozen.iter().zip(target).any(|(p, t)| (p.unwrap() - t).abs() > 20.0), "{frozen:?}");
    let status = s.command("status").unwrap();
    assert!(status.starts_with("ok status stopped"), "{status}");
    assert_within_limits(&s);
}

/// `switch glass` on the real ELF: a touch anywhere is the switch's press,
/// not the screen's. A touch on the map while the arm moves is STOP (not a
/// new target), and once stopped a touch on the map sends no move.
#[test]
fn with_the_glass_as_the_switch_a_touch_while_the_arm_moves_is_stop() {
    let mut s = boot();
    let from = s.avr.uart_output().len();
    let reply = s.command("switch glass").unwrap();
    assert!(reply.starts_with("ok switch glass sweep 6.00"), "{reply}");
    let reply = s.command("goto 20 150 -30").unwrap();
    assert!(reply.starts_with("ok goto "), "{reply}");
    let t_move = s.avr.time_s();
    s.run_for(0.8).unwrap();
    s.press_xy(0.5, 0.5).unwrap();
    s.run_for(PRESS_S).unwrap();
    s.release();
    let (stop, t_stop) = line(&mut s, from, "info switch stop", 0.5);
    assert_eq!(stop, "info switch stop");
    // Counted a hold after the touch landed, within a frame or two.
    let after = t_stop - (t_move + 0.8);
    assert!((HOLD_S..HOLD_S + 3.0 * FRAME_S).contains(&after), "STOP {after:.3} s after the touch");
    s.run_for(2.0 * FRAME_S).unwrap();
    let frozen = s.last_pulses();
    // Stopped: another touch on the map is a press of the scan (the
    // buttons light in turn while stopped: this one presses the lit
    // one), never a move.
    s.run_for(0.5).unwrap();
    s.press_xy(-0.4, 0.6).unwrap();
    s.run_for(PRESS_S).unwrap();
    s.release();
    s.run_for(1.0).unwrap();
    assert_eq!(s.last_pulses(), frozen, "the pulses moved after {stop}");
    let out = String::from_utf8_lossy(&s.avr.uart_output()[from..]).to_string();
    let lines: Vec<&str> = out.lines().collect();
    assert!(!out.contains("info touch"), "{out}");
    // The screen acted only for the scan's button press.
    for (i, l) in lines.iter().enumerate() {
        if l.starts_with("info screen") {
            assert!(i > 0 && lines[i - 1].starts_with("info switch button "), "the glass reached the screen:\n{out}");
        }
    }
    assert!(lines.iter().any(|l| l.starts_with("info switch button ")), "{out}");
    let status = s.command("status").unwrap();
    assert!(status.starts_with("ok status stopped"), "{status}");
    assert_within_limits(&s);
}
