//! How a contact becomes an action (issue #19 §2–4): the map and the
//! buttons act on lift-off, STOP on contact, RESUME after a long fresh hold.
//!
//! Every read feeds the contact ([`crate::touch::contact`]); then:
//! - **STOP** latches as soon as [`STOP_READS`] consecutive touched reads
//!   lie in its hit area (≤ 60 ms after the finger lands, or slides onto
//!   it without lifting), whatever the contact is otherwise: the one
//!   on-contact action, never ignored.
//! - **RESUME** (shown after STOP) needs a contact that lands in its box at
//!   least `repeat` after STOP latched (and after the last lift-off) and
//!   stays there, without a single dropout, for [`RESUME_MS`]; the screen
//!   counts it down. A bounce (any dropout) or a finger that slides off
//!   voids that contact. The finger that resumed, left on STOP's place,
//!   does not latch STOP again.
//! - Everything else acts when the finger lifts, after at least `hold`:
//!   a contact that landed on the map and lifts on the map sends the arm to
//!   the contact's robust centre (a marker and a ring that fills over the
//!   hold show the candidate and its reach verdict meanwhile); one that
//!   landed on a button and lifts on the same button presses it. Lifting
//!   elsewhere, or wandering farther than `radius`, cancels (`info screen
//!   cancel`, the screen says so). A second contact joining (a palm) shows
//!   "Lift your hand" and never acts (`info screen ignored hand`); a contact
//!   shorter than `hold` sends `info screen ignored brief`, one that lands
//!   within `repeat` of the last lift-off `info screen ignored repeat`;
//!   except that a contact landing within `repeat` of a brief one on the
//!   same target (the map, or the same button) continues it: their holds
//!   add up, so the flicker of a force tremor is one touch (issue #19 §6),
//!   acting at the lift-off of the contact that completes the hold.
//! - The carer's gesture and the carer mode's pose save are long holds on
//!   no button and on a pose button (`access.rs`): a still contact of the
//!   rules above, judged at its lift-off.
//! - Without a screen the same rules commit the robust centre on lift-off
//!   (the whole panel is the workspace) and send the same lines.
//! - `mode hold` (`hold.rs`): a map contact (without a screen, any) that has
//!   rested `hold` commits its robust centre there and then, and its lift
//!   is the release (nothing more at lift-off).

use super::text::Line;
use super::App;
use crate::seam::{SerialPort, Storage};
use crate::touch::contact::{Contact, ContactConfig, ContactEvent};
use crate::touch::filter::{Read, TouchPoint};
use crate::ui::Hit;

/// Consecutive touched reads in STOP's hit area that latch it.
pub const STOP_READS: u8 = 3;
/// How long RESUME must be held, ms.
pub const RESUME_MS: u32 = 600;
/// Steps of the ring that fills over the hold (and of RESUME's countdown).
pub const RING_STEPS: u8 = 4;

/// What the contact on the glass is doing. Fieldless, `Idle` first, and
/// where it landed beside it in [`Press::landed`]: so [`Press::IDLE`] is all
/// zero bytes and initializing `App` copies no constant from RAM.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
pub(super) enum Role {
    /// No contact yet.
    Idle = 0,
    /// It acts on lift-off by where it landed ([`Press::landed`]): the map,
    /// a button, the calibration's crosshair, or (no screen) the workspace.
    Pending,
    /// As `Pending`, landed on nothing (a gap, the status lines).
    Blank,
    /// It may become RESUME (landed in its box late enough after STOP).
    Resume,
    /// Already acted (STOP) or voided: nothing at lift-off.
    Spent,
    /// RESUME acted: nothing at lift-off, and the same finger, now on
    /// STOP's place, does not latch it again.
    Resumed,
    /// Landed within `repeat` of the last lift-off.
    Repeat,
}

/// The contact's state beyond its measures (one field of `App`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Press {
    pub(super) contact: Contact,
    pub(super) role: Role,
    /// Where a `Pending` contact landed.
    landed: Hit,
    /// Consecutive touched reads in STOP's hit area.
    stop_reads: u8,
    /// A read of this contact was no touch (RESUME needs none).
    dropped: bool,
    /// The last lift-off, ms (`None` before the first).
    lifted_ms: Option<u32>,
    /// When STOP latched, ms.
    stop_ms: u32,
    /// The hold so far of brief contacts on the same target, each landing
    /// within `repeat` of the one before (a force tremor's flicker), ms:
    /// the next such contact continues it (0 after anything else).
    carry_ms: u32,
    /// The ring's fill, 0..=[`RING_STEPS`] (hold on the map, or RESUME's
    /// countdown), for the screen.
    pub(super) ring: u8,
}

impl Press {
    pub(super) const IDLE: Press = Press {
        contact: Contact::IDLE,
        role: Role::Idle,
        landed: Hit::Stop,
        stop_reads: 0,
        dropped: false,
        lifted_ms: None,
        stop_ms: 0,
        carry_ms: 0,
        ring: 0,
    };
}

/// The line a contact's outcome sends (beyond the actions' own lines).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Said {
    Stop,
    Resume,
    Cancel,
    Brief,
    Repeat,
    Hand,
}

