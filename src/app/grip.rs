//! The gripper: a fourth servo (D11, Timer1's OC1A on the chip), calibrated
//! like a joint (`cal set grip …`, stored in its own record,
//! [`crate::config::grip`]) and moved by `grip open|close|<deg>` and the
//! screen's Grip button.
//!
//! # Motion
//! A grip is a single-joint move planned by the arm's planner
//! ([`plan_move`](crate::motion::planner::plan_move::plan_move): the selected law, the speed preset, the gripper's speed
//! and acceleration limits less the safety margin, `ts_min`/`ts_max`, the
//! same refusals), the gripper in the plan's first joint and the other two
//! standing still, so no second trajectory implementation exists. It runs on
//! its own clock beside the arm's move: a grip while the arm moves (or a
//! move while the gripper moves) runs at once, each on its own plan. The
//! gripper's plan is evaluated once per frame (one profile value) and its
//! angle mapped to a pulse by its [`ServoMap`], inside its limits.
//!
//! A grip target is planned after the frame's pulses, like the arm's; when
//! the arm planned in the same frame (`pose go` with a gripper angle), the
//! grip is planned in the next frame, so a frame holds one plan at most,
//! and never in a catch-up frame (which plans nothing, module doc of `app`).
//! A pose's gripper waits for the arm's verdict: its plan, or its path or
//! lift check, which can take many frames; a refused arm drops it, so a
//! refused pose does not open or close the hand where it stands.
//! A new grip target while the gripper moves is refused (`err busy
//! gripping`): its plans start at rest, and a gripper's moves are short.
//!
//! # Power-up and STOP
//! The gripper gets no pulse before the configuration (and its record) is
//! loaded: the first frame loads them and sends no pulse; from the second
//! frame the gripper is commanded **open** (the low end of its output
//! window) with the joints' home pose, and grip targets are refused while
//! the arm homes. Its true position is unknown at power-up, so, as for the
//! joints, nothing can make this first approach slow, and the first grip
//! move after power-up runs at the slow preset at most. STOP freezes the
//! gripper where the previous frame put it and refuses grips until
//! `resume`.

use super::refusal::Refusal;
use super::serial::Done;
use super::text::Line;
use super::{App, Mode, FRAME_S};
use crate::config::grip::{self as record, GRIP_DEFAULT};
use crate::config::settings::{field_value, set_field, ConfigError, JointField, SpeedPreset};
use crate::config::store::SaveError;
use crate::math::units::centideg_to_rad;
use crate::motion::plan::{MultiPlan, JOINTS};
use crate::motion::planner::plan_move::{choose_law, plan_chosen, ChosenLaw};
use crate::motion::planner::request::{MoveRequest, PlanLimits};
use crate::protocol::command::GripCmd;
use crate::seam::{SerialPort, ServoOutputs, Storage};
use crate::servo::map::{JointCal, ServoMap};

/// The gripper's state in the app.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Grip {
    /// Its calibration, validated.
    pub(super) map: ServoMap,
    /// Angle commanded in the last frame, rad.
    pub(super) commanded: f32,
    /// Target of the current or last grip move, rad.
    pub(super) target: f32,
    /// The running move (the gripper in joint 0), and the frames it has run.
    plan: Option<MultiPlan<f32>>,
    n: u16,
    /// Pulse written in the last frame, ticks (`None` before the first).
    pub(super) ticks: Option<u16>,
    /// A target accepted this frame, planned after the pulses.
    due: Option<GripDue>,
    /// Duration of the current or last grip move, s.
    pub(super) ts: f32,
    /// The calibration differs from the stored one (`cal save` stores it).
    dirty: bool,
    /// No grip move has completed since power-up.
    first: bool,
}

/// A grip target waiting for its plan, and who hears how it went.
#[derive(Debug, Clone, Copy, PartialEq)]
struct GripDue {
    target: f32,
    who: GripWho,
    /// A pose's gripper waits for the arm's verdict (its plan, or its path
    /// or lift check over the following frames): a refused pose moves
    /// nothing, the hand included.
    awaits_arm: bool,
}

/// Who asked for a grip.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum GripWho {
    /// A `grip` line: its reply.
    Serial,
    /// `pose go n` (from serial or the screen): answered by the arm's plan;
    /// a failed grip plan is a `warn` line.
    Pose(u8),
    /// The screen's Grip button: `info screen grip …` / `err screen grip …`.
    Screen,
}

impl Grip {
    /// At rest at the open end of `cal`'s output window, no pulse yet.
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn new(cal: &JointCal) -> Option<Grip> {
        let map = ServoMap::new(cal).ok()?;
        let open = map.output_window().0;
        Some(Grip {
            map,
            commanded: open,
            target: open,
            plan: None,
            n: 0,
            ticks: None,
            due: None,
            ts: 0.0,
            dirty: false,
            first: true,
        })
    }

