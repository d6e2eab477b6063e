//! The stack bound (`xtask::elf::stack_bound`): on small assembly
//! programs whose depth is known by hand (`tests/fixtures/stack/*.S`, each
//! deriving its numbers in its comments; linked here by avr-gcc with
//! avr-libc's start-up code and vectors, as `elf_fixtures.rs` links its C
//! programs), on recursion and on an indirect call it cannot resolve; then
//! on every firmware ELF `cargo avr` builds, against memory.x's budget.

use std::path::{Path, PathBuf};
use std::process::Command;

use touch_arm_rig::firmware;
use xtask::bench_report::flash_map;
use xtask::bench_report::stack_bounds::{self, StackBoundRow};
use xtask::elf::stack_bound::{self, Bound};
use xtask::elf::Image;

/// Links `tests/fixtures/stack/<name>.S` for the ATmega2560 (with
/// `--emit-relocs`, as the firmware is) and returns the ELF's bytes.
fn link(name: &str, defines: &[&str]) -> Vec<u8> {
    let source = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/stack").join(format!("{name}.S"));
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("stack-fixtures");
    std::fs::create_dir_all(&dir).unwrap();
    let elf = dir.join(format!("{name}{}.elf", defines.concat()));
    let out = Command::new("avr-gcc")
        .args(["-mmcu=atmega2560", "-Wl,--emit-relocs"])
        .args(defines)
        .arg(&source)
        .arg("-o")
        .arg(&elf)
        .output()
        .expect("avr-gcc (gcc-avr; scripts/setup.sh installs it)");
    assert!(out.status.success(), "avr-gcc {name}: {}", String::from_utf8_lossy(&out.stderr));
    std::fs::read(&elf).unwrap()
}

fn bound(bytes: &[u8]) -> Result<Bound, Vec<String>> {
    stack_bound::bound(&Image::parse(bytes).unwrap(), &[])
}

/// (name, entered at, frame) of each step of a chain.
fn steps(chain: &stack_bound::Chain) -> Vec<(&str, u32, u32)> {
    chain.steps.iter().map(|s| (s.name.as_str(), s.entered_at, s.frame)).collect()
}

#[test]
fn a_known_depth_is_found_with_its_chain() {
    let b = bound(&link("known_depth", &[])).unwrap();
    // known_depth.S: 3 (call main) + 12 + 3 + 304 + 3 + 4.
    assert_eq!(b.thread.depth, 329);
    assert_eq!(steps(&b.thread), [("main", 3, 12), ("outer", 18, 304), ("inner", 325, 4)]);
    // The table in .data holds leaf_a and leaf_b: all that main's icall reaches.
    let taken: Vec<String> = stack_bound::address_taken(&Image::parse(&link("known_depth", &[])).unwrap())
        .into_iter()
        .map(|(n, _)| n)
        .collect();
    assert_eq!(taken, ["leaf_a", "leaf_b"]);
    assert_eq!(b.indirect_sites, 1);
    let handlers: Vec<(u64, u32, bool)> = b.handlers.iter().map(|h| (h.vector, h.chain.depth, h.reenables)).collect();
    // Vector 25: 3 + 3 pushes + 3 + leaf_b's 5; vector 23: 3 + 1 push.
    assert_eq!(handlers, [(23, 4, false), (25, 14, false)]);
    assert_eq!(steps(&b.handlers[1].chain), [("__vector_25", 3, 3), ("leaf_b", 9, 5)]);
    // Neither re-enables interrupts: one handler at a time, the deepest.
    assert_eq!((b.interrupts, b.total), (14, 343));
    assert!(b.odd.is_empty(), "{:?}", b.odd);
    // The budget check: at the bound it passes, a byte below it fails and
    // prints the chain.
    let image = link("known_depth", &[]);
    let image = Image::parse(&image).unwrap();
    assert_eq!(stack_bound::check(&image, 343).map(|b| b.total), Ok(343));
    let err = stack_bound::check(&image, 342).unwrap_err();
    assert!(err.starts_with("the stack bound exceeds the 342-byte stack budget\nstack bound 343 B"), "{err}");
    assert!(err.contains("   325 B  inner (4 B, its deepest point)"), "{err}");
}

