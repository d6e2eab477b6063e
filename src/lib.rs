//! touch-arm core: pure, `no_std` logic shared by the ATmega2560 firmware (f32)
//! and the desktop tool `armsim` (f64).
#![no_std]
// f32_exp's 16×16 multiply is inline assembly on the chip.
#![cfg_attr(target_arch = "avr", feature(asm_experimental_arch))]
// The board layer's interrupt handlers use the AVR interrupt calling convention.
#![cfg_attr(target_arch = "avr", feature(abi_avr_interrupt))]

// First, so `t!` is in scope in every module below.
#[macro_use]
pub mod text;

pub mod app;
#[cfg(target_arch = "avr")]
pub mod board;
pub mod command;
pub mod config_store;
pub mod crc;
pub mod f32_atan;
pub mod f32_exp;
pub mod ik;
pub mod laws;
pub mod motion;
pub mod peak_rate;
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
