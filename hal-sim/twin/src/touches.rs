//! What the firmware did with a touch, read from its own serial lines
//! (docs/serial.md), tolerantly: today's lines and the lines of the touch
//! logic of issue #19 (`info screen cancel`, `info screen ignored <why>`)
//! alike. Shared by the main job's `summary.json` (`touches`) and the
//! twin's touch Monte Carlo ([`crate::touch_mc`]).
//!
//! | line | action | point |
//! |---|---|---|
//! | `info touch <x> <y> …` | `move` | raw (x, y) |
//! | `err touch <x> <y> <reason>` | `ignored` (a refused map touch: nothing moves) | raw (x, y) |
//! | `info screen stop` / `resume` / `cancel` | `stop` / `resume` / `cancel` | none |
//! | `info screen ignored <why>` | `ignored` | none |
//! | `info screen <word> …`, `err screen <word> …` | `<word>` (speed, page, pose, grip, path, lift, calibrate, …) | none |
//!
//! Anything else (`err touch wiring …`, `info touch-arm …`, replies) is no
//! touch action.

/// One action the firmware took on a touch.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TouchAction {
    /// `move`, `stop`, `resume`, `cancel`, `ignored` or the button's word.
    pub action: String,
    /// The raw panel reading the action was taken at (ADC counts), for the
    /// lines that carry one.
    pub raw: Option<(u16, u16)>,
    /// The `<why>` of `info screen ignored <why>`, or the reason of `err touch`.
    pub why: Option<String>,
}

/// The touch action of one serial line, if it is one.
pub fn touch_action(line: &str) -> Option<TouchAction> {
    let w: Vec<&str> = line.split_whitespace().collect();
    let act =
        |a: &str, raw, why: Option<&str>| Some(TouchAction { action: a.to_string(), raw, why: why.map(String::from) });
    let point = |x: &str, y: &str| Some((x.parse::<u16>().ok()?, y.parse::<u16>().ok()?));
    match w[..] {
        ["info", "touch", x, y, ..] => act("move", Some(point(x, y)?), None),
        ["err", "touch", x, y, ref why @ ..] => {
            let raw = point(x, y)?;
            let why = why.join(" ");
            act("ignored", Some(raw), (!why.is_empty()).then_some(why.as_str()))
        }
        ["info", "screen", "ignored", ref why @ ..] => {
            let why = why.join(" ");
            act("ignored", None, (!why.is_empty()).then_some(why.as_str()))
        }
        ["info" | "err", "screen", word, ..] => act(word, None, None),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lines_of_today_and_of_the_new_touch_logic() {
        let a = |l| touch_action(l).map(|t| (t.action, t.raw, t.why));
        let s = |v: &str| v.to_string();
        assert_eq!(a("info touch 612 700 cond 2 ts_ms 840 vend 0 0 0"), Some((s("move"), Some((612, 700)), None)));
        assert_eq!(
            a("err touch 130 880 outside workspace"),
            Some((s("ignored"), Some((130, 880)), Some(s("outside workspace"))))
        );
        assert_eq!(a("info screen stop"), Some((s("stop"), None, None)));
        assert_eq!(a("info screen resume"), Some((s("resume"), None, None)));
        assert_eq!(a("info screen cancel"), Some((s("cancel"), None, None)));
        assert_eq!(a("info screen ignored hand"), Some((s("ignored"), None, Some(s("hand")))));
        assert_eq!(a("info screen ignored"), Some((s("ignored"), None, None)));
        assert_eq!(a("info screen speed fast"), Some((s("speed"), None, None)));
        assert_eq!(a("info screen pose go 2 ts_ms 900 vend 0 0 0"), Some((s("pose"), None, None)));
        assert_eq!(a("err screen grip busy moving"), Some((s("grip"), None, None)));
        assert_eq!(a("info screen page more"), Some((s("page"), None, None)));
        for other in [
            "info touch-arm 0.2.0 commit abc reset power-on",
            "err touch wiring unknown plates 0x3 open 0x0",
            "info touch",
            "ok move cond 2 ts_ms 100 vend 0 0 0",
            "info wiring a",
            "",
        ] {
            assert_eq!(touch_action(other), None, "{other:?}");
        }
    }
}
