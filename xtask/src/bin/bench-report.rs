//! `bench-report`: writes BENCHMARKS.md from one bench run. `scripts/bench.sh`
//! runs the bench firmware and the display and stack tests in simavr, keeps
//! their output and calls this (also `cargo xtask bench-report`); the figures
//! and the document come from `xtask::bench_report` (`command` reads the
//! arguments).

use std::process::ExitCode;

use clap::Parser;
use xtask::bench_report::command::{run, Args};

fn main() -> ExitCode {
    match run(&Args::parse()) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("bench-report: {e}");
            ExitCode::FAILURE
        }
    }
}
