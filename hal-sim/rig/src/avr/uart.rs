//! USART capture (TX) and paced injection (RX) for one simavr UART.
//!
//! simavr hands every byte the firmware writes to UDR to `UART_IRQ_OUTPUT`
//! at the moment of the write (not when its stop bit would leave the pin).
//! Input goes through `UART_IRQ_INPUT` into a 64-deep FIFO that a real AVR
//! does not have (it holds 2 bytes plus the shift register), so the harness
//! paces input itself with a cycle timer ticking once per character time.
//!
//! simavr derives the character time only when UBRRnL is written, from the
//! U2X/UCSZ/USBS bits of that moment, and always counts a parity bit (11 bit
//! times for 8N1). Firmware that sets U2X after the baud rate (a common and
//! legal order) would run its UART at half speed. The harness recomputes the
//! character time after every write to UBRRnL, UCSRnA and UCSRnC, from the
//! datasheet frame: start + data + parity (only if enabled) + stop bits.

use std::collections::VecDeque;
use std::os::raw::c_void;

use simavr_ffi as ffi;

use super::sys;
use super::Shared;

/// How bytes queued with [`super::Avr::uart_send`] reach the firmware.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RxPacing {
    /// One byte per character time, but only while the receiver holds fewer
    /// than 2 unread bytes: nothing is ever lost, a slow reader just slows
    /// the sender (like a link with hardware flow control).
    FlowControl,
    /// One byte per character time regardless of the reader, like a USB
    /// serial bridge without flow control. A byte arriving while the
    /// receiver already holds 3 unread bytes (2-byte buffer + shift register)
    /// is dropped and counted in [`super::Avr::uart_overruns`].
    LineRate,
}

/// Bytes the real receiver can hold before the next one overruns.
const RX_HW_CAPACITY: u16 = 3;
/// simavr's `uart_fifo` size (DECLARE_FIFO(uint16_t, uart_fifo, 64)).
const SIM_FIFO_SIZE: u16 = 64;

pub(crate) struct UartState {
    pub(crate) uart: *mut ffi::avr_uart_t,
    pub(crate) irq: *mut ffi::avr_irq_t,
    pub(crate) tx: Vec<u8>,
    pub(crate) tx_cycles: Vec<u64>,
    pub(crate) line_cursor: usize,
    pub(crate) rx_queue: VecDeque<u8>,
    pub(crate) pacing: RxPacing,
    pub(crate) pump_armed: bool,
    pub(crate) overruns: u64,
    pub(crate) reg_hooks: Vec<*mut RegHook>,
}

/// A wrapped register write handler (simavr holds its address).
pub(crate) struct RegHook {
    uart: *mut ffi::avr_uart_t,
    orig: ffi::avr_io_write_t,
    orig_param: *mut c_void,
}

impl UartState {
    pub(crate) fn new() -> Self {
        Self {
            uart: std::ptr::null_mut(),
            irq: std::ptr::null_mut(),
            tx: Vec::new(),
            tx_cycles: Vec::new(),
            line_cursor: 0,
            rx_queue: VecDeque::new(),
            pacing: RxPacing::FlowControl,
            pump_armed: false,
            overruns: 0,
            reg_hooks: Vec::new(),
        }
    }

    /// Complete lines captured since the last call; a trailing partial line
    /// stays for the next call.
    pub(crate) fn take_lines(&mut self) -> Vec<String> {
        let mut lines = Vec::new();
        let pending = &self.tx[self.line_cursor..];
        let mut start = 0;
        for (i, &b) in pending.iter().enumerate() {
            if b == b'\n' {
                let mut line = &pending[start..i];
                if let [rest @ .., b'\r'] = line {
                    line = rest;
                }
                lines.push(String::from_utf8_lossy(line).into_owned());
                start = i + 1;
            }
        }
        self.line_cursor += start;
        lines
    }
}

/// Hooks UART `name` ('0'..'3'): output capture, and no console echo or
/// `usleep` on status polls (simavr's defaults, which slow a headless run).
///
/// # Safety
/// `avr` must be a live core and `shared` the harness state that outlives it.
pub(crate) unsafe fn attach(avr: *mut ffi::avr_t, shared: *mut Shared, name: u8) -> bool {
    let Some(uart) = sys::find_io::<ffi::avr_uart_t>(avr, sys::ioctl_uart_getirq(name)) else {
        return false;
    };
    let mut flags: u32 = 0;
    ffi::avr_ioctl(avr, sys::ioctl_uart_set_flags(name), (&mut flags as *mut u32).cast());
    let irq = (*uart).io.irq;
    (*shared).uart.uart = uart;
    (*shared).uart.irq = irq;
    for reg in [(*uart).ubrrl.reg() as u16, (*uart).r_ucsra, (*uart).r_ucsrc] {
        if let Some(h) = hook_timing_reg(avr, uart, reg) {
            (*shared).uart.reg_hooks.push(h);
        }
    }
    ffi::avr_irq_register_notify(irq.add(ffi::UART_IRQ_OUTPUT as usize), Some(on_tx), shared.cast());
    true
}

