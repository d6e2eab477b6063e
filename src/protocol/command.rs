//! The serial command protocol: one command per line, parsed without
//! allocation into a [`Command`].
//!
//! # Grammar
//! Tokens are separated by any run of spaces or tabs (CR and LF count as
//! whitespace too, for callers that pass the terminator); leading and trailing
//! whitespace is ignored. Keywords are exact but case-insensitive (`STOP`,
//! `Goto 1 2 3`, `law ZAT`: a terminal with caps lock, a script's habits).
//! Every byte of the line must be printable ASCII or whitespace, else
//! [`CmdError::BadCharacter`].
//!
//! [`STOP_BYTE`] (`!`) is no part of any line: the port takes it out of the
//! stream as it arrives and the app latches STOP in its next frame
//! (`seam::SerialPort::take_stop_byte`), without a line ending.
//!
//! | line | meaning |
//! |------|---------|
//! | `move <raw_x> <raw_y>` | go to a touch point given as raw ADC values, integers 0..=1023 |
//! | `goto <deg1> <deg2> <deg3>` | joint angles base, shoulder, elbow in degrees (−360..=360, ≤ 2 decimals), in the convention of [`crate::servo::map`] (elbow relative to the upper arm, negative = elbow up, see [`crate::servo::map::ELBOW_BRANCH`]) |
//! | `stop` / `resume` / `status` | |
//! | `law <zat\|zat-paper\|quintic\|cubic\|trapezoid\|linear>` | motion law |
//! | `speed <slow\|normal\|fast>` | 25 / 50 / 100 % of each joint's max speed |
//! | `cal show` / `cal save` / `cal reset` | print / store to EEPROM / back to defaults (in RAM) |
//! | `cal set <base\|shoulder\|elbow> <field> <value>` | see [`JointField`] |
//! | `cal set touch <field> <value>` | see [`TouchField`] |
//! | `cal set grip <field> <value>` | the gripper, in the joints' fields ([`JointField`]) |
//! | `cal reset grip` | the gripper's calibration back to its defaults (in RAM) |
//! | `cal set arm <l2\|l3> <mm>` | a link's length, 10.00..=650.00 mm, the longer at most 4× the shorter ([`ArmSettings`]) |
//! | `cal set <home\|park> <deg1> <deg2> <deg3>` | the power-up pose, or `park`'s (±327.67°, in the current joint limits) |
//! | `park` | go to the park pose (as `goto` its angles) |
//! | `undo` | back to the pose held before the last accepted target (up to 4 steps; the gripper stays) |
//! | `cal set lcd <auto\|ili9341\|st7789\|ili9486\|ili9325\|st7796>`, `cal set lcd invert on\|off`, `cal set lcd rotate 0\|180` | the display overrides, stored at once, used from the next boot ([`LcdSet`]) |
//! | `grip <open\|close\|deg>` | the gripper: open (its `min_deg`), closed (its `max_deg`) or an angle in degrees (≤ 2 decimals), see [`GripCmd`] |
//! | `log <on\|off\|plot>` | per-frame telemetry: `t …` lines for programs, or `base:<deg>,…` lines for the Arduino Serial Plotter; `off` stops both |
//! | `help` / `version` | the commands in one line / the crate version and git commit |
//! | `pose <save\|go\|clear> <1-4>` / `pose list` | saved poses, see [`PoseCmd`] |
//! | `path <joint\|line>` | how targets are reached: joint-space moves, or the effector along the straight segment |
//! | `lift <h>` / `lift off` | joint moves pass a via pose h (workspace units, 0.01..=0.50) above the higher end, halfway in base rotation and reach; excludes `path line` |
//! | `mode <tap\|hold>` | how a map touch moves the arm: on its commit after the hold (`tap`, the default), or only while it stays held (`hold`: a lift brings the arm to rest along its path) |
//! | `access lock` / `access unlock <pin>` | the carer lock: lock the user's pages (a PIN must be set), or open carer mode; see [`AccessCmd`] |
//! | `access pin <4-8 digits>\|off`, `access hide\|show <cal\|line\|lift\|fast\|touch>`, `access cap <slow\|normal\|fast>` | the carer's settings, stored at once (carer mode only) |
//! | `switch on\|off\|glass`, `switch sweep <s>` | the assistive switch: used or not (`glass`: the whole glass is one too), and its scan's sweep per axis, 2.00..=20.00 s (kept to the tenth); stored at once (carer mode only) |
//! | `circle <r>` | one turn of radius r (workspace units, 0.01..=0.50) in the arm's vertical plane, starting and ending where the effector is |
//!
//! # Numbers
//! Integers: optional sign, decimal digits. Decimals: optional sign, at least
//! one digit, optionally `.` and one or two digits (`12`, `-0.5`, `90.25`; not
//! `.5`, `1.`, `1e3` or `1.234`). Decimals are parsed as fixed-point hundredths
//! into an `i32`, so the chip parses no floats. A syntactically bad number is
//! [`CmdError::BadNumber`]; a good one outside the field's range is
//! [`CmdError::OutOfRange`]. Arguments are checked left to right and the first
//! error is reported.

