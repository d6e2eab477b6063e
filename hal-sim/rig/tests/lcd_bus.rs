//! The display bus decoder (`touch_arm_rig::lcd_bus`): a C fixture built with
//! avr-gcc bit-bangs the shield's 8-bit bus on the Mega's real pins under
//! simavr, and the decoded picture, registers and counters must be exactly
//! what the fixture sent. The DCS model's MADCTL rotations are checked
//! against the geometry of the four standard orientations, each DCS chip's
//! ID answers against its datasheet, and the ILI9325 model's register reads,
//! address counter and scan directions against the ILI9325 datasheet.

use std::path::{Path, PathBuf};
use std::process::Command;

use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use touch_arm::ui::ili9325 as reg;
use touch_arm_rig::avr::{Avr, Error, HaltReason};
use touch_arm_rig::lcd_bus::{cmd, rgb565, BusPins, Chip, Dcs, Ili9325, Ili9341, LcdBus};

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
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/ui-snapshots");
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
    let raw = |lcd: &Ili9341, x: u16, y: u16| touch_arm_rig::lcd_bus::raw565(lcd.gram(x, y).unwrap());
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

// ---- the ILI9325 (register-indexed) --------------------------------------

/// Index `r`, then `v` upper byte first, as the 8-bit bus carries them.
fn write_reg(lcd: &mut Ili9325, r: u8, v: u16) {
    lcd.command(0x00);
    lcd.command(r);
    let [hi, lo] = v.to_be_bytes();
    lcd.data(hi);
    lcd.data(lo);
}

/// R22h, then one pixel per colour.
fn write_pixels(lcd: &mut Ili9325, colors: &[u16]) {
    lcd.command(0x00);
    lcd.command(reg::GRAM_DATA);
    for c in colors {
        let [hi, lo] = c.to_be_bytes();
        lcd.data(hi);
        lcd.data(lo);
    }
}

#[test]
fn ili9325_reads_its_driver_code_and_moves_its_address_counter_as_the_datasheet_says() {
    let mut lcd = Ili9325::new();
    // R00h: 9325h, upper byte first; nothing more to read.
    lcd.command(0x00);
    lcd.command(reg::DRIVER_CODE);
    assert_eq!([lcd.read(), lcd.read(), lcd.read()], [Some(0x93), Some(0x25), None]);
    // A register reads back what was written.
    write_reg(&mut lcd, reg::GATE_SCAN, 0xA700);
    lcd.command(0x00);
    lcd.command(reg::GATE_SCAN);
    assert_eq!([lcd.read(), lcd.read()], [Some(0xA7), Some(0x00)]);

    // Window columns 10..=12, rows 20..=21.
    write_reg(&mut lcd, reg::WINDOW_X0, 10);
    write_reg(&mut lcd, reg::WINDOW_X1, 12);
    write_reg(&mut lcd, reg::WINDOW_Y0, 20);
    write_reg(&mut lcd, reg::WINDOW_Y1, 21);
    let at = |lcd: &Ili9325, x: u16, y: u16| touch_arm_rig::lcd_bus::raw565(lcd.gram(x, y).unwrap());
    // AM = 0, I/D = 11 (BGR): along the row, then down, from R20h/R21h;
    // the seventh pixel wraps to the window's start.
    write_reg(&mut lcd, reg::ENTRY_MODE, 0x1030);
    write_reg(&mut lcd, reg::GRAM_X, 10);
    write_reg(&mut lcd, reg::GRAM_Y, 20);
    write_pixels(&mut lcd, &[1, 2, 3, 4, 5, 6, 7]);
    let rows = [
        [at(&lcd, 10, 20), at(&lcd, 11, 20), at(&lcd, 12, 20)],
        [at(&lcd, 10, 21), at(&lcd, 11, 21), at(&lcd, 12, 21)],
    ];
    assert_eq!(rows, [[7, 2, 3], [4, 5, 6]]);
    // AM = 1, I/D1 = 1 (rows up), I/D0 = 0 (columns down), from column 12:
    // down the column first, then one column left.
    write_reg(&mut lcd, reg::ENTRY_MODE, 0x1028);
    write_reg(&mut lcd, reg::GRAM_X, 12);
    write_reg(&mut lcd, reg::GRAM_Y, 20);
    write_pixels(&mut lcd, &[11, 12, 13, 14, 15, 16]);
    let rows = [
        [at(&lcd, 10, 20), at(&lcd, 11, 20), at(&lcd, 12, 20)],
        [at(&lcd, 10, 21), at(&lcd, 11, 21), at(&lcd, 12, 21)],
    ];
    assert_eq!(rows, [[15, 13, 11], [16, 14, 12]]);
    // R22h does not reset the counter (unlike RAMWR): the next pixel goes
    // where the last left off (the window's start again).
    write_pixels(&mut lcd, &[21]);
    assert_eq!(at(&lcd, 12, 20), 21);
    assert_eq!(lcd.stats.pixels, 14);
    assert_eq!((lcd.stats.stray_data, lcd.stats.wrong_format), (0, 0));

    // BGR clear: red and blue swap on the glass; TRI/DFM set: not the
    // 16-bit two-transfer format.
    write_reg(&mut lcd, reg::ENTRY_MODE, 0x0030);
    write_reg(&mut lcd, reg::GRAM_X, 10);
    write_reg(&mut lcd, reg::GRAM_Y, 20);
    write_pixels(&mut lcd, &[0xF800]);
    assert_eq!(lcd.gram(10, 20), Some(Rgb565::BLUE));
    write_reg(&mut lcd, reg::ENTRY_MODE, 0xC030);
    write_pixels(&mut lcd, &[0]);
    assert_eq!(lcd.stats.wrong_format, 1);
    // An index cut short by RS rising is a protocol error.
    lcd.command(0x00);
    lcd.data(0x12);
    assert_eq!(lcd.stats.stray_data, 1);
    // R07h D1:0 = 11 shows the GRAM.
    assert!(!lcd.display_on());
    write_reg(&mut lcd, reg::DISPLAY_CONTROL, 0x0133);
    assert!(lcd.display_on());
}

