//! On-screen touch calibration: a pure state machine that shows crosshairs
//! one after another, collects the raw panel readings touched on them, fits a
//! [`Calibration`] (min/max, axis swap and inversion detected), and lets the
//! user Save or Cancel. Cancel keeps the old calibration; the app stores a
//! saved one in EEPROM.
//!
//! The caller feeds every confirmed press (`TouchEvent::Pressed` from the
//! touch filter) as raw channels, unmapped: during the crosshairs the old
//! calibration may be wrong, so nothing is mapped. On the result screen the
//! touch is mapped with the *new* calibration (when the fit succeeded), so
//! hitting Save already proves the new mapping works; after a failed fit the
//! old one is used for Retry / Cancel.
//!
//! With [`CalibrationFlow::with_settings`] (the app's Calib button, unless
//! the carer lock hides the touch settings) Save leads to a last page that
//! sets the touch's `hold`, `repeat` and `radius` (issue #19 §3) with its −
//! and + buttons on a ladder of steps; its Save keeps the calibration and those values
//! in one record, its Cancel keeps the old ones. The edited values are not
//! in force until saved, so the − and + taps themselves are judged by the
//! settings in use (a carer who raises `hold` is not caught by it halfway).

use embedded_graphics::pixelcolor::Rgb565;

use super::draw::{fill, text_centered, Area, Canvas, TextStyle};
use super::flash::TextSource;
use super::layout::Layout;
use super::theme;
use crate::config::settings::{
    PressSettings, HOLD_MIN_CS, MIN_TOUCH_SPAN, PLATE_MAX, PLATE_MIN, RADIUS_MIN, TIME_MAX_CS,
};
use crate::text::line::Line;
use crate::text::Text;
use crate::touch::contact::PLATE_TOL_DIV;
use crate::touch::filter::median_u16;
use crate::touch::map::{Calibration, CalibrationError, Crosshair, SwapMode};

/// Crosshairs per calibration.
pub const CAL_COUNT: usize = 5;

/// Crosshair `i`'s centre in screen pixels: the four corners inset by 10 %,
/// then the centre (five points average touch noise and detect swap and
/// inversion); (32, 24), (288, 24), (288, 216), (32, 216), (160, 120) at
/// 320×240.
pub const fn cal_pixel(lay: &Layout, i: usize) -> Option<(i16, i16)> {
    let (w, h) = (lay.width() as i16, lay.height() as i16);
    let (dx, dy) = (lay.sx(32), lay.sy(24));
    match i {
        0 => Some((dx, dy)),
        1 => Some((w - dx, dy)),
        2 => Some((w - dx, h - dy)),
        3 => Some((dx, h - dy)),
        4 => Some((w / 2, h / 2)),
        _ => None,
    }
}

/// A reading within this many counts of the previous crosshair's on both
/// channels is taken as a repeated touch of the old cross and ignored.
pub const MIN_SEPARATION: u16 = 40;

/// Half the crosshair's arm length: crosses are 31×31 at 320×240.
pub const fn cross_r(lay: &Layout) -> u16 {
    lay.sm(15)
}

/// Panel coordinates of crosshair `i`'s centre.
pub fn cal_point(lay: &Layout, i: usize) -> Option<(f32, f32)> {
    cal_pixel(lay, i).map(|(x, y)| lay.pixel_center_to_panel(x, y))
}

/// Why a fit was not offered for saving.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CalFailure {
    /// The readings do not determine a calibration.
    Fit(CalibrationError),
    /// The fit spans fewer than `MIN_TOUCH_SPAN` counts on an axis (the
    /// settings store would refuse it).
    SpanTooSmall,
}

/// Where the flow is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CalPhase {
    /// Waiting for a touch on a crosshair.
    Touch {
        /// Which crosshair, 0..[`CAL_COUNT`].
        index: u8,
    },
    /// The fit is shown with Save / Cancel (or Retry / Cancel on failure).
    Review {
        /// The fitted calibration, or why there is none.
        result: Result<Calibration, CalFailure>,
    },
    /// The touch settings page, after Save on a good fit (only with
    /// [`CalibrationFlow::with_settings`]).
    Settings {
        /// The fit that Save accepted.
        cal: Calibration,
    },
}

