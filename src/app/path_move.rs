//! Path moves on the chip (issue #13): with `path line` a target is reached
//! by the effector along the straight segment from where it is; `circle <r>`
//! makes one turn in the arm's vertical plane. Both are paced by the selected
//! law and start and end at rest; every frame solves the IK of the path's
//! point (the path frame, BENCHMARKS.md `path_frame`).
//!
//! # The check, spread over frames
//! A path's plan-time check ([`PathCheck`]: every point reachable, inside the
//! angle limits, on one IK branch, no joint over its speed or acceleration
//! limit; slowed down to the shortest admissible duration, never clamped)
//! takes far more than a frame: a unit of it (one visit, or the search for a
//! critical instant) takes up to [`UNIT_MAX_TICKS`]. So the frame that accepts
//! the target only sets the check up (state `checking`), and every following
//! frame, after its pulses, runs units while the PWM period has room for one
//! more at its worst ([`ServoOutputs::period_ticks_left`]); where the outputs
//! keep no time (the host twin) it runs [`HOST_UNITS_PER_FRAME`]. A catch-up
//! frame runs none. The reply comes when the check decides: `ok move … path
//! line …` (or `ok goto …`, `ok circle …`, `info touch …`), or the refusal;
//! lines sent meanwhile are answered in between.
//!
//! # Policy
//! - A path move starts from rest: a target while a move runs or a check is
//!   pending is refused (`busy moving`), as is a path while a joint move runs.
//!   Nothing is superposed on a path move, so no velocity can step.
//! - STOP cancels a pending check (its requester gets `err path check
//!   stopped`) and freezes a running path move on the pose of the previous
//!   frame, like any move; `resume` does not continue it.
//! - The pulses go through the calibration's fast map ([`TickMap`]), which
//!   clamps to the output window: the check already keeps every scanned point
//!   inside the angle limits, and no pulse can leave the window between them.
//!   A point whose IK fails in flight (rounding at the rim) holds the
//!   previous pulses and latches STOP with `fault`, as a non-finite setpoint
//!   of a joint move does.
//! - `circle <r>` starts and ends at the effector's current position: the
//!   circle's centre lies r closer to the base axis, so its first point (the
//!   farthest out, [`Path::circle`]) is where the effector stands. A circle
//!   centred on the effector would not pass through it, and getting onto it
//!   would be a jump or a second move.

use super::refusal::Refusal;
use super::{Answer, App, MoveInfo, MoveKind, PlanDue, FRAME_S};
use crate::config::settings::PathMode;
use crate::geometry::ik::fk3_pose;
use crate::geometry::path::{Path, PathShapeError};
use crate::math::real::Real;
use crate::motion::path::{Pace, PathArm, PathCheck, PathError, PathLimits, PathPlan, PathRequest};
use crate::motion::plan::{LawKind, JOINTS};
use crate::seam::{SerialPort, ServoOutputs};
use crate::servo::map::{Joint, TickMap};

/// The longest unit of a path check, Timer5 ticks (8 cycles each): the
/// 24-bisection search for a critical instant, BENCHMARKS.md
/// `path_check_unit` max, rounded up with some room.
pub const UNIT_MAX_TICKS: u16 = 17_500;
/// Left at the end of a checking frame for its reply line (float to
/// decimal), telemetry and the jump back to the wait.
const TAIL_TICKS: u16 = 4_000;
/// Units per frame where the outputs keep no time.
pub const HOST_UNITS_PER_FRAME: u16 = 4;
/// Scan intervals of the chip's check: the bench's `path_check_unit` scan.
const CHECK_SAMPLES: u16 = 24;
/// Refinement steps around each critical point: offsets down to
/// tₛ·2^(−6) on each side.
const CHECK_REFINE: u16 = 24;

/// A path move's lifecycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum PathRun {
    /// No path move.
    Idle,
    /// Being checked; `due` says who hears the outcome.
    Checking {
        /// The check so far.
        check: PathCheck<f32>,
        /// The accepted target and its requester.
        due: PlanDue,
    },
    /// Running: frame `frame` of the plan (t = frame × 20 ms) comes next.
    Running {
        /// The checked plan.
        plan: PathPlan<f32>,
        /// The calibration's fast maps, built for this move.
        ticks: [TickMap; JOINTS],
        /// Frames since the start.
        frame: u16,
    },
}

