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
use super::flash::TextSource;
use super::layout::Layout;
use super::model::{warn, Refusal, UiModel, UiState};
use super::theme;
use super::ws_view::{self, Mark, MarkKind, Reach};
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
    /// The three speed preset buttons.
    pub const SPEED: u16 = 1 << 8;
    /// The Calib button.
    pub const CALIBRATE: u16 = 1 << 9;
    /// Guard bands and gaps (full redraws only).
    pub const GAPS: u16 = 1 << 10;
    /// The calibration screen (all of it, or the parts that changed).
    pub const CALIBRATION: u16 = 1 << 11;
    /// A full redraw of the main screen (the map repaint covers the markers).
    pub const ALL_MAIN: u16 = (1 << 11) - 1 - Self::MARKERS;

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
    /// The Calib button.
    Calibrate,
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
    Moving,
    Holding,
    Stopped,
    OutOfReach,
    OffMap,
    JointLimit,
    Busy,
}

impl Headline {
    fn text(self) -> Text {
        match self {
            Headline::Starting => t!("Starting up"),
            Headline::Ready => t!("Ready"),
            Headline::Moving => t!("Moving to target"),
            Headline::Holding => t!("Holding"),
            Headline::Stopped => t!("Stopped - tap RESUME"),
            Headline::OutOfReach => t!("Out of reach"),
            Headline::OffMap => t!("Not on the map"),
            Headline::JointLimit => t!("Can't reach that way"),
            Headline::Busy => t!("Still moving"),
        }
    }

    fn color(self) -> Rgb565 {
        match self {
            Headline::Stopped | Headline::OutOfReach | Headline::OffMap | Headline::JointLimit => theme::REFUSED,
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
    headline: Headline,
    detail: Detail,
    zone: Option<(u8, Option<i16>)>,
    warning: u8,
    joints: [Option<i16>; 3],
    touch: Option<Mark>,
    target: Option<Mark>,
    speed: SpeedPreset,
}

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
        0
    } else {
        1 << (7 - bits.leading_zeros() as u8)
    }
}

fn warning_text(bit: u8) -> Text {
    match bit {
        warn::DEFAULT_SETTINGS => t!("! default settings in use"),
        warn::SERVOS_OFF => t!("! servos are off"),
        0 => t!(""),
        _ => t!("! check the serial log"),
    }
}

impl View {
    fn of(m: &UiModel, lay: &Layout) -> Self {
        let (headline, detail) = match m.state {
            UiState::PowerUp => (Headline::Starting, Detail::Hint(t!("Please wait"))),
            UiState::Idle => (Headline::Ready, Detail::Hint(t!("Touch the map to move"))),
            UiState::Moving { progress } => {
                let (px, percent) = progress_of(progress, lay.bar_fill().w);
                (Headline::Moving, Detail::Progress { px, percent })
            }
            UiState::Holding => (Headline::Holding, Detail::Hint(t!("Touch the map to move"))),
            UiState::Stopped => (Headline::Stopped, Detail::Hint(t!("The arm holds still"))),
            UiState::Refused(r) => match r {
                Refusal::TooFar => (Headline::OutOfReach, Detail::Hint(t!("Try closer to the base"))),
                Refusal::TooClose => (Headline::OutOfReach, Detail::Hint(t!("Try further from base"))),
                Refusal::OffMap => (Headline::OffMap, Detail::Hint(t!("Touch inside the map"))),
                Refusal::JointLimit => (Headline::JointLimit, Detail::Hint(t!("Try another point"))),
                Refusal::Busy => (Headline::Busy, Detail::Hint(t!("Wait, or tap STOP"))),
            },
        };
        let refused = matches!(m.state, UiState::Refused(_));
        let mark = |p: Option<(f32, f32)>, kind: MarkKind| {
            p.and_then(|(x, y)| lay.ws_point_to_pixel(x, y)).map(|(x, y)| Mark { x, y, kind })
        };
        View {
            stop_shown: m.state != UiState::Stopped,
            headline,
            detail,
            zone: m.condition.map(|c| (c.number(), whole_deg(m.alpha))),
            warning: top_warning(m.warnings),
            joints: [whole_deg(m.joints[0]), whole_deg(m.joints[1]), whole_deg(m.joints[2])],
            touch: mark(m.touch, if refused { MarkKind::TouchRefused } else { MarkKind::Touch }),
            target: mark(m.target, MarkKind::Target),
            speed: m.speed,
        }
    }

