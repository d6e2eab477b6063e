//! scripts/flash.sh, the way onto a real board: the dry run prints the exact
//! avrdude command, and a missing board or firmware gives a clear message.

use std::path::PathBuf;
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn flash(args: &[&str], env: &[(&str, &str)]) -> (i32, String, String) {
    let mut cmd = Command::new("bash");
    cmd.arg(root().join("scripts/flash.sh")).args(args).env_remove("TOUCH_ARM_PORT");
    for (k, v) in env {
        cmd.env(k, v);
    }
    let out = cmd.output().expect("bash");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

/// Any existing file stands in for the ELF: the script only checks it exists.
fn some_elf() -> String {
    root().join("memory.x").to_string_lossy().replace("memory.x", "Cargo.toml")
}

#[test]
fn dry_run_prints_the_exact_avrdude_command() {
    let elf = some_elf();
    let (code, out, err) = flash(&["--dry-run", "--port", "/dev/ttyACM3", &elf], &[]);
    assert_eq!(code, 0, "{err}");
    let hex = elf.trim_end_matches(".elf").to_string() + ".hex";
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines[0], format!("avr-objcopy -O ihex -R .eeprom {elf} {hex}"));
    assert_eq!(lines[1], format!("avrdude -p atmega2560 -c wiring -P /dev/ttyACM3 -b 115200 -D -U flash:w:{hex}:i"));
}

#[test]
fn port_comes_from_the_environment() {
    let (code, out, _) = flash(&["--dry-run", &some_elf()], &[("TOUCH_ARM_PORT", "/dev/ttyUSB7")]);
    assert_eq!(code, 0);
    assert!(out.contains(" -P /dev/ttyUSB7 "), "{out}");
}

#[test]
fn no_board_is_a_clear_error() {
    let (code, out, err) = flash(&["--port", "/dev/touch-arm-no-such-port", &some_elf()], &[]);
    assert_eq!(code, 1);
    assert!(out.is_empty());
    assert!(err.contains("no board found at /dev/touch-arm-no-such-port"), "{err}");
}

#[test]
fn missing_firmware_says_how_to_build_it() {
    let (code, _, err) = flash(&["--dry-run", "/nonexistent/touch-arm.elf"], &[]);
    assert_eq!(code, 1);
    assert!(err.contains("cargo avr"), "{err}");
}
