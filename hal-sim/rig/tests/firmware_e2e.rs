//! The real firmware ELF in simavr, end to end: the panel model answers the
//! firmware's own touch driver through the ADC and the pin registers, the
//! servo pulses are measured on PL3/PL4/PL5 cycle-exactly, and commands go
//! through USART0. Expected values come from method.md's formulas in f64 here,
//! not from the crate's code.

use std::f64::consts::PI;

use touch_arm::touch::map::Calibration;
use touch_arm::ui::calibration::{cal_pixel, save_area, setting_area, Setting, CAL_COUNT};
use touch_arm::ui::Layout;
use touch_arm_rig::firmware::{self, Session};
use touch_arm_rig::panel::PanelWiring;

/// The ILI9341 the session simulates: the 320×240 screen.
const L: Layout = Layout::QVGA;

/// Frame period of the firmware (one servo PWM period).
const FRAME_S: f64 = 0.02;

fn start() -> Session {
    let mut s = Session::start(&firmware::default_elf(), PanelWiring::A, 11).expect("firmware ELF (cargo avr)");
    // Boot, load the (missing) configuration, home, settle.
    s.run_for(1.5).unwrap();
    s
}

/// method.md §4–6 and the default servo calibration (10 µs/°, base and shoulder
/// 600 µs at 0°, elbow 2400 µs at 0°, elbow-up branch): the pulses a target
/// at workspace point (x_p, y_p) must end at, and its condition.
fn expected(x_p: f64, y_p: f64) -> ([f64; 3], u8) {
    let alpha = y_p.atan2(x_p);
    let cond = if x_p >= y_p {
        1
    } else if x_p >= 0.0 {
        2
    } else if y_p >= -x_p {
        3
    } else {
        4
    };
    let (r, h) = (x_p.abs(), y_p);
    let c = (r * r + h * h - 2.0) / 2.0;
    let q3 = -c.acos();
    let q2 = h.atan2(r) + q3.abs().sin().atan2(1.0 + q3.cos());
    let deg = 180.0 / PI;
    ([600.0 + 10.0 * alpha * deg, 600.0 + 10.0 * q2 * deg, 2400.0 + 10.0 * q3 * deg], cond)
}

/// Pulses measured after `t0` (s), per joint.
fn pulses_after(s: &Session, t0: f64) -> [Vec<(f64, f64)>; 3] {
    s.pulses().map(|p| p.into_iter().filter(|(t, _)| *t >= t0).collect())
}

/// Pulse widths equal within the harness's edge-stamp jitter (≤ 4 cycles).
fn assert_same_pulses(a: [Option<f64>; 3], b: [Option<f64>; 3]) {
    for j in 0..3 {
        let (x, y) = (a[j].unwrap(), b[j].unwrap());
        assert!((x - y).abs() <= 0.25, "joint {j}: {x} µs vs {y} µs");
    }
}

/// A tap: held 0.3 s, then lifted; the firmware acts on the lift-off
/// (issue #19), read over the three frames after it.
fn touch(s: &mut Session, raw_x: f64, raw_y: f64) {
    s.press_raw(raw_x, raw_y).unwrap();
    s.run_for(0.3).unwrap();
    s.release();
    s.run_for(0.1).unwrap();
}

fn map_touch(x: f32, y: f32) -> ((f64, f64), (f64, f64)) {
    firmware::map_touch(x, y).expect("point on the map")
}

#[test]
fn touches_on_the_map_in_all_four_conditions_reach_the_ik_pose() {
    for (x, y) in [(0.7f32, 0.3f32), (0.2, 0.6), (-0.3, 0.5), (-0.8, 0.15)] {
        let ((raw_x, raw_y), (wx, wy)) = map_touch(x, y);
        let (want, cond) = expected(wx, wy);
        let mut s = start();
        touch(&mut s, raw_x, raw_y);
        let out = s.avr.uart_output_string();
        let line =
            out.lines().find(|l| l.starts_with("info touch ")).unwrap_or_else(|| panic!("no touch reply:\n{out}"));
        assert!(line.starts_with(&format!("info touch {raw_x} {raw_y} cond {cond} ts_ms")), "({x}, {y}): {line}");
        let ts: f64 =
            line.split_whitespace().skip_while(|w| *w != "ts_ms").nth(1).unwrap().parse::<f64>().unwrap() / 1000.0;
        s.run_for(ts + 0.5).unwrap();
        let last = s.last_pulses();
        for j in 0..3 {
            let got = last[j].unwrap();
            assert!(
                (got - want[j]).abs() <= 1.0,
                "map point ({wx:.4},{wy:.4}) joint {j}: {got} µs, want {:.2}",
                want[j]
            );
        }
        assert!(s.command("status").unwrap().starts_with("ok status holding"));
    }
}

