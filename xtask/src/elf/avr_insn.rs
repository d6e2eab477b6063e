//! The few AVR instructions the ELF checks look at, decoded from their
//! 16-bit words (AVR Instruction Set Manual encodings). Everything else is
//! `Other`, with its correct length so a linear walk stays aligned.

/// A pointer register pair used with displacement (`ldd`/`std`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ptr {
    /// Y (r28:r29), the frame pointer.
    Y,
    /// Z (r30:r31).
    Z,
}

/// I/O addresses of the stack pointer and status register (`in`/`out`).
pub const SPL: u8 = 0x3d;
/// Stack pointer, high byte.
pub const SPH: u8 = 0x3e;
/// Status register.
pub const SREG: u8 = 0x3f;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
/// One decoded instruction: the ones the checks look at, everything else [`Insn::Other`].
pub enum Insn {
    /// `push Rr`.
    Push(u8),
    /// `in Rd, io`.
    In {
        /// Destination register.
        d: u8,
        /// I/O address.
        io: u8,
    },
    /// `out io, Rr`.
    Out {
        /// I/O address.
        io: u8,
        /// Source register.
        r: u8,
    },
    /// `cli`: interrupts off.
    Cli,
    /// `adiw`/`sbiw` on the pair starting at `d` (24, 26, 28, 30).
    Adiw {
        /// First register of the pair.
        d: u8,
        /// The immediate, 0..=63.
        k: u8,
    },
    /// `sbiw` on the pair starting at `d`.
    Sbiw {
        /// First register of the pair.
        d: u8,
        /// The immediate, 0..=63.
        k: u8,
    },
    /// `subi Rd, K` (Rd in r16..r31).
    Subi {
        /// Destination register.
        d: u8,
        /// The immediate.
        k: u8,
    },
    /// `sbci Rd, K`: subtract with carry.
    Sbci {
        /// Destination register.
        d: u8,
        /// The immediate.
        k: u8,
    },
    /// `ldi Rd, K`.
    Ldi {
        /// Destination register.
        d: u8,
        /// The immediate.
        k: u8,
    },
    /// `ld`/`ldd` Rd, Y+q or Z+q (q = 0 is plain `ld`).
    Ldd {
        /// Destination register.
        d: u8,
        /// The pointer pair.
        ptr: Ptr,
        /// The displacement, 0..=63.
        q: u8,
    },
    /// `rjmp`, `ijmp` or `eijmp`: an unconditional jump whose target the
    /// walk does not need.
    JumpAway,
    /// `jmp`/`call` with its target as a byte address.
    Jmp(u32),
    /// `call`, target as a byte address.
    Call(u32),
    /// `ret`.
    Ret,
    /// `reti`.
    Reti,
    /// Any other instruction (its length is still right).
    Other,
}

impl Insn {
    /// Decodes the instruction starting at `words[0]`; returns it and its
    /// length in words (2 for `jmp`, `call`, `lds`, `sts`).
    pub fn decode(words: &[u16]) -> (Insn, usize) {
        let Some(&w) = words.first() else { return (Insn::Other, 1) };
        let second = || words.get(1).copied().map(u32::from);
        let d5 = ((w >> 4) & 0x1f) as u8;
        let d_hi = 16 + ((w >> 4) & 0xf) as u8;
        let k8 = (((w >> 4) & 0xf0) | (w & 0xf)) as u8;
        let insn = match w {
            0x9508 => Insn::Ret,
            0x9518 => Insn::Reti,
            0x94f8 => Insn::Cli,
            0x9409 | 0x9419 => Insn::JumpAway,
            _ if w & 0xf000 == 0xc000 => Insn::JumpAway,
            _ if w & 0xfe0f == 0x920f => Insn::Push(d5),
            _ if w & 0xf800 == 0xb000 => Insn::In { d: d5, io: (((w >> 5) & 0x30) | (w & 0xf)) as u8 },
            _ if w & 0xf800 == 0xb800 => Insn::Out { io: (((w >> 5) & 0x30) | (w & 0xf)) as u8, r: d5 },
            _ if w & 0xff00 == 0x9600 || w & 0xff00 == 0x9700 => {
                let d = 24 + 2 * ((w >> 4) & 3) as u8;
                let k = (((w >> 2) & 0x30) | (w & 0xf)) as u8;
                if w & 0x0100 == 0 {
                    Insn::Adiw { d, k }
                } else {
                    Insn::Sbiw { d, k }
                }
            }
            _ if w & 0xf000 == 0x5000 => Insn::Subi { d: d_hi, k: k8 },
            _ if w & 0xf000 == 0x4000 => Insn::Sbci { d: d_hi, k: k8 },
            _ if w & 0xf000 == 0xe000 => Insn::Ldi { d: d_hi, k: k8 },
            // 10q0 qq0d dddd yqqq: `ldd` (bit 9 clear; bit 9 set is `std`).
            _ if w & 0xd200 == 0x8000 => {
                let q = (((w >> 8) & 0x20) | ((w >> 7) & 0x18) | (w & 7)) as u8;
                Insn::Ldd { d: d5, ptr: if w & 8 != 0 { Ptr::Y } else { Ptr::Z }, q }
            }
            _ if w & 0xfe0c == 0x940c => {
                let Some(lo) = second() else { return (Insn::Other, 1) };
                let hi = (u32::from(w >> 3) & 0x3e) | u32::from(w & 1);
                let target = ((hi << 16) | lo) * 2;
                return (if w & 2 == 0 { Insn::Jmp(target) } else { Insn::Call(target) }, 2);
            }
            // lds / sts Rd, k (the 16-bit address in the second word).
            _ if w & 0xfc0f == 0x9000 => return (Insn::Other, 2),
            _ => Insn::Other,
        };
        (insn, 1)
    }

