//! The post-link checks can fail: small C programs compiled and linked by
//! avr-gcc (the firmware's linker, with its avr6 script) into the very
//! mistakes the checks exist for, and the same programs linked correctly.
//! `tests/firmware_elf.rs` runs the checks on the firmware ELFs.

use std::path::{Path, PathBuf};
use std::process::Command;

use xtask::elf::code_pointers::{self, Kind, LPM_REACH, POINTER_REACH};
use xtask::elf::{stack_args, Image};

/// A function above 128 KiB reached through a pointer in data (a table:
/// `R_AVR_16_PM`) and one built in registers (`ldi` pair: `*_LDI_GS`).
const FAR_POINTERS: &str = r#"
typedef unsigned (*op_t)(unsigned);
__attribute__((noinline, section(".far_text"))) unsigned far_twice(unsigned x) { return 2 * x + 1; }
__attribute__((noinline)) unsigned near_inc(unsigned x) { return x + 1; }
op_t table[2] = { far_twice, near_inc };
volatile op_t sink;
int main(void) { sink = far_twice; return table[sink(1) & 1](3); }
"#;

/// 24 bytes of arguments: `e` and `f` go on the stack. `framed` reads
/// only its own locals.
const WIDE_ARGS: &str = r#"
__attribute__((noinline)) long wide(long a, long b, long c, long d, long e, long f) { return a + b + c + d + e + f; }
__attribute__((noinline)) long framed(long a, long b, long c, long d) {
    volatile long buf[4] = { a, b, c, d };
    return buf[0] + buf[1] + buf[2] + buf[3];
}
int main(void) { volatile long r = wide(1, 2, 3, 4, 5, 6) + framed(1, 2, 3, 4); return (int)r; }
"#;

/// 90 000 bytes of `.progmem` data (an object is at most 32 767 bytes on
/// the AVR): its end is past what `lpm` reads.
const BIG_PROGMEM: &str = r#"
#include <avr/pgmspace.h>
const char a[30000] PROGMEM = { 1 }, b[30000] PROGMEM = { 2 }, c[30000] PROGMEM = { 3 };
int main(void) { return pgm_read_byte(&a[1]) + pgm_read_byte(&b[1]) + pgm_read_byte(&c[1]); }
"#;

/// Compiles and links `source` with avr-gcc for the ATmega2560 and returns
/// the ELF's bytes.
fn link(name: &str, source: &str, extra: &[&str]) -> Vec<u8> {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("elf-fixtures");
    std::fs::create_dir_all(&dir).unwrap();
    let c = dir.join(format!("{name}.c"));
    let elf = dir.join(format!("{name}.elf"));
    std::fs::write(&c, source).unwrap();
    let out = Command::new("avr-gcc")
        .args(["-mmcu=atmega2560", "-Os", "-Wl,--section-start=.far_text=0x20000"])
        .args(extra)
        .arg(&c)
        .arg("-o")
        .arg(&elf)
        .output()
        .expect("avr-gcc (gcc-avr; scripts/setup.sh installs it)");
    assert!(out.status.success(), "avr-gcc {name}: {}", String::from_utf8_lossy(&out.stderr));
    read(&elf)
}

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap()
}

fn function(image: &Image, name: &str) -> u64 {
    image.functions().into_iter().find(|f| f.name == name).unwrap().address
}

#[test]
fn far_pointers_pass_through_trampolines() {
    let bytes = link("far_stubs", FAR_POINTERS, &["-Wl,--emit-relocs"]);
    let image = Image::parse(&bytes).unwrap();
    let far = function(&image, "far_twice");
    let near = function(&image, "near_inc");
    assert!(far >= POINTER_REACH && near < POINTER_REACH);
    let report = code_pointers::check(&image);
    assert!(report.problems.is_empty(), "{:#?}", report.problems);
    let stub = report.trampolines.iter().find(|t| t.to == far).expect("a trampoline to far_twice").at;
    let sites: Vec<(Kind, u64, Option<u64>)> = report.sites.iter().map(|s| (s.kind, s.target, s.via)).collect();
    for want in [
        (Kind::Pm16, far, Some(stub)),
        (Kind::Pm16, near, None),
        (Kind::Lo8Gs, far, Some(stub)),
        (Kind::Hi8Gs, far, Some(stub)),
        // avr-libc's start-up code: EIND = hh8(pm(__vectors)) = 0.
        (Kind::Hh8Pm, 0, None),
    ] {
        assert!(sites.contains(&want), "{want:?} not in {sites:?}");
    }
    assert_eq!(sites.len(), 5);
}

#[test]
fn a_link_without_stubs_fails_at_every_far_site() {
    let bytes = link("far_no_stubs", FAR_POINTERS, &["-Wl,--emit-relocs", "-Wl,--no-stubs"]);
    let image = Image::parse(&bytes).unwrap();
    let report = code_pointers::check(&image);
    assert!(report.trampolines.is_empty());
    // The table entry and both halves of the ldi pair hold the target's word
    // address cut to 16 bits (0x20000 / 2 → 0: the reset vector).
    assert_eq!(report.problems.len(), 3, "{:#?}", report.problems);
    for kind in ["R_AVR_16_PM", "R_AVR_LO8_LDI_GS", "R_AVR_HI8_LDI_GS"] {
        let p = report.problems.iter().find(|p| p.starts_with(kind)).unwrap();
        assert!(p.contains("target 0x20000") && p.contains("no trampoline jumps to it"), "{p}");
    }
    // The near entry of the table still checks out.
    assert_eq!(report.sites.iter().filter(|s| s.kind == Kind::Pm16).count(), 1);
}

#[test]
fn an_elf_without_relocations_is_refused() {
    let bytes = link("far_no_relocs", FAR_POINTERS, &[]);
    let report = code_pointers::check(&Image::parse(&bytes).unwrap());
    assert_eq!(report.problems, ["no relocations in the ELF: link with -Wl,--emit-relocs"]);
}

#[test]
fn progmem_past_64_kib_is_found() {
    let bytes = link("big_progmem", BIG_PROGMEM, &["-Wl,--emit-relocs"]);
    let image = Image::parse(&bytes).unwrap();
    let report = code_pointers::check(&image);
    let last = ["a", "b", "c"].map(|n| image.symbol(n).unwrap() + 30_000).into_iter().max().unwrap();
    assert!(report.progmem_end >= last && report.progmem_end > LPM_REACH, "{:#x}", report.progmem_end);
    assert_eq!(report.problems.len(), 1, "{:#?}", report.problems);
    assert!(report.problems[0].contains("`lpm`"), "{}", report.problems[0]);
}

#[test]
fn the_stack_argument_lint_finds_the_function_that_reads_them() {
    let bytes = link("wide_args", WIDE_ARGS, &[]);
    let image = Image::parse(&bytes).unwrap();
    let lint = stack_args::lint(&image);
    let found: Vec<(&str, i32)> = lint.offenders.iter().map(|o| (o.name.as_str(), o.reads)).collect();
    // `wide` saves 14 registers and has no locals: Y+1..Y+14 are its own,
    // Y+15..Y+17 the 3-byte return address, `e` starts at Y+18.
    assert_eq!(found, [("wide", 18)]);
    assert_eq!((lint.offenders[0].pushes, lint.offenders[0].frame), (14, 0));
    // `framed` has a frame pointer and 16 bytes of locals, and is not flagged.
    assert!(lint.with_frame_pointer >= 2, "{lint:?}");
}
