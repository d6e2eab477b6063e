//! The product's app: a pure state machine over the seam traits, stepped once
//! per 20 ms servo PWM period.
//!
//! # How the firmware drives it
//! ```text
//! let mut app = App::new(&AppParams::DEFAULT)?;
//! loop {
//!     wait for the Timer5 period start;          // 50 Hz, aligned with the PWM
//!     app.set_switch(switch pin is low);          // the assistive switch
//!     app.frame(&mut Io { panel, servos, clock, storage, serial });
//!     draw(app.status());                         // the display, never during frame()
//! }
//! ```
//! `frame` samples the touch panel itself (the UI must not draw meanwhile:
//! the panel shares pins with the LCD), so a display draws between frames from
//! the read-only [`Status`] snapshot.
//!
//! # One frame, in order
//! 0. Catch-up: a frame that starts late, because the one before ran past
//!    the period end ([`App::frame_was_late`]), does no heavy thing: no serial
//!    line, no panel read, no plan (a `pose go`'s gripper, due after the
//!    arm's plan, waits too). It steps the motion and writes the pulses
//!    early, so work that ran long (a re-plan's doublings, which cannot be
//!    cut short; BENCHMARKS.md) never pushes the next pulses past their
//!    period, however the following frames are loaded.
//! 1. Serial: first a one-byte STOP (`!`) the port flagged is latched and
//!    answered, in every frame (catch-up ones too). Then at most
//!    `serial_bytes_per_frame` bytes, at most one complete line, only while
//!    the port has room for the longest reply; one `ok …`/`err …` line (see
//!    `serial.rs`). A partial line idle for `line_timeout_ms` is dropped and
//!    answered `err line timeout (no line ending?)`.
//! 2. Touch: one filtered read feeds the contact (`press.rs`): STOP latches
//!    on contact; a map point or a button acts when the finger lifts after
//!    the hold, at the contact's robust centre (`mode hold`: a map point as
//!    soon as the hold is reached, and the move runs while it stays down,
//!    `hold.rs`). A frame does one heavy
//!    thing: after a serial line the panel is not read and a lift-off that
//!    would plan waits a frame.
//! 3. Motion: the setpoint of every joint at t = frames since the plan × 20 ms
//!    (exact, no clock drift); the move ends exactly on its target at tₛ. A
//!    held move once released (`mode hold`) runs on its planned stop's
//!    clock instead ([`crate::motion::stop`]).
//! 4. Servos: every setpoint goes through [`ServoMap::angle_to_pulse`]
//!    (angle and pulse limits), then `set_pulses`. A non-finite setpoint keeps
//!    the previous pulse and latches STOP (`Refusal::Fault`).
//!    Then the gripper: its angle at its own plan's t and its pulse
//!    (`grip.rs`), after the joints' pulses so it does not delay them.
//! 5. Plan: a target accepted in 1 or 2 is planned now, from the pose just
//!    commanded, and answered (`ok move`, `info touch …`); the move starts in
//!    the next frame. A re-plan (a target while moving) that finds too
//!    little of the period left waits for the next frame, which takes no
//!    other heavy thing, and its search stops refining where the period's
//!    time does (`machine.rs`, `finish_plan`). A plan can take most of a frame; coming after the
//!    pulses, it cannot delay them. A path target (`path line`, `circle`)
//!    only has its check set up here.
//! 6. Path check: a pending path move's plan-time check runs as many units
//!    as the PWM period still has room for at their worst (none in a
//!    catch-up frame), and answers once it decides (`path_move`).
//! 7. Telemetry (`log on`): `t <ms> <base> <shoulder> <elbow> <us> <us> <us>
//!    <grip> <us>`, angles in centidegrees; or (`log plot`)
//!    `base:<deg>,shoulder:<deg>,elbow:<deg>,grip:<deg>` with two decimals,
//!    for the Arduino Serial Plotter.
//! 8. One line of a multi-line reply (`cal show`), if pending and the frame
//!    is not busy.
//!
//! # States
//! - **off**: before the first frame; that frame loads the configuration
//!   (two EEPROM copies, defaults and a `warn` line if neither is valid) and
//!   sends no pulse.
//! - **homing**: from the second frame the pulses command the home pose
//!   (all three servos centred at 1500 µs with the default calibration: the
//!   pose hobby servos are assembled and parked in). The servos' true
//!   position is unknown at power-up, so nothing can make this first approach
//!   slow; the app waits `home_settle_frames` before accepting targets, and
//!   the first move after power-up never runs faster than the slow preset.
//! - **holding** / **moving**: a target (touch, `move`, `goto`) is mapped,
//!   solved, checked against the joint limits and planned from the pose
//!   commanded in the previous frame. A new target while moving keeps the
//!   running move and superposes a correction that starts at rest
//!   ([`crate::motion::superpose`]), so neither the position nor the velocity
//!   steps; under the linear law or the papers' ζ-a-tₛ (whose profiles start
//!   with a velocity or change shape with tₛ) it re-plans from the commanded
//!   pose at rest.
//! - **checking**: a path move's check runs over frames; the arm holds
//!   still, and a new target is refused as busy until it decides.
//! - **stopped**: `stop` latches; the pose of the previous frame is held
//!   (pulses freeze in the frame that reads the command) and every target is
//!   refused until `resume`, which does not continue the interrupted move.
//!
//! # How the feature files divide `App`
//! One file per feature, each an `impl App` block beside the one struct:
//! `machine.rs` (the frame and the moves), `serial.rs` (lines and replies),
//! `screen.rs` (the touch screen), `path_move.rs` (paths and lifts),
//! `grip.rs` (the gripper), `poses.rs` (saved poses), `recalibrate.rs`
//! (calibration changes while holding), `wiring.rs` (the panel's wiring),
//! `telemetry.rs` (output lines), `undo.rs` (going back), `access.rs` (the
//! carer lock), `hold.rs` (hold to run), `switch.rs` (the assistive switch). The rule they follow:
//! - A feature's own state is one field of its own type, declared in its
//!   file (`grip: grip::Grip`, `path: path_move::PathRun`, `screen:
//!   screen::Screen`, `session: serial::Session`); only that file changes
//!   it. Other files read it through that file's methods.
//! - The arm's state (`commanded`, `track`, `mode`, `stopped`,
//!   `last_move`) belongs to `machine.rs`: a feature moves the arm only
//!   through the planner (`plan_motion`, `start_move`) or a latch (`stop`),
//!   never by writing a pose or a pulse, so every move keeps the limits and
//!   the no-jump rule. The exceptions are `path_move.rs`, whose accepted
//!   path or lift move commands its IK pose frame by frame, and `hold.rs`,
//!   whose planned stop commands the running move's own poses on a slowed
//!   clock, each frame checked against the acceleration limits.
//! - The running configuration (`config`, `maps`) changes only as a whole
//!   validated record (`recalibrate.rs`'s `replace_config`, the screen's
//!   calibration, boot) or by one field a command owns (`speed`, `law`,
//!   `path`, `lift_centi`, `wiring`), set by that command's handler after
//!   its checks; `cal save` stores it.
//! - The frame's one heavy thing (`HeavyTask`) is taken only through
//!   `App::spend_heavy`, and a feature that would do heavy work first asks
//!   whether it is spent (a catch-up frame starts spent).
//! - A feature's replies and refusals go through `refusal.rs` and
//!   `text.rs`: one reason text per refusal, one line type.

