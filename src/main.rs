//! touch-arm firmware for the Arduino Mega 2560 (ATmega2560, 16 MHz).
//!
//! Wires the board layer to the pure app (`touch_arm::app`): every 20 ms servo
//! PWM period (Timer5 overflow) the app runs one frame (serial commands, one
//! filtered touch read, the motion setpoint, the servo pulses), then redraws
//! what changed on the screen (whichever controller the boot probe found,
//! `ui::controller`), as much as fits in the period (`board::frame`). The watchdog
//! is fed once per frame, so a hang resets the chip. A reset that keeps RAM
//! (watchdog, RESET pin) resumes the pulses the servos had (`board::resume`,
//! `app::resume`); a power-up sends no pulse until the configuration is
//! loaded and then the home pose.
#![no_std]
#![no_main]
#![feature(optimize_attribute)]

use core::mem::MaybeUninit;

use avr_device::atmega2560 as pac;
use embedded_hal::digital::InputPin;
use touch_arm::app::resume::{ResetKind, Restart};
use touch_arm::app::text::Line;
use touch_arm::app::{App, AppParams, Io};
use touch_arm::board::adc::Adc;
use touch_arm::board::eeprom::Eeprom;
use touch_arm::board::fault::halt;
use touch_arm::board::frame::{self, FrameBudget};
use touch_arm::board::gpio::{self, Input};
use touch_arm::board::lcd::{Controller, IdReads, Lcd, Rotation};
use touch_arm::board::resume;
use touch_arm::board::servo_pwm::{ServoPwm, TickLimits, CHANNELS, SERVO_RANGE};
use touch_arm::board::shield::ShieldBus;
use touch_arm::board::shield::TouchWiring;
use touch_arm::board::tick::Tick;
use touch_arm::board::usart::Usart0;
use touch_arm::board::watchdog::{ResetCause, Timeout, Watchdog};
use touch_arm::config::lcd::{LcdSettings, LCD_DEFAULT};
use touch_arm::config::settings::Config;
use touch_arm::seam::SerialPort;
use touch_arm::touch::wiring::Probe;
use ufmt::uwriteln;

/// A planning frame can take tens of milliseconds and `cal save` feeds the
/// dog per EEPROM byte; 500 ms leaves margin and still stops a hung arm fast.
const WATCHDOG: Timeout = Timeout::Ms500;

/// The board's drivers, owned by `main` and lent to each frame.
struct Board {
    serial: Usart0,
    tick: Tick,
    adc: Adc,
    bus: ShieldBus,
    eeprom: Eeprom,
    pwm: ServoPwm,
    dog: Watchdog,
    /// The display controller found (or forced) at boot.
    lcd: Controller,
    /// Its orientation: landscape, or turned by 180° (`cal set lcd rotate`).
    rotation: Rotation,
    /// The panel's wiring being measured (`touch::wiring`), if the app asked.
    probe: Option<Probe>,
    /// The assistive switch's jack: D22 (PA0), pulled up, closed = low.
    /// D22 is the first pin of the Mega's end header, which no Uno-shaped
    /// shield covers and no driver here uses (ports E–H are the shield's,
    /// L and B the servos'), so a 3.5 mm jack's two wires go to D22 and GND
    /// beside it with the shield on.
    switch: Input,
}

