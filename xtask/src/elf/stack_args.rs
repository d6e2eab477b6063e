//! Finds functions that read arguments passed on the stack.
//!
//! avr-gcc's ABI passes the first 18 bytes of arguments in r25..r8 and the
//! rest on the stack, above the return address. On the ATmega2560 that
//! address is 3 bytes, and LLVM's AVR backend places the incoming stack
//! arguments as if it were 2: such a function reads the wrong bytes. The
//! firmware therefore keeps argument lists within 18 bytes (structs by
//! reference), and this lint proves it on the linked ELF.
//!
//! The only way AVR code reads its stack is through a copy of SP: LLVM
//! (like avr-gcc) copies SP into Y (`in r28, SPL; in r29, SPH`), lowers it
//! by the frame size, writes SP back, and addresses locals as `Y+1 ..
//! Y+frame`. Above them lie the registers the prologue pushed, then the
//! return address, then the caller's stack arguments. A `ldd` through that
//! frame pointer past `frame + pushes` reads outside the function's own
//! frame: that is the signature of a stack-argument read. Temporary moves
//! of Y for far offsets (`adiw`/`sbiw`, `subi`/`sbci` pairs) are followed.

use super::avr_insn::{words, Insn, Ptr, SPH, SPL, SREG};
use super::Image;

/// A function that reads above its frame and saved registers.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Offender {
    /// Its (mangled) symbol name.
    pub name: String,
    /// Its flash byte address.
    pub address: u64,
    /// Registers pushed by the prologue.
    pub pushes: u32,
    /// Bytes of locals the prologue reserved.
    pub frame: u32,
    /// The first offending read, as an offset from the frame pointer.
    pub reads: i32,
}

impl std::fmt::Display for Offender {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(
            f,
            "{} at {:#x} reads Y+{} above its {}-byte frame and {} saved registers: a stack-passed argument",
            self.name, self.address, self.reads, self.frame, self.pushes
        )
    }
}

/// What the lint saw: how many functions it walked, how many of them copy
/// SP into a frame pointer (the only way to read the stack), and the
/// offenders. Every function symbol is walked, avr-libc's and libgcc's too:
/// none of them takes more than 18 bytes of arguments today, and a single
/// rule is easier to trust than a list of exceptions.
#[derive(Debug, Default)]
pub struct Lint {
    /// Function symbols walked.
    pub functions: usize,
    /// Those that copy SP into Y (a frame pointer).
    pub with_frame_pointer: usize,
    /// The functions that read stack-passed arguments.
    pub offenders: Vec<Offender>,
}

/// Walks every function of the image.
pub fn lint(image: &Image) -> Lint {
    let mut lint = Lint::default();
    for f in image.functions() {
        let Some(code) = image.bytes(f.address, f.size) else { continue };
        lint.functions += 1;
        let walk = walk(&words(code));
        lint.with_frame_pointer += usize::from(walk.frame_pointer);
        if let Some(reads) = walk.read_above_frame {
            let (pushes, frame) = (walk.pushes, walk.frame);
            lint.offenders.push(Offender { name: f.name.to_string(), address: f.address, pushes, frame, reads });
        }
    }
    lint
}

/// One function's prologue and its first read above the frame, if any.
#[derive(Debug, Default, PartialEq, Eq)]
struct Walk {
    frame_pointer: bool,
    pushes: u32,
    frame: u32,
    read_above_frame: Option<i32>,
}

/// Where the walk is in a function: before it copies SP into Y, while it
/// reserves its frame, or in its body.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Phase {
    Saving,
    Reserving,
    Body,
}

