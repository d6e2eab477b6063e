//! The settings that survive a reset ([`Config`]: joint calibrations, the
//! touch calibration, speed preset and motion law), their validation, and the
//! vocabulary of their fields that the serial protocol parses into and `cal
//! show` prints ([`JointField`], [`TouchField`], [`CalSet`]).

use crate::math::units::{centideg_to_rad, deg_per_rad, rad_to_centideg, round_i32};
use crate::motion::plan::LawKind;
use crate::servo::map::{Joint, JointCal, JointCalError};
use crate::touch::map::{Calibration, CalibrationError};
use crate::touch::wiring::Wiring;

/// How a joint target is reached: each joint by its own profile (the
/// effector's path is whatever the joints make of it), or the effector along
/// the straight segment, the IK solved every frame (`motion::path`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PathMode {
    /// Joint-space moves (the default).
    Joint,
    /// Straight-line moves of the effector.
    Line,
}

impl PathMode {
    /// Both modes, the default first.
    pub const ALL: [PathMode; 2] = [PathMode::Joint, PathMode::Line];

    /// The word of the serial protocol (`path joint|line`).
    pub fn name(self) -> crate::text::Text {
        match self {
            PathMode::Joint => t!("joint"),
            PathMode::Line => t!("line"),
        }
    }

    /// The mode named `name` on the serial line (in any case).
    pub fn from_name(name: &[u8]) -> Option<PathMode> {
        PathMode::ALL.iter().copied().find(|p| p.name().eq_ignore_case(name))
    }

    /// The byte stored in the EEPROM record: 0, 1. Never renumber.
    pub fn id(self) -> u8 {
        match self {
            PathMode::Joint => 0,
            PathMode::Line => 1,
        }
    }

    /// The mode stored as `id`; `None` for an unknown byte.
    pub fn from_id(id: u8) -> Option<PathMode> {
        PathMode::ALL.iter().copied().find(|p| p.id() == id)
    }
}

/// Largest lift, hundredths of a workspace unit (`lift 0.5`).
pub const LIFT_MAX_CENTI: u8 = 50;

/// Raw ADC range accepted by `move` and the touch calibration.
pub const RAW_MAX: i32 = 1023;
/// How fast moves are planned: the move duration is chosen so that no joint
/// exceeds this percentage of its `max_speed_rad_s`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpeedPreset {
    /// 25 %.
    Slow,
    /// 50 %.
    Normal,
    /// 100 %.
    Fast,
}

impl SpeedPreset {
    /// Every preset, slowest first (the order of the screen's buttons).
    pub const ALL: [SpeedPreset; 3] = [SpeedPreset::Slow, SpeedPreset::Normal, SpeedPreset::Fast];

    /// The byte stored in the EEPROM record: 0, 1, 2. Never renumber.
    pub fn id(self) -> u8 {
        match self {
            SpeedPreset::Slow => 0,
            SpeedPreset::Normal => 1,
            SpeedPreset::Fast => 2,
        }
    }

    /// The preset stored as `id`; `None` for an unknown byte.
    pub fn from_id(id: u8) -> Option<SpeedPreset> {
        SpeedPreset::ALL.iter().copied().find(|p| p.id() == id)
    }

    /// The word of the serial protocol (`speed slow|normal|fast`).
    pub fn name(self) -> crate::text::Text {
        match self {
            SpeedPreset::Slow => t!("slow"),
            SpeedPreset::Normal => t!("normal"),
            SpeedPreset::Fast => t!("fast"),
        }
    }

    /// The preset named `name` on the serial line (in any case).
    pub fn from_name(name: &[u8]) -> Option<SpeedPreset> {
        SpeedPreset::ALL.iter().copied().find(|p| p.name().eq_ignore_case(name))
    }

    /// Share of each joint's max speed the planner may use, percent.
    pub fn percent(self) -> u8 {
        match self {
            SpeedPreset::Slow => 25,
            SpeedPreset::Normal => 50,
            SpeedPreset::Fast => 100,
        }
    }
}

/// Smallest accepted `max − min` per axis: a real panel spans hundreds of
/// counts; less means a botched calibration that would blow up the mapping.
pub const MIN_TOUCH_SPAN: u16 = 100;

