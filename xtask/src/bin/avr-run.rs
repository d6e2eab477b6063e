//! Runs an AVR ELF in the simavr harness until it prints `done` and writes
//! its UART output to stdout (used by scripts/bench.sh; also `cargo xtask
//! avr-run`).

use std::process::ExitCode;

use xtask::cli::{avr_run, AvrRunArgs};

fn main() -> ExitCode {
    match armsim::args::parse::<AvrRunArgs>("avr-run") {
        Ok(args) => avr_run(&args),
        Err(code) => code,
    }
}
