//! `cargo avr-hex` (`xtask::hex`): the Intel HEX it writes decodes to the
//! firmware ELF's loadable flash bytes, byte for byte, as avr-objcopy
//! extracts them independently (`.text` and `.data`'s initializers from
//! address 0); and the encoder's records round-trip across 64 KiB pages.

use std::path::PathBuf;
use std::process::Command;

use touch_arm_rig::firmware;
use xtask::hex::{decode, encode};

#[test]
fn records_round_trip_across_64k_pages() {
    let a: Vec<u8> = (0..100u32).map(|i| (i * 7) as u8).collect();
    let b: Vec<u8> = (0..40u32).map(|i| (i * 13 + 1) as u8).collect();
    // The second segment straddles 0x10000, the third sits above 128 KiB.
    let segs = vec![(0x0u32, a.clone()), (0xFFF0, b.clone()), (0x2_0003, vec![0xAB, 0xCD])];
    let text = encode(&segs);
    assert!(text.ends_with(":00000001FF\n"));
    assert!(text.contains(":020000040001F9\n") && text.contains(":020000040002F8\n"), "{text}");
    let mem = decode(&text).unwrap();
    for (start, bytes) in &segs {
        for (k, v) in bytes.iter().enumerate() {
            assert_eq!(mem.get(&(start + k as u32)), Some(v), "{:#x}", start + k as u32);
        }
    }
    assert_eq!(mem.len(), a.len() + b.len() + 2);
    // Every record is at most 16 data bytes and never crosses a page.
    for l in text.lines() {
        let n = usize::from_str_radix(&l[1..3], 16).unwrap();
        let addr = usize::from_str_radix(&l[3..7], 16).unwrap();
        assert!(n <= 16 && addr + n <= 0x1_0000, "{l}");
    }
    // A damaged checksum is refused.
    let bad = text.replacen(":10000000", ":10000001", 1);
    assert!(decode(&bad).unwrap_err().contains("checksum"));
}

/// `cargo avr-hex` builds the firmware (a fingerprint check: the test
/// command has built it) and writes touch-arm.hex next to the ELF.
#[test]
fn cargo_avr_hex_writes_the_elf_flash_bytes() {
    let root = firmware::workspace_root();
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let out = Command::new(cargo).args(["avr-hex"]).current_dir(&root).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let elf = firmware::default_elf();
    let hex = elf.with_extension("hex");
    assert!(hex.ends_with("avr-none/release/touch-arm.hex"), "{}", hex.display());
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains(&format!("wrote {}", hex.display())), "{stdout}");
    let mem = decode(&std::fs::read_to_string(&hex).unwrap()).unwrap();

    // avr-objcopy's view of the same flash: .text, then .data at its load
    // address, as one binary from 0.
    let bin: PathBuf = std::env::temp_dir().join(format!("touch-arm-flash-{}.bin", std::process::id()));
    let st = Command::new("avr-objcopy")
        .args(["-O", "binary", "-j", ".text", "-j", ".data"])
        .arg(&elf)
        .arg(&bin)
        .status()
        .expect("avr-objcopy (binutils-avr)");
    assert!(st.success());
    let flash = std::fs::read(&bin).unwrap();
    let _ = std::fs::remove_file(&bin);
    assert!(flash.len() > 100_000, "{} bytes", flash.len());
    assert_eq!(mem.len(), flash.len(), "the hex holds exactly the flash image's bytes");
    let first_diff = flash.iter().enumerate().find(|(a, b)| mem.get(&(*a as u32)) != Some(b)).map(|(a, _)| a);
    assert_eq!(first_diff, None, "the hex differs from the ELF's flash bytes");
    // Nothing from the data space (.data's run address, .noinit).
    assert!(mem.keys().all(|a| *a < 0x80_0000));
}
