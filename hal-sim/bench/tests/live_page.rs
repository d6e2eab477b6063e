//! The live bench's page in a real browser: Debian's headless Chromium,
//! driven by Playwright (`hal-sim/bench/tests/browser/live_page.mjs`, installed by
//! scripts/setup.sh), against a bench started here on a free loopback port.
//! A click on the map in the screen image moves the drawn arm to the host's
//! IK angles, a click on STOP in the screen image freezes the pulses, and
//! `status` typed in the console shows the firmware's reply, and the Switch
//! button held by the mouse, by Space and by a pointer that slides off
//! closes and opens the assistive switch (the firmware's scan fixes a column
//! and a row). Screenshots go to out/live-page*.png.

use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use touch_arm_bench::live::LAYOUT;
use touch_arm_bench::live::{self, Options};
use touch_arm_rig::firmware;

/// The script bounds itself at 90 s; this is the backstop.
const TIMEOUT: Duration = Duration::from_secs(150);

#[test]
fn the_page_moves_the_arm_stops_it_and_talks_to_the_console() {
    let root = firmware::workspace_root();
    let script_dir = root.join("hal-sim/bench/tests/browser");
    let chromium = std::env::var_os("CHROMIUM").map_or_else(|| PathBuf::from("/usr/bin/chromium"), PathBuf::from);
    assert!(chromium.exists(), "{} not found: scripts/setup.sh installs Debian's chromium", chromium.display());
    assert!(
        script_dir.join("node_modules/playwright-core/package.json").exists(),
        "playwright-core not installed: scripts/setup.sh runs `npm ci` in {}",
        script_dir.display()
    );

    let bench =
        live::start(&Options::new(0, firmware::default_elf(), 9)).expect("live bench (firmware ELF: cargo avr)");
    // A map point left of the base (condition 3), and the host's angles for
    // the pixel's centre, which is what the firmware targets.
    let (px, py) = LAYOUT.ws_point_to_pixel(-0.3, 0.5).unwrap();
    let (x_p, y_p) = LAYOUT.ws_pixel_to_point(px, py).unwrap();
    let host = firmware::host_target(f64::from(x_p), f64::from(y_p)).unwrap();
    let target = host.q.map(|q| format!("{:.4}", q.to_degrees())).join(",");
    let stop = LAYOUT.stop();
    let (sx, sy) = (stop.x + stop.w as i16 / 2, stop.y + stop.h as i16 / 2);
    let out = root.join("out");

    let start = Instant::now();
    let mut child = Command::new("node")
        .current_dir(&script_dir)
        .arg("live_page.mjs")
        .arg(bench.url())
        .arg(&out)
        .arg(format!("{px},{py}"))
        .arg(&target)
        .arg(format!("{sx},{sy}"))
        .env("CHROMIUM", &chromium)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("node (scripts/setup.sh installs nodejs)");
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break Some(s);
        }
        if start.elapsed() > TIMEOUT {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let output = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    let stderr = String::from_utf8_lossy(&output.stderr);
    eprintln!("{stdout}{stderr}page test: {:.1} s", start.elapsed().as_secs_f64());
    bench.stop();
    let status = status.unwrap_or_else(|| panic!("the page test did not finish within {TIMEOUT:?}"));
    assert!(
        status.success() && stdout.contains("PASS"),
        "page test failed ({status}); screenshots in {}",
        out.display()
    );
    assert!(out.join("live-page.png").exists());
}
