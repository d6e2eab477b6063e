//! Serial command handling: bytes → lines → [`Command`] → one reply line.
//!
//! Every non-empty line gets exactly one reply, `ok …` or `err <reason>`
//! (a line of only spaces and tabs: `err empty line`; `cal show` sends its
//! data lines first, one per frame, and ends with `ok cal show …`). A
//! malformed, over-long or out-of-range line is answered with `err` and
//! changes nothing; so is a partial line left idle for `line_timeout_ms`
//! (`err line timeout (no line ending?)`: a terminal set to send no line
//! ending).
//!
//! The one-byte STOP `!` is no line: the port flags it as it arrives and the
//! next frame latches STOP first of all, in a catch-up frame too (a latch is
//! no heavy work), with a line half received or a reply pending, and answers
//! `ok stop` (once per frame that took a `!`, before that frame's other
//! replies; when the port lacks room, as soon as it has it).
//!
//! A path move (`move`/`goto` under `path line`, `circle`) is answered when
//! its check decides, some frames later (`path_move`): `ok move … path line
//! ts_ms …`, `ok circle r_milli … ts_ms …` or `err path …`; lines sent
//! meanwhile are taken and answered in between (`stop` cancels the check:
//! `ok stop`, then the move's `err path check stopped`).
//!
//! Flow control, so nothing is lost silently and nothing blocks the frame:
//! - at most one line is taken per frame, and only while the port has room
//!   for the longest reply ([`LINE_CAP`]); until then the bytes wait in the
//!   port; no line is taken while a multi-line reply is being sent or a touch
//!   waits for a frame to plan in;
//! - lines the port lost (its receive buffer was full, or a byte arrived
//!   garbled) are answered together, in their place in the stream:
//!   `err input lost: <n> lines`;
//! - other output (touch and screen events, telemetry) goes out when it fits
//!   and is otherwise counted, then reported as `warn output full: <n> lines
//!   dropped` as soon as that fits.

use super::access::AccessDone;
use super::poses::{PoseDone, PoseStoreError};
use super::refusal::Refusal;
use super::telemetry::status_line;
use super::text::{Line, LINE_CAP};
use super::{Answer, App, Io, Pending};
use crate::config::settings::CalSet;
use crate::config::settings::{Config, ConfigError, PathMode, SpeedPreset};
use crate::config::store::{self, SaveError};
use crate::motion::plan::LawKind;
use crate::protocol::command::{parse, CmdError, Command, LogMode, SerialLine, Verb, STOP_BYTE};
use crate::seam::{SerialPort, Storage};
use crate::touch::filter::TouchPoint;

/// The serial session's state, apart from what the commands change: the
/// line being received and when its last byte came (the idle timeout), the
/// telemetry switch, a multi-line reply in progress and the unsolicited
/// lines the port had no room for.
pub(super) struct Session {
    /// The line being received.
    pub(super) line: SerialLine,
    /// When its last byte came, ms (a partial line idle too long is dropped
    /// and answered).
    pub(super) last_rx_ms: u32,
    /// Per-frame telemetry (`log on|plot|off`).
    pub(super) log: LogMode,
    /// Lines still to send of a multi-line reply.
    pub(super) pending: Option<Pending>,
    /// Unsolicited lines the port had no room for, not yet reported.
    pub(super) tx_dropped: u16,
    /// A `!` latched STOP and its `ok stop` is not sent yet.
    pub(super) stop_owed: bool,
}

impl Session {
    /// No line, no telemetry, nothing pending or dropped.
    pub(super) const fn new() -> Session {
        Session {
            line: SerialLine::new(),
            last_rx_ms: 0,
            log: LogMode::Off,
            pending: None,
            tx_dropped: 0,
            stop_owed: false,
        }
    }
}

