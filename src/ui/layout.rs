//! Where everything sits on the landscape screen, for both panel sizes the
//! firmware drives (320×240: ILI9341, ST7789V, ILI9325; 480×320: ILI9486,
//! ST7796S),
//! and the two coordinate mappings.
//!
//! One description: every region is placed by the same arithmetic from a
//! handful of numbers ([`Layout`]: screen size, map scale `s`, text scale,
//! row heights and the gap between buttons); the buttons take what the
//! status lines leave. [`Layout::QVGA`] gives the 320×240 screen below;
//! [`Layout::HVGA`] the same arrangement on 480×320, with the map at 160 px
//! per unit (same 2:1 proportions), a 152×160 STOP, 83×80 buttons and text
//! one scale larger. The sizes in millimetres, and why: docs/targets.md.
//!
//! ```text
//!  0                              224 232                 320     (QVGA; 2s = 224)
//!  +--------------------------------+--+-----------------+ 0
//!  | workspace map 2s×s (224×112)    |g |   STOP/RESUME   |
//!  | (x_p, y_p) ∈ [−1,1]×[0,1]        |  |     88×112      |
//!  +--------------------------------+  +-----------------+ s = 112
//!  guard band (touches ignored; next to STOP they count as STOP)   120
//!  headline  (2×)                                          140
//!  detail: hint (2×) or progress bar                       160
//!  zone + direction (1×) | warning                         174
//!  joints (1×)                                             188
//!  +------+   +------+   +------+   +------+   +------+
//!  | slot0|15 | slot1|   | slot2|   | slot3|   | key  |   (5 × 52×52, 15 px apart)
//!  +------+   +------+   +------+   +------+   +------+    240
//!  Main:  Slow  Mid   Fast  Undo  More
//!  More:  1     2     3     4     More
//!  Setup: Grab  Cal   Line  Lift  Back
//! ```
//!
//! **Pages.** One row of five buttons fits under the status lines at the
//! sizes a user with limited hand use can hit (docs/targets.md:
//! 9 mm on the 2.8" panel, 12 mm on the 3.5", and a σ = 2 mm scatter that
//! stays on its button), so the buttons are on three pages, each with the
//! page key in the last slot: *More* turns Main into More (the four saved
//! poses) and More into Setup (Grab/Open, Cal, the toggles *Line*
//! (`path line` ↔ `path joint`) and *Lift* (`lift 0.20` ↔ `lift off`),
//! each highlighted while on), whose *Back* returns to Main. STOP, the
//! headline (which says what the arm does and why a press was refused) and
//! the status lines are on every page. The page changes only when the user
//! presses the page key: not after an action and never on a timer, since a
//! page that turned by itself could put a different button under a finger
//! already on its way (a pose, which moves the arm, where a speed button
//! was). While a page change is being drawn, only STOP answers.
//! The user's pages cannot save a pose (one mis-aimed press would
//! overwrite a carer's preset); in carer mode a pose button held 2 s and
//! confirmed by a tap saves one (`app::access`). While the carer lock is
//! on, the buttons it hides are blank and do nothing; the carer's gesture
//! places ([`Layout::carer_corner`]) are at both ends of the headline and
//! detail rows.
//!
//! **Panel coordinates** are what the touch pipeline produces from a raw
//! reading with the calibration (method.md §3): `(x_p, y_p)` over the *whole* glass,
//! `x_p = −1` at the left edge, `+1` at the right, `y_p = 0` at the bottom,
//! `1` at the top. [`Layout::panel_to_pixel`] turns them into a screen pixel
//! and [`Layout::pixel_center_to_panel`] back; the calibration crosshairs are
//! placed with this mapping.
//!
//! **Workspace coordinates** are the paper's `(x_p, y_p) ∈ [−1, 1] × [0, 1]`
//! that the arm math takes. They live in the 2s×s map at the top left, `s`
//! pixels per unit on both axes, so the reach circle is drawn round: pixel
//! column `i` covers `x_p ∈ [(i − s)/s, (i − s + 1)/s)` and row `j` covers
//! `y_p ∈ [(s − 1 − j)/s, (s − j)/s)` (the map's right and top edges fold onto
//! the last column and row); a touch on pixel `(i, j)` means its centre,
//! `x_p = (2i + 1 − 2s)/2s`, `y_p = (2s − 1 − 2j)/2s`. The base of the arm is
//! the middle of the map's bottom edge.
//!
//! Why a sub-rectangle and not the paper's whole-panel map with buttons on
//! top: for a user with limited hand use, a touch meant for STOP that lands a
//! little off must never send the arm somewhere. So no arm target shares an
//! edge with a button: an 8-pixel guard band separates the map from
//! everything else, touches in it do nothing — except beside STOP, where they
//! count as STOP (the safe reading of an ambiguous touch). RESUME, which
//! starts motion, is hit only inside its own drawn box.

