//! Touch pipeline for a 4-wire resistive panel: median of N samples, spread
//! rejection, a pressure window and press/release debouncing (docs/hardware.md).
//!
//! The driver performs one *read*: it takes `N` [`RawSample`]s (each an X, a Y
//! and a pressure measurement after the settle delay) and hands them to
//! [`TouchFilter::update`]. A read is classified ([`Read`]) and fed to a small
//! state machine that emits [`TouchEvent`]s.
//!
//! # Classifying a read
//! 1. Every sample's pressure `z` is checked against the window `[z_min, z_max]`.
//!    None inside: the panel is **not touched** ([`Read::NotTouched`]) — never a
//!    point at (0, 0). Some inside and some outside: the finger was landing or
//!    lifting during the read, so its X/Y samples are voltages of a half-made
//!    contact: [`Reject::PartialContact`].
//! 2. The spread (max − min) of X and of Y must not exceed `max_spread`, else the
//!    read is rejected ([`Reject::SpreadX`] / [`Reject::SpreadY`]): a median hides
//!    single spikes, but a wide spread means the voltage had not settled.
//! 3. Otherwise the read is [`Read::Touched`] with the per-axis medians.
//!
//! # Debouncing
//! A *stable run* is a sequence of consecutive touched reads that all fit in a
//! box of `stability_radius` counts per axis (so every pair is within the radius
//! of each other, Chebyshev distance). A read that does not fit starts a new
//! run; a not-touched or rejected read ends the run.
//!
//! - Idle: when a run reaches `press_confirm` reads, [`TouchEvent::Pressed`] is
//!   emitted with the **mean of those reads**. That is the safe target for the
//!   arm: it is where the user held the finger steady for the whole confirmation
//!   time. The first readings of a landing finger (the membrane still
//!   deforming, contact resistance high) and the last readings of a lifting one
//!   are transients that can sit far from the intended point; they either fail
//!   the pressure/spread checks or break the run, so they never become a target.
//! - Held: any read that is not a valid touch (not touched *or* rejected) counts
//!   toward release; `release_confirm` consecutive such reads emit
//!   [`TouchEvent::Released`]. A single dropout does not release (hysteresis),
//!   and a panel that only produces garbage does release eventually.
//! - Held, drag: a new stable run of `press_confirm` reads whose mean lies more
//!   than `stability_radius` from the current point emits [`TouchEvent::Moved`].
//!   So a drag reports only points the finger rested on, never the path between.
//!
//! # Pressure measure
//! With XP low and YM high the driver reads `z1` (on XM) and `z2` (on YP). The
//! common formula for the touch resistance, `R = R_x·(x/1024)·(z2/z1 − 1)`, needs
//! the X-plate resistance and a division. This module uses the simpler monotone
//! measure `z = 1023 + z1 − z2` ([`pressure`]) used by the MCUFRIEND-style
//! shield libraries: untouched, the plates are disconnected, so `z1 ≈ 0`,
//! `z2 ≈ 1023` and `z ≈ 0`; pressing harder lowers the contact resistance, `z1`
//! rises, `z2` falls and `z` grows. It depends a little on the touch position,
//! so the window should be generous (default 200..1015: a plate short reads
//! 1021–1023, and a finger pressed ten times as firmly as usual reads inside
//! it in the twin's panel model: BENCHMARKS.md, "Touch for an unsteady hand").

use crate::seam::RawSample;

/// Largest number of samples per read.
pub const MAX_SAMPLES: usize = 9;

/// Full scale of the 10-bit ADC.
pub const ADC_MAX: u16 = 1023;

/// A filtered panel position in raw ADC counts (calibration is applied later).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TouchPoint {
    /// X, ADC counts.
    pub x: u16,
    /// Y, ADC counts.
    pub y: u16,
}

/// Pressure measure from the two pressure readings: `1023 + z1 − z2`, in
/// `0..=2046`, larger means a firmer touch, ≈ 0 when untouched. Readings above
/// the ADC range are clamped to 1023 first.
pub fn pressure(z1: u16, z2: u16) -> u16 {
    ADC_MAX + z1.min(ADC_MAX) - z2.min(ADC_MAX)
}

/// Fixed-point one of [`plate_ratio`]: a ratio of 1 is 256.
pub const PLATE_ONE: u32 = 256;

