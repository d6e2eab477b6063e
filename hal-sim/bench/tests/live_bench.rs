//! The live bench (`touch-arm-live`, `scripts/run.sh --live`) through its
//! JSON API, as a script would use it: the real firmware in simavr paced to
//! real time, a server on a free loopback port. A press on the map ends at
//! the host's IK target, `stop` freezes the pulses, the faults do what the
//! page promises, a checked move's late answer reaches `/api/serial`, the
//! console log reads without gaps, the assistive switch's endpoint drives
//! PA0, and bad requests get a 4xx with one line of reason.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::time::{Duration, Instant};

use serde_json::{json, Value};
use touch_arm_bench::live::LAYOUT;
use touch_arm_bench::live::{self, LiveBench, Options};
use touch_arm_rig::firmware;

fn start() -> LiveBench {
    live::start(&Options::new(0, firmware::default_elf(), 5)).expect("live bench (firmware ELF: cargo avr)")
}

/// One HTTP/1.1 exchange on a fresh connection: status and body text.
fn request(addr: SocketAddr, method: &str, path: &str, body: &str, headers: &[(&str, &str)]) -> (u16, String) {
    let (status, bytes) = request_bytes(addr, method, path, body, headers);
    (status, String::from_utf8_lossy(&bytes).into_owned())
}

fn request_bytes(addr: SocketAddr, method: &str, path: &str, body: &str, headers: &[(&str, &str)]) -> (u16, Vec<u8>) {
    let mut s = TcpStream::connect(addr).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    let mut head = format!("{method} {path} HTTP/1.1\r\nConnection: close\r\nContent-Length: {}\r\n", body.len());
    if !headers.iter().any(|(k, _)| k.eq_ignore_ascii_case("host")) {
        head += &format!("Host: {addr}\r\n");
    }
    for (k, v) in headers {
        head += &format!("{k}: {v}\r\n");
    }
    s.write_all(format!("{head}\r\n{body}").as_bytes()).unwrap();
    let mut raw = Vec::new();
    s.read_to_end(&mut raw).unwrap();
    let split = raw.windows(4).position(|w| w == b"\r\n\r\n").map_or(raw.len(), |i| i + 4);
    let head = String::from_utf8_lossy(&raw[..split]);
    let status = head.split_whitespace().nth(1).and_then(|c| c.parse().ok()).unwrap_or(0);
    (status, raw[split..].to_vec())
}

fn get(addr: SocketAddr, path: &str) -> Value {
    let (status, body) = request(addr, "GET", path, "", &[]);
    assert_eq!(status, 200, "GET {path}: {body}");
    serde_json::from_str(&body).unwrap()
}

fn post(addr: SocketAddr, path: &str, body: Value) -> (u16, Value) {
    let (status, text) = request(addr, "POST", path, &body.to_string(), &[("Content-Type", "application/json")]);
    (status, serde_json::from_str(&text).unwrap_or_else(|_| panic!("POST {path}: not JSON: {text:?}")))
}

fn ok(addr: SocketAddr, path: &str, body: Value) -> Value {
    let (status, v) = post(addr, path, body.clone());
    assert_eq!(status, 200, "POST {path} {body}: {v}");
    v
}

fn serial(addr: SocketAddr, line: &str) -> Vec<String> {
    let v = ok(addr, "/api/serial", json!({ "line": line }));
    v["replies"].as_array().unwrap().iter().map(|l| l.as_str().unwrap().to_string()).collect()
}

/// Polls `GET /api/state` until `f` holds (wall-clock timeout: the bench
/// runs in real time).
fn wait_state(addr: SocketAddr, what: &str, timeout_s: f64, f: impl Fn(&Value) -> bool) -> Value {
    let end = Instant::now() + Duration::from_secs_f64(timeout_s);
    loop {
        let s = get(addr, "/api/state");
        if f(&s) {
            return s;
        }
        assert!(Instant::now() < end, "{what}: not within {timeout_s} s; last state {s}");
        std::thread::sleep(Duration::from_millis(100));
    }
}

