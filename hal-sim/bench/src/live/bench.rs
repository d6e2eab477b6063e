//! The simulated bench: the real firmware ELF in simavr (a [`Session`]: the
//! panel model on the ADC, the LCD bus decoder, the servo pins watched),
//! paced to the wall clock, driven by the HTTP threads' [`Command`]s and
//! publishing what it sees: a [`Snapshot`] for the API's GETs and server-sent
//! events for the pages.
//!
//! A `Session` is not `Send` (simavr's callbacks hold raw pointers into it),
//! so the whole bench lives on one thread and everything else talks to it
//! through a channel.

use std::collections::VecDeque;
use std::path::PathBuf;
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender, SyncSender, TryRecvError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use embedded_graphics::pixelcolor::{Rgb565, RgbColor};
use serde_json::{json, Value};
use touch_arm::servo::map::ServoMap;
use touch_arm::touch::map::Calibration;
use touch_arm::ui::layout::Layout;

use super::api::{Control, Press, MAX_CONSOLE_LINES};
use super::arm::{self, Target};
use super::pacing::Pacer;
use super::pulses::PulsePairing;
use super::screen::ScreenTracker;
use super::serial::SerialRouter;
use hal_sim::display::Framebuffer;
use hal_sim::finger::Glass;
use touch_arm_rig::firmware::{self, Session, CPU_HZ};
use touch_arm_rig::lcd_bus::Chip;
use touch_arm_rig::panel::PanelWiring;

mod faults;
mod publish;

/// How often the bench publishes (state, screen patches, console lines).
pub const TICK: Duration = Duration::from_millis(40);
/// Longest stretch simulated between two looks at the command channel.
const SLICE_CYCLES: u64 = CPU_HZ as u64 / 100;
/// Console lines kept for a page that connects.
const CONSOLE_BACKLOG: usize = 400;
/// Firmware lines kept for `GET /api/console` (about 40 minutes of
/// telemetry at 50 lines/s; older ones are gone, and the answer's first
/// line number says so).
const FIRMWARE_LOG: usize = 120_000;
/// A held press (`/api/press`) ends by itself after this long, so a page
/// that vanished mid-drag does not leave a finger on the panel; a closed
/// switch (`/api/switch`) opens after it too.
const MAX_HOLD_S: f64 = 30.0;
/// Events queued per page before the page counts as gone.
pub const EVENT_QUEUE: usize = 256;
/// A stall that has not tripped the watchdog after this long is called off.
const STALL_GIVE_UP_S: f64 = 2.0;

/// What the HTTP threads ask of the bench. Each carries where the answer goes.
pub enum Command {
    Press(Press, Sender<Result<Value, String>>),
    /// A finger script (`/api/finger`), starting now.
    Finger(Box<hal_sim::finger::FingerScript>, Sender<Result<Value, String>>),
    Release(Sender<Result<Value, String>>),
    /// The assistive switch closed (`true`) or open (`/api/switch`).
    Switch(bool, Sender<Result<Value, String>>),
    Serial(String, Sender<Vec<String>>),
    Control(Control, Sender<Result<Value, String>>),
    /// `GET /api/console?since=N`: the firmware's lines from number N on.
    Console(u64, Sender<Value>),
    /// A page's event stream: the bench sends it the current picture,
    /// recent history and then every event.
    Subscribe(SyncSender<Arc<str>>),
    Stop,
}

/// What the GET endpoints read, refreshed every tick.
#[derive(Clone)]
pub struct Snapshot {
    pub state: String,
    pub t_s: f64,
    pub pulses_us: [Option<f64>; 3],
    pub angles_deg: [Option<f64>; 3],
    pub grip_pulse_us: Option<f64>,
    pub grip_deg: Option<f64>,
    pub screen_seq: u64,
    pub screen: Arc<Framebuffer>,
    /// Pacing and faults (`GET /api/bench`).
    pub bench: Value,
    /// When this snapshot was taken (pairs `t_s` with the wall clock).
    pub taken: Instant,
}

