//! Port listeners: a user callback run after every PORT or DDR write of
//! chosen ports (including `sbi`/`cbi` and PINx toggles), with the levels of
//! all ports at that instant. Bus decoders (e.g. the LCD's 8-bit parallel
//! bus, `crate::lcd_bus`) latch their data here on a strobe edge, and a bus
//! device answers a read strobe by driving input pins ([`PinDrive`]) before
//! the firmware's next instruction samples them.
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

    /// DDRx of `port` at the write; `None` if the core has no such port.
    pub fn ddr(&self, port: char) -> Option<u8> {
        self.index(port).map(|i| self.ddr[i])
    }

    /// The logic level of `pin` (false if its port does not exist).
    pub fn level(&self, pin: Pin) -> bool {
        self.levels(pin.port).is_some_and(|v| v >> (pin.bit & 7) & 1 == 1)
    }

    /// `pin` is an output (false if its port does not exist).
    pub fn is_output(&self, pin: Pin) -> bool {
        self.ddr(pin.port).is_some_and(|v| v >> (pin.bit & 7) & 1 == 1)
    }

    /// An input with its internal pull-up on (DDR 0, PORT 1).
    pub fn is_pulled_up(&self, pin: Pin) -> bool {
        self.index(pin.port).is_some_and(|i| (self.port[i] & !self.ddr[i]) >> (pin.bit & 7) & 1 == 1)
    }
}

/// Drives pins from inside a port listener, as a device on the wire would:
/// an input's PINx bit takes the level (what the firmware reads next); an
/// output keeps the firmware's level (simavr ignores the drive), so a bus
/// fight shows up as the firmware's value, not the device's. Unlike
/// [`Avr::drive_pin`](super::Avr::drive_pin), watched-pin edges are not
/// recorded.
pub struct PinDrive<'a> {
    ports: &'a [PortInfo],
}

impl PinDrive<'_> {
    /// Drives `pin` to `high` (no effect on a pin of a missing port).
    pub fn drive(&mut self, pin: Pin, high: bool) {
        let Some(info) = self.ports.iter().find(|p| p.name == pin.port) else {
            return;
        };
        // SAFETY: the listener runs inside avr_run on the live core that owns
        // these IRQs; a pin IRQ only updates PINx (no PIN_ALL, so no listener
        // is re-entered).
        unsafe { ffi::avr_raise_irq(info.irq.add(usize::from(pin.bit & 7)), u32::from(high)) };
    }
}

/// Called as `(port written, cycle, all port levels)`.
pub type PortListener = Box<dyn FnMut(char, u64, &PortLevels)>;

/// A listener that may also drive pins: `(port written, cycle, all port
/// levels, drive)`.
pub type BusDevice = Box<dyn FnMut(char, u64, &PortLevels, &mut PinDrive<'_>)>;

pub(crate) struct Listener {
    /// Bit `i` = port `shared.ports[i]`.
    pub(crate) mask: u32,
    pub(crate) f: BusDevice,
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
    let mut drive = PinDrive { ports: &shared.ports };
    for l in shared.port_listeners.iter_mut() {
        if l.mask & bit == 0 {
            continue;
        }
        // A panic must not unwind through simavr's C frames: park it and
        // re-raise it once avr_run has returned.
        let f = &mut l.f;
        let call = std::panic::AssertUnwindSafe(|| f(name, cycle, &levels, &mut drive));
        if let Err(payload) = std::panic::catch_unwind(call) {
            panicked.get_or_insert(payload);
        }
    }
    if let Some(p) = panicked {
        shared.callback_panic.get_or_insert(p);
    }
}