/// The configuration rule for a stored touch calibration: what
/// [`Calibration::validate`] requires (limits within the ADC range, min < max)
/// plus a span of at least [`MIN_TOUCH_SPAN`] counts per axis.
pub fn validate_touch(cal: &Calibration) -> Result<(), TouchCalError> {
    cal.validate().map_err(|e| match e {
        CalibrationError::EmptyRange { .. } => TouchCalError::Order,
        _ => TouchCalError::OutOfRange,
    })?;
    if cal.x_max - cal.x_min < MIN_TOUCH_SPAN || cal.y_max - cal.y_min < MIN_TOUCH_SPAN {
        return Err(TouchCalError::Span);
    }
    Ok(())
}

/// Why a touch calibration is not accepted as configuration.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TouchCalError {
    /// A limit above 1023.
    OutOfRange,
    /// `min >= max` on an axis.
    Order,
    /// An axis spans fewer than [`MIN_TOUCH_SPAN`] counts.
    Span,
    /// A hold, repeat, radius or plate ratio outside its range ([`PressSettings`]).
    Press,
}

/// How a touch becomes an action (issue #19): `cal set touch
/// hold|repeat|radius|plate`, stored in the configuration record (version 5;
/// the plate ratio since version 8).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PressSettings {
    /// A contact acts only if it lasted this long, hundredths of a second,
    /// [`HOLD_MIN_CS`]..=[`TIME_MAX_CS`].
    pub hold_cs: u8,
    /// A contact that starts within this time of the last lift-off is
    /// ignored, hundredths of a second, 0..=[`TIME_MAX_CS`].
    pub repeat_cs: u8,
    /// A contact that wanders farther than this from where it landed is
    /// cancelled: raw ADC counts per axis, [`RADIUS_MIN`]..=255 (about 14
    /// counts per mm across and 18 up the 2.8" panel with the default
    /// calibration; 160 ≈ 11 × 9 mm).
    pub radius: u8,
    /// The panel's plate ratio ([`crate::touch::filter::plate_ratio`],
    /// 256 = 1) as the touch calibration measured it, [`PLATE_MIN`]..=
    /// [`PLATE_MAX`]; 0: not measured (a second contact is then found by
    /// its jump alone).
    pub plate: u16,
}

/// Shortest `hold`, hundredths of a second (0.04 s: two reads).
pub const HOLD_MIN_CS: u8 = 4;
/// Longest `hold` and `repeat`, hundredths of a second (2.00 s).
pub const TIME_MAX_CS: u8 = 200;
/// Smallest cancel radius, ADC counts.
pub const RADIUS_MIN: u8 = 20;
/// A plate ratio (256 = 1) in hundredths, rounded: 427 → 167.
pub const fn plate_centi(plate: u16) -> i32 {
    ((plate as i32) * 100 + 128) / 256
}

/// Hundredths of a plate ratio as the ratio (256 = 1), rounded: 167 → 428.
pub const fn centi_plate(centi: u16) -> u16 {
    ((centi as u32 * 256 + 50) / 100) as u16
}

/// Smallest plate ratio taken, 256 = 1 (0.25: plates 1:4).
pub const PLATE_MIN: u16 = 64;
/// Largest plate ratio taken (4.00).
pub const PLATE_MAX: u16 = 1024;

impl PressSettings {
    /// Hold 0.10 s (five reads: a brush of 80 ms never acts, and the
    /// centre has its mid-range), repeat 0.30 s, radius 240 counts (a 5 mm
    /// tremor of ±20 % stays inside it on the 2.8" panel: BENCHMARKS.md, "Touch for an unsteady hand"),
    /// the plate ratio not measured (the touch calibration measures it).
    pub const DEFAULT: PressSettings = PressSettings { hold_cs: 10, repeat_cs: 30, radius: 240, plate: 0 };

    /// Every value in its range.
    pub fn is_valid(&self) -> bool {
        (HOLD_MIN_CS..=TIME_MAX_CS).contains(&self.hold_cs)
            && self.repeat_cs <= TIME_MAX_CS
            && self.radius >= RADIUS_MIN
            && (self.plate == 0 || (PLATE_MIN..=PLATE_MAX).contains(&self.plate))
    }
}