#[test]
fn screen_buttons_stop_resume_and_set_the_speed() {
    let mut s = start();
    assert!(s.command("goto 20 150 -30").unwrap().starts_with("ok goto"));
    s.run_for(1.0).unwrap();
    // The STOP button (right edge, top): panel point of its centre.
    let stop = L.pixel_center_to_panel(L.stop().x + L.stop().w as i16 / 2, L.stop().y + L.stop().h as i16 / 2);
    let (rx, ry) = Calibration::DEFAULT.unmap_exact::<f64>(stop.0 as f64, stop.1 as f64).unwrap();
    touch(&mut s, rx.round(), ry.round());
    assert!(s.avr.uart_output_string().contains("info screen stop"));
    assert!(s.command("status").unwrap().starts_with("ok status stopped"));
    let t_stop = s.avr.time_s();
    s.run_for(1.0).unwrap();
    for p in pulses_after(&s, t_stop + 2.0 * FRAME_S) {
        assert!(p.iter().all(|(_, w)| (w - p[0].1).abs() <= 0.25), "moved after the STOP button");
    }
    // The same place is RESUME now: a fresh contact held 0.6 s.
    s.run_for(0.3).unwrap();
    s.press_raw(rx.round(), ry.round()).unwrap();
    s.run_for(0.8).unwrap();
    s.release();
    s.run_for(0.1).unwrap();
    assert!(s.avr.uart_output_string().contains("info screen resume"));
    // Speed buttons.
    let fast = L.pixel_center_to_panel(L.fast().x + L.fast().w as i16 / 2, L.fast().y + L.fast().h as i16 / 2);
    let (fx, fy) = Calibration::DEFAULT.unmap_exact::<f64>(fast.0 as f64, fast.1 as f64).unwrap();
    s.run_for(0.3).unwrap();
    touch(&mut s, fx.round(), fy.round());
    assert!(s.avr.uart_output_string().contains("info screen speed fast"), "{}", s.avr.uart_output_string());
    assert!(s.command("status").unwrap().contains("speed fast"));
}

