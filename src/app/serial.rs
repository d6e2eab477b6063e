//! Serial command handling: bytes → lines → [`Command`] → one reply line.
//!
//! Every non-empty line gets exactly one reply, `ok …` or `err <reason>`
//! (a line of only spaces and tabs: `err empty line`; `cal show` sends its
//! data lines first, one per frame, and ends with `ok cal show …`). A
//! malformed, over-long or out-of-range line is answered with `err` and
//! changes nothing.
//!
//! Flow control, so nothing is lost silently and nothing blocks the frame:
//! - at most one line is taken per frame, and only while the port has room
//!   for the longest reply ([`LINE_CAP`]); until then the bytes wait in the
//!   port, and while a multi-line reply is being sent no line is taken;
//! - lines the port's full receive buffer dropped are answered together, in
//!   their place in the stream: `err input overflow: <n> lines lost`;
//! - other output (touch and screen events, telemetry) goes out when it fits
//!   and is otherwise counted, then reported as `warn output full: <n> lines
//!   dropped` as soon as that fits.

use super::refusal::Refusal;
use super::telemetry::status_line;
use super::text::{Line, LINE_CAP};
use super::{App, Io, Pending};
use crate::config::settings::CalSet;
use crate::config::settings::{Config, ConfigError};
use crate::config::store::{self, SaveError};
use crate::protocol::command::{parse, CmdError, Command, LINE_LEN};
use crate::seam::{SerialPort, Storage};
use crate::touch::filter::TouchPoint;

impl App {
    /// Reads up to the byte budget, stopping after the first complete line
    /// (or a receive loss), and answers it.
    pub(super) fn poll_serial<P, S, C, E, U>(&mut self, io: &mut Io<'_, P, S, C, E, U>, now_ms: u32)
    where
        E: Storage,
        U: SerialPort,
    {
        if self.pending.is_some() || io.serial.tx_room() < LINE_CAP {
            return;
        }
        if self.line.is_partial() && now_ms.wrapping_sub(self.last_rx_ms) >= self.params.line_timeout_ms {
            self.line.clear();
        }
        let mut copy = [0u8; LINE_LEN];
        let mut reply = Line::new();
        let mut budget = self.params.serial_bytes_per_frame;
        while budget > 0 {
            budget -= 1;
            let Some(byte) = io.serial.read_byte() else {
                if let Some(loss) = io.serial.take_rx_loss() {
                    self.line.after_loss(&loss);
                    let n = loss.lines;
                    if n > 0 {
                        reply.str(t!("err input overflow:")).num(i32::from(n)).str(t!(" lines lost"));
                    }
                }
                break;
            };
            self.last_rx_ms = now_ms;
            let got = match self.line.push(byte) {
                None => continue,
                Some(Ok(l)) => {
                    let n = l.len().min(LINE_LEN);
                    if let (Some(dst), Some(src)) = (copy.get_mut(..n), l.get(..n)) {
                        dst.copy_from_slice(src);
                    }
                    Ok(n)
                }
                Some(Err(e)) => Err(e),
            };
            match got {
                Ok(n) => self.handle_line(copy.get(..n).unwrap_or(&[]), io.storage, &mut reply),
                Err(e) => {
                    reply.str(t!("err ")).str(e.reason());
                }
            }
            break;
        }
        if !reply.as_bytes().is_empty() {
            io.serial.write(reply.finish());
        }
    }

    /// Parses and executes one line; the reply goes into `reply` (left
    /// empty for an empty line).
    fn handle_line<E: Storage>(&mut self, bytes: &[u8], storage: &mut E, reply: &mut Line) {
        let cmd = match parse(bytes) {
            Ok(c) => c,
            Err(CmdError::Empty) if bytes.is_empty() => return,
            Err(e) => {
                reply.str(t!("err ")).str(e.reason());
                return;
            }
        };
        let result = match cmd {
            Command::Move { x, y } => self.move_to_raw(&TouchPoint { x, y }).map(|()| {
                reply.str(t!("ok move"));
                self.describe_move(reply, true);
            }),
            Command::Goto { centideg } => self.move_to_angles(&centideg).map(|()| {
                reply.str(t!("ok goto"));
                self.describe_move(reply, false);
            }),
            Command::Stop => {
                self.stop();
                reply.str(t!("ok stop"));
                Ok(())
            }
            Command::Resume => {
                self.resume();
                reply.str(t!("ok resume"));
                Ok(())
            }
            Command::Status => {
                status_line(&self.status(), reply);
                Ok(())
            }
            Command::Law(l) => {
                self.config.law = l;
                reply.str(t!("ok law ")).str(l.name());
                Ok(())
            }
            Command::Speed(s) => {
                self.config.speed = s;
                reply.str(t!("ok speed ")).str(s.name());
                Ok(())
            }
            Command::Log(on) => {
                self.log = on;
                reply.str(if on { t!("ok log on") } else { t!("ok log off") });
                Ok(())
            }
            Command::CalShow => {
                // The data lines follow one per frame, starting with this one.
                self.pending = Some(Pending::CalShow(0));
                Ok(())
            }
            Command::CalSet(set) => self.cal_set(&set, reply),
            Command::CalReset => self.replace_config(&Config::DEFAULT, false).map(|slew| {
                reply.str(t!("ok cal reset"));
                slew_suffix(slew, reply);
            }),
            Command::CalSave => self.cal_save(storage, reply),
        };
        if let Err(r) = result {
            reply.clear().str(t!("err ")).str(r.reason());
        }
    }

    fn cal_set(&mut self, set: &CalSet, reply: &mut Line) -> Result<(), Refusal> {
        if self.is_moving() {
            return Err(Refusal::Busy);
        }
        let mut next = self.config;
        if let Err(e) = next.apply(set) {
            reply.str(t!("err "));
            config_error(&e, reply);
            return Ok(());
        }
        let slew = self.replace_config(&next, matches!(set, CalSet::Touch { .. }))?;
        reply.str(t!("ok cal set"));
        slew_suffix(slew, reply);
        Ok(())
    }

    fn cal_save<E: Storage>(&mut self, storage: &mut E, reply: &mut Line) -> Result<(), Refusal> {
        if self.is_moving() {
            return Err(Refusal::Busy);
        }
        let config = self.config;
        match self.save_config(storage, &config) {
            Ok(seq) => {
                reply.str(t!("ok cal save seq")).num(i32::from(seq));
            }
            Err(SaveError::Invalid(e)) => {
                reply.str(t!("err "));
                config_error(&e, reply);
            }
            Err(SaveError::Storage(_)) => {
                reply.str(t!("err save failed: storage"));
            }
            Err(SaveError::Verify) => {
                reply.str(t!("err save failed: verify"));
            }
        }
        Ok(())
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
            self.tx_dropped = self.tx_dropped.saturating_add(1);
        }
    }

    /// `warn output full: <n> lines dropped`, once it fits, for the lines
    /// [`App::emit`] could not send.
    pub(super) fn report_dropped<U: SerialPort>(&mut self, serial: &mut U) {
        if self.tx_dropped == 0 {
            return;
        }
        let mut line = Line::new();
        line.str(t!("warn output full:")).num(i32::from(self.tx_dropped)).str(t!(" lines dropped"));
        let bytes = line.finish();
        if serial.tx_room() >= bytes.len() {
            serial.write(bytes);
            self.tx_dropped = 0;
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
    if let ConfigError::Joint(j, _) = e {
        line.str(j.name()).str(t!(" "));
    }
    line.str(e.reason());
}
