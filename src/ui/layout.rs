//! Where everything sits on the 320×240 landscape screen, and the two
//! coordinate mappings.
//!
//! ```text
//!  0                                240 248             320
//!  +----------------------------------+--+---------------+ 0
//!  | workspace map 240×120             |g |  STOP/RESUME  |
//!  | (x_p, y_p) ∈ [−1,1]×[0,1]          |  |    72×120     |
//!  +----------------------------------+  +---------------+ 120
//!  guard band (touches ignored; next to STOP they count as STOP)   128
//!  headline  (2×)                                          148
//!  detail: hint (2×) or progress bar                       168
//!  zone + direction (1×)          | warning (1×)           182
//!  joint angles (1×)                                       196
//!  +------+ +--------+ +------+    +---------+             200
//!  | Slow | | Normal | | Fast |    |  Calib  |
//!  +------+ +--------+ +------+    +---------+             240
//! ```
//!
//! **Panel coordinates** are what the touch pipeline produces from a raw
//! reading with the calibration (SPEC §2): `(x_p, y_p)` over the *whole* glass,
//! `x_p = −1` at the left edge, `+1` at the right, `y_p = 0` at the bottom,
//! `1` at the top. [`panel_to_pixel`] turns them into a screen pixel and
//! [`pixel_center_to_panel`] back; the calibration crosshairs are placed with
//! this mapping.
//!
//! **Workspace coordinates** are the paper's `(x_p, y_p) ∈ [−1, 1] × [0, 1]`
//! that the arm math takes. They live in the 240×120 map at the top left,
//! 120 pixels per unit on both axes, so the reach circle is drawn round:
//! pixel column `i` covers `x_p ∈ [(i − 120)/120, (i − 119)/120)` and row `j`
//! covers `y_p ∈ [(119 − j)/120, (120 − j)/120)` (the map's right and top
//! edges fold onto the last column and row); a touch on pixel `(i, j)`
//! means its centre, `x_p = (2i + 1 − 240)/240`, `y_p = (239 − 2j)/240`. The
//! base of the arm is the middle of the map's bottom edge.
//!
//! Why a sub-rectangle and not the paper's whole-panel map with buttons on
//! top: for a user with limited hand use, a touch meant for STOP that lands a
//! little off must never send the arm somewhere. So no arm target shares an
//! edge with a button: an 8-pixel guard band separates the map from
//! everything else, touches in it do nothing — except beside STOP, where they
//! count as STOP (the safe reading of an ambiguous touch). RESUME, which
//! starts motion, is hit only inside its own drawn box.

use super::draw::Area;

/// Display width in landscape, pixels.
pub const SCREEN_W: u16 = 320;
/// Display height in landscape, pixels.
pub const SCREEN_H: u16 = 240;

/// The workspace map. `WS_SCALE` pixels per workspace unit; the origin (arm
/// base) is at pixel edge (`WS_ORIGIN_X`, `WS.bottom()`).
pub const WS: Area = Area::new(0, 0, 240, 120);
/// Pixels per workspace unit (the map is 2 × 1 units).
pub const WS_SCALE: u16 = 120;
/// Column of the arm base, the workspace's x = 0.
pub const WS_ORIGIN_X: i16 = 120;

/// The STOP (or RESUME) button, right of the map.
pub const STOP: Area = Area::new(248, 0, 72, 120);
/// Where a touch counts as STOP while STOP is shown: its box plus the guard
/// band beside and below it.
pub const STOP_HIT: Area = Area::new(240, 0, 80, 128);

/// What the arm is doing, in words, at double size.
pub const HEADLINE: Area = Area::new(0, 128, 320, 20);
/// The second line: a hint in words, or the progress bar while moving.
pub const DETAIL: Area = Area::new(0, 148, 320, 20);
/// Zone and direction α of the touched point.
pub const INFO: Area = Area::new(0, 168, 160, 14);
/// The most important warning.
pub const WARN: Area = Area::new(160, 168, 160, 14);
/// The three joint angles, whole degrees.
pub const JOINTS: Area = Area::new(0, 182, 320, 14);