use crate::config::access::{item_nth, Pin, SwitchUse, SWEEP_MAX_DS, SWEEP_MIN_DS};
use crate::config::lcd::{LcdChoice, LcdSet};
use crate::config::poses::{POSES, POSE_MAX_CENTIDEG};
#[cfg(doc)]
use crate::config::settings::ArmSettings;
use crate::config::settings::{
    ArmLink, CalSet, JointField, NamedPose, PathMode, SpeedPreset, TouchField, LINK_MAX_CMM, LINK_MIN_CMM,
    NAMED_POSE_MAX_CENTIDEG, RAW_MAX,
};
use crate::motion::plan::LawKind;
use crate::seam::RxLoss;
use crate::servo::map::Joint;

/// The one-byte STOP: acted on from the receive interrupt's flag, never
/// part of a line (no command uses `!`).
pub const STOP_BYTE: u8 = b'!';

/// Capacity of the serial line buffer (bytes of a line, terminator excluded).
pub const LINE_LEN: usize = 64;

/// The firmware's line buffer.
pub type SerialLine = LineBuffer<LINE_LEN>;

/// `goto` accepts ±360.00° (joint limits are the servo layer's business),
/// the range a saved pose may hold.
pub const GOTO_MAX_CENTIDEG: i32 = POSE_MAX_CENTIDEG;

/// One parsed command line (see the module doc's grammar).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Command {
    /// `move <raw_x> <raw_y>`: go where this raw panel reading maps.
    Move {
        /// Raw X, ADC counts 0..=1023.
        x: u16,
        /// Raw Y, ADC counts 0..=1023.
        y: u16,
    },
    /// Angles in hundredths of a degree, in [`Joint::index`] order.
    Goto {
        /// Base, shoulder, elbow, each within ±[`GOTO_MAX_CENTIDEG`].
        centideg: [i32; 3],
    },
    /// `stop`: halt where the arm is.
    Stop,
    /// `resume`: accept moves again after a stop.
    Resume,
    /// `status`: report state, pose, move and warnings.
    Status,
    /// `law <name>`: the law of new moves.
    Law(LawKind),
    /// `speed <name>`: the preset of new moves.
    Speed(SpeedPreset),
    /// `cal show`: print every calibration field.
    CalShow,
    /// `cal set ...`: change one calibration field (in RAM).
    CalSet(CalSet),
    /// `cal save`: store the running configuration in the EEPROM.
    CalSave,
    /// `cal reset`: back to the built-in defaults (in RAM).
    CalReset,
    /// `log on|off|plot`: per-frame telemetry.
    Log(LogMode),
    /// `path joint|line`: how targets are reached.
    Path(PathMode),
    /// `lift <h>` (hundredths of a workspace unit, 1..=[`LIFT_MAX_CENTI`])
    /// or `lift off` (`None`).
    Lift(Option<u8>),
    /// `mode hold` (`true`) or `mode tap`: hold to run.
    Mode(bool),
    /// `circle <r>`: one turn of radius `r` hundredths of a workspace unit.
    Circle {
        /// Radius, hundredths of a workspace unit, 1..=[`CIRCLE_MAX_CENTI`].
        r_centi: u16,
    },
    /// `pose …`: the saved poses.
    Pose(PoseCmd),
    /// `cal reset grip`: the gripper's calibration back to its defaults.
    CalResetGrip,
    /// `grip …`: move the gripper.
    Grip(GripCmd),
    /// `help`: the command words in one line.
    Help,
    /// `version`: the crate version and the git commit built from.
    Version,
    /// `cal set lcd …`: one display override.
    CalLcd(LcdSet),
    /// `park`: to the park pose.
    Park,
    /// `undo`: back to the pose held before the last accepted target.
    Undo,
    /// `access …`: the carer lock and its settings.
    Access(AccessCmd),
}

