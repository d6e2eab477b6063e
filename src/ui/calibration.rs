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

use embedded_graphics::pixelcolor::Rgb565;

use super::draw::{fill, text_centered, Area, Canvas, TextStyle};
use super::flash::TextSource;
use super::layout::Layout;
use super::theme;
use crate::config::settings::MIN_TOUCH_SPAN;
use crate::text::line::Line;
use crate::text::Text;
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
    rejected: bool,
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
        Self { layout: *lay, old, phase: CalPhase::Touch { index: 0 }, samples: [blank; CAL_COUNT], rejected: false }
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
            CalPhase::Review { .. } => None,
        }
    }

    /// The last reading was ignored as a repeat of the previous crosshair.
    pub fn last_rejected(&self) -> bool {
        self.rejected
    }

    /// Feeds a confirmed press (raw channels as read).
    pub fn feed(&mut self, raw_x: u16, raw_y: u16) -> Option<CalibrationEvent> {
        match self.phase {
            CalPhase::Touch { index } => {
                self.take_sample(usize::from(index), raw_x, raw_y);
                None
            }
            CalPhase::Review { result } => {
                let cal = result.unwrap_or(self.old);
                let p = cal.map::<f32>(raw_x, raw_y).ok()?;
                let (x, y) = self.layout.panel_to_pixel(p.x_p, p.y_p)?;
                if cancel_area(&self.layout).contains(x, y) {
                    Some(CalibrationEvent::Cancelled)
                } else if save_area(&self.layout).contains(x, y) {
                    match result {
                        Ok(c) => Some(CalibrationEvent::Done(c)),
                        Err(_) => {
                            *self = Self::new(self.old, &self.layout);
                            None
                        }
                    }
                } else {
                    None
                }
            }
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
    Touch { index: u8, rejected: bool },
    Review(Result<Calibration, CalFailure>),
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
    let mut line: Line<16> = Line::new();
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

fn draw_review<D: Canvas>(d: &mut D, lay: &Layout, result: &Result<Calibration, CalFailure>) -> Result<(), D::Error> {
    fill(d, lay.screen(), BG)?;
    let style = style(lay);
    let t = lay.text_scale();
    let (save, cancel) = (save_area(lay), cancel_area(lay));
    match result {
        Ok(c) => {
            line_centered(d, lay, 16, &t!("Calibration result"), &style)?;
            let mut l: Line<24> = Line::new();
            l.str(t!("X ")).i32(i32::from(c.x_min)).str(t!(" - ")).i32(i32::from(c.x_max));
            line_centered(d, lay, 48, l.as_bytes(), &style)?;
            let mut l: Line<24> = Line::new();
            l.str(t!("Y ")).i32(i32::from(c.y_min)).str(t!(" - ")).i32(i32::from(c.y_max));
            line_centered(d, lay, 72, l.as_bytes(), &style)?;
            let mut l: Line<24> = Line::new();
            l.str(t!("Swap X/Y: ")).str(yes_no(c.swap_xy));
            line_centered(d, lay, 96, l.as_bytes(), &style)?;
            let mut l: Line<26> = Line::new();
            l.str(t!("Flip X: ")).str(yes_no(c.invert_x)).str(t!("  Flip Y: ")).str(yes_no(c.invert_y));
            line_centered(d, lay, 120, l.as_bytes(), &style)?;
            line_centered(d, lay, 148, &t!("Save to keep it"), &TextStyle::opaque(1, theme::TEXT_DIM, BG))?;
            fill(d, save, theme::RESUME_GREEN)?;
            text_centered(d, save, &t!("Save"), &TextStyle::opaque(t, theme::WHITE, theme::RESUME_GREEN))?;
        }
        Err(f) => {
            line_centered(d, lay, 16, &t!("Calibration failed"), &TextStyle::opaque(t, theme::REFUSED, BG))?;
            line_centered(d, lay, 64, &failure_text(*f), &style)?;
            line_centered(d, lay, 96, &t!("Please try again"), &style)?;
            fill(d, save, theme::BUTTON_ON)?;
            text_centered(d, save, &t!("Retry"), &TextStyle::opaque(t, theme::WHITE, theme::BUTTON_ON))?;
        }
    }
    fill(d, cancel, theme::BUTTON)?;
    text_centered(d, cancel, &t!("Cancel"), &TextStyle::opaque(t, theme::TEXT, theme::BUTTON))
}

/// What the calibration screen shows for `flow`.
pub(crate) fn view(flow: &CalibrationFlow) -> CalView {
    match flow.phase {
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
