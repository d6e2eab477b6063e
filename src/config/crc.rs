//! CRC-16/CCITT-FALSE (poly 0x1021, init 0xFFFF, no reflection, no final xor;
//! check value `crc16(b"123456789") == 0x29B1`).
//!
//! Bitwise rather than table-driven: on AVR a `static` table lives in SRAM
//! unless it is placed in program memory, and 512 bytes of an 8 KiB SRAM is too
//! much for a checksum that runs a few times per boot. A 16-bit CRC detects every
//! error burst of up to 16 bits, so any one decayed or overwritten EEPROM byte;
//! a save torn by a power loss is excluded by the store's commit byte
//! (`config::store`), not left to the CRC's 2⁻¹⁶ odds.

/// Initial register value.
pub const CRC16_INIT: u16 = 0xFFFF;

/// Feeds `data` into a running CRC (start from [`CRC16_INIT`]); lets a caller
/// checksum a record in pieces.
pub fn crc16_update(mut crc: u16, data: &[u8]) -> u16 {
    for &byte in data {
        crc ^= (byte as u16) << 8;
        let mut bit = 0;
        while bit < 8 {
            crc = if crc & 0x8000 != 0 { (crc << 1) ^ 0x1021 } else { crc << 1 };
            bit += 1;
        }
    }
    crc
}

/// CRC-16/CCITT-FALSE of `data`.
pub fn crc16(data: &[u8]) -> u16 {
    crc16_update(CRC16_INIT, data)
}