    /// `K` of an `ldi` word (what an `*_LDI_*` relocation wrote).
    pub fn ldi_immediate(word: u16) -> Option<u8> {
        match Insn::decode(&[word]).0 {
            Insn::Ldi { k, .. } => Some(k),
            _ => None,
        }
    }
}

/// Little-endian 16-bit words of a byte slice (a trailing odd byte is dropped).
pub fn words(bytes: &[u8]) -> Vec<u16> {
    bytes.chunks_exact(2).map(|c| u16::from_le_bytes([c[0], c[1]])).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Encodings from avr-objdump's disassembly of the firmware.
    #[test]
    fn decodes_the_prologue_and_frame_instructions() {
        assert_eq!(Insn::decode(&[0x93cf]), (Insn::Push(28), 1)); // push r28
        assert_eq!(Insn::decode(&[0xb7cd]), (Insn::In { d: 28, io: SPL }, 1)); // in r28, 0x3d
        assert_eq!(Insn::decode(&[0xbfde]), (Insn::Out { io: SPH, r: 29 }, 1)); // out 0x3e, r29
        assert_eq!(Insn::decode(&[0xb60f]), (Insn::In { d: 0, io: SREG }, 1)); // in r0, 0x3f
        assert_eq!(Insn::decode(&[0x9728]), (Insn::Sbiw { d: 28, k: 8 }, 1)); // sbiw r28, 0x08
        assert_eq!(Insn::decode(&[0x96e0]), (Insn::Adiw { d: 28, k: 48 }, 1)); // adiw r28, 0x30
        assert_eq!(Insn::decode(&[0x52c0]), (Insn::Subi { d: 28, k: 0x20 }, 1)); // subi r28, 0x20
        assert_eq!(Insn::decode(&[0x40d1]), (Insn::Sbci { d: 29, k: 0x01 }, 1)); // sbci r29, 0x01
        assert_eq!(Insn::decode(&[0x8589]), (Insn::Ldd { d: 24, ptr: Ptr::Y, q: 9 }, 1)); // ldd r24, Y+9
        assert_eq!(Insn::decode(&[0xad8f]), (Insn::Ldd { d: 24, ptr: Ptr::Y, q: 63 }, 1)); // ldd r24, Y+63
        assert_eq!(Insn::decode(&[0x8180]), (Insn::Ldd { d: 24, ptr: Ptr::Z, q: 0 }, 1)); // ld r24, Z
        assert_eq!(Insn::decode(&[0x8389]).0, Insn::Other); // std Y+1, r24
        assert_eq!(Insn::decode(&[0xe08f]), (Insn::Ldi { d: 24, k: 0x0f }, 1)); // ldi r24, 0x0F
        assert_eq!(Insn::decode(&[0x940c, 0x0072]), (Insn::Jmp(0xe4), 2)); // jmp 0xe4
        assert_eq!(Insn::decode(&[0x940d, 0x0000]), (Insn::Jmp(0x20000), 2)); // jmp 0x20000
        assert_eq!(Insn::decode(&[0x940e, 0x1234]), (Insn::Call(0x2468), 2));
        assert_eq!(Insn::decode(&[0x9180, 0x0200]), (Insn::Other, 2)); // lds r24, 0x0200
        assert_eq!(Insn::decode(&[0x9508]), (Insn::Ret, 1));
        assert_eq!(Insn::decode(&[0xc041]), (Insn::JumpAway, 1)); // rjmp .+130
        assert_eq!(Insn::decode(&[0x9409]), (Insn::JumpAway, 1)); // ijmp
    }
}
