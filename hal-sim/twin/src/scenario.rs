//! Scenario files: a touch, a delay, a serial line at a time, with
//! expectations on the app's and the twin's state.
//!
//! # Format
//! One directive per line; `#` starts a comment (outside quotes); blank lines
//! are ignored. Numbers are decimal; durations are `250ms`, `1.5s` or `12f`
//! (frames of 20 ms). Strings are double-quoted with the escapes `\"`, `\\`,
//! `\n`, `\r`, `\t` and `\xNN`.
//!
//! Set-up (before the first other directive; they shape the simulation):
//! - `geometry k <k>`: the map's scale (`AppParams::k`); the links' lengths
//!   are the firmware's settings, changed with `send "cal set arm l2 <mm>"`.
//! - `servo_init_deg <b> <s> <e>`: shaft angles at power-up (unknown to the app).
//! - `servo_model speed <rad/s> deadband <µs>`
//! - `seed <n>`: noise seed.
//! - `screen on`: the app runs the touch screen (map and buttons, as the
//!   firmware does), drawn after every frame.
//!
//! Actions:
//! - `panel noise <σ counts>` / `panel spikes <probability>`
//! - `press xy <x_p> <y_p> [force <f>]` / `press raw <x> <y> [force <f>]`:
//!   the finger goes down (and stays until `release` or another press).
//!   `press button <name> [force <f>]`: on the centre of a button of the
//!   320×240 screen, read through the default calibration: `stop` (also
//!   RESUME), `slow`, `normal`, `fast`, `undo`, `more` / `back` (the page
//!   key), `pose1`…`pose4`, `grip`, `calib`, `line`, `lift`: one row of
//!   five slots whose meaning is the page's (Main: Slow Normal Fast Undo
//!   More; More: the poses, More; Setup: Grip Calib Line Lift Back), so a
//!   name presses its slot whatever the page shows.
//! - `finger <t,x,y,f> … [second <t,x,y,f> …]`: a finger script
//!   (`hal_sim::finger`) from the next frame on: knots of t in ms from its
//!   start, x and y in pixels of the 320×240 screen, force (0 no contact, 1
//!   firm), linearly interpolated and evaluated at each conversion; after
//!   `second`, a second contact's knots. It ends by itself after its last knot.
//! - `touch xy|raw|button …` (the same arguments): a tap, as the app acts
//!   on lift-off (issue #19): the press, 200 ms held ([`TAP_FRAMES`]), the
//!   release and the 80 ms ([`LIFT_FRAMES`]) in which the release is read
//!   and the tap acts. A `release` after it changes nothing.
//! - `release`
//! - `run <duration>`; `run_until <state> within <duration>`: runs at least
//!   one frame (so a line just sent is read), then until the state holds
//!   (fails if not reached)
//! - `send "<line>"` (a newline is appended); `send_raw "<bytes>"` (exactly these)
//! - `reboot`: power cycle (EEPROM kept, servos keep their shafts, pulses stop)
//! - `mark <name>`: remembers the number of frames run; "since <name>" below
//!   checks the frames after it (and the step from the frame before it).
//! - `eeprom corrupt <addr> <byte>`; `eeprom powerloss_after <bytes>`
//!
//! Expectations (`tol` is an absolute tolerance in the value's unit):
//! - `expect state <off|homing|holding|moving|stopped|checking>`
//! - `expect angles_deg <b> <s> <e> tol <deg>`: the app's commanded pose
//! - `expect target_deg <b> <s> <e> tol <deg>`: the app's current target
//! - `expect servo_deg <b> <s> <e> tol <deg>`: the twin servos' shafts
//! - `expect pulses <b> <s> <e> tol <µs>`: the pulses being output
//! - `expect effector <reach> <height> tol <t>`: FK of the servo shafts
//! - `expect no_pulses`; `expect first_pulses <b> <s> <e> at_frame <k>`
//!   (k counts frames since the last boot, from 0)
//! - `expect line "<text>"` / `expect line_starts "<prefix>"` /
//!   `expect line_contains "<text>"`: a serial output line after the cursor
//!   matches; the cursor moves past it. `expect no_line_contains "<text>"`:
//!   no line after the cursor contains it (cursor unchanged);
//!   `expect no_line_starts "<prefix>"` likewise.
//! - `expect lines_starting "<prefix>" <n>`: exactly n lines after the cursor
//!   start with the prefix; the cursor moves to the end of the output.
//! - `expect still since <mark>`: pulses never changed since the frame before the mark
//! - `expect max_step_us <n> [since <mark>]`: largest pulse change between frames
//! - `expect speed_within <pct> [since <mark>]`: every joint's commanded
//!   speed (frame differences) ≤ pct % of its configured max speed
//! - `expect accel_within <pct> [since <mark>]`: every joint's commanded
//!   acceleration (second differences over 20 ms) ≤ pct % of its max_accel
//! - `expect peak_speed_at_least <pct> since <mark>`: some joint reached it
//! - `expect synchronized since <mark> tol <t>`: all moving joints share the
//!   same normalized progress at every frame (within t)
//! - `expect move_ms <ms> tol <ms> since <mark>`: the commanded pose stops
//!   changing for good this long after the mark
//! - `expect on_segment since <mark> tol <t>`: the effector of every commanded
//!   pose (FK, arm units) since the mark lies within t of the segment from
//!   the one before the mark to the last one (a `path line` move)
//! - `expect on_circle <r> since <mark> tol <t>`: ... within t of the circle of
//!   radius r (arm units) in the vertical plane through the base axis and the
//!   pose before the mark, which is its point farthest out (a `circle`)
//! - `expect refusal "<reason>"` / `expect no_refusal`
//! - `expect screen_warning "<text>"`: the warning line the screen shows
//!   (`""` for none)
//! - `expect screen_state "<state>"`: the screen model's state as Rust
//!   prints it (`Holding`, `Refused(Cancelled)`, `Refused(Hand)`, …)
//! - `expect screen_speed slow|normal|fast`: the preset the screen shows
//!   pressed (the one in effect under the carer's cap)
//! - `expect preview shown|none`: the candidate marker under a finger on
//!   the map
//!
//! The gripper (the fourth channel):
//! - `expect grip_deg <deg> tol <deg>`: the app's commanded gripper angle
//! - `expect grip_pulse <µs> tol <µs>`: the gripper pulse being output
//! - `expect grip_servo_deg <deg> tol <deg>`: the twin gripper's shaft
//! - `expect no_grip_pulses`: no gripper pulse in any frame run so far;
//!   `expect first_grip_pulse <µs> at_frame <k>` (k counts frames since the
//!   last boot)
//! - `expect grip_still since <mark>`: its pulse never changed since the
//!   frame before the mark
//! - `expect grip_max_step_us <n> since <mark>`: its largest pulse change
//!   between frames
//! - `expect grip_speed_within <pct> since <mark>`: its commanded speed
//!   (frame differences) ≤ pct % of its configured max speed
//! - `expect grip_move_ms <ms> tol <ms> since <mark>`: its commanded angle
//!   stops changing for good this long after the mark
//!
//! Every scenario also checks at its end that no pulse outside a servo's
//! configured range (the gripper's included) was ever written.