fn pulses(s: &Value) -> [f64; 3] {
    std::array::from_fn(|j| s["pulses_us"][j].as_f64().unwrap_or(f64::NAN))
}

/// The home pose's pulses, as measured: within one Timer5 tick (0.5 µs) of
/// 1500 µs. The measurement counts CPU cycles (1/16 µs), and on a loaded
/// machine a home pulse was once read one cycle long (1500.0625 µs); any
/// other commanded width is at least one tick away.
fn assert_home(s: &Value, what: &str) {
    let p = pulses(s);
    assert!(p.iter().all(|w| (w - 1500.0).abs() < 0.5), "{what}: {p:?} ({s})");
}

fn holding(addr: SocketAddr) -> Value {
    wait_state(addr, "the firmware holds its pose", 10.0, |s| s["state"] == "holding")
}

#[test]
fn a_map_press_reaches_the_host_ik_target_and_stop_freezes_the_pulses() {
    let bench = start();
    let a = bench.addr();
    let s0 = holding(a);
    assert_home(&s0, "home pose");
    let keys: Vec<&str> = s0.as_object().unwrap().keys().map(String::as_str).collect();
    assert_eq!(
        keys,
        ["angles_deg", "grip_deg", "grip_pulse_us", "pulses_us", "screen_seq", "state", "t_s"],
        "exactly the documented keys"
    );

    // Press the map where the workspace point (0.4, 0.6) is drawn; the
    // firmware targets that pixel's centre, and so does the host's chain.
    let (px, py) = LAYOUT.ws_point_to_pixel(0.4, 0.6).unwrap();
    let (x_p, y_p) = LAYOUT.ws_pixel_to_point(px, py).unwrap();
    let host = firmware::host_target(f64::from(x_p), f64::from(y_p)).unwrap();
    assert!(host.within_limits);
    let seq0 = s0["screen_seq"].as_u64().unwrap();
    let r = ok(a, "/api/touch", json!({ "x_px": px, "y_px": py, "ms": 300 }));
    assert_eq!(r["target"]["pulses_us"], json!(host.pulses_us), "{r}");
    let s = wait_state(a, "the pulses reach the host's IK target", 12.0, |s| {
        s["state"] == "holding" && pulses(s).iter().zip(host.pulses_us).all(|(p, t)| (p - t).abs() <= 1.0)
    });
    for j in 0..3 {
        let angle = s["angles_deg"][j].as_f64().unwrap();
        assert!((angle - host.q[j].to_degrees()).abs() < 0.11, "joint {j}: {angle}° vs {}°", host.q[j].to_degrees());
    }
    assert!(s["screen_seq"].as_u64().unwrap() > seq0, "the screen changed (marker, text): {s}");
    let (status, png) = request_bytes(a, "GET", "/api/screen.png", "", &[]);
    assert_eq!(status, 200);
    assert!(png.starts_with(b"\x89PNG\r\n\x1a\n"), "screen.png is a PNG");

    // A long move, then `stop` over the serial API: the pulses freeze.
    let replies = serial(a, "goto 20 150 -30");
    assert!(replies.last().is_some_and(|l| l.starts_with("ok goto")), "{replies:?}");
    std::thread::sleep(Duration::from_millis(800));
    assert_eq!(serial(a, "stop"), ["ok stop"]);
    let stopped = wait_state(a, "the firmware reports stopped", 2.0, |s| s["state"] == "stopped");
    let frozen = pulses(&stopped);
    assert!(frozen.iter().zip(host.pulses_us).any(|(p, t)| (p - t).abs() > 5.0), "stopped mid-move, not before it");
    std::thread::sleep(Duration::from_millis(1000));
    let later = get(a, "/api/state");
    for (j, (p, q)) in pulses(&later).iter().zip(frozen).enumerate() {
        assert!((p - q).abs() <= 0.25, "joint {j} moved after stop: {q} -> {p} µs");
    }
    assert!(later["t_s"].as_f64().unwrap() - stopped["t_s"].as_f64().unwrap() > 0.9, "time went on");
    let status = serial(a, "status");
    assert!(status.len() == 1 && status[0].starts_with("ok status stopped"), "{status:?}");
    bench.stop();
}

