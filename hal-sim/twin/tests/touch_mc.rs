//! The touch Monte Carlo (`hal_sim::touch_mc`, issue #19 §6) in the test
//! command: short seeded runs of the cells that carry the goals, and the
//! harness's determinism. The long run (10³–10⁴ taps a cell, every goal of
//! §6) is opt-in: `cargo test --release -p hal-sim --test touch_mc --
//! --ignored`; BENCHMARKS.md's table is the same run's figures
//! (`touch-mc`), beside the touch logic before issue #19 ("before").

use hal_sim::touch_mc::{grid, run_cell, Cell, CellStats};

fn cell(name: &str) -> Cell {
    grid().into_iter().find(|c| c.name == name).unwrap_or_else(|| panic!("no cell {name:?}"))
}

#[test]
fn a_steady_tap_commits_once_at_its_point() {
    // 0.5 s and 1.5 s: every tap one move, within 0.25 mm (ADC noise 1
    // count σ; a count is 0.071 mm in x, 0.056 mm in y on the 2.8" glass;
    // the firmware's mean of 3 reads of 5-sample medians).
    for name in ["steady, 0.5 s", "steady, 1.5 s"] {
        let r = run_cell(&cell(name), 25, 7).unwrap();
        assert_eq!((r.taps, r.once, r.none, r.far), (25, 1.0, 0.0, 0), "{r:?}");
        assert_eq!(r.moves, 25);
        let e = r.err_p99_mm.unwrap();
        assert!(e < 0.25, "{name}: p99 {e} mm");
    }
}

#[test]
fn stop_latches_within_60_ms_and_a_frame() {
    // STOP pressed (150 ms) then bounced on: each trial's first contact
    // latches STOP (issue #19 §6: within 60 ms + 1 frame of contact).
    let r = run_cell(&cell("bounces on STOP"), 20, 3).unwrap();
    assert_eq!(r.moves, 0, "{r:?}");
    let latency = r.stop_p99_ms.unwrap();
    assert!(latency <= 60.0 + 20.0, "{latency} ms");
}

#[test]
fn the_harness_is_deterministic_for_a_seed() {
    let c = cell("A 2 mm, 6 Hz, 0.5 s");
    let a: CellStats = run_cell(&c, 12, 42).unwrap();
    assert_eq!(a, run_cell(&c, 12, 42).unwrap());
    assert_eq!(a.taps, 12);
    assert!((0.0..=1.0).contains(&a.once) && a.once + a.none <= 1.0 + 1e-12);
}

/// The cells that carry issue #19 §6's goals, short seeded runs (the long
/// run below has every goal at 10³–10⁴ taps a cell).
#[test]
fn the_goal_cells_hold_on_a_short_run() {
    // A palm beside the finger never moves the arm (the touch calibration
    // measured the panel's plate ratio: `touch_mc::new_sim`); single
    // fingers of 0.1–10× a firm force all commit once.
    let r = run_cell(&cell("palm + finger"), 150, 5).unwrap();
    assert_eq!((r.moves, r.far), (0, 0), "{r:?}");
    let r = run_cell(&cell("single finger, force 0.1-10"), 150, 6).unwrap();
    assert_eq!((r.once, r.moves), (1.0, 150), "{r:?}");
    // Contacts shorter than hold − 20 ms never act; one that ends off the
    // map never moves; a force tremor's flicker is one move.
    let r = run_cell(&cell("contacts 20-80 ms (below hold - 20 ms)"), 100, 8).unwrap();
    assert_eq!(r.moves, 0, "{r:?}");
    let r = run_cell(&cell("slides off the map before lifting"), 40, 9).unwrap();
    assert_eq!(r.moves, 0, "{r:?}");
    let r = run_cell(&cell("force tremor 5 Hz, 50 % duty, 1.5 s"), 40, 10).unwrap();
    assert_eq!(r.once, 1.0, "{r:?}");
}

/// Issue #19 §6's goals over ≥ 10³ taps a cell, 10⁴ where the issue says so
/// (`Cell::taps`; opt-in: about a minute in release). How each goal is read:
/// - "exactly one action per tap under force tremor": exactly one move per
///   tap (`once` = 1); the flicker's other contacts send only `ignored`
///   lines (counted in `actions`), never a second action;
/// - "0 moves from contacts shorter than `hold`": the cell whose contacts
///   all end before `hold` − 20 ms (a read later a contact of `hold` − 20 ms
///   can read as `hold` long: the scenario `hold_boundaries.scn` holds both
///   edges); the 20–140 ms cell straddles `hold` and carries no goal;
/// - palm + finger: with the plate ratio measured by the touch calibration
///   (the set-up the product asks for); the row without it is reported, not
///   a goal.
#[test]
#[ignore = "long run (~1 min in release)"]
fn long_run_meets_the_issue_goals() {
    use hal_sim::touch_mc::Kind;
    let mut failures = Vec::new();
    for (i, c) in grid().iter().enumerate() {
        let r = run_cell(c, c.taps(1000), 19 + i as u64).unwrap();
        let mut fail = |what: String| failures.push(format!("{}: {what}", c.name));
        if let Kind::Tap { amp_mm, contact_ms, slide, .. } = c.kind {
            if r.once < 0.999 && contact_ms >= 500.0 {
                fail(format!("once {:.3}", r.once));
            }
            let limit = match slide {
                Some(_) => 1.0 + 0.25 * amp_mm,
                None if amp_mm <= 3.0 => (0.25 * amp_mm).clamp(0.25, 1.0),
                None => 0.25 * amp_mm,
            };
            if r.err_p99_mm.is_none_or(|e| e > limit) {
                fail(format!("err p99 {:?} > {limit}", r.err_p99_mm));
            }
        }
        match c.kind {
            Kind::Brief { max_ms } if max_ms <= 80.0 && r.moves > 0 => fail(format!("{} moves", r.moves)),
            Kind::OffMap if r.moves > 0 => fail(format!("{} moves", r.moves)),
            Kind::ForceTremor { .. } if r.once < 1.0 => fail(format!("once {:.4}", r.once)),
            Kind::StopBounce if r.releases > 0 || r.taps < 10_000 => {
                fail(format!("{} releases in {}", r.releases, r.taps))
            }
            Kind::StopBounce if r.stop_p99_ms.is_none_or(|ms| ms > 60.0 + 20.0) => {
                fail(format!("STOP p99 {:?} ms", r.stop_p99_ms))
            }
            Kind::Palm { measured: true } if r.far > 0 || r.taps < 10_000 => {
                fail(format!("{} far moves in {}", r.far, r.taps))
            }
            Kind::Force if r.once < 0.999 || r.taps < 10_000 => fail(format!("once {:.4} in {}", r.once, r.taps)),
            _ => {}
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
