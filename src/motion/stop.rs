//! A planned stop: a running motion brought to rest along its own path by
//! slowing its clock, and brought back to speed the same way (hold to run,
//! issue #20 §5; later a path check that fails mid-move).
//!
//! # The warp
//! The running motion is any [`Timeline`]: a pose q(τ) at its own time τ (a
//! planned move with corrections superposed, a line, a circle, a lift). The
//! stop does not plan a new trajectory: it drives τ with a rate r, each
//! frame τ += r·dt, and lowers r from 1 to 0 along the smooth ramp
//! r(u) = 1 − u²(3 − 2u), u = k/n (r′ = 0 at both ends). Every commanded
//! pose is q at some τ, so the arm stays on its planned path (a line stays a
//! line) and stops short of the target; speed is q′(τ)·r, never above the
//! plan's since r ≤ 1; the acceleration is q″(τ)·r² + q′(τ)·r′.
//!
//! # The bound, frame by frame
//! The ramp's length is chosen from the speed when the stop starts:
//! n frames with n·dt = 3·max_j |v_j| / A_j, so that the braking term
//! |q′|·|r′| ≤ |v|·1.5/(n·dt) is A/2 at its peak. Its sum with the plan's
//! own q″·r² is not bounded by that choice alone (a plan braking at its own
//! limit), so every step is checked exactly, on the poses the servos get:
//! the next ramp step is taken only if every joint's second difference
//! |q_{k+1} − 2q_k + q_{k−1}| stays ≤ A_j·dt². Otherwise the ramp pauses
//! for that frame and τ advances by the same step as before: then the three
//! poses are equally spaced in τ by h = r·dt and the second difference is
//! h²·q″(ξ) ≤ r²·dt²·P_j, with P_j ≤ A_j the plan's own bound (mean value
//! theorem, per joint). So no frame is ever outside the limits; a pause
//! only makes the stop longer (at worst the motion runs to its own end,
//! where it rests). Position is continuous by construction; velocity too:
//! the first step is r(1/n)·dt, within 3/n² of the running step.
//!
//! Cost: one pose evaluation per frame, two in a frame whose ramp step is
//! refused.

use super::plan::JOINTS;

/// A running motion as the stop sees it.
pub trait Timeline {
    /// The pose at the motion's own time `tau`, s (its end pose past its
    /// end); `None` if it cannot be evaluated (a path whose IK fails).
    fn pose(&self, tau: f32) -> Option<[f32; JOINTS]>;
}

/// The longest ramp, frames (10 s at 50 Hz): a motion too fast for it
/// pauses the ramp instead.
pub const MAX_RAMP: u16 = 500;

/// The ramp's rate at step `k` of `n`: 1 at 0, 0 at `n`.
fn ramp(k: u16, n: u16) -> f32 {
    let u = f32::from(k) / f32::from(n.max(1));
    1.0 - u * u * (3.0 - 2.0 * u)
}

/// A motion's clock being slowed to rest or brought back to speed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Warp {
    /// The motion's time of the last pose given out, s.
    tau: f32,
    /// τ's advance into that pose (r·dt), s.
    step: f32,
    /// The pose before it (at τ − step) and that pose.
    prev: [f32; JOINTS],
    now: [f32; JOINTS],
    /// Ramp step k of n: r = ramp(k, n).
    k: u16,
    n: u16,
    /// Toward full speed (resume) rather than rest.
    up: bool,
    dt: f32,
}

impl Warp {
    /// No stop (all zero bytes: a static's initializer copies nothing).
    pub const NONE: Warp =
        Warp { tau: 0.0, step: 0.0, prev: [0.0; JOINTS], now: [0.0; JOINTS], k: 0, n: 0, up: false, dt: 0.0 };

    /// A stop of `m`, whose last frame was at `tau` and the one before at
    /// `tau − dt`, under the joints' acceleration limits
    /// `accel` (rad/s²); `None` if the motion cannot be evaluated there.
    #[inline(never)] // avr-trap: frame-size
    pub fn begin<M: Timeline>(m: &M, tau: f32, dt: f32, accel: &[f32; JOINTS]) -> Option<Warp> {
        let (prev, now) = (m.pose(tau - dt)?, m.pose(tau)?);
        let step = dt;
        // Frames of the ramp: 3·|v|/A, |v| from the last step.
        let mut t = 0.0f32;
        for ((p, q), a) in prev.iter().zip(now.iter()).zip(accel.iter()) {
            t = t.max(3.0 * (q - p).abs() / (step * a));
        }
        let frames = t / dt;
        let n = if frames < f32::from(MAX_RAMP) { (frames as u16).saturating_add(1) } else { MAX_RAMP };
        Some(Warp { tau, step, prev, now, k: 0, n, up: false, dt })
    }

    /// Ramp toward full speed (`true`: a held contact again) or toward rest.
    pub fn set_up(&mut self, up: bool) {
        self.up = up;
    }

    /// The pose of the next frame (see the module doc); `None` if the motion
    /// cannot be evaluated (the caller faults).
    #[inline(never)] // avr-trap: frame-size
    pub fn next<M: Timeline>(&mut self, m: &M, accel: &[f32; JOINTS]) -> Option<[f32; JOINTS]> {
        let k = if self.up { self.k.saturating_sub(1) } else { (self.k + 1).min(self.n) };
        if k != self.k {
            let step = ramp(k, self.n) * self.dt;
            let q = m.pose(self.tau + step)?;
            if self.within(&q, accel) {
                self.k = k;
                return Some(self.take(q, step));
            }
        }
        // The ramp pauses: the same step, within the plan's own bound.
        let q = m.pose(self.tau + self.step)?;
        let q = self.take(q, self.step);
        // The motion has reached its own end (three equal poses): at rest
        // now, not after the rest of a ramp that would move nothing.
        if !self.up && self.now == self.prev {
            self.k = self.n;
            self.step = 0.0;
        }
        Some(q)
    }

    fn within(&self, q: &[f32; JOINTS], accel: &[f32; JOINTS]) -> bool {
        let dt2 = self.dt * self.dt;
        let d = q.iter().zip(self.now.iter().zip(self.prev.iter()));
        d.zip(accel.iter()).all(|((q, (n, p)), a)| (q - 2.0 * n + p).abs() <= a * dt2)
    }

    fn take(&mut self, q: [f32; JOINTS], step: f32) -> [f32; JOINTS] {
        self.tau += step;
        self.step = step;
        self.prev = self.now;
        self.now = q;
        q
    }

    /// The motion's time of the last pose, s.
    pub fn tau(&self) -> f32 {
        self.tau
    }

    /// At rest: the ramp has reached r = 0 and the last step moved nothing.
    pub fn at_rest(&self) -> bool {
        self.k == self.n && self.step == 0.0
    }

    /// Ramping toward full speed.
    pub fn rising(&self) -> bool {
        self.up
    }

    /// Back at full speed (r = 1) after a resume.
    pub fn full(&self) -> bool {
        self.k == 0 && self.up
    }

    /// Frames left to rest if no ramp step is refused.
    pub fn frames_to_rest(&self) -> u16 {
        self.n - self.k
    }
}
