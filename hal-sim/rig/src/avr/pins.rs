//! GPIO ports: state snapshots, external drive, and cycle-stamped edge
//! recording of selected pins.
//!
//! Edges come from the port's `IOPORT_IRQ_PIN_ALL` IRQ, which simavr raises
//! after every PORT or DDR change, including the ones a timer's compare
//! output makes (simavr models OCnx by writing the PORT bit). The stamp is
//! `avr->cycle` when simavr processes the change: an event scheduled inside a
//! multi-cycle instruction is seen at the end of that instruction, so a stamp
//! can lag the ideal edge by up to the longest instruction minus one cycle
//! (4 cycles = 0.25 µs at 16 MHz), and by one cycle while the core sleeps.

use std::os::raw::c_void;

use simavr_ffi as ffi;

use super::sys;
use super::Shared;

/// One GPIO pin, e.g. `Pin::new('L', 3)` for PL3 (OC5A, Arduino D46).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Pin {
    /// Port letter, 'A'..'L'.
    pub port: char,
    /// Bit within the port, 0..=7.
    pub bit: u8,
}

impl Pin {
    /// Pin `bit` of port `port`.
    pub const fn new(port: char, bit: u8) -> Self {
        Self { port, bit }
    }

    /// A pin of the firmware's pin map (`touch_arm::seam::pins`).
    pub const fn of(p: touch_arm::seam::pins::Pin) -> Self {
        Self::new(p.port().letter(), p.bit())
    }
}

/// Register view of one port.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PortState {
    /// Port letter, 'A'..'L'.
    pub name: char,
    /// PORTx: output levels, or the pull-ups of inputs.
    pub port: u8,
    /// DDRx: 1 for an output pin.
    pub ddr: u8,
    /// PINx as simavr holds it: outputs mirror PORT, inputs hold what was
    /// last driven from outside (or the pull-up level).
    pub pin: u8,
}

impl PortState {
    /// Bit `bit` of the port is an output.
    pub fn is_output(&self, bit: u8) -> bool {
        self.ddr >> bit & 1 == 1
    }

    /// The level the firmware drives, or `None` for an input (hi-Z, or
    /// weak pull-up: see [`PortState::pull_up`]).
    pub fn driven(&self, bit: u8) -> Option<bool> {
        self.is_output(bit).then_some(self.port >> bit & 1 == 1)
    }

    /// Input with the internal pull-up enabled (DDR = 0, PORT = 1).
    pub fn pull_up(&self, bit: u8) -> bool {
        !self.is_output(bit) && self.port >> bit & 1 == 1
    }

    /// Logic level on the pin (driven level for outputs, PIN for inputs).
    pub fn level(&self, bit: u8) -> bool {
        let v = (self.pin & !self.ddr) | (self.port & self.ddr);
        v >> bit & 1 == 1
    }
}

/// A level change of a watched pin.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Edge {
    /// CPU cycle of the change.
    pub cycle: u64,
    /// The level after the change.
    pub high: bool,
}

/// A complete high pulse (rising edge followed by a falling edge).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pulse {
    /// CPU cycle of the rising edge.
    pub rise_cycle: u64,
    /// Cycles from the rising to the falling edge.
    pub width_cycles: u64,
}

impl Pulse {
    /// The width in µs at `cpu_hz`.
    pub fn width_us(&self, cpu_hz: u32) -> f64 {
        self.width_cycles as f64 * 1e6 / cpu_hz as f64
    }
}

/// Builds the high pulses of an edge list; a pulse still high at the end is
/// left out.
pub(crate) fn pulses_from(edges: &[Edge]) -> Vec<Pulse> {
    let mut out = Vec::new();
    let mut rise = None;
    for e in edges {
        match (e.high, rise) {
            (true, _) => rise = Some(e.cycle),
            (false, Some(r)) => {
                out.push(Pulse { rise_cycle: r, width_cycles: e.cycle - r });
                rise = None;
            }
            (false, None) => {}
        }
    }
    out
}

pub(crate) struct PortInfo {
    pub(crate) name: char,
    pub(crate) r_port: u16,
    pub(crate) r_ddr: u16,
    pub(crate) r_pin: u16,
    pub(crate) irq: *mut ffi::avr_irq_t,
}

impl PortInfo {
    /// # Safety
    /// `avr` must be a live core.
    pub(crate) unsafe fn state(&self, avr: *const ffi::avr_t) -> PortState {
        let d = (*avr).data;
        PortState {
            name: self.name,
            port: *d.add(self.r_port as usize),
            ddr: *d.add(self.r_ddr as usize),
            pin: *d.add(self.r_pin as usize),
        }
    }
}

/// All ports 'A'..='L' the core has.
///
/// # Safety
/// `avr` must be a live, initialised core.
pub(crate) unsafe fn discover_ports(avr: *mut ffi::avr_t) -> Vec<PortInfo> {
    let mut ports = Vec::new();
    for name in b'A'..=b'L' {
        if let Some(p) = sys::find_io::<ffi::avr_ioport_t>(avr, sys::ioctl_ioport_getirq(name)) {
            ports.push(PortInfo {
                name: name as char,
                r_port: (*p).r_port,
                r_ddr: (*p).r_ddr,
                r_pin: (*p).r_pin,
                irq: (*p).io.irq,
            });
        }
    }
    ports
}

/// Edge recorder for the watched bits of one port; boxed so simavr can hold
/// its address.
pub(crate) struct PortWatch {
    pub(crate) shared: *mut Shared,
    pub(crate) port: usize,
    pub(crate) mask: u8,
    pub(crate) last: u8,
    pub(crate) edges: [Vec<Edge>; 8],
}

impl PortWatch {
    /// Records edges of the watched bits between `last` and `now`.
    pub(crate) fn update(&mut self, now: u8, cycle: u64) -> bool {
        let changed = (now ^ self.last) & self.mask;
        if changed == 0 {
            return false;
        }
        for bit in 0..8 {
            if changed >> bit & 1 == 1 {
                self.edges[bit].push(Edge { cycle, high: now >> bit & 1 == 1 });
            }
        }
        self.last = (self.last & !self.mask) | (now & self.mask);
        true
    }
}

pub(crate) unsafe extern "C" fn on_pin_all(_irq: *mut ffi::avr_irq_t, value: u32, param: *mut c_void) {
    let watch = param.cast::<PortWatch>();
    let shared = (*watch).shared;
    let cycle = (*shared).now();
    if (*watch).update(value as u8, cycle) {
        (*shared).events += 1;
    }
}

/// Effective levels of a port's 8 pins straight from the registers.
///
/// # Safety
/// `avr` must be a live core.
pub(crate) unsafe fn levels(info: &PortInfo, avr: *const ffi::avr_t) -> u8 {
    let s = info.state(avr);
    (s.pin & !s.ddr) | (s.port & s.ddr)
}
