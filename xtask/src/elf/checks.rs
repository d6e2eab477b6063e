//! The post-link checks, in one list ([`CHECKS`]): what `cargo xtask
//! elf-check` runs on each firmware ELF. Each check reads the ELF only and
//! returns a one-line summary, or the problems it found; a new check is one
//! more entry here (the tests in `xtask/tests/firmware_elf.rs` gate the
//! same properties in `cargo test`).

use super::{code_pointers, stack_args, stack_bound, Image};
use crate::bench_report::Budgets;

/// One firmware under check: its name (`touch-arm`, `bench`, an example...),
/// its parsed ELF and memory.x's budgets.
pub struct Firmware<'a> {
    /// The firmware's name, as `firmware::all_elfs` gives it.
    pub name: &'a str,
    /// The ELF as the linker left it.
    pub image: &'a Image<'a>,
    /// The budgets memory.x states.
    pub budgets: &'a Budgets,
    /// Also report the stack bound's deepest chains when it passes (a
    /// failing bound always prints them).
    pub chains: bool,
}

/// A post-link check: `run` gives `Ok(summary)` or `Err(problems)`, one
/// problem a line.
pub struct Check {
    /// What `elf-check` prints before the result.
    pub name: &'static str,
    /// The check itself.
    pub run: fn(&Firmware) -> Result<String, String>,
}

/// Every post-link check, in the order `elf-check` prints them.
pub const CHECKS: &[Check] = &[
    Check { name: "budgets", run: budgets },
    Check { name: "code-pointers", run: code_pointers },
    Check { name: "stack-args", run: stack_args },
    Check { name: "stack-bound", run: stack_bound },
];

/// Flash within memory.x's budget for every firmware; static RAM for the
/// product (`touch-arm`) only, as `firmware_elf.rs` does: the budget is the
/// product's, the checks and examples are not shipped.
fn budgets(fw: &Firmware) -> Result<String, String> {
    let (end, bytes) = (fw.image.flash_end(), fw.image.flash_bytes());
    let mut problems = Vec::new();
    if bytes == 0 {
        problems.push("nothing in flash".to_string());
    }
    if end > fw.budgets.flash {
        problems.push(format!("flash ends at {end:#x}, past the memory.x budget {}", fw.budgets.flash));
    }
    let mut summary = format!("flash {bytes} B, ends at {end:#x} (budget {})", fw.budgets.flash);
    if fw.name == "touch-arm" {
        let ram = fw.image.static_ram();
        if ram > fw.budgets.static_ram {
            problems.push(format!("static RAM {ram} B exceeds the memory.x budget {}", fw.budgets.static_ram));
        }
        summary += &format!(", static RAM {ram} B (budget {})", fw.budgets.static_ram);
    }
    if problems.is_empty() {
        Ok(summary)
    } else {
        Err(problems.join("\n"))
    }
}

/// Every 16-bit code pointer reaches its target and `lpm` data stays below
/// 64 KiB ([`code_pointers::check`]).
fn code_pointers(fw: &Firmware) -> Result<String, String> {
    let r = code_pointers::check(fw.image);
    let mut problems = r.problems.clone();
    // avr-libc's start-up code loads EIND from hh8(pm(__vectors)): one such
    // relocation shows the check saw the relocations (`--emit-relocs`).
    let hh8 = r.count(code_pointers::Kind::Hh8Pm);
    if hh8 != 1 {
        problems
            .push(format!("{hh8} hh8(pm()) relocations, not the start-up code's one: linked without --emit-relocs?"));
    }
    if !problems.is_empty() {
        return Err(problems.join("\n"));
    }
    Ok(format!(
        "{} code-pointer sites ({} through trampolines), {} trampolines ending at {:#x}, low flash ends at {:#x}",
        r.sites.len(),
        r.far_sites(),
        r.trampolines.len(),
        r.trampolines_end,
        r.progmem_end
    ))
}

/// No function reads stack-passed arguments ([`stack_args::lint`]).
fn stack_args(fw: &Firmware) -> Result<String, String> {
    let lint = stack_args::lint(fw.image);
    if lint.functions == 0 {
        return Err("no function symbols (stripped ELF?)".into());
    }
    if !lint.offenders.is_empty() {
        return Err(lint.offenders.iter().map(|o| o.to_string()).collect::<Vec<_>>().join("\n"));
    }
    Ok(format!(
        "{} functions, {} with a frame pointer, none reads stack-passed arguments",
        lint.functions, lint.with_frame_pointer
    ))
}

/// The worst-case stack depth from the call graph, interrupts included, within
/// the firmware's stack budget ([`stack_bound::check`]; the budget is
/// `firmware::stack_budget_of`: memory.x's for every ELF but the bench's).
fn stack_bound(fw: &Firmware) -> Result<String, String> {
    let budget =
        touch_arm_rig::firmware::stack_budget_of(fw.name, fw.budgets.stack, fw.budgets.ram, fw.image.static_ram());
    let b = stack_bound::check(fw.image, budget)?;
    let summary = format!(
        "stack bound {} B ({} thread + {} interrupts) within the {budget}-byte budget",
        b.total, b.thread.depth, b.interrupts
    );
    Ok(if fw.chains { format!("{summary}\n{b}") } else { summary })
}
