//! The ILI9341 bus decoder (`hal_sim::lcd_bus`): a C fixture built with
//! avr-gcc bit-bangs the shield's 8-bit bus on the Mega's real pins under
//! simavr, and the decoded picture, registers and counters must be exactly
//! what the fixture sent. The controller model's MADCTL rotations are checked
//! against the geometry of the four standard orientations.

use std::path::{Path, PathBuf};
use std::process::Command;

use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use hal_sim::avr::{Avr, Error, HaltReason};
use hal_sim::lcd_bus::{cmd, rgb565, BusPins, Ili9341, LcdBus};

fn fixture(name: &str, defines: &[&str]) -> PathBuf {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("tests/fixtures/simavr/{name}.c"));
    let out_dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("lcd-fixtures");
    std::fs::create_dir_all(&out_dir).unwrap();
    let elf = out_dir.join(format!("{name}{}.elf", defines.join("_")));
    let mut c = Command::new("avr-gcc");
    c.args(["-mmcu=atmega2560", "-DF_CPU=16000000UL", "-Os", "-Wall", "-Werror", "-o"]).arg(&elf).arg(&src);
    for d in defines {
        c.arg(format!("-D{d}"));
    }
    let out = c.output().expect("avr-gcc not found (install gcc-avr and avr-libc)");
    assert!(out.status.success(), "avr-gcc {name}: {}", String::from_utf8_lossy(&out.stderr));
    elf
}

fn run_fixture(defines: &[&str]) -> (Avr, LcdBus) {
    let mut avr = Avr::load(fixture("lcd", defines), "atmega2560", 16_000_000).unwrap();
    let bus = LcdBus::attach(&mut avr, BusPins::MEGA_SHIELD).unwrap();
    match avr.run_until(|_| false, 200_000_000) {
        Err(Error::Halted(h)) => assert_eq!(h.reason, HaltReason::SleepWithInterruptsOff),
        other => panic!("fixture did not finish: {other:?}"),
    }
    assert_eq!(avr.uart_output(), b"done\n");
    (avr, bus)
}

#[test]
fn decodes_the_fixture_picture_registers_and_counters() {
    let (_avr, bus) = run_fixture(&[]);
    let fb = bus.landscape();
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../target/ui-snapshots");
    fb.save_png(dir.join("lcd_fixture.png")).unwrap();
    let red = rgb565(0xF800);
    let green = rgb565(0x07E0);
    let blue = rgb565(0x001F);
    let yellow = rgb565(0xFFE0);
    let white = rgb565(0xFFFF);
    let grey = rgb565(0x8410);
    let expected = |x: i32, y: i32| -> Rgb565 {
        if (10..40).contains(&x) && (20..60).contains(&y) {
            red
        } else if (300..320).contains(&x) && (200..240).contains(&y) && !(x == 319 && y == 239) {
            green
        } else if x == 319 && y == 239 {
            blue
        } else if (0..3).contains(&x) && (238..240).contains(&y) {
            // Portrait MX: logical (c, p) in 2×3 → GRAM column 239 − c, row p.
            yellow
        } else if (100..102).contains(&x) && y == 100 {
            white
        } else if (100..102).contains(&x) && y == 101 {
            grey
        } else {
            Rgb565::BLACK
        }
    };
    for y in 0..240 {
        for x in 0..320 {
            assert_eq!(fb.pixel(x, y), Some(expected(x, y)), "pixel ({x},{y})");
        }
    }
    let lcd = bus.lcd();
    assert_eq!(lcd.madctl, 0x28);
    assert_eq!(lcd.colmod, 0x55);
    assert!(!lcd.sleeping && lcd.display_on);
    let s = lcd.stats;
    let pixels = 320 * 240 + 30 * 40 + 20 * 40 + 1 + 6 + 4;
    assert_eq!(s.pixels, pixels);
    assert_eq!(s.pixels_clipped, 0);
    assert_eq!(s.deselected_writes, 3, "the CS-high command and its two bytes");
    assert_eq!(s.reads, 1);
    assert_eq!(s.undriven_writes, 0);
    assert_eq!(s.hardware_resets, 0, "RST only rose");
    assert_eq!(s.stray_data, 0);
    assert_eq!(s.wrong_format, 0);
    // Windows: 5 fills + the RAMWR-continue window, 3 commands each.
    let log = &lcd.command_log;
    assert_eq!(&log[..6], &[cmd::SWRESET, 0xCF, cmd::SLPOUT, cmd::COLMOD, cmd::MADCTL, cmd::DISPON]);
    assert_eq!(log.iter().filter(|&&c| c == cmd::RAMWR).count(), 6);
    assert_eq!(log.iter().filter(|&&c| c == cmd::RAMWRC).count(), 1);
    assert_eq!(log.last(), Some(&cmd::RAMWRC));
    // The C loop is slow but steady: every pixel byte is a stream byte.
    let per_byte = s.cycles_per_stream_byte().unwrap();
    eprintln!("fixture bus: {per_byte:.1} cycles per pixel byte, min gap {:?}", s.min_gap_cycles);
    assert!(per_byte > 10.0 && per_byte < 200.0);
}

#[test]
fn a_write_with_the_data_pins_left_as_inputs_is_reported() {
    let (_avr, bus) = run_fixture(&["UNDRIVEN"]);
    assert_eq!(bus.stats().undriven_writes, 1);
}

