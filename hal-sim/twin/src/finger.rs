//! A scripted finger on the simulated glass (issue #19 §1): a time series of
//! knots (t, x, y, force) in the screen's pixels, with an optional second
//! contact (a palm, a knuckle, a second finger), linearly interpolated and
//! evaluated by the panel at each ADC conversion's own time, so motion and
//! lifts inside one panel read are represented ([`crate::panel::SimPanel`]).
//!
//! # Semantics
//! - Times are milliseconds from the script's start, non-decreasing. Between
//!   two knots x, y and force are interpolated linearly; two knots at the
//!   same time make a step (the later one holds from that time on).
//! - Force 0 is no contact, 1 a firm press (contact resistance
//!   [`crate::panel::R_TOUCH_FIRM`] / force). Before the first knot and after
//!   the last one there is no contact.
//! - Coordinates are screen pixels (fractional allowed; pixel (x, y)'s
//!   centre is (x, y)), on the glass of [`Glass`]: a point off the plates is
//!   no contact.
//!
//! # Millimetres on the glass
//! [`Glass::QVGA_28`]: the 2.8" 320×240 panel, 0.180 mm per pixel (57.6 ×
//! 43.2 mm visible); [`Glass::HVGA_35`]: the 3.5" 480×320 one, 0.154 mm per
//! pixel (73.9 × 49.3 mm). The twin's panel model puts the visible screen on
//! raw counts 123..932 × 128..897 of the plates (the default calibration,
//! `Calibration::DEFAULT`), so its plates (1024 counts) span 72.9 × 57.5 mm
//! on the 2.8" glass and 93.6 × 65.6 mm on the 3.5" ([`Glass::plate_mm`]):
//! 0.071 mm per X count and 0.056 per Y count on the 2.8".
//!
//! # Generators
//! [`gen`] builds seeded scripts: sinusoidal tremor, landing slides, force
//! tremor, bounces, brief contacts and a palm beside the finger.

use touch_arm::touch::map::Calibration;

/// Most knots a script may have (both contacts together).
pub const MAX_KNOTS: usize = 10_000;
/// Longest script, ms.
pub const MAX_MS: f64 = 60_000.0;
/// Largest force accepted (a palm pressed hard is a few times a fingertip).
pub const MAX_FORCE: f64 = 100.0;

/// The glass a script's pixels lie on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Glass {
    /// Screen width, pixels.
    pub w_px: u16,
    /// Screen height, pixels.
    pub h_px: u16,
    /// Millimetres per pixel.
    pub mm_per_px: f64,
}

impl Glass {
    /// The 2.8" 320×240 panel (ILI9341, ST7789V, ILI9325): 0.180 mm per pixel.
    pub const QVGA_28: Glass = Glass { w_px: 320, h_px: 240, mm_per_px: 0.180 };
    /// The 3.5" 480×320 panel (ILI9486): 0.154 mm per pixel.
    pub const HVGA_35: Glass = Glass { w_px: 480, h_px: 320, mm_per_px: 0.154 };

    /// The glass of a `w`×`h` landscape screen, if there is one.
    pub fn for_size(w: u16, h: u16) -> Option<Glass> {
        match (w, h) {
            (320, 240) => Some(Glass::QVGA_28),
            (480, 320) => Some(Glass::HVGA_35),
            _ => None,
        }
    }

    /// Panel coordinates (x_p in [-1, 1] left to right, y_p in [0, 1] bottom
    /// to top over the visible screen) of a pixel position; pixel (x, y)'s
    /// centre is (x, y), as `Layout::pixel_center_to_panel`.
    pub fn px_to_panel(&self, x_px: f64, y_px: f64) -> (f64, f64) {
        let (w, h) = (f64::from(self.w_px), f64::from(self.h_px));
        ((2.0 * x_px + 1.0) / w - 1.0, 1.0 - (2.0 * y_px + 1.0) / (2.0 * h))
    }

