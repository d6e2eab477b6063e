//! touch-arm core: pure, `no_std` logic shared by the ATmega2560 firmware (f32)
//! and the desktop tool `armsim` (f64).
//!
//! The modules follow the pipeline, lowest layer first; a module uses only
//! the ones above it in this list (`tests/layers.rs` enforces it):
//! [`text`], [`math`] → [`seam`] → [`touch`], [`geometry`] → [`motion`] →
//! [`servo`] → [`config`] → [`protocol`] → [`ui`] → [`app`] → `board` (AVR
//! only).
#![no_std]
#![cfg_attr(target_arch = "avr", feature(optimize_attribute))]
#![warn(missing_docs)]
// The fixed-point 16×16 multiply is inline assembly on the chip.
#![cfg_attr(target_arch = "avr", feature(asm_experimental_arch))]
// The board layer's interrupt handlers use the AVR interrupt calling convention.
#![cfg_attr(target_arch = "avr", feature(abi_avr_interrupt))]

// First, so `t!` is in scope in every module below.
#[macro_use]
pub mod text;

pub mod app;
#[cfg(target_arch = "avr")]
pub mod board;
pub mod config;
pub mod geometry;
pub mod math;
pub mod motion;
pub mod protocol;
pub mod seam;
pub mod servo;
pub mod touch;
pub mod ui;

/// The crate version (`version` and the boot line print it, through `t!`).
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
/// The git commit the crate was built from (`build.rs`: 12 hex digits,
/// `-dirty` when the tree differed, `unknown` without git).
pub const COMMIT: &str = env!("TOUCH_ARM_COMMIT");
