//! Three hobby servos and the gripper's (the fourth channel, Timer1's OC1A
//! on the chip): each turns toward the angle its pulse stands for (the
//! inverse of its calibration), no faster than its speed limit, and ignores
//! errors inside its deadband. Without pulses (power-up, `disable`) a servo
//! stays where it is.

use touch_arm::config::grip::GRIP_DEFAULT;
use touch_arm::seam::ServoOutputs;
use touch_arm::servo::map::{JointCal, ABS_MAX_US, ABS_MIN_US};

/// Mechanical behaviour shared by the three servos.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoModel {
    /// Fastest turn, rad/s (an MG996R unloaded: ~0.17 s/60° ≈ 6 rad/s).
    pub max_speed_rad_s: f64,
    /// Pulse error, µs, below which the servo does not move.
    pub deadband_us: f64,
}

impl Default for ServoModel {
    fn default() -> Self {
        ServoModel { max_speed_rad_s: 6.0, deadband_us: 3.0 }
    }
}

/// One recorded PWM period.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ServoSample {
    /// Pulses of the period in Timer5 ticks of 0.5 µs (`None`: no pulse).
    pub pulses: Option<[u16; 3]>,
    /// Shaft angles at the end of the period, rad (servo convention).
    pub angles: [f64; 3],
    /// The gripper's pulse of the period, ticks (`None`: no pulse).
    pub grip: Option<u16>,
    /// The gripper's shaft angle at the end of the period, rad.
    pub grip_angle: f64,
}

#[derive(Debug, Clone)]
/// The three joint servos and the gripper as the app's servo outputs drive them: pulses in, shaft angles out, every out-of-range pulse recorded.
pub struct SimServos {
    /// The servos' true pulse ↔ angle relation (fixed: a `cal set` in the app
    /// does not change the hardware).
    pub cals: [JointCal; 3],
    /// How fast the shafts follow their pulses.
    pub model: ServoModel,
    angles: [f64; 3],
    pulses: Option<[u16; 3]>,
    /// One sample per servo period: pulses and shaft angles.
    pub history: Vec<ServoSample>,
    /// Every `set_pulses` value (ticks) outside a servo's configured pulse range.
    pub violations: Vec<[u16; 3]>,
    /// The gripper servo's true calibration (its defaults unless a test
    /// changes it).
    pub grip_cal: JointCal,
    grip_angle: f64,
    grip_pulse: Option<u16>,
    /// Every `set_grip` value (ticks) outside the gripper's pulse range.
    pub grip_violations: Vec<u16>,
}

impl SimServos {
    /// Servos with true calibrations `cals` and dynamics `model`, their shafts at `initial` (rad), no pulse yet.
    pub fn new(cals: &[JointCal; 3], model: &ServoModel, initial: &[f64; 3]) -> Self {
        SimServos {
            cals: *cals,
            model: *model,
            angles: *initial,
            pulses: None,
            history: Vec::new(),
            violations: Vec::new(),
            grip_cal: GRIP_DEFAULT,
            // Half open: unknown to the app, like the joints' shafts.
            grip_angle: 0.5,
            grip_pulse: None,
            grip_violations: Vec::new(),
        }
    }

    /// The gripper's shaft angle, rad.
    pub fn grip_angle(&self) -> f64 {
        self.grip_angle
    }

    /// The gripper's pulse being output, ticks.
    pub fn grip_pulse(&self) -> Option<u16> {
        self.grip_pulse
    }

    /// The joints' shaft angles now, rad (servo convention).
    pub fn angles(&self) -> [f64; 3] {
        self.angles
    }

    /// The joints' pulses being output, ticks; `None` before the first.
    pub fn pulses(&self) -> Option<[u16; 3]> {
        self.pulses
    }

    /// Power cycle: the pulses stop, the shafts stay put.
    pub fn power_cycle(&mut self) {
        self.pulses = None;
        self.grip_pulse = None;
    }

    /// The angle a pulse of `ticks` (0.5 µs) stands for, from the calibration in f64.
    pub fn pulse_angle(cal: &JointCal, ticks: u16) -> f64 {
        (f64::from(ticks) / 2.0 - cal.offset_us as f64) / cal.us_per_rad as f64
    }

