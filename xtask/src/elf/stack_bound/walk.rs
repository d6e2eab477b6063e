//! One piece of code walked for its stack use: the deepest point of its own
//! frame and every call or jump out of it, with the depth at that site.
//!
//! The walk follows the code's control flow from its entry (fall-through,
//! conditional branches, skips, jumps inside the code; a call returns to
//! the next instruction), so code after a `ret` that belongs to another
//! entry of a hand-written routine is not charged to this one. Along each
//! path it follows the stack pointer the way the code moves it:
//! `push`/`pop` (1 byte), `rcall .+0` (a 3-byte allocation, avr-gcc's
//! idiom), and the frame allocation through Y (`in r28, SPL; in r29, SPH`,
//! `sbiw r28, k` or `subi r28/sbci r29`, then `out SPL, r28`), which sets SP
//! to wherever Y then stands. Where two paths meet at different depths the
//! deeper one is walked on; a return reached with bytes still pushed, or a
//! meeting of different depths, is recorded (a sign the model does not fit
//! that code), not hidden.

use super::super::avr_insn::{words, Insn, SPL};

/// An instruction as the walk sees it: the few that move SP or leave the
/// code, on top of what `avr_insn` decodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Op {
    Push,
    /// `pop Rd`.
    Pop(u8),
    /// `rcall` to a byte offset from the next instruction (0: `rcall .+0`).
    Rcall(i32),
    /// `rjmp` to a byte offset from the next instruction.
    Rjmp(i32),
    /// `icall` / `eicall`: a call through Z (EIND:Z).
    Icall,
    /// `ijmp` / `eijmp`: a jump through Z.
    Ijmp,
    Sei,
    /// `movw Rd, Rr` with `d` the even destination.
    Movw(u8),
    /// `brbs`/`brbc` (every conditional branch) to a byte offset from the
    /// next instruction.
    Branch(i32),
    /// `cpse`, `sbrc`, `sbrs`, `sbic`, `sbis`: may skip the next instruction.
    Skip,
    /// Anything `avr_insn` decodes.
    Plain(Insn),
}

/// Decodes the instruction at `code[0]`, and its length in words.
pub(super) fn decode(code: &[u16]) -> (Op, usize) {
    let Some(&w) = code.first() else { return (Op::Plain(Insn::Other), 1) };
    // A signed 12-bit word offset, as a byte offset.
    let k12 = || (i32::from((w & 0x0fff) as i16) << 20 >> 20) * 2;
    let op = match w {
        0x9509 | 0x9519 => Op::Icall,
        0x9409 | 0x9419 => Op::Ijmp,
        0x9478 => Op::Sei,
        _ if w & 0xfe0f == 0x900f => Op::Pop(((w >> 4) & 0x1f) as u8),
        _ if w & 0xf000 == 0xd000 => Op::Rcall(k12()),
        _ if w & 0xf000 == 0xc000 => Op::Rjmp(k12()),
        _ if w & 0xff00 == 0x0100 => Op::Movw((((w >> 4) & 0xf) * 2) as u8),
        _ if w & 0xf800 == 0xf000 => Op::Branch(((i32::from(w >> 3) & 0x7f) << 25 >> 25) * 2),
        _ if w & 0xfc00 == 0x1000 || w & 0xfc08 == 0xfc00 || w & 0xfd00 == 0x9900 => Op::Skip,
        _ => {
            let (insn, len) = Insn::decode(code);
            return (if matches!(insn, Insn::Push(_)) { Op::Push } else { Op::Plain(insn) }, len);
        }
    };
    (op, 1)
}

/// How a site leaves the code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Leave {
    /// `call`/`rcall`: the callee runs 3 bytes (its return address) deeper.
    Call(u64),
    /// `jmp`/`rjmp` out of the code: a tail call, at the site's depth.
    Jump(u64),
    /// `icall`/`eicall`: a call through Z, resolved by the caller of `walk`.
    IndirectCall,
    /// `ijmp`/`eijmp`: a jump through Z.
    IndirectJump,
}

