//! Who each line from the firmware's USART0 is for.
//!
//! The firmware answers every non-empty command line with exactly one `ok …`
//! or `err <reason>` line, in order (`cal show` sends its `cal …` lines
//! first), and sends other lines on its own: `info …`, `warn …`, `err touch …`,
//! `err cal touch …`, `err screen …` and the `t …` telemetry. So the answers
//! are matched to the commands in flight first in, first out.
//!
//! A command that plans a move (`move`, `goto`, `pose go`, `circle`, `park`) is
//! answered only once the plan-time check of a line, circle or lift has
//! decided (docs/serial.md, "Path and lift moves"): seconds for a line near
//! the rim. Its answer window is [`CHECK_WINDOW_S`] instead of
//! [`ANSWER_WINDOW_S`], so `/api/serial` returns that answer, not an empty
//! list (the answer usually comes at once, and then so does the reply).
//!
//! Besides the user's commands the bench sends its own `status` every
//! [`STATUS_PERIOD_S`], only when nothing else is in flight: the firmware's
//! state word (holding, moving, stopped…) exists nowhere else outside the
//! chip. Those replies are kept off the console.

use std::collections::VecDeque;
use std::sync::mpsc::Sender;

/// How often the bench asks for `status`, simulated seconds.
pub const STATUS_PERIOD_S: f64 = 0.1;
/// How long an API client waits for its answer, simulated seconds.
pub const ANSWER_WINDOW_S: f64 = 1.0;
/// How long a client waits for the answer to a command that may wait for a
/// plan-time check, simulated seconds: well above the longest check the
/// benchmark has (the rim line's, in BENCHMARKS.md).
pub const CHECK_WINDOW_S: f64 = 30.0;
/// A command still unanswered this long after its window closed is given
/// up (its answer, if it ever comes, then shows on the console only).
pub const FORGET_AFTER_S: f64 = 2.0;

/// Command words whose answer may wait for a plan-time check.
const PLANNING: [&str; 5] = ["move", "goto", "pose", "circle", "park"];

/// The answer window of a command line, simulated seconds: its first word
/// decides (case-insensitive, as the firmware reads it).
pub fn answer_window_s(line: &str) -> f64 {
    let word = line.split_whitespace().next().unwrap_or("");
    if PLANNING.iter().any(|w| w.eq_ignore_ascii_case(word)) {
        CHECK_WINDOW_S
    } else {
        ANSWER_WINDOW_S
    }
}

/// Lines the firmware sends unasked (see the module docs).
pub fn unsolicited(line: &str) -> bool {
    ["info ", "warn ", "t ", "err touch ", "err cal touch ", "err screen "].iter().any(|p| line.starts_with(p))
}

fn ends_answer(line: &str) -> bool {
    (line == "ok" || line.starts_with("ok ") || line == "err" || line.starts_with("err ")) && !unsolicited(line)
}

enum Asker {
    /// The bench's own `status`.
    Bench,
    /// A client; `None` once it got what arrived within its window.
    Client(Option<Sender<Vec<String>>>),
}

struct InFlight {
    asker: Asker,
    sent_s: f64,
    /// Its answer window ([`answer_window_s`]).
    window_s: f64,
    lines: Vec<String>,
}

/// What one line from the firmware means to the bench.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Routed {
    /// Show it on the console.
    pub console: bool,
    /// The firmware's state word, from an `ok status <word> …` line.
    pub state: Option<String>,
}

#[derive(Default)]
pub struct SerialRouter {
    in_flight: VecDeque<InFlight>,
    last_status_s: f64,
}

impl SerialRouter {
    /// A client's command line: the bytes to send; `reply` gets the answer.
    pub fn client_line(&mut self, line: &str, reply: Sender<Vec<String>>, now_s: f64) -> Vec<u8> {
        let window_s = answer_window_s(line);
        self.in_flight.push_back(InFlight {
            asker: Asker::Client(Some(reply)),
            sent_s: now_s,
            window_s,
            lines: Vec::new(),
        });
        format!("{line}\n").into_bytes()
    }

    /// Whether nothing is in flight.
    pub fn idle(&self) -> bool {
        self.in_flight.is_empty()
    }

    /// A line the bench itself sends (its answer stays off the console).
    pub fn bench_line(&mut self, line: &str, now_s: f64) -> Vec<u8> {
        self.in_flight.push_back(InFlight {
            asker: Asker::Bench,
            sent_s: now_s,
            window_s: ANSWER_WINDOW_S,
            lines: Vec::new(),
        });
        format!("{line}\n").into_bytes()
    }

    /// The bench's own `status`, when one is due and the line is free.
    pub fn poll_status(&mut self, now_s: f64, line_free: bool) -> Option<Vec<u8>> {
        if !line_free || !self.in_flight.is_empty() || now_s - self.last_status_s < STATUS_PERIOD_S {
            return None;
        }
        self.last_status_s = now_s;
        self.in_flight.push_back(InFlight {
            asker: Asker::Bench,
            sent_s: now_s,
            window_s: ANSWER_WINDOW_S,
            lines: Vec::new(),
        });
        Some(b"status\n".to_vec())
    }