/// What a touch on the calibration screen decided.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CalibrationEvent {
    /// Save pressed: store and use this calibration.
    Done(Calibration),
    /// Cancel pressed: keep the old calibration.
    Cancelled,
}

/// The calibration screen's state.
#[derive(Debug, Clone, PartialEq)]
pub struct CalibrationFlow {
    layout: Layout,
    old: Calibration,
    phase: CalPhase,
    samples: [Crosshair<f32>; CAL_COUNT],
    /// Each crosshair touch's mean plate ratio ([`crate::touch::contact::Contact::plate`]).
    plates: [u16; CAL_COUNT],
    rejected: bool,
    /// The touch settings being edited (`None`: no settings page).
    press: Option<PressSettings>,
}

/// The result screen's Cancel button: (16, 168, 136, 56) at 320×240.
pub const fn cancel_area(lay: &Layout) -> Area {
    Area::new(lay.sx(16), lay.sy(168), lay.sx(136) as u16, lay.sy(56) as u16)
}

/// The Save button (Retry after a failed fit): (168, 168, 136, 56) at 320×240.
pub const fn save_area(lay: &Layout) -> Area {
    Area::new(lay.sx(168), lay.sy(168), lay.sx(136) as u16, lay.sy(56) as u16)
}

impl CalibrationFlow {
    /// Starts at the first crosshair of a screen laid out as `lay`; `old` is
    /// kept for Cancel.
    pub fn new(old: Calibration, lay: &Layout) -> Self {
        let blank = Crosshair { x_p: 0.0, y_p: 0.0, raw_x: 0, raw_y: 0 };
        Self {
            layout: *lay,
            old,
            phase: CalPhase::Touch { index: 0 },
            samples: [blank; CAL_COUNT],
            plates: [0; CAL_COUNT],
            rejected: false,
            press: None,
        }
    }

    /// With a touch settings page after Save, starting from `press`.
    pub fn with_settings(mut self, press: PressSettings) -> Self {
        self.press = Some(press);
        self
    }

    /// The touch settings as edited on the settings page (`None` without
    /// one): what [`CalibrationEvent::Done`] asks to store with the fit.
    pub fn settings(&self) -> Option<PressSettings> {
        self.press
    }

    /// The screen the crosshairs are placed on.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// The current phase.
    pub fn phase(&self) -> CalPhase {
        self.phase
    }

    /// The calibration in use before this flow (kept on Cancel).
    pub fn old(&self) -> &Calibration {
        &self.old
    }

    /// Screen pixel of the crosshair to touch now.
    pub fn crosshair_pixel(&self) -> Option<(i16, i16)> {
        match self.phase {
            CalPhase::Touch { index } => cal_pixel(&self.layout, usize::from(index)),
            CalPhase::Review { .. } | CalPhase::Settings { .. } => None,
        }
    }

    /// The last reading was ignored as a repeat of the previous crosshair.
    pub fn last_rejected(&self) -> bool {
        self.rejected
    }

    /// Feeds a confirmed press (raw channels as read) and its contact's
    /// plate ratio ([`crate::touch::contact::Contact::plate`]).
    pub fn feed(&mut self, raw_x: u16, raw_y: u16, plate: u16) -> Option<CalibrationEvent> {
        match self.phase {
            CalPhase::Touch { index } => {
                self.take_sample(usize::from(index), raw_x, raw_y);
                if !self.rejected {
                    if let Some(slot) = self.plates.get_mut(usize::from(index)) {
                        *slot = plate;
                    }
                }
                None
            }
            // After a failed fit the old calibration maps Retry / Cancel;
            // after a good one the new fit maps every button: Save on its
            // review already proved it.
            CalPhase::Review { result } => {
                let cal = result.unwrap_or(self.old);
                self.button_at(&cal, raw_x, raw_y)
            }
            CalPhase::Settings { cal } => self.button_at(&cal, raw_x, raw_y),
        }
    }

