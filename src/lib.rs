//! touch-arm core: pure, `no_std` logic shared by the ATmega2560 firmware (f32)
//! and the desktop tool `armsim` (f64).
#![no_std]

pub mod laws;
pub mod motion;
pub mod plan;
pub mod real;
pub mod via;
pub mod zat;
