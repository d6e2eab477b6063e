//! The touch screen, when the app runs one (`AppParams::screen`): a confirmed
//! touch is routed by what the screen shows (the map sends the arm, STOP and
//! RESUME latch, the speed buttons set the preset, More and Back turn the
//! page, Undo is `undo`, a pose button is `pose go <n>`, Grip `grip open|close`, the Line
//! toggle `path line|joint` and the Lift toggle `lift 0.20|off` through the
//! same app paths as the serial commands, Calibrate starts the crosshair
//! flow), and the app draws its state through the UI after each frame.
//! What the carer lock hides does nothing (`access.rs`), and in carer mode
//! a pose button held 2 s and confirmed saves the pose held now.
//! Without a screen the whole panel is the workspace, as in the paper.

use crate::config::settings::{PathMode, PressSettings, SpeedPreset};
use crate::config::store;
use crate::geometry::pose::ArmGeometry;
use crate::protocol::command::PoseCmd;
use crate::seam::SerialPort;
use crate::seam::Storage;
use crate::touch::filter::TouchPoint;
use crate::ui::{
    self, CalibrationEvent, CalibrationFlow, Canvas, DrawBudget, Drawn, Hit, Layout, Page, Redrawn, Ui, UiConfig,
    UiModel, UiState, Unlimited,
};

use super::poses::PoseDone;
use super::refusal::Refusal;
use super::text::Line;
use super::{Answer, App, State};

/// What the screen shows and how far the calibration flow has got.
pub(super) struct Screen {
    pub(super) ui: Ui,
    pub(super) calibration: Option<CalibrationFlow>,
    /// The last point touched on the map (workspace coordinates).
    pub(super) touched: Option<(f32, f32)>,
    /// Why the last map touch was refused, until the next accepted one.
    pub(super) refusal: Option<ui::Refusal>,
    /// The button set shown; changed only by the page key (see
    /// `ui::layout`).
    pub(super) page: Page,
    /// The candidate under a finger on the map: workspace point and reach
    /// verdict (`press.rs`).
    pub(super) preview: Option<(f32, f32, bool)>,
    /// The raw centre the preview's verdict was worked out for.
    preview_raw: Option<TouchPoint>,
}

impl Screen {
    pub(super) fn new(reach: &UiConfig) -> Screen {
        Screen {
            ui: Ui::new(reach),
            calibration: None,
            touched: None,
            refusal: None,
            page: Page::Main,
            preview: None,
            preview_raw: None,
        }
    }
}

/// What a confirmed touch did on the screen, for its line.
#[derive(Debug, Clone, Copy, PartialEq)]
enum ScreenEvent {
    Nothing,
    Map(Result<(), Refusal>),
    CalSaved(Option<u16>),
    CalCancelled,
    Stop,
    Resume,
    Speed(SpeedPreset),
    Calibrate(Result<(), Refusal>),
    Page(Page),
    /// A pose button refused at once (a refusal, or an empty slot: `None`).
    Pose(u8, Option<Refusal>),
    /// A carer's confirmed pose save: the sequence number, or the refusal
    /// (`None`: the EEPROM save failed).
    PoseSave(u8, Result<u16, Option<Refusal>>),
    Grip(Refusal),
    /// Undo refused at once (STOP latched, nothing to undo).
    Undo(Refusal),
    /// The Line toggle: the mode set, or the refusal of `path line`.
    Path(Result<PathMode, Refusal>),
    /// The Lift toggle: the height set (`None`: off), or the refusal.
    Lift(Result<Option<u8>, Refusal>),
}

/// The height the Lift toggle sets, hundredths of a workspace unit: a fixed
/// 0.20 (the config keeps no height while the lift is off, and a height the
/// screen chose by itself would be one nobody set). Other heights are set
/// over serial (`lift <h>`); the toggle then shows on and turns it off.
pub const SCREEN_LIFT_CENTI: u8 = 20;