    /// Markers in drawing order (the touch on top).
    fn marks(&self) -> ([Mark; 2], usize) {
        let mut out = [Mark { x: 0, y: 0, kind: MarkKind::Touch }; 2];
        let mut n = 0;
        for m in [self.target, self.touch].into_iter().flatten() {
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

/// The renderer. Holds its layout and only what it last drew (a few dozen
/// bytes).
pub struct Ui {
    layout: Layout,
    reach: Reach,
    shown: Shown,
}

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
fn text_box<D: Canvas, T: TextSource + ?Sized>(d: &mut D, a: Area, s: &T, style: &TextStyle) -> Result<(), D::Error> {
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
        Self { layout, reach, shown: Shown::Nothing }
    }

    /// Where everything sits.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// Changes the reach shading; the next [`Ui::draw`] repaints the map.
    pub fn set_reach(&mut self, config: &UiConfig) {
        self.reach = Reach::new(config.reach_min, config.reach_max, self.layout.scale());
        if let Shown::Main(_) = self.shown {
            self.shown = Shown::Nothing;
        }
    }

    /// Forgets what is on the glass (after a display reset): the next draw is
    /// full.
    pub fn invalidate(&mut self) {
        self.shown = Shown::Nothing;
    }

    /// Draws the main screen, repainting only what differs from the last
    /// draw (everything after a calibration screen, a reach change or an
    /// error).
    pub fn draw<D: Canvas>(&mut self, model: &UiModel, d: &mut D) -> Result<Redrawn, D::Error> {
        let v = View::of(model, &self.layout);
        let old = match self.shown {
            Shown::Main(old) => old,
            _ => return self.draw_view_full(&v, d),
        };
        // Until this draw completes, the glass is unknown.
        self.shown = Shown::Nothing;
        let r = self.draw_changes(&old, &v, d)?;
        self.shown = Shown::Main(v);
        Ok(r)
    }

    /// Draws the whole main screen.
    pub fn draw_full<D: Canvas>(&mut self, model: &UiModel, d: &mut D) -> Result<Redrawn, D::Error> {
        self.draw_view_full(&View::of(model, &self.layout), d)
    }

    fn draw_view_full<D: Canvas>(&mut self, v: &View, d: &mut D) -> Result<Redrawn, D::Error> {
        self.shown = Shown::Nothing;
        let lay = &self.layout;
        let (marks, n) = v.marks();
        ws_view::draw_map(d, lay, &self.reach, marks.get(..n).unwrap_or(&[]))?;
        for g in lay.gaps() {
            fill(d, g, theme::BG)?;
        }
        draw_stop(d, lay, v.stop_shown)?;
        draw_headline(d, lay, v.headline)?;
        draw_detail(d, lay, &v.detail)?;
        draw_info(d, lay, v.zone)?;
        draw_warning(d, lay, v.warning)?;
        draw_joints(d, lay, &v.joints)?;
        draw_speed(d, lay, v.speed)?;
        button(d, lay.calibrate(), t!("Calib"), &label_style(lay, theme::TEXT, theme::BUTTON))?;
        self.shown = Shown::Main(*v);
        Ok(Redrawn(Redrawn::ALL_MAIN))
    }

    fn draw_changes<D: Canvas>(&self, old: &View, v: &View, d: &mut D) -> Result<Redrawn, D::Error> {
        let lay = &self.layout;
        let mut r = 0u16;
        if old.stop_shown != v.stop_shown {
            draw_stop(d, lay, v.stop_shown)?;
            r |= Redrawn::STOP;
        }
        if old.headline != v.headline {
            draw_headline(d, lay, v.headline)?;
            r |= Redrawn::HEADLINE;
        }
        if old.detail != v.detail {
            match (old.detail, v.detail) {
                (Detail::Progress { px: a, percent: pa }, Detail::Progress { px: b, percent: pb }) => {
                    update_progress(d, lay, a, b)?;
                    if pa != pb {
                        draw_percent(d, lay, pb)?;
                    }
                }
                _ => draw_detail(d, lay, &v.detail)?,
            }
            r |= Redrawn::DETAIL;
        }
        if old.zone != v.zone {
            draw_info(d, lay, v.zone)?;
            r |= Redrawn::INFO;
        }
        if old.warning != v.warning {
            draw_warning(d, lay, v.warning)?;
            r |= Redrawn::WARN;
        }
        if old.joints != v.joints {
            draw_joints(d, lay, &v.joints)?;
            r |= Redrawn::JOINTS;
        }
        if old.speed != v.speed {
            draw_speed(d, lay, v.speed)?;
            r |= Redrawn::SPEED;
        }
        if old.touch != v.touch || old.target != v.target {
            let mut dirty = [Area::new(0, 0, 0, 0); 4];
            let mut n = 0;
            for (a, b) in [(old.touch, v.touch), (old.target, v.target)] {
                if a != b {
                    for m in [a, b].into_iter().flatten() {
                        if let Some(slot) = dirty.get_mut(n) {
                            *slot = m.area(lay);
                            n += 1;
                        }
                    }
                }
            }
            let (marks, k) = v.marks();
            let marks = marks.get(..k).unwrap_or(&[]);
            for (i, box_) in dirty.iter().enumerate().take(n) {
                // A box already repainted (same place) needs no second pass.
                if dirty.get(..i).is_some_and(|prev| prev.contains(box_)) {
                    continue;
                }
                ws_view::repaint(d, lay, &self.reach, *box_, marks)?;
            }
            r |= Redrawn::MARKERS;
        }
        Ok(Redrawn(r))
    }

    /// What a touch at screen pixel `(x, y)` means on the main screen as last
    /// drawn; `None` for guard bands, gaps and anything before the first draw
    /// (except STOP, which works from the start).
    pub fn hit(&self, x: i16, y: i16) -> Option<Hit> {
        let view = match self.shown {
            Shown::Main(v) => Some(v),
            Shown::Calibration(_) => return None,
            Shown::Nothing => None,
        };
        let lay = &self.layout;
        let resume_shown = view.is_some_and(|v| !v.stop_shown);
        if resume_shown {
            if lay.stop().contains(x, y) {
                return Some(Hit::Resume);
            }
        } else if lay.stop_hit().contains(x, y) {
            return Some(Hit::Stop);
        }
        view?;
        if let Some((x_p, y_p)) = lay.ws_pixel_to_point(x, y) {
            return Some(Hit::Map { x_p, y_p });
        }
        let buttons = [
            (lay.slow(), Hit::Speed(SpeedPreset::Slow)),
            (lay.normal(), Hit::Speed(SpeedPreset::Normal)),
            (lay.fast(), Hit::Speed(SpeedPreset::Fast)),
            (lay.calibrate(), Hit::Calibrate),
        ];
        buttons.iter().find(|(a, _)| a.contains(x, y)).map(|&(_, h)| h)
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
        let old = match self.shown {
            Shown::Calibration(v) => Some(v),
            _ => None,
        };
        self.shown = Shown::Nothing;
        let v = calibration::draw(flow, old, d)?;
        self.shown = Shown::Calibration(v);
        Ok(Redrawn(Redrawn::CALIBRATION))
    }
}

fn draw_stop<D: Canvas>(d: &mut D, lay: &Layout, stop: bool) -> Result<(), D::Error> {
    let t = lay.text_scale();
    if stop {
        button(d, lay.stop(), t!("STOP"), &TextStyle::opaque(t + 1, theme::WHITE, theme::STOP_RED).tight())
    } else {
        button(d, lay.stop(), t!("RESUME"), &TextStyle::opaque(t, theme::WHITE, theme::RESUME_GREEN).tight())
    }
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
    let mut line: Line<5> = Line::new();
    line.i32(i32::from(percent)).bytes(b"%");
    // Right-aligned in a 4-character field so the digits do not jump.
    let mut padded: Line<5> = Line::new();
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

fn draw_speed<D: Canvas>(d: &mut D, lay: &Layout, speed: SpeedPreset) -> Result<(), D::Error> {
    let items: [(Area, SpeedPreset, Text); 3] = [
        (lay.slow(), SpeedPreset::Slow, t!("Slow")),
        (lay.normal(), SpeedPreset::Normal, t!("Normal")),
        (lay.fast(), SpeedPreset::Fast, t!("Fast")),
    ];
    for (a, p, label) in items {
        let style = if p == speed {
            label_style(lay, theme::WHITE, theme::BUTTON_ON)
        } else {
            label_style(lay, theme::TEXT, theme::BUTTON)
        };
        button(d, a, label, &style)?;
    }
    Ok(())
}
