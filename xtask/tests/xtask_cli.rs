//! `cargo xtask`'s subcommands: `elf-check` runs every check of
//! `elf::checks::CHECKS` on each ELF given and fails on an ELF it cannot
//! read; a bad argument is one line and exit code 2 like the other tools.
//! Needs the product firmware (`cargo avr`).

use std::process::Command;

use touch_arm_rig::firmware;
use xtask::elf::checks::CHECKS;

fn xtask(args: &[&str]) -> (Option<i32>, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_xtask")).args(args).output().expect("run xtask");
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    (out.status.code(), text(&out.stdout), text(&out.stderr))
}

#[test]
fn elf_check_runs_every_check_on_the_product_firmware() {
    let elf = firmware::default_elf();
    let (code, out, err) = xtask(&["elf-check", elf.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{out}{err}");
    // One line per check, in the list's order, each passed.
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), CHECKS.len(), "{out}");
    for (line, check) in lines.iter().zip(CHECKS) {
        assert!(line.starts_with(&format!("ok   touch-arm: {}: ", check.name)), "{line}");
    }
    // The product's static RAM is part of its budget line.
    assert!(lines[0].contains("static RAM"), "{}", lines[0]);
}

/// `--chains` adds the stack bound's chains under its line: each frame on
/// the way from `main` down, indented, and the deepest total last.
#[test]
fn elf_check_chains_prints_the_deepest_path_of_a_passing_bound() {
    let elf = firmware::default_elf();
    let (code, out, err) = xtask(&["elf-check", "--chains", elf.to_str().unwrap()]);
    assert_eq!(code, Some(0), "{out}{err}");
    let lines: Vec<&str> = out.lines().collect();
    let at = lines.iter().position(|l| l.starts_with("ok   touch-arm: stack-bound: ")).expect(&out);
    let bound: u32 = lines[at].split("stack bound ").nth(1).and_then(|r| r.split(' ').next()).unwrap().parse().unwrap();
    let chain = &lines[at + 1..];
    assert!(chain[0].starts_with(&format!("    stack bound {bound} B: thread ")), "{out}");
    assert!(chain.iter().any(|l| l.contains(" main (")), "{out}");
    assert!(chain.iter().all(|l| l.starts_with("    ")), "{out}");
    // Without the flag, one line per check.
    let (_, plain, _) = xtask(&["elf-check", elf.to_str().unwrap()]);
    assert_eq!(plain.lines().count(), CHECKS.len());
}

#[test]
fn elf_check_fails_on_a_missing_elf_and_bad_arguments_are_one_line() {
    let (code, _, err) = xtask(&["elf-check", "/nonexistent/touch-arm.elf"]);
    assert_eq!(code, Some(1), "{err}");
    assert!(err.contains("build the firmware first"), "{err}");
    let (code, out, err) = xtask(&["frobnicate"]);
    assert_eq!(code, Some(2), "{out}{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.starts_with("xtask: "), "{err}");
}
