//! The main job: run the real firmware ELF in simavr, touch the simulated
//! panel once (twice with `--then`: a second map touch mid-move), and
//! record what the servos receive.
//!
//! Writes to the output directory (default `out/`):
//! - `pulses.csv`: every measured servo pulse, `t_s,base_us,shoulder_us,elbow_us`
//!   (µs to the timer's 0.5 µs tick), with `--grip` one more column, `grip_us`:
//!   the gripper's pulse of the same period (D11, Timer1, started with Timer5);
//! - `summary.json`: `{raw, x_p, y_p, condition, alpha_deg, q, target_pulses_us,
//!   final_pulses_us, arrival_s, law, ts_s, wiring, touches}` for the point the arm ends on,
//!   `path` (joint or line) and `lift_h` (null without a lift), and with
//!   `--then` `first_raw`, `then_delay_ms`, `then_confirmed_after_s`,
//!   `then_ts_s`, `then_reply`; with `--grip` `grip`, `grip_reply`,
//!   `grip_ts_s`, `grip_final_us`;
//! - `angles.png`: each joint's angle (from the pulses through the default
//!   calibration) and angular velocity over time;
//! - `effector.csv`: `t_s,x,y,z`, where the measured pulses put the effector
//!   (through the default calibration and the forward kinematics);
//! - `path.png`: top and side views of that effector path, start and target
//!   (and with `--lift` the via pose) marked, and the joint angles;
//! - `screen.png`: the final screen, decoded from the firmware's LCD bus writes,
//!   at the panel's size.
//!
//! `--path line` sends `path line` over serial before the touch (the effector
//! moves along the straight segment); `--lift H` sends `lift H` (the move
//! passes the via pose H above the higher end, marked `via` in `path.png`).
//! Both are answered when the firmware's check decides, some frames after
//! the touch; they exclude each other and `--then` (nothing is superposed on
//! a path or lift move).
//!
//! `--lcd` chooses the display controller simulated around the same ELF
//! (ili9341, st7789, ili9486, ili9325 or st7796; the firmware probes it at boot),
//! `--wiring` the pins the touch panel is on (a, b or c; the firmware
//! measures it at boot and prints `info wiring …`). Wiring c is the same two
//! plates as b with X and Y exchanged and reversed, so the firmware reads it
//! as b, mirrored: the job then sets over serial the touch calibration the
//! calibration screen finds for it (swap, both inversions, the span
//! mirrored), so the same map point is touched on every wiring. `summary.json`
//! gains `wiring`, the one the firmware reported.
//!
//! `--grip open|close` sends `grip open` or `grip close` once the move has
//! arrived and records the gripper's pulses until it rests (the first grip
//! after power-up runs at the slow preset).
//!
//! `--reset` pulls the RESET pin once the arm has arrived (after the grip,
//! with `--grip`), in the middle of a PWM period (a reset during a pulse
//! cuts that pulse short, on the chip too): the chip restarts with its RAM, and the firmware resumes
//! the pulses the servos had (issue #21 §1). `pulses.csv` runs on through
//! the reboot (no row for the ~0.3 s without pulses while it boots), and
//! `summary.json` gains `reset_line` (the firmware's `info reset …`),
//! `reset_at_s`, `reset_gap_s` (from the last pulse before to the first
//! after), `pulses_before_reset_us` and `pulses_after_reset_us` (the last
//! and the first, per joint).
//!
//! A `--raw` press on a button or a guard band moves nothing: the job prints
//! what the screen did with it and writes `screen.png` only.
//!
//! `--finger FILE` replaces the press with a finger script (`hal_sim::finger`):
//! a CSV with header `t_ms,x_px,y_px,force` (optionally `,x2_px,y2_px,force2`
//! for a second contact), in the screen's pixels, started once the firmware
//! is ready and evaluated at each ADC conversion's own cycle. The job runs
//! until 1 s after the script's last knot; the arm's end point is the last
//! `move`. Without any move it writes `screen.png` and a `summary.json` of
//! `touches` (and `wiring`) only.
//!
//! `--switch T1,T2,…` replaces the press with the assistive switch (issue
//! #20 §4, D22 = PA0, pressed = driven low): once the arm has homed the job
//! sends `switch on` (the firmware starts scanning: a column line, then a
//! row line over the map, then Go and Cancel) and presses the switch at
//! each time, in ms after the firmware's `ok switch on` reply, holding PA0
//! low for 200 ms each. The job runs until 1 s after the last release; the
//! arm's end point is the pixel of the last `info switch go <px> <py>`, and
//! `arrival_s` counts from that line. Without a go (or when the go's move
//! is refused) it writes `screen.png` and a `summary.json` of `touches`,
//! `wiring`, `switch_ms` and `switch` only. `summary.json` gains `switch_ms`
//! (the times asked) and `switch`: every `info switch …` line, `[{t_s,
//! line}]`, `t_s` from the reply.
//!
//! `touches` (every run) lists every action the firmware took on a touch,
//! from its own serial lines (`hal_sim::touches`): `[{t_s, action, x_p,
//! y_p}]`, `t_s` from the start of the press or script, `action` one of
//! `move`, `stop`, `resume`, `cancel`, `ignored` or a button's word (`speed`,
//! `page`, `pose`, `grip`, `path`, `lift`, `calibrate`), `x_p`/`y_p` the map
//! point of the line's raw reading (default calibration; `null` for lines
//! without one or off the map). `err touch <x> <y> <reason>` (a refused map
//! touch, nothing moves) is `ignored` with its point.

use std::path::PathBuf;
use std::process::ExitCode;

