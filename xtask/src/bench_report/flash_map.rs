//! Flash by module: what `avr-nm --size-sort` shows, summed by the
//! crate and module each symbol belongs to, so the report shows where the
//! flash goes (issue #22 §4: make room by measurement).
//!
//! Every byte the image writes to flash is counted once: the code and
//! `.progmem` data of `.text`, and the initializers of `.data` (on the AVR
//! Rust's constants live in `.data`, copied to RAM at start-up). A sized
//! symbol (a function or an object) owns its bytes. Assembly routines of
//! avr-libc and libgcc often have no `.size`: the bytes from such a label
//! to the next symbol are its own. What no symbol starts before is
//! *unattributed*: alignment padding, and `.data` constants LLVM emits
//! without a symbol (string literals, anonymous tables).

use std::collections::BTreeMap;

use object::{Object, ObjectSection, ObjectSymbol, SymbolKind};

use crate::elf::stack_bound::demangled;
use crate::elf::{Image, DATA_SPACE};

/// One group of the table.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Module {
    /// `touch_arm::motion`, `core::fmt`, `compiler_builtins`, … (see [`module_of`]).
    pub name: String,
    /// Flash bytes.
    pub bytes: u64,
    /// Symbols counted.
    pub symbols: usize,
}

/// The flash of one image by module.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct FlashMap {
    /// Largest first.
    pub modules: Vec<Module>,
    /// Bytes no symbol accounts for, by section (`.text`, `.data`).
    pub unattributed: Vec<(String, u64)>,
    /// Every flash byte the sections hold (`modules` + `unattributed`).
    pub total: u64,
}

/// The group a symbol belongs to: for Rust, the crate and the first module
/// of its demangled path (`touch_arm::motion::planner::plan_move::<f32>` →
/// `touch_arm::motion`; an item at a crate's root → the crate; methods of
/// `<T as Trait>` by T's path, or the trait's when T is a primitive);
/// `compiler_builtins` and `libm` whole; LLVM's `switch.table.<f>` with
/// `f`; its unnamed constants (`anon.<hash>.<n>`) in a group of their own;
/// the interrupt handlers (`__vector_N`); avr-libc's start-up code and
/// vector table; other names (C and assembly) as C names (avr-libc's
/// `memcpy`, `sqrt`, and compiler-builtins' C-ABI functions such as
/// `fminimum_numf`, which the symbol alone does not tell apart), avr-libc's
/// float library (`__fp_*`, `__*sf*`) or libgcc (other `__`-names).
pub fn module_of(symbol: &str) -> String {
    if symbol.starts_with("__vector_") {
        return "interrupt handlers".into();
    }
    if matches!(symbol, "__vectors" | "__ctors_end" | "__trampolines_start" | "__bad_interrupt" | "_exit" | "exit")
        || symbol.starts_with("__do_")
        || symbol.starts_with("__ctors")
        || symbol.starts_with("__dtors")
    {
        return "vectors and start-up (avr-libc)".into();
    }
    // LLVM's lookup tables carry the function's name; its unnamed
    // constants (string literals, tables) only a hash.
    if let Some(function) = symbol.strip_prefix("switch.table.") {
        return module_of(function);
    }
    if symbol.starts_with("anon.") {
        return "Rust constants without a path (anon.*)".into();
    }
    let name = demangled(symbol);
    if name == symbol {
        return if symbol.starts_with("__fp_") || (symbol.starts_with("__") && symbol.contains("sf")) {
            "avr-libc libm (float)".into()
        } else if symbol.starts_with("__") {
            "libgcc".into()
        } else {
            "C names (avr-libc; compiler-builtins' C ABI)".into()
        };
    }
    let path = owner_path(&name);
    let parts = split_path(&path);
    match parts.as_slice() {
        [] => "?".into(),
        [one] => one.to_string(),
        [krate, ..] if matches!(*krate, "compiler_builtins" | "libm") => krate.to_string(),
        [krate, _item] => krate.to_string(),
        [krate, module, ..] => format!("{krate}::{module}"),
    }
}

