//! A calibration change while the arm holds a pose.
//!
//! The held pose is a set of joint angles; a new calibration can give the same
//! angles other pulses (offset, scale, `cal reset`). The servo must not jump
//! to them at its own speed: the change **slews** the pulses instead, as a
//! planned move from the pulse each servo gets now (re-read as an angle of the
//! new calibration) to the held pose, at the slow preset within every joint's
//! speed limit (state `moving`; STOP freezes it like any move). A change that
//! moves no pulse (speed limits, the touch panel, limits that still hold the
//! pose) takes effect at once. Refused: while moving or homing; while STOP is
//! latched if a pulse would move; and when the held pose or a servo's present
//! pulse lies outside the new limits (the servo would be driven to a limit).
//! The held pose is judged as a `goto` to it: within the angle limits to the
//! hundredth of a degree, and no clamp moving its pulse by more than 0.5 µs
//! (the angle and the pulse clamp counted together, [`ServoMap::angle_to_pulse`]),
//! so no sequence of accepted changes walks it out of its window. A slew is
//! the current move: `status` reports its target (the held pose) and duration.

use super::machine::within_centi;
use super::refusal::Refusal;
use super::{build_maps, App, Mode};
use crate::config::settings::{Config, SpeedPreset};
use crate::motion::plan::JOINTS;
use crate::servo::map::ServoMap;

impl App {
    /// Installs a valid configuration (see the module doc); returns the
    /// slew's duration in s when pulses move.
    #[cfg_attr(target_arch = "avr", optimize(size))] // reason: cold
    pub(super) fn replace_config(&mut self, next: &Config, touch_changed: bool) -> Result<Option<f32>, Refusal> {
        if self.is_moving() {
            return Err(Refusal::Busy);
        }
        if matches!(self.mode, Mode::Homing { .. }) {
            return Err(Refusal::Homing);
        }
        // By reference: one copy of the maps in this frame (`ok_or` and a
        // moved binding made three, across the slew's deep call).
        let built = build_maps(next);
        let Some(maps) = built.as_ref() else {
            return Err(Refusal::Fault);
        };
        // `plan_motion` starts the slew; the configuration it was planned
        // under is installed right after, in the same frame.
        let slew = match self.slew_start(maps)? {
            Some(_) if self.stopped => return Err(Refusal::Stopped),
            Some(start) => {
                let held = self.commanded;
                // The slew is the current move: `status` reports its target
                // and duration, not the previous move's.
                let info = self.plan_motion(&start, &held, Some(maps), SpeedPreset::Slow.percent())?;
                self.last_move = info;
                Some(info.ts)
            }
            None => None,
        };
        if touch_changed || next.touch != self.config.touch {
            self.filter.reset();
        }
        let links_changed = (next.arm.l2_cmm, next.arm.l3_cmm) != (self.config.arm.l2_cmm, self.config.arm.l3_cmm);
        self.config = *next;
        self.maps = *maps;
        if links_changed {
            self.install_geometry();
        }
        Ok(slew)
    }

    /// Where a slew to the held pose under `maps` starts (each servo's present
    /// pulse as an angle of `maps`), or `None` if no pulse would change.
    // Its pulse temporaries stay out of
    // replace_config's frame, which is on the slew's deep chain.
    #[inline(never)] // avr-trap: frame-size
    fn slew_start(&self, maps: &[ServoMap; JOINTS]) -> Result<Option<[f32; JOINTS]>, Refusal> {
        let mut start = [0.0f32; JOINTS];
        let mut moves = false;
        for (j, ((s, m), q)) in start.iter_mut().zip(maps.iter()).zip(self.commanded.iter()).enumerate() {
            // The held pose is judged as a `goto` to it would be: within the
            // angle limits to the hundredth, and no clamp moving its pulse.
            let held = match m.angle_to_pulse(*q) {
                Ok(p) if p.clamped.is_none() && within_centi(m.angle_limits(), *q) => p.ticks,
                _ => return Err(Refusal::HeldPoseOutside),
            };
            let now = match (self.pulses.as_ref().and_then(|p| p.get(j)), self.maps.get(j)) {
                (Some(ticks), _) => *ticks,
                (None, Some(old)) => old.angle_to_pulse(*q).map_err(|_| Refusal::NotFinite)?.ticks,
                (None, None) => held,
            };
            *s = m.pulse_to_angle(now);
            match m.angle_to_pulse(*s) {
                Ok(p) if p.clamped.is_none() => {}
                _ => return Err(Refusal::HeldPoseOutside),
            }
            moves |= held != now;
        }
        Ok(moves.then_some(start))
    }
}