    /// A touch on the review or settings page's buttons, mapped by `cal`.
    #[inline(never)] // reason: cold
    fn button_at(&mut self, cal: &Calibration, raw_x: u16, raw_y: u16) -> Option<CalibrationEvent> {
        let p = cal.map::<f32>(raw_x, raw_y).ok()?;
        let lay = self.layout;
        let (x, y) = lay.panel_to_pixel(p.x_p, p.y_p)?;
        if cancel_area(&lay).contains(x, y) {
            return Some(CalibrationEvent::Cancelled);
        }
        let save = save_area(&lay).contains(x, y);
        match self.phase {
            CalPhase::Review { result: Ok(c) } if save && self.press.is_some() => {
                self.phase = CalPhase::Settings { cal: c };
                None
            }
            CalPhase::Review { result: Ok(c) } | CalPhase::Settings { cal: c } if save => {
                Some(CalibrationEvent::Done(c))
            }
            CalPhase::Review { result: Err(_) } if save => {
                let press = self.press;
                *self = Self::new(self.old, &lay);
                self.press = press;
                None
            }
            CalPhase::Settings { .. } => {
                let field = Setting::ALL.into_iter().find(|&f| {
                    setting_area(&lay, f, false).contains(x, y) || setting_area(&lay, f, true).contains(x, y)
                })?;
                let up = setting_area(&lay, field, true).contains(x, y);
                field.step(self.press.as_mut()?, up);
                None
            }
            _ => None,
        }
    }

    /// The panel's plate ratio as the crosshair touches measured it: their
    /// median, if every one lies within half the second-contact check's
    /// tolerance of it ([`PLATE_TOL_DIV`]: one finger on an even panel) and
    /// the median is a ratio the settings take; 0 otherwise, which leaves
    /// the check off (a panel too uneven for it, or a touch that was not
    /// one finger).
    pub fn plate(&self) -> u16 {
        let mut p = self.plates;
        let m = median_u16(&mut p);
        let even = p.iter().all(|&q| u32::from(q.abs_diff(m)) * 2 * PLATE_TOL_DIV <= u32::from(m));
        if even && (PLATE_MIN..=PLATE_MAX).contains(&m) {
            m
        } else {
            0
        }
    }

    /// Leaves the flow without saving (e.g. on a timeout or a serial command).
    pub fn cancel(&mut self) -> CalibrationEvent {
        CalibrationEvent::Cancelled
    }

    fn take_sample(&mut self, index: usize, raw_x: u16, raw_y: u16) {
        if let Some(prev) = index.checked_sub(1).and_then(|i| self.samples.get(i)) {
            let near = prev.raw_x.abs_diff(raw_x) < MIN_SEPARATION && prev.raw_y.abs_diff(raw_y) < MIN_SEPARATION;
            if near {
                self.rejected = true;
                return;
            }
        }
        let (Some(slot), Some((x_p, y_p))) = (self.samples.get_mut(index), cal_point(&self.layout, index)) else {
            return;
        };
        *slot = Crosshair { x_p, y_p, raw_x, raw_y };
        self.rejected = false;
        let next = index + 1;
        self.phase = if next < CAL_COUNT {
            CalPhase::Touch { index: next as u8 }
        } else {
            CalPhase::Review { result: fit(&self.samples) }
        };
    }
}

/// A row of the touch settings page.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Setting {
    /// `hold`, hundredths of a second.
    Hold,
    /// `repeat`, hundredths of a second.
    Repeat,
    /// `radius`, ADC counts.
    Radius,
}

