//! The product firmware on every display controller it supports, end to end
//! in simavr: the same ELF probes the controller on the shield bus at boot
//! (`touch_arm_rig::lcd_bus` answers the ID reads as each datasheet says), prints
//! `info lcd <name> id 0x… <w>x<h>`, draws through that controller's
//! protocol in its layout (the decoded screen equals the host's rendering of
//! what the screen must show), and a touch on its map moves the arm to the
//! IK pose. An unknown controller gets a `warn lcd unknown id` line, the
//! ILI9341 driver, and an arm that works over serial. The display
//! overrides (`cal set lcd`, stored in their own EEPROM record) are decoded
//! here too: a forced controller, inversion, and a screen turned by 180°
//! whose buttons still answer where they are drawn.

use std::f64::consts::PI;

use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use hal_sim::display::Framebuffer;
use touch_arm::config::lcd::{LcdChoice, LcdSettings, LCD_DEFAULT, LCD_SLOT_A};
use touch_arm::config::{self, settings::Config};
use touch_arm::geometry::workspace::condition;
use touch_arm::ui::draw::Area;
use touch_arm::ui::{warn, Layout, Page, Ui, UiConfig, UiModel, UiState};
use touch_arm_rig::firmware::{self, Session};
use touch_arm_rig::lcd_bus::Chip;
use touch_arm_rig::panel::PanelWiring;

const CPU_HZ: f64 = 16e6;

/// The app's map shading: links 1 and 1 at scale 1 reach radii 0 to 2.
const REACH: UiConfig = UiConfig { reach_min: 0.0, reach_max: 2.0 };

/// Booted, homed, taking targets.
fn boot(chip: Chip) -> Session {
    boot_with(chip, None)
}

/// [`boot`] with the display overrides `lcd` stored in the EEPROM first.
fn boot_with(chip: Chip, lcd: Option<LcdSettings>) -> Session {
    let mut s =
        Session::start_with_lcd(&firmware::default_elf(), PanelWiring::A, chip, 5).expect("firmware (cargo avr)");
    if let Some(set) = lcd {
        s.avr.set_eeprom(LCD_SLOT_A, &config::lcd::encode(&set, 1)).unwrap();
    }
    s.run_for(1.5).unwrap();
    s.run_until_ready(2.0).unwrap();
    s
}

/// The ID each controller's datasheet gives, as the firmware prints it.
fn datasheet_id(chip: Chip) -> &'static str {
    match chip {
        Chip::Ili9341 => "0x9341",
        Chip::St7789 => "0x858552",
        Chip::Ili9486 => "0x9486",
        Chip::Ili9325 => "0x9325",
        Chip::St7796 => "0x7796",
        Chip::Unknown => unreachable!(),
    }
}

/// method.md §4–6 in f64 with the default servo calibration (10 µs/°, base and
/// shoulder 600 µs at 0°, elbow 2400 µs at 0°): the pulses a target at
/// (x_p, y_p) ends at, and the joint angles in degrees.
fn expected(x_p: f64, y_p: f64) -> ([f64; 3], [f64; 3]) {
    let alpha = y_p.atan2(x_p);
    let (r, h) = (x_p.abs(), y_p);
    let c = (r * r + h * h - 2.0) / 2.0;
    let q3 = -c.acos();
    let q2 = h.atan2(r) + q3.abs().sin().atan2(1.0 + q3.cos());
    let deg = [alpha, q2, q3].map(|q| q * 180.0 / PI);
    ([600.0 + 10.0 * deg[0], 600.0 + 10.0 * deg[1], 2400.0 + 10.0 * deg[2]], deg)
}

/// The host's rendering of `model` in `lay`.
fn host_screen(lay: Layout, model: &UiModel) -> Framebuffer {
    let mut fb = Framebuffer::new(lay.width().into(), lay.height().into(), Rgb565::BLACK);
    Ui::with_layout(&REACH, lay).draw_full(model, &mut fb).unwrap();
    fb
}

