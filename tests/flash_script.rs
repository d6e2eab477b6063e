//! scripts/flash.sh, the way onto a real board and the cargo runner behind
//! `cargo avr-run`: the dry run prints the exact ravedude command, a missing
//! board or firmware gives a clear message, and Ravedude.toml is the Mega's
//! stock bootloader at 115200 with the console at 115200.

use std::path::PathBuf;
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn flash(args: &[&str], env: &[(&str, &str)]) -> (i32, String, String) {
    let mut cmd = Command::new("bash");
    cmd.arg(root().join("scripts/flash.sh")).args(args);
    run(cmd, env)
}

fn run(mut cmd: Command, env: &[(&str, &str)]) -> (i32, String, String) {
    cmd.env_remove("TOUCH_ARM_PORT");
    for (k, v) in env {
        cmd.env(k, v);
    }
    let out = cmd.output().expect("spawn");
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
fn dry_run_prints_the_exact_ravedude_command() {
    let elf = some_elf();
    let (code, out, err) = flash(&["--dry-run", "--port", "/dev/ttyACM3", &elf], &[]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(out, format!("ravedude -P /dev/ttyACM3 -c {elf}\n"));
    // Without the console; options may follow the ELF (as cargo passes them).
    let (code, out, _) = flash(&[&elf, "--no-console", "--dry-run", "--port=/dev/ttyUSB1"], &[]);
    assert_eq!(code, 0);
    assert_eq!(out, format!("ravedude -P /dev/ttyUSB1 {elf}\n"));
}

#[test]
fn a_relative_elf_is_the_callers() {
    let mut cmd = Command::new("bash");
    cmd.arg(root().join("scripts/flash.sh")).args(["--dry-run", "--port", "/dev/ttyACM0", "../Cargo.toml"]);
    cmd.current_dir(root().join("hal-sim"));
    let (code, out, err) = run(cmd, &[]);
    assert_eq!(code, 0, "{err}");
    let want = root().join("hal-sim").join("../Cargo.toml");
    assert_eq!(out, format!("ravedude -P /dev/ttyACM0 -c {}\n", want.display()));
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

#[test]
fn unknown_option_is_refused() {
    let (code, out, err) = flash(&["--baud", "9600"], &[]);
    assert_eq!(code, 2);
    assert!(out.is_empty());
    assert!(err.contains("unknown option --baud"), "{err}");
}

/// `cargo avr-run` is `cargo run --release` for the firmware: cargo builds
/// the ELF and hands it to the runner, ravedude itself (no shell script, so
/// it runs on every OS), with the options after `--`. `--dump-config` shows
/// ravedude got them and reads Ravedude.toml, its console on. The firmware is
/// already built by the test command, so this is a fingerprint check, not a
/// build.
#[test]
fn cargo_avr_run_hands_the_firmware_to_ravedude() {
    let mut cmd = Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()));
    cmd.args(["avr-run", "--quiet", "--", "--dump-config"]).current_dir(root());
    let (code, out, err) = run(cmd, &[]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("board = \"mega2560\"") && out.contains("open-console = true"), "{out}");
    let config = std::fs::read_to_string(root().join(".cargo/config.toml")).unwrap();
    assert!(config.contains("runner = \"ravedude\""), "{config}");
    // The alias no longer shadows probe-rs's `cargo flash`.
    assert!(!config.lines().any(|l| l.trim_start().starts_with("flash =")), "{config}");
}

/// What ravedude makes of Ravedude.toml (scripts/setup.sh installs ravedude).
#[test]
fn ravedude_config_is_the_mega_bootloader_and_a_115200_console() {
    let mut cmd = Command::new("ravedude");
    cmd.arg("--dump-config").current_dir(root());
    let out = cmd.output().expect("ravedude not installed: scripts/setup.sh installs it");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout);
    let value = |key: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(key)?.trim_start().strip_prefix('=').map(str::trim))
            .unwrap_or_else(|| panic!("no {key} in\n{text}"))
    };
    assert_eq!(value("board"), "\"mega2560\"");
    assert_eq!(value("serial-baudrate"), "115200");
    assert_eq!(value("programmer"), "\"wiring\"");
    assert_eq!(value("partno"), "\"atmega2560\"");
    assert_eq!(value("baudrate"), "115200");
    // No chip erase (avrdude -D, as the flash script always did).
    assert_eq!(value("do-chip-erase"), "false");
    // `cargo avr-run` opens the console after flashing (avr-hal-template's
    // `open-console`).
    assert_eq!(value("open-console"), "true");
}
