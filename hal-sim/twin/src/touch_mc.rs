//! The touch Monte Carlo of issue #19 §6: seeded finger scripts
//! ([`crate::finger::gen`]) played on the twin's panel, tap after tap, into
//! the app as the firmware runs it (the screen on, 320×240), and what the app
//! did with each tap read from its own serial lines ([`crate::touches`]), so
//! the same harness measures whatever touch logic is compiled in: the
//! "before" column today, the "after" one once the new logic is merged.
//!
//! Per tap: a script starts at a frame's start, the twin runs until
//! [`SETTLE_MS`] after the script's end, and every touch action printed
//! meanwhile belongs to that tap. Per cell:
//! - `err_p99_mm`: the 99th percentile of the distance (mm on the glass)
//!   between each `move`'s raw point and the tap's intended point;
//! - `once`: the share of taps with exactly one `move`;
//! - `none`: the share with no `move` at all;
//! - `actions`: touch actions per tap (every kind);
//! - `moves`: `move`s in all (what brief contacts and off-map ends must not do);
//! - `far`: `move`s more than [`FAR_MM`] from the intended point (a palm's midpoint);
//! - `releases`: bounce trials on STOP that printed a `resume`;
//! - `stop_p99_ms`: how long after the contact began STOP latched (99th percentile).
//!
//! The ADC noise is 1 count (σ) per conversion; targets are drawn in the
//! middle of the map (workspace x in [−0.5, 0.5], y in [0.4, 0.6]) so a
//! 5 mm tremor stays on it. Before the first tap the panel is calibrated on
//! the screen as a carer does at set-up ([`calibrate_on_screen`]), which
//! also measures the panel's plate ratio that the second-contact check uses
//! (`touch::contact`).

use touch_arm::app::{AppParams, FRAME_MS};
use touch_arm::touch::map::Calibration;
use touch_arm::ui::Layout;

use crate::finger::gen::{self, Palm, Slide, TapPlan, Tremor};
use crate::finger::{FingerScript, Glass, Knot, Track};
use crate::rng::Rng;
use crate::sim::{Sim, SimSetup};
use crate::touches::{touch_action, TouchAction};

/// Quiet time after each script before the next tap, ms: longer than the
/// release debounce and the new logic's `repeat` window (0.30 s default)
/// and its lift-off commit.
pub const SETTLE_MS: f64 = 800.0;
/// A move farther than this from the intended point counts as `far`, mm.
pub const FAR_MM: f64 = 3.0;
/// ADC noise of the Monte Carlo's panel, counts (σ).
pub const NOISE_COUNTS: f64 = 1.0;

/// What a cell's taps are.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// A tap of `contact_ms` with a tremor (amplitude 0: a steady finger),
    /// optionally after a landing slide.
    Tap {
        /// Tremor amplitude, mm.
        amp_mm: f64,
        /// Tremor frequency, Hz.
        freq_hz: f64,
        /// Contact duration, ms.
        contact_ms: f64,
        /// A landing slide before the tremor, if any.
        slide: Option<Slide>,
    },
    /// A 0.5 s tap followed by 1–4 bounces (lift gaps 20–300 ms, contacts 20–150 ms).
    Bounce,
    /// A contact of 20 ms to `max_ms`: 140 ms straddles the default `hold`
    /// (0.10 s), 80 ms stays below `hold` − 20 ms (a read's worth), which
    /// must never act.
    Brief {
        /// Longest contact, ms.
        max_ms: f64,
    },
    /// A 1.5 s contact broken by a force tremor of `freq_hz` at 50 % duty.
    ForceTremor {
        /// The tremor's frequency, Hz.
        freq_hz: f64,
    },
    /// A 0.5 s finger and a palm or knuckle 15–30 mm beside it (left or
    /// right, ±5 mm up or down; force 2–5) landing within ±40 ms of each
    /// other; `measured`: after the touch calibration measured the panel's
    /// plate ratio (else the jump alone finds the hand).
    Palm {
        /// The plate ratio measured ([`new_sim`] calibrates on the screen).
        measured: bool,
    },
    /// A single steady 0.5 s finger of force drawn log-uniformly in 0.1–10.
    Force,
    /// A contact that starts on the map and slides off the glass's top edge before lifting.
    OffMap,
    /// STOP pressed for 150 ms, then 1–4 bounces on the same spot.
    StopBounce,
}

