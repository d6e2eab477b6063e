//! Colours. Pastel zones where the arm reaches, muted ones where it cannot;
//! dark text on light ground, red STOP, green RESUME.

use embedded_graphics::pixelcolor::Rgb565;

/// Screen background, a pale green-grey.
pub const BG: Rgb565 = Rgb565::new(29, 59, 29);
/// Normal text: black.
pub const TEXT: Rgb565 = Rgb565::new(0, 0, 0);
/// Secondary text (hints).
pub const TEXT_DIM: Rgb565 = Rgb565::new(10, 20, 10);
/// Labels on coloured buttons, marker halos, the calibration background.
pub const WHITE: Rgb565 = Rgb565::new(31, 63, 31);
/// The STOP button.
pub const STOP_RED: Rgb565 = Rgb565::new(28, 0, 0);
/// The RESUME and Save buttons.
pub const RESUME_GREEN: Rgb565 = Rgb565::new(0, 40, 4);
/// A button that is not selected.
pub const BUTTON: Rgb565 = Rgb565::new(22, 45, 22);
/// The selected speed preset, and Retry.
pub const BUTTON_ON: Rgb565 = Rgb565::new(2, 12, 18);
/// Warning text: amber.
pub const WARN_TEXT: Rgb565 = Rgb565::new(24, 16, 0);
/// Refusals and the STOP headline; a refused touch's marker.
pub const REFUSED: Rgb565 = Rgb565::new(26, 0, 0);
/// The progress bar's fill.
pub const PROGRESS: Rgb565 = Rgb565::new(2, 44, 6);
/// The progress bar's unfilled part.
pub const PROGRESS_BG: Rgb565 = Rgb565::new(24, 48, 24);
/// The progress bar's frame.
pub const FRAME: Rgb565 = Rgb565::new(6, 12, 6);

/// Zone colours by condition 1..4 (index 0..3), where the arm reaches.
pub const ZONE: [Rgb565; 4] = [
    Rgb565::new(18, 48, 31), // 1: sky blue
    Rgb565::new(18, 61, 18), // 2: light green
    Rgb565::new(31, 60, 14), // 3: light yellow
    Rgb565::new(31, 46, 24), // 4: pink
];
/// The same zones, out of reach: darker and greyer, still telling the zones
/// apart.
pub const ZONE_OUT: [Rgb565; 4] =
    [Rgb565::new(10, 26, 16), Rgb565::new(10, 32, 10), Rgb565::new(16, 31, 8), Rgb565::new(16, 24, 13)];
/// The triangle edges (the diagonals and the vertical through the base).
pub const ZONE_LINE: Rgb565 = Rgb565::new(6, 12, 6);
/// The arm base drawn at the map's origin.
pub const BASE: Rgb565 = Rgb565::new(8, 16, 8);
/// The touched point's plus.
pub const TOUCH_MARK: Rgb565 = Rgb565::new(0, 0, 0);
/// The target's ring.
pub const TARGET_MARK: Rgb565 = Rgb565::new(4, 0, 22);
/// The switch scan's line and highlight: orange, unlike every zone and
/// button colour.
pub const SCAN: Rgb565 = Rgb565::new(31, 26, 0);
/// The calibration crosshair.
pub const CROSSHAIR: Rgb565 = Rgb565::new(28, 0, 0);