    /// A grip move is running.
    pub(super) fn is_moving(&self) -> bool {
        self.plan.is_some()
    }

    /// The open and closed angles (rad): the ends of the output window.
    pub(super) fn ends(&self) -> (f32, f32) {
        self.map.output_window()
    }
}

impl App {
    /// Boot: the stored gripper calibration (defaults when none is valid; a
    /// damaged copy is reported), the gripper open and at rest.
    pub(super) fn grip_boot<E: Storage, U: SerialPort>(&mut self, storage: &mut E, serial: &mut U) {
        let loaded = record::load(storage);
        // `load` validates; the defaults are checked by `App::new`.
        if let Some(g) = Grip::new(&loaded.cal) {
            self.grip = g;
        }
        if loaded.damaged {
            let mut line = Line::new();
            line.str(t!("warn stored grip calibration damaged"));
            self.emit(serial, &mut line);
        }
    }

    /// After a reset that kept RAM (`resume.rs`): the gripper holds the
    /// resumed pulse's angle `q` instead of opening.
    pub(super) fn grip_hold_resumed(&mut self, q: f32) {
        self.grip.commanded = q;
        self.grip.target = q;
    }

    /// `grip open|close|<deg>`: checked now, planned after the pulses.
    // The gripper's commands are not inlined into `execute`: their locals
    // would sit in its frame under the deepest path (a calibration slew's
    // plan); measured with the stack test of `firmware_e2e.rs`.
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn grip_command(&mut self, cmd: GripCmd) -> Result<Done, Refusal> {
        let (open, close) = self.grip.ends();
        let target = match cmd {
            GripCmd::Open => open,
            GripCmd::Close => close,
            GripCmd::Centideg(c) => centideg_to_rad(c),
        };
        self.accept_grip(target, GripWho::Serial)?;
        Ok(Done::GripDue)
    }

    /// Checks state and limits and accepts a grip target (planned by
    /// [`App::finish_grip`]).
    fn accept_grip(&mut self, target: f32, who: GripWho) -> Result<(), Refusal> {
        let target = self.check_grip(target)?;
        self.grip_due(target, who);
        Ok(())
    }

    /// The grip target `target` would be, inside the limits, or why it is
    /// refused (nothing changes).
    pub(super) fn check_grip(&self, target: f32) -> Result<f32, Refusal> {
        if self.stopped {
            return Err(Refusal::Stopped);
        }
        if self.mode != Mode::Run {
            return Err(Refusal::Homing);
        }
        if self.grip.is_moving() || self.grip.due.is_some() {
            return Err(Refusal::GripBusy);
        }
        let (lo, hi) = self.grip.ends();
        if !super::machine::within_centi((lo, hi), target) {
            return Err(Refusal::GripLimit);
        }
        // max/min, not f32::clamp: its panic location would cost RAM.
        Ok(target.max(lo).min(hi))
    }

    /// A checked grip target, planned after this frame's pulses.
    fn grip_due(&mut self, target: f32, who: GripWho) {
        self.spend_heavy();
        let awaits_arm = matches!(who, GripWho::Pose(_));
        self.grip.due = Some(GripDue { target, who, awaits_arm });
    }

    /// A `pose go <n>`'s checked gripper target: planned once the arm's
    /// move is (`release_pose_grip`), dropped if it is refused.
    pub(super) fn pose_grip_due(&mut self, target: f32, n: u8) {
        self.grip_due(target, GripWho::Pose(n));
    }

    /// The arm's part of a `pose go` was planned (or its check passed): its
    /// gripper target is planned in the next frame that may plan.
    pub(super) fn release_pose_grip(&mut self) {
        if let Some(d) = self.grip.due.as_mut() {
            d.awaits_arm = false;
        }
    }

    /// The screen's Grip button: closes an open gripper and opens a closed
    /// one (the target of its last move decides: nearer the closed end is
    /// closed), by the same checks and planner as `grip open|close`.
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn screen_grip(&mut self) -> Result<(), Refusal> {
        let (open, close) = self.grip.ends();
        let target = if self.grip_closed() { open } else { close };
        self.accept_grip(target, GripWho::Screen)
    }

    /// The gripper is closed or closing: its last target is nearer the
    /// closed end of its window than the open one.
    pub(super) fn grip_closed(&self) -> bool {
        let (open, close) = self.grip.ends();
        let t = self.grip.target;
        let (to_open, to_close) = (t - open, close - t);
        to_close.abs() < to_open.abs()
    }

    /// Drops a gripper target that a `pose go` left for the next frame
    /// (its arm move was not planned).
    pub(super) fn drop_pose_grip(&mut self) {
        if self.grip.due.is_some_and(|d| matches!(d.who, GripWho::Pose(_))) {
            self.grip.due = None;
        }
    }

