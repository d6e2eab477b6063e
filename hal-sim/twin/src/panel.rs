//! The 4-wire resistive panel: two resistive plates, X between the XM and XP
//! electrodes and Y between YM and YP, that touch at one point through a
//! contact resistance when pressed.
//!
//! [`PanelModel::voltage`] solves that resistor network for *any* drive
//! pattern (each of the four pins high, low or floating), so the same model
//! answers the firmware's standard reads here and whatever the simavr harness
//! sees the real firmware do to the pins. A pin whose plate connects to no
//! driven pin floats: its voltage is undefined and the ADC reads noise.
//!
//! The standard reads (docs/hardware.md), with the contact at fraction `fx` of the X
//! plate from XM and `fy` of the Y plate from YM:
//! - X: XP high, XM low, Y floating, read YP → `fx` (no current in the Y plate).
//! - Y: YP high, YM low, X floating, read XM → `fy`.
//! - pressure: XP low, YM high, read z1 on XM and z2 on YP; current flows YM →
//!   Y plate → contact → X plate → XP, so z1 = Rx(1−fx)/R, z2 = (Rt + Rx(1−fx))/R
//!   with R = Ry·fy + Rt + Rx(1−fx), and `1023 + z1 − z2` ∝ 1 − Rt/R grows as
//!   the contact resistance Rt falls (a firmer touch). Untouched, z1 = 0 and
//!   z2 = 1023: pressure 0.

use touch_arm::seam::RawSample;
use touch_arm::seam::{TouchError, TouchPanel};
use touch_arm::touch::filter::{pressure, ADC_MAX};
use touch_arm::touch::map::Calibration;

use super::finger::{FingerScript, Glass};
use super::rng::Rng;

/// Time between two conversions of a panel read on the chip, s: 104 µs of
/// conversion (13 ADC clocks at 125 kHz) after the driver's 20 µs plate and
/// 10 µs channel settle (`board::touch`, `board::adc`), rounded. The twin
/// spaces its conversions by this; the simavr rig uses each conversion's own
/// cycle instead.
pub const CONVERSION_S: f64 = 125e-6;

/// State of one panel pin.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Drive {
    /// Output high (Vcc).
    High,
    /// Output low (ground).
    Low,
    /// Input, high impedance (the ADC input draws no current).
    Float,
    /// Input with the internal pull-up: [`R_PULLUP`] to Vcc.
    PullUp,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
/// One of the panel's four terminals: the ends of the X plate (XP, XM) and of the Y plate (YP, YM).
pub enum Pin {
    /// X plate, plus end.
    Xp,
    /// X plate, minus end.
    Xm,
    /// Y plate, plus end.
    Yp,
    /// Y plate, minus end.
    Ym,
}

/// How the firmware has configured the four panel pins.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PanelPins {
    /// How XP is driven.
    pub xp: Drive,
    /// How XM is driven.
    pub xm: Drive,
    /// How YP is driven.
    pub yp: Drive,
    /// How YM is driven.
    pub ym: Drive,
}

impl PanelPins {
    /// X read: XP high, XM low, Y floating (read YP).
    pub const READ_X: PanelPins = PanelPins { xp: Drive::High, xm: Drive::Low, yp: Drive::Float, ym: Drive::Float };
    /// Y read: YP high, YM low, X floating (read XM).
    pub const READ_Y: PanelPins = PanelPins { xp: Drive::Float, xm: Drive::Float, yp: Drive::High, ym: Drive::Low };
    /// Pressure read: XP low, YM high (read XM for z1, YP for z2).
    pub const READ_Z: PanelPins = PanelPins { xp: Drive::Low, xm: Drive::Float, yp: Drive::Float, ym: Drive::High };
}

/// Where and how firmly the panel is pressed.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// Position along the X plate, 0 at XM, 1 at XP.
    pub fx: f64,
    /// Position along the Y plate, 0 at YM, 1 at YP.
    pub fy: f64,
    /// Contact resistance between the plates, Ω.
    pub r_touch: f64,
}

/// The plates and the current contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PanelModel {
    /// Plate resistances, Ω (typical panels: a few hundred).
    pub rx: f64,
    /// The Y plate's resistance, Ω.
    pub ry: f64,
    /// The finger's contact between the plates; `None`: not touched.
    pub contact: Option<Contact>,
    /// A second contact (a palm, a knuckle, another finger), if any: the
    /// network then has two paths between the plates.
    pub second: Option<Contact>,
}

