//! The repository tools' command lines: `cargo xtask <command>` (the `xtask`
//! binary) and the two stand-alone binaries scripts/bench.sh runs
//! (`avr-run`; `bench-report`, whose arguments and body are
//! `bench_report::command`), which take the same arguments as their
//! subcommands. A new tool is one more [`Command`] variant and its function.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use touch_arm_rig::firmware;

use crate::bench_report::command as bench_report;
use crate::bench_report::Budgets;
use crate::elf;

/// `cargo xtask`: the touch-arm repository's tooling.
#[derive(Parser, Debug)]
#[command(name = "xtask")]
pub struct Xtask {
    /// The tool to run.
    #[command(subcommand)]
    pub command: Command,
}

/// One tool of the repository.
#[derive(Subcommand, Debug)]
pub enum Command {
    /// The post-link checks on firmware ELFs (memory budgets, code pointers,
    /// stack-passed arguments); exits 1 if any check fails.
    ElfCheck(ElfCheckArgs),
    /// Writes BENCHMARKS.md from one bench run (scripts/bench.sh).
    BenchReport(bench_report::Args),
    /// Runs an AVR ELF in simavr until it prints `done`.
    AvrRun(AvrRunArgs),
    /// Builds the firmware and writes it as Intel HEX (`cargo avr-hex`):
    /// target/avr-none/release/touch-arm.hex, for avrdude or any uploader.
    AvrHex(AvrHexArgs),
    /// Prints BENCHMARKS.md's section on the time-optimal reference, which
    /// the host computes alone (no bench run).
    BenchOptimal,
}

/// Runs the tool `cmd` names; its exit code.
pub fn run(cmd: &Command) -> ExitCode {
    match cmd {
        Command::ElfCheck(a) => elf_check(a),
        Command::BenchReport(a) => report(bench_report::run(a), "bench-report"),
        Command::AvrRun(a) => avr_run(a),
        Command::AvrHex(a) => report(avr_hex(a), "avr-hex"),
        Command::BenchOptimal => {
            report(crate::bench_report::optimal::section().map(|s| print!("{s}")), "bench-optimal")
        }
    }
}

/// Prints `Err` as `prog: message` and turns the result into an exit code.
fn report(r: Result<(), String>, prog: &str) -> ExitCode {
    match r {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("{prog}: {e}");
            ExitCode::FAILURE
        }
    }
}

