//! `armsim`: the touch-arm method on a PC, in f64, with no hardware. It replaces
//! the source papers' MATLAB GUI: map a touch, solve the IK, evaluate and plot
//! the ζ-a-tₛ, via-point and classic trajectories. See `armsim <cmd> --help`.

use std::process::ExitCode;

use armsim::cli::{run, Cli};

fn main() -> ExitCode {
    let cli: Cli = match armsim::args::parse("armsim") {
        Ok(cli) => cli,
        Err(code) => return code,
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