#[test]
fn a_handler_that_reenables_interrupts_nests_under_the_others() {
    let b = bound(&link("known_depth", &["-DREENABLE"])).unwrap();
    let handlers: Vec<(u64, u32, bool)> = b.handlers.iter().map(|h| (h.vector, h.chain.depth, h.reenables)).collect();
    assert_eq!(handlers, [(23, 4, true), (25, 14, false)]);
    // 329 + 4 (vector 23, interrupted) + 14 (vector 25 inside it).
    assert_eq!((b.interrupts, b.total), (18, 347));
    let on: Vec<u64> = b.worst_nesting().iter().map(|h| h.vector).collect();
    assert_eq!(on, [25, 23]);
}

#[test]
fn an_indirect_call_through_an_ldi_pair_goes_to_its_one_target() {
    let b = bound(&link("ldi_pointer", &[])).unwrap();
    // ldi_pointer.S: 3 + 3 + 1, not 3 + 3 + 4 through `table`'s `deep`.
    assert_eq!(b.total, 7);
    assert_eq!(steps(&b.thread), [("main", 3, 0), ("shallow", 6, 1)]);
    assert_eq!((b.indirect_sites, b.address_taken), (1, 2));
}

#[test]
fn recursion_is_refused_with_its_cycle() {
    let err = bound(&link("recursion", &[])).unwrap_err();
    assert_eq!(err, ["recursion: ping -> pong -> ping"]);
}

#[test]
fn recursion_of_a_known_depth_is_bounded_when_allowed() {
    let bytes = link("bounded_recursion", &[]);
    let image = Image::parse(&bytes).unwrap();
    assert_eq!(stack_bound::bound(&image, &[]).unwrap_err(), ["recursion: twice -> twice"]);
    let allowed = [stack_bound::Recursion { function: "twice", levels: 1, why: "the bit is cleared" }];
    let b = stack_bound::bound(&image, &allowed).unwrap();
    // bounded_recursion.S: 3 + 3 + 5 + 2.
    assert_eq!(b.total, 13);
    assert_eq!(steps(&b.thread), [("main", 3, 0), ("twice", 6, 2), ("twice", 11, 2)]);
}

#[test]
fn an_indirect_call_to_a_constant_address_is_refused_at_its_site() {
    let bytes = link("unresolved_icall", &[]);
    let image = Image::parse(&bytes).unwrap();
    let icall = image.symbol("main").unwrap() + 4;
    let err = stack_bound::bound(&image, &[]).unwrap_err();
    assert_eq!(
        err,
        [format!(
            "main at {icall:#x}: an indirect call through a constant Z that no code-pointer relocation formed (a cast integer?)"
        )]
    );
}