/// One way out of the code.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Site {
    /// Byte address of the instruction.
    pub at: u64,
    /// Bytes the code itself has on the stack at the site (its return
    /// address not counted).
    pub depth: u32,
    /// Where it goes.
    pub leave: Leave,
}

/// What the walk found.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Walk {
    /// The deepest point of the code's own frame, bytes.
    pub own: u32,
    /// Every call and jump out of it, by address.
    pub sites: Vec<Site>,
    /// Whether the code contains `sei`.
    pub sei: bool,
    /// Where the walk's model did not fit (SP set from an unknown Y, more
    /// pops than pushes, a return with bytes still pushed).
    pub odd: Vec<String>,
}

/// The walk's state: SP's depth and, if Y holds a copy of SP (lowered or
/// raised since), the depth SP would have at Y.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct State {
    depth: i32,
    y: Option<i32>,
    /// The low byte of a `subi r28` waiting for its `sbci r29`.
    subi: Option<u8>,
}

/// A depth no path of real code reaches: a loop that pushes more each turn.
const RUNAWAY: i32 = 0x2000;

/// Walks the code of `bytes`, which starts at byte address `start`, from
/// its first instruction; `inside` says whether a jump target is in the
/// same piece of code (a branch, not a tail call).
pub fn walk(start: u64, bytes: &[u8], inside: impl Fn(u64) -> bool) -> Walk {
    let code = words(bytes);
    let mut out = Walk::default();
    let mut seen: Vec<Option<State>> = vec![None; code.len()];
    let mut sites = std::collections::BTreeMap::new();
    let mut todo = vec![(0usize, State { depth: 0, y: None, subi: None })];
    while let Some((at, mut s)) = todo.pop() {
        if at >= code.len() {
            continue;
        }
        match seen[at] {
            // Y may differ where paths meet: LLVM ends far accesses' Y
            // restores in a shared block (`subi r28, k` on each path, the
            // `sbci r29` after the jump), and every path's pair lands on the
            // same frame pointer. SP may not.
            Some(old) if old.depth >= s.depth => {
                if old.depth != s.depth {
                    note(&mut out.odd, format!("{:#x}: paths meet at different depths", start + 2 * at as u64));
                }
                continue;
            }
            Some(_) => note(&mut out.odd, format!("{:#x}: paths meet at different depths", start + 2 * at as u64)),
            None => {}
        }
        seen[at] = Some(s);
        let here = start + 2 * at as u64;
        let (op, len) = decode(&code[at..]);
        let next = at + len;
        let next_address = start + 2 * next as u64;
        let depth = s.depth.max(0) as u32;
        let to = |offset: i32| next_address.wrapping_add_signed(i64::from(offset));
        // Where control goes next, as word indices into the code.
        let mut follow: Vec<usize> = vec![next];
        let index = |t: u64| (t >= start && inside(t)).then(|| ((t - start) / 2) as usize);
        let jump = |t: u64, follow: &mut Vec<usize>, sites: &mut std::collections::BTreeMap<u64, Site>| {
            follow.clear();
            match index(t) {
                Some(i) => follow.push(i),
                None => {
                    sites.entry(here).and_modify(|x: &mut Site| x.depth = x.depth.max(depth)).or_insert(Site {
                        at: here,
                        depth,
                        leave: Leave::Jump(t),
                    });
                }
            }
        };
        let site = |leave: Leave, sites: &mut std::collections::BTreeMap<u64, Site>| {
            sites.entry(here).and_modify(|x: &mut Site| x.depth = x.depth.max(depth)).or_insert(Site {
                at: here,
                depth,
                leave,
            });
        };
        match op {
            Op::Push => s.depth += 1,
            Op::Rcall(0) => s.depth += 3,
            Op::Pop(r) => {
                s.depth -= 1;
                if r == 28 || r == 29 {
                    s.y = None;
                }
                if s.depth < 0 {
                    note(&mut out.odd, format!("{here:#x}: a pop below the code's entry"));
                    s.depth = 0;
                }
            }
            Op::Rcall(k) => site(Leave::Call(to(k)), &mut sites),
            Op::Plain(Insn::Call(t)) => site(Leave::Call(u64::from(t)), &mut sites),
            Op::Rjmp(k) => jump(to(k), &mut follow, &mut sites),
            Op::Plain(Insn::Jmp(t)) => jump(u64::from(t), &mut follow, &mut sites),
            Op::Branch(k) => follow.extend(index(to(k))),
            Op::Skip => {
                let (_, skipped) = decode(code.get(next..).unwrap_or(&[]));
                follow.push(next + skipped);
            }
            Op::Icall => site(Leave::IndirectCall, &mut sites),
            Op::Ijmp => {
                site(Leave::IndirectJump, &mut sites);
                follow.clear();
            }
            Op::Plain(Insn::Ret | Insn::Reti) => {
                if s.depth != 0 {
                    note(&mut out.odd, format!("{here:#x}: returns with {} bytes still on the stack", s.depth));
                }
                follow.clear();
            }
            Op::Sei => out.sei = true,
            Op::Movw(28) | Op::Plain(Insn::Ldi { d: 28 | 29, .. }) => s.y = None,
            Op::Plain(Insn::In { d: 28, io: SPL }) => s.y = Some(s.depth),
            Op::Plain(Insn::Sbiw { d: 28, k }) => s.y = s.y.map(|y| y + i32::from(k)),
            Op::Plain(Insn::Adiw { d: 28, k }) => s.y = s.y.map(|y| y - i32::from(k)),
            Op::Plain(Insn::Subi { d: 28, k }) => s.subi = Some(k),
            Op::Plain(Insn::Sbci { d: 29, k }) => match s.subi.take() {
                Some(lo) => s.y = s.y.map(|y| y + i32::from(u16::from_le_bytes([lo, k]) as i16)),
                None => s.y = None,
            },
            Op::Plain(Insn::Out { io: SPL, .. }) => match s.y {
                Some(y) => s.depth = y,
                None => note(&mut out.odd, format!("{here:#x}: sets SP from a Y the walk does not know")),
            },
            _ => {}
        }
        if s.depth > RUNAWAY {
            note(&mut out.odd, format!("{here:#x}: the stack grows without bound on a loop"));
            continue;
        }
        out.own = out.own.max(s.depth.max(0) as u32);
        todo.extend(follow.into_iter().map(|i| (i, s)));
    }
    out.sites = sites.into_values().collect();
    out
}