fn assert_screen(s: &Session, want: &Framebuffer, what: &str) {
    let got = s.lcd.landscape();
    if &got != want {
        let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/ui-snapshots");
        got.save_png(dir.join(format!("{what}_chip.png"))).unwrap();
        want.save_png(dir.join(format!("{what}_host.png"))).unwrap();
        let diff = got.pixels().iter().zip(want.pixels()).filter(|(a, b)| a != b).count();
        panic!("{what}: the decoded screen differs from the host rendering in {diff} pixels (PNGs written)");
    }
}

#[test]
fn each_controller_is_identified_drawn_and_a_touch_moves_the_arm() {
    eprintln!("controller  first pixel ms  bus reads (answered)");
    for chip in Chip::SUPPORTED {
        let name = chip.name();
        let mut s = boot(chip);
        let (w, h) = chip.landscape_size();
        let out = s.avr.uart_output_string();
        let line = out.lines().find(|l| l.contains(" lcd ")).unwrap_or_else(|| panic!("{name}: no lcd line:\n{out}"));
        assert_eq!(line, format!("info lcd {name} id {} {w}x{h}", datasheet_id(chip)));
        let stats = s.lcd.stats();
        let first_pixel = stats.first_pixel_cycle.expect("drawn") as f64 / CPU_HZ * 1e3;
        eprintln!("{name:<10} {first_pixel:>14.1} {:>10} ({})", stats.reads, stats.reads_answered);
        assert_eq!(stats.reads, 10, "{name}: the probe's 2 + 4 + 4 strobes");
        assert_eq!(stats.read_conflicts, 0, "{name}");
        assert!(s.lcd.model().display_on(), "{name}");
        assert!(!s.lcd.model().inverted(), "{name}: no inversion unless asked");
        assert_eq!(out.lines().filter(|l| l.contains(" lcd ")).count(), 1, "{name}: no override line:\n{out}");

        // A touch on the map pixel showing (0.4, 0.6), in this screen's layout.
        let lay = chip.layout();
        let ((rx, ry), (wx, wy)) = firmware::map_touch_on(&lay, 0.4, 0.6).unwrap();
        s.press_raw(rx, ry).unwrap();
        s.run_for(0.3).unwrap();
        s.release();
        // The tap acts on the lift-off (issue #19).
        s.run_for(0.1).unwrap();
        let out = s.avr.uart_output_string();
        let reply = out.lines().find(|l| l.starts_with("info touch ")).unwrap_or_else(|| panic!("{name}:\n{out}"));
        let ts: f64 = reply.split_whitespace().skip_while(|w| *w != "ts_ms").nth(1).unwrap().parse().unwrap();
        s.run_for(ts / 1000.0 + 0.5).unwrap();
        let (pulses, deg) = expected(wx, wy);
        let last = s.last_pulses();
        for j in 0..3 {
            let got = last[j].unwrap();
            assert!((got - pulses[j]).abs() <= 1.0, "{name} joint {j}: {got} µs, want {:.2}", pulses[j]);
            // Whole degrees on the screen: no angle near a rounding edge.
            assert!((deg[j].fract().abs() - 0.5).abs() > 0.01, "{name}: {} is a rounding edge", deg[j]);
        }

        // The screen after the move, as the host draws it.
        let (xf, yf) = (wx as f32, wy as f32);
        let model = UiModel {
            state: UiState::Holding,
            preview: None,
            resume: None,
            touch: Some((xf, yf)),
            target: Some((xf, yf)),
            condition: Some(condition(xf, yf).unwrap()),
            alpha: yf.atan2(xf),
            joints: deg.map(|d| d.to_radians() as f32),
            speed: Config::DEFAULT.speed,
            warnings: warn::DEFAULT_SETTINGS,
            page: Page::Main,
            grip_closed: false,
            path_line: false,
            lift: false,
            scan: None,
            hide: 0,
            confirm: 0,
        };
        assert_screen(&s, &host_screen(lay, &model), &format!("lcd_{name}_after_touch"));
    }
}