/// Issue #19 on the real ELF: a contact on the map moves nothing while the
/// finger is down (0.5 s), and the arm goes when it lifts, to the contact's
/// centre; a brief contact (60 ms, under the 0.10 s hold) and one lifted
/// in the guard band below the map move nothing and say why; STOP latches
/// on contact within 60 ms and a frame.
#[test]
fn a_tap_on_the_map_commits_on_lift_off() {
    let mut s = start();
    let ((rx, ry), (wx, wy)) = map_touch(0.4, 0.6);
    let (want, cond) = expected(wx, wy);
    let from = s.avr.uart_output().len();
    let t0 = s.avr.time_s();
    s.press_raw(rx, ry).unwrap();
    s.run_for(0.5).unwrap();
    let out = s.avr.uart_output_string()[from..].to_string();
    assert!(!out.contains("info touch"), "acted before the lift-off:\n{out}");
    let held = pulses_after(&s, t0);
    for p in &held {
        assert!(p.iter().all(|(_, w)| (w - p[0].1).abs() <= 0.25), "moved while the finger was down");
    }
    s.release();
    let t_lift = s.avr.time_s();
    let (line, t) = s.await_line(from, &["info touch", "err touch"], 0.5).unwrap().expect("a reply on lift-off");
    assert!(line.starts_with(&format!("info touch {} {} cond {cond}", rx as u16, ry as u16)), "{line}");
    // The release is read over three frames, then the plan: within 5.
    assert!(t - t_lift <= 5.0 * FRAME_S, "reply {:.3} s after the lift", t - t_lift);
    let ts: f64 = line.split_whitespace().skip_while(|w| *w != "ts_ms").nth(1).unwrap().parse().unwrap();
    s.run_for(ts / 1000.0 + 0.3).unwrap();
    let got = s.last_pulses();
    for j in 0..3 {
        assert!((got[j].unwrap() - want[j]).abs() <= 1.0, "joint {j}: {:?} vs {want:?}", got[j]);
    }
    // A brief contact: ignored, nothing moves.
    s.run_for(0.4).unwrap();
    let ((bx, by), _) = map_touch(-0.5, 0.5);
    let from = s.avr.uart_output().len();
    s.press_raw(bx, by).unwrap();
    s.run_for(0.06).unwrap();
    s.release();
    let (line, _) = s.await_line(from, &["info screen ignored", "info touch"], 0.3).unwrap().expect("a line");
    assert_eq!(line, "info screen ignored brief");
    // Lifted in the guard band below the map: cancelled.
    s.run_for(0.4).unwrap();
    let from = s.avr.uart_output().len();
    s.press_raw(bx, by).unwrap();
    s.run_for(0.3).unwrap();
    let (gx, gy) = firmware::raw_at_pixel(&L, 60, L.ws().bottom() + 4).unwrap();
    s.press_raw(gx, gy).unwrap();
    s.run_for(0.1).unwrap();
    s.release();
    let (line, _) = s.await_line(from, &["info screen cancel", "info touch"], 0.3).unwrap().expect("a line");
    assert_eq!(line, "info screen cancel");
    assert_same_pulses(s.last_pulses(), got);
    // STOP on contact: the latch within 60 ms + a frame of the landing.
    s.run_for(0.4).unwrap();
    let (sx, sy) = firmware::raw_at_centre(&L, L.stop()).unwrap();
    let from = s.avr.uart_output().len();
    s.press_raw(sx, sy).unwrap();
    let t_land = s.avr.time_s();
    let (line, t) = s.await_line(from, &["info screen stop"], 0.3).unwrap().expect("STOP latched");
    assert_eq!(line, "info screen stop");
    assert!(t - t_land <= 0.06 + FRAME_S, "STOP {:.3} s after the contact", t - t_land);
    s.release();
}

#[test]
fn all_joints_arrive_together_at_ts() {
    let mut s = start();
    // A linear law moves every joint at constant speed until exactly tₛ, so
    // the last frame in which each pulse changes marks its arrival.
    assert_eq!(s.command("law linear").unwrap(), "ok law linear");
    let t_cmd = s.avr.time_s();
    let reply = s.command("goto 30 120 -60").unwrap();
    assert!(reply.starts_with("ok goto ts_ms"), "{reply}");
    let ts: f64 = reply.split_whitespace().nth(3).unwrap().parse::<f64>().unwrap() / 1000.0;
    s.run_for(ts + 1.0).unwrap();
    let trains = pulses_after(&s, t_cmd);
    let want = [600.0 + 300.0, 600.0 + 1200.0, 2400.0 - 600.0];
    let mut arrivals = [0.0; 3];
    for j in 0..3 {
        let p = &trains[j];
        let last_change = p.windows(2).filter(|w| (w[1].1 - w[0].1).abs() > 0.25).map(|w| w[1].0).next_back().unwrap();
        arrivals[j] = last_change;
        assert!((p.last().unwrap().1 - want[j]).abs() <= 1.0, "joint {j} ends at {}", p.last().unwrap().1);
    }
    let spread = arrivals.iter().cloned().fold(f64::MIN, f64::max) - arrivals.iter().cloned().fold(f64::MAX, f64::min);
    assert!(spread <= FRAME_S + 1e-6, "arrivals {arrivals:?}");
    // The line is read in the next frame (< 1 frame), planned after that
    // frame's pulses so the move's t = 0 is the frame after (1), each pulse
    // is latched at the following period start (1), and tₛ ends inside a
    // frame (< 1).
    assert!(
        (arrivals[0] - (t_cmd + ts)).abs() <= 4.0 * FRAME_S,
        "arrival {} vs command at {t_cmd} + tₛ {ts}",
        arrivals[0]
    );
}