    /// Raw plate position (counts, fractional) of a pixel position on a panel
    /// whose true response is `cal`: the calibration's linear map, extended
    /// past the visible screen over the whole plate.
    pub fn px_to_raw(&self, cal: &Calibration, x_px: f64, y_px: f64) -> (f64, f64) {
        let (x_p, y_p) = self.px_to_panel(x_px, y_px);
        let x = if cal.invert_x { -x_p } else { x_p };
        let sx = (f64::from(cal.x_min) + f64::from(cal.x_max) + x * f64::from(cal.x_max - cal.x_min)) * 0.5;
        let span_y = f64::from(cal.y_max - cal.y_min);
        let sy = if cal.invert_y { f64::from(cal.y_max) - y_p * span_y } else { f64::from(cal.y_min) + y_p * span_y };
        if cal.swap_xy {
            (sy, sx)
        } else {
            (sx, sy)
        }
    }

    /// Millimetres per raw count along (X, Y) of an unswapped `cal`.
    pub fn mm_per_count(&self, cal: &Calibration) -> (f64, f64) {
        let w_mm = f64::from(self.w_px) * self.mm_per_px;
        let h_mm = f64::from(self.h_px) * self.mm_per_px;
        (w_mm / f64::from(cal.x_max - cal.x_min), h_mm / f64::from(cal.y_max - cal.y_min))
    }

    /// The plates' span (1024 counts per axis) in mm under `cal`.
    pub fn plate_mm(&self, cal: &Calibration) -> (f64, f64) {
        let (mx, my) = self.mm_per_count(cal);
        (1024.0 * mx, 1024.0 * my)
    }

    /// Pixels of `mm` millimetres.
    pub fn mm_to_px(&self, mm: f64) -> f64 {
        mm / self.mm_per_px
    }
}

/// One knot of a contact's track.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Knot {
    /// Time from the script's start, ms.
    pub t_ms: f64,
    /// Screen x, pixels.
    pub x_px: f64,
    /// Screen y, pixels.
    pub y_px: f64,
    /// 0: no contact, 1: a firm press.
    pub force: f64,
}

impl Knot {
    /// A knot from its four numbers.
    pub const fn new(t_ms: f64, x_px: f64, y_px: f64, force: f64) -> Knot {
        Knot { t_ms, x_px, y_px, force }
    }
}

/// One contact's knots, checked: finite, times from 0 to [`MAX_MS`] and
/// non-decreasing, forces 0..=[`MAX_FORCE`].
#[derive(Debug, Clone, PartialEq)]
pub struct Track {
    knots: Vec<Knot>,
}

impl Track {
    /// Checks `knots`; the error is one line naming the first bad knot (its
    /// index from 0).
    pub fn new(knots: Vec<Knot>) -> Result<Track, String> {
        if knots.is_empty() {
            return Err("a track needs at least one sample".into());
        }
        let mut prev = 0.0;
        for (i, k) in knots.iter().enumerate() {
            if ![k.t_ms, k.x_px, k.y_px, k.force].iter().all(|v| v.is_finite()) {
                return Err(format!("sample {i}: every value must be a finite number"));
            }
            if !(0.0..=MAX_MS).contains(&k.t_ms) {
                return Err(format!("sample {i}: t_ms {} outside 0..={MAX_MS}", k.t_ms));
            }
            if k.t_ms < prev {
                return Err(format!("sample {i}: t_ms {} before the previous sample's {prev}", k.t_ms));
            }
            if !(0.0..=MAX_FORCE).contains(&k.force) {
                return Err(format!("sample {i}: force {} outside 0..={MAX_FORCE}", k.force));
            }
            prev = k.t_ms;
        }
        Ok(Track { knots })
    }

    /// The knots.
    pub fn knots(&self) -> &[Knot] {
        &self.knots
    }

    /// Time of the last knot, ms.
    pub fn end_ms(&self) -> f64 {
        self.knots.last().map_or(0.0, |k| k.t_ms)
    }

    /// Position and force at `t_ms` (see the module's semantics); `None`: no
    /// contact (force 0, or outside the track's time span).
    pub fn at(&self, t_ms: f64) -> Option<(f64, f64, f64)> {
        let k = &self.knots;
        // The last knot at or before t (the later of equal times: a step).
        let i = k.partition_point(|q| q.t_ms <= t_ms).checked_sub(1)?;
        let a = k[i];
        let (x, y, f) = match k.get(i + 1) {
            None if t_ms > a.t_ms => return None,
            None => (a.x_px, a.y_px, a.force),
            Some(b) => {
                let u = (t_ms - a.t_ms) / (b.t_ms - a.t_ms);
                (a.x_px + u * (b.x_px - a.x_px), a.y_px + u * (b.y_px - a.y_px), a.force + u * (b.force - a.force))
            }
        };
        (f > 0.0).then_some((x, y, f))
    }
}