impl Snapshot {
    /// `GET /api/state`, exactly the documented keys.
    pub fn state_json(&self) -> Value {
        json!({
            "state": self.state,
            "t_s": self.t_s,
            "pulses_us": self.pulses_us,
            "angles_deg": self.angles_deg,
            "grip_pulse_us": self.grip_pulse_us,
            "grip_deg": self.grip_deg,
            "screen_seq": self.screen_seq,
        })
    }
}

pub struct Options {
    pub elf: PathBuf,
    /// Seed of the panel model's noise (varied per power-up).
    pub seed: u64,
    pub lcd: Chip,
    pub wiring: PanelWiring,
}

/// The current press on the panel.
#[derive(Debug, Clone, Copy)]
struct Finger {
    px: (i16, i16),
    /// Bench cycle at which it lifts.
    until: u64,
}

struct Bench {
    opts: Options,
    /// The simulated screen's layout (`opts.lcd`'s).
    layout: Layout,
    /// The touch calibration the firmware runs with on `opts.wiring`
    /// (`shield::touch_calibration`; the bench sets it at every boot).
    cal: Calibration,
    session: Session,
    /// Bench cycles before the current power-up (bench time never restarts).
    cycle_base: u64,
    power_ups: u32,
    resets_seen: u32,
    maps: [ServoMap; 3],
    /// The gripper's default calibration (`config::grip::GRIP_DEFAULT`),
    /// as `maps` are the joints' defaults.
    grip_map: ServoMap,
    /// The gripper's last pulse, µs (D11, Timer1).
    last_grip: Option<f64>,
    pairing: PulsePairing,
    last_pulses: [Option<f64>; 3],
    new_samples: Vec<Value>,
    recent: VecDeque<(f64, Value)>,
    router: SerialRouter,
    console_new: Vec<Value>,
    console_log: VecDeque<Value>,
    /// Every line the firmware sent, numbered from 0 at the bench's start
    /// (power cycles and resets included), the last [`FIRMWARE_LOG`] kept.
    fw_log: VecDeque<String>,
    /// The number of `fw_log`'s first line.
    fw_first: u64,
    screen: ScreenTracker,
    subscribers: Vec<SyncSender<Arc<str>>>,
    noise: bool,
    /// Lines the bench still has to send after a boot: on wiring c the
    /// calibration its calibration screen would find, as the main job sets
    /// it (`shield::calibration_lines`), one at a time once the firmware
    /// holds (it refuses settings while homing) and nothing else is in flight.
    setup: VecDeque<String>,
    /// Bench time at which the frame loop was stalled, until the watchdog fires.
    stalled_at: Option<f64>,
    halted: Option<String>,
    finger: Option<Finger>,
    /// While the assistive switch is closed: the bench cycle at which it
    /// opens by itself ([`MAX_HOLD_S`]).
    switch_until: Option<u64>,
    target: Option<Target>,
    state: String,
    pacer: Pacer,
    watchdog_resets: u32,
    /// `reset` controls so far.
    external_resets: u32,
    /// What the GET endpoints read.
    shared: Arc<Mutex<Snapshot>>,
}

/// Runs the bench on the calling thread until [`Command::Stop`] or until
/// every sender is gone. `ready` hears whether the firmware loaded.
pub fn run(
    opts: Options,
    commands: Receiver<Command>,
    shared: Arc<Mutex<Snapshot>>,
    ready: Sender<Result<(), String>>,
) {
    let mut bench = match Bench::new(opts, shared) {
        Ok(b) => {
            let _ = ready.send(Ok(()));
            b
        }
        Err(e) => {
            let _ = ready.send(Err(e));
            return;
        }
    };
    let mut next_tick = Instant::now();
    loop {
        loop {
            match commands.try_recv() {
                Ok(Command::Stop) | Err(TryRecvError::Disconnected) => return,
                Ok(c) => bench.handle(c),
                Err(TryRecvError::Empty) => break,
            }
        }
        let now = Instant::now();
        if bench.halted.is_some() {
            // Nothing runs; pacing starts afresh after the power cycle.
            bench.pacer.restart(now, bench.cycles());
        } else if bench.cycles() < bench.pacer.due(now) {
            bench.advance(bench.pacer.due(now));
            bench.pacer.settle(Instant::now(), bench.cycles());
        }
        if Instant::now() >= next_tick {
            bench.tick();
            next_tick = schedule(next_tick);
        }
        let caught_up = bench.halted.is_some() || bench.cycles() >= bench.pacer.due(Instant::now());
        if caught_up {
            // Wait for a command, the next tick or ~2 ms of wall time (the
            // slice the simulation then runs).
            let wait = next_tick.saturating_duration_since(Instant::now()).min(Duration::from_millis(2));
            match commands.recv_timeout(wait) {
                Ok(Command::Stop) | Err(RecvTimeoutError::Disconnected) => return,
                Ok(c) => bench.handle(c),
                Err(RecvTimeoutError::Timeout) => {}
            }
        }
    }
}

