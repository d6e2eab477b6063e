//! BENCHMARKS.md from one bench run: `scripts/bench.sh` runs the bench
//! firmware in simavr and the two simavr tests that measure the display and
//! the product's stack, then calls the `bench-report` program, which reads
//! their output and the two ELFs' section sizes and fills `template.md` (the
//! document's prose, kept as Markdown) with the figures; from the ELFs
//! themselves it adds every firmware's stack bound (`stack_bounds`) and the
//! product's flash by module (`flash_map`).

mod accuracy;
pub mod command;
pub mod flash_map;
pub mod optimal;
mod parse;
mod routines;
pub mod stack_bounds;

pub use accuracy::{ulp_err, Accuracy};
pub use parse::{BenchOutput, Count, Routine, UiOutput};

/// The document with `{name}` where a figure or a table goes.
const TEMPLATE: &str = include_str!("template.md");

/// memory.x's budgets, bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Budgets {
    /// Flash (`__budget_flash`).
    pub flash: u64,
    /// Static RAM: .data + .bss + .noinit (`__budget_static_ram`).
    pub static_ram: u64,
    /// Stack (`__budget_stack`).
    pub stack: u64,
    /// The chip's RAM (memory.x's RAM region): the bench's stack budget is
    /// what its static RAM leaves of it (`firmware::stack_budget_in`).
    pub ram: u64,
}

impl Budgets {
    /// From memory.x's text (`__budget_flash`, `__budget_static_ram`, `__budget_stack`).
    pub fn parse(memory_x: &str) -> Result<Budgets, String> {
        let b = |name| touch_arm_rig::firmware::budget_in(memory_x, name);
        let (flash, static_ram, stack) = (b("flash")?, b("static_ram")?, b("stack")?);
        Ok(Budgets { flash, static_ram, stack, ram: touch_arm_rig::firmware::ram_in(memory_x)? })
    }
}

/// An ELF's section sizes (`firmware::section_sizes`).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Sizes(pub Vec<(String, u64)>);

impl Sizes {
    fn section(&self, name: &str) -> u64 {
        self.0.iter().find(|(n, _)| n == name).map_or(0, |(_, v)| *v)
    }

    /// Flash: code plus the initializers of `.data`.
    pub fn flash(&self) -> u64 {
        self.section(".text") + self.section(".data")
    }

    /// Static RAM: `.data` and `.bss`.
    pub fn static_ram(&self) -> u64 {
        self.section(".data") + self.section(".bss")
    }
}

/// Everything one report is made of.
#[derive(Debug, Clone)]
pub struct Inputs {
    /// The bench firmware's UART output.
    pub bench: BenchOutput,
    /// The display and stack tests' output.
    pub ui: UiOutput,
    /// The product firmware (`touch-arm.elf`) and the bench firmware.
    pub product: Sizes,
    /// The bench firmware's section sizes.
    pub bench_elf: Sizes,
    /// memory.x's budgets.
    pub budgets: Budgets,
    /// Every ELF's stack bound (empty: the section is left out).
    pub stack_bounds: Vec<stack_bounds::StackBoundRow>,
    /// The product's flash by module (None: the section is left out).
    pub flash_map: Option<flash_map::FlashMap>,
}

/// The heading and method of the frame-budget section.
const FRAME_BUDGET_INTRO: &str = "## Frame budget on the chip

Measured by `hal-sim/rig/tests/frame_budget.rs` on the product firmware in simavr (`board::frame` keeps the
record): a frame sets the servo pulses, then plans an accepted target, answers, sends telemetry
and draws the screen in slices that fit what the 20 ms period leaves (`ui::slice`). A period is
missed when no frame set its pulses before it started; a frame whose plan (or a draw over its
estimate) runs past the period end, its pulses already out, is counted as ending late, and the
next frame catches up: it steps the motion and writes the pulses, and takes no serial line, panel
read or plan (in brackets: of those frames, the ones whose app part had already passed the period
end before any drawing). A re-plan that finds less than 15 ms of the period left waits a frame
(which takes nothing else heavy), and its bisections stop when less than 8 ms is left
(`app::machine`). The test fails on a missed period or on any frame ending late.";

