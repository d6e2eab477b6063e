//! The UI as the real chip draws it: the `ui-demo` firmware (built by
//! `cargo avr`) runs under simavr, its ILI9341 bus is decoded from the
//! shield pins (`hal_sim::lcd_bus`), and after every step of the
//! `touch_arm::ui::demo` script the decoded screen must equal, pixel for
//! pixel, the host rendering of the same step. The draw times the firmware
//! measures and the bus speed are reported and bounded.

use std::path::PathBuf;

use hal_sim::avr::Avr;
use hal_sim::display::Framebuffer;
use hal_sim::lcd_bus::{cmd, BusPins, LcdBus};
use touch_arm::ui::demo::{self, Screen};
use touch_arm::ui::{Layout, Ui};

fn demo_elf() -> PathBuf {
    let elf = hal_sim::firmware::ui_demo_elf();
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

#[test]
fn the_chip_draws_exactly_what_the_host_renders() {
    let mut avr = Avr::load(demo_elf(), "atmega2560", 16_000_000).unwrap();
    avr.paint_stack(0xA5).unwrap();
    let bus = LcdBus::attach(&mut avr, BusPins::MEGA_SHIELD).unwrap();
    let banner = format!("ui-demo {}\n", demo::STEPS);
    avr.run_until_output(banner.as_bytes(), 16_000_000 * 2).unwrap();
    avr.take_lines();
    {
        let lcd = bus.lcd();
        assert!(!lcd.sleeping && lcd.display_on, "init leaves the display awake and on");
        assert_eq!(lcd.colmod, 0x55);
        assert_eq!(lcd.madctl, 0x28, "landscape, BGR");
        assert_eq!(&lcd.command_log[..], &[cmd::SWRESET, cmd::SLPOUT, cmd::COLMOD, cmd::MADCTL, cmd::DISPON]);
        assert_eq!(lcd.stats.hardware_resets, 1);
    }
    let mut ui = Ui::new(&demo::CONFIG);
    let mut fb = Framebuffer::landscape();
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/ui-snapshots");
    let mut report = Vec::new();
    for k in 0..demo::STEPS {
        let before = bus.stats();
        avr.uart_send(b"g");
        let needle = format!("S {k} ");
        let line_done = |a: &Avr| {
            let out = a.uart_output_string();
            out.find(&needle).is_some_and(|i| out[i..].contains('\n'))
        };
        avr.run_until(line_done, 16_000_000 * 2).unwrap_or_else(|e| panic!("step {k}: {e}"));
        let cycles = step_cycles(&mut avr, k);
        match demo::screen(k, &Layout::QVGA) {
            Screen::Main(m) => ui.draw(&m, &mut fb).unwrap(),
            Screen::Calibration(f) => ui.draw_calibration(&f, &mut fb).unwrap(),
        };
        let chip = bus.landscape();
        if chip != fb {
            chip.save_png(dir.join(format!("chip_step{k}.png"))).unwrap();
            fb.save_png(dir.join(format!("host_step{k}.png"))).unwrap();
            let diff = (0..240)
                .flat_map(|y| (0..320).map(move |x| (x, y)))
                .filter(|&(x, y)| chip.pixel(x, y) != fb.pixel(x, y))
                .count();
            panic!("step {k}: the decoded screen differs from the host rendering in {diff} pixels (PNGs written)");
        }
        let after = bus.stats();
        let pixels = after.pixels - before.pixels;
        let commands = after.commands - before.commands;
        report.push((k, cycles, pixels, commands));
        if k == 0 || k == demo::STEPS - 1 || k == 13 {
            chip.save_png(dir.join(format!("chip_step{k}.png"))).unwrap();
        }
    }
    let s = bus.stats();
    assert_eq!(s.undriven_writes, 0);
    assert_eq!(s.pixels_clipped, 0);
    assert_eq!(s.stray_data, 0);
    assert_eq!(s.wrong_format, 0);
    let per_byte = s.cycles_per_stream_byte().unwrap();
    eprintln!(
        "bus: {per_byte:.2} cycles per pixel byte on average inside RAMWR streams, fastest strobe gap {:?} cycles",
        s.min_gap_cycles
    );
    eprintln!("step  cycles      ms   pixels  commands");
    for (k, c, p, n) in &report {
        eprintln!("{k:>4} {c:>8} {:>7.2} {p:>8} {n:>9}", *c as f64 / 16_000.0);
    }
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
    assert!(step_pixels < 72 * 16 + 12 * 40, "{step_pixels}");
    assert!(
        step_cycles < full_cycles / 20 && step_cycles < 100_000,
        "progress step {step_cycles} vs full {full_cycles}"
    );
    avr.uart_send(b"g");
    avr.run_until_output(b"done\n", 16_000_000).unwrap();
}