/// Contact resistance of a touch of force 1 (a firm fingertip).
pub const R_TOUCH_FIRM: f64 = 100.0;
/// Keeps a contact at an electrode from making a zero resistor.
const R_MIN: f64 = 1e-3;
/// The ATmega2560's I/O pull-up (datasheet: 20–50 kΩ).
pub const R_PULLUP: f64 = 35_000.0;

const NODES: usize = 9;
const XP: usize = 0;
const XM: usize = 1;
const YP: usize = 2;
const YM: usize = 3;
const CX: usize = 4;
const CY: usize = 5;
/// Vcc, the far end of the pull-ups.
const VCC: usize = 6;
/// The second contact's points on the X and Y plates.
const CX2: usize = 7;
const CY2: usize = 8;

impl Default for PanelModel {
    fn default() -> Self {
        PanelModel { rx: 300.0, ry: 500.0, contact: None, second: None }
    }
}

impl PanelModel {
    /// Resistors of the network as (node, node, Ω): the plates, the contact
    /// and the pull-ups that `pins` enables.
    fn resistors(&self, pins: &PanelPins) -> Vec<(usize, usize, f64)> {
        let mut res = self.plates();
        for (node, d) in [(XP, pins.xp), (XM, pins.xm), (YP, pins.yp), (YM, pins.ym)] {
            if d == Drive::PullUp {
                res.push((node, VCC, R_PULLUP));
            }
        }
        res
    }

    /// Each plate is cut at its contact points (in order along it) into
    /// segments; each contact joins its two points through its resistance.
    fn plates(&self) -> Vec<(usize, usize, f64)> {
        let contacts: Vec<(Contact, usize, usize)> = [(self.contact, CX, CY), (self.second, CX2, CY2)]
            .into_iter()
            .filter_map(|(c, x, y)| Some((c?, x, y)))
            .collect();
        let mut res = Vec::new();
        for (lo, hi, r, x_plate) in [(XM, XP, self.rx, true), (YM, YP, self.ry, false)] {
            let mut points: Vec<(f64, usize)> =
                contacts.iter().map(|(c, nx, ny)| if x_plate { (c.fx, *nx) } else { (c.fy, *ny) }).collect();
            points.sort_by(|a, b| a.0.total_cmp(&b.0));
            let (mut at, mut node) = (0.0, lo);
            for (f, n) in points {
                res.push((node, n, (r * (f - at)).max(R_MIN)));
                (at, node) = (f, n);
            }
            res.push((node, hi, (r * (1.0 - at)).max(R_MIN)));
        }
        for (c, nx, ny) in &contacts {
            res.push((*nx, *ny, c.r_touch.max(R_MIN)));
        }
        res
    }

    /// Voltage of `pin` as a fraction of Vcc, or `None` if it floats (no
    /// resistive path to a driven pin).
    pub fn voltage(&self, pins: &PanelPins, pin: Pin) -> Option<f64> {
        let mut fixed: [Option<f64>; NODES] = [None; NODES];
        fixed[VCC] = Some(1.0);
        for (node, d) in [(XP, pins.xp), (XM, pins.xm), (YP, pins.yp), (YM, pins.ym)] {
            fixed[node] = match d {
                Drive::High => Some(1.0),
                Drive::Low => Some(0.0),
                Drive::Float | Drive::PullUp => None,
            };
        }
        let res = self.resistors(pins);
        // Nodes connected to a driven node (union over the resistors).
        let mut reach: [bool; NODES] = [false; NODES];
        for (i, f) in fixed.iter().enumerate() {
            reach[i] = f.is_some();
        }
        for _ in 0..NODES {
            for &(a, b, _) in &res {
                if reach[a] || reach[b] {
                    reach[a] = true;
                    reach[b] = true;
                }
            }
        }
        let target = match pin {
            Pin::Xp => XP,
            Pin::Xm => XM,
            Pin::Yp => YP,
            Pin::Ym => YM,
        };
        if !reach[target] {
            return None;
        }
        if let Some(v) = fixed[target] {
            return Some(v);
        }
        // Nodal analysis over the unknown, connected nodes.
        let unknown: Vec<usize> = (0..NODES).filter(|&i| fixed[i].is_none() && reach[i]).collect();
        let idx = |node: usize| unknown.iter().position(|&u| u == node);
        let m = unknown.len();
        let mut a = vec![vec![0.0f64; m + 1]; m];
        for &(p, q, r) in &res {
            let g = 1.0 / r;
            for (this, other) in [(p, q), (q, p)] {
                if let Some(i) = idx(this) {
                    a[i][i] += g;
                    match (idx(other), fixed[other]) {
                        (Some(j), _) => a[i][j] -= g,
                        (None, Some(v)) => a[i][m] += g * v,
                        (None, None) => {}
                    }
                }
            }
        }
        let x = solve(a)?;
        idx(target).map(|i| x[i])
    }
}

