//! The main screen renderer: draws a [`UiModel`], remembers what it drew and
//! afterwards repaints only the regions whose visible content changed; maps
//! touches back to buttons and map points.
//!
//! "Visible content" is compared, not raw model values: joint angles are
//! compared in whole degrees, progress in bar pixels and percent, points in
//! map pixels, so a 0.01° wobble repaints nothing.

use embedded_graphics::pixelcolor::Rgb565;

use super::calibration::{self, CalView, CalibrationFlow};
use super::degrees::{whole_deg, PushDeg};
use super::draw::{fill, frame, text, Area, Canvas, TextStyle};
use super::flash::{Chars, TextSource};
use super::layout::{Layout, SLOTS};
use super::model::{warn, Page, Refusal, UiModel, UiState};
use super::scan::{ScanShow, STOP_ITEM};
use super::slice::{DrawBudget, Slicer, Unlimited};
use super::theme;
use super::ws_view::{self, Mark, MarkKind, Reach};
use crate::config::access::item;
use crate::config::settings::SpeedPreset;
use crate::text::line::Line;
use crate::text::Text;

/// Which regions a draw call repainted (bit set).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Redrawn(pub u16);

impl Redrawn {
    /// The whole map (background and everything on it).
    pub const MAP: u16 = 1 << 0;
    /// Only the boxes around markers that moved, appeared or vanished.
    pub const MARKERS: u16 = 1 << 1;
    /// The STOP / RESUME button.
    pub const STOP: u16 = 1 << 2;
    /// [`Layout::headline`].
    pub const HEADLINE: u16 = 1 << 3;
    /// [`Layout::detail`] (text or progress bar).
    pub const DETAIL: u16 = 1 << 4;
    /// [`Layout::info`].
    pub const INFO: u16 = 1 << 5;
    /// [`Layout::warn`].
    pub const WARN: u16 = 1 << 6;
    /// [`Layout::joints`].
    pub const JOINTS: u16 = 1 << 7;
    /// The three speed presets (main page).
    pub const SPEED: u16 = 1 << 8;
    /// The page key, the row's last button: More or Back.
    pub const PAGE_KEY: u16 = 1 << 9;
    /// Guard bands and gaps (full redraws only).
    pub const GAPS: u16 = 1 << 10;
    /// The calibration screen (all of it, or the parts that changed).
    pub const CALIBRATION: u16 = 1 << 11;
    /// The page's other buttons: Undo (main page), poses 1–4 (More), Grab
    /// and Cal (Setup).
    pub const ROW2: u16 = 1 << 12;
    /// The Setup page's toggles Line and Lift (only the one that changed).
    pub const TOGGLES: u16 = 1 << 13;
    /// The switch scan's highlight round a button or STOP's place.
    pub const SCAN: u16 = 1 << 14;
    /// A full redraw of the main page (the map repaint covers the markers).
    pub const ALL_MAIN: u16 = ((1 << 11) - 1 - Self::MARKERS) | Self::ROW2;
    /// A full redraw of the More page: the status lines, the poses and the
    /// page key.
    pub const ALL_MORE: u16 = Self::ALL_MAIN - Self::SPEED;
    /// A full redraw of the Setup page.
    pub const ALL_SETUP: u16 = Self::ALL_MORE | Self::TOGGLES;

    /// Every region in `bits` was repainted.
    pub const fn contains(self, bits: u16) -> bool {
        self.0 & bits == bits
    }

    /// Nothing was repainted.
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }
}

/// What a touch on the main screen means.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Hit {
    /// The STOP button (or beside it, in the guard band).
    Stop,
    /// The RESUME button, shown after a stop.
    Resume,
    /// A speed preset button.
    Speed(SpeedPreset),
    /// Undo (main page): back to the pose before the last move (`undo`).
    Undo,
    /// The Cal button (Setup page): the touch calibration.
    Calibrate,
    /// The page key: More on Main and More, Back on Setup.
    Page,
    /// Saved pose button `n` (1..=4, More page).
    Pose(u8),
    /// The Grip button (Setup page).
    Grip,
    /// The Line toggle (Setup page): `path line` ↔ `path joint`.
    Line,
    /// The Lift toggle (Setup page): a lift ↔ `lift off`.
    Lift,
    /// Carer gesture place `k` ([`Layout::carer_corner`], every page):
    /// nothing is drawn there and a touch does nothing but a step of the
    /// carer's gesture (`app::access`).
    Carer(u8),
    /// A point of the map, in workspace coordinates.
    Map {
        /// −1..=1, left → right.
        x_p: f32,
        /// 0..=1, bottom → top.
        y_p: f32,
    },
}

/// The arm's reach drawn on the map, in workspace units: for links `l2, l3`
/// and screen-to-arm scale `k`, `reach_min = |l2 − l3|/k`,
/// `reach_max = (l2 + l3)/k`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UiConfig {
    /// Inner radius of the reachable ring, workspace units.
    pub reach_min: f32,
    /// Outer radius of the reachable ring, workspace units.
    pub reach_max: f32,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Headline {
    Starting,
    Ready,
    Checking,
    Moving,
    Holding,
    Paused,
    Stopped,
    OutOfReach,
    OffMap,
    JointLimit,
    Busy,
    Cancelled,
    Hand,
    Resuming,
}

impl Headline {
    fn text(self) -> Text {
        match self {
            Headline::Starting => t!("Starting up"),
            Headline::Ready => t!("Ready"),
            Headline::Checking => t!("Checking the way"),
            Headline::Moving => t!("Moving to target"),
            Headline::Holding => t!("Holding"),
            Headline::Paused => t!("Paused"),
            Headline::Stopped => t!("Stopped - hold RESUME"),
            Headline::Cancelled => t!("Cancelled"),
            Headline::Hand => t!("Lift your hand"),
            Headline::Resuming => t!("Keep holding RESUME"),
            Headline::OutOfReach => t!("Out of reach"),
            Headline::OffMap => t!("Not on the map"),
            Headline::JointLimit => t!("Can't reach that way"),
            Headline::Busy => t!("Still moving"),
        }
    }

