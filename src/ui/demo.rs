//! A fixed script of screens: the `ui-demo` firmware draws it on the chip
//! (through the real ILI9341 bus driver) and the host test replays it into a
//! framebuffer, so the decoded bus picture can be compared pixel for pixel
//! and each draw timed in cycles.

use super::calibration::{cal_point, CalibrationFlow};
use super::layout::Layout;
use super::model::{warn, Page, Refusal, UiModel, UiState};
use super::screen::UiConfig;
use crate::config::settings::SpeedPreset;
use crate::geometry::workspace::Condition;
use crate::touch::map::Calibration;

/// The map's shading for the script: reachable between radius 0.3 and 0.9.
pub const CONFIG: UiConfig = UiConfig { reach_min: 0.3, reach_max: 0.9 };

/// Steps of the script.
pub const STEPS: u8 = 19;

/// What step `k` draws.
pub enum Screen {
    /// The main screen showing this model.
    Main(UiModel),
    /// The calibration screen in this state.
    Calibration(CalibrationFlow),
}

fn moving(progress: f32) -> UiModel {
    UiModel {
        state: UiState::Moving { progress },
        preview: None,
        resume: None,
        touch: Some((0.4, 0.5)),
        target: Some((0.4, 0.5)),
        condition: Some(Condition::C2),
        // atan2(0.5, 0.4) = 51.34°.
        alpha: 0.896_055,
        joints: [0.896_055, 0.7, 1.4],
        speed: SpeedPreset::Normal,
        hide: 0,
        confirm: 0,
        warnings: 0,
        page: Page::Main,
        grip_closed: false,
        path_line: false,
        lift: false,
        scan: None,
    }
}

/// Step `k` (0..STEPS): a full first draw, a move with progress, arrival,
/// a refused touch, STOP, a preset change with a warning, two calibration
/// screens, a full redraw back on the main screen, the Setup page (Grip,
/// Cal, Line on) and its Grip button turning to Open with Line off and Lift
/// on, and the main page again.
pub fn screen(k: u8, lay: &Layout) -> Screen {
    let mut m = moving(0.0);
    match k {
        0..=8 => m.state = UiState::Moving { progress: f32::from(k) / 8.0 },
        9 => m.state = UiState::Holding,
        10..=12 => {
            m.state = UiState::Refused(Refusal::TooFar);
            m.touch = Some((-0.6, 0.7));
            m.condition = Some(Condition::C4);
            // atan2(0.7, −0.6) = 130.6°.
            m.alpha = 2.279_423;
            if k >= 11 {
                m.state = UiState::Stopped;
            }
            if k >= 12 {
                m.speed = SpeedPreset::Fast;
                m.warnings = warn::SERVOS_OFF;
            }
        }
        13 | 14 => {
            let cal = Calibration::DEFAULT;
            let mut flow = CalibrationFlow::new(cal, lay);
            if k == 14 {
                if let Some(raw) = cal_point(lay, 0).and_then(|(x, y)| cal.unmap::<f32>(x, y).ok()) {
                    flow.feed(raw.x, raw.y, 0);
                }
            }
            return Screen::Calibration(flow);
        }
        _ => {
            m.state = UiState::Idle;
            m.touch = None;
            m.target = None;
            m.condition = None;
            if k == 16 || k == 17 {
                m.page = Page::Setup;
                m.grip_closed = k == 17;
                // Both toggles in both states: a full draw, then two toggle
                // repaints.
                m.path_line = k == 16;
                m.lift = k == 17;
            }
        }
    }
    Screen::Main(m)
}
