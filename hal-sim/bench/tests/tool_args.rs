//! The main job's command line (`armsim` and `avr-run` have their own tests):
//! a bad argument exits with code 2 and one line naming the problem, before any simulation.

use std::process::Command;

fn fails(bin: &str, args: &[&str], needle: &str) {
    let out = Command::new(bin).args(args).output().expect("run the tool");
    let name = bin.rsplit('/').next().unwrap();
    if let Err(e) = armsim::args::bad_argument_report(name, &out, needle) {
        panic!("{args:?}: {e}");
    }
}

#[test]
fn touch_arm_sim_rejects_bad_arguments_in_one_line() {
    let bin = env!("CARGO_BIN_EXE_touch-arm-sim");
    fails(bin, &["--raw", "1024,5"], "0..=1023");
    fails(bin, &["--raw", "12.5,5"], "0..=1023");
    fails(bin, &["--raw", "12"], "X,Y");
    fails(bin, &["--raw"], "a value is required");
    fails(bin, &["--xy", "1.5,0.2"], "not on the map");
    fails(bin, &["--xy", "-0.5,nan"], "finite");
    fails(bin, &["--xy", "0.1,0.2", "--raw", "500,500"], "cannot be used with");
    fails(bin, &["--frobnicate"], "unexpected argument '--frobnicate'");
    fails(bin, &["--then", "0.5,0.5"], "X2,Y2@MS");
    fails(bin, &["--then", "0.5,0.5@50"], "at least 350");
    fails(bin, &["--then", "0.5,0.5@soon"], "whole number of milliseconds");
    fails(bin, &["--then", "2.5,0.5@400"], "not on the map");
    fails(bin, &["--law", "sine"], "invalid value 'sine'");
    fails(bin, &["--lcd", "ssd1289"], "unknown controller \"ssd1289\" (ili9341, st7789, ili9486, ili9325");
    fails(bin, &["--lcd"], "a value is required");
    fails(bin, &["--wiring", "d"], "unknown wiring \"d\" (a, b or c)");
    fails(bin, &["--wiring"], "a value is required");
    fails(bin, &["--grip", "squeeze"], "invalid value 'squeeze'");
    fails(bin, &["--grip"], "a value is required");
    fails(bin, &["--switch", ""], "each time must be a whole number of milliseconds");
    fails(bin, &["--switch", "500,1.5"], "each time must be a whole number of milliseconds");
    fails(bin, &["--switch", "500,,900"], "got \"\"");
    fails(bin, &["--switch", "900,500"], "the times must increase, each at least 200 ms after the one before");
    fails(bin, &["--switch", "500,600"], "600 after 500");
    fails(bin, &["--switch", "70000"], "at most 60000 ms");
    fails(bin, &["--switch", "-5"], "whole number");
    fails(bin, &["--switch"], "a value is required");
    fails(bin, &["--switch", "500", "--xy", "0.1,0.2"], "cannot be used with");
    let help = Command::new(bin).arg("--help").output().unwrap();
    assert!(help.status.success());
    let text = String::from_utf8_lossy(&help.stdout);
    assert!(text.contains("--xy <X,Y>") && text.contains("--raw <X,Y>") && text.contains("--out <DIR>"), "{text}");
    assert!(text.contains("--then <X2,Y2@MS>") && text.contains("--law <LAW>"), "{text}");
    assert!(text.contains("--lcd <CONTROLLER>") && text.contains("--wiring <WIRING>"), "{text}");
    assert!(text.contains("--grip <open|close>") && text.contains("--switch <T1,T2,...>"), "{text}");
}
