//! Regression tests of issue #11 ("Reliability under fire") that are Rust
//! rather than scenario files: the longest `status` reply, the screen's
//! settings warnings, and calibration changes while holding. (Torn saves:
//! `store_tearing.rs`; the serial flood and the home pose: scenarios
//! `flood.scn`, `home_pulse_window.scn`.)

use touch_arm::app::text::{Line, LINE_CAP};
use touch_arm::app::{status_line, Refusal, State, Status, TouchTarget};
use touch_arm::config::settings::{PathMode, SpeedPreset};
use touch_arm::config::store::{Source, Warning};
use touch_arm::geometry::workspace::Condition;
use touch_arm::motion::plan::LawKind;
use touch_arm::motion::planner::shape_choice::{AChoice, AKind};

/// The twin's screen: the default 320×240 layout.
const LAY: touch_arm::ui::Layout = touch_arm::ui::Layout::QVGA;

/// `status` with every optional field and the widest numbers a valid
/// configuration allows (angle limits ±360°, so commanded and target angles
/// within ±36000 cdeg; pulses ≤ 2500 µs; tₛ ≤ ts_max = 30 s; α ≤ 180°),
/// for every state, law, preset, warning and refusal: never cut, and the
/// longest fills the line buffer to within a few bytes.
#[test]
fn the_longest_status_fits_its_line() {
    let widest = -2.0 * std::f32::consts::PI;
    let mut longest = (0, String::new());
    for state in State::ALL {
        for law in LawKind::ALL {
            for (speed, (path, lift_centi)) in SpeedPreset::ALL.into_iter().flat_map(|s| {
                [(PathMode::Joint, Some(50)), (PathMode::Joint, None), (PathMode::Line, None)].map(|p| (s, p))
            }) {
                for warning in Warning::ALL {
                    for refusal in Refusal::ALL {
                        let s = Status {
                            state,
                            law,
                            speed,
                            path,
                            lift_centi,
                            commanded: [widest; 3],
                            target: [widest; 3],
                            pulses: Some([4999; 3]),
                            progress: 100,
                            ts: 30.0,
                            a: Some(AChoice { a: 29.0, kind: AKind::MonotoneLimit }),
                            end_velocity: [-50.0; 3],
                            touch_target: Some(TouchTarget {
                                raw_x: 1023,
                                raw_y: 1023,
                                x_p: -1.0,
                                y_p: 0.0,
                                condition: Condition::C4,
                                alpha: std::f32::consts::PI,
                            }),
                            touch_held: true,
                            last_refusal: Some(refusal),
                            config_source: Source::SlotB,
                            config_warning: Some(warning),
                            first_move_pending: true,
                            log: true,
                            grip: widest,
                            grip_target: widest,
                            grip_pulse: Some(4999),
                            grip_moving: true,
                        };
                        let mut line = Line::new();
                        status_line(&s, &mut line);
                        assert!(!line.truncated(), "cut: {:?}", String::from_utf8_lossy(line.as_bytes()));
                        let text = String::from_utf8(line.finish().to_vec()).unwrap();
                        let tail = format!(" refused {}\r\n", refusal.reason().as_str());
                        assert!(text.ends_with(&tail), "{text:?}");
                        assert!(text.contains(" q -36000 -36000 -36000 target -36000 -36000 -36000 "), "{text:?}");
                        assert!(text.contains(" grip -36000"), "{text:?}");
                        if text.len() > longest.0 {
                            longest = (text.len(), text);
                        }
                    }
                }
            }
        }
    }
    eprintln!("longest status: {} bytes of {LINE_CAP}: {:?}", longest.0, longest.1);
    assert!(longest.0 <= LINE_CAP && longest.0 + 8 >= LINE_CAP, "{} bytes, LINE_CAP {LINE_CAP}", longest.0);
}

