//! The faults a tester provokes from the page: power cycle, EEPROM
//! corruption, a noisy panel and the stalled frame loop.

use std::time::Instant;

use serde_json::{json, Value};

use super::Bench;
use crate::live::api::Control;
use touch_arm_rig::firmware::Session;

/// The noisy-panel fault: the noisy-touch scenario's ADC noise (σ, counts)
/// and glitch probability (`hal-sim/twin/tests/scenarios/touch_noisy.scn`).
const NOISE_COUNTS: f64 = 2.0;
const NOISE_SPIKES: f64 = 0.01;
/// TCCR5B's data address: clearing it stops Timer5's clock (see `stall`).
const TCCR5B: u16 = 0x121;

impl Bench {
    pub(super) fn control(&mut self, c: Control) -> Result<Value, String> {
        match c {
            Control::PowerCycle => self.power_cycle(),
            Control::Reset => self.external_reset(),
            Control::CorruptEeprom { addr } => {
                let ee = self.session.avr.eeprom().map_err(|e| e.to_string())?;
                let old = *ee.get(usize::from(addr)).ok_or_else(|| format!("no EEPROM byte {addr}"))?;
                let new = !old;
                self.session.avr.set_eeprom(addr, &[new]).map_err(|e| e.to_string())?;
                self.note(format!(
                    "EEPROM byte {addr} corrupted: {old:#04x} -> {new:#04x} (read at the next power-up)"
                ));
                Ok(json!({ "addr": addr, "old": old, "new": new }))
            }
            Control::Noise(on) => {
                self.noise = on;
                self.apply_noise();
                self.note(if on {
                    format!("noisy panel: ADC noise {NOISE_COUNTS} counts, {}% glitches", NOISE_SPIKES * 100.0)
                } else {
                    "clean panel".into()
                });
                Ok(json!({ "noise": on }))
            }
            Control::Stall => self.stall(),
        }
    }

    pub(super) fn apply_noise(&mut self) {
        let (n, s) = if self.noise { (NOISE_COUNTS, NOISE_SPIKES) } else { (0.0, 0.0) };
        self.session.set_noise(n, s);
    }

    /// Power off and on: a new core loads the same ELF; the EEPROM is the
    /// only thing that survives, as on the board (the screen, RAM and
    /// timers start from power-on state, the finger is lifted).
    fn power_cycle(&mut self) -> Result<Value, String> {
        let eeprom = self.session.avr.eeprom().map_err(|e| e.to_string())?;
        let base = self.cycles();
        let seed = self.opts.seed.wrapping_add(u64::from(self.power_ups));
        let mut s = Session::start_with_lcd(&self.opts.elf, self.opts.wiring, self.opts.lcd, seed)?;
        s.set_glass(super::glass_of(self.opts.lcd));
        s.avr.set_eeprom(0, &eeprom).map_err(|e| e.to_string())?;
        self.session = s;
        self.cycle_base = base;
        self.power_ups += 1;
        self.resets_seen = 0;
        self.finger = None;
        self.last_pulses = [None; 3];
        self.last_grip = None;
        if self.halted.take().is_some() {
            self.pacer.restart(Instant::now(), base);
        }
        self.apply_noise();
        self.after_restart("power cycle (the EEPROM keeps its contents)");
        Ok(json!({ "power_ups": self.power_ups, "t_s": self.now_s() }))
    }

    /// The RESET pin pulled low (the board's button, or a console opening
    /// the port): the same core restarts with its RAM, so the firmware
    /// resumes the pulses it had (`info reset external resume pulses …`).
    fn external_reset(&mut self) -> Result<Value, String> {
        self.session.avr.external_reset();
        // Not a watchdog reset: the tick's reset counter must not count it.
        self.resets_seen = self.session.avr.resets();
        self.external_resets += 1;
        if self.halted.take().is_some() {
            self.pacer.restart(Instant::now(), self.cycles());
        }
        self.after_restart("external reset (the RESET pin): RAM kept, the firmware resumes its pulses");
        Ok(json!({ "external_resets": self.external_resets, "t_s": self.now_s() }))
    }

    /// The watchdog's case. The firmware has no command that hangs it, so
    /// the bench stalls its frame loop from outside: it clears TCCR5B, which
    /// stops Timer5's clock. The loop then waits for a PWM period that never
    /// starts, nothing feeds the watchdog, and its 500 ms timeout resets the
    /// chip, which restarts Timer5 at boot (as `hal-sim/rig/tests/firmware_e2e.rs`'s
    /// watchdog test does).
    fn stall(&mut self) -> Result<Value, String> {
        if self.halted.is_some() {
            return Err("the firmware is halted; power-cycle first".into());
        }
        // It arms the watchdog before its first frame, so once it has
        // answered a `status` the stall is sure to trip it.
        if self.state == "booting" {
            return Err("the firmware is still booting; its watchdog is not armed yet".into());
        }
        self.session.avr.write_io(TCCR5B, 0).map_err(|e| e.to_string())?;
        let t = self.now_s();
        self.stalled_at = Some(t);
        self.state = "stalled".into();
        self.note(
            "frame loop stalled (Timer5's clock stopped); the watchdog should reset the chip within 0.5 s".into(),
        );
        Ok(json!({ "stalled_at_s": t }))
    }
}
