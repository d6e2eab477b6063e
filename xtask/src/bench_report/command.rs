//! `bench-report`: writes BENCHMARKS.md from one bench run. `scripts/bench.sh`
//! runs the bench firmware and the display and stack tests in simavr, keeps
//! their output and calls this (the `bench-report` binary, or `cargo xtask
//! bench-report`); the figures and the document come from `bench_report`.

use clap::Parser;
use std::path::{Path, PathBuf};
use touch_arm_rig::firmware;

use super::stack_bounds::StackBoundRow;
use super::{flash_map, render, BenchOutput, Budgets, Inputs, Sizes, UiOutput};
use crate::elf::Image;

/// Writes BENCHMARKS.md from a bench run's output.
#[derive(Parser, Debug)]
#[command(name = "bench-report")]
pub struct Args {
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
pub fn run(args: &Args) -> Result<(), String> {
    let memory_x = read(&firmware::workspace_root().join("memory.x"))?;
    let inputs = Inputs {
        bench: BenchOutput::parse(&read(&args.bench_output)?),
        ui: UiOutput::parse(&read(&args.ui_output)?),
        product: Sizes(firmware::section_sizes(&args.firmware.clone().unwrap_or_else(firmware::default_elf))?),
        bench_elf: Sizes(firmware::section_sizes(&args.bench_elf.clone().unwrap_or_else(firmware::bench_elf))?),
        budgets: Budgets::parse(&memory_x)?,
        stack_bounds: Vec::new(),
        flash_map: None,
    };
    let mut inputs = inputs;
    let product = args.firmware.clone().unwrap_or_else(firmware::default_elf);
    let bench = args.bench_elf.clone().unwrap_or_else(firmware::bench_elf);
    // Every ELF `cargo avr` builds (the product and the bench as given);
    // one not built (`mipidsi-fill` needs `cargo avr-mipidsi`) is left out.
    for (name, elf) in firmware::all_elfs() {
        let elf = match name {
            "touch-arm" => product.clone(),
            "bench" => bench.clone(),
            _ => elf,
        };
        if let Ok(bytes) = std::fs::read(&elf) {
            inputs.stack_bounds.push(StackBoundRow::of(name, &bytes));
        }
    }
    let bytes = std::fs::read(&product).map_err(|e| format!("{}: {e}", product.display()))?;
    inputs.flash_map = Some(flash_map::of(&Image::parse(&bytes)?));
    let text = render(&inputs)?;
    std::fs::write(&args.out, text).map_err(|e| format!("{}: {e}", args.out.display()))?;
    println!("wrote {}", args.out.display());
    Ok(())
}