    fn color(self) -> Rgb565 {
        match self {
            Headline::Stopped | Headline::OutOfReach | Headline::OffMap | Headline::JointLimit | Headline::Hand => {
                theme::REFUSED
            }
            _ => theme::TEXT,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Detail {
    Hint(Text),
    /// Filled bar pixels and the percentage shown.
    Progress {
        px: u16,
        percent: u8,
    },
}

/// The screen as drawn, in display units.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct View {
    stop_shown: bool,
    /// RESUME's countdown ring, 0..=4 (0 while STOP is shown).
    resume_ring: u8,
    headline: Headline,
    detail: Detail,
    zone: Option<(u8, Option<i16>)>,
    warning: u8,
    joints: [Option<i16>; 3],
    touch: Option<Mark>,
    target: Option<Mark>,
    /// The candidate under a finger (on top of the others).
    candidate: Option<Mark>,
    speed: SpeedPreset,
    page: Page,
    /// The More page's states, [`GRIP_CLOSED`] | [`PATH_LINE`] | [`LIFT`]:
    /// one byte, since the renderer holds two views (what is shown and the
    /// redraw's target) in the app's RAM.
    more: u8,
    /// [`UiModel::hide`].
    hide: u8,
    /// [`UiModel::confirm`].
    confirm: u8,
    /// The switch scan's line: `x + 1` for a column, `−(y + 1)` for a row,
    /// 0 for none (two bytes, not an `Option<Mark>`: two views live in RAM).
    line: i16,
    /// The item the switch scan highlights, plus one (0: none).
    item: u8,
}

/// The scan's line as a mark ([`View::line`]).
fn line_mark(line: i16) -> Option<Mark> {
    match line {
        0 => None,
        x if x > 0 => Some(Mark { x: x - 1, y: 0, kind: MarkKind::ScanColumn }),
        y => Some(Mark { x: 0, y: -y - 1, kind: MarkKind::ScanRow }),
    }
}

/// The highlighted item if it is a button of the row (1..=5), else 0: the
/// row is repainted when it changes.
const fn slot_highlight(item: u8) -> u8 {
    if item >= 1 && item <= STOP_ITEM {
        item
    } else {
        0
    }
}

const GRIP_CLOSED: u8 = 1 << 0;
const PATH_LINE: u8 = 1 << 1;
const LIFT: u8 = 1 << 2;

/// Filled pixels of a `bar_w`-pixel bar and the percentage shown.
fn progress_of(p: f32, bar_w: u16) -> (u16, u8) {
    // NaN → 0 through the failed comparison.
    let p = if p > 0.0 { p.min(1.0) } else { 0.0 };
    let px = (p * bar_w as f32 + 0.5) as u16;
    let percent = (p * 100.0 + 0.5) as u8;
    (px.min(bar_w), percent.min(100))
}

/// The highest set warning bit.
fn top_warning(bits: u8) -> u8 {
    if bits == 0 {
        return 0;
    }
    // A bit at a time: `leading_zeros` is a long inline expansion on the AVR.
    let mut top = 0x80;
    while bits & top == 0 {
        top >>= 1;
    }
    top
}

/// The warning line the screen shows for [`warn`] bits (the most important
/// set bit; empty for none).
pub fn warning_line(bits: u8) -> Text {
    warning_text(top_warning(bits))
}

fn warning_text(bit: u8) -> Text {
    match bit {
        warn::COPY_DAMAGED => t!("! a settings copy damaged"),
        warn::DEFAULT_SETTINGS => t!("! default settings in use"),
        warn::SERVOS_OFF => t!("! servos are off"),
        warn::TOUCH_WIRING => t!("! touch wiring unknown"),
        0 => t!(""),
        _ => t!("! check the serial log"),
    }
}

impl View {
    fn of(m: &UiModel, lay: &Layout) -> Self {
        let (headline, detail) = match m.state {
            UiState::PowerUp => (Headline::Starting, Detail::Hint(t!("Please wait"))),
            UiState::Idle => (Headline::Ready, Detail::Hint(t!("Touch the map to move"))),
            UiState::Checking => (Headline::Checking, Detail::Hint(t!("The arm starts soon"))),
            UiState::Moving { progress } => {
                let (px, percent) = progress_of(progress, lay.bar_fill().w);
                (Headline::Moving, Detail::Progress { px, percent })
            }
            UiState::Holding => (Headline::Holding, Detail::Hint(t!("Touch the map to move"))),
            UiState::Paused => (Headline::Paused, Detail::Hint(t!("Hold the map to go on"))),
            UiState::Stopped => match m.resume {
                Some(k) => {
                    let (px, percent) = progress_of(f32::from(k) / 4.0, lay.bar_fill().w);
                    (Headline::Resuming, Detail::Progress { px, percent })
                }
                None => (Headline::Stopped, Detail::Hint(t!("The arm holds still"))),
            },
            UiState::Refused(r) => match r {
                Refusal::TooFar => (Headline::OutOfReach, Detail::Hint(t!("Try closer to the base"))),
                Refusal::TooClose => (Headline::OutOfReach, Detail::Hint(t!("Try further from base"))),
                Refusal::OffMap => (Headline::OffMap, Detail::Hint(t!("Touch inside the map"))),
                Refusal::JointLimit => (Headline::JointLimit, Detail::Hint(t!("Try another point"))),
                Refusal::Busy => (Headline::Busy, Detail::Hint(t!("Wait, or tap STOP"))),
                Refusal::Cancelled => (Headline::Cancelled, Detail::Hint(t!("Lift on the map to move"))),
                Refusal::Hand => (Headline::Hand, Detail::Hint(t!("Touch with one finger"))),
            },
        };
        // The scan says what a press does now, where the hint is a hint.
        let detail = match (m.scan, detail) {
            (Some(sc), Detail::Hint(_)) => Detail::Hint(match sc {
                ScanShow::Column(_) => t!("Press: this column"),
                ScanShow::Row(_) => t!("Press: this row"),
                ScanShow::Target { go: true, .. } => t!("Press now to go"),
                ScanShow::Target { go: false, .. } => t!("Press now to cancel"),
                ScanShow::Item(_) => t!("Press: this button"),
            }),
            (_, d) => d,
        };
        let refused = matches!(m.state, UiState::Refused(_));
        let mark = |p: Option<(f32, f32)>, kind: MarkKind| {
            p.and_then(|(x, y)| lay.ws_point_to_pixel(x, y)).map(|(x, y)| Mark { x, y, kind })
        };
        View {
            stop_shown: m.state != UiState::Stopped,
            resume_ring: if m.state == UiState::Stopped { m.resume.unwrap_or(0).min(4) } else { 0 },
            headline,
            detail,
            zone: m.condition.map(|c| (c.number(), whole_deg(m.alpha))),
            warning: top_warning(m.warnings),
            joints: [whole_deg(m.joints[0]), whole_deg(m.joints[1]), whole_deg(m.joints[2])],
            touch: mark(m.touch, if refused { MarkKind::TouchRefused } else { MarkKind::Touch }),
            target: mark(m.target, MarkKind::Target),
            candidate: m
                .preview
                .and_then(|p| mark(Some((p.x_p, p.y_p)), MarkKind::Candidate { ok: p.ok, ring: p.ring.min(4) })),
            speed: m.speed,
            page: m.page,
            more: if m.grip_closed { GRIP_CLOSED } else { 0 }
                | if m.path_line { PATH_LINE } else { 0 }
                | if m.lift { LIFT } else { 0 },
            hide: m.hide,
            confirm: m.confirm,
            line: match m.scan {
                Some(ScanShow::Column(x)) => x + 1,
                Some(ScanShow::Row(y)) => -(y + 1),
                _ => 0,
            },
            item: match m.scan {
                Some(ScanShow::Item(i)) => i + 1,
                _ => 0,
            },
        }
    }

    /// Markers in drawing order (the scan's line under the others, the
    /// touch on top).
    fn marks(&self) -> ([Mark; 4], usize) {
        let mut out = [Mark { x: 0, y: 0, kind: MarkKind::Touch }; 4];
        let mut n = 0;
        for m in [line_mark(self.line), self.target, self.touch, self.candidate].into_iter().flatten() {
            if let Some(slot) = out.get_mut(n) {
                *slot = m;
                n += 1;
            }
        }
        (out, n)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Shown {
    Nothing,
    Main(View),
    Calibration(CalView),
}

/// A redraw under way: the picture it draws and how far it got (the step,
/// and the drawing operations of that step already done; see `slice`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Pass {
    target: Shown,
    step: u8,
    op: u32,
    /// Bit k: step k has something to draw (worked out once per pass, so
    /// the others cost nothing).
    steps: u64,
}

/// The renderer. Holds its layout, what it last drew and the redraw under
/// way (a few dozen bytes).
pub struct Ui {
    layout: Layout,
    reach: Reach,
    /// What the glass showed when the redraw under way started (all of it
    /// when none is).
    shown: Shown,
    pass: Option<Pass>,
}

/// What a sliced draw did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Drawn {
    /// Regions whose repaint completed in this call.
    pub redrawn: Redrawn,
    /// The glass shows the requested picture (false: the budget ran out;
    /// call again in the next frame).
    pub finished: bool,
}

/// Map rows per redraw step (the map's background is computed row by row,
/// so a step resumed in the middle recomputes at most this many rows).
const BAND_ROWS: u16 = 8;
/// Map bands of the largest layout; a smaller map leaves the last band
/// steps empty.
const BANDS: u8 = (Layout::HVGA.ws().h / BAND_ROWS) as u8;
const _: () = assert!(Layout::HVGA.ws().h.is_multiple_of(BAND_ROWS) && Layout::QVGA.ws().h.is_multiple_of(BAND_ROWS));
const _: () = assert!(Layout::QVGA.ws().h <= Layout::HVGA.ws().h);
const S_OVERLAYS: u8 = BANDS;
const S_GAPS: u8 = BANDS + 1;
const S_STOP: u8 = BANDS + 2;
const S_HEADLINE: u8 = BANDS + 3;
const S_DETAIL: u8 = BANDS + 4;
const S_INFO: u8 = BANDS + 5;
const S_WARN: u8 = BANDS + 6;
const S_JOINTS: u8 = BANDS + 7;
const S_SPEED: u8 = BANDS + 8;
const S_KEY: u8 = BANDS + 9;
const S_ROW2: u8 = BANDS + 10;
const S_TOGGLES: u8 = BANDS + 11;
/// The switch scan's frame round the highlighted item.
const S_SCAN: u8 = BANDS + 12;
/// Up to eight marker boxes (old and new scan line, target, touch and
/// candidate).
const S_MARKERS: u8 = BANDS + 13;
const S_END: u8 = S_MARKERS + 8;
/// The steps a page change redraws: the row of buttons.
const PAGE_STEPS: u64 = (1 << S_SPEED) | (1 << S_KEY) | (1 << S_ROW2) | (1 << S_TOGGLES);
const _: () = assert!(S_END <= 64);

/// The headline, hints and percentage: the layout's text scale.
fn head_style(lay: &Layout, fg: Rgb565) -> TextStyle {
    TextStyle::opaque(lay.text_scale(), fg, theme::BG)
}

/// A button label in the layout's text scale.
fn label_style(lay: &Layout, fg: Rgb565, bg: Rgb565) -> TextStyle {
    TextStyle::opaque(lay.text_scale(), fg, bg)
}

const SMALL_STYLE: TextStyle = TextStyle::opaque(1, theme::TEXT, theme::BG);

/// Paints `a` exactly once: `s` at `(a.x + pad, vertically centred)`, the
/// rest of `a` in `bg`. Text longer than `a` is cut at a whole character.
#[inline]
fn text_box<D: Canvas, T: TextSource + ?Sized>(d: &mut D, a: Area, s: &T, style: &TextStyle) -> Result<(), D::Error> {
    text_box_chars(d, a, &s.chars(), style)
}

/// [`text_box`] for either kind of text: one copy for both.
fn text_box_chars<D: Canvas>(d: &mut D, a: Area, s: &Chars<'_>, style: &TextStyle) -> Result<(), D::Error> {
    let pad: u16 = 4;
    let (cw, th) = style.extent(1);
    let fit = (a.w.saturating_sub(pad) / cw.max(1)) as usize;
    let n = s.len().min(fit);
    let (tw, _) = style.extent(n);
    let inner = Area::new(a.x + pad as i16, a.y + (a.h.saturating_sub(th) / 2) as i16, tw, th.min(a.h));
    text(d, inner.x, inner.y, &Prefix { s, n }, style)?;
    fill_around(d, a, inner, style.bg.unwrap_or(theme::BG))
}

/// The first `n` bytes of a text.
struct Prefix<'a, T: ?Sized> {
    s: &'a T,
    n: usize,
}

impl<T: TextSource + ?Sized> TextSource for Prefix<'_, T> {
    fn len(&self) -> usize {
        self.n.min(self.s.len())
    }

