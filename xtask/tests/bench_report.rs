//! `bench-report`, the program `scripts/bench.sh` writes BENCHMARKS.md with,
//! on a real bench run kept in `tests/fixtures/bench/`: the bench firmware's
//! UART output, the display and stack test output, `avr-size -A` of both
//! ELFs and memory.x's budgets. The expected document is the one the
//! script's former Python writer produced from these same files.

use std::path::{Path, PathBuf};
use std::process::Command;

use touch_arm_rig::firmware::parse_section_sizes;
use xtask::bench_report::{render, Accuracy, BenchOutput, Budgets, Inputs, Sizes, UiOutput};

fn fixture(name: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/bench").join(name);
    std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn inputs() -> Inputs {
    Inputs {
        bench: BenchOutput::parse(&fixture("bench-output.txt")),
        ui: UiOutput::parse(&fixture("ui-output.txt")),
        product: Sizes(parse_section_sizes(&fixture("size-touch-arm.txt"))),
        bench_elf: Sizes(parse_section_sizes(&fixture("size-bench.txt"))),
        budgets: Budgets::parse(&fixture("budgets.x")).unwrap(),
        stack_bounds: Vec::new(),
        flash_map: None,
    }
}

#[test]
fn a_real_run_gives_the_python_writers_document_byte_for_byte() {
    let got = render(&inputs()).unwrap();
    let want = fixture("BENCHMARKS.md");
    for (i, (g, w)) in got.lines().zip(want.lines()).enumerate() {
        assert_eq!(g, w, "line {}", i + 1);
    }
    assert_eq!(got, want);
}

#[test]
fn a_real_run_parses_into_its_figures() {
    let i = inputs();
    let routines = i.bench.routines().unwrap();
    assert_eq!(routines.len(), 47);
    let frame = routines.iter().find(|r| r.name == "frame").unwrap();
    assert_eq!((frame.median, frame.min, frame.max, frame.stack), (6778, 3232, 7000, 1228));
    let counts = i.bench.counts().unwrap();
    assert_eq!(counts.len(), 1);
    assert_eq!((counts[0].name.as_str(), counts[0].median), ("via_paper_iterations", 19));
    assert_eq!(i.bench.stamp_overhead(), Ok(11));
    assert_eq!(i.bench.stack(), Ok((1278, 6184)));
    assert_eq!(i.ui.steps.len(), 16);
    assert_eq!(i.ui.firmware_stack.as_deref(), Some("1799"));
    assert_eq!((i.product.flash(), i.product.static_ram()), (116_508, 1708));
    assert_eq!((i.bench_elf.flash(), i.bench_elf.static_ram()), (122_576, 1075));
    // The chip's G and G′ within the 2e-6 of `bench_elf.rs`, exact at tₛ.
    let acc = Accuracy::of(&i.bench).unwrap();
    assert_eq!(acc.samples, 584);
    assert!(acc.g <= 2e-6 && acc.rate <= 2e-6 && acc.g_at_ts == 0.0, "{acc:?}");
    assert!(acc.ln_ulps < 1.0 && acc.atan2_ulps < 1.5 && acc.sqrt_rel < 2f64.powi(-46), "{acc:?}");
}

#[test]
fn a_run_without_its_headline_figures_is_refused() {
    let mut i = inputs();
    i.bench = BenchOutput::parse(&fixture("bench-output.txt").replace("B paper_frame ", "B paper_frame_x "));
    assert_eq!(render(&i).unwrap_err(), "the bench has no `paper_frame` figure");
    i.bench = BenchOutput::parse(&fixture("bench-output.txt").replace("\nO 11\n", "\n"));
    assert_eq!(render(&i).unwrap_err(), "the bench output has no `O` line");
}

#[test]
fn the_program_names_a_missing_input() {
    let missing = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("no-such-bench-output.txt");
    let out = Command::new(env!("CARGO_BIN_EXE_bench-report"))
        .arg("--bench-output")
        .arg(&missing)
        .args(["--ui-output", "/dev/null", "--out", "/dev/null"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.starts_with("bench-report: ") && err.contains("no-such-bench-output.txt"), "{err}");
}
