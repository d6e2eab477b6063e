//! Timer5 hardware PWM for the three servos on OC5A/OC5B/OC5C = D46/D45/D44
//! (PL3/PL4/PL5: base, shoulder, elbow), and Timer1's OC1A = D11 (PB5) for a
//! fourth servo, the gripper. Timers 3 and 4 sit on the shield's LCD data
//! pins; Timer1's outputs are the shield's microSD pins D11..D13, free on
//! the Mega when no card is used (`seam::pins::mega::D11` says why D11).
//!
//! Mode 14 (fast PWM, TOP = ICR = 39999) with prescaler 8: 16 MHz / 8 = 2 MHz,
//! so one tick is 0.5 µs and the period is 40000 ticks = 20 ms (50 Hz). OCRnx
//! is double-buffered by the hardware and latched at BOTTOM, so a new width
//! never produces a glitched pulse; Timer5's overflow flag marks the start of
//! each period, which is what the app's 50 Hz frame aligns with.
//!
//! Timer1 runs in the same mode with the same TOP and prescaler, started on
//! the same clock edge as Timer5 (ATmega2560 datasheet, GTCCR: with TSM set,
//! PSRSYNC holds the prescaler shared by timers 0, 1, 3, 4 and 5 in reset;
//! clearing TSM releases them together), so every gripper pulse starts with
//! the joints' pulses and a width set in a frame takes effect at the same
//! period start as theirs.

use avr_device::atmega2560::{PORTB, PORTL, TC1, TC5};
use embedded_hal::pwm::SetDutyCycle;

use crate::seam::pins::mega::{GRIPPER, SERVOS};
use crate::seam::pins::Port;
use crate::servo::map::{us_to_ticks, JointCal, TIMER5_TOP};

/// Timer5 compare channels in use: OC5A, OC5B, OC5C (base, shoulder, elbow).
pub const CHANNELS: usize = 3;
/// The gripper's channel number in [`ServoPwm::set`] and friends: Timer1's OC1A.
pub const GRIP_CHANNEL: usize = CHANNELS;
/// Every output: the three joints and the gripper.
const OUTPUTS: usize = CHANNELS + 1;
/// PB5 (the pin map's gripper pin).
const GRIP_PIN: u8 = 1 << GRIPPER.bit();
const _: () = assert!(matches!(GRIPPER.port(), Port::B));
/// PL3, PL4, PL5 (the pin map's servo pins, all on port L).
const SERVO_PINS: u8 = (1 << SERVOS[0].bit()) | (1 << SERVOS[1].bit()) | (1 << SERVOS[2].bit());
const _: () = assert!(
    matches!(SERVOS[0].port(), Port::L) && matches!(SERVOS[1].port(), Port::L) && matches!(SERVOS[2].port(), Port::L)
);

/// Inclusive pulse-width window (ticks) a channel may ever be set to.
#[derive(Clone, Copy, Debug)]
pub struct TickLimits {
    /// Shortest pulse, ticks of 0.5 µs.
    pub min: u16,
    /// Longest pulse, ticks of 0.5 µs.
    pub max: u16,
}

impl TickLimits {
    /// A joint calibration's pulse limits (µs) in ticks: the hardware
    /// layer's own clamp, under the app's.
    pub fn of_joint(cal: &JointCal) -> TickLimits {
        TickLimits { min: us_to_ticks(cal.min_us), max: us_to_ticks(cal.max_us) }
    }
}

/// Timer5 and its three compare outputs, and Timer1's OC1A for the
/// gripper, owned, with a tick window per channel.
pub struct ServoPwm {
    tc5: TC5,
    tc1: TC1,
    limits: [TickLimits; OUTPUTS],
    enabled: [bool; OUTPUTS],
    /// When the last `set_pulses` came: ticks into the period, and whether
    /// the next period had already started (its pulses then went out with
    /// the previous widths: a missed period).
    pub last_write: (u16, bool),
}

/// The servo range a channel's window starts at before a calibration
/// narrows it: 500..2500 µs.
pub const SERVO_RANGE: TickLimits = TickLimits { min: 1000, max: 5000 };

