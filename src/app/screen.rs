//! The touch screen, when the app runs one (`AppParams::screen`): a confirmed
//! touch is routed by what the screen shows (the map sends the arm, STOP and
//! RESUME latch, the speed buttons set the preset, Calibrate starts the
//! crosshair flow), and the app draws its state through the UI after each
//! frame. Without a screen the whole panel is the workspace, as in the paper.

use crate::config::store;
use crate::seam::SerialPort;
use crate::seam::Storage;
use crate::touch::filter::TouchPoint;
use crate::ui::{
    self, CalibrationEvent, CalibrationFlow, Canvas, Hit, Layout, Redrawn, Ui, UiConfig, UiModel, UiState,
};

use super::refusal::Refusal;
use super::text::Line;
use super::{App, State};

/// What the screen shows and how far the calibration flow has got.
pub(super) struct Screen {
    pub(super) ui: Ui,
    pub(super) calibration: Option<CalibrationFlow>,
    /// The last point touched on the map (workspace coordinates).
    pub(super) touched: Option<(f32, f32)>,
    /// Why the last map touch was refused, until the next accepted one.
    pub(super) refusal: Option<ui::Refusal>,
}

impl Screen {
    pub(super) fn new(reach: &UiConfig) -> Screen {
        Screen { ui: Ui::new(reach), calibration: None, touched: None, refusal: None }
    }
}

/// The arm's reach drawn on the map: the IK annulus divided by the scale.
pub(super) fn reach(l2: f32, l3: f32, k: f32) -> UiConfig {
    let d = l2 - l3;
    UiConfig { reach_min: if d < 0.0 { -d } else { d } / k, reach_max: (l2 + l3) / k }
}

impl App {
    /// A confirmed touch in screen mode.
    pub(super) fn screen_touch<E: Storage, U: SerialPort>(&mut self, p: &TouchPoint, storage: &mut E, serial: &mut U) {
        let mut line = Line::new();
        if let Some(flow) = self.screen.calibration.as_mut() {
            match flow.feed(p.x, p.y) {
                Some(CalibrationEvent::Done(cal)) => {
                    self.screen.calibration = None;
                    self.screen.ui.invalidate();
                    let mut next = self.config;
                    next.touch = cal;
                    match store::save(storage, &next) {
                        Ok(seq) => {
                            self.config = next;
                            line.str(t!("info cal touch saved seq")).num(i32::from(seq));
                        }
                        Err(_) => {
                            line.str(t!("err cal touch not saved"));
                        }
                    }
                }
                Some(CalibrationEvent::Cancelled) => {
                    self.screen.calibration = None;
                    self.screen.ui.invalidate();
                    line.str(t!("info cal touch cancelled"));
                }
                None => return,
            }
            serial.write(line.finish());
            return;
        }
        let hit = match self.raw_to_panel(p) {
            Ok((x, y)) => self.screen.ui.hit_panel(x, y),
            Err(_) => None,
        };
        match hit {
            Some(Hit::Map { x_p, y_p }) => {
                self.screen.touched = Some((x_p, y_p));
                match self.move_to_point(p, x_p, y_p) {
                    Ok(()) => {
                        self.screen.refusal = None;
                        line.str(t!("info touch")).num(i32::from(p.x)).num(i32::from(p.y));
                        self.describe_move(&mut line, true);
                    }
                    Err(r) => {
                        self.screen.refusal = Some(self.ui_refusal(r, x_p, y_p));
                        line.str(t!("err touch")).num(i32::from(p.x)).num(i32::from(p.y)).word(r.reason());
                    }
                }
            }
            Some(Hit::Stop) => {
                self.stop();
                line.str(t!("info screen stop"));
            }
            Some(Hit::Resume) => {
                self.resume();
                self.screen.refusal = None;
                line.str(t!("info screen resume"));
            }
            Some(Hit::Speed(s)) => {
                self.config.speed = s;
                line.str(t!("info screen speed")).word(s.name());
            }
            Some(Hit::Calibrate) => {
                if self.is_moving() {
                    self.screen.refusal = Some(ui::Refusal::Busy);
                    line.str(t!("err screen calibrate")).word(Refusal::Busy.reason());
                } else {
                    self.screen.calibration = Some(CalibrationFlow::new(self.config.touch, self.screen.ui.layout()));
                    line.str(t!("info screen calibrate"));
                }
            }
            // Guard bands and gaps between buttons: deliberately nothing.
            None => return,
        }
        serial.write(line.finish());
    }

    /// The words the screen uses for a refused map point.
    fn ui_refusal(&self, r: Refusal, x_p: f32, y_p: f32) -> ui::Refusal {
        match r {
            Refusal::Unreachable | Refusal::Singular => {
                let k = self.params.k;
                let reach = k * k * (x_p * x_p + y_p * y_p);
                let far = (self.params.l2 + self.params.l3) * (self.params.l2 + self.params.l3);
                if reach > far {
                    ui::Refusal::TooFar
                } else {
                    ui::Refusal::TooClose
                }
            }
            Refusal::OutsideCalibration | Refusal::OutsideWorkspace => ui::Refusal::OffMap,
            Refusal::Busy | Refusal::Homing | Refusal::Stopped => ui::Refusal::Busy,
            _ => ui::Refusal::JointLimit,
        }
    }

    /// Lays the screen out for the panel found at boot (320×240 until
    /// then); what is on the glass is forgotten, so the next draw is full.
    pub fn set_screen_layout(&mut self, layout: Layout) {
        let reach = reach(self.params.l2, self.params.l3, self.params.k);
        self.screen.ui = Ui::with_layout(&reach, layout);
        self.screen.calibration = None;
    }

    /// Draws what changed since the last call (everything the first time, and
    /// after the calibration screen). Call between frames: drawing holds the
    /// shared pins, so it must not overlap a touch read.
    pub fn draw_screen<D: Canvas>(&mut self, d: &mut D) -> Result<Redrawn, D::Error> {
        if let Some(flow) = &self.screen.calibration {
            return self.screen.ui.draw_calibration(flow, d);
        }
        let model = self.ui_model();
        self.screen.ui.draw(&model, d)
    }

    /// The main screen's content, from the app's state.
    pub fn ui_model(&self) -> UiModel {
        let st = self.status();
        let state = match st.state {
            State::Off | State::Homing => UiState::PowerUp,
            State::Stopped => UiState::Stopped,
            State::Moving => UiState::Moving { progress: f32::from(st.progress) / 100.0 },
            State::Holding => match self.screen.refusal {
                Some(r) => UiState::Refused(r),
                None if st.touch_target.is_none() && st.first_move_pending => UiState::Idle,
                None => UiState::Holding,
            },
        };
        let target = st.touch_target.map(|t| (t.x_p, t.y_p));
        let mut warnings = 0;
        if st.config_warning.is_some() {
            warnings |= ui::warn::DEFAULT_SETTINGS;
        }
        if st.pulses.is_none() {
            warnings |= ui::warn::SERVOS_OFF;
        }
        UiModel {
            state,
            touch: self.screen.touched,
            target,
            condition: st.touch_target.map(|t| t.condition),
            alpha: st.touch_target.map_or(f32::NAN, |t| t.alpha),
            joints: st.commanded,
            speed: st.speed,
            warnings,
        }
    }
}
