//! Runs an AVR ELF in the simavr harness until it prints `done` and writes
//! its UART output to stdout (used by scripts/bench.sh).
//! usage: avr-run FILE.elf [MAX_SECONDS]

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let Some(elf) = args.next().map(PathBuf::from) else {
        eprintln!("usage: avr-run FILE.elf [MAX_SECONDS]");
        return ExitCode::from(2);
    };
    let max = match args.next().map(|s| s.parse::<f64>()) {
        None => 300.0,
        Some(Ok(s)) if s > 0.0 => s,
        Some(_) => {
            eprintln!("avr-run: MAX_SECONDS must be a positive number");
            return ExitCode::from(2);
        }
    };
    match hal_sim::firmware::run_to_done(&elf, max) {
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