mod access;
mod grip;
mod hold;
mod lcd;
mod machine;
mod path_move;
mod poses;
mod press;
mod recalibrate;
pub mod refusal;
pub mod resume;
mod screen;
mod serial;
mod switch;
mod telemetry;
pub mod text;
mod undo;
mod wiring;

use core::mem::MaybeUninit;

use crate::config::settings::{ArmSettings, Config, NamedPose, PathMode, SpeedPreset};
use crate::config::store::{Source, Warning};
use crate::geometry::ik::{Branch, LinksError};
use crate::geometry::pose::ArmGeometry;
use crate::geometry::workspace::Condition;
use crate::motion::plan::{LawKind, JOINTS};
use crate::motion::planner::shape_choice::AChoice;
use crate::servo::map::{ServoMap, ELBOW_BRANCH};
use crate::servo::track::ServoTrack;
use crate::touch::filter::{FilterConfig, FilterConfigError, TouchFilter, TouchPoint};

pub use path_move::{CHECK_REFINE, CHECK_SAMPLES};
pub use refusal::Refusal;
pub use telemetry::status_line;

/// One frame = one servo PWM period.
pub const FRAME_MS: u32 = 20;
/// [`FRAME_MS`] in seconds.
pub const FRAME_S: f32 = 0.02;

