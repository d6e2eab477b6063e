//! hal-sim: the host-side twin of the touch-arm hardware, the simavr harness
//! that runs the real firmware ELF, and the `armsim` desktop tool.

pub mod armsim;
pub mod avr;
pub mod bench_report;
pub mod cli;
pub mod display;
pub mod elf;
pub mod firmware;
pub mod lcd_bus;
pub mod live;
pub mod panel;
pub mod paper;
pub mod plot;
pub mod random_input;
pub mod report;
pub mod twin;