    fn at(&self, i: usize) -> u8 {
        if i < self.n {
            self.s.at(i)
        } else {
            0
        }
    }

    fn chars(&self) -> Chars<'_> {
        match self.s.chars() {
            Chars::Flash(t) => Chars::Flash(t.prefix(self.n)),
            Chars::Ram(b) => Chars::Ram(b.get(..self.n).unwrap_or(b)),
        }
    }
}

/// Fills `outer` minus `inner` (which must lie inside it) in up to 4 strips.
fn fill_around<D: Canvas>(d: &mut D, outer: Area, inner: Area, c: Rgb565) -> Result<(), D::Error> {
    let Some(inner) = inner.intersect(&outer) else {
        return fill(d, outer, c);
    };
    fill(d, Area::new(outer.x, outer.y, outer.w, (inner.y - outer.y) as u16), c)?;
    fill(d, Area::new(outer.x, inner.bottom(), outer.w, (outer.bottom() - inner.bottom()) as u16), c)?;
    fill(d, Area::new(outer.x, inner.y, (inner.x - outer.x) as u16, inner.h), c)?;
    fill(d, Area::new(inner.right(), inner.y, (outer.right() - inner.right()) as u16, inner.h), c)
}

/// A button: `a` filled with `bg` and `label` centred, each pixel once.
fn button<D: Canvas>(d: &mut D, a: Area, label: Text, style: &TextStyle) -> Result<(), D::Error> {
    let (tw, th) = style.extent(label.len());
    // Centre the ink: the last glyph's trailing gap is blank.
    let ink_w = tw.saturating_sub(u16::from(style.gap));
    let inner =
        Area::new(a.x + (a.w.saturating_sub(ink_w) / 2) as i16, a.y + (a.h.saturating_sub(th) / 2) as i16, tw, th);
    text(d, inner.x, inner.y, &label, style)?;
    fill_around(d, a, inner, style.bg.unwrap_or(theme::BG))
}