    /// Runs the servos for `dt` seconds of the current pulses and records it.
    pub fn advance(&mut self, dt: f64) {
        if let Some(p) = self.pulses {
            for ((a, cal), ticks) in self.angles.iter_mut().zip(self.cals.iter()).zip(p.iter()) {
                self.model.turn(a, cal, *ticks, dt);
            }
        }
        if let Some(t) = self.grip_pulse {
            self.model.turn(&mut self.grip_angle, &self.grip_cal, t, dt);
        }
        self.history.push(ServoSample {
            pulses: self.pulses,
            angles: self.angles,
            grip: self.grip_pulse,
            grip_angle: self.grip_angle,
        });
    }
}

impl ServoModel {
    /// One servo's shaft `a` turning toward what `ticks` stands for for `dt`.
    fn turn(&self, a: &mut f64, cal: &JointCal, ticks: u16, dt: f64) {
        let target = SimServos::pulse_angle(cal, ticks);
        let err = target - *a;
        let err_us = err.abs() * (cal.us_per_rad as f64).abs();
        if err_us > self.deadband_us {
            let step = self.max_speed_rad_s * dt;
            *a += err.clamp(-step, step);
        }
    }
}

impl ServoOutputs for SimServos {
    fn set_pulses(&mut self, ticks: &[u16; 3]) {
        // Ticks against limits in µs: compare 2·limit.
        let bad = ticks.iter().zip(self.cals.iter()).any(|(t, c)| {
            let t = u32::from(*t);
            t < 2 * u32::from(c.min_us.max(ABS_MIN_US)) || t > 2 * u32::from(c.max_us.min(ABS_MAX_US))
        });
        if bad {
            self.violations.push(*ticks);
        }
        self.pulses = Some(*ticks);
    }

    fn set_grip(&mut self, ticks: u16) {
        let c = &self.grip_cal;
        let t = u32::from(ticks);
        if t < 2 * u32::from(c.min_us.max(ABS_MIN_US)) || t > 2 * u32::from(c.max_us.min(ABS_MAX_US)) {
            self.grip_violations.push(ticks);
        }
        self.grip_pulse = Some(ticks);
    }

    fn disable(&mut self) {
        self.pulses = None;
        self.grip_pulse = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn turns_at_its_speed_limit_and_stops_within_the_deadband() {
        let model = ServoModel { max_speed_rad_s: 5.0, deadband_us: 3.0 };
        let mut s = SimServos::new(&JointCal::DEFAULTS, &model, &[0.0, 0.0, -1.0]);
        s.advance(0.02);
        assert_eq!(s.angles(), [0.0, 0.0, -1.0], "no pulse, no motion");
        // 1500 us (3000 ticks) on the base = pi/2; 0.1 rad per 20 ms frame.
        s.set_pulses(&[3000, 1200, 3656]);
        s.advance(0.02);
        assert!((s.angles()[0] - 0.1).abs() < 1e-12);
        for _ in 0..20 {
            s.advance(0.02);
        }
        // Arrived exactly (the last step is shorter than the limit): π/2 up to
        // the f32 calibration constants.
        assert_eq!(s.angles()[0], SimServos::pulse_angle(&JointCal::BASE_DEFAULT, 3000));
        assert!((s.angles()[0] - std::f64::consts::FRAC_PI_2).abs() < 1e-6);
        // Elbow: 1828 us = -0.99833 rad, 0.95 us from -1 rad: inside the deadband.
        assert_eq!(s.angles()[2], -1.0);
        assert_eq!(s.history.len(), 22);
        assert!(s.violations.is_empty());
        s.set_pulses(&[4900, 1200, 3000]);
        assert_eq!(s.violations, vec![[4900, 1200, 3000]]);
        // Half a µs past a limit is a violation now that ticks are carried.
        s.set_pulses(&[4801, 1200, 3000]);
        assert_eq!(s.violations.len(), 2);
        s.set_pulses(&[4800, 1199, 3000]);
        assert_eq!(s.violations.len(), 3);
    }
}