#[test]
fn refused_targets_leave_the_arm_where_it_is() {
    let mut s = start();
    let before = s.last_pulses();
    // With the paper's geometry (k = l2 = l3 = 1) every panel point is within
    // reach (the host scenarios cover the unreachable case with a larger k);
    // on the chip: a target outside a joint's limits, and a raw point outside
    // the calibrated span, are refused, never clamped into another pose.
    for (line, want) in [
        ("goto 200 90 -90", "err joint limit base"),
        ("goto 90 90 30", "err joint limit elbow"),
        ("move 60 500", "err outside calibrated area"),
    ] {
        assert_eq!(s.command(line).unwrap(), want, "{line}");
    }
    s.run_for(1.0).unwrap();
    assert_same_pulses(s.last_pulses(), before);
    assert!(s.command("status").unwrap().contains("refused"));
}

#[test]
fn idle_panel_noise_moves_nothing() {
    let mut s = start();
    s.set_noise(3.0, 0.01);
    let t0 = s.avr.time_s();
    s.run_for(3.0).unwrap();
    for (j, p) in pulses_after(&s, t0).iter().enumerate() {
        assert!(p.len() >= 140, "joint {j} kept pulsing ({} pulses)", p.len());
        assert!(
            p.iter().all(|(_, w)| (w - 1500.0).abs() <= 0.5),
            "joint {j} moved: {:?}",
            p.iter().find(|(_, w)| (w - 1500.0).abs() > 0.5)
        );
    }
    assert!(!s.avr.uart_output_string().contains("info touch "));
}

/// Every pulse that starts at `t0` (s) or later has one width per joint,
/// away from both ends of `goto 20 150 -30` from home (base and shoulder
/// 600 µs + 10 µs/°, elbow 2400 µs + 10 µs/°: 1500 1500 1500 → 800 2100 2100).
fn assert_frozen_mid_move(s: &Session, t0: f64) {
    let (home, target) = ([1500.0, 1500.0, 1500.0], [800.0, 2100.0, 2100.0]);
    for (j, p) in pulses_after(s, t0).iter().enumerate() {
        let first = p[0].1;
        assert!(p.iter().all(|(_, w)| (w - first).abs() <= 0.25), "joint {j} moved after the stop");
        assert!(
            (first - home[j]).abs() > 20.0 && (first - target[j]).abs() > 20.0,
            "joint {j} stopped at {first}, not mid-move"
        );
    }
}

#[test]
fn stop_mid_move_freezes_the_pulses_within_a_frame() {
    let mut s = start();
    let reply = s.command("goto 20 150 -30").unwrap();
    assert!(reply.starts_with("ok goto"), "{reply}");
    let ts: f64 = reply.split_whitespace().nth(3).unwrap().parse::<f64>().unwrap() / 1000.0;
    s.run_for(ts / 2.0).unwrap();
    assert_eq!(s.command("stop").unwrap(), "ok stop");
    let t_stop = s.avr.time_s();
    s.run_for(1.5).unwrap();
    assert_frozen_mid_move(&s, t_stop + FRAME_S);
    // Held until resume; a new target is refused while stopped.
    assert!(s.command("goto 90 90 -90").unwrap().starts_with("err stopped"));
    assert_eq!(s.command("resume").unwrap(), "ok resume");
    assert!(s.command("goto 90 90 -90").unwrap().starts_with("ok goto"));
}