#[avr_device::entry]
fn main() -> ! {
    // `take` only fails on a second call; there is none.
    let Some(dp) = pac::Peripherals::take() else { halt() };
    // First: after a watchdog reset the dog runs with a 16 ms timeout.
    let (dog, cause) = Watchdog::boot(dp.WDT, &dp.CPU);
    let mut board = Board {
        serial: Usart0::new(dp.USART0),
        tick: Tick::new(dp.TC0),
        adc: Adc::new(dp.ADC),
        bus: ShieldBus::new(dp.PORTE, dp.PORTF, dp.PORTG, dp.PORTH),
        eeprom: Eeprom::new(dp.EEPROM),
        // Outputs stay disconnected until the app commands its first pose;
        // the hardware window starts at the servo range and narrows to the
        // loaded calibration's limits every frame.
        pwm: ServoPwm::new(dp.TC5, dp.TC1, &dp.PORTL, &dp.PORTB, &[SERVO_RANGE; CHANNELS]),
        dog,
        lcd: Controller::Ili9341,
        rotation: Rotation::Landscape,
        probe: None,
        switch: switch_pin(dp.PORTA),
    };
    // SAFETY: every peripheral the interrupt handlers touch is initialised.
    unsafe { avr_device::interrupt::enable() };

    report_boot(&mut board.serial, cause);
    // Taken after the boot frame (below): resume or home.
    let mut restart = Some(cause);
    let app = start_screen_and_app(&mut board);
    board.dog.enable(WATCHDOG);
    // The overflow flag has been set since Timer5 started: drop it, so the
    // first frame starts at a period start like every other.
    let _ = board.pwm.period_started();
    loop {
        while !board.pwm.period_started() {}
        board.dog.feed();
        // The widths this period sends (set in the previous frame), so a
        // reset from here on resumes the pulses the servos last got.
        resume::record(&board.pwm);
        frame(app, &mut board);
        // After the boot frame (configuration loaded), before any pulse.
        if let Some(cause) = restart.take() {
            resume_or_home(app, cause, &mut board.serial);
        }
        if !app.pulses_started() && app.wiring_probe_wanted() {
            // First boot: the whole probe before the first pulse, outside the
            // frame cadence like the display's start-up (no pulse is due
            // yet); the next frame waits for a fresh period start.
            probe_wiring(app, &mut board);
            let _ = board.pwm.period_started();
        }
    }
}

/// The screen: reset, which controller, its initialisation, landscape
/// (≈ 270 ms, more for the ILI9325; before the watchdog runs), with the
/// stored display overrides (`config::lcd`: a forced controller, colours
/// inverted, turned by 180°); then the app, with the screen's touch layout.
/// An unknown controller is driven as an ILI9341; the arm works over serial
/// either way.
// Out of line: the identification reads and the display settings are
// boot-only locals; in `main`'s frame they sat under every frame's deepest
// call path (`cargo xtask elf-check`, stack-bound).
#[inline(never)] // avr-trap: frame-size
fn start_screen_and_app(board: &mut Board) -> &'static mut App {
    let display = touch_arm::config::lcd::load(&mut board.eeprom).2;
    let forced = Controller::forced(display.controller);
    if display.rotate_180 {
        board.rotation = Rotation::LandscapeFlipped;
    }
    let (ids, found) = Lcd::new(&mut board.bus).start_forced(forced, board.rotation, display.invert);
    board.lcd = forced.or(found).unwrap_or(Controller::Ili9341);
    report_lcd(&mut board.serial, &ids, found, &display);
    let Some(app) = start_app() else {
        let _ = uwriteln!(board.serial, "err app parameters invalid");
        halt()
    };
    // Turned, the touch mapping turns with the picture (`ui::layout`).
    app.set_screen_layout(board.lcd.layout().turned(display.rotate_180));
    app
}

static mut APP: MaybeUninit<App> = MaybeUninit::uninit();

/// Builds the app in .bss rather than in main's stack frame: a frame that
/// large makes LLVM address it through temporary Y-pointer adjustments.
#[inline(never)] // avr-trap: frame-size
fn start_app() -> Option<&'static mut App> {
    // SAFETY: called once (from `main`, which never returns), so this is the
    // only reference ever made to APP.
    let slot = unsafe { &mut *core::ptr::addr_of_mut!(APP) };
    // Built in place: an App-sized temporary in this frame plus the calls
    // that build it went past the stack budget.
    App::init(slot, &AppParams { screen: true, ..AppParams::DEFAULT }).ok()
}

