//! The workspace map: the four triangles of method.md §4–5 (the paper's Figure 1)
//! over `[−1, 1] × [0, 1]`, shaded by reach, with the arm base, zone numbers
//! and the touch / target markers.
//!
//! The background is computed per pixel row as a handful of runs whose ends
//! are known in closed form (the diagonals and the reach circles), so any
//! sub-rectangle can be repainted exactly as a full draw would paint it, with
//! integer arithmetic only: pixel centres are `(dx, dy)/2s` with odd
//! integers `dx, dy` (see `layout`), and the condition and reach tests on
//! them are exact. Sizes are the 320×240 screen's, scaled with the map
//! ([`Layout::sm`]).

use embedded_graphics::pixelcolor::Rgb565;

use super::draw::{fill, frame, text, Area, Canvas, Clip, Run, TextStyle};
use super::font::{CELL_H, CELL_W};
use super::layout::Layout;
use super::theme;

/// Half side of a marker's box: markers are 17×17 at 320×240.
pub const fn marker_r(lay: &Layout) -> u16 {
    lay.sm(8)
}

/// Map pixels of the arm base (the middle of the bottom edge): 14×5 at
/// 320×240.
pub const fn base_area(lay: &Layout) -> Area {
    let half = lay.sm(7);
    let h = lay.sm(5);
    let ws = lay.ws();
    Area::new(lay.ws_origin_x() - half as i16, ws.bottom() - h as i16, 2 * half, h)
}

/// The zone numbers: ink one scale above the layout's text.
fn label_style(lay: &Layout) -> TextStyle {
    TextStyle::ink(lay.text_scale() + 1, theme::TEXT)
}

/// Zone labels "1".."4" at the triangles' centroids (2/3, 1/3), (1/3, 2/3),
/// (−1/3, 2/3), (−2/3, 1/3).
fn labels(lay: &Layout) -> [(u8, i16, i16); 4] {
    let (ox, top) = (lay.ws_origin_x(), lay.ws().y);
    let third = (lay.scale() / 3) as i16;
    let two = (2 * lay.scale() / 3) as i16;
    [
        (b'1', ox + two, top + two),
        (b'2', ox + third, top + third),
        (b'3', ox - third, top + third),
        (b'4', ox - two, top + two),
    ]
}

fn label_area(style: &TextStyle, cx: i16, cy: i16) -> Area {
    let s = u16::from(style.scale);
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
    /// The candidate under a finger (issue #19): a frame whose sides fill
    /// one by one over the hold (`ring` of 4), green if the arm reaches
    /// it, red if not.
    Candidate {
        /// The arm can reach it.
        ok: bool,
        /// Sides filled, 0..=4.
        ring: u8,
    },
    /// The switch scan's column line (issue #20 §4), across the map at
    /// `x`: one pixel of ink between two of white, so it shows on every
    /// zone colour.
    ScanColumn,
    /// The switch scan's row line at `y`, as the column's.
    ScanRow,
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
    pub fn area(&self, lay: &Layout) -> Area {
        let ws = lay.ws();
        match self.kind {
            MarkKind::ScanColumn => Area::new(self.x - 1, ws.y, 3, ws.h),
            MarkKind::ScanRow => Area::new(ws.x, self.y - 1, ws.w, 3),
            _ => Area::around(self.x, self.y, marker_r(lay)),
        }
    }
}

/// Reach limits precomputed as squared radii in half-pixel units of one
/// map scale.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Reach {
    inner2: u32,
    outer2: u32,
}

impl Reach {
    /// `min`, `max`: the annulus the arm reaches, in workspace units
    /// (`|l2 − l3|/k` and `(l2 + l3)/k`), on a map of `scale` pixels per unit.
    /// Non-finite or negative values count as 0; everything is reachable
    /// with `max ≥ √2`.
    pub fn new(min: f32, max: f32, scale: u16) -> Self {
        Self { inner2: half_units_sq(min, scale), outer2: half_units_sq(max, scale) }
    }

    /// Whether the centre `(dx, dy)/2s` lies in the annulus.
    pub fn contains(&self, dx: i16, dy: i16) -> bool {
        let r2 = sq(dx) + sq(dy);
        r2 >= self.inner2 && r2 <= self.outer2
    }
}

fn sq(v: i16) -> u32 {
    let a = u32::from(v.unsigned_abs());
    a * a
}

