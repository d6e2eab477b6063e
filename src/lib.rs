//! touch-arm core: pure, `no_std` logic shared by the ATmega2560 firmware (f32)
//! and the desktop tool `armsim` (f64).
#![no_std]
// The UI font is read from flash with `lpm` (ui::font).
#![cfg_attr(target_arch = "avr", feature(asm_experimental_arch))]

#[cfg(target_arch = "avr")]
pub mod board;
pub mod command;
pub mod config_store;
pub mod crc;
pub mod ik;
pub mod laws;
pub mod motion;
pub mod plan;
pub mod pose;
pub mod real;
pub mod seam;
pub mod servo;
pub mod touch_filter;
pub mod touch_map;
pub mod ui;
pub mod via;
pub mod workspace;
pub mod zat;
