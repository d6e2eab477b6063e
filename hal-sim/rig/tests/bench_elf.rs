//! Runs the benchmark firmware in simavr and enforces what a cycle-exact
//! simulator can: the 50 Hz frame fits its cycle budget, the deepest
//! routine's stack high-water fits the bench's stack budget (its free RAM
//! less a margin, `firmware::stack_budget`), and the chip's own f32 results are
//! the host's (`exp`/`expm1`/`ln`/`atan2`/split `sqrt` and whole plans bit for
//! bit) and within 2e-6 of f64 (G, G′).
//! Cycle counts are deterministic, so these are not flaky timing tests.
//!
//! The ELF is built by `scripts/test.sh` (`cargo avr-bench`) before
//! `cargo test` runs; `TOUCH_ARM_BENCH_ELF` overrides its path.

use reference::zat::Zat;
use std::collections::HashMap;
use std::sync::OnceLock;
use touch_arm::geometry::ik::{Branch, Links};
use touch_arm::geometry::pose::{pose_for_point, ArmGeometry};
use touch_arm::math::{exp, fixed, sqrt_split};
use touch_arm::motion::plan::{JointLaw, MultiPlan};
use touch_arm::motion::zat::Shape;
use touch_arm::touch::map::Calibration;
use touch_arm_rig::firmware;

/// Issue target for one 50 Hz frame of 3 joints (0.5 ms at 16 MHz).
const FRAME_BUDGET_CYCLES: u32 = 8_000;

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
    for name in [
        "g",
        "g_rate",
        "plan",
        "app_plan_move",
        "app_plan_move_paper",
        "app_replan",
        "frame_zat_paper",
        "frame_superposed",
        "via_solve",
        "via_paper",
        "frame_linear",
        "frame_cubic",
        "frame_quintic",
        "frame_trapezoid",
        "paper_frame",
    ] {
        assert!(b.contains_key(name), "no {name} figure");
    }
}

/// Issue #13's target for a frame of a straight-line effector move (IK, law
/// and pulses), at its worst.
const PATH_FRAME_BUDGET_CYCLES: u32 = 16_000;

#[test]
fn path_frame_fits_its_cycle_budget() {
    let b = benches();
    let [median, _, max, _] = b["path_frame"];
    eprintln!("path frame: median {median}, max {max} cycles; via frame: {:?}", b["via_frame"]);
    assert!(max <= PATH_FRAME_BUDGET_CYCLES, "path frame worst case {max} cycles > {PATH_FRAME_BUDGET_CYCLES}");
}

/// The deepest routine's high-water against the bench's stack budget (the
/// RAM its static data leaves, less a margin: `firmware::stack_budget` says
/// why it is not the product's 2 KiB). The runner paints before each
/// routine and prints its high-water on its `B` line; the closing `S` line
/// covers only the last routine after its paint.
#[test]
fn stack_high_water_fits_budget() {
    let s = fields("S");
    let closing = u64::from(s[0][0]);
    let b = benches();
    let (name, deepest) = b.iter().map(|(n, v)| (n.as_str(), u64::from(v[3]))).max_by_key(|(_, s)| *s).unwrap();
    let hw = deepest.max(closing);
    // Static RAM as the ELF's sections give it (.data, .bss, .noinit; the
    // ELF reader with the same sum is xtask's, which depends on this crate).
    let static_ram: u64 = firmware::section_sizes(&firmware::bench_elf())
        .unwrap()
        .iter()
        .filter(|(n, _)| matches!(n.as_str(), ".data" | ".bss" | ".noinit"))
        .map(|(_, b)| b)
        .sum();
    let budget = firmware::stack_budget("bench", static_ram).unwrap();
    assert_eq!(budget, 8192 - static_ram - 512);
    eprintln!("stack high-water {hw} B (deepest routine {name}: {deepest} B, closing S {closing} B; budget {budget})");
    assert!(closing > 200, "implausibly small stack figure {closing}: painting broken?");
    assert!(hw <= budget, "stack high-water {hw} B exceeds the bench's stack budget {budget}");
}

#[test]
fn chip_exp_is_the_hosts_bit_for_bit() {
    let e = fields("E");
    assert!(e.len() > 150);
    for v in e {
        let x = f32::from_bits(v[0]);
        assert_eq!(exp::exp(x).to_bits(), v[1], "exp({x})");
        assert_eq!(exp::expm1(x).to_bits(), v[2], "expm1({x})");
    }
}

#[test]
fn chip_mul_hi_approx_is_the_hosts() {
    // The chip's is hand-written assembly, the host's plain Rust.
    let m = fields("M");
    assert!(m.len() >= 128);
    for v in m {
        assert_eq!(fixed::mul_hi_approx(v[0], v[1]), v[2], "mul_hi_approx({:#x}, {:#x})", v[0], v[1]);
    }
}