use std::collections::HashMap;
use std::path::Path;

use touch_arm::app::{State, FRAME_MS};

use super::sim::{FrameRecord, Sim, SimSetup};

const FRAME_S: f64 = FRAME_MS as f64 / 1000.0;

#[derive(Debug, Clone, PartialEq)]
enum Tok {
    Word(String),
    Str(Vec<u8>),
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum LineMatch {
    Exact,
    Starts,
    Contains,
}

#[derive(Debug, Clone, PartialEq)]
enum Expect {
    State(State),
    Angles([f64; 3], f64),
    Target([f64; 3], f64),
    Servo([f64; 3], f64),
    Pulses([f64; 3], f64),
    Effector(f64, f64, f64),
    NoPulses,
    FirstPulses([u16; 3], u64),
    Line(LineMatch, String),
    NoLineContains(String),
    NoLineStarts(String),
    LinesStarting(String, usize),
    Still(String),
    MaxStepUs(f64, Option<String>),
    SpeedWithin(f64, Option<String>),
    AccelWithin(f64, Option<String>),
    PeakSpeedAtLeast(f64, String),
    Synchronized(String, f64),
    MoveMs(f64, f64, String),
    OnSegment(String, f64),
    OnCircle(f64, String, f64),
    Refusal(String),
    NoRefusal,
    ScreenWarning(String),
    ScreenState(String),
    /// The switch scan as the screen shows it (`Debug` of the model's
    /// `scan`: `None`, `Some(Column(112))`, ...).
    Scan(String),
    /// The scan's `Debug` contains the text.
    ScanContains(String),
    ScreenSpeed(String),
    Preview(bool),
    GripDeg(f64, f64),
    GripPulse(f64, f64),
    GripServo(f64, f64),
    NoGripPulses,
    FirstGripPulse(u16, u64),
    GripStill(String),
    GripMaxStepUs(f64, String),
    GripSpeedWithin(f64, String),
    GripMoveMs(f64, f64, String),
}

#[derive(Debug, Clone, PartialEq)]
enum Step {
    Geometry {
        k: f64,
    },
    ServoInit([f64; 3]),
    ServoModel {
        speed: f64,
        deadband: f64,
    },
    Seed(u64),
    Screen,
    PanelNoise(f64),
    PanelSpikes(f64),
    TouchXy(f64, f64, f64),
    TouchRaw(f64, f64, f64),
    Finger(Box<crate::finger::FingerScript>),
    /// A tap: the press, [`TAP_FRAMES`] held, the release, [`LIFT_FRAMES`].
    Tap(Box<Step>),
    Release,
    /// The assistive switch closed (`true`) or opened.
    Switch(bool),
    Run(u64),
    RunUntil(State, u64),
    Send(Vec<u8>),
    Reboot,
    Mark(String),
    EepromCorrupt(u16, u8),
    EepromPowerLoss(usize),
    Expect(Expect),
}

impl Step {
    fn is_setup(&self) -> bool {
        matches!(
            self,
            Step::Geometry { .. } | Step::ServoInit(_) | Step::ServoModel { .. } | Step::Seed(_) | Step::Screen
        )
    }
}

/// A parsed scenario: steps with their line numbers.
#[derive(Debug, Clone)]
pub struct Scenario {
    steps: Vec<(usize, Step)>,
}

fn tokenize(line: &str) -> Result<Vec<Tok>, String> {
    let mut toks = Vec::new();
    let b = line.as_bytes();
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b' ' | b'\t' | b'\r' => i += 1,
            b'#' => break,
            b'"' => {
                i += 1;
                let mut s = Vec::new();
                loop {
                    let c = *b.get(i).ok_or("unterminated string")?;
                    i += 1;
                    match c {
                        b'"' => break,
                        b'\\' => {
                            let e = *b.get(i).ok_or("dangling escape")?;
                            i += 1;
                            match e {
                                b'n' => s.push(b'\n'),
                                b'r' => s.push(b'\r'),
                                b't' => s.push(b'\t'),
                                b'"' => s.push(b'"'),
                                b'\\' => s.push(b'\\'),
                                b'x' => {
                                    let h = line.get(i..i + 2).ok_or("short \\x escape")?;
                                    s.push(u8::from_str_radix(h, 16).map_err(|_| format!("bad \\x escape {h:?}"))?);
                                    i += 2;
                                }
                                _ => return Err(format!("unknown escape \\{}", e as char)),
                            }
                        }
                        _ => s.push(c),
                    }
                }
                toks.push(Tok::Str(s));
            }
            _ => {
                let start = i;
                while i < b.len() && !matches!(b[i], b' ' | b'\t' | b'\r' | b'"' | b'#') {
                    i += 1;
                }
                toks.push(Tok::Word(line[start..i].to_string()));
            }
        }
    }
    Ok(toks)
}

/// Cursor over one line's tokens.
struct Args {
    toks: Vec<Tok>,
    pos: usize,
}

impl Args {
    fn word(&mut self) -> Result<String, String> {
        match self.toks.get(self.pos) {
            Some(Tok::Word(w)) => {
                self.pos += 1;
                Ok(w.clone())
            }
            Some(Tok::Str(_)) => Err("expected a word, got a string".into()),
            None => Err("missing argument".into()),
        }
    }

    fn keyword(&mut self, k: &str) -> Result<(), String> {
        let w = self.word()?;
        if w == k {
            Ok(())
        } else {
            Err(format!("expected `{k}`, got `{w}`"))
        }
    }

    fn peek_is(&self, k: &str) -> bool {
        matches!(self.toks.get(self.pos), Some(Tok::Word(w)) if w == k)
    }

