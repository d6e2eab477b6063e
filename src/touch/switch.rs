//! The assistive switch (issue #20 §4): one normally open contact to ground,
//! sampled once per frame, turned into presses by the panel's own rules, as
//! pure logic (the board reads the pin, `app::switch` acts).
//!
//! - **Bounce:** a contact chatters for a few milliseconds when it closes
//!   and opens. A down that reads up for fewer than `release_confirm`
//!   consecutive samples is still down (the panel's release rule), so a
//!   chatter of one frame neither ends a press nor starts a new one.
//! - **Hold:** a press counts once the switch has stayed down `hold` (the
//!   panel's `hold` setting): a knock or a spasm shorter than that is no
//!   press. It counts on reaching the hold, not at the release, so a user
//!   who cannot let go quickly is not slowed down (Apple's Switch Control
//!   "hold duration").
//! - **Repeat:** a down that starts within `repeat` of the last release is
//!   ignored as a whole (the panel's `repeat`; Switch Control's "ignore
//!   repeat"): the second hit of a tremor's double press.

/// The press rules' numbers (the touch settings, in ms).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SwitchRules {
    /// Down this long before a press counts.
    pub hold_ms: u32,
    /// A down starting within this of the last release is ignored.
    pub repeat_ms: u32,
    /// Consecutive up samples that end a down (at least 1).
    pub release_confirm: u8,
}

/// What one sample made of the switch.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SwitchEvent {
    /// The switch has been down `hold`: a press (once per down).
    Pressed,
    /// A down started within `repeat` of the last release: ignored.
    Repeat,
    /// The switch opened (debounced) after a down, press or not.
    Released,
}

/// The debounced switch (12 bytes: one field of the app, in the chip's
/// last free RAM; flags instead of `Option`s, which would double the times).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Switch {
    /// The current down's first sample, ms (while `down`).
    since: u32,
    /// The last release, ms (once `released_once`).
    released: u32,
    down: bool,
    released_once: bool,
    /// Up samples in a row during a down.
    ups: u8,
    /// This down has already pressed, or was a repeat: nothing more.
    spent: bool,
}

impl Switch {
    /// Up, never pressed.
    pub const IDLE: Switch = Switch { since: 0, released: 0, down: false, released_once: false, ups: 0, spent: false };

    /// One sample at `now_ms`: `down` is the contact closed.
    pub fn update(&mut self, down: bool, now_ms: u32, rules: &SwitchRules) -> Option<SwitchEvent> {
        if !self.down {
            if !down {
                return None;
            }
            self.down = true;
            self.since = now_ms;
            self.ups = 0;
            let repeat = self.released_once && now_ms.wrapping_sub(self.released) < rules.repeat_ms;
            self.spent = repeat;
            return if repeat { Some(SwitchEvent::Repeat) } else { self.held(now_ms, rules) };
        }
        if !down {
            self.ups = self.ups.saturating_add(1);
            if self.ups < rules.release_confirm.max(1) {
                return None;
            }
            self.down = false;
            self.released_once = true;
            self.released = now_ms;
            return Some(SwitchEvent::Released);
        }
        self.ups = 0;
        self.held(now_ms, rules)
    }

    /// A press once the current down reaches the hold.
    fn held(&mut self, now_ms: u32, rules: &SwitchRules) -> Option<SwitchEvent> {
        if self.spent || now_ms.wrapping_sub(self.since) < rules.hold_ms {
            return None;
        }
        self.spent = true;
        Some(SwitchEvent::Pressed)
    }

    /// The switch is down (debounced).
    pub fn is_down(&self) -> bool {
        self.down
    }

    /// How long the current down has lasted at `now_ms` (0 while up).
    pub fn down_ms(&self, now_ms: u32) -> u32 {
        if self.down {
            now_ms.wrapping_sub(self.since)
        } else {
            0
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use std::vec;
    use std::vec::Vec;

    const RULES: SwitchRules = SwitchRules { hold_ms: 100, repeat_ms: 200, release_confirm: 2 };

    /// Samples every 20 ms from t = 0; the events with their times.
    fn run(levels: &[bool]) -> Vec<(u32, SwitchEvent)> {
        let mut s = Switch::IDLE;
        let mut out = Vec::new();
        for (i, &d) in levels.iter().enumerate() {
            let t = 20 * i as u32;
            if let Some(e) = s.update(d, t, &RULES) {
                out.push((t, e));
            }
        }
        out
    }

    fn pattern(s: &str) -> Vec<bool> {
        s.bytes().map(|b| b == b'#').collect()
    }

    #[test]
    fn a_press_counts_once_on_reaching_the_hold() {
        // Down at 0; 100 ms of down is reached at the sixth sample (t = 100).
        let ev = run(&pattern("##########.."));
        assert_eq!(ev, vec![(100, SwitchEvent::Pressed), (220, SwitchEvent::Released)]);
    }

    #[test]
    fn a_knock_shorter_than_the_hold_is_no_press() {
        // 80 ms down (t = 0..=60 read down), then up.
        let ev = run(&pattern("####......"));
        assert_eq!(ev, vec![(100, SwitchEvent::Released)]);
    }

    #[test]
    fn one_frame_of_chatter_neither_ends_nor_restarts_a_press() {
        let ev = run(&pattern("###.######..."));
        assert_eq!(ev, vec![(100, SwitchEvent::Pressed), (220, SwitchEvent::Released)]);
    }

    #[test]
    fn a_down_within_repeat_of_the_release_is_ignored_whole() {
        // Released at t = 160 (two ups at 140, 160); down again at 200 (40 ms
        // later, within 200 ms) and held long: ignored, no press at all.
        let ev = run(&pattern("#######..##########.."));
        assert_eq!(
            ev,
            vec![
                (100, SwitchEvent::Pressed),
                (160, SwitchEvent::Released),
                (180, SwitchEvent::Repeat),
                (400, SwitchEvent::Released)
            ]
        );
    }

    #[test]
    fn a_down_after_repeat_presses_again() {
        let mut levels = pattern("#######");
        levels.extend(pattern(".............")); // released at 160, up to 380
        levels.extend(pattern("#######"));
        let ev = run(&levels);
        assert_eq!(ev.iter().filter(|e| e.1 == SwitchEvent::Pressed).count(), 2);
        // The second down starts at 400, 240 ms after the release: pressed at 500.
        assert_eq!(ev.last(), Some(&(500, SwitchEvent::Pressed)));
    }

    #[test]
    fn the_clock_may_wrap() {
        let mut s = Switch::IDLE;
        let t0 = u32::MAX - 30;
        let mut got = None;
        for i in 0..8u32 {
            if let Some(e) = s.update(true, t0.wrapping_add(20 * i), &RULES) {
                got = Some((i, e));
            }
        }
        assert_eq!(got, Some((5, SwitchEvent::Pressed)));
        assert_eq!(s.down_ms(t0.wrapping_add(140)), 140);
    }
}