/// The tick after `prev`, never in the past (no burst of ticks after a stall).
fn schedule(prev: Instant) -> Instant {
    let next = prev + TICK;
    let now = Instant::now();
    if next < now {
        now + TICK
    } else {
        next
    }
}

impl Bench {
    fn new(opts: Options, shared: Arc<Mutex<Snapshot>>) -> Result<Bench, String> {
        let mut session = Session::start_with_lcd(&opts.elf, opts.wiring, opts.lcd, opts.seed)?;
        session.set_glass(glass_of(opts.lcd));
        let (layout, cal) = (opts.lcd.layout(), crate::shield::touch_calibration(opts.wiring));
        let opts_wiring = opts.wiring;
        let maps = firmware::default_servo_maps()?;
        let grip_map =
            ServoMap::new(&touch_arm::config::grip::GRIP_DEFAULT).map_err(|e| format!("gripper map: {e:?}"))?;
        let pacer = Pacer::new(Instant::now(), 0, f64::from(CPU_HZ));
        let mut b = Bench {
            opts,
            layout,
            cal,
            session,
            cycle_base: 0,
            power_ups: 1,
            resets_seen: 0,
            maps,
            grip_map,
            last_grip: None,
            pairing: PulsePairing::default(),
            last_pulses: [None; 3],
            new_samples: Vec::new(),
            recent: VecDeque::new(),
            router: SerialRouter::default(),
            console_new: Vec::new(),
            console_log: VecDeque::new(),
            fw_log: VecDeque::new(),
            fw_first: 0,
            screen: ScreenTracker::new(u32::from(layout.width()), u32::from(layout.height())),
            subscribers: Vec::new(),
            noise: false,
            setup: crate::shield::calibration_lines(opts_wiring).into(),
            stalled_at: None,
            halted: None,
            finger: None,
            switch_until: None,
            target: None,
            state: "booting".into(),
            pacer,
            watchdog_resets: 0,
            external_resets: 0,
            shared,
        };
        let name = b
            .opts
            .elf
            .file_name()
            .map_or_else(|| b.opts.elf.display().to_string(), |n| n.to_string_lossy().into_owned());
        b.note(format!("power-up: {name} in simavr, paced to real time"));
        Ok(b)
    }

    /// Bench cycles since the bench started.
    fn cycles(&self) -> u64 {
        self.cycle_base + self.session.avr.cycles()
    }

    fn now_s(&self) -> f64 {
        self.cycles() as f64 / f64::from(CPU_HZ)
    }

    fn s_to_cycles(s: f64) -> u64 {
        (s * f64::from(CPU_HZ)).round() as u64
    }