    /// The gripper's commanded angle, rad.
    pub(super) fn grip_angle(&self) -> f32 {
        self.grip.commanded
    }

    /// Plans this frame's grip target from the commanded angle at rest and
    /// answers it: `ok grip <cdeg> ts_ms <ms>` or `err <reason>` (a pose's:
    /// `warn pose <n> grip <reason>`). Waits while `wait` (the arm planned in
    /// this frame, or it is a catch-up frame, which plans nothing) and while
    /// a pose's gripper waits for the arm's verdict.
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn finish_grip<U: SerialPort>(&mut self, serial: &mut U, wait: bool) {
        if wait || self.grip.due.is_none_or(|d| d.awaits_arm) {
            return;
        }
        let Some(due) = self.grip.due.take() else { return };
        let map = self.grip.map;
        let start = self.grip.commanded;
        let pct = self.grip_percent();
        let r = self.plan_grip(start, due.target, &map, pct);
        if let Err(e) = r {
            self.last_refusal = Some(e);
        }
        self.report_grip(serial, &due, r);
    }

    /// The answer of a grip plan (not inlined: its line buffer is not on
    /// the stack while the grip is planned).
    #[inline(never)] // avr-trap: frame-size
    fn report_grip<U: SerialPort>(&mut self, serial: &mut U, due: &GripDue, r: Result<(), Refusal>) {
        let mut line = Line::new();
        match (r, due.who) {
            (Ok(()), GripWho::Serial) => {
                line.str(t!("ok grip")).num(crate::math::units::rad_to_centideg(due.target));
                line.word(t!("ts_ms")).num(super::text::milli(self.grip.ts));
                serial.write(line.finish());
            }
            (Err(e), GripWho::Serial) => {
                line.str(t!("err ")).str(e.reason());
                serial.write(line.finish());
            }
            (Ok(()), GripWho::Screen) => {
                line.str(t!("info screen grip")).num(crate::math::units::rad_to_centideg(due.target));
                line.word(t!("ts_ms")).num(super::text::milli(self.grip.ts));
                self.emit(serial, &mut line);
            }
            (Err(e), GripWho::Screen) => {
                line.str(t!("err screen grip")).word(e.reason());
                self.emit(serial, &mut line);
            }
            (Ok(()), GripWho::Pose(_)) => {}
            (Err(e), GripWho::Pose(n)) => {
                line.str(t!("warn pose")).num(i32::from(n)).word(t!("grip")).word(e.reason());
                self.emit(serial, &mut line);
            }
        }
    }

    /// The speed preset's share for a grip: the slow preset at most until a
    /// grip move has completed since power-up.
    fn grip_percent(&self) -> u8 {
        let pct = self.speed_now().percent();
        if self.grip.first {
            pct.min(SpeedPreset::Slow.percent())
        } else {
            pct
        }
    }

    /// A grip move from `start` at rest to `target` under `map`'s limits at
    /// `pct` % of its speed, by the arm's planner (the other two joints of
    /// the plan stand still); started from the next frame.
    #[inline(never)] // avr-trap: frame-size
    fn plan_grip(&mut self, start: f32, target: f32, map: &ServoMap, pct: u8) -> Result<(), Refusal> {
        let lim = self.plan_limits([map; JOINTS], pct);
        let req = MoveRequest { start: [start, 0.0, 0.0], target: [target, 0.0, 0.0], law: self.config.law };
        // By reference: a `?` would copy the law out of its Result.
        let chosen = choose_law(&req, &lim);
        match &chosen {
            Ok(law) => self.start_grip_plan(&req, &lim, law, target),
            Err(e) => Err(Refusal::from(*e)),
        }
    }

    /// [`Self::plan_grip`]'s plan by the law chosen, installed.
    // The plan (the move's largest value) lives here,
    // after the duration search has returned, not in plan_grip's frame.
    #[inline(never)] // avr-trap: frame-size
    fn start_grip_plan(
        &mut self,
        req: &MoveRequest<f32>,
        lim: &PlanLimits<f32>,
        chosen: &ChosenLaw<f32>,
        target: f32,
    ) -> Result<(), Refusal> {
        let planned = plan_chosen(req, lim, chosen)?;
        self.grip.ts = planned.ts;
        self.grip.plan = Some(planned.plan);
        self.grip.n = 0;
        self.grip.target = target;
        Ok(())
    }

    /// The gripper's angle of this frame: its plan at t = frames since the
    /// plan × 20 ms, exactly the target from the plan's end on.
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn step_grip(&mut self) {
        let Some(plan) = self.grip.plan.as_ref() else { return };
        let t = f32::from(self.grip.n) * FRAME_S;
        self.grip.commanded = plan.positions(t)[0];
        if plan.is_finished(t) {
            self.grip.plan = None;
            self.grip.first = false;
        } else {
            self.grip.n = self.grip.n.saturating_add(1);
        }
    }

