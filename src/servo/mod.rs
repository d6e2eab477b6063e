//! The last stage before the hardware: joint angles to pulse widths under each
//! joint's calibration and limits ([`map`]), and the per-frame integer track
//! that turns a planned move into pulses ([`track`], the 50 Hz hot path).

pub mod map;
pub mod track;
