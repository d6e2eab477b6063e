//! The carer lock and carer mode (issue #20 §3), after the clinician
//! profiles of powered-wheelchair controls: the carer decides what the user
//! may change.
//!
//! - **Locked** (user mode): the items the carer hid (`access hide
//!   <cal|line|lift|fast|touch>`, stored in `config::access`) are blank on
//!   the screen and their places do nothing; the serial commands that change
//!   them answer `err locked`, as do the carer's own `access pin|hide|show|
//!   cap`. STOP, RESUME, moves, poses, Grip and Undo always work.
//! - **Carer mode** (unlocked): everything shows and works; a pose button
//!   held [`POSE_SAVE_HOLD_MS`] arms a save of the pose held now into it
//!   (the button says *Save*), which a tap on the same button within
//!   [`CONFIRM_MS`] confirms (`pose save <n>`'s path); a plain tap still
//!   goes to the pose.
//!
//! A board with a PIN boots locked; one without never locks (a fresh board,
//! so a maker is never locked out). `access unlock <pin>` or the screen's
//! gesture opens carer mode until `access lock`, the gesture again,
//! [`RELOCK_MS`] with no contact and no serial line, or a power cycle.
//! Three wrong PINs in a row make `access unlock` wait [`PIN_WAIT_MS`].
//!
//! **The gesture** is two holds of [`GESTURE_HOLD_MS`] each, first on the
//! left end of the status lines, then on their right end
//! ([`crate::ui::Layout::carer_corner`]), the second lifted within
//! [`GESTURE_WINDOW_MS`] of the first, with no other contact between: each
//! is a still finger (the contact's wander radius) on a place where the
//! user's screen has nothing, so neither a tremor's taps, nor a resting
//! hand (a palm is refused), nor a slide across the screen makes it.
//!
//! The speed cap (`access cap slow|normal|fast`) holds in both modes: a
//! preset above it moves as the cap (the screen highlights, and `status`
//! reports, the preset in effect; replies say `cap <preset>`).

use super::refusal::Refusal;
use super::text::Line;
use super::App;
use crate::config::access::{self, item, Access, SwitchUse, ACCESS_DEFAULT};
use crate::config::settings::CalSet;
use crate::config::settings::SpeedPreset;
use crate::config::store::SaveError;
use crate::protocol::command::{AccessCmd, Command};
use crate::seam::{SerialPort, Storage};
use crate::text::Text;
use crate::touch::contact::Contact;

/// Each of the gesture's two holds, ms.
pub const GESTURE_HOLD_MS: u32 = 3000;
/// From the first hold's lift-off to the second's, ms at most.
pub const GESTURE_WINDOW_MS: u32 = 10_000;
/// A pose button held this long in carer mode arms its save, ms.
pub const POSE_SAVE_HOLD_MS: u32 = 2000;
/// The armed save waits this long for its confirming tap, ms.
pub const CONFIRM_MS: u32 = 5000;
/// Carer mode ends after this long with no contact and no serial line, ms
/// (5 min: a carer who walks away leaves a locked screen).
pub const RELOCK_MS: u32 = 300_000;
/// Wrong PINs in a row before `access unlock` waits.
pub const PIN_TRIES: u8 = 3;
/// The wait, ms.
pub const PIN_WAIT_MS: u32 = 30_000;

/// The lock's state (one field of `App`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Carer {
    /// The stored settings.
    pub(super) access: Access,
    locked: bool,
    /// The last frame's clock, ms (the commands' handlers have none).
    now_ms: u32,
    /// The last contact or serial line, ms (for [`RELOCK_MS`]).
    active_ms: u32,
    /// Wrong PINs in a row, and when the last came.
    wrong: u8,
    wrong_ms: u32,
    /// The gesture's first hold lifted, at ms.
    pub(super) gesture: Option<u32>,
    /// A pose save armed: the slot and when, ms.
    confirm: Option<(u8, u32)>,
}

impl Carer {
    /// The last frame's clock, ms.
    pub(super) fn now_ms(&self) -> u32 {
        self.now_ms
    }

