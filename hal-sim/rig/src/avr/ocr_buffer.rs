//! Double-buffered OCRnx in fast PWM, which simavr lacks.
//!
//! On the chip, in fast PWM modes the CPU writes an OCRnx *buffer*; the
//! compare register takes it at BOTTOM, so a new width never glitches the
//! pulse in progress. simavr applies the write at once: a width shortened
//! below the current count while the output is still high misses its
//! compare and stretches that pulse by a whole period (e.g. a 21.5 ms servo
//! pulse), and a lengthened one changes the running pulse. The harness
//! wraps each OCRnx(L) write handler: in fast PWM with the timer running, the
//! write only lands in memory (so reads see it, like the buffer) and simavr
//! is told at the next BOTTOM, which simavr models as its overflow event.
//! Phase-correct modes (update at TOP) and non-PWM modes pass through.

use std::os::raw::c_void;

use simavr_ffi as ffi;

use super::sys;

pub(crate) struct OcrHook {
    timer: *mut ffi::avr_timer_t,
    addr: u16,
    orig: unsafe extern "C" fn(*mut ffi::avr_t, u16, u8, *mut c_void),
    orig_param: *mut c_void,
    pending: bool,
}

/// Installs the hook on every compare unit of every timer; returns the
/// boxed hooks (simavr holds their addresses: free them only after the
/// core is gone).
///
/// # Safety
/// `avr` must be a live, initialised core.
pub(crate) unsafe fn install(avr: *mut ffi::avr_t) -> Vec<*mut OcrHook> {
    let mut hooks = Vec::new();
    for name in b'0'..=b'5' {
        let Some(timer) = sys::find_io::<ffi::avr_timer_t>(avr, sys::ioctl_timer_getirq(name)) else {
            continue;
        };
        for comp in 0..(*timer).comp.len() {
            let addr = (*timer).comp[comp].r_ocr;
            let Some(io) = usize::from(addr).checked_sub(32) else {
                continue;
            };
            if addr == 0 || io >= (*avr).io.len() {
                continue;
            }
            let slot = &mut (*avr).io[io].w;
            let Some(orig) = slot.c else {
                continue;
            };
            let hook = Box::into_raw(Box::new(OcrHook { timer, addr, orig, orig_param: slot.param, pending: false }));
            slot.c = Some(on_ocr_write);
            slot.param = hook.cast();
            hooks.push(hook);
        }
    }
    hooks
}

unsafe extern "C" fn on_ocr_write(avr: *mut ffi::avr_t, addr: u16, v: u8, param: *mut c_void) {
    let hook = param.cast::<OcrHook>();
    let t = (*hook).timer;
    let buffered = (*t).wgm_op_mode_kind == ffi::avr_timer_wgm_fast_pwm as i32 && (*t).tov_cycles > 1;
    if !buffered {
        ((*hook).orig)(avr, addr, v, (*hook).orig_param);
        return;
    }
    *(*avr).data.add(usize::from(addr)) = v;
    if !(*hook).pending {
        (*hook).pending = true;
        let bottom = (*t).tov_base + (*t).tov_cycles;
        let delay = bottom.saturating_sub((*avr).cycle).max(1);
        ffi::avr_cycle_timer_register(avr, delay, Some(latch), hook.cast());
    }
}

unsafe extern "C" fn latch(avr: *mut ffi::avr_t, when: u64, param: *mut c_void) -> u64 {
    let hook = param.cast::<OcrHook>();
    let t = (*hook).timer;
    if (*t).tov_cycles > 1 && (*t).tov_base + (*t).tov_cycles <= when {
        // simavr's overflow for this BOTTOM has not run yet (it was
        // re-registered after us): latch right after it.
        return (*avr).cycle + 1;
    }
    (*hook).pending = false;
    let addr = usize::from((*hook).addr);
    let v = *(*avr).data.add(addr);
    // simavr reconfigures only when the OCR value differs from memory.
    *(*avr).data.add(addr) = v ^ 1;
    ((*hook).orig)(avr, (*hook).addr, v, (*hook).orig_param);
    0
}

/// A reset dropped the latch timers.
///
/// # Safety
/// The hooks must be live.
pub(crate) unsafe fn forget_pending(hooks: &[*mut OcrHook]) {
    for &h in hooks {
        (*h).pending = false;
    }
}