/// The arm's reach drawn on the map: the IK annulus divided by the scale.
pub(super) fn reach(geo: &ArmGeometry<f32>) -> UiConfig {
    UiConfig { reach_min: geo.links.r_min() / geo.k, reach_max: geo.links.r_max() / geo.k }
}

/// Raw counts the candidate moves before its verdict is worked out again.
const PREVIEW_STEP: u16 = 3;

impl App {
    /// Shows (or clears) the candidate under the finger.
    pub(super) fn screen_preview(&mut self, p: Option<(f32, f32, bool)>) {
        self.screen.preview = p;
        if p.is_none() {
            self.screen.preview_raw = None;
        }
    }

    /// The candidate at raw centre `c` and its reach verdict (the pose and
    /// the joint limits, as a commit would check them; worked out again only
    /// when the centre moved).
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn screen_candidate(&mut self, c: &TouchPoint) {
        if let Some(o) = self.screen.preview_raw {
            if o.x.abs_diff(c.x) < PREVIEW_STEP && o.y.abs_diff(c.y) < PREVIEW_STEP {
                return;
            }
        }
        self.screen.preview_raw = Some(*c);
        self.screen.preview = match self.raw_to_panel(c) {
            Ok((x_p, y_p)) => {
                let ok = match self.point_to_target(c, x_p, y_p) {
                    Ok((angles, _)) => self.within_limits(&angles),
                    Err(_) => false,
                };
                Some((x_p, y_p, ok))
            }
            Err(_) => None,
        };
    }

    /// A contact cancelled: nothing moves and the screen says so.
    pub(super) fn screen_cancelled(&mut self) {
        self.screen.refusal = Some(ui::Refusal::Cancelled);
    }

    /// A second contact: "Lift your hand".
    pub(super) fn screen_hand(&mut self) {
        self.screen.preview = None;
        self.screen.preview_raw = None;
        self.screen.refusal = Some(ui::Refusal::Hand);
    }

    /// RESUME held long enough.
    pub(super) fn screen_resumed(&mut self) {
        self.screen.refusal = None;
    }

    /// A confirmed touch in screen mode.
    pub(super) fn screen_touch<E: Storage, U: SerialPort>(&mut self, p: &TouchPoint, storage: &mut E, serial: &mut U) {
        let event = self.screen_event(p, storage);
        if event != ScreenEvent::Nothing {
            self.report_screen(serial, p, &event);
        }
    }

    /// What a confirmed touch does on the screen.
    fn screen_event<E: Storage>(&mut self, p: &TouchPoint, storage: &mut E) -> ScreenEvent {
        let plate = self.press.contact.plate();
        if let Some(flow) = self.screen.calibration.as_mut() {
            return match flow.feed(p.x, p.y, plate) {
                Some(CalibrationEvent::Done(cal)) => {
                    let mut next = self.config;
                    next.touch = cal;
                    // The settings' page's values (started from these), and
                    // the panel's ratio the crosshair touches measured (0:
                    // the second-contact check off).
                    next.press = PressSettings { plate: flow.plate(), ..flow.settings().unwrap_or(next.press) };
                    self.screen.calibration = None;
                    self.screen.ui.invalidate();
                    let saved = self.save_config(storage, &next).ok();
                    if saved.is_some() {
                        self.config = next;
                    }
                    ScreenEvent::CalSaved(saved)
                }
                Some(CalibrationEvent::Cancelled) => {
                    self.screen.calibration = None;
                    self.screen.ui.invalidate();
                    ScreenEvent::CalCancelled
                }
                None => ScreenEvent::Nothing,
            };
        }
        let hit = match self.raw_to_panel(p) {
            Ok((x, y)) => self.screen.ui.hit_panel(x, y),
            Err(_) => None,
        };
        self.screen_hit(hit, p, storage)
    }