/// One row of the table.
#[derive(Debug, Clone, PartialEq)]
pub struct Cell {
    /// The row's name.
    pub name: String,
    /// Its taps.
    pub kind: Kind,
}

impl Cell {
    /// Taps of this cell in a run of `taps` a cell: ten times as many where
    /// issue #19 §6 states its goal over 10⁴ trials (palm + finger with the
    /// ratio measured, single fingers of 0.1–10× force, bounces on STOP).
    pub fn taps(&self, taps: u32) -> u32 {
        match self.kind {
            Kind::Palm { measured: true } | Kind::Force | Kind::StopBounce => taps.saturating_mul(10),
            _ => taps,
        }
    }
}

/// What a cell measured.
#[derive(Debug, Clone, PartialEq)]
pub struct CellStats {
    /// The row's name.
    pub name: String,
    /// Taps run.
    pub taps: u32,
    /// p99 commit error, mm (`None`: no move).
    pub err_p99_mm: Option<f64>,
    /// Share of taps with exactly one move.
    pub once: f64,
    /// Share of taps with no move.
    pub none: f64,
    /// Touch actions per tap.
    pub actions: f64,
    /// Moves in all.
    pub moves: u32,
    /// Moves more than [`FAR_MM`] from the intended point (toward a palm's
    /// midpoint, a slide's landing or a tremor's far turn).
    pub far: u32,
    /// STOP releases (bounce trials that resumed).
    pub releases: u32,
    /// p99 latency of STOP from the contact's start, ms.
    pub stop_p99_ms: Option<f64>,
}

/// The table's rows: the tremor grid A = 0, 1, 2, 3, 5 mm × f = 4, 6, 10 Hz ×
/// contact 0.5 and 1.5 s, then slides, bounces, brief contacts, force
/// tremor, palm + finger, firm and light fingers, off-map ends and bounces on STOP.
pub fn grid() -> Vec<Cell> {
    let mut cells = Vec::new();
    for &contact_ms in &[500.0, 1500.0] {
        for &amp_mm in &[0.0, 1.0, 2.0, 3.0, 5.0] {
            for &freq_hz in &[4.0, 6.0, 10.0] {
                if amp_mm == 0.0 && freq_hz != 6.0 {
                    continue; // no tremor: one row per contact time
                }
                let name = if amp_mm == 0.0 {
                    format!("steady, {:.1} s", contact_ms / 1000.0)
                } else {
                    format!("A {amp_mm} mm, {freq_hz} Hz, {:.1} s", contact_ms / 1000.0)
                };
                cells.push(Cell { name, kind: Kind::Tap { amp_mm, freq_hz, contact_ms, slide: None } });
            }
        }
    }
    for &amp_mm in &[0.0, 2.0] {
        cells.push(Cell {
            name: format!("slide 5 mm in 200 ms, then A {amp_mm} mm 6 Hz, 0.7 s"),
            kind: Kind::Tap { amp_mm, freq_hz: 6.0, contact_ms: 700.0, slide: Some(Slide { len_mm: 5.0, ms: 200.0 }) },
        });
    }
    cells.push(Cell { name: "bounces (1-4, gaps 20-300 ms)".into(), kind: Kind::Bounce });
    cells.push(Cell { name: "brief contacts 20-140 ms".into(), kind: Kind::Brief { max_ms: 140.0 } });
    cells.push(Cell { name: "contacts 20-80 ms (below hold - 20 ms)".into(), kind: Kind::Brief { max_ms: 80.0 } });
    for &freq_hz in &[3.0, 5.0, 8.0] {
        cells.push(Cell {
            name: format!("force tremor {freq_hz} Hz, 50 % duty, 1.5 s"),
            kind: Kind::ForceTremor { freq_hz },
        });
    }
    cells.push(Cell { name: "palm + finger".into(), kind: Kind::Palm { measured: true } });
    cells.push(Cell { name: "palm + finger, plate ratio not measured".into(), kind: Kind::Palm { measured: false } });
    cells.push(Cell { name: "single finger, force 0.1-10".into(), kind: Kind::Force });
    cells.push(Cell { name: "slides off the map before lifting".into(), kind: Kind::OffMap });
    cells.push(Cell { name: "bounces on STOP".into(), kind: Kind::StopBounce });
    cells
}