/// The gripper's pulse and angle in the state (and so on the page): `grip
/// 60` ends at 60° through the default calibration, 600 µs + 10 µs/°.
#[test]
fn the_gripper_shows_in_the_state() {
    let bench = start();
    let a = bench.addr();
    holding(a);
    let r = serial(a, "grip 60");
    assert!(r.len() == 1 && r[0].starts_with("ok grip"), "{r:?}");
    let s = wait_state(a, "the gripper reaches 60°", 10.0, |s| {
        s["grip_deg"].as_f64().is_some_and(|g| (g - 60.0).abs() < 0.05)
    });
    let us = s["grip_pulse_us"].as_f64().unwrap();
    assert!((us - 1200.0).abs() <= 0.5, "grip pulse {us} µs");
    bench.stop();
}

/// `POST /api/finger`: a scripted finger (a 4 Hz, 1 mm tremor of 0.5 s on
/// the map pixel of (0.4, 0.6)) answers at once with the bench time it
/// starts at, and the firmware acts on it: the arm leaves its pose. A bad
/// script is a 400 with one line of reason.
#[test]
fn a_finger_script_starts_at_once_and_moves_the_arm() {
    let bench = start();
    let a = bench.addr();
    let s0 = holding(a);
    let p0 = pulses(&s0);
    let (px, py) = LAYOUT.ws_point_to_pixel(0.4, 0.6).unwrap();
    let samples: Vec<Value> = (0..=250)
        .map(|i| {
            let t = f64::from(i) * 2.0;
            let d = (1.0 / 0.18) * (std::f64::consts::TAU * 4.0 * t / 1000.0).sin();
            json!([t, f64::from(px) + d, f64::from(py), 1])
        })
        .collect();
    let before = get(a, "/api/state")["t_s"].as_f64().unwrap();
    let r = ok(a, "/api/finger", json!({ "samples": samples }));
    let t0 = r["t_s"].as_f64().unwrap();
    assert!(t0 >= before && r.as_object().unwrap().len() == 1, "{r}");
    let s =
        wait_state(a, "the arm leaves its pose", 6.0, |s| pulses(s).iter().zip(p0).any(|(p, q)| (p - q).abs() > 20.0));
    assert!(s["t_s"].as_f64().unwrap() > t0);
    let (status, body) = request(a, "POST", "/api/finger", r#"{"samples": [[5, 1, 1, 1], [2, 1, 1, 1]]}"#, &[]);
    assert_eq!(status, 400);
    assert!(
        body.contains("samples: sample 1: t_ms 2 before the previous sample's 5") && !body.trim_end().contains('\n'),
        "{body}"
    );
    let (status, _) = request(a, "GET", "/api/finger", "", &[]);
    assert_eq!(status, 405);
    bench.stop();
}

/// Method, path, body, extra headers, expected status, expected reason.
type BadRequest<'a> = (&'a str, &'a str, &'a str, &'a [(&'a str, &'a str)], u16, &'a str);

