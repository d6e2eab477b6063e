//! `cargo xtask <command>`: the repository's tooling (`cargo xtask --help`
//! lists the commands; the alias is in `.cargo/config.toml`).

use std::process::ExitCode;

use xtask::cli::{run, Xtask};

fn main() -> ExitCode {
    match armsim::args::parse::<Xtask>("xtask") {
        Ok(x) => run(&x.command),
        Err(code) => code,
    }
}
