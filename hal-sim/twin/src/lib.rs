//! The host twin of the touch-arm hardware: implementations of the seam
//! traits (`touch_arm::seam`) that behave like the real parts, a runner that
//! steps the app frame by frame, and the scenario-file interpreter; the
//! screen's framebuffer, the seeded random inputs and the host's f64
//! references of the firmware's chain. No simulator of the chip: the simavr
//! rig (`touch-arm-rig`) builds on this crate.

#![deny(missing_docs)]

pub mod arm;
pub mod devices;
pub mod display;
pub mod finger;
pub mod host;
pub mod panel;
pub mod random_input;
pub mod rng;
pub mod scenario;
pub mod servos;
pub mod sim;
pub mod touch_mc;
pub mod touches;

pub use devices::{SimClock, SimEeprom, SimSerial};
pub use panel::{Drive, PanelModel, PanelPins, Pin, SimPanel};
pub use servos::{ServoModel, SimServos};
pub use sim::{FrameRecord, Sim, SimSetup};
