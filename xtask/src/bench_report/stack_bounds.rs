//! The report's stack-bound section: each ELF's proven worst case
//! (`elf::stack_bound`) beside the high-water mark the simavr runs measured.

use crate::elf::stack_bound::{self, Bound};
use crate::elf::Image;

/// One ELF's row.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StackBoundRow {
    /// The ELF's name (`touch-arm`, `bench`, …).
    pub elf: String,
    /// The bound, or why there is none (recursion, an unresolved indirect
    /// call: `stack_bound::bound`'s refusals).
    pub bound: Result<Bound, String>,
    /// Its `.data` + `.bss`, bytes (0 when the ELF does not parse): the
    /// bench's stack budget depends on it.
    pub static_ram: u64,
}

impl StackBoundRow {
    /// The row of the ELF in `bytes`, with the firmware's allowed recursion.
    pub fn of(elf: &str, bytes: &[u8]) -> StackBoundRow {
        let image = Image::parse(bytes).map_err(|e| e.to_string());
        let static_ram = image.as_ref().map_or(0, Image::static_ram);
        let bound = image
            .and_then(|image| stack_bound::bound(&image, stack_bound::FIRMWARE_RECURSION).map_err(|r| r.join("; ")));
        StackBoundRow { elf: elf.to_string(), bound, static_ram }
    }
}

/// The section, or nothing when the run computed no bound. `measured`
/// gives an ELF's painted high-water mark where a run measured one,
/// `budget` its stack budget from its name and static RAM
/// (`firmware::stack_budget_of`).
pub fn section(
    rows: &[StackBoundRow],
    measured: impl Fn(&str) -> Option<String>,
    budget: impl Fn(&str, u64) -> u64,
) -> String {
    if rows.is_empty() {
        return String::new();
    }
    let mut out = vec![
        "## Stack bound".to_string(),
        String::new(),
        "Computed by `xtask::elf::stack_bound` from each ELF's call graph: every function's frame read from
its code (pushes, the frame its prologue allocates through Y, 3-byte return addresses), indirect
calls resolved to the functions whose address a code-pointer relocation forms, recursion refused
unless listed with its reason (`FIRMWARE_RECURSION`: `acc_scan` nests once), and the interrupt
handlers on top at their worst nesting (one at a time where no handler executes `sei`).
`xtask/tests/stack_bound.rs` fails when a bound exceeds its ELF's budget: memory.x's 2 KiB, but
for the bench (it does not ship, its static RAM and its deepest frames, the harness's, are its own)
the RAM its `.data` and `.bss` leave of the 8 KiB less a 512 B margin. Beside it, the
painted high-water mark of the runs above (the product's busiest session, the bench's deepest
routine, the UI demo's deepest draw; — where no run measures that ELF): a bound below it would be
no bound."
            .to_string(),
        String::new(),
        "| ELF | stack bound | thread | interrupts | measured high-water | budget |".to_string(),
        "| --- | ---: | ---: | ---: | ---: | ---: |".to_string(),
    ];
    for r in rows {
        let high = measured(&r.elf).map_or("—".to_string(), |m| format!("{m} B"));
        let budget = budget(&r.elf, r.static_ram);
        out.push(match &r.bound {
            Ok(b) => {
                let over = if u64::from(b.total) > budget { " ✗" } else { " ✓" };
                format!(
                    "| {} | {} B{over} | {} B | {} B | {high} | {budget} B |",
                    r.elf, b.total, b.thread.depth, b.interrupts
                )
            }
            Err(why) => format!("| {} | none: {why} | | | {high} | {budget} B |", r.elf),
        });
    }
    if let Some(Ok(b)) = rows.iter().find(|r| r.elf == "touch-arm").map(|r| &r.bound) {
        out.push(String::new());
        out.push(
            "The product's worst chain (depth on entry, function, its frame on the chain), then the deepest handler:"
                .to_string(),
        );
        out.push(String::new());
        out.push("```".to_string());
        // Closures' names (`{closure#0}`) in the braces the report's
        // template keeps for its placeholders: shown in ⟨⟩.
        out.push(b.to_string().trim_end().replace('{', "⟨").replace('}', "⟩"));
        out.push("```".to_string());
    }
    out.push(String::new());
    out.push(String::new());
    out.join("\n")
}