/// The whole BENCHMARKS.md.
pub fn render(inputs: &Inputs) -> Result<String, String> {
    let bench = &inputs.bench;
    let routines = bench.routines()?;
    let median = |name: &str| {
        routines.iter().find(|r| r.name == name).map(|r| r.median).ok_or(format!("the bench has no `{name}` figure"))
    };
    let (frame, paper_frame) = (median("frame")?, median("paper_frame")?);
    let mut cycles: Vec<String> = routines.iter().map(cycle_row).collect();
    cycles.extend(
        bench
            .counts()?
            .iter()
            .map(|c| format!("| {} (count) | {} | {} | {} | | |", c.name.replace('_', " "), c.median, c.min, c.max)),
    );
    let acc = Accuracy::of(bench)?;
    let ui = &inputs.ui;
    let steps: Vec<String> = ui.steps.iter().map(|s| format!("| {} |", s.join(" | "))).collect();
    let notes: Vec<String> = ui
        .notes
        .iter()
        .map(|n| match (n.strip_prefix("bus:"), n.strip_prefix("stack:")) {
            (Some(rest), _) => format!("Bus:{rest}"),
            (_, Some(rest)) => format!("UI stack:{rest}"),
            _ => n.clone(),
        })
        .collect();
    // The frame-budget section, where the run measured it.
    let frame_budget = if ui.frame_budget.is_empty() {
        String::new()
    } else {
        format!("{FRAME_BUDGET_INTRO}\n\n{}\n\n", ui.frame_budget.join("\n"))
    };
    // The move-time ratio, where the bench measured it.
    let move_time = match bench.counts()?.iter().find(|c| c.name == "zat_time_over_quintic_permille") {
        Some(c) => format!(
            "## Move time against the quintic\n\nThe time-scaled ζ-a-tₛ under the same speed and acceleration limits as the quintic, 15 moves at\n3 rad/s from speed-bound (60 rad/s²) to acceleration-bound (1 rad/s²), planned on the chip: median\n{:.3}×, from {:.3}× (both at the 0.5 s floor) to {:.3}× (goal ≤ 1.1×).\n\n",
            c.median as f64 / 1000.0,
            c.min as f64 / 1000.0,
            c.max as f64 / 1000.0
        ),
        None => String::new(),
    };
    // The host's time-optimal reference follows it (a run without the
    // move-time figure, like the test fixture's, has neither).
    let optimal = if move_time.is_empty() { String::new() } else { optimal::section()? };
    let (p, b, budgets) = (&inputs.product, &inputs.bench_elf, &inputs.budgets);
    // The high-water marks the runs measured: the product's busiest
    // session, the bench's deepest routine (it paints before each, so its
    // closing `S` line covers the last one only), the UI demo's note.
    let bench_deepest = routines.iter().map(|r| r.stack).max().map(|s| s.to_string());
    let measured = |elf: &str| match elf {
        "touch-arm" => ui.firmware_stack.clone(),
        "bench" => bench_deepest.clone(),
        "ui-demo" => ui.notes.iter().find_map(|n| n.strip_prefix("stack: ")?.split(' ').next().map(str::to_string)),
        _ => None,
    };
    let budget =
        |elf: &str, static_ram| touch_arm_rig::firmware::stack_budget_of(elf, budgets.stack, budgets.ram, static_ram);
    let stack_bound = stack_bounds::section(&inputs.stack_bounds, measured, budget);
    let flash_by_module = match &inputs.flash_map {
        Some(m) => format!(
            "## Flash by module

The product firmware's flash (`.text` and `.data`'s initializers) summed by the crate and module of
each symbol (`xtask::bench_report::flash_map`: demangled paths, methods by their type; C and
assembly as avr-libc, its float library or libgcc). Unattributed: bytes no symbol starts before
(alignment padding, and constants LLVM emits into `.data` without a symbol).

{}

",
            m.table(20)
        ),
        None => String::new(),
    };
    fill(
        TEMPLATE,
        &[
            ("overhead", bench.stamp_overhead()?.to_string()),
            ("cycles", cycles.join("\n")),
            ("frame_ms", format!("{:.3}", frame as f64 / 16000.0)),
            ("paper_ratio", format!("{:.1}", paper_frame as f64 / frame as f64)),
            ("samples", acc.samples.to_string()),
            ("g", sci(acc.g, 2)),
            ("g_at_ts", sci(acc.g_at_ts, 1)),
            ("rate", sci(acc.rate, 2)),
            ("paper", sci(acc.paper, 2)),
            ("paper_at_ts", sci(acc.paper_at_ts, 1)),
            ("ln", format!("{:.2}", acc.ln_ulps)),
            ("atan2", format!("{:.2}", acc.atan2_ulps)),
            ("sqrt", sci(acc.sqrt_rel, 1)),
            ("move_time", move_time),
            ("optimal", optimal),
            ("ui_steps", steps.join("\n")),
            ("ui_notes", notes.join("\n\n")),
            ("frame_budget", frame_budget),
            ("fw_flash", p.flash().to_string()),
            ("bench_flash", b.flash().to_string()),
            ("flash_budget", budgets.flash.to_string()),
            ("flash_kib", (budgets.flash / 1024).to_string()),
            ("flash_met", if p.flash() <= budgets.flash { "is met" } else { "is not met" }.to_string()),
            ("fw_ram", p.static_ram().to_string()),
            ("bench_ram", b.static_ram().to_string()),
            ("ram_budget", budgets.static_ram.to_string()),
            ("fw_stack", ui.firmware_stack.clone().unwrap_or_else(|| "?".into())),
            ("bench_stack", bench.stack()?.0.to_string()),
            ("stack_budget", budgets.stack.to_string()),
            ("stack_bound", stack_bound),
            ("flash_by_module", flash_by_module),
        ],
    )
}