#[test]
fn an_unknown_controller_is_reported_and_the_arm_still_works() {
    let mut s = boot(Chip::Unknown);
    let out = s.avr.uart_output_string();
    // Register 0000h unanswered (pulled-up lines), zeros on Read ID4 and RDDID.
    assert!(out.lines().any(|l| l == "warn lcd unknown id 0x000000 reg00 0xffff rddid 0x000000"), "{out}");
    assert!(!out.contains("info lcd"), "{out}");
    // The screen tries the ILI9341 path: it shows the idle screen.
    let home = [90.0f32, 90.0, -90.0].map(f32::to_radians);
    let idle = UiModel {
        state: UiState::Idle,
        preview: None,
        resume: None,
        touch: None,
        target: None,
        condition: None,
        alpha: f32::NAN,
        joints: home,
        speed: Config::DEFAULT.speed,
        warnings: warn::DEFAULT_SETTINGS,
        page: Page::Main,
        grip_closed: false,
        path_line: false,
        lift: false,
        scan: None,
        hide: 0,
        confirm: 0,
    };
    assert_screen(&s, &host_screen(Layout::QVGA, &idle), "lcd_unknown_idle");
    // Fully usable over serial.
    assert!(s.command("status").unwrap().starts_with("ok status holding"));
    let reply = s.command("goto 30 120 -60").unwrap();
    assert!(reply.starts_with("ok goto ts_ms"), "{reply}");
    let ts: f64 = reply.split_whitespace().nth(3).unwrap().parse().unwrap();
    s.run_for(ts / 1000.0 + 0.5).unwrap();
    let want = [600.0 + 300.0, 600.0 + 1200.0, 2400.0 - 600.0];
    for (j, got) in s.last_pulses().into_iter().enumerate() {
        assert!((got.unwrap() - want[j]).abs() <= 1.0, "joint {j}: {got:?} µs, want {}", want[j]);
    }
}

/// Presses the centre of `a` on `lay` for 0.3 s, releases, and returns the
/// serial lines the press produced, after 0.7 s more (the sliced redraw
/// finished).
fn press(s: &mut Session, lay: &Layout, a: Area) -> Vec<String> {
    let before = s.avr.uart_output_string().len();
    let (rx, ry) = firmware::raw_at_centre(lay, a).unwrap();
    s.press_raw(rx, ry).unwrap();
    s.run_for(0.3).unwrap();
    s.release();
    s.run_for(0.7).unwrap();
    s.avr.uart_output_string()[before..].lines().map(str::to_string).collect()
}

/// `ts_ms` of a reply line.
fn ts_s(line: &str) -> f64 {
    let ms: f64 = line.split_whitespace().skip_while(|w| *w != "ts_ms").nth(1).unwrap().parse().unwrap();
    ms / 1000.0
}