/// One tap of `kind` as the Monte Carlo draws it from `rng` on the 2.8"
/// glass: its script and the intended point (raw counts; `None` where no
/// target is intended). The simavr cross-check plays the same scripts on
/// the real ELF.
pub fn tap_script(rng: &mut Rng, kind: &Kind) -> (FingerScript, Option<(f64, f64)>) {
    let t = trial(rng, kind, &Glass::QVGA_28, &Calibration::DEFAULT, &Layout::QVGA);
    (t.script, t.intended)
}

/// One tap as planned: its script and where it was meant to land.
struct Trial {
    script: FingerScript,
    /// Intended point, raw counts (fractional); `None`: no target intended.
    intended: Option<(f64, f64)>,
    /// End of the first contact window, ms.
    first_window_ms: f64,
}

fn uniform(rng: &mut Rng, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * rng.uniform()
}

/// A map point in the middle of the map, as a pixel centre.
fn map_target(rng: &mut Rng, lay: &Layout) -> (f64, f64) {
    let (x, y) = (uniform(rng, -0.5, 0.5) as f32, uniform(rng, 0.4, 0.6) as f32);
    let (px, py) = lay.ws_point_to_pixel(x, y).unwrap_or((lay.scale() as i16, (lay.scale() / 2) as i16));
    (f64::from(px), f64::from(py))
}

/// End of a script's first contact (its first knot of force 0 after contact), ms.
fn first_window(s: &FingerScript) -> f64 {
    let k = s.first.knots();
    let on = k.iter().position(|q| q.force > 0.0).unwrap_or(0);
    k[on..].iter().find(|q| q.force == 0.0).map_or(s.first.end_ms(), |q| q.t_ms)
}

fn trial(rng: &mut Rng, kind: &Kind, glass: &Glass, cal: &Calibration, lay: &Layout) -> Trial {
    let centre = map_target(rng, lay);
    let raw = glass.px_to_raw(cal, centre.0, centre.1);
    let on_map = |script: FingerScript| {
        let first_window_ms = first_window(&script);
        Trial { script, intended: Some(raw), first_window_ms }
    };
    match *kind {
        Kind::Tap { amp_mm, freq_hz, contact_ms, slide } => {
            let tremor = (amp_mm > 0.0).then_some(Tremor { amp_mm, freq_hz });
            let plan = TapPlan { tremor, slide, ..TapPlan::steady(centre, contact_ms) };
            on_map(gen::tap(rng, glass, &plan))
        }
        Kind::Bounce => {
            let n = 1 + rng.below(4) as u32;
            let windows = gen::bounce_windows(rng, 500.0, n, (20.0, 150.0));
            on_map(gen::tap(rng, glass, &TapPlan { windows, ..TapPlan::steady(centre, 0.0) }))
        }
        Kind::Brief { max_ms } => {
            let ms = uniform(rng, 20.0, max_ms);
            on_map(gen::tap(rng, glass, &TapPlan::steady(centre, ms)))
        }
        Kind::ForceTremor { freq_hz } => {
            let windows = gen::force_tremor_windows(rng, 1500.0, freq_hz, 0.5);
            on_map(gen::tap(rng, glass, &TapPlan { windows, ..TapPlan::steady(centre, 0.0) }))
        }
        Kind::Palm { .. } => {
            // The hand comes down with the finger: the palm lands within
            // ±40 ms of the finger (at 50 ms) and lifts up to 100 ms after it.
            let palm = Palm {
                offset_mm: (
                    if rng.below(2) == 0 { -1.0 } else { 1.0 } * uniform(rng, 15.0, 30.0),
                    uniform(rng, -5.0, 5.0),
                ),
                force: uniform(rng, 2.0, 5.0),
                window_ms: (uniform(rng, 10.0, 90.0), 550.0 + uniform(rng, 0.0, 100.0)),
            };
            let plan = TapPlan { palm: Some(palm), windows: vec![(50.0, 550.0)], ..TapPlan::steady(centre, 0.0) };
            on_map(gen::tap(rng, glass, &plan))
        }
        Kind::Force => {
            let force = 10f64.powf(uniform(rng, -1.0, 1.0));
            on_map(gen::tap(rng, glass, &TapPlan { force, ..TapPlan::steady(centre, 500.0) }))
        }
        Kind::OffMap => {
            // From the map's upper part straight up off the glass (the plate
            // ends ~40 px above the screen) in 250 ms, lifted 100 ms later.
            let (x, y0) = (centre.0, uniform(rng, 10.0, 40.0));
            let mut k = vec![Knot::new(0.0, x, y0, 1.0), Knot::new(300.0, x, y0, 1.0)];
            k.push(Knot::new(550.0, x, -80.0, 1.0));
            k.push(Knot::new(650.0, x, -80.0, 1.0));
            let t = Track::new(k).unwrap_or_else(|e| unreachable!("{e}"));
            Trial { script: FingerScript { first: t, second: None }, intended: None, first_window_ms: 650.0 }
        }
        Kind::StopBounce => {
            let a = lay.stop();
            let c = (f64::from(a.x) + f64::from(a.w) / 2.0, f64::from(a.y) + f64::from(a.h) / 2.0);
            let n = 1 + rng.below(4) as u32;
            let windows = gen::bounce_windows(rng, 150.0, n, (20.0, 150.0));
            let plan = TapPlan { windows, ..TapPlan::steady(c, 0.0) };
            let script = gen::tap(rng, glass, &plan);
            Trial { first_window_ms: first_window(&script), script, intended: None }
        }
    }
}