impl Ui {
    /// A 320×240 UI ([`Layout::QVGA`]) with `config`'s reach; nothing is
    /// drawn until [`Ui::draw`].
    pub fn new(config: &UiConfig) -> Self {
        Self::with_layout(config, Layout::QVGA)
    }

    /// A UI laid out as `layout` (the panel's size) with `config`'s reach.
    pub fn with_layout(config: &UiConfig, layout: Layout) -> Self {
        let reach = Reach::new(config.reach_min, config.reach_max, layout.scale());
        Self { layout, reach, shown: Shown::Nothing, pass: None }
    }

    /// Where everything sits.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// Changes the reach shading; the next [`Ui::draw`] repaints the map.
    pub fn set_reach(&mut self, config: &UiConfig) {
        self.reach = Reach::new(config.reach_min, config.reach_max, self.layout.scale());
        if let Shown::Main(_) = self.shown {
            self.invalidate();
        }
    }

    /// Forgets what is on the glass (after a display reset): the next draw is
    /// full.
    pub fn invalidate(&mut self) {
        self.shown = Shown::Nothing;
        self.pass = None;
    }

    /// Draws the main screen, repainting only what differs from the last
    /// draw (everything after a calibration screen, a reach change or an
    /// error).
    pub fn draw<D: Canvas>(&mut self, model: &UiModel, d: &mut D) -> Result<Redrawn, D::Error> {
        self.draw_sliced(model, d, &mut Unlimited).map(|r| r.redrawn)
    }

    /// [`Ui::draw`] within `budget`: what does not fit is drawn by the next
    /// calls (a redraw under way is finished before a newer picture starts,
    /// so the glass always converges on the latest model).
    pub fn draw_sliced<D: Canvas, B: DrawBudget>(
        &mut self,
        model: &UiModel,
        d: &mut D,
        budget: &mut B,
    ) -> Result<Drawn, D::Error> {
        self.run(Shown::Main(View::of(model, &self.layout)), d, budget)
    }

    /// Draws the whole main screen.
    pub fn draw_full<D: Canvas>(&mut self, model: &UiModel, d: &mut D) -> Result<Redrawn, D::Error> {
        self.invalidate();
        self.draw(model, d)
    }

    /// Redraws towards `target` until it is on the glass or the budget ends.
    #[cfg_attr(target_arch = "avr", optimize(size))] // reason: cold
    fn run<D: Canvas, B: DrawBudget>(&mut self, target: Shown, d: &mut D, budget: &mut B) -> Result<Drawn, D::Error> {
        let mut redrawn = 0u16;
        loop {
            let mut pass = match self.pass {
                Some(p) => p,
                None if self.shown == target => return Ok(Drawn { redrawn: Redrawn(redrawn), finished: true }),
                None => Pass { target, step: 0, op: 0, steps: self.steps_to(&target) },
            };
            // The steps still to do, lowest first (one shift here: a shift by
            // a variable amount is a loop on the AVR).
            let mut todo = pass.steps >> pass.step;
            while todo != 0 {
                if todo & 1 == 0 {
                    pass.step += 1;
                    todo >>= 1;
                    continue;
                }
                let mut s = Slicer::new(d, budget, pass.op);
                let r = self.step(&pass.target, pass.step, &mut s);
                let (ops, paused) = (s.ops, s.paused);
                match r {
                    Ok(_) if paused => {
                        pass.op = ops;
                        self.pass = Some(pass);
                        return Ok(Drawn { redrawn: Redrawn(redrawn), finished: false });
                    }
                    Ok(bits) => {
                        redrawn |= bits;
                        pass.step += 1;
                        pass.op = 0;
                        todo >>= 1;
                    }
                    Err(e) => {
                        self.invalidate();
                        return Err(e);
                    }
                }
            }
            self.shown = pass.target;
            self.pass = None;
        }
    }

