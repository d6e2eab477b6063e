//! Code pointers and `lpm` data on a chip with more flash than they reach.
//!
//! A function pointer on the AVR is a 16-bit *word* address: it reaches the
//! first 128 KiB (`icall`/`eicall` with EIND = 0, which avr-libc's start-up
//! code sets). For code above that, GNU ld answers the relocations that form
//! such pointers (`R_AVR_16_PM` in data such as vtables, `R_AVR_LO8/HI8_LDI_GS`
//! in `ldi` pairs) with the address of a `jmp` stub in `.trampolines`, placed
//! low in flash. Nothing fails when that goes wrong: `--no-stubs`, or a
//! `pm()` relocation instead of `gs()`, silently keeps the low 16 bits. Data
//! read with `lpm` (a 16-bit Z) reaches only the first 64 KiB.
//!
//! `check` reads the relocations that `-Wl,--emit-relocs` keeps in the ELF
//! and proves, site by site, that the word the linker wrote is the target
//! itself (below 128 KiB) or a trampoline whose `jmp` goes to the target;
//! and that the low-flash region (vectors, `.progmem*`, trampolines) ends
//! where `lpm` and 16-bit pointers reach it.

use object::{Object, ObjectSection, ObjectSymbol, RelocationFlags, RelocationTarget};

use super::avr_insn::{words, Insn};
use super::Image;

/// Byte addresses a 16-bit word address reaches.
pub const POINTER_REACH: u64 = 0x2_0000;
/// Byte addresses `lpm` (16-bit Z) reaches.
pub const LPM_REACH: u64 = 0x1_0000;

/// The relocations that form a 16-bit word address of code.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Kind {
    /// `.word gs(f)` / `pm(f)`: a whole pointer in data (vtables, tables).
    Pm16,
    /// `ldi Rd, lo8(gs(f))` / `hi8(gs(f))`: a pointer built in registers.
    Lo8Gs,
    /// `hi8(gs(f))`, the high byte of the same.
    Hi8Gs,
    /// `lo8(pm(f))` / `hi8(pm(f))`: the same without a stub (truncates).
    Lo8Pm,
    /// `hi8(pm(f))`, the high byte of the same.
    Hi8Pm,
    /// `hh8(pm(f))`: bits 16..23 of a word address, what EIND is loaded
    /// with (avr-libc's start-up code: `hh8(pm(__vectors))`, 0). Trampolines
    /// assume EIND = 0, so every such site must hold 0.
    Hh8Pm,
}

impl Kind {
    fn from_elf(r_type: u32) -> Option<Kind> {
        use object::elf::*;
        match r_type {
            R_AVR_16_PM => Some(Kind::Pm16),
            R_AVR_LO8_LDI_GS => Some(Kind::Lo8Gs),
            R_AVR_HI8_LDI_GS => Some(Kind::Hi8Gs),
            R_AVR_LO8_LDI_PM => Some(Kind::Lo8Pm),
            R_AVR_HI8_LDI_PM => Some(Kind::Hi8Pm),
            R_AVR_HH8_LDI_PM => Some(Kind::Hh8Pm),
            _ => None,
        }
    }

    /// The relocation's ELF name (`R_AVR_16_PM`, ...), for messages.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Pm16 => "R_AVR_16_PM",
            Kind::Lo8Gs => "R_AVR_LO8_LDI_GS",
            Kind::Hi8Gs => "R_AVR_HI8_LDI_GS",
            Kind::Lo8Pm => "R_AVR_LO8_LDI_PM",
            Kind::Hi8Pm => "R_AVR_HI8_LDI_PM",
            Kind::Hh8Pm => "R_AVR_HH8_LDI_PM",
        }
    }

    /// Whether the linker answers this kind with a trampoline for code above
    /// 128 KiB (`gs()`); the others must reach their target directly.
    fn stubbed(self) -> bool {
        matches!(self, Kind::Pm16 | Kind::Lo8Gs | Kind::Hi8Gs)
    }

    /// The part of a 16-bit word address this site holds, as (mask, shift).
    fn part(self) -> (u16, u32) {
        match self {
            Kind::Pm16 => (0xffff, 0),
            Kind::Lo8Gs | Kind::Lo8Pm => (0xff, 0),
            Kind::Hi8Gs | Kind::Hi8Pm => (0xff, 8),
            Kind::Hh8Pm => (0xff, 16),
        }
    }
}

/// One relocation site that forms a code pointer, as resolved.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Site {
    /// Address of the site (flash, or data space for initialized data).
    pub at: u64,
    /// Which relocation forms it.
    pub kind: Kind,
    /// The byte address the relocation asked for (symbol + addend).
    pub target: u64,
    /// The trampoline the site points to instead, if any.
    pub via: Option<u64>,
}

/// A `jmp` stub of `.trampolines`: its address and where it jumps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Trampoline {
    /// The stub's address.
    pub at: u64,
    /// Where it jumps (byte address).
    pub to: u64,
}

/// What `check` found; `problems` is empty when the image is safe.
#[derive(Debug, Default)]
pub struct Report {
    /// Every code-pointer site that resolved correctly.
    pub sites: Vec<Site>,
    /// The trampolines the linker emitted.
    pub trampolines: Vec<Trampoline>,
    /// End of `.trampolines` (`__trampolines_end`).
    pub trampolines_end: u64,
    /// End of the low-flash region the linker script fills before the
    /// constructors and the start-up code (`__ctors_start`): vectors,
    /// `.progmem*`, trampolines, `.jumptables`, `.lowtext`. Everything read
    /// with `lpm` lies below it.
    pub progmem_end: u64,
    /// What is wrong, one line each; empty when the image is safe.
    pub problems: Vec<String>,
}