fn refusal(e: &PathError<f32>) -> Refusal {
    match *e {
        PathError::Shape(PathShapeError::NotFinite) => Refusal::NotFinite,
        PathError::Shape(_) => Refusal::PathShape,
        PathError::Law(_) | PathError::BadLimits => Refusal::Trajectory,
        PathError::LawNotScalable => Refusal::PathLaw,
        PathError::Unreachable { .. } => Refusal::PathUnreachable,
        PathError::Singular { .. } => Refusal::PathSingular,
        PathError::JointLimit { joint, .. } => {
            Refusal::PathJointLimit(Joint::ALL.get(usize::from(joint)).copied().unwrap_or(Joint::Base))
        }
        PathError::Speed { .. } | PathError::Accel { .. } | PathError::TooSlow { .. } => Refusal::PathTooSlow,
    }
}

impl App {
    /// The kind of move a joint target makes under the `path` setting.
    pub(super) fn target_kind(&self) -> MoveKind {
        match self.path_mode {
            PathMode::Joint => MoveKind::Joint,
            PathMode::Line => MoveKind::Line,
        }
    }

    /// A path move is being checked or running.
    pub(super) fn path_busy(&self) -> bool {
        self.path != PathRun::Idle
    }

    /// `circle <r>` (hundredths of a workspace unit): accepted now, checked
    /// after the frame's pulses.
    pub(super) fn start_circle(&mut self, r_centi: u16) -> Result<(), Refusal> {
        let r = f32::from(r_centi) * 0.01 * self.params.k;
        let here = self.commanded;
        let res = self.accept(&here, None, MoveKind::Circle { r });
        if let Err(e) = res {
            self.last_refusal = Some(e);
        }
        res
    }

    /// Sets up the check of an accepted path target (the frame's plan step).
    /// `Err` is answered at once; `Ok` waits for the check.
    #[inline(never)]
    pub(super) fn begin_path_check(&mut self, due: &PlanDue) -> Result<(), Refusal> {
        let links = self.geo.links;
        let here = fk3_pose(&links, &self.commanded);
        let [x, y, z] = here;
        let path = match due.kind {
            MoveKind::Circle { r } => {
                // The centre r nearer the base axis in the top view, so the
                // turn starts where the effector is (module doc).
                let rho = Real::sqrt(x * x + y * y);
                if !rho.is_finite() || rho <= r {
                    return Err(Refusal::PathShape);
                }
                let f = (rho - r) / rho;
                Path::circle(&[x * f, y * f, z], r)
            }
            _ => Path::line(&here, &fk3_pose(&links, &due.target)),
        }
        .map_err(|e| refusal(&PathError::Shape(e)))?;
        if self.config.law == LawKind::ZatPaper {
            return Err(Refusal::PathLaw);
        }
        let check = self.new_check(&path)?;
        self.path = PathRun::Checking { check, due: *due };
        self.busy = true;
        Ok(())
    }

    /// The check of `path` under this move's limits, at the shortest move
    /// the law allows and slowed down to what the joints allow.
    fn new_check(&self, path: &Path<f32>) -> Result<PathCheck<f32>, Refusal> {
        let lim = self.plan_limits(&self.maps, self.move_percent());
        let mut min = [0.0f32; JOINTS];
        let mut max = [0.0f32; JOINTS];
        for ((lo, hi), m) in min.iter_mut().zip(max.iter_mut()).zip(self.maps.iter()) {
            (*lo, *hi) = m.angle_limits::<f32>();
        }
        let plim = PathLimits { min, max, speed: lim.speed, accel: lim.accel, ts_max: lim.ts_max };
        let arm = PathArm { links: self.geo.links, branch: self.geo.branch };
        let req = PathRequest {
            path: *path,
            law: self.config.law,
            ts: lim.ts_min,
            pace: Pace::SlowDown,
            samples: CHECK_SAMPLES,
            refine: CHECK_REFINE,
        };
        PathCheck::new(&req, &arm, &plim).map_err(|e| refusal(&e))
    }