    /// Unlocked with the defaults, until the boot loads the record.
    pub(super) const NEW: Carer = Carer {
        access: ACCESS_DEFAULT,
        locked: false,
        now_ms: 0,
        active_ms: 0,
        wrong: 0,
        wrong_ms: 0,
        gesture: None,
        confirm: None,
    };
}

/// What an `access` command did, for its reply (a few bytes: it sits in
/// `serial::Done`, which every reply copies).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum AccessDone {
    Lock,
    Unlock,
    /// A setting stored: which, and its sequence number.
    Stored(AccessSet, Result<u16, SaveError>),
}

/// Which setting an `access` command stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum AccessSet {
    /// A PIN set (true) or removed.
    Pin(bool),
    /// An item bit hidden (true) or shown.
    Hide(u8, bool),
    Cap(SpeedPreset),
    /// The switch's use set.
    Switch(SwitchUse),
    /// The switch's sweep, tenths of a second.
    Sweep(u8),
}

impl App {
    /// Loads the stored settings: a board with a PIN starts locked.
    pub(super) fn access_boot<E: Storage>(&mut self, storage: &mut E) {
        let access = access::load(storage).2;
        self.carer = Carer { access, locked: access.pin.is_set(), ..Carer::NEW };
    }

    /// The [`item`] bits hidden now (none in carer mode).
    pub(super) fn hidden_now(&self) -> u8 {
        if self.carer.locked {
            self.carer.access.hide
        } else {
            0
        }
    }

    /// The pose slot whose save is armed (0: none), for the screen.
    pub(super) fn confirm_slot(&self) -> u8 {
        self.carer.confirm.map_or(0, |(n, _)| n)
    }

    /// The preset moves use: the one chosen, or the cap below it.
    pub(super) fn speed_now(&self) -> SpeedPreset {
        self.speed_allowed(self.config.speed)
    }

    /// `s`, or the cap below it; a hidden Fast moves as Mid (the user's
    /// pages have no fastest speed while locked).
    fn speed_allowed(&self, s: SpeedPreset) -> SpeedPreset {
        let s = self.carer.access.capped(s);
        if s == SpeedPreset::Fast && self.hidden_now() & item::FAST != 0 {
            SpeedPreset::Normal
        } else {
            s
        }
    }

    /// Each frame: the clock, the armed save's timeout and the idle relock.
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn carer_tick<U: SerialPort>(&mut self, now_ms: u32, serial: &mut U) {
        let c = &mut self.carer;
        c.now_ms = now_ms;
        if self.press.contact.is_down() {
            c.active_ms = now_ms;
        }
        if c.confirm.is_some_and(|(_, t)| now_ms.wrapping_sub(t) > CONFIRM_MS) {
            c.confirm = None;
        }
        if !c.locked && c.access.pin.is_set() && now_ms.wrapping_sub(c.active_ms) >= RELOCK_MS {
            self.set_locked(true);
            self.say_access(serial, t!("info access lock idle"), None);
        }
    }

    /// A line of the lock's nobody asked for: `text`, then the refusal's
    /// reason if any (one small function for all of them: flash).
    #[inline(never)] // avr-trap: frame-size
    fn say_access<U: SerialPort>(&mut self, serial: &mut U, text: Text, reason: Option<Refusal>) {
        let mut line = Line::new();
        line.str(text);
        if let Some(r) = reason {
            line.word(r.reason());
        }
        self.emit(serial, &mut line);
    }

    fn set_locked(&mut self, on: bool) {
        // A calibration flow the carer left open is closed with the lock
        // that hides it.
        if on && self.carer.access.hide & (item::CAL | item::TOUCH) != 0 && self.screen.calibration.is_some() {
            self.screen.calibration = None;
            self.screen.ui.invalidate();
        }
        self.carer.locked = on;
        self.carer.confirm = None;
        self.carer.active_ms = self.carer.now_ms;
    }