/// A bounded receive buffer with the chip's drop rule, read at random rates:
/// every non-empty line of the stream is either read intact, in order, or
/// counted in exactly one loss report (`RxLoss::lines`), never both,
/// never neither.
#[test]
fn every_line_is_read_intact_or_counted_lost() {
    use std::collections::VecDeque;
    use touch_arm::protocol::command::LineBuffer;
    use touch_arm::protocol::rx_loss::LossCounter;
    let mut rng = hal_sim::rng::Rng::new(7);
    let (mut intact_total, mut lost_total) = (0u64, 0u64);
    for round in 0..3000 {
        // The stream: lines of 0..20 bytes (spaces included), each ended by
        // \n, \r or \r\n; the reference lines are its non-empty ones.
        let mut stream = Vec::new();
        let mut lines: Vec<(Vec<u8>, std::ops::Range<usize>)> = Vec::new();
        for _ in 0..rng.below(60) {
            let start = stream.len();
            let text: Vec<u8> = (0..rng.below(21)).map(|_| b" abcxyz"[rng.below(7) as usize]).collect();
            stream.extend_from_slice(&text);
            let term: &[u8] = [&b"\n"[..], b"\r", b"\r\n"][rng.below(3) as usize];
            let end = stream.len() + 1;
            stream.extend_from_slice(term);
            if !text.is_empty() {
                lines.push((text, start..end));
            }
        }
        let capacity = 1 + rng.below(40) as usize;
        let (mut ring, mut counter, mut lb) = (VecDeque::new(), LossCounter::new(), LineBuffer::<64>::new());
        let mut kept = vec![false; stream.len()];
        let (mut got, mut lost) = (Vec::new(), 0u64);
        let mut pos = 0;
        while pos < stream.len() || !ring.is_empty() || counter.is_open() {
            for _ in 0..rng.below(12) {
                let Some(&b) = stream.get(pos) else { break };
                let keep = !counter.is_open() && ring.len() < capacity;
                if keep {
                    ring.push_back(b);
                }
                kept[pos] = keep;
                counter.byte(b, keep);
                pos += 1;
            }
            for _ in 0..rng.below(12) {
                match ring.pop_front() {
                    Some(b) => {
                        if let Some(Ok(l)) = lb.push(b) {
                            if !l.is_empty() {
                                got.push(l.to_vec());
                            }
                        }
                    }
                    None => {
                        if let Some(loss) = counter.take() {
                            lb.after_loss(&loss);
                            lost += u64::from(loss.lines);
                        }
                        break;
                    }
                }
            }
        }
        let intact: Vec<Vec<u8>> =
            lines.iter().filter(|(_, r)| r.clone().all(|i| kept[i])).map(|(t, _)| t.clone()).collect();
        assert_eq!(got, intact, "round {round}: the lines read are the intact ones, in order");
        assert_eq!(got.len() as u64 + lost, lines.len() as u64, "round {round}: read + lost = sent");
        intact_total += got.len() as u64;
        lost_total += lost;
    }
    assert!(intact_total > 1000 && lost_total > 1000, "{intact_total} intact, {lost_total} lost");
}

/// Presses the twin's panel at a screen pixel's centre, as read through `cal`,
/// long enough to be confirmed, then lets go.
fn tap_pixel(sim: &mut hal_sim::Sim, cal: &touch_arm::touch::map::Calibration, x: i16, y: i16) {
    let (px, py) = LAY.pixel_center_to_panel(x, y);
    let (rx, ry) = cal.unmap_exact::<f64>(f64::from(px), f64::from(py)).unwrap();
    sim.panel.touch_raw(rx.round(), ry.round(), 1.0).unwrap();
    sim.run_ms(300);
    sim.panel.release();
    sim.run_ms(400);
}