    /// Simulates up to bench cycle `due` (one slice at most), stopping early
    /// where a timed press lifts, then reads what the firmware said.
    fn advance(&mut self, due: u64) {
        let now = self.cycles();
        let mut end = due.min(now + SLICE_CYCLES);
        if let Some(f) = self.finger {
            end = end.min(f.until.max(now + 1));
        }
        if let Some(until) = self.switch_until {
            end = end.min(until.max(now + 1));
            // Driven again every slice: simavr puts an input's pull-up back
            // on its pin whenever the firmware writes the port's PORT or DDR
            // (at every boot, after a reset or power cycle, which a switch
            // held shut outlasts).
            if let Err(e) = self.session.set_switch(true) {
                self.note(e);
            }
        }
        if let Err(e) = self.session.avr.run_cycles(end - now) {
            self.halted = Some(e.to_string());
            self.state = "halted".into();
            self.note(format!("the firmware stopped: {e}; power-cycle to restart it"));
        }
        if self.finger.is_some_and(|f| self.cycles() >= f.until) {
            self.session.release();
            self.finger = None;
        }
        if self.switch_until.is_some_and(|u| self.cycles() >= u) {
            // The page that held it is gone, or a script forgot to open it.
            if let Err(e) = self.switch(false) {
                self.note(e);
            }
        }
        self.read_serial();
        let resets = self.session.avr.resets();
        if resets != self.resets_seen {
            self.resets_seen = resets;
            self.watchdog_resets += 1;
            self.after_restart("the watchdog reset the chip");
        }
        let t = self.now_s();
        if self.stalled_at.is_some_and(|s| t - s > STALL_GIVE_UP_S) {
            self.stalled_at = None;
            self.note("the stall did not trip the watchdog (the firmware had not armed it yet)".into());
        }
        self.router.expire(t);
        let line_free = self.session.avr.uart_rx_pending() == 0;
        if self.stalled_at.is_none() && self.halted.is_none() {
            if self.state == "holding" && line_free && self.router.idle() {
                if let Some(cmd) = self.setup.pop_front() {
                    let bytes = self.router.bench_line(&cmd, t);
                    self.session.avr.uart_send(&bytes);
                }
            }
            if let Some(bytes) = self.router.poll_status(t, line_free) {
                self.session.avr.uart_send(&bytes);
            }
        }
    }

    fn read_serial(&mut self) {
        let lines = self.session.avr.take_lines();
        self.session.avr.forget_taken_output();
        for line in lines {
            self.fw_log.push_back(line.clone());
            if self.fw_log.len() > FIRMWARE_LOG {
                self.fw_log.pop_front();
                self.fw_first += 1;
            }
            match arm::target_news(&self.cal, &self.layout, &line) {
                Some(arm::TargetNews::Touched(t)) => self.target = Some(t),
                Some(arm::TargetNews::Cleared) => self.target = None,
                None => {}
            }
            let r = self.router.on_line(&line);
            if let Some(s) = r.state {
                if self.stalled_at.is_none() {
                    self.state = s;
                }
            }
            if r.console {
                self.console("rx", line);
            }
        }
    }

    /// The firmware starts over (power-up or watchdog): nothing it was asked
    /// will be answered, and its state is unknown until it says.
    fn after_restart(&mut self, why: &str) {
        let t = self.now_s();
        self.router.reset(t);
        self.pairing.clear();
        self.stalled_at = None;
        self.target = None;
        self.state = "booting".into();
        self.setup = crate::shield::calibration_lines(self.opts.wiring).into();
        self.note(why.into());
    }

    fn console(&mut self, dir: &str, text: String) {
        let v = json!({ "d": dir, "t": round3(self.now_s()), "s": text });
        self.console_log.push_back(v.clone());
        while self.console_log.len() > CONSOLE_BACKLOG {
            self.console_log.pop_front();
        }
        self.console_new.push(v);
    }

    /// A line from the bench itself on the console.
    fn note(&mut self, text: String) {
        self.console("bench", text);
    }

    fn handle(&mut self, c: Command) {
        match c {
            Command::Press(p, done) => {
                let _ = done.send(self.press(p));
            }
            Command::Finger(f, done) => {
                self.session.finger(*f);
                self.finger = None;
                let _ = done.send(Ok(json!({ "t_s": self.now_s() })));
            }
            Command::Release(done) => {
                self.session.release();
                self.finger = None;
                let _ = done.send(Ok(json!({ "released": true })));
            }
            Command::Switch(down, done) => {
                let r = self.switch(down);
                // A script that reads /api/bench next sees the switch as set.
                self.publish(false);
                let _ = done.send(r);
            }
            Command::Serial(line, reply) => {
                self.console("tx", line.clone());
                let bytes = self.router.client_line(&line, reply, self.now_s());
                self.session.avr.uart_send(&bytes);
            }
            Command::Control(c, done) => {
                let r = self.control(c);
                // A script that reads /api/state or /api/bench next sees the effect.
                self.publish(false);
                let _ = done.send(r);
            }
            Command::Subscribe(tx) => self.subscribe(tx),
            Command::Console(since, reply) => {
                let _ = reply.send(self.console_since(since));
            }
            Command::Stop => {}
        }
    }