impl ServoPwm {
    /// Starts both timers together with every output disconnected (the pins
    /// driven low): no servo sees a pulse until `set` commands a width for
    /// it. The joints get `limits`; the gripper's window is [`SERVO_RANGE`]
    /// until [`ServoPwm::set_grip_limits`].
    pub fn new(tc5: TC5, tc1: TC1, portl: &PORTL, portb: &PORTB, limits: &[TickLimits; CHANNELS]) -> Self {
        // SAFETY: every bit pattern is valid for the port registers; only the
        // servo bits change. No interrupt handler touches ports L or B.
        portl.portl().modify(|r, w| unsafe { w.bits(r.bits() & !SERVO_PINS) });
        portl.ddrl().modify(|r, w| unsafe { w.bits(r.bits() | SERVO_PINS) });
        portb.portb().modify(|r, w| unsafe { w.bits(r.bits() & !GRIP_PIN) });
        portb.ddrb().modify(|r, w| unsafe { w.bits(r.bits() | GRIP_PIN) });
        // SAFETY: only GTCCR of Timer0's block is touched; `Tick` (the owner
        // of Timer0) never writes it. Halting the shared prescaler delays
        // Timer0 by the few cycles below, once, at start-up.
        let gtccr = unsafe { (*avr_device::atmega2560::TC0::ptr()).gtccr() };
        gtccr.write(|w| w.tsm().set_bit().psrsync().set_bit());
        tc5.tccr5b().write(|w| w.cs5().no_clock());
        tc1.tccr1b().write(|w| w.cs1().no_clock());
        tc5.tccr5a().write(|w| w.wgm5().set(0b10).com5a().disconnected().com5b().disconnected().com5c().disconnected());
        tc1.tccr1a().write(|w| w.wgm1().set(0b10).com1a().disconnected().com1b().disconnected().com1c().disconnected());
        avr_device::interrupt::free(|_| {
            tc5.icr5().write(|w| w.set(TIMER5_TOP));
            tc5.tcnt5().write(|w| w.set(0));
            tc1.icr1().write(|w| w.set(TIMER5_TOP));
            tc1.tcnt1().write(|w| w.set(0));
        });
        tc5.tccr5b().write(|w| w.wgm5().set(0b11).cs5().prescale_8());
        tc1.tccr1b().write(|w| w.wgm1().set(0b11).cs1().prescale_8());
        // Both count from here, on the same prescaler edge.
        gtccr.write(|w| w.tsm().clear_bit());
        let mut pwm =
            Self { tc5, tc1, limits: [SERVO_RANGE; OUTPUTS], enabled: [false; OUTPUTS], last_write: (0, false) };
        pwm.set_limits(limits);
        pwm
    }

    /// Sets channel `ch`'s pulse width in 0.5 µs ticks (0..=2 the joints,
    /// [`GRIP_CHANNEL`] the gripper), clamped into the channel's limits, and
    /// connects its output on first use. Returns the value actually
    /// written. Takes effect at the next period start.
    pub fn set(&mut self, ch: usize, ticks: u16) -> u16 {
        let Some(lim) = self.limits.get(ch).copied() else {
            return 0;
        };
        let v = ticks.clamp(lim.min, lim.max);
        // In fast PWM the output is set at BOTTOM and cleared after the compare
        // match tick, so it stays high for OCR + 1 ticks.
        let ocr = v.saturating_sub(1);
        // 16-bit timer registers go through the shared TEMP byte: no interrupt
        // may touch another 16-bit register between the two byte writes.
        avr_device::interrupt::free(|_| match ch {
            0 => self.tc5.ocr5a().write(|w| w.set(ocr)),
            1 => self.tc5.ocr5b().write(|w| w.set(ocr)),
            2 => self.tc5.ocr5c().write(|w| w.set(ocr)),
            _ => self.tc1.ocr1a().write(|w| w.set(ocr)),
        });
        if !self.enabled[ch] {
            self.enabled[ch] = true;
            match ch {
                0 => self.tc5.tccr5a().modify(|_, w| w.com5a().match_clear()),
                1 => self.tc5.tccr5a().modify(|_, w| w.com5b().match_clear()),
                2 => self.tc5.tccr5a().modify(|_, w| w.com5c().match_clear()),
                _ => self.tc1.tccr1a().modify(|_, w| w.com1a().match_clear()),
            };
        }
        v
    }

    /// The gripper's window (e.g. from its calibration). A value already
    /// set stays until the next `set`.
    pub fn set_grip_limits(&mut self, limits: TickLimits) {
        self.limits[GRIP_CHANNEL] = sanitize(limits);
    }

    /// Replaces the per-channel windows (e.g. after the stored calibration is
    /// loaded or changed). A value already set stays until the next `set`.
    pub fn set_limits(&mut self, limits: &[TickLimits; CHANNELS]) {
        for (l, new) in self.limits.iter_mut().zip(limits.iter()) {
            *l = sanitize(*new);
        }
    }

    /// Disconnects every output (pins low, no pulses): servos go limp rather
    /// than being driven somewhere unintended. Used on panic and fault.
    pub fn disable_all(&mut self) {
        self.tc5.tccr5a().modify(|_, w| w.com5a().disconnected().com5b().disconnected().com5c().disconnected());
        self.tc1.tccr1a().modify(|_, w| w.com1a().disconnected());
        self.enabled = [false; OUTPUTS];
    }

