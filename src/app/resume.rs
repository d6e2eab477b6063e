//! No jump after a reset (issue #21 §1): the pulses the servos were getting
//! when the chip reset, kept in RAM through the reset, become the first
//! pulses after it.
//!
//! # The block
//! The firmware keeps the last commanded pulses (three joints and the
//! gripper) in a [`Snapshot::BYTES`]-byte block of a `.noinit` RAM section,
//! which the C runtime's start-up code does not clear (`board::resume`),
//! written at the start of every frame with the widths going out in that PWM
//! period. The block is a magic word, the four widths (Timer ticks of
//! 0.5 µs, 0 for a gripper that has no pulse yet) and a CRC-16 over both
//! ([`Snapshot::encode`]). RAM survives an external reset (the RESET pin: the
//! reset button, a serial console opening the port, an upload) and a
//! watchdog reset; after power-up it holds garbage, which the magic word and
//! the CRC refuse ([`Snapshot::decode`]).
//!
//! # At boot
//! [`App::restart`] runs right after the boot frame has loaded the
//! configuration. After an external, a watchdog or an unknown reset (a
//! bootloader may clear the reset flags) with a valid block, every joint and
//! the gripper are commanded the block's pulses: the arm holds where it was
//! (a move interrupted by the reset is not continued), the app's joint
//! angles are those pulses read through the loaded calibration, targets are
//! taken at once (no settling: the servos are where they were), and the
//! first move still runs at the slow preset. A pulse the loaded calibration
//! does not allow (the running one had not been saved) is never commanded:
//! it is pulled into the joint's output window and reported. After a
//! power-on or brown-out reset, or with no valid block, the behaviour is the
//! power-up one (the home pose). Either way one line says which:
//! `info reset <cause> resume pulses <b> <s> <e> <g>` (µs, `-` for a
//! gripper with no pulse) or `info reset <cause> home`.

use super::text::Line;
use super::{App, Mode};
use crate::config::crc::crc16;
use crate::config::store::copy;
use crate::motion::plan::JOINTS;
use crate::seam::SerialPort;
use crate::servo::map::{Joint, ServoMap, ABS_MAX_US, ABS_MIN_US, TICKS_PER_US};

/// Why the chip started, as the reset flags (MCUSR) say.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ResetKind {
    /// Power was applied (RAM holds garbage).
    PowerOn,
    /// The supply dipped below the brown-out level.
    BrownOut,
    /// The RESET pin: the reset button, a console opening the port (DTR), an
    /// upload.
    External,
    /// The watchdog: a frame loop that stopped.
    Watchdog,
    /// No flag set: a bootloader read and cleared them first.
    Unknown,
}

impl ResetKind {
    /// The word `info reset` prints.
    pub fn name(self) -> crate::text::Text {
        match self {
            ResetKind::PowerOn => t!("power-on"),
            ResetKind::BrownOut => t!("brown-out"),
            ResetKind::External => t!("external"),
            ResetKind::Watchdog => t!("watchdog"),
            ResetKind::Unknown => t!("unknown"),
        }
    }

    /// A reset after which the pulses kept in RAM may be resumed: not a
    /// power-up, not a brown-out (the supply failed; the servos may have
    /// dropped wherever gravity took them).
    pub fn may_resume(self) -> bool {
        !matches!(self, ResetKind::PowerOn | ResetKind::BrownOut)
    }
}

/// The pulses going out when the block was written, Timer ticks (0.5 µs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Snapshot {
    /// Base, shoulder, elbow.
    pub joints: [u16; JOINTS],
    /// The gripper's, `None` while it has no pulse yet.
    pub grip: Option<u16>,
}

/// The block's first word: a valid block starts with it (and its layout).
const MAGIC: u16 = 0x7253;
/// The joints and the gripper.
const CHANNELS: usize = JOINTS + 1;
/// A pulse any calibration could allow, ticks.
const TICKS: core::ops::RangeInclusive<u16> = ABS_MIN_US * TICKS_PER_US..=ABS_MAX_US * TICKS_PER_US;

impl Snapshot {
    /// The block's size: magic, four widths, CRC.
    pub const BYTES: usize = 12;

