//! Switch scanning (issue #20 §4): how one switch picks a point of the map
//! or a button, as Apple's Switch Control point scanning does, one frame at
//! a time and in whole pixels.
//!
//! 1. **Column:** a vertical line sweeps the map left to right in `sweep`
//!    frames; a press fixes its column.
//! 2. **Row:** a horizontal line sweeps up from the bottom in `sweep`
//!    frames; a press fixes its row, and the target is shown. A row sweep
//!    that ends unpressed starts over at 1.
//! 3. **Go / Cancel:** two phases of [`dwell`] each, twice: a press in Go
//!    sends the arm there, in Cancel starts over; unpressed, it cancels.
//! 4. **Items:** a column sweep that ends unpressed highlights the page's
//!    buttons in turn, then RESUME while stopped, [`dwell`] each; a press
//!    presses the one highlighted. Then 1 again (only 4 while stopped: the
//!    map takes no target then). RESUME comes last, at least five dwells
//!    after the STOP, so a second press right after a STOP (a spasm's
//!    second jerk) never lands on it.
//!
//! **Every pixel in three presses.** At a sweep of `n` frames over `w`
//! columns the line moves `w/n` columns a frame, more than one when the
//! sweep is short (2 s is 100 frames for 224 or 320 columns). So sweep `p`
//! starts `p mod k` of `k = ⌈w/n⌉` sub-steps late: the line's column at
//! frame `f` is `⌊(k·f + p mod k)·w / (k·n)⌋`, and over `k` sweeps it stands
//! on every column (the step `w/(k·n)` is at most one column). Rows alike,
//! counting the row sweeps after the column press: an unpressed row sweep
//! runs again with the next sub-step, `k` times in all, before a new
//! column, so every row can follow every column.

use super::layout::Layout;

/// The items scanned after the map, in this order: the four buttons left
/// of the page key and the page key (0..=4), then STOP's place (RESUME
/// while stopped).
pub const ITEMS: u8 = 6;
/// Item number of STOP's place.
pub const STOP_ITEM: u8 = 5;
/// Go and Cancel are each offered this many times.
const ROUNDS: u8 = 2;

/// Frames a button stays highlighted, and each of Go and Cancel lasts: a
/// fifth of the sweep, at least one second.
pub const fn dwell(sweep: u16) -> u16 {
    let d = sweep / 5;
    if d < 50 {
        50
    } else {
        d
    }
}

/// Where the scan is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[repr(u8)]
enum Phase {
    Column = 0,
    Row,
    Go,
    Cancel,
    Item,
}

/// What a press did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScanPress {
    /// The column is fixed (screen x); the row sweep starts.
    Column(i16),
    /// The row is fixed (screen y); Go and Cancel follow.
    Row(i16),
    /// Go to the map pixel `(x, y)`.
    Go(i16, i16),
    /// Cancelled in a Cancel phase.
    Cancel,
    /// Press item `i` (0..=4: the buttons, [`STOP_ITEM`]: STOP's place).
    Item(u8),
}

/// What the screen shows of the scan.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ScanShow {
    /// The column line at screen x.
    Column(i16),
    /// The row line at screen y.
    Row(i16),
    /// The chosen pixel; `go`: a press goes (else it cancels).
    Target {
        /// Screen x.
        x: i16,
        /// Screen y.
        y: i16,
        /// A Go phase.
        go: bool,
    },
    /// Item `i` highlighted.
    Item(u8),
}

/// The scan's state (8 bytes; one field of the app).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Scan {
    phase: Phase,
    /// Frames into the phase.
    frame: u16,
    /// Sweeps done, for the sub-step offset (module doc).
    pass: u8,
    /// Go and Cancel rounds begun; or the highlighted item.
    k: u8,
    x: i16,
    y: i16,
}

/// `⌊(k·f + p mod k)·w / (k·n)⌋` for `k = ⌈w/n⌉` (module doc), below `w`.
#[cfg_attr(target_arch = "avr", optimize(size))] // reason: cold
fn sweep_at(frame: u16, pass: u8, w: u16, n: u16) -> u16 {
    let n = u32::from(n.max(1));
    let w = u32::from(w);
    let k = w.div_ceil(n).max(1);
    let m = k * u32::from(frame) + u32::from(pass) % k;
    ((m * w) / (k * n)).min(w.saturating_sub(1)) as u16
}