/// Issue #21 §2: the one-byte STOP `!`, with no line ending. The receive
/// interrupt flags it; the next frame (at most one period after the byte)
/// latches STOP first and answers `ok stop`; that frame's pulses are the
/// previous frame's, so every pulse that starts two periods after the byte
/// or later has one width per joint, mid-move.
#[test]
fn the_one_byte_stop_freezes_the_pulses_within_a_frame_of_the_byte() {
    let mut s = start();
    let reply = s.command("goto 20 150 -30").unwrap();
    assert!(reply.starts_with("ok goto"), "{reply}");
    let ts: f64 = reply.split_whitespace().nth(3).unwrap().parse::<f64>().unwrap() / 1000.0;
    s.run_for(ts / 2.0).unwrap();
    let from = s.avr.uart_output().len();
    let t_byte = s.avr.time_s();
    s.avr.uart_send(b"!");
    let (line, t_reply) = s.await_line(from, &["ok", "err"], 0.5).unwrap().expect("a reply to `!`");
    assert_eq!(line, "ok stop");
    // Sent at the start of the next frame: within one period of the byte
    // (its 87 µs on the wire included).
    assert!(t_reply - t_byte <= FRAME_S + 0.001, "ok stop {:.1} ms after the byte", (t_reply - t_byte) * 1e3);
    s.run_for(1.0).unwrap();
    assert_frozen_mid_move(&s, t_byte + 2.0 * FRAME_S);
    assert!(s.command("status").unwrap().starts_with("ok status stopped"));
    // Mid-line: the `!` is not part of the line, which goes on without it
    // (`goto 90 90 -90`, refused while stopped; with the `!` in it, it would be
    // `err bad number`).
    assert_eq!(s.command("resume").unwrap(), "ok resume");
    let from = s.avr.uart_output().len();
    s.avr.uart_send(b"goto 90 9!0 -90\n");
    s.await_line(from, &["err"], 0.5).unwrap().expect("the line's reply");
    let out = String::from_utf8_lossy(&s.avr.uart_output()[from..]).to_string();
    let replies: Vec<&str> = out.lines().map(str::trim_end).collect();
    assert_eq!(replies, ["ok stop", "err stopped (send resume)"]);
}

/// `version` answers the crate version and the git commit, the same two the
/// boot line printed (`info touch-arm <version> commit <commit> reset …`);
/// `help` and keywords in capitals, a line left without its ending and `log
/// plot` on the chip.
#[test]
fn version_help_case_timeout_and_plot_on_the_chip() {
    let mut s = start();
    let out = s.avr.uart_output_string();
    let boot = out.lines().find(|l| l.starts_with("info touch-arm ")).expect("boot line").to_string();
    let words: Vec<&str> = boot.split_whitespace().collect();
    assert_eq!(words[3], "commit", "{boot}");
    let (version, commit) = (words[2], words[4]);
    assert_eq!(version, touch_arm::VERSION);
    assert_eq!(s.command("version").unwrap(), format!("ok version {version} {commit}"));
    assert_eq!(
        s.command("help").unwrap(),
        "ok help move goto stop resume status law speed path lift mode circle grip pose park undo access switch cal log help version !"
    );
    assert_eq!(s.command("SPEED Slow").unwrap(), "ok speed slow");
    assert!(s.command("STATUS").unwrap().starts_with("ok status holding law zat speed slow "));
    // No line ending: answered after line_timeout_ms (2 s) without a byte,
    // not before.
    let from = s.avr.uart_output().len();
    s.avr.uart_send(b"status");
    assert_eq!(s.await_line(from, &["ok", "err"], 1.9).unwrap(), None);
    let (line, _) = s.await_line(from, &["ok", "err"], 0.5).unwrap().expect("the timeout's reply");
    assert_eq!(line, "err line timeout (no line ending?)");
    // `log plot`: the home pose, two decimals, nothing else on the line.
    assert_eq!(s.command("log plot").unwrap(), "ok log plot");
    let from = s.avr.uart_output().len();
    s.run_for(0.25).unwrap();
    let out = String::from_utf8_lossy(&s.avr.uart_output()[from..]).to_string();
    // 0.25 s is 12 frames, a line each; the first piece may be the end of a
    // line under way when the reply came, the last one not ended yet.
    let plot: Vec<&str> = out.split('\n').map(str::trim_end).collect();
    assert!(plot.len() >= 12, "{plot:?}");
    for l in &plot[1..11] {
        assert_eq!(*l, "base:90.00,shoulder:90.00,elbow:-90.00,grip:0.00");
    }
    assert_eq!(s.command("log off").unwrap(), "ok log off");
}