use armsim::args::{parse_pair, parse_raw};
use armsim::plot::{self, Curve, Panel};
use armsim::report::Json;
use clap::Parser;
use touch_arm_bench::shield;
use touch_arm_rig::firmware::{self, Session};
use touch_arm_rig::lcd_bus::Chip;
use touch_arm_rig::panel::PanelWiring;

/// Runs the firmware in simavr, touches the panel once (or presses the assistive switch, --switch) and writes DIR/pulses.csv,
/// DIR/summary.json, DIR/angles.png, DIR/effector.csv, DIR/path.png and DIR/screen.png. A press that lands on a
/// button or between the screen's regions moves nothing: the job says what the
/// screen did with it and writes DIR/screen.png only.
#[derive(Parser, Debug)]
#[command(name = "touch-arm-sim")]
struct Args {
    /// A workspace point picked on the screen's map, in [-1,1]x[0,1] [default: 0.4,0.6]
    #[arg(long, value_name = "X,Y", value_parser = map_point, allow_hyphen_values = true)]
    xy: Option<(f64, f64)>,
    /// The display controller on the simulated shield: ili9341, st7789, ili9486, ili9325 or st7796
    #[arg(long, value_name = "CONTROLLER", value_parser = shield::lcd_chip, default_value = "ili9341")]
    lcd: Chip,
    /// The touch panel's wiring on the simulated shield: a, b or c
    #[arg(long, value_name = "WIRING", value_parser = shield::panel_wiring, default_value = "a")]
    wiring: PanelWiring,
    /// A raw panel reading (ADC counts 0..=1023), wherever it lands: map, button or nothing
    #[arg(long, value_name = "X,Y", value_parser = parse_raw, conflicts_with = "xy")]
    raw: Option<(u16, u16)>,
    /// The firmware ELF [default: target/avr-none/release/touch-arm.elf, or $TOUCH_ARM_ELF]
    #[arg(long, value_name = "FILE")]
    elf: Option<PathBuf>,
    /// Output directory
    #[arg(long, value_name = "DIR", default_value = "out")]
    out: PathBuf,
    /// A second map touch MS ms after the first is confirmed (mid-move: the firmware re-plans)
    #[arg(long, value_name = "X2,Y2@MS", value_parser = then_touch, allow_hyphen_values = true)]
    then: Option<Then>,
    /// The motion law, sent over serial (`law <LAW>`) before the touch [default: the firmware's, zat]
    #[arg(long, value_name = "LAW", value_parser = ["zat", "zat-paper", "quintic", "cubic", "trapezoid", "linear"])]
    law: Option<String>,
    /// A grip command sent after the move (`grip open` or `grip close`); pulses.csv gains grip_us
    #[arg(long, value_name = "open|close", value_parser = ["open", "close"])]
    grip: Option<String>,
    /// How the target is reached, sent over serial (`path <PATH>`) before the touch [default: joint]
    #[arg(long, value_name = "PATH", value_parser = ["joint", "line"], conflicts_with_all = ["then", "lift"])]
    path: Option<String>,
    /// Lift by H (workspace units, 0 < H <= 0.5, two decimals at most) through a via pose, sent over serial (`lift H`) before the touch
    #[arg(long, value_name = "H", value_parser = lift_height, conflicts_with = "then")]
    lift: Option<u8>,
    /// An external reset (the RESET pin, RAM kept) once the arm has arrived; pulses.csv runs on through the reboot
    #[arg(long)]
    reset: bool,
    /// A finger script instead of the press: CSV t_ms,x_px,y_px,force[,x2_px,y2_px,force2] in screen pixels
    #[arg(long, value_name = "FILE", conflicts_with_all = ["xy", "raw", "then"])]
    finger: Option<PathBuf>,
    /// Switch presses instead of the press: `switch on` once homed, then PA0 held low 200 ms at each time (ms after the reply; increasing, each at least 200 ms after the one before, at most 60000)
    #[arg(long, value_name = "T1,T2,...", value_parser = switch_times, allow_hyphen_values = true, conflicts_with_all = ["xy", "raw", "then", "finger"])]
    switch: Option<SwitchTimes>,
}

/// `--switch T1,T2,…`: when the switch is pressed, ms after the firmware's
/// `ok switch on` (a newtype: clap would read a bare `Vec` as repeated
/// values).
#[derive(Debug, Clone)]
struct SwitchTimes(Vec<u32>);

/// How long each `--switch` press holds PA0 low: twice the firmware's
/// default `hold` (0.10 s), so a press counts under it.
const SWITCH_PRESS_MS: u32 = 200;
/// The last `--switch` time allowed, ms (as a finger script's last knot).
const SWITCH_MAX_MS: u32 = 60_000;
/// Time the job runs on after the last switch release, s (a Go's move is
/// answered once planned).
const SWITCH_TAIL_S: f64 = 1.0;

fn switch_times(s: &str) -> Result<SwitchTimes, String> {
    let mut times: Vec<u32> = Vec::new();
    for w in s.split(',') {
        let w = w.trim();
        let t: u32 = w.parse().map_err(|_| {
            format!("each time must be a whole number of milliseconds (T1,T2,...: ms after `switch on`), got {w:?}")
        })?;
        if t > SWITCH_MAX_MS {
            return Err(format!("each time must be at most {SWITCH_MAX_MS} ms, got {t}"));
        }
        if let Some(&prev) = times.last() {
            if t < prev + SWITCH_PRESS_MS {
                return Err(format!(
                    "the times must increase, each at least {SWITCH_PRESS_MS} ms after the one before (a press holds the switch {SWITCH_PRESS_MS} ms): {t} after {prev}"
                ));
            }
        }
        times.push(t);
    }
    Ok(SwitchTimes(times))
}

/// Time the job runs on after a finger script's last knot, s (the new touch
/// logic commits on lift-off; a move's reply comes once planned).
const FINGER_TAIL_S: f64 = 1.0;

