//! Path and lift moves on the chip (issue #13): with `path line` a target is
//! reached by the effector along the straight segment from where it is;
//! `circle <r>` makes one turn in the arm's vertical plane. Both are paced by
//! the selected law and start and end at rest; every frame solves the IK of
//! the path's point (the path frame, BENCHMARKS.md `path_frame`). With
//! `lift <h>` a joint target is reached through the via pose h above the
//! higher end ([`crate::motion::lift`]: its own two time-scaled smooth stops,
//! whatever the law), both shapes' G every frame (`lift_frame`). A lift and
//! `path line` exclude each other (`lift and path line exclusive`): a line's
//! effector goes straight, a lift's goes up. Both are settings of the
//! configuration, stored by `cal save` (record version 4).
//!
//! # The check, spread over frames
//! A path's plan-time check ([`PathCheck`]: every point reachable, inside the
//! output window (angle ∩ pulse limits), on one IK branch, no joint over its speed or acceleration
//! limit; slowed down to the shortest admissible duration, never clamped)
//! takes far more than a frame: a unit of it (one visit, or the search for a
//! critical instant, or one stretch's bound) takes up to [`UNIT_MAX_TICKS`],
//! a visit up to [`VISIT_MAX_TICKS`]. A lift's ([`LiftCheck`]:
//! the via pose reachable, every joint inside its output window on a 513-point scan
//! where the two terms can overshoot, the shortest duration within the
//! speed and acceleration limits, decided on the scan's hull vertices)
//! likewise, a vertex a unit, up to [`LIFT_UNIT_MAX_TICKS`]. So the frame that accepts
//! the target only sets the check up (state `checking`), and every following
//! frame, after its pulses, runs units while the PWM period has room for one
//! more at its worst ([`ServoOutputs::period_ticks_left`]); where the outputs
//! keep no time (the host twin) it runs [`HOST_UNITS_PER_FRAME`]. A catch-up
//! frame runs none. The reply comes when the check decides: `ok move … path
//! line …` or `ok move … lift 0.20 …` (or `ok goto …`, `ok circle …`, `info
//! touch …`), or the refusal; lines sent meanwhile are answered in between.
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
//!   inside that window (the angle limits and the pulse limits seen as
//!   angles, as a superposed correction's check), and no pulse can leave the
//!   window between them.
//!   A point whose IK fails in flight (rounding at the rim) holds the
//!   previous pulses and latches STOP with `fault`, as a non-finite setpoint
//!   of a joint move does.
//! - `circle <r>` starts and ends at the effector's current position: the
//!   circle's centre lies r closer to the base axis, so its first point (the
//!   farthest out, [`Path::circle`]) is where the effector stands. A circle
//!   centred on the effector would not pass through it, and getting onto it
//!   would be a jump or a second move.

use super::refusal::Refusal;
use super::{App, MoveInfo, MoveKind, PlanDue, FRAME_S};
use crate::config::settings::PathMode;
use crate::geometry::ik::{fk3_pose, ik3};
use crate::geometry::path::{Path, PathShapeError};
use crate::math::real::Real;
use crate::motion::lift::{LiftCheck, LiftError, LiftPlan, LiftRequest};
use crate::motion::path::{Pace, PathArm, PathCheck, PathError, PathLimits, PathPlan, PathRequest};
use crate::motion::plan::{LawKind, JOINTS};
use crate::motion::planner::request::PlanLimits;
use crate::seam::{SerialPort, ServoOutputs};
use crate::servo::map::{Joint, TickMap};