/// The More and Setup pages on the chip, 320×240 (ILI9341) and 480×320 (ILI9486): More
/// opens each and the decoded picture is the host's rendering of it; Grip
/// closes the gripper through `grip close`'s path (same first-grip plan at
/// the slow preset, ends on 1500 µs) and its label turns to Open; pose 1
/// (saved over serial at home) brings the arm and the gripper back exactly
/// as `pose go 1`; Line and Lift are `path line|joint` and `lift 0.20|off`
/// (refused together) and drawn on as the host draws them; Back restores
/// the main page.
#[test]
fn the_more_page_drives_the_gripper_and_the_saved_poses_on_both_sizes() {
    for chip in [Chip::Ili9341, Chip::Ili9486] {
        let name = chip.name();
        let lay = chip.layout();
        let mut s = boot(chip);
        // Pose 1 = home (90°, 90°, −90°), gripper open; then somewhere else.
        assert!(s.command("pose save 1").unwrap().starts_with("ok pose save 1"), "{name}");
        let reply = s.command("goto 30 120 -60").unwrap();
        s.run_for(ts_s(&reply) + 0.3).unwrap();

        let lines = press(&mut s, &lay, lay.page_key());
        assert_eq!(lines, ["info screen page more"], "{name}");
        let mut more = UiModel {
            state: UiState::Holding,
            preview: None,
            resume: None,
            touch: None,
            target: None,
            condition: None,
            alpha: f32::NAN,
            joints: [30.0f32, 120.0, -60.0].map(f32::to_radians),
            speed: Config::DEFAULT.speed,
            warnings: warn::DEFAULT_SETTINGS,
            page: Page::More,
            grip_closed: false,
            path_line: false,
            lift: false,
            scan: None,
            hide: 0,
            confirm: 0,
        };
        assert_screen(&s, &host_screen(lay, &more), &format!("lcd_{name}_more"));
        // More again: the Setup page (Grip, Cal, the toggles, Back).
        assert_eq!(press(&mut s, &lay, lay.page_key()), ["info screen page setup"], "{name}");
        more.page = Page::Setup;
        assert_screen(&s, &host_screen(lay, &more), &format!("lcd_{name}_setup"));

        // Grip: exactly `grip close` after power-up (grip_firmware.rs).
        let t0 = s.avr.cycles();
        let lines = press(&mut s, &lay, lay.grip());
        assert_eq!(lines, ["info screen grip 9000 ts_ms 4317"], "{name}");
        s.run_for(4.0).unwrap();
        let grip: Vec<u16> = s.grip_pulse_ticks().into_iter().filter(|(c, _)| *c > t0).map(|(_, t)| t).collect();
        assert!(grip.windows(2).all(|w| w[1] >= w[0]), "{name}: the gripper closes monotonically");
        assert_eq!(*grip.last().unwrap(), 3000, "{name}: closed at 1500 us");
        assert!(grip.iter().all(|t| (1200..=3000).contains(t)), "{name}: inside its window");
        more.grip_closed = true;
        assert_screen(&s, &host_screen(lay, &more), &format!("lcd_{name}_more_closed"));

        // The toggles: `path line|joint` and `lift 0.20|off`, refused
        // together as over serial, each drawn highlighted while on.
        assert_eq!(press(&mut s, &lay, lay.line_toggle()), ["info screen path line"], "{name}");
        more.path_line = true;
        assert_screen(&s, &host_screen(lay, &more), &format!("lcd_{name}_more_line"));
        let lines = press(&mut s, &lay, lay.lift_toggle());
        assert_eq!(lines, ["err screen lift lift and path line exclusive"], "{name}");
        assert_eq!(press(&mut s, &lay, lay.line_toggle()), ["info screen path joint"], "{name}");
        assert_eq!(press(&mut s, &lay, lay.lift_toggle()), ["info screen lift 0.20"], "{name}");
        more.path_line = false;
        more.lift = true;
        assert_screen(&s, &host_screen(lay, &more), &format!("lcd_{name}_more_lift"));
        assert_eq!(press(&mut s, &lay, lay.lift_toggle()), ["info screen lift off"], "{name}");

        // Back to Main, then More: the poses.
        assert_eq!(press(&mut s, &lay, lay.page_key()), ["info screen page main"], "{name}");
        assert_eq!(press(&mut s, &lay, lay.page_key()), ["info screen page more"], "{name}");
        // Pose 1: the arm home and the gripper open again.
        let lines = press(&mut s, &lay, lay.pose(0));
        let went = lines
            .iter()
            .find(|l| l.starts_with("info screen pose go 1 ts_ms"))
            .unwrap_or_else(|| panic!("{name}: {lines:?}"));
        s.run_for(ts_s(went) + 5.0).unwrap();
        for (j, got) in s.last_pulses().into_iter().enumerate() {
            assert!((got.unwrap() - 1500.0).abs() <= 1.0, "{name} joint {j}: {got:?} us, want 1500 (home)");
        }
        assert_eq!(s.grip_pulse_ticks().last().unwrap().1, 1200, "{name}: the pose's open gripper");
        // An empty slot is refused as over serial.
        assert_eq!(press(&mut s, &lay, lay.pose(3)), ["err screen pose go 4 empty"], "{name}");

        // Setup, then Back: the main page as the host draws it.
        assert_eq!(press(&mut s, &lay, lay.page_key()), ["info screen page setup"], "{name}");
        assert_eq!(press(&mut s, &lay, lay.page_key()), ["info screen page main"], "{name}");
        let main = UiModel {
            page: Page::Main,
            grip_closed: false,
            path_line: false,
            lift: false,
            scan: None,
            hide: 0,
            confirm: 0,
            joints: [90.0f32, 90.0, -90.0].map(f32::to_radians),
            ..more
        };
        assert_screen(&s, &host_screen(lay, &main), &format!("lcd_{name}_back"));
    }
}

