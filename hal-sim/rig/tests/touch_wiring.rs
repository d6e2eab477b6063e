//! The touch panel's wiring found at run time (issue #14 §2), end to end on
//! the real firmware ELF in simavr: the same ELF with the simulated panel on
//! the pins of wiring a, b and c, a noisy panel, a panel no preset fits, and
//! the wiring stored with the configuration across a power cycle.
//!
//! What the probe must read comes from the panel model (`twin::panel`): a
//! plate of 300 or 500 Ω against the 35 kΩ pull-up reads 8 or 14 counts, an
//! open pair the pull-up alone, 1023 (`examples.rs` checks those counts on
//! the panel-probe example, which runs the same probe).

use touch_arm::config::settings::Config;
use touch_arm::config::store::{RECORD_LEN, SLOT_A_ADDR};
use touch_arm::touch::wiring::{Wiring, ALL_PAIRS, READS};
use touch_arm_rig::firmware::{self, Session, CPU_HZ};
use touch_arm_rig::panel::PanelWiring;

/// The wiring's report and the lines before it, after boot.
fn boot(wiring: PanelWiring, seed: u64, noise: Option<(f64, f64)>) -> Session {
    let mut s = Session::start(&firmware::default_elf(), wiring, seed).expect("firmware ELF (cargo avr)");
    if let Some((sigma, spikes)) = noise {
        s.set_noise(sigma, spikes);
    }
    // The display's start-up first (see `run_until_ready`).
    s.run_for(1.0).unwrap();
    s.run_until_ready(2.0).unwrap();
    s
}

/// The one line the probe's verdict produced.
fn wiring_line(s: &Session) -> String {
    let out = s.avr.uart_output_string();
    let lines: Vec<&str> =
        out.lines().filter(|l| l.starts_with("info wiring") || l.starts_with("err touch wiring")).collect();
    assert_eq!(lines.len(), 1, "{out}");
    lines[0].to_string()
}

/// A touch at raw (x, y) as the panel's own wiring reads it; the firmware's
/// `info touch` reply and, once the move is over, the last pulses.
fn touch_and_settle(s: &mut Session, raw_x: f64, raw_y: f64) -> (String, [Option<f64>; 3]) {
    let from = s.avr.uart_output().len();
    s.press_raw(raw_x, raw_y).unwrap();
    s.run_for(0.2).unwrap();
    // The tap acts on the lift-off (issue #19).
    s.release();
    let line = s.await_line(from, &["info touch", "err touch"], 0.5).unwrap();
    let (line, _) = line.unwrap_or_else(|| panic!("no touch reply:\n{}", s.avr.uart_output_string()));
    let ts_ms: f64 = line.split_whitespace().skip_while(|w| *w != "ts_ms").nth(1).unwrap().parse().unwrap();
    s.run_for(ts_ms / 1000.0 + 0.3).unwrap();
    assert!(s.command("status").unwrap().starts_with("ok status holding"));
    (line, s.last_pulses())
}

/// A map point in condition 2 (method.md §4–5: 0 ≤ x_p < y_p).
const POINT: (f32, f32) = (0.2, 0.6);

