//! Post-link checks on a firmware ELF, as the linker left it.
//!
//! Properties of an ATmega2560 image that no compiler or linker error reports:
//! - `code_pointers`: a function pointer is a 16-bit word address, so code
//!   above 128 KiB is reached only through a linker trampoline, and data
//!   read with `lpm` only below 64 KiB;
//! - `stack_args`: LLVM miscompiles functions that read arguments passed on
//!   the stack (it assumes a 2-byte return address; the 2560's is 3 bytes);
//! - `stack_bound`: the worst-case stack depth from the call graph, which
//!   no simavr high-water mark proves.
//!
//! All read the ELF itself (with the `object` crate); nothing runs the
//! firmware. `Image` is the little view of the ELF they share.

pub mod avr_insn;
pub mod checks;
pub mod code_pointers;
pub mod stack_args;
pub mod stack_bound;

use object::read::elf::{ElfFile32, ProgramHeader};
use object::{Object, ObjectSection, ObjectSymbol, SymbolKind};

/// Data-space addresses in an AVR ELF start here (avr-gcc's convention);
/// everything below is flash.
pub const DATA_SPACE: u64 = 0x80_0000;

/// A parsed firmware ELF.
pub struct Image<'a> {
    pub(crate) file: ElfFile32<'a>,
}

/// A function symbol of the ELF: its name, start address and size in bytes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Function<'a> {
    /// Its (mangled) symbol name.
    pub name: &'a str,
    /// Its first byte, a flash byte address.
    pub address: u64,
    /// Its size, bytes.
    pub size: u64,
}

impl<'a> Image<'a> {
    /// Parses the bytes of a 32-bit AVR ELF.
    pub fn parse(bytes: &'a [u8]) -> Result<Image<'a>, String> {
        let file = ElfFile32::parse(bytes).map_err(|e| format!("not a 32-bit ELF: {e}"))?;
        if file.elf_header().e_machine.get(file.endian()) != object::elf::EM_AVR {
            return Err("not an AVR ELF".into());
        }
        Ok(Image { file })
    }

    /// The address of a symbol by name.
    pub fn symbol(&self, name: &str) -> Option<u64> {
        self.file.symbols().find(|s| s.name() == Ok(name)).map(|s| s.address())
    }

    /// Every function symbol with a size, in address order.
    pub fn functions(&self) -> Vec<Function<'a>> {
        let mut f: Vec<Function<'a>> = self
            .file
            .symbols()
            .filter(|s| s.kind() == SymbolKind::Text && s.size() > 0)
            .filter_map(|s| Some(Function { name: s.name().ok()?, address: s.address(), size: s.size() }))
            .collect();
        f.sort_by_key(|f| f.address);
        f.dedup_by_key(|f| f.address);
        f
    }

    /// `len` bytes at `address` (flash, or data space for initialized
    /// data), from the section that holds them.
    pub fn bytes(&self, address: u64, len: u64) -> Option<&'a [u8]> {
        self.loaded_sections().find_map(|s| {
            let start = s.address();
            if address < start || address + len > start + s.size() {
                return None;
            }
            let data = s.data().ok()?;
            let at = usize::try_from(address - start).ok()?;
            data.get(at..at + usize::try_from(len).ok()?)
        })
    }

    /// The sections that occupy memory on the chip (SHF_ALLOC): the others
    /// (symbols, relocations, comments) sit at address 0 too.
    fn loaded_sections(&self) -> impl Iterator<Item = object::read::elf::ElfSection32<'a, '_>> {
        self.file.sections().filter(|s| match s.flags() {
            object::SectionFlags::Elf { sh_flags } => sh_flags & u64::from(object::elf::SHF_ALLOC) != 0,
            _ => false,
        })
    }

    /// Where the byte at `address` sits in the ELF file (to craft a broken
    /// image from a good one in the tests).
    pub fn file_offset(&self, address: u64) -> Option<u64> {
        self.loaded_sections().find_map(|s| {
            let (offset, size) = s.file_range()?;
            (address >= s.address() && address < s.address() + size).then(|| offset + address - s.address())
        })
    }

    /// One past the highest flash byte the image writes: the loadable
    /// segments' load addresses (`.data`'s initializers included), which is
    /// what must stay below the bootloader.
    pub fn flash_end(&self) -> u64 {
        let endian = self.file.endian();
        self.file
            .elf_program_headers()
            .iter()
            .filter(|p| p.p_type(endian) == object::elf::PT_LOAD && p.p_filesz(endian) > 0)
            .map(|p| (u64::from(p.p_paddr(endian)), u64::from(p.p_filesz(endian))))
            .filter(|(at, _)| *at < DATA_SPACE)
            .map(|(at, len)| at + len)
            .max()
            .unwrap_or(0)
    }

    /// Bytes of flash the image writes (sum over its loadable segments).
    pub fn flash_bytes(&self) -> u64 {
        let endian = self.file.endian();
        self.file
            .elf_program_headers()
            .iter()
            .filter(|p| p.p_type(endian) == object::elf::PT_LOAD && u64::from(p.p_paddr(endian)) < DATA_SPACE)
            .map(|p| u64::from(p.p_filesz(endian)))
            .sum()
    }

    /// Static RAM: `.data` + `.bss` + `.noinit` (every allocated section in
    /// data space).
    pub fn static_ram(&self) -> u64 {
        self.loaded_sections()
            .filter(|s| s.address() >= DATA_SPACE && s.address() < DATA_SPACE + 0x1_0000)
            .map(|s| s.size())
            .sum()
    }
}
