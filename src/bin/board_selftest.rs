//! Board-layer self-test firmware (not the app): exercises every driver in
//! `touch_arm::board` and reports on USART0. Meant for simavr with the
//! harness `board_selftest_harness.c` (which models the touch panel on the
//! ADC, types into the UART and checks pin states at every conversion), and
//! usable on a real Mega with a serial terminal.
//!
//! Report lines: `<test> ok ...` or `<test> FAIL ...`; the run ends with
//! `selftest done fails=<n>`. The first boot ends by letting the watchdog
//! bite; the second boot (reset cause WDRF) reports that and finishes.
//!
//! ```text
//! cargo build --release --target avr-none -Z build-std=core --features firmware --bin board-selftest
//! cc -O2 -o /tmp/board_harness src/bin/board_selftest_harness.c -I/usr/include/simavr -lsimavr -lelf
//! /tmp/board_harness target/avr-none/release/board-selftest.elf   # exit 0 = pass
//! ```
#![no_std]
#![no_main]

use avr_device::atmega2560 as pac;
use touch_arm::board::adc::{Adc, AdcError};
use touch_arm::board::eeprom::{Eeprom, EEPROM_SIZE};
use touch_arm::board::gpio::PinMode;
use touch_arm::board::servo_pwm::{ServoPwm, TickLimits, CHANNELS};
use touch_arm::board::shield::{LcdLine, ShieldBus};
use touch_arm::board::tick::Tick;
use touch_arm::board::touch::TouchWiring;
use touch_arm::board::usart::Usart0;
use touch_arm::board::watchdog::{Timeout, Watchdog};
use touch_arm::board::delay_us;
use touch_arm::config_store::{Storage, StorageError};
use touch_arm::seam::{Clock, SerialPort, ServoOutputs, TouchPanel};
use touch_arm::touch_filter::RawSample;
use ufmt::{uwrite, uwriteln};

/// EEPROM address of the test pattern (far from the config records at 0).
const EE_TEST_ADDR: u16 = 4000;
/// GPIOR0 tells the harness which wiring is being read (1..=3); bit 7 asks it
/// to model an untouched panel.
const GPIOR_UNTOUCHED: u8 = 0x80;

struct Report {
    fails: u16,
}

impl Report {
    fn check(&mut self, serial: &mut Usart0, name: &str, ok: bool) {
        if !ok {
            self.fails += 1;
        }
        let _ = uwriteln!(serial, "{} {}", name, if ok { "ok" } else { "FAIL" });
    }
}

#[avr_device::entry]
fn main() -> ! {
    let Some(dp) = pac::Peripherals::take() else { halt() };
    let (mut wd, cause) = Watchdog::boot(dp.WDT, &dp.CPU);
    let mut serial = Usart0::new(dp.USART0);
    let mut rep = Report { fails: 0 };
    let _ = uwriteln!(serial, "selftest mcusr={} wdrf={}", cause.bits(), cause.watchdog() as u8);

    let tick = Tick::new(dp.TC0);
    // SAFETY: every static the ISRs touch is initialised by now.
    unsafe { avr_device::interrupt::enable() };

    // Tick: 100 ms of busy-waiting by cycle count must read as ~100 ms (the
    // tick ISR and the busy loop interfere a little: allow 100..=104).
    let t0 = tick.now_ms();
    for _ in 0..100 {
        delay_us(1000);
    }
    let dt = tick.now_ms().wrapping_sub(t0);
    let _ = uwriteln!(serial, "tick dt={}", dt);
    rep.check(&mut serial, "tick", (100..=104).contains(&dt));
    let t1 = tick.now_ms();
    tick.delay_ms(20);
    let dt = Clock::now_ms(&tick).wrapping_sub(t1);
    let _ = uwriteln!(serial, "delay_ms(20) dt={}", dt);
    rep.check(&mut serial, "delay_ms", (20..=22).contains(&dt));

    eeprom_test(&mut serial, &mut rep, dp.EEPROM, cause.watchdog());

    let mut adc = Adc::new(dp.ADC);
    for ch in [0u8, 5, 8, 15] {
        match adc.read(ch) {
            Ok(v) => {
                let _ = uwriteln!(serial, "adc ch={} v={}", ch, v);
                rep.check(&mut serial, "adc", v <= 1023);
            }
            Err(_) => rep.check(&mut serial, "adc", false),
        }
    }
    rep.check(&mut serial, "adc badch", adc.read(16) == Err(AdcError::BadChannel));

    let mut bus = ShieldBus::new(dp.PORTE, dp.PORTF, dp.PORTG, dp.PORTH);
    let lcd_mode = bus.pin_modes();
    let all_out = lcd_mode.iter().all(|m| matches!(m, PinMode::OutputHigh | PinMode::OutputLow));
    rep.check(&mut serial, "lcd pins outputs", all_out);
    touch_test(&mut serial, &mut rep, &mut bus, &mut adc, &dp.CPU);

    servo_test(&mut serial, &mut rep, dp.TC5, &dp.PORTL);
    uart_test(&mut serial, &mut rep, &tick);

    if cause.watchdog() {
        rep.check(&mut serial, "watchdog reset seen", true);
        let _ = uwriteln!(serial, "selftest done fails={}", rep.fails);
        serial.flush();
        halt()
    }
    // Watchdog: fed it survives 600 ms at a 250 ms timeout, unfed it resets.
    wd.enable(Timeout::Ms250);
    for _ in 0..6 {
        tick.delay_ms(100);
        wd.feed();
    }
    let _ = uwriteln!(serial, "wdt fed ok; first boot fails={}; hanging", rep.fails);
    serial.flush();
    loop {}
}