impl Report {
    /// Sites per relocation kind.
    pub fn count(&self, kind: Kind) -> usize {
        self.sites.iter().filter(|s| s.kind == kind).count()
    }

    /// Sites whose target is above 128 KiB (reached through a trampoline).
    pub fn far_sites(&self) -> usize {
        self.sites.iter().filter(|s| s.via.is_some()).count()
    }
}

/// Checks every code-pointer relocation site and the low-flash layout.
pub fn check(image: &Image) -> Report {
    let mut report = Report::default();
    let symbol = |name: &str, report: &mut Report| {
        image.symbol(name).unwrap_or_else(|| {
            report.problems.push(format!("no symbol {name}: not linked with avr-gcc's linker script"));
            0
        })
    };
    let start = symbol("__trampolines_start", &mut report);
    report.trampolines_end = symbol("__trampolines_end", &mut report);
    report.progmem_end = symbol("__ctors_start", &mut report);
    report.trampolines = trampolines(image, start, report.trampolines_end, &mut report.problems);
    if report.trampolines_end > POINTER_REACH {
        report.problems.push(format!(
            "the trampolines end at {:#x}, past the {POINTER_REACH:#x} that 16-bit word addresses reach",
            report.trampolines_end
        ));
    }
    if report.progmem_end > LPM_REACH {
        report.problems.push(format!(
            "the low-flash region (.progmem data) ends at {:#x}, past the {LPM_REACH:#x} that `lpm` reaches",
            report.progmem_end
        ));
    }
    check_sites(image, &mut report);
    report
}

fn trampolines(image: &Image, start: u64, end: u64, problems: &mut Vec<String>) -> Vec<Trampoline> {
    let Some(code) = image.bytes(start, end.saturating_sub(start)) else {
        problems.push(format!("cannot read the trampolines at {start:#x}..{end:#x}"));
        return Vec::new();
    };
    let code = words(code);
    code.chunks(2)
        .enumerate()
        .filter_map(|(i, w)| {
            let at = start + 4 * i as u64;
            match Insn::decode(w) {
                (Insn::Jmp(to), 2) => Some(Trampoline { at, to: u64::from(to) }),
                _ => {
                    problems.push(format!("the trampoline at {at:#x} is not a `jmp`"));
                    None
                }
            }
        })
        .collect()
}

fn check_sites(image: &Image, report: &mut Report) {
    let file = &image.file;
    let mut relocations = 0usize;
    for section in file.sections() {
        for (at, reloc) in section.relocations() {
            relocations += 1;
            let RelocationFlags::Elf { r_type } = reloc.flags() else { continue };
            let Some(kind) = Kind::from_elf(r_type) else { continue };
            let (base, name) = match reloc.target() {
                RelocationTarget::Symbol(i) => match file.symbol_by_index(i) {
                    Ok(s) => (s.address(), s.name().unwrap_or("").to_string()),
                    Err(_) => (0, String::new()),
                },
                RelocationTarget::Section(i) => match file.section_by_index(i) {
                    Ok(s) => (s.address(), s.name().unwrap_or("").to_string()),
                    Err(_) => (0, String::new()),
                },
                _ => (0, String::new()),
            };
            let target = base.wrapping_add_signed(reloc.addend());
            match resolve(image, &report.trampolines, at, kind, target) {
                Ok(via) => report.sites.push(Site { at, kind, target, via }),
                Err(why) => report.problems.push(format!(
                    "{} at {at:#x} ({}{name}{:+}): {why}",
                    kind.name(),
                    section.name().unwrap_or("?"),
                    reloc.addend()
                )),
            }
        }
    }
    if relocations == 0 {
        report.problems.push("no relocations in the ELF: link with -Wl,--emit-relocs".into());
    }
}

/// The trampoline a site goes through (None: straight to its target), or
/// why the value the linker wrote is not a way to the target.
fn resolve(image: &Image, trampolines: &[Trampoline], at: u64, kind: Kind, target: u64) -> Result<Option<u64>, String> {
    let bytes = image.bytes(at, 2).ok_or("the site is outside every section")?;
    let word = u16::from_le_bytes([bytes[0], bytes[1]]);
    let written = match kind {
        Kind::Pm16 => word,
        _ => u16::from(Insn::ldi_immediate(word).ok_or("the site is not an `ldi`")?),
    };
    let (mask, shift) = kind.part();
    let holds = |address: u64| address.is_multiple_of(2) && ((address / 2) >> shift) as u16 & mask == written;
    if target < POINTER_REACH && holds(target) {
        return Ok(None);
    }
    if let Some(t) = trampolines.iter().find(|t| kind.stubbed() && t.to == target && holds(t.at)) {
        return Ok(Some(t.at));
    }
    let how = if target % 2 == 1 {
        "is odd, not an instruction".to_string()
    } else if target < POINTER_REACH {
        format!("is below {POINTER_REACH:#x}, and the site does not hold its word address")
    } else if !kind.stubbed() {
        format!("is above {POINTER_REACH:#x}, which this relocation cannot reach (no trampoline for it)")
    } else if trampolines.iter().any(|t| t.to == target) {
        "has a trampoline, but the site does not point to it".to_string()
    } else {
        format!("is above {POINTER_REACH:#x} and no trampoline jumps to it (linked with --no-stubs?)")
    };
    Err(format!("holds {written:#x} (part of a word address), but its target {target:#x} {how}"))
}
