//! The workspace map: the four triangles of SPEC §3 (the paper's Figure 1)
//! over `[−1, 1] × [0, 1]`, shaded by reach, with the arm base, zone numbers
//! and the touch / target markers.
//!
//! The background is computed per pixel row as a handful of runs whose ends
//! are known in closed form (the diagonals and the reach circles), so any
//! sub-rectangle can be repainted exactly as a full draw would paint it, with
//! integer arithmetic only: pixel centres are `(dx, dy)/240` with odd
//! integers `dx, dy` (see `layout`), and the condition and reach tests on
//! them are exact.

use embedded_graphics::pixelcolor::Rgb565;

use super::draw::{fill, frame, text, Area, Canvas, Clip, Run, TextStyle};
use super::font::{CELL_H, CELL_W};
use super::layout::{ws_half_units, WS, WS_ORIGIN_X, WS_SCALE};
use super::theme;

/// Half side of a marker's box: markers are 17×17.
pub const MARKER_R: u16 = 8;

/// Map pixel of the arm base (the middle of the bottom edge).
pub const BASE_AREA: Area = Area::new(WS_ORIGIN_X - 7, WS.y + WS.h as i16 - 5, 14, 5);

const LABEL_STYLE: TextStyle = TextStyle::ink(3, theme::TEXT);

/// Zone labels "1".."4" at the triangles' centroids (2/3, 1/3), (1/3, 2/3),
/// (−1/3, 2/3), (−2/3, 1/3).
const LABELS: [(u8, i16, i16); 4] = [
    (b'1', WS_ORIGIN_X + 80, WS.y + 80),
    (b'2', WS_ORIGIN_X + 40, WS.y + 40),
    (b'3', WS_ORIGIN_X - 40, WS.y + 40),
    (b'4', WS_ORIGIN_X - 80, WS.y + 80),
];

fn label_area(cx: i16, cy: i16) -> Area {
    let s = u16::from(LABEL_STYLE.scale);
    let (w, h) = (CELL_W * s, CELL_H * s);
    // The cell's last column and row are blank: centre the 5×7 ink.
    Area::new(cx - (5 * s / 2) as i16, cy - (7 * s / 2) as i16, w, h)
}

/// How a marker looks.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MarkKind {
    /// The touched point: a plus.
    Touch,
    /// A touched point that was refused: a red plus.
    TouchRefused,
    /// The arm's target: a ring.
    Target,
}

/// A marker at a map pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Mark {
    /// Centre column, screen pixels.
    pub x: i16,
    /// Centre row, screen pixels.
    pub y: i16,
    /// Which marker.
    pub kind: MarkKind,
}

impl Mark {
    /// The box the marker paints (to repaint when it moves).
    pub fn area(&self) -> Area {
        Area::around(self.x, self.y, MARKER_R)
    }
}

/// Reach limits precomputed as squared radii in half-pixel units.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Reach {
    inner2: u32,
    outer2: u32,
}

impl Reach {
    /// `min`, `max`: the annulus the arm reaches, in workspace units
    /// (`|l2 − l3|/k` and `(l2 + l3)/k`). Non-finite or negative values count
    /// as 0; everything is reachable with `max ≥ √2`.
    pub fn new(min: f32, max: f32) -> Self {
        Self { inner2: half_units_sq(min), outer2: half_units_sq(max) }
    }

    /// Whether the centre `(dx, dy)/240` lies in the annulus.
    pub fn contains(&self, dx: i16, dy: i16) -> bool {
        let r2 = sq(dx) + sq(dy);
        r2 >= self.inner2 && r2 <= self.outer2
    }
}

fn sq(v: i16) -> u32 {
    let a = u32::from(v.unsigned_abs());
    a * a
}