/// The steps − and + go through: finer where a small change matters (a
/// short hold, a small radius), all inside the ranges the settings take
/// (`config::settings`), ends included. A value set over serial between
/// two steps moves to the next step in the direction pressed.
/// In flash (`.progmem.data`), not copied into SRAM at start-up.
#[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
static HOLD_STEPS: [u8; 14] = [HOLD_MIN_CS, 6, 8, 10, 12, 15, 20, 30, 40, 50, 75, 100, 150, TIME_MAX_CS];
#[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
static REPEAT_STEPS: [u8; 11] = [0, 10, 20, 30, 40, 50, 75, 100, 125, 150, TIME_MAX_CS];
#[cfg_attr(target_arch = "avr", link_section = ".progmem.data")]
static RADIUS_STEPS: [u8; 10] = [RADIUS_MIN, 40, 60, 80, 120, 160, 200, 220, 240, 255];

/// Step `i` of a ladder above (`None` past its end).
fn ladder_at(steps: &'static [u8], i: usize) -> Option<u8> {
    if i >= steps.len() {
        return None;
    }
    // SAFETY: `steps` is one of the `.progmem.data` statics above and
    // `i < len`: on the chip the byte is in flash, read with `lpm` (a
    // plain load would read SRAM at that address).
    Some(unsafe { crate::text::flash_byte(steps.as_ptr().wrapping_add(i)) })
}

impl Setting {
    /// The page's rows, top to bottom.
    pub const ALL: [Setting; 3] = [Setting::Hold, Setting::Repeat, Setting::Radius];

    const fn row(self) -> i16 {
        match self {
            Setting::Hold => 0,
            Setting::Repeat => 1,
            Setting::Radius => 2,
        }
    }

    fn steps(self) -> &'static [u8] {
        match self {
            Setting::Hold => &HOLD_STEPS,
            Setting::Repeat => &REPEAT_STEPS,
            Setting::Radius => &RADIUS_STEPS,
        }
    }

    /// The field's value in `p`.
    pub fn value(self, p: &PressSettings) -> u8 {
        match self {
            Setting::Hold => p.hold_cs,
            Setting::Repeat => p.repeat_cs,
            Setting::Radius => p.radius,
        }
    }

    /// One step up or down the field's ladder (nothing past its ends).
    pub fn step(self, p: &mut PressSettings, up: bool) {
        let v = self.value(p);
        let steps = self.steps();
        // Read with `lpm`: the ladders are in flash.
        let at = |i| ladder_at(steps, i);
        let next = if up {
            (0..steps.len()).filter_map(at).find(|&s| s > v)
        } else {
            (0..steps.len()).rev().filter_map(at).find(|&s| s < v)
        };
        let Some(n) = next else { return };
        match self {
            Setting::Hold => p.hold_cs = n,
            Setting::Repeat => p.repeat_cs = n,
            Setting::Radius => p.radius = n,
        }
    }
}

/// Setting `field`'s + (`up`) or − button: 60×50 at the row's ends, rows
/// 50 high 4 apart from y 4, at 320×240 (above Save and Cancel).
pub const fn setting_area(lay: &Layout, field: Setting, up: bool) -> Area {
    let x = if up { 252 } else { 8 };
    Area::new(lay.sx(x), lay.sy(4 + 54 * field.row()), lay.sx(60) as u16, lay.sy(50) as u16)
}

/// The value between a row's − and +.
fn value_area(lay: &Layout, field: Setting) -> Area {
    Area::new(lay.sx(72), lay.sy(4 + 54 * field.row()), lay.sx(176) as u16, lay.sy(50) as u16)
}

fn fit(samples: &[Crosshair<f32>]) -> Result<Calibration, CalFailure> {
    let cal = Calibration::from_crosshairs(samples, SwapMode::Detect).map_err(CalFailure::Fit)?;
    if cal.x_max - cal.x_min < MIN_TOUCH_SPAN || cal.y_max - cal.y_min < MIN_TOUCH_SPAN {
        return Err(CalFailure::SpanTooSmall);
    }
    Ok(cal)
}

