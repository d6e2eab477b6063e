//! Which of the known panel wirings (a, b, c: [`PanelPinout`]) a shield has,
//! found by measurement instead of an ohmmeter.
//!
//! With nobody touching the panel, every pair of a digital candidate (D6..D9,
//! driven low) and an analog one (A1..A3, pulled up and read by the ADC) is
//! measured: the two ends of one plate (a few hundred ohms against the
//! 20–50 kΩ pull-up) read under 20 counts, an open pair 1023. A wiring is
//! identified when its two plates (X+ to X−, Y− to Y+) are exactly the pairs
//! that read as plates and all ten others read open; anything else (a pair
//! in between, a plate where no preset has one, a missing plate) is
//! [`WiringUnknown`], never a guess.
//!
//! Wirings b and c are the same two plates (D6–A2 and D7–A1) with X and Y
//! exchanged and both directions reversed, so no measurement of the pins can
//! tell them apart; both read the panel correctly once the touch calibration
//! has set the swap and the inversions (the calibration screen does). Such a
//! shield is identified as b, the first preset that matches.
//!
//! Noise: each pair is read [`READS_PER_PAIR`] times and the median counts,
//! so one glitched conversion per pair cannot flip a verdict; a median
//! between [`PLATE_BELOW`] and [`OPEN_ABOVE`] is neither and makes the
//! result unknown.
//!
//! [`Probe`] is the measurement as a sequence of single reads, so the
//! firmware can run it all at once at boot (before any servo pulse) or one
//! read per frame while the arm holds a pose (from the calibration screen).
//! The reads themselves are the board's (`ShieldBus::plate_link`).

use crate::seam::pins::{mega, PanelPinout, Pin, Port};

/// The preset wirings of the pin map.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wiring {
    /// (a) XP = D8, XM = A2, YP = A3, YM = D9.
    A,
    /// (b) XP = D6, XM = A2, YP = A1, YM = D7.
    B,
    /// (c) XP = D7, XM = A1, YP = A2, YM = D6.
    C,
}

impl Wiring {
    /// Every preset, in the order [`identify`] tries them.
    pub const ALL: [Wiring; 3] = [Wiring::A, Wiring::B, Wiring::C];

    /// The byte stored in the EEPROM record: 1, 2, 3 (0 is "none stored").
    /// Never renumber.
    pub fn id(self) -> u8 {
        match self {
            Wiring::A => 1,
            Wiring::B => 2,
            Wiring::C => 3,
        }
    }

    /// The wiring stored as `id`; `None` for 0 or an unknown byte.
    pub fn from_id(id: u8) -> Option<Wiring> {
        Wiring::ALL.iter().copied().find(|w| w.id() == id)
    }

    /// The letter the docs and the serial lines use.
    pub fn name(self) -> crate::text::Text {
        match self {
            Wiring::A => t!("a"),
            Wiring::B => t!("b"),
            Wiring::C => t!("c"),
        }
    }

    /// Which pins carry the four electrodes.
    pub fn pinout(self) -> &'static PanelPinout {
        match self {
            Wiring::A => &PanelPinout::A,
            Wiring::B => &PanelPinout::B,
            Wiring::C => &PanelPinout::C,
        }
    }

    /// The pairs that form plates under this wiring, as a mask over
    /// [`pair_index`].
    pub const fn plates(self) -> u16 {
        // Constants: on the chip a table of pinouts would sit in SRAM.
        const A: u16 = plates_of(&PanelPinout::A);
        const B: u16 = plates_of(&PanelPinout::B);
        const C: u16 = plates_of(&PanelPinout::C);
        match self {
            Wiring::A => A,
            Wiring::B => B,
            Wiring::C => C,
        }
    }
}

const fn plates_of(p: &PanelPinout) -> u16 {
    bit(p.xp, p.xm) | bit(p.ym, p.yp)
}

/// Pins the presets drive (their X+ and Y− electrodes).
pub const DRIVES: [Pin; 4] = [mega::D6, mega::D7, mega::D8, mega::D9];
/// Pins the presets sense (their X− and Y+ electrodes, all analog).
pub const SENSES: [Pin; 3] = [mega::A1, mega::A2, mega::A3];
/// Drive–sense pairs measured.
pub const PAIRS: usize = DRIVES.len() * SENSES.len();
/// Reads per pair; the median decides.
pub const READS_PER_PAIR: usize = 3;
/// Reads of a whole probe.
pub const READS: usize = PAIRS * READS_PER_PAIR;
/// A median below this is a plate: a plate of up to ~10 kΩ against the
/// 20–50 kΩ pull-up reads under a third of full scale.
pub const PLATE_BELOW: u16 = 256;
/// A median above this is an open pair (the pull-up alone reads 1023).
pub const OPEN_ABOVE: u16 = 768;

