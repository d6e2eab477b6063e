//! The virtual bench (issue #15): the real firmware ELF running in simavr,
//! paced to the wall clock, served to a browser on the loopback address.
//!
//! - `bench`: the simulator thread (firmware session, pacing, faults, what it
//!   publishes); `pacing`, `pulses`, `screen`, `serial` and `arm` are its parts.
//! - `http` and `api`: the HTTP server, the JSON API and the event stream.
//! - `assets/`: the page (HTML, JS, CSS), compiled into the binary.
//!
//! The API (JSON in and out; a refusal is a 4xx with `{"error": "<reason>"}`):
//!
//! | request | answer |
//! | --- | --- |
//! | `GET /api/state` | `{"state", "t_s", "pulses_us": [b, s, e], "angles_deg": [b, s, e], "grip_pulse_us", "grip_deg", "screen_seq"}` |
//! | `POST /api/touch` `{"x_px", "y_px", "ms"}` | a steady finger of `ms` ms at screen pixel (x, y) |
//! | `POST /api/finger` `{"samples": [[t_ms, x_px, y_px, force], ...], "second"?: [...]}` | a finger script starting now (≤ 10 000 samples, ≤ 60 s): `{"t_s"}` |
//! | `POST /api/serial` `{"line"}` | `{"replies": [...]}`: the firmware's answer lines within 1 s (30 s for a command that plans a move: its check may take seconds) |
//! | `GET /api/console?since=N` | `{"lines": [...], "next": M, "first": F}`: every line the firmware sent from line N on (at most 5 000; `first` is the oldest kept) |
//! | `GET /api/screen.png` | the screen as the firmware drew it |
//! | `POST /api/press` `{"x_px", "y_px"}` / `POST /api/release` | the page's press-and-drag |
//! | `POST /api/switch` `{"down": true \| false}` | the assistive switch on D22 = PA0 closed (driven low) or open: `{"down", "t_s"}` |
//! | `POST /api/control` `{"action", "addr"?}` | `power_cycle`, `reset` (the RESET pin: RAM kept), `corrupt_eeprom`, `noise_on`, `noise_off`, `stall` |
//! | `GET /api/bench` | pacing figures and fault switches |
//! | `GET /api/geometry` | arm links, map layout and reachable map pixels |
//! | `GET /api/layout` | every hit region of every page (pixels) and the panel's mm per pixel |
//! | `GET /api/events` | server-sent events: `screen`, `history`, `serial`, `state` |

mod api;
mod arm;
mod bench;
mod http;
mod pacing;
mod pulses;
mod report;
mod screen;
mod serial;

use std::net::{Ipv4Addr, SocketAddr};
use std::path::PathBuf;
use std::sync::mpsc::{channel, Sender};
use std::sync::{Arc, Mutex};
use std::thread::JoinHandle;

use touch_arm::ui::layout::Layout;
use touch_arm_rig::lcd_bus::Chip;
use touch_arm_rig::panel::PanelWiring;

pub use report::pacing_report;

/// The screen of the default shield (its ILI9341, 320×240 in landscape),
/// laid out as the firmware lays it out; `--lcd` picks another
/// ([`Options::layout`]).
pub const LAYOUT: touch_arm::ui::layout::Layout = touch_arm::ui::layout::Layout::QVGA;

/// How to start a bench.
#[derive(Debug, Clone)]
pub struct Options {
    /// Port on 127.0.0.1; 0 picks a free one.
    pub port: u16,
    /// The firmware ELF the bench runs.
    pub elf: PathBuf,
    /// Seed of the panel model's noise.
    pub seed: u64,
    /// The display controller simulated around the ELF (`--lcd`).
    pub lcd: Chip,
    /// The touch panel's wiring on the simulated shield (`--wiring`).
    pub wiring: PanelWiring,
}

impl Options {
    /// The default shield's bench on `port`: ILI9341, wiring a.
    pub fn new(port: u16, elf: PathBuf, seed: u64) -> Options {
        Options { port, elf, seed, lcd: Chip::Ili9341, wiring: PanelWiring::A }
    }

    /// The firmware's layout of the simulated screen.
    pub fn layout(&self) -> Layout {
        self.lcd.layout()
    }
}

/// A running bench: the simulator thread and the HTTP server. Dropping it
/// stops both.
pub struct LiveBench {
    addr: SocketAddr,
    /// The simulated screen's layout.
    layout: Layout,
    server: Arc<tiny_http::Server>,
    bench_tx: Sender<bench::Command>,
    snapshot: Arc<Mutex<bench::Snapshot>>,
    sim: Option<JoinHandle<()>>,
    http: Option<JoinHandle<()>>,
}

/// Loads the firmware, starts it and serves the page on 127.0.0.1 (never
/// another address). Returns once the server listens.
pub fn start(opts: &Options) -> Result<LiveBench, String> {
    let snapshot = Arc::new(Mutex::new(bench::empty_snapshot(&opts.layout())));
    let (bench_tx, bench_rx) = channel();
    let (ready_tx, ready_rx) = channel();
    let bench_opts = bench::Options { elf: opts.elf.clone(), seed: opts.seed, lcd: opts.lcd, wiring: opts.wiring };
    let shared = snapshot.clone();
    let sim = std::thread::Builder::new()
        .name("live-sim".into())
        .spawn(move || bench::run(bench_opts, bench_rx, shared, ready_tx))
        .map_err(|e| format!("starting the simulator thread: {e}"))?;
    match ready_rx.recv() {
        Ok(Ok(())) => {}
        Ok(Err(e)) => return Err(e),
        Err(_) => return Err("the simulator thread ended while loading the firmware".into()),
    }
    let server = tiny_http::Server::http((Ipv4Addr::LOCALHOST, opts.port))
        .map_err(|e| format!("listening on 127.0.0.1:{}: {e}", opts.port))?;
    let addr = server.server_addr().to_ip().ok_or("the server has no IP address")?;
    let server = Arc::new(server);
    let lay = opts.layout();
    let mut geometry = arm::geometry_json(&lay);
    geometry["lcd"] = opts.lcd.name().into();
    geometry["wiring"] = crate::shield::wiring_name(opts.wiring).into();
    let geometry = geometry.to_string();
    let ctx = Arc::new(http::Context::new(bench_tx.clone(), snapshot.clone(), geometry, lay, addr.port()));
    let srv = server.clone();
    let http = std::thread::Builder::new()
        .name("live-http".into())
        .spawn(move || http::serve(srv, ctx))
        .map_err(|e| format!("starting the server thread: {e}"))?;
    Ok(LiveBench { addr, layout: lay, server, bench_tx, snapshot, sim: Some(sim), http: Some(http) })
}

impl LiveBench {
    /// The address the page is served at (the port picked when `Options::port` was 0).
    pub fn addr(&self) -> SocketAddr {
        self.addr
    }

    /// `http://127.0.0.1:<port>/`
    pub fn url(&self) -> String {
        format!("http://{}/", self.addr)
    }

    /// Whether the simulator thread still runs.
    pub fn is_running(&self) -> bool {
        self.sim.as_ref().is_some_and(|h| !h.is_finished())
    }

    /// Stops the simulator and the server and waits for both. Open event
    /// streams end when their queues close.
    pub fn stop(mut self) {
        self.shutdown();
    }

    fn shutdown(&mut self) {
        let _ = self.bench_tx.send(bench::Command::Stop);
        self.server.unblock();
        for h in [self.sim.take(), self.http.take()].into_iter().flatten() {
            let _ = h.join();
        }
    }
}

impl Drop for LiveBench {
    fn drop(&mut self) {
        self.shutdown();
    }
}
