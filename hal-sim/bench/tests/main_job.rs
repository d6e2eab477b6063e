//! The README's main job (`touch-arm-sim`, run by scripts/run.sh): it writes
//! what it promises, and the chip's final pulses are the host's targets; a
//! press off the map is what the screen makes of it, not a failure.

use std::process::Command;

use serde_json::Value;
use touch_arm::ui::draw::Area;
use touch_arm::ui::Layout;

#[test]
fn main_job_writes_pulses_summary_plots_and_screen() {
    let dir = std::env::temp_dir().join(format!("touch-arm-main-job-{}", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_touch-arm-sim"))
        .args(["--xy", "-0.4,0.5", "--out"])
        .arg(&dir)
        .output()
        .expect("run touch-arm-sim");
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let summary: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    for key in [
        "raw",
        "x_p",
        "y_p",
        "condition",
        "alpha_deg",
        "q",
        "target_pulses_us",
        "final_pulses_us",
        "arrival_s",
        "law",
        "ts_s",
        "wiring",
    ] {
        assert!(!summary[key].is_null(), "summary.json lacks {key}: {summary}");
    }
    assert_eq!(summary["condition"], 3);
    assert_eq!(summary["law"], "zat");
    assert_eq!(summary["wiring"], "a");
    let (x, y) = (summary["x_p"].as_f64().unwrap(), summary["y_p"].as_f64().unwrap());
    assert!((x + 0.4).abs() < 0.01 && (y - 0.5).abs() < 0.01, "the map pixel holding (-0.4, 0.5): ({x}, {y})");
    let target: Vec<f64> =
        summary["target_pulses_us"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    let last: Vec<f64> = summary["final_pulses_us"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    for j in 0..3 {
        assert!((target[j] - last[j]).abs() <= 1.0, "joint {j}: {} vs {}", last[j], target[j]);
    }
    let csv = std::fs::read_to_string(dir.join("pulses.csv")).unwrap();
    assert!(csv.starts_with("t_s,base_us,shoulder_us,elbow_us\n") && csv.lines().count() > 100);
    for png in ["angles.png", "path.png", "screen.png"] {
        let bytes = std::fs::read(dir.join(png)).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{png}");
    }
    check_effector(&csv, &std::fs::read_to_string(dir.join("effector.csv")).unwrap(), &summary);
    std::fs::remove_dir_all(&dir).ok();
}

/// The default calibration inverted (600 + (1800/π)·θ for base and shoulder,
/// 2400 + (1800/π)·θ for the elbow) and the FK of the paper's arm
/// (l2 = l3 = 1), written out here.
fn effector(pulses_us: &[f64]) -> [f64; 3] {
    let k = 1800.0 / std::f64::consts::PI;
    let (a, q2, q3) = ((pulses_us[0] - 600.0) / k, (pulses_us[1] - 600.0) / k, (pulses_us[2] - 2400.0) / k);
    let (rho, z) = (q2.cos() + (q2 + q3).cos(), q2.sin() + (q2 + q3).sin());
    [rho * a.cos(), rho * a.sin(), z]
}

/// effector.csv is the FK of pulses.csv row by row, and ends on the target
/// pose's effector (reach |x_p|, height y_p in the direction α).
fn check_effector(pulses: &str, eff: &str, summary: &Value) {
    assert!(eff.starts_with("t_s,x,y,z\n"), "{}", &eff[..eff.len().min(80)]);
    let rows = |text: &str| -> Vec<Vec<f64>> {
        text.lines().skip(1).map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect()
    };
    let (p, e) = (rows(pulses), rows(eff));
    assert_eq!(p.len(), e.len());
    for (pr, er) in p.iter().zip(&e) {
        assert_eq!(pr[0], er[0]);
        let want = effector(&pr[1..]);
        // The firmware calibration holds its constants in f32: 1e-7 relative.
        assert!((0..3).all(|i| (er[1 + i] - want[i]).abs() < 1e-6), "t {}: {er:?} vs {want:?}", pr[0]);
    }
    let (x_p, y_p) = (summary["x_p"].as_f64().unwrap(), summary["y_p"].as_f64().unwrap());
    let alpha = summary["alpha_deg"].as_f64().unwrap().to_radians();
    let end = &e[e.len() - 1];
    let target = [x_p.abs() * alpha.cos(), x_p.abs() * alpha.sin(), y_p];
    // Within a few half-microsecond ticks of the pulses (1.6e-3 rad each).
    assert!((0..3).all(|i| (end[1 + i] - target[i]).abs() < 5e-3), "{end:?} vs {target:?}");
}

/// Width and height from a PNG's header (IHDR).
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let be = |i: usize| u32::from_be_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    (be(16), be(20))
}

#[test]
fn lcd_chooses_the_simulated_controller_around_the_same_elf() {
    for (lcd, size, id) in [("ili9486", (480, 320), "0x9486"), ("ili9325", (320, 240), "0x9325")] {
        let dir = std::env::temp_dir().join(format!("touch-arm-main-job-{}-{lcd}", std::process::id()));
        let out = Command::new(env!("CARGO_BIN_EXE_touch-arm-sim"))
            .args(["--xy", "0.4,0.6", "--lcd", lcd, "--out"])
            .arg(&dir)
            .output()
            .expect("run touch-arm-sim");
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "--lcd {lcd}: {}{stdout}", String::from_utf8_lossy(&out.stderr));
        assert!(stdout.contains(&format!("info lcd {lcd} id {id} {}x{}", size.0, size.1)), "{stdout}");
        // The arm went to the point picked on this screen's map.
        let summary: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
        let (x, y) = (summary["x_p"].as_f64().unwrap(), summary["y_p"].as_f64().unwrap());
        assert!((x - 0.4).abs() < 0.01 && (y - 0.6).abs() < 0.01, "--lcd {lcd}: ({x}, {y})");
        assert_eq!(png_size(&std::fs::read(dir.join("screen.png")).unwrap()), size, "--lcd {lcd}");
        std::fs::remove_dir_all(&dir).ok();
    }
}

/// `--wiring` puts the simulated panel on another preset's pins around the
/// same ELF: the firmware finds b on both b and c (the same plates), and the
/// arm ends on the same map point, c after the job has set the mirrored
/// calibration the calibration screen finds for it.
#[test]
fn wiring_chooses_the_simulated_panel_pins_around_the_same_elf() {
    let mut finals = Vec::new();
    for wiring in ["b", "c"] {
        let dir = std::env::temp_dir().join(format!("touch-arm-main-job-{}-wiring-{wiring}", std::process::id()));
        let out = Command::new(env!("CARGO_BIN_EXE_touch-arm-sim"))
            .args(["--xy", "0.4,0.6", "--wiring", wiring, "--out"])
            .arg(&dir)
            .output()
            .expect("run touch-arm-sim");
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "--wiring {wiring}: {}{stdout}", String::from_utf8_lossy(&out.stderr));
        assert!(stdout.contains("info wiring b\n"), "{stdout}");
        let summary: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
        assert_eq!(summary["wiring"], "b");
        let (x, y) = (summary["x_p"].as_f64().unwrap(), summary["y_p"].as_f64().unwrap());
        assert!((x - 0.4).abs() < 0.01 && (y - 0.6).abs() < 0.01, "--wiring {wiring}: ({x}, {y})");
        finals.push(summary["final_pulses_us"].clone());
        std::fs::remove_dir_all(&dir).ok();
    }
    assert_eq!(finals[0], finals[1]);
}

/// `--raw X,Y` for the centre of a screen region (default calibration).
fn raw_at_centre(a: Area) -> String {
    let (rx, ry) = touch_arm_rig::firmware::raw_at_centre(&Layout::QVGA, a).unwrap();
    format!("{rx},{ry}")
}

#[test]
fn a_press_on_stop_or_a_guard_band_says_what_the_screen_did() {
    let guard_below_map = Layout::QVGA.gaps()[1];
    for (region, expect, firmware) in [
        (Layout::QVGA.stop(), "STOP pressed: the arm holds", Some("firmware: info screen stop")),
        (guard_below_map, "guard band or a gap: the screen ignores it and the arm holds", None),
    ] {
        let raw = raw_at_centre(region);
        let dir = std::env::temp_dir().join(format!("touch-arm-main-job-{}-{raw}", std::process::id()));
        let out = Command::new(env!("CARGO_BIN_EXE_touch-arm-sim"))
            .args(["--raw", &raw, "--out"])
            .arg(&dir)
            .output()
            .expect("run touch-arm-sim");
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(out.status.success(), "--raw {raw}: {}{stdout}", String::from_utf8_lossy(&out.stderr));
        assert!(stdout.contains(&format!("touch at raw ({}): ", raw.replace(',', ", "))), "{stdout}");
        assert!(stdout.contains(expect), "--raw {raw}: {stdout}");
        assert_eq!(firmware.is_some_and(|f| stdout.contains(f)), firmware.is_some(), "{stdout}");
        // Nothing moved: the screen is the only output.
        assert_eq!(&std::fs::read(dir.join("screen.png")).unwrap()[..4], b"\x89PNG");
        assert!(!dir.join("summary.json").exists() && !dir.join("pulses.csv").exists());
        std::fs::remove_dir_all(&dir).ok();
    }
}

/// `--then X2,Y2@MS` touches the map a second time mid-move and `--law`
/// picks the profile: the summary says which, with both durations, and the
/// arm ends on the second target.
#[test]
fn main_job_re_plans_mid_move_under_the_law_asked() {
    let dir = std::env::temp_dir().join(format!("touch-arm-main-job-then-{}", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_touch-arm-sim"))
        .args(["--xy", "-0.5,0.5", "--then", "0.5,0.5@400", "--law", "quintic", "--out"])
        .arg(&dir)
        .output()
        .expect("run touch-arm-sim");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}{stdout}", String::from_utf8_lossy(&out.stderr));
    let summary: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["law"], "quintic");
    let (ts, then_ts) = (summary["ts_s"].as_f64().unwrap(), summary["then_ts_s"].as_f64().unwrap());
    assert!(ts > 0.5 && then_ts > 0.5, "{summary}");
    assert_eq!(summary["then_delay_ms"], 400);
    // The second tap starts 400 ms after the first's reply, rests 0.3 s and
    // is answered a few frames after its lift-off (the firmware acts on it).
    let after = summary["then_confirmed_after_s"].as_f64().unwrap();
    assert!((0.7..0.8).contains(&after), "{summary}");
    assert!(summary["then_reply"].as_str().unwrap().contains(" replan "), "{summary}");
    // The second touch is where the arm ends (condition 1, right of centre).
    assert_eq!(summary["condition"], 1);
    let target: Vec<f64> =
        summary["target_pulses_us"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    let last: Vec<f64> = summary["final_pulses_us"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert_eq!(target, last);
    // pulses.csv carries the timer's half-µs ticks.
    let csv = std::fs::read_to_string(dir.join("pulses.csv")).unwrap();
    for row in csv.lines().skip(1) {
        for v in row.split(',').skip(1) {
            let us: f64 = v.parse().unwrap();
            assert_eq!((us * 2.0).fract(), 0.0, "{row}");
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}

/// `--grip close`: the grip goes out after the move, and pulses.csv gains
/// `grip_us`, the gripper's pulse of each row's period: 600 µs (open, the
/// home pose's) until the grip, then up to 1500 µs (closed, the default
/// calibration's 90°), never back, never outside 600..1500 µs, and the
/// arm's columns as without it. The first grip runs at the slow preset:
/// 4317 ms for 90° (scenario grip.scn).
#[test]
fn main_job_grips_after_the_move() {
    let dir = std::env::temp_dir().join(format!("touch-arm-main-job-{}-grip", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_touch-arm-sim"))
        .args(["--xy", "0.4,0.6", "--grip", "close", "--out"])
        .arg(&dir)
        .output()
        .expect("run touch-arm-sim");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{}{stdout}", String::from_utf8_lossy(&out.stderr));
    let summary: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["grip"], "close");
    assert_eq!(summary["grip_reply"], "ok grip 9000 ts_ms 4317");
    assert_eq!(summary["grip_ts_s"].as_f64(), Some(4.317));
    assert_eq!(summary["grip_final_us"].as_f64(), Some(1500.0));
    let csv = std::fs::read_to_string(dir.join("pulses.csv")).unwrap();
    assert!(csv.starts_with("t_s,base_us,shoulder_us,elbow_us,grip_us\n"), "{}", &csv[..80]);
    let rows: Vec<Vec<f64>> = csv.lines().skip(1).map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    assert!(rows.iter().all(|r| r.len() == 5), "a row without its gripper pulse");
    let grip: Vec<f64> = rows.iter().map(|r| r[4]).collect();
    assert_eq!(grip[0], 600.0);
    assert_eq!(*grip.last().unwrap(), 1500.0);
    assert!(grip.iter().all(|w| (600.0..=1500.0).contains(w) && (w * 2.0).fract() == 0.0));
    assert!(grip.windows(2).all(|w| w[1] >= w[0] && w[1] - w[0] <= 8.5), "not smooth");
    // The grip starts once the arm has arrived: the arm's pulses are final
    // before the first gripper change.
    let moved = grip.iter().position(|w| *w != 600.0).unwrap();
    let finals: Vec<f64> = summary["final_pulses_us"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    assert!(rows[moved..].iter().all(|r| r[1..4] == finals[..]), "the arm moved during the grip");
    // 4.317 s of motion: 216 frames of change at most, and most of them.
    let changes = grip.windows(2).filter(|w| w[1] != w[0]).count();
    assert!((150..=216).contains(&changes), "{changes} changes");
    assert!(stdout.contains("firmware: ok grip 9000 ts_ms 4317; gripper pulse at the end 1500 us"), "{stdout}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Rows of effector.csv: (t, [x, y, z]).
fn effector_rows(dir: &std::path::Path) -> Vec<(f64, [f64; 3])> {
    let text = std::fs::read_to_string(dir.join("effector.csv")).unwrap();
    text.lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            (v[0], [v[1], v[2], v[3]])
        })
        .collect()
}

fn run_job(args: &[&str], tag: &str) -> (std::path::PathBuf, Value, String) {
    let dir = std::env::temp_dir().join(format!("touch-arm-main-job-{tag}-{}", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_touch-arm-sim")).args(args).arg("--out").arg(&dir).output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let summary: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    (dir, summary, String::from_utf8_lossy(&out.stdout).to_string())
}

#[test]
fn main_job_path_line_and_lift() {
    // --path line: the measured effector stays on the segment from the home
    // pose's effector (0, 1, 1) to the target's, within 0.005.
    let (dir, summary, stdout) = run_job(&["--xy", "0.6,0.3", "--path", "line"], "line");
    assert!(stdout.contains("firmware: info touch ") && stdout.contains(" path line ts_ms "), "{stdout}");
    assert_eq!(summary["path"], "line");
    assert!(summary["lift_h"].is_null());
    let rows = effector_rows(&dir);
    let (a, b) = ([0.0, 1.0, 1.0], rows.last().unwrap().1);
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let dd: f64 = d.iter().map(|x| x * x).sum();
    let worst = rows
        .iter()
        .map(|(_, p)| {
            let s = ((0..3).map(|i| (p[i] - a[i]) * d[i]).sum::<f64>() / dd).clamp(0.0, 1.0);
            (0..3).map(|i| (p[i] - a[i] - d[i] * s).powi(2)).sum::<f64>().sqrt()
        })
        .fold(0.0, f64::max);
    assert!(worst <= 0.005, "{worst} off the segment");
    std::fs::remove_dir_all(&dir).ok();
    // --lift 0.2: the effector passes the via pose (0.2 above the higher end,
    // halfway in base rotation and reach), marked in path.png.
    let (dir, summary, stdout) = run_job(&["--xy", "0.6,0.3", "--lift", "0.2"], "lift");
    assert!(stdout.contains(" lift 0.20 ts_ms "), "{stdout}");
    assert_eq!(summary["lift_h"], 0.2);
    let rows = effector_rows(&dir);
    let b = rows.last().unwrap().1;
    let base = (std::f64::consts::FRAC_PI_2 + b[1].atan2(b[0])) / 2.0;
    let rho = (1.0 + b[0].hypot(b[1])) / 2.0;
    let via = [rho * base.cos(), rho * base.sin(), 1f64.max(b[2]) + 0.2];
    let nearest =
        rows.iter().map(|(_, p)| (0..3).map(|i| (p[i] - via[i]).powi(2)).sum::<f64>().sqrt()).fold(f64::MAX, f64::min);
    // Within a frame's travel of the via pose.
    assert!(nearest <= 0.02, "{nearest} from the via pose {via:?}");
    assert_eq!(&std::fs::read(dir.join("path.png")).unwrap()[..8], b"\x89PNG\r\n\x1a\n");
    std::fs::remove_dir_all(&dir).ok();
    // The options exclude each other and --then.
    let out = Command::new(env!("CARGO_BIN_EXE_touch-arm-sim"))
        .args(["--xy", "0.6,0.3", "--path", "line", "--lift", "0.2"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let out = Command::new(env!("CARGO_BIN_EXE_touch-arm-sim")).args(["--lift", "0.55"]).output().unwrap();
    assert!(!out.status.success() && String::from_utf8_lossy(&out.stderr).contains("(0, 0.5]"));
}

/// `--finger FILE`: a scripted finger instead of the press, on the real ELF
/// (each ADC conversion at its own cycle). A 1 mm, 4 Hz tremor tap on the
/// pixel of (0.4, 0.6) commits once, within the tremor's reach (1.2 mm at
/// its drift-free amplitude, 6.7 px: 0.060 workspace units at 112 px a
/// unit) of the pixel, and `touches` is that one move at the summary's
/// point. STOP held then bounced on: the first action is STOP, within 60 ms
/// and a frame of contact, and no move; summary.json is `touches` and `wiring` only.
#[test]
fn main_job_plays_a_finger_script() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let tremor = root.join("fingers/tremor_1mm_4hz.csv");
    let (_, summary, _) = run_job(&["--finger", tremor.to_str().unwrap()], "finger_tremor");
    let touches = summary["touches"].as_array().unwrap();
    assert_eq!(touches.len(), 1, "{summary}");
    assert_eq!(touches[0]["action"], "move");
    assert_eq!(touches[0]["x_p"], summary["x_p"]);
    assert_eq!(touches[0]["y_p"], summary["y_p"]);
    let (x_p, y_p) = (summary["x_p"].as_f64().unwrap(), summary["y_p"].as_f64().unwrap());
    assert!((x_p - 0.4).abs() <= 0.06 && (y_p - 0.6).abs() <= 0.01, "({x_p}, {y_p})");
    assert!(touches[0]["t_s"].as_f64().unwrap() > 0.0);

    let stop = root.join("fingers/stop.csv");
    let dir = std::env::temp_dir().join(format!("touch-arm-sim-finger-stop-{}", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_touch-arm-sim"))
        .args(["--finger", stop.to_str().unwrap(), "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let summary: Value = serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    let mut keys: Vec<&str> = summary.as_object().unwrap().keys().map(String::as_str).collect();
    keys.sort_unstable();
    assert_eq!(keys, ["touches", "wiring"], "{summary}");
    let touches = summary["touches"].as_array().unwrap();
    assert_eq!(touches[0]["action"], "stop", "{summary}");
    assert!(touches[0]["x_p"].is_null() && touches[0]["y_p"].is_null());
    assert!(touches[0]["t_s"].as_f64().unwrap() <= 0.08, "{summary}");
    assert!(touches.iter().all(|t| t["action"] != "move"));
    assert!(dir.join("screen.png").exists() && !dir.join("pulses.csv").exists());
    let _ = std::fs::remove_dir_all(&dir);

    // A script that does not parse: the job says which line and fails.
    let bad = std::env::temp_dir().join(format!("touch-arm-sim-bad-finger-{}.csv", std::process::id()));
    std::fs::write(&bad, "t_ms,x_px,y_px,force\n0,1,2\n").unwrap();
    let out =
        Command::new(env!("CARGO_BIN_EXE_touch-arm-sim")).args(["--finger", bad.to_str().unwrap()]).output().unwrap();
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("line 2: 3 values, the header has 4"));
    let _ = std::fs::remove_file(&bad);
}

/// `--reset`: the RESET pin once the arm has arrived. The firmware reboots
/// with its RAM and resumes the pulses it had: pulses.csv runs on through
/// the reboot, its last row before the gap and its first after it equal,
/// and every row after the arrival holds the final pulses (no jump home).
#[test]
fn main_job_resets_once_the_arm_has_arrived_and_the_pulses_run_on() {
    let (dir, summary, stdout) = run_job(&["--xy", "0.4,0.6", "--reset"], "reset");
    let line = summary["reset_line"].as_str().unwrap();
    assert_eq!(line, "info reset external resume pulses 1166 1854.5 1023 600", "{summary}");
    assert_eq!(summary["pulses_before_reset_us"], summary["pulses_after_reset_us"], "{summary}");
    assert_eq!(summary["pulses_after_reset_us"], summary["final_pulses_us"], "{summary}");
    let gap = summary["reset_gap_s"].as_f64().unwrap();
    // The display's start-up and the boot frame: no pulse for a few hundred ms.
    assert!(gap > 0.1 && gap < 1.0, "{gap}");
    assert!(stdout.contains("external reset at "), "{stdout}");
    let csv = std::fs::read_to_string(dir.join("pulses.csv")).unwrap();
    let rows: Vec<Vec<f64>> = csv.lines().skip(1).map(|l| l.split(',').map(|x| x.parse().unwrap()).collect()).collect();
    let at = summary["reset_at_s"].as_f64().unwrap();
    let k = rows.iter().position(|r| r[0] > at).expect("rows after the reset");
    assert!(rows[k][0] - rows[k - 1][0] > 0.1, "the gap is in pulses.csv");
    assert!(rows.len() - k > 40, "a second of pulses after the reboot");
    let finals: Vec<f64> = summary["final_pulses_us"].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect();
    for r in &rows[k - 5..] {
        assert_eq!(&r[1..4], &finals[..], "row {r:?}");
    }
}

/// `--switch T1,T2,T3`: `switch on` once homed, then PA0 held low 200 ms at
/// each time (ms after the reply). At the default sweep of 6 s (300 frames;
/// the 224×112 map; the scan stands still while the switch is down) a press
/// 2.0 s into the column sweep fixes column 74 (frame 100), one at 5.1 s
/// row 58 (the row sweep starts when the column press's release counts,
/// ~2.25 s: 142 frames, 53 rows up from row 111), and one at 5.7 s, in the
/// 1.2 s Go phase, sends the arm to that pixel, (−0.33, 0.48) on the map:
/// the job's end point, reached within a microsecond of the host's target,
/// away from the home pose.
#[test]
fn main_job_presses_the_switch_and_the_arm_goes_where_the_scan_points() {
    let (dir, summary, stdout) = run_job(&["--switch", "2000,5100,5700"], "switch");
    assert!(stdout.contains("info switch go "), "{stdout}");
    assert_eq!(summary["switch_ms"], serde_json::json!([2000, 5100, 5700]));
    let lines: Vec<&str> = summary["switch"].as_array().unwrap().iter().map(|l| l["line"].as_str().unwrap()).collect();
    let go = lines.iter().find(|l| l.starts_with("info switch go ")).unwrap_or_else(|| panic!("{summary}"));
    let px: Vec<i16> = go["info switch go ".len()..].split(' ').map(|v| v.parse().unwrap()).collect();
    assert!(lines.iter().position(|l| l.starts_with("info switch column ")) < lines.iter().position(|l| l == go));
    // Near the pixel the press times point at (the rig's switch test checks
    // the scan's timing; here only that the presses did their part): a
    // press takes the line the glass shows, within a frame of the scan's
    // (frame_budget.rs measures it).
    assert!((px[0] - 74).abs() <= 2 && (px[1] - 58).abs() <= 2, "{go}");
    let (x_p, y_p) = Layout::QVGA.ws_pixel_to_point(px[0], px[1]).unwrap();
    let (x, y) = (summary["x_p"].as_f64().unwrap(), summary["y_p"].as_f64().unwrap());
    assert!((x - f64::from(x_p)).abs() < 1e-6 && (y - f64::from(y_p)).abs() < 1e-6, "({x}, {y}) vs {go}");
    let f = |k: &str| -> Vec<f64> { summary[k].as_array().unwrap().iter().map(|v| v.as_f64().unwrap()).collect() };
    let (target, last) = (f("target_pulses_us"), f("final_pulses_us"));
    for j in 0..3 {
        assert!((target[j] - last[j]).abs() <= 1.0, "joint {j}: {} vs {}", last[j], target[j]);
    }
    // The arm moved: from the home pose (1500 µs each) to the target.
    let csv = std::fs::read_to_string(dir.join("pulses.csv")).unwrap();
    let rows: Vec<Vec<f64>> = csv.lines().skip(1).map(|l| l.split(',').map(|v| v.parse().unwrap()).collect()).collect();
    assert!(rows.first().unwrap()[1..4].iter().all(|w| *w == 1500.0), "{:?}", rows[0]);
    assert!(last.iter().any(|w| (w - 1500.0).abs() > 20.0), "{last:?}");
    assert!(summary["arrival_s"].as_f64().unwrap() > 0.0, "{summary}");
    check_effector(&csv, &std::fs::read_to_string(dir.join("effector.csv")).unwrap(), &summary);
    std::fs::remove_dir_all(&dir).ok();
}