    /// A press on the switch's scan (`switch.rs`): what a touch on `hit`
    /// does (`p`: the raw reading of that place), and its line.
    pub(super) fn screen_press<E: Storage, U: SerialPort>(
        &mut self,
        hit: Hit,
        p: &TouchPoint,
        storage: &mut E,
        serial: &mut U,
    ) {
        let event = self.screen_hit(Some(hit), p, storage);
        if event != ScreenEvent::Nothing {
            self.report_screen(serial, p, &event);
        }
    }

    /// What a confirmed touch on `hit` does (the touch's raw reading `p`).
    fn screen_hit<E: Storage>(&mut self, hit: Option<Hit>, p: &TouchPoint, storage: &mut E) -> ScreenEvent {
        // What the lock hides now does nothing, even if the glass has not
        // caught up yet.
        let hidden = self.hidden_now();
        let hit = hit.filter(|h| !ui::hides(hidden, h));
        let confirm = self.take_confirm();
        match hit {
            Some(Hit::Map { x_p, y_p }) => {
                self.screen.touched = Some((x_p, y_p));
                let r = self.move_to_point(p, x_p, y_p);
                self.screen.refusal = r.err().map(|e| self.ui_refusal(e, x_p, y_p));
                if r.is_ok() {
                    // Answered once planned (`finish_plan`).
                    self.answer_due(Answer::Screen(*p, x_p, y_p));
                    return ScreenEvent::Nothing;
                }
                ScreenEvent::Map(r)
            }
            Some(Hit::Stop) => {
                self.stop();
                ScreenEvent::Stop
            }
            Some(Hit::Resume) => {
                self.resume();
                self.screen.refusal = None;
                ScreenEvent::Resume
            }
            Some(Hit::Speed(s)) => {
                self.config.speed = s;
                ScreenEvent::Speed(s)
            }
            Some(Hit::Calibrate) if self.is_moving() => {
                self.screen.refusal = Some(ui::Refusal::Busy);
                ScreenEvent::Calibrate(Err(Refusal::Busy))
            }
            Some(Hit::Calibrate) => {
                // Measured again once the finger is lifted: the shield may have changed.
                self.probe_wanted = true;
                let flow = CalibrationFlow::new(self.config.touch, self.screen.ui.layout());
                // The touch settings' page, unless the carer lock hides them.
                let touch_hidden = hidden & crate::config::access::item::TOUCH != 0;
                self.screen.calibration = Some(if touch_hidden { flow } else { flow.with_settings(self.config.press) });
                ScreenEvent::Calibrate(Ok(()))
            }
            Some(Hit::Page) => {
                self.screen.page = self.screen.page.next();
                ScreenEvent::Page(self.screen.page)
            }
            Some(Hit::Pose(n)) if confirm == Some(n) => self.screen_pose_save(n, storage),
            Some(Hit::Pose(n)) => self.screen_pose(n, storage),
            Some(Hit::Grip) => match self.screen_grip() {
                // Answered once planned (`finish_grip`).
                Ok(()) => {
                    self.screen.refusal = None;
                    ScreenEvent::Nothing
                }
                Err(e) => {
                    self.screen.refusal = Some(self.ui_refusal(e, 0.0, 0.0));
                    ScreenEvent::Grip(e)
                }
            },
            Some(Hit::Undo) => match self.undo() {
                // Answered once planned (`finish_plan`).
                Ok(()) => {
                    self.screen.refusal = None;
                    self.answer_due(Answer::ScreenUndo);
                    ScreenEvent::Nothing
                }
                Err(e) => {
                    self.screen.refusal = Some(self.ui_refusal(e, 0.0, 0.0));
                    ScreenEvent::Undo(e)
                }
            },
            Some(Hit::Line) => self.screen_toggle(false),
            Some(Hit::Lift) => self.screen_toggle(true),
            // Guard bands and gaps between buttons: deliberately nothing
            // (the carer's places act at the lift-off: `press.rs`).
            Some(Hit::Carer(_)) | None => ScreenEvent::Nothing,
        }
    }