/// What the calibration screen shows, for partial repaints.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum CalView {
    Touch {
        index: u8,
        rejected: bool,
    },
    Review(Result<Calibration, CalFailure>),
    /// The settings page: the values shown, and `radius` in screen pixels
    /// on the axis where the fit gives the fewest (where a wander cancels
    /// first).
    Settings {
        press: PressSettings,
        radius_px: u16,
    },
}

const BG: Rgb565 = theme::WHITE;
/// The title's row on the 240-high reference screen.
const TITLE_Y: i16 = 56;

/// Titles, results and button labels: the layout's text scale.
fn style(lay: &Layout) -> TextStyle {
    TextStyle::opaque(lay.text_scale(), theme::TEXT, BG)
}

/// The "Point i of 5" line, one text row high.
fn step_area(lay: &Layout) -> Area {
    Area::new(0, lay.sy(146), lay.width(), 8 * u16::from(lay.text_scale()))
}

/// The repeated-touch hint, 1× text.
fn hint_area(lay: &Layout) -> Area {
    Area::new(0, lay.sy(170), lay.width(), 8)
}

fn cross_area(lay: &Layout, x: i16, y: i16) -> Area {
    Area::around(x, y, cross_r(lay))
}

fn draw_cross<D: Canvas>(d: &mut D, lay: &Layout, x: i16, y: i16) -> Result<(), D::Error> {
    let big_r = cross_r(lay);
    let r = big_r as i16;
    fill(d, Area::new(x - r, y - 1, 2 * big_r + 1, 3), theme::CROSSHAIR)?;
    fill(d, Area::new(x - 1, y - r, 3, 2 * big_r + 1), theme::CROSSHAIR)?;
    // A dark centre dot shows exactly where to press.
    fill(d, Area::new(x - 1, y - 1, 3, 3), theme::TEXT)
}

/// `s` centred on the row at reference height `y` (scaled to the screen).
fn line_centered<D: Canvas, T: TextSource + ?Sized>(
    d: &mut D,
    lay: &Layout,
    y: i16,
    s: &T,
    style: &TextStyle,
) -> Result<(), D::Error> {
    let (_, h) = style.extent(s.len());
    text_centered(d, Area::new(0, lay.sy(y), lay.width(), h), s, style)
}

fn draw_step<D: Canvas>(d: &mut D, lay: &Layout, index: u8) -> Result<(), D::Error> {
    let mut line: Line<26> = Line::new();
    line.str(t!("Point ")).i32(i32::from(index) + 1).str(t!(" of ")).i32(CAL_COUNT as i32);
    fill(d, step_area(lay), BG)?;
    line_centered(d, lay, 146, line.as_bytes(), &style(lay))
}

fn draw_hint<D: Canvas>(d: &mut D, lay: &Layout, rejected: bool) -> Result<(), D::Error> {
    fill(d, hint_area(lay), BG)?;
    if rejected {
        line_centered(d, lay, 170, &t!("Lift, then touch the NEW cross"), &TextStyle::opaque(1, theme::WARN_TEXT, BG))?;
    }
    Ok(())
}

fn failure_text(f: CalFailure) -> Text {
    match f {
        CalFailure::SpanTooSmall => t!("Touch range too small"),
        CalFailure::Fit(e) => match e {
            CalibrationError::AmbiguousAxes => t!("Touches did not line up"),
            CalibrationError::FitOutOfAdcRange { .. } => t!("Touches were off target"),
            CalibrationError::RawReadingOutOfRange => t!("Panel reading too high"),
            CalibrationError::EmptyRange { .. } | CalibrationError::AboveAdcRange { .. } => t!("Touch range too small"),
            CalibrationError::TooFewPoints
            | CalibrationError::DegeneratePositions
            | CalibrationError::PointOutOfRange => t!("Not enough good touches"),
        },
    }
}

fn yes_no(b: bool) -> Text {
    if b {
        t!("yes")
    } else {
        t!("no")
    }
}

