//! Colours. Pastel zones where the arm reaches, muted ones where it cannot;
//! dark text on light ground, red STOP, green RESUME.

use embedded_graphics::pixelcolor::Rgb565;

pub const BG: Rgb565 = Rgb565::new(29, 59, 29);
pub const TEXT: Rgb565 = Rgb565::new(0, 0, 0);
pub const TEXT_DIM: Rgb565 = Rgb565::new(10, 20, 10);
pub const WHITE: Rgb565 = Rgb565::new(31, 63, 31);
pub const STOP_RED: Rgb565 = Rgb565::new(28, 0, 0);
pub const RESUME_GREEN: Rgb565 = Rgb565::new(0, 40, 4);
pub const BUTTON: Rgb565 = Rgb565::new(22, 45, 22);
pub const BUTTON_ON: Rgb565 = Rgb565::new(2, 12, 18);
pub const WARN_TEXT: Rgb565 = Rgb565::new(24, 16, 0);
pub const REFUSED: Rgb565 = Rgb565::new(26, 0, 0);
pub const PROGRESS: Rgb565 = Rgb565::new(2, 44, 6);
pub const PROGRESS_BG: Rgb565 = Rgb565::new(24, 48, 24);
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
pub const BASE: Rgb565 = Rgb565::new(8, 16, 8);
pub const TOUCH_MARK: Rgb565 = Rgb565::new(0, 0, 0);
pub const TARGET_MARK: Rgb565 = Rgb565::new(4, 0, 22);
pub const CROSSHAIR: Rgb565 = Rgb565::new(28, 0, 0);
