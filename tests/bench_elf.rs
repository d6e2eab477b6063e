//! Runs the benchmark firmware in simavr and enforces what a cycle-exact
//! simulator can: the 50 Hz frame fits its cycle budget, the stack high-water
//! mark fits `__budget_stack` from memory.x, and the chip's own f32 results are
//! the host's (`exp`/`expm1` bit for bit) and within 2e-6 of f64 (G, G′).
//! Cycle counts are deterministic, so these are not flaky timing tests.
//!
//! The ELF is built by `scripts/test.sh` (`cargo avr-bench`) before
//! `cargo test` runs; `TOUCH_ARM_BENCH_ELF` overrides its path.

use std::collections::HashMap;
use std::sync::OnceLock;
use hal_sim::firmware;
use touch_arm::f32_exp;

/// Issue target for one 50 Hz frame of 3 joints (0.5 ms at 16 MHz).
const FRAME_BUDGET_CYCLES: u32 = 8_000;

fn budget(name: &str) -> u64 {
    firmware::budget(name).unwrap()
}

/// The bench firmware's UART lines, from one run in the simavr harness.
fn output() -> &'static Vec<String> {
    static OUT: OnceLock<Vec<String>> = OnceLock::new();
    OUT.get_or_init(|| {
        let elf = firmware::bench_elf();
        assert!(elf.exists(), "{} missing: build it with `cargo avr-bench` (scripts/test.sh does)", elf.display());
        let text = firmware::run_to_done(&elf, 300.0).unwrap();
        let lines: Vec<String> = text.lines().map(|l| l.trim().to_string()).collect();
        assert!(!lines.iter().any(|l| l.starts_with("PANIC")), "bench firmware panicked");
        lines
    })
}

/// `B <name> <median> <min> <max> <stack>` lines by name.
fn benches() -> HashMap<String, [u32; 4]> {
    output()
        .iter()
        .filter_map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (f.len() == 6 && f[0] == "B").then(|| {
                let n: Vec<u32> = f[2..].iter().map(|v| v.parse().unwrap()).collect();
                (f[1].to_string(), [n[0], n[1], n[2], n[3]])
            })
        })
        .collect()
}

fn fields(tag: &str) -> Vec<Vec<u32>> {
    output()
        .iter()
        .filter_map(|l| {
            let mut it = l.split_whitespace();
            (it.next() == Some(tag)).then(|| it.map(|v| v.parse().unwrap()).collect())
        })
        .collect()
}

#[test]
fn frame_fits_its_cycle_budget() {
    let b = benches();
    let [median, _, max, _] = b["frame"];
    eprintln!("frame: median {median}, max {max} cycles");
    assert!(max <= FRAME_BUDGET_CYCLES, "frame worst case {max} cycles > {FRAME_BUDGET_CYCLES}");
    // Every routine the runner reports was measured.
    for name in ["g", "g_rate", "plan", "via_solve", "via_paper", "frame_linear", "frame_cubic", "frame_quintic", "frame_trapezoid", "paper_frame"] {
        assert!(b.contains_key(name), "no {name} figure");
    }
}

#[test]
fn stack_high_water_fits_budget() {
    let s = fields("S");
    let hw = u64::from(s[0][0]);
    eprintln!("stack high-water {hw} B (budget {})", budget("stack"));
    assert!(hw > 200, "implausibly small stack figure {hw}: painting broken?");
    assert!(hw <= budget("stack"), "stack high-water {hw} B exceeds the memory.x budget {}", budget("stack"));
}

#[test]
fn chip_exp_is_the_hosts_bit_for_bit() {
    let e = fields("E");
    assert!(e.len() > 150);
    for v in e {
        let x = f32::from_bits(v[0]);
        assert_eq!(f32_exp::exp(x).to_bits(), v[1], "exp({x})");
        assert_eq!(f32_exp::expm1(x).to_bits(), v[2], "expm1({x})");
    }
}

#[test]
fn chip_profile_within_2e6_of_f64_and_exact_at_ts() {
    let a = fields("A");
    assert!(a.len() > 300);
    let (mut worst_g, mut worst_v, mut at_ts) = (0.0f64, 0.0f64, 0);
    for v in a {
        let [ts, av, n, t, g, r, _paper] = [0, 1, 2, 3, 4, 5, 6].map(|i| f32::from_bits(v[i]) as f64);
        let l = n.ln();
        let u = t + ts / t - 1.0;
        let ln_q = |w: f64| -(l * w).exp_m1().ln();
        let gr = if t >= ts { 1.0 } else { (l * (t - ts) + ln_q(u - av) - ln_q(ts - av)).exp() };
        let q = 1.0 / (l * (u - av)).exp_m1();
        let vr = gr * (l - l * (1.0 - ts / (t * t)) * (1.0 + q));
        if t == ts {
            assert_eq!(g, 1.0, "G(tₛ) on the chip");
            at_ts += 1;
        }
        worst_g = worst_g.max((g - gr).abs());
        worst_v = worst_v.max((r - vr).abs() / vr.abs().max(1.0));
    }
    eprintln!("chip: worst |G − f64| {worst_g:e}, G′ {worst_v:e}");
    assert!(at_ts > 30);
    assert!(worst_g <= 2e-6 && worst_v <= 2e-6);
}
