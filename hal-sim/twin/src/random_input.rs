//! Seeded random input for the firmware's own random testing (issue #11):
//! serial lines valid and garbage, touches, and the rule that counts the
//! replies a line must get. Shared by the twin's random test
//! (`tests/random_inputs.rs`) and the soak of the real ELF in simavr
//! (`hal-sim/rig/tests/firmware_soak.rs`).
//!
//! Every generated line ends with a terminator and holds no backspace, so
//! "non-empty" is simply "has a byte before its terminator": each such line
//! must get exactly one reply (README, serial interface).

use crate::rng::Rng;

/// The generator. The same seed gives the same inputs.
pub struct Inputs {
    /// The seeded generator every draw comes from (tests may draw from it directly).
    pub rng: Rng,
}

const LAWS: [&str; 5] = ["zat", "quintic", "cubic", "trapezoid", "linear"];
const SPEEDS: [&str; 3] = ["slow", "normal", "fast"];
const JOINTS: [&str; 3] = ["base", "shoulder", "elbow"];
const TERMINATORS: [&[u8]; 3] = [b"\n", b"\r", b"\r\n"];

/// A serial line: its bytes (terminator included) and whether it must be
/// answered (it is not empty).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SerialLine {
    /// The line's bytes, terminator included.
    pub bytes: Vec<u8>,
    /// The app must reply to it: the line is not empty.
    pub answered: bool,
}

impl Inputs {
    /// A generator whose inputs follow from `seed` alone.
    pub fn new(seed: u64) -> Self {
        Inputs { rng: Rng::new(seed) }
    }