    /// The Line toggle (`lift` false) or the Lift toggle: exactly `path
    /// line|joint` or `lift 0.20|off` (same refusal when the other is on).
    /// Out of line: the touch's deepest path (a map point's plan) does not
    /// carry its frame.
    #[inline(never)] // avr-trap: frame-size
    fn screen_toggle(&mut self, lift: bool) -> ScreenEvent {
        if lift {
            let h = if self.config.lift_centi.is_some() { None } else { Some(SCREEN_LIFT_CENTI) };
            ScreenEvent::Lift(self.set_lift(h).map(|()| h))
        } else {
            let m = if self.config.path == PathMode::Line { PathMode::Joint } else { PathMode::Line };
            ScreenEvent::Path(self.set_path(m).map(|()| m))
        }
    }

    /// A pose button: exactly `pose go <n>` (same checks, planner and
    /// refusals), answered once planned (`finish_plan`).
    #[inline(never)] // avr-trap: frame-size
    fn screen_pose<E: Storage>(&mut self, n: u8, storage: &mut E) -> ScreenEvent {
        match self.pose(PoseCmd::Go(n), storage) {
            Ok(PoseDone::Went(_)) => {
                self.screen.refusal = None;
                self.answer_due(Answer::ScreenPose(n));
                ScreenEvent::Nothing
            }
            Ok(_) => ScreenEvent::Pose(n, None),
            Err(e) => {
                self.screen.refusal = Some(self.ui_refusal(e, 0.0, 0.0));
                ScreenEvent::Pose(n, Some(e))
            }
        }
    }

    /// The carer's confirmed save: exactly `pose save <n>`.
    #[inline(never)] // avr-trap: frame-size
    fn screen_pose_save<E: Storage>(&mut self, n: u8, storage: &mut E) -> ScreenEvent {
        let r = match self.pose(PoseCmd::Save(n), storage) {
            Ok(PoseDone::Stored(_, _, Ok(seq))) => Ok(seq),
            Ok(_) => Err(None),
            Err(e) => Err(Some(e)),
        };
        ScreenEvent::PoseSave(n, r)
    }

    /// `info screen pose go <n> …` once a screen pose's move is planned, or
    /// `err screen pose go <n> <reason>`.
    #[inline(never)] // avr-trap: frame-size
    pub(super) fn report_screen_pose<U: SerialPort>(&mut self, serial: &mut U, n: u8, r: Result<(), Refusal>) {
        let mut line = Line::new();
        match r {
            Ok(()) => {
                line.str(t!("info screen pose go")).num(i32::from(n));
                self.describe_move(&mut line, false);
            }
            Err(e) => {
                line.str(t!("err screen pose go")).num(i32::from(n)).word(e.reason());
            }
        }
        self.emit(serial, &mut line);
    }

    /// `info screen undo … left <n>` once a screen Undo's move is planned
    /// (the words of `ok undo`), or `err screen undo <reason>`.
    pub(super) fn report_screen_undo<U: SerialPort>(&mut self, serial: &mut U, r: Result<(), Refusal>) {
        let mut line = Line::new();
        match r {
            Ok(()) => {
                line.str(t!("info screen undo"));
                self.describe_move(&mut line, false);
                line.word(t!("left")).num(i32::from(self.undo.left()));
                if let Some(g) = self.undo.grip_kept() {
                    line.word(t!("grip kept")).bytes(b" ").centi(crate::math::units::rad_to_centideg(g));
                }
            }
            Err(e) => {
                line.str(t!("err screen undo")).word(e.reason());
            }
        }
        self.emit(serial, &mut line);
    }

