//! Code above 128 KiB runs on the chip when called through a function pointer
//! and through a trait object: the `far-call` firmware (src/bin/far_call.rs,
//! built by `cargo avr`) places its two callees at 0x20000 and prints each
//! pointer it calls through and each result. Here simavr runs it; the
//! results must be the host's, the pointers must be the linker's trampolines
//! (16-bit word addresses in low flash) and those must jump to the callees.

use std::path::PathBuf;
use touch_arm_rig::firmware;
use xtask::elf::code_pointers::{self, Kind, POINTER_REACH};
use xtask::elf::Image;

/// The firmware's `far_mix`.
fn far_mix(x: u16) -> u16 {
    x.rotate_left(3) ^ 0x5a5a
}

/// The firmware's `Affine { mul: 7, add: 3 }.step`.
fn affine(x: u16) -> u16 {
    x.wrapping_mul(7).wrapping_add(3)
}

fn numbers(line: &str) -> Vec<u32> {
    line.split_whitespace().skip(1).map(|v| v.parse().unwrap()).collect()
}

#[test]
fn code_above_128_kib_runs_through_a_fn_pointer_and_a_dyn_call() {
    let elf = firmware::far_call_elf();
    let bytes = std::fs::read(&elf).unwrap_or_else(|e| panic!("{}: {e}: build it with `cargo avr`", elf.display()));
    let image = Image::parse(&bytes).unwrap();
    let function = |suffix: &str| {
        let f = image.functions().into_iter().find(|f| f.name.ends_with(suffix));
        f.unwrap_or_else(|| panic!("no function *{suffix} in far-call.elf")).address
    };
    let (mix_at, step_at) = (function("7far_mix"), function("4step"));
    assert!(mix_at >= POINTER_REACH && step_at >= POINTER_REACH, "callees at {mix_at:#x}, {step_at:#x}");

    let report = code_pointers::check(&image);
    assert!(report.problems.is_empty(), "{:#?}", report.problems);
    let trampoline_to = |target: u64| report.trampolines.iter().find(|t| t.to == target).map(|t| t.at);
    let (mix_stub, step_stub) = (trampoline_to(mix_at).unwrap(), trampoline_to(step_at).unwrap());
    assert!(mix_stub < POINTER_REACH && step_stub < POINTER_REACH);
    // The fn pointer is built by an `ldi` pair, the trait object's method
    // comes from its vtable (in .data): both through the trampolines.
    let via =
        |kind: Kind| report.sites.iter().filter(|s| s.kind == kind).map(|s| (s.target, s.via)).collect::<Vec<_>>();
    assert_eq!(via(Kind::Lo8Gs), [(mix_at, Some(mix_stub))]);
    assert_eq!(via(Kind::Hi8Gs), [(mix_at, Some(mix_stub))]);
    assert_eq!(via(Kind::Pm16), [(step_at, Some(step_stub))]);

    let out = firmware::run_to_done(&elf, 1.0).unwrap();
    let lines: Vec<&str> = out.lines().map(str::trim).collect();
    let fn_calls: Vec<Vec<u32>> = lines.iter().filter(|l| l.starts_with("fn ")).map(|l| numbers(l)).collect();
    let dyn_calls: Vec<Vec<u32>> = lines.iter().filter(|l| l.starts_with("dyn ")).map(|l| numbers(l)).collect();
    assert_eq!(fn_calls.len(), 2, "{out}");
    assert_eq!(dyn_calls.len(), 2, "{out}");
    for c in &fn_calls {
        let (pointer, x, y) = (c[0], c[1] as u16, c[2] as u16);
        assert_eq!(u64::from(pointer) * 2, mix_stub, "the fn pointer is the trampoline's word address");
        assert_eq!(y, far_mix(x), "far_mix({x:#x}) on the chip");
    }
    for c in &dyn_calls {
        let (x, y) = (c[0] as u16, c[1] as u16);
        assert_eq!(y, affine(x), "Affine::step({x:#x}) through the vtable on the chip");
    }
    eprintln!(
        "far_mix at {mix_at:#x} via trampoline {mix_stub:#x} (pointer word {:#x}); Affine::step at {step_at:#x} \
         via {step_stub:#x}",
        mix_stub / 2
    );
}

/// The same firmware as a link without stubs would leave it: the vtable
/// entry of `Affine::step` cut to 16 bits. The check names the site, and
/// on the chip the `dyn` call lands in the vector table instead (the run
/// never completes).
#[test]
fn a_pointer_cut_to_16_bits_fails_the_check_and_the_chip() {
    let elf = firmware::far_call_elf();
    let mut bytes = std::fs::read(&elf).unwrap();
    let (at, target, offset) = {
        let image = Image::parse(&bytes).unwrap();
        let report = code_pointers::check(&image);
        let site = report.sites.iter().find(|s| s.kind == Kind::Pm16).expect("the vtable entry").clone();
        (site.at, site.target, image.file_offset(site.at).unwrap() as usize)
    };
    let cut = ((target / 2) as u16).to_le_bytes();
    bytes[offset..offset + 2].copy_from_slice(&cut);

    let report = code_pointers::check(&Image::parse(&bytes).unwrap());
    assert_eq!(report.problems.len(), 1, "{:#?}", report.problems);
    let problem = &report.problems[0];
    assert!(problem.starts_with(&format!("R_AVR_16_PM at {at:#x}")), "{problem}");
    assert!(problem.contains("has a trampoline, but the site does not point to it"), "{problem}");

    let broken = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("far-call-cut.elf");
    std::fs::write(&broken, &bytes).unwrap();
    let run = firmware::run_to_done(&broken, 0.2);
    assert!(run.is_err(), "the cut pointer still ran to the end: {run:?}");
}
