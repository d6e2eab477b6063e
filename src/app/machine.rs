//! The frame: boot, touch, motion and servo output (the order is in the
//! module doc of `app`).

use super::refusal::Refusal;
use super::text::Line;
use super::{build_maps, App, Io, Mode, MoveInfo, TouchTarget};
use crate::config::settings::{Config, SpeedPreset};
use crate::config::store::{self, Warning};
use crate::geometry::ik::IkError;
use crate::geometry::pose::{pose_for_point, PoseError};
use crate::motion::plan::JOINTS;
use crate::motion::planner::plan_move::plan_move;
use crate::motion::planner::request::{MoveRequest, PlanLimits};
use crate::seam::RawSample;
use crate::seam::{Clock, SerialPort, ServoOutputs, Storage, TouchPanel};
use crate::servo::track::Replan;
use crate::touch::filter::{TouchEvent, TouchPoint, MAX_SAMPLES};

impl App {
    /// One 20 ms frame. Call once per servo PWM period.
    pub fn frame<P, S, C, E, U>(&mut self, io: &mut Io<'_, P, S, C, E, U>)
    where
        P: TouchPanel,
        S: ServoOutputs,
        C: Clock,
        E: Storage,
        U: SerialPort,
    {
        if self.mode == Mode::Boot {
            self.boot(io.storage, io.serial);
            io.servos.disable();
            return;
        }
        let now = io.clock.now_ms();
        self.poll_serial(io, now);
        self.poll_touch(io.panel, io.storage, io.serial);
        self.step_motion();
        self.write_pulses(io.servos);
        if self.log {
            self.send_telemetry(io.serial, now);
        }
        self.flush_pending(io.serial);
    }

    /// Loads the configuration and starts homing (no pulse in this frame).
    fn boot<E: Storage, U: SerialPort>(&mut self, storage: &mut E, serial: &mut U) {
        let loaded = store::load(storage);
        self.source = loaded.source;
        self.warning = loaded.warning;
        match build_maps(&loaded.config) {
            Some(maps) => {
                self.config = loaded.config;
                self.maps = maps;
            }
            None => {
                // `load` validates, so this is a build inconsistency: stay on
                // the defaults App::new checked.
                self.config = Config::DEFAULT;
                self.warning = Some(Warning::Corrupt);
            }
        }
        self.filter.reset();
        self.commanded = self.clamp_to_limits(&self.params.home);
        self.last_move.target = self.commanded;
        self.mode = Mode::Homing { frames_left: self.params.home_settle_frames };
        let mut line = Line::new();
        line.str(t!("info boot config")).word(match self.source {
            store::Source::SlotA => t!("slotA"),
            store::Source::SlotB => t!("slotB"),
            store::Source::Defaults => t!("defaults"),
        });
        line.word(t!("seq")).num(i32::from(loaded.seq));
        serial.write(line.finish());
        if let Some(w) = self.warning {
            serial.write(line.clear().str(t!("warn ")).str(w.reason()).finish());
        }
    }

    /// `pose` with every angle pulled into its joint's limits.
    fn clamp_to_limits(&self, pose: &[f32; JOINTS]) -> [f32; JOINTS] {
        let mut out = *pose;
        for (o, m) in out.iter_mut().zip(self.maps.iter()) {
            let (lo, hi) = m.angle_limits::<f32>();
            *o = o.clamp(lo, hi);
        }
        out
    }

    fn poll_touch<P: TouchPanel, E: Storage, U: SerialPort>(&mut self, panel: &mut P, storage: &mut E, serial: &mut U) {
        let mut buf = [RawSample { x: 0, y: 0, z: 0 }; MAX_SAMPLES];
        let n = usize::from(self.filter.config().samples);
        let Some(samples) = buf.get_mut(..n) else { return };
        let got = panel.read(samples).min(n);
        let step = self.filter.update(samples.get(..got).unwrap_or(&[]));
        match step.event {
            // On a screen a press is a button or a map point; a drag (Moved)
            // must not turn into a second button press.
            Some(TouchEvent::Pressed(p)) if self.params.screen => self.screen_touch(&p, storage, serial),
            Some(TouchEvent::Moved(_)) if self.params.screen => {}
            Some(TouchEvent::Pressed(p)) | Some(TouchEvent::Moved(p)) => self.touch_target(&p, serial),
            Some(TouchEvent::Released) | None => {}
        }
    }

    /// A confirmed touch: move there, or say why not.
    fn touch_target<U: SerialPort>(&mut self, p: &TouchPoint, serial: &mut U) {
        let mut line = Line::new();
        match self.move_to_raw(p) {
            Ok(()) => {
                line.str(t!("info touch")).num(i32::from(p.x)).num(i32::from(p.y));
                self.describe_move(&mut line, true);
            }
            Err(r) => {
                line.str(t!("err touch")).num(i32::from(p.x)).num(i32::from(p.y)).word(r.reason());
            }
        }
        serial.write(line.finish());
    }

    /// Raw panel point → calibration → pose → move.
    pub(super) fn move_to_raw(&mut self, p: &TouchPoint) -> Result<(), Refusal> {
        // A match, not a closure over the (angles, target) tuple: that would
        // be a 32-byte by-value argument if it were not inlined.
        let r = match self.raw_to_target(p) {
            Ok((angles, tt)) => self.start_move(&angles, Some(&tt)),
            Err(e) => Err(e),
        };
        if let Err(e) = r {
            self.last_refusal = Some(e);
        }
        r
    }

    fn raw_to_target(&self, p: &TouchPoint) -> Result<([f32; JOINTS], TouchTarget), Refusal> {
        let (x_p, y_p) = self.raw_to_panel(p)?;
        self.point_to_target(p, x_p, y_p)
    }

    /// Raw reading → normalized panel point through the calibration; a
    /// reading outside the calibrated span is refused, never clamped.
    pub(super) fn raw_to_panel(&self, p: &TouchPoint) -> Result<(f32, f32), Refusal> {
        let m = self.config.touch.map::<f32>(p.x, p.y).map_err(|_| Refusal::OutsideCalibration)?;
        if m.clamped {
            return Err(Refusal::OutsideCalibration);
        }
        Ok((m.x_p, m.y_p))
    }

    /// Workspace point → pose (the paper's chain), remembering the raw
    /// reading it came from.
    pub(super) fn point_to_target(
        &self,
        p: &TouchPoint,
        x_p: f32,
        y_p: f32,
    ) -> Result<([f32; JOINTS], TouchTarget), Refusal> {
        let pose = pose_for_point(&self.geo, x_p, y_p).map_err(|e| match e {
            PoseError::Workspace(_) => Refusal::OutsideWorkspace,
            PoseError::Ik(IkError::Unreachable { .. }) => Refusal::Unreachable,
            PoseError::Ik(IkError::Singular) => Refusal::Singular,
            PoseError::Ik(IkError::NotFinite) => Refusal::NotFinite,
        })?;
        let tt = TouchTarget { raw_x: p.x, raw_y: p.y, x_p, y_p, condition: pose.condition, alpha: pose.alpha };
        Ok(([pose.alpha, pose.q2, pose.q3], tt))
    }

    /// A workspace point picked on the screen's map → move.
    pub(super) fn move_to_point(&mut self, p: &TouchPoint, x_p: f32, y_p: f32) -> Result<(), Refusal> {
        let r = match self.point_to_target(p, x_p, y_p) {
            Ok((angles, tt)) => self.start_move(&angles, Some(&tt)),
            Err(e) => Err(e),
        };
        if let Err(e) = r {
            self.last_refusal = Some(e);
        }
        r
    }

    /// Joint target → move (the `goto` path).
    pub(super) fn move_to_angles(&mut self, target: &[f32; JOINTS]) -> Result<(), Refusal> {
        let r = self.start_move(target, None);
        if let Err(e) = r {
            self.last_refusal = Some(e);
        }
        r
    }

    /// Checks state and limits, plans from the pose commanded last frame and
    /// starts the move.
    fn start_move(&mut self, target: &[f32; JOINTS], touch: Option<&TouchTarget>) -> Result<(), Refusal> {
        if self.stopped {
            return Err(Refusal::Stopped);
        }
        match self.mode {
            Mode::Run => {}
            _ => return Err(Refusal::Homing),
        }
        self.check_limits(target)?;
        let lim = self.plan_limits();
        // A new target while moving: a correction superposed on the move.
        if !self.track.is_done() {
            let slack = 1.0 / (1.0 - self.params.speed_margin);
            let r = Replan { target, law: self.config.law, lim: &lim, slack };
            if let Some((ts, wait)) = self.track.replan(&r, &self.maps)? {
                let end_velocity = [0.0; JOINTS];
                let replan = Some(wait);
                self.last_move = MoveInfo { target: *target, ts, replan, a: None, end_velocity, touch: touch.copied() };
                return Ok(());
            }
        }
        self.start_fresh(target, touch, &lim)
    }

    /// A move from the pose commanded last frame, at rest (not inlined: its
    /// plan and track would otherwise share the caller's stack frame with
    /// the re-plan's).
    #[inline(never)]
    fn start_fresh(
        &mut self,
        target: &[f32; JOINTS],
        touch: Option<&TouchTarget>,
        lim: &PlanLimits<f32>,
    ) -> Result<(), Refusal> {
        let req = MoveRequest { start: self.commanded, target: *target, law: self.config.law };
        let planned = plan_move(&req, lim)?;
        self.track.start(&planned.plan, &self.maps).map_err(|_| Refusal::Trajectory)?;
        self.last_move = MoveInfo {
            target: *target,
            ts: planned.ts,
            replan: None,
            a: planned.a,
            end_velocity: planned.end_velocity,
            touch: touch.copied(),
        };
        Ok(())
    }

    /// A target angle the servo layer would have to clamp (angle or pulse
    /// limit, beyond its 0.5 µs rounding allowance) is refused.
    fn check_limits(&self, target: &[f32; JOINTS]) -> Result<(), Refusal> {
        for ((q, m), j) in target.iter().zip(self.maps.iter()).zip(crate::servo::map::Joint::ALL.iter()) {
            match m.angle_to_pulse(*q) {
                Ok(p) if p.clamped.is_none() => {}
                Ok(_) => return Err(Refusal::JointLimit(*j)),
                Err(_) => return Err(Refusal::NotFinite),
            }
        }
        Ok(())
    }

    /// Limits for the next move: the preset's share of every joint's max
    /// speed (the slow preset at most before the first move has completed)
    /// and its max acceleration, both less the safety margin.
    fn plan_limits(&self) -> PlanLimits<f32> {
        let mut pct = self.config.speed.percent();
        if self.first_move {
            pct = pct.min(SpeedPreset::Slow.percent());
        }
        let keep = 1.0 - self.params.speed_margin;
        let share = f32::from(pct) * 0.01 * keep;
        let mut speed = [0.0f32; JOINTS];
        let mut accel = [0.0f32; JOINTS];
        for ((s, a), m) in speed.iter_mut().zip(accel.iter_mut()).zip(self.maps.iter()) {
            *s = m.max_speed::<f32>() * share;
            *a = m.max_accel::<f32>() * keep;
        }
        PlanLimits {
            speed,
            accel,
            ts_min: self.params.ts_min,
            zat_ts_min: self.params.zat_ts_min,
            ts_max: self.params.ts_max,
            n: self.params.n,
        }
    }

    fn step_motion(&mut self) {
        if let Mode::Homing { frames_left } = self.mode {
            self.mode = match frames_left {
                0 | 1 => Mode::Run,
                n => Mode::Homing { frames_left: n - 1 },
            };
        }
        self.frame_pulses = None;
        if !self.track.is_done() {
            let f = self.track.frame_now();
            self.commanded = self.track.positions(&f);
            self.frame_pulses = Some(f.pulses);
            self.track.advance();
            if self.track.is_done() {
                self.first_move = false;
            }
        }
    }

    /// Every setpoint through the servo layer's clamping; a refused
    /// (non-finite) setpoint holds the previous pulse and latches STOP.
    fn write_pulses<S: ServoOutputs>(&mut self, servos: &mut S) {
        // While moving, the track already mapped this frame's pose through
        // the calibration, inside the same angle and pulse windows.
        if let Some(out) = self.frame_pulses {
            servos.set_pulses(&out);
            self.pulses = Some(out);
            return;
        }
        let mut out = [0u16; JOINTS];
        let mut fault = false;
        let prev = self.pulses;
        for (j, ((o, m), q)) in out.iter_mut().zip(self.maps.iter()).zip(self.commanded.iter()).enumerate() {
            match m.angle_to_pulse(*q) {
                Ok(p) => *o = p.ticks,
                Err(_) => {
                    fault = true;
                    match prev.as_ref().and_then(|p| p.get(j)) {
                        Some(us) => *o = *us,
                        None => {
                            servos.disable();
                            self.latch_fault();
                            return;
                        }
                    }
                }
            }
        }
        if fault {
            self.latch_fault();
            // The pose that the held pulses stand for.
            for (q, (m, us)) in self.commanded.iter_mut().zip(self.maps.iter().zip(out.iter())) {
                *q = m.pulse_to_angle(*us);
            }
        }
        servos.set_pulses(&out);
        self.pulses = Some(out);
    }

    fn latch_fault(&mut self) {
        self.stopped = true;
        self.track.halt();
        self.last_refusal = Some(Refusal::Fault);
    }

    /// STOP: hold the pose commanded in the previous frame.
    pub(super) fn stop(&mut self) {
        self.stopped = true;
        self.track.halt();
    }

    pub(super) fn resume(&mut self) {
        self.stopped = false;
    }

    pub(super) fn is_moving(&self) -> bool {
        !self.track.is_done()
    }
}