/// Everything that survives a reset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Config {
    /// In [`Joint::index`] order.
    pub joints: [JointCal; 3],
    /// Raw panel readings ↔ normalized panel points.
    pub touch: Calibration,
    /// Share of the joints' speed limits moves are planned for.
    pub speed: SpeedPreset,
    /// The trajectory law of new moves.
    pub law: LawKind,
    /// The panel's wiring as measured (`touch::wiring`); `None` until a
    /// probe has identified one (the firmware then probes at boot).
    pub wiring: Option<Wiring>,
    /// How targets are reached (`path joint|line`).
    pub path: PathMode,
    /// Lift of joint moves through a via pose, hundredths of a workspace
    /// unit, 1..=[`LIFT_MAX_CENTI`] (`lift <h>`); `None`: `lift off`. Never
    /// with [`PathMode::Line`].
    pub lift_centi: Option<u8>,
    /// Hold, repeat and cancel radius of touches.
    pub press: PressSettings,
    /// The links' lengths, the home and the park pose.
    pub arm: ArmSettings,
    /// `mode hold`: a map touch moves the arm only while it is held (or the
    /// switch is), and a lift brings it to rest (`app::hold`); `false`:
    /// `mode tap`, the default.
    pub hold_to_run: bool,
}

/// Why a configuration is refused (by `validate`, or a `cal set` that
/// would make it invalid).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConfigError {
    /// A joint's calibration is inconsistent.
    Joint(Joint, JointCalError),
    /// The touch calibration is not acceptable.
    Touch(TouchCalError),
    /// The gripper's calibration is inconsistent (`config::grip`).
    Grip(JointCalError),
    /// The links' lengths are out of range or too unequal ([`ArmSettings`]).
    Arm,
}

impl ConfigError {
    /// The reason as the `err` reply states it.
    pub fn reason(self) -> crate::text::Text {
        match self {
            ConfigError::Joint(_, e) | ConfigError::Grip(e) => e.reason(),
            ConfigError::Touch(TouchCalError::OutOfRange) => t!("touch limit above 1023"),
            ConfigError::Touch(TouchCalError::Order) => t!("touch min >= max"),
            ConfigError::Touch(TouchCalError::Span) => t!("touch span too small"),
            ConfigError::Touch(TouchCalError::Press) => t!("touch hold/repeat/radius/plate out of range"),
            ConfigError::Arm => t!("arm links differ more than 4x"),
        }
    }
}

impl Config {
    /// ζ-a-tₛ is the default law (the product's method; the app picks the
    /// smooth-stop shape when it is admissible and monotone).
    pub const DEFAULT: Config = Config {
        joints: JointCal::DEFAULTS,
        touch: Calibration::DEFAULT,
        speed: SpeedPreset::Normal,
        law: LawKind::Zat,
        wiring: None,
        path: PathMode::Joint,
        lift_centi: None,
        press: PressSettings::DEFAULT,
        arm: ArmSettings::DEFAULT,
        hold_to_run: false,
    };

    /// Checks every joint calibration and the touch calibration; the first
    /// failure is returned.
    pub fn validate(&self) -> Result<(), ConfigError> {
        for (joint, cal) in Joint::ALL.iter().zip(self.joints.iter()) {
            cal.validate().map_err(|e| ConfigError::Joint(*joint, e))?;
        }
        validate_touch(&self.touch).map_err(ConfigError::Touch)?;
        if !self.press.is_valid() {
            return Err(ConfigError::Touch(TouchCalError::Press));
        }
        if !self.arm.is_valid() {
            return Err(ConfigError::Arm);
        }
        Ok(())
    }

    /// The calibration of `joint`.
    pub fn joint(&self, joint: Joint) -> &JointCal {
        match joint {
            Joint::Base => &self.joints[0],
            Joint::Shoulder => &self.joints[1],
            Joint::Elbow => &self.joints[2],
        }
    }

    fn joint_mut(&mut self, joint: Joint) -> &mut JointCal {
        match joint {
            Joint::Base => &mut self.joints[0],
            Joint::Shoulder => &mut self.joints[1],
            Joint::Elbow => &mut self.joints[2],
        }
    }