    fn pick<'a, T: ?Sized>(&mut self, items: &[&'a T]) -> &'a T {
        items[self.rng.below(items.len() as u64) as usize]
    }

    fn int(&mut self, lo: i64, hi: i64) -> i64 {
        lo + self.rng.below((hi - lo + 1) as u64) as i64
    }

    /// A decimal with 0..=2 places in `[lo, hi]`.
    fn decimal(&mut self, lo: f64, hi: f64) -> String {
        let v = lo + self.rng.uniform() * (hi - lo);
        match self.rng.below(3) {
            0 => format!("{}", v.round() as i64),
            1 => format!("{v:.1}"),
            _ => format!("{v:.2}"),
        }
    }

    /// A command of the README's grammar, with arguments mostly plausible
    /// and sometimes out of range (the app must refuse those).
    pub fn command(&mut self) -> String {
        match self.rng.below(29) {
            0..=3 => format!("move {} {}", self.int(0, 1023), self.int(0, 1023)),
            4..=6 => {
                let (b, s, e) = (self.decimal(-5.0, 185.0), self.decimal(-5.0, 185.0), self.decimal(-185.0, 5.0));
                format!("goto {b} {s} {e}")
            }
            // Near the rim: the arm almost stretched, where a path's joint
            // rates grow like 1/sin θ₃ (issue #24, F4).
            7 => {
                let (b, s, e) = (self.decimal(0.0, 180.0), self.decimal(0.0, 150.0), self.decimal(-12.0, -0.2));
                format!("goto {b} {s} {e}")
            }
            8 => "stop".into(),
            9 => "resume".into(),
            10 | 11 => "status".into(),
            12 => format!("law {}", self.pick(&LAWS)),
            13 => format!("speed {}", self.pick(&SPEEDS)),
            14 => "cal show".into(),
            15 => "cal save".into(),
            16 => "cal reset".into(),
            17 => format!("log {}", if self.rng.below(2) == 0 { "on" } else { "off" }),
            // Issue #13's path and lift moves (their checks span frames).
            18 => format!("path {}", if self.rng.below(2) == 0 { "line" } else { "joint" }),
            19 => match self.rng.below(3) {
                0 => "lift off".into(),
                _ => format!("lift {}", self.decimal(0.0, 0.6)),
            },
            20 => format!(
                "circle {}",
                if self.rng.below(2) == 0 { self.decimal(0.0, 0.6) } else { self.decimal(0.0, 0.15) }
            ),
            // Issue #14's gripper and saved poses.
            21 => match self.rng.below(3) {
                0 => "grip open".into(),
                1 => "grip close".into(),
                _ => format!("grip {}", self.decimal(-10.0, 100.0)),
            },
            22 => self.cal_set_grip(),
            23 => format!("pose {} {}", self.pick(&["save", "go", "go", "clear"]), self.int(1, 4)),
            // Issue #21 §4's arm: link lengths (some out of range or over 4x
            // apart), home and park poses (some outside the limits), park.
            24 => match self.rng.below(4) {
                0 => format!("cal set arm {} {}", self.pick(&["l2", "l3"]), self.decimal(5.0, 700.0)),
                1 => format!("cal set arm {} {}", self.pick(&["l2", "l3"]), self.decimal(60.0, 160.0)),
                _ => {
                    let (b, s, e) = (self.decimal(-5.0, 185.0), self.decimal(-5.0, 185.0), self.decimal(-185.0, 5.0));
                    format!("cal set {} {b} {s} {e}", self.pick(&["home", "park"]))
                }
            },
            25 => "park".into(),
            // Issue #20 §2: undo.
            26 => "undo".into(),
            _ => self.cal_set(),
        }
    }

    /// A gripper calibration change around its defaults (0..90 deg over
    /// 600..1500 us).
    fn cal_set_grip(&mut self) -> String {
        let (field, v) = match self.rng.below(6) {
            0 => ("offset", self.decimal(550.0, 650.0)),
            1 => ("scale", self.decimal(8.0, 12.0)),
            2 => ("min_us", self.int(500, 700).to_string()),
            3 => ("max_us", self.int(1300, 2000).to_string()),
            4 => ("max_deg", self.decimal(40.0, 120.0)),
            _ => ("max_speed", self.decimal(5.0, 400.0)),
        };
        format!("cal set grip {field} {v}")
    }

    fn cal_set(&mut self) -> String {
        if self.rng.below(4) == 0 {
            let (field, v) = match self.rng.below(7) {
                0 => ("x_min", self.int(0, 400)),
                1 => ("x_max", self.int(600, 1023)),
                2 => ("y_min", self.int(0, 400)),
                3 => ("y_max", self.int(600, 1023)),
                4 => ("swap", self.int(0, 1)),
                5 => ("invert_x", self.int(0, 1)),
                _ => ("invert_y", self.int(0, 1)),
            };
            return format!("cal set touch {field} {v}");
        }
        let joint = self.pick(&JOINTS);
        let elbow = joint == "elbow";
        let (field, v) = match self.rng.below(9) {
            0 => ("offset", if elbow { self.decimal(2300.0, 2500.0) } else { self.decimal(500.0, 700.0) }),
            1 => ("scale", self.decimal(8.0, 12.0)),
            2 => ("min_us", self.int(500, 1200).to_string()),
            3 => ("max_us", self.int(1800, 2500).to_string()),
            // Pulse limits well inside the angle limits (an ordinary
            // calibration of a servo with less travel): the output window
            // ends inside the workspace (issue #24, F1).
            7 => ("min_us", self.int(600, 1700).to_string()),
            8 => ("max_us", self.int(1300, 2400).to_string()),
            4 => ("min_deg", if elbow { self.decimal(-200.0, -150.0) } else { self.decimal(-20.0, 30.0) }),
            5 => ("max_deg", if elbow { self.decimal(-30.0, 20.0) } else { self.decimal(150.0, 200.0) }),
            _ => ("max_speed", self.decimal(5.0, 400.0)),
        };
        format!("cal set {joint} {field} {v}")
    }

    /// Lines that set up a path or lift move and start one (issue #24, F3:
    /// `pose go` under `path line` and a lift), with no frame between.
    pub fn path_burst(&mut self) -> Vec<String> {
        let mode = match self.rng.below(3) {
            0 => "path line".to_string(),
            1 => format!("lift {}", self.decimal(0.01, 0.4)),
            _ => "path joint".to_string(),
        };
        let go = match self.rng.below(3) {
            0 => format!("circle {}", self.decimal(0.01, 0.3)),
            _ => format!("pose go {}", self.int(1, 4)),
        };
        vec![mode, go]
    }

    /// Bytes that are mostly not a command: random printable words, control
    /// bytes, high bytes, runs of spaces, over-long lines.
    pub fn garbage(&mut self) -> Vec<u8> {
        let len = match self.rng.below(6) {
            0 => 65 + self.rng.below(100) as usize,
            1 => self.rng.below(4) as usize,
            _ => self.rng.below(40) as usize,
        };
        (0..len)
            .map(|_| loop {
                let b = match self.rng.below(10) {
                    0 => self.rng.below(32) as u8,
                    1 => 0x80 + self.rng.below(128) as u8,
                    2 | 3 => b' ',
                    _ => 0x21 + self.rng.below(94) as u8,
                };
                // Not `!` either: the one-byte STOP is a command of its own
                // (stop_byte.scn), answered `ok stop` outside any line.
                if !matches!(b, b'\r' | b'\n' | 0x08 | 0x7F | b'!') {
                    break b;
                }
            })
            .collect()
    }

    /// One line: a command (4 in 5) or garbage, with a random terminator.
    pub fn line(&mut self) -> SerialLine {
        let mut bytes = if self.rng.below(5) == 0 { self.garbage() } else { self.command().into_bytes() };
        let answered = !bytes.is_empty();
        bytes.extend_from_slice(self.pick(&TERMINATORS));
        SerialLine { bytes, answered }
    }

    /// A press on the panel: a raw reading (x, y), the finger's force and how
    /// many 20 ms frames it stays down.
    pub fn touch(&mut self) -> (f64, f64, f64, u64) {
        let x = self.rng.uniform() * 1023.0;
        let y = self.rng.uniform() * 1023.0;
        let force = 0.3 + self.rng.uniform() * 1.5;
        (x, y, force, 1 + self.rng.below(40))
    }
}

