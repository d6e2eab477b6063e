//! The app's output lines: [`crate::text::line::Line`] sized for the longest
//! reply, [`milli`] for the thousandths they print, and the words lines share.

use crate::math::units::round_i32;

/// Longest line the app writes, terminator included: the longest `status`
/// (every optional field, the widest values and the longest words; tested).
pub const LINE_CAP: usize = 272;
const _: () = assert!(LINE_CAP <= crate::protocol::rx_loss::TX_BUFFER);

/// One output line (the serial replies and logs).
pub type Line = crate::text::line::Line<LINE_CAP>;

/// A value in thousandths (e.g. mrad/s from rad/s), rounded, saturating.
pub fn milli(v: f32) -> i32 {
    round_i32(v * 1000.0)
}

/// The word of `mode` for hold to run on (`hold`) or off (`tap`), for its
/// reply and `cal show`.
pub fn mode_name(hold: bool) -> crate::text::Text {
    if hold {
        t!("hold")
    } else {
        t!("tap")
    }
}

/// ` off` for a plate ratio not measured (0), else ` <ratio>` with two
/// decimals: how `cal show` and the calibration's reply print it.
pub fn plate_word(line: &mut Line, plate: u16) {
    if plate == 0 {
        line.word(t!("off"));
    } else {
        line.bytes(b" ").centi(crate::config::settings::plate_centi(plate));
    }
}
