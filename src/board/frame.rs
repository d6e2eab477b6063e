//! The 50 Hz frame on the chip: how much of the servo PWM period is left for
//! drawing (the screen is drawn in slices that fit it, `ui::slice`), and the
//! record of every frame's length that the simulator tests and BENCHMARKS.md
//! read ([`FRAME_STATS`]).

use super::servo_pwm::{ServoPwm, TOP};
use crate::ui::DrawBudget;

/// Timer ticks (0.5 µs = 8 cycles) a drawing operation may take per pixel,
/// and on top of that per operation (bus window set-up, the drawing code
/// that computes the operation), at most: measured in simavr
/// (`tests/frame_budget.rs` fails when a frame overruns).
const TICKS_PER_PIXEL: u32 = 5;
const TICKS_PER_OP: u32 = 300;
/// Left at the end of the period for the frame's bookkeeping and the jump
/// back to the wait for the next period.
const END_TICKS: u32 = 100;

/// The time left in the current PWM period, as a [`DrawBudget`].
pub struct FrameBudget<'a> {
    pwm: &'a ServoPwm,
}

impl<'a> FrameBudget<'a> {
    pub fn new(pwm: &'a ServoPwm) -> Self {
        FrameBudget { pwm }
    }
}

impl DrawBudget for FrameBudget<'_> {
    #[inline(never)]
    fn allows(&mut self, pixels: u32) -> bool {
        if self.pwm.period_pending() {
            return false;
        }
        let left = u32::from(TOP - self.pwm.ticks().min(TOP));
        left > pixels * TICKS_PER_PIXEL + TICKS_PER_OP + END_TICKS
    }
}

/// Every frame since power-up: how many, how many ended after the next
/// period had started, and the latest end (ticks after the period start),
/// for the whole frame and for the app's part before drawing.
#[repr(C)]
#[derive(Debug, Clone, Copy)]
pub struct FrameStats {
    pub frames: u32,
    pub overruns: u32,
    pub worst_ticks: u16,
    pub worst_app_ticks: u16,
}

/// Read by the simulator harness through the ELF symbol; written only by
/// [`record`], from the main loop.
#[no_mangle]
pub static mut FRAME_STATS: FrameStats = FrameStats { frames: 0, overruns: 0, worst_ticks: 0, worst_app_ticks: 0 };

/// Records the frame that just ended; `app_ticks` is when the app's part
/// ended.
pub fn record(pwm: &ServoPwm, app_ticks: u16) {
    let end = pwm.ticks();
    let overrun = pwm.period_pending();
    // SAFETY: only the main loop touches FRAME_STATS (no interrupt handler
    // does), and no reference to it outlives this function.
    let s = unsafe { &mut *core::ptr::addr_of_mut!(FRAME_STATS) };
    s.frames = s.frames.wrapping_add(1);
    if overrun {
        s.overruns = s.overruns.saturating_add(1);
    } else {
        s.worst_ticks = s.worst_ticks.max(end);
        s.worst_app_ticks = s.worst_app_ticks.max(app_ticks);
    }
}