/// A finger script: the main contact and an optional second one.
#[derive(Debug, Clone, PartialEq)]
pub struct FingerScript {
    /// The finger.
    pub first: Track,
    /// A second contact (a palm, a knuckle, another finger), if any.
    pub second: Option<Track>,
}

impl FingerScript {
    /// Checks the limits over both contacts: at most [`MAX_KNOTS`] knots.
    pub fn new(first: Track, second: Option<Track>) -> Result<FingerScript, String> {
        let n = first.knots.len() + second.as_ref().map_or(0, |s| s.knots.len());
        if n > MAX_KNOTS {
            return Err(format!("{n} samples, at most {MAX_KNOTS}"));
        }
        Ok(FingerScript { first, second })
    }

    /// A steady firm finger at pixel (x, y) for `ms` milliseconds.
    pub fn steady(x_px: f64, y_px: f64, ms: f64) -> FingerScript {
        let first = Track { knots: vec![Knot::new(0.0, x_px, y_px, 1.0), Knot::new(ms, x_px, y_px, 1.0)] };
        FingerScript { first, second: None }
    }

    /// Time of the last knot of either contact, ms.
    pub fn end_ms(&self) -> f64 {
        self.first.end_ms().max(self.second.as_ref().map_or(0.0, Track::end_ms))
    }

    /// Both contacts at `t_ms`.
    pub fn at(&self, t_ms: f64) -> [Option<(f64, f64, f64)>; 2] {
        [self.first.at(t_ms), self.second.as_ref().and_then(|s| s.at(t_ms))]
    }

    /// A script from CSV text: header `t_ms,x_px,y_px,force` or
    /// `t_ms,x_px,y_px,force,x2_px,y2_px,force2` (the second contact's knot
    /// at the same time), then one knot per row; blank lines and lines
    /// starting with `#` are skipped. Errors name the line (from 1).
    pub fn parse_csv(text: &str) -> Result<FingerScript, String> {
        let mut rows = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let (hl, header) = rows.next().ok_or("empty file: expected the header t_ms,x_px,y_px,force")?;
        let cols: Vec<&str> = header.split(',').map(str::trim).collect();
        let two = match cols[..] {
            ["t_ms", "x_px", "y_px", "force"] => false,
            ["t_ms", "x_px", "y_px", "force", "x2_px", "y2_px", "force2"] => true,
            _ => {
                return Err(format!(
                    "line {hl}: header must be t_ms,x_px,y_px,force (optionally ,x2_px,y2_px,force2), got {header:?}"
                ))
            }
        };
        let (mut first, mut second) = (Vec::new(), Vec::new());
        let mut lines = Vec::new();
        for (n, row) in rows {
            let vals: Vec<&str> = row.split(',').map(str::trim).collect();
            if vals.len() != cols.len() {
                return Err(format!("line {n}: {} values, the header has {}", vals.len(), cols.len()));
            }
            let mut v = [0.0; 7];
            for (j, s) in vals.iter().enumerate() {
                v[j] = s.parse::<f64>().map_err(|_| format!("line {n}: {} is not a number: {s:?}", cols[j]))?;
            }
            first.push(Knot::new(v[0], v[1], v[2], v[3]));
            if two {
                second.push(Knot::new(v[0], v[4], v[5], v[6]));
            }
            lines.push(n);
        }
        let at_line = |e: String| match e.strip_prefix("sample ").and_then(|r| r.split_once(':')) {
            Some((i, rest)) => match i.parse::<usize>().ok().and_then(|i| lines.get(i)) {
                Some(n) => format!("line {n}:{rest}"),
                None => e,
            },
            None => e,
        };
        let first = Track::new(first).map_err(at_line)?;
        let second = if two { Some(Track::new(second).map_err(at_line)?) } else { None };
        FingerScript::new(first, second)
    }

