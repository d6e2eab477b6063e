//! The real firmware under simavr: where its ELF is, how to load it, and how to
//! read the lines it prints. Shared by the main-job binary and the tests.

use std::path::{Path, PathBuf};

use crate::avr::{Avr, Error};

/// ATmega2560 on the Mega 2560 board.
pub const MCU: &str = "atmega2560";
pub const CPU_HZ: u32 = 16_000_000;

/// `target/avr-none/release/touch-arm.elf` of this workspace, or `TOUCH_ARM_ELF`.
pub fn default_elf() -> PathBuf {
    std::env::var_os("TOUCH_ARM_ELF").map(PathBuf::from).unwrap_or_else(|| {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/avr-none/release/touch-arm.elf")
    })
}

/// Loads the firmware, with a message that says how to build it when missing.
pub fn load(elf: &Path) -> Result<Avr, String> {
    if !elf.exists() {
        return Err(format!("{} not found: build the firmware first with `cargo avr`", elf.display()));
    }
    Avr::load(elf, MCU, CPU_HZ).map_err(|e: Error| format!("loading {}: {e:?}", elf.display()))
}

/// One demo frame as the firmware prints it (angles µrad, velocities µrad/s).
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    pub k: u32,
    pub t_us: u32,
    pub q_urad: [i32; 3],
    pub v_urad_s: [i32; 3],
    pub eval_cycles: u32,
}

/// Parses `F <k> <t_us> <q×3> <v×3> <cycles>`; other lines give `None`.
pub fn parse_frame(line: &str) -> Option<Frame> {
    let mut it = line.strip_prefix("F ")?.split_whitespace();
    let mut next = || it.next()?.parse::<i64>().ok();
    let k = next()? as u32;
    let t_us = next()? as u32;
    let q_urad = [next()? as i32, next()? as i32, next()? as i32];
    let v_urad_s = [next()? as i32, next()? as i32, next()? as i32];
    let eval_cycles = next()? as u32;
    Some(Frame { k, t_us, q_urad, v_urad_s, eval_cycles })
}