/// The twin as the firmware runs it (the screen on and drawn every frame:
/// the screen's hit regions follow what was drawn), homed, its touch
/// calibrated on the screen ([`calibrate_on_screen`]) and back on the main
/// page.
pub fn new_sim(seed: u64) -> Result<Sim, String> {
    let mut sim = new_uncalibrated_sim(seed)?;
    calibrate_on_screen(&mut sim)?;
    sim.serial.output.clear();
    Ok(sim)
}

/// [`new_sim`] without the touch calibration: the default one, and no
/// plate ratio measured.
pub fn new_uncalibrated_sim(seed: u64) -> Result<Sim, String> {
    let setup = SimSetup { params: AppParams { screen: true, ..AppParams::DEFAULT }, seed, ..SimSetup::default() };
    let mut sim = Sim::new(&setup)?;
    sim.panel.noise_counts = NOISE_COUNTS;
    sim.run_ms(3000);
    sim.serial.output.clear();
    Ok(sim)
}

/// A steady firm tap of 300 ms at a screen pixel's centre (2.8" layout,
/// the panel's true response), then 400 ms without contact.
fn tap_pixel(sim: &mut Sim, x: i16, y: i16) -> Result<(), String> {
    let lay = Layout::QVGA;
    let (px, py) = lay.pixel_center_to_panel(x, y);
    let (rx, ry) =
        Calibration::DEFAULT.unmap_exact::<f64>(f64::from(px), f64::from(py)).map_err(|e| format!("{e:?}"))?;
    sim.panel.touch_raw(rx, ry, 1.0)?;
    sim.run_ms(300);
    sim.panel.release();
    sim.run_ms(400);
    Ok(())
}

/// The touch calibration as a carer makes it at set-up, on the 2.8" screen
/// from the main page: More twice to the Setup page, Cal, a tap on each
/// crosshair, Save on the review and on the touch settings' page (the
/// settings as they were), and Back to the main page. Returns the
/// firmware's reply (`info cal touch saved seq <n> plate <ratio> hold …`):
/// the crosshair touches also measure the panel's plate ratio.
pub fn calibrate_on_screen(sim: &mut Sim) -> Result<String, String> {
    use touch_arm::ui::calibration::{cal_pixel, save_area, CAL_COUNT};
    let lay = Layout::QVGA;
    let centre = |a: touch_arm::ui::draw::Area| (a.x + a.w as i16 / 2, a.y + a.h as i16 / 2);
    let (key, cal, save) = (centre(lay.page_key()), centre(lay.calibrate()), centre(save_area(&lay)));
    let mut taps = vec![key, key, cal];
    taps.extend((0..CAL_COUNT).filter_map(|i| cal_pixel(&lay, i)));
    taps.extend([save, save, key]);
    sim.serial.output.clear();
    for (x, y) in taps {
        tap_pixel(sim, x, y)?;
    }
    let lines = sim.serial.lines();
    let saved = lines.iter().find(|l| l.starts_with("info cal touch saved")).cloned();
    match saved {
        Some(l) if sim.app.ui_model().page == touch_arm::ui::Page::Main => Ok(l),
        _ => Err(format!("the screen's touch calibration did not save and return: {lines:?}")),
    }
}