/// What a line did, for its reply. The reply is formatted after the work, in
/// [`App::send_reply`], so its buffer is not on the stack while a move is
/// planned.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Done {
    /// No reply: an empty line, or `cal show` (its lines follow).
    Nothing,
    Bad(CmdError),
    Refused(Refusal),
    Moved,
    Went,
    Stopped,
    Resumed,
    Status,
    Law(LawKind),
    Speed(SpeedPreset),
    Log(LogMode),
    Help,
    Version,
    CalSet(Option<f32>),
    CalReset(Option<f32>),
    CalInvalid(ConfigError),
    /// The configuration's sequence number, and the gripper record's if it
    /// was stored too.
    CalSaved(Result<(u16, Option<u16>), SaveError>),
    /// A `grip` line, answered once planned (`App::finish_grip`).
    GripDue,
    /// Lines the port lost.
    Lost(u16),
    /// A `pose` command.
    Pose(PoseDone),
    Path(PathMode),
    Lift(Option<u8>),
    /// `mode hold` (`true`) or `mode tap`.
    Mode(bool),
    /// A circle, once its check decided.
    Circled,
    /// `park`, once planned.
    Parked,
    /// `undo`, once planned.
    Undone,
    /// `cal set lcd …`: the display overrides' new sequence number.
    CalLcd(Result<u16, SaveError>),
    /// An `access` command.
    Access(AccessDone),
}

impl App {
    /// The one-byte STOP: latches STOP if the port flagged a `!`, and sends
    /// the `ok stop` it owes once the port has room (see the module doc).
    /// Before everything else in the frame, catch-up frames included.
    // Out of line: inlined it added a byte to the firmware's frame, which is
    // on the deepest stack chain (frame → execute → replace_config → planner).
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn poll_stop_byte<U: SerialPort>(&mut self, serial: &mut U) {
        if serial.take_stop_byte() {
            self.stop();
            self.session.stop_owed = true;
        }
        if self.session.stop_owed && serial.tx_room() >= LINE_CAP {
            self.session.stop_owed = false;
            self.send_reply(serial, &Done::Stopped);
        }
    }