/// The panel's plate ratio as one read sees it, [`PLATE_ONE`] = 1, from the
/// X read `x`, the Y read `y`, the pressure measure `z` and the pressure
/// read's `z1` (all ADC counts).
///
/// With a single contact at fraction `fx` of the X plate from XM and `fy` of
/// the Y plate from YM, the pressure read (XP low, YM high) drives a current
/// through the Y plate's `Ry·fy`, the contact and the X plate's `Rx·(1 − fx)`;
/// `z1` is the X plate's voltage at the contact and `1023 − z2 = z − z1` the
/// drop across `Ry·fy`, so `(z − z1)/z1 = Ry·fy / (Rx·(1 − fx))`. With
/// `x ≈ 1024·fx` and `y ≈ 1024·fy`,
/// `(z − z1)·(1023 − x) / (z1·y) = Ry/Rx`: the same for every point and force
/// (the contact resistance drops out). These are the two touch-resistance
/// formulas of the resistive-panel application notes (through z1 and z2, and
/// through z1 with x and y) set equal. A second contact makes a network that
/// no single point and resistance explains: the ratio moves away from the
/// panel's own ([`crate::touch::contact`] uses that against a palm).
///
/// Each reading is taken at the middle of its ADC step (`code + ½`: the ADC
/// truncates), which keeps small readings from biasing the ratio and the
/// denominator from being 0.
pub fn plate_ratio(x: u16, y: u16, z: u16, z1: u16) -> u16 {
    let half = |v: u16| 2 * u32::from(v.min(ADC_MAX)) + 1;
    let num = half(z.saturating_sub(z1)) * half(ADC_MAX.saturating_sub(x));
    let den = half(z1) * half(y);
    // num < 2^22, so num · 256 + den/2 < 2^31; rounded.
    ((num * PLATE_ONE + den / 2) / den).min(u32::from(u16::MAX)) as u16
}

/// Median of `v` by insertion sort (sorts `v` in place; meant for `len ≤ 9`).
/// For an even length it returns the upper of the two middle values; for an
/// empty slice it returns 0.
pub fn median_u16(v: &mut [u16]) -> u16 {
    for i in 1..v.len() {
        let mut j = i;
        while j > 0 && v[j - 1] > v[j] {
            v.swap(j - 1, j);
            j -= 1;
        }
    }
    v.get(v.len() / 2).copied().unwrap_or(0)
}

/// Filter parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FilterConfig {
    /// Samples per read: odd, `1..=9`.
    pub samples: u8,
    /// Largest accepted `max − min` of the X (and of the Y) samples of a read.
    pub max_spread: u16,
    /// Pressure window: a sample is in contact iff `z_min ≤ z ≤ z_max`.
    /// `z_min` must be > 0 (an untouched panel reads z ≈ 0).
    pub z_min: u16,
    /// Upper end of the pressure window (above it: a short, not a finger).
    pub z_max: u16,
    /// Consecutive stable touched reads that confirm a press (≥ 2).
    pub press_confirm: u8,
    /// Consecutive non-touch reads that confirm a release (≥ 2).
    pub release_confirm: u8,
    /// Per-axis size of the box a stable run must fit in, ADC counts.
    pub stability_radius: u16,
}

impl FilterConfig {
    /// Starting values for a MCUFRIEND-style shield: 5 samples, spread 24,
    /// pressure 200..1015, 3 reads to press, 3 to release, radius 8.
    pub const DEFAULT: FilterConfig = FilterConfig {
        samples: 5,
        max_spread: 24,
        z_min: 200,
        z_max: 1015,
        press_confirm: 3,
        release_confirm: 3,
        stability_radius: 8,
    };

    /// Checks the ranges given with each field.
    pub fn validate(&self) -> Result<(), FilterConfigError> {
        if self.samples == 0 || self.samples as usize > MAX_SAMPLES || self.samples.is_multiple_of(2) {
            return Err(FilterConfigError::SampleCount);
        }
        if self.z_min == 0 || self.z_min > self.z_max {
            return Err(FilterConfigError::PressureWindow);
        }
        if self.press_confirm < 2 || self.release_confirm < 2 {
            return Err(FilterConfigError::Confirm);
        }
        Ok(())
    }
}

