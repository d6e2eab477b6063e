//! Hold to run (issue #20 §5, `mode hold`): a map touch moves the arm only
//! while it stays on the glass (or the switch is held), and a lift brings
//! the arm to rest along its planned path ([`crate::motion::stop`]).
//!
//! - **Commit**: in hold mode a contact on the map (without a screen: on the
//!   panel) commits its robust centre as soon as it has rested `hold`, on
//!   contact rather than on lift-off (`press.rs`); the move is planned as
//!   in tap mode and runs while that contact stays down.
//! - **Release**: when the contact lifts (and the switch is not held) the
//!   running move's clock is slowed to rest: `info hold released <ms>` (the
//!   planned stop time), then, at rest, `info hold rest <b> <s> <e>` (the
//!   pose it rests on, hundredths of a degree: a pose of the planned path,
//!   short of the target). The arm shows `holding`.
//! - **Resume**: a new contact that rests `hold` anywhere on the map (or the
//!   switch) continues the same move toward the same target, its clock
//!   brought back to speed the same way (`info hold resumed`); where it
//!   lands does not matter, so a shaky second touch does not retarget the
//!   arm. A new target is picked once the arm has arrived.
//! - Serial moves, `goto`, poses and the screen's buttons run as in tap
//!   mode (no finger is involved); one that comes while the arm rests on a
//!   released move drops that move and starts from rest; one while the clock
//!   is being slowed or sped up is refused as busy. A serial target while
//!   a held move runs is superposed on it and stays held.
//! - STOP latches at once in every mode and forgets the held move.
//!
//! Like `path_move.rs`, this file commands the pose frame by frame while
//! it warps a move: every pose is the running move's own (within its limits)
//! and each frame's change is checked against the acceleration limits
//! ([`Warp`]).

use super::path_move::PathRun;
use super::refusal::Refusal;
use super::text::Line;
use super::{App, FRAME_S};
use crate::math::units::rad_to_centideg;
use crate::motion::plan::JOINTS;
use crate::motion::stop::{Timeline, Warp};
use crate::seam::SerialPort;
use crate::servo::track::ServoTrack;

/// A line `hold.rs` owes. Fieldless, `Nothing` first, so that
/// [`HoldRun::IDLE`] is all zero bytes (initializing `App` copies no
/// constant from RAM).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
enum Said {
    Nothing = 0,
    /// `info hold released <ms>`, [`HoldRun::stop_frames`] long.
    Released,
    Rest,
    Resumed,
}

/// Hold to run's state (one field of `App`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct HoldRun {
    /// The running move came from a held commit: it runs only while held.
    armed: bool,
    /// A committed contact is on the glass.
    touch: bool,
    /// The switch is held (the switch feature's hook).
    switch: bool,
    /// The held move has been released: its clock is `warp`'s from then
    /// until the move ends.
    released: bool,
    warp: Warp,
    /// The rest line has been sent for this rest.
    rested: bool,
    said: Said,
    /// The planned stop's frames, for the released line.
    stop_frames: u16,
}

impl HoldRun {
    pub(super) const IDLE: HoldRun = HoldRun {
        armed: false,
        touch: false,
        switch: false,
        released: false,
        warp: Warp::NONE,
        rested: false,
        said: Said::Nothing,
        stop_frames: 0,
    };
}

/// The running move as the stop sees it: the servo track's motion or a
/// path move's plan.
struct Running<'a> {
    track: &'a ServoTrack,
    path: &'a PathRun,
}

impl Timeline for Running<'_> {
    fn pose(&self, tau: f32) -> Option<[f32; JOINTS]> {
        match self.path {
            // Not `clamp`: its panic path would cost flash and RAM.
            PathRun::Running { run, .. } => run.angles(tau.max(0.0).min(run.ts())),
            _ => Some(self.track.positions(&self.track.frame(tau))),
        }
    }
}

impl App {
    /// A released held move at rest on its path ([`super::State::Paused`]).
    pub(super) fn hold_paused(&self) -> bool {
        self.hold.released && self.hold.warp.at_rest()
    }

    /// `mode hold|tap`; refused while the arm moves or rests on a released
    /// move (its clock belongs to the mode it started in).
    pub(super) fn set_hold_mode(&mut self, hold: bool) -> Result<(), Refusal> {
        if self.is_moving() {
            return Err(Refusal::Busy);
        }
        self.config.hold_to_run = hold;
        Ok(())
    }

    /// The hold-to-run input: a committed contact on the glass or the
    /// switch held. The one place "held" is decided.
    pub fn hold_input(&self) -> bool {
        self.hold.touch || self.hold.switch
    }

    /// The assistive switch's hook (issue #20 §4): held or let go. A held
    /// move runs while [`App::hold_input`] is true: a committed contact on
    /// the glass or the switch held.
    pub fn hold_switch(&mut self, down: bool) {
        self.hold.switch = down;
    }

    /// A held move runs or rests on its path: the switch holds it rather
    /// than stopping it (`switch.rs`).
    pub(super) fn hold_armed(&self) -> bool {
        self.hold.armed
    }