    /// Applies a `cal set` command. The whole configuration is validated with
    /// the change and left untouched if that fails, so the running
    /// configuration is always valid (change limits in an order that stays
    /// valid, e.g. widen before narrowing).
    // Out of line: its copy of the configuration is not in the frame of
    // the serial command's handler, which is on the deepest path.
    #[inline(never)] // avr-trap: frame-size
    pub fn apply(&mut self, set: &CalSet) -> Result<(), ConfigError> {
        let mut next = *self;
        match *set {
            CalSet::Joint { joint, field, value } => set_field(next.joint_mut(joint), field, value),
            // Not part of the configuration record (`config::grip`): the app
            // applies it with [`set_field`].
            CalSet::Grip { .. } => {}
            CalSet::Touch { field, value } => {
                let t = &mut next.touch;
                match field {
                    TouchField::XMin => t.x_min = value,
                    TouchField::XMax => t.x_max = value,
                    TouchField::YMin => t.y_min = value,
                    TouchField::YMax => t.y_max = value,
                    TouchField::Swap => t.swap_xy = value != 0,
                    TouchField::InvertX => t.invert_x = value != 0,
                    TouchField::InvertY => t.invert_y = value != 0,
                    // Ranged by the parser (`TouchField::range`).
                    TouchField::Hold => next.press.hold_cs = value as u8,
                    TouchField::Repeat => next.press.repeat_cs = value as u8,
                    TouchField::Radius => next.press.radius = value as u8,
                    TouchField::Plate => next.press.plate = centi_plate(value),
                }
            }
            CalSet::Arm { link: ArmLink::L2, cmm } => next.arm.l2_cmm = cmm,
            CalSet::Arm { link: ArmLink::L3, cmm } => next.arm.l3_cmm = cmm,
            CalSet::Pose { which: NamedPose::Home, centideg } => next.arm.home = centideg,
            CalSet::Pose { which: NamedPose::Park, centideg } => next.arm.park = centideg,
        }
        next.validate()?;
        *self = next;
        Ok(())
    }

    /// A joint field in the units of `cal set` (see [`JointField`]), for `cal show`.
    pub fn joint_field(&self, joint: Joint, field: JointField) -> i32 {
        field_value(self.joint(joint), field)
    }
}

/// Sets one calibration field from its `cal set` value (see [`JointField`]
/// for the units); the caller validates the result.
pub fn set_field(cal: &mut JointCal, field: JointField, value: i32) {
    let v = value as f32;
    match field {
        JointField::Offset => cal.offset_us = v / 100.0,
        JointField::Scale => cal.us_per_rad = v / 100.0 * deg_per_rad::<f32>(),
        JointField::MinUs => cal.min_us = value.clamp(0, u16::MAX as i32) as u16,
        JointField::MaxUs => cal.max_us = value.clamp(0, u16::MAX as i32) as u16,
        JointField::MinDeg => cal.min_rad = centideg_to_rad(value),
        JointField::MaxDeg => cal.max_rad = centideg_to_rad(value),
        JointField::MaxSpeed => cal.max_speed_rad_s = centideg_to_rad(value),
        JointField::MaxAccel => cal.max_accel_rad_s2 = centideg_to_rad(value),
    }
}

/// A calibration field in the units of `cal set` (see [`JointField`]), for `cal show`.
pub fn field_value(c: &JointCal, field: JointField) -> i32 {
    match field {
        JointField::Offset => round_i32(c.offset_us * 100.0),
        JointField::Scale => round_i32(c.us_per_rad * 100.0 / deg_per_rad::<f32>()),
        JointField::MinUs => c.min_us as i32,
        JointField::MaxUs => c.max_us as i32,
        JointField::MinDeg => rad_to_centideg(c.min_rad),
        JointField::MaxDeg => rad_to_centideg(c.max_rad),
        JointField::MaxSpeed => rad_to_centideg(c.max_speed_rad_s),
        JointField::MaxAccel => rad_to_centideg(c.max_accel_rad_s2),
    }
}

impl Default for Config {
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// A joint calibration field for `cal set <joint> <field> <value>`. The value
/// is fixed-point hundredths except for the pulse limits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointField {
    /// `offset`: pulse at 0°, µs (decimal, |v| ≤ 20000).
    Offset,
    /// `scale`: µs per degree, the sign is the direction (decimal, |v| ≤ 100).
    Scale,
    /// `min_us` / `max_us`: pulse limits, whole µs, 500..=2500.
    MinUs,
    /// `max_us`, see [`JointField::MinUs`].
    MaxUs,
    /// `min_deg` / `max_deg`: angle limits, degrees (decimal, |v| ≤ 360).
    MinDeg,
    /// `max_deg`, see [`JointField::MinDeg`].
    MaxDeg,
    /// `max_speed`: degrees per second (decimal, 0..=3600).
    MaxSpeed,
    /// `max_accel`: degrees per second squared (decimal, 0..=60000).
    MaxAccel,
}

impl JointField {
    /// Every field, in the order `cal show` prints them.
    pub const ALL: [JointField; 8] = [
        JointField::Offset,
        JointField::Scale,
        JointField::MinUs,
        JointField::MaxUs,
        JointField::MinDeg,
        JointField::MaxDeg,
        JointField::MaxSpeed,
        JointField::MaxAccel,
    ];