/// An `access` command (the carer lock, `config::access`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AccessCmd {
    /// `access lock`: the user's pages locked (needs a PIN).
    Lock,
    /// `access unlock <pin>`: carer mode, if the PIN is right.
    Unlock(Pin),
    /// `access pin <digits>` / `access pin off` ([`Pin::NONE`]).
    SetPin(Pin),
    /// `access hide <item>` (true) / `access show <item>`: an
    /// [`crate::config::access::item`] bit.
    Hide(u8, bool),
    /// `access cap <preset>`: the fastest preset any move uses.
    Cap(SpeedPreset),
    /// `switch on|off|glass`: whether the assistive switch is used, and
    /// the glass as one.
    Switch(SwitchUse),
    /// `switch sweep <s>`: the scan's sweep per axis, tenths of a second.
    Sweep(u8),
}

/// What `log` prints every frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LogMode {
    /// Nothing (`log off`).
    Off,
    /// `t <ms> <centidegrees…> <µs…> …` for programs (`log on`).
    On,
    /// `base:<deg>,shoulder:<deg>,elbow:<deg>,grip:<deg>` for the Arduino
    /// Serial Plotter (`log plot`).
    Plot,
}

/// A command's first word. [`Verb::ALL`] is what `parse` knows and what
/// `help` lists, so the two cannot disagree.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verb {
    /// `move`
    Move,
    /// `goto`
    Goto,
    /// `stop`
    Stop,
    /// `resume`
    Resume,
    /// `status`
    Status,
    /// `law`
    Law,
    /// `speed`
    Speed,
    /// `path`
    Path,
    /// `lift`
    Lift,
    /// `mode`
    Mode,
    /// `circle`
    Circle,
    /// `grip`
    Grip,
    /// `pose`
    Pose,
    /// `park`
    Park,
    /// `undo`
    Undo,
    /// `access`
    Access,
    /// `switch`
    Switch,
    /// `cal`
    Cal,
    /// `log`
    Log,
    /// `help`
    Help,
    /// `version`
    Version,
}

impl Verb {
    /// Every command word, in the order `help` lists them.
    pub const ALL: [Verb; 21] = [
        Verb::Move,
        Verb::Goto,
        Verb::Stop,
        Verb::Resume,
        Verb::Status,
        Verb::Law,
        Verb::Speed,
        Verb::Path,
        Verb::Lift,
        Verb::Mode,
        Verb::Circle,
        Verb::Grip,
        Verb::Pose,
        Verb::Park,
        Verb::Undo,
        Verb::Access,
        Verb::Switch,
        Verb::Cal,
        Verb::Log,
        Verb::Help,
        Verb::Version,
    ];

    /// [`Verb::ALL`] in order, by index: the array itself, iterated at run
    /// time, would be a 16-byte table in static RAM on the chip.
    pub fn all() -> impl Iterator<Item = Verb> {
        (0u8..).map_while(Verb::nth)
    }

    /// Entry `i` of [`Verb::ALL`].
    fn nth(i: u8) -> Option<Verb> {
        Some(match i {
            0 => Verb::Move,
            1 => Verb::Goto,
            2 => Verb::Stop,
            3 => Verb::Resume,
            4 => Verb::Status,
            5 => Verb::Law,
            6 => Verb::Speed,
            7 => Verb::Path,
            8 => Verb::Lift,
            9 => Verb::Mode,
            10 => Verb::Circle,
            11 => Verb::Grip,
            12 => Verb::Pose,
            13 => Verb::Park,
            14 => Verb::Undo,
            15 => Verb::Access,
            16 => Verb::Switch,
            17 => Verb::Cal,
            18 => Verb::Log,
            19 => Verb::Help,
            20 => Verb::Version,
            _ => return None,
        })
    }