/// One row of the cycles table, with its target judged.
fn cycle_row(r: &Routine) -> String {
    let target = match routines::target(&r.name) {
        None => String::new(),
        Some(t) => {
            let ok = routines::judged(&r.name, r.median, r.max) <= t;
            format!("≤ {t} {}", if ok { "✓" } else { "✗" })
        }
    };
    format!("| {} | {} | {} | {} | {target} | {} |", routines::describe(&r.name), r.median, r.min, r.max, r.stack)
}

/// `x` in scientific notation with `digits` decimals and a signed exponent of
/// at least two digits (1.28e-07), as the document has always shown them.
pub fn sci(x: f64, digits: usize) -> String {
    let s = format!("{x:.digits$e}");
    match s.split_once('e') {
        Some((mantissa, exp)) => {
            let e: i32 = exp.parse().unwrap_or(0);
            format!("{mantissa}e{}{:02}", if e < 0 { '-' } else { '+' }, e.unsigned_abs())
        }
        None => s, // inf, NaN
    }
}

/// `template` with every `{name}` replaced; a name the template lacks, or a
/// placeholder left unfilled, is an error (the two drifted apart).
fn fill(template: &str, values: &[(&str, String)]) -> Result<String, String> {
    let mut out = template.to_string();
    for (name, value) in values {
        let key = format!("{{{name}}}");
        if !out.contains(&key) {
            return Err(format!("the report template has no {key}"));
        }
        out = out.replace(&key, value);
    }
    match out.find('{') {
        Some(i) => Err(format!("the report template's {} is not filled", out[i..].split('}').next().unwrap_or(""))),
        None => Ok(out),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scientific_notation_has_a_signed_two_digit_exponent() {
        assert_eq!(sci(1.2849e-7, 2), "1.28e-07");
        assert_eq!(sci(0.0, 1), "0.0e+00");
        assert_eq!(sci(5.44e-5, 1), "5.4e-05");
        assert_eq!(sci(2.25e-15, 1), "2.2e-15"); // ties to even on the exact value
        assert_eq!(sci(3.0e123, 2), "3.00e+123");
        assert_eq!(sci(f64::INFINITY, 2), "inf");
    }

    #[test]
    fn rows_judge_the_targets() {
        let row = |name: &str, median, max| Routine { name: name.into(), median, min: 1, max, stack: 900 };
        assert_eq!(
            cycle_row(&row("plan", 16849, 69474)),
            format!("| {} | 16849 | 1 | 69474 | ≤ 20000 ✓ | 900 |", routines::describe("plan"))
        );
        assert!(cycle_row(&row("plan", 20001, 20001)).contains("≤ 20000 ✗"));
        // The frame is judged on its max.
        assert!(cycle_row(&row("frame", 6778, 8001)).contains("≤ 8000 ✗"));
        assert_eq!(cycle_row(&row("g", 4707, 4799)), "| ζ-a-tₛ G alone | 4707 | 1 | 4799 |  | 900 |");
    }

    #[test]
    fn template_placeholders_are_filled_exactly() {
        assert_eq!(fill("a {x} b {y}", &[("x", "1".into()), ("y", "2".into())]).unwrap(), "a 1 b 2");
        assert_eq!(fill("a {x}", &[("z", "1".into())]).unwrap_err(), "the report template has no {z}");
        assert_eq!(fill("a {x} {y}", &[("x", "1".into())]).unwrap_err(), "the report template's {y is not filled");
    }

    #[test]
    fn sizes_and_budgets() {
        let s = Sizes(touch_arm_rig::firmware::parse_section_sizes(
            "touch-arm.elf  :\nsection   size   addr\n.data  786  8389120\n.text  115722  0\n.bss  922  8389906\nTotal  117546\n",
        ));
        assert_eq!((s.flash(), s.static_ram()), (116508, 1708));
        let b = Budgets::parse(
            "    RAM    (rw!x): ORIGIN = 0x800200, LENGTH = 8K\n__budget_flash      = 120K;  /* x */\n\
             __budget_static_ram = 2K;\n__budget_stack = 2048;\n",
        );
        assert_eq!(b, Ok(Budgets { flash: 122880, static_ram: 2048, stack: 2048, ram: 8192 }));
        // The bench's stack budget: 8192 − its static RAM − the 512 B margin;
        // every other ELF's is __budget_stack.
        assert_eq!(touch_arm_rig::firmware::stack_budget_of("bench", 2048, 8192, 1860), 8192 - 1860 - 512);
        assert_eq!(touch_arm_rig::firmware::stack_budget_of("touch-arm", 2048, 8192, 3065), 2048);
        assert!(Budgets::parse("__budget_flash = 1K;").unwrap_err().contains("__budget_static_ram"));
    }
}
