//! The scripted finger (`hal_sim::finger`) on the real firmware ELF in
//! simavr: the panel model evaluates the script at each ADC conversion's own
//! cycle, so a finger moving during a read moves between its conversions;
//! and the twin's touch Monte Carlo (`hal_sim::touch_mc`) cross-checked on
//! the ELF with the same scripts for two cells.

use hal_sim::finger::{FingerScript, Knot, Track};
use hal_sim::rng::Rng;
use hal_sim::touch_mc::{self, Kind};
use hal_sim::touches::touch_action;
use touch_arm_rig::avr::AdcMux;
use touch_arm_rig::firmware::{self, Session, CPU_HZ};
use touch_arm_rig::panel::PanelWiring;

fn ready() -> Session {
    let mut s = Session::start(&firmware::default_elf(), PanelWiring::A, 1).expect("firmware ELF (cargo avr)");
    s.run_for(1.0).unwrap();
    s.run_until_ready(2.0).unwrap();
    s
}

/// A slide of 240 px in 200 ms (1.2 px/ms: 3.0 X counts a ms at 809 counts
/// over 320 px). On wiring a X is read on YP (ADC3) and the firmware takes
/// 5 samples of X, Y, z1, z2 a read: each read's X conversions (its 1st,
/// 5th, … conversion) climb with the finger, by 3.0 counts per ms between
/// the first and the last of them.
#[test]
fn a_moving_finger_moves_between_the_conversions_of_one_read() {
    let mut s = ready();
    let from = s.avr.adc_conversions().len();
    let t0 = s.avr.cycles();
    let t = Track::new(vec![Knot::new(0.0, 40.0, 60.0, 1.0), Knot::new(200.0, 280.0, 60.0, 1.0)]).unwrap();
    s.finger(FingerScript::new(t, None).unwrap());
    s.run_for(0.25).unwrap();
    let conv: Vec<_> = s.avr.adc_conversions()[from..].to_vec();
    // Reads: runs of conversions less than 1 ms apart.
    let mut reads: Vec<Vec<_>> = Vec::new();
    for c in conv {
        match reads.last_mut() {
            Some(r) if c.cycle - r.last().map_or(0, |l: &touch_arm_rig::avr::AdcConversion| l.cycle) < 16_000 => {
                r.push(c)
            }
            _ => reads.push(vec![c]),
        }
    }
    let mut checked = 0;
    for r in reads.iter().filter(|r| r.len() == 20) {
        // Inside the script, well clear of its ends.
        let start_ms = (r[0].cycle - t0) as f64 * 1000.0 / f64::from(CPU_HZ);
        if !(5.0..190.0).contains(&start_ms) {
            continue;
        }
        let xs: Vec<(f64, f64)> = r
            .iter()
            .step_by(4)
            .map(|c| {
                assert_eq!(c.mux, AdcMux::Single(3));
                let raw = f64::from(c.millivolts) * 1023.0 / f64::from(c.vref_mv);
                ((c.cycle - t0) as f64 * 1000.0 / f64::from(CPU_HZ), raw)
            })
            .collect();
        assert!(xs.windows(2).all(|p| p[1].1 >= p[0].1), "{xs:?}");
        let (dt, dx) = (xs[4].0 - xs[0].0, xs[4].1 - xs[0].1);
        let expect = 1.2 * dt * 809.0 / 320.0;
        assert!((dx - expect).abs() <= 1.5, "{dx} counts in {dt} ms, expected {expect}");
        checked += 1;
    }
    assert!(checked >= 5, "only {checked} reads inside the slide");
}

/// The twin's Monte Carlo and the ELF agree on the same scripts: a steady
/// 0.5 s tap commits once within 0.25 mm on both, and the share of 2 mm,
/// 6 Hz taps that commit once (the twin: 56 % over 10³ taps) is within 25
/// points of the twin's on the same 16 scripts.
#[test]
fn the_monte_carlo_cross_checks_on_the_elf() {
    let mut s = ready();
    let glass = hal_sim::finger::Glass::QVGA_28;
    let (mmx, mmy) = glass.mm_per_count(&touch_arm::touch::map::Calibration::DEFAULT);
    for (kind, taps) in [
        (Kind::Tap { amp_mm: 0.0, freq_hz: 6.0, contact_ms: 500.0, slide: None }, 4),
        (Kind::Tap { amp_mm: 2.0, freq_hz: 6.0, contact_ms: 500.0, slide: None }, 16),
    ] {
        let mut rng = Rng::new(77);
        let mut twin = touch_mc::new_sim(77).unwrap();
        let (mut once_elf, mut once_twin) = (0, 0);
        for _ in 0..taps {
            let (script, intended) = touch_mc::tap_script(&mut rng, &kind);
            let (ix, iy) = intended.unwrap();
            let end = script.end_ms() / 1000.0 + touch_mc::SETTLE_MS / 1000.0;
            // The ELF.
            let from = s.avr.uart_output().len();
            s.finger(script.clone());
            s.run_for(end).unwrap();
            let text = String::from_utf8_lossy(&s.avr.uart_output()[from..]).to_string();
            let moves: Vec<(u16, u16)> =
                text.lines().filter_map(touch_action).filter(|a| a.action == "move").filter_map(|a| a.raw).collect();
            once_elf += usize::from(moves.len() == 1);
            if kind == (Kind::Tap { amp_mm: 0.0, freq_hz: 6.0, contact_ms: 500.0, slide: None }) {
                assert_eq!(moves.len(), 1, "{text}");
                let (x, y) = moves[0];
                let e = ((f64::from(x) - ix) * mmx).hypot((f64::from(y) - iy) * mmy);
                assert!(e < 0.25, "{e} mm");
            }
            // The twin.
            twin.serial.output.clear();
            twin.finger(script);
            twin.run_ms((end * 1000.0) as u64);
            let n = twin.serial.lines().iter().filter_map(|l| touch_action(l)).filter(|a| a.action == "move").count();
            once_twin += usize::from(n == 1);
        }
        let (e, t) = (once_elf as f64 / taps as f64, once_twin as f64 / taps as f64);
        println!("{kind:?}: once on the ELF {e:.2}, in the twin {t:.2}");
        assert!((e - t).abs() <= 0.25, "ELF {e} vs twin {t}");
    }
}
