//! The UI as the real chip draws it: the `ui-demo` firmware (built by
//! `cargo avr`) runs under simavr with each supported display controller on
//! the shield bus (`touch_arm_rig::lcd_bus`: ILI9341, ST7789V, ILI9486, ILI9325),
//! probes it, and after every step of the `touch_arm::ui::demo` script the
//! decoded screen must equal, pixel for pixel, the host rendering of the
//! same step in that controller's layout. The draw times the firmware
//! measures and the bus speed are reported and bounded.

use std::path::PathBuf;

use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use hal_sim::display::Framebuffer;
use touch_arm::ui::demo::{self, Screen};
use touch_arm::ui::Ui;
use touch_arm_rig::avr::Avr;
use touch_arm_rig::lcd_bus::{cmd, BusPins, Chip, LcdBus};

fn demo_elf() -> PathBuf {
    let elf = touch_arm_rig::firmware::ui_demo_elf();
    assert!(
        elf.exists(),
        "{} missing: build the firmware first with `cargo avr` (scripts/test.sh does)",
        elf.display()
    );
    elf
}

/// Cycles the firmware reports for step `k` (`S <k> <cycles> <ok>`).
fn step_cycles(avr: &mut Avr, k: u8) -> u64 {
    let line = avr.take_lines().into_iter().find(|l| l.starts_with("S ")).expect("step line");
    let f: Vec<&str> = line.split_whitespace().collect();
    assert_eq!(f.len(), 4, "{line}");
    assert_eq!(f[1].parse::<u8>().unwrap(), k, "{line}");
    assert_eq!(f[3], "1", "draw reported an error: {line}");
    f[2].parse().unwrap()
}

/// What one run of the script on one controller measured.
struct DemoRun {
    bus: LcdBus,
    avr: Avr,
    /// Per step: (step, cycles, pixels, commands).
    report: Vec<(u8, u64, u64, u64)>,
    /// Cycles the firmware measured for probe + initialisation.
    start_cycles: u64,
}

/// Runs the ui-demo ELF with `chip` on the bus; after every step the decoded
/// screen must equal the host rendering of the step in the chip's layout.
fn run_demo(chip: Chip) -> DemoRun {
    let mut avr = Avr::load(demo_elf(), "atmega2560", 16_000_000).unwrap();
    avr.paint_stack(0xA5).unwrap();
    let bus = LcdBus::attach_chip(&mut avr, BusPins::MEGA_SHIELD, chip).unwrap();
    let banner = format!("ui-demo {}\n", demo::STEPS);
    avr.run_until_output(banner.as_bytes(), 16_000_000 * 2).unwrap();
    let lines = avr.take_lines();
    let start = lines.iter().find(|l| l.starts_with("lcd ")).expect("lcd line");
    let f: Vec<&str> = start.split_whitespace().collect();
    assert_eq!(f[1], "1", "{}: the probe found the controller ({start})", chip.name());
    let start_cycles = f[3].parse().unwrap();
    let lay = chip.layout();
    let mut ui = Ui::with_layout(&demo::CONFIG, lay);
    let mut fb = Framebuffer::new(lay.width().into(), lay.height().into(), Rgb565::BLACK);
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/ui-snapshots");
    let mut report = Vec::new();
    for k in 0..demo::STEPS {
        let before = bus.stats();
        avr.uart_send(b"g");
        let needle = format!("S {k} ");
        let line_done = |a: &Avr| {
            let out = a.uart_output_string();
            out.find(&needle).is_some_and(|i| out[i..].contains('\n'))
        };
        avr.run_until(line_done, 16_000_000 * 2).unwrap_or_else(|e| panic!("{} step {k}: {e}", chip.name()));
        let cycles = step_cycles(&mut avr, k);
        match demo::screen(k, &lay) {
            Screen::Main(m) => ui.draw(&m, &mut fb).unwrap(),
            Screen::Calibration(f) => ui.draw_calibration(&f, &mut fb).unwrap(),
        };
        let chip_fb = bus.landscape();
        let name = chip.name();
        if chip_fb != fb {
            chip_fb.save_png(dir.join(format!("chip_{name}_step{k}.png"))).unwrap();
            fb.save_png(dir.join(format!("host_{name}_step{k}.png"))).unwrap();
            let diff = fb.pixels().iter().zip(chip_fb.pixels()).filter(|(a, b)| a != b).count();
            panic!(
                "{name} step {k}: the decoded screen differs from the host rendering in {diff} pixels (PNGs written)"
            );
        }
        let after = bus.stats();
        report.push((k, cycles, after.pixels - before.pixels, after.commands - before.commands));
        if k == 0 || k == demo::STEPS - 1 || k == 13 {
            chip_fb.save_png(dir.join(format!("chip_{name}_step{k}.png"))).unwrap();
        }
    }
    let s = bus.stats();
    assert_eq!(s.undriven_writes, 0);
    assert_eq!(s.pixels_clipped, 0);
    assert_eq!(s.stray_data, 0);
    assert_eq!(s.wrong_format, 0);
    assert_eq!(s.read_conflicts, 0, "the data lines are inputs whenever RD is low");
    assert!(bus.model().display_on());
    avr.uart_send(b"g");
    avr.run_until_output(b"done\n", 16_000_000).unwrap();
    DemoRun { bus, avr, report, start_cycles }
}