    /// The word, lowercase.
    pub fn name(self) -> crate::text::Text {
        match self {
            Verb::Move => t!("move"),
            Verb::Goto => t!("goto"),
            Verb::Stop => t!("stop"),
            Verb::Resume => t!("resume"),
            Verb::Status => t!("status"),
            Verb::Law => t!("law"),
            Verb::Speed => t!("speed"),
            Verb::Path => t!("path"),
            Verb::Lift => t!("lift"),
            Verb::Mode => t!("mode"),
            Verb::Circle => t!("circle"),
            Verb::Grip => t!("grip"),
            Verb::Pose => t!("pose"),
            Verb::Park => t!("park"),
            Verb::Undo => t!("undo"),
            Verb::Access => t!("access"),
            Verb::Switch => t!("switch"),
            Verb::Cal => t!("cal"),
            Verb::Log => t!("log"),
            Verb::Help => t!("help"),
            Verb::Version => t!("version"),
        }
    }

    fn from_word(tok: &[u8]) -> Option<Verb> {
        Verb::all().find(|v| v.name().eq_ignore_case(tok))
    }
}

/// A `grip` command.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GripCmd {
    /// `grip open`: to the gripper's lower angle limit.
    Open,
    /// `grip close`: to the gripper's upper angle limit.
    Close,
    /// `grip <deg>`: to this angle, hundredths of a degree, within
    /// ±[`GOTO_MAX_CENTIDEG`] (the gripper's limits are the app's business).
    Centideg(i32),
}

/// A `pose` command; slots are numbered 1..=[`POSES`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PoseCmd {
    /// `pose save <n>`: the pose held now into slot n, stored in the EEPROM.
    Save(u8),
    /// `pose go <n>`: move to slot n's pose (as `goto` its angles).
    Go(u8),
    /// `pose clear <n>`: empty slot n, stored in the EEPROM.
    Clear(u8),
    /// `pose list`: every slot.
    List,
}

/// Largest `lift` height, hundredths of a workspace unit (issue #13: 0.5).
pub const LIFT_MAX_CENTI: i32 = crate::config::settings::LIFT_MAX_CENTI as i32;

/// Largest `circle` radius, hundredths of a workspace unit (0.5: the lab
/// note's circles are a fraction of the arm; larger ones leave the reach
/// from most poses).
pub const CIRCLE_MAX_CENTI: i32 = 50;

/// Why a line was not a command; each has the reason the `err` reply gives.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CmdError {
    /// Nothing but whitespace.
    Empty,
    /// The first word is no command.
    UnknownCommand,
    /// An unknown keyword argument (law, speed, joint, field, on/off, cal verb).
    BadArgument,
    /// Fewer arguments than the command takes.
    MissingArgument,
    /// More arguments than the command takes.
    ExtraArgument,
    /// A number that does not follow the grammar (module doc, Numbers).
    BadNumber,
    /// A well-formed number outside its field's range.
    OutOfRange,
    /// The line exceeded [`LINE_LEN`] bytes.
    TooLong,
    /// A byte that is not printable ASCII, space or tab.
    BadCharacter,
    /// A partial line got no new byte for `line_timeout_ms` (a terminal
    /// set to send no line ending): dropped and answered.
    LineTimeout,
}

impl CmdError {
    /// Short text for the `err <reason>` reply.
    pub fn reason(self) -> crate::text::Text {
        match self {
            CmdError::Empty => t!("empty line"),
            CmdError::UnknownCommand => t!("unknown command"),
            CmdError::BadArgument => t!("bad argument"),
            CmdError::MissingArgument => t!("missing argument"),
            CmdError::ExtraArgument => t!("extra argument"),
            CmdError::BadNumber => t!("bad number"),
            CmdError::OutOfRange => t!("out of range"),
            CmdError::TooLong => t!("line too long"),
            CmdError::BadCharacter => t!("bad character"),
            CmdError::LineTimeout => t!("line timeout (no line ending?)"),
        }
    }
}

/// `tok` is the keyword `kw`, in any case (`kw` in flash: as byte-string
/// constants the argument words took 55 bytes of static RAM on the chip).
fn is(tok: &[u8], kw: crate::text::Text) -> bool {
    kw.eq_ignore_case(tok)
}

fn is_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\n')
}

/// Whitespace-separated tokens of a line.
struct Tokens<'a> {
    rest: &'a [u8],
}

impl<'a> Tokens<'a> {
    fn next(&mut self) -> Option<&'a [u8]> {
        let start = self.rest.iter().position(|&b| !is_space(b))?;
        let rest = self.rest.get(start..).unwrap_or(&[]);
        let len = rest.iter().position(|&b| is_space(b)).unwrap_or(rest.len());
        let (tok, tail) = rest.split_at(len);
        self.rest = tail;
        Some(tok)
    }

    fn arg(&mut self) -> Result<&'a [u8], CmdError> {
        self.next().ok_or(CmdError::MissingArgument)
    }

    fn end(&mut self) -> Result<(), CmdError> {
        match self.next() {
            Some(_) => Err(CmdError::ExtraArgument),
            None => Ok(()),
        }
    }
}

