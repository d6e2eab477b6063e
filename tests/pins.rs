//! The pin map (`seam::pins`) against docs/hardware.md's table, written out here
//! independently: the board and the simulator both take their pins from it.

use touch_arm::seam::pins::mega::*;
use touch_arm::seam::pins::{PanelPinout, Pin, Port};

fn p(port: char, bit: u8) -> Pin {
    let port = match port {
        'E' => Port::E,
        'F' => Port::F,
        'G' => Port::G,
        'H' => Port::H,
        'L' => Port::L,
        _ => unreachable!(),
    };
    Pin::new(port, bit)
}

#[test]
fn lcd_bus_and_servos_follow_the_spec_table() {
    assert_eq!([LCD_RD, LCD_WR, LCD_RS, LCD_CS, LCD_RST], [p('F', 0), p('F', 1), p('F', 2), p('F', 3), p('F', 4)]);
    assert_eq!(LCD_DATA, [p('H', 5), p('H', 6), p('E', 4), p('E', 5), p('G', 5), p('E', 3), p('H', 3), p('H', 4)]);
    // Base, shoulder, elbow on OC5A/B/C.
    assert_eq!(SERVOS, [p('L', 3), p('L', 4), p('L', 5)]);
    assert_eq!(Port::L.letter(), 'L');
    assert_eq!(Pin::new(Port::F, 9).bit(), 1, "bit is taken modulo 8");
}

#[test]
fn panel_pinouts_are_four_distinct_shield_pins_with_analog_x_minus_and_y_plus() {
    let shield: Vec<Pin> = [LCD_RD, LCD_WR, LCD_RS, LCD_CS, LCD_RST].into_iter().chain(LCD_DATA).collect();
    let expect = [
        (PanelPinout::A, [p('H', 5), p('F', 2), p('F', 3), p('H', 6)], (2, 3)),
        (PanelPinout::B, [p('H', 3), p('F', 2), p('F', 1), p('H', 4)], (2, 1)),
        (PanelPinout::C, [p('H', 4), p('F', 1), p('F', 2), p('H', 3)], (1, 2)),
    ];
    for (w, pins, (xm_ch, yp_ch)) in expect {
        assert_eq!([w.xp, w.xm, w.yp, w.ym], pins);
        assert_eq!((w.xm.adc_channel(), w.yp.adc_channel()), (Some(xm_ch), Some(yp_ch)));
        for (i, a) in pins.iter().enumerate() {
            assert!(shield.contains(a));
            assert!(!pins[i + 1..].contains(a));
        }
    }
    assert_eq!(Pin::new(Port::K, 2).adc_channel(), Some(10));
    assert_eq!(D8.adc_channel(), None);
}