/// Progress bar inside DETAIL: a 1-pixel frame around the fill.
pub const BAR: Area = Area::new(4, 151, 232, 14);
/// The bar's fill: filled from the left by the move's progress.
pub const BAR_FILL: Area = Area::new(5, 152, 230, 12);
/// The percentage next to the bar.
pub const BAR_TEXT: Area = Area::new(244, 150, 72, 16);

/// Speed preset button Slow.
pub const SLOW: Area = Area::new(0, 200, 72, 40);
/// Speed preset button Normal.
pub const NORMAL: Area = Area::new(80, 200, 80, 40);
/// Speed preset button Fast.
pub const FAST: Area = Area::new(168, 200, 72, 40);
/// Opens the touch calibration.
pub const CALIBRATE: Area = Area::new(248, 200, 72, 40);

/// Pixels no region paints: the guard bands and button gaps (a full redraw
/// fills them with the background).
pub const GAPS: [Area; 6] = [
    Area::new(240, 0, 8, 120),
    Area::new(0, 120, 320, 8),
    Area::new(0, 196, 320, 4),
    Area::new(72, 200, 8, 40),
    Area::new(160, 200, 8, 40),
    Area::new(240, 200, 8, 40),
];

/// A panel point to the pixel it falls on, `None` outside `[−1,1]×[0,1]` or
/// not finite. `x = ⌊(x_p + 1)·160⌋`, `y = ⌊(1 − y_p)·240⌋`, the far edges
/// folded onto the last pixel.
pub fn panel_to_pixel(x_p: f32, y_p: f32) -> Option<(i16, i16)> {
    let inside = (-1.0..=1.0).contains(&x_p) && (0.0..=1.0).contains(&y_p);
    if !inside {
        return None;
    }
    let x = ((x_p + 1.0) * (SCREEN_W / 2) as f32) as i16;
    let y = ((1.0 - y_p) * SCREEN_H as f32) as i16;
    Some((x.min(SCREEN_W as i16 - 1), y.min(SCREEN_H as i16 - 1)))
}

/// The panel coordinates of a pixel's centre (inverse of [`panel_to_pixel`]).
pub fn pixel_center_to_panel(x: i16, y: i16) -> (f32, f32) {
    let x_p = (2.0 * f32::from(x) + 1.0) / SCREEN_W as f32 - 1.0;
    let y_p = 1.0 - (2.0 * f32::from(y) + 1.0) / (2.0 * SCREEN_H as f32);
    (x_p, y_p)
}

/// Workspace point of a map pixel's centre; `None` outside the map.
pub fn ws_pixel_to_point(x: i16, y: i16) -> Option<(f32, f32)> {
    if !WS.contains(x, y) {
        return None;
    }
    let (dx, dy) = ws_half_units(x, y);
    let two_scale = (2 * WS_SCALE) as f32;
    Some((f32::from(dx) / two_scale, f32::from(dy) / two_scale))
}

/// Pixel centre relative to the arm base in half-pixel units (both odd):
/// `x_p = dx/240`, `y_p = dy/240` exactly.
pub const fn ws_half_units(x: i16, y: i16) -> (i16, i16) {
    let dx = 2 * (x - WS.x) + 1 - 2 * (WS_ORIGIN_X - WS.x);
    let dy = 2 * (WS.bottom() - y) - 1;
    (dx, dy)
}

/// The map pixel a workspace point falls on, `None` outside `[−1,1]×[0,1]`
/// or not finite; the top and right edges fold onto the last pixel.
pub fn ws_point_to_pixel(x_p: f32, y_p: f32) -> Option<(i16, i16)> {
    let inside = (-1.0..=1.0).contains(&x_p) && (0.0..=1.0).contains(&y_p);
    if !inside {
        return None;
    }
    let s = WS_SCALE as f32;
    // Both products are ≥ 0, so `as` truncation is the floor.
    let i = ((x_p + 1.0) * s) as i16;
    let j_up = (y_p * s) as i16;
    let x = (WS.x + i).min(WS.right() - 1);
    let y = (WS.bottom() - 1 - j_up).max(WS.y);
    Some((x, y))
}