/// D22 (PA0) as the switch's input with its pull-up; the port's other pins
/// stay as reset left them (inputs, no pull-up).
fn switch_pin(port: pac::PORTA) -> Input {
    // The pin map's switch is this port's bit 0.
    const _: () = assert!(matches!(touch_arm::seam::pins::mega::SWITCH.port(), touch_arm::seam::pins::Port::A));
    const _: () = assert!(touch_arm::seam::pins::mega::SWITCH.bit() == 0);
    let [pa0, ..] = gpio::split(port);
    pa0.into_input(true)
}

/// One 20 ms frame: the hardware clamp follows the calibration (the
/// gripper's too), then the
/// app reads serial and touch and writes the servo pulses. Not inlined, so
/// its large temporaries stay out of `main`'s frame.
#[inline(never)] // avr-trap: frame-size
fn frame(app: &mut App, b: &mut Board) {
    b.pwm.set_limits(&tick_limits(app.config()));
    b.pwm.set_grip_limits(TickLimits::of_joint(app.grip_cal()));
    // The measured wiring; none (not measured, or not identified) reads nothing.
    let wiring = app.config().wiring.map(TouchWiring::preset);
    let mut panel = b.bus.touch(&mut b.adc, wiring.as_ref());
    app.set_switch(matches!(b.switch.is_low(), Ok(true)));
    app.frame(&mut Io {
        panel: &mut panel,
        servos: &mut b.pwm,
        clock: &b.tick,
        storage: &mut b.eeprom,
        serial: &mut b.serial,
    });
    if app.pulses_started() {
        probe_wiring(app, b);
    }
    let app_ticks = b.pwm.ticks();
    let app_late = b.pwm.period_pending();
    // After the touch read, never during it: drawing holds the shared pins.
    // Only what changed is redrawn, and only as much as the period leaves;
    // the rest in the next frames.
    let _ = app.draw_screen_sliced(&mut Lcd::oriented(&mut b.bus, b.lcd, b.rotation), &mut FrameBudget::new(&b.pwm));
    if frame::record(&b.pwm, app_ticks, app_late) {
        app.frame_was_late();
    }
}

/// The panel's wiring probe, when the app wants one (first boot, the
/// calibration screen): before the first servo pulse all of it at once
/// (README "Touch wiring" gives its time), later one plate-link read per
/// frame so no frame misses its period, started over whenever the app's
/// panel read saw contact (`app::wiring`), its verdict taken only after a
/// frame whose panel read was clean. The verdict goes to the app, which
/// reports it and reads the panel through it from the next frame.
#[inline(never)] // avr-trap: frame-size
fn probe_wiring(app: &mut App, b: &mut Board) {
    if b.probe.is_none() && app.wiring_probe_wanted() {
        b.probe = Some(Probe::new());
    }
    let Some(probe) = b.probe.as_mut() else { return };
    if !app.pulses_started() {
        while b.bus.probe_step(&mut b.adc, probe) {
            b.dog.feed();
        }
    } else if app.panel_contact() {
        *probe = Probe::new();
        return;
    } else if b.bus.probe_step(&mut b.adc, probe) {
        return;
    }
    if let Some(found) = probe.result() {
        b.probe = None;
        app.set_wiring(found, &mut b.serial);
    }
}

/// `info touch-arm <version> commit <git commit> reset <cause>`: the crate
/// version, the commit the firmware was built from (`build.rs`: 12 hex
/// digits, `-dirty` when the tree differed from it, `unknown` without git)
/// and why the chip started. Every piece is in flash (`t!`), the line in
/// this function's frame only.
#[inline(never)] // avr-trap: frame-size
fn report_boot(serial: &mut Usart0, cause: ResetCause) {
    let mut line = Line::new();
    line.str(touch_arm::t!("info touch-arm ")).str(touch_arm::t!(touch_arm::VERSION));
    line.str(touch_arm::t!(" commit ")).str(touch_arm::t!(touch_arm::COMMIT));
    line.str(touch_arm::t!(" reset ")).str(reset_name(cause));
    serial.write(line.finish());
}