/// Splits an optional leading sign.
fn sign(tok: &[u8]) -> (bool, &[u8]) {
    match tok.split_first() {
        Some((b'-', rest)) => (true, rest),
        Some((b'+', rest)) => (false, rest),
        _ => (false, tok),
    }
}

/// `v·10 + d` unless it would pass `i32::MAX`. Written with comparisons
/// rather than `checked_mul`: the overflow-checking multiply helper that
/// `checked_mul` calls crashes on the ATmega2560 (found in simavr).
fn push_digit(v: i32, d: i32) -> Option<i32> {
    const LAST: i32 = i32::MAX / 10;
    const LAST_DIGIT: i32 = i32::MAX % 10;
    if v > LAST || (v == LAST && d > LAST_DIGIT) {
        None
    } else {
        Some(v * 10 + d)
    }
}

fn digits_value(d: &[u8]) -> Result<i32, CmdError> {
    let mut v: i32 = 0;
    for &b in d {
        v = push_digit(v, (b - b'0') as i32).ok_or(CmdError::OutOfRange)?;
    }
    Ok(v)
}

fn all_digits(d: &[u8]) -> bool {
    !d.is_empty() && d.iter().all(u8::is_ascii_digit)
}

/// Parses a signed decimal integer in `min..=max`.
pub fn parse_int(tok: &[u8], min: i32, max: i32) -> Result<i32, CmdError> {
    let (neg, d) = sign(tok);
    if !all_digits(d) {
        return Err(CmdError::BadNumber);
    }
    let v = digits_value(d)?;
    let v = if neg { -v } else { v };
    if v < min || v > max {
        return Err(CmdError::OutOfRange);
    }
    Ok(v)
}

/// Parses a decimal with at most two fractional digits into hundredths, in
/// `min..=max` (hundredths).
pub fn parse_centi(tok: &[u8], min: i32, max: i32) -> Result<i32, CmdError> {
    let (neg, d) = sign(tok);
    let (int, frac) = match d.iter().position(|&b| b == b'.') {
        Some(p) => {
            let (i, f) = d.split_at(p);
            (i, f.get(1..).unwrap_or(&[]))
        }
        None => (d, &[][..]),
    };
    let has_point = int.len() != d.len();
    if !all_digits(int) || (has_point && (!all_digits(frac) || frac.len() > 2)) {
        return Err(CmdError::BadNumber);
    }
    let f = match frac {
        [a] => (a - b'0') as i32 * 10,
        [a, b] => (a - b'0') as i32 * 10 + (b - b'0') as i32,
        _ => 0,
    };
    // ×100 + f as two more digits, with the same overflow guard.
    let v = push_digit(digits_value(int)?, f / 10).and_then(|v| push_digit(v, f % 10)).ok_or(CmdError::OutOfRange)?;
    let v = if neg { -v } else { v };
    if v < min || v > max {
        return Err(CmdError::OutOfRange);
    }
    Ok(v)
}

fn parse_joint(tok: &[u8]) -> Option<Joint> {
    Joint::ALL.iter().copied().find(|j| j.name().eq_ignore_case(tok))
}