#[test]
fn the_same_elf_finds_wirings_a_b_and_c_and_a_touch_moves_the_arm() {
    let ((raw_x, raw_y), _) = firmware::map_touch(POINT.0, POINT.1).expect("on the map");
    let mut ends = Vec::new();
    for (wiring, found) in [(PanelWiring::A, "a"), (PanelWiring::B, "b"), (PanelWiring::C, "b")] {
        let mut s = boot(wiring, 3, None);
        assert_eq!(wiring_line(&s), format!("info wiring {found}"));
        let read = if wiring == PanelWiring::C {
            // c's plates are b's (D6–A2, D7–A1) with X and Y exchanged and
            // reversed, so the probe says b and the firmware reads the
            // panel's X plate as its Y and the other way round, both from
            // the far end: a contact at raw (x, y) of the panel's own wiring
            // reads (1023 − y, 1023 − x) (the model's ADC code of 1 − f for
            // f = (raw + 0.5)/1024). The touch calibration undoes it, as the
            // calibration screen would find: swap, both inversions, and the
            // default limits mirrored (1023 − max .. 1023 − min: x 91..900
            // for 123..932, y 126..895 for 128..897), so the mapped point is
            // the one of wiring a bit for bit.
            for cmd in [
                "cal set touch x_min 91",
                "cal set touch x_max 900",
                "cal set touch y_min 126",
                "cal set touch y_max 895",
                "cal set touch swap 1",
                "cal set touch invert_x 1",
                "cal set touch invert_y 1",
            ] {
                assert!(s.command(cmd).unwrap().starts_with("ok"), "{cmd}");
            }
            (1023.0 - raw_y, 1023.0 - raw_x)
        } else {
            (raw_x, raw_y)
        };
        let (line, end) = touch_and_settle(&mut s, raw_x, raw_y);
        assert!(line.starts_with(&format!("info touch {} {} cond 2 ts_ms", read.0, read.1)), "{found}: {line}");
        ends.push(end);
    }
    // The same point, the same pose: and not the home pose (1500 µs each).
    for end in &ends {
        for j in 0..3 {
            let (a, b) = (ends[0][j].unwrap(), end[j].unwrap());
            assert!((a - b).abs() <= 0.25, "joint {j}: {a} vs {b}");
        }
    }
    assert!(ends[0].iter().any(|p| (p.unwrap() - 1500.0).abs() > 50.0), "{:?}", ends[0]);
}

/// σ = 6 counts of Gaussian noise on every conversion and 2 % of them a
/// random value anywhere in 0..=1023: a plate reads 8 or 14 ± a few counts,
/// far below 256, an open pair 1023 minus a few, far above 768, and a
/// glitch is outvoted by the pair's other two reads.
#[test]
fn a_noisy_panel_is_still_identified() {
    for (wiring, found, seed) in [(PanelWiring::A, "a", 21), (PanelWiring::B, "b", 22)] {
        let s = boot(wiring, seed, Some((6.0, 0.02)));
        assert_eq!(wiring_line(&s), format!("info wiring {found}"));
    }
}

/// Every conversion a random value: no pair reads a consistent verdict, so
/// no preset fits. The firmware says so, leaves the panel unread (a press
/// does nothing) and the arm moves over serial.
#[test]
fn an_unidentified_wiring_is_reported_and_the_arm_stays_usable_over_serial() {
    let mut s = boot(PanelWiring::A, 9, Some((0.0, 1.0)));
    let line = wiring_line(&s);
    let f: Vec<&str> = line.split(' ').collect();
    assert_eq!(&f[..5], ["err", "touch", "wiring", "unknown", "plates"], "{line}");
    let plate = u16::from_str_radix(f[5].trim_start_matches("0x"), 16).unwrap();
    let open = u16::from_str_radix(f[7].trim_start_matches("0x"), 16).unwrap();
    assert_eq!(plate & open, 0, "{line}");
    assert!(plate | open <= ALL_PAIRS);
    assert!(Wiring::ALL.iter().all(|w| plate != w.plates() || open != ALL_PAIRS & !w.plates()), "{line}");
    let before = s.avr.uart_output().len();
    s.press_raw(500.0, 500.0).unwrap();
    s.run_for(0.4).unwrap();
    s.release();
    s.run_for(0.2).unwrap();
    assert!(!s.avr.uart_output_string()[before..].contains("touch"), "{}", s.avr.uart_output_string());
    // The line is unsolicited, like the other `err touch` lines (README rule).
    assert_eq!(hal_sim::random_input::replies_in(&line), 0);
    assert!(s.command("goto 20 150 -30").unwrap().starts_with("ok goto"));
}

