//! Exact CPU cycle counts, for benchmarks (simavr counts cycles exactly, so a
//! count is a repeatable figure, not a noisy time).
//!
//! Two free-running 16-bit timers, no interrupt: Timer1 at prescaler 1 gives
//! the count modulo 2¹⁶ exactly; Timer3 at prescaler 256 gives it to within a
//! few hundred cycles over a range of 2²⁴ cycles (1.05 s). The coarse count
//! picks the number of Timer1 wraps, so a section up to 1 s long is measured to
//! the cycle. No overflow interrupt means nothing perturbs the section being
//! measured and no static RAM is needed.
//!
//! Overhead: taking a [`Stamp`] costs a few cycles (interrupts masked, four
//! register reads) of which a constant part falls between the two Timer1
//! reads. [`CycleCounter::new`] measures that constant with an empty section,
//! and [`CycleCounter::cycles`] subtracts it, so an empty section reads 0.
//! The benchmark's own `black_box` of inputs and outputs (a store and a load
//! or two) stays in the figure; it is a handful of cycles.
//!
//! Timers 1 and 3 drive no pin here (compare outputs disconnected), so the
//! LCD shield's pins that share them are untouched; the servo PWM runs on
//! Timer5. The counter owns both timers while it exists.

use avr_device::atmega2560::{TC1, TC3};

/// Timer3 runs 256 times slower than the CPU clock.
const COARSE_SHIFT: u32 = 8;

/// Both timers read at one instant.
#[derive(Clone, Copy, Debug)]
pub struct Stamp {
    fine: u16,
    coarse: u16,
}

/// Owner of Timers 1 and 3 while they count cycles (see the module doc).
pub struct CycleCounter {
    tc1: TC1,
    tc3: TC3,
    overhead: u32,
}

impl CycleCounter {
    /// Starts both timers in normal mode (count 0..0xFFFF, no outputs) and
    /// calibrates the stamp overhead.
    pub fn new(tc1: TC1, tc3: TC3) -> Self {
        tc1.tccr1b().write(|w| w.cs1().no_clock());
        tc3.tccr3b().write(|w| w.cs3().no_clock());
        tc1.tccr1a().write(|w| w.wgm1().set(0).com1a().disconnected().com1b().disconnected().com1c().disconnected());
        tc3.tccr3a().write(|w| w.wgm3().set(0).com3a().disconnected().com3b().disconnected().com3c().disconnected());
        tc1.timsk1().reset();
        tc3.timsk3().reset();
        tc1.tccr1b().write(|w| w.wgm1().set(0).cs1().direct());
        tc3.tccr3b().write(|w| w.wgm3().set(0).cs3().prescale_256());
        let mut c = CycleCounter { tc1, tc3, overhead: 0 };
        // The smallest of a few empty sections: all are equal in practice.
        let mut best = u32::MAX;
        for _ in 0..4 {
            let a = c.now();
            let b = c.now();
            best = best.min(Self::raw(a, b));
        }
        c.overhead = best;
        c
    }

    /// Reads both timers (Timer1 first).
    #[inline(always)]
    pub fn now(&self) -> Stamp {
        // 16-bit reads go through the timer's TEMP byte: no interrupt may
        // read another of its 16-bit registers between the two byte reads.
        avr_device::interrupt::free(|_| {
            let fine = self.tc1.tcnt1().read().bits();
            let coarse = self.tc3.tcnt3().read().bits();
            Stamp { fine, coarse }
        })
    }

    /// Cycles from `a` to `b`, stamp overhead removed. Exact for sections
    /// shorter than 2²⁴ cycles.
    #[inline]
    pub fn cycles(&self, a: Stamp, b: Stamp) -> u32 {
        Self::raw(a, b).saturating_sub(self.overhead)
    }

    /// The stamp overhead that [`CycleCounter::cycles`] subtracts.
    pub fn overhead(&self) -> u32 {
        self.overhead
    }

    /// The count c with c ≡ Δfine (mod 2¹⁶) nearest to 256·Δcoarse (off by
    /// at most 2·256 cycles: prescaler phase and rounding at both ends).
    fn raw(a: Stamp, b: Stamp) -> u32 {
        let fine = u32::from(b.fine.wrapping_sub(a.fine));
        let coarse = u32::from(b.coarse.wrapping_sub(a.coarse)) << COARSE_SHIFT;
        // coarse − fine = 2¹⁶·wraps + e with |e| ≤ 512, so adding half a
        // wrap before the shift rounds to the right wrap count (never < 0).
        let wraps = (coarse + 0x8000).wrapping_sub(fine) >> 16;
        (wraps << 16) + fine
    }
}
