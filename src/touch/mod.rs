//! The first stage of the pipeline: raw panel samples are filtered into one
//! confirmed press ([`filter`]) and mapped through the calibration to the
//! normalized workspace ([`map`]); which pins the panel is on is measured
//! ([`wiring`]).

pub mod contact;
pub mod filter;
pub mod map;
pub mod wiring;
