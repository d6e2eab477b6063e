//! The 50 Hz frame on the chip: how much of the servo PWM period is left for
//! drawing (the screen is drawn in slices that fit it, `ui::slice`), and the
//! record of every frame's length that the simulator tests and BENCHMARKS.md
//! read ([`FRAME_STATS`]).

use super::servo_pwm::ServoPwm;
use crate::seam::ServoOutputs;
use crate::ui::DrawBudget;

/// Timer ticks (0.5 µs = 8 cycles) a drawing operation may take per pixel,
/// and on top of that per operation (bus window set-up, and the drawing code
/// that runs before the next operation asks), at most, with the serial
/// interrupts of a full-rate flood taking their share: measured in simavr
/// (`hal-sim/rig/tests/frame_budget.rs` fails when a frame overruns; BENCHMARKS.md).
const TICKS_PER_PIXEL: u32 = 5;
const TICKS_PER_OP: u32 = 1500;
/// Before the first operation: the screen model from the app's state (float
/// work), and a resumed step's replay up to where it stopped.
const START_TICKS: u32 = 5000;
/// Left at the end of the period for the frame's bookkeeping and the jump
/// back to the wait for the next period, and for what a flood's serial
/// interrupts add to the last operation: with half of it, the busiest
/// frames' last draws ran past the period end in over 1 % of the frames
/// once the replies' traffic shifted (issue #13's longer `status`); with
/// 1600, one draw of the busiest window (a map background's slice, with the
/// carer lock's screen) ran past it once the frame-budget test allowed no
/// late frame (issue #22 §2); with 2400, one of the busiest window's draws
/// ran past it once the candidate's boxes were repainted whenever the
/// candidate changed (issue #20 §4's screen). The latest frame end it
/// leaves is in BENCHMARKS.md (frame budget).
const END_TICKS: u32 = 3200;

/// The time left in the current PWM period, as a [`DrawBudget`].
pub struct FrameBudget<'a> {
    pwm: &'a ServoPwm,
}

impl<'a> FrameBudget<'a> {
    /// The budget of the period `pwm` is in.
    pub fn new(pwm: &'a ServoPwm) -> Self {
        FrameBudget { pwm }
    }

    /// Ticks left before the next period starts (0 once it has).
    fn left(&self) -> u32 {
        u32::from(self.pwm.period_ticks_left().unwrap_or(0))
    }
}

impl DrawBudget for FrameBudget<'_> {
    fn may_start(&mut self) -> bool {
        self.left() > START_TICKS + END_TICKS
    }

    #[inline(never)] // reason: code-size
    fn allows(&mut self, pixels: u32) -> bool {
        self.left() > pixels * TICKS_PER_PIXEL + TICKS_PER_OP + END_TICKS
    }
}

/// Every frame since power-up: how many; how many set their pulses only
/// after the next period had started (that period went out with the old
/// widths: a missed period); how many ended after the next period had
/// started (a plan or a redraw ran long, the pulses were out in time); and
/// the latest pulse write (of the frames whose write was in time), app end
/// and frame end (of the frames that did not overrun), in ticks after the
/// period start.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct FrameStats {
    /// Frames since power-up.
    pub frames: u32,
    /// Frames that set their pulses after the next period had started.
    pub late_pulses: u32,
    /// Frames that ended after the next period had started.
    pub overruns: u32,
    /// Latest in-time pulse write, ticks after the period start.
    pub worst_pulse_ticks: u16,
    /// Latest end of the app's work, ticks after the period start.
    pub worst_app_ticks: u16,
    /// Latest frame end (of the frames that did not overrun), ticks.
    pub worst_ticks: u16,
    /// Of the overruns, those whose app part (serial, touch, plan, check)
    /// had already passed the period end before any drawing: the rest ran
    /// late in a draw slice.
    pub app_overruns: u32,
}

/// Read by the simulator harness through the ELF symbol; written only by
/// [`record`], from the main loop.
#[no_mangle]
pub static mut FRAME_STATS: FrameStats = FrameStats {
    frames: 0,
    late_pulses: 0,
    overruns: 0,
    worst_pulse_ticks: 0,
    worst_app_ticks: 0,
    worst_ticks: 0,
    app_overruns: 0,
};

/// Records the frame that just ended; `app_ticks` is when the app's part
/// (before drawing) ended, `app_late` whether the next period had started
/// by then. Returns whether it overran: the next frame then starts late.
pub fn record(pwm: &ServoPwm, app_ticks: u16, app_late: bool) -> bool {
    let end = pwm.ticks();
    let overrun = pwm.period_pending();
    let (write, late) = pwm.last_write;
    // SAFETY: only the main loop touches FRAME_STATS (no interrupt handler
    // does), and no reference to it outlives this function.
    let s = unsafe { &mut *core::ptr::addr_of_mut!(FRAME_STATS) };
    s.frames = s.frames.wrapping_add(1);
    if late {
        s.late_pulses = s.late_pulses.saturating_add(1);
    } else {
        s.worst_pulse_ticks = s.worst_pulse_ticks.max(write);
    }
    if overrun {
        s.overruns = s.overruns.saturating_add(1);
        if app_late {
            s.app_overruns = s.app_overruns.saturating_add(1);
        }
    } else {
        s.worst_app_ticks = s.worst_app_ticks.max(app_ticks);
        s.worst_ticks = s.worst_ticks.max(end);
    }
    overrun
}
