//! The real firmware under simavr: where its ELF is, how to load it, and how to
//! read the lines it prints. Shared by the main-job binary and the tests.

use std::path::{Path, PathBuf};

use crate::avr::{Avr, Error};
use touch_arm::seam::pins::mega;

// The pure references moved to the twin (`hal_sim::host`); the firmware
// session's callers keep finding them here.
pub use hal_sim::host::{
    default_servo_maps, effector_at, host_geometry, host_target, map_touch, map_touch_on, raw_at_centre, raw_at_pixel,
    raw_to_map_point, raw_to_map_point_on, HostTarget,
};

/// ATmega2560 on the Mega 2560 board.
pub const MCU: &str = "atmega2560";
/// The Mega's crystal: 16 MHz.
pub const CPU_HZ: u32 = 16_000_000;

/// The workspace root (where memory.x and target/ live).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// An AVR release ELF of this workspace: `$CARGO_TARGET_DIR` (or target/)
/// `/avr-none/release/<name>.elf`, or the path in the override variable.
fn avr_elf(name: &str, override_var: &str) -> PathBuf {
    if let Some(p) = std::env::var_os(override_var) {
        return PathBuf::from(p);
    }
    avr_release_dir().join(format!("{name}.elf"))
}

/// `$CARGO_TARGET_DIR` (or target/) `/avr-none/release`.
fn avr_release_dir() -> PathBuf {
    let target =
        std::env::var_os("CARGO_TARGET_DIR").map(PathBuf::from).unwrap_or_else(|| workspace_root().join("target"));
    target.join("avr-none/release")
}

/// The product firmware (`cargo avr`), or `TOUCH_ARM_ELF`.
pub fn default_elf() -> PathBuf {
    avr_elf("touch-arm", "TOUCH_ARM_ELF")
}

/// The benchmark firmware (`cargo avr-bench`), or `TOUCH_ARM_BENCH_ELF`.
pub fn bench_elf() -> PathBuf {
    avr_elf("bench", "TOUCH_ARM_BENCH_ELF")
}

/// The on-chip UI check (`cargo avr`), or `UI_DEMO_ELF`.
pub fn ui_demo_elf() -> PathBuf {
    avr_elf("ui-demo", "UI_DEMO_ELF")
}

/// The code-above-128-KiB check (`cargo avr`), or `TOUCH_ARM_FAR_CALL_ELF`.
pub fn far_call_elf() -> PathBuf {
    avr_elf("far-call", "TOUCH_ARM_FAR_CALL_ELF")
}

/// The example programs the test command builds (`cargo avr`, and `cargo
/// avr-mipidsi` for the last).
pub const EXAMPLES: [&str; 3] = ["panel-probe", "servo-sweep", "mipidsi-fill"];

/// Every firmware and example the test command builds, by name: what the
/// post-link checks (`xtask/tests/firmware_elf.rs`) run over.
pub fn all_elfs() -> Vec<(&'static str, PathBuf)> {
    let mut elfs = vec![
        ("touch-arm", default_elf()),
        ("bench", bench_elf()),
        ("ui-demo", ui_demo_elf()),
        ("far-call", far_call_elf()),
    ];
    elfs.extend(EXAMPLES.iter().map(|name| (*name, example_elf(name))));
    elfs
}

/// An example program (`examples/`, built by `cargo avr`), e.g. "panel-probe".
pub fn example_elf(name: &str) -> PathBuf {
    avr_release_dir().join("examples").join(format!("{name}.elf"))
}

/// A budget from memory.x: `__budget_<name> = <n>K;` or `= <n>;`, in bytes.
pub fn budget(name: &str) -> Result<u64, String> {
    let path = workspace_root().join("memory.x");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    budget_in(&text, name)
}

/// [`budget`] from memory.x's text.
pub fn budget_in(memory_x: &str, name: &str) -> Result<u64, String> {
    let key = format!("__budget_{name}");
    let line =
        memory_x.lines().find(|l| l.trim_start().starts_with(&key)).ok_or_else(|| format!("memory.x has no {key}"))?;
    let value = line.split('=').nth(1).and_then(|v| v.split(';').next()).map(str::trim).unwrap_or("");
    let parsed = match value.strip_suffix('K') {
        Some(k) => k.parse::<u64>().map(|k| k * 1024),
        None => value.parse::<u64>(),
    };
    parsed.map_err(|_| format!("memory.x: {key} = {value:?} is not a size"))
}

