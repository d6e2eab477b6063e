//! The JSON bodies the API accepts, checked field by field, and the
//! screen's regions it reports (`GET /api/layout`). Every refusal
//! is one line that says what is wrong, sent back with a 4xx status; nothing
//! a client sends reaches the simulator unchecked.

use hal_sim::finger::{self, FingerScript, Knot, Track};
use serde_json::{json, Map, Value};
use touch_arm::config::settings::SpeedPreset;
use touch_arm::ui::draw::Area;
use touch_arm::ui::layout::{Layout, SLOTS};
use touch_arm::ui::screen::page_button;
use touch_arm::ui::{Hit, Page};

/// Largest request body read, bytes.
pub const MAX_BODY: usize = 16 * 1024;
/// Largest body of `/api/finger`, bytes: 10 000 samples of four numbers
/// (~40 bytes each as a client writes them).
pub const MAX_FINGER_BODY: usize = 512 * 1024;
/// Longest command line passed to the firmware, bytes. The firmware itself
/// refuses lines over 64 bytes (`err line too long`); a tester may want to
/// see that, so the bench allows more, but not without bound.
pub const MAX_LINE: usize = 256;
/// Longest press of `/api/touch`, ms.
pub const MAX_PRESS_MS: u64 = 60_000;

/// A press at a screen pixel; `ms: None` holds it until released.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Press {
    pub x_px: i16,
    pub y_px: i16,
    pub ms: Option<u64>,
}

/// A tester's fault or power action (`POST /api/control`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    PowerCycle,
    /// The RESET pin: the chip restarts with its RAM (the firmware resumes
    /// the pulses it had, issue #21 §1).
    Reset,
    /// Invert the bits of one EEPROM byte.
    CorruptEeprom {
        addr: u16,
    },
    Noise(bool),
    Stall,
}

/// Most lines one `GET /api/console` returns; a script reads on from `next`.
pub const MAX_CONSOLE_LINES: usize = 5_000;

/// `GET /api/console?since=N`: the query's `since` (0 when absent).
pub fn console_since(query: Option<&str>) -> Result<u64, Refusal> {
    let mut since = 0;
    for pair in query.unwrap_or("").split('&').filter(|p| !p.is_empty()) {
        let (k, v) = pair.split_once('=').unwrap_or((pair, ""));
        match k {
            "since" => {
                since = v.parse().map_err(|_| bad(format!("since must be a line number 0 or more, got {v:?}")))?
            }
            other => return Err(bad(format!("unknown parameter {other:?} (expected since)"))),
        }
    }
    Ok(since)
}

/// A refusal: HTTP status and the one-line reason.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Refusal {
    pub status: u16,
    pub reason: String,
}

pub fn refuse(status: u16, reason: impl Into<String>) -> Refusal {
    Refusal { status, reason: reason.into() }
}

fn bad(reason: impl Into<String>) -> Refusal {
    refuse(400, reason)
}

/// The body as a JSON object with no keys but `allowed`.
fn object(body: &[u8], allowed: &[&str]) -> Result<Map<String, Value>, Refusal> {
    let v: Value = serde_json::from_slice(body).map_err(|e| bad(format!("body is not JSON: {e}")))?;
    let Value::Object(m) = v else { return Err(bad("body must be a JSON object")) };
    if let Some(k) = m.keys().find(|k| !allowed.contains(&k.as_str())) {
        return Err(bad(format!("unknown field {k:?} (expected {})", allowed.join(", "))));
    }
    Ok(m)
}

/// An integer field within `lo..=hi`.
fn int(m: &Map<String, Value>, key: &str, lo: u64, hi: u64) -> Result<Option<u64>, Refusal> {
    let Some(v) = m.get(key) else { return Ok(None) };
    let n = v.as_u64().filter(|n| (lo..=hi).contains(n));
    n.map(Some).ok_or_else(|| bad(format!("{key} must be an integer {lo}..={hi}, got {v}")))
}

fn required(m: &Map<String, Value>, key: &str, lo: u64, hi: u64) -> Result<u64, Refusal> {
    int(m, key, lo, hi)?.ok_or_else(|| bad(format!("missing field {key}")))
}