const fn position(pins: &[Pin], p: Pin) -> Option<usize> {
    let mut i = 0;
    while i < pins.len() {
        if pins[i].bit() == p.bit() && pins[i].port() as u8 == p.port() as u8 {
            return Some(i);
        }
        i += 1;
    }
    None
}

/// The index of the pair (`drive`, `sense`): drive-major over [`DRIVES`] and
/// [`SENSES`]; `None` if either is not a candidate.
pub const fn pair_index(drive: Pin, sense: Pin) -> Option<usize> {
    match (position(&DRIVES, drive), position(&SENSES, sense)) {
        (Some(d), Some(s)) => Some(d * SENSES.len() + s),
        _ => None,
    }
}

/// The candidates are consecutive bits of one port each (D6..D9 = PH3..PH6,
/// A1..A3 = PF1..PF3), so [`pair`] computes a pair instead of reading a
/// table, which on the chip would sit in SRAM.
const fn drive_pin(d: usize) -> Pin {
    Pin::new(Port::H, 3 + d as u8)
}
const fn sense_pin(s: usize) -> Pin {
    Pin::new(Port::F, 1 + s as u8)
}
const _: () = {
    let mut i = 0;
    while i < DRIVES.len() {
        assert!(matches!(position(&DRIVES, drive_pin(i)), Some(k) if k == i));
        i += 1;
    }
    let mut i = 0;
    while i < SENSES.len() {
        assert!(matches!(position(&SENSES, sense_pin(i)), Some(k) if k == i));
        i += 1;
    }
};

/// The pair at `index` (see [`pair_index`]).
pub fn pair(index: usize) -> Option<(Pin, Pin)> {
    (index < PAIRS).then(|| (drive_pin(index / SENSES.len()), sense_pin(index % SENSES.len())))
}

const fn bit(drive: Pin, sense: Pin) -> u16 {
    match pair_index(drive, sense) {
        Some(i) => 1 << i,
        None => 0,
    }
}

/// Every pair's bit.
pub const ALL_PAIRS: u16 = (1 << PAIRS) - 1;

/// What the probe measured: which pairs read as plates and which as open
/// (bit [`pair_index`]); a pair in neither read in between or failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Links {
    /// Pairs whose median read below [`PLATE_BELOW`].
    pub plate: u16,
    /// Pairs whose median read above [`OPEN_ABOVE`].
    pub open: u16,
}

/// No preset matches what was measured.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WiringUnknown(pub Links);

impl Links {
    /// True if `w`'s plates are exactly the plate pairs and every other pair
    /// is open.
    pub fn fit(&self, w: Wiring) -> bool {
        self.plate == w.plates() && self.open == ALL_PAIRS & !w.plates()
    }
}

/// The first preset that fits what was measured ([`Links::fit`]).
pub fn identify(links: &Links) -> Result<Wiring, WiringUnknown> {
    Wiring::ALL.iter().copied().find(|w| links.fit(*w)).ok_or(WiringUnknown(*links))
}

/// The median of three.
fn median(r: &[u16; READS_PER_PAIR]) -> u16 {
    let [a, b, c] = *r;
    a.max(b).min(a.min(b).max(c))
}

/// The measurement, one read at a time (see the module doc).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Probe {
    /// Reads recorded so far, 0..=[`READS`].
    done: u8,
    reads: [u16; READS_PER_PAIR],
    links: Links,
}

impl Default for Probe {
    fn default() -> Self {
        Self::new()
    }
}

impl Probe {
    /// Nothing measured yet.
    pub const fn new() -> Probe {
        Probe { done: 0, reads: [0; READS_PER_PAIR], links: Links { plate: 0, open: 0 } }
    }

    /// The pair to read next (drive, sense), or `None` when finished.
    pub fn next(&self) -> Option<(Pin, Pin)> {
        pair(usize::from(self.done) / READS_PER_PAIR)
    }

