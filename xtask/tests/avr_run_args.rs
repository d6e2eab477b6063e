//! `avr-run`'s command line (the main job's is in the bench's tests): a bad
//! argument exits with code 2 and one line naming the problem, before any simulation.

use std::process::Command;

fn fails(bin: &str, args: &[&str], needle: &str) {
    let out = Command::new(bin).args(args).output().expect("run the tool");
    let name = bin.rsplit('/').next().unwrap();
    if let Err(e) = armsim::args::bad_argument_report(name, &out, needle) {
        panic!("{args:?}: {e}");
    }
}

#[test]
fn avr_run_rejects_bad_arguments_in_one_line() {
    let bin = env!("CARGO_BIN_EXE_avr-run");
    fails(bin, &[], "required arguments were not provided: <ELF>");
    fails(bin, &["x.elf", "-3"], "MAX_SECONDS must be a positive number");
    fails(bin, &["x.elf", "soon"], "MAX_SECONDS must be a positive number");
    fails(bin, &["x.elf", "1", "2"], "unexpected argument '2'");
    // A missing ELF is a failed run (1), not a bad argument.
    let out = Command::new(bin).args(["/nonexistent/touch-arm.elf", "1"]).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("build the firmware first"));
}