#[test]
fn bad_requests_get_a_4xx_with_one_line_of_reason_and_change_nothing() {
    let bench = start();
    let a = bench.addr();
    let cases: [BadRequest; 13] = [
        (
            "POST",
            "/api/touch",
            "{\"x_px\": 320, \"y_px\": 10, \"ms\": 100}",
            &[],
            400,
            "x_px must be an integer 0..=319",
        ),
        ("POST", "/api/touch", "{\"x_px\": 10, \"y_px\": 10}", &[], 400, "missing field ms"),
        ("POST", "/api/touch", "{\"x_px\": 10, \"y_px\": 10, \"ms\": 0}", &[], 400, "ms must be"),
        ("POST", "/api/touch", "not json", &[], 400, "body is not JSON"),
        ("POST", "/api/touch", "[1]", &[], 400, "body must be a JSON object"),
        ("POST", "/api/serial", "{\"line\": \"stop\\nresume\"}", &[], 400, "line must be a single line"),
        ("POST", "/api/serial", "{\"line\": \"\"}", &[], 400, "line is empty"),
        ("POST", "/api/control", "{\"action\": \"explode\"}", &[], 400, "unknown action"),
        ("GET", "/api/touch", "", &[], 405, "/api/touch takes POST"),
        ("POST", "/api/state", "{}", &[], 405, "/api/state takes GET"),
        ("GET", "/api/nothing", "", &[], 404, "no such endpoint"),
        ("GET", "/api/state", "", &[("Host", "attacker.example:80")], 403, "Host"),
        (
            "POST",
            "/api/control",
            "{\"action\": \"power_cycle\"}",
            &[("Origin", "http://attacker.example")],
            403,
            "requests from",
        ),
    ];
    for (method, path, body, headers, want, reason) in cases {
        let (status, text) = request(a, method, path, body, headers);
        assert_eq!(status, want, "{method} {path} {body}: {text}");
        let v: Value = serde_json::from_str(&text).unwrap_or_else(|_| panic!("{method} {path}: {text:?}"));
        let e = v["error"].as_str().unwrap();
        assert!(e.contains(reason) && !e.contains('\n'), "{method} {path}: {e:?} lacks {reason:?}");
    }
    let big = format!("{{\"line\": \"{}\"}}", "a".repeat(20_000));
    assert_eq!(request(a, "POST", "/api/serial", &big, &[]).0, 413);
    // Garbage on the socket does not take the server down.
    let mut s = TcpStream::connect(a).unwrap();
    s.write_all(b"\x00\xff NOT HTTP\r\n\r\n").unwrap();
    drop(s);
    // None of that reached the firmware: it boots and holds as always.
    let s = holding(a);
    assert_home(&s, "after the bad requests");
    assert!(bench.is_running());
    bench.stop();
}

#[test]
fn power_cycle_keeps_the_eeprom_a_corrupted_copy_is_reported_and_a_stall_trips_the_watchdog() {
    let bench = start();
    let a = bench.addr();
    holding(a);
    assert_eq!(ok(a, "/api/control", json!({ "action": "noise_on" })), json!({ "noise": true }));
    assert_eq!(get(a, "/api/bench")["noise"], true);
    assert_eq!(ok(a, "/api/control", json!({ "action": "noise_off" })), json!({ "noise": false }));

    // Save the configuration (both copies), damage copy A, power-cycle: the
    // firmware boots from copy B and says one copy is damaged.
    assert!(serial(a, "cal save").last().is_some_and(|l| l.starts_with("ok cal save seq 1")));
    let c = ok(a, "/api/control", json!({ "action": "corrupt_eeprom" }));
    assert_eq!(c["addr"], 5);
    assert_eq!(c["new"].as_u64().unwrap(), 255 - c["old"].as_u64().unwrap(), "{c}");
    let p = ok(a, "/api/control", json!({ "action": "power_cycle" }));
    assert_eq!(p["power_ups"], 2);
    // Right after power-up the watchdog is not armed yet: no stall.
    let (status, v) = post(a, "/api/control", json!({ "action": "stall" }));
    assert_eq!(status, 409, "{v}");
    let s = holding(a);
    assert!(s["t_s"].as_f64().unwrap() > p["t_s"].as_f64().unwrap(), "bench time goes on across power-ups");
    let status = serial(a, "status");
    assert!(status[0].starts_with("ok status holding") && status[0].contains("warn copy_damaged"), "{status:?}");

    // The stalled frame loop: the watchdog resets the chip within its 500 ms
    // (plus the bench's tick), and the firmware comes back to its home pose.
    let st = ok(a, "/api/control", json!({ "action": "stall" }));
    assert!(st["stalled_at_s"].as_f64().is_some(), "{st}");
    assert_eq!(get(a, "/api/state")["state"], "stalled");
    let end = Instant::now() + Duration::from_secs(3);
    while get(a, "/api/bench")["watchdog_resets"] != 1 {
        assert!(Instant::now() < end, "no watchdog reset within 3 s");
        std::thread::sleep(Duration::from_millis(50));
    }
    let s = holding(a);
    assert_home(&s, "after the reset: the home pose");
    assert_eq!(get(a, "/api/bench")["stalled"], false);
    bench.stop();
}