fn half_units_sq(r: f32, scale: u16) -> u32 {
    // Beyond every pixel centre of the map: 2·(2s)² ≥ max dx² + dy².
    let limit = 2.0 * (2 * scale) as f32 * (2 * scale) as f32;
    if !crate::math::real::Real::is_positive(r) {
        return 0;
    }
    let v = r * (2 * scale) as f32;
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

/// Colour of map pixel `(x, y)` (screen coordinates inside the map).
pub fn background_at(lay: &Layout, reach: &Reach, x: i16, y: i16) -> Rgb565 {
    let ws = lay.ws();
    let col = x - ws.x;
    let row = y - ws.y;
    let last = ws.w as i16 - 1;
    // The 45° diagonals pass through columns `row` and `last − row`; the
    // vertical is the two middle columns.
    let mid = lay.ws_origin_x() - ws.x;
    if col == row || col == last - row || col == mid - 1 || col == mid {
        return theme::ZONE_LINE;
    }
    let (dx, dy) = lay.ws_half_units(x, y);
    let z = zone_index(dx, dy);
    if reach.contains(dx, dy) {
        theme::ZONE[z]
    } else {
        theme::ZONE_OUT[z]
    }
}

/// Breakpoints along one map row (`by_columns` false: screen x) or one
/// map column (screen y), sorted, where the colour may change: the two
/// diagonals' pixels, the vertical's edges and the reach circles. At
/// most 10.
fn line_breaks(lay: &Layout, reach: &Reach, at: i16, by_columns: bool, out: &mut [i16; 14]) -> usize {
    let ws = lay.ws();
    let last = ws.w as i16 - 1;
    let mid = lay.ws_origin_x() - ws.x;
    // The line's index, where it starts, how long it is, the centre of the
    // reach circles along it, and its half-unit coordinate across.
    let (i, origin, len, centre, across) = if by_columns {
        (at - ws.x, ws.y, ws.h, ws.h as i16, lay.ws_half_units(at, ws.y).0)
    } else {
        (at - ws.y, ws.x, ws.w, mid, lay.ws_half_units(ws.x, at).1)
    };
    let across2 = sq(across) as i32;
    let mut n = 0;
    let mut push = |v: i16, n: &mut usize| {
        if *n < out.len() {
            out[*n] = v.clamp(0, len as i16) + origin;
            *n += 1;
        }
    };
    // A diagonal pixel has column = row or column = last − row, the same
    // rule along either axis; along a column the vertical's edges are
    // spare breaks (its two columns are one colour all the way).
    for v in [i, i + 1, last - i, last - i + 1, mid - 1, mid + 1] {
        push(v, &mut n);
    }
    // Pixels with |d| ≤ m, where d = 2·k + 1 − 2·centre at index k (dx
    // along a row; −dy along a column, whose centre is the map's bottom).
    let span = |m: i16| ((2 * centre - 1 - m) / 2, (2 * centre - 1 + m) / 2 + 1);
    if let Some(m) = largest_odd_root(reach.outer2 as i32 - across2) {
        let (a, b) = span(m);
        push(a, &mut n);
        push(b, &mut n);
    }
    if let Some(m) = largest_odd_root(reach.inner2 as i32 - across2 - 1) {
        let (a, b) = span(m);
        push(a, &mut n);
        push(b, &mut n);
    }
    sort(out, n);
    n
}

/// Insertion sort of `out[..n]`: a dozen values.
fn sort(out: &mut [i16; 14], n: usize) {
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
}

/// Widest area painted column by column: a scan line's box (3 pixels)
/// takes three operations of a few runs each instead of one per map row
/// (a hundred, and the column line trailed the scan on the chip:
/// BENCHMARKS.md, frame budget).
const COLUMNS_W: u16 = 3;

/// Paints the map background over `area ∩` the map: one [`Canvas::fill_runs`]
/// per row (a dozen runs each), or per column for an area at most
/// 3 pixels wide (a scan line's box).
pub fn draw_background<D: Canvas>(d: &mut D, lay: &Layout, reach: &Reach, area: Area) -> Result<(), D::Error> {
    let Some(a) = area.intersect(&lay.ws()) else {
        return Ok(());
    };
    let by_columns = a.w <= COLUMNS_W;
    let (lines, from, to) =
        if by_columns { (a.x..a.right(), a.y, a.bottom()) } else { (a.y..a.bottom(), a.x, a.right()) };
    let mut breaks = [0i16; 14];
    for at in lines {
        if d.paused() {
            break;
        }
        // One operation per line.
        if d.skip_op() {
            continue;
        }
        let n = line_breaks(lay, reach, at, by_columns, &mut breaks);
        let mut runs = [Run { len: 0, color: theme::ZONE_LINE }; 14];
        let mut count = 0usize;
        let mut start = from;
        let mut k = 0;
        while start < to {
            // Next breakpoint after `start`.
            while k < n && breaks[k] <= start {
                k += 1;
            }
            let end = if k < n { breaks[k].min(to) } else { to };
            let (x, y) = if by_columns { (at, start) } else { (start, at) };
            if let Some(slot) = runs.get_mut(count) {
                *slot = Run { len: (end - start) as u16, color: background_at(lay, reach, x, y) };
                count += 1;
            }
            start = end;
        }
        let line = if by_columns { Area::new(at, a.y, 1, a.h) } else { Area::new(a.x, at, a.w, 1) };
        d.fill_runs(&line.to_rect(), runs.get(..count).unwrap_or(&[]))?;
    }
    Ok(())
}

/// Base, zone numbers and markers (`marks` in drawing order), clipped to
/// `clip`: the layers above the background.
pub fn draw_overlays<D: Canvas>(d: &mut D, lay: &Layout, clip: Area, marks: &[Mark]) -> Result<(), D::Error> {
    let Some(clip) = clip.intersect(&lay.ws()) else {
        return Ok(());
    };
    let mut c = Clip { inner: d, clip };
    if let Some(b) = base_area(lay).intersect(&clip) {
        fill(&mut *c.inner, b, theme::BASE)?;
    }
    let style = label_style(lay);
    for &(ch, cx, cy) in labels(lay).iter() {
        let la = label_area(&style, cx, cy);
        if la.intersect(&clip).is_some() {
            text(&mut c, la.x, la.y, &[ch][..], &style)?;
        }
    }
    for m in marks {
        if m.area(lay).intersect(&clip).is_some() {
            draw_mark(&mut c, lay, m)?;
        }
    }
    Ok(())
}

fn draw_mark<D: Canvas>(d: &mut D, lay: &Layout, m: &Mark) -> Result<(), D::Error> {
    let big_r = marker_r(lay);
    let r = big_r as i16;
    match m.kind {
        MarkKind::Touch | MarkKind::TouchRefused => {
            let ink = if m.kind == MarkKind::Touch { theme::TOUCH_MARK } else { theme::REFUSED };
            // A white halo keeps the plus visible on every zone colour.
            fill(d, Area::new(m.x - r, m.y - 2, 2 * big_r + 1, 5), theme::WHITE)?;
            fill(d, Area::new(m.x - 2, m.y - r, 5, 2 * big_r + 1), theme::WHITE)?;
            fill(d, Area::new(m.x - r + 1, m.y - 1, 2 * big_r - 1, 3), ink)?;
            fill(d, Area::new(m.x - 1, m.y - r + 1, 3, 2 * big_r - 1), ink)
        }
        MarkKind::Target => {
            let outer = Area::around(m.x, m.y, big_r);
            frame(d, outer, 1, theme::WHITE)?;
            frame(d, outer.shrink(1), 3, theme::TARGET_MARK)?;
            frame(d, outer.shrink(4), 1, theme::WHITE)
        }
        MarkKind::Candidate { ok, ring } => draw_candidate(d, lay, m, ok, ring),
        MarkKind::ScanColumn | MarkKind::ScanRow => {
            let a = m.area(lay);
            fill(d, a, theme::WHITE)?;
            fill(d, a.shrink_across(m.kind == MarkKind::ScanColumn), theme::SCAN)
        }
    }
}

/// The candidate: a white frame and four rings inside it that take the
/// verdict's colour from the outside in as the hold fills, around a dot in
/// that colour. Out of line: only the preview draws it, rarely.
#[inline(never)] // reason: cold
fn draw_candidate<D: Canvas>(d: &mut D, lay: &Layout, m: &Mark, ok: bool, ring: u8) -> Result<(), D::Error> {
    let outer = Area::around(m.x, m.y, marker_r(lay));
    let ink = if ok { theme::RESUME_GREEN } else { theme::REFUSED };
    for i in 0..5u8 {
        let c = if i > 0 && i <= ring { ink } else { theme::WHITE };
        frame(d, outer.shrink(u16::from(i)), 1, c)?;
    }
    fill(d, Area::around(m.x, m.y, 2), ink)
}

/// The whole map: background, base, labels, markers.
pub fn draw_map<D: Canvas>(d: &mut D, lay: &Layout, reach: &Reach, marks: &[Mark]) -> Result<(), D::Error> {
    draw_background(d, lay, reach, lay.ws())?;
    draw_overlays(d, lay, lay.ws(), marks)
}

/// Repaints exactly `area ∩` the map with every layer.
pub fn repaint<D: Canvas>(d: &mut D, lay: &Layout, reach: &Reach, area: Area, marks: &[Mark]) -> Result<(), D::Error> {
    draw_background(d, lay, reach, area)?;
    draw_overlays(d, lay, area, marks)
}
