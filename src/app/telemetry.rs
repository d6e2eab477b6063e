//! The app's output lines (integers only): move summaries, `status`,
//! `cal show` and the per-frame telemetry of `log on`.

use super::text::{milli, Line};
use super::{App, MoveKind, Pending, Status};
use crate::config::settings::{JointField, PathMode, TouchField};
use crate::math::units::rad_to_centideg;
use crate::motion::planner::shape_choice::AKind;
use crate::protocol::command::LogMode;
use crate::seam::SerialPort;
use crate::servo::map::Joint;

/// `cal show` lines before its final `ok` line.
const CAL_SHOW_LINES: u8 = 8;

impl App {
    /// Appends ` [cond <c>] ts_ms <ms> [replan [wait_ms <ms>]] [a_milli <a>
    /// smooth|limit|floor] vend <v> <v> <v>` (end velocities in mrad/s) for
    /// the move just started; `replan`: superposed on the running move.
    pub(super) fn describe_move(&self, line: &mut Line, with_condition: bool) {
        let m = &self.last_move;
        if with_condition {
            if let Some(t) = &m.touch {
                line.word(t!("cond")).num(i32::from(t.condition.number()));
            }
        }
        match m.kind {
            MoveKind::Joint => {}
            MoveKind::Line => {
                line.word(t!("path line"));
            }
            MoveKind::Circle { r } => {
                line.word(t!("r_milli")).num(milli(r / self.params.k));
            }
            MoveKind::Lift { h } => {
                // Back to the hundredths it was given in.
                line.word(t!("lift")).bytes(b" ").centi((h / self.params.k * 100.0 + 0.5) as i32);
            }
        }
        line.word(t!("ts_ms")).num(milli(m.ts));
        if let Some(wait) = m.replan {
            line.word(t!("replan"));
            if wait > 0 {
                line.word(t!("wait_ms")).num(i32::from(wait) * super::FRAME_MS as i32);
            }
        }
        if let Some(a) = &m.a {
            line.word(t!("a_milli")).num(milli(a.a)).word(match a.kind {
                AKind::SmoothStop => t!("smooth"),
                AKind::MonotoneLimit => t!("limit"),
                AKind::Floor => t!("floor"),
            });
        }
        line.word(t!("vend"));
        for v in m.end_velocity.iter() {
            line.num(milli(*v));
        }
    }

    /// `t <ms> <base> <shoulder> <elbow> <us> <us> <us> <grip> <us>`: the
    /// clock, the commanded angles in centidegrees and the pulses written
    /// this frame (µs, `.5` for a half: the timer's resolution), then the
    /// gripper's angle and pulse (`-` before its first).
    /// With `log plot` instead: `base:<deg>,shoulder:<deg>,elbow:<deg>,grip:<deg>`,
    /// the commanded angles in degrees with two decimals (centidegrees
    /// rounded, as `log on` prints them), nothing else on the line: the
    /// Arduino Serial Plotter's `label:value` pairs. Nothing with `log off`
    /// or before the first pulses.
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn send_telemetry<U: SerialPort>(&mut self, serial: &mut U, now_ms: u32) {
        let Some(pulses) = self.pulses else { return };
        let mut line = Line::new();
        match self.session.log {
            LogMode::Off => return,
            LogMode::On => {}
            LogMode::Plot => {
                for (j, q) in Joint::ALL.iter().zip(self.commanded.iter()) {
                    line.str(j.name()).bytes(b":").centi(rad_to_centideg(*q)).bytes(b",");
                }
                line.str(t!("grip:")).centi(rad_to_centideg(self.grip.commanded));
                self.emit(serial, &mut line);
                return;
            }
        }
        line.str(t!("t ")).u32(now_ms);
        for q in self.commanded.iter() {
            line.num(rad_to_centideg(*q));
        }
        for t in pulses.iter() {
            line.bytes(b" ").ticks_us(*t);
        }
        // The gripper's angle and pulse, appended (scripts read the first
        // seven fields by position).
        line.num(rad_to_centideg(self.grip.commanded)).bytes(b" ");
        match self.grip.ticks {
            Some(t) => line.ticks_us(t),
            None => line.bytes(b"-"),
        };
        self.emit(serial, &mut line);
    }

    /// Sends the next line of a multi-line reply, if one is pending.
    #[inline(never)] // avr-trap: frame-size
    #[cfg_attr(target_arch = "avr", optimize(size))] // reason: cold
    pub(super) fn flush_pending<U: SerialPort>(&mut self, serial: &mut U) {
        let Some(Pending::CalShow(i)) = self.session.pending else { return };
        // Not in a busy frame: the line waits for the next.
        if self.heavy.is_spent() {
            return;
        }
        let mut line = Line::new();
        self.cal_show_line(i, &mut line);
        // Part of a reply: it waits for room rather than being dropped.
        let bytes = line.finish();
        if serial.tx_room() < bytes.len() {
            return;
        }
        serial.write(bytes);
        self.session.pending = if i < CAL_SHOW_LINES { Some(Pending::CalShow(i + 1)) } else { None };
    }

