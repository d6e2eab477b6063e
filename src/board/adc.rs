//! The 10-bit ADC: AVcc reference, single blocking conversions on ADC0..15.
//!
//! Clock: 16 MHz / 128 = 125 kHz, inside the 50–200 kHz window the datasheet
//! requires for full 10-bit resolution. A conversion takes 13 ADC clocks
//! (104 µs), the first one after enabling 25 (200 µs).
//!
//! Channel switching: the multiplexer (MUX4:0 in ADMUX, MUX5 in ADCSRB for
//! ADC8..15) is latched when a conversion starts, and the sample-and-hold
//! then tracks the input for 1.5 ADC clocks (12 µs) before it holds. That is
//! enough for a source of ≤ 10 kΩ; to also cover the input's own wiring and a
//! slower source, [`Adc::read`] waits [`CHANNEL_SETTLE_US`] after every channel
//! change before starting. Callers that switch *drive* pins (the touch panel)
//! add their own settle time for the analog source itself.

use avr_device::atmega2560::ADC;

use super::delay_us;

/// Wait after selecting a different channel, before starting the conversion.
pub const CHANNEL_SETTLE_US: u32 = 10;

/// ADMUX: REFS1:0 = 01 selects AVcc (with the board's capacitor on AREF).
const ADMUX_REFS_AVCC: u8 = 0b0100_0000;
/// Polls of ADSC, at least 1 µs apart, before a conversion counts as stuck:
/// ≥ 1 ms against ≤ 200 µs for the slowest (first) conversion.
const MAX_POLLS: u16 = 1000;

/// Why a conversion gave no value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AdcError {
    /// The channel number is above 15.
    BadChannel,
    /// The conversion did not finish in time (the ADC is stuck or disabled).
    Timeout,
}

/// The 10-bit ADC, single-ended on channels 0..=15 (A0..A15), AVcc reference.
pub struct Adc {
    regs: ADC,
    /// The channel currently on the multiplexer.
    channel: u8,
}

impl Adc {
    /// Enables the ADC on channel 0 with AVcc reference and a 125 kHz clock.
    pub fn new(regs: ADC) -> Self {
        // SAFETY: a valid REFS/MUX combination (AVcc, single-ended ADC0).
        regs.admux().write(|w| unsafe { w.bits(ADMUX_REFS_AVCC) });
        // Free-running off, MUX5 = 0.
        regs.adcsrb().write(|w| w.mux5().clear_bit());
        regs.adcsra().write(|w| w.aden().set_bit().adps().prescaler_128());
        Self { regs, channel: 0 }
    }

    /// One conversion on `channel` (0..=15), in counts 0..=1023.
    pub fn read(&mut self, channel: u8) -> Result<u16, AdcError> {
        if channel > 15 {
            return Err(AdcError::BadChannel);
        }
        if channel != self.channel {
            self.select(channel);
            delay_us(CHANNEL_SETTLE_US);
        }
        self.convert()
    }

    /// The channel the next conversion will sample.
    pub fn channel(&self) -> u8 {
        self.channel
    }

    fn select(&mut self, channel: u8) {
        let mux5 = channel & 0b1000 != 0;
        self.regs.adcsrb().modify(|_, w| w.mux5().bit(mux5));
        // SAFETY: AVcc reference with a single-ended channel 0..7 (with MUX5
        // that is ADC8..15).
        self.regs.admux().write(|w| unsafe { w.bits(ADMUX_REFS_AVCC | (channel & 0b0111)) });
        self.channel = channel;
    }

    /// Starts a conversion on the current channel and waits for it, bounded.
    fn convert(&mut self) -> Result<u16, AdcError> {
        if self.regs.adcsra().read().aden().bit_is_clear() {
            return Err(AdcError::Timeout);
        }
        self.regs.adcsra().modify(|_, w| w.adsc().set_bit());
        for _ in 0..MAX_POLLS {
            if self.regs.adcsra().read().adsc().bit_is_clear() {
                // The 16-bit read takes ADCL first, which locks ADCH until it
                // is read: both bytes come from the same conversion.
                return Ok(self.regs.adc().read().bits() & 0x3FF);
            }
            delay_us(1);
        }
        Err(AdcError::Timeout)
    }
}