#[cfg_attr(target_arch = "avr", optimize(size))] // reason: cold
fn parse_cal_set(t: &mut Tokens) -> Result<CalSet, CmdError> {
    let target = t.arg()?;
    if is(target, t!("arm")) {
        let link = match t.arg()? {
            w if is(w, t!("l2")) => ArmLink::L2,
            w if is(w, t!("l3")) => ArmLink::L3,
            _ => return Err(CmdError::BadArgument),
        };
        let cmm = parse_centi(t.arg()?, i32::from(LINK_MIN_CMM), i32::from(LINK_MAX_CMM))? as u16;
        return Ok(CalSet::Arm { link, cmm });
    }
    let named = match target {
        w if is(w, t!("home")) => Some(NamedPose::Home),
        w if is(w, t!("park")) => Some(NamedPose::Park),
        _ => None,
    };
    if let Some(which) = named {
        let mut centideg = [0i16; 3];
        for v in centideg.iter_mut() {
            *v = parse_centi(t.arg()?, -NAMED_POSE_MAX_CENTIDEG, NAMED_POSE_MAX_CENTIDEG)? as i16;
        }
        return Ok(CalSet::Pose { which, centideg });
    }
    if is(target, t!("touch")) {
        let name = t.arg()?;
        let field =
            TouchField::ALL.iter().copied().find(|f| f.name().eq_ignore_case(name)).ok_or(CmdError::BadArgument)?;
        let (lo, hi) = field.range();
        let tok = t.arg()?;
        let value = if field.is_centi() { parse_centi(tok, lo, hi)? } else { parse_int(tok, lo, hi)? };
        return Ok(CalSet::Touch { field, value: value as u16 });
    }
    let joint = match target {
        w if is(w, t!("grip")) => None,
        _ => Some(parse_joint(target).ok_or(CmdError::BadArgument)?),
    };
    let name = t.arg()?;
    let field = JointField::ALL.iter().copied().find(|f| f.name().eq_ignore_case(name)).ok_or(CmdError::BadArgument)?;
    let tok = t.arg()?;
    let value = match field {
        JointField::Offset => parse_centi(tok, -2_000_000, 2_000_000)?,
        JointField::Scale => parse_centi(tok, -10_000, 10_000)?,
        JointField::MinUs | JointField::MaxUs => parse_int(tok, 500, 2500)?,
        JointField::MinDeg | JointField::MaxDeg => parse_centi(tok, -GOTO_MAX_CENTIDEG, GOTO_MAX_CENTIDEG)?,
        JointField::MaxSpeed => parse_centi(tok, 0, 360_000)?,
        JointField::MaxAccel => parse_centi(tok, 0, 6_000_000)?,
    };
    Ok(match joint {
        Some(joint) => CalSet::Joint { joint, field, value },
        None => CalSet::Grip { field, value },
    })
}

/// `auto|<controller>`, `invert on|off` or `rotate 0|180` after `cal set lcd`.
fn parse_lcd_set(t: &mut Tokens) -> Result<LcdSet, CmdError> {
    let w = t.arg()?;
    let invert = is(w, t!("invert"));
    if invert || is(w, t!("rotate")) {
        let v = t.arg()?;
        let (on, off) = if invert { (t!("on"), t!("off")) } else { (t!("180"), t!("0")) };
        let on = match v {
            v if is(v, on) => true,
            v if is(v, off) => false,
            _ => return Err(CmdError::BadArgument),
        };
        return Ok(if invert { LcdSet::Invert(on) } else { LcdSet::Rotate180(on) });
    }
    (0..).map_while(LcdChoice::from_id).find(|c| is(w, c.name())).map(LcdSet::Controller).ok_or(CmdError::BadArgument)
}

/// The words after `access`.
fn parse_access(t: &mut Tokens) -> Result<AccessCmd, CmdError> {
    let w = t.arg()?;
    let hide = is(w, t!("hide"));
    Ok(match w {
        w if is(w, t!("lock")) => AccessCmd::Lock,
        w if is(w, t!("unlock")) => AccessCmd::Unlock(Pin::parse(t.arg()?).ok_or(CmdError::BadArgument)?),
        w if is(w, t!("pin")) => AccessCmd::SetPin(match t.arg()? {
            p if is(p, t!("off")) => Pin::NONE,
            p => Pin::parse(p).ok_or(CmdError::BadArgument)?,
        }),
        w if hide || is(w, t!("show")) => {
            let name = t.arg()?;
            let bit = (0..).map_while(item_nth).find(|(_, n)| is(name, *n)).ok_or(CmdError::BadArgument)?.0;
            AccessCmd::Hide(bit, hide)
        }
        w if is(w, t!("cap")) => AccessCmd::Cap(SpeedPreset::from_name(t.arg()?).ok_or(CmdError::BadArgument)?),
        _ => return Err(CmdError::BadArgument),
    })
}

