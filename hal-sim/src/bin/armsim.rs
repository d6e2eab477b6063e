//! `armsim`: the touch-arm method on a PC, in f64, with no hardware. It replaces
//! the source papers' MATLAB GUI: map a touch, solve the IK, evaluate and plot
//! the ζ-a-tₛ, via-point and classic trajectories. See `armsim <cmd> --help`.

use std::process::ExitCode;

use clap::Parser;
use hal_sim::armsim::{run, Cli};

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) if e.use_stderr() => {
            // One line naming the problem, as scripts expect (clap adds a usage
            // hint below it; `--help` has the full text).
            let text = e.render().to_string();
            let first = text.lines().next().unwrap_or("invalid arguments");
            eprintln!("armsim: {}", first.trim_start_matches("error: "));
            return ExitCode::from(2);
        }
        Err(e) => {
            let _ = e.print();
            return ExitCode::SUCCESS;
        }
    };
    match run(&cli) {
        Ok(out) => {
            print!("{out}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("armsim: {e}");
            ExitCode::from(2)
        }
    }
}