#[test]
fn malformed_lines_get_err_and_move_nothing() {
    let mut s = start();
    let before = s.last_pulses();
    for (line, reason) in [
        ("frobnicate", "err unknown command"),
        ("move 600", "err missing argument"),
        ("move 600 600 600", "err extra argument"),
        ("move 6x0 600", "err bad number"),
        ("move 2000 600", "err out of range"),
        ("move 99999999999999 1", "err out of range"),
        ("goto 90 90", "err missing argument"),
        ("law warp", "err bad argument"),
    ] {
        assert_eq!(s.command(line).unwrap(), reason, "{line}");
    }
    let long = "x".repeat(100);
    assert_eq!(s.command(&long).unwrap(), "err line too long");
    // The buffer recovered: a good line still works.
    assert!(s.command("status").unwrap().starts_with("ok status holding"));
    s.run_for(0.5).unwrap();
    assert_same_pulses(s.last_pulses(), before);
}

#[test]
fn power_up_sends_no_pulse_before_the_home_pose() {
    let mut s = Session::start(&firmware::default_elf(), PanelWiring::A, 3).unwrap();
    s.run_for(0.05).unwrap();
    assert!(s.pulses().iter().all(|p| p.is_empty()), "pulses before the configuration was loaded");
    assert!(s.grip_pulse_ticks().is_empty(), "a gripper pulse before the configuration was loaded");
    s.run_for(1.0).unwrap();
    for p in s.pulses() {
        assert!(!p.is_empty());
        assert!(p.iter().all(|(_, w)| (w - 1500.0).abs() <= 0.5), "first pulses are the home pose");
    }
    let out = s.avr.uart_output_string();
    assert!(out.contains("reset power-on") && out.contains("warn no stored config, defaults"), "{out}");
}

/// The boot line names the core crate's version (read from its Cargo.toml
/// here, not hal-sim's) and the commit the ELF was built from: 12 hex digits
/// and `-dirty`, a commit of this repository when git can tell, or `unknown`
/// (built without git). Then the reset cause.
#[test]
fn the_boot_line_names_the_version_and_the_commit() {
    let mut s = Session::start(&firmware::default_elf(), PanelWiring::A, 3).unwrap();
    s.run_for(0.05).unwrap();
    let out = s.avr.uart_output_string();
    let line = out.lines().next().unwrap_or_default();
    let root = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");
    let manifest = std::fs::read_to_string(format!("{root}/Cargo.toml")).unwrap();
    let version = manifest.lines().find_map(|l| l.strip_prefix("version = \"")).unwrap().trim_end_matches('"');
    let words: Vec<&str> = line.split(' ').collect();
    let ["info", "touch-arm", v, "commit", commit, "reset", "power-on"] = words[..] else {
        panic!("boot line {line:?} (all output: {out})");
    };
    assert_eq!(v, version, "{line}");
    if commit != "unknown" {
        let hash = commit.strip_suffix("-dirty").unwrap_or(commit);
        assert!(hash.len() == 12 && hash.bytes().all(|b| b.is_ascii_hexdigit()), "{line}");
        let known = std::process::Command::new("git")
            .args(["-C", root, "cat-file", "-e", &format!("{hash}^{{commit}}")])
            .status()
            .map(|st| st.success());
        // Without git here nothing more can be checked.
        assert!(known.unwrap_or(true), "{hash} is no commit of this repository ({line})");
    }
}

#[test]
fn a_hang_resets_through_the_watchdog_and_the_arm_holds_where_it_was() {
    let mut s = start();
    assert!(s.command("goto 30 120 -60").unwrap().starts_with("ok goto"));
    s.run_for(0.5).unwrap();
    // Stop Timer5's clock (TCCR5B, data address 0x121): the frame loop waits
    // for a PWM period that never comes, so nothing feeds the watchdog.
    s.avr.write_io(0x121, 0).unwrap();
    let t_hang = s.avr.time_s();
    let last = s.last_pulses();
    s.avr.run_until_output(b"reset watchdog", firmware::CPU_HZ as u64).expect("watchdog reset within 1 s");
    let t_reset = s.avr.time_s();
    assert!(
        t_reset - t_hang > 0.4 && t_reset - t_hang < 0.8,
        "watchdog fired after {:.3} s (500 ms timeout)",
        t_reset - t_hang
    );
    // After the reset: no pulses until the configuration is loaded, then
    // the pulses of the last frame before the hang (RAM kept them,
    // `board::resume`): neither home nor the interrupted move's target.
    s.avr.clear_edges();
    s.run_for(1.5).unwrap();
    let out = s.avr.uart_output_string();
    assert!(out.contains("info boot config"), "{out}");
    assert!(out.contains("info reset watchdog resume pulses "), "{out}");
    for (p, was) in s.pulses().iter().zip(last) {
        let was = was.expect("pulses before the hang");
        assert!(!p.is_empty());
        assert!(p.iter().all(|(_, w)| *w == was), "after the reset the servos hold {was} us: {p:?}");
    }
    assert!(s.last_pulses()[0] != Some(1500.0) && s.last_pulses()[0] != Some(900.0), "{:?}", s.last_pulses());
    assert!(s.command("status").unwrap().starts_with("ok status holding"));
}

