//! An electrical model of the 4-wire resistive touch panel, at the level of
//! its four terminals: given how the firmware drives XP, XM, YP and YM (high,
//! low or floating) it says what an ADC sampling one terminal reads. The same
//! model serves the simavr harness (it sees the real pin registers) and any
//! host-side twin that wants terminal-level behaviour.
//!
//! The X sheet runs from XM (0) to XP (1), the Y sheet from YM (0) to YP (1).
//! A touch at sheet fractions (u, v) joins the sheets through a contact
//! resistance that falls as the finger presses harder.

use crate::avr::{AdcRequest, Pin, PortsSnapshot};

/// How one terminal is driven.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Drive {
    High,
    Low,
    /// Input without pull-up: no current flows through it.
    Float,
}

/// The four terminals.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Terminal {
    Xp,
    Xm,
    Yp,
    Ym,
}

/// A touch on the sheets.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Fractions along the X and Y sheets, 0..=1.
    pub u: f64,
    pub v: f64,
    /// Contact resistance in ohms (≈ 100–1000 Ω for a finger; large = light).
    pub r_touch: f64,
}

/// Sheet resistances and the ADC's full scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sheets {
    pub r_x: f64,
    pub r_y: f64,
}

impl Default for Sheets {
    fn default() -> Self {
        // Typical 2.8" shield panels measure 300–700 Ω per sheet.
        Sheets { r_x: 350.0, r_y: 550.0 }
    }
}

/// The ADC fraction of the supply (0..=1) a terminal reads, or `None` when the
/// terminal is floating and nothing defines its voltage (an unconnected
/// input: the real ADC returns whatever charge is left).
pub fn terminal_fraction(sheets: &Sheets, contact: Option<&Contact>, drive: [Drive; 4], read: Terminal) -> Option<f64> {
    let [xp, xm, yp, ym] = drive;
    let idx = |t: Terminal| t as usize;
    // A driven terminal reads its own level.
    match drive[idx(read)] {
        Drive::High => return Some(1.0),
        Drive::Low => return Some(0.0),
        Drive::Float => {}
    }
    let level = |d: Drive| match d {
        Drive::High => Some(1.0),
        Drive::Low => Some(0.0),
        Drive::Float => None,
    };
    let on_x = matches!(read, Terminal::Xp | Terminal::Xm);
    // Voltage along a sheet driven at both ends: linear in position.
    let x_gradient = |u: f64| Some(level(xm)? + (level(xp)? - level(xm)?) * u);
    let y_gradient = |v: f64| Some(level(ym)? + (level(yp)? - level(ym)?) * v);
    let x_driven = xp != Drive::Float && xm != Drive::Float;
    let y_driven = yp != Drive::Float && ym != Drive::Float;

    // No current flows through a floating terminal, so it reads its sheet's
    // voltage at the contact point. Without a contact, a sheet driven at one
    // end sits at that end's level; one driven at neither end is undefined.
    let Some(c) = contact else {
        let (a, b) = if on_x { (xp, xm) } else { (yp, ym) };
        return level(a).or(level(b));
    };
    if on_x && y_driven {
        // X sheet floats, touching the driven Y sheet at v.
        return y_gradient(c.v);
    }
    if !on_x && x_driven {
        return x_gradient(c.u);
    }
    // Cross-sheet drive (the pressure measurement): one terminal of each
    // sheet driven, current flows from one sheet through the contact into
    // the other. Each sheet's floating terminal reads its sheet's voltage at
    // the contact point.
    let (x_end, x_len) = match (xp, xm) {
        (d, Drive::Float) if d != Drive::Float => (level(d)?, sheets.r_x * (1.0 - c.u)),
        (Drive::Float, d) if d != Drive::Float => (level(d)?, sheets.r_x * c.u),
        _ => return None,
    };
    let (y_end, y_len) = match (yp, ym) {
        (d, Drive::Float) if d != Drive::Float => (level(d)?, sheets.r_y * (1.0 - c.v)),
        (Drive::Float, d) if d != Drive::Float => (level(d)?, sheets.r_y * c.v),
        _ => return None,
    };
    let total = x_len + c.r_touch + y_len;
    let i = (y_end - x_end) / total;
    let at_x = x_end + i * x_len;
    let at_y = y_end - i * y_len;
    Some(if on_x { at_x } else { at_y })
}

/// Which MCU pins carry the panel's terminals, and the ADC channel of each
/// terminal that sits on an analog pin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PanelWiring {
    pub xp: (Pin, Option<u8>),
    pub xm: (Pin, Option<u8>),
    pub yp: (Pin, Option<u8>),
    pub ym: (Pin, Option<u8>),
}