/// The chip's RAM from memory.x's text (`RAM … LENGTH = 8K`), in bytes.
pub fn ram_in(memory_x: &str) -> Result<u64, String> {
    let line = memory_x
        .lines()
        .find(|l| l.trim_start().starts_with("RAM ") || l.trim_start().starts_with("RAM("))
        .ok_or("memory.x has no RAM region")?;
    let value = line.split("LENGTH").nth(1).and_then(|v| v.split('=').nth(1)).map(str::trim).unwrap_or("");
    let parsed = match value.strip_suffix('K') {
        Some(k) => k.parse::<u64>().map(|k| k * 1024),
        None => value.parse::<u64>(),
    };
    parsed.map_err(|_| format!("memory.x: RAM LENGTH {value:?} is not a size"))
}

/// What the benchmark firmware's stack bound must leave free between its
/// deepest point and its static RAM ([`stack_budget_in`]).
pub const BENCH_STACK_MARGIN: u64 = 512;

/// The stack budget of the ELF named `elf` whose static RAM (`.data` +
/// `.bss`) is `static_ram` bytes, given memory.x's text.
///
/// The product is held to `__budget_stack`: 2 KiB is what it may take of
/// the 8 KiB beside its 3.5 KiB static RAM budget, with room left for the
/// features still to come (issue #22 §4). So are the UI and far-call
/// checks and the examples, which fit it with room.
///
/// The benchmark firmware (`bench`) is held to the RAM it actually leaves
/// free, less [`BENCH_STACK_MARGIN`]: it does not ship, its static RAM is
/// its own (1.9 KiB, not the product's 3 KiB), and its deepest frames are
/// its own harness (the inputs and closures of its timed routines, ~2.5 KiB
/// of its 3.3 KiB bound), which no product path has. What a stack overflow
/// would cost it is its figures (the stack running into `.bss`), so the
/// limit that matters is where its `.bss` ends. The product routines it
/// times are held to 2 KiB by the product ELF's own bound, where they run
/// under the product's callers; shrinking the harness to the product's
/// budget would protect nothing. The
/// margin is a fixed 512 B (a quarter of the product's budget): the gate
/// fails while the stack still clears `.bss` by that much, not at the
/// byte where the figures would start to go wrong.
pub fn stack_budget_in(memory_x: &str, elf: &str, static_ram: u64) -> Result<u64, String> {
    Ok(stack_budget_of(elf, budget_in(memory_x, "stack")?, ram_in(memory_x)?, static_ram))
}

/// [`stack_budget_in`]'s rule on memory.x's figures: `stack` is
/// `__budget_stack`, `ram` the chip's RAM.
pub fn stack_budget_of(elf: &str, stack: u64, ram: u64, static_ram: u64) -> u64 {
    if elf == "bench" {
        ram.saturating_sub(static_ram).saturating_sub(BENCH_STACK_MARGIN)
    } else {
        stack
    }
}

/// [`stack_budget_in`] with this workspace's memory.x.
pub fn stack_budget(elf: &str, static_ram: u64) -> Result<u64, String> {
    let path = workspace_root().join("memory.x");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    stack_budget_in(&text, elf, static_ram)
}

/// An ELF's section sizes as `avr-size -A` reports them.
pub fn section_sizes(elf: &Path) -> Result<Vec<(String, u64)>, String> {
    let out = std::process::Command::new("avr-size")
        .arg("-A")
        .arg(elf)
        .output()
        .map_err(|e| format!("avr-size (binutils-avr): {e}"))?;
    if !out.status.success() {
        return Err(format!("avr-size -A {}: {}", elf.display(), String::from_utf8_lossy(&out.stderr).trim()));
    }
    Ok(parse_section_sizes(&String::from_utf8_lossy(&out.stdout)))
}

/// The `(.section, bytes)` rows of `avr-size -A` output.
pub fn parse_section_sizes(text: &str) -> Vec<(String, u64)> {
    text.lines()
        .filter_map(|l| {
            let mut it = l.split_whitespace();
            let name = it.next()?;
            let size = it.next()?.parse().ok()?;
            name.starts_with('.').then(|| (name.to_string(), size))
        })
        .collect()
}

/// Runs an ELF until it prints `done` (or halts) and returns its UART text.
pub fn run_to_done(elf: &Path, max_seconds: f64) -> Result<String, String> {
    let mut avr = load(elf)?;
    let max = (max_seconds * CPU_HZ as f64) as u64;
    avr.run_until_output(b"done\n", max)
        .map_err(|e| format!("{} did not finish: {e:?}\n{}", elf.display(), avr.uart_output_string()))?;
    Ok(avr.uart_output_string())
}