    /// Reads up to the byte budget, stopping after the first complete line
    /// (or a receive loss), and answers it.
    pub(super) fn poll_serial<P, S, C, E, U>(&mut self, io: &mut Io<'_, P, S, C, E, U>, now_ms: u32)
    where
        E: Storage,
        U: SerialPort,
    {
        // A late frame catches up; a touch waiting to plan has this frame
        // (see `poll_touch`).
        if self.heavy.is_spent()
            || self.session.pending.is_some()
            || self.deferred_touch.is_some()
            || io.serial.tx_room() < LINE_CAP
        {
            return;
        }
        let mut done = Done::Nothing;
        let mut budget = self.params.serial_bytes_per_frame;
        if self.session.line.is_partial()
            && now_ms.wrapping_sub(self.session.last_rx_ms) >= self.params.line_timeout_ms
            && self.session.line.expire()
        {
            // Answered like a line: it is this frame's one reply.
            done = Done::Bad(CmdError::LineTimeout);
            budget = 0;
        }
        while budget > 0 {
            budget -= 1;
            let Some(byte) = io.serial.read_byte() else {
                if let Some(loss) = io.serial.take_rx_loss() {
                    self.session.line.after_loss(&loss);
                    if loss.lines > 0 {
                        done = Done::Lost(loss.lines);
                    }
                }
                break;
            };
            if byte == STOP_BYTE {
                // A port that passes `!` on in the stream (the seam's
                // default): acted on here, still no part of the line.
                self.stop();
                done = Done::Stopped;
                break;
            }
            self.session.last_rx_ms = now_ms;
            let parsed = match self.session.line.push(byte) {
                None => continue,
                Some(Ok([])) => None,
                Some(Ok(l)) => Some(parse(l)),
                Some(Err(e)) => Some(Err(e)),
            };
            done = match parsed {
                None => Done::Nothing,
                Some(Ok(cmd)) => match self.check_unlocked(&cmd) {
                    Ok(()) => self.execute(cmd, io.storage),
                    Err(e) => Done::Refused(e),
                },
                Some(Err(e)) => Done::Bad(e),
            };
            break;
        }
        if done == Done::Nothing {
            return;
        }
        self.spend_heavy();
        // A move is answered once it is planned (`finish_plan`).
        if let Some(due) = self.plan_due.as_mut().filter(|d| d.answer == Answer::Nobody) {
            due.answer = Answer::Serial(done);
            return;
        }
        self.send_reply(io.serial, &done);
    }

    /// Carries out one command.
    fn execute<E: Storage>(&mut self, cmd: Command, storage: &mut E) -> Done {
        let result = match cmd {
            Command::Move { x, y } => self.move_to_raw(&TouchPoint { x, y }).map(|()| Done::Moved),
            Command::Goto { centideg } => self.move_to_angles(&centideg).map(|()| Done::Went),
            Command::Stop => {
                self.stop();
                Ok(Done::Stopped)
            }
            Command::Resume => {
                self.resume();
                Ok(Done::Resumed)
            }
            Command::Status => Ok(Done::Status),
            Command::Law(l) => {
                self.config.law = l;
                Ok(Done::Law(l))
            }
            Command::Speed(s) => {
                self.config.speed = s;
                Ok(Done::Speed(s))
            }
            Command::Log(mode) => {
                self.session.log = mode;
                Ok(Done::Log(mode))
            }
            Command::Help => Ok(Done::Help),
            Command::Version => Ok(Done::Version),
            Command::Path(m) => self.set_path(m).map(|()| Done::Path(m)),
            Command::Lift(h) => self.set_lift(h).map(|()| Done::Lift(h)),
            Command::Mode(hold) => self.set_hold_mode(hold).map(|()| Done::Mode(hold)),
            Command::Circle { r_centi } => self.start_circle(r_centi).map(|()| Done::Circled),
            Command::CalShow => {
                // The data lines follow one per frame, starting with this one.
                self.session.pending = Some(Pending::CalShow(0));
                Ok(Done::Nothing)
            }
            Command::CalSet(set) => self.cal_set(&set),
            // The measured wiring is a fact about the shield, not a setting.
            Command::CalReset => {
                let defaults = Config { wiring: self.config.wiring, ..Config::DEFAULT };
                self.replace_config(&defaults, false).map(Done::CalReset)
            }
            Command::CalSave => self.cal_save(storage),
            Command::Pose(p) => self.pose(p, storage).map(Done::Pose),
            Command::Grip(g) => self.grip_command(g),
            Command::CalResetGrip => self.grip_reset(),
            Command::CalLcd(set) => self.cal_lcd(set, storage),
            Command::Park => self.move_to_angles(&self.config.arm.park.map(i32::from)).map(|()| Done::Parked),
            Command::Undo => self.undo().map(|()| Done::Undone),
            Command::Access(a) => self.access(a, storage).map(Done::Access),
        };
        result.unwrap_or_else(Done::Refused)
    }

    fn cal_set(&mut self, set: &CalSet) -> Result<Done, Refusal> {
        if self.is_moving() {
            return Err(Refusal::Busy);
        }
        if let CalSet::Grip { field, value } = *set {
            return self.grip_cal_set(field, value);
        }
        if let CalSet::Pose { centideg, .. } = set {
            self.check_named_pose(centideg)?;
        }
        let mut next = self.config;
        if let Err(e) = next.apply(set) {
            return Ok(Done::CalInvalid(e));
        }
        self.replace_config(&next, matches!(set, CalSet::Touch { .. })).map(Done::CalSet)
    }

    /// A home or park pose is judged as a `goto` to it under the running
    /// calibration (angle limits to the hundredth, no pulse clamp), so the
    /// arm can reach what it is told to power up in or park at. A later
    /// limit change does not re-judge it: home is clamped into the windows
    /// at power-up, as the pulses would be, and `park` is judged as a
    /// `goto` each time.
    // Its angles stay out of cal_set's frame, on the slew's deep chain.
    #[inline(never)] // avr-trap: frame-size
    fn check_named_pose(&self, centideg: &[i16; 3]) -> Result<(), Refusal> {
        let target = self.goto_angles(&centideg.map(i32::from))?;
        self.check_limits(&target)
    }

    fn cal_save<E: Storage>(&mut self, storage: &mut E) -> Result<Done, Refusal> {
        if self.is_moving() {
            return Err(Refusal::Busy);
        }
        let config = self.config;
        let saved = self.save_config(storage, &config).and_then(|seq| Ok((seq, self.save_grip(storage)?)));
        Ok(Done::CalSaved(saved))
    }

    /// The one reply line of a command (see [`Done`]).
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn send_reply<U: SerialPort>(&mut self, serial: &mut U, done: &Done) {
        if matches!(done, Done::Nothing | Done::GripDue) {
            return;
        }
        let mut reply = Line::new();
        self.reply_line(done, &mut reply);
        serial.write(reply.finish());
    }

    /// The text of [`App::send_reply`]'s line (not `Nothing` or `GripDue`).
    // Out of line: its locals stay within `ldd`/`std`'s reach, the line's
    // buffer in the caller's frame.
    #[inline(never)] // reason: code-size
    #[cfg_attr(target_arch = "avr", optimize(size))] // reason: cold
    fn reply_line(&self, done: &Done, r: &mut Line) {
        match *done {
            Done::Nothing | Done::GripDue => {}
            Done::Bad(e) => {
                r.str(t!("err ")).str(e.reason());
            }
            Done::Refused(e) => {
                r.str(t!("err ")).str(e.reason());
            }
            Done::Moved => {
                r.str(t!("ok move"));
                self.describe_move(r, true);
            }
            Done::Went => {
                r.str(t!("ok goto"));
                self.describe_move(r, false);
            }
            Done::Stopped => {
                r.str(t!("ok stop"));
            }
            Done::Resumed => {
                r.str(t!("ok resume"));
            }
            Done::Status => status_line(&self.status(), r),
            Done::Law(l) => {
                r.str(t!("ok law ")).str(l.name());
            }
            Done::Speed(s) => {
                r.str(t!("ok speed ")).str(s.name());
                self.cap_suffix(s, r);
            }
            Done::Log(mode) => {
                r.str(match mode {
                    LogMode::On => t!("ok log on"),
                    LogMode::Off => t!("ok log off"),
                    LogMode::Plot => t!("ok log plot"),
                });
            }
            Done::Help => {
                // The words `parse` knows, from its own table, and the `!`.
                r.str(t!("ok help"));
                for v in Verb::all() {
                    r.word(v.name());
                }
                r.word(t!("!"));
            }
            Done::Version => {
                // Both from flash, as the boot line (`build.rs`).
                r.str(t!("ok version ")).str(t!(crate::VERSION)).word(t!(crate::COMMIT));
            }
            Done::Path(m) => {
                r.str(t!("ok path ")).str(m.name());
            }
            Done::Lift(Some(h)) => {
                r.str(t!("ok lift ")).centi(i32::from(h));
            }
            Done::Lift(None) => {
                r.str(t!("ok lift off"));
            }
            Done::Mode(hold) => {
                r.str(t!("ok mode ")).str(super::text::mode_name(hold));
            }
            Done::Circled => {
                r.str(t!("ok circle"));
                self.describe_move(r, false);
            }
            Done::Parked => {
                r.str(t!("ok park"));
                self.describe_move(r, false);
            }
            Done::Undone => {
                r.str(t!("ok undo"));
                self.describe_move(r, false);
                r.word(t!("left")).num(i32::from(self.undo.left()));
                if let Some(g) = self.undo.grip_kept() {
                    r.word(t!("grip kept")).bytes(b" ").centi(crate::math::units::rad_to_centideg(g));
                }
            }
            Done::CalSet(slew) => {
                r.str(t!("ok cal set"));
                slew_suffix(slew, r);
            }
            Done::CalReset(slew) => {
                r.str(t!("ok cal reset"));
                slew_suffix(slew, r);
            }
            Done::CalInvalid(e) | Done::CalSaved(Err(SaveError::Invalid(e))) => {
                r.str(t!("err "));
                config_error(&e, r);
            }
            Done::CalSaved(Ok((seq, grip))) => {
                r.str(t!("ok cal save seq")).num(i32::from(seq));
                if let Some(g) = grip {
                    r.word(t!("grip_seq")).num(i32::from(g));
                }
            }
            Done::CalLcd(Ok(seq)) => {
                r.str(t!("ok cal set "));
                self.lcd_words(r);
                r.word(t!("seq")).num(i32::from(seq)).word(t!("(next boot)"));
            }
            Done::CalSaved(Err(SaveError::Storage(_))) | Done::CalLcd(Err(SaveError::Storage(_))) => {
                r.str(t!("err save failed: storage"));
            }
            Done::CalSaved(Err(SaveError::Verify)) | Done::CalLcd(Err(_)) => {
                r.str(t!("err save failed: verify"));
            }
            Done::Lost(n) => {
                r.str(t!("err input lost:")).num(i32::from(n)).str(t!(" lines"));
            }
            Done::Pose(PoseDone::Stored(n, save, Ok(seq))) => {
                r.str(if save { t!("ok pose save") } else { t!("ok pose clear") });
                r.num(i32::from(n)).word(t!("seq")).num(i32::from(seq));
            }
            Done::Pose(PoseDone::Stored(_, _, Err(e))) => {
                r.str(match e {
                    PoseStoreError::Range => t!("err out of range"),
                    PoseStoreError::Save(SaveError::Verify) => t!("err save failed: verify"),
                    PoseStoreError::Save(_) => t!("err save failed: storage"),
                });
            }
            Done::Pose(PoseDone::Went(n)) => {
                r.str(t!("ok pose go")).num(i32::from(n));
                self.describe_move(r, false);
            }
            Done::Pose(PoseDone::Empty(n)) => {
                r.str(t!("err pose")).num(i32::from(n)).str(t!(" empty"));
            }
            Done::Pose(PoseDone::List) => self.pose_list(r),
            Done::Access(d) => self.access_reply(&d, r),
        }
    }
}

impl App {
    /// Sends a line nobody asked for (touch and screen events, telemetry)
    /// if it fits in the port; otherwise counts it for
    /// [`App::report_dropped`].
    pub(super) fn emit<U: SerialPort>(&mut self, serial: &mut U, line: &mut Line) {
        let bytes = line.finish();
        if serial.tx_room() >= bytes.len() {
            serial.write(bytes);
        } else {
            self.session.tx_dropped = self.session.tx_dropped.saturating_add(1);
        }
    }

