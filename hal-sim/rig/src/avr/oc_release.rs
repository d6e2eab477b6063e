//! Returning a pin to its PORT latch when a compare output is disconnected.
//!
//! simavr drives OCnx by writing the waveform level into the PORT register,
//! so the latch the firmware wrote before connecting the output is lost:
//! clearing COMnx1:0 in the middle of a pulse leaves the pin high for good,
//! where the chip hands the pin back to the PORT latch at once (a firmware
//! that "disables" a servo by disconnecting its output would, in simavr
//! alone, hold it at a constant high). The harness wraps the TCCRnA write
//! handlers: it remembers each output's PORT bit when the output gets
//! connected and puts it back, through simavr's pin IRQ, when it gets
//! disconnected.
//!
//! Left as simavr does it: while connected, PORTx reads back the waveform
//! level and PINx does not follow the waveform.

use std::os::raw::c_void;

use simavr_ffi as ffi;

use super::sys;

pub(crate) struct ComHook {
    timer: *mut ffi::avr_timer_t,
    orig: ffi::avr_io_write_t,
    orig_param: *mut c_void,
    /// PORT bit of each output at the moment it was connected.
    latch: [u8; 3],
}

/// Wraps the register(s) holding the COM bits of every timer; returns the
/// boxed hooks (simavr holds their addresses: free them after the core).
///
/// # Safety
/// `avr` must be a live, initialised core.
pub(crate) unsafe fn install(avr: *mut ffi::avr_t) -> Vec<*mut ComHook> {
    let mut hooks = Vec::new();
    for name in b'0'..=b'5' {
        let Some(timer) = sys::find_io::<ffi::avr_timer_t>(avr, sys::ioctl_timer_getirq(name)) else {
            continue;
        };
        let mut regs: Vec<u16> = (*timer).comp.iter().map(|c| c.com.reg() as u16).filter(|&r| r != 0).collect();
        regs.dedup();
        for reg in regs {
            let Some(slot) = usize::from(reg).checked_sub(32).and_then(|i| (*avr).io.get_mut(i)) else {
                continue;
            };
            let slot = &mut slot.w;
            let hook = Box::into_raw(Box::new(ComHook { timer, orig: slot.c, orig_param: slot.param, latch: [0; 3] }));
            slot.c = Some(on_com_write);
            slot.param = hook.cast();
            hooks.push(hook);
        }
    }
    hooks
}

unsafe fn com_modes(avr: *const ffi::avr_t, t: *const ffi::avr_timer_t) -> [u8; 3] {
    let mut m = [0; 3];
    for (i, c) in (*t).comp.iter().enumerate() {
        m[i] = sys::regbit_get(avr, &c.com);
    }
    m
}

unsafe extern "C" fn on_com_write(avr: *mut ffi::avr_t, addr: u16, v: u8, param: *mut c_void) {
    let hook = param.cast::<ComHook>();
    let t = (*hook).timer;
    let before = com_modes(avr, t);
    match (*hook).orig {
        Some(orig) => orig(avr, addr, v, (*hook).orig_param),
        None => *(*avr).data.add(usize::from(addr)) = v,
    }
    let after = com_modes(avr, t);
    for i in 0..3 {
        let pin = (*t).comp[i].com_pin;
        if pin.reg() == 0 {
            continue;
        }
        let port_bit = (*(*avr).data.add(pin.reg() as usize) >> pin.bit()) & 1;
        if before[i] == 0 && after[i] != 0 {
            (*hook).latch[i] = port_bit;
        } else if before[i] != 0 && after[i] == 0 && port_bit != (*hook).latch[i] {
            // The compare IRQ is wired to the pin: the same path the
            // waveform takes, so PORT, PIN_ALL and edge recording follow.
            let irq = (*t).io.irq.add(ffi::TIMER_IRQ_OUT_COMP as usize + i);
            ffi::avr_raise_irq(irq, ffi::AVR_IOPORT_OUTPUT | u32::from((*hook).latch[i]));
        }
    }
}

/// A reset cleared the PORT registers and disconnected every output.
///
/// # Safety
/// The hooks must be live.
pub(crate) unsafe fn forget_latches(hooks: &[*mut ComHook]) {
    for &h in hooks {
        (*h).latch = [0; 3];
    }
}