/// The path a demangled name belongs to: itself, or for `<T as Trait>::m`
/// and `<T>::m` the path of T (of the trait when T has no path).
fn owner_path(name: &str) -> String {
    let Some(rest) = name.strip_prefix('<') else { return name.to_string() };
    // The matching `>` of the leading `<`.
    let mut level = 1;
    let mut end = rest.len();
    for (i, c) in rest.char_indices() {
        match c {
            '<' => level += 1,
            '>' => {
                level -= 1;
                if level == 0 {
                    end = i;
                    break;
                }
            }
            _ => {}
        }
    }
    let inner = &rest[..end];
    let (ty, tr) = match top_level_find(inner, " as ") {
        Some(i) => (&inner[..i], Some(&inner[i + 4..])),
        None => (inner, None),
    };
    let ty = ty.trim_start_matches(['&', '*', '[', '(']).trim_start_matches("mut ").trim_start_matches("const ");
    let ty = ty.trim_start_matches(['&', '*', '[', '(']);
    if split_path(ty).len() > 1 {
        return ty.to_string();
    }
    match tr {
        Some(t) => t.to_string(),
        None => ty.to_string(),
    }
}

/// `needle`'s first position outside any `<…>`.
fn top_level_find(s: &str, needle: &str) -> Option<usize> {
    let mut level = 0i32;
    for (i, c) in s.char_indices() {
        match c {
            '<' => level += 1,
            '>' => level -= 1,
            _ if level == 0 && s[i..].starts_with(needle) => return Some(i),
            _ => {}
        }
    }
    None
}

/// The `::`-separated segments of a path, generic arguments left inside
/// their segment (`plan_move::<f32>` is one segment after `::`… it is
/// dropped: it starts with `<`).
fn split_path(path: &str) -> Vec<&str> {
    let mut parts = Vec::new();
    let (mut level, mut start) = (0i32, 0usize);
    let bytes = path.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'<' => level += 1,
            b'>' => level -= 1,
            b':' if level == 0 && bytes.get(i + 1) == Some(&b':') => {
                parts.push(&path[start..i]);
                start = i + 2;
                i += 1;
            }
            _ => {}
        }
        i += 1;
    }
    parts.push(&path[start..]);
    parts.retain(|p| !p.is_empty() && !p.starts_with('<') && !p.starts_with('{'));
    parts
}

/// The flash map of an image.
pub fn of(image: &Image) -> FlashMap {
    let mut groups: BTreeMap<String, (u64, usize)> = BTreeMap::new();
    let mut unattributed = Vec::new();
    let mut total = 0;
    // The sections whose bytes are written to flash: code below the data
    // space, and `.data` (its initializers), not the EEPROM, nor `.noinit`
    // (RAM the start-up code leaves alone, `board::resume`; rustc gives it
    // contents, zeros that no loader writes anywhere).
    for section in image.file.sections() {
        let (start, size) = (section.address(), section.size());
        let noinit = section.name().is_ok_and(|n| n.starts_with(".noinit"));
        let flash = section.kind() == object::SectionKind::Text && start < DATA_SPACE
            || section.kind() == object::SectionKind::Data
                && (DATA_SPACE..DATA_SPACE + 0x1_0000).contains(&start)
                && !noinit;
        if !flash || size == 0 {
            continue;
        }
        total += size;
        let mut symbols: Vec<(u64, u64, bool, String)> = image
            .file
            .symbols()
            .filter(|s| s.section_index() == Some(section.index()))
            .filter(|s| matches!(s.kind(), SymbolKind::Text | SymbolKind::Data | SymbolKind::Unknown))
            .filter_map(|s| Some((s.address(), s.size(), s.kind() == SymbolKind::Text, s.name().ok()?.to_string())))
            .filter(|(_, _, _, n)| !n.is_empty() && !n.starts_with('.'))
            .collect();
        // At one address the sized, typed symbol names the bytes.
        symbols.sort_by_key(|(at, size, typed, _)| (*at, std::cmp::Reverse((*size, *typed))));
        symbols.dedup_by_key(|s| s.0);
        let end = start + size;
        let mut counted = 0;
        let mut covered = start;
        for (i, (at, size, _, name)) in symbols.iter().enumerate() {
            let next = symbols.get(i + 1).map_or(end, |n| n.0).min(end);
            let from = (*at).max(covered);
            let to = if *size > 0 { (at + size).min(end) } else { next };
            if to <= from {
                continue;
            }
            let g = groups.entry(module_of(name)).or_default();
            g.0 += to - from;
            g.1 += 1;
            counted += to - from;
            covered = to;
        }
        unattributed.push((section.name().unwrap_or("?").to_string(), size - counted));
    }
    let mut modules: Vec<Module> =
        groups.into_iter().map(|(name, (bytes, symbols))| Module { name, bytes, symbols }).collect();
    modules.sort_by_key(|m| (std::cmp::Reverse(m.bytes), m.name.clone()));
    FlashMap { modules, unattributed, total }
}