#[test]
fn every_firmware_stack_bound_is_within_the_budget() {
    let mut failures = Vec::new();
    for (name, elf) in firmware::all_elfs() {
        let bytes = std::fs::read(&elf).unwrap_or_else(|e| {
            panic!("{}: {e}: build the firmware first with `cargo avr` (scripts/test.sh does)", elf.display())
        });
        let image = Image::parse(&bytes).unwrap();
        // memory.x's 2 KiB, except the bench: the RAM its static data
        // leaves, less a margin (`firmware::stack_budget` says why).
        let budget = firmware::stack_budget(name, image.static_ram()).unwrap();
        let want = if name == "bench" { 8192 - image.static_ram() - 512 } else { 2048 };
        assert_eq!(budget, want, "{name}'s stack budget");
        let b = match stack_bound::bound(&image, stack_bound::FIRMWARE_RECURSION) {
            Ok(b) => b,
            Err(refusals) => {
                failures.push(format!("{name}: {}", refusals.join("\n")));
                continue;
            }
        };
        eprintln!(
            "{name}: stack bound {} B of {budget} B (thread {} + interrupts {}; {} code pieces, {} indirect sites, \
             {} address-taken, handlers re-enabling interrupts: {})",
            b.total,
            b.thread.depth,
            b.interrupts,
            b.nodes,
            b.indirect_sites,
            b.address_taken,
            b.handlers.iter().filter(|h| h.reenables).count()
        );
        for o in &b.odd {
            eprintln!("{name}: note: {o}");
        }
        // The thread alone is at least main's return address.
        assert!(b.thread.depth >= stack_bound::RETURN_ADDRESS, "{name}");
        // `check` is this comparison, with the chain in its message.
        match stack_bound::check(&image, budget) {
            Ok(checked) => assert_eq!(checked.total, b.total),
            Err(e) => failures.push(format!("{name}: {e}")),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// The report's two sections from the real ELFs: a row per ELF with the
/// bound the check computes, and the product's flash by module adding up
/// to the flash the image writes.
#[test]
fn the_report_shows_every_bound_and_the_flash_by_module() {
    let mut rows = Vec::new();
    for (name, elf) in firmware::all_elfs() {
        rows.push(StackBoundRow::of(name, &std::fs::read(&elf).unwrap()));
    }
    // The bench's budget: the 8 KiB less its static RAM and the 512 B
    // margin; every other ELF's is memory.x's 2048 B.
    let budget = |elf: &str, static_ram: u64| if elf == "bench" { 8192 - static_ram - 512 } else { 2048 };
    let text = stack_bounds::section(&rows, |elf| (elf == "touch-arm").then(|| "1898".to_string()), budget);
    for r in &rows {
        let b = r.bound.as_ref().unwrap();
        let budget = budget(&r.elf, r.static_ram);
        let want = format!(
            "| {} | {} B {} | {} B | {} B | — | {budget} B |",
            r.elf,
            b.total,
            if u64::from(b.total) > budget { "✗" } else { "✓" },
            b.thread.depth,
            b.interrupts
        );
        if r.elf != "touch-arm" {
            assert!(text.contains(&want), "{want} not in\n{text}");
        }
    }
    let bench = rows.iter().find(|r| r.elf == "bench").unwrap();
    assert!(bench.static_ram > 1000 && text.contains(&format!("| {} B |\n", 8192 - bench.static_ram - 512)), "{text}");
    assert!(text.contains("| 1898 B | 2048 B |") && !text.contains('{'), "{text}");
    eprintln!("{text}");

    let bytes = std::fs::read(firmware::default_elf()).unwrap();
    let image = Image::parse(&bytes).unwrap();
    let map = flash_map::of(&image);
    let counted: u64 =
        map.modules.iter().map(|m| m.bytes).sum::<u64>() + map.unattributed.iter().map(|u| u.1).sum::<u64>();
    assert_eq!(counted, map.total);
    assert_eq!(map.total, image.flash_bytes());
    assert!(map.modules.iter().any(|m| m.name == "touch_arm::motion"), "{:?}", map.modules);
    eprintln!("{}", map.table(20));
}

/// A bound below what a run measures would be no bound: the product's
/// painted high-water after a calibration change that slews the held pose
/// under the default law (the ζ-a-tₛ plan, whose duration search is the
/// worst chain's tail; `firmware_e2e`'s busiest session slews under the
/// quintic).
#[test]
fn a_slew_under_the_default_law_stays_within_the_bound() {
    let mut s =
        touch_arm_rig::firmware::Session::start(&firmware::default_elf(), touch_arm_rig::panel::PanelWiring::A, 11)
            .expect("firmware ELF (cargo avr)");
    s.run_for(1.5).unwrap();
    assert!(s.command("goto 45 100 -120").unwrap().starts_with("ok goto"));
    s.run_for(4.0).unwrap();
    let reply = s.command("cal set base offset 650").unwrap();
    assert!(reply.starts_with("ok cal set slew ts_ms"), "{reply}");
    s.run_for(0.5).unwrap();
    let used = s.stack_high_water().expect("stack painted at load");
    let bytes = std::fs::read(firmware::default_elf()).unwrap();
    let b = stack_bound::bound(&Image::parse(&bytes).unwrap(), stack_bound::FIRMWARE_RECURSION).unwrap();
    eprintln!("touch-arm: stack high-water {used} B after a slew under the default law; bound {} B", b.total);
    assert!(used as u32 <= b.total, "high-water {used} B above the bound {} B", b.total);
}