/// Everything about the arm and the app that is fixed at build time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AppParams {
    /// Screen-to-arm scale of the linear transform.
    pub k: f32,
    /// IK elbow branch; the servo defaults assume [`ELBOW_BRANCH`]. The
    /// links' lengths and the home pose are settings (`cal set arm`, `cal
    /// set home`: [`crate::config::settings::ArmSettings`]).
    pub branch: Branch,
    /// The papers' ζ-a-tₛ base n (`law zat-paper`; the default law's
    /// reference shape is fixed: [`crate::motion::scaled`]).
    pub n: f32,
    /// Shortest move of the laws that scale with their duration (the
    /// classic ones and the time-scaled ζ-a-tₛ), s.
    pub ts_min: f32,
    /// Shortest move of the papers' ζ-a-tₛ, s, at least [`crate::motion::planner::request::ZAT_TS_FLOOR`]: above 1 so
    /// the smooth stop exists (for tₛ ≤ 1 a ζ-a-tₛ move ends with a velocity
    /// step of at least |Δ|·ln n / tₛ), and not just above 1, where the
    /// smooth-stop shape sits next to its pole.
    pub zat_ts_min: f32,
    /// Longest move, s: a slower requirement is refused.
    pub ts_max: f32,
    /// Fraction of each joint's speed kept in reserve (0.02 = plan at 98 %).
    pub speed_margin: f32,
    /// Frames of holding the home pose before targets are accepted.
    pub home_settle_frames: u16,
    /// Touch filter: samples per read, pressure window, spread and the press
    /// and release confirmations.
    pub filter: FilterConfig,
    /// Serial bytes read per frame at most (115200 baud brings ≤ 230).
    pub serial_bytes_per_frame: u8,
    /// A partial line with no new byte for this long is dropped and
    /// answered `err line timeout (no line ending?)`.
    pub line_timeout_ms: u32,
    /// A touch screen shows the map and buttons and routes touches (the
    /// firmware); without one the whole panel is the workspace, as in the
    /// paper (the host twin's default).
    pub screen: bool,
}

impl AppParams {
    /// The paper's map (k = 1: with the default equal links, k = l2 = l3 =
    /// 1), n = 2, moves of 0.5 s (classic) or 1.2 s (ζ-a-tₛ) up to 30 s, 2 %
    /// speed reserve, 1 s of settling at home, no screen.
    pub const DEFAULT: AppParams = AppParams {
        k: 1.0,
        branch: ELBOW_BRANCH,
        n: 2.0,
        ts_min: 0.5,
        zat_ts_min: 1.2,
        ts_max: 30.0,
        speed_margin: 0.02,
        home_settle_frames: 50,
        filter: FilterConfig::DEFAULT,
        serial_bytes_per_frame: 64,
        line_timeout_ms: 2000,
        screen: false,
    };

    /// Checks the parameters and builds the geometry of the arm `arm`
    /// describes (its links in the map's arm unit,
    /// [`ArmGeometry::from_lengths`]).
    pub fn geometry(&self, arm: &ArmSettings) -> Result<ArmGeometry<f32>, ParamsError> {
        let geo = arm_geometry(self, arm).map_err(ParamsError::Links)?;
        if !(self.k.is_finite() && self.k > 0.0) {
            return Err(ParamsError::Scale);
        }
        if !(self.n.is_finite() && self.n > 1.0) {
            return Err(ParamsError::Base);
        }
        let durations_ok = self.ts_min > 0.0
            && self.zat_ts_min >= crate::motion::planner::request::ZAT_TS_FLOOR
            && self.ts_max.is_finite()
            && self.ts_max >= self.ts_min
            && self.ts_max >= self.zat_ts_min;
        if !durations_ok {
            return Err(ParamsError::Durations);
        }
        if !(self.speed_margin >= 0.0 && self.speed_margin < 0.5) {
            return Err(ParamsError::Margin);
        }
        self.filter.validate().map_err(ParamsError::Filter)?;
        Ok(geo)
    }
}

/// The geometry of `arm` under `params`' scale and branch.
#[cfg_attr(target_arch = "avr", optimize(size))] // reason: cold
fn arm_geometry(params: &AppParams, arm: &ArmSettings) -> Result<ArmGeometry<f32>, LinksError> {
    let mm = |cmm: u16| f32::from(cmm) * 0.01;
    ArmGeometry::from_lengths(params.k, mm(arm.l2_cmm), mm(arm.l3_cmm), params.branch)
}