    /// The line a screen event sends (its buffer is not on the stack while
    /// the touch is planned).
    #[inline(never)] // avr-trap: frame-size
    fn report_screen<U: SerialPort>(&mut self, serial: &mut U, p: &TouchPoint, event: &ScreenEvent) {
        let mut line = Line::new();
        match *event {
            ScreenEvent::Nothing => return,
            ScreenEvent::Map(r) => return self.report_touch(serial, p, r),
            ScreenEvent::CalSaved(Some(seq)) => {
                let p = self.config.press;
                line.str(t!("info cal touch saved seq")).num(i32::from(seq)).str(t!(" plate"));
                super::text::plate_word(&mut line, p.plate);
                line.str(t!(" hold ")).centi(i32::from(p.hold_cs)).str(t!(" repeat "));
                line.centi(i32::from(p.repeat_cs)).str(t!(" radius")).num(i32::from(p.radius));
            }
            ScreenEvent::CalSaved(None) => {
                line.str(t!("err cal touch not saved"));
            }
            ScreenEvent::CalCancelled => {
                line.str(t!("info cal touch cancelled"));
            }
            ScreenEvent::Stop => {
                line.str(t!("info screen stop"));
            }
            ScreenEvent::Resume => {
                line.str(t!("info screen resume"));
            }
            ScreenEvent::Speed(s) => {
                line.str(t!("info screen speed")).word(s.name());
                self.cap_suffix(s, &mut line);
            }
            ScreenEvent::Calibrate(Ok(())) => {
                line.str(t!("info screen calibrate"));
            }
            ScreenEvent::Calibrate(Err(r)) => {
                line.str(t!("err screen calibrate")).word(r.reason());
            }
            ScreenEvent::Page(p) => {
                line.str(match p {
                    Page::Main => t!("info screen page main"),
                    Page::More => t!("info screen page more"),
                    Page::Setup => t!("info screen page setup"),
                });
            }
            ScreenEvent::Pose(n, None) => {
                line.str(t!("err screen pose go")).num(i32::from(n)).str(t!(" empty"));
            }
            ScreenEvent::Pose(n, Some(r)) => return self.report_screen_pose(serial, n, Err(r)),
            ScreenEvent::PoseSave(n, r) => {
                line.str(match r {
                    Ok(_) => t!("info screen pose save"),
                    Err(_) => t!("err screen pose save"),
                });
                line.num(i32::from(n));
                match r {
                    Ok(seq) => line.word(t!("seq")).num(i32::from(seq)),
                    Err(Some(e)) => line.word(e.reason()),
                    Err(None) => line.word(t!("save failed")),
                };
            }
            ScreenEvent::Grip(r) => {
                line.str(t!("err screen grip")).word(r.reason());
            }
            ScreenEvent::Undo(r) => {
                line.str(t!("err screen undo")).word(r.reason());
            }
            ScreenEvent::Path(Ok(m)) => {
                line.str(t!("info screen path")).word(m.name());
            }
            ScreenEvent::Path(Err(r)) => {
                line.str(t!("err screen path line")).word(r.reason());
            }
            ScreenEvent::Lift(Ok(Some(h))) => {
                line.str(t!("info screen lift ")).centi(i32::from(h));
            }
            ScreenEvent::Lift(Ok(None)) => {
                line.str(t!("info screen lift off"));
            }
            ScreenEvent::Lift(Err(r)) => {
                line.str(t!("err screen lift")).word(r.reason());
            }
        }
        self.emit(serial, &mut line);
    }

    /// Whether a confirmed touch would plan a move (a map point, a pose
    /// button or Grip on the screen, or any touch without a screen): in a
    /// busy frame it waits for the next, as a map touch does.
    pub(super) fn touch_plans(&self, p: &TouchPoint) -> bool {
        if !self.params.screen {
            return true;
        }
        let hit = match self.raw_to_panel(p) {
            Ok((x, y)) if self.screen.calibration.is_none() => self.screen.ui.hit_panel(x, y),
            _ => None,
        };
        matches!(hit, Some(Hit::Map { .. } | Hit::Pose(_) | Hit::Grip | Hit::Undo))
    }

