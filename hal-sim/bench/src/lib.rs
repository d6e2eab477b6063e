//! touch-arm-bench: the main job (`touch-arm-sim`: one touch through the real
//! firmware under simavr, with its report and plots) and the live bench
//! (`touch-arm-live`: the firmware running in real time behind a browser
//! page, `live`); `shield` is the simulated shield both take by name.

#![deny(missing_docs)]

pub mod live;
pub mod shield;