impl PanelWiring {
    /// SPEC §8 wiring (a): XP = D8 (PH5), XM = A2 (PF2), YP = A3 (PF3), YM = D9 (PH6).
    pub const A: PanelWiring = PanelWiring {
        xp: (Pin::new('H', 5), None),
        xm: (Pin::new('F', 2), Some(2)),
        yp: (Pin::new('F', 3), Some(3)),
        ym: (Pin::new('H', 6), None),
    };
    /// Wiring (b): XP = D6 (PH3), XM = A2 (PF2), YP = A1 (PF1), YM = D7 (PH4).
    pub const B: PanelWiring = PanelWiring {
        xp: (Pin::new('H', 3), None),
        xm: (Pin::new('F', 2), Some(2)),
        yp: (Pin::new('F', 1), Some(1)),
        ym: (Pin::new('H', 4), None),
    };
    /// Wiring (c): XP = D7 (PH4), XM = A1 (PF1), YP = A2 (PF2), YM = D6 (PH3).
    pub const C: PanelWiring = PanelWiring {
        xp: (Pin::new('H', 4), None),
        xm: (Pin::new('F', 1), Some(1)),
        yp: (Pin::new('F', 2), Some(2)),
        ym: (Pin::new('H', 3), None),
    };

    fn terminals(&self) -> [(Terminal, Pin, Option<u8>); 4] {
        [
            (Terminal::Xp, self.xp.0, self.xp.1),
            (Terminal::Xm, self.xm.0, self.xm.1),
            (Terminal::Yp, self.yp.0, self.yp.1),
            (Terminal::Ym, self.ym.0, self.ym.1),
        ]
    }

    /// How the firmware drives each terminal, from the port registers.
    pub fn drives(&self, ports: &PortsSnapshot) -> [Drive; 4] {
        self.terminals().map(|(_, pin, _)| match ports.get(pin.port) {
            Some(p) if p.is_output(pin.bit) => {
                if p.port >> pin.bit & 1 == 1 {
                    Drive::High
                } else {
                    Drive::Low
                }
            }
            // An input with its pull-up on is a weak high: ignore the ~35 kΩ
            // against the sheets' hundreds of ohms (the firmware never does it
            // while measuring).
            _ => Drive::Float,
        })
    }

    /// The terminal an ADC channel samples, if it is one of the panel's.
    pub fn terminal_on_channel(&self, channel: u8) -> Option<Terminal> {
        self.terminals().into_iter().find(|(_, _, ch)| *ch == Some(channel)).map(|(t, _, _)| t)
    }
}

/// A deterministic noise source (xorshift64*), so simulated runs repeat.
#[derive(Debug, Clone)]
pub struct Noise(u64);

impl Noise {
    pub fn new(seed: u64) -> Self {
        Noise(seed.max(1))
    }

    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Approximately normal (sum of four uniforms), zero mean, given sigma.
    pub fn gaussian(&mut self, sigma: f64) -> f64 {
        let s: f64 = (0..4).map(|_| self.uniform()).sum::<f64>() - 2.0;
        s * sigma * (3.0f64).sqrt()
    }
}

/// The panel as the simavr ADC sees it: the wiring, the sheets, the current
/// touch (if any), and noise in ADC counts.
pub struct PanelModel {
    pub wiring: PanelWiring,
    pub sheets: Sheets,
    pub contact: Option<Contact>,
    /// Standard deviation of the reading noise, in ADC counts.
    pub noise_counts: f64,
    noise: Noise,
}

impl PanelModel {
    pub fn new(wiring: PanelWiring, seed: u64) -> Self {
        PanelModel { wiring, sheets: Sheets::default(), contact: None, noise_counts: 1.5, noise: Noise::new(seed) }
    }

    /// The 10-bit reading for an ADC request, or `None` when the channel is
    /// not one of the panel's.
    pub fn read(&mut self, req: &AdcRequest<'_>) -> Option<u16> {
        let t = self.wiring.terminal_on_channel(req.channel)?;
        let drive = self.wiring.drives(req.ports);
        let frac = match terminal_fraction(&self.sheets, self.contact.as_ref(), drive, t) {
            Some(f) => f,
            // A floating, unconnected input: leftover charge, anywhere.
            None => self.noise.uniform(),
        };
        let counts = frac * 1023.0 + self.noise.gaussian(self.noise_counts);
        Some(counts.round().clamp(0.0, 1023.0) as u16)
    }
}

/// Touch at raw-ADC coordinates (what the firmware's X and Y reads should
/// return without noise) with a contact resistance.
pub fn contact_at_raw(raw_x: f64, raw_y: f64, r_touch: f64) -> Contact {
    Contact { u: raw_x / 1023.0, v: raw_y / 1023.0, r_touch }
}