/// Records an oddity once.
fn note(odd: &mut Vec<String>, what: String) {
    if !odd.contains(&what) {
        odd.push(what);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn bytes(words: &[u16]) -> Vec<u8> {
        words.iter().flat_map(|w| w.to_le_bytes()).collect()
    }

    fn walked(words: &[u16]) -> Walk {
        let len = 2 * words.len() as u64;
        walk(0x100, &bytes(words), |t| (0x100..0x100 + len).contains(&t))
    }

    /// Encodings from avr-objdump's disassembly of the fixtures.
    #[test]
    fn decodes_what_moves_the_stack_or_leaves() {
        assert_eq!(decode(&[0x900f]), (Op::Pop(0), 1)); // pop r0
        assert_eq!(decode(&[0x91df]), (Op::Pop(29), 1)); // pop r29
        assert_eq!(decode(&[0xd000]), (Op::Rcall(0), 1)); // rcall .+0
        assert_eq!(decode(&[0xd00c]), (Op::Rcall(24), 1)); // rcall .+24
        assert_eq!(decode(&[0xcfff]), (Op::Rjmp(-2), 1)); // rjmp .-2
        assert_eq!(decode(&[0x9509]), (Op::Icall, 1));
        assert_eq!(decode(&[0x9519]), (Op::Icall, 1)); // eicall
        assert_eq!(decode(&[0x9419]), (Op::Ijmp, 1)); // eijmp
        assert_eq!(decode(&[0x9478]), (Op::Sei, 1));
        assert_eq!(decode(&[0x01ec]), (Op::Movw(28), 1)); // movw r28, r24
        assert_eq!(decode(&[0x93cf]), (Op::Push, 1)); // push r28
    }

    #[test]
    fn the_frame_allocation_through_y_sets_the_depth() {
        // push r28; push r29; in r28,SPL; in r29,SPH; sbiw r28,10; in r0,SREG;
        // cli; out SPH,r29; out SREG,r0; out SPL,r28; call 0x400;
        // adiw r28,10; (out SPH, SREG, SPL); pop r29; pop r28; ret
        let w = walked(&[
            0x93cf, 0x93df, 0xb7cd, 0xb7de, 0x972a, 0xb60f, 0x94f8, 0xbfde, 0xbe0f, 0xbfcd, 0x940e, 0x0200, 0x962a,
            0xbfde, 0xbe0f, 0xbfcd, 0x91df, 0x91cf, 0x9508,
        ]);
        assert_eq!(w.own, 12);
        assert_eq!(w.sites, [Site { at: 0x114, depth: 12, leave: Leave::Call(0x400) }]);
        assert!(w.odd.is_empty(), "{:?}", w.odd);
    }

    #[test]
    fn every_path_is_walked_from_the_entry_and_only_those() {
        // push r16; push r17; brne .+6; pop r17; pop r16; ret;
        // (the branch's path) rcall .+0; rcall .+8 (a call 3 + 2 bytes deep); pop ×3; ...
        let w = walked(&[0x930f, 0x931f, 0xf419, 0x911f, 0x910f, 0x9508, 0xd000, 0xd004, 0x900f, 0x900f, 0x900f]);
        assert_eq!(w.own, 5);
        assert_eq!(w.sites, [Site { at: 0x10e, depth: 5, leave: Leave::Call(0x118) }]);
        // ret; then code no path reaches: push r16 ×2, call.
        let w = walked(&[0x9508, 0x930f, 0x930f, 0x940e, 0x0200]);
        assert_eq!((w.own, w.sites.len()), (0, 0));
        // sbrc r24,0 skips the 2-word call: both paths are walked.
        let w = walked(&[0x930f, 0xfd80, 0x940e, 0x0200, 0x910f, 0x9508]);
        assert_eq!(w.sites, [Site { at: 0x104, depth: 1, leave: Leave::Call(0x400) }]);
        assert!(w.odd.is_empty(), "{:?}", w.odd);
    }

    #[test]
    fn a_jump_out_of_the_code_is_a_tail_call_and_an_unknown_sp_is_noted() {
        // movw r28,r24; out SPL,r28; rjmp .+0x7fe (outside).
        let w = walked(&[0x01ec, 0xbfcd, 0xc3ff]);
        assert_eq!(w.sites, [Site { at: 0x104, depth: 0, leave: Leave::Jump(0x904) }]);
        assert_eq!(w.odd, ["0x102: sets SP from a Y the walk does not know"]);
    }

    #[test]
    fn branches_decode_with_their_signed_offsets() {
        assert_eq!(decode(&[0xf419]), (Op::Branch(6), 1)); // brne .+6
        assert_eq!(decode(&[0xf7f1]), (Op::Branch(-4), 1)); // brne .-4
        assert_eq!(decode(&[0xfd80]), (Op::Skip, 1)); // sbrc r24, 0
        assert_eq!(decode(&[0x9b5d]), (Op::Skip, 1)); // sbis 0x0b, 5
        assert_eq!(decode(&[0x1381]), (Op::Skip, 1)); // cpse r24, r17
    }
}