    fn num(&mut self) -> Result<f64, String> {
        let w = self.word()?;
        let v: f64 = w.parse().map_err(|_| format!("not a number: {w:?}"))?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(format!("not finite: {w:?}"))
        }
    }

    fn int<T: std::str::FromStr>(&mut self) -> Result<T, String> {
        let w = self.word()?;
        let w2 = w.trim_start_matches("0x");
        if w2.len() != w.len() {
            return u64::from_str_radix(w2, 16)
                .ok()
                .and_then(|v| v.to_string().parse().ok())
                .ok_or_else(|| format!("bad hex integer {w:?}"));
        }
        w.parse().map_err(|_| format!("bad integer {w:?}"))
    }

    fn three(&mut self) -> Result<[f64; 3], String> {
        Ok([self.num()?, self.num()?, self.num()?])
    }

    fn tol(&mut self) -> Result<f64, String> {
        self.keyword("tol")?;
        self.num()
    }

    fn string(&mut self) -> Result<Vec<u8>, String> {
        match self.toks.get(self.pos) {
            Some(Tok::Str(s)) => {
                self.pos += 1;
                Ok(s.clone())
            }
            _ => Err("expected a quoted string".into()),
        }
    }

    fn text(&mut self) -> Result<String, String> {
        String::from_utf8(self.string()?).map_err(|_| "string is not UTF-8".to_string())
    }

    /// Frames of a duration: `250ms`, `1.5s`, `12f`.
    fn duration(&mut self) -> Result<u64, String> {
        let w = self.word()?;
        let (num, scale_ms) = if let Some(v) = w.strip_suffix("ms") {
            (v, 1.0)
        } else if let Some(v) = w.strip_suffix('s') {
            (v, 1000.0)
        } else if let Some(v) = w.strip_suffix('f') {
            (v, FRAME_MS as f64)
        } else {
            return Err(format!("duration needs ms, s or f: {w:?}"));
        };
        let v: f64 = num.parse().map_err(|_| format!("bad duration {w:?}"))?;
        if !(v >= 0.0 && v.is_finite()) {
            return Err(format!("bad duration {w:?}"));
        }
        Ok((v * scale_ms / FRAME_MS as f64).ceil() as u64)
    }

    fn since(&mut self) -> Result<Option<String>, String> {
        if self.peek_is("since") {
            self.pos += 1;
            Ok(Some(self.word()?))
        } else {
            Ok(None)
        }
    }

    fn end(&self) -> Result<(), String> {
        if self.pos == self.toks.len() {
            Ok(())
        } else {
            Err(format!("unexpected extra arguments: {:?}", &self.toks[self.pos..]))
        }
    }
}

fn parse_state(w: &str) -> Result<State, String> {
    Ok(match w {
        "off" => State::Off,
        "homing" => State::Homing,
        "holding" => State::Holding,
        "moving" => State::Moving,
        "stopped" => State::Stopped,
        "checking" => State::Checking,
        "paused" => State::Paused,
        _ => return Err(format!("unknown state {w:?}")),
    })
}

fn force(a: &mut Args) -> Result<f64, String> {
    if a.peek_is("force") {
        a.pos += 1;
        a.num()
    } else {
        Ok(1.0)
    }
}

fn parse_expect(a: &mut Args) -> Result<Expect, String> {
    let what = a.word()?;
    Ok(match what.as_str() {
        "state" => Expect::State(parse_state(&a.word()?)?),
        "angles_deg" => Expect::Angles(a.three()?, a.tol()?),
        "target_deg" => Expect::Target(a.three()?, a.tol()?),
        "servo_deg" => Expect::Servo(a.three()?, a.tol()?),
        "pulses" => Expect::Pulses(a.three()?, a.tol()?),
        "effector" => Expect::Effector(a.num()?, a.num()?, a.tol()?),
        "no_pulses" => Expect::NoPulses,
        "first_pulses" => {
            let p = [a.int()?, a.int()?, a.int()?];
            a.keyword("at_frame")?;
            Expect::FirstPulses(p, a.int()?)
        }
        "line" => Expect::Line(LineMatch::Exact, a.text()?),
        "line_starts" => Expect::Line(LineMatch::Starts, a.text()?),
        "line_contains" => Expect::Line(LineMatch::Contains, a.text()?),
        "no_line_contains" => Expect::NoLineContains(a.text()?),
        "no_line_starts" => Expect::NoLineStarts(a.text()?),
        "lines_starting" => {
            let p = a.text()?;
            Expect::LinesStarting(p, a.int()?)
        }
        "still" => {
            a.keyword("since")?;
            Expect::Still(a.word()?)
        }
        "max_step_us" => Expect::MaxStepUs(a.num()?, a.since()?),
        "speed_within" => Expect::SpeedWithin(a.num()?, a.since()?),
        "accel_within" => Expect::AccelWithin(a.num()?, a.since()?),
        "peak_speed_at_least" => {
            let p = a.num()?;
            a.keyword("since")?;
            Expect::PeakSpeedAtLeast(p, a.word()?)
        }
        "synchronized" => {
            a.keyword("since")?;
            let m = a.word()?;
            Expect::Synchronized(m, a.tol()?)
        }
        "move_ms" => {
            let ms = a.num()?;
            let tol = a.tol()?;
            a.keyword("since")?;
            Expect::MoveMs(ms, tol, a.word()?)
        }
        "on_segment" => {
            a.keyword("since")?;
            let m = a.word()?;
            Expect::OnSegment(m, a.tol()?)
        }
        "on_circle" => {
            let r = a.num()?;
            a.keyword("since")?;
            let m = a.word()?;
            Expect::OnCircle(r, m, a.tol()?)
        }
        "refusal" => Expect::Refusal(a.text()?),
        "no_refusal" => Expect::NoRefusal,
        "screen_warning" => Expect::ScreenWarning(a.text()?),
        "screen_state" => Expect::ScreenState(a.text()?),
        "scan" => Expect::Scan(a.text()?),
        "scan_contains" => Expect::ScanContains(a.text()?),
        "screen_speed" => Expect::ScreenSpeed(a.word()?),
        "preview" => Expect::Preview(match a.word()?.as_str() {
            "shown" => true,
            "none" => false,
            w => return Err(format!("preview shown|none, got {w:?}")),
        }),
        "grip_deg" => Expect::GripDeg(a.num()?, a.tol()?),
        "grip_pulse" => Expect::GripPulse(a.num()?, a.tol()?),
        "grip_servo_deg" => Expect::GripServo(a.num()?, a.tol()?),
        "no_grip_pulses" => Expect::NoGripPulses,
        "first_grip_pulse" => {
            let p = a.int()?;
            a.keyword("at_frame")?;
            Expect::FirstGripPulse(p, a.int()?)
        }
        "grip_still" => {
            a.keyword("since")?;
            Expect::GripStill(a.word()?)
        }
        "grip_max_step_us" => {
            let v = a.num()?;
            a.keyword("since")?;
            Expect::GripMaxStepUs(v, a.word()?)
        }
        "grip_speed_within" => {
            let v = a.num()?;
            a.keyword("since")?;
            Expect::GripSpeedWithin(v, a.word()?)
        }
        "grip_move_ms" => {
            let ms = a.num()?;
            let tol = a.tol()?;
            a.keyword("since")?;
            Expect::GripMoveMs(ms, tol, a.word()?)
        }
        _ => return Err(format!("unknown expectation {what:?}")),
    })
}