/// Sweeps that put the line on each of `w` pixels at `n` frames a sweep:
/// `⌈w/n⌉` (module doc).
fn sweeps_to_cover(w: u16, n: u16) -> u8 {
    let n = n.max(1);
    (w.div_ceil(n)).min(u16::from(u8::MAX)) as u8
}

/// The most rows a map has (the 480×320 layout's): row sweeps repeat
/// until this many would be covered, which covers the smaller map too.
const fn lay_rows() -> u16 {
    Layout::HVGA.ws().h
}

impl Scan {
    /// The column sweep's first frame.
    pub const START: Scan = Scan { phase: Phase::Column, frame: 0, pass: 0, k: 0, x: 0, y: 0 };

    /// Back to the column sweep (a new point), keeping the sweep count.
    pub fn restart(&mut self) {
        *self = Scan { pass: self.pass, ..Scan::START };
    }

    fn column(&self, lay: &Layout, sweep: u16) -> i16 {
        let ws = lay.ws();
        ws.x + sweep_at(self.frame, self.pass, ws.w, sweep) as i16
    }

    /// The row sweep's sub-step offset is its own count (`k`), not the
    /// column's: every row in the sweeps after whatever column was fixed.
    fn row(&self, lay: &Layout, sweep: u16) -> i16 {
        let ws = lay.ws();
        ws.bottom() - 1 - sweep_at(self.frame, self.k, ws.h, sweep) as i16
    }

    /// The first item of `items` (bit `i`: item `i` can be pressed) from
    /// `from` on, if any.
    fn next_item(items: u8, from: u8) -> Option<u8> {
        (from..ITEMS).find(|&i| items & (1 << i) != 0)
    }

    fn start_items(&mut self, items: u8, map: bool) {
        self.frame = 0;
        match Scan::next_item(items, 0) {
            Some(i) => {
                self.phase = Phase::Item;
                self.k = i;
            }
            None => {
                self.phase = Phase::Column;
                self.pass = self.pass.wrapping_add(u8::from(map));
            }
        }
    }

    /// One frame: `sweep` frames per axis, `items` the items that can be
    /// pressed now, `map` whether the map takes a point now (not while
    /// stopped).
    pub fn tick(&mut self, sweep: u16, items: u8, map: bool) {
        if !map && self.phase != Phase::Item {
            return self.start_items(items, map);
        }
        self.frame = self.frame.saturating_add(1);
        let dwell = dwell(sweep);
        match self.phase {
            Phase::Column if self.frame >= sweep => {
                self.start_items(items, map);
                if self.phase == Phase::Column {
                    // Nothing to highlight: the next sweep.
                    self.frame = 0;
                }
            }
            Phase::Row if self.frame >= sweep => {
                // Again with the next sub-step until every row has had
                // its turn, then a new column.
                self.k += 1;
                self.frame = 0;
                if self.k >= sweeps_to_cover(lay_rows(), sweep) {
                    self.restart();
                }
            }
            Phase::Go if self.frame >= dwell => {
                self.phase = Phase::Cancel;
                self.frame = 0;
            }
            Phase::Cancel if self.frame >= dwell => {
                self.k += 1;
                self.frame = 0;
                if self.k >= ROUNDS {
                    self.restart();
                } else {
                    self.phase = Phase::Go;
                }
            }
            Phase::Item if self.frame >= dwell || items & (1 << self.k) == 0 => {
                self.frame = 0;
                match Scan::next_item(items, self.k + 1) {
                    Some(i) => self.k = i,
                    None if map => {
                        self.pass = self.pass.wrapping_add(1);
                        self.phase = Phase::Column;
                    }
                    None => self.start_items(items, map),
                }
            }
            _ => {}
        }
    }

    /// What the screen shows now.
    pub fn show(&self, lay: &Layout, sweep: u16) -> ScanShow {
        match self.phase {
            Phase::Column => ScanShow::Column(self.column(lay, sweep)),
            Phase::Row => ScanShow::Row(self.row(lay, sweep)),
            Phase::Go | Phase::Cancel => ScanShow::Target { x: self.x, y: self.y, go: self.phase == Phase::Go },
            Phase::Item => ScanShow::Item(self.k),
        }
    }

