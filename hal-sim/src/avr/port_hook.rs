//! Port listeners: a user callback run after every PORT or DDR write of
//! chosen ports (including `sbi`/`cbi` and PINx toggles), with the levels of
//! all ports at that instant. Bus decoders (e.g. the LCD's 8-bit parallel
//! bus, `crate::lcd_bus`) latch their data here on a strobe edge.
//!
//! The hook is simavr's `IOPORT_IRQ_PIN_ALL`, raised after each such write
//! once the port registers hold the new value; data written to other ports
//! before the strobe is therefore already visible. Timing carries the same
//! ≤ 4-cycle stamp lag as pin edges (see `pins`).

use std::os::raw::c_void;

use simavr_ffi as ffi;

use super::pins::{Pin, PortInfo};
use super::Shared;

/// Port registers of every port at one instant.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PortLevels {
    names: [u8; 12],
    port: [u8; 12],
    ddr: [u8; 12],
    pin: [u8; 12],
    n: usize,
}

impl PortLevels {
    /// # Safety
    /// `avr` must be live and `ports` its ports.
    pub(crate) unsafe fn read(ports: &[PortInfo], avr: *const ffi::avr_t) -> Self {
        let mut s = PortLevels { names: [0; 12], port: [0; 12], ddr: [0; 12], pin: [0; 12], n: 0 };
        for p in ports.iter().take(12) {
            let st = p.state(avr);
            s.names[s.n] = p.name as u8;
            s.port[s.n] = st.port;
            s.ddr[s.n] = st.ddr;
            s.pin[s.n] = st.pin;
            s.n += 1;
        }
        s
    }

    fn index(&self, port: char) -> Option<usize> {
        self.names[..self.n].iter().position(|&c| c as char == port)
    }

    /// Logic levels of `port`'s 8 pins (driven level for outputs, PIN for
    /// inputs).
    pub fn levels(&self, port: char) -> Option<u8> {
        let i = self.index(port)?;
        Some((self.pin[i] & !self.ddr[i]) | (self.port[i] & self.ddr[i]))
    }

    pub fn ddr(&self, port: char) -> Option<u8> {
        self.index(port).map(|i| self.ddr[i])
    }

    pub fn level(&self, pin: Pin) -> bool {
        self.levels(pin.port).is_some_and(|v| v >> (pin.bit & 7) & 1 == 1)
    }

    pub fn is_output(&self, pin: Pin) -> bool {
        self.ddr(pin.port).is_some_and(|v| v >> (pin.bit & 7) & 1 == 1)
    }
}

/// Called as `(port written, cycle, all port levels)`.
pub type PortListener = Box<dyn FnMut(char, u64, &PortLevels)>;

pub(crate) struct Listener {
    /// Bit `i` = port `shared.ports[i]`.
    pub(crate) mask: u32,
    pub(crate) f: PortListener,
}

/// The per-port notify parameter; boxed so simavr can hold its address.
pub(crate) struct PortHook {
    pub(crate) shared: *mut Shared,
    pub(crate) port: usize,
}

pub(crate) unsafe extern "C" fn on_port_write(_irq: *mut ffi::avr_irq_t, _value: u32, param: *mut c_void) {
    let hook = &*param.cast::<PortHook>();
    // SAFETY: callbacks run only inside avr_run, while the owning `Avr` is
    // borrowed mutably and nobody else touches `Shared`.
    let shared = &mut *hook.shared;
    let Some(info) = shared.ports.get(hook.port) else {
        return;
    };
    let name = info.name;
    let cycle = shared.now();
    let levels = PortLevels::read(&shared.ports, shared.avr);
    let bit = 1u32 << hook.port;
    let mut panicked = None;
    for l in shared.port_listeners.iter_mut() {
        if l.mask & bit == 0 {
            continue;
        }
        // A panic must not unwind through simavr's C frames: park it and
        // re-raise it once avr_run has returned.
        let f = &mut l.f;
        if let Err(payload) = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| f(name, cycle, &levels))) {
            panicked.get_or_insert(payload);
        }
    }
    if let Some(p) = panicked {
        shared.callback_panic.get_or_insert(p);
    }
}
