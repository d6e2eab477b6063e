//! What the screen shows, as plain data the app fills in each frame.

use crate::config::settings::SpeedPreset;
use crate::geometry::workspace::Condition;

use super::scan::ScanShow;

/// Why a touched point was not accepted as a target.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Refusal {
    /// Beyond the arm's reach (IK `c > 1`).
    TooFar,
    /// Inside the arm's dead zone near the base (IK `c < −1`).
    TooClose,
    /// The point is off the map (panel edge, out-of-range reading).
    OffMap,
    /// Reachable, but a joint would leave its limits or the plan was rejected.
    JointLimit,
    /// A new target while the arm is moving; STOP first.
    Busy,
    /// The finger lifted off the map, or wandered: nothing moved.
    Cancelled,
    /// A second contact (a palm, a knuckle): nothing moved.
    Hand,
}

/// The candidate under a finger on the map (nothing has moved yet).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Preview {
    /// Workspace point, −1..=1.
    pub x_p: f32,
    /// Workspace height, 0..=1.
    pub y_p: f32,
    /// The arm can reach it.
    pub ok: bool,
    /// The ring's fill over the hold, 0..=4.
    pub ring: u8,
}

/// Which row of buttons the screen shows under the status lines (see
/// [`crate::ui::layout`]): STOP, the headline and the status lines are on
/// every page; the page key turns Main → More → Setup → Main.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Page {
    /// Slow | Mid | Fast | Undo | More.
    #[default]
    Main,
    /// The saved poses 1–4 | More.
    More,
    /// Grab (Open) | Cal | Line | Lift | Back.
    Setup,
}

impl Page {
    /// The page the page key turns to.
    pub const fn next(self) -> Page {
        match self {
            Page::Main => Page::More,
            Page::More => Page::Setup,
            Page::Setup => Page::Main,
        }
    }
}

/// The arm's state as the user should understand it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum UiState {
    /// Starting up: settings not loaded or servos not yet placed.
    PowerUp,
    /// Ready, waiting for a touch.
    Idle,
    /// A line's, circle's or lift's check runs before the move starts: the
    /// arm holds still, and says so (a "Moving" that does not move would
    /// invite a second tap).
    Checking,
    /// On the way.
    Moving {
        /// Share of the planned duration elapsed, 0..=1.
        progress: f32,
    },
    /// Arrived; the servos hold the pose.
    Holding,
    /// Hold to run: the lift brought the arm to rest on its way; a held
    /// finger goes on.
    Paused,
    /// The user pressed STOP: motion halted where it was.
    Stopped,
    /// The last touch was refused.
    Refused(Refusal),
}

/// Problems worth a line on the screen, each a bit the app sets; the highest
/// set bit is shown, so the most important is highest.
pub mod warn {
    /// One stored copy of the settings is damaged; the other is in use (the
    /// next save repairs it).
    pub const COPY_DAMAGED: u8 = 1 << 0;
    /// EEPROM settings were invalid; defaults are in use.
    pub const DEFAULT_SETTINGS: u8 = 1 << 1;
    /// Servo outputs are off (limp arm).
    pub const SERVOS_OFF: u8 = 1 << 2;
    /// The panel's wiring probe identified no known wiring: touches are not
    /// read (the serial line still works). Above the others, since it is
    /// why touching the screen does nothing.
    pub const TOUCH_WIRING: u8 = 1 << 3;
}

/// Everything the main screen shows. Angles are radians (as the pose and
/// plan produce them); points are workspace coordinates `(x_p, y_p)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UiModel {
    /// What the arm is doing, as the headline says it.
    pub state: UiState,
    /// The candidate under a finger on the map.
    pub preview: Option<Preview>,
    /// RESUME's countdown while it is held, 0..=4 (shown while stopped).
    pub resume: Option<u8>,
    /// The last touched point on the map.
    pub touch: Option<(f32, f32)>,
    /// The point the arm is going to or holding.
    pub target: Option<(f32, f32)>,
    /// Condition (zone) and base direction α of the touched point.
    pub condition: Option<Condition>,
    /// Base direction α of that point, radians (shown when `condition` is set).
    pub alpha: f32,
    /// Base, shoulder, elbow angles now (radians); non-finite shows `--`.
    pub joints: [f32; 3],
    /// The preset button shown pressed.
    pub speed: SpeedPreset,
    /// The carer lock's hidden items now (`config::access::item` bits; 0
    /// in carer mode): their buttons are blank and do nothing.
    pub hide: u8,
    /// The pose slot (1..=4) whose carer save waits for its confirming tap
    /// (its button says Save); 0 for none.
    pub confirm: u8,
    /// [`warn`] bits.
    pub warnings: u8,
    /// The button set shown.
    pub page: Page,
    /// The gripper is closed or closing (the Grip button then says Open).
    pub grip_closed: bool,
    /// Targets are reached along a straight line (`path line`): the Line
    /// toggle shown on.
    pub path_line: bool,
    /// Joint moves pass a via pose (`lift <h>`): the Lift toggle shown on.
    pub lift: bool,
    /// The switch scan's line, target phase or highlighted item
    /// ([`crate::ui::scan`]); `None` while the switch is off or idle.
    pub scan: Option<ScanShow>,
}

impl UiModel {
    /// Power-up screen: nothing touched, angles unknown.
    pub const fn new(speed: SpeedPreset) -> Self {
        Self {
            state: UiState::PowerUp,
            preview: None,
            resume: None,
            touch: None,
            target: None,
            condition: None,
            alpha: 0.0,
            joints: [f32::NAN; 3],
            speed,
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
}