/// The probe's verdict is saved with the calibration (record version 3) and
/// read back after a power cycle: the next boot does not probe. Its cost at
/// boot is measured from the ADC conversions it starts.
#[test]
fn the_wiring_is_saved_with_the_calibration_and_survives_a_power_cycle() {
    let mut s = Session::start(&firmware::default_elf(), PanelWiring::B, 4).unwrap();
    let found = s.await_line(0, &["info wiring"], 1.5).unwrap().expect("wiring line");
    assert_eq!(found.0, "info wiring b");
    // No conversion before the probe (the panel is not read without a
    // wiring): its 36 reads are the first, the last just before the verdict.
    let adc = s.adc_count();
    assert_eq!(adc.conversions, READS as u64);
    // Each read: the pins set, the 2 ms settle, one conversion; the first
    // read's settle comes before its conversion.
    let per_read = (adc.last_cycle - adc.first_cycle) as f64 / (READS - 1) as f64;
    let probe_cycles = per_read * READS as f64;
    eprintln!(
        "boot probe: {probe_cycles:.0} cycles ({:.1} ms), {per_read:.0} per read",
        probe_cycles / f64::from(CPU_HZ) * 1e3
    );
    // 2 ms = 32 000 cycles of settle and 13 ADC clocks of 128 cycles
    // (1 664), plus saving, switching and restoring the 13 shield pins and
    // the ADC's 10 µs channel settle when the pair changes: under 5 000.
    assert!((33_664.0..38_664.0).contains(&per_read), "{per_read}");
    s.run_for(0.5).unwrap();
    s.run_until_ready(2.0).unwrap();
    assert!(s.command("cal save").unwrap().starts_with("ok cal save"), "{}", s.avr.uart_output_string());
    let ee = s.avr.eeprom().unwrap();
    let rec = Config::decode(ee[usize::from(SLOT_A_ADDR)..][..RECORD_LEN].try_into().unwrap()).unwrap();
    assert_eq!(rec.config.wiring, Some(Wiring::B));

    // Power cycle: a new chip with the old EEPROM.
    let mut s = Session::start(&firmware::default_elf(), PanelWiring::B, 5).unwrap();
    s.avr.set_eeprom(0, &ee).unwrap();
    s.run_for(1.0).unwrap();
    s.run_until_ready(2.0).unwrap();
    let out = s.avr.uart_output_string();
    assert!(!out.contains("wiring"), "probed again:\n{out}");
    let ((raw_x, raw_y), _) = firmware::map_touch(POINT.0, POINT.1).unwrap();
    let (line, _) = touch_and_settle(&mut s, raw_x, raw_y);
    assert!(line.starts_with(&format!("info touch {raw_x} {raw_y} cond 2")), "{line}");
}

/// From the calibration screen: the probe runs again once the finger that
/// opened it is lifted, one read per frame (36 frames, 0.72 s) while the arm
/// holds, and starts over when a touch (the first crosshair) lands in the
/// middle of it, so the finger never makes it report an unknown wiring; the
/// verdict comes once the panel has been left alone for a whole probe.
#[test]
fn the_calibration_screen_probes_again_and_a_touch_restarts_the_probe() {
    let lay = touch_arm::ui::Layout::QVGA;
    let mut s = boot(PanelWiring::A, 6, None);
    // Calib is on the Setup page: More twice first (button presses, no
    // probe).
    let (kx, ky) = firmware::raw_at_centre(&lay, lay.page_key()).unwrap();
    for page in ["more", "setup"] {
        let from = s.avr.uart_output().len();
        s.press_raw(kx.round(), ky.round()).unwrap();
        s.run_for(0.3).unwrap();
        s.release();
        s.run_for(0.7).unwrap();
        assert_eq!(s.avr.uart_output_string()[from..].trim_end(), format!("info screen page {page}"));
    }
    let c = lay.calibrate();
    let (bx, by) = firmware::raw_at_centre(&lay, c).unwrap();
    let from = s.avr.uart_output().len();
    s.press_raw(bx.round(), by.round()).unwrap();
    s.run_for(0.3).unwrap();
    s.release();
    let t_release = s.avr.time_s();
    // 0.3 s in (15 of the 36 reads), a touch of 0.3 s.
    s.run_for(0.3).unwrap();
    s.press_raw(300.0, 300.0).unwrap();
    s.run_for(0.3).unwrap();
    s.release();
    let t_lift = s.avr.time_s();
    let (line, t) = s.await_line(from, &["info wiring", "err touch wiring"], 1.5).unwrap().expect("a verdict");
    assert_eq!(line, "info wiring a");
    let out = &s.avr.uart_output_string()[from..];
    assert!(out.contains("info screen calibrate"), "{out}");
    // Not before the touch: 36 reads after the lift (and the filter's
    // release confirmation), not 36 after the first release.
    assert!(t - t_release > 0.6 + 0.72, "{t} after a release at {t_release}");
    assert!((0.72..0.72 + 0.2).contains(&(t - t_lift)), "{} s after the lift", t - t_lift);
}