/// `info lcd <name> id 0x… <w>x<h>`, or `warn lcd unknown id 0x…` with the
/// Read ID4 answer and then the other two probes: what the probe found.
/// With display overrides (`cal set lcd`) a second line says which:
/// `info lcd forced <name>` (or `auto`), ` invert`, ` rotate 180`; a forced
/// controller the probe did not find makes it `warn lcd forced <name> …
/// not detected`.
#[inline(never)] // avr-trap: frame-size
#[cfg_attr(target_arch = "avr", optimize(size))] // reason: cold
fn report_lcd(serial: &mut Usart0, ids: &IdReads, found: Option<Controller>, display: &LcdSettings) {
    let mut line = Line::new();
    match found {
        Some(c) => {
            let (w, h) = c.size();
            let digits = if c.id() > 0xFFFF { 6 } else { 4 };
            line.str(touch_arm::t!("info lcd ")).str(c.name()).str(touch_arm::t!(" id ")).hex(c.id(), digits);
            line.bytes(b" ").u32(u32::from(w)).bytes(b"x").u32(u32::from(h));
        }
        None => {
            line.str(touch_arm::t!("warn lcd unknown id ")).hex(ids.id4_value(), 6);
            line.str(touch_arm::t!(" reg00 ")).hex(u32::from(ids.reg00_value()), 4);
            line.str(touch_arm::t!(" rddid ")).hex(ids.rddid_value(), 6);
        }
    }
    serial.write(line.finish());
    if *display == LCD_DEFAULT {
        return;
    }
    let forced = Controller::forced(display.controller);
    let missed = forced.is_some() && forced != found;
    line.clear().str(if missed { touch_arm::t!("warn lcd ") } else { touch_arm::t!("info lcd ") });
    if forced.is_some() {
        line.str(touch_arm::t!("forced "));
    }
    line.str(display.controller.name());
    if display.invert {
        line.str(touch_arm::t!(" invert"));
    }
    if display.rotate_180 {
        line.str(touch_arm::t!(" rotate 180"));
    }
    if missed {
        line.str(touch_arm::t!(" not detected"));
    }
    serial.write(line.finish());
}

/// The configured pulse limits per joint, in Timer5 ticks (0.5 µs).
fn tick_limits(cfg: &Config) -> [TickLimits; CHANNELS] {
    cfg.joints.map(|j| TickLimits::of_joint(&j))
}

/// After the boot frame: the pulses of the last period before the reset,
/// if RAM kept them and the cause allows, else the home pose; the app says
/// which (`info reset …`). Out of line, so the block's copy is not in
/// `main`'s frame, which sits under every other.
#[inline(never)] // avr-trap: frame-size
fn resume_or_home(app: &mut App, cause: ResetCause, serial: &mut Usart0) {
    app.restart(&Restart { kind: reset_kind(cause), pulses: resume::load() }, serial);
}

/// The reset flags as `app::resume` judges them: a power-on or brown-out
/// flag wins over the others (RAM may be lost then).
fn reset_kind(c: ResetCause) -> ResetKind {
    if c.power_on() {
        ResetKind::PowerOn
    } else if c.brown_out() {
        ResetKind::BrownOut
    } else if c.watchdog() {
        ResetKind::Watchdog
    } else if c.external() {
        ResetKind::External
    } else {
        ResetKind::Unknown
    }
}

fn reset_name(c: ResetCause) -> touch_arm::text::Text {
    if c.watchdog() {
        touch_arm::t!("watchdog")
    } else if c.brown_out() {
        touch_arm::t!("brownout")
    } else if c.external() {
        touch_arm::t!("external")
    } else if c.power_on() {
        touch_arm::t!("power-on")
    } else {
        // Some bootloaders clear the flags before the app starts.
        touch_arm::t!("unknown")
    }
}