    /// The field's word in `cal set` and `cal show`.
    pub fn name(self) -> crate::text::Text {
        match self {
            JointField::Offset => t!("offset"),
            JointField::Scale => t!("scale"),
            JointField::MinUs => t!("min_us"),
            JointField::MaxUs => t!("max_us"),
            JointField::MinDeg => t!("min_deg"),
            JointField::MaxDeg => t!("max_deg"),
            JointField::MaxSpeed => t!("max_speed"),
            JointField::MaxAccel => t!("max_accel"),
        }
    }

    /// True if the value is in hundredths (printed with two decimals).
    pub fn is_centi(self) -> bool {
        !matches!(self, JointField::MinUs | JointField::MaxUs)
    }
}

/// A touch calibration field for `cal set touch <field> <value>`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TouchField {
    /// `x_min`, `x_max`, `y_min`, `y_max`: raw ADC, integers 0..=1023.
    XMin,
    /// `x_max`, see [`TouchField::XMin`].
    XMax,
    /// `y_min`, see [`TouchField::XMin`].
    YMin,
    /// `y_max`, see [`TouchField::XMin`].
    YMax,
    /// `swap`, `invert_x`, `invert_y`: 0 or 1.
    Swap,
    /// `invert_x`, see [`TouchField::Swap`].
    InvertX,
    /// `invert_y`, see [`TouchField::Swap`].
    InvertY,
    /// `hold`: seconds with two decimals, 0.04..=2.00 ([`PressSettings`]).
    Hold,
    /// `repeat`: seconds with two decimals, 0..=2.00.
    Repeat,
    /// `radius`: ADC counts, integers 20..=255.
    Radius,
    /// `plate`: the panel's plate ratio with two decimals, 0.25..=4.00, or
    /// 0 (the second-contact check off): what the touch calibration
    /// measures ([`PressSettings::plate`]).
    Plate,
}

impl TouchField {
    /// Every field, in the order `cal show` prints them.
    pub const ALL: [TouchField; 11] = [
        TouchField::XMin,
        TouchField::XMax,
        TouchField::YMin,
        TouchField::YMax,
        TouchField::Swap,
        TouchField::InvertX,
        TouchField::InvertY,
        TouchField::Hold,
        TouchField::Repeat,
        TouchField::Radius,
        TouchField::Plate,
    ];

    /// The field's word in `cal set touch` and `cal show`.
    pub fn name(self) -> crate::text::Text {
        match self {
            TouchField::XMin => t!("x_min"),
            TouchField::XMax => t!("x_max"),
            TouchField::YMin => t!("y_min"),
            TouchField::YMax => t!("y_max"),
            TouchField::Swap => t!("swap"),
            TouchField::InvertX => t!("invert_x"),
            TouchField::InvertY => t!("invert_y"),
            TouchField::Hold => t!("hold"),
            TouchField::Repeat => t!("repeat"),
            TouchField::Radius => t!("radius"),
            TouchField::Plate => t!("plate"),
        }
    }

    /// Largest accepted value.
    pub fn max(self) -> i32 {
        self.range().1
    }

    /// Accepted values, in the field's units (hundredths of a second for
    /// `hold` and `repeat`).
    pub fn range(self) -> (i32, i32) {
        match self {
            TouchField::XMin | TouchField::XMax | TouchField::YMin | TouchField::YMax => (0, RAW_MAX),
            TouchField::Swap | TouchField::InvertX | TouchField::InvertY => (0, 1),
            TouchField::Hold => (i32::from(HOLD_MIN_CS), i32::from(TIME_MAX_CS)),
            TouchField::Repeat => (0, i32::from(TIME_MAX_CS)),
            TouchField::Radius => (i32::from(RADIUS_MIN), 255),
            // 0 or 0.25..=4.00: the gap is `PressSettings::is_valid`'s.
            TouchField::Plate => (0, plate_centi(PLATE_MAX)),
        }
    }

    /// True if the value is in hundredths (typed and printed with two decimals).
    pub fn is_centi(self) -> bool {
        matches!(self, TouchField::Hold | TouchField::Repeat | TouchField::Plate)
    }
}

