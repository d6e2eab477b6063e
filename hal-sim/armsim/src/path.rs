//! `armsim path` and `armsim plot path`: an end-effector line or circle
//! planned by the firmware's path planner (in f64), sampled or plotted.

use std::path::PathBuf;

use clap::{Args, Subcommand};
use touch_arm::geometry::path::Path;
use touch_arm::motion::path::{Pace, PathArm, PathLimits, PathPlan, PathRequest, REFINE_FULL};
use touch_arm::motion::plan::LawKind;
use touch_arm::servo::map::{JointCal, ELBOW_BRANCH};

use crate::args::parse_triple;
use crate::opts::{links, times, BranchArg, LawKindArg, LinkArgs, Times, PLOT_SAMPLES};
use crate::plot::{self, Curve, Panel};
use crate::report::{csv_row, num, Json, Val};

#[derive(Args, Debug)]
/// `armsim path`'s arguments: the path's shape and its plan.
pub struct PathArgs {
    #[command(subcommand)]
    /// A line or a circle.
    pub kind: PathKind,
}

#[derive(Subcommand, Debug, Clone)]
/// The end-effector paths `armsim path` plans.
pub enum PathKind {
    /// The straight segment --from → --to
    Line(PathLine),
    /// One turn of radius --radius around --center in the arm's vertical plane, from the point farthest out, rising first
    Circle(PathCircle),
}

#[derive(Args, Debug, Clone)]
#[command(allow_hyphen_values = true)]
/// A straight segment of the effector.
pub struct PathLine {
    /// Start point "X,Y,Z" (x, y horizontal, z up; workspace units)
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_triple, allow_hyphen_values = true)]
    pub from: [f64; 3],
    /// End point "X,Y,Z"
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_triple, allow_hyphen_values = true)]
    pub to: [f64; 3],
    #[command(flatten)]
    /// Duration, law, limits, links, samples.
    pub common: PathCommon,
}

#[derive(Args, Debug, Clone)]
#[command(allow_hyphen_values = true)]
/// One turn of a circle of the effector.
pub struct PathCircle {
    /// Centre "X,Y,Z"
    #[arg(long, value_name = "X,Y,Z", value_parser = parse_triple, allow_hyphen_values = true)]
    pub center: [f64; 3],
    /// Radius r > 0 (smaller than the centre's distance from the base axis)
    #[arg(long)]
    pub radius: f64,
    #[command(flatten)]
    /// Duration, law, limits, links, samples.
    pub common: PathCommon,
}

#[derive(Args, Debug, Clone)]
#[command(allow_hyphen_values = true)]
/// What every path plan takes: duration, law, joint limits, links, samples.
pub struct PathCommon {
    /// Duration tₛ > 0 [s]
    #[arg(long)]
    pub ts: f64,
    /// The law pacing the path (default: the firmware's, zat)
    #[arg(long, value_enum, default_value_t = LawKindArg::Zat)]
    pub law: LawKindArg,
    /// Take the shortest admissible duration when --ts is too short for a joint's limits (else refuse)
    #[arg(long)]
    pub slow_down: bool,
    /// Largest joint speed [rad/s] (default: the servo defaults')
    #[arg(long)]
    pub max_speed: Option<f64>,
    /// Largest joint acceleration [rad/s²] (default: the servo defaults')
    #[arg(long)]
    pub max_accel: Option<f64>,
    /// Upper-arm length l2
    #[arg(long, default_value_t = 1.0)]
    pub l2: f64,
    /// Forearm length l3
    #[arg(long, default_value_t = 1.0)]
    pub l3: f64,
    #[command(flatten)]
    /// Where to sample the path.
    pub times: Times,
    /// Print the plan's duration and peaks as JSON instead of samples
    #[arg(long, conflicts_with_all = ["t", "samples"])]
    pub info: bool,
}

#[derive(Args, Debug)]
/// `armsim plot path`'s arguments: the path and the output file.
pub struct PlotPath {
    #[command(subcommand)]
    /// A line or a circle.
    pub kind: PathKind,
    /// Output file, .png or .svg
    #[arg(long, value_name = "FILE", global = true)]
    pub out: Option<PathBuf>,
}

/// Scan intervals of a path plan: with the refinement around the path's
/// critical points, the tests find no peak a four times denser scan exceeds
/// by more than a few percent.
const PATH_SCAN: u16 = 400;

/// Longest path move `--slow-down` may take, s.
const PATH_TS_MAX: f64 = 600.0;

fn path_law(l: LawKindArg) -> LawKind {
    match l {
        LawKindArg::Linear => LawKind::Linear,
        LawKindArg::Cubic => LawKind::Cubic,
        LawKindArg::Quintic => LawKind::Quintic,
        LawKindArg::Trapezoid => LawKind::Trapezoid,
        LawKindArg::Zat => LawKind::Zat,
    }
}

fn path_common(k: &PathKind) -> &PathCommon {
    match k {
        PathKind::Line(l) => &l.common,
        PathKind::Circle(c) => &c.common,
    }
}