    /// Line `i` of `cal show`: one per joint and one for the touch panel, in
    /// `cal set` units (so each value can be typed back), then `ok cal show`.
    // Out of line: its locals stay within `ldd`/`std`'s reach, the line's
    // buffer in the caller's frame.
    #[inline(never)] // reason: code-size
    fn cal_show_line(&self, i: u8, line: &mut Line) {
        let joint = match i {
            0 => Some(Joint::Base),
            1 => Some(Joint::Shoulder),
            2 => Some(Joint::Elbow),
            _ => None,
        };
        if let Some(j) = joint {
            line.str(t!("cal ")).str(j.name());
            for f in JointField::ALL {
                let v = self.config.joint_field(j, f);
                line.word(f.name()).bytes(b" ");
                if f.is_centi() {
                    line.centi(v);
                } else {
                    line.i32(v);
                }
            }
            return;
        }
        if i == 4 {
            self.grip_show_line(line);
            return;
        }
        if i == 5 {
            line.str(t!("cal "));
            self.lcd_words(line);
            return;
        }
        if i == 7 {
            self.access_show_line(line);
            return;
        }
        if i == 6 {
            // `cal arm l2 <mm> l3 <mm> home <b> <s> <e> park <b> <s> <e>`.
            let a = &self.config.arm;
            line.str(t!("cal arm l2 ")).centi(i32::from(a.l2_cmm));
            line.str(t!(" l3 ")).centi(i32::from(a.l3_cmm));
            let angles = |line: &mut Line, pose: &[i16; 3]| {
                for c in pose {
                    line.bytes(b" ").centi(i32::from(*c));
                }
            };
            line.str(t!(" home"));
            angles(line, &a.home);
            line.str(t!(" park"));
            angles(line, &a.park);
            return;
        }
        if i == 3 {
            let t = &self.config.touch;
            line.str(t!("cal touch"));
            for f in TouchField::ALL {
                let v = match f {
                    TouchField::XMin => t.x_min,
                    TouchField::XMax => t.x_max,
                    TouchField::YMin => t.y_min,
                    TouchField::YMax => t.y_max,
                    TouchField::Swap => u16::from(t.swap_xy),
                    TouchField::InvertX => u16::from(t.invert_x),
                    TouchField::InvertY => u16::from(t.invert_y),
                    TouchField::Hold => u16::from(self.config.press.hold_cs),
                    TouchField::Repeat => u16::from(self.config.press.repeat_cs),
                    TouchField::Radius => u16::from(self.config.press.radius),
                    TouchField::Plate => {
                        line.word(f.name());
                        super::text::plate_word(line, self.config.press.plate);
                        continue;
                    }
                };
                line.word(f.name());
                if f.is_centi() {
                    line.bytes(b" ").centi(i32::from(v));
                } else {
                    line.num(i32::from(v));
                }
            }
            return;
        }
        line.str(t!("ok cal show law ")).str(self.config.law.name()).word(t!("speed")).word(self.config.speed.name());
        line.word(t!("mode")).word(super::text::mode_name(self.config.hold_to_run));
    }
}

/// `ok status <state> law <l> speed <s> q <3 cdeg> target <3 cdeg> pulses
/// <3 us (.5 for a half) | - - -> progress <%> ts_ms <ms> [cond <c> alpha <cdeg>] [first_move_slow]
/// [warn <w>] grip <cdeg> [refused <reason>]`; the
/// reason, which may contain spaces, is last.
pub fn status_line(s: &Status, line: &mut Line) {
    line.str(t!("ok status ")).str(s.state.name());
    line.word(t!("law")).word(s.law.name()).word(t!("speed")).word(s.speed.name());
    // The defaults (joint moves, no lift) print nothing: the longest status
    // must fit the transmit ring.
    if s.path == PathMode::Line {
        line.word(t!("path line"));
    }
    if let Some(h) = s.lift_centi {
        line.word(t!("lift")).bytes(b" ").centi(i32::from(h));
    }
    line.word(t!("q"));
    for q in s.commanded.iter() {
        line.num(rad_to_centideg(*q));
    }
    line.word(t!("target"));
    for q in s.target.iter() {
        line.num(rad_to_centideg(*q));
    }
    line.word(t!("pulses"));
    match &s.pulses {
        Some(p) => {
            for t in p.iter() {
                line.bytes(b" ").ticks_us(*t);
            }
        }
        None => {
            line.str(t!(" - - -"));
        }
    }
    line.word(t!("progress")).num(i32::from(s.progress));
    line.word(t!("ts_ms")).num(milli(s.ts));
    if let Some(t) = &s.touch_target {
        line.word(t!("cond")).num(i32::from(t.condition.number()));
        line.word(t!("alpha")).num(rad_to_centideg(t.alpha));
    }
    if s.first_move_pending {
        line.word(t!("first_move_slow"));
    }
    if let Some(w) = s.config_warning {
        line.word(t!("warn")).word(match w {
            crate::config::store::Warning::Missing => t!("missing"),
            crate::config::store::Warning::Corrupt => t!("corrupt"),
            crate::config::store::Warning::VersionMismatch => t!("version"),
            crate::config::store::Warning::CopyDamaged => t!("copy_damaged"),
        });
    }
    // The gripper's commanded angle after every older field, before the
    // refusal reason, which stays last because it may contain spaces (its
    // pulse is in the telemetry: with it the widest status would not fit the
    // transmit ring).
    line.word(t!("grip")).num(rad_to_centideg(s.grip));
    if let Some(r) = s.last_refusal {
        line.word(t!("refused")).word(r.reason());
    }
}
