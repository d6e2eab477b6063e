//! The panel's wiring as the app knows it: measured by the firmware's probe
//! (`touch::wiring::Probe` over the shield pins, which only the board can
//! drive), reported, kept in the running configuration and saved with it.
//!
//! The app asks for a probe when the loaded configuration has no wiring
//! (first boot, or a record written before version 3) and when the
//! calibration screen opens (a shield may have been swapped), but only once
//! no press is held: a finger joins the plates and pairs that are open would
//! read linked. The firmware runs the probe and hands the verdict to
//! [`App::set_wiring`]. While the arm runs, the probe takes one read per
//! frame between the app's own panel reads, and starts over whenever one of
//! those saw contact ([`App::panel_contact`]): a finger put down during a
//! probe read shows in the next panel read at the latest, so a verdict is
//! only taken after a frame whose panel read was clean. An unidentified wiring leaves the touch panel unread
//! (or read through the wiring it had), says so on serial and on the screen,
//! and the arm stays fully usable over serial.

use super::text::Line;
use super::{App, Mode};
use crate::seam::SerialPort;
use crate::touch::wiring::{Wiring, WiringUnknown};

impl App {
    /// True when the firmware should probe the panel's wiring now (see the
    /// module doc).
    pub fn wiring_probe_wanted(&self) -> bool {
        self.probe_wanted && self.mode != Mode::Boot && self.filter.held().is_none() && !self.finger_down()
    }

    /// The last panel read saw something other than an untouched panel (a
    /// press, or a read the filter rejected).
    pub fn panel_contact(&self) -> bool {
        self.contact
    }

    /// True once a frame has written servo pulses: the probe must then run
    /// one read per frame instead of all at once.
    pub fn pulses_started(&self) -> bool {
        self.pulses.is_some()
    }

    /// The probe's verdict. An identified wiring becomes the running one
    /// (saved by the next `cal save` or calibration) and is reported as
    /// `info wiring <a|b|c>`; none identified keeps the wiring there
    /// was (none at first boot: the panel is not read), shows the screen's
    /// warning and is reported as `err touch wiring unknown plates 0x… open
    /// 0x…` (the pair masks of `touch::wiring::Links`).
    pub fn set_wiring<U: SerialPort>(&mut self, found: Result<Wiring, WiringUnknown>, serial: &mut U) {
        self.probe_wanted = false;
        let mut line = Line::new();
        match found {
            Ok(w) => {
                if self.config.wiring != Some(w) {
                    self.config.wiring = Some(w);
                    self.filter.reset();
                }
                self.wiring_unknown = false;
                line.str(t!("info wiring")).word(w.name());
            }
            Err(WiringUnknown(links)) => {
                self.wiring_unknown = true;
                line.str(t!("err touch wiring unknown plates ")).hex(u32::from(links.plate), 3);
                line.str(t!(" open ")).hex(u32::from(links.open), 3);
            }
        }
        self.emit(serial, &mut line);
    }
}