    /// `warn output full: <n> lines dropped`, once it fits, for the lines
    /// [`App::emit`] could not send.
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn report_dropped<U: SerialPort>(&mut self, serial: &mut U) {
        if self.session.tx_dropped == 0 {
            return;
        }
        let mut line = Line::new();
        line.str(t!("warn output full:")).num(i32::from(self.session.tx_dropped)).str(t!(" lines dropped"));
        let bytes = line.finish();
        if serial.tx_room() >= bytes.len() {
            serial.write(bytes);
            self.session.tx_dropped = 0;
        }
    }

    /// Writes `config` to both EEPROM copies. Both now hold it, so a warning
    /// about the stored copies no longer holds (every save goes through here:
    /// `cal save` and the screen's calibration Save).
    pub(super) fn save_config<E: Storage>(&mut self, storage: &mut E, config: &Config) -> Result<u16, SaveError> {
        let seq = store::save(storage, config)?;
        self.warning = None;
        Ok(seq)
    }
}

/// ` slew ts_ms <ms>` when a calibration change moves the held pulses.
fn slew_suffix(slew: Option<f32>, reply: &mut Line) {
    if let Some(ts) = slew {
        reply.word(t!("slew ts_ms")).num(super::text::milli(ts));
    }
}

/// `<joint> <reason>` or `<reason>` of an invalid calibration change.
fn config_error(e: &ConfigError, line: &mut Line) {
    match e {
        ConfigError::Joint(j, _) => {
            line.str(j.name()).str(t!(" "));
        }
        ConfigError::Grip(_) => {
            line.str(t!("grip "));
        }
        ConfigError::Touch(_) | ConfigError::Arm => {}
    }
    line.str(e.reason());
}
