//! scripts/setup.sh installs what the command being set up needs: run on a
//! machine that has nothing (stand-ins for `dpkg-query`, `id` and `sudo` on
//! the PATH: no package installed, not root, no sudo), it stops before
//! installing anything and names the Debian packages each command needs.

use std::fs;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// A folder of stand-in tools that make the script see an empty machine.
fn empty_machine(dir: &Path) {
    fs::create_dir_all(dir).unwrap();
    for (name, body) in [("dpkg-query", "exit 1"), ("id", "echo 1000"), ("sudo", "exit 1")] {
        let p = dir.join(name);
        fs::write(&p, format!("#!/bin/sh\n{body}\n")).unwrap();
        fs::set_permissions(&p, fs::Permissions::from_mode(0o755)).unwrap();
    }
}

/// The packages setup.sh asks for with `what` on an empty machine.
fn asks_for(what: &str) -> Vec<String> {
    let dir = std::env::temp_dir().join(format!("touch-arm-setup-test-{}", std::process::id()));
    empty_machine(&dir);
    let path = format!("{}:{}", dir.display(), std::env::var("PATH").unwrap());
    let out = Command::new("bash").arg(root().join("scripts/setup.sh")).arg(what).env("PATH", path).output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "setup.sh {what}: {err}");
    let line = err.lines().find_map(|l| l.strip_prefix("setup: missing Debian packages: ")).unwrap_or_else(|| {
        panic!("setup.sh {what} did not name the missing packages: {err}");
    });
    line.split_whitespace().map(str::to_string).collect()
}

#[test]
fn each_command_asks_for_what_it_needs() {
    let avr = ["gcc-avr", "avr-libc", "binutils-avr"];
    let simavr = ["libelf-dev", "zlib1g-dev", "libzstd-dev", "pkg-config", "clang", "libclang-dev", "make"];
    let main = asks_for("main");
    let live = asks_for("live");
    let flash = asks_for("flash");
    let test = asks_for("test");
    for p in avr.iter().chain(&simavr) {
        assert!(main.contains(&p.to_string()) && live.contains(&p.to_string()), "{p}: {main:?} {live:?}");
    }
    assert!(main.contains(&"fonts-dejavu-core".to_string()) && !live.contains(&"fonts-dejavu-core".to_string()));
    // The main job and the live bench: no browser, no flashing tools.
    for p in ["chromium", "avrdude", "libudev-dev"] {
        assert!(!main.contains(&p.to_string()) && !live.contains(&p.to_string()), "{p}");
        assert!(test.contains(&p.to_string()), "{p}: {test:?}");
    }
    // A board needs the AVR toolchain and avrdude, not simavr's C build;
    // ravedude's libudev-sys finds libudev through pkg-config.
    assert!(
        avr.iter().chain(&["avrdude", "libudev-dev", "pkg-config"]).all(|p| flash.contains(&p.to_string())),
        "{flash:?}"
    );
    assert!(!flash.contains(&"clang".to_string()) && !flash.contains(&"chromium".to_string()), "{flash:?}");
    // The test command needs everything the others do.
    for p in main.iter().chain(&live).chain(&flash) {
        assert!(test.contains(p), "{p}: {test:?}");
    }
    // No argument is the test command (.ci/run and scripts/test.sh call it so).
    assert_eq!(asks_for(""), test);
}

#[test]
fn an_unknown_command_is_refused() {
    let out = Command::new("bash").arg(root().join("scripts/setup.sh")).arg("everything").output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown command 'everything' (main, live, flash or test)"));
}