#[test]
fn stack_stays_within_budget_in_the_busiest_session() {
    let mut s = start();
    // Everything at once: telemetry every frame, touches that plan moves,
    // re-plans mid-move, calibration output, an EEPROM save and a
    // calibration slew.
    assert_eq!(s.command("log on").unwrap(), "ok log on");
    let (a, _) = map_touch(0.7, 0.3);
    touch(&mut s, a.0, a.1);
    s.run_for(0.5).unwrap();
    let (b, _) = map_touch(-0.8, 0.15);
    touch(&mut s, b.0, b.1);
    assert!(s.command("goto 45 100 -120").unwrap().starts_with("ok goto"));
    assert_eq!(s.command("law quintic").unwrap(), "ok law quintic");
    assert!(s.command("goto 120 60 -30").unwrap().starts_with("ok goto"));
    s.run_for(0.5).unwrap();
    assert!(s.command("cal show").unwrap().starts_with("ok cal show"));
    assert_eq!(s.command("stop").unwrap(), "ok stop");
    assert!(s.command("cal save").unwrap().starts_with("ok cal save"));
    assert!(s.command("status").unwrap().starts_with("ok status"));
    // A calibration change that slews the held pose plans a move from
    // inside the command handler.
    assert_eq!(s.command("resume").unwrap(), "ok resume");
    assert!(s.command("cal set base offset 650").unwrap().starts_with("ok cal set slew ts_ms"));
    let used = s.stack_high_water().expect("stack painted at load");
    let budget = firmware::budget("stack").unwrap() as usize;
    eprintln!("firmware stack high-water: {used} B of {budget} B");
    assert!(used <= budget, "stack high-water {used} B exceeds the memory.x budget {budget} B");
}

/// Raw reading of a screen pixel's centre on a panel whose true response is `cal`.
fn pixel_raw(cal: &Calibration, x: i16, y: i16) -> (f64, f64) {
    let (px, py) = L.pixel_center_to_panel(x, y);
    let (rx, ry) = cal.unmap_exact::<f64>(px as f64, py as f64).unwrap();
    (rx.round(), ry.round())
}