/// The touch actions in the firmware's output after byte `from`, with their
/// times from `t0` (s): the JSON array of `summary.json`'s `touches`.
fn touches_json(s: &Session, lay: &touch_arm::ui::Layout, from: usize, t0: f64) -> String {
    let out = s.avr.uart_output();
    let cycles = s.avr.uart_output_cycles();
    let mut items = Vec::new();
    let mut start = from;
    for i in from..out.len() {
        if out[i] != b'\n' {
            continue;
        }
        let line = String::from_utf8_lossy(&out[start..i]).trim_end().to_string();
        let t = cycles.get(start).map_or(f64::NAN, |c| *c as f64 / f64::from(firmware::CPU_HZ)) - t0;
        start = i + 1;
        let Some(a) = hal_sim::touches::touch_action(&line) else { continue };
        let p = a.raw.and_then(|(x, y)| firmware::raw_to_map_point_on(lay, x, y));
        let n = |v: Option<f64>| v.map_or("null".to_string(), armsim::report::num);
        items.push(format!(
            "{{\"t_s\": {}, \"action\": \"{}\", \"x_p\": {}, \"y_p\": {}}}",
            armsim::report::num(t),
            a.action.replace(['"', '\\'], ""),
            n(p.map(|p| p.0)),
            n(p.map(|p| p.1))
        ));
    }
    format!("[{}]", items.join(", "))
}

/// `--lift H`: hundredths of a workspace unit, 1..=50 (what the firmware's
/// `lift` takes).
fn lift_height(s: &str) -> Result<u8, String> {
    let h: f64 = s.trim().parse().map_err(|_| format!("H must be a number, got {s:?}"))?;
    let centi = (h * 100.0).round();
    if !(h > 0.0 && h <= 0.5) || (h * 100.0 - centi).abs() > 1e-9 {
        return Err(format!("H must be in (0, 0.5] with at most two decimals, got {s}"));
    }
    Ok(centi as u8)
}

/// `--then X2,Y2@MS`: where and when the second touch goes.
#[derive(Debug, Clone, Copy)]
struct Then {
    /// The map point (X2, Y2); the raw reading that presses its pixel is
    /// found with the layout of the panel chosen (`--lcd`).
    xy: (f64, f64),
    /// Delay after the first touch's confirmation, ms.
    ms: u32,
}

/// The firmware ignores a contact that starts within `repeat` (0.30 s by
/// default, `cal set touch repeat`) of the last lift-off, and the first tap's
/// lift-off is confirmed a few frames before its reply: a second tap earlier
/// than this would be ignored, not a touch.
const THEN_MIN_MS: u32 = 350;

/// How long the job's finger rests on the glass: a tap well over the
/// firmware's `hold` (0.10 s by default), which acts on the lift-off.
const TAP_S: f64 = 0.3;
/// How long after the lift-off the job waits for the tap's reply.
const REPLY_S: f64 = 0.5;

fn then_touch(s: &str) -> Result<Then, String> {
    let (xy, ms) = s.split_once('@').ok_or_else(|| format!("expected X2,Y2@MS, got {s:?}"))?;
    let ms: u32 = ms.trim().parse().map_err(|_| format!("MS must be a whole number of milliseconds, got {ms:?}"))?;
    if ms < THEN_MIN_MS {
        return Err(format!(
            "MS must be at least {THEN_MIN_MS} (a tap inside the repeat window after a lift-off is ignored), got {ms}"
        ));
    }
    Ok(Then { xy: map_point(xy)?, ms })
}

/// `--xy`: a point of the map (the workspace [-1,1]x[0,1]).
fn map_point(s: &str) -> Result<(f64, f64), String> {
    let (x, y) = parse_pair(s)?;
    if (-1.0..=1.0).contains(&x) && (0.0..=1.0).contains(&y) {
        Ok((x, y))
    } else {
        Err(format!("{x},{y} is not on the map (the workspace is [-1,1]x[0,1])"))
    }
}

fn main() -> ExitCode {
    let args: Args = match armsim::args::parse("touch-arm-sim") {
        Ok(a) => a,
        Err(code) => return code,
    };
    // The docs' commands are checked against this parser (doc_commands test).
    if std::env::var_os(armsim::args::CHECK_ARGS).is_some() {
        return ExitCode::SUCCESS;
    }
    match run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("touch-arm-sim: {e}");
            ExitCode::FAILURE
        }
    }
}

/// What the screen did with a press that is no map touch, from the line the
/// firmware printed for it (`None`: it printed none); `None` for a map touch.
fn off_map(line: Option<&str>) -> Option<String> {
    let Some(line) = line else {
        return Some("the press landed on a guard band or a gap: the screen ignores it and the arm holds".into());
    };
    let words: Vec<&str> = line.split_whitespace().collect();
    Some(match words[..] {
        ["info", "screen", "stop"] => "STOP pressed: the arm holds".into(),
        ["info", "screen", "resume"] => "RESUME pressed: the arm takes targets again".into(),
        ["info", "screen", "speed", preset] => {
            // The button's label: the preset's name capitalized.
            let label: String =
                preset.chars().take(1).flat_map(char::to_uppercase).chain(preset.chars().skip(1)).collect();
            format!("{label} pressed: the next moves run at the {preset} speed")
        }
        ["info", "screen", "calibrate"] => "Calib pressed: the calibration screen opens".into(),
        ["err", "screen", "calibrate", ..] => format!("Calib pressed: refused ({})", words[3..].join(" ")),
        _ => return None,
    })
}

