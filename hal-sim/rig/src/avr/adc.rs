//! ADC input injection.
//!
//! simavr raises `ADC_IRQ_OUT_TRIGGER` with the conversion's mux setting at
//! the moment it samples (2 ADC clocks after ADSC, 14 for the first
//! conversion), then reads its per-channel millivolt table. The harness
//! answers that trigger: per-channel fixed inputs, or a handler that sees the
//! channel and every port's DDR/PORT/PIN (what a resistive touch panel model
//! needs: the panel's voltage depends on which plates the firmware drives).
//! simavr converts with `mV * 1023 / vref` truncated; the result lands in
//! ADCL/ADCH 11 ADC clocks later.

use std::os::raw::c_void;

use simavr_ffi as ffi;

use super::pins::{Pin, PortState};
use super::Shared;

/// What one ADC input pin carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AdcInput {
    /// A voltage, mV: simavr converts it against the reference in use.
    Millivolts(u32),
    /// A 10-bit conversion result; converted to the millivolts that make
    /// simavr return exactly this value under the reference in use.
    Raw(u16),
}

/// The mux selection of one conversion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AdcMux {
    /// One input against ground: ADC channel 0..=15.
    Single(u8),
    /// A differential pair with its gain.
    Differential {
        /// The positive input's channel.
        pos: u8,
        /// The negative input's channel.
        neg: u8,
        /// The amplifier's gain (1, 10 or 200).
        gain: u8,
    },
    /// Internal sources simavr handles itself (bandgap, GND, temperature...):
    /// the raw `ADC_MUX_*` kind.
    Internal(u8),
}

/// One conversion as the harness saw it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct AdcConversion {
    /// CPU cycle at which simavr sampled the input.
    pub cycle: u64,
    /// The input the conversion selected.
    pub mux: AdcMux,
    /// Reference voltage of the conversion.
    pub vref_mv: u32,
    /// Millivolts fed to the positive (single-ended: the only) input.
    pub millivolts: u32,
}

/// Every port's registers at the moment of a conversion.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PortsSnapshot {
    /// Each port's registers, in the core's port order.
    pub ports: Vec<PortState>,
}

impl PortsSnapshot {
    /// The registers of `port` ('A'..'L'); `None` if the core has no such port.
    pub fn get(&self, port: char) -> Option<PortState> {
        self.ports.iter().copied().find(|p| p.name == port)
    }

    /// The logic level of `pin` (PINx bit); `None` if its port does not exist.
    pub fn level(&self, pin: Pin) -> Option<bool> {
        self.get(pin.port).map(|p| p.level(pin.bit))
    }
}

/// Passed to the ADC handler for each input a conversion samples.
#[derive(Debug)]
pub struct AdcRequest<'a> {
    /// CPU cycle of the conversion.
    pub cycle: u64,
    /// The same instant in seconds, at the core's clock.
    pub time_s: f64,
    /// ADC input number 0..=15 (ADC8..15 sit on port K).
    pub channel: u8,
    /// Reference voltage of the conversion, mV.
    pub vref_mv: u32,
    /// The ports as the conversion found them: how the firmware drives the pins around the sampled one.
    pub ports: &'a PortsSnapshot,
}