    /// The script as CSV ([`FingerScript::parse_csv`] reads it back; the
    /// second contact's columns need it knotted at the same times).
    pub fn to_csv(&self) -> String {
        let mut s = String::from("t_ms,x_px,y_px,force");
        let second = self.second.as_ref().filter(|s| {
            s.knots.len() == self.first.knots.len()
                && s.knots.iter().zip(&self.first.knots).all(|(a, b)| a.t_ms == b.t_ms)
        });
        if second.is_some() {
            s += ",x2_px,y2_px,force2";
        }
        s.push('\n');
        for (i, k) in self.first.knots.iter().enumerate() {
            s += &format!("{},{},{},{}", k.t_ms, k.x_px, k.y_px, k.force);
            if let Some(q) = second.map(|t| t.knots[i]) {
                s += &format!(",{},{},{}", q.x_px, q.y_px, q.force);
            }
            s.push('\n');
        }
        s
    }
}

/// Seeded generators of finger scripts (issue #19 §1).
pub mod gen {
    use super::{FingerScript, Glass, Knot, Track};
    use crate::rng::Rng;

    /// Knot spacing of generated motion, ms (a 12 Hz sinusoid sampled every
    /// 2 ms is within 0.3 % of its amplitude between knots).
    pub const DT_MS: f64 = 2.0;

    /// A sinusoidal tremor: amplitude (peak displacement) and frequency at
    /// their means; each tap draws a random direction and phase, and the
    /// frequency drifts ±10 % and the amplitude ±20 % (slow sinusoids of
    /// random period 0.7–2 s and phase).
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct Tremor {
        /// Mean amplitude, mm.
        pub amp_mm: f64,
        /// Mean frequency, Hz.
        pub freq_hz: f64,
    }

    /// One tremor as drawn: its direction and drift.
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct TremorDraw {
        /// The mean parameters.
        pub tremor: Tremor,
        /// Direction of the oscillation, rad.
        pub dir: f64,
        phase: f64,
        f_period_s: f64,
        f_phase: f64,
        a_period_s: f64,
        a_phase: f64,
    }

    impl TremorDraw {
        /// Draws direction, phase and drift.
        pub fn new(rng: &mut Rng, tremor: Tremor) -> TremorDraw {
            let tau = std::f64::consts::TAU;
            TremorDraw {
                tremor,
                dir: tau * rng.uniform(),
                phase: tau * rng.uniform(),
                f_period_s: 0.7 + 1.3 * rng.uniform(),
                f_phase: tau * rng.uniform(),
                a_period_s: 0.7 + 1.3 * rng.uniform(),
                a_phase: tau * rng.uniform(),
            }
        }

        /// Instantaneous amplitude (mm) at `t_s`.
        pub fn amp_mm(&self, t_s: f64) -> f64 {
            let tau = std::f64::consts::TAU;
            self.tremor.amp_mm * (1.0 + 0.2 * (tau * t_s / self.a_period_s + self.a_phase).sin())
        }

        /// Instantaneous frequency (Hz) at `t_s`.
        pub fn freq_hz(&self, t_s: f64) -> f64 {
            let tau = std::f64::consts::TAU;
            self.tremor.freq_hz * (1.0 + 0.1 * (tau * t_s / self.f_period_s + self.f_phase).sin())
        }

        /// Signed displacement along [`TremorDraw::dir`] at `t_s`, mm: the
        /// amplitude times the sine of the integrated frequency.
        pub fn displacement_mm(&self, t_s: f64) -> f64 {
            let tau = std::f64::consts::TAU;
            let w = tau / self.f_period_s;
            // ∫0^t 2π f0 (1 + 0.1 sin(w s + p)) ds
            let integral =
                tau * self.tremor.freq_hz * (t_s - 0.1 / w * ((w * t_s + self.f_phase).cos() - self.f_phase.cos()));
            self.amp_mm(t_s) * (self.phase + integral).sin()
        }

        /// Displacement (dx, dy) in mm at `t_s`.
        pub fn offset_mm(&self, t_s: f64) -> (f64, f64) {
            let d = self.displacement_mm(t_s);
            (d * self.dir.cos(), d * self.dir.sin())
        }
    }