/// Loads the firmware, with a message that says how to build it when missing.
pub fn load(elf: &Path) -> Result<Avr, String> {
    if !elf.exists() {
        return Err(format!("{} not found: build the firmware first with `cargo avr`", elf.display()));
    }
    Avr::load(elf, MCU, CPU_HZ).map_err(|e: Error| format!("loading {}: {e:?}", elf.display()))
}

/// Fill pattern for stack painting (unlikely as real stack content).
const STACK_PAINT: u8 = 0xA5;

/// The servo signal pins: base, shoulder, elbow on OC5A/B/C = PL3/PL4/PL5
/// (the firmware's pin map).
pub const SERVO_PINS: [crate::avr::Pin; 3] =
    [crate::avr::Pin::of(mega::SERVOS[0]), crate::avr::Pin::of(mega::SERVOS[1]), crate::avr::Pin::of(mega::SERVOS[2])];

/// The gripper servo's pin: OC1A = PB5 = D11 (Timer1, started with Timer5).
pub const GRIPPER_PIN: crate::avr::Pin = crate::avr::Pin::of(mega::GRIPPER);

/// The assistive switch's pin (issue #20 §4): D22 = PA0, an input under the
/// firmware's pull-up; the switch, normally open, closes it to ground.
pub const SWITCH_PIN: crate::avr::Pin = crate::avr::Pin::of(mega::SWITCH);

/// The firmware running in simavr with a touch panel on its ADC and its servo
/// pins watched: what the end-to-end tests and the main job drive.
pub struct Session {
    /// The simavr core running the firmware.
    pub avr: Avr,
    /// The display controller as the firmware's bus writes leave it.
    pub lcd: crate::lcd_bus::LcdBus,
    panel: std::rc::Rc<std::cell::RefCell<crate::panel::PanelOnPins>>,
    adc: std::rc::Rc<std::cell::Cell<AdcCount>>,
}

/// ADC conversions the firmware has started, on any channel: how many, and
/// the cycles of the first and the last.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct AdcCount {
    /// Conversions started.
    pub conversions: u64,
    /// CPU cycle of the first.
    pub first_cycle: u64,
    /// CPU cycle of the last.
    pub last_cycle: u64,
}

/// The `ts_ms` of a move reply (`ok goto … ts_ms 1234 …`), in seconds.
pub fn reply_ts(line: &str) -> Result<f64, String> {
    line.split_whitespace()
        .skip_while(|w| *w != "ts_ms")
        .nth(1)
        .and_then(|v| v.parse::<f64>().ok())
        .map(|ms| ms / 1000.0)
        .ok_or_else(|| format!("no ts_ms in {line:?}"))
}

impl Session {
    /// The product firmware (seed 8) with `eeprom` loaded before its first
    /// frame (erased if `None`, as after a power cycle with that EEPROM),
    /// its display up and the arm holding home.
    pub fn boot_product(eeprom: Option<&[u8]>) -> Result<Session, String> {
        let mut s = Session::start(&default_elf(), crate::panel::PanelWiring::A, 8)?;
        if let Some(e) = eeprom {
            s.avr.set_eeprom(0, e).map_err(|err| format!("eeprom: {err:?}"))?;
        }
        s.run_for(1.0)?;
        s.run_until_ready(2.0)?;
        Ok(s)
    }

    /// Sends `cmd`, whose reply must start with `want`, runs its move (the
    /// reply's `ts_ms`) and `settle_s` more, and checks the arm holds.
    pub fn go(&mut self, cmd: &str, want: &str, settle_s: f64) -> Result<(), String> {
        let reply = self.command(cmd)?;
        if !reply.starts_with(want) {
            return Err(format!("{cmd}: {reply}"));
        }
        self.run_for(reply_ts(&reply)? + settle_s)?;
        let status = self.command("status")?;
        if !status.starts_with("ok status holding") {
            return Err(format!("after {cmd}: {status}"));
        }
        Ok(())
    }

    /// The product firmware homed, its slow first move after power-up done
    /// (to 90° 100° −100°), at the fast preset: where the motion tests start.
    pub fn start_moved_fast(seed: u64) -> Result<Session, String> {
        let mut s = Session::start(&default_elf(), crate::panel::PanelWiring::A, seed)?;
        s.run_for(1.5)?;
        let fast = s.command("speed fast")?;
        if fast != "ok speed fast" {
            return Err(format!("speed fast: {fast}"));
        }
        let reply = s.command("goto 90 100 -100")?;
        s.run_for(reply_ts(&reply)? + 0.2)?;
        Ok(s)
    }

