//! Servo frames from the three pins' pulses.
//!
//! The three outputs share Timer5, so in every 20 ms PWM period the three
//! pulses rise together (within the harness's few cycles of stamp lag); a
//! plot sample is one such triple. The pins are measured independently, so
//! a pulse can be missing on one pin (outputs connecting or disconnecting,
//! a reset): such a period is skipped instead of pairing pulses of
//! different periods.

use std::collections::VecDeque;

/// Rises further apart than this (cycles; 100 µs) are different periods.
const SAME_PERIOD: u64 = 1600;

#[derive(Default)]
pub struct PulsePairing {
    queues: [VecDeque<(u64, f64)>; 3],
}

impl PulsePairing {
    /// A complete pulse of joint `j`: rise cycle, width µs.
    pub fn push(&mut self, j: usize, rise: u64, width_us: f64) {
        self.queues[j].push_back((rise, width_us));
    }

    /// Every complete triple so far: (rise cycle of the base pulse, widths).
    pub fn frames(&mut self) -> Vec<(u64, [f64; 3])> {
        let mut out = Vec::new();
        loop {
            let heads: Vec<(u64, f64)> = self.queues.iter().filter_map(|q| q.front().copied()).collect();
            if heads.len() < 3 {
                // A pin's pulse for this period may still be high: wait.
                return out;
            }
            let first = heads.iter().map(|h| h.0).min().unwrap_or(0);
            let same: Vec<bool> = heads.iter().map(|h| h.0 - first <= SAME_PERIOD).collect();
            for (q, &s) in self.queues.iter_mut().zip(&same) {
                if s {
                    q.pop_front();
                }
            }
            if same.iter().all(|&s| s) {
                out.push((heads[0].0, [heads[0].1, heads[1].1, heads[2].1]));
            }
        }
    }

    pub fn clear(&mut self) {
        self.queues.iter_mut().for_each(VecDeque::clear);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn triples_of_one_period_and_a_period_missing_a_pin_is_skipped() {
        let mut p = PulsePairing::default();
        // Period 0: all three; period 1: the elbow is missing; period 2: all.
        for (j, rise) in [(0, 0), (1, 2), (2, 3), (0, 320_000), (1, 320_001), (0, 640_000), (1, 640_000)] {
            p.push(j, rise, 1500.0 + j as f64);
        }
        assert_eq!(p.frames(), vec![(0, [1500.0, 1501.0, 1502.0])]);
        // The elbow's next pulse is period 2's: period 1 is dropped.
        p.push(2, 640_004, 1600.0);
        assert_eq!(p.frames(), vec![(640_000, [1500.0, 1501.0, 1600.0])]);
        assert!(p.frames().is_empty());
    }
}
