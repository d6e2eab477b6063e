//! Serial command handling: bytes → lines → [`Command`] → one reply line.
//!
//! Every line gets exactly one reply, `ok …` or `err <reason>` (empty lines
//! are ignored; `cal show` sends its data lines first, one per frame, and
//! ends with `ok cal show …`). A malformed, over-long or out-of-range line is
//! answered with `err` and changes nothing. While a multi-line reply is being
//! sent no new line is read (the bytes wait in the port).

use super::refusal::Refusal;
use super::telemetry::status_line;
use super::text::Line;
use super::{build_maps, App, Io, Pending};
use crate::config::settings::CalSet;
use crate::config::settings::{Config, ConfigError};
use crate::config::store::{self, SaveError};
use crate::math::units::centideg_to_rad;
use crate::motion::plan::JOINTS;
use crate::protocol::command::{parse, CmdError, Command, LINE_LEN};
use crate::seam::{SerialPort, Storage};
use crate::touch::filter::TouchPoint;

impl App {
    /// Reads up to the byte budget, stopping after the first complete line,
    /// and answers it.
    pub(super) fn poll_serial<P, S, C, E, U>(&mut self, io: &mut Io<'_, P, S, C, E, U>, now_ms: u32)
    where
        E: Storage,
        U: SerialPort,
    {
        if self.pending.is_some() {
            return;
        }
        if self.line_partial && now_ms.wrapping_sub(self.last_rx_ms) >= self.params.line_timeout_ms {
            self.line.clear();
            self.line_partial = false;
        }
        let mut copy = [0u8; LINE_LEN];
        let mut budget = self.params.serial_bytes_per_frame;
        while budget > 0 {
            budget -= 1;
            let Some(byte) = io.serial.read_byte() else { break };
            self.last_rx_ms = now_ms;
            let got = match self.line.push(byte) {
                None => {
                    self.line_partial = !matches!(byte, b'\r' | b'\n');
                    continue;
                }
                Some(Ok(l)) => {
                    let n = l.len().min(LINE_LEN);
                    if let (Some(dst), Some(src)) = (copy.get_mut(..n), l.get(..n)) {
                        dst.copy_from_slice(src);
                    }
                    Ok(n)
                }
                Some(Err(e)) => Err(e),
            };
            self.line_partial = false;
            let mut reply = Line::new();
            match got {
                Ok(n) => self.handle_line(copy.get(..n).unwrap_or(&[]), io.storage, &mut reply),
                Err(e) => {
                    reply.str(t!("err ")).str(e.reason());
                }
            }
            if !reply.as_bytes().is_empty() {
                io.serial.write(reply.finish());
            }
            break;
        }
    }

    /// Parses and executes one line; the reply goes into `reply` (left
    /// empty for an empty line).
    fn handle_line<E: Storage>(&mut self, bytes: &[u8], storage: &mut E, reply: &mut Line) {
        let cmd = match parse(bytes) {
            Ok(c) => c,
            Err(CmdError::Empty) => return,
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
            Command::Goto { centideg } => {
                let mut target = [0.0f32; JOINTS];
                for (t, c) in target.iter_mut().zip(centideg.iter()) {
                    *t = centideg_to_rad(*c);
                }
                self.move_to_angles(&target).map(|()| {
                    reply.str(t!("ok goto"));
                    self.describe_move(reply, false);
                })
            }
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
            Command::CalReset => self.replace_config(&Config::DEFAULT, false).map(|()| {
                reply.str(t!("ok cal reset"));
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
        self.replace_config(&next, matches!(set, CalSet::Touch { .. }))?;
        reply.str(t!("ok cal set"));
        Ok(())
    }

    /// Installs a valid configuration, unless a move runs or the held pose
    /// would fall outside the new limits (the servo would jump to a limit).
    fn replace_config(&mut self, next: &Config, touch_changed: bool) -> Result<(), Refusal> {
        if self.is_moving() {
            return Err(Refusal::Busy);
        }
        let maps = build_maps(next).ok_or(Refusal::Fault)?;
        for (m, q) in maps.iter().zip(self.commanded.iter()) {
            match m.angle_to_pulse(*q) {
                Ok(p) if p.clamped.is_none() => {}
                _ => return Err(Refusal::HeldPoseOutside),
            }
        }
        if touch_changed || next.touch != self.config.touch {
            self.filter.reset();
        }
        self.config = *next;
        self.maps = maps;
        Ok(())
    }

    fn cal_save<E: Storage>(&mut self, storage: &mut E, reply: &mut Line) -> Result<(), Refusal> {
        if self.is_moving() {
            return Err(Refusal::Busy);
        }
        match store::save(storage, &self.config) {
            Ok(seq) => {
                // Both copies now hold this configuration.
                self.warning = None;
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

/// `<joint> <reason>` or `<reason>` of an invalid calibration change.
fn config_error(e: &ConfigError, line: &mut Line) {
    if let ConfigError::Joint(j, _) = e {
        line.str(j.name()).str(t!(" "));
    }
    line.str(e.reason());
}