    /// After the pulses: cancels a check STOP interrupted, or runs the
    /// check's units the period has room for and answers once it decides.
    #[inline(never)]
    pub(super) fn step_path_check<S: ServoOutputs, U: SerialPort>(
        &mut self,
        servos: &S,
        serial: &mut U,
        catch_up: bool,
    ) {
        let PathRun::Checking { mut check, due } = self.path else { return };
        if self.stopped {
            self.path = PathRun::Idle;
            self.answer_path(serial, &due.answer, Err(Refusal::PathStopped));
            return;
        }
        if catch_up {
            return;
        }
        let mut outcome = None;
        let mut units = 0u16;
        loop {
            let room = match servos.period_ticks_left() {
                Some(left) => left >= UNIT_MAX_TICKS + TAIL_TICKS,
                None => units < HOST_UNITS_PER_FRAME,
            };
            if !room {
                break;
            }
            units += 1;
            outcome = check.step(1);
            if outcome.is_some() {
                break;
            }
        }
        self.path = PathRun::Checking { check, due };
        if let Some(r) = outcome {
            let r = r.map_err(|e| refusal(&e)).and_then(|plan| self.start_path(&plan, &due));
            if let Err(e) = r {
                self.path = PathRun::Idle;
                self.last_refusal = Some(e);
            }
            self.answer_path(serial, &due.answer, r);
        }
    }

    /// A checked plan starts in the next frame.
    fn start_path(&mut self, plan: &PathPlan<f32>, due: &PlanDue) -> Result<(), Refusal> {
        let [b, s, e] = &self.maps;
        let (Some(b), Some(s), Some(e)) = (TickMap::new(b), TickMap::new(s), TickMap::new(e)) else {
            return Err(Refusal::Trajectory);
        };
        // The pose the move ends on: the IK of the path's last point (a
        // circle's end is its start; a line's is the target's effector).
        let end = plan.angles(plan.ts()).map_err(|_| Refusal::PathUnreachable)?;
        self.last_move = MoveInfo {
            target: end,
            ts: plan.ts(),
            replan: None,
            a: None,
            end_velocity: [0.0; JOINTS],
            touch: due.touch,
            kind: due.kind,
        };
        self.path = PathRun::Running { plan: *plan, ticks: [b, s, e], frame: 0 };
        Ok(())
    }

    /// Tells the requester how the check went.
    fn answer_path<U: SerialPort>(&mut self, serial: &mut U, answer: &Answer, r: Result<(), Refusal>) {
        match *answer {
            Answer::Nobody => {}
            Answer::Serial(done) => self.send_reply(serial, &r.map_or_else(super::serial::Done::Refused, |()| done)),
            Answer::Touch(p) => self.report_touch(serial, &p, r),
            Answer::Screen(p, x_p, y_p) => {
                self.screen.refusal = r.err().map(|e| self.ui_refusal(e, x_p, y_p));
                self.report_touch(serial, &p, r);
            }
        }
    }

    /// The path frame: the law's progress, the path's point, its IK and the
    /// pulses. Returns `false` when there is no running path move.
    #[inline(never)]
    pub(super) fn step_path(&mut self) -> bool {
        let PathRun::Running { plan, ticks, frame } = &mut self.path else { return false };
        let t = f32::from(*frame) * FRAME_S;
        let done = t >= plan.ts();
        let q = plan.angles(t).ok();
        let mut out = [0u16; JOINTS];
        let mut ok = q.is_some();
        if let Some(q) = &q {
            for ((o, m), a) in out.iter_mut().zip(ticks.iter()).zip(q.iter()) {
                match m.ticks(*a) {
                    Some(v) => *o = v,
                    None => ok = false,
                }
            }
        }
        *frame = frame.saturating_add(1);
        match (ok, q) {
            (true, Some(q)) => {
                self.commanded = q;
                self.frame_pulses = Some(out);
                if done {
                    self.path = PathRun::Idle;
                    self.first_move = false;
                }
            }
            _ => {
                // The previous frame's pose and pulses stay.
                self.path = PathRun::Idle;
                self.latch_fault();
            }
        }
        true
    }
}