/// The last `move` line (`info touch <x> <y> …`) after byte `from` of the
/// firmware's output, with the time (s) of its first byte.
fn last_move(s: &Session, from: usize) -> Option<(String, f64)> {
    let out = s.avr.uart_output();
    let cycles = s.avr.uart_output_cycles();
    let mut found = None;
    let mut start = from;
    for i in from..out.len() {
        if out[i] == b'\n' {
            let line = String::from_utf8_lossy(&out[start..i]).trim_end().to_string();
            if line.starts_with("info touch ") && hal_sim::touches::touch_action(&line).is_some() {
                found = Some((line, cycles.get(start).map_or(0.0, |c| *c as f64 / f64::from(firmware::CPU_HZ))));
            }
            start = i + 1;
        }
    }
    found
}

/// The raw reading of a `move` action's line.
struct TouchRaw(u16, u16);

fn move_raw(line: &str) -> Option<TouchRaw> {
    let a = hal_sim::touches::touch_action(line)?;
    let (x, y) = a.raw?;
    Some(TouchRaw(x, y))
}

/// The firmware's `info switch …` lines after byte `from`, with their times
/// from `t0` (s): `summary.json`'s `switch`.
fn switch_lines(s: &Session, from: usize, t0: f64) -> Vec<(String, f64)> {
    let out = s.avr.uart_output();
    let cycles = s.avr.uart_output_cycles();
    let mut lines = Vec::new();
    let mut start = from;
    for i in from..out.len() {
        if out[i] == b'\n' {
            let line = String::from_utf8_lossy(&out[start..i]).trim_end().to_string();
            if line.starts_with("info switch ") {
                let t = cycles.get(start).map_or(f64::NAN, |c| *c as f64 / f64::from(firmware::CPU_HZ));
                lines.push((line, t - t0));
            }
            start = i + 1;
        }
    }
    lines
}

/// `summary.json`'s `switch`: `[{"t_s": …, "line": "info switch column 74"}, …]`.
fn switch_json(lines: &[(String, f64)]) -> String {
    let items: Vec<String> = lines
        .iter()
        .map(|(l, t)| format!("{{\"t_s\": {}, \"line\": \"{}\"}}", armsim::report::num(*t), l.replace(['"', '\\'], "")))
        .collect();
    format!("[{}]", items.join(", "))
}

/// What the last `info switch go <px> <py>` after byte `from` led to: the
/// pixel, the line's time and the firmware's answer to the move it started
/// (its first later line carrying a `ts_ms`, or an `err` line), if that has
/// come yet.
struct SwitchGo {
    px: (i16, i16),
    t: f64,
    answer: Option<(String, f64)>,
}

fn last_switch_go(s: &Session, from: usize) -> Option<SwitchGo> {
    let out = s.avr.uart_output();
    let cycles = s.avr.uart_output_cycles();
    let at = |i: usize| cycles.get(i).map_or(0.0, |c| *c as f64 / f64::from(firmware::CPU_HZ));
    let mut go: Option<SwitchGo> = None;
    let mut start = from;
    for i in from..out.len() {
        if out[i] != b'\n' {
            continue;
        }
        let line = String::from_utf8_lossy(&out[start..i]).trim_end().to_string();
        if let Some(rest) = line.strip_prefix("info switch go ") {
            let v: Vec<i16> = rest.split_whitespace().filter_map(|w| w.parse().ok()).collect();
            if let [x, y] = v[..] {
                go = Some(SwitchGo { px: (x, y), t: at(start), answer: None });
            }
        } else if let Some(g) = go.as_mut().filter(|g| g.answer.is_none()) {
            if line.split_whitespace().any(|w| w == "ts_ms") || line.starts_with("err ") {
                g.answer = Some((line, at(start)));
            }
        }
        start = i + 1;
    }
    go
}