impl Default for AppParams {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// Why [`AppParams::geometry`] refused the parameters.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ParamsError {
    /// A link length is not positive and finite.
    Links(LinksError),
    /// k not positive and finite.
    Scale,
    /// n not > 1.
    Base,
    /// A duration not positive, or ts_max below a minimum.
    Durations,
    /// speed_margin not in [0, 0.5).
    Margin,
    /// The touch filter configuration is inconsistent.
    Filter(FilterConfigError),
    /// The built-in default calibration does not validate (a build error).
    Defaults,
}

/// The seam handed to [`App::frame`]: one borrow of each hardware part.
pub struct Io<'a, P, S, C, E, U> {
    /// The touch panel, read once per frame.
    pub panel: &'a mut P,
    /// The three servo outputs, written once per frame.
    pub servos: &'a mut S,
    /// Milliseconds, for the serial line timeout and telemetry stamps.
    pub clock: &'a C,
    /// The EEPROM holding the configuration record.
    pub storage: &'a mut E,
    /// The command and reply line.
    pub serial: &'a mut U,
}

/// What the arm is doing, for `status` and the display.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum State {
    /// Before the configuration is loaded: no pulses.
    Off,
    /// Going to and settling at the home pose; targets are refused.
    Homing,
    /// At rest, holding the last pose; a target starts a move.
    Holding,
    /// Following a planned move.
    Moving,
    /// Halted by STOP where it was; only RESUME (or `resume`) moves again.
    Stopped,
    /// A path move's plan-time check runs, a bounded part per frame; the
    /// arm holds still until it decides.
    Checking,
    /// `mode hold`: the held move was released by the lift and has come to
    /// rest on its path; a new held contact resumes it (its move is paused,
    /// not over).
    Paused,
}

impl State {
    /// Every state, for tests that go through them all.
    pub const ALL: [State; 7] =
        [State::Off, State::Homing, State::Holding, State::Moving, State::Stopped, State::Checking, State::Paused];

    /// The word `status` prints for the state.
    pub fn name(self) -> crate::text::Text {
        match self {
            State::Off => t!("off"),
            State::Homing => t!("homing"),
            State::Holding => t!("holding"),
            State::Moving => t!("moving"),
            State::Stopped => t!("stopped"),
            State::Checking => t!("checking"),
            State::Paused => t!("paused"),
        }
    }
}

/// The screen point behind the current target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TouchTarget {
    /// Raw panel reading it came from.
    pub raw_x: u16,
    /// Raw panel reading, Y (ADC counts).
    pub raw_y: u16,
    /// Normalized workspace point.
    pub x_p: f32,
    /// Normalized workspace height, 0..=1 (`x_p` is −1..=1).
    pub y_p: f32,
    /// The point's triangle condition (zone 1–4).
    pub condition: Condition,
    /// Base direction α, rad.
    pub alpha: f32,
}

/// Read-only snapshot for a display (and for `status`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Status {
    /// What the arm is doing.
    pub state: State,
    /// The trajectory law new moves use.
    pub law: LawKind,
    /// The speed preset new moves use (the one chosen, or the carer's cap
    /// below it).
    pub speed: SpeedPreset,
    /// How targets are reached (`path joint|line`).
    pub path: PathMode,
    /// Lift height of joint moves, hundredths of a workspace unit (`None`:
    /// `lift off`).
    pub lift_centi: Option<u8>,
    /// Pose commanded in the last frame, rad (base, shoulder, elbow).
    pub commanded: [f32; JOINTS],
    /// Target of the current or last move, rad.
    pub target: [f32; JOINTS],
    /// Pulses written in the last frame, Timer5 ticks of 0.5 µs (`None`
    /// before the first).
    pub pulses: Option<[u16; JOINTS]>,
    /// Share of the current move's tₛ elapsed, 0..=100 (100 at rest).
    pub progress: u8,
    /// Duration of the current or last move, s.
    pub ts: f32,
    /// Its ζ-a-tₛ shape, if it used that law.
    pub a: Option<AChoice<f32>>,
    /// Its joint velocities just before the end, rad/s.
    pub end_velocity: [f32; JOINTS],
    /// The screen point of the current or last target (`None` after `goto`).
    pub touch_target: Option<TouchTarget>,
    /// A press is being held on the panel.
    pub touch_held: bool,
    /// Why the last target was refused, until the next accepted one.
    pub last_refusal: Option<Refusal>,
    /// Where the running configuration came from (EEPROM slot or defaults).
    pub config_source: Source,
    /// What went wrong loading the configuration, if anything.
    pub config_warning: Option<Warning>,
    /// The first move after power-up is limited to the slow preset.
    pub first_move_pending: bool,
    /// Per-frame telemetry is on (`log on` or `log plot`).
    pub log: bool,
    /// Gripper angle commanded in the last frame, rad.
    pub grip: f32,
    /// Target of the gripper's current or last move, rad.
    pub grip_target: f32,
    /// The gripper's pulse written in the last frame, ticks (`None` before
    /// the first).
    pub grip_pulse: Option<u16>,
    /// A grip move is running.
    pub grip_moving: bool,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Mode {
    Boot,
    Homing { frames_left: u16 },
    Run,
}