/// The idle screen after boot (home pose, nothing touched).
fn idle_model() -> UiModel {
    UiModel {
        state: UiState::Idle,
        preview: None,
        resume: None,
        touch: None,
        target: None,
        condition: None,
        alpha: f32::NAN,
        joints: [90.0f32, 90.0, -90.0].map(f32::to_radians),
        speed: Config::DEFAULT.speed,
        warnings: warn::DEFAULT_SETTINGS,
        page: Page::Main,
        grip_closed: false,
        path_line: false,
        lift: false,
        scan: None,
        hide: 0,
        confirm: 0,
    }
}

/// The lines of the boot report about the display.
fn lcd_lines(s: &Session) -> Vec<String> {
    s.avr.uart_output_string().lines().filter(|l| l.contains(" lcd ")).map(str::to_string).collect()
}

/// `cal set lcd <controller>` is MCUFRIEND_kbv's `begin(ID)`: the probe
/// still runs, but the forced controller is driven. An ST7796S (480×320)
/// forced to `ili9341` gets the ILI9341's 320×240 layout, drawn into the top
/// left of its GRAM exactly as the host draws it, and the boot report says
/// the probe found another controller; forced to itself it is confirmed;
/// an unknown clone forced to `st7789` is driven as one (the default would
/// be the ILI9341 driver) and warned about.
#[test]
fn a_forced_controller_is_driven_whatever_the_probe_finds() {
    let forced = |c| Some(LcdSettings { controller: c, ..LCD_DEFAULT });
    let mut s = boot_with(Chip::St7796, forced(LcdChoice::Ili9341));
    assert_eq!(lcd_lines(&s), ["info lcd st7796 id 0x7796 480x320", "warn lcd forced ili9341 not detected"]);
    let want = host_screen(Layout::QVGA, &idle_model());
    let got = s.lcd.landscape();
    assert_eq!((got.width(), got.height()), (480, 320));
    let mut top_left = Framebuffer::new(320, 240, Rgb565::BLACK);
    for y in 0..240 {
        for x in 0..320 {
            top_left.set_pixel(x, y, got.pixel(x, y).unwrap());
        }
    }
    if top_left != want {
        let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../target/ui-snapshots");
        top_left.save_png(dir.join("lcd_forced_ili9341_chip.png")).unwrap();
        panic!("forced ili9341 on an st7796: the top left differs from the host's 320x240 screen");
    }
    s.command("cal show").unwrap();
    s.run_for(0.3).unwrap();
    let out = s.avr.uart_output_string();
    assert!(out.lines().any(|l| l == "cal lcd ili9341 invert off rotate 0"), "{out}");

    let s = boot_with(Chip::St7796, forced(LcdChoice::St7796));
    assert_eq!(lcd_lines(&s), ["info lcd st7796 id 0x7796 480x320", "info lcd forced st7796"]);
    assert_screen(&s, &host_screen(Layout::HVGA, &idle_model()), "lcd_forced_st7796");

    let s = boot_with(Chip::Unknown, forced(LcdChoice::St7789));
    let lines = lcd_lines(&s);
    assert_eq!(lines[1], "warn lcd forced st7789 not detected", "{lines:?}");
    assert!(lines[0].starts_with("warn lcd unknown id"), "{lines:?}");
    assert_screen(&s, &host_screen(Layout::QVGA, &idle_model()), "lcd_forced_st7789_on_unknown");
}