/// Parses one line (without or with its terminator).
#[cfg_attr(target_arch = "avr", optimize(size))] // reason: cold
pub fn parse(line: &[u8]) -> Result<Command, CmdError> {
    // A line from the buffer is at most LINE_LEN bytes; allow a caller that
    // passes its terminator too.
    if line.len() > LINE_LEN + 2 {
        return Err(CmdError::TooLong);
    }
    if line.iter().any(|&b| !(b.is_ascii_graphic() || is_space(b))) {
        return Err(CmdError::BadCharacter);
    }
    let mut t = Tokens { rest: line };
    let word = t.next().ok_or(CmdError::Empty)?;
    let cmd = match Verb::from_word(word).ok_or(CmdError::UnknownCommand)? {
        Verb::Move => {
            let x = parse_int(t.arg()?, 0, RAW_MAX)? as u16;
            let y = parse_int(t.arg()?, 0, RAW_MAX)? as u16;
            Command::Move { x, y }
        }
        Verb::Goto => {
            let mut centideg = [0i32; 3];
            for v in centideg.iter_mut() {
                *v = parse_centi(t.arg()?, -GOTO_MAX_CENTIDEG, GOTO_MAX_CENTIDEG)?;
            }
            Command::Goto { centideg }
        }
        Verb::Stop => Command::Stop,
        Verb::Resume => Command::Resume,
        Verb::Status => Command::Status,
        Verb::Law => Command::Law(LawKind::from_name(t.arg()?).ok_or(CmdError::BadArgument)?),
        Verb::Speed => Command::Speed(SpeedPreset::from_name(t.arg()?).ok_or(CmdError::BadArgument)?),
        Verb::Log => match t.arg()? {
            w if is(w, t!("on")) => Command::Log(LogMode::On),
            w if is(w, t!("off")) => Command::Log(LogMode::Off),
            w if is(w, t!("plot")) => Command::Log(LogMode::Plot),
            _ => return Err(CmdError::BadArgument),
        },
        Verb::Path => Command::Path(PathMode::from_name(t.arg()?).ok_or(CmdError::BadArgument)?),
        Verb::Lift => match t.arg()? {
            w if is(w, t!("off")) => Command::Lift(None),
            tok => Command::Lift(Some(parse_centi(tok, 1, LIFT_MAX_CENTI)? as u8)),
        },
        Verb::Mode => match t.arg()? {
            w if is(w, t!("hold")) => Command::Mode(true),
            w if is(w, t!("tap")) => Command::Mode(false),
            _ => return Err(CmdError::BadArgument),
        },
        Verb::Circle => Command::Circle { r_centi: parse_centi(t.arg()?, 1, CIRCLE_MAX_CENTI)? as u16 },
        Verb::Cal => match t.arg()? {
            w if is(w, t!("show")) => Command::CalShow,
            w if is(w, t!("save")) => Command::CalSave,
            w if is(w, t!("reset")) => match t.next() {
                None => Command::CalReset,
                Some(w) if is(w, t!("grip")) => Command::CalResetGrip,
                Some(_) => return Err(CmdError::ExtraArgument),
            },
            w if is(w, t!("set")) => {
                let mut after = Tokens { rest: t.rest };
                if after.next().is_some_and(|w| is(w, t!("lcd"))) {
                    t = after;
                    Command::CalLcd(parse_lcd_set(&mut t)?)
                } else {
                    Command::CalSet(parse_cal_set(&mut t)?)
                }
            }
            _ => return Err(CmdError::BadArgument),
        },
        Verb::Pose => {
            let verb = t.arg()?;
            let slot = |t: &mut Tokens| -> Result<u8, CmdError> { Ok(parse_int(t.arg()?, 1, POSES as i32)? as u8) };
            Command::Pose(match verb {
                w if is(w, t!("save")) => PoseCmd::Save(slot(&mut t)?),
                w if is(w, t!("go")) => PoseCmd::Go(slot(&mut t)?),
                w if is(w, t!("clear")) => PoseCmd::Clear(slot(&mut t)?),
                w if is(w, t!("list")) => PoseCmd::List,
                _ => return Err(CmdError::BadArgument),
            })
        }
        Verb::Grip => Command::Grip(match t.arg()? {
            w if is(w, t!("open")) => GripCmd::Open,
            w if is(w, t!("close")) => GripCmd::Close,
            tok => GripCmd::Centideg(parse_centi(tok, -GOTO_MAX_CENTIDEG, GOTO_MAX_CENTIDEG)?),
        }),
        Verb::Park => Command::Park,
        Verb::Undo => Command::Undo,
        Verb::Access => Command::Access(parse_access(&mut t)?),
        Verb::Switch => Command::Access(match t.arg()? {
            w if is(w, t!("on")) => AccessCmd::Switch(SwitchUse::On),
            w if is(w, t!("off")) => AccessCmd::Switch(SwitchUse::Off),
            w if is(w, t!("glass")) => AccessCmd::Switch(SwitchUse::Glass),
            w if is(w, t!("sweep")) => {
                let centi = parse_centi(t.arg()?, i32::from(SWEEP_MIN_DS) * 10, i32::from(SWEEP_MAX_DS) * 10)?;
                // Kept to the nearest tenth; the reply says what is kept.
                // In u16: an i32 division would link compiler_builtins'
                // 32-bit division (1.3 KB) over libgcc's.
                AccessCmd::Sweep(((centi as u16 + 5) / 10) as u8)
            }
            _ => return Err(CmdError::BadArgument),
        }),
        Verb::Help => Command::Help,
        Verb::Version => Command::Version,
    };
    t.end()?;
    Ok(cmd)
}