/// What the last accepted move was.
#[derive(Debug, Clone, Copy, PartialEq)]
struct MoveInfo {
    target: [f32; JOINTS],
    ts: f32,
    /// Superposed on a running move, and the frames it waits for the
    /// older of two running terms to end.
    replan: Option<u16>,
    a: Option<AChoice<f32>>,
    end_velocity: [f32; JOINTS],
    touch: Option<TouchTarget>,
    kind: MoveKind,
}

/// What kind of move a target makes.
#[derive(Debug, Clone, Copy, PartialEq)]
enum MoveKind {
    /// Joint-space (the planner and the servo track).
    Joint,
    /// The effector along the straight segment.
    Line,
    /// One turn of radius `r` (arm units) from where the effector is.
    Circle {
        /// Radius, arm units.
        r: f32,
    },
    /// Every joint through the via pose `h` (arm units) above the higher end.
    Lift {
        /// Lift height, arm units.
        h: f32,
    },
}

/// A target accepted in this frame's serial or touch step: it is planned
/// after the frame's pulses are out, and then answered.
#[derive(Debug, Clone, Copy, PartialEq)]
struct PlanDue {
    target: [f32; JOINTS],
    touch: Option<TouchTarget>,
    answer: Answer,
    kind: MoveKind,
}

/// Who hears how a due plan went.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Answer {
    /// Not attached yet (the caller attaches right after `start_move`).
    Nobody,
    /// A serial line: its reply if the plan succeeds.
    Serial(serial::Done),
    /// A touch without a screen: `info touch …` / `err touch …`.
    Touch(TouchPoint),
    /// A touch on the screen's map (workspace point for the refusal words).
    Screen(TouchPoint, f32, f32),
    /// The screen's pose button `n`: `info screen pose go <n> …` /
    /// `err screen pose go <n> …`.
    ScreenPose(u8),
    /// The screen's Undo: `info screen undo … left <n>` / `err screen undo …`.
    ScreenUndo,
}

/// Lines still to send of a multi-line reply.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Pending {
    /// `cal show`: the next line index.
    CalShow(u8),
}

/// This frame's one heavy thing (module doc, "One frame, in order"): a
/// serial line answered, a move planned or a path check set up, a pose's
/// gripper planned. Spent once, by [`App::spend_heavy`]; a catch-up frame
/// starts with it spent, so it does none.
#[derive(Debug, Clone, Copy, Default)]
struct HeavyTask {
    spent: bool,
}

impl HeavyTask {
    /// A frame's task: already spent in a catch-up frame.
    fn new_frame(catch_up: bool) -> HeavyTask {
        HeavyTask { spent: catch_up }
    }

    /// The frame has no room left for a heavy thing.
    fn is_spent(self) -> bool {
        self.spent
    }
}