    /// Loads the ELF with the panel wired as `wiring` (the firmware's wiring)
    /// and an ILI9341 on the shield.
    pub fn start(elf: &Path, wiring: crate::panel::PanelWiring, seed: u64) -> Result<Session, String> {
        Self::start_with_lcd(elf, wiring, crate::lcd_bus::Chip::Ili9341, seed)
    }

    /// [`Session::start`] with `chip` as the shield's display controller.
    pub fn start_with_lcd(
        elf: &Path,
        wiring: crate::panel::PanelWiring,
        chip: crate::lcd_bus::Chip,
        seed: u64,
    ) -> Result<Session, String> {
        let mut avr = load(elf)?;
        // Before the first instruction, so the high-water mark covers the run.
        avr.paint_stack(STACK_PAINT).map_err(|e| format!("painting the stack: {e:?}"))?;
        for pin in SERVO_PINS.into_iter().chain([GRIPPER_PIN]) {
            avr.watch_pin(pin).map_err(|e| format!("{e:?}"))?;
        }
        let lcd = crate::lcd_bus::LcdBus::attach_chip(&mut avr, crate::lcd_bus::BusPins::MEGA_SHIELD, chip)
            .map_err(|e| format!("{e:?}"))?;
        let panel = std::rc::Rc::new(std::cell::RefCell::new(crate::panel::PanelOnPins {
            wiring,
            panel: hal_sim::panel::SimPanel::new(seed),
        }));
        let model = panel.clone();
        let adc = std::rc::Rc::new(std::cell::Cell::new(AdcCount::default()));
        let count = adc.clone();
        avr.set_adc_handler(move |req| {
            let mut c = count.get();
            if c.conversions == 0 {
                c.first_cycle = req.cycle;
            }
            c.conversions += 1;
            c.last_cycle = req.cycle;
            count.set(c);
            let v = model.borrow_mut().read(req).unwrap_or_else(|| crate::panel::PanelOnPins::read_off_panel(req));
            crate::avr::AdcInput::Raw(v)
        });
        Ok(Session { avr, lcd, panel, adc })
    }

    /// Presses the panel where the firmware's X and Y reads return (raw_x,
    /// raw_y) without noise, with a firm finger (force 1).
    pub fn press_raw(&mut self, raw_x: f64, raw_y: f64) -> Result<(), String> {
        self.panel.borrow_mut().panel.touch_raw(raw_x, raw_y, 1.0)
    }

    /// Presses at a normalized workspace point through the panel's true response.
    pub fn press_xy(&mut self, x_p: f64, y_p: f64) -> Result<(), String> {
        self.panel.borrow_mut().panel.touch_xy(x_p, y_p, 1.0)
    }

    /// Plays a finger script from now on (its t_ms = 0 is the current
    /// simulated time), evaluated at every ADC conversion's own cycle; it
    /// replaces any press and ends by itself after its last knot. The
    /// script's pixels are on the 2.8" glass unless [`Session::set_glass`]
    /// says otherwise.
    pub fn finger(&mut self, script: hal_sim::finger::FingerScript) {
        let now = self.avr.time_s();
        self.panel.borrow_mut().panel.set_finger(script, now);
    }

    /// The glass the finger scripts' pixels lie on (the screen's size and mm per pixel).
    pub fn set_glass(&mut self, glass: hal_sim::finger::Glass) {
        self.panel.borrow_mut().panel.glass = glass;
    }

    /// Lifts the finger from the panel.
    pub fn release(&mut self) {
        self.panel.borrow_mut().panel.release();
    }

    /// Closes (`down`) or opens the assistive switch on [`SWITCH_PIN`]: the
    /// pin driven low, or high (the level the firmware's pull-up gives an
    /// open switch). simavr re-applies an input's pull-up whenever the
    /// firmware writes its port's PORT or DDR register, so a caller that
    /// holds the switch across such writes (a reset re-initialises the
    /// port) drives it again afterwards.
    pub fn set_switch(&mut self, down: bool) -> Result<(), String> {
        self.avr.drive_pin(SWITCH_PIN, !down).map_err(|e| format!("driving the switch pin: {e:?}"))
    }

