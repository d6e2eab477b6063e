//! The live bench: the real firmware in simavr, paced to real time, with a
//! page at http://127.0.0.1:PORT/ to touch its screen, watch the arm and
//! talk to its serial port (`scripts/run.sh --live`). Ctrl-C stops it.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use touch_arm_bench::live::{self, Options};
use touch_arm_rig::firmware;

const USAGE: &str = "usage: touch-arm-live [--port P] [--elf FILE] [--seed N] [--lcd CONTROLLER] [--wiring a|b|c]
       touch-arm-live --pacing-report SECONDS [--elf FILE] [--out FILE]
Runs the firmware ELF in simavr paced to real time and serves the bench page
on http://127.0.0.1:P/ (default port 8080; 0 picks a free one). Ctrl-C stops.
--lcd and --wiring choose the simulated shield as for scripts/run.sh (default
ili9341, a).
--pacing-report measures the pacing for SECONDS idle and SECONDS moving and
prints (or writes to FILE) a Markdown section.";

static STOP: AtomicBool = AtomicBool::new(false);

extern "C" fn on_signal(_: libc::c_int) {
    // Only an atomic store: safe in a signal handler.
    STOP.store(true, Ordering::SeqCst);
}

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("touch-arm-live: {e}");
            ExitCode::FAILURE
        }
    }
}

fn value<T: std::str::FromStr>(flag: &str, v: Option<String>) -> Result<T, String> {
    let v = v.ok_or_else(|| format!("{flag} needs a value\n{USAGE}"))?;
    v.parse().map_err(|_| format!("{flag}: bad value {v:?}\n{USAGE}"))
}

/// A shield option's value through the parser the main job uses.
fn shield<T>(v: Option<String>, flag: &str, parse: fn(&str) -> Result<T, String>) -> Result<T, String> {
    let v = v.ok_or_else(|| format!("{flag} needs a value\n{USAGE}"))?;
    parse(&v).map_err(|e| format!("{flag}: {e}\n{USAGE}"))
}

fn run() -> Result<(), String> {
    let mut opts = Options::new(8080, firmware::default_elf(), 1);
    let mut report: Option<f64> = None;
    let mut out: Option<PathBuf> = None;
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--port" => opts.port = value("--port", args.next())?,
            "--elf" => opts.elf = value("--elf", args.next())?,
            "--seed" => opts.seed = value("--seed", args.next())?,
            "--lcd" => opts.lcd = shield(args.next(), "--lcd", touch_arm_bench::shield::lcd_chip)?,
            "--wiring" => opts.wiring = shield(args.next(), "--wiring", touch_arm_bench::shield::panel_wiring)?,
            "--pacing-report" => report = Some(value("--pacing-report", args.next())?).filter(|s: &f64| *s > 0.0),
            "--out" => out = Some(value("--out", args.next())?),
            "-h" | "--help" => {
                println!("{USAGE}");
                return Ok(());
            }
            other => return Err(format!("unknown argument {other:?}\n{USAGE}")),
        }
    }
    // The docs' commands are checked against this parser (doc_commands test).
    if std::env::var_os(armsim::args::CHECK_ARGS).is_some() {
        return Ok(());
    }
    if let Some(seconds) = report {
        let md = live::pacing_report(&opts, seconds)?;
        match out {
            Some(path) => std::fs::write(&path, md).map_err(|e| format!("{}: {e}", path.display()))?,
            None => print!("{md}"),
        }
        return Ok(());
    }

    // SAFETY: installs a handler that only stores to an atomic.
    unsafe {
        libc::signal(libc::SIGINT, on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t);
        libc::signal(libc::SIGTERM, on_signal as extern "C" fn(libc::c_int) as libc::sighandler_t);
    }
    let bench = live::start(&opts)?;
    println!("touch-arm live bench: {} (firmware {}; Ctrl-C stops)", bench.url(), opts.elf.display());
    while !STOP.load(Ordering::SeqCst) {
        if !bench.is_running() {
            return Err("the simulator thread stopped".into());
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    bench.stop();
    println!("touch-arm live bench: stopped");
    Ok(())
}