/// The carer lock closes a calibration screen the carer left open (issue
/// #20 §3, left out of its first note): a locked board never shows the
/// crosshairs or the touch settings' page, and a tap where Save was does
/// nothing. The glass returns to the main screen: STOP red, the map drawn.
#[test]
fn locking_closes_an_open_calibration_screen() {
    use touch_arm::touch::map::Calibration;
    use touch_arm::ui::calibration::{cal_pixel, save_area};
    use touch_arm::ui::theme;
    let cal = Calibration::DEFAULT;
    let mut setup = hal_sim::SimSetup::default();
    setup.params.screen = true;
    let mut sim = hal_sim::Sim::new(&setup).unwrap();
    sim.run_ms(1500);
    sim.send_line("access pin 2468");
    sim.run_frames(2);
    assert!(sim.serial.lines().iter().any(|l| l == "ok access pin set seq 1"));
    let centre = |a: touch_arm::ui::draw::Area| (a.x + a.w as i16 / 2, a.y + a.h as i16 / 2);
    let (key, calib) = (centre(LAY.page_key()), centre(LAY.calibrate()));
    for (x, y) in [key, key, calib] {
        tap_pixel(&mut sim, &cal, x, y);
    }
    assert!(sim.serial.lines().iter().any(|l| l == "info screen calibrate"));
    let stop = centre(LAY.stop());
    let (cx, cy) = cal_pixel(&LAY, 0).unwrap();
    let px = |sim: &hal_sim::Sim, x: i16, y: i16| sim.display.as_ref().unwrap().pixel(x.into(), y.into());
    assert_eq!(px(&sim, cx, cy), Some(theme::TEXT), "the first crosshair's centre dot");
    assert_eq!(px(&sim, stop.0, stop.1 - 30), Some(theme::WHITE), "the calibration screen covers STOP");
    sim.send_line("access lock");
    sim.run_ms(1000);
    assert!(sim.serial.lines().iter().any(|l| l == "ok access lock"));
    assert_eq!(px(&sim, stop.0, stop.1 - 30), Some(theme::STOP_RED), "the main screen is back");
    // The five crosshairs and Save, tapped as before, calibrate nothing.
    sim.serial.output.clear();
    for (x, y) in (0..5).filter_map(|i| cal_pixel(&LAY, i)).chain([centre(save_area(&LAY))]) {
        tap_pixel(&mut sim, &cal, x, y);
    }
    assert!(sim.serial.lines().iter().all(|l| !l.starts_with("info cal touch")), "{:?}", sim.serial.lines());
    assert_eq!(sim.app.config().touch, cal);
}

/// Issue #11, defect 3: the screen's calibration Save writes both copies like
/// `cal save`, so the stored-settings warning goes (in `status` and on the
/// screen) as it does after `cal save`.
#[test]
fn the_screens_calibration_save_clears_the_stored_settings_warning() {
    use touch_arm::touch::map::Calibration;
    use touch_arm::ui::calibration::{cal_pixel, save_area};
    let (calibrate, save) = (LAY.calibrate(), save_area(&LAY));
    let mut setup = hal_sim::SimSetup::default();
    setup.params.screen = true;
    let mut sim = hal_sim::Sim::new(&setup).unwrap();
    sim.run_ms(1500);
    let warning = |sim: &hal_sim::Sim| touch_arm::ui::warning_line(sim.app.ui_model().warnings).as_str();
    assert_eq!(warning(&sim), "! default settings in use");
    assert_eq!(sim.app.status().config_warning, Some(Warning::Missing));
    let cal = Calibration::DEFAULT;
    // Calib is on the Setup page: More twice.
    let key = LAY.page_key();
    tap_pixel(&mut sim, &cal, key.x + key.w as i16 / 2, key.y + key.h as i16 / 2);
    tap_pixel(&mut sim, &cal, key.x + key.w as i16 / 2, key.y + key.h as i16 / 2);
    tap_pixel(&mut sim, &cal, calibrate.x + calibrate.w as i16 / 2, calibrate.y + calibrate.h as i16 / 2);
    for (x, y) in (0..5).map(|i| cal_pixel(&LAY, i).unwrap()) {
        tap_pixel(&mut sim, &cal, x, y);
    }
    // Save on the fit's review, then Save on the touch settings' page
    // (the same place), which keeps hold, repeat and radius as they were.
    tap_pixel(&mut sim, &cal, save.x + save.w as i16 / 2, save.y + save.h as i16 / 2);
    assert!(sim.serial.lines().iter().all(|l| !l.starts_with("info cal touch saved")));
    tap_pixel(&mut sim, &cal, save.x + save.w as i16 / 2, save.y + save.h as i16 / 2);
    let lines = sim.serial.lines();
    assert!(lines.iter().any(|l| l == "info screen page more"), "{lines:?}");
    assert!(lines.iter().any(|l| l == "info screen page setup"), "{lines:?}");
    assert!(lines.iter().any(|l| l == "info screen calibrate"), "{lines:?}");
    // The crosshair touches measured the twin's plate ratio, Ry/Rx = 500 / 300 Ω
    // (`hal_sim::panel::PanelModel`) = 1.6667 = 426.67/256, as 426 (1.664:
    // the ADC's quantization and noise at the crosshairs), and saved it with
    // the calibration.
    let saved = "info cal touch saved seq 1 plate 1.66 hold 0.10 repeat 0.30 radius 240";
    assert!(lines.iter().any(|l| l == saved), "{lines:?}");
    assert_eq!(sim.app.config().press.plate, 426);
    assert_eq!(sim.app.status().config_warning, None);
    assert_eq!(warning(&sim), "");
    sim.send_line("status");
    sim.run_frames(2);
    let status = sim.serial.lines().into_iter().rev().find(|l| l.starts_with("ok status")).unwrap();
    assert!(!status.contains(" warn "), "{status}");
}