/// Frames a `touch` tap holds the finger down (200 ms: past the default
/// hold of 0.10 s with room for a hold of up to 0.16 s).
pub const TAP_FRAMES: u64 = 10;
/// Frames a `touch` tap runs after the release: the release's three reads
/// and the frame that acts and plans.
pub const LIFT_FRAMES: u64 = 4;

fn parse_press(a: &mut Args) -> Result<Step, String> {
    Ok(match a.word()?.as_str() {
        "xy" => {
            let (x, y) = (a.num()?, a.num()?);
            Step::TouchXy(x, y, force(a)?)
        }
        "raw" => {
            let (x, y) = (a.num()?, a.num()?);
            Step::TouchRaw(x, y, force(a)?)
        }
        "button" => {
            let (x, y) = button_raw(&a.word()?)?;
            Step::TouchRaw(x, y, force(a)?)
        }
        "map" => {
            let (x_p, y_p) = (a.num()?, a.num()?);
            let lay = touch_arm::ui::Layout::QVGA;
            let (px, py) = lay
                .ws_point_to_pixel(x_p as f32, y_p as f32)
                .ok_or_else(|| format!("({x_p}, {y_p}) is not on the map"))?;
            let (x, y) = crate::host::raw_at_pixel(&lay, px, py).ok_or("no raw reading")?;
            Step::TouchRaw(x, y, force(a)?)
        }
        "pixel" => {
            let (px, py) = (a.int::<i16>()?, a.int::<i16>()?);
            let lay = touch_arm::ui::Layout::QVGA;
            let (x, y) = crate::host::raw_at_pixel(&lay, px, py).ok_or("no raw reading")?;
            Step::TouchRaw(x, y, force(a)?)
        }
        w => return Err(format!("touch needs xy, raw, button, map or pixel, got {w:?}")),
    })
}

fn parse_step(a: &mut Args) -> Result<Step, String> {
    let d = a.word()?;
    Ok(match d.as_str() {
        "geometry" => {
            a.keyword("k")?;
            Step::Geometry { k: a.num()? }
        }
        "servo_init_deg" => Step::ServoInit(a.three()?),
        "servo_model" => {
            a.keyword("speed")?;
            let speed = a.num()?;
            a.keyword("deadband")?;
            Step::ServoModel { speed, deadband: a.num()? }
        }
        "seed" => Step::Seed(a.int()?),
        "screen" => {
            a.keyword("on")?;
            Step::Screen
        }
        "panel" => match a.word()?.as_str() {
            "noise" => Step::PanelNoise(a.num()?),
            "spikes" => Step::PanelSpikes(a.num()?),
            w => return Err(format!("unknown panel setting {w:?}")),
        },
        "touch" => Step::Tap(Box::new(parse_press(a)?)),
        "press" => parse_press(a)?,
        "finger" => {
            let mut tracks = [Vec::new(), Vec::new()];
            let mut k = 0;
            while a.pos < a.toks.len() {
                let w = a.word()?;
                if w == "second" && k == 0 {
                    k = 1;
                    continue;
                }
                let v: Vec<f64> = w
                    .split(',')
                    .map(str::parse)
                    .collect::<Result<_, _>>()
                    .map_err(|_| format!("knot {w:?}: expected t,x,y,f"))?;
                let [t, x, y, f] = v[..] else { return Err(format!("knot {w:?}: expected t,x,y,f")) };
                tracks[k].push(crate::finger::Knot::new(t, x, y, f));
            }
            let [first, second] = tracks;
            let first = crate::finger::Track::new(first)?;
            let second = if k == 1 { Some(crate::finger::Track::new(second)?) } else { None };
            Step::Finger(Box::new(crate::finger::FingerScript::new(first, second)?))
        }
        "release" => Step::Release,
        "switch" => Step::Switch(match a.word()?.as_str() {
            "down" => true,
            "up" => false,
            w => return Err(format!("switch needs down or up, got {w:?}")),
        }),
        "run" => Step::Run(a.duration()?),
        "run_until" => {
            let s = parse_state(&a.word()?)?;
            a.keyword("within")?;
            Step::RunUntil(s, a.duration()?)
        }
        "send" => {
            let mut s = a.string()?;
            s.push(b'\n');
            Step::Send(s)
        }
        "send_raw" => Step::Send(a.string()?),
        "reboot" => Step::Reboot,
        "mark" => Step::Mark(a.word()?),
        "eeprom" => match a.word()?.as_str() {
            "corrupt" => Step::EepromCorrupt(a.int()?, a.int()?),
            "powerloss_after" => Step::EepromPowerLoss(a.int()?),
            w => return Err(format!("unknown eeprom action {w:?}")),
        },
        "expect" => Step::Expect(parse_expect(a)?),
        _ => return Err(format!("unknown directive {d:?}")),
    })
}

impl Scenario {
    /// Parses a scenario file's text: its setup directives, then the steps; `Err` names the line that is wrong.
    pub fn parse(text: &str) -> Result<Scenario, String> {
        let mut steps = Vec::new();
        let mut setup_done = false;
        for (i, line) in text.lines().enumerate() {
            let n = i + 1;
            let toks = tokenize(line).map_err(|e| format!("line {n}: {e}"))?;
            if toks.is_empty() {
                continue;
            }
            let mut a = Args { toks, pos: 0 };
            let step = parse_step(&mut a).map_err(|e| format!("line {n}: {e}"))?;
            a.end().map_err(|e| format!("line {n}: {e}"))?;
            if step.is_setup() && setup_done {
                return Err(format!("line {n}: set-up directives must come before everything else"));
            }
            setup_done |= !step.is_setup();
            steps.push((n, step));
        }
        if steps.iter().all(|(_, s)| s.is_setup()) {
            return Err("scenario has no actions".into());
        }
        Ok(Scenario { steps })
    }

