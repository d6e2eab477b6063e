//! Small helpers over the raw simavr bindings: ioctl ids, register bit reads
//! and lookup of the peripheral structs simavr keeps in its io-module list.
//! simavr exposes several of these only as C macros or `static inline`
//! functions, which bindgen does not carry over.

use std::os::raw::{c_char, c_int, c_void};
use std::sync::Once;

use simavr_ffi as ffi;

extern "C" {
    // simavr allocates the core with malloc and never frees it itself
    // (`avr_terminate` releases only what the core points to).
    fn free(p: *mut c_void);
    // `va_list` travels as a pointer on the x86-64 and AArch64 C ABIs.
    fn vsnprintf(buf: *mut c_char, n: usize, fmt: *const c_char, ap: *mut c_void) -> c_int;
}

/// simavr's stock logger prints every message that has no core attached,
/// debug chatter included ("Loaded 386 bytes of Flash data at 0"); this one
/// keeps errors, and per-core messages up to the core's log level.
unsafe extern "C" fn logger(avr: *mut ffi::avr_t, level: c_int, fmt: *const c_char, ap: *mut c_void) {
    let limit = if avr.is_null() { ffi::LOG_ERROR as c_int } else { c_int::from((*avr).log()) };
    if level > limit.max(ffi::LOG_ERROR as c_int) {
        return;
    }
    let mut buf = [0 as c_char; 512];
    vsnprintf(buf.as_mut_ptr(), buf.len(), fmt, ap);
    let msg = std::ffi::CStr::from_ptr(buf.as_ptr()).to_string_lossy();
    eprint!("simavr: {msg}");
}

pub(crate) fn install_logger() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        type Logger = unsafe extern "C" fn(*mut ffi::avr_t, c_int, *const c_char, *mut c_void);
        let f: Logger = logger;
        // SAFETY: same C signature; the `va_list` parameter is passed as a
        // pointer either way (see `vsnprintf` above).
        unsafe { ffi::avr_global_logger_set(std::mem::transmute::<Logger, ffi::avr_logger_p>(f)) };
    });
}

/// `AVR_IOCTL_DEF(a, b, c, d)` from sim_io.h.
pub(crate) const fn ioctl_def(a: u8, b: u8, c: u8, d: u8) -> u32 {
    ((a as u32) << 24) | ((b as u32) << 16) | ((c as u32) << 8) | d as u32
}

pub(crate) const fn ioctl_uart_getirq(name: u8) -> u32 {
    ioctl_def(b'u', b'a', b'r', name)
}

pub(crate) const fn ioctl_uart_set_flags(name: u8) -> u32 {
    ioctl_def(b'u', b'a', b's', name)
}

pub(crate) const fn ioctl_ioport_getirq(name: u8) -> u32 {
    ioctl_def(b'i', b'o', b'g', name)
}

pub(crate) const fn ioctl_timer_getirq(name: u8) -> u32 {
    ioctl_def(b't', b'm', b'r', name)
}

pub(crate) const IOCTL_ADC_GETIRQ: u32 = ioctl_def(b'a', b'd', b'c', b'0');

/// `avr_regbit_get`: the (masked, shifted) value of a register bit field.
///
/// # Safety
/// `avr` must be a live, initialised core.
pub(crate) unsafe fn regbit_get(avr: *const ffi::avr_t, rb: &ffi::avr_regbit_t) -> u8 {
    let reg = rb.reg() as usize;
    if reg == 0 {
        return 0;
    }
    let v = *(*avr).data.add(reg);
    (v >> rb.bit()) & rb.mask() as u8
}

/// The io module whose IRQ block answers to `ioctl`, cast to its concrete
/// type `T` (every simavr peripheral struct starts with its `avr_io_t`).
///
/// # Safety
/// `avr` must be a live, initialised core and `T` the struct that really
/// embeds the module answering to `ioctl`.
pub(crate) unsafe fn find_io<T>(avr: *mut ffi::avr_t, ioctl: u32) -> Option<*mut T> {
    let mut io = (*avr).io_port;
    while !io.is_null() {
        if (*io).irq_ioctl_get == ioctl && !(*io).irq.is_null() {
            return Some(io.cast());
        }
        io = (*io).next;
    }
    None
}

/// Releases a pointer malloc'ed by simavr.
///
/// # Safety
/// `p` must come from simavr's malloc and not be used afterwards.
pub(crate) unsafe fn c_free<T>(p: *mut T) {
    if !p.is_null() {
        free(p.cast());
    }
}