/// Draws a 320×240 test pattern through `madctl` (logical coordinates as the
/// orientation defines them) and returns the GRAM.
fn pattern(madctl: u8) -> Ili9341 {
    let mut lcd = Ili9341::new();
    lcd.command(cmd::COLMOD);
    lcd.data(0x55);
    lcd.command(cmd::MADCTL);
    lcd.data(madctl);
    let landscape = madctl & 0x20 != 0;
    let (w, h) = if landscape { (320u16, 240u16) } else { (240, 320) };
    let be = |v: u16| v.to_be_bytes();
    lcd.command(cmd::CASET);
    for b in be(0).into_iter().chain(be(w - 1)) {
        lcd.data(b);
    }
    lcd.command(cmd::PASET);
    for b in be(0).into_iter().chain(be(h - 1)) {
        lcd.data(b);
    }
    lcd.command(cmd::RAMWR);
    for p in 0..h {
        for c in 0..w {
            // A colour unique per logical pixel (at most 76 800 < 65 536·2:
            // fold the index into 16 bits through both coordinates).
            let v = (c.wrapping_mul(251) ^ p.wrapping_mul(4093)) | 1;
            let [hi, lo] = v.to_be_bytes();
            lcd.data(hi);
            lcd.data(lo);
        }
    }
    lcd
}

/// The logical pixel (c, p) of `pattern` as a raw value.
fn logical(c: u16, p: u16) -> u16 {
    (c.wrapping_mul(251) ^ p.wrapping_mul(4093)) | 1
}

#[test]
fn madctl_orientations_are_rotations_of_one_another() {
    let raw = |lcd: &Ili9341, x: u16, y: u16| hal_sim::lcd_bus::raw565(lcd.gram(x, y).unwrap());
    // Portrait (MX|BGR, 0x48): logical (c, p) shows at GRAM (239 − c, p).
    // Landscape (MV|BGR, 0x28): logical (c, p) at GRAM (p, c).
    // Portrait flipped (MY|BGR, 0x88): at (c, 319 − p).
    // Landscape flipped (MX|MY|MV|BGR, 0xE8): at (239 − p, 319 − c).
    let p0 = pattern(0x48);
    let l0 = pattern(0x28);
    let p1 = pattern(0x88);
    let l1 = pattern(0xE8);
    for y in (0..320).step_by(7) {
        for x in (0..240).step_by(5) {
            assert_eq!(raw(&p0, x, y), logical(239 - x, y));
            assert_eq!(raw(&l0, x, y), logical(y, x));
            assert_eq!(raw(&p1, x, y), logical(x, 319 - y));
            assert_eq!(raw(&l1, x, y), logical(319 - y, 239 - x));
            // Flipped orientations are the 180° turn of the plain ones.
            assert_eq!(raw(&p1, x, y), raw(&p0, 239 - x, 319 - y));
            assert_eq!(raw(&l1, x, y), raw(&l0, 239 - x, 319 - y));
        }
    }
    // Where one logical pixel lands, found by scanning the GRAM: landscape is
    // portrait turned a quarter, the flipped ones are half turns.
    let lands = |madctl: u8, c: u16, p: u16| -> (u16, u16) {
        let mut lcd = Ili9341::new();
        for (command, params) in [
            (cmd::COLMOD, vec![0x55]),
            (cmd::MADCTL, vec![madctl]),
            (cmd::CASET, [c.to_be_bytes(), c.to_be_bytes()].concat()),
            (cmd::PASET, [p.to_be_bytes(), p.to_be_bytes()].concat()),
            (cmd::RAMWR, vec![0xFF, 0xFF]),
        ] {
            lcd.command(command);
            params.into_iter().for_each(|b| lcd.data(b));
        }
        let mut at = None;
        for y in 0..320 {
            for x in 0..240 {
                if lcd.gram(x, y) == Some(Rgb565::WHITE) {
                    assert!(at.is_none(), "one pixel written");
                    at = Some((x, y));
                }
            }
        }
        at.expect("pixel landed")
    };
    for (c, p) in [(0u16, 0u16), (319, 0), (0, 239), (200, 17), (5, 180)] {
        assert_eq!(lands(0x28, c, p), lands(0x48, 239 - p, c), "quarter turn at ({c},{p})");
        assert_eq!(lands(0xE8, c, p), lands(0x28, 319 - c, 239 - p), "half turn at ({c},{p})");
    }
    for (c, p) in [(0u16, 0u16), (239, 0), (0, 319), (100, 200)] {
        assert_eq!(lands(0x88, c, p), lands(0x48, 239 - c, 319 - p));
    }
    // The landscape view shows MV|BGR upright.
    let fb = l0.landscape();
    for (c, p) in [(0u16, 0u16), (319, 0), (0, 239), (123, 45)] {
        assert_eq!(fb.pixel(c.into(), p.into()), Some(rgb565(logical(c, p))));
    }
    // Without BGR the panel swaps red and blue.
    let mut lcd = Ili9341::new();
    lcd.command(cmd::COLMOD);
    lcd.data(0x55);
    lcd.command(cmd::MADCTL);
    lcd.data(0x20);
    lcd.command(cmd::RAMWR);
    lcd.data(0xF8);
    lcd.data(0x00);
    assert_eq!(lcd.gram(0, 0), Some(Rgb565::BLUE));
}