    /// The steps of a redraw from `self.shown` to `target` (see [`Pass`]).
    fn steps_to(&self, target: &Shown) -> u64 {
        let (old, v) = match (&self.shown, target) {
            (Shown::Main(o), Shown::Main(v)) => (o, v),
            (_, Shown::Main(_)) => return (1 << (S_SCAN + 1)) - 1,
            _ => return 1,
        };
        let bit = |changed: bool, k: u8| if changed { 1u64 << k } else { 0 };
        // One step per box that changed, no more: a step with no box still
        // works out the list before it finds that out, between the budget's
        // asks (with all eight steps every time, the busiest window's
        // frames ran late).
        let mut boxes = 0u64;
        for _ in 0..self.marker_box(old, v, 0).1 {
            // One-bit shifts: a variable one is a loop on the AVR anyway.
            boxes = (boxes << 1) | 1;
        }
        let markers = boxes << S_MARKERS;
        // A new page: its row of buttons (STOP, the headline, the status
        // lines and the map as usual); so is a new scan highlight on it.
        let page = if !same_row(old, v) { PAGE_STEPS } else { 0 };
        let on_stop = |i: u8| i == STOP_ITEM + 1;
        let stop_hl = on_stop(old.item) != on_stop(v.item);
        let more = old.more ^ v.more;
        let steps = page
            | bit(old.stop_shown != v.stop_shown || old.resume_ring != v.resume_ring || stop_hl, S_STOP)
            | bit(old.headline != v.headline, S_HEADLINE)
            | bit(old.detail != v.detail, S_DETAIL)
            | bit(old.zone != v.zone, S_INFO)
            | bit(old.warning != v.warning, S_WARN)
            | bit(old.joints != v.joints, S_JOINTS)
            | bit(old.speed != v.speed && v.page == Page::Main, S_SPEED)
            | bit(more & GRIP_CLOSED != 0 && v.page == Page::Setup, S_ROW2)
            | bit(old.confirm != v.confirm && v.page == Page::More, S_ROW2)
            | bit(more & (PATH_LINE | LIFT) != 0 && v.page == Page::Setup, S_TOGGLES)
            | markers;
        // The highlight goes on after whatever repaints under it.
        let under = PAGE_STEPS | (1 << S_STOP);
        steps | bit(v.item != 0 && (old.item != v.item || steps & under != 0), S_SCAN)
    }

    /// Step `k` of the redraw from `self.shown` to `target` (nothing if the
    /// step does not apply); the [`Redrawn`] bits it painted.
    #[inline(never)] // avr-trap: frame-size
    fn step<D: Canvas>(&self, target: &Shown, k: u8, d: &mut D) -> Result<u16, D::Error> {
        match (target, &self.shown) {
            (Shown::Main(v), Shown::Main(o)) => self.main_step(Some(o), v, k, d),
            (Shown::Main(v), _) => self.main_step(None, v, k, d),
            (Shown::Calibration(v), old) if k == 0 => {
                let old = match old {
                    Shown::Calibration(o) => Some(o),
                    _ => None,
                };
                calibration::draw(&self.layout, v, old, d)?;
                Ok(Redrawn::CALIBRATION)
            }
            _ => Ok(0),
        }
    }

    /// The main screen's steps: in a full redraw (`old` = `None`) the map in
    /// bands, its overlays, the gaps and every region; otherwise the regions
    /// whose visible content changed and the boxes around markers that moved.
    #[inline(never)] // avr-trap: frame-size
    fn main_step<D: Canvas>(&self, old: Option<&View>, v: &View, k: u8, d: &mut D) -> Result<u16, D::Error> {
        let lay = &self.layout;
        let ws = lay.ws();
        // The row of buttons is new with a new page or a lock change.
        let page_step = (PAGE_STEPS >> k) & 1 != 0;
        let old = old.filter(|o| same_row(o, v) || !page_step);
        let main = v.page == Page::Main;
        let setup = v.page == Page::Setup;
        match k {
            _ if k < BANDS && old.is_none() => {
                let top = u16::from(k) * BAND_ROWS;
                if top < ws.h {
                    let band = Area::new(ws.x, ws.y + top as i16, ws.w, BAND_ROWS);
                    ws_view::draw_background(d, lay, &self.reach, band)?;
                }
                return Ok(Redrawn::MAP);
            }
            S_OVERLAYS if old.is_none() => {
                let (marks, n) = v.marks();
                ws_view::draw_overlays(d, lay, ws, marks.get(..n).unwrap_or(&[]))?;
                return Ok(Redrawn::MAP);
            }
            S_GAPS if old.is_none() => {
                draw_gaps(d, lay)?;
                return Ok(Redrawn::GAPS);
            }
            S_STOP
                if old.is_none_or(|o| {
                    o.stop_shown != v.stop_shown
                        || o.resume_ring != v.resume_ring
                        || (o.item == STOP_HL) != (v.item == STOP_HL)
                }) =>
            {
                // A highlight that leaves repaints the whole button.
                let ring = old.filter(|o| o.stop_shown == v.stop_shown && o.item != STOP_HL).map(|o| o.resume_ring);
                draw_stop(d, lay, v.stop_shown, v.resume_ring, ring)?;
                return Ok(Redrawn::STOP);
            }
            S_HEADLINE if old.is_none_or(|o| o.headline != v.headline) => {
                draw_headline(d, lay, v.headline)?;
                return Ok(Redrawn::HEADLINE);
            }
            S_DETAIL if old.is_none_or(|o| o.detail != v.detail) => {
                match (old.map(|o| o.detail), v.detail) {
                    (Some(Detail::Progress { px: a, percent: pa }), Detail::Progress { px: b, percent: pb }) => {
                        update_progress(d, lay, a, b)?;
                        if pa != pb {
                            draw_percent(d, lay, pb)?;
                        }
                    }
                    _ => draw_detail(d, lay, &v.detail)?,
                }
                return Ok(Redrawn::DETAIL);
            }
            S_INFO if old.is_none_or(|o| o.zone != v.zone) => {
                draw_info(d, lay, v.zone)?;
                return Ok(Redrawn::INFO);
            }
            S_WARN if old.is_none_or(|o| o.warning != v.warning) => {
                draw_warning(d, lay, v.warning)?;
                return Ok(Redrawn::WARN);
            }
            S_JOINTS if old.is_none_or(|o| o.joints != v.joints) => {
                draw_joints(d, lay, &v.joints)?;
                return Ok(Redrawn::JOINTS);
            }
            S_SPEED if main && old.is_none_or(|o| o.speed != v.speed) => {
                draw_speed(d, lay, v.speed, v.hide)?;
                return Ok(Redrawn::SPEED);
            }
            S_KEY if old.is_none() => {
                let label = if setup { t!("Back") } else { t!("More") };
                button(d, lay.page_key(), label, &label_style(lay, theme::TEXT, theme::BUTTON))?;
                return Ok(Redrawn::PAGE_KEY);
            }
            S_ROW2
                if old.is_none_or(|o| {
                    (setup && (o.more ^ v.more) & GRIP_CLOSED != 0) || (v.page == Page::More && o.confirm != v.confirm)
                }) =>
            {
                draw_row2(d, lay, v, old.is_none())?;
                return Ok(Redrawn::ROW2);
            }
            S_TOGGLES if setup => {
                // Only a toggle whose state changed (both in a full draw).
                let changed = old.map_or(PATH_LINE | LIFT, |o| o.more ^ v.more);
                let (line, lift) = (changed & PATH_LINE != 0, changed & LIFT != 0);
                if line {
                    draw_toggle(
                        d,
                        lay.line_toggle(),
                        t!("Line"),
                        v.more & PATH_LINE != 0,
                        v.hide & item::LINE != 0,
                        lay,
                    )?;
                }
                if lift {
                    draw_toggle(d, lay.lift_toggle(), t!("Lift"), v.more & LIFT != 0, v.hide & item::LIFT != 0, lay)?;
                }
                return Ok(if line || lift { Redrawn::TOGGLES } else { 0 });
            }
            S_SCAN if v.item != 0 => {
                let i = v.item - 1;
                let a = if i == STOP_ITEM { lay.stop() } else { lay.slot(i) };
                frame(d, a, lay.sm(4), theme::SCAN)?;
                return Ok(Redrawn::SCAN);
            }
            _ if k >= S_MARKERS => {
                if let Some(o) = old {
                    return self.marker_step(o, v, usize::from(k - S_MARKERS), d);
                }
            }
            _ => {}
        }
        Ok(0)
    }