/// Runs `taps` taps of `cell` from `seed`.
pub fn run_cell(cell: &Cell, taps: u32, seed: u64) -> Result<CellStats, String> {
    let glass = Glass::QVGA_28;
    let cal = Calibration::DEFAULT;
    let lay = Layout::QVGA;
    let (mmx, mmy) = glass.mm_per_count(&cal);
    let mut sim =
        if cell.kind == (Kind::Palm { measured: false }) { new_uncalibrated_sim(seed)? } else { new_sim(seed)? };
    let mut rng = Rng::new(seed ^ 0x5EED_F1A6);
    let (mut errs, mut latencies) = (Vec::new(), Vec::new());
    let (mut once, mut none, mut actions, mut moves, mut releases, mut far) = (0u32, 0u32, 0u64, 0u32, 0u32, 0u32);
    let mut pending = String::new();
    for _ in 0..taps {
        let t = trial(&mut rng, &cell.kind, &glass, &cal, &lay);
        let start = sim.time_s();
        let frames = ((t.script.end_ms() + SETTLE_MS) / f64::from(FRAME_MS)).ceil() as u64;
        sim.finger(t.script);
        let mut got: Vec<(f64, TouchAction)> = Vec::new();
        for _ in 0..frames {
            let at = sim.time_s() - start;
            sim.step();
            pending.push_str(&String::from_utf8_lossy(&std::mem::take(&mut sim.serial.output)));
            while let Some(i) = pending.find('\n') {
                let line: String = pending.drain(..=i).collect();
                if let Some(a) = touch_action(line.trim_end()) {
                    got.push((at, a));
                }
            }
        }
        let n_moves = got.iter().filter(|(_, a)| a.action == "move").count() as u32;
        actions += got.len() as u64;
        moves += n_moves;
        once += u32::from(n_moves == 1);
        none += u32::from(n_moves == 0);
        if let Some((ix, iy)) = t.intended {
            for (_, a) in got.iter().filter(|(_, a)| a.action == "move") {
                if let Some((x, y)) = a.raw {
                    let e = ((f64::from(x) - ix) * mmx).hypot((f64::from(y) - iy) * mmy);
                    far += u32::from(e > FAR_MM);
                    errs.push(e);
                }
            }
        }
        if cell.kind == Kind::StopBounce {
            let first_end = t.first_window_ms / 1000.0;
            if let Some((at, _)) = got.iter().find(|(at, a)| a.action == "stop" && *at <= first_end) {
                latencies.push(at * 1000.0 + f64::from(FRAME_MS));
            }
            releases += u32::from(got.iter().any(|(_, a)| a.action == "resume"));
            // Latched at the end (a bounce may have stopped it again): resume
            // over serial for the next trial.
            let last = got.iter().rev().find(|(_, a)| a.action == "stop" || a.action == "resume");
            if last.is_some_and(|(_, a)| a.action == "stop") {
                sim.send_line("resume");
                sim.run_ms(200);
                sim.serial.output.clear();
                pending.clear();
            }
        }
    }
    let taps_f = f64::from(taps.max(1));
    Ok(CellStats {
        name: cell.name.clone(),
        taps,
        err_p99_mm: p99(&mut errs),
        once: f64::from(once) / taps_f,
        none: f64::from(none) / taps_f,
        actions: actions as f64 / taps_f,
        moves,
        far,
        releases,
        stop_p99_ms: p99(&mut latencies),
    })
}

/// The 99th percentile (nearest rank) of `v`.
pub fn p99(v: &mut [f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let rank = ((0.99 * v.len() as f64).ceil() as usize).clamp(1, v.len());
    Some(v[rank - 1])
}

/// The cells' figures as CSV
/// (`taps,err_p99_mm,once,none,actions,moves,far,releases,stop_p99_ms,name`;
/// the name last, as it may hold commas).
pub fn to_csv(rows: &[CellStats]) -> String {
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.3}"));
    let mut s = String::from("taps,err_p99_mm,once,none,actions,moves,far,releases,stop_p99_ms,name\n");
    for r in rows {
        s += &format!(
            "{},{},{:.4},{:.4},{:.3},{},{},{},{},{}\n",
            r.taps,
            opt(r.err_p99_mm),
            r.once,
            r.none,
            r.actions,
            r.moves,
            r.far,
            r.releases,
            opt(r.stop_p99_ms),
            r.name,
        );
    }
    s
}

