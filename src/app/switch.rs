//! The assistive switch (issue #20 §4): a user who cannot tap reaches the
//! map and the buttons through one switch and the screen's scan.
//!
//! The board samples the switch once a frame and hands the level in
//! ([`App::set_switch`]); [`crate::touch::switch`] debounces it with the
//! touch's `hold` and `repeat`; [`crate::ui::scan`] is the scan. Here:
//! - **Off** (`switch off`, the default): the level is ignored.
//! - **The glass as a switch** (`switch glass`): as `switch on`, and any
//!   contact on the glass (the touch filter's, anything but a clean "not
//!   touched") is the switch closed too, for a user who can touch but not
//!   aim; no touch reaches the screen's buttons or map then (the
//!   calibration's crosshairs excepted, which need the glass).
//! - **While the arm moves** (or a path is checked): any press is STOP
//!   (`info switch stop`). In `mode hold` a move the switch started runs
//!   while the switch stays down instead, and letting go brings it to rest
//!   (`hold.rs`); a press then goes on, as a held finger does.
//! - **Idle:** the scan runs; a press fixes the column (`info switch
//!   column <x>`), the row (`info switch row <y>`, and the target shows
//!   with its reach verdict), then goes (`info switch go <x> <y>` and the
//!   move's own lines: the screen's map touch at that pixel) or cancels
//!   (`info switch cancel`). A highlighted button is pressed as a touch on
//!   it would be (`info switch button <slot>` and the button's line). The
//!   calibration's button is not scanned: its crosshairs need the glass.
//! - **Stopped:** only the buttons and then RESUME are scanned. RESUME
//!   takes a press held [`RESUME_MS`] on it, as the glass does (`info
//!   switch resume`; let go sooner, `info switch ignored brief`).
//! - The scan stands still while the switch is down, so a press takes the
//!   line where it was when the switch closed (the `hold` later it would
//!   have moved on), and the next sweep starts when the switch opens.
//! - A press that would plan in a frame that has already done its heavy
//!   thing waits for the next frame, the scan held where it was.

use super::press::{RESUME_MS, RING_STEPS};
use super::text::Line;
use super::{App, State};
use crate::config::access::SwitchUse;
use crate::seam::{SerialPort, Storage};
use crate::text::Text;
use crate::touch::filter::TouchPoint;
use crate::touch::switch::{Switch, SwitchEvent, SwitchRules};
use crate::ui::scan::{Scan, ScanPress, ScanShow, STOP_ITEM};
use crate::ui::{hides, Hit};

/// The switch's state (one field of `App`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct SwitchRun {
    input: Switch,
    scan: Scan,
    /// The level the board read for the next frame (true: closed).
    level: bool,
    /// The glass had a contact in this frame's read (`switch glass`).
    pub(super) glass: bool,
    /// A press not acted on yet (a frame without room for a plan).
    due: bool,
    /// The down that pressed on RESUME: it resumes at [`RESUME_MS`].
    resume: bool,
    /// The scan is on the screen.
    shown: bool,
}

impl SwitchRun {
    pub(super) const IDLE: SwitchRun = SwitchRun {
        input: Switch::IDLE,
        scan: Scan::START,
        level: false,
        glass: false,
        due: false,
        resume: false,
        shown: false,
    };
}

/// Frames of a sweep of `ds` tenths of a second.
fn sweep_frames(ds: u8) -> u16 {
    u16::from(ds) * 5
}

impl App {
    /// The switch's level for the next frame (the board's pin, sampled
    /// once a frame: `true` while the contact is closed).
    pub fn set_switch(&mut self, down: bool) {
        self.switch.level = down;
    }

    /// The glass is a switch now (`switch glass`, the main screen up): the
    /// touch's read closes it instead of reaching the screen.
    pub(super) fn glass_is_switch(&self) -> bool {
        self.carer.access.switch == SwitchUse::Glass && self.params.screen && self.screen.calibration.is_none()
    }

    /// What the screen shows of the scan (`None`: no scan now).
    pub(super) fn switch_show(&self) -> Option<ScanShow> {
        let sweep = sweep_frames(self.carer.access.sweep_ds);
        self.switch.shown.then(|| self.switch.scan.show(self.screen.ui.layout(), sweep))
    }

    /// RESUME's countdown while the switch holds it, 0..=[`RING_STEPS`].
    pub(super) fn switch_resume_ring(&self) -> Option<u8> {
        let held = self.switch.input.down_ms(self.carer.now_ms());
        // Steps passed, by comparisons: no division in the frame.
        let step = RESUME_MS / u32::from(RING_STEPS);
        self.switch.resume.then(|| (1..=RING_STEPS).filter(|&k| held >= u32::from(k) * step).count() as u8)
    }