    /// `{"lines", "next"}`: the firmware's lines from number `since` on (from
    /// the oldest kept when `since` is older; none when it is past the last),
    /// at most [`MAX_CONSOLE_LINES`]; `next` is the number to ask for next.
    /// `first`, the oldest line number kept, tells a reader who fell behind
    /// by how many lines.
    fn console_since(&self, since: u64) -> Value {
        let end = self.fw_first + self.fw_log.len() as u64;
        let from = since.clamp(self.fw_first, end);
        let lines: Vec<&String> =
            self.fw_log.iter().skip((from - self.fw_first) as usize).take(MAX_CONSOLE_LINES).collect();
        json!({ "lines": lines, "next": from + lines.len() as u64, "first": self.fw_first })
    }

    /// Closes or opens the assistive switch (PA0 low or high) at once; a
    /// change shows on the console.
    fn switch(&mut self, down: bool) -> Result<Value, String> {
        self.session.set_switch(down)?;
        let was = self.switch_until.is_some();
        self.switch_until = down.then(|| self.cycles() + Self::s_to_cycles(MAX_HOLD_S));
        if was != down {
            self.note(if down { "switch closed (PA0 low)".into() } else { "switch open (PA0 high)".into() });
        }
        Ok(json!({ "down": down, "t_s": self.now_s() }))
    }

    /// The finger at the centre of screen pixel (x, y), through the panel's
    /// true response, so the firmware's own driver reads it through the ADC,
    /// noise included: a timed press (`/api/touch`) is a steady finger
    /// script of that duration; a held one (`/api/press`) stays until released.
    fn press(&mut self, p: Press) -> Result<Value, String> {
        match p.ms {
            Some(ms) => {
                self.session.finger(hal_sim::finger::FingerScript::steady(
                    f64::from(p.x_px),
                    f64::from(p.y_px),
                    ms as f64,
                ));
                self.finger = None;
            }
            None => {
                let (panel_x, panel_y) = self.layout.pixel_center_to_panel(p.x_px, p.y_px);
                self.session.press_xy(f64::from(panel_x), f64::from(panel_y))?;
                let until = self.cycles() + Self::s_to_cycles(MAX_HOLD_S);
                self.finger = Some(Finger { px: (p.x_px, p.y_px), until });
            }
        }
        // What this pixel would target; the drawn target changes only when
        // the firmware reports the touch it confirmed.
        let target = arm::target_at_pixel(&self.layout, p.x_px, p.y_px);
        Ok(json!({
            "x_px": p.x_px,
            "y_px": p.y_px,
            "ms": p.ms,
            "t_s": self.now_s(),
            "target": target.as_ref().map(Target::to_json),
        }))
    }
}

/// The glass finger scripts' pixels lie on: the controller's screen.
fn glass_of(lcd: Chip) -> Glass {
    let (w, h) = lcd.landscape_size();
    Glass::for_size(w, h).unwrap_or(Glass::QVGA_28)
}

/// An initial snapshot for the HTTP side before the first tick.
pub fn empty_snapshot(lay: &Layout) -> Snapshot {
    Snapshot {
        state: "booting".into(),
        t_s: 0.0,
        pulses_us: [None; 3],
        angles_deg: [None; 3],
        grip_pulse_us: None,
        grip_deg: None,
        screen_seq: 0,
        screen: Arc::new(Framebuffer::new(u32::from(lay.width()), u32::from(lay.height()), Rgb565::BLACK)),
        bench: json!({}),
        taken: Instant::now(),
    }
}

fn round3(v: f64) -> f64 {
    (v * 1000.0).round() / 1000.0
}