/// How many lines an output line answers: 1 for a reply (`ok …`, `err …`),
/// n for `err input lost: <n> lines`, 0 for everything the app sends
/// unasked (`info …`, `warn …`, telemetry, `cal …` data lines, and the
/// touch and screen errors `err touch …`, `err screen …`, `err cal touch …`).
pub fn replies_in(line: &str) -> u64 {
    if let Some(rest) = line.strip_prefix("err input lost: ") {
        return rest.split_whitespace().next().and_then(|n| n.parse().ok()).unwrap_or(0);
    }
    let unsolicited = ["err touch ", "err screen ", "err cal touch "];
    if line.starts_with("ok ") || (line.starts_with("err ") && !unsolicited.iter().any(|p| line.starts_with(p))) {
        1
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn replies_are_counted_by_the_readme_rule() {
        assert_eq!(replies_in("ok status holding law zat"), 1);
        assert_eq!(replies_in("err bad number"), 1);
        assert_eq!(replies_in("err input lost: 12 lines"), 12);
        assert_eq!(replies_in("err touch 10 20 unreachable"), 0);
        assert_eq!(replies_in("info touch 10 20 cond 1"), 0);
        assert_eq!(replies_in("cal base offset 600.00"), 0);
        assert_eq!(replies_in("t 20 9000 9000 -9000 1500 1500 1500"), 0);
        let mut g = Inputs::new(3);
        for _ in 0..1000 {
            let l = g.line();
            assert!(matches!(l.bytes.last(), Some(b'\n' | b'\r')));
            let body = l.bytes.iter().take_while(|b| !matches!(b, b'\r' | b'\n')).count();
            assert_eq!(l.answered, body > 0);
            assert!(!l.bytes.contains(&0x08) && !l.bytes.contains(&0x7F));
        }
    }
}