    /// The frame's switch step (module doc), after the touch's.
    #[inline(never)] // avr-trap: frame-size
    #[cfg_attr(target_arch = "avr", optimize(size))] // reason: cold
    pub(super) fn poll_switch<E: Storage, U: SerialPort>(&mut self, now_ms: u32, storage: &mut E, serial: &mut U) {
        if self.carer.access.switch == SwitchUse::Off {
            self.switch = SwitchRun::IDLE;
            self.hold_switch(false);
            return;
        }
        let rules = SwitchRules {
            hold_ms: u32::from(self.config.press.hold_cs) * 10,
            repeat_ms: u32::from(self.config.press.repeat_cs) * 10,
            release_confirm: self.params.filter.release_confirm,
        };
        let sw = &mut self.switch;
        match sw.input.update(sw.level || sw.glass, now_ms, &rules) {
            Some(SwitchEvent::Pressed) => sw.due = true,
            Some(SwitchEvent::Repeat) => self.say_switch(serial, t!("ignored repeat"), None, None),
            Some(SwitchEvent::Released) if core::mem::take(&mut self.switch.resume) => {
                self.say_switch(serial, t!("ignored brief"), None, None);
            }
            _ => {}
        }
        let down = self.switch.input.is_down();
        self.hold_switch(down);
        let state = self.state();
        let scanning = self.params.screen
            && self.screen.calibration.is_none()
            && !self.hold_armed()
            && matches!(state, State::Holding | State::Stopped);
        if !scanning {
            self.switch.shown = false;
            self.switch.resume = false;
            self.switch.scan.restart();
            let due = core::mem::take(&mut self.switch.due);
            if due && matches!(state, State::Moving | State::Checking) && !self.hold_armed() {
                self.stop();
                self.screen_preview(None);
                self.say_switch(serial, t!("stop"), None, None);
            }
            return;
        }
        self.switch.shown = true;
        if self.switch.resume {
            if self.switch.input.down_ms(now_ms) >= RESUME_MS {
                self.switch.resume = false;
                self.resume();
                self.screen_resumed();
                self.say_switch(serial, t!("resume"), None, None);
            }
            return;
        }
        let sweep = sweep_frames(self.carer.access.sweep_ds);
        if !self.switch.due {
            // The line stands still while the switch is down: the press
            // counts where the line was when the switch closed, not `hold`
            // later.
            if !down {
                let items = self.switch_items();
                self.switch.scan.tick(sweep, items, state != State::Stopped);
            }
            return;
        }
        // Go and the buttons may plan: not in a frame that already did its
        // heavy thing.
        let plans = matches!(
            self.switch.scan.show(self.screen.ui.layout(), sweep),
            ScanShow::Target { .. } | ScanShow::Item(_)
        );
        if plans && self.heavy.is_spent() {
            return;
        }
        self.switch.due = false;
        let shown = self.screen.ui.scan_shown();
        let lay = *self.screen.ui.layout();
        match self.switch.scan.press(&lay, sweep, shown) {
            ScanPress::Column(x) => self.say_switch(serial, t!("column"), Some(x), None),
            ScanPress::Row(y) => {
                let x = match self.switch_show() {
                    Some(ScanShow::Target { x, .. }) => x,
                    _ => 0,
                };
                self.switch_target(x, y);
                self.say_switch(serial, t!("row"), Some(y), None);
            }
            ScanPress::Cancel => {
                self.screen_preview(None);
                self.say_switch(serial, t!("cancel"), None, None);
            }
            ScanPress::Go(x, y) => {
                self.screen_preview(None);
                self.say_switch(serial, t!("go"), Some(x), Some(y));
                if let Some((x_p, y_p)) = lay.ws_pixel_to_point(x, y) {
                    self.hold_arm();
                    let p = self.pixel_raw(x, y);
                    self.screen_press(Hit::Map { x_p, y_p }, &p, storage, serial);
                }
            }
            ScanPress::Item(i) => {
                self.say_switch(serial, t!("button"), Some(i16::from(i)), None);
                let (cx, cy) = if i == STOP_ITEM { lay.stop() } else { lay.slot(i) }.centre();
                match self.screen.ui.hit(cx, cy) {
                    Some(Hit::Resume) => self.switch.resume = true,
                    Some(h) => {
                        let p = self.pixel_raw(cx, cy);
                        self.screen_press(h, &p, storage, serial);
                    }
                    None => {}
                }
            }
        }
    }

    /// The items that can be pressed now (bit `i`: [`crate::ui::scan`]'s
    /// item `i`): the buttons the page shows and the lock leaves, not the
    /// calibration's; RESUME while stopped.
    fn switch_items(&self) -> u8 {
        let ui = &self.screen.ui;
        let lay = ui.layout();
        let hidden = self.hidden_now();
        let mut items = if self.stopped { 1 << STOP_ITEM } else { 0 };
        for i in 0..STOP_ITEM {
            let (cx, cy) = lay.slot(i).centre();
            match ui.hit(cx, cy) {
                None | Some(Hit::Calibrate) => {}
                Some(h) if hides(hidden, &h) => {}
                Some(_) => items |= 1 << i,
            }
        }
        items
    }

    /// Shows the chosen pixel as the candidate with its reach verdict, as
    /// a finger's candidate is shown (from the pixel's raw reading).
    fn switch_target(&mut self, x: i16, y: i16) {
        let p = self.pixel_raw(x, y);
        self.screen_preview(None);
        self.screen_candidate(&p);
    }

    /// The raw reading an ideal panel gives at pixel `(x, y)`'s centre
    /// under the running calibration: the raw point a switch press
    /// reports.
    fn pixel_raw(&self, x: i16, y: i16) -> TouchPoint {
        let lay = self.screen.ui.layout();
        let (gx, gy) = lay.glass_pixel(x, y);
        let r = self.config.touch.unmap_pixel(gx, gy, lay.width(), lay.height());
        TouchPoint { x: r.x, y: r.y }
    }

    /// `info switch <what> [a [b]]`.
    #[inline(never)] // avr-trap: frame-size
    fn say_switch<U: SerialPort>(&mut self, serial: &mut U, what: Text, a: Option<i16>, b: Option<i16>) {
        let mut line = Line::new();
        line.str(t!("info switch")).word(what);
        for v in [a, b].into_iter().flatten() {
            line.num(i32::from(v));
        }
        self.emit(serial, &mut line);
    }
}
