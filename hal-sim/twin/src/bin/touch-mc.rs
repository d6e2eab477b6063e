//! The touch Monte Carlo's generator (`hal_sim::touch_mc`): runs every cell
//! of the grid and writes the BENCHMARKS.md section (and the figures as CSV).
//!
//!   touch-mc [--taps N] [--seed S] [--out FILE.md] [--csv FILE.csv] [--before FILE.csv] [--only TEXT]
//!
//! `--taps` per cell (default 1000; ten times as many in the cells whose
//! goals are stated over 10⁴ trials: `Cell::taps`), `--before` a CSV of an earlier run (the
//! "before" columns; default `hal-sim/twin/data/touch_mc_before.csv` when it
//! exists), `--only` runs the cells whose name contains TEXT. Progress goes
//! to stderr.

use std::process::ExitCode;

use hal_sim::touch_mc;

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("touch-mc: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), String> {
    let (mut taps, mut seed, mut out, mut csv, mut only) = (1000u32, 19u64, None, None, None);
    let mut before = Some(std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/data/touch_mc_before.csv")));
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        let mut val = || args.next().ok_or_else(|| format!("{a} needs a value"));
        match a.as_str() {
            "--taps" => taps = val()?.parse().map_err(|_| "--taps takes a whole number")?,
            "--seed" => seed = val()?.parse().map_err(|_| "--seed takes a whole number")?,
            "--out" => out = Some(val()?),
            "--csv" => csv = Some(val()?),
            "--before" => before = Some(val()?.into()),
            "--only" => only = Some(val()?),
            "-h" | "--help" => {
                println!(
                    "touch-mc [--taps N] [--seed S] [--out FILE.md] [--csv FILE.csv] [--before FILE.csv] [--only TEXT]"
                );
                return Ok(());
            }
            other => return Err(format!("unknown argument {other:?}")),
        }
    }
    let before = match before.filter(|p| p.exists()) {
        Some(p) => touch_mc::from_csv(&std::fs::read_to_string(&p).map_err(|e| format!("{}: {e}", p.display()))?)?,
        None => Vec::new(),
    };
    let mut rows = Vec::new();
    for (i, cell) in touch_mc::grid().iter().enumerate() {
        if only.as_ref().is_some_and(|o| !cell.name.contains(o.as_str())) {
            continue;
        }
        let t0 = std::time::Instant::now();
        let r = touch_mc::run_cell(cell, cell.taps(taps), seed.wrapping_add(i as u64))?;
        eprintln!(
            "{:<48} {:>6.1} s  {}",
            cell.name,
            t0.elapsed().as_secs_f64(),
            touch_mc::to_csv(std::slice::from_ref(&r)).lines().nth(1).unwrap_or("")
        );
        rows.push(r);
    }
    if let Some(p) = &csv {
        std::fs::write(p, touch_mc::to_csv(&rows)).map_err(|e| format!("{p}: {e}"))?;
    }
    let md = touch_mc::markdown(&rows, &before, seed);
    match &out {
        Some(p) => std::fs::write(p, md).map_err(|e| format!("{p}: {e}"))?,
        None => print!("{md}"),
    }
    Ok(())
}