fn pixel(m: &Map<String, Value>, lay: &Layout) -> Result<(i16, i16), Refusal> {
    let x = required(m, "x_px", 0, u64::from(lay.width()) - 1)?;
    let y = required(m, "y_px", 0, u64::from(lay.height()) - 1)?;
    Ok((x as i16, y as i16))
}

/// The name `GET /api/layout` (and the scenarios' `touch button …`) gives
/// what a press of a button does.
fn hit_name(hit: Hit) -> &'static str {
    match hit {
        Hit::Stop => "stop",
        Hit::Resume => "resume",
        Hit::Speed(SpeedPreset::Slow) => "slow",
        Hit::Speed(SpeedPreset::Normal) => "normal",
        Hit::Speed(SpeedPreset::Fast) => "fast",
        Hit::Undo => "undo",
        Hit::Calibrate => "calib",
        Hit::Page => "more",
        Hit::Pose(1) => "pose1",
        Hit::Pose(2) => "pose2",
        Hit::Pose(3) => "pose3",
        Hit::Pose(_) => "pose4",
        Hit::Grip => "grip",
        Hit::Line => "line",
        Hit::Lift => "lift",
        Hit::Map { .. } => "map",
        Hit::Carer(0) => "carer_left",
        Hit::Carer(_) => "carer_right",
    }
}

/// `GET /api/layout`: `{"width_px": W, "height_px": H, "mm_per_px": f,
/// "pages": {"main"|"more"|"setup": [{"name", "x", "y", "w", "h"}, …]}}`,
/// every hit region of every page: the map, STOP with the guard band
/// beside and below it (where a touch counts as STOP; RESUME, shown in its
/// place after a stop, answers only inside STOP's drawn box), the guard
/// band below the map and the gaps between the buttons (`"guard"`: a touch
/// does nothing), the buttons, and the carer's two gesture places
/// (`"carer_left"`, `"carer_right"`: only a 3 s hold there counts, as a
/// step of the carer's unlock). A pixel in no region (the headline and
/// the status lines) does nothing either.
pub fn layout_json(lay: &Layout, mm_per_px: f64) -> Value {
    let region = |name: &str, a: Area| json!({"name": name, "x": a.x, "y": a.y, "w": a.w, "h": a.h});
    let gaps = lay.gaps();
    let below_map = Area::new(0, gaps[1].y, lay.ws().w, gaps[1].h);
    let mut pages = Map::new();
    for (key, page) in [("main", Page::Main), ("more", Page::More), ("setup", Page::Setup)] {
        let mut r = vec![region("map", lay.ws()), region("stop", lay.stop_hit()), region("guard", below_map)];
        r.extend(gaps[2..].iter().map(|g| region("guard", *g)));
        r.extend((0..SLOTS - 1).map(|i| region(hit_name(page_button(page, i)), lay.slot(i))));
        r.push(region(if page == Page::Setup { "back" } else { "more" }, lay.page_key()));
        r.extend((0..2).map(|k| region(hit_name(Hit::Carer(k)), lay.carer_corner(k))));
        pages.insert(key.into(), Value::Array(r));
    }
    json!({"width_px": lay.width(), "height_px": lay.height(), "mm_per_px": mm_per_px, "pages": pages})
}

/// `POST /api/touch`: `{"x_px": X, "y_px": Y, "ms": M}`.
pub fn touch(body: &[u8], lay: &Layout) -> Result<Press, Refusal> {
    let m = object(body, &["x_px", "y_px", "ms"])?;
    let (x_px, y_px) = pixel(&m, lay)?;
    let ms = required(&m, "ms", 1, MAX_PRESS_MS)?;
    Ok(Press { x_px, y_px, ms: Some(ms) })
}

