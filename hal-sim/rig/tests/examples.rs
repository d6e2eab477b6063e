//! The board examples (`examples/`, built by `cargo avr`) in simavr: the
//! panel probe against the simulated panel on the shield pins, the servo
//! sweep with its pulses measured on the Timer5 pins. Expected values come
//! from the panel model's resistances and the default calibration here.

use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use embedded_graphics::prelude::{Point, Size};
use embedded_graphics::primitives::Rectangle;
use hal_sim::panel::{PanelModel, R_PULLUP};
use touch_arm::touch::filter::FilterConfig;
use touch_arm_rig::avr::Pin;
use touch_arm_rig::firmware::{self, Session, CPU_HZ};
use touch_arm_rig::lcd_bus::{cmd, BusPins, LcdBus};
use touch_arm_rig::panel::PanelWiring;

fn start(name: &str, wiring: PanelWiring) -> Session {
    Session::start(&firmware::example_elf(name), wiring, 5).expect("example ELF (cargo avr)")
}

/// Runs until `needle` has been printed (at most `seconds` of chip time).
fn run_until_printed(s: &mut Session, needle: &str, seconds: f64) -> String {
    let max = (seconds * f64::from(CPU_HZ)) as u64;
    if let Err(e) = s.avr.run_until_output(needle.as_bytes(), max) {
        panic!("no {needle:?} within {seconds} s ({e:?}):\n{}", s.avr.uart_output_string());
    }
    s.avr.uart_output_string()
}

/// The count a plate of `r` ohms reads against the pull-up (the probe's
/// sense pin), as the simulated 10-bit ADC converts it.
fn plate_count(r: f64) -> u16 {
    (1024.0 * r / (r + R_PULLUP)).floor() as u16
}

/// The probe's `link` lines as (drive, sense, count, verdict).
fn links(out: &str) -> Vec<(String, String, u16, String)> {
    out.lines()
        .filter_map(|l| {
            let f: Vec<&str> = l.strip_prefix("link ")?.split(' ').collect();
            Some((f[0].to_string(), f[1].to_string(), f[2].parse().ok()?, f[3].to_string()))
        })
        .collect()
}

/// Every pair of the probe's table with what it must read: the two plates
/// (X: X+ to X−, Y: Y− to Y+) at their divider against the pull-up, every
/// other pair open (the pull-up alone: 1023).
fn expected_links(x_plate: (&str, &str), y_plate: (&str, &str)) -> Vec<(String, String, u16, String)> {
    let m = PanelModel::default();
    let mut v = Vec::new();
    for d in ["D6", "D7", "D8", "D9"] {
        for s in ["A1", "A2", "A3"] {
            let (count, verdict) = if (d, s) == x_plate {
                (plate_count(m.rx), "plate")
            } else if (d, s) == y_plate {
                (plate_count(m.ry), "plate")
            } else {
                (1023, "open")
            };
            v.push((d.to_string(), s.to_string(), count, verdict.to_string()));
        }
    }
    v
}

fn matches(out: &str) -> Vec<&str> {
    out.lines().filter_map(|l| l.strip_prefix("match ")).collect()
}

