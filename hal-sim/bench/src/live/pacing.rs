//! Simulated time in step with the wall clock, and how well it keeps step.
//!
//! The simulator runs the firmware far faster than real time when left
//! alone (roughly ten times on this machine), so pacing means holding it
//! back: the bench asks [`Pacer::due`] how many cycles the wall clock allows
//! and never runs past them. When the machine is too busy for the simulator
//! to keep up, it falls behind; up to [`MAX_BACKLOG_S`] of backlog is caught
//! up (briefly faster than real time, which keeps a minute's average exact),
//! beyond that the backlog is dropped ([`Pacer::slipped_s`]) rather than
//! rushed through, and the page says the simulator is behind.

use std::collections::VecDeque;
use std::time::{Duration, Instant};

/// Backlog beyond which the simulator gives up catching up, seconds.
pub const MAX_BACKLOG_S: f64 = 0.5;
/// Lag above which the bench counts as behind, seconds.
pub const BEHIND_LAG_S: f64 = 0.1;
/// Longest window [`Pacer::ratio`] can look back over.
pub const HISTORY: Duration = Duration::from_secs(65);

pub struct Pacer {
    hz: f64,
    anchor_wall: Instant,
    anchor_cycles: u64,
    slipped_s: f64,
    /// (wall, simulated cycles) at each [`Pacer::sample`], oldest first.
    history: VecDeque<(Instant, u64)>,
}

impl Pacer {
    /// Starts pacing now, at `cycles` simulated cycles of a `hz` clock.
    pub fn new(now: Instant, cycles: u64, hz: f64) -> Pacer {
        Pacer { hz, anchor_wall: now, anchor_cycles: cycles, slipped_s: 0.0, history: VecDeque::from([(now, cycles)]) }
    }

    /// The cycle count the simulation should have reached at `now`.
    pub fn due(&self, now: Instant) -> u64 {
        let wall = now.saturating_duration_since(self.anchor_wall).as_secs_f64();
        self.anchor_cycles + (wall * self.hz) as u64
    }

    /// Simulated seconds the simulation trails the wall clock (0 when on time).
    pub fn lag_s(&self, now: Instant, cycles: u64) -> f64 {
        self.due(now).saturating_sub(cycles) as f64 / self.hz
    }

    /// After running: drops a backlog too large to catch up, so the
    /// simulator does not race through seconds of firmware time at once.
    pub fn settle(&mut self, now: Instant, cycles: u64) {
        let lag = self.lag_s(now, cycles);
        if lag > MAX_BACKLOG_S {
            self.slipped_s += lag;
            self.anchor_wall = now;
            self.anchor_cycles = cycles;
        }
    }

    /// Re-anchors without counting a slip: the simulation stood still on
    /// purpose (a halted firmware) and starts again from `cycles` now.
    pub fn restart(&mut self, now: Instant, cycles: u64) {
        self.anchor_wall = now;
        self.anchor_cycles = cycles;
    }

    /// Simulated seconds dropped so far because the simulator was too slow.
    pub fn slipped_s(&self) -> f64 {
        self.slipped_s
    }

    /// Records a point for [`Pacer::ratio`] (call at a steady rate).
    pub fn sample(&mut self, now: Instant, cycles: u64) {
        self.history.push_back((now, cycles));
        while self.history.front().is_some_and(|(t, _)| now.saturating_duration_since(*t) > HISTORY) {
            self.history.pop_front();
        }
    }

    /// Simulated time over wall time across (about) the last `window`, and
    /// the wall seconds it actually covers; `None` before any time passed.
    pub fn ratio(&self, window: Duration) -> Option<(f64, f64)> {
        let &(t1, c1) = self.history.back()?;
        let &(t0, c0) = self.history.iter().find(|(t, _)| t1.saturating_duration_since(*t) <= window)?;
        let wall = t1.saturating_duration_since(t0).as_secs_f64();
        (wall > 0.0).then(|| ((c1 - c0) as f64 / self.hz / wall, wall))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const HZ: f64 = 16e6;

    #[test]
    fn due_follows_the_wall_clock() {
        let t0 = Instant::now();
        let p = Pacer::new(t0, 1000, HZ);
        assert_eq!(p.due(t0), 1000);
        assert_eq!(p.due(t0 + Duration::from_millis(250)), 1000 + 4_000_000);
        assert!((p.lag_s(t0 + Duration::from_secs(1), 1000) - 1.0).abs() < 1e-9);
        assert_eq!(p.lag_s(t0, 5000), 0.0);
    }

    #[test]
    fn a_large_backlog_is_dropped_and_counted() {
        let t0 = Instant::now();
        let mut p = Pacer::new(t0, 0, HZ);
        let t1 = t0 + Duration::from_millis(300);
        p.settle(t1, 0);
        assert_eq!(p.slipped_s(), 0.0, "300 ms is caught up");
        let t2 = t0 + Duration::from_secs(2);
        p.settle(t2, 16_000_000);
        assert!((p.slipped_s() - 1.0).abs() < 1e-9);
        assert_eq!(p.due(t2), 16_000_000);
    }

    #[test]
    fn ratio_over_a_window() {
        let t0 = Instant::now();
        let mut p = Pacer::new(t0, 0, HZ);
        for i in 1..=100u64 {
            // 1 s of wall per sample, 0.99 s simulated.
            p.sample(t0 + Duration::from_secs(i), i * 15_840_000);
        }
        let (r, wall) = p.ratio(Duration::from_secs(60)).unwrap();
        assert!((r - 0.99).abs() < 1e-9 && (wall - 60.0).abs() < 1e-9, "{r} over {wall} s");
    }
}
