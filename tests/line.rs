//! The one line builder (`text::line::Line`) at the sizes the screen uses,
//! and the screen's angle text (`ui::degrees`). The app's 192-byte replies
//! are checked in `tests/app.rs` (`text_formatting`).

use touch_arm::t;
use touch_arm::text::line::Line;
use touch_arm::ui::degrees::{whole_deg, PushDeg};
use touch_arm::ui::font::DEGREE;

#[test]
fn a_short_line_keeps_what_fits() {
    let mut l: Line<5> = Line::new();
    l.str(t!("Point ")).i32(12);
    assert_eq!(l.as_bytes(), b"Point");
    let mut l: Line<6> = Line::new();
    l.i32(-1234).u32(567);
    assert_eq!(l.as_bytes(), b"-12345");
    l.clear().centi(-5);
    assert_eq!(l.as_bytes(), b"-0.05");
    assert_eq!(Line::<4>::default().as_bytes(), b"");
}

#[test]
fn finish_always_fits_the_terminator() {
    let mut l: Line<5> = Line::new();
    l.bytes(b"abcdefgh");
    assert_eq!(l.finish(), b"abc\r\n");
    let mut l: Line<8> = Line::new();
    l.bytes(b"ok");
    assert_eq!(l.finish(), b"ok\r\n");
}

#[test]
fn hex_shows_the_low_digits_lowercase() {
    let mut l: Line<32> = Line::new();
    l.hex(0x9341, 4).bytes(b" ").hex(0x0085_8552, 6).bytes(b" ").hex(0xABCD_EF01, 8).bytes(b" ").hex(0x1F, 1);
    assert_eq!(l.as_bytes(), b"0x9341 0x858552 0xabcdef01 0xf");
    // 1 to 8 digits, whatever is asked.
    assert_eq!(Line::<16>::new().hex(u32::MAX, 12).as_bytes(), b"0xffffffff");
    assert_eq!(Line::<16>::new().hex(0x9341, 0).as_bytes(), b"0x1");
}

#[test]
fn angles_show_whole_degrees_with_the_glyph() {
    let mut l: Line<16> = Line::new();
    l.deg(Some(-45)).bytes(b" ").deg(None);
    assert_eq!(l.as_bytes(), &[b'-', b'4', b'5', DEGREE, b' ', b'-', b'-']);
    assert_eq!(whole_deg(std::f32::consts::FRAC_PI_2), Some(90));
    // 0.5° rounds away from zero, both ways.
    assert_eq!(whole_deg(0.5f32.to_radians()), Some(1));
    assert_eq!(whole_deg(-0.5f32.to_radians()), Some(-1));
    assert_eq!(whole_deg(0.49f32.to_radians()), Some(0));
    assert_eq!(whole_deg(1e6), Some(9999));
    assert_eq!(whole_deg(-1e6), Some(-9999));
    assert_eq!(whole_deg(f32::NAN), None);
    assert_eq!(whole_deg(f32::INFINITY), None);
}