impl FlashMap {
    /// The Markdown table: the `rows` largest modules, the rest summed in
    /// one row, then the unattributed bytes and the total.
    pub fn table(&self, rows: usize) -> String {
        let pct = |b: u64| if self.total == 0 { 0.0 } else { 100.0 * b as f64 / self.total as f64 };
        let mut out =
            vec!["| module | flash B | % | symbols |".to_string(), "| --- | ---: | ---: | ---: |".to_string()];
        for m in self.modules.iter().take(rows) {
            out.push(format!("| `{}` | {} | {:.1} | {} |", m.name, m.bytes, pct(m.bytes), m.symbols));
        }
        let rest = &self.modules[rows.min(self.modules.len())..];
        if !rest.is_empty() {
            let (bytes, symbols) = rest.iter().fold((0, 0), |(b, s), m| (b + m.bytes, s + m.symbols));
            out.push(format!("| {} other modules | {bytes} | {:.1} | {symbols} |", rest.len(), pct(bytes)));
        }
        let un: u64 = self.unattributed.iter().map(|u| u.1).sum();
        let by: Vec<String> = self.unattributed.iter().map(|(s, b)| format!("{s} {b}")).collect();
        out.push(format!("| unattributed ({}) | {un} | {:.1} | |", by.join(", "), pct(un)));
        out.push(format!("| total | {} | 100.0 | |", self.total));
        out.join("\n")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// v0-mangled names as rustc wrote them into touch-arm.elf.
    #[test]
    fn symbols_group_by_crate_and_module() {
        for (symbol, module) in [
            ("_RINvNtNtNtCs88XBLxR489V_9touch_arm6motion7planner9peak_rate8acc_scanfEB8_", "touch_arm::motion"),
            ("_RNvCs88XBLxR489V_9touch_arm5frame", "touch_arm"),
            ("_RNvNtNtCs88XBLxR489V_9touch_arm5board5stack5paint", "touch_arm::board"),
            ("memcpy", "C names (avr-libc; compiler-builtins' C ABI)"),
            ("anon.08b04471a6c0ccb9af32497c1320d53f.9", "Rust constants without a path (anon.*)"),
            ("switch.table._RNvNtNtCs88XBLxR489V_9touch_arm6config5store8classify", "touch_arm::config"),
            ("__mulsf3", "avr-libc libm (float)"),
            ("__fp_split3", "avr-libc libm (float)"),
            ("__udivmodsi4", "libgcc"),
            ("__vector_25", "interrupt handlers"),
            ("__vectors", "vectors and start-up (avr-libc)"),
        ] {
            assert_eq!(module_of(symbol), module, "{symbol} ({})", demangled(symbol));
        }
    }

    #[test]
    fn methods_group_by_their_type_or_trait() {
        assert_eq!(
            owner_path("<touch_arm::app::App>::execute::<touch_arm::board::eeprom::Eeprom>"),
            "touch_arm::app::App"
        );
        assert_eq!(owner_path("<f32 as core::fmt::Display>::fmt"), "core::fmt::Display");
        assert_eq!(owner_path("<&mut ufmt::Formatter<W> as core::ops::Drop>::drop"), "ufmt::Formatter<W>");
        assert_eq!(split_path("touch_arm::motion::plan::<f32>"), ["touch_arm", "motion", "plan"]);
        assert_eq!(split_path("core::ptr::drop_in_place::<touch_arm::ui::Screen>"), ["core", "ptr", "drop_in_place"]);
    }

    #[test]
    fn the_table_sums_the_rest_and_states_what_is_unattributed() {
        let map = FlashMap {
            modules: vec![
                Module { name: "touch_arm::motion".into(), bytes: 600, symbols: 10 },
                Module { name: "core::fmt".into(), bytes: 300, symbols: 5 },
                Module { name: "libgcc".into(), bytes: 50, symbols: 2 },
            ],
            unattributed: vec![(".text".into(), 30), (".data".into(), 20)],
            total: 1000,
        };
        assert_eq!(
            map.table(2),
            "| module | flash B | % | symbols |\n| --- | ---: | ---: | ---: |\n\
             | `touch_arm::motion` | 600 | 60.0 | 10 |\n| `core::fmt` | 300 | 30.0 | 5 |\n\
             | 1 other modules | 50 | 5.0 | 2 |\n| unattributed (.text 30, .data 20) | 50 | 5.0 | |\n\
             | total | 1000 | 100.0 | |"
        );
    }
}