impl Default for FilterConfig {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Why a filter configuration was refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FilterConfigError {
    /// `samples` is not odd in `1..=9`.
    SampleCount,
    /// `z_min` is 0 or above `z_max`.
    PressureWindow,
    /// `press_confirm` or `release_confirm` below 2.
    Confirm,
}

/// Why a read was thrown away (count these to judge the panel and wiring).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Reject {
    /// The driver passed a number of samples other than `FilterConfig::samples`.
    SampleCount,
    /// Some samples in the pressure window, some not: finger landing/lifting.
    PartialContact,
    /// The X samples spread more than `max_spread`: noise or a sliding finger.
    SpreadX,
    /// The Y samples spread more than `max_spread`.
    SpreadY,
}

/// Why a read counts as "not touched".
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoTouch {
    /// Median pressure below the window: nothing on the panel.
    PressureLow,
    /// Median pressure above the window (a short or a wiring fault).
    PressureHigh,
}

/// Classification of one read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Read {
    /// Every sample in contact and the spreads small.
    Touched {
        /// The median X and Y, ADC counts.
        point: TouchPoint,
        /// The median pressure (see [`pressure`]).
        z: u16,
        /// The plate ratio of the medians ([`plate_ratio`]).
        plate: u16,
    },
    /// Nothing on the panel (or a fault that looks like it).
    NotTouched(NoTouch),
    /// Not usable: breaks a press run, and counts as a miss while held.
    Rejected(Reject),
}

/// What the filter tells the app, at most one per read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TouchEvent {
    /// A press was confirmed at this point (mean of the stable run).
    Pressed(TouchPoint),
    /// While held, the finger came to rest at a different point.
    Moved(TouchPoint),
    /// The press ended (after `release_confirm` non-touch reads).
    Released,
}

/// Result of [`TouchFilter::update`]: the read's classification and at most one event.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Step {
    /// How the read was classified.
    pub read: Read,
    /// What it changed, if anything.
    pub event: Option<TouchEvent>,
}

/// Consecutive touched reads that fit in a `radius` box.
#[derive(Debug, Clone, Copy)]
struct Run {
    count: u8,
    min_x: u16,
    max_x: u16,
    min_y: u16,
    max_y: u16,
    sum_x: u32,
    sum_y: u32,
    /// The mean was reported; later reads only keep testing the box.
    reported: bool,
}

impl Run {
    const EMPTY: Run = Run { count: 0, min_x: 0, max_x: 0, min_y: 0, max_y: 0, sum_x: 0, sum_y: 0, reported: false };

    fn start(p: TouchPoint) -> Run {
        Run {
            count: 1,
            min_x: p.x,
            max_x: p.x,
            min_y: p.y,
            max_y: p.y,
            sum_x: p.x as u32,
            sum_y: p.y as u32,
            reported: false,
        }
    }

    /// Adds a read; returns the run's mean exactly when the run reaches
    /// `confirm` reads. The mean covers the first `confirm` reads only, so the
    /// sums cannot overflow however long the finger rests.
    fn push(&mut self, p: TouchPoint, radius: u16, confirm: u8) -> Option<TouchPoint> {
        if self.count == 0 {
            *self = Run::start(p);
        } else {
            let (min_x, max_x) = (self.min_x.min(p.x), self.max_x.max(p.x));
            let (min_y, max_y) = (self.min_y.min(p.y), self.max_y.max(p.y));
            if max_x - min_x > radius || max_y - min_y > radius {
                *self = Run::start(p);
            } else {
                self.min_x = min_x;
                self.max_x = max_x;
                self.min_y = min_y;
                self.max_y = max_y;
                if self.count < confirm {
                    self.count += 1;
                    self.sum_x += p.x as u32;
                    self.sum_y += p.y as u32;
                }
            }
        }
        if self.count >= confirm && !self.reported {
            self.reported = true;
            let n = self.count as u32;
            Some(TouchPoint { x: ((self.sum_x + n / 2) / n) as u16, y: ((self.sum_y + n / 2) / n) as u16 })
        } else {
            None
        }
    }
}

/// The debouncing state machine. Create with [`TouchFilter::new`].
#[derive(Debug, Clone, Copy)]
pub struct TouchFilter {
    cfg: FilterConfig,
    run: Run,
    held: Option<TouchPoint>,
    /// Consecutive non-touch reads while held.
    misses: u8,
}

