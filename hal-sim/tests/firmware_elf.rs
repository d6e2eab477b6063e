//! Gates on the firmware ELF itself: the memory budgets stated in `memory.x`
//! and the stack-argument lint (LLVM miscompiles stack-passed arguments on the
//! ATmega2560). The ELF is built by `scripts/test.sh` (`cargo avr`) before
//! `cargo test` runs.

use std::path::{Path, PathBuf};
use std::process::Command;

use hal_sim::firmware;

fn root() -> PathBuf {
    firmware::workspace_root()
}

fn firmware_elf() -> PathBuf {
    let elf = firmware::default_elf();
    assert!(
        elf.exists(),
        "{} missing: build the firmware first with `cargo avr` (scripts/test.sh does)",
        elf.display()
    );
    elf
}

fn budget(name: &str) -> u64 {
    firmware::budget(name).unwrap()
}

/// Section sizes from `avr-size -A`.
fn sections(elf: &Path) -> Vec<(String, u64)> {
    firmware::section_sizes(elf).unwrap()
}

fn size_of(s: &[(String, u64)], name: &str) -> u64 {
    s.iter().find(|(n, _)| n == name).map_or(0, |(_, v)| *v)
}

#[test]
fn memory_x_states_the_budgets() {
    assert_eq!(budget("flash"), 120 * 1024);
    assert_eq!(budget("static_ram"), 2048);
    assert_eq!(budget("stack"), 2048);
}

#[test]
fn firmware_fits_flash_and_static_ram_budgets() {
    let s = sections(&firmware_elf());
    let text = size_of(&s, ".text");
    let data = size_of(&s, ".data");
    let bss = size_of(&s, ".bss");
    assert!(text > 0, "no .text in the ELF");
    let flash = text + data;
    let ram = data + bss;
    eprintln!(
        "firmware: flash {flash} B (budget {}), static RAM {ram} B (budget {})",
        budget("flash"),
        budget("static_ram")
    );
    assert!(flash <= budget("flash"), "flash {flash} B exceeds the memory.x budget {}", budget("flash"));
    assert!(ram <= budget("static_ram"), "static RAM {ram} B exceeds the memory.x budget {}", budget("static_ram"));
}

#[test]
fn firmware_has_no_function_reading_stack_passed_arguments() {
    let lint = root().join("../shared/tools/stackarg_lint.py");
    assert!(lint.exists(), "{} missing (shared/ must sit beside the checkout)", lint.display());
    let out = Command::new("python3").arg(&lint).arg(firmware_elf()).output().expect("python3");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success() && text.contains("0 function(s)"),
        "stack-argument lint failed:\n{text}{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// Function pointers on the ATmega2560 are 16-bit word addresses: code past
/// the first 128 KiB is reached only through EIND and linker trampolines,
/// which this project does not rely on. The product has its tighter budget
/// above; the bench firmware
/// (many more routines) must stay below this line too, or its figures would
/// come from a binary that cannot be trusted.
#[test]
fn bench_firmware_stays_below_128_kib() {
    let elf = firmware::bench_elf();
    assert!(elf.exists(), "{} missing: build it first with `cargo avr`", elf.display());
    let s = sections(&elf);
    let flash = size_of(&s, ".text") + size_of(&s, ".data");
    eprintln!("bench firmware: flash {flash} B");
    assert!(
        flash <= 128 * 1024,
        "bench firmware flash {flash} B is past the 128 KiB that 16-bit function pointers reach"
    );
}
