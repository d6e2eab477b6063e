//! `cargo avr-hex`: the firmware as Intel HEX, what avrdude (and every other
//! uploader: the Arduino IDE's, XLoader on Windows) flashes without knowing
//! ELF. The image is the ELF's loadable flash bytes: every `PT_LOAD` segment
//! with file contents below the data space, at its load address (`.text`,
//! and `.data`'s initializers after it, which the C runtime copies to RAM).
//! Data-space sections (`.data`'s run address, `.noinit`) are not flash.
//!
//! The records: data (type 00, 16 bytes a line), extended linear address
//! (type 04) before each 64 KiB page the image enters (the firmware runs
//! past 64 KiB), and the end record (type 01).

use std::collections::BTreeMap;

use object::read::elf::ProgramHeader;

use crate::elf::{Image, DATA_SPACE};

/// The bytes per data record (what avr-objcopy writes too).
const RECORD: usize = 16;

/// The image's loadable flash bytes: (load address, bytes) per segment, in
/// address order.
pub fn flash_segments(image: &Image<'_>) -> Result<Vec<(u32, Vec<u8>)>, String> {
    let endian = image.file.endian();
    let data = image.file.data();
    let mut out = Vec::new();
    for p in image.file.elf_program_headers() {
        let (at, len) = (u64::from(p.p_paddr(endian)), u64::from(p.p_filesz(endian)));
        if p.p_type(endian) != object::elf::PT_LOAD || len == 0 || at >= DATA_SPACE {
            continue;
        }
        let bytes = p.data(endian, data).map_err(|_| format!("segment at {at:#x}: bytes outside the file"))?;
        out.push((u32::try_from(at).map_err(|_| format!("segment at {at:#x}"))?, bytes.to_vec()));
    }
    out.sort_by_key(|(a, _)| *a);
    Ok(out)
}

fn record(kind: u8, addr: u16, data: &[u8]) -> String {
    let mut sum = (data.len() as u8).wrapping_add((addr >> 8) as u8).wrapping_add(addr as u8).wrapping_add(kind);
    let mut s = format!(":{:02X}{addr:04X}{kind:02X}", data.len());
    for b in data {
        s += &format!("{b:02X}");
        sum = sum.wrapping_add(*b);
    }
    s + &format!("{:02X}\n", sum.wrapping_neg())
}

/// Intel HEX of `segments` (address, bytes).
pub fn encode(segments: &[(u32, Vec<u8>)]) -> String {
    let mut out = String::new();
    let mut page = 0u32;
    for (start, bytes) in segments {
        let mut at = *start;
        let mut rest = bytes.as_slice();
        while !rest.is_empty() {
            if at >> 16 != page {
                page = at >> 16;
                out += &record(4, 0, &(page as u16).to_be_bytes());
            }
            // A record never crosses a 64 KiB page.
            let room = (0x1_0000 - (at & 0xFFFF)) as usize;
            let n = rest.len().min(RECORD).min(room);
            out += &record(0, at as u16, &rest[..n]);
            at += n as u32;
            rest = &rest[n..];
        }
    }
    out + ":00000001FF\n"
}

/// The bytes an Intel HEX text writes, by address; checks every checksum,
/// the record types this tool writes (00, 01, 02, 04; 03 and 05, start
/// addresses, are skipped), and that it ends with an end record.
pub fn decode(text: &str) -> Result<BTreeMap<u32, u8>, String> {
    let mut mem = BTreeMap::new();
    let mut base = 0u32;
    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        let hex = line.trim_end().strip_prefix(':').ok_or_else(|| format!("line {n}: no ':'"))?;
        let bytes = (0..hex.len() / 2)
            .map(|k| u8::from_str_radix(hex.get(2 * k..2 * k + 2).unwrap_or("zz"), 16))
            .collect::<Result<Vec<u8>, _>>()
            .map_err(|_| format!("line {n}: not hex"))?;
        if hex.len() % 2 != 0 || bytes.len() < 5 || bytes.len() != 5 + usize::from(bytes[0]) {
            return Err(format!("line {n}: bad length"));
        }
        if bytes.iter().fold(0u8, |s, b| s.wrapping_add(*b)) != 0 {
            return Err(format!("line {n}: bad checksum"));
        }
        let addr = u16::from_be_bytes([bytes[1], bytes[2]]);
        let data = &bytes[4..bytes.len() - 1];
        match bytes[3] {
            0 => {
                for (k, b) in data.iter().enumerate() {
                    mem.insert(base + u32::from(addr) + k as u32, *b);
                }
            }
            1 => return Ok(mem),
            2 if data.len() == 2 => base = u32::from(u16::from_be_bytes([data[0], data[1]])) << 4,
            4 if data.len() == 2 => base = u32::from(u16::from_be_bytes([data[0], data[1]])) << 16,
            3 | 5 => {}
            t => return Err(format!("line {n}: record type {t:02X}")),
        }
    }
    Err("no end record".into())
}