/// One contact's samples: `[[t_ms, x_px, y_px, force], ...]`.
fn track(m: &Map<String, Value>, key: &str) -> Result<Option<Track>, Refusal> {
    let Some(v) = m.get(key) else { return Ok(None) };
    let rows = v.as_array().ok_or_else(|| bad(format!("{key} must be an array of [t_ms, x_px, y_px, force]")))?;
    if rows.len() > finger::MAX_KNOTS {
        return Err(bad(format!("{key}: {} samples, at most {}", rows.len(), finger::MAX_KNOTS)));
    }
    let mut knots = Vec::with_capacity(rows.len());
    for (i, r) in rows.iter().enumerate() {
        let vals: Option<Vec<f64>> =
            r.as_array().filter(|a| a.len() == 4).map(|a| a.iter().filter_map(Value::as_f64).collect());
        match vals {
            Some(v) if v.len() == 4 => knots.push(Knot::new(v[0], v[1], v[2], v[3])),
            _ => return Err(bad(format!("{key}[{i}] must be [t_ms, x_px, y_px, force] (four numbers), got {r}"))),
        }
    }
    Track::new(knots).map(Some).map_err(|e| bad(format!("{key}: {e}")))
}

/// `POST /api/finger`: `{"samples": [[t_ms, x_px, y_px, force], ...],
/// "second": [[...], ...]}` (`second` optional), a finger script starting
/// now (`hal_sim::finger`): t_ms from 0, force 0 no contact and 1 a firm
/// press, at most 10 000 samples and 60 s.
pub fn finger(body: &[u8]) -> Result<FingerScript, Refusal> {
    let m = object(body, &["samples", "second"])?;
    let first = track(&m, "samples")?.ok_or_else(|| bad("missing field samples"))?;
    let second = track(&m, "second")?;
    FingerScript::new(first, second).map_err(bad)
}

/// `POST /api/press`: `{"x_px": X, "y_px": Y}`, held until `/api/release`
/// (the page's press and drag).
pub fn press(body: &[u8], lay: &Layout) -> Result<Press, Refusal> {
    let m = object(body, &["x_px", "y_px"])?;
    let (x_px, y_px) = pixel(&m, lay)?;
    Ok(Press { x_px, y_px, ms: None })
}

/// `POST /api/release`: an empty object (or no body).
pub fn release(body: &[u8]) -> Result<(), Refusal> {
    if body.iter().all(u8::is_ascii_whitespace) {
        return Ok(());
    }
    object(body, &[]).map(|_| ())
}

/// `POST /api/switch`: `{"down": true | false}`, the assistive switch
/// closed (PA0 driven low) or open; returns `down`.
pub fn switch(body: &[u8]) -> Result<bool, Refusal> {
    let m = object(body, &["down"])?;
    let v = m.get("down").ok_or_else(|| bad("missing field down (true: the switch closed, false: open)"))?;
    v.as_bool().ok_or_else(|| bad(format!("down must be true or false, got {v}")))
}

/// `POST /api/serial`: `{"line": "..."}`, one command line.
pub fn serial(body: &[u8]) -> Result<String, Refusal> {
    let m = object(body, &["line"])?;
    let v = m.get("line").ok_or_else(|| bad("missing field line"))?;
    let line = v.as_str().ok_or_else(|| bad(format!("line must be a string, got {v}")))?;
    if line.contains(['\n', '\r']) {
        return Err(bad("line must be a single line (no CR or LF)"));
    }
    if line.trim().is_empty() {
        // The firmware answers no empty line, so there would be nothing to wait for.
        return Err(bad("line is empty"));
    }
    if line.len() > MAX_LINE {
        return Err(bad(format!("line is {} bytes, at most {MAX_LINE}", line.len())));
    }
    Ok(line.to_string())
}

/// `POST /api/control`: `{"action": "power_cycle" | "reset" | "corrupt_eeprom" |
/// "noise_on" | "noise_off" | "stall", "addr": A}` (`addr` only with
/// `corrupt_eeprom`, default [`DEFAULT_CORRUPT_ADDR`]).
pub fn control(body: &[u8], eeprom_size: u64) -> Result<Control, Refusal> {
    let m = object(body, &["action", "addr"])?;
    let v = m.get("action").ok_or_else(|| bad("missing field action"))?;
    let action = v.as_str().ok_or_else(|| bad(format!("action must be a string, got {v}")))?;
    let c = match action {
        "power_cycle" => Control::PowerCycle,
        "reset" => Control::Reset,
        "corrupt_eeprom" => {
            let addr = int(&m, "addr", 0, eeprom_size - 1)?.unwrap_or(u64::from(DEFAULT_CORRUPT_ADDR));
            return Ok(Control::CorruptEeprom { addr: addr as u16 });
        }
        "noise_on" => Control::Noise(true),
        "noise_off" => Control::Noise(false),
        "stall" => Control::Stall,
        other => {
            return Err(bad(format!(
                "unknown action {other:?} (expected power_cycle, reset, corrupt_eeprom, noise_on, noise_off, stall)"
            )))
        }
    };
    if m.contains_key("addr") {
        return Err(bad("addr goes only with corrupt_eeprom"));
    }
    Ok(c)
}

