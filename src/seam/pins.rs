//! The pin map: which ATmega2560 pin carries which signal of the shield and
//! the servos (docs/hardware.md). Pure data, shared by the chip's drivers (`board`)
//! and by the simulator (`hal_sim`: the LCD-bus decoder, the panel on the
//! ADC, the measured servo pins), as [`crate::ui::ili9341`] is for the LCD
//! commands; so the firmware and its simulated board cannot disagree.

/// The eleven GPIO ports of the ATmega2560 (there is no port I).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Port {
    /// PA0..PA7: Mega D22..D29.
    A,
    /// PB0..PB3: D53, D52, D51, D50 (SPI); PB4..PB7: D10..D13.
    B,
    /// PC0..PC7: Mega D37..D30.
    C,
    /// PD0..PD3: D21, D20, D19, D18 (TWI, USART1); PD7: D38.
    D,
    /// PE0, PE1: D0, D1 (USART0); PE3: D5; PE4, PE5: D2, D3.
    E,
    /// PF0..PF7: A0..A7 (ADC0..7).
    F,
    /// PG0..PG2: D41, D40, D39; PG5: D4.
    G,
    /// PH0, PH1: D17, D16 (USART2); PH3..PH6: D6..D9.
    H,
    /// PJ0, PJ1: D15, D14 (USART3).
    J,
    /// PK0..PK7: A8..A15 (ADC8..15).
    K,
    /// PL0..PL7: Mega D49..D42 (PL3..PL5 = OC5A..OC5C).
    L,
}

impl Port {
    /// The port's letter, as the datasheet (and simavr) names it: `'A'`..`'L'`.
    pub const fn letter(self) -> char {
        match self {
            Port::A => 'A',
            Port::B => 'B',
            Port::C => 'C',
            Port::D => 'D',
            Port::E => 'E',
            Port::F => 'F',
            Port::G => 'G',
            Port::H => 'H',
            Port::J => 'J',
            Port::K => 'K',
            Port::L => 'L',
        }
    }
}

/// One GPIO pin: a port and a bit number 0..=7. Only a descriptor (two
/// bytes, `Copy`); the right to drive it belongs to the board layer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pin {
    port: Port,
    bit: u8,
}

impl Pin {
    /// `bit` is taken modulo 8.
    pub const fn new(port: Port, bit: u8) -> Pin {
        Pin { port, bit: bit & 7 }
    }

    /// The pin's port.
    pub const fn port(self) -> Port {
        self.port
    }

    /// The pin's bit in its port, 0..=7.
    pub const fn bit(self) -> u8 {
        self.bit
    }

    /// The ADC channel on this pin: PF0..PF7 are ADC0..7 (A0..A7), PK0..PK7
    /// are ADC8..15 (A8..A15).
    pub const fn adc_channel(self) -> Option<u8> {
        match self.port {
            Port::F => Some(self.bit),
            Port::K => Some(8 + self.bit),
            _ => None,
        }
    }
}

/// Arduino Mega 2560 names of the pins the UNO-form TFT shield and the servos
/// use.
pub mod mega {
    use super::{Pin, Port};