    /// `err locked` for a command that changes something hidden now (the
    /// carer's own `access` settings are refused in `access`).
    pub(super) fn check_unlocked(&mut self, cmd: &Command) -> Result<(), Refusal> {
        self.carer.active_ms = self.carer.now_ms;
        let needs = match cmd {
            Command::Path(_) => item::LINE,
            Command::Lift(_) => item::LIFT,
            Command::Speed(SpeedPreset::Fast) => item::FAST,
            Command::CalSet(CalSet::Touch { .. }) => item::TOUCH,
            Command::CalSet(_) | Command::CalSave | Command::CalReset | Command::CalResetGrip | Command::CalLcd(_) => {
                item::CAL
            }
            _ => 0,
        };
        if self.hidden_now() & needs != 0 {
            return Err(Refusal::Locked);
        }
        Ok(())
    }

    /// Carries out an `access` command.
    pub(super) fn access<E: Storage>(&mut self, cmd: AccessCmd, storage: &mut E) -> Result<AccessDone, Refusal> {
        let mut next = self.carer.access;
        let set = match cmd {
            AccessCmd::Lock if !next.pin.is_set() => return Err(Refusal::NoPin),
            AccessCmd::Lock => {
                self.set_locked(true);
                return Ok(AccessDone::Lock);
            }
            AccessCmd::Unlock(pin) => return self.unlock(&pin),
            _ if self.carer.locked => return Err(Refusal::Locked),
            AccessCmd::SetPin(pin) => {
                next.pin = pin;
                AccessSet::Pin(pin.is_set())
            }
            AccessCmd::Hide(bit, hide) => {
                next.hide = if hide { next.hide | bit } else { next.hide & !bit };
                AccessSet::Hide(bit, hide)
            }
            AccessCmd::Cap(p) => {
                next.cap = p;
                AccessSet::Cap(p)
            }
            AccessCmd::Switch(u) => {
                next.switch = u;
                AccessSet::Switch(u)
            }
            AccessCmd::Sweep(ds) => {
                next.sweep_ds = ds;
                AccessSet::Sweep(ds)
            }
        };
        // The RAM copy changes only once stored.
        let saved = access::save(storage, &next);
        if saved.is_ok() {
            self.carer.access = next;
        }
        Ok(AccessDone::Stored(set, saved))
    }

    /// `access unlock <pin>`, rate-limited: after [`PIN_TRIES`] wrong PINs
    /// every try within [`PIN_WAIT_MS`] of the last wrong one is refused
    /// unchecked (and does not restart the wait).
    fn unlock(&mut self, pin: &access::Pin) -> Result<AccessDone, Refusal> {
        let c = &mut self.carer;
        if !c.access.pin.is_set() {
            return Err(Refusal::NoPin);
        }
        if c.wrong >= PIN_TRIES && c.now_ms.wrapping_sub(c.wrong_ms) < PIN_WAIT_MS {
            return Err(Refusal::PinWait);
        }
        if c.access.pin != *pin {
            c.wrong = c.wrong.saturating_add(1);
            c.wrong_ms = c.now_ms;
            return Err(Refusal::WrongPin);
        }
        c.wrong = 0;
        self.set_locked(false);
        Ok(AccessDone::Unlock)
    }

    /// A still contact that landed and lifted on carer place `k`
    /// (`press.rs`): a step of the gesture if it was held
    /// [`GESTURE_HOLD_MS`] by itself (a flicker's brief contacts do not add
    /// up here); `before` is the first step's lift-off, if it was the last
    /// contact.
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn carer_gesture<U: SerialPort>(&mut self, c: &Contact, k: u8, before: Option<u32>, serial: &mut U) {
        if c.duration_ms() < GESTURE_HOLD_MS {
            return;
        }
        let now = c.last_ms();
        let (text, reason) = if k == 0 {
            self.carer.gesture = Some(now);
            (t!("info screen access 1 of 2"), None)
        } else if before.is_some_and(|t| now.wrapping_sub(t) <= GESTURE_WINDOW_MS) {
            if self.carer.locked {
                self.set_locked(false);
                (t!("info screen access unlock"), None)
            } else if self.carer.access.pin.is_set() {
                self.set_locked(true);
                (t!("info screen access lock"), None)
            } else {
                (t!("err screen access"), Some(Refusal::NoPin))
            }
        } else {
            return;
        };
        self.say_access(serial, text, reason);
    }