    /// The ADC conversions so far (the touch reads and the wiring probe's).
    pub fn adc_count(&self) -> AdcCount {
        self.adc.get()
    }

    /// ADC noise (σ, counts) and the probability of a random glitch per conversion.
    pub fn set_noise(&mut self, counts: f64, spike_prob: f64) {
        let mut p = self.panel.borrow_mut();
        p.panel.noise_counts = counts;
        p.panel.spike_prob = spike_prob;
    }

    /// Runs for `seconds` of simulated time.
    pub fn run_for(&mut self, seconds: f64) -> Result<(), String> {
        self.avr.run_for(seconds).map_err(|e| format!("{e:?}"))
    }

    /// Sends one command line and runs until the firmware's reply line
    /// (`ok ...` / `err ...`) arrives.
    pub fn command(&mut self, line: &str) -> Result<String, String> {
        let before = self.avr.uart_output().len();
        self.avr.uart_send(format!("{line}\n").as_bytes());
        let max = CPU_HZ as u64;
        self.avr
            .run_until(
                |a| {
                    let out = &a.uart_output()[before..];
                    // A complete reply line (the last piece after a split has no newline yet).
                    let mut lines: Vec<&[u8]> = out.split(|b| *b == b'\n').collect();
                    lines.pop();
                    lines.iter().any(|l| l.starts_with(b"ok") || l.starts_with(b"err"))
                },
                max,
            )
            .map_err(|e| format!("no reply to {line:?}: {e:?}"))?;
        let out = String::from_utf8_lossy(&self.avr.uart_output()[before..]).to_string();
        Ok(out.lines().find(|l| l.starts_with("ok") || l.starts_with("err")).unwrap_or("").to_string())
    }

    /// Runs until the firmware has booted, homed and takes targets (`status`
    /// says `holding`), polling every 0.1 s, for at most `max_s` seconds. The
    /// boot time depends on the display controller (the ILI9325's power-up
    /// sequence waits 350 ms more than the DCS controllers'), so a fixed wait
    /// would be too short for one or needlessly long for the others. Call it
    /// after the display's start-up (1 s in): serial bytes sent earlier would
    /// overrun the USART while the firmware is still initialising the LCD.
    pub fn run_until_ready(&mut self, max_s: f64) -> Result<(), String> {
        let end = self.avr.time_s() + max_s;
        loop {
            let reply = self.command("status")?;
            if reply.starts_with("ok status holding") {
                return Ok(());
            }
            if self.avr.time_s() > end {
                return Err(format!("not ready after {max_s} s: {reply}"));
            }
            self.run_for(0.1)?;
        }
    }

    /// The deepest the stack has been since power-up, in bytes.
    pub fn stack_high_water(&self) -> Option<usize> {
        self.avr.stack_high_water().map(|(used, _)| used)
    }

    /// Every complete servo pulse measured so far, per joint: (rise time s,
    /// width in Timer5 ticks of 0.5 µs), see [`pulse_ticks`].
    pub fn pulse_ticks(&self) -> [Vec<(f64, u16)>; 3] {
        SERVO_PINS.map(|pin| {
            pulse_ticks(&self.avr.pulses(pin)).into_iter().map(|(c, t)| (c as f64 / CPU_HZ as f64, t)).collect()
        })
    }

    /// Every complete gripper pulse measured so far: (rise time in CPU
    /// cycles, width in Timer1 ticks of 0.5 µs).
    pub fn grip_pulse_ticks(&self) -> Vec<(u64, u16)> {
        pulse_ticks(&self.avr.pulses(GRIPPER_PIN))
    }

    /// Every complete servo pulse measured so far, per joint: (rise time s,
    /// width µs, a multiple of 0.5 µs: [`Session::pulse_ticks`] halved).
    pub fn pulses(&self) -> [Vec<(f64, f64)>; 3] {
        self.pulse_ticks().map(|p| p.into_iter().map(|(t, ticks)| (t, f64::from(ticks) / 2.0)).collect())
    }