/// A move under `path line` is answered only once its plan-time check has
/// decided: for the line from the nearly stretched arm that
/// hal-sim/rig/tests/path_firmware.rs measures (its check's time is in
/// BENCHMARKS.md), seconds later, past the ordinary answer window, and
/// `/api/serial` still returns that answer. And
/// `GET /api/console?since=N` gives every line the firmware sent, numbered:
/// the boot line, the answers, the unsolicited lines, with no gap or
/// repeat between consecutive reads.
#[test]
fn a_checked_move_is_answered_and_the_console_reads_every_line() {
    let bench = start();
    let a = bench.addr();
    holding(a);
    // From the nearly stretched arm (on the IK's branch; home is not:
    // `path pose off IK range`), where the check halves many stretches.
    assert!(serial(a, "goto 0.9 36.82 -0.63")[0].starts_with("ok goto"));
    std::thread::sleep(Duration::from_millis(300));
    holding(a);
    assert_eq!(serial(a, "path line"), ["ok path line"]);
    let t0 = get(a, "/api/state")["t_s"].as_f64().unwrap();
    let replies = serial(a, "goto 81.64 124.21 -138.52");
    let t1 = get(a, "/api/state")["t_s"].as_f64().unwrap();
    assert!(
        replies.len() == 1 && replies[0].starts_with("ok goto") && replies[0].contains(" path line ts_ms "),
        "{replies:?}"
    );
    // The check took longer than the ordinary 1 s answer window
    // (`ANSWER_WINDOW_S` in src/live/serial.rs).
    assert!(t1 - t0 > 1.0, "answered after {:.2} s: was the check run?", t1 - t0);

    let all = get(a, "/api/console?since=0");
    let lines: Vec<&str> = all["lines"].as_array().unwrap().iter().map(|l| l.as_str().unwrap()).collect();
    assert_eq!(all["first"], 0);
    assert_eq!(all["next"].as_u64().unwrap(), lines.len() as u64);
    assert!(lines[0].starts_with("info touch-arm "), "the boot line first: {:?}", &lines[..3]);
    let at = |p: &str| lines.iter().position(|l| l.starts_with(p)).unwrap_or_else(|| panic!("no {p:?} in {lines:?}"));
    assert!(
        at("ok goto ts_ms") < at("ok path line") && at("ok path line") < at("ok goto path line"),
        "in the order sent"
    );
    // Reading on from `next` repeats nothing and skips nothing.
    let n = all["next"].as_u64().unwrap();
    std::thread::sleep(Duration::from_millis(300));
    assert_eq!(serial(a, "version").len(), 1);
    let more = get(a, &format!("/api/console?since={n}"));
    let more_lines = more["lines"].as_array().unwrap();
    assert_eq!(more["next"].as_u64().unwrap(), n + more_lines.len() as u64);
    assert!(more_lines.iter().any(|l| l.as_str().unwrap().starts_with("ok version ")), "{more}");
    let overlap = get(a, &format!("/api/console?since={}", n - 1));
    assert_eq!(overlap["lines"][0].as_str(), lines.last().copied(), "line n - 1 is the last of the first read");
    // Past the end: nothing, and `next` stays where the log ends.
    let past = get(a, "/api/console?since=100000000");
    assert_eq!(past["lines"], json!([]));
    assert!(past["next"].as_u64().unwrap() >= more["next"].as_u64().unwrap());
    let (status, body) = request(a, "GET", "/api/console?since=-3", "", &[]);
    assert!(status == 400 && body.contains("since must be"), "{status} {body}");
    bench.stop();
}