#[test]
fn ili9325_landscape_view_follows_the_scan_directions() {
    let mut lcd = Ili9325::new();
    write_reg(&mut lcd, reg::ENTRY_MODE, 0x1030);
    // One distinct pixel near each GRAM corner.
    for (x, y, c) in [(1u16, 2u16, 0x1111u16), (238, 3, 0x2222), (4, 317, 0x3333), (235, 318, 0x4444)] {
        write_reg(&mut lcd, reg::GRAM_X, x);
        write_reg(&mut lcd, reg::GRAM_Y, y);
        write_pixels(&mut lcd, &[c]);
    }
    let view = |lcd: &Ili9325, vx: u16, vy: u16| {
        touch_arm_rig::lcd_bus::raw565(lcd.landscape().pixel(vx.into(), vy.into()).unwrap())
    };
    // SS and GS set (the shields' reference initialisation): portrait shows
    // GRAM (x, y) at (x, y); landscape (vx, vy) is portrait (239 − vy, vx).
    write_reg(&mut lcd, reg::DRIVER_OUTPUT, 0x0100);
    write_reg(&mut lcd, reg::GATE_SCAN, 0xA700);
    assert_eq!(lcd.landscape().width(), 320);
    assert_eq!(view(&lcd, 2, 239 - 1), 0x1111);
    assert_eq!(view(&lcd, 3, 239 - 238), 0x2222);
    assert_eq!(view(&lcd, 317, 239 - 4), 0x3333);
    // SS and GS clear: the glass shows both axes mirrored.
    write_reg(&mut lcd, reg::DRIVER_OUTPUT, 0x0000);
    write_reg(&mut lcd, reg::GATE_SCAN, 0x2700);
    assert_eq!(view(&lcd, 319 - 2, 1), 0x1111);
    assert_eq!(view(&lcd, 319 - 318, 235), 0x4444);
}

#[test]
fn each_dcs_chip_answers_its_datasheet_ids() {
    // A dummy byte, then the ID; nothing after the answer, nothing after a
    // command that reads nothing.
    for (chip, rddid, id4) in [
        (Chip::Ili9341, [0x00, 0x00, 0x00], Some([0x00, 0x93, 0x41])),
        (Chip::St7789, [0x85, 0x85, 0x52], None),
        (Chip::Ili9486, [0x00, 0x00, 0x00], Some([0x00, 0x94, 0x86])),
        (Chip::St7796, [0x00, 0x00, 0x00], Some([0x00, 0x77, 0x96])),
    ] {
        let mut lcd = Dcs::of(chip);
        lcd.command(cmd::RDDID);
        let got: Vec<Option<u8>> = (0..5).map(|_| lcd.read()).collect();
        assert_eq!(got, [Some(0), Some(rddid[0]), Some(rddid[1]), Some(rddid[2]), None], "{chip:?}");
        lcd.command(cmd::RDID4);
        let got: Vec<Option<u8>> = (0..4).map(|_| lcd.read()).collect();
        let want: Vec<Option<u8>> = match id4 {
            Some(id) => vec![Some(0), Some(id[0]), Some(id[1]), Some(id[2])],
            None => vec![None; 4],
        };
        assert_eq!(got, want, "{chip:?}");
        lcd.command(cmd::NOP);
        assert_eq!(lcd.read(), None);
    }
    // The ILI9486's GRAM is 320×480 (the ST7796S's too): landscape 480×320.
    assert_eq!(Dcs::of(Chip::St7796).gram_size(), (320, 480));
    let mut lcd = Dcs::of(Chip::Ili9486);
    assert_eq!(lcd.gram_size(), (320, 480));
    lcd.command(cmd::MADCTL);
    lcd.data(0x28);
    lcd.command(cmd::COLMOD);
    lcd.data(0x55);
    lcd.command(cmd::CASET);
    [0x01, 0xDF, 0x01, 0xDF].into_iter().for_each(|b| lcd.data(b));
    lcd.command(cmd::PASET);
    [0x01, 0x3F, 0x01, 0x3F].into_iter().for_each(|b| lcd.data(b));
    lcd.command(cmd::RAMWR);
    lcd.data(0xFF);
    lcd.data(0xFF);
    let fb = lcd.landscape();
    assert_eq!((fb.width(), fb.height()), (480, 320));
    assert_eq!(fb.pixel(479, 319), Some(Rgb565::WHITE));
    assert_eq!(lcd.stats.pixels_clipped, 0);
}

/// INVON/INVOFF (21h/20h): the panel's inversion, cleared by a reset; the
/// GRAM is untouched and the commands take no parameter.
#[test]
fn dcs_inversion_follows_invon_and_invoff() {
    let mut lcd = Dcs::of(Chip::St7796);
    assert!(!lcd.inverted);
    lcd.command(cmd::INVON);
    assert!(lcd.inverted);
    lcd.command(cmd::INVOFF);
    assert!(!lcd.inverted);
    lcd.command(cmd::INVON);
    lcd.command(cmd::SWRESET);
    assert!(!lcd.inverted, "a reset clears it");
    lcd.command(cmd::INVON);
    lcd.data(0x00);
    assert_eq!(lcd.stats.stray_data, 1);
}