/// Walks one function's code in address order.
fn walk(code: &[u16]) -> Walk {
    let mut phase = Phase::Saving;
    let (mut pushes, mut frame) = (0u32, 0u32);
    // Current Y minus the frame pointer's value after the prologue.
    let mut y_moved = 0i32;
    let mut pending_subi: Option<u8> = None;
    let mut at = 0;
    while at < code.len() {
        let (insn, len) = Insn::decode(&code[at..]);
        at += len;
        if phase == Phase::Saving {
            match insn {
                Insn::Push(_) => pushes += 1,
                Insn::In { d: 28 | 29, io: SPL | SPH } => phase = Phase::Reserving,
                _ => {}
            }
            continue;
        }
        if phase == Phase::Reserving {
            match insn {
                Insn::In { d: 28 | 29, io: SPL | SPH } | Insn::In { io: SREG, .. } | Insn::Cli => {}
                Insn::Out { io: SPH | SREG, .. } => {}
                Insn::Sbiw { d: 28, k } => frame = u32::from(k),
                Insn::Subi { d: 28, k } => pending_subi = Some(k),
                Insn::Sbci { d: 29, k } if pending_subi.is_some() => {
                    frame = u32::from(u16::from_le_bytes([pending_subi.take().unwrap_or(0), k]));
                }
                Insn::Out { io: SPL, .. } => phase = Phase::Body,
                // No frame to reserve: the body starts here.
                _ => phase = Phase::Body,
            }
            if phase == Phase::Reserving || matches!(insn, Insn::Out { io: SPL, .. }) {
                continue;
            }
            pending_subi = None;
        }
        match insn {
            // An epilogue (or the end of a path): Y is back at the frame.
            Insn::Ret | Insn::Reti | Insn::Out { io: SPL, .. } => y_moved = 0,
            // What follows an unconditional jump is reached from elsewhere,
            // where Y is at the frame. LLVM may end a far access's restore
            // pair in a shared block: `subi r28` here, `rjmp`, and the
            // `sbci r29` at the target; carrying the half-undone move on
            // would count it twice.
            Insn::JumpAway | Insn::Jmp(_) => {
                y_moved = 0;
                pending_subi = None;
            }
            Insn::Adiw { d: 28, k } => y_moved += i32::from(k),
            Insn::Sbiw { d: 28, k } => y_moved -= i32::from(k),
            Insn::Subi { d: 28, k } => pending_subi = Some(k),
            Insn::Sbci { d: 29, k } if pending_subi.is_some() => {
                let lowered = u16::from_le_bytes([pending_subi.take().unwrap_or(0), k]) as i16;
                y_moved -= i32::from(lowered);
            }
            Insn::Ldd { ptr: Ptr::Y, q, .. } => {
                let offset = i32::from(q) + y_moved;
                if offset > (pushes + frame) as i32 {
                    return Walk { frame_pointer: true, pushes, frame, read_above_frame: Some(offset) };
                }
            }
            _ => {}
        }
    }
    Walk { frame_pointer: phase != Phase::Saving, pushes, frame, read_above_frame: None }
}

#[cfg(test)]
mod tests {
    use super::*;

    // push r28; push r29; in r28,SPL; in r29,SPH; sbiw r28,4; in r0,SREG;
    // cli; out SPH,r29; out SREG,r0; out SPL,r28
    const PROLOGUE: [u16; 10] = [0x93cf, 0x93df, 0xb7cd, 0xb7de, 0x9724, 0xb60f, 0x94f8, 0xbfde, 0xbe0f, 0xbfcd];

    fn with(body: &[u16]) -> Vec<u16> {
        let mut code = PROLOGUE.to_vec();
        code.extend_from_slice(body);
        code.push(0x9508);
        code
    }

    fn read_above(code: &[u16]) -> Option<i32> {
        walk(code).read_above_frame
    }

    #[test]
    fn reads_within_frame_and_saved_registers_pass() {
        // ldd r24, Y+1 (a local) and ldd r24, Y+6 (a saved register: 4 + 2).
        let w = walk(&with(&[0x8189, 0x818e]));
        assert_eq!(w, Walk { frame_pointer: true, pushes: 2, frame: 4, read_above_frame: None });
    }

    #[test]
    fn a_read_above_the_saved_registers_is_found() {
        // ldd r24, Y+7: past 4 bytes of frame and 2 pushes.
        assert_eq!(read_above(&with(&[0x818f])), Some(7));
    }

    #[test]
    fn temporary_moves_of_y_are_followed() {
        // adiw r28,60; ldd r24,Y+1 → offset 61, above 6.
        assert_eq!(read_above(&with(&[0x96ec, 0x8189])), Some(61));
        // subi r28,0x40; sbci r29,0 (Y −= 64), then ldd r24,Y+63 → −1: fine.
        assert_eq!(read_above(&with(&[0x54c0, 0x40d0, 0xad8f])), None);
        // The epilogue resets Y: ret, then a second path reads Y+6.
        assert_eq!(read_above(&with(&[0x96ec, 0x9508, 0x818e])), None);
        // A far access whose restore ends in a shared block (seen in the
        // product's `frame`): subi r28,0xFE; sbci r29,0xFF (Y += 2);
        // ldd r24,Y+1; subi r28,0x02; rjmp (the `sbci r29,0` is at the
        // target); then another path reads Y+6, inside the frame.
        assert_eq!(read_above(&with(&[0x5fce, 0x4fdf, 0x8189, 0x50c2, 0xc041, 0x818e])), None);
        // Without the jump the move stays: Y+6 is then 8.
        assert_eq!(read_above(&with(&[0x5fce, 0x4fdf, 0x818e])), Some(8));
    }

    #[test]
    fn y_used_as_a_plain_pointer_is_not_a_frame() {
        // push r28; push r29; movw r28,r24; ldd r24,Y+40; ret
        let w = walk(&[0x93cf, 0x93df, 0x01ec, 0xa588, 0x9508]);
        assert_eq!(w, Walk { frame_pointer: false, pushes: 2, frame: 0, read_above_frame: None });
    }
}