    /// The words the screen uses for a refused map point.
    pub(super) fn ui_refusal(&self, r: Refusal, x_p: f32, y_p: f32) -> ui::Refusal {
        match r {
            Refusal::Unreachable | Refusal::Singular => {
                let k = self.geo.k;
                let reach = k * k * (x_p * x_p + y_p * y_p);
                let far = self.geo.links.r_max() * self.geo.links.r_max();
                if reach > far {
                    ui::Refusal::TooFar
                } else {
                    ui::Refusal::TooClose
                }
            }
            Refusal::OutsideCalibration | Refusal::OutsideWorkspace => ui::Refusal::OffMap,
            Refusal::Busy | Refusal::Homing | Refusal::Stopped | Refusal::GripBusy => ui::Refusal::Busy,
            _ => ui::Refusal::JointLimit,
        }
    }

    /// Lays the screen out for the panel found at boot (320×240 until
    /// then); what is on the glass is forgotten, so the next draw is full.
    pub fn set_screen_layout(&mut self, layout: Layout) {
        self.screen.ui = Ui::with_layout(&reach(&self.geo), layout);
        self.screen.calibration = None;
    }

    /// Draws what changed since the last call (everything the first time, and
    /// after the calibration screen). Call between frames: drawing holds the
    /// shared pins, so it must not overlap a touch read.
    pub fn draw_screen<D: Canvas>(&mut self, d: &mut D) -> Result<Redrawn, D::Error> {
        self.draw_screen_sliced(d, &mut Unlimited).map(|r| r.redrawn)
    }

    /// [`App::draw_screen`] within `budget` (what the frame leaves); the rest
    /// is drawn by the next calls.
    pub fn draw_screen_sliced<D: Canvas, B: DrawBudget>(
        &mut self,
        d: &mut D,
        budget: &mut B,
    ) -> Result<Drawn, D::Error> {
        // Not even the model is worked out when the frame has no room left.
        if !budget.may_start() {
            return Ok(Drawn { redrawn: Redrawn(0), finished: false });
        }
        if let Some(flow) = &self.screen.calibration {
            return self.screen.ui.draw_calibration_sliced(flow, d, budget);
        }
        let model = self.ui_model();
        self.screen.ui.draw_sliced(&model, d, budget)
    }

    /// The main screen's content, from the app's state.
    pub fn ui_model(&self) -> UiModel {
        let st = self.status();
        let state = match st.state {
            State::Off | State::Homing => UiState::PowerUp,
            State::Stopped => UiState::Stopped,
            State::Moving => UiState::Moving { progress: f32::from(st.progress) / 100.0 },
            // STOP stays on the screen while a path is checked.
            State::Checking => UiState::Checking,
            State::Paused => UiState::Paused,
            State::Holding => match self.screen.refusal {
                Some(r) => UiState::Refused(r),
                None if st.touch_target.is_none() && st.first_move_pending => UiState::Idle,
                None => UiState::Holding,
            },
        };
        let target = st.touch_target.map(|t| (t.x_p, t.y_p));
        let mut warnings = 0;
        match st.config_warning {
            Some(store::Warning::CopyDamaged) => warnings |= ui::warn::COPY_DAMAGED,
            Some(_) => warnings |= ui::warn::DEFAULT_SETTINGS,
            None => {}
        }
        if st.pulses.is_none() {
            warnings |= ui::warn::SERVOS_OFF;
        }
        if self.wiring_unknown {
            warnings |= ui::warn::TOUCH_WIRING;
        }
        UiModel {
            state,
            preview: self.screen.preview.map(|(x_p, y_p, ok)| ui::Preview { x_p, y_p, ok, ring: self.press.ring }),
            resume: self.resume_ring(),
            touch: self.screen.touched,
            target,
            condition: st.touch_target.map(|t| t.condition),
            alpha: st.touch_target.map_or(f32::NAN, |t| t.alpha),
            joints: st.commanded,
            speed: st.speed,
            hide: self.hidden_now(),
            confirm: self.confirm_slot(),
            warnings,
            page: self.screen.page,
            grip_closed: self.grip_closed(),
            path_line: self.config.path == PathMode::Line,
            lift: self.config.lift_centi.is_some(),
            scan: self.switch_show(),
        }
    }
}
