//! `touch-arm-live --pacing-report SECONDS`: how well the bench keeps real
//! time, measured on this machine, idle and while the arm moves, as the
//! Markdown section `scripts/bench.sh` puts into BENCHMARKS.md.

use std::fmt::Write;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{channel, sync_channel};
use std::sync::Arc;
use std::time::{Duration, Instant};

use super::api::Press;
use super::bench::{Command, Snapshot, EVENT_QUEUE};
use super::{start, LiveBench, Options};

/// The moving phase's touches: far apart on the map, so every touch re-plans
/// a long move and the arm is in motion nearly all the time.
const TOUCH_POINTS: [(f32, f32); 2] = [(0.75, 0.3), (-0.75, 0.3)];
const TOUCH_EVERY: Duration = Duration::from_millis(2500);
const TOUCH_MS: u64 = 300;
const SAMPLE_EVERY: Duration = Duration::from_millis(100);

struct Phase {
    name: String,
    wall_s: f64,
    sim_s: f64,
    worst_lag_ms: f64,
    slipped_s: f64,
    cpu: f64,
    moving: f64,
    /// Event-stream bytes a page received per second.
    event_rate: f64,
    load: String,
}

/// User + system CPU seconds of this process.
fn cpu_seconds() -> f64 {
    // SAFETY: getrusage fills the zeroed struct it is given.
    let mut u: libc::rusage = unsafe { std::mem::zeroed() };
    unsafe { libc::getrusage(libc::RUSAGE_SELF, &mut u) };
    let tv = |t: libc::timeval| t.tv_sec as f64 + t.tv_usec as f64 / 1e6;
    tv(u.ru_utime) + tv(u.ru_stime)
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|l| l.split_whitespace().next().map(str::to_string))
        .unwrap_or_else(|| "?".into())
}

impl LiveBench {
    fn snapshot(&self) -> Snapshot {
        self.snapshot.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }

    fn touch_map(&self, x: f32, y: f32) -> Result<(), String> {
        let (px, py) = self.layout.ws_point_to_pixel(x, y).ok_or("point off the map")?;
        let (tx, rx) = channel();
        self.bench_tx
            .send(Command::Press(Press { x_px: px, y_px: py, ms: Some(TOUCH_MS) }, tx))
            .map_err(|_| "the bench stopped")?;
        rx.recv().map_err(|_| "the bench stopped")?.map(|_| ())
    }

    /// A page's share of the work: an event stream whose every event is
    /// taken (and counted) as a browser would, without the browser.
    fn subscribe_counter(&self) -> Result<Arc<AtomicU64>, String> {
        let (tx, rx) = sync_channel::<Arc<str>>(EVENT_QUEUE);
        self.bench_tx.send(Command::Subscribe(tx)).map_err(|_| "the bench stopped")?;
        let bytes = Arc::new(AtomicU64::new(0));
        let count = bytes.clone();
        std::thread::spawn(move || {
            for e in rx {
                count.fetch_add(e.len() as u64, Ordering::Relaxed);
            }
        });
        Ok(bytes)
    }

    fn measure(&self, name: &str, seconds: f64, touches: bool, events: &AtomicU64) -> Result<Phase, String> {
        let first = self.snapshot();
        let bytes0 = events.load(Ordering::Relaxed);
        let cpu0 = cpu_seconds();
        let slipped0 = first.bench["slipped_s"].as_f64().unwrap_or(0.0);
        let end = first.taken + Duration::from_secs_f64(seconds);
        let (mut worst_lag, mut samples, mut moving) = (0.0f64, 0u32, 0u32);
        let mut next_touch = Instant::now();
        let mut which = 0;
        while Instant::now() < end {
            if touches && Instant::now() >= next_touch {
                let (x, y) = TOUCH_POINTS[which % TOUCH_POINTS.len()];
                self.touch_map(x, y)?;
                which += 1;
                next_touch += TOUCH_EVERY;
            }
            std::thread::sleep(SAMPLE_EVERY);
            let s = self.snapshot();
            worst_lag = worst_lag.max(s.bench["lag_ms"].as_f64().unwrap_or(0.0));
            samples += 1;
            moving += u32::from(s.state == "moving");
            if !self.is_running() {
                return Err("the simulator thread stopped".into());
            }
        }
        let last = self.snapshot();
        let wall_s = last.taken.duration_since(first.taken).as_secs_f64();
        Ok(Phase {
            name: name.into(),
            wall_s,
            sim_s: last.t_s - first.t_s,
            worst_lag_ms: worst_lag,
            slipped_s: last.bench["slipped_s"].as_f64().unwrap_or(0.0) - slipped0,
            cpu: (cpu_seconds() - cpu0) / wall_s,
            moving: f64::from(moving) / f64::from(samples.max(1)),
            event_rate: (events.load(Ordering::Relaxed) - bytes0) as f64 / wall_s,
            load: load_average(),
        })
    }
}

/// Runs the bench for `seconds` idle and `seconds` moving and describes it.
pub fn pacing_report(opts: &Options, seconds: f64) -> Result<String, String> {
    let bench = start(&Options { port: 0, ..opts.clone() })?;
    // Boot, configuration, homing and the 1 s settle before touches count.
    let events = bench.subscribe_counter()?;
    std::thread::sleep(Duration::from_secs(3));
    let idle = bench.measure("idle (holding the home pose)", seconds, false, &events)?;
    let moving = bench.measure("moving (a far touch every 2.5 s)", seconds, true, &events)?;
    bench.stop();
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    let mut o = String::new();
    let _ = writeln!(o, "## Live bench pacing\n");
    let _ = writeln!(
        o,
        "Measured by `touch-arm-live --pacing-report {seconds}` (the live bench of `scripts/run.sh --live`: the"
    );
    let _ = writeln!(o, "product firmware in simavr, paced to the wall clock, with one page's event stream taken in");
    let _ = writeln!(
        o,
        "process instead of by a browser) on a {cores}-core machine shared with other work (load average at"
    );
    let _ =
        writeln!(o, "the end of each phase in the last column). The target: simulated time within ±2 % of wall time");
    let _ =
        writeln!(o, "over a minute. Lag is how far simulated time trailed the wall clock at a 0.1 s sample; dropped");
    let _ = writeln!(o, "is backlog given up (beyond 0.5 s the bench drops it rather than rush).\n");
    let _ = writeln!(o, "| phase | wall s | simulated s | simulated / wall | worst lag ms | dropped s | arm moving | events KB/s | CPU (one core) | load |");
    let _ = writeln!(o, "| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |");
    for p in [&idle, &moving] {
        let _ = writeln!(
            o,
            "| {} | {:.2} | {:.2} | {:.4} | {:.1} | {:.2} | {:.0} % | {:.1} | {:.0} % | {} |",
            p.name,
            p.wall_s,
            p.sim_s,
            p.sim_s / p.wall_s,
            p.worst_lag_ms,
            p.slipped_s,
            p.moving * 100.0,
            p.event_rate / 1000.0,
            p.cpu * 100.0,
            p.load
        );
    }
    Ok(o)
}