    /// Records the read of the pair [`Probe::next`] named: the ADC count, or
    /// `None` for a failed conversion (the pair then reads neither plate nor
    /// open, so the result is unknown).
    pub fn record(&mut self, count: Option<u16>) {
        let i = usize::from(self.done);
        if i >= READS {
            return;
        }
        // A failed read counts as mid-scale: neither verdict.
        let v = count.unwrap_or(PLATE_BELOW + (OPEN_ABOVE - PLATE_BELOW) / 2);
        if let Some(slot) = self.reads.get_mut(i % READS_PER_PAIR) {
            *slot = v;
        }
        if i % READS_PER_PAIR == READS_PER_PAIR - 1 {
            let m = median(&self.reads);
            let b = 1u16 << (i / READS_PER_PAIR);
            if m < PLATE_BELOW {
                self.links.plate |= b;
            } else if m > OPEN_ABOVE {
                self.links.open |= b;
            }
        }
        self.done += 1;
    }

    /// The pairs decided so far.
    pub fn links(&self) -> Links {
        self.links
    }

    /// The verdict once every pair is read.
    pub fn result(&self) -> Option<Result<Wiring, WiringUnknown>> {
        (usize::from(self.done) >= READS).then(|| identify(&self.links))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Reads a panel whose plates are `plates` (mask), with `noise(i)` added
    /// to the i-th read.
    fn run(plates: u16, noise: impl Fn(usize) -> i32) -> Option<Result<Wiring, WiringUnknown>> {
        let mut p = Probe::new();
        let mut i = 0;
        while let Some((d, s)) = p.next() {
            let base = if plates & bit(d, s) != 0 { 14 } else { 1023 };
            p.record(Some((base + noise(i)).clamp(0, 1023) as u16));
            i += 1;
        }
        assert_eq!(i, READS);
        p.result()
    }

    #[test]
    fn each_preset_has_its_own_two_plates_except_b_and_c() {
        // a: D8–A2 (pair 2·3+1 = 7), D9–A3 (3·3+2 = 11).
        assert_eq!(Wiring::A.plates(), 1 << 7 | 1 << 11);
        // b: D6–A2 (1), D7–A1 (3); c: D7–A1, D6–A2: the same pairs.
        assert_eq!(Wiring::B.plates(), 1 << 1 | 1 << 3);
        assert_eq!(Wiring::C.plates(), Wiring::B.plates());
    }

    #[test]
    fn a_clean_panel_is_identified() {
        assert_eq!(run(Wiring::A.plates(), |_| 0), Some(Ok(Wiring::A)));
        assert_eq!(run(Wiring::B.plates(), |_| 0), Some(Ok(Wiring::B)));
    }

    #[test]
    fn one_glitch_per_pair_is_outvoted() {
        // Every pair's first read is a full-scale glitch the other way.
        let plates = Wiring::A.plates();
        let r = run(plates, |i| {
            if i % READS_PER_PAIR == 0 {
                if plates & (1 << (i / 3)) != 0 {
                    1000
                } else {
                    -1000
                }
            } else {
                0
            }
        });
        assert_eq!(r, Some(Ok(Wiring::A)));
    }

    #[test]
    fn anything_but_two_preset_plates_is_unknown() {
        // One plate only, an extra link, no plates at all.
        for plates in [1 << 7, Wiring::A.plates() | 1, 0, Wiring::A.plates() | Wiring::B.plates()] {
            let r = run(plates, |_| 0).unwrap();
            assert_eq!(r, Err(WiringUnknown(Links { plate: plates, open: ALL_PAIRS & !plates })), "{plates:#x}");
        }
        // A pair whose median is mid-scale is neither: unknown.
        let r = run(Wiring::A.plates(), |i| if i / 3 == 0 { -500 } else { 0 }).unwrap();
        assert_eq!(
            r,
            Err(WiringUnknown(Links { plate: Wiring::A.plates(), open: ALL_PAIRS & !Wiring::A.plates() & !1 }))
        );
        // A failed conversion counts as mid-scale.
        let mut p = Probe::new();
        while let Some((d, s)) = p.next() {
            p.record((pair_index(d, s) != Some(5)).then_some(if Wiring::A.plates() & bit(d, s) != 0 {
                14
            } else {
                1023
            }));
        }
        assert!(p.result().unwrap().is_err());
    }

    #[test]
    fn ids_round_trip_and_zero_is_none() {
        for w in Wiring::ALL {
            assert_eq!(Wiring::from_id(w.id()), Some(w));
        }
        assert_eq!(Wiring::from_id(0), None);
        assert_eq!(Wiring::from_id(4), None);
        assert_eq!(pair(PAIRS), None);
        assert_eq!(pair_index(mega::A1, mega::D6), None);
    }
}
