//! The argument types `armsim`'s subcommands share (evaluation times, the
//! links and the elbow branch, the motion laws) and their resolution: one
//! place, which `cli`, `path` and `paper` all use (none of them imports the
//! others' arguments).

use clap::{Args, ValueEnum};
use touch_arm::geometry::ik::{Branch, Links};
use touch_arm::servo::map::ELBOW_BRANCH;

/// Samples of a plot when its command gives none.
pub const PLOT_SAMPLES: usize = 600;

/// Where to evaluate: explicit times or K evenly spaced samples over the motion.
#[derive(Args, Debug, Clone)]
#[command(allow_hyphen_values = true)]
pub struct Times {
    /// Comma-separated times "t1,t2,..." [s]
    #[arg(long, value_name = "T1,T2,...", value_parser = parse_times, allow_hyphen_values = true)]
    pub t: Option<TimeList>,
    /// K evenly spaced samples from the start to the end of the motion (K ≥ 2)
    #[arg(long, value_name = "K")]
    pub samples: Option<usize>,
}

#[derive(ValueEnum, Clone, Copy, Debug)]
/// The motion laws `armsim law` and `path --law` take.
pub enum LawKindArg {
    /// Constant velocity
    Linear,
    /// Cubic polynomial (velocity zero at the ends)
    Cubic,
    /// Quintic polynomial (velocity and acceleration zero at the ends)
    Quintic,
    /// Trapezoidal velocity profile
    Trapezoid,
    /// The firmware's default: ζ-a-tₛ time-scaled from its reference shape
    /// (n = 2, T₀ = 1.5 s, a*) onto [t0, t_f]; `traj` is the papers' own form
    Zat,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
/// The IK's elbow branch: the sign of q3.
pub enum BranchArg {
    /// q3 = +acos(c)
    Plus,
    /// q3 = −acos(c): the elbow-up pose the firmware uses
    Minus,
}

impl BranchArg {
    /// The firmware's branch (`touch_arm::servo::map::ELBOW_BRANCH`, the one
    /// its servo calibration assumes): what `ik` and `plan` solve on unless
    /// `--branch` says otherwise, so their angles are the ones the arm takes.
    pub const FIRMWARE: BranchArg = match ELBOW_BRANCH {
        Branch::Plus => BranchArg::Plus,
        Branch::Minus => BranchArg::Minus,
    };

    /// The branch's name in the output (`"plus"`/`"minus"`), as `--branch`
    /// takes it.
    pub fn name(self) -> &'static str {
        match self {
            BranchArg::Plus => "plus",
            BranchArg::Minus => "minus",
        }
    }
}

impl From<BranchArg> for Branch {
    fn from(b: BranchArg) -> Self {
        match b {
            BranchArg::Plus => Branch::Plus,
            BranchArg::Minus => Branch::Minus,
        }
    }
}

#[derive(Args, Debug, Clone)]
/// The arm's links and the IK branch (shared by `ik` and `plan`).
pub struct LinkArgs {
    /// Upper-arm length l2
    #[arg(long, default_value_t = 1.0)]
    pub l2: f64,
    /// Forearm length l3
    #[arg(long, default_value_t = 1.0)]
    pub l3: f64,
    /// Elbow branch [default: the firmware's, minus (elbow up)]
    #[arg(long, value_enum, default_value_t = BranchArg::FIRMWARE, hide_default_value = true)]
    pub branch: BranchArg,
}

/// An explicit list of evaluation times (one clap value, not many).
#[derive(Clone, Debug)]
pub struct TimeList(pub Vec<f64>);

/// Comma-separated list of numbers ("0,0.1,0.5").
pub fn parse_times(s: &str) -> Result<TimeList, String> {
    s.split(',')
        .map(|v| match v.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => Ok(x),
            _ => Err(format!("not a finite number in list: {v:?}")),
        })
        .collect::<Result<Vec<_>, _>>()
        .map(TimeList)
}

/// The evaluation times: explicit, or K evenly spaced over [start, end].
pub fn times(t: &Times, start: f64, end: f64) -> Result<Vec<f64>, String> {
    match (&t.t, t.samples) {
        (Some(list), _) => Ok(list.0.clone()),
        (None, Some(k)) if k >= 2 => Ok((0..k).map(|i| start + (end - start) * i as f64 / (k - 1) as f64).collect()),
        (None, Some(k)) => Err(format!("--samples must be at least 2, got {k}")),
        (None, None) => Err("give --t t1,t2,... or --samples K".into()),
    }
}

/// The links, or why they are none.
pub fn links(a: &LinkArgs) -> Result<Links<f64>, String> {
    Links::new(a.l2, a.l3)
        .map_err(|e| format!("link lengths l2={}, l3={}: {e:?} (must be positive and finite)", a.l2, a.l3))
}
