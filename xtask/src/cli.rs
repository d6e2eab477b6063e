//! The repository tools' command lines: `cargo xtask <command>` (the `xtask`
//! binary) and the two stand-alone binaries scripts/bench.sh runs
//! (`avr-run`, `bench-report`), which take the same arguments as their
//! subcommands. A new tool is one more [`Command`] variant and its function.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use touch_arm_rig::firmware;

use crate::bench_report::{render, BenchOutput, Budgets, Inputs, Sizes, UiOutput};
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
    BenchReport(BenchReportArgs),
    /// Runs an AVR ELF in simavr until it prints `done`.
    AvrRun(AvrRunArgs),
}

/// Runs the tool `cmd` names; its exit code.
pub fn run(cmd: &Command) -> ExitCode {
    match cmd {
        Command::ElfCheck(a) => elf_check(a),
        Command::BenchReport(a) => report(bench_report(a), "bench-report"),
        Command::AvrRun(a) => avr_run(a),
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

/// The firmware ELFs to check.
#[derive(Args, Debug)]
pub struct ElfCheckArgs {
    /// ELF files [default: every firmware and example `cargo avr` and
    /// `cargo avr-mipidsi` build].
    pub elfs: Vec<PathBuf>,
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
        let fw = elf::checks::Firmware { name, image: &image, budgets: &budgets };
        for check in elf::checks::CHECKS {
            match (check.run)(&fw) {
                Ok(summary) => println!("ok   {name}: {}: {summary}", check.name),
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

/// Writes BENCHMARKS.md from a bench run's output.
#[derive(Parser, Debug)]
#[command(name = "bench-report")]
pub struct BenchReportArgs {
    /// The bench firmware's UART output (`avr-run bench.elf`).
    #[arg(long)]
    pub bench_output: PathBuf,
    /// The `ui_firmware` and `firmware_e2e stack_stays_within_budget` test
    /// output (`--nocapture`): draw times, bus speed, stacks.
    #[arg(long)]
    pub ui_output: PathBuf,
    /// The product firmware [default: target/avr-none/release/touch-arm.elf, or TOUCH_ARM_ELF].
    #[arg(long)]
    pub firmware: Option<PathBuf>,
    /// The bench firmware [default: target/avr-none/release/bench.elf, or TOUCH_ARM_BENCH_ELF].
    #[arg(long)]
    pub bench_elf: Option<PathBuf>,
    /// Where to write.
    #[arg(long, short, default_value = "BENCHMARKS.md")]
    pub out: PathBuf,
}

fn read(path: &Path) -> Result<String, String> {
    std::fs::read(path)
        .map(|b| String::from_utf8_lossy(&b).into_owned())
        .map_err(|e| format!("{}: {e}", path.display()))
}

/// Reads the bench run's outputs, the two ELFs' section sizes and memory.x's
/// budgets, and writes the document to `args.out`.
pub fn bench_report(args: &BenchReportArgs) -> Result<(), String> {
    let memory_x = read(&firmware::workspace_root().join("memory.x"))?;
    let inputs = Inputs {
        bench: BenchOutput::parse(&read(&args.bench_output)?),
        ui: UiOutput::parse(&read(&args.ui_output)?),
        product: Sizes(firmware::section_sizes(&args.firmware.clone().unwrap_or_else(firmware::default_elf))?),
        bench_elf: Sizes(firmware::section_sizes(&args.bench_elf.clone().unwrap_or_else(firmware::bench_elf))?),
        budgets: Budgets::parse(&memory_x)?,
    };
    let text = render(&inputs)?;
    std::fs::write(&args.out, text).map_err(|e| format!("{}: {e}", args.out.display()))?;
    println!("wrote {}", args.out.display());
    Ok(())
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