/// The test's model of what an ADC input carries: called for every conversion, it returns the input's value.
pub type AdcHandler = Box<dyn FnMut(&AdcRequest<'_>) -> AdcInput>;

pub(crate) struct AdcState {
    pub(crate) adc: *mut ffi::avr_adc_t,
    pub(crate) inputs: [AdcInput; 16],
    pub(crate) handler: Option<AdcHandler>,
    pub(crate) log: Vec<AdcConversion>,
}

impl AdcState {
    pub(crate) fn new() -> Self {
        Self { adc: std::ptr::null_mut(), inputs: [AdcInput::Millivolts(0); 16], handler: None, log: Vec::new() }
    }
}

/// Millivolts that simavr's `mv * 1023 / vref` (truncating) maps to `raw`.
pub fn raw_to_millivolts(raw: u16, vref_mv: u32) -> u32 {
    let raw = u32::from(raw.min(1023));
    // ceil(raw * vref / 1023): the truncation then lands exactly on raw
    // because vref >= 1023 mV for every AVR reference.
    (raw * vref_mv).div_ceil(1023)
}

fn decode_mux(v: u32) -> AdcMux {
    // avr_adc_mux_t { kind:3, gain:8, diff:8, src:13 } packed LSB first.
    let kind = v & 0x7;
    let gain = (v >> 3) & 0xff;
    let diff = (v >> 11) & 0xff;
    let src = (v >> 19) & 0x1fff;
    match kind {
        ffi::ADC_MUX_SINGLE => AdcMux::Single(src as u8),
        ffi::ADC_MUX_DIFF => AdcMux::Differential { pos: src as u8, neg: diff as u8, gain: gain as u8 },
        k => AdcMux::Internal(k as u8),
    }
}

/// # Safety
/// `avr` must be a live core and `adc` its ADC.
unsafe fn vref_mv(avr: *const ffi::avr_t, adc: *const ffi::avr_adc_t) -> u32 {
    let refi = usize::from((*adc).current_refi).min(7);
    match u32::from((*adc).ref_values[refi]) {
        ffi::ADC_VREF_AREF => (*avr).aref,
        ffi::ADC_VREF_VCC => (*avr).vcc,
        ffi::ADC_VREF_AVCC => (*avr).avcc,
        v => v,
    }
}

/// # Safety
/// `avr` must be a live core and `shared` the harness state that outlives it.
pub(crate) unsafe fn attach(avr: *mut ffi::avr_t, shared: *mut Shared) -> bool {
    let Some(adc) = super::sys::find_io::<ffi::avr_adc_t>(avr, super::sys::IOCTL_ADC_GETIRQ) else {
        return false;
    };
    (*shared).adc.adc = adc;
    ffi::avr_irq_register_notify((*adc).io.irq.add(ffi::ADC_IRQ_OUT_TRIGGER as usize), Some(on_trigger), shared.cast());
    true
}

unsafe extern "C" fn on_trigger(_irq: *mut ffi::avr_irq_t, value: u32, param: *mut c_void) {
    let shared = param.cast::<Shared>();
    let avr = (*shared).avr;
    let adc = (*shared).adc.adc;
    let cycle = (*shared).now();
    let mux = decode_mux(value);
    let vref = vref_mv(avr, adc);
    let channels: &[u8] = match &mux {
        AdcMux::Single(c) => &[*c][..],
        AdcMux::Differential { pos, neg, .. } => &[*pos, *neg][..],
        AdcMux::Internal(_) => &[],
    };
    let snapshot = if (*shared).adc.handler.is_some() && !channels.is_empty() {
        let ports = (*shared).ports.iter().map(|p| p.state(avr)).collect();
        Some(PortsSnapshot { ports })
    } else {
        None
    };
    let mut first_mv = 0;
    for (i, &ch) in channels.iter().enumerate() {
        let ch = ch & 15;
        let state = &mut (*shared).adc;
        let input = match (&mut state.handler, &snapshot) {
            (Some(h), Some(ports)) => {
                let time_s = cycle as f64 / f64::from((*avr).frequency);
                let req = AdcRequest { cycle, time_s, channel: ch, vref_mv: vref, ports };
                // A panic must not unwind through simavr's C frames: park it
                // and re-raise it once avr_run has returned.
                match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| h(&req))) {
                    Ok(input) => input,
                    Err(payload) => {
                        (*shared).callback_panic.get_or_insert(payload);
                        AdcInput::Millivolts(0)
                    }
                }
            }
            _ => state.inputs[usize::from(ch)],
        };
        let mv = match input {
            AdcInput::Millivolts(mv) => mv.min(u32::from(u16::MAX)),
            AdcInput::Raw(raw) => raw_to_millivolts(raw, vref),
        };
        if i == 0 {
            first_mv = mv;
        }
        ffi::avr_raise_irq((*adc).io.irq.add(ffi::ADC_IRQ_ADC0 as usize + usize::from(ch)), mv);
    }
    (*shared).adc.log.push(AdcConversion { cycle, mux, vref_mv: vref, millivolts: first_mv });
    (*shared).events += 1;
}
