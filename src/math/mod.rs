//! Numbers: the [`real::Real`] trait that lets the same algorithms run in f32
//! on the chip and f64 on the host, and the integer-core elementary functions
//! (exp/ln, atan2, split square root) that make f32 fast on the AVR and
//! bit-identical on both; and the angle units (`units`: radians inside,
//! degrees and hundredths of a degree at the edges).
//!
//! Dependency order inside: `fixed` ← `exp`, `atan` ← `real` ← `sqrt_split`,
//! `units`.

pub mod atan;
pub mod exp;
pub mod fixed;
pub mod real;
pub mod sqrt_split;
pub mod units;