#[test]
fn the_chip_draws_exactly_what_the_host_renders() {
    let run = run_demo(Chip::Ili9341);
    let (bus, avr, report) = (&run.bus, &run.avr, &run.report);
    {
        let lcd = bus.lcd();
        assert!(!lcd.sleeping && lcd.display_on, "init leaves the display awake and on");
        assert_eq!(lcd.colmod, 0x55);
        assert_eq!(lcd.madctl, 0x28, "landscape, BGR");
        // The ID probe (register 0000h, Read ID4, RDDID, each after a NOP),
        // then the initialisation.
        let probe = [cmd::NOP, cmd::NOP, cmd::NOP, cmd::RDID4, cmd::NOP, cmd::RDDID];
        let init = [cmd::SWRESET, cmd::SLPOUT, cmd::COLMOD, cmd::MADCTL, cmd::DISPON];
        assert_eq!(&lcd.command_log[..11], &[&probe[..], &init[..]].concat()[..]);
        assert_eq!(lcd.stats.hardware_resets, 1);
        // 2 + 4 + 4 strobes; the ILI9341 answers the 8 of D3h and 04h.
        assert_eq!((lcd.stats.reads, lcd.stats.reads_answered), (10, 8));
    }
    eprintln!("lcd: ili9341 probe and initialisation {:.1} ms", run.start_cycles as f64 / 16_000.0);
    let s = bus.stats();
    let per_byte = s.cycles_per_stream_byte().unwrap();
    eprintln!(
        "bus: {per_byte:.2} cycles per pixel byte on average inside RAMWR streams, fastest strobe gap {} cycles",
        s.min_gap_cycles.map_or("none".to_string(), |g| g.to_string())
    );
    // One write, so the other test's lines cannot split the table
    // (scripts/bench.sh parses it).
    let mut table = String::from("step  cycles      ms   pixels  commands\n");
    for (k, c, p, n) in report {
        table += &format!("{k:>4} {c:>8} {:>7.2} {p:>8} {n:>9}\n", *c as f64 / 16_000.0);
    }
    eprint!("{table}");
    let (stack, margin) = avr.stack_high_water().unwrap();
    eprintln!("stack: {stack} bytes at the deepest, {margin} bytes never touched");
    assert!(stack < 1024, "the UI needs {stack} bytes of stack");
    // The goal: at most 30 cycles per byte on the bus.
    assert!(per_byte <= 30.0, "{per_byte:.1} cycles per byte");
    // A full redraw (step 0) paints every pixel at least once, in about
    // 170 ms (the pixel stores alone are ~1.2 M cycles).
    let (_, full_cycles, full_pixels, _) = report[0];
    assert!(full_pixels >= 320 * 240);
    assert!(full_cycles < 3_500_000, "full redraw {full_cycles} cycles");
    // A progress step repaints a few bar columns and the percentage: a
    // fraction of a full redraw, and well inside one 20 ms servo frame.
    let (_, step_cycles, step_pixels, _) = report[3];
    assert!(step_pixels < 52 * 16 + 12 * 40, "{step_pixels}");
    assert!(
        step_cycles < full_cycles / 20 && step_cycles < 100_000,
        "progress step {step_cycles} vs full {full_cycles}"
    );
}

/// The same script on every other supported controller: probed, initialised
/// and drawn through its own protocol and size, pixel for pixel the host's
/// rendering in that controller's layout.
#[test]
fn every_controller_draws_exactly_what_the_host_renders() {
    let mut table = String::from(
        "controller  probe+init ms  full redraw ms  progress step ms  slowest step ms  pixels (full)  commands (full)\n",
    );
    for chip in [Chip::St7789, Chip::Ili9486, Chip::Ili9325] {
        let run = run_demo(chip);
        let (_, full, pixels, commands) = run.report[0];
        let (_, step, _, _) = run.report[3];
        let slowest = run.report.iter().map(|r| r.1).max().unwrap();
        let (w, h) = chip.landscape_size();
        let ms = |c: u64| c as f64 / 16_000.0;
        table += &format!(
            "{:<10} {:>13.1} {:>15.1} {:>17.2} {:>16.1} {pixels:>14} {commands:>16}\n",
            chip.name(),
            ms(run.start_cycles),
            ms(full),
            ms(step),
            ms(slowest)
        );
        assert!(pixels >= u64::from(w) * u64::from(h), "{}: a full redraw paints every pixel", chip.name());
        // Every draw, full ones included, stays well inside the watchdog's
        // 500 ms, with room for a planning frame.
        assert!(slowest < 16_000 * 400, "{}: a draw took {slowest} cycles", chip.name());
        // The 3× percentage on the 480×320 screen makes the step larger;
        // it stays within half a 20 ms servo frame.
        assert!(step < 160_000, "{}: progress step {step} cycles", chip.name());
    }
    eprint!("{table}");
}