/// Gaussian elimination with partial pivoting on an augmented matrix.
fn solve(mut a: Vec<Vec<f64>>) -> Option<Vec<f64>> {
    let m = a.len();
    for col in 0..m {
        let piv = (col..m).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[piv][col].abs() < 1e-15 {
            return None;
        }
        a.swap(col, piv);
        let pivot = a[col].clone();
        for (row, r) in a.iter_mut().enumerate() {
            if row != col {
                let f = r[col] / pivot[col];
                for (x, p) in r[col..=m].iter_mut().zip(&pivot[col..=m]) {
                    *x -= f * p;
                }
            }
        }
    }
    Some((0..m).map(|i| a[i][m] / a[i][i]).collect())
}

/// The panel as the firmware's touch driver sees it: the model, where screen
/// points land on it, and ADC noise.
#[derive(Debug, Clone)]
pub struct SimPanel {
    /// The plates and the present contact.
    pub model: PanelModel,
    /// The panel's true response: screen point → raw channels (as read).
    pub cal: Calibration,
    /// Gaussian ADC noise, counts (σ).
    pub noise_counts: f64,
    /// Probability that a conversion returns a random value (a glitch).
    pub spike_prob: f64,
    rng: Rng,
    /// Samples delivered so far.
    pub samples: u64,
    /// The scripted finger and the panel time (s) its t_ms = 0 is at; while
    /// set, it decides the contacts at every conversion.
    pub finger: Option<(FingerScript, f64)>,
    /// The glass the finger's pixels lie on.
    pub glass: Glass,
    /// Panel time of the next conversion, s ([`SimPanel::set_time`]).
    pub t_s: f64,
    /// How far each conversion advances [`SimPanel::t_s`], s.
    pub conversion_s: f64,
}

impl SimPanel {
    /// An untouched panel with the default calibration and no noise; `seed` drives the noise and glitches once they are set.
    pub fn new(seed: u64) -> Self {
        SimPanel {
            model: PanelModel::default(),
            cal: Calibration::DEFAULT,
            noise_counts: 0.0,
            spike_prob: 0.0,
            rng: Rng::new(seed),
            samples: 0,
            finger: None,
            glass: Glass::QVGA_28,
            t_s: 0.0,
            conversion_s: CONVERSION_S,
        }
    }

    /// Sets the panel time of the next conversion, s.
    pub fn set_time(&mut self, t_s: f64) {
        self.t_s = t_s;
    }

    /// Plays `script` from panel time `start_s` on (replacing any finger or
    /// press); it ends by itself after its last knot.
    pub fn set_finger(&mut self, script: FingerScript, start_s: f64) {
        self.finger = Some((script, start_s));
        self.apply_finger();
    }

    /// The contacts the finger script puts on the plates at [`SimPanel::t_s`].
    fn apply_finger(&mut self) {
        let Some((script, start)) = &self.finger else { return };
        let [a, b] = script.at((self.t_s - start) * 1000.0);
        let contact = |c: Option<(f64, f64, f64)>| {
            let (x, y, force) = c?;
            let (rx, ry) = self.glass.px_to_raw(&self.cal, x, y);
            let lim = -0.5..(ADC_MAX as f64 + 0.5);
            (lim.contains(&rx) && lim.contains(&ry)).then(|| Contact {
                fx: (rx + 0.5) / 1024.0,
                fy: (ry + 0.5) / 1024.0,
                r_touch: R_TOUCH_FIRM / force,
            })
        };
        let (c1, c2) = (contact(a), contact(b));
        // One contact alone is the finger, whichever track it came from.
        (self.model.contact, self.model.second) = if c1.is_some() { (c1, c2) } else { (c2, None) };
    }