    /// A0 = PF0: LCD_RD.
    pub const A0: Pin = Pin::new(Port::F, 0);
    /// A1 = PF1: LCD_WR.
    pub const A1: Pin = Pin::new(Port::F, 1);
    /// A2 = PF2: LCD_RS (command/data).
    pub const A2: Pin = Pin::new(Port::F, 2);
    /// A3 = PF3: LCD_CS.
    pub const A3: Pin = Pin::new(Port::F, 3);
    /// A4 = PF4: LCD_RST.
    pub const A4: Pin = Pin::new(Port::F, 4);
    /// D2 = PE4: LCD_D2.
    pub const D2: Pin = Pin::new(Port::E, 4);
    /// D3 = PE5: LCD_D3.
    pub const D3: Pin = Pin::new(Port::E, 5);
    /// D4 = PG5: LCD_D4.
    pub const D4: Pin = Pin::new(Port::G, 5);
    /// D5 = PE3: LCD_D5.
    pub const D5: Pin = Pin::new(Port::E, 3);
    /// D6 = PH3: LCD_D6.
    pub const D6: Pin = Pin::new(Port::H, 3);
    /// D7 = PH4: LCD_D7.
    pub const D7: Pin = Pin::new(Port::H, 4);
    /// D8 = PH5: LCD_D0.
    pub const D8: Pin = Pin::new(Port::H, 5);
    /// D9 = PH6: LCD_D1.
    pub const D9: Pin = Pin::new(Port::H, 6);
    /// D11 = PB5 (OC1A): the gripper servo. On the UNO the shield's D10..D13
    /// are its microSD card's SPI (SS, MOSI, MISO, SCK); on the Mega those
    /// header pins are PB4..PB7, not the SPI port (PB0..PB3), so the card
    /// cannot work there and, with no card in the socket, the pins are
    /// free. D11 (the card's MOSI, an input on the shield side) is driven by
    /// nothing on the shield, unlike D12 (MISO, which a card drives); D13
    /// (PB7) carries the board's LED.
    pub const D11: Pin = Pin::new(Port::B, 5);
    /// D22 = PA0: the assistive switch's input (pull-up; closed = low). The
    /// first pin of the Mega's end header, which no UNO-form shield covers;
    /// port A carries nothing else here.
    pub const D22: Pin = Pin::new(Port::A, 0);
    /// D44 = PL5 (OC5C): the elbow servo.
    pub const D44: Pin = Pin::new(Port::L, 5);
    /// D45 = PL4 (OC5B): the shoulder servo.
    pub const D45: Pin = Pin::new(Port::L, 4);
    /// D46 = PL3 (OC5A): the base servo.
    pub const D46: Pin = Pin::new(Port::L, 3);

    /// LCD read strobe (active low).
    pub const LCD_RD: Pin = A0;
    /// LCD write strobe (active low; data latched on the rising edge).
    pub const LCD_WR: Pin = A1;
    /// LCD register select: low = command, high = data.
    pub const LCD_RS: Pin = A2;
    /// LCD chip select (active low).
    pub const LCD_CS: Pin = A3;
    /// LCD reset (active low).
    pub const LCD_RST: Pin = A4;
    /// LCD data bits D0..D7 in bit order.
    pub const LCD_DATA: [Pin; 8] = [D8, D9, D2, D3, D4, D5, D6, D7];

    /// The servo signal pins in joint order (base, shoulder, elbow): Timer5's
    /// OC5A, OC5B, OC5C.
    pub const SERVOS: [Pin; 3] = [D46, D45, D44];
    /// The gripper servo's signal pin: Timer1's OC1A.
    pub const GRIPPER: Pin = D11;
    /// The assistive switch (issue #20 §4).
    pub const SWITCH: Pin = D22;
}

/// Which shield pins carry the resistive panel's four electrodes. Shields
/// differ (docs/hardware.md); X− and Y+ must be analog pins, since they are the ones
/// read by the ADC.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PanelPinout {
    /// X+ electrode.
    pub xp: Pin,
    /// X− electrode (analog: the Y position and z1 are read here).
    pub xm: Pin,
    /// Y+ electrode (analog: the X position and z2 are read here).
    pub yp: Pin,
    /// Y− electrode.
    pub ym: Pin,
}

impl PanelPinout {
    /// (a) XP = D8, XM = A2, YP = A3, YM = D9: the firmware's default.
    pub const A: PanelPinout = PanelPinout { xp: mega::D8, xm: mega::A2, yp: mega::A3, ym: mega::D9 };
    /// (b) XP = D6, XM = A2, YP = A1, YM = D7.
    pub const B: PanelPinout = PanelPinout { xp: mega::D6, xm: mega::A2, yp: mega::A1, ym: mega::D7 };
    /// (c) XP = D7, XM = A1, YP = A2, YM = D6.
    pub const C: PanelPinout = PanelPinout { xp: mega::D7, xm: mega::A1, yp: mega::A2, ym: mega::D6 };
}