unsafe fn hook_timing_reg(avr: *mut ffi::avr_t, uart: *mut ffi::avr_uart_t, reg: u16) -> Option<*mut RegHook> {
    let io = usize::from(reg).checked_sub(32)?;
    let slot = &mut (*avr).io.get_mut(io)?.w;
    let hook = Box::into_raw(Box::new(RegHook { uart, orig: slot.c, orig_param: slot.param }));
    slot.c = Some(on_timing_reg_write);
    slot.param = hook.cast();
    Some(hook)
}

unsafe extern "C" fn on_timing_reg_write(avr: *mut ffi::avr_t, addr: u16, v: u8, param: *mut c_void) {
    let hook = param.cast::<RegHook>();
    match (*hook).orig {
        Some(orig) => orig(avr, addr, v, (*hook).orig_param),
        None => *(*avr).data.add(usize::from(addr)) = v,
    }
    let u = (*hook).uart;
    let ubrr = u32::from(sys::regbit_get(avr, &(*u).ubrrl)) | u32::from(sys::regbit_get(avr, &(*u).ubrrh)) << 8;
    let bit = (ubrr + 1) * if sys::regbit_get(avr, &(*u).u2x) != 0 { 8 } else { 16 };
    const DATA_BITS: [u32; 8] = [5, 6, 7, 8, 8, 8, 8, 9];
    let ucsz = usize::from(sys::regbit_get(avr, &(*u).ucsz) | sys::regbit_get(avr, &(*u).ucsz2) << 2);
    // UPMn1:0 are bits 5:4 of UCSRnC on every classic megaAVR USART.
    let parity = u32::from((*(*avr).data.add(usize::from((*u).r_ucsrc)) >> 4) & 3 != 0);
    let stop = 1 + u32::from(sys::regbit_get(avr, &(*u).usbs));
    (*u).cycles_per_byte = u64::from(bit * (1 + DATA_BITS[ucsz & 7] + parity + stop));
}

unsafe extern "C" fn on_tx(_irq: *mut ffi::avr_irq_t, value: u32, param: *mut c_void) {
    let shared = param.cast::<Shared>();
    let cycle = (*shared).now();
    let u = &mut (*shared).uart;
    u.tx.push(value as u8);
    u.tx_cycles.push(cycle);
    (*shared).events += 1;
}

/// Starts the RX pump if bytes wait and it is idle.
///
/// # Safety
/// As for [`attach`], after a successful attach.
pub(crate) unsafe fn arm_pump(avr: *mut ffi::avr_t, shared: *mut Shared) {
    let u = &mut (*shared).uart;
    if u.pump_armed || u.rx_queue.is_empty() || u.uart.is_null() {
        return;
    }
    u.pump_armed = true;
    ffi::avr_cycle_timer_register(avr, 1, Some(rx_pump), shared.cast());
}

unsafe extern "C" fn rx_pump(avr: *mut ffi::avr_t, when: u64, param: *mut c_void) -> u64 {
    let shared = param.cast::<Shared>();
    let u = &mut (*shared).uart;
    let uart = u.uart;
    if u.rx_queue.is_empty() {
        u.pump_armed = false;
        return 0;
    }
    // Before the firmware writes UBRR this is simavr's 100 µs default.
    let char_time = (*uart).cycles_per_byte.max(1);
    if sys::regbit_get(avr, &(*uart).rxen) == 0 {
        // Receiver off: a host would not have opened the port yet; hold.
        return when + char_time;
    }
    let fifo = &(*uart).input;
    let unread = (fifo.write + SIM_FIFO_SIZE - fifo.read) % SIM_FIFO_SIZE;
    let deliver = match u.pacing {
        RxPacing::FlowControl => unread < 2,
        RxPacing::LineRate => {
            if unread >= RX_HW_CAPACITY {
                u.rx_queue.pop_front();
                u.overruns += 1;
                (*shared).events += 1;
            }
            unread < RX_HW_CAPACITY
        }
    };
    if deliver {
        if let Some(b) = u.rx_queue.pop_front() {
            ffi::avr_raise_irq(u.irq.add(ffi::UART_IRQ_INPUT as usize), b as u32);
        }
    }
    if u.rx_queue.is_empty() {
        u.pump_armed = false;
        return 0;
    }
    when + char_time
}
