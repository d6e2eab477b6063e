//! The first stage of the pipeline: raw panel samples are filtered into one
//! confirmed press ([`filter`]) and mapped through the calibration to the
//! normalized workspace ([`map`]); which pins the panel is on is measured
//! ([`wiring`]). The assistive switch, the other way in, is debounced by
//! the same rules ([`switch`]).

pub mod contact;
pub mod filter;
pub mod map;
pub mod switch;
pub mod wiring;