    /// The widths set last, for the reset block (`board::resume`): read at
    /// a period start, they are the pulses of that period. `None` until
    /// every joint has a pulse; the gripper's is `None` until it has one.
    pub fn snapshot(&self) -> Option<crate::app::resume::Snapshot> {
        let [eb, es, ee, eg] = self.enabled;
        if !(eb && es && ee) {
            return None;
        }
        // OCRnx reads its buffer, the width set last (kept here rather than
        // in a copy: `ServoPwm` lives in `main`'s frame). 16-bit reads go
        // through the shared TEMP byte: no interrupt in between.
        let [b, s, e, g] = avr_device::interrupt::free(|_| {
            [
                self.tc5.ocr5a().read().bits(),
                self.tc5.ocr5b().read().bits(),
                self.tc5.ocr5c().read().bits(),
                self.tc1.ocr1a().read().bits(),
            ]
        })
        .map(|ocr| ocr.wrapping_add(1));
        Some(crate::app::resume::Snapshot { joints: [b, s, e], grip: eg.then_some(g) })
    }

    /// Timer ticks (0.5 µs, 8 CPU cycles) since the current period started.
    pub fn ticks(&self) -> u16 {
        // 16-bit read through the shared TEMP byte: keep interrupts out.
        avr_device::interrupt::free(|_| self.tc5.tcnt5().read().bits())
    }

    /// A new period has started since the flag was last cleared (a frame
    /// that sees this at its end overran).
    pub fn period_pending(&self) -> bool {
        self.tc5.tifr5().read().tov5().bit_is_set()
    }

    /// True once per 20 ms period (at BOTTOM), clearing the flag.
    pub fn period_started(&mut self) -> bool {
        if self.tc5.tifr5().read().tov5().bit_is_set() {
            self.tc5.tifr5().write(|w| w.tov5().set_bit());
            true
        } else {
            false
        }
    }
}

/// One servo output as embedded-hal's [`SetDutyCycle`]: the duty cycle is
/// the pulse width in Timer5 ticks out of the period ([`PERIOD_TICKS`], so a
/// duty of 3000 is a 1.5 ms pulse). Every value goes through
/// [`ServoPwm::set`]'s clamp, so no duty cycle, not even 0 ("fully off") or
/// the maximum, drives the servo outside its channel's window: use
/// [`ServoPwm::disable_all`] to stop the pulses.
pub struct ServoChannel<'a> {
    pwm: &'a mut ServoPwm,
    ch: usize,
}

/// Timer5 ticks per PWM period (20 ms): the duty cycle's full scale.
pub const PERIOD_TICKS: u16 = TIMER5_TOP + 1;

impl ServoPwm {
    /// Channel `ch` (0 base, 1 shoulder, 2 elbow, [`GRIP_CHANNEL`] the
    /// gripper) as a [`SetDutyCycle`], or `None` past the last channel.
    pub fn channel(&mut self, ch: usize) -> Option<ServoChannel<'_>> {
        (ch < OUTPUTS).then_some(ServoChannel { pwm: self, ch })
    }

    /// Channel `ch`'s window in ticks.
    pub fn limits(&self, ch: usize) -> Option<TickLimits> {
        self.limits.get(ch).copied()
    }
}

impl embedded_hal::pwm::ErrorType for ServoChannel<'_> {
    type Error = core::convert::Infallible;
}

impl SetDutyCycle for ServoChannel<'_> {
    fn max_duty_cycle(&self) -> u16 {
        PERIOD_TICKS
    }

    fn set_duty_cycle(&mut self, duty: u16) -> Result<(), Self::Error> {
        self.pwm.set(self.ch, duty);
        Ok(())
    }
}

/// A limit window must lie inside one period and be ordered; anything else is
/// collapsed to an empty-but-safe window at the lower bound.
fn sanitize(l: TickLimits) -> TickLimits {
    let min = l.min.min(TIMER5_TOP);
    let max = l.max.min(TIMER5_TOP).max(min);
    TickLimits { min, max }
}

impl crate::seam::ServoOutputs for ServoPwm {
    /// Ticks as they come, through `set`'s per-channel clamp.
    fn set_pulses(&mut self, ticks: &[u16; 3]) {
        for (ch, &t) in ticks.iter().enumerate() {
            self.set(ch, t);
        }
        self.last_write = (self.ticks(), self.period_pending());
    }

    /// Through `set`'s clamp to the gripper's window.
    fn set_grip(&mut self, ticks: u16) {
        self.set(GRIP_CHANNEL, ticks);
    }

    fn disable(&mut self) {
        self.disable_all();
    }

    /// From Timer5's count, as `frame::FrameBudget` reads it for drawing.
    fn period_ticks_left(&self) -> Option<u16> {
        if self.period_pending() {
            return Some(0);
        }
        Some(TIMER5_TOP - self.ticks().min(TIMER5_TOP))
    }
}