fn half_units_sq(r: f32) -> u32 {
    // Beyond every pixel centre of the map: (2·240)² / 2 ≥ max dx² + dy².
    let limit = 2.0 * (2 * WS_SCALE) as f32 * (2 * WS_SCALE) as f32;
    if !crate::math::real::Real::is_positive(r) {
        return 0;
    }
    let v = r * (2 * WS_SCALE) as f32;
    let v2 = v * v;
    if v2 >= limit {
        limit as u32
    } else {
        (v2 + 0.5) as u32
    }
}

/// Largest odd `m ≥ 1` with `m² ≤ t`, or `None`.
fn largest_odd_root(t: i32) -> Option<i16> {
    if t < 1 {
        return None;
    }
    let mut r = isqrt(t as u32);
    if r.is_multiple_of(2) {
        r -= 1;
    }
    Some(r as i16)
}

fn isqrt(n: u32) -> u32 {
    let mut rem = n;
    let mut root = 0u32;
    let mut bit = 1u32 << 30;
    while bit > n {
        bit >>= 2;
    }
    while bit != 0 {
        if rem >= root + bit {
            rem -= root + bit;
            root = (root >> 1) + bit;
        } else {
            root >>= 1;
        }
        bit >>= 2;
    }
    root
}

/// Condition 1..4 (as index 0..3) of the centre `(dx, dy)` with `dy > 0`,
/// the same exact rule as `workspace::Condition`.
pub fn zone_index(dx: i16, dy: i16) -> usize {
    if dx >= dy {
        0
    } else if dx >= 0 {
        1
    } else if dy >= -dx {
        2
    } else {
        3
    }
}

/// Colour of map pixel `(x, y)` (screen coordinates inside [`WS`]).
pub fn background_at(reach: &Reach, x: i16, y: i16) -> Rgb565 {
    let col = x - WS.x;
    let row = y - WS.y;
    let last = WS.w as i16 - 1;
    // The 45° diagonals pass through columns `row` and `last − row`; the
    // vertical is the two middle columns.
    let mid = WS_ORIGIN_X - WS.x;
    if col == row || col == last - row || col == mid - 1 || col == mid {
        return theme::ZONE_LINE;
    }
    let (dx, dy) = ws_half_units(x, y);
    let z = zone_index(dx, dy);
    if reach.contains(dx, dy) {
        theme::ZONE[z]
    } else {
        theme::ZONE_OUT[z]
    }
}

/// Column breakpoints of one map row (screen x), sorted, where the colour
/// may change. At most 12.
fn row_breaks(reach: &Reach, y: i16, out: &mut [i16; 14]) -> usize {
    let row = y - WS.y;
    let last = WS.w as i16 - 1;
    let mid = WS_ORIGIN_X - WS.x;
    let (_, dy) = ws_half_units(WS.x, y);
    let dy2 = sq(dy) as i32;
    let mut n = 0;
    let mut push = |v: i16, n: &mut usize| {
        if *n < out.len() {
            out[*n] = v.clamp(0, WS.w as i16) + WS.x;
            *n += 1;
        }
    };
    for v in [row, row + 1, last - row, last - row + 1, mid - 1, mid + 1] {
        push(v, &mut n);
    }
    // Columns with |dx| ≤ m, where dx = 2·col + 1 − 2·mid.
    let span = |m: i16| ((2 * mid - 1 - m) / 2, (2 * mid - 1 + m) / 2 + 1);
    if let Some(m) = largest_odd_root(reach.outer2 as i32 - dy2) {
        let (a, b) = span(m);
        push(a, &mut n);
        push(b, &mut n);
    }
    if let Some(m) = largest_odd_root(reach.inner2 as i32 - dy2 - 1) {
        let (a, b) = span(m);
        push(a, &mut n);
        push(b, &mut n);
    }
    // Insertion sort: a dozen values.
    let mut i = 1;
    while i < n {
        let v = out[i];
        let mut j = i;
        while j > 0 && out[j - 1] > v {
            out[j] = out[j - 1];
            j -= 1;
        }
        out[j] = v;
        i += 1;
    }
    n
}

