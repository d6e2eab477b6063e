//! The main job: run the real firmware ELF in simavr and report what it does.
//! Writes `out/frames.csv` and `out/frames.png` and prints a short summary.

use std::path::PathBuf;
use std::process::ExitCode;

use hal_sim::firmware::{self, parse_frame};
use hal_sim::plot::{self, Curve, Panel};

fn main() -> ExitCode {
    match run() {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("touch-arm-sim: {e}");
            ExitCode::FAILURE
        }
    }
}

fn run() -> Result<(), String> {
    let mut elf = firmware::default_elf();
    let mut out = PathBuf::from("out");
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--elf" => elf = args.next().ok_or("--elf needs a path")?.into(),
            "--out" => out = args.next().ok_or("--out needs a directory")?.into(),
            "-h" | "--help" => {
                println!("usage: touch-arm-sim [--elf FILE] [--out DIR]\nRuns the firmware in simavr; writes DIR/frames.csv and DIR/frames.png.");
                return Ok(());
            }
            other => return Err(format!("unknown argument {other:?} (see --help)")),
        }
    }
    let mut avr = firmware::load(&elf)?;
    avr.run_until_output(b"done\n", firmware::CPU_HZ as u64 * 10).map_err(|e| format!("firmware did not finish: {e:?}"))?;
    let text = avr.uart_output_string();
    let frames: Vec<_> = text.lines().filter_map(parse_frame).collect();
    if frames.is_empty() {
        return Err(format!("no frames in the firmware output:\n{text}"));
    }
    std::fs::create_dir_all(&out).map_err(|e| format!("{}: {e}", out.display()))?;
    let mut csv = String::from("t_s,q_base,q_shoulder,q_elbow,v_base,v_shoulder,v_elbow,eval_cycles\n");
    for f in &frames {
        let q = f.q_urad.map(|v| v as f64 * 1e-6);
        let v = f.v_urad_s.map(|v| v as f64 * 1e-6);
        csv += &format!("{},{},{},{},{},{},{},{}\n", f.t_us as f64 * 1e-6, q[0], q[1], q[2], v[0], v[1], v[2], f.eval_cycles);
    }
    let csv_path = out.join("frames.csv");
    std::fs::write(&csv_path, csv).map_err(|e| format!("{}: {e}", csv_path.display()))?;

    let t: Vec<f64> = frames.iter().map(|f| f.t_us as f64 * 1e-6).collect();
    let col = |j: usize, vel: bool| -> Vec<f64> {
        frames.iter().map(|f| if vel { f.v_urad_s[j] } else { f.q_urad[j] } as f64 * 1e-6).collect()
    };
    let q: Vec<Vec<f64>> = (0..3).map(|j| col(j, false)).collect();
    let v: Vec<Vec<f64>> = (0..3).map(|j| col(j, true)).collect();
    let names = ["base", "shoulder", "elbow"];
    let png = out.join("frames.png");
    plot::panels(&png, "firmware in simavr: joint angles [rad] and velocities [rad/s]", &t, &[Panel { ylabel: "angle [rad]", curves: curves(&names, &q) }, Panel { ylabel: "velocity [rad/s]", curves: curves(&names, &v) }])
        .map_err(|e| e.to_string())?;

    let mut cycles: Vec<u32> = frames.iter().map(|f| f.eval_cycles).collect();
    cycles.sort_unstable();
    let last = frames.last().unwrap();
    println!("{}", text.lines().next().unwrap_or(""));
    println!("{} frames at 50 Hz over {:.2} s (simulated)", frames.len(), last.t_us as f64 * 1e-6);
    println!("final angles [rad]: {:.6} {:.6} {:.6}", last.q_urad[0] as f64 * 1e-6, last.q_urad[1] as f64 * 1e-6, last.q_urad[2] as f64 * 1e-6);
    println!("frame evaluation: median {} cycles ({:.0} us at 16 MHz)", cycles[cycles.len() / 2], cycles[cycles.len() / 2] as f64 / 16.0);
    println!("wrote {} and {}", csv_path.display(), png.display());
    Ok(())
}

fn curves<'a>(names: &[&'a str; 3], data: &'a [Vec<f64>]) -> Vec<Curve<'a>> {
    names.iter().zip(data).map(|(label, y)| Curve { label, y }).collect()
}