    /// The switch's Go in hold mode: the move it plans runs while the
    /// switch stays down, as a held finger's does.
    pub(super) fn hold_arm(&mut self) {
        if self.config.hold_to_run {
            self.hold.armed = true;
        }
    }

    /// A contact in hold mode rested `hold` at `p`: resumes a released move,
    /// else commits `p` as a new held move.
    pub(super) fn hold_commit<E: crate::seam::Storage, U: SerialPort>(
        &mut self,
        p: &crate::touch::filter::TouchPoint,
        storage: &mut E,
        serial: &mut U,
    ) {
        self.hold.touch = true;
        if self.hold.released {
            return;
        }
        self.hold.armed = true;
        if self.heavy.is_spent() {
            self.deferred_touch = Some(*p);
        } else {
            self.route_touch(p, storage, serial);
        }
    }

    /// The committed contact lifted.
    pub(super) fn hold_lifted(&mut self) {
        self.hold.touch = false;
    }

    /// A target accepted outside a held commit (serial, buttons) while a
    /// held move was released: at rest the released move is dropped (the
    /// target starts from rest); while its clock changes, busy.
    pub(super) fn hold_accept(&mut self) -> Result<(), Refusal> {
        if !self.hold.released {
            return Ok(());
        }
        if !self.hold.warp.at_rest() {
            return Err(Refusal::Busy);
        }
        self.hold_drop();
        self.track.halt();
        self.path = PathRun::Idle;
        Ok(())
    }

    /// STOP, a fault, or the end of the move: nothing is held any more.
    pub(super) fn hold_drop(&mut self) {
        // Field by field: a struct update from `IDLE` made the compiler
        // keep a copy of it in RAM. The warp is unused while not released.
        let h = &mut self.hold;
        h.armed = false;
        h.released = false;
        h.rested = false;
        h.said = Said::Nothing;
    }

    /// Steps a held move (module doc): `false` when the frame steps the
    /// motion as usual (no held move, or held and never released).
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn step_hold(&mut self) -> bool {
        if !self.hold.armed {
            return false;
        }
        let running = !self.track.is_done() || matches!(self.path, PathRun::Running { .. });
        if !running {
            // Refused, or still being planned or checked.
            if !self.path_busy() && self.plan_due.is_none() && self.deferred_touch.is_none() {
                self.hold_drop();
            }
            return false;
        }
        let held = self.hold_input();
        let accel = self.stop_accel();
        let end = match &self.path {
            PathRun::Running { run, .. } => run.ts(),
            _ => self.track.end_s(),
        };
        let mut w = match self.hold.released {
            true => self.hold.warp,
            false if held => return false,
            false => {
                // The last frame ran at the clock's previous count.
                let frames = match &self.path {
                    PathRun::Running { frame, .. } => *frame,
                    _ => self.track.frames(),
                };
                let tau = (f32::from(frames) - 1.0) * FRAME_S;
                let begun = Warp::begin(&Running { track: &self.track, path: &self.path }, tau, FRAME_S, &accel);
                let Some(w) = begun else { return self.hold_fault() };
                w
            }
        };
        if held && w.at_rest() {
            self.hold.said = Said::Resumed;
            self.hold.rested = false;
        } else if !held && (!self.hold.released || w.rising()) {
            self.hold.said = Said::Released;
            self.hold.stop_frames = w.frames_to_rest();
        }
        w.set_up(held);
        let q = w.next(&Running { track: &self.track, path: &self.path }, &accel);
        let Some(q) = q else { return self.hold_fault() };
        self.commanded = q;
        if w.tau() >= end {
            // The move's own end: on its target, at rest.
            self.hold_drop();
            self.track.halt();
            self.path = PathRun::Idle;
            self.first_move = false;
            return true;
        }
        if w.at_rest() && !self.hold.rested {
            self.hold.rested = true;
            self.hold.said = Said::Rest;
        }
        self.hold.warp = w;
        self.hold.released = true;
        true
    }

    fn hold_fault(&mut self) -> bool {
        self.latch_fault();
        true
    }

    /// Each joint's acceleration limit, rad/s² (the plans keep a margin
    /// below it).
    fn stop_accel(&self) -> [f32; JOINTS] {
        let mut a = [0.0f32; JOINTS];
        for (a, m) in a.iter_mut().zip(self.maps.iter()) {
            *a = m.max_accel::<f32>();
        }
        a
    }

    /// `info hold released <ms>` / `info hold rest <b> <s> <e>` / `info
    /// hold resumed`, after the frame's pulses.
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn hold_report<U: SerialPort>(&mut self, serial: &mut U) {
        let said = core::mem::replace(&mut self.hold.said, Said::Nothing);
        let mut line = Line::new();
        line.str(t!("info hold"));
        match said {
            Said::Nothing => return,
            Said::Released => {
                line.word(t!("released")).num(i32::from(self.hold.stop_frames) * super::FRAME_MS as i32);
            }
            Said::Rest => {
                // As `status` prints `q`.
                line.word(t!("rest"));
                for q in self.commanded {
                    line.num(rad_to_centideg(q));
                }
            }
            Said::Resumed => {
                line.word(t!("resumed"));
            }
        }
        self.emit(serial, &mut line);
    }
}