    /// The block: magic, base, shoulder, elbow, gripper (0: none), all
    /// little-endian u16, then the CRC-16/CCITT-FALSE of those 10 bytes.
    pub fn encode(&self) -> [u8; Snapshot::BYTES] {
        let mut b = [0u8; Snapshot::BYTES];
        let words = [MAGIC, self.joints[0], self.joints[1], self.joints[2], self.grip.unwrap_or(0)];
        for (chunk, w) in b.chunks_exact_mut(2).zip(words.iter()) {
            copy(chunk, &w.to_le_bytes());
        }
        let crc = crc16(b.get(..10).unwrap_or(&[]));
        if let Some(tail) = b.get_mut(10..) {
            copy(tail, &crc.to_le_bytes());
        }
        b
    }

    /// The pulses of a block [`Snapshot::encode`] wrote; `None` for anything
    /// else (RAM after power-up, a block torn by a reset while it was being
    /// written, a pulse no calibration allows).
    pub fn decode(b: &[u8; Snapshot::BYTES]) -> Option<Snapshot> {
        let w = |i: usize| u16::from_le_bytes([b[2 * i], b[2 * i + 1]]);
        if w(0) != MAGIC || w(5) != crc16(b.get(..10)?) {
            return None;
        }
        let joints = [w(1), w(2), w(3)];
        let grip = match w(4) {
            0 => None,
            g => Some(g),
        };
        let ok = joints.iter().chain(grip.iter()).all(|t| TICKS.contains(t));
        ok.then_some(Snapshot { joints, grip })
    }
}

/// What the firmware found at boot: the reset's cause and the block.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Restart {
    /// The reset flags' verdict.
    pub kind: ResetKind,
    /// The block, if it was valid.
    pub pulses: Option<Snapshot>,
}

/// The angle of `ticks` under `m`, and the ticks actually commanded when
/// `m` does not allow `ticks` (then the angle is pulled into the output
/// window).
#[inline(never)] // reason: code-size
fn resumed(m: &ServoMap, ticks: u16) -> (f32, Option<u16>) {
    let q = m.pulse_to_angle::<f32>(ticks);
    match m.angle_to_pulse(q) {
        Ok(p) if p.clamped.is_none() && p.ticks == ticks => (q, None),
        _ => {
            let held = m.clamp_angle(q);
            let t = m.angle_to_pulse(held).map_or(ticks, |p| p.ticks);
            (held, Some(t))
        }
    }
}

impl App {
    /// After the boot frame (the configuration is loaded, state `homing`)
    /// and before the next: resumes the pulses of `r` if the reset allows it
    /// (module doc), or keeps homing; says which in one line. Does nothing
    /// before the boot frame or once pulses have started.
    #[inline(never)] // avr-trap: frame-size
    pub fn restart<U: SerialPort>(&mut self, r: &Restart, serial: &mut U) {
        if self.mode == Mode::Boot || self.pulses.is_some() {
            return;
        }
        let Some(snap) = r.pulses.filter(|_| r.kind.may_resume()) else {
            self.report_restart(serial, r.kind, None);
            return;
        };
        // The joints and the gripper as four channels (the gripper's only
        // if it had a pulse).
        let ticks = [snap.joints[0], snap.joints[1], snap.joints[2], snap.grip.unwrap_or(0)];
        let n = if snap.grip.is_some() { CHANNELS } else { JOINTS };
        let mut q = [0.0f32; CHANNELS];
        let mut out = ticks;
        // Loops to `n`, not over the arrays: unrolled four times over they
        // cost flash.
        let mut i = 0;
        while i < n {
            let m = self.maps.get(i).unwrap_or(&self.grip.map);
            let t = ticks.get(i).copied().unwrap_or(0);
            let (angle, held) = resumed(m, t);
            if let Some(h) = held {
                self.report_clamp(serial, i, t, h);
            }
            if let (Some(q), Some(o)) = (q.get_mut(i), out.get_mut(i)) {
                (*q, *o) = (angle, held.unwrap_or(t));
            }
            i += 1;
        }
        let [b, s, e, g] = q;
        self.hold_resumed(&[b, s, e]);
        if n == CHANNELS {
            self.grip_hold_resumed(g);
        }
        self.report_restart(serial, r.kind, Some(&out[..n]));
    }

