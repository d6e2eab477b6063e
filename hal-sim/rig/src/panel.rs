//! The touch panel on the simulated chip's pins: which MCU pins carry the
//! panel's terminals (the firmware's wiring), read back from the port
//! registers, fed to the twin's panel model (`twin::panel`), whose voltage
//! becomes what the simulated ADC converts. So the real firmware's touch
//! driver, with its own drive/float/settle/sample sequence, is what is tested.
//! A scripted finger (`hal_sim::finger`) is evaluated at each conversion's
//! own cycle (the moment simavr samples the input).

use crate::avr::{AdcRequest, Pin, PortsSnapshot};
use hal_sim::panel::{Drive, PanelPins, Pin as Terminal, SimPanel};
use touch_arm::seam::pins::PanelPinout;
use touch_arm::touch::filter::ADC_MAX;

/// Which MCU pins carry the panel's terminals, and the ADC channel of each
/// terminal that sits on an analog pin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PanelWiring {
    /// XP's pin and its ADC channel (`None`: a digital pin).
    pub xp: (Pin, Option<u8>),
    /// XM's pin and its ADC channel.
    pub xm: (Pin, Option<u8>),
    /// YP's pin and its ADC channel.
    pub yp: (Pin, Option<u8>),
    /// YM's pin and its ADC channel.
    pub ym: (Pin, Option<u8>),
}

impl PanelWiring {
    /// docs/hardware.md wiring (a): XP = D8 (PH5), XM = A2 (PF2), YP = A3 (PF3), YM = D9 (PH6).
    pub const A: PanelWiring = PanelWiring::of(&PanelPinout::A);
    /// Wiring (b): XP = D6 (PH3), XM = A2 (PF2), YP = A1 (PF1), YM = D7 (PH4).
    pub const B: PanelWiring = PanelWiring::of(&PanelPinout::B);
    /// Wiring (c): XP = D7 (PH4), XM = A1 (PF1), YP = A2 (PF2), YM = D6 (PH3).
    pub const C: PanelWiring = PanelWiring::of(&PanelPinout::C);

    /// A pinout of the firmware's pin map, with the ADC channel of each
    /// terminal on an analog pin.
    pub const fn of(p: &PanelPinout) -> PanelWiring {
        const fn terminal(pin: touch_arm::seam::pins::Pin) -> (Pin, Option<u8>) {
            (Pin::of(pin), pin.adc_channel())
        }
        PanelWiring { xp: terminal(p.xp), xm: terminal(p.xm), yp: terminal(p.yp), ym: terminal(p.ym) }
    }

    /// How the firmware drives each terminal, from the port registers.
    pub fn drives(&self, ports: &PortsSnapshot) -> PanelPins {
        let drive = |pin: Pin| match ports.get(pin.port) {
            Some(p) => match p.driven(pin.bit) {
                Some(true) => Drive::High,
                Some(false) => Drive::Low,
                None if p.pull_up(pin.bit) => Drive::PullUp,
                None => Drive::Float,
            },
            None => Drive::Float,
        };
        PanelPins { xp: drive(self.xp.0), xm: drive(self.xm.0), yp: drive(self.yp.0), ym: drive(self.ym.0) }
    }

    /// The terminal an ADC channel samples, if it is one of the panel's.
    pub fn terminal_on_channel(&self, channel: u8) -> Option<Terminal> {
        [(Terminal::Xp, self.xp.1), (Terminal::Xm, self.xm.1), (Terminal::Yp, self.yp.1), (Terminal::Ym, self.ym.1)]
            .into_iter()
            .find(|(_, ch)| *ch == Some(channel))
            .map(|(t, _)| t)
    }
}

/// The panel as the simulated ADC sees it.
pub struct PanelOnPins {
    /// Which pins carry the terminals.
    pub wiring: PanelWiring,
    /// The twin's panel model behind them.
    pub panel: SimPanel,
}

impl PanelOnPins {
    /// The 10-bit conversion of an ADC request, or `None` when the channel is
    /// not one of the panel's.
    pub fn read(&mut self, req: &AdcRequest<'_>) -> Option<u16> {
        let t = self.wiring.terminal_on_channel(req.channel)?;
        let pins = self.wiring.drives(req.ports);
        self.panel.set_time(req.time_s);
        Some(self.panel.adc(&pins, t))
    }

    /// What an analog pin off the panel reads: its own level when the
    /// firmware drives it or pulls it up, 0 when it floats (nothing else is
    /// wired to it in the model).
    pub fn read_off_panel(req: &AdcRequest<'_>) -> u16 {
        let pin = if req.channel < 8 { Pin::new('F', req.channel) } else { Pin::new('K', req.channel - 8) };
        match req.ports.get(pin.port) {
            Some(p) if p.driven(pin.bit) == Some(true) || p.pull_up(pin.bit) => ADC_MAX,
            _ => 0,
        }
    }
}