/// A byte of configuration copy A's joint data (the record starts with the
/// magic, version and sequence: 5 bytes), so corrupting it damages copy A's
/// CRC and the next power-up falls back on copy B.
pub const DEFAULT_CORRUPT_ADDR: u16 = touch_arm::config::store::SLOT_A_ADDR + 5;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::live::LAYOUT;

    fn touch(body: &[u8]) -> Result<Press, Refusal> {
        super::touch(body, &LAYOUT)
    }

    fn press(body: &[u8]) -> Result<Press, Refusal> {
        super::press(body, &LAYOUT)
    }

    #[test]
    fn touch_bodies() {
        assert_eq!(touch(br#"{"x_px": 10, "y_px": 239, "ms": 300}"#), Ok(Press { x_px: 10, y_px: 239, ms: Some(300) }));
        for (body, why) in [
            (&br#"{"x_px": 320, "y_px": 0, "ms": 1}"#[..], "x_px must be an integer 0..=319"),
            (br#"{"x_px": -1, "y_px": 0, "ms": 1}"#, "x_px must be"),
            (br#"{"x_px": 1.5, "y_px": 0, "ms": 1}"#, "x_px must be"),
            (br#"{"x_px": 1, "y_px": 0}"#, "missing field ms"),
            (br#"{"x_px": 1, "y_px": 0, "ms": 0}"#, "ms must be an integer 1..=60000"),
            (br#"{"x_px": 1, "y_px": 0, "ms": 5, "force": 1}"#, "unknown field \"force\""),
            (br#"[1, 2]"#, "body must be a JSON object"),
            (b"x_px=1", "body is not JSON"),
        ] {
            let r = touch(body).unwrap_err();
            assert_eq!(r.status, 400);
            assert!(r.reason.starts_with(why), "{} vs {why}", r.reason);
            assert!(!r.reason.contains('\n'));
        }
        assert_eq!(press(br#"{"x_px": 5, "y_px": 6}"#), Ok(Press { x_px: 5, y_px: 6, ms: None }));
        assert!(release(b"").is_ok() && release(b"{}").is_ok() && release(b"{\"a\":1}").is_err());
    }

    #[test]
    fn console_queries() {
        assert_eq!(console_since(None), Ok(0));
        assert_eq!(console_since(Some("since=17")), Ok(17));
        assert_eq!(console_since(Some("")), Ok(0));
        assert!(console_since(Some("since=-1")).unwrap_err().reason.starts_with("since must be"));
        assert!(console_since(Some("since=x")).is_err());
        assert!(console_since(Some("from=3")).unwrap_err().reason.contains("unknown parameter"));
    }

    #[test]
    fn finger_bodies() {
        let s = finger(br#"{"samples": [[0, 100, 60, 1], [250, 102.5, 60, 1], [250, 102.5, 60, 0]]}"#).unwrap();
        assert_eq!(s.first.knots().len(), 3);
        assert_eq!(s.first.at(125.0), Some((101.25, 60.0, 1.0)));
        assert_eq!(s.second, None);
        let two = finger(
            br#"{"samples": [[0, 10, 10, 1], [100, 10, 10, 1]], "second": [[0, 200, 100, 3], [100, 200, 100, 3]]}"#,
        )
        .unwrap();
        assert_eq!(two.at(50.0)[1], Some((200.0, 100.0, 3.0)));
        let many = format!(r#"{{"samples": [{}]}}"#, vec!["[0, 1, 1, 1]"; 10_001].join(","));
        let split = format!(
            r#"{{"samples": [{}], "second": [{}]}}"#,
            vec!["[0, 1, 1, 1]"; 6000].join(","),
            vec!["[0, 1, 1, 1]"; 6000].join(",")
        );
        for (body, why) in [
            (&br#"{}"#[..], "missing field samples"),
            (br#"{"samples": 5}"#, "samples must be an array of [t_ms, x_px, y_px, force]"),
            (
                br#"{"samples": [[0, 1, 2]]}"#,
                "samples[0] must be [t_ms, x_px, y_px, force] (four numbers), got [0,1,2]",
            ),
            (br#"{"samples": [[0, 1, 2, "x"]]}"#, "samples[0] must be"),
            (br#"{"samples": []}"#, "samples: a track needs at least one sample"),
            (
                br#"{"samples": [[10, 1, 1, 1], [5, 1, 1, 1]]}"#,
                "samples: sample 1: t_ms 5 before the previous sample's 10",
            ),
            (br#"{"samples": [[60001, 1, 1, 1]]}"#, "samples: sample 0: t_ms 60001 outside 0..=60000"),
            (br#"{"samples": [[0, 1, 1, -1]]}"#, "samples: sample 0: force -1 outside 0..=100"),
            (br#"{"samples": [[0, 1, 1, 1]], "second": [[0, 1]]}"#, "second[0] must be"),
            (br#"{"samples": [[0, 1, 1, 1]], "third": []}"#, "unknown field \"third\""),
            (many.as_bytes(), "samples: 10001 samples, at most 10000"),
            (split.as_bytes(), "12000 samples, at most 10000"),
        ] {
            let r = finger(body).unwrap_err();
            assert_eq!(r.status, 400);
            assert!(r.reason.starts_with(why), "{} vs {why}", r.reason);
            assert!(!r.reason.contains('\n'));
        }
    }

    #[test]
    fn switch_bodies() {
        assert_eq!(switch(br#"{"down": true}"#), Ok(true));
        assert_eq!(switch(br#"{"down": false}"#), Ok(false));
        for (body, why) in [
            (&br#"{}"#[..], "missing field down"),
            (br#"{"down": 1}"#, "down must be true or false, got 1"),
            (br#"{"down": "true"}"#, "down must be true or false, got \"true\""),
            (br#"{"down": true, "ms": 5}"#, "unknown field \"ms\" (expected down)"),
            (b"down", "body is not JSON"),
            (b"", "body is not JSON"),
        ] {
            let r = switch(body).unwrap_err();
            assert_eq!(r.status, 400);
            assert!(r.reason.starts_with(why), "{} vs {why}", r.reason);
            assert!(!r.reason.contains('\n'));
        }
    }

    #[test]
    fn serial_and_control_bodies() {
        assert_eq!(serial(br#"{"line": "status"}"#), Ok("status".to_string()));
        assert!(serial(br#"{"line": "stop\nresume"}"#).unwrap_err().reason.contains("single line"));
        assert!(serial(br#"{"line": "   "}"#).unwrap_err().reason.contains("empty"));
        assert!(serial(br#"{"line": 5}"#).unwrap_err().reason.contains("string"));
        let long = format!(r#"{{"line": "{}"}}"#, "a".repeat(MAX_LINE + 1));
        assert!(serial(long.as_bytes()).is_err());
        assert_eq!(control(br#"{"action": "stall"}"#, 4096), Ok(Control::Stall));
        assert_eq!(control(br#"{"action": "reset"}"#, 4096), Ok(Control::Reset));
        assert!(control(br#"{"action": "Reset"}"#, 4096).is_err());
        assert_eq!(control(br#"{"action": "corrupt_eeprom"}"#, 4096), Ok(Control::CorruptEeprom { addr: 5 }));
        assert_eq!(
            control(br#"{"action": "corrupt_eeprom", "addr": 4095}"#, 4096),
            Ok(Control::CorruptEeprom { addr: 4095 })
        );
        assert!(control(br#"{"action": "corrupt_eeprom", "addr": 4096}"#, 4096).is_err());
        assert!(control(br#"{"action": "stall", "addr": 1}"#, 4096).is_err());
        assert!(control(br#"{"action": "explode"}"#, 4096).unwrap_err().reason.contains("unknown action"));
    }
}