    /// Repaints box `i` of the markers that changed ([`Self::marker_box`]).
    #[inline(never)] // avr-trap: frame-size
    fn marker_step<D: Canvas>(&self, old: &View, v: &View, i: usize, d: &mut D) -> Result<u16, D::Error> {
        let (Some(box_), _) = self.marker_box(old, v, i) else {
            return Ok(0);
        };
        let (marks, k) = v.marks();
        let marks = marks.get(..k).unwrap_or(&[]);
        // The new scan line is opaque over all of its box: the background
        // under it would be painted over at once (for a column, a hundred
        // map rows of it, and the line trailed the scan on the chip).
        if line_mark(v.line).is_some_and(|m| m.area(&self.layout) == box_) {
            ws_view::draw_overlays(d, &self.layout, box_, marks)?;
        } else {
            ws_view::repaint(d, &self.layout, &self.reach, box_, marks)?;
        }
        Ok(Redrawn::MARKERS)
    }

    /// Box `i` of the markers that changed (old and new places of the scan
    /// line, the touch, the target and the candidate), unless an earlier
    /// box covers it; and how many boxes there are. Out of line, so its
    /// list of boxes is not on the stack while the box is repainted: the
    /// draw chain is the UI's deepest (ui-demo).
    #[inline(never)] // avr-trap: frame-size
    fn marker_box(&self, old: &View, v: &View, i: usize) -> (Option<Area>, u8) {
        let lay = &self.layout;
        let mut dirty = [Area::new(0, 0, 0, 0); 8];
        let mut n = 0;
        let lines = (line_mark(old.line), line_mark(v.line));
        for (a, b) in [lines, (old.touch, v.touch), (old.target, v.target), (old.candidate, v.candidate)] {
            if a != b {
                for m in [a, b].into_iter().flatten() {
                    if let Some(slot) = dirty.get_mut(n) {
                        *slot = m.area(lay);
                        n += 1;
                    }
                }
            }
        }
        let count = n as u8;
        let Some(&box_) = dirty.get(..n).and_then(|b| b.get(i)) else { return (None, count) };
        // A box already repainted (same place) needs no second pass.
        if dirty.get(..i).is_some_and(|prev| prev.contains(&box_)) {
            return (None, count);
        }
        (Some(box_), count)
    }

    /// What a touch at screen pixel `(x, y)` means on the main screen as last
    /// drawn; `None` for guard bands, gaps and anything before the first draw
    /// (except STOP, which works from the start).
    #[cfg_attr(target_arch = "avr", optimize(size))] // reason: cold
    pub fn hit(&self, x: i16, y: i16) -> Option<Hit> {
        let view = match self.shown {
            Shown::Main(v) => Some(v),
            Shown::Calibration(_) => return None,
            Shown::Nothing => None,
        };
        let lay = &self.layout;
        // While a redraw is under way the button may be half STOP, half
        // RESUME: it is STOP unless both pictures say RESUME.
        let stop_coming = matches!(self.pass, Some(Pass { target: Shown::Main(t), .. }) if t.stop_shown);
        let resume_shown = view.is_some_and(|v| !v.stop_shown) && !stop_coming;
        if resume_shown {
            if lay.stop().contains(x, y) {
                return Some(Hit::Resume);
            }
        } else if lay.stop_hit().contains(x, y) {
            return Some(Hit::Stop);
        }
        let view = view?;
        if let Some((x_p, y_p)) = lay.ws_pixel_to_point(x, y) {
            return Some(Hit::Map { x_p, y_p });
        }
        // A page change being drawn: the glass is part old, part new page,
        // so no button below the map counts until it is done.
        // So is a lock change (a button hidden or shown).
        if matches!(self.pass, Some(Pass { target: Shown::Main(t), .. }) if t.page != view.page || t.hide != view.hide)
        {
            return None;
        }
        if lay.page_key().contains(x, y) {
            return Some(Hit::Page);
        }
        if let Some(k) = lay.carer_at(x, y) {
            return Some(Hit::Carer(k));
        }
        let i = (0..SLOTS - 1).find(|&i| lay.slot(i).contains(x, y))?;
        Some(page_button(view.page, i)).filter(|h| !hides(view.hide, h))
    }

