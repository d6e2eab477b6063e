//! What the bench publishes: server-sent events for the pages (screen
//! patches, plot samples, console lines, state) and the snapshot the GET
//! endpoints read.

use std::sync::mpsc::{SyncSender, TrySendError};
use std::sync::Arc;
use std::time::{Duration, Instant};

use serde_json::{json, Value};

use super::{round3, Bench};
use crate::live::arm::{self, Target};
use crate::live::pacing::BEHIND_LAG_S;
use touch_arm_rig::firmware::{CPU_HZ, GRIPPER_PIN, SERVO_PINS};

/// Plot samples kept for a page that connects (seconds of history).
const PLOT_HISTORY_S: f64 = 12.0;

impl Bench {
    pub(super) fn subscribe(&mut self, tx: SyncSender<Arc<str>>) {
        let history: Vec<&Value> = self.recent.iter().map(|(_, v)| v).collect();
        let intro = [
            event("screen", &self.screen.keyframe().to_json()),
            event("history", &json!({ "samples": history })),
            event("serial", &json!({ "lines": self.console_log })),
            event("state", &self.state_event(&[])),
        ];
        if intro.into_iter().all(|e| tx.try_send(e).is_ok()) {
            self.subscribers.push(tx);
        }
    }

    fn broadcast(&mut self, e: Arc<str>) {
        // A page that cannot keep up (its queue is full) is dropped: its
        // stream ends and the browser reconnects, getting a fresh keyframe.
        self.subscribers.retain(|tx| match tx.try_send(e.clone()) {
            Ok(()) => true,
            Err(TrySendError::Full(_) | TrySendError::Disconnected(_)) => false,
        });
    }

    /// Collects the pulses, screen and console lines since the last tick
    /// and publishes them.
    pub(super) fn tick(&mut self) {
        for (j, pin) in SERVO_PINS.into_iter().enumerate() {
            for p in self.session.avr.drain_pulses(pin) {
                let width = p.width_us(CPU_HZ);
                self.last_pulses[j] = Some(width);
                self.pairing.push(j, self.cycle_base + p.rise_cycle, width);
            }
        }
        if let Some(p) = self.session.avr.drain_pulses(GRIPPER_PIN).last() {
            self.last_grip = Some(p.width_us(CPU_HZ));
        }
        for (rise, widths) in self.pairing.frames() {
            let t = rise as f64 / f64::from(CPU_HZ);
            let a = arm::pose_from_pulses(&self.maps, widths).angles_deg;
            let v = json!([round3(t), round3(a[0]), round3(a[1]), round3(a[2])]);
            self.recent.push_back((t, v.clone()));
            self.new_samples.push(v);
        }
        let now_s = self.now_s();
        while self.recent.front().is_some_and(|(t, _)| now_s - t > PLOT_HISTORY_S) {
            self.recent.pop_front();
        }
        // What a session that runs for hours must not keep.
        self.session.avr.forget_adc_log();
        self.session.lcd.forget_command_log();

        let patch = self.screen.update(self.session.lcd.landscape());
        if let Some(p) = &patch {
            self.broadcast(event("screen", &p.to_json()));
        }
        if !self.console_new.is_empty() {
            let lines = std::mem::take(&mut self.console_new);
            self.broadcast(event("serial", &json!({ "lines": lines })));
        }
        self.pacer.sample(Instant::now(), self.cycles());
        let samples = std::mem::take(&mut self.new_samples);
        let state = self.state_event(&samples);
        self.broadcast(event("state", &state));
        self.publish(patch.is_some());
    }

    /// Refreshes the snapshot the GET endpoints read (with the picture
    /// only when it changed: a copy is 150 KB).
    pub(super) fn publish(&self, screen_changed: bool) {
        let mut snap = self.shared.lock().unwrap_or_else(|e| e.into_inner());
        snap.state = self.state.clone();
        snap.t_s = self.now_s();
        snap.pulses_us = self.last_pulses;
        snap.angles_deg = self.angles_deg();
        snap.grip_pulse_us = self.last_grip;
        snap.grip_deg = self.grip_deg();
        snap.screen_seq = self.screen.seq();
        if screen_changed {
            snap.screen = Arc::new(self.screen.current().clone());
        }
        snap.bench = self.bench_json();
        snap.taken = Instant::now();
    }

    fn angles_deg(&self) -> [Option<f64>; 3] {
        std::array::from_fn(|j| self.last_pulses[j].map(|us| arm::pulse_to_angle_deg(&self.maps[j], us)))
    }

    fn grip_deg(&self) -> Option<f64> {
        self.last_grip.map(|us| arm::pulse_to_angle_deg(&self.grip_map, us))
    }

    /// The `state` event: the API's state plus what the page draws.
    fn state_event(&self, samples: &[Value]) -> Value {
        let pose = match self.last_pulses {
            [Some(b), Some(s), Some(e)] => Some(arm::pose_from_pulses(&self.maps, [b, s, e])),
            _ => None,
        };
        json!({
            "state": self.state,
            "t_s": self.now_s(),
            "pulses_us": self.last_pulses,
            "angles_deg": self.angles_deg(),
            "grip_pulse_us": self.last_grip,
            "grip_deg": self.grip_deg(),
            "screen_seq": self.screen.seq(),
            "arm": pose.map(|p| json!({ "angles_deg": p.angles_deg, "elbow": p.elbow, "tip": p.tip })),
            "target": self.target.as_ref().map(Target::to_json),
            "finger": self.finger.map(|f| [f.px.0, f.px.1]),
            "samples": samples,
            "bench": self.bench_json(),
        })
    }

    /// Pacing figures and fault switches (`GET /api/bench`).
    fn bench_json(&self) -> Value {
        let now = Instant::now();
        let lag = self.pacer.lag_s(now, self.cycles());
        let r60 = self.pacer.ratio(Duration::from_secs(60));
        let r5 = self.pacer.ratio(Duration::from_secs(5));
        // A short window says "behind" only once it spans a few seconds.
        let slow = r5.is_some_and(|(r, wall)| wall >= 4.0 && r < 0.98);
        json!({
            "ratio_60s": r60.map(|r| r.0),
            "window_60s_s": r60.map(|r| r.1),
            "ratio_5s": r5.map(|r| r.0),
            "lag_ms": lag * 1000.0,
            "slipped_s": self.pacer.slipped_s(),
            "behind": self.halted.is_none() && (lag > BEHIND_LAG_S || slow),
            "noise": self.noise,
            "switch": self.switch_until.is_some(),
            "stalled": self.stalled_at.is_some(),
            "halted": self.halted,
            "power_ups": self.power_ups,
            "watchdog_resets": self.watchdog_resets,
            "external_resets": self.external_resets,
            "eeprom_size": self.session.avr.eeprom_size(),
        })
    }
}

/// One server-sent event (JSON has no raw newlines, so one data line).
fn event(name: &str, data: &Value) -> Arc<str> {
    format!("event: {name}\ndata: {data}\n\n").into()
}