#[test]
fn on_screen_calibration_learns_the_panel_and_saves_it() {
    let mut s = start();
    // A panel whose true span differs from the defaults, with X inverted.
    let truth =
        Calibration { x_min: 150, x_max: 900, y_min: 100, y_max: 880, swap_xy: false, invert_x: true, invert_y: false };
    // More twice, then the Calibrate button on the Setup page, found
    // through the *current* (default) mapping...
    let k = L.page_key();
    let (kx, ky) = pixel_raw(&Calibration::DEFAULT, k.x + k.w as i16 / 2, k.y + k.h as i16 / 2);
    touch(&mut s, kx, ky);
    s.run_for(0.7).unwrap();
    assert!(s.avr.uart_output_string().contains("info screen page more"), "{}", s.avr.uart_output_string());
    touch(&mut s, kx, ky);
    s.run_for(0.7).unwrap();
    assert!(s.avr.uart_output_string().contains("info screen page setup"), "{}", s.avr.uart_output_string());
    let c = L.calibrate();
    let (bx, by) = pixel_raw(&Calibration::DEFAULT, c.x + c.w as i16 / 2, c.y + c.h as i16 / 2);
    touch(&mut s, bx, by);
    s.run_for(0.4).unwrap();
    assert!(s.avr.uart_output_string().contains("info screen calibrate"), "{}", s.avr.uart_output_string());
    // ...then each crosshair is touched where the true panel reads it.
    for (x, y) in (0..CAL_COUNT).filter_map(|i| cal_pixel(&L, i)) {
        let (rx, ry) = pixel_raw(&truth, x, y);
        touch(&mut s, rx, ry);
        s.run_for(0.4).unwrap();
    }
    // Save, where the new calibration puts the Save button: the touch
    // settings' page follows. Hold + twice (0.10 → 0.12 → 0.15 s), repeat −
    // once (0.30 → 0.20 s), then Save there.
    let save = save_area(&L);
    let centre_raw = |a: touch_arm::ui::draw::Area| pixel_raw(&truth, a.x + a.w as i16 / 2, a.y + a.h as i16 / 2);
    let (sx, sy) = centre_raw(save);
    touch(&mut s, sx, sy);
    s.run_for(0.4).unwrap();
    assert!(!s.avr.uart_output_string().contains("info cal touch saved"), "{}", s.avr.uart_output_string());
    for (field, up) in [(Setting::Hold, true), (Setting::Hold, true), (Setting::Repeat, false)] {
        let (rx, ry) = centre_raw(setting_area(&L, field, up));
        touch(&mut s, rx, ry);
        s.run_for(0.4).unwrap();
    }
    touch(&mut s, sx, sy);
    s.run_for(0.3).unwrap();
    let out = s.avr.uart_output_string();
    let saved = out.lines().find(|l| l.starts_with("info cal touch saved seq")).unwrap_or_else(|| panic!("{out}"));
    assert!(saved.ends_with(" hold 0.15 repeat 0.20 radius 240"), "{saved}");
    // The learned calibration is in use and in EEPROM: `cal show` reports it.
    s.command("cal show").unwrap();
    let out = s.avr.uart_output_string();
    let line = out.lines().rev().find(|l| l.starts_with("cal touch")).expect("cal touch line");
    let field =
        |name: &str| -> i64 { line.split_whitespace().skip_while(|w| *w != name).nth(1).unwrap().parse().unwrap() };
    for (name, want) in [("x_min", 150), ("x_max", 900), ("y_min", 100), ("y_max", 880)] {
        assert!((field(name) - want).abs() <= 3, "{name}: {} vs {want} ({line})", field(name));
    }
    assert_eq!(field("invert_x"), 1, "{line}");
    assert_eq!(field("swap"), 0, "{line}");
    // The crosshair touches measured the panel's plate ratio on the chip:
    // the rig's panel is the twin's model, Ry/Rx = 500/300 Ω = 1.667
    // (`filter::plate_ratio`; within 1 %: the ADC's steps at the crosshairs).
    let plate: f64 = line.split_whitespace().skip_while(|w| *w != "plate").nth(1).unwrap().parse().unwrap();
    assert!((plate / (500.0 / 300.0) - 1.0).abs() < 0.01, "plate {plate} ({line})");
    assert!(out.contains(&format!("plate {plate:.2}")), "{out}");
    // The settings' page's values were stored with the fit.
    assert!(line.contains(" hold 0.15 repeat 0.20 radius 240 plate "), "{line}");
}

#[test]
fn cal_show_prints_the_decimals_it_was_given() {
    // Every two-decimal field goes through the same digit code; values whose
    // hundredths run over 0..99 in both digits, negative ones included. The
    // host twin prints them right, so this is the chip's own arithmetic.
    let mut s = start();
    // Fields that leave the held pulse where it is (no calibration slew).
    let cases = [("max_speed", "171.89"), ("max_speed", "0.05"), ("min_deg", "-0.97"), ("max_deg", "180.58")];
    for (field, value) in cases {
        assert_eq!(s.command(&format!("cal set base {field} {value}")).unwrap(), "ok cal set", "{field} {value}");
        s.command("cal show").unwrap();
        s.run_for(0.2).unwrap();
        let out = s.avr.uart_output_string();
        let line = out.lines().rev().find(|l| l.starts_with("cal base")).expect("cal base line");
        let got = line.split_whitespace().skip_while(|w| *w != field).nth(1).unwrap();
        assert_eq!(got, value, "{line}");
    }
}