    /// The switch scan's line as the glass shows it (the picture last
    /// finished), if it shows one.
    pub fn scan_shown(&self) -> Option<ScanShow> {
        let Shown::Main(v) = self.shown else { return None };
        match v.line {
            0 => None,
            x if x > 0 => Some(ScanShow::Column(x - 1)),
            y => Some(ScanShow::Row(-y - 1)),
        }
    }

    /// [`Ui::hit`] for a panel point (what the calibrated touch pipeline
    /// gives).
    pub fn hit_panel(&self, x_p: f32, y_p: f32) -> Option<Hit> {
        let (x, y) = self.layout.panel_to_pixel(x_p, y_p)?;
        self.hit(x, y)
    }

    /// Draws the calibration screen for `flow`'s current step, repainting
    /// only what changed since the last calibration draw.
    pub fn draw_calibration<D: Canvas>(&mut self, flow: &CalibrationFlow, d: &mut D) -> Result<Redrawn, D::Error> {
        self.draw_calibration_sliced(flow, d, &mut Unlimited).map(|r| r.redrawn)
    }

    /// [`Ui::draw_calibration`] within `budget` (see [`Ui::draw_sliced`]).
    pub fn draw_calibration_sliced<D: Canvas, B: DrawBudget>(
        &mut self,
        flow: &CalibrationFlow,
        d: &mut D,
        budget: &mut B,
    ) -> Result<Drawn, D::Error> {
        self.run(Shown::Calibration(calibration::view(flow)), d, budget)
    }
}

/// What button `i` (0..=3, left of the page key) of `page` does: the one
/// table the hit test, the drawing order and `GET /api/layout` follow.
pub const fn page_button(page: Page, i: u8) -> Hit {
    match (page, i) {
        (Page::Main, 0) => Hit::Speed(SpeedPreset::Slow),
        (Page::Main, 1) => Hit::Speed(SpeedPreset::Normal),
        (Page::Main, 2) => Hit::Speed(SpeedPreset::Fast),
        (Page::Main, _) => Hit::Undo,
        (Page::More, n) => Hit::Pose(if n > 3 { 4 } else { n + 1 }),
        (Page::Setup, 0) => Hit::Grip,
        (Page::Setup, 1) => Hit::Calibrate,
        (Page::Setup, 2) => Hit::Line,
        (Page::Setup, _) => Hit::Lift,
    }
}

/// The carer lock hides `hit` under the hidden [`item`] bits `hide`: the
/// Cal button with the calibration or the touch settings (its flow is the
/// touch's calibration), Line, Lift and Fast with their items. The one
/// table the hit test, the drawing and the app's own check follow.
pub fn hides(hide: u8, hit: &Hit) -> bool {
    let needs = match hit {
        Hit::Calibrate => item::CAL | item::TOUCH,
        Hit::Line => item::LINE,
        Hit::Lift => item::LIFT,
        Hit::Speed(SpeedPreset::Fast) => item::FAST,
        _ => 0,
    };
    hide & needs != 0
}

/// The highlight on STOP's place in [`View::item`].
const STOP_HL: u8 = STOP_ITEM + 1;

/// The row of buttons shows the same: page, lock and scan highlight.
fn same_row(a: &View, b: &View) -> bool {
    a.page == b.page && a.hide == b.hide && slot_highlight(a.item) == slot_highlight(b.item)
}

/// The guard bands and gaps (out of line: the six areas are not in the
/// frame of the steps that call deeper, the map's bands).
#[inline(never)] // avr-trap: frame-size
fn draw_gaps<D: Canvas>(d: &mut D, lay: &Layout) -> Result<(), D::Error> {
    for g in lay.gaps() {
        fill(d, g, theme::BG)?;
    }
    Ok(())
}

/// STOP, or RESUME with its countdown: a white band inside its edge, one
/// text-scale pixel thick per step of `ring` (0..=4), so it closes in on the
/// label as the hold fills (issue #19 §3). `was` is the ring on the glass
/// (`None`: the button is not drawn as RESUME yet): a ring that grew adds
/// its new band only, one that fell back (a new contact) repaints.
fn draw_stop<D: Canvas>(d: &mut D, lay: &Layout, stop: bool, ring: u8, was: Option<u8>) -> Result<(), D::Error> {
    let t = lay.text_scale();
    let a = lay.stop().shrink(1);
    if stop {
        return button(d, lay.stop(), t!("STOP"), &TextStyle::opaque(t + 1, theme::WHITE, theme::STOP_RED).tight());
    }
    let from = match was {
        Some(w) if w <= ring => w,
        _ => {
            button(d, lay.stop(), t!("RESUME"), &TextStyle::opaque(t, theme::WHITE, theme::RESUME_GREEN).tight())?;
            0
        }
    };
    let band = u16::from(t);
    for k in from..ring {
        frame(d, a.shrink(band * u16::from(k)), band, theme::WHITE)?;
    }
    Ok(())
}

fn draw_headline<D: Canvas>(d: &mut D, lay: &Layout, h: Headline) -> Result<(), D::Error> {
    text_box(d, lay.headline(), &h.text(), &head_style(lay, h.color()))
}

