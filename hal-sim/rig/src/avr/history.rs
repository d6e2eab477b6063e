//! Bounded memory for sessions that run for hours (the live bench): the
//! harness records every pin edge, ADC conversion and UART byte since load,
//! which a test of a few seconds wants and an open-ended session cannot keep.
//! These calls hand over what was recorded and forget it.

use super::pins::{self, Pin, Pulse};
use super::Avr;

impl Avr {
    /// The complete high pulses of a watched pin recorded since the last
    /// call (or since watching began), forgetting their edges. A pulse that
    /// is still high keeps its rising edge for the next call. Afterwards
    /// [`Avr::pulses`] and [`Avr::edges`] only see what came later.
    pub fn drain_pulses(&mut self, pin: Pin) -> Vec<Pulse> {
        let Ok(port) = self.port_index(pin.port) else { return Vec::new() };
        let Some(&w) = self.shared().watches.iter().find(|&&w| unsafe { (*w).port } == port) else {
            return Vec::new();
        };
        // SAFETY: the watch is owned by `shared`; simavr only touches it
        // inside `avr_run`, which cannot be running while we hold &mut self.
        let edges = unsafe { &mut (*w).edges[usize::from(pin.bit & 7)] };
        let out = pins::pulses_from(edges);
        let keep_rise = edges.last().filter(|e| e.high).copied();
        edges.clear();
        edges.extend(keep_rise);
        out
    }

    /// Forgets the ADC conversion log ([`Avr::adc_conversions`]).
    pub fn forget_adc_log(&mut self) {
        self.shared_mut().adc.log.clear();
    }

    /// Forgets the UART output already returned by [`Avr::take_lines`]:
    /// [`Avr::uart_output`] then starts at the first byte not yet taken.
    pub fn forget_taken_output(&mut self) {
        let u = &mut self.shared_mut().uart;
        let n = u.line_cursor;
        u.tx.drain(..n);
        u.tx_cycles.drain(..n);
        u.line_cursor = 0;
    }
}