use super::draw::Area;

/// The guard band between the map and everything else, pixels (both
/// sizes).
pub const GUARD: u16 = 8;

/// Buttons in the bottom row of every page (the page key is the last).
pub const SLOTS: u8 = 5;

/// The screen's arrangement for one panel size (every region is computed
/// from these numbers by the methods below).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layout {
    w: u16,
    h: u16,
    s: u16,
    text: u8,
    row: u16,
    small_row: u16,
    gap: u16,
    turned: bool,
}

impl Layout {
    /// 320×240 (ILI9341, ST7789V, ILI9325 in landscape): map 224×112, STOP
    /// 88×112, buttons 52×52 15 px apart.
    pub const QVGA: Layout = Layout { w: 320, h: 240, s: 112, text: 2, row: 20, small_row: 14, gap: 15, turned: false };
    /// 480×320 (ILI9486, ST7796S in landscape): map 320×160, STOP 152×160,
    /// buttons 83×80 16 px apart, headline and buttons in 3× text.
    pub const HVGA: Layout = Layout { w: 480, h: 320, s: 160, text: 3, row: 24, small_row: 12, gap: 16, turned: false };

    /// The layout for a `w`×`h` landscape screen, if there is one.
    pub const fn for_size(w: u16, h: u16) -> Option<Layout> {
        match (w, h) {
            (320, 240) => Some(Layout::QVGA),
            (480, 320) => Some(Layout::HVGA),
            _ => None,
        }
    }

    /// This layout on a screen turned by 180° (`cal set lcd rotate 180`:
    /// the controller draws pixel `(x, y)` where the glass's
    /// `(w − 1 − x, h − 1 − y)` is), so the panel mappings turn with it: a
    /// touch on a drawn button still hits that button, and the touch
    /// calibration stays the glass's.
    pub const fn turned(self, on: bool) -> Layout {
        Layout { turned: on, ..self }
    }

    /// The carer's gesture places (`app::access`): `i` = 0 the left end of
    /// the headline and the detail line, 1 their right end, each a button
    /// wide: places where the user's pages have nothing to press, below the
    /// guard band and two status lines above the buttons.
    pub const fn carer_corner(&self, i: u8) -> Area {
        let top = self.headline().y;
        let h = (self.detail().bottom() - top) as u16;
        let w = self.button_h();
        let x = if i == 0 { 0 } else { (self.w - w) as i16 };
        Area::new(x, top, w, h)
    }

    /// Which carer place `(x, y)` is in ([`Layout::carer_corner`]): one
    /// test of the rows and one of the columns.
    pub const fn carer_at(&self, x: i16, y: i16) -> Option<u8> {
        let a = self.carer_corner(0);
        if y < a.y || y >= a.bottom() || x < 0 || x >= self.w as i16 {
            None
        } else if x < a.right() {
            Some(0)
        } else if x >= (self.w - a.w) as i16 {
            Some(1)
        } else {
            None
        }
    }

    /// Screen width, pixels.
    pub const fn width(&self) -> u16 {
        self.w
    }

    /// Screen height, pixels.
    pub const fn height(&self) -> u16 {
        self.h
    }

    /// The whole screen.
    pub const fn screen(&self) -> Area {
        Area::new(0, 0, self.w, self.h)
    }

    /// Pixels per workspace unit on the map (the map is 2 × 1 units).
    pub const fn scale(&self) -> u16 {
        self.s
    }

    /// Text scale of the headline, the hint, the percentage and the button
    /// labels; STOP and the zone numbers are one larger, the status lines 1×.
    pub const fn text_scale(&self) -> u8 {
        self.text
    }

    /// The workspace map at the top left, 2s × s.
    pub const fn ws(&self) -> Area {
        Area::new(0, 0, 2 * self.s, self.s)
    }

    /// Column of the arm base, the workspace's x = 0 (a pixel edge).
    pub const fn ws_origin_x(&self) -> i16 {
        self.s as i16
    }

    /// Left edge of STOP's column (right of the map and its guard band).
    const fn right_x(&self) -> i16 {
        (2 * self.s + GUARD) as i16
    }

    /// Width of STOP's column.
    const fn right_w(&self) -> u16 {
        self.w - 2 * self.s - GUARD
    }

    /// The STOP (or RESUME) button, right of the map.
    pub const fn stop(&self) -> Area {
        Area::new(self.right_x(), 0, self.right_w(), self.s)
    }

    /// Where a touch counts as STOP while STOP is shown: its box plus the
    /// guard band beside and below it.
    pub const fn stop_hit(&self) -> Area {
        Area::new((2 * self.s) as i16, 0, self.w - 2 * self.s, self.s + GUARD)
    }