/// The longest unit of a path check, Timer5 ticks (8 cycles each): the
/// 24-bisection search for a critical instant (BENCHMARKS.md
/// `path_check_unit` max) and, as long, a unit of the bounds between the
/// samples (a visit and the interval bound, 134 988 cycles at most:
/// `hal-sim/rig/tests/bench_elf.rs` keeps it within this), rounded up with
/// some room.
pub const UNIT_MAX_TICKS: u16 = 17_500;
/// The longest unit of a path check that [`PathCheck::next_is_visit`]
/// says is a visit (law, IK with rates, three joints), Timer5 ticks:
/// BENCHMARKS.md `path_visit_unit` max (`hal-sim/rig/tests/bench_elf.rs`
/// keeps it within nine tenths of this), rounded up with about a fifth of
/// room; a visit's work is the same float operations wherever the path
/// goes. Most of a check's units are visits: a frame fits
/// two or three of them where it fits one unit of [`UNIT_MAX_TICKS`].
pub const VISIT_MAX_TICKS: u16 = 8_000;
/// Left at the end of a checking frame for its reply line (float to
/// decimal), telemetry and the jump back to the wait.
const TAIL_TICKS: u16 = 4_000;
/// Units per frame where the outputs keep no time.
pub const HOST_UNITS_PER_FRAME: u16 = 4;
/// The longest unit of a lift's check (one hull vertex, three joints; the
/// last unit also works out the duration), Timer5 ticks: BENCHMARKS.md
/// `lift_check_unit` max, rounded up with some room.
pub const LIFT_UNIT_MAX_TICKS: u16 = 1_400;
/// Lift units per frame where the outputs keep no time: the check's
/// vertices ([`crate::motion::lift_hull::UNITS`]) in 4 frames, about what a
/// checking frame on the chip has room for (BENCHMARKS.md, the checked
/// moves' latency).
pub const HOST_LIFT_UNITS_PER_FRAME: u16 = 48;
/// Scan intervals of the chip's check: the bench's `path_check_unit` scan.
pub const CHECK_SAMPLES: u16 = 24;
/// Refinement steps around each critical point and end: none, the
/// critical instant alone (`PathRequest::refine` 3). Since the stretches'
/// bounds decide the duration (issue #24, F4), visits around the critical
/// instants only raised the floor a bound is measured against, and the
/// halving next to a spike finds it as well: with 24 steps (offsets down to
/// tₛ·2^(−6) each side, 43 visits per point) the check took about twice as
/// many cycles for the same verdicts and durations no shorter (issue #22
/// §1; BENCHMARKS.md, the checked moves' latency). The angle, reach and
/// base-axis extremes lie at the critical instants and the ends, which are
/// still visited.
pub const CHECK_REFINE: u16 = 3;

/// A check spread over frames.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Check {
    /// A line's or a circle's.
    Path(PathCheck<f32>),
    /// A lift's.
    Lift(LiftCheck<f32>),
}

/// A checked move the frames run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Run {
    /// The effector along a path: the IK of its point every frame.
    Path(PathPlan<f32>),
    /// Every joint through the via pose: both shapes' G every frame.
    Lift(LiftPlan<f32>),
}

impl Run {
    pub(super) fn ts(&self) -> f32 {
        match self {
            Run::Path(p) => p.ts(),
            Run::Lift(l) => l.ts(),
        }
    }

    pub(super) fn angles(&self, t: f32) -> Option<[f32; JOINTS]> {
        match self {
            Run::Path(p) => p.angles(t).ok(),
            Run::Lift(l) => Some(l.angles(t)),
        }
    }
}

/// A path or lift move's lifecycle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum PathRun {
    /// None.
    Idle,
    /// Being checked; `due` says who hears the outcome.
    Checking {
        /// The check so far.
        check: Check,
        /// The accepted target and its requester.
        due: PlanDue,
    },
    /// Running: frame `frame` of the plan (t = frame × 20 ms) comes next.
    Running {
        /// The checked plan.
        run: Run,
        /// The calibration's fast maps, built for this move.
        ticks: [TickMap; JOINTS],
        /// Frames since the start.
        frame: u16,
    },
}

impl PathRun {
    /// Share of a running move's tₛ elapsed (`None` unless running).
    pub(super) fn progress(&self) -> Option<f32> {
        match self {
            PathRun::Running { run, frame, .. } => Some((f32::from(*frame) * FRAME_S / run.ts()).min(1.0)),
            _ => None,
        }
    }
}