    /// A landing slide: the finger lands `len_mm` from the intended point in
    /// a random direction and slides straight onto it in `ms`.
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct Slide {
        /// Distance of the landing from the intended point, mm.
        pub len_mm: f64,
        /// Duration of the slide, ms.
        pub ms: f64,
    }

    /// A second contact beside the finger (a palm or knuckle): where
    /// relative to the finger, how firm, and when it lands and lifts.
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct Palm {
        /// Offset from the finger, mm (screen axes: x right, y down).
        pub offset_mm: (f64, f64),
        /// Its force (a palm: larger than a fingertip's).
        pub force: f64,
        /// Contact window, ms from the script's start.
        pub window_ms: (f64, f64),
    }

    /// Everything one generated tap is made of.
    #[derive(Debug, Clone, PartialEq)]
    pub struct TapPlan {
        /// The intended point, screen pixels.
        pub centre_px: (f64, f64),
        /// Contact windows (start, end) in ms: one for a plain tap, several
        /// for bounces or a force tremor.
        pub windows: Vec<(f64, f64)>,
        /// The finger's force while in contact.
        pub force: f64,
        /// A tremor of the finger, if any.
        pub tremor: Option<Tremor>,
        /// A landing slide, if any.
        pub slide: Option<Slide>,
        /// A second contact, if any.
        pub palm: Option<Palm>,
    }

    impl TapPlan {
        /// A steady firm tap of `ms` at `centre_px`.
        pub fn steady(centre_px: (f64, f64), ms: f64) -> TapPlan {
            TapPlan { centre_px, windows: vec![(0.0, ms)], force: 1.0, tremor: None, slide: None, palm: None }
        }
    }

    /// Contact windows of a force tremor over `ms`: on for `duty` of each
    /// period of `freq_hz`, from a random phase (the first window starts at 0).
    pub fn force_tremor_windows(rng: &mut Rng, ms: f64, freq_hz: f64, duty: f64) -> Vec<(f64, f64)> {
        let period = 1000.0 / freq_hz;
        let on = duty.clamp(0.0, 1.0) * period;
        // Start partway through an on phase.
        let mut t = -on * rng.uniform();
        let mut w = Vec::new();
        while t < ms {
            let (a, b) = (t.max(0.0), (t + on).min(ms));
            if b > a {
                w.push((a, b));
            }
            t += period;
        }
        w
    }

    /// Contact windows of a tap of `ms` followed by `bounces` short
    /// re-contacts, each after a lift gap drawn in 20–300 ms and lasting
    /// `bounce_ms` (min, max).
    pub fn bounce_windows(rng: &mut Rng, ms: f64, bounces: u32, bounce_ms: (f64, f64)) -> Vec<(f64, f64)> {
        let mut w = vec![(0.0, ms)];
        let mut t = ms;
        for _ in 0..bounces {
            let gap = 20.0 + 280.0 * rng.uniform();
            let on = bounce_ms.0 + (bounce_ms.1 - bounce_ms.0) * rng.uniform();
            w.push((t + gap, t + gap + on));
            t += gap + on;
        }
        w
    }

    /// The script of `plan` on `glass`, drawing the tremor's direction,
    /// phase and drift and the slide's direction from `rng`.
    pub fn tap(rng: &mut Rng, glass: &Glass, plan: &TapPlan) -> FingerScript {
        let tremor = plan.tremor.map(|t| TremorDraw::new(rng, t));
        let slide_dir = std::f64::consts::TAU * rng.uniform();
        let pos = |t_ms: f64| {
            let (mut dx, mut dy) = (0.0, 0.0);
            if let Some(tr) = &tremor {
                (dx, dy) = tr.offset_mm(t_ms / 1000.0);
            }
            if let Some(s) = plan.slide {
                let left = (1.0 - t_ms / s.ms.max(1e-9)).max(0.0) * s.len_mm;
                dx += left * slide_dir.cos();
                dy += left * slide_dir.sin();
            }
            (plan.centre_px.0 + glass.mm_to_px(dx), plan.centre_px.1 + glass.mm_to_px(dy))
        };
        let mut knots = Vec::new();
        for &(a, b) in &plan.windows {
            let (x, y) = pos(a);
            knots.push(Knot::new(a, x, y, 0.0));
            let mut t = a;
            while t < b {
                let (x, y) = pos(t);
                knots.push(Knot::new(t, x, y, plan.force));
                t += DT_MS;
            }
            let (x, y) = pos(b);
            knots.push(Knot::new(b, x, y, plan.force));
            knots.push(Knot::new(b, x, y, 0.0));
        }
        let first = Track { knots };
        let second = plan.palm.map(|p| {
            let (a, b) = p.window_ms;
            let (x, y) =
                (plan.centre_px.0 + glass.mm_to_px(p.offset_mm.0), plan.centre_px.1 + glass.mm_to_px(p.offset_mm.1));
            Track {
                knots: vec![
                    Knot::new(a, x, y, 0.0),
                    Knot::new(a, x, y, p.force),
                    Knot::new(b, x, y, p.force),
                    Knot::new(b, x, y, 0.0),
                ],
            }
        });
        FingerScript { first, second }
    }
}