    /// One complete line from the firmware.
    pub fn on_line(&mut self, line: &str) -> Routed {
        let state = line.strip_prefix("ok status ").and_then(|r| r.split_whitespace().next()).map(str::to_string);
        if unsolicited(line) {
            return Routed { console: true, state };
        }
        let Some(head) = self.in_flight.front_mut() else {
            return Routed { console: true, state };
        };
        let console = matches!(head.asker, Asker::Client(_));
        head.lines.push(line.to_string());
        if ends_answer(line) {
            if let Some(done) = self.in_flight.pop_front() {
                if let Asker::Client(Some(tx)) = done.asker {
                    // The client may have gone: nothing to do then.
                    let _ = tx.send(done.lines);
                }
            }
        }
        Routed { console, state }
    }

    /// Answers clients whose window closed with what arrived so far, and
    /// gives up commands unanswered for too long.
    pub fn expire(&mut self, now_s: f64) {
        for f in self.in_flight.iter_mut() {
            if now_s - f.sent_s >= f.window_s {
                if let Asker::Client(tx) = &mut f.asker {
                    if let Some(tx) = tx.take() {
                        let _ = tx.send(f.lines.clone());
                    }
                }
            }
        }
        while self.in_flight.front().is_some_and(|f| now_s - f.sent_s >= f.window_s + FORGET_AFTER_S) {
            self.in_flight.pop_front();
        }
    }

    /// The firmware restarted (power cycle, watchdog): nothing in flight
    /// will be answered. Clients get what they have.
    pub fn reset(&mut self, now_s: f64) {
        for f in self.in_flight.drain(..) {
            if let Asker::Client(Some(tx)) = f.asker {
                let _ = tx.send(f.lines);
            }
        }
        self.last_status_s = now_s;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::mpsc::channel;

    #[test]
    fn answers_go_to_their_askers_in_order_and_bench_status_stays_hidden() {
        let mut r = SerialRouter::default();
        assert_eq!(r.poll_status(1.0, true), Some(b"status\n".to_vec()));
        let (tx, rx) = channel();
        assert_eq!(r.client_line("cal show", tx, 1.01), b"cal show\n");
        // The bench's status answer: hidden, but its state word is read.
        assert_eq!(r.on_line("ok status holding law zat"), Routed { console: false, state: Some("holding".into()) });
        // Unsolicited lines in between go to the console only.
        assert_eq!(r.on_line("t 100 9000 9000 -9000 1500 1500 1500"), Routed { console: true, state: None });
        assert_eq!(r.on_line("err touch 10 20 unreachable"), Routed { console: true, state: None });
        assert!(r.on_line("cal base offset 600").console);
        assert!(r.on_line("ok cal show law zat speed normal mode tap").console);
        assert_eq!(
            rx.recv().unwrap(),
            vec!["cal base offset 600".to_string(), "ok cal show law zat speed normal mode tap".into()]
        );
        // No status too soon after the last, nor while the line is busy.
        assert_eq!(r.poll_status(1.05, true), None);
        assert_eq!(r.poll_status(1.3, false), None);
        assert!(r.poll_status(1.3, true).is_some());
    }

    #[test]
    fn an_unanswered_client_gets_what_arrived_and_a_late_answer_is_still_matched() {
        let mut r = SerialRouter::default();
        let (tx, rx) = channel();
        r.client_line("cal show", tx, 0.0);
        r.on_line("cal base offset 600");
        r.expire(1.0);
        assert_eq!(rx.recv().unwrap(), vec!["cal base offset 600".to_string()]);
        // The late terminator still belongs to that command, not the next one.
        let (tx2, rx2) = channel();
        r.client_line("stop", tx2, 1.5);
        r.on_line("ok cal show");
        r.on_line("ok stop");
        assert_eq!(rx2.recv().unwrap(), vec!["ok stop".to_string()]);
        // Forgotten FORGET_AFTER_S after its window; a reset answers whatever is left.
        let (tx3, rx3) = channel();
        r.client_line("status", tx3, 2.0);
        r.reset(2.1);
        assert_eq!(rx3.recv().unwrap(), Vec::<String>::new());
    }

    #[test]
    fn a_planning_command_waits_for_its_check_and_others_do_not() {
        assert_eq!(answer_window_s("status"), ANSWER_WINDOW_S);
        assert_eq!(answer_window_s("GOTO 10 20 30"), CHECK_WINDOW_S);
        assert_eq!(answer_window_s("pose go 2"), CHECK_WINDOW_S);
        assert_eq!(answer_window_s("park"), CHECK_WINDOW_S);
        assert_eq!(answer_window_s("circle 0.2"), CHECK_WINDOW_S);
        assert_eq!(answer_window_s("path line"), ANSWER_WINDOW_S);
        let mut r = SerialRouter::default();
        let (tx, rx) = channel();
        r.client_line("move 500 400", tx, 0.0);
        // The check runs for seconds; lines the firmware sends meanwhile are
        // unsolicited, and the window stays open past the ordinary one.
        r.on_line("info touch 1 2 cond 1");
        r.expire(ANSWER_WINDOW_S + 5.0);
        assert!(rx.try_recv().is_err(), "answered before the check decided");
        r.on_line("ok move 500 400 path line ts_ms 1864");
        assert_eq!(rx.recv().unwrap(), vec!["ok move 500 400 path line ts_ms 1864".to_string()]);
        // A check that never answers: the client hears at the window's end.
        let (tx, rx) = channel();
        r.client_line("circle 0.2", tx, 10.0);
        r.expire(10.0 + CHECK_WINDOW_S - 0.1);
        assert!(rx.try_recv().is_err());
        r.expire(10.0 + CHECK_WINDOW_S);
        assert_eq!(rx.recv().unwrap(), Vec::<String>::new());
    }
}
