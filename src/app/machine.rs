//! The frame: boot, touch, motion and servo output (the order is in the
//! module doc of `app`).

use super::path_move::PathRun;
use super::refusal::Refusal;
use super::serial::Done;
use super::text::Line;
use super::{build_maps, Answer, App, HeavyTask, Io, Mode, MoveInfo, MoveKind, PlanDue, TouchTarget};
use crate::config::settings::{Config, NamedPose, SpeedPreset};
use crate::config::store::{self, Warning};
use crate::geometry::ik::IkError;
use crate::geometry::pose::{pose_for_point, PoseError};
use crate::math::units::centideg_to_rad;
use crate::motion::plan::JOINTS;
use crate::motion::planner::plan_move::{choose_law, plan_chosen, ChosenLaw};
use crate::motion::planner::request::{MoveRequest, PlanLimits};
use crate::seam::RawSample;
use crate::seam::{Clock, SerialPort, ServoOutputs, Storage, TouchPanel};
use crate::servo::map::{Joint, ServoMap};
use crate::servo::track::Replan;
use crate::touch::filter::{Read, TouchPoint, MAX_SAMPLES};

/// Half a hundredth of a degree, rad: the slack of an angle against a limit
/// (the unit `cal show` prints limits in and `goto` is typed in).
pub(super) const HALF_CENTIDEG: f32 = core::f32::consts::PI / 36_000.0;

/// Timer ticks (0.5 µs) a re-plan wants left in the PWM period to start in
/// this frame: its doublings, which it cannot cut short, at their measured
/// cost (BENCHMARKS.md, frame budget). With less it waits a frame
/// (`finish_plan`).
const REPLAN_ROOM_TICKS: u16 = 30_000;
/// Ticks a re-plan wants left for one more bisection of its duration
/// search: one check at its worst, then the law, the superposition, the
/// answer and the telemetry line (measured in simavr; BENCHMARKS.md).
const CHECK_ROOM_TICKS: u16 = 16_000;