    /// Runs the scenario; `Err` names the first failing line.
    pub fn run(&self) -> Result<Sim, String> {
        let mut setup = SimSetup::default();
        let mut runner: Option<Runner> = None;
        for (n, step) in &self.steps {
            let r = match runner.as_mut() {
                None if step.is_setup() => apply_setup(&mut setup, step),
                None => {
                    let mut r = Runner::new(&setup)?;
                    let res = r.step(step);
                    runner = Some(r);
                    res
                }
                Some(r) => r.step(step),
            };
            r.map_err(|e| format!("line {n}: {e}"))?;
        }
        let r = runner.ok_or("scenario has no actions")?;
        if let Some(v) = r.sim.servos.violations.first() {
            return Err(format!("a pulse outside the servo range was written: {v:?}"));
        }
        if let Some(v) = r.sim.servos.grip_violations.first() {
            return Err(format!("a gripper pulse outside its range was written: {v} ticks"));
        }
        Ok(r.sim)
    }
}

fn apply_setup(setup: &mut SimSetup, step: &Step) -> Result<(), String> {
    match step {
        Step::Geometry { k } => setup.params.k = *k as f32,
        Step::ServoInit(d) => setup.servo_initial = d.map(f64::to_radians),
        Step::ServoModel { speed, deadband } => {
            setup.servo_model.max_speed_rad_s = *speed;
            setup.servo_model.deadband_us = *deadband;
        }
        Step::Seed(s) => setup.seed = *s,
        Step::Screen => setup.params.screen = true,
        _ => return Err("not a set-up directive".into()),
    }
    Ok(())
}

struct Runner {
    sim: Sim,
    marks: HashMap<String, usize>,
    cursor: usize,
}

fn deg3(v: &[f32; 3]) -> [f64; 3] {
    v.map(|x| (x as f64).to_degrees())
}

fn close3(name: &str, got: &[f64; 3], want: &[f64; 3], tol: f64) -> Result<(), String> {
    let bad = got.iter().zip(want.iter()).any(|(g, w)| !(g - w).abs().le(&tol));
    if bad {
        Err(format!("{name}: got {got:?}, want {want:?} ± {tol}"))
    } else {
        Ok(())
    }
}

fn close1(name: &str, got: f64, want: f64, tol: f64) -> Result<(), String> {
    if (got - want).abs().le(&tol) {
        Ok(())
    } else {
        Err(format!("{name}: got {got}, want {want} ± {tol}"))
    }
}

impl Runner {
    fn new(setup: &SimSetup) -> Result<Runner, String> {
        Ok(Runner { sim: Sim::new(setup)?, marks: HashMap::new(), cursor: 0 })
    }

    /// Frame index where the checked range starts.
    fn mark(&self, name: &Option<String>) -> Result<usize, String> {
        match name {
            None => Ok(0),
            Some(m) => self.marks.get(m).copied().ok_or_else(|| format!("unknown mark {m:?}")),
        }
    }

    /// Records from the frame before `from` (if any) to the end.
    fn window(&self, from: usize) -> &[FrameRecord] {
        &self.sim.history[from.saturating_sub(1).min(self.sim.history.len())..]
    }

    fn step(&mut self, step: &Step) -> Result<(), String> {
        let sim = &mut self.sim;
        match step {
            Step::Geometry { .. } | Step::ServoInit(_) | Step::ServoModel { .. } | Step::Seed(_) | Step::Screen => {
                return Err("set-up directive after the simulation started".into())
            }
            Step::PanelNoise(s) => sim.panel.noise_counts = *s,
            Step::PanelSpikes(p) => sim.panel.spike_prob = *p,
            Step::TouchXy(x, y, f) => sim.panel.touch_xy(*x, *y, *f)?,
            Step::TouchRaw(x, y, f) => sim.panel.touch_raw(*x, *y, *f)?,
            Step::Finger(script) => sim.finger((**script).clone()),
            Step::Tap(press) => {
                self.step(press)?;
                let sim = &mut self.sim;
                sim.run_frames(TAP_FRAMES);
                sim.panel.release();
                sim.run_frames(LIFT_FRAMES);
            }
            Step::Release => sim.panel.release(),
            Step::Switch(down) => sim.switch = *down,
            Step::Run(frames) => sim.run_frames(*frames),
            Step::RunUntil(state, max) => {
                // At least one frame, so a line just sent is read first.
                let mut k = 0;
                loop {
                    if k >= *max {
                        return Err(format!(
                            "state {:?} not reached within {max} frames (now {:?})",
                            state,
                            sim.app.state()
                        ));
                    }
                    sim.step();
                    k += 1;
                    if sim.app.state() == *state {
                        break;
                    }
                }
            }
            Step::Send(bytes) => sim.serial.send(bytes),
            Step::Reboot => sim.reboot()?,
            Step::Mark(name) => {
                self.marks.insert(name.clone(), sim.history.len());
            }
            Step::EepromCorrupt(addr, v) => sim.eeprom.corrupt(*addr, *v)?,
            Step::EepromPowerLoss(n) => sim.eeprom.power_loss_after(*n),
            Step::Expect(e) => self.expect(e)?,
        }
        Ok(())
    }

