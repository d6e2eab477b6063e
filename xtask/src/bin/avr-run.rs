//! Runs an AVR ELF in the simavr harness until it prints `done` and writes
//! its UART output to stdout (used by scripts/bench.sh).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;

/// Runs an AVR ELF (ATmega2560 at 16 MHz) in simavr until it prints `done`,
/// then writes its UART output to stdout.
#[derive(Parser, Debug)]
#[command(name = "avr-run", allow_negative_numbers = true)]
struct Args {
    /// The firmware ELF
    elf: PathBuf,
    /// Simulated time limit in seconds
    #[arg(default_value_t = 300.0, value_parser = positive_seconds)]
    max_seconds: f64,
}

fn positive_seconds(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v > 0.0 && v.is_finite() => Ok(v),
        _ => Err("MAX_SECONDS must be a positive number".into()),
    }
}

fn main() -> ExitCode {
    let args: Args = match armsim::args::parse("avr-run") {
        Ok(a) => a,
        Err(code) => return code,
    };
    match touch_arm_rig::firmware::run_to_done(&args.elf, args.max_seconds) {
        Ok(text) => {
            print!("{text}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("avr-run: {e}");
            ExitCode::FAILURE
        }
    }
}