    /// Presses at raw channel values (as read, fractional allowed): an ideal
    /// noise-free read returns `floor(raw + 0.5)`.
    pub fn touch_raw(&mut self, raw_x: f64, raw_y: f64, force: f64) -> Result<(), String> {
        if !(force > 0.0 && force.is_finite()) {
            return Err(format!("force must be > 0, got {force}"));
        }
        let lim = -0.5..(ADC_MAX as f64 + 0.5);
        if !(lim.contains(&raw_x) && lim.contains(&raw_y)) {
            return Err(format!("raw point ({raw_x}, {raw_y}) is off the panel"));
        }
        self.finger = None;
        self.model.second = None;
        self.model.contact =
            Some(Contact { fx: (raw_x + 0.5) / 1024.0, fy: (raw_y + 0.5) / 1024.0, r_touch: R_TOUCH_FIRM / force });
        Ok(())
    }

    /// Presses at a normalized workspace point (through the panel's true response).
    pub fn touch_xy(&mut self, x_p: f64, y_p: f64, force: f64) -> Result<(), String> {
        let (rx, ry) = self.cal.unmap_exact::<f64>(x_p, y_p).map_err(|e| format!("point ({x_p}, {y_p}): {e:?}"))?;
        self.touch_raw(rx, ry, force)
    }

    /// Lifts the finger: no contact until the next touch.
    pub fn release(&mut self) {
        self.finger = None;
        self.model.contact = None;
        self.model.second = None;
    }

    /// One ADC conversion of `pin` with the pins driven as given.
    pub fn adc(&mut self, pins: &PanelPins, pin: Pin) -> u16 {
        self.apply_finger();
        self.t_s += self.conversion_s;
        if self.spike_prob > 0.0 && self.rng.uniform() < self.spike_prob {
            return self.rng.below(ADC_MAX as u64 + 1) as u16;
        }
        match self.model.voltage(pins, pin) {
            // A floating input reads whatever charge the sample capacitor holds.
            None => self.rng.below(ADC_MAX as u64 + 1) as u16,
            Some(v) => {
                let noise = if self.noise_counts > 0.0 { self.noise_counts * self.rng.normal() } else { 0.0 };
                let code = (v * 1024.0 + noise).floor();
                code.clamp(0.0, ADC_MAX as f64) as u16
            }
        }
    }

    /// One sample as the touch driver takes it: X, Y, then the two pressure reads.
    pub fn sample(&mut self) -> RawSample {
        let x = self.adc(&PanelPins::READ_X, Pin::Yp);
        let y = self.adc(&PanelPins::READ_Y, Pin::Xm);
        let z1 = self.adc(&PanelPins::READ_Z, Pin::Xm);
        let z2 = self.adc(&PanelPins::READ_Z, Pin::Yp);
        self.samples += 1;
        RawSample { x, y, z: pressure(z1, z2), z1 }
    }
}