/// `q` lies within `(lo, hi)` to the hundredth of a degree: how a typed
/// target (`goto`, `grip`) and a held pose under a new calibration (`cal
/// set`) are judged against angle limits, so the two agree.
pub(super) fn within_centi((lo, hi): (f32, f32), q: f32) -> bool {
    q >= lo - HALF_CENTIDEG && q <= hi + HALF_CENTIDEG
}

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
        // STOP from the port's one-byte `!` before anything else, catch-up
        // frames included: a latch is no heavy work (`serial.rs`).
        self.poll_stop_byte(io.serial);
        let now = io.clock.now_ms();
        self.carer_tick(now, io.serial);
        // A late frame starts busy: the catch-up (module doc of `app`, step 0).
        let catch_up = core::mem::take(&mut self.late);
        // A deferred re-plan is this frame's heavy thing (`finish_plan`).
        self.heavy = HeavyTask::new_frame(catch_up || self.plan_deferred);
        self.poll_serial(io, now);
        self.poll_touch(io.panel, now, io.storage, io.serial);
        self.poll_switch(now, io.storage, io.serial);
        self.step_motion();
        self.write_pulses(io.servos);
        // The gripper after the joints' pulses, so its step does not delay them.
        self.step_grip();
        self.write_grip(io.servos);
        // After the pulses: a plan may take most of the frame, and the next
        // period's pulses are already set if it takes a little longer. One
        // plan a frame: a grip waits for a frame without an arm plan.
        let arm_planned = self.plan_due.is_some();
        self.finish_plan(io.servos, io.serial, catch_up);
        self.finish_grip(io.serial, arm_planned || catch_up);
        // A path check takes what the period leaves (`path_move`).
        self.step_path_check(io.servos, io.serial, catch_up);
        self.send_telemetry(io.serial, now);
        self.hold_report(io.serial);
        self.flush_pending(io.serial);
        self.report_dropped(io.serial);
    }

    /// The frame that just ran ended after the next period had started, so
    /// the next one starts late: it only steps the motion and writes the
    /// pulses (the module doc of `app`, step 0). Called by the firmware's
    /// loop, which sees the period's timer.
    pub fn frame_was_late(&mut self) {
        self.late = true;
    }

    /// Loads the configuration and starts homing (no pulse in this frame).
    #[inline(never)] // avr-trap: frame-size
    fn boot<E: Storage, U: SerialPort>(&mut self, storage: &mut E, serial: &mut U) {
        let loaded = store::load(storage);
        self.poses = crate::config::poses::load(storage).poses;
        self.grip_boot(storage, serial);
        self.lcd = crate::config::lcd::load(storage).2;
        self.access_boot(storage);
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
        self.install_geometry();
        self.filter.reset();
        self.probe_wanted = self.config.wiring.is_none();
        self.commanded = self.clamp_to_limits(&self.config.arm.pose_rad(NamedPose::Home));
        self.last_move.target = self.commanded;
        self.mode = Mode::Homing { frames_left: self.params.home_settle_frames };
        let mut line = Line::new();
        line.str(t!("info boot config")).word(match self.source {
            store::Source::SlotA => t!("slotA"),
            store::Source::SlotB => t!("slotB"),
            store::Source::Defaults => t!("defaults"),
        });
        line.word(t!("seq")).num(i32::from(loaded.seq));
        self.emit(serial, &mut line);
        if let Some(w) = self.warning {
            line.clear().str(t!("warn ")).str(w.reason());
            self.emit(serial, &mut line);
        }
    }

    /// After a reset that kept RAM (`resume.rs`): hold `pose` (the resumed
    /// pulses' angles, inside the output windows) instead of homing, and
    /// take targets from the next frame; the first move stays slow.
    pub(super) fn hold_resumed(&mut self, pose: &[f32; JOINTS]) {
        // The track is idle (nothing has moved since `App::new`): the next
        // move starts from `commanded`.
        self.commanded = *pose;
        self.last_move.target = *pose;
        self.mode = Mode::Run;
    }

    /// `pose` with every angle pulled into its joint's output window (angle
    /// and pulse limits), so the pose describes the pulses the servos get.
    fn clamp_to_limits(&self, pose: &[f32; JOINTS]) -> [f32; JOINTS] {
        let mut out = *pose;
        for (o, m) in out.iter_mut().zip(self.maps.iter()) {
            *o = m.clamp_angle(*o);
        }
        out
    }

    /// One filtered panel read, fed to the contact (`press.rs`): STOP acts
    /// on contact, everything else on lift-off. A frame does one heavy thing
    /// (a plan can take most of it; a reply is formatted in it): after a
    /// serial line or a plan the panel is not read, a lift-off that would
    /// plan waits for the next frame, and that frame takes no serial line.
    // Not inlined (nor are `step_motion`, `finish_plan` and `plan_target`):
    // inlined into the firmware's frame they made it reserve 603 bytes of
    // stack, and LLVM then miscompiled the touch read's loop on the chip (the
    // frame never ended; the watchdog reset it). Out of line it is 168.
    #[inline(never)] // avr-trap: frame-size
    fn poll_touch<P: TouchPanel, E: Storage, U: SerialPort>(
        &mut self,
        panel: &mut P,
        now_ms: u32,
        storage: &mut E,
        serial: &mut U,
    ) {
        if let Some(p) = self.deferred_touch {
            if self.heavy.is_spent() {
                return;
            }
            self.deferred_touch = None;
            self.route_touch(&p, storage, serial);
        }
        // A busy frame has no time for a read (the filter takes the next
        // one; a touch would have to wait anyway).
        if self.heavy.is_spent() {
            return;
        }
        let mut buf = [RawSample { x: 0, y: 0, z: 0, z1: 0 }; MAX_SAMPLES];
        let n = usize::from(self.filter.config().samples);
        let Some(samples) = buf.get_mut(..n) else { return };
        // A failed read is a miss: the filter refuses an empty read.
        let read: &[RawSample] = if panel.read(samples).is_ok() { samples } else { &[] };
        let step = self.filter.update(read);
        // Anything but a clean "not touched" may be a finger joining the plates.
        self.contact = !matches!(step.read, Read::NotTouched(_));
        // The whole glass as the switch: a contact closes it, and no
        // contact acts on the screen (nor is left half judged for later).
        self.switch.glass = self.contact && self.glass_is_switch();
        if self.glass_is_switch() {
            self.press = super::press::Press::IDLE;
            return;
        }
        self.press_read(&step.read, now_ms, storage, serial);
    }

    #[cfg_attr(target_arch = "avr", optimize(size))] // reason: cold
    pub(super) fn route_touch<E: Storage, U: SerialPort>(&mut self, p: &TouchPoint, storage: &mut E, serial: &mut U) {
        if self.params.screen {
            self.screen_touch(p, storage, serial);
        } else {
            self.touch_target(p, serial);
        }
    }

    /// A confirmed touch: move there, or say why not.
    fn touch_target<U: SerialPort>(&mut self, p: &TouchPoint, serial: &mut U) {
        match self.move_to_raw(p) {
            // Answered once planned (`finish_plan`).
            Ok(()) => self.answer_due(Answer::Touch(*p)),
            Err(e) => self.report_touch(serial, p, Err(e)),
        }
    }

    /// Who hears how this frame's due plan goes.
    pub(super) fn answer_due(&mut self, answer: Answer) {
        if let Some(due) = self.plan_due.as_mut() {
            due.answer = answer;
        }
    }

    /// `info touch <x> <y> …` or `err touch <x> <y> <reason>` (its buffer is
    /// not on the stack while the touch is planned).
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn report_touch<U: SerialPort>(&mut self, serial: &mut U, p: &TouchPoint, r: Result<(), Refusal>) {
        let mut line = Line::new();
        match r {
            Ok(()) => {
                line.str(t!("info touch")).num(i32::from(p.x)).num(i32::from(p.y));
                self.describe_move(&mut line, true);
            }
            Err(e) => {
                line.str(t!("err touch")).num(i32::from(p.x)).num(i32::from(p.y)).word(e.reason());
            }
        }
        self.emit(serial, &mut line);
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

    /// Joint target in hundredths of a degree → move (the `goto` path). A
    /// target outside a joint's angle limits by a hundredth of a degree (the
    /// unit `cal show` prints them in) is refused: the limits get half a
    /// hundredth of slack for the float conversions, not the servo layer's
    /// 0.5 µs rounding allowance.
    pub(super) fn move_to_angles(&mut self, centideg: &[i32; JOINTS]) -> Result<(), Refusal> {
        let r = self.goto_angles(centideg).and_then(|target| self.start_move(&target, None));
        if let Err(e) = r {
            self.last_refusal = Some(e);
        }
        r
    }

    /// A `goto`'s angles (hundredths of a degree) in radians, if each is
    /// within its joint's angle limits to the hundredth; the first joint
    /// outside is the refusal. The pulse limits are judged with the move
    /// ([`App::check_limits`]).
    pub(super) fn goto_angles(&self, centideg: &[i32; JOINTS]) -> Result<[f32; JOINTS], Refusal> {
        let mut target = [0.0f32; JOINTS];
        for ((t, c), (m, j)) in target.iter_mut().zip(centideg.iter()).zip(self.maps.iter().zip(Joint::ALL.iter())) {
            *t = centideg_to_rad(*c);
            if !within_centi(m.angle_limits::<f32>(), *t) {
                return Err(Refusal::JointLimit(*j));
            }
        }
        Ok(target)
    }

    /// A joint target, reached as the `path` setting says.
    pub(super) fn start_move(&mut self, target: &[f32; JOINTS], touch: Option<&TouchTarget>) -> Result<(), Refusal> {
        self.accept(target, touch, self.target_kind())
    }

    /// Checks state and limits and accepts the target: it is planned (or a
    /// path's check is set up) after this frame's pulses (`finish_plan`). A
    /// path move starts from rest and nothing is superposed on one
    /// (`path_move`): a path while anything moves, and any target while a
    /// path move is checked or runs, is refused as busy.
    pub(super) fn accept(
        &mut self,
        target: &[f32; JOINTS],
        touch: Option<&TouchTarget>,
        kind: MoveKind,
    ) -> Result<(), Refusal> {
        if self.stopped {
            return Err(Refusal::Stopped);
        }
        match self.mode {
            Mode::Run => {}
            _ => return Err(Refusal::Homing),
        }
        self.hold_accept()?;
        if self.path_busy() || (kind != MoveKind::Joint && !self.track.is_done()) {
            return Err(Refusal::Busy);
        }
        self.check_limits(target)?;
        self.undo_note_target(kind);
        self.spend_heavy();
        self.plan_due = Some(PlanDue { target: *target, touch: touch.copied(), answer: Answer::Nobody, kind });
        Ok(())
    }

    /// Plans this frame's accepted target (the move starts in the next frame)
    /// and answers whoever asked: while moving, a correction superposed on
    /// the running move; at rest, a move from the pose just commanded.
    ///
    /// A re-plan's duration search takes up to about a whole PWM period on
    /// the chip (BENCHMARKS.md, frame budget): when this frame has less than
    /// [`REPLAN_ROOM_TICKS`] left it waits for the next, which starts it
    /// right after the pulses and takes nothing else heavy (a catch-up frame
    /// passes it on again). Its bisections stop where the period's time
    /// does (`correction_duration_within`), so it ends inside the period.
    #[inline(never)] // avr-trap: frame-size
    fn finish_plan<S: ServoOutputs, U: SerialPort>(&mut self, servos: &S, serial: &mut U, catch_up: bool) {
        let Some(due) = self.plan_due.take() else { return };
        let replan = due.kind == MoveKind::Joint && !self.track.is_done();
        let short = |need: u16| servos.period_ticks_left().is_some_and(|left| left < need);
        if catch_up || (replan && !self.plan_deferred && short(REPLAN_ROOM_TICKS)) {
            self.plan_due = Some(due);
            self.plan_deferred = true;
            return;
        }
        self.plan_deferred = false;
        let r = if self.stopped {
            // Latched (the `!` byte) while the plan waited.
            Err(Refusal::Stopped)
        } else if due.kind == MoveKind::Joint {
            let mut room = || !short(CHECK_ROOM_TICKS);
            self.plan_target(&due.target, due.touch.as_ref(), &mut room)
        } else {
            match self.begin_path_check(&due) {
                // Answered when the check decides (`step_path_check`).
                Ok(()) => return,
                Err(e) => Err(e),
            }
        };
        if let Err(e) = r {
            self.last_refusal = Some(e);
        }
        self.answer_plan(serial, &due.answer, r);
    }

    /// Tells whoever asked for a move how its plan (or its path check) went.
    pub(super) fn answer_plan<U: SerialPort>(&mut self, serial: &mut U, answer: &Answer, r: Result<(), Refusal>) {
        self.undo_verdict(r.is_ok());
        // A pose's gripper target waits for this verdict (`grip.rs`): a pose
        // whose arm move cannot be planned moves nothing.
        if r.is_ok() {
            self.release_pose_grip();
        } else {
            self.drop_pose_grip();
        }
        match *answer {
            Answer::Nobody => {}
            Answer::Serial(done) => self.send_reply(serial, &r.map_or_else(Done::Refused, |()| done)),
            Answer::Touch(p) => self.report_touch(serial, &p, r),
            Answer::Screen(p, x_p, y_p) => {
                self.screen.refusal = r.err().map(|e| self.ui_refusal(e, x_p, y_p));
                self.report_touch(serial, &p, r);
            }
            Answer::ScreenPose(n) => {
                self.screen.refusal = r.err().map(|e| self.ui_refusal(e, 0.0, 0.0));
                self.report_screen_pose(serial, n, r);
            }
            Answer::ScreenUndo => {
                self.screen.refusal = r.err().map(|e| self.ui_refusal(e, 0.0, 0.0));
                self.report_screen_undo(serial, r);
            }
        }
    }

    /// The plan of an accepted target under this move's limits.
    #[inline(never)] // avr-trap: frame-size
    fn plan_target<F: FnMut() -> bool>(
        &mut self,
        target: &[f32; JOINTS],
        touch: Option<&TouchTarget>,
        room: &mut F,
    ) -> Result<(), Refusal> {
        let lim = self.plan_limits(self.maps.each_ref(), self.move_percent());
        // A new target while moving: a correction superposed on the move.
        if !self.track.is_done() {
            let slack = 1.0 / (1.0 - self.params.speed_margin);
            let r = Replan { target, law: self.config.law, lim: &lim, slack };
            if let Some((ts, wait)) = self.track.replan(&r, &self.maps, room)? {
                let end_velocity = [0.0; JOINTS];
                let replan = Some(wait);
                let touch = touch.copied();
                let kind = MoveKind::Joint;
                self.last_move = MoveInfo { target: *target, ts, replan, a: None, end_velocity, touch, kind };
                return Ok(());
            }
        }
        let start = self.commanded;
        let info = self.start_fresh(&start, target, None, &lim)?;
        self.last_move = MoveInfo { touch: touch.copied(), ..info };
        Ok(())
    }

    /// Plans a synchronized move from `start` to `target` under `new_maps`
    /// (the running calibration's if `None`) at `pct` % of every joint's max
    /// speed and within its max acceleration, less the safety margin, and
    /// starts it from rest (a calibration slew). Returns what to report.
    pub(super) fn plan_motion(
        &mut self,
        start: &[f32; JOINTS],
        target: &[f32; JOINTS],
        new_maps: Option<&[ServoMap; JOINTS]>,
        pct: u8,
    ) -> Result<MoveInfo, Refusal> {
        let lim = self.plan_limits(new_maps.unwrap_or(&self.maps).each_ref(), pct);
        self.start_fresh(start, target, new_maps, &lim)
    }

    /// A move from `start` at rest (not inlined: its plan and track would
    /// otherwise share the caller's stack frame with the re-plan's).
    // Only the request and the chosen law are in this
    // frame during the duration search; the plan is built in `start_chosen`.
    #[inline(never)] // avr-trap: frame-size
    fn start_fresh(
        &mut self,
        start: &[f32; JOINTS],
        target: &[f32; JOINTS],
        new_maps: Option<&[ServoMap; JOINTS]>,
        lim: &PlanLimits<f32>,
    ) -> Result<MoveInfo, Refusal> {
        self.spend_heavy();
        let req = MoveRequest { start: *start, target: *target, law: self.config.law };
        // By reference: a `?` would copy the law out of its Result.
        let chosen = choose_law(&req, lim);
        match &chosen {
            Ok(law) => self.start_chosen(&req, law, new_maps, lim),
            Err(e) => Err(Refusal::from(*e)),
        }
    }

    /// [`Self::start_fresh`]'s plan by the law chosen, started on the track.
    // The plan (the move's largest value) lives here,
    // after the duration search has returned, not in start_fresh's frame.
    #[inline(never)] // avr-trap: frame-size
    fn start_chosen(
        &mut self,
        req: &MoveRequest<f32>,
        chosen: &ChosenLaw<f32>,
        new_maps: Option<&[ServoMap; JOINTS]>,
        lim: &PlanLimits<f32>,
    ) -> Result<MoveInfo, Refusal> {
        let planned = plan_chosen(req, lim, chosen)?;
        let maps = new_maps.unwrap_or(&self.maps);
        self.track.start(&planned.plan, maps).map_err(|_| Refusal::Trajectory)?;
        Ok(MoveInfo {
            target: req.target,
            ts: planned.ts,
            replan: None,
            a: planned.a,
            end_velocity: planned.end_velocity,
            touch: None,
            kind: MoveKind::Joint,
        })
    }

    /// The speed preset's percentage for the next move: the slow preset at
    /// most before the first move has completed.
    pub(super) fn move_percent(&self) -> u8 {
        let pct = self.speed_now().percent();
        if self.first_move {
            pct.min(SpeedPreset::Slow.percent())
        } else {
            pct
        }
    }

    /// The pose's angles pass [`Self::check_limits`] (the screen's preview).
    pub(super) fn within_limits(&self, target: &[f32; JOINTS]) -> bool {
        self.check_limits(target).is_ok()
    }

    /// A target angle the servo layer would have to clamp (angle or pulse
    /// limit, beyond its 0.5 µs rounding allowance) is refused.
    pub(super) fn check_limits(&self, target: &[f32; JOINTS]) -> Result<(), Refusal> {
        for ((q, m), j) in target.iter().zip(self.maps.iter()).zip(crate::servo::map::Joint::ALL.iter()) {
            match m.angle_to_pulse(*q) {
                Ok(p) if p.clamped.is_none() => {}
                Ok(_) => return Err(Refusal::JointLimit(*j)),
                Err(_) => return Err(Refusal::NotFinite),
            }
        }
        Ok(())
    }

    /// Limits for a move under `maps`: `pct` % of every joint's max speed
    /// and its max acceleration, both less the safety margin.
    pub(super) fn plan_limits(&self, maps: [&ServoMap; JOINTS], pct: u8) -> PlanLimits<f32> {
        let keep = 1.0 - self.params.speed_margin;
        let share = f32::from(pct) * 0.01 * keep;
        let mut speed = [0.0f32; JOINTS];
        let mut accel = [0.0f32; JOINTS];
        for ((s, a), m) in speed.iter_mut().zip(accel.iter_mut()).zip(maps.iter()) {
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

    #[inline(never)] // avr-trap: frame-size
    fn step_motion(&mut self) {
        if let Mode::Homing { frames_left } = self.mode {
            self.mode = match frames_left {
                0 | 1 => Mode::Run,
                n => Mode::Homing { frames_left: n - 1 },
            };
        }
        self.frame_pulses = None;
        if self.step_hold() || self.step_path() {
            return;
        }
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

    pub(super) fn latch_fault(&mut self) {
        self.stopped = true;
        self.track.halt();
        self.hold_drop();
        self.halt_grip();
        self.last_refusal = Some(Refusal::Fault);
    }

    /// STOP: hold the pose commanded in the previous frame.
    pub(super) fn stop(&mut self) {
        self.stopped = true;
        self.track.halt();
        self.hold_drop();
        self.halt_grip();
        // A running path move freezes on the previous frame's pose; a
        // pending check is cancelled and answered after the pulses.
        if matches!(self.path, PathRun::Running { .. }) {
            self.path = PathRun::Idle;
        }
    }

    pub(super) fn resume(&mut self) {
        self.stopped = false;
    }

    pub(super) fn is_moving(&self) -> bool {
        !self.track.is_done() || self.path_busy()
    }
}