impl TouchFilter {
    /// An idle filter with `cfg`, once it validates.
    pub fn new(cfg: &FilterConfig) -> Result<TouchFilter, FilterConfigError> {
        cfg.validate()?;
        Ok(TouchFilter { cfg: *cfg, run: Run::EMPTY, held: None, misses: 0 })
    }

    /// The configuration in use.
    pub fn config(&self) -> &FilterConfig {
        &self.cfg
    }

    /// The point of the current press, if one is held.
    pub fn held(&self) -> Option<TouchPoint> {
        self.held
    }

    /// Back to idle without emitting `Released` (e.g. after a configuration change).
    pub fn reset(&mut self) {
        self.run = Run::EMPTY;
        self.held = None;
        self.misses = 0;
    }

    /// Classifies one read without touching the state machine.
    pub fn classify(&self, samples: &[RawSample]) -> Read {
        let n = samples.len();
        if n != self.cfg.samples as usize || n > MAX_SAMPLES {
            return Read::Rejected(Reject::SampleCount);
        }
        let in_window = samples.iter().filter(|s| s.z >= self.cfg.z_min && s.z <= self.cfg.z_max).count();
        // One channel at a time through one buffer: the read's frame is on
        // the deepest stack chain (`poll_touch`), so no array per channel.
        let mut buf = [0u16; MAX_SAMPLES];
        let mut sorted = |channel: fn(&RawSample) -> u16| -> (u16, u16) {
            let v = buf.get_mut(..n).unwrap_or(&mut []);
            for (slot, s) in v.iter_mut().zip(samples) {
                *slot = channel(s);
            }
            // Sorted by the median: the spread is last − first.
            let median = median_u16(v);
            (median, spread(v))
        };
        let (z, _) = sorted(|s| s.z);
        if in_window == 0 {
            return Read::NotTouched(if z < self.cfg.z_min { NoTouch::PressureLow } else { NoTouch::PressureHigh });
        }
        if in_window < n {
            return Read::Rejected(Reject::PartialContact);
        }
        let (x, spread_x) = sorted(|s| s.x);
        if spread_x > self.cfg.max_spread {
            return Read::Rejected(Reject::SpreadX);
        }
        let (y, spread_y) = sorted(|s| s.y);
        if spread_y > self.cfg.max_spread {
            return Read::Rejected(Reject::SpreadY);
        }
        let (z1, _) = sorted(|s| s.z1);
        Read::Touched { point: TouchPoint { x, y }, z, plate: plate_ratio(x, y, z, z1) }
    }

    /// Feeds one read (exactly `FilterConfig::samples` samples).
    pub fn update(&mut self, samples: &[RawSample]) -> Step {
        let read = self.classify(samples);
        let event = self.advance(&read);
        Step { read, event }
    }

    fn advance(&mut self, read: &Read) -> Option<TouchEvent> {
        let (radius, confirm) = (self.cfg.stability_radius, self.cfg.press_confirm);
        match (*read, self.held) {
            (Read::Touched { point, .. }, None) => {
                let mean = self.run.push(point, radius, confirm)?;
                self.held = Some(mean);
                self.misses = 0;
                Some(TouchEvent::Pressed(mean))
            }
            (Read::Touched { point, .. }, Some(held)) => {
                self.misses = 0;
                let mean = self.run.push(point, radius, confirm)?;
                if held.x.abs_diff(mean.x) > radius || held.y.abs_diff(mean.y) > radius {
                    self.held = Some(mean);
                    Some(TouchEvent::Moved(mean))
                } else {
                    None
                }
            }
            (_, None) => {
                self.run = Run::EMPTY;
                None
            }
            (_, Some(_)) => {
                self.run = Run::EMPTY;
                self.misses = self.misses.saturating_add(1);
                if self.misses >= self.cfg.release_confirm {
                    self.held = None;
                    self.misses = 0;
                    Some(TouchEvent::Released)
                } else {
                    None
                }
            }
        }
    }
}

/// `max − min` of an ascending slice.
fn spread(sorted: &[u16]) -> u16 {
    match (sorted.first(), sorted.last()) {
        (Some(lo), Some(hi)) => hi.saturating_sub(*lo),
        _ => 0,
    }
}