    /// What the arm is doing, in words, at the text scale.
    pub const fn headline(&self) -> Area {
        Area::new(0, (self.s + GUARD) as i16, self.w, self.row)
    }

    /// The second line: a hint in words, or the progress bar while moving.
    pub const fn detail(&self) -> Area {
        Area::new(0, self.headline().bottom(), self.w, self.row)
    }

    /// Zone and direction α of the touched point (left half).
    pub const fn info(&self) -> Area {
        Area::new(0, self.detail().bottom(), self.w / 2, self.small_row)
    }

    /// The most important warning (right half).
    pub const fn warn(&self) -> Area {
        Area::new((self.w / 2) as i16, self.detail().bottom(), self.w - self.w / 2, self.small_row)
    }

    /// The three joint angles, whole degrees.
    pub const fn joints(&self) -> Area {
        Area::new(0, self.info().bottom(), self.w, self.small_row)
    }

    /// Progress bar inside DETAIL, under the map's columns: a 1-pixel frame
    /// around the fill.
    pub const fn bar(&self) -> Area {
        Area::new(4, self.detail().y + 3, 2 * self.s - 8, self.row - 6)
    }

    /// The bar's fill: filled from the left by the move's progress.
    pub const fn bar_fill(&self) -> Area {
        let b = self.bar();
        Area::new(b.x + 1, b.y + 1, b.w - 2, b.h - 2)
    }

    /// The percentage next to the bar, in STOP's column: four characters
    /// after a 4-px pad, as tall as the text, centred in the detail line.
    pub const fn bar_text(&self) -> Area {
        let h = 8 * self.text as u16;
        let w = 4 + 4 * 6 * self.text as u16;
        Area::new(self.right_x() - 4, self.detail().y + ((self.row - h) / 2) as i16, w, h)
    }

    /// Top of the button row: under the status lines.
    const fn buttons_y(&self) -> i16 {
        self.joints().bottom()
    }

    /// Height of a button: what the status lines leave.
    pub const fn button_h(&self) -> u16 {
        self.h - self.buttons_y() as u16
    }

    /// Width of a button: five in the screen's width, `gap` apart (the last
    /// takes the rounding).
    const fn slot_w(&self) -> u16 {
        (self.w - (SLOTS as u16 - 1) * self.gap) / SLOTS as u16
    }

    /// Bottom-row button `i` (0..=4, left to right; larger is clamped to
    /// the last): what it does depends on the page ([`crate::ui::Ui::hit`]).
    pub const fn slot(&self, i: u8) -> Area {
        let i = if i >= SLOTS { SLOTS - 1 } else { i } as u16;
        let x = i * (self.slot_w() + self.gap);
        let w = if i == SLOTS as u16 - 1 { self.w - x } else { self.slot_w() };
        Area::new(x as i16, self.buttons_y(), w, self.button_h())
    }

    /// Speed preset button Slow (main page).
    pub const fn slow(&self) -> Area {
        self.slot(0)
    }

    /// Speed preset button Normal (main page, labelled Mid).
    pub const fn normal(&self) -> Area {
        self.slot(1)
    }

    /// Speed preset button Fast (main page).
    pub const fn fast(&self) -> Area {
        self.slot(2)
    }

    /// Undo (main page): back to the pose before the last move.
    pub const fn undo(&self) -> Area {
        self.slot(3)
    }

    /// The page key, the last slot: More on Main and More, Back on Setup.
    pub const fn page_key(&self) -> Area {
        self.slot(SLOTS - 1)
    }

    /// Pose button `n` (0..=3 for poses 1–4; larger is clamped to the last)
    /// on the More page.
    pub const fn pose(&self, n: u8) -> Area {
        self.slot(if n > 3 { 3 } else { n })
    }

    /// The Grip button (Setup page): Grab, or Open while closed.
    pub const fn grip(&self) -> Area {
        self.slot(0)
    }

    /// Opens the touch calibration (Setup page).
    pub const fn calibrate(&self) -> Area {
        self.slot(1)
    }

    /// The Line toggle (Setup page): `path line` when highlighted, `path
    /// joint` otherwise.
    pub const fn line_toggle(&self) -> Area {
        self.slot(2)
    }

    /// The Lift toggle (Setup page): a lift set when highlighted, `lift
    /// off` otherwise.
    pub const fn lift_toggle(&self) -> Area {
        self.slot(3)
    }

    /// Pixels no region paints, the same on every page: the guard bands
    /// right of and below the map, and the gaps between the buttons (a
    /// full redraw fills them with the background).
    pub const fn gaps(&self) -> [Area; 6] {
        [
            Area::new((2 * self.s) as i16, 0, GUARD, self.s),
            Area::new(0, self.s as i16, self.w, GUARD),
            self.slot_gap(0),
            self.slot_gap(1),
            self.slot_gap(2),
            self.slot_gap(3),
        ]
    }

