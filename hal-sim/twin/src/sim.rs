//! The runner: the app and its twin devices, stepped one 20 ms frame at a time.

use touch_arm::app::{App, AppParams, Io, State, FRAME_MS};
use touch_arm::geometry::ik::Links;
use touch_arm::servo::map::JointCal;

use super::arm::{effector, Effector};
use super::devices::{SimClock, SimEeprom, SimSerial};
use super::panel::SimPanel;
use super::servos::{ServoModel, SimServos};
use crate::display::Framebuffer;

/// Everything a simulation starts from.
#[derive(Debug, Clone)]
pub struct SimSetup {
    /// The app's parameters (`AppParams::DEFAULT` unless a scenario changes them).
    pub params: AppParams,
    /// The servos' true calibration.
    pub servo_cals: [JointCal; 3],
    /// How fast the shafts follow their pulses.
    pub servo_model: ServoModel,
    /// Shaft angles at power-up (unknown to the app), rad.
    pub servo_initial: [f64; 3],
    /// Seeds the panel's noise.
    pub seed: u64,
}

impl Default for SimSetup {
    fn default() -> Self {
        SimSetup {
            params: AppParams::DEFAULT,
            servo_cals: JointCal::DEFAULTS,
            servo_model: ServoModel::default(),
            servo_initial: [1.0, 2.0, -2.0],
            seed: 1,
        }
    }
}

/// What one frame left behind.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrameRecord {
    /// Frame number since the simulation started (reboots included).
    pub frame: u64,
    /// Frame number since the last (re)boot.
    pub boot_frame: u64,
    /// The app's state after the frame.
    pub state: State,
    /// Pose the app commanded, rad.
    pub commanded: [f32; 3],
    /// Pulses in the servo outputs after the frame.
    /// Timer5 ticks of 0.5 µs.
    pub pulses: Option<[u16; 3]>,
    /// Servo shaft angles at the end of the period, rad.
    pub servo: [f64; 3],
    /// The gripper angle the app commanded, rad.
    pub grip_commanded: f32,
    /// The gripper's pulse after the frame, ticks.
    pub grip_pulse: Option<u16>,
    /// The gripper's shaft angle at the end of the period, rad.
    pub grip_servo: f64,
}

/// The app running on the host twin, frame by frame: the app and every simulated part it talks to through the seam traits, with a record of each frame.
pub struct Sim {
    /// What the simulation was started from (kept for reboots).
    pub setup: SimSetup,
    /// The app under test.
    pub app: App,
    /// The touch panel the app reads.
    pub panel: SimPanel,
    /// The servos the app drives.
    pub servos: SimServos,
    /// The clock, one frame per step.
    pub clock: SimClock,
    /// The EEPROM the app's settings live in (survives reboots).
    pub eeprom: SimEeprom,
    /// The serial port: what tests send and what the app printed.
    pub serial: SimSerial,
    /// One record per frame run.
    pub history: Vec<FrameRecord>,
    /// The screen, redrawn after every frame when the app runs one
    /// (`AppParams::screen`), as the firmware does.
    pub display: Option<Framebuffer>,
    /// The assistive switch: closed (`true`) or open, sampled by every
    /// frame as the firmware samples D22.
    pub switch: bool,
    frames: u64,
    boot_frames: u64,
}

impl Sim {
    /// Boots the app from `setup`: parts at power-up, no frame run yet; `Err` if the app refuses the parameters.
    pub fn new(setup: &SimSetup) -> Result<Sim, String> {
        let app = App::new(&setup.params).map_err(|e| format!("app parameters: {e:?}"))?;
        Ok(Sim {
            setup: setup.clone(),
            app,
            panel: SimPanel::new(setup.seed),
            servos: SimServos::new(&setup.servo_cals, &setup.servo_model, &setup.servo_initial),
            clock: SimClock::default(),
            eeprom: SimEeprom::new(),
            serial: SimSerial::default(),
            history: Vec::new(),
            display: setup.params.screen.then(Framebuffer::landscape),
            switch: false,
            frames: 0,
            boot_frames: 0,
        })
    }

    /// Frames run so far.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// One PWM period: the app's frame, then 20 ms of servo motion.
    pub fn step(&mut self) {
        self.serial.advance_frame();
        // The frame's panel read starts at the frame's start; its
        // conversions follow each other by `panel::CONVERSION_S`.
        self.panel.set_time(self.time_s());
        let mut io = Io {
            panel: &mut self.panel,
            servos: &mut self.servos,
            clock: &self.clock,
            storage: &mut self.eeprom,
            serial: &mut self.serial,
        };
        self.app.set_switch(self.switch);
        self.app.frame(&mut io);
        if let Some(fb) = &mut self.display {
            let _ = self.app.draw_screen(fb);
        }
        self.servos.advance(FRAME_MS as f64 * 1e-3);
        let st = self.app.status();
        self.history.push(FrameRecord {
            frame: self.frames,
            boot_frame: self.boot_frames,
            state: st.state,
            commanded: st.commanded,
            pulses: self.servos.pulses(),
            servo: self.servos.angles(),
            grip_commanded: st.grip,
            grip_pulse: self.servos.grip_pulse(),
            grip_servo: self.servos.grip_angle(),
        });
        self.frames += 1;
        self.boot_frames += 1;
        self.clock.ms = self.clock.ms.wrapping_add(FRAME_MS);
    }

    /// Simulated time since the simulation started (reboots included), s:
    /// the start of the next frame.
    pub fn time_s(&self) -> f64 {
        self.frames as f64 * f64::from(FRAME_MS) * 1e-3
    }

    /// Plays a finger script from the next frame on (its t_ms = 0 at
    /// [`Sim::time_s`]).
    pub fn finger(&mut self, script: crate::finger::FingerScript) {
        let t = self.time_s();
        self.panel.set_finger(script, t);
    }

    /// Runs `n` frames.
    pub fn run_frames(&mut self, n: u64) {
        for _ in 0..n {
            self.step();
        }
    }

    /// Runs whole frames covering `ms` (rounded up).
    pub fn run_ms(&mut self, ms: u64) {
        self.run_frames(ms.div_ceil(FRAME_MS as u64));
    }

    /// Sends `line` and a newline over the serial port, as a host would.
    pub fn send_line(&mut self, line: &str) {
        self.serial.send(line.as_bytes());
        self.serial.send(b"\n");
    }

    /// Power cycle: power returns to the EEPROM, the servos lose their pulses
    /// but keep their shafts, the clock restarts and a fresh app boots.
    pub fn reboot(&mut self) -> Result<(), String> {
        self.app = App::new(&self.setup.params).map_err(|e| format!("app parameters: {e:?}"))?;
        self.eeprom.restore_power();
        self.servos.power_cycle();
        self.serial.reset();
        self.clock.ms = 0;
        self.boot_frames = 0;
        Ok(())
    }

    /// End effector of the servos' shaft angles (f64 FK with the app's links).
    pub fn effector(&self) -> Result<Effector, String> {
        Ok(effector(&self.links()?, &self.servos.angles()))
    }

    /// The app's links now (the running configuration's, in the map's arm
    /// unit), in f64.
    pub fn links(&self) -> Result<Links<f64>, String> {
        let l = &self.app.geometry().links;
        Links::new(f64::from(l.l2()), f64::from(l.l3())).map_err(|e| format!("links: {e:?}"))
    }
}
