//! The display overrides (`config::lcd`): `cal set lcd …` stores them at
//! once in their own record (they are read at boot, before the display
//! starts, so there is nothing to apply in RAM), and `cal show` prints the
//! stored ones.

use super::refusal::Refusal;
use super::serial::Done;
use super::text::Line;
use super::App;
use crate::config::lcd::{self, LcdSet};
use crate::seam::Storage;

impl App {
    /// `cal set lcd …`: the stored overrides with `set` applied, saved (not
    /// while the arm moves: a save holds the frame for tens of ms). Out of
    /// line: its record buffers stay out of `execute`'s frame, which is on
    /// the deepest stack chain.
    #[inline(never)] // reason: cold
    pub(super) fn cal_lcd<E: Storage>(&mut self, set: LcdSet, storage: &mut E) -> Result<Done, Refusal> {
        if self.is_moving() {
            return Err(Refusal::Busy);
        }
        let next = self.lcd.with(set);
        let saved = lcd::save(storage, &next);
        if saved.is_ok() {
            self.lcd = next;
        }
        Ok(Done::CalLcd(saved))
    }

    /// `lcd <name> invert on|off rotate 0|180`: the stored overrides in
    /// `cal set`'s words (`cal show`, the reply to `cal set lcd`).
    pub(super) fn lcd_words(&self, line: &mut Line) {
        let s = &self.lcd;
        line.str(t!("lcd ")).str(s.controller.name());
        line.word(t!("invert")).word(if s.invert { t!("on") } else { t!("off") });
        line.word(t!("rotate")).word(if s.rotate_180 { t!("180") } else { t!("0") });
    }
}