/// `GET /api/layout`: every hit region of every page of the 320×240 screen,
/// exactly, with the 2.8" panel's 0.180 mm per pixel; a press on the
/// centre of the region a script finds by name does what the name says.
#[test]
fn the_layout_lists_every_hit_region_and_a_press_by_name_does_it() {
    let bench = start();
    let a = bench.addr();
    let l = get(a, "/api/layout");
    let r = |name: &str, x: i32, y: i32, w: i32, h: i32| json!({"name": name, "x": x, "y": y, "w": w, "h": h});
    let common = [
        r("map", 0, 0, 224, 112),
        r("stop", 224, 0, 96, 120),
        r("guard", 0, 112, 224, 8),
        r("guard", 52, 188, 15, 52),
        r("guard", 119, 188, 15, 52),
        r("guard", 186, 188, 15, 52),
        r("guard", 253, 188, 15, 52),
    ];
    let page = |names: [&str; 5]| {
        let mut v: Vec<Value> = common.to_vec();
        v.extend(names.iter().enumerate().map(|(i, n)| r(n, 67 * i as i32, 188, 52, 52)));
        // The carer's gesture places, the same on every page.
        v.extend([r("carer_left", 0, 120, 52, 40), r("carer_right", 268, 120, 52, 40)]);
        Value::Array(v)
    };
    let want = json!({
        "width_px": 320,
        "height_px": 240,
        "mm_per_px": 0.18,
        "pages": {
            "main": page(["slow", "normal", "fast", "undo", "more"]),
            "more": page(["pose1", "pose2", "pose3", "pose4", "more"]),
            "setup": page(["grip", "calib", "line", "lift", "back"]),
        }
    });
    assert_eq!(l, want);
    holding(a);
    // The main page's "more", found by name: the page turns.
    let more = l["pages"]["main"].as_array().unwrap().iter().find(|r| r["name"] == "more").unwrap().clone();
    let centre = |r: &Value| {
        (
            r["x"].as_i64().unwrap() + r["w"].as_i64().unwrap() / 2,
            r["y"].as_i64().unwrap() + r["h"].as_i64().unwrap() / 2,
        )
    };
    let (x, y) = centre(&more);
    ok(a, "/api/touch", json!({ "x_px": x, "y_px": y, "ms": 300 }));
    wait_console(a, "info screen page more");
    bench.stop();
}

/// `POST /api/switch`: `{"down": true}` closes the assistive switch (PA0
/// driven low), `{"down": false}` opens it, each answered at once with the
/// bench time; `/api/bench` says which. After `switch on` a press held
/// 0.3 s (over the firmware's 0.10 s hold) in the column sweep fixes a
/// column; a press while the arm moves is STOP. A malformed body is a 400
/// with one line of reason and changes nothing.
#[test]
fn the_switch_endpoint_closes_and_opens_the_switch_and_the_firmware_scans() {
    let bench = start();
    let a = bench.addr();
    holding(a);
    for (body, why) in [
        ("{}", "missing field down"),
        ("{\"down\": 1}", "down must be true or false, got 1"),
        ("{\"down\": true, \"ms\": 200}", "unknown field \"ms\""),
        ("down", "body is not JSON"),
    ] {
        let (status, text) = request(a, "POST", "/api/switch", body, &[]);
        assert_eq!(status, 400, "{body}: {text}");
        let e = serde_json::from_str::<Value>(&text).unwrap()["error"].as_str().unwrap().to_string();
        assert!(e.contains(why) && !e.contains('\n'), "{body}: {e:?} lacks {why:?}");
    }
    assert_eq!(request(a, "GET", "/api/switch", "", &[]).0, 405);
    assert_eq!(get(a, "/api/bench")["switch"], false, "the bad bodies closed nothing");

    let on = serial(a, "switch on");
    assert!(on.len() == 1 && on[0].starts_with("ok switch on sweep 6.00"), "{on:?}");
    let since = get(a, "/api/console?since=0")["next"].as_u64().unwrap();
    let down = ok(a, "/api/switch", json!({ "down": true }));
    assert_eq!(down["down"], true, "{down}");
    assert!(down["t_s"].as_f64().is_some(), "{down}");
    assert_eq!(get(a, "/api/bench")["switch"], true);
    std::thread::sleep(Duration::from_millis(300));
    let up = ok(a, "/api/switch", json!({ "down": false }));
    assert_eq!(up["down"], false, "{up}");
    assert!(up["t_s"].as_f64().unwrap() > down["t_s"].as_f64().unwrap());
    assert_eq!(get(a, "/api/bench")["switch"], false);
    let column = wait_console_prefix(a, since, "info switch column ");
    let x: i64 = column["info switch column ".len()..].parse().unwrap_or_else(|_| panic!("{column:?}"));
    assert!((0..224).contains(&x), "{column}");

    // While the arm moves, a press is STOP.
    let replies = serial(a, "goto 20 150 -30");
    assert!(replies.last().is_some_and(|l| l.starts_with("ok goto")), "{replies:?}");
    wait_state(a, "the arm moves", 2.0, |s| s["state"] == "moving");
    std::thread::sleep(Duration::from_millis(500));
    let since = get(a, "/api/console?since=0")["next"].as_u64().unwrap();
    ok(a, "/api/switch", json!({ "down": true }));
    std::thread::sleep(Duration::from_millis(300));
    ok(a, "/api/switch", json!({ "down": false }));
    wait_console_prefix(a, since, "info switch stop");
    wait_state(a, "the firmware reports stopped", 2.0, |s| s["state"] == "stopped");
    bench.stop();
}