    /// Runs until the firmware has written a complete line starting with one
    /// of `prefixes` after byte `from` of its output, at most `max_s`
    /// seconds; returns the line and the time (s) its first byte was sent,
    /// or `None` on timeout.
    pub fn await_line(&mut self, from: usize, prefixes: &[&str], max_s: f64) -> Result<Option<(String, f64)>, String> {
        let find = |a: &crate::avr::Avr| -> Option<(usize, usize)> {
            let out = a.uart_output().get(from..)?;
            let mut start = 0;
            for (i, b) in out.iter().enumerate() {
                if *b == b'\n' {
                    let line = &out[start..i];
                    if prefixes.iter().any(|p| line.starts_with(p.as_bytes())) {
                        return Some((from + start, from + i));
                    }
                    start = i + 1;
                }
            }
            None
        };
        let max = (max_s * CPU_HZ as f64) as u64;
        match self.avr.run_until(|a| find(a).is_some(), max) {
            Ok(_) => {}
            Err(crate::avr::Error::Timeout { .. }) => return Ok(None),
            Err(e) => return Err(format!("{e:?}")),
        }
        let Some((a, b)) = find(&self.avr) else { return Ok(None) };
        let line = String::from_utf8_lossy(&self.avr.uart_output()[a..b]).trim_end().to_string();
        let t = self.avr.uart_output_cycles().get(a).map_or(self.avr.time_s(), |c| *c as f64 / CPU_HZ as f64);
        Ok(Some((line, t)))
    }

    /// The most recent pulse width per joint (µs), if the joint has pulsed.
    pub fn last_pulses(&self) -> [Option<f64>; 3] {
        self.pulses().map(|p| p.last().map(|(_, w)| *w))
    }
}

/// Timer5's period in CPU cycles: 40 000 ticks of 8 cycles (0.5 µs).
const PERIOD_CYCLES: u64 = 320_000;
const CYCLES_PER_TICK: u64 = 8;

/// Pulse widths in Timer5 ticks from cycle-stamped edges: (rise cycle,
/// ticks). A stamp lags its edge by 0 to 4 cycles (see `avr::pins`), so a
/// width read plainly is off by up to ±4 cycles, half a tick. Every rise
/// happens at a period start (BOTTOM), on a grid of `PERIOD_CYCLES`:
/// the smallest lag of the rises on one grid stands for the grid itself
/// (a watchdog reset restarts the timer and starts a new grid), so the
/// width measured from it errs by the fall's lag only, 0 to 4 cycles, and
/// rounding it down to the tick is exact.
pub fn pulse_ticks(pulses: &[crate::avr::Pulse]) -> Vec<(u64, u16)> {
    // Offsets of every rise from its grid's first rise, modulo the period.
    let off = |c: u64, r0: u64| -> i64 {
        let d = ((c - r0) % PERIOD_CYCLES) as i64;
        if d > (PERIOD_CYCLES / 2) as i64 {
            d - PERIOD_CYCLES as i64
        } else {
            d
        }
    };
    let mut out = Vec::with_capacity(pulses.len());
    let mut i = 0;
    while i < pulses.len() {
        let r0 = pulses[i].rise_cycle;
        let mut end = i + 1;
        while end < pulses.len() && off(pulses[end].rise_cycle, r0).abs() <= 2 * CYCLES_PER_TICK as i64 {
            end += 1;
        }
        let min_lag = pulses[i..end].iter().map(|p| off(p.rise_cycle, r0)).min().unwrap_or(0);
        for p in &pulses[i..end] {
            let fall = (p.rise_cycle + p.width_cycles) as i64;
            let rise = p.rise_cycle as i64 - off(p.rise_cycle, r0) + min_lag;
            let ticks = ((fall - rise).max(0) as u64 + CYCLES_PER_TICK / 2 - 1) / CYCLES_PER_TICK;
            out.push((p.rise_cycle, ticks.min(u64::from(u16::MAX)) as u16));
        }
        i = end;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::avr::Pulse;

    /// Rises on the period grid and falls after whole ticks, each edge
    /// stamped 0 to 4 cycles late: the widths come out in exact ticks, also
    /// across a restart of the timer (a new grid).
    #[test]
    fn pulse_widths_are_whole_ticks_despite_late_stamps() {
        let mut pulses = Vec::new();
        let mut want = Vec::new();
        for k in 0..40u64 {
            let ticks = 2999 + k % 5;
            // A second grid after a reset, 123 cycles off the first.
            let bottom = if k < 20 { 1000 + k * PERIOD_CYCLES } else { 1123 + (k + 3) * PERIOD_CYCLES };
            let (rise_lag, fall_lag) = ((k * 7) % 5, (k * 3) % 5);
            let rise = bottom + rise_lag;
            let fall = bottom + ticks * CYCLES_PER_TICK + fall_lag;
            pulses.push(Pulse { rise_cycle: rise, width_cycles: fall - rise });
            want.push((rise, ticks as u16));
        }
        assert_eq!(pulse_ticks(&pulses), want);
    }
}