    fn expect(&mut self, e: &Expect) -> Result<(), String> {
        let sim = &self.sim;
        let st = sim.app.status();
        match e {
            Expect::State(s) => {
                if st.state != *s {
                    return Err(format!("state is {:?}, want {:?}", st.state, s));
                }
            }
            Expect::Angles(w, tol) => close3("commanded angles (deg)", &deg3(&st.commanded), w, *tol)?,
            Expect::Target(w, tol) => close3("target angles (deg)", &deg3(&st.target), w, *tol)?,
            Expect::Servo(w, tol) => {
                close3("servo shaft angles (deg)", &sim.servos.angles().map(f64::to_degrees), w, *tol)?
            }
            Expect::Pulses(w, tol) => {
                let p = sim.servos.pulses().ok_or("no pulses are being output")?;
                close3("pulses (us)", &p.map(|t| f64::from(t) / 2.0), w, *tol)?
            }
            Expect::Effector(reach, height, tol) => {
                let ef = sim.effector()?;
                if !((ef.reach - reach).abs() <= *tol && (ef.height - height).abs() <= *tol) {
                    return Err(format!(
                        "effector (reach, height) = ({}, {}), want ({reach}, {height}) ± {tol}",
                        ef.reach, ef.height
                    ));
                }
            }
            Expect::NoPulses => {
                if let Some(r) = sim.history.iter().find(|r| r.pulses.is_some()) {
                    return Err(format!("pulses in frame {}: {:?}", r.frame, r.pulses));
                }
            }
            Expect::FirstPulses(p, at) => {
                let boot_start = sim.history.iter().rposition(|r| r.boot_frame == 0).ok_or("no frame run")?;
                let first = sim.history[boot_start..]
                    .iter()
                    .find(|r| r.pulses.is_some())
                    .ok_or("no pulses since the last boot")?;
                // The scenario states whole µs, the servos see ticks of 0.5 µs.
                if first.pulses != Some(p.map(|us| us * 2)) || first.boot_frame != *at {
                    return Err(format!(
                        "first pulses {:?} ticks at boot frame {}, want {p:?} µs at {at}",
                        first.pulses, first.boot_frame
                    ));
                }
            }
            Expect::Line(kind, text) => {
                let lines = sim.serial.lines();
                let hit = lines.iter().enumerate().skip(self.cursor).find(|(_, l)| match kind {
                    LineMatch::Exact => l.as_str() == text,
                    LineMatch::Starts => l.starts_with(text.as_str()),
                    LineMatch::Contains => l.contains(text.as_str()),
                });
                match hit {
                    Some((i, _)) => self.cursor = i + 1,
                    None => {
                        return Err(format!(
                            "no {kind:?} match for {text:?} in the new output: {:?}",
                            &lines[self.cursor.min(lines.len())..]
                        ))
                    }
                }
            }
            Expect::NoLineContains(text) => {
                let lines = sim.serial.lines();
                if let Some(l) = lines.iter().skip(self.cursor).find(|l| l.contains(text.as_str())) {
                    return Err(format!("unexpected output line {l:?}"));
                }
            }
            Expect::NoLineStarts(text) => {
                let lines = sim.serial.lines();
                if let Some(l) = lines.iter().skip(self.cursor).find(|l| l.starts_with(text.as_str())) {
                    return Err(format!("unexpected output line {l:?}"));
                }
            }
            Expect::LinesStarting(text, n) => {
                let lines = sim.serial.lines();
                let got = lines.iter().skip(self.cursor).filter(|l| l.starts_with(text.as_str())).count();
                if got != *n {
                    return Err(format!("{got} lines start with {text:?} in the new output, want {n}"));
                }
                self.cursor = lines.len();
            }
            Expect::Still(m) => {
                let from = self.mark(&Some(m.clone()))?;
                let w = self.window(from);
                let first = w.first().ok_or("no frames")?;
                if let Some(r) = w.iter().find(|r| r.pulses != first.pulses) {
                    return Err(format!("pulses changed in frame {}: {:?} -> {:?}", r.frame, first.pulses, r.pulses));
                }
            }
            Expect::MaxStepUs(max, m) => {
                let from = self.mark(m)?;
                let mut worst = 0.0f64;
                for p in self.window(from).windows(2) {
                    if let (Some(a), Some(b)) = (p[0].pulses, p[1].pulses) {
                        for (x, y) in a.iter().zip(b.iter()) {
                            worst = worst.max((*x as f64 - *y as f64).abs() / 2.0);
                        }
                    }
                }
                if worst > *max {
                    return Err(format!("largest pulse step {worst} us > {max}"));
                }
            }
            Expect::SpeedWithin(pct, m) => {
                let (worst, frame) = self.peak_speed_share(self.mark(m)?);
                if worst > pct / 100.0 * (1.0 + 1e-3) {
                    return Err(format!(
                        "a joint moved at {:.2} % of its max speed (frame {frame}) > {pct} %",
                        worst * 100.0
                    ));
                }
            }
            Expect::AccelWithin(pct, m) => {
                // Second differences of the commanded angles over 20 ms
                // frames against each joint's max_accel.
                let cfg = self.sim.app.config();
                let mut worst = (0.0f64, 0u64);
                for p in self.window(self.mark(m)?).windows(3) {
                    if p[1].boot_frame == 0 || p[2].boot_frame == 0 {
                        continue;
                    }
                    for j in 0..3 {
                        let q = |k: usize| p[k].commanded[j] as f64;
                        let a = (q(2) - 2.0 * q(1) + q(0)).abs() / (FRAME_S * FRAME_S);
                        let share = a / cfg.joints[j].max_accel_rad_s2 as f64;
                        if share > worst.0 {
                            worst = (share, p[2].frame);
                        }
                    }
                }
                if worst.0 > pct / 100.0 * (1.0 + 1e-3) {
                    return Err(format!(
                        "a joint accelerated at {:.2} % of its max accel (frame {}) > {pct} %",
                        worst.0 * 100.0,
                        worst.1
                    ));
                }
            }
            Expect::PeakSpeedAtLeast(pct, m) => {
                let (best, _) = self.peak_speed_share(self.mark(&Some(m.clone()))?);
                if best < pct / 100.0 {
                    return Err(format!("peak joint speed {:.2} % of max < {pct} %", best * 100.0));
                }
            }
            Expect::Synchronized(m, tol) => {
                let from = self.mark(&Some(m.clone()))?;
                let w = self.window(from);
                let (first, last) = (w.first().ok_or("no frames")?, w.last().ok_or("no frames")?);
                let start = deg3(&first.commanded);
                let end = deg3(&last.commanded);
                let moving: Vec<usize> = (0..3).filter(|&j| (end[j] - start[j]).abs() > 0.05).collect();
                if moving.len() < 2 {
                    return Err(format!("fewer than two joints moved: {start:?} -> {end:?}"));
                }
                for r in w {
                    let q = deg3(&r.commanded);
                    let prog: Vec<f64> = moving.iter().map(|&j| (q[j] - start[j]) / (end[j] - start[j])).collect();
                    let spread =
                        prog.iter().cloned().fold(f64::MIN, f64::max) - prog.iter().cloned().fold(f64::MAX, f64::min);
                    if spread > *tol {
                        return Err(format!("joints out of step in frame {}: progress {prog:?}", r.frame));
                    }
                }
            }
            Expect::MoveMs(ms, tol, m) => {
                let from = self.mark(&Some(m.clone()))?;
                let h = &sim.history;
                let last = h.last().ok_or("no frames")?.commanded;
                let arrive = h.iter().rposition(|r| r.commanded != last).map_or(0, |i| i + 1);
                if arrive < from {
                    return Err("the pose did not change after the mark".into());
                }
                let got = (arrive - from) as f64 * FRAME_MS as f64;
                if !(got - ms).abs().le(tol) {
                    return Err(format!("move took {got} ms, want {ms} ± {tol}"));
                }
            }
            Expect::OnSegment(m, tol) => {
                let w = self.window(self.mark(&Some(m.clone()))?);
                let fk = commanded_fk(sim, w)?;
                let (a, b) = (fk[0], fk[fk.len() - 1]);
                let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
                let dd = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                for (p, r) in fk.iter().zip(w) {
                    let s = (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1] + (p[2] - a[2]) * d[2]) / dd).clamp(0.0, 1.0);
                    let e = dist(p, &[a[0] + d[0] * s, a[1] + d[1] * s, a[2] + d[2] * s]);
                    if e > *tol {
                        return Err(format!("effector {p:?} is {e:.6} off the segment in frame {}", r.frame));
                    }
                }
            }
            Expect::OnCircle(radius, m, tol) => {
                let w = self.window(self.mark(&Some(m.clone()))?);
                let fk = commanded_fk(sim, w)?;
                let a = fk[0];
                let rho = (a[0] * a[0] + a[1] * a[1]).sqrt();
                let f = (rho - radius) / rho;
                let c = [a[0] * f, a[1] * f, a[2]];
                for (p, r) in fk.iter().zip(w) {
                    // In the plane (the top view's direction of the centre)
                    // and at the radius from the centre.
                    let off_plane = (p[0] * c[1] - p[1] * c[0]).abs() / (c[0] * c[0] + c[1] * c[1]).sqrt();
                    let e = (dist(p, &c) - radius).abs().max(off_plane);
                    if e > *tol {
                        return Err(format!("effector {p:?} is {e:.6} off the circle in frame {}", r.frame));
                    }
                }
            }
            Expect::Refusal(text) => {
                let r = st.last_refusal.map(|r| r.reason().as_str());
                if r != Some(text.as_str()) {
                    return Err(format!("last refusal {r:?}, want {text:?}"));
                }
            }
            Expect::NoRefusal => {
                if let Some(r) = st.last_refusal {
                    return Err(format!("unexpected refusal {:?}", r.reason()));
                }
            }
            Expect::ScreenWarning(text) => {
                let shown = touch_arm::ui::warning_line(sim.app.ui_model().warnings);
                if shown.as_str() != text {
                    return Err(format!("screen warning {:?}, want {text:?}", shown.as_str()));
                }
            }
            Expect::ScreenSpeed(want) => {
                let shown = sim.app.ui_model().speed.name();
                if shown.as_str() != want {
                    return Err(format!("screen speed {:?}, want {want}", shown.as_str()));
                }
            }
            Expect::ScreenState(text) => {
                let shown = format!("{:?}", sim.app.ui_model().state);
                if shown != *text {
                    return Err(format!("screen state {shown}, want {text}"));
                }
            }
            Expect::Scan(text) => {
                let shown = format!("{:?}", sim.app.ui_model().scan);
                if shown != *text {
                    return Err(format!("scan {shown}, want {text}"));
                }
            }
            Expect::ScanContains(text) => {
                let shown = format!("{:?}", sim.app.ui_model().scan);
                if !shown.contains(text.as_str()) {
                    return Err(format!("scan {shown}, want it to contain {text}"));
                }
            }
            Expect::Preview(want) => {
                let p = sim.app.ui_model().preview;
                if p.is_some() != *want {
                    return Err(format!("preview {p:?}, want {}", if *want { "shown" } else { "none" }));
                }
            }
            Expect::GripDeg(w, tol) => {
                close1("commanded gripper angle (deg)", f64::from(st.grip).to_degrees(), *w, *tol)?
            }
            Expect::GripPulse(w, tol) => {
                let p = sim.servos.grip_pulse().ok_or("no gripper pulse is being output")?;
                close1("gripper pulse (us)", f64::from(p) / 2.0, *w, *tol)?
            }
            Expect::GripServo(w, tol) => close1("gripper shaft (deg)", sim.servos.grip_angle().to_degrees(), *w, *tol)?,
            Expect::NoGripPulses => {
                if let Some(r) = sim.history.iter().find(|r| r.grip_pulse.is_some()) {
                    return Err(format!("gripper pulse in frame {}: {:?}", r.frame, r.grip_pulse));
                }
            }
            Expect::FirstGripPulse(us, at) => {
                let boot_start = sim.history.iter().rposition(|r| r.boot_frame == 0).ok_or("no frame run")?;
                let first = sim.history[boot_start..]
                    .iter()
                    .find(|r| r.grip_pulse.is_some())
                    .ok_or("no gripper pulse since the last boot")?;
                if first.grip_pulse != Some(us * 2) || first.boot_frame != *at {
                    return Err(format!(
                        "first gripper pulse {:?} ticks at boot frame {}, want {us} µs at {at}",
                        first.grip_pulse, first.boot_frame
                    ));
                }
            }
            Expect::GripStill(m) => {
                let from = self.mark(&Some(m.clone()))?;
                let w = self.window(from);
                let first = w.first().ok_or("no frames")?;
                if let Some(r) = w.iter().find(|r| r.grip_pulse != first.grip_pulse) {
                    return Err(format!(
                        "gripper pulse changed in frame {}: {:?} -> {:?}",
                        r.frame, first.grip_pulse, r.grip_pulse
                    ));
                }
            }
            Expect::GripMaxStepUs(max, m) => {
                let from = self.mark(&Some(m.clone()))?;
                let worst = self
                    .window(from)
                    .windows(2)
                    .filter_map(|p| Some((f64::from(p[0].grip_pulse?) - f64::from(p[1].grip_pulse?)).abs() / 2.0))
                    .fold(0.0, f64::max);
                if worst > *max {
                    return Err(format!("largest gripper pulse step {worst} us > {max}"));
                }
            }
            Expect::GripSpeedWithin(pct, m) => {
                let from = self.mark(&Some(m.clone()))?;
                let limit = f64::from(sim.app.grip_cal().max_speed_rad_s);
                let worst = self
                    .window(from)
                    .windows(2)
                    .filter(|p| p[1].boot_frame != 0)
                    .map(|p| (f64::from(p[1].grip_commanded) - f64::from(p[0].grip_commanded)).abs() / FRAME_S / limit)
                    .fold(0.0, f64::max);
                if worst > pct / 100.0 * (1.0 + 1e-3) {
                    return Err(format!("the gripper moved at {:.2} % of its max speed > {pct} %", worst * 100.0));
                }
            }
            Expect::GripMoveMs(ms, tol, m) => {
                let from = self.mark(&Some(m.clone()))?;
                let h = &sim.history;
                let last = h.last().ok_or("no frames")?.grip_commanded;
                let arrive = h.iter().rposition(|r| r.grip_commanded != last).map_or(0, |i| i + 1);
                if arrive < from {
                    return Err("the gripper did not move after the mark".into());
                }
                let got = (arrive - from) as f64 * FRAME_MS as f64;
                if !(got - ms).abs().le(tol) {
                    return Err(format!("grip took {got} ms, want {ms} ± {tol}"));
                }
            }
        }
        Ok(())
    }

    /// Largest commanded joint speed since `from` as a share of the joint's
    /// configured max speed, and the frame where it happened.
    fn peak_speed_share(&self, from: usize) -> (f64, u64) {
        let cfg = self.sim.app.config();
        let mut worst = (0.0f64, 0u64);
        for p in self.window(from).windows(2) {
            if p[1].boot_frame == 0 {
                continue;
            }
            for j in 0..3 {
                let v = (p[1].commanded[j] as f64 - p[0].commanded[j] as f64).abs() / FRAME_S;
                let share = v / cfg.joints[j].max_speed_rad_s as f64;
                if share > worst.0 {
                    worst = (share, p[1].frame);
                }
            }
        }
        worst
    }
}