/// Paints the map background over `area ∩ WS`: one [`Canvas::fill_runs`]
/// per row (a dozen runs each).
pub fn draw_background<D: Canvas>(d: &mut D, reach: &Reach, area: Area) -> Result<(), D::Error> {
    let Some(a) = area.intersect(&WS) else {
        return Ok(());
    };
    let mut breaks = [0i16; 14];
    for y in a.y..a.bottom() {
        let n = row_breaks(reach, y, &mut breaks);
        let mut runs = [Run { len: 0, color: theme::ZONE_LINE }; 14];
        let mut count = 0usize;
        let mut start = a.x;
        let mut k = 0;
        while start < a.right() {
            // Next breakpoint after `start`.
            while k < n && breaks[k] <= start {
                k += 1;
            }
            let end = if k < n { breaks[k].min(a.right()) } else { a.right() };
            if let Some(slot) = runs.get_mut(count) {
                *slot = Run { len: (end - start) as u16, color: background_at(reach, start, y) };
                count += 1;
            }
            start = end;
        }
        d.fill_runs(&Area::new(a.x, y, a.w, 1).to_rect(), runs.get(..count).unwrap_or(&[]))?;
    }
    Ok(())
}

/// Base, zone numbers and markers (`marks` in drawing order), clipped to
/// `clip`: the layers above the background.
pub fn draw_overlays<D: Canvas>(d: &mut D, clip: Area, marks: &[Mark]) -> Result<(), D::Error> {
    let Some(clip) = clip.intersect(&WS) else {
        return Ok(());
    };
    let mut c = Clip { inner: d, clip };
    if let Some(b) = BASE_AREA.intersect(&clip) {
        fill(&mut *c.inner, b, theme::BASE)?;
    }
    for &(ch, cx, cy) in LABELS.iter() {
        let la = label_area(cx, cy);
        if la.intersect(&clip).is_some() {
            text(&mut c, la.x, la.y, &[ch][..], &LABEL_STYLE)?;
        }
    }
    for m in marks {
        if m.area().intersect(&clip).is_some() {
            draw_mark(&mut c, m)?;
        }
    }
    Ok(())
}

fn draw_mark<D: Canvas>(d: &mut D, m: &Mark) -> Result<(), D::Error> {
    let r = MARKER_R as i16;
    match m.kind {
        MarkKind::Touch | MarkKind::TouchRefused => {
            let ink = if m.kind == MarkKind::Touch { theme::TOUCH_MARK } else { theme::REFUSED };
            // A white halo keeps the plus visible on every zone colour.
            fill(d, Area::new(m.x - r, m.y - 2, 2 * MARKER_R + 1, 5), theme::WHITE)?;
            fill(d, Area::new(m.x - 2, m.y - r, 5, 2 * MARKER_R + 1), theme::WHITE)?;
            fill(d, Area::new(m.x - r + 1, m.y - 1, 2 * MARKER_R - 1, 3), ink)?;
            fill(d, Area::new(m.x - 1, m.y - r + 1, 3, 2 * MARKER_R - 1), ink)
        }
        MarkKind::Target => {
            let outer = Area::around(m.x, m.y, MARKER_R);
            frame(d, outer, 1, theme::WHITE)?;
            frame(d, outer.shrink(1), 3, theme::TARGET_MARK)?;
            frame(d, outer.shrink(4), 1, theme::WHITE)
        }
    }
}

/// The whole map: background, base, labels, markers.
pub fn draw_map<D: Canvas>(d: &mut D, reach: &Reach, marks: &[Mark]) -> Result<(), D::Error> {
    draw_background(d, reach, WS)?;
    draw_overlays(d, WS, marks)
}

/// Repaints exactly `area ∩ WS` with every layer.
pub fn repaint<D: Canvas>(d: &mut D, reach: &Reach, area: Area, marks: &[Mark]) -> Result<(), D::Error> {
    draw_background(d, reach, area)?;
    draw_overlays(d, area, marks)
}