#[inline(never)] // reason: cold
fn draw_review<D: Canvas>(d: &mut D, lay: &Layout, result: &Result<Calibration, CalFailure>) -> Result<(), D::Error> {
    fill(d, lay.screen(), BG)?;
    let style = style(lay);
    let t = lay.text_scale();
    match result {
        Ok(c) => {
            line_centered(d, lay, 16, &t!("Calibration result"), &style)?;
            let mut l: Line<26> = Line::new();
            l.str(t!("X ")).i32(i32::from(c.x_min)).str(t!(" - ")).i32(i32::from(c.x_max));
            line_centered(d, lay, 48, l.as_bytes(), &style)?;
            let mut l: Line<26> = Line::new();
            l.str(t!("Y ")).i32(i32::from(c.y_min)).str(t!(" - ")).i32(i32::from(c.y_max));
            line_centered(d, lay, 72, l.as_bytes(), &style)?;
            let mut l: Line<26> = Line::new();
            l.str(t!("Swap X/Y: ")).str(yes_no(c.swap_xy));
            line_centered(d, lay, 96, l.as_bytes(), &style)?;
            let mut l: Line<26> = Line::new();
            l.str(t!("Flip X: ")).str(yes_no(c.invert_x)).str(t!("  Flip Y: ")).str(yes_no(c.invert_y));
            line_centered(d, lay, 120, l.as_bytes(), &style)?;
            line_centered(d, lay, 148, &t!("Save to keep it"), &TextStyle::opaque(1, theme::TEXT_DIM, BG))?;
            draw_buttons(d, lay, t!("Save"), theme::RESUME_GREEN)
        }
        Err(f) => {
            line_centered(d, lay, 16, &t!("Calibration failed"), &TextStyle::opaque(t, theme::REFUSED, BG))?;
            line_centered(d, lay, 64, &failure_text(*f), &style)?;
            line_centered(d, lay, 96, &t!("Please try again"), &style)?;
            draw_buttons(d, lay, t!("Retry"), theme::BUTTON_ON)
        }
    }
}

/// The pages' two buttons: Save (or Retry: `label` on `color`) and Cancel.
fn draw_buttons<D: Canvas>(d: &mut D, lay: &Layout, label: Text, color: Rgb565) -> Result<(), D::Error> {
    let (save, cancel) = (save_area(lay), cancel_area(lay));
    let t = lay.text_scale();
    fill(d, save, color)?;
    text_centered(d, save, &label, &TextStyle::opaque(t, theme::WHITE, color))?;
    fill(d, cancel, theme::BUTTON)?;
    text_centered(d, cancel, &t!("Cancel"), &TextStyle::opaque(t, theme::TEXT, theme::BUTTON))
}

/// `radius` counts in screen pixels along the axis where `cal` gives the
/// fewest: the per-axis wander check ([`crate::touch::contact`]) cancels
/// there first.
fn radius_px(lay: &Layout, cal: &Calibration, radius: u8) -> u16 {
    let px = |screen: u16, span: u16| u32::from(radius) * u32::from(screen) / u32::from(span.max(1));
    let across = px(lay.width(), cal.x_max.saturating_sub(cal.x_min));
    let up = px(lay.height(), cal.y_max.saturating_sub(cal.y_min));
    across.min(up).min(u32::from(u16::MAX)) as u16
}

#[inline(never)] // reason: cold
fn draw_setting<D: Canvas>(d: &mut D, lay: &Layout, field: Setting, value: u8, radius_px: u16) -> Result<(), D::Error> {
    let a = value_area(lay, field);
    fill(d, a, BG)?;
    let style = style(lay);
    let (_, h) = style.extent(1);
    let name = match field {
        Setting::Hold => t!("Hold"),
        Setting::Repeat => t!("Ignore repeat"),
        Setting::Radius => t!("Wander limit"),
    };
    let mut l: Line<26> = Line::new();
    match field {
        Setting::Hold | Setting::Repeat => {
            l.centi(i32::from(value)).str(t!(" s"));
        }
        Setting::Radius => {
            l.i32(i32::from(value)).str(t!(" = ")).i32(i32::from(radius_px)).str(t!(" px"));
        }
    }
    let gap = (a.h.saturating_sub(2 * h)) / 3;
    text_centered(d, Area::new(a.x, a.y + gap as i16, a.w, h), &name, &style)?;
    text_centered(d, Area::new(a.x, a.y + (2 * gap + h) as i16, a.w, h), l.as_bytes(), &style)
}