fn eeprom_test(serial: &mut Usart0, rep: &mut Report, regs: pac::EEPROM, second_boot: bool) {
    let mut ee = Eeprom::new(regs);
    let pattern = [0xA5u8, 0x5A, 0x00, 0xFF, 0x42, 0x17];
    let mut back = [0u8; 6];
    if second_boot {
        // Written on the first boot: must have survived the watchdog reset.
        let r = ee.read(EE_TEST_ADDR, &mut back);
        rep.check(serial, "eeprom persists", r.is_ok() && back == pattern);
    }
    let w = ee.write(EE_TEST_ADDR, &pattern);
    let r = ee.read(EE_TEST_ADDR, &mut back);
    let _ = uwriteln!(serial, "eeprom back={} {} {} {} {} {}", back[0], back[1], back[2], back[3], back[4], back[5]);
    rep.check(serial, "eeprom rw", w.is_ok() && r.is_ok() && back == pattern);
    // Rewriting the same bytes starts no write: EEPE stays clear right after.
    let again = ee.write(EE_TEST_ADDR, &pattern).is_ok();
    // SAFETY: read-only peek at EECR for the test.
    let eecr = unsafe { (*pac::EEPROM::ptr()).eecr().read().bits() };
    rep.check(serial, "eeprom skip unchanged", again && eecr & 0b10 == 0);
    rep.check(serial, "eeprom range", ee.write(EEPROM_SIZE - 2, &pattern) == Err(StorageError::OutOfRange));
    rep.check(serial, "eeprom range rd", ee.read(EEPROM_SIZE, &mut back[..1]) == Err(StorageError::OutOfRange));
    rep.check(serial, "eeprom last byte", ee.read(EEPROM_SIZE - 1, &mut back[..1]).is_ok());
}

/// Raw DDR and PORT bytes of ports E, F, G, H (data addresses).
fn port_bytes() -> [u8; 8] {
    const ADDRS: [usize; 8] = [0x2D, 0x2E, 0x30, 0x31, 0x33, 0x34, 0x101, 0x102];
    // SAFETY: read-only volatile peeks at I/O registers, for the comparison.
    ADDRS.map(|a| unsafe { core::ptr::read_volatile(a as *const u8) })
}

fn touch_test(serial: &mut Usart0, rep: &mut Report, bus: &mut ShieldBus, adc: &mut Adc, cpu: &pac::CPU) {
    // A non-idle LCD state (CS active, WR low, a data byte on the bus) must
    // come back exactly too, not just the power-on pattern.
    bus.write_data(0xA5);
    bus.set_line(LcdLine::Cs, false);
    for idx in 0..4u8 {
        let (wiring, gpior) = match idx {
            0 => (TouchWiring::A, 1),
            1 => (TouchWiring::B, 2),
            2 => (TouchWiring::C, 3),
            _ => (TouchWiring::A, 1 | GPIOR_UNTOUCHED),
        };
        if idx == 3 {
            bus.set_line(LcdLine::Wr, false);
        }
        // SAFETY: GPIOR0 is a free general-purpose register; the harness
        // reads it to know what to model.
        cpu.gpior0().write(|w| unsafe { w.bits(gpior) });
        let before = port_bytes();
        let modes = bus.pin_modes();
        let mut buf = [RawSample { x: 0, y: 0, z: 0 }; 5];
        let n = bus.touch(adc, &wiring).read(&mut buf);
        let after = port_bytes();
        let _ = uwrite!(serial, "touch w={} n={}", gpior, n);
        for s in &buf[..n.min(buf.len())] {
            let _ = uwrite!(serial, " ({},{},{})", s.x, s.y, s.z);
        }
        let _ = uwriteln!(serial, "");
        rep.check(serial, "touch n", n == buf.len());
        rep.check(serial, "touch restore", before == after && modes == bus.pin_modes());
    }
    // SAFETY: as above.
    cpu.gpior0().write(|w| unsafe { w.bits(0) });
    bus.set_line(LcdLine::Wr, true);
    bus.set_line(LcdLine::Cs, true);
    // The lent handle reads too, inside with_touch.
    let w = TouchWiring::B;
    let ok = bus.with_touch(adc, &w, |p| p.read_x().is_ok() && p.read_y().is_ok());
    rep.check(serial, "with_touch", ok);
}