    /// A pose button lifted after `held` ms: in carer mode a hold of
    /// [`POSE_SAVE_HOLD_MS`] arms its save (true: the press is taken).
    pub(super) fn carer_pose_hold<U: SerialPort>(&mut self, n: u8, held: u32, serial: &mut U) -> bool {
        if self.carer.locked || held < POSE_SAVE_HOLD_MS {
            return false;
        }
        self.carer.confirm = Some((n, self.carer.now_ms));
        let mut line = Line::new();
        line.str(t!("info screen pose save")).num(i32::from(n)).str(t!("? tap to confirm"));
        self.emit(serial, &mut line);
        true
    }

    /// A confirmed touch on the screen: the armed save's slot, if any (it
    /// is disarmed whatever was touched).
    pub(super) fn take_confirm(&mut self) -> Option<u8> {
        self.carer.confirm.take().filter(|_| !self.carer.locked).map(|(n, _)| n)
    }

    /// `cal access <locked|carer> pin <set|none> hide <items|none> cap
    /// <preset> switch <on|off> sweep <s>`.
    pub(super) fn access_show_line(&self, line: &mut Line) {
        let a = &self.carer.access;
        line.str(t!("cal access ")).str(if self.carer.locked { t!("locked") } else { t!("carer") });
        line.word(t!("pin")).word(if a.pin.is_set() { t!("set") } else { t!("none") });
        line.word(t!("hide"));
        for (bit, name) in (0..).map_while(access::item_nth) {
            if a.hide & bit != 0 {
                line.word(name);
            }
        }
        if a.hide == 0 {
            line.word(t!("none"));
        }
        line.word(t!("cap")).word(a.cap.name());
        line.word(t!("switch")).word(a.switch.name());
        line.word(t!("sweep")).bytes(b" ").centi(i32::from(a.sweep_ds) * 10);
    }

    /// The reply of an `access` command.
    pub(super) fn access_reply(&self, done: &AccessDone, r: &mut Line) {
        let (set, seq) = match *done {
            AccessDone::Lock => {
                r.str(t!("ok access lock"));
                return;
            }
            AccessDone::Unlock => {
                r.str(t!("ok access unlock"));
                return;
            }
            AccessDone::Stored(_, Err(SaveError::Verify)) => {
                r.str(t!("err save failed: verify"));
                return;
            }
            AccessDone::Stored(_, Err(_)) => {
                r.str(t!("err save failed: storage"));
                return;
            }
            AccessDone::Stored(set, Ok(seq)) => (set, seq),
        };
        let switch = matches!(set, AccessSet::Switch(_) | AccessSet::Sweep(_));
        r.str(if switch { t!("ok switch ") } else { t!("ok access ") });
        match set {
            AccessSet::Switch(SwitchUse::Off) => {
                r.str(t!("off"));
            }
            AccessSet::Switch(u) => {
                r.str(u.name()).str(t!(" sweep ")).centi(i32::from(self.carer.access.sweep_ds) * 10);
            }
            AccessSet::Sweep(ds) => {
                r.str(t!("sweep ")).centi(i32::from(ds) * 10);
            }
            AccessSet::Pin(on) => {
                r.str(if on { t!("pin set") } else { t!("pin off") });
            }
            AccessSet::Hide(bit, hide) => {
                r.str(if hide { t!("hide") } else { t!("show") });
                if let Some((_, name)) = (0..).map_while(access::item_nth).find(|(b, _)| *b == bit) {
                    r.word(name);
                }
            }
            AccessSet::Cap(p) => {
                r.str(t!("cap ")).str(p.name());
            }
        }
        r.word(t!("seq")).num(i32::from(seq));
    }

    /// ` cap <preset>` after a preset the cap holds down.
    pub(super) fn cap_suffix(&self, s: SpeedPreset, r: &mut Line) {
        let capped = self.speed_allowed(s);
        if capped != s {
            r.word(t!("cap")).word(capped.name());
        }
    }
}