/// Reads [`to_csv`] back.
pub fn from_csv(text: &str) -> Result<Vec<CellStats>, String> {
    let mut out = Vec::new();
    for (i, line) in text.lines().enumerate().skip(1).filter(|(_, l)| !l.trim().is_empty()) {
        let f: Vec<&str> = line.splitn(10, ',').collect();
        if f.len() != 10 {
            return Err(format!("line {}: {} fields, expected 10", i + 1, f.len()));
        }
        let num = |j: usize| f[j].parse::<f64>().map_err(|_| format!("line {}: field {} {:?}", i + 1, j + 1, f[j]));
        let opt = |j: usize| if f[j].is_empty() { Ok(None) } else { num(j).map(Some) };
        out.push(CellStats {
            name: f[9].to_string(),
            taps: num(0)? as u32,
            err_p99_mm: opt(1)?,
            once: num(2)?,
            none: num(3)?,
            actions: num(4)?,
            moves: num(5)? as u32,
            far: num(6)? as u32,
            releases: num(7)? as u32,
            stop_p99_ms: opt(8)?,
        });
    }
    Ok(out)
}

/// The BENCHMARKS.md section: each cell's figures now, beside the "before"
/// baseline (today's touch logic, measured by the same harness) where given.
pub fn markdown(now: &[CellStats], before: &[CellStats], seed: u64) -> String {
    let opt = |v: Option<f64>, d: usize| v.map_or("–".to_string(), |v| format!("{v:.d$}"));
    let pct = |v: f64| format!("{:.1} %", 100.0 * v);
    let mut s = String::from("## Touch for an unsteady hand (twin Monte Carlo)\n\n");
    s += &format!(
        "Seeded finger scripts (`hal-sim/twin/src/finger.rs`) played tap after tap on the twin's panel into the app \
         with the screen on (320×240, 0.180 mm/px, ADC noise {NOISE_COUNTS} count), what the app did read from its \
         serial lines (`hal-sim/twin/src/touch_mc.rs`, seed {seed}; `cargo run --release -p hal-sim --bin touch-mc`). \
         err p99: 99th percentile of the distance between a move's point and the intended one; once: taps with \
         exactly one move; none: taps with no move; actions: touch actions per tap, `ignored` included (a force tremor's re-contacts inside `repeat`: one move and an `ignored` each); moves: in all; far: moves more \
         than 3 mm from the intended point; releases: bounce trials on STOP that resumed; STOP p99: latency from contact to latch (frame-quantized). \
         Before each cell the twin is calibrated on the screen as a carer does it (five crosshairs, which also \
         measure the panel's plate ratio), except in \"plate ratio not measured\"; the palm, force and STOP-bounce \
         cells run ten times the taps. Two cells (steady and A 2 mm, 6 Hz, 0.5 s) are played with the same scripts \
         on the real ELF in simavr by `hal-sim/rig/tests/finger_firmware.rs`, which holds the ELF's once-rate \
         within 0.25 of the twin's and the steady tap within 0.25 mm.\n\n"
    );
    s += "| cell | taps | err p99 (mm) | once | none | actions/tap | moves | far | releases | STOP p99 (ms) | before: err p99 | before: once | before: actions/tap |\n";
    s += "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    for r in now {
        let b = before.iter().find(|b| b.name == r.name);
        s += &format!(
            "| {} | {} | {} | {} | {} | {:.2} | {} | {} | {} | {} | {} | {} | {} |\n",
            r.name,
            r.taps,
            opt(r.err_p99_mm, 2),
            pct(r.once),
            pct(r.none),
            r.actions,
            r.moves,
            r.far,
            r.releases,
            opt(r.stop_p99_ms, 0),
            b.map_or("–".into(), |b| opt(b.err_p99_mm, 2)),
            b.map_or("–".into(), |b| pct(b.once)),
            b.map_or("–".into(), |b| format!("{:.2}", b.actions)),
        );
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn p99_and_csv_round_trip() {
        let mut v: Vec<f64> = (1..=200).map(f64::from).collect();
        assert_eq!(p99(&mut v), Some(198.0));
        assert_eq!(p99(&mut [3.0]), Some(3.0));
        assert_eq!(p99(&mut []), None);
        let rows = vec![CellStats {
            name: "A 2 mm, 6 Hz, 0.5 s".into(),
            taps: 10,
            err_p99_mm: Some(1.5),
            once: 0.5,
            none: 0.5,
            actions: 0.5,
            moves: 5,
            far: 1,
            releases: 0,
            stop_p99_ms: None,
        }];
        assert_eq!(from_csv(&to_csv(&rows)).unwrap(), rows);
        assert!(from_csv("h\n1,2\n").unwrap_err().contains("2 fields, expected 10"));
        assert_eq!(grid().len(), 26 + 13);
    }
}
