//! The real firmware under simavr: where its ELF is, how to load it, and how to
//! read the lines it prints. Shared by the main-job binary and the tests.

use std::path::{Path, PathBuf};

use crate::avr::{Avr, Error};

/// ATmega2560 on the Mega 2560 board.
pub const MCU: &str = "atmega2560";
pub const CPU_HZ: u32 = 16_000_000;

/// The workspace root (where memory.x and target/ live).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// An AVR release ELF of this workspace: `$CARGO_TARGET_DIR` (or target/)
/// `/avr-none/release/<name>.elf`, or the path in the override variable.
fn avr_elf(name: &str, override_var: &str) -> PathBuf {
    if let Some(p) = std::env::var_os(override_var) {
        return PathBuf::from(p);
    }
    let target =
        std::env::var_os("CARGO_TARGET_DIR").map(PathBuf::from).unwrap_or_else(|| workspace_root().join("target"));
    target.join("avr-none/release").join(format!("{name}.elf"))
}

/// The product firmware (`cargo avr`), or `TOUCH_ARM_ELF`.
pub fn default_elf() -> PathBuf {
    avr_elf("touch-arm", "TOUCH_ARM_ELF")
}

/// The benchmark firmware (`cargo avr-bench`), or `TOUCH_ARM_BENCH_ELF`.
pub fn bench_elf() -> PathBuf {
    avr_elf("bench", "TOUCH_ARM_BENCH_ELF")
}

/// A budget from memory.x: `__budget_<name> = <n>K;` or `= <n>;`, in bytes.
pub fn budget(name: &str) -> Result<u64, String> {
    let path = workspace_root().join("memory.x");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let key = format!("__budget_{name}");
    let line =
        text.lines().find(|l| l.trim_start().starts_with(&key)).ok_or_else(|| format!("memory.x has no {key}"))?;
    let value = line.split('=').nth(1).and_then(|v| v.split(';').next()).map(str::trim).unwrap_or("");
    let parsed = match value.strip_suffix('K') {
        Some(k) => k.parse::<u64>().map(|k| k * 1024),
        None => value.parse::<u64>(),
    };
    parsed.map_err(|_| format!("memory.x: {key} = {value:?} is not a size"))
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

/// The servo signal pins: base, shoulder, elbow on OC5A/B/C = PL3/PL4/PL5.
pub const SERVO_PINS: [crate::avr::Pin; 3] =
    [crate::avr::Pin::new('L', 3), crate::avr::Pin::new('L', 4), crate::avr::Pin::new('L', 5)];

/// The firmware running in simavr with a touch panel on its ADC and its servo
/// pins watched: what the end-to-end tests and the main job drive.
pub struct Session {
    pub avr: Avr,
    /// The ILI9341 as the firmware's bus writes leave it.
    pub lcd: crate::lcd_bus::LcdBus,
    panel: std::rc::Rc<std::cell::RefCell<crate::panel::PanelOnPins>>,
}

impl Session {
    /// Loads the ELF with the panel wired as `wiring` (the firmware's wiring).
    pub fn start(elf: &Path, wiring: crate::panel::PanelWiring, seed: u64) -> Result<Session, String> {
        let mut avr = load(elf)?;
        // Before the first instruction, so the high-water mark covers the run.
        avr.paint_stack(STACK_PAINT).map_err(|e| format!("painting the stack: {e:?}"))?;
        for pin in SERVO_PINS {
            avr.watch_pin(pin).map_err(|e| format!("{e:?}"))?;
        }
        let lcd = crate::lcd_bus::LcdBus::attach(&mut avr, crate::lcd_bus::BusPins::MEGA_SHIELD)
            .map_err(|e| format!("{e:?}"))?;
        let panel = std::rc::Rc::new(std::cell::RefCell::new(crate::panel::PanelOnPins {
            wiring,
            panel: crate::twin::panel::SimPanel::new(seed),
        }));
        let model = panel.clone();
        avr.set_adc_handler(move |req| match model.borrow_mut().read(req) {
            Some(v) => crate::avr::AdcInput::Raw(v),
            None => crate::avr::AdcInput::Raw(0),
        });
        Ok(Session { avr, lcd, panel })
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

    pub fn release(&mut self) {
        self.panel.borrow_mut().panel.release();
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
/// happens at a period start (BOTTOM), on a grid of [`PERIOD_CYCLES`]:
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

/// Where to press the panel to pick workspace point (x, y) on the screen's
/// map: the raw reading (default calibration) of the centre of the map pixel
/// that shows the point, and that pixel's centre in workspace coordinates,
/// which is the point the firmware sends the arm to (`ui::layout`).
pub fn map_touch(x: f32, y: f32) -> Option<((f64, f64), (f64, f64))> {
    use touch_arm::ui::layout;
    let (px, py) = layout::ws_point_to_pixel(x, y)?;
    let (panel_x, panel_y) = layout::pixel_center_to_panel(px, py);
    let (raw_x, raw_y) =
        touch_arm::touch::map::Calibration::DEFAULT.unmap_exact::<f64>(f64::from(panel_x), f64::from(panel_y)).ok()?;
    let (wx, wy) = layout::ws_pixel_to_point(px, py)?;
    Some(((raw_x.round(), raw_y.round()), (f64::from(wx), f64::from(wy))))
}

/// The workspace point a raw reading picks on the screen's map, if it lands
/// on the map at all.
pub fn raw_to_map_point(raw_x: u16, raw_y: u16) -> Option<(f64, f64)> {
    use touch_arm::ui::layout;
    let m = touch_arm::touch::map::Calibration::DEFAULT.map::<f32>(raw_x, raw_y).ok()?;
    let (px, py) = layout::panel_to_pixel(m.x_p, m.y_p)?;
    let (wx, wy) = layout::ws_pixel_to_point(px, py)?;
    Some((f64::from(wx), f64::from(wy)))
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