    /// `info reset <cause> resume pulses <b> <s> <e> <g|->` (µs) or `info
    /// reset <cause> home`. Its line is in this frame, not in
    /// [`App::restart`]'s, whose locals would then sit beyond `ldd`'s reach.
    #[inline(never)] // reason: code-size
    #[cfg_attr(target_arch = "avr", optimize(size))] // reason: cold
    fn report_restart<U: SerialPort>(&mut self, serial: &mut U, kind: ResetKind, pulses: Option<&[u16]>) {
        let mut line = Line::new();
        line.str(t!("info reset ")).str(kind.name());
        match pulses {
            Some(p) => {
                line.word(t!("resume pulses"));
                for t in p {
                    line.bytes(b" ").ticks_us(*t);
                }
                if p.len() < CHANNELS {
                    line.bytes(b" -");
                }
            }
            None => {
                line.word(t!("home"));
            }
        }
        self.emit(serial, &mut line);
    }

    /// `warn resume <joint|grip> <us> outside its limits, held at <us>`
    /// for channel `ch` (0..=2 the joints, 3 the gripper).
    #[inline(never)] // reason: cold
    fn report_clamp<U: SerialPort>(&mut self, serial: &mut U, ch: usize, was: u16, now: u16) {
        let mut line = Line::new();
        let name = Joint::ALL.get(ch).map_or(t!("grip"), |j| j.name());
        line.str(t!("warn resume ")).str(name).bytes(b" ").ticks_us(was);
        line.str(t!(" outside its limits, held at ")).ticks_us(now);
        self.emit(serial, &mut line);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::servo::map::JointCal;

    #[test]
    fn a_block_round_trips_and_any_damage_is_refused() {
        let s = Snapshot { joints: [3000, 4123, 1201], grip: Some(1800) };
        let b = s.encode();
        assert_eq!(Snapshot::decode(&b), Some(s));
        let none = Snapshot { grip: None, ..s };
        assert_eq!(Snapshot::decode(&none.encode()), Some(none));
        for i in 0..Snapshot::BYTES {
            for bit in 0..8 {
                let mut d = b;
                d[i] ^= 1 << bit;
                assert_eq!(Snapshot::decode(&d), None, "byte {i} bit {bit}");
            }
        }
        assert_eq!(Snapshot::decode(&[0; Snapshot::BYTES]), None);
        assert_eq!(Snapshot::decode(&[0xA5; Snapshot::BYTES]), None);
        // A well-formed block with a pulse no calibration allows.
        let wild = Snapshot { joints: [999, 3000, 3000], grip: None };
        assert_eq!(Snapshot::decode(&wild.encode()), None);
    }

    #[test]
    fn only_power_on_and_brown_out_home() {
        use ResetKind::*;
        let resume = [PowerOn, BrownOut, External, Watchdog, Unknown].map(|k| k.may_resume());
        assert_eq!(resume, [false, false, true, true, true]);
    }

    /// Every pulse inside a calibration's window reads as an angle that maps
    /// back to the same tick: the first pulse after a reset is the last one
    /// before it, to the tick.
    #[test]
    fn every_allowed_pulse_is_resumed_to_the_tick() {
        let odd =
            JointCal { offset_us: 1437.3, us_per_rad: -611.7, min_rad: -1.2, max_rad: 1.9, ..JointCal::BASE_DEFAULT };
        for cal in JointCal::DEFAULTS.iter().chain([odd, crate::config::grip::GRIP_DEFAULT].iter()) {
            let m = ServoMap::new(cal).unwrap();
            let (lo, hi) = m.output_window();
            let (a, b) = (m.angle_to_pulse(lo).unwrap().ticks, m.angle_to_pulse(hi).unwrap().ticks);
            let (a, b) = (a.min(b), a.max(b));
            let mut inside = 0;
            for t in 900..=5100u16 {
                let (q, held) = resumed(&m, t);
                let out = m.angle_to_pulse(q).unwrap();
                assert!(out.clamped.is_none(), "{cal:?}: {t} held at a clamped angle");
                if (a + 1..b).contains(&t) {
                    assert_eq!(held, None, "{cal:?}: tick {t}");
                    assert_eq!(out.ticks, t);
                    inside += 1;
                } else if let Some(h) = held {
                    // Outside: pulled to the window's nearer end, never beyond.
                    assert!((a..=b).contains(&h), "{cal:?}: {t} held at {h}");
                    assert_eq!(out.ticks, h);
                }
            }
            assert!(inside > 1000);
        }
    }
}