#[test]
fn chip_profile_within_2e6_of_f64_and_exact_at_ts() {
    let a = fields("A");
    assert!(a.len() > 300);
    let (mut worst_g, mut worst_v, mut at_ts) = (0.0f64, 0.0f64, 0);
    for v in a {
        let [ts, av, n, t, g, r, _paper] = [0, 1, 2, 3, 4, 5, 6].map(|i| f32::from_bits(v[i]) as f64);
        let (gr, vr) = Zat::new(ts, av, n).g_rate(t);
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

#[test]
fn chip_ln_atan2_and_sqrt_split_are_the_hosts_bit_for_bit() {
    let f = f32::from_bits;
    let l = fields("L");
    assert!(l.len() > 150);
    for v in l {
        assert_eq!(exp::ln(f(v[0])).to_bits(), v[1], "ln({:e})", f(v[0]));
    }
    let q = fields("Q");
    assert!(q.len() > 100);
    for v in q {
        let (s, c) = sqrt_split::sqrt_split(f(v[0]));
        assert_eq!((s.to_bits(), c.to_bits()), (v[1], v[2]), "sqrt_split({:e})", f(v[0]));
    }
    let t = fields("T");
    assert!(t.len() > 90);
    for v in t {
        let got = touch_arm::math::atan::atan2(f(v[0]), f(v[1]));
        assert_eq!(got.to_bits(), v[2], "atan2({:e}, {:e})", f(v[0]), f(v[1]));
    }
}

/// The bench's plan inputs, as `src/bin/bench.rs` forms them.
fn plan_input(i: usize) -> (u16, u16, f32) {
    let ts = 1.5 + (4.0 - 1.5) * (i as f32) / 14.0;
    (150 + (i as u16) * 50, 200 + ((i as u16 * 7) % 15) * 40, ts)
}

#[test]
fn chip_plans_are_the_hosts_bit_for_bit() {
    // The whole chain (touch map, pose with its arctangents, a*, the shape and
    // its checks) on the chip equals the host's: a miscompile anywhere in it
    // shows up here (one in `ln` once did).
    #[allow(clippy::approx_constant, reason = "the bench firmware's START literal (src/bin/bench.rs), bit for bit")]
    const START: [f32; 3] = [1.570_796_3, 0.785_398_2, -1.570_796_3];
    let geo = ArmGeometry { k: 1.0f32, links: Links::new(1.0f32, 1.0).unwrap(), branch: Branch::Minus };
    let p = fields("P");
    assert_eq!(p.len(), 15);
    let mut planned = 0;
    for v in p {
        let (rx, ry, ts) = plan_input(v[0] as usize);
        let host = Calibration::DEFAULT.map::<f32>(rx, ry).ok().and_then(|m| {
            let pose = pose_for_point(&geo, m.x_p, m.y_p).ok()?;
            let shape = Shape::smooth_stop(ts, 2.0f32).ok()?;
            MultiPlan::with_law(&START, &[pose.alpha, pose.q2, pose.q3], &JointLaw::Zat(shape)).ok()
        });
        match host {
            Some(plan) => {
                let JointLaw::Zat(s) = plan.law() else { panic!("not a ζ-a-tₛ plan") };
                let t = plan.target().map(f32::to_bits);
                assert_eq!(v[1..], [1, t[0], t[1], t[2], s.a().to_bits()], "plan {}", v[0]);
                planned += 1;
            }
            None => assert_eq!(v[1], 0, "plan {}: the chip planned, the host did not", v[0]),
        }
    }
    // tₛ = 4 with n = 2 is past the smooth stop's monotone range (L·(tₛ − 1) > 2).
    assert_eq!(planned, 14);
}

/// Issue #24, F4: a unit of the path check's bounds between its samples
/// (a visit and the interval bound) stays within the unit the app plans a
/// frame's check for (`app::path_move::UNIT_MAX_TICKS`, 17 500 Timer5 ticks
/// of 8 cycles), as the bisection unit does.
#[test]
fn path_bound_unit_fits_the_check_unit() {
    let b = benches();
    let [median, min, max, stack] = b["path_bound_unit"];
    let unit = b["path_check_unit"];
    eprintln!("path bound unit: median {median}, min {min}, max {max} cycles, stack {stack} B; check unit {unit:?}");
    assert!(max <= 17_500 * 8, "bound unit {max} cycles > the check unit budget");
}

/// A unit `PathCheck::next_is_visit` calls a visit stays within the shorter
/// budget the app plans a frame's visits for
/// (`app::path_move::VISIT_MAX_TICKS`, 8 000 Timer5 ticks of 8 cycles),
/// with a tenth of it to spare.
#[test]
fn path_visit_unit_fits_the_visit_budget() {
    let b = benches();
    let [median, min, max, stack] = b["path_visit_unit"];
    eprintln!("path visit unit: median {median}, min {min}, max {max} cycles, stack {stack} B");
    assert!(max * 10 <= 8_000 * 8 * 9, "visit unit {max} cycles > 90 % of the visit budget");
    // And it is the cheap kind: the units it leaves out take longer.
    assert!(max < b["path_check_unit"][2] && max < b["path_bound_unit"][2]);
}