impl TouchPanel for SimPanel {
    fn read(&mut self, out: &mut [RawSample]) -> Result<(), TouchError> {
        for s in out.iter_mut() {
            *s = self.sample();
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pressed(fx: f64, fy: f64, r_touch: f64) -> PanelModel {
        PanelModel { rx: 300.0, ry: 500.0, contact: Some(Contact { fx, fy, r_touch }), second: None }
    }

    #[test]
    fn standard_reads_follow_the_voltage_dividers() {
        let m = pressed(0.3, 0.8, 100.0);
        // Floating plate: no current, so the read pin sees the contact point.
        assert!((m.voltage(&PanelPins::READ_X, Pin::Yp).unwrap() - 0.3).abs() < 1e-12);
        assert!((m.voltage(&PanelPins::READ_X, Pin::Ym).unwrap() - 0.3).abs() < 1e-12);
        assert!((m.voltage(&PanelPins::READ_Y, Pin::Xm).unwrap() - 0.8).abs() < 1e-12);
        // Pressure: series YM -> Ry*fy -> Rt -> Rx*(1-fx) -> XP.
        let (a, t, b) = (500.0 * 0.8, 100.0, 300.0 * 0.7);
        let total = a + t + b;
        let z1 = m.voltage(&PanelPins::READ_Z, Pin::Xm).unwrap();
        let z2 = m.voltage(&PanelPins::READ_Z, Pin::Yp).unwrap();
        assert!((z1 - b / total).abs() < 1e-12);
        assert!((z2 - (t + b) / total).abs() < 1e-12);
        // A firmer touch (smaller Rt) gives a larger pressure measure.
        let z = |r: f64| {
            let m = pressed(0.3, 0.8, r);
            1.0 + m.voltage(&PanelPins::READ_Z, Pin::Xm).unwrap() - m.voltage(&PanelPins::READ_Z, Pin::Yp).unwrap()
        };
        assert!(z(50.0) > z(100.0) && z(100.0) > z(1000.0));
    }

    #[test]
    fn two_contacts_solve_as_the_hand_network() {
        // Finger at (0.3, 0.8) through 100 Ω, palm at (0.6, 0.2) through 40 Ω.
        let (rx, ry) = (300.0, 500.0);
        let (f1, f2) = (Contact { fx: 0.3, fy: 0.8, r_touch: 100.0 }, Contact { fx: 0.6, fy: 0.2, r_touch: 40.0 });
        let m = PanelModel { rx, ry, contact: Some(f1), second: Some(f2) };
        // X read: XM –a– CX1 –b– CX2 –c– XP, and b shunted by the path
        // CX1 –r1– CY1 –Ry·0.6– CY2 –r2– CX2 through the floating Y plate.
        let (a, b, c) = (rx * 0.3, rx * 0.3, rx * 0.4);
        let rs = 100.0 + ry * 0.6 + 40.0;
        let bp = b * rs / (b + rs);
        let i = 1.0 / (a + bp + c);
        let (v1, v2) = (i * a, i * (a + bp));
        let is = (v2 - v1) / rs;
        let (vy1, vy2) = (v1 + is * 100.0, v2 - is * 40.0);
        // YP sits beyond the contact nearer to it (fy 0.8: the finger's), no current.
        let yp = m.voltage(&PanelPins::READ_X, Pin::Yp).unwrap();
        let ym = m.voltage(&PanelPins::READ_X, Pin::Ym).unwrap();
        assert!((yp - vy1).abs() < 1e-12 && (ym - vy2).abs() < 1e-12, "{yp} {vy1} {ym} {vy2}");
        // A point between the contacts: the X read lands between 0.3 and 0.6.
        assert!(yp > 0.3 && yp < 0.6, "{yp}");
        // Pressure: YM high, XP low; two parallel paths YM → X plate. z1 on XM
        // (beyond CX1, no current) = V(CX1), z2 on YP (beyond CY1) = V(CY1).
        // Node equations at CX1, CX2, CY1, CY2 solved by hand (Cramer is long:
        // check the currents balance instead).
        let z1 = m.voltage(&PanelPins::READ_Z, Pin::Xm).unwrap();
        let z2 = m.voltage(&PanelPins::READ_Z, Pin::Yp).unwrap();
        let one = PanelModel { second: None, ..m };
        let z1_one = one.voltage(&PanelPins::READ_Z, Pin::Xm).unwrap();
        let z2_one = one.voltage(&PanelPins::READ_Z, Pin::Yp).unwrap();
        // Two contacts conduct more: a higher pressure measure than the finger alone.
        assert!(1.0 + z1 - z2 > 1.0 + z1_one - z2_one + 0.05, "{z1} {z2} vs {z1_one} {z2_one}");
        // Kirchhoff at CY2 with the solved node voltages: in from YM = out via r2 + along to CY1.
        let v = |pin| m.voltage(&PanelPins::READ_Z, pin).unwrap();
        let (vcx1, vcy1) = (v(Pin::Xm), v(Pin::Yp));
        // CX1 carries: from CY1 through r1 = to XP through the X plate (via CX2).
        let i_r1 = (vcy1 - vcx1) / 100.0;
        assert!(i_r1 > 0.0);
        // Untouched second contact: the one-contact model is unchanged.
        let single = pressed(0.3, 0.8, 100.0);
        assert_eq!(
            single.voltage(&PanelPins::READ_X, Pin::Yp),
            PanelModel { second: None, ..single }.voltage(&PanelPins::READ_X, Pin::Yp)
        );
    }

    #[test]
    fn a_finger_script_is_evaluated_at_each_conversion() {
        use crate::finger::{FingerScript, Knot, Track};
        let mut p = SimPanel::new(1);
        // Pixel (150, 100) is raw (503.48, 574.98), read as floor(raw + 0.5);
        // a slide of 8 px in x over 10 ms.
        let t = Track::new(vec![Knot::new(0.0, 150.0, 100.0, 1.0), Knot::new(10.0, 158.0, 100.0, 1.0)]).unwrap();
        p.set_time(2.0);
        p.set_finger(FingerScript::new(t, None).unwrap(), 2.0);
        let s = p.sample();
        assert_eq!((s.x, s.y), (503, 575));
        // Conversion k happens k·125 µs in: at 5 ms the finger is 4 px on.
        p.set_time(2.005);
        let x = p.adc(&PanelPins::READ_X, Pin::Yp);
        let expect = ((503.484_375f64 + 4.0 * 809.0 / 320.0) + 0.5).floor() as u16;
        assert_eq!(expect, 514);
        assert_eq!(x, expect);
        // After the script: lifted.
        p.set_time(2.011);
        assert!(p.sample().z < 5);
        // A palm beside the finger reads between the two.
        let f = Track::new(vec![Knot::new(0.0, 60.0, 60.0, 1.0), Knot::new(100.0, 60.0, 60.0, 1.0)]).unwrap();
        let palm = Track::new(vec![Knot::new(0.0, 260.0, 200.0, 3.0), Knot::new(100.0, 260.0, 200.0, 3.0)]).unwrap();
        p.set_time(0.0);
        p.set_finger(FingerScript::new(f.clone(), None).unwrap(), 0.0);
        let alone = p.sample();
        p.set_time(0.0);
        p.set_finger(FingerScript::new(f, Some(palm)).unwrap(), 0.0);
        let both = p.sample();
        let (fx, _) = Glass::QVGA_28.px_to_raw(&Calibration::DEFAULT, 60.0, 60.0);
        let (px, _) = Glass::QVGA_28.px_to_raw(&Calibration::DEFAULT, 260.0, 200.0);
        assert_eq!(alone.x, (fx + 0.5).floor() as u16);
        assert!(f64::from(both.x) > fx + 50.0 && f64::from(both.x) < px - 50.0, "{both:?} {fx} {px}");
        assert!(both.z > alone.z, "{both:?} {alone:?}");
    }

    #[test]
    fn untouched_plates_float_or_follow_their_drive() {
        let m = PanelModel::default();
        assert_eq!(m.voltage(&PanelPins::READ_X, Pin::Yp), None);
        assert_eq!(m.voltage(&PanelPins::READ_Y, Pin::Xm), None);
        // Pressure pins: each plate is tied to its own driven electrode.
        assert_eq!(m.voltage(&PanelPins::READ_Z, Pin::Xm), Some(0.0));
        assert_eq!(m.voltage(&PanelPins::READ_Z, Pin::Yp), Some(1.0));
        // Any other pattern: a driven pin reads its level, a plate without a
        // driven end floats.
        let pins = PanelPins { xp: Drive::High, xm: Drive::Float, yp: Drive::Float, ym: Drive::Float };
        assert_eq!(m.voltage(&pins, Pin::Xm), Some(1.0));
        assert_eq!(m.voltage(&pins, Pin::Yp), None);
    }

    #[test]
    fn a_pull_up_reads_high_unless_its_plate_is_driven_low() {
        let m = PanelModel::default();
        let pins = PanelPins { xp: Drive::Low, xm: Drive::PullUp, yp: Drive::PullUp, ym: Drive::Float };
        // X plate: divider Rx / (Rx + R_PULLUP); the Y plate has no other end driven.
        let xm = m.voltage(&pins, Pin::Xm).unwrap();
        assert!((xm - 300.0 / (300.0 + R_PULLUP)).abs() < 1e-12, "{xm}");
        for pin in [Pin::Yp, Pin::Ym] {
            assert!((m.voltage(&pins, pin).unwrap() - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn sim_panel_reads_exact_raw_values_without_noise() {
        let mut p = SimPanel::new(1);
        p.touch_raw(649.0, 589.0, 1.0).unwrap();
        for _ in 0..10 {
            let s = p.sample();
            assert_eq!((s.x, s.y), (649, 589));
            assert!((200..=1000).contains(&s.z), "{s:?}");
        }
        p.release();
        for _ in 0..10 {
            assert!(p.sample().z < 5);
        }
        // A normalized point goes through the panel's true response.
        p.touch_xy(-1.0, 0.0, 1.0).unwrap();
        let s = p.sample();
        assert_eq!((s.x, s.y), (123, 128));
        assert!(p.touch_xy(0.0, 1.5, 1.0).is_err());
    }
}