/// `a / b` of the ring's steps, clamped.
fn ring_of(a: u32, b: u32) -> u8 {
    let steps = u32::from(RING_STEPS);
    (a.saturating_mul(steps) / b.max(1)).min(steps) as u8
}

impl App {
    /// One classified read at `now_ms`: the contact's rules (module doc).
    // Out of line: the hit tests and the preview's pose are not in
    // `poll_touch`'s frame while a committed touch is routed.
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn press_read<E: Storage, U: SerialPort>(
        &mut self,
        read: &Read,
        now_ms: u32,
        storage: &mut E,
        serial: &mut U,
    ) {
        let cfg = ContactConfig {
            release_confirm: self.params.filter.release_confirm,
            radius: u16::from(self.config.press.radius),
            plate: self.config.press.plate,
        };
        let Some(ev) = self.press.contact.update(read, now_ms, &cfg) else { return };
        match ev {
            ContactEvent::Landed => self.press_landed(now_ms),
            ContactEvent::Held => {}
            ContactEvent::Missed => {
                self.press.dropped = true;
                self.press.stop_reads = 0;
                return;
            }
            ContactEvent::Lifted => return self.press_lifted(storage, serial),
        }
        let last = self.press.contact.last();
        let hit = self.hit_of(&last);
        // STOP, on contact, whatever else the contact is.
        let stop_here = matches!(hit, Some(Hit::Stop)) && self.press.role != Role::Resumed;
        if stop_here && self.params.screen && self.screen.calibration.is_none() {
            self.press.stop_reads = self.press.stop_reads.saturating_add(1);
            if self.press.stop_reads >= STOP_READS && !self.stopped {
                self.stop();
                self.press.stop_ms = now_ms;
                self.press.role = Role::Spent;
                self.press.ring = 0;
                self.screen_preview(None);
                self.say(serial, Said::Stop);
            }
            return;
        }
        self.press.stop_reads = 0;
        if self.press.contact.palm() {
            if self.press.role != Role::Spent {
                self.screen_hand();
            }
            return;
        }
        match self.press.role {
            Role::Resume => {
                let held = self.press.contact.duration_ms();
                if !matches!(hit, Some(Hit::Resume)) || self.press.dropped || !self.stopped {
                    self.press.role = Role::Spent;
                    self.press.ring = 0;
                } else if held >= RESUME_MS {
                    self.resume();
                    self.press.role = Role::Resumed;
                    self.press.ring = 0;
                    self.screen_resumed();
                    self.say(serial, Said::Resume);
                } else {
                    self.press.ring = ring_of(held, RESUME_MS);
                }
            }
            Role::Pending if matches!(self.press.landed, Hit::Map { .. }) => {
                let hold = u32::from(self.config.press.hold_cs) * 10;
                self.press.ring = ring_of(self.press.contact.duration_ms() + self.press.carry_ms, hold);
                let centre = self.press.contact.centre();
                self.screen_candidate(&centre);
                self.press_hold_commit(storage, serial);
            }
            Role::Blank if !self.params.screen => self.press_hold_commit(storage, serial),
            _ => {}
        }
    }

    /// `mode hold`: a contact on the map (the panel, without a screen) that
    /// has rested `hold` commits its robust centre now, not at lift-off,
    /// and spends the contact (`hold.rs`).
    fn press_hold_commit<E: Storage, U: SerialPort>(&mut self, storage: &mut E, serial: &mut U) {
        let c = &self.press.contact;
        let hold = u32::from(self.config.press.hold_cs) * 10;
        if !self.config.hold_to_run || c.duration_ms() + self.press.carry_ms < hold || c.wandered() {
            return;
        }
        let centre = c.centre();
        if self.params.screen && !matches!(self.hit_of(&centre), Some(Hit::Map { .. })) {
            return;
        }
        self.press.role = Role::Spent;
        self.press.ring = 0;
        self.press.carry_ms = 0;
        self.screen_preview(None);
        self.hold_commit(&centre, storage, serial);
    }

    /// A new contact: what it may become.
    fn press_landed(&mut self, now_ms: u32) {
        self.press.stop_reads = 0;
        self.press.dropped = false;
        self.press.ring = 0;
        let start = self.press.contact.start_ms();
        let repeat = u32::from(self.config.press.repeat_cs) * 10;
        let soon = self.press.lifted_ms.is_some_and(|t| start.wrapping_sub(t) < repeat);
        let hit = self.hit_of(&self.press.contact.last());
        self.press.role = if matches!(hit, Some(Hit::Resume)) {
            // Fresh: late enough after the latch and after the last lift-off.
            if self.stopped && !soon && now_ms.wrapping_sub(self.press.stop_ms) >= repeat {
                Role::Resume
            } else {
                Role::Spent
            }
        } else if soon && self.press.carry_ms > 0 && hit.is_some_and(|h| same_target(&self.press.landed, &h)) {
            // The flicker of one touch: it continues the brief contacts
            // before it (their hold counts), where they landed.
            Role::Pending
        } else if soon {
            self.press.carry_ms = 0;
            Role::Repeat
        } else if let Some(h) = hit {
            self.press.carry_ms = 0;
            self.press.landed = h;
            Role::Pending
        } else {
            self.press.carry_ms = 0;
            Role::Blank
        };
    }

