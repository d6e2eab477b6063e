//! Scenario tests of the app on the host twin: one test per file in
//! `tests/scenarios/` (format: `hal_sim::scenario`). A file that no
//! test lists fails `every_scenario_file_has_a_test`.

use std::path::{Path, PathBuf};

fn dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/scenarios")
}

fn run(name: &str) {
    let path = dir().join(format!("{name}.scn"));
    if let Err(e) = hal_sim::scenario::run_file(&path) {
        panic!("{e}");
    }
}

macro_rules! scenarios {
    ($($name:ident),* $(,)?) => {
        $(
            #[test]
            fn $name() {
                run(stringify!($name));
            }
        )*
        const LISTED: &[&str] = &[$(stringify!($name)),*];
    };
}

scenarios!(
    access_lock,
    carer_pose_save,
    speed_cap,
    arm_geometry,
    undo,
    arrive_together,
    cal_consistency,
    cal_roundtrip,
    cal_slew,
    case,
    circle,
    eeprom_corrupt,
    finger_script,
    flicker,
    flood,
    grip,
    help_version,
    home_pulse_window,
    idle_noise,
    law_switch,
    lcd_settings,
    lift,
    line_timeout,
    log_plot,
    malformed,
    pose,
    pose_path,
    path_ik_range,
    path_line,
    path_pulse_window,
    path_refusals,
    powerup,
    refusals,
    replan,
    screen_more,
    screen_undo,
    screen_warnings,
    speed_bound,
    stop_byte,
    stop_mid_move,
    telemetry,
    touch_cond1,
    touch_cond2,
    touch_cond3,
    touch_cond4,
    touch_noisy,
    touch_cancel,
    stop_slide,
    switch_scan,
    switch_glass,
    stop_bounce,
    hold_boundaries,
    palm,
    unreachable,
    hold_release,
);

#[test]
fn every_scenario_file_has_a_test() {
    let mut files: Vec<String> = std::fs::read_dir(dir())
        .expect("tests/scenarios exists")
        .filter_map(|e| {
            let p = e.ok()?.path();
            if p.extension()? != "scn" {
                return None;
            }
            Some(p.file_stem()?.to_string_lossy().into_owned())
        })
        .collect();
    files.sort();
    let mut listed: Vec<String> = LISTED.iter().map(|s| s.to_string()).collect();
    listed.sort();
    assert_eq!(files, listed, "scenario files and listed tests differ");
}