#[cfg(test)]
mod tests {
    use super::gen::*;
    use super::*;
    use crate::rng::Rng;

    #[test]
    fn interpolation_is_exact_at_the_knots_and_linear_between() {
        let t = Track::new(vec![
            Knot::new(0.0, 10.0, 20.0, 1.0),
            Knot::new(10.0, 20.0, 40.0, 0.5),
            Knot::new(10.0, 20.0, 40.0, 0.0),
            Knot::new(30.0, 60.0, 40.0, 0.0),
            Knot::new(30.0, 60.0, 40.0, 2.0),
            Knot::new(40.0, 70.0, 50.0, 2.0),
        ])
        .unwrap();
        assert_eq!(t.at(0.0), Some((10.0, 20.0, 1.0)));
        assert_eq!(t.at(5.0), Some((15.0, 30.0, 0.75)));
        assert_eq!(t.at(2.5), Some((12.5, 25.0, 0.875)));
        // A step down at 10 ms: lifted from 10 to just before 30.
        assert_eq!(t.at(9.999_999).map(|v| v.2 > 0.5), Some(true));
        assert_eq!(t.at(10.0), None);
        assert_eq!(t.at(29.9), None);
        assert_eq!(t.at(30.0), Some((60.0, 40.0, 2.0)));
        assert_eq!(t.at(35.0), Some((65.0, 45.0, 2.0)));
        assert_eq!(t.at(40.0), Some((70.0, 50.0, 2.0)));
        // Outside the span: no contact.
        assert_eq!(t.at(-0.001), None);
        assert_eq!(t.at(40.001), None);
        assert_eq!(t.end_ms(), 40.0);
    }

    #[test]
    fn tracks_and_scripts_refuse_bad_knots() {
        let k = |t| Knot::new(t, 1.0, 1.0, 1.0);
        assert_eq!(Track::new(vec![]).unwrap_err(), "a track needs at least one sample");
        assert_eq!(Track::new(vec![k(5.0), k(4.0)]).unwrap_err(), "sample 1: t_ms 4 before the previous sample's 5");
        assert_eq!(Track::new(vec![k(-1.0)]).unwrap_err(), "sample 0: t_ms -1 outside 0..=60000");
        assert_eq!(Track::new(vec![k(60_001.0)]).unwrap_err(), "sample 0: t_ms 60001 outside 0..=60000");
        assert_eq!(
            Track::new(vec![Knot::new(0.0, 1.0, 1.0, -0.5)]).unwrap_err(),
            "sample 0: force -0.5 outside 0..=100"
        );
        assert!(Track::new(vec![Knot::new(0.0, f64::NAN, 1.0, 1.0)]).unwrap_err().contains("finite"));
        let many = Track::new((0..6000).map(|i| k(f64::from(i))).collect()).unwrap();
        assert_eq!(FingerScript::new(many.clone(), None).map(|s| s.end_ms()), Ok(5999.0));
        assert_eq!(FingerScript::new(many.clone(), Some(many)).unwrap_err(), "12000 samples, at most 10000");
    }