/// The app. Holds no hardware; see the module doc for the frame.
pub struct App {
    params: AppParams,
    geo: ArmGeometry<f32>,
    config: Config,
    maps: [ServoMap; JOINTS],
    filter: TouchFilter,
    mode: Mode,
    stopped: bool,
    first_move: bool,
    commanded: [f32; JOINTS],
    pulses: Option<[u16; JOINTS]>,
    /// This frame's pulses from the moving track (None when holding).
    frame_pulses: Option<[u16; JOINTS]>,
    /// The running move (with any correction superposed on it), its pulse
    /// lines and clock: one profile evaluation per running term and frame
    /// gives the pulses and the commanded angles. Done when holding.
    track: ServoTrack,
    last_move: MoveInfo,
    last_refusal: Option<Refusal>,
    source: Source,
    warning: Option<Warning>,
    /// The serial session: the line being received, telemetry, a reply in
    /// progress, dropped output (`serial.rs`).
    session: serial::Session,
    /// This frame's one heavy thing (module doc, "One frame, in order").
    heavy: HeavyTask,
    /// The next frame starts late (see [`App::frame_was_late`]).
    late: bool,
    /// A touch target that waits for a frame with no plan yet.
    deferred_touch: Option<TouchPoint>,
    /// The target of this frame, planned after the pulses.
    plan_due: Option<PlanDue>,
    /// `plan_due` is a re-plan the last frame had no room for: this frame
    /// takes no other heavy thing and plans it (`machine.rs`).
    plan_deferred: bool,
    screen: screen::Screen,
    /// The firmware should probe the panel's wiring (`wiring.rs`).
    probe_wanted: bool,
    /// The last probe identified no wiring.
    wiring_unknown: bool,
    /// The last panel read saw (or may have seen) a finger.
    contact: bool,
    /// The saved poses (`poses.rs`), loaded at boot.
    poses: crate::config::poses::Poses,
    /// The gripper (`grip.rs`): calibration, angle and move.
    grip: grip::Grip,
    /// The path move being checked or run (`path_move`).
    path: path_move::PathRun,
    /// The display overrides as stored (`lcd.rs`), loaded at boot.
    lcd: crate::config::lcd::LcdSettings,
    /// The contact on the glass and what it may become (`press.rs`).
    press: press::Press,
    /// The poses to go back to (`undo.rs`).
    undo: undo::Undo,
    /// The carer lock and its settings (`access.rs`), loaded at boot.
    carer: access::Carer,
    /// Hold to run (`hold.rs`): the held move and its planned stop.
    hold: hold::HoldRun,
    /// The assistive switch and its scan (`switch.rs`).
    switch: switch::SwitchRun,
}

// `App::init` assigns over an uninitialized slot: sound only while nothing
// in the app has drop glue.
const _: () = assert!(!core::mem::needs_drop::<App>());

/// Servo maps of a configuration.
fn build_maps(config: &Config) -> Option<[ServoMap; JOINTS]> {
    let [b, s, e] = &config.joints;
    match (ServoMap::new(b), ServoMap::new(s), ServoMap::new(e)) {
        (Ok(b), Ok(s), Ok(e)) => Some([b, s, e]),
        _ => None,
    }
}

impl App {
    /// Makes the map, the IK and the screen's reach shading follow the
    /// links of the running configuration (at boot and when `cal set arm`
    /// or `cal reset` changes them; the arm holds, so nothing moves).
    fn install_geometry(&mut self) {
        // Validated lengths always give a geometry; were one refused, the
        // last good one stays.
        if let Ok(geo) = arm_geometry(&self.params, &self.config.arm) {
            self.geo = geo;
            self.screen.ui.set_reach(&screen::reach(&geo));
        }
    }

    /// The one place the frame's heavy thing is taken (see [`HeavyTask`]).
    fn spend_heavy(&mut self) {
        self.heavy.spent = true;
    }

    /// A fresh app in the `off` state. The configuration is loaded by the
    /// first frame; until then the built-in defaults stand.
    pub fn new(params: &AppParams) -> Result<App, ParamsError> {
        let mut slot = MaybeUninit::uninit();
        App::init(&mut slot, params)?;
        // SAFETY: `init` returned Ok, so it wrote the whole app into `slot`.
        Ok(unsafe { slot.assume_init() })
    }