fn servo_test(serial: &mut Usart0, rep: &mut Report, tc5: pac::TC5, portl: &pac::PORTL) {
    let limits = [TickLimits { min: 1000, max: 5000 }; CHANNELS];
    let mut pwm = ServoPwm::new(tc5, portl, &limits);
    pwm.set_pulses(&[1500, 100, 3000]);
    // SAFETY: read-only peeks at the compare registers.
    let regs = unsafe { &*pac::TC5::ptr() };
    let (a, b, c) = avr_device::interrupt::free(|_| {
        (regs.ocr5a().read().bits(), regs.ocr5b().read().bits(), regs.ocr5c().read().bits())
    });
    let _ = uwriteln!(serial, "servo ocr={} {} {}", a, b, c);
    rep.check(serial, "servo", a == 3000 && b == 1000 && c == 5000);
    ServoOutputs::disable(&mut pwm);
    let com = regs.tccr5a().read().bits() & 0b1111_1100;
    rep.check(serial, "servo disable", com == 0);
}

fn uart_test(serial: &mut Usart0, rep: &mut Report, tick: &Tick) {
    while serial.read_byte().is_some() {}
    let _ = serial.take_rx_errors();
    // Echo: the harness types a line after the prompt.
    let _ = uwriteln!(serial, "echo>");
    let mut line = [0u8; 16];
    let mut n = 0;
    let start = tick.now_ms();
    while tick.now_ms().wrapping_sub(start) < 500 {
        if let Some(b) = SerialPort::read_byte(serial) {
            if b == b'\n' {
                break;
            }
            if let Some(slot) = line.get_mut(n) {
                *slot = b;
                n += 1;
            }
        }
    }
    serial.write(b"echo [");
    serial.write(&line[..n]);
    serial.write(b"]\n");
    rep.check(serial, "uart echo", &line[..n] == b"hello board");
    // Flood: 200 bytes arrive while nobody reads; the ring keeps 128 and
    // flags the overflow.
    let _ = uwriteln!(serial, "flood>");
    tick.delay_ms(40);
    let kept = serial.rx_len();
    let errs = serial.take_rx_errors();
    let mut first = 0u8;
    let mut count = 0u16;
    while let Some(b) = serial.read_byte() {
        if count == 0 {
            first = b;
        }
        count += 1;
    }
    let _ = uwriteln!(serial, "flood kept={} read={} first={} overflow={}", kept, count, first, errs.overflow as u8);
    rep.check(serial, "uart overflow", kept == 128 && count == 128 && first == 0 && errs.overflow);
    let cleared = !serial.take_rx_errors().overflow;
    rep.check(serial, "uart flag cleared", cleared);
}

/// Stops for good: interrupts off, CPU asleep (simavr ends the run here).
fn halt() -> ! {
    avr_device::interrupt::disable();
    // SAFETY: single-threaded end of the program.
    let dp = unsafe { pac::Peripherals::steal() };
    dp.CPU.smcr().write(|w| w.se().set_bit());
    loop {
        avr_device::asm::sleep();
    }
}

#[panic_handler]
fn panic(_: &core::panic::PanicInfo) -> ! {
    avr_device::interrupt::disable();
    // SAFETY: the program is dead; reclaim USART0 to say so.
    let dp = unsafe { pac::Peripherals::steal() };
    let mut serial = Usart0::new(dp.USART0);
    let _ = uwriteln!(serial, "PANIC");
    serial.flush();
    halt()
}