    /// A press, where the glass shows `shown` (the line as drawn, which
    /// may trail the scan by a frame on the chip; `None`: as the scan is).
    pub fn press(&mut self, lay: &Layout, sweep: u16, shown: Option<ScanShow>) -> ScanPress {
        let now = self.show(lay, sweep);
        let at = match (now, shown) {
            (ScanShow::Column(_), Some(s @ ScanShow::Column(_))) | (ScanShow::Row(_), Some(s @ ScanShow::Row(_))) => s,
            _ => now,
        };
        match at {
            ScanShow::Column(x) => {
                self.x = x;
                self.phase = Phase::Row;
                self.frame = 0;
                self.k = 0;
                ScanPress::Column(x)
            }
            ScanShow::Row(y) => {
                self.y = y;
                self.phase = Phase::Go;
                self.frame = 0;
                self.k = 0;
                ScanPress::Row(y)
            }
            ScanShow::Target { x, y, go } => {
                self.restart();
                if go {
                    ScanPress::Go(x, y)
                } else {
                    ScanPress::Cancel
                }
            }
            ScanShow::Item(i) => {
                self.restart();
                ScanPress::Item(i)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    extern crate std;

    use super::*;
    use std::collections::BTreeSet;

    const ALL: u8 = (1 << ITEMS) - 1;

    #[test]
    fn the_line_crosses_every_column_and_row_within_k_sweeps() {
        for lay in [Layout::QVGA, Layout::HVGA] {
            let ws = lay.ws();
            for sweep in [100u16, 150, 224, 300, 1000] {
                let k_w = u32::from(ws.w).div_ceil(u32::from(sweep)) as u8;
                let mut cols = BTreeSet::new();
                for pass in 0..k_w {
                    for f in 0..sweep {
                        let s = Scan { phase: Phase::Column, frame: f, pass, k: 0, x: 0, y: 0 };
                        match s.show(&lay, sweep) {
                            ScanShow::Column(x) => cols.insert(x),
                            other => panic!("{other:?}"),
                        };
                    }
                }
                assert_eq!(cols.len(), usize::from(ws.w), "{lay:?} sweep {sweep}");
                assert_eq!(cols.first(), Some(&ws.x));
                assert_eq!(cols.last(), Some(&(ws.right() - 1)));
                let k_h = u32::from(ws.h).div_ceil(u32::from(sweep)) as u8;
                let mut rows = BTreeSet::new();
                for pass in 0..k_h {
                    for f in 0..sweep {
                        let s = Scan { phase: Phase::Row, frame: f, pass: 0, k: pass, x: 0, y: 0 };
                        if let ScanShow::Row(y) = s.show(&lay, sweep) {
                            rows.insert(y);
                        }
                    }
                }
                assert_eq!(rows.len(), usize::from(ws.h), "{lay:?} sweep {sweep}");
            }
        }
    }

    /// Every map pixel, on both panels and at the shortest, a middle and
    /// the longest sweep, is reached by three presses at exactly the pixel
    /// under the lines: a column press in some sweep at some frame, a row
    /// press likewise, and Go.
    #[test]
    fn every_pixel_in_three_presses() {
        for lay in [Layout::QVGA, Layout::HVGA] {
            let ws = lay.ws();
            for sweep in [100u16, 300, 1000] {
                let mut at_col = std::collections::BTreeMap::new();
                let mut at_row = std::collections::BTreeMap::new();
                for pass in 0..4u8 {
                    for f in 0..sweep {
                        let c = Scan { phase: Phase::Column, frame: f, pass, k: 0, x: 0, y: 0 };
                        if let ScanShow::Column(x) = c.show(&lay, sweep) {
                            at_col.entry(x).or_insert((pass, f));
                        }
                        let r = Scan { phase: Phase::Row, frame: f, pass: 0, k: pass, x: 0, y: 0 };
                        if let ScanShow::Row(y) = r.show(&lay, sweep) {
                            at_row.entry(y).or_insert((pass, f));
                        }
                    }
                }
                for x in ws.x..ws.right() {
                    for y in ws.y..ws.bottom() {
                        let (pc, fc) = at_col[&x];
                        let (pr, fr) = at_row[&y];
                        let mut s = Scan { phase: Phase::Column, frame: fc, pass: pc, k: 0, x: 0, y: 0 };
                        assert_eq!(s.press(&lay, sweep, None), ScanPress::Column(x));
                        // The row sweeps that follow: `pr` unpressed ones,
                        // then `fr` frames into the next.
                        for _ in 0..u32::from(pr) * u32::from(sweep) + u32::from(fr) {
                            s.tick(sweep, 0, true);
                        }
                        assert_eq!(s.press(&lay, sweep, None), ScanPress::Row(y));
                        assert_eq!(s.press(&lay, sweep, None), ScanPress::Go(x, y), "{lay:?} {sweep}");
                    }
                }
            }
        }
    }

    #[test]
    fn the_line_moves_at_the_sweeps_speed() {
        // 224 columns in 300 frames: frame f shows ⌊224 f / 300⌋ (k = 1).
        let lay = Layout::QVGA;
        let mut s = Scan::START;
        for f in 0..300u32 {
            assert_eq!(s.show(&lay, 300), ScanShow::Column((224 * f / 300) as i16));
            s.tick(300, ALL, true);
        }
        // The sweep ended unpressed: the first button is highlighted.
        assert_eq!(s.show(&lay, 300), ScanShow::Item(0));
    }

    #[test]
    fn three_presses_pick_the_pixel_under_the_lines() {
        let lay = Layout::QVGA;
        let sweep = 300;
        let mut s = Scan::START;
        for _ in 0..150 {
            s.tick(sweep, ALL, true);
        }
        assert_eq!(s.press(&lay, sweep, None), ScanPress::Column(112));
        for _ in 0..75 {
            s.tick(sweep, ALL, true);
        }
        // 75 of 300 frames up the 112 rows: 28 rows up from the bottom row 111.
        assert_eq!(s.press(&lay, sweep, None), ScanPress::Row(111 - 28));
        assert_eq!(s.show(&lay, sweep), ScanShow::Target { x: 112, y: 83, go: true });
        assert_eq!(s.press(&lay, sweep, None), ScanPress::Go(112, 83));
        assert_eq!(s.show(&lay, sweep), ScanShow::Column(0));
    }

    #[test]
    fn the_glass_line_wins_over_the_scan_when_they_differ() {
        let lay = Layout::QVGA;
        let mut s = Scan::START;
        for _ in 0..10 {
            s.tick(100, ALL, true);
        }
        assert_eq!(s.press(&lay, 100, Some(ScanShow::Column(17))), ScanPress::Column(17));
    }

    #[test]
    fn go_and_cancel_alternate_twice_then_cancel() {
        let lay = Layout::QVGA;
        let sweep = 300;
        let d = dwell(sweep);
        assert_eq!(d, 60);
        let mut s = Scan { phase: Phase::Go, frame: 0, pass: 0, k: 0, x: 5, y: 6 };
        let mut seen = std::vec::Vec::new();
        for _ in 0..4 * d {
            let go = matches!(s.show(&lay, sweep), ScanShow::Target { go: true, .. });
            if seen.last() != Some(&go) {
                seen.push(go);
            }
            s.tick(sweep, ALL, true);
        }
        assert_eq!(seen, [true, false, true, false]);
        assert_eq!(s.show(&lay, sweep), ScanShow::Column(0));
        let mut c = Scan { phase: Phase::Cancel, frame: 0, pass: 0, k: 0, x: 5, y: 6 };
        assert_eq!(c.press(&lay, sweep, None), ScanPress::Cancel);
    }

    #[test]
    fn items_follow_in_order_skipping_what_cannot_be_pressed() {
        let lay = Layout::QVGA;
        let sweep = 100;
        let items = 0b00_1101; // 0, 2, 3 (not 1, 4, STOP)
        let mut s = Scan::START;
        let mut seen = std::vec::Vec::new();
        for _ in 0..(sweep + 3 * dwell(sweep)) {
            if let ScanShow::Item(i) = s.show(&lay, sweep) {
                if seen.last() != Some(&i) {
                    seen.push(i);
                }
            }
            s.tick(sweep, items, true);
        }
        assert_eq!(seen, [0, 2, 3]);
        // Then the map again, one sweep later (its sub-step offset).
        assert_eq!(s.show(&lay, sweep), ScanShow::Column(0));
        assert_eq!(s.pass, 1);
    }

    #[test]
    fn while_stopped_only_items_are_scanned() {
        let lay = Layout::QVGA;
        let mut s = Scan::START;
        let items = 1 << STOP_ITEM | 1;
        s.tick(100, items, false);
        assert_eq!(s.show(&lay, 100), ScanShow::Item(0));
        for _ in 0..dwell(100) {
            s.tick(100, items, false);
        }
        assert_eq!(s.show(&lay, 100), ScanShow::Item(STOP_ITEM));
        for _ in 0..dwell(100) {
            s.tick(100, items, false);
        }
        assert_eq!(s.show(&lay, 100), ScanShow::Item(0));
        for _ in 0..dwell(100) {
            s.tick(100, items, false);
        }
        assert_eq!(s.press(&lay, 100, None), ScanPress::Item(STOP_ITEM));
    }
}