    #[test]
    fn csv_round_trips_and_its_errors_name_the_line() {
        let s = FingerScript::parse_csv(
            "# a tap\nt_ms,x_px,y_px,force\n0,100,120,1\n\n250,101.5,120,1\r\n250,101.5,120,0\n",
        )
        .unwrap();
        assert_eq!(s.first.knots().len(), 3);
        assert_eq!(s.second, None);
        assert_eq!(s.first.at(125.0), Some((100.75, 120.0, 1.0)));
        assert_eq!(FingerScript::parse_csv(&s.to_csv()).unwrap(), s);
        let two = FingerScript::parse_csv(
            "t_ms,x_px,y_px,force,x2_px,y2_px,force2\n0,10,20,1,50,200,3\n100,10,20,1,50,200,3\n",
        )
        .unwrap();
        assert_eq!(two.at(50.0), [Some((10.0, 20.0, 1.0)), Some((50.0, 200.0, 3.0))]);
        assert_eq!(FingerScript::parse_csv(&two.to_csv()).unwrap(), two);
        for (text, err) in [
            ("", "empty file: expected the header t_ms,x_px,y_px,force"),
            (
                "t,x,y,f\n",
                "line 1: header must be t_ms,x_px,y_px,force (optionally ,x2_px,y2_px,force2), got \"t,x,y,f\"",
            ),
            ("t_ms,x_px,y_px,force\n0,1,2\n", "line 2: 3 values, the header has 4"),
            ("t_ms,x_px,y_px,force\n0,1,2,1\n5,x,2,1\n", "line 3: x_px is not a number: \"x\""),
            ("t_ms,x_px,y_px,force\n0,1,2,1\n\n# c\n-5,1,2,1\n", "line 5: t_ms -5 outside 0..=60000"),
            ("t_ms,x_px,y_px,force\n9,1,2,1\n5,1,2,1\n", "line 3: t_ms 5 before the previous sample's 9"),
            ("t_ms,x_px,y_px,force\n", "a track needs at least one sample"),
        ] {
            assert_eq!(FingerScript::parse_csv(text).unwrap_err(), err, "{text:?}");
        }
    }

    #[test]
    fn glass_millimetres_and_plate_span() {
        let cal = Calibration::DEFAULT;
        let (px, py) = Glass::QVGA_28.plate_mm(&cal);
        assert!((px - 1024.0 * 57.6 / 809.0).abs() < 1e-9 && (px - 72.91).abs() < 0.01, "{px}");
        assert!((py - 1024.0 * 43.2 / 769.0).abs() < 1e-9 && (py - 57.52).abs() < 0.01, "{py}");
        let (hx, hy) = Glass::HVGA_35.plate_mm(&cal);
        assert!((hx - 93.57).abs() < 0.01 && (hy - 65.62).abs() < 0.01, "{hx} {hy}");
        // The screen's corners land on the calibration's span.
        let g = Glass::QVGA_28;
        assert_eq!(g.px_to_raw(&cal, -0.5, 239.5), (123.0, 128.0));
        assert_eq!(g.px_to_raw(&cal, 319.5, -0.5), (932.0, 897.0));
        assert_eq!(g.px_to_panel(159.5, 119.5), (0.0, 0.5));
        assert_eq!(g.mm_to_px(0.9), 5.0);
    }

