//! The README's main job (`touch-arm-sim`, run by scripts/run.sh): it writes
//! what it promises, and the chip's final pulses are the host's targets.

use std::process::Command;

use serde_json::Value;

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
    for key in ["raw", "x_p", "y_p", "condition", "alpha_deg", "q", "target_pulses_us", "final_pulses_us", "arrival_s"]
    {
        assert!(!summary[key].is_null(), "summary.json lacks {key}: {summary}");
    }
    assert_eq!(summary["condition"], 3);
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
    for png in ["angles.png", "screen.png"] {
        let bytes = std::fs::read(dir.join(png)).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "{png}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