/// Accumulates received bytes into lines.
///
/// A line ends at `\n`, `\r` or `\r\n` (the `\n` of a `\r\n` pair does not
/// make a second, empty line). Backspace (0x08) and DEL (0x7F) remove the last
/// byte, for typing in a terminal. A line longer than `N` bytes is discarded
/// up to its terminator and reported once as [`CmdError::TooLong`]; the next
/// line is received normally. After bytes were lost in the port
/// ([`LineBuffer::after_loss`]) a damaged line is discarded without a report:
/// the loss is reported instead.
#[derive(Debug, Clone)]
pub struct LineBuffer<const N: usize> {
    buf: [u8; N],
    len: usize,
    overflowed: bool,
    after_cr: bool,
    /// Drop everything up to the next terminator, silently.
    skip: bool,
}

impl<const N: usize> Default for LineBuffer<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> LineBuffer<N> {
    /// An empty buffer.
    pub const fn new() -> Self {
        LineBuffer { buf: [0; N], len: 0, overflowed: false, after_cr: false, skip: false }
    }

    /// Feeds one byte. Returns `Some` when a line is complete: `Ok(line)`
    /// (possibly empty; terminator excluded) or `Err(TooLong)`.
    pub fn push(&mut self, byte: u8) -> Option<Result<&[u8], CmdError>> {
        let after_cr = core::mem::replace(&mut self.after_cr, byte == b'\r');
        match byte {
            b'\n' if after_cr => None,
            b'\r' | b'\n' => {
                let len = core::mem::replace(&mut self.len, 0);
                if core::mem::replace(&mut self.skip, false) {
                    self.overflowed = false;
                    None
                } else if core::mem::replace(&mut self.overflowed, false) {
                    Some(Err(CmdError::TooLong))
                } else {
                    Some(Ok(self.buf.get(..len).unwrap_or(&[])))
                }
            }
            _ if self.skip => None,
            0x08 | 0x7F => {
                if !self.overflowed {
                    self.len = self.len.saturating_sub(1);
                }
                None
            }
            _ => {
                if self.overflowed {
                    return None;
                }
                match self.buf.get_mut(self.len) {
                    Some(slot) => {
                        *slot = byte;
                        self.len += 1;
                    }
                    None => self.overflowed = true,
                }
                None
            }
        }
    }

    /// Drops a partial line (e.g. after a receive error).
    pub fn clear(&mut self) {
        self.len = 0;
        self.overflowed = false;
        self.after_cr = false;
        self.skip = false;
    }

    /// Bytes were lost right after the ones pushed so far (see
    /// [`crate::seam::SerialPort`]): the partial line belongs to a lost line
    /// and is dropped, and so is the rest of a line the loss cut into.
    pub fn after_loss(&mut self, loss: &RxLoss) {
        if loss.lines > 0 {
            self.len = 0;
            self.overflowed = false;
        }
        self.skip = loss.rest_damaged;
        self.after_cr = loss.after_cr;
    }

    /// A partial line was left idle (`line_timeout_ms`): drops it, and says
    /// whether it is owed a reply ([`CmdError::LineTimeout`]); the rest of a
    /// line cut by a receive loss is not (the loss was answered).
    pub fn expire(&mut self) -> bool {
        let owed = !self.skip && (self.len > 0 || self.overflowed);
        self.clear();
        owed
    }

    /// A partial line is waiting for its terminator.
    pub fn is_partial(&self) -> bool {
        self.len > 0 || self.overflowed || self.skip
    }
}
