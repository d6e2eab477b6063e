//! Independent f64 references for the touch-arm method (docs/method.md): the
//! oracle that the core crate's tests, the host crates' tests and the benchmark
//! report (`xtask::bench_report`) compare the crate's results with.
//!
//! Each reference is the documented formula written the plain way, in f64,
//! with none of the crate's evaluation tricks (shared factors, integer cores,
//! split roots). This crate depends on nothing, and in particular not on
//! `touch-arm`, so it cannot end up checking the code with itself.

pub mod zat;