    /// The gap right of button `i`.
    const fn slot_gap(&self, i: u16) -> Area {
        let x = i * (self.slot_w() + self.gap) + self.slot_w();
        Area::new(x as i16, self.buttons_y(), self.gap, self.button_h())
    }

    /// `v` (a length or position on the 320-wide reference screen) scaled to
    /// this width: the calibration screen's positions.
    #[inline(never)] // reason: code-size
    pub const fn sx(&self, v: i16) -> i16 {
        (v as i32 * self.w as i32 / 320) as i16
    }

    /// `v` (on the 240-high reference screen) scaled to this height.
    #[inline(never)] // reason: code-size
    pub const fn sy(&self, v: i16) -> i16 {
        (v as i32 * self.h as i32 / 240) as i16
    }

    /// `v` (a size on the 112-px-per-unit map of 320×240) scaled to this
    /// map: markers, the arm base, the crosshairs.
    #[inline(never)] // reason: code-size
    pub const fn sm(&self, v: u16) -> u16 {
        (v as u32 * self.s as u32 / 112) as u16
    }

    /// A panel point to the pixel it falls on, `None` outside `[−1,1]×[0,1]`
    /// or not finite. `x = ⌊(x_p + 1)·w/2⌋`, `y = ⌊(1 − y_p)·h⌋`, the far
    /// edges folded onto the last pixel (then the opposite pixel when
    /// [`Layout::turned`]).
    pub fn panel_to_pixel(&self, x_p: f32, y_p: f32) -> Option<(i16, i16)> {
        let inside = (-1.0..=1.0).contains(&x_p) && (0.0..=1.0).contains(&y_p);
        if !inside {
            return None;
        }
        let x = ((x_p + 1.0) * (self.w / 2) as f32) as i16;
        let y = ((1.0 - y_p) * self.h as f32) as i16;
        Some(self.turn(x.min(self.w as i16 - 1), y.min(self.h as i16 - 1)))
    }

    /// The panel coordinates of a pixel's centre (inverse of
    /// [`Layout::panel_to_pixel`]).
    pub fn pixel_center_to_panel(&self, x: i16, y: i16) -> (f32, f32) {
        let (x, y) = self.turn(x, y);
        let x_p = (2.0 * f32::from(x) + 1.0) / self.w as f32 - 1.0;
        let y_p = 1.0 - (2.0 * f32::from(y) + 1.0) / (2.0 * self.h as f32);
        (x_p, y_p)
    }

    /// The glass's pixel under screen pixel `(x, y)` (the opposite one
    /// when [`Layout::turned`]).
    pub const fn glass_pixel(&self, x: i16, y: i16) -> (i16, i16) {
        self.turn(x, y)
    }

    /// Between the glass's pixel and the screen's (its own inverse): the
    /// same pixel unless [`Layout::turned`], else the opposite one.
    const fn turn(&self, x: i16, y: i16) -> (i16, i16) {
        if self.turned {
            (self.w as i16 - 1 - x, self.h as i16 - 1 - y)
        } else {
            (x, y)
        }
    }

    /// Workspace point of a map pixel's centre; `None` outside the map.
    pub fn ws_pixel_to_point(&self, x: i16, y: i16) -> Option<(f32, f32)> {
        if !self.ws().contains(x, y) {
            return None;
        }
        let (dx, dy) = self.ws_half_units(x, y);
        let two_scale = (2 * self.s) as f32;
        Some((f32::from(dx) / two_scale, f32::from(dy) / two_scale))
    }

    /// Pixel centre relative to the arm base in half-pixel units (both odd):
    /// `x_p = dx/2s`, `y_p = dy/2s` exactly.
    pub const fn ws_half_units(&self, x: i16, y: i16) -> (i16, i16) {
        let ws = self.ws();
        let dx = 2 * (x - ws.x) + 1 - 2 * (self.ws_origin_x() - ws.x);
        let dy = 2 * (ws.bottom() - y) - 1;
        (dx, dy)
    }

    /// The map pixel a workspace point falls on, `None` outside
    /// `[−1,1]×[0,1]` or not finite; the top and right edges fold onto the
    /// last pixel.
    pub fn ws_point_to_pixel(&self, x_p: f32, y_p: f32) -> Option<(i16, i16)> {
        let inside = (-1.0..=1.0).contains(&x_p) && (0.0..=1.0).contains(&y_p);
        if !inside {
            return None;
        }
        let ws = self.ws();
        let s = self.s as f32;
        // Both products are ≥ 0, so `as` truncation is the floor.
        let i = ((x_p + 1.0) * s) as i16;
        let j_up = (y_p * s) as i16;
        let x = (ws.x + i).min(ws.right() - 1);
        let y = (ws.bottom() - 1 - j_up).max(ws.y);
        Some((x, y))
    }
}