    /// The finger lifted: act, cancel or ignore (module doc).
    fn press_lifted<E: Storage, U: SerialPort>(&mut self, storage: &mut E, serial: &mut U) {
        self.hold_lifted();
        let c = self.press.contact;
        self.press.lifted_ms = Some(c.last_ms());
        self.press.ring = 0;
        self.press.stop_reads = 0;
        let role = core::mem::replace(&mut self.press.role, Role::Idle);
        let carry = core::mem::take(&mut self.press.carry_ms);
        // The gesture's second hold must be the very next contact.
        let gesture = self.carer.gesture.take();
        self.screen_preview(None);
        let landed = match role {
            Role::Idle | Role::Spent | Role::Resume | Role::Resumed => return,
            Role::Repeat => return self.say(serial, Said::Repeat),
            Role::Pending => Some(self.press.landed),
            Role::Blank => None,
        };
        if c.palm() {
            self.screen_hand();
            return self.say(serial, Said::Hand);
        }
        let held = c.duration_ms() + carry;
        if held < u32::from(self.config.press.hold_cs) * 10 {
            // Kept, for a flicker's next contact (`press_landed`).
            if role == Role::Pending {
                self.press.carry_ms = held.max(1);
            }
            return self.say(serial, Said::Brief);
        }
        let (centre, last) = (c.centre(), c.last());
        if c.wandered() {
            return self.press_cancel(serial);
        }
        // The calibration's crosshair and the no-screen workspace take the
        // centre; the map the centre if it lies on the map where the finger
        // lifted; a button its own lift-off inside it.
        let p = if !self.params.screen || self.screen.calibration.is_some() {
            centre
        } else {
            match (landed, self.hit_of(&last), self.hit_of(&centre)) {
                (Some(Hit::Map { .. }), Some(Hit::Map { .. }), Some(Hit::Map { .. })) => centre,
                (Some(a), Some(b), _) if same_button(&a, &b) => last,
                // Landed and lifted on no button (a gap, the status lines,
                // a hidden button): deliberately nothing, as before.
                (None, None, _) => return,
                _ => return self.press_cancel(serial),
            }
        };
        match landed.filter(|_| self.screen.calibration.is_none()) {
            Some(Hit::Carer(k)) => return self.carer_gesture(&c, k, gesture, serial),
            Some(Hit::Pose(n)) if self.carer_pose_hold(n, held, serial) => return,
            _ => {}
        }
        if self.heavy.is_spent() && self.touch_plans(&p) {
            self.deferred_touch = Some(p);
        } else {
            self.route_touch(&p, storage, serial);
        }
    }

    fn press_cancel<U: SerialPort>(&mut self, serial: &mut U) {
        self.screen_cancelled();
        self.say(serial, Said::Cancel);
    }

    /// What the screen shows at a raw point (`None` without a screen, on
    /// the calibration screen, or off the calibrated span).
    fn hit_of(&self, p: &TouchPoint) -> Option<Hit> {
        if !self.params.screen || self.screen.calibration.is_some() {
            return None;
        }
        match self.raw_to_panel(p) {
            Ok((x, y)) => self.screen.ui.hit_panel(x, y),
            Err(_) => None,
        }
    }

    /// The contact's line: `info screen stop|resume|cancel` or `info
    /// screen ignored brief|repeat|hand`.
    #[inline(never)] // avr-trap: frame-size
    fn say<U: SerialPort>(&mut self, serial: &mut U, said: Said) {
        let mut line = Line::new();
        line.str(match said {
            Said::Stop => t!("info screen stop"),
            Said::Resume => t!("info screen resume"),
            Said::Cancel => t!("info screen cancel"),
            Said::Brief => t!("info screen ignored brief"),
            Said::Repeat => t!("info screen ignored repeat"),
            Said::Hand => t!("info screen ignored hand"),
        });
        self.emit(serial, &mut line);
    }

    /// A finger is on the glass (for `status` and the wiring probe).
    pub(super) fn finger_down(&self) -> bool {
        self.press.contact.is_down()
    }

    /// The RESUME countdown's fill, 0..=[`RING_STEPS`] (`None`: none runs).
    pub(super) fn resume_ring(&self) -> Option<u8> {
        (self.press.role == Role::Resume).then_some(self.press.ring).or_else(|| self.switch_resume_ring())
    }
}

/// Where a contact continues a brief one before it: the map (anywhere:
/// the centre is the new contact's) or the same button.
fn same_target(a: &Hit, b: &Hit) -> bool {
    matches!((a, b), (Hit::Map { .. }, Hit::Map { .. })) || same_button(a, b)
}

/// The same button (the map is no button; STOP and RESUME act on contact).
fn same_button(a: &Hit, b: &Hit) -> bool {
    !matches!(a, Hit::Map { .. } | Hit::Stop | Hit::Resume) && a == b
}