    /// The gripper's pulse, through its map's clamping; a refused
    /// (non-finite) angle holds the previous pulse and latches STOP.
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn write_grip<S: ServoOutputs>(&mut self, servos: &mut S) {
        match self.grip.map.angle_to_pulse(self.grip.commanded) {
            Ok(p) => {
                servos.set_grip(p.ticks);
                self.grip.ticks = Some(p.ticks);
            }
            Err(_) => {
                self.latch_fault();
                if let Some(t) = self.grip.ticks {
                    self.grip.commanded = self.grip.map.pulse_to_angle(t);
                    servos.set_grip(t);
                }
            }
        }
    }

    /// STOP (or a fault): the gripper holds the angle of the previous frame.
    pub(super) fn halt_grip(&mut self) {
        self.grip.plan = None;
        self.grip.due = None;
    }

    /// `cal set grip <field> <value>`.
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn grip_cal_set(&mut self, field: JointField, value: i32) -> Result<Done, Refusal> {
        let mut next = *self.grip.map.cal();
        set_field(&mut next, field, value);
        if let Err(e) = next.validate() {
            return Ok(Done::CalInvalid(ConfigError::Grip(e)));
        }
        self.replace_grip(&next).map(Done::CalSet)
    }

    /// `cal reset grip`.
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn grip_reset(&mut self) -> Result<Done, Refusal> {
        self.replace_grip(&GRIP_DEFAULT).map(Done::CalReset)
    }

    /// Installs a valid gripper calibration the way `replace_config` does
    /// the joints': refused while the arm or the gripper moves, while homing, when the
    /// held angle or the present pulse lies outside the new limits, and
    /// under STOP when the pulse would move; a change that moves the pulse
    /// slews it (a slow-preset grip move from the present pulse, re-read as
    /// an angle of the new calibration, to the held angle). Returns the
    /// slew's duration.
    fn replace_grip(&mut self, cal: &JointCal) -> Result<Option<f32>, Refusal> {
        // A calibration change waits for the arm as well, as the joints'
        // (`cal set` and `cal reset grip` alike).
        if self.is_moving() {
            return Err(Refusal::Busy);
        }
        if self.grip.is_moving() || self.grip.due.is_some() {
            return Err(Refusal::GripBusy);
        }
        if self.mode != Mode::Run {
            return Err(Refusal::Homing);
        }
        let map = ServoMap::new(cal).map_err(|_| Refusal::Fault)?;
        let held = self.grip.commanded;
        let unclamped = |a: f32| matches!(map.angle_to_pulse(a), Ok(p) if p.clamped.is_none());
        // As a joint's held pose (`recalibrate.rs`): within the angle limits
        // to the hundredth, and no clamp moving its pulse.
        let held_ticks = match map.angle_to_pulse(held) {
            Ok(p) if p.clamped.is_none() && super::machine::within_centi(map.angle_limits(), held) => p.ticks,
            _ => return Err(Refusal::HeldPoseOutside),
        };
        let now = self.grip.ticks.unwrap_or(held_ticks);
        let start = map.pulse_to_angle(now);
        if !unclamped(start) {
            return Err(Refusal::HeldPoseOutside);
        }
        let slew = if now == held_ticks {
            None
        } else if self.stopped {
            return Err(Refusal::Stopped);
        } else {
            self.plan_grip(start, held, &map, SpeedPreset::Slow.percent())?;
            // The slew is planned under the new map; the pose it ends on is the held one.
            self.grip.commanded = start;
            Some(self.grip.ts)
        };
        self.grip.map = map;
        self.grip.dirty = true;
        Ok(slew)
    }

    /// Stores the gripper's calibration if it changed since it was loaded
    /// or stored (`cal save`); its sequence number, or `None` if unchanged.
    pub(super) fn save_grip<E: Storage>(&mut self, storage: &mut E) -> Result<Option<u16>, SaveError> {
        if !self.grip.dirty {
            return Ok(None);
        }
        let seq = record::save(storage, self.grip.map.cal())?;
        self.grip.dirty = false;
        Ok(Some(seq))
    }

    /// `cal grip offset … max_accel …`: the gripper's line of `cal show`.
    pub(super) fn grip_show_line(&self, line: &mut Line) {
        line.str(t!("cal grip"));
        for f in JointField::ALL {
            let v = field_value(self.grip.map.cal(), f);
            line.word(f.name()).bytes(b" ");
            if f.is_centi() {
                line.centi(v);
            } else {
                line.i32(v);
            }
        }
    }
}