/// Writes what a run without a move leaves: `screen.png` and a
/// `summary.json` of `extra` (pairs of key and raw JSON), `wiring` and
/// `touches`; `what` says why on stdout.
fn write_no_move(
    s: &mut Session,
    out: &std::path::Path,
    extra: Vec<(&'static str, String)>,
    touches: String,
    wiring: &str,
    what: &str,
) -> Result<(), String> {
    // Let the screen finish redrawing before it is saved.
    s.run_for(0.2)?;
    std::fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    let screen = out.join("screen.png");
    s.lcd.landscape().save_png(&screen).map_err(|e| format!("{}: {e}", screen.display()))?;
    let mut json = Json::new()
        .set("wiring", armsim::report::Val::Str(wiring.to_string()))
        .set("touches", armsim::report::Val::Raw(touches));
    for (k, v) in extra {
        json = json.set(k, armsim::report::Val::Raw(v));
    }
    let json_path = out.join("summary.json");
    std::fs::write(&json_path, json.render() + "\n").map_err(|e| format!("{}: {e}", json_path.display()))?;
    print_boot(&s.avr.uart_output_string());
    println!("{what}");
    println!("wrote {} and {}", screen.display(), json_path.display());
    Ok(())
}

/// The lines the firmware answers a confirmed press with.
const TOUCH_REPLIES: [&str; 4] = ["info touch ", "err touch ", "info screen ", "err screen "];

fn run(args: Args) -> Result<(), String> {
    let elf = args.elf.unwrap_or_else(firmware::default_elf);
    let out = args.out;
    let lay = args.lcd.layout();
    let on_map = |(x, y): (f64, f64)| {
        firmware::map_touch_on(&lay, x as f32, y as f32).map(|(raw, _)| raw).ok_or("point off the map")
    };
    let then = match args.then {
        Some(t) => Some((t, on_map(t.xy)?)),
        None => None,
    };
    let raw = match (args.raw, args.xy) {
        (Some((x, y)), _) => (f64::from(x), f64::from(y)),
        (None, Some(xy)) => on_map(xy)?,
        (None, None) => on_map((0.4, 0.6))?,
    };
    let script = match &args.finger {
        Some(p) => {
            let text = std::fs::read_to_string(p).map_err(|e| format!("{}: {e}", p.display()))?;
            Some(hal_sim::finger::FingerScript::parse_csv(&text).map_err(|e| format!("{}: {e}", p.display()))?)
        }
        None => None,
    };

    let mut s = Session::start_with_lcd(&elf, args.wiring, args.lcd, 1)?;
    s.run_for(1.5)?;
    s.run_until_ready(2.0)?;
    let boot = s.avr.uart_output_string();
    let found = boot
        .lines()
        .find_map(|l| l.strip_prefix("info wiring "))
        .ok_or_else(|| format!("the firmware did not identify the touch wiring:\n{boot}"))?
        .to_string();
    if args.wiring == PanelWiring::C {
        for cmd in shield::calibration_lines(args.wiring) {
            let reply = s.command(&cmd)?;
            if reply != "ok cal set" {
                return Err(format!("the firmware refused `{cmd}`: {reply}"));
            }
        }
    }
    let law = match &args.law {
        Some(l) => {
            let reply = s.command(&format!("law {l}"))?;
            if reply != format!("ok law {l}") {
                return Err(format!("the firmware refused `law {l}`: {reply}"));
            }
            l.clone()
        }
        None => "zat".to_string(),
    };
    let path = args.path.clone().unwrap_or_else(|| "joint".to_string());
    if path != "joint" {
        let reply = s.command(&format!("path {path}"))?;
        if reply != format!("ok path {path}") {
            return Err(format!("the firmware refused `path {path}`: {reply}"));
        }
    }
    let lift = args.lift.map(|c| f64::from(c) / 100.0);
    if let Some(h) = lift {
        let reply = s.command(&format!("lift {h:.2}"))?;
        if reply != format!("ok lift {h:.2}") {
            return Err(format!("the firmware refused `lift {h:.2}`: {reply}"));
        }
    }
    // A path or lift move is answered when its check decides, some frames on.
    let deferred = path != "joint" || lift.is_some();
    // The switch's scan starts with the firmware's answer to `switch on`:
    // the presses count from it.
    if args.switch.is_some() {
        let reply = s.command("switch on")?;
        if !reply.starts_with("ok switch on") {
            return Err(format!("the firmware refused `switch on`: {reply}"));
        }
    }
    let t_touch = s.avr.time_s();
    let from = s.avr.uart_output().len();
    let touch_from = from;
    let mut raw = raw;
    let mut first;
    // With `--switch`: the go line's time and the summary's switch keys.
    let mut switch_go: Option<(f64, Vec<(&'static str, String)>)> = None;
    if let Some(script) = script {
        let glass = hal_sim::finger::Glass::for_size(lay.width(), lay.height())
            .ok_or_else(|| format!("no glass of {}x{}", lay.width(), lay.height()))?;
        s.set_glass(glass);
        let end_s = script.end_ms() / 1000.0;
        s.finger(script);
        s.run_for(end_s + FINGER_TAIL_S)?;
        // The arm ends on the last move; its reply may come later under a path or lift check.
        first = last_move(&s, from);
        if first.is_none() && deferred {
            first = s.await_line(from, &["info touch "], 5.0)?;
        }
        let Some((line, _)) = &first else {
            let touches = touches_json(&s, &lay, touch_from, t_touch);
            return write_no_move(&mut s, &out, Vec::new(), touches, &found, "finger script: no move");
        };
        if let Some(TouchRaw(x, y)) = move_raw(line) {
            raw = (f64::from(x), f64::from(y));
        }
    } else if let Some(SwitchTimes(times)) = &args.switch {
        for &ms in times {
            s.run_for((t_touch + f64::from(ms) / 1000.0 - s.avr.time_s()).max(0.0))?;
            s.set_switch(true)?;
            s.run_for(f64::from(SWITCH_PRESS_MS) / 1000.0)?;
            s.set_switch(false)?;
        }
        s.run_for(SWITCH_TAIL_S)?;
        let mut go = last_switch_go(&s, from);
        // A path or lift move is answered once its check has decided.
        let end = s.avr.time_s() + 5.0;
        while go.as_ref().is_some_and(|g| g.answer.is_none()) && s.avr.time_s() < end {
            s.run_for(0.1)?;
            go = last_switch_go(&s, from);
        }
        let lines = switch_lines(&s, from, t_touch);
        for (l, t) in &lines {
            println!("switch at {t:.3} s: {l}");
        }
        let extra = || {
            let ms: Vec<String> = times.iter().map(u32::to_string).collect();
            vec![("switch_ms", format!("[{}]", ms.join(", "))), ("switch", switch_json(&lines))]
        };
        let touches = touches_json(&s, &lay, touch_from, t_touch);
        let Some(g) = go else {
            return write_no_move(&mut s, &out, extra(), touches, &found, "switch presses: no go, no move");
        };
        let answer = match g.answer {
            Some((a, t)) if !a.starts_with("err") => (a, t),
            other => {
                let why = other.map_or("no answer to the move".to_string(), |(a, _)| a);
                let what = format!("switch go at pixel ({}, {}): no move ({why})", g.px.0, g.px.1);
                return write_no_move(&mut s, &out, extra(), touches, &found, &what);
            }
        };
        // The end point: the raw reading of the answer when it names one
        // (`info touch <x> <y> …`), else the one of the chosen pixel's centre
        // (the host's chain below takes a raw reading).
        raw = match move_raw(&answer.0) {
            Some(TouchRaw(x, y)) => (f64::from(x), f64::from(y)),
            None => firmware::raw_at_pixel(&lay, g.px.0, g.px.1)
                .ok_or_else(|| format!("pixel ({}, {}) has no raw reading", g.px.0, g.px.1))?,
        };
        switch_go = Some((g.t, extra()));
        first = Some(answer);
    } else {
        // A tap: the firmware acts on the lift-off (issue #19).
        s.press_raw(raw.0, raw.1)?;
        s.run_for((t_touch + TAP_S - s.avr.time_s()).max(0.0))?;
        s.release();
        first = s.await_line(from, &TOUCH_REPLIES, REPLY_S)?;
        if first.is_none() && deferred {
            first = s.await_line(from, &TOUCH_REPLIES, 5.0)?;
        }
    }
    let text = s.avr.uart_output_string();
    let line = first.as_ref().map(|(l, _)| l.clone());
    // No reply is right only off the map (a guard band or gap); on it, a fault.
    let on_map = firmware::raw_to_map_point_on(&lay, raw.0 as u16, raw.1 as u16).is_some();
    if let Some(what) = off_map(line.as_deref()).filter(|_| line.is_some() || !on_map) {
        // Let the screen finish redrawing before it is saved.
        s.run_for(0.2)?;
        std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
        let screen = out.join("screen.png");
        s.lcd.landscape().save_png(&screen).map_err(|e| format!("{}: {e}", screen.display()))?;
        print_boot(&text);
        println!("touch at raw ({}, {}): {what}", raw.0, raw.1);
        if let Some(line) = &line {
            println!("firmware: {line}");
        }
        println!("no move: wrote {} only", screen.display());
        return Ok(());
    }
    let Some((line, t_confirm)) = first else { return Err(format!("the firmware did not report the touch:\n{text}")) };
    if line.starts_with("err") {
        return Err(format!("the firmware refused the touch: {line}"));
    }
    let ts = firmware::reply_ts(&line)?;
    // The last touch decides where the arm ends up.
    let (mut end_raw, mut end_ts, mut end_t) = (raw, ts, t_confirm);
    let mut second = None;
    if let Some((then, then_raw)) = then {
        s.run_for((t_confirm + f64::from(then.ms) / 1000.0 - s.avr.time_s()).max(0.0))?;
        let from = s.avr.uart_output().len();
        s.press_raw(then_raw.0, then_raw.1)?;
        s.run_for(TAP_S)?;
        s.release();
        let reply = s.await_line(from, &TOUCH_REPLIES, REPLY_S)?;
        let Some((line2, t2)) = reply else {
            return Err(format!("the firmware did not report the second touch:\n{}", s.avr.uart_output_string()));
        };
        if !line2.starts_with("info touch ") {
            return Err(format!("the firmware refused the second touch: {line2}"));
        }
        (end_raw, end_ts, end_t) = (then_raw, firmware::reply_ts(&line2)?, t2);
        second = Some((then, line2, t2 - t_confirm));
    }
    s.run_for((end_t + end_ts + 1.0 - s.avr.time_s()).max(0.0))?;
    // The grip after the move: its reply, and its pulses until it rests.
    let grip = match &args.grip {
        Some(g) => {
            let reply = s.command(&format!("grip {g}"))?;
            if !reply.starts_with("ok grip ") {
                return Err(format!("the firmware refused `grip {g}`: {reply}"));
            }
            let ts = firmware::reply_ts(&reply)?;
            s.run_for(ts + 0.5)?;
            Some((g.clone(), reply, ts))
        }
        None => None,
    };
    // The RESET pin once the arm rests: the firmware reboots with its RAM.
    let reset = if args.reset {
        // In the middle of a PWM period, clear of the pulses (at most 2.5 ms
        // after each period start): a reset during one cuts it short, on the
        // chip as here (a twitch towards a shorter pulse).
        if let Some((last, _)) = s.pulse_ticks()[0].last().copied() {
            let period = 0.02;
            let phase = (s.avr.time_s() - last).rem_euclid(period);
            s.run_for((period / 2.0 - phase).rem_euclid(period).max(1e-6))?;
        }
        let from = s.avr.uart_output().len();
        let at = s.avr.time_s();
        s.avr.external_reset();
        let Some((line, _)) = s.await_line(from, &["info reset "], 3.0)? else {
            return Err(format!(
                "no `info reset` line after the external reset:\n{}",
                String::from_utf8_lossy(&s.avr.uart_output()[from..])
            ));
        };
        s.run_for(1.0)?;
        Some((at, line))
    } else {
        None
    };
    let first_raw = raw;
    let raw = end_raw;
    // Where the move starts: the press, or the switch's go.
    let t_start = switch_go.as_ref().map_or(t_touch, |(t, _)| *t);

    // Host f64 reference of the same chain (method.md §3–6) for the summary.
    let (x_p, y_p) = firmware::raw_to_map_point_on(&lay, raw.0 as u16, raw.1 as u16)
        .ok_or_else(|| format!("raw ({}, {}) is not on the screen's map", raw.0, raw.1))?;
    let host = firmware::host_target(x_p, y_p)?;
    let (pose, q, target) = (host.pose, host.q, host.pulses_us);
    let maps = firmware::default_servo_maps()?;

    let trains = s.pulses();
    let n = trains.iter().map(Vec::len).min().unwrap_or(0);
    if n == 0 {
        return Err("no servo pulses measured".into());
    }
    let finals: Vec<f64> = trains.iter().map(|p| p[n - 1].1).collect();
    // Arrival: the first pulse after which every joint stays within 1 µs of its final width.
    let settled = |i: usize| (0..3).all(|j| trains[j][i..n].iter().all(|(_, w)| (w - finals[j]).abs() <= 1.0));
    let first_settled = (0..n).find(|&i| settled(i)).unwrap_or(n - 1);
    let arrival = trains[0][first_settled].0 - t_start;

    // The gripper's pulse of each row's period: its rise within a timer tick
    // of the base's (both timers start on the same prescaler edge).
    let grip_rows: Vec<Option<f64>> = if grip.is_some() {
        let g = s.grip_pulse_ticks();
        let per_tick = 1.0 / f64::from(firmware::CPU_HZ);
        let mut k = 0;
        trains[0]
            .iter()
            .take(n)
            .map(|(t, _)| {
                while k < g.len() && (g[k].0 as f64) * per_tick < t - 1e-3 {
                    k += 1;
                }
                g.get(k).filter(|(c, _)| ((*c as f64) * per_tick - t).abs() <= 1e-3).map(|(_, w)| f64::from(*w) / 2.0)
            })
            .collect()
    } else {
        Vec::new()
    };
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut csv = String::from(if grip.is_some() {
        "t_s,base_us,shoulder_us,elbow_us,grip_us\n"
    } else {
        "t_s,base_us,shoulder_us,elbow_us\n"
    });
    for (i, ((b, s), e)) in trains[0].iter().zip(&trains[1]).zip(&trains[2]).take(n).enumerate() {
        csv += &format!("{:.6},{:.1},{:.1},{:.1}", b.0, b.1, s.1, e.1);
        if grip.is_some() {
            // Empty before the gripper's first pulse.
            csv += &grip_rows.get(i).copied().flatten().map_or(",".to_string(), |w| format!(",{w:.1}"));
        }
        csv += "\n";
    }
    let csv_path = out.join("pulses.csv");
    std::fs::write(&csv_path, csv).map_err(|e| format!("{}: {e}", csv_path.display()))?;

    let list = |v: &[f64]| format!("[{}]", v.iter().map(|x| armsim::report::num(*x)).collect::<Vec<_>>().join(", "));
    let json = Json::new()
        .set("raw", armsim::report::Val::Raw(format!("[{}, {}]", raw.0, raw.1)))
        .set("x_p", x_p)
        .set("y_p", y_p)
        .set("condition", pose.condition.number())
        .set("alpha_deg", pose.alpha.to_degrees())
        .set("q", armsim::report::Val::Raw(list(&q)))
        .set("target_pulses_us", armsim::report::Val::Raw(list(&target)))
        .set("final_pulses_us", armsim::report::Val::Raw(list(&finals)))
        .set("arrival_s", arrival)
        .set("law", armsim::report::Val::Str(law))
        .set("ts_s", ts)
        .set("wiring", armsim::report::Val::Str(found.clone()))
        .set("path", armsim::report::Val::Str(path))
        .set("lift_h", armsim::report::Val::Raw(lift.map_or("null".to_string(), armsim::report::num)))
        .set("touches", armsim::report::Val::Raw(touches_json(&s, &lay, touch_from, t_touch)));
    let json = match &second {
        Some((then, line2, after)) => json
            .set("first_raw", armsim::report::Val::Raw(format!("[{}, {}]", first_raw.0, first_raw.1)))
            .set("then_delay_ms", then.ms)
            .set("then_confirmed_after_s", *after)
            .set("then_ts_s", end_ts)
            .set("then_reply", armsim::report::Val::Str(line2.clone())),
        None => json,
    };
    let json = match switch_go {
        Some((_, extra)) => extra.into_iter().fold(json, |j, (k, v)| j.set(k, armsim::report::Val::Raw(v))),
        None => json,
    };
    let json = match &grip {
        Some((g, reply, ts)) => json
            .set("grip", armsim::report::Val::Str(g.clone()))
            .set("grip_reply", armsim::report::Val::Str(reply.clone()))
            .set("grip_ts_s", *ts)
            .set("grip_final_us", grip_rows.iter().rev().find_map(|w| *w).unwrap_or(f64::NAN)),
        None => json,
    };
    // The last pulse before the reset and the first after, per joint.
    let around = reset.as_ref().map(|(at, _)| {
        let last =
            |j: usize| trains[j].iter().take(n).rev().find(|(t, _)| t < at).copied().unwrap_or((f64::NAN, f64::NAN));
        let next = |j: usize| trains[j].iter().take(n).find(|(t, _)| t > at).copied().unwrap_or((f64::NAN, f64::NAN));
        let before: Vec<f64> = (0..3).map(|j| last(j).1).collect();
        let after: Vec<f64> = (0..3).map(|j| next(j).1).collect();
        (before, after, next(0).0 - last(0).0)
    });
    let json = match (&reset, &around) {
        (Some((at, line)), Some((before, after, gap))) => json
            .set("reset_line", armsim::report::Val::Str(line.clone()))
            .set("reset_at_s", *at)
            .set("reset_gap_s", *gap)
            .set("pulses_before_reset_us", armsim::report::Val::Raw(list(before)))
            .set("pulses_after_reset_us", armsim::report::Val::Raw(list(after))),
        _ => json,
    }
    .render();
    let json_path = out.join("summary.json");
    std::fs::write(&json_path, json.clone() + "\n").map_err(|e| format!("{}: {e}", json_path.display()))?;

    // Angles back from the pulses through the calibration, and their rates.
    let t: Vec<f64> = (0..n).map(|i| trains[0][i].0).collect();
    let ang: Vec<Vec<f64>> = (0..3)
        .map(|j| (0..n).map(|i| maps[j].pulse_to_angle::<f64>((trains[j][i].1 * 2.0) as u16).to_degrees()).collect())
        .collect();
    let vel: Vec<Vec<f64>> = ang
        .iter()
        .map(|a| (0..n).map(|i| if i == 0 { 0.0 } else { (a[i] - a[i - 1]) / (t[i] - t[i - 1]) }).collect())
        .collect();
    let names = ["base", "shoulder", "elbow"];
    let png = out.join("angles.png");
    plot::panels(
        &png,
        "firmware in simavr: joint angles from the measured servo pulses",
        &t,
        &[
            Panel { ylabel: "angle [deg]", curves: curves(&names, &ang) },
            Panel { ylabel: "velocity [deg/s]", curves: curves(&names, &vel) },
        ],
    )
    .map_err(|e| e.to_string())?;

    // Where the measured pulses put the effector, and its path.
    let links = firmware::host_geometry()?.links;
    let eff: Vec<[f64; 3]> = (0..n)
        .map(|i| firmware::effector_at(&maps, &links, &[trains[0][i].1, trains[1][i].1, trains[2][i].1]))
        .collect();
    let mut ecsv = String::from("t_s,x,y,z\n");
    for (ti, p) in t.iter().zip(&eff) {
        ecsv += &format!("{ti:.6},{:.9},{:.9},{:.9}\n", p[0], p[1], p[2]);
    }
    let eff_path = out.join("effector.csv");
    std::fs::write(&eff_path, ecsv).map_err(|e| format!("{}: {e}", eff_path.display()))?;
    // The move starts from where the arm was when the panel was touched (or the switch's go came).
    let start = eff[t.iter().position(|&ti| ti >= t_start).unwrap_or(0)];
    let (tx, ty, tz) = touch_arm::geometry::ik::fk3(&links, q[0], q[1], q[2]);
    let col = |k: usize| eff.iter().map(|p| p[k]).collect::<Vec<f64>>();
    let (ex, ey, ez) = (col(0), col(1), col(2));
    let (mut top_marks, mut side_marks) = (
        vec![("start", start[0], start[1]), ("target", tx, ty), ("base", 0.0, 0.0)],
        vec![("start", start[0], start[2]), ("target", tx, tz)],
    );
    if let Some(h) = lift {
        let v = via_point(&start, &[tx, ty, tz], h * firmware::host_geometry()?.k);
        top_marks.push(("via", v[0], v[1]));
        side_marks.push(("via", v[0], v[2]));
    }
    let views = [
        plot::View { title: "top view", xlabel: "x", ylabel: "y", x: &ex, y: &ey, marks: top_marks },
        plot::View { title: "side view", xlabel: "x", ylabel: "z", x: &ex, y: &ez, marks: side_marks },
    ];
    let path_png = out.join("path.png");
    plot::path_figure(
        &path_png,
        "firmware in simavr: effector path from the measured servo pulses",
        &views,
        &t,
        &Panel { ylabel: "angle [deg]", curves: curves(&names, &ang) },
    )
    .map_err(|e| e.to_string())?;

    let screen = out.join("screen.png");
    s.lcd.landscape().save_png(&screen).map_err(|e| format!("{}: {e}", screen.display()))?;

    print_boot(&text);
    println!(
        "touch at raw ({}, {}) -> map point x_p {:.4}, y_p {:.4}, condition {}, alpha {:.2} deg",
        raw.0,
        raw.1,
        x_p,
        y_p,
        pose.condition.number(),
        pose.alpha.to_degrees()
    );
    println!("firmware: {line}");
    if let Some((then, line2, after)) = &second {
        println!(
            "second touch at raw ({}, {}), confirmed {:.3} s after the first ({} ms asked): {line2}",
            end_raw.0, end_raw.1, after, then.ms
        );
    }
    println!(
        "IK (host f64): base {:.2} deg, shoulder {:.2} deg, elbow {:.2} deg",
        q[0].to_degrees(),
        q[1].to_degrees(),
        q[2].to_degrees()
    );
    println!("pulses target {:?} us, measured final {:?} us, settled {:.2} s after the touch", target, finals, arrival);
    if let Some((_, reply, _)) = &grip {
        let last = grip_rows.iter().rev().find_map(|w| *w).unwrap_or(f64::NAN);
        println!("firmware: {reply}; gripper pulse at the end {last} us");
    }
    if let (Some((at, line)), Some((before, after, gap))) = (&reset, &around) {
        println!(
            "external reset at {at:.3} s: firmware: {line}; pulses {before:?} us before, {after:?} us after ({gap:.3} s without pulses)"
        );
    }
    println!(
        "wrote {}, {}, {}, {}, {}, {}",
        csv_path.display(),
        json_path.display(),
        png.display(),
        eff_path.display(),
        path_png.display(),
        screen.display()
    );
    Ok(())
}

/// The via pose's effector point of a lift by `h` (arm units) from the
/// effector `a` to `b` (motion::lift, docs/method.md §8.2): h above the
/// higher end, halfway in base rotation and in reach.
fn via_point(a: &[f64; 3], b: &[f64; 3], h: f64) -> [f64; 3] {
    let (rho_a, rho_b) = (a[0].hypot(a[1]), b[0].hypot(b[1]));
    let base = (a[1].atan2(a[0]) + b[1].atan2(b[0])) / 2.0;
    let rho = (rho_a + rho_b) / 2.0;
    [rho * base.cos(), rho * base.sin(), a[2].max(b[2]) + h]
}

/// The firmware's first line and what it said about the display.
fn print_boot(text: &str) {
    println!("{}", text.lines().next().unwrap_or(""));
    for prefix in [["info lcd ", "warn lcd "], ["info wiring ", "err touch wiring "]] {
        if let Some(l) = text.lines().find(|l| prefix.iter().any(|p| l.starts_with(p))) {
            println!("{l}");
        }
    }
}

fn curves<'a>(names: &[&'a str; 3], data: &'a [Vec<f64>]) -> Vec<Curve<'a>> {
    data.iter().zip(names).map(|(y, label)| Curve { label, y }).collect()
}