/// `cal set lcd invert on`: INVON on a DCS controller, R61h's REV cleared on
/// the ILI9325; the GRAM holds the same picture (the panel inverts it).
#[test]
fn invert_uses_each_controllers_inversion() {
    for chip in [Chip::Ili9341, Chip::Ili9325] {
        let name = chip.name();
        let s = boot_with(chip, Some(LcdSettings { invert: true, ..LCD_DEFAULT }));
        assert_eq!(lcd_lines(&s)[1], "info lcd auto invert", "{name}");
        assert!(s.lcd.model().inverted(), "{name}");
        assert_screen(&s, &host_screen(chip.layout(), &idle_model()), &format!("lcd_{name}_inverted"));
    }
}

/// The host's screen turned by 180°: what the glass shows when the
/// controller draws every pixel at the opposite corner.
fn turned(fb: &Framebuffer) -> Framebuffer {
    let (w, h) = (fb.width() as i32, fb.height() as i32);
    let mut out = Framebuffer::new(fb.width(), fb.height(), Rgb565::BLACK);
    for y in 0..h {
        for x in 0..w {
            out.set_pixel(w - 1 - x, h - 1 - y, fb.pixel(x, y).unwrap());
        }
    }
    out
}

/// `cal set lcd rotate 180` on a DCS controller (MADCTL MX|MY|MV), the
/// ILI9325 (its entry mode and GRAM mapping) and the 480×320 ST7796S: the
/// glass shows the host's screen turned by 180°, and a finger on the glass
/// where the Fast button is drawn (the unturned layout's opposite corner,
/// computed here without the firmware's mapping) selects the fast preset;
/// one on the map where (0.4, 0.6) is drawn moves the arm there.
#[test]
fn rotate_180_turns_the_picture_and_the_touches_with_it() {
    for chip in [Chip::Ili9341, Chip::Ili9325, Chip::St7796] {
        let name = chip.name();
        let lay = chip.layout();
        let mut s = boot_with(chip, Some(LcdSettings { rotate_180: true, ..LCD_DEFAULT }));
        assert_eq!(lcd_lines(&s)[1], "info lcd auto rotate 180", "{name}");
        assert_screen(&s, &turned(&host_screen(lay, &idle_model())), &format!("lcd_{name}_turned"));

        // Where Fast is on the glass: its box at the opposite corner.
        let f = lay.fast();
        let glass = Area::new(lay.width() as i16 - f.x - f.w as i16, lay.height() as i16 - f.y - f.h as i16, f.w, f.h);
        let lines = press(&mut s, &lay, glass);
        assert!(lines.iter().any(|l| l == "info screen speed fast"), "{name}: {lines:?}");
        assert!(s.command("status").unwrap().contains(" speed fast"), "{name}");

        // The map pixel showing (0.4, 0.6), found on the glass.
        let (px, py) = lay.ws_point_to_pixel(0.4, 0.6).unwrap();
        let (wx, wy) = lay.ws_pixel_to_point(px, py).unwrap();
        let (gx, gy) = (lay.width() as i16 - 1 - px, lay.height() as i16 - 1 - py);
        let (rx, ry) = firmware::raw_at_pixel(&lay, gx, gy).unwrap();
        s.press_raw(rx, ry).unwrap();
        s.run_for(0.3).unwrap();
        s.release();
        // The tap acts on its lift-off (issue #19): its reply a few frames on.
        s.run_for(0.2).unwrap();
        let out = s.avr.uart_output_string();
        let reply = out.lines().rfind(|l| l.starts_with("info touch ")).unwrap_or_else(|| panic!("{name}:\n{out}"));
        s.run_for(ts_s(reply) + 0.5).unwrap();
        let (pulses, _) = expected(f64::from(wx), f64::from(wy));
        for (j, got) in s.last_pulses().into_iter().enumerate() {
            assert!((got.unwrap() - pulses[j]).abs() <= 1.0, "{name} joint {j}: {got:?} us, want {:.2}", pulses[j]);
        }
    }
}