#[test]
fn panel_probe_detects_wiring_a_and_prints_raw_readings() {
    let mut s = start("panel-probe", PanelWiring::A);
    let out = run_until_printed(&mut s, "reading: touch the screen\n", 1.0);
    assert_eq!(links(&out), expected_links(("D8", "A2"), ("D9", "A3")), "{out}");
    // The plates read 8 and 14 counts (300 and 500 Ω against 35 kΩ).
    assert_eq!((plate_count(300.0), plate_count(500.0)), (8, 14));
    assert_eq!(matches(&out), ["a"], "{out}");

    // A press: the probe reads the panel through the detected wiring.
    let before = out.len();
    s.press_raw(549.0, 745.0).unwrap();
    s.run_for(0.35).unwrap();
    s.release();
    s.run_for(0.2).unwrap();
    let out = s.avr.uart_output_string();
    let raws: Vec<Vec<u16>> = out[before..]
        .lines()
        .filter_map(|l| l.strip_prefix("raw "))
        .map(|l| l.split(' ').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert!((3..=4).contains(&raws.len()), "{out}");
    for r in &raws {
        assert_eq!((r[0], r[1]), (549, 745), "{out}");
        assert!(r[2] >= FilterConfig::DEFAULT.z_min, "{out}");
    }
    // The LED (D13 = PB7, an embedded-hal OutputPin) toggles per reading.
    let led = s.avr.pin_level(Pin::new('B', 7)).unwrap();
    assert_eq!(led, raws.len() % 2 == 1);
}

#[test]
fn panel_probe_finds_b_and_c_on_a_shield_wired_b() {
    let mut s = start("panel-probe", PanelWiring::B);
    let out = run_until_printed(&mut s, "reading: touch the screen\n", 1.0);
    assert_eq!(links(&out), expected_links(("D6", "A2"), ("D7", "A1")), "{out}");
    // Same two plates, X and Y exchanged: the calibration's swap tells them apart.
    assert_eq!(matches(&out), ["b", "c"], "{out}");
}

/// Default window: 600..2400 µs for every joint (`JointCal::DEFAULTS`).
#[test]
fn servo_sweep_covers_the_window_and_only_the_chosen_joint() {
    let mut s = start("servo-sweep", PanelWiring::A);
    let out = run_until_printed(&mut s, "end base 600\n", 4.0);
    assert!(out.starts_with("window base 600 2400 defaults\nend base 2400\nend base 600\n"), "{out}");
    // A width set now is latched at the next period start and measured at its end.
    s.run_for(0.045).unwrap();
    let [base, shoulder, elbow] = s.pulses();
    let widths: Vec<f64> = base.iter().map(|p| p.1).collect();
    let (lo, hi) = widths.iter().fold((f64::MAX, f64::MIN), |(lo, hi), w| (lo.min(*w), hi.max(*w)));
    assert!((lo - 600.0).abs() <= 0.25 && (hi - 2400.0).abs() <= 0.25, "{lo} .. {hi}");
    // 20 µs per 20 ms step, so neighbouring pulses differ by at most that.
    assert!(widths.windows(2).all(|w| (w[1] - w[0]).abs() <= 20.25), "{widths:?}");
    assert!(shoulder.is_empty() && elbow.is_empty());

    // Key `1`: the shoulder sweeps from the middle of its window up; the
    // base holds its last pulse.
    s.avr.uart_send(b"1");
    let out = run_until_printed(&mut s, "end shoulder 2400\n", 2.0);
    assert!(out.contains("window shoulder 600 2400 defaults\n"), "{out}");
    let [base, shoulder, _] = s.pulses();
    let held = base[widths.len() + 2..].iter().map(|p| p.1);
    assert!(held.clone().count() > 40 && held.clone().all(|w| (w - base.last().unwrap().1).abs() <= 0.25));
    assert!((shoulder[0].1 - 1520.0).abs() <= 0.25, "{:?}", shoulder[0]);
    assert!(shoulder.iter().all(|p| (599.75..=2400.25).contains(&p.1)));
}

/// Key `3` sweeps the gripper on D11 (OC1A, Timer1) over the servo range,
/// 500..2500 µs (it has no calibration yet), at 0.5 µs resolution, and its
/// pulses start with the base's: Timer1 runs with Timer5's TOP (39999) and
/// prescaler (8) and was started with it. The harness stamps an edge 0 to 4
/// cycles late; simavr starts each timer at the write of its clock select
/// (it does not model GTCCR's TSM, which on the chip releases both on the
/// same prescaler edge), 2 cycles apart: so the rises differ by less than
/// one tick (8 cycles) here and by none on the chip.
#[test]
fn servo_sweep_drives_the_gripper_on_timer1_aligned_with_timer5() {
    let mut s = start("servo-sweep", PanelWiring::A);
    run_until_printed(&mut s, "end base 2400\n", 2.0);
    assert!(s.grip_pulse_ticks().is_empty(), "the gripper is limp until swept");
    s.avr.uart_send(b"3");
    let out = run_until_printed(&mut s, "end grip 2500\n", 3.0);
    assert!(out.contains("window grip 500 2500 servo-range\n"), "{out}");
    s.run_for(0.1).unwrap();
    let grip = s.grip_pulse_ticks();
    // From the middle of the window (3000 ticks) up in steps of 40 ticks
    // (20 µs per 20 ms; the first pulse is one step in), every width on the
    // 0.5 µs grid.
    assert!(grip.len() > 40, "{}", grip.len());
    assert!(grip.iter().all(|(_, t)| (1000..=5000).contains(t)), "{grip:?}");
    assert_eq!(grip[0].1, 3040);
    assert!(grip.windows(2).all(|w| w[1].1.abs_diff(w[0].1) <= 40), "{grip:?}");
    assert!(grip.iter().any(|(_, t)| *t == 5000));
    // The base holds its last pulse meanwhile; every gripper rise has a base
    // rise within a tick.
    let base: Vec<u64> = s.avr.pulses(firmware::SERVO_PINS[0]).iter().map(|p| p.rise_cycle).collect();
    let rises: Vec<u64> = s.avr.pulses(firmware::GRIPPER_PIN).iter().map(|p| p.rise_cycle).collect();
    assert_eq!(rises.len(), grip.len());
    for r in &rises {
        let nearest = base.iter().map(|b| b.abs_diff(*r)).min().unwrap();
        assert!(nearest < 8, "a gripper pulse {nearest} cycles off the base's");
    }
}

/// The `mipidsi` feature's example: mipidsi's ILI9341 driver through the
/// shield bus. The decoded controller must hold a blue screen with a red
/// 100×50 rectangle at (10, 20) of the landscape view.
#[test]
fn mipidsi_draws_through_the_shield_bus() {
    let elf = firmware::example_elf("mipidsi-fill");
    assert!(elf.exists(), "{} missing: build it with `cargo avr-mipidsi` (scripts/test.sh does)", elf.display());
    let mut avr = firmware::load(&elf).unwrap();
    let bus = LcdBus::attach(&mut avr, BusPins::MEGA_SHIELD).unwrap();
    avr.run_until_output(b"done\n", u64::from(CPU_HZ)).unwrap();
    let lcd = bus.lcd();
    assert!(!lcd.sleeping && lcd.display_on);
    // The firmware's own landscape and 16-bit pixels; SWRESET first (no RST pin).
    assert_eq!((lcd.madctl, lcd.colmod), (0x28, 0x55));
    assert_eq!(lcd.command_log.first(), Some(&cmd::SWRESET));
    let st = lcd.stats;
    assert_eq!((st.stray_data, st.wrong_format, st.pixels_clipped, st.undriven_writes), (0, 0, 0, 0));
    assert_eq!(st.pixels, 320 * 240 + 100 * 50);
    drop(lcd);
    let fb = bus.landscape();
    let whole = Rectangle::new(Point::zero(), Size::new(320, 240));
    let rect = Rectangle::new(Point::new(10, 20), Size::new(100, 50));
    assert_eq!(fb.count_in(&rect, Rgb565::RED), 100 * 50);
    assert_eq!(fb.count_in(&whole, Rgb565::BLUE), 320 * 240 - 100 * 50);
}