fn lift_refusal(e: &LiftError<f32>) -> Refusal {
    match *e {
        LiftError::ViaUnreachable => Refusal::LiftViaUnreachable,
        LiftError::JointLimit { joint } => {
            Refusal::LiftJointLimit(Joint::ALL.get(usize::from(joint)).copied().unwrap_or(Joint::Base))
        }
        LiftError::TooSlow { .. } => Refusal::LiftTooSlow,
        LiftError::BadHeight | LiftError::Trajectory(_) => Refusal::Trajectory,
    }
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
    /// The kind of move a joint target makes under the `path` and `lift`
    /// settings (which exclude each other).
    pub(super) fn target_kind(&self) -> MoveKind {
        match (self.config.path, self.config.lift_centi) {
            (PathMode::Line, _) => MoveKind::Line,
            (PathMode::Joint, Some(h)) => MoveKind::Lift { h: f32::from(h) * 0.01 * self.params.k },
            (PathMode::Joint, None) => MoveKind::Joint,
        }
    }

    /// `path joint|line`; `line` is refused while a lift is set.
    pub(super) fn set_path(&mut self, m: PathMode) -> Result<(), Refusal> {
        if m == PathMode::Line && self.config.lift_centi.is_some() {
            return Err(Refusal::LiftWithLine);
        }
        self.config.path = m;
        Ok(())
    }

    /// `lift <h>|off`; a lift is refused under `path line` (a line's
    /// effector goes straight; a lift's joints go through the via pose).
    pub(super) fn set_lift(&mut self, h: Option<u8>) -> Result<(), Refusal> {
        if h.is_some() && self.config.path == PathMode::Line {
            return Err(Refusal::LiftWithLine);
        }
        self.config.lift_centi = h;
        Ok(())
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

    /// Sets up the check of an accepted path or lift target (the frame's
    /// plan step). `Err` is answered at once; `Ok` waits for the check.
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn begin_path_check(&mut self, due: &PlanDue) -> Result<(), Refusal> {
        let check = match due.kind {
            MoveKind::Lift { h } => Check::Lift(self.new_lift_check(&due.target, h)?),
            _ => Check::Path(self.new_path_check(due)?),
        };
        self.path = PathRun::Checking { check, due: *due };
        self.spend_heavy();
        Ok(())
    }

    /// The check of a line to `due`'s target or of a circle from here.
    fn new_path_check(&self, due: &PlanDue) -> Result<PathCheck<f32>, Refusal> {
        let links = self.geo.links;
        let here = fk3_pose(&links, &self.commanded);
        // A path's joints are the IK of its points: its first frame must be
        // the pose held now, and a line's last the target asked for.
        self.ik_keeps(&here, &self.commanded)?;
        if due.kind == MoveKind::Line {
            self.ik_keeps(&fk3_pose(&links, &due.target), &due.target)?;
        }
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
        self.new_check(&path)
    }

    /// The IK of the effector point `p` gives the pose `q` back. Not so when
    /// `q` is on the other elbow branch, or a joint's calibration lets it
    /// past the IK's range (a base beyond 180°, which the IK reads as the
    /// same direction below −180°): the path's frames would start or end a
    /// turn away, a jump. Refused instead (`path pose off IK range`).
    fn ik_keeps(&self, p: &[f32; 3], q: &[f32; JOINTS]) -> Result<(), Refusal> {
        /// Far above the FK-IK round trip's rounding, even next to the rim
        /// (√ε of f32), far below any other solution of the same point.
        const SAME_POSE_RAD: f32 = 2e-3;
        let k = ik3(&self.geo.links, p[0], p[1], p[2], self.geo.branch).map_err(|_| Refusal::PathUnreachable)?;
        let same = [k.th1, k.th2, k.th3].iter().zip(q.iter()).all(|(a, b)| (*a - *b).abs() <= SAME_POSE_RAD);
        if same {
            Ok(())
        } else {
            Err(Refusal::PathBranch)
        }
    }

    /// The check of a lift by `h` (arm units) from the pose at rest to
    /// `target`, under this move's limits.
    fn new_lift_check(&self, target: &[f32; JOINTS], h: f32) -> Result<LiftCheck<f32>, Refusal> {
        let lim = self.plan_limits(self.maps.each_ref(), self.move_percent());
        let plim = self.path_limits(&lim);
        let req = LiftRequest {
            start: self.commanded,
            target: *target,
            h,
            links: self.geo.links,
            branch: self.geo.branch,
            ts_min: lim.ts_min,
        };
        LiftCheck::new(&req, &plim).map_err(|e| lift_refusal(&e))
    }

    /// The output window of the calibration (angle limits ∩ pulse limits,
    /// [`crate::servo::map::ServoMap::output_window`]) with `lim`'s rates.
    /// Not the angle limits alone: with a pulse limit tighter than its angle
    /// limit, a plan that passes the pulse limit has its servo clamped there,
    /// stopped dead while the plan goes on (issue #24, F1); a superposed
    /// correction is checked in the same window.
    fn path_limits(&self, lim: &PlanLimits<f32>) -> PathLimits<f32> {
        let mut min = [0.0f32; JOINTS];
        let mut max = [0.0f32; JOINTS];
        for ((lo, hi), m) in min.iter_mut().zip(max.iter_mut()).zip(self.maps.iter()) {
            (*lo, *hi) = m.output_window();
        }
        PathLimits { min, max, speed: lim.speed, accel: lim.accel, ts_max: lim.ts_max }
    }

    /// The check of `path` under this move's limits, at the shortest move
    /// the law allows and slowed down to what the joints allow.
    fn new_check(&self, path: &Path<f32>) -> Result<PathCheck<f32>, Refusal> {
        let lim = self.plan_limits(self.maps.each_ref(), self.move_percent());
        let plim = self.path_limits(&lim);
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
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn step_path_check<S: ServoOutputs, U: SerialPort>(
        &mut self,
        servos: &S,
        serial: &mut U,
        catch_up: bool,
    ) {
        let PathRun::Checking { due, .. } = self.path else { return };
        if self.stopped {
            self.path = PathRun::Idle;
            self.answer_plan(serial, &due.answer, Err(Refusal::PathStopped));
            return;
        }
        if catch_up {
            return;
        }
        let Some(r) = self.run_check_units(servos) else { return };
        let r = r.and_then(|run| self.start_run(&run, &due));
        if let Err(e) = r {
            self.path = PathRun::Idle;
            self.last_refusal = Some(e);
        }
        self.answer_plan(serial, &due.answer, r);
    }

    /// The check's units the period has room for, in place; the plan or the
    /// refusal once it decides.
    fn run_check_units<S: ServoOutputs>(&mut self, servos: &S) -> Option<Result<Run, Refusal>> {
        let PathRun::Checking { check, .. } = &mut self.path else { return None };
        let host_units = match check {
            Check::Path(_) => HOST_UNITS_PER_FRAME,
            Check::Lift(_) => HOST_LIFT_UNITS_PER_FRAME,
        };
        let mut units = 0u16;
        loop {
            let unit_max = match check {
                Check::Path(c) if c.next_is_visit() => VISIT_MAX_TICKS,
                Check::Path(_) => UNIT_MAX_TICKS,
                Check::Lift(_) => LIFT_UNIT_MAX_TICKS,
            };
            let room = match servos.period_ticks_left() {
                Some(left) => left >= unit_max + TAIL_TICKS,
                None => units < host_units,
            };
            if !room {
                return None;
            }
            units += 1;
            let r = match check {
                Check::Path(c) => c.step(1).map(|r| r.map(Run::Path).map_err(|e| refusal(&e))),
                Check::Lift(c) => c.step(1).map(|r| r.map(Run::Lift).map_err(|e| lift_refusal(&e))),
            };
            if r.is_some() {
                return r;
            }
        }
    }

    /// A checked plan starts in the next frame.
    fn start_run(&mut self, run: &Run, due: &PlanDue) -> Result<(), Refusal> {
        let [b, s, e] = &self.maps;
        let (Some(b), Some(s), Some(e)) = (TickMap::new(b), TickMap::new(s), TickMap::new(e)) else {
            return Err(Refusal::Trajectory);
        };
        // The pose the move ends on: for a path the IK of its last point (a
        // circle's end is its start; a line's is the target's effector).
        let end = run.angles(run.ts()).ok_or(Refusal::PathUnreachable)?;
        self.last_move = MoveInfo {
            target: end,
            ts: run.ts(),
            replan: None,
            a: None,
            end_velocity: [0.0; JOINTS],
            touch: due.touch,
            kind: due.kind,
        };
        self.path = PathRun::Running { run: *run, ticks: [b, s, e], frame: 0 };
        Ok(())
    }

    /// The path frame (the law's progress, the path's point, its IK) or the
    /// via frame (both shapes' G), then the pulses. Returns `false` when there is no running path move.
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn step_path(&mut self) -> bool {
        let PathRun::Running { run, ticks, frame } = &mut self.path else { return false };
        let t = f32::from(*frame) * FRAME_S;
        let done = t >= run.ts();
        let q = run.angles(t);
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