/// Parses and runs a scenario file.
pub fn run_file(path: &Path) -> Result<Sim, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let sc = Scenario::parse(&text).map_err(|e| format!("{}: {e}", path.display()))?;
    sc.run().map_err(|e| format!("{}: {e}", path.display()))
}

/// FK (arm units) of the commanded pose of every record.
fn commanded_fk(sim: &Sim, w: &[FrameRecord]) -> Result<Vec<[f64; 3]>, String> {
    let links = sim.links()?;
    if w.is_empty() {
        return Err("no frames".into());
    }
    Ok(w.iter()
        .map(|r| {
            let q = r.commanded.map(f64::from);
            let (x, y, z) = touch_arm::geometry::ik::fk3(&links, q[0], q[1], q[2]);
            [x, y, z]
        })
        .collect())
}

fn dist(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

/// The raw reading of a touch on the centre of the named button (see the
/// module doc), 320×240 screen, default calibration.
fn button_raw(name: &str) -> Result<(f64, f64), String> {
    let lay = touch_arm::ui::Layout::QVGA;
    let area = match name {
        "stop" => lay.stop(),
        "slow" => lay.slow(),
        "normal" => lay.normal(),
        "fast" => lay.fast(),
        "more" | "back" => lay.page_key(),
        "grip" => lay.grip(),
        "calib" => lay.calibrate(),
        "line" => lay.line_toggle(),
        "lift" => lay.lift_toggle(),
        "pose1" => lay.pose(0),
        "pose2" => lay.pose(1),
        "pose3" => lay.pose(2),
        "pose4" => lay.pose(3),
        "undo" => lay.undo(),
        "carer_left" => lay.carer_corner(0),
        "carer_right" => lay.carer_corner(1),
        _ => return Err(format!("unknown button {name:?}")),
    };
    crate::host::raw_at_centre(&lay, area).ok_or_else(|| format!("button {name:?} has no raw reading"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_errors_name_the_line() {
        let e = Scenario::parse("run 1s\nfly away\n").unwrap_err();
        assert!(e.starts_with("line 2: unknown directive"), "{e}");
        let e = Scenario::parse("run 1s\nseed 3\n").unwrap_err();
        assert!(e.contains("set-up directives must come before"), "{e}");
        let e = Scenario::parse("run 3 s\n").unwrap_err();
        assert!(e.starts_with("line 1:"), "{e}");
        assert!(Scenario::parse("send \"abc\n").is_err());
        assert!(Scenario::parse("# only a comment\n").is_err());
        let e = Scenario::parse("expect angles_deg 1 2 3 tol\n").unwrap_err();
        assert!(e.contains("missing argument"), "{e}");
    }

    #[test]
    fn finger_steps_parse_their_knots() {
        let sc = Scenario::parse("finger 0,10,20,1 100,12,20,1 second 0,200,100,3").unwrap();
        let Step::Finger(f) = &sc.steps[0].1 else { panic!("{:?}", sc.steps) };
        assert_eq!(f.first.at(50.0), Some((11.0, 20.0, 1.0)));
        assert_eq!(f.at(0.0)[1], Some((200.0, 100.0, 3.0)));
        for (text, err) in [
            ("finger 0,1,2", "knot \"0,1,2\": expected t,x,y,f"),
            ("finger 0,1,2,x", "knot \"0,1,2,x\": expected t,x,y,f"),
            ("finger", "a track needs at least one sample"),
            ("finger 5,1,1,1 4,1,1,1", "sample 1: t_ms 4 before the previous sample's 5"),
        ] {
            let e = Scenario::parse(text).unwrap_err();
            assert!(e.contains(err), "{text}: {e}");
        }
    }

    #[test]
    fn strings_durations_and_failures() {
        let t = tokenize(r#"send_raw "a\x01\"b\\\r\n" # tail"#).unwrap();
        assert_eq!(t, vec![Tok::Word("send_raw".into()), Tok::Str(b"a\x01\"b\\\r\n".to_vec())]);
        let mut a = Args { toks: tokenize("250ms 1.5s 12f 0.01s").unwrap(), pos: 0 };
        assert_eq!(
            [a.duration().unwrap(), a.duration().unwrap(), a.duration().unwrap(), a.duration().unwrap()],
            [13, 75, 12, 1]
        );
        // A false expectation fails with its line.
        let e = Scenario::parse("run 2s\nexpect state moving\n").unwrap().run().err().unwrap();
        assert!(e.starts_with("line 2: state is Holding"), "{e}");
        let e = Scenario::parse("run 1f\nexpect line \"nope\"\n").unwrap().run().err().unwrap();
        assert!(e.starts_with("line 2: no Exact match"), "{e}");
    }
}