/// The path's plan under the servo defaults' angle ranges (elbow up) and
/// the given or default speed and acceleration limits.
pub(crate) fn path_plan(k: &PathKind) -> Result<PathPlan<f64>, String> {
    let c = path_common(k);
    let path = match k {
        PathKind::Line(l) => Path::line(&l.from, &l.to),
        PathKind::Circle(ci) => Path::circle(&ci.center, ci.radius),
    };
    let path = path.map_err(|e| touch_arm::motion::path::PathError::<f64>::Shape(e).to_string())?;
    let links = links(&LinkArgs { l2: c.l2, l3: c.l3, branch: BranchArg::FIRMWARE })?;
    let d = JointCal::DEFAULTS;
    let speed = c.max_speed.unwrap_or(f64::from(d[0].max_speed_rad_s));
    let accel = c.max_accel.unwrap_or(f64::from(d[0].max_accel_rad_s2));
    if !(speed.is_finite() && speed > 0.0 && accel.is_finite() && accel > 0.0) {
        return Err(format!("--max-speed and --max-accel must be positive and finite, got {speed}, {accel}"));
    }
    let lim = PathLimits {
        min: d.map(|j| f64::from(j.min_rad)),
        max: d.map(|j| f64::from(j.max_rad)),
        speed: [speed; 3],
        accel: [accel; 3],
        ts_max: PATH_TS_MAX,
    };
    let pace = if c.slow_down { Pace::SlowDown } else { Pace::Refuse };
    let req = PathRequest { path, law: path_law(c.law), ts: c.ts, pace, samples: PATH_SCAN, refine: REFINE_FULL };
    PathPlan::new(&req, &PathArm { links, branch: ELBOW_BRANCH }, &lim).map_err(|e| e.to_string())
}

/// A JSON array of numbers.
fn num_array(v: &[f64]) -> Val {
    Val::Raw(format!("[{}]", v.iter().map(|x| num(*x)).collect::<Vec<_>>().join(", ")))
}

/// t, the effector and the joint angles at each time.
fn path_rows(plan: &PathPlan<f64>, ts: &[f64]) -> Result<Vec<[f64; 7]>, String> {
    ts.iter()
        .map(|&t| {
            let s = plan.state(t).map_err(|e| format!("at t = {t}: {e}"))?;
            Ok([t, s.p[0], s.p[1], s.p[2], s.q[0], s.q[1], s.q[2]])
        })
        .collect()
}

pub(crate) fn cmd_path(k: &PathKind) -> Result<String, String> {
    let plan = path_plan(k)?;
    let c = path_common(k);
    if c.info {
        let p = plan.peaks();
        return Ok(Json::new()
            .set("ts", plan.ts())
            .set("ts_asked", c.ts)
            .set("slowed", plan.ts() > c.ts)
            .set("peak_speed", num_array(&p.speed))
            .set("peak_accel", num_array(&p.accel))
            .render()
            + "\n");
    }
    let ts = times(&c.times, 0.0, plan.ts())?;
    let rows = path_rows(&plan, &ts)?;
    let mut out = String::from("t,x,y,z,th1,th2,th3\n");
    for r in rows {
        out.push_str(&csv_row(&r));
        out.push('\n');
    }
    Ok(out)
}

/// `armsim plot path`: top view (x, y), side view (x, z) and the joint angles.
pub(crate) fn plot_path(p: &PlotPath) -> Result<String, String> {
    let out = p.out.as_ref().ok_or("give --out FILE (.png or .svg)")?;
    let plan = path_plan(&p.kind)?;
    let c = path_common(&p.kind);
    let t = times(&Times { t: None, samples: Some(c.times.samples.unwrap_or(PLOT_SAMPLES)) }, 0.0, plan.ts())?;
    let rows = path_rows(&plan, &t)?;
    let col = |i: usize| rows.iter().map(|r| r[i]).collect::<Vec<f64>>();
    let (x, y, z, th1, th2, th3) = (col(1), col(2), col(3), col(4), col(5), col(6));
    let (a, b) = (plan.path().start(), plan.path().end());
    let title = match &p.kind {
        PathKind::Line(l) => format!("line {:?} -> {:?}, ts = {:.3} s ({:?})", l.from, l.to, plan.ts(), c.law),
        PathKind::Circle(ci) => {
            format!("circle around {:?}, r = {}, ts = {:.3} s ({:?})", ci.center, ci.radius, plan.ts(), c.law)
        }
    };
    let views = [
        plot::View {
            title: "top view",
            xlabel: "x",
            ylabel: "y",
            x: &x,
            y: &y,
            marks: vec![("start", a[0], a[1]), ("target", b[0], b[1]), ("base", 0.0, 0.0)],
        },
        plot::View {
            title: "side view",
            xlabel: "x",
            ylabel: "z",
            x: &x,
            y: &z,
            marks: vec![("start", a[0], a[2]), ("target", b[0], b[2])],
        },
    ];
    let panel = Panel {
        ylabel: "joint angle [rad]",
        curves: vec![
            Curve { label: "th1 (base)", y: &th1 },
            Curve { label: "th2 (shoulder)", y: &th2 },
            Curve { label: "th3 (elbow)", y: &th3 },
        ],
    };
    plot::path_figure(out, &title, &views, &t, &panel).map_err(|e| e.to_string())?;
    Ok(format!("wrote {}\n", out.display()))
}