    /// [`App::new`] built in `slot` (the firmware's static): the app is most
    /// of the chip's static RAM, and built in a stack frame and moved, that
    /// frame plus the calls made while building it went past the stack
    /// budget (docs/avr-traps.md, trap 2). On `Err` the slot is left
    /// uninitialized.
    pub fn init<'a>(slot: &'a mut MaybeUninit<App>, params: &AppParams) -> Result<&'a mut App, ParamsError> {
        let config = Config::DEFAULT;
        let geo = params.geometry(&config.arm)?;
        let home = config.arm.pose_rad(NamedPose::Home);
        let filter = TouchFilter::new(&params.filter).map_err(ParamsError::Filter)?;
        let maps = build_maps(&config).ok_or(ParamsError::Defaults)?;
        let grip = grip::Grip::new(&crate::config::grip::GRIP_DEFAULT).ok_or(ParamsError::Defaults)?;
        let screen = screen::Screen::new(&screen::reach(&geo));
        let at = slot.as_mut_ptr();
        // SAFETY: `at` points to the slot, valid and exclusively borrowed for
        // 'a. Assigning to the place writes every field of the aggregate
        // there directly (no App-sized temporary), and drops nothing: the app
        // has no drop glue (asserted beside `build_maps`), so the uninitialized old
        // contents are never read.
        unsafe {
            *at = App {
                params: *params,
                geo,
                config,
                maps,
                filter,
                mode: Mode::Boot,
                stopped: false,
                first_move: true,
                commanded: home,
                pulses: None,
                frame_pulses: None,
                track: ServoTrack::idle(&home, FRAME_S),
                last_move: MoveInfo {
                    target: home,
                    ts: 0.0,
                    replan: None,
                    a: None,
                    end_velocity: [0.0; JOINTS],
                    touch: None,
                    kind: MoveKind::Joint,
                },
                last_refusal: None,
                source: Source::Defaults,
                warning: None,
                session: serial::Session::new(),
                heavy: HeavyTask::default(),
                late: false,
                deferred_touch: None,
                plan_due: None,
                plan_deferred: false,
                screen,
                probe_wanted: false,
                wiring_unknown: false,
                contact: false,
                poses: crate::config::poses::Poses::EMPTY,
                grip,
                path: path_move::PathRun::Idle,
                lcd: crate::config::lcd::LCD_DEFAULT,
                press: press::Press::IDLE,
                undo: undo::Undo::EMPTY,
                carer: access::Carer::NEW,
                hold: hold::HoldRun::IDLE,
                switch: switch::SwitchRun::IDLE,
            };
            Ok(&mut *at)
        }
    }

    /// The build-time parameters the app was made with.
    pub fn params(&self) -> &AppParams {
        &self.params
    }

    /// The running configuration (calibration, speed preset, law).
    pub fn config(&self) -> &Config {
        &self.config
    }

    /// The arm as the map and the IK see it now: the links of the running
    /// configuration in the map's arm unit, `k` and the branch.
    pub fn geometry(&self) -> &ArmGeometry<f32> {
        &self.geo
    }

    /// What the arm is doing now.
    pub fn state(&self) -> State {
        match self.mode {
            Mode::Boot => State::Off,
            _ if self.stopped => State::Stopped,
            Mode::Homing { .. } => State::Homing,
            Mode::Run if matches!(self.path, path_move::PathRun::Checking { .. }) => State::Checking,
            Mode::Run if self.hold_paused() => State::Paused,
            Mode::Run if !self.track.is_done() || self.path_busy() => State::Moving,
            Mode::Run => State::Holding,
        }
    }

    /// The snapshot a display draws from.
    pub fn status(&self) -> Status {
        let progress = match self.path.progress() {
            Some(p) => (p * 100.0) as u8,
            None if self.path_busy() => 0,
            None if self.track.is_done() => 100,
            None => (self.track.progress() * 100.0) as u8,
        };
        Status {
            state: self.state(),
            law: self.config.law,
            speed: self.speed_now(),
            path: self.config.path,
            lift_centi: self.config.lift_centi,
            commanded: self.commanded,
            target: self.last_move.target,
            pulses: self.pulses,
            progress,
            ts: self.last_move.ts,
            a: self.last_move.a,
            end_velocity: self.last_move.end_velocity,
            touch_target: self.last_move.touch,
            touch_held: self.finger_down(),
            last_refusal: self.last_refusal,
            config_source: self.source,
            config_warning: self.warning,
            first_move_pending: self.first_move,
            log: self.session.log != crate::protocol::command::LogMode::Off,
            grip: self.grip.commanded,
            grip_target: self.grip.target,
            grip_pulse: self.grip.ticks,
            grip_moving: self.grip.is_moving(),
        }
    }

    /// The gripper's running calibration (its pulse limits are the board's
    /// own clamp for the gripper's channel).
    pub fn grip_cal(&self) -> &crate::servo::map::JointCal {
        self.grip.map.cal()
    }
}