#[inline(never)] // reason: cold
fn draw_settings_page<D: Canvas>(d: &mut D, lay: &Layout) -> Result<(), D::Error> {
    fill(d, lay.screen(), BG)?;
    let t = lay.text_scale();
    let key = TextStyle::opaque(t, theme::WHITE, theme::BUTTON_ON);
    for field in Setting::ALL {
        for (up, label) in [(false, t!("-")), (true, t!("+"))] {
            let a = setting_area(lay, field, up);
            fill(d, a, theme::BUTTON_ON)?;
            text_centered(d, a, &label, &key)?;
        }
    }
    line_centered(d, lay, 228, &t!("Touch settings: Save keeps them"), &TextStyle::opaque(1, theme::TEXT_DIM, BG))?;
    draw_buttons(d, lay, t!("Save"), theme::RESUME_GREEN)
}

/// What the calibration screen shows for `flow`.
pub(crate) fn view(flow: &CalibrationFlow) -> CalView {
    match flow.phase {
        CalPhase::Settings { cal } => {
            let p = flow.press.unwrap_or(PressSettings::DEFAULT);
            CalView::Settings { press: p, radius_px: radius_px(&flow.layout, &cal, p.radius) }
        }
        CalPhase::Review { result } => CalView::Review(result),
        CalPhase::Touch { index } => CalView::Touch { index, rejected: flow.rejected },
    }
}

/// Draws `new` laid out by `lay`; with `old` (what is on the glass) only the
/// changed parts are repainted. Deterministic in (`new`, `old`), so a sliced
/// redraw can replay it.
#[inline(never)] // avr-trap: frame-size
pub(crate) fn draw<D: Canvas>(lay: &Layout, new: &CalView, old: Option<&CalView>, d: &mut D) -> Result<(), D::Error> {
    match *new {
        CalView::Settings { press, radius_px } => {
            let was = match old {
                Some(&CalView::Settings { press, radius_px }) => Some((press, radius_px)),
                _ => None,
            };
            if was.is_none() {
                draw_settings_page(d, lay)?;
            }
            for field in Setting::ALL {
                let same = was.is_some_and(|(p, px)| {
                    field.value(&p) == field.value(&press) && (field != Setting::Radius || px == radius_px)
                });
                if !same {
                    draw_setting(d, lay, field, field.value(&press), radius_px)?;
                }
            }
        }
        CalView::Review(result) => {
            if old != Some(new) {
                draw_review(d, lay, &result)?;
            }
        }
        CalView::Touch { index, rejected } => {
            let centre = (lay.width() as i16 / 2, lay.height() as i16 / 2);
            let (x, y) = cal_pixel(lay, usize::from(index)).unwrap_or(centre);
            match old {
                Some(&CalView::Touch { index: i0, rejected: r0 }) => {
                    if i0 != index {
                        if let Some((ox, oy)) = cal_pixel(lay, usize::from(i0)) {
                            fill(d, cross_area(lay, ox, oy), BG)?;
                        }
                        draw_cross(d, lay, x, y)?;
                        draw_step(d, lay, index)?;
                    }
                    if r0 != rejected {
                        draw_hint(d, lay, rejected)?;
                    }
                }
                _ => {
                    fill(d, lay.screen(), BG)?;
                    line_centered(d, lay, TITLE_Y, &t!("Touch calibration"), &style(lay))?;
                    line_centered(d, lay, TITLE_Y + 24, &t!("Touch the red cross"), &style(lay))?;
                    draw_cross(d, lay, x, y)?;
                    draw_step(d, lay, index)?;
                    draw_hint(d, lay, rejected)?;
                }
            }
        }
    }
    Ok(())
}
