//! The settings that survive a reset ([`Config`]: joint calibrations, the
//! touch calibration, speed preset and motion law), their validation, and the
//! vocabulary of their fields that the serial protocol parses into and `cal
//! show` prints ([`JointField`], [`TouchField`], [`CalSet`]).

use crate::motion::plan::LawKind;
use crate::servo::map::{Joint, JointCal, JointCalError};
use crate::touch::map::{Calibration, CalibrationError};

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
    pub const ALL: [SpeedPreset; 3] = [SpeedPreset::Slow, SpeedPreset::Normal, SpeedPreset::Fast];

    pub fn id(self) -> u8 {
        match self {
            SpeedPreset::Slow => 0,
            SpeedPreset::Normal => 1,
            SpeedPreset::Fast => 2,
        }
    }

    pub fn from_id(id: u8) -> Option<SpeedPreset> {
        SpeedPreset::ALL.iter().copied().find(|p| p.id() == id)
    }

    pub fn name(self) -> crate::text::Text {
        match self {
            SpeedPreset::Slow => t!("slow"),
            SpeedPreset::Normal => t!("normal"),
            SpeedPreset::Fast => t!("fast"),
        }
    }

    pub fn from_name(name: &[u8]) -> Option<SpeedPreset> {
        SpeedPreset::ALL.iter().copied().find(|p| p.name().eq_bytes(name))
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

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TouchCalError {
    /// A limit above 1023.
    OutOfRange,
    /// `min >= max` on an axis.
    Order,
    /// An axis spans fewer than [`MIN_TOUCH_SPAN`] counts.
    Span,
}

/// Everything that survives a reset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Config {
    /// In [`Joint::index`] order.
    pub joints: [JointCal; 3],
    pub touch: Calibration,
    pub speed: SpeedPreset,
    pub law: LawKind,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ConfigError {
    Joint(Joint, JointCalError),
    Touch(TouchCalError),
}

impl ConfigError {
    pub fn reason(self) -> crate::text::Text {
        match self {
            ConfigError::Joint(_, e) => e.reason(),
            ConfigError::Touch(TouchCalError::OutOfRange) => t!("touch limit above 1023"),
            ConfigError::Touch(TouchCalError::Order) => t!("touch min >= max"),
            ConfigError::Touch(TouchCalError::Span) => t!("touch span too small"),
        }
    }
}

const DEG_PER_RAD: f32 = 180.0 / core::f32::consts::PI;
const RAD_PER_CENTIDEG: f32 = core::f32::consts::PI / 18_000.0;

/// Rounds half away from zero; saturates (core has no `f32::round`).
pub(crate) fn round_i32(v: f32) -> i32 {
    if v >= 0.0 {
        (v + 0.5) as i32
    } else {
        (v - 0.5) as i32
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
    };

    pub fn validate(&self) -> Result<(), ConfigError> {
        for (joint, cal) in Joint::ALL.iter().zip(self.joints.iter()) {
            cal.validate().map_err(|e| ConfigError::Joint(*joint, e))?;
        }
        validate_touch(&self.touch).map_err(ConfigError::Touch)
    }

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
    pub fn apply(&mut self, set: &CalSet) -> Result<(), ConfigError> {
        let mut next = *self;
        match *set {
            CalSet::Joint { joint, field, value } => {
                let cal = next.joint_mut(joint);
                let v = value as f32;
                match field {
                    JointField::Offset => cal.offset_us = v / 100.0,
                    JointField::Scale => cal.us_per_rad = v / 100.0 * DEG_PER_RAD,
                    JointField::MinUs => cal.min_us = value.clamp(0, u16::MAX as i32) as u16,
                    JointField::MaxUs => cal.max_us = value.clamp(0, u16::MAX as i32) as u16,
                    JointField::MinDeg => cal.min_rad = v * RAD_PER_CENTIDEG,
                    JointField::MaxDeg => cal.max_rad = v * RAD_PER_CENTIDEG,
                    JointField::MaxSpeed => cal.max_speed_rad_s = v * RAD_PER_CENTIDEG,
                    JointField::MaxAccel => cal.max_accel_rad_s2 = v * RAD_PER_CENTIDEG,
                }
            }
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
                }
            }
        }
        next.validate()?;
        *self = next;
        Ok(())
    }

    /// A joint field in the units of `cal set` (see [`JointField`]), for `cal show`.
    pub fn joint_field(&self, joint: Joint, field: JointField) -> i32 {
        let c = self.joint(joint);
        match field {
            JointField::Offset => round_i32(c.offset_us * 100.0),
            JointField::Scale => round_i32(c.us_per_rad * 100.0 / DEG_PER_RAD),
            JointField::MinUs => c.min_us as i32,
            JointField::MaxUs => c.max_us as i32,
            JointField::MinDeg => round_i32(c.min_rad / RAD_PER_CENTIDEG),
            JointField::MaxDeg => round_i32(c.max_rad / RAD_PER_CENTIDEG),
            JointField::MaxSpeed => round_i32(c.max_speed_rad_s / RAD_PER_CENTIDEG),
            JointField::MaxAccel => round_i32(c.max_accel_rad_s2 / RAD_PER_CENTIDEG),
        }
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
    MaxUs,
    /// `min_deg` / `max_deg`: angle limits, degrees (decimal, |v| ≤ 360).
    MinDeg,
    MaxDeg,
    /// `max_speed`: degrees per second (decimal, 0..=3600).
    MaxSpeed,
    /// `max_accel`: degrees per second squared (decimal, 0..=60000).
    MaxAccel,
}

impl JointField {
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
    XMax,
    YMin,
    YMax,
    /// `swap`, `invert_x`, `invert_y`: 0 or 1.
    Swap,
    InvertX,
    InvertY,
}

impl TouchField {
    pub const ALL: [TouchField; 7] = [
        TouchField::XMin,
        TouchField::XMax,
        TouchField::YMin,
        TouchField::YMax,
        TouchField::Swap,
        TouchField::InvertX,
        TouchField::InvertY,
    ];

    pub fn name(self) -> crate::text::Text {
        match self {
            TouchField::XMin => t!("x_min"),
            TouchField::XMax => t!("x_max"),
            TouchField::YMin => t!("y_min"),
            TouchField::YMax => t!("y_max"),
            TouchField::Swap => t!("swap"),
            TouchField::InvertX => t!("invert_x"),
            TouchField::InvertY => t!("invert_y"),
        }
    }

    /// Largest accepted value.
    pub fn max(self) -> i32 {
        match self {
            TouchField::XMin | TouchField::XMax | TouchField::YMin | TouchField::YMax => RAW_MAX,
            TouchField::Swap | TouchField::InvertX | TouchField::InvertY => 1,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CalSet {
    Joint { joint: Joint, field: JointField, value: i32 },
    Touch { field: TouchField, value: u16 },
}