/// `cargo avr-hex`'s arguments.
#[derive(Args, Debug)]
pub struct AvrHexArgs {
    /// The ELF to convert, as it is (no build) [default: build the firmware
    /// (the `touch-arm` binary, release, avr-none) and convert
    /// target/avr-none/release/touch-arm.elf]
    #[arg(long, value_name = "FILE")]
    pub elf: Option<PathBuf>,
    /// Where to write [default: the ELF's path with `.hex`]
    #[arg(long, value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// Builds (unless `--elf`) and writes the Intel HEX; prints where and how
/// many bytes.
pub fn avr_hex(args: &AvrHexArgs) -> Result<(), String> {
    let elf = match &args.elf {
        Some(p) => p.clone(),
        None => {
            // The product binary only, as `cargo avr` builds it.
            let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
            let status = std::process::Command::new(cargo)
                .current_dir(firmware::workspace_root())
                .args(["build", "--release", "--target", "avr-none", "-Z", "build-std=core"])
                .args(["--features", "firmware", "-p", "touch-arm", "--bin", "touch-arm"])
                .status()
                .map_err(|e| format!("cargo: {e}"))?;
            if !status.success() {
                return Err("building the firmware failed".into());
            }
            firmware::default_elf()
        }
    };
    let bytes = std::fs::read(&elf).map_err(|e| format!("{}: {e}", elf.display()))?;
    let image = elf::Image::parse(&bytes).map_err(|e| format!("{}: {e}", elf.display()))?;
    let segments = crate::hex::flash_segments(&image)?;
    let out = args.out.clone().unwrap_or_else(|| elf.with_extension("hex"));
    std::fs::write(&out, crate::hex::encode(&segments)).map_err(|e| format!("{}: {e}", out.display()))?;
    let total: usize = segments.iter().map(|(_, b)| b.len()).sum();
    println!("avr-hex: wrote {} ({total} bytes of flash)", out.display());
    Ok(())
}

/// The firmware ELFs to check.
#[derive(Args, Debug)]
pub struct ElfCheckArgs {
    /// ELF files [default: every firmware and example `cargo avr` and
    /// `cargo avr-mipidsi` build].
    pub elfs: Vec<PathBuf>,
    /// Print each ELF's deepest stack chains (thread and interrupts, every
    /// function's frame on the way) also when its bound is within budget:
    /// where to cut when the bound grows.
    #[arg(long)]
    pub chains: bool,
}

/// Runs every check of [`elf::checks::CHECKS`] on each ELF, one line per
/// check and firmware; 1 if any check failed or an ELF could not be read.
pub fn elf_check(args: &ElfCheckArgs) -> ExitCode {
    let budgets = match std::fs::read_to_string(firmware::workspace_root().join("memory.x"))
        .map_err(|e| format!("memory.x: {e}"))
        .and_then(|text| Budgets::parse(&text))
    {
        Ok(b) => b,
        Err(e) => {
            eprintln!("elf-check: {e}");
            return ExitCode::FAILURE;
        }
    };
    let elfs: Vec<(String, PathBuf)> = if args.elfs.is_empty() {
        firmware::all_elfs().into_iter().map(|(n, p)| (n.to_string(), p)).collect()
    } else {
        args.elfs.iter().map(|p| (elf_name(p), p.clone())).collect()
    };
    let mut failed = false;
    for (name, path) in &elfs {
        let bytes = match std::fs::read(path) {
            Ok(b) => b,
            Err(e) => {
                eprintln!("elf-check: {}: {e}: build the firmware first with `cargo avr`", path.display());
                failed = true;
                continue;
            }
        };
        let image = match elf::Image::parse(&bytes) {
            Ok(i) => i,
            Err(e) => {
                eprintln!("elf-check: {}: {e}", path.display());
                failed = true;
                continue;
            }
        };
        let fw = elf::checks::Firmware { name, image: &image, budgets: &budgets, chains: args.chains };
        for check in elf::checks::CHECKS {
            match (check.run)(&fw) {
                Ok(summary) => {
                    let mut lines = summary.lines();
                    println!("ok   {name}: {}: {}", check.name, lines.next().unwrap_or(""));
                    for l in lines {
                        println!("    {l}");
                    }
                }
                Err(problems) => {
                    failed = true;
                    println!("FAIL {name}: {}:", check.name);
                    for p in problems.lines() {
                        println!("    {p}");
                    }
                }
            }
        }
    }
    if failed {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    }
}

/// An ELF's firmware name, as `all_elfs` names them: the file stem.
fn elf_name(path: &Path) -> String {
    path.file_stem().map_or_else(|| path.display().to_string(), |s| s.to_string_lossy().into_owned())
}

/// Runs an AVR ELF (ATmega2560 at 16 MHz) in simavr until it prints `done`,
/// then writes its UART output to stdout.
#[derive(Parser, Debug)]
#[command(name = "avr-run", allow_negative_numbers = true)]
pub struct AvrRunArgs {
    /// The firmware ELF
    pub elf: PathBuf,
    /// Simulated time limit in seconds
    #[arg(default_value_t = 300.0, value_parser = positive_seconds)]
    pub max_seconds: f64,
}

fn positive_seconds(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v > 0.0 && v.is_finite() => Ok(v),
        _ => Err("MAX_SECONDS must be a positive number".into()),
    }
}

/// Runs the ELF and prints its output: 0 once it printed `done`, 1 if it
/// could not be loaded or ran out of time.
pub fn avr_run(args: &AvrRunArgs) -> ExitCode {
    match firmware::run_to_done(&args.elf, args.max_seconds) {
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