/// One parsed `cal set` command: a field and its value in the field's units.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CalSet {
    /// `cal set <joint> <field> <value>`.
    Joint {
        /// The joint whose calibration changes.
        joint: Joint,
        /// Which field.
        field: JointField,
        /// In hundredths of the field's unit, or whole µs for the pulse limits.
        value: i32,
    },
    /// `cal set grip <field> <value>`: the gripper (`config::grip`), in
    /// the joints' fields and units.
    Grip {
        /// Which field.
        field: JointField,
        /// As [`CalSet::Joint`]'s value.
        value: i32,
    },
    /// `cal set touch <field> <value>`.
    Touch {
        /// Which field.
        field: TouchField,
        /// ADC counts, 0/1 for the flags, hundredths of a second for
        /// `hold` and `repeat`.
        value: u16,
    },
    /// `cal set arm l2|l3 <mm>`.
    Arm {
        /// Which link.
        link: ArmLink,
        /// Hundredths of a millimetre, [`LINK_MIN_CMM`]..=[`LINK_MAX_CMM`].
        cmm: u16,
    },
    /// `cal set home|park <base> <shoulder> <elbow>`.
    Pose {
        /// Which pose.
        which: NamedPose,
        /// Hundredths of a degree, in [`Joint::index`] order.
        centideg: [i16; 3],
    },
}

/// A link of `cal set arm`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ArmLink {
    /// The upper arm, shoulder axis to elbow axis.
    L2,
    /// The forearm, elbow axis to the point the hand brings to the target.
    L3,
}

/// A pose of the arm's own settings.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NamedPose {
    /// Where the arm goes at power-up.
    Home,
    /// Where `park` sends it (a rest pose for switching off).
    Park,
}

/// Shortest link, hundredths of a millimetre (10 mm).
pub const LINK_MIN_CMM: u16 = 1_000;
/// A home or park angle within ±327.67° (an i16 of hundredths in the
/// record; wider than any servo turns).
pub const NAMED_POSE_MAX_CENTIDEG: i32 = i16::MAX as i32;
/// Longest link, hundredths of a millimetre (650 mm: a u16 of hundredths).
pub const LINK_MAX_CMM: u16 = 65_000;
/// The longer link at most this many times the shorter: beyond it the
/// near-base disc of radius |l2 − l3| that no pose reaches covers most of
/// the map (a digit lost while typing a length, most likely).
pub const LINK_RATIO_MAX: u32 = 4;

/// The arm's own geometry and its two named poses (issue #21 §4): `cal set
/// arm l2|l3 <mm>`, `cal set home|park <b> <s> <e>`, stored in the
/// configuration record (version 6). Only the links' ratio enters the
/// angles (the map's arm unit is their mean length,
/// [`crate::geometry::pose::ArmGeometry::from_lengths`]); their length in
/// millimetres says what one workspace unit of `circle` and `lift` is.
/// There is no base height: the map's heights are measured from the
/// shoulder axis, so a base height changes nothing the firmware computes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ArmSettings {
    /// Upper arm, hundredths of a millimetre.
    pub l2_cmm: u16,
    /// Forearm, hundredths of a millimetre.
    pub l3_cmm: u16,
    /// The power-up pose, hundredths of a degree (clamped into the joints'
    /// windows when used, as the pulses would be).
    pub home: [i16; 3],
    /// `park`'s pose, hundredths of a degree (judged as a `goto` when used).
    pub park: [i16; 3],
}

impl ArmSettings {
    /// Equal links of 100 mm (any equal pair gives the same angles), home
    /// and park at 90°, 90°, −90° (upper arm up, forearm ahead) until set.
    pub const DEFAULT: ArmSettings =
        ArmSettings { l2_cmm: 10_000, l3_cmm: 10_000, home: [9000, 9000, -9000], park: [9000, 9000, -9000] };

    /// Lengths in range and within [`LINK_RATIO_MAX`] of each other.
    pub fn is_valid(&self) -> bool {
        let ok = |l: u16| (LINK_MIN_CMM..=LINK_MAX_CMM).contains(&l);
        let (a, b) = (u32::from(self.l2_cmm), u32::from(self.l3_cmm));
        ok(self.l2_cmm) && ok(self.l3_cmm) && a <= b * LINK_RATIO_MAX && b <= a * LINK_RATIO_MAX
    }

    /// A named pose in radians.
    pub fn pose_rad(&self, which: NamedPose) -> [f32; 3] {
        let p = match which {
            NamedPose::Home => &self.home,
            NamedPose::Park => &self.park,
        };
        p.map(|c| centideg_to_rad(i32::from(c)))
    }
}