    #[test]
    fn tremor_follows_its_parameters() {
        let glass = Glass::QVGA_28;
        for seed in 1..=20u64 {
            let mut rng = Rng::new(seed);
            let tr = TremorDraw::new(&mut rng, Tremor { amp_mm: 2.0, freq_hz: 6.0 });
            let (mut peak, mut lo, mut crossings) = (0.0f64, f64::MAX, 0);
            let mut prev = tr.displacement_mm(0.0);
            let mut half_peak = 0.0f64;
            for i in 1..=10_000 {
                let t = f64::from(i) * 1e-3;
                let d = tr.displacement_mm(t);
                peak = peak.max(d.abs());
                half_peak = half_peak.max(d.abs());
                if d.signum() != prev.signum() {
                    crossings += 1;
                    if crossings > 1 {
                        lo = lo.min(half_peak);
                    }
                    half_peak = 0.0;
                }
                prev = d;
                // The instantaneous parameters stay inside their drift.
                assert!((tr.freq_hz(t) / 6.0 - 1.0).abs() <= 0.1 + 1e-12);
                assert!((tr.amp_mm(t) / 2.0 - 1.0).abs() <= 0.2 + 1e-12);
                let (dx, dy) = tr.offset_mm(t);
                assert!((dx * tr.dir.sin() - dy * tr.dir.cos()).abs() < 1e-9, "along its direction");
            }
            // 10 s at 6 Hz ±10 %: 2 crossings a period.
            let f = f64::from(crossings) / 2.0 / 10.0;
            assert!((5.4..=6.6).contains(&f), "seed {seed}: {f} Hz");
            assert!((2.0..=2.4 + 1e-9).contains(&peak), "seed {seed}: peak {peak}");
            assert!(lo >= 1.6 * 0.95, "seed {seed}: smallest half-cycle peak {lo}");
        }
        // The generated tap follows the draw at its knots, in pixels.
        let mut rng = Rng::new(7);
        let plan =
            TapPlan { tremor: Some(Tremor { amp_mm: 3.0, freq_hz: 4.0 }), ..TapPlan::steady((100.0, 120.0), 500.0) };
        let s = tap(&mut rng, &glass, &plan);
        let mut rng = Rng::new(7);
        let tr = TremorDraw::new(&mut rng, Tremor { amp_mm: 3.0, freq_hz: 4.0 });
        let (dx, dy) = tr.offset_mm(0.1);
        let (x, y, f) = s.first.at(100.0).unwrap();
        assert!((x - 100.0 - dx / 0.18).abs() < 1e-9 && (y - 120.0 - dy / 0.18).abs() < 1e-9 && f == 1.0);
        assert_eq!(s.first.at(500.0 + 1e-9), None);
    }

    #[test]
    fn force_tremor_bounces_slides_and_palms_follow_their_parameters() {
        let mut rng = Rng::new(3);
        for (freq, duty) in [(3.0, 0.5), (5.0, 0.7), (8.0, 0.3)] {
            let w = force_tremor_windows(&mut rng, 1500.0, freq, duty);
            let on: f64 = w.iter().map(|(a, b)| b - a).sum();
            let period = 1000.0 / freq;
            // On for the duty of each whole period, give or take the ends.
            assert!((on - duty * 1500.0).abs() <= duty * period + 1e-9, "{freq} {duty}: {on}");
            assert_eq!(w[0].0, 0.0);
            for p in w.windows(2) {
                assert!((p[1].0 - p[0].0 - period).abs() < 1e-9 || p[0].0 == 0.0);
            }
        }
        for seed in 0..50 {
            let mut rng = Rng::new(seed);
            let w = bounce_windows(&mut rng, 200.0, 4, (10.0, 40.0));
            assert_eq!(w.len(), 5);
            for p in w.windows(2) {
                let gap = p[1].0 - p[0].1;
                assert!((20.0..300.0).contains(&gap), "{gap}");
                assert!((10.0..40.0).contains(&(p[1].1 - p[1].0)));
            }
        }
        let glass = Glass::QVGA_28;
        let mut rng = Rng::new(11);
        let plan = TapPlan { slide: Some(Slide { len_mm: 4.5, ms: 150.0 }), ..TapPlan::steady((150.0, 100.0), 400.0) };
        let s = tap(&mut rng, &glass, &plan);
        let (x0, y0, _) = s.first.at(0.0).unwrap();
        assert!(((x0 - 150.0).hypot(y0 - 100.0) * 0.18 - 4.5).abs() < 1e-9);
        let (x1, y1, _) = s.first.at(75.0).unwrap();
        assert!(((x1 - 150.0).hypot(y1 - 100.0) * 0.18 - 2.25).abs() < 1e-9);
        assert_eq!(s.first.at(150.0).map(|(x, y, _)| (x, y)), Some((150.0, 100.0)));
        let plan = TapPlan {
            palm: Some(Palm { offset_mm: (0.0, 25.2), force: 3.0, window_ms: (50.0, 450.0) }),
            ..TapPlan::steady((150.0, 100.0), 400.0)
        };
        let s = tap(&mut rng, &glass, &plan);
        assert_eq!(s.at(40.0), [Some((150.0, 100.0, 1.0)), None]);
        assert_eq!(s.at(420.0), [None, Some((150.0, 240.0, 3.0))]);
    }
}
