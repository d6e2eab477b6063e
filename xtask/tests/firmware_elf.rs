//! Gates on the firmware ELFs themselves (`xtask::elf`): the memory budgets
//! stated in `memory.x`, every 16-bit code pointer reaching its target (code
//! above 128 KiB through a linker trampoline) with `lpm` data below 64 KiB,
//! no function reading stack-passed arguments (LLVM miscompiles those on
//! the ATmega2560), and no overflow-checking multiply helper (it crashes the
//! chip). The ELFs are built by `scripts/test.sh` (`cargo avr`)
//! before `cargo test` runs; `tests/elf_fixtures.rs` shows the pointer and
//! argument checks failing.

use std::path::Path;

use touch_arm_rig::firmware;
use xtask::elf::{code_pointers, stack_args, Image};

fn budget(name: &str) -> u64 {
    firmware::budget(name).unwrap()
}

fn read(elf: &Path) -> Vec<u8> {
    std::fs::read(elf).unwrap_or_else(|e| {
        panic!("{}: {e}: build the firmware first with `cargo avr` (scripts/test.sh does)", elf.display())
    })
}

/// Runs `f` on every firmware `cargo avr` builds.
fn each_firmware(mut f: impl FnMut(&str, &Image)) {
    for (name, elf) in firmware::all_elfs() {
        let bytes = read(&elf);
        f(name, &Image::parse(&bytes).unwrap());
    }
}

#[test]
fn memory_x_states_the_budgets() {
    // 256 KiB less the stock bootloader's 8 KiB at the top.
    assert_eq!(budget("flash"), 248 * 1024);
    assert_eq!(budget("static_ram"), 3584);
    assert_eq!(budget("stack"), 2048);
}

#[test]
fn firmware_fits_flash_and_static_ram_budgets() {
    each_firmware(|name, image| {
        let (end, bytes) = (image.flash_end(), image.flash_bytes());
        eprintln!("{name}: flash {bytes} B, ends at {end:#x} (budget {})", budget("flash"));
        assert!(bytes > 0, "{name}: nothing in flash");
        assert!(end <= budget("flash"), "{name}: flash ends at {end:#x}, past the memory.x budget {}", budget("flash"));
    });
    let bytes = read(&firmware::default_elf());
    let ram = Image::parse(&bytes).unwrap().static_ram();
    eprintln!("touch-arm: static RAM {ram} B (budget {})", budget("static_ram"));
    assert!(ram <= budget("static_ram"), "static RAM {ram} B exceeds the memory.x budget {}", budget("static_ram"));
}

#[test]
fn every_code_pointer_reaches_its_target_and_lpm_data_stays_low() {
    each_firmware(|name, image| {
        let r = code_pointers::check(image);
        eprintln!(
            "{name}: {} code-pointer sites ({} through trampolines), {} trampolines ending at {:#x}, \
             low flash (.progmem) ends at {:#x}",
            r.sites.len(),
            r.far_sites(),
            r.trampolines.len(),
            r.trampolines_end,
            r.progmem_end
        );
        assert!(r.problems.is_empty(), "{name}:\n{}", r.problems.join("\n"));
        // avr-libc's start-up code loads EIND from hh8(pm(__vectors)): the
        // check saw the relocations, and that one holds 0.
        assert_eq!(r.count(code_pointers::Kind::Hh8Pm), 1, "{name}");
    });
}

#[test]
fn firmware_has_no_function_reading_stack_passed_arguments() {
    each_firmware(|name, image| {
        let lint = stack_args::lint(image);
        eprintln!(
            "{name}: {} functions, {} with a frame pointer, {} read stack-passed arguments",
            lint.functions,
            lint.with_frame_pointer,
            lint.offenders.len()
        );
        assert!(lint.functions > 0, "{name}: no function symbols (stripped ELF?)");
        let offenders: Vec<String> = lint.offenders.iter().map(|o| o.to_string()).collect();
        assert!(offenders.is_empty(), "{name}:\n{}", offenders.join("\n"));
    });
}

/// compiler-builtins' overflow-checking multiplies (what `checked_mul` and
/// its kin call) crash the ATmega2560 (docs/avr-traps.md, trap 5): no
/// firmware links one. Tried: an `i32::checked_mul` on black-boxed values in
/// an example links `__mulosi4`, which this refuses.
#[test]
fn firmware_links_no_overflow_checking_multiply() {
    each_firmware(|name, image| {
        for helper in ["__mulosi4", "__mulodi4", "__muloti4"] {
            assert!(
                image.symbol(helper).is_none(),
                "{name} links {helper}: a checked multiply (checked_mul and its kin) crashes the chip"
            );
        }
    });
}