fn draw_detail<D: Canvas>(d: &mut D, lay: &Layout, detail: &Detail) -> Result<(), D::Error> {
    let a = lay.detail();
    match *detail {
        Detail::Hint(s) => text_box(d, a, &s, &head_style(lay, theme::TEXT)),
        Detail::Progress { px, percent } => {
            let (bar, bar_text) = (lay.bar(), lay.bar_text());
            let left = Area::new(a.x, a.y, (bar_text.x - a.x) as u16, a.h);
            let right = Area::new(bar_text.x, a.y, (a.right() - bar_text.x) as u16, a.h);
            fill_around(d, left, bar, theme::BG)?;
            fill_around(d, right, bar_text, theme::BG)?;
            frame(d, bar, 1, theme::FRAME)?;
            let f = lay.bar_fill();
            fill(d, Area::new(f.x, f.y, px, f.h), theme::PROGRESS)?;
            fill(d, Area::new(f.x + px as i16, f.y, f.w - px, f.h), theme::PROGRESS_BG)?;
            draw_percent(d, lay, percent)
        }
    }
}

/// Repaints only the bar columns between the old and the new fill.
fn update_progress<D: Canvas>(d: &mut D, lay: &Layout, old_px: u16, new_px: u16) -> Result<(), D::Error> {
    let f = lay.bar_fill();
    let (lo, hi, c) =
        if new_px >= old_px { (old_px, new_px, theme::PROGRESS) } else { (new_px, old_px, theme::PROGRESS_BG) };
    fill(d, Area::new(f.x + lo as i16, f.y, hi - lo, f.h), c)
}

fn draw_percent<D: Canvas>(d: &mut D, lay: &Layout, percent: u8) -> Result<(), D::Error> {
    let mut line: Line<26> = Line::new();
    line.i32(i32::from(percent)).bytes(b"%");
    // Right-aligned in a 4-character field so the digits do not jump.
    let mut padded: Line<26> = Line::new();
    for _ in line.as_bytes().len()..4 {
        padded.bytes(b" ");
    }
    padded.bytes(line.as_bytes());
    text_box(d, lay.bar_text(), padded.as_bytes(), &head_style(lay, theme::TEXT))
}

fn draw_info<D: Canvas>(d: &mut D, lay: &Layout, zone: Option<(u8, Option<i16>)>) -> Result<(), D::Error> {
    let mut line: Line<26> = Line::new();
    if let Some((z, alpha)) = zone {
        line.str(t!("Zone ")).i32(i32::from(z)).str(t!("  Direction ")).deg(alpha);
    }
    text_box(d, lay.info(), line.as_bytes(), &SMALL_STYLE)
}

fn draw_warning<D: Canvas>(d: &mut D, lay: &Layout, bit: u8) -> Result<(), D::Error> {
    text_box(d, lay.warn(), &warning_text(bit), &TextStyle::opaque(1, theme::WARN_TEXT, theme::BG))
}

fn draw_joints<D: Canvas>(d: &mut D, lay: &Layout, joints: &[Option<i16>; 3]) -> Result<(), D::Error> {
    let mut line: Line<52> = Line::new();
    line.str(t!("Base ")).deg(joints[0]);
    line.str(t!("   Shoulder ")).deg(joints[1]);
    line.str(t!("   Elbow ")).deg(joints[2]);
    text_box(d, lay.joints(), line.as_bytes(), &SMALL_STYLE)
}

/// The page's buttons other than the speed presets, the toggles and the
/// page key: Undo (Main), poses 1–4 (More; *Save*, highlighted, for the one
/// whose carer save waits for its confirmation), or Grip, labelled with what
/// a press does, and Cal (Setup; Cal only when `all`: its label never
/// changes; blank while the lock hides it).
fn draw_row2<D: Canvas>(d: &mut D, lay: &Layout, v: &View, all: bool) -> Result<(), D::Error> {
    let style = label_style(lay, theme::TEXT, theme::BUTTON);
    match v.page {
        Page::Main => button(d, lay.undo(), t!("Undo"), &style),
        Page::More => {
            let labels = [t!("1"), t!("2"), t!("3"), t!("4")];
            let on = label_style(lay, theme::WHITE, theme::BUTTON_ON);
            for (n, label) in (0u8..).zip(labels) {
                let (label, style) = if v.confirm == n + 1 { (t!("Save"), &on) } else { (label, &style) };
                button(d, lay.pose(n), label, style)?;
            }
            Ok(())
        }
        Page::Setup => {
            if all && hides(v.hide, &Hit::Calibrate) {
                fill(d, lay.calibrate(), theme::BG)?;
            } else if all {
                button(d, lay.calibrate(), t!("Cal"), &style)?;
            }
            let grip = if v.more & GRIP_CLOSED != 0 { t!("Open") } else { t!("Grab") };
            button(d, lay.grip(), grip, &label_style(lay, theme::WHITE, theme::BUTTON_ON))
        }
    }
}

/// A toggle of the More page: highlighted while on, as the speed buttons
/// show the preset; blank while the lock hides it.
fn draw_toggle<D: Canvas>(
    d: &mut D,
    a: Area,
    label: Text,
    on: bool,
    hidden: bool,
    lay: &Layout,
) -> Result<(), D::Error> {
    if hidden {
        return fill(d, a, theme::BG);
    }
    let style = if on {
        label_style(lay, theme::WHITE, theme::BUTTON_ON)
    } else {
        label_style(lay, theme::TEXT, theme::BUTTON)
    };
    button(d, a, label, &style)
}

/// The presets (Fast blank while the lock hides it).
fn draw_speed<D: Canvas>(d: &mut D, lay: &Layout, speed: SpeedPreset, hide: u8) -> Result<(), D::Error> {
    let items: [(Area, SpeedPreset, Text); 3] = [
        (lay.slow(), SpeedPreset::Slow, t!("Slow")),
        (lay.normal(), SpeedPreset::Normal, t!("Mid")),
        (lay.fast(), SpeedPreset::Fast, t!("Fast")),
    ];
    for (a, p, label) in items {
        if hides(hide, &Hit::Speed(p)) {
            fill(d, a, theme::BG)?;
            continue;
        }
        let style = if p == speed {
            label_style(lay, theme::WHITE, theme::BUTTON_ON)
        } else {
            label_style(lay, theme::TEXT, theme::BUTTON)
        };
        button(d, a, label, &style)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::top_warning;

    #[test]
    fn top_warning_is_the_highest_set_bit() {
        assert_eq!(top_warning(0), 0);
        for bits in 1..=u8::MAX {
            assert_eq!(top_warning(bits), 1 << (7 - bits.leading_zeros()), "{bits:#04x}");
        }
    }
}