/// The screen drawn in slices (`ui::slice`): whatever the budget per call,
/// and with the model changing between calls, the glass ends up exactly as
/// an unsliced draw of the last model leaves it; no call draws more than its
/// budget; and the STOP button answers STOP while a redraw towards it is
/// under way.
#[test]
fn sliced_drawing_converges_on_the_unsliced_picture() {
    use hal_sim::display::Framebuffer;
    use touch_arm::ui::demo::{screen, Screen, CONFIG, STEPS};
    use touch_arm::ui::{Hit, PixelBudget, Ui, UiModel, UiState};
    let mut rng = hal_sim::rng::Rng::new(5);
    for budget in [1100u32, 3000, 20_000] {
        let (mut whole, mut sliced) = (Ui::new(&CONFIG), Ui::new(&CONFIG));
        let (mut fa, mut fb) = (Framebuffer::landscape(), Framebuffer::landscape());
        let mut calls = 0u32;
        for k in 0..STEPS {
            let s = screen(k, &LAY);
            match &s {
                Screen::Main(m) => whole.draw(m, &mut fa).unwrap(),
                Screen::Calibration(f) => whole.draw_calibration(f, &mut fa).unwrap(),
            };
            // The sliced UI sees the model of this step with a progress that
            // keeps changing while it draws, then the final one until done.
            loop {
                calls += 1;
                let mut b = PixelBudget { pixels: budget };
                let done = match &s {
                    Screen::Main(m) => {
                        let mut jittered: UiModel = *m;
                        if let UiState::Moving { .. } = m.state {
                            jittered.state = UiState::Moving { progress: rng.uniform() as f32 };
                        }
                        sliced.draw_sliced(&jittered, &mut fb, &mut b).unwrap();
                        let mut b = PixelBudget { pixels: budget };
                        sliced.draw_sliced(m, &mut fb, &mut b).unwrap().finished
                    }
                    Screen::Calibration(f) => sliced.draw_calibration_sliced(f, &mut fb, &mut b).unwrap().finished,
                };
                assert!(calls < 100_000, "no progress");
                if done {
                    break;
                }
            }
            assert!(fa == fb, "budget {budget}, step {k}: the sliced picture differs");
        }
        eprintln!("budget {budget} px: {calls} calls for {STEPS} screens");
    }
    // STOP while the button is being redrawn from RESUME to STOP.
    let mut ui = Ui::new(&CONFIG);
    let mut fb = Framebuffer::landscape();
    let Screen::Main(mut m) = screen(11, &LAY) else { panic!("step 11 is the stopped main screen") };
    ui.draw(&m, &mut fb).unwrap();
    let (x, y) = (LAY.stop().x + 10, LAY.stop().y + 10);
    assert_eq!(ui.hit(x, y), Some(Hit::Resume));
    m.state = UiState::Holding;
    let d = ui.draw_sliced(&m, &mut fb, &mut PixelBudget { pixels: 1000 }).unwrap();
    assert!(!d.finished);
    assert_eq!(ui.hit(x, y), Some(Hit::Stop), "half-drawn STOP counts as STOP");
}

/// `text::decimal`, the integer formatting of every reply and telemetry
/// line (powers of ten subtracted, 16-bit where the value allows), against
/// Rust's own formatting.
#[test]
fn decimal_digits_match_rust_formatting() {
    let mut probe = vec![0u32, 1, 9, 10, 99, 100, 999, 1000, 9999, 10_000, 10_001, 65_535, 65_536, 99_999, 100_000];
    probe.extend([123_456, 1_000_000, 4_294_967_295, 4_000_000_000, 1_000_000_000, 999_999_999]);
    let mut rng = hal_sim::rng::Rng::new(9);
    for _ in 0..20_000 {
        let x = rng.next_u64() as u32;
        probe.push(x >> rng.below(32));
    }
    for v in probe {
        let mut out = [0u8; 10];
        let n = touch_arm::text::decimal(v, &mut out);
        assert_eq!(std::str::from_utf8(&out[..n]).unwrap(), v.to_string(), "{v}");
    }
}