/// Waits (up to 10 s of wall time) for a firmware line from number `since`
/// on that starts with `prefix`; returns it.
fn wait_console_prefix(a: SocketAddr, since: u64, prefix: &str) -> String {
    let t0 = std::time::Instant::now();
    loop {
        let lines = get(a, &format!("/api/console?since={since}"));
        if let Some(l) =
            lines["lines"].as_array().unwrap().iter().filter_map(Value::as_str).find(|l| l.starts_with(prefix))
        {
            return l.to_string();
        }
        assert!(t0.elapsed() < Duration::from_secs(10), "no {prefix:?} in {lines}");
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// Waits (up to 10 s of wall time) for a firmware line `want`.
fn wait_console(a: SocketAddr, want: &str) {
    let t0 = std::time::Instant::now();
    loop {
        let lines = get(a, "/api/console?since=0");
        if lines["lines"].as_array().unwrap().iter().any(|l| l == want) {
            return;
        }
        assert!(t0.elapsed() < Duration::from_secs(10), "no {want:?} in {lines}");
        std::thread::sleep(Duration::from_millis(50));
    }
}

/// `--lcd ili9486 --wiring c` (`Options::lcd`, `Options::wiring`): the
/// 480×320 screen and the mirrored panel wiring, set up as the main job sets
/// them (the calibration wiring c's screen would find, sent at boot). A
/// press on the map still ends at the host's IK target for its pixel, and
/// the geometry and the screen are the larger screen's.
#[test]
fn a_larger_screen_and_wiring_c_still_land_on_the_host_target() {
    let mut opts = Options::new(0, firmware::default_elf(), 7);
    opts.lcd = touch_arm_rig::lcd_bus::Chip::Ili9486;
    opts.wiring = touch_arm_rig::panel::PanelWiring::C;
    let lay = opts.layout();
    let bench = live::start(&opts).expect("live bench (firmware ELF: cargo avr)");
    let a = bench.addr();
    let g = get(a, "/api/geometry");
    assert_eq!(
        (g["screen"].clone(), g["lcd"].clone(), g["wiring"].clone()),
        (json!([480, 320]), json!("ili9486"), json!("c"))
    );
    // The layout is the larger panel's: 480×320 at 0.154 mm per pixel,
    // 83×80 buttons.
    let l = get(a, "/api/layout");
    assert_eq!(
        (l["width_px"].clone(), l["height_px"].clone(), l["mm_per_px"].clone()),
        (json!(480), json!(320), json!(0.154))
    );
    let main = l["pages"]["main"].as_array().unwrap();
    assert_eq!(main[0], json!({"name": "map", "x": 0, "y": 0, "w": 320, "h": 160}));
    assert_eq!(main[7], json!({"name": "slow", "x": 0, "y": 240, "w": 83, "h": 80}));
    assert_eq!(main[12], json!({"name": "carer_left", "x": 0, "y": 168, "w": 80, "h": 48}));
    assert_eq!(main.len(), 14);
    holding(a);
    let (px, py) = lay.ws_point_to_pixel(0.4, 0.6).unwrap();
    assert!(u32::from(lay.width()) > 320 && px >= 0);
    let (x_p, y_p) = lay.ws_pixel_to_point(px, py).unwrap();
    let host = firmware::host_target(f64::from(x_p), f64::from(y_p)).unwrap();
    let r = ok(a, "/api/touch", json!({ "x_px": px, "y_px": py, "ms": 300 }));
    assert_eq!(r["target"]["pulses_us"], json!(host.pulses_us), "{r}");
    wait_state(a, "the pulses reach the host's IK target", 12.0, |s| {
        s["state"] == "holding" && pulses(s).iter().zip(host.pulses_us).all(|(p, t)| (p - t).abs() <= 1.0)
    });
    // The firmware reported the touch where the host put it, through the
    // mirrored calibration: the bench's own reading of the line agrees.
    let lines = get(a, "/api/console?since=0");
    let lines: Vec<&str> = lines["lines"].as_array().unwrap().iter().map(|l| l.as_str().unwrap()).collect();
    assert!(lines.iter().any(|l| l.starts_with("info lcd ili9486")), "{lines:?}");
    assert_eq!(lines.iter().filter(|l| **l == "ok cal set").count(), 7, "the seven calibration lines answered");
    let (status, png) = request_bytes(a, "GET", "/api/screen.png", "", &[]);
    assert_eq!(status, 200);
    // PNG IHDR: width and height, big-endian, at bytes 16..24.
    assert_eq!((&png[16..20], &png[20..24]), (&480u32.to_be_bytes()[..], &320u32.to_be_bytes()[..]));
    bench.stop();
}

/// `POST /api/control {"action": "reset"}`: the RESET pin. The chip
/// restarts with its RAM, so the firmware resumes the pulses the servos had
/// (a moved pose, not home) and says so; it is no watchdog reset.
#[test]
fn an_external_reset_resumes_the_pulses_the_servos_had() {
    let bench = start();
    let a = bench.addr();
    holding(a);
    let replies = serial(a, "goto 60 120 -70");
    assert!(replies.last().is_some_and(|l| l.starts_with("ok goto")), "{replies:?}");
    // 60° 120° −70°: 1200, 1800 and 1700 µs (600 + 10 µs per degree; the elbow 2400 − 700).
    let want = [1200.0, 1800.0, 1700.0];
    let moved = wait_state(a, "the arm arrives", 10.0, |s| {
        s["state"] == "holding" && pulses(s).iter().zip(want).all(|(p, w)| (p - w).abs() < 0.5)
    });
    let r = ok(a, "/api/control", json!({ "action": "reset" }));
    assert_eq!(r["external_resets"], 1, "{r}");
    assert!(r["t_s"].as_f64().unwrap() >= moved["t_s"].as_f64().unwrap());
    assert_eq!(get(a, "/api/state")["state"], "booting");
    holding(a);
    // The reset lands wherever the wall clock puts it, possibly inside a
    // pulse, which it cuts short (as on the board: docs/serial.md, "After a
    // reset"); that short pulse stays the last one measured until the
    // rebooted firmware's first pulses, which are the ones the servos had.
    // (The rig's reset tests check them to the tick.)
    let s = wait_state(a, "the resumed pulses", 3.0, |s| pulses(s).iter().zip(want).all(|(p, w)| (p - w).abs() < 0.5));
    assert_eq!(s["state"], "holding", "{s}");
    let b = get(a, "/api/bench");
    assert_eq!(b["watchdog_resets"], 0, "{b}");
    assert_eq!(b["external_resets"], 1, "{b}");
    let status = serial(a, "status");
    assert!(status[0].starts_with("ok status holding") && status[0].contains("first_move_slow"), "{status:?}");
    bench.stop();
}
